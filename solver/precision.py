"""The instantaneous solve in three arithmetics, and how well float64 does.

At a state (theta, theta_dot) the unknowns x = (theta_ddot, reactions...)
solve the linear system A x = b of the Derivation (for Example 1 the paper's
Eqs. 24, 25 and 28, whose numbers are Eq. 29). This module solves it

* ``"float64"``: numpy, as :func:`solver.derivation.solve_instant` does;
* ``"exact"``: sympy, with every parameter turned into an exact number
  from the decimal text the scene gave (``"32.174 ft/s^2"`` becomes
  Rational(32174, 1000) * Rational(3048, 10000) m/s^2, ``"45 deg"`` becomes
  pi/4): rational arithmetic and exact trigonometric values (sin(pi/6) = 1/2),
  symbolic where no closed value exists;
* ``"mpmath"``: mpmath at ``dps`` significant digits, parameters from the
  same exact values.

and reports the condition number of A (2-norm, float64), which bounds the
relative error of the float64 answer by about cond(A) * 2.2e-16.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Mapping

import mpmath
import numpy as np
import pint
import sympy as sp

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
    """(parameter symbol -> exact SI value, exact theta, exact theta_dot) of a scene."""
    from .derivation import as_system

    system = as_system(scene)
    params = {sp.Symbol(n, real=True): exact_quantity(q) for n, q in system.parameters.items()}
    c = system.free[0]
    if c.given is not None:
        return params, exact_quantity(c.given[0]), exact_quantity(c.given[1])
    return params, sp.Rational(repr(c.value)), sp.Rational(repr(c.rate))


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
        2-norm condition number of A (float64).
    float64_error : dict[str, float]
        |float64 - this| / |this| per unknown (0 for the float64 solve).
    units : dict[str, str]
    """

    precision: str
    dps: int
    unknowns: dict[str, Any]
    text: dict[str, str]
    condition_number: float
    float64_error: dict[str, float] = field(default_factory=dict)
    units: dict[str, str] = field(default_factory=dict)
    exact_form: dict[str, str] = field(default_factory=dict)

    def to_dict(self) -> dict:
        out = {
            "precision": self.precision,
            "dps": self.dps,
            "unknowns": {n: {"value": float(self.text[n]),
                             "text": self.text[n], "unit": self.units.get(n, "")}
                         for n, v in self.unknowns.items()},
            "condition_number": self.condition_number,
            "float64_relative_error": self.float64_error,
        }
        if self.exact_form:
            out["exact"] = self.exact_form
        return out


def _validate_solve_precise(precision: str, dps: int) -> None:
    if precision not in PRECISIONS:
        raise ValueError(f"`precision` must be one of {PRECISIONS}, got {precision!r}")
    if not (isinstance(dps, int) and MIN_DPS <= dps <= MAX_DPS):
        raise InputError(f"--dps must be an integer from {MIN_DPS} to {MAX_DPS}, got {dps!r}")


def solve_precise(derivation: Any, precision: str = "float64", dps: int = 50,
                  state: tuple[Any, Any] | None = None,
                  parameters: Mapping[sp.Symbol, Any] | None = None) -> PreciseSolution:
    """Solve A x = b at the scene's state in the chosen arithmetic.

    Parameters
    ----------
    derivation : solver.derivation.Derivation
    precision : {"float64", "exact", "mpmath"}
    dps : int
        Digits for mpmath (and for printing the exact answer).
    state : (theta, theta_dot), optional
        Exact sympy numbers (or floats) overriding the scene's state. [rad, rad/s]
    parameters : mapping, optional
        Exact values overriding the scene's (symbol -> number).

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
    scene = d.scene
    params, q_ex, qd_ex = exact_values(scene)
    if parameters:
        params.update({k: sp.nsimplify(v) if isinstance(v, float) else v for k, v in parameters.items()})
    if state is not None:
        q_ex, qd_ex = (sp.sympify(state[0]), sp.sympify(state[1]))
    A, b = d.linear_system()
    names = [str(u) for u in d.unknowns]
    units = {names[0]: "rad/s**2", "alpha": "rad/s**2"}
    units.update(d.reaction_units)
    subs = dict(params)
    subs.update({d.q: q_ex, d.qd: qd_ex, d.t: sp.Integer(0)})
    args = (d.q, d.qd, d.t, *params.keys())
    # linear in qdd: alpha = dphi * qdd + ddphi * qd^2; the body's alpha only for a one-body scene
    alpha_expr = d.alpha if len(d.system.bodies) == 1 else None

    # float64 ---------------------------------------------------------------
    fA = lambdify(args, [list(A.row(i)) for i in range(A.rows)] + [list(b)], "numpy")
    fvals = [float(sp.N(v, 20)) for v in params.values()]
    qf, qdf = float(sp.N(q_ex, 20)), float(sp.N(qd_ex, 20))
    with np.errstate(all="ignore"):
        out = fA(qf, qdf, 0.0, *fvals)
    Af = np.array(out[:-1], dtype=float)
    bf = np.array(out[-1], dtype=float)
    with np.errstate(all="ignore"):
        cond = float(np.linalg.cond(Af)) if np.all(np.isfinite(Af)) else math.inf
    if not math.isfinite(cond) or cond > 1e16:
        raise SingularConfigurationError(
            f"{scene.source or scene.name}: singular configuration at {d.q} = {math.degrees(qf):.6g} deg "
            f"(condition number {cond:.3g})"
        )
    xf = np.linalg.solve(Af, bf)
    fl = {n: float(x) for n, x in zip(names, xf)}
    if alpha_expr is not None:
        falpha = lambdify((d.q, d.qd, d.qdd), alpha_expr, "math")
        fl["alpha"] = float(falpha(qf, qdf, fl[names[0]]))

    if precision == "float64":
        text = {n: repr(v) for n, v in fl.items()}
        return PreciseSolution("float64", 16, fl, text, cond, {n: 0.0 for n in fl}, units)

    if precision == "exact":
        # rational values are substituted; irrational ones (angles: multiples of pi) stay symbols
        # until the end, so that sympy never expands e.g. sin(41 pi/120) into nested radicals
        rational = {k: v for k, v in subs.items() if sp.sympify(v).is_Rational}
        kept = {k: v for k, v in subs.items() if k not in rational}
        where = f"{scene.source or scene.name}: singular configuration at {d.q} = {q_ex}"
        x = _exact_solve(A.xreplace(rational), b.xreplace(rational), kept, where)
        sym = {n: x[i] for i, n in enumerate(names)}
        if alpha_expr is not None:
            sym["alpha"] = alpha_expr.xreplace(rational).xreplace({d.qdd: sym[names[0]]})
        vals = {n: _exact_value(v, kept) for n, v in sym.items()}
        text = {n: str(_evalf(v, kept, dps)) for n, v in sym.items()}
        err = {n: _relerr(fl[n], _evalf(v, kept, dps + 5)) for n, v in sym.items()}
        at = ", ".join(f"{k} = {v}" for k, v in kept.items())
        exact_form = {n: str(v) + (f"   at {at}" if at else "") for n, v in sym.items()}
        return PreciseSolution("exact", dps, vals, text, cond, err, units, exact_form)

    # mpmath ----------------------------------------------------------------
    with mpmath.workdps(dps + 5):
        mvals = [mpmath.mpf(str(sp.N(v, dps + 10))) for v in params.values()]
        mq = mpmath.mpf(str(sp.N(q_ex, dps + 10)))
        mqd = mpmath.mpf(str(sp.N(qd_ex, dps + 10)))
        fm = sp.lambdify(args, [list(A.row(i)) for i in range(A.rows)] + [list(b)], modules="mpmath")
        rows = fm(mq, mqd, mpmath.mpf(0), *mvals)
        Am = mpmath.matrix(rows[:-1])
        bm = mpmath.matrix(rows[-1])
        try:
            xm = mpmath.lu_solve(Am, bm)
        except ZeroDivisionError:
            raise SingularConfigurationError(
                f"{scene.source or scene.name}: singular configuration at {d.q} = {math.degrees(qf):.6g} deg"
            ) from None
        vals = {n: xm[i] for i, n in enumerate(names)}
        if alpha_expr is not None:
            malpha = sp.lambdify((d.q, d.qd, d.qdd), alpha_expr, "mpmath")
            vals["alpha"] = malpha(mq, mqd, vals[names[0]])
        text = {n: mpmath.nstr(v, dps) for n, v in vals.items()}
        err = {n: _relerr(fl[n], v) for n, v in vals.items()}
    return PreciseSolution("mpmath", dps, vals, text, cond, err, units)


def _evalf(expr: sp.Expr, kept: Mapping, dps: int) -> sp.Float:
    """expr at the kept symbols' exact values, to ``dps`` digits (numeric substitution, no expansion)."""
    return sp.sympify(expr).evalf(dps, subs={k: sp.N(v, dps + 15) for k, v in kept.items()})


def _exact_value(expr: sp.Expr, kept: Mapping) -> sp.Expr:
    """expr with the kept symbols replaced by their exact values (sympy evaluates what it can)."""
    return sp.sympify(expr).xreplace(dict(kept))


def _exact_solve(A: sp.Matrix, b: sp.Matrix, kept: Mapping, where: str) -> sp.Matrix:
    """Solve A x = b exactly; A and b hold rationals and the ``kept`` symbols (exact angles).

    Every function of the kept symbols (sin(theta), cos(beta - theta), ...) is
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
    for e in exprs:
        atoms |= {a for a in e.atoms(sp.Function) if a.free_symbols}
        atoms |= {a for a in e.atoms(sp.Pow) if a.free_symbols and not a.exp.is_Integer}
    ordered = sorted(atoms, key=lambda a: -sp.count_ops(a))
    if any(e.has(sp.pi) for e in exprs):  # pi outside the functions: one more generator of the field
        ordered.append(sp.pi)
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
    det = dom.to_sympy(dA.det()).xreplace(back)
    if det == 0 or _evalf(det, kept, 50) == 0 or abs(_evalf(det, kept, 50)) < sp.Float(10) ** -40 * max(
            sp.Float(1), *[abs(_evalf(e.xreplace(back), kept, 5)) for e in list(As)]) ** A.rows:
        raise SingularConfigurationError(f"{where}: the linear system is exactly singular (det A = 0)")
    x = dA.lu_solve(db).to_Matrix()
    return x.xreplace(back)


def _relerr(approx: float, ref) -> float:
    ref = mpmath.mpf(str(ref)) if not isinstance(ref, mpmath.mpf) else ref
    if ref == 0:
        return abs(approx)
    return float(abs((mpmath.mpf(approx) - ref) / ref))
