"""The independent route: Lagrange's and Kane's equations via sympy.physics.mechanics.

Built from the scene directly with ``ReferenceFrame``, ``Point``,
``RigidBody``/``Particle`` and ``dynamicsymbols``; it shares nothing with
:mod:`solver.kinematics` or :mod:`solver.euler` except the element mass
properties of :mod:`solver.bodies` (checked against integration in the tests).

* Equation of motion: Kane's equation Fr + Fr* = 0 for the generalized
  speed u = theta_dot (``KanesMethod``, gravity as forces), negated so that
  it reads ``M qdd + 1/2 M' qd^2 + V' - Q``; or, with ``eom_by="lagrange"``,
  ``LagrangesMethod`` with L = T - V (gravity as the potential V) and the
  other loads in the force list, ``d/dt(dL/dqd) - dL/dq - Q``, the same
  normalised expression.
* Reactions: ``KanesMethod`` with two auxiliary generalized speeds, a
  translation of the whole body along x and along y, that bring the
  (otherwise noncontributing) constraint forces into evidence; the two
  auxiliary equations are then linear in theta_ddot and the reactions.
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp
from sympy.physics import mechanics as me

from .bodies import ROUND_KINDS, element_properties
from .errors import SceneError
from .euler import NamedEquation
from .kinematics import scene_label
from .scene import Scene

__all__ = ["LagrangeRoute", "lagrange_route"]

REF_LAGRANGE = "Lagrange's equation (sympy.physics.mechanics.LagrangesMethod)"
REF_KANE = "Kane's auxiliary equation (sympy.physics.mechanics.KanesMethod, u_auxiliary)"
REF_KANE_MAIN = "Kane's equation (sympy.physics.mechanics.KanesMethod)"
EOM_BY = ("kane", "lagrange")


@dataclass(frozen=True)
class LagrangeRoute:
    """Results of the mechanics route, in the scene's plain symbols.

    Attributes
    ----------
    eom : sympy.Expr
        M qdd + 1/2 M' qd^2 + V' - Q (== 0).
    equations : tuple of NamedEquation
        Lagrange's equation and the two Kane auxiliary equations.
    kinetic_energy, potential_energy, generalized_force, mass : sympy.Expr
    """

    eom: sp.Expr
    equations: tuple
    kinetic_energy: sp.Expr
    potential_energy: sp.Expr
    generalized_force: sp.Expr
    mass: sp.Expr


def _vec(frame, m):
    return m[0] * frame.x + m[1] * frame.y


def lagrange_route(scene: Scene, eom_by: str = "kane") -> LagrangeRoute:
    """Build the equations of ``scene`` with sympy.physics.mechanics.

    Parameters
    ----------
    scene : Scene
    eom_by : {"kane", "lagrange"}
        Which mechanics class gives the equation of motion: ``KanesMethod``
        (default, several times faster on composite bodies) or
        ``LagrangesMethod`` with L = T - V. Both normalise to
        M qdd + 1/2 M' qd^2 + V' - Q; the tests hold them equal.

    Returns
    -------
    LagrangeRoute

    Raises
    ------
    SceneError
        A constraint set the route cannot place the body with.
    """
    if eom_by not in EOM_BY:
        raise ValueError(f"`eom_by` must be one of {EOM_BY}, got {eom_by!r}")
    label = scene_label(scene)
    q_s, qd_s, qdd_s, t_s = scene.q, scene.qd, scene.qdd, scene.t
    th = me.dynamicsymbols(scene.coordinate + "_f")
    t = me.dynamicsymbols._t
    thd = th.diff(t)
    u = me.dynamicsymbols("u_f")
    ux, uy = me.dynamicsymbols("ux_f uy_f")

    def in_time(expr):
        return sp.sympify(expr).subs({q_s: th, t_s: t})

    phi = in_time(scene.orientation)
    N = me.ReferenceFrame("N")
    B = N.orientnew("B", "Axis", (phi, N.z))
    O = me.Point("O")
    O.set_vel(N, 0)

    # -- placement of the body frame's origin Bo ----------------------------
    def body_vec(coords):
        return _vec(B, sp.Matrix(coords).applyfunc(in_time))

    points = scene.points
    kinds = sorted(c.kind for c in scene.constraints)
    if scene.position is not None:
        name, where = scene.position
        r_origin = _vec(N, sp.Matrix(where).applyfunc(in_time)) - body_vec(points[name].coords)
    elif kinds == ["pivot"]:
        c = scene.constraints[0]
        r_origin = _vec(N, c.origin) - body_vec(points[c.point].coords)
    elif kinds == ["rolling"]:
        c = scene.constraints[0]
        element = next(e for e in scene.elements if e.name == c.element)
        if element.kind not in ROUND_KINDS:
            raise SceneError(f"{label}: constraint {c.name!r}: element {c.element!r} cannot roll")
        r = element.dims["radius"]
        d = sp.cos(c.angle) * N.x + sp.sin(c.angle) * N.y
        n = -sp.sin(c.angle) * N.x + sp.cos(c.angle) * N.y
        # no slip: arc length rolled equals the distance travelled along d
        s = c.contact_at_zero - r * (phi - phi.subs(th, 0))
        r_origin = _vec(N, c.origin) + s * d + r * n - body_vec(element.center)
    elif kinds == ["rail", "rail"]:
        # Point 1 sits at o1 + s d1 on rail 1; s follows from point 2 lying on
        # rail 2: n2 . (o1 + s d1 + (p2 - p1) - o2) = 0.
        c1, c2 = scene.constraints
        d1 = sp.cos(c1.angle) * N.x + sp.sin(c1.angle) * N.y
        n2 = -sp.sin(c2.angle) * N.x + sp.cos(c2.angle) * N.y
        p1, p2 = body_vec(points[c1.point].coords), body_vec(points[c2.point].coords)
        o1, o2 = _vec(N, c1.origin), _vec(N, c2.origin)
        denom = d1.dot(n2)
        if denom == 0:
            raise SceneError(f"{label}: impossible geometry: the two rails are parallel")
        s = (o2 - o1 - (p2 - p1)).dot(n2) / denom
        r_origin = o1 + s * d1 - p1
    else:
        raise SceneError(f"{label}: unsupported constraint set ({', '.join(kinds)})")
    Bo = O.locatenew("Bo", r_origin)
    Bo.set_vel(N, r_origin.dt(N))  # the only differentiated position; the rest by v2pt_theory

    # -- bodies ---------------------------------------------------------------
    lag_bodies, kane_bodies = [], []
    omega_u = sp.diff(phi, th) * u  # angular velocity with theta_dot -> u

    B_k = N.orientnew("Bk", "Axis", (phi, N.z))
    B_k.set_ang_vel(N, omega_u * N.z)
    Bo_k = me.Point("Bo_k")
    Bo_k.set_pos(O, r_origin)
    Bo_k.set_vel(N, Bo.vel(N).subs(thd, u) + ux * N.x + uy * N.y)

    def kane_point(name, pos):
        """Body point at ``pos`` (from O), velocity in u plus the auxiliary translations."""
        P = Bo_k.locatenew(name + "_k", pos - r_origin)
        P.v2pt_theory(Bo_k, N, B_k)
        return P
    gravity = [ld for ld in scene.loads if ld.kind == "gravity"]
    kane_loads = []
    V = sp.Integer(0)
    for element in scene.elements:
        props = element_properties(element)
        m = props.mass
        pos = Bo.pos_from(O) + body_vec(props.center)
        G_l = Bo.locatenew(element.name + "_G", body_vec(props.center))
        G_l.v2pt_theory(Bo, N, B)
        V_k = sp.Integer(0)
        for ld in gravity:
            V_k += -m * in_time(ld.magnitude) * pos.dot(_vec(N, sp.Matrix(ld.direction)))
        V += V_k
        G_k = kane_point(element.name + "_G", pos)
        for ld in gravity:  # Kane has no potential: weights as forces
            kane_loads.append((G_k, m * in_time(ld.magnitude) * _vec(N, sp.Matrix(ld.direction))))
        if element.kind == "point_mass":
            lag_bodies.append(me.Particle(element.name, G_l, m))
            kane_bodies.append(me.Particle(element.name + "_k", G_k, m))
        else:
            I = me.inertia(B, 0, 0, props.I_G)
            lag_bodies.append(me.RigidBody(element.name, G_l, B, m, (I, G_l)))
            I_k = me.inertia(B_k, 0, 0, props.I_G)
            kane_bodies.append(me.RigidBody(element.name + "_k", G_k, B_k, m, (I_k, G_k)))
        lag_bodies[-1].potential_energy = V_k

    # -- loads ------------------------------------------------------------------
    def point_position(name):
        p = points[name]
        if p.frame == "instant":
            return point_position(p.relative_to) + _vec(N, sp.Matrix(p.coords).applyfunc(in_time))
        return Bo.pos_from(O) + body_vec(p.coords)

    def material_velocity(name):
        """Velocity (in theta_dot) of the body point at ``name`` (rigid-body relation)."""
        p = points[name]
        if p.frame == "instant":
            return material_velocity(p.relative_to) + (sp.diff(phi, th) * thd * N.z).cross(
                _vec(N, sp.Matrix(p.coords).applyfunc(in_time))
            )
        return Bo.vel(N) + B.ang_vel_in(N).cross(body_vec(p.coords))

    forcelist, Q_terms = [], []
    for ld in scene.loads:
        if ld.kind == "force":
            F = _vec(N, sp.Matrix(ld.components).applyfunc(in_time))
            pos = point_position(ld.point)
            v = material_velocity(ld.point)
            P_l = O.locatenew(ld.name + "_at", pos)
            P_l.set_vel(N, v)
            forcelist.append((P_l, F))
            P_k = me.Point(ld.name + "_atk")
            P_k.set_pos(O, pos)
            P_k.set_vel(N, v.subs(thd, u) + ux * N.x + uy * N.y)
            kane_loads.append((P_k, F))
            Q_terms.append(F.dot(v.diff(thd, N)))
        elif ld.kind == "couple":
            C = in_time(ld.magnitude)
            forcelist.append((B, C * N.z))
            kane_loads.append((B_k, C * N.z))
            Q_terms.append(C * sp.diff(phi, th))
    for c in scene.constraints:
        syms = [sp.Symbol(nm, real=True) for nm in c.reactions]
        if c.kind == "rail":
            n = -sp.sin(c.angle) * N.x + sp.cos(c.angle) * N.y
            kane_loads.append((kane_point(c.name + "_pt", point_position(c.point)), syms[0] * n))
        elif c.kind == "pivot":
            kane_loads.append((kane_point(c.name + "_pt", point_position(c.point)), syms[0] * N.x + syms[1] * N.y))
        else:
            element = next(e for e in scene.elements if e.name == c.element)
            n = -sp.sin(c.angle) * N.x + sp.cos(c.angle) * N.y
            d = sp.cos(c.angle) * N.x + sp.sin(c.angle) * N.y
            contact = Bo.pos_from(O) + body_vec(element.center) - element.dims["radius"] * n
            kane_loads.append((kane_point(c.name + "_pt", contact), syms[0] * d + syms[1] * n))

    # -- Lagrange ---------------------------------------------------------------
    # -- Kane with auxiliary speeds (reactions; and the eom by default) -------
    KM = me.KanesMethod(N, q_ind=[th], u_ind=[u], kd_eqs=[thd - u], u_auxiliary=[ux, uy])
    fr, frstar = KM.kanes_equations(kane_bodies, kane_loads)
    aux = KM.auxiliary_eqs
    if eom_by == "lagrange":
        L = me.Lagrangian(N, *lag_bodies)
        LM = me.LagrangesMethod(L, [th], forcelist=forcelist or None, frame=N)
        main_eq = LM.form_lagranges_equations()[0]
        main_name, main_ref = "Lagrange's equation", REF_LAGRANGE
    else:
        # Fr + Fr* = 0 for the true speed u. The constraint forces are
        # noncontributing (their points move along the rails / roll without
        # slip), so their coefficients vanish identically: drop them.
        reaction_zero = {sp.Symbol(nm, real=True): 0 for nm in scene.reaction_names()}
        main_eq = -(fr[0] + frstar[0]).subs(reaction_zero)
        main_name, main_ref = "Kane's equation", REF_KANE_MAIN

    to_plain = {
        u.diff(t): qdd_s, th.diff(t, 2): qdd_s, u: qd_s, thd: qd_s,
        ux.diff(t): 0, uy.diff(t): 0, ux: 0, uy: 0,
    }

    def plain(expr):
        expr = me.msubs(sp.sympify(expr), to_plain)
        return expr.subs({th: q_s}).subs({t: t_s})

    T = plain(sum((b.kinetic_energy(N) for b in lag_bodies), sp.Integer(0)))
    M = sp.diff(T, qd_s, 2)
    eom = plain(main_eq)
    equations = (
        NamedEquation(main_name, eom, main_ref),
        NamedEquation("Kane auxiliary (x translation)", plain(aux[0]), REF_KANE),
        NamedEquation("Kane auxiliary (y translation)", plain(aux[1]), REF_KANE),
    )
    return LagrangeRoute(
        eom=eom,
        equations=equations,
        kinetic_energy=T,
        potential_energy=plain(V),
        generalized_force=plain(sp.Add(*Q_terms)),
        mass=M,
    )
