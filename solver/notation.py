"""The paper's notation for the rates of the coordinates in LaTeX: one dot for a rate, two for an
acceleration (theta_dot as a dotted theta), the dots over the name's nucleus and not over its
subscript (th1_dot as th with a dot, subscript 1), as textbooks write a dotted theta_1.
:mod:`solver.mathml` writes the same in MathML."""
from __future__ import annotations

import re

import sympy as sp

__all__ = ["rate_latex_names", "dotted_latex"]

_SUBSCRIPTED = re.compile(r"(?P<nucleus>\\?[A-Za-z]+)(?P<sub>_\{.*\})")


def dotted_latex(symbol: sp.Symbol, accent: str) -> str:
    r"""``accent`` (``dot`` or ``ddot``) over the nucleus of ``symbol``'s LaTeX name.

    >>> import sympy as sp
    >>> dotted_latex(sp.Symbol("theta"), "ddot"), dotted_latex(sp.Symbol("th1"), "dot")
    ('\\ddot{\\theta}', '\\dot{th}_{1}')
    """
    name = sp.latex(symbol)
    parts = _SUBSCRIPTED.fullmatch(name)
    if parts is None:
        return rf"\{accent}{{{name}}}"
    return rf"\{accent}{{{parts['nucleus']}}}{parts['sub']}"


def rate_latex_names(coordinates) -> dict:
    """Each coordinate's rate and acceleration symbol -> its dotted LaTeX name (``symbol_names`` of
    :func:`sympy.latex`)."""
    names = {}
    for c in coordinates:
        names[c.qd] = dotted_latex(c.q, "dot")
        names[c.qdd] = dotted_latex(c.q, "ddot")
    return names
