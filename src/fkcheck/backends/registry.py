"""The one place backends are registered, and how ``--against`` names map to them.

Backends are referenced by ``module:attribute`` and imported only when used, so
listing them costs nothing and a missing library only affects its own backend.
Every list of backends by kind — the default set, the URDF readers, the names a
``[[known_difference]]`` may give, the ``--against`` help — is derived here from
what each backend declares (:class:`~fkcheck.backends.base.Backend`).

Names:

* built-ins: ``rtb-dh``, ``pinocchio-dh``, ``pinocchio-urdf``, ``yourdfpy-urdf``,
  ``rtb-urdf``… (:data:`BUILTIN`; those marked default run without ``--against``,
  and ``mujoco-mjcf``, ``pinocchio-mjcf`` too for a model with ``[mjcf]``);
* ``rtb-model:<Name>`` — a model Robotics Toolbox ships (``rtb-model:UR5``);
* ``poses:<file.csv>`` — measured poses (a robot's pendant log, say), or
  ``poses:<bag>`` — a ROS 2 bag's joint states and tf (:mod:`fkcheck.backends.bag`);
  the check runs at their configurations;
* ``cmd:<command line>`` — an external FK program (stdin/stdout protocol);
* ``<module>:<function>`` — a Python callable (plugin);
* third-party backends: an installed distribution's entry point in the
  ``fkcheck.backends`` group (:data:`ENTRY_POINT_GROUP`), as pytest plugins
  register. The entry point's name is the backend's name (ending in ``:`` for a
  prefix taking an argument) and its value a ``module:Class`` called as
  ``Class(argument, options)``::

      [project.entry-points."fkcheck.backends"]
      my-urdf = "my_fk.backend:MyUrdf"

  Such a backend is named with ``--against my-urdf``, appears in reports and,
  when its evidence is ``table``, may be named in ``[[known_difference]]``. Its
  code runs only in processes of its own (:mod:`fkcheck.backends.thirdparty`).

A name answers to one source only: a name a built-in has or two distributions
register, and a prefix whose ``prefix:function`` also names an importable
module, are refused when asked for, naming both (:func:`make_backend`).

This module is the registry's public face: registering and building backends
is :mod:`fkcheck.backends.registration`, the lists of backends by kind
:mod:`fkcheck.backends.listing`, the versions a run depends on
:mod:`fkcheck.backends.versions`.
"""

from __future__ import annotations

from fkcheck.backends.listing import (
    against_help,
    check_known_differences,
    default_backends,
    default_names,
    known_difference_names,
    names,
)
from fkcheck.backends.registration import (
    BUILTIN,
    ENTRY_POINT_GROUP,
    MAX_TIMEOUT_S,
    AmbiguousBackendError,
    BackendContractError,
    BackendOptions,
    Registration,
    build_in_process,
    make_backend,
    name_problems,
    parse_against,
    registrations,
    valid_names,
)
from fkcheck.backends.versions import library_versions

__all__ = [
    "BUILTIN",
    "ENTRY_POINT_GROUP",
    "MAX_TIMEOUT_S",
    "AmbiguousBackendError",
    "BackendContractError",
    "BackendOptions",
    "Registration",
    "against_help",
    "build_in_process",
    "check_known_differences",
    "default_backends",
    "default_names",
    "known_difference_names",
    "library_versions",
    "make_backend",
    "name_problems",
    "names",
    "parse_against",
    "registrations",
    "valid_names",
]
