"""``[mjcf]``: the reference MJCF (MuJoCo's format) and its joints in DH order."""

from __future__ import annotations

from typing import Any

from fkcheck.io.numbers import show_text
from fkcheck.model.sections.reader import Reader, is_text_list
from fkcheck.model.types import MjcfSpec

__all__ = ["MJCF_KEYS", "read_mjcf"]

MJCF_KEYS = {"path", "joints"}


def read_mjcf(r: Reader, raw: Any, n: int) -> MjcfSpec:
    """The ``[mjcf]`` table of a model with ``n`` joints."""
    u = r.table(raw, "mjcf", MJCF_KEYS)
    if "path" not in u:
        raise r.fail("mjcf.path", "missing (required in [mjcf])")
    path = r.string(u["path"], "mjcf.path")
    if not path.strip():
        raise r.fail(
            "mjcf.path",
            f"{show_text(path)} names no file: give the MJCF's path (relative to this file)",
        )
    joints: Any = u.get("joints")
    if not is_text_list(joints):
        raise r.fail("mjcf.joints", "expected a list of MJCF joint names in DH order")
    if len(joints) != n:
        raise r.fail("mjcf.joints", f"names {len(joints)} MJCF joints but the DH table has {n}")
    if len(set(joints)) != len(joints):
        raise r.fail("mjcf.joints", "names an MJCF joint twice")
    return MjcfSpec(path, tuple(joints))
