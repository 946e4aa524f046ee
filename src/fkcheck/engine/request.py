"""What a check is asked: one :class:`CheckRequest`, built once where a check starts.

``fkcheck check`` (its flags over ``[tool.fkcheck]``), :func:`fkcheck.check` (its
arguments) and the pytest plugin (``[tool.fkcheck]``) each build one request;
it then flows through the check's three stages, unchanged:

* *prepare* (:mod:`fkcheck.engine.prepare`): the descriptions read and screened
  once, the frame pair and tolerances resolved, the configurations sampled, the
  calibration's effect, what the pair can verify, the plan;
* *run* (:mod:`fkcheck.engine.runner`): each backend in its thread (an isolated
  one's poses in processes of its own), compared with the core;
* *judge* (:mod:`fkcheck.engine.judge`): known differences, provenance, lint and
  the verdict, into a :class:`~fkcheck.engine.results.CheckResult` that keeps
  the request's :class:`~fkcheck.model.options.CheckOptions`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from fkcheck.backends.base import Backend
from fkcheck.engine.jacobian import Explain
from fkcheck.model.options import CheckOptions
from fkcheck.model.types import Model

__all__ = ["CheckRequest"]


@dataclass(frozen=True, eq=False)
class CheckRequest:
    """One check asked for: the model, the backends and the options; never changed after.

    Attributes:
        model: The model, as loaded (its ``[urdf]`` description is read by *prepare*).
        backends: Backends to compare, in the order results are shown.
        options: The options, resolved once at the entry point (with where each
            came from); what they leave ``None`` is the model's ``[check]``'s.
        lint_ignore: Lint rules left out of the check's ``lint`` (a project's
            ``[tool.fkcheck] lint_ignore``), on top of the model's own ``[lint]``.
        explain_jacobian: Names each Jacobian disagreement (``fkcheck.check``
            passes the diagnosis's); without it a failure carries its numbers only.
    """

    model: Model
    backends: tuple[Backend, ...]
    options: CheckOptions = field(default_factory=CheckOptions)
    lint_ignore: tuple[str, ...] = ()
    explain_jacobian: Explain | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "backends", tuple(self.backends))
        object.__setattr__(self, "lint_ignore", tuple(self.lint_ignore))
