"""The worked equation of motion with slipping contacts holds no reaction (QA 15 #1).

A slipping contact's friction -mu_k N does work, so its normal force N stays in the projection
of the body equations; the worked solution must express N in the coordinates, rates and
accelerations and substitute it. The references are hand-written Newton-Euler equations about
each mass centre, solved with numpy (independent of the solver's formulations):

ladder_friction at theta = 30 deg, from rest, both ends slipping (A to the right along the floor,
B down the wall; data/scenes/ladder_friction.toml: m = 12 kg, L = 5 m, mu_A = 0.3, mu_B = 0.2,
g = 9.80665 m/s^2). A = (L cos th, 0), B = (0, L sin th), G their midpoint; the body's angle is
pi - th, so alpha = -th''. Forces: at A (-mu_A N_A, N_A), at B (N_B, mu_B N_B), gravity at G:

    -mu_A N_A + N_B = m a_Gx,  N_A + mu_B N_B - m g = m a_Gy,  a_G = (L/2)(-sin th, cos th) th''
    (L/2)(cos th - mu_A sin th) N_A - (L/2)(mu_B cos th + sin th) N_B = -(m L^2/12) th''

wheel_pend (tests/data/multibody/wheel_pend.toml): wheel M, R at C = (x, R), angle phi, sliding
forward with backspin (slip velocity x' + R phi' = 3.5 m/s > 0, friction -mu_k N along x); a bar
m, L hung from C at angle th from the downward vertical (G_a = C + (L/2)(sin th, -cos th)), pin
force (X, Y) on the bar, (-X, -Y) on the wheel; from rest in th:

    M x'' = -mu_k N - X,  0 = N - M g - Y,  (M R^2/2) phi'' = -R mu_k N
    m (x'' + (L/2) cos th th'') = X,  m (L/2) sin th th'' = Y - m g
    (m L^2/12) th'' = -(L/2) sin th Y - (L/2) cos th X
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from solver.explain import explain
from solver.io.scenes import load_system

ROOT = Path(__file__).resolve().parents[1]
LADDER = ROOT / "data" / "scenes" / "ladder_friction.toml"
WHEEL_PEND = ROOT / "tests" / "data" / "multibody" / "wheel_pend.toml"


def _ladder_by_hand(th: float) -> dict:
    m, L, mu_A, mu_B, g = 12.0, 5.0, 0.3, 0.2, 9.80665
    s, c = math.sin(th), math.cos(th)
    # unknowns th'', N_A, N_B
    A = np.array([[m * L / 2 * s, -mu_A, 1.0],
                  [-m * L / 2 * c, 1.0, mu_B],
                  [m * L**2 / 12, L / 2 * (c - mu_A * s), -L / 2 * (mu_B * c + s)]])
    b = np.array([0.0, m * g, 0.0])
    return dict(zip(("theta_ddot",), np.linalg.solve(A, b)))


def _wheel_pend_by_hand() -> dict:
    M, R, m, L, mu_k, g, th = 3.0, 0.3, 1.0, 0.5, 0.2, 9.81, math.radians(40)
    s, c = math.sin(th), math.cos(th)
    # unknowns x'', phi'', th'', N, X, Y
    A = np.array([[M, 0, 0, mu_k, 1, 0],
                  [0, 0, 0, 1, 0, -1],
                  [0, M * R**2 / 2, 0, R * mu_k, 0, 0],
                  [m, 0, m * L / 2 * c, 0, -1, 0],
                  [0, 0, m * L / 2 * s, 0, 0, -1],
                  [0, 0, m * L**2 / 12, 0, L / 2 * c, L / 2 * s]])
    b = np.array([0, M * g, 0, 0, -m * g, 0])
    return dict(zip(("x_ddot", "phi_ddot", "th_ddot"), np.linalg.solve(A, b)[:3]))


def _shown_equations_of_motion(path: Path, overrides: dict, point: str | None):
    """(system in the regime at the state, state, residuals of the displayed equations of motion)."""
    from solver.analyses.regimes import system_in_regime

    scene = load_system(path, overrides)
    expl = explain(scene, point)
    system, _, _, state = system_in_regime(load_system(path, overrides), point)
    motion = expl.sections[-1].step("motion")
    rows = [sp.sympify(e.residual) for e in motion.equations if e.tag.startswith(("eom:", "closure:"))]
    return system, state, rows, motion


CASES = [(LADDER, {"theta": "30 deg"}, point, lambda: _ladder_by_hand(math.radians(30)))
         for point in ("A", "B", "G")]
CASES.append((WHEEL_PEND, {}, None, _wheel_pend_by_hand))


@pytest.mark.parametrize("path, overrides, point, by_hand", CASES,
                         ids=["ladder-A", "ladder-B", "ladder-G", "wheel_pend"])
def test_slipping_equation_of_motion_holds_no_reaction(path, overrides, point, by_hand):
    """The displayed equations of motion hold no reaction symbol, and solved at the state they give
    the accelerations of the hand-written equations. 1e-9 relative: both are one small linear solve
    in double precision (round-off ~1e-15; condition numbers below 10)."""
    system, state, rows, motion = _shown_equations_of_motion(path, overrides, point)
    reactions = {r.symbol for r in system.reactions}
    for row in rows:
        assert not (row.free_symbols & reactions), (row.free_symbols & reactions, motion.text)
    assert not any("still holds" in t for t in motion.text)
    values = {k: sp.Float(v) for k, v in system.si_values().items()}
    values.update({x: sp.Float(v) for x, v in zip(system.q, state.q)})
    values.update({x: sp.Float(v) for x, v in zip(system.qd, state.qd)})
    numeric = [sp.expand(row.xreplace(values)) for row in rows]
    A = np.array([[float(row.coeff(u)) for u in system.qdd] for row in numeric])
    b = np.array([-float(row.xreplace({u: 0 for u in system.qdd})) for row in numeric])
    shown = dict(zip(map(str, system.qdd), np.linalg.solve(A, b)))
    for name, value in by_hand().items():
        assert shown[name] == pytest.approx(value, rel=1e-9), name


def test_when_no_equations_give_the_reactions_the_text_says_they_stay(monkeypatch):
    """With no set of body equations allowed (MAX_ROWS_SOLVED = 0), the equation of motion keeps
    N_A and N_B as reaction terms and the text says so, and how they are found, instead of
    substituting a value that holds another unknown reaction."""
    import solver.explain.slip_reactions as slip

    monkeypatch.setattr(slip, "MAX_ROWS_SOLVED", 0)
    system, _, rows, motion = _shown_equations_of_motion(LADDER, {"theta": "30 deg"}, "G")
    left = set().union(*(row.free_symbols for row in rows)) & {r.symbol for r in system.reactions}
    assert {str(r) for r in left} == {"N_A", "N_B"}
    assert not any(e.tag.startswith("from_newton:") for e in motion.equations)
    assert any("still holds N_A and N_B" in t and "equations with the data entered" in t for t in motion.text)
