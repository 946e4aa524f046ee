"""One reader per section of a model file, each validating its section into model types.

:func:`fkcheck.model.read.model_from_dict` calls them in the file's order of
dependence: the header (``name``, ``convention``, ``angle_unit``), the
``[[joint]]`` rows, ``[base]`` and ``[tool]``, ``[poses]``, ``[urdf]``,
``[frames.NAME]``, ``[check]``, ``[lint]`` and ``[[known_difference]]``. Every
reader takes a :class:`~fkcheck.model.sections.reader.Reader` (the file, for
messages) and raises :class:`~fkcheck.errors.ModelError` naming the file, the
field and the problem.
"""
