"""Fuzzing xacro expressions: plain data or one refusal, never anything else, never a file.

Expressions are built from xacro's grammar (numbers, strings, properties, math,
``python.``/``xacro.`` names, arithmetic, comparisons, conditionals, literals,
indexing) mixed with the known ways out of a Python ``eval``: attribute chains
(``__class__``, ``gi_frame.f_back.f_builtins``, ``format``, ``__globals__`` …),
format strings (``'{0.__class__}'.format``, ``%``, f-strings), generators,
lambdas, comprehensions, ``:=``, unpacking, and getattr-likes (``getattr``,
``vars``, ``type``, ``__import__``, ``open``), plus arbitrary text.
:func:`~fkcheck.urdf.expression.evaluate` must return plain data
(:func:`~fkcheck.urdf.expression.is_plain`) or raise
:class:`~fkcheck.urdf.expression.ExpressionError` with a one-line message —
no other exception — and while it runs, Python's audit hooks must see no file
opened, no import, no exec, no frame or code object reached, no process started,
and the working directory must stay empty. A second, slower property puts the
same expressions in a real description and expands it in its process. ``nox -s
fuzz`` runs these with 10x the examples.
"""

from __future__ import annotations

import contextlib
import os
import sys
import tempfile
from collections.abc import Iterator
from pathlib import Path
from xml.sax.saxutils import escape

import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from fkcheck.errors import UrdfError
from fkcheck.urdf.expression import (
    ExpressionError,
    Function,
    evaluate,
    is_plain,
    namespace,
    standard_names,
)
from fkcheck.urdf.xacro import expand_xacro
from tests.helpers import deadline
from tests.xacro_cases import TOP, write_description

#: Seconds one in-process example may take (values are bounded; the examples are small).
EXAMPLE_BOUND_S = 10.0
MARKER = "FKCHECK_MARKER"

# --------------------------------------------------------------------------- the names

PROPERTIES: dict[str, object] = {
    "a": 0.25, "n": 3, "s": "ab c", "flag": True, "nothing": None,
    "l": [1, 2.5, "x"], "t": (1, 2), "cfg": {"arm": {"reach": 0.5}, "l": [1, 2, 3], "k": "v"},
}  # fmt: skip
NAMES = standard_names()
NAMES["xacro"] = namespace(
    "xacro",
    {
        "load_yaml": Function("xacro.load_yaml", lambda name: {"file": str(name), "v": [1, 2]}),
        "arg": Function("xacro.arg", lambda name: "1.5"),
    },
)


def resolve(name: str) -> object:
    return PROPERTIES[name] if name in PROPERTIES else NAMES[name]


# --------------------------------------------------------------------------- watching

#: Audit events no evaluation may cause (prefixes); ``compile`` is ast.parse's own.
FORBIDDEN_EVENTS = (
    "open", "os.", "subprocess.", "shutil.", "socket.", "exec", "import", "sys._getframe",
    "sys._current_frames", "sys.settrace", "sys.setprofile", "object.__getattr__",
    "object.__setattr__", "object.__delattr__", "builtins.input", "ctypes.", "code.__new__",
    "function.__new__", "marshal.", "pickle.", "glob.", "tempfile.", "webbrowser.",
    "urllib.", "http.", "ftplib.", "smtplib.", "pty.", "fcntl.", "resource.", "signal.",
)  # fmt: skip
_seen: list[tuple[str, str]] = []
_watching = False


def _hook(name: str, args: tuple[object, ...]) -> None:
    if _watching and name.startswith(FORBIDDEN_EVENTS):
        _seen.append((name, repr(args)[:200]))


sys.addaudithook(_hook)  # permanent once added; inert unless _watching


@contextlib.contextmanager
def watched() -> Iterator[list[tuple[str, str]]]:
    """The forbidden audit events that happen inside the block."""
    global _watching
    _seen.clear()
    _watching = True
    try:
        yield _seen
    finally:
        _watching = False


@pytest.fixture(scope="module")
def empty_cwd() -> Iterator[Path]:
    """An empty working directory for the whole module: nothing may appear in it."""
    before = Path.cwd()
    with tempfile.TemporaryDirectory() as directory:
        os.chdir(directory)
        try:
            yield Path(directory)
        finally:
            os.chdir(before)


# --------------------------------------------------------------------------- expressions

NUMBERS = st.one_of(
    st.integers(-(10**6), 10**6).map(str),
    st.floats(allow_nan=False, allow_infinity=False, width=32).map(repr),
    st.sampled_from(["0", "1", "2", "10**6", "2**100", "1e308", "1j", "0.5", "-1"]),
)
FORMAT_AND_NAMES = [
    "'{0.__class__.__mro__}'", "'{0.__globals__}'", "'%s'", "'%(a)s'", "'__import__'", "'os'",
    "'open'", "'gi_frame'", "'x'", "''", "'a,b;c'",
]  # fmt: skip
STRINGS = st.one_of(
    st.text(max_size=8).map(repr),
    st.sampled_from(FORMAT_AND_NAMES),
)
NAME_ATOMS = st.sampled_from(
    [*PROPERTIES, "pi", "e", "inf", "sin", "math", "python", "xacro", "True", "False", "None",
     "list", "dict", "len", "str", "int", "float", "max", "round", "range", "sorted",
     "load_yaml", "undefined", "map", "__builtins__", "__import__", "open", "getattr",
     "globals", "locals", "vars", "type", "eval", "exec", "object", "self", "__class__"]
)  # fmt: skip
ATOMS = st.one_of(NUMBERS, STRINGS, NAME_ATOMS)

ATTRIBUTES = st.sampled_from(
    ["__class__", "__mro__", "__bases__", "__base__", "__subclasses__", "__globals__",
     "__builtins__", "__dict__", "__self__", "__func__", "__code__", "__closure__",
     "__getattribute__", "__reduce_ex__", "__init__", "__call__", "__module__", "__doc__",
     "gi_frame", "gi_code", "gi_yieldfrom", "f_back", "f_builtins", "f_globals", "f_locals",
     "cr_frame", "ag_frame", "tb_frame", "co_consts", "format", "format_map", "mro", "real",
     "imag", "conjugate", "keys", "values", "items", "get", "pop", "update", "append",
     "join", "split", "lower", "replace", "startswith", "strip", "zfill", "center", "encode",
     "__len__", "__add__", "__mod__", "__format__", "system", "popen", "load_yaml", "arg",
     "sin", "pi", "abs", "type", "vars", "reach", "arm", "l", "k", "v", "file"]
)  # fmt: skip
FUNCTIONS = st.sampled_from(
    ["getattr", "setattr", "vars", "type", "eval", "exec", "compile", "open", "__import__",
     "globals", "locals", "breakpoint", "dir", "id", "iter", "next", "print", "input",
     "python.type", "python.vars", "python.map", "python.filter", "python.isinstance",
     "python.slice", "python.set", "python.hash", "python.abs", "python.sum", "python.zip",
     "python.enumerate", "python.reversed", "python.repr", "python.divmod", "python.ord",
     "python.all", "python.any", "python.tuple", "math.factorial", "math.prod", "math.sqrt",
     "math.atan2", "math.floor", "math.fsum", "math.gcd", "math.ldexp", "math.isqrt",
     "xacro.load_yaml", "xacro.arg", "str.format", "str", "int", "float", "len", "list",
     "dict", "min", "max", "round", "sorted", "range", "sin", "radians", "pow", "fabs",
     "load_yaml", "map", "(lambda: 0)", "s.split", "s.format", "cfg.get", "cfg.keys",
     "' '.join", "s.replace", "a.__class__", "cfg.pop"]
)  # fmt: skip
BINARY = st.sampled_from(["+", "-", "*", "/", "//", "%", "**", "<<", ">>", "&", "|", "^", "@"])
COMPARE = st.sampled_from(["==", "!=", "<", "<=", ">", ">=", "in", "not in", "is", "is not"])

#: Known ways out, whole (they did escape Python's eval under xacro's fence).
ESCAPES = st.sampled_from(
    ["[(g := (g.gi_frame.f_back.f_back.f_builtins for _ in [1])), list(g)][1][0]"
     f"['open']('{MARKER}', 'w').write('x')",
     "(lambda: ().__class__.__base__.__subclasses__())()",
     "[c for c in ().__class__.__mro__]",
     "'{0.__class__.__mro__}'.format(1.0)",
     "s.format(1.0)",
     "python.list((x.gi_frame.f_back for x in [1]))",
     f"open('{MARKER}', 'w').write('x')",
     f"__import__('os').system('touch {MARKER}')",
     "xacro.load_yaml.__globals__['os'].system('true')",
     "python.vars(python)", "python.type(1).__subclasses__()",
     "[x for x in ().__class__.__base__.__subclasses__() if x.__name__ == 'Popen'][0]",
     "(1).__class__.__mro__[-1].__subclasses__()",
     "getattr(getattr(1, '__class__'), '__mro__')",
     "math.__dict__", "sin.__self__", "cfg.__class__", "str.format(s, 1)",
     "f'{a.__class__}'", "'%s' % (a,)", "{**cfg}", "[*l]", "(y := 1)",
     "dict(a=1).pop('a')", "s.__mod__(1)", "s.zfill(10**9)", "'x' * 10**10",
     "2 ** 2 ** 2 ** 2 ** 2", "1 << 10**6", "[[0] * 1000] * 1000", "python.range(10**9)",
     "' '.join(['x'] * 10**6)", "s * 10**7"]
)  # fmt: skip


def _extend(children: st.SearchStrategy[str]) -> st.SearchStrategy[str]:
    two = st.tuples(children, children)
    args = st.lists(children, max_size=3).map(", ".join)
    return st.one_of(
        st.tuples(children, BINARY, children).map(lambda t: f"({t[0]} {t[1]} {t[2]})"),
        st.tuples(st.sampled_from(["-", "+", "not ", "~"]), children).map("({0[0]}{0[1]})".format),
        st.tuples(children, COMPARE, children).map(lambda t: f"({t[0]} {t[1]} {t[2]})"),
        two.map(lambda t: f"({t[0]} and {t[1]})"),
        two.map(lambda t: f"({t[0]} or {t[1]})"),
        st.tuples(children, children, children).map(lambda t: f"({t[0]} if {t[1]} else {t[2]})"),
        st.tuples(FUNCTIONS, args).map(lambda t: f"{t[0]}({t[1]})"),
        st.tuples(FUNCTIONS, children, children).map(lambda t: f"{t[0]}({t[1]}, key={t[2]})"),
        st.tuples(FUNCTIONS, children).map(lambda t: f"{t[0]}(*{t[1]})"),
        st.tuples(FUNCTIONS, children).map(lambda t: f"{t[0]}(**{t[1]})"),
        st.tuples(children, st.lists(ATTRIBUTES, min_size=1, max_size=4)).map(
            lambda t: f"({t[0]})." + ".".join(t[1])
        ),
        st.tuples(children, ATTRIBUTES, args).map(lambda t: f"({t[0]}).{t[1]}({t[2]})"),
        two.map(lambda t: f"({t[0]})[{t[1]}]"),
        st.tuples(children, children, children).map(lambda t: f"({t[0]})[{t[1]}:{t[2]}]"),
        args.map(lambda a: f"[{a}]"),
        args.map(lambda a: f"({a},)"),
        two.map(lambda t: f"{{{t[0]}: {t[1]}}}"),
        children.map(lambda c: f"{{{c}}}"),
        two.map(lambda t: f"(lambda x: {t[0]})({t[1]})"),
        two.map(lambda t: f"[{t[0]} for x in {t[1]}]"),
        two.map(lambda t: f"({t[0]} for x in {t[1]})"),
        two.map(lambda t: f"{{x: {t[0]} for x in {t[1]}}}"),
        children.map(lambda c: f"(y := {c})"),
        children.map(lambda c: f"f'{{{c}}}'"),
        children.map(lambda c: f"'{{0.__class__}}'.format({c})"),
        children.map(lambda c: f"'%s' % ({c},)"),
        st.tuples(children, ATTRIBUTES).map(lambda t: f"getattr({t[0]}, '{t[1]}')"),
        children.map(lambda c: f"[*{c}]"),
        children.map(lambda c: f"({c}).__class__.__mro__[-1].__subclasses__()"),
        children.map(lambda c: f"list(({c} for _ in [1]))[0]"),
    )


# xacro's own grammar: what a description writes (mostly values, some plain errors)
SMALL = st.one_of(
    st.integers(-100, 100).map(str),
    st.floats(-100, 100, allow_nan=False, width=32).map(repr),
    st.sampled_from(["pi", "e", "a", "n", "True", "False", "None", "cfg.arm.reach", "l[0]"]),
)
WORDS = st.one_of(
    st.text(alphabet="abc _,", max_size=6).map(repr),
    st.sampled_from(["s", "cfg['k']", "'$(arg x)'", "xacro.arg('x')", "str(n)"]),
)
CONTAINERS = st.sampled_from(["l", "t", "cfg", "cfg['l']", "[1, 2]", "(0.5, 1.5)", "{'k': 1}"])
MATH_CALLS = st.sampled_from(
    ["sin", "cos", "tan", "atan", "sqrt", "radians", "degrees", "fabs", "floor", "ceil", "exp",
     "log", "int", "float", "round", "str", "bool", "math.sin", "math.cos", "python.abs",
     "python.repr"]
)  # fmt: skip
LIST_CALLS = st.sampled_from(
    ["len", "list", "sorted", "min", "max", "python.sum", "python.tuple", "python.reversed",
     "python.any", "python.all", "python.enumerate"]
)  # fmt: skip


def _grammar(children: st.SearchStrategy[str]) -> st.SearchStrategy[str]:
    two = st.tuples(children, children)
    arithmetic = st.sampled_from(["+", "-", "*", "/", "//", "%", "**"])
    return st.one_of(
        st.tuples(children, arithmetic, children).map(lambda t: f"({t[0]} {t[1]} {t[2]})"),
        st.tuples(st.sampled_from(["-", "+", "not "]), children).map("({0[0]}{0[1]})".format),
        st.tuples(children, COMPARE, children).map(lambda t: f"({t[0]} {t[1]} {t[2]})"),
        two.map(lambda t: f"({t[0]} and {t[1]})"),
        two.map(lambda t: f"({t[0]} or {t[1]})"),
        st.tuples(children, children, children).map(lambda t: f"({t[0]} if {t[1]} else {t[2]})"),
        st.tuples(MATH_CALLS, children).map(lambda t: f"{t[0]}({t[1]})"),
        st.tuples(st.sampled_from(["atan2", "pow", "min", "max", "hypot", "math.fmod"]), two).map(
            lambda t: f"{t[0]}({t[1][0]}, {t[1][1]})"
        ),
        st.tuples(LIST_CALLS, st.one_of(CONTAINERS, children)).map(lambda t: f"{t[0]}({t[1]})"),
        st.tuples(st.one_of(CONTAINERS, children), children).map(lambda t: f"{t[0]}[{t[1]}]"),
        st.tuples(WORDS, st.sampled_from(["upper()", "split()", "strip()", "split(',')"])).map(
            lambda t: f"{t[0]}.{t[1]}"
        ),
        st.lists(WORDS, max_size=3).map(lambda w: f"' '.join([{', '.join(w)}])"),
        st.lists(children, max_size=3).map(lambda c: f"[{', '.join(c)}]"),
        two.map(lambda t: f"{{'x': {t[0]}, 'y': {t[1]}}}['x']"),
    )


EXPRESSIONS = st.one_of(
    st.recursive(st.one_of(SMALL, WORDS), _grammar, max_leaves=8),
    st.recursive(st.one_of(ATOMS, ESCAPES), _extend, max_leaves=10),
    ESCAPES,
    st.text(max_size=40),
    st.text(alphabet="()[]{}.,:;'\"+-*/%<>=!&|^~@ _abcxyz0123456789", max_size=40),
)


def _kind(message: str) -> str:
    """What a refusal says, in a few words (for hypothesis's statistics)."""
    for words in ("is not allowed", "is not available", "is not defined", "the limit",
                  "not a valid expression", "is a function", "is a namespace"):  # fmt: skip
        if words in message:
            return f"refused: {words}"
    return "refused: an error in plain data (types, zero division, missing key …)"


def _outcome(expression: str) -> str:
    """Evaluate, checking the contract; ``"value"`` or ``"refused"``."""
    with deadline(EXAMPLE_BOUND_S), watched() as seen:
        try:
            value = evaluate(expression, resolve)
        except ExpressionError as exc:
            message = str(exc)
            assert message, expression
            assert "\n" not in message, (expression, message)
            assert len(message) <= 400, (expression, message)
            outcome = _kind(message)
        else:
            assert is_plain(value), (expression, type(value))
            outcome = "value"
    assert seen == [], (expression, seen)
    return outcome


@settings(suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
@given(expression=EXPRESSIONS)
def test_property_an_expression_is_plain_data_or_one_refusal(expression, empty_cwd):
    outcome = _outcome(expression)
    event(outcome)
    assert list(empty_cwd.iterdir()) == [], expression


@pytest.mark.parametrize(
    "expression",
    [
        "[(g := (g.gi_frame.f_back.f_back.f_builtins for _ in [1])), list(g)][1][0]"
        f"['open']('{MARKER}', 'w').write('x')",
        "'{0.__class__.__mro__}'.format(1.0)",
        "getattr(getattr(1, '__class__'), '__mro__')",
        "(1).__class__.__mro__[-1].__subclasses__()",
    ],
)
def test_property_the_known_ways_out_are_refused(expression, empty_cwd):
    assert _outcome(expression).startswith("refused")
    assert list(empty_cwd.iterdir()) == []


# --------------------------------------------------------------------------- in a description


@settings(
    max_examples=max(8, settings.default.max_examples // 6),
    suppress_health_check=[HealthCheck.too_slow],
)
@given(expression=st.one_of(EXPRESSIONS, ESCAPES))
def test_property_a_description_with_any_expression_expands_or_is_refused(expression):
    """The same, through xacro in its own process: a URDF or one UrdfError line, no file."""
    with tempfile.TemporaryDirectory() as directory:
        root = Path(directory)
        body = escape(f"${{{expression}}}")
        top = TOP.replace('<link name="tip"/>', f'<link name="tip"/><gazebo>{body}</gazebo>')
        path, package = write_description(root, top)
        before = sorted(root.rglob("*"))
        with contextlib.chdir(root):  # the expansion's working directory too
            try:
                expand_xacro(path, {}, {"arm_description": package}, timeout_s=30.0)
            except UrdfError as exc:
                message: str | None = str(exc)
            else:
                message = None
        event("expanded" if message is None else "refused")
        if message is not None:
            assert "\n" not in message, message
            assert "Traceback" not in message
        assert sorted(root.rglob("*")) == before, expression
