"""Friction and contact regimes (stick, slip, separation) against closed forms and
independent integrations built here.

Every answer is read through the command line (``solver_cli``, in process) from
the shipped scenes, with ``--set`` to move parameters. References:

* the ladder's critical angle, tan(theta) = (1 - mu_A mu_B) / (2 mu_A);
* the crate's thresholds: sliding at P = mu_s m g, tipping at P = m g w / (2 h);
* a disk with backspin: rolling starts at t* = (v0 + r w0) / (3 mu g) with
  speed (2 v0 - r w0) / 3; the friction's work is -m (v0 + r w0)^2 / 6;
* the least mu on an incline: tan(beta) / 3 for a disk, tan(beta) / 2 for a ring;
* a frictionless ladder leaves the wall at sin(theta) = (2/3) sin(theta0).

Tolerances: the closed forms hold to 1e-10 relative. The onsets are roots
found by brentq to ~1e-15 of smooth margins; the switch times are event
roots of DOP853 dense output run at rtol 1e-11, atol 1e-13, so their error
is ~1e-12; 1e-10 leaves two orders of margin while any wrong term (a factor,
a sign, mu_k for mu_s) is off by percents.
"""
from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest
from scipy.integrate import solve_ivp

G = 9.80665
REL = 1e-10


def _json(solver_cli, *argv):
    code, out, err = solver_cli(*argv)
    assert code == 0, err
    return json.loads(out)


@pytest.mark.parametrize("mu_a, mu_b", [(0.3, 0.2), (0.5, 0.0), (0.25, 0.6)])
def test_ladder_critical_angle(solver_cli, mu_a, mu_b):
    out = _json(solver_cli, "friction", "data/scenes/ladder_friction.toml", "--set", f"mu_A={mu_a}",
                "--set", f"mu_B={mu_b}", "--critical", "theta", "--between", "5", "89.5", "--json")
    onsets = out["critical"]["onsets"]
    # one onset in range: both ends slip together below it
    assert len(onsets) == 1 and not onsets[0]["starts"], onsets
    assert set(onsets[0]["regimes"].values()) == {"slip + (impending)"}
    expected = math.degrees(math.atan((1 - mu_a * mu_b) / (2 * mu_a)))
    assert onsets[0]["value"] == pytest.approx(expected, rel=REL)
    assert out["critical"]["throughout"] is None  # the regime changes in the range


# Why the ladder slips, or stands, at every angle of 5..89 deg. With both frictions at their
# limits (the wall's helping most, F_B = mu_B N_B up): horizontally F_A = N_B, vertically
# N_A + mu_B N_B = m g, moments about the foot N_B (sin + mu_B cos) = (m g / 2) cos, so
# N_B = m g / (2 (tan + mu_B)), and the floor holds, F_A <= mu_A N_A, exactly when
#     2 mu_A tan(theta) >= 1 - mu_A mu_B.
# mu_A = 0.001 (mu_B = 0.2 as in the scene): tan(theta) >= 0.9998 / 0.002 = 499.9, theta >= 89.885 deg:
#     at 89 deg tan = 57.3 falls short, so both ends slip (the foot out, + along the floor; the top
#     down, + along the wall's -y) at every angle of the range.
# mu_A = 2, mu_B = 0.6: 4 tan(theta) >= 1 - 1.2 = -0.2 holds for every tan > 0 (at 5 deg, 0.35 >= -0.2):
#     every contact sticks throughout.
@pytest.mark.parametrize("sets, throughout, words", [
    (("mu_A=0.001",), {"floor": "slip +", "wall": "slip +"},
     "floor slips (+ along its line), wall slips (+ along its line) throughout"),
    (("mu_A=2", "mu_B=0.6"), {"floor": "stick", "wall": "stick"}, "every contact sticks throughout"),
])
def test_ladder_regime_throughout_a_range_without_onsets(solver_cli, sets, throughout, words):
    argv = ["friction", "data/scenes/ladder_friction.toml", "--critical", "theta", "--between", "5 deg", "89 deg"]
    for s in sets:
        argv += ["--set", s]
    out = _json(solver_cli, *argv, "--json")["critical"]
    assert out["onsets"] == [] and out["throughout"] == throughout
    code, text, err = solver_cli(*argv)
    assert code == 0, err
    assert f"no regime change in the range: from rest, {words}" in text


def test_ladder_sticks_above_and_slips_below_the_critical_angle(solver_cli):
    crit = math.degrees(math.atan((1 - 0.3 * 0.2) / (2 * 0.3)))
    above = _json(solver_cli, "solve", "data/scenes/ladder_friction.toml", "--set", f"theta={crit + 0.5} deg", "--json")
    below = _json(solver_cli, "solve", "data/scenes/ladder_friction.toml", "--set", f"theta={crit - 0.5} deg", "--json")
    assert {v["regime"] for v in above["regime"].values()} == {"stick"} and "indeterminate" in above
    assert above["unknowns"]["theta_ddot"]["value"] == 0.0
    assert {v["regime"] for v in below["regime"].values()} == {"slip +"}
    # sliding: each friction force is mu_k N against the sliding (mu_k = mu_s here)
    u = below["unknowns"]
    assert abs(u["F_A"]["value"]) == pytest.approx(0.3 * u["N_A"]["value"], rel=1e-12)
    assert abs(u["F_B"]["value"]) == pytest.approx(0.2 * u["N_B"]["value"], rel=1e-12)
    assert u["theta_ddot"]["value"] < 0  # the ladder falls


# Statically indeterminate sticking (a body held by more contacts than it has freedoms). The
# shown split must be the physics' one: the equations about any point P, and the mass-centre form,
# have the same solutions, so one rule (the least-squeeze split: least SI norm among the splits
# inside every cone by SPLIT_MARGIN of the largest force) gives one answer. Before, a linear
# programme's vertex depended on how the rows were written: N_A 111.722 N about A, 111.695 N about G.
# Tolerance 1e-9 relative: the split comes from an SVD and a few 1-by-1 or 2-by-2 solves of
# well-conditioned equations (round-off ~1e-14); the defect moved the forces by 2e-4 to 4e-3.
SPLIT_REL = 1e-9
SPLIT_MARGIN = 1e-3  # the rule's margin, as solver.analyses.regimes.SPLIT_MARGIN states it


@pytest.mark.parametrize("scene, runs", [
    ("ladder_friction", [("--point", "A"), ("--point", "B"), ("--point", "G"), ("--point", "ladder:I(N_A,N_B)"),
                         ("--method", "mass_center"), ("--method", "lagrange")]),
    ("crate_tipping", [("--point", "A"), ("--point", "B"), ("--point", "G"), ("--point", "Q"),
                       ("--method", "mass_center")]),
])
def test_indeterminate_split_is_the_same_about_every_point(solver_cli, scene, runs):
    path = f"data/scenes/{scene}.toml"
    shown = [_json(solver_cli, "solve", path, *run, "--json") for run in runs]
    assert all("indeterminate" in s for s in shown)
    first = shown[0]["unknowns"]
    for run, s in zip(runs[1:], shown[1:]):
        for name, entry in s["unknowns"].items():
            assert entry["value"] == pytest.approx(first[name]["value"], rel=SPLIT_REL, abs=0.0), (run, name)
    # simulate (a run that stays at rest) shows the same split, about another point
    final = _json(solver_cli, "simulate", path, "--t-end", "0.1", "--samples", "3", "--point", runs[2][1],
                  "--json")["final"]
    for name in ("N_A", "N_B", "F_A", "F_B"):
        assert final[name]["value"] == pytest.approx(first[name]["value"], rel=SPLIT_REL), name


def _least_norm_split(E, e, cones, margin_of):
    """By hand, for one free direction: x = x0 + p z (x0 = pinv(E) e, z spans E's null space);
    ``cones`` the rows g of g.x <= -margin; the least |x| is the least |p| in the interval the
    rows allow, since x0 is orthogonal to z. Returns x0 and the split."""
    x0 = np.linalg.pinv(E) @ e
    z = np.linalg.svd(E)[2][-1]
    assert np.allclose(E @ z, 0.0, atol=1e-12)  # one free direction
    margin = margin_of(x0)
    lo, hi = -math.inf, math.inf
    for g in cones:  # g.(x0 + p z) <= -margin
        gz, rest = g @ z, -margin - g @ x0
        assert gz != 0 or rest >= 0
        if gz > 0:
            hi = min(hi, rest / gz)
        else:
            lo = max(lo, rest / gz)
    assert lo <= hi
    return x0, x0 + min(max(0.0, lo), hi) * z


def test_ladder_at_rest_shows_the_least_norm_split_inside_the_cones(solver_cli):
    """The ladder of ladder_friction.toml at 60 deg, its equilibrium written here. Unknowns
    (N_A, F_A, N_B, F_B) with the scene's directions: N_A up and F_A along +x at the foot A
    (the origin), N_B along +x and F_B along -y at the top B = (-L cos, L sin):
        x:             F_A + N_B = 0
        y:             N_A - F_B = m g
        moments at A:  L cos F_B - L sin N_B = -m g L cos / 2
    Least norm of this one-parameter family, by hand: F_B = p, N_A = m g + p, N_B = -F_A =
    cot (p + m g / 2), and d|x|^2/dp = 0 gives p = -m g / 2: N_A = m g / 2, F_B = -m g / 2,
    N_B = F_A = 0, outside the wall's cone (|F_B| > mu_B N_B = 0). So the rule takes the least
    norm among the splits inside every cone by d = SPLIT_MARGIN * m g / 2 (the largest force of
    the least-norm split): the wall's lower bound binds, -F_B = mu_B N_B - d, which gives
        F_B = (d - mu_B cot m g / 2) / (1 + mu_B cot)."""
    m, L, mu_a, mu_b, th = 12.0, 5.0, 0.3, 0.2, math.radians(60.0)
    c, s, W = math.cos(th), math.sin(th), m * G
    E = np.array([[0.0, 1.0, 1.0, 0.0], [1.0, 0.0, 0.0, -1.0], [0.0, 0.0, -L * s, L * c]])
    e = np.array([0.0, W, -W * L * c / 2])
    cones = [np.array(g, float) for g in (  # G x <= -d: N >= d, +-F - mu N <= -d
        [-1, 0, 0, 0], [0, 0, -1, 0], [-mu_a, 1, 0, 0], [-mu_a, -1, 0, 0], [0, 0, -mu_b, 1], [0, 0, -mu_b, -1])]
    x0, split = _least_norm_split(E, e, cones, lambda x0: SPLIT_MARGIN * np.abs(x0).max())
    np.testing.assert_allclose(x0, [W / 2, 0.0, 0.0, -W / 2], atol=1e-12 * W)  # the hand result
    d, cot = SPLIT_MARGIN * W / 2, c / s
    assert split[3] == pytest.approx((d - mu_b * cot * W / 2) / (1 + mu_b * cot), rel=1e-12)
    out = _json(solver_cli, "solve", "data/scenes/ladder_friction.toml", "--point", "G", "--json")["unknowns"]
    x = np.array([out[n]["value"] for n in ("N_A", "F_A", "N_B", "F_B")])
    np.testing.assert_allclose(x, split, rtol=SPLIT_REL)
    np.testing.assert_allclose(E @ x, e, rtol=0, atol=1e-12 * W)  # the equations hold (round-off)
    assert all(g @ x <= -d * (1 - 1e-9) for g in cones)  # every cone, by the margin


def test_crate_at_rest_shows_the_least_norm_split_when_it_is_inside_the_cones(solver_cli):
    """The crate of crate_tipping.toml pushed by P = 50 N (it holds below 174 N), equilibrium
    written here with (N_A, F_A, N_B, F_B), corners A = (0, 0), B = (w, 0), push at (0, h):
        x:            F_A + F_B = -P
        y:            N_A + N_B = m g
        moments at A: w N_B = m g w / 2 + P h
    Least norm: the normal forces are determined, the frictions share the push equally,
    F_A = F_B = -P / 2; inside both cones by far (mu_s N_A = 70 N against 25 N), so it is shown."""
    m, w, h, P, mu = 40.0, 0.8, 0.9, 50.0, 0.5
    W = m * G
    E = np.array([[0.0, 1.0, 0.0, 1.0], [1.0, 0.0, 1.0, 0.0], [0.0, 0.0, w, 0.0]])
    e = np.array([-P, W, W * w / 2 + P * h])
    expected = [W / 2 - P * h / w, -P / 2, W / 2 + P * h / w, -P / 2]
    np.testing.assert_allclose(np.linalg.pinv(E) @ e, expected, rtol=1e-12)  # the hand result
    for point in ("A", "G", "Q"):
        out = _json(solver_cli, "solve", "data/scenes/crate_tipping.toml", "--set", "P=50 N", "--point", point,
                    "--json")["unknowns"]
        np.testing.assert_allclose([out[n]["value"] for n in ("N_A", "F_A", "N_B", "F_B")], expected, rtol=SPLIT_REL)


@pytest.mark.parametrize("h, kind", [(0.9, "tip"), (1.1, "tip"), (0.5, "slide"), (0.3, "slide")])
def test_crate_thresholds(solver_cli, h, kind):
    m, w, mu_s = 40.0, 0.8, 0.5
    out = _json(solver_cli, "friction", "data/scenes/crate_tipping.toml", "--set", f"h={h} m",
                "--critical", "P", "--between", "1 N", "600 N", "--json")
    first = out["critical"]["onsets"][0]
    assert first["starts"]
    slide, tip = mu_s * m * G, m * G * w / (2 * h)
    if kind == "tip":
        assert tip < slide and first["regimes"] == {"back": "separated", "front": "stick"}
        assert first["value"] == pytest.approx(tip, rel=REL)
    else:
        assert slide < tip and set(first["regimes"].values()) == {"slip + (impending)"}
        assert first["value"] == pytest.approx(slide, rel=REL)


def test_disk_with_backspin_slips_then_rolls(solver_cli, tmp_path):
    m, r, mu, v0, w0 = 2.0, 0.1, 0.2, 3.0, 20.0
    csv = tmp_path / "run.csv"
    out = _json(solver_cli, "simulate", "data/scenes/disk_backspin.toml", "--t-end", "2", "--rtol", "1e-11",
                "--atol", "1e-13", "--samples", "401", "--out", str(csv), "--json")
    (event,) = out["events"]
    assert (event["from"], event["to"]) == ("slip +", "stick")
    t_star = (v0 + r * w0) / (3 * mu * G)
    assert event["t"] == pytest.approx(t_star, rel=REL)
    v_star = (2 * v0 - r * w0) / 3
    assert event["state"]["x_dot"] == pytest.approx(v_star, rel=REL)
    data = np.genfromtxt(csv, delimiter=",", names=True)
    t, x, xd, phid = data["t_s"], data["x_m"], data["x_dot_ms"], data["phi_dot_rads"]
    # independent integration of each regime: sliding, a = -mu g, alpha = -2 mu g / r; then rolling at v*
    slip = t <= t_star
    np.testing.assert_allclose(xd[slip], v0 - mu * G * t[slip], rtol=0, atol=1e-10)
    np.testing.assert_allclose(phid[slip], w0 - 2 * mu * G / r * t[slip], rtol=0, atol=1e-9)
    x_star = v0 * t_star - mu * G * t_star ** 2 / 2
    np.testing.assert_allclose(x[~slip], x_star + v_star * (t[~slip] - t_star), rtol=0, atol=1e-9)
    np.testing.assert_allclose(phid[~slip], -v_star / r, rtol=0, atol=1e-8)
    # energy: it falls only while sliding, by exactly the friction's work
    E = 0.5 * m * xd ** 2 + 0.5 * (0.5 * m * r ** 2) * phid ** 2
    work = data["friction_work_floor_J"]
    np.testing.assert_allclose(E - E[0], work, rtol=0, atol=1e-9 * E[0])
    assert np.ptp(E[~slip]) < 1e-9 * E[0]
    assert work[-1] == pytest.approx(-m * (v0 + r * w0) ** 2 / 6, rel=REL)


@pytest.mark.parametrize("beta", [15.0, 30.0, 50.0])
def test_least_mu_on_an_incline(solver_cli, one_load_per_scene, beta):
    t = math.tan(math.radians(beta))
    for body, expected in (("disk", t / 3), ("ring", t / 2)):
        out = _json(solver_cli, "friction", f"data/scenes/incline_{body}.toml", "--set", f"beta={beta} deg", "--json")
        assert out["at_state"]["least_mu"]["incline"]["value"] == pytest.approx(expected, rel=REL)
    # the same from the other side: sweeping mu itself, slipping from rest is possible below tan(beta)/3
    out = _json(solver_cli, "friction", "data/scenes/incline_disk.toml", "--set", f"beta={beta} deg",
                "--critical", "mu", "--between", "0.001", "2", "--json")
    (onset,) = out["critical"]["onsets"]
    assert onset["regimes"] == {"incline": "slip + (impending)"} and not onset["starts"]
    assert onset["value"] == pytest.approx(t / 3, rel=REL)
    # over a motion the ratio is constant
    out = _json(solver_cli, "friction", "data/scenes/incline_disk.toml", "--set", f"beta={beta} deg",
                "--set", "mu=10", "--over", "0.5", "--json")
    assert out["over_motion"]["least_mu"]["incline"]["value"] == pytest.approx(t / 3, rel=REL)


def _wheel_least_mu(m_h, r, m_u, d, gamma, F_0):
    """|F_f| / F_n for wheel_on_incline.toml at rest at theta = 0, t = 0, derived by hand.

    A hoop (I_O = m_h r^2) rolls down a slope at gamma, axle moving r theta along
    d = (cos, -sin), with a point mass m_u at d straight below the axle and a push
    F_0 along d at the axle. Lagrange at rest: the hoop's generalized mass is
    2 m_h r^2, the point mass's m_u |r d - d k x (0, -1)|^2 = m_u (r^2 - 2 r d cos + d^2);
    gravity does (m_h + m_u) g r sin per unit theta, the push F_0 r, the contact
    nothing. Newton for the whole wheel along d and along the normal n = (sin, cos)
    (the point mass accelerates by r theta'' d - d theta'' x) gives F_f and F_n.
    """
    s, c = math.sin(gamma), math.cos(gamma)
    m = m_h + m_u
    theta_dd = (m * G * r * s + F_0 * r) / (2 * m_h * r ** 2 + m_u * (r ** 2 - 2 * r * d * c + d ** 2))
    F_f = m * r * theta_dd - m_u * d * c * theta_dd - m * G * s - F_0
    F_n = m * G * c - m_u * d * s * theta_dd
    return abs(F_f) / F_n


@pytest.mark.parametrize("gamma", [5.0, 30.0])
def test_least_mu_of_a_rolling_contact_without_a_coefficient(solver_cli, gamma):
    # wheel_on_incline.toml's rolling joint has no friction coefficient: it rolls by assumption,
    # and the least mu that keeps it rolling is still |F|/N. The bare hoop (no unbalance, no push):
    # a = g sin / 2 (I = m r^2), so F = m g sin / 2 against N = m g cos: mu = tan(gamma) * k, k = 1/2.
    # 1e-9 relative: the solve's round-off is ~1e-14, while the disk's k = 1/3 is off by a third.
    scene = "data/scenes/wheel_on_incline.toml"
    bare = _json(solver_cli, "friction", scene, "--set", "F_0=0 N", "--set", "m_u=0 kg",
                 "--set", f"gamma={gamma} deg", "--json")["at_state"]
    assert list(bare["least_mu"]) == ["rolling_hoop"]
    assert bare["least_mu"]["rolling_hoop"]["value"] == pytest.approx(math.tan(math.radians(gamma)) / 2, rel=1e-9)
    # the scene as shipped (unbalance mass and axle push): the hand derivation above, 0.0880 at 5 deg
    out = _json(solver_cli, "friction", scene, "--set", f"gamma={gamma} deg", "--json")["at_state"]
    expected = _wheel_least_mu(2.0, 0.3, 1.0, 0.25, math.radians(gamma), 3.0)
    assert out["least_mu"]["rolling_hoop"]["value"] == pytest.approx(expected, rel=1e-9)
    assert out["regime"]["rolling_hoop"]["least_mu"] == pytest.approx(expected, rel=1e-9)
    # and the text table has its row
    code, text, err = solver_cli("friction", scene, "--set", f"gamma={gamma} deg")
    assert code == 0, err
    (row,) = [line for line in text.splitlines() if line.startswith("rolling_hoop ")]
    assert float(row.split()[1]) == pytest.approx(expected, rel=1e-9)
    assert "no coefficient given: it rolls by assumption" in row


def test_the_ring_slides_where_the_disk_rolls(solver_cli):
    disk = _json(solver_cli, "solve", "data/scenes/incline_disk.toml", "--json")
    ring = _json(solver_cli, "solve", "data/scenes/incline_ring.toml", "--json")
    assert disk["regime"]["incline"]["regime"] == "stick"
    assert ring["regime"]["incline"]["regime"] == "slip +"
    b = math.radians(30)
    # rolling disk: a = (2/3) g sin(beta); sliding ring: a = g (sin b - mu cos b), r alpha = -mu g cos b ... m r^2 alpha = F r
    assert disk["unknowns"]["s_ddot"]["value"] == pytest.approx(2 / 3 * G * math.sin(b), rel=1e-12)
    assert ring["unknowns"]["s_ddot"]["value"] == pytest.approx(G * (math.sin(b) - 0.25 * math.cos(b)), rel=1e-12)
    assert ring["unknowns"]["psi_ddot"]["value"] == pytest.approx(-0.25 * G * math.cos(b) / 0.2, rel=1e-12)


def _bar_on_floor(t, y, L, g=G):
    """Frictionless floor, free top: a bar of length L with its foot A on the floor.
    y = (theta, x_A, theta', x_A'); G at A + (L/2)(-cos, sin) (the foot is to the right).
    Lagrange: T = m/2 (xG'^2 + yG'^2) + m L^2 theta'^2 / 24, V = m g (L/2) sin(theta)."""
    th, x, thd, xd = y
    s, c = math.sin(th), math.cos(th)
    # xG = x - L/2 cos, yG = L/2 sin: xG' = x' + L/2 s thd, yG' = L/2 c thd
    # x: m xG'' = 0; theta: (L/2) s x'' + (L^2/4 + L^2/12) theta'' = -g (L/2) c (the theta'^2 terms cancel)
    M = np.array([[1.0, L / 2 * s], [L / 2 * s, L ** 2 / 4 + L ** 2 / 12]])
    xdd_thdd = np.linalg.solve(M, np.array([-L / 2 * c * thd ** 2, -g * L / 2 * c]))
    return [thd, xd, xdd_thdd[1], xdd_thdd[0]]


@pytest.mark.parametrize("theta0", [50.0, 70.0, 85.0])
def test_frictionless_ladder_leaves_the_wall(solver_cli, theta0):
    L = 4.0
    out = _json(solver_cli, "simulate", "data/scenes/ladder_leaves_wall.toml", "--set", f"theta={theta0} deg",
                "--set", f"x={L * math.cos(math.radians(theta0))} m", "--t-end", "3", "--rtol", "1e-11",
                "--atol", "1e-13", "--samples", "3", "--json")
    leave = out["events"][0]
    assert (leave["joint"], leave["to"]) == ("wall", "separated")
    assert math.sin(leave["state"]["theta"]) == pytest.approx(2 / 3 * math.sin(math.radians(theta0)), rel=REL)
    if out["t_final"]["value"] <= leave["t"] + 1e-3:
        return  # the top reached the floor first (an impact): nothing after the switch to compare
    # after the switch: the bar on a frictionless floor, integrated here from the switch state
    s = leave["state"]
    y0 = [s["theta"], s["x"], s["theta_dot"], s["x_dot"]]
    t1 = out["t_final"]["value"]
    ref = solve_ivp(_bar_on_floor, (leave["t"], t1), y0, args=(L,), rtol=1e-12, atol=1e-13, method="DOP853")
    final = out["final"]
    # the two integrations carry ~1e-11 each over a fraction of a second
    assert final["theta"]["value"] == pytest.approx(ref.y[0, -1], abs=1e-8)
    assert final["x"]["value"] == pytest.approx(ref.y[1, -1], abs=1e-8)
    # no friction: the energy is conserved through the switch
    m = 10.0

    def energy(th, x, thd, xd):
        xg, yg = xd + L / 2 * math.sin(th) * thd, L / 2 * math.cos(th) * thd
        return 0.5 * m * (xg ** 2 + yg ** 2) + m * L ** 2 / 24 * thd ** 2 + m * G * L / 2 * math.sin(th)

    e0 = energy(math.radians(theta0), L * math.cos(math.radians(theta0)), 0, 0)
    e1 = energy(final["theta"]["value"], final["x"]["value"], final["theta_dot"]["value"], final["x_dot"]["value"])
    assert e1 == pytest.approx(e0, rel=1e-9)


def test_painleve_rod_is_reported_not_chosen():
    """A rod sliding on a very rough floor (Painlevé's example): with
    1 + 3 cos^2(theta) - 3 mu sin(theta) cos(theta) < 0 the Coulomb problem has
    no solution or several, for one sliding direction; the solver says so."""
    from solver.analyses.regimes import AmbiguousRegime, NoConsistentRegime, find_regime
    from solver.io.scenes import load_system

    text = """
name = "painleve"
[parameters]
m = "1 kg"
L = "1 m"
mu = "MU"
g = "9.80665 m/s^2"
[coordinates]
x = { value = "0 m", rate = "VX" }
y = { value = "0 m", rate = "0 m/s" }
theta = { value = "30 deg", rate = "0 rad/s" }
[[bodies]]
name = "rod"
orientation = "theta"
position = { point = "A", at = ["x", "y"] }
points = { A = ["0", "0"], B = ["L", "0"] }
elements = [{ kind = "slender_bar", mass = "m", from = "A", to = "B" }]
[[joints]]
kind = "rail"
name = "floor"
point = "rod:A"
reaction = "N"
friction = "F"
one_sided = true
friction_coefficient = "mu"
[[loads]]
kind = "gravity"
g = "g"
"""
    import tempfile
    from pathlib import Path

    def regime(mu, vx):
        with tempfile.TemporaryDirectory() as d:
            p = Path(d) / "rod.toml"
            p.write_text(text.replace("MU", str(mu)).replace("VX", vx))
            return find_regime(load_system(p))

    th = math.radians(30)
    assert 1 + 3 * math.cos(th) ** 2 - 3 * 0.3 * math.sin(th) * math.cos(th) > 0
    calm = regime(0.3, "1 m/s")
    assert calm.regimes["floor"].label == "slip +"
    assert 1 + 3 * math.cos(th) ** 2 - 3 * 4.0 * math.sin(th) * math.cos(th) < 0
    outcomes = []
    for vx in ("1 m/s", "-1 m/s"):
        try:
            outcomes.append(regime(4.0, vx).regimes["floor"].label)
        except (NoConsistentRegime, AmbiguousRegime) as err:
            outcomes.append(type(err).__name__)
    assert {"NoConsistentRegime", "AmbiguousRegime"} & set(outcomes), outcomes


@pytest.mark.parametrize("argv, needle", [
    (["friction", "data/scenes/ladder_friction.toml", "--critical", "nope", "--between", "1", "2"], "--critical nope"),
    (["friction", "data/scenes/crate_tipping.toml", "--critical", "P", "--between", "1 m", "2 m"], "--between LOW"),
    (["friction", "data/scenes/crate_tipping.toml", "--critical", "P"], "--critical and --between"),
    (["friction", "data/scenes/crate_tipping.toml", "--over", "-1 s"], "--over"),
])
def test_bad_friction_flags_get_one_line(solver_cli, argv, needle):
    code, out, err = solver_cli(*argv)
    assert code == 2 and needle in err and err.count("\n") == 1, err


@pytest.mark.parametrize("joint, message", [
    ('kind = "rail"\nname = "floor"\npoint = "rod:A"\nfriction_coefficient = "0.3"', "one_sided"),
    ('kind = "rail"\nname = "floor"\npoint = "rod:A"\none_sided = true\nstatic_friction = "0.2"\n'
     'kinetic_friction = "0.3"', "kinetic_friction"),
    ('kind = "rail"\nname = "floor"\npoint = "rod:A"\none_sided = true\nstatic_friction = "0.2"', "static_friction"),
])
def test_bad_friction_keys_name_the_key(solver_cli, tmp_path, joint, message):
    scene = tmp_path / "rod.toml"
    scene.write_text(f"""
name = "rod"
[parameters]
m = "1 kg"
[coordinates]
x = {{ value = "0 m", rate = "0 m/s" }}
[[bodies]]
name = "rod"
orientation = "0"
position = {{ point = "A", at = ["x", "0"] }}
points = {{ A = ["0", "0"] }}
elements = [{{ kind = "point_mass", mass = "m", at = "A" }}]
[[joints]]
{joint}
""")
    code, out, err = solver_cli("solve", str(scene))
    assert code == 2 and "joints[0]" in err and message in err and err.count("\n") == 1, err


BOWL = """
name = "bowl"
[parameters]
m = "1 kg"
r = "0.1 m"
R = "1 m"
mu = "0.1"
g = "9.80665 m/s^2"
[coordinates]
psi = { value = "-60 deg", rate = "0 rad/s" }
phi = { value = "0 rad", rate = "30 rad/s" }
[[bodies]]
name = "disk"
orientation = "phi"
position = { point = "C", at = ["(R - r)*cos(psi)", "(R - r)*sin(psi)"] }
points = { C = ["0", "0"] }
elements = [{ name = "wheel", kind = "uniform_disk", mass = "m", center = "C", radius = "r" }]
[[joints]]
kind = "rolling_on_circle"
name = "bowl"
element = "disk:wheel"
radius = "R"
side = "inside"
friction_coefficient = "mu"
[[loads]]
kind = "gravity"
g = "g"
"""


def test_spinning_disk_in_a_bowl_loses_exactly_the_friction_work(solver_cli, tmp_path):
    """A disk dropped spinning into a circular bowl slips, rolls, slips back and
    forth: through every switch (rolling on a circle, both ways) the mechanical
    energy, computed here from the state, falls by exactly the friction's work
    and stays constant while rolling."""
    scene = tmp_path / "bowl.toml"
    scene.write_text(BOWL)
    csv = tmp_path / "bowl.csv"
    out = _json(solver_cli, "simulate", str(scene), "--t-end", "3", "--rtol", "1e-11", "--atol", "1e-13",
                "--samples", "601", "--out", str(csv), "--json")
    kinds = [(e["from"], e["to"]) for e in out["events"]]
    assert ("slip +", "stick") in kinds and ("stick", "slip +") in kinds and len(kinds) >= 3, kinds
    d = np.genfromtxt(csv, delimiter=",", names=True)
    m, r, R = 1.0, 0.1, 1.0
    E = (0.5 * m * ((R - r) * d["psi_dot_rads"]) ** 2 + 0.5 * (0.5 * m * r ** 2) * d["phi_dot_rads"] ** 2
         + m * G * (R - r) * np.sin(d["psi_rad"]))
    work = d["friction_work_bowl_J"]
    # the work is integrated with the motion (same tolerances): ~1e-10 of the initial kinetic energy 4.5 J
    np.testing.assert_allclose(E - E[0], work, rtol=0, atol=1e-8)
    assert work[-1] < -0.1  # it did slip
    # while rolling (no slip speed) the energy is constant
    rolling = np.abs(d["v_slip_bowl_ms"]) < 1e-9
    assert rolling.sum() > 10


BLOCK = """
name = "block"
[parameters]
m = "2 kg"
beta = "20 deg"
mu_s = "MU_S"
mu_k = "0.2"
g = "9.80665 m/s^2"
[coordinates]
s = { value = "0 m", rate = "-3 m/s" }      # thrown up the incline (s counts down the slope)
[[bodies]]
name = "block"
orientation = "0"
position = { point = "C", at = ["s*cos(beta)", "-s*sin(beta)"] }
points = { C = ["0", "0"] }
elements = [{ kind = "point_mass", mass = "m", at = "C" }]
[[joints]]
kind = "slider"
name = "incline"
point = "block:C"
angle = "-beta"
reactions = ["N", "M"]
friction = "F"
one_sided = true
static_friction = "mu_s"
kinetic_friction = "mu_k"
[[loads]]
kind = "gravity"
g = "g"
"""


@pytest.mark.parametrize("mu_s", [0.5, 0.3])
def test_block_thrown_up_an_incline_stops_then_sticks_or_slides_back(solver_cli, tmp_path, mu_s):
    """A block on a slider with Coulomb friction, thrown up a 20 deg slope at 3 m/s: it decelerates at
    g (sin b + mu_k cos b), stops at t1 = v0 / that, then stays if mu_s >= tan b (0.5 > 0.364) or
    slides back down at g (sin b - mu_k cos b) (0.3 < 0.364)."""
    scene = tmp_path / "block.toml"
    scene.write_text(BLOCK.replace("MU_S", str(mu_s)))
    out = _json(solver_cli, "simulate", str(scene), "--t-end", "1.5", "--rtol", "1e-11", "--atol", "1e-13",
                "--samples", "3", "--json")
    b, v0 = math.radians(20), 3.0
    up = G * (math.sin(b) + 0.2 * math.cos(b))
    t1 = v0 / up
    event = out["events"][0]
    assert event["t"] == pytest.approx(t1, rel=REL) and event["from"] == "slip -"
    s1 = -v0 * t1 + up * t1 ** 2 / 2
    final = out["final"]
    if mu_s > math.tan(b):
        assert event["to"] == "stick" and len(out["events"]) == 1
        assert final["s"]["value"] == pytest.approx(s1, rel=REL)
        assert final["F"]["value"] == pytest.approx(-2.0 * G * math.sin(b), rel=1e-12)  # static: holds the weight
    else:
        assert event["to"] == "slip +" and len(out["events"]) == 1
        down = G * (math.sin(b) - 0.2 * math.cos(b))
        dt = 1.5 - t1
        assert final["s"]["value"] == pytest.approx(s1 + down * dt ** 2 / 2, rel=REL)
        assert final["s_dot"]["value"] == pytest.approx(down * dt, rel=REL)


def test_one_body_format_ladder_with_friction(solver_cli, tmp_path):
    """The one-body format takes friction on its rails too: the same critical angle."""
    scene = tmp_path / "ladder.toml"
    scene.write_text("""
name = "old_ladder"
[parameters]
m = "12 kg"
L = "5 m"
mu_A = "0.4"
mu_B = "0.1"
g = "9.80665 m/s^2"
[coordinate]
name = "theta"
value = "60 deg"
rate = "0 rad/s"
[body]
orientation = "pi - theta"
[points]
A = ["0", "0"]
B = ["L", "0"]
[[elements]]
name = "bar"
kind = "slender_bar"
mass = "m"
from = "A"
to = "B"
[[constraints]]
kind = "rail"
point = "A"
reaction = "N_A"
friction = "F_A"
friction_coefficient = "mu_A"
one_sided = true
[[constraints]]
kind = "rail"
point = "B"
angle = "-pi/2"
reaction = "N_B"
friction = "F_B"
friction_coefficient = "mu_B"
one_sided = true
[[loads]]
kind = "gravity"
g = "g"
""")
    out = _json(solver_cli, "friction", str(scene), "--critical", "theta", "--between", "5", "89.5", "--json")
    (onset,) = out["critical"]["onsets"]
    assert onset["value"] == pytest.approx(math.degrees(math.atan((1 - 0.4 * 0.1) / (2 * 0.4))), rel=REL)
    code, _, err = solver_cli("solve", str(scene), "--set", "mu_A=-1")  # a negative coefficient: refused
    assert code == 2 and "mu_A" in err


def test_regime_throughout_is_not_claimed_when_the_ends_differ():
    # the guard behind "throughout": over 20..89 deg the default ladder slips at 20 deg and stands
    # at 89 deg (tan 20 deg = 0.36 < tan(theta_c) = 0.94 / 0.6 = 1.57 < tan 89 deg), so no single
    # regime may be named, whatever the scan found
    from solver.cli_contacts import _throughout
    from solver.io.scenes import load_system

    system = load_system("data/scenes/ladder_friction.toml", {})
    out = _throughout(system, "theta", math.radians(20), math.radians(89), math.radians(1), "deg")
    assert "throughout" not in out
    assert "theta = 20 deg: floor slips" in out["note"] and "theta = 89 deg: every contact sticks" in out["note"]


def test_critical_value_of_a_pure_number_prints_no_unit(solver_cli):
    """A coefficient swept by --critical is a pure number: its header and onsets carry no unit
    (pint's dimensionless unit printed as a stray "1": "from 0.05 to 2 1")."""
    code, text, err = solver_cli("friction", "data/scenes/ladder_friction.toml", "--critical", "mu_A",
                                 "--between", "0.05", "2")
    assert code == 0, err
    assert "motion from rest as mu_A goes from 0.05 to 2:" in text
    assert re.search(r"^  mu_A = [0-9.]+: ", text, flags=re.M)


def test_friction_json_names_the_units_of_times_and_forces(solver_cli, one_load_per_scene, tmp_path):
    """`friction --over --json` gives every time and force as {value, unit} in the scene's output
    units, as its text does (both commands read the scene once): the incline disk with
    [output_units] time in ms and force in lbf.
    Reference, rolling from rest on the incline (beta = 30 deg): N = m g cos(beta) and
    |F| = m g sin(beta) / 3 (a solid disk), in lbf by its definition (4.4482216152605 N exactly)."""
    scene = tmp_path / "incline_disk_us.toml"
    scene.write_text(open("data/scenes/incline_disk.toml").read()
                     + '\n[output_units]\ntime = "ms"\nforce = "lbf"\n')
    out = _json(solver_cli, "friction", str(scene), "--set", "mu=10", "--over", "0.5", "--json")
    over = out["over_motion"]
    assert over["t_end"] == {"value": pytest.approx(500.0, rel=1e-12), "unit": "ms"}
    assert over["least_mu"]["incline"]["at_t"]["unit"] == "ms"
    assert 0 <= over["least_mu"]["incline"]["at_t"]["value"] <= 500.0
    check = out["at_state"]["regime"]["incline"]
    m, g, beta, lbf = 3.0, 9.80665, math.radians(30.0), 4.4482216152605
    assert check["normal_force"]["unit"] == check["friction_force"]["unit"] == "lbf"
    assert check["normal_force"]["value"] == pytest.approx(m * g * math.cos(beta) / lbf, rel=REL)
    assert abs(check["friction_force"]["value"]) == pytest.approx(m * g * math.sin(beta) / 3 / lbf, rel=REL)
    text = solver_cli("friction", str(scene), "--set", "mu=10", "--over", "0.5")[1]
    assert "to t = 500 ms" in text


def test_sliding_friction_is_written_with_the_scene_s_names(solver_cli):
    """QA round 9 item 14: the sliding contact's line read `friction = -s mu_k N`, s being the
    slip's sign, in a scene whose coordinate is named s. It writes the sign out and the reaction
    names: F = -mu_k N for a slip in +, with N = m g cos(beta) (2 kg, 30 deg, g = 9.81 m/s^2,
    mu_k = 0.4 as the scene gives them; 6 figures printed, so 1e-5 relative)."""
    code, out, err = solver_cli("solve", "tests/data/multibody/block_incline.toml")
    assert code == 0, err
    line = next(x for x in out.splitlines() if x.strip().startswith("ramp:"))
    assert "-s mu_k" not in line
    value = re.search(r"friction F = -mu_k N = (\S+) N", line)
    assert value, line
    assert float(value[1]) == pytest.approx(-0.4 * 2.0 * 9.81 * math.cos(math.radians(30.0)), rel=1e-5)


def test_eom_is_written_in_the_regime_that_holds_at_the_state(solver_cli):
    """Regression: `eom` refused every scene whose contacts can slip although `explain` writes
    the equations in the regime at the state. incline_disk.toml rolls at its state (mu = 0.25 >
    tan(30 deg)/3): the solid disk rolling down an incline, (3/2) m s_ddot - m g sin(beta) = 0,
    must be the equation, identically (symbolic, so no tolerance)."""
    import sympy as sp

    payload = _json(solver_cli, "eom", "data/scenes/incline_disk.toml", "--json")
    assert payload["regime"] == {"incline": "stick"} and payload["coordinates"] == ["s"]
    names = {n: sp.Symbol(n) for n in ("m", "g", "beta", "s_ddot")}  # beta a symbol, not sympy's beta()
    eom = sp.sympify(payload["eom"][0], locals=names)
    m, g, beta, s_ddot = names.values()
    assert sp.simplify(eom - (sp.Rational(3, 2) * m * s_ddot - m * g * sp.sin(beta))) == 0
    code, out, err = solver_cli("eom", "data/scenes/incline_disk.toml")
    assert code == 0, err
    assert "contacts  in the regime that holds at the state (as `solve` finds it): incline: stick" in out


@pytest.mark.parametrize(("scene", "why"), [
    ("incline_ring.toml", "'incline' slides with friction -mu_k N"),  # a ring slips: mu < tan(beta)/2
    ("ladder_friction.toml", "sticking contacts hold redundantly"),
])
def test_eom_refuses_a_regime_it_cannot_write_saying_why(solver_cli, scene, why):
    code, out, err = solver_cli("eom", f"data/scenes/{scene}")
    assert code == 2 and out == "" and len(err.strip().splitlines()) == 1
    assert why in err and "in the contact regime that holds at the state" in err


def test_contact_kinematics_walked_then_compiled_equal_exact_values():
    """The ladder's contact kinematics (gap, its rates, the sliding rate and acceleration) are walked
    for a state's first calls and compiled after: both give sympy's 30-digit values of the same
    expressions at random states, to 1e-12 of the largest (a few dozen double operations round
    to ~1e-15 of it; a dropped or wrong term is off by order one)."""
    from pathlib import Path

    import sympy as sp

    from solver.analyses.regimes import contact_kinematics
    from solver.io.scenes import load_system

    system = load_system(Path(__file__).resolve().parents[1] / "data/scenes/ladder_friction.toml")
    rng = np.random.default_rng(7)
    for f, pv in contact_kinematics(system).values():
        for _ in range(f.WALKS + 3):
            values = [*rng.uniform(0.2, 1.2, len(f.args) - len(pv)), *pv]
            point = {a: sp.Float(v, 30) for a, v in zip(f.args, values)}
            exact = [float(sp.N(e.xreplace(point), 30)) for e in f.exprs]
            scale = max(1.0, *map(abs, exact))
            assert np.allclose(f(*values), exact, rtol=0, atol=1e-12 * scale)
        assert f._f is not None  # the calls after the first WALKS went to the compiled function


def test_a_coefficient_of_zero_has_no_friction_to_overcome(solver_cli):
    """QA 21 #6: with mu_B = 0 at the wall the reason read "F_B = -mu_k N_B = -0 N; it starts to slip
    (mu_s N overcome)". By hand F_B = -mu_k N_B = 0 exactly (mu_k = 0), and a coefficient of 0 holds
    nothing: the wall's reason now says it slips at once and slides without friction; the floor
    (mu = 0.25) keeps its words."""
    code, out, err = solver_cli("solve", "data/scenes/ladder_friction.toml", "--set", "mu_A=0.25", "--set", "mu_B=0")
    assert code == 0, err
    wall = next(line for line in out.splitlines() if line.strip().startswith("wall:"))
    floor = next(line for line in out.splitlines() if line.strip().startswith("floor:"))
    assert "F_B = -mu_k N_B = 0 N" in wall and "-0 N" not in wall
    assert "it slips at once (mu_s = 0: no friction holds it), then slides without friction (mu_k = 0)" in wall
    assert "mu_s N overcome" not in wall
    assert "it starts to slip (mu_s N overcome), then slides with mu_k N" in floor


@pytest.mark.parametrize("method", ["lagrange", "generalized_euler", "mass_center"])
def test_sliding_friction_enters_every_route(solver_cli, method):
    """QA 23 #1: the Lagrange route left a sliding contact's friction out (its multiplier gives
    only the normal force), and printed F = -mu_k N beside accelerations of a frictionless slide.
    By hand: a block sliding down a 30 deg ramp with mu_k = 0.4 (g = 9.81) has
    s'' = g (sin 30 deg - 0.4 cos 30 deg); a disk (m r^2/2) thrown with backspin slides with
    x'' = -mu g and phi'' = -mu m g r / (m r^2 / 2) = -2 mu g / r (mu = 0.2, r = 0.1 m). Tolerance:
    the round-off of small linear solves, 1e-10 relative (REL)."""
    out = _json(solver_cli, "solve", "tests/data/multibody/block_incline.toml", "--method", method, "--json")
    b = math.radians(30)
    assert out["unknowns"]["s_ddot"]["value"] == pytest.approx(9.81 * (math.sin(b) - 0.4 * math.cos(b)), rel=REL)
    out = _json(solver_cli, "solve", "data/scenes/disk_backspin.toml", "--method", method, "--json")
    assert out["unknowns"]["x_ddot"]["value"] == pytest.approx(-0.2 * G, rel=REL)
    assert out["unknowns"]["phi_ddot"]["value"] == pytest.approx(-2 * 0.2 * G / 0.1, rel=REL)
