"""Friction needed for rolling (Example 2) and release angles keeping contact (Example 1).

Independent references, typed from the paper here:
* Example 2: theta_dot^2 = 2 (V(theta0) - V) / M with M, V of Eq. 44 (F_a = 0),
  theta_ddot from Eq. 44, F_f from Eq. 39, F_n from Eq. 40; the maximum of
  |F_f| / F_n by brute force over 400001 angles;
* Example 1: R_A, R_B, alpha from the 3x3 system of Eqs. 24, 25 and 28
  (omega = 0 at release), solved by numpy on a grid; at theta = 90 deg
  Eq. 28 gives alpha = 0 and Eq. 24 then R_B = 0 for every beta.
"""
from __future__ import annotations

import json
import math
from functools import lru_cache

import numpy as np
import pytest

from solver.errors import InputError
from solver.friction import friction_map, least_friction, release_window
from solver.period import OneDofSystem

DISK = "data/scenes/disk_bar.toml"
BAR = "data/scenes/sliding_bar.toml"
EX2 = dict(m_d=4.0, r_d=0.25, m_b=1.5, l_b=0.2, g=9.80665)
# Example 1 in SI: 50 lbm, 4 ft, 32.174 ft/s^2 (exact unit definitions)
EX1 = dict(m_b=50 * 0.45359237, l_b=4 * 0.3048, g=32.174 * 0.3048)


@lru_cache(maxsize=None)
def system(path: str, **overrides) -> OneDofSystem:
    from solver.derivation import derive
    from solver.scenefile import load_scene

    return OneDofSystem.from_derivation(derive(load_scene(path, dict(overrides))))


def brute_mu(amplitude: float, p=EX2) -> float:
    md, rd, mb, lb, g = (p[k] for k in ("m_d", "r_d", "m_b", "l_b", "g"))
    th = np.linspace(-amplitude, amplitude, 400001)
    s, c = np.sin(th), np.cos(th)
    M = (1.5 * md + mb) * rd**2 + mb * lb**2 / 3 - mb * rd * lb * c
    w2 = np.maximum(mb * g * lb * (c - math.cos(amplitude)) / M, 0.0)  # energy: V = -m_b g l_b cos / 2
    qdd = (-0.5 * mb * rd * lb * s * w2 - 0.5 * mb * g * lb * s) / M  # Eq. 44, F_a = 0
    F_f = (md + mb) * rd * qdd + 0.5 * mb * lb * (w2 * s - qdd * c)  # Eq. 39
    F_n = (md + mb) * g + 0.5 * mb * lb * (w2 * c + qdd * s)  # Eq. 40
    return float(np.max(np.abs(F_f) / F_n))


@pytest.mark.parametrize("deg", [5.0, 60.0, 120.0, 170.0])
@pytest.mark.parametrize("ratio", [0.01, 0.375, 10.0])
def test_least_mu_against_paper_equations(deg, ratio):
    p = dict(EX2, m_b=ratio * EX2["m_d"])
    s = system(DISK).with_values(m_b=p["m_b"])
    res = least_friction(s, math.radians(deg))
    # the brute-force grid (spacing ~1e-5 rad) finds the maximum of a smooth ratio to ~1e-9 relative;
    # the refined search is exact to the optimiser's 1e-12 rad
    assert res.mu_min == pytest.approx(brute_mu(math.radians(deg), p), rel=1e-7)
    assert not res.lifts_off and res.normal > 0


def test_friction_map_is_the_table_of_least_mu():
    s = system(DISK)
    amps = [math.radians(10), math.radians(90)]
    fmap = friction_map(s, amps, [0.1, 1.0])
    assert fmap.mu_min.shape == (2, 2)
    for i, r in enumerate([0.1, 1.0]):
        p = dict(EX2, m_b=r * EX2["m_d"])
        for j, a in enumerate(amps):
            assert fmap.mu_min[i, j] == pytest.approx(brute_mu(a, p), rel=1e-7)
    # larger swings need more friction, at both ratios
    assert np.all(fmap.mu_min[:, 1] > fmap.mu_min[:, 0])


def test_least_mu_needs_a_rolling_contact():
    with pytest.raises(InputError, match="rolling"):
        least_friction(system(BAR), 0.2)


def paper_ex1(theta, beta, p=EX1):
    """(R_A, R_B, alpha) at release from rest by Eqs. 24, 25 and 28."""
    m, l, g = p["m_b"], p["l_b"], p["g"]
    theta = np.atleast_1d(theta)
    out = []
    for th in theta:
        A = np.array([
            [0.0, math.sin(beta), -m * (math.cos(th) / math.tan(beta) + 0.5 * math.sin(th)) * l],  # Eq. 24
            [1.0, math.cos(beta), 0.5 * m * math.cos(th) * l],  # Eq. 25
            [0.0, math.cos(beta - th),
             (1 / 3 - 0.5 * math.sin(th) * (math.cos(th) / math.tan(beta) + math.sin(th))) * m * l],  # Eq. 28
        ])
        b = np.array([0.0, m * g, 0.5 * math.cos(th) * m * g])
        out.append(np.linalg.solve(A, b))
    return np.array(out).T


@pytest.mark.parametrize("beta_deg", [10.0, 45.0, 80.0, 120.0])
def test_release_window_against_eqs_24_25_28(beta_deg):
    beta = math.radians(beta_deg)
    win = release_window(system(BAR, beta=f"{beta_deg} deg"), search_range=(math.radians(1), math.radians(179)))
    grid = np.radians(np.linspace(1.0, 179.0, 7121))
    grid = grid[np.abs(np.cos(beta - grid)) > 1e-3]  # stay off the paper system's own singular angles
    R_A, R_B, _ = paper_ex1(grid, beta)
    inside = (R_A >= 0) & (R_B >= 0)
    mine = np.array([win.contains(x) for x in grid])
    # grid points closer than 1e-9 rad to an edge may fall either way
    edges = np.array([e for iv in win.intervals for e in (iv.low, iv.high)])
    near = np.min(np.abs(grid[:, None] - edges[None, :]), axis=1) < 1e-9
    assert np.array_equal(inside[~near], mine[~near])
    # at each edge that a reaction bounds, Eqs. 24/25/28 give that reaction = 0
    weight = EX1["m_b"] * EX1["g"]
    for iv in win.intervals:
        for x, why in ((iv.low, iv.low_reason), (iv.high, iv.high_reason)):
            if why.endswith("= 0"):
                R = dict(zip(("R_A", "R_B"), paper_ex1(x, beta)[:2, 0]))
                assert abs(R[why.split()[0]]) < 1e-9 * weight


def test_vertical_bar_edge_is_exactly_90_deg():
    win = release_window(system(BAR))
    ends = [iv.high for iv in win.intervals if iv.high_reason == "R_B = 0"]
    assert any(abs(e - math.pi / 2) < 1e-12 for e in ends)  # root found to brentq's xtol


def test_cli_friction_both_modes(solver_cli):
    code, out, _ = solver_cli("friction", DISK, "--amplitude", "60 deg", "--mass-ratio", "0.375", "--json")
    assert code == 0
    data = json.loads(out)
    assert data["mode"] == "rolling"
    assert data["mu_min"][0][0] == pytest.approx(brute_mu(math.radians(60)), rel=1e-7)
    code, out, _ = solver_cli("friction", BAR, "--json")
    data = json.loads(out)
    assert data["mode"] == "release"
    assert data["intervals"][0]["high"]["value"] == pytest.approx(90.0, abs=1e-9)
    code, out, err = solver_cli("friction", BAR, "--reactions", "R_X")
    assert code == 2 and "R_X" in err


ROCKER = "data/scenes/rocking_semicircle.toml"


def rocker_brute_mu(amplitude: float, m=1.2, r=0.1, g=9.80665, n=400001) -> float:
    """max |F_f| / F_n for the rocking semicircle (scene values), by energy + Newton on G on a grid.

    O = (r theta, r), G = O + c(-sin, -cos), c = 4 r / (3 pi), I_G = (1/2 - 16/(9 pi^2)) m r^2."""
    c = 4 * r / (3 * math.pi)
    th = np.linspace(-amplitude, amplitude, n)
    M = m * (r * r - 2 * r * c * np.cos(th) + c * c) + (0.5 - 16 / (9 * math.pi**2)) * m * r * r
    w2 = np.maximum(2 * m * g * c * (np.cos(th) - math.cos(amplitude)) / M, 0.0)
    al = -(m * r * c * np.sin(th) * w2 + m * g * c * np.sin(th)) / M
    Ff = m * (r * al - c * (np.cos(th) * al - np.sin(th) * w2))
    Fn = m * g + m * c * (np.sin(th) * al + np.cos(th) * w2)
    return float(np.max(np.abs(Ff) / Fn))


def test_friction_uses_the_scenes_masses_when_it_has_no_mass_ratio():
    # Regression: a rolling scene without m_b, m_d (the default --ratio-of) was refused
    # ("no parameter 'm_b'") even when no mass ratio was asked for.
    fmap = friction_map(system(ROCKER), [math.radians(30)])
    assert fmap.ratio_of == () and fmap.to_dict()["mass_ratio"] is None
    # grid of 4e5 points on a smooth maximum: agreement to ~1e-9
    assert fmap.mu_min[0, 0] == pytest.approx(rocker_brute_mu(math.radians(30)), rel=1e-8)


def test_ratio_of_a_mass_and_a_length_is_refused(solver_cli):
    # Regression: --ratio-of m_d/l_b --mass-ratio 2 set the disk's mass to "2 x 0.2 m" silently.
    code, _, err = solver_cli("friction", DISK, "--amplitude", "30 deg", "--ratio-of", "m_d/l_b", "--mass-ratio", "2")
    assert code == 2 and err.count("\n") == 1 and "same kind" in err
