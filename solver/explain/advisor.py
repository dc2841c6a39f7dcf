"""The point advisor: which point P makes a body's moment equation simplest.

About any point X of a body's plane, rigidly attached to it (the body
extended), the generalized Euler equation is the one about the body's
reference point P0 plus r_P0/X x (Newton's equation), so its coefficients at
the state follow from the three rows already formulated::

    E_X = E_P0 + (r_P0 - r_X) x N          (Eq. 3 applied to Eq. 10)

For every candidate (named points, G, the element centres, the points where
joints act, and the intersections of two reactions' lines of action) the
advisor counts the unknowns that E_X contains at the state, finds the
smallest group of the body's equations (E_X alone, with Newton x or y, or all
three) that can be solved by itself ("decouples"), and states the kinematic
cost: whether a_X is known straight from a joint or the placement, or must be
derived first by Eq. 6/15 from such a point.

Ranking: among the points whose acceleration is known, fewest unknowns, then
the smallest solvable group, then the scene's order. A derived point with
fewer unknowns is reported alongside (the instant centre of two reactions'
lines, for example), with its cost.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import sympy as sp

from ..model.joints import xy
from .content import Step, Table

__all__ = ["Candidate", "rank_points", "advice_step", "unknowns_at_state", "unknowns_in_equations",
           "MAX_CANDIDATES"]

MAX_CANDIDATES = 60
"""Most candidate points examined per body (pairs of reaction lines grow quadratically)."""
_REL_ZERO = 1e-9
"""A coefficient counts as zero below this fraction of the largest coefficient of the body's rows
(round-off of the float evaluation is ~1e-15 relative; real coefficients are far above 1e-9)."""


@dataclass
class Candidate:
    """A candidate point P for a body's moment equation.

    Attributes
    ----------
    body, name : str
    position : tuple of float
        Fixed-frame position at the state [m].
    origin : str
        "named point", "mass centre", "element centre", "point of its joint" (C_<joint>), "intersection of ...".
    unknowns : list of str
        The unknowns its moment equation contains at the state.
    group : int or None
        Size of the smallest group of the body's equations, including this moment
        equation, that can be solved on its own (1: the moment equation alone); None if none.
    known : bool
        Whether a_P is known straight from a joint or the placement.
    cost : str
        The kinematic cost in words.
    """

    body: str
    name: str
    position: tuple
    origin: str
    unknowns: list = field(default_factory=list)
    group: int | None = None
    known: bool = False
    fixed: bool = False
    cost: str = ""
    needless: bool = False
    """Whether a_P is not needed at all: P is the mass centre, where the inertial term vanishes."""
    together: str = "it must be solved together with the other bodies' equations"
    """What the moment equation needs when no group of the body's equations is solvable alone."""

    @property
    def key(self):
        return (0 if self.known or self.needless else 1, len(self.unknowns), self.group or 99, 0 if self.fixed else 1)

    def reason(self) -> str:
        from .build import counted

        n = len(self.unknowns)
        parts = [f"the moment equation about {self.name} holds {counted(n, 'unknown')} ({', '.join(self.unknowns)})"]
        if self.group == 1:
            parts.append(f"it gives {'it' if n == 1 else 'them'} on its own")
        elif self.group:
            parts.append(f"with {counted(self.group - 1, 'Newton component')} it forms a group of {self.group} "
                         "equations solvable on its own")
        else:
            parts.append(self.together)
        parts.append(self.cost)
        return "; ".join(parts)


class _State(dict):
    """The state as symbol -> sympy Float (for ``xreplace``), with ``floats``: the same as Python floats,
    ``values``: the value of each subtree evaluated there so far (a body's coefficients and
    positions share their kinematics: :func:`solver.tree_value.tree_value`'s ``memo``), and
    ``forms``: per tuple of unknowns, the affine forms of the subtrees holding them
    (:func:`solver.tree_value.affine_value`'s ``forms``)."""

    def __init__(self, subs):
        super().__init__(subs)
        self.floats = {k: float(v) for k, v in subs.items()}
        self.values: dict = {}
        self.forms: dict = {}

    def affine(self, expr, unknowns: list) -> list:
        """:func:`solver.tree_value.affine_value` of ``expr`` at this state, sharing the walks."""
        from ..tree_value import affine_value

        return affine_value(expr, self.floats, unknowns, self.values, self.forms.setdefault(tuple(unknowns), {}))


def _numeric(expr, subs: _State) -> float:
    """``expr`` at the state ``subs``, in double precision: the advisor only compares these values
    against tolerances far above round-off (:data:`_REL_ZERO`)."""
    from ..tree_value import NotEvaluable, tree_value

    expr = sp.sympify(expr)
    try:
        value = tree_value(expr, subs.floats, memo=subs.values)
    except (NotEvaluable, KeyError, ZeroDivisionError, OverflowError):
        value = None
    if value is None or value.imag != 0:
        return float(expr.xreplace(subs))
    return value.real


def _rows(system, f, body, subs):
    """The body's Newton x, Newton y and moment rows about its P0 at the state: the formulation's,
    or, when P0's acceleration on the motion is not the placement's (a pivot the placement reaches
    along a loop: :meth:`System.point_kinematics`), the body's equations with that acceleration, as
    the worked solution writes them."""
    from ..formulations import _coefficients
    from ..formulations.newton_euler import body_equations

    P0 = f.points[body]
    a_P, placed = system.point_kinematics(body, P0)[2], system.point_acceleration(body, P0)
    if a_P is not placed and any(sp.expand(x - y) != 0 for x, y in zip(a_P, placed)):
        zero = {u: sp.Integer(0) for u in f.unknowns}
        eqs = dict(zip("xyE", body_equations(system, body, P0, a_P)))
        return {k: np.array([_numeric(a, subs) for a in _coefficients(e.expr, f.unknowns, zero)])
                for k, e in eqs.items()}
    idx = {"x": None, "y": None, "E": None}
    for i, e in enumerate(f.equations):
        if e.body != body:
            continue
        tail = e.name.split(": ")[-1]
        if tail == "Newton x":
            idx["x"] = i
        elif tail == "Newton y":
            idx["y"] = i
        elif tail.startswith("Euler"):
            idx["E"] = i
    return {k: _coefficients_at(f, i, subs) for k, i in idx.items()}


def _coefficients_at(f, i: int, subs: _State) -> np.ndarray:
    """The coefficients of the unknowns of ``f`` in its equation ``i`` at the state, by one walk of
    its tree (:func:`solver.tree_value.affine_value`); by row ``i`` of the formulation's matrix A
    where the walk does not go or gives no real number."""
    from ..tree_value import NotEvaluable

    try:
        values = subs.affine(f.equations[i].expr, list(f.unknowns))[1:]
    except (NotEvaluable, KeyError, TypeError, ValueError, ZeroDivisionError, OverflowError):
        values = None
    if values is None or any(v.imag != 0 for v in values):
        A, _ = f.linear_system()
        return np.array([_numeric(a, subs) for a in A.tolist()[i]])
    return np.array([v.real for v in values])


def _known_points(system, body, forces_at):
    """Names of points whose acceleration comes straight from a joint or the placement."""
    known = {name for name in forces_at}
    b = system.bodies[body]
    for name in b.point_names():
        if name in b.points and not b.points[name].is_instant and all(
                c == 0 for c in b.points[name].coords):
            known.add(name)  # the body frame's origin: the placement gives its motion
    if b.position is not None:
        known.add(b.position[0])
    return known


class _BodyRows:
    """A body's equations at the state, and the one decision of which unknowns a moment equation
    about a point X holds there (the advisor's ranking and the worked solution's step "Unknowns in
    the moment equation" both ask :meth:`unknowns_about`)."""

    def __init__(self, system, f, body: str, state):
        from .build import _walk_state

        self.subs = _walk_state(system, state)
        self.rows = _rows(system, f, body, self.subs)
        self.names = [str(u) for u in f.unknowns]
        self.scale = max(float(np.max(np.abs(r))) for r in self.rows.values()) or 1.0
        self.r0 = np.array([_numeric(x, self.subs) for x in xy(system.point_position(body, f.points[body]))])

    def position(self, r) -> np.ndarray:
        """A symbolic position at the state [m]."""
        return np.array([_numeric(x, self.subs) for x in xy(r)])

    def moment_row(self, at) -> np.ndarray:
        """Coefficients of the unknowns in the moment equation about the place ``at`` (Eq. 3)."""
        a = self.r0 - np.asarray(at, dtype=float)
        return self.rows["E"] + a[0] * self.rows["y"] - a[1] * self.rows["x"]

    def unknowns_about(self, at) -> list[str]:
        """The unknowns whose coefficient about ``at`` is not zero at the state (:data:`_REL_ZERO`)."""
        return self.held(self.moment_row(at))

    def held(self, row) -> list[str]:
        """The unknowns whose coefficient in ``row`` (one of the body's rows at the state, or a
        moment row) is not zero: above :data:`_REL_ZERO` of the body's largest coefficient."""
        return [n for n, v in zip(self.names, row) if abs(v) > _REL_ZERO * self.scale]


def _body_rows(system, f, body: str, state) -> _BodyRows:
    """The :class:`_BodyRows` of ``body`` in formulation ``f`` at ``state``, remembered by the system
    (the worked solution's steps and the advisor ask it for the same body and state; read only)."""
    key = ("body_rows", f.method, tuple(sorted(f.points.items())), body, tuple(state.q), tuple(state.qd), state.t)
    return system._memo(key, lambda: _BodyRows(system, f, body, state))


def unknowns_at_state(system, f, body: str, P: str, state) -> list[str]:
    """The unknowns the moment equation of ``body`` about its point ``P`` holds at ``state``: the
    same decision as the advisor's count for P (:class:`_BodyRows`)."""
    return unknowns_in_equations(system, f, body, P, state)["euler"]


def unknowns_in_equations(system, f, body: str, P: str, state) -> dict[str, list[str]]:
    """The unknowns each equation of ``body`` holds at ``state`` (tags ``euler``, the moment equation
    about ``P``, ``newton_x``, ``newton_y``), by the one decision of :class:`_BodyRows`: the step on
    the dropped unknowns, the advisor and the equations with the data entered all ask it."""
    rows = _body_rows(system, f, body, state)
    return {"euler": rows.unknowns_about(rows.position(system.point_position(body, P))),
            "newton_x": rows.held(rows.rows["x"]), "newton_y": rows.held(rows.rows["y"])}


def rank_points(system, body: str, state, f=None, parts=None) -> list[Candidate]:
    """The candidate points of ``body`` at ``state``, best first (see the module docstring);
    ``parts``: the body's (points, forces) when the worked solution has built them already."""
    from ..formulations import formulate
    from .build import _Points, _forces_on, crossing_name, crossing_words

    f = f or formulate(system, "generalized_euler", None)
    body_rows = _body_rows(system, f, body, state)
    subs, rows, scale = body_rows.subs, body_rows.rows, body_rows.scale

    if parts is None:
        points = _Points(system, body)
        parts = points, _forces_on(system, body, points)
    points, forces = parts
    reaction_at = {fc.point for fc in forces if fc.reaction is not None and fc.force is not None}
    known_names = _known_points(system, body, reaction_at)
    cands: list[Candidate] = []

    def add(name, pos, origin):
        pos = tuple(float(x) for x in pos)
        atol = 1e-9 * (1 + max(abs(x) for x in pos))
        for c in cands:  # numpy.allclose (rtol 1e-5) of two finite points, without its array machinery
            if all(abs(p - q) <= atol + 1e-05 * abs(q) for p, q in zip(c.position, pos)):
                return
        cands.append(Candidate(body, name, pos, origin))

    b = system.bodies[body]
    for name, r in points.named.items():
        origin = ("mass centre" if name == "G" else "element centre" if name.startswith("G_")
                  else points.origin.get(name, "named point"))
        add(name, np.array([_numeric(x, subs) for x in xy(r)]), origin)
    lines = []
    for fc in forces:
        if fc.reaction is not None and fc.force is not None:
            at = np.array([_numeric(x, subs) for x in xy(fc.at)])
            d = np.array([_numeric(x.xreplace({fc.unknown: 1}), subs) for x in xy(fc.force)])
            if np.linalg.norm(d) > 0:
                lines.append((fc.name, at, d / np.linalg.norm(d)))
    for i in range(len(lines)):
        for j in range(i + 1, len(lines)):
            if len(cands) >= MAX_CANDIDATES:
                break
            (n1, p1, d1), (n2, p2, d2) = lines[i], lines[j]
            M = np.column_stack([d1, -d2])
            if abs(np.linalg.det(M)) < 1e-9:
                continue
            s, _ = np.linalg.solve(M, p2 - p1)
            add(crossing_name(n1, n2), p1 + s * d1, crossing_words(n1, n2))
    g_at = cands_g[0].position if (cands_g := [c for c in cands if c.origin == "mass centre"]) else None
    if g_at is None and "G" in points.named:
        g_at = tuple(_numeric(x, subs) for x in xy(points.named["G"]))
    for c in cands:
        row = body_rows.moment_row(c.position)
        c.unknowns = body_rows.unknowns_about(c.position)
        c.group = _group(row, rows, scale)
        c.known = c.name in known_names
        if len(system.bodies) == 1:
            c.together = ("it must be solved together with the joints' closure equations" if system.closure
                          else "it must be solved together with the body's other equations")
        c.fixed = c.name in points.named and c.name in b.point_names() and _fixed(system, body, c.name)
        at_g = g_at is not None and all(abs(p - q) <= 1e-9 * (1 + abs(q)) for p, q in zip(c.position, g_at))
        if at_g and not c.fixed and not c.known:  # r_G/P = 0: Eq. 10 about G is M_G = I_G alpha, whatever a_P is
            at = "" if c.name == "G" else f"{c.name} is the mass centre: "
            c.cost = f"{at}the inertial term -r_G/{c.name} x m a_{c.name} vanishes, so a_{c.name} is not needed"
            c.needless = True
        elif c.fixed:
            c.cost = f"a_{c.name} = 0 (a fixed point): no inertial term, no extra kinematics"
        elif c.known:
            c.cost = f"a_{c.name} is known from the joints (no extra kinematics)"
        else:
            c.cost = f"a_{c.name} must be derived first (Eq. 6 from a point whose acceleration is known)"
    order = {c.name: i for i, c in enumerate(cands)}
    return sorted(cands, key=lambda c: (*c.key, order[c.name]))


def _fixed(system, body, name) -> bool:
    from .build import _zero

    a = system.point_kinematics(body, name)[2]
    x, y = xy(a)
    return _zero(x) and _zero(y)


def _group(row, rows, scale):
    """Smallest solvable group containing the moment row: unknowns <= equations, their columns of
    full rank (``numpy.linalg.matrix_rank``; a single unknown in a single row, whose finite entry is
    above the zero tolerance, has rank 1 without it)."""
    tol = _REL_ZERO * scale
    held = {id(r): np.abs(r) > tol for r in (row, rows["x"], rows["y"])}
    options = [(row,), (row, rows["x"]), (row, rows["y"]), (row, rows["x"], rows["y"])]
    for group in options:
        present = np.logical_or.reduce([held[id(r)] for r in group])
        count = int(present.sum())
        if not 0 < count <= len(group):
            continue
        if (count == 1 and len(group) == 1 and np.isfinite(row[present]).all()
                or np.linalg.matrix_rank(np.vstack(group)[:, present]) == count):
            return len(group)
    return None


def advice_step(system, state, parts: dict | None = None) -> Step:
    """The ranking as a step of the worked solution (all bodies); ``parts``: body -> (points,
    forces) as the body sections built them."""
    from .build import counted

    rows, text = [], []
    for body in system.bodies:
        ranked = rank_points(system, body, state, parts=(parts or {}).get(body))
        best = ranked[0]
        label = f" of {body}" if len(system.bodies) > 1 else ""
        text.append(f"Best point{label}: {best.name} — {best.reason()}.")
        fewer = [c for c in ranked if not (c.known or c.needless) and len(c.unknowns) < len(best.unknowns)]
        if fewer:
            c = min(fewer, key=lambda c: c.key[1:])
            text.append(f"{c.name} ({c.origin}) would leave only {counted(len(c.unknowns), 'unknown')}, "
                        f"but a_{c.name} must be derived first.")
        for c in ranked:
            rows.append((body, c.name, c.origin, str(len(c.unknowns)), ", ".join(c.unknowns),
                         str(c.group) if c.group else "-", "0 (fixed)" if c.fixed else "known" if c.known else "not needed (G)" if c.needless else "derive"))
    return Step("advice", "Which point P?", text,
                table=Table(("body", "point", "what", "unknowns", "which", "solvable group", "a_P"), tuple(rows)))


def advice_explanation(system):
    """The point advisor alone (``explain --suggest-point``) as an Explanation, so that every
    ``--format`` renders it: the contact regime that holds at the state (when the scene has
    contacts), then :func:`advice_step`. Contacts that hold a body redundantly leave its contact
    forces statically indeterminate: then no point is ranked, and the step says why."""
    from ..analyses.instant import assemble
    from ..analyses.regimes import system_in_regime
    from .build import _regime_step, latex_names
    from .content import Explanation, Section

    scene, section = system, Section("Choosing the point P", None)
    if scene.contacts:  # the points are ranked in the contact regime that holds at the state
        system, regime, warning, state = system_in_regime(scene, None)
        section.steps.append(_regime_step(scene, regime, warning))
        if regime is not None and regime.indeterminate:
            section.steps.append(Step("advice", "Which point P?", [
                "The sticking contacts hold redundantly, so their forces are statically "
                "indeterminate: no choice of P separates them, and no point is ranked."]))
    else:
        state = assemble(system)
    if not section.steps or section.steps[-1].kind != "advice":
        section.steps.append(advice_step(system, state))
    return Explanation(f"Point advisor: {scene.name}", scene.name, {}, [section], symbol_latex=latex_names(system))
