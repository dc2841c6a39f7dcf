"""Equations of motion: the reactions eliminated, M(q) q'' = f(q, q', t).

Each route's per-body equations (Newton x, Newton y, a moment equation) are
combined with the partial velocities of the point the moment equation is
about (Kane's projection): for coordinate i,

    sum_b [ (d v_P / d q_i') . N_b + (d omega_b / d q_i') E_b ] = 0 .

This is exact for any point P: with v_G = v_P + omega x r_G/P the combination
equals the one about G (the generalized Euler equation differs from Euler's
about G by r_G/P x N, Eq. 3). Ideal joints do no work on motions the
coordinates allow, so the reactions of every joint that the placement
satisfies drop out. A closure joint's reactions are removed by projecting on
the velocity transformation of the independent coordinates
(:func:`reduced_equations_of_motion`).
"""
from __future__ import annotations

import sympy as sp

from ..model.system import derivative

__all__ = ["equations_of_motion", "reduced_equations_of_motion", "projection", "Projection"]


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

    Closure reactions remain when the system has closure equations; see
    :func:`reduced_equations_of_motion`.
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
                terms += [derivative(v[0], c.qd) * nx, derivative(v[1], c.qd) * ny, derivative(w, c.qd) * eu]
            out.append(-sp.Add(*terms).xreplace(zero))
        return out

    return s._memo(("eom", formulation.method, tuple(sorted(formulation.points.items()))), build)


def _is_closure(system, reaction) -> bool:
    return any(row.reaction.name == reaction.name for row in system.closure)


def reduced_equations_of_motion(formulation) -> tuple[list[sp.Expr], list]:
    """Equations of motion in the independent coordinates u of a system with closure equations.

    With the closure equations Phi(q, t) = 0 split into their dependent
    coordinates v and the independent u, q' = B u' + b where
    B = [I; -Phi_v^-1 Phi_u]. Projecting the equations of
    :func:`equations_of_motion` on B removes the closure reactions (their
    generalized forces are Phi_q^T lambda, and B^T Phi_q^T = 0); the dependent
    accelerations then follow from the acceleration form of the closure,
    v'' = -Phi_v^-1 (Phi_u u'' + (d^2 Phi/dt^2 at q'' = 0)).

    Returns
    -------
    (list of sympy.Expr, list of Coordinate)
        One expression (== 0) per independent coordinate, in u'', the
        coordinates (dependent ones included, known at a state from the
        closure) and their rates; and the independent coordinates.
    """
    s = formulation.system

    def build():
        p = projection(formulation)
        projected = [sp.Add(*[p.ratio(i, k) * e for i, e in enumerate(p.equations)]) for k in range(len(p.independent))]
        subs = {c.qdd: v for c, v in zip(p.dependent, p.dependent_accelerations)}
        return [e.xreplace(subs) for e in projected], list(p.independent)

    return s._memo(("reduced_eom", formulation.method, tuple(sorted(formulation.points.items()))), build)


class Projection:
    """The parts of :func:`reduced_equations_of_motion`, kept apart for display (``eom`` on a loop).

    Attributes
    ----------
    equations : list of sympy.Expr
        Each free coordinate's equation of :func:`equations_of_motion` with the closure reactions
        set to zero (they drop out of the projection).
    independent, dependent : list of Coordinate
    ratios : sympy.Matrix
        dv'/du' = -Phi_v^-1 Phi_u (dependent x independent): the velocity ratios.
    dependent_accelerations : list of sympy.Expr
        v'' from the closure differentiated twice, in u'', the coordinates and their rates.
    dependent_rate_terms : list of sympy.Expr
        The same without the u'' terms: v'' = ratios u'' + dependent_rate_terms.
    """

    def __init__(self, formulation):
        s = formulation.system
        free = s.free
        self.independent = [c for c in free if not c.dependent]
        self.dependent = [c for c in free if c.dependent]
        ind = [i for i, c in enumerate(free) if not c.dependent]
        dep = [i for i, c in enumerate(free) if c.dependent]
        zero_l = {r.reaction.symbol: 0 for r in s.closure}
        self.equations = [e.xreplace(zero_l) for e in equations_of_motion(formulation)]
        Phi = sp.Matrix([r.expr for r in s.closure])
        J = Phi.jacobian(sp.Matrix(s.q))
        Ju, Jv = J[:, ind], J[:, dep]
        Jv_inv = Jv.inv(method="LU")
        self.ratios = -Jv_inv * Ju
        self._position = {i: ("dep", k) for k, i in enumerate(dep)} | {i: ("ind", k) for k, i in enumerate(ind)}
        acc = sp.Matrix([s.D(s.D(r.expr)) for r in s.closure])
        rest = acc.xreplace({c.qdd: 0 for c in free})
        udd = sp.Matrix([c.qdd for c in self.independent])
        self.dependent_accelerations = list(-Jv_inv * (Ju * udd + rest))
        self.dependent_rate_terms = list(-Jv_inv * rest)  # v'' = ratios u'' + these (for display)

    def ratio(self, i: int, k: int) -> sp.Expr:
        """d q_i' / d u_k': 1 or 0 for an independent coordinate, the velocity ratio for a dependent one."""
        kind, j = self._position[i]
        return self.ratios[j, k] if kind == "dep" else sp.Integer(1 if j == k else 0)


def projection(formulation) -> Projection:
    """The :class:`Projection` of a system with closure equations (cached on the system)."""
    s = formulation.system
    return s._memo(("projection", formulation.method, tuple(sorted(formulation.points.items()))),
                   lambda: Projection(formulation))
