"""``ur-analytic-ik``: the UR family's analytic IK (Victor-Louis De Gusseme, MIT), as a solver.

The library (PyPI ``ur-analytic-ik``, C++ with nanobind bindings) holds UR's
nominal DH numbers for each robot (``ur3`` … ``ur30``) and solves the pose of
DH frame 6 (``tool0``) in DH frame 0 (the controller's ``base``). This wrapper

* takes the library's robot of the model's name (``ur5e`` → ``ur_analytic_ik.ur5e``),
  or the one named after a colon (``--solver ur-analytic-ik:ur5e`` for a model
  file of another name);
* refuses, in one line, a model that is not a UR-shaped table (six revolute
  joints, standard DH, ``α = 90°, 0, 0, 90°, −90°, 0``, ``a1 = a4 = a5 = a6 = 0``,
  ``d2 = d3 = 0``) and a check frame pair not fixed to DH frames 0 and 6
  (:mod:`fkcheck.ik.frames`);
* turns the check's ``from_T_to`` into ``base_T_tool0`` and the library's DH
  angles into the model's joint values (``q = sign · (θ − θ_offset)``).

It does not compare the library's numbers with the model's: that is the IK
check's job (the library's own FK is checked against the table, and every
solution against the table's FK), so a calibrated table whose d4 differs from
the library's nominal one fails the check, it is not refused.

The library writes a line to standard output (C++ ``std::cout``) for each
solution it filters out; the wrapper sends file descriptor 1 to a file of its
own during each call and keeps those lines (:attr:`UrAnalyticIk.messages`), so
they never reach fkcheck's output.
"""

from __future__ import annotations

import contextlib
import math
import os
import sys
import tempfile
import weakref
from collections.abc import Callable, Iterator
from typing import Any

import numpy as np

from fkcheck.core.geometry import invert
from fkcheck.core.typing import Float
from fkcheck.ik.frames import dh_anchor
from fkcheck.ik.solver import SolverRefused
from fkcheck.model.types import Model

__all__ = ["LIBRARY", "UR_SHAPE", "UrAnalyticIk", "library_robots", "ur_shape_problem"]

#: The distribution and its module.
LIBRARY = "ur-analytic-ik"
_MODULE = "ur_analytic_ik"
#: α per joint of a UR-shaped standard DH table, degrees.
UR_SHAPE = (90.0, 0.0, 0.0, 90.0, -90.0, 0.0)
#: How close a table's α and its zero a, d must be to UR's shape (radians / metres):
#: the model file's own round-off (degrees written with 6 decimals are 1e-8 rad off).
_SHAPE_TOL = 1e-6
#: What is kept of the library's printing per call, bytes (it prints a line per filtered solution).
_MAX_MESSAGE_BYTES = 64 * 1024


def library_robots() -> list[str]:
    """The robots the installed library knows (``ur3``, ``ur5e``…).

    Raises:
        SolverRefused: The library is not installed (how to install it).
    """
    module = _import()
    return sorted(
        name
        for name in dir(module)
        if name.startswith("ur") and hasattr(getattr(module, name), "inverse_kinematics")
    )


def _import() -> Any:
    try:
        import ur_analytic_ik
    except ImportError:
        raise SolverRefused(
            f"IK solver {LIBRARY}: the library is not installed: pip install 'fkcheck[ik]' "
            f"(or pip install {LIBRARY})"
        ) from None
    return ur_analytic_ik


def ur_shape_problem(model: Model) -> str | None:
    """Why ``model`` is not a UR-shaped table, or ``None`` when it is."""
    if model.dof != 6:
        return f"it has {model.dof} joints, not 6"
    if model.convention != "standard":
        return f"its table is {model.convention} DH, not standard"
    for i, joint in enumerate(model.joints, start=1):
        if joint.type != "revolute":
            return f"joint {i} ({joint.name}) is {joint.type}"
        if abs(joint.alpha - math.radians(UR_SHAPE[i - 1])) > _SHAPE_TOL:
            return (
                f"α{i} ({joint.name}) is {math.degrees(joint.alpha):g}°, not {UR_SHAPE[i - 1]:g}°"
            )
    for i in (1, 4, 5, 6):
        if abs(model.joints[i - 1].a) > _SHAPE_TOL:
            return f"a{i} is {model.joints[i - 1].a:g} m, not 0"
    for i in (2, 3):
        if abs(model.joints[i - 1].d) > _SHAPE_TOL:
            return f"d{i} is {model.joints[i - 1].d:g} m, not 0"
    return None


class UrAnalyticIk:
    """IK of one UR robot from ``ur-analytic-ik``, in the model's frames and joint values.

    Attributes:
        name: ``"ur-analytic-ik"`` (or ``"ur-analytic-ik:<robot>"``).
        method: The library, its version and the robot.
        robot: The library's robot (``"ur5e"``).
        messages: The lines the library printed during the last :meth:`solve` (or
            :meth:`batch`).
    """

    def __init__(
        self, model: Model, frame_from: str, frame_to: str, robot: str | None = None
    ) -> None:
        """Pick the library's robot and check the model and frames fit it.

        Raises:
            SolverRefused: The library is missing, has no such robot, the model is
                not UR-shaped, or the frame pair is not fixed to DH frames 0 and 6.
        """
        module = _import()
        known = library_robots()
        chosen = (robot or model.name).strip().lower()
        self.name = LIBRARY if robot is None else f"{LIBRARY}:{robot}"
        if chosen not in known:
            how = (
                f"model {model.name!r} is not one of its robots"
                if robot is None
                else f"it has no robot {robot!r}"
            )
            raise SolverRefused(
                f"IK solver {self.name}: {how}; its robots are: {', '.join(known)} "
                f"(name one: --solver {LIBRARY}:ROBOT)"
            )
        problem = ur_shape_problem(model)
        if problem is not None:
            raise SolverRefused(
                f"IK solver {self.name}: model {model.name} is not a UR-shaped table: {problem}"
            )
        anchors = dh_anchor(model, frame_from), dh_anchor(model, frame_to)
        if anchors[0][0] != 0 or anchors[1][0] != model.dof:
            raise SolverRefused(
                f"IK solver {self.name} solves DH frame 0 (base) to DH frame 6 (tool0); "
                f"frame {frame_from!r} sits on DH frame {anchors[0][0]} and {frame_to!r} on "
                f"DH frame {anchors[1][0]}: choose --from/--to fixed to those"
            )
        from importlib import metadata

        try:
            version = metadata.version(LIBRARY)
        except metadata.PackageNotFoundError:  # imported from a source tree
            version = "unknown version"
        self.robot = chosen
        self.method = f"{LIBRARY} {version}, robot {chosen} (its own nominal DH numbers)"
        self._robot = getattr(module, chosen)
        self._dh0_T_from = anchors[0][1]
        self._from_T_dh0 = invert(anchors[0][1])
        self._dhn_T_to = anchors[1][1]
        self._to_T_dhn = invert(anchors[1][1])
        self._offset = np.array([j.theta for j in model.joints])
        self._sign = np.array([-1.0 if j.flip else 1.0 for j in model.joints])
        self.messages: tuple[str, ...] = ()
        self._sink = _StdoutSink()
        self._batched = False

    def solve(self, from_T_to: Float) -> Float:
        """Every solution the library returns, as the model's joint values ``(k, 6)``."""
        dh0_T_dh6 = self._dh0_T_from @ np.asarray(from_T_to, dtype=np.float64) @ self._to_T_dhn
        if self._batched:  # inside batch(): fd 1 is already the sink
            answer = self._robot.inverse_kinematics(np.ascontiguousarray(dh0_T_dh6))
        else:
            with self._sink.around() as printed:
                answer = self._robot.inverse_kinematics(np.ascontiguousarray(dh0_T_dh6))
            self.messages = tuple(printed)
        theta = np.asarray(answer, dtype=np.float64).reshape(-1, 6)
        q: Float = self._sign * (theta - self._offset)
        return q

    @contextlib.contextmanager
    def batch(self) -> Iterator[None]:
        """Many :meth:`solve` calls with fd 1 sent to the sink once, not once per call.

        What the library printed over the whole batch is on :attr:`messages` after it.
        """
        self.messages = ()
        with self._sink.around() as printed:
            self._batched = True
            try:
                yield
            finally:
                self._batched = False
        self.messages = tuple(printed)

    def library_call(self, poses: Float) -> Callable[[], list[Any]]:
        """The library's own call on ``poses`` (the check's frames turned into its own), unwrapped.

        For ``fkcheck bench --ik``: what the wrapper adds is the difference. The
        library's printing goes to the sink once for the whole run.
        """
        dh_poses = [
            np.ascontiguousarray(self._dh0_T_from @ T @ self._to_T_dhn) for T in np.asarray(poses)
        ]
        solve = self._robot.inverse_kinematics

        def run() -> list[Any]:
            with self._sink.around():
                return [solve(T) for T in dh_poses]

        return run

    def fk(self, q: Float) -> Float:
        """The library's own FK of the model's joint values, as ``from_T_to`` ``(4, 4)``."""
        theta = self._offset + self._sign * np.asarray(q, dtype=np.float64)
        dh0_T_dh6 = np.asarray(self._robot.forward_kinematics(*(float(t) for t in theta)))
        from_T_to: Float = self._from_T_dh0 @ dh0_T_dh6 @ self._dhn_T_to
        return from_T_to


class _StdoutSink:
    """File descriptor 1 sent to a temporary file of its own around a call.

    One file for the solver's life (a new one per call would cost more than the
    solve); what the call printed is read back and the file emptied.
    """

    def __init__(self) -> None:
        self._file: Any = None

    @contextlib.contextmanager
    def around(self) -> Iterator[list[str]]:
        """Send fd 1 to the sink for the ``with`` body; the yielded list gets what it printed."""
        if self._file is None:
            self._file = tempfile.TemporaryFile()  # noqa: SIM115 (lives as long as the solver)
            weakref.finalize(self, self._file.close)  # closed with the solver, not left open
        printed: list[str] = []
        sys.stdout.flush()
        saved = os.dup(1)
        os.dup2(self._file.fileno(), 1)
        try:
            yield printed
        finally:
            os.dup2(saved, 1)
            os.close(saved)
            if os.fstat(self._file.fileno()).st_size:
                self._file.seek(0)
                text = self._file.read(_MAX_MESSAGE_BYTES).decode("utf-8", "replace")
                printed.extend(line for line in text.splitlines() if line.strip())
                self._file.seek(0)
                self._file.truncate()
