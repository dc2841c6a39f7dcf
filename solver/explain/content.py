"""The one source of a worked solution: structured steps holding sympy expressions and text.

:func:`solver.explain.build.explain` fills these; :mod:`solver.explain.render`
turns the same content into text, Markdown, HTML or LaTeX. Nothing here
knows a format.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp

from ..model.joints import copy_vec
from ..strprint import FastStrPrinter

__all__ = ["Term", "Equation", "Table", "Step", "Section", "Explanation", "SceneText", "slip_friction",
           "SLIP_VELOCITY_NOTE"]


class SceneText(str):
    """Text the scene gives (its name, its description): shown as text in every format, escaped,
    never read as names and formulae (a title ``theta_dot = 2 rad/s`` stays as typed)."""


def slip_friction(normal: str = "N") -> str:
    """A slipping contact's friction as the worked solution writes it: ``-sign(v_slip) mu_k N``.
    ``sign(...)`` is a function applied, which no scene can name (a lone ``s`` could be a scene's
    coordinate: incline_ring's is)."""
    return f"-sign(v_slip) mu_k {normal}"


SLIP_VELOCITY_NOTE = "v_slip the sliding velocity"
"""What ``v_slip`` of :func:`slip_friction` is, said once where the friction is first written."""


@dataclass(frozen=True)
class Term:
    """One displayed term of an equation's side, kept apart from its neighbours.

    Attributes
    ----------
    expr : sympy.Expr
    note : str
        What the term is ("moment of R_B about A", "inertial term -r_G/A x m a_A").
    """

    expr: sp.Expr
    note: str = ""


@dataclass(frozen=True)
class Equation:
    """``lhs = rhs``, each side a list of terms displayed separately.

    Attributes
    ----------
    lhs, rhs : tuple of Term
        The sides; their sums are the mathematical content (tests compare these).
    label : str
        What the equation is ("Newton, x component").
    ref : str
        The paper's general equation it instantiates ("Eq. (10)").
    tag : str
        A stable identifier (``"euler"``, ``"newton_x"``, ``"accel:G"``...) within its step.
    name : str
        When set, the left side is displayed as this name (``a_G``, ``I_A``), and
        ``lhs`` holds its value.
    vector : bool
        Both sides are 2-component vectors (sympy Matrix) in the fixed frame.
    approximate : bool
        ``lhs ~ rhs`` (a small-motion rule, the paper's Eq. 45), shown with an approximately-equal sign.
    """

    lhs: tuple[Term, ...]
    rhs: tuple[Term, ...]
    label: str = ""
    ref: str = ""
    tag: str = ""
    name: str = ""
    vector: bool = False
    approximate: bool = False

    @property
    def sign(self) -> str:
        """The relation as text: ``=``, or ``~`` for an approximation."""
        return "~" if self.approximate else "="

    @property
    def left(self):
        return _sum(self.lhs, self.vector)

    @property
    def right(self):
        return _sum(self.rhs, self.vector)

    @property
    def residual(self):
        """lhs - rhs (a scalar, or a 2x1 Matrix for a vector equation)."""
        return self.left - self.right


def _sum(terms, vector: bool):
    if vector:  # the same matrix as sum(terms, zeros(2, 1)), without adding the zeros (unifying
        if not terms:  # their domain with the terms' costs more than the sum)
            return sp.zeros(2, 1)
        total = copy_vec(terms[0].expr)
        for t in terms[1:]:
            total = total + copy_vec(t.expr)
        return total
    return sp.Add(*[t.expr for t in terms])


@dataclass(frozen=True)
class Table:
    header: tuple[str, ...]
    rows: tuple[tuple[str, ...], ...]


@dataclass
class Step:
    """One step of the worked solution.

    Attributes
    ----------
    kind : str
        ``data``, ``kinematics``, ``fbd``, ``newton``, ``euler``, ``dropped``,
        ``motion``, ``solution``, ``check`` or ``advice``.
    title : str
    text : list of str
        Paragraphs (plain text; renderers escape them).
    equations : list of Equation
    table : Table or None
    figure : str or None
        Hook for a drawing of this step (the free-body diagram of the body):
        None until the drawing module provides a file or inline SVG for it.
    figure_request : dict or None
        What the drawing should show (``{"scene": ..., "body": ..., "fbd": True}``).
    figure_svg : str or None
        That drawing as inline SVG (:func:`solver.explain.figures.attach_figures`), shown by the
        HTML rendering.
    """

    kind: str
    title: str
    text: list[str] = field(default_factory=list)
    equations: list[Equation] = field(default_factory=list)
    table: Table | None = None
    figure: str | None = None
    figure_request: dict | None = None
    figure_svg: str | None = None

    def equation(self, tag: str) -> Equation:
        for e in self.equations:
            if e.tag == tag:
                return e
        raise KeyError(tag)


@dataclass
class Section:
    """The steps of one body (``body`` set) or of the whole system (``body`` None)."""

    title: str
    body: str | None
    steps: list[Step] = field(default_factory=list)

    def step(self, kind: str) -> Step:
        for s in self.steps:
            if s.kind == kind:
                return s
        raise KeyError(kind)


@dataclass
class Explanation:
    """A worked solution.

    Attributes
    ----------
    title : str
    scene : str
    points : dict[str, str]
        body -> the point P of its moment equation.
    sections : list of Section
    symbol_latex : dict[sympy.Symbol, str]
        LaTeX names of the symbols (dotted rates, Greek letters).
    printer : solver.strprint.FastStrPrinter
        The sympy text of the expressions, each printed once for the whole explanation: the steps
        that put an expression's text in a table or compare two forms' lengths, and the text
        renderings, all print the same expressions.
    latex : dict
        Each expression's LaTeX (with :attr:`symbol_latex`'s names), printed once for the
        explanation: its Markdown and LaTeX renderings write the same equations alike.
    """

    title: str
    scene: str
    points: dict[str, str]
    sections: list[Section] = field(default_factory=list)
    symbol_latex: dict = field(default_factory=dict)
    printer: FastStrPrinter = field(default_factory=FastStrPrinter, repr=False, compare=False)
    latex: dict = field(default_factory=dict, repr=False, compare=False)

    def section(self, body: str | None) -> Section:
        for s in self.sections:
            if s.body == body:
                return s
        raise KeyError(body)

    def steps(self):
        for section in self.sections:
            yield from section.steps
