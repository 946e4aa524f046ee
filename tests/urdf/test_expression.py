"""fkcheck's xacro expression evaluator: xacro's expression language over plain data, no more.

What a description writes evaluates as xacro evaluated it; everything outside
the whitelist is refused in one line by what it is (an attribute, a lambda, a
format string), not by its name; sizes are bounded before values are built.
"""

from __future__ import annotations

import datetime
import math
import time

import pytest

from fkcheck.urdf.expression import (
    MAX_INT_BITS,
    MAX_ITEMS,
    MAX_TEXT_CHARS,
    ExpressionError,
    Function,
    Namespace,
    evaluate,
    is_plain,
    namespace,
    plain,
    standard_names,
)

NAMES = standard_names()
PROPERTIES = {
    "a": 0.25, "n": 3, "s": "ab c", "l": [1, 2.5, "x"],
    "cfg": {"arm": {"reach": 0.5}, "limits": [1, 2, 3], "k": "v"},
}  # fmt: skip


def resolve(name):
    return PROPERTIES[name] if name in PROPERTIES else NAMES[name]


def ev(expression):
    return evaluate(expression, resolve)


@pytest.mark.parametrize(
    ("expression", "value"),
    [
        ("1 + 2 * 3", 7), ("7 / 2", 3.5), ("7 // 2", 3), ("-7 % 3", 2), ("2 ** 10", 1024),
        ("pi / 2", math.pi / 2), ("a * 2", 0.5), ("-a", -0.25), ("not a", False),
        ("sin(pi / 2)", 1.0), ("math.cos(0)", 1.0), ("radians(180)", math.pi),
        ("degrees(pi)", 180.0), ("atan2(1, 1)", math.pi / 4), ("sqrt(2) ** 2", 2.0000000000000004),
        ("pow(2, 3)", 8.0), ("fabs(-1)", 1.0), ("floor(1.5)", 1), ("ceil(1.5)", 2),
        ("python.abs(-2)", 2), ("max(1, n)", 3), ("min([3, 1])", 1), ("round(2.567, 2)", 2.57),
        ("int('12')", 12), ("float('1.5')", 1.5), ("str(n)", "3"), ("bool(0)", False),
        ("len(s)", 4), ("sorted([3, 1, 2])", [1, 2, 3]), ("list(python.range(3))", [0, 1, 2]),
        ("python.sum([1, 2.5])", 3.5), ("python.zip([1], [2])", [(1, 2)]),
        ("1 < a < 2", False), ("0 < a < 1", True), ("'b' in s", True), ("None is None", True),
        ("n == 3 and s", "ab c"), ("0 or 'x'", "x"), ("'y' if n > 2 else 'z'", "y"),
        ("cfg['arm']['reach']", 0.5), ("cfg.arm.reach", 0.5), ("cfg.limits[-1]", 3),
        ("cfg.get('missing', 7)", 7), ("cfg.keys()", ["arm", "limits", "k"]),
        ("l[1:]", [2.5, "x"]), ("s[::-1]", "c ba"), ("s.split()", ["ab", "c"]),
        ("s.upper()", "AB C"), ("' '.join(['0.5'] * 3)", "0.5 0.5 0.5"),
        ("s.replace('ab', 'x')", "x c"), ("(1, 2)", (1, 2)), ("{'k': n}", {"k": 3}),
        ("[a, s]", [0.25, "ab c"]), ("True", True), ("1j * 1j", -1 + 0j),
        ("python.repr('x')", "'x'"), ("python.divmod(7, 2)", (3, 1)), ("e", math.e),
    ],
)  # fmt: skip
def test_xacros_expression_language_evaluates(expression, value):
    result = ev(expression)
    assert result == value
    assert type(result) is type(value)
    assert is_plain(result)


@pytest.mark.parametrize(
    ("expression", "refusal"),
    [
        # attribute access on a value, whatever the name
        ("(1).__class__", r"attribute \.__class__ of an int is not allowed"),
        ("a.real", r"attribute \.real of a float is not allowed"),
        ("().__class__.__base__.__subclasses__()", r"attribute \.__class__ of a tuple"),
        ("l.__len__()", r"attribute \.__len__ of a list"),
        ("s.format(1)", r"string method \.format\(\) is not allowed"),
        ("'{0.__class__.__mro__}'.format(1.0)", r"string method \.format\(\) is not allowed"),
        ("s.format_map(cfg)", r"string method \.format_map\(\) is not allowed"),
        ("s.__mod__(1)", r"string method \.__mod__\(\) is not allowed"),
        ("s.zfill(10)", r"string method \.zfill\(\) is not allowed"),
        ("str.format(s, 1)", r"attribute \.format of str \(a function\) is not allowed"),
        ("sin.__self__", r"attribute \.__self__ of sin \(a function\) is not allowed"),
        ("cfg.pop('k')", r"mapping method \.pop\(\) is not allowed .*\(only get, keys"),
        ("cfg.__class__", r"the mapping has no key '__class__'"),
        ("math.__dict__", r"math\.__dict__ is not defined"),
        ("python.__class__", r"python\.__class__ is not defined"),
        # constructs outside the whitelist
        ("(lambda: 1)()", r"a lambda is not allowed"),
        ("[x for x in l]", r"a comprehension is not allowed"),
        ("{x: 1 for x in l}", r"a comprehension is not allowed"),
        ("(x for x in l)", r"a generator expression is not allowed"),
        ("list(x.gi_frame for x in [1])", r"a generator expression is not allowed"),
        ("f'{a}'", r"an f-string is not allowed"),
        ("'%s' % a", r"string formatting with % is not allowed"),
        ("(y := 1)", r"an assignment \(:=\) is not allowed"),
        ("[*l]", r"'\*' unpacking is not allowed"),
        ("max(*l)", r"'\*' unpacking is not allowed"),
        ("dict(**cfg)", r"'\*\*' unpacking is not allowed"),
        ("{**cfg}", r"'\*\*' unpacking is not allowed"),
        ("{1, 2}", r"a set is not allowed"),
        ("b'x'", r"a bytes constant is not allowed"),
        ("...", r"an ellipsis constant is not allowed"),
        ("1 @ 2", r"the operator @ is not allowed"),
        ("l[1:2, 0]", r"Slice is not allowed"),
        # names: only properties and the tables
        ("getattr(a, 'real')", r"name 'getattr' is not defined"),
        ("__import__('os')", r"name '__import__' is not defined"),
        ("open('x', 'w')", r"name 'open' is not defined"),
        ("__builtins__", r"name '__builtins__' is not defined"),
        ("abs(-1)", r"name 'abs' is not defined"),  # xacro has it as python.abs only
        ("python.type(1)", r"type is not available .*\(it gives Python classes\)"),
        ("python.vars(python)", r"vars is not available"),
        ("map(float, l)", r"map is not available .*\(it takes a function\)"),
        ("math.factorial(5)", r"factorial is not available"),
        ("sin", r"sin is a function: call it, as sin\(…\)"),
        ("python", r"python is a namespace, not a value"),
        ("a(1)", r"a float is not a function"),
        # plain errors, one line each
        ("1 / 0", r"division by zero"), ("cfg['x']", r"no key 'x'"), ("l[9]", r"out of range"),
        ("'a' + 1", r"can only concatenate str"), ("sqrt(-1)", r"math domain error"),
        ("python.sum(['a'])", r"sum\(\) adds numbers, not a str"),
        ("1 +", r"not a valid expression"), ("", r"not a valid expression"),
        ("1\n+ 1", r"not a valid expression"),
    ],
)  # fmt: skip
def test_everything_else_is_refused_in_one_line(expression, refusal):
    with pytest.raises(ExpressionError, match=refusal) as caught:
        ev(expression)
    assert "\n" not in str(caught.value)


@pytest.mark.parametrize(
    ("expression", "refusal"),
    [
        (f"'x' * {MAX_TEXT_CHARS + 1}", f"a string longer than {MAX_TEXT_CHARS} characters"),
        ("'x' * 10**18", "a string longer than"),
        ("s.replace('a', 'a' * 10**7) * 10", "a string longer than"),
        ("' '.join(['x' * 10**7] * 4)", "a string longer than"),
        ("'x' * 20000000 + 'y' * 20000000", "a string longer than"),
        (f"[0] * {MAX_ITEMS + 1}", f"more than {MAX_ITEMS} items"),
        ("[[0] * 1000] * 1000", f"more than {MAX_ITEMS} items"),
        ("python.range(10**12)", f"more than {MAX_ITEMS} items"),
        ("list('x' * 10**6)", f"more than {MAX_ITEMS} items"),
        (f"2 ** {MAX_INT_BITS}", f"an integer of more than {MAX_INT_BITS} bits"),
        ("2 ** 2 ** 2 ** 2 ** 2", f"an integer of more than {MAX_INT_BITS} bits"),
        ("10 ** 10 ** 10", f"an integer of more than {MAX_INT_BITS} bits"),
        ("1 << 10**9", f"an integer of more than {MAX_INT_BITS} bits"),
        ("int('9' * 20000)", "a number of more than 10000 characters"),
        ("round(1.5, 10**9)", "round\\(\\) to more than 1000 digits"),
        ("1e308 * 10 ** 400", "int too large to convert to float"),
        ("'(' * 100 + '1' + ')' * 100", None),  # a string, not nesting: fine
    ],
)
def test_sizes_are_bounded_before_values_are_built(expression, refusal):
    start = time.perf_counter()
    if refusal is None:
        assert is_plain(ev(expression))
    else:
        with pytest.raises(ExpressionError, match=refusal):
            ev(expression)
    assert time.perf_counter() - start < 2.0


def test_nesting_is_refused_not_crashed():
    for expression in ("(" * 300 + "1" + ")" * 300, "-" * 5000 + "1", "[" * 300 + "]" * 300):
        with pytest.raises(ExpressionError, match=r"not a valid expression|nested too deeply"):
            ev(expression)


def test_names_come_only_from_the_resolver():
    seen = []

    def recording(name):
        seen.append(name)
        return {"x": 2}[name]

    assert evaluate("x * x", recording) == 4
    assert seen == ["x", "x"]
    with pytest.raises(ExpressionError, match="name 'pi' is not defined"):
        evaluate("pi", recording)


def test_what_a_resolver_or_function_gives_must_be_plain_data():
    with pytest.raises(ExpressionError, match=r"thing is not a value \(an object\)"):
        evaluate("thing", {"thing": object()}.__getitem__)
    leaky = Function("leaky", lambda: lambda: 0)
    with pytest.raises(ExpressionError, match="a function is not a value a xacro expression has"):
        evaluate("leaky()", {"leaky": leaky}.__getitem__)
    nested = Function("nested", lambda: [1, {"k": {1, 2}}])
    with pytest.raises(ExpressionError, match="a set is not a value"):
        evaluate("nested()", {"nested": nested}.__getitem__)
    space = Namespace("ns", {"v": 1, "o": object()}.__getitem__)
    assert evaluate("ns.v", {"ns": space}.__getitem__) == 1
    with pytest.raises(ExpressionError, match=r"ns\.o is not a value"):
        evaluate("ns.o", {"ns": space}.__getitem__)


def test_namespaces_hold_members_not_values():
    space = namespace("colors", {"grey": "0.5 0.5 0.5 1"})
    assert evaluate("colors.grey", {"colors": space}.__getitem__) == "0.5 0.5 0.5 1"
    with pytest.raises(ExpressionError, match=r"colors\.red is not defined"):
        evaluate("colors.red", {"colors": space}.__getitem__)
    with pytest.raises(ExpressionError, match="colors is a namespace, not a value"):
        evaluate("[colors]", {"colors": space}.__getitem__)


class Mapping(dict):
    pass


@pytest.mark.parametrize(
    ("data", "expected"),
    [
        ({"a": [1, 2.5, "x", None, True]}, {"a": [1, 2.5, "x", None, True]}),
        (Mapping(k=(1, 2)), {"k": (1, 2)}),
    ],
)
def test_plain_copies_data_to_exact_types(data, expected):
    copied = plain(data)
    assert copied == expected
    assert type(copied) is dict
    assert is_plain(copied)


def test_plain_refuses_what_is_not_plain_data_and_what_is_too_large():
    with pytest.raises(ExpressionError, match="a date is not plain data"):
        plain({"when": datetime.date(2024, 1, 1)})
    with pytest.raises(ExpressionError, match="a bytes is not plain data"):
        plain([b"x"])
    loop: list[object] = []
    loop.append(loop)
    with pytest.raises(ExpressionError, match="nested more than 200 levels"):
        plain(loop)
    shared = [[0] * 100] * 100
    bomb = [shared] * 100  # 10**6 items through shared parts
    with pytest.raises(ExpressionError, match=f"more than {MAX_ITEMS} items"):
        plain(bomb)
    assert not is_plain(bomb)
