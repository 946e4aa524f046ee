"""No output replaces a file the run reads: a xacro's includes and ``load_yaml`` files too.

The description (:mod:`tests.xacro_cases`) includes ``parts.xacro`` from its
package and, here, loads ``xarm.json`` (YAML) from there; the model opts in with
``xacro = true``. Every command that writes is pointed at each of those files:
exit 2, one line naming what the file is, no file changed or created.
"""

from __future__ import annotations

import hashlib
from pathlib import Path

import pytest

from fkcheck.cli.main import main
from tests.xacro_cases import TOP, write_description, write_model

PACKAGES = 'packages = { arm_description = "../arm_description" }'
LOADED = "xarm.json"
#: TOP with ``a`` read from a YAML file of the package, by ``xacro.load_yaml``.
LOAD = f"xacro.load_yaml('$(find arm_description)/{LOADED}')"
TOP_WITH_YAML = TOP.replace(
    '<xacro:property name="a" value="0.25"/>',
    f'<xacro:property name="cfg" value="${{{LOAD}}}"/>'
    '<xacro:property name="a" value="${cfg[\'a\']}"/>',
)


def snapshot(root: Path) -> dict[str, str]:
    """Every file under ``root`` and a hash of its content."""
    return {
        str(p.relative_to(root)): hashlib.sha256(p.read_bytes()).hexdigest()
        for p in sorted(root.rglob("*"))
        if p.is_file()
    }


@pytest.fixture
def xarm(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """The description and its model (``robot/xarm.toml``) in the working directory."""
    monkeypatch.chdir(tmp_path)
    _top, package = write_description(tmp_path, TOP_WITH_YAML)
    (package / LOADED).write_text('{"a": 0.25}\n')
    write_model(tmp_path, "0.4", f'xacro = true\nxacro_args = {{ reach = "0.4" }}\n{PACKAGES}')
    return tmp_path


MODEL = "robot/xarm.toml"
XACRO = "robot/arm.urdf.xacro"
INCLUDED = "arm_description/urdf/parts.xacro"
YAML = f"arm_description/{LOADED}"
XACRO_OPTIONS = ["--allow-xacro", "--package", "arm_description=arm_description",
                 "--arg", "reach=0.4"]  # fmt: skip
FEW = ["--samples", "3"]

#: (id, argv with {target} the file the output is pointed at).
COMMANDS = [
    ("check-json-dh-only", ["check", MODEL, *FEW, "--against", "rtb-dh", "--json", "{target}"]),
    ("check-html", ["check", MODEL, *FEW, "--against", "pinocchio-urdf", "--html", "{target}"]),
    ("check-junit", ["check", MODEL, *FEW, "--against", "rtb-dh", "--junit", "{target}"]),
    ("check-summary", ["check", MODEL, *FEW, "--against", "rtb-dh", "--summary", "{target}"]),
    ("diagnose-json", ["diagnose", MODEL, "--samples", "5", "--json", "{target}"]),
    ("urdf-o", ["urdf", MODEL, "-o", "{target}"]),
    ("urdf-write-model", ["urdf", MODEL, "-o", "new.urdf", "--write-model", "{target}"]),
    ("convert-o", ["convert", MODEL, "--to", "modified", *FEW, "-o", "{target}"]),
    ("bench-json", ["bench", MODEL, "--n", "4", "--repeat", "1", "--json", "{target}"]),
    ("map-o", ["map", MODEL, "--samples", "8", "-o", "{target}"]),
    ("map-urdf-o", ["map", MODEL, XACRO, "--samples", "8", *XACRO_OPTIONS, "-o", "{target}"]),
    ("table-from-o", ["table-from", XACRO, "--base", "base", "--tip", "tip", *XACRO_OPTIONS,
                        "-o", "{target}"]),
    ("expand-o", ["expand", XACRO, "--package", "arm_description=arm_description", "-o",
                  "{target}"]),
]  # fmt: skip


@pytest.mark.parametrize(
    ("target", "what"),
    [
        pytest.param(INCLUDED, "reads (xacro include or load_yaml)", id="included"),
        pytest.param(YAML, "reads (xacro include or load_yaml)", id="load_yaml"),
    ],
)
@pytest.mark.parametrize(("argv"), [pytest.param(a, id=i) for i, a in COMMANDS])
def test_no_output_replaces_a_file_the_xacro_reads(xarm, capsys, argv, target, what):
    if argv[0] == "expand":
        what = "a file the xacro file includes"
    before = snapshot(xarm)
    code = main([a.replace("{target}", target) for a in argv])
    err = capsys.readouterr().err
    assert code == 2, err
    assert err.count("\n") == 1, err
    assert err.startswith("fkcheck: error: "), err
    assert f"{target}: is " in err, err
    assert what in err, err
    assert "an input of this run" in err, err
    assert snapshot(xarm) == before  # nothing changed, nothing created


def test_out_dir_is_refused_when_a_report_would_replace_a_file_the_xacro_reads(xarm, capsys):
    before = snapshot(xarm)
    argv = ["check", MODEL, *FEW, "--against", "rtb-dh", "--out-dir", "arm_description"]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err == (
        f"fkcheck: error: --out-dir arm_description/{LOADED}: is a file the URDF of xarm reads "
        "(xacro include or load_yaml), an input of this run: write elsewhere\n"
    )
    assert snapshot(xarm) == before


def test_a_check_that_writes_expands_the_xacro_once(xarm, capsys, monkeypatch):
    """Naming the files runs the expansion; the check's URDF backends reuse it."""
    import fkcheck.urdf.xacro as xacro_module

    xacro_module._CACHE.clear()
    calls: list[Path] = []
    expand = xacro_module.expand_xacro

    def counted(path, *args, **kwargs):
        calls.append(path)
        return expand(path, *args, **kwargs)

    monkeypatch.setattr(xacro_module, "expand_xacro", counted)
    argv = ["check", MODEL, *FEW, "--against", "pinocchio-urdf,rtb-dh", "--json", "out.json"]
    assert main(argv) == 0, capsys.readouterr().err
    assert len(calls) == 1
    assert Path("out.json").is_file()


def test_a_check_that_writes_nothing_does_not_expand_for_dh_only_backends(
    xarm, capsys, monkeypatch
):
    import fkcheck.urdf.xacro as xacro_module

    xacro_module._CACHE.clear()
    monkeypatch.setattr(xacro_module, "expand_xacro", lambda *a, **k: pytest.fail("expanded"))
    assert main(["check", MODEL, *FEW, "--against", "rtb-dh"]) == 0, capsys.readouterr().err
