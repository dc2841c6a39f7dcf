"""Equations for the outputs: presentation MathML for HTML, LaTeX for the paper.

Browsers render MathML natively (MathML Core), so the HTML needs no script or
web font. Symbols follow the paper's notation: ``theta_dot`` is printed as a
dotted theta, ``theta_ddot`` with two dots, ``R_B`` with a subscript.
"""
from __future__ import annotations

import re
from functools import lru_cache

import sympy as sp
from markupsafe import Markup
from sympy.printing.latex import LatexPrinter
from sympy.printing.mathml import MathMLPresentationPrinter

__all__ = ["to_mathml", "equation_mathml", "to_latex", "equation_latex", "display_symbols"]

_MATHML_NS = "http://www.w3.org/1998/Math/MathML"
_DOTS = (("_ddot", "\u00a8"), ("_dot", "\u02d9"))
_LATEX_DOTS = (("_ddot", r"\ddot"), ("_dot", r"\dot"))


class _Printer(MathMLPresentationPrinter):
    """sympy's presentation printer with dotted time derivatives."""

    def _print_Symbol(self, sym, style="plain"):  # noqa: N802 (sympy's naming)
        for suffix, accent in _DOTS:
            if sym.name.endswith(suffix):
                base = sp.Symbol(sym.name[: -len(suffix)])
                over = self.dom.createElement("mover")
                over.setAttribute("accent", "true")
                over.appendChild(super()._print_Symbol(base, style))
                mo = self.dom.createElement("mo")
                mo.appendChild(self.dom.createTextNode(accent))
                over.appendChild(mo)
                return over
        return super()._print_Symbol(sym, style)


def _mathml_body(expr: sp.Basic) -> str:
    """The MathML of one expression, printed once per build however often it is shown (the
    report prints each transcribed equation in block and inline form, the paper shares some)."""
    try:
        return _printed_mathml(expr)
    except TypeError:  # an unhashable expression (a mutable Matrix): printed each time
        return _Printer({"mul_symbol": None}).doprint(expr)


@lru_cache(maxsize=2048)
def _printed_mathml(expr: sp.Basic) -> str:
    # sympy's == is structural (2.0 and 2 differ), so equal expressions print alike
    return _Printer({"mul_symbol": None}).doprint(expr)


def _wrap(body: str, display: str) -> Markup:
    # Output of sympy's printer only contains text of our own symbols and numbers,
    # escaped by xml.dom; it is safe to mark up.
    return Markup(f'<math xmlns="{_MATHML_NS}" display="{display}">{body}</math>')


def to_mathml(expr: sp.Basic, display: str = "inline") -> Markup:
    """Render one sympy expression as a ``<math>`` element.

    Parameters
    ----------
    expr : sympy.Basic
    display : {"inline", "block"}

    Returns
    -------
    markupsafe.Markup
        ``<math xmlns=... display=...>...</math>``, safe to insert in HTML.
    """
    _validate_display(display)
    return _wrap(_mathml_body(sp.sympify(expr)), display)


def equation_mathml(lhs: sp.Basic, rhs: sp.Basic, display: str = "block") -> Markup:
    """``lhs = rhs`` as one ``<math>`` element (left and right kept as written)."""
    _validate_display(display)
    body = f"<mrow>{_mathml_body(lhs)}<mo>=</mo>{_mathml_body(rhs)}</mrow>"
    return _wrap(body, display)


def _validate_display(display: str) -> None:
    valid = ("inline", "block")
    if display not in valid:
        raise ValueError(f"`display` must be one of {valid}, got {display!r}")


def display_symbols(expr: sp.Basic) -> dict[sp.Symbol, str]:
    """LaTeX names for the symbols of ``expr`` (dotted rates, subscripts)."""
    names: dict[sp.Symbol, str] = {}
    for sym in expr.free_symbols:
        for suffix, accent in _LATEX_DOTS:
            if sym.name.endswith(suffix):
                base = sp.latex(sp.Symbol(sym.name[: -len(suffix)]))
                names[sym] = f"{accent}{{{base}}}"
                break
    return names


def to_latex(expr: sp.Basic) -> str:
    """LaTeX of one expression (math mode content, without delimiters)."""
    expr = sp.sympify(expr)
    return LatexPrinter({"symbol_names": display_symbols(expr)}).doprint(expr)


def equation_latex(lhs: sp.Basic, rhs: sp.Basic) -> str:
    """LaTeX of ``lhs = rhs`` (math mode content)."""
    return f"{to_latex(lhs)} = {to_latex(rhs)}"


_TAG = re.compile(r"<[^>]+>")


def mathml_text(markup: str) -> str:
    """The visible text of a MathML fragment (for tests and plain-text alt)."""
    return _TAG.sub("", str(markup))
