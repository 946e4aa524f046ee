"""A check's plan, made before anything runs: how many configurations each backend compares.

A million samples do not fit every backend's time limit: yourdfpy computes
about 1,600 UR5 poses a second on a busy 2-core machine, so the full set would
take ten minutes against the 120 s default. Rather than let such a backend time
out (an error, and one that comes or goes with the machine's load), the check is
planned from numbers known before it starts:

* **Declared costs.** A built-in backend declares ``pose_cost_us``: microseconds
  per configuration for a 6-joint arm, the engine's comparison included,
  measured on the project's 2-core machine while it was busy; with a Jacobian
  of its own, ``jacobian_cost_us`` likewise. A backend that differentiates its
  poses costs ``2n + 1`` poses per configuration. Costs scale with the joint
  count (``n / 6``). A backend that declares no cost (a plugin, a ``cmd:``
  program, a third-party backend) is planned the full set: the time limit is
  then its only bound.
* **Budget.** A backend is planned to need at most :data:`BUDGET_SHARE` of its
  time limit, so the limit stays a safety net with room for a slower or busier
  machine. Backends that run in the engine's process share one interpreter lock,
  so they share one budget: each is given up to a common number of seconds
  (water-filling), which leaves the cheap ones their full set. An isolated
  backend (its own processes) has its budget to itself; the plan counts it as one
  process, though its configurations are split over the cores when there are
  enough of them (:data:`fkcheck.engine.runner.SPLIT_MIN_CONFIGS`): a machine's
  core count changes how soon it ends, never what it compares.
* **The subset.** A backend over its budget compares every structured
  configuration (named poses, zero, mid-range, limit corners and edges: see
  :mod:`fkcheck.model.sampling`; measured poses count as structured) and the
  first ``k`` random samples — a prefix of the seeded sequence, so a seeded
  share, and for Sobol a prefix keeps the sequence's balance. Structured
  configurations come first, so the subset is a prefix of the check's
  configurations: ``q[:compared]``. ``k`` is rounded down to a thousand (from
  10,000 on), for counts a person can read.
* **Deterministic.** The plan depends on the backends, the number and kinds of
  configurations, the joint count, the time limit and whether Jacobians are
  compared — never on a clock: the same inputs give the same subset and the
  same JSON, whatever the machine's load.
* **Stated.** Each subset is said before the check runs (:meth:`Plan.notes`,
  with the way out: ``--full``, or a longer ``--timeout``), and its count is
  carried by the backend's result (``BackendResult.subset``) into every output:
  the terminal table, the evidence sentences, the headline, JSON, JUnit,
  Markdown and HTML.
* ``full``: every backend compares everything; the time limit still applies.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from fkcheck.backends.base import Backend

__all__ = [
    "BUDGET_SHARE",
    "REFERENCE_JOINTS",
    "BackendPlan",
    "Plan",
    "configuration_cost_us",
    "count_text",
    "plan_check",
]

#: A backend is planned to need at most this share of its time limit.
BUDGET_SHARE = 0.5
#: Declared costs are for an arm of this many joints; they scale linearly with the count.
REFERENCE_JOINTS = 6
#: Random samples of a subset are rounded down to a multiple of this, from ten of them on.
_ROUND = 1000
#: A backend whose full set needs at most this much more than its share gets the full set.
_SLACK = 1.05


def count_text(n: int) -> str:
    """``1 000 081``: a count with its thousands apart, as plans and reports print it."""
    return f"{n:,}".replace(",", " ")


def configuration_cost_us(backend: Backend, dof: int, *, jacobian: bool) -> float | None:
    """What one configuration costs ``backend``, µs, by its declared cost; ``None``: undeclared.

    Args:
        backend: The backend.
        dof: The model's joint count.
        jacobian: Whether its Jacobian is compared too.
    """
    pose = getattr(backend, "pose_cost_us", None)
    if not isinstance(pose, int | float) or pose <= 0:
        return None
    scale = dof / REFERENCE_JOINTS
    if not jacobian:
        return float(pose) * scale
    own = getattr(backend, "jacobian_cost_us", None)
    if backend.jacobian_method is not None:
        return float(own) * scale if isinstance(own, int | float) and own > 0 else None
    return float(pose) * scale * (2 * dof + 1)  # central differences: 2n poses around each


@dataclass(frozen=True)
class BackendPlan:
    """What one backend is planned to compare.

    Attributes:
        name: The backend's name.
        compared: Configurations it compares: the first ``compared`` of the check's.
        total: Configurations of the check.
        structured: Of these, the structured ones (all compared).
        full_s: Its declared time for the full set, seconds (``None``: no cost declared).
        shared_s: For a backend in the engine's process, the declared time of all
            of those backends' full sets together, seconds (they share one
            interpreter and one budget); ``None`` for an isolated one.
        timeout_s: Its time limit, seconds.
    """

    name: str
    compared: int
    total: int
    structured: int
    full_s: float | None
    shared_s: float | None
    timeout_s: float

    @property
    def subset(self) -> bool:
        """Whether it compares fewer configurations than the check has."""
        return self.compared < self.total

    def note(self) -> str:
        """One sentence: the subset, why, and the way out (``""`` for the full set)."""
        if not self.subset or self.full_s is None:
            return ""
        random_total = self.total - self.structured
        random_compared = self.compared - self.structured
        needed = self.full_s if self.shared_s is None else self.shared_s
        wanted = max(self.timeout_s, math.ceil(needed / BUDGET_SHARE / 60.0) * 60.0)
        why = (
            f"the full set would take it about {_duration(self.full_s)} by its declared cost"
            if self.shared_s is None
            else f"the full sets of the backends in fkcheck's process, which share one "
            f"interpreter, would take about {_duration(self.shared_s)} together by their "
            "declared costs"
        )
        return (
            f"{self.name} compares {count_text(self.compared)} of {count_text(self.total)} "
            f"configurations (all {count_text(self.structured)} structured ones and the first "
            f"{count_text(random_compared)} of {count_text(random_total)} random samples): "
            f"{why}, more than half of the {self.timeout_s:g} s limit; --full compares every "
            f"configuration (with --timeout {wanted:g})"
        )


def _duration(seconds: float) -> str:
    if seconds < 120:
        return f"{seconds:.0f} s"
    return f"{seconds / 60:.0f} min"


@dataclass(frozen=True)
class Plan:
    """The plan of a check: one :class:`BackendPlan` per backend, in the order given.

    Attributes:
        backends: One per backend.
        total: Configurations of the check.
        structured: Of these, the structured ones.
        full: Whether every backend was asked to compare everything.
    """

    backends: tuple[BackendPlan, ...]
    total: int
    structured: int
    full: bool = False

    def notes(self) -> tuple[str, ...]:
        """A sentence per backend given a subset, in the order given."""
        return tuple(b.note() for b in self.backends if b.subset)


def _caps(costs: Sequence[float], budget_s: float) -> list[float]:
    """Seconds each member of one budget may take (water-filling: cheapest full first)."""
    caps = [0.0] * len(costs)
    left, members = budget_s, len(costs)
    for i in sorted(range(len(costs)), key=lambda k: costs[k]):
        share = left / members
        caps[i] = min(costs[i], share)
        left -= caps[i]
        members -= 1
    return caps


def _compared(cap_s: float, cost_us: float, total: int, structured: int) -> int:
    """Configurations that fit ``cap_s`` seconds: the structured ones at least."""
    fits = math.floor(cap_s * 1e6 / cost_us) - structured
    random_total = total - structured
    extra = max(0, min(random_total, fits))
    if extra < random_total and extra >= 10 * _ROUND:
        extra -= extra % _ROUND
    return structured + extra


def _compared_of(
    cap: float | None, cost: float | None, whole: float | None, total: int, structured: int
) -> int:
    """Configurations one backend compares: all of them unless its cap is too short."""
    fits = cap is None or cost is None or whole is None or cap * _SLACK >= whole
    return total if fits else _compared(cap or 0.0, cost or 1.0, total, structured)


def _time_caps(
    backends: Sequence[Backend],
    full_s: Sequence[float | None],
    pool: Sequence[int],
    pool_full: Sequence[float],
    budget: float,
) -> list[float | None]:
    """Seconds each backend may take: the in-process ``pool`` shares ``budget``.

    An isolated backend has the whole ``budget`` to itself; a backend whose cost
    is unknown has no cap (``None``).
    """
    caps: list[float | None] = [None] * len(backends)
    for i, pool_cap in zip(pool, _caps(pool_full, budget), strict=True):
        caps[i] = pool_cap
    for i, b in enumerate(backends):
        if b.isolated and full_s[i] is not None:
            caps[i] = min(full_s[i] or 0.0, budget)
    return caps


def plan_check(
    backends: Sequence[Backend],
    origin: Sequence[str],
    *,
    dof: int,
    timeout_s: float,
    jacobian: bool = False,
    full: bool = False,
) -> Plan:
    """How many configurations each backend compares (see the module docstring).

    Args:
        backends: The backends, in the order asked.
        origin: Where each configuration came from (:class:`~fkcheck.model.sampling.Samples`):
            ``random`` ones may be left out, the others never are.
        dof: The model's joint count.
        timeout_s: Each backend's time limit, seconds.
        jacobian: Whether Jacobians are compared too.
        full: Every backend compares every configuration.

    Returns:
        The plan; the same for the same arguments.
    """
    total = len(origin)
    random_total = sum(1 for o in origin if o == "random")
    structured = total - random_total
    if origin[structured:].count("random") != random_total:  # pragma: no cover - sampling's order
        raise ValueError("random configurations must come after the structured ones")
    costs = [configuration_cost_us(b, dof, jacobian=jacobian) for b in backends]
    full_s = [None if c is None else c * total / 1e6 for c in costs]
    budget = BUDGET_SHARE * timeout_s
    pool = [i for i, b in enumerate(backends) if not b.isolated and full_s[i] is not None]
    pool_full = [full_s[i] or 0.0 for i in pool]
    shared = sum(pool_full)
    caps: list[float | None] = (
        [None] * len(backends) if full else _time_caps(backends, full_s, pool, pool_full, budget)
    )
    plans = []
    for i, backend in enumerate(backends):
        plans.append(
            BackendPlan(
                backend.name,
                _compared_of(caps[i], costs[i], full_s[i], total, structured),
                total,
                structured,
                full_s[i],
                shared if i in pool else None,
                timeout_s,
            )
        )
    return Plan(tuple(plans), total, structured, full)
