"""Prose, names, expressions and units of a worked solution written as HTML with MathML.

The counterpart of :mod:`.latex_prose` for the HTML rendering: the same decision of which words
and formulae of a sentence are maths (:meth:`LatexProse.segments`), each formula then written as
an inline ``<math>`` element through the project's one MathML conversion (:mod:`solver.mathml`:
names as sympy symbols, so ``theta_ddot`` is a theta with two dots and ``r_G/A`` an r with a
subscript), powers as superscripts, no ``*`` and no ``**``. The words are escaped text; a unit
is written ``ft/s<sup>2</sup>``.
"""
from __future__ import annotations

import html
import re

import sympy as sp

from ..mathml import mathml_body, wrap
from ..notation import compound_subscript
from .latex_prose import _FUNCTIONS, _NUMBER_UNIT, _UNIT, CODE, UNIT, LatexProse

__all__ = ["MathmlProse", "unit_html", "unit_mathml", "name_mathml", "number_mathml"]

# a number with an exponent in the prose, and the unit after it when a bracket closes there
_E_NUMBER = re.compile(r"(?<![\w.])(?P<num>-?\d+(?:\.\d+)?e[-+]?\d+)(?:\s+(?P<unit>" + _UNIT.pattern + r")(?=\)))?")
_RELATIONS = {">=": "\u2265", "<=": "\u2264", "=": "=", "~": "\u2248", ">": ">", "<": "<"}


def _h(text) -> str:
    return html.escape(str(text), quote=True)


def unit_html(unit: str) -> str | None:
    """``ft / s ** 2`` -> ``ft/s<sup>2</sup>``, ``N*m`` -> ``N&#183;m``; None when ``unit`` is not
    written as units are (letters joined by ``*``, ``/`` and integer powers)."""
    unit = unit.strip()
    if not _UNIT.fullmatch(unit):
        return None
    text = re.sub(r"\s*\*\*\s*(-?\d+)", r"<sup>\1</sup>", unit)
    text = re.sub(r"\s*\*\s*", "&#183;", text)
    return re.sub(r"\s*/\s*", "/", text)


def unit_mathml(unit: str) -> str:
    """``ft / s ** 2`` as MathML: upright unit names (``mathvariant="normal"``, so the unit N is not
    the italic symbol N), a middle dot for ``*``, a superscript for a power."""
    out = []
    for word, op, power in re.findall(r"([A-Za-z]+)|(\*\*|[*/])|(-?\d+)", unit):
        if word:
            out.append(f"<mi mathvariant=\"normal\">{_h(word)}</mi>")
        elif op == "**":
            continue
        elif op:
            out.append("<mo>&#183;</mo>" if op == "*" else "<mo>/</mo>")
        elif out:
            out[-1] = f"<msup>{out[-1]}<mn>{power}</mn></msup>"
    return "<mrow>" + "".join(out) + "</mrow>"


def name_mathml(word: str) -> str:
    """The MathML (without ``<math>``) of a name as the equations print its symbol: ``theta_ddot``
    dotted, ``R_B`` subscripted, ``omega`` Greek; primes (``C_x'``) after it."""
    bare = word.rstrip("'")
    primes = "<mo>\u2032</mo>" * (len(word) - len(bare))
    body = mathml_body(sp.Symbol(bare)) if bare else ""
    return f"<mrow>{body}{primes}</mrow>" if primes else body


def number_mathml(number: str) -> str:
    """``1.9e-16`` -> 1.9 x 10 to the -16; other numbers as written."""
    mantissa, e, exponent = number.partition("e")
    if not e:
        return f"<mn>{_h(number)}</mn>"
    if float(mantissa) == 0:
        return "<mn>0</mn>"
    return f"<mrow><mn>{_h(mantissa)}</mn><mo>\u00d7</mo><msup><mn>10</mn><mn>{int(exponent)}</mn></msup></mrow>"


class MathmlProse:
    """Text of a worked solution as HTML with inline MathML, with the names of one explanation.

    Parameters
    ----------
    symbols, symbol_latex
        As :class:`LatexProse` takes them: they decide which words are names of maths.
    decide : LatexProse, optional
        That decision made already (shared with the LaTeX rendering:
        :func:`solver.explain.render.prose_names`); then ``symbols`` and ``symbol_latex`` are not read.
    """

    def __init__(self, symbols=(), symbol_latex: dict | None = None, decide: LatexProse | None = None):
        self.decide = decide if decide is not None else LatexProse(symbols, symbol_latex or {})

    def text(self, text: str, letters: bool = False) -> str:
        """Prose as escaped HTML with an inline ``<math>`` for each name and formula, and for each
        number written with an exponent (``-2.56e-15``, as the tables write it: -2.56 x 10 to the
        -15; with its unit when a bracket closes after it, ``(error bound 1.2e-13 rad/s**2)``)."""
        out, start = [], 0
        for m in _E_NUMBER.finditer(str(text)):
            out.append(self._words(text[start:m.start()], letters))
            unit = f"&#8201;{unit_html(m['unit'])}" if m["unit"] and unit_html(m["unit"]) else ""
            out.append(str(wrap(number_mathml(m["num"]), "inline")) + unit)
            start = m.end() if unit else m.start("unit") if m["unit"] else m.end()
        return "".join(out) + self._words(str(text)[start:], letters)

    def _words(self, text: str, letters: bool) -> str:
        return "".join(wrap(self._maths(part), "inline") if maths is True else
                       f"<code>{_h(part)}</code>" if maths == CODE else _h(part)
                       for maths, part in self.decide.segments(text, letters))

    def cell(self, text: str, unit: bool = False) -> str:
        """A table cell: a unit (``unit``), a number with its unit, a name, or prose."""
        text = str(text)
        if unit and unit_html(text):
            return unit_html(text)
        m = _NUMBER_UNIT.fullmatch(text.strip())
        if m:
            number = m["num"] if "e" not in m["num"] else str(wrap(number_mathml(m["num"]), "inline"))
            return number + (f"&#8201;{unit_html(m['unit'])}" if m["unit"] else "")
        word = text.strip()
        if re.fullmatch(r"[A-Z][0-9]*", word) or (re.fullmatch(r"[A-Za-z][A-Za-z0-9_,/]*'*", word)
                                                   and self.decide.name(word)):
            return wrap(name_mathml(word), "inline")
        return self.text(text, letters=True)

    def _name(self, word: str) -> str:
        if compound_subscript(word.rstrip("'")) is not None:  # v_I(O_x,A_y), r_G/I(O_x,A_y): a subscript
            return name_mathml(word)
        if word.endswith(")") and "(" in word:  # a point named by two lines, I(R_A,R_B); sin(beta)
            head, _, inner = word[:-1].partition("(")
            args = "<mo>,</mo>".join(name_mathml(a) for a in inner.split(","))
            return f"<mrow>{self._name(head)}<mo>(</mo>{args}<mo>)</mo></mrow>"
        if word in _FUNCTIONS:
            return f"<mi>{word}</mi>"
        return name_mathml(word)

    def _maths(self, tokens) -> str:
        """The MathML of one formula's tokens (as :meth:`LatexProse._maths` writes its LaTeX)."""
        out, i = [], 0
        while i < len(tokens):
            kind, value = tokens[i]
            if value in ("**", "^") and i + 1 < len(tokens):
                j, group = LatexProse._exponent(tokens, i + 1)
                base = out.pop() if out else "<mrow></mrow>"
                out.append(f"<msup>{base}<mrow>{self._maths(group)}</mrow></msup>")
                i = j
                continue
            if kind == "name":
                prev = [v for k, v in tokens[:i] if k != "space"]
                after = [v for k, v in tokens[i + 1:] if k != "space"]
                if value == "x" and prev and after and prev[-1] not in ("(", ",") and after[0] not in (")", ","):
                    out.append("<mo>\u00d7</mo>")
                else:
                    out.append(self._name(value))
            elif kind == "num":
                out.append(number_mathml(value))
            elif kind == UNIT:  # (a thin space, then the unit upright)
                out.append(f"<mspace width=\"0.167em\"/>{unit_mathml(value)}")
            elif kind == "op":
                prev = [(k, v) for k, v in tokens[:i] if k != "space"]
                if value == "-" and (not prev or prev[-1][0] == "op" or prev[-1][1] in ("(", ",")):
                    out.append('<mo form="prefix">-</mo>')  # a sign, (-A_x, 0): no space as around a binary minus
                else:
                    out.append({"*": "<mo>&#8290;</mo>"}.get(value) or f"<mo>{_h(_RELATIONS.get(value, value))}</mo>")
            elif kind != "space":
                out.append(f"<mo>{_h(value)}</mo>")
            i += 1
        return "<mrow>" + "".join(out) + "</mrow>"
