"""Kinematics at a state: every named point's position, velocity and acceleration,
and each body's omega and alpha (accelerations from the instantaneous solve)."""
from __future__ import annotations

import sympy as sp

from .instant import entry_sizes, round_off_bound, sized_input, solve_instant
from .regimes import start_state

__all__ = ["kinematics_at"]


def kinematics_at(system, point=None, method: str = "generalized_euler") -> dict:
    """JSON-ready kinematics of ``system`` at its state.

    A value no larger than its own error bound is given as 0, as `solve` gives an unknown (README
    "Zero to round-off"): the bound is that of evaluating its expression (:func:`round_off_bound` of
    the sizes of its terms, :func:`entry_sizes`), the solved accelerations entering with their own
    bounds (:func:`sized_input`). A piston on the line y = 0 moves with y velocity 0, not the
    -8.9e-16 m/s its cancelling terms leave.

    Returns
    -------
    dict
        ``{"state": {...}, "bodies": {name: {"omega", "alpha"}}, "points":
        {"BODY:POINT": {"position", "velocity", "acceleration"}}}``; vectors
        as ``{"value": [x, y], "unit": ...}`` in SI; ``"zero_to_round_off": {"BODY:POINT
        quantity x": {"computed", "error_bound"}}`` where a value was set to 0.
    """
    state = start_state(system)  # contacts open at the state stay open
    sol = solve_instant(system, point, method, state)
    values = dict(system.si_values())
    values.update(zip(system.q, state.q))
    values.update(zip(system.qd, state.qd))
    values.update({c.qdd: sol.unknowns[str(c.qdd)].to_base_units().magnitude for c in system.free})
    values[system.t] = state.t
    subs = {k: sp.Float(v) for k, v in values.items()}
    sized = {**values, **{c.qdd: sized_input(values[c.qdd], sol.error_bound.get(str(c.qdd), 0.0))
                          for c in system.free}}
    zeros: dict = {}

    def shown(label: str, exprs, unit: str) -> dict:
        """The values of ``exprs``, each within its own bound given as 0 (recorded in ``zeros``)."""
        exact = [float(sp.sympify(e).xreplace(subs).evalf()) for e in exprs]
        sizes = entry_sizes([sp.sympify(e) for e in exprs], sized)
        for i, x in enumerate(exact):
            bound = None if sizes is None else round_off_bound(sizes[i])
            if bound is not None and x != 0 and abs(x) <= bound:
                name = label + ("" if len(exprs) == 1 else f" {'xy'[i]}")
                zeros[name] = {"computed": {"value": x, "unit": unit}, "error_bound": {"value": bound, "unit": unit}}
                exact[i] = 0.0
        return {"value": exact[0] if len(exprs) == 1 else exact, "unit": unit}

    bodies = {}
    points = {}
    for name, body in system.bodies.items():
        bodies[name] = {"omega": shown(f"{name} omega", [system.omega(name)], "rad/s"),
                        "alpha": shown(f"{name} alpha", [system.alpha(name)], "rad/s**2")}
        for p in body.point_names():
            r, v, a = system.point_kinematics(name, p)  # a pivot held by a ground pin: at its place, at rest
            points[f"{name}:{p}"] = {
                "position": shown(f"{name}:{p} position", list(r), "m"),
                "velocity": shown(f"{name}:{p} velocity", list(v), "m/s"),
                "acceleration": shown(f"{name}:{p} acceleration", list(a), "m/s**2"),
            }
    state_out = {}
    for c, v, r in zip(system.free, state.q, state.qd):
        state_out[c.name] = {"value": v, "unit": c.unit}
        state_out[f"{c.name}_dot"] = {"value": r, "unit": f"{c.unit}/s"}
    out = {"state": state_out, "bodies": bodies, "points": points}
    return {**out, "zero_to_round_off": zeros} if zeros else out
