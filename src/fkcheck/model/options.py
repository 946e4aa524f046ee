"""A check's options in one place: defaults, bounds, precedence and validation.

Every way into a check builds one :class:`CheckOptions`: ``fkcheck check``
(its flags over ``[tool.fkcheck]``, and so the GitHub Action, which runs it),
:func:`fkcheck.check` (its arguments) and the pytest plugin
(``[tool.fkcheck]``). :func:`resolve_options` takes each option from the first
layer that gives it — flag or argument > ``[tool.fkcheck]`` > default — and
records where it came from (:attr:`CheckOptions.sources`). An option left
``None`` (the frames, the tolerances, the Jacobian's) is the model's
``[check]``'s: the engine fills it in and says so; ``require`` adds to the
model's.

Every value is checked by one rule, :func:`option_problem`, in one message
form, ``WHERE: must be … (why), got VALUE`` (:class:`~fkcheck.errors.OptionError`;
exit 2 on the command line). ``[tool.fkcheck]`` applies the same rule when it
is read (:mod:`fkcheck.model.project`), and the tolerances' ranges are
:mod:`fkcheck.core.tolerances`'s.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, Literal, TypedDict, get_args

from fkcheck.core.tolerances import LimitKind, limit_problem
from fkcheck.core.typing import JACOBIAN_REFERENCES, JacobianReference
from fkcheck.errors import OptionError, ToleranceError
from fkcheck.model.require import KINDS, Kind
from fkcheck.process.supervise import MAX_TIMEOUT_S

if TYPE_CHECKING:
    from fkcheck.model.types import Model

__all__ = [
    "BAG_FLAGS",
    "BAG_KEYS",
    "DEFAULT_SAMPLER",
    "DEFAULT_SAMPLES",
    "DEFAULT_SEED",
    "DEFAULT_TIMEOUT_S",
    "FLAGS",
    "FLOAT_OPTIONS",
    "MAX_BAG_STAMP_TOLERANCE_S",
    "MAX_PROCESSES",
    "MAX_SAMPLES",
    "MAX_SEED",
    "MAX_TIMEOUT_S",
    "OPTIONS",
    "PROJECT_KEYS",
    "SAMPLERS",
    "CheckOptions",
    "OptionArgs",
    "OptionLayer",
    "OptionName",
    "Sampler",
    "bag_problem",
    "check_option",
    "jacobian_for",
    "option_problem",
    "resolve_options",
]

Sampler = Literal["sobol", "uniform"]
#: The samplers, in the order messages list them.
SAMPLERS: tuple[Sampler, ...] = get_args(Sampler)

#: Random samples a check draws when nobody says (on top of the structured ones).
DEFAULT_SAMPLES = 1000
#: Seed of the random samples when nobody says.
DEFAULT_SEED = 0
#: Sampler when nobody says.
DEFAULT_SAMPLER: Sampler = "sobol"
#: Time limit per backend when nobody says, seconds: well below a CI job's hour.
#: Not enough for every backend at a million samples (yourdfpy computes about
#: 3,000 UR5 poses a second): the plan (:mod:`fkcheck.engine.plan`) then gives
#: such a backend a stated subset, unless ``full`` asks for every configuration.
DEFAULT_TIMEOUT_S = 120.0
#: Most random samples one check draws: ten million configurations are 0.5 GB of
#: joint values alone for six joints; more is a typo, not a check.
MAX_SAMPLES = 10_000_000
#: Most processes one isolated backend may split its configurations over.
MAX_PROCESSES = 1024
#: Largest seed: NumPy's ``SeedSequence`` takes any non-negative integer; seeds
#: are 64-bit numbers (0 … 2^64 − 1) everywhere fkcheck takes one.
MAX_SEED = 2**64 - 1

OptionName = Literal[
    "samples", "seed", "sampler", "timeout_s", "frame_from", "frame_to", "tol_pos_m",
    "tol_rot_rad", "require", "jacobian", "jacobian_reference", "tol_jacobian", "full",
    "processes",
]  # fmt: skip
#: Every option of a check, in the order :class:`CheckOptions` holds them.
OPTIONS: tuple[OptionName, ...] = get_args(OptionName)

#: The ``fkcheck check`` flag of each option (the Action passes the same flags).
FLAGS: Mapping[OptionName, str] = MappingProxyType(
    {
        "samples": "--samples",
        "seed": "--seed",
        "sampler": "--sampler",
        "timeout_s": "--timeout",
        "frame_from": "--from",
        "frame_to": "--to",
        "tol_pos_m": "--tol-pos",
        "tol_rot_rad": "--tol-rot",
        "require": "--require",
        "jacobian": "--jacobian",
        "jacobian_reference": "--jacobian-reference",
        "tol_jacobian": "--tol-jacobian",
        "full": "--full",
        "processes": "--processes",
    }
)

#: The ``[tool.fkcheck]`` key of each option it may set (not the frames: they are per model).
PROJECT_KEYS: Mapping[OptionName, str] = MappingProxyType(
    {
        "samples": "samples",
        "seed": "seed",
        "sampler": "sampler",
        "timeout_s": "timeout",
        "tol_pos_m": "tol_pos_m",
        "tol_rot_rad": "tol_rot_rad",
        "require": "require",
        "jacobian": "jacobian",
        "jacobian_reference": "jacobian_reference",
        "tol_jacobian": "tol_jacobian",
        "full": "full",
        "processes": "processes",
    }
)

_TOLERANCES: Mapping[str, LimitKind] = MappingProxyType(
    {"tol_pos_m": "tol_pos", "tol_rot_rad": "tol_rot", "tol_jacobian": "tol_jacobian"}
)
#: Integer options: (lowest, highest, the highest as printed, why it ends there).
_INTEGERS: Mapping[str, tuple[int, int, str, str]] = MappingProxyType(
    {
        "samples": (0, MAX_SAMPLES, f"{MAX_SAMPLES:_}", "more is a typo, not a check"),
        "seed": (0, MAX_SEED, "2**64 - 1", "a 64-bit seed"),
        "processes": (1, MAX_PROCESSES, str(MAX_PROCESSES), "more than any machine's cores"),
    }
)
#: Options in seconds or tolerances: an integer given (``timeout = 60``) is read as a float.
FLOAT_OPTIONS: frozenset[OptionName] = frozenset(
    {"timeout_s", "tol_pos_m", "tol_rot_rad", "tol_jacobian"}
)
_TIMEOUT_WHY = "a day: longer than any CI job runs"


def _shown(value: object) -> str:
    """A value as a message prints it: numbers as numbers, anything else as its short repr."""
    if isinstance(value, float):
        return f"{value:g}"
    if isinstance(value, int) and not isinstance(value, bool):
        return str(value)
    text = repr(value)
    return text if len(text) <= 40 else text[:39] + "…"


def _choice(value: object, choices: tuple[str, ...], what: str) -> str | None:
    if isinstance(value, str) and value in choices:
        return None
    return f"{_shown(value)} unknown; {what} are: {', '.join(choices)}"


def _timeout_problem(value: object) -> str | None:
    """Why ``value`` is no time limit: a number of seconds, > 0 and at most a day."""
    number = (
        float(value)
        if isinstance(value, int | float) and not isinstance(value, bool) and abs(value) < 1e308
        else math.nan
    )
    if 0.0 < number <= MAX_TIMEOUT_S:
        return None
    return f"must be > 0 and at most {MAX_TIMEOUT_S:g} s ({_TIMEOUT_WHY}), got {_shown(value)}"


#: The settings of a ROS 2 bag read as measured poses (``--against poses:BAG``), by the
#: :class:`~fkcheck.backends.registry.BackendOptions` attribute each sets: its
#: ``fkcheck check`` flag ...
BAG_FLAGS: Mapping[str, str] = MappingProxyType(
    {
        "bag_joint_states": "--bag-joint-states",
        "bag_tf": "--bag-tf",
        "bag_tf_static": "--bag-tf-static",
        "bag_stamp_tolerance_s": "--bag-stamp-tolerance",
    }
)
#: ... and its ``[tool.fkcheck]`` key (a flag wins over the key).
BAG_KEYS: Mapping[str, str] = MappingProxyType(
    {
        "bag_joint_states": "bag_joint_states",
        "bag_tf": "bag_tf",
        "bag_tf_static": "bag_tf_static",
        "bag_stamp_tolerance_s": "bag_stamp_tolerance",
    }
)
#: Largest stamp tolerance of a bag (seconds): a larger one pairs poses with readings
#: of other cycles whenever one is missing.
MAX_BAG_STAMP_TOLERANCE_S = 1.0
#: Longest topic name of a bag setting (characters); ROS's are a few dozen.
_MAX_TOPIC_CHARS = 256


def bag_problem(name: str, value: object) -> str | None:
    """Why ``value`` cannot be the bag setting ``name`` (:data:`BAG_FLAGS`), one phrase.

    The one rule of the flags and the ``[tool.fkcheck]`` keys: a topic is a
    non-empty name of at most 256 characters of UTF-8 text, without spaces or
    control characters; the stamp tolerance a number of seconds from 0 to
    :data:`MAX_BAG_STAMP_TOLERANCE_S`. ``None`` when it can.
    """
    if name == "bag_stamp_tolerance_s":
        number = (
            float(value)
            if isinstance(value, int | float) and not isinstance(value, bool)
            else math.nan
        )
        if 0.0 <= number <= MAX_BAG_STAMP_TOLERANCE_S:
            return None
        return (
            f"must be seconds from 0 to {MAX_BAG_STAMP_TOLERANCE_S:g} (a larger lag pairs "
            f"poses with other cycles' readings), got {_shown(value)}"
        )
    if (
        isinstance(value, str)
        and 0 < len(value) <= _MAX_TOPIC_CHARS
        and all(c.isprintable() and not c.isspace() for c in value)
        and not any("\ud800" <= c <= "\udfff" for c in value)
    ):
        return None
    return (
        f"must be a topic name (at most {_MAX_TOPIC_CHARS} characters of text, no spaces), "
        f"got {_shown(value)}"
    )


def option_problem(name: OptionName, value: object, *, lowest: int | None = None) -> str | None:
    """Why ``value`` cannot be option ``name``, one phrase; ``None`` when it can.

    The phrase names the range and the value, in one form for every option:
    ``must be an integer from 0 to 2**64 - 1 (a 64-bit seed), got -1``,
    ``must be > 0 and at most 86400 s (…), got 0``. ``lowest`` raises an
    integer option's lowest value (``diagnose`` wants a sample at least).
    """
    if name in _TOLERANCES:
        return limit_problem(value, _TOLERANCES[name])
    if name in _INTEGERS:
        low, high, shown_high, why = _INTEGERS[name]
        low = low if lowest is None else lowest
        if isinstance(value, int) and not isinstance(value, bool) and low <= value <= high:
            return None
        return f"must be an integer from {low} to {shown_high} ({why}), got {_shown(value)}"
    if name == "timeout_s":
        return _timeout_problem(value)
    if name == "sampler":
        return _choice(value, SAMPLERS, "samplers")
    if name == "jacobian_reference":
        return _choice(value, JACOBIAN_REFERENCES, "references")
    if name == "require":
        bad = [k for k in value if k not in KINDS] if isinstance(value, tuple) else [value]
        return f"must be among {', '.join(KINDS)}, got {_shown(bad[0])}" if bad else None
    if name in ("jacobian", "full"):
        return None if isinstance(value, bool) else f"must be true or false, got {_shown(value)}"
    # frame_from, frame_to: names the model resolves (FrameError lists its frames)
    return None if isinstance(value, str) else f"must be a frame name, got {_shown(value)}"


def check_option(name: OptionName, value: Any, where: str, *, lowest: int | None = None) -> Any:
    """``value`` when it is a valid option ``name`` (:func:`option_problem`).

    Raises:
        OptionError: It is not (a :class:`~fkcheck.errors.ToleranceError` for a
            tolerance); the message is ``where: problem``.
    """
    problem = option_problem(name, value, lowest=lowest)
    if problem is not None:
        raise (ToleranceError if name in _TOLERANCES else OptionError)(where, problem)
    return value


@dataclass(frozen=True)
class CheckOptions:
    """Everything a check is asked to do besides its model and backends; valid by construction.

    Attributes:
        samples: Random samples, on top of named poses, zero, mid-range and limit corners.
        seed: Seed of the random samples.
        sampler: ``sobol`` or ``uniform``.
        timeout_s: Time limit per backend, seconds: the engine's wait and every
            ``cmd:`` program's and plugin's own limit.
        frame_from: Frame the compared pose is in (``None``: the model's ``[check]``).
        frame_to: Frame whose pose is compared (``None``: the model's ``[check]``).
        tol_pos_m: Position tolerance, metres (``None``: the model's ``[check]``).
        tol_rot_rad: Rotation tolerance, radians (``None``: the model's ``[check]``).
        require: Kinds of evidence that must be verified, on top of the model's.
        jacobian: Also compare Jacobians (``None``: the model's ``[check] jacobian``).
        jacobian_reference: Their reference frame (``None``: the model's ``[check]``).
        tol_jacobian: Their tolerance (``None``: the model's ``[check]``).
        full: Every backend compares every configuration, however long it takes
            (the time limit still applies); by default a backend whose declared
            cost cannot fit its limit compares a stated subset
            (:mod:`fkcheck.engine.plan`).
        processes: Most processes an isolated backend (a slow pure-Python one)
            splits its configurations over (``None``: one per usable core, its
            CPU quota included); 1 keeps each in one process, for a CI runner
            shared with other jobs. It changes the time a check takes, never its result.
        sources: Where each option given came from (``--seed``, ``[tool.fkcheck]
            seed in …/pyproject.toml``); absent: a default, or the caller's argument.

    Raises:
        OptionError: A value out of its range, named by its source (else its name).
    """

    samples: int = DEFAULT_SAMPLES
    seed: int = DEFAULT_SEED
    sampler: Sampler = DEFAULT_SAMPLER
    timeout_s: float = DEFAULT_TIMEOUT_S
    frame_from: str | None = None
    frame_to: str | None = None
    tol_pos_m: float | None = None
    tol_rot_rad: float | None = None
    require: tuple[Kind, ...] = ()
    jacobian: bool | None = None
    jacobian_reference: JacobianReference | None = None
    tol_jacobian: float | None = None
    full: bool = False
    processes: int | None = None
    sources: Mapping[str, str] = field(default_factory=dict, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "sources", MappingProxyType(dict(self.sources)))
        for name in OPTIONS:
            value = getattr(self, name)
            if value is not None:
                check_option(name, value, self.sources.get(name) or name)

    @property
    def tolerance_source(self) -> tuple[str, str]:
        """Where the position and the rotation tolerance came from (``""``: the caller)."""
        return (self.sources.get("tol_pos_m", ""), self.sources.get("tol_rot_rad", ""))


class OptionArgs(TypedDict, total=False):
    """The options as keyword arguments (:func:`fkcheck.check`): see :class:`CheckOptions`.

    ``None`` (or an empty ``require``) is an argument not given.
    """

    samples: int | None
    seed: int | None
    sampler: Sampler | None
    timeout_s: float | None
    frame_from: str | None
    frame_to: str | None
    tol_pos_m: float | None
    tol_rot_rad: float | None
    require: Sequence[Kind]
    jacobian: bool | None
    jacobian_reference: JacobianReference | None
    tol_jacobian: float | None
    full: bool | None
    processes: int | None


@dataclass(frozen=True)
class OptionLayer:
    """The options one layer below the caller's gives (``[tool.fkcheck]``), each checked.

    :mod:`fkcheck.model.project` reads one from a ``pyproject.toml``;
    :func:`resolve_options` puts the caller's values over it.

    Attributes:
        values: Each option the layer sets, by name (one it leaves out is not given).
        sources: Where each came from, in words (``[tool.fkcheck] seed in …/pyproject.toml``).
    """

    values: Mapping[OptionName, Any] = field(default_factory=dict)
    sources: Mapping[OptionName, str] = field(default_factory=dict)

    def __post_init__(self) -> None:
        object.__setattr__(self, "values", MappingProxyType(dict(self.values)))
        object.__setattr__(self, "sources", MappingProxyType(dict(self.sources)))

    def get(self, name: OptionName) -> Any:
        """The value the layer gives option ``name``, or ``None``."""
        return self.values.get(name)


def resolve_options(
    given: Mapping[str, Any] | None = None,
    *,
    labels: Mapping[OptionName, str] | None = None,
    project: OptionLayer | None = None,
    base: CheckOptions | None = None,
) -> CheckOptions:
    """Each option from the first layer that gives it: ``given`` > ``project`` > default.

    Args:
        given: Values from the command line or a caller's arguments, by option
            name; ``None``, an empty ``require`` or absent is not given.
        labels: How ``given`` values are named in sources and messages
            (:data:`FLAGS` for the command line); without, they are the caller's
            and a bad one is named by its argument.
        project: ``[tool.fkcheck]``'s options (:attr:`ProjectConfig.options
            <fkcheck.model.project.ProjectConfig.options>`), named by key and file.
        base: Options already resolved (by the command line, the pytest
            plugin), in place of ``project`` and the defaults.

    Raises:
        OptionError: A given value out of its range, named by its flag or argument.
    """
    values: dict[str, Any] = {}
    sources: dict[str, str] = {}
    for name in OPTIONS:
        value = (given or {}).get(name)
        if value is not None and value != ():
            values[name] = tuple(value) if name == "require" else value
            if labels is not None:
                sources[name] = labels[name]
            continue
        if base is not None:
            values[name] = getattr(base, name)
            if name in base.sources:
                sources[name] = base.sources[name]
            continue
        value = project.get(name) if project is not None else None
        if value is not None and value != ():
            values[name] = tuple(value) if name == "require" else value
            if project is not None and name in project.sources:
                sources[name] = project.sources[name]
    return CheckOptions(**values, sources=sources)


def jacobian_for(options: CheckOptions, model: Model) -> tuple[JacobianReference, float] | None:
    """The Jacobian comparison asked for: ``(reference, tolerance)``, or ``None`` for none.

    The model's ``[check]`` gives what ``options`` leave ``None`` (the last layer
    of the precedence, as the engine does for the frames and pose tolerances).
    """
    wanted = model.check.jacobian if options.jacobian is None else options.jacobian
    if not wanted:
        return None
    reference = options.jacobian_reference or model.check.jacobian_reference
    tol = model.check.tol_jacobian if options.tol_jacobian is None else options.tol_jacobian
    return reference, tol
