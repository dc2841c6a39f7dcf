"""solver.model.system.derivative and second_derivative give exactly what sympy.diff gives.

The reference is sympy's own ``diff`` (the path it shortens); "exactly" is the same tree
(``srepr``), not only an equal value, since the displays print these trees as they are. The
expressions: the model's own (every point velocity and acceleration of the shipped scenes, in each
coordinate, rate and t), nodes the fast path hands back to sympy (an undefined function, whose
derivative stays unevaluated; Abs, sign and a Derivative itself), and random sums, products and
powers of sin, cos, exp, sqrt and Abs of the symbols.
"""
from __future__ import annotations

from pathlib import Path

import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from solver.io.scenes import load_system
from solver.model.system import derivative, second_derivative
from trees import same_tree

ROOT = Path(__file__).resolve().parents[1]
x, y = sp.symbols("x y", real=True)
t = sp.Symbol("t")


def _same(e, v) -> None:
    assert same_tree(derivative(e, v), sp.diff(e, v))


def _same_second(e, v) -> None:
    assert same_tree(second_derivative(e, v), sp.diff(e, v, 2))


@pytest.mark.parametrize("scene", ["sliding_bar", "disk_bar", "slider_crank", "four_bar", "double_pendulum"])
def test_model_expressions(scene):
    system = load_system(ROOT / "data" / "scenes" / f"{scene}.toml")
    symbols = [*system.q, *system.qd, system.t]
    checked = 0
    for body, b in system.bodies.items():
        for point in b.point_names():
            for vector in (system.point_position(body, point), system.point_velocity(body, point)):
                for e in vector:
                    for v in symbols:
                        _same(e, v)
                        checked += 1
    assert checked > 0


@pytest.mark.parametrize("scene", ["sliding_bar", "disk_bar", "slider_crank", "four_bar", "wheel_on_incline",
                                   "crate_tipping"])
def test_second_derivative_of_kinetic_energy(scene):
    """The generalized masses d2T/dqd2 (wheel_on_incline: sympy's closing factor_terms(signsimp(...))
    changes its signs; crate_tipping: a sum whose first derivative is not a sum)."""
    system = load_system(ROOT / "data" / "scenes" / f"{scene}.toml")
    T = system.kinetic_energy()
    for v in system.qd:
        _same_second(T, v)


@pytest.mark.parametrize("e", [
    sp.Function("f")(x) * sp.sin(x),      # an unevaluated Derivative in the result: sympy's diff
    sp.Abs(x - y) + sp.sign(x),           # sympy's own rules for them
    sp.Derivative(sp.Function("f")(x), x),
    sp.Integer(3), sp.sin(y), x**x, sp.exp(x * y) / (1 + x**2),
    sp.oo * x * y, sp.zoo * y * sp.sin(x),  # a product with an infinite factor: the zero terms are not 0
])
def test_special_nodes(e):
    _same(e, x)
    _same_second(e, x)


leaves = st.sampled_from([x, y, sp.Integer(2), sp.Rational(-1, 3), sp.Float(0.5), sp.pi])
functions = [sp.sin, sp.cos, sp.exp, sp.sqrt, sp.Abs]
trees = st.recursive(leaves, lambda inner: st.one_of(
    st.tuples(inner, inner).map(lambda p: p[0] + p[1]),
    st.tuples(inner, inner).map(lambda p: p[0] * p[1]),
    st.tuples(inner, st.sampled_from([-2, -1, 2, 3])).map(lambda p: p[0] ** p[1]),
    st.tuples(st.sampled_from(functions), inner).map(lambda p: p[0](p[1])),
), max_leaves=8)


@settings(max_examples=150, deadline=None)  # 150 trees: about 1 s
@given(trees)
def test_random_trees(e):
    _same(e, x)
    _same_second(e, x)


def test_a_zero_term_is_left_out_only_where_sympy_makes_it_zero():
    """A Leibniz term whose differentiated factor is 0 is 0 unless another factor can be infinite,
    where sympy makes it nan: beside oo, zoo or a symbol assumed infinite the derivative is still
    sympy's own tree (nan included), and so is a 2-vector scaled by such a factor."""
    from solver.model.joints import vec, vscale, xy

    big = sp.Symbol("big", infinite=True)
    for e in (big * x * y, sp.oo * x * sp.sin(y), sp.zoo * x * y ** 2, x * y * sp.cos(x) ** 2,
              x / y * sp.sin(y), x * t * sp.exp(y)):
        for v in (x, y):
            _same(e, v)
    assert sp.diff(big * x * y, x) is sp.nan  # (the case the shortcut must leave to sympy: 0 times an infinity)
    for k in (big, sp.oo, x * sp.sin(y) + 2, t):
        for v in ((0, y), (x, 0), (0, 0)):
            assert [sp.srepr(c) for c in xy(vscale(k, vec(*v)))] == [sp.srepr(k * sp.Integer(c) if c == 0 else k * c)
                                                                    for c in v]
