"""URDF files: screened before any parser, resolved, walked as one joint chain.

Owns screening untrusted URDF text (:mod:`~fkcheck.urdf.screen`), finding a
URDF from a ``[urdf].path`` spec (:mod:`~fkcheck.urdf.locate`), reading its
checked robot tree and the one walk down a joint chain
(:mod:`~fkcheck.urdf.tree`), loading a model's URDF against its mapping
(:mod:`~fkcheck.urdf.source`), the URDF's kinematic geometry
(:mod:`~fkcheck.urdf.chain`), writing a URDF from a DH model
(:mod:`~fkcheck.urdf.export`), a DH table from a URDF
(:mod:`~fkcheck.urdf.to_dh`), a xacro file expanded when asked
(:mod:`~fkcheck.urdf.xacro`) with fkcheck's own evaluator of its expressions
(:mod:`~fkcheck.urdf.expression`). May import: :mod:`fkcheck.core`,
:mod:`fkcheck.model`, :mod:`fkcheck.io`, :mod:`fkcheck.process`, :mod:`fkcheck.errors`.
"""

__all__: list[str] = []
