"""The independent route: Lagrange's equations with multipliers, by sympy.physics.mechanics.

The kinematics, the Lagrangian and the generalized forces come from the mechanics API; the
equations are formed term by term as ``LagrangesMethod.form_lagranges_equations`` forms them
(:func:`_formed`, proven equal to the method's own in tests/test_multibody_properties.py).

Every body gets its own three body coordinates (x_b, y_b, phi_b) as
``dynamicsymbols``; its kinetic energy is built from the elements' masses and
centroidal inertias with ``ReferenceFrame``/``Point``/``RigidBody`` and
``Particle``; the potential energy of gravity and springs enters the
Lagrangian; every joint equation is a holonomic constraint of
``LagrangesMethod``, so that its multiplier is the joint's reaction
(R_k = -lambda_k in sympy's sign convention, whose equations read
M q'' - Q + Phi_q^T lambda = 0); the other loads enter the force list.

The body coordinates are then expressed through the scene's coordinates
(x_b = X_b(q, t), ...), which turns Lagrange's 3N equations and the
constraints that the placement does not satisfy identically into a square
system linear in the q'' and the reactions, solved like the Newton-Euler
routes. It shares with them only the model's inputs: element mass
properties, joint geometry and applied forces at the state.
"""
from __future__ import annotations

import sympy as sp
from sympy.physics import mechanics as me

from ..kept import Kept
from .newton_euler import NamedEquation

__all__ = ["lagrange_equations"]

REF = "Lagrange's equation with multipliers (sympy.physics.mechanics.LagrangesMethod)"


def lagrange_equations(system) -> list[NamedEquation]:
    """Lagrange's equations in body coordinates, expressed in the scene's coordinates."""
    t = me.dynamicsymbols._t
    N = me.ReferenceFrame("N")
    O = me.Point("O")
    O.set_vel(N, 0)
    coords, poses, frames, origins = [], {}, {}, {}
    for name in system.bodies:
        x, y, ph = me.dynamicsymbols(f"x_{name} y_{name} phi_{name}")
        coords += [x, y, ph]
        poses[name] = (sp.Matrix([x, y]), ph)
        F = N.orientnew(f"F_{name}", "Axis", [ph, N.z])
        frames[name] = F
        Pb = O.locatenew(f"O_{name}", x * N.x + y * N.y)
        Pb.set_vel(N, x.diff(t) * N.x + y.diff(t) * N.y)
        origins[name] = Pb

    def pose(b):
        if b == "ground":
            return sp.zeros(2, 1), sp.Integer(0)
        return poses[b]

    # kinetic energy: each element as a rigid body (or a particle) of the body's frame
    parts = []
    for name, body in system.bodies.items():
        F, Pb = frames[name], origins[name]
        for e in body.elements:
            c = e.mass_center
            G = Pb.locatenew(f"G_{name}_{e.name}", c[0] * F.x + c[1] * F.y)
            G.v2pt_theory(Pb, N, F)
            if e.I_G == 0:
                parts.append(me.Particle(f"p_{name}_{e.name}", G, e.mass))
            else:
                parts.append(me.RigidBody(f"b_{name}_{e.name}", G, F, e.mass, (me.inertia(F, 0, 0, e.I_G), G)))
    # the scene's coordinates as functions of time, to express loads and the placement
    tt = system.t
    qfun = {c.q: me.dynamicsymbols(c.name) for c in system.free}
    to_dyn = dict(qfun)
    to_dyn.update({c.qd: qfun[c.q].diff(t) for c in system.free})
    to_dyn[tt] = t
    # potential energy of the conservative loads, rebuilt in body coordinates
    V = _potential(system, pose)
    # expanded: the vector algebra leaves products of sums (v . v of every element) that
    # LagrangesMethod would differentiate three times over; a flat sum halves its cost
    L = sp.expand(me.Lagrangian(N, *parts) - V.xreplace({tt: t}))
    forcelist = _forces(system, N, frames, origins, to_dyn)
    rows = []
    for j in system.joints:
        system._bind_prescribed(j)
        for row in j.rows(pose, tt):
            rows.append(sp.sympify(system.prescribe(sp.sympify(row))).xreplace(to_dyn))
    eom, lam_vec = _lagranges_equations(L, coords, rows, forcelist, N)
    reactions = [r.symbol for r in system.reactions]
    lam = {l: -R for l, R in zip(lam_vec, reactions)}
    # body coordinates through the scene's coordinates
    subs = {}
    for name in system.bodies:
        origin, phi = system.origin(name), system.angle(name)
        for dyn, expr in zip(poses[name][0][:] + [poses[name][1]], list(origin) + [phi]):
            d1 = system.D(expr)
            subs[dyn.diff(t, 2)] = system.D(d1)
            subs[dyn.diff(t)] = d1
            subs[dyn] = expr
    back = {v: k for k, v in to_dyn.items() if k != tt}
    back_d = {qfun[c.q].diff(t): c.qd for c in system.free}
    out = []
    for i, e in enumerate(eom):
        expr = -e.xreplace(lam)  # same sign as the Newton-Euler rows: applied - inertial
        expr = _plain(expr, subs, back_d, back, t, tt)
        body, what = divmod(i, 3)
        bname = list(system.bodies)[body]
        label = ("x", "y", "phi")[what]
        out.append(NamedEquation(f"Lagrange {label}_{bname}", expr, REF, bname))
    from .newton_euler import closure_equations

    return out + closure_equations(system)


def _lagranges_equations(L, coords, rows, forcelist, N) -> tuple:
    """(eom, multipliers) of ``LagrangesMethod(L, coords, hol_coneqs=rows, forcelist=forcelist,
    frame=N).form_lagranges_equations()`` (formed by :func:`_formed`), made once per process for
    equal inputs (the last 64, a :class:`solver.kept.Kept`): a scene loaded again (each test of
    a suite, a command after another) gives the same Lagrangian, constraints and forces, and
    forming the equations is most of
    :func:`lagrange_equations`' cost (about 0.17 s a scene).

    The key holds what the equations depend on: the Lagrangian, the coordinates and the constraint
    rows (sympy objects, equal only when they are structurally the same), and of each force the
    velocity (of its point, or its frame's angular velocity) and the force, each vector as its
    components with the name of the frame they are in. A frame's name says which frame it is:
    :func:`lagrange_equations` makes N and each body's F_<body> (at the angle phi_<body> about
    N.z) the same way every time."""
    from sympy.physics.mechanics.functions import _f_list_parser

    def vector(v):
        return tuple((m.as_immutable(), frame.name) for m, frame in v.args)

    velocities, forces = _f_list_parser(forcelist, N)
    key = (L, tuple(coords), tuple(rows), tuple((vector(v), vector(f)) for v, f in zip(velocities, forces)))

    return _LAGRANGE.get(key, lambda: _formed(L, coords, rows, forcelist, N))


def _formed(L, coords, rows, forcelist, N) -> tuple:
    """Lagrange's equations with multipliers, formed term by term exactly as
    ``LagrangesMethod.form_lagranges_equations`` forms its ``eom`` (so the result is the same
    expression tree):

        d/dt (dL/dq')^T - (dL/dq)^T - Q - (-dC'/dq')^T lambda = 0,

    with C' the time derivatives of the holonomic rows, one multiplier ``lam1``, ``lam2``, ...
    per row, and Q_i = sum over the force list of (dv/dq'_i) . F. What it leaves out is only
    what this route never reads: the method's separate mass and forcing matrices of the
    equations and of the differentiated constraints (jacobians in q'' and substitutions of
    q'' = 0 over every equation), which were about 40 % of forming the equations of the
    slider-crank, four-bar and parallel-link scenes."""
    from sympy.physics.mechanics.functions import _f_list_parser

    t = me.dynamicsymbols._t
    q = sp.Matrix(coords)
    qds = q.diff(t)
    Lm = sp.Matrix([L])
    term1 = Lm.jacobian(qds).diff(t).T
    term2 = Lm.jacobian(q).T
    term4 = sp.zeros(len(q), 1)
    if forcelist:
        for i, qd in enumerate(qds):
            term4[i] = sum(v.diff(qd, N).dot(f) for v, f in zip(*_f_list_parser(forcelist, N)))
    without_lam = term1 - term2 - term4
    if not rows:
        return without_lam.as_immutable(), ()
    coneqs = sp.Matrix(rows).diff(t)
    lam_vec = sp.Matrix(me.dynamicsymbols("lam1:" + str(len(rows) + 1)))
    return (without_lam - (-coneqs.jacobian(qds)).T * lam_vec).as_immutable(), tuple(lam_vec)


_LAGRANGE = Kept(64)


def _plain(expr, subs, back_d, back, t, tt):
    # highest derivatives first so that xreplace does not split them
    expr = expr.xreplace({k: v for k, v in subs.items() if k.is_Derivative and k.derivative_count == 2})
    expr = expr.xreplace({k: v for k, v in subs.items() if k.is_Derivative})
    expr = expr.xreplace({k: v for k, v in subs.items() if not k.is_Derivative})
    expr = expr.xreplace(back_d).xreplace(back)
    return expr.xreplace({t: tt})


def _potential(system, pose):
    from ..model.joints import rotation
    from ..model.loads import Gravity, Spring, TorsionalSpring

    terms = []
    for load in system.loads:
        if isinstance(load, Gravity):
            for name, body in system.bodies.items():
                o, ph = pose(name)
                for e in body.elements:
                    r = o + rotation(ph) * e.mass_center
                    terms.append(-e.mass * load.g * (load.direction.T * r)[0])
        elif isinstance(load, Spring):
            ra = _point(system, pose, *load.a)
            rb = _point(system, pose, *load.b)
            d = rb - ra
            terms.append(load.stiffness * (sp.sqrt(d[0] ** 2 + d[1] ** 2) - load.free_length) ** 2 / 2)
        elif isinstance(load, TorsionalSpring):
            rel = pose(load.second)[1] - pose(load.first)[1]
            terms.append(load.stiffness * (rel - load.free_angle) ** 2 / 2)
    return system.prescribe(sp.Add(*terms))


def _point(system, pose, body, point):
    from ..model.joints import rotation

    kind, data = system._resolve(body, point)
    if kind == "instant":
        ref, offset = data
        return _point(system, pose, body, ref) + offset
    o, ph = pose(body)
    return o + rotation(ph) * data


def _forces(system, N, frames, origins, to_dyn):
    """Non-conservative loads as (Point, Vector) and (Frame, Vector) pairs of the mechanics API,
    and the friction of each sliding contact (:func:`_sliding_friction`)."""
    out = []
    for load in system.loads:
        if load.conservative:
            continue
        for a in load.applied(system):
            body = a.body
            if a.force is not None:
                out.append(_force_at(system, N, frames, origins, to_dyn, body, a.at, a.force, f"P_{a.name}_{len(out)}"))
            if a.couple != 0:
                out.append((frames[body], system.prescribe(sp.sympify(a.couple)).xreplace(to_dyn) * N.z))
    return out + _sliding_friction(system, N, frames, origins, to_dyn)


def _force_at(system, N, frames, origins, to_dyn, body: str, at, force, name: str):
    """(Point, Vector): ``force`` (scene coordinates) at ``at``, a point fixed in ``body`` at the
    state's body coordinates (the material point there, whose velocity gives the virtual work)."""
    F, Pb = frames[body], origins[body]
    rel = system.prescribe(sp.Matrix(at) - system.origin(body))
    c, s = sp.cos(system.angle(body)), sp.sin(system.angle(body))
    rel_body = (sp.Matrix([[c, s], [-s, c]]) * rel).xreplace(to_dyn)
    P = Pb.locatenew(name, rel_body[0] * F.x + rel_body[1] * F.y)
    P.v2pt_theory(Pb, N, F)
    f = system.prescribe(sp.Matrix(force)).xreplace(to_dyn)
    return P, f[0] * N.x + f[1] * N.y


def _sliding_friction(system, N, frames, origins, to_dyn) -> list:
    """The friction -s mu_k N along each sliding contact's tangent d, on the second body at the
    contact and, opposite, on the first (as the Newton-Euler routes apply the joint's reaction,
    ``Joint.loads``). The constraint's multiplier gives only the normal force N n; without this
    term a sliding block on a 30 deg ramp with mu_k = 0.4 slid as if frictionless (g sin 30 deg
    instead of g (sin 30 deg - 0.4 cos 30 deg)). N is the reaction's own symbol (the unknown the
    multiplier becomes), so the equations stay linear in it."""
    pose = system._pose_fn(system.poses)
    out = []
    for j in system.contacts:
        r = j.current_regime
        s = r.friction_direction()
        if not (r.keeps_normal and not r.keeps_tangential and s and j.friction is not None):
            continue
        d, _, at = j.contact_frame(pose)
        normal = j.pair[1].symbol
        friction = sp.Matrix(d) * (-s * r.coefficient(j.friction) * normal)
        for jl in j.loads(pose, system.t):  # where the reaction acts on each body
            if jl.reaction.symbol != normal or jl.body not in frames:
                continue
            sign = 1 if jl.body == j.second else -1
            out.append(_force_at(system, N, frames, origins, to_dyn, jl.body, jl.at, sign * friction,
                                 f"P_friction_{j.name}_{jl.body}"))
    return out
