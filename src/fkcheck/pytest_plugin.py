"""The pytest plugin: your robots' tables checked by plain ``pytest``.

Registered as the ``pytest11`` entry point ``fkcheck``, so installing fkcheck
enables it in that environment's pytest (``-p no:fkcheck`` disables it);
``pip install 'fkcheck[pytest]'`` installs pytest with it, and the reference
libraries its checks compare against. A pytest of another environment never
loads it and runs none of this code, so it cannot say so; a project's
``required_plugins = ["fkcheck"]`` (pytest's own option) makes such a pytest
stop before collecting. It does nothing unless the
``pyproject.toml`` of pytest's rootdir (or the nearest one above it) has a
``[tool.fkcheck]`` table with ``models`` (:mod:`fkcheck.model.project`)::

    [tool.fkcheck]
    models = ["robots/*.toml"]
    samples = 2000
    require = ["table"]

Then each model file that pytest walks past is collected as tests: one per
backend, ``robots/arm.toml::fkcheck[pinocchio-urdf]``, and one per kind of
evidence the project or the model's ``[check]`` requires,
``robots/arm.toml::fkcheck[require:table]``. A backend that disagrees or
cannot answer fails with the verdict, its largest errors in mm and degrees,
the worst configuration and the diagnosis's headline; a backend that does not
apply (library missing, frame out of its reach) is a *skip* with its reason,
never a pass; required evidence that is not verified fails its own test. A
model file that cannot be read is one failing test, ``fkcheck[load]``, with
the one-line error.

Two checks compare nothing, and fail every test of their model, as
``fkcheck check`` reports them: one in which no backend answered (each skipped
one fails with its reason instead of skipping: the CLI's ``error — nothing was
cross-checked``), and one whose frame pair spans no joint
(:mod:`fkcheck.model.coverage`: ``from = to = "tcp"``, or ``world``
and a frame on DH frame 0), whose pose is the same in every configuration.

Each model's check runs once per pytest process, when its first test runs,
with every backend (``[tool.fkcheck] against``, default: the standard set);
under pytest-xdist (``-n auto``) every worker computes what its own tests need,
so ``--dist loadfile`` keeps a model's tests, and its one check, on one worker.
Models are collected only where pytest looks: run ``pytest`` from the project's
root, or list the models' directory in ``testpaths``. When a run that was not
given paths (plain ``pytest``: ``testpaths``, or the current directory) leaves
some ``[tool.fkcheck]`` models out, the plugin says so with a
:class:`FkcheckCollectionWarning` in pytest's warnings summary, naming them and
the way in. It warns rather than collect them anyway: pytest collects what its
arguments and ``testpaths`` say, and a plugin that reached past them would
surprise a project that left the models out on purpose (a warning can be made an
error with ``filterwarnings``). A run given paths (``pytest tests/unit``) chose
what to collect, and is not warned.

One table error fails each backend that disagrees once, and its diagnosis is
written out once, in the first of those backends' tests (the others name it); a
required kind of evidence that fails shows each backend's status line only.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import pytest

if TYPE_CHECKING:
    from _pytest._code.code import ExceptionInfo, TerminalRepr

    from fkcheck.api import Outcome
    from fkcheck.engine.results import CheckResult
    from fkcheck.model.project import ProjectConfig
    from fkcheck.model.types import Model

__all__ = ["FkcheckCollectionWarning", "FkcheckFailure", "ModelFile", "ModelItem"]

_PROJECT_KEY = pytest.StashKey["tuple[ProjectConfig, frozenset[Path]] | None"]()
_COLLECTED_KEY = pytest.StashKey["set[Path]"]()
_VOUCHED_KEY = pytest.StashKey["dict[Path, str]"]()


class FkcheckFailure(Exception):
    """A failed fkcheck test; its message is the whole report (no traceback is shown)."""


class FkcheckCollectionWarning(pytest.PytestWarning):
    """``[tool.fkcheck]`` models that pytest's collection did not reach: they were not checked."""


def pytest_configure(config: pytest.Config) -> None:
    """Read ``[tool.fkcheck]`` once; a table that is wrong stops the run with its one line.

    A project with models: BLAS runs on one thread
    (:func:`fkcheck.process.threads.one_blas_thread`), and in a pytest-xdist worker
    the other pools are sized to the worker's share of the cores
    (:func:`fkcheck.process.threads.share_xdist_cores`), so that every check it runs
    shares them with the other workers.
    """
    from fkcheck.errors import FkcheckError
    from fkcheck.model.project import load_project
    from fkcheck.process.threads import one_blas_thread, share_xdist_cores

    try:
        project = load_project(config.rootpath)
        paths = frozenset(p.resolve() for p in project.model_paths()) if project else frozenset()
    except FkcheckError as exc:
        raise pytest.UsageError(f"fkcheck: {exc}") from None
    config.stash[_PROJECT_KEY] = (project, paths) if project is not None and paths else None
    if config.stash[_PROJECT_KEY] is not None:
        one_blas_thread()
        share_xdist_cores()
    config.stash[_COLLECTED_KEY] = set()
    config.stash[_VOUCHED_KEY] = {}


def pytest_report_teststatus(report: pytest.TestReport, config: pytest.Config) -> None:
    """Remember a model verified on a vouch's word, from its ``require:table`` test's report.

    From the report, not the check: under pytest-xdist the check runs on a worker and
    only reports reach the process that writes the summary. Returns nothing: the
    test's status is pytest's own.
    """
    if report.when != "call":
        return
    for name, value in report.user_properties:
        if name == "fkcheck_on_word_of" and _VOUCHED_KEY in config.stash:
            config.stash[_VOUCHED_KEY][Path(report.nodeid.split("::", 1)[0])] = str(value)


def pytest_terminal_summary(terminalreporter: Any, config: pytest.Config) -> None:
    """Name the models whose table was verified partly on the word of a vouched frame.

    A vouch (``[frames.NAME] source = "…"``) is the model author's claim, not
    something the check compared: a passing test that rests on one says so here
    (and in the ``fkcheck_on_word_of`` property of its ``require:table`` test).
    """
    from fkcheck.io.text import terminal_text

    vouched = config.stash.get(_VOUCHED_KEY, {})
    if not vouched:
        return
    terminalreporter.section("fkcheck: verified on a vouch's word")
    for path, said in sorted(vouched.items()):  # node ids' paths: relative to the rootdir
        terminalreporter.write_line(terminal_text(f"{path}: {said}"))


def pytest_report_header(config: pytest.Config) -> str | None:
    """``fkcheck VERSION: N [tool.fkcheck] models`` in pytest's header, when there are models.

    Without ``[tool.fkcheck] models`` the plugin does nothing and adds no line
    (pytest's ``plugins:`` line names it with its version anyway).
    """
    from fkcheck._version import __version__

    found = config.stash.get(_PROJECT_KEY, None)
    if found is None:
        return None
    return f"fkcheck {__version__}: {len(found[1])} [tool.fkcheck] models"


def pytest_collect_file(file_path: Path, parent: pytest.Collector) -> ModelFile | None:
    """A model file named by ``[tool.fkcheck] models`` becomes a :class:`ModelFile`."""
    found = parent.config.stash.get(_PROJECT_KEY, None)
    if found is None or file_path.resolve() not in found[1]:
        return None
    parent.config.stash[_COLLECTED_KEY].add(file_path.resolve())
    return ModelFile.from_parent(parent, path=file_path)


def pytest_collection_finish(session: pytest.Session) -> None:
    """Warn when a run not given paths leaves ``[tool.fkcheck]`` models uncollected."""
    import warnings

    from fkcheck.io.text import terminal_text

    config = session.config
    found = config.stash.get(_PROJECT_KEY, None)
    if found is None or config.args_source == pytest.Config.ArgsSource.ARGS:
        return  # no project, or the run was told what to collect
    collected: set[Path] = config.stash[_COLLECTED_KEY]
    missed = sorted(p for p in found[1] if p not in collected)
    if not missed:
        return
    root = config.rootpath.resolve()
    shown = [
        terminal_text(str(p.relative_to(root) if p.is_relative_to(root) else p)) for p in missed
    ]
    folders = " ".join(sorted({str(Path(s).parent) for s in shown}))
    if config.args_source == pytest.Config.ArgsSource.TESTPATHS:
        where = f"testpaths = {list(config.getini('testpaths'))}"
        way = f"add {folders} to testpaths, or run pytest {folders}"
    else:
        where = f"the current directory, {terminal_text(str(config.invocation_params.dir))}"
        way = f"run pytest from the project's root, or pytest {folders}"
    pyproject = root / "pyproject.toml"
    # Located at [tool.fkcheck] models, the line that names them.
    warnings.warn_explicit(
        FkcheckCollectionWarning(
            f"fkcheck: {len(missed)} of {len(found[1])} [tool.fkcheck] models lie outside what "
            f"pytest collects ({where}) and were not checked: {', '.join(shown)}; {way}"
        ),
        FkcheckCollectionWarning,
        filename=str(pyproject),
        lineno=_models_line(pyproject),
    )


def _models_line(pyproject: Path) -> int:
    """The line of ``models =`` in ``[tool.fkcheck]`` (1 when it cannot be found)."""
    try:
        lines = pyproject.read_text(encoding="utf-8").splitlines()
    except (OSError, UnicodeDecodeError):
        return 1
    inside = False
    for number, line in enumerate(lines, 1):
        stripped = line.strip()
        if stripped.startswith("["):
            inside = stripped.replace(" ", "") == "[tool.fkcheck]"
        elif inside and stripped.split("=", 1)[0].strip() == "models":
            return number
    return 1


#: The target of an item that checks an IK solver (``[tool.fkcheck] ik_solvers``).
IK_PREFIX = "ik:"


class ModelFile(pytest.File):
    """One model file: its tests, and its check, run once when first needed."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self._outcome: Outcome | None = None
        self._error: str | None = None

    @property
    def project(self) -> ProjectConfig:
        """The ``[tool.fkcheck]`` this file was collected for."""
        found = self.config.stash[_PROJECT_KEY]
        assert found is not None  # collected only when there is a project
        return found[0]

    def _backend_names(self, model: Model) -> list[str]:
        from fkcheck.backends.registry import default_backends, parse_against

        against = self.project.against
        backends = parse_against(list(against)) if against else default_backends(model=model)
        return [b.name for b in backends]

    def collect(self) -> list[ModelItem]:
        """One item per backend and per required kind of evidence; ``load`` if unreadable."""
        from fkcheck.errors import FkcheckError
        from fkcheck.model.read import load_model
        from fkcheck.model.require import KINDS

        try:
            model = load_model(self.path)
            names = self._backend_names(model)
        except FkcheckError as exc:
            self._error = str(exc)
            return [ModelItem.from_parent(self, name="fkcheck[load]", target="load")]
        wanted = (*model.check.require, *self.project.require)
        kinds = [k for k in KINDS if k in wanted]
        solvers = [f"{IK_PREFIX}{name}" for name in self.project.ik_solvers]
        return [
            *(ModelItem.from_parent(self, name=f"fkcheck[{n}]", target=n) for n in names),
            *(ModelItem.from_parent(self, name=f"fkcheck[require:{k}]", target=k) for k in kinds),
            *(ModelItem.from_parent(self, name=f"fkcheck[{t}]", target=t) for t in solvers),
        ]

    def ik_outcome(self, solver: str) -> str | None:
        """``fkcheck ik`` of this model against ``solver``: ``None`` if it passes, else the report.

        The configurations and seed are the project's check options (``samples``,
        ``seed``), the frames the model's ``[check]`` pair (or the project's).

        Raises:
            FkcheckFailure: The model, the project or the solver cannot be used (one line).
        """
        from fkcheck.errors import FkcheckError
        from fkcheck.ik import check_ik, make_solver
        from fkcheck.ik.output import format_text
        from fkcheck.model.options import resolve_options
        from fkcheck.model.read import load_model

        try:
            options = resolve_options(project=self.project.options)
            model = load_model(self.path)
            pair = (
                options.frame_from or model.check.frame_from,
                options.frame_to or model.check.frame_to,
            )
            made = make_solver(solver, model, *pair, timeout_s=options.timeout_s)
            result = check_ik(model, made, frame_from=pair[0], frame_to=pair[1],
                              samples=options.samples, seed=options.seed)  # fmt: skip
        except FkcheckError as exc:
            raise FkcheckFailure(f"{self.path.name}: IK solver {solver}: {exc}") from None
        return None if result.passed else format_text(result)

    def outcome(self) -> Outcome:
        """The model's check, run on first call (then remembered in this process).

        Raises:
            FkcheckFailure: The model or the project cannot be used (the one line).
        """
        if self._error is None and self._outcome is None:
            self._outcome = self._run()
        if self._outcome is None:
            raise FkcheckFailure(str(self._error))  # it names the file
        return self._outcome

    def _run(self) -> Outcome | None:
        from fkcheck.api import check_request
        from fkcheck.backends.registry import BackendOptions, default_backends, parse_against
        from fkcheck.diagnose.jacobian import explain_sample
        from fkcheck.engine.request import CheckRequest
        from fkcheck.errors import FkcheckError
        from fkcheck.model.options import resolve_options
        from fkcheck.model.read import load_model

        p = self.project
        try:
            options = resolve_options(project=p.options)  # [tool.fkcheck] > defaults, as the CLI's
            limit = BackendOptions(
                timeout_s=options.timeout_s,
                frame_from=options.frame_from,
                frame_to=options.frame_to,
                **p.bag_settings(),  # a ROS 2 bag's topics and stamp tolerance
            )
            against = list(p.against) if p.against else None
            model = load_model(self.path)
            backends = parse_against(against, limit) if against else default_backends(limit, model)
            return check_request(
                CheckRequest(model, tuple(backends), options, p.lint_ignore, explain_sample)
            )
        except FkcheckError as exc:
            self._error = str(exc)
            return None


def _where(anchor: object) -> str:
    """An anchor (``FrameSpec.dh``) in words."""
    return {"world": "the world", "tcp": "the TCP"}.get(str(anchor), f"DH frame {anchor}")


def _pair_spans_no_joint(check: CheckResult) -> str | None:
    """Why the check's frame pair compares nothing, or ``None`` when it spans a joint.

    Decided from the kinematics (:mod:`fkcheck.model.coverage`): no joint moves
    the compared pose.
    """
    from fkcheck.io.text import terminal_text
    from fkcheck.model.types import resolve_frame

    model, pair = check.model, (check.frame_from, check.frame_to)
    if check.numbers is None or not check.numbers.spans_no_joint:
        return None
    a, b = (resolve_frame(model, name).dh for name in pair)
    shown = [terminal_text(repr(name)) for name in pair]
    why = (
        "a frame compared with itself"
        if pair[0] == pair[1]
        else f"{shown[0]} is on {_where(a)}, {shown[1]} on {_where(b)}; no joint moves one and "
        "not the other"
    )
    return (
        f"fkcheck {terminal_text(model.name)}: the frame pair {shown[0]} → {shown[1]} spans no "
        f"joint ({why}): its pose is the same in every configuration, so comparing it verifies "
        "none of the table; set [check] from and to to frames with at least one joint between them"
    )


class ModelItem(pytest.Item):
    """One backend's answer for a model, or one required kind of evidence."""

    def __init__(self, *, target: str, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.target = target

    @property
    def model_file(self) -> ModelFile:
        """The model file this test belongs to."""
        parent = self.parent
        assert isinstance(parent, ModelFile)
        return parent

    def runtest(self) -> None:
        """Pass, fail with the report, or skip with the backend's reason."""
        from fkcheck.model.require import KINDS
        from fkcheck.report.record import check_record
        from fkcheck.testing import backend_message, backend_ok, check_message

        if self.target.startswith(IK_PREFIX):  # an IK solver against the model's FK
            failed = self.model_file.ik_outcome(self.target[len(IK_PREFIX) :])
            if failed is not None:
                raise FkcheckFailure(failed)
            return
        outcome = self.model_file.outcome()  # raises FkcheckFailure for "load" too
        c = outcome.check
        degenerate = _pair_spans_no_joint(c)
        if degenerate is not None:
            raise FkcheckFailure(f"{degenerate}\n{check_message(outcome)}")
        if self.target in KINDS:
            kind = c.evidence.of(self.target)
            if kind.status != "verified":
                sentence = check_record(c).of(kind.kind).sentence
                raise FkcheckFailure(  # each backend's details are in its own test
                    f"required evidence {kind.kind!r} not verified ({kind.status}): {sentence}\n"
                    + check_message(outcome, details=False)
                )
            word = c.numbers.on_word() if c.numbers is not None and kind.kind == "table" else ""
            if word:  # verified, partly on a vouch's word: the run's summary names it too
                self.user_properties.append(("fkcheck_on_word_of", word))
            return
        result = next(b for b in c.backends if b.name == self.target)
        if result.status == "skipped" and not c.ran:  # a skip must not hide that nothing ran
            raise FkcheckFailure(
                f"{check_message(outcome, backends=())}\n{backend_message(outcome, result)}\n"
                "no backend of this model answered, so nothing was cross-checked: make one "
                "of them apply (install its library, give the model what it needs) or change "
                "[tool.fkcheck] against"
            )
        if result.status == "skipped":  # reported at the model file, not at this line
            raise pytest.skip.Exception(f"{result.name}: {result.message}", _use_item_location=True)
        if not backend_ok(result):  # xfail (as the model file records) passes; Jacobian too
            head = check_message(outcome, backends=())
            raise FkcheckFailure(f"{head}\n{backend_message(outcome, result, once=True)}")

    def repr_failure(
        self,
        excinfo: ExceptionInfo[BaseException],
        style: Any = None,
    ) -> str | TerminalRepr:
        """The report's text for fkcheck's own failures; pytest's usual one otherwise.

        The report is the whole text; pytest's short summary line (``-rA``, and
        untruncated in CI) shows its first line only, so that the diagnosis is
        not printed again there. Built as pytest's own exception report, so that
        it crosses pytest-xdist's workers as it is.
        """
        if isinstance(excinfo.value, FkcheckFailure):
            from _pytest._code.code import (
                ExceptionChainRepr,
                ReprEntryNative,
                ReprFileLocation,
                ReprTraceback,
            )

            text = str(excinfo.value)
            headline = text.split("\n", 1)[0]
            report = ReprTraceback([ReprEntryNative([text + "\n"])], None, "native")
            where = ReprFileLocation(str(self.path), 1, headline)
            return ExceptionChainRepr([(report, where, None)])
        return super().repr_failure(excinfo, style=style)

    def reportinfo(self) -> tuple[Path, int, str]:
        """Where the test is: the model file (line 0); its failure's heading names the node.

        (A heading that is a suffix of the node id would have pytest's verbose
        line turn ``good.toml`` into ``good::toml``.)
        """
        return self.path, 0, f"fkcheck: {self.nodeid}"
