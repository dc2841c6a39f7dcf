"""Render an :class:`~solver.explain.content.Explanation` as text, Markdown, HTML or LaTeX.

One content, four renderings: every renderer walks the same sections, steps,
equations and tables. Input text (names from the scene) is data: HTML escapes
it, LaTeX escapes its special characters, Markdown escapes table pipes. The LaTeX
rendering also writes the names, formulae and units in the prose and tables as
LaTeX (:mod:`.latex_prose`). Where the equations write a one-body scene's q'' as
the body's alpha, every rendering says so once (:func:`_alpha_alias`).
"""
from __future__ import annotations

import html
import re

import sympy as sp

from ..strprint import FastStrPrinter, sstr
from .content import Equation, Explanation, Step, Table, Term
from .latex_prose import LatexProse, latex_escape, unit_latex

__all__ = ["FORMATS", "render"]

FORMATS = ("text", "markdown", "html", "latex")


def render(expl: Explanation, fmt: str = "text") -> str:
    """The explanation as a string in ``fmt`` (one of :data:`FORMATS`).

    Raises
    ------
    ValueError
        Unknown format (the message lists the valid ones).
    """
    if fmt not in FORMATS:
        raise ValueError(f"`--format` must be one of {', '.join(FORMATS)}, got {fmt!r}")
    return {"text": _Text, "markdown": _Markdown, "html": _Html, "latex": _Latex}[fmt](expl).document()


class _Renderer:
    def __init__(self, expl: Explanation):
        self.expl = expl
        self.printed = FastStrPrinter()  # each expression's text once per rendering (a point's v_P shows often)
        self.alias = _alpha_alias(expl)

    def document(self) -> str:
        out = [self.title(self.expl.title)]
        points = ", ".join(f"{b}: {p}" for b, p in self.expl.points.items())
        out.append(self.paragraph(f"Scene {self.expl.scene}; moments about {points}." if points
                                  else f"Scene {self.expl.scene}."))
        for section in self.expl.sections:
            out.append(self.heading(section.title, 2))
            for step in section.steps:
                out.append(self.step(step))
        return self.wrap("\n".join(x for x in out if x))

    def step(self, step: Step) -> str:
        out = [self.heading(step.title, 3)]
        out += [self.paragraph(t) for t in step.text]
        if self.alias is not None and step is self.alias[0]:
            out.append(self.paragraph(self.alias[1]))
        if step.figure is not None:
            out.append(self.figure(step.figure))
        if step.figure_svg is not None:
            out.append(self.drawing(step.figure_svg))
        for eq in step.equations:
            out.append(self.equation(eq))
        if step.table is not None:
            out.append(self.table(step.table))
        return "\n".join(out)

    def wrap(self, body: str) -> str:
        return body

    def figure(self, figure: str) -> str:
        return self.paragraph(f"[figure: {figure}]")

    def drawing(self, svg: str) -> str:
        """A drawn free-body diagram: only HTML shows it (the forces are listed in every format)."""
        return ""


def _alpha_alias(expl: Explanation):
    """(step, sentence) saying once that alpha stands for +-q'': the first step after the kinematics whose
    equations write the unknown q'' as the body's angular acceleration alpha (a one-body, one-coordinate
    scene: the collected moment equation and the numbers, as the paper's Eqs. 28-29 do); None otherwise."""
    defined = [(section.body, e) for section in expl.sections for step in section.steps
               if step.kind == "kinematics" for e in step.equations if e.tag == "alpha"]
    if len(defined) != 1:
        return None
    body, eq = defined[0]
    rate = sp.sympify(eq.right)
    q_ddot = [s for s in rate.free_symbols if s in expl.symbol_latex]
    if len(q_ddot) != 1 or rate not in (q_ddot[0], -q_ddot[0]):
        return None
    alpha = sp.Symbol("alpha", real=True)
    for step in expl.steps():
        if step.kind != "kinematics" and any(alpha in sp.sympify(t.expr).free_symbols
                                             for e in step.equations for t in (*e.lhs, *e.rhs)):
            return step, (f"Here alpha = {sstr(rate)}, the angular acceleration of {body} (k component, "
                          f"counter-clockwise positive): from here on the equations write the unknown {q_ddot[0]} "
                          "as alpha.")
    return None


# -- text ------------------------------------------------------------------------------------------


def _sstr(expr, printed: FastStrPrinter | None = None) -> str:
    """``sympy.sstr`` of an expression, or ``(x, y)`` of a 2-vector; ``printed``, the printer of one
    rendering, remembers the texts (the same expression prints the same)."""
    if isinstance(expr, sp.MatrixBase):
        return f"({_sstr(expr[0], printed)}, {_sstr(expr[1], printed)})"
    return sstr(expr, printed)


def _join_text(terms, printed: FastStrPrinter | None = None) -> str:
    out = ""
    for i, t in enumerate(terms):
        s = _sstr(t.expr, printed)
        if i and s.startswith("-") and not isinstance(t.expr, sp.MatrixBase):
            out += " - " + s[1:]
        else:
            out += (" + " if i else "") + s
    return out


class _Text(_Renderer):
    def title(self, text):
        return f"{text}\n{'=' * len(text)}\n"

    def heading(self, text, level):
        return f"\n{text}\n{'-' * len(text) if level == 2 else ''}".rstrip()

    def paragraph(self, text):
        return f"{text}"

    def equation(self, eq: Equation) -> str:
        head = f"  {eq.label}" + (f" ({eq.ref})" if eq.ref else "") + ":"
        noted = [t for t in (*eq.rhs, *([] if eq.name else eq.lhs)) if t.note]
        if len(noted) < 2:
            lhs = eq.name or _join_text(eq.lhs, self.printed)
            return f"{head}\n    {lhs} {eq.sign} {_join_text(eq.rhs, self.printed)}"
        lines = [head]
        sides = [("", eq.lhs)] if not eq.name else [("", (Term(sp.Symbol(eq.name)),))]
        sides.append((f"{eq.sign} ", eq.rhs))
        for mark, terms in sides:
            for i, t in enumerate(terms):
                text = _sstr(t.expr, self.printed)
                sign = mark if i == 0 else "+ "
                if i and text.startswith("-") and not isinstance(t.expr, sp.MatrixBase):
                    sign, text = "- ", text[1:]
                lines.append(f"    {sign:>2}{text}" + (f"    [{t.note}]" if t.note else ""))
        return "\n".join(lines)

    def table(self, table: Table) -> str:
        from ..cli_common import format_table

        return "\n".join("    " + line for line in format_table(table.header, table.rows).splitlines())


# -- LaTeX-based (Markdown and LaTeX) -------------------------------------------------------------

def _name_latex(name: str) -> str:
    """``a_G,x`` -> ``a_{G,x}``; names are letters, digits, _ , / and ``G_bar`` style."""
    safe = re.sub(r"[^A-Za-z0-9_,/()]", "", name)
    head, _, tail = safe.partition("_")
    head = {"omega": r"\omega", "alpha": r"\alpha"}.get(head, head)
    return head + (f"_{{{tail.replace('_', ' ')}}}" if tail else "")


class _LatexMath:
    def __init__(self, names, note=None):
        self.names = names
        self.printed: dict = {}  # expression -> its LaTeX, for this rendering
        self.note = note or latex_escape  # a term's note as the text of \text{...}

    def expr(self, e) -> str:
        if isinstance(e, sp.MatrixBase):
            return r"\begin{pmatrix}" + r" \\ ".join(self.expr(x) for x in e) + r"\end{pmatrix}"
        text = self.printed.get(e)
        if text is None:
            text = self.printed[e] = sp.latex(e, symbol_names=self.names)
        return text

    def join(self, terms, notes=True) -> str:
        out = ""
        for i, t in enumerate(terms):
            expr = t.expr
            negative = i > 0 and not isinstance(expr, sp.MatrixBase) and sp.sympify(expr).could_extract_minus_sign()
            s = self.expr(-expr if negative else expr)
            if notes and t.note and len(terms) > 1:
                s = rf"\underbrace{{{s}}}_{{\text{{{self.note(t.note)}}}}}"
            out += ("" if i == 0 else (" - " if negative else " + ")) + s
        return out

    def equation(self, eq: Equation) -> str:
        lhs = _name_latex(eq.name) if eq.name else self.join(eq.lhs)
        relation = r"\approx" if eq.approximate else "="
        return f"{lhs} {relation} {self.join(eq.rhs)}"


class _Markdown(_Renderer):
    def __init__(self, expl):
        super().__init__(expl)
        self.math = _LatexMath(expl.symbol_latex)

    def title(self, text):
        return f"# {_md(text)}\n"

    def heading(self, text, level):
        return f"\n{'#' * level} {_md(text)}\n"

    def paragraph(self, text):
        return _md(text) + "\n"

    def equation(self, eq):
        head = _md(eq.label) + (f" ({_md(eq.ref)})" if eq.ref else "")
        return f"{head}:\n\n$$\n{self.math.equation(eq)}\n$$\n"

    def table(self, table):
        rows = [table.header, tuple("---" for _ in table.header), *table.rows]
        return "\n".join("| " + " | ".join(_md(c).replace("|", r"\|") for c in r) + " |" for r in rows) + "\n"


def _md(text: str) -> str:
    """Markdown-escape plain text (no HTML, no emphasis from names like a_b_c)."""
    text = html.escape(str(text), quote=False)
    return re.sub(r"([\\`*_\[\]#<>])", r"\\\1", text)


class _Latex(_Renderer):
    """A LaTeX document: prose as text with inline maths for its names and formulae (names through the
    explanation's LaTeX name map), units upright (``\\mathrm{ft/s^{2}}``), no code-style ``*`` or ``**``."""

    def __init__(self, expl):
        super().__init__(expl)
        symbols = set().union(*[sp.sympify(t.expr).free_symbols for s in expl.steps() for e in s.equations
                                for t in (*e.lhs, *e.rhs)])
        self.prose = LatexProse(symbols, expl.symbol_latex)
        self.math = _LatexMath(expl.symbol_latex, note=self.prose.cell)

    def wrap(self, body):
        return ("\\documentclass{article}\n\\usepackage{amsmath}\n\\usepackage[margin=2cm]{geometry}\n"
                "\\allowdisplaybreaks\n\\begin{document}\n" + body + "\n\\end{document}\n")

    def title(self, text):
        return f"\\section*{{{self.prose.text(text)}}}"

    def heading(self, text, level):
        return f"\\{'sub' * (level - 1)}section*{{{self.prose.text(text)}}}"

    def paragraph(self, text):
        return self.prose.text(text) + "\n"

    def equation(self, eq):
        label, unit = eq.label, ""
        bracket = re.fullmatch(r"(.*) \[([^\]]+)\]", label)  # "body: Newton, x component [lbf]"
        if bracket and unit_latex(bracket[2]):
            label, unit = bracket[1], f" [${unit_latex(bracket[2])}$]"
        head = self.prose.text(label) + unit + (f" ({self.prose.text(eq.ref)})" if eq.ref else "")
        return f"{head}:\n\\begin{{equation*}}\n{self.math.equation(eq)}\n\\end{{equation*}}"

    def table(self, table):
        cols = "l" * len(table.header)
        units = [h == "unit" for h in table.header]
        rows = [" & ".join(self.prose.text(c) for c in table.header) + r" \\"]
        rows += [" & ".join(self.prose.cell(c, u) for c, u in zip(r, units)) + r" \\" for r in table.rows]
        return ("\\begin{center}\\small\n\\begin{tabular}{" + cols + "}\n" + rows[0] + "\n\\hline\n"
                + "\n".join(rows[1:]) + "\n\\end{tabular}\n\\end{center}")

    def figure(self, figure):
        return f"% figure: {latex_escape(figure)}"


# -- HTML ------------------------------------------------------------------------------------------


_CSS = ("body{font-family:sans-serif;max-width:60em;margin:auto} "
        ".eq{font-family:monospace;margin:.3em 0 .8em 2em;white-space:pre-wrap} .note{color:#555} "
        "table{border-collapse:collapse} td,th{border:1px solid #ccc;padding:.2em .5em}")
"""The worked solution's style sheet (a plain string: no f-string brace doubling)."""


class _Html(_Renderer):
    def wrap(self, body):
        return ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
                f"<title>{_h(self.expl.title)}</title>\n<style>{_CSS}</style></head><body>\n" + body
                + "\n</body></html>\n")

    def title(self, text):
        return f"<h1>{_h(text)}</h1>"

    def heading(self, text, level):
        return f"<h{level}>{_h(text)}</h{level}>"

    def paragraph(self, text):
        return f"<p>{_h(text)}</p>"

    def equation(self, eq):
        head = _h(eq.label) + (f" ({_h(eq.ref)})" if eq.ref else "")
        notes = len([t for t in (*eq.rhs, *([] if eq.name else eq.lhs)) if t.note]) >= 2  # as the text shows them
        lhs = _h(eq.name) if eq.name else _terms_html(eq.lhs, self.printed, notes)
        sign = "&asymp;" if eq.approximate else "="
        return f"<div>{head}:</div><div class=\"eq\">{lhs} {sign} {_terms_html(eq.rhs, self.printed, notes)}</div>"

    def table(self, table):
        head = "".join(f"<th>{_h(c)}</th>" for c in table.header)
        rows = "".join("<tr>" + "".join(f"<td>{_h(c)}</td>" for c in r) + "</tr>" for r in table.rows)
        return f"<table><tr>{head}</tr>{rows}</table>"

    def figure(self, figure):
        return f"<figure data-figure=\"{_h(figure)}\"></figure>"

    def drawing(self, svg):
        return f"<figure class=\"fbd\">{svg}</figure>"  # the project's own SVG (labels escaped by matplotlib)


def _h(text) -> str:
    return html.escape(str(text), quote=True)


def _terms_html(terms, printed: FastStrPrinter | None = None, notes: bool = True) -> str:
    """The terms of one side, a negative scalar term after the first joined by "-" (not "+ -"),
    each with its note when ``notes``."""
    out = ""
    for i, t in enumerate(terms):
        s = _sstr(t.expr, printed)
        sign = "\n   + " if i else ""
        if i and s.startswith("-") and not isinstance(t.expr, sp.MatrixBase):
            sign, s = "\n   - ", s[1:]
        out += sign + _h(s) + (f" <span class=\"note\">[{_h(t.note)}]</span>" if t.note and notes else "")
    return out
