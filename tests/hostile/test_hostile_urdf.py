"""Hostile and broken URDFs: one clear line and exit 2, before any parser sees them.

Every command that reads a URDF — ``check`` with each URDF backend, ``check``
writing reports, ``diagnose`` and ``table-from`` — runs each hostile URDF.
Each case asserts: exit code 2; standard error (captured at the file-descriptor
level, so a native library's own prints count too) is exactly one line naming
the file and the problem, with no traceback; no parser entry point was called;
the marker file a payload would create does not exist; the content of the file
a payload would read appears nowhere; no file in the directory was created or
changed (reports included); and the run ended within its time bound.
"""

from __future__ import annotations

import os
import re
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import pytest

import fkcheck.backends.pinocchio_urdf as pinocchio_urdf
import fkcheck.backends.rtb_urdf as rtb_urdf
import fkcheck.backends.yourdfpy_urdf as yourdfpy_urdf
import fkcheck.description.urdf as description_urdf
import fkcheck.engine.runner as check_module
import fkcheck.urdf.chain as urdf_kinematics
from fkcheck.cli.main import main
from fkcheck.errors import UrdfError
from fkcheck.model.read import bundled_model_paths
from fkcheck.urdf.locate import example_robot_data_dir
from fkcheck.urdf.screen import MAX_XML_DEPTH, MAX_XML_ELEMENTS
from fkcheck.urdf.tree import MAX_URDF_DEPTH, MAX_URDF_LINKS, read_urdf
from tests.helpers import deadline

UR5_URDF = example_robot_data_dir() / "ur_description" / "urdf" / "ur5_robot.urdf"
UR5_TEXT = UR5_URDF.read_text()
#: What a payload would create in the working directory (the test's tmp_path).
MARKER = "FKCHECK_MARKER"
#: The content of a file no URDF may read (written to tmp_path/secret.txt).
SECRET = "s3cr3t-token-5b7e0c"
#: Every run, refused or not, ends within this many seconds.
TIME_BOUND_S = 20.0

RCE = f"__import__('os').system('touch {MARKER}')"


# --------------------------------------------------------------------------- helpers


def snapshot(root: Path) -> dict[str, tuple[int, int]]:
    """Every file below ``root`` (FIFOs and sockets included): size and mtime."""
    out = {}
    for path in root.rglob("*"):
        st = path.lstat()
        out[str(path.relative_to(root))] = (st.st_size, st.st_mtime_ns)
    return out


def ur5_plain() -> str:
    """ur5.toml without its xacro opt-in: its [urdf] is to be a plain URDF, xacro refused."""
    toml = bundled_model_paths()["ur5"].read_text()
    return re.sub(r"^(xacro|xacro_args|packages) = .*\n", "", toml, flags=re.MULTILINE)


def model_with_urdf(tmp_path: Path, urdf: str | bytes | None, *, edit=lambda s: s) -> Path:
    """ur5.toml, pointed at ``robot.urdf`` next to it (None: no URDF file written)."""
    toml = re.sub(r'path = ".*"', 'path = "robot.urdf"', ur5_plain())
    model = tmp_path / "ur5_local.toml"
    model.write_text(edit(toml))
    if isinstance(urdf, str):
        (tmp_path / "robot.urdf").write_text(urdf)
    elif isinstance(urdf, bytes):
        (tmp_path / "robot.urdf").write_bytes(urdf)
    return model


def model_pointing_at(tmp_path: Path, target: Path) -> Path:
    """ur5.toml with ``[urdf].path`` naming ``target`` (absolute)."""
    toml = re.sub(r'path = ".*"', f'path = "{target}"', ur5_plain())
    model = tmp_path / "ur5_local.toml"
    model.write_text(toml)
    return model


@dataclass(frozen=True)
class Run:
    code: int
    out: str
    err: str
    seconds: float


def run_cli(capfd: pytest.CaptureFixture[str], argv: list[str | Path]) -> Run:
    start = time.perf_counter()
    with deadline(TIME_BOUND_S):
        code = main([str(a) for a in argv])
    seconds = time.perf_counter() - start
    out, err = capfd.readouterr()
    return Run(code, out, err, seconds)


def assert_refused(run: Run, name: str, problem: str) -> None:
    """Exit 2, one line on stderr naming ``name`` and matching ``problem``, nothing else."""
    assert run.code == 2, (run.out, run.err)
    lines = run.err.splitlines()
    assert len(lines) == 1, run.err
    assert lines[0].startswith("fkcheck: error: "), run.err
    assert name in lines[0], run.err
    assert re.search(problem, lines[0]), run.err
    assert "Traceback" not in run.out + run.err
    assert run.seconds < TIME_BOUND_S


#: The commands that read a URDF: argv from (model file, URDF file, output directory).
COMMANDS: dict[str, Callable[[Path, Path, Path], list[str | Path]]] = {
    "check-pinocchio-urdf": lambda m, u, o: [
        "check", m, "--samples", "5", "--against", "pinocchio-urdf",
    ],
    "check-yourdfpy-urdf": lambda m, u, o: [
        "check", m, "--samples", "5", "--against", "yourdfpy-urdf",
    ],
    "check-rtb-urdf": lambda m, u, o: ["check", m, "--samples", "5", "--against", "rtb-urdf"],
    "check-reports": lambda m, u, o: [
        "check", m, "--samples", "5", "--json", o / "r.json", "--html", o / "r.html",
        "--junit", o / "r.xml",
    ],
    "diagnose": lambda m, u, o: ["diagnose", m, "--samples", "5", "--json", o / "d.json"],
    "table-from": lambda m, u, o: [
        "table-from", u, "--base", "base_link", "--tip", "tool0", "-o", o / "m.toml",
    ],
}  # fmt: skip


@pytest.fixture
def parser_calls(monkeypatch: pytest.MonkeyPatch) -> list[str]:
    """Replace every door to a URDF parser with a recorder; the list of doors used."""
    calls: list[str] = []

    def recorder(name: str) -> Callable[..., object]:
        def record(*args: object, **kwargs: object) -> object:
            calls.append(name)
            raise AssertionError(f"{name} was called on a URDF the screen should refuse")

        return record

    doors = [
        (pinocchio_urdf, "_build"),  # Pinocchio / urdfdom
        (rtb_urdf, "_read_robot"),  # Robotics Toolbox's reader
        (yourdfpy_urdf, "_load"),  # yourdfpy (lxml), in the parent
        (check_module, "run_isolated"),  # yourdfpy's own process
        (urdf_kinematics, "urdf_kinematics"),  # table-from's own reader
        (description_urdf, "urdf_kinematics"),  # a description's tree (axes, diagnose, map)
    ]
    for module, attr in doors:
        monkeypatch.setattr(module, attr, recorder(f"{module.__name__}.{attr}"))
    return calls


@pytest.fixture
def workdir(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """tmp_path as the working directory, with the secret file in it."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "secret.txt").write_text(SECRET + "\n")
    (tmp_path / "out").mkdir()
    return tmp_path


def run_hostile(
    command: str, workdir: Path, capfd: pytest.CaptureFixture[str], urdf: str | bytes
) -> tuple[Run, dict[str, tuple[int, int]]]:
    """Run ``command`` on a model whose URDF is ``urdf``; the run and the directory before."""
    model = model_with_urdf(workdir, urdf)
    argv = COMMANDS[command](model, workdir / "robot.urdf", workdir / "out")
    before = snapshot(workdir)
    return run_cli(capfd, argv), before


def assert_nothing_happened(run: Run, workdir: Path, before: dict[str, tuple[int, int]]) -> None:
    assert not (workdir / MARKER).exists(), "a payload ran"
    assert SECRET not in run.out + run.err, "a payload read a file"
    assert snapshot(workdir) == before, "a file was created or changed"


# --------------------------------------------------------------------------- hostile content


def replace(old: str, new: str, text: str = UR5_TEXT, count: int = 1) -> str:
    assert old in text
    return text.replace(old, new, count)


def after_first(anchor: str, payload: str, text: str = UR5_TEXT) -> str:
    assert anchor in text
    return text.replace(anchor, anchor + payload, 1)


def utf16(text: str, *, bom: bool) -> bytes:
    declared = re.sub(r'encoding="[^"]*"', 'encoding="UTF-16"', text, count=1)
    return declared.encode("utf-16" if bom else "utf-16-le")


def latin1(text: str) -> bytes:
    declared = re.sub(r'encoding="[^"]*"', 'encoding="ISO-8859-1"', text, count=1)
    return declared.replace('name="ur5"', 'name="ür5"', 1).encode("latin-1")


DTD_EXTERNAL = '<!DOCTYPE robot [<!ENTITY x SYSTEM "file://{secret}">]>\n'


def with_dtd(dtd: str, text: str = UR5_TEXT) -> str:
    """``text`` with ``dtd`` before <robot> and the robot named after an entity."""
    text = text.replace("<robot ", dtd + "<robot ", 1)
    return text.replace('name="ur5"', 'name="&x;"', 1)


@dataclass(frozen=True)
class Hostile:
    """A hostile URDF: its content (given the secret file's path) and the problem line."""

    make: Callable[[Path], str | bytes]
    problem: str


XACRO = r"contains a xacro expression "
HOSTILE: dict[str, Hostile] = {
    "xacro-in-attribute": Hostile(
        lambda s: UR5_TEXT.replace('name="ur5"', f'name="${{{RCE}}}"', 1),
        XACRO + r"\$\{…\} in attribute name= of <robot>",
    ),
    "xacro-in-tail": Hostile(
        lambda s: after_first("</link>", f"${{{RCE}}}"),
        XACRO + r"\$\{…\} in the text after </link>",
    ),
    "xacro-in-text": Hostile(
        lambda s: UR5_TEXT.replace(
            '<link name="world"/>', f'<link name="world">$(eval {RCE})</link>'
        ),
        XACRO + r"\$\(…\) in the text of <link>",
    ),
    "xacro-in-cdata": Hostile(
        lambda s: after_first("</joint>", f"<![CDATA[${{{RCE}}}]]>"),
        XACRO + r"\$\{…\} in the text after </joint>",
    ),
    "xacro-split-by-cdata": Hostile(
        lambda s: after_first("</joint>", f"$<![CDATA[{{{RCE}}}]]>"),
        XACRO + r"\$\{…\} in the text after </joint>",
    ),
    "xacro-as-character-reference": Hostile(
        lambda s: after_first("</joint>", f"&#36;&#123;{RCE}}}"),
        XACRO + r"\$\{…\} in the text after </joint>",
    ),
    "xacro-eval-reads-a-file": Hostile(
        lambda s: after_first("</link>", f"$(eval open('{s}').read())"),
        XACRO + r"\$\(…\)",
    ),
    "xacro-find-in-mesh-filename": Hostile(
        lambda s: replace(
            'filename="package://example-robot-data/robots/ur_description',
            'filename="$(find ur_description)',
        ),
        XACRO + r"\$\(…\) in attribute filename= of <mesh>",
    ),
    "xacro-env": Hostile(
        lambda s: UR5_TEXT.replace('name="ur5"', 'name="$(env HOME)"', 1),
        XACRO + r"\$\(…\) in attribute name= of <robot>",
    ),
    "shell-style-cat": Hostile(
        lambda s: after_first("</link>", f"$(cat {s})"),
        XACRO + r"\$\(…\) in the text after </link>",
    ),
    "dtd-internal-entity": Hostile(
        lambda s: with_dtd('<!DOCTYPE robot [<!ENTITY x "ur5">]>\n'), r"line \d+: has a DTD"
    ),
    "dtd-external-entity": Hostile(
        lambda s: with_dtd(DTD_EXTERNAL.format(secret=s)), r"line \d+: has a DTD"
    ),
    "dtd-parameter-entity": Hostile(
        lambda s: with_dtd(f'<!DOCTYPE robot [<!ENTITY % p SYSTEM "file://{s}"> %p;]>\n'),
        r"has a DTD",
    ),
    "dtd-external-subset": Hostile(
        lambda s: UR5_TEXT.replace("<robot ", f'<!DOCTYPE robot SYSTEM "file://{s}">\n<robot ', 1),
        r"has a DTD",
    ),
    "utf16-bom-external-entity": Hostile(
        lambda s: utf16(with_dtd(DTD_EXTERNAL.format(secret=s)), bom=True), r"has a DTD"
    ),
    "utf16-no-bom-external-entity": Hostile(
        lambda s: utf16(with_dtd(DTD_EXTERNAL.format(secret=s)), bom=False), r"has a DTD"
    ),
    "utf16-xacro-in-tail": Hostile(
        lambda s: utf16(after_first("</link>", f"${{{RCE}}}"), bom=True),
        XACRO + r"\$\{…\} in the text after </link>",
    ),
    "latin1-xacro-in-tail": Hostile(
        lambda s: latin1(after_first("</link>", f"${{{RCE}}}")),
        XACRO + r"\$\{…\} in the text after </link>",
    ),
    "xinclude": Hostile(
        lambda s: after_first(
            "</link>",
            f'<xi:include xmlns:xi="http://www.w3.org/2001/XInclude" href="{s}" parse="text"/>',
        ),
        r"has a XInclude element <include>",
    ),
    "xacro-include": Hostile(
        lambda s: after_first("</link>", f'<xacro:include filename="{s}"/>'),
        r"has a xacro element <include> \(http://wiki\.ros\.org/xacro\)",
    ),
    "xacro-macro": Hostile(
        lambda s: after_first(
            "</link>", '<xacro:macro name="m" params="p"><link name="p"/></xacro:macro>'
        ),
        r"has a xacro element <macro>",
    ),
    "xacro-attribute": Hostile(
        lambda s: UR5_TEXT.replace('<link name="world"/>', '<link name="world" xacro:if="1"/>'),
        r"has a xacro attribute if= on <link>",
    ),
    "plain-include": Hostile(
        lambda s: after_first("</link>", f'<include filename="{s}"/>'),
        r"has an <include> element",
    ),
    "billion-laughs": Hostile(
        lambda s: with_dtd(
            '<!DOCTYPE robot [\n <!ENTITY a "aaaaaaaaaa">\n'
            + "".join(
                f' <!ENTITY {chr(98 + i)} "{("&" + chr(97 + i) + ";") * 10}">\n' for i in range(8)
            )
            + ' <!ENTITY x "&i;">\n]>\n'
        ),
        r"line 6: has a DTD",
    ),
}


@pytest.mark.parametrize("command", COMMANDS)
@pytest.mark.parametrize("case", HOSTILE)
def test_hostile_urdf_is_refused_before_any_parser(case, command, workdir, capfd, parser_calls):
    hostile = HOSTILE[case]
    run, before = run_hostile(command, workdir, capfd, hostile.make(workdir / "secret.txt"))
    assert_refused(run, "robot.urdf", hostile.problem)
    assert parser_calls == []
    assert_nothing_happened(run, workdir, before)


# --------------------------------------------------------------------------- broken structure


def extra(xml: str) -> str:
    return replace("</robot>", xml + "</robot>")


def joint(name: str, parent: str, child: str, jtype: str = "fixed", body: str = "") -> str:
    return (
        f'<joint name="{name}" type="{jtype}"><parent link="{parent}"/>'
        f'<child link="{child}"/>{body}</joint>'
    )


def wide_robot(links: int) -> str:
    parts = ['<robot name="r"><link name="l0"/>']
    for i in range(1, links):
        parts.append(f'<link name="l{i}"/>' + joint(f"j{i}", "l0", f"l{i}"))
    return "".join(parts) + "</robot>"


def deep_robot(depth: int) -> str:
    parts = ['<robot name="r"><link name="l0"/>']
    for i in range(1, depth + 1):
        parts.append(f'<link name="l{i}"/>' + joint(f"j{i}", f"l{i - 1}", f"l{i}"))
    return "".join(parts) + "</robot>"


WRIST_3_ORIGIN = '<origin rpy="0.0 0.0 0.0" xyz="0.0 0.0 0.09465"/>'
BROKEN: dict[str, tuple[str | bytes, str]] = {
    "detached-cycle": (
        extra(
            '<link name="c1"/><link name="c2"/>'
            + joint("c12", "c1", "c2")
            + joint("c21", "c2", "c1")
        ),
        r"joints 'c12', 'c21' form a cycle \(c1 → c2 → c1\); a URDF is a tree",
    ),
    "cycle-through-the-root": (
        extra(joint("back", "tool0", "world")),
        r"joints 'shoulder_pan_joint', 'shoulder_lift_joint', .*, … \(1 more\) form a cycle "
        r"\(base_link → shoulder_link → .* → … → base_link\); a URDF is a tree",
    ),
    "self-loop": (
        extra(joint("loop", "tool0", "tool0")),
        r"joint 'loop' connects link 'tool0' to itself",
    ),
    "two-parents": (
        extra(joint("second", "base_link", "wrist_3_link")),
        r"link 'wrist_3_link' has two parents: joint 'wrist_3_joint' hangs it from "
        r"'wrist_2_link' and joint 'second' from 'base_link'",
    ),
    "missing-child-link": (
        extra(joint("dangling", "tool0", "ghost")),
        r"joint 'dangling' names child link 'ghost', which is not a link; links are: "
        r"base_link, shoulder_link",
    ),
    "missing-parent-link": (
        extra('<link name="x"/>' + joint("dangling", "ghost", "x")),
        r"joint 'dangling' names parent link 'ghost', which is not a link",
    ),
    "duplicate-link": (
        extra('<link name="ee_link"/>'),
        r"line \d+: link 'ee_link' is defined twice \(first on line 213\)",
    ),
    "duplicate-joint": (
        extra('<link name="x"/>' + joint("elbow_joint", "tool0", "x")),
        r"joint 'elbow_joint' is defined twice \(first on line 108\)",
    ),
    "unnamed-link": (extra("<link/>"), r"a <link> has no name"),
    "unnamed-joint": (
        extra(
            '<link name="x"/><joint type="fixed"><parent link="tool0"/><child link="x"/></joint>'
        ),
        r"a <joint> has no name",
    ),
    "unknown-joint-type": (
        replace('name="elbow_joint" type="revolute"', 'name="elbow_joint" type="spherical"'),
        r"joint 'elbow_joint' has type 'spherical'; URDF joint types are: revolute, continuous",
    ),
    "joint-without-parent": (
        replace('<parent link="upper_arm_link"/>', ""),
        r"joint 'elbow_joint' has no <parent link=\"…\">",
    ),
    "nan-origin": (
        replace(WRIST_3_ORIGIN, '<origin rpy="0 0 0" xyz="nan 0 0"/>'),
        r"joint 'wrist_3_joint': <origin xyz> is 'nan 0 0', expected 3 finite decimal numbers",
    ),
    "infinite-origin": (
        replace(WRIST_3_ORIGIN, '<origin rpy="1e999 0 0" xyz="0 0 0"/>'),
        r"<origin rpy> is '1e999 0 0', expected 3 finite",
    ),
    "two-numbers": (
        replace(WRIST_3_ORIGIN, '<origin rpy="0 0" xyz="0 0 0"/>'),
        r"<origin rpy> is '0 0', expected 3 finite decimal numbers separated by spaces",
    ),
    "commas": (
        replace(WRIST_3_ORIGIN, '<origin rpy="0,0,0" xyz="0 0 0"/>'),
        r"<origin rpy> is '0,0,0'",
    ),
    "underscore-digits": (
        replace(WRIST_3_ORIGIN, '<origin rpy="0 0 0" xyz="1_0 0 0"/>'),
        r"<origin xyz> is '1_0 0 0'",
    ),
    "arabic-indic-digits": (
        replace(WRIST_3_ORIGIN, '<origin rpy="0 0 0" xyz="\u0661 0 0"/>'),
        r"<origin xyz> is '\u0661 0 0'",
    ),
    "tab-separated": (
        replace(WRIST_3_ORIGIN, '<origin rpy="0 0 0" xyz="1&#9;0 0"/>'),
        r"<origin xyz> is '1\\t0 0'",
    ),
    "zero-axis": (
        replace('<axis xyz="0 0 1"/>', '<axis xyz="0 0 0"/>'),
        r"joint 'shoulder_pan_joint': <axis xyz> is zero; a revolute joint needs a direction",
    ),
    "malformed-limit": (
        replace('lower="-6.28318530718"', 'lower="-2pi"'),
        r"<limit lower> is '-2pi', expected a finite decimal number",
    ),
    "malformed-mass": (
        replace('<mass value="4.0"/>', '<mass value="four"/>'),
        r"line 53: link 'base_link': <mass value> is 'four', expected a finite decimal number",
    ),
    "two-roots": (
        extra('<link name="floating"/>'),
        r"expected one root link, found 2: world, floating",
    ),
    "root-is-not-robot": ("<model><link name='a'/></model>", r"root element is <model>"),
    "no-link": ('<robot name="r"/>', r"has no <link>"),
    "not-xml": ("this is { not xml", r"not valid XML"),
    "empty": ("", r"not valid XML: no element found"),
    "binary": (bytes(range(256)), r"not valid XML"),
    "invalid-utf8": (b'<robot name="\xff\xfe"><link name="a"/></robot>', r"not valid XML"),
    "undefined-entity": ('<robot name="&x;"><link name="a"/></robot>', r"not valid XML"),
    "unbound-prefix": ('<robot name="r"><a:b/></robot>', r"not valid XML: unbound prefix"),
    "control-character": ('<robot name="&#27;[2J"/>', r"not valid XML"),
    "multibyte-encoding": (
        b'<?xml version="1.0" encoding="Shift_JIS"?><robot name="r"/>',
        r"not valid XML: multi-byte encodings are not supported",
    ),
    "too-many-links": (
        wide_robot(MAX_URDF_LINKS + 1),
        rf"has {MAX_URDF_LINKS + 1} links, more than the {MAX_URDF_LINKS} a URDF may have",
    ),
    "too-deep-chain": (
        deep_robot(MAX_URDF_DEPTH + 1),
        rf"link 'l{MAX_URDF_DEPTH + 1}' is more than {MAX_URDF_DEPTH} joints below the root",
    ),
    "too-deeply-nested": (
        '<robot name="r">' + "<a>" * MAX_XML_DEPTH + "</a>" * MAX_XML_DEPTH + "</robot>",
        rf"nests elements deeper than {MAX_XML_DEPTH} levels",
    ),
    "too-many-elements": (
        '<robot name="r">' + "<a/>" * MAX_XML_ELEMENTS + "</robot>",
        rf"has more than {MAX_XML_ELEMENTS} elements",
    ),
}

#: Broken structure goes through the commands that read URDFs differently.
STRUCTURE_COMMANDS = ("check-reports", "diagnose", "table-from")


@pytest.mark.parametrize("command", STRUCTURE_COMMANDS)
@pytest.mark.parametrize("case", BROKEN)
def test_broken_urdf_is_one_line_exit_2(case, command, workdir, capfd, parser_calls):
    urdf, problem = BROKEN[case]
    run, before = run_hostile(command, workdir, capfd, urdf)
    assert_refused(run, "robot.urdf", problem)
    assert parser_calls == []
    assert_nothing_happened(run, workdir, before)


# --------------------------------------------------------------------------- not a regular file


def make_fifo(tmp_path: Path) -> Path:
    fifo = tmp_path / "pipe.urdf"
    os.mkfifo(fifo)
    return fifo


def make_fifo_link(tmp_path: Path) -> Path:
    link = tmp_path / "link.urdf"
    link.symlink_to(make_fifo(tmp_path))
    return link


def make_directory(tmp_path: Path) -> Path:
    (tmp_path / "dir.urdf").mkdir()
    return tmp_path / "dir.urdf"


def make_huge(tmp_path: Path) -> Path:
    huge = tmp_path / "huge.urdf"
    with huge.open("wb") as f:
        f.truncate(33 * 1024 * 1024)  # sparse: no disk used
    return huge


SPECIAL_FILES: dict[str, tuple[Callable[[Path], Path], str]] = {
    "missing": (lambda d: d / "missing.urdf", r"missing\.urdf: no such file"),
    "directory": (make_directory, r"dir\.urdf: is a directory, not a regular file"),
    "fifo": (make_fifo, r"pipe\.urdf: is a FIFO \(named pipe\), not a regular file"),
    "symlink-to-fifo": (
        make_fifo_link,
        r"link\.urdf: is a symlink to \S*/pipe\.urdf, which is a FIFO \(named pipe\), "
        r"not a regular file",
    ),
    "dev-zero": (lambda d: Path("/dev/zero"), r"zero: is a character device, not a regular file"),
    "larger-than-32-MiB": (make_huge, r"file too large: 34603008 bytes \(at most 32 MiB\)"),
}


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs POSIX named pipes")
@pytest.mark.parametrize("command", STRUCTURE_COMMANDS)
@pytest.mark.parametrize("case", SPECIAL_FILES)
def test_urdf_path_that_is_not_a_regular_file(case, command, workdir, capfd, parser_calls):
    make, problem = SPECIAL_FILES[case]
    target = make(workdir)
    model = model_pointing_at(workdir, target)
    before = snapshot(workdir)
    run = run_cli(capfd, COMMANDS[command](model, target, workdir / "out"))
    assert_refused(run, target.name, problem)
    assert run.seconds < 5  # a FIFO is never opened, so never waited on
    assert parser_calls == []
    assert snapshot(workdir) == before


# --------------------------------------------------------------------------- harmless, accepted


COMMENTED = after_first(
    "</link>",
    f"<!-- ${{{RCE}}} $(eval {RCE}) <xacro:include filename='secret.txt'/> --><?xacro ${{{RCE}}}?>",
)


@pytest.mark.parametrize("command", ["check-rtb-urdf", "check-pinocchio-urdf", "table-from"])
def test_xacro_in_comments_and_processing_instructions_is_dropped_never_run(
    command, workdir, capfd
):
    # Published URDFs keep xacro source in comments (TALOS, Go1): they are
    # accepted, and no parser ever receives them.
    run, _ = run_hostile(command, workdir, capfd, COMMENTED)
    assert run.code == 0, run.out + run.err
    assert run.err == ""
    assert not (workdir / MARKER).exists()
    text = read_urdf(workdir / "robot.urdf").text
    assert "<!--" not in text
    assert "<?" not in text
    assert "$" not in text


@pytest.mark.parametrize(
    "encode",
    [
        pytest.param(lambda t: utf16(t, bom=True), id="utf16-bom"),
        pytest.param(lambda t: utf16(t, bom=False), id="utf16-no-bom"),
        pytest.param(latin1, id="iso-8859-1"),
    ],
)
def test_urdf_in_another_encoding_is_read_as_declared(encode, workdir, capfd):
    text = UR5_TEXT.replace('name="ur5"', 'name="ür5"', 1)
    data = encode(text)
    run, _ = run_hostile("check-pinocchio-urdf", workdir, capfd, data)
    assert run.code == 0, run.out + run.err
    info = read_urdf(workdir / "robot.urdf")
    assert '<robot name="ür5">' in info.text  # never U+FFFD
    assert "\ufffd" not in info.text


def test_urdfdom_refusal_is_one_line_without_its_own_prints(workdir, capfd):
    # The screen does not require <limit> (table-from needs none); urdfdom does,
    # and prints "Error: ... at line 607 in joint.cpp" on fd 2 before Pinocchio raises.
    text = re.sub(
        r'(<joint name="wrist_3_joint" type="revolute">.*?)<limit[^>]*/>',
        r"\1",
        UR5_TEXT,
        count=1,
        flags=re.S,
    )
    run, _ = run_hostile("check-pinocchio-urdf", workdir, capfd, text)
    assert_refused(
        run,
        "robot.urdf",
        r"Pinocchio cannot build a model from it: urdfdom says: Joint \[wrist_3_joint\] is of "
        r"type REVOLUTE but it does not specify limits",
    )
    assert "joint.cpp" not in run.err


def test_valid_urdf_text_reaches_parsers_without_comments_or_declaration():
    info = read_urdf(UR5_URDF)
    assert info.text.startswith('<robot name="ur5">')
    assert "<!--" not in info.text
    assert info.root == "world"
    assert len(info.joints) == 10
    assert len(info.links) == 11


def test_rtb_urdf_never_runs_xacro(monkeypatch, capfd):
    # URDF_file runs xacrodoc on its input; the backend must not call it, nor xacrodoc.
    import xacrodoc
    from roboticstoolbox.models.URDF import URDFRobot

    def refuse(*args, **kwargs):
        raise AssertionError("xacro must never run")

    monkeypatch.setattr(URDFRobot, "URDF_file", refuse)
    monkeypatch.setattr(URDFRobot, "_expand_xacro", refuse)
    monkeypatch.setattr(xacrodoc.XacroDoc, "from_string", refuse)
    monkeypatch.setattr(xacrodoc.XacroDoc, "from_file", refuse)
    assert callable(URDFRobot._links_from_urdf)  # the private step the backend relies on
    run = run_cli(capfd, ["check", "ur5", "--samples", "5", "--against", "rtb-urdf"])
    assert run.code == 0, run.out + run.err
    assert re.search(r"rtb-urdf\s+│\s+table\s+│\s+pass", run.out), run.out


# --------------------------------------------------------------------------- model mapping


def check(capfd, model: Path, *extra_args: str) -> Run:
    return run_cli(capfd, ["check", model, "--samples", "20", *extra_args])


def test_mapped_joint_missing_from_urdf(tmp_path, capfd):
    text = UR5_TEXT.replace('"elbow_joint"', '"elbow"')
    run = check(capfd, model_with_urdf(tmp_path, text))
    assert_refused(
        run,
        "robot.urdf",
        r"joint 'elbow_joint' \(for DH joint elbow\) not in URDF; movable joints are: .*elbow",
    )


def test_mapped_joint_of_the_wrong_type(tmp_path, capfd):
    text = UR5_TEXT.replace(
        '<joint name="elbow_joint" type="revolute">', '<joint name="elbow_joint" type="prismatic">'
    )
    run = check(capfd, model_with_urdf(tmp_path, text))
    assert_refused(run, "robot.urdf", r"joint 'elbow_joint' is prismatic in the URDF but revolute")


def test_frame_not_in_urdf_lists_the_links(tmp_path, capfd):
    model = model_with_urdf(
        tmp_path, UR5_TEXT, edit=lambda s: s.replace('urdf = "tool0"', 'urdf = "tool"')
    )
    run = check(capfd, model)
    assert_refused(
        run, "robot.urdf", r"frame 'tool' not in URDF robot\.urdf .*; frames are: .*tool0"
    )


def test_disconnected_chain(tmp_path, capfd):
    # Cut the joint that hangs tool0 off wrist_3_link: two separate trees.
    cut = r'<joint name="wrist_3_link-tool0_fixed_joint".*?</joint>'
    text = re.sub(cut, "", UR5_TEXT, flags=re.S)
    run = check(capfd, model_with_urdf(tmp_path, text))
    assert_refused(run, "robot.urdf", r"expected one root link, found 2: tool0, world")


def test_unknown_check_frame_lists_model_frames(capfd):
    run = check(capfd, Path(bundled_model_paths()["ur5"]), "--to", "tool")
    assert_refused(
        run, "ur5", r"frame 'tool' not in model ur5; frames are: world, tcp, base, base_link"
    )


def test_unknown_backend_lists_backends(capfd):
    run = check(capfd, Path(bundled_model_paths()["ur5"]), "--against", "kdl")
    assert_refused(run, "kdl", r"unknown backend 'kdl'; backends are: rtb-dh, pinocchio-dh")


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs POSIX named pipes")
def test_mesh_paths_are_never_opened(tmp_path, capfd):
    # Every mesh of the URDF points at a FIFO: opening one for reading blocks
    # forever, so a backend that touched a mesh would hit the time limit.
    fifo = tmp_path / "mesh.stl"
    os.mkfifo(fifo)
    text = re.sub(r'filename="[^"]*"', f'filename="{fifo}"', UR5_TEXT)
    assert str(fifo) in text
    model = model_with_urdf(tmp_path, text)
    run = check(
        capfd, model, "--against", "pinocchio-urdf,yourdfpy-urdf,rtb-urdf", "--timeout", "60"
    )
    assert run.code == 0, run.out + run.err
    assert "timed out" not in run.out
    assert run.out.count("pass") >= 3


def test_read_urdf_errors_are_urdf_errors(tmp_path):
    path = tmp_path / "r.urdf"
    path.write_text(extra(joint("back", "tool0", "world")))
    with pytest.raises(UrdfError, match=r"r\.urdf: joints .* form a cycle"):
        read_urdf(path)


def test_bounds_are_inclusive_and_parsers_survive_them(tmp_path):
    # A robot exactly at the link and depth limits is read, and Pinocchio (whose
    # urdfdom recursion overflows the C stack at about 3,700 nested links) builds it.
    import pinocchio as pin

    wide, deep = tmp_path / "wide.urdf", tmp_path / "deep.urdf"
    wide.write_text(wide_robot(MAX_URDF_LINKS))
    deep.write_text(deep_robot(MAX_URDF_DEPTH))
    assert len(read_urdf(wide).links) == MAX_URDF_LINKS
    info = read_urdf(deep)
    assert len(info.chain(info.root, f"l{MAX_URDF_DEPTH}")) == MAX_URDF_DEPTH
    assert pin.buildModelFromXML(info.text).nframes > MAX_URDF_DEPTH


def test_xacro_message_quotes_a_snippet_on_one_line(tmp_path):
    path = tmp_path / "r.urdf"
    path.write_text(after_first("</link>", "\n  ${1 +\n 2} and then a long tail of text " * 2))
    with pytest.raises(UrdfError) as caught:
        read_urdf(path)
    message = str(caught.value)
    assert "\n" not in message
    expected = repr("\n  ${1 +\n 2} and then a long tail of text \n…")  # 10 before, 40 after
    assert message.endswith(
        "r.urdf: line 58: contains a xacro expression ${…} in the text after </link>: "
        f"{expected}; fkcheck runs xacro only when asked: to expand it, set xacro = true in "
        "the model's [urdf] table or pass --allow-xacro (or write a plain URDF with fkcheck "
        "expand)"
    ), message
