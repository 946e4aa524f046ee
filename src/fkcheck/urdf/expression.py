"""fkcheck's own evaluator of xacro expressions: plain data in, plain data out, nothing else.

xacro evaluates ``${…}`` and ``$(eval …)`` with Python's ``eval``, and no
check on a Python expression makes ``eval`` safe: a generator's frame, a
format string or a builtin's attributes lead back to everything. fkcheck never
runs an expression as Python. :func:`evaluate` parses it with :func:`ast.parse`
(which builds a tree and runs nothing) and walks a whitelist of node types
itself:

* constants: numbers, strings, ``True``/``False``/``None``;
* names: what the caller resolves (xacro properties and arguments) and the
  functions and constants of :func:`standard_names`;
* arithmetic, comparisons (``in`` and ``is`` included), ``and``/``or``/``not``,
  ``x if c else y``;
* list, tuple and dict literals, indexing and slicing;
* calls of the functions of the name tables (and of :data:`STRING_METHODS`
  and :data:`MAPPING_METHODS` on a string or a mapping), with positional and
  keyword arguments;
* ``a.b`` only where it is not attribute access: a namespace's member
  (``math.pi``, ``python.len``, ``xacro.load_yaml``, an included file's ``ns``)
  or a key of a mapping (``cfg.arm.reach``, as xacro's yaml mappings allow).

Everything else is refused with one line, whatever it is named: attribute
access on a value (so no ``__class__``, ``gi_frame``, ``format``), lambdas,
comprehensions and generators, f-strings, ``%`` formatting of strings,
``*``/``**`` unpacking, ``:=``, sets, bytes. Every value the walk handles is
plain data — ``bool``, ``int``, ``float``, ``complex``, ``str``, ``None`` and
``list``, ``tuple``, ``dict`` of them, exact types — and the only operations
applied to values are Python's own operators on those types and the fixed
functions of the tables, so there is no object through which to reach a
class, a frame, a module or a builtin.

Sizes are bounded, so one expression can take neither long nor much memory:
a string has at most :data:`MAX_TEXT_CHARS` characters, a value at most
:data:`MAX_ITEMS` items in all its lists, tuples and mappings, an integer at
most :data:`MAX_INT_BITS` bits; a repetition, power, shift or concatenation
that would be larger is refused before it is computed.
"""

from __future__ import annotations

import ast
import functools
import math
import operator
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

from fkcheck.urdf.screen import MAX_URDF_BYTES

__all__ = [
    "MAPPING_METHODS",
    "MAX_EXPRESSION_CHARS",
    "MAX_INT_BITS",
    "MAX_ITEMS",
    "MAX_TEXT_CHARS",
    "STRING_METHODS",
    "ExpressionError",
    "Function",
    "Namespace",
    "Unavailable",
    "Value",
    "evaluate",
    "is_plain",
    "namespace",
    "plain",
    "standard_names",
]

#: A value of an expression: plain data (:func:`is_plain`), which the walk checks at run
#: time, hence ``Any`` for the type checker.
Value = Any

#: The longest expression evaluated, characters.
MAX_EXPRESSION_CHARS = 100_000
#: The longest string a value may be (a URDF's own limit).
MAX_TEXT_CHARS = MAX_URDF_BYTES
#: The most items (elements, keys and values) one value may hold, nested ones included.
MAX_ITEMS = 100_000
#: The largest integer, bits (a float reaches 2**1024).
MAX_INT_BITS = 4096
#: The longest string ``int()`` or ``float()`` converts (no number needs more digits).
_MAX_NUMBER_CHARS = 10_000
#: The most digits ``round(x, n)`` rounds to.
_MAX_ROUND_DIGITS = 1_000
#: The longest message quoted from an error.
_MESSAGE_CHARS = 300

_SCALARS: frozenset[type] = frozenset({bool, int, float, complex, str, type(None)})
_CONTAINERS: frozenset[type] = frozenset({list, tuple, dict})
_INTEGERS: frozenset[type] = frozenset({bool, int})
_NUMBERS: frozenset[type] = frozenset({bool, int, float, complex})


class ExpressionError(Exception):
    """An expression refused or failing; ``str()`` is one line (without the expression)."""


@dataclass(frozen=True)
class Function:
    """A function an expression may call (never a value: it can only be called).

    Attributes:
        name: How messages name it.
        call: What a call runs; it gets plain data and must return plain data.
    """

    name: str
    call: Callable[..., object]


@dataclass(frozen=True)
class Namespace:
    """A name whose members are reached with ``name.member`` (never a value).

    Attributes:
        name: How messages name it.
        member: The member of that name; ``KeyError`` when there is none.
    """

    name: str
    member: Callable[[str], object]


@dataclass(frozen=True)
class Unavailable:
    """A name xacro has that fkcheck does not evaluate: using it is refused with ``reason``."""

    name: str
    reason: str


def namespace(name: str, members: Mapping[str, object]) -> Namespace:
    """A :class:`Namespace` of fixed members."""
    return Namespace(name, members.__getitem__)


def _a(name: str) -> str:
    """``name`` with its indefinite article: ``an int``, ``a str``."""
    return f"an {name}" if name[:1] in "aeiou" else f"a {name}"


def _one_line(text: str) -> str:
    flat = " ".join(text.split())
    return flat if len(flat) <= _MESSAGE_CHARS else flat[:_MESSAGE_CHARS] + "…"


# --------------------------------------------------------------------------- sizes


def _too_large(what: str) -> ExpressionError:
    return ExpressionError(f"{what} (the limit of a xacro value)")


def _check_int(value: int) -> int:
    if value.bit_length() > MAX_INT_BITS:
        raise _too_large(f"an integer of more than {MAX_INT_BITS} bits")
    return value


def _check_text(length: int) -> None:
    if length > MAX_TEXT_CHARS:
        raise _too_large(f"a string longer than {MAX_TEXT_CHARS} characters")


def _check_items(count: int) -> None:
    if count > MAX_ITEMS:
        raise _too_large(f"more than {MAX_ITEMS} items")


def _checked(value: Value) -> Value:
    """``value`` if it is plain data within the size limits, else :class:`ExpressionError`.

    Walks containers without recursion; stops as soon as a limit is passed, so a
    value that shares one big part many times costs no more than the limits.
    """
    items = chars = 0
    todo = [value]
    while todo:
        item = todo.pop()
        kind = type(item)
        if kind is str:
            chars += len(item)
            _check_text(chars)
        elif kind is int:
            _check_int(item)
        elif kind in _CONTAINERS:
            parts = [*item.keys(), *item.values()] if kind is dict else item
            for part in parts:
                items += 1
                _check_items(items)
                todo.append(part)
        elif kind not in _SCALARS:
            raise ExpressionError(f"{_a(kind.__name__)} is not a value a xacro expression has")
    return value


def is_plain(value: Value) -> bool:
    """Whether ``value`` is plain data (exact types, any depth) within the size limits."""
    try:
        _checked(value)
    except ExpressionError:
        return False
    return True


def plain(value: object) -> Value:
    """A copy of ``value`` as plain data: mappings, sequences and scalars, exact types.

    For data read from elsewhere (a yaml file): ``dict``/``list``/``tuple``
    subclasses become the plain types; shared parts are copied, so aliases that
    repeat a part are counted, and a self-referencing structure ends at the limit.

    Raises:
        ExpressionError: Something else than numbers, strings, booleans, null,
            lists and mappings (a date, bytes, a set), or beyond the size limits.
    """
    budget = [0, 0]  # items, characters

    def copy(item: Any, depth: int) -> Value:
        if depth > 200:
            raise _too_large("nested more than 200 levels")
        kind = type(item)
        if kind is str:
            budget[1] += len(item)
            _check_text(budget[1])
            return item
        if kind is int:
            return _check_int(item)
        if kind in _SCALARS:
            return item
        if isinstance(item, dict):
            out: dict[Value, Value] = {}
            for key, part in item.items():
                budget[0] += 2
                _check_items(budget[0])
                out[copy(key, depth + 1)] = copy(part, depth + 1)
            return out
        if isinstance(item, list | tuple):
            parts: list[Value] = []
            for part in item:
                budget[0] += 1
                _check_items(budget[0])
                parts.append(copy(part, depth + 1))
            return parts if isinstance(item, list) else tuple(parts)
        raise ExpressionError(
            f"{_a(kind.__name__)} is not plain data (numbers, strings, booleans, null, "
            "lists and mappings)"
        )

    return copy(value, 0)


# --------------------------------------------------------------------------- functions


def _sized(value: Value) -> int:
    """The number of items converting ``value`` to a list gives, checked against the limit."""
    if type(value) not in (str, list, tuple, dict):
        raise ExpressionError(f"{_a(type(value).__name__)} is not a sequence or mapping")
    count = len(value)
    _check_items(count)
    return count


def _list(value: Value = ()) -> Value:
    _sized(value)
    return list(value)


def _tuple(value: Value = ()) -> Value:
    _sized(value)
    return tuple(value)


def _sorted(value: Value, *, reverse: Value = False) -> Value:
    _sized(value)
    return sorted(value, reverse=bool(reverse))


def _reversed(value: Value) -> Value:
    _sized(value)
    return list(reversed(value))


def _enumerate(value: Value, start: Value = 0) -> Value:
    _sized(value)
    return list(enumerate(value, start))


def _zip(*values: Value) -> Value:
    for value in values:
        _sized(value)
    return list(zip(*values, strict=False))


def _dict(*args: Value, **kwargs: Value) -> Value:
    for value in args:
        _sized(value)
    return dict(*args, **kwargs)


def _range(*args: Value) -> Value:
    numbers = range(*args)
    _check_items(len(numbers))
    return list(numbers)


def _sum(value: Value, start: Value = 0) -> Value:
    _sized(value)
    items = [start, *value]
    for item in items:
        if type(item) not in _NUMBERS:
            raise ExpressionError(f"sum() adds numbers, not {_a(type(item).__name__)}")
    total = start
    for item in items[1:]:
        total = _checked(total + item)
    return total


def _number_text(value: Value) -> None:
    if type(value) is str and len(value) > _MAX_NUMBER_CHARS:
        raise ExpressionError(f"a number of more than {_MAX_NUMBER_CHARS} characters")


def _int(*args: Value) -> Value:
    if args:
        _number_text(args[0])
    return int(*args)


def _float(value: Value = 0.0) -> Value:
    _number_text(value)
    return float(value)


def _round(value: Value, ndigits: Value = None) -> Value:
    if ndigits is None:
        return round(value)
    if type(ndigits) not in _INTEGERS or abs(ndigits) > _MAX_ROUND_DIGITS:
        raise ExpressionError(f"round() to more than {_MAX_ROUND_DIGITS} digits")
    return round(value, ndigits)


def _need_str(*values: Value) -> None:
    for value in values:
        if type(value) is not str:
            raise ExpressionError(f"expected a string, got {_a(type(value).__name__)}")


def _split(
    method: Callable[..., list[str]], text: str, sep: Value = None, maxsplit: Value = -1
) -> Value:
    if sep is not None:
        _need_str(sep)
    if type(maxsplit) not in _INTEGERS:
        raise ExpressionError("maxsplit must be an integer")
    limit = MAX_ITEMS if maxsplit < 0 or maxsplit > MAX_ITEMS else maxsplit
    parts = method(text, sep, limit)
    _check_items(len(parts))
    return parts


def _replace(text: str, old: Value, new: Value, count: Value = -1) -> Value:
    _need_str(old, new)
    if type(count) not in _INTEGERS:
        raise ExpressionError("count must be an integer")
    found = text.count(old) if old else len(text) + 1
    if count >= 0:
        found = min(found, count)
    _check_text(len(text) + found * (len(new) - len(old)))
    return text.replace(old, new, count)


def _join(sep: str, value: Value) -> Value:
    _sized(value)
    parts = list(value)
    _need_str(*parts)
    _check_text(sum(map(len, parts)) + len(sep) * max(len(parts) - 1, 0))
    return sep.join(parts)


_STR_METHODS: dict[str, Callable[..., Value]] = {
    "lower": str.lower, "upper": str.upper, "strip": str.strip, "lstrip": str.lstrip,
    "rstrip": str.rstrip, "startswith": str.startswith, "endswith": str.endswith,
    "find": str.find, "count": str.count,
}  # fmt: skip


def _str_method(name: str) -> Callable[..., Value]:
    method = _STR_METHODS[name]

    def call(text: str, *args: Value) -> Value:
        for arg in args:
            if type(arg) not in (str, int, bool, tuple, type(None)):
                raise ExpressionError(f"str.{name}() takes strings and integers")
        return method(text, *args)

    return call


#: The string methods an expression may call: ``'a b'.split()``, ``name.lower()`` …
STRING_METHODS: Mapping[str, Callable[..., Value]] = {
    **{name: _str_method(name) for name in _STR_METHODS},
    "split": functools.partial(_split, str.split),
    "rsplit": functools.partial(_split, str.rsplit),
    "replace": _replace,
    "join": _join,
}

#: The mapping methods an expression may call (``keys``, ``values``, ``items`` give lists).
MAPPING_METHODS: Mapping[str, Callable[..., Value]] = {
    "get": lambda mapping, key, default=None: mapping.get(key, default),
    "keys": lambda mapping: list(mapping.keys()),
    "values": lambda mapping: list(mapping.values()),
    "items": lambda mapping: list(mapping.items()),
}

#: math's functions an expression may call (factorial, comb, perm, prod and lcm
#: are left out: their results outgrow any bound before they can be checked).
_MATH_FUNCTIONS = (
    "acos", "acosh", "asin", "asinh", "atan", "atan2", "atanh", "cbrt", "ceil", "copysign",
    "cos", "cosh", "degrees", "dist", "erf", "erfc", "exp", "exp2", "expm1", "fabs", "floor",
    "fmod", "frexp", "fsum", "gamma", "gcd", "hypot", "isclose", "isfinite", "isinf", "isnan",
    "isqrt", "ldexp", "lgamma", "log", "log10", "log1p", "log2", "modf", "nextafter", "pow",
    "radians", "remainder", "sin", "sinh", "sqrt", "tan", "tanh", "trunc", "ulp",
)  # fmt: skip
_MATH_LEFT_OUT = ("factorial", "comb", "perm", "prod", "lcm")
_MATH_CONSTANTS = {"pi": math.pi, "e": math.e, "tau": math.tau, "inf": math.inf, "nan": math.nan}

#: Python's builtins an expression may call (xacro's list, less those taking functions
#: or returning classes and other objects).
_BUILTINS: dict[str, Callable[..., Value]] = {
    "abs": abs, "all": all, "any": any, "bool": bool, "dict": _dict, "divmod": divmod,
    "enumerate": _enumerate, "float": _float, "int": _int, "len": len, "list": _list,
    "max": max, "min": min, "ord": ord, "range": _range, "repr": repr, "reversed": _reversed,
    "round": _round, "sorted": _sorted, "str": str, "sum": _sum, "tuple": _tuple, "zip": _zip,
}  # fmt: skip
#: xacro's builtins fkcheck leaves out, and why.
_BUILTINS_LEFT_OUT = {
    "map": "it takes a function", "filter": "it takes a function",
    "type": "it gives Python classes", "isinstance": "it takes Python classes",
    "issubclass": "it takes Python classes", "vars": "it gives an object's namespace",
    "hash": "it differs from run to run", "slice": "use a[i:j]", "set": "sets are not plain data",
    "frozenset": "sets are not plain data", "complex": "use j, as in 1j",
}  # fmt: skip
#: The builtins xacro puts directly among the names (the rest are in ``python.``).
_DIRECT_BUILTINS = (
    "list", "dict", "len", "str", "float", "int", "bool", "min", "max", "round", "sorted", "range",
)  # fmt: skip


def _unavailable(name: str, why: str) -> Unavailable:
    return Unavailable(name, f"{name} is not available in fkcheck's xacro expressions ({why})")


def standard_names() -> dict[str, object]:
    """The names every xacro expression has, as xacro defines them (fkcheck's subset).

    math's functions and constants, directly and as ``math.NAME``; xacro's direct
    builtins (``list``, ``dict``, ``len``, ``str``, ``float``, ``int``, ``bool``,
    ``min``, ``max``, ``round``, ``sorted``, ``range``) and ``python.NAME`` for
    those and ``abs``, ``all``, ``any``, ``divmod``, ``enumerate``, ``ord``,
    ``repr``, ``reversed``, ``sum``, ``tuple``, ``zip``; ``True`` and ``False``.
    xacro's ``map``, ``python.type`` and the like are :class:`Unavailable`.
    The ``xacro.`` namespace (``load_yaml``, ``arg`` …) is the caller's.
    """
    maths: dict[str, object] = {n: Function(n, getattr(math, n)) for n in _MATH_FUNCTIONS}
    maths.update(_MATH_CONSTANTS)
    for name in _MATH_LEFT_OUT:
        maths[name] = _unavailable(name, "its result outgrows any bound")
    python: dict[str, object] = {n: Function(n, fn) for n, fn in _BUILTINS.items()}
    python.update({n: _unavailable(n, why) for n, why in _BUILTINS_LEFT_OUT.items()})
    python.update({"True": True, "False": False})
    names: dict[str, object] = dict(maths)
    names.update({n: python[n] for n in _DIRECT_BUILTINS})
    names["map"] = python["map"]
    names.update({"True": True, "False": False})
    names["math"] = namespace("math", maths)
    names["python"] = namespace("python", python)
    return names


# --------------------------------------------------------------------------- evaluation

_UNARY: dict[type[ast.unaryop], Callable[[Value], Value]] = {
    ast.UAdd: operator.pos, ast.USub: operator.neg, ast.Not: operator.not_,
    ast.Invert: operator.invert,
}  # fmt: skip
_BINARY: dict[type[ast.operator], Callable[[Value, Value], Value]] = {
    ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul,
    ast.Div: operator.truediv, ast.FloorDiv: operator.floordiv, ast.Mod: operator.mod,
    ast.Pow: operator.pow, ast.LShift: operator.lshift, ast.RShift: operator.rshift,
    ast.BitOr: operator.or_, ast.BitXor: operator.xor, ast.BitAnd: operator.and_,
}  # fmt: skip
_COMPARE: dict[type[ast.cmpop], Callable[[Value, Value], Value]] = {
    ast.Eq: operator.eq, ast.NotEq: operator.ne, ast.Lt: operator.lt, ast.LtE: operator.le,
    ast.Gt: operator.gt, ast.GtE: operator.ge, ast.Is: operator.is_,
    ast.IsNot: operator.is_not, ast.In: lambda a, b: a in b, ast.NotIn: lambda a, b: a not in b,
}  # fmt: skip

#: What refusals call the constructs outside the whitelist.
_CONSTRUCTS: dict[type[ast.AST], str] = {
    ast.Lambda: "a lambda", ast.ListComp: "a comprehension", ast.SetComp: "a comprehension",
    ast.DictComp: "a comprehension", ast.GeneratorExp: "a generator expression",
    ast.JoinedStr: "an f-string", ast.FormattedValue: "an f-string",
    ast.NamedExpr: "an assignment (:=)", ast.Starred: "'*' unpacking", ast.Set: "a set",
    ast.Await: "await", ast.Yield: "yield", ast.YieldFrom: "yield",
    ast.MatMult: "the operator @",
}  # fmt: skip


def _refused(node: ast.AST) -> ExpressionError:
    what = _CONSTRUCTS.get(type(node), type(node).__name__)
    return ExpressionError(f"{what} is not allowed in a xacro expression")


def _repeat_size(seq: Value, times: Value) -> None:
    """Refuse ``seq * times`` before it is built when it would be too large."""
    if type(times) not in _INTEGERS or type(seq) not in (str, list, tuple):
        return
    size = len(seq) * max(times, 0)
    if type(seq) is str:
        _check_text(size)
    else:
        _check_items(size)


def _precheck(op: type[ast.operator], left: Value, right: Value) -> None:
    """Refuse what cannot be computed safely, before computing it."""
    kinds = (type(left), type(right))
    if op is ast.Mod and kinds[0] is str:
        raise ExpressionError("string formatting with % is not allowed in a xacro expression")
    if op is ast.Mult:
        _repeat_size(left, right)
        _repeat_size(right, left)
    elif op is ast.Add and kinds[0] is kinds[1] and kinds[0] in (str, list, tuple):
        size = len(left) + len(right)
        if kinds[0] is str:
            _check_text(size)
        else:
            _check_items(size)
    elif kinds[0] in _INTEGERS and kinds[1] in _INTEGERS:
        base, exponent = int(left), int(right)
        if op is ast.Pow and exponent > 0 and abs(base) > 1:
            if exponent * (abs(base).bit_length() - 1) > MAX_INT_BITS:
                raise _too_large(f"an integer of more than {MAX_INT_BITS} bits")
        elif op is ast.LShift and exponent > MAX_INT_BITS and base != 0:
            raise _too_large(f"an integer of more than {MAX_INT_BITS} bits")


class _Walk:
    """One evaluation: the tree walked over the whitelist, names from ``resolve``."""

    def __init__(self, resolve: Callable[[str], object]) -> None:
        self.resolve = resolve

    def value(self, node: ast.AST) -> Value:
        """A node's value, which must be plain data (not a function or namespace)."""
        found = self.term(node)
        if isinstance(found, Function):
            raise ExpressionError(f"{found.name} is a function: call it, as {found.name}(…)")
        if isinstance(found, Namespace):
            raise ExpressionError(f"{found.name} is a namespace, not a value")
        return found

    def term(self, node: ast.AST) -> Value:
        """A node's value, a function or a namespace."""
        handler = _HANDLERS.get(type(node))
        if handler is None:
            raise _refused(node)
        return handler(self, node)

    def member(self, found: Any, name: str, calling: bool) -> Any:
        """``found.name``: a namespace's member, a mapping's key or method, a string method."""
        if isinstance(found, Namespace):
            try:
                return _bound(found.member(name), f"{found.name}.{name}")
            except KeyError:
                raise ExpressionError(f"{found.name}.{name} is not defined") from None
        kind = type(found)
        if calling and kind is str and name in STRING_METHODS:
            return Function(f"str.{name}", functools.partial(STRING_METHODS[name], found))
        if kind is dict:
            if calling and name in MAPPING_METHODS:
                return Function(name, functools.partial(MAPPING_METHODS[name], found))
            if name in found:
                return found[name]
            if calling:
                raise ExpressionError(
                    f"mapping method .{name}() is not allowed in a xacro expression "
                    f"(only {', '.join(MAPPING_METHODS)})"
                )
            raise ExpressionError(f"the mapping has no key {name!r}")
        if kind is str and calling:
            raise ExpressionError(
                f"string method .{name}() is not allowed in a xacro expression "
                f"(only {', '.join(STRING_METHODS)})"
            )
        what = f"{found.name} (a function)" if kind is Function else _a(kind.__name__)
        raise ExpressionError(
            f"attribute .{name} of {what} is not allowed in a xacro expression "
            "(a.b is a namespace member, a yaml key or one of a few string methods)"
        )

    def constant(self, node: ast.Constant) -> object:
        if type(node.value) not in _SCALARS:
            raise ExpressionError(f"{_a(type(node.value).__name__)} constant is not allowed")
        return _checked(node.value)

    def name(self, node: ast.Name) -> object:
        try:
            found = self.resolve(node.id)
        except KeyError:
            raise ExpressionError(f"name {node.id!r} is not defined") from None
        return _bound(found, node.id)

    def attribute(self, node: ast.Attribute) -> object:
        return self.member(self.term(node.value), node.attr, calling=False)

    def unary(self, node: ast.UnaryOp) -> object:
        return _checked(_UNARY[type(node.op)](self.value(node.operand)))

    def binary(self, node: ast.BinOp) -> object:
        function = _BINARY.get(type(node.op))
        if function is None:
            raise _refused(node.op)
        left, right = self.value(node.left), self.value(node.right)
        _precheck(type(node.op), left, right)
        return _checked(function(left, right))

    def boolean(self, node: ast.BoolOp) -> object:
        result: object = None
        for operand in node.values:
            result = self.value(operand)
            if bool(result) == isinstance(node.op, ast.Or):
                return result
        return result

    def compare(self, node: ast.Compare) -> object:
        left = self.value(node.left)
        result: object = True
        for op, operand in zip(node.ops, node.comparators, strict=True):
            right = self.value(operand)
            result = _COMPARE[type(op)](left, right)
            if not result:
                return result
            left = right
        return result

    def conditional(self, node: ast.IfExp) -> object:
        return self.value(node.body) if self.value(node.test) else self.value(node.orelse)

    def call(self, node: ast.Call) -> object:
        if isinstance(node.func, ast.Attribute):
            function = self.member(self.term(node.func.value), node.func.attr, calling=True)
        else:
            function = self.term(node.func)
        if not isinstance(function, Function):
            raise ExpressionError(f"{_a(type(function).__name__)} is not a function")
        args = [self.value(arg) for arg in node.args]
        kwargs = {}
        for keyword in node.keywords:
            if keyword.arg is None:
                raise ExpressionError("'**' unpacking is not allowed in a xacro expression")
            kwargs[keyword.arg] = self.value(keyword.value)
        return _checked(function.call(*args, **kwargs))

    def subscript(self, node: ast.Subscript) -> object:
        found = self.value(node.value)
        if type(found) not in (str, list, tuple, dict):
            raise ExpressionError(f"{_a(type(found).__name__)} cannot be indexed")
        if isinstance(node.slice, ast.Slice):
            if type(found) is dict:
                raise ExpressionError("a mapping cannot be sliced")
            parts = [
                None if part is None else self.value(part)
                for part in (node.slice.lower, node.slice.upper, node.slice.step)
            ]
            if any(part is not None and type(part) not in _INTEGERS for part in parts):
                raise ExpressionError("slice bounds must be integers")
            return found[slice(*parts)]
        return found[self.value(node.slice)]

    def sequence(self, node: ast.List | ast.Tuple) -> object:
        items = [self.value(item) for item in node.elts]
        return _checked(items if isinstance(node, ast.List) else tuple(items))

    def mapping(self, node: ast.Dict) -> object:
        if any(key is None for key in node.keys):
            raise ExpressionError("'**' unpacking is not allowed in a xacro expression")
        keys = [self.value(key) for key in node.keys if key is not None]
        values = [self.value(value) for value in node.values]
        return _checked(dict(zip(keys, values, strict=True)))


def _bound(found: object, name: str) -> object:
    """What a name or member resolved to, if it is something an expression may hold."""
    if isinstance(found, Unavailable):
        raise ExpressionError(found.reason)
    if isinstance(found, Function | Namespace) or type(found) in _SCALARS | _CONTAINERS:
        return found
    raise ExpressionError(f"{name} is not a value ({_a(type(found).__name__)})")


_HANDLERS: dict[type[ast.AST], Callable[..., object]] = {
    ast.Constant: _Walk.constant, ast.Name: _Walk.name, ast.Attribute: _Walk.attribute,
    ast.UnaryOp: _Walk.unary, ast.BinOp: _Walk.binary, ast.BoolOp: _Walk.boolean,
    ast.Compare: _Walk.compare, ast.IfExp: _Walk.conditional, ast.Call: _Walk.call,
    ast.Subscript: _Walk.subscript, ast.List: _Walk.sequence, ast.Tuple: _Walk.sequence,
    ast.Dict: _Walk.mapping,
}  # fmt: skip


def evaluate(expression: str, resolve: Callable[[str], object]) -> object:
    """Evaluate a xacro expression over the whitelist (see the module docstring).

    Args:
        expression: The text inside ``${…}`` (or after ``$(eval``).
        resolve: A name's value, :class:`Function`, :class:`Namespace` or
            :class:`Unavailable`; ``KeyError`` when the name is not defined.
            It is the only way in: nothing else is looked up.

    Returns:
        Plain data (see :func:`is_plain`).

    Raises:
        ExpressionError: The expression is refused (not on the whitelist, too
            large) or fails (division by zero, a missing key, a wrong type …);
            the message is one line.
    """
    if len(expression) > MAX_EXPRESSION_CHARS:
        raise ExpressionError(f"the expression is longer than {MAX_EXPRESSION_CHARS} characters")
    try:
        tree = ast.parse(expression.strip(), mode="eval")
    except SyntaxError as exc:
        raise ExpressionError(f"not a valid expression: {_one_line(str(exc.msg))}") from None
    except (ValueError, RecursionError, MemoryError) as exc:
        raise ExpressionError(f"not a valid expression: {_one_line(str(exc))}") from None
    try:
        return _Walk(resolve).value(tree.body)
    except RecursionError:
        raise ExpressionError("the expression is nested too deeply") from None
    except KeyError as exc:
        key = exc.args[0] if exc.args else None
        raise ExpressionError(_one_line(f"no key {key!r}")) from None
    except (ArithmeticError, LookupError, TypeError, ValueError) as exc:
        raise ExpressionError(_one_line(str(exc) or type(exc).__name__)) from None
