"""URDF files: screened before any parser, resolved, walked as one joint chain.

Owns screening untrusted URDF text (:mod:`~fkcheck.urdf.screen`), resolving a
model's URDF and its links (:mod:`~fkcheck.urdf.source`), the one URDF joint
chain (:mod:`~fkcheck.urdf.chain`), writing a URDF from a DH model
(:mod:`~fkcheck.urdf.export`) and a DH table from a URDF
(:mod:`~fkcheck.urdf.to_dh`). May import: :mod:`fkcheck.core`,
:mod:`fkcheck.model`, :mod:`fkcheck.io`, :mod:`fkcheck.errors`.
"""

__all__: list[str] = []
