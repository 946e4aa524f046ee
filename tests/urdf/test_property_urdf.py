"""Fuzzing the URDF reader: any input ends in a screened URDF or one UrdfError, quickly.

``read_urdf`` gets random bytes and structured mutations of a small valid URDF
(dangerous tokens inserted, slices deleted or repeated, re-encoded as UTF-16 or
ISO-8859-1). Whatever it gets, it returns a :class:`~fkcheck.urdf.tree.UrdfInfo`
or raises :class:`~fkcheck.errors.UrdfError` with a one-line message — never
another exception, never a hang (each example is bounded in time). What it
accepts is safe to hand on: no DTD, comment, processing instruction or xacro
expression in the text the parsers get, a tree every link of which hangs below
the root, and fkcheck's own URDF reader and Pinocchio (urdfdom) read it or
refuse it cleanly. ``nox -s fuzz`` runs these with 10x the examples.
"""

from __future__ import annotations

import contextlib
import itertools
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
from hypothesis import event, given
from hypothesis import strategies as st

from fkcheck.backends.pinocchio_urdf import _build
from fkcheck.errors import UrdfError
from fkcheck.urdf.chain import urdf_kinematics
from fkcheck.urdf.tree import UrdfInfo, read_urdf
from tests.helpers import deadline

pin = pytest.importorskip("pinocchio")

#: Seconds one example may take (the 32 MiB limit is far away: inputs are small).
EXAMPLE_BOUND_S = 10.0

SMALL = """<?xml version="1.0" encoding="utf-8"?>
<!-- a small valid URDF: two links below the base, a revolute and a prismatic joint -->
<robot name="two" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <link name="base"/>
  <link name="l1">
    <inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>
  </link>
  <link name="tip">
    <visual><origin xyz="0 0 0"/><geometry><box size="0.1 0.1 0.1"/></geometry></visual>
  </link>
  <joint name="j1" type="revolute">
    <parent link="base"/><child link="l1"/>
    <origin xyz="0 0 0.1" rpy="0 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/>
  </joint>
  <joint name="j2" type="prismatic">
    <parent link="l1"/><child link="tip"/>
    <origin xyz="0.5 0 0"/><axis xyz="1 0 0"/>
    <limit lower="0" upper="1" effort="1" velocity="1"/>
  </joint>
  <transmission name="t"><joint name="j1"/></transmission>
</robot>
"""

#: What an attacker or an unlucky editor puts into a URDF.
TOKENS = (
    "${",
    "$(",
    "${__import__('os').system('touch FKCHECK_MARKER')}",
    "$(find x)",
    "}",
    ")",
    '<!DOCTYPE robot [<!ENTITY x SYSTEM "file:///etc/hostname">]>',
    '<!DOCTYPE robot [<!ENTITY x "y">]>',
    "&x;",
    "&#36;",
    "&#123;",
    "&#40;",
    "<![CDATA[",
    "]]>",
    "<!--",
    "-->",
    "<?pi ${x}?>",
    "<",
    ">",
    "&",
    "&amp;",
    '"',
    "'",
    "\x00",
    "\x1b",
    "\ufeff",
    "é",
    " nan",
    " inf",
    "1e999",
    "1_0",
    "\u0661",
    "\t",
    "\n",
    '<link name="l1"/>',
    '<link name="x"/>',
    '<joint name="back" type="fixed"><parent link="tip"/><child link="base"/></joint>',
    '<joint name="j1" type="fixed"><parent link="base"/><child link="tip"/></joint>',
    '<joint name="k" type="fixed"><parent link="l1"/><child link="ghost"/></joint>',
    '<xacro:include filename="x"/>',
    '<xacro:property name="p" value="1"/>',
    '<include filename="/etc/hostname"/>',
    '<xi:include xmlns:xi="http://www.w3.org/2001/XInclude" href="/etc/hostname"/>',
    "</robot>",
    "<robot>",
    "</link>",
    "<a>" * 70,
)
ENCODINGS = ("utf-8", "utf-16", "utf-16-le", "utf-16-be", "iso-8859-1")

_names = itertools.count()


@pytest.fixture(scope="module")
def fuzz_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return tmp_path_factory.mktemp("fuzz_urdf")


#: Attribute values: names of links and joints, numbers good and bad, payloads.
VALUES = (
    "base",
    "l1",
    "tip",
    "ghost",
    "j1",
    "j2",
    "",
    "fixed",
    "continuous",
    "floating",
    "spherical",
    "0",
    "0 0 0",
    "1 0",
    "0 0 1 0",
    "1e999 0 0",
    "nan 0 0",
    "-inf",
    "+1 .5 1.",
    "1,0,0",
    "0x10",
    "\u0661 0 0",
    "${x}",
    "$(env HOME)",
    "&#36;{x}",
    "&quot;",
    "&lt;",
)
_ATTRIBUTE_VALUE = re.compile(r'="[^"]*"')
_TAG_END = re.compile(r">")


@st.composite
def mutated_urdfs(draw: st.DrawFn) -> bytes:
    """SMALL after a few edits, in some encoding (declared, mostly).

    Edits: an attribute value replaced, a token inserted between two tags or
    anywhere, a slice deleted or repeated.
    """
    text = SMALL
    for _ in range(draw(st.integers(1, 5))):
        op = draw(st.sampled_from(("value", "value", "between", "anywhere", "delete", "repeat")))
        if op == "value":
            spans = [m.span() for m in _ATTRIBUTE_VALUE.finditer(text)]
            if spans:
                start, end = draw(st.sampled_from(spans))
                text = text[:start] + f'="{draw(st.sampled_from(VALUES))}"' + text[end:]
            continue
        if op in ("between", "anywhere"):
            ends = [m.end() for m in _TAG_END.finditer(text)] if op == "between" else []
            i = draw(st.sampled_from(ends)) if ends else draw(st.integers(0, len(text)))
            printable = st.text(
                st.characters(codec="utf-8", exclude_categories=("Cc", "Cs")), max_size=6
            )
            token = draw(st.one_of(st.sampled_from(TOKENS), printable))
            text = text[:i] + token + text[i:]
            continue
        i = draw(st.integers(0, len(text)))
        j = draw(st.integers(i, min(len(text), i + 80)))
        text = text[:i] + text[j:] if op == "delete" else text[:j] + text[i:j] + text[j:]
    encoding = draw(st.sampled_from(ENCODINGS))
    if encoding != "utf-8" and draw(st.integers(0, 4)):
        declared = "UTF-16" if encoding.startswith("utf-16") else "ISO-8859-1"
        text = text.replace('encoding="utf-8"', f'encoding="{declared}"', 1)
    return text.encode(encoding, errors="xmlcharrefreplace")


def read_or_refuse(data: bytes, directory: Path, note=event) -> UrdfInfo | None:
    """``read_urdf`` on ``data``: the URDF, or ``None`` after a clean one-line UrdfError.

    ``note`` records the outcome (hypothesis's ``event``, for its statistics).
    """
    path = directory / f"fuzz{next(_names)}.urdf"  # a new name: the reader caches by path
    path.write_bytes(data)
    try:
        with deadline(EXAMPLE_BOUND_S):
            info = read_urdf(path)
    except UrdfError as exc:
        message = str(exc)
        note(_kind_of_refusal(message.removeprefix(f"{path}: ")))
        assert message.startswith(str(path)), message
        assert "\n" not in message
        return None
    finally:
        path.unlink()
    note("accepted")
    return info


def _kind_of_refusal(problem: str) -> str:
    """A refusal's kind for hypothesis's statistics: the problem without names and numbers."""
    problem = re.sub(r"^line \d+: ", "", problem)
    problem = re.sub(r"'[^']*'|<[^>]*>|\d+", "_", problem)
    return "refused: " + problem[:60]


def assert_safe_to_hand_on(info: UrdfInfo) -> None:
    """What the parsers get: no DTD, comment, PI or xacro; a tree; parseable or cleanly refused."""
    text = info.text
    assert not re.search(r"\$[{(]", text), text
    assert "<!" not in text  # no DTD, comment or CDATA
    assert "<?" not in text  # no declaration or processing instruction
    assert ET.fromstring(text).tag == "robot"
    for link in info.links:  # every link hangs below the root
        info.chain(info.root, link)
    with contextlib.suppress(UrdfError):
        urdf_kinematics(info)
    try:
        _build(pin, info)  # urdfdom's prints captured; never a crash
        message = ""
    except UrdfError as exc:
        message = str(exc)
    assert "\n" not in message


@given(
    data=st.one_of(
        st.binary(max_size=2048),
        st.binary(max_size=512).map(
            lambda b: b'<robot name="r"><link name="a"/>' + b + b"</robot>"
        ),
    )
)
def test_property_read_urdf_random_bytes(data, fuzz_dir):
    info = read_or_refuse(data, fuzz_dir)
    if info is not None:
        assert_safe_to_hand_on(info)


@given(data=mutated_urdfs())
def test_property_read_urdf_mutations(data, fuzz_dir):
    info = read_or_refuse(data, fuzz_dir)
    if info is not None:
        assert_safe_to_hand_on(info)


def test_the_unmutated_urdf_is_accepted(fuzz_dir):
    # The mutations start from a URDF the reader accepts (else they prove little).
    info = read_or_refuse(SMALL.encode(), fuzz_dir, note=lambda outcome: None)
    assert info is not None
    assert info.root == "base"
    assert sorted(info.joints) == ["j1", "j2"]
    assert_safe_to_hand_on(info)
