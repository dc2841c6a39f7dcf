"""The paper's notation for the rates of the coordinates in LaTeX: one dot for a rate, two for an
acceleration (theta_dot as a dotted theta), the dots over the name's nucleus and not over its
subscript (th1_dot as th with a dot, subscript 1), as textbooks write a dotted theta_1.
:mod:`solver.mathml` writes the same in MathML."""
from __future__ import annotations

import re

import sympy as sp

__all__ = ["rate_latex_names", "dotted_latex", "name_text", "typeset_text", "latex_escape", "compound_subscript",
           "compound_latex"]

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


# -- compound names: a subscript naming a point by two lines, or an element of a body --------------
_COMPOUND = re.compile(r"[(). ]")
_SUBSCRIPT_TOKEN = re.compile(r"[A-Za-z0-9_]+|\s+|.")


def compound_subscript(name: str):
    """The parts of a symbol name whose subscript names a point by two lines (``r_G/I(A_x,B_y)``),
    an element of a body (``W_upper.bob1``, ``W_upper.point_mass_1``) or a point named by words
    joined by underscores (``a_C_floor``, ``r_G/C_floor``, ``I_G_shank``: a joint's or an element's
    point), or None for any other name (sympy's printers read those; a rate ``theta_1_dot`` too).
    Each part is ``("name", text)`` for a symbol inside the brackets (``A_x``, itself subscripted),
    ``("point", text)`` for a point named by words joined by underscores (``C_floor``, printed
    as words apart, "C floor", as the equations' labels print it), ``("word", text)`` for a word
    of the name (an element's spelled as the scene and the force list spell it, underscores
    kept: ``point_mass_1``), ``("space", " ")`` or ``("mark", text)`` for ``( ) , / .``; the
    nucleus comes first as ``("head", text)``. The one reading of such names, for LaTeX
    (:func:`compound_latex`) and MathML (:mod:`solver.mathml`).

    >>> compound_subscript("r_I(A_x,B_y)")[:4]
    [('head', 'r'), ('word', 'I'), ('mark', '('), ('name', 'A_x')]
    >>> compound_subscript("theta_1") is None
    True
    """
    head, _, tail = name.partition("_")
    joined = "_" in tail and len(head) == 1 and not name.endswith(("_dot", "_ddot"))
    if not tail or not head or not (joined or _COMPOUND.search(tail)) or _COMPOUND.search(head):
        return None  # (I(O_x,A_y) itself is a point's name, no nucleus with a subscript)
    parts, depth = [("head", head)], 0
    for token in _SUBSCRIPT_TOKEN.findall(tail):
        depth += {"(": 1, ")": -1}.get(token, 0)
        if token.isspace():
            parts.append(("space", " "))
        elif re.fullmatch(r"[A-Za-z0-9_]+", token):
            if depth > 0 and token[0].isalpha():
                parts.append(("name", token))
            elif "_" in token and parts[-1] != ("mark", "."):  # (after a dot: a body's element, a word)
                parts.append(("point", token))
            else:
                parts.append(("word", token))
        else:
            parts.append(("mark", token))
    return parts


def compound_latex(name: str) -> str | None:
    r"""LaTeX of a compound name (:func:`compound_subscript`), None for any other name: the crossing
    point's names keep their own subscripts, words stay apart.

    >>> compound_latex("r_G/I(A_x,B_y)"), compound_latex("W_upper.point_mass_1"), compound_latex("r_G/C_floor")
    ('r_{G/I(A_{x},B_{y})}', 'W_{upper.point\\_mass\\_1}', 'r_{G/C\\ floor}')
    """
    parts = compound_subscript(name)
    if parts is None:
        return None
    out = []
    for kind, text in parts[1:]:
        if kind == "name":
            out.append(sp.latex(sp.Symbol(text)))
        elif kind == "point":
            out.append(text.replace("_", r"\ "))
        elif kind == "word":
            out.append(latex_escape(text))
        else:
            out.append(r"\ " if kind == "space" else latex_escape(text))
    return sp.latex(sp.Symbol(parts[0][1])) + "_{" + "".join(out) + "}"


# -- names in running text and on figures ---------------------------------------------------------
_GREEK = {"alpha": "\u03b1", "beta": "\u03b2", "theta": "\u03b8", "phi": "\u03c6", "omega": "\u03c9", "psi": "\u03c8"}
_ACCENT = {"_ddot": "\u0308", "_dot": "\u0307"}
_NAME = re.compile(r"\b(alpha|beta|theta|phi|omega|psi)(_ddot|_dot)?\b")


def name_text(text: str) -> str:
    """Symbol names of the solver in a sentence as the paper writes them: ``theta_ddot`` as θ̈
    (theta with a combining diaeresis), ``omega`` as ω; other names unchanged."""
    return _NAME.sub(lambda m: _GREEK[m.group(1)] + _ACCENT.get(m.group(2) or "", ""), text)


def typeset_text(text: str) -> str:
    """A caption's or a figure label's text in the paper's notation: the names as :func:`name_text`
    writes them, and a minus sign (U+2212) for a hyphen that starts a term or a number (``-m a_A``,
    ``|-I_A alpha|``, ``= -5.6 deg``), not one inside a word (``free-body``).

    >>> typeset_text("|-I_A alpha| = 1 N, phi_dot = -2 rad/s, free-body")
    '|\u2212I_A \u03b1| = 1 N, \u03c6\u0307 = \u22122 rad/s, free-body'
    """
    return name_text(re.sub(r"(^|[\s(|])-(?=[\w.])", "\\1\u2212", text))


# -- text for LaTeX --------------------------------------------------------------------------------
_LATEX_SPECIAL = {
    "\\": r"\textbackslash{}",
    "&": r"\&",
    "%": r"\%",
    "$": r"\$",
    "#": r"\#",
    "_": r"\_",
    "{": r"\{",
    "}": r"\}",
    "~": r"\textasciitilde{}",
    "^": r"\textasciicircum{}",
    "<": r"\textless{}",  # (a bare < or > prints as ¡ or ¿ in LaTeX's default OT1 font encoding)
    ">": r"\textgreater{}",
    "²": r"\textsuperscript{2}",
    "·": r"\ensuremath{\cdot}",
    "±": r"\ensuremath{\pm}",
    "\u2212": r"\ensuremath{-}",  # minus sign (also of captions: typeset_text)
    "×": r"\ensuremath{\times}",
    "\u2248": r"\ensuremath{\approx}",
    "°": r"\ensuremath{^\circ}",
    "\u2264": r"\ensuremath{\leq}",
    "\u2265": r"\ensuremath{\geq}",
}
_LATEX_GREEK = re.compile("([\u03b1-\u03c9])([\u0307\u0308]?)")
_GREEK_NAMES = {letter: name for name, letter in _GREEK.items()}


def _latex_greek(m: re.Match) -> str:
    """A Greek letter of prose (:func:`name_text`) as maths, with its dot accent (theta with two
    dots as ``\\ensuremath{\\ddot{\\theta}}``); other Greek letters as they are."""
    name = _GREEK_NAMES.get(m.group(1))
    if name is None:
        return m.group(0)
    accent = {"\u0307": r"\dot", "\u0308": r"\ddot"}.get(m.group(2))
    return rf"\ensuremath{{{accent}{{\{name}}}}}" if accent else rf"\ensuremath{{\{name}}}"


def latex_escape(value) -> str:
    """Text for LaTeX's text mode, the one escape of the project (the report's paper.tex and the
    worked solution's LaTeX): every special character escaped, so input text stays text; ``<`` and
    ``>`` as ``\\textless{}``, ``\\textgreater{}``; the maths signs of the prose and a Greek letter of
    :func:`name_text`, dotted or not, as maths.

    >>> latex_escape("50% of {x}_1 < 2 & θ̇")
    '50\\\\% of \\\\{x\\\\}\\\\_1 \\\\textless{} 2 \\\\& \\\\ensuremath{\\\\dot{\\\\theta}}'
    """
    text = "".join(_LATEX_SPECIAL.get(ch, ch) for ch in str(value))
    return _LATEX_GREEK.sub(_latex_greek, text)
