"""Render an :class:`~solver.explain.content.Explanation` as text, Markdown, HTML or LaTeX.

One content, four renderings: every renderer walks the same sections, steps,
equations and tables. Input text (names from the scene) is data: HTML escapes
it, LaTeX escapes its special characters, Markdown escapes table pipes.
"""
from __future__ import annotations

import html
import re

import sympy as sp

from ..strprint import FastStrPrinter, sstr
from .content import Equation, Explanation, Step, Table, Term

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

_LATEX_SPECIAL = {"\\": r"\textbackslash{}", "&": r"\&", "%": r"\%", "$": r"\$", "#": r"\#", "_": r"\_",
                  "{": r"\{", "}": r"\}", "~": r"\textasciitilde{}", "^": r"\textasciicircum{}"}


def latex_escape(text: str) -> str:
    return "".join(_LATEX_SPECIAL.get(ch, ch) for ch in str(text))


def _name_latex(name: str) -> str:
    """``a_G,x`` -> ``a_{G,x}``; names are letters, digits, _ , / and ``G_bar`` style."""
    safe = re.sub(r"[^A-Za-z0-9_,/()]", "", name)
    head, _, tail = safe.partition("_")
    head = {"omega": r"\omega", "alpha": r"\alpha"}.get(head, head)
    return head + (f"_{{{tail.replace('_', ' ')}}}" if tail else "")


class _LatexMath:
    def __init__(self, names):
        self.names = names
        self.printed: dict = {}  # expression -> its LaTeX, for this rendering

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
                s = rf"\underbrace{{{s}}}_{{\text{{{latex_escape(t.note)}}}}}"
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
    def __init__(self, expl):
        super().__init__(expl)
        self.math = _LatexMath(expl.symbol_latex)

    def wrap(self, body):
        return ("\\documentclass{article}\n\\usepackage{amsmath}\n\\usepackage[margin=2cm]{geometry}\n"
                "\\allowdisplaybreaks\n\\begin{document}\n" + body + "\n\\end{document}\n")

    def title(self, text):
        return f"\\section*{{{latex_escape(text)}}}"

    def heading(self, text, level):
        return f"\\{'sub' * (level - 1)}section*{{{latex_escape(text)}}}"

    def paragraph(self, text):
        return latex_escape(text) + "\n"

    def equation(self, eq):
        head = latex_escape(eq.label) + (f" ({latex_escape(eq.ref)})" if eq.ref else "")
        return f"{head}:\n\\begin{{equation*}}\n{self.math.equation(eq)}\n\\end{{equation*}}"

    def table(self, table):
        cols = "l" * len(table.header)
        rows = [" & ".join(latex_escape(c) for c in r) + r" \\" for r in (table.header, *table.rows)]
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
