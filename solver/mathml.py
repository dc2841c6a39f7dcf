"""Presentation MathML of sympy expressions: the one conversion of every HTML output.

Browsers render MathML natively (MathML Core), so a page needs no script or web
font. Symbols follow the paper's notation: ``theta_dot`` is printed as a dotted
theta, ``theta_ddot`` with two dots, ``R_B`` with a subscript. The report's pages
(:mod:`reports.mathml` re-exports these functions) and the worked solution's HTML
(:mod:`solver.explain.render`) print through here; :mod:`solver.mathfont` embeds the
maths font they are drawn with.
"""
from __future__ import annotations

import html
import re
from functools import lru_cache, wraps

import sympy as sp
from markupsafe import Markup
from sympy.printing.mathml import MathMLPresentationPrinter
from sympy.printing.precedence import PRECEDENCE

from .notation import compound_subscript

__all__ = ["to_mathml", "equation_mathml", "mathml_body", "printed_once", "wrap", "mathml_text", "mathml_width", "MATHML_NS", "MINUS", "minus_signs"]

MATHML_NS = "http://www.w3.org/1998/Math/MathML"
_DOTS = (("_ddot", "\u00a8"), ("_dot", "\u02d9"))


class _Printer(MathMLPresentationPrinter):
    """sympy's presentation printer with dotted time derivatives: the dots over the name's nucleus,
    below which its subscript stays (th1_dot: th dotted, subscript 1), as
    :func:`solver.notation.dotted_latex` writes them in LaTeX."""

    def _print_Symbol(self, sym, style="plain"):  # noqa: N802 (sympy's naming)
        parts = compound_subscript(sym.name)
        if parts is not None:
            return self._compound(parts, style)
        for suffix, accent in _DOTS:
            if sym.name.endswith(suffix):
                name = super()._print_Symbol(sp.Symbol(sym.name[: -len(suffix)]), style)
                if name.tagName in ("msub", "msubsup"):  # dot the nucleus, keep the subscript
                    name.replaceChild(self._dotted(name.firstChild, accent), name.firstChild)
                    return name
                return self._dotted(name, accent)
        return super()._print_Symbol(sym, style)

    def _print_Mul(self, expr):  # noqa: N802 (sympy's naming)
        """A negated sum keeps its brackets, -(a + b): sympy's printer drops them when the
        minus is the product's only other factor (an unevaluated ``Mul(-1, a + b)``)."""
        if expr.could_extract_minus_sign() and isinstance(-expr, sp.Add):
            return self._minus(-expr)
        return super()._print_Mul(expr)

    def _print_Add(self, expr, order=None):  # noqa: N802 (sympy's naming)
        """A sum whose terms print as sympy's do, except that a term subtracted as a whole
        sum is bracketed, a - (b - c), where sympy's printer writes a - b - c."""
        mrow = self.dom.createElement("mrow")
        terms = self._as_ordered_terms(expr, order=order)
        mrow.appendChild(self._print(terms[0]))
        for term in terms[1:]:
            negative = term.could_extract_minus_sign()
            mrow.appendChild(self._operator("-" if negative else "+"))
            shown = -term if negative else term
            mrow.appendChild(self.parenthesize(shown, PRECEDENCE["Add"]) if negative else self._print(shown))
        return mrow

    def _minus(self, expr):
        """``-(expr)``, the sum ``expr`` in brackets."""
        mrow = self.dom.createElement("mrow")
        mrow.appendChild(self._operator("-"))
        mrow.appendChild(self.parenthesize(expr, PRECEDENCE["Add"]))
        return mrow

    def _operator(self, text: str):
        mo = self.dom.createElement("mo")
        mo.appendChild(self.dom.createTextNode(text))
        return mo

    def _compound(self, parts, style):
        """A compound name (:func:`solver.notation.compound_subscript`): the nucleus with a
        subscript row of words, marks and the crossing point's own subscripted names."""
        row = self.dom.createElement("mrow")
        for kind, text in parts[1:]:
            if kind == "name":
                row.appendChild(self._print_Symbol(sp.Symbol(text), style))
            elif kind == "space":
                space = self.dom.createElement("mspace")
                space.setAttribute("width", "0.3em")
                row.appendChild(space)
            else:
                node = self.dom.createElement("mo" if kind == "mark" else "mn" if text.isdigit() else "mi")
                node.appendChild(self.dom.createTextNode(text.replace("_", " ") if kind == "point" else text))
                if text == ".":  # a body's element (upper.bob1): a separator inside a name, not an operator
                    node.setAttribute("lspace", "0")
                    node.setAttribute("rspace", "0")
                row.appendChild(node)
        sub = self.dom.createElement("msub")
        sub.appendChild(self._print_Symbol(sp.Symbol(parts[0][1]), style))
        sub.appendChild(row)
        return sub

    def _dotted(self, node, accent: str):
        over = self.dom.createElement("mover")
        over.setAttribute("accent", "true")
        mo = self.dom.createElement("mo")
        mo.appendChild(self.dom.createTextNode(accent))
        over.appendChild(node.cloneNode(True))
        over.appendChild(mo)
        return over


MINUS = "\u2212"
"""The minus sign of every HTML output (sympy's printer and Python's numbers write the hyphen-minus "-")."""

_PIECE = re.compile(r"(<(/?)([A-Za-z][\w:-]*)?[^>]*>)")  # a tag; its "/" if closing, and its name
_VERBATIM = ("svg", "style", "script", "code", "pre", "textarea", "bdi", "title")  # text shown or read as written:
# <bdi> holds what a user typed (a scene's name and description), <title> the page's name in plain text
# a sign before a number or a name (-2.5, (-0.3, -r_G, but not x-1, 2-3, --point or 1e-16), or an
# operator between spaces (lhs - rhs)
_TEXT_MINUS = re.compile(r"(?<![\w.\-\u2212])-(?=\.?[\w(])|(?<=\s)-(?=\s)")


def minus_signs(page: str) -> str:
    """``page`` (HTML, or a MathML fragment) with every minus shown as U+2212: a ``<mo>-</mo>``
    operator, the sign of an ``<mn>`` number (``10`` to the ``-16``) and of a number or a name in the
    text (``-7.35``, ``-r_G``), and a hyphen between spaces in the text (``lhs - rhs``: the prose writes no dash so). Tags and their attributes, and the text of ``<svg>``, ``<style>``, ``<script>``,
    ``<code>``, ``<pre>``, ``<textarea>``, ``<bdi>`` and ``<title>`` (a command to copy, a drawing, text a
    user typed such as a scene's name or description, the page's title) are left as they are;
    so are hyphens in words and ranges (``mass-centre``, ``1-5``) and a lone "-" in a table cell
    (an empty value).

    The one rule for the minus sign of the HTML outputs: every MathML expression
    (:func:`mathml_body`), the worked solution's page and the report's pages pass through here.
    """
    parts = _PIECE.split(page)  # text, then per tag: the tag, its "/" or "", its name or None, the text after
    pieces = parts[::4]  # the text between the tags
    verbatim, tag = 0, ""
    for i in range(len(pieces)):
        if i:  # the tag before this text
            name = parts[4 * i - 1]
            if name is not None:
                name = name.lower()
                closing = parts[4 * i - 2]
                tag = "" if closing else name
                if name in _VERBATIM and not parts[4 * i - 3].endswith("/>"):
                    verbatim += -1 if closing else 1
        piece = pieces[i]
        if not verbatim and "-" in piece:
            pieces[i] = _text_minus(piece, tag)
    out = [""] * (2 * len(pieces) - 1)
    out[::2], out[1::2] = pieces, parts[1::4]
    return "".join(out)


def _text_minus(piece: str, tag: str) -> str:
    """One text of a page outside the verbatim elements, with its minus signs (:func:`minus_signs`);
    ``tag``: the element it is in (``mo``, ``mn``, or another)."""
    if tag == "mo" and piece.strip() == "-":
        return piece.replace("-", MINUS)
    if tag == "mn" and piece.lstrip().startswith("-"):
        return piece.replace("-", MINUS, 1)
    return _TEXT_MINUS.sub(MINUS, piece)


def printed_once(doprint):
    """``doprint`` (an expression's printed text) remembered per expression for the process:
    sympy's == is structural (2.0 and 2 differ), so equal expressions print alike. An unhashable
    expression (a mutable Matrix) is printed each time."""
    remembered = lru_cache(maxsize=2048)(doprint)

    @wraps(doprint)
    def printed(expr: sp.Basic) -> str:
        try:
            return remembered(expr)
        except TypeError:
            return doprint(expr)
    return printed


def _mathml_body(expr: sp.Basic) -> str:
    """The MathML of one expression without its ``<math>`` element, printed once per process
    however often it is shown (the report prints each transcribed equation in block and inline
    form, the worked solution shows a point's velocity in several steps). A minus is U+2212
    (:func:`minus_signs`)."""
    return minus_signs(_Printer({"mul_symbol": None}).doprint(expr))


mathml_body = printed_once(_mathml_body)


def wrap(body: str, display: str) -> Markup:
    """``body`` (MathML made by this module, its text escaped) as one ``<math>`` element."""
    _validate_display(display)
    return Markup(f'<math xmlns="{MATHML_NS}" display="{display}">{body}</math>')


def to_mathml(expr: sp.Basic, display: str = "inline") -> Markup:
    """Render one sympy expression as a ``<math>`` element.

    Parameters
    ----------
    expr : sympy.Basic
    display : {"inline", "block"}

    Returns
    -------
    markupsafe.Markup
        ``<math xmlns=... display=...>...</math>``, safe to insert in HTML: sympy's printer
        escapes the text of the symbols through ``xml.dom``.
    """
    _validate_display(display)
    return wrap(mathml_body(sp.sympify(expr)), display)


def equation_mathml(lhs: sp.Basic, rhs: sp.Basic, display: str = "block") -> Markup:
    """``lhs = rhs`` as one ``<math>`` element (left and right kept as written)."""
    _validate_display(display)
    return wrap(f"<mrow>{mathml_body(lhs)}<mo>=</mo>{mathml_body(rhs)}</mrow>", display)


def _validate_display(display: str) -> None:
    valid = ("inline", "block")
    if display not in valid:
        raise ValueError(f"`display` must be one of {valid}, got {display!r}")


_TAG = re.compile(r"<[^>]+>")


def mathml_text(markup: str) -> str:
    """The visible text of a MathML fragment (for tests and plain-text alt)."""
    return _TAG.sub("", str(markup))


_TOKEN = re.compile(r"<(/?)([a-z]+)[^>]*?(/?)>|([^<]+)")
_STACKED = {"mfrac", "mover", "munder", "munderover", "mtable"}  # children above each other: the widest
_SCRIPTED = {"msub", "msup", "msubsup"}  # a base and smaller scripts beside it
_SPACED = {"+", MINUS, "=", "\u2248", "\u00d7", ","}  # operators with space around them


def mathml_width(markup: str) -> float:
    """A rough width, in em of the maths font, of a MathML fragment made by this module: the
    glyphs of a row side by side, a fraction or an accent as wide as its widest part, scripts at
    0.7 of the size. Used to lay a long display out (a column vector, a note above its term) where
    a row would run off the page; within about a tenth of what Chromium draws with the embedded font.
    (A worked solution measures each of its displays about ten times over: the width of each text is
    kept, the last 4096.)"""
    return _width(str(markup))


@lru_cache(maxsize=4096)
def _width(markup: str) -> float:
    """:func:`mathml_width` of the text ``markup``."""
    stack: list[list[float]] = [[]]
    for m in _TOKEN.finditer(markup):
        closing, tag, empty, text = m.groups()
        if text is not None:
            chars = html.unescape(text).strip()
            stack[-1].append(sum(0.0 if "\u2061" <= c <= "\u2064" else 1.8 if c in _SPACED else 0.62
                                 for c in chars))
        elif empty:
            continue
        elif not closing:
            stack.append([])
        elif len(stack) > 1:
            parts = stack.pop()
            if tag in _STACKED:
                width = max(parts, default=0.0)
            elif tag in _SCRIPTED and parts:
                width = parts[0] + 0.7 * (max(parts[1:]) if tag == "msubsup" else sum(parts[1:]))
            else:
                width = sum(parts)
            stack[-1].append(width)
    return sum(stack[0])
