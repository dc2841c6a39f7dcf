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
import math
from fractions import Fraction
from contextlib import contextmanager
from contextvars import ContextVar
from functools import lru_cache, reduce
from typing import NamedTuple
from math import gcd as igcd

import sympy as sp
from sympy.core.exprtools import gcd_terms
from sympy.core.mul import _keep_coeff, _mulsort

from .tree_value import DOUBLE, NotEvaluable, tree_value

__all__ = ["expanded", "reduce_trig", "numerator_reduces_to_zero", "constant_value", "tidy", "positive_parameters", "without_known_abs", "tidy_fraction", "tidy_linear",
           "is_identically_zero", "free_symbols_of", "tree_size", "term_powers", "could_extract_minus_sign", "coefficient",
           "MAX_TIDY_NODES"]

MAX_CANCEL_NODES = 120
"""Above this size a single fraction of polynomials is not passed through ``cancel`` (the common
factors it would remove cost more to find than they save on display)."""
MAX_TIDY_NODES = 1000
"""Expressions with more nodes than this are shown as built (tidying would cost more than it saves)."""


_EXPANDED_TERMS = 20000
"""Most products :func:`expanded` distributes before it leaves an expression to sympy."""


def expanded(expr):
    """``sympy.expand(expr)``: the same object; for a polynomial in the model's atoms by distributing
    its products directly.

    The atoms: symbols, exact rational numbers, the sine and the cosine of a symbol, and integer
    powers of these. A sum of products of atoms and of such sums (and of positive integer powers of
    them) has one expanded form, the sum of its monomials with their rational coefficients
    collected; sympy's ``expand`` reaches it by passing every hint over the whole tree (the model's
    equations of motion and reactions spend most of their time there), :func:`_monomials` lists the
    monomials and ``Add`` collects them. Anything else (another function, a float, a power of a sum
    in the denominator) goes to sympy's own passes (:func:`_sympy_expand`, which skips those that
    cannot change it). Remembered per process, as sympy remembers its own (the display and the
    checks expand many expressions more than once).
    """
    return _expanded(expr) if isinstance(expr, sp.Expr) else sp.expand(expr)


@lru_cache(maxsize=2048)
def _expanded(expr: sp.Expr) -> sp.Expr:
    """:func:`expanded` of an expression."""
    products = _monomials(expr, [0])
    if products is None:
        return _sympy_expand(expr)
    return sp.Add(*[_monomial(p) for p in products])


_EXPAND_HINTS = {"basic": True, "log": True, "multinomial": True, "mul": True, "power_base": True, "power_exp": True}
"""``sympy.expand``'s default hints, as its passes receive them."""


def _sympy_expand(expr: sp.Expr) -> sp.Expr:
    """``sympy.expand(expr)``, the same tree, without the passes over the tree that cannot change it.

    ``expand`` passes each hint over the whole tree (basic, log, multinomial, mul, power_base,
    power_exp), then multinomial, mul and log again until nothing changes; a pass calls the hint's
    method of each node that has one. Here a pass is made only where a node could act on it
    (:func:`_hint_nodes`): a power of a sum for multinomial, a power of a product for power_base,
    and mul always. basic, log and power_exp act only on integrals and sums, logarithms,
    exponentials and powers whose exponent is not a number; an expression that holds one goes to
    ``sympy.expand`` itself. The loop ends without its last pass of mul when that pass is known to
    give the tree back (:func:`_mul_settled`). The passes made are sympy's own, in its order, with
    its hints. (About a fifth less CPU than ``sympy.expand`` on the expressions the display and
    explain tests leave to sympy: sums over denominators that are sums, Abs, roots.)
    """
    from sympy.core.expr import Expr

    def run(e, hint):
        return Expr._expand_hint(e, "_eval_expand_" + hint, deep=True, **_EXPAND_HINTS)[0]

    found = _hint_nodes(expr)
    if found is None:
        return sp.expand(expr)
    e = run(expr, "multinomial") if "multinomial" in found else expr
    e = run(e, "mul")
    found = _hint_nodes(e)
    if found is None:
        return sp.expand(expr)
    if "power_base" in found:
        e = run(e, "power_base")
    while True:
        was = e
        found = _hint_nodes(e)
        if found is None:
            return sp.expand(expr)
        if "multinomial" not in found and _mul_settled(e):
            return e  # (the pass would give e again: the loop's end)
        if "multinomial" in found:
            e = run(e, "multinomial")
        e = run(e, "mul")
        if e == was:
            return e


def _hint_nodes(e: sp.Expr) -> set | None:
    """Which of the passes multinomial and power_base of ``sympy.expand`` could change ``e`` (a power
    of a sum whose exponent's size exceeds 1, a power of a product); None when basic, log or
    power_exp could (see :func:`_sympy_expand`)."""
    found, stack = set(), [e]
    while stack:
        x = stack.pop()
        kind = type(x)
        if kind is sp.Pow:
            base, exp = x.args
            if not exp.is_Number:
                return None
            if base.is_Add and exp.is_Rational and abs(exp.p) > exp.q:
                found.add("multinomial")
            elif base.is_Mul:
                found.add("power_base")
        elif _expand_hints_of(kind):
            return None
        stack.extend(x.args)
    return found


def _mul_settled(e: sp.Expr) -> bool:
    """Whether expand's mul pass gives ``e`` back, known from its nodes: sums, powers of a
    non-number to a rational exponent, function calls and atoms, and products whose factors are
    none of them a sum and whose denominator (see ``sympy.fraction``) is a single factor or holds
    no sum. ``Mul._eval_expand_mul`` rebuilds such a product as its numerator over its denominator,
    which multiplies its own factors together again; a product with a sum among its factors is
    distributed, and a denominator with a sum times another factor is expanded (then False)."""
    stack = [e]
    while stack:
        x = stack.pop()
        kind = type(x)
        if kind is sp.Mul:
            below, sums_below = 0, False
            for f in x.args:
                if type(f) is sp.Pow:
                    if f.exp.is_negative:
                        below += 1
                        sums_below = sums_below or type(f.base) is sp.Add
                elif type(f) is sp.Add or not f.is_commutative:
                    return False
                elif isinstance(f, sp.Rational) and f.q != 1:
                    below += 1
            if below > 1 and sums_below:
                return False
        elif kind is sp.Pow:
            if x.base.is_Number or not isinstance(x.exp, sp.Rational):
                return False
        elif not (kind is sp.Add or x.is_Atom or x.is_Function):
            return False
        stack.extend(x.args)
    return True


@lru_cache(maxsize=None)
def _expand_hints_of(kind: type) -> bool:
    """Whether a node of class ``kind`` (not a power) has a method for expand's basic, log,
    power_exp, power_base or multinomial hint."""
    return any(hasattr(kind, "_eval_expand_" + h) for h in ("basic", "log", "power_exp", "power_base", "multinomial"))


def _monomial(factors: tuple) -> sp.Expr:
    """``Mul(*factors)`` of :func:`expanded`'s atoms, as ``Mul.flatten`` builds it for them: the
    rational coefficient, the exponents of each base summed (x**0 dropped, x**1 as x), the powers
    in sympy's canonical order after the coefficient (when it is not 1); 0 for a zero coefficient
    (the atoms are finite)."""
    coeff = sp.S.One
    powers: dict = {}
    for f in factors:
        if isinstance(f, sp.Rational):
            coeff *= f
        elif type(f) is sp.Pow:
            powers[f.base] = powers.get(f.base, 0) + f.exp
        else:
            powers[f] = powers.get(f, 0) + 1
    if coeff.is_zero:
        return sp.S.Zero
    part = [b if e == 1 else sp.Pow(b, e) for b, e in powers.items() if e != 0]
    _mulsort(part)
    if coeff is not sp.S.One:
        part.insert(0, coeff)
    return sp.Mul._from_args(part, True)


def _expansion_atom(e) -> bool:
    """A factor :func:`expanded` keeps as it is (see there)."""
    kind = type(e)
    if kind is sp.Symbol:
        return e.is_commutative
    if isinstance(e, sp.Rational):
        return True
    if kind is sp.sin or kind is sp.cos:
        return type(e.args[0]) is sp.Symbol
    if kind is sp.Pow:
        base = e.base
        return isinstance(e.exp, sp.Integer) and ((type(base) is sp.Symbol and base.is_commutative) or (
            (type(base) is sp.sin or type(base) is sp.cos) and type(base.args[0]) is sp.Symbol))
    return False


def _monomials(e, count: list) -> list[tuple] | None:
    """The products of atoms whose sum is ``e`` (each a tuple of factors), or None when ``e`` is not
    a polynomial in :func:`expanded`'s atoms or has more than :data:`_EXPANDED_TERMS` of them
    (``count``: the products listed so far)."""
    kind = type(e)
    if _expansion_atom(e):
        return [(e,)]
    if kind is sp.Add:
        out = []
        for a in e.args:
            part = _monomials(a, count)
            if part is None:
                return None
            out += part
        return out
    if kind is sp.Mul:
        out = [()]
        for f in e.args:
            part = [(f,)] if _expansion_atom(f) else _monomials(f, count)
            if part is None:
                return None
            out = _distributed(out, part, count)
            if out is None:
                return None
        return out
    if kind is sp.Pow and isinstance(e.exp, sp.Integer) and 1 < e.exp <= 8 and type(e.base) is sp.Add:
        base = _monomials(e.base, count)
        if base is None:
            return None
        out = [()]
        for _ in range(int(e.exp)):
            out = _distributed(out, base, count)
            if out is None:
                return None
        return out
    return None


def _distributed(left: list, right: list, count: list) -> list[tuple] | None:
    """Every product of a term of ``left`` and a term of ``right``; None past :data:`_EXPANDED_TERMS`."""
    count[0] += len(left) * len(right)
    if count[0] > _EXPANDED_TERMS:
        return None
    return [a + b for a in left for b in right]


def _nodes(e: sp.Basic, kinds) -> set:
    """``e.atoms(*kinds)``, the nodes of those classes, by one walk with a list for a stack (sympy's
    nested generators pay the tree's depth at every node)."""
    out, stack = set(), [e]
    while stack:
        x = stack.pop()
        if isinstance(x, kinds):
            out.add(x)
        stack.extend(x.args)
    return out


class _Shape(NamedTuple):
    """What :func:`tidy` asks of an expression's tree, found in one walk: its number of nodes
    (:func:`tree_size`), its powers and its sin/cos calls (:func:`_nodes` of each)."""

    size: int
    pows: set
    trig: set


def _shape(e: sp.Basic) -> _Shape:
    size, pows, trig, stack = 0, set(), set(), [e]
    while stack:
        x = stack.pop()
        size += 1
        if isinstance(x, sp.Pow):
            pows.add(x)
        elif isinstance(x, (sp.sin, sp.cos)):
            trig.add(x)
        stack.extend(x.args)
    return _Shape(size, pows, trig)


def _angles_ok(expr: sp.Expr, trig: set | None = None) -> bool:
    """Whether every sin/cos argument is free of sin/cos itself (then the arguments are
    independent generators: sin(a)**2 + cos(a)**2 = 1 per argument a, after expand_trig).
    ``trig``: the sin/cos calls of ``expr`` when the caller has them."""
    trig = _nodes(expr, (sp.sin, sp.cos)) if trig is None else trig
    return all(not f.args[0].has(sp.sin, sp.cos, sp.tan) for f in trig)


def _is_sine_square(x) -> bool:
    return x.is_Pow and isinstance(x.base, sp.sin) and x.exp.is_Integer and x.exp.p >= 2


def _lower_sine(x):
    a = x.base.args[0]
    return sp.sin(a) ** (int(x.exp) % 2) * (1 - sp.cos(a) ** 2) ** (int(x.exp) // 2)


def _reduce_poly(poly: sp.Expr, pows: set | None = None) -> sp.Expr:
    """A polynomial in sin/cos, reduced modulo sin(a)**2 + cos(a)**2 - 1 for every argument a:
    each sin(a)**n, n >= 2, becomes sin(a)**(n mod 2) (1 - cos(a)**2)**(n // 2), then expanded.
    This is the remainder of the division by the Groebner basis {sin**2 + cos**2 - 1} with
    sin ahead of cos, a canonical form: an identically zero polynomial reduces to 0. ``pows``:
    the powers of ``poly`` when the caller has them."""
    p = expanded(poly)
    reduced = _replace_powers(p, _is_sine_square, _lower_sine, pows if p is poly else None)
    return p if reduced is p else expanded(reduced)


def _replace_powers(e: sp.Expr, match, rewrite, pows: set | None = None) -> sp.Expr:
    """``e.replace(match, rewrite)`` for a ``match`` that only powers satisfy, in one ``xreplace``
    of the matching powers when none lies inside another (each is then rewritten where it stands,
    as ``replace`` does); else by ``replace`` itself, whose bottom-up order then matters. ``e``
    itself when nothing matches. ``pows``: the powers of ``e`` when the caller has them."""
    found = [x for x in (_nodes(e, sp.Pow) if pows is None else pows) if match(x)]
    if not found:
        return e
    if any(match(y) for x in found for a in x.args for y in _nodes(a, sp.Pow)):
        return e.replace(match, rewrite)
    return e.xreplace({x: rewrite(x) for x in found})


def reduce_trig(expr: sp.Expr) -> sp.Expr | None:
    """Normal form of a rational expression in sin/cos of plain symbols, or None.

    tan and cot become sin/cos, sums of angles are expanded, numerator and
    denominator are reduced modulo sin**2 + cos**2 - 1 (sin**2 replaced by
    1 - cos**2: the remainder by a Groebner basis, so an expression that is
    identically zero reduces to 0). None when a trigonometric argument is not a
    plain symbol after expansion (e.g. ``sin(t**2)``).
    """
    e = sp.sympify(expr)
    polynomial = _ring_polynomial(e)
    if polynomial is not None:
        return sp.cancel(polynomial)
    e = e.replace(sp.tan, lambda a: sp.sin(a) / sp.cos(a)).replace(sp.cot, lambda a: sp.cos(a) / sp.sin(a))
    e = sp.expand_trig(e)
    if not _angles_ok(e):
        return None
    num, den = sp.fraction(sp.cancel(_together(e)))
    return sp.cancel(_reduce_poly(num) / _reduce_poly(den))


def _ring_polynomial(e: sp.Expr) -> sp.Expr | None:
    """The remainder of ``e`` modulo the sin**2 + cos**2 - 1 as an expanded polynomial, when ``e`` is
    a rational function of symbols and sin/cos/tan/cot of symbols whose denominator's remainder
    is a number (:func:`_ring_remainders`); else None.

    :func:`reduce_trig` then gives ``cancel`` of this polynomial, without its own two ``cancel``
    of the whole expression: the denominator d that route reduces divides, times some g, the
    product of denominators met here, whose remainder is a number; so g d is a unit modulo the
    (prime, rational) ideal, where the units are the numbers, and the remainder of d is a number
    too. The two routes then reduce the same class to normal forms that differ by a constant
    factor, the same rational function for ``cancel``, which writes it one way."""
    remainders = _ring_remainders(e, generators=True)
    if remainders is None:
        return None
    num, den, gens = remainders
    if len(den) != 1 or any(next(iter(den))):
        return None
    return _polynomial_expr(num, next(iter(den.values())), gens)


def numerator_reduces_to_zero(expr: sp.Expr) -> bool | None:
    """Whether ``expr`` is identically zero, decided exactly and without ``cancel``: its numerator
    over a common denominator, reduced modulo sin**2 + cos**2 - 1, is 0. None when a
    trigonometric argument is not a plain symbol after expansion.

    Notes
    -----
    Sound and complete for a rational expression in sin/cos of independent angles whose
    denominator is not itself zero: the ideal generated by the sin(a)**2 + cos(a)**2 - 1 is
    prime (each generator is irreducible, also over the complex numbers, in variables of its
    own), so num/den vanishes identically exactly when num lies in it, that is when its
    remainder (:func:`_reduce_poly`) is 0. The same answer as ``reduce_trig(expr) == 0``
    without the greatest common divisors ``cancel`` computes (about 2.5x faster). A rational
    function of symbols and sin/cos/tan/cot of symbols is decided in sympy's sparse polynomials
    (:func:`_ring_numerator_zero`, the same remainder, about 5x faster again), and so is one whose
    sums or multiples of angles become such a function once written out (:func:`_angle_sums_expanded`,
    the expansion the expression route makes); the rest (floats, roots) as expressions.
    """
    e = sp.sympify(expr)
    decided = _ring_numerator_zero(e)
    if decided is not None:
        return decided
    expanded_angles = _angle_sums_expanded(e)
    if expanded_angles is not None:
        decided = _ring_numerator_zero(expanded_angles)
        if decided is not None:
            return decided
    e = e.replace(sp.tan, lambda a: sp.sin(a) / sp.cos(a)).replace(sp.cot, lambda a: sp.cos(a) / sp.sin(a))
    e = sp.expand_trig(e)
    if not _angles_ok(e):
        return None
    num, _ = sp.fraction(_together(e))
    return _reduce_poly(num) == 0


def _angle_sums_expanded(e: sp.Expr) -> sp.Expr | None:
    """``e`` with each sin/cos/tan/cot whose argument is not a plain symbol (cos(beta - theta),
    sin(2*theta)) written out by ``expand_trig`` of that call alone: the same function, which the
    ring route (:func:`_ring_numerator_zero`) can then take when every argument has become a
    symbol. None when every argument is a symbol already."""
    calls = [x for x in _nodes(e, (sp.sin, sp.cos, sp.tan, sp.cot)) if not x.args[0].is_Symbol]
    if not calls:
        return None
    return e.xreplace({f: sp.expand_trig(f) for f in calls})


class _NotRational(Exception):
    """An expression outside :func:`_ring_numerator_zero`'s reach."""


def _ring_generators(e: sp.Expr) -> tuple[list, list]:
    """(angles, symbols) of an expression built by +, * and integer powers from rationals, symbols
    and sin/cos/tan/cot of symbols; :class:`_NotRational` for anything else (a float, a square root,
    pi, a trigonometric function of a sum)."""
    angles, symbols, stack = set(), set(), [e]
    while stack:
        x = stack.pop()
        if x.is_Symbol:
            symbols.add(x)
        elif x.is_Add or x.is_Mul:
            stack.extend(x.args)
        elif x.is_Pow and x.exp.is_Integer:
            stack.append(x.base)
        elif isinstance(x, (sp.sin, sp.cos, sp.tan, sp.cot)) and x.args[0].is_Symbol:
            angles.add(x.args[0])
        elif not x.is_Rational:
            raise _NotRational(x)
    key = sp.default_sort_key
    return sorted(angles, key=key), sorted(symbols - angles, key=key) + sorted(symbols & angles, key=key)


def _ring_numerator_zero(e: sp.Expr) -> bool | None:
    """:func:`numerator_reduces_to_zero` in sympy's sparse polynomials with integer coefficients:
    ``e`` as numerator / denominator (products of the denominators met, no gcd) in S_a = sin(a),
    C_a = cos(a) for each angle a and the other symbols, the numerator's remainder by the
    S_a**2 + C_a**2 - 1 (:func:`_ring_remainders`).

    The same decision as the expression route: with S_a ahead of C_a in lexicographic order the
    leading terms S_a**2 are coprime, so the S_a**2 + C_a**2 - 1 are a Groebner basis and the
    remainder is 0 exactly when the numerator lies in the (prime) ideal they generate. None, so that
    the expression route decides, when ``e`` holds something else (:func:`_ring_generators`) or its
    denominator itself reduces to 0 (``e`` undefined)."""
    remainders = _ring_remainders(e)
    return None if remainders is None else not remainders[0]


def constant_value(e: sp.Expr) -> sp.Rational | None:
    """The rational number ``e`` equals modulo sin**2 + cos**2 = 1, decided exactly; None when it is
    not a rational constant, or not a rational function of symbols and sin/cos/tan/cot of symbols.

    The remainders of numerator and denominator (:func:`_ring_remainders`) are normal forms, so
    ``e`` is the constant k exactly when the numerator's is k times the denominator's. (The same
    number :func:`reduce_trig` gives then, without its ``cancel``.)"""
    remainders = _ring_remainders(e)
    if remainders is None:
        return None
    num, den = remainders
    if not num:
        return sp.Integer(0)
    if num.keys() != den.keys():
        return None
    mon = next(iter(den))
    k = sp.Rational(num[mon], den[mon])
    return k if all(num[m] * k.q == den[m] * k.p for m in den) else None


def _ring_remainders(e: sp.Expr, generators: bool = False) -> tuple | None:
    """The terms of the remainders of ``e``'s numerator and denominator in sympy's sparse integer
    polynomials (see :func:`_ring_numerator_zero`); None outside that form, or when the
    denominator's remainder is 0. ``generators``: the generators' expressions too, a third item,
    in the order of the terms' exponents."""
    fractions = _ring_fraction(e)
    if fractions is None:
        return None
    num, den, gens, angles = fractions
    if not gens:
        out = (dict(num), dict(den))  # a rational number
        return (*out, []) if generators else out
    den = _circle_remainder(den, angles)
    if not den:
        return None
    out = (_circle_remainder(num, angles), den)
    return (*out, gens) if generators else out


def _ring_fraction(e: sp.Expr) -> tuple | None:
    """(numerator, denominator, generators, number of angles) of ``e`` in sympy's sparse integer
    polynomials in sin(a), cos(a) for each angle a and the other symbols (the denominator the
    product of those met, no gcd); None when ``e`` holds anything else (:func:`_ring_generators`).
    A rational number has no generators: its numerator and denominator are ``{(): p}`` (``{}`` for
    0) and ``{(): q}``."""
    from sympy.polys.domains import ZZ
    from sympy.polys.rings import ring

    try:
        angles, symbols = _ring_generators(e)
    except _NotRational:
        return None
    trig = [f(a) for a in angles for f in (sp.sin, sp.cos)]
    if not trig + symbols:
        return ({(): e.p} if e.p else {}), {(): e.q}, [], 0
    R, *gens = ring(trig + symbols, ZZ)  # sin(a) > cos(a) > the next angle's > ... > the symbols
    at = dict(zip(trig + symbols, gens))
    for a in angles:  # (an angle's own symbol, when it also stands alone, is a generator of its own)
        at[sp.tan(a)] = (at[sp.sin(a)], at[sp.cos(a)])
        at[sp.cot(a)] = (at[sp.cos(a)], at[sp.sin(a)])
    memo: dict = {}

    def fraction(x):  # (numerator, denominator) of x in R
        if x in memo:
            return memo[x]
        if x.is_Rational:
            out = (R(x.p), R(x.q))
        elif x in at:
            g = at[x]
            out = g if isinstance(g, tuple) else (g, R.one)
        elif x.is_Add:
            n, d = fraction(x.args[0])
            for a in x.args[1:]:
                n2, d2 = fraction(a)
                n, d = (n + n2, d) if d2 == d else (n * d2 + n2 * d, d * d2)
            out = (n, d)
        elif x.is_Mul:
            n, d = R.one, R.one
            for a in x.args:
                n2, d2 = fraction(a)
                n, d = n * n2, d * d2
            out = (n, d)
        else:  # an integer power
            n, d = fraction(x.base)
            k = int(x.exp)
            out = (n**k, d**k) if k >= 0 else (d**-k, n**-k)
        memo[x] = out
        return out

    num, den = fraction(e)
    return num, den, trig + symbols, len(angles)


def _polynomial_expr(terms, scale, gens, under=None) -> sp.Expr:
    """The sum of ``terms`` ({exponents: integer coefficient}) over the number ``scale`` (and the
    monomial of exponents ``under``), each term a rational times powers of ``gens``."""
    under = under or (0,) * len(gens)
    return sp.Add(*[sp.Mul(sp.Rational(coeff, scale), *[g**(k - j) for g, k, j in zip(gens, mon, under) if k != j])
                    for mon, coeff in terms.items()])


def _circle_remainder(p, angles: int) -> dict:
    """The terms ({exponents: coefficient}) of the remainder of the polynomial ``p`` (a sparse
    polynomial whose first 2 * ``angles`` generators are sin and cos of each angle) by the
    sin**2 + cos**2 - 1: each sin**k, k >= 2, becomes sin**(k mod 2) (1 - cos**2)**(k // 2), written
    out by the binomial theorem (what :func:`_reduce_poly` does to an expression)."""
    terms = dict(p)
    for a in range(angles):
        s, c = 2 * a, 2 * a + 1
        out: dict = {}
        for mon, coeff in terms.items():
            k = mon[s]
            if k < 2:
                out[mon] = out.get(mon, 0) + coeff
                continue
            m = k // 2
            for j in range(m + 1):
                term = list(mon)
                term[s], term[c] = k % 2, mon[c] + 2 * j
                term = tuple(term)
                out[term] = out.get(term, 0) + coeff * (-1) ** j * math.comb(m, j)
        terms = {mon: coeff for mon, coeff in out.items() if coeff}
    return terms


_PROBES = 2
"""Random points at which an expression is evaluated before the exact test."""


def _term_values(expr: sp.Expr, point: dict) -> list[complex]:
    """The value of each term of ``expr`` at ``point``: in double precision when every node is
    known to :func:`solver.tree_value.tree_value`, else by sympy's evalf."""
    terms = sp.Add.make_args(expr)
    memo: dict = {}
    try:
        return [tree_value(t, point, DOUBLE, memo) for t in terms]
    except NotEvaluable:
        floats = {s: sp.Float(v) for s, v in point.items()}
        return [complex(t.xreplace(floats).evalf(20)) for t in terms]


def _free_symbols(expr: sp.Expr) -> set:
    """``expr.free_symbols``, by one walk with a list for a stack when the tree holds only sums,
    products, powers, function calls and atoms (none of them binds a symbol: the free symbols are
    the symbols met); sympy's own answer for any other tree (a derivative, an integral)."""
    out, stack = set(), [expr]
    while stack:
        x = stack.pop()
        if x.is_Symbol:
            out.add(x)
        elif x.is_Add or x.is_Mul or x.is_Pow or x.is_Function:
            stack.extend(x.args)
        elif not (x.is_Atom and not x.args):
            return expr.free_symbols
    return out


def free_symbols_of(exprs) -> set:
    """The union of the ``free_symbols`` of ``exprs``, each distinct subtree visited once (the
    entries of a formulation's matrices share most of theirs, which sympy's ``free_symbols``
    walks again for every occurrence). Sums, products, powers and function calls bind no symbol:
    their free symbols are their arguments'; any other node with arguments (a derivative, an
    integral) answers by sympy's own ``free_symbols``."""
    out, seen, stack = set(), set(), list(exprs)
    while stack:
        x = stack.pop()
        if x in seen:
            continue
        seen.add(x)
        if x.is_Symbol:
            out.add(x)
        elif x.is_Add or x.is_Mul or x.is_Pow or x.is_Function:
            stack.extend(x.args)
        elif not (x.is_Atom and not x.args):
            out |= x.free_symbols
    return out


def _numerically_nonzero(expr: sp.Expr) -> bool:
    """True when ``expr`` is clearly nonzero at a random point (a cheap first test:
    a nonzero value far above round-off proves it nonzero; zero is then decided exactly)."""
    symbols = sorted(_free_symbols(expr), key=lambda s: s.name)
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
    if isinstance(expr, sp.Expr) and (expr.is_Rational or _plain_monomial(expr)):
        return False  # a nonzero rational, or one times symbols and sin/cos of symbols (no test needed)
    if _numerically_nonzero(expr):
        return False
    return numerator_reduces_to_zero(expr)


def term_powers(term: sp.Expr) -> dict:
    """``term.as_powers_dict()`` (base -> exponent, the exponents of a repeated base added), in a
    plain dict built factor by factor: Mul's own goes through a defaultdict per factor and adds
    each exponent to a 0, the cost of the display's passes over the terms."""
    out: dict = {}
    for f in sp.Mul.make_args(term):
        base, exp = f.as_base_exp()
        out[base] = out[base] + exp if base in out else exp
    return out


def _plain_polynomial(p: sp.Expr) -> bool:
    """A sum of monomials: products of non-sum factors with positive integer exponents."""
    for t in sp.Add.make_args(p):
        for base, exp in term_powers(t).items():
            if base.is_Add or base.is_Mul or not (exp.is_Integer and exp.p > 0):
                return False
    return True


def _power(base: sp.Expr, k: int) -> sp.Expr:
    """``base**k`` for a Python int ``k``: 1 and ``base`` themselves for k = 0 and 1 (sympy's
    answers too, without a power built and its exponent sympified)."""
    return sp.S.One if k == 0 else base if k == 1 else base**k


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
    coeffs, powers = [], []  # the exponents as Python ints (sympy Integer arithmetic is the cost here)
    for t in terms:
        c, rest = t.as_coeff_Mul()
        if not c.is_Rational:
            return None
        d = {}
        for base, exp in term_powers(rest).items():
            if base.is_Mul or base.is_number or not exp.is_Integer:
                return None
            exp = int(exp)
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
        low = min(d.get(base, 0) for d in powers)
        if low != 0:
            common[base] = low
    content = reduce(lambda a, b: a.gcd(b), coeffs)
    rest = sp.Add(*[(c / content) * sp.Mul(*[_power(b, d.get(b, 0) - low) for b, low in common.items()],
                                           *[_power(b, x) for b, x in d.items() if b not in common])
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


def _generator_power(x) -> tuple | None:
    """(generator, integer exponent) of a symbol or function call to a nonzero integer power."""
    base, exp = (x.base, x.exp) if x.is_Pow else (x, sp.Integer(1))
    if not exp.is_Integer or not (base.is_Symbol or base.is_Function):
        return None
    return base, int(exp)


def _positive_integer_sum(x) -> bool:
    """A sum whose every term is a positive integer times generators to positive integer powers."""
    for term in x.args:
        coef, rest = term.as_coeff_Mul()
        if not (coef.is_Integer and coef.p > 0):
            return False
        for f in sp.Mul.make_args(rest):
            gp = _generator_power(f) if f != 1 else (None, 1)
            if gp is None or gp[1] < 1:
                return False
    return True


def _single_term_fraction(e: sp.Expr) -> tuple[sp.Expr, sp.Expr] | None:
    """``sympy.fraction(sympy.cancel(e))`` for one term over sums: ``e`` a rational times
    generators (symbols, function calls) to integer powers times sums to negative integer powers,
    each sum with positive integer coefficients, and no generator of the numerator in every term of
    the expanded denominator. There the polynomial gcd is the integer content alone and the denominator's
    leading coefficient is positive, so cancel's answer is (p/g * numerator monomial,
    expanded denominator / g), g the gcd of p and the denominator's content. None otherwise."""
    if not e.is_Mul:
        return None
    coef, rest = e.as_coeff_Mul()
    if not coef.is_Rational:
        return None
    top, bottom, sums, top_gens = [], [], [], set()
    for f in sp.Mul.make_args(rest):
        if f.is_Pow and f.base.is_Add:
            if not (f.exp.is_Integer and f.exp.p < 0 and _positive_integer_sum(f.base)):
                return None
            sums.append(f.base ** -f.exp)
            continue
        gp = _generator_power(f)
        if gp is None:
            return None
        if gp[1] > 0:
            top.append(f)
            top_gens.add(gp[0])
        else:
            bottom.append(gp[0] ** -gp[1])
    if not sums:
        return None
    den = expanded(sp.Mul(sp.Integer(coef.q), *bottom, *sums))
    terms = sp.Add.make_args(den)
    powers = [term_powers(t) for t in terms]
    if any(all(d.get(g, 0) for d in powers) for g in top_gens):  # a monomial factor in common
        return None
    g = reduce(igcd, [int(t.as_coeff_Mul()[0]) for t in terms], abs(coef.p))
    return sp.Mul(sp.Integer(coef.p // g), *top), sp.Add(*[t / g for t in terms])


def _monomial_powers(d: sp.Expr) -> dict | None:
    """{base: exponent} of a product of powers (a monomial denominator), else None."""
    out = {}
    for f in sp.Mul.make_args(d):
        base, exp = f.as_base_exp()
        if base.is_Add or not exp.is_Integer or exp.p < 0:
            return None
        if base.is_number:
            base, exp = f, sp.Integer(1)
        out[base] = out.get(base, 0) + int(exp)  # (Python ints: sympy's compare each with a sympified 0)
    return out


def _simple_term(t: sp.Expr) -> tuple | None:
    """(rational coefficient, numerator factors, {denominator base: Python int exponent}) of a term
    built from a rational and other commutative factors (no exponential), each possibly to an integer
    power whose base, when the power is negative, is neither a product nor a number: the split
    ``sympy.fraction`` makes of such a term, read off its factors. None for any other term."""
    coeff, top, bottom = sp.S.One, [], {}
    for f in sp.Mul.make_args(t):
        if f.is_Pow:
            base, exp = f.args
            if not exp.is_Integer or base is sp.E or not f.is_commutative:
                return None
            if exp.p > 0:
                top.append(f)
            elif base.is_Mul or base.is_number:
                return None
            else:
                bottom[base] = -exp.p
        elif f.is_Rational:
            coeff = coeff * f
        elif not f.is_commutative or sp.exp in type(f).__mro__:
            return None
        else:
            top.append(f)
    return coeff, top, bottom


def _over_common_denominator(e: sp.Expr) -> tuple[sp.Expr, sp.Expr]:
    """(numerator, denominator) of ``e``: when every term's denominator is a monomial, over their
    least common multiple (one pass, no recursion); otherwise sympy's ``together``. Terms read by
    :func:`_simple_term` are put over it directly (the same products, built once)."""
    e = expanded(e)
    parts = [_simple_term(t) for t in sp.Add.make_args(e)]
    if any(p is None or any(b.is_Add for b in p[2]) for p in parts):
        return _over_common_denominator_of_fractions(e)
    lcm: dict = {}
    for _, _, bottom in parts:
        for base, exp in bottom.items():
            lcm[base] = max(lcm.get(base, 0), exp)
    scale = reduce(math.lcm, [c.q for c, _, _ in parts], 1)
    den = sp.Integer(scale) * sp.Mul(*[b**x for b, x in lcm.items()])
    num = sp.Add(*[sp.Mul(sp.Integer(c.p * (scale // c.q)), *top,
                          *[_power(b, x - bottom.get(b, 0)) for b, x in lcm.items()]) for c, top, bottom in parts])
    return expanded(num), den


def _over_common_denominator_of_fractions(e: sp.Expr) -> tuple[sp.Expr, sp.Expr]:
    """:func:`_over_common_denominator` of an expanded ``e`` by ``sympy.fraction`` of each term."""
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
    return expanded(num), den


def _over_factored_denominators(e: sp.Expr) -> sp.Expr | None:
    """``e`` over the least common multiple of its terms' denominators, each factored, with the
    numerator divided by every non-monomial factor that divides it: ``num / den`` with ``den`` left
    as a product of powers (``12*(m_b + m_d)**3``); None when a denominator holds sin/cos or
    none has a factor that is a sum.

    The case ``sympy.cancel`` is too slow for on large expressions (tens of ms): moments about a
    composite's mass centre G, whose position carries 1/(m_b + m_d), otherwise print as degree-7
    polynomials over degree-6 ones. Each distinct denominator is factored once (they are small);
    the numerator is reduced modulo sin**2 + cos**2 = 1 first (only then may a factor divide it),
    and divided by ``sympy.div`` (exact division by a known factor, no gcd search).
    """
    e = expanded(e)
    parts = [sp.fraction(t) for t in sp.Add.make_args(e)]
    factored = {}
    for _, d in parts:
        if d not in factored:
            if d.has(sp.sin, sp.cos):
                return None
            factored[d] = sp.factor_list(d)
    lcm: dict = {}
    for _, pieces in factored.values():
        for base, k in pieces:
            lcm[base] = max(lcm.get(base, 0), k)
    sums = [b for b in lcm if b.is_Add]
    if not sums:
        return None
    num = expanded(sp.Add(*[n / factored[d][0] * sp.Mul(*[b**(x - dict(factored[d][1]).get(b, 0))
                                                        for b, x in lcm.items()]) for n, d in parts]))
    if num.is_Add and _has_square(num):
        reduced = _reduce_poly(num)
        num = reduced if len(sp.Add.make_args(reduced)) < len(num.args) else num
    for base in sums:
        while lcm[base] > 0:
            quotient, remainder = sp.div(num, base)
            if remainder != 0:
                break
            num, lcm[base] = quotient, lcm[base] - 1
    return _tidy_polynomial(num) / sp.Mul(*[b**x for b, x in lcm.items()])


def _is_trig_denominator(x) -> bool:
    return x.is_Pow and x.exp.is_negative and x.base.is_Add and x.base.has(sp.sin, sp.cos)


def _reduce_denominators(e: sp.Expr, pows: set | None = None) -> sp.Expr:
    """Every denominator that is a polynomial in sin/cos reduced modulo sin**2 + cos**2 = 1
    (``(sin(g)**2 + cos(g)**2)**2`` becomes 1): the cheap structural step that removes a
    printed denominator equal to a constant; ``e`` itself when there is none. ``pows``: the
    powers of ``e`` when the caller has them."""
    return _replace_powers(e, _is_trig_denominator, lambda x: _reduce_poly(x.base) ** x.exp, pows)


def _is_trig_radicand(x) -> bool:
    return x.is_Pow and not x.exp.is_Integer and x.base.is_Add and x.base.has(sp.sin, sp.cos)


def _reduce_radicands(e: sp.Expr, pows: set | None = None) -> sp.Expr:
    """Every sum under a root (a spring's length ``sqrt(r**2*sin(u)**2 + r**2*cos(u)**2)``) that
    holds sin/cos tidied as a polynomial (:func:`_tidy_polynomial`: reduced modulo
    sin**2 + cos**2 = 1 when that leaves fewer terms): the terms of the expression around it do not
    change in number, so the reduction of the whole would not be taken for it. ``e`` itself when
    there is none; ``pows``: the powers of ``e`` when the caller has them."""
    return _replace_powers(e, _is_trig_radicand, lambda x: _tidy_polynomial(x.base) ** x.exp, pows)


def tree_size(e: sp.Expr, cap: "int | None" = None) -> int:
    """Number of nodes of the expression tree (a cheap stand-in for ``count_ops``; the count of
    ``sympy.preorder_traversal``, by a walk with a list for a stack). With ``cap``, the walk stops
    once the count passes it (a result above ``cap`` means "larger than cap")."""
    n, stack = 0, [e]
    while stack:
        n += 1
        if cap is not None and n > cap:
            return n
        stack.extend(stack.pop().args)
    return n


def _monomial_denominators(e: sp.Expr) -> bool:
    """Whether every term's denominator is a monomial (read off the term by :func:`_simple_term`,
    else by ``sympy.fraction``)."""
    for t in sp.Add.make_args(e):
        parts = _simple_term(t)
        if any(b.is_Add for b in parts[2]) if parts else _monomial_powers(sp.fraction(t)[1]) is None:
            return False
    return True


def _has_denominator(e: sp.Expr, pows: set | None = None) -> bool:
    return any(x.exp.is_negative for x in (_nodes(e, sp.Pow) if pows is None else pows))


def _denominator_free(p: sp.Expr) -> bool:
    """No negative powers: a polynomial in its symbols and its sin/cos terms."""
    return not any(x.exp.is_negative for x in _nodes(p, sp.Pow))


def _has_square(p: sp.Expr, pows: set | None = None) -> bool:
    """Whether some sin(a)**n with n >= 2 appears (only then can the reduction change anything).
    ``pows``: the powers of ``p`` when the caller has them."""
    pows = _nodes(p, sp.Pow) if pows is None else pows
    return any(isinstance(x.base, sp.sin) and x.exp.is_Integer and x.exp.p >= 2 for x in pows)


def _tidy_polynomial(p: sp.Expr) -> sp.Expr:
    """Expanded, reduced modulo sin**2 + cos**2 = 1 when that leaves fewer terms, common factors out.
    A single term is only expanded (its reduction has at least one term; it has no other to share
    a factor with)."""
    p = expanded(p)
    if not p.is_Add:
        return p
    pows = _nodes(p, sp.Pow)  # (one walk for both questions)
    if _has_square(p, pows):
        reduced = _reduce_poly(p, pows)
        shown = reduced if len(sp.Add.make_args(reduced)) < len(sp.Add.make_args(p)) else _merge_pairs(p)
        p, pows = shown, (pows if shown is p else None)
    return _common_factor(_merge_complements(p, pows))


def _merge_pairs(p: sp.Expr) -> sp.Expr:
    """``p`` (an expanded sum) with each pair of terms X*sin(u)**2 and X*cos(u)**2 (the same X,
    coefficient included) written X, until none is left; ``p`` itself when there is none. What the
    reader sees as sin**2 + cos**2 goes even where the remainder of :func:`_reduce_poly` (sin**2
    written 1 - cos**2 everywhere) has as many terms as ``p``: ``-c*sin**2 - c*cos**2 + b*sin**2``."""
    terms, merged = set(sp.Add.make_args(p)), False
    for t in sp.Add.make_args(p):  # (in the sum's own order: the set's would depend on the hash seed)
        if t not in terms:
            continue
        for f in sp.Mul.make_args(t):
            if not (f.is_Pow and isinstance(f.base, sp.sin) and f.exp.is_Integer and f.exp.p >= 2):
                continue
            rest = t / f.base**2
            partner = rest * sp.cos(f.base.args[0]) ** 2
            if partner in terms and partner != t:
                terms -= {t, partner}
                terms.add(rest)  # (an equal term already there doubles: Add below adds them)
                merged = True
                break
    if not merged:
        return p
    return _merge_pairs(sp.Add(*terms))


def _merge_complements(p: sp.Expr, pows: set | None = None) -> sp.Expr:
    """``p`` (an expanded sum, reduced by :func:`_reduce_poly`) with each pair of terms X and
    -X*cos(u)**2 written X*sin(u)**2, until none is left; ``p`` itself when there is none. The
    reduction writes sin**2 as 1 - cos**2 everywhere; where both terms of that difference are left
    in the sum, the reader sees ``1 - cos(u)**2``, which the sine squared says in one term.
    ``pows``: the powers of ``p`` when the caller has them: without
    a cos(u)**n, n >= 2, among them nothing is looked at."""
    pows = _nodes(p, sp.Pow) if pows is None else pows
    if not p.is_Add or not any(isinstance(x.base, sp.cos) and x.exp.is_Integer and x.exp.p >= 2 for x in pows):
        return p
    terms = set(sp.Add.make_args(p))
    for t in p.args:  # (in the sum's own order, not the set's: which pair goes first decides the form)
        for f in sp.Mul.make_args(t):
            if not (f.is_Pow and isinstance(f.base, sp.cos) and f.exp.is_Integer and f.exp.p >= 2):
                continue
            rest = t / f.base**2  # (-X)
            if -rest in terms and -rest != t:
                return _merge_complements(sp.Add(*(terms - {t, -rest}), -rest * sp.sin(f.base.args[0]) ** 2), None)
    return p


def could_extract_minus_sign(e: sp.Expr) -> bool:
    """``e.could_extract_minus_sign()``; for a product whose first factor is a rational, the sign of
    that coefficient, and False when the first factor is not a number (sympy first compares the
    product with its negative, which differs from it whenever the coefficient is a finite nonzero
    number, and then answers from a numeric first factor only)."""
    if type(e) is sp.Mul:
        c = e.args[0]
        if c.is_Rational:
            return c.p < 0
        if not c.is_Number:
            return False
    return e.could_extract_minus_sign()


def _integer(x) -> int:
    """A sympy Integer as a Python int (a key for ``min``: comparing sympy Integers sympifies)."""
    return x.p


def _common_monomial(powers: list) -> dict:
    """{base: least exponent} of the non-number bases with a positive integer exponent in every one
    of ``powers`` (the :func:`term_powers` of the terms of a sum)."""
    common = {}
    for base, exp in powers[0].items():
        if base.is_number or not (exp.is_Integer and exp.p > 0):
            continue
        exps = [d.get(base, sp.S.Zero) for d in powers]
        low = min(exps, key=_integer) if all(x.is_Integer for x in exps) else min(exps)
        if low.is_Integer and low.p > 0:
            common[base] = low
    return common


def _common_factor(p: sp.Expr) -> sp.Expr:
    """``p`` with the monomial common to all its terms (symbols, sin/cos powers, the rational
    content) written in front: what ``factor_terms`` does for a sum of monomials, in one pass.
    Without a common monomial a sum with rational coefficients is returned as it is (its content
    times its primitive part is the same sum again) and only the content is taken out."""
    terms = sp.Add.make_args(p)
    if len(terms) < 2:
        return p
    split = [t.as_coeff_Mul() for t in terms]
    powers = [term_powers(rest) for _, rest in split]
    common = _common_monomial(powers)  # (number bases are left out: the coefficients change none)
    rational = all(c.is_Rational for c, _ in split)
    if not common and rational:
        return p
    if common and rational and all(_monomial_of_generators(d) for d in powers):
        return _monomial_out(split, powers, common)
    content, prim = p.primitive()
    if not common:
        return content * prim if content != 1 else p
    monomial = sp.Mul(*[b**e for b, e in common.items()])
    rest = [t / monomial for t in sp.Add.make_args(prim)]
    if all(could_extract_minus_sign(t) for t in rest):  # -(a + b) rather than (-a - b)
        content, rest = -content, [-t for t in rest]
    return content * monomial * sp.Add(*rest)


def _monomial_of_generators(powers: dict) -> bool:
    """Whether {base: exponent} is a monomial: integer exponents of bases that are neither numbers
    nor sums."""
    return all(e.is_Integer and not (b.is_Add or b.is_number) for b, e in powers.items())


def _monomial_out(split: list, powers: list, common: dict) -> sp.Expr:
    """:func:`_common_factor` of a sum of terms ``c * rest`` (``split``, c rational, each rest a
    monomial with those ``powers``) with the ``common`` monomial: content and signs in Python ints
    (``Add.primitive``'s gcd of the numerators over the lcm of the denominators), each term divided
    by the monomial by subtracting exponents; the same sympy expression, without the primitive part
    and the quotients built on the way."""
    top = reduce(math.gcd, [c.p for c, _ in split], 0)
    bottom = reduce(math.lcm, [c.q for c, _ in split], 1)
    ks = [(c.p // top) * (bottom // c.q) for c, _ in split]
    content = Fraction(top, bottom)
    if all(k < 0 for k in ks):  # -(a + b) rather than (-a - b)
        content, ks = -content, [-k for k in ks]
    monomial = sp.Mul(*[b**e for b, e in common.items()])
    rest = [sp.Mul(sp.Integer(k), *[_power(b, int(e) - int(common.get(b, 0))) for b, e in d.items()])
            for k, d in zip(ks, powers)]  # (one product per term: no base is a sum, nothing distributes)
    return sp.Mul(_rational(content), monomial, sp.Add(*rest))


_POSITIVE: ContextVar[dict | None] = ContextVar("positive_parameters", default=None)


@contextmanager
def positive_parameters(system):
    """Within this block, :func:`tidy` writes ``Abs(p)`` as ``p`` for each parameter ``p`` of
    ``system`` whose value is positive. sympy's symbols of parameters are only real (a positive
    assumption would change every symbol that code builds to look a value up), so the square root
    of ``L**2*X`` becomes ``Abs(L)*sqrt(X)`` (QA 19 #10, a spring from a bar's tip). The scene's
    equations hold at its parameters' values, where |L| = L: nothing computed changes, only what
    is shown. A parameter of zero or negative value keeps its Abs. So does a sum or product of
    parameters only when its sign is not known from theirs: ``Abs(r1 + r2)`` of two positive radii
    is ``r1 + r2`` (QA 21 #7, a gear pair's centre distance), and the form is tidied again."""
    positive = {s: sp.Dummy(s.name, positive=True) for s, v in system.si_values().items() if v > 0}
    token = _POSITIVE.set(positive or None)
    try:
        yield
    finally:
        _POSITIVE.reset(token)


def tidy(expr: sp.Expr, max_nodes: int = MAX_TIDY_NODES) -> sp.Expr:
    """:func:`_tidy`, with each parameter known positive written without its Abs inside a
    :func:`positive_parameters` block."""
    shown = _tidy(expr, max_nodes)
    bare = without_known_abs(shown)
    if bare is shown or not any(not a.args[0].is_Symbol and not bare.has(a) for a in shown.atoms(sp.Abs)):
        return bare  # (none, or only parameters' |p| written p)
    return _tidy(bare, max_nodes)  # (Abs(r1 + r2) written r1 + r2 may cancel: tidied again)


def without_known_abs(expr: sp.Expr) -> sp.Expr:
    """``expr`` with each ``Abs(a)`` whose argument is known positive within a
    :func:`positive_parameters` block written ``a``; ``expr`` itself (the same object) when there
    is none, or outside such a block."""
    positive = _POSITIVE.get()
    if not positive or not isinstance(expr, sp.Basic) or not expr.has(sp.Abs):
        return expr
    known = {a: a.args[0] for a in expr.atoms(sp.Abs) if _known_positive(a.args[0], positive)}
    return expr.xreplace(known) if known else expr


def _known_positive(expr: sp.Expr, positive: dict) -> bool:
    """Whether ``expr``, a function of parameters only, is positive when each of ``positive``'s
    parameters (symbol -> a positive Dummy) is: a parameter, a sum or product of them with positive
    numbers (sympy's assumptions decide)."""
    return expr.free_symbols <= positive.keys() and expr.xreplace(positive).is_positive is True


tidy.cache_clear, tidy.cache_info = (lambda: _tidy.cache_clear()), (lambda: _tidy.cache_info())


@lru_cache(maxsize=4096)
def _tidy(expr: sp.Expr, max_nodes: int = MAX_TIDY_NODES) -> sp.Expr:
    """A short display form built from the structure of ``expr``: one fraction whose numerator and
    denominator are each reduced modulo sin**2 + cos**2 = 1 (when that shortens them) with their
    common factors pulled out; ``cancel`` only on small expressions.

    Expressions larger than ``max_nodes`` (:data:`MAX_TIDY_NODES`; a caller that bounds the time
    itself may allow more) are returned as they are; an angle that holds
    sin/cos itself (a prescribed ``W*t + 3*sin(W*t)/10``) is reduced as a plain angle is
    (:func:`_mask_nested_angles`).
    """
    e = sp.sympify(expr)
    if e.is_number or _plain_monomial(e):
        return e
    shape = _shape(e)
    if shape.size > max_nodes:
        return e
    shown = _tidy_general(e, shape)
    return _collapse_angle_sums(shown) if _several_angles(shape.trig) else shown


def _several_angles(trig: set) -> bool:
    """Whether sin/cos calls ``trig`` hold two or more different angles (only then can a product of
    them collapse to the sine or cosine of a sum)."""
    angles = set()
    for f in trig:
        angles.add(f.args[0])
        if len(angles) > 1:
            return True
    return False


_OTHER = {sp.sin: sp.cos, sp.cos: sp.sin}


def _collapse_angle_sums(e: sp.Expr) -> sp.Expr:
    """``e`` with each pair of terms K*cos(a)*cos(b) and ±K*sin(a)*sin(b) of a sum written
    K*cos(a ∓ b), and each pair K*sin(a)*cos(b), ±K*cos(a)*sin(b) written K*sin(a ± b) (the
    angle-addition formulas read backwards, as ``sympy.simplify.fu.TR10i`` does, in one walk of the
    tree with the terms matched by dictionary: TR10i costs about a millisecond a sum, which doubled
    the time of ``explain`` on sliding_bar); terms left with the same new sine or cosine are then
    written with it in front. An identity: the value is the same at every point."""
    if not e.args:
        return e
    args = [a if _of_leaves(a) else _collapse_angle_sums(a) for a in e.args]
    if any(x is not y for x, y in zip(args, e.args)):
        e = e.func(*args)
    return _collapse_sum(e) if e.is_Add else e


def _of_leaves(e: sp.Basic) -> bool:
    """Whether ``e`` is a leaf or a node of leaves only (``sin(theta)``, ``theta_dot**2``, ``l_b*m_b``):
    :func:`_collapse_angle_sums` leaves it as it is (no term of a sum of leaves holds a sine or a
    cosine), so it need not be walked."""
    args = e.args
    return not args or not any(a.args for a in args)


def _collapse_sum(add: sp.Add) -> sp.Expr:
    """One sum of :func:`_collapse_angle_sums` (its terms already collapsed inside)."""
    split = [t.as_coeff_Mul() for t in add.args]
    index = {rest: k for k, (_, rest) in enumerate(split)}
    used, new = set(), {}
    for k, (c, rest) in enumerate(split):
        if k in used:
            continue
        pair = _partner(c, rest, split, index, used | {k})  # (a partner may come before k)
        if pair is None:
            continue
        m, trig, others = pair
        used |= {k, m}
        sign, trig = trig.as_coeff_Mul()  # (sin(b - a) comes as -sin(a - b))
        new.setdefault(trig, []).append(sign * others)
    if not new:
        return add
    kept = [t for k, t in enumerate(add.args) if k not in used]
    return sp.Add(*kept, *[_signed_product(trig, others) for trig, others in new.items()])


def _signed_product(trig: sp.Expr, terms: list) -> sp.Expr:
    """trig times the sum of ``terms``, written -trig*(a + b) rather than trig*(-a - b)."""
    if len(terms) > 1 and all(could_extract_minus_sign(t) for t in terms):
        return -trig * sp.Add(*[-t for t in terms])
    return trig * sp.Add(*terms)


def _partner(c, rest, split, index, taken):
    """(index of the term that pairs with c*rest, the sine or cosine of the sum or difference, the
    term's other factors with its coefficient), or None."""
    factors = sp.Mul.make_args(rest)
    trig = [i for i, f in enumerate(factors) if isinstance(f, (sp.sin, sp.cos))]
    for n, i in enumerate(trig):
        for j in trig[n + 1:]:
            f, g = factors[i], factors[j]
            if f.args[0] == g.args[0]:
                continue
            if f.func is sp.cos and g.func is sp.sin:  # a mixed pair as sin(a)*cos(b)
                f, g = g, f
            others = [x for q, x in enumerate(factors) if q not in (i, j)]
            m = index.get(sp.Mul(*others, _OTHER[f.func](f.args[0]), _OTHER[g.func](g.args[0])))
            if m is None or m in taken:
                continue
            sign = 1 if split[m][0] == c else -1 if split[m][0] == -c else 0
            if not sign:
                continue
            a, b = f.args[0], g.args[0]
            if f.func is g.func:  # c cos cos + s c sin sin = c cos(a - s b); c sin sin + s c cos cos = s c cos(a - s b)
                return m, sp.cos(a - sign * b), sp.Mul(c if f.func is sp.cos else sign * c, *others)
            return m, sp.sin(a + sign * b), sp.Mul(c, *others)  # c sin(a) cos(b) + s c cos(a) sin(b)
    return None


def _plain_factor(f) -> bool:
    """A symbol, or sin/cos of a symbol, possibly to a positive integer power."""
    if f.is_Pow:
        f = f.base if f.exp.is_Integer and f.exp.p > 0 else None
    return f is not None and (f.is_Symbol or isinstance(f, (sp.sin, sp.cos)) and f.args[0].is_Symbol)


def _plain_monomial(e: sp.Expr) -> bool:
    """A rational times plain factors (:func:`_plain_factor`), which :func:`tidy` leaves as it is:
    no denominator but the rational's, nothing to expand, reduce or factor out (the test checks
    :func:`_tidy_general` against it)."""
    return all(f.is_Rational or _plain_factor(f) for f in sp.Mul.make_args(e)) and not e.is_Rational


def _tidy_general(e: sp.Expr, shape: _Shape | None = None) -> sp.Expr:
    """:func:`tidy` of an expression that is not a number (nor a plain monomial); ``shape``: its
    :func:`_shape` when the caller has it."""
    shape = _shape(e) if shape is None else shape
    reduced = _reduce_denominators(e, shape.pows)
    reduced = _reduce_radicands(reduced, shape.pows if reduced is e else None)
    if reduced is not e:
        e, shape = reduced, _shape(reduced)
    if e.has(sp.tan, sp.cot):
        e = e.replace(sp.tan, lambda a: sp.sin(a) / sp.cos(a)).replace(sp.cot, lambda a: sp.cos(a) / sp.sin(a))
        shape = _shape(e)
    if not _angles_ok(e, shape.trig):
        masked, back = _mask_nested_angles(e, shape.trig)
        return _tidy_general(masked).xreplace(back)
    monomial = _monomial_denominators(e)
    small = shape.size <= MAX_CANCEL_NODES
    if not monomial and small:  # common factors out (cheap when small)
        num, den = _single_term_fraction(e) or sp.fraction(sp.cancel(_together(e)))
    else:
        factored = None if monomial else _over_factored_denominators(e)
        if factored is not None:
            return factored
        num, den = _over_common_denominator(e) if _has_denominator(e, shape.pows) else (e, sp.Integer(1))
        if not monomial and not (_denominator_free(num) and _denominator_free(den)):
            num, den = _single_term_fraction(e) or sp.fraction(sp.cancel(_together(e)))
    # (over monomial denominators the common monomial of the numerator cancels by itself below)
    num, den = _tidy_polynomial(num), _tidy_polynomial(den)
    if den.is_number and den != 0 and num.is_Add:
        return factor_monomial_terms(expanded(num / den))
    return num / den


def _mask_nested_angles(e: sp.Expr, trig: set) -> tuple[sp.Expr, dict]:
    """(``e`` with each angle that holds sin/cos/tan itself, ``W*t + 3*sin(W*t)/10``, replaced under
    its sin and cos by a dummy symbol of its own, {dummy: angle}). sin(u)**2 + cos(u)**2 = 1 for any
    u, so the display tidy reduces the masked form as it reduces a plain angle; the angles then come
    back by ``xreplace``. (Taking each masked angle for an independent one is sound: it loses
    only identities between an angle and what it holds, which the display does not look for.)"""
    angles = {f.args[0] for f in trig if f.args[0].has(sp.sin, sp.cos, sp.tan)}
    dummies = {u: sp.Dummy("u") for u in angles}
    masked = e.xreplace({f(u): f(d) for u, d in dummies.items() for f in (sp.sin, sp.cos)})
    return masked, {d: u for u, d in dummies.items()}


def _plain_generator(f) -> bool:
    """A symbol, or a function call whose arguments are all symbols (``sin(theta)``)."""
    return f.is_Symbol or (f.is_Function and all(a.is_Symbol for a in f.args))


def _monomial_term(t) -> bool:
    """A rational times plain generators (:func:`_plain_generator`) to positive integer powers."""
    for f in sp.Mul.make_args(t):
        if f.is_Rational:
            continue
        if f.is_Pow:
            if not (f.exp.is_Integer and f.exp.p > 0):
                return False
            f = f.base
        if not _plain_generator(f):
            return False
    return True


def factor_monomial_terms(p: sp.Expr) -> sp.Expr:
    """``sympy.factor_terms(p)``, the same expression, without its recursion when ``p`` is a sum of
    monomials in plain generators (:func:`_monomial_term`). The steps ``factor_terms`` composes
    there (its default ``clear=False``): the rational content, a common negative sign, the greatest
    common monomial of the terms, a denominator kept inside the sum when some term's coefficient
    is then an integer (``x/2 + y`` stays as it is), in one pass over the terms with the
    coefficients as Python fractions (:func:`_primitive_coefficients`); only the result is built in
    sympy (about 3x faster than ``factor_terms``, which builds its ``Factors`` per term at every
    level). Any other expression goes to ``factor_terms`` itself."""
    if not p.is_Add or not all(_monomial_term(t) for t in p.args):
        return sp.factor_terms(p)
    split = [t.as_coeff_Mul() for t in p.args]
    content, coeffs = _primitive_coefficients([Fraction(c.p, c.q) for c, _ in split])
    if all(k < 0 for k in coeffs):  # factor_terms takes a common -1 out
        content, coeffs = -content, [-k for k in coeffs]
    powers = [{b: int(x) for b, x in term_powers(rest).items()} for _, rest in split]  # (positive integers)
    common = {b: min(d.get(b, 0) for d in powers) for b in powers[0]}
    common = {b: x for b, x in common.items() if x}
    g = Fraction(reduce(math.gcd, [k.numerator for k in coeffs]), reduce(math.lcm, [k.denominator for k in coeffs]))
    coeffs = [k / g for k in coeffs]
    if g.denominator != 1 and any((k / g.denominator).denominator == 1 for k in coeffs):
        coeffs, g = [k / g.denominator for k in coeffs], Fraction(g.numerator)  # (gcd_terms, clear=False)
    sums = sp.Add(*[sp.Mul(_rational(k), *[_power(b, x - common.get(b, 0)) for b, x in d.items()])
                    for k, d in zip(coeffs, powers)])  # (one product per term: no factor is a sum)
    inner = _keep_coeff(_rational(g), sp.Mul(*[b**x for b, x in common.items()], sums), clear=False)
    return _keep_coeff(_rational(content), inner, clear=False, sign=True)


def _primitive_coefficients(coeffs: list) -> tuple:
    """(content, coefficients of the primitive part) of a sum of terms with these rational
    coefficients, as ``Add.as_content_primitive(clear=False)`` finds them: the positive gcd of the
    numerators over the lcm of the denominators, except that the denominator stays with the terms
    when one of them then has an integer coefficient."""
    top = reduce(math.gcd, [c.numerator for c in coeffs], 0)
    bottom = reduce(math.lcm, [c.denominator for c in coeffs], 1)
    prim = [c * bottom / top for c in coeffs]
    if bottom != 1 and any(k.numerator % bottom == 0 for k in prim):
        return Fraction(top), [k / bottom for k in prim]
    return Fraction(top, bottom), prim


def _rational(x: Fraction) -> sp.Rational:
    return sp.Rational(x.numerator, x.denominator)


def _fraction_of_ratio(num: sp.Expr, den: sp.Expr, once=None) -> tuple[sp.Expr, sp.Expr]:
    """``sympy.fraction(sympy.together(num / den))``, by :func:`_gathered_sum` on each side when
    both are sums of monomials over monomial denominators (the reactions of the structured solve);
    otherwise by ``together`` itself. ``once(key, build)`` remembers the denominator's side."""
    once = once or (lambda key, build: build())
    top = _gathered_sum(sp.Add.make_args(num))
    bottom = once(("gathered", den), lambda: _gathered_sum(sp.Add.make_args(den)))
    if top is None or bottom is None:
        return sp.fraction(_together(num / den))
    return sp.fraction(top / bottom)


def _reduced_with_powers(e: sp.Expr) -> tuple[sp.Expr, set | None]:
    """(``_reduce_denominators(expand(e))``, its powers when it is the expanded ``e`` itself, else
    None): one walk of the tree for both."""
    e = expanded(e)
    pows = _nodes(e, sp.Pow)
    reduced = _reduce_denominators(e, pows)
    return (e, pows) if reduced is e else (reduced, None)


def tidy_fraction(num: sp.Expr, den: sp.Expr, memo: dict | None = None) -> sp.Expr:
    """Display form of num/den when both are known polynomials in sin/cos (no ``together``,
    no ``cancel``): each part reduced and factored on its own.

    ``memo``: a dict shared by the fractions of one display (the reactions share their
    denominator, the generalized mass), where the work on a common denominator is kept."""
    memo = {} if memo is None else memo

    def once(key, build):
        if key not in memo:
            memo[key] = build()
        return memo[key]

    num, num_pows = _reduced_with_powers(num)
    den, den_pows = once(("reduced", den), lambda: _reduced_with_powers(den))
    if _has_denominator(den, den_pows):
        num, den = _fraction_of_ratio(num, den, once)
        num_pows = None
    if _has_denominator(num, num_pows) and _monomial_denominators(num):
        num, extra = _over_common_denominator(num)
        den = den * extra
    return _tidy_polynomial(num) / once(("polynomial", den), lambda: _tidy_polynomial(den))


def tidy_linear(expr: sp.Expr, variables) -> sp.Expr:
    """Display form of an expression affine in ``variables`` (accelerations,
    reactions, squared rates): each coefficient tidied on its own, the rest last.

    Parameters
    ----------
    expr : sympy.Expr
    variables : sequence of sympy.Expr
        Symbols or monomials (``theta_dot**2``) in display order.
    """
    e = expanded(sp.sympify(expr))
    parts = []
    rest = e
    symbols = {u for u in variables if u.is_Symbol}
    for v in variables:
        if not (v.is_Symbol or v.is_Pow):
            continue
        coef, others = _coefficient_and_rest(rest, v)
        if coef != 0 and not _mentions(coef, symbols):
            parts.append(tidy(coef) * v)
            rest = others
    return sp.Add(*parts, tidy(rest))


def coefficient(expr: sp.Expr, v: sp.Expr) -> sp.Expr:
    """``expr.coeff(v)``, the same expression, in one pass over the terms of a commutative ``expr``
    when ``v`` is a symbol or a power (``theta_dot**2``): ``coeff`` collects, from each term holding
    ``v`` as a factor, the product of its other factors (its ``args_cnc`` sets, compared by set
    difference, cost about twice this). Any other ``v`` (a product, whose factors ``coeff`` finds
    among a term's) goes to ``coeff`` itself."""
    if not (v.is_Symbol or v.is_Pow) or not (expr.is_commutative and v.is_commutative):
        return expr.coeff(v)
    holding = []
    for t in sp.Add.make_args(expr):
        factors = sp.Mul.make_args(t)
        if v in factors:
            holding.append(sp.Mul(*[f for f in factors if f != v]))
    return sp.Add(*holding)


def _coefficient_and_rest(rest: sp.Expr, v: sp.Expr) -> tuple[sp.Expr, sp.Expr]:
    """(``rest.coeff(v)``, :func:`_without_factor` of ``rest`` and ``v``) of an expanded sum, in one
    pass over its terms when both are commutative: ``coeff`` collects, from each term holding ``v``
    as a factor, the product of its other factors."""
    if not (rest.is_commutative and v.is_commutative):
        return rest.coeff(v), _without_factor(rest, v)
    holding, others = [], []
    for t in sp.Add.make_args(rest):
        factors = sp.Mul.make_args(t)
        if v in factors:
            factors = list(factors)
            factors.remove(v)
            holding.append(sp.Mul(*factors))
        else:
            others.append(t)
    return sp.Add(*holding), sp.Add(*others)


def _mentions(e: sp.Expr, symbols: set) -> bool:
    """``e.has(*symbols)`` for symbols: whether a node of the tree is one of them (one walk)."""
    stack = [e]
    while stack:
        x = stack.pop()
        if x.is_Symbol and x in symbols:
            return True
        stack.extend(x.args)
    return False


def _without_factor(rest: sp.Expr, v: sp.Expr) -> sp.Expr:
    """``expand(rest - rest.coeff(v) * v)`` of an expanded commutative sum: the terms that do not
    hold ``v`` as a factor (those are the ones ``coeff`` collects), without expanding again."""
    if not rest.is_commutative:
        return expanded(rest - rest.coeff(v) * v)
    return sp.Add(*[t for t in sp.Add.make_args(rest) if v not in sp.Mul.make_args(t)])
