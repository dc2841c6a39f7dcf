"""Display forms built from structure: trigonometric tidying without ``simplify``.

A displayed coefficient is a rational function of the parameters and of
sin/cos of the angles. :func:`reduce_trig` writes its numerator and its
denominator as polynomials in S = sin(a), C = cos(a) for every angle a and
reduces each modulo S**2 + C**2 - 1 (so ``2*sin**4 + 4*sin**2*cos**2 + sin**2 +
2*cos**4 + cos**2`` becomes 3); :func:`tidy` keeps, per part, whichever of the
reduced and the original form is shorter. Both are polynomial arithmetic:
their cost grows with the size of the expression, not unpredictably as
``simplify``'s does.
"""
from __future__ import annotations

import cmath
from functools import lru_cache, reduce

import sympy as sp
from sympy.core.exprtools import gcd_terms
from sympy.core.mul import _keep_coeff

__all__ = ["reduce_trig", "tidy", "tidy_fraction", "tidy_linear", "is_identically_zero", "MAX_TIDY_NODES"]

MAX_CANCEL_NODES = 120
"""Above this size a single fraction of polynomials is not passed through ``cancel`` (the common
factors it would remove cost more to find than they save on display)."""
MAX_TIDY_NODES = 1000
"""Expressions with more nodes than this are shown as built (tidying would cost more than it saves)."""


def _angles_ok(expr: sp.Expr) -> bool:
    """Whether every sin/cos argument is free of sin/cos itself (then the arguments are
    independent generators: sin(a)**2 + cos(a)**2 = 1 per argument a, after expand_trig)."""
    return all(not f.args[0].has(sp.sin, sp.cos, sp.tan) for f in expr.atoms(sp.sin, sp.cos))


def _is_sine_square(x) -> bool:
    return x.is_Pow and isinstance(x.base, sp.sin) and x.exp.is_Integer and x.exp >= 2


def _lower_sine(x):
    a = x.base.args[0]
    return sp.sin(a) ** (int(x.exp) % 2) * (1 - sp.cos(a) ** 2) ** (int(x.exp) // 2)


def _reduce_poly(poly: sp.Expr) -> sp.Expr:
    """A polynomial in sin/cos, reduced modulo sin(a)**2 + cos(a)**2 - 1 for every argument a:
    each sin(a)**n, n >= 2, becomes sin(a)**(n mod 2) (1 - cos(a)**2)**(n // 2), then expanded.
    This is the remainder of the division by the Groebner basis {sin**2 + cos**2 - 1} with
    sin ahead of cos, a canonical form: an identically zero polynomial reduces to 0."""
    p = sp.expand(poly)
    if not any(_is_sine_square(x) for x in p.atoms(sp.Pow)):
        return p
    return sp.expand(p.replace(_is_sine_square, _lower_sine))


def reduce_trig(expr: sp.Expr) -> sp.Expr | None:
    """Normal form of a rational expression in sin/cos of plain symbols, or None.

    tan and cot become sin/cos, sums of angles are expanded, numerator and
    denominator are reduced modulo sin**2 + cos**2 - 1 (sin**2 replaced by
    1 - cos**2: the remainder by a Groebner basis, so an expression that is
    identically zero reduces to 0). None when a trigonometric argument is not a
    plain symbol after expansion (e.g. ``sin(t**2)``).
    """
    e = sp.sympify(expr)
    e = e.replace(sp.tan, lambda a: sp.sin(a) / sp.cos(a)).replace(sp.cot, lambda a: sp.cos(a) / sp.sin(a))
    e = sp.expand_trig(e)
    if not _angles_ok(e):
        return None
    num, den = sp.fraction(sp.cancel(_together(e)))
    return sp.cancel(_reduce_poly(num) / _reduce_poly(den))


_PROBES = 2
"""Random points at which an expression is evaluated before the exact test."""


class _NotFloat(Exception):
    """An expression node that :func:`_complex_value` does not evaluate."""


_FUNCTIONS = {sp.sin: cmath.sin, sp.cos: cmath.cos, sp.tan: cmath.tan, sp.exp: cmath.exp, sp.log: cmath.log,
              sp.sinh: cmath.sinh, sp.cosh: cmath.cosh, sp.tanh: cmath.tanh}


def _complex_value(e: sp.Expr, point: dict) -> complex:
    """``e`` at ``point`` (symbol -> float) in double-precision complex arithmetic, walking the tree
    once (no sympy Float arithmetic). Raises _NotFloat at a node it does not know."""
    if e.is_Symbol:
        return point[e]
    if e.is_Number:
        return complex(e)
    if e.is_Add:
        return sum((_complex_value(a, point) for a in e.args), 0j)
    if e.is_Mul:
        out = 1 + 0j
        for a in e.args:
            out *= _complex_value(a, point)
        return out
    if e.is_Pow:
        base, exp = _complex_value(e.base, point), e.exp
        return base ** (int(exp) if exp.is_Integer else _complex_value(exp, point))
    f = _FUNCTIONS.get(type(e))
    if f is not None:
        return f(_complex_value(e.args[0], point))
    if e.is_number:
        return complex(e)
    raise _NotFloat


def _term_values(expr: sp.Expr, point: dict) -> list[complex]:
    """The value of each term of ``expr`` at ``point``: in double precision when every node is
    known to :func:`_complex_value`, else by sympy's evalf."""
    terms = sp.Add.make_args(expr)
    try:
        return [_complex_value(t, point) for t in terms]
    except _NotFloat:
        floats = {s: sp.Float(v) for s, v in point.items()}
        return [complex(t.xreplace(floats).evalf(20)) for t in terms]


def _numerically_nonzero(expr: sp.Expr) -> bool:
    """True when ``expr`` is clearly nonzero at a random point (a cheap first test:
    a nonzero value far above round-off proves it nonzero; zero is then decided exactly)."""
    symbols = sorted(expr.free_symbols, key=lambda s: s.name)
    for k in range(_PROBES):
        point = {s: 0.3 + 0.137 * ((i + 3 * k) % 7) + 0.01 * i for i, s in enumerate(symbols)}
        try:
            values = _term_values(expr, point)
        except (TypeError, ValueError, ZeroDivisionError, OverflowError):
            continue
        value = sum(values, 0j)
        scale = max(1.0, *(abs(v) for v in values))
        # Double precision: the round-off of a sum of n terms of products is ~n 1e-16 of the scale,
        # so 1e-12 of it is far above round-off for any expression we tidy (at most
        # MAX_TIDY_NODES nodes) and a smaller value is left to the exact test.
        if not cmath.isnan(value) and abs(value) > 1e-12 * scale:
            return True
    return False


@lru_cache(maxsize=4096)
def is_identically_zero(expr: sp.Expr) -> bool | None:
    """True/False when :func:`reduce_trig` decides it, None when it cannot."""
    if expr == 0:
        return True
    if _numerically_nonzero(expr):
        return False
    reduced = reduce_trig(expr)
    if reduced is None:
        return None
    return reduced == 0


def _plain_polynomial(p: sp.Expr) -> bool:
    """A sum of monomials: products of non-sum factors with positive integer exponents."""
    for t in sp.Add.make_args(p):
        for base, exp in t.as_powers_dict().items():
            if base.is_Add or base.is_Mul or not (exp.is_Integer and exp > 0):
                return False
    return True


def _gathered_sum(terms) -> sp.Expr | None:
    """``sympy.gcd_terms(terms)`` for a sum of monomials with monomial denominators, in one pass:
    the positive rational content times the monomial common to the terms (negative exponents: the
    least common denominator) times the primitive sum left. None when a term is not such a
    monomial (a fractional power, for one), where ``gcd_terms`` itself is needed. A power of a sum
    counts as one factor, its rational content moved into the coefficient, as in ``gcd_terms``.

    The same expression as ``gcd_terms`` (the terms keep their signs; the content is positive),
    built without its ``Factors`` machinery (most of the cost of ``together``).
    """
    if len(terms) < 2:
        return None
    coeffs, powers = [], []
    for t in terms:
        c, rest = t.as_coeff_Mul()
        if not c.is_Rational:
            return None
        d = {}
        for base, exp in rest.as_powers_dict().items():
            if base.is_Mul or base.is_number or not exp.is_Integer:
                return None
            if base.is_Add:  # a denominator: its rational content joins the coefficient (as gcd_terms)
                if exp > 0 or not _plain_polynomial(base):
                    return None  # (sums as factors, nested fractions: gcd_terms' own forms)
                content, base = base.primitive()
                c = c * content**exp
            d[base] = d.get(base, 0) + exp
        coeffs.append(c)
        powers.append(d)
    common = {}
    for base in set().union(*powers):
        low = min(d.get(base, sp.S.Zero) for d in powers)
        if low != 0:
            common[base] = low
    content = reduce(lambda a, b: a.gcd(b), coeffs)
    rest = sp.Add(*[(c / content) * sp.Mul(*[b**(d.get(b, 0) - low) for b, low in common.items()],
                                           *[b**x for b, x in d.items() if b not in common])
                    for c, d in zip(coeffs, powers)])
    if rest.is_Add:  # a number distributed over a sum factor can leave content (as in gcd_terms)
        more, rest = rest.primitive()
        content = content * more
    return _keep_coeff(content, sp.Mul(*[b**x for b, x in common.items()], rest))


def _together(e: sp.Expr) -> sp.Expr:
    """``sympy.together(e)``, the same expression: its recursion, with :func:`_gathered_sum` in
    place of ``gcd_terms`` for the sums it can gather (all of them in the display forms here)."""
    if e.is_Atom or e.is_Function:
        return e
    if e.is_Add:
        terms = [_together(t) for t in e.args]
        gathered = _gathered_sum(terms)
        return gathered if gathered is not None else gcd_terms(terms, fraction=True)
    if e.is_Pow:
        return e.func(_together(e.base), e.exp)
    return e.func(*[_together(a) for a in e.args])


def _monomial_powers(d: sp.Expr) -> dict | None:
    """{base: exponent} of a product of powers (a monomial denominator), else None."""
    out = {}
    for f in sp.Mul.make_args(d):
        base, exp = f.as_base_exp()
        if base.is_Add or not exp.is_Integer or exp < 0:
            return None
        if base.is_number:
            base, exp = f, sp.Integer(1)
        out[base] = out.get(base, 0) + exp
    return out


def _over_common_denominator(e: sp.Expr) -> tuple[sp.Expr, sp.Expr]:
    """(numerator, denominator) of ``e``: when every term's denominator is a monomial, over their
    least common multiple (one pass, no recursion); otherwise sympy's ``together``."""
    e = sp.expand(e)
    parts = [sp.fraction(t) for t in sp.Add.make_args(e)]
    powers = [_monomial_powers(d) for _, d in parts]
    if any(p is None for p in powers):
        return sp.fraction(_together(e))
    lcm: dict = {}
    for p in powers:
        for base, exp in p.items():
            if base.is_number:
                continue
            lcm[base] = max(lcm.get(base, 0), exp)
    numbers = [sp.Mul(*[b for b in p if b.is_number]) for p in powers]
    scale = reduce(sp.ilcm, [int(sp.fraction(x)[0]) if x.is_Rational and x != 0 else 1 for x in numbers], 1)
    den = sp.Integer(scale) * sp.Mul(*[b**x for b, x in lcm.items()])
    num = sp.Add(*[n * (den / d) for n, d in parts])
    return sp.expand(num), den


def _is_trig_denominator(x) -> bool:
    return x.is_Pow and x.exp.is_negative and x.base.is_Add and x.base.has(sp.sin, sp.cos)


def _reduce_denominators(e: sp.Expr) -> sp.Expr:
    """Every denominator that is a polynomial in sin/cos reduced modulo sin**2 + cos**2 = 1
    (``(sin(g)**2 + cos(g)**2)**2`` becomes 1): the cheap structural step that removes a
    printed denominator equal to a constant."""
    if not any(_is_trig_denominator(x) for x in e.atoms(sp.Pow)):
        return e
    return e.replace(_is_trig_denominator, lambda x: _reduce_poly(x.base) ** x.exp)


def _size(e: sp.Expr) -> int:
    """Number of nodes of the expression tree (a cheap stand-in for ``count_ops``)."""
    return sum(1 for _ in sp.preorder_traversal(e))


def _monomial_denominators(e: sp.Expr) -> bool:
    return all(_monomial_powers(sp.fraction(t)[1]) is not None for t in sp.Add.make_args(e))


def _has_denominator(e: sp.Expr) -> bool:
    return any(x.exp.is_negative for x in e.atoms(sp.Pow))


def _denominator_free(p: sp.Expr) -> bool:
    """No negative powers: a polynomial in its symbols and its sin/cos terms."""
    return not any(x.exp.is_negative for x in p.atoms(sp.Pow))


def _has_square(p: sp.Expr) -> bool:
    """Whether some sin(a)**n with n >= 2 appears (only then can the reduction change anything)."""
    return any(isinstance(x.base, sp.sin) and x.exp.is_Integer and x.exp >= 2 for x in p.atoms(sp.Pow))


def _tidy_polynomial(p: sp.Expr) -> sp.Expr:
    """Expanded, reduced modulo sin**2 + cos**2 = 1 when that leaves fewer terms, common factors out."""
    p = sp.expand(p)
    if _has_square(p):
        reduced = _reduce_poly(p)
        if len(sp.Add.make_args(reduced)) < len(sp.Add.make_args(p)):
            p = reduced
    return _common_factor(p)


def _common_factor(p: sp.Expr) -> sp.Expr:
    """``p`` with the monomial common to all its terms (symbols, sin/cos powers, the rational
    content) written in front: what ``factor_terms`` does for a sum of monomials, in one pass."""
    terms = sp.Add.make_args(p)
    if len(terms) < 2:
        return p
    content, prim = p.primitive()
    terms = sp.Add.make_args(prim)
    powers = [t.as_powers_dict() for t in terms]
    common = {}
    for base, exp in powers[0].items():
        if base.is_number or not (exp.is_Integer and exp > 0):
            continue
        low = min(d.get(base, sp.Integer(0)) for d in powers)
        if low.is_Integer and low > 0:
            common[base] = low
    if not common:
        return content * prim if content != 1 else p
    monomial = sp.Mul(*[b**e for b, e in common.items()])
    rest = [t / monomial for t in terms]
    if all(t.could_extract_minus_sign() for t in rest):  # -(a + b) rather than (-a - b)
        content, rest = -content, [-t for t in rest]
    return content * monomial * sp.Add(*rest)


@lru_cache(maxsize=4096)
def tidy(expr: sp.Expr) -> sp.Expr:
    """A short display form built from the structure of ``expr``: one fraction whose numerator and
    denominator are each reduced modulo sin**2 + cos**2 = 1 (when that shortens them) with their
    common factors pulled out; ``cancel`` only on small expressions.

    Expressions larger than :data:`MAX_TIDY_NODES` are returned as they are; expressions with
    nested trigonometric arguments with only common factors pulled out.
    """
    e = sp.sympify(expr)
    if e.is_number or _size(e) > MAX_TIDY_NODES:
        return e
    e = _reduce_denominators(e)
    if e.has(sp.tan, sp.cot):
        e = e.replace(sp.tan, lambda a: sp.sin(a) / sp.cos(a)).replace(sp.cot, lambda a: sp.cos(a) / sp.sin(a))
    if not _angles_ok(e):
        return sp.factor_terms(e)
    monomial = _monomial_denominators(e)
    small = _size(e) <= MAX_CANCEL_NODES
    if not monomial and small:
        num, den = sp.fraction(sp.cancel(_together(e)))  # common factors out (cheap when small)
    else:
        num, den = _over_common_denominator(e) if _has_denominator(e) else (e, sp.Integer(1))
        if not monomial and not (_denominator_free(num) and _denominator_free(den)):
            num, den = sp.fraction(sp.cancel(_together(e)))
    # (over monomial denominators the common monomial of the numerator cancels by itself below)
    num, den = _tidy_polynomial(num), _tidy_polynomial(den)
    if den.is_number and den != 0 and num.is_Add:
        return sp.factor_terms(sp.expand(num / den))
    return num / den


def _fraction_of_ratio(num: sp.Expr, den: sp.Expr) -> tuple[sp.Expr, sp.Expr]:
    """``sympy.fraction(sympy.together(num / den))``, by :func:`_gathered_sum` on each side when
    both are sums of monomials over monomial denominators (the reactions of the structured solve);
    otherwise by ``together`` itself."""
    top, bottom = _gathered_sum(sp.Add.make_args(num)), _gathered_sum(sp.Add.make_args(den))
    if top is None or bottom is None:
        return sp.fraction(_together(num / den))
    return sp.fraction(top / bottom)


def tidy_fraction(num: sp.Expr, den: sp.Expr) -> sp.Expr:
    """Display form of num/den when both are known polynomials in sin/cos (no ``together``,
    no ``cancel``): each part reduced and factored on its own."""
    num, den = _reduce_denominators(sp.expand(num)), _reduce_denominators(sp.expand(den))
    if _has_denominator(den):
        num, den = _fraction_of_ratio(num, den)
    if _has_denominator(num) and _monomial_denominators(num):
        num, extra = _over_common_denominator(num)
        den = den * extra
    return _tidy_polynomial(num) / _tidy_polynomial(den)


def tidy_linear(expr: sp.Expr, variables) -> sp.Expr:
    """Display form of an expression affine in ``variables`` (accelerations,
    reactions, squared rates): each coefficient tidied on its own, the rest last.

    Parameters
    ----------
    expr : sympy.Expr
    variables : sequence of sympy.Expr
        Symbols or monomials (``theta_dot**2``) in display order.
    """
    e = sp.expand(sp.sympify(expr))
    parts = []
    rest = e
    for v in variables:
        coef = rest.coeff(v) if v.is_Symbol or v.is_Pow else sp.Integer(0)
        if coef != 0 and not coef.has(*[u for u in variables if u.is_Symbol]):
            parts.append(tidy(coef) * v)
            rest = sp.expand(rest - coef * v)
    return sp.Add(*parts, tidy(rest))
