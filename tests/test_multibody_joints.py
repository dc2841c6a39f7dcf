"""Joint kinds beyond the shipped scenes, against closed forms and across routes.

Each scene in tests/data/multibody exercises joints and loads that the six
shipped multibody scenes do not: a gear mesh, rolling inside a circle, a pivot
moving on a prescribed path with a torsional spring, a coordinate prescribed as
a function of time with its driving motor, a collar sliding on a turning arm
with a spring and a damper. References are textbook closed forms written here;
the routes must also agree with each other (the Lagrange route uses each
joint's constraint equations, the Newton-Euler routes its reaction forces, so
agreement checks every joint's sign conventions).
"""
from __future__ import annotations

import math
import re
from functools import lru_cache
from pathlib import Path

import pytest
import sympy as sp

from solver.analyses.instant import solve_instant
from solver.io.scenes import load_system

DATA = Path(__file__).parent / "data" / "multibody"
G = 9.80665
# The routes solve equivalent well-conditioned linear systems (condition numbers below 10):
# they agree to round-off, ~1e-13 relative; 1e-10 leaves room and catches any wrong term.
RTOL = 1e-10
# (abs=1e-9 [N, rad/s^2] below only for quantities whose exact value is 0, e.g. a frictionless collar's
# normal force at its centre of percussion; round-off there is ~1e-15.)


@lru_cache(maxsize=None)
def system_of(name):
    """One system per scene file for this module: its kinematics and each (route, point)'s equations
    are derived once (cached on the system) and shared by the closed-form tests and the route checks,
    which loaded the same file afresh for every call. What the routes share is unchanged: the same
    code computed the same point kinematics for each of them before; each route's own equations
    (reactions for Newton-Euler, constraint equations for Lagrange) are still derived separately."""
    return load_system(DATA / name)


def values(name, method="generalized_euler", point=None):
    sol = solve_instant(system_of(name), point, method)
    return {k: v.to_base_units().magnitude for k, v in sol.unknowns.items()}


def test_gear_pair_driven_by_a_couple():
    # I_eff = I1 + I2 (r1/r2)^2 reflects the second gear to the first; F = I2 alpha2 / r2.
    m1, m2, r1, r2, C = 2.0, 1.0, 0.2, 0.1, 3.0
    I1, I2 = m1 * r1**2 / 2, m2 * r2**2 / 2
    alpha1 = C / (I1 + I2 * (r1 / r2) ** 2)
    v = values("gears.toml")
    assert v["th_ddot"] == pytest.approx(alpha1, rel=RTOL)
    assert v["F_mesh"] == pytest.approx(I2 * alpha1 * (r1 / r2) / r2, rel=RTOL)


def test_disk_rolling_inside_a_bowl():
    # beta = psi + pi/2 from the bottom: beta'' = -2 g sin(beta) / (3 (R - r)); alpha of the disk
    # from rolling inside: omega = -(R - r) psi' / r.
    R, r, beta = 0.5, 0.05, math.radians(30.0)
    v = values("disk_in_bowl.toml")
    psi_dd = -2 * G * math.sin(beta) / (3 * (R - r))
    assert v["psi_ddot"] == pytest.approx(psi_dd, rel=RTOL)
    assert v["alpha"] == pytest.approx(-(R - r) * psi_dd / r, rel=RTOL)
    # normal force: m (R - r) psi'^2 + m g cos(beta) = N ... minus nothing else (friction is tangential)
    assert v["N_bowl"] == pytest.approx(1.0 * (R - r) * 0.5**2 + 1.0 * G * math.cos(beta), rel=RTOL)


def test_pendulum_on_a_moving_pivot_with_a_torsional_spring():
    # Pivot x_P = A sin(w t): at t = 0 it accelerates at 0 but moves at A w. Bar from the
    # downward vertical at th: I_O th'' = -m g (L/2) sin th - k th - m (L/2) cos(th) x_P''.
    m, L, k, th = 1.0, 0.5, 2.0, math.radians(20.0)
    I_O = m * L**2 / 3
    v = values("moving_pivot.toml")
    assert v["th_ddot"] == pytest.approx((-m * G * L / 2 * math.sin(th) - k * th) / I_O, rel=RTOL)


def test_prescribed_coordinate_returns_the_driving_torque():
    # th = w t + al t^2 / 2: at t = 0, th = 0 (bar horizontal), th' = w, th'' = al.
    m, L, w, al = 1.0, 0.5, 3.0, 2.0
    v = values("driven_coord.toml")
    assert v["M"] == pytest.approx(m * L**2 / 3 * al + m * G * L / 2, rel=RTOL)
    assert v["alpha"] == pytest.approx(al, rel=RTOL)
    # the pin force: the centre moves on a circle: a_G = (L/2)(-w^2, al) at th = 0
    assert v["pin_1_x"] == pytest.approx(-m * L / 2 * w**2, rel=RTOL)
    assert v["pin_1_y"] == pytest.approx(m * L / 2 * al + m * G, rel=RTOL)


def test_collar_on_a_turning_arm_with_spring_and_damper():
    # Arm (bar M, L) pinned at O; collar (point mass m) at distance s along it, pushed by a
    # spring k (s - L0) and a damper c s' towards O. With N the collar's normal force:
    #   m (s'' - s th'^2) = -k (s - L0) - c s' - m g sin th
    #   m (s th'' + 2 s' th') = N - m g cos th
    #   I_O th'' = -M g (L/2) cos th - N s
    m, k, c, L0, M, L, th, thd, s, sd = 2.0, 100.0, 1.0, 0.3, 1.0, 0.6, math.radians(30.0), 1.0, 0.4, 0.0
    I_O = M * L**2 / 3
    # eliminate N: (I_O + m s^2) th'' = -M g L/2 cos th - m g s cos th - 2 m s s' th'
    th_dd = (-M * G * L / 2 * math.cos(th) - m * G * s * math.cos(th) - 2 * m * s * sd * thd) / (I_O + m * s**2)
    s_dd = s * thd**2 + (-k * (s - L0) - c * sd - m * G * math.sin(th)) / m
    for method in ("generalized_euler", "mass_center"):
        v = values("spring_slot.toml", method)
        assert v["th_ddot"] == pytest.approx(th_dd, rel=RTOL)
        assert v["s_ddot"] == pytest.approx(s_dd, rel=RTOL)


@pytest.mark.parametrize("name", ["gears.toml", "disk_in_bowl.toml", "moving_pivot.toml", "driven_coord.toml",
                                  "spring_slot.toml"])
def test_routes_and_points_agree(name):
    ref = values(name)
    system = system_of(name)
    points = [f"{b}:{p}" for b, body in system.bodies.items() for p in body.point_names()]
    for point in points[:3]:
        other = values(name, point=point)
        for key, value in ref.items():
            assert other[key] == pytest.approx(value, rel=RTOL, abs=1e-9), (point, key)
    other = values(name, "lagrange")
    for key, value in ref.items():
        assert other[key] == pytest.approx(value, rel=RTOL, abs=1e-9), ("lagrange", key)


def test_reduced_equation_of_motion_of_the_four_bar_holds_at_the_solved_state(solver_cli):
    """`eom` on a loop (closure reactions projected out, dependent accelerations eliminated) is
    satisfied by the crank acceleration that `solve` finds from the full augmented system: two
    different computations. Residual relative to the generalized mass times that acceleration
    (round-off of expressions with ~2000 operations: ~1e-14; 1e-10 leaves room)."""
    import json

    import sympy as sp

    from solver.analyses.eom import reduced_equations_of_motion
    from solver.formulations import formulate

    scene = str(Path(__file__).parents[1] / "data" / "scenes" / "four_bar.toml")
    code, out, err = solver_cli("eom", scene, "--json")
    assert code == 0, err
    payload = json.loads(out)
    assert payload["coordinates"] == ["theta2"] and payload["dependent"] == ["theta3", "theta4"]
    code, out, err = solver_cli("solve", scene, "--json")
    solved = json.loads(out)
    system = load_system(scene)
    values = {sp.Symbol(k, real=True): v["value"] for k, v in solved["state"].items()}
    values[sp.Symbol("theta2_ddot", real=True)] = solved["unknowns"]["theta2_ddot"]["value"]
    values.update(system.si_values())
    subs = {k: sp.Float(v) for k, v in values.items()}
    eom = reduced_equations_of_motion(formulate(system))[0][0]
    residual = float(eom.xreplace(subs))
    mass = float(sp.diff(eom, sp.Symbol("theta2_ddot", real=True)).xreplace(subs))
    assert abs(residual) <= 1e-10 * abs(mass * solved["unknowns"]["theta2_ddot"]["value"])


def test_four_bar_eom_text_is_the_projection_in_parts(solver_cli, monkeypatch):
    """`eom` on a loop prints the equation as built: E_u + sum_v k_v E_v = 0 with each coordinate's
    equation E, the velocity ratios k and the dependent accelerations printed apart (written out
    whole it ran to 13,000 characters). The printed parts, parsed back and evaluated at the state
    `solve` finds (from the full augmented system, another computation), satisfy the equation:
    residual within 1e-9 of the largest term (double-precision evaluations of a few hundred
    operations agree to ~1e-14)."""
    import json
    import re

    import sympy as sp

    from solver import expressions
    from solver.expressions import parse_expression

    monkeypatch.setattr(expressions, "MAX_LENGTH", 5000)  # the product's own output, longer than a scene's input
    scene = str(Path(__file__).parents[1] / "data" / "scenes" / "four_bar.toml")
    code, out, err = solver_cli("eom", scene)
    assert code == 0, err
    assert "  E_theta2 + k_theta3_theta2*E_theta3 + k_theta4_theta2*E_theta4 = 0" in out and len(out) < 6000
    parts = dict(re.findall(r"^  (\w+) = (.+)$", out, flags=re.M))
    system = load_system(scene)
    names = {**system.symbols, **{n: sp.Symbol(n, real=True) for n in parts if n.startswith("k_")}}
    for c in system.free:
        names.update({c.name: c.q, f"{c.name}_dot": c.qd, f"{c.name}_ddot": c.qdd})
    parsed = {k: parse_expression(v, names, where=k) for k, v in parts.items()}
    solved = json.loads(solver_cli("solve", scene, "--json")[1])
    values = {sp.Symbol(k, real=True): v["value"] for k, v in solved["state"].items()}
    values.update(system.si_values())
    values[sp.Symbol("theta2_ddot", real=True)] = solved["unknowns"]["theta2_ddot"]["value"]

    def num(e):
        return float(e.xreplace({k: sp.Float(v) for k, v in values.items()}))

    for k in ("k_theta3_theta2", "k_theta4_theta2"):
        values[sp.Symbol(k, real=True)] = num(parsed[k])
    for v in ("theta3_ddot", "theta4_ddot"):
        values[sp.Symbol(v, real=True)] = num(parsed[v])
    terms = [num(parsed["E_theta2"]), values[sp.Symbol("k_theta3_theta2", real=True)] * num(parsed["E_theta3"]),
             values[sp.Symbol("k_theta4_theta2", real=True)] * num(parsed["E_theta4"])]
    assert abs(sum(terms)) <= 1e-9 * max(abs(t) for t in terms)
    # the dependent accelerations printed agree with solve's
    for v in ("theta3_ddot", "theta4_ddot"):
        assert values[sp.Symbol(v, real=True)] == pytest.approx(solved["unknowns"][v]["value"], rel=1e-9)


def test_eom_prints_short_reactions_tidied_in_text_and_json(solver_cli):
    """QA 13 #3: the reactions were left out as "too long to read here" (hundreds of nodes with
    sin**2 + cos**2 left in) although they are short; the display tidy now reduces them first, and
    --json carries the same forms. By hand, for the block (mass mb, radius r) on the bar (M, L) turned
    at omega about O, the slider frictionless so that r'' = r omega**2: the block's acceleration is the
    Coriolis 2 r' omega across the bar, so N = 2 mb omega r', O = M (-L omega**2/2) e_r + 2 mb r' omega
    e_theta (e_r at omega t), T = d/dt (M L**2/3 + mb r**2) omega = 2 mb r r' omega, M_g = 0. The disk
    rolling in the bowl: N_bowl = m ((R - r) psi'**2 - g sin(psi)) (centripetal, along the radius). The
    collar (m) on rot_arm, turned at the constant W: T = d/dt (m r**2 + I) W = 2 m r r' W, N = 2 m W r'."""
    import json

    names = {n: sp.Symbol(n, real=True) for n in ("mb", "M", "L", "omega", "t", "r", "r_dot", "m", "R", "g",
                                                  "psi", "psi_dot", "W")}
    mb, M, L, w, t, r, rd, m, R, g, psi, pd, W = names.values()
    closed = {"arm_block": {"O_x": -M * L * w**2 * sp.cos(w * t) / 2 - 2 * mb * rd * w * sp.sin(w * t),
                            "O_y": -M * L * w**2 * sp.sin(w * t) / 2 + 2 * mb * rd * w * sp.cos(w * t),
                            "T": 2 * mb * r * rd * w, "N": 2 * mb * w * rd, "M_g": sp.Integer(0)},
              "disk_in_bowl": {"N_bowl": m * ((R - r) * pd**2 - g * sp.sin(psi))},
              "rot_arm": {"T": 2 * m * r * rd * W, "N": 2 * m * W * rd}}
    for scene, forms in closed.items():
        path = str(Path(__file__).parent / "data" / "multibody" / f"{scene}.toml")
        code, out, err = solver_cli("eom", path)
        assert code == 0, err
        assert not any(f"  {name} = (a closed form" in out for name in forms), out[-1500:]
        printed = dict(re.findall(r"^  (\w+) = (.+)$", out, flags=re.M))
        payload = json.loads(solver_cli("eom", path, "--json")[1])["reactions"]
        for name, reference in forms.items():
            for text in (printed[name], payload[name]):
                assert len(text) < 80 and sp.expand(sp.sympify(text, locals=names) - reference) == 0, text


def test_eom_does_not_print_a_closed_form_nobody_can_read(solver_cli, one_load_per_scene):
    """The plate on two links: its reactions' closed forms (Cramer's rule over eight unknowns) run to
    100,000 characters each; the text output names their size and prints their values, and --json
    still carries the expressions. (Both commands read one loaded scene: Cramer's rule, about half a
    second, is formed once.)"""
    import json

    scene = str(Path(__file__).parents[1] / "data" / "scenes" / "parallel_link_plate.toml")
    code, out, err = solver_cli("eom", scene)
    assert code == 0, err
    import re

    # (QA 13 #3: B_y, 8,000 nodes, is tidied and printed; the line of each other says why it is left
    # out: over the size the display tidy takes on, not only long)
    left = re.findall(r"^  (\w+) = \(a closed form of (\d+) nodes \(over the 10000 the display tidy takes on\), "
                      r"too long to read here", out, flags=re.M)
    assert len(out) < 5000 and len(left) == 7 and all(int(n) > 10000 for _, n in left)
    assert len(re.findall(r"^      = \S+ N at the state$", out, flags=re.M)) == 8
    payload = json.loads(solver_cli("eom", scene, "--json")[1])
    assert len(payload["reactions"]) == 8 and sorted(len(e) > 1500 for e in payload["reactions"].values()) == [False] + [True] * 7


def test_a_disk_rolling_in_a_bowl_has_its_closed_forms_in_R_minus_r(solver_cli):
    """New-user report: the disk rolling in a circular track printed its equation of motion, mass and
    friction in sqrt(R**2 - 2*R*r + r**2) (the centre's distance from the bowl's centre, which the
    placement makes R - r), e.g. F = g*m*(-R + r)*cos(psi)/(-2*R + 2*r - sqrt(R**2 - 2*R*r + r**2)).
    By hand (beta = psi + pi/2 from the bottom, rolling inside): M = 3 m (R - r)**2 / 2 and the
    friction m g sin(beta) / 3 = m g cos(psi) / 3, the textbook result; no square root is left."""
    code, out, err = solver_cli("eom", str(DATA / "disk_in_bowl.toml"))
    assert code == 0, err
    assert "sqrt" not in out
    lines = {line.split("=")[0].strip(): line.split("=", 1)[1].strip() for line in out.splitlines()
             if line.strip().startswith(("M =", "F_bowl ="))}
    R, r, m, g, psi = sp.symbols("R r m g psi", real=True)
    names = {"R": R, "r": r, "m": m, "g": g, "psi": psi}
    from solver.expressions import parse_expression

    M = parse_expression(lines["M"], names, where="M")
    F = parse_expression(lines["F_bowl"], names, where="F_bowl")
    assert sp.expand(M - sp.Rational(3, 2) * m * (R - r) ** 2) == 0
    assert sp.simplify(F - m * g * sp.cos(psi) / 3) == 0
