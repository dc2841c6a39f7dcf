"""Tests for the whitelist expression parser (solver/expressions.py).

The parser is the only door from scene-file text into sympy, so the tests
check (1) that everything outside the whitelist is refused with an
ExpressionError that says where and what, and (2) that what is accepted is
parsed exactly: precedence, powers written ``^``, and decimals as exact
rationals. Property (2) is checked on random arithmetic trees: each tree is
rendered to text with the fewest parentheses the usual precedence rules
allow, parsed, and compared with the sympy expression built from the tree
directly (never from text).
"""
from __future__ import annotations

from fractions import Fraction

import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from solver.errors import ExpressionError, InputError
from solver.expressions import MAX_ARGUMENT, MAX_LENGTH, parse_expression

X = sp.Symbol("x", real=True)
Y = sp.Symbol("y", real=True)
NAMES = {"x": X, "y": Y}
WHERE = "demo.toml: points.B"


def parse(text: str) -> sp.Expr:
    return parse_expression(text, NAMES, WHERE)


# -- refusals ------------------------------------------------------------------

REFUSED = [
    ("__import__('os')", "unknown function '__import__'"),
    ("__import__('os').system('true')", "attribute access"),
    ("().__class__", "attribute access"),
    ("().__class__.__bases__[0].__subclasses__()", "not allowed"),
    ("[x for x in y]", "comprehensions"),
    ("(x for x in y)", "comprehensions"),
    ("lambda: 1", "lambda"),
    ("'a'.upper()", "attribute access"),
    ("'abc'", "strings"),
    ("x[0]", "subscripts"),
    ("sin(x=1)", "keyword arguments"),
    ("sin(*x)", "starred"),
    ("open('f')", "unknown function 'open'"),
    ("y.real", "attribute access"),
    ("z + 1", "unknown name 'z'"),
    ("sin", "used without calling"),
    ("x if y else 1", "conditional"),
    ("x < y", "comparisons"),
    ("x and y", "boolean"),
    ("x % 2", "Mod"),
    ("x // 2", "FloorDiv"),
    ("(x := 2)", "assignments"),
    ("f'{x}'", "strings"),
    ("True", "bool"),
    ("2j", "complex"),
    ("x; 1", "syntax error"),
    ("atan2(x)", "atan2() takes 2 argument(s), got 1"),
    ("1/0", "division by zero"),
    ("log(0)", "undefined"),
    ("9**9**9", "too large"),
    # constants that would hang sympy's evaluation or reach float64 as inf / complex
    ("x*exp(exp(exp(100)))", "too large"),
    ("x*pi**(10**100)", "too large"),
    ("x*cos(10**200)", "too large"),
    ("x*1e999", "too large or too small"),
    ("x*1e-999", "too large or too small"),
    ("x*1e299*1e299", "too large or too small"),
    ("x*exp(710)", "too large or too small"),
    ("x*exp(-746)", "too large or too small"),  # 1.2e-324: below the least double, not 0
    ("x*sqrt(-1)", "not a real number"),
    ("x*acos(2)", "not a real number"),
    ("x" + "+x" * 150, "nesting deeper"),
    ("", "empty expression"),
    ("x" * (MAX_LENGTH + 1), "characters long"),
]


@pytest.mark.parametrize(("text", "reason"), REFUSED)
def test_refuses_outside_whitelist(text: str, reason: str) -> None:
    with pytest.raises(ExpressionError) as info:
        parse(text)
    message = str(info.value)
    assert message.startswith(WHERE + ": "), message
    assert reason in message, message
    # One line, and it repeats (the start of) the offending text.
    assert "\n" not in message
    assert isinstance(info.value, InputError)


def test_refused_text_is_quoted_in_message() -> None:
    with pytest.raises(ExpressionError, match=r"'x\[0\]' in '2\*x\[0\]'"):
        parse("2*x[0]")


def test_non_text_is_refused() -> None:
    with pytest.raises(ExpressionError, match="expected an expression written as text"):
        parse_expression(3, NAMES, WHERE)  # type: ignore[arg-type]


# -- exactness -----------------------------------------------------------------


def test_one_third_is_an_exact_rational() -> None:
    value = parse("1/3")
    assert isinstance(value, sp.Rational) and value == sp.Rational(1, 3)


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("0.1", sp.Rational(1, 10)),
        ("1.5e-3", sp.Rational(3, 2000)),
        ("2.5E2", sp.Integer(250)),
        ("32.174", sp.Rational(32174, 1000)),
        ("2^3", sp.Integer(8)),
        ("2*x^2", 2 * X**2),  # ^ is power and binds tighter than *
        ("-x^2", -(X**2)),
        ("2**0.5", sp.sqrt(2)),
        ("pi - x", sp.pi - X),
        ("atan2(y, x) + abs(x)", sp.atan2(Y, X) + sp.Abs(X)),
        ("max(x, y, 1)", sp.Max(X, Y, 1)),
    ],
)
def test_accepted_forms(text: str, expected: sp.Expr) -> None:
    assert parse(text) == expected


def test_symbols_are_the_callers() -> None:
    # The parser must use the given Symbol objects (with their assumptions),
    # not make new ones: a plain Symbol("x") is a different symbol.
    assert parse("x").is_real is True
    assert parse("x") - X == 0


# -- property: random arithmetic trees --------------------------------------------

# A tree is (text, precedence, sympy value, undefined); precedence: 1 sum,
# 2 product, 3 unary minus, 4 power, 5 atom. `undefined` marks a division by
# an exact zero somewhere inside, which the parser must refuse even where
# sympy would quietly absorb it (nan**0 is 1).
Tree = tuple[str, int, sp.Expr, bool]


def _wrap(tree: Tree, minimum: int) -> str:
    text, prec = tree[0], tree[1]
    return text if prec >= minimum else f"({text})"


@st.composite
def _decimal_leaf(draw) -> Tree:
    whole = draw(st.integers(0, 999))
    frac = draw(st.integers(0, 999))
    text = f"{whole}.{frac:03d}"
    return text, 5, sp.Rational(Fraction(text).numerator, Fraction(text).denominator), False


_leaves = st.one_of(
    st.integers(0, 50).map(lambda n: (str(n), 5, sp.Integer(n), False)),
    _decimal_leaf(),
    st.sampled_from([("x", 5, X, False), ("y", 5, Y, False), ("pi", 5, sp.pi, False)]),
)


def _extend(children):
    binary = st.tuples(st.sampled_from(["+", "-", "*", "/"]), children, children).map(
        lambda t: (
            f"{_wrap(t[1], {'+': 1, '-': 1}.get(t[0], 2))} {t[0]} "
            f"{_wrap(t[2], {'+': 2, '-': 2}.get(t[0], 3))}",
            {"+": 1, "-": 1}.get(t[0], 2),
            {
                "+": lambda a, b: a + b,
                "-": lambda a, b: a - b,
                "*": lambda a, b: a * b,
                "/": lambda a, b: a / b,
            }[t[0]](t[1][2], t[2][2]),
            t[1][3] or t[2][3] or (t[0] == "/" and t[2][2] == 0),
        )
    )
    negation = children.map(lambda c: (f"-{_wrap(c, 3)}", 3, -c[2], c[3]))
    power = st.tuples(children, st.integers(-2, 3), st.sampled_from(["**", "^"])).map(
        lambda t: (f"{_wrap(t[0], 5)}{t[2]}{t[1]}", 4, t[0][2] ** t[1], t[0][3])
    )
    call = st.tuples(st.sampled_from(["sin", "cos", "sqrt", "exp"]), children).map(
        lambda t: (f"{t[0]}({t[1][0]})", 5, getattr(sp, t[0])(t[1][2]),
                   t[1][3] or (t[1][2].is_number and abs(complex(sp.N(t[1][2], 20))) > MAX_ARGUMENT))
    )
    # a constant outside the documented limits anywhere in the tree must be refused too, and so
    # must an undefined node even where its parent hides it (1/(0**-1) is 0 to sympy)
    return st.one_of(binary, negation, power, call).map(
        lambda t: (*t[:3], t[3] or not _constant_within_limits(t[2]) or t[2].has(sp.zoo, sp.nan, sp.oo, -sp.oo))
    )


trees = st.recursive(_leaves, _extend, max_leaves=8)


def _constant_within_limits(expr: sp.Expr) -> bool:
    """A constant node is real, 0 or within 1e-300..1e300 in size, and a constant function
    argument is at most MAX_ARGUMENT in size (the parser's documented limits: exp(691),
    sin(exp(35)) and sqrt(-2) are refused). Applied node by node as the tree grows, so
    nothing huge is ever evaluated. Sizes are compared as 20-digit sympy Floats: a double would
    take exp(-746) (1.2e-324, refused by the parser as smaller than 1e-300) for 0."""
    if not expr.is_number or expr.has(sp.zoo, sp.nan, sp.oo, -sp.oo):
        return True
    re, im = sp.N(expr, 20).as_real_imag()  # sympy Floats: exp(-746) is 1.2e-324, where a double is 0
    re, im = abs(sp.Float(re, 20)), abs(sp.Float(im, 20))
    if im > sp.Float("1e-12") * max(re, sp.Float("1e-300")):
        return False
    return re == 0 or sp.Float("1e-300") <= re <= sp.Float("1e300")


@settings(max_examples=50)  # each example is a parse plus a sympy comparison (~ms)
@given(trees)
def test_random_trees_parse_to_their_value(tree: Tree) -> None:
    text, _, expected, undefined = tree
    if undefined or expected.has(sp.zoo, sp.nan, sp.oo, -sp.oo):
        # e.g. a division by an exact zero: must be refused, never returned.
        with pytest.raises(ExpressionError):
            parse(text)
        return
    parsed = parse(text)
    assert parsed == expected or sp.expand(parsed - expected) == 0, text


@pytest.mark.parametrize("text", ["1/(0**-1)", "x/(0^-1)", "-(0**-1)**-1", "2 + (0**-2)**-1"])
def test_an_undefined_node_is_refused_even_where_its_parent_hides_it(text):
    # Regression (found by the random-tree property): sympy turns 1/zoo into 0, so 1/(0**-1)
    # parsed to 0 instead of being refused as a division by zero.
    with pytest.raises(ExpressionError, match="undefined"):
        parse(text)


@pytest.mark.parametrize("text", ["x", " y ", "0", "7", "12345678901234567890", "pi"])
def test_bare_names_and_integers_read_as_the_parser_reads_them(text: str) -> None:
    # a bare known name or unsigned integer skips the syntax tree: the reference is the same text
    # in parentheses, which the parser itself reads
    assert sp.srepr(parse(text)) == sp.srepr(parse(f"({text})"))


@pytest.mark.parametrize(("text", "words"), [("007", "syntax error"), ("z", "unknown name 'z'"),
                                             ("lambda", "syntax error")])
def test_atoms_the_parser_refuses_are_refused(text: str, words: str) -> None:
    with pytest.raises(ExpressionError, match=words):
        parse(text)
