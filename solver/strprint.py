"""``sympy.sstr``, the same text at a fraction of the cost, for the displays of ``eom`` and ``explain``.

sympy's :class:`~sympy.printing.str.StrPrinter` spends most of its time on
work it repeats or does generically: the precedence of a node is found again
by each caller, a subexpression met twice (``sin(beta)``, ``cos(theta)**2``)
is printed twice, and each sum's terms are ordered by
:meth:`sympy.core.expr.Expr.as_ordered_terms`, which turns every rational
coefficient into a complex number through ``evalf``.

:class:`FastStrPrinter` is a StrPrinter that keeps every printing rule and
changes only how the work is done:

* each distinct subexpression is printed once per printer (the text of a node
  depends on the node alone; sympy compares nodes structurally, and a Float is
  never equal to an Integer or Rational, so ``2.0*x`` and ``2*x`` stay apart),
  except a Float itself, whose text depends on where it stands (``1.50000000000000``
  printed alone, ``1.5`` inside ``sin(1.5*theta)``: sympy's ``full_prec="auto"``);
* the precedence of a node is found once per printer (once per class where the class alone
  decides it), and so is the printing method of each class (sympy walks the class's method
  resolution order at every node);
* a product's coefficient is put in front of its other factors without a sort key (a number's
  key is below every other factor's);
* a sum's terms are ordered by the same key as ``as_ordered_terms`` (lex order
  of the exponents of the sorted generators, then the coefficient), with a
  rational coefficient made complex by exact integer division (correctly
  rounded, as ``evalf`` at 53 bits is) instead of ``evalf``.

The text is sympy's own: ``tests/test_strprint.py`` compares it with
``sympy.sstr`` on random expressions and on every display of the shipped scenes.
"""
from __future__ import annotations


import sympy as sp
from sympy.core.exprtools import decompose_power
from sympy.core.function import AppliedUndef, UndefinedFunction
from sympy.core.sorting import default_sort_key
from sympy.printing.numpy import NumPyPrinter
from sympy.printing.precedence import PRECEDENCE, PRECEDENCE_FUNCTIONS, PRECEDENCE_VALUES, precedence
from sympy.printing.pycode import PythonCodePrinter
from sympy.printing.str import StrPrinter

from .display import could_extract_minus_sign
from .kept import Kept

__all__ = ["FastStrPrinter", "sstr", "join_sum", "lambdify"]

_EXACT = 2 ** 53
"""Numerators and denominators below this are exact doubles, so p/q is one correctly rounded division."""


def _complex(number) -> complex:
    """``complex(number)`` as sympy computes it (``evalf`` at 53 bits), without evalf for a rational."""
    if number.is_Rational and abs(number.p) < _EXACT and number.q < _EXACT:
        return complex(number.p / number.q)
    return complex(number)


def _coeff_factors(term) -> tuple:
    """(c, factors): ``c, rest = term.as_coeff_Mul()`` and the factors of ``rest`` (none when it is
    1), without building ``rest`` (a new product for every term of every sum printed)."""
    if term.is_Mul:
        c = term.args[0]
        return (c, term.args[1:]) if c.is_Number else (sp.S.One, term.args)
    return (term, ()) if term.is_Number else (sp.S.One, (term,))


def _terms_with_keys(expr, sort_key) -> list:
    """``Expr.as_terms`` of a sum: (term, (coefficient, exponents of the sorted generators, ()))."""
    gens, terms = set(), []
    for term in sp.Add.make_args(expr):
        coeff, factors = _coeff_factors(term)
        coeff = _complex(coeff)
        powers = {}
        for factor in factors:
            if factor.is_number:
                try:
                    coeff *= _complex(factor)
                except (TypeError, ValueError):
                    pass
                else:
                    continue
            base, exp = decompose_power(factor)
            powers[base] = exp
            gens.add(base)
        terms.append((term, (coeff.real, coeff.imag), powers))
    index = {g: i for i, g in enumerate(sorted(gens, key=sort_key))}
    out = []
    for term, coeff, powers in terms:
        monom = [0] * len(index)
        for base, exp in powers.items():
            monom[index[base]] = exp
        out.append((term, coeff, tuple(monom)))
    return out


def _ordered_terms(expr, sort_key=default_sort_key) -> list:
    """The terms of a commutative sum in the order of ``expr.as_ordered_terms()`` (lex)."""
    keyed = _terms_with_keys(expr, sort_key)

    def key(item):
        _, (re, im), monom = item
        return tuple(-m for m in monom), (), ((bool(im), im), (re, im))

    return [term for term, _, _ in sorted(keyed, key=key)]


class _FastOrdering:
    """A printer's sums ordered as ``as_ordered_terms`` orders them, without its ``evalf`` (see the module)."""

    def _as_ordered_terms(self, expr, order=None):
        if (order or self.order) is not None or not expr.is_commutative or any(
                t.is_Order for t in expr.args) or _special_pair(expr):
            return super()._as_ordered_terms(expr, order=order)
        return _ordered_terms(expr, self._sort_key)

    def _sort_key(self, item):
        return default_sort_key(item)


class FastStrPrinter(_FastOrdering, StrPrinter):
    """sympy's StrPrinter with default settings, each node printed and ranked once (see the module)."""

    def __init__(self):
        super().__init__()
        self._texts: dict = {}
        self._precedences: dict = {}  # node -> its precedence, where the class alone does not say it
        self._class_precedences: dict = {}  # class -> the precedence of all its nodes, or None
        self._sort_keys: dict = {}
        self._methods: dict = {}  # class -> its printing method (unbound), or _GENERIC

    def _sort_key(self, item):
        key = self._sort_keys.get(item)
        if key is None:
            key = self._sort_keys[item] = default_sort_key(item)
        return key

    def _print(self, expr, **kwargs) -> str:
        if kwargs or not isinstance(expr, sp.Basic) or expr.is_Float:  # a Float's text depends on its level:
            return super()._print(expr, **kwargs)  # all its digits alone, shortest inside an expression
        text = self._texts.get(expr)
        if text is None:
            text = self._texts[expr] = self._print_new(expr)
        return text

    def _print_new(self, expr) -> str:
        """``Printer._print`` of a Basic: the printing method of its class, found once per class (sympy
        walks the class's method resolution order at every node); the printing level kept as there."""
        method = self._methods.get(type(expr))
        if method is None:
            method = self._methods[type(expr)] = _method_of(self, type(expr))
        if method is _GENERIC:
            return super()._print(expr)
        self._print_level += 1
        try:
            return method(self, expr)
        finally:
            self._print_level -= 1

    def _precedence(self, item) -> int:
        if not isinstance(item, sp.Basic):
            return precedence(item)
        value = self._class_precedences.get(type(item), _UNSET)
        if value is _UNSET:
            value = self._class_precedences[type(item)] = _class_precedence(type(item))
        if value is not None:
            return value
        if item.is_Rational:  # precedence_Integer, precedence_Rational
            return _ADD if item.p < 0 else _ATOM if item.q == 1 else _MUL
        value = self._precedences.get(item)
        if value is None:
            value = self._precedences[item] = _precedence_of(item)
        return value

    def parenthesize(self, item, level, strict=False):
        prec = self._precedence(item)
        if prec < level or (not strict and prec <= level):
            return "(%s)" % self._print(item)
        return self._print(item)

    def _print_Add(self, expr, order=None):  # StrPrinter._print_Add with the precedences remembered
        terms = self._as_ordered_terms(expr, order=order)
        prec = self._precedence(expr)
        parts = []
        for term in terms:
            t = self._print(term)
            if t.startswith("-") and not term.is_Add:
                sign, t = "-", t[1:]
            else:
                sign = "+"
            if self._precedence(term) < prec or term.is_Add:
                parts.extend([sign, "(%s)" % t])
            else:
                parts.extend([sign, t])
        sign = parts.pop(0)
        return ("" if sign == "+" else sign) + " ".join(parts)

    def _ordered_factors(self, c, rest) -> tuple:
        """``c`` and ``rest`` sorted by ``sort_key``. A number's key, (class key (1, 0, 'Number'),
        (0, ()), ...), is below that of any factor that is not a number: every other class key is
        larger, and a power of a number, whose key is its base's, follows with (1, (base,)). So
        ``c`` comes first, and one factor needs no sorting."""
        rest = rest if len(rest) < 2 else sorted(rest, key=self._sort_key)
        return rest if c is sp.S.One else (c, *rest)

    def _print_Mul(self, expr):
        """StrPrinter._print_Mul; for an evaluated commutative product its factors are ordered
        directly: sympy's ``_keep_coeff(-c, rest).as_ordered_factors()`` is the coefficient and
        the other factors sorted by ``sort_key``."""
        args = expr.args
        if not expr.is_commutative or args[0] is sp.S.One or self.order not in (None, "lex") or any(
                isinstance(a, sp.Number) or a.is_Mul or a.is_Pow and a.base.is_Integer and a.exp.is_Integer
                for a in args[1:]):  # a product inside a product: sympy left it unflattened (-I**(3/2))
            return super()._print_Mul(expr)
        prec = self._precedence(expr)
        c, rest = (args[0], args[1:]) if args[0].is_Number else (sp.S.One, args)
        sign = ""
        if _negative(c):
            c, sign = -c, "-"
        factors = self._ordered_factors(c, rest)
        a_str, b, b_str, pow_paren = [], [], [], []  # numerator, denominator, bases of x**-1 with a compound base
        for item in factors:
            if item.is_Pow and _negative(item.exp.as_coeff_Mul()[0]):
                if item.exp is not sp.S.NegativeOne:
                    b.append(_inverted_power(item))
                else:
                    if len(item.args[0].args) != 1 and isinstance(item.base, (sp.Mul, sp.Pow)):
                        pow_paren.append(item)
                    b.append(item.base)
                b_str.append(self.parenthesize(b[-1], prec, strict=False))
            elif item.is_Rational:  # positive here: its numerator and denominator print as integers
                if item.p != 1:
                    a_str.append(str(item.p))
                if item.q != 1:
                    b.append(None)
                    b_str.append(str(item.q))
            else:
                a_str.append(self.parenthesize(item, prec, strict=False))
        a_str = a_str or ["1"]
        for item in pow_paren:
            if item.base in b:
                b_str[b.index(item.base)] = "(%s)" % b_str[b.index(item.base)]
        if not b:
            return sign + "*".join(a_str)
        if len(b) == 1:
            return sign + "*".join(a_str) + "/" + b_str[0]
        return sign + "*".join(a_str) + "/(%s)" % "*".join(b_str)



_GENERIC = object()
"""The mark of a class whose nodes go through ``Printer._print`` itself."""


def _method_of(printer, cls):
    """The unbound ``_print_<Class>`` method ``Printer._print`` picks for the nodes of ``cls`` (the same
    classes tried in the same order: an undefined function from its base, a subclass of a named
    function skipped); :data:`_GENERIC` for a class that prints itself (``_sympystr``) or one no
    method serves (the empty printer)."""
    if hasattr(cls, printer.printmethod):
        return _GENERIC
    classes = cls.__mro__
    for base in (AppliedUndef, UndefinedFunction):
        if base in classes:
            classes = classes[classes.index(base):]
    if sp.Function in classes:
        i = classes.index(sp.Function)
        classes = tuple(c for c in classes[:i] if c.__name__ == classes[0].__name__
                        or c.__name__.endswith("Base")) + classes[i:]
    for c in classes:
        method = getattr(type(printer), "_print_" + c.__name__, None)
        if method is not None:
            return method
    return _GENERIC


def _negative(number) -> bool:
    """``bool(number < 0)`` of a sympy number; a rational's sign read from its numerator (sympy's
    comparison sympifies the 0 first)."""
    return number.p < 0 if number.is_Rational else bool(number < 0)


_UNSET = object()
_ADD, _MUL, _ATOM = PRECEDENCE["Add"], PRECEDENCE["Mul"], PRECEDENCE["Atom"]


def _class_precedence(cls) -> int | None:
    """The precedence sympy's ``precedence`` gives every node of class ``cls`` (the first class of its
    method resolution order with a fixed value, else an atom's); None when it depends on the node
    (a rule of ``PRECEDENCE_FUNCTIONS``, or a ``precedence`` attribute)."""
    if hasattr(cls, "precedence"):
        return None
    for c in cls.__mro__:
        if c.__name__ in PRECEDENCE_FUNCTIONS:
            return None
        if c.__name__ in PRECEDENCE_VALUES:
            return PRECEDENCE_VALUES[c.__name__]
    return _ATOM


def _precedence_of(item) -> int:
    """sympy's ``precedence``; for a product, its minus sign found by
    :func:`solver.display.could_extract_minus_sign` (without building the product's negative)."""
    if type(item) is sp.Mul and not any(isinstance(a, sp.Function) and hasattr(a, "precedence") for a in item.args):
        return _ADD if could_extract_minus_sign(item) else _MUL
    return precedence(item)


def _inverted_power(item):
    """``apow`` of StrPrinter._print_Mul: b**(-e) of a power b**e whose exponent's coefficient is negative."""
    base, exp = item.as_base_exp()
    eargs = list(sp.Mul.make_args(exp))
    if eargs[0] is sp.S.NegativeOne:
        eargs = eargs[1:]
    else:
        eargs[0] = -eargs[0]
    return item.func(base, sp.Mul._from_args(eargs), evaluate=False)


def _special_pair(expr) -> bool:
    """A sum of a number and a number times something: ``as_ordered_terms`` may keep it as written."""
    return len(expr.args) == 2 and any(isinstance(a, (sp.Number, sp.NumberSymbol)) for a in expr.args)


def sstr(expr, printer: FastStrPrinter | None = None) -> str:
    """``sympy.sstr(expr)`` (default settings), by :class:`FastStrPrinter`.

    Parameters
    ----------
    expr : sympy.Basic
    printer : FastStrPrinter, optional
        Reuse one printer for several expressions of one display (their common
        subexpressions are then printed once); a new one by default.

    Examples
    --------
    >>> th = sp.Symbol("theta")
    >>> sstr(3 * sp.cos(th)**2 / 2 - sp.sin(th) + 1) == sp.sstr(3 * sp.cos(th)**2 / 2 - sp.sin(th) + 1)
    True
    """
    return (printer or FastStrPrinter()).doprint(expr)


def join_sum(texts) -> str:
    """Printed terms joined into the text of their sum as sympy prints one: a term printed with a
    leading minus follows as ``a - b``, not ``a + -b``.

    >>> join_sum(["k*s_ddot", "-L*theta_dot**2*cos(theta)", "x"])
    'k*s_ddot - L*theta_dot**2*cos(theta) + x'
    """
    out = ""
    for i, s in enumerate(texts):
        out += (s if i == 0 else f" - {s[1:]}" if s.startswith("-") else f" + {s}")
    return out


class _FastNumPyPrinter(_FastOrdering, NumPyPrinter):
    """NumPyPrinter, sums ordered without evalf (the same code)."""


class _FastPythonCodePrinter(_FastOrdering, PythonCodePrinter):
    """PythonCodePrinter, sums ordered without evalf (the same code)."""


def lambdify(args, expr, modules: str, cse: bool = False):
    """``sympy.lambdify(args, expr, modules, cse=cse)`` for the solver's own numeric functions: the
    same generated code (lambdify's own printer for ``"numpy"`` or ``"math"``, with its settings,
    sums ordered as in :class:`FastStrPrinter`), and no docstring (lambdify prints the whole
    expression into it, about half its cost; nobody reads these functions' docstrings). Other
    ``modules`` (``"mpmath"``) keep lambdify's own printer, without the docstring.

    The function made for equal arguments is made once per process (the last 1024, a
    :class:`solver.kept.Kept`): a scene loaded again (a command after another, each test of a suite)
    gives the same expressions, and printing them into code is most of the cost."""
    def make():
        fast = {"numpy": _FastNumPyPrinter, "math": _FastPythonCodePrinter}.get(modules)
        printer = None if fast is None else fast(
            {"fully_qualified_modules": False, "inline": True, "allow_unknown_functions": True, "user_functions": {}})
        return sp.lambdify(args, expr, modules=modules, printer=printer, cse=cse, docstring_limit=0)

    return _LAMBDIFIED.get(_lambdify_key(args, expr, modules, cse), make)


_LAMBDIFIED = Kept(1024)


def _lambdify_key(args, expr, modules: str, cse: bool):
    """A key equal only for arguments that print the same code, or None (not kept).

    sympy objects compare structurally (a Float is never equal to an Integer, nor to a Float of
    another precision; symbols of other assumptions differ), so equal ones print alike; the type of
    each container and Python number is part of the key (a list gives a list, a tuple a tuple,
    2.0 is not 2)."""
    def frozen(x):
        if isinstance(x, sp.MatrixBase):
            return (type(x).__name__, x.as_immutable())
        if isinstance(x, sp.Basic):
            return x
        if isinstance(x, (list, tuple)):
            return (type(x).__name__, *map(frozen, x))
        if type(x) in (int, float, complex, bool, str):
            return (type(x).__name__, x)
        raise TypeError(type(x).__name__)

    try:
        key = (modules, bool(cse), frozen(args), frozen(expr))
        hash(key)
    except TypeError:
        return None
    return key
