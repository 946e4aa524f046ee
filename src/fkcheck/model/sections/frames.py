"""``[frames.NAME]``: named frames on the DH chain, with their offsets and URDF twins."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from fkcheck.model.sections.offsets import read_offset
from fkcheck.model.sections.reader import Reader, kind, shown_key, shown_value
from fkcheck.model.types import DhIndex, FrameSpec, default_frames

__all__ = ["FRAME_KEYS", "read_frames"]

FRAME_KEYS = {"dh", "xyz", "rpy", "urdf", "mjcf", "source"}


def read_frames(r: Reader, top: Mapping[str, Any], n: int, to_rad: float) -> dict[str, FrameSpec]:
    """``world`` and ``tcp``, then the file's ``[frames.NAME]`` tables, if any."""
    frames = default_frames()
    if "frames" not in top:
        return frames
    raw = top["frames"]
    if not isinstance(raw, dict):
        raise r.fail("frames", f"expected tables [frames.NAME], got {kind(raw)}")
    for fname, table in raw.items():
        frames[fname] = _read_frame(r, fname, table, n, to_rad)
    return frames


def _read_frame(r: Reader, fname: str, raw: Any, n: int, to_rad: float) -> FrameSpec:
    """One ``[frames.NAME]`` table of a model with ``n`` joints."""
    where = f"frames.{shown_key(fname)}"
    tbl = r.table(raw, where, FRAME_KEYS)
    idx = _dh_index(r, tbl, where, n)
    off = read_offset(r, {k: tbl[k] for k in ("xyz", "rpy") if k in tbl}, where, to_rad)
    twin = r.string(tbl["urdf"], f"{where}.urdf") if "urdf" in tbl else None
    mjcf = r.string(tbl["mjcf"], f"{where}.mjcf") if "mjcf" in tbl else None
    source = r.string(tbl["source"], f"{where}.source") if "source" in tbl else ""
    if "source" in tbl and not source.strip():
        raise r.fail(f"{where}.source", "empty: say where the offset comes from")
    return FrameSpec(fname, idx, off, twin, source, mjcf)


def _dh_index(r: Reader, tbl: dict[str, Any], where: str, n: int) -> DhIndex:
    """``dh``: required; a DH frame ``0…n``, ``"tcp"`` or ``"world"``."""
    if "dh" not in tbl:
        raise r.fail(f"{where}.dh", 'missing: the DH frame index 0…n, "tcp" or "world"')
    idx = tbl["dh"]
    if isinstance(idx, bool) or not (
        (isinstance(idx, int) and 0 <= idx <= n) or idx in ("tcp", "world")
    ):
        raise r.fail(f"{where}.dh", f'expected 0…{n}, "tcp" or "world", got {shown_value(idx)}')
    return idx  # type: ignore[no-any-return]
