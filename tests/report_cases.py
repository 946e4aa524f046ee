"""Deterministic check results for the report tests (no reference library involved).

The gold file must not depend on library versions or round-off, so the result is
built by hand: a small 3R model, six fixed configurations, and per-configuration
errors chosen exactly. Only the matrices the engine would have kept for a
failing backend (:class:`~fkcheck.engine.evidence.FailureDetail`) come from the
FK core and the fake backends (shown to nine decimals, far above any round-off
difference), built here the way the engine builds them.
"""

from __future__ import annotations

import copy
import math
import re
from html.parser import HTMLParser
from typing import Any

import numpy as np

from fkcheck.backends.base import BackendDefaults
from fkcheck.core.geometry import translation
from fkcheck.diagnose import Diagnosis, Explanation
from fkcheck.diagnose.findings import Change
from fkcheck.diagnose.problem import Residual
from fkcheck.engine.evidence import FailureDetail, WorstCases, arm_pose, dh_parting
from fkcheck.engine.results import BackendResult, CheckResult
from fkcheck.model.coverage import coverage
from fkcheck.model.frames import frame_poses_from_dh, reference_poses, relative_pose
from fkcheck.model.options import CheckOptions
from fkcheck.model.read import model_from_dict
from fkcheck.model.types import Model

SPEC: dict[str, Any] = {
    "name": "golden-3r",
    "description": "A 3R arm with a tool, for the report's gold file",
    "source": "tests/report_cases.py",
    "convention": "standard",
    "angle_unit": "deg",
    "joint": [
        {"name": "waist", "a": 0.0, "alpha": 90, "d": 0.3, "limits": [-170, 170]},
        {"name": "shoulder", "a": 0.4, "alpha": 0, "d": 0.0, "limits": [-120, 120]},
        {"name": "elbow", "a": 0.3, "alpha": 0, "d": 0.0, "theta": 90, "flip": True},
    ],
    "tool": {"xyz": [0.0, 0.0, 0.1]},
    "frames": {"base": {"dh": 0}, "flange": {"dh": 3}, "tool": {"dh": "tcp"}},
    "check": {"from": "base", "to": "tool"},
}

Q = np.deg2rad(
    [
        [5.0, -10.0, 25.0],
        [10.0, 20.0, 30.0],
        [-45.0, 60.0, -15.0],
        [90.0, -30.0, 120.0],
        [135.0, 45.0, -90.0],
        [-160.0, 100.0, 75.0],
    ]
)
ORIGIN = ("pose:ready", "mid", "corner", "random", "random", "random")


def golden_model(**changes: Any) -> Model:
    """The gold model, with top-level fields replaced (e.g. ``name=...``)."""
    spec = copy.deepcopy(SPEC)
    spec.update(changes)
    return model_from_dict(spec)


def twisted_model(model: Model) -> Model:
    """The same table with joint 2's α flipped (0 → 180°): its chain parts at DH frame 2."""
    spec = copy.deepcopy(SPEC)
    spec["name"] = model.name
    spec["joint"][1]["alpha"] = 180
    return model_from_dict(spec)


class Agrees(BackendDefaults):
    """A backend that computes exactly what the in-house core does."""

    name = "agrees"
    method = "model.fk"
    evidence = "implementation"
    reads = "dh"

    def unavailable_reason(self, model: Model) -> str | None:
        return None

    def frame_poses(self, model: Model, q: np.ndarray, frames: Any) -> np.ndarray:
        return frame_poses_from_dh(model, model.fk(q, all_frames=True), model.fk(q), frames)


class Shifted(Agrees):
    """A constant 0.3 mm offset along the tool's z axis (a rounded d, say)."""

    name = "shifted"
    method = "pose @ Tz(0.3 mm)"
    evidence = "implementation"

    def frame_poses(self, model: Model, q: np.ndarray, frames: Any) -> np.ndarray:
        poses = super().frame_poses(model, q, frames)
        poses[1] = poses[1] @ translation(0.0, 0.0, 3e-4)
        return poses


class TwistedDH(Agrees):
    """Built from the table with one α flipped; shares its DH frames."""

    name = "twisted-dh"
    method = "flipped alpha_2"
    evidence = "implementation"

    def frame_poses(self, model: Model, q: np.ndarray, frames: Any) -> np.ndarray:
        twisted = twisted_model(model)
        return frame_poses_from_dh(model, twisted.fk(q, all_frames=True), twisted.fk(q), frames)

    def dh_frames(self, model: Model, q: np.ndarray) -> np.ndarray:
        return np.asarray(twisted_model(model).fk(q, all_frames=True))


class Unused(Agrees):
    """Stands for a backend that errored or was skipped (never called again)."""

    def __init__(self, name: str) -> None:
        self.name = name


def backends() -> list[Any]:
    """Backend objects in the order of :func:`golden_check`'s results."""
    return [Agrees(), Shifted(), TwistedDH(), Unused("raises"), Unused("absent")]


PAIR = ("base", "tool")
TOL = (1e-6, 1e-6)


def failure_detail(
    model: Model, backend: Any, pos: np.ndarray, rot: np.ndarray, worst: int
) -> FailureDetail:
    """What the engine keeps for a failing backend, built from the hand-made errors."""
    score = np.maximum(pos / TOL[0], rot / TOL[1])
    ranked = [int(i) for i in np.argsort(-score, kind="stable") if int(i) != worst]
    indices = [worst, *ranked][:3]
    ref = reference_poses(model, Q[indices], PAIR)
    theirs = backend.frame_poses(model, Q[indices], PAIR)
    cases = WorstCases(
        tuple(indices), relative_pose(ref[0], ref[1]), relative_pose(theirs[0], theirs[1])
    )
    arm = arm_pose(model, Q[worst], PAIR)
    parting = None
    if hasattr(backend, "dh_frames"):
        parting = dh_parting(
            worst, arm.world_T_dh, backend.dh_frames(model, Q[worst : worst + 1])[0], TOL
        )
    return FailureDetail(cases, arm, dh_parting=parting)


def golden_check(model: Model | None = None, message_extra: str = "") -> CheckResult:
    """The hand-built result: one pass, two failures (one shares DH frames), an error, a skip."""
    model = model or golden_model()
    n = Q.shape[0]
    twisted_pos = np.array([0.0, 0.0125, 0.0625, 0.25, 0.125, 0.5])
    twisted_rot = np.array([0.0, 0.5, 1.0, 2.0, 1.5, 3.0])
    shifted_pos, shifted_rot = np.full(n, 3e-4), np.zeros(n)
    results = (
        BackendResult("agrees", "pass", "", "model.fk", 0.0125, np.zeros(n), np.zeros(n), 0),
        BackendResult(
            "shifted",
            "fail",
            "6 of 6 configurations differ: max position error 0.300 mm (3.00e-04 m), "
            "max rotation error 0.00° (0.00e+00 rad)" + message_extra,
            "pose @ Tz(0.3 mm)",
            0.25,
            shifted_pos,
            shifted_rot,
            0,
            failure_detail(model, Shifted(), shifted_pos, shifted_rot, 0),
        ),
        BackendResult(
            "twisted-dh",
            "fail",
            "5 of 6 configurations differ: max position error 500 mm (5.00e-01 m), "
            "max rotation error 172° (3.00e+00 rad)",
            "flipped alpha_2",
            0.5,
            twisted_pos,
            twisted_rot,
            5,
            failure_detail(model, TwistedDH(), twisted_pos, twisted_rot, 5),
        ),
        BackendResult("raises", "error", "ZeroDivisionError: boom (fake.py:1)", "raise", 0.001),
        BackendResult("absent", "skipped", "library not installed here", "import absent"),
    )
    return CheckResult(
        model=model,
        options=CheckOptions(samples=3, seed=7, sampler="sobol"),
        frame_from="base",
        frame_to="tool",
        tol_pos_m=1e-6,
        tol_rot_rad=1e-6,
        q=Q,
        origin=ORIGIN,
        backends=results,
        verdict="fail",
        created="2026-01-02T03:04:05+00:00",
        duration_s=1.25,
        command="fkcheck check golden-3r --samples 3 --seed 7",
        numbers=coverage(model, "base", "tool", 1e-6, 1e-6),
    )


#: What ``fkcheck diagnose`` tries on the 3R model (as it says for these backends).
TRIED = (
    "constant base/tip frame offsets (least squares on SE(3))",
    "standard ⇄ modified convention (1)",
    "one α, a or d with the wrong sign (4)",
    "a missing ±90° or 180° θ offset (9)",
    "one joint reversed (3)",
    "a published table (1)",
    "one parameter fitted alone (12)",
)


def golden_diagnoses(check: CheckResult) -> list[Any]:
    """Diagnoses of the two failing backends, built by hand like :func:`golden_check`.

    They say what ``fkcheck diagnose`` says for these backends (shifted: a black
    box whose 0.3 mm no change of the table removes; twisted-dh: α2 off by 180°),
    with round numbers, so the gold file does not depend on SciPy's least squares.
    """
    from fkcheck.diagnose.failures import BackendDiagnosis

    def diagnosis(backend: str, before: Residual, explanations: tuple[Explanation, ...]):
        return Diagnosis(
            model=check.model,
            backend=backend,
            frame_from=check.frame_from,
            frame_to=check.frame_to,
            configurations=202,
            before=before,
            tol_pos_m=check.tol_pos_m,
            tol_rot_rad=check.tol_rot_rad,
            explanations=explanations,
            tried=TRIED,
            duration_s=0.5,
        )

    alpha2 = Change("joint[1].alpha", "α2 (shoulder)", 0.0, math.pi, angle=True)
    twisted = Explanation(
        kind="parameter",
        title="one number differs: α2 (shoulder)",
        residual=Residual(0.0, 0.0),
        explains=True,
        changes=(alpha2,),
    )
    command = "fkcheck diagnose golden-3r --against {} --from base --to tool --seed 7"
    return [
        BackendDiagnosis(
            "shifted", diagnosis("shifted", Residual(3e-4, 0.0), ()), "", (),
            command.format("shifted"),
        ),
        BackendDiagnosis(
            "twisted-dh", diagnosis("twisted-dh", Residual(0.6325, math.pi), (twisted,)), "", (),
            command.format("twisted-dh"),
        ),
    ]  # fmt: skip


_VOLATILE = re.compile(r'(data-volatile="[a-z]+">)[^<]*(<)')
_DATA_URI = re.compile(r"data:image/png;base64,[A-Za-z0-9+/=]+")


def scrub(page: str) -> str:
    """Replace what changes between runs and machines (dates, versions, paths, images)."""
    page = _VOLATILE.sub(r"\1SCRUBBED\2", page)
    return _DATA_URI.sub("data:image/png;base64,SCRUBBED", page)


class PageNumbers(HTMLParser):
    """Collects the machine-readable parts of a report: verdict, statuses, numbers."""

    def __init__(self) -> None:
        super().__init__()
        self.verdict: str | None = None
        self.status: dict[str, str] = {}
        self.values: dict[tuple[str, str], str] = {}
        self.tags: list[tuple[str, list[tuple[str, str | None]]]] = []
        self._row: str | None = None

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        self.tags.append((tag, attrs))
        a = dict(attrs)
        if a.get("id") == "verdict-badge":
            self.verdict = a.get("data-verdict")
        if tag == "tr" and "data-backend" in a:
            self._row = a["data-backend"]
        if self._row and "data-status" in a and self._row not in self.status:
            self.status[self._row] = str(a["data-status"])
        if self._row and "data-key" in a:
            self.values[(self._row, str(a["data-key"]))] = str(a.get("data-value"))

    def handle_endtag(self, tag: str) -> None:
        if tag == "tbody":
            self._row = None


def page_numbers(page: str) -> PageNumbers:
    """Parse a rendered report."""
    parser = PageNumbers()
    parser.feed(page)
    return parser
