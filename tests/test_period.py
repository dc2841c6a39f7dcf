"""Exact period by the energy integral (solver.period) and model selection (solver.fidelity).

Independent routes used as references:
* simple / compound pendulum: T = 4 K(m) sqrt(l_eq / g), m = sin^2(theta0 / 2)
  (complete elliptic integral, scipy.special.ellipkm1 with 1 - m = cos^2(theta0/2)
  so that amplitudes near 180 deg keep full precision);
* Example 2: M(theta) and V(theta) typed from the paper's Eq. 44 (F_a = 0) and
  the singular energy integral evaluated by mpmath's tanh-sinh quadrature at
  30 digits (no substitution, no code shared with solver.period);
* Eq. 46 for the linearized frequency; c2 = 1/16 for the pendulum (textbook
  series T = T0 (1 + theta0^2 / 16 + ...)).
"""
from __future__ import annotations

import json
import math
from functools import lru_cache

import mpmath
import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from references import EX2, elliptic_period, ex2_reference_period
from solver.errors import InputError, NoRestoringError
from solver.fidelity import amplitude_coefficient, period_to_tolerance
from solver.period import OneDofSystem, exact_period, find_equilibrium
from solver.simulate import period_by_integration

q, qd, qdd, t = sp.symbols("theta theta_dot theta_ddot t", real=True)
m, l, g = sp.symbols("m l g", real=True)

SCENE = "data/scenes/disk_bar.toml"


def pendulum(length=1.5, gravity=9.81, mass=2.0) -> OneDofSystem:
    return OneDofSystem(q, qd, qdd, t, mass=m * l**2, potential=-m * g * l * sp.cos(q),
                        params=(m, l, g), values=(mass, length, gravity), name="pendulum")


def eq46_period(p=EX2) -> float:
    """Paper Eq. 46: omega_n^2 = (m_b g l_b / 2) / ((3/2 m_d + m_b) r_d^2 + m_b l_b (l_b / 3 - r_d))."""
    w2 = (0.5 * p["m_b"] * p["g"] * p["l_b"]) / (
        (1.5 * p["m_d"] + p["m_b"]) * p["r_d"] ** 2 + p["m_b"] * p["l_b"] * (p["l_b"] / 3 - p["r_d"]))
    return 2 * math.pi / math.sqrt(w2)


@lru_cache(maxsize=None)
def ex2_system() -> OneDofSystem:
    from solver.derivation import derive
    from solver.scenefile import load_scene

    return OneDofSystem.from_derivation(derive(load_scene(SCENE)))


# ------------------------------------------------------------------ closed forms
@pytest.mark.parametrize("deg", [0.5, 10.0, 90.0, 150.0, 170.0, 179.0, 179.9])
def test_pendulum_period_matches_elliptic_integral(deg):
    a = math.radians(deg)
    res = exact_period(pendulum(), a, tol=1e-12)
    # tol 1e-12 requested; allow 5x for the reference's own rounding (ellipkm1 ~1e-15) and the estimate
    np.testing.assert_allclose(res.period, elliptic_period(a, 1.5, 9.81), rtol=5e-12)
    assert res.error_estimate <= 1e-12
    np.testing.assert_allclose(res.period_linear, 2 * math.pi * math.sqrt(1.5 / 9.81), rtol=1e-14)


# 30 pendulums spread over 6 decades of length, 3 of gravity and 0.1-178 deg either side
# (~35 ms each: the product's exact period against the elliptic-integral reference).
@settings(max_examples=30)
@given(length=st.floats(1e-3, 1e3), gravity=st.floats(0.1, 100.0), deg=st.floats(0.1, 178.0),
       sign=st.sampled_from([1.0, -1.0]))
def test_pendulum_period_property(length, gravity, deg, sign):
    a = sign * math.radians(deg)
    res = exact_period(pendulum(length, gravity), a, tol=1e-10)
    # the requested tolerance, with a factor 2 for the reference's rounding
    np.testing.assert_allclose(res.period, elliptic_period(abs(a), length, gravity), rtol=2e-10)


def test_compound_pendulum():
    # a uniform bar of length L pivoted at one end: M = m L^2 / 3, V = -m g L cos / 2 -> l_eq = 2 L / 3
    L = 0.8
    s = OneDofSystem(q, qd, qdd, t, mass=m * l**2 / 3, potential=-m * g * l / 2 * sp.cos(q),
                     params=(m, l, g), values=(3.0, L, 9.80665))
    a = math.radians(120)
    np.testing.assert_allclose(exact_period(s, a, tol=1e-12).period, elliptic_period(a, 2 * L / 3, 9.80665),
                               rtol=5e-12)


def test_asymmetric_potential_against_integration():
    # M and V without symmetry (turning points not symmetric): independent route = DOP853 between turning points
    s = OneDofSystem(q, qd, qdd, t, mass=2 + sp.sin(q) / 2, potential=1 - sp.cos(q) + sp.Rational(3, 10) * q**3,
                     name="asym")
    for a in (0.4, -0.6):
        res = exact_period(s, a, tol=1e-12)
        lo, hi = res.turning_points
        assert abs(abs(lo) - abs(hi)) > 1e-3  # really asymmetric
        ref = period_by_integration(s, a, "DOP853", rtol=1e-13).period
        # DOP853 at rtol 1e-13 over one period is good to ~1e-11
        np.testing.assert_allclose(res.period, ref, rtol=1e-10)


# ------------------------------------------------------------------ Example 2 (the scene)
@pytest.mark.parametrize("deg", [5.0, 60.0, 170.0])
def test_example2_period_against_eq44_energy_integral(deg):
    a = math.radians(deg)
    res = exact_period(ex2_system(), a, tol=1e-12)
    # mpmath tanh-sinh at 30 digits is good to ~1e-20; the limit is the requested 1e-12
    np.testing.assert_allclose(res.period, ex2_reference_period(a), rtol=2e-12)
    # linearized period is Eq. 46 (to rounding)
    np.testing.assert_allclose(res.period_linear, eq46_period(), rtol=1e-13)


def test_example2_linear_period_equals_natural_frequency():
    from solver.derivation import natural_frequency
    from solver.scenefile import load_scene

    fr = natural_frequency(load_scene(SCENE))
    np.testing.assert_allclose(find_equilibrium(ex2_system()).period, fr.period.to("s").magnitude, rtol=1e-12)


@pytest.mark.parametrize("deg", [180.0, 200.0, -180.0])
def test_separatrix_is_refused(deg):
    with pytest.raises(InputError, match="separatrix"):
        exact_period(ex2_system(), math.radians(deg))


def test_bad_tolerance_and_no_restoring():
    with pytest.raises(InputError, match="tolerance"):
        exact_period(pendulum(), 0.3, tol=1e-20)
    flat = OneDofSystem(q, qd, qdd, t, mass=sp.Integer(1), potential=sp.Integer(0))
    with pytest.raises(NoRestoringError):
        exact_period(flat, 0.3)


# ------------------------------------------------------------------ fidelity
def test_amplitude_coefficient_closed_forms():
    # pendulum: T = T0 (1 + a^2/16 + ...)
    assert amplitude_coefficient(pendulum()).c2 == pytest.approx(1 / 16, rel=1e-14)
    # Example 2: M = M0 + B (1 - cos), V = -C cos -> c2 = 1/16 + B / (8 M0), B = m_b r_d l_b
    p = EX2
    M0 = (1.5 * p["m_d"] + p["m_b"]) * p["r_d"] ** 2 + p["m_b"] * p["l_b"] ** 2 / 3 - p["m_b"] * p["r_d"] * p["l_b"]
    B = p["m_b"] * p["r_d"] * p["l_b"]
    assert amplitude_coefficient(ex2_system()).c2 == pytest.approx(1 / 16 + B / (8 * M0), rel=1e-12)


def test_amplitude_coefficient_asymmetric_against_quadrature():
    # (T(a)/T0 - 1)/a^2 -> c2 as a -> 0; the symmetric average removes the a^3 term
    s = OneDofSystem(q, qd, qdd, t, mass=2 + sp.sin(q) / 2, potential=1 - sp.cos(q) + sp.Rational(3, 10) * q**3)
    c2 = amplitude_coefficient(s).c2
    a = 1e-2
    Tp, Tm = exact_period(s, a, tol=1e-14), exact_period(s, -a, tol=1e-14)
    est = ((Tp.period + Tm.period) / 2 / Tp.period_linear - 1) / a**2
    # O(a^2) = 1e-4 relative remainder of the series, on c2 ~ 0.1
    assert est == pytest.approx(c2, rel=1e-3, abs=1e-6)


# Example 2's M and V are affine in cos(theta): beyond the linear model's reach the closed
# form in elliptic integrals answers (it meets any tolerance down to its round-off, 3.6e-15)
@pytest.mark.parametrize("deg,tol,model", [(0.5, 1e-4, "linear"), (0.5, 1e-12, "elliptic"),
                                           (60.0, 1e-3, "elliptic")])
def test_fidelity_picks_cheapest_model_that_meets_tol(deg, tol, model):
    a = math.radians(deg)
    res = period_to_tolerance(ex2_system(), a, tol=tol)
    assert res.model == model
    err = abs(res.period - ex2_reference_period(a)) / ex2_reference_period(a)
    assert err <= tol
    assert err <= res.error_estimate * 1.01 + 1e-15  # the estimate is an upper bound


def test_fidelity_integration_model():
    a = math.radians(40)
    res = period_to_tolerance(ex2_system(), a, tol=1e-8, model="integration")
    assert res.model == "integration"
    np.testing.assert_allclose(res.period, ex2_reference_period(a), rtol=1e-8)


# ------------------------------------------------------------------ command line
def test_cli_period_json(solver_cli):
    code, out, _ = solver_cli("period", SCENE, "--amplitude", "30 deg", "--tol", "1e-11", "--json")
    assert code == 0
    data = json.loads(out)
    assert data["period"]["unit"] == "s" and data["period_linear"]["unit"] == "s"
    ref = ex2_reference_period(math.radians(30))
    np.testing.assert_allclose(data["period"]["value"], ref, rtol=1e-11)
    np.testing.assert_allclose(data["period_linear"]["value"], eq46_period(), rtol=1e-13)
    assert data["ratio"] == pytest.approx(ref / eq46_period(), rel=1e-11)
    assert data["model"] in ("linear", "elliptic", "quadrature", "integration")
    assert 0 <= data["error_estimate"] <= 1e-11


@pytest.mark.parametrize("degrees, step", [(120.0, 1e-6), (179.0, 1e-7)])
def test_amplitude_sensitivity_is_the_periods_condition_number(solver_cli, degrees, step):
    """`period` reports kappa = (a / T) dT/da, the relative change of the period per relative change
    of the amplitude: near the separatrix it is large, and the amplitude's own rounding then limits
    what any model can give. Reference: a central difference of the 30-digit mpmath quadrature of
    the energy integral (Eqs. 44-46), with a step well inside the distance to the separatrix; its
    error is about (step kappa)**2 + 1e-16 / step, under 1e-6 here. 1e-4: the product's own
    difference (of periods to 1e-12) carries up to ~1e-6."""
    a = math.radians(degrees)
    T = ex2_reference_period(a)
    kappa = a / T * (ex2_reference_period(a * (1 + step)) - ex2_reference_period(a * (1 - step))) / (2 * a * step)
    code, out, err = solver_cli("period", SCENE, "--amplitude", f"{degrees} deg", "--tol", "1e-12", "--json")
    assert code == 0, err
    assert json.loads(out)["amplitude_sensitivity"] == pytest.approx(kappa, rel=1e-4)


def test_amplitude_rounding_beyond_the_tolerance_is_said(solver_cli):
    """At 179.9999999 deg the period is so sensitive (kappa ~ 1e8) that the amplitude's own rounding
    (2**-52) moves it by ~2e-8, beyond the requested 1e-12: the text says so."""
    code, out, err = solver_cli("period", SCENE, "--amplitude", "179.9999999 deg", "--tol", "1e-12")
    assert code == 0, err
    assert "more than the tolerance: the period of the amplitude as typed is known only that closely" in out


def test_cli_period_units_and_errors(solver_cli):
    code, out, _ = solver_cli("period", SCENE, "--amplitude", "0.5 rad", "--json")
    assert json.loads(out)["period"]["value"] == pytest.approx(ex2_reference_period(0.5), rel=1e-10)
    code, out, err = solver_cli("period", SCENE, "--amplitude", "185 deg")
    assert code == 2 and err.count("\n") == 1 and "separatrix" in err and "Traceback" not in err
    code, out, err = solver_cli("period", SCENE, "--amplitude", "3 kg")
    assert code == 2 and "--amplitude" in err


@pytest.mark.parametrize("deg", [1e-9, -1e-6, 1e-3])
def test_tiny_amplitudes_are_small_oscillations_not_the_separatrix(deg):
    # Regression: below ~1e-7 deg float64 cannot resolve V(a) - V(0) ~ k a^2 / 2, and the
    # release was refused as "at the separatrix"; the turning points came out up to 16% off.
    s = pendulum()
    a = math.radians(deg)
    T0 = 2 * math.pi * math.sqrt(1.5 / 9.81)  # linearized pendulum
    auto = period_to_tolerance(s, a, tol=1e-12)
    quad = period_to_tolerance(s, a, tol=1e-12, model="quadrature")
    for res in (auto, quad):
        # series T = T0 (1 + a^2/16): at most 2e-8 relative at 1e-3 deg; quadrature to 1e-12
        assert res.period == pytest.approx(T0 * (1 + a**2 / 16), rel=1e-11)
        # symmetric potential: turning points -|a|, +|a| (mpmath root, 1e-9 relative)
        assert res.turning_points[0] == pytest.approx(-abs(a), rel=1e-9)
        assert res.turning_points[1] == pytest.approx(abs(a), rel=1e-9)


def test_a_time_dependent_load_set_to_zero_leaves_a_free_oscillation():
    # Regression: Q = F l cos(t) with F = 0 (what the error message tells the user to do with
    # --set) still counted as time-dependent, so `period` kept refusing.
    F = sp.Symbol("F", real=True)
    base = dict(mass=m * l**2, potential=-m * g * l * sp.cos(q), generalized_force=F * l * sp.cos(t),
                params=(m, l, g, F), name="forced pendulum")
    off = OneDofSystem(q, qd, qdd, t, values=(2.0, 1.5, 9.81, 0.0), **base)
    a = math.radians(60)
    assert exact_period(off, a, tol=1e-12).period == pytest.approx(elliptic_period(a, 1.5, 9.81), rel=1e-11)
    on = off.with_values(F=1.0)  # shares the compiled code: must not reuse the F = 0 potential
    with pytest.raises(InputError, match="depends on the rate or on time"):
        exact_period(on, a)


def test_flat_minimum_is_no_restoring_moment_not_an_internal_error():
    # Regression: V = theta^6 has V' ~ x^5 at its minimum; brentq (xtol 1e-300) gave up with a
    # RuntimeError (an "internal error" on the command line). V''(0) = 0: no linear oscillation.
    flat6 = OneDofSystem(q, qd, qdd, t, mass=sp.Integer(1), potential=q**6, name="flat")
    with pytest.raises(NoRestoringError, match="no stable equilibrium"):
        find_equilibrium(flat6, near=0.1)


# ------------------------------------------------------------------ closed form (elliptic integrals)
def test_closed_form_agrees_with_the_quadrature_at_every_amplitude():
    # Example 2 (M = A - B cos, V = -C cos) admits the closed form in R_F and R_J. Against
    # the solver's own quadrature route (midpoint rule in u, cancellation-free differences) at
    # every degree 1..179: 1e-13 relative, the proof of the closed form (both are
    # good to ~1e-15; the quadrature's tolerance 1e-14 keeps its own error below that).
    s = ex2_system()
    eq = find_equilibrium(s)
    for deg in range(1, 180):
        a = math.radians(deg)
        closed = exact_period(s, a, tol=1e-12, equilibrium=eq)
        quad = exact_period(s, a, tol=1e-14, equilibrium=eq, method="quadrature")
        assert closed.model == "elliptic" and quad.model == "quadrature"
        assert abs(closed.period - quad.period) <= 1e-13 * quad.period, deg
        assert closed.turning_points == pytest.approx((-a, a), abs=1e-15)


@pytest.mark.parametrize("deg", [1.0, 5.0, 60.0, 120.0, 170.0, 179.0])
def test_closed_form_against_mpmath(deg):
    # the independent reference: the raw singular integral by mpmath's tanh-sinh at 30
    # digits (tests/references.py). 1e-13: the closed form's round-off is ~4e-15.
    a = math.radians(deg)
    res = exact_period(ex2_system(), a, tol=1e-12)
    assert res.model == "elliptic" and res.error_estimate <= 1e-14
    ref = ex2_reference_period(a)
    assert abs(res.period - ref) <= 1e-13 * ref


@pytest.mark.parametrize("deg", [1.0, 5.0, 170.0, 179.0])
def test_quadrature_meets_1e12_in_float64_at_the_extremes(deg):
    # Regression: the float64 round-off estimate switched to mpmath at small and large
    # amplitudes (25-60 ms a call); with cancellation-free differences the float64 sum meets
    # 1e-12 (against the mpmath reference above, 1e-12 relative as requested).
    a = math.radians(deg)
    res = exact_period(ex2_system(), a, tol=1e-12, method="quadrature")
    assert res.precision == "float64"
    ref = ex2_reference_period(a)
    assert abs(res.period - ref) <= 1e-12 * ref
    assert abs(res.period - ref) <= res.error_estimate * ref * 1.01 + 1e-15 * ref  # the estimate bounds it


def test_closed_form_only_where_the_structure_admits_it():
    from solver.period import elliptic_form

    # a torsional spring adds k q^2 / 2 to V: not affine in cos and sin, quadrature
    spring = OneDofSystem(q, qd, qdd, t, mass=sp.Integer(2), potential=1 - sp.cos(q) + q**2 / 4)
    assert elliptic_form(spring, find_equilibrium(spring)) is None
    assert exact_period(spring, 0.5, tol=1e-10).model == "quadrature"
    # M with a sin term out of phase with V's cosine: no closed form of this kind
    tilted = OneDofSystem(q, qd, qdd, t, mass=2 + sp.sin(q) / 2, potential=1 - sp.cos(q))
    assert elliptic_form(tilted, find_equilibrium(tilted)) is None
    # V = -C cos(q - phi) with M in phase: the closed form about the shifted equilibrium,
    # against the quadrature (1e-12 requested of both)
    phase = sp.Rational(1, 3)
    shifted = OneDofSystem(q, qd, qdd, t, mass=3 - sp.cos(q - phase),
                           potential=-2 * sp.cos(q) * sp.cos(phase) - 2 * sp.sin(q) * sp.sin(phase))
    eq = find_equilibrium(shifted)
    assert eq.q == pytest.approx(1 / 3, abs=1e-12)
    closed = exact_period(shifted, 1.0, tol=1e-12, equilibrium=eq)
    quad = exact_period(shifted, 1.0, tol=1e-12, equilibrium=eq, method="quadrature")
    assert closed.model == "elliptic"
    assert closed.period == pytest.approx(quad.period, rel=2e-12)
    # forcing the closed form where there is none is refused in one line
    with pytest.raises(InputError, match="no closed form"):
        exact_period(spring, 0.5, method="elliptic")
    # the separatrix is refused by the closed form too
    with pytest.raises(InputError, match="separatrix"):
        exact_period(ex2_system(), math.radians(180.0))


def test_cli_period_names_the_closed_form(solver_cli):
    code, out, _ = solver_cli("period", SCENE, "--amplitude", "30 deg", "--tol", "1e-12")
    assert code == 0 and "model: elliptic (closed form" in out
    code, out, _ = solver_cli("period", SCENE, "--amplitude", "30 deg", "--tol", "1e-12", "--model", "quadrature",
                              "--json")
    assert code == 0 and json.loads(out)["model"] == "quadrature"


def _mpmath_period(mass, potential, q_e, amplitude):
    """The raw singular energy integral by mpmath's tanh-sinh at 30 digits, the far turning
    point by mpmath's root finder (nothing from solver.period)."""
    with mpmath.workdps(30):
        M, V = (sp.lambdify(q, e, "mpmath") for e in (mass, potential))
        q0 = mpmath.mpf(q_e) + mpmath.mpf(amplitude)
        q1 = mpmath.findroot(lambda x: V(x) - V(q0), 2 * mpmath.mpf(q_e) - q0)
        lo, hi = sorted((q0, q1))

        def f(x):
            dV = V(q0) - V(x)
            return mpmath.sqrt(M(x) / (2 * dV)) if dV > 0 else mpmath.mpf(0)

        return float(2 * mpmath.quad(f, [lo, (lo + hi) / 2, hi]))


# Potentials without a closed form, where the float64 potential difference is hardest: a
# tilted cosine (equilibrium at pi/6, V' of its two terms nearly cancel for small swings:
# the difference sums terms of both signs) and a spring plus gravity, at 1 and 60 deg.
@pytest.mark.parametrize("deg", [1.0, -1.0, 60.0])
@pytest.mark.parametrize("name", ["tilted", "spring"])
def test_quadrature_in_float64_against_mpmath_without_closed_form(name, deg):
    mass, potential = {"tilted": (2 + sp.cos(q) / 2, -sp.cos(q) - q / 2),
                       "spring": (sp.Integer(2), 1 - sp.cos(q) + q**2 / 4)}[name]
    s = OneDofSystem(q, qd, qdd, t, mass=mass, potential=potential, name=name)
    eq = find_equilibrium(s)
    a = math.radians(deg)
    res = exact_period(s, a, tol=1e-12, equilibrium=eq, method="quadrature")
    assert res.model == "quadrature" and res.precision == "float64"
    ref = _mpmath_period(mass, potential, eq.q, a)
    # 1e-12 requested; the 30-digit reference is good to ~1e-25; the estimate bounds the error
    assert abs(res.period - ref) <= 1e-12 * ref
    assert abs(res.period - ref) <= res.error_estimate * ref * 1.01 + 1e-15 * ref


def test_mpmath_quadrature_keeps_the_release_point_exact():
    # Regression: the mpmath sum took the higher turning point as exact; released at -179 deg
    # that is the float64 root, and its rounding (an ulp) moved the period by 4e-15 near the
    # separatrix. Against the 30-digit reference (good to ~4e-16 here, see the closed form
    # test), 1e-15 requested.
    a = math.radians(-179.0)
    res = exact_period(ex2_system(), a, tol=1e-15, method="quadrature", precision="mpmath")
    assert res.precision == "mpmath"
    ref = ex2_reference_period(abs(a))
    assert abs(res.period - ref) <= 1e-15 * ref


@pytest.mark.parametrize("expr", [-3 * sp.cos(q), sp.sin(q) * sp.cos(q), sp.exp(q) / q, sp.sqrt(2 + sp.sin(q)),
                                  q**3 - sp.cos(q - sp.Rational(1, 3)), sp.log(2 + q) * q**-2,
                                  sp.cosh(q) * sp.atan(q), sp.tan(q) + sp.sinh(q)])
def test_potential_difference_keeps_its_relative_accuracy(expr):
    # V(q_ref) - V(q) for q_ref - q = 2e-7 (a node next to a turning point): the plain float64
    # difference keeps ~9 digits; the rewritten one agrees with 40-digit mpmath to a few ulps
    # times B / |D| (its own round-off measure). 16 ulps: the deepest expression here has ~8
    # rounded operations on the path to D.
    from solver.period import _HALF, _difference

    D, B = _difference(expr, q)
    x, H = 0.3, 1e-7  # both exact enough: the reference takes the same float64 numbers
    value = float(sp.lambdify((q, _HALF), D, "math")(x, H))
    size = abs(value) if B is None else float(sp.lambdify((q, _HALF), B, "math")(x, H))
    with mpmath.workdps(40):
        f = sp.lambdify(q, expr, "mpmath")
        exact = float(f(mpmath.mpf(x) + 2 * mpmath.mpf(H)) - f(mpmath.mpf(x)))
    assert abs(value - exact) <= 16 * np.finfo(float).eps * size


TORSION_PENDULUM = "tests/data/multibody/torsion_pendulum.toml"


def torsion_pendulum_reference(a: float) -> float:
    """Period [s] of tests/data/multibody/torsion_pendulum.toml released from rest at ``a``,
    by scipy.integrate.quad of the energy integral, typed from the scene by hand.

    M = m L^2 / 3 (slender bar about its end), V = -m g L / 2 cos q + kt q^2 / 2, and
    T = 4 int_0^a sqrt(M / (2 (V(a) - V(q)))) dq. With q = a sin u the end point's
    1/sqrt singularity goes: dq = a cos u du and V(a) - V(q) = cos^2 u h(u), where
    h = m g L sin(a (1 + s) / 2) sin(a c^2 / (2 (1 + s))) / c^2 + kt a^2 / 2 (s = sin u,
    c = cos u; cos q - cos a as a product, 1 - s = c^2 / (1 + s), no cancellation).
    """
    from scipy.integrate import quad

    mass, length, gravity, kt = 2.0, 0.8, 9.81, 10.0
    inertia = mass * length**2 / 3

    def h(u):
        s, c = math.sin(u), math.cos(u)
        gravity_part = mass * gravity * length * math.sin(a * (1 + s) / 2) * math.sin(a * c * c / (2 * (1 + s)))
        return gravity_part / (c * c) + kt * a * a / 2

    value, error = quad(lambda u: math.sqrt(inertia / (2 * h(u))), 0.0, math.pi / 2, epsabs=0.0, epsrel=1e-13)
    assert error < 1e-12 * value  # the integrand is smooth: quad's own estimate is far below the test's tolerance
    return 4 * a * value


@pytest.mark.parametrize("deg", [30.0, 90.0])
def test_period_of_a_pendulum_with_a_torsional_spring(solver_cli, deg):
    # QA round 9 item 4: a lone parameter factor (kt in V' = ... + kt q) was left symbolic in
    # the compiled potential, so the well scan computed with sympy objects (over 20 s of CPU,
    # then "cannot determine truth value of Relational", exit 1).
    code, out, err = solver_cli("period", TORSION_PENDULUM, "--amplitude", f"{deg} deg", "--tol", "1e-12", "--json")
    assert code == 0, err
    res = json.loads(out)
    assert res["model"] == "quadrature"  # kt q^2 / 2 is not affine in cos q and sin q: no closed form
    ref = torsion_pendulum_reference(math.radians(deg))
    # 1e-12 requested; twice that for the reference (quad to ~1e-14) and the printing of JSON floats
    assert res["period"]["value"] == pytest.approx(ref, rel=2e-12)
    # the linearized period: 2 pi sqrt(M / V''(0)), V''(0) = m g L / 2 + kt (exact arithmetic)
    T0 = 2 * math.pi * math.sqrt((2.0 * 0.8**2 / 3) / (2.0 * 9.81 * 0.8 / 2 + 10.0))
    assert res["period_linear"]["value"] == pytest.approx(T0, rel=1e-14)  # a few roundings of the same formula
    if deg == 90.0:
        assert round(ref, 5) == 1.03736  # the QA tester's own quadrature at 90 deg, to the 6 figures reported


def _bits(v: float):
    """A float's bits (any nan as one value: the payload is not an answer)."""
    import struct

    return "nan" if math.isnan(v) else struct.pack("<d", v)


_ENTRY = st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.sampled_from([0.0, -0.0, 1.0, -1.0, 2.0, -2.0]))


@settings(max_examples=200)
@given(st.lists(_ENTRY, min_size=12, max_size=12))
def test_the_written_out_3x3_elimination_is_the_general_one_bit_for_bit(entries):
    """The event functions' 3x3 solve (``period._eliminate3``, written out for speed) must give the
    general elimination's numbers (``period._eliminate`` with n = 3) to the last bit: A row by row
    then b, with zeros, signed zeros, ties between pivots (the small integers), infinities and nan.
    The general one is held to numpy's solve below."""
    from solver.period import _eliminate, _eliminate3

    x3, det3 = _eliminate3(list(entries))
    x, det = _eliminate(list(entries), 3)
    assert [_bits(v) for v in [*x3, det3]] == [_bits(v) for v in [*x, det]]


def test_the_general_elimination_solves_as_numpy_does():
    """``period._eliminate`` against numpy's LAPACK solve on a well-conditioned 3x3 system (cond
    about 10): agreement to 1e-14 relative (a few roundings of double precision times cond), and
    the determinant of the row-scaled matrix."""
    from solver.period import _eliminate

    A = np.array([[4.0, -1.0, 0.5], [2.0, 5.0, -1.0], [-1.0, 0.25, 3.0]])
    b = np.array([1.0, -2.0, 0.5])
    x, det = _eliminate([*A.ravel(), *b], 3)
    assert np.allclose(x, np.linalg.solve(A, b), rtol=1e-14, atol=0)
    scaled = A / np.abs(A).max(axis=1, keepdims=True)
    assert det == pytest.approx(np.linalg.det(scaled), rel=1e-14)
