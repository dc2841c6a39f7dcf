"""Render an :class:`~solver.explain.content.Explanation` as text, Markdown, HTML or LaTeX.

One content, four renderings: every renderer walks the same sections, steps,
equations and tables. Input text (names from the scene) is data: HTML escapes
it, LaTeX escapes its special characters, Markdown escapes table pipes. The LaTeX
rendering also writes the names, formulae and units in the prose and tables as
LaTeX (:mod:`.latex_prose`), the HTML rendering as MathML (:mod:`.mathml_prose`,
through :mod:`solver.mathml`). The sentence saying what alpha stands for, where the
equations write a one-body scene's q'' as alpha, is content like any other
(:func:`solver.explain.build.say_what_alpha_is`).
"""
from __future__ import annotations

import html
import re

import sympy as sp

from ..display import could_extract_minus_sign
from ..drawing.svg_ids import inline_svg
from ..kept import Kept
from ..strprint import FastStrPrinter, join_sum, sstr
from .content import Equation, Explanation, SceneText, Step, Table, Term
from ..notation import compound_latex
from .latex_prose import LatexProse, latex_escape, subscripted, unit_latex

__all__ = ["FORMATS", "render", "terms_table", "prose_names"]

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
        self.printed = expl.printer  # each expression's text once (a point's v_P shows often)

    def document(self) -> str:
        scene = SceneText(self.expl.scene)
        title = self.expl.title
        out = [self.title((title[:-len(scene)], scene) if scene and title.endswith(": " + scene) else title)]
        points = ", ".join(f"{b}: {p}" for b, p in self.expl.points.items())
        out.append(self.paragraph(("Scene ", scene, f"; moments about {points}.") if points else ("Scene ", scene, ".")))
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
        elif (step.figure_request or {}).get("command"):  # not drawn here: where to get the drawing
            out.append(self.command("The free-body diagram as a drawing:", step.figure_request["command"]))
        for eq in step.equations:
            out.append(self.equation(eq))
        if step.table is not None:
            out.append(self.table(step.table))
        return "\n".join(out)

    def words(self, text) -> str:
        """``text`` in this format: prose (:meth:`prose_text`), or a tuple of prose and
        :class:`~.content.SceneText` parts, the scene's own text only escaped (:meth:`plain`)."""
        parts = text if isinstance(text, tuple) else (text,)
        return "".join(self.plain(p) if isinstance(p, SceneText) else self.prose_text(p) for p in parts)

    def plain(self, text: str) -> str:
        """Text as it is, escaped for the format."""
        return text

    def prose_text(self, text: str) -> str:
        """Prose with its names and formulae as the format writes maths."""
        return text

    def wrap(self, body: str) -> str:
        return body

    def figure(self, figure: str) -> str:
        return self.paragraph(f"[figure: {figure}]")

    def drawing(self, svg: str) -> str:
        """A drawn free-body diagram: only HTML shows it (the forces are listed in every format)."""
        return ""

    def command(self, intro: str, command: str) -> str:
        """One line: the prose ``intro``, then a command line to type, written as it is."""
        return f"{intro} {command}"


# -- text ------------------------------------------------------------------------------------------


def _sstr(expr, printed: FastStrPrinter | None = None) -> str:
    """``sympy.sstr`` of an expression, or ``(x, y)`` of a 2-vector; ``printed``, the printer of one
    rendering, remembers the texts (the same expression prints the same)."""
    if isinstance(expr, sp.MatrixBase):
        return f"({_sstr(expr[0], printed)}, {_sstr(expr[1], printed)})"
    return sstr(expr, printed)


def _join_text(terms, printed: FastStrPrinter | None = None) -> str:
    return join_sum(_sstr(t.expr, printed) for t in terms)  # a 2-vector prints "(x, y)": never "-..."


class _Text(_Renderer):
    def title(self, text):
        text = self.words(text)
        return f"{text}\n{'=' * len(text)}\n"

    def heading(self, text, level):
        text = self.words(text)
        return f"\n{text}\n{'-' * len(text) if level == 2 else ''}".rstrip()

    def paragraph(self, text):
        return self.words(text)

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
    """``a_G,x`` -> ``a_{G,x}``, ``v_C_contact`` -> ``v_{C\\ contact}``; names are letters, digits,
    _ , / and ``G_bar`` style."""
    compound = compound_latex(name)
    if compound:
        return compound
    safe = re.sub(r"[^A-Za-z0-9_,/()]", "", name)
    head, _, tail = safe.partition("_")
    head = {"omega": r"\omega", "alpha": r"\alpha"}.get(head, head)
    return subscripted(head, tail) if tail else head


_PROSE = Kept(64)
"""The decisions of which words are maths, by symbols and LaTeX names (:func:`prose_names`)."""


def prose_names(expl: Explanation) -> LatexProse:
    """The one decision of which words of ``expl``'s prose are maths (:class:`LatexProse`: the names
    of the symbols its equations hold, written with its LaTeX names), kept per process for those
    symbols and names (:class:`solver.kept.Kept`): the LaTeX and HTML renderings of an explanation,
    and of one made again of the same scene, split each text and decide each word once."""
    symbols = set().union(*[_free_symbols(t.expr) for s in expl.steps() for e in s.equations for t in (*e.lhs, *e.rhs)])
    return _PROSE.get((frozenset(symbols), frozenset(expl.symbol_latex.items())),
                      lambda: LatexProse(symbols, expl.symbol_latex))


def _free_symbols(expr) -> set:
    """The free symbols of a term: an expression's, a 2-vector's (without copying the Matrix into an
    immutable one, as ``sympify`` does), none of a number's."""
    return expr.free_symbols if isinstance(expr, (sp.Basic, sp.MatrixBase)) else sp.sympify(expr).free_symbols


class _LatexMath:
    def __init__(self, names, note=None, printed: dict | None = None):
        self.names = names
        # expression -> its LaTeX with ``names``: the explanation's (:attr:`Explanation.latex`), or this one's
        self.printed = {} if printed is None else printed
        self.note = note or latex_escape  # a term's note as the text of \text{...}

    def expr(self, e) -> str:
        if isinstance(e, sp.MatrixBase):
            return r"\begin{pmatrix}" + r" \\ ".join(self.expr(x) for x in e) + r"\end{pmatrix}"
        text = self.printed.get(e)
        if text is None:
            text = self.printed[e] = _latex(e, self._names(e))
        return text

    def _names(self, e) -> dict:
        """The explanation's LaTeX names, and those of ``e``'s compound names
        (:func:`solver.notation.compound_latex`: ``r_{I(A_{x},B_{y})}``, not sympy's ``r_{I(A x,B y)}``)."""
        compound = {s: tex for s in getattr(e, "free_symbols", ()) if s not in self.names
                    for tex in [compound_latex(s.name)] if tex}
        return {**self.names, **compound} if compound else self.names

    def signed(self, terms, notes=True) -> list[tuple[str, str]]:
        """(operator, LaTeX) per term: "", then " + " or " - " (a negative scalar term's sign taken out);
        each term with its note under a brace where the side has several terms."""
        out = []
        for i, t in enumerate(terms):
            expr = t.expr
            negative = i > 0 and not isinstance(expr, sp.MatrixBase) and could_extract_minus_sign(sp.sympify(expr))
            s = self.expr(-expr if negative else expr)
            if notes and t.note and len(terms) > 1:
                s = rf"\underbrace{{{s}}}_{{\text{{{self.note(t.note)}}}}}"
            out.append(("" if i == 0 else (" - " if negative else " + "), s))
        return out

    def join(self, terms, notes=True) -> str:
        return "".join(op + s for op, s in self.signed(terms, notes))

    def equation(self, eq: Equation) -> str:
        """The equation on one line, or, where that line would run past the page
        (:func:`_latex_too_wide`), as ``aligned`` rows: one term per row, aligned on the operators."""
        relation = r"\approx" if eq.approximate else "="
        if not _latex_too_wide(eq):
            lhs = _name_latex(eq.name) if eq.name else self.join(eq.lhs)
            return f"{lhs} {relation} {self.join(eq.rhs)}"
        rhs = self.signed(eq.rhs)
        if eq.name or len(eq.lhs) == 1:
            first = _name_latex(eq.name) if eq.name else self.join(eq.lhs)
            rows = [f"{first} &{relation} {rhs[0][1]}"]
        else:
            rows = [f"&{op.strip()} {s}".replace("& ", "&") for op, s in self.signed(eq.lhs)]
            rows.append(f"&{relation} {rhs[0][1]}")
        rows += [f"&{{}}{op.strip()} {s}" for op, s in rhs[1:]]
        return "\\begin{aligned}\n" + " \\\\\n".join(rows) + "\n\\end{aligned}"


_LATEX = Kept(4096)
"""Expressions' LaTeX, by expression and the names of its symbols (:func:`_latex`)."""


def _latex(e, names: dict) -> str:
    """``sympy.latex(e, symbol_names=names)``, kept per process (:class:`solver.kept.Kept`) by ``e``
    and the names given to the symbols it holds (the only ones the printer reads): an explanation
    made again, of a scene loaded again (a command after another in one process, each test of a
    suite), prints the same expressions, which :attr:`Explanation.latex` keeps for one explanation only."""
    held = e.atoms(sp.Symbol) if isinstance(e, sp.Basic) else ()
    key = (e, frozenset((x, names[x]) for x in held if x in names))
    return _LATEX.get(key, lambda: sp.latex(e, symbol_names=names))


LATEX_LINE_EM = 44.0
"""The room, in em, for one displayed equation of the LaTeX worked solution (an article's 10 pt text
between 2 cm margins, about 48 em, less the display's indent): wider, and it is set as rows."""


def _latex_too_wide(eq: Equation) -> bool:
    """Whether ``eq`` on one line would run past :data:`LATEX_LINE_EM`: each term as wide as its
    maths (:func:`solver.mathml.mathml_width`, 2-vectors as columns, as LaTeX sets them) or its note
    (under a brace, at script size), whichever is wider."""
    from ..mathml import mathml_width

    def width(terms):
        notes = len(terms) > 1
        return sum(max(mathml_width(_term_mathml(t.expr, column=True)),
                       0.35 * len(t.note) if notes and t.note else 0.0) + 1.8 for t in terms)
    left = 3.0 if eq.name else width(eq.lhs)
    return len(eq.lhs) + len(eq.rhs) > 2 and left + width(eq.rhs) > LATEX_LINE_EM


class _Markdown(_Renderer):
    def __init__(self, expl):
        super().__init__(expl)
        self.math = _LatexMath(expl.symbol_latex, printed=expl.latex)

    def plain(self, text):
        return _md(text)

    def prose_text(self, text):
        return _md(text)

    def title(self, text):
        return f"# {self.words(text)}\n"

    def heading(self, text, level):
        return f"\n{'#' * level} {self.words(text)}\n"

    def paragraph(self, text):
        return self.words(text) + "\n"

    def command(self, intro, command):
        return f"{_md(intro)} {_code_span(command)}\n"

    def equation(self, eq):
        head = _md(eq.label) + (f" ({_md(eq.ref)})" if eq.ref else "")
        return f"{head}:\n\n$$\n{self.math.equation(eq)}\n$$\n"

    def table(self, table):
        rows = [table.header, tuple("---" for _ in table.header), *table.rows]
        return "\n".join("| " + " | ".join(_md(c).replace("|", r"\|") for c in r) + " |" for r in rows) + "\n"


def _code_span(text: str) -> str:
    """A Markdown code span holding ``text`` as it is: fenced by one backtick more than its longest
    run of backticks (CommonMark), padded by a space where it starts or ends with one."""
    longest = max((len(run) for run in re.findall(r"`+", text)), default=0)
    fence = "`" * (longest + 1)
    pad = " " if text.startswith("`") or text.endswith("`") else ""
    return f"{fence}{pad}{text}{pad}{fence}"


def _md(text: str) -> str:
    """Markdown-escape plain text: no HTML, no emphasis from names like a_b_c, no maths from a ``$``
    (GitHub, Jupyter and other KaTeX/MathJax renderers read ``$...$`` as inline maths)."""
    text = html.escape(str(text), quote=False)
    return re.sub(r"([\\`*_\[\]#<>$])", r"\\\1", text)


class _Latex(_Renderer):
    """A LaTeX document: prose as text with inline maths for its names and formulae (names through the
    explanation's LaTeX name map), units upright (``\\mathrm{ft/s^{2}}``), no code-style ``*`` or ``**``."""

    def __init__(self, expl):
        super().__init__(expl)
        self.prose = prose_names(expl)
        self.math = _LatexMath(expl.symbol_latex, note=self.prose.cell, printed=expl.latex)

    def wrap(self, body):
        beyond = _beyond_latin(body)
        return ("\\documentclass{article}\n" + LATEX_ENGINE_NOTE + (LATEX_UNICODE_NOTE if beyond else "")
                + LATEX_PREAMBLE + "\\begin{document}\n" + body + "\n\\end{document}\n")

    def plain(self, text):
        return latex_escape(text)

    def prose_text(self, text):
        return self.prose.text(text)

    def title(self, text):
        return f"\\section*{{{self.words(text)}}}"

    def heading(self, text, level):
        return f"\\{'sub' * (level - 1)}section*{{{self.words(text)}}}"

    def paragraph(self, text):
        return self.words(text) + "\n"

    def command(self, intro, command):
        return f"{self.prose.text(intro)} \\texttt{{{latex_escape(command)}}}\n"

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


LATEX_ENGINE_NOTE = ("% A worked solution written by `python -m solver explain`: LaTeX2e, standard packages only.\n"
                     "% pdflatex sets it in T1-encoded Latin Modern from UTF-8 input; lualatex and xelatex through fontspec.\n")
LATEX_UNICODE_NOTE = ("% This text holds letters beyond the Latin script (from the scene's text): compile it with\n"
                      "% lualatex or xelatex, with a main font that has them (\\setmainfont{...} after fontspec).\n")
LATEX_PREAMBLE = ("\\usepackage{iftex}\n"
                  "\\ifPDFTeX\n  \\usepackage[T1]{fontenc}\n  \\usepackage[utf8]{inputenc}\n  \\usepackage{lmodern}\n"
                  "\\else\n  \\usepackage{fontspec}\n\\fi\n"
                  "\\usepackage{amsmath}\n\\usepackage[margin=2cm]{geometry}\n\\allowdisplaybreaks\n")
"""The LaTeX worked solution's preamble: for pdflatex T1 fonts (``<``, ``>``, ``|`` and accented
letters print as typed, not as OT1's inverted marks) and UTF-8 input; for lualatex and xelatex
fontspec (\\ifPDFTeX from the iftex package, which every distribution with hyperref has)."""
_LATIN_PUNCTUATION = set("\u2013\u2014\u2018\u2019\u201c\u201d\u2026")


_BEYOND_LATIN = re.compile("[^\x00-\u017f" + "".join(sorted(_LATIN_PUNCTUATION)) + "]")
"""One character beyond Latin Extended-A that is none of :data:`_LATIN_PUNCTUATION`."""


def _beyond_latin(text: str) -> bool:
    """Whether ``text`` holds a character pdflatex's T1/UTF-8 setup does not set: beyond Latin
    Extended-A (U+017F), typographic dashes, quotes and the ellipsis apart (one regular expression
    over the document, not a test per character)."""
    return _BEYOND_LATIN.search(text) is not None


# -- HTML ------------------------------------------------------------------------------------------


_CSS = ("body{font-family:sans-serif;max-width:60em;margin:auto;padding:0 1em} "
        ".eq{margin:.3em 0 .8em 2em;padding:.2em 0;overflow-x:auto;overflow-y:hidden} .eq math{font-size:1.15em} "
        ".terms td{border:none;padding:.1em .3em;vertical-align:middle} .note{color:#555;white-space:nowrap} "
        "table{border-collapse:collapse} td,th{border:1px solid #ccc;padding:.2em .5em} "
        "figure.fbd{margin:1em 0} figure.fbd svg{display:block;width:100%;max-width:44em;height:auto}")
"""The worked solution's style sheet (a plain string: no f-string brace doubling). A free-body
diagram is drawn at the page's width (at most 44em), so that its labels read at the size of the text."""


class _Html(_Renderer):
    """HTML with every equation, name and formula as MathML (:mod:`solver.mathml`, the report's
    conversion), drawn with the embedded maths font (:mod:`solver.mathfont`): no script, no network."""

    def __init__(self, expl):
        super().__init__(expl)
        from .mathml_prose import MathmlProse

        self.prose = MathmlProse(decide=prose_names(expl))
        self.drawings = 0  # the free-body diagrams inlined so far: each one's ids get its number

    def wrap(self, body):
        from ..mathfont import font_face_css
        from ..mathml import minus_signs

        return minus_signs("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
                f"<title>{_h(self.expl.title)}</title>\n<style>{font_face_css()}\n  {_CSS}</style></head><body>\n"
                + body + "\n</body></html>\n")

    def plain(self, text):
        return f"<bdi>{_h(text)}</bdi>"  # the scene's own text: the minus rule leaves it as typed

    def prose_text(self, text):
        return self.prose.text(text)

    def title(self, text):
        return f"<h1>{self.words(text)}</h1>"

    def heading(self, text, level):
        return f"<h{level}>{self.words(text)}</h{level}>"

    def paragraph(self, text):
        return f"<p>{self.words(text)}</p>"

    def command(self, intro, command):
        return f"<p>{self.prose.text(intro)} <code>{html.escape(command)}</code></p>"

    def equation(self, eq):
        label, unit = eq.label, ""
        bracket = re.fullmatch(r"(.*) \[([^\]]+)\]", label)  # "body: Newton, x component [lbf]"
        if bracket and _unit_html(bracket[2]):
            label, unit = bracket[1], f" [{_unit_html(bracket[2])}]"
        head = self.prose.text(label) + unit + (f" ({self.prose.text(eq.ref)})" if eq.ref else "")
        notes = len([t for t in (*eq.rhs, *([] if eq.name else eq.lhs)) if t.note]) >= 2  # as the text shows them
        sign = "<mo>\u2248</mo>" if eq.approximate else "<mo>=</mo>"
        lhs = (Term(sp.Symbol(eq.name)),) if eq.name else eq.lhs
        if not notes:
            body = f"{_terms_mathml(lhs, eq.name)}{sign}{_terms_mathml(eq.rhs)}"
            return f"<div>{head}:</div><div class=\"eq\">{_math(body)}</div>"
        table = terms_table(lhs, eq.rhs, sign, eq.name, lambda note: f"[{self.prose.cell(note)}]")
        return f"<div>{head}:</div><div class=\"eq\">{table}</div>"

    def table(self, table):
        units = [h == "unit" for h in table.header]
        head = "".join(f"<th>{self.prose.cell(c)}</th>" for c in table.header)
        rows = "".join("<tr>" + "".join(f"<td>{self.prose.cell(c, u)}</td>" for c, u in zip(r, units)) + "</tr>"
                       for r in table.rows)
        return f"<table><tr>{head}</tr>{rows}</table>"

    def figure(self, figure):
        return f"<figure data-figure=\"{_h(figure)}\"></figure>"

    def drawing(self, svg):
        self.drawings += 1  # the project's own SVG (labels escaped by matplotlib), ids unique in the page
        return f"<figure class=\"fbd\">{inline_svg(svg, f'fbd{self.drawings}')}</figure>"


def terms_table(lhs, rhs, sign: str, name: str, note_html) -> str:
    """An equation laid out one term a row (left side, then right side), each with its note: the
    worked solution's HTML for an equation whose terms carry notes, and paper.html's for a display
    wider than its page. A left side of one term without a note (a name, a_G) stands before the
    right side's first row; a 2-vector is written as a column and a note goes above its term where
    the rows would still be wider than :data:`EQUATION_WIDTH_EM`.

    Parameters
    ----------
    lhs, rhs : sequence of Term
    sign : str
        The relation's MathML, ``<mo>=</mo>`` or ``<mo>\u2248</mo>``.
    name : str
        The left side's name ("" when the left side is its terms).
    note_html : callable
        A term's note -> its HTML (escaped), shown in a ``<span class="note">``.
    """
    inline = len(lhs) == 1 and not lhs[0].note
    sides = ((sign, rhs),) if inline else (("", lhs), (sign, rhs))
    column, above = _term_layout(lhs, rhs, inline, name)
    rows = []
    for mark, terms in sides:
        for i, t in enumerate(terms):
            negative = i > 0 and _negative(t.expr)
            op = "<mo>\u2212</mo>" if negative else "<mo>+</mo>" if i else mark
            term = _term_mathml(-t.expr if negative else t.expr, name if t in lhs and name else "", column)
            note = f"<span class=\"note\">{note_html(t.note)}</span>" if t.note else ""
            left = _math(_term_mathml(lhs[0].expr, name)) if inline and i == 0 else ""
            if above and note:  # the note on a row of its own, where a wide term leaves it no room beside
                rows.append(f"<tr><td></td><td></td><td>{note}</td><td></td></tr>")
                note = ""
            rows.append(f"<tr><td>{left}</td><td>{_math(op) if op else ''}</td><td>{_math(term)}</td>"
                        f"<td>{note}</td></tr>")
    return f"<table class=\"terms\">{''.join(rows)}</table>"


def _h(text) -> str:
    return html.escape(str(text), quote=True)


def _unit_html(unit: str):
    from .mathml_prose import unit_html

    return unit_html(unit)


def _math(body: str) -> str:
    """One inline ``<math>`` element shown in display style (full-size fractions), left-aligned."""
    from ..mathml import wrap

    return wrap(f"<mstyle displaystyle=\"true\">{body}</mstyle>", "inline")


def _negative(expr) -> bool:
    return not isinstance(expr, sp.MatrixBase) and could_extract_minus_sign(sp.sympify(expr))


def _term_mathml(expr, name: str = "", column: bool = False) -> str:
    """The MathML of one term: a 2-vector as ``(x, y)``, as the text writes it, or with ``column``
    as a column vector, as the LaTeX writes it; ``name`` a name."""
    from ..mathml import mathml_body
    from .mathml_prose import name_mathml

    if name:
        return name_mathml(name)
    if isinstance(expr, sp.MatrixBase) and column:
        rows = "".join(f"<mtr><mtd><mstyle displaystyle=\"true\">{mathml_body(x)}</mstyle></mtd></mtr>" for x in expr)
        return f"<mrow><mo>(</mo><mtable>{rows}</mtable><mo>)</mo></mrow>"
    if isinstance(expr, sp.MatrixBase):
        return f"<mrow><mo>(</mo>{mathml_body(expr[0])}<mo>,</mo>{mathml_body(expr[1])}<mo>)</mo></mrow>"
    return mathml_body(sp.sympify(expr))


EQUATION_WIDTH_EM = 45.0
"""The room, in em of the maths font, for one term-by-term equation of the worked solution's HTML
(the page's 60em less the equation's indent and the cells' padding, at the maths' 1.15em size):
wider, and a 2-vector is written as a column, then the terms' notes go on rows of their own."""
NOTE_EM_PER_CHAR = 0.45
"""The width of one character of a note (sans-serif at the text's size) in em of the maths font."""


def _term_layout(lhs, rhs, inline: bool, name: str) -> tuple[bool, bool]:
    """(column vectors, notes above their terms) for a term-by-term equation: each only where the
    row form would run past :data:`EQUATION_WIDTH_EM` and the page would scroll it sideways."""
    from ..mathml import mathml_width

    def widest(column):
        left = mathml_width(_term_mathml(lhs[0].expr, name)) if inline else 0.0
        terms = [*([] if inline else lhs), *rhs]
        return left + 2.0 + max(mathml_width(_term_mathml(t.expr, name if t in lhs else "", column)) for t in terms)

    notes = max((len(t.note) + 2 for t in (*lhs, *rhs) if t.note), default=0) * NOTE_EM_PER_CHAR
    column = widest(False) + notes > EQUATION_WIDTH_EM and any(isinstance(t.expr, sp.MatrixBase) for t in rhs)
    return column, widest(column) + notes > EQUATION_WIDTH_EM


def _terms_mathml(terms, name: str = "") -> str:
    """The terms of one side in one row, a negative scalar term after the first joined by "-" (not "+ -")."""
    out = ""
    for i, t in enumerate(terms):
        negative = i > 0 and _negative(t.expr)
        out += ("<mo>\u2212</mo>" if negative else "<mo>+</mo>" if i else "") + _term_mathml(-t.expr if negative else t.expr, name)
    return f"<mrow>{out}</mrow>"
