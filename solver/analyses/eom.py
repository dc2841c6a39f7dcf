"""Equations of motion: the reactions eliminated, M(q) q'' = f(q, q', t).

Each route's per-body equations (Newton x, Newton y, a moment equation) are
combined with the partial velocities of the point the moment equation is
about (Kane's projection): for coordinate i,

    sum_b [ (d v_P / d q_i') . N_b + (d omega_b / d q_i') E_b ] = 0 .

This is exact for any point P: with v_G = v_P + omega x r_G/P the combination
equals the one about G (the generalized Euler equation differs from Euler's
about G by r_G/P x N, Eq. 3). Ideal joints do no work on motions the
coordinates allow, so the reactions of every joint that the placement
satisfies drop out. A closure joint's reactions would remain; systems with
closure equations are integrated and solved through the instantaneous system
instead.
"""
from __future__ import annotations

import sympy as sp

__all__ = ["equations_of_motion"]


def _reference_velocity(formulation, body: str) -> sp.Matrix:
    s = formulation.system
    if formulation.method == "generalized_euler":
        return s.point_velocity(body, formulation.points[body])
    if formulation.method == "mass_center":
        return s.D(s.body_point(body, s.bodies[body].mass_center()))
    return s.D(s.origin(body))  # Lagrange's equations are about the body frame's origin


def equations_of_motion(formulation) -> list[sp.Expr]:
    """One expression (== 0) per free coordinate, reactions of placed joints eliminated,
    in the form  M q'' + (terms in q', q, t) - Q  (so the q'' coefficients are the mass matrix).

    Closure reactions remain when the system has closure equations (their
    reduced form is not built; ``eom`` says so).
    """
    s = formulation.system

    def build():
        per_body = {}
        for e in formulation.equations:
            if e.body is not None:
                per_body.setdefault(e.body, []).append(e.expr)
        zero = {r.symbol: 0 for r in s.reactions if not _is_closure(s, r)}
        out = []
        for c in s.free:
            terms = []
            for body, (nx, ny, eu) in per_body.items():
                v = _reference_velocity(formulation, body)
                w = s.omega(body)
                terms += [sp.diff(v[0], c.qd) * nx, sp.diff(v[1], c.qd) * ny, sp.diff(w, c.qd) * eu]
            out.append(-sp.Add(*terms).xreplace(zero))
        return out

    return s._memo(("eom", formulation.method, tuple(sorted(formulation.points.items()))), build)


def _is_closure(system, reaction) -> bool:
    return any(row.reaction.name == reaction.name for row in system.closure)
