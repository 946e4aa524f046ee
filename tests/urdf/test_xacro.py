"""xacro, opt in: expanded in a fenced child process, then screened like a plain URDF.

The description (tests/xacro_cases.py) uses a macro three times, an argument
with a default and an override, ``${pi/2}`` and ``${a*2}``, and a ``$(find …)``
include of a declared package; it is compared with its hand-expanded twin.
"""

from __future__ import annotations

import ast
import time
from pathlib import Path

import numpy as np
import pytest

from fkcheck.cli.main import main
from fkcheck.errors import ModelError, UrdfError
from fkcheck.model.read import load_model
from fkcheck.model.write import model_to_toml
from fkcheck.urdf.chain import urdf_kinematics
from fkcheck.urdf.source import allow_xacro, load_urdf
from fkcheck.urdf.tree import read_urdf
from fkcheck.urdf.xacro import XACRO_MEMORY_BYTES, expand_xacro, read_xacro
from tests.helpers import deadline, ur5_ros1
from tests.processes import LINUX_ONLY
from tests.xacro_cases import (
    TOP,
    environ_job,
    grow_macro,
    twin_urdf,
    write_description,
    write_model,
    write_ur_description,
)

#: Exact agreement, up to the last bits of the chain products.
SAME = 1e-12

OPT_IN = (
    "set xacro = true in the model's [urdf] table or pass --allow-xacro "
    "(or write a plain URDF with fkcheck expand)"
)
PACKAGES = 'packages = { arm_description = "../arm_description" }'


def poses(info, q):
    kin = urdf_kinematics(info)
    chain = kin.chain("base", "tip")
    return kin.chain_poses(chain, q)


@pytest.mark.parametrize(("args", "reach"), [({}, "0.3"), ({"reach": "0.4"}, "0.4")])
def test_expansion_equals_the_hand_expanded_twin(tmp_path, args, reach):
    top, package = write_description(tmp_path)
    twin = tmp_path / "twin.urdf"
    twin.write_text(twin_urdf(reach))
    expanded = read_xacro(top, args, {"arm_description": package})
    plain = read_urdf(twin)
    assert expanded.links == plain.links
    assert expanded.joints == plain.joints
    q = np.random.default_rng(3).uniform(-3, 3, size=(64, 3))
    a, b = poses(expanded, q), poses(plain, q)
    np.testing.assert_allclose(a, b, rtol=0, atol=SAME)
    # The argument reaches the pose: the tip is `reach` along x of l3 at q = 0.
    at_zero = poses(expanded, np.zeros((1, 3)))[0][-1]
    assert at_zero[0, 3] == pytest.approx(0.5 + float(reach), abs=SAME)


def test_expansion_without_xacrodoc_names_the_extra_that_installs_it(tmp_path, monkeypatch):
    import importlib.util

    top, package = write_description(tmp_path)
    real = importlib.util.find_spec
    monkeypatch.setattr(
        importlib.util, "find_spec", lambda name, *a: None if name == "xacrodoc" else real(name)
    )
    wanted = (
        r"expanding xacro needs xacrodoc, which is not installed "
        r"\(pip install 'fkcheck\[reference\]'\)"
    )
    with pytest.raises(UrdfError, match=wanted):
        expand_xacro(top, {}, {"arm_description": package})


def test_expansion_leaves_no_file_behind(tmp_path):
    top, package = write_description(tmp_path)
    before = sorted(tmp_path.rglob("*"))
    expand_xacro(top, {}, {"arm_description": package})
    assert sorted(tmp_path.rglob("*")) == before


def test_check_passes_with_xacro_true(tmp_path, capsys):
    write_description(tmp_path)
    extra = f'xacro = true\nxacro_args = {{ reach = "0.4" }}\n{PACKAGES}'
    model = write_model(tmp_path, "0.4", extra)
    code = main(["check", str(model), "--quiet", "--samples", "40"])
    out, err = capsys.readouterr()
    assert code == 0, out + err
    assert "verdict: pass — table verified independently" in out
    for backend in ("pinocchio-urdf", "yourdfpy-urdf", "rtb-urdf"):
        row = next(line for line in out.splitlines() if f" {backend} " in line)
        assert " pass " in row, row


def test_check_fails_when_the_argument_disagrees_with_the_table(tmp_path, capsys):
    # Without the override, reach is its default 0.3 while the table says 0.4: the
    # URDF backends must see the difference (the argument really reaches them).
    write_description(tmp_path)
    model = write_model(tmp_path, "0.4", f"xacro = true\n{PACKAGES}")
    code = main(["check", str(model), "--quiet", "--samples", "20", "--no-diagnose"])
    out, err = capsys.readouterr()
    assert code == 1, out + err
    assert "verdict: fail" in out


def test_refused_without_the_opt_in_naming_it(tmp_path, capsys):
    write_description(tmp_path)
    model = write_model(tmp_path, "0.4", f'xacro_args = {{ reach = "0.4" }}\n{PACKAGES}')
    code = main(["check", str(model), "--quiet", "--samples", "20"])
    out, err = capsys.readouterr()
    assert code == 2
    assert err.count("\n") == 1
    assert "Traceback" not in err
    assert "arm.urdf.xacro: line 3: has a xacro element <arg>" in err
    assert OPT_IN in err
    with pytest.raises(UrdfError, match="pass --allow-xacro"):
        load_urdf(load_model(model))
    # --allow-xacro on the command line is the same opt-in.
    code = main(["check", str(model), "--allow-xacro", "--quiet", "--samples", "20"])
    out, err = capsys.readouterr()
    assert code == 0, out + err


def test_diagnose_takes_allow_xacro(tmp_path, capsys):
    write_description(tmp_path)
    model = write_model(tmp_path, "0.4", f'xacro_args = {{ reach = "0.4" }}\n{PACKAGES}')
    assert main(["diagnose", str(model), "--samples", "20"]) == 2
    assert "--allow-xacro" in capsys.readouterr().err
    code = main(["diagnose", str(model), "--samples", "20", "--allow-xacro"])
    out, err = capsys.readouterr()
    assert code == 0, out + err


def test_allow_xacro_sets_the_flag_only():
    model = ur5_ros1()  # a plain URDF, no opt-in
    allowed = allow_xacro(model)
    assert allowed.urdf is not None
    assert model.urdf is not None
    assert allowed.urdf.xacro
    assert not model.urdf.xacro
    assert allowed.urdf.path == model.urdf.path
    assert allowed.joints == model.joints
    planar = load_model("planar2")
    assert allow_xacro(planar) is planar


# --- the fence: packages, files, environment, time, memory, the screen afterwards ----


def expand_top(tmp_path, top, args=None, packages=None, timeout_s=30.0):
    path, package = write_description(tmp_path, top)
    declared = {"arm_description": package} if packages is None else packages
    return expand_xacro(path, args or {}, declared, timeout_s).text


def test_undeclared_package_is_one_line_naming_the_declared(tmp_path):
    with pytest.raises(UrdfError) as caught:
        expand_top(tmp_path, TOP, packages={"other_pkg": tmp_path})
    message = str(caught.value)
    assert "\n" not in message
    assert (
        "arm.urdf.xacro: xacro expansion failed: $(find arm_description): package "
        "'arm_description' is not declared; declared packages: other_pkg" in message
    )
    assert "--package arm_description=DIR" in message


def test_find_never_looks_at_ros_package_path(tmp_path, monkeypatch):
    # A ROS environment that does have the package: fkcheck must not use it.
    _, package = write_description(tmp_path / "ros")
    monkeypatch.setenv("ROS_PACKAGE_PATH", str(package.parent))
    monkeypatch.setenv("AMENT_PREFIX_PATH", str(package.parent))
    with pytest.raises(UrdfError, match="declared packages: none"):
        expand_top(tmp_path / "mine", TOP, packages={})


def test_a_declared_package_must_be_a_directory(tmp_path):
    with pytest.raises(UrdfError, match=r"package .arm_description. is declared at .*, not a dir"):
        expand_top(tmp_path, TOP, packages={"arm_description": tmp_path / "missing"})


def test_include_outside_the_allowed_directories_is_refused(tmp_path):
    secret = tmp_path / "secret.xacro"
    secret.write_text('<robot><link name="stolen"/></robot>')
    top = TOP.replace(
        '<link name="base"/>', f'<xacro:include filename="{secret}"/><link name="base"/>'
    )
    with pytest.raises(UrdfError, match=r"include of '.*secret\.xacro': outside the xacro file's"):
        expand_top(tmp_path, top)


def test_load_yaml_outside_the_allowed_directories_is_refused(tmp_path):
    (tmp_path / "secret.yaml").write_text("a: 1\n")
    top = TOP.replace(
        '<link name="base"/>',
        f'<xacro:property name="s" value="${{xacro.load_yaml(\'{tmp_path / "secret.yaml"}\')}}"/>'
        '<link name="base"/><link name="y${s[\'a\']}"/>',
    )
    with pytest.raises(UrdfError, match=r"load_yaml of '.*secret\.yaml': outside"):
        expand_top(tmp_path, top)


@LINUX_ONLY
def test_the_expansion_process_is_executed_with_an_empty_environment(tmp_path, monkeypatch):
    # Not cleared after start: /proc/PID/environ keeps what a process was executed with.
    import fkcheck.urdf.xacro as xacro_module

    monkeypatch.setenv("FKCHECK_TEST_SECRET", "s3cr3t")
    monkeypatch.setattr(xacro_module, "_expand_job", environ_job)  # pickled by name: runs there
    text = expand_top(tmp_path, TOP)
    own, supervisor, names = ast.literal_eval(text)
    assert own == b""
    assert supervisor == b""
    assert "FKCHECK_TEST_SECRET" not in names
    assert "PATH" not in names


@pytest.mark.parametrize("expression", ["$(env HOME)", "$(optenv HOME fallback)"])
def test_the_environment_is_never_read(tmp_path, expression):
    top = TOP.replace('<link name="tip"/>', f'<link name="tip"><!-- x -->{expression}</link>')
    with pytest.raises(UrdfError, match=r"fkcheck does not read the environment for xacro"):
        expand_top(tmp_path, top)


def test_eval_is_evaluated_as_xacro_does(tmp_path):
    # $(eval …) is evaluated like ${…}, by fkcheck's evaluator, with the arguments as names.
    top = TOP.replace('xyz="0 0 0.2"', 'xyz="0 0 $(eval 0.1 * 2)"')
    path, package = write_description(tmp_path, top)
    info = read_xacro(path, {}, {"arm_description": package})
    assert 'xyz="0 0 0.2"' in info.text


def growing(leaf: str, depth: int) -> str:
    """TOP with a macro that calls itself twice per level, ``depth`` levels: 2**depth leaves."""
    return TOP.replace('<link name="base"/>', grow_macro(leaf, depth) + '<link name="base"/>')


def test_a_loop_is_stopped_by_the_time_limit(tmp_path):
    # No expression loops; macros can: 2**40 calls.
    top = growing("", 40)
    with deadline(20), pytest.raises(UrdfError, match=r"did not end within 2 s \(stopped\)"):
        expand_top(tmp_path, top, timeout_s=2.0)


def test_a_huge_expansion_is_stopped_by_the_memory_limit(tmp_path):
    # Each value is bounded (32 Mi characters); 256 of them are not.
    top = growing("<link name=\"${'x' * 30 * 2**20}\"/>", 8)
    gib = XACRO_MEMORY_BYTES // 1024**3
    with deadline(30), pytest.raises(UrdfError, match=f"needs more than {gib} GiB of memory"):
        expand_top(tmp_path, top)


def test_a_huge_value_is_refused_before_it_is_built(tmp_path):
    top = TOP.replace('value="0.25"', "value=\"${'x' * 10**10}\"")
    with deadline(20), pytest.raises(UrdfError, match=r"\$\{'x' \* 10\*\*10\}: a string longer"):
        expand_top(tmp_path, top)


def test_a_huge_expansion_is_refused_by_size(tmp_path):
    # Each value within the limit, the text they make is not.
    top = TOP.replace(
        '<link name="tip"/>', "<link name=\"tip\">${'x' * 20 * 2**20}${'y' * 20 * 2**20}</link>"
    )
    with (
        deadline(30),
        pytest.raises(UrdfError, match="its expansion is larger than 33554432 bytes"),
    ):
        expand_top(tmp_path, top)


def test_an_expansion_keeping_a_dtd_is_refused_by_the_screen(tmp_path):
    top = TOP.replace(
        '<?xml version="1.0"?>', '<?xml version="1.0"?>\n<!DOCTYPE robot [<!ENTITY e "0.3">]>'
    )
    path, package = write_description(tmp_path, top)
    # xacro keeps the DTD; the screen refuses it
    assert "<!DOCTYPE" in expand_xacro(path, {}, {"arm_description": package}).text
    with pytest.raises(UrdfError, match=r"has a DTD \(<!DOCTYPE …>\)"):
        read_xacro(path, {}, {"arm_description": package})


def test_xacro_left_after_expansion_is_refused_by_the_screen(tmp_path):
    # xacro does not evaluate a CDATA section: ${…} in one comes out as written.
    top = TOP.replace('<link name="tip"/>', '<link name="tip"><![CDATA[${1 + 1}]]></link>')
    path, package = write_description(tmp_path, top)
    with pytest.raises(UrdfError, match=r"contains a xacro expression \$\{…\}"):
        read_xacro(path, {}, {"arm_description": package})


def test_a_missing_argument_names_the_ways_to_give_it(tmp_path):
    # xacro 2 requires a default on <xacro:arg>; an undeclared $(arg …) is the missing one.
    top = TOP.replace("$(arg reach)", "$(arg offset)")
    with pytest.raises(UrdfError) as caught:
        expand_top(tmp_path, top)
    assert "xacro argument 'offset' is not given and has no default" in str(caught.value)
    assert "--arg offset=VALUE" in str(caught.value)
    assert expand_top(tmp_path / "given", top, args={"offset": "0.1"}).count('xyz="0.1 0 0"') == 1


def test_a_xacro_error_is_one_line(tmp_path):
    top = TOP.replace('value="0.25"', 'value="${1/0}"')
    with pytest.raises(UrdfError) as caught:
        expand_top(tmp_path, top)
    message = str(caught.value)
    assert "\n" not in message
    assert "xacro expansion failed: ${1/0}: division by zero" in message


# --- the model file's [urdf] keys -------------------------------------------------


@pytest.mark.parametrize(
    ("line", "field", "problem"),
    [
        ('xacro = "yes"', "urdf.xacro", "expected true or false, got a string"),
        ("xacro_args = { reach = 0.4 }", "urdf.xacro_args.reach", "expected a string"),
        ('xacro_args = ["reach"]', "urdf.xacro_args", "expected a table"),
        ('packages = { "bad name" = "x" }', "urdf.packages.bad name", "not a package name"),
        ("packages = { p = 1 }", "urdf.packages.p", "expected a string (a directory"),
        ("xacro_arg = {}", "urdf.xacro_arg", "unknown key; allowed keys are: joints, packages"),
    ],
)
def test_model_keys_are_checked(tmp_path, line, field, problem):
    write_description(tmp_path)
    path = write_model(tmp_path, "0.4", line)
    with pytest.raises(ModelError) as caught:
        load_model(path)
    message = str(caught.value)
    assert "xarm.toml" in message, message
    assert field in message, message
    assert problem in message, message


def test_model_keys_round_trip_through_the_writer(tmp_path):
    write_description(tmp_path)
    extra = f'xacro = true\nxacro_args = {{ reach = "0.4" }}\n{PACKAGES}'
    model = load_model(write_model(tmp_path, "0.4", extra))
    assert model.urdf is not None
    assert model.urdf.xacro
    assert model.urdf.xacro_args == {"reach": "0.4"}
    assert model.urdf.packages == {"arm_description": "../arm_description"}
    again = tmp_path / "robot" / "again.toml"
    again.write_text(model_to_toml(model))
    assert load_model(again).urdf == model.urdf


@pytest.mark.parametrize(
    ("expression", "refusal"),
    [
        # round two's ways out (dunders inside a lambda or a comprehension, python.type and
        # python.vars): refused by what they are, not by their names
        (r"${(lambda: ().__class__.__base__.__subclasses__())()}",
         r"\$\{\(lambda: \(\)\.__class__.*\}: a lambda is not allowed"),
        (r"${[c for c in ().__class__.__mro__]}", r"a comprehension is not allowed"),
        (r"${python.vars(python)}", r"vars is not available .*\(it gives an object's namespace\)"),
        (r"${python.type(1)}", r"type is not available .*\(it gives Python classes\)"),
    ],
)  # fmt: skip
def test_the_ways_out_of_xacros_expression_check_are_closed(tmp_path, expression, refusal):
    top = TOP.replace('xyz="0 0 0.2"', f'xyz="0 0 {expression}"')
    with pytest.raises(UrdfError, match=f"xacro expansion failed: .*{refusal}"):
        expand_top(tmp_path, top)


def test_the_file_is_expanded_once_per_check_and_only_for_backends_that_read_it(
    tmp_path, monkeypatch
):
    """The expansion runs the file's Python: once for all backends, never for DH-only checks."""
    import fkcheck.urdf.source as source
    import fkcheck.urdf.xacro as xacro_module
    from fkcheck.backends.registry import make_backend
    from fkcheck.engine.runner import run_check

    write_description(tmp_path)
    extra = f'xacro = true\nxacro_args = {{ reach = "0.4" }}\n{PACKAGES}'
    model = load_model(write_model(tmp_path, "0.4", extra))
    calls: list[str] = []
    expand = xacro_module.expand_xacro

    def counted(*args, **kwargs):
        calls.append("expanded")
        return expand(*args, **kwargs)

    monkeypatch.setattr(xacro_module, "expand_xacro", counted)
    check = run_check(model, [make_backend("rtb-dh")], samples=5)
    assert check.verdict == "pass"
    assert calls == []  # no backend reads the URDF: the file never ran
    xacro_module._CACHE.clear()
    backends = [make_backend(n) for n in ("pinocchio-urdf", "yourdfpy-urdf", "rtb-urdf")]
    check = run_check(model, backends, samples=5)
    assert check.verdict == "pass"
    assert calls == ["expanded"]  # once, here
    # What an isolated backend's own process does with the model it is sent: the text
    # the engine kept is screened again, the file is not run again.
    sent = check.model
    assert sent.urdf is not None
    assert sent.urdf.expanded is not None
    monkeypatch.setattr(xacro_module, "expand_xacro", lambda *a, **k: pytest.fail("expanded again"))
    assert source.read_model_urdf(sent).joints.keys() == load_urdf(sent).joints.keys()


def test_map_takes_allow_xacro_as_every_refusal_says(tmp_path, capsys):
    write_description(tmp_path)
    model = write_model(tmp_path, "0.4", f'xacro_args = {{ reach = "0.4" }}\n{PACKAGES}')
    assert main(["map", str(model)]) == 2
    assert "pass --allow-xacro" in capsys.readouterr().err
    assert main(["map", str(model), "--allow-xacro"]) == 0
    out, err = capsys.readouterr()
    assert 'joints = ["j1", "j2", "j3"]' in out
    assert "fkcheck map: xarm onto arm.urdf.xacro: 3 joints" in err
    # And a xacro URDF named on the command line, with its arguments and package.
    package = tmp_path / "arm_description"
    top = tmp_path / "robot" / "arm.urdf.xacro"
    argv = ["map", str(model), str(top), "--allow-xacro", "--arg", "reach=0.4",
            "--package", f"arm_description={package}"]  # fmt: skip
    assert main(argv) == 0, capsys.readouterr().err


def test_a_plain_urdf_with_the_opt_in_is_read_as_plain_xacro_never_runs(
    monkeypatch, capsys, tmp_path
):
    import fkcheck.urdf.xacro as xacro_module

    def never(*_args, **_kwargs):
        raise AssertionError("xacro ran on a plain URDF")

    monkeypatch.setattr(xacro_module, "expand_xacro", never)
    model = tmp_path / "ur5_ros1.toml"  # example-robot-data's plain ur5_robot.urdf
    model.write_text(model_to_toml(ur5_ros1()), encoding="utf-8")
    argv = ["check", str(model), "--allow-xacro", "--samples", "8", "--against", "pinocchio-urdf"]
    code = main(argv)
    out = capsys.readouterr().out
    assert code == 0, out
    assert "table verified" in out


# --- a UR-style description: the same text as xacro's own evaluation gave -----------

GOLDEN = Path(__file__).parents[1] / "golden"


@pytest.mark.parametrize("variant", ["find", "relative"])
@pytest.mark.parametrize(
    ("args", "golden"),
    [({}, "xacro_ur_style.urdf"),
     ({"safety_limits": "true", "prefix": "a_", "ur_type": "ur5"}, "xacro_ur_style_safety.urdf")],
)  # fmt: skip
def test_a_ur_style_description_expands_as_xacro_expanded_it(tmp_path, variant, args, golden):
    """Properties, yaml with units, dotted keys, a namespace, macros, conditionals, math, eval.

    The golden files are what xacro's own evaluation (Python's eval, before fkcheck's
    evaluator) made of the ``find`` variant; the ``relative`` variant names its files
    with ``$(dirname)`` and paths relative to the xacro file (which failed then).
    """
    top, package = write_ur_description(tmp_path, variant)
    expansion = expand_xacro(top, args, {"ur_description": package})
    assert expansion.text == (GOLDEN / golden).read_text()
    config = package / "config" / "ur5"
    assert set(expansion.files) == {
        top, package / "urdf" / "ur_macro.xacro", package / "urdf" / "colors.xacro",
        config / "default_kinematics.yaml", config / "joint_limits.yaml",
    }  # fmt: skip
    info = read_xacro(top, args, {"ur_description": package})
    assert len(info.joints) == 9
    if args:
        assert "a_shoulder_pan_joint" in info.joints


def test_load_yaml_and_dirname_are_relative_to_the_file_being_read(tmp_path, monkeypatch):
    # Not to the working directory, nor to the top file: to the file that names them,
    # when it is read (a macro's body is read where the macro is called, as in xacro).
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)
    top, package = write_description(tmp_path)
    (package / "urdf" / "names.yaml").write_text("link: from_yaml\n")
    (top.parent / "names.yaml").write_text("link: wrong_file\n")
    parts = package / "urdf" / "parts.xacro"
    parts.write_text(
        parts.read_text().replace(
            "</robot>",
            "<link name=\"${xacro.load_yaml('names.yaml')['link']}\"/>"
            '<link name="$(dirname)/x"/></robot>',
        )
    )
    text = expand_xacro(top, {}, {"arm_description": package}).text
    assert '<link name="from_yaml"/>' in text
    assert f'<link name="{package.resolve() / "urdf"}/x"/>' in text


def test_check_timeout_bounds_the_expansion_too(tmp_path, capsys):
    write_description(tmp_path, growing("", 40))
    model = write_model(tmp_path, "0.3", f"xacro = true\n{PACKAGES}")
    start = time.perf_counter()
    with deadline(30):
        code = main(["check", str(model), "--samples", "5", "--timeout", "2"])
    out, err = capsys.readouterr()
    assert code == 2, out + err
    assert err.count("\n") == 1
    assert "xacro expansion did not end within 2 s (stopped)" in err
    assert time.perf_counter() - start < 15


def test_a_kept_expansion_is_used_only_while_every_file_it_read_is_unchanged(tmp_path, monkeypatch):
    """The per-process cache is keyed by the bytes of every file read, not a date."""
    import os

    import fkcheck.urdf.xacro as xacro_module

    xacro_module._CACHE.clear()
    path, package = write_description(tmp_path)
    calls: list[Path] = []
    expand = xacro_module.expand_xacro

    def counted(where, *args, **kwargs):
        calls.append(where)
        return expand(where, *args, **kwargs)

    monkeypatch.setattr(xacro_module, "expand_xacro", counted)
    packages = {"arm_description": package}
    first = read_xacro(path, {}, packages)
    assert read_xacro(path, {}, packages) is first  # kept
    assert len(calls) == 1
    parts = package / "urdf" / "parts.xacro"  # an included file: same size, same mtime
    stat = parts.stat()
    parts.write_text(parts.read_text().replace('upper="3"', 'upper="2"'))
    os.utime(parts, ns=(stat.st_atime_ns, stat.st_mtime_ns))
    assert parts.stat().st_size == stat.st_size
    changed = read_xacro(path, {}, packages)
    assert len(calls) == 2
    assert changed.text != first.text
    assert read_xacro(path, {"reach": "0.5"}, packages) is not changed  # another argument
    assert len(calls) == 3


def test_an_expansion_that_looked_for_files_is_not_kept(tmp_path, monkeypatch):
    """A wildcard include may match a file added later: such an expansion runs each time."""
    import fkcheck.urdf.xacro as xacro_module

    xacro_module._CACHE.clear()
    top = TOP.replace(
        '<link name="tip"/>', '<xacro:include filename="extra/*.xacro"/><link name="tip"/>'
    )
    path, package = write_description(tmp_path, top)
    (path.parent / "extra").mkdir()
    calls: list[Path] = []
    expand = xacro_module.expand_xacro
    monkeypatch.setattr(
        xacro_module, "expand_xacro", lambda *a, **k: calls.append(a[0]) or expand(*a, **k)
    )
    packages = {"arm_description": package}
    read_xacro(path, {}, packages)
    read_xacro(path, {}, packages)
    assert len(calls) == 2
