"""How the fkcheck program ends: its exit code and output intact, exit hooks run,
the interpreter not finalized (its libraries' teardown is time with nothing to write)."""

from __future__ import annotations

import subprocess
import sys
import textwrap
from pathlib import Path

PROGRAM = """
    import atexit, sys
    from pathlib import Path

    import fkcheck.cli.main as cli

    hook, final = Path(sys.argv[1]), Path(sys.argv[2])
    atexit.register(hook.write_text, "exit hooks ran")

    class Finalized:
        def __del__(self):
            final.write_text("finalized")

    keep = Finalized()  # a module global: collected only when the interpreter finalizes
    sys.argv = ["fkcheck", *sys.argv[3:]]
    cli.main()
    print("not reached")
"""


def _program(tmp_path: Path, *args: str) -> tuple[subprocess.CompletedProcess[str], Path, Path]:
    script = tmp_path / "program.py"
    script.write_text(textwrap.dedent(PROGRAM), encoding="utf-8")
    hook, final = tmp_path / "hook", tmp_path / "final"
    done = subprocess.run(
        [sys.executable, str(script), str(hook), str(final), *args],
        capture_output=True, text=True, timeout=300, check=False, cwd=tmp_path,
    )  # fmt: skip
    return done, hook, final


def test_a_finished_check_keeps_its_code_and_output_runs_exit_hooks_and_skips_finalizing(tmp_path):
    done, hook, final = _program(tmp_path, "check", "ur5", "--samples", "2", "--against", "rtb-dh")
    assert done.returncode == 0, done.stderr
    assert done.stdout.rstrip().splitlines()[-1].startswith("verdict: pass")
    assert "not reached" not in done.stdout
    assert hook.read_text() == "exit hooks ran"
    assert not final.exists()
    assert done.stderr == ""


def test_bad_input_still_ends_with_exit_2_and_its_one_line(tmp_path):
    done, hook, _ = _program(tmp_path, "check", "no-such-model")
    assert done.returncode == 2
    assert done.stderr.count("\n") == 1
    assert done.stderr.startswith("fkcheck: error: ")
    assert hook.exists()


def test_a_run_that_code_it_calls_ends_with_sys_exit_0_is_never_exit_0(monkeypatch, capsys):
    # CI reads exit 0 as a pass: a run ended before its verdict must not give it.
    import fkcheck.backends.registry as registry
    from fkcheck.cli.main import main

    def ends(*args: object, **kwargs: object) -> None:
        sys.exit(0)

    monkeypatch.setattr(registry, "parse_against", ends)
    assert main(["check", "ur5", "--samples", "2", "--against", "rtb-dh"]) == 1
    captured = capsys.readouterr()
    assert "verdict" not in captured.out
    assert captured.err == (
        "fkcheck: error: the run was ended by sys.exit(0) before it finished: no verdict, "
        "no report written\n"
    )
