"""A robot's description, whatever its format: one concept, one loader, one cache.

A model names its robot's description in a section of its model file
(``[urdf]``, ``[mjcf]``); the description is read in one place
(:func:`~fkcheck.description.registry.load_description`), screened before any
parser sees it, and kept once per process while its files keep their bytes.
What the rest of fkcheck asks of it — its format, its files, its screened
text, its kinematic tree (:class:`~fkcheck.urdf.chain.KinematicTree`) and its
frame names — is the same for every format (:class:`~fkcheck.description.types.Description`).

A format is a module that fulfils
:class:`~fkcheck.description.types.DescriptionFormat` and is listed in
:data:`~fkcheck.description.registry.FORMATS`: URDF and xacro
(:mod:`~fkcheck.description.urdf`, wrapping :mod:`fkcheck.urdf`) and MJCF
(:mod:`~fkcheck.description.mjcf`, wrapping :mod:`fkcheck.mjcf`); what depends
only on the names of its model-file section and frame key is
:class:`~fkcheck.description.section.SectionFormat`'s, which each extends. Readers of a
format are backends that declare it (``formats`` on
:class:`fkcheck.backends.base.Backend`). May import: :mod:`fkcheck.mjcf`,
:mod:`fkcheck.urdf`, :mod:`fkcheck.model`, :mod:`fkcheck.core`, :mod:`fkcheck.io`,
:mod:`fkcheck.process`, :mod:`fkcheck.errors`.
"""

__all__: list[str] = []
