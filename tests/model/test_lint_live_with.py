"""Lint you can live with: per-rule ignores, true messages, clean table-from output."""

from __future__ import annotations

import json
import math
import tomllib
from dataclasses import replace

import pytest

from fkcheck import load_model
from fkcheck.cli.main import main
from fkcheck.model.lint_rules import LINT_RULES
from fkcheck.model.read import model_from_dict
from fkcheck.model.write import model_to_toml
from tests.helpers import BUNDLED


def with_joint(model, index, **changes):
    joints = list(model.joints)
    joints[index] = replace(joints[index], **changes)
    return replace(model, joints=tuple(joints))


def wide_axis(tmp_path, *, lint_table=""):
    """UR5 with a real ±400° axis (as IRB 120's axis 6), optionally a [lint] table."""
    model = with_joint(load_model("ur5"), 5, limits=(-math.radians(400), math.radians(400)))
    path = tmp_path / "wide.toml"
    path.write_text(model_to_toml(model) + lint_table, encoding="utf-8")
    return path


def rules(capsys, argv):
    code = main(["lint", *argv, "--json"])
    return code, [f["rule"] for f in json.loads(capsys.readouterr().out)["findings"]]


def test_a_wide_axis_warns_and_each_way_of_ignoring_it_silences_it(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)  # no pyproject.toml above tmp_path's own
    path = wide_axis(tmp_path)
    assert rules(capsys, [str(path)]) == (1, ["limits"])
    assert rules(capsys, [str(path), "--ignore", "limits"]) == (0, [])
    assert rules(capsys, [str(path), "--ignore", "twist"]) == (1, ["limits"])
    silenced = wide_axis(tmp_path, lint_table='\n[lint]\nignore = ["limits"]\n')
    assert rules(capsys, [str(silenced)]) == (0, [])
    (tmp_path / "pyproject.toml").write_text('[tool.fkcheck]\nlint_ignore = ["limits"]\n')
    assert rules(capsys, [str(path)]) == (0, [])


def test_the_ignore_list_survives_a_write_and_read():
    model = replace(load_model("ur5"), lint_ignore=("limits", "twist"))
    text = model_to_toml(model)
    assert '[lint]\nignore = ["limits", "twist"]' in text
    assert model_from_dict(tomllib.loads(text)).lint_ignore == ("limits", "twist")


@pytest.mark.parametrize(
    ("table", "field", "problem"),
    [
        ('[lint]\nignore = ["limits-beyond-2pi"]\n', "lint.ignore", "unknown lint rule"),
        ('[lint]\nignore = "limits"\n', "lint.ignore", "expected a list of rule names"),
        ('[lint]\nskip = ["limits"]\n', "lint.skip", "unknown key; allowed keys are: ignore"),
    ],
)
def test_a_bad_lint_table_is_exit_2_naming_the_field_and_the_rules(
    tmp_path, capsys, table, field, problem
):
    path = wide_axis(tmp_path, lint_table="\n" + table)
    assert main(["lint", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert f"{field}: {problem}" in err
    if "unknown lint rule" in problem:
        assert ", ".join(LINT_RULES) in err


def test_unknown_ignore_on_the_command_line_lists_the_rules(capsys):
    assert main(["lint", "ur5", "--ignore", "limits-beyond-2pi"]) == 2
    err = capsys.readouterr().err
    assert "--ignore: unknown lint rule 'limits-beyond-2pi'" in err
    assert ", ".join(LINT_RULES) in err


def test_unknown_rule_in_the_project_is_exit_2(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "pyproject.toml").write_text('[tool.fkcheck]\nlint_ignore = ["nope"]\n')
    assert main(["lint", "ur5"]) == 2
    assert "tool.fkcheck.lint_ignore: unknown lint rule 'nope'" in capsys.readouterr().err


def test_published_message_says_every_other_number_matches_only_when_it_does(tmp_path, capsys):
    one = with_joint(load_model("ur5"), 0, d=0.08946)
    (tmp_path / "one.toml").write_text(model_to_toml(one), encoding="utf-8")
    main(["lint", str(tmp_path / "one.toml"), "--json"])
    (message,) = [f["message"] for f in json.loads(capsys.readouterr().out)["findings"]]
    assert "; every other number matches" in message
    two = with_joint(with_joint(one, 3, d=0.10945), 4, d=0.09466)
    (tmp_path / "two.toml").write_text(model_to_toml(two), encoding="utf-8")
    main(["lint", str(tmp_path / "two.toml"), "--json"])
    messages = [f["message"] for f in json.loads(capsys.readouterr().out)["findings"]]
    assert len(messages) == 3
    assert messages[0].startswith("d1 ")
    assert "d4, d5 are close too, every other number matches" in messages[0]
    assert "d1, d5 are close too" in messages[1]
    assert "d1, d4 are close too" in messages[2]
    assert not any("; every other number matches" in m for m in messages)


def test_lint_of_many_files_prints_a_block_each_and_exits_with_the_worst(tmp_path, capsys):
    bad = wide_axis(tmp_path)
    assert main(["lint", "ur5", str(bad), "planar2"]) == 1
    lines = capsys.readouterr().out.splitlines()
    # A bundled model by its fkcheck: spec, never its place in site-packages or the checkout.
    assert lines[0] == "fkcheck:ur5.toml: clean (6 joints, standard DH)"
    assert lines[1].startswith(f"{bad}: joint[5].limits (wrist_3): warning [limits]")
    assert lines[2] == "fkcheck:planar2.toml: clean (2 joints, standard DH)"
    assert lines[3] == "fkcheck lint: 3 models, 2 clean, 1 with warnings"


def test_lint_of_many_files_checks_every_file_before_printing(tmp_path, capsys):
    broken = tmp_path / "broken.toml"
    broken.write_text("name = 'x'\n", encoding="utf-8")
    assert main(["lint", "ur5", str(broken)]) == 2
    out, err = capsys.readouterr()
    assert out == ""
    assert f"{broken}: convention: missing (required)" in err


def test_lint_of_a_directory_lints_its_model_files(tmp_path, capsys):
    wide_axis(tmp_path)
    (tmp_path / "notes.txt").write_text("not a model")
    assert main(["lint", str(tmp_path), "--json"]) == 1
    (block,) = [json.loads(capsys.readouterr().out)]
    assert block["path"] == str(tmp_path / "wide.toml")


def test_bundled_models_lint_clean_all_at_once(capsys):
    assert main(["lint", *BUNDLED]) == 0
    assert capsys.readouterr().out.splitlines()[-1] == (
        f"fkcheck lint: {len(BUNDLED)} models, {len(BUNDLED)} clean, 0 with warnings"
    )
