"""Element mass properties against direct integration, and Eqs. 12-13 for composites.

References: the mass centre and centroidal moment of inertia of each shape
computed here by numerical quadrature over its area/length with uniform
density (scipy.integrate), independent of the textbook formulas in
solver/model/elements.py.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import integrate

from solver.model.bodies import RigidBody
from solver.model.elements import ELEMENT_CLASSES


def Element(name, kind, mass, center, angle=sp.Integer(0), dims=None):
    return ELEMENT_CLASSES[kind](name, mass, sp.Matrix(center), angle, dict(dims or {}))

# quad/dblquad on smooth integrands reach ~1e-12; 1e-9 leaves room, and any
# wrong formula factor (1/12 vs 1/3, 4/(3 pi) vs 1/2, ...) is off by > 1e-2.
RTOL = 1e-9

M, L, R, W, H = 2.5, 1.3, 0.7, 0.9, 0.4  # arbitrary mass [kg] and dimensions [m]


def numeric_properties(kind):
    """(x_G, y_G, I_G) by quadrature, shape in its own frame (reference point at 0)."""
    if kind == "slender_bar":  # along x from -L/2 to L/2
        lam = M / L
        xg = integrate.quad(lambda s: lam * s, -L / 2, L / 2)[0] / M
        I0 = integrate.quad(lambda s: lam * s * s, -L / 2, L / 2)[0]
        return xg, 0.0, I0 - M * xg**2
    if kind == "uniform_disk":
        sig = M / (math.pi * R**2)
        I0 = integrate.dblquad(lambda r, p: sig * r**3, 0, 2 * math.pi, 0, R)[0]
        return 0.0, 0.0, I0
    if kind == "thin_ring":
        lam = M / (2 * math.pi * R)
        I0 = integrate.quad(lambda p: lam * R**3, 0, 2 * math.pi)[0]
        return 0.0, 0.0, I0
    if kind == "rectangular_plate":  # width along x, height along y
        sig = M / (W * H)
        I0 = integrate.dblquad(lambda y, x: sig * (x * x + y * y), -W / 2, W / 2, -H / 2, H / 2)[0]
        return 0.0, 0.0, I0
    if kind == "semicircular_disk":  # straight edge on the y axis, bulging towards +x
        sig = M / (math.pi * R**2 / 2)
        p0, p1 = -math.pi / 2, math.pi / 2
        xm = integrate.dblquad(lambda r, p: sig * r * math.cos(p) * r, p0, p1, 0, R)[0] / M
        I0 = integrate.dblquad(lambda r, p: sig * r**3, p0, p1, 0, R)[0]
        return xm, 0.0, I0 - M * xm**2
    if kind == "point_mass":
        return 0.0, 0.0, 0.0
    raise AssertionError(kind)


DIMS = {
    "slender_bar": {"length": L},
    "uniform_disk": {"radius": R},
    "thin_ring": {"radius": R},
    "rectangular_plate": {"width": W, "height": H},
    "point_mass": {},
    "semicircular_disk": {"radius": R},
}


@pytest.mark.parametrize("kind", list(DIMS))
def test_element_properties_match_integration(kind):
    xg, yg, I_G = numeric_properties(kind)
    # place the element at (0.3, -0.2), rotated by 0.6 rad: the centre offset must rotate with it
    ang = 0.6
    e = Element("e", kind, sp.Float(M), sp.Matrix([0.3, -0.2]), sp.Float(ang),
                {k: sp.Float(v) for k, v in DIMS[kind].items()})
    p = e
    c = np.array([0.3, -0.2]) + np.array([[math.cos(ang), -math.sin(ang)], [math.sin(ang), math.cos(ang)]]) @ [xg, yg]
    np.testing.assert_allclose(np.array(p.mass_center, dtype=float).ravel(), c, rtol=RTOL, atol=1e-12)
    assert float(p.I_G) == pytest.approx(I_G, rel=RTOL, abs=1e-12)
    assert float(p.mass) == M


def test_semicircular_disk_formulas_exact():
    r, m = sp.symbols("r m", positive=True)
    p = Element("s", "semicircular_disk", m, sp.zeros(2, 1), sp.Integer(0), {"radius": r})
    assert sp.simplify(p.mass_center[0] - 4 * r / (3 * sp.pi)) == 0
    assert sp.simplify(p.I_G - (sp.Rational(1, 2) - 16 / (9 * sp.pi**2)) * m * r**2) == 0


coord = st.floats(-2, 2, allow_nan=False).map(lambda v: sp.Rational(round(v * 100), 100))
pos = st.integers(1, 300).map(lambda v: sp.Rational(v, 100))


@st.composite
def elements(draw):
    kind = draw(st.sampled_from(list(DIMS)))
    dims = {k: draw(pos) for k in DIMS[kind]}
    return Element(f"e{draw(st.integers(0, 10**6))}", kind, draw(pos), sp.Matrix([draw(coord), draw(coord)]),
                   draw(coord), dims)


# 30 composite bodies of 1-4 elements of every kind (exact rationals, ~15 ms each): enough that
# each element kind appears in several mixtures and offsets every run.
@settings(max_examples=30)
@given(st.lists(elements(), min_size=1, max_size=4), coord, coord)
def test_composite_parallel_axis(elems, px, py):
    """Eq. 12 summed over elements equals I_G + m |r_G - r_P|^2 with G from Eq. 13."""
    body = RigidBody("b", tuple(elems))
    P = sp.Matrix([px, py])
    G = body.mass_center()
    d = G - P
    lhs = body.inertia_about(P)
    rhs = body.centroidal_inertia() + body.total_mass * (d[0] ** 2 + d[1] ** 2)
    # an algebraic identity in the (cos, sin) of the element angles: expand is exact
    assert sp.expand(lhs - rhs) == 0
    # Eq. 13: m r_G = sum m_k r_k  <=>  first moment about G vanishes
    assert sp.expand(body.first_moment_about(G)) == sp.zeros(2, 1)
