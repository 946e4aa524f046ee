"""Which URDF joints and links a DH model's joints and frames are, found by behaviour.

``fkcheck map`` proposes a model's ``[urdf]`` and ``[frames.*]`` block; ``fkcheck
check --to urdf:LINK`` places a link the model does not declare. Both compare the
in-house DH frames (:meth:`fkcheck.model.Model.fk`) with fkcheck's own URDF
chain geometry (:mod:`fkcheck.urdf.chain`) over seeded configurations: this is
a *mapping* tool, not a check (``fkcheck check`` on the result compares the
model against the independent URDF parsers).

Joints are matched by what they do, never by name. For each window of ``n``
consecutive movable URDF joints on a path from the root (every arm of a tree is
tried), and each axis direction, the relative motions of the last DH frame in
DH frame 0 are fitted to those of the window's last link in its first link's
parent (hand–eye calibration, ``M(q) = X·U(q)·Y``: rotation axes aligned with
:meth:`scipy.spatial.transform.Rotation.align_vectors`, then the translation by
least squares). A joint whose URDF axis turns the other way from the DH joint
(the URDF receives ``q`` unchanged) needs ``flip`` toggled in the table: the
directions are found by a beam search over the chain's prefixes, preferring no
flip where both fit (a planar chain is ambiguous).

Links: a link sits at a *constant* offset from a DH frame when that offset
varies over the samples by at most the model's check tolerances. Joints the
model does not map (fingers) take seeded random values then, so links below
them never count as rigid. Offsets are written with numbers within 1e-9 of a
round one (0, a multiple of 90°, a whole micrometre) snapped to it
(:func:`fkcheck.urdf.to_dh.clean_number`).

The modules: :mod:`~fkcheck.urdf.hand_eye` (the ``M ≈ X·U·Y`` fit),
:mod:`~fkcheck.urdf.chain_fit` (the configurations, the beam search, each link's
offset), :mod:`~fkcheck.urdf.matching` (:func:`map_model`,
:func:`reconcile_table`, the proposed check), :mod:`~fkcheck.urdf.map_frames`
(the proposed frames), :mod:`~fkcheck.urdf.map_result` (what the map found),
:mod:`~fkcheck.urdf.proposal` (the TOML block) and
:mod:`~fkcheck.urdf.placement` (``urdf:LINK``). This module re-exports their
public names.
"""

from __future__ import annotations

from fkcheck.urdf.chain_fit import DEFAULT_SAMPLES, LinkFit
from fkcheck.urdf.map_frames import COMMON_NAMES
from fkcheck.urdf.map_result import JointMatch, MapResult, ProposedFrame
from fkcheck.urdf.matching import Reconciled, map_model, reconcile_table
from fkcheck.urdf.placement import link_frame, with_link_frames
from fkcheck.urdf.proposal import proposal_toml

__all__ = [
    "COMMON_NAMES",
    "DEFAULT_SAMPLES",
    "JointMatch",
    "LinkFit",
    "MapResult",
    "ProposedFrame",
    "Reconciled",
    "link_frame",
    "map_model",
    "proposal_toml",
    "reconcile_table",
    "with_link_frames",
]
