"""A whitelist parser for the expressions written in scene files.

Scene files hold formulas as text: positions such as ``"l_b/2"``, an
orientation ``"pi - theta"``, a force history ``"F_0*sin(w*t)"``. Text from a
file is data, never code, so nothing here calls ``eval``, ``exec``,
``sympify`` or ``parse_expr``. The text is parsed into a Python syntax tree
(:func:`ast.parse` only builds the tree; it runs nothing) and the tree is
walked node by node. Only the node types listed below are accepted; each is
turned directly into the matching sympy object. Anything else is refused
with an :class:`~solver.errors.ExpressionError` that says where the text came
from, what is not allowed, and the offending piece of text.

Accepted
--------
* numbers: integers, decimals and scientific notation (``2``, ``0.5``,
  ``1.5e-3``). Decimals become *exact* rationals (``0.5`` -> 1/2), so
  symbolic comparisons stay exact; ``1/3`` is ``Rational(1, 3)``;
* names given by the caller (parameters, the coordinate, ``t`` ...) and
  ``pi``;
* ``+ - * /``, powers written ``**`` or ``^``, unary ``+``/``-``,
  parentheses;
* calls of the functions in :data:`FUNCTIONS` with positional arguments.
"""
from __future__ import annotations

import ast
import keyword
import math
from collections.abc import Callable, Mapping
from fractions import Fraction

import sympy as sp

from solver.errors import ExpressionError

MAX_LENGTH = 500
"""Longest accepted expression text [characters]."""
MAX_DEPTH = 100
"""Deepest accepted nesting of operations and calls."""
MAX_DIGITS = 300
"""Largest number of decimal digits a numeric power may produce (keeps
``9**9**9`` from computing a huge integer). Every constant part of an
expression (a literal, or a sub-expression free of names) must also lie
within 10**-MAX_DIGITS .. 10**MAX_DIGITS in size (or be 0) and be real."""
MAX_EXPONENT = 12
"""Largest size of a constant exponent on a base that holds names (``theta**12``,
``(l_b/2)**3``); its denominator, for a fraction, is at most this too. Larger
powers of the coordinate (``theta**(10**300)``) would stall the derivation."""
MAX_ARGUMENT = 1e15
"""Largest size of a constant function argument (``exp(1e6)``, ``cos(1e200)``):
beyond it float64 has lost the value (or the result overflows), and sympy's
exact evaluation of ``exp(exp(exp(100)))`` would never finish."""

# name -> (sympy function, allowed argument counts)
FUNCTIONS: dict[str, tuple[Callable[..., sp.Expr], tuple[int, ...]]] = {
    "sin": (sp.sin, (1,)),
    "cos": (sp.cos, (1,)),
    "tan": (sp.tan, (1,)),
    "asin": (sp.asin, (1,)),
    "acos": (sp.acos, (1,)),
    "atan": (sp.atan, (1,)),
    "atan2": (sp.atan2, (2,)),
    "sqrt": (sp.sqrt, (1,)),
    "exp": (sp.exp, (1,)),
    "log": (sp.log, (1, 2)),
    "abs": (sp.Abs, (1,)),
    "sinh": (sp.sinh, (1,)),
    "cosh": (sp.cosh, (1,)),
    "tanh": (sp.tanh, (1,)),
    "sign": (sp.sign, (1,)),
    "min": (sp.Min, (2, 3, 4, 5, 6, 7, 8)),
    "max": (sp.Max, (2, 3, 4, 5, 6, 7, 8)),
}
CONSTANTS: dict[str, sp.Expr] = {"pi": sp.pi}
RESERVED_NAMES = frozenset(FUNCTIONS) | frozenset(CONSTANTS)
"""Names a scene cannot use for its own parameters."""
SOLVER_NAMES = frozenset({"t", "alpha"})
"""Names of the solver's own symbols (time, and alpha: a body's angular acceleration, an unknown
of the worked solutions): a scene's parameter or coordinate cannot take them (a parameter
``alpha`` was printed as, and merged with, the unknown alpha). ``omega`` stays free: a crank
speed named omega is a parameter of its own, printed beside the bodies' ``omega = ...``."""

_BINARY = {
    ast.Add: lambda a, b: a + b,
    ast.Sub: lambda a, b: a - b,
    ast.Mult: lambda a, b: a * b,
    ast.Div: lambda a, b: a / b,
    ast.Pow: lambda a, b: a**b,
}

# Friendly names for refused syntax, so the message says what was written.
_REFUSED = {
    ast.Attribute: "attribute access",
    ast.Subscript: "subscripts",
    ast.Lambda: "lambda functions",
    ast.ListComp: "comprehensions",
    ast.SetComp: "comprehensions",
    ast.DictComp: "comprehensions",
    ast.GeneratorExp: "comprehensions",
    ast.Starred: "starred arguments",
    ast.List: "lists",
    ast.Tuple: "tuples",
    ast.Dict: "dictionaries",
    ast.Set: "sets",
    ast.Compare: "comparisons",
    ast.BoolOp: "boolean operators",
    ast.IfExp: "conditional expressions",
    ast.NamedExpr: "assignments",
    ast.JoinedStr: "strings",
    ast.Await: "await",
    ast.Yield: "yield",
    ast.YieldFrom: "yield",
    ast.Slice: "slices",
}


def parse_expression(text: str, names: Mapping[str, sp.Symbol], where: str) -> sp.Expr:
    """Parse one scene expression into a sympy expression, by whitelist.

    Parameters
    ----------
    text : str
        The expression as written, e.g. ``"l_b*sin(beta - theta)/sin(beta)"``.
        ``^`` means power, like ``**``.
    names : Mapping[str, sympy.Symbol]
        The names the expression may use (parameters, the coordinate, ``t``),
        each mapped to its sympy symbol. ``pi`` is always available.
    where : str
        Where the text came from, e.g. ``"sliding_bar.toml: points.B"``;
        it starts every error message.

    Returns
    -------
    sympy.Expr
        The expression; exact rationals for decimal numbers.

    Raises
    ------
    ExpressionError
        ``"<where>: <what is wrong> in '<text>'"`` for anything outside the
        whitelist (attributes, subscripts, lambdas, comprehensions, strings,
        keyword arguments, unknown names or functions), for text longer than
        :data:`MAX_LENGTH` or nested deeper than :data:`MAX_DEPTH`, and for
        expressions that are undefined (division by zero).

    Examples
    --------
    >>> import sympy as sp
    >>> l_b = sp.Symbol("l_b", real=True)
    >>> parse_expression("l_b/3 + 0.25*l_b", {"l_b": l_b}, "demo")
    7*l_b/12
    """
    _validate_parse_expression(text, names, where)
    plain = _plain_atom(text.strip(), names)
    if plain is not None:
        return plain
    source = text.replace("^", "**")
    try:
        tree = ast.parse(source.strip(), mode="eval")
    except SyntaxError as err:
        detail = err.msg or "invalid syntax"
        if err.offset:
            detail += f" at column {err.offset}"
        raise ExpressionError(f"{where}: syntax error ({detail}) in {text!r}") from None
    except (ValueError, RecursionError, MemoryError):
        raise ExpressionError(f"{where}: cannot parse {text!r}") from None
    builder = _Builder(source.strip(), text, names, where)
    expr = builder.build(tree.body, 0)
    if expr.has(sp.zoo, sp.nan, sp.oo, -sp.oo):
        raise ExpressionError(
            f"{where}: the expression is undefined (division by zero or a "
            f"function outside its domain) in {text!r}"
        )
    return expr


def _plain_atom(text: str, names: Mapping[str, sp.Symbol]) -> sp.Expr | None:
    """What the parser makes of a bare known name (``"m_b"``) or an unsigned integer (``"0"``),
    about half the expressions of a scene, without parsing: ``names[text]``, ``Integer(text)``.
    None for anything else, including what the parser would refuse or read differently (a
    keyword, a non-ASCII name, which Python normalizes, an integer with a leading zero)."""
    if not text.isascii():
        return None
    if text in names and text.isidentifier() and not keyword.iskeyword(text):
        return names[text]
    if text.isdigit() and (text == "0" or text[0] != "0"):
        return sp.Integer(int(text))
    return None


def _validate_parse_expression(text: object, names: Mapping[str, sp.Symbol], where: str) -> None:
    if not isinstance(text, str):
        raise ExpressionError(
            f"{where}: expected an expression written as text, got {type(text).__name__} {text!r}"
        )
    if not text.strip():
        raise ExpressionError(f"{where}: empty expression")
    if len(text) > MAX_LENGTH:
        raise ExpressionError(
            f"{where}: expression is {len(text)} characters long; the limit is "
            f"{MAX_LENGTH} in {text[:40]!r}..."
        )
    for name, symbol in names.items():
        if not isinstance(symbol, sp.Symbol):  # a caller bug, not a user error
            raise TypeError(f"`names[{name!r}]` must be a sympy Symbol, got {symbol!r}")


def _too_large_power(base: sp.Expr, exponent: sp.Expr) -> bool:
    """True when ``base**exponent`` would make sympy compute an exact rational
    with more than :data:`MAX_DIGITS` digits.

    sympy evaluates powers of rationals eagerly (also the rational factor of
    a product, ``(9*x)**2 = 81*x**2``); symbolic factors such as ``exp(230)``
    stay unevaluated and cost nothing.
    """
    if not exponent.is_Rational:
        return False
    coefficient = base.as_coeff_Mul()[0] if base.is_Mul else base
    if not coefficient.is_Rational:
        return False
    p, q = abs(int(coefficient.p)), int(coefficient.q)
    digits = max(math.log10(p) if p else 0.0, math.log10(q))
    return abs(float(exponent)) * digits > MAX_DIGITS


def _size(value: sp.Expr) -> float | None:
    """|value| of a constant built from bounded parts (cheap to evaluate), or None when it
    is not real or cannot be evaluated. A value below the least double (exp(-746), 1.2e-324) is
    sized as that least double, 5e-324: it is no 0."""
    try:
        n = sp.N(value, 20)
        z = complex(n)
    except (TypeError, ValueError, OverflowError, ArithmeticError):
        return None
    if z == 0 and n != 0:
        return math.ulp(0.0)
    if not (math.isfinite(z.real) and math.isfinite(z.imag)):
        return math.inf
    if abs(z.imag) > 1e-12 * max(abs(z.real), 1e-300):
        return None
    return abs(z.real)


def _huge_power(base: sp.Expr, exponent: sp.Expr) -> bool:
    """True when a constant ``base**exponent`` (e.g. ``pi**(10**100)``) would be larger
    than 10**MAX_DIGITS or smaller than 10**-MAX_DIGITS; checked before sympy builds it."""
    if not (base.is_number and exponent.is_number):
        return False
    b, e = _size(base), _size(exponent)
    if b is None or e is None or b == 0:
        return False  # complex or 0**e: left to the other checks
    return abs(e * math.log10(b)) > MAX_DIGITS


def _too_large_exponent(base: sp.Expr, exponent: sp.Expr) -> bool:
    """True when a base that holds names (the coordinate, parameters) is raised to a
    constant exponent larger than :data:`MAX_EXPONENT` in size, or to a fraction whose
    denominator is larger (``theta**(10**300)``, ``theta**(1/10**6)``)."""
    if base.is_number or not exponent.is_number:
        return False
    if exponent.is_Rational:
        return abs(exponent) > MAX_EXPONENT or exponent.q > MAX_EXPONENT
    size = _size(exponent)
    return size is None or size > MAX_EXPONENT


class _Builder:
    """Walks a parsed tree and builds the sympy expression, node by node."""

    def __init__(self, source: str, text: str, names: Mapping[str, sp.Symbol], where: str):
        self.source = source
        self.text = text
        self.names = names
        self.where = where

    # -- helpers ------------------------------------------------------------
    def _segment(self, node: ast.AST) -> str:
        seg = ast.get_source_segment(self.source, node)
        return seg if seg is not None else type(node).__name__

    def _fail(self, what: str, node: ast.AST | None = None) -> ExpressionError:
        piece = ""
        if node is not None:
            seg = self._segment(node)
            if seg.strip() != self.source:
                piece = f": {seg!r}"
        return ExpressionError(f"{self.where}: {what}{piece} in {self.text!r}")

    # -- the walk -----------------------------------------------------------
    def build(self, node: ast.AST, depth: int) -> sp.Expr:
        if depth > MAX_DEPTH:
            raise self._fail(f"nesting deeper than {MAX_DEPTH} levels")
        if isinstance(node, ast.Constant):
            return self._constant(node)
        if isinstance(node, ast.Name):
            return self._name(node)
        if isinstance(node, ast.UnaryOp):
            operand = self.build(node.operand, depth + 1)
            if isinstance(node.op, ast.USub):
                return -operand
            if isinstance(node.op, ast.UAdd):
                return operand
            raise self._fail(f"operator {type(node.op).__name__} is not allowed", node)
        if isinstance(node, ast.BinOp):
            return self._binop(node, depth)
        if isinstance(node, ast.Call):
            return self._call(node, depth)
        what = _REFUSED.get(type(node), f"{type(node).__name__} syntax")
        raise self._fail(f"{what} not allowed", node)

    def _constant(self, node: ast.Constant) -> sp.Expr:
        value = node.value
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            kind = "strings" if isinstance(value, (str, bytes)) else f"{type(value).__name__} values"
            raise self._fail(f"{kind} not allowed", node)
        if isinstance(value, int):
            return sp.Integer(value)
        # Exact rational from the digits as written (0.1 -> 1/10, not the binary float).
        try:
            frac = Fraction(self._segment(node).replace("_", ""))
        except (ValueError, ZeroDivisionError):
            frac = Fraction(value)
        # 10**300 itself has MAX_DIGITS + 1 digits
        if frac and max(len(str(abs(frac.numerator))), len(str(frac.denominator))) > MAX_DIGITS + 1:
            raise self._fail(f"number too large or too small (more than {MAX_DIGITS} digits)", node)
        return sp.Rational(frac.numerator, frac.denominator)

    def _name(self, node: ast.Name) -> sp.Expr:
        if node.id in self.names:
            return self.names[node.id]
        if node.id in CONSTANTS:
            return CONSTANTS[node.id]
        if node.id in FUNCTIONS:
            raise self._fail(f"function {node.id!r} used without calling it")
        known = ", ".join(sorted(set(self.names) | set(CONSTANTS))) or "none"
        raise self._fail(f"unknown name {node.id!r} (known names: {known})")

    def _binop(self, node: ast.BinOp, depth: int) -> sp.Expr:
        op = _BINARY.get(type(node.op))
        if op is None:
            raise self._fail(f"operator {type(node.op).__name__} is not allowed", node)
        left = self.build(node.left, depth + 1)
        right = self.build(node.right, depth + 1)
        if isinstance(node.op, ast.Pow) and (_too_large_power(left, right) or _huge_power(left, right)):
            raise self._fail(f"number too large or too small (more than {MAX_DIGITS} digits)", node)
        if isinstance(node.op, ast.Pow) and _too_large_exponent(left, right):
            raise self._fail(
                f"the exponent of {self._segment(node.left)!r} must be at most {MAX_EXPONENT} in size "
                f"(and a fraction's denominator at most {MAX_EXPONENT})", node)
        if isinstance(node.op, ast.Div) and right == 0:
            raise self._fail("division by zero", node)
        return self._checked(op(left, right), node)

    def _call(self, node: ast.Call, depth: int) -> sp.Expr:
        if not isinstance(node.func, ast.Name):
            what = _REFUSED.get(type(node.func), "calling this")
            raise self._fail(f"{what} not allowed", node.func)
        name = node.func.id
        if name not in FUNCTIONS:
            valid = ", ".join(sorted(FUNCTIONS))
            raise self._fail(f"unknown function {name!r} (valid functions: {valid})")
        if node.keywords:
            raise self._fail("keyword arguments not allowed", node)
        func, counts = FUNCTIONS[name]
        for arg in node.args:
            if isinstance(arg, ast.Starred):
                raise self._fail("starred arguments not allowed", arg)
        if len(node.args) not in counts:
            if len(counts) == 1:
                expected = str(counts[0])
            elif len(counts) == 2:
                expected = f"{counts[0]} or {counts[1]}"
            else:
                expected = f"{counts[0]} to {counts[-1]}"
            raise self._fail(
                f"{name}() takes {expected} argument(s), got {len(node.args)}", node
            )
        args = [self.build(arg, depth + 1) for arg in node.args]
        for arg, arg_node in zip(args, node.args):
            if arg.is_number and not arg.has(sp.zoo, sp.nan, sp.oo, -sp.oo):
                size = _size(arg)
                if size is None or size > MAX_ARGUMENT:
                    raise self._fail(
                        f"constant argument of {name}() too large (more than {MAX_ARGUMENT:g} in size)", arg_node
                    )
        return self._checked(func(*args), node)

    def _checked(self, value: sp.Expr, node: ast.AST) -> sp.Expr:
        """A constant sub-expression must be a real number of bounded size; an undefined one
        (zoo, nan, oo) is refused at once; names pass unchecked."""
        if value.has(sp.zoo, sp.nan, sp.oo, -sp.oo):
            # refused where it happens: an enclosing node could hide it (1/(0**-1) is 0 to sympy)
            raise self._fail("the expression is undefined (division by zero or a function outside its domain)",
                             node)
        if not value.is_number:
            # constant factors combine as they are built: L*1e299*1e299 holds 10**598
            for r in value.atoms(sp.Rational):
                if max(len(str(abs(r.p))), len(str(r.q))) > MAX_DIGITS + 1:
                    raise self._fail(f"number too large or too small (more than {MAX_DIGITS} digits)", node)
            return value
        size = _size(value)
        if size is None:
            raise self._fail("the constant is not a real number", node)
        if size != 0 and not (10.0**-MAX_DIGITS <= size <= 10.0**MAX_DIGITS):
            raise self._fail(f"number too large or too small (more than {MAX_DIGITS} digits)", node)
        return value


__all__ = ["parse_expression", "FUNCTIONS", "CONSTANTS", "RESERVED_NAMES", "SOLVER_NAMES", "MAX_LENGTH", "MAX_DEPTH", "MAX_DIGITS",
           "MAX_EXPONENT", "MAX_ARGUMENT"]
