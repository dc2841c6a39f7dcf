"""Kinematics at a state: every named point's position, velocity and acceleration,
and each body's omega and alpha (accelerations from the instantaneous solve)."""
from __future__ import annotations

import sympy as sp

from .instant import solve_instant
from .regimes import start_state

__all__ = ["kinematics_at"]


def kinematics_at(system, point=None, method: str = "generalized_euler") -> dict:
    """JSON-ready kinematics of ``system`` at its state.

    Returns
    -------
    dict
        ``{"state": {...}, "bodies": {name: {"omega", "alpha"}}, "points":
        {"BODY:POINT": {"position", "velocity", "acceleration"}}}``; vectors
        as ``{"value": [x, y], "unit": ...}`` in SI.
    """
    state = start_state(system)  # contacts open at the state stay open
    sol = solve_instant(system, point, method, state)
    values = dict(system.si_values())
    values.update(zip(system.q, state.q))
    values.update(zip(system.qd, state.qd))
    values.update({c.qdd: sol.unknowns[str(c.qdd)].to_base_units().magnitude for c in system.free})
    values[system.t] = state.t
    subs = {k: sp.Float(v) for k, v in values.items()}

    def num(expr) -> float:
        return float(sp.sympify(expr).xreplace(subs).evalf())

    bodies = {}
    points = {}
    for name, body in system.bodies.items():
        bodies[name] = {"omega": {"value": num(system.omega(name)), "unit": "rad/s"},
                        "alpha": {"value": num(system.alpha(name)), "unit": "rad/s**2"}}
        for p in body.point_names():
            r, v, a = system.point_kinematics(name, p)  # a pivot held by a ground pin: at its place, at rest
            points[f"{name}:{p}"] = {
                "position": {"value": [num(x) for x in r], "unit": "m"},
                "velocity": {"value": [num(x) for x in v], "unit": "m/s"},
                "acceleration": {"value": [num(x) for x in a], "unit": "m/s**2"},
            }
    state_out = {}
    for c, v, r in zip(system.free, state.q, state.qd):
        state_out[c.name] = {"value": v, "unit": c.unit}
        state_out[f"{c.name}_dot"] = {"value": r, "unit": f"{c.unit}/s"}
    return {"state": state_out, "bodies": bodies, "points": points}
