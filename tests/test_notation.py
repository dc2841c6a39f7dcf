"""Dotted rates in LaTeX and MathML: the dots over the name's nucleus, the subscript beside it.

The reference is sympy's own notation for a name with a modifier, which puts the accent on the
nucleus before the subscript (``Symbol("thdot_1")`` prints ``\\dot{th}_{1}``): for each coordinate
name, the product's dotted name of ``th1`` must equal sympy's print of ``thdot_1``. Before, the
dot covered the whole subscripted name (``\\dot{th_{1}}``).
"""
from __future__ import annotations

import xml.dom.minidom

import sympy as sp
import pytest

from solver.mathml import mathml_body
from solver.notation import dotted_latex

# (coordinate name, the same name with sympy's modifier before the subscript)
NAMES = [("theta", "theta{}"), ("x", "x{}"), ("th1", "th{}_1"), ("theta_A", "theta{}_A"),
         ("phi12", "phi{}_12"), ("Th_2", "Th{}_2")]


@pytest.mark.parametrize("name,modified", NAMES)
@pytest.mark.parametrize("accent", ["dot", "ddot"])
def test_dotted_latex_is_sympys_modifier_notation(name, modified, accent):
    assert dotted_latex(sp.Symbol(name), accent) == sp.latex(sp.Symbol(modified.format(accent)))


@pytest.mark.parametrize("name,nucleus,sub", [("th1_dot", "th", "1"), ("theta_A_ddot", "\u03b8", "A")])
def test_mathml_dots_the_nucleus_and_keeps_the_subscript(name, nucleus, sub):
    """The MathML tree: msub(mover(nucleus, accent), subscript), not mover(msub(...), accent)."""
    dom = xml.dom.minidom.parseString(f"<math>{mathml_body(sp.Symbol(name))}</math>")
    top = dom.documentElement.firstChild
    assert top.tagName == "msub", top.toxml()
    over, subscript = top.childNodes
    assert over.tagName == "mover" and over.firstChild.firstChild.data == nucleus, top.toxml()
    assert subscript.firstChild.data == sub


# --- MathML read back as arithmetic: a printed formula must have its expression's value ---------

_INVISIBLE_TIMES = "\u2062"


def _mathml_value(node, env):
    """The value a reader gets from presentation MathML (the subset printed for sums, products,
    quotients, powers and roots of named numbers), reading the brackets and signs as shown."""
    tag, kids = node.tagName, [k for k in node.childNodes if k.nodeType == k.ELEMENT_NODE]
    if tag == "mi":
        return env[node.firstChild.data]
    if tag == "mn":
        return float(node.firstChild.data.replace("\u2212", "-"))  # a sign shown as the minus sign
    if tag == "mfrac":
        return _mathml_value(kids[0], env) / _mathml_value(kids[1], env)
    if tag == "msup":
        return _mathml_value(kids[0], env) ** _mathml_value(kids[1], env)
    if tag == "msqrt":
        return _row_value(kids, env) ** 0.5
    assert tag == "mrow", node.toxml()
    return _row_value(kids, env)


def _row_value(kids, env):
    """An infix row: sums of products of factors, a unary minus, brackets as <mo> pairs. An
    inner <mrow> groups nothing a reader sees, so its tokens join the row's."""
    tokens = _row_tokens(kids)
    position = 0

    def peek():
        return tokens[position] if position < len(tokens) else None

    def take():
        nonlocal position
        position += 1
        return tokens[position - 1]

    def factor():
        token = take()
        if token == "\u2212":
            return -factor()
        if token == "(":
            inner = expression()
            assert take() == ")"
            return inner
        assert not isinstance(token, str), token
        return _mathml_value(token, env)

    def product():
        result = factor()
        while peek() in (_INVISIBLE_TIMES, "(") or not isinstance(peek(), (str, type(None))):
            if peek() == _INVISIBLE_TIMES:  # a reader multiplies factors set side by side too
                take()
            result *= factor()
        return result

    def expression():
        result = product()
        while peek() in ("+", "\u2212"):
            result = result + product() if take() == "+" else result - product()
        return result

    result = expression()
    assert peek() is None, tokens
    return result


def _row_tokens(kids):
    tokens = []
    for kid in kids:
        if kid.tagName == "mrow":
            tokens.extend(_row_tokens([k for k in kid.childNodes if k.nodeType == k.ELEMENT_NODE]))
        else:
            tokens.append(kid.firstChild.data if kid.tagName == "mo" else kid)
    return tokens


def _printed_value(expr, env):
    body = mathml_body(expr).replace("&InvisibleTimes;", _INVISIBLE_TIMES)
    return _mathml_value(xml.dom.minidom.parseString(body).documentElement, env)


_A, _B, _C = sp.symbols("a b c")
_ENV = {"a": 1.25, "b": -0.75, "c": 2.5}


def _unevaluated():
    """Expressions as the worked solution builds them, unevaluated: sums, differences,
    negations and products of names with small rational coefficients."""
    from hypothesis import strategies as st
    leaves = st.sampled_from([_A, _B, _C, 2 * _A, 3 * _C, -_B, _A / 2])

    def grow(inner):
        pair = st.tuples(inner, inner)
        return st.one_of(
            pair.map(lambda p: sp.Add(*p, evaluate=False)),
            pair.map(lambda p: sp.Add(p[0], sp.Mul(-1, p[1], evaluate=False), evaluate=False)),
            pair.map(lambda p: sp.Mul(*p, evaluate=False)),
            inner.map(lambda e: sp.Mul(-1, e, evaluate=False)))
    return st.recursive(leaves, grow, max_leaves=8)


def test_a_negated_sum_is_printed_in_brackets():
    """QA 19 #1: -(a + b) and a - (b - c) were printed as -a + b and a - b - c, so the HTML
    worked solution of slider_crank showed the piston's velocity with wrong signs."""
    assert _printed_value(sp.Mul(-1, _A + _B, evaluate=False), _ENV) == -(1.25 - 0.75)
    difference = sp.Add(_A, sp.Mul(-1, _B - _C, evaluate=False), evaluate=False)
    assert _printed_value(difference, _ENV) == 1.25 - (-0.75 - 2.5)


def test_every_printed_formula_has_its_expressions_value():
    """Read back by the precedence rules a reader applies, each printed formula has the value of
    the expression it shows. The tolerance is a few round-offs of sums of at most 8 terms of size
    at most 3**8 (the terms are about 1)."""
    from hypothesis import given, settings

    @settings(max_examples=150, deadline=None)  # (trees of up to 8 leaves from 7: 150 cover the
    # shapes that matter, a minus before a sum at the top, inside a sum and under a product)
    @given(_unevaluated())
    def check(expr):
        expected = float(expr.subs({_A: sp.Rational(5, 4), _B: sp.Rational(-3, 4), _C: sp.Rational(5, 2)}))
        assert _printed_value(expr, _ENV) == pytest.approx(expected, rel=1e-12, abs=1e-9), mathml_body(expr)
    check()

