"""Symbolic comparison of the paper's printed equations with the solver's derivation.

Each printed equation (``data/published/equations.toml``) is parsed by the
whitelist parser, its printed symbols are replaced by the quantities the
solver derives (alpha, point accelerations, reactions, inertia, omega_n), the
paper's conditions are applied (Example 1: omega = 0), and the difference of
its two sides is tested for zero:

* ``identity`` (kinematics, inertia): as it stands, for every state;
* ``relation`` (components of Eq. 1 / Eqs. 10-11): after substituting the
  solver's solution, theta_ddot and every reaction as functions of the state;
* ``eom``: additionally, the printed equation must equal the derived equation
  of motion times a constant factor; the difference is the residual shown;
* ``frequency``: against sqrt(stiffness / mass) of the derived equation of
  motion linearised about the printed state (Eq. 45), after checking that the
  linearisation has the printed form (no rate or forcing term);
* ``approximation``: a small-motion rule (Eq. 45, ``sin theta ~ theta``): lhs - rhs
  must vanish to first order about the printed state (its value and its first
  derivatives in the coordinate and the rate are zero there).

Zero is decided twice: numerically at random points to 30 digits (a nonzero
residual cannot pass) and symbolically by an exact normal form: numerator and
denominator as polynomials in sin and cos of each angle, reduced modulo
sin**2 + cos**2 - 1 (:func:`solver.display.reduce_trig`, the remainder by a
Groebner basis, so an identically zero residual reduces to 0 and a nonzero one
is shown in closed form). sympy's generic ``simplify`` is asked only where that
form does not apply. A nonzero residual is diagnosed when it is a multiple of
one printed term ("the term F_a r_d has the wrong sign").
"""
from __future__ import annotations

import random
import zlib
from dataclasses import dataclass, field, replace
from functools import cached_property, lru_cache

import mpmath
import sympy as sp

from reports.mathml import expr_text
from reports.published import ReportInputError, Transcription
from solver.expressions import parse_expression
from solver.display import expanded
from solver.model.system import derivative
from solver.tree_value import NotEvaluable, mpmath_arithmetic, tree_program

__all__ = ["EquationOutcome", "DerivedQuantities", "check_equation", "is_zero"]

_RANDOM_POINTS = 4
"""Random points at which a residual is evaluated."""
_DIGITS = 30
"""Working precision of the numeric zero test [decimal digits]."""
_ZERO_REL = sp.Float("1e-20")
"""A residual counts as zero when |residual| <= 1e-20 * (|lhs| + |rhs|): ten orders of
magnitude above the 30-digit round-off, twenty below any real discrepancy."""


@dataclass
class EquationOutcome:
    """Result of comparing one printed equation with the derivation.

    Attributes
    ----------
    transcription : Transcription
    printed_lhs, printed_rhs : sympy.Expr
        The equation as printed (parsed, printed symbols kept).
    residual : sympy.Expr or None
        ``printed (lhs - rhs) - factor * derived`` for kind ``eom``; otherwise
        ``lhs - rhs`` with the derived quantities and the solution substituted;
        simplified. Zero when the equation agrees.
    factor : sympy.Expr or None
        Constant between the printed and the derived equation of motion (``eom``).
    derived_lhs, derived_rhs : sympy.Expr or None
        The derived counterpart, for display.
    verdict : str
        "agrees", "disagrees" or "not-checkable".
    detail : str
    diagnosis : str
        A plain statement of the error when it is a single wrong term (sympy's text of the term).
    diagnosis_prose : str
        The same statement with the term in the paper's notation (:func:`reports.mathml.expr_text`).
    symbolic_zero : bool
        Whether sympy reduced the residual to 0 (besides the numeric test).
    """

    transcription: Transcription
    printed_lhs: sp.Expr
    printed_rhs: sp.Expr
    residual: sp.Expr | None
    verdict: str
    detail: str
    factor: sp.Expr | None = None
    derived_lhs: sp.Expr | None = None
    derived_rhs: sp.Expr | None = None
    diagnosis: str = ""
    diagnosis_prose: str = ""
    symbolic_zero: bool = False
    notes: list[str] = field(default_factory=list)


def _names(scene, deriv, tr: Transcription) -> dict[str, sp.Symbol]:
    names = dict(scene.symbols)
    names.update({deriv.q.name: deriv.q, deriv.qd.name: deriv.qd, deriv.qdd.name: deriv.qdd})
    names[deriv.t.name] = deriv.t
    for symbol in tr.symbols:
        if symbol in names:
            raise ReportInputError(
                f"{tr.where}.symbols.{symbol}: already a parameter or state name of scene "
                f"{tr.scene!r}; printed symbols need names of their own"
            )
        names[symbol] = sp.Symbol(symbol, real=True)
    return names


def _state_subs(table: dict[str, str], scene, deriv, tr: Transcription, key: str) -> dict:
    base = dict(scene.symbols)
    subs = {}
    targets = {deriv.q.name: deriv.q, deriv.qd.name: deriv.qd, deriv.t.name: deriv.t, **base}
    for name, text in table.items():
        if name not in targets:
            raise ReportInputError(
                f"{tr.where}.{key}.{name}: not a parameter or state of scene {tr.scene!r}; "
                f"valid: {', '.join(sorted(targets))}"
            )
        subs[targets[name]] = parse_expression(text, base, where=f"{tr.where}.{key}.{name}")
    return subs


def _reduced(expr: sp.Expr) -> sp.Expr:
    """Display form from structure (:func:`solver.display.tidy`), exactly 0 when the expression is
    identically zero modulo sin**2 + cos**2 = 1 (:func:`solver.display.is_identically_zero`)."""
    from solver.display import is_identically_zero, tidy

    expr = expanded(expr)
    return sp.Integer(0) if is_identically_zero(expr) else tidy(expr)


def _linearisation(deriv, assume: dict, about: dict):
    """(M0, K, C, E0) of the derived eom (conditions applied) about ``about``."""
    eom = deriv.eom.xreplace(assume)
    q, qd, qdd = deriv.q, deriv.qd, deriv.qdd
    at = {q: about.get(q, sp.Integer(0)), qd: about.get(qd, sp.Integer(0))}
    mass = _reduced(derivative(eom, qdd).xreplace(at))
    stiffness = _reduced(derivative(eom, q).xreplace({qdd: 0}).xreplace(at))
    damping = _reduced(derivative(eom, qd).xreplace({qdd: 0}).xreplace(at))
    offset = _reduced(eom.xreplace({qdd: 0}).xreplace(at))
    return mass, stiffness, damping, offset


class DerivedQuantities:
    """The derived quantities the printed symbols of one example stand for, each computed once.

    The printed equations of an example share most meanings (the acceleration of B along the
    rail is a symbol of five of them, under other names): :meth:`value` keeps each value by what
    the symbol means, its name aside, for as long as this object lives (one report build).

    Parameters
    ----------
    scene : solver.scene.Scene
    deriv : solver.derivation.Derivation
        The scene's derivation, about the point the printed equations are written about.
    """

    def __init__(self, scene, deriv):
        self.scene, self.deriv = scene, deriv
        self._values: dict = {}

    def value(self, meaning, tr: Transcription, lin) -> sp.Expr:
        """The value of a printed symbol of ``tr`` (``lin``: the equation's linearisation, or None)."""
        if meaning.quantity == "natural_frequency":  # of this equation's own linearisation
            return _meaning_value(meaning, self, tr, lin)
        key = replace(meaning, symbol="")
        if key not in self._values:
            self._values[key] = _meaning_value(meaning, self, tr, lin)
        return self._values[key]

    @cached_property
    def forces(self) -> dict[str, sp.Matrix]:
        """Every force on the (single) body by name (:func:`_forces`)."""
        return _forces(self.deriv)


def _meaning_value(meaning, quantities: DerivedQuantities, tr: Transcription, lin) -> sp.Expr:
    scene, deriv = quantities.scene, quantities.deriv
    where = f"{tr.where}.symbols.{meaning.symbol}"
    quantity = meaning.quantity
    if quantity == "alpha":
        return deriv.alpha
    if quantity == "omega":
        return deriv.omega
    if meaning.point is not None and meaning.point not in scene.points and meaning.point != "G":
        raise ReportInputError(
            f"{where}.point: {meaning.point!r} is not a point of scene {tr.scene!r}; "
            f"valid: {', '.join(scene.points)}"
        )
    if quantity == "relative_position" and meaning.relative_to not in scene.points and meaning.relative_to != "G":
        raise ReportInputError(
            f"{where}.relative_to: {meaning.relative_to!r} is not a point of scene {tr.scene!r}; "
            f"valid: {', '.join(scene.points)}"
        )
    if meaning.along is not None:
        base = dict(scene.symbols)
        u = sp.Matrix([parse_expression(x, base, where=f"{where}.along") for x in meaning.along])
        if _exact_zero(u.dot(u) - 1) is not True:
            raise ReportInputError(f"{where}.along: must be a unit vector, got {list(meaning.along)}")
        vector = _vector_quantity(meaning, quantities, where)
        # the component along u (vector . u); a zero component of u adds nothing (v * 0 is 0 for a finite v,
        # which sympy would ask of the whole expression v to be sure)
        return sp.Add(*[v * w for v, w in zip(vector, u) if w != 0])
    if quantity == "element_inertia":
        return _element_inertia(deriv, meaning, where)
    if quantity == "reaction":
        if meaning.name not in deriv.reactions:
            raise ReportInputError(
                f"{where}.name: {meaning.name!r} is not a reaction of scene {tr.scene!r}; "
                f"valid: {', '.join(deriv.reactions)}"
            )
        return deriv.reactions[meaning.name]
    if quantity == "inertia_about":
        return deriv.inertia_about(meaning.point)
    if quantity == "natural_frequency":
        if lin is None:
            raise ReportInputError(f"{where}: natural_frequency needs an 'about' table on the equation")
        mass, stiffness = lin[0], lin[1]
        return sp.sqrt(stiffness / mass)
    raise ReportInputError(f"{where}.quantity: unsupported quantity {quantity!r}")  # pragma: no cover


def _vector_quantity(meaning, quantities: DerivedQuantities, where: str) -> sp.Matrix:
    """The fixed-frame vector a printed component reads (position, velocity, acceleration, force)."""
    quantity, deriv = meaning.quantity, quantities.deriv
    if quantity == "acceleration":
        return deriv.acceleration(meaning.point)
    if quantity == "velocity":
        return deriv.velocity(meaning.point)
    if quantity == "position":
        return deriv.position(meaning.point)
    if quantity == "relative_position":
        return deriv.position(meaning.point) - deriv.position(meaning.relative_to)
    forces = quantities.forces
    if quantity == "resultant":
        return sum(forces.values(), sp.zeros(2, 1))
    if quantity == "force":
        if meaning.name not in forces:
            raise ReportInputError(f"{where}.name: {meaning.name!r} is not a force on the body; "
                                   f"valid: {', '.join(forces)}")
        return forces[meaning.name]
    raise ReportInputError(f"{where}.quantity: unsupported quantity {quantity!r}")  # pragma: no cover


def _forces(deriv) -> dict[str, sp.Matrix]:
    """Every force on the (single) body by name: applied loads, and reactions with their
    magnitudes replaced by the derivation's solution (as printed reaction symbols are)."""
    system = deriv.system
    body = deriv._only_body()
    solution = {sp.Symbol(name, real=True): value for name, value in deriv.reactions.items()}
    out = {}
    for a in system.applied_loads:
        if a.body == body and a.force is not None:
            out[a.name] = sp.Matrix(a.force)
    for jl in system.joint_loads():
        if jl.body == body and jl.force is not None:
            out[jl.reaction.name] = (jl.reaction.symbol * sp.Matrix(jl.force)).xreplace(solution)
    return out


def _element_inertia(deriv, meaning, where: str) -> sp.Expr:
    """One element's moment of inertia about a named point: I_G,k + m_k d_k^2 (a term of Eq. 12)."""
    system, b = deriv.system, deriv._only_body()
    body = system.bodies[b]
    try:
        e = body.element(meaning.element)
    except KeyError:
        raise ReportInputError(f"{where}.element: {meaning.element!r} is not an element of the body; valid: "
                               f"{', '.join(x.name for x in body.elements)}") from None
    if system.is_body_point(b, meaning.point):
        at = body.body_coords(meaning.point)
    else:
        rel = system.point_position(b, meaning.point) - system.origin(b)
        phi = system.angle(b)
        at = sp.Matrix([[sp.cos(phi), sp.sin(phi)], [-sp.sin(phi), sp.cos(phi)]]) * rel
    d = e.mass_center - at
    return e.I_G + e.mass * (d[0] ** 2 + d[1] ** 2)


def _first_order(expr: sp.Expr, deriv, about: dict) -> sp.Expr:
    """The constant and linear part of ``expr`` about the state ``about`` (q, qd; 0 unless given):
    zero when ``expr`` is of second order there (kind ``approximation``, Eq. 45)."""
    q, qd = deriv.q, deriv.qd
    at = {q: about.get(q, sp.Integer(0)), qd: about.get(qd, sp.Integer(0))}
    return (expr.subs(at) + derivative(expr, q).subs(at) * (q - at[q])
            + derivative(expr, qd).subs(at) * (qd - at[qd]))


def _random_point(symbols, seed: int) -> dict:
    """Symbol -> a random rational n / 97 as an mpmath number at the working precision (call it
    inside ``mpmath.workdps``)."""
    rng = random.Random(seed)
    # Positive values of moderate size: masses, lengths, angles and rates alike; evaluation is at
    # _DIGITS digits.
    values = _ninety_sevenths(mpmath.mp.prec)
    return {s: values[rng.randint(23, 181)] for s in sorted(symbols, key=lambda s: s.name)}


@lru_cache(maxsize=4)
def _ninety_sevenths(prec: int) -> tuple:
    """n / 97 as mpmath numbers at the precision ``prec`` [bits], for n = 0 ... 181 (a number is
    made once, not once per symbol of every point)."""
    with mpmath.workprec(prec):
        return tuple(mpmath.mpf(n) / 97 for n in range(182))


def _evaluator(exprs: list) -> tuple:
    """(f, ordered): f(*args) -> [mpmath values of exprs] at args (mpf, one per symbol of ``ordered``,
    the expressions' free symbols by name): the trees walked once into a program
    (:func:`solver.tree_value.tree_program` in mpmath) run at each point, or lambdify where a node
    is not one the walk knows."""
    try:
        program, symbols = tree_program(exprs, mpmath_arithmetic())
    except NotEvaluable:
        ordered = sorted(set().union(*(e.free_symbols for e in exprs)), key=lambda s: s.name)
        return sp.lambdify(ordered, exprs, modules="mpmath"), ordered
    ordered = sorted(symbols, key=lambda s: s.name)
    return (lambda *args: program(dict(zip(ordered, args)))), ordered


def is_zero(expr: sp.Expr, scale_terms=(), seed: int = 0) -> tuple[bool, float]:
    """Numeric zero test of ``expr`` at random points.

    Parameters
    ----------
    expr : sympy.Expr
    scale_terms : iterable of sympy.Expr
        Expressions whose magnitudes set the scale of "zero" (the terms of both sides).
    seed : int

    Returns
    -------
    (bool, float)
        Whether |expr| <= 1e-20 * sum |scale_terms| at every point, and the largest
        relative residual (NaN when no point could be evaluated).
    """
    expr = sp.sympify(expr)
    scale_terms = [sp.sympify(t) for t in scale_terms]
    # mpmath at _DIGITS digits, the (already parsed) sympy tree evaluated directly: one walk gives the
    # residual and the scale terms.
    fn, ordered = _evaluator([expr, *(scale_terms or [sp.Integer(1)])])
    worst = 0.0
    tried = attempt = 0
    with mpmath.workdps(_DIGITS):
        while tried < _RANDOM_POINTS and attempt < 5 * _RANDOM_POINTS:
            point = _random_point(ordered, seed + attempt)
            attempt += 1
            args = [point[s] for s in ordered]
            try:
                values = fn(*args)
                value = abs(values[0])
                scale = sum(abs(x) for x in values[1:])
            except (ZeroDivisionError, ValueError, TypeError):
                continue
            if not (mpmath.isfinite(value) and mpmath.isfinite(scale)):
                continue
            tried += 1
            rel = float(value / max(scale, mpmath.mpf("1e-300")))
            worst = max(worst, rel)
    if tried == 0:
        return False, float("nan")
    return worst <= float(_ZERO_REL), worst


def _exact_zero(expr: sp.Expr) -> bool | None:
    """Whether ``expr`` is identically zero, decided exactly: the numerator of its normal form
    modulo sin**2 + cos**2 = 1 (:func:`solver.display.is_identically_zero`); None when the form
    does not apply (a trigonometric argument that is not a plain symbol)."""
    from solver.display import is_identically_zero

    return is_identically_zero(expanded(expr))


def _trig_reduce(expr: sp.Expr) -> sp.Expr | None:
    """Normal form of a rational expression in sin/cos modulo sin**2 + cos**2 = 1, or None
    (:func:`solver.display.reduce_trig`: one implementation for the solver's display and the report)."""
    from solver.display import reduce_trig

    return reduce_trig(expr)


def _normal_form(expr: sp.Expr) -> sp.Expr:
    """The rational normal form modulo sin**2 + cos**2 = 1 (a constant ratio comes out as a
    number: :func:`solver.display.constant_value` finds it without the form's ``cancel``); sympy's
    ``simplify`` only where that form does not apply."""
    from solver.display import constant_value

    constant = constant_value(expr)
    if constant is not None:
        return constant
    reduced = _trig_reduce(expr)
    return sp.simplify(expr) if reduced is None else reduced


def _simplify(expr: sp.Expr) -> sp.Expr:
    """Reduce a residual: exact trigonometric normal form first (factored), sympy's generic
    ``simplify`` only when there is no such form or it came out larger than the residual
    itself (``simplify`` took seconds per disagreeing equation, most of a report build's
    checking time)."""
    from solver.display import numerator_reduces_to_zero

    if numerator_reduces_to_zero(expr):  # the exact zero test alone (no cancel): most residuals
        return sp.Integer(0)
    reduced = _trig_reduce(expr)
    if reduced is not None and reduced == 0:
        return sp.Integer(0)
    if reduced is not None:
        reduced = sp.factor(reduced)
        if sp.count_ops(reduced) <= sp.count_ops(expr):
            return reduced
    full = sp.simplify(expr)
    if reduced is None:
        return full
    return full if sp.count_ops(full) <= sp.count_ops(reduced) else reduced


def _varies(expr: sp.Expr, seed: int = 0) -> bool:
    """True when ``expr`` takes clearly different values at two random points (so it is not a
    constant and sympy's slow ``simplify`` need not be asked); False when it may be constant
    or could not be evaluated."""
    fn, symbols = _evaluator([expr])
    if not symbols:
        return False
    values = []
    with mpmath.workdps(_DIGITS):
        for attempt in range(4):
            point = _random_point(symbols, seed + attempt)
            try:
                value = fn(*[point[s] for s in symbols])[0]
            except (ZeroDivisionError, ValueError, TypeError):
                continue
            if not mpmath.isfinite(value):
                continue
            values.append(value)
            # 1e-20 relative at 30 digits: far above the round-off, far below any real variation
            if len(values) == 2:
                return abs(values[0] - values[1]) > float(_ZERO_REL) * (abs(values[0]) + abs(values[1]))
    return False


def _diagnose(residual: sp.Expr, lhs: sp.Expr, rhs: sp.Expr, solution: dict) -> tuple[str, str]:
    """Say which printed term is wrong when the residual is a multiple of one term: the sentence
    twice, with the term as sympy's text (verification.json) and as prose (:func:`expr_text`).

    ``lhs``/``rhs`` are the printed sides with the derived quantities substituted
    (before the solution); the residual is printed (lhs - rhs) minus the derived form.
    """
    if residual == 0:
        return "", ""
    for side, sign, expr in (("left-hand side", 1, lhs), ("right-hand side", -1, rhs)):
        for term in sp.Add.make_args(expanded(expr)):
            value = (sign * term).xreplace(solution) if solution else sign * term
            if value == 0:
                continue
            if _varies(residual / value):
                continue  # not a constant multiple of this term: no need to ask simplify
            ratio = _ratio(residual / value)
            if ratio.is_number and ratio != 0:
                factor = sp.nsimplify(1 - ratio)
                if factor == -1:
                    return tuple(f"the term {show(term)} on the {side} has the wrong sign: "
                                 f"the derivation gives {show(-term)} there" for show in (sp.sstr, expr_text))
                return tuple(f"the term {show(term)} on the {side} should be {show(sp.expand(factor * term))}"
                             for show in (sp.sstr, expr_text))
    return "", ""


def _ratio(expr: sp.Expr) -> sp.Expr:
    """``sympy.simplify(expr)`` as far as :func:`_diagnose` asks (is it a number, and which): for a
    rational expression in symbols and sin/cos/tan/cot (of sums of symbols too), its exact normal
    form (:func:`_trig_reduce`), which is the rational number a constant equals and holds a symbol
    otherwise, so that ``simplify`` can give no number either; ``simplify`` for anything else.
    (``simplify`` took a third of a second to find a constant ratio of -1/3 the form finds in a
    hundredth.)"""
    if _rational_in_trig(expr):
        reduced = _trig_reduce(expr)
        if reduced is not None and (reduced.is_Rational or reduced.free_symbols):
            return reduced
    return sp.simplify(expr)


def _rational_in_trig(expr: sp.Expr) -> bool:
    """Whether ``expr`` is built by +, * and integer powers from rational numbers, symbols and
    sin/cos/tan/cot (the expressions whose normal form :func:`_trig_reduce` gives exactly)."""
    return (all(isinstance(f, (sp.sin, sp.cos, sp.tan, sp.cot)) for f in expr.atoms(sp.Function))
            and all(p.exp.is_Integer for p in expr.atoms(sp.Pow))
            and all(n.is_Rational for n in expr.atoms(sp.Number))
            and not expr.atoms(sp.NumberSymbol) and not expr.has(sp.I))


@lru_cache(maxsize=64)
def _qdd_solution(eom: sp.Expr, qdd: sp.Symbol) -> sp.Expr:
    """theta_ddot solved from the equation of motion (linear in it); the same for every printed
    equation of an example under the same conditions, so solved once."""
    return -eom.xreplace({qdd: 0}) / derivative(eom, qdd)


def check_equation(tr: Transcription, scene, deriv,
                   quantities: DerivedQuantities | None = None) -> EquationOutcome:
    """Compare one printed equation with the solver's derivation.

    Parameters
    ----------
    tr : Transcription
        The printed equation.
    scene : solver.scene.Scene
        The scene of the example it belongs to.
    deriv : solver.derivation.Derivation
        The derivation of that scene about the paper's reference point.
    quantities : DerivedQuantities, optional
        Of ``scene`` and ``deriv``, shared by the equations of one example (default: a new one).

    Returns
    -------
    EquationOutcome

    Raises
    ------
    ReportInputError
        A transcription that names unknown symbols, points, reactions or states.
    """
    names = _names(scene, deriv, tr)
    lhs = parse_expression(tr.lhs, names, where=f"{tr.where}.lhs")
    rhs = parse_expression(tr.rhs, names, where=f"{tr.where}.rhs")
    assume = _state_subs(tr.assume, scene, deriv, tr, "assume")
    about = _state_subs(tr.about, scene, deriv, tr, "about")
    lin = _linearisation(deriv, assume, about) if tr.kind == "frequency" else None
    quantities = DerivedQuantities(scene, deriv) if quantities is None else quantities
    meanings = {names[s]: quantities.value(m, tr, lin) for s, m in tr.symbols.items()}
    seed = zlib.crc32(tr.id.encode())

    q, qd, qdd = deriv.q, deriv.qd, deriv.qdd
    mapped_l = lhs.xreplace(meanings).xreplace(assume)
    mapped_r = rhs.xreplace(meanings).xreplace(assume)
    eom = deriv.eom.xreplace(assume)
    printed = mapped_l - mapped_r
    notes: list[str] = []
    factor = None
    derived_l = derived_r = None
    solution: dict = {}

    if tr.kind == "identity":
        diff = printed
        derived_l, derived_r = mapped_l, mapped_r
    elif tr.kind in ("relation", "eom"):
        solution = {qdd: _qdd_solution(eom, qdd)}
        diff = printed.xreplace(solution)
        if tr.kind == "eom":
            if printed.has(*[sp.Symbol(r, real=True) for r in deriv.reactions]):
                raise ReportInputError(f"{tr.where}: kind 'eom' must not contain reactions")
            factor = _normal_form(derivative(printed, qdd) / derivative(eom, qdd))
            if factor.free_symbols & {q, qd, qdd, deriv.t}:
                notes.append(
                    "the printed and derived equations of motion are not proportional "
                    f"(their theta_ddot coefficients differ by the state-dependent factor {sp.sstr(factor)})"
                )
                factor = None
            else:
                diff = printed - factor * eom
                derived_l, derived_r = expanded(factor * eom), sp.Integer(0)
    elif tr.kind == "approximation":
        diff = _first_order(printed, deriv, about)
        derived_l, derived_r = mapped_l, mapped_r
    elif tr.kind == "frequency":
        mass, stiffness, damping, offset = lin
        if offset != 0:
            notes.append(f"the linearisation point is not an equilibrium (residual force {sp.sstr(offset)})")
        if damping != 0:
            notes.append(f"the linearised equation keeps a rate term {sp.sstr(damping)} theta_dot")
        diff = printed
        derived_l, derived_r = lhs, sp.sqrt(_normal_form(stiffness / mass))
    else:  # pragma: no cover - validated on load
        raise ReportInputError(f"{tr.where}.kind: unknown kind {tr.kind!r}")

    scale_terms = [
        term.xreplace(meanings).xreplace(assume).xreplace(solution)
        for side in (lhs, rhs)
        for term in sp.Add.make_args(side)
    ]
    numeric_zero, worst = is_zero(diff, scale_terms, seed)
    residual = _simplify(diff)
    symbolic_zero = residual == 0
    if tr.kind == "frequency" and not symbolic_zero:
        # Square roots resist simplify; compare squares of the (positive) sides instead.
        if _exact_zero(mapped_l**2 - mapped_r**2):
            symbolic_zero = True
            residual = sp.Integer(0)
    agrees = numeric_zero and not notes
    diagnosis, diagnosis_prose = ("", "") if agrees else _diagnose(residual, mapped_l, mapped_r, solution)

    if agrees:
        how = "reduces to 0 symbolically" if symbolic_zero else (
            f"is 0 to {_DIGITS} digits at {_RANDOM_POINTS} random points (sympy's simplify left it unreduced)"
        )
        detail = {
            "identity": f"printed lhs - rhs with the derived quantities substituted {how}.",
            "relation": f"printed lhs - rhs with the solver's solution (theta_ddot and reactions) substituted {how}.",
            "eom": f"printed equation = {sp.sstr(factor)} x derived equation of motion; the difference {how}.",
            "frequency": f"printed omega_n = sqrt(stiffness/mass) of the linearised derived equation of motion; the difference {how}.",
            "approximation": f"printed lhs - rhs vanishes to first order about the printed state: its constant and "
                             f"linear part {how}.",
        }[tr.kind]
        verdict = "agrees"
    else:
        verdict = "disagrees"
        parts = [f"residual (printed lhs - rhs{' - factor x derived' if factor is not None else ''}) = {sp.sstr(residual)}"]
        if worst == worst:  # not NaN
            parts.append("nonzero at the random test points")
        if diagnosis:
            parts.append(diagnosis)
        parts.extend(notes)
        detail = "; ".join(parts) + "."
    conditions = ", ".join(f"{k} = {v}" for k, v in {**tr.assume, **tr.about}.items())
    if conditions:
        detail += f" Conditions applied: {conditions}."
    return EquationOutcome(
        transcription=tr,
        printed_lhs=lhs,
        printed_rhs=rhs,
        residual=residual,
        verdict=verdict,
        detail=detail,
        factor=factor,
        derived_lhs=derived_l,
        derived_rhs=derived_r,
        diagnosis=diagnosis,
        diagnosis_prose=diagnosis_prose,
        symbolic_zero=symbolic_zero,
        notes=notes,
    )
