"""The instantaneous solve: every acceleration and every reaction at a state.

:class:`NumericModel` turns a formulation's linear system A(q, q', t) x = b
into numpy functions (lambdified once, ``cse=True``) and solves it,
vectorised over any number of states. The singularity decision lives here,
once: the 1-norm condition number of the row- and column-equilibrated A,
computed from its inverse; above :data:`CONDITION_LIMIT` the configuration is
singular and :class:`SingularConfigurationError` names the joints and
coordinates the null vector involves. Nothing returns NaN.

:func:`assemble` completes a state: the dependent coordinates from the
closure equations (Newton's method from their guesses), the dependent rates
from their velocity form.
"""
from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field
from functools import lru_cache
from typing import Mapping

import numpy as np
import pint
import sympy as sp

from ..display import free_symbols_of
from ..errors import InputError, SingularConfigurationError
from ..kept import Kept
from ..strprint import lambdify
from ..units import Q_

__all__ = ["round_off_zeros", "round_off_bound", "sized_input", "CONDITION_LIMIT", "ROUND_OFF", "ERROR_BOUND_FACTOR", "SIGNIFICANT_ERROR", "entry_sizes", "refine",
           "error_bounds", "NumericModel", "refuse_zero_length", "InstantSolution", "State", "assemble", "solve_instant",
           "condition_numbers", "solve_with_estimate"]

CONDITION_LIMIT = 1e12
"""Above this condition number the answer is meaningless: SingularConfigurationError."""
_NEWTON_STEPS = 60
STRUCTURED_MIN_STATES = 4096
"""Batches of at least this many states are solved by the structured solve
(:mod:`solver.analyses.structured`); smaller ones, and single states, by the dense
path, whose set-up is cheaper."""


def _equilibrate(A: np.ndarray):
    """(As, row scales, column scales): A scaled by its columns' then its rows' largest entries."""
    with np.errstate(all="ignore"):  # (the arrays' own reductions: numpy's functions, less their wrapping)
        col = np.abs(A).max(axis=-2, keepdims=True)
        col = np.where(col > 0, col, 1.0)
        As = A / col
        row = np.abs(As).max(axis=-1, keepdims=True)
        row = np.where(row > 0, row, 1.0)
        As = As / row
    return As, row[..., 0], col[..., 0, :]


def condition_numbers(A: np.ndarray) -> np.ndarray:
    """Exact 1-norm condition numbers of the equilibrated A (a stack of matrices), by its inverse.

    Used where the exact value is reported (``precision``) and to name what a
    singular configuration involves; the solve itself uses the cheap estimate
    of :meth:`NumericModel.solve`. Degenerate matrices get an infinite condition.
    """
    As, _, _ = _equilibrate(np.asarray(A, dtype=float))
    bad = ~np.all(np.isfinite(As), axis=(-2, -1))
    n = As.shape[-1]
    As = np.where(bad[..., None, None], np.eye(n), As)
    out = np.full(As.shape[:-2], np.inf)
    for idx in np.ndindex(*As.shape[:-2]):
        if bad[idx]:
            continue
        try:
            inv = np.linalg.inv(As[idx])
        except np.linalg.LinAlgError:
            continue
        out[idx] = np.linalg.norm(As[idx], 1) * np.linalg.norm(inv, 1)
    return np.where(np.isfinite(out), out, np.inf)


def solve_with_estimate(A: np.ndarray, b: np.ndarray):
    """x and a cheap estimate of the equilibrated 1-norm condition number, from one LU
    (stacks of systems: A (..., n, n), b (..., n)); the one condition number of the
    solver's singularity decision (> :data:`CONDITION_LIMIT`: singular).

    The equilibrated system As (Dc^-1 x) = Dr b is solved together with two
    fixed +/-1 right-hand sides z; ||As||_1 max ||As^-1 z||_1 / ||z||_1 is a
    lower bound of cond_1(As) that is rarely off by more than a small factor
    (Hager's first step), at the cost of two extra columns.
    """
    n = A.shape[-1]
    As, row, col = _equilibrate(A)
    finite = np.array(np.isfinite(As).all(axis=(-2, -1)) & np.isfinite(b).all(axis=-1), dtype=bool)
    rhs = np.concatenate([(b / row)[..., None], np.broadcast_to(_estimate_columns(n), As.shape[:-2] + (n, 2))],
                         axis=-1)
    if not finite.all():
        As = np.where(finite[..., None, None], As, np.eye(n))
    try:
        with np.errstate(all="ignore"):
            sol = np.linalg.solve(As, rhs)
    except np.linalg.LinAlgError:  # an exactly singular member: find which, one by one
        sol = np.full(rhs.shape, np.nan)
        for idx in np.ndindex(*As.shape[:-2]):
            try:
                sol[idx] = np.linalg.solve(As[idx], rhs[idx])
            except np.linalg.LinAlgError:
                finite[idx] = False
    with np.errstate(all="ignore"):
        norm_A = np.abs(As).sum(axis=-2).max(axis=-1)
        est = np.abs(sol[..., 1:]).sum(axis=-2).max(axis=-1) / n
        cond = norm_A * est
        x = sol[..., 0] / col
    cond = np.where(finite & np.isfinite(cond) & np.isfinite(x).all(axis=-1), cond, np.inf)
    return x, cond


@lru_cache(maxsize=64)
def _estimate_columns(n: int) -> np.ndarray:
    """The two fixed +/-1 right-hand sides z (n, 2) of :func:`solve_with_estimate`'s estimate
    (read-only, made once per size)."""
    z = np.ones((n, 2))
    z[1::2, 0] = -1.0
    z[: n // 2, 1] = -1.0
    z.setflags(write=False)
    return z


ROUND_OFF = 2.0 ** -53
"""float64's unit round-off u (1.1e-16)."""
ERROR_BOUND_FACTOR = 16.0
"""The first-order bound u * |A^-1| (S_A |x| + S_b) counts one rounding per size; the evaluation
chains a few operations per term. Measured on a bar on a pin (tests/data/multibody/pin_bar.toml:
7 angles from 1 to 200 deg, rates 1e2 .. 1e9 rad/s, about O, G and A, mass centre and Lagrange;
515 solves against -1.5 g sin(theta)/L), the error reached 0.96 of the unscaled bound where both
are a unit in the last place, 0.69 where cancellation lost every digit (about A at 1e9 rad/s);
16 leaves a margin of 16 over that. With the sizes of the walked entries and the exact inverse's
|A^-1| (QA 17 #3), 294 such solves (7 angles, rates 1e2 .. 1e20 rad/s, about O, G and A and the
mass-centre route) erred by at most 0.25 of the unscaled bound where they erred beyond a few ulp."""
def round_off_bound(size: float) -> float:
    """The float64 error bound of one value computed from terms whose sizes add up to ``size``
    (:class:`solver.tree_value.Sized`), by the rule of :func:`error_bounds`: u size times
    :data:`ERROR_BOUND_FACTOR`. A value no larger than it is 0 to round-off (a direction's
    component, an equation's known side at rest)."""
    return ERROR_BOUND_FACTOR * ROUND_OFF * size


def sized_input(value: float, bound: float):
    """``value``, known to within ``bound``, as an input of :func:`entry_sizes`: a size whose
    round-off bound (:func:`round_off_bound`) is at least ``bound``, so that what is computed from
    it carries its error (times its coefficient) besides its own round-off."""
    from ..tree_value import Sized

    return Sized(float(value), abs(float(value)) + bound / (ERROR_BOUND_FACTOR * ROUND_OFF))


def singular_to_round_off(A: np.ndarray, b: np.ndarray, size_A: np.ndarray) -> "np.ndarray | None":
    """The singularity decision (:data:`CONDITION_LIMIT`) on ``A`` with its entries that are 0 to
    round-off set to 0 (no larger than their own bound, :func:`round_off_bound` of their terms'
    sizes ``size_A``): that matrix where it is singular, else None.

    The equilibrated condition number of ``A`` itself cannot see a column of round-off: the
    scaling makes 1e-16 beside terms of 3 an entry like any other (a bar's angle sin(3 theta) at
    theta = 30 deg, d(angle)/d(theta) = 3 cos(90 deg) computed as 1.8e-16)."""
    small = (np.abs(A) <= round_off_bound(size_A)) & (A != 0)
    if not small.any():
        return None
    A0 = np.where(small, 0.0, A)
    _, cond = solve_with_estimate(A0, b)
    return A0 if not cond <= CONDITION_LIMIT else None


SIGNIFICANT_ERROR = 1e-6
"""An unknown whose error bound exceeds this fraction of its size is flagged: its sixth significant
digit, the last `solve` prints, may be wrong."""


def entry_sizes(entries, point: Mapping) -> np.ndarray | None:
    """The size of the round-off of each expression of ``entries`` evaluated in float64 at ``point``
    (symbol -> float): :data:`solver.tree_value.SIZED`, the sum of its terms' sizes, so that a
    cancelling sum (omega**2 terms of 1e16 leaving 7) has a size far above its value. None where
    the walk cannot evaluate an expression (a function it does not know: then nothing is bounded).
    A value of ``point`` may be a :class:`~solver.tree_value.Sized` already (an input with a round-off
    of its own: a solved acceleration, :func:`sized_input`)."""
    from ..tree_value import SIZED, NotEvaluable, Sized, tree_value

    memo: dict = {}
    at = {k: v if isinstance(v, Sized) else Sized.of(v) for k, v in point.items()}
    sizes = []
    for e in entries:
        try:
            sizes.append(tree_value(e, at, SIZED, memo).size)
        except (NotEvaluable, KeyError, TypeError, ValueError, ZeroDivisionError, OverflowError):
            return None
    return np.array(sizes, dtype=float)


def refine(A: np.ndarray, b: np.ndarray, x: np.ndarray) -> np.ndarray:
    """``x`` after one step of iterative refinement, x + A^-1 (b - A x) (one system, float64).

    Elimination mixes the rows: at large rates a pin's reactions are 1e15 times the angular
    acceleration and their round-off fell into it (a bar at 1e8 rad/s gave -6.93 rad/s**2 for
    -7.3575, though no equation of it cancels). One step of refinement makes the solve
    componentwise accurate (Skeel 1980), leaving only the round-off of A and b themselves, which
    :func:`error_bounds` bounds."""
    with np.errstate(all="ignore"):
        try:
            dx = np.linalg.solve(A, b - A @ x)
        except np.linalg.LinAlgError:
            return x
    return x + dx if np.all(np.isfinite(dx)) else x


EXACT_INVERSE_MAX = 24
"""The largest system whose |A^-1| :func:`error_bounds` takes from the exact inverse (rational
arithmetic: about 0.1 s for 20 dense unknowns, far less for a mechanism's sparse ones)."""


def exact_inverse(A: np.ndarray) -> np.ndarray | None:
    """The inverse of the float64 matrix ``A`` computed in rational arithmetic, rounded to float64
    (each entry within u of the exact inverse's; an entry that is 0 exactly, as the equations'
    structure makes it, stays 0), or None where A is exactly singular or larger than
    :data:`EXACT_INVERSE_MAX`.

    Elimination in float64 leaves round-off of about u |A^-1| |A| |A^-1| where the exact inverse is
    0: at large rates that couples an unknown to equations whose terms are omega**2 times its own
    (a pendulum's reactions at 1e13 rad/s), and the bound grew as omega**2 for an answer that
    stays exact.

    Kept per process by the matrix's values (:data:`_EXACT_INVERSES`, read-only): the solve at rest
    that scales an unknown (:func:`_scale_at_rest`) has the matrix of the solve at the state, whose
    entries hold no rate, and a scene solved again has it too."""
    n = A.shape[0]
    if n > EXACT_INVERSE_MAX or not np.all(np.isfinite(A)):
        return None
    A = np.array(A, dtype=float)
    return _EXACT_INVERSES.get((A.shape, A.tobytes()), lambda: _rational_inverse(A))


def _rational_inverse(A: np.ndarray) -> np.ndarray | None:
    """:func:`exact_inverse` of a finite square matrix, computed (read-only)."""
    from fractions import Fraction

    from sympy import QQ
    from sympy.polys.matrices import DomainMatrix
    from sympy.polys.matrices.exceptions import DMNonInvertibleMatrixError

    n = A.shape[0]
    M = DomainMatrix([[QQ(Fraction(float(v))) for v in row] for row in A], (n, n), QQ)
    try:
        inv = M.inv()
    except (DMNonInvertibleMatrixError, ZeroDivisionError):
        return None
    out = np.array([[float(v) for v in row] for row in inv.to_list()], dtype=float)
    out.setflags(write=False)
    return out


_EXACT_INVERSES = Kept(256)
""":func:`exact_inverse`'s results by (shape, bytes) of the matrix (:class:`solver.kept.Kept`)."""


def error_bounds(A: np.ndarray, b: np.ndarray, x: np.ndarray, size_A: np.ndarray, size_b: np.ndarray) -> np.ndarray:
    """A bound on each unknown's float64 error, from the round-off of evaluating A and b.

    The equations' residual at the exact answer errs by about u (S_A |x| + S_b) (sizes from
    :func:`entry_sizes`), so x errs by |A^-1| times that, times :data:`ERROR_BOUND_FACTOR`.
    Where the equations' terms cancel (large rates), the bound is far above u |x|: the digits
    lost are log10(bound / (u |x|)). |A^-1| is the exact inverse's (:func:`exact_inverse`;
    float64's where that is not computed)."""
    with np.errstate(all="ignore"):
        inv = exact_inverse(A)
        inv = np.linalg.inv(A) if inv is None else inv
        return ERROR_BOUND_FACTOR * ROUND_OFF * (np.abs(inv) @ (size_A @ np.abs(x) + size_b))


class NumericModel:
    """Numeric, numpy-vectorised form of a formulation.

    Methods take arrays (or scalars) of each free coordinate, each rate and t,
    broadcast together; results are SI.
    """

    def __init__(self, formulation):
        f = formulation
        sysm = f.system
        self.formulation = f
        self.system = sysm
        self.label = sysm.label
        self.n = len(f.equations)
        self.shape = (len(f.equations), len(f.unknowns))  # (A's, without building it: :meth:`entries`)
        self.names = tuple(str(u) for u in f.unknowns)
        self.owner = {}
        for c in sysm.free:
            self.owner[str(c.qdd)] = f"coordinate {c.name}"
        for j in sysm.joints:
            for r in j.reactions:
                self.owner[r.name] = f"joint {j.name!r} ({j.kind})"
        values = sysm.si_values()
        params = sorted(values, key=str)
        self._param_values = tuple(values[p] for p in params)
        self.args = (*sysm.q, *sysm.qd, sysm.t)
        stray = free_symbols_of([e.expr for e in f.equations]) - set(self.args) - set(params) - set(f.unknowns)
        if stray:
            raise InputError(f"{self.label}: undefined name(s) {', '.join(sorted(map(str, stray)))} in the scene's expressions")
        self._entries, self._params = None, tuple(params)
        self._f = None  # compiled on first use (:meth:`_compiled`)
        self._structured = None
        self.walked = False

    def entries(self) -> list:
        """The entries of A, row by row, then those of b (``Formulation.linear_system``), built on
        first use: a model asked for one state only (:meth:`solve` with ``once``) walks the
        equations themselves (:meth:`_walked`)."""
        if self._entries is None:
            A, b = self.formulation.linear_system()
            self._entries = [sp.sympify(e) for e in list(A) + list(b)]
        return self._entries

    def _compiled(self):
        """The entries of A and b as one numpy function (``lambdify`` with common subexpressions),
        built on first use: a model asked for one state only (:meth:`solve` with ``once``) never
        pays for it."""
        if self._f is None:
            self._f = lambdify((*self.args, *self._params), self.entries(), "numpy", cse=True)
        return self._f

    def _walked(self, arrays):
        """The entries of A and b at the one state of ``arrays``, each equation's coefficients and rest
        by one walk of its tree (:func:`solver.tree_value.affine_value`, shared subtrees once), or
        None where the walk cannot go (then the compiled function serves). What numpy would give as
        inf or nan, or a complex number gives, is nan (a singular system, as the compiled path
        decides it): for a whole equation when its walk divides by zero or overflows."""
        from ..tree_value import NotEvaluable, real_value

        point = dict(zip(self._params, self._param_values))
        point.update((a, float(v.reshape(-1)[0])) for a, v in zip(self.args, arrays))
        n = len(self.formulation.unknowns)
        rows, rests = [], []
        try:
            for values in self._walks(point):
                values = [complex(math.nan)] * (n + 1) if values is None else values
                rows += [real_value(v) for v in values[1:]]
                rests.append(real_value(-values[0]))
        except (NotEvaluable, KeyError, TypeError, ValueError):
            return None
        return rows + rests

    def _walks(self, point: dict, *arithmetic):
        """Each equation's [rest, coefficients...] at ``point`` by one walk of its tree
        (:func:`solver.tree_value.affine_value`, in ``arithmetic``; subtrees the equations share
        walked once), or None for an equation whose walk divides by zero or overflows; the
        walk's other refusals (:class:`~solver.tree_value.NotEvaluable`...) are raised."""
        from ..tree_value import affine_value

        memo: dict = {}
        forms: dict = {}
        unknowns = list(self.formulation.unknowns)
        for e in self.formulation.equations:
            try:
                yield affine_value(e.expr, point, unknowns, memo, forms, *arithmetic)
            except (ZeroDivisionError, OverflowError):
                yield None

    def matrices(self, q, qd, t=0.0, once: bool = False):
        """(A, b) at the states: q and qd are sequences (one array per free coordinate).
        ``once``: a single state asked for once (:meth:`solve`)."""
        arrays = [np.asarray(v, dtype=float) for v in (*q, *qd, t)]
        arrays = np.broadcast_arrays(*arrays) if arrays else arrays
        shape = arrays[0].shape if arrays else ()
        vals = self._walked(arrays) if once and arrays and arrays[0].size == 1 else None
        self.walked = vals is not None  # how the last matrices were evaluated (:meth:`_sizes`)
        if vals is None:
            with np.errstate(all="ignore"):
                vals = self._compiled()(*arrays, *self._param_values)
        m, k = self.shape
        if not shape:  # one state: its values as one array (each converted as an assignment converts it)
            try:
                return np.array(vals[: m * k], dtype=float).reshape(m, k), np.array(vals[m * k:], dtype=float)
            except ValueError:
                pass
        A = np.empty(shape + (m * k,))
        b = np.empty(shape + (m,))
        for i, v in enumerate(vals[: m * k]):
            A[..., i] = v
        for i, v in enumerate(vals[m * k:]):
            b[..., i] = v
        return A.reshape(shape + (m, k)), b

    def solve(self, q, qd, t=0.0, once: bool = False, bounds: bool = False) -> dict[str, np.ndarray]:
        """Every unknown (SI) at the given states, with ``condition_number``.

        ``once``: the caller solves this one state once (an instantaneous solve, one contact
        regime tried): its matrices come from one walk over the expressions (:meth:`_walked`,
        tens of microseconds) instead of compiled code (``lambdify``, milliseconds to build), and
        the answer is refined once (:func:`refine`). Both are double precision; their results
        agree to round-off, not always to the last bit. ``bounds`` (with ``once``): also
        ``error_bound``, an array of each unknown's error bound (:func:`error_bounds`), or None
        where the sizes cannot be evaluated.

        Raises
        ------
        SingularConfigurationError
            When any state's system is singular or its condition number exceeds
            :data:`CONDITION_LIMIT`.
        """
        if self.shape[0] != self.shape[1]:
            raise InputError(f"{self.label}: the equations are not square ({self.shape[0]} equations, "
                             f"{self.shape[1]} unknowns)")
        shape = np.broadcast_shapes(*(np.shape(v) for v in (*q, *qd, t)))  # (no arrays made for one state)
        if math.prod(shape) >= STRUCTURED_MIN_STATES and self.structured().usable:
            x, cond = self._solve_structured(np.broadcast_arrays(*[np.asarray(v, dtype=float) for v in (*q, *qd, t)]))
            out = {name: x[i].reshape(shape) for i, name in enumerate(self.names)}
            out["condition_number"] = cond.reshape(shape)
            return out
        A, b = self.matrices(q, qd, t, once)
        x, cond = self._solve_with_estimate(A, b)
        if np.any(~(cond <= CONDITION_LIMIT)):
            self.singular(q, qd, t, A, cond)
        if once and A.ndim == 2:
            x = refine(A, b, x)
        out = {name: x[..., i] for i, name in enumerate(self.names)}
        out["condition_number"] = cond
        if bounds and once and A.ndim == 2:
            sizes = self._sizes(q, qd, t, walked=self.walked)
            if sizes is not None:
                self._refuse_singular_to_round_off(A, b, sizes[0], q, qd, t)
            out["error_bound"] = None if sizes is None else error_bounds(A, b, x, *sizes)
        return out

    def _refuse_singular_to_round_off(self, A: np.ndarray, b: np.ndarray, size_A: np.ndarray, q, qd, t) -> None:
        """The singularity decision with the matrix's entries that are 0 to round-off taken as 0
        (no larger than their own bound, :func:`round_off_bound` of their terms' ``size_A``).

        The equilibrated condition number cannot see a column whose entries are all round-off:
        the scaling makes 1e-16 beside terms of 3 an entry like any other. A bar whose angle is
        sin(3 theta) has at theta = 30 deg d(angle)/d(theta) = 3 cos(90 deg), exactly 0,
        computed as 1.8e-16: theta_ddot came out 3.5e16 rad/s**2 with bounds far above every
        unknown. Such a matrix is singular to float64's precision: decided here as
        :meth:`singular` decides it, by the same condition limit."""
        A0 = singular_to_round_off(A, b, size_A)
        if A0 is not None:
            self.singular(q, qd, t, A0, np.asarray(math.inf))

    def _refuse_round_off(self, M: np.ndarray, q, qd, t: float) -> None:
        """Raise :class:`SingularConfigurationError` saying that the matrix ``M`` (found singular at
        the state q, qd, t) is round-off, when the terms of its entries cancel beyond float64's
        digits (about a bar's end at 3e8 rad/s, m L omega**2 terms of 1e17 leave 0.5) and do not
        at rest: the configuration is not the cause, and no other message should say it is. Where
        they cancel at rest too (a bar's angle sin(3 theta) at theta = 30 deg, whose
        d(angle)/d(theta) is 3 cos(90 deg)), the configuration is the cause."""
        if not (any(np.asarray(qd, dtype=float).ravel()) and self._cancels(M, q, qd, t)):
            return
        rest = [0.0] * len(qd)
        if self._cancels(self.matrices(q, rest, t)[0], q, rest, t):
            return
        sizes = self._sizes(q, qd, t)
        state = _state_text(self.system, q, qd, t, ())
        raise SingularConfigurationError(
            f"{self.label}: at {state} (rates {', '.join(f'{c.name}_dot = {v:.3g} {c.unit}/s' for c, v in zip(self.system.free, qd))}) "
            f"the terms of the equations' matrix cancel beyond float64's digits (terms up to {np.nanmax(sizes[0]):.3g} "
            "leave far smaller entries): the matrix is round-off there, so the motion cannot be solved in float64; "
            "this is no singular configuration (about another point, or by another --method, the terms may not cancel)")

    def _cancels(self, M: np.ndarray, q, qd, t) -> bool:
        """Whether the entries of a column of ``M`` (at q, qd, t) are far below their terms'
        round-off sizes (a thousandth of the column's largest entry is round-off)."""
        sizes = self._sizes(q, qd, t)
        if sizes is None:
            return False
        lost = ROUND_OFF * sizes[0] / np.maximum(np.max(np.abs(M), axis=0), 1e-300)  # per entry, by its column
        return bool(np.nanmax(lost, initial=0.0) > 1e-3)

    def _sizes(self, q, qd, t, walked: bool = False):
        """(S_A, S_b): the round-off sizes of A's and b's entries at one state, as they were
        evaluated: ``walked``, by the walk of :meth:`_walked` (:meth:`_walked_sizes`), else from
        the symbolic entries (:func:`entry_sizes`)."""
        point = dict(zip(self._params, self._param_values))
        point.update((a, float(np.asarray(v, dtype=float).reshape(-1)[0])) for a, v in zip(self.args, (*q, *qd, t)))
        sizes = self._walked_sizes(point) if walked else entry_sizes(self.entries(), point)
        if sizes is None or not np.all(np.isfinite(sizes)):
            return None
        m, k = self.shape
        return sizes[: m * k].reshape(m, k), sizes[m * k:]

    def _walked_sizes(self, point: dict) -> np.ndarray | None:
        """The round-off sizes of the entries :meth:`_walked` computes at ``point``: the same walk in
        :data:`solver.tree_value.SIZED`. A coefficient the walk collects term by term has the sizes
        of those terms only, not those of the symbolic entry (``linear_system`` writes a term's
        coefficient as t(u = 1) - t(u = 0), whose omega**2 parts cancel exactly: a sliding bar's
        coefficient of 30.9 sized 4e26 at 1e12 rad/s). None where the walk cannot go."""
        from ..tree_value import SIZED, NotEvaluable, Sized

        rows, rests = [], []
        try:
            for values in self._walks({k: Sized.of(v) for k, v in point.items()}, SIZED):
                if values is None:
                    return None
                rows += [v.size for v in values[1:]]
                rests.append(values[0].size)
        except (NotEvaluable, KeyError, TypeError, ValueError):
            return None
        return np.array(rows + rests, dtype=float)

    def structured(self):
        """The :class:`~solver.analyses.structured.StructuredSolver` of this model (built once).

        Its matrix is built from the equations directly, A_ij = d e_i / d x_j
        (exact, the equations being affine in the unknowns), with the
        parameters' values substituted, so that constant entries are known."""
        if self._structured is None:
            from .structured import StructuredSolver

            f = self.formulation
            values = {p: sp.Float(v) for p, v in self.system.si_values().items()}
            zero = {u: sp.Integer(0) for u in f.unknowns}
            exprs = [e.expr.xreplace(values) for e in f.equations]
            A = sp.Matrix([[e.diff(u) for u in f.unknowns] for e in exprs])
            b = sp.Matrix([-e.xreplace(zero) for e in exprs])
            self._structured = StructuredSolver(A, b, self.args, self._sample_states())
        return self._structured

    def _sample_states(self, k: int = 64):
        """``args`` at k states spread around the scene's: angles anywhere, lengths
        within half their value (at least 0.1 m), rates up to 3 per second, t over 1 s."""
        rng = np.random.default_rng(20261123)
        sysm = self.system
        q = [rng.uniform(-np.pi, np.pi, k) if c.kind == "angle"
             else c.value + rng.uniform(-1, 1, k) * max(0.5 * abs(c.value), 0.1) for c in sysm.free]
        qd = [rng.uniform(-3, 3, k) for _ in sysm.free]
        return [*q, *qd, sysm.time + rng.uniform(0, 1, k)]

    def _solve_structured(self, arrays):
        """x (n, N) and the condition estimate (N,) of flat states by the structured
        solve; the states it does not certify go through the dense path (and its
        singularity decision)."""
        flat = [a.ravel() for a in arrays]
        x, cond, ok = self.structured().solve(flat)
        ok &= cond <= CONDITION_LIMIT  # the decision that a state is singular is the dense path's
        if not np.all(ok):
            redo = np.flatnonzero(~ok)
            k = len(self.system.q)
            sub_q, sub_qd, sub_t = [a[redo] for a in flat[:k]], [a[redo] for a in flat[k:2 * k]], flat[-1][redo]
            A, b = self.matrices(sub_q, sub_qd, sub_t)
            xs, cs = self._solve_with_estimate(A, b)
            if np.any(~(cs <= CONDITION_LIMIT)):
                self.singular(sub_q, sub_qd, sub_t, A, cs)
            x[:, redo], cond[redo] = xs.T, cs
        return x, cond

    def _solve_with_estimate(self, A, b):
        return solve_with_estimate(A, b)

    def singular(self, q, qd, t, A, cond):
        """Raise SingularConfigurationError for the worst state, naming what the null vector involves."""
        idx = np.unravel_index(int(np.argmax(cond)), cond.shape) if cond.ndim else ()
        refuse_zero_length(self.system, q, qd, t, idx)
        M = A[idx]
        self._refuse_round_off(M, [_at(v, idx) for v in q], [_at(v, idx) for v in qd], _at(t, idx))
        c = float(condition_numbers(M[None])[0]) if np.all(np.isfinite(M)) else math.inf
        c = max(c, float(cond[idx]))
        involved = []
        if np.all(np.isfinite(M)):
            colscale = np.max(np.abs(M), axis=0)
            colscale[colscale == 0] = 1.0
            _, _, vt = np.linalg.svd(M / colscale)
            v = np.abs(vt[-1])
            for name, weight in sorted(zip(self.names, v), key=lambda p: -p[1]):
                if weight > 0.1 * v.max() and self.owner[name] not in involved:
                    involved.append(self.owner[name])
        if not any(o.startswith("joint") for o in involved):
            joints = [f"joint {j.name!r} ({j.kind})" for j in self.system.joints]
            if joints:
                involved.append("with " + ", ".join(joints))
        state = _state_text(self.system, q, qd, t, idx)
        cond_text = "infinite" if not math.isfinite(c) else f"{c:.3g}"
        raise SingularConfigurationError(
            f"{self.label}: singular configuration at {state}: the equations of "
            f"{', '.join(involved) or 'the system'} do not determine the motion "
            f"(condition number {cond_text} > {CONDITION_LIMIT:.0e})"
        )


def _at(v, idx) -> float:
    """The float of one state ``idx`` of a state array (or of a scalar)."""
    return float(np.asarray(v, dtype=float)[idx] if np.ndim(v) else v)


def refuse_zero_length(system, q, qd, t, idx=(), within: float = 1e-12) -> None:
    """Raise SingularConfigurationError when a spring's or a damper's two points coincide at
    the state (state ``idx`` of arrays q, qd, t; or scalars): there its line, and so its force,
    has no direction (0/0 in the equations' right-hand side), whatever the joints do.

    A length of at most ``within`` [m] counts as zero. The default, 1e-12 m (a picometre: far
    below any scene's scale, far above the round-off of a position of metres), names the cause of
    a system found singular; a caller that asks before any solve (``eom``, whose expressions are
    defined at every length but zero) passes 0."""
    values = dict(system.si_values())
    values.update({s: _at(v, idx) for s, v in zip((*system.q, *system.qd), (*q, *qd))})
    values[system.t] = _at(t, idx)
    zero = []
    for load in system.loads:
        length = load.line_length(system)
        if length is not None and abs(system._num(system.prescribe(length), values)) <= within:  # nan: no
            zero.append(f"{load.kind} {load.name!r}")
    if zero:
        one = len(zero) == 1
        raise SingularConfigurationError(
            f"{system.label}: singular configuration at {_state_text(system, q, qd, t, idx)}: "
            f"{' and '.join(zero)} {'has' if one else 'have'} zero length there, so the direction of "
            f"{'its' if one else 'their'} force is undefined")


def _state_text(system, q, qd, t, idx) -> str:
    parts = []
    for c, v in zip(system.free, q):
        val = _at(v, idx)
        parts.append(f"{c.name} = {math.degrees(val):.6g} deg" if c.kind == "angle" else f"{c.name} = {val:.6g} m")
    if system.motion_subs:
        tv = _at(t, idx)
        parts.append(f"t = {tv:.6g} s")
    return ", ".join(parts) or "the state"


# --------------------------------------------------------------------------- the state
@dataclass
class State:
    """A complete state: every free coordinate's value and rate, and t (SI)."""

    q: tuple[float, ...]
    qd: tuple[float, ...]
    t: float = 0.0


def _closure_functions(system):
    from ..model.system import derivative

    def build():
        rows = [r.expr for r in system.closure]
        dep = [c.q for c in system.dependent]
        args = (*system.q, system.t)
        values = system.si_values()
        params = sorted(values, key=str)
        pv = [values[p] for p in params]
        if not rows:
            return None
        Phi = sp.Matrix(rows)
        # the Jacobian and d/dt by the model's derivative (sympy's, remembered per process: a scene
        # loaded again differentiates the same rows), row by row as Matrix.jacobian lists them
        J = [derivative(r, x) for r in Phi for x in system.q]
        Pt = [derivative(r, system.t) for r in Phi]
        fPhi = lambdify((*args, *params), list(Phi), "numpy", cse=True)
        fJ = lambdify((*args, *params), J, "numpy", cse=True)
        fPt = lambdify((*args, *params), Pt, "numpy", cse=True)
        return fPhi, fJ, fPt, pv, len(rows), dep
    return system._memo("closure_numeric", build)


def assemble(system, q=None, qd=None, t=None) -> State:
    """Complete a state: solve the dependent coordinates and rates.

    Parameters
    ----------
    q, qd : sequences of float, optional
        Values and rates of the free coordinates (dependent ones are guesses
        and are ignored for rates); default the scene's state.
    t : float, optional
        Time [s]; default the scene's.

    Raises
    ------
    InputError
        The closure equations cannot be satisfied near the guesses, or the
        state violates a closure equation that no dependent coordinate can
        absorb (inconsistent prescribed motion).
    """
    free = system.free
    q = np.array([c.value for c in free] if q is None else q, dtype=float)
    qd = np.array([c.rate for c in free] if qd is None else qd, dtype=float)
    t = system.time if t is None else float(t)
    funcs = _closure_functions(system)
    if funcs is None:
        return State(tuple(q), tuple(qd), t)
    fPhi, fJ, fPt, pv, m, _ = funcs
    n = len(free)
    dep, ind, turns = _closure_indices(system)
    guesses = q  # (_newton_closure works on a copy)
    q, res = _newton_closure(funcs, q, t, dep, turns)
    if not _closes(res, q):
        _refuse_unclosed(system, funcs, guesses, t, dep, res)
    # each angle in the turn of its guess: a whole turn is a quotient past one half (or nan)
    if any(not abs((float(q[i]) - float(guesses[i])) / (2 * math.pi)) <= 0.5 for i in turns):
        whole = np.round((q[turns] - guesses[turns]) / (2 * math.pi))
        if np.any(whole):  # (else q is that already, and closes)
            near = q.copy()
            near[turns] -= 2 * math.pi * whole
            if _closes(np.array(fPhi(*near, t, *pv), dtype=float), near):
                q = near
    J = np.array(fJ(*q, t, *pv), dtype=float).reshape(m, n)
    Pt = np.array(fPt(*q, t, *pv), dtype=float)
    if dep:
        _check_closure_jacobian(system, J[:, dep], q, t)
        rhs = -(Pt + J[:, ind] @ qd[ind])
        sol, *_ = np.linalg.lstsq(J[:, dep], rhs, rcond=None)
        qd[dep] = sol
    return State(tuple(q), tuple(qd), t)


def _closure_indices(system) -> tuple[list[int], list[int], list[int]]:
    """(dependent, independent, dependent angles): indices into ``system.free``, as :func:`assemble`
    takes them at every state (cached on the system)."""
    def build():
        free = system.free
        dep = [i for i, c in enumerate(free) if c.dependent]
        return dep, [i for i, c in enumerate(free) if not c.dependent], [i for i in dep if free[i].kind == "angle"]
    return system._memo("closure_indices", build)


_MAX_ANGLE_STEP = 1.0
"""The largest change of a dependent angle in one Newton step [rad]: from a guess where the closure's
Jacobian vanishes (slider_crank's rod at phi = 90 deg, J = l cos(phi) = 6e-17) the full step was
1e16 rad, an angle with no digit left, which then "closed" the loop to the tolerance of its size."""


def _newton_closure(funcs, q, t, dep, angles=()):
    """(q, residual): Newton's method (Gauss-Newton where the rows outnumber ``dep``) on the
    closure equations in the dependent coordinates ``dep`` (indices), from ``q``; a step that
    would turn one of the dependent ``angles`` (indices) by more than :data:`_MAX_ANGLE_STEP` is
    shortened to that, along its direction."""
    fPhi, fJ, _, pv, m, _ = funcs
    q = np.array(q, dtype=float)
    turning = [k for k, i in enumerate(dep) if i in set(angles)]
    for _ in range(_NEWTON_STEPS):
        res = np.array(fPhi(*q, t, *pv), dtype=float)
        if _closes(res, q, 1e-13) or not dep:
            return q, res  # (the residual at this very q)
        J = np.array(fJ(*q, t, *pv), dtype=float).reshape(m, len(q))
        step, *_ = np.linalg.lstsq(J[:, dep], -res, rcond=None)
        widest = float(np.abs(step[turning]).max(initial=0.0))
        if widest > _MAX_ANGLE_STEP:
            step = step * (_MAX_ANGLE_STEP / widest)
        q[dep] += step
        if not np.isfinite(q).all():
            break
    return q, np.array(fPhi(*q, t, *pv), dtype=float)


def _closes(res, q, tol=1e-9) -> bool:
    """Whether the closure residual ``res`` is zero to ``tol`` of the coordinates' size.

    In Python floats (the same roundings as numpy's, a tenth of its time on a few values) unless
    a coordinate is nan, which numpy's largest propagates and Python's ``max`` may skip."""
    qs = q.tolist()
    if not qs or any(x != x for x in qs):
        return bool(np.all(np.abs(res) < tol * (1 + np.abs(q).max())))
    limit = tol * (1 + max(map(abs, qs)))
    return all(abs(r) < limit for r in res.tolist())


_CLOSURE_STARTS = 81
"""At most this many starts when the guesses do not close the loop: each dependent angle
at evenly spaced places on its circle (8 for one angle, 4 each for three)."""


def _refuse_unclosed(system, funcs, guesses, t, dep, res) -> None:
    """Raise the one-line error for a loop that does not close from the guesses, saying whether
    it closes elsewhere (where: other guesses) or from no start spread over the dependent
    angles' circles (the geometry cannot close there), and by how much it misses."""
    worst = int(np.argmax(np.abs(res)))
    row = system.closure[worst]
    head = f"{system.label}: joint {row.joint.name!r} ({row.joint.kind}) cannot be satisfied at the state"
    if not dep:
        raise InputError(f"{head} (residual {res[worst]:.3g}): no coordinate is marked dependent (give one a "
                         "`guess` instead of a `value`); check the prescribed motion and the guesses")
    free = system.free
    angles = [i for i in dep if free[i].kind == "angle"]
    per = max(2, min(8, int(_CLOSURE_STARTS ** (1 / len(angles))))) if angles else 1
    least = float(np.max(np.abs(res)))
    for k, spots in enumerate(itertools.product(range(per), repeat=len(angles))):
        if k >= _CLOSURE_STARTS:
            break
        start = np.array(guesses, dtype=float)
        start[angles] += 2 * math.pi * np.array(spots) / per
        q, r = _newton_closure(funcs, start, t, dep, angles)
        if _closes(r, q):
            found = ", ".join(f"{free[i].name} = {math.degrees(q[i]) if free[i].kind == 'angle' else q[i]:.6g}"
                              f" {'deg' if free[i].kind == 'angle' else 'm'}" for i in dep)
            raise InputError(f"{head} (residual {res[worst]:.3g}): no configuration near the dependent "
                             f"coordinates' guesses satisfies it, but one does at {found}: give guesses near it")
        least = min(least, float(np.max(np.abs(r))))
    searched = f"from the guesses and {min(per ** len(angles), _CLOSURE_STARTS)} starts around the dependent angles' circles"
    if len(angles) == len(dep):
        raise InputError(f"{head}: the loop cannot close there, the geometry does not allow it (no value of the "
                         f"dependent angles satisfies it, {searched}; the residual stays at least {least:.3g}): "
                         "check the lengths and the prescribed motion")
    raise InputError(f"{head}: no configuration found {searched} (the residual stays at least {least:.3g}): "
                     "the loop may not close there; check the lengths, the prescribed motion and the guesses")


CLOSURE_CONDITION_LIMIT = 1e6
"""Above this condition number of the closure equations' Jacobian in the dependent
coordinates (columns equilibrated), they do not determine those coordinates (a
linkage at a dead centre). Much lower than :data:`CONDITION_LIMIT` because at such
a singular root the residual is quadratic in the error, so Newton's method stops
about sqrt(1e-13) ~ 3e-7 away from it, where the condition is ~3e6 instead of
infinite. A regular assembly this close to a dead centre (1e-6 rad) is refused too."""


def _check_closure_jacobian(system, Jd: np.ndarray, q, t) -> None:
    if Jd.shape == (1, 1) and math.isfinite(Jd[0, 0]) and Jd[0, 0] != 0:
        return  # (one finite entry not 0, scaled by its own size: condition number 1)
    with np.errstate(all="ignore"):
        s = np.linalg.svd(Jd / np.maximum(np.max(np.abs(Jd), axis=0), 1e-300), compute_uv=False)
    cond = s[0] / s[-1] if s[-1] > 0 else math.inf
    if not cond <= CLOSURE_CONDITION_LIMIT:
        joints = ", ".join(dict.fromkeys(repr(r.joint.name) for r in system.closure))
        where = _state_text(system, q, [0.0] * len(q), t, ())
        raise SingularConfigurationError(
            f"{system.label}: singular configuration at {where}: the closure equations of joints {joints} do not "
            f"determine the dependent coordinates ({', '.join(c.name for c in system.dependent)}) there, a dead "
            f"centre (condition number {cond:.3g} > {CLOSURE_CONDITION_LIMIT:.0e})"
        )


# --------------------------------------------------------------------------- results
@dataclass
class InstantSolution:
    """Every acceleration and reaction at one state.

    Attributes
    ----------
    unknowns : dict[str, pint.Quantity]
        ``alpha`` (one-body systems) and each coordinate's second derivative
        [rad/s**2 or m/s**2], then each reaction [N or N*m].
    condition_number : float
        The cheap estimate of the solve (:func:`solve_with_estimate`; JSON
        ``condition_number_estimate``); the exact value is :func:`condition_numbers`'.
    point : str or None
        The reference point(s) P of the moment equations; None for a route that uses none
        (:data:`solver.formulations.POINT_FREE_METHODS`).
    method : str
    state : State
    scene : str
    """

    unknowns: dict[str, pint.Quantity]
    condition_number: float
    point: str | None
    method: str
    state: State | None = None
    scene: str | None = None
    extra: dict = field(default_factory=dict)
    error_bound: dict[str, float] = field(default_factory=dict)
    """Each unknown's float64 error bound [SI] (:func:`error_bounds`), where the solve is bounded
    (not printed: what derives from the unknowns, ``kinematics``, bounds its own values by it)."""

    def to_dict(self, units: Mapping[str, str] | None = None) -> dict:
        """JSON-ready dict; ``units`` is a scene's ``[output_units]`` (dimension names such
        as ``force``, ``moment``, ``length`` -> display units such as ``lbf``), applied by
        :func:`solver.output_units.to_output_units`."""
        from solver.output_units import to_output_units

        out = to_output_units({name: {"value": float(qty.magnitude), "unit": f"{qty.units:~}"}
                               for name, qty in self.unknowns.items()}, units)
        head = {"scene": self.scene} if self.scene is not None else {}
        cond = float(self.condition_number)
        from solver.formulations import point_entries

        return {**head, **point_entries(self.method, self.point), "method": self.method, "unknowns": out,
                "condition_number_estimate": cond if math.isfinite(cond) else None, **self.extra}

    def __repr__(self) -> str:
        vals = ", ".join(f"{k}={v:.6g~P}" for k, v in self.unknowns.items())
        return f"InstantSolution({vals}, cond={self.condition_number:.3g}, point={self.point!r}, method={self.method!r})"


def solve_instant(system, point: str | None = None, method: str = "generalized_euler",
                  state: State | None = None) -> InstantSolution:
    """Every acceleration and reaction at the system's state (or ``state``).

    Raises
    ------
    SingularConfigurationError
        Singular or badly conditioned system (condition number > 1e12).
    InputError
        A state outside a joint's model (a semicircle past its rim) or an
        inconsistent prescribed motion.
    """
    regime, warning = None, None
    if system.contacts:  # contacts that can stick, slip or separate: the regime that holds first
        from .regimes import regime_at_state

        regime, warning, state = regime_at_state(system, state, point, method)
    return solution_in_regime(system, regime, warning, state, point, method)


def solution_in_regime(system, regime, warning: str | None, state: State | None, point: str | None = None,
                       method: str = "generalized_euler") -> InstantSolution:
    """The :class:`InstantSolution` of :func:`solve_instant` once the contact regime is known:
    ``(regime, warning, state)`` as :func:`solver.analyses.regimes.regime_at_state` returns them
    (``regime`` None: the system as written). Both are bounded by one rule (:func:`error_bounds`;
    a regime through :func:`solver.analyses.regimes.regime_error_bounds`), and a value within its
    own bound is given as 0 (:func:`round_off_zeros`); a regime's checks are then redone with
    those zeros (``regime.checks``)."""
    from ..formulations import resolve_points, shown_point

    extra = {"warning": warning} if warning else {}
    if regime is None:
        res, treated, state = solved_at_state(system, point, method, state)
        extra.update(treated)
        names = _solved_names(res)
    else:  # the regime's own system, bounded by the same rule (regime_error_bounds)
        from .regimes import INDETERMINATE_NOTE, recheck, regime_error_bounds

        state = assemble(system) if state is None else state
        res = dict(regime.values)
        bounded = regime_error_bounds(system, regime, state.q, state.qd, state.t, point, method)
        names = bounded[0] if bounded is not None else []
        if bounded is not None:
            res["error_bound"] = bounded[1]

        def bound_at_rest():
            at_rest = regime_error_bounds(system, regime, state.q, [0.0] * len(state.qd), state.t, point, method)
            return at_rest[1] if at_rest is not None and at_rest[0] == names else None
        if _round_off_treatment(system, res, names, bound_at_rest, state, extra):
            # the reasons print the forces the table does (kept on the regime, for explain's step)
            regime.checks = recheck(system, regime, state.q, state.qd, state.t, res, point, method)
        extra["regime"] = {c.joint: c.to_dict() for c in regime.checks}
        if regime.indeterminate:
            extra["indeterminate"] = INDETERMINATE_NOTE
    _check_limits(system, state)
    unknowns = unknown_quantities(system, state, res)
    resolve_points(system, point)  # checks the point whatever the route
    shown = shown_point(system, method, point)
    cond = float(res["condition_number"]) if "condition_number" in res else math.inf
    bounds = res.get("error_bound")
    bound_of = {} if bounds is None else {n: float(e) for n, e in zip(names, bounds)}
    return InstantSolution(unknowns, cond, shown, method, state, system.name, extra, bound_of)


def _solved_names(res: dict) -> list[str]:
    """The unknowns' names of a :meth:`NumericModel.solve` result, in its order (that of
    ``res["error_bound"]``): every key but the condition number and the bounds."""
    return [name for name in res if name not in ("condition_number", "error_bound")]


def _round_off_treatment(system, res: dict, names, bound_at_rest, state: State, extra: dict) -> dict:
    """The one treatment of a bounded solve's round-off (``res["error_bound"]``, aligned with
    ``names``): the unknowns whose digits cancellation took (:func:`_digits_lost`, against their
    scale at rest, ``bound_at_rest()``: :func:`_scale_at_rest`) into ``extra["digits_lost"]``, and
    those within their own bound set to 0 in ``res`` (:func:`round_off_zeros`) into
    ``extra["zero_to_round_off"]``, which is returned."""
    lost = _digits_lost(system, res, names, _scale_at_rest(bound_at_rest, state, res), state)
    if lost:
        extra["digits_lost"] = lost
    zeros = round_off_zeros(system, res, names, lost, state)
    if zeros:
        extra["zero_to_round_off"] = zeros
    return zeros


def _unknown_units(system) -> dict[str, str]:
    """The SI unit of each unknown an instantaneous solve gives: every coordinate's acceleration,
    every reaction, and each contact's friction (a sliding one's -s mu_k N is no unknown of the
    scene's system, but is printed and bounded with them)."""
    units = {str(c.qdd): "rad/s**2" if c.kind == "angle" else "m/s**2" for c in system.free}
    units.update({r.name: r.unit for r in system.reactions})
    units.update({j.pair[0].name: j.pair[0].unit for j in system.contacts if j.pair[0] is not None})
    return units


def solved_at_state(system, point: str | None, method: str, state: State | None) -> tuple[dict, dict, State]:
    """(res, extra, state) of the solve of a system without a contact regime at ``state`` (None: the
    scene's), as :func:`solution_in_regime` makes its solution from them: every unknown (SI, by name;
    those 0 to round-off set to 0) with ``condition_number`` and ``error_bound``, and ``digits_lost``
    and ``zero_to_round_off`` where there are any (:func:`_round_off_treatment`).
    ``explain`` at rest takes only the round-off zeros from them (its own solve gives the rest).

    Raises
    ------
    SingularConfigurationError
        As :meth:`NumericModel.solve`.
    """
    from ..formulations import formulate

    model = formulate(system, method, point).numeric()  # (its checks before assembly's)
    state = assemble(system) if state is None else state
    res = model.solve(state.q, state.qd, state.t, once=True, bounds=True)
    rest = [0.0] * len(state.qd)

    def bound_at_rest():
        return model.solve(state.q, rest, state.t, once=True, bounds=True).get("error_bound")
    extra: dict = {}
    _round_off_treatment(system, res, model.names, bound_at_rest, state, extra)
    return res, extra, state


def unknown_quantities(system, state: State, res: dict, names=None) -> dict[str, pint.Quantity]:
    """The unknowns of a solve's ``res`` (SI, by name) as quantities, in the order of an
    :class:`InstantSolution`: a one-body system's alpha, each free coordinate's acceleration, each
    reaction (a contact's forces too, 0 where it separates or slides: :func:`_unknown_units`);
    ``names``: only these."""
    unknowns: dict[str, pint.Quantity] = {}
    if len(system.bodies) == 1 and (names is None or "alpha" in names):
        body = next(iter(system.bodies))
        unknowns["alpha"] = Q_(_alpha_value(system, body, state, res), "rad/s**2")
    for name, unit in _unknown_units(system).items():
        if names is None or name in names:
            unknowns[name] = Q_(float(res.get(name, 0.0)), unit)
    return unknowns


def round_off_zeros(system, res: dict, names, lost: dict, state: State) -> dict:
    """The unknowns that are 0 to round-off, set to 0 in ``res``: name -> {"computed", "error_bound"}
    (each ``{"value", "unit"}``); a one-body system's alpha, a combination of its accelerations,
    goes with them when it is shown as 0 because they are, with its own bound (:func:`_alpha_bound`).

    The rule: an unknown whose computed value is no larger than its own error bound
    (``res["error_bound"]``, :func:`error_bounds`), where that bound is round-off of its scale
    (not among ``lost``, the unknowns whose digits cancellation took: :func:`_digits_lost`), is
    indistinguishable from 0: its sign and digits are the round-off of the equations' terms (a
    pendulum hanging straight down, theta_ddot = -2.6e-15 rad/s**2 beside a bound of 1.2e-13).
    It is given as 0, with what was computed and the bound. A lost unknown keeps its value and
    its warning; an unknown computed as exactly 0 needs no word."""
    bound = res.get("error_bound")
    if bound is None:
        return {}
    units = _unknown_units(system)
    zeros, computed = {}, dict(res)
    for name, e in zip(names, bound):
        x = float(res[name])
        if name not in lost and x != 0 and abs(x) <= e:
            unit = units.get(name, "")
            zeros[name] = {"computed": {"value": x, "unit": unit}, "error_bound": {"value": float(e), "unit": unit}}
            res[name] = 0.0
    if len(system.bodies) == 1 and any(str(c.qdd) in zeros for c in system.free):
        body = next(iter(system.bodies))
        was, now = _alpha_value(system, body, state, computed), _alpha_value(system, body, state, res)
        e = _alpha_bound(system, state, dict(zip(names, bound)))
        if was != 0 and now == 0 and e is not None:  # alpha shown as 0 because its accelerations are
            alpha = {"computed": {"value": was, "unit": "rad/s**2"}, "error_bound": {"value": e, "unit": "rad/s**2"}}
            zeros = {"alpha": alpha, **zeros}  # (first, as the table of unknowns lists it)
    return zeros


def _alpha_bound(system, state: State, bounds: dict) -> float | None:
    """The float64 error bound of a one-body system's alpha [rad/s**2], a combination of its
    accelerations: the sum of |d alpha / d q''| times each acceleration's bound (``bounds``, by
    name), over the accelerations alpha holds at the state (a bar sliding on a rail: its
    theta_ddot's, not x_ddot's, whose unit is m/s**2); None where one of them has no bound."""
    body = next(iter(system.bodies))
    al = sp.sympify(system.alpha(body))
    total = 0.0
    for c in system.free:
        coefficient = al.diff(c.qdd)
        if coefficient == 0:
            continue
        k = abs(_at_state(system, coefficient, state))
        if k and str(c.qdd) not in bounds:
            return None
        total += k * float(bounds.get(str(c.qdd), 0.0))
    return total


def _scale_at_rest(bound_at_rest, state, res) -> "np.ndarray | None":
    """Each unknown's scale at rest: the size of the terms that make it with every rate set to
    0 at the same configuration (its error bound there, ``bound_at_rest()``, over
    :data:`ERROR_BOUND_FACTOR` u), the size gravity, springs and the given loads give it. None
    where nothing moves (the bound at the state is that one) or that solve fails."""
    if res.get("error_bound") is None or not any(state.qd):
        return None
    try:
        bound = bound_at_rest()
    except (InputError, SingularConfigurationError):
        return None
    return None if bound is None else np.asarray(bound) / (ERROR_BOUND_FACTOR * ROUND_OFF)


def _digits_lost(system, res: dict, names, at_rest=None, state: State | None = None) -> dict:
    """The unknowns whose error bound (``res["error_bound"]``) exceeds :data:`SIGNIFICANT_ERROR` of
    their size: name -> {"digits": float64 digits lost, "error_bound": {"value", "unit"}}; a
    one-body system's alpha, a combination of its accelerations, is named when its own bound at
    ``state`` (:func:`_alpha_bound`) exceeds that fraction of its size.

    The size is the larger of the unknown's value and of its scale (:func:`_scale_at_rest`,
    ``at_rest``; at rest, the size of the terms that make it): an answer that is 0 (a pendulum's
    angular acceleration at the bottom, a vertical bar's reaction on a wall), computed as
    1e-16 beside terms of 10, is round-off of 0, not an answer that lost its digits, while an
    angular acceleration of 7 left by omega**2 terms of 1e17 at 1e9 rad/s lost every digit of
    it. An unknown computed as exactly 0 is not flagged: a reaction with nothing to carry is 0
    by the structure of the equations, whatever the round-off of the other unknowns."""
    bound = res.get("error_bound")
    if bound is None:
        return {}
    units = _unknown_units(system)
    scale = dict(zip(names, bound / (ERROR_BOUND_FACTOR * ROUND_OFF) if at_rest is None else at_rest))
    lost = {}
    for name, e in zip(names, bound):
        size = abs(float(res[name]))
        if size and e > SIGNIFICANT_ERROR * max(size, float(scale[name])):  # (an exact 0 is not flagged)
            digits = min(16.0, max(0.0, math.log10(e / (ROUND_OFF * size))))
            lost[name] = {"digits": round(digits, 1), "error_bound": {"value": float(e), "unit": units.get(name, "")}}
    if len(system.bodies) == 1 and state is not None and any(str(c.qdd) in lost for c in system.free):
        body = next(iter(system.bodies))
        size = abs(_alpha_value(system, body, state, res))
        e = _alpha_bound(system, state, dict(zip(names, bound)))
        if size and e is not None and e > SIGNIFICANT_ERROR * size:
            digits = min(16.0, max(0.0, math.log10(e / (ROUND_OFF * size))))
            lost["alpha"] = {"digits": round(digits, 1), "error_bound": {"value": e, "unit": "rad/s**2"}}
    return lost


def _alpha_value(system, body, state, res) -> float:
    """The angular acceleration of ``body`` at ``state`` with the accelerations ``res``
    (:func:`_at_state`)."""
    return _at_state(system, sp.sympify(system.alpha(body)), state, res) + 0.0  # (no -0.0)


def _at_state(system, expr: sp.Expr, state: State, res: dict | None = None) -> float:
    """``expr`` at ``state`` (the accelerations from ``res``, SI by name, where given), with a Float
    put for each of its own symbols only (a Float made for every parameter cost more than the
    substitution)."""
    vals = dict(zip(system.q, state.q))
    vals.update(zip(system.qd, state.qd))
    if res is not None:
        vals.update({c.qdd: float(res[str(c.qdd)]) for c in system.free})
    vals[system.t] = state.t
    vals.update(system.si_values())
    return float(expr.xreplace({k: sp.Float(vals[k]) for k in expr.free_symbols if k in vals}))


def _check_limits(system, state: State) -> None:
    for text, g in system.limits():
        vals = dict(zip(system.q, state.q))
        vals[system.t] = state.t
        vals.update(system.si_values())
        value = float(sp.sympify(g).xreplace({k: sp.Float(v) for k, v in vals.items()}))
        if value < -1e-12:
            where = _state_text(system, state.q, state.qd, state.t, ())
            raise InputError(f"{system.label}: {where} is outside the model: it holds only while {text} "
                             "(there the straight edge meets the surface)")
