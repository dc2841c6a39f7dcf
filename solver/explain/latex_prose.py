"""Prose, names, expressions and units of a worked solution written as LaTeX.

The content of a worked solution (:mod:`solver.explain.content`) carries its words as plain
text in which names (``theta_ddot``, ``r_G/A``), short formulae (``v = v_A + omega x r``),
expressions (``l_b**2*m_b/12``) and units (``ft / s ** 2``) are written the way code writes
them. :class:`LatexProse` turns such text into LaTeX: the words stay text (escaped), each
formula becomes inline maths with the symbols' LaTeX names (the ``symbol_latex`` map of the
explanation, :func:`solver.explain.build.latex_names`, and sympy's names of the symbols the
equations hold), powers as superscripts, no ``*`` and no ``**``; a unit becomes
``\\mathrm{ft/s^{2}}``.

Nothing is evaluated: the text is split by one regular expression into words, numbers and
operators, and a word is maths only when it is a symbol of the explanation, a Greek letter,
a rate (``x_dot``, ``x_ddot``) or a one-letter name with a subscript (``a_A``, ``M_P``).
Everything else is escaped text, so scene names stay data.
"""
from __future__ import annotations

import re

import sympy as sp

from ..notation import compound_latex, latex_escape

__all__ = ["LatexProse", "latex_escape", "unit_latex", "subscripted"]


def subscripted(head: str, tail: str) -> str:
    r"""``head`` with the subscript ``tail``, whose underscores join the words of one name
    (``C_contact``, ``rectangular_plate_1``): a visible space between them, as LaTeX's maths
    drops a plain one (``Ccontact``) and ``\\_`` would read as code.

    >>> subscripted("v", "C_contact"), subscripted("r", "C_incline/P")
    ('v_{C\\ contact}', 'r_{C\\ incline/P}')
    """
    return head + "_{" + tail.replace("_", r"\ ") + "}"


_GREEK = {"alpha", "beta", "gamma", "delta", "epsilon", "zeta", "eta", "theta", "iota", "kappa", "lambda",
          "mu", "nu", "xi", "pi", "rho", "sigma", "tau", "upsilon", "phi", "chi", "psi", "omega",
          "Gamma", "Delta", "Theta", "Lambda", "Xi", "Pi", "Sigma", "Upsilon", "Phi", "Psi", "Omega"}
_FUNCTIONS = {"sin": r"\sin", "cos": r"\cos", "tan": r"\tan", "exp": r"\exp", "log": r"\log",
              "sqrt": r"\operatorname{sqrt}", "sign": r"\operatorname{sign}", "Abs": r"\operatorname{abs}"}
_RELATIONS = {">=": r"\geq", "<=": r"\leq", "=": "=", "~": r"\approx", ">": ">", "<": "<"}

_TOKEN = re.compile(r"""
    (?P<flag>--point[ ][A-Za-z0-9_:(),]*[A-Za-z0-9_)]|--[a-z][a-z-]*[a-z])
  | (?P<prose>[A-Za-z]+'[a-z]+(?![A-Za-z0-9_]))
  | (?P<name>[A-Za-z][A-Za-z0-9]*
             (?:(?:_[A-Za-z0-9]+)+(?:,[a-z](?![A-Za-z0-9]))?
                (?:/[A-Za-z][A-Za-z0-9]*(?:_[A-Za-z0-9]+)*(?:\([A-Za-z0-9_,]+\)(?=[\s,.;:)]|$))?(?![A-Za-z0-9(]))?)?
             (?:\([A-Za-z0-9_,]+\)(?:/[A-Za-z][A-Za-z0-9]*)?(?=[\s,.;:)]|$))?'*(?![A-Za-z]))
  | (?P<num>\d+(?:\.\d+)?(?:e[-+]?\d+)?)
  | (?P<op>\*\*|>=|<=|(?<=[ ])[<>](?=[ ])|[-+*/=^|~])
  | (?P<paren>[()])
  | (?P<space>[ ]+)
  | (?P<other>.)
""", re.VERBOSE | re.DOTALL)
UNIT = "unit"
"""The kind of a prose token that is the unit of the number before it (:func:`_mark_units`)."""
CODE = "code"
"""The kind of a prose segment that is a command-line flag as typed (:meth:`LatexProse.segments`)."""
_ONE_LETTER_SUB = re.compile(r"[A-Za-z](?:_[A-Za-z0-9]+)+(?:,[a-z])?(?:/[A-Za-z][A-Za-z0-9]*)?")
_SUBSCRIPTED = re.compile(r"[A-Za-z][0-9]*(?:_[A-Za-z0-9]+)+")
_RATE = re.compile(r"(?P<base>[A-Za-z][A-Za-z0-9]*)_(?P<dots>d?dot)")
_UNIT = re.compile(r"[A-Za-z]+(?:\s*(?:\*\*\s*-?\d+|[*/]\s*[A-Za-z]+))*")
_NUMBER_UNIT = re.compile(r"(?P<num>-?\d+(?:\.\d+)?(?:e[-+]?\d+)?)(?:\s+(?P<unit>" + _UNIT.pattern + "))?")


def _mark_units(tokens: list) -> list:
    """``tokens`` with the unit after a number that a relation gives (``|F| = 7.35 N``, ``N_B =
    -15 lbf < 0``, ``a = 2 ft/s**2``) as one token of kind :data:`UNIT`, so that it is set upright
    and not read as a symbol (N the unit, not the normal force N). Only there: elsewhere in prose
    a number and a word ("1 Newton component") stay what they are."""
    out, last, i = [], ["", ""], 0  # last: the two tokens before, spaces left out
    while i < len(tokens):
        kind, value = tokens[i]
        out.append(tokens[i])
        relation = last[1] if last[1] != "-" else last[0]  # (= -15 N)
        if kind == "num" and relation in _RELATIONS and tokens[i + 1:i + 2] == [("space", " ")]:
            j = _unit_end(tokens, i + 2)
            if j > i + 2:
                out.append((UNIT, "".join(v for _, v in tokens[i + 2:j])))
                last, i = [value, "unit"], j
                continue
        if kind != "space":
            last = [last[1], value]
        i += 1
    return out


def _unit_end(tokens: list, i: int) -> int:
    """The end of the unit written from token ``i`` on (``ft*lbf``, ``m/s**2``), ``i`` when none:
    names of letters joined by ``*`` and ``/``, and integer powers, as :data:`_UNIT` reads them."""
    text, ends = "", {}
    for j in range(i, len(tokens)):
        if tokens[j][0] in ("space", "other", "paren", "flag"):
            break
        text += tokens[j][1]
        ends[len(text)] = j + 1
    m = _UNIT.match(text)
    return ends.get(m.end(), i) if m else i


def unit_latex(unit: str) -> str | None:
    """``ft / s ** 2`` -> ``\\mathrm{ft/s^{2}}``, ``N*m`` -> ``\\mathrm{N\\,m}``; None when ``unit`` is
    not written as units are (letters joined by ``*``, ``/`` and integer powers)."""
    unit = unit.strip()
    if not _UNIT.fullmatch(unit):
        return None
    text = re.sub(r"\s*\*\*\s*(-?\d+)", r"^{\1}", unit)
    text = re.sub(r"\s*\*\s*", r"\\,", text)
    text = re.sub(r"\s*/\s*", "/", text)
    return rf"\mathrm{{{text}}}"


def _number_latex(number: str) -> str:
    """``1.9e-16`` -> ``1.9\\times 10^{-16}``; other numbers as written."""
    mantissa, e, exponent = number.partition("e")
    if not e:
        return number
    return "0" if float(mantissa) == 0 else rf"{mantissa}\times 10^{{{int(exponent)}}}"


class LatexProse:
    """Text of a worked solution as LaTeX, with the names of one explanation.

    Parameters
    ----------
    symbols : iterable of sympy.Symbol
        The symbols the explanation's equations hold (each is maths wherever its name appears).
    symbol_latex : dict
        LaTeX names that differ from sympy's (dotted rates, :func:`solver.explain.build.latex_names`).
    """

    def __init__(self, symbols, symbol_latex: dict):
        self.known = {str(s): compound_latex(s.name) or sp.latex(s, symbol_names=symbol_latex) for s in symbols}
        self.known.update({str(s): tex for s, tex in symbol_latex.items()})
        self._names: dict = {}  # word -> its LaTeX or None: each word decided once (a worked solution
        self._segments: dict = {}  # names a few dozen thousand times); (text, letters) -> its segments

    # -- names ------------------------------------------------------------------------------------

    def name(self, word: str) -> str | None:
        """The LaTeX of a name, or None when the word is not a name of maths."""
        if word not in self._names:
            self._names[word] = self._name(word)
        return self._names[word]

    def _name(self, word: str) -> str | None:
        primes = len(word) - len(word.rstrip("'"))
        word = word.rstrip("'")
        point, slash, reference = word.rpartition("/")
        if slash and point.endswith(")") and "(" in point:  # r_I(R_A,R_B)/A: the subscript takes the /A
            tex = self.name(point)
            return None if tex is None or not tex.endswith("}") else tex[:-1] + "/" + reference + "}" + "'" * primes
        args = ""
        if word.endswith(")") and "(" in word:  # a point named by two lines, I(R_A,R_B)
            word, _, inner = word[:-1].partition("(")
            args = "(" + ",".join(self.name(a) or latex_escape(a) for a in inner.split(",")) + ")"
        tex = _FUNCTIONS.get(word) if args and word in _FUNCTIONS else self._plain_name(word)  # sin(beta)
        if tex is None:
            return None
        if args:  # a function's arguments follow it; a point's lines go in its subscript
            tex = tex[:-1] + args + "}" if tex.endswith("}") and word not in _FUNCTIONS else tex + args
        return tex + "'" * primes

    def _plain_name(self, word: str) -> str | None:
        if word in self.known:
            return self.known[word]
        compound = compound_latex(word)  # (a_C_floor, r_G/C_floor: the one reading of such names)
        if compound:
            return compound
        rate = _RATE.fullmatch(word)
        if rate:
            base = self._plain_name(rate["base"])
            return None if base is None else rf"\{rate['dots']}{{{base}}}"
        head, _, tail = word.partition("_")
        if head in _GREEK or _SUBSCRIPTED.fullmatch(word):  # as sympy writes the symbol (O2_x: O_{2 x})
            return sp.latex(sp.Symbol(word))
        if _ONE_LETTER_SUB.fullmatch(word):
            return subscripted(head, tail)
        if len(word) == 1 or word == "dt":  # one letter; dt of d^2 Phi/dt^2
            return word
        return None

    def _strong(self, word: str, letters: bool) -> bool:
        """Maths by itself. A single letter is, in prose, maths only next to an operator or another name
        (``a`` is also an article); with ``letters`` (a table cell, a note) a symbol's letter is maths."""
        bare = word.rstrip("'")
        if len(bare) == 1 and bare == word:
            return letters and word in self.known
        return self.name(word) is not None or bare in _FUNCTIONS

    # -- text -------------------------------------------------------------------------------------

    def text(self, text: str, letters: bool = False) -> str:
        """Prose as LaTeX text with inline maths for its names and formulae (``letters``: see
        :meth:`_strong`)."""
        return "".join("$" + self._maths(part) + "$" if maths is True else
                       r"\texttt{" + latex_escape(part) + "}" if maths == CODE else latex_escape(part)
                       for maths, part in self.segments(text, letters))

    def segments(self, text: str, letters: bool = False) -> tuple:
        """The prose split into words and formulae: ``(False, text)`` for text, ``(True, tokens)`` for a
        formula (its ``(kind, value)`` tokens), ``(CODE, text)`` for a command-line flag as typed
        (``--point C_contact``: text a user types, never maths). The one decision of what is maths
        in the worked solution's prose, for LaTeX (:meth:`text`) and for HTML's MathML
        (:mod:`.mathml_prose`). Each text is split once (table cells and notes repeat)."""
        key = (str(text), letters)
        if key not in self._segments:
            self._segments[key] = tuple(self._split(*key))
        return self._segments[key]

    def _split(self, text: str, letters: bool):
        """The segments of :meth:`segments`, one at a time."""
        tokens = _mark_units([(m.lastgroup, m.group()) for m in _TOKEN.finditer(str(text))])
        i, words = 0, ""
        while i < len(tokens):
            if tokens[i][0] == "flag":
                if words:
                    yield False, words
                    words = ""
                yield CODE, tokens[i][1]
                i += 1
                continue
            end = self._formula_end(tokens, i, letters)
            if end > i:
                if words:
                    yield False, words
                    words = ""
                yield True, tokens[i:end]
                i = end
            else:
                words += tokens[i][1]
                i += 1
        if words:
            yield False, words

    def cell(self, text: str, unit: bool = False) -> str:
        """A table cell: a unit (``unit``), a number with its unit, a name, or prose."""
        text = str(text)
        if unit and unit_latex(text):
            return "$" + unit_latex(text) + "$"
        m = _NUMBER_UNIT.fullmatch(text.strip())
        if m:
            tail = rf"\,{unit_latex(m['unit'])}" if m["unit"] else ""
            return f"${_number_latex(m['num'])}{tail}$"
        word = text.strip()
        if re.fullmatch(r"[A-Z][0-9]*", word):  # a point (A, O2)
            return f"${word}$"
        if _TOKEN.fullmatch(word) and _TOKEN.fullmatch(word).lastgroup == "name" and self.name(word):
            return "$" + self.name(word) + "$"
        return self.text(text, letters=True)

    def _operand(self, kind: str, value: str) -> bool:
        return kind in ("num", UNIT) or (kind == "name" and (self.name(value) is not None or value in _FUNCTIONS
                                                     or value == "x"))

    def _formula_end(self, tokens, start: int, letters: bool) -> int:
        """End of the formula that starts at ``start`` (``start`` when none does)."""
        kind, value = tokens[start]
        if not (self._operand(kind, value) or value in ("-", "(", "|", "=")):
            return start
        if value in _FUNCTIONS and tokens[start + 1:start + 2] != [("paren", "(")]:
            return start
        end, depth, last_good, strong, relation = start, 0, start, False, False
        while end < len(tokens):
            kind, value = tokens[end]
            if (kind == "other" and not (value == "," and depth > 0)) or kind == "prose":
                break  # ("prose": a word with an apostrophe, the advisor's, is never maths)
            if kind == "name" and not self._operand(kind, value):
                break
            if value in _FUNCTIONS and tokens[end + 1:end + 2] != [("paren", "(")]:
                break  # sin, sign... are functions only when applied: "the sign of" is a word
            if kind == "paren":
                depth += 1 if value == "(" else -1
                if depth < 0:
                    break
            strong = strong or (kind == "name" and self._strong(value, letters)) or value in ("**", "^", "*")
            relation = relation or (value in _RELATIONS and value not in "<>")  # (a spaced < or > joins formulae,
            # makes none: "b > a" stays text, as it did)
            end += 1
            if depth == 0 and kind in ("name", "num", "paren", UNIT) or value == "|":
                last_good = end
        if last_good == start or not (strong or relation):
            return start
        if all(k in ("num", "space", "op", "paren") for k, _ in tokens[start:last_good]) and not strong:
            return start  # numbers alone (Eqs. 11-14) stay text
        return last_good

    def _maths(self, tokens) -> str:
        out, i = [], 0
        while i < len(tokens):
            kind, value = tokens[i]
            if value in ("**", "^") and i + 1 < len(tokens):
                j, group = self._exponent(tokens, i + 1)
                out.append("^{" + self._maths(group) + "}")
                i = j
                continue
            if kind == "name":
                prev = [v for k, v in tokens[:i] if k != "space"]
                after = [v for k, v in tokens[i + 1:] if k != "space"]
                if value == "x" and prev and after and prev[-1] not in ("(", ",") and after[0] not in (")", ","):
                    out.append(r"\times")
                else:
                    out.append(_FUNCTIONS.get(value) or self.name(value))
            elif kind == "op":
                out.append({"*": r"\,", "|": "|", "/": "/"}.get(value, _RELATIONS.get(value, value)))
            elif kind == "space":
                out.append(" ")
            elif kind == UNIT:
                out.append(r"\," + unit_latex(value))
            else:
                out.append(value)
            i += 1
        return re.sub(r" *\\, *", r"\\,", "".join(out)).strip()

    @staticmethod
    def _exponent(tokens, i: int):
        """(index after the exponent, its tokens): one operand or one parenthesised group."""
        while i < len(tokens) and tokens[i][0] == "space":
            i += 1
        if i < len(tokens) and tokens[i][1] == "-":
            j, group = LatexProse._exponent(tokens, i + 1)
            return j, [tokens[i], *group]
        if i < len(tokens) and tokens[i][1] == "(":
            depth, j = 0, i
            while j < len(tokens):
                depth += {"(": 1, ")": -1}.get(tokens[j][1], 0)
                j += 1
                if depth == 0:
                    break
            return j, tokens[i + 1:j - 1]
        return i + 1, tokens[i:i + 1]
