"""Equations for the outputs: presentation MathML for HTML, LaTeX for the paper.

The MathML conversion is :mod:`solver.mathml` (the worked solution's HTML prints through it
too), re-exported here under the names the report's code uses. Symbols follow the paper's
notation: ``theta_dot`` is printed as a dotted theta, ``theta_ddot`` with two dots, ``R_B``
with a subscript.
"""
from __future__ import annotations

import ast
import re
from functools import lru_cache

import sympy as sp
from markupsafe import escape
from sympy.printing.latex import LatexPrinter

from solver.mathml import equation_mathml, mathml_text, printed_once, to_mathml
from solver.notation import name_text  # noqa: F401 (the one rule for Greek names in text and on figures)
from solver.mathml import mathml_body as _mathml_body  # noqa: F401 (reports.paper prints term by term)
from solver.mathml import wrap as _wrap
from markupsafe import Markup

__all__ = ["to_mathml", "equation_mathml", "to_latex", "equation_latex", "display_symbols", "mathml_text",
           "transcription_mathml", "latex_display", "latex_width", "expr_text"]

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


def _latex(expr: sp.Basic) -> str:
    return LatexPrinter({"symbol_names": display_symbols(expr)}).doprint(expr)


_printed_latex = printed_once(_latex)


def to_latex(expr: sp.Basic) -> str:
    """LaTeX of one expression (math mode content, without delimiters), printed once per process
    however often it is shown (paper.tex shows an equation in its example and in the findings)."""
    return _printed_latex(sp.sympify(expr))


def equation_latex(lhs: sp.Basic, rhs: sp.Basic) -> str:
    """LaTeX of ``lhs = rhs`` (math mode content)."""
    return f"{to_latex(lhs)} = {to_latex(rhs)}"


# -- a transcription shown as written ------------------------------------------------------------
# Operator precedence of the whitelist syntax (solver.expressions), to put back the brackets the
# syntax tree drops: a sum inside a product, a product inside a power, ...
_PRECEDENCE = {ast.Add: 1, ast.Sub: 1, ast.Mult: 2, ast.Pow: 4, ast.Div: 4.5}  # a fraction bar groups itself
_OPERATOR = {ast.Add: "+", ast.Sub: "\u2212", ast.Mult: "&InvisibleTimes;"}


def transcription_mathml(lhs: str, rhs: str, display: str = "block", relation: str = "=") -> Markup:
    """``lhs = rhs`` as MathML, each side drawn from its transcribed text as written: terms and
    factors in the order of the text, numbers with their printed digits, nothing evaluated
    (sympy's parser would reorder terms and merge factors).

    Parameters
    ----------
    lhs, rhs : str
        The two sides in the whitelist expression syntax (:mod:`solver.expressions`), already
        accepted by its parser (this function only draws the syntax tree; it runs nothing).
    display : {"inline", "block"}
    relation : str
        The sign printed between the sides: "=" or, for a small-motion rule, "\u2248".

    Returns
    -------
    markupsafe.Markup
        One ``<math>`` element; brackets only where the order of operations needs them.

    Raises
    ------
    ValueError
        A construct outside the whitelist syntax.
    """
    return _wrap(_transcription_row(lhs, rhs, relation), display)


@lru_cache(maxsize=512)
def _transcription_row(lhs: str, rhs: str, relation: str = "=") -> str:
    """The ``<mrow>`` of :func:`transcription_mathml`, drawn once per transcription (the report shows
    each printed equation in a block and inline)."""
    sides = [_drawn(ast.parse(t.replace("^", "**").strip(), mode="eval").body, t.replace("^", "**").strip())
             for t in (lhs, rhs)]
    return f"<mrow>{sides[0]}<mo>{relation}</mo>{sides[1]}</mrow>"


def _rank(node: ast.AST) -> int:
    """Precedence of a node (5 for atoms: names, numbers, calls; 3 for a unary sign; a fraction
    binds tighter than a product, being drawn as one block)."""
    if isinstance(node, ast.BinOp):
        return _PRECEDENCE[type(node.op)]
    return 3 if isinstance(node, ast.UnaryOp) else 5


def _bracketed(node: ast.AST, source: str, below: float) -> str:
    """A node drawn inside brackets when its precedence is below ``below``."""
    body = _drawn(node, source)
    return f"<mrow><mo>(</mo>{body}<mo>)</mo></mrow>" if _rank(node) < below else body


def _drawn(node: ast.AST, source: str) -> str:
    """MathML of one node of a transcription's syntax tree, in the order written."""
    if isinstance(node, ast.Name):
        return _mathml_body(sp.Symbol(node.id)) if node.id != "pi" else "<mi>&#960;</mi>"
    if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)):
        return f"<mn>{escape(ast.get_source_segment(source, node))}</mn>"
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
        sign = "\u2212" if isinstance(node.op, ast.USub) else "+"
        return f"<mrow><mo>{sign}</mo>{_bracketed(node.operand, source, 3)}</mrow>"
    if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Div) and isinstance(node.right, ast.Constant):
        # "-1/2*a" and "a*1/2" read as a number over 2, not as a fraction with "-1" or "a*1" on top
        left = node.left
        if isinstance(left, ast.UnaryOp) and isinstance(left.op, ast.USub) and isinstance(left.operand, ast.Constant):
            return f"<mrow><mo>\u2212</mo>{_drawn(ast.BinOp(left.operand, ast.Div(), node.right), source)}</mrow>"
        if isinstance(left, ast.BinOp) and isinstance(left.op, ast.Mult) and isinstance(left.right, ast.Constant):
            number = _drawn(ast.BinOp(left.right, ast.Div(), node.right), source)
            return f"<mrow>{_bracketed(left.left, source, 2)}<mo>&InvisibleTimes;</mo>{number}</mrow>"
    if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Div):
        return f"<mfrac><mrow>{_drawn(node.left, source)}</mrow><mrow>{_drawn(node.right, source)}</mrow></mfrac>"
    if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Pow):
        return f"<msup>{_bracketed(node.left, source, 5)}<mrow>{_drawn(node.right, source)}</mrow></msup>"
    if isinstance(node, ast.BinOp) and type(node.op) in _OPERATOR:
        rank = _PRECEDENCE[type(node.op)]
        left = _bracketed(node.left, source, rank)
        # a sum after a minus, and a product after a number, keep their brackets
        right = _bracketed(node.right, source, 5 if isinstance(node.right, ast.UnaryOp) else
                           rank + (not isinstance(node.op, ast.Add)))
        op = _OPERATOR[type(node.op)]
        if isinstance(node.op, ast.Mult) and isinstance(node.right, ast.Constant):
            op = "\u00b7"  # two numbers side by side need a visible product sign
        return f"<mrow>{left}<mo>{op}</mo>{right}</mrow>"
    if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and not node.keywords:
        args = "<mo>,</mo>".join(_drawn(a, source) for a in node.args)
        if node.func.id == "sqrt" and len(node.args) == 1:
            return f"<msqrt><mrow>{args}</mrow></msqrt>"
        if node.func.id == "abs" and len(node.args) == 1:
            return f"<mrow><mo>|</mo>{args}<mo>|</mo></mrow>"
        call = f"<mi>{escape(node.func.id)}</mi><mo>&ApplyFunction;</mo>"
        return f"<mrow>{call}<mrow><mo>(</mo>{args}<mo>)</mo></mrow></mrow>"
    raise ValueError(f"not in the whitelist expression syntax: {ast.dump(node)[:60]}")


# -- LaTeX displays that fit the text block ---------------------------------------------------------
LINE_WIDTH = 55
"""Widest display line of paper.tex, in :func:`latex_width` units (about one glyph of 11 pt maths).
The 16.6 cm text block of the paper's 2.5 cm margins holds some 85 italic glyphs of 11 pt maths
(about 1.9 mm each); the estimate leaves out the spacing around operators and brackets, which
takes up to a third of a long display, hence 55."""
_COMMAND = re.compile(r"\\([A-Za-z]+)")
_NAMED = {"sin", "cos", "tan", "sinh", "cosh", "tanh", "log", "exp", "asin", "acos", "atan"}
_SILENT = {"left", "right", "frac", "dfrac", "text", "underbrace", "mathrm", "operatorname", "quad", "qquad"}


def latex_width(body: str) -> float:
    """An estimate of the printed width of LaTeX maths, erring wide: each visible character and each
    symbol command (``\\theta``) counts one, a function's name its letters, spacing and grouping
    nothing; a fraction counts its wider part, an underbrace the wider of its term and its label
    (set in script size, 0.7)."""
    total, i = 0.0, 0
    while i < len(body):
        for command, scale in ((r"\frac{", 1.0), (r"\underbrace{", 0.7)):
            if body.startswith(command, i):
                first, i = _group(body, i + len(command) - 1)
                second = ""
                if body.startswith("}{", i - 1) or body.startswith("{", i) or body.startswith("_{", i):
                    second, i = _group(body, body.index("{", i))
                total += max(latex_width(first), scale * latex_width(second))
                break
        else:
            j = body.find("\\", i + 1) if body[i] != "\\" else i
            j = len(body) if j == -1 else j
            if j == i:  # a command
                m = _COMMAND.match(body, i)
                name = m.group(1) if m else body[i + 1:i + 2]
                total += 0 if name in _SILENT else len(name) if name in _NAMED else 1
                total += 4 if name == "qquad" else 0
                i += 1 + len(name)
            else:
                total += len(re.sub(r"[{}_^\s]", "", body[i:j]))
                i = j
    return total


def _group(body: str, start: int) -> tuple[str, int]:
    """The text of the brace group opening at ``body[start]`` and the index after it."""
    depth = 0
    for k in range(start, len(body)):
        if body[k] == "{" and body[k - 1] != "\\":
            depth += 1
        elif body[k] == "}" and body[k - 1] != "\\":
            depth -= 1
            if depth == 0:
                return body[start + 1:k], k + 1
    return body[start + 1:], len(body)


def _top_level_breaks(body: str) -> list[int]:
    """Positions in ``body`` just before a `` + ``, `` - ``, `` = `` or ``\\qquad`` outside every
    group, where a display may break (never right after "=", which would leave a lone sign)."""
    depth, found = 0, []
    for i, ch in enumerate(body):
        depth += {"{": 1, "}": -1}.get(ch, 0) if body[i - 1:i] != "\\" else 0
        depth += 1 if body.startswith(r"\left", i) else -1 if body.startswith(r"\right", i) else 0
        if depth == 0 and i and (body.startswith((" + ", " - ", " = "), i) or body.startswith(r" \qquad", i)):
            if not body[:i].rstrip().endswith("="):
                found.append(i)
    return found


def latex_display(body: str, width: int = LINE_WIDTH) -> str:
    """One unnumbered display: ``equation*`` when it fits, else ``multline*`` broken at top-level
    signs into lines of at most ``width`` (:func:`latex_width`) where the terms allow."""
    body = body.strip()
    if latex_width(body) <= width:
        return f"\\begin{{equation*}}\n{body}\n\\end{{equation*}}\n"
    lines, start, last = [], 0, 0
    for cut in [*_top_level_breaks(body), len(body)]:
        # break before the piece that overflows, unless the line would hold only a short left side
        short_side = body.startswith(" = ", last) and latex_width(body[start:last]) < width / 4
        if latex_width(body[start:cut]) > width and last > start and not short_side:
            lines.append(body[start:last].strip())
            start = last
        last = cut
    lines.append(body[start:].strip())
    env = "multline*" if len(lines) > 1 else "equation*"
    shown = f"\\begin{{{env}}}\n" + " \\\\\n".join(lines) + f"\n\\end{{{env}}}"
    widest = max(latex_width(line) for line in lines)
    # a single term wider than the line cannot break: the display is set one or two sizes smaller
    # (\small is 10/11 of the text size, \footnotesize 9/11)
    size = "" if widest <= width else "\\small" if widest <= width * 11 / 10 else "\\footnotesize"
    return (f"{{{size}\n{shown}}}" if size else shown) + "\n"


# -- an expression in running text ---------------------------------------------------------------
def expr_text(expr: sp.Basic) -> str:
    """An expression for running text, in the paper's notation rather than code: products with a
    middle dot, squares as ², a minus sign −, Greek letters and dotted rates (:func:`name_text`)."""
    text = sp.sstr(expr).replace("**2", "\u00b2").replace("*", "\u00b7")
    return name_text(re.sub(r"(^|[\s(])-", "\\1\u2212", text).replace(" - ", " \u2212 "))
