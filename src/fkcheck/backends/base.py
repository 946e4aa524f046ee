"""The one small interface every reference backend implements.

A backend turns a :class:`~fkcheck.model.Model` and a batch of joint
configurations into poses of the model's *named frames* (``[frames.NAME]``),
all expressed in one root frame of the backend's choosing. The engine compares
``from_T_to = (root_T_from)⁻¹ · root_T_to`` across backends, so the root never
has to agree between them.

Backends live one per module under :mod:`fkcheck.backends`, import their library
inside their methods (never at module import), and are registered in
:mod:`fkcheck.backends.registry` (third-party ones through the ``fkcheck.backends``
entry-point group). Adding one touches no other backend: everything the engine,
the reports and the command line need from a backend is declared on it
(:class:`Backend`), and every list of backends by kind is derived from the
registry.

Every backend declares which question its agreement answers (:data:`Evidence`):

* ``"implementation"`` — *is the in-house core right, given the table?* The
  backend computes FK from the model's own DH table (``rtb-dh``,
  ``pinocchio-dh``), or is the user's code running that table (plugins,
  ``cmd:`` programs). Agreement proves the arithmetic, not the numbers: a wrong
  d1 is wrong in both.
* ``"table"`` — *is the table right, for the robot?* The backend's poses do not
  come from the table: the robot's URDF read by its parsers, measured or
  pendant poses, a table published elsewhere (``rtb-model:``). A URDF that
  ``fkcheck urdf`` wrote from the checked table does come from it: the engine
  then counts the URDF backends' results as implementation evidence
  (:mod:`fkcheck.engine.provenance`).

Independence is a rule: no backend uses fkcheck's own kinematics (the DH core,
its rotation helpers, its frame offsets, its URDF export) for anything it is
compared on. Base, tool and named-frame offsets are built with each library's
own constructs from the model's ``xyz``/``rpy`` numbers. The import contract in
``pyproject.toml`` (``[tool.importlinter]``) and ``tests/test_independence.py``
enforce it.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any, Literal, Protocol, runtime_checkable

from fkcheck.core.joint_array import joint_array, require_finite
from fkcheck.core.typing import JACOBIAN_REFERENCES, Float, JacobianReference
from fkcheck.errors import BackendUnavailable, FrameUnavailable
from fkcheck.model.types import Model

__all__ = [
    "CONTRACT",
    "EVIDENCE_BY_READS",
    "Backend",
    "BackendDefaults",
    "BackendUnavailable",
    "Evidence",
    "FixedConfigurations",
    "FrameUnavailable",
    "Reads",
    "SharesDHFrames",
    "contract_problems",
    "reads_description",
    "reads_format",
    "reads_model_description",
    "validated_q",
]


#: Which question a backend's agreement answers (see the module docstring).
Evidence = Literal["implementation", "table"]

#: What a backend's poses are computed from:
#:
#: * ``"dh"`` — the model's own DH table (``rtb-dh``, ``pinocchio-dh``);
#: * ``"urdf"`` — the model's description in the URDF language (a URDF, a xacro
#:   file's expansion), any link of it (``pinocchio-urdf``…);
#: * ``"mjcf"`` — the model's description in MuJoCo's MJCF;
#: * ``"published"`` — a table published elsewhere (``rtb-model:``);
#: * ``"poses"`` — poses recorded on a robot (``poses:``);
#: * ``"program"`` — the user's own code running the table (plugins, ``cmd:``).
Reads = Literal["dh", "urdf", "mjcf", "published", "poses", "program"]

#: The evidence a backend may claim, by what it reads: a backend that computes
#: from the table (or is the user's code running it) proves the implementation only.
EVIDENCE_BY_READS: dict[str, tuple[Evidence, ...]] = {
    "dh": ("implementation",),
    "program": ("implementation",),
    "urdf": ("table",),
    "mjcf": ("table",),
    "published": ("table",),
    "poses": ("table",),
}


@runtime_checkable
class Backend(Protocol):
    """A reference FK implementation: the one contract every backend fulfils.

    Attributes:
        name: The backend's name as shown in results (``"rtb-dh"``, ``"cmd:./fk"``).
        method: The library call used, for the report (``"DHRobot.fkine_all"``).
        evidence: ``"implementation"`` or ``"table"``: what its agreement proves.
        reads: What its poses are computed from (:data:`Reads`); a description
            language (``"urdf"``) means it computes any link of the model's
            description, so it may compare ``urdf:LINK`` for a link no frame
            declares (:func:`fkcheck.urdf.mapping.with_link_frames`).
        formats: The description formats it reads (``("urdf", "xacro")``;
            :data:`fkcheck.description.registry.FORMATS`), each in the language
            ``reads`` names; empty for a backend that reads no description.
            :func:`reads_format` is the question every part of a check asks.
        isolated: ``True``: the engine calls its :meth:`frame_poses` (and
            :meth:`frame_jacobian`) in processes of its own, a large ``q`` split over
            the cores — for slow pure-Python backends that hold the GIL; the object,
            the model and ``q`` must pickle. A share its declared cost puts under
            :data:`fkcheck.engine.runner.IN_PROCESS_MAX_S` runs in the engine's
            process (starting a process would cost more), unless a description it
            reads is longer than
            :data:`~fkcheck.engine.runner.IN_PROCESS_MAX_DESCRIPTION_CHARS`; with no
            declared cost, always in its own.
        imports: Module names the engine imports once, in the main thread, before
            backends start (two threads importing one heavy library lazily at the
            same time can hit Python's import-deadlock detection).
        distributions: The installed distributions (PyPI names) it computes with,
            whose versions every report shows.
        jacobian_method: The library call its own Jacobians come from, for the
            reports; ``None`` when it has none (the engine then differentiates its
            poses).
        jacobian_references: The references (:data:`~fkcheck.core.typing.JacobianReference`)
            its own Jacobians are given in; the engine asks for ``world-aligned``
            and re-expresses it when the one wanted is not among them.

    :class:`BackendDefaults` gives the usual values of the optional members.
    """

    name: str
    method: str
    evidence: Evidence
    reads: Reads
    formats: tuple[str, ...]
    isolated: bool
    imports: tuple[str, ...]
    distributions: tuple[str, ...]
    jacobian_method: str | None
    jacobian_references: tuple[JacobianReference, ...]

    def unavailable_reason(self, model: Model) -> str | None:
        """Why this backend cannot check ``model`` here, or ``None`` if it can.

        Must be cheap: look for the library and the model's inputs (e.g. a
        ``[urdf]`` table) without importing heavy libraries.
        """
        ...

    def inputs(self, model: Model) -> tuple[Path, ...]:
        """The files this backend reads for ``model`` (never to be overwritten by outputs).

        The model's URDF for a URDF reader, a measured-poses file, a program and
        the files on its command line, a plugin's module. Cheap, and never raises
        for a missing file (the check reports that).
        """
        ...

    def frame_poses(self, model: Model, q: Float, frames: Sequence[str]) -> Float:
        """Poses of named frames for a batch of configurations.

        Args:
            model: The model being checked.
            q: Joint values, shape ``(N, n)``, radians / metres, DH joint order.
            frames: Names from ``model.frames``.

        Returns:
            Shape ``(len(frames), N, 4, 4)``: ``root_T_frame`` for each frame, with
            one root shared by all frames of this call.

        Raises:
            BackendUnavailable: The library or an input is missing (→ skipped).
            FrameUnavailable: A frame cannot be computed by this backend (→ skipped).
            FkcheckError: Bad input such as an unreadable URDF (→ exit 2).
            Exception: Anything else is reported as this backend's *error*.
        """
        ...

    def frame_jacobian(
        self, model: Model, q: Float, frame: str, reference: JacobianReference
    ) -> Float | None:
        """The library's own geometric Jacobian of a named frame, ``(N, 6, n)``, or ``None``.

        Rows are linear then angular, one column per DH joint, in the backend's
        own root frame (the DH world for backends built from the table, the
        URDF's root for URDF backends). ``reference`` is one of
        :attr:`jacobian_references`: ``"world-aligned"`` (the frame origin's
        velocity and the angular velocity in root axes), ``"local"`` (both in
        the frame's own axes) or ``"world"`` (the spatial twist at the root's
        origin, in root axes) — Pinocchio's ``LOCAL_WORLD_ALIGNED``, ``LOCAL``
        and ``WORLD``. ``None`` when it has no Jacobian of that frame (the
        engine then differentiates its poses).
        """
        ...


class BackendDefaults:
    """The usual values of a backend's optional members, to inherit from.

    In-process, no library imported ahead or named, no Jacobian of its own, no input file,
    no declared cost.

    The optional cost members are read by the check's plan (:mod:`fkcheck.engine.plan`):
    ``pose_cost_us``, microseconds per configuration of a 6-joint arm with the
    engine's comparison, measured on the project's busy 2-core machine, and
    ``jacobian_cost_us`` the same with its own Jacobian; ``None``: not declared
    (the backend then always compares every configuration).
    """

    pose_cost_us: float | None = None
    jacobian_cost_us: float | None = None
    isolated: bool = False
    formats: tuple[str, ...] = ()
    imports: tuple[str, ...] = ()
    distributions: tuple[str, ...] = ()
    jacobian_method: str | None = None
    jacobian_references: tuple[JacobianReference, ...] = JACOBIAN_REFERENCES

    def inputs(self, model: Model) -> tuple[Path, ...]:
        """No file of its own."""
        return ()

    def frame_jacobian(
        self, model: Model, q: Float, frame: str, reference: JacobianReference
    ) -> Float | None:
        """No Jacobian of its own: the engine differentiates the poses."""
        return None


#: The members every backend declares (:class:`Backend`), with the types they must have.
CONTRACT: dict[str, tuple[type, ...]] = {
    "name": (str,),
    "method": (str,),
    "evidence": (str,),
    "reads": (str,),
    "isolated": (bool,),
    "imports": (tuple,),
    "distributions": (tuple,),
    "jacobian_method": (str, type(None)),
    "jacobian_references": (tuple,),
}
_METHODS = ("unavailable_reason", "inputs", "frame_poses", "frame_jacobian")


def contract_problems(backend: Any) -> list[str]:
    """How ``backend`` breaks the :class:`Backend` contract; empty when it keeps it."""
    problems: list[str] = []
    for member, types in CONTRACT.items():
        if not hasattr(backend, member):
            problems.append(f"no {member!r}")
        elif not isinstance(getattr(backend, member), types):
            want = " or ".join("None" if t is type(None) else t.__name__ for t in types)
            problems.append(f"{member!r} is not {want}")
    problems += [f"no method {m}()" for m in _METHODS if not callable(getattr(backend, m, None))]
    if problems:
        return problems
    evidence, reads = backend.evidence, backend.reads
    if reads not in EVIDENCE_BY_READS:
        problems.append(f"reads {reads!r}, not one of {', '.join(EVIDENCE_BY_READS)}")
    elif evidence not in EVIDENCE_BY_READS[reads]:
        problems.append(
            f"claims {evidence!r} evidence but reads {reads!r}, which proves "
            f"{' or '.join(EVIDENCE_BY_READS[reads])} only"
        )
    for member in ("imports", "distributions"):
        if not all(isinstance(m, str) for m in getattr(backend, member)):
            problems.append(f"{member!r} holds something other than names")
    formats = getattr(backend, "formats", ())  # optional: BackendDefaults gives ()
    if not isinstance(formats, tuple) or not all(isinstance(f, str) for f in formats):
        problems.append("'formats' is not a tuple of format names")
    else:
        problems += _format_problems(reads, formats)
    references = backend.jacobian_references
    if backend.jacobian_method is not None and "world-aligned" not in references:
        problems.append("has a jacobian_method but 'world-aligned' is not in jacobian_references")
    unknown = set(references) - set(JACOBIAN_REFERENCES)
    if unknown:
        problems.append(
            f"jacobian_references {sorted(map(str, unknown))} are not among "
            f"{', '.join(JACOBIAN_REFERENCES)}"
        )
    return problems


def _format_problems(reads: str, formats: tuple[str, ...]) -> list[str]:
    """How a backend's ``formats`` disagree with its ``reads`` (each must be in its language)."""
    from fkcheck.description.registry import FORMATS

    languages = {f.name: f.language for f in FORMATS}
    problems = [
        f"formats names {f!r}, not one of {', '.join(languages)}"
        for f in formats
        if f not in languages
    ]
    problems += [
        f"reads {reads!r} but reads format {f!r}, which is in {languages[f]!r}"
        for f in formats
        if f in languages and languages[f] != reads
    ]
    return problems


def reads_format(backend: Backend, fmt: str) -> bool:
    """Whether ``backend`` reads descriptions of format ``fmt`` (``"urdf"``, ``"xacro"``)."""
    return fmt in getattr(backend, "formats", ())


def reads_model_description(backend: Backend, model: Model) -> bool:
    """Whether ``backend`` reads one of ``model``'s descriptions (its format is one it reads)."""
    from fkcheck.description.registry import model_formats

    return any(reads_format(backend, fmt.name) for fmt in model_formats(model))


def reads_description(backend: Backend) -> bool:
    """Whether ``backend`` computes its poses from a model's description (of any format)."""
    return bool(getattr(backend, "formats", ()))


@runtime_checkable
class SharesDHFrames(Protocol):
    """A backend built from the DH table itself, which can give every DH frame.

    Used to find the first joint at which two chains part ways.
    """

    def dh_frames(self, model: Model, q: Float) -> Float:
        """``world_T_i`` for DH frames ``0…n``: shape ``(N, n+1, 4, 4)``."""
        ...


@runtime_checkable
class FixedConfigurations(Protocol):
    """A backend that only knows poses at given configurations (e.g. measured poses).

    When one takes part, the check runs on its configurations instead of sampling.
    """

    def configurations(self, model: Model) -> Float:
        """The configurations it has poses for, ``(N, n)``, radians / metres."""
        ...


def validated_q(model: Model, q: Float) -> Float:
    """``q`` as a C-contiguous float64 ``(N, n)`` array, checked but not computed on.

    Raises:
        JointInputError: Wrong shape, not numeric, or not finite.
    """
    q_arr = joint_array(q, model.dof)
    require_finite(q_arr)
    return q_arr
