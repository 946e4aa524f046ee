"""A pytest plugin: in CI, a skipped test is a failure (``FKCHECK_REQUIRE_BACKENDS=1``).

On a developer's machine a test that needs Pinocchio, a C++ toolchain or
Chromium may skip, with its reason. In CI everything it needs is installed by
``.ci/run``, so a skip there means the suite silently tested less than it says:
with ``FKCHECK_REQUIRE_BACKENDS=1`` (set by ``.ci/run``) every skip — a test's,
or a whole module's ``pytest.importorskip`` — is reported as a failure with its
reason. xfail is not a skip and is left alone.
"""

from __future__ import annotations

import os
from collections.abc import Generator
from typing import Any

import pytest

ENV = "FKCHECK_REQUIRE_BACKENDS"


def _required() -> bool:
    return os.environ.get(ENV) == "1"


def _reason(report: Any) -> str:
    longrepr = report.longrepr
    if isinstance(longrepr, tuple) and len(longrepr) == 3:
        return str(longrepr[2])
    return str(longrepr)


def _fail(report: Any) -> None:
    report.outcome = "failed"
    report.longrepr = f"skipped, but {ENV}=1 forbids skips: {_reason(report)}"


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item: pytest.Item, call: Any) -> Generator[None, Any, None]:
    outcome = yield
    report = outcome.get_result()
    if _required() and report.skipped and not hasattr(report, "wasxfail"):
        _fail(report)


@pytest.hookimpl(hookwrapper=True)
def pytest_make_collect_report(collector: pytest.Collector) -> Generator[None, Any, None]:
    outcome = yield
    report = outcome.get_result()
    if _required() and report.skipped:
        _fail(report)
