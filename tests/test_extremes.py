"""Stability at the extremes: an accurate answer or a clear error, never a silent NaN.

Independent references:
* Example 1: the paper's Eqs. 24, 25 and 28 typed here and solved in mpmath at
  50 digits (so that near-singular cases have a trustworthy reference);
* Example 2: Eq. 46 and the Eq. 44 energy integral (mpmath tanh-sinh, 30 digits);
  DOP853 at rtol 1e-13 for the period near the separatrix;
* dimensional analysis: scaling every length by s scales the period by sqrt(s),
  the angular acceleration by 1/s and leaves the forces unchanged;
* limits: a disk of vanishing radius leaves a bar pivoted at its end,
  omega^2 = 3 g / (2 l_b) and the compound-pendulum elliptic period with
  l_eq = 2 l_b / 3; a massless bar leaves no restoring moment at all.
"""
from __future__ import annotations

import json
import math
from functools import lru_cache

import mpmath
import numpy as np
import pytest

from references import EX2, elliptic_period, ex2_reference_period
from solver.errors import InputError, NoRestoringError, SceneError
from solver.fidelity import period_to_tolerance
from solver.period import OneDofSystem, exact_period, find_equilibrium
from solver.simulate import period_by_integration, simulate

BAR = "data/scenes/sliding_bar.toml"
DISK = "data/scenes/disk_bar.toml"
EX1 = dict(m_b=50 * 0.45359237, l_b=4 * 0.3048, g=32.174 * 0.3048)


def scene(path, **overrides):
    from solver.scenefile import load_scene

    return load_scene(path, dict(overrides))


@lru_cache(maxsize=None)
def system(path, **overrides) -> OneDofSystem:
    from solver.derivation import derive

    return OneDofSystem.from_derivation(derive(scene(path, **overrides)))


def paper_ex1_mp(theta, beta, p=EX1):
    """(alpha, R_A, R_B) from Eqs. 24, 25, 28 (omega = 0) in mpmath at 50 digits."""
    with mpmath.workdps(50):
        m, l, g = (mpmath.mpf(repr(p[k])) for k in ("m_b", "l_b", "g"))
        th, be = mpmath.mpf(theta), mpmath.mpf(beta)
        c, s = mpmath.cos(th), mpmath.sin(th)
        A = mpmath.matrix([
            [0, mpmath.sin(be), -m * (c / mpmath.tan(be) + s / 2) * l],  # Eq. 24
            [1, mpmath.cos(be), m * c * l / 2],  # Eq. 25
            [0, mpmath.cos(be - th), (mpmath.mpf(1) / 3 - s / 2 * (c / mpmath.tan(be) + s)) * m * l],  # Eq. 28
        ])
        x = mpmath.lu_solve(A, mpmath.matrix([0, m * g, c * m * g / 2]))
        return float(x[2]), float(x[0]), float(x[1])


def instant(**overrides):
    from solver.derivation import solve_instant

    sol = solve_instant(scene(BAR, **overrides))
    return (sol.unknowns["alpha"].to("rad/s**2").magnitude, sol.unknowns["R_A"].to("N").magnitude,
            sol.unknowns["R_B"].to("N").magnitude)


# ------------------------------------------------------------------ Example 1 release angles
@pytest.mark.parametrize("deg", ["1e-6", "0.001", "1", "89", "89.999", "89.9999999", "90"])
def test_release_angles_near_0_and_90_deg(deg):
    alpha, RA, RB = instant(theta=f"{deg} deg")
    ref = paper_ex1_mp(math.radians(float(deg)), math.radians(45))
    W = EX1["m_b"] * EX1["g"]
    # well conditioned here (cond < 1e3): float64 answers good to ~1e-13 of the scale (W, g / l)
    assert abs(RA - ref[1]) <= 1e-12 * W and abs(RB - ref[2]) <= 1e-12 * W
    assert abs(alpha - ref[0]) <= 1e-12 * EX1["g"] / EX1["l_b"]
    if deg == "90":  # vertical bar: Eq. 28 gives alpha = 0, then Eq. 24 R_B = 0 and Eq. 25 R_A = W
        assert abs(alpha) < 1e-12 and abs(RB) < 1e-10 * W and RA == pytest.approx(W, rel=1e-12)


@pytest.mark.parametrize("beta", ["1e-4", "0.5", "179.5", "179.9999"])
def test_rail_angles_near_0_and_180_deg_are_answered_accurately(beta):
    # Rails 1e-4 deg from parallel still fix the bar: an answer is required.
    alpha, RA, RB = instant(beta=f"{beta} deg")
    cond = solve_instant_cond(beta)
    ref = paper_ex1_mp(math.radians(30), math.radians(float(beta)))
    W = EX1["m_b"] * EX1["g"]
    # The 1/sin(beta) in Eqs. 24 and 28 is a scaling of one row, which the solver equilibrates
    # away: the system it solves stays well conditioned (cond ~ 2.6 at every beta here), so
    # float64 is good to cond * eps ~ 1e-15 relative; 1e-13 leaves a factor 100. Reactions are
    # compared on the scale of the weight W (one of them may pass near zero).
    assert cond < 10
    assert abs(alpha - ref[0]) <= 1e-13 * abs(ref[0])
    assert abs(RA - ref[1]) <= 1e-13 * max(abs(ref[1]), W) and abs(RB - ref[2]) <= 1e-13 * max(abs(ref[2]), W)


@pytest.mark.parametrize("beta", ["0", "1e-9", "179.999999999", "180"])
def test_parallel_rails_are_refused(beta):
    # |sin(beta)| below 1e-9 (the scene loader's geometry tolerance): the rails are parallel
    with pytest.raises(SceneError, match=r"constraints\[1\]\.angle: impossible geometry: .* are parallel"):
        instant(beta=f"{beta} deg")


def solve_instant_cond(beta: str) -> float:
    from solver.derivation import solve_instant

    return solve_instant(scene(BAR, beta=f"{beta} deg")).condition_number


# ------------------------------------------------------------------ Example 2 mass ratios and lengths
def eq46_omega(p):
    return math.sqrt((0.5 * p["m_b"] * p["g"] * p["l_b"]) / (
        (1.5 * p["m_d"] + p["m_b"]) * p["r_d"] ** 2 + p["m_b"] * p["l_b"] * (p["l_b"] / 3 - p["r_d"])))


@pytest.mark.parametrize("ratio", [1e-9, 1e-3, 1.0, 1e3, 1e9])
def test_mass_ratios(ratio):
    p = dict(EX2, m_b=ratio * EX2["m_d"])
    s = system(DISK).with_values(m_b=p["m_b"])
    eq = find_equilibrium(s)
    assert eq.omega == pytest.approx(eq46_omega(p), rel=1e-12)  # Eq. 46, rounding only
    a = math.radians(30)
    # requested 1e-11; the reference is good to ~1e-20
    assert exact_period(s, a, tol=1e-11, equilibrium=eq).period == pytest.approx(ex2_reference_period(a, p),
                                                                              rel=2e-11)


@pytest.mark.parametrize("scale", [1e-6, 1e-3, 1e3, 1e6])
def test_lengths_scale_by_dimensional_analysis(scale):
    # Example 2: every length times s -> period times sqrt(s)
    a = math.radians(45)
    base = exact_period(system(DISK), a, tol=1e-12).period
    s = system(DISK, r_d=f"{0.25 * scale} m", l_b=f"{0.2 * scale} m")
    assert exact_period(s, a, tol=1e-12).period == pytest.approx(base * math.sqrt(scale), rel=1e-11)
    # Example 1: alpha times 1/s, forces unchanged
    alpha0, RA0, RB0 = instant()
    alpha, RA, RB = instant(l_b=f"{4 * scale} ft")
    assert alpha == pytest.approx(alpha0 / scale, rel=1e-12)
    assert (RA, RB) == pytest.approx((RA0, RB0), rel=1e-12)


# ------------------------------------------------------------------ amplitudes
@pytest.mark.parametrize("deg", [120.0, 175.0, 179.0])
def test_large_amplitudes(deg):
    a = math.radians(deg)
    res = period_to_tolerance(system(DISK), a, tol=1e-11)
    ref = period_by_integration(system(DISK), a, "DOP853", rtol=1e-13).period
    assert res.model == "elliptic"  # M = A - B cos(theta), V = -C cos(theta): the closed form
    # DOP853 at rtol 1e-13 over half a period: ~1e-11
    assert res.period == pytest.approx(ref, rel=5e-11)


def test_long_run_energy_drift_is_bounded():
    # 1000 periods of Example 2 at 30 deg: compiled rhs, DOP853 at rtol 1e-10
    s = system(DISK)
    a = math.radians(30)
    T = exact_period(s, a, tol=1e-13).period
    res = simulate(s, 1000 * T, y0=(a, 0.0), method="DOP853", rtol=1e-10, atol=1e-12, samples=2001)
    assert res.status == "completed"
    # the chosen bound: 1e3 periods x rtol 1e-10 -> relative energy drift below 1e-7
    assert res.energy_drift < 1e-7
    # and the phase after 1000 exact periods is still at the release point (the period is exact)
    assert res.theta[-1] == pytest.approx(a, abs=1e-5)
    assert np.all(np.isfinite(res.reactions["F_n"]))


# ------------------------------------------------------------------ limits
def test_vanishing_disk_radius_is_a_compound_pendulum():
    s = system(DISK, r_d="1e-9 m")
    l_b, g = EX2["l_b"], EX2["g"]
    # corrections are O(r_d / l_b) = 5e-9
    assert find_equilibrium(s).omega ** 2 == pytest.approx(3 * g / (2 * l_b), rel=1e-7)
    from solver.derivation import natural_frequency

    w = natural_frequency(scene(DISK, r_d="1e-9 m")).omega_n.to("rad/s").magnitude
    assert w**2 == pytest.approx(3 * g / (2 * l_b), rel=1e-7)
    a = math.radians(60)
    compound = elliptic_period(a, 2 * l_b / 3, g)
    assert exact_period(s, a, tol=1e-12).period == pytest.approx(compound, rel=1e-7)


def test_massless_bar_has_no_restoring_moment():
    s = system(DISK).with_values(m_b=0.0)
    for call in (lambda: find_equilibrium(s), lambda: exact_period(s, 0.3),
                 lambda: period_to_tolerance(s, 0.3, tol=1e-3)):
        with pytest.raises(NoRestoringError, match="restoring"):
            call()


@pytest.mark.parametrize("command", [["period", DISK, "--amplitude", "10 deg"], ["frequency", DISK]])
def test_massless_bar_on_the_command_line(solver_cli, command):
    code, _, err = solver_cli(*command, "--set", "m_b=0 kg")
    # A massless element is a legal limit; the answer is "no restoring moment", one line, exit 2.
    assert code == 2 and err.count("\n") == 1 and "restoring" in err
    assert "nan" not in err.lower() or "finite" in err.lower()


def test_no_restoring_force_for_a_length(solver_cli):
    """QA round 9 item 14: a block free on an arm turning at omega in a horizontal plane has no
    potential in its coordinate r, a length. Relative to the arm (QA round 10 item 1) r'' = omega^2 r:
    r = 0 is an equilibrium, unstable, with nothing restoring it; said of r, not as a moment (one
    line, exit 2)."""
    code, _, err = solver_cli("frequency", "tests/data/multibody/arm_block.toml")
    assert code == 2 and err.count("\n") == 1
    assert "(r = 0) is unstable" in err and "moment" not in err


def test_period_input_errors_are_one_line():
    with pytest.raises(InputError, match="separatrix"):
        period_to_tolerance(system(DISK), math.radians(181), tol=1e-6)


@pytest.mark.parametrize("m_b", [1e-12, 1e-100])
def test_tiny_bar_mass_keeps_its_small_restoring_moment(m_b):
    # Regression: `frequency` called V' "zero" when below 1e-13 of V's constant m g r_d
    # (m_b = 1e-12 kg gave "no restoring moment" while `period` answered), and the
    # series coefficient of the period divided by k^2 m0^2, which underflowed at 1e-300 kg
    # (scene values now stop at 1e-100 in SI: the smallest a scene can give is tried).
    from solver.derivation import natural_frequency

    p = dict(EX2, m_b=m_b)
    k = p["m_b"] * p["g"] * p["l_b"] / 2  # V''(0) of V = -m_b g (l_b/2) cos theta
    M0 = 1.5 * p["m_d"] * p["r_d"] ** 2 + p["m_b"] * (p["r_d"] - p["l_b"] / 2) ** 2 + p["m_b"] * p["l_b"] ** 2 / 12
    w = math.sqrt(k / M0)  # Eq. 46 with these values
    got = natural_frequency(scene(DISK, m_b=f"{m_b} kg")).omega_n.to("rad/s").magnitude
    assert got == pytest.approx(w, rel=1e-12)  # closed form; only round-off differs
    res = period_to_tolerance(system(DISK).with_values(m_b=m_b), math.radians(1e-4), tol=1e-10)
    assert res.period == pytest.approx(2 * math.pi / w, rel=1e-10)  # linear model within tol


def test_scene_values_scale_down_to_the_floor_and_stop_there(solver_cli):
    """Mass and length 1e-100 times the paper's (the smallest a scene may give, in SI about 4.5e-101
    kg and 3e-101 m): alpha scales as 1/l and the reactions as m, exactly up to the unit conversions'
    round-off (1e-12 relative). At 1e-150 of each, m*l**2 = 1e-450 would underflow to 0 (the answers
    came out 0.5 % off): refused, one line naming the flag, exit 2."""
    def solve(*sets):
        code, out, err = solver_cli("solve", BAR, "--json", *sets)
        assert code == 0, err
        return {k: v["value"] for k, v in json.loads(out)["unknowns"].items()}

    paper, tiny = solve(), solve("--set", "m_b=5e-99 lbm", "--set", "l_b=4e-100 ft")
    assert tiny["alpha"] == pytest.approx(paper["alpha"] * 1e100, rel=1e-12)
    assert tiny["R_A"] == pytest.approx(paper["R_A"] * 1e-100, rel=1e-12)
    code, out, err = solver_cli("solve", BAR, "--set", "m_b=1e-150 lbm", "--set", "l_b=1e-150 ft")
    assert code == 2 and out == "" and err.count("\n") == 1
    assert "--set m_b: 1e-150 lbm" in err and "at least 1e-100" in err


ROCKER = "data/scenes/rocking_semicircle.toml"


def test_semicircle_beyond_its_rim_is_outside_the_model(solver_cli):
    # Regression: the rocking semicircle was solved past 90 deg, where the straight edge, not
    # the curved rim, meets the floor (the model rolled it on a full circle).
    code, _, err = solver_cli("solve", ROCKER, "--set", "theta=100 deg")
    assert code == 2 and err.count("\n") == 1 and "rim" in err
    s = system(ROCKER)
    assert period_to_tolerance(s, math.radians(89), tol=1e-8).model == "elliptic"  # affine in cos(theta)
    with pytest.raises(InputError, match="rim"):
        period_to_tolerance(s, math.radians(91), tol=1e-8)
    # thrown from the bottom fast enough to reach 90 deg: the run stops there
    res = simulate(s, 2.0, y0=(0.0, 20.0))
    assert res.status == "model_limit"
    assert res.event.theta == pytest.approx(math.pi / 2, abs=1e-9)  # event located to solve_ivp's root tolerance
