"""Example 2 (paper Eqs. 31-46): the disk-bar system, three routes, closed forms.

References:
* The equation of motion from Lagrange's equation via sympy.physics.mechanics
  (method="lagrange"), which is independent of the Newton-Euler code.
* The closed form of Eq. (44) with the sign of F_a corrected: Lagrange's
  generalized force of F_a i at P (x_P = r_d theta, Eq. 31) is +F_a r_d, so
      [(3/2 m_d + m_b) r_d^2 + 1/3 m_b l_b^2 - m_b r_d l_b cos th] th''
      + 1/2 m_b r_d l_b sin th th'^2 + 1/2 m_b g l_b sin th = +F_a r_d.
  The paper prints -F_a r_d (Eq. 44): Eq. 39 has F_f = (...) - F_a, and
  substituting it into Eq. 42 gives "- F_a" inside the bracket of Eq. 43,
  not "+ F_a". We do NOT encode the printed sign as truth.
* Eqs. (39), (40) for the reactions (printed correctly).
* Eq. (46) for the natural frequency.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from solver.derivation import METHODS, derive, natural_frequency, solve_instant
from solver.errors import NoRestoringError
from solver.units import Q_

from scenes_factory import example2

ROOT = Path(__file__).resolve().parents[1]
S = lambda n: sp.Symbol(n, real=True)  # noqa: E731
m_d, r_d, m_b, l_b, g, F_a = (S(n) for n in ("m_d", "r_d", "m_b", "l_b", "g", "F_a"))
th, thd, thdd = S("theta"), S("theta_dot"), S("theta_ddot")

# Eq. (44), sign of F_a corrected (see module docstring).
EOM_CLOSED = (
    ((sp.Rational(3, 2) * m_d + m_b) * r_d**2 + sp.Rational(1, 3) * m_b * l_b**2 - m_b * r_d * l_b * sp.cos(th)) * thdd
    + sp.Rational(1, 2) * m_b * r_d * l_b * sp.sin(th) * thd**2
    + sp.Rational(1, 2) * m_b * g * l_b * sp.sin(th)
    - F_a * r_d
)
# Eq. (44) exactly as printed (right-hand side -F_a r_d): known to be wrong in F_a's sign.
EOM_AS_PRINTED = EOM_CLOSED + 2 * F_a * r_d
# Eq. (46)
OMEGA_N_EQ46 = sp.sqrt(
    sp.Rational(1, 2) * m_b * g * l_b
    / ((sp.Rational(3, 2) * m_d + m_b) * r_d**2 + m_b * l_b * (sp.Rational(1, 3) * l_b - r_d))
)


def is_zero(expr) -> bool:
    """Exact symbolic zero test: expand + trigsimp, then simplify if needed."""
    e = sp.trigsimp(sp.expand(expr))
    return e == 0 or sp.simplify(e) == 0


@pytest.fixture(scope="module")
def scene():
    return example2()


@pytest.fixture(scope="module")
def file_scene():
    try:
        from solver.scenefile import load_scene
    except ImportError:  # pragma: no cover
        pytest.skip("scene loader not available")
    return load_scene(ROOT / "data/scenes/disk_bar.toml")


@pytest.mark.parametrize("method", ["generalized_euler", "mass_center"])
def test_eom_equals_lagrange_symbolically(scene, method):
    ours = derive(scene, "P", method).eom
    independent = derive(scene, method="lagrange").eom
    assert is_zero(ours - independent)


@pytest.mark.parametrize("method", METHODS)
def test_eom_equals_corrected_eq44(scene, method):
    eom = derive(scene, "P", method).eom
    assert is_zero(eom - EOM_CLOSED)
    # ... and it is NOT the printed Eq. (44) (the tests can tell the sign of F_a apart)
    assert not is_zero(eom - EOM_AS_PRINTED)


def test_file_scene_eom_equals_lagrange(file_scene):
    ours = derive(file_scene, None, "generalized_euler").eom
    assert is_zero(ours - derive(file_scene, None, "lagrange").eom)
    assert is_zero(ours - EOM_CLOSED)


def test_generalized_mass_is_eq44_bracket(scene):
    # M(q) from the kinetic energy equals the coefficient of theta_ddot in Eq. (44)
    for method in METHODS:
        assert is_zero(derive(scene, "P", method).mass - EOM_CLOSED.coeff(thdd))


@pytest.mark.parametrize("point", ["P", "Q", "C"])
def test_reactions_match_eqs_39_40(point):
    # A moving state with a push: every term of Eqs. (39)-(40) is exercised.
    scene = example2(theta_deg=25.0, theta_dot=1.3, values={"F_a": Q_(3.0, "N")})
    sol = solve_instant(scene, point)
    vals = dict(scene.si_values()) | {th: np.radians(25.0), thd: 1.3}
    qdd = sol.unknowns["theta_ddot"].to("rad/s**2").magnitude
    vals[thdd] = qdd
    # Eq. (39): F_f + F_a = (m_d + m_b) r_d th'' + 1/2 m_b l_b (th'^2 sin th - th'' cos th)
    F_f = (m_d + m_b) * r_d * thdd + m_b * l_b * (thd**2 * sp.sin(th) - thdd * sp.cos(th)) / 2 - F_a
    # Eq. (40): F_n = (m_d + m_b) g + 1/2 m_b l_b (th'^2 cos th + th'' sin th)
    F_n = (m_d + m_b) * g + m_b * l_b * (thd**2 * sp.cos(th) + thdd * sp.sin(th)) / 2
    # 1e-9: double-precision solve of a well-conditioned 3x3 (cond < 10), no model error
    assert sol.unknowns["F_f"].to("N").magnitude == pytest.approx(float(F_f.subs(vals)), rel=1e-9)
    assert sol.unknowns["F_n"].to("N").magnitude == pytest.approx(float(F_n.subs(vals)), rel=1e-9)
    # and theta_ddot satisfies the corrected Eq. (44)
    assert float(EOM_CLOSED.subs(vals)) == pytest.approx(0.0, abs=1e-9)
    # alpha = -theta_ddot (omega = -theta_dot k, Eq. 33)
    assert sol.unknowns["alpha"].magnitude == pytest.approx(-qdd, rel=1e-12)


def test_push_to_the_right_increases_theta():
    # From rest at theta = 0 a push +F_a i at P must give theta_ddot > 0 (x_P = r_d theta).
    scene = example2(theta_deg=0.0, values={"F_a": Q_(5.0, "N")})
    assert solve_instant(scene).unknowns["theta_ddot"].magnitude > 0


def test_natural_frequency_eq46(scene):
    res = natural_frequency(scene)
    vals = dict(scene.si_values())
    # 1e-10: same formula evaluated in floats; the equilibrium search is exact here (theta_e = 0)
    assert res.omega_n.to("rad/s").magnitude == pytest.approx(float(OMEGA_N_EQ46.subs(vals)), rel=1e-10)
    assert res.equilibrium.to("rad").magnitude == pytest.approx(0.0, abs=1e-12)
    # symbolic: V''(0) / M(0) is Eq. (46) squared
    d = derive(scene)
    w2 = sp.diff(d.potential_energy, th, 2).subs(th, 0) / d.mass.subs(th, 0)
    assert is_zero(w2 - OMEGA_N_EQ46**2)


def test_massless_bar_has_no_restoring_moment():
    scene = example2(values={"m_b": Q_(0.0, "kg")})
    with pytest.raises(NoRestoringError, match="restoring"):
        natural_frequency(scene)
