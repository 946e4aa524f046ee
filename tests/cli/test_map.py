"""``fkcheck map`` and ``check --from/--to urdf:LINK`` from the command line."""

from __future__ import annotations

import json
import shlex
import tomllib
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from fkcheck.cli.main import main
from fkcheck.model.write import model_to_toml
from fkcheck.urdf.locate import locate_urdf
from tests.helpers import ur5_ros1
from tests.paths import REPO_ROOT
from tests.vendor_arms import FANUC, KUKA, write_arm

UR5_URDF = "example-robot-data:ur_description/urdf/ur5_robot.urdf"
FAST = ["--samples", "16"]


def test_map_prints_a_block_to_paste(capsys):
    assert main(["map", "ur5"]) == 0
    out, err = capsys.readouterr()
    block = tomllib.loads(out)
    assert block["urdf"] == {
        "path": "fkcheck:ur_description/urdf/ur.urdf.xacro",
        "joints": [
            "shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint",
            "wrist_1_joint", "wrist_2_joint", "wrist_3_joint",
        ],
        "xacro": True,
        "xacro_args": {"ur_type": "ur5", "name": "ur5"},
        "packages": {"ur_description": "fkcheck:ur_description"},
    }  # fmt: skip
    ros2 = "Universal_Robots_ROS2_Description 2.4.5, ur_macro.xacro"
    assert block["frames"]["base_link"].pop("source").startswith(ros2)
    assert block["frames"]["base_link"] == {"dh": 0, "rpy": [0.0, 0.0, 180.0], "urdf": "base_link"}
    assert block["frames"]["tool0"] == {"dh": 6, "urdf": "tool0"}
    assert block["frames"]["flange"].pop("source").startswith(ros2)
    assert block["frames"]["flange"] == {"dh": 6, "rpy": [-90.0, -90.0, 0.0], "urdf": "flange"}
    assert "# tool0: max deviation" in out
    assert "fkcheck map: ur5 onto ur.urdf.xacro: 6 joints" in err


def test_map_writes_the_block_to_a_file(tmp_path, capsys):
    target = tmp_path / "block.toml"
    assert main(["map", "panda", "-o", str(target)]) == 0
    frames = tomllib.loads(target.read_text(encoding="utf-8"))["frames"]
    assert frames["panda_link8"] == {"dh": "tcp", "urdf": "panda_link8"}
    assert f"wrote {target}" in capsys.readouterr().out


def test_map_onto_another_urdf_names_it_relative_to_the_model(tmp_path, capsys):
    model = tmp_path / "ur5.toml"
    model.write_text((REPO_ROOT / "models" / "ur5.toml").read_text(encoding="utf-8"))
    urdf = tmp_path / "robot.urdf"
    urdf.write_bytes(locate_urdf(UR5_URDF)[0].read_bytes())
    assert main(["map", str(model), str(urdf)]) == 0
    assert tomllib.loads(capsys.readouterr().out)["urdf"]["path"] == "robot.urdf"


def test_a_wrong_table_exits_1_saying_how_near_the_nearest_came(tmp_path, capsys):
    text = (REPO_ROOT / "models" / "ur5.toml").read_text(encoding="utf-8")
    wrong = tmp_path / "ur5_wrong.toml"
    # Two numbers off (another arm's, say): no chain moves like it, even one number changed.
    wrong.write_text(text.replace("a = -0.39225", "a = -0.29225").replace("a = -0.425", "a = -0.5"))
    assert main(["map", str(wrong)]) == 1
    out, err = capsys.readouterr()
    assert "no chain of the URDF moves like the table (the nearest leaves the last DH frame" in err
    assert "NO URDF link sits at a constant offset from DH frame 6: the nearest" in out


def test_a_sign_typed_the_other_way_is_named_as_the_edit(tmp_path, capsys):
    text = (REPO_ROOT / "models" / "ur5.toml").read_text(encoding="utf-8")
    wrong = tmp_path / "ur5_wrong.toml"
    wrong.write_text(text.replace("alpha = 90\nd = 0.10915", "alpha = -90\nd = 0.10915"))
    assert main(["map", str(wrong)]) == 1
    out, err = capsys.readouterr()
    assert err == (
        "fkcheck map: ur5 onto ur.urdf.xacro: the chain moves like the table only with these "
        "rows changed (the block's comments say so too): [[joint]] wrist_1: alpha = 90 (was "
        "-90: α4's sign)\n"
    )
    assert "#   [[joint]] wrist_1: alpha = 90 (was -90: α4's sign)" in out


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["map", "nosuch"], "no bundled model of that name"),
        (["map", "puma560"], "has no [urdf]: give the URDF"),
        (["map", "ur5", "missing.urdf"], "missing.urdf"),
        (["map", "ur5", "--samples", "-1"], "--samples"),
    ],
)
def test_bad_input_is_one_line_and_exit_2(argv, message, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert message in err
    assert err.count("\n") == 1


def test_check_to_an_undeclared_link(tmp_path, capsys):
    report = tmp_path / "r.json"
    argv = ["check", "ur5", "--to", "urdf:wrist_2_link", *FAST, "--json", str(report)]
    assert main([*argv, "--against", "pinocchio-urdf,pinocchio-dh"]) == 0
    assert "base → urdf:wrist_2_link" in capsys.readouterr().out
    backends = {b["name"]: b for b in json.loads(report.read_text(encoding="utf-8"))["backends"]}
    assert backends["pinocchio-urdf"]["status"] == "pass"
    # The DH backend is skipped, saying the offset came from the URDF.
    skipped = backends["pinocchio-dh"]
    assert skipped["status"] == "skipped"
    assert "urdf:wrist_2_link is declared by no frame" in skipped["message"]
    assert "only URDF backends compare it" in skipped["message"]


def test_check_to_a_link_of_a_wrong_table_says_no_placement_can_be_trusted(tmp_path, capsys):
    text = (REPO_ROOT / "models" / "ur5.toml").read_text(encoding="utf-8")
    assert text.count("a = -0.39225\n") == 1
    wrong = tmp_path / "ur5.toml"  # a3 10 mm long
    wrong.write_text(text.replace("a = -0.39225\n", "a = -0.40225\n"), encoding="utf-8")
    assert main(["check", str(wrong), "--to", "urdf:shoulder_link", *FAST]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert (
        "URDF link 'shoulder_link' moves with URDF joint 'shoulder_pan_joint' (DH joint 1: it "
        "belongs on DH frame 1), but no placement of it on model ur5's DH frames can be "
        "trusted: the table and the URDF disagree over the chain"
    ) in err
    # The right table places the same link on DH frame 1.
    assert main(["check", "ur5", "--to", "urdf:shoulder_link", *FAST]) == 0


def test_check_to_an_unknown_link_lists_the_links(capsys):
    assert main(["check", "ur5", "--to", "urdf:nosuch", *FAST]) == 2
    err = capsys.readouterr().err
    assert "'nosuch'" in err
    assert "wrist_2_link" in err
    assert err.count("\n") == 1


@pytest.fixture
def ur5_without_base(tmp_path: Path) -> Path:
    """ur5.toml copied next to a URDF without UR's `base` link (as in a user's own)."""
    root = ET.parse(locate_urdf(UR5_URDF)[0]).getroot()
    for el in list(root):
        child = el.find("child")
        if (el.tag == "link" and el.get("name") == "base") or (
            el.tag == "joint" and child is not None and child.get("link") == "base"
        ):
            root.remove(el)
    ET.ElementTree(root).write(tmp_path / "robot.urdf")
    text = model_to_toml(ur5_ros1())  # the bundled UR5 on that ROS 1 URDF
    assert UR5_URDF in text
    model = tmp_path / "ur5.toml"
    model.write_text(text.replace(UR5_URDF, "robot.urdf"), encoding="utf-8")
    return model


def test_a_frame_whose_link_is_absent_is_an_error_only_where_used(ur5_without_base, capsys):
    model = str(ur5_without_base)
    assert main(["check", model, "--from", "base_link", *FAST, "--against", "pinocchio-urdf"]) == 0
    capsys.readouterr()
    assert main(["check", model, *FAST, "--against", "pinocchio-urdf"]) == 2  # [check] from base
    err = capsys.readouterr().err
    assert "'base' not in URDF robot.urdf (frame base)" in err
    assert "base_link" in err
    assert err.count("\n") == 1


def test_map_keeps_a_frame_whose_link_is_absent_without_one(ur5_without_base, capsys):
    assert main(["map", str(ur5_without_base)]) == 0
    out = capsys.readouterr().out
    assert tomllib.loads(out)["frames"]["base"] == {"dh": 0}
    assert "its URDF link 'base' is not a link of robot.urdf" in out


def test_map_of_a_xacro_file_opts_the_block_in_and_check_passes_on_it(tmp_path, capsys):
    from tests.xacro_cases import write_description, write_model

    top, package = write_description(tmp_path)
    full = write_model(tmp_path, "0.4", "").read_text(encoding="utf-8")
    table = tmp_path / "robot" / "table.toml"
    table.write_text(full[: full.index("[urdf]")], encoding="utf-8")  # the joints only
    block = tmp_path / "robot" / "block.toml"
    argv = ["map", str(table), str(top), "-o", str(block), *FAST]
    assert main(argv) == 2  # xacro, and no opt-in: refused, naming it
    assert "--allow-xacro" in capsys.readouterr().err
    xacro = ["--allow-xacro", "--arg", "reach=0.4", "--package", f"arm_description={package}"]
    assert main([*argv, *xacro]) == 0, capsys.readouterr().err
    urdf = tomllib.loads(block.read_text(encoding="utf-8"))["urdf"]
    assert urdf == {
        "path": "arm.urdf.xacro",
        "joints": ["j1", "j2", "j3"],
        "xacro": True,
        "xacro_args": {"reach": "0.4"},
        "packages": {"arm_description": "../arm_description"},
    }
    pasted = tmp_path / "robot" / "pasted.toml"
    pasted.write_text(table.read_text() + "\n" + block.read_text(), encoding="utf-8")
    capsys.readouterr()
    code = main(["check", str(pasted), "--samples", "40", "--from", "base", "--to", "tip"])
    out = capsys.readouterr().out
    assert code == 0, out
    assert "table verified" in out


def test_map_of_a_plain_urdf_with_the_opt_in_does_not_opt_the_block_in(tmp_path, capsys):
    model = tmp_path / "ur5.toml"
    model.write_text((REPO_ROOT / "models" / "ur5.toml").read_text(encoding="utf-8"))
    urdf = tmp_path / "robot.urdf"
    urdf.write_bytes(locate_urdf(UR5_URDF)[0].read_bytes())
    assert main(["map", str(model), str(urdf), "--allow-xacro", *FAST]) == 0
    assert set(tomllib.loads(capsys.readouterr().out)["urdf"]) == {"path", "joints"}


def _ur5_table_only(tmp_path, old="", new=""):
    """The bundled UR5's table, no [urdf], no frames, no [check]; one number changed."""
    text = (REPO_ROOT / "models" / "ur5.toml").read_text(encoding="utf-8").split("\n[urdf]")[0]
    text = text.split("# The ROS UR description")[0]
    if old:
        assert old in text
        text = text.replace(old, new, 1)
    path = tmp_path / "arm.toml"
    path.write_text(text, encoding="utf-8")
    return path


@pytest.mark.parametrize(
    ("old", "new", "frame", "hidden"),
    [
        ("d = 0.089159", "d = 0.099159", "base", "d1: translation along z of DH frame 0"),
        ("d = 0.0823\ntheta = 0", "d = 0.0823\ntheta = 20", "tool0",
         "θ6: rotation about z of DH frame 6"),
    ],
)  # fmt: skip
def test_map_never_hides_a_first_or_last_row_error_in_an_offset(
    capsys, tmp_path, old, new, frame, hidden
):
    model = _ur5_table_only(tmp_path, old, new)
    assert main(["map", str(model), UR5_URDF]) == 0
    out, err = capsys.readouterr()
    # The frame over which the error went is flagged, in the block and the summary.
    head = out[: out.index(f"[frames.{frame}]")]
    above = head[head.rindex("\n[", 0, len(head) - 1) if "\n[" in head else 0 :]
    assert "NOT IDENTIFIABLE" in above.split("\n\n")[-1]  # the comments over this frame
    assert f"#   {hidden}" in out
    assert "fkcheck cannot tell" in err
    # Pasted with its [check], the check passes — and says the table is not all verified.
    block = tmp_path / "block.toml"
    block.write_text(out, encoding="utf-8")
    model.write_text(model.read_text(encoding="utf-8") + "\n" + out, encoding="utf-8")
    assert main(["check", str(model), *FAST, "--against", "pinocchio-urdf"]) == 0
    verdict = capsys.readouterr().out
    assert "table verified except" in verdict
    assert "table verified independently" not in verdict


def test_map_on_the_right_table_names_the_links_that_compete_and_a_vouch_settles_them(
    capsys, tmp_path
):
    # ROS 1's UR5 description has base_link and base half a turn apart: the right
    # table maps onto base, a table with θ1 off by 180° onto base_link. At the tip,
    # wrist_3_link sits where α6 + 90° and d6 − 82.3 mm would put DH frame 6. Which
    # link is the DH frame is the vendor's word, not something the poses can tell.
    model = _ur5_table_only(tmp_path)
    assert main(["map", str(model), UR5_URDF]) == 0
    out, err = capsys.readouterr()
    assert tomllib.loads(out)["check"] == {"from": "base", "to": "tool0"}
    assert (
        "can verify every number of the table except θ1, α6, d6, θ6 not identifiable (link" in err
    )
    assert "base_link" in err
    assert "wrist_3_link" in err
    table = model.read_text(encoding="utf-8")
    model.write_text(table + "\n" + out, encoding="utf-8")
    assert main(["check", str(model), *FAST, "--against", "pinocchio-urdf"]) == 0
    printed = " ".join(capsys.readouterr().out.split())
    assert "table verified except θ1, α6, d6, θ6 not identifiable (link" in printed
    assert "table verified independently" not in printed
    # The vendor's word, as a source on the compared frames: verified, and said so.
    vouched = out.replace(
        '[frames.base]\ndh = 0\nurdf = "base"',
        '[frames.base]\ndh = 0\nurdf = "base"\nsource = "UR: base is DH 0"',
    )
    vouched = vouched.replace(
        '[frames.tool0]\ndh = 6\nurdf = "tool0"',
        '[frames.tool0]\ndh = 6\nurdf = "tool0"\nsource = "UR: tool0"',
    )
    assert vouched.count("\nsource = ") == 2
    model.write_text(table + "\n" + vouched, encoding="utf-8")
    assert main(["check", str(model), *FAST, "--against", "pinocchio-urdf",
                 "--require", "table"]) == 0  # fmt: skip
    printed = " ".join(capsys.readouterr().out.split())
    assert (
        "verdict: pass — table verified independently, θ1, α6, d6, θ6 on the word of "
        '[frames.base] ("UR: base is DH 0"), [frames.tool0] ("UR: tool0"); no second '
        "implementation ran"
    ) in printed


UR_ROS2 = [
    "fkcheck:ur_description/urdf/ur.urdf.xacro", "--allow-xacro", "--arg", "ur_type=ur5e",
    "--arg", "name=ur5e", "--package", "ur_description=fkcheck:ur_description",
]  # fmt: skip


def _ur5e_table_only(tmp_path, old, new):
    text = (REPO_ROOT / "models" / "ur5e.toml").read_text(encoding="utf-8").split("[poses]")[0]
    assert old in text
    path = tmp_path / "arm.toml"
    path.write_text(text.replace(old, new, 1), encoding="utf-8")
    return path


@pytest.mark.parametrize(
    ("old", "new", "number", "pair", "rival"),
    [
        # θ1 = 180°: map moved the pair to base_link, and the check said "table verified".
        ("d = 0.1625\ntheta = 0", "d = 0.1625\ntheta = 180", "θ1", ("base_link", "tool0"),
         "base"),
        # α6 = 180°: map moved it to ft_frame.
        ("alpha = 0\nd = 0.0996", "alpha = 180\nd = 0.0996", "α6", ("base", "ft_frame"),
         "tool0"),
    ],
)  # fmt: skip
def test_map_then_check_never_verifies_a_half_turn_hidden_in_the_choice_of_link(
    capsys, tmp_path, old, new, number, pair, rival
):
    model = _ur5e_table_only(tmp_path, old, new)
    assert main(["map", str(model), *UR_ROS2]) == 0
    out, err = capsys.readouterr()
    assert tomllib.loads(out)["check"] == dict(zip(("from", "to"), pair, strict=True))
    # map says so, and names the rivals
    hidden, rivals = err.split("except ", 1)[1].split(" not identifiable (link", 1)
    assert number in hidden.split(", ")
    assert rival in rivals.split(" of the description")[0]
    model.write_text(model.read_text(encoding="utf-8") + "\n" + out, encoding="utf-8")
    code = main(["check", str(model), *FAST, "--against", "pinocchio-urdf", "--require", "table",
                 "--json", str(tmp_path / "r.json")])  # fmt: skip
    printed = " ".join(capsys.readouterr().out.split())
    assert code == 1
    assert "verdict: unverified" in printed
    partly = printed.split("table PARTLY verified", 1)[1]
    assert number in partly.split(" not identifiable (link")[0]
    result = json.loads((tmp_path / "r.json").read_text(encoding="utf-8"))
    evidence = next(n for n in result["numbers"]["numbers"] if n["name"] == number)
    assert evidence["pair_can"] == "not-identifiable"
    assert rival in evidence["competing"]


def _printed_check(summary: str) -> list[str]:
    """The ``fkcheck check …`` command that map's summary says to run, as argv for main."""
    line = next(line for line in summary.splitlines() if "; check it: " in line)
    argv = shlex.split(line.split("; check it: ", 1)[1])
    assert argv[:2] == ["fkcheck", "check"]
    return argv[1:]


@pytest.mark.parametrize(
    ("extra", "flags", "frames"),
    [
        # The model's own [check] (tolerances only) compares world → tcp: map gives them twins.
        ("[check]\ntol_pos_m = 1e-06\n", [], {"world": "base", "tcp": "tool0"}),
        # With a [base], no link sits on the world: the printed command names the pair.
        ("[base]\nxyz = [0.1, 0.0, 0.0]\nrpy = [0, 0, 45]\n\n[check]\ntol_pos_m = 1e-06\n",
         ["--from", "base", "--to", "tool0"], {"tcp": "tool0"}),
        # No [check] of its own: the block's [check] is live, the command is plain.
        ("", [], {}),
    ],
)  # fmt: skip
def test_the_block_pasted_passes_the_check_map_prints(capsys, tmp_path, extra, flags, frames):
    model = _ur5_table_only(tmp_path)
    model.write_text(model.read_text(encoding="utf-8") + "\n" + extra, encoding="utf-8")
    assert main(["map", str(model), UR5_URDF, *FAST]) == 0
    out, err = capsys.readouterr()
    argv = _printed_check(err)
    assert argv == ["check", str(model), *flags]
    block = tomllib.loads(out)
    assert {k: v["urdf"] for k, v in block["frames"].items() if k in ("world", "tcp")} == frames
    model.write_text(model.read_text(encoding="utf-8") + "\n" + out, encoding="utf-8")
    assert main([*argv, *FAST, "--against", "pinocchio-urdf"]) == 0
    assert "verdict: pass — table verified" in capsys.readouterr().out


@pytest.mark.parametrize("arm", [FANUC, KUKA], ids=["fanuc-like", "kuka-like"])
def test_a_vendors_conventions_are_named_and_the_edited_table_with_the_block_passes(
    tmp_path, capsys, monkeypatch, arm
):
    """A vendor's table onto its ROS-Industrial-style URDF (written apart, tests.vendor_arms).

    The KUKA-like arm's zeros differ too: before, no chain moved like the table.
    The edits the block's comments name, made by hand, and the block pasted in
    place of the model's own mapping, pass the real check.
    """
    path = write_arm(arm, tmp_path)
    assert main(["map", str(path)]) == 1
    block, err = capsys.readouterr()
    flips = ", ".join(arm.reversed)
    assert f"joints {flips} turn the other way in the URDF: toggle their flip" in err
    zeros = [
        f"[[joint]] {name}: theta = {zero:g} (was 0: θ{name[-1]}'s zero {zero:+g}° away)"
        for name, zero in arm.zeros.items()
    ]
    for line in zeros:
        assert f"#   {line}\n" in block
    assert ("only with these rows changed" in err) == bool(zeros)
    assert "NO " not in block
    text = path.read_text(encoding="utf-8")
    table = text[text.index("[[joint]]") :]
    for name in arm.reversed:  # by hand, as the comments say
        head = f'[[joint]]\nname = "{name}"\n'
        assert f"set flip = true on [[joint]] {name}" in block
        table = table.replace(head, head + "flip = true\n")
    for name, zero in arm.zeros.items():
        head = f'[[joint]]\nname = "{name}"\n'
        start = table.index(head)
        table = table[:start] + table[start:].replace("theta = 0.0", f"theta = {zero:g}", 1)
    head = text[: text.index("[urdf]")]
    head += text[text.index("[check]") : text.index("[[joint]]")]  # the model's own check
    pasted = tmp_path / "pasted.toml"
    pasted.write_text(head + block + "\n" + table, encoding="utf-8")
    monkeypatch.chdir(tmp_path)
    assert main(["check", str(pasted), "--samples", "16"]) == 0, capsys.readouterr()
