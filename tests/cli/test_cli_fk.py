"""`fkcheck fk` and `fkcheck models` as a user runs them: output values and exit codes."""

from __future__ import annotations

import json
import re
import subprocess
import sys

import numpy as np
import pytest

from fkcheck import load_model
from fkcheck.cli.main import main
from fkcheck.core.tolerances import SAME_CHAIN, SIX_DECIMALS
from fkcheck.model.read import bundled_model_paths
from tests import seed_ur5
from tests.helpers import assert_pose_close

ARTICLE = "30,-60,90,-120,-90,45"


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_fk_prints_the_seed_pose(capsys):
    code, out, err = run(capsys, "fk", "ur5", "--q", ARTICLE, "--deg")
    assert code == 0, err
    printed = np.array([[float(v) for v in line.split()] for line in out.strip().splitlines()])
    assert_pose_close(printed, seed_ur5.T0[6], SIX_DECIMALS)


def test_fk_json_contract(capsys):
    code, out, _ = run(capsys, "fk", "ur5", "--q", ARTICLE, "--deg", "--json")
    assert code == 0
    record = json.loads(out)
    assert set(record) == {"model", "q_rad", "matrix", "position", "rotation"}
    assert record["model"] == "ur5"
    np.testing.assert_allclose(record["q_rad"], np.deg2rad(seed_ur5.Q_DEG), atol=1e-15)
    np.testing.assert_allclose(
        record["position"], [-0.505612, -0.417951, 0.178795], atol=SIX_DECIMALS
    )
    np.testing.assert_array_equal(np.array(record["matrix"])[:3, :3], record["rotation"])


def test_fk_negative_first_value_is_not_an_option(capsys):
    code, out, err = run(capsys, "fk", "ur5", "--q", "-30,-60,90,-120,-90,45", "--deg", "--json")
    assert code == 0, err
    assert json.loads(out)["q_rad"][0] == pytest.approx(np.deg2rad(-30))


def test_fk_all_frames_prints_each_T_0_i(capsys):
    code, out, _ = run(capsys, "fk", "ur5", "--q", ARTICLE, "--deg", "--all-frames", "--json")
    assert code == 0
    frames = np.array(json.loads(out)["frames"])
    assert frames.shape == (7, 4, 4)
    for k, expected in seed_ur5.T0.items():
        assert_pose_close(frames[k], expected, SIX_DECIMALS, f"T0_{k}")
    code, out, _ = run(capsys, "fk", "ur5", "--q", ARTICLE, "--deg", "--all-frames")
    assert [ln for ln in out.splitlines() if ln.startswith("T_0_")] == [
        f"T_0_{i} =" for i in range(7)
    ]


def fk_subprocess(*argv):
    """``fkcheck fk …`` in a fresh process, as a user runs it."""
    return subprocess.run(
        [sys.executable, "-m", "fkcheck", "fk", *argv], capture_output=True, text=True, check=False
    )


def test_fk_from_to_in_a_subprocess_is_rz_pi_times_base_to_tool0():
    # ur5e's base_link is base turned π about z (ur_macro.xacro), written here by hand.
    rz_pi = np.diag([-1.0, -1.0, 1.0, 1.0])
    runs = {
        frame: fk_subprocess("ur5e", "--q", ARTICLE, "--deg", "--from", frame, "--to", "tool0",
                             "--json")
        for frame in ("base", "base_link")
    }  # fmt: skip
    for proc in runs.values():
        assert proc.returncode == 0, proc.stderr
        assert proc.stderr == ""
    base, base_link = (json.loads(runs[f].stdout) for f in ("base", "base_link"))
    assert (base_link["from"], base_link["to"]) == ("base_link", "tool0")
    assert_pose_close(base_link["matrix"], rz_pi @ np.array(base["matrix"]), SAME_CHAIN)
    # The text form prints the same matrix, six decimals.
    proc = fk_subprocess("ur5e", "--q", ARTICLE, "--deg", "--from", "base_link", "--to", "tool0")
    printed = np.array([[float(v) for v in line.split()] for line in proc.stdout.splitlines()])
    assert_pose_close(printed, base_link["matrix"], SIX_DECIMALS)


def test_fk_from_base_to_tool0_is_the_seeds_T0_6(capsys):
    code, out, err = run(capsys, "fk", "ur5", "--q", ARTICLE, "--deg", "--from", "base", "--to",
                         "tool0")  # fmt: skip
    assert code == 0, err
    printed = np.array([[float(v) for v in line.split()] for line in out.strip().splitlines()])
    assert_pose_close(printed, seed_ur5.T0[6], SIX_DECIMALS)


def test_fk_from_to_each_seed_link_in_a_model_file(tmp_path, capsys):
    # A model file naming every DH frame: --from dh{k-1} --to dh{k} prints the seed's A_k.
    text = load_model("ur5").path.read_text(encoding="utf-8")
    text += "".join(f"\n[frames.dh{k}]\ndh = {k}\n" for k in range(7))
    path = tmp_path / "ur5_dh_frames.toml"
    path.write_text(text, encoding="utf-8")
    for k in range(1, 7):
        code, out, err = run(capsys, "fk", str(path), "--q", ARTICLE, "--deg", "--from",
                             f"dh{k - 1}", "--to", f"dh{k}", "--json")  # fmt: skip
        assert code == 0, err
        assert_pose_close(json.loads(out)["matrix"], seed_ur5.A[k - 1], SIX_DECIMALS, f"A{k}")


def test_fk_from_to_on_a_q_file_and_in_a_pose_format(tmp_path, capsys, rng):
    model = load_model("ur5e")
    q = rng.uniform(-3, 3, (7, 6))
    path = tmp_path / "q.csv"
    path.write_text("".join(",".join(repr(float(v)) for v in row) + "\n" for row in q))
    expected = model.fk(q, frame_from="base_link", frame_to="flange")
    code, out, err = run(capsys, "fk", "ur5e", "--q-file", str(path), "--from", "base_link",
                         "--to", "flange")  # fmt: skip
    assert code == 0, err
    rows = np.array([[float(v) for v in ln.split()] for ln in out.strip().splitlines()])
    np.testing.assert_array_equal(rows.reshape(7, 4, 4), expected)
    code, out, err = run(capsys, "fk", "ur5e", "--q-file", str(path), "--to", "flange", "--json")
    records = json.loads(out)
    assert {(r["from"], r["to"]) for r in records} == {("world", "flange")}
    np.testing.assert_array_equal([r["matrix"] for r in records],
                                  model.fk(q, frame_to="flange"))  # fmt: skip
    first = ",".join(repr(float(v)) for v in q[0])
    code, out, err = run(capsys, "fk", "ur5e", "--q", first, "--from", "base_link", "--to",
                         "flange", "--format", "quat", "--json")  # fmt: skip
    assert code == 0, err
    np.testing.assert_array_equal(json.loads(out)["position_m"], expected[0, :3, 3])


def test_fk_without_from_to_keeps_its_json_contract(capsys):
    code, out, _ = run(capsys, "fk", "ur5", "--q", ARTICLE, "--deg", "--json")
    assert code == 0
    assert "from" not in json.loads(out)


def test_fk_unknown_frame_in_a_subprocess_is_one_line_listing_the_frames():
    proc = fk_subprocess("ur5e", "--q", "0,0,0,0,0,0", "--from", "base_lnk", "--to", "tool0")
    assert proc.returncode == 2
    assert proc.stdout == ""
    assert proc.stderr.splitlines() == [
        "fkcheck: error: frame 'base_lnk' not in model ur5e; frames are: world, tcp, base, "
        "base_link, tool0, flange"
    ]


def test_fk_named_pose(capsys):
    code, out, _ = run(capsys, "fk", "ur5", "--pose", "worked_example", "--json")
    assert code == 0
    np.testing.assert_allclose(json.loads(out)["position"], [-0.505612, -0.417951, 0.178795],
                               atol=SIX_DECIMALS)  # fmt: skip


def test_fk_q_file_batch(tmp_path, capsys, rng):
    model = load_model("ur5")
    q = rng.uniform(-3, 3, (25, 6))
    lines = ["# logged joint states, radians"] + [
        ",".join(repr(float(v)) for v in row) for row in q
    ]
    path = tmp_path / "q.csv"
    path.write_text("\n".join(lines) + "\n\n")
    code, out, _ = run(capsys, "fk", "ur5", "--q-file", str(path))
    assert code == 0
    rows = np.array([[float(v) for v in ln.split()] for ln in out.strip().splitlines()])
    assert rows.shape == (25, 16)
    assert_pose_close(rows.reshape(25, 4, 4), model.fk(q), SAME_CHAIN)
    code, out, _ = run(capsys, "fk", "ur5", "--q-file", str(path), "--json")
    records = json.loads(out)
    assert len(records) == 25
    np.testing.assert_allclose([r["matrix"] for r in records], model.fk(q), atol=SAME_CHAIN)


def test_fk_accepts_a_csv_model(capsys):
    code, out, _ = run(
        capsys, "fk", "tests/data/ur5_seed001.csv", "--q", ARTICLE, "--deg", "--json"
    )
    assert code == 0
    np.testing.assert_allclose(json.loads(out)["position"], [-0.505612, -0.417951, 0.178795],
                               atol=SIX_DECIMALS)  # fmt: skip


@pytest.mark.parametrize(
    ("argv", "match"),
    [
        (["fk", "ur5", "--q", "1,2,3"], r"--q: model ur5 has 6 joints, got 3 values"),
        (["fk", "ur5", "--q", "1,2,x,4,5,6"], r"--q: value 3: not a number: 'x'"),
        (["fk", "ur5", "--q", "1,2,nan,4,5,6"], r"--q: value 3: must be finite, got 'nan'"),
        (["fk", "ur5", "--q", "0,0,4,0,0,0"], r"joint elbow = 4 rad is outside its limits"),
        (
            ["fk", "ur5", "--q", "0,0,200,0,0,0", "--deg"],  # degrees in, degrees out
            r"joint elbow = 200° is outside its limits \[-180, 180\]° ",
        ),
        (["fk", "stanford", "--q", "0,0,5,0,0,0", "--deg"], r"joint j3 = 5 m is outside .*\] m "),
        (
            ["fk", "ur5", "--pose", "nope"],
            r"has no pose 'nope'; poses are: zero, home, worked_example",
        ),
        (["fk", "ur7", "--q", "0"], r"no bundled model of that name"),
        (
            ["fk", "ur5", "--q", "0,0,0,0,0,0", "--to", "tool9"],
            r"frame 'tool9' not in model ur5; frames are: world, tcp, base, base_link, tool0, ",
        ),
        (
            ["fk", "ur5", "--q", "0,0,0,0,0,0", "--to", "urdf:tool9"],
            r"no declared frame has URDF twin 'tool9'.*frames are: urdf:base \(= base\)",
        ),
        (
            ["fk", "ur5", "--q", "0,0,0,0,0,0", "--from", "base", "--all-frames"],
            r"--all-frames: prints every DH frame in the world; it does not combine with --from",
        ),
        (["fk", "ur5"], r"give joint values with --q, --q-file or --pose"),
        (["fk", "ur5", "--q-file", "missing.csv"], r"missing\.csv: no such file"),
        (["fk", "ur5", "--bogus"], r"unrecognized arguments: --bogus"),
        (["nonsense"], r"invalid choice: 'nonsense'"),
    ],
)
def test_bad_input_exits_2_with_one_line(capsys, argv, match):
    code, out, err = run(capsys, *argv)
    assert code == 2
    assert out == ""
    assert len(err.strip().splitlines()) == 1, err
    assert re.search(match, err), err


def test_ignore_limits_allows_out_of_range(capsys):
    code, out, _ = run(capsys, "fk", "ur5", "--q", "0,0,4,0,0,0", "--ignore-limits", "--json")
    assert code == 0
    assert json.loads(out)["q_rad"][2] == 4.0


def test_q_file_bad_line_names_the_line(tmp_path, capsys):
    path = tmp_path / "q.csv"
    path.write_text("0,0,0,0,0,0\n0,0,0\n")
    code, _, err = run(capsys, "fk", "ur5", "--q-file", str(path))
    assert code == 2
    assert f"{path}: line 2: model ur5 has 6 joints, got 3 values" in err


def test_models_lists_every_bundled_model_on_one_line_each_within_80_columns(capsys):
    code, out, _ = run(capsys, "models")
    assert code == 0
    lines = out.splitlines()
    bundled = bundled_model_paths()
    # A header, one line per model, a footer: no wrapped source text.
    assert len(lines) == len(bundled) + 2
    assert max(len(line) for line in lines) <= 80
    assert lines[0].split() == ["model", "DOF", "DH", "evidence", "(description)"]
    rows = {line.split()[0]: line.split(maxsplit=3)[1:] for line in lines[1:-1]}
    assert list(rows) == list(bundled)  # sorted by name
    assert "ur_description" not in out  # the bundled description is no model
    assert rows["ur5"] == ["6", "standard", "table + code (ur.urdf.xacro)"]
    assert rows["panda"] == ["7", "modified", "table + code (panda.urdf)"]
    assert rows["planar2"] == ["2", "standard", "code only (no description)"]
    assert rows["xarm7"] == ["7", "modified", "table + code (xarm7.urdf, 1 known difference)"]
    assert lines[-1] == (
        f"{len(bundled)} bundled models; details: fkcheck models NAME (e.g. ur5), or --long for all"
    )


def test_models_name_and_long_show_the_source_in_full(capsys, monkeypatch):
    monkeypatch.setenv("COLUMNS", "200")  # a wide table: each source on one line
    code, out, _ = run(capsys, "models", "ur5", "panda")
    assert code == 0
    assert "fkcheck:ur_description/urdf/ur.urdf.xacro" in out
    assert "DH parameters for calculations of kinematics and dynamics" in out
    assert re.search(r"│ panda +│ 7 +│ modified +│", out), out
    assert "│ ur10 " not in out  # only the named ones
    code, out, _ = run(capsys, "models", "--long")
    assert code == 0
    for name in bundled_model_paths():
        assert f"│ {name} " in out


def test_models_of_an_unknown_name_is_a_usage_error(capsys):
    code, _, err = run(capsys, "models", "ur7")
    assert code == 2
    assert "no bundled model of that name; bundled models are: baxter_left" in err


def test_console_script_entry_point_runs():
    # The installed entry point, as a user calls it (a fresh process, no reference library).
    proc = subprocess.run(
        [sys.executable, "-c", "import sys; from fkcheck.cli.main import main; "
         "code = main(['fk', 'ur5', '--q', '0,0,0,0,0,0']); "
         "heavy = [m for m in ('roboticstoolbox', 'pinocchio', 'yourdfpy') if m in sys.modules]; "
         "print('HEAVY', heavy); sys.exit(code)"],
        capture_output=True, text=True, check=False,
    )  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    assert "HEAVY []" in proc.stdout
