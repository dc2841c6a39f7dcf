"""The normal forces of slipping contacts in the worked equation of motion (QA 15 #1).

A contact that slides with friction loads its body with N (n - s mu_k d): the friction does work,
so N stays in the projection of the body equations on the partial velocities. To write the
equation of motion in the coordinates, their rates and accelerations alone, N must be expressed in
those and substituted. When one body equation holds N with no other unknown reaction,
:func:`solver.explain.build._constrained_motion_step` takes it from there; otherwise (a pin on the
body, a second slipping contact) the body equations holding these reactions are solved together
here, as a linear system in the reactions with the accelerations kept as symbols.

Any set of body equations solved for the reactions gives values that hold on the motion, but the
projected equations may then be identically satisfied (they would be sums of the very equations
used): the set is accepted only when, with the closure rows, the result still determines every
acceleration at the state.
"""
from __future__ import annotations

from itertools import combinations

import numpy as np
import sympy as sp

from .content import Equation, Term, slip_friction

__all__ = ["settle_slipping_reactions"]

MAX_ROWS_SOLVED = 4
"""At most this many body equations are solved together (Cramer's rule on symbols: the
determinants of larger systems are too long to show)."""

MAX_SETS_TRIED = 2000
"""At most this many sets of body equations are tried (a bound on the work for many bodies)."""

_ROW_WORDS = {"newton_x": "Newton x", "newton_y": "Newton y", "euler": "the moment equation"}


def _body_rows(expl) -> list[tuple[str, sp.Expr]]:
    """(words, residual) of each body's displayed Newton x, Newton y and moment equation, in the
    order of the bodies."""
    rows = []
    for section in expl.sections:
        if section.body is None:
            continue
        for kind, tag in (("newton", "newton_x"), ("newton", "newton_y"), ("euler", "euler")):
            try:
                residual = section.step(kind).equation(tag).residual
            except KeyError:
                continue
            rows.append((f"{_ROW_WORDS[tag]} of {section.body}", sp.expand(sp.sympify(residual))))
    return rows


def _matrix_at_state(system, rows, unknowns, state) -> np.ndarray:
    """The coefficients of ``unknowns`` in the expanded ``rows`` at the state."""
    from .build import _at_state

    return np.array([[float(_at_state(system, row.coeff(u), state)) for u in unknowns] for row in rows])


def _regular(A: np.ndarray) -> bool:
    """Whether the square matrix ``A`` is comfortably regular: its equilibrated condition number
    under the limit the solver itself uses (:data:`solver.analyses.instant.CONDITION_LIMIT`)."""
    from ..analyses.instant import CONDITION_LIMIT, condition_numbers

    return A.shape[0] == A.shape[1] and float(condition_numbers(A[None])[0]) <= CONDITION_LIMIT


def motion_determined(system, projected, rows, reactions, closure, state) -> bool:
    """Whether the ``projected`` equations (with ``reactions`` unknown), the closure rows at the
    acceleration level and the body equations ``rows`` determine every acceleration, the closure
    multipliers ``closure`` and ``reactions`` at the state: then the reactions solved from ``rows``
    and substituted leave equations of motion that still determine the motion."""
    accel = [sp.expand(system.D(system.D(r.expr))) for r in system.closure]
    unknowns = list(system.qdd) + list(closure) + list(reactions)
    return _regular(_matrix_at_state(system, list(projected) + accel + list(rows), unknowns, state))


def _cramer(rows, unknowns) -> dict:
    """The solution of the linear ``rows`` (residuals) for ``unknowns`` by Cramer's rule, each a
    quotient of two expanded determinants (what :func:`solver.display.tidy` shortens best)."""
    A = sp.Matrix([[row.coeff(u) for u in unknowns] for row in rows])
    b = sp.Matrix([-row.xreplace({u: 0 for u in unknowns}) for row in rows])
    from ..derivation import berkowitz_det

    det = sp.expand(berkowitz_det(A))
    out = {}
    for i, u in enumerate(unknowns):
        Ai = A.copy()
        Ai[:, i] = b
        out[u] = sp.expand(berkowitz_det(Ai)) / det
    return out


def solve_together(system, expl, state, projected, working, closure):
    """(values, words, others): the reactions ``working`` from the fewest body equations holding
    them and no unknown reaction besides the ones they solve for, chosen so that the motion stays
    determined (:func:`motion_determined`); ``values`` maps each of ``working`` to its expression
    in the coordinates, rates, accelerations and closure multipliers, ``words`` names the equations
    used, ``others`` the other reactions solved with them. None when no such set exists within
    :data:`MAX_ROWS_SOLVED` equations and :data:`MAX_SETS_TRIED` sets."""
    from .build import _unknowns_in

    unknown = [r.symbol for r in system.reactions if r.symbol not in set(closure)]
    rows = _body_rows(expl)
    held = [set(_unknowns_in(system, row, unknown)) for _, row in rows]
    tried = 0
    for k in range(len(working), min(MAX_ROWS_SOLVED, len(unknown)) + 1):
        for chosen in combinations(range(len(rows)), k):
            solved = set().union(*(held[i] for i in chosen))
            if len(solved) != k or not set(working) <= solved:
                continue
            tried += 1
            if tried > MAX_SETS_TRIED:
                return None
            order = [u for u in unknown if u in solved]
            exprs = [rows[i][1] for i in chosen]
            if not _regular(_matrix_at_state(system, exprs, order, state)):
                continue
            if not motion_determined(system, projected, exprs, order, closure, state):
                continue
            values = _cramer(exprs, order)
            return ({r: values[r] for r in working}, [rows[i][0] for i in chosen],
                    [u for u in order if u not in working])
    return None


def _listed(names) -> str:
    """``N``, ``N_A and N_B``, ``a, b and c``."""
    names = [str(n) for n in names]
    return names[0] if len(names) == 1 else f"{', '.join(names[:-1])} and {names[-1]}"


def settle_slipping_reactions(system, expl, state, projected, working, closure, known, eqs, text):
    """The slipping contacts' normal forces ``working`` as the equation of motion shows them:
    (known, eqs, text) to use in place of those the one-equation search found (``known``: reaction
    -> its expression; ``eqs``, ``text``: the equations and sentences that say where each is from).

    Kept as they are when that search found every one of them and the motion stays determined
    once they are substituted. Otherwise they are solved together (:func:`solve_together`); when no
    set of body equations gives them, none is substituted and the text says that the equation of
    motion still holds them and how they are found.
    """
    from ..display import tidy

    if not working:
        return known, eqs, text
    substituted = [sp.expand(e.xreplace(known)) for e in projected]
    if all(r in known for r in working) and motion_determined(system, substituted, [], [], closure, state):
        return known, eqs, text
    found = solve_together(system, expl, state, projected, working, closure)
    names = _listed(working)
    plural = len(working) > 1
    does = f"{names} {'do' if plural else 'does'} work through the slipping friction {slip_friction()}, so " \
           f"{'they stay' if plural else 'it stays'} in the projected equations"
    if found is None:
        return {}, [], [f"{does}. No set of body equations gives {'them' if plural else 'it'} in the coordinates, "
                        f"rates and accelerations alone here, so the equation of motion below still holds "
                        f"{names} (the reaction terms): {'they are' if plural else 'it is'} found with the "
                        "accelerations by solving the equations with the data entered, below."]
    values, words, others = found
    where = _listed(words)
    with_others = f", with {_listed(others)}," if others else ""
    text = [f"{does}; no body equation holds {'one of them' if plural else 'it'} without another unknown "
            f"reaction, so {where} {'are' if len(words) > 1 else 'is'} solved together for "
            f"{'them' if plural else 'it'}{with_others} as linear equations in the reactions (the accelerations "
            f"kept as symbols), and {'they are' if plural else 'it is'} substituted."]
    known = {r: sp.expand(v) for r, v in values.items()}
    eqs = [Equation((Term(r),), (Term(tidy(known[r])),), f"{r} from {where}", tag=f"from_newton:{r}", name=str(r))
           for r in working]
    return known, eqs, text
