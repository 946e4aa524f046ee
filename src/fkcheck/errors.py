"""The exceptions fkcheck raises: two families that never mix.

* :class:`FkcheckError` and its subclasses mean *bad input*: every error's
  ``str()`` is one line that names where the problem is (file and field, or
  argument) and what is wrong, and where there is a closed set of valid values,
  lists them. The CLI prints that line and exits with status 2.
* :class:`Skip` and its subclasses mean *a backend does not apply here* (its
  library is missing, or it cannot compute a frame): the check reports that
  backend as ``skipped`` with the reason. A ``Skip`` is not an ``FkcheckError``
  and vice versa, so no ``except`` order can turn one into the other.
"""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path

__all__ = [
    "INSTALL_REFERENCE",
    "REFERENCE_EXTRA",
    "REFERENCE_LIBRARIES",
    "BackendNotFoundError",
    "BackendUnavailable",
    "FkcheckError",
    "FrameError",
    "FrameUnavailable",
    "JointInputError",
    "MissingExtraError",
    "MjcfError",
    "ModelError",
    "OptionError",
    "Skip",
    "TimeLimitError",
    "ToleranceError",
    "UnmappedFrameError",
    "UrdfError",
    "XacroRefused",
    "failure_text",
    "missing_extra",
]

#: The extra that installs the reference libraries and what a check computes with
#: (``[project.optional-dependencies] reference`` of pyproject.toml). fkcheck's own
#: dependencies are what lint, convert, fk and export import.
REFERENCE_EXTRA = "reference"

#: The one command that installs it, as every message about a missing library gives it.
INSTALL_REFERENCE = f"pip install 'fkcheck[{REFERENCE_EXTRA}]'"

#: The top-level modules that the reference extra installs, each with the library's name.
REFERENCE_LIBRARIES: dict[str, str] = {
    "scipy": "SciPy",
    "matplotlib": "Matplotlib",
    "numba": "numba",
    "llvmlite": "numba",
    "roboticstoolbox": "Robotics Toolbox for Python",
    "spatialmath": "Robotics Toolbox for Python",
    "pinocchio": "Pinocchio",
    "example_robot_data": "example-robot-data",
    "yourdfpy": "yourdfpy",
    "mujoco": "MuJoCo",
    "idyntree": "iDynTree",
    "xacrodoc": "xacrodoc",
    "xacro": "xacrodoc",
    "rosbags": "rosbags",
}


def _alternatives(valid: Iterable[str]) -> str:
    names = list(valid)
    return ", ".join(names) if names else "(none)"


class FkcheckError(Exception):
    """Base class of every error fkcheck raises on bad input."""


class ModelError(FkcheckError):
    """A model file (TOML or DH CSV) that cannot be read as a valid model.

    Attributes:
        path: The model file, or ``None`` for a model built in memory.
        field: Dotted location inside the file, e.g. ``joint[2].alpha``.
        problem: What is wrong, in a few words.
        joint: The name of the joint the field belongs to (``""``: none, or not
            read yet); the message shows it after the field, ``joint[2].alpha (elbow)``
            (:mod:`fkcheck.model.names`: a 0-based field path always with its name).
    """

    def __init__(
        self, path: Path | str | None, field: str, problem: str, *, joint: str = ""
    ) -> None:
        self.path = None if path is None else Path(path)
        self.field = field
        self.problem = problem
        self.joint = joint
        where = str(self.path) if self.path is not None else "<model>"
        shown = f"{field} ({joint})" if field and joint else field
        super().__init__(f"{where}: {shown}: {problem}" if field else f"{where}: {problem}")


class JointInputError(FkcheckError, ValueError):
    """Joint values that cannot be used: wrong length, non-finite, out of limits.

    It is also a :class:`ValueError`, so numeric code can catch it as such.
    """


class OptionError(FkcheckError, ValueError):
    """A check's option out of its range (:mod:`fkcheck.model.options`): ``where: problem``.

    It is also a :class:`ValueError`, so numeric code can catch it as such.

    Attributes:
        where: The argument, flag or key it came in (``--seed``, ``samples``,
            ``[tool.fkcheck] timeout in pyproject.toml``).
        problem: The range it must be in, and the value given.
    """

    def __init__(self, where: str, problem: str) -> None:
        self.where = where
        self.problem = problem
        super().__init__(f"{where}: {problem}")


class ToleranceError(OptionError):
    """A tolerance or a known difference's bound out of range (:mod:`fkcheck.core.tolerances`)."""


class TimeLimitError(FkcheckError):
    """Work of fkcheck's own (not a backend's) that did not finish within the check's time limit.

    Said in one line, with the limit and how to give more (``--timeout``).
    """


class FrameError(FkcheckError):
    """A frame name that the model (or its URDF) does not define.

    Attributes:
        frame: The name asked for.
        where: Where it was looked up (``"model ur5"``, ``"URDF ur5_robot.urdf"``).
        valid: The names that exist there.
    """

    def __init__(self, frame: str, where: str, valid: Iterable[str]) -> None:
        self.frame = frame
        self.where = where
        self.valid = tuple(valid)
        super().__init__(f"frame {frame!r} not in {where}; frames are: {_alternatives(self.valid)}")


class UrdfError(FkcheckError):
    """A URDF that is missing, unreadable, unsafe, or does not fit the model.

    Attributes:
        path: The URDF file (or the spec as written in the model).
        problem: What is wrong.
    """

    def __init__(self, path: Path | str, problem: str) -> None:
        self.path = str(path)
        self.problem = problem
        super().__init__(f"{self.path}: {problem}")


class MjcfError(FkcheckError):
    """An MJCF (MuJoCo) description that is missing, unreadable, unsafe, or cannot be followed.

    Attributes:
        path: The MJCF file (or the file of it where the problem is: an include).
        problem: What is wrong.
    """

    def __init__(self, path: Path | str, problem: str) -> None:
        self.path = str(path)
        self.problem = problem
        super().__init__(f"{self.path}: {problem}")


class XacroRefused(UrdfError):
    """A file refused as a URDF because it is xacro: expanding it needs the opt-in."""


class BackendNotFoundError(FkcheckError):
    """A backend name (``--against``) that fkcheck does not know.

    Attributes:
        name: The name asked for.
        valid: The registered backend names and accepted prefixes.
    """

    def __init__(self, name: str, valid: Iterable[str]) -> None:
        self.name = name
        self.valid = tuple(valid)
        super().__init__(f"unknown backend {name!r}; backends are: {_alternatives(self.valid)}")


class MissingExtraError(FkcheckError):
    """What was asked computes with a library of the reference extra, which is not installed.

    Attributes:
        module: The top-level module that could not be imported (``"scipy"``).
        library: Its library's name (``"SciPy"``).
    """

    def __init__(self, module: str, library: str) -> None:
        self.module = module
        self.library = library
        super().__init__(
            f"{library} is not installed (no module {module!r}); it comes with fkcheck's "
            f"{REFERENCE_EXTRA!r} extra: {INSTALL_REFERENCE}"
        )


def missing_extra(exc: ImportError) -> MissingExtraError | None:
    """The :class:`MissingExtraError` that ``exc`` means, or ``None``.

    Args:
        exc: An import that failed.

    Returns:
        The error naming the library and the extra, when ``exc`` is a
        :class:`ModuleNotFoundError` for a module of :data:`REFERENCE_LIBRARIES`
        (or below one); ``None`` for any other import error, which is a bug or a
        broken installation and stays as it is.
    """
    if not isinstance(exc, ModuleNotFoundError) or not exc.name:
        return None
    top = exc.name.partition(".")[0]
    library = REFERENCE_LIBRARIES.get(top)
    return None if library is None else MissingExtraError(top, library)


class Skip(Exception):
    """Base class of the reasons a backend does not apply here (→ status ``skipped``)."""


class BackendUnavailable(Skip):
    """A backend cannot run here: its library (or a package its input names) is missing."""


class FrameUnavailable(Skip):
    """A backend cannot provide a named frame (e.g. a mid-chain frame from a black box)."""


class UnmappedFrameError(Exception):
    """A URDF backend was asked for a frame that has no URDF twin.

    Not a skip: a model that declares a URDF and then never compares it must not
    stay green. The check reports the backend as ``error`` with this message,
    which names the frames to map and the URDF links to map them onto.
    """


def failure_text(exc: BaseException) -> str:
    """A backend's failure as its result (and a one-line error) says it.

    fkcheck's own messages are sentences and are shown as they are; another
    library's exception (or a third party's) keeps its type name, which is often
    all that says what went wrong (``KeyError: 'tool0'``).
    """
    own = isinstance(exc, UnmappedFrameError) or type(exc).__module__.startswith("fkcheck.")
    return str(exc) if own else f"{type(exc).__name__}: {exc}"
