"""The derived content of the reproducible paper: method, both examples step by step.

Everything returned here is computed: equations come from the solver's
derivation (as sympy expressions, rendered by :mod:`reports.mathml`), numbers
from its numeric solution. The templates only arrange them.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import re

import sympy as sp

from reports.mathml import equation_latex, equation_mathml, name_text, to_latex, to_mathml
from solver.display import expanded
from solver.model.system import derivative

__all__ = ["Shown", "shown", "method_equations", "method_prose", "example_steps", "STEP_PARTS", "quantity_text", "linearisation",
           "unit_conversion", "result_rows"]


@dataclass
class Shown:
    """An equation ready for both outputs (and as plain text, :attr:`text`, made when asked: no
    output shows it, and sympy's printer is not free)."""

    mathml: str
    latex: str
    sides: tuple = field(repr=False)
    """The left and the right side, each a sympy expression or its text."""
    label: str = ""
    ref: str = ""
    number: str = ""
    """The article's equation number the display carries in both renderings ("" for none)."""

    @property
    def text(self) -> str:
        """``lhs = rhs`` in sympy's plain text."""
        return " = ".join(side if isinstance(side, str) else sp.sstr(side) for side in self.sides)


def shown(lhs, rhs, label: str = "", ref: str = "", number: str = "") -> Shown:
    """Render ``lhs = rhs`` as MathML (block) and LaTeX."""
    return Shown(
        mathml=equation_mathml(lhs, rhs),
        latex=equation_latex(lhs, rhs),
        sides=(lhs, rhs),
        label=label,
        ref=ref,
        number=number,
    )


def inline(expr) -> dict:
    """An expression for inline use in both outputs (``mathml``, ``latex``)."""
    return {"mathml": to_mathml(expr), "latex": to_latex(expr)}


def quantity_text(q, digits: int = 4, keep_zeros: bool = False) -> str:
    """``"1.234 rad/s²"``-style text of a pint quantity (significant figures); with ``keep_zeros``
    the trailing zeros stay, so a column of results shows each to the same precision (725.0 next to
    897.1, not 725)."""
    return f"{q.magnitude:{'#' if keep_zeros else ''}.{digits}g} {q.units:~P}".strip()


def _upright(expr: sp.Expr) -> sp.Expr:
    """A fraction shown with its denominator's sign pulled out (``a/(-b)`` as ``-a/b``)."""
    num, den = sp.fraction(expr)
    if den != 1 and den.could_extract_minus_sign():
        return sp.Mul(-num, sp.Pow(sp.expand(-den), -1))
    return expr


def _shown_tidy(expr: sp.Expr) -> sp.Expr:
    """Display form from structure (:func:`solver.display.tidy`: sin**2 + cos**2 = 1 reductions,
    common factors out), never a generic ``simplify``."""
    from solver.display import tidy

    return _upright(tidy(expanded(expr)))


def _grouped(expr: sp.Expr, keys) -> sp.Expr:
    """Display form: collected by ``keys`` (unknowns, rates), each coefficient tidied on its own
    (:func:`solver.display.tidy_linear`)."""
    from solver.display import tidy_linear

    return tidy_linear(expr, list(keys))


def method_equations() -> dict[str, Shown]:
    """Eq. 10 (single body), Eq. 11 (composite body) and Eq. 14 in planar scalar form, derived by sympy.

    The k-component of r x (m a_P) is computed from the cross product of
    planar vectors, so the displayed forms are produced, not typed.
    """
    x, y, ax, ay, m, M_P, I_P, alpha = sp.symbols("x_G/P y_G/P a_Px a_Py m M_P I_P alpha", real=True)
    r = sp.Matrix([x, y, 0])
    a = sp.Matrix([ax, ay, 0])
    inertial = (r.cross(m * a))[2]
    eq10 = shown(M_P - inertial, I_P * alpha, "Moments about an embedded point P", "Eq. (10)", "10")
    k, n = sp.symbols("k n", integer=True, positive=True)
    mk, xk, yk, Ik = (sp.IndexedBase(s) for s in ("m", "x", "y", "I_P"))
    rk = sp.Matrix([xk[k], yk[k], 0])
    term = (rk.cross(mk[k] * a))[2]
    eq11 = shown(M_P - sp.Sum(term, (k, 1, n)), sp.Sum(Ik[k], (k, 1, n)) * alpha,
                 "Composite body of n elements", "Eq. (11)", "11")
    eq1 = shown(sp.Symbol("F_x"), sp.Sum(mk[k] * sp.Indexed(sp.IndexedBase("a_x"), k), (k, 1, n)),
                "Newton's law for the composite body, x component", "Eq. (14)", "14")
    eq1y = shown(sp.Symbol("F_y"), sp.Sum(mk[k] * sp.Indexed(sp.IndexedBase("a_y"), k), (k, 1, n)),
                 "Newton's law for the composite body, y component", "Eq. (14)", "14")
    return {"eq10": eq10, "eq11": eq11, "eq14": eq1, "eq14y": eq1y}


def rich_text(template: str, maths: dict) -> list[tuple[str, dict | None]]:
    """A sentence with inline maths for both renderings: ``{name}`` in ``template`` is the expression
    ``maths[name]``. Returns (text, None) and ("", :func:`inline`) parts in order; the templates escape
    the text and insert each expression's MathML or LaTeX."""
    parts = []
    for i, piece in enumerate(re.split(r"\{(\w+)\}", template)):
        parts.append(("", inline(maths[piece])) if i % 2 else (piece, None))
    return [p for p in parts if p != ("", None)]


def method_prose() -> dict[str, list]:
    """The sentences around Eqs. 10, 11 and 14 (section 1 of the paper), one content for paper.html and
    paper.tex (:func:`rich_text` parts), every symbol the displays of :func:`method_equations` use."""
    P, m, aP, rGP, MP, IP, n, k = sp.symbols("P m a_P r_G/P M_P I_P n k", real=True)
    mk, xk, yk, Ik = (sp.IndexedBase(s) for s in ("m", "x", "y", "I_P"))
    ax, ay = sp.IndexedBase("a_x"), sp.IndexedBase("a_y")
    maths = {"P": P, "m": m, "a_P": aP, "r_GP": rGP, "x_GP": sp.Symbol("x_G/P", real=True),
             "y_GP": sp.Symbol("y_G/P", real=True), "M_P": MP, "I_P": IP, "n": n, "k": k, "alpha": sp.Symbol("alpha"),
             "m_k": mk[k], "x_k": xk[k], "y_k": yk[k], "I_Pk": Ik[k], "ax_k": ax[k], "ay_k": ay[k]}
    texts = {
        "idea": "For a rigid body moving in a plane, the rotational equation is usually written about the mass "
                "centre or about a fixed pivot. Both are special cases of one relation that holds about any "
                "point {P} of the body, provided one more moment is counted: that of the inertial force "
                "\u2212{m} {a_P} applied at the mass centre, the whole mass {m} times the acceleration of {P}, "
                "reversed in direction. The planar cross product of the mass centre's offset {r_GP} from {P} (components "
                "{x_GP}, {y_GP}) with "
                "{m} {a_P} gives the scalar form, in which {alpha} is the k-component of the body's angular "
                "acceleration (each example writes it in terms of its own coordinate in its kinematics):",
        "terms": "Here {M_P} is the moment of the external forces about {P} and {I_P} the moment of inertia about "
                 "{P}. When {P} is the mass centre the extra term vanishes because the offset is zero; when {P} is "
                 "fixed it vanishes because its acceleration is zero. For a body built from {n} rigid elements, "
                 "applying the relation to each element and adding gives the composite form, in which only the "
                 "element masses and their own mass centres appear, so the overall mass centre never has to be "
                 "located. In it {m_k} is the mass of element {k}, {x_k} and {y_k} the components of the offset "
                 "of its mass centre from {P}, and {I_Pk} its moment of inertia about {P} (Eq. 12):",
        "newton": "Newton's law completes the system. For the composite body the resultant external force is the "
                  "sum of the element masses times the accelerations of their mass centres, whose components are "
                  "{ax_k} and {ay_k}:",
    }
    return {key: rich_text(text, maths) for key, text in texts.items()}


def linearisation(deriv, about: dict, assume: dict | None = None):
    """(mass M0, stiffness K, omega_n^2 = K/M0) of the derived eom about a state."""
    from solver.display import tidy

    eom = deriv.eom.subs(assume or {})
    q, qd, qdd = deriv.q, deriv.qd, deriv.qdd
    at = {q: about.get(q, 0), qd: about.get(qd, 0)}
    mass = tidy(derivative(eom, qdd).subs(at))
    stiffness = tidy(derivative(eom, q).subs(qdd, 0).subs(at))
    return mass, stiffness, _upright(tidy(stiffness / mass))


STEP_PARTS = ("accelerations", "omega", "alpha", "inertia", "eom", "qdd_solution", "alpha_solution", "reactions")
""":func:`example_steps`' steps, in order."""


def example_steps(scene, deriv, at_rest: bool, parts=STEP_PARTS) -> dict:
    """The derivation of one example, step by step, for the paper.

    Parameters
    ----------
    scene : solver.scene.Scene
    deriv : solver.derivation.Derivation
        About the paper's reference point.
    at_rest : bool
        Show the equations at theta_dot = 0 (Example 1 is released from rest).
    parts : iterable of str
        The steps wanted (names of :data:`STEP_PARTS`; default all): each is tidied and rendered
        for both outputs, so a step the paper does not show is not built.

    Returns
    -------
    dict
        Of the steps wanted: ``accelerations`` (x, y of every named point), ``omega``, ``alpha``,
        ``inertia``, ``eom``, ``qdd_solution``, ``alpha_solution`` and ``reactions`` (from the
        Newton rows, theta_ddot kept).

    Raises
    ------
    ValueError
        A name in ``parts`` that is not a step.

    Notes
    -----
    Every form is built from the structure of the derivation: the equation of motion as
    M qdd + f = Q, theta_ddot = -f / M, the reactions by eliminating the linear Newton rows,
    each coefficient tidied by :mod:`solver.display` (reduction modulo sin**2 + cos**2 = 1,
    common factors out), never by a generic ``simplify``.
    """
    want = set(parts)
    unknown = sorted(want - set(STEP_PARTS))
    if unknown:
        raise ValueError(f"`parts` must name steps of {', '.join(STEP_PARTS)}, got {', '.join(unknown)}")
    qd = deriv.qd
    rest = {qd: 0} if at_rest else {}
    steps = {}
    if "accelerations" in want:  # kinematics of every named point (the rigid-body relation, tidied from its structure)
        points = {}
        for name in scene.points:
            acc = deriv.acceleration(name).xreplace(rest)
            points[name] = {"x": inline(_shown_tidy(acc[0])), "y": inline(_shown_tidy(acc[1]))}
        steps["accelerations"] = points
    if "omega" in want:
        steps["omega"] = inline(deriv.omega)
    if "alpha" in want:
        # opposite: alpha is -theta_ddot (the coordinate turns clockwise), so their numbers differ in sign
        steps["alpha"] = {**inline(deriv.alpha), "opposite": sp.expand(deriv.alpha + deriv.qdd) == 0}
    if "inertia" in want:
        inertia = expanded(deriv.inertia_about(deriv.point))
        steps["inertia"] = inline(inertia if not inertia.has(sp.sin, sp.cos) else _shown_tidy(inertia))
    if want & {"eom", "qdd_solution", "alpha_solution"}:
        steps.update(_motion_steps(deriv, rest, want))
    if "reactions" in want:
        steps["reactions"] = _reaction_steps(scene, deriv, rest)
    return steps


def _motion_steps(deriv, rest: dict, want: set) -> dict:
    """The steps of :func:`example_steps` from the equation of motion: ``eom``, ``qdd_solution``,
    ``alpha_solution`` (those in ``want``)."""
    qd, qdd = deriv.qd, deriv.qdd
    out = {}
    # equation of motion M qdd + f = Q, from the derivation's (already structured) form
    eom = expanded(deriv.eom.xreplace(rest))
    if "eom" in want:
        Q = deriv.generalized_force.xreplace(rest)
        out["eom"] = shown(_grouped(eom + Q, [qdd, qd**2]), _shown_tidy(Q), "Equation of motion", "")
    # closed-form theta_ddot = -f / M and alpha (affine in theta_ddot: a1 qdd + a0 = (a0 M - a1 f) / M)
    mass = eom.coeff(qdd)
    rest_terms = expanded(eom - mass * qdd)
    if "qdd_solution" in want:
        out["qdd_solution"] = shown(qdd, _shown_tidy(-rest_terms / mass), "Angular acceleration", "")
    if "alpha_solution" in want:
        alpha = sp.expand(deriv.alpha)
        a1 = alpha.coeff(qdd)
        a0 = sp.expand(alpha - a1 * qdd)
        out["alpha_solution"] = shown(sp.Symbol("alpha"), _shown_tidy((a0 * mass - a1 * rest_terms) / mass),
                                      "alpha", "")
    return out


def _reaction_steps(scene, deriv, rest: dict) -> list:
    """The ``reactions`` step of :func:`example_steps`: each reaction from the Newton rows."""
    qd, qdd = deriv.qd, deriv.qdd
    # reactions from the Newton components, theta_ddot left symbolic (cf. Eqs. 24-25, 39-40): a linear
    # system in the reactions, solved by elimination
    symbols = [sp.Symbol(r, real=True) for r in scene.reaction_names()]
    newton = [expanded(e.expr.xreplace(rest)) for e in deriv.equations if "Newton" in e.name]
    reactions = []
    A, b = sp.linear_eq_to_matrix(newton, symbols)
    if A.shape[0] == A.shape[1] and A.det() != 0:
        for s, value in zip(symbols, A.LUsolve(b)):
            reactions.append(shown(s, _grouped(value, [qdd, qd**2]), f"Reaction {s}", ""))
    return reactions


def degrees(x: float) -> float:
    return math.degrees(x)


@dataclass
class Example:
    """Everything the paper says about one example."""

    key: str
    scene: object
    point: str
    parameters: list[dict] = field(default_factory=list)
    steps: dict = field(default_factory=dict)
    results: list[dict] = field(default_factory=list)
    extra: dict = field(default_factory=dict)


def parameter_rows(scene) -> list[dict]:
    """The scene's parameters and state as rows (name as math, value with unit)."""
    rows = []
    for name, q in scene.parameters.items():
        rows.append({"name": inline(sp.Symbol(name, real=True)), "value": f"{q:~P}"})
    for name, q in scene.state.items():
        rows.append({"name": inline(sp.Symbol(name, real=True)), "value": f"{q:~P}"})
    return rows


def unit_conversion(scene) -> dict | None:
    """How a force in the scene's own consistent units becomes its output force unit (g_c).

    With the mass in lbm and g in ft/s^2, m g comes out in lbm*ft/s^2; the output unit lbf is
    that divided by g_c = 32.174 (lbm*ft/s^2)/lbf. The factor is pint's, never typed.

    Returns
    -------
    dict or None
        ``consistent`` (the pint unit of mass times gravity), ``force`` (the output unit),
        ``factor`` (g_c, consistent units per output unit) and ``sentence`` (the words shared by
        paper.html and paper.tex); None when the scene names no output force unit, has no mass or
        gravity parameter, or needs no conversion (SI: kg*m/s^2 is N).
    """
    from solver.units import ureg

    force = scene.output_units.get("force")
    gravity = next((load for load in getattr(scene, "loads", ()) if load.kind == "gravity"), None)
    mass = next((q for q in scene.parameters.values() if q.check("[mass]")), None)
    g = scene.parameters.get(str(gravity.magnitude)) if gravity is not None else None
    if force is None or mass is None or g is None or not g.check("[acceleration]"):
        return None
    consistent = mass.units * g.units
    factor = float(ureg.Quantity(1, force).to(consistent).magnitude)
    if math.isclose(factor, 1.0, rel_tol=1e-12):
        return None
    c_text, f_text = f"{consistent:~P}", f"{ureg.Unit(force):~P}"
    g_value = float(g.to(ureg.Unit(force) / mass.units).magnitude)  # the article's g_c: its g, as a number
    sentence = (f"The equations above hold in any consistent set of units. With the mass in {mass.units:~P} and "
                f"g in {g.units:~P}, a force comes out in {c_text}; it is given in {f_text} by dividing by "
                f"g_c = {factor:.7g} ({c_text})/{f_text}, the exact definition (1 {f_text} is the weight of 1 "
                f"{mass.units:~P} under standard gravity). The article divides by its g instead, "
                f"{g_value * factor:.7g}; the two differ by {abs(factor / (g_value * factor) - 1):.2g} in relative "
                f"terms, far below the precision of its results. The table shows each force both ways.")
    return {"consistent": consistent, "force": force, "factor": factor, "sentence": sentence,
            "consistent_text": c_text}


def result_rows(solution, scene, conversion: dict | None = None) -> list[dict]:
    """The solver's unknowns at the scene's state as table rows (name as math, value with unit).

    Forces are shown in the scene's output force unit when it names one; with ``conversion``
    (:func:`unit_conversion`) a force also carries ``consistent``, its value before dividing by g_c.
    """
    force_unit = scene.output_units.get("force")
    rows = []
    for name, q in solution.unknowns.items():
        is_force = q.check("[force]")
        shown_q = q.to(force_unit) if is_force and force_unit else q
        before = quantity_text(q.to(conversion["consistent"]), keep_zeros=True) if is_force and conversion else ""
        rows.append({"name": inline(sp.Symbol(name, real=True)), "value": quantity_text(shown_q, keep_zeros=True),
                     "consistent": before, "text": name})
    return rows


def friction_peak(one_dof, least, rtol: float = 1e-9) -> dict:
    """Where the friction ratio |F_f|/F_n of a free swing peaks, for the paper's sentence.

    Parameters
    ----------
    one_dof : solver.period.OneDofSystem
        The model :func:`solver.friction.least_friction` ran on.
    least : solver.friction.FrictionResult
        Its result.
    rtol : float
        Relative agreement with the peak for a turning point to count as one (the ratio there is
        evaluated in closed form, at zero rate, to rounding error).

    Returns
    -------
    dict
        ``mu_min``, ``lifts_off``, ``angles_deg`` (the turning points where the ratio reaches the peak,
        or the one angle of the peak when it lies inside the swing) and ``sentence`` (one text for
        paper.html and paper.tex).
    """
    import numpy as np

    pair = one_dof.friction_pairs[0]
    reactions = one_dof.reactions_fn()
    at_turn = []
    for q in least.turning_points:  # at rest there: theta_dot = 0
        r = reactions(np.array([q]), np.array([0.0]), 0.0)
        ratio = abs(float(r[pair.friction][0])) / float(r[pair.normal][0])
        if math.isclose(ratio, least.mu_min, rel_tol=rtol):
            at_turn.append(math.degrees(q))
    angles = at_turn or [math.degrees(least.theta_at_max)]
    if len(at_turn) == 2 and math.isclose(at_turn[0], -at_turn[1], rel_tol=rtol):
        where = f"equally at both turning points, \u00b1{abs(at_turn[0]):.3g} deg"
    elif at_turn:
        where = "at the turning point" + ("s " if len(at_turn) > 1 else " ") + ", ".join(f"{a:.3g}" for a in at_turn) + " deg"
    else:
        where = f"at an angle of {angles[0]:.3g} deg"
    sentence = ("The analysis assumes the disk rolls without slipping. Over that same swing the friction force "
                f"needed, divided by the normal force, peaks at {least.mu_min:.3g} ({where})"
                + (", and the disk would leave the floor" if least.lifts_off else "")
                + ": a floor with a smaller coefficient of friction would let the disk slip, and the equations "
                "above would no longer apply.")
    return {"mu_min": least.mu_min, "lifts_off": least.lifts_off, "angles_deg": angles, "sentence": sentence}


# -- worked steps from solver.explain (one source for paper.html and paper.tex) ------------------------

def unreachable_cells(findings, respondents: int) -> str:
    """The sentence under the survey table naming the published cells no whole count gives (the
    table shows the rebuilt counts' percentages, so those cells differ from the published ones):
    empty when there are none. One text for both renderings."""
    cells = [r for r in findings if r.kind == "table-cell"]
    if not cells:
        return ""
    listed = "; ".join(f"{r.label.removeprefix('Table 1, ')} printed {r.published_text or r.published} %, "
                       f"shown {r.computed} %" for r in cells)
    verb = "prints" if len(cells) == 1 else "print"
    return (f"{_count(cells, 'cell')} of the published table {verb} a percentage that no whole count out of "
            f"{respondents} gives; the table shows the percentage of the nearest count: {listed} "
            f"(section 5 says why).")


def survey_table(survey) -> dict:
    """The survey table and the statements under it, one content for paper.html and paper.tex.

    Returns
    -------
    dict
        ``header``: the column titles; ``rows``: per item its cells as text (item id, per scale
        label "count (percent%)", n, agreement, 95 % interval); ``statements``: per item its id and
        its wording as printed on the survey (a quotation, copied verbatim from the paper).
    """
    from analysis.rounding import share_percent_text

    facts = survey.facts
    header = ["item", *facts.labels, "n", "agree", "95% interval"]
    rows = []
    for item_id, it in zip(facts.item_ids, survey.summary.items):
        shown = it.printed_percent(1)
        rows.append([item_id, *(f"{it.counts[label]} ({shown[label]}%)" for label in facts.labels), str(it.n),
                     f"{it.agree.percent_text(1)}%",
                     f"{share_percent_text(it.agree.ci[0], 1)}\u2013{share_percent_text(it.agree.ci[1], 1)}%"])
    return {"header": header, "rows": rows,
            "statements": [{"id": i, "text": t} for i, t in zip(facts.item_ids, facts.item_texts)]}


def claim_readings(survey, path=None) -> dict:
    """The other reading of a claim that ``[[readings]]`` of data/published/survey.toml names: its share
    taken among the respondents of another claim's group, bounded by the marginals alone (which answers
    go together is unknown). By inclusion-exclusion, of the g in the group at least k - (n - g) and at most
    min(k, g) are among the k of the claim.

    Returns
    -------
    dict
        Claim id -> the sentence (one text for report.html, paper.html and paper.tex).

    Raises
    ------
    ReportInputError
        A reading naming a claim that is not evaluated, or missing a key (file and place named).
    """
    from fractions import Fraction

    from analysis.rounding import share_percent_text
    from analysis.tables import published_dir
    from reports.published import ReportInputError, read_toml

    path = path or published_dir() / "survey.toml"
    by_id = {r.claim.id: r for r in survey.claims.results}
    words = {">": "over", ">=": "at least", "<": "under", "<=": "at most"}
    out = {}
    for i, reading in enumerate(read_toml(path).get("readings", [])):
        where = f"{path}: readings[{i}]"
        for key in ("claim", "group", "printed"):
            if key not in reading:
                raise ReportInputError(f"{where}: key '{key}' is missing")
        for key in ("claim", "group"):
            if reading[key] not in by_id:
                raise ReportInputError(f"{where}.{key}: no evaluated claim {reading[key]!r}; "
                                       f"claims: {', '.join(by_id)}")
        it, grp = by_id[reading["claim"]], by_id[reading["group"]]
        n, k, g = it.n, it.k, grp.k
        low, high = max(0, k - (n - g)), min(k, g)
        lo, hi = Fraction(low, g), Fraction(high, g)
        c = it.claim
        threshold = Fraction(c.threshold).limit_denominator(10**6)
        meets = {">": lo > threshold, ">=": lo >= threshold, "<": hi < threshold, "<=": hi <= threshold}[c.comparison]
        group_item = grp.claim.item if isinstance(grp.claim.item, int) else grp.claim.table_item or grp.claim.item
        low_text, high_text = share_percent_text(float(lo)), share_percent_text(float(hi))
        out[c.id] = (
            f"Read as \u201c{reading['printed']}\u201d, that is among the {g} respondents who agreed with item "
            f"{group_item}, the share is not in the table, since which answers go together is unknown: the counts "
            f"allow from {low}/{g} = {low_text}% to {high}/{g} = {high_text}%, "
            + (f"{words[c.comparison]} {100 * c.threshold:g}% whatever the pairing." if meets else
               f"so on this reading the share is at least {low_text}% but not certainly "
               f"{words[c.comparison]} {100 * c.threshold:g}%.")
        )
    return out


def claim_texts(rows, survey) -> dict:
    """Each claim check's id -> ``{"statement", "explanation"}``: the claim as stated and its verdict
    explained by :meth:`analysis.claims.ClaimResult.explanation`, the one text report.html shows for a
    claim (the paper shows the same, per result). The claim checks are the ``kind == "claim"`` rows, one
    per result in the same order; a row whose printed wording is not its result's is an error."""
    if survey is None:
        return {}
    rows = [r for r in rows if r.kind == "claim"]
    results = survey.claims.results
    if len(rows) != len(results) or any(r.published != (c.claim.printed or c.claim.statement)
                                        for r, c in zip(rows, results)):
        raise ValueError("the claim checks do not match the evaluated claims one to one")
    readings = claim_readings(survey)
    return {r.id: {"statement": c.claim.statement,
                   "explanation": " ".join(filter(None, (c.explanation(), readings.get(c.claim.id, ""))))}
            for r, c in zip(rows, results)}


def rounding_ties(survey) -> str:
    """The sentence under the survey table stating the tie a published row needs: a row that
    largest-remainder rounding of the rebuilt counts prints only because equal remainders were
    broken in favour of the first label (:func:`analysis.rounding.largest_remainder_tie`); empty
    when no published row needs one. One text for both renderings."""
    from fractions import Fraction

    from analysis.rounding import largest_remainder
    from analysis.tables import load_table1

    table, _ = load_table1()
    found = []
    for row_id, cells, it in zip(table.items, table.cells, survey.summary.items):
        counts = [it.counts[label] for label in table.labels]
        tie = it.rounding_tie(survey.facts.decimals)
        if tie and largest_remainder(counts, survey.facts.decimals) == [Fraction(c) for c in cells]:
            found.append(f"row {row_id} ({', '.join(map(str, counts))} of {it.n}) is what largest-remainder "
                         f"rounding prints, with a tie: {tie}")
    if not found:
        return ""
    return "In the published table, " + "; ".join(found) + "."


PROSE = {
    "separate": "The moment equation is written as the paper writes it: the moments of the actual forces "
                "about P, then the inertial term -r_G/P x m a_P as a term of its own, equal to I_P alpha with "
                "I_P built element by element by the parallel-axis theorem (Eq. 12).",
    "kinematics_heading": "Kinematics at release",
    "equations_heading": "Equations",
    "ex1_numbers_heading": "Numbers at release",
    "ex2_numbers_heading": "Numbers at the chosen state",
    "oscillations_heading": "Small oscillations",
    "alpha_opposite": "so \u03b1 and \u03b8\u0308 carry opposite signs in the numbers below",
    "ex1_solve": "The moment equation about {point} holds only the reaction at the other end and the angular "
                 "acceleration; together with the horizontal force balance it fixes both, and the vertical "
                 "balance then gives the remaining reaction. Solving the system:",
    "ex1_reactions": "and the reactions in terms of the angular acceleration:",
    "ex2_reactions": "The force balances give the friction and normal forces in terms of the motion:",
    "ex2_eom": "Eliminating the friction force between the horizontal balance and the moment equation gives the "
               "equation of motion:",
    "ex2_findings": "The article's printed versions of this step differ from the derivation:",
    "solver": "The solver writes these equations for a scene file (geometry, elements, constraints, loads), adds "
              "the constraint acceleration equations, solves the linear system for the angular acceleration and "
              "the reactions, and eliminates the reactions to obtain the equation of motion. Its results are "
              "confirmed in the test suite by two independent routes: Newton-Euler about the mass centre, and "
              "Lagrange's equations built with sympy.physics.mechanics.",
    "oscillations": "Without the applied force, linearising the equation of motion about the hanging equilibrium "
                    "gives a harmonic oscillator with",
    "survey_intro": "{respondents} of {enrolled} enrolled students answered five statements on a five-point scale. "
                    "The published table gives percentages only; the counts behind them were reconstructed (each "
                    "cell's percentage must come from a whole number of the {respondents} respondents) and a "
                    "respondent-level file was rebuilt from them, then summarised by the same code an instructor "
                    "would run on their own export. Agreement is the share answering either agreeing option, with "
                    "a 95% Wilson interval.",
    "claims_lead": "Claims made about these answers:",
    "statements_lead": "The statements, as worded on the survey:",
}
"""Sentences and headings shared word for word by paper.html and paper.tex."""


def _term_parts(terms):
    """(mathml, latex) of a sum of terms kept apart (each term's note under it)."""
    from html import escape

    from reports.mathml import _mathml_body

    ml, lx = [], []
    for i, t in enumerate(terms):
        expr = sp.sympify(t.expr)
        negative = i > 0 and expr.could_extract_minus_sign()
        body = -expr if negative else expr
        op = "\u2212" if negative else "+"
        m = _mathml_body(body)
        x = to_latex(body)
        if t.note and len(terms) > 1:
            note = note_text(t.note)
            m = f"<munder><mrow>{m}</mrow><mtext mathsize=\"small\">{escape(note)}</mtext></munder>"
            x = rf"\underbrace{{{x}}}_{{\text{{{_latex_text(note)}}}}}"
        ml.append(("" if i == 0 else f"<mo>{op}</mo>") + m)
        lx.append(("" if i == 0 else (" - " if negative else " + ")) + x)
    return "".join(ml), "".join(lx)


_NOTE_WORDS = ((re.compile(r"gravity:(\w+)"), r"weight of \1"), (re.compile(r"\bm d\^2\b"), "m d\u00b2"),
               (re.compile(r" x "), " \u00d7 "), (re.compile(r"(?<![\w/])-(?=r_G)"), "\u2212"))


def note_text(note: str) -> str:
    """A term's note in words and symbols, not code: the scene's load id ``gravity:bar`` as "weight
    of bar", ``d^2`` as d², the cross product ``x`` as ×, a minus as −."""
    for pattern, words in _NOTE_WORDS:
        note = pattern.sub(words, note)
    return note


def _latex_text(text: str) -> str:
    """Text for ``\\text{}`` in a display: the paper.tex escape (:func:`reports.make_report.latex_escape`:
    LaTeX's special characters, and −, ×, ² as pdflatex can set them)."""
    from reports.make_report import latex_escape

    return latex_escape(text)


PAGE_WIDTH_EM = 75.0
"""The widest display paper.html shows in one row, in :func:`solver.mathml.mathml_width` units. In a
1000 px window the page's column is about 950 px wide, and Chromium draws the paper's displays at
about 11.5 px a unit (Example 1's moment equation about A, 62 units, is 710 px wide; about P, 69 units,
800 px): 950 / 11.5 is about 82 units, less the estimate's tenth, 75. A wider display (Example 2's
about C, 82 units) is laid out one term a row (:func:`solver.explain.render.terms_table`)."""


def terms_shown(eq) -> Shown:
    """An :class:`solver.explain.content.Equation` with its terms kept apart, for both outputs."""
    from markupsafe import Markup, escape

    from reports.mathml import _wrap
    from solver.explain.content import Term
    from solver.explain.render import terms_table
    from solver.mathml import mathml_width

    if eq.name:
        head_m = _mathml_body(sp.Symbol(eq.name.replace("/", "")))
        head_x = to_latex(sp.Symbol(eq.name.replace("/", "")))
    else:
        head_m, head_x = _term_parts(eq.lhs)
    rhs_m, rhs_x = _term_parts(eq.rhs)
    row = f"<mrow>{head_m}<mo>=</mo>{rhs_m}</mrow>"
    if mathml_width(row) > PAGE_WIDTH_EM:  # wider than the page: one term a row, as the worked solution's HTML
        lhs = (Term(sp.Symbol(eq.name.replace("/", ""))),) if eq.name else eq.lhs
        notes = lambda note: escape(note_text(note))  # noqa: E731
        mathml = f"<div class=\"terms-eq\">{terms_table(lhs, eq.rhs, '<mo>=</mo>', '', notes)}</div>"
    else:
        mathml = _wrap(row, "block")
    return Shown(mathml=Markup(mathml), latex=f"{head_x} = {rhs_x}",
                 sides=(eq.name or eq.left, eq.right), label=eq.label, ref=eq.ref)


def _mathml_body(expr):
    from reports.mathml import _mathml_body as body

    return body(expr)


def printed_number(eqset, scene_key: str, quantity: str, point: str | None = None) -> str:
    """The article's number of the first printed equation of a scene that gives ``quantity`` (at
    ``point``) on its left-hand side, as data/published/equations.toml transcribes it ("" for none):
    Example 1's I_A is Eq. 21, Example 2's I_P Eq. 35 and its alpha Eq. 33."""
    for tr in eqset.equations:
        meaning = tr.symbols.get(tr.lhs.strip()) if tr.scene == scene_key else None
        if meaning is not None and meaning.quantity == quantity and (point is None or meaning.point == point):
            return tr.number
    return ""


def ranked_points(system) -> dict:
    """The point advisor's candidates for the (first) body at the scene's state, by name
    (:func:`solver.explain.rank_points`)."""
    from solver.analyses.instant import assemble
    from solver.explain import rank_points

    body = next(iter(system.bodies))
    return {c.name: c for c in rank_points(system, body, assemble(system))}


def explained(system, point: str, at_rest: bool, shows_alternative: bool = False, ranked: dict | None = None,
              inertia_number: str = "") -> dict:
    """Newton by component, I_P per element and the generalized Euler equation about ``point`` with the
    inertial term apart, the unknowns that drop out, and why this point (the advisor's reason);
    ``shows_alternative``: the paper shows the advisor's point too, after the equation of motion;
    ``ranked``: :func:`ranked_points` of the system when the caller has it (default: ranked here);
    ``inertia_number``: the article's equation for this I_P (:func:`printed_number`), cited beside
    Eq. (12), the parallel-axis rule each term follows."""
    from solver.explain import explain

    # the per-body steps are what the paper shows (its kinematics are example_steps'; it shows the moment
    # equation as written, not collected by unknown)
    expl = explain(system, point, advice=False, solution=False, kinematics=False, collected=False)
    body = next(iter(system.bodies))
    section = expl.section(body)
    rest = {c.qd: 0 for c in system.coordinates} if at_rest else {}

    def at(eq):
        from solver.display import tidy_linear
        from solver.explain.content import Equation, Term

        keys = list(system.qdd) + [r.symbol for r in system.reactions]
        side = lambda terms: tuple(Term(tidy_linear(sp.sympify(t.expr).xreplace(rest), keys), t.note)
                                   for t in terms)
        return terms_shown(Equation(side(eq.lhs), side(eq.rhs), eq.label, eq.ref, eq.tag, eq.name))

    newton = [at(e) for e in section.step("newton").equations]
    euler_step = section.step("euler")
    ranked = ranked_points(system) if ranked is None else ranked
    best = min(ranked.values(), key=lambda c: c.key)
    return {
        "newton": newton,
        "inertia": _cited(terms_shown(euler_step.equation("inertia")), inertia_number),
        "euler": at(euler_step.equation("euler")),
        "dropped": [name_text(t) for t in section.step("dropped").text],
        **point_choice(ranked, point, best, shows_alternative),
    }


def _cited(eq: Shown, number: str) -> Shown:
    """The per-element I_P display citing the article's own equation for it, then Eq. (12)."""
    if number and number != "12":
        eq.ref = f"Eq. ({number}); each term by {eq.ref}" if eq.ref else f"Eq. ({number})"
    return eq


def point_choice(ranked: dict, point: str, best, shows_alternative: bool = False) -> dict:
    """The words on the choice of P, from the point advisor's ranking (:func:`solver.explain.rank_points`).

    Parameters
    ----------
    ranked : dict
        Candidate name -> :class:`solver.explain.advisor.Candidate`.
    point : str
        The point the paper takes moments about.
    best : Candidate
        The advisor's first choice.
    shows_alternative : bool
        Whether the paper shows the working about ``best`` after the equation of motion.

    Returns
    -------
    dict
        ``why`` (why ``point``, and, when the advisor prefers another point, that both work),
        ``advisor_best`` (its name), ``alternative_title`` and ``advisor_why`` (the paper's choice
        and the advisor's side by side), all shared word for word by paper.html and paper.tex.
    """
    one_step = best.group == 1
    kind = "one-step alternative" if one_step else "alternative"
    why = f"Why {point}: {ranked[point].reason()}." if point in ranked else ""
    if best.name == point or point not in ranked:
        return {"why": name_text(why), "advisor_best": best.name, "alternative_title": "", "advisor_why": ""}
    mine, theirs = ranked[point], best
    why += f" The point advisor ranks {theirs.name} first; both points work" + (
        f" (the {kind} about {theirs.name} is shown after the equation of motion)." if shows_alternative else ".")
    advisor_why = (
        f"Both {point} and {theirs.name} work: the generalized Euler equation holds about any point of the body, "
        f"and every choice gives the same motion. The paper takes moments about {point}, whose moment equation "
        f"holds {_count(mine.unknowns, 'unknown')} ({', '.join(mine.unknowns)}) and {_solved(mine)}. "
        f"The point advisor ranks {theirs.name} first because its moment equation holds "
        f"{_count(theirs.unknowns, 'unknown')} ({', '.join(theirs.unknowns)})"
        + (", which it gives on its own: a one-step alternative." if one_step else f": an {kind}."))
    return {"why": name_text(why), "advisor_best": theirs.name,
            "alternative_title": f"The {kind} about {theirs.name}", "advisor_why": name_text(advisor_why)}


def _count(items, noun: str) -> str:
    """``"1 unknown"``, ``"2 unknowns"``."""
    return f"{len(items)} {noun}{'' if len(items) == 1 else 's'}"


def _solved(candidate) -> str:
    """How a candidate's moment equation is solved, from its group size (advisor's ``group``)."""
    if candidate.group == 1:
        return "gives them on its own"
    if candidate.group:
        return f"is solved together with {_count(range(candidate.group - 1), 'Newton component')}"
    return "is solved together with the other bodies' equations"
