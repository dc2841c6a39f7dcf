"""Build the worked solution of a scene at its state (issue 11, ``python -m solver explain``).

For each body, in order (paper Eqs. 1, 6, 10-15):

1. the data with units;
2. the kinematics: the positions of the points used relative to P, then their
   velocities and accelerations by the rigid-body relation from P (Eqs. 6, 15);
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

import sympy as sp

from ..model.joints import cross_k, k_cross
from .content import Equation, Explanation, Section, Step, Table, Term
from ..display import is_identically_zero, tidy, tidy_linear

__all__ = ["explain", "latex_names"]


def latex_names(system) -> dict:
    """LaTeX names: dotted rates of the coordinates."""
    names = {}
    for c in system.coordinates:
        base = sp.latex(c.q)
        names[c.qd] = rf"\dot{{{base}}}"
        names[c.qdd] = rf"\ddot{{{base}}}"
    return names


def _vec(v) -> sp.Matrix:
    return sp.Matrix([tidy(v[0]), tidy(v[1])])


def _zero(expr) -> bool:
    expr = sp.expand(expr)
    if expr == 0:
        return True
    return bool(is_identically_zero(expr))


def _state_subs(system, state) -> dict:
    vals = dict(system.si_values())
    vals.update(zip(system.q, state.q))
    vals.update(zip(system.qd, state.qd))
    vals[system.t] = state.t
    return {k: sp.Float(v) for k, v in vals.items()}


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
                if not any(_zero(r[0] - q[0]) and _zero(r[1] - q[1]) for q in self.named.values()):
                    self.named[key] = r
        self.extra = 0

    def name_of(self, at) -> str:
        for name, r in self.named.items():
            d = r - at
            if _zero(d[0]) and _zero(d[1]):
                return name
        self.extra += 1
        name = f"X{self.extra}"
        self.named[name] = sp.Matrix(at)
        return name


# -- the forces on a body -----------------------------------------------------------------------


class _Force:
    """One force or couple on a body: applied (known) or a reaction (unknown magnitude)."""

    def __init__(self, name, kind, force, at, couple, reaction=None, point=""):
        self.name, self.kind = name, kind
        self.force = None if force is None else sp.Matrix(force)
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
    for jl in system.joint_loads():
        if jl.body != body:
            continue
        sym = jl.reaction.symbol
        force = None if jl.force is None else sym * jl.force
        point = points.name_of(jl.at) if jl.force is not None else ""
        out.append(_Force(jl.reaction.name, f"reaction of joint {jl.reaction.joint}", force, jl.at,
                          sym * jl.couple, reaction=jl.reaction, point=point))
    return out


def _moment(f: _Force, r_P) -> sp.Expr:
    m = f.couple
    if f.force is not None:
        m = m + cross_k(f.at - r_P, f.force)
    return m


# -- per body ------------------------------------------------------------------------------------


def _data_step(system, body: str) -> Step:
    b = system.bodies[body]
    rows = []
    for e in b.elements:
        rows.append((e.name, e.kind or type(e).__name__, sp.sstr(e.mass), sp.sstr(tidy(e.I_G))))
    text = [f"Body {body}: {len(b.elements)} element(s), total mass m = {sp.sstr(b.total_mass)}."]
    if len(b.elements) > 1:
        text.append("A composite body (Eqs. 11-14): each element keeps its own mass centre and centroidal inertia.")
    return Step("data", f"Data of {body}", text, table=Table(("element", "kind", "mass m_k", "I_G,k"), tuple(rows)))


def _kinematics_step(system, body: str, P: str, used: list[str], points: _Points) -> Step:
    w, al = system.omega(body), system.alpha(body)
    r_P = system.point_position(body, P)
    v_P, a_P = system.point_velocity(body, P), system.point_acceleration(body, P)
    eqs = [
        Equation((Term(w),), (Term(tidy(w)),), "angular velocity (k component)", tag="omega", name="omega"),
        Equation((Term(al),), (Term(tidy(al)),), "angular acceleration (k component)", tag="alpha", name="alpha"),
        Equation((Term(r_P),), (Term(_vec(r_P)),), f"position of {P}", tag=f"pos:{P}", name=f"r_{P}", vector=True),
        Equation((Term(v_P),), (Term(_vec(v_P)),), f"velocity of {P}, from the placement (the joints)",
                 "Eq. (6)", tag=f"vel:{P}", name=f"v_{P}", vector=True),
        Equation((Term(a_P),), (Term(_vec(a_P)),), f"acceleration of {P}, from the placement (the joints)",
                 "Eq. (15)", tag=f"accel:{P}", name=f"a_{P}", vector=True),
    ]
    for X in used:
        if X == P:
            continue
        r = points.named[X] - r_P
        wr, ar, cr = k_cross(w, r), k_cross(al, r), -w**2 * r
        eqs.append(Equation((Term(r),), (Term(_vec(r)),), f"position of {X} relative to {P}",
                            tag=f"rel:{X}", name=f"r_{X}/{P}", vector=True))
        eqs.append(Equation((Term(v_P + wr),), (Term(_vec(v_P), f"v_{P}"), Term(_vec(wr), f"omega x r_{X}/{P}")),
                            f"velocity of {X}", "Eq. (6)", tag=f"vel:{X}", name=f"v_{X}", vector=True))
        eqs.append(Equation((Term(a_P + ar + cr),),
                            (Term(_vec(a_P), f"a_{P}"), Term(_vec(ar), f"alpha x r_{X}/{P}"),
                             Term(_vec(cr), f"-omega^2 r_{X}/{P}")),
                            f"acceleration of {X}", "Eq. (15)", tag=f"accel:{X}", name=f"a_{X}", vector=True))
    text = [f"P = {P}. Its velocity and acceleration follow from the joints (the placement of {body}); "
            f"every other point's follow by the rigid-body relation from {P}: v = v_{P} + omega x r, "
            f"a = a_{P} + alpha x r - omega^2 r (Eqs. 6, 15)."]
    return Step("kinematics", f"Kinematics of {body} from {P}", text, eqs)


def _fbd_step(system, body: str, forces: list[_Force]) -> Step:
    rows = []
    for f in forces:
        what = "unknown (reaction)" if f.reaction is not None else "known (applied)"
        if f.force is not None:
            rows.append((f.name, f.kind, f.point, f"({sp.sstr(tidy(f.force[0]))}, {sp.sstr(tidy(f.force[1]))})", what))
        else:
            rows.append((f.name, f.kind, "-", f"couple {sp.sstr(tidy(f.couple))}", what))
    step = Step("fbd", f"Free-body diagram of {body}",
                [f"The forces and couples on {body}, fixed-frame components (x right, y up)."],
                table=Table(("force", "kind", "at", "components", ""), tuple(rows)))
    step.figure_request = {"scene": system.source or system.name, "body": body, "fbd": True}
    return step


def _element_accelerations(system, body: str, P: str):
    """(element, m_k, r_k/P, a_k) per element, a_k by Eq. 15 from P."""
    r_P = system.point_position(body, P)
    a_P = system.point_acceleration(body, P)
    w, al = system.omega(body), system.alpha(body)
    out = []
    for e in system.bodies[body].elements:
        r = system.body_point(body, e.mass_center) - r_P
        out.append((e, e.mass, r, a_P + k_cross(al, r) - w**2 * r))
    return out


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
        d = system.body_point(body, e.mass_center) - r_P
        terms.append(Term(tidy(e.I_G), f"I_G of {e.name}"))
        d2 = tidy(sp.expand(d[0] ** 2 + d[1] ** 2))
        if d2 != 0:
            terms.append(Term(tidy(e.mass * d2), f"m d^2 of {e.name}"))
    total = sp.Add(*[t.expr for t in terms])
    return Equation((Term(total),), tuple(terms), f"moment of inertia about {P}, per element (parallel axes)",
                    "Eq. (12)", tag="inertia", name=f"I_{P}")


def _euler_step(system, body: str, P: str, forces: list[_Force]) -> tuple[Step, list[_Force]]:
    r_P = system.point_position(body, P)
    a_P = system.point_acceleration(body, P)
    al = system.alpha(body)
    rates = system.qdd + [c.qd**2 for c in system.coordinates]
    lhs, dropped = [], []
    for f in forces:
        m = _moment(f, r_P)
        if _zero(m):
            dropped.append(f)
            continue
        lhs.append(Term(tidy(m), f"moment of {f.name} about {P}"))
    S = sum(((m_k * r) for _, m_k, r, _ in _element_accelerations(system, body, P)), sp.zeros(2, 1))
    inertial = -cross_k(S, a_P)
    if not _zero(inertial):
        lhs.append(Term(tidy_linear(inertial, rates), f"inertial term -r_G/{P} x m a_{P}"))
    inertia = _inertia_equation(system, body, P)
    I_P = tidy(inertia.left)
    euler = Equation(tuple(lhs) or (Term(sp.Integer(0)),), (Term(sp.Mul(I_P, al, evaluate=False), f"I_{P} alpha"),),
                     f"generalized Euler equation about {P}",
                     "Eq. (11)" if len(system.bodies[body].elements) > 1 else "Eq. (10)", tag="euler")
    text = [f"M_{P} - r_G/{P} x m a_{P} = I_{P} alpha: the moments of the actual forces about {P}, then the "
            f"inertial term, then I_{P} alpha with I_{P} from the parallel-axis theorem (Eq. 12)."]
    if _zero(inertial):
        text.append(f"The inertial term vanishes here: r_G/{P} x a_{P} = 0 ({P} is the mass centre, or a_{P} "
                    f"is parallel to r_G/{P} or zero).")
    return Step("euler", f"Generalized Euler equation of {body} about {P}", text, [inertia, euler]), dropped


def _unknowns_in(expr, unknowns) -> list:
    e = sp.expand(expr)
    return [u for u in unknowns if not _zero(e.coeff(u))]


def _dropped_step(system, body: str, P: str, forces, dropped, newton: Step, euler: Step) -> Step:
    unknowns = list(system.qdd) + [r.symbol for r in system.reactions]
    in_euler = _unknowns_in(euler.equation("euler").residual, unknowns)
    rows = []
    text = []
    for f in forces:
        if f.reaction is None:
            continue
        u = f.unknown
        cells = [f.name]
        for tag in ("newton_x", "newton_y"):
            cells.append("yes" if u in _unknowns_in(newton.equation(tag).residual, [u]) else "no")
        cells.append("yes" if u in in_euler else "no")
        if f in dropped:
            why = (f"its line of action passes through {P}" if f.force is not None and _zero(f.couple)
                   else f"its moment about {P} is zero")
        elif u not in in_euler:
            why = f"its moments about {P} cancel"
        else:
            why = ""
        cells.append(why)
        rows.append(tuple(cells))
        if why:
            text.append(f"{f.name} drops out of the moment equation: {why}.")
    names = ", ".join(str(u) for u in in_euler)
    text.insert(0, f"The moment equation about {P} contains {len(in_euler)} unknown(s): {names}.")
    return Step("dropped", f"Unknowns in the moment equation about {P}", text,
                table=Table(("reaction", "Newton x", "Newton y", f"Euler about {P}", "why not in Euler"), tuple(rows)))


def explain(system, point: str | None = None, *, advice: bool = True, solution: bool = True) -> Explanation:
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

    Returns
    -------
    Explanation

    Raises
    ------
    SceneError
        An unknown point; SingularConfigurationError at a singular state.
    """
    from ..analyses.instant import assemble, solve_instant
    from ..formulations import formulate

    f = formulate(system, "generalized_euler", point)
    state = assemble(system)
    expl = Explanation(f"Worked solution: {system.name}", system.name, dict(f.points),
                       symbol_latex=latex_names(system))
    expl.sections.append(_system_data_section(system, state))
    for body, P in f.points.items():
        expl.sections.append(_body_section(system, body, P))
    if not solution:
        return expl
    final = Section("Solution", None)
    if advice:
        from .advisor import advice_step

        final.steps.append(advice_step(system, state))
    motion = _motion_step(system, f, expl)
    if motion is not None:
        final.steps.append(motion)
    solution = _solve_at_state(system, f, point, state) or solve_instant(system, point, "generalized_euler", state)
    check = _mass_center_check(system, state)
    final.steps.append(_solution_step(system, solution))
    final.steps.append(_check_step(system, solution, check))
    expl.sections.append(final)
    return expl


def _body_section(system, body: str, P: str) -> Section:
    points = _Points(system, body)
    forces = _forces_on(system, body, points)
    b = system.bodies[body]
    used = [P] + (["G"] if "G" != P else [])
    if len(b.elements) > 1:
        used += [f"G_{e.name}" for e in b.elements if f"G_{e.name}" in points.named]
    for f in forces:
        if f.force is not None and f.point not in used:
            used.append(f.point)
    section = Section(f"Body {body}", body)
    section.steps.append(_data_step(system, body))
    section.steps.append(_kinematics_step(system, body, P, used, points))
    section.steps.append(_fbd_step(system, body, forces))
    newton = _newton_step(system, body, P, forces)
    section.steps.append(newton)
    euler, dropped = _euler_step(system, body, P, forces)
    section.steps.append(euler)
    section.steps.append(_dropped_step(system, body, P, forces, dropped, newton, euler))
    return section


# -- the whole system ----------------------------------------------------------------------------


def _system_data_section(system, state) -> Section:
    rows = tuple((name, f"{q:~}" if hasattr(q, "units") else str(q)) for name, q in system.parameters.items())
    coords = []
    for c, v, r in zip(system.free, state.q, state.qd):
        if c.kind == "angle":
            coords.append((c.name, f"{math.degrees(v):.6g} deg", f"{r:.6g} rad/s"))
        else:
            coords.append((c.name, f"{v:.6g} m", f"{r:.6g} m/s"))
    step = Step("data", "Data and state", [system.description] if system.description else [],
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
    left = [r for r in reactions if not _zero(sp.expand(euler).coeff(r))]
    subs, used = {}, []
    for r in left:
        for axis in ("Newton x", "Newton y"):
            e = sp.expand(eqs[axis])
            others = [x for x in reactions if x != r and not _zero(e.coeff(x))]
            if not others and not _zero(e.coeff(r)) and axis not in used:
                subs[r] = -e.xreplace({r: 0}) / e.coeff(r)  # linear in r
                used.append(axis)
                break
        else:
            return None
    return euler, subs, used


def _motion_step(system, f, expl) -> Step | None:
    """The equation of motion from its structure: M q'' + (rate terms) + (rest) = Q."""
    if system.closure or not system.independent:
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
            eliminated = sp.expand(euler.xreplace(subs))
            eqs.append(Equation((Term(tidy_linear(eliminated, qdd + rates)),), (Term(sp.Integer(0)),),
                                f"moment equation with {', '.join(map(str, subs))} substituted", tag="eliminated"))
            text.append(f"The moment equation about {f.points[body]} still holds "
                        f"{', '.join(map(str, subs))}; {', '.join(used)} give(s) it without other reactions.")
    Q = system.generalized_forces()
    for c, e, q in zip(system.free, equations_of_motion(f), Q):
        e = sp.expand(e + q)  # M q'' + ... (the generalized force moved to the right)
        lhs = []
        for x in qdd:
            coef = e.coeff(x)
            if coef != 0:
                lhs.append(Term(tidy(coef) * x, f"M {x}"))
        rest = sp.expand(e - sp.Add(*[t.expr for t in lhs]))
        for x in rates:
            coef = rest.coeff(x)
            if coef != 0 and not coef.has(*system.qd):
                lhs.append(Term(tidy(coef) * x, f"rate terms {x}"))
                rest = sp.expand(rest - coef * x)
        if rest != 0:
            lhs.append(Term(tidy(rest), "configuration terms"))
        eqs.append(Equation(tuple(lhs), (Term(tidy(q), "Q"),), f"equation of motion in {c.name}",
                            "reactions eliminated", tag=f"eom:{c.name}"))
    small = _small_oscillations(system, eqs[-1]) if len(system.free) == 1 else None
    if small is not None:
        eqs.append(small)
        text.append(f"Small oscillations about {system.free[0].name} = 0 (an equilibrium with the scene's "
                    "parameters, those that are zero set to zero): the equation of motion linearised, "
                    "M(0) q'' + K q = 0, oscillates at omega_n = sqrt(K / M(0)).")
    text.append("Equation(s) of motion: the reactions eliminated (projection on the partial velocities of "
                "each body's P), written as M q'' + (rate terms) + (configuration terms) = Q, with Q the "
                "generalized force of the non-conservative loads.")
    return Step("motion", "Equation of motion", text, eqs)


def _small_oscillations(system, eom: Equation) -> Equation | None:
    """omega_n of the equation of motion linearised about q = 0 when that is an equilibrium
    (Eq. 45-46 for Example 2); None otherwise (no equilibrium there, or not stable)."""
    c = system.free[0]
    zero = {sp.Symbol(n, real=True): 0 for n, q in system.parameters.items() if q.magnitude == 0}
    e = sp.expand(eom.residual.xreplace(zero))
    if e.has(system.t):
        return None
    at = {c.q: 0, c.qd: 0}
    rest = e.xreplace({c.qdd: 0})
    if not _zero(rest.xreplace(at)):
        return None
    mass = tidy(e.coeff(c.qdd).xreplace(at))
    stiffness = tidy(sp.diff(rest, c.q).xreplace(at))
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


def _out(system, name: str, qty):
    from ..cli_common import quantity_entry, to_output_units

    entry = to_output_units(quantity_entry(qty), system.output_units)
    return entry["value"], entry["unit"].replace(" / ", "/").replace(" ** ", "**").replace(" * ", "*")


def _solution_step(system, solution) -> Step:
    rows = []
    for name, qty in solution.unknowns.items():
        value, unit = _out(system, name, qty)
        rows.append((name, f"{value:.6g}", unit))
    text = [f"The {len(rows)} unknowns at the state, from the linear equations above "
            f"(condition number {solution.condition_number:.3g}), in the scene's output units."]
    return Step("solution", "Solution", text, table=Table(("unknown", "value", "unit"), tuple(rows)))


def _numeric_system(system, f, state):
    """(A, b) of a formulation evaluated at the state by substitution (one state: cheaper than lambdify)."""
    import numpy as np

    A, b = f.linear_system()
    subs = _state_subs(system, state)
    An = np.array([[float(x.xreplace(subs)) for x in A.row(i)] for i in range(A.shape[0])])
    bn = np.array([float(x.xreplace(subs)) for x in b])
    return An, bn


def _solve_at_state(system, f, point, state):
    """The InstantSolution at the state from the substituted system, or None when its condition
    number is not comfortably regular (then :func:`solve_instant` decides and names the singularity)."""
    import numpy as np

    from ..analyses.instant import CONDITION_LIMIT, InstantSolution, condition_numbers
    from ..units import Q_

    if system.limits():  # a joint with a model limit: solve_instant checks it
        return None
    An, bn = _numeric_system(system, f, state)
    if An.shape[0] != An.shape[1]:
        return None
    cond = float(condition_numbers(An[None])[0])
    if not np.isfinite(cond) or cond > CONDITION_LIMIT:
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


def _check_step(system, solution, check) -> Step:
    rows = []
    worst = 0.0
    for name, qty in solution.unknowns.items():
        v1, unit = _out(system, name, qty)
        v2, _ = _out(system, name, check[name])
        scale = max(abs(v1), abs(v2), 1e-300)
        diff = abs(v1 - v2) / scale if (v1 or v2) else 0.0
        worst = max(worst, diff)
        rows.append((name, f"{v1:.6g}", f"{v2:.6g}", unit, f"{diff:.1e}"))
    text = ["The same unknowns by the mass-centre form (Eq. 1 with a_G, Eq. 2 about G for each body): "
            f"the largest relative difference is {worst:.1e}."]
    return Step("check", "Check by the mass-centre form", text,
                table=Table(("unknown", "about P", "about G", "unit", "rel. difference"), tuple(rows)))
