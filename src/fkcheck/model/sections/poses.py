"""``[poses]``: named configurations, one value per joint, in radians / metres."""

from __future__ import annotations

from typing import Any

from fkcheck.model.sections.joints import joint_value
from fkcheck.model.sections.reader import Reader, kind, shown_key
from fkcheck.model.types import Joint

__all__ = ["read_poses"]


def read_poses(
    r: Reader, raw: Any, joints: tuple[Joint, ...], to_rad: float
) -> dict[str, tuple[float, ...]]:
    """Each pose: as many values as joints, revolute ones in the file's angle unit."""
    if not isinstance(raw, dict):
        raise r.fail("poses", f"expected a table, got {kind(raw)}")
    poses: dict[str, tuple[float, ...]] = {}
    for pname, values in raw.items():
        nums = r.numbers(values, f"poses.{shown_key(pname)}", len(joints))
        poses[pname] = tuple(
            joint_value(r, v * (to_rad if j.type == "revolute" else 1.0),
                        f"poses.{shown_key(pname)}[{k}]", j.type)
            for k, (v, j) in enumerate(zip(nums, joints, strict=True))
        )  # fmt: skip
    return poses
