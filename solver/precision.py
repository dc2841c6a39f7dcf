"""The instantaneous solve in three arithmetics, and how well float64 does.

At a state (every coordinate's value and rate, and t) the unknowns
x = (the coordinates' second derivatives, reactions...) solve the linear system
A x = b of the Derivation (for Example 1 the paper's Eqs. 24, 25 and 28, whose
numbers are Eq. 29). Dependent coordinates (loop closures) have no closed value:
they are solved again from the closure equations in mpmath to the digits asked
for plus 15, and the exact answer is exact at those values. This module solves it

* ``"float64"``: numpy, as :func:`solver.derivation.solve_instant` does;
* ``"exact"``: sympy, with every parameter turned into an exact number
  from the decimal text the scene gave (``"32.174 ft/s^2"`` becomes
  Rational(32174, 1000) * Rational(3048, 10000) m/s^2, ``"45 deg"`` becomes
  pi/4): rational arithmetic and exact trigonometric values (sin(pi/6) = 1/2),
  symbolic where no closed value exists;
* ``"mpmath"``: mpmath at ``dps`` significant digits, parameters from the
  same exact values.

and reports the condition number of A (float64): exactly, the one whose cheap estimate
``solve`` prints (:func:`solver.analyses.instant.condition_numbers`: 1-norm, rows and
columns equilibrated, so that it does not depend on the units). It bounds the relative
error of the float64 answer, each unknown measured against its column's scale, by about
cond(A) * 2.2e-16. An unknown much smaller than the equations' terms (a pendulum's angular
acceleration beside its pin forces at 1e8 rad/s) loses more: each unknown's own bound
(:func:`solver.analyses.instant.error_bounds`, from the round-off size of A's and b's entries)
counts it.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Mapping

import mpmath
import numpy as np
import pint
import sympy as sp

from .analyses.instant import (ROUND_OFF, condition_numbers, entry_sizes, error_bounds, refine,
                               refuse_zero_length, solve_with_estimate)
from .display import tidy
from .errors import InputError, SingularConfigurationError
from .strprint import lambdify

__all__ = ["PRECISIONS", "MIN_DPS", "MAX_DPS", "exact_quantity", "exact_values", "PreciseSolution", "solve_precise"]

from .limits import MAX_DPS, MIN_DPS, PRECISIONS  # noqa: E402,F401 - one place for the caps


def _exact_unit_factor(unit_name: str) -> sp.Expr:
    """SI factor of one named unit as an exact number (see :func:`exact_quantity`)."""
    from .units import ureg

    base = (1.0 * ureg.Unit(unit_name)).to_base_units()
    factor = float(base.magnitude)
    if "radian" in str(base.units):
        # angles: a rational multiple of pi (deg -> pi/180, revolution -> 2 pi)
        r = sp.Rational(factor / math.pi).limit_denominator(10**7)
        if abs(float(r) * math.pi - factor) <= 4e-16 * abs(factor):
            return r * sp.pi
    # unit definitions are decimals of at most 15 significant digits (0.3048,
    # 0.45359237, 4.4482216152605); pint's float chain may be off in the last bit
    short = f"{factor:.15g}"
    if abs(float(short) - factor) <= 4e-16 * abs(factor):
        return sp.Rational(short)
    return sp.Rational(repr(factor))


def exact_quantity(quantity: pint.Quantity) -> sp.Expr:
    """The SI value of a pint quantity as an exact sympy number.

    The magnitude (a float parsed from decimal text) is taken back to that
    decimal with ``repr`` (shortest round-trip) and made a Rational. Each unit
    of the quantity contributes its own SI factor: a short decimal (unit
    definitions such as ft = 0.3048 m, lb = 0.45359237 kg are exact decimals
    of at most 15 digits, recovered from pint's float factor), or for angles
    a rational multiple of pi (deg -> pi/180).
    """
    mag = quantity.magnitude
    value = sp.Integer(mag) if isinstance(mag, int) else sp.Rational(repr(float(mag)))
    for name, power in quantity.unit_items():
        p = sp.Rational(repr(float(power))) if not isinstance(power, int) else sp.Integer(power)
        value *= _exact_unit_factor(name) ** p
    return value


def exact_values(scene: Any) -> tuple[dict[sp.Symbol, sp.Expr], sp.Expr, sp.Expr]:
    """(parameter symbol -> exact SI value, exact theta, exact theta_dot) of a scene
    (the first free coordinate's value and rate)."""
    from .derivation import as_system

    system = as_system(scene)
    params = {sp.Symbol(n, real=True): exact_quantity(q) for n, q in system.parameters.items()}
    c = system.free[0]
    return (params, *_exact_coordinate(c, c.value, c.rate))


def _exact_coordinate(c: Any, value: float, rate: float) -> tuple[sp.Expr, sp.Expr]:
    """A free coordinate's value and rate as exact numbers: from the text the scene gave when
    the state is the scene's, else from the float (its shortest decimal)."""
    if c.given is not None and not c.dependent and value == c.value and rate == c.rate:
        return exact_quantity(c.given[0]), exact_quantity(c.given[1])
    return sp.Rational(repr(float(value))), sp.Rational(repr(float(rate)))


def _dependent_state(system: Any, subs: dict, dps: int) -> dict:
    """The dependent coordinates' values and rates, solved from the closure equations
    Phi(q, t) = 0 and Phi_q q' + Phi_t = 0 by Newton's method in mpmath at ``dps`` + 15 digits,
    starting from the float64 assembly already in ``subs`` (exact independent values, t
    and parameters); returned as sympy Floats of that precision (symbol -> value).

    Raises
    ------
    SingularConfigurationError
        When the closure Jacobian of the dependent coordinates is singular there.
    """
    dep = [c for c in system.free if c.dependent]
    if not dep or not system.closure:
        return {}
    rows = sp.Matrix([r.expr for r in system.closure])
    q_dep = [c.q for c in dep]
    fixed = {k: v for k, v in subs.items() if k not in q_dep and k not in [c.qd for c in dep]}
    digits = dps + 15
    with mpmath.workdps(digits):
        num = {k: mpmath.mpf(str(sp.N(v, digits + 5))) for k, v in fixed.items()}
        args = (*q_dep, *num.keys())
        f_phi = lambdify(args, list(rows), "mpmath")
        f_jac = lambdify(args, rows.jacobian(q_dep).tolist(), "mpmath")
        x = [mpmath.mpf(str(sp.N(subs[q], 20))) for q in q_dep]
        for _ in range(2 * digits):  # quadratic convergence from a float64 start: a few steps
            J = mpmath.matrix(f_jac(*x, *num.values()))
            r = mpmath.matrix(f_phi(*x, *num.values()))
            try:
                step = mpmath.lu_solve(J, -r) if J.rows == J.cols else mpmath.qr_solve(J, -r)[0]
            except ZeroDivisionError:
                raise SingularConfigurationError(f"{system.label}: the closure equations are singular at "
                                                 "the state (a dead centre)") from None
            x = [a + b for a, b in zip(x, step)]
            if mpmath.norm(step) <= mpmath.mpf(10) ** (-digits) * (1 + mpmath.norm(mpmath.matrix(x))):
                break
        out = {q: sp.Float(str(v), digits) for q, v in zip(q_dep, x)}
        # rates: Phi_q q' + Phi_t = 0, i.e. J_dep q'_dep = -(J_ind q'_ind + Phi_t)
        at = {**fixed, **out}
        rate_rows = rows.jacobian([c.q for c in system.free]) * sp.Matrix([c.qd for c in system.free]) \
            + sp.diff(rows, system.t)
        A = rate_rows.jacobian([c.qd for c in dep])
        b = -rate_rows.xreplace({c.qd: 0 for c in dep})
        Am = mpmath.matrix([[mpmath.mpf(str(sp.N(e.xreplace(at), digits))) for e in A.row(i)] for i in range(A.rows)])
        bm = mpmath.matrix([mpmath.mpf(str(sp.N(e.xreplace(at), digits))) for e in b])
        rates = mpmath.lu_solve(Am, bm) if Am.rows == Am.cols else mpmath.qr_solve(Am, bm)[0]
        out.update({c.qd: sp.Float(str(v), digits) for c, v in zip(dep, rates)})
    return out


@dataclass(frozen=True)
class PreciseSolution:
    """Instantaneous unknowns in one arithmetic.

    Attributes
    ----------
    precision : str
        ``"float64"``, ``"exact"`` or ``"mpmath"``.
    dps : int
        Decimal digits (53 bits ~ 15.95 for float64; the evaluation digits of
        an exact answer).
    unknowns : dict[str, Any]
        Values in SI: floats, exact sympy expressions, or mpmath numbers.
        Includes ``alpha``.
    text : dict[str, str]
        Each value printed to ``dps`` digits (the exact expression's value).
    condition_number : float
        The exact condition number of A (float64; 1-norm, rows and columns equilibrated,
        :func:`solver.analyses.instant.condition_numbers`).
    float64_error : dict[str, float]
        |float64 - this| / |this| per unknown (0 for the float64 solve).
    error_bound : dict[str, float]
        A bound on each unknown's float64 relative error (:func:`solver.analyses.instant.error_bounds`
        over its size; inf for an unknown computed as 0 with a bound above 0); empty where the
        entries' round-off cannot be sized (a function the walk does not know).
    units : dict[str, str]
    exact_form : dict[str, str]
        The exact answers as expressions (none with dependent coordinates).
    note : str
        What the answer rests on besides the scene's exact values, if anything.
    """

    precision: str
    dps: int
    unknowns: dict[str, Any]
    text: dict[str, str]
    condition_number: float
    float64_error: dict[str, float] = field(default_factory=dict)
    units: dict[str, str] = field(default_factory=dict)
    exact_form: dict[str, str] = field(default_factory=dict)
    note: str = ""
    error_bound: dict[str, float] = field(default_factory=dict)

    def to_dict(self) -> dict:
        out = {
            "precision": self.precision,
            "dps": self.dps,
            "unknowns": {n: {"value": float(self.text[n]),
                             "text": self.text[n], "unit": self.units.get(n, "")}
                         for n, v in self.unknowns.items()},
            "condition_number": self.condition_number,
            "float64_relative_error": {n: v if math.isfinite(v) else None for n, v in self.float64_error.items()},
        }
        if self.error_bound:
            out["float64_relative_error_bound"] = {n: v if math.isfinite(v) else None for n, v in self.error_bound.items()}
        if self.exact_form:
            out["exact"] = self.exact_form
        if self.note:
            out["note"] = self.note
        return out


def _validate_solve_precise(precision: str, dps: int) -> None:
    if precision not in PRECISIONS:
        raise ValueError(f"`precision` must be one of {PRECISIONS}, got {precision!r}")
    if not (isinstance(dps, int) and MIN_DPS <= dps <= MAX_DPS):
        raise InputError(f"--dps must be an integer from {MIN_DPS} to {MAX_DPS}, got {dps!r}")


def solve_precise(derivation: Any, precision: str = "float64", dps: int = 50,
                  state: tuple[Any, Any] | None = None,
                  parameters: Mapping[sp.Symbol, Any] | None = None,
                  assembled: Any = None) -> PreciseSolution:
    """Solve A x = b at the scene's state in the chosen arithmetic.

    Parameters
    ----------
    derivation : solver.derivation.Derivation
    precision : {"float64", "exact", "mpmath"}
    dps : int
        Digits for mpmath (and for printing the exact answer).
    state : (theta, theta_dot), optional
        Exact sympy numbers (or floats) overriding the first coordinate's state. [rad, rad/s]
    parameters : mapping, optional
        Exact values overriding the scene's (symbol -> number).
    assembled : solver.analyses.instant.State, optional
        The float64 state of every free coordinate (and t), dependent ones solved from the
        closure equations; default the scene's, assembled. The independent coordinates take
        the exact values the scene wrote when they are the scene's; the dependent ones are
        solved again from the closure equations to ``dps`` + 15 digits.

    Returns
    -------
    PreciseSolution

    Raises
    ------
    SingularConfigurationError
        When A is singular (exactly, or numerically in float64/mpmath).
    """
    _validate_solve_precise(precision, dps)
    d = derivation
    system = d.system
    params = {sp.Symbol(n, real=True): exact_quantity(q) for n, q in system.parameters.items()}
    if parameters:
        params.update({k: sp.nsimplify(v) if isinstance(v, float) else v for k, v in parameters.items()})
    subs = _exact_state(system, params, state, assembled, dps)
    A, b = d.linear_system()
    names = [str(u) for u in d.unknowns]
    units = {str(c.qdd): "rad/s**2" if c.kind == "angle" else "m/s**2" for c in system.free}
    units["alpha"] = "rad/s**2"
    units.update(d.reaction_units)
    coords = [c.q for c in system.free] + [c.qd for c in system.free] + [system.t]
    args = (*coords, *params.keys())
    accelerations = [c.qdd for c in system.free]
    # the body's alpha only for a one-body scene; linear in the accelerations
    alpha_expr = d.alpha if len(system.bodies) == 1 else None
    where = f"{system.label}: singular configuration at {_state_words(system, subs)}"

    # float64 ---------------------------------------------------------------
    fA = lambdify(args, [list(A.row(i)) for i in range(A.rows)] + [list(b)], "numpy")
    fvals = [float(sp.N(subs[a], 20)) for a in args]
    with np.errstate(all="ignore"):
        out = fA(*fvals)
    Af = np.array(out[:-1], dtype=float)
    bf = np.array(out[-1], dtype=float)
    cond = float(condition_numbers(Af[None])[0])  # the exact one, as `solve` estimates it
    if not math.isfinite(cond) or cond > 1e16:
        raise SingularConfigurationError(f"{where} (condition number {cond:.3g})")
    if not np.all(np.isfinite(bf)):  # a force without a direction (a spring of zero length)
        n = len(system.free)
        refuse_zero_length(system, fvals[:n], fvals[n:2 * n], fvals[2 * n])
        raise SingularConfigurationError(f"{where}: the equations' right-hand side is not finite there")
    xf = refine(Af, bf, solve_with_estimate(Af[None], bf[None])[0][0])  # as `solve` does
    fl = {n: float(x) for n, x in zip(names, xf)}
    bound = _relative_bounds(A, b, args, fvals, Af, bf, xf, names)
    if alpha_expr is not None:
        falpha = lambdify((*args, *accelerations), alpha_expr, "math")
        fl["alpha"] = float(falpha(*fvals, *[fl[str(a)] for a in accelerations]))
        if bound:
            bound["alpha"] = max(bound[str(a)] for a in accelerations)

    if precision == "float64":
        text = {n: repr(v) for n, v in fl.items()}
        return PreciseSolution("float64", 16, fl, text, cond, {n: 0.0 for n in fl}, units, error_bound=bound)

    if precision == "exact":
        # rational values are substituted; the coordinates and irrational values (angles:
        # multiples of pi; dependent coordinates solved to many digits) stay symbols until the
        # end, so that sympy never expands e.g. sin(41 pi/120) into nested radicals, nor meets
        # sin(1/2), which has no closed value
        # A dependent coordinate has no closed value: its value and rate, solved to dps + 15
        # digits, enter as those exact decimals, and so do the sines and cosines of them.
        solved = {k: subs[k] for c in system.free if c.dependent for k in (c.q, c.qd)}
        A, b = _as_rationals(A.xreplace(solved)), _as_rationals(b.xreplace(solved))
        # the state (coordinates, rates, t) stays symbolic too, so that the exact forms read as
        # formulas in it and the "at ..." line lists every value they need
        state = {c.q for c in system.free} | {c.qd for c in system.free} | {system.t}
        rational = {k: v for k, v in subs.items()
                    if k not in solved and sp.sympify(v).is_Rational and k not in state}
        kept = {k: v for k, v in subs.items() if k not in rational and k not in solved}
        x = _exact_solve(A.xreplace(rational), b.xreplace(rational), kept, where)
        sym = {n: x[i] for i, n in enumerate(names)}
        if alpha_expr is not None:
            sym["alpha"] = alpha_expr.xreplace(rational).xreplace({a: sym[str(a)] for a in accelerations})
        vals = {n: _exact_value(v, kept) for n, v in sym.items()}
        # an answer sympy finds to be 0 exactly (sin(pi)) is 0, not the evalf of its form at a
        # many-digit pi (-1.9e-65)
        text = {n: "0" if vals[n] == 0 else str(_evalf(v, kept, dps)) for n, v in sym.items()}
        err = {n: _relerr(fl[n], 0 if vals[n] == 0 else _evalf(v, kept, dps + 5)) for n, v in sym.items()}
        at = ", ".join(f"{k} = {v}" for k, v in kept.items() if _uses(sym, k))
        # with dependent coordinates the closed form holds their many-digit values: not shown
        exact_form = {} if solved else {n: str(tidy(v)) + (f"   at {at}" if at else "") for n, v in sym.items()}
        return PreciseSolution("exact", dps, vals, text, cond, err, units, exact_form, _note(system, dps), bound)

    # mpmath ----------------------------------------------------------------
    with mpmath.workdps(dps + 5):
        mvals = [mpmath.mpf(str(sp.N(subs[a], dps + 10))) for a in args]
        fm = lambdify(args, [list(A.row(i)) for i in range(A.rows)] + [list(b)], "mpmath")
        rows = fm(*mvals)
        Am = mpmath.matrix(rows[:-1])
        bm = mpmath.matrix(rows[-1])
        try:
            xm = mpmath.lu_solve(Am, bm)
        except ZeroDivisionError:
            raise SingularConfigurationError(where) from None
        vals = {n: xm[i] for i, n in enumerate(names)}
        if alpha_expr is not None:
            malpha = lambdify((*args, *accelerations), alpha_expr, "mpmath")
            vals["alpha"] = malpha(*mvals, *[vals[str(a)] for a in accelerations])
        text = {n: mpmath.nstr(v, dps) for n, v in vals.items()}
        err = {n: _relerr(fl[n], v) for n, v in vals.items()}
    return PreciseSolution("mpmath", dps, vals, text, cond, err, units, note=_note(system, dps), error_bound=bound)


def _relative_bounds(A, b, args, fvals, Af, bf, xf, names) -> dict[str, float]:
    """Each unknown's float64 relative error bound: :func:`solver.analyses.instant.error_bounds`
    over its size (at least u, the rounding of the answer itself); {} where the entries cannot
    be sized."""
    sizes = entry_sizes([*A, *b], dict(zip(args, fvals)))
    if sizes is None or not np.all(np.isfinite(sizes)):
        return {}
    n = A.rows * A.cols
    bounds = error_bounds(Af, bf, xf, sizes[:n].reshape(A.rows, A.cols), sizes[n:])
    out = {}
    for name, e, x in zip(names, bounds, xf):
        out[name] = max(float(e) / abs(float(x)), ROUND_OFF) if x else (0.0 if e == 0 else math.inf)
    return out


def _as_rationals(matrix: sp.Matrix) -> sp.Matrix:
    """``matrix`` with every floating-point number (a function of a solved dependent
    coordinate, evaluated at its precision) replaced by the rational it stands for exactly."""
    floats = set().union(*(sp.sympify(e).atoms(sp.Float) for e in matrix)) if len(matrix) else set()
    return matrix.xreplace({f: sp.Rational(f) for f in floats})


def _note(system: Any, dps: int) -> str:
    """What the answer rests on besides the scene's exact values (dependent coordinates)."""
    dependent = [c.name for c in system.free if c.dependent]
    if not dependent or not system.closure:
        return ""
    return (f"the dependent coordinate(s) {', '.join(dependent)} and their rates are solved from the closure "
            f"equations to {dps + 15} digits; the answer is exact at those values")


def _uses(solution: Mapping[str, sp.Expr], symbol: sp.Symbol) -> bool:
    """Whether any exact answer still holds ``symbol``."""
    return any(sp.sympify(v).has(symbol) for v in solution.values())


def _exact_state(system: Any, params: dict, state: tuple[Any, Any] | None, assembled: Any, dps: int) -> dict:
    """symbol -> exact (or ``dps`` + 15 digit) value of every parameter, coordinate, rate and t."""
    from .analyses.instant import assemble

    st = assemble(system) if assembled is None else assembled
    subs = dict(params)
    subs[system.t] = sp.Rational(repr(float(st.t)))
    for c, v, r in zip(system.free, st.q, st.qd):
        subs[c.q], subs[c.qd] = _exact_coordinate(c, v, r)
    if state is not None:
        c = system.free[0]
        subs[c.q], subs[c.qd] = sp.sympify(state[0]), sp.sympify(state[1])
    subs.update(_dependent_state(system, subs, dps))
    return subs


def _state_words(system: Any, subs: Mapping) -> str:
    """``theta = 30 deg, x = 1.2 m`` (the free coordinates, for messages)."""
    parts = []
    for c in system.free:
        v = float(sp.N(subs[c.q], 20))
        parts.append(f"{c.name} = {math.degrees(v):.6g} deg" if c.kind == "angle" else f"{c.name} = {v:.6g} m")
    return ", ".join(parts)


def _evalf(expr: sp.Expr, kept: Mapping, dps: int) -> sp.Float:
    """expr at the kept symbols' exact values, to ``dps`` digits (numeric substitution, no expansion)."""
    return sp.sympify(expr).evalf(dps, subs={k: sp.N(v, dps + 15) for k, v in kept.items()})


def _exact_value(expr: sp.Expr, kept: Mapping) -> sp.Expr:
    """expr with the kept symbols replaced by their exact values (sympy evaluates what it can)."""
    return sp.sympify(expr).xreplace(dict(kept))


def _exact_solve(A: sp.Matrix, b: sp.Matrix, kept: Mapping, where: str) -> sp.Matrix:
    """Solve A x = b exactly; A and b hold rationals and the ``kept`` symbols (exact angles).

    Every function of the kept symbols (sin(theta), cos(beta - theta), ...), and
    every irrational number (sqrt(3), pi), is
    replaced by a fresh symbol, and the system is solved over the field of
    rational functions in those symbols and the kept symbols (sympy
    DomainMatrix: fraction-free, exact, fast). By Cramer's rule the solution
    is det(A_i) / det(A), a polynomial identity in the atoms, so putting the
    atoms back is exact whenever det(A) != 0 at the actual values, which is
    checked to 50 digits.
    """
    from sympy.polys.matrices import DomainMatrix

    exprs = [sp.sympify(e) for e in list(A) + list(b)]
    atoms: set = set()
    for e in exprs:  # (numbers too: an advisor point's coordinate may be sqrt(3)/20)
        atoms |= {a for a in e.atoms(sp.Function) if a.free_symbols or not a.is_Rational}
        atoms |= {a for a in e.atoms(sp.Pow) if not a.exp.is_Integer and (a.free_symbols or not a.is_Rational)}
    ordered = sorted(atoms, key=lambda a: (-sp.count_ops(a), sp.default_sort_key(a)))  # (ties: not the set's order)
    # pi, E, ... outside the functions: more generators of the field
    ordered += sorted({c for e in exprs for c in e.atoms(sp.NumberSymbol)}, key=str)
    syms = sp.symbols(f"_atom0:{len(ordered)}")
    rep = dict(zip(ordered, syms))
    back = dict(zip(syms, ordered))
    As, bs = A.xreplace(rep), b.xreplace(rep)
    gens = tuple(syms) + tuple(sorted((As.free_symbols | bs.free_symbols) - set(syms), key=str))
    stray = [g for g in gens if g not in syms and g not in kept]
    if stray or As.atoms(sp.Function) or bs.atoms(sp.Function):
        raise InputError(f"{where}: cannot solve exactly (left-over {stray or As.atoms(sp.Function)})")
    dom = sp.QQ.frac_field(*gens) if gens else sp.QQ
    dA = DomainMatrix.from_Matrix(As).convert_to(dom)
    db = DomainMatrix.from_Matrix(bs).convert_to(dom)
    rows = _polynomial_rows(dA, db) if gens else None
    det_dom = dA.det() if rows is None else _det_from_rows(dom, *rows)
    det = dom.to_sympy(det_dom).xreplace(back)
    det_value = None if det == 0 else _evalf(det, kept, 50)
    if det == 0 or det_value == 0 or abs(det_value) < sp.Float(10) ** -40 * max(
            sp.Float(1), *[abs(_evalf(e.xreplace(back), kept, 5)) for e in list(As)]) ** A.rows:
        raise SingularConfigurationError(f"{where}: the linear system is exactly singular (det A = 0)")
    x = dA.lu_solve(db) if rows is None else _solve_rows(dom, *rows)
    return x.to_Matrix().xreplace(back)


def _polynomial_rows(dA, db) -> tuple:
    """(A', b', multipliers): each row of A x = b over the field of rational functions times the
    least common multiple of its denominators, so that A' and b' hold polynomials.

    The field's elements are kept in lowest terms with a normalised denominator (one way of
    writing each), so that the answers over the polynomials below are the very elements
    ``DomainMatrix.det`` and ``lu_solve`` give over the field, at about a quarter of the work:
    elimination without fractions (``solve_den``) instead of a greatest common divisor at every
    step."""
    from sympy.polys.matrices import DomainMatrix

    field = dA.domain
    ring = field.get_ring()
    n, m = dA.shape[0], db.shape[1]
    rows, multipliers = [], []
    for ra, rb in zip(dA.to_list(), db.to_list()):
        lcm = ring.one
        for e in ra + rb:
            lcm = lcm.lcm(e.denom)
        row = []
        for e in ra + rb:
            f = e * field(lcm)  # a polynomial: its denominator is a number
            row.append(f.numer if f.denom.LC == 1 else f.numer.quo_ground(f.denom.LC))
        rows.append(row)
        multipliers.append(lcm)
    return (DomainMatrix([r[:n] for r in rows], (n, n), ring), DomainMatrix([r[n:] for r in rows], (n, m), ring),
            multipliers)


def _det_from_rows(field, A, b, multipliers):
    """det of the field's matrix from :func:`_polynomial_rows`: det A' over the row multipliers."""
    det = field(A.det())
    for lcm in multipliers:
        det = det / field(lcm)
    return det


def _solve_rows(field, A, b, multipliers):
    """The solution of A' x = b' (:func:`_polynomial_rows`) as a matrix over the field."""
    from sympy.polys.matrices import DomainMatrix

    numerators, denominator = A.solve_den(b)
    d = field(denominator)
    return DomainMatrix([[field(e) / d for e in row] for row in numerators.to_list()], numerators.shape, field)


def _relerr(approx: float, ref) -> float:
    """|approx - ref| / |ref|; against a reference 0, 0 for an approx of 0 and infinite otherwise
    (no relative error is defined: the tables give the absolute one, JSON null)."""
    ref = mpmath.mpf(str(ref)) if not isinstance(ref, mpmath.mpf) else ref
    if ref == 0:
        return 0.0 if approx == 0 else math.inf
    return float(abs((mpmath.mpf(approx) - ref) / ref))
