"""The value of a sympy expression at a point, by walking its tree once.

Two callers need numbers from expressions many times over, where generating
and compiling code (``lambdify``) or sympy's own Float arithmetic costs more
than the evaluation: the display's quick nonzero test (:mod:`solver.display`,
the point advisor), in double-precision complex arithmetic, and the report's
numeric equation checks (:mod:`reports.equations`), in mpmath at the working
precision. One walk serves both; an :class:`Arithmetic` says how numbers of
each kind are made, added, multiplied and raised, and which functions it
knows. Shared subtrees are evaluated once (``memo``). The same expressions at
many points (the report's zero test) are walked once into a program
(:func:`tree_program`), which then costs only the arithmetic per point.

A node the walk does not know raises :class:`NotEvaluable`; the caller then
falls back to sympy (``evalf``, or ``lambdify``).
"""
from __future__ import annotations

import cmath
import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass

import mpmath
import sympy as sp

__all__ = ["Arithmetic", "DOUBLE", "SIZED", "Sized", "mpmath_arithmetic", "NotEvaluable", "real_value", "substitute", "tree_value",
           "tree_program", "affine_value"]


class NotEvaluable(Exception):
    """An expression node that :func:`tree_value` does not evaluate."""


@dataclass(frozen=True)
class Arithmetic:
    """How one kind of number is made and combined.

    Attributes
    ----------
    number : callable
        A sympy number (no free symbols) to a value.
    total, product : callable
        Sum and product of an iterable of values.
    sqrt, power : callable
        Square root; a value to a non-integer power.
    functions : dict
        sympy function class -> one-argument function on values.
    """

    number: Callable
    total: Callable[[Iterable], object]
    product: Callable[[Iterable], object]
    sqrt: Callable
    power: Callable
    functions: dict


def _complex_product(values) -> complex:
    out = 1 + 0j
    for v in values:
        out *= v
    return out


def _double_number(e) -> complex:
    """``complex(e)`` of a sympy number, without its ``evalf`` where the double is exact: a rational
    whose denominator is a power of two and whose numerator has at most 53 bits (integers, halves).
    Other rationals go through ``complex`` (its rounding is ``evalf``'s, not always the nearest double)."""
    if e.is_Rational and abs(e.p) <= 2**53 and e.q & (e.q - 1) == 0:
        return complex(e.p / e.q)
    return complex(e)


DOUBLE = Arithmetic(
    number=_double_number,
    total=lambda values: sum(values, 0j),
    product=_complex_product,
    sqrt=cmath.sqrt,
    power=lambda base, exp: base ** exp,
    functions={sp.sin: cmath.sin, sp.cos: cmath.cos, sp.tan: cmath.tan, sp.exp: cmath.exp, sp.log: cmath.log,
               sp.sinh: cmath.sinh, sp.cosh: cmath.cosh, sp.tanh: cmath.tanh, sp.asin: cmath.asin,
               sp.acos: cmath.acos, sp.atan: cmath.atan, sp.Abs: abs},
)
"""Double-precision complex arithmetic (``cmath``); the functions of :data:`SIZED`, so that a walk
in one goes wherever a walk in the other does (an angle with atan in it was walked for its sizes
but not for its values, and its matrix came from compiled entries whose omega**2 parts cancel)."""


@dataclass(slots=True)
class Sized:
    """A double-precision value and the size of its round-off: evaluated in float64, an expression
    errs by about u * size (u = 2**-53, to first order, up to a small multiple for the number of
    operations in a row). A sum's size is the sum of its terms' sizes, so a result much smaller
    than its terms (cancellation: omega**2 terms of 1e16 leaving 7) has a size much larger than
    itself; a function passes on its argument's error times its slope.

    Never changed once made (a walk's memo shares one among the nodes above it); not frozen, as a
    frozen dataclass's ``__init__`` costs about twice as much and the walk makes one per node."""

    value: float
    size: float

    def __pow__(self, k: int) -> "Sized":
        v, c = self.value, self._ratio()
        if k < 0 and v == 0:
            return Sized(math.nan, math.nan)
        return Sized(v ** k, abs(v) ** k * (1 + abs(k) * (c - 1)) if k < 0 else self.size ** k)

    def __add__(self, other: "Sized") -> "Sized":
        return Sized(self.value + other.value, self.size + other.size)

    def __mul__(self, other: "Sized") -> "Sized":
        return Sized(self.value * other.value, self.size * other.size)

    def _ratio(self) -> float:
        """size / |value| (at least 1): the relative error in units of u."""
        return self.size / abs(self.value) if self.value else math.inf

    @staticmethod
    def of(value) -> "Sized":
        v = float(value)
        return Sized(v, abs(v))


def _sized_product(values) -> Sized:
    v, s = 1.0, 1.0
    for x in values:  # the product of the sizes bounds the product's first-order error
        v, s = v * x.value, s * x.size
    return Sized(v, s)


def _sized_power(base: Sized, exp: Sized) -> Sized:
    v, p = base.value, exp.value
    if v < 0 or (v == 0 and p < 0):
        return Sized(math.nan, math.nan)
    value = v ** p
    return Sized(value, abs(value) + abs(p) * v ** (p - 1) * base.size if v else abs(value))


def _sized(f, slope):
    """The sized version of a function of one argument with derivative ``slope``."""
    def apply(x: Sized) -> Sized:
        try:
            value = f(x.value)
            return Sized(value, abs(value) + abs(slope(x.value)) * x.size)
        except (ValueError, OverflowError, ZeroDivisionError):
            return Sized(math.nan, math.nan)
    return apply


def _sized_number(e) -> Sized:
    """A sympy number as :class:`Sized`: its double (:func:`_double_number`, which is ``complex(e)``
    where it is not exact; converted once) with its own size, or nan when it is not real."""
    value = _double_number(e)
    return Sized.of(value.real) if value.imag == 0 else Sized(math.nan, math.nan)


SIZED = Arithmetic(
    number=_sized_number,
    total=lambda values: Sized(*map(math.fsum, zip(*((x.value, x.size) for x in values)))),
    product=_sized_product,
    sqrt=lambda x: _sized_power(x, Sized(0.5, 0.5)),
    power=_sized_power,
    functions={sp.sin: _sized(math.sin, math.cos), sp.cos: _sized(math.cos, math.sin),
               sp.tan: _sized(math.tan, lambda x: 1 + math.tan(x) ** 2), sp.exp: _sized(math.exp, math.exp),
               sp.log: _sized(math.log, lambda x: 1 / x), sp.sinh: _sized(math.sinh, math.cosh),
               sp.cosh: _sized(math.cosh, math.sinh), sp.tanh: _sized(math.tanh, lambda x: 1 - math.tanh(x) ** 2),
               sp.asin: _sized(math.asin, lambda x: 1 / math.sqrt(1 - x * x)),
               sp.acos: _sized(math.acos, lambda x: 1 / math.sqrt(1 - x * x)),
               sp.atan: _sized(math.atan, lambda x: 1 / (1 + x * x)),
               sp.Abs: _sized(abs, lambda x: 1.0)},
)
"""Float64 values with the size of their round-off (:class:`Sized`): the size of each entry of a
linear system's matrix and right-hand side, from which :func:`solver.analyses.instant.error_bounds`
bounds what cancellation in them costs the answer."""


def mpmath_arithmetic() -> Arithmetic:
    """mpmath at its working precision (``mpmath.workdps``): rationals exact to that precision,
    other numbers through ``sympy.N`` with ten guard digits, sums by ``fsum``."""
    import mpmath

    def number(e):
        if e.is_Rational:
            return mpmath.mpf(e.p) / e.q
        return mpmath.mpmathify(str(sp.N(e, mpmath.mp.dps + 10)))

    return Arithmetic(number=number, total=mpmath.fsum, product=mpmath.fprod, sqrt=mpmath.sqrt,
                      power=mpmath.power,
                      functions={sp.sin: mpmath.sin, sp.cos: mpmath.cos, sp.tan: mpmath.tan, sp.cot: mpmath.cot,
                                 sp.exp: mpmath.exp, sp.log: mpmath.log, sp.Abs: abs})


def tree_value(expr: sp.Expr, point: dict, arithmetic: Arithmetic = DOUBLE, memo: dict | None = None):
    """``expr`` at ``point`` (Symbol -> value of the arithmetic's kind).

    Raises
    ------
    NotEvaluable
        At a node that is not a symbol, number, sum, product, power or one of the
        arithmetic's functions of one argument.
    KeyError
        A free symbol missing from ``point``.

    Examples
    --------
    >>> x = sp.Symbol("x")
    >>> tree_value(sp.sin(x)**2 + sp.cos(x)**2 + sp.Rational(1, 2), {x: 0.3})
    (1.5+0j)
    """
    memo = {} if memo is None else memo
    value = memo.get(expr)
    if value is not None:
        return value
    if expr.is_Symbol:
        value = point[expr]
    elif expr.is_Number:
        value = arithmetic.number(expr)
    elif expr.is_Add:
        value = arithmetic.total(tree_value(a, point, arithmetic, memo) for a in expr.args)
    elif expr.is_Mul:
        value = arithmetic.product(tree_value(a, point, arithmetic, memo) for a in expr.args)
    elif expr.is_Pow:
        base, exp = tree_value(expr.base, point, arithmetic, memo), expr.exp
        if exp.is_Integer:
            value = base ** int(exp)
        elif exp == sp.S.Half:
            value = arithmetic.sqrt(base)
        else:
            value = arithmetic.power(base, tree_value(exp, point, arithmetic, memo))
    elif type(expr) in arithmetic.functions and len(expr.args) == 1:
        value = arithmetic.functions[type(expr)](tree_value(expr.args[0], point, arithmetic, memo))
    elif expr.is_number and not expr.free_symbols:
        value = arithmetic.number(expr)
    else:
        raise NotEvaluable(type(expr).__name__)
    memo[expr] = value
    return value



def affine_value(expr: sp.Expr, point: dict, unknowns: list, memo: dict | None = None,
                 forms: dict | None = None, arithmetic: Arithmetic = DOUBLE) -> list:
    """[``expr`` with the ``unknowns`` 0, then the coefficient of each unknown] at ``point`` (Symbol ->
    double), for an ``expr`` affine in the unknowns, by one walk of its tree in double-precision
    complex arithmetic (:data:`DOUBLE`): a subtree free of the unknowns has its :func:`tree_value`
    (``memo``, shared with it); a sum adds its arguments' lists in their order, a product scales
    the one argument that holds unknowns by the product of the others. No expression is built
    (``expand`` of the tree with the point substituted costs tens of times more). ``forms``: the
    forms of the subtrees holding unknowns, shared by calls with the same point and unknowns (the
    equations of one formulation share their kinematics); the lists are never changed once made.
    ``arithmetic``: :data:`DOUBLE`, or :data:`SIZED` for the round-off size of each value the
    double walk computes (``point`` then holds :class:`Sized` values), the same operations in
    the same order.

    Raises
    ------
    NotEvaluable
        A product of two arguments holding unknowns, an unknown under a power or a function (not
        affine, or not in that form), or a node :func:`tree_value` does not evaluate.
    KeyError
        A free symbol missing from ``point`` (and not an unknown).
    """
    memo = {} if memo is None else memo
    index = {u: k for k, u in enumerate(unknowns, start=1)}
    size = len(unknowns) + 1
    affine = {} if forms is None else forms
    zero, one = arithmetic.number(sp.Integer(0)), arithmetic.number(sp.Integer(1))

    def walk(e):  # a value (no unknown below) or the list of the affine form
        done = memo.get(e)
        if done is None:
            done = affine.get(e)
        if done is not None:
            return done
        if e in index:
            out = [zero] * size
            out[index[e]] = one
        elif not (e.is_Add or e.is_Mul):
            if any(isinstance(walk(a), list) for a in e.args):
                raise NotEvaluable(f"an unknown under {type(e).__name__}")
            return tree_value(e, point, arithmetic, memo)
        else:
            parts = [walk(a) for a in e.args]
            forms = [p for p in parts if isinstance(p, list)]
            if not forms:
                value = arithmetic.total(parts) if e.is_Add else arithmetic.product(parts)
                memo[e] = value
                return value
            out = _affine_sum(parts, size, zero) if e.is_Add else _affine_product(parts, forms, arithmetic)
        affine[e] = out
        return out

    out = walk(expr)
    return out if isinstance(out, list) else [out] + [zero] * len(unknowns)


def _affine_sum(parts: list, size: int, zero=0j) -> list:
    """The affine form of a sum of ``parts`` (values, and forms: lists), added in their order
    (``zero``: the arithmetic's 0; its values add with ``+``)."""
    out = [zero] * size
    for p in parts:
        if isinstance(p, list):
            out = [a + b for a, b in zip(out, p)]
        else:
            out[0] += p
    return out


def _affine_product(parts: list, forms: list, arithmetic: Arithmetic = DOUBLE) -> list:
    """The affine form of a product of ``parts`` of which one, ``forms[0]``, holds unknowns: that form
    times the product of the others (their values multiply with ``*``)."""
    if len(forms) > 1:
        raise NotEvaluable("a product of two factors holding unknowns")
    k = arithmetic.product(p for p in parts if not isinstance(p, list))
    return [k * c for c in forms[0]]


def _program_steps(exprs: list, arithmetic: Arithmetic) -> tuple[list, list]:
    """(steps, outputs) of :func:`tree_program`: each distinct subtree of ``exprs`` once, its
    arguments before it, as (kind, what, argument slots); ``outputs`` the slot of each expression."""
    slots: dict = {}  # subtree -> its slot
    steps: list = []  # per slot: (kind, what, argument slots)

    def slot(expr) -> int:
        found = slots.get(expr)
        if found is not None:
            return found
        if expr.is_Symbol:
            step = ("symbol", expr, ())
        elif expr.is_Number:
            step = ("number", expr, ())
        elif expr.is_Add or expr.is_Mul:
            step = ("total" if expr.is_Add else "product", None, tuple(slot(a) for a in expr.args))
        elif expr.is_Pow:
            base, exp = slot(expr.base), expr.exp
            if exp.is_Integer:
                step = ("integer power", int(exp), (base,))
            elif exp == sp.S.Half:
                step = ("sqrt", None, (base,))
            else:
                step = ("power", None, (base, slot(exp)))
        elif type(expr) in arithmetic.functions and len(expr.args) == 1:
            step = ("function", arithmetic.functions[type(expr)], (slot(expr.args[0]),))
        elif expr.is_number and not expr.free_symbols:
            step = ("number", expr, ())
        else:
            raise NotEvaluable(type(expr).__name__)
        steps.append(step)
        slots[expr] = len(steps) - 1
        return slots[expr]

    outputs = [slot(e) for e in exprs]
    return steps, outputs


def tree_program(exprs: list, arithmetic: Arithmetic = DOUBLE) -> tuple[Callable[[dict], list], set]:
    """(f, symbols): f(point) -> the values of ``exprs`` at ``point`` as :func:`tree_value` gives them (the same
    operations on the same values in the same order), for evaluating the same expressions at many
    points: the trees are walked once here, each distinct subtree given a slot, so that each point
    costs only the arithmetic (no sympy hashing or dispatch per node and point).

    The numbers of the trees are made by the arithmetic at the first call (at the working precision
    then, as :func:`tree_value` makes them at each call; made again should it change). ``symbols``: the
    symbols of the trees, which ``point`` must give (their free symbols: the trees the walk knows bind
    none).

    Raises
    ------
    NotEvaluable
        As :func:`tree_value`, here and not at the call.
    """
    steps, outputs = _program_steps(exprs, arithmetic)
    numbers: dict = {}  # working precision -> the numbers' values
    total, product, sqrt, power = arithmetic.total, arithmetic.product, arithmetic.sqrt, arithmetic.power

    def run(point: dict) -> list:
        made = numbers.get(mpmath.mp.prec)
        if made is None:
            made = numbers[mpmath.mp.prec] = {k: arithmetic.number(what) for k, (kind, what, _) in enumerate(steps)
                                               if kind == "number"}
        values: list = []
        for k, (kind, what, args) in enumerate(steps):
            if kind == "symbol":
                value = point[what]
            elif kind == "number":
                value = made[k]
            elif kind == "total":
                value = total(values[a] for a in args)
            elif kind == "product":
                value = product(values[a] for a in args)
            elif kind == "integer power":
                value = values[args[0]] ** what
            elif kind == "sqrt":
                value = sqrt(values[args[0]])
            elif kind == "power":
                value = power(values[args[0]], values[args[1]])
            else:
                value = what(values[args[0]])
            values.append(value)
        return [values[k] for k in outputs]
    return run, {what for kind, what, _ in steps if kind == "symbol"}


def real_value(value) -> float:
    """The real number a double-precision walk (:data:`DOUBLE`, complex arithmetic) gave: its real
    part when the imaginary part is round-off (at most 1e-12 of the real part's size, or of 1),
    else nan (the expression is not real there: a square root of a negative number)."""
    value = complex(value)
    return value.real if abs(value.imag) <= 1e-12 * max(1.0, abs(value.real)) else float("nan")


def substitute(expr: sp.Basic, rule: dict, memo: dict) -> sp.Basic:
    """``expr.xreplace(rule)``, with the subtrees that several expressions (or one, in several
    places) share rebuilt once: ``memo`` (original subtree -> result) is shared by the calls of one
    evaluation. The same trees as ``xreplace``: each node is rebuilt by ``node.func(*args)`` from the
    same arguments in the same order, and left as it is when none of them changed (so Float
    arithmetic at the state gives the same numbers to the last bit)."""
    if not isinstance(expr, sp.Basic):  # a non-sympy argument (xreplace leaves it too)
        return expr
    if expr in rule:
        return rule[expr]
    done = memo.get(expr)
    if done is not None:
        return done
    args = expr.args
    new = tuple(substitute(a, rule, memo) for a in args)
    out = expr.func(*new) if any(a is not b for a, b in zip(new, args)) else expr
    memo[expr] = out
    return out
