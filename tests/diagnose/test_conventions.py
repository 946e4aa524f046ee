"""A vendor's table against a ROS-Industrial-style URDF: several conventions apart at once.

The FANUC-like arm's J3–J6 turn the other way in its URDF; the KUKA-like arm's A1,
A4 and A6 do, its A2 and A3 zeros are a quarter turn apart, and its tool frame
was typed without the URDF's turn (:mod:`tests.vendor_arms`: the URDFs are
written from the dimensions with numpy, not by fkcheck). ``diagnose`` must name
the combination and print the model-file edits; the edits, applied to the file
as printed, must make the real check pass.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from fkcheck import load_model
from fkcheck.backends import registry
from fkcheck.cli.main import main
from fkcheck.diagnose import diagnose
from fkcheck.engine.runner import run_check
from tests.backend_cases import URDF_BACKENDS
from tests.vendor_arms import FANUC, KUKA, VendorArm, write_arm

SAMPLES = ["--samples", "30"]


def printed_edits(out: str) -> tuple[list[str], str]:
    """The ``[[joint]]`` edit lines and the ``[frames…]`` TOML of the first explanation."""
    first = out.split("\n\n")[1]
    lines = first.splitlines()
    edits: list[str] = []
    toml: list[str] = []
    mode = ""
    for line in lines:
        if line.strip() in ("edit, in the model file:",):
            mode = "edits"
            continue
        if line.strip() in ("and set these tables:", "fix, in the model file:"):
            mode = "toml"
            continue
        if mode == "edits" and line.startswith("     [[joint]]"):
            edits.append(line.strip())
        elif mode == "toml" and line.startswith("     "):
            toml.append(line[5:])
    return edits, "\n".join(toml) + ("\n" if toml else "")


_EDIT = re.compile(r"^\[\[joint\]\] (?P<joint>\S+): (?P<key>\w+) = (?P<value>\S+)")


def apply_printed(path: Path, edits: list[str], toml: str) -> None:
    """Apply printed edits to the model file as a user would: by hand, key by key."""
    text = path.read_text(encoding="utf-8")
    for edit in edits:
        m = _EDIT.match(edit)
        assert m is not None, edit
        head = f'[[joint]]\nname = "{m["joint"]}"\n'
        start = text.index(head) + len(head)
        end = text.find("\n\n", start)
        end = len(text) if end < 0 else end
        block = text[start:end]
        line = f"{m['key']} = {m['value']}"
        if re.search(rf"^{m['key']} = ", block, flags=re.M):
            block = re.sub(rf"^{m['key']} = .*$", line, block, flags=re.M)
        else:
            block = block.rstrip("\n") + "\n" + line
        text = text[:start] + block + text[end:]
    for table in re.split(r"\n(?=\[frames\.)", toml.strip()):
        if not table:
            continue
        header = table.splitlines()[0]
        start = text.index(header + "\n")
        end = text.index("\n\n", start)
        text = text[:start] + table + text[end:]
    path.write_text(text, encoding="utf-8")


def check_passes(path: Path) -> bool:
    """The real check, against every URDF backend that runs here."""
    model = load_model(path)
    backends = [registry.make_backend(name) for name in URDF_BACKENDS]
    result = run_check(model, backends, samples=32)
    assert result.verdict in ("pass", "fail"), [b.message for b in result.backends]
    return result.verdict == "pass"


@pytest.mark.parametrize(
    ("arm", "tool", "title", "expected"),
    [
        (
            FANUC,
            (0.0, 0.0, 180.0),
            "J3, J4, J5, J6 turn the other way",
            [f"[[joint]] J{k}: flip = true" for k in (3, 4, 5, 6)],
        ),
        (
            KUKA,
            (0.0, 0.0, 0.0),
            "A1, A4, A6 turn the other way; the zeros differ: A2's by -90°, A3's by +90°; "
            "the frames at the ends differ",
            [
                "[[joint]] A1: flip = true",
                "[[joint]] A2: theta = -90 (was 0: θ2's zero -90° away)",
                "[[joint]] A3: theta = 90 (was 0: θ3's zero +90° away)",
                "[[joint]] A4: flip = true",
                "[[joint]] A6: flip = true",
            ],
        ),
    ],
    ids=["fanuc-like", "kuka-like"],
)
def test_the_combination_is_named_and_its_printed_edits_make_the_check_pass(
    tmp_path, capsys, arm: VendorArm, tool, title, expected
):
    path = write_arm(arm, tmp_path, tool)
    assert not check_passes(path)
    assert main(["diagnose", str(path), *SAMPLES]) == 0
    out = capsys.readouterr().out
    assert f"1. [conventions] the table and the URDF differ by conventions: {title}\n" in out
    assert "no hypothesis explains" not in out
    edits, toml = printed_edits(out)
    assert [e.split(" (was")[0] for e in edits] == [e.split(" (was")[0] for e in expected]
    assert edits == expected
    if arm is KUKA:  # the tool frame typed without the URDF's turn: its fix is printed too
        assert toml.startswith("[frames.tool0]\ndh = 6\n")
    else:
        assert toml == ""
    apply_printed(path, edits, toml)
    assert check_passes(path)
    # And the edited file has nothing left to explain; what the agreement leaves open
    # (the tool frame's turn carries α6 and θ6) is named, with what would settle it.
    assert main(["diagnose", str(path), *SAMPLES, "--json", str(tmp_path / "d.json")]) == 0
    out = capsys.readouterr().out
    hidden = ["α6", "θ6"]
    assert "the table agrees with the reference, but 2 numbers are not identifiable" in out
    last = arm.rows[-1][0]
    for name in hidden:
        axis = "x" if name == "α6" else "z"
        line = (
            f"   {name} (joint 6 ({last})): [frames.tool0]: rotation about {axis} of DH frame 6\n"
        )
        assert line in out
    assert "or take [frames.tool0] from the vendor's drawing" in out
    data = json.loads((tmp_path / "d.json").read_text(encoding="utf-8"))
    assert [u["name"] for u in data["not_identifiable"]] == hidden
    assert all(
        u["settle"].startswith("compare frames that sit exactly") for u in data["not_identifiable"]
    )


def test_a_table_error_on_top_of_the_conventions_is_named_with_them(tmp_path, capsys):
    """KUKA's conventions plus a2 typed 1 mm long: the edits, and the one number left."""
    path = write_arm(KUKA, tmp_path)
    text = path.read_text(encoding="utf-8")
    path.write_text(text.replace("a = 0.68\n", "a = 0.681\n"), encoding="utf-8")
    assert main(["diagnose", str(path), *SAMPLES]) == 0
    out = capsys.readouterr().out
    assert "1. [conventions] the table and the URDF differ by conventions: A1, A4, A6 turn" in out
    assert "; and one number differs: a2 (A2)\n" in out
    edits, toml = printed_edits(out)
    assert "[[joint]] A2: a = 0.68 (was 0.681: a2 differs)" in edits
    apply_printed(path, edits, toml)
    assert check_passes(path)


def test_what_the_edits_leave_is_said(tmp_path):
    """Two numbers off on top of the conventions: the edits explain part, and say what is left."""
    path = write_arm(KUKA, tmp_path)
    text = path.read_text(encoding="utf-8")
    text = text.replace("a = 0.68\n", "a = 0.69\n").replace("d = 0.67\n", "d = 0.68\n")
    path.write_text(text, encoding="utf-8")
    result = diagnose(load_model(path), registry.make_backend("pinocchio-urdf"), samples=20)
    [conventions] = [e for e in result.explanations if e.kind == "conventions"]
    assert not conventions.explains
    assert conventions.residual.position_m < result.before.position_m / 2
    assert any("unexplained: something else differs too" in d for d in conventions.details)
    assert "[[joint]] A1: flip = true" in conventions.edits


def test_one_flip_alone_is_left_to_its_own_hypothesis(tmp_path):
    """A single reversed joint is the ``flip`` hypothesis, not a combination."""
    arm = VendorArm(FANUC.name, FANUC.rows, ("J4",), {})
    path = write_arm(arm, tmp_path, (0.0, 0.0, 180.0))
    result = diagnose(load_model(path), registry.make_backend("pinocchio-urdf"), samples=20)
    assert result.best is not None
    assert result.best.kind == "flip"
    assert "J4" in result.best.title
    assert not [e for e in result.explanations if e.kind == "conventions"]


def test_the_html_report_of_the_failing_check_carries_the_edits(tmp_path, capsys, monkeypatch):
    path = write_arm(KUKA, tmp_path)
    monkeypatch.chdir(tmp_path)
    html = tmp_path / "report.html"
    argv = ["check", str(path), "--samples", "16", "--against", "pinocchio-urdf", "--html"]
    assert main([*argv, str(html)]) == 1
    out = capsys.readouterr().out
    assert "diagnosis (pinocchio-urdf): the table and the URDF differ by conventions: A1, A4" in out
    page = html.read_text(encoding="utf-8")
    at = page.index('<pre class="fix-edits">')
    edits = page[at : page.index("</pre>", at)]
    assert "[[joint]] A1: flip = true\n[[joint]] A2: theta = -90" in edits
    assert "And set these tables:" in page
