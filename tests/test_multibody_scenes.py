"""The six multibody scenes against routes built here from the same data.

Each scene's parameters are read from the file (``load_system(...).parameters``)
but its dynamics are written out in this module, independently of the solver:

* slider_crank: closed-form kinematics of the crank-rod-piston loop at time t
  (crank angle omega t), then Newton-Euler about each body's mass centre;
* four_bar: closed-form loop kinematics (the triangle A-B-O4), then
  Newton-Euler about each link's mass centre with the two loop-acceleration rows;
* double_pendulum, cart_pendulum: Lagrange's equations written by hand, the pin
  forces from Newton's law of each bob / of the pendulum bar;
* drum_and_block: a = m g r^2 / (I + m r^2), T = m (g - a);
* parallel_link_plate: theta'' from the energy (a one-freedom system whose
  generalized mass is 2 m_l L^2 / 3 + m_p L^2), the pin forces from
  Newton-Euler of the two links and the translating plate.

Every route of the product (``--method``), several reference points
(``--point``) and moved states (``--set``) must agree with these. Tolerance
(:func:`assert_matches`): 1e-10 relative per entry, plus an absolute floor of
1e-12 of the largest entry of the same unit. Why: each answer is one linear
solve of a system whose (equilibrated) condition number is below 1e3 at all
the states used here (checked: ``condition_number_estimate`` in the answers), so
double-precision round-off leaves ~1e3 * 2.2e-16 * (largest entry) ~ 1e-13 of
the largest entry in every entry, and the dependent coordinates are solved by Newton to a
residual of 1e-13; 1e-10 is therefore well above what a correct solver
can show (three orders), and an error in any term of the dynamics (a wrong inertia, a missed
Coriolis term, a wrong sign) shows orders of magnitude above it. The floor
covers reactions that are exactly zero (``M_cyl``, ``N_guide``), which a
correct solve returns up to that round-off.
"""
from __future__ import annotations

import json
import math
import re
from functools import lru_cache
from pathlib import Path

import numpy as np
import pytest

from solver.analyses.instant import assemble, solve_instant
from solver.formulations import formulate
from solver.io.scenes import load_system

SCENES = Path(__file__).resolve().parent.parent / "data" / "scenes"
RTOL = 1e-10  # see the module docstring
FLOOR = 1e-12  # absolute floor, as a fraction of the largest entry of the same unit (module docstring)
N, NM, RAD2, M2 = "N", "N*m", "rad/s**2", "m/s**2"


def params(scene: str, overrides: dict | None = None) -> dict[str, float]:
    """The scene's parameters in SI (angles in rad), read by the product's loader only."""
    system = load_system(SCENES / f"{scene}.toml", overrides)
    return {k: float(q.to_base_units().magnitude) for k, q in system.parameters.items()}


def cross(a, b) -> float:
    return a[0] * b[1] - a[1] * b[0]


def e(angle: float) -> np.ndarray:
    return np.array([math.cos(angle), math.sin(angle)])


def kxe(w: float, v) -> np.ndarray:
    """(w k) x v."""
    return np.array([-w * v[1], w * v[0]])


def solve_affine(residual, n: int) -> np.ndarray:
    """Solve residual(u) = 0 for u in R^n, residual affine in u (columns by unit vectors)."""
    r0 = np.asarray(residual(np.zeros(n)), dtype=float)
    A = np.column_stack([np.asarray(residual(np.eye(n)[i]), dtype=float) - r0 for i in range(n)])
    assert A.shape == (n, n)
    assert np.linalg.cond(A) < 1e6  # the reference itself must be well posed
    return np.linalg.solve(A, -r0)


def assert_matches(got: dict, ref: dict, label: str = "") -> None:
    """``got``: name -> (value, unit) from the product; ``ref``: the same from this module."""
    assert set(got) == set(ref), f"{label}: unknowns {sorted(got)} != {sorted(ref)}"
    largest: dict[str, float] = {}
    for value, unit in ref.values():
        largest[unit] = max(largest.get(unit, 0.0), abs(value))
    for name, (value, unit) in ref.items():
        g, gu = got[name]
        assert gu == unit, f"{label}: {name} in {gu}, expected {unit}"
        tol = RTOL * abs(value) + FLOOR * largest[unit]
        assert abs(g - value) <= tol, f"{label}: {name} = {g!r}, independent route {value!r} (|diff| {abs(g - value):.3g} > {tol:.3g})"


def from_json(payload: dict) -> dict:
    return {k: (v["value"], v["unit"]) for k, v in payload["unknowns"].items()}


def from_solution(sol) -> dict:
    return {k: (float(q.magnitude), _unit(q)) for k, q in sol.unknowns.items()}


def _unit(q) -> str:
    for u in (N, NM, RAD2, M2):
        if q.units == q._REGISTRY.Unit(u):
            return u
    return str(q.units)


# --------------------------------------------------------------------------- independent routes
def slider_crank_ref(p: dict, t: float, left: bool = False):
    """(state, unknowns) of the slider-crank at time t: closed-form kinematics, Newton-Euler about G.
    ``left``: the other assembly, with the piston to the left of the crank pin (cos phi < 0)."""
    r, l, w, g = p["r"], p["l"], p["omega"], p["g"]
    th = w * t  # the motor's angle; constant speed, so theta'' = 0
    phi = math.asin(-r * math.sin(th) / l)  # piston on the x axis: sin(phi) = -r sin(theta) / l
    if left:
        phi = math.pi - phi
    phid = -r * w * math.cos(th) / (l * math.cos(phi))
    phidd = (r * w**2 * math.sin(th) + l * math.sin(phi) * phid**2) / (l * math.cos(phi))
    rA = r * e(th)
    aA = -r * w**2 * e(th)
    rB = rA + l * e(phi)
    aB = aA + kxe(phidd, l * e(phi)) - phid**2 * l * e(phi)
    assert abs(rB[1]) < 1e-15 and abs(aB[1]) < 1e-9 * abs(aB[0])  # the piston stays on its line
    # crank: uniform bar O-A
    mc = p["m_c"]
    rGc, aGc, Ic = rA / 2, aA / 2, mc * r**2 / 12
    # rod: big-end ring at A, shank A-B, small-end ring at B (parallel axes about A)
    mb, ms, msm = p["m_big"], p["m_s"], p["m_small"]
    mR = mb + ms + msm
    xG = (ms * l / 2 + msm * l) / mR
    IA = mb * p["r_big"] ** 2 + ms * l**2 / 3 + msm * (p["r_small"] ** 2 + l**2)
    IR = IA - mR * xG**2
    rGR = rA + xG * e(phi)
    aGR = aA + kxe(phidd, xG * e(phi)) - phid**2 * xG * e(phi)
    mp = p["m_p"]

    def res(u):
        Ox, Oy, M, Ax, Ay, Bx, By, Nc, Mc = u
        O, A, B = np.array([Ox, Oy]), np.array([Ax, Ay]), np.array([Bx, By])
        return [
            *(O - A - mc * aGc - [0, mc * g]),
            M + cross(-rGc, O) + cross(rA - rGc, -A) - Ic * 0.0,
            *(A - B - mR * aGR - [0, mR * g]),
            cross(rA - rGR, A) + cross(rB - rGR, -B) - IR * phidd,
            *(B + [0, Nc] - mp * aB - [0, mp * g]),
            Mc,  # the piston (a point mass) has no inertia about B
        ]

    u = solve_affine(res, 9)
    names = ["O_x", "O_y", "M_drive", "A_x", "A_y", "B_x", "B_y", "N_cyl", "M_cyl"]
    out = {"phi_ddot": (phidd, RAD2)}
    out.update({n: (float(v), NM if n.startswith("M_") else N) for n, v in zip(names, u)})
    return {"phi": phi, "phi_dot": phid}, out


def four_bar_angles(p: dict, th2: float, guess3: float) -> tuple[float, float]:
    """theta3, theta4 by the triangle A-B-O4 (the assembly nearest to the coupler's guess)."""
    a, b, c, d = p["a"], p["b"], p["c"], p["d"]
    A = a * e(th2)
    D = np.array([d, 0.0]) - A
    dist = math.hypot(*D)
    gamma = math.acos((b**2 + dist**2 - c**2) / (2 * b * dist))
    delta = math.atan2(D[1], D[0])
    th3 = min((delta + gamma, delta - gamma), key=lambda x: abs(math.remainder(x - guess3, 2 * math.pi)))
    B = A + b * e(th3)
    th4 = math.atan2(B[1], B[0] - d)
    return th3, th4


def four_bar_ref(p: dict, th2: float, w2: float, guess3: float = math.radians(20)):
    a, b, c, g = p["a"], p["b"], p["c"], p["g"]
    th3, th4 = four_bar_angles(p, th2, guess3)
    # velocity loop: a w2 e2' + b w3 e3' - c w4 e4' = 0, e' = k x e
    J = np.column_stack([b * kxe(1, e(th3)), -c * kxe(1, e(th4))])
    w3, w4 = np.linalg.solve(J, -a * w2 * kxe(1, e(th2)))
    m2, m3, m4 = p["m2"], p["m3"], p["m4"]
    rA = a * e(th2)
    rO4 = np.array([p["d"], 0.0])
    rB = rO4 + c * e(th4)

    def res(u):
        al2, al3, al4, O2x, O2y, Ax, Ay, Bx, By, O4x, O4y = u
        O2, A, B, O4 = (np.array(v) for v in ([O2x, O2y], [Ax, Ay], [Bx, By], [O4x, O4y]))
        aA = kxe(al2, rA) - w2**2 * rA
        aG2 = aA / 2
        aG3 = aA + kxe(al3, b / 2 * e(th3)) - w3**2 * b / 2 * e(th3)
        aB3 = aA + kxe(al3, b * e(th3)) - w3**2 * b * e(th3)
        aB4 = kxe(al4, c * e(th4)) - w4**2 * c * e(th4)
        G2, G3, G4 = rA / 2, rA + b / 2 * e(th3), (rO4 + rB) / 2
        aG4 = aB4 / 2
        return [
            *(O2 - A - m2 * aG2 - [0, m2 * g]),
            cross(-G2, O2) + cross(rA - G2, -A) - m2 * a**2 / 12 * al2,
            *(A - B - m3 * aG3 - [0, m3 * g]),
            cross(rA - G3, A) + cross(rB - G3, -B) - m3 * b**2 / 12 * al3,
            *(O4 + B - m4 * aG4 - [0, m4 * g]),
            cross(rO4 - G4, O4) + cross(rB - G4, B) - m4 * c**2 / 12 * al4,
            *(aB3 - aB4),  # the loop closes in acceleration
        ]

    u = solve_affine(res, 11)
    names = ["theta2_ddot", "theta3_ddot", "theta4_ddot", "O2_x", "O2_y", "A_x", "A_y", "B_x", "B_y", "O4_x", "O4_y"]
    out = {n: (float(v), RAD2 if n.endswith("_ddot") else N) for n, v in zip(names, u)}
    return {"theta3": th3, "theta3_dot": w3, "theta4": th4, "theta4_dot": w4}, out


def double_pendulum_ref(p: dict, t1: float, t2: float, w1: float, w2: float) -> dict:
    """Lagrange's equations of two bobs on massless links, theta from the downward vertical."""
    m1, m2, l1, l2, g = p["m1"], p["m2"], p["l1"], p["l2"], p["g"]
    s, c = math.sin(t1 - t2), math.cos(t1 - t2)
    M = np.array([[(m1 + m2) * l1, m2 * l2 * c], [l1 * c, l2]])
    rhs = np.array([-m2 * l2 * w2**2 * s - (m1 + m2) * g * math.sin(t1),
                    l1 * w1**2 * s - g * math.sin(t2)])
    a1, a2 = np.linalg.solve(M, rhs)
    u1, u2 = np.array([math.sin(t1), -math.cos(t1)]), np.array([math.sin(t2), -math.cos(t2)])
    n1, n2 = np.array([math.cos(t1), math.sin(t1)]), np.array([math.cos(t2), math.sin(t2)])  # d u / d theta
    aA = l1 * (a1 * n1 - w1**2 * u1)
    aB = aA + l2 * (a2 * n2 - w2**2 * u2)
    A = m2 * aB + [0, m2 * g]  # pin A on the lower bob
    O = m1 * aA + A + [0, m1 * g]  # pin O on the upper bob (which also carries -A)
    return {"theta1_ddot": (a1, RAD2), "theta2_ddot": (a2, RAD2),
            "O_x": (O[0], N), "O_y": (O[1], N), "A_x": (A[0], N), "A_y": (A[1], N)}


def cart_pendulum_ref(p: dict, th: float, xd: float, thd: float) -> dict:
    """Lagrange's equations of the cart (M) and the hanging uniform bar (m, L), by hand:
    (M + m) x'' + m d (th'' cos th - th'^2 sin th) = 0,  m d x'' cos th + (m L^2/3) th'' + m g d sin th = 0."""
    M, m, L, g = p["M"], p["m"], p["L"], p["g"]
    d = L / 2
    A = np.array([[M + m, m * d * math.cos(th)], [m * d * math.cos(th), m * L**2 / 3]])
    rhs = np.array([m * d * thd**2 * math.sin(th), -m * g * d * math.sin(th)])
    xdd, thdd = np.linalg.solve(A, rhs)
    aG = np.array([xdd + d * (thdd * math.cos(th) - thd**2 * math.sin(th)),
                   d * (thdd * math.sin(th) + thd**2 * math.cos(th))])
    C = m * aG + [0, m * g]  # the pin's force on the bar
    return {"x_ddot": (xdd, M2), "theta_ddot": (thdd, RAD2), "N_track": (M * g + C[1], N),
            "M_track": (0.0, NM), "C_x": (C[0], N), "C_y": (C[1], N)}


def drum_and_block_ref(p: dict) -> dict:
    """a = m g r^2 / (I + m r^2) downwards; the drum turns clockwise (phi'' = -a / r)."""
    m, r, g = p["m"], p["r"], p["g"]
    I = p["m_d"] * p["k_d"] ** 2
    a = m * g * r**2 / (I + m * r**2)
    T = m * (g - a)
    return {"phi_ddot": (-a / r, RAD2), "axle_x": (0.0, N), "axle_y": (p["m_d"] * g + T, N), "T": (T, N),
            "N_guide": (0.0, N), "M_guide": (0.0, NM)}


def parallel_link_plate_ref(p: dict, th: float, thd: float) -> dict:
    mp, w, h, ml, L, g = p["m_p"], p["w"], p["h"], p["m_l"], p["L"], p["g"]
    thdd = -(ml + mp) * g * L * math.sin(th) / (2 * ml * L**2 / 3 + mp * L**2)
    u = np.array([math.sin(th), -math.cos(th)])  # the links' direction, pivot to tip
    n = np.array([math.cos(th), math.sin(th)])  # d u / d theta
    O1, O2 = np.zeros(2), np.array([w, 0.0])
    A, B = O1 + L * u, O2 + L * u
    G = A + [w / 2, -h / 2]

    def res(x):
        al, O1x, O1y, O2x, O2y, Ax, Ay, Bx, By = x
        F1, F2, FA, FB = (np.array(v) for v in ([O1x, O1y], [O2x, O2y], [Ax, Ay], [Bx, By]))
        aTip = L * (al * n - thd**2 * u)  # both link tips, and every point of the plate
        eqs = []
        for O, F, tip, Ft in ((O1, F1, A, FA), (O2, F2, B, FB)):
            Gl = (O + tip) / 2
            eqs += [*(F - Ft - ml * aTip / 2 - [0, ml * g]),
                    cross(O - Gl, F) + cross(tip - Gl, -Ft) - ml * L**2 / 12 * al]
        eqs += [*(FA + FB - mp * aTip - [0, mp * g]), cross(A - G, FA) + cross(B - G, FB)]
        return eqs

    x = solve_affine(res, 9)
    assert abs(x[0] - thdd) <= 1e-12 * abs(thdd) + 1e-15  # Newton-Euler and the energy agree
    names = ["theta_ddot", "O1_x", "O1_y", "O2_x", "O2_y", "A_x", "A_y", "B_x", "B_y"]
    return {nm: (float(v), RAD2 if nm == "theta_ddot" else N) for nm, v in zip(names, x)}


def deg(x: float) -> float:
    return math.radians(x)


def reference(scene: str, overrides: dict | None = None):
    """(state dict or None, unknowns) at the scene's state after ``overrides`` (quantity strings)."""
    p = params(scene, overrides)
    s = load_system(SCENES / f"{scene}.toml", overrides)
    c = {co.name: co for co in s.coordinates}
    if scene == "slider_crank":
        return slider_crank_ref(p, s.time, left=math.cos(c["phi"].value) < 0)  # the guess picks the assembly
    if scene == "four_bar":
        return four_bar_ref(p, c["theta2"].value, c["theta2"].rate, c["theta3"].value)
    if scene == "double_pendulum":
        return None, double_pendulum_ref(p, c["theta1"].value, c["theta2"].value, c["theta1"].rate, c["theta2"].rate)
    if scene == "cart_pendulum":
        return None, cart_pendulum_ref(p, c["theta"].value, c["x"].rate, c["theta"].rate)
    if scene == "drum_and_block":
        return None, drum_and_block_ref(p)
    return None, parallel_link_plate_ref(p, c["theta"].value, c["theta"].rate)


# The state read above from the product's loader is the *given* state (values and
# rates exactly as written or --set); the independent routes compute everything else.
# To make sure the loader reads those correctly, the expected values are also pinned:
def test_given_states_are_read_as_written():
    s = load_system(SCENES / "four_bar.toml", {"theta2": "75 deg", "theta2_dot": "-3 rad/s"})
    th2 = next(c for c in s.coordinates if c.name == "theta2")
    assert (th2.value, th2.rate) == (pytest.approx(deg(75), rel=1e-15), -3.0)
    assert params("slider_crank")["omega"] == 100.0 and params("drum_and_block")["k_d"] == 0.15


def test_kinematics_of_the_four_bar_rockers_fixed_pivot():
    """`kinematics` gives the rocker's pivot O4 where the pin to the ground holds it, (d, 0) =
    (0.28 m, 0) as the scene writes it, at rest, exactly (the placement, through the coupler, put
    round-off there: 2.7e-15 m); the rocker's B, carried from O4, is the coupler's B (the pin B)
    to the module's tolerance."""
    from solver.analyses.kinematics import kinematics_at

    out = kinematics_at(load_system(SCENES / "four_bar.toml"))["points"]
    o4 = out["rocker:O4"]
    assert (o4["position"]["value"], o4["velocity"]["value"], o4["acceleration"]["value"]) == (
        [0.28, 0.0], [0.0, 0.0], [0.0, 0.0])
    for what in ("position", "velocity", "acceleration"):
        ours, theirs = out["rocker:B"][what]["value"], out["coupler:B"][what]["value"]
        assert ours == pytest.approx(theirs, rel=RTOL, abs=FLOOR * max(map(abs, theirs))), what


def test_references_reproduce_textbook_limits():
    """Sanity of the references themselves: a double pendulum hanging straight with
    no motion feels no acceleration and carries the weights; the drum's closed form
    for a massless drum is free fall."""
    p = {"m1": 2.0, "m2": 3.0, "l1": 1.0, "l2": 0.5, "g": 10.0}
    ref = double_pendulum_ref(p, 0.0, 0.0, 0.0, 0.0)
    assert ref["O_y"][0] == pytest.approx(50.0) and ref["A_y"][0] == pytest.approx(30.0)
    assert ref["theta1_ddot"][0] == 0.0 and ref["theta2_ddot"][0] == 0.0
    assert drum_and_block_ref({"m": 1.0, "r": 0.1, "g": 9.0, "m_d": 0.0, "k_d": 0.1})["phi_ddot"][0] == pytest.approx(-90.0)


# --------------------------------------------------------------------------- the command line
# (scene, method, point, --set overrides): every method, several points, moved states.
# The Lagrange route costs 0.2-2 s per system, so on the command line it runs on the
# three cheap scenes; the other three go through the Python API below (one system each,
# several states at once).
CASES = [
    ("slider_crank", "generalized_euler", None, {}),
    ("slider_crank", "generalized_euler", "rod:G", {"omega": "60 rad/s"}),
    ("slider_crank", "generalized_euler", "B", {"r": "0.06 m", "omega": "-80 rad/s"}),
    ("slider_crank", "mass_center", "crank:A", {}),
    ("slider_crank", "generalized_euler", "piston:G", {"phi": "170 deg"}),  # the other assembly
    ("four_bar", "generalized_euler", None, {}),
    ("four_bar", "generalized_euler", "coupler:B", {"theta2": "75 deg", "theta2_dot": "-3 rad/s"}),
    ("four_bar", "mass_center", None, {"theta2": "200 deg", "theta2_dot": "5 rad/s"}),
    ("double_pendulum", "generalized_euler", None, {}),
    ("double_pendulum", "generalized_euler", "lower:B", {"theta1": "-50 deg", "theta2_dot": "1.5 rad/s"}),
    ("double_pendulum", "mass_center", "upper:A", {"theta2": "120 deg", "theta1_dot": "-2 rad/s"}),
    ("double_pendulum", "lagrange", "G", {"theta1": "-50 deg", "theta2_dot": "1.5 rad/s", "m2": "2.5 kg"}),
    ("cart_pendulum", "generalized_euler", None, {}),
    ("cart_pendulum", "generalized_euler", "pendulum:E", {"theta": "-35 deg", "theta_dot": "2 rad/s"}),
    ("cart_pendulum", "mass_center", "G", {"x_dot": "-1 m/s", "theta_dot": "-1 rad/s"}),
    ("cart_pendulum", "lagrange", "cart:G", {"theta": "100 deg", "theta_dot": "3 rad/s", "M": "0.7 kg"}),
    ("drum_and_block", "generalized_euler", "G", {"phi_dot": "3 rad/s", "m": "5 kg"}),
    ("drum_and_block", "mass_center", None, {"phi": "40 deg"}),
    ("drum_and_block", "lagrange", "block:G", {"k_d": "0.3 m", "phi_dot": "-2 rad/s"}),
    ("parallel_link_plate", "mass_center", None, {}),
    ("parallel_link_plate", "generalized_euler", "plate:G", {"theta": "-20 deg", "theta_dot": "1 rad/s"}),
    ("parallel_link_plate", "generalized_euler", "B", {"theta": "70 deg", "h": "0.5 m"}),
]


@pytest.mark.parametrize("scene, method, point, overrides", CASES,
                         ids=[f"{c[0]}-{c[1]}-{c[2]}-{'+'.join(c[3]) or 'as-written'}" for c in CASES])
def test_command_line_agrees_with_independent_route(solver_cli, scene, method, point, overrides):
    argv = ["solve", str(SCENES / f"{scene}.toml"), "--method", method, "--json"]
    if point is not None:
        argv += ["--point", point]
    for k, v in overrides.items():
        argv += ["--set", f"{k}={v}"]
    code, out, err = solver_cli(*argv)
    assert code == 0, err
    payload = json.loads(out)
    assert payload["method"] == method
    assert payload["condition_number_estimate"] < 1e2  # the premise of the tolerance (module docstring)
    state, ref = reference(scene, overrides)
    assert_matches(from_json(payload), ref, f"{scene} {method} {point} {overrides}")
    if state is not None:  # the dependent coordinates and rates, solved by the product
        for k, v in state.items():
            got = payload["state"][k]["value"]
            assert abs(got - v) <= 1e-12 * max(1.0, abs(v)), f"{k}: {got} vs {v}"


# --------------------------------------------------------------------------- the Python API
@lru_cache(maxsize=None)
def _system(scene: str):
    """One system per scene: its formulations are cached on it."""
    return load_system(SCENES / f"{scene}.toml")


def _states(scene: str):
    """Moved states for the vectorised solve: (q, qd, t) lists and the references there."""
    s = _system(scene)
    p = params(scene)
    out = []
    if scene == "slider_crank":
        for t in (0.0, 0.004, 0.013, 0.031, 0.05):
            st = assemble(s, [math.radians(-10) if math.sin(p["omega"] * t) > 0 else math.radians(10)], [0.0], t)
            out.append((st, slider_crank_ref(p, t)))
    elif scene == "four_bar":
        for th2, w2 in ((deg(60), 2.0), (deg(0), -1.0), (deg(135), 4.0), (deg(-100), 0.5)):
            ref = four_bar_ref(p, th2, w2)
            st = assemble(s, [th2, ref[0]["theta3"] + 0.01, ref[0]["theta4"] - 0.01], [w2, 0.0, 0.0])
            out.append((st, ref))
    elif scene == "parallel_link_plate":
        for th, w in ((deg(30), 2.0), (deg(-60), -1.0), (deg(170), 0.3)):
            out.append((assemble(s, [th], [w]), (None, parallel_link_plate_ref(p, th, w))))
    elif scene == "double_pendulum":
        for a, b, wa, wb in ((30, 10, 0, 0), (-70, 150, 1, -2), (5, -5, 3, 0.5)):
            st = assemble(s, [deg(a), deg(b)], [wa, wb])
            out.append((st, (None, double_pendulum_ref(p, deg(a), deg(b), wa, wb))))
    elif scene == "cart_pendulum":
        for th, xd, w in ((20, 0.5, 0), (-120, -1, 2), (90, 0, -3)):
            st = assemble(s, [0.3, deg(th)], [xd, w])
            out.append((st, (None, cart_pendulum_ref(p, deg(th), xd, w))))
    else:
        for ph, w in ((0, 0), (deg(300), -4.0)):
            out.append((assemble(s, [ph], [w]), (None, drum_and_block_ref(p))))
    return out



# The Lagrange route of the three other scenes runs on the command line above.
API_CASES = [(scene, "generalized_euler") for scene in ("slider_crank", "four_bar", "parallel_link_plate",
                                                        "double_pendulum", "cart_pendulum", "drum_and_block")]
API_CASES += [(scene, "lagrange") for scene in ("slider_crank", "four_bar", "parallel_link_plate")]


@pytest.mark.parametrize("scene, method", API_CASES)
def test_python_api_over_several_states(scene, method):
    """Each route's numeric model, solved for several states at once, against the references."""
    s = _system(scene)
    cases = _states(scene)
    model = formulate(s, method, None).numeric()
    q = [np.array([st.q[i] for st, _ in cases]) for i in range(len(s.free))]
    qd = [np.array([st.qd[i] for st, _ in cases]) for i in range(len(s.free))]
    t = np.array([st.t for st, _ in cases])
    res = model.solve(q, qd, t)
    assert np.all(res["condition_number"] < 1e3)  # the premise of the tolerance
    for k, (st, (state, ref)) in enumerate(cases):
        got = {name: (float(res[name][k]), unit) for name, (_, unit) in ref.items()}
        assert_matches(got, ref, f"{scene} {method} state {k}")
        if state is not None:
            names = [c.name for c in s.free]
            for name, v in state.items():
                val = st.qd[names.index(name[:-4])] if name.endswith("_dot") else st.q[names.index(name)]
                assert abs(val - v) <= 1e-12 * max(1.0, abs(v)), f"{name}: {val} vs {v}"


@pytest.mark.parametrize("scene, point", [("four_bar", "coupler:G")])
def test_solve_instant_through_the_api(scene, point):
    """solve_instant (the public entry point) at the scene's own state, another point."""
    sol = solve_instant(_system(scene), point, "generalized_euler")
    state, ref = reference(scene)
    assert_matches(from_solution(sol), ref, f"{scene} api {point}")


# --------------------------------------------------------------------------- small oscillations
def _numbers(x):
    """Every number in a JSON value, whatever its layout."""
    if isinstance(x, dict):
        for v in x.values():
            yield from _numbers(v)
    elif isinstance(x, list):
        for v in x:
            yield from _numbers(v)
    elif isinstance(x, (int, float)) and not isinstance(x, bool):
        yield float(x)


@pytest.mark.parametrize("method, overrides", [("generalized_euler", {}), ("mass_center", {"m_p": "3 kg", "L": "0.9 m"})])
def test_parallel_link_plate_frequency(solver_cli, method, overrides):
    """One freedom: omega^2 = (m_l + m_p) g L / (2 m_l L^2 / 3 + m_p L^2) (the generalized mass of
    the two links about their pivots and the translating plate). 1e-10 relative: a ratio of two
    sums of a few products, round-off ~1e-15."""
    argv = ["frequency", str(SCENES / "parallel_link_plate.toml"), "--method", method, "--json"]
    for k, v in overrides.items():
        argv += ["--set", f"{k}={v}"]
    code, out, err = solver_cli(*argv)
    assert code == 0, err
    p = params("parallel_link_plate", overrides)
    ml, mp, L = p["m_l"], p["m_p"], p["L"]
    w = math.sqrt((ml + mp) * p["g"] * L / (2 * ml * L**2 / 3 + mp * L**2))
    payload = json.loads(out)
    assert payload["omega_n"]["unit"] == "rad/s"
    assert abs(payload["omega_n"]["value"] - w) <= 1e-10 * w
    assert abs(payload["equilibrium"]["value"]) <= 1e-12


def test_cart_pendulum_frequency(solver_cli):
    """The pendulum's mode with the cart free: (M + m) x'' + m d th'' = 0, m d x'' + I_O th'' + m g d th = 0
    give omega^2 = (M + m) m g d / ((M + m) I_O - m^2 d^2), d = L/2, I_O = m L^2/3. It must appear
    in the JSON answer (whatever its layout) to 1e-10 relative (round-off ~1e-15)."""
    code, out, err = solver_cli("frequency", str(SCENES / "cart_pendulum.toml"), "--json")
    assert code == 0, err
    p = params("cart_pendulum")
    M, m, L = p["M"], p["m"], p["L"]
    d, IO = L / 2, m * L**2 / 3
    w = math.sqrt((M + m) * m * p["g"] * d / ((M + m) * IO - m**2 * d**2))
    found = list(_numbers(json.loads(out)))
    assert any(abs(v - w) <= 1e-10 * w for v in found), f"omega = {w} rad/s not in {out}"


def four_bar_small_oscillations(p: dict, th2_start: float, guess3: float) -> tuple[float, float]:
    """(theta2 at the stable equilibrium, omega_n) of the four-bar under gravity, on the assembly of
    the scene, by closed-form loop kinematics: V'(theta2) and V''(theta2) from the first- and
    second-order velocity ratios (theta3' = k3 theta2', theta3'' = l3 theta2'^2 when theta2'' = 0,
    from the loop's velocity and acceleration equations), the generalized mass from the
    kinetic energy; omega^2 = V''/M at the root of V' with V'' > 0 (one per turn here)."""
    a, b, c, g = p["a"], p["b"], p["c"], p["g"]
    m2, m3, m4 = p["m2"], p["m3"], p["m4"]

    def ratios(th2, g3):
        th3, th4 = four_bar_angles(p, th2, g3)
        J = np.column_stack([b * kxe(1, e(th3)), -c * kxe(1, e(th4))])
        k3, k4 = np.linalg.solve(J, -a * kxe(1, e(th2)))
        l3, l4 = np.linalg.solve(J, a * e(th2) + b * k3**2 * e(th3) - c * k4**2 * e(th4))
        return th3, th4, k3, k4, l3, l4

    def dV(th2, g3):  # V = g (m2 yG2 + m3 yG3 + m4 yG4): (V', V'')
        th3, th4, k3, k4, l3, l4 = ratios(th2, g3)
        s2, c2, s3, c3, s4, c4 = (f(x) for x in (th2, th3, th4) for f in (math.sin, math.cos))
        d1 = m2 * a / 2 * c2 + m3 * (a * c2 + b / 2 * c3 * k3) + m4 * c / 2 * c4 * k4
        d2 = (-m2 * a / 2 * s2 + m3 * (-a * s2 + b / 2 * (-s3 * k3**2 + c3 * l3))
              + m4 * c / 2 * (-s4 * k4**2 + c4 * l4))
        return g * d1, g * d2

    th, g3 = th2_start, guess3
    step = 2 * math.pi / 720
    for _ in range(720):  # follow the assembly round one turn to a sign change - to + of V'
        lo, g_lo = th, g3
        th += step
        g3 = ratios(th, g3)[0]
        if dV(lo, g_lo)[0] < 0 <= dV(th, g3)[0]:
            break
    else:
        raise AssertionError("no stable equilibrium in one turn")
    hi = th
    for _ in range(200):  # bisection to round-off
        mid = (lo + hi) / 2
        if mid in (lo, hi):
            break
        if dV(mid, g3)[0] < 0:
            lo = mid
        else:
            hi = mid
    th3, th4, k3, k4, _, _ = ratios(lo, g3)
    v3 = a * kxe(1, e(lo)) + b / 2 * k3 * kxe(1, e(th3))
    M = (m2 * a**2 / 3 + m3 * (v3 @ v3) + m3 * b**2 / 12 * k3**2 + m4 * c**2 / 3 * k4**2)
    V2 = dV(lo, g3)[1]
    assert V2 > 0
    return lo, math.sqrt(V2 / M)


def test_four_bar_reference_frequency_is_consistent():
    """The four-bar reference: V' = 0 there, and omega^2 from V''/M agrees with the linearised
    instantaneous route of this module (four_bar_ref): theta2'' = -omega^2 (theta2 - theta_e) for a
    small displacement from rest, to O(displacement) (1e-4 at 1e-6 rad)."""
    p = params("four_bar")
    th_e, w = four_bar_small_oscillations(p, math.radians(60), math.radians(20))
    g3 = four_bar_angles(p, th_e, math.radians(65))[0]
    eps = 1e-6
    _, ref = four_bar_ref(p, th_e + eps, 0.0, g3)
    assert ref["theta2_ddot"][0] == pytest.approx(-w**2 * eps, rel=1e-4)


def test_four_bar_frequency(solver_cli):
    """omega_n about the stable equilibrium (theta2 = 258.05 deg on the scene's assembly) to 1e-10
    relative: the reference has V'' in closed form and the equilibrium to round-off."""
    code, out, err = solver_cli("frequency", str(SCENES / "four_bar.toml"), "--json")
    assert code == 0, err
    th_e, w = four_bar_small_oscillations(params("four_bar"), math.radians(60), math.radians(20))
    payload = json.loads(out)
    assert abs(payload["omega_n"]["value"] - w) <= 1e-10 * w
    assert abs(math.remainder(payload["equilibrium"]["value"] - th_e, 2 * math.pi)) <= 1e-9


def test_double_pendulum_normal_mode_frequencies(solver_cli):
    """Equal masses and lengths: omega^2 = (2 -/+ sqrt 2) g / l. Both numbers must appear in the
    JSON answer (whatever its layout) to 1e-10 relative (an eigenvalue problem of a 2x2 system
    with well separated eigenvalues, ratio 5.8: round-off ~1e-15)."""
    code, out, err = solver_cli("frequency", str(SCENES / "double_pendulum.toml"), "--json")
    assert code == 0, err
    p = params("double_pendulum")
    expected = [math.sqrt((2 + s * math.sqrt(2)) * p["g"] / p["l1"]) for s in (-1, 1)]

    found = list(_numbers(json.loads(out)))
    for w in expected:
        assert any(abs(v - w) <= 1e-10 * w for v in found), f"omega = {w} rad/s not in {out}"


def two_bar_small_oscillations() -> tuple[np.ndarray, np.ndarray]:
    """(omega [rad/s], shapes as columns, largest component 1) of tests/data/multibody/two_bar.toml
    about (0, 0), typed by hand: slender bars m1 = 2 kg, L1 = 0.6 m and m2 = 1 kg, L2 = 0.4 m,
    angles from the downward vertical. Linearised, T = q'^T M q' / 2 with
    M = [[m1 L1^2 / 3 + m2 L1^2, m2 L1 L2 / 2], [m2 L1 L2 / 2, m2 L2^2 / 3]] and
    V = -g ((m1 / 2 + m2) L1 cos th1 + m2 L2 / 2 cos th2), so K = diag(g (m1 / 2 + m2) L1, g m2 L2 / 2);
    omega^2 are the eigenvalues of K v = omega^2 M v (scipy.linalg.eigh)."""
    from scipy.linalg import eigh

    m1, m2, L1, L2, g = 2.0, 1.0, 0.6, 0.4, 9.81
    M = np.array([[m1 * L1**2 / 3 + m2 * L1**2, m2 * L1 * L2 / 2], [m2 * L1 * L2 / 2, m2 * L2**2 / 3]])
    K = np.diag([g * (m1 / 2 + m2) * L1, g * m2 * L2 / 2])
    w2, shapes = eigh(K, M)
    return np.sqrt(w2), shapes / shapes[np.argmax(np.abs(shapes), axis=0), [0, 1]]


@pytest.mark.parametrize("th1, th2", [("20 deg", "-40 deg"), ("20 deg", "-60 deg"), ("20 deg", "-90 deg"),
                                      ("20 deg", "-170 deg"), ("180 deg", "180 deg")])
def test_frequency_about_the_nearest_stable_equilibrium(solver_cli, th1, th2):
    """QA round 9 item 3: from (20, th2) deg Newton's method on the accelerations at rest reached
    the unstable (0, -180) deg (141 deg or more away) and `frequency` refused; the stable (0, 0) is
    at most 92 deg away; from (20, -170) deg it is (0, 0), 171 deg away, not (0, -360), 191 deg
    away, where the descent ends. Released on the maximum of the potential itself, (180, 180) deg, every
    hanging position is as near (the equilibrium is checked modulo a turn). The modes must be
    those about the hanging position: 1e-10 relative, as the other frequency tests (a 2x2
    eigenproblem, eigenvalues 6 apart; the linearisation's error ~1e-11); the equilibrium to
    1e-9 rad (it is found to round-off)."""
    scene = Path(__file__).parent / "data" / "multibody" / "two_bar.toml"
    code, out, err = solver_cli("frequency", str(scene), "--set", f"th1={th1}", "--set", f"th2={th2}", "--json")
    assert code == 0, err
    payload = json.loads(out)
    found = [payload["equilibrium"][c]["value"] for c in ("th1", "th2")]
    if th1 == "180 deg":
        found = [math.remainder(x, 2 * math.pi) for x in found]
    assert found == pytest.approx([0.0, 0.0], abs=1e-9)
    omega, shapes = two_bar_small_oscillations()
    assert [m["omega_n"]["value"] for m in payload["modes"]] == pytest.approx(omega, rel=1e-10)
    for k, mode in enumerate(payload["modes"]):  # the shapes too: they tell a mode about (0, 0) from others
        got = [mode["shape"][c]["value"] for c in ("th1", "th2")]
        assert got == pytest.approx(shapes[:, k], rel=1e-8, abs=1e-10)  # eigenvectors: ~1e-11 from J's differences


def test_frequency_keeps_a_free_cart_where_it_is(solver_cli):
    """The cart pendulum released nearly upright (theta = 179 deg, x = 0.5 m): every x is an
    equilibrium with the bar hanging, and the nearest is x = 0.5 m, theta = 0 (the descent to it
    moves the cart; taken back along that neutral direction). 1e-9 m and rad: found to round-off."""
    code, out, err = solver_cli("frequency", str(SCENES / "cart_pendulum.toml"), "--set", "theta=179 deg",
                                "--set", "x=0.5 m", "--json")
    assert code == 0, err
    found = json.loads(out)["equilibrium"]
    assert [found["x"]["value"], found["theta"]["value"]] == pytest.approx([0.5, 0.0], abs=1e-9)


DISK_PENDULUM = (Path(__file__).parent / "data" / "multibody" / "disk_pend.toml").read_text(encoding="utf-8")


def test_frequency_prints_a_neutral_coordinate_at_the_states_value(solver_cli, tmp_path):
    """A disk rolling on the floor with a bar hanging from its centre: every x is an equilibrium
    (nothing depends on it), so the equilibrium about which the modes are taken is x = 0, the
    state's. Regression: "stable equilibrium x = -3.71687e-13 m", where Newton's round-off had
    left x. 1e-15 m: the state's value to the round-off of one move along the neutral direction,
    far below that noise."""
    scene = tmp_path / "disk_pend.toml"
    scene.write_text(DISK_PENDULUM)
    code, out, err = solver_cli("frequency", str(scene))
    assert code == 0, err
    assert "stable equilibrium x = 0 m, th = 0 deg" in out
    code, out, err = solver_cli("frequency", str(scene), "--json")
    assert abs(json.loads(out)["equilibrium"]["x"]["value"]) <= 1e-15


def test_crank_angle_as_a_prescribed_coordinate(solver_cli, tmp_path):
    """The slider-crank written with theta = { motion = "omega*t" } as the crank's orientation and a
    motor without its own angle (it drives what the coordinate prescribes): the same answers."""
    text = (SCENES / "slider_crank.toml").read_text()
    edits = [('phi = { guess = "-10 deg" }', 'phi = { guess = "-10 deg" }\ntheta = { motion = "omega*t" }'),
             ('name = "crank"\nreference_point = "O"', 'name = "crank"\norientation = "theta"\nreference_point = "O"'),
             ('angle = "omega*t"\n', '')]
    for old, new in edits:
        assert text.count(old) == 1
        text = text.replace(old, new)
    path = tmp_path / "prescribed.toml"
    path.write_text(text)
    code, out, err = solver_cli("solve", str(path), "--json", "--point", "rod:B")
    assert code == 0, err
    state, ref = slider_crank_ref(params("slider_crank"), 0.004)
    assert_matches(from_json(json.loads(out)), ref, "prescribed theta")


def test_cart_pendulum_mode_shape_names_each_components_unit(solver_cli, tmp_path):
    """A mode shape mixes a length and an angle: each component carries its unit, in the scene's
    output units, in JSON and text. Reference: with the cart free, horizontal momentum is conserved,
    (M + m) x'' + m (L/2) theta'' = 0 to first order, so the pendulum mode moves
    x = -m (L/2) / (M + m) theta (0.06 m per rad); printed with length in ft and angle in deg it is
    -0.06 / 0.3048 ft per 180/pi deg. Tolerance 1e-9 relative: the modes come from a
    finite-difference linearization that is exact for the quadratic terms left at the equilibrium
    (observed ~1e-12)."""
    scene = tmp_path / "cart_pendulum_us.toml"
    scene.write_text((SCENES / "cart_pendulum.toml").read_text() + '\n[output_units]\nlength = "ft"\nangle = "deg"\n')
    code, out, err = solver_cli("frequency", str(scene), "--json")
    assert code == 0, err
    neutral, swing = json.loads(out)["modes"]
    assert {k: v["unit"] for k, v in swing["shape"].items()} == {"x": "ft", "theta": "deg"}
    # QA 15 #10: normalised in the printed units (it printed 3.281 ft: 1 m), the largest component 1
    assert neutral["shape"]["x"] == {"value": pytest.approx(1.0, rel=1e-9), "unit": "ft"}
    assert max(abs(v["value"]) for v in swing["shape"].values()) == pytest.approx(1.0, rel=1e-12)
    M, m, L = 2.0, 0.5, 0.6
    per_rad = -m * (L / 2) / (M + m) / 0.3048  # ft per rad
    ratio = swing["shape"]["x"]["value"] / swing["shape"]["theta"]["value"]
    assert ratio == pytest.approx(per_rad * math.pi / 180, rel=1e-9)
    code, text, err = solver_cli("frequency", str(scene))
    assert code == 0, err
    assert re.search(r"x: -?[\d.]+ ft, theta: [\d.]+ deg", text)
