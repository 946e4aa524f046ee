"""What a calibration changes: the calibrated table's poses against the nominal table's.

A factory calibration moves a UR arm's tool by millimetres. Over a check's
configurations, both tables' ``from_T_to`` come from the in-house core, and
their difference is summarised as every output shows it: largest, median and
95th percentile, in millimetres and degrees, and the configuration of the
largest position difference.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from fkcheck.calibration.provenance import Provenance
from fkcheck.core.metrics import position_error_m, rotation_error_rad
from fkcheck.core.typing import Float
from fkcheck.errors import ModelError
from fkcheck.io.numbers import show_text
from fkcheck.model.frames import CHUNK, reference_poses, relative_pose
from fkcheck.model.types import Model

__all__ = [
    "CalibrationEffect",
    "calibration_effect",
    "dh_chain_effect",
    "dh_frame",
    "nominal_location",
    "nominal_model",
]


@dataclass(frozen=True)
class CalibrationEffect:
    """The calibrated ``from_T_to`` against the nominal one, over a check's configurations.

    Attributes:
        nominal: The nominal model's name.
        identity: The calibration's name (hash, checksums or file digest).
        frame_from: Frame the poses are expressed in.
        frame_to: Frame whose poses are compared.
        configurations: How many configurations were compared.
        max_position_m: Largest position difference, metres.
        median_position_m: Its median, metres.
        p95_position_m: Its 95th percentile, metres.
        max_rotation_rad: Largest rotation difference (angle of the relative rotation), rad.
        median_rotation_rad: Its median, rad.
        p95_rotation_rad: Its 95th percentile, rad.
        worst_index: The configuration of the largest position difference.
        worst_q: That configuration, rad.
        provenance: Whether the model is still what its calibration file gives
            (:mod:`fkcheck.calibration.provenance`), ``None`` where not compared.
    """

    nominal: str
    identity: str
    frame_from: str
    frame_to: str
    configurations: int
    max_position_m: float
    median_position_m: float
    p95_position_m: float
    max_rotation_rad: float
    median_rotation_rad: float
    p95_rotation_rad: float
    worst_index: int
    worst_q: tuple[float, ...]
    provenance: Provenance | None = None

    @property
    def line(self) -> str:
        """One line for every format: sizes in mm and degrees, and where."""
        mm = 1e3
        deg = 180.0 / math.pi
        where = ", ".join(f"{v * deg:.1f}°" for v in self.worst_q)
        note = self.provenance.note if self.provenance is not None else ""
        return (
            f"calibration {self.identity}{f' ({note})' if note else ''} vs nominal {self.nominal} "
            f"({self.frame_from} → {self.frame_to}, {self.configurations} configurations): "
            f"position max {self.max_position_m * mm:.3f} mm, "
            f"median {self.median_position_m * mm:.3f} mm, "
            f"95th percentile {self.p95_position_m * mm:.3f} mm; "
            f"rotation max {self.max_rotation_rad * deg:.4f}°, "
            f"median {self.median_rotation_rad * deg:.4f}°, "
            f"95th percentile {self.p95_rotation_rad * deg:.4f}°; "
            f"largest at q = [{where}]"
        )


def nominal_location(ref: str, folder: Path) -> Path:
    """The model file ``[calibration] nominal`` names, held to the calibrated model's folder.

    ``ref`` is a bundled model's name (``ur5e``), ``fkcheck:<subpath>`` (a model
    file bundled with fkcheck), or a model file (``.toml``, ``.csv``) named
    relative to ``folder`` — the calibrated model's folder — by a relative path
    without ``..`` that stays inside ``folder`` once symbolic links are followed.
    Nothing is read here, and no message quotes more than the reference.

    Raises:
        ModelError: (field ``calibration.nominal``, no file) An unknown name, an
            absolute path, ``..``, a path leading out of ``folder``, or not a
            model file's name.
    """
    from fkcheck.errors import UrdfError
    from fkcheck.model.read import bundled_model_paths
    from fkcheck.urdf.locate import FKCHECK_PREFIX, bundled_location

    field = "calibration.nominal"
    shown = show_text(ref)
    if ref.startswith(FKCHECK_PREFIX):
        try:
            return bundled_location(ref)
        except UrdfError as exc:
            raise ModelError(None, field, f"{shown}: {exc.problem}") from None
    pure = Path(ref)
    if "/" not in ref and "\\" not in ref and pure.suffix == "":
        bundled = bundled_model_paths()
        if ref not in bundled:
            raise ModelError(
                None,
                field,
                f"{shown} is no bundled model ({', '.join(bundled)}) and no model file's name "
                "(.toml or .csv)",
            )
        return bundled[ref]
    if pure.is_absolute() or ".." in pure.parts or "\\" in ref:
        raise ModelError(
            None,
            field,
            f"{shown}: a nominal model file is named relative to the calibrated model's folder, "
            "without '..' (keep the nominal model in that folder, or name a bundled model)",
        )
    if pure.suffix.lower() not in (".toml", ".csv"):
        raise ModelError(None, field, f"{shown} names no model file (.toml or .csv)")
    target = folder / pure
    if not target.resolve().is_relative_to(folder.resolve()):
        raise ModelError(
            None, field, f"{shown} leads outside the calibrated model's folder (a symbolic link)"
        )
    return target


def nominal_model(calibrated: Model) -> Model:
    """The nominal model a calibrated model names in ``[calibration] nominal``.

    A bundled model's name, or a model file in the calibrated model's folder
    (:func:`nominal_location`; the current directory for a model built in memory).

    Raises:
        ModelError: No ``[calibration]``, a nominal model outside the calibrated
            model's folder, or one that cannot be loaded, or whose joints are
            not the calibrated model's.
    """
    from fkcheck.model.read import load_model

    spec = calibrated.calibration
    if spec is None:
        raise ModelError(calibrated.path, "calibration", "the model has no [calibration]")
    ref = spec.nominal
    folder = calibrated.path.parent if calibrated.path is not None else Path.cwd()
    try:
        target = nominal_location(ref, folder)
        nominal = load_model(target)
    except ModelError as exc:
        problem = exc.problem if exc.path is None else str(exc)
        raise ModelError(calibrated.path, "calibration.nominal", problem) from None
    if nominal.joint_names != calibrated.joint_names:
        raise ModelError(
            calibrated.path,
            "calibration.nominal",
            f"{show_text(ref)} has joints {', '.join(nominal.joint_names)}; "
            f"this model has {', '.join(calibrated.joint_names)}",
        )
    return nominal


def _from_T_to(model: Model, q: Float, frame_from: str, frame_to: str) -> Float:
    poses = reference_poses(model, q, (frame_from, frame_to))
    return relative_pose(poses[0], poses[1])


def dh_frame(index: int) -> str:
    """How an effect names DH frame ``index`` (not a named frame of the model)."""
    return f"DH frame {index}"


def _dh0_T_dhn(model: Model, q: Float) -> Float:
    out = np.empty((q.shape[0], 4, 4))
    for start in range(0, q.shape[0], CHUNK):
        frames = model.fk(q[start : start + CHUNK], all_frames=True)  # (N, n+1, 4, 4)
        out[start : start + CHUNK] = relative_pose(frames[:, 0], frames[:, -1])
    return out


def dh_chain_effect(
    calibrated: Model, nominal: Model, q: Float, identity: str = ""
) -> CalibrationEffect:
    """Compare the two tables' DH frame 0 → last DH frame at ``q`` (shape ``(N, dof)``, N ≥ 1).

    What the calibration changes of the table itself, whatever frames the models
    name: every joint lies between the two frames, and neither base nor tool
    offset does. A calibration's fit is measured so (``fkcheck calibration`` and
    lint): measured between a ``[check]`` pair, a pair that spans no joint or
    only the first (``tool0 → tool0``) would let another type's table, or one in
    millimetres, "fit" by 0 mm.
    """
    return _effect(
        calibrated, nominal, q, (dh_frame(0), dh_frame(calibrated.dof)),
        _dh0_T_dhn(calibrated, q), _dh0_T_dhn(nominal, q), identity,
    )  # fmt: skip


def calibration_effect(
    calibrated: Model,
    nominal: Model,
    q: Float,
    frame_from: str,
    frame_to: str,
    identity: str = "",
) -> CalibrationEffect:
    """Compare the two tables' ``from_T_to`` at ``q`` (shape ``(N, dof)``, N ≥ 1).

    Raises:
        FrameError: A frame is not in one of the models.
    """
    ours = _from_T_to(calibrated, q, frame_from, frame_to)
    theirs = _from_T_to(nominal, q, frame_from, frame_to)
    return _effect(calibrated, nominal, q, (frame_from, frame_to), ours, theirs, identity)


def _effect(
    calibrated: Model,
    nominal: Model,
    q: Float,
    pair: tuple[str, str],
    ours: Float,
    theirs: Float,
    identity: str,
) -> CalibrationEffect:
    """The summary of two batches of ``from_T_to`` (``(N, 4, 4)`` each)."""
    pos = position_error_m(ours, theirs)
    rot = rotation_error_rad(ours, theirs)
    worst = int(np.argmax(pos))
    return CalibrationEffect(
        nominal=nominal.name,
        identity=identity or (calibrated.calibration.identity if calibrated.calibration else ""),
        frame_from=pair[0],
        frame_to=pair[1],
        configurations=int(q.shape[0]),
        max_position_m=float(pos.max()),
        median_position_m=float(np.median(pos)),
        p95_position_m=float(np.percentile(pos, 95)),
        max_rotation_rad=float(rot.max()),
        median_rotation_rad=float(np.median(rot)),
        p95_rotation_rad=float(np.percentile(rot, 95)),
        worst_index=worst,
        worst_q=tuple(float(v) for v in q[worst]),
    )
