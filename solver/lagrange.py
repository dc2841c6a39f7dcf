"""The independent route: Lagrange's and Kane's equations via sympy.physics.mechanics.

Built from the scene directly with ``ReferenceFrame``, ``Point``,
``RigidBody``/``Particle`` and ``dynamicsymbols``; it shares nothing with
:mod:`solver.kinematics` or :mod:`solver.euler` except the element mass
properties of :mod:`solver.bodies` (checked against integration in the tests).

* Equation of motion: ``LagrangesMethod`` with L = T - V (gravity as the
  potential V) and the other loads in the force list, giving
  ``d/dt(dL/dqd) - dL/dq - Q = M qdd + 1/2 M' qd^2 + V' - Q``.
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


def lagrange_route(scene: Scene) -> LagrangeRoute:
    """Build the equations of ``scene`` with sympy.physics.mechanics.

    Parameters
    ----------
    scene : Scene

    Returns
    -------
    LagrangeRoute

    Raises
    ------
    SceneError
        A constraint set the route cannot place the body with.
    """
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
        X, Y = sp.symbols("X_o Y_o", real=True)
        eqs = []
        for c in scene.constraints:
            n = -sp.sin(c.angle) * N.x + sp.cos(c.angle) * N.y
            r_pt = X * N.x + Y * N.y + body_vec(points[c.point].coords) - _vec(N, c.origin)
            eqs.append(r_pt.dot(n))
        sol = sp.solve(eqs, [X, Y], dict=True)
        if len(sol) != 1:
            raise SceneError(f"{label}: impossible geometry: the two rails cannot fix the body's position")
        r_origin = sol[0][X] * N.x + sol[0][Y] * N.y
    else:
        raise SceneError(f"{label}: unsupported constraint set ({', '.join(kinds)})")
    Bo = O.locatenew("Bo", r_origin)

    # -- bodies ---------------------------------------------------------------
    lag_bodies, kane_bodies = [], []
    omega_u = sp.diff(phi, th) * u  # angular velocity with theta_dot -> u

    def kane_point(name, pos):
        """Point with velocity in u plus the two auxiliary translations."""
        P = me.Point(name + "_k")
        P.set_pos(O, pos)
        P.set_vel(N, pos.dt(N).subs(thd, u) + ux * N.x + uy * N.y)
        return P

    B_k = N.orientnew("Bk", "Axis", (phi, N.z))
    B_k.set_ang_vel(N, omega_u * N.z)
    gravity = [ld for ld in scene.loads if ld.kind == "gravity"]
    kane_loads = []
    V = sp.Integer(0)
    for element in scene.elements:
        props = element_properties(element)
        m = props.mass
        pos = Bo.pos_from(O) + body_vec(props.center)
        G_l = O.locatenew(element.name + "_G", pos)
        G_l.set_vel(N, pos.dt(N))
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
        return point_position(name).dt(N)

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
    L = me.Lagrangian(N, *lag_bodies)
    LM = me.LagrangesMethod(L, [th], forcelist=forcelist or None, frame=N)
    lag_eq = LM.form_lagranges_equations()[0]

    # -- Kane with auxiliary speeds (reactions) -----------------------------
    KM = me.KanesMethod(N, q_ind=[th], u_ind=[u], kd_eqs=[thd - u], u_auxiliary=[ux, uy])
    KM.kanes_equations(kane_bodies, kane_loads)
    aux = KM.auxiliary_eqs

    to_plain = {
        u.diff(t): qdd_s, th.diff(t, 2): qdd_s, u: qd_s, thd: qd_s,
        ux.diff(t): 0, uy.diff(t): 0, ux: 0, uy: 0,
    }

    def plain(expr):
        expr = me.msubs(sp.sympify(expr), to_plain)
        return expr.subs({th: q_s}).subs({t: t_s})

    T = plain(sum((b.kinetic_energy(N) for b in lag_bodies), sp.Integer(0)))
    M = sp.diff(T, qd_s, 2)
    eom = plain(lag_eq)
    equations = (
        NamedEquation("Lagrange's equation", eom, REF_LAGRANGE),
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
