"""Equations for the outputs: presentation MathML for HTML, LaTeX for the paper.

The MathML conversion is :mod:`solver.mathml` (the worked solution's HTML prints through it
too), re-exported here under the names the report's code uses. Symbols follow the paper's
notation: ``theta_dot`` is printed as a dotted theta, ``theta_ddot`` with two dots, ``R_B``
with a subscript.
"""
from __future__ import annotations

import sympy as sp
from sympy.printing.latex import LatexPrinter

from solver.mathml import equation_mathml, mathml_text, to_mathml
from solver.mathml import mathml_body as _mathml_body  # noqa: F401 (reports.paper prints term by term)
from solver.mathml import wrap as _wrap  # noqa: F401

__all__ = ["to_mathml", "equation_mathml", "to_latex", "equation_latex", "display_symbols", "mathml_text"]

_LATEX_DOTS = (("_ddot", r"\ddot"), ("_dot", r"\dot"))


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
