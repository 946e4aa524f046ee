"""`fkcheck table-from`, and `dh-from-urdf`, the name it had, which still runs and says so."""

from __future__ import annotations

from fkcheck.cli.main import main
from fkcheck.model.read import load_model
from tests.xacro_cases import twin_urdf


def test_the_former_name_runs_the_same_command_and_says_it_was_renamed(tmp_path, capsys):
    urdf = tmp_path / "arm.urdf"
    urdf.write_text(twin_urdf("0.4"))
    common = [str(urdf), "--base", "base", "--tip", "tip", "--name", "arm"]
    assert main(["table-from", *common, "-o", str(tmp_path / "new.toml")]) == 0
    new_err = capsys.readouterr().err
    assert "renamed" not in new_err
    assert main(["dh-from-urdf", *common, "-o", str(tmp_path / "old.toml")]) == 0
    old_err = capsys.readouterr().err
    assert old_err.startswith("fkcheck: dh-from-urdf was renamed table-from; running table-from\n")
    old = (tmp_path / "old.toml").read_text().replace("old.toml", "new.toml")  # its own name
    assert old == (tmp_path / "new.toml").read_text()
    model = load_model(tmp_path / "new.toml")
    assert model.dof == 3
    assert "fkcheck table-from" in model.description
    assert main(["check", str(tmp_path / "new.toml"), "--quiet", "--samples", "20"]) == 0


def test_the_help_lists_both_names(capsys):
    assert main(["--help"]) == 0
    out = capsys.readouterr().out
    assert "table-from" in out
    assert "renamed table-from (this name still works)" in out
