"""Build the worked solution of a scene at its state (issue 11, ``python -m solver explain``).

For each body, in order (paper Eqs. 1, 6, 10-15):

1. the data with units;
2. the kinematics: the positions of the points used relative to P, then their
   velocities and accelerations by the rigid-body relations from P (the accelerations: Eq. 6, Eq. 15
   for the elements' mass centres; the paper prints no velocity relation);
3. the free-body diagram as a list of forces (``Step.figure`` is the hook for the drawing);
4. Newton's equations by component (Eq. 1; Eq. 14 for a composite body);
5. the generalized Euler equation about P: the moments of the actual forces,
   the inertial term -r_G/P x m a_P as a separate term, and I_P alpha with I_P
   built per element by the parallel-axis theorem (Eqs. 10-12);
6. which unknowns dropped out of the moment equation, and why.

Then, for the whole system: the point advisor's ranking, the equation of
motion built from its structure (M q'' + ... = Q), the solution at the state in
the scene's output units, and the check of the same answers by the mass-centre
form (Eqs. 1-2).
"""
from __future__ import annotations

import math
import re

import sympy as sp

from ..model.joints import copy_vec, cross_k, k_cross, vadd, vec, vscale, vsub, xy
from ..model.system import derivative
from .content import SLIP_VELOCITY_NOTE, Equation, Explanation, SceneText, Section, Step, Table, Term, slip_friction
from ..display import (coefficient, could_extract_minus_sign, expanded, is_identically_zero, term_powers, tidy, tidy_linear,
                       without_known_abs)
from ..strprint import FastStrPrinter, sstr

__all__ = ["explain", "latex_names"]


def latex_names(system) -> dict:
    """LaTeX names: dotted rates of the coordinates (:func:`solver.notation.rate_latex_names`)."""
    from ..notation import rate_latex_names

    return rate_latex_names(system.coordinates)


def _vec(v) -> sp.Matrix:
    x, y = xy(v)
    return vec(tidy(x), tidy(y))


def _same_place(r, at) -> bool:
    """Whether the positions ``r`` and ``at`` (2-vectors) are identically the same place, by components."""
    (rx, ry), (ax, ay) = xy(r), xy(at)
    if rx == ax and ry == ay:  # the same expressions (a point met again): no difference to test
        return True
    return _zero(rx - ax) and _zero(ry - ay)


def _zero(expr) -> bool:
    expr = expanded(without_known_abs(expr))  # (|r1 + r2| of positive radii is r1 + r2, as shown)
    if expr == 0:
        return True
    return bool(is_identically_zero(expr))


def _state_subs(system, state) -> dict:
    """Symbol -> sympy Float: the parameters, the coordinates and rates at ``state``, and t (for
    ``xreplace``); remembered by the system for that state (several steps evaluate there). Read only."""
    def build():
        vals = dict(system.si_values())
        vals.update(zip(system.q, state.q))
        vals.update(zip(system.qd, state.qd))
        vals[system.t] = state.t
        return {k: sp.Float(v) for k, v in vals.items()}
    return system._memo(("state_subs", tuple(state.q), tuple(state.qd), state.t), build)


def _at_state(system, expr, state):
    """``expr.xreplace(_state_subs(system, state))``: the same tree, so the same Floats to the last
    bit (:func:`solver.tree_value.substitute`), each subtree substituted once per state. The system
    remembers the substituted subtrees for that state: the equations shown, the formulations'
    matrices and the equations with the data entered share the bodies' kinematics."""
    from ..tree_value import substitute

    memo = system._memo(("at_state", tuple(state.q), tuple(state.qd), state.t), dict)
    return substitute(expr, _state_subs(system, state), memo)


def _walk_state(system, state):
    """The state as the walks at it take it: a :class:`solver.explain.advisor._State` (the Floats of
    :func:`_state_subs`, the same as doubles, and the memo of the subtrees' values there), remembered
    by the system for that state (the advisor's rows, the formulations' matrices and the equations
    with the data entered share the bodies' kinematics). Read only, but for the memo."""
    from .advisor import _State

    return system._memo(("walk_state", tuple(state.q), tuple(state.qd), state.t),
                        lambda: _State(_state_subs(system, state)))


def _value(expr, subs) -> float:
    return float(sp.sympify(expr).xreplace(subs).xreplace(subs))


# -- naming the points where forces act ---------------------------------------------------------


class _Points:
    """Named points of a body, and names for the other places forces act at."""

    def __init__(self, system, body: str):
        self.system, self.body = system, body
        b = system.bodies[body]
        self.named = {p: system.point_position(body, p) for p in b.point_names()}
        for e in b.elements:
            key = f"G_{e.name}"
            if len(b.elements) > 1 and key not in self.named:
                r = system.body_point(body, e.mass_center)
                if not any(_same_place(r, q) for q in self.named.values()):
                    self.named[key] = r
        self.extra = 0
        self.about: dict[str, str] = {}  # a point named after its joint or two reactions -> what it is
        self.origin: dict[str, str] = {}  # the same, in the advisor's words
        for j in system.joints:  # one that --point asked for is a point of the body already
            name = f"C_{j.name}"
            if name in b.points and b.points[name].is_instant:
                self.about[name] = self.describe(name, j)
        for name in b.points:
            crossed = _CROSSING.fullmatch(name)
            if crossed and b.points[name].is_instant:
                self.about[name] = self.describe_crossing(name, *crossed.groups())

    def describe(self, name: str, joint) -> str:
        self.origin[name] = "point of its joint"
        return (f"{name} is the point of {self.body} where joint {joint.name} acts at this instant "
                f"({_joint_place(joint)}); the scene names no point there, so it is named after its joint, "
                f"and --point {name} takes moments about it")

    def describe_crossing(self, name: str, first: str, second: str) -> str:
        self.origin[name] = crossing_words(first, second)
        return (f"{name} is the point of {self.body} (the body extended) where the lines of action of "
                f"{first} and {second} cross at this instant; the scene names no point there, so it is "
                f"named after them, and --point {name} takes moments about it")

    def name_of(self, at, joint=None) -> str:
        """The name of the place ``at``: a named point there, else ``C_<joint>`` for the place where
        ``joint`` acts (:func:`joint_point_name`), else ``X1``, ``X2`` ..."""
        for name, r in self.named.items():
            if _same_place(r, at):
                return name
        if joint is not None:
            name = joint_point_name(joint, self.named)
            self.about[name] = self.describe(name, joint)
        else:
            self.extra += 1
            name = f"X{self.extra}"
        self.named[name] = copy_vec(at)
        return name


def add_joint_point(system, point: str | None) -> None:
    """Make the point ``--point`` names a point of its body when it is one the worked solution and
    the advisor name after an element (``G_<element>``, its mass centre, a point of the body, as
    :class:`_Points` names it), after a joint (``C_<joint>``, :meth:`_Points.name_of`) or after two
    reactions (``I(R1,R2)``, :func:`crossing_name`): for the last two an instant point at the place where the joint acts or
    the lines of action cross, so that the moment equation can be taken about it. Other names are
    left to the formulation to accept or refuse.

    The point's offset from its body's reference point stays a function of the coordinates, so that
    its position reads as the place itself: the joint's own point (a contact on a circle at
    ``R*(sin(theta), -cos(theta))``, the joint's symbolic point) or the crossing (``(x, L*sin(theta))``),
    not the state's numbers, which would leave the joint's loads at a twin point and the "exact"
    answers rounded. Its velocity and acceleration are still those of the material point there at
    the instant (Eq. 6), and the drawing places it by its value at the scene's state.
    """
    from ..analyses.regimes import start_state
    from ..model.bodies import Point

    if point is None:
        return
    body, _, name = point.rpartition(":")
    state = None
    candidates = [system.bodies[body]] if body in system.bodies else [] if body else list(system.bodies.values())
    placed = False
    for b in candidates:
        if name in b.point_names():
            placed = True
            continue
        points = _Points(system, b.name)
        centre = next((e for e in b.elements if f"G_{e.name}" == name and name in points.named), None)
        if centre is not None:  # an element's mass centre, as the advisor lists it: a point of the body
            b.points[name] = Point(name, copy_vec(centre.mass_center))
            system.reset()
            placed = True
            continue
        forces = _forces_on(system, b.name, points)
        at = next((f.at for f in forces if f.point == name), None)
        state = state or start_state(system)  # (a contact may be open there)
        crossing = at is None or name not in points.about
        if crossing:
            at = _crossing(system, forces, name, point, _state_subs(system, state))
        if at is None:
            continue
        ref = next((n for n, p in b.points.items() if not p.is_instant), "G")
        offset = sp.Matrix(at) - system.point_position(b.name, ref)
        b.points[name] = Point(name, _vec(offset), frame="instant", relative_to=ref)
        system.reset()
        placed = True
    if not placed and candidates and name.startswith("I("):
        raise _not_a_crossing(system, point, name, candidates)


def _not_a_crossing(system, point: str, name: str, bodies):
    """The SceneError for a ``--point`` ``I(...)`` that names no crossing on ``bodies``: the form
    expected, and each body's reactions that have a line of action."""
    from ..errors import SceneError

    lines = {b.name: [f.name for f in _forces_on(system, b.name, _Points(system, b.name))
                      if f.reaction is not None and f.force is not None] for b in bodies}
    crossed = _CROSSING.fullmatch(name)
    if crossed is None:
        why = f"{name!r} is not of the form I(R1,R2)"
    else:
        unknown = [r for r in crossed.groups() if not any(r in names for names in lines.values())]
        why = (f"{' and '.join(map(repr, unknown))} {'is not a reaction' if len(unknown) == 1 else 'are not reactions'}"
               f" with a line of action on {'the body' if len(bodies) == 1 else 'any body'}") if unknown else \
            f"{crossed[1]} and {crossed[2]} do not both act on one body"
    listed = "; ".join(f"{b}: {', '.join(n) or 'none'}" for b, n in lines.items())
    return SceneError(f"{system.label}: --point {point}: {why}; expected BODY:I(R1,R2), the crossing of the lines "
                      f"of action of two reactions R1, R2 on the body (reactions: {listed})")


_CROSSING = re.compile(r"I\(([^,()]+),([^,()]+)\)")
"""``I(R1,R2)``, the advisor's name of the place where two reactions' lines of action cross."""


def read_point_name(text: str) -> str:
    """A ``--point`` value with the spaces inside an ``I(...)`` taken out (``crank:I(O_x, A_y)`` is
    ``crank:I(O_x,A_y)``, the name :func:`crossing_name` gives); any other value as it is."""
    body, colon, name = text.rpartition(":")
    if name.startswith("I(") and name.endswith(")"):
        return f"{body}{colon}I({''.join(name[2:-1].split())})"
    return text


def crossing_name(first: str, second: str) -> str:
    """``I(R1,R2)``: the advisor's name of the place where the lines of action of the reactions
    ``first`` and ``second`` cross (:data:`_CROSSING` reads it back for ``--point``)."""
    return f"I({first},{second})"


def crossing_words(first: str, second: str) -> str:
    """What the point :func:`crossing_name` names is, in the advisor's words."""
    return f"intersection of the lines of action of {first} and {second}"


def _crossing(system, forces, name: str, point: str, subs: dict):
    """The place (2x1, in the coordinates) where the lines of action of the two reactions the name
    ``I(R1,R2)`` gives cross, or None when ``name`` is not such a name of two reactions on the body
    among ``forces``. Lines parallel at the state ``subs`` are refused naming ``--point`` (the
    advisor lists no such point)."""
    from ..errors import SceneError

    crossed = _CROSSING.fullmatch(name)
    lines = {f.name: (sp.Matrix(f.at), f.force.xreplace({f.unknown: 1}))
             for f in forces if f.reaction is not None and f.force is not None}
    if crossed is None or not all(n in lines for n in crossed.groups()):
        return None
    (p1, d1), (p2, d2) = (lines[n] for n in crossed.groups())
    det, gap = cross_k(d1, d2), p2 - p1
    if not abs(_value(det, subs)) > 1e-9 * _value(d1.norm() * d2.norm(), subs):  # as the advisor's test
        raise SceneError(f"{system.label}: --point {point}: the lines of action of {crossed[1]} and "
                         f"{crossed[2]} are parallel at the scene's state: they do not cross")
    return p1 + d1 * cross_k(gap, d2) / det  # p1 + s d1 = p2 + t d2, s by Cramer's rule


def joint_point_name(joint, taken=()) -> str:
    """``C_<joint>``: the name of the unnamed place where ``joint`` acts on a body (a contact point,
    a cord's tangent point, a gear's pitch point), primed until it is not in ``taken``."""
    name = f"C_{joint.name}"
    while name in taken:
        name += "'"
    return name


def _joint_place(joint) -> str:
    from ..model.joints import Cord, Contact, GearMesh

    if isinstance(joint, Cord):
        return "where the cord leaves the drum"
    if isinstance(joint, GearMesh):
        return "the pitch point of the gears"
    if isinstance(joint, Contact):
        return "the contact point, a material point of the body"
    return f"a {joint.kind} joint"


# -- the forces on a body -----------------------------------------------------------------------


class _Force:
    """One force or couple on a body: applied (known) or a reaction (unknown magnitude)."""

    def __init__(self, name, kind, force, at, couple, reaction=None, point=""):
        self.name, self.kind = name, kind
        self.force = None if force is None else copy_vec(force)
        self.at = at
        self.couple = sp.sympify(couple)
        self.reaction = reaction
        self.point = point

    @property
    def unknown(self):
        return None if self.reaction is None else self.reaction.symbol


def _forces_on(system, body: str, points: _Points) -> list[_Force]:
    out = []
    for a in system.applied_loads:
        if a.body != body:
            continue
        point = points.name_of(a.at) if a.force is not None else ""
        out.append(_Force(a.name, a.kind, a.force, a.at, a.couple, point=point))
    slipping = _slipping_contacts(system)
    joints = {j.name: j for j in system.joints}
    for jl in system.joint_loads():
        if jl.body != body:
            continue
        sym = jl.reaction.symbol
        force = None if jl.force is None else vscale(sym, jl.force)
        point = points.name_of(jl.at, joints.get(jl.reaction.joint)) if jl.force is not None else ""
        contact = slipping.get(jl.reaction.name)
        if contact is not None and force is not None:  # N n, and the friction -sign(v_slip) mu_k N d apart
            joint, d, n = contact
            out.append(_Force(jl.reaction.name, f"normal reaction of contact {joint.name}",
                              sym * n * expanded(jl.force.dot(n)), jl.at, 0, reaction=jl.reaction, point=point))
            name = joint.friction_reaction.name if joint.friction_reaction is not None else f"friction_{joint.name}"
            out.append(_Force(name, f"friction of contact {joint.name}, slipping: {slip_friction(jl.reaction.name)}",
                              sym * d * expanded(jl.force.dot(d)), jl.at, 0, point=point))
            continue
        out.append(_Force(jl.reaction.name, f"reaction of joint {jl.reaction.joint}", force, jl.at,
                          sym * jl.couple, reaction=jl.reaction, point=point))
    return out


def _slipping_contacts(system) -> dict:
    """Normal reaction name -> (contact, d, n) for each contact sliding with friction (its
    normal reaction's load is N (n - s mu_k d): the friction is known once N is)."""
    out = {}
    contacts = [j for j in getattr(system, "contacts", ()) if j.friction is not None
                and j.current_regime.keeps_normal and not j.current_regime.keeps_tangential
                and j.current_regime.friction_direction()]
    if contacts:
        pose = system._pose_fn(system.poses)
        for j in contacts:
            d, n, _ = j.contact_frame(pose)
            out[j.normal_reaction.name] = (j, sp.Matrix(d), sp.Matrix(n))
    return out


def _moment(f: _Force, r_P) -> sp.Expr:
    m = f.couple
    if f.force is not None:
        m = m + cross_k(vsub(f.at, r_P), f.force)
    return m


# -- per body ------------------------------------------------------------------------------------


def _data_step(system, body: str, printer: FastStrPrinter | None = None) -> Step:
    b = system.bodies[body]
    rows = []
    for e in b.elements:
        rows.append((e.name, e.kind or type(e).__name__, sstr(e.mass, printer), sstr(tidy(e.I_G), printer)))
    mass = sstr(b.total_mass, printer)
    text = [f"Body {body}: {counted(len(b.elements), 'element')}, total mass m" + ("." if mass == "m" else f" = {mass}.")]
    if len(b.elements) > 1:
        text.append("A composite body (Eqs. 11-14): each element keeps its own mass centre and centroidal inertia.")
    return Step("data", f"Data of {body}", text, table=Table(("element", "kind", "mass m_k", "I_G,k"), tuple(rows)))


def _kinematics_step(system, body: str, P: str, used: list[str], points: _Points) -> Step:
    w, al = system.omega(body), system.alpha(body)
    r_P = system.point_position(body, P)  # the placement's: the other points are placed with it
    shown, v_P, a_P = system.point_kinematics(body, P)
    pivot = _pivot_text(system, body, P, r_P, shown) or _crossing_source(system, body, P)
    source = pivot[0] if pivot else "from the placement (the joints)"
    v_shown, a_shown = _vec(v_P), _vec(a_P)  # shown again in every other point's relation
    eqs = [
        Equation((Term(w),), (Term(tidy(w)),), "angular velocity (k component)", tag="omega", name="omega"),
        Equation((Term(al),), (Term(tidy(al)),), "angular acceleration (k component)", tag="alpha", name="alpha"),
        Equation((Term(shown),), (Term(_vec(shown)),), f"position of {P}", tag=f"pos:{P}", name=f"r_{P}", vector=True),
        Equation((Term(v_P),), (Term(v_shown),), f"velocity of {P}, {source}",
                 tag=f"vel:{P}", name=f"v_{P}", vector=True),
        Equation((Term(a_P),), (Term(a_shown),), f"acceleration of {P}, {source}",
                 tag=f"accel:{P}", name=f"a_{P}", vector=True),
    ]
    for X in used:
        if X == P:
            continue
        r = vsub(points.named[X], r_P)
        wr, ar, cr = k_cross(w, r), k_cross(al, r), vscale(-w**2, r)
        eqs.append(Equation((Term(r),), (Term(_vec(r)),), f"position of {X} relative to {P}",
                            tag=f"rel:{X}", name=f"r_{X}/{P}", vector=True))
        eqs.append(Equation((Term(vadd(v_P, wr)),), (Term(v_shown, f"v_{P}"), Term(_vec(wr), f"omega x r_{X}/{P}")),
                            f"velocity of {X}", tag=f"vel:{X}", name=f"v_{X}", vector=True))
        eqs.append(Equation((Term(vadd(a_P, ar, cr)),),
                            (Term(a_shown, f"a_{P}"), Term(_vec(ar), f"alpha x r_{X}/{P}"),
                             Term(_vec(cr), f"-omega^2 r_{X}/{P}")),
                            f"acceleration of {X}", "Eq. (15)" if X.startswith("G_") else "Eq. (6)",
                            tag=f"accel:{X}", name=f"a_{X}", vector=True))
    eqs += _midpoints(system, body, points, eqs)
    how = pivot[1] if pivot else f"Its velocity and acceleration follow from the joints (the placement of {body})"
    text = [("" if P == "P" else f"P = {P}. ") + f"{how}; "  # (a scene's own point named P: no "P = P")
            f"every other point's follow by the rigid-body relation from {P}: v = v_{P} + omega x r, "
            f"a = a_{P} + alpha x r - omega^2 r (Eq. 6; Eq. 15 for an element's mass centre G_k)."]
    text += [points.about[X] + "." for X in dict.fromkeys([P, *used]) if X in points.about]
    return Step("kinematics", f"Kinematics of {body} from {P}", text, eqs)


def _pivot_text(system, body: str, P: str, r_P, shown) -> tuple[str, str] | None:
    """(label, sentence) saying where P's motion comes from when a pin to the ground holds the body
    and its placement reaches it through other bodies (:meth:`System.point_kinematics`); None
    when P's kinematics are the placement's."""
    if _same_place(r_P, shown):
        return None
    joint, F, _, _ = system.fixed_point(body)
    F = F or "the pivot"
    why = (f"{body} is placed through the other bodies, so its placement writes {F} along the loop, at its "
           f"place only where the closure equations hold")
    if F == P:
        return (f"fixed by joint {joint.name} (a pin to the ground)",
                f"{P} is held by joint {joint.name}, a pin to the ground: r_{P} is the pin's fixed place and "
                f"v_{P} = a_{P} = 0 ({why})")
    return (f"from the fixed point {F}",
            f"{P} turns with {body} about {F}, held by joint {joint.name}, a pin to the ground ({why}): "
            f"v_{P} = omega x r_{P}/{F}, a_{P} = alpha x r_{P}/{F} - omega^2 r_{P}/{F}")


def _crossing_source(system, body: str, P: str) -> tuple[str, str] | None:
    """(label, sentence) saying where P's motion comes from when P is a crossing ``I(R1,R2)``
    (:func:`add_joint_point`): no joint acts there, so its velocity and acceleration are derived, as
    the advisor's column a_P says; None for any other P."""
    p = system.bodies[body].points.get(P)
    if p is None or not p.is_instant or _CROSSING.fullmatch(P) is None:
        return None
    ref = p.relative_to
    return (f"derived by the rigid-body relation from {ref} (Eq. 6)",
            f"No joint acts at {P}, so its velocity and acceleration are derived (as the advisor's a_P says): "
            f"those of the material point of {body} at {P} at this instant, by the rigid-body relation from "
            f"{ref} (Eq. 6), v_{P} = v_{ref} + omega x r_{P}/{ref}, a_{P} = a_{ref} + alpha x r_{P}/{ref} - "
            f"omega^2 r_{P}/{ref}; r_{P} is where the lines of action cross, a function of the coordinates")


def _midpoints(system, body: str, points: _Points, eqs: list[Equation]) -> list[Equation]:
    """a_C = (a_X + a_Y)/2 for a slender bar whose centre C and ends X, Y are named points whose
    accelerations are shown (r_C = (r_X + r_Y)/2 differentiated twice: the paper's Eq. 16)."""
    shown = {e.tag.split(":", 1)[1]: e for e in eqs if e.tag.startswith("accel:")}  # .left: the acceleration
    out = []
    for e in system.bodies[body].elements:
        if e.kind != "slender_bar":
            continue
        half = vscale(e.dims["length"] / 2, vec(sp.cos(e.angle), sp.sin(e.angle)))
        names = [next((n for n, r in points.named.items() if n in shown and _same_place(r, at)),
                      None) for at in (system.body_point(body, c) for c in (e.mass_center, vsub(e.mass_center, half),
                                                                           vadd(e.mass_center, half)))]
        if None in names:
            continue
        C, X, Y = names
        a = {n: shown[n].left for n in names}
        out.append(Equation((Term(a[C]),), (Term(_vec(vscale(sp.S.Half, a[X])), f"a_{X}/2"),
                                                  Term(_vec(vscale(sp.S.Half, a[Y])), f"a_{Y}/2")),
                            f"{C} is the midpoint of the bar {X}{Y}: r_{C} = (r_{X} + r_{Y})/2, differentiated twice",
                            "Eq. (16)", tag=f"midpoint:{C}", name=f"a_{C}", vector=True))
    return out


MAX_CELL = 60
"""Most characters of a free-body table cell; a longer force is shown by its vector equation only."""


def _fbd_step(system, body: str, forces: list[_Force], printer: FastStrPrinter | None = None) -> Step:
    rows = []
    for f in forces:
        what = "unknown (reaction)" if f.reaction is not None else "known (applied)"
        if f.force is not None:
            fx, fy = xy(f.force)
            shown = f"({sstr(tidy(fx), printer)}, {sstr(tidy(fy), printer)})"
            if len(shown) > MAX_CELL:
                shown = f"the vector {_vector_name(f)} above"
            rows.append((f.name, f.kind, f.point, shown, what))
        else:
            shown = f"couple {sstr(tidy(f.couple), printer)}"
            rows.append((f.name, f.kind, "-", shown if len(shown) <= MAX_CELL else "a couple (too long to show here)", what))
    step = Step("fbd", f"Free-body diagram of {body}",
                [f"The forces and couples on {body}, fixed-frame components (x right, y up)."],
                _force_vectors(forces, body), table=Table(("force", "kind", "at", "components", ""), tuple(rows)))
    step.figure_request = {"scene": system.source or system.name, "body": body, "fbd": True}
    return step


def _force_vectors(forces: list[_Force], body: str) -> list[Equation]:
    """Each force as a vector in the fixed frame (the paper's Eqs. 22 and 36), tag ``force:NAME``.

    A reaction whose vector on ``body`` negates its scalar in a component (the opposite half of a
    joint's pair, ``(-A_x, 0)``; a guide's normal pushing along -x) is not named by its scalar, which
    would read ``A_x = (-A_x, 0)``: the vector is F_A_x, the force whose scalar is A_x, and the
    label says so."""
    out = []
    for f in forces:
        if f.force is None:
            continue
        name, label = _vector_name(f), f"force {f.name} at {f.point} (vector)"
        if name != f.name.replace("gravity:", "W_"):
            label = f"force {f.name} at {f.point} (vector {name}: the force on {body} whose scalar is {f.name})"
        out.append(Equation((Term(f.force),), (Term(_vec(f.force)),), label, tag=f"force:{f.name}", name=name,
                            vector=True))
    return out


def _vector_name(f: _Force) -> str:
    """The name of the force ``f``'s vector: W_body for a weight, F_A_x for a reaction A_x whose
    components negate it (:func:`_force_vectors`), else the force's own name."""
    if f.reaction is not None and any(could_extract_minus_sign(c) for c in _vec(f.force) if c != 0):
        return f"F_{f.name}"
    return f.name.replace("gravity:", "W_")


def _element_offsets(system, body: str, P: str):
    """(element, m_k, r_k/P) per element."""
    r_P = system.point_position(body, P)
    return [(e, e.mass, vsub(system.body_point(body, e.mass_center), r_P)) for e in system.bodies[body].elements]


def _element_accelerations(system, body: str, P: str):
    """(element, m_k, r_k/P, a_k) per element, a_k by Eq. 15 from P."""
    a_P = system.point_kinematics(body, P)[2]
    w, al = system.omega(body), system.alpha(body)
    return [(e, m, r, vsub(vadd(a_P, k_cross(al, r)), vscale(w**2, r))) for e, m, r in _element_offsets(system, body, P)]


def _newton_step(system, body: str, P: str, forces: list[_Force]) -> Step:
    b = system.bodies[body]
    composite = len(b.elements) > 1
    parts = _element_accelerations(system, body, P)
    eqs = []
    for i, axis in enumerate("xy"):
        lhs = tuple(Term(tidy(f.force[i]), f.name) for f in forces if f.force is not None and not _zero(f.force[i]))
        if composite:
            rhs = tuple(Term(tidy_linear(m * a[i], system.qdd + [c.qd**2 for c in system.coordinates]),
                             f"m_{e.name} a_{e.name},{axis}") for e, m, _, a in parts if not _zero(a[i]))
            rhs = rhs or (Term(sp.Integer(0)),)
        else:
            e, m, _, a = parts[0]
            rhs = (Term(tidy_linear(m * a[i], system.qdd + [c.qd**2 for c in system.coordinates]), f"m a_G,{axis}"),)
        eqs.append(Equation(lhs or (Term(sp.Integer(0)),), rhs, f"Newton, {axis} component",
                            "Eq. (14)" if composite else "Eq. (1)", tag=f"newton_{axis}"))
    text = ["Sum of the forces = sum over the elements of m_k a_k (Eq. 14), a_k from P by Eq. 15."
            if composite else "Sum of the forces = m a_G (Eq. 1)."]
    return Step("newton", f"Newton's equations for {body}", text, eqs)


def _inertia_equation(system, body: str, P: str) -> Equation:
    terms = []
    r_P = system.point_position(body, P)
    for e in system.bodies[body].elements:
        d = vsub(system.body_point(body, e.mass_center), r_P)
        terms.append(Term(tidy(e.I_G), f"I_G of {e.name}"))
        dx, dy = xy(d)
        d2 = tidy(expanded(dx ** 2 + dy ** 2))
        if d2 != 0:
            terms.append(Term(tidy(e.mass * d2), f"m d^2 of {e.name}"))
    total = sp.Add(*[t.expr for t in terms])
    return Equation((Term(total),), tuple(terms), f"moment of inertia about {P}, per element (parallel axes)",
                    "Eq. (12)", tag="inertia", name=f"I_{P}")


def _euler_step(system, body: str, P: str, forces: list[_Force],
                printer: FastStrPrinter | None = None, collect: bool = True) -> tuple[Step, list[_Force]]:
    """The generalized Euler equation about P (and I_P per element); ``collect``: with the equation
    collected by unknown when that form is not longer. Also returns the forces whose moment is zero."""
    r_P = system.point_position(body, P)
    a_P = system.point_kinematics(body, P)[2]
    al = system.alpha(body)
    rates = system.qdd + [c.qd**2 for c in system.coordinates]
    lhs, dropped = [], []
    for f in forces:
        m = _moment(f, r_P)
        if _zero(m):
            dropped.append(f)
            continue
        lhs.append(Term(tidy(m), f"moment of {f.name} about {P}"))
    S = vadd(vec(0, 0), *[vscale(m_k, r) for _, m_k, r in _element_offsets(system, body, P)])
    inertial = -cross_k(S, a_P)
    if not _zero(inertial):
        lhs.append(Term(tidy_linear(inertial, rates), f"inertial term -r_G/{P} x m a_{P}"))
    inertia = _inertia_equation(system, body, P)
    I_P = tidy(inertia.left)
    euler = Equation(tuple(lhs) or (Term(sp.Integer(0)),), (Term(_inertia_times_alpha(I_P, al), f"I_{P} alpha"),),
                     f"generalized Euler equation about {P}",
                     "Eq. (11)" if len(system.bodies[body].elements) > 1 else "Eq. (10)", tag="euler")
    text = [f"M_{P} - r_G/{P} x m a_{P} = I_{P} alpha: the moments of the actual forces about {P}, then the "
            f"inertial term, then I_{P} alpha with I_{P} from the parallel-axis theorem (Eq. 12)."]
    text += _vanishing_inertia_words(body, P, I_P, al, system.omega(body))
    if _zero(inertial):
        text.append(f"The inertial term vanishes here: r_G/{P} x a_{P} = 0 ({P} is the mass centre, or a_{P} "
                    f"is parallel to r_G/{P} or zero).")
    collected = _collected_equation(system, body, P, euler) if collect else None
    printer = printer or FastStrPrinter()  # the two forms share their subexpressions: each printed once
    if collected is not None and _length(collected, printer) > _length(euler, printer):
        collected = None  # collecting spreads the terms over the unknowns' coefficients: no help to read
        text.append(f"The equation is not shown collected by unknown: that form is longer than the equation "
                    f"above.")
    if collected is not None:
        text.append(collected.label[0].upper() + collected.label[1:] + ": each unknown with its coefficient, "
                    "the known terms on the right (as the paper's Eq. 28 writes Eq. 27).")
    return (Step("euler", f"Generalized Euler equation of {body} about {P}", text,
                 [inertia, euler] + ([collected] if collected is not None else [])), dropped)


def _inertia_times_alpha(I_P, al) -> sp.Expr:
    """I_P alpha as shown: the product unevaluated (I_P first, as Eq. 10 writes it), or 0 when
    either factor is zero (never ``(m*r**2/3)*0``)."""
    if I_P == 0 or al == 0:
        return sp.Integer(0)
    return sp.Mul(I_P, al, evaluate=False)


def _vanishing_inertia_words(body: str, P: str, I_P, al, omega) -> list[str]:
    """The sentence saying why I_P alpha is 0, when it is (:func:`_inertia_times_alpha`)."""
    if al == 0:
        how = "does not turn (omega = alpha = 0)" if omega == 0 else "turns at a constant rate (alpha = 0)"
        return [f"{body} {how}, so I_{P} alpha = 0."]
    if I_P == 0:
        return [f"I_{P} = 0 (the mass of {body} is all at {P}), so I_{P} alpha = 0."]
    return []


def _length(eq: Equation, printer: FastStrPrinter | None = None) -> int:
    """Characters of an equation's terms as printed (to compare two forms of it); ``printer``, one
    shared by the forms compared (:func:`solver.strprint.sstr`)."""
    return sum(len(sstr(t.expr, printer)) for t in (*eq.lhs, *eq.rhs))


ALPHA = sp.Symbol("alpha", real=True)
"""The body's angular acceleration, written for q'' in a one-body, one-coordinate system."""


def _alpha_form(system) -> dict:
    """{q'': (alpha, k)} when the only body's alpha = k q'' (k = +-1): the unknown written as alpha
    (remembered by the system: several steps ask; read only)."""
    def build():
        if len(system.bodies) != 1 or len(system.free) != 1:
            return {}
        c = system.free[0]
        al = system.alpha(next(iter(system.bodies)))
        k = derivative(al, c.qdd)
        return {c.qdd: (ALPHA, k)} if k in (1, -1) and _zero(al - k * c.qdd) else {}
    return system._memo("explain_alpha_form", build)


_WRITES_ALPHA = ("euler", "numbers")
"""The kinds of step whose equations write the unknown q'' as alpha (:func:`_alpha_form`): the
collected moment equation's (:func:`_collected_equation`) and the equations with the data entered."""


def say_what_alpha_is(system, expl: Explanation) -> None:
    """Say once, in the text of the first step whose equations write the unknown q'' as alpha
    (:func:`_alpha_form`: the collected moment equation, else the equations with the data entered, as
    the paper's Eqs. 28-29 do), what alpha stands for; nothing when no equation does (in place)."""
    form = _alpha_form(system)
    if not form:
        return
    (q_ddot, (alpha, k)), = form.items()
    body = next(iter(system.bodies))
    names = {*system.parameters, *(r.name for r in system.reactions),
             *(str(x) for c in system.coordinates for x in (c.q, c.qd, c.qdd))}
    writing = [step for step in expl.steps() if (step.kind in _WRITES_ALPHA or alpha.name in names)
               and any(_has(t.expr, alpha) for e in step.equations for t in (*e.lhs, *e.rhs))]
    if not writing:  # (no other step writes it, unless the scene names a symbol alpha itself)
        return
    which = {"euler": "the moment equation collected below", "numbers": "the equations with the data entered"}
    where = " and ".join(dict.fromkeys(which.get(s.kind, f"the equations of '{s.title}'") for s in writing))
    writing[0].text.append(f"Here alpha = {sstr(k * q_ddot)}, the angular acceleration of {body} (k component, "
                           f"counter-clockwise positive): {where} write the unknown {q_ddot} as alpha; the "
                           f"other equations keep {q_ddot}.")


def _has(expr, symbol) -> bool:
    """Whether ``symbol`` appears in ``expr`` (an expression, a 2-vector Matrix or a number)."""
    if isinstance(expr, sp.MatrixBase):  # entry by entry (Basic.has is cached; Matrix.has is not)
        return any(x.has(symbol) for x in expr.flat())
    if isinstance(expr, sp.Basic):
        return expr.has(symbol)  # (no sympify: it would copy a Matrix into an immutable one)
    return sp.sympify(expr).has(symbol)


def _collected_equation(system, body: str, P: str, euler: Equation) -> Equation | None:
    """The moment equation divided by the parameters common to all its terms and collected by
    unknown, known terms on the right, signed so that the first reaction's coefficient reads
    positive (Eq. 27 -> Eq. 28).
    None when there is nothing to collect."""
    unknowns = list(system.qdd) + [r.symbol for r in system.reactions]
    e = expanded(euler.residual)
    terms = [t for t in sp.Add.make_args(e) if t != 0]
    coefs = {u: c for u, (c, zero) in _coefficients(system, e, unknowns).items() if not zero}
    if not terms or not coefs:
        return None
    common, divided = sp.Integer(1), []
    powers = [term_powers(t) for t in terms]
    for p in system.symbols.values():
        k = sp.sympify(min(sp.sympify(d.get(p, 0)) for d in powers))
        if k.is_Integer and k > 0:
            common *= p**k
            divided.append(sstr(p**k))
    rest = expanded(e - sp.Add(*[c * u for u, c in coefs.items()]))
    rhs = tidy(expanded(-rest / common))
    reactions = [c for u, c in coefs.items() if u not in system.qdd]
    lead = reactions[0] if reactions else -rhs  # the first reaction's coefficient reads positive (Eq. 28)
    sign = -1 if could_extract_minus_sign(sp.sympify(lead)) else 1
    rename = _alpha_form(system)
    lhs = []
    for u, c in coefs.items():
        shown, k = rename.get(u, (u, 1))
        lhs.append(Term(tidy(expanded(sign * c / common / k)) * shown, str(shown)))
    how = f"divided by {' '.join(divided)} and collected" if divided else "collected"
    return Equation(tuple(lhs), (Term(sign * rhs, "known"),), f"the moment equation about {P} {how}",
                    tag="collected")


def _coefficients(system, expr, unknowns) -> dict:
    """{u: (``expand(expr).coeff(u)``, whether it is identically zero)} for each of ``unknowns``,
    remembered by the system (the moment equation's are asked by the collected form, the step on
    the dropped unknowns and the equation of motion; read only)."""
    e = expanded(expr)

    def build():
        out = {}
        for u in unknowns:
            c = coefficient(e, u)
            out[u] = (c, c == 0 or _zero(c))
        return out
    return system._memo(("coefficients", e, tuple(unknowns)), build)


def _unknowns_in(system, expr, unknowns) -> list:
    """The ``unknowns`` whose coefficient in ``expr`` is not identically zero."""
    return [u for u, (_, zero) in _coefficients(system, expr, unknowns).items() if not zero]


def counted(n: int, noun: str) -> str:
    """``1 unknown``, ``2 unknowns``: a count with its noun in the right number."""
    return f"{n} {noun}" if n == 1 else f"{n} {noun}s"


def _where_it_vanishes(system, coefficient, printer) -> tuple[str, str]:
    """(table cell, phrase) for an unknown's coefficient that is not identically zero but is zero
    at the state: at this state only when it depends on the coordinates, their rates or time; for
    the scene's parameter values (at every state) when it holds none of them, as
    ``L*m*(6*a - L)/12`` at L = 6a, a bar pinned at its centre of percussion."""
    shown = sstr(tidy(coefficient), printer)
    if coefficient.free_symbols & {*system.q, *system.qd, system.t}:
        return "at this state", f"at this state only (its coefficient {shown} vanishes here, not identically)"
    return ("for these values", f"for the scene's parameter values, at every state (its coefficient {shown} "
            "is zero for these values, not identically)")


def _dropped_step(system, body: str, P: str, forces, dropped, newton: Step, euler: Step,
                  at_state: list[str] | None = None, printer: FastStrPrinter | None = None) -> Step:
    """Which unknowns the moment equation about P holds, and why the others drop out.

    ``at_state``: the names of the unknowns it holds at the state, as the point advisor counts them
    (:func:`solver.explain.advisor.unknowns_at_state`); an unknown whose coefficient is not
    identically zero but vanishes there is said to vanish at this state only.
    """
    unknowns = list(system.qdd) + [r.symbol for r in system.reactions]
    residual = expanded(euler.equation("euler").residual)
    coefficients = _coefficients(system, residual, unknowns)
    in_euler = _unknowns_in(system, residual, unknowns)
    here = [u for u in in_euler if at_state is None or str(u) in at_state]
    newton_rows = {tag: expanded(newton.equation(tag).residual) for tag in ("newton_x", "newton_y")}
    reactions = [r.symbol for r in system.reactions]
    rows, text = [], []
    for f in forces:
        if f.reaction is None:
            continue
        u = f.unknown
        cells = [f.name]
        for tag in ("newton_x", "newton_y"):
            cells.append("yes" if u in _unknowns_in(system, newton_rows[tag], reactions) else "no")
        line = f.force is not None and _zero(f.couple)
        if u in here:
            cells.append("yes")
            why = ""
        elif u in in_euler:
            where, note = _where_it_vanishes(system, coefficients[u][0], printer)
            cells.append(f"no, {where}")
            why = f"{'its line of action passes through ' + P if line else 'its moment about ' + P + ' is zero'} {note}"
        else:
            cells.append("no")
            why = (f"its line of action passes through {P}" if f in dropped and line
                   else f"its moment about {P} is zero" if f in dropped else f"its moments about {P} cancel")
        cells.append(why)
        rows.append(tuple(cells))
        if why:
            text.append(f"{f.name} drops out of the moment equation: {why}.")
    for u in in_euler:  # an acceleration whose coefficient vanishes at the state
        if u not in here and u in system.qdd:
            text.append(f"{u} drops out of the moment equation {_where_it_vanishes(system, coefficients[u][0], printer)[1]}.")
    names = ", ".join(str(u) for u in here)
    if len(here) == len(in_euler):
        text.insert(0, f"The moment equation about {P} contains {counted(len(here), 'unknown')}: {names}.")
    else:
        text.insert(0, f"The moment equation about {P} contains {counted(len(in_euler), 'unknown')} in "
                       f"general ({', '.join(map(str, in_euler))}), {len(here)} at this state ({names}): the "
                       "count of the point advisor and of the equations with the data entered.")
    return Step("dropped", f"Unknowns in the moment equation about {P}", text,
                table=Table(("reaction", "Newton x", "Newton y", f"Euler about {P}", "why not in Euler"), tuple(rows)))


def explain(system, point: str | None = None, *, advice: bool = True, solution: bool = True,
            kinematics: bool = True, collected: bool = True) -> Explanation:
    """The worked solution of ``system`` at its state about ``point`` (``--point``).

    Parameters
    ----------
    system : solver.model.system.System
    point : str or None
        ``BODY:POINT``, a point name, or None (each body's reference point).
    advice : bool
        Include the point advisor's ranking.
    solution : bool
        Include the whole-system section (equation of motion, solution at the state, check by
        the mass-centre form); False: the data and the per-body steps only.
    kinematics : bool
        Include each body's kinematics step (False: a reader that shows its own kinematics, as
        the paper's examples do, skips its cost, a third of the per-body work).
    collected : bool
        Include, in each body's Euler step, the moment equation collected by unknown (as the paper's
        Eq. 28 writes Eq. 27) where that form is not longer (False: a reader that shows the equation
        as written only, as the paper's examples do, skips its cost).

    Returns
    -------
    Explanation

    Raises
    ------
    SceneError
        An unknown point; SingularConfigurationError at a singular state.
    """
    from ..analyses.instant import assemble, solution_in_regime, solve_instant, solved_at_state, unknown_quantities
    from ..formulations import formulate

    add_joint_point(system, point)
    scene, regime, warning = system, None, None
    if system.contacts:  # the contact regime that holds at the state decides the equations
        from ..analyses.regimes import system_in_regime

        system, regime, warning, state = system_in_regime(system, point)
        found = (regime, warning, state)  # as solve_instant would find it (the same search)
    if regime is not None and regime.indeterminate:  # every contact row kept: it does not validate
        from ..formulations import Formulation, resolve_points

        f = Formulation(system, "generalized_euler", resolve_points(system, point))
    else:
        f = formulate(system, "generalized_euler", point)
    if not scene.contacts:
        state = assemble(system)
    expl = Explanation(f"Worked solution: {system.name}", system.name, dict(f.points),
                       symbol_latex=latex_names(system))
    expl.sections.append(_system_data_section(system, state))
    in_regime = None
    if scene.contacts and solution:  # the product's own regime solve (its round-off zeros in the regime's reasons)
        in_regime = solution_in_regime(scene, *found, point, "generalized_euler")
    if scene.contacts:
        expl.sections[-1].steps.append(_regime_step(scene, regime, warning))
    parts: dict = {}
    for body, P in f.points.items():
        expl.sections.append(_body_section(system, body, P, parts, (f, state), kinematics, expl.printer,
                                           collected))
    if not solution:
        say_what_alpha_is(system, expl)
        return expl
    final = Section("Solution", None)
    if advice and not (regime is not None and regime.indeterminate):  # the advisor needs a system that validates
        from .advisor import advice_step

        final.steps.append(advice_step(system, state, parts))
    motion = _motion_step(system, f, expl)
    if motion is None and system.free:
        motion = _constrained_motion_step(system, f, expl, state)
    if motion is not None:
        final.steps.append(motion)
    numbers = _numbers_step(system, f, expl, state)
    if numbers is not None:
        final.steps.append(numbers)
    numeric = _numeric_system(system, f, state)  # the equations shown, at the state
    cond = _condition_number(numeric[0])
    if scene.contacts:  # the product's own regime solve, and the same by the mass-centre form
        solution = in_regime
        check = _mass_center_in_regime(scene, found)
    else:
        # where something moves, the product's own solve (refined once, its round-off bounded: the
        # cancellation warning of `solve`)
        own = None if any(state.qd) else _solve_at_state(system, f, point, state, numeric, cond)
        if own is None:
            solution = solve_instant(system, point, "generalized_euler", state)
        else:  # at rest the substituted system above, solved here, with solve's round-off zeros
            res, extra, _ = solved_at_state(system, point, "generalized_euler", state)
            zeros = extra.get("zero_to_round_off", {})
            own.unknowns.update(unknown_quantities(system, state, res, zeros))
            own.extra.update({"zero_to_round_off": zeros} if zeros else {})
            solution = own
        check = _mass_center_check(system, state)
    final.steps.append(_solution_step(system, solution, cond))
    final.steps.append(_check_step(system, solution, check))
    if regime is not None and regime.indeterminate:
        from ..analyses.regimes import SPLIT_NAME

        final.steps[-1].text.append(f"The contact forces are statically indeterminate: both routes show {SPLIT_NAME}, "
                                    "which one rule chooses (see the contact regime), so they agree, as the "
                                    "accelerations (which are determined) must.")
    expl.sections.append(final)
    say_what_alpha_is(system, expl)
    return expl


def _regime_step(scene, regime, warning) -> Step:
    """Which contact regime holds at the state, and why (solver.analyses.regimes.find_regime)."""
    text = ["Each contact sticks (rolls), slips or separates; the regime that holds is the one whose "
            "conditions all hold: normal forces press (N >= 0), sticking friction stays in the cone "
            "(|F| <= mu_s N), a slip accelerates the way it slides, an opened gap does not close; Coulomb's "
            "rule prefers sticking to slipping and contact to separation."]
    rows = []
    if regime is None:
        text.append(warning or "The scene as written is solved.")
    else:
        for c in regime.checks:
            rows.append((c.joint, c.regime.label, c.reason))
        if any(c.regime.friction_direction() and c.regime.keeps_normal for c in regime.checks):
            text.append("In the slipping regime the friction is not an unknown: it is the known force "
                        f"{slip_friction()} along the contact line ({SLIP_VELOCITY_NOTE}), so only N is; "
                        "the free-body diagram shows N and the friction apart.")
        if regime.indeterminate:
            from ..analyses.regimes import INDETERMINATE_NOTE

            text.append(INDETERMINATE_NOTE[0].upper() + INDETERMINATE_NOTE[1:] + ".")
        for reason in regime.rejected[:6]:
            text.append(f"Rejected: {reason}.")
    return Step("regime", "Contact regime at the state", text,
                table=Table(("contact", "regime", "why"), tuple(rows)) if rows else None)


def _body_section(system, body: str, P: str, parts: dict | None = None, at=None,
                  kinematics: bool = True, printer: FastStrPrinter | None = None,
                  collected: bool = True) -> Section:
    """The steps of one body; ``parts`` (body -> (points, forces)) receives what the point advisor
    needs again (no later step names new points); ``at``: (formulation, state), to say which
    unknowns the moment equation holds at the state; ``kinematics``: with the kinematics step;
    ``printer``: the explanation's (:attr:`Explanation.printer`), for the texts the steps hold;
    ``collected``: with the moment equation collected by unknown (:func:`_euler_step`)."""
    points = _Points(system, body)
    forces = _forces_on(system, body, points)
    if parts is not None:
        parts[body] = (points, forces)
    b = system.bodies[body]
    used = [P] + (["G"] if "G" != P else [])
    if len(b.elements) > 1:
        used += [f"G_{e.name}" for e in b.elements if f"G_{e.name}" in points.named]
    for f in forces:
        if f.force is not None and f.point not in used:
            used.append(f.point)
    section = Section(f"Body {body}", body)
    section.steps.append(_data_step(system, body, printer))
    if kinematics:
        section.steps.append(_kinematics_step(system, body, P, used, points))
    section.steps.append(_fbd_step(system, body, forces, printer))
    newton = _newton_step(system, body, P, forces)
    section.steps.append(newton)
    euler, dropped = _euler_step(system, body, P, forces, printer, collected)
    section.steps.append(euler)
    at_state = None
    if at is not None:
        from .advisor import unknowns_at_state

        at_state = unknowns_at_state(system, at[0], body, P, at[1])
    section.steps.append(_dropped_step(system, body, P, forces, dropped, newton, euler, at_state, printer))
    return section


# -- the whole system ----------------------------------------------------------------------------


def _system_data_section(system, state) -> Section:
    from ..cli_common import format_number, in_output_units
    from ..units import unit_text

    rows = tuple((name, f"{format_number(float(q.magnitude))} {unit_text(q.units)}".strip() if hasattr(q, "units")
                  else str(q)) for name, q in system.parameters.items())

    def shown(value: float, unit: str) -> str:  # in the scene's output units
        value, unit = in_output_units(value, unit, system.output_units)
        return f"{format_number(value)} {unit}"

    coords = []
    for c, v, r in zip(system.free, state.q, state.qd):
        if c.kind == "angle":
            coords.append((c.name, shown(math.degrees(v), "deg"), shown(r, "rad/s")))
        else:
            coords.append((c.name, shown(v, "m"), shown(r, "m/s")))
    step = Step("data", "Data and state", [SceneText(system.description)] if system.description else [],
                table=Table(("parameter", "value"), rows))
    state_step = Step("data", "State", ["The instant solved (dependent coordinates from the closure equations)."]
                      if system.dependent else [], table=Table(("coordinate", "value", "rate"), tuple(coords)))
    return Section("Data", None, [step, state_step])


def _single_reaction_substitution(system, f, body: str):
    """For a one-body, one-coordinate system: each reaction left in the moment equation
    solved from the Newton component that holds it alone. None when that does not apply."""
    if len(system.bodies) != 1 or len(system.free) != 1 or system.closure:
        return None
    eqs = {e.name.split(": ")[-1]: e.expr for e in f.equations if e.body == body}
    euler = next(v for k, v in eqs.items() if k.startswith("Euler"))
    reactions = [r.symbol for r in system.reactions]
    left = _unknowns_in(system, euler, reactions)
    subs, used = {}, []
    for r in left:
        for axis in ("Newton x", "Newton y"):
            e = expanded(eqs[axis])
            held = _unknowns_in(system, e, reactions)
            if held == [r] and axis not in used:
                subs[r] = -e.xreplace({r: 0}) / coefficient(e, r)  # linear in r
                used.append(axis)
                break
        else:
            return None
    return euler, subs, used


def _motion_step(system, f, expl) -> Step | None:
    """The equation of motion from its structure: M q'' + (rate terms) + (rest) = Q (None for a
    system with closure rows or a slipping contact: :func:`_constrained_motion_step`)."""
    if system.closure or not system.independent or _slipping_contacts(system):
        return None
    from ..analyses.eom import equations_of_motion

    eqs = []
    text = []
    body = next(iter(system.bodies))
    sub = _single_reaction_substitution(system, f, body)
    qdd = system.qdd
    rates = [a * b for i, a in enumerate(system.qd) for b in system.qd[i:]]
    if sub is not None:
        euler, subs, used = sub
        for r, value in subs.items():
            eqs.append(Equation((Term(r),), (Term(tidy_linear(value, qdd + rates)),),
                                f"{r} from {', '.join(used)}", tag=f"from_newton:{r}", name=str(r)))
        if subs:
            eliminated = expanded(euler.xreplace(subs))
            eqs.append(Equation((Term(tidy_linear(eliminated, qdd + rates)),), (Term(sp.Integer(0)),),
                                f"moment equation with {', '.join(map(str, subs))} substituted", tag="eliminated"))
            text.append(f"The moment equation about {f.points[body]} still holds "
                        f"{', '.join(map(str, subs))}; {' and '.join(used)} "
                        f"give{'s' if len(used) == 1 else ''} {'it' if len(subs) == 1 else 'them'} without other "
                        "reactions.")
    Q = system.generalized_forces()
    for c, e, q in zip(system.free, equations_of_motion(f), Q):
        eqs.append(_structured_eom(system, c, e, q, (), "reactions eliminated"))
    linear = _zero_parameters_set(system, eqs[-1]) if len(system.free) == 1 else None
    small = _small_oscillations(system, linear) if linear is not None else None
    if small is not None:
        eqs.extend(_small_motion_rules(system, linear))  # Eq. 45
        eqs.append(_linearised(system, small))           # Eq. 46, first part
        eqs.append(small)                                 # Eq. 46, omega_n
        text.append(f"Small oscillations about {system.free[0].name} = 0 (an equilibrium with the scene's "
                    "parameters, those that are zero set to zero): with the small-motion rules below (each "
                    "exact to first order), the equation of motion linearised, M(0) q'' + K q = 0, "
                    "oscillates at omega_n = sqrt(K / M(0)).")
    text.append(f"{_eom_words(system)}: the reactions eliminated (projection on the partial velocities of "
                f"each body's P), written as M q'' + (rate terms) + (configuration terms) = Q, with Q the "
                f"generalized force of the non-conservative loads.")
    return Step("motion", "Equation of motion", text, eqs)


def _projected(system, f) -> list[sp.Expr]:
    """Kane's projection of each body's equations on the partial velocities of its P, one per
    free coordinate (as :func:`solver.analyses.eom.equations_of_motion`), keeping every reaction
    whose coefficient is not identically zero: the closure multipliers, and a slipping contact's
    normal force (its friction -sign(v_slip) mu_k N does work)."""
    per_body = {}
    for e in f.equations:
        if e.body is not None:
            per_body.setdefault(e.body, []).append(e.expr)
    out = []
    for c in system.free:
        terms = []
        for body, (nx, ny, eu) in per_body.items():
            v, w = system.point_velocity(body, f.points[body]), system.omega(body)
            terms += [derivative(v[0], c.qd) * nx, derivative(v[1], c.qd) * ny, derivative(w, c.qd) * eu]
        e = expanded(-sp.Add(*terms))
        for r in system.reactions:
            coef = coefficient(e, r.symbol)
            if coef != 0 and _zero(coef):  # a workless reaction: it drops out
                e = expanded(e - coef * r.symbol)
        out.append(e)
    return out


def _reaction_from_body_equations(expl, r, known: dict, unknown: set):
    """(value, where) of reaction ``r`` from a displayed body equation holding it and no other
    unknown reaction (those in ``known`` substituted), or None."""
    for section in expl.sections:
        if section.body is None:
            continue
        for kind, tag in (("newton", "newton_x"), ("newton", "newton_y"), ("euler", "euler")):
            try:
                e = expanded(sp.sympify(section.step(kind).equation(tag).residual).xreplace(known))
            except KeyError:
                continue
            coef = coefficient(e, r)
            if _zero(coef) or any(not _zero(coefficient(e, x)) for x in unknown - {r}):
                continue
            label = {"newton_x": "Newton x", "newton_y": "Newton y", "euler": "the moment equation"}[tag]
            return -e.xreplace({r: 0}) / coef, f"{label} of {section.body}"
    return None


def _normal_force_from_newton(expl, contact, r, known: dict, unknown: set):
    """(N, where) from Newton's equation of the contact's body along the contact normal n (the
    friction, along d, has no component there), or None when that holds other unknown reactions."""
    joint, _, n = contact
    try:
        newton = expl.section(joint.second).step("newton")
    except KeyError:
        return None
    e = expanded((n[0] * newton.equation("newton_x").residual
                   + n[1] * newton.equation("newton_y").residual).xreplace(known))
    coef = coefficient(e, r)
    if _zero(coef) or any(not _zero(coefficient(e, x)) for x in unknown - {r}):
        return None
    return -e.xreplace({r: 0}) / coef, f"Newton along the normal of contact {joint.name} ({joint.second})"


def _eom_words(system) -> str:
    """``The equation of motion`` or ``The equations of motion``, by the number of free coordinates."""
    return "The equation of motion" if len(system.free) == 1 else "The equations of motion"


def _kinetic_coefficients(system) -> set:
    """The symbols of the kinetic friction coefficients of the contacts slipping at the state."""
    return {s for joint, _, _ in _slipping_contacts(system).values()
            for s in sp.sympify(joint.friction.kinetic).free_symbols}


def _structured_eom(system, c, e, q, keep, ref: str = "projected on the partial velocities") -> Equation:
    """M q'' + (rate terms) + (configuration terms) - (reaction terms in ``keep``) = Q for one coordinate
    (``e + q``: the equation with the generalized force ``q`` moved to the right)."""
    rates = [a * b for i, a in enumerate(system.qd) for b in system.qd[i:]]
    e = expanded(e + q)
    lhs, taken = [], []
    for x, label in [(x, "M") for x in system.qdd] + [(lam, "reaction term") for lam in keep]:
        coef = coefficient(e, x)
        if coef != 0:
            lhs.append(Term(tidy(coef) * x, f"{label} {x}"))
            taken.append(coef * x)  # (the coefficient as it is: its tidy form differs by sin**2 + cos**2 - 1)
    rest = expanded(e - sp.Add(*taken))
    for x in rates:
        coef = coefficient(rest, x)
        if coef != 0 and not coef.has(*system.qd):
            lhs.append(Term(tidy(coef) * x, f"rate terms {x}"))
            rest = expanded(rest - coef * x)
    mus = _kinetic_coefficients(system)
    friction = sp.Add(*[t for t in sp.Add.make_args(rest) if mus and t.has(*mus)])
    if friction != 0:  # the slipping friction -sign(v_slip) mu_k N with N substituted: not a configuration term
        lhs.append(Term(tidy(friction), f"friction terms (slipping: {slip_friction()})"))
        rest = expanded(rest - friction)
    if rest != 0:
        lhs.append(Term(tidy(rest), "configuration terms"))
    return Equation(tuple(lhs) or (Term(sp.Integer(0)),), (Term(tidy(q), "Q"),),
                    f"equation of motion in {c.name}", ref, tag=f"eom:{c.name}")


def _constrained_motion_step(system, f, expl, state) -> Step:
    """The equations of motion of a system with closure rows or a slipping contact.

    Constrained form: one projected equation per free coordinate (dependent ones included),
    M q'' + ... - C^T lambda = Q, with the closure multipliers lambda (the joints' reactions)
    kept, then each closure row at the acceleration level, C q'' = gamma. A slipping contact's
    normal force N, which does work through its friction, is taken from the body equation that
    holds it alone and substituted.
    """
    closure = [r.reaction.symbol for r in system.closure]
    projected = _projected(system, f)
    working = [r.symbol for r in system.reactions if r.symbol not in closure
               and any(not _zero(coefficient(e, r.symbol)) for e in projected)]
    eqs, text, known = [], [], {}
    slipping = _slipping_contacts(system)
    for r in working:
        unknown = set(working) | set(closure) | {x.symbol for x in system.reactions}  # a pin's too
        found = (_normal_force_from_newton(expl, slipping[str(r)], r, known, unknown) if str(r) in slipping
                 else None) or _reaction_from_body_equations(expl, r, known, unknown)
        if found is None:
            continue
        value, where = found
        known[r] = expanded(value)
        eqs.append(Equation((Term(r),), (Term(tidy(known[r])),), f"{r} from {where}",
                            tag=f"from_newton:{r}", name=str(r)))
        text.append(f"{r} does work through the slipping friction {slip_friction(r)}, so it stays in the projected "
                    f"equations; {where} holds it alone and gives it.")
    from .slip_reactions import settle_slipping_reactions

    known, eqs, text = settle_slipping_reactions(system, expl, state, projected, working, closure, known, eqs, text)
    keep = closure + [r for r in working if r not in known]
    Q = system.generalized_forces()
    for c, e, q in zip(system.free, projected, Q):
        eqs.append(_structured_eom(system, c, expanded(e.xreplace(known)), q, keep))
    for row in system.closure:
        acc = expanded(system.D(system.D(row.expr)))
        terms = [Term(tidy(coefficient(acc, x)) * x, f"C {x}") for x in system.qdd if coefficient(acc, x) != 0]
        rest = expanded(acc - sp.Add(*[coefficient(acc, x) * x for x in system.qdd]))
        if rest != 0:
            terms.append(Term(tidy(rest), "-gamma (rate terms)"))
        eqs.append(Equation(tuple(terms) or (Term(sp.Integer(0)),), (Term(sp.Integer(0)),),
                            f"closure of joint {row.joint.name} at the acceleration level (multiplier "
                            f"{row.reaction.name})", "d^2 Phi/dt^2 = 0", tag=f"closure:{row.reaction.name}"))
    if closure:
        text.append(
            "Constrained form M q'' + (rate terms) + (configuration terms) - C^T lambda = Q, C q'' = gamma: one "
            "equation per coordinate (the dependent ones too) with the closure multipliers lambda ("
            + ", ".join(map(str, closure)) + ", the joints' reactions) kept, then each closure row "
            "differentiated twice. Chosen over the equation in the independent coordinates alone because that "
            "needs the inverse of the closure Jacobian (expressions that grow fast and fail at a dead centre), "
            "and a driven mechanism has no independent coordinate at all; here every term stays small, each "
            "row is named by its joint, and lambda keep their meaning as reactions.")
    else:
        friction = " + (friction terms)" if _kinetic_coefficients(system) else ""
        text.append(f"{_eom_words(system)}: the workless reactions eliminated (projection on the partial "
                    f"velocities of each body's P), written as M q'' + (rate terms) + (configuration terms)"
                    f"{friction} = Q.")
    return Step("motion", "Equation of motion", text, eqs)


def _zero_parameters_set(system, eom: Equation) -> sp.Expr:
    """The residual of the equation of motion ``eom``, expanded, with the parameters that are zero
    in the scene set to zero: what the small-oscillation steps linearise (Eqs. 45-46)."""
    zero = {sp.Symbol(n, real=True): 0 for n, q in system.parameters.items() if q.magnitude == 0}
    return expanded(eom.residual.xreplace(zero))


def _small_motion_rules(system, e: sp.Expr) -> list[Equation]:
    """The rules that linearise the equation of motion about q = 0 (the paper's Eq. 45): each
    function of q by its first-order value (sin q ~ q, cos q ~ 1), then each rate term's
    state-dependent factor ~ 0 (of second order or higher). Tags ``approx:1``, ``approx:2`` ...
    ``e``: the equation's residual as :func:`_zero_parameters_set` gives it."""
    c = system.free[0]
    rules = []
    functions = sorted((f for f in e.atoms(sp.Function) if f.has(c.q) and not f.has(c.qd, c.qdd)),
                       key=lambda f: (type(f).__name__ != "sin", type(f).__name__ != "cos", sstr(f)))
    for f in functions:
        rules.append((f, f.xreplace({c.q: 0}) + derivative(f, c.q).xreplace({c.q: 0}) * c.q))
    for term in sp.Add.make_args(e):
        if term.has(c.qd):
            factor = term.as_independent(c.q, c.qd, as_Add=False)[1]
            if all(factor != r[0] for r in rules):
                rules.append((factor, sp.Integer(0)))
    return [Equation((Term(lhs),), (Term(rhs),), "small motion: exact to first order about the equilibrium",
                     tag=f"approx:{k}", approximate=True) for k, (lhs, rhs) in enumerate(rules, start=1)]


def _linearised(system, omega_n: Equation) -> Equation:
    """q'' + omega_n^2 q = 0: the linearised equation of motion divided by M(0)."""
    c = system.free[0]
    return Equation((Term(c.qdd), Term(omega_n.right**2 * c.q)), (Term(sp.Integer(0)),),
                    "linearised equation of motion (divided by M(0))", tag="linearised")


def _small_oscillations(system, e: sp.Expr) -> Equation | None:
    """omega_n of the equation of motion linearised about q = 0 when that is an equilibrium
    (Eq. 45-46 for Example 2); None otherwise (no equilibrium there, or not stable). ``e``: the
    equation's residual as :func:`_zero_parameters_set` gives it."""
    c = system.free[0]
    if e.has(system.t):
        return None
    at = {c.q: 0, c.qd: 0}
    rest = e.xreplace({c.qdd: 0})
    if not _zero(rest.xreplace(at)):
        return None
    mass = tidy(coefficient(e, c.qdd).xreplace(at))
    stiffness = tidy(derivative(rest, c.q).xreplace(at))
    values = {k: sp.Float(v) for k, v in system.si_values().items()}
    ratio = stiffness / mass
    try:
        positive = float(ratio.xreplace(values)) > 0
    except TypeError:
        return None
    if not positive:
        return None
    omega = sp.sqrt(ratio)
    return Equation((Term(omega),), (Term(omega),), f"natural frequency of small oscillations about {c.name} = 0",
                    "linearised equation of motion", tag="omega_n", name="omega_n")


NUMBER_DIGITS = 4


def _shown_number(x: float) -> sp.Expr:
    """``x`` to :data:`NUMBER_DIGITS` significant figures as a person writes it: an integer when
    the rounded value is one with at most that many digits (2, 0, 1235; never 2.0 or 0.0), else a
    Float of that precision (0.6732, 29.43, 1.235e+5)."""
    rounded = float(f"{x:.{NUMBER_DIGITS}g}")
    if math.isfinite(rounded) and rounded == int(rounded) and abs(rounded) < 10**NUMBER_DIGITS:
        return sp.Integer(int(rounded))
    return sp.Float(x, NUMBER_DIGITS)
"""Significant figures of the equations with the data entered (as the paper's Eq. 29)."""


def _numbers_step(system, f, expl, state) -> Step | None:
    """Each body's equations with the data and the state entered, in the scene's output units
    (the paper's Eq. 29): numeric linear equations in the unknowns, those with the fewest unknowns
    first (they can be solved first), the moment equation before Newton's within a body. A one-body,
    one-coordinate system is written in alpha when alpha = +-q''. None when there is no body step.
    Which unknowns an equation holds at the state is the decision of the step on the dropped unknowns
    and of the advisor (:func:`solver.explain.advisor.unknowns_in_equations`), so that they agree."""
    from .advisor import unknowns_in_equations
    unknowns = [(c.qdd, str(c.qdd), "rad/s**2" if c.kind == "angle" else "m/s**2") for c in system.free]
    unknowns += [(r.symbol, r.name, r.unit) for r in system.reactions]
    rename = _alpha_form(system)  # q'' = alpha / k
    per = {u: _per_si(system, unit)[0] for u, name, unit in unknowns}  # output units per SI unit
    rows, zeros = [], {}
    for section in expl.sections:
        if section.body is None:
            continue
        held = unknowns_in_equations(system, f, section.body, expl.points[section.body], state)
        for step_kind, tag, unit in (("euler", "euler", "N*m"), ("newton", "newton_x", "N"), ("newton", "newton_y", "N")):
            try:
                eq = section.step(step_kind).equation(tag)
            except KeyError:
                continue
            residual = sp.sympify(eq.residual)
            if tag == "euler":  # the collected form when there is one (Eq. 28), alpha as the body's
                collected = next((x for x in section.step(step_kind).equations if x.tag == "collected"), None)
                if collected is not None:
                    eq = collected
                    residual = sp.sympify(collected.residual).xreplace({ALPHA: system.alpha(section.body)})
                    unit = _collected_unit(system, collected)
            scale, row_unit = _per_si(system, unit)
            si_unit = unit
            coefficients, known = _numbers_at_state(system, residual, [u for u, _, _ in unknowns], state)
            terms = []
            for u, name, _ in unknowns:
                coef = float(coefficients[u]) * scale / per[u]
                if name in held[tag]:
                    shown, k = rename.get(u, (u, 1))
                    value = _shown_number(coef / k)
                    unit = abs(float(f"{coef / k:.{NUMBER_DIGITS}g}")) == 1.0  # written as R_A, not 1.000 R_A
                    terms.append(Term(sp.sign(value) * shown if unit else value * shown, str(shown)))
            rhs = -float(known) * scale
            bound = _known_bound(system, residual, [u for u, _, _ in unknowns], state) if known else None
            if bound is not None and abs(known) <= bound:  # 0 to round-off, as the solution's unknowns
                label = f"the known side of {section.body}: {eq.label}"
                zeros[label] = {"computed": {"value": -float(known), "unit": si_unit},
                                "error_bound": {"value": bound, "unit": si_unit}}
                rhs = 0.0
            rows.append((len(terms), Equation(tuple(terms) or (Term(sp.Integer(0)),),
                                              (Term(_shown_number(rhs), "known"),),
                                              f"{section.body}: {eq.label} [{row_unit}]", tag=f"numbers:{section.body}:{tag}")))
    if not rows:
        return None
    rows.sort(key=lambda r: r[0])  # stable: fewest unknowns first
    text = [f"The equations above with the data and the state entered, in the scene's output units, "
            f"{NUMBER_DIGITS} significant figures; those with the fewest unknowns first."]
    if system.closure:
        text.append("The closure rows of the joints (acceleration level) complete the system; they are not shown.")
    if zeros:
        from ..cli_common import round_off_zero_text

        text.append(round_off_zero_text(zeros, system.output_units) + ".")
    return Step("numbers", "The equations with the data entered", text, [e for _, e in rows])


def _known_bound(system, residual, unknowns: list, state) -> float | None:
    """The float64 error bound of an equation's known side at the state (SI), where it is the
    round-off of the side's scale: the walk of :func:`_numbers_at_state` in
    :data:`solver.tree_value.SIZED` gives the size of its terms, and
    :func:`solver.analyses.instant.round_off_bound` the bound. None where the walk does not go,
    or where the terms cancel beyond :data:`~solver.analyses.instant.SIGNIFICANT_ERROR` of their
    size with every rate 0 (omega**2 terms of 1e17 leaving 0.4 lost its digits, as `solve`'s
    digits lost: it is no 0)."""
    from ..analyses.instant import SIGNIFICANT_ERROR, round_off_bound
    from ..tree_value import SIZED, NotEvaluable, Sized, affine_value

    floats = _walk_state(system, state).floats
    sizes = []
    for rates in ({}, {qd: 0.0 for qd in system.qd}):  # at the state, then at rest
        point = {k: Sized.of(rates.get(k, v)) for k, v in floats.items()}
        try:
            sizes.append(affine_value(residual, point, unknowns, arithmetic=SIZED)[0].size)
        except (NotEvaluable, KeyError, TypeError, ValueError, ZeroDivisionError, OverflowError):
            return None
    bound = round_off_bound(sizes[0])
    return bound if math.isfinite(bound) and bound <= SIGNIFICANT_ERROR * sizes[1] else None


def _numbers_at_state(system, residual, unknowns: list, state) -> tuple[dict, float]:
    """({unknown: its coefficient}, the rest) of an equation's ``residual``, affine in the
    ``unknowns``, at the state in double precision by one walk of its tree
    (:func:`solver.tree_value.affine_value`, sharing the walks at the state: :func:`_walk_state`);
    where the walk does not go or gives no real number, by the residual with the state substituted
    and expanded (:func:`_numeric_row`)."""
    from ..tree_value import NotEvaluable

    try:
        values = _walk_state(system, state).affine(residual, unknowns)
    except (NotEvaluable, KeyError, TypeError, ValueError, ZeroDivisionError, OverflowError):
        values = None
    if values is None or any(v.imag != 0 for v in values):
        coefficients, known = _numeric_row(expanded(_at_state(system, residual, state)), unknowns)
        return {u: float(c) for u, c in coefficients.items()}, float(known)
    return {u: v.real for u, v in zip(unknowns, values[1:])}, values[0].real


def _numeric_row(row: sp.Expr, unknowns: list) -> tuple[dict, sp.Expr]:
    """({unknown: ``row.coeff(unknown)``}, ``row.xreplace({unknowns: 0})``) of an equation at the
    state, expanded: a sum of at most one number and one term ``c*u`` per unknown (a sum collects
    like terms and adds its numbers), read in one pass over its terms; the same sympy numbers as
    ``coeff`` and ``xreplace`` give, which pick these very terms. Any other shape goes to them."""
    coefficients, known, wanted = {u: sp.S.Zero for u in unknowns}, sp.S.Zero, set(unknowns)
    for term in sp.Add.make_args(row):
        if term.is_Number:
            known = term
            continue
        c, u = term.as_coeff_Mul()
        if u not in wanted or coefficients[u] != 0:
            return {u: coefficient(row, u) for u in unknowns}, row.xreplace({u: 0 for u in unknowns})
        coefficients[u] = c
    return coefficients, known


def _collected_unit(system, collected: Equation) -> str:
    """The unit of the collected moment equation: the moment's, N*m, divided by the units of the
    parameters it was divided by (Eq. 28 is Eq. 27 divided by l_b: N; divided by m L: m/s**2), in
    SI, spelled as the output units spell it (:data:`solver.output_units._OUTPUT_UNIT_RULES`)."""
    from ..output_units import si_unit_of
    from ..units import ureg

    divided = collected.label.split("divided by ", 1)
    unit = ureg.Unit("N*m")
    if len(divided) == 2:
        for token in divided[1].split(" and collected")[0].split():  # m, L, r**2 (sstr of p**k)
            name, _, power = token.partition("**")
            unit /= (1.0 * system.parameters[name]).units ** int(power or 1)
    return si_unit_of(unit)


def _per_si(system, unit: str) -> tuple[float, str]:
    """(value of one SI ``unit`` in the scene's output unit, that unit), remembered by the system
    (the equations with the data entered ask it for every unknown and row)."""
    from ..cli_common import to_output_units

    def build():
        entry = to_output_units({"value": 1.0, "unit": unit}, system.output_units)
        return float(entry["value"]), entry["unit"]
    return system._memo(("per_si", unit, tuple(sorted(system.output_units.items()))), build)


def _out(system, name: str, qty):
    """(value, unit) of a quantity in the scene's output units, as ``to_output_units`` of its
    ``quantity_entry`` gives them: the value times its unit's factor (:func:`_per_si`, the same
    product), the factor and the unit's text found once per unit (the solution and its check
    convert every unknown)."""
    from ..cli_common import quantity_entry
    from ..units import Q_

    def build():
        factor, unit = _per_si(system, quantity_entry(Q_(1.0, qty.units))["unit"])
        return factor, unit.replace(" / ", "/").replace(" ** ", "**").replace(" * ", "*")
    factor, unit = system._memo(("output_unit", qty.units, tuple(sorted(system.output_units.items()))), build)
    value = float(qty.magnitude)
    return (value if factor == 1.0 else value * factor), unit


def _condition_number(A) -> float | None:
    """The exact condition number of the equations' matrix ``A`` at the state, the one quantity
    ``precision`` prints (:func:`solver.analyses.instant.condition_numbers`: 1-norm, rows and columns
    equilibrated); None when ``A`` is not square."""
    from ..analyses.instant import condition_numbers

    if A.shape[0] != A.shape[1]:
        return None
    return float(condition_numbers(A[None])[0])


def _solution_step(system, solution, cond: float | None) -> Step:
    """The unknowns at the state; ``cond``: the exact condition number of the equations (:func:`_condition_number`)."""
    from ..cli_common import format_number

    rows = []
    for name, qty in solution.unknowns.items():
        value, unit = _out(system, name, qty)
        rows.append((name, format_number(value), unit))
    how = (f"condition number {cond:.3g}" if cond is not None and math.isfinite(cond) else
           "their matrix is singular, its condition number infinite: one admissible solution")
    text = [f"The {len(rows)} unknowns at the state, from the linear equations above ({how}), in the scene's "
            "output units."]
    if "digits_lost" in solution.extra:  # as `solve` warns of it
        from ..cli_common import digits_lost_text

        text.append("Warning: " + digits_lost_text(solution.extra["digits_lost"], system.output_units) + ".")
    if "zero_to_round_off" in solution.extra:  # as `solve` says it
        from ..cli_common import round_off_zero_text

        text.append(round_off_zero_text(solution.extra["zero_to_round_off"], system.output_units) + ".")
    return Step("solution", "Solution", text, table=Table(("unknown", "value", "unit"), tuple(rows)))


def _numeric_system(system, f, state):
    """(A, b) of a formulation at the state, A x = b: each equation's coefficients and rest by one
    walk of its tree (:func:`_numbers_at_state`; one state: cheaper than lambdify, and than the
    symbolic matrices ``linear_system`` builds to be evaluated after)."""
    import numpy as np

    unknowns = list(f.unknowns)
    rows = [_numbers_at_state(system, e.expr, unknowns, state) for e in f.equations]
    An = np.array([[coefficients[u] for u in unknowns] for coefficients, _ in rows], dtype=float)
    bn = np.array([-known for _, known in rows], dtype=float)
    return An, bn


def _solve_at_state(system, f, point, state, numeric, cond):
    """The InstantSolution at the state from the substituted system ``numeric`` (A, b) whose exact
    condition number is ``cond``, or None when that is not comfortably regular or ``b`` is not
    finite (then :func:`solve_instant` decides and names the singularity)."""
    import numpy as np

    from ..analyses.instant import CONDITION_LIMIT, InstantSolution
    from ..units import Q_

    if system.limits():  # a joint with a model limit: solve_instant checks it
        return None
    An, bn = numeric
    if cond is None or not np.isfinite(cond) or cond > CONDITION_LIMIT or not np.all(np.isfinite(bn)):
        return None
    x = dict(zip((str(u) for u in f.unknowns), np.linalg.solve(An, bn)))
    unknowns = {}
    if len(system.bodies) == 1:
        body = next(iter(system.bodies))
        al = sp.sympify(system.alpha(body)).xreplace({c.qdd: sp.Float(x[str(c.qdd)]) for c in system.free})
        unknowns["alpha"] = Q_(float(al.xreplace(_state_subs(system, state))), "rad/s**2")
    for c in system.free:
        unknowns[str(c.qdd)] = Q_(x[str(c.qdd)], "rad/s**2" if c.kind == "angle" else "m/s**2")
    for r in system.reactions:
        unknowns[r.name] = Q_(x[r.name], r.unit)
    shown = point if point is not None else ",".join(f"{b}:{p}" for b, p in f.points.items())
    return InstantSolution(unknowns, cond, shown, "generalized_euler", state, system.name)


def _mass_center_check(system, state) -> dict:
    """The unknowns by the mass-centre form (Eqs. 1-2), evaluated directly at the state (an
    evaluation path of its own: substitution and numpy's solve, no lambdify)."""
    import numpy as np

    from ..formulations import formulate
    from ..units import Q_

    f = formulate(system, "mass_center", None)
    subs = _state_subs(system, state)
    An, bn = _numeric_system(system, f, state)
    x = dict(zip((str(u) for u in f.unknowns), np.linalg.solve(An, bn)))
    out = {}
    if len(system.bodies) == 1:
        body = next(iter(system.bodies))
        al = sp.sympify(system.alpha(body)).xreplace({c.qdd: sp.Float(x[str(c.qdd)]) for c in system.free})
        out["alpha"] = Q_(float(al.xreplace(subs)), "rad/s**2")
    for c in system.free:
        out[str(c.qdd)] = Q_(x[str(c.qdd)], "rad/s**2" if c.kind == "angle" else "m/s**2")
    for r in system.reactions:
        out[r.name] = Q_(x[r.name], r.unit)
    return out


def _mass_center_in_regime(scene, found) -> dict:
    """The unknowns of a scene with contacts by the mass-centre form (Eqs. 1-2), in the contact regime
    the generalized Euler route found (``found``: (regime, warning, state) of
    :func:`solver.analyses.regimes.regime_at_state`).

    The check stays a route of its own: the mass-centre equations are solved in that regime and
    every condition of the regime (normal forces press, sticking friction in its cone, a slip
    sliding its way) is tested again on their numbers; only the search for the regime is not
    repeated. When a condition fails on them, the regime is indeterminate or none was found, the
    whole search is run by the mass-centre form (:func:`solver.analyses.instant.solve_instant`).
    The conditions are tested as the search tests its final regime (``strict_direction=False``:
    a slip at rest is the kinetic one after an impending slip, which the search solves so)."""
    from ..analyses.instant import solution_in_regime, solve_instant
    from ..analyses.regimes import solve_in_regime
    from ..errors import SceneError

    regime, _, state = found
    res = None
    if regime is not None and not regime.indeterminate:
        try:
            res = solve_in_regime(scene, regime.regimes, state.q, state.qd, state.t, None, "mass_center",
                                  strict_direction=False)
        except SceneError:  # (singular with every contact holding, or not describable: the search decides)
            res = None
    if res is None or isinstance(res, str):
        return solve_instant(scene, None, "mass_center", state).unknowns
    return solution_in_regime(scene, res, None, state, None, "mass_center").unknowns


def _check_step(system, solution, check) -> Step:
    from ..cli_common import format_pair

    rows = []
    worst = 0.0
    zeros = solution.extra.get("zero_to_round_off", {})
    for name, qty in solution.unknowns.items():
        v1, unit = _out(system, name, qty)
        v2, _ = _out(system, name, check[name])
        if name in zeros and abs(float(check[name].to(zeros[name]["error_bound"]["unit"]).magnitude)) \
                <= zeros[name]["error_bound"]["value"]:
            v2 = 0.0  # 0 to round-off by the solution's rule, as the solution gives it (round_off_zeros)
        scale = max(abs(v1), abs(v2), 1e-300)
        diff = abs(v1 - v2) / scale if (v1 or v2) else 0.0
        worst = max(worst, diff)
        rows.append((name, *format_pair(v1, v2), unit, f"{diff:.1e}"))
    text = ["The same unknowns by the mass-centre form (Eq. 1 with a_G, Eq. 2 about G for each body): "
            f"the largest relative difference is {worst:.1e}."]
    return Step("check", "Check by the mass-centre form", text,
                table=Table(("unknown", "about P", "about G", "unit", "rel. difference"), tuple(rows)))
