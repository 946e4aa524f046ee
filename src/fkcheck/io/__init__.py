"""Files and text at the boundary: reading untrusted files, writing outputs safely.

Owns what kind of file a path is (:mod:`~fkcheck.io.files`), strict number
parsing (:mod:`~fkcheck.io.numbers`), text made safe for terminals, XML,
Markdown and HTML (:mod:`~fkcheck.io.text`), atomic writes
(:mod:`~fkcheck.io.atomic`), strict JSON (:mod:`~fkcheck.io.strict_json`) and
the output-path policy (:mod:`~fkcheck.io.output_paths`) and the one way a
number is written for a person (:mod:`~fkcheck.io.format`). May import: the
standard library, NumPy, :mod:`fkcheck.errors`. No kinematics.
"""

__all__: list[str] = []
