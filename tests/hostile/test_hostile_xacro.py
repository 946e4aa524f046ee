"""Hostile xacro, opted in by the model file alone: nothing beyond xacro's expressions runs.

A model with ``xacro = true`` in its ``[urdf]`` (no flag on the command line, as
in a pull request checked by CI) names a xacro description that tries to get
out: through a generator's frame to the real builtins, format strings,
``$(eval …)`` with Python's builtins, a yaml unit tag, the environment, files
outside its directory and declared packages. Each is refused with exit 2 and
one line naming the file (and the expression), writes no file, changes no file,
prints no secret. The payloads that write a file did so before fkcheck evaluated
expressions itself (``generator-frame-builtins``, ``eval-builtins``).
"""

from __future__ import annotations

import re
import time
from dataclasses import dataclass
from pathlib import Path

import pytest

from fkcheck.cli.main import main
from tests.helpers import deadline
from tests.xacro_cases import TOP, write_description, write_model

#: What a payload would create in the working directory.
MARKER = "FKCHECK_MARKER"
#: A secret in a file next to the description and in the environment.
SECRET = "s3cr3t-token-9d41aa"
SECRET_VAR = "FKCHECK_TEST_SECRET"
#: Every run ends within this many seconds.
TIME_BOUND_S = 30.0
PACKAGES = 'packages = { arm_description = "../arm_description" }'

#: A generator whose frame's caller's caller is xacro's own module: its builtins, open().
GENERATOR = (
    "[(g := (g.gi_frame.f_back.f_back.f_builtins for _ in [1])), list(g)][1][0]"
    f"['open']('{MARKER}', 'w').write('x')"
)


@dataclass(frozen=True)
class Escape:
    """A payload put in the description, and the refusal expected (a regex)."""

    payload: str
    refusal: str
    yaml: str | None = None  # evil.yaml next to the description


ESCAPES: dict[str, Escape] = {
    # the audit's: a running generator's frame leads back to xacro's module
    "generator-frame-builtins": Escape(
        "${" + GENERATOR + "}", r"\$\{\[\(g := .*\}: an assignment \(:=\) is not allowed"
    ),
    "generator-without-walrus": Escape(
        "${python.list((x.gi_frame.f_back for x in [1]))}",
        r"a generator expression is not allowed",
    ),
    "format-string-from-a-property": Escape(
        "${fmt.format(1.0)}", r"\$\{fmt\.format\(1\.0\)\}: string method \.format\(\) is not"
    ),
    "format-through-str": Escape(
        "${str.format(fmt, 1.0)}", r"attribute \.format of str \(a function\) is not allowed"
    ),
    "percent-format": Escape("${'%r' % 1.5}", r"string formatting with % is not allowed"),
    "f-string": Escape("${f'x'}", r"an f-string is not allowed"),
    "lambda": Escape("${(lambda: 1)()}", r"a lambda is not allowed"),
    "comprehension": Escape("${[c for c in python.range(3)]}", r"a comprehension is not allowed"),
    "getattr": Escape("${getattr(1, 'real')}", r"name 'getattr' is not defined"),
    "attribute-of-a-number": Escape("${(1.0).real}", r"attribute \.real of a float is not"),
    "vars": Escape("${python.vars(python)}", r"vars is not available"),
    "type": Escape("${python.type(1)}", r"type is not available"),
    "function-globals": Escape(
        "${xacro.load_yaml.__globals__}", r"attribute \.__globals__ of xacro\.load_yaml"
    ),
    "namespace-dict": Escape("${math.__dict__}", r"math\.__dict__ is not defined"),
    "import": Escape(
        f"${{__import__('os').system('touch {MARKER}')}}", r"name '__import__' is not defined"
    ),
    "open": Escape(f"${{open('{MARKER}', 'w')}}", r"name 'open' is not defined"),
    "mapping-mutation": Escape("${dict(a=1).pop('a')}", r"mapping method \.pop\(\) is not"),
    # $(eval …) ran Python's eval with the real builtins: no '__' needed
    "eval-builtins": Escape(
        f"$(eval open('{MARKER}', 'w'${{b}}.write('x'${{b}})",
        r"\$\(eval open\('FKCHECK_MARKER', 'w'\)\.write\('x'\)\): name 'open' is not defined",
    ),
    "eval-generator": Escape(
        "$(eval list(x.gi_frame for x in [1]${b})", r"a generator expression is not allowed"
    ),
    # a yaml unit tag was evaluated by xacro's eval too
    "yaml-unit": Escape(
        "${xacro.load_yaml('evil.yaml')['a']}",
        r"load_yaml of 'evil\.yaml': !degrees \[\(g := .*: an assignment \(:=\) is not allowed",
        yaml=f'a: !degrees "{GENERATOR}"\n',
    ),
    "yaml-python-object": Escape(
        "${xacro.load_yaml('evil.yaml')}",
        r"load_yaml of 'evil\.yaml': could not determine a constructor for the tag "
        r"'tag:yaml\.org,2002:python/object/apply:os\.system'",
        yaml=f'a: !!python/object/apply:os.system ["touch {MARKER}"]\n',
    ),
    "yaml-aliases-bomb": Escape(
        "${xacro.load_yaml('evil.yaml')}",
        r"load_yaml of 'evil\.yaml': more than 100000 items",
        yaml="a: &a [1, 1, 1, 1, 1, 1, 1, 1, 1, 1]\n"
        + "".join(
            f"{chr(98 + i)}: &{chr(98 + i)} [{', '.join(['*' + chr(97 + i)] * 10)}]\n"
            for i in range(8)
        ),
    ),
    # the environment
    "env": Escape(f"$(env {SECRET_VAR})", r"fkcheck does not read the environment"),
    "optenv": Escape(f"$(optenv {SECRET_VAR} none)", r"fkcheck does not read the environment"),
    "eval-env": Escape(
        f"$(eval env('{SECRET_VAR}'${{b}})", r"fkcheck does not read the environment"
    ),
    # files outside the description's directory and its declared packages
    "load-yaml-climbing-out": Escape(
        "${xacro.load_yaml('../secret.txt')}", r"load_yaml of '\.\./secret\.txt': outside"
    ),
    "load-yaml-absolute": Escape(
        "${xacro.load_yaml('/etc/passwd')}", r"load_yaml of '/etc/passwd': outside"
    ),
    "load-yaml-through-a-symlink": Escape(
        "${xacro.load_yaml('link.yaml')}", r"load_yaml of 'link\.yaml': outside"
    ),
    "include-climbing-out": Escape(
        '<xacro:include filename="../secret.txt"/>', r"include of '.*secret\.txt': outside"
    ),
    "include-wildcard-outside": Escape(
        '<xacro:include filename="/etc/*"/>', r"include of '/etc/\*': outside"
    ),
    "include-wildcard-climbing-out": Escape(
        '<xacro:include filename="*/../../secret.txt"/>',
        r"'\.\.' after a wildcard is not allowed",
    ),
}


@pytest.fixture
def workdir(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """tmp_path as the working directory: a secret file, a secret variable."""
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv(SECRET_VAR, SECRET)
    (tmp_path / "secret.txt").write_text(SECRET + "\n")
    (tmp_path / "out").mkdir()
    return tmp_path


def snapshot(root: Path) -> dict[str, tuple[int, int] | None]:
    """Every file below ``root``: size and mtime (directories: that they exist).

    A directory's mtime is left out: ``check`` probes that it can write its outputs
    (a file created and removed) before it reads the model.
    """
    return {
        str(path.relative_to(root)): (
            None if path.is_dir() else (path.lstat().st_size, path.lstat().st_mtime_ns)
        )
        for path in root.rglob("*")
    }


def write_hostile(root: Path, escape: Escape) -> Path:
    """The description with the payload in it, and a model opting in; the model file."""
    extra = (
        '<xacro:property name="b" value=")"/>'  # $(…) ends at the first ')': a property gives one
        '<xacro:property name="fmt" value="{0.__class__.__mro__}"/>'
    )
    if escape.payload.startswith("<"):
        body = escape.payload
    else:
        body = f'<gazebo reference="tip">{escape.payload}</gazebo>'
    top = TOP.replace('<link name="tip"/>', f'{extra}<link name="tip"/>{body}')
    path, _ = write_description(root, top)
    (path.parent / "link.yaml").symlink_to(root / "secret.txt")
    if escape.yaml is not None:
        (path.parent / "evil.yaml").write_text(escape.yaml)
    return write_model(root, "0.3", f"xacro = true\n{PACKAGES}")


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
    out, err = capfd.readouterr()
    return Run(code, out, err, time.perf_counter() - start)


COMMANDS = {
    "check": lambda model, top, out: ["check", model, "--samples", "5", "--json", out / "r.json"],
    "expand": lambda model, top, out: [
        "expand", top, "--package", f"arm_description={top.parent.parent / 'arm_description'}",
        "-o", out / "robot.urdf",
    ],
}  # fmt: skip


@pytest.mark.parametrize("command", sorted(COMMANDS))
@pytest.mark.parametrize("name", sorted(ESCAPES))
def test_hostile_xacro_is_refused_in_one_line_and_nothing_happens(name, command, workdir, capfd):
    escape = ESCAPES[name]
    model = write_hostile(workdir, escape)
    top = workdir / "robot" / "arm.urdf.xacro"
    before = snapshot(workdir)
    run = run_cli(capfd, COMMANDS[command](model, top, workdir / "out"))
    assert run.code == 2, (run.out, run.err)
    lines = run.err.splitlines()
    assert len(lines) == 1, run.err
    assert lines[0].startswith(f"fkcheck: error: {top}: xacro expansion failed: "), run.err
    assert re.search(escape.refusal, lines[0]), run.err
    assert "Traceback" not in run.out + run.err
    assert SECRET not in run.out + run.err, "a secret was read"
    assert not (workdir / MARKER).exists(), "a payload ran"
    assert snapshot(workdir) == before, "a file was created or changed"
    assert run.seconds < TIME_BOUND_S


def test_a_refusal_in_an_included_file_names_that_file(workdir, capfd):
    write_hostile(workdir, ESCAPES["open"])
    parts = workdir / "arm_description" / "urdf" / "parts.xacro"
    text = parts.read_text().replace("</robot>", '<link name="${open}"/></robot>')
    parts.write_text(text)  # outside the macro: evaluated while parts.xacro is read
    model = workdir / "robot" / "xarm.toml"
    run = run_cli(capfd, ["check", model, "--samples", "5"])
    assert run.code == 2
    assert (
        "xacro expansion failed: in ../arm_description/urdf/parts.xacro: ${open}: "
        "name 'open' is not defined" in run.err
    ), run.err
