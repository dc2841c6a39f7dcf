"""A fast, vectorised solve of A(q, q', t) x = b that exploits the structure of A.

Used by :meth:`solver.analyses.instant.NumericModel.solve` for large batches of
states. The matrix of a multibody formulation is sparse, and many of its
entries do not depend on the state (the +/-1 of a reaction in Newton's
equations, a body's inertia about a fixed point). :class:`StructuredSolver`
plans, once, the order of a Gaussian elimination: at each step a pivot that is
the largest entry of its column at 64 sample states, fewest updates first
(Markowitz), constants before state-dependent entries. The elimination then
needs no pivot search, and its code is written out entry by entry, skipping
the structural zeros and folding the constants. Whatever no entry dominates
at every sample is solved by Gaussian elimination with partial pivoting,
vectorised over the states. States are processed in chunks that stay in the
processor's cache.

The same elimination solves, besides b, the two +/-1 right-hand sides of the
condition estimate of :func:`solver.analyses.instant.solve_with_estimate`
(Hager's first step on the row- and column-equilibrated A), so the estimate is
the same quantity as on the plain path.

Every state is checked: a planned pivot is accepted only where it is, at that
state, at least as large as every other entry of its column still to be
eliminated (every |multiplier| <= 1). Where that holds, the whole elimination
is Gaussian elimination with partial pivoting of A with its rows and columns
reordered, with LAPACK's backward stability. The caller solves the other
states (and any non-finite result or estimate, or an estimate above the
singularity limit) by the plain dense path, where the singularity decision
lives. The planned order can therefore cost speed but never accuracy, and a
singular state is never returned as NaN.
"""
from __future__ import annotations

import math
import re

import numpy as np
import sympy as sp

from ..strprint import lambdify

__all__ = ["StructuredSolver", "CHUNK"]

CHUNK = 4096
"""States per chunk: the live arrays of a chunk (32 kB each) stay in the cache."""


class _NotFinite(Exception):
    """A constant entry of A or b is not a finite real number."""


def _fmt(v) -> str:
    """Source text of a value: a float literal or a (possibly negated) variable."""
    return repr(v) if isinstance(v, float) else v


def _neg(v):
    """-v without code: a negation is carried in the name ("-_3") until used."""
    if isinstance(v, float):
        return -v
    return v[1:] if v.startswith("-") else "-" + v


class _Code:
    """Straight-line numpy code with constant folding. A value is a float
    (a constant) or a str: an array variable, possibly negated ("-_3"), so
    that sign changes cost no operation."""

    def __init__(self):
        self.lines: list[str] = []
        self.count = 0

    def let(self, text: str) -> str:
        name = f"_{self.count}"
        self.count += 1
        self.lines.append(f"{name} = {text}")
        return name

    def mul(self, a, b):
        if isinstance(a, float) and isinstance(b, float):
            return a * b
        if isinstance(a, float):
            a, b = b, a
        if isinstance(b, float):  # a is a variable
            if b == 0.0:
                return 0.0
            if abs(b) == 1.0:
                return a if b > 0 else _neg(a)
            if a.startswith("-"):
                a, b = a[1:], -b
            return self.let(f"{a} * {b!r}")
        sign = a.startswith("-") != b.startswith("-")
        out = self.let(f"{a.lstrip('-')} * {b.lstrip('-')}")
        return _neg(out) if sign else out

    def add(self, a, b):
        if isinstance(a, float) and isinstance(b, float):
            return a + b
        if isinstance(a, float):
            a, b = b, a
        if isinstance(b, float):  # a is a variable
            if b == 0.0:
                return a
            if a.startswith("-"):
                return _neg(self.let(f"{a[1:]} - {b!r}"))
            return self.let(f"{a} + {b!r}")
        if a.startswith("-") and b.startswith("-"):
            return _neg(self.let(f"{a[1:]} + {b[1:]}"))
        if b.startswith("-"):
            return self.let(f"{a} - {b[1:]}")
        if a.startswith("-"):
            return self.let(f"{b} - {a[1:]}")
        return self.let(f"{a} + {b}")

    def sub(self, a, b):
        return self.add(a, _neg(b))

    def absolute(self, a):
        return abs(a) if isinstance(a, float) else self.let(f"_abs({a.lstrip('-')})")

    def maximum(self, values):
        """Largest of non-negative values."""
        consts = [v for v in values if isinstance(v, float)]
        arrays = [v for v in values if not isinstance(v, float)]
        if not arrays:
            return max(consts, default=0.0)
        out = arrays[0]
        for v in arrays[1:]:
            out = self.let(f"_max({out}, {v})")
        if consts and max(consts) > 0:
            out = self.let(f"_max({out}, {max(consts)!r})")
        return out

    def total(self, values):
        out = 0.0
        for v in values:
            out = self.add(out, v)
        return out

    def positive(self, v):
        """v where v > 0, else 1 (the scale of an all-zero row or column)."""
        if isinstance(v, float):
            return v if v > 0 else 1.0
        return self.let(f"{v} + ({v} == 0)")

    def reciprocal(self, v):
        return 1.0 / v if isinstance(v, float) else self.let(f"1.0 / {v}")


def _partial_pivoting(c: _Code, M: list[list], R: list) -> list:
    """Emit Gaussian elimination with partial pivoting of the block M X = R
    (entries: floats or array names, each R[i] a (3, n) array); returns X's rows.

    The pivot search is written as conditional row swaps: at step k, row k is
    swapped with each lower row i whose |entry| in column k is larger, so row k
    ends with the largest. A zero pivot gives inf/nan, which the caller rejects."""
    s = len(M)
    M = [row[:] for row in M]
    R = list(R)
    for k in range(s):
        for i in range(k + 1, s):
            if isinstance(M[i][k], float) and M[i][k] == 0.0:
                continue
            swap = c.let(f"_abs({_fmt(M[i][k])}) > _abs({_fmt(M[k][k])})")
            for j in range(k, s):
                a, b = M[k][j], M[i][j]
                if isinstance(a, float) and isinstance(b, float) and a == b:
                    continue
                M[k][j] = c.let(f"_where({swap}, {_fmt(b)}, {_fmt(a)})")
                M[i][j] = c.let(f"_where({swap}, {_fmt(a)}, {_fmt(b)})")
            R[k], R[i] = (c.let(f"_where({swap}, {R[i]}, {R[k]})"), c.let(f"_where({swap}, {R[k]}, {R[i]})"))
        inv = c.let(f"1.0 / {_fmt(M[k][k])}") if not isinstance(M[k][k], float) else 1.0 / M[k][k]
        for i in range(k + 1, s):
            if isinstance(M[i][k], float) and M[i][k] == 0.0:
                continue
            f = c.mul(M[i][k], inv)
            for j in range(k + 1, s):
                M[i][j] = c.sub(M[i][j], c.mul(f, M[k][j]))
            R[i] = c.sub(R[i], c.mul(f, R[k]))
        M[k][k] = inv
    X = [None] * s
    for k in range(s - 1, -1, -1):
        acc = R[k]
        for j in range(k + 1, s):
            acc = c.sub(acc, c.mul(M[k][j], X[j]))
        X[k] = c.mul(acc, M[k][k])
    return X


class StructuredSolver:
    """Plan and run the structured solve of A x = b (see the module docstring).

    Parameters
    ----------
    A, b : sympy.Matrix
        The square linear system with numbers substituted for the parameters:
        entries are functions of ``args`` only.
    args : sequence of sympy.Symbol
        The state variables (coordinates, rates, t), in call order.
    samples : sequence of arrays
        Values of ``args`` at a few typical states. An entry is planned as a
        pivot only if no other entry of its column exceeds it there; the
        condition is checked again at every solved state.

    Attributes
    ----------
    usable : bool
        False when A has an empty row or column (singular for every state);
        the caller then uses the dense path only.
    pivots : int
        Unknowns eliminated on planned pivots.
    pivoted_block : int
        Size of the block left to partial pivoting.
    """

    def __init__(self, A: sp.Matrix, b: sp.Matrix, args, samples):
        n = self.n = A.shape[0]
        exprs: list = []
        index: dict = {}

        def value(e):  # a float, or the lambdified output that holds e (or -e)
            if e.is_number:
                v = complex(e)
                if v.imag != 0 or not math.isfinite(v.real):
                    raise _NotFinite
                return v.real
            if e.could_extract_minus_sign():  # a negation costs an operation; the code carries signs
                return _neg(value(-e))
            if e not in index:
                index[e] = f"e[{len(exprs)}]"
                exprs.append(e)
            return index[e]

        try:
            E0 = {ij: value(A[ij]) for ij in np.ndindex(n, n) if A[ij] != 0}
            B0 = [value(b[i]) for i in range(n)]
        except _NotFinite:  # a constant entry is infinite or undefined: the dense path reports it
            self.usable = False
            return
        self.usable = {j for _, j in E0} == set(range(n)) and {i for i, _ in E0} == set(range(n))
        self._eval = lambdify(tuple(args), exprs, "numpy", cse=True) if exprs else None
        with np.errstate(all="ignore"):
            e = self._eval(*samples) if self._eval is not None else []
        k = len(samples[0]) if samples else 1
        sampled = {name: np.broadcast_to(np.asarray(v, dtype=float), (k,)) for name, v in
                   zip((f"e[{i}]" for i in range(len(exprs))), e)}
        self._samples = {ij: (np.full(k, v) if isinstance(v, float) else
                              np.nan_to_num(-sampled[v[1:]] if v.startswith("-") else sampled[v], nan=np.inf))
                         for ij, v in E0.items()}
        self._chunk = self._generate(E0, B0) if self.usable else None

    # -- planning ------------------------------------------------------------------------
    def _generate(self, E0: dict, B0: list):
        """Compile the code of one chunk: e (the lambdified entries), m (states) ->
        (x rows, condition estimate, ok)."""
        n = self.n
        c = _Code()
        # Equilibration (as instant._equilibrate): columns by their largest entry, then rows.
        absA = {ij: c.absolute(v) for ij, v in E0.items()}
        col = [c.positive(c.maximum([v for (_, j), v in absA.items() if j == jj])) for jj in range(n)]
        inv_col = [c.reciprocal(v) for v in col]
        scaled = {ij: c.mul(v, inv_col[ij[1]]) for ij, v in absA.items()}
        row = [c.positive(c.maximum([v for (i, _), v in scaled.items() if i == ii])) for ii in range(n)]
        inv_row = [c.reciprocal(v) for v in row]
        # ||As||_1 = max_j sum_i |A_ij| / (row_i col_j)
        norm_A = c.maximum([c.total([c.mul(v, inv_row[i]) for (i, jj), v in scaled.items() if jj == j])
                            for j in range(n)])
        # b, and the estimate's +/-1 vectors z scaled by the rows: A w = R z, y = C w
        z1 = [-1.0 if i % 2 else 1.0 for i in range(n)]
        z2 = [-1.0 if i < n // 2 else 1.0 for i in range(n)]
        R = [c.let(f"_rows3({_fmt(B0[i])}, {_fmt(c.mul(row[i], z1[i]))}, {_fmt(c.mul(row[i], z2[i]))}, m)")
             for i in range(n)]
        X = self._eliminate(c, dict(E0), R)
        x = [c.let(f"{X[j]}[0]") if not X[j].startswith("-") else _neg(c.let(f"{X[j][1:]}[0]"))
             for j in range(n)]
        # ||y||_1 for both z at once: (2, m) arrays
        est = c.total([c.absolute(c.mul(col[j], c.let(f"{X[j].lstrip('-')}[1:]"))) for j in range(n)])
        cond = c.let(f"{_fmt(norm_A)} * _max({est}[0], {est}[1]) * {1.0 / n!r}")
        # x finite (b may hold an infinity), and every multiplier of a planned pivot <= 1
        finite = c.total(x)
        ok = c.let(f"_isfinite({cond}) & _isfinite({_fmt(finite)})"
                   + (f" & ({self._growth} <= 1.0)" if self._growth is not None else ""))
        keep = [v.lstrip("-") for v in (*x, cond, ok)]
        body = "\n    ".join(_free_temporaries(c.lines, keep))
        src = f"def _chunk(e, m):\n    {body}\n    return ({', '.join(x)},), {cond}, {ok}\n"
        namespace = {"_abs": np.abs, "_max": np.maximum, "_where": np.where, "_isfinite": np.isfinite,
                     "_rows3": _rows3}
        exec(compile(src, "<structured solve>", "exec"), namespace)  # noqa: S102 - code we generated, no input text
        self.source = src
        return namespace["_chunk"]

    def _eliminate(self, c: _Code, E: dict, R: list) -> list:
        """Emit the elimination of A X = R: planned pivots in Markowitz order, then
        partial pivoting on the block they leave. Returns X's rows (each (3, m))."""
        n = self.n
        rows_left, cols_left = set(range(n)), set(range(n))
        pivots = []
        growth = None  # the largest |multiplier| of a static pivot, per state
        S = dict(self._samples)  # each entry's values at the sample states, to choose the pivots
        while True:
            rcount = {i: 0 for i in rows_left}
            ccount = {j: 0 for j in cols_left}
            for (i, j) in E:
                rcount[i] += 1
                ccount[j] += 1
            best = None
            for (i, j), v in E.items():
                if isinstance(v, float) and v == 0.0:
                    continue
                size = np.abs(S[i, j])  # a pivot must be the largest of its column at every sample
                others = [np.abs(S[ii, jj]) for (ii, jj) in E if jj == j and ii != i]
                if not np.all(size > 0) or (others and not np.all(np.max(others, axis=0) <= size)):
                    continue
                # fewest updates first (Markowitz), then constants (no division), then larger
                key = ((rcount[i] - 1) * (ccount[j] - 1), not isinstance(v, float), -float(np.min(size)), i, j)
                if best is None or key < best[0]:
                    best = (key, i, j, v)
            if best is None:
                break
            _, r, piv_c, p = best
            for i in [i for (i, j) in E if j == piv_c and i != r]:  # the sample values follow
                for j in [j for (ii, j) in E if ii == r and j != piv_c]:
                    S[i, j] = S.get((i, j), np.zeros(len(S[r, j]))) - S[i, piv_c] / S[r, piv_c] * S[r, j]
            prow = {j: v for (i, j), v in E.items() if i == r and j != piv_c}
            p = 1.0 / p if isinstance(p, float) else c.reciprocal(p)  # from here on, 1 / pivot
            for i in [i for (i, j) in E if j == piv_c and i != r]:
                f = c.mul(E.pop((i, piv_c)), p)
                if not isinstance(f, float):  # the partial-pivoting condition, checked per state
                    af = c.absolute(f)
                    growth = af if growth is None else c.let(f"_max({growth}, {af})")
                for j, a_rj in prow.items():
                    new = c.sub(E.get((i, j), 0.0), c.mul(f, a_rj))
                    if isinstance(new, float) and new == 0.0:
                        E.pop((i, j), None)
                    else:
                        E[i, j] = new
                R[i] = c.sub(R[i], c.mul(f, R[r]))
            for j in list(prow):
                E.pop((r, j))
            E.pop((r, piv_c))
            rows_left.remove(r)
            cols_left.remove(piv_c)
            pivots.append((r, piv_c, p, prow))
        X: dict[int, str] = {}
        rl, cl = sorted(rows_left), sorted(cols_left)
        if rl:
            M = [[E.get((i, j), 0.0) for j in cl] for i in rl]
            for j, v in zip(cl, _partial_pivoting(c, M, [R[i] for i in rl])):
                X[j] = v
        for r, piv_c, p, prow in reversed(pivots):
            acc = R[r]
            for j, a_rj in prow.items():
                acc = c.sub(acc, c.mul(a_rj, X[j]))
            X[piv_c] = c.mul(acc, p)
        self.pivots, self.pivoted_block, self._growth = len(pivots), len(rl), growth
        return [X[j] for j in range(n)]

    # -- solving -------------------------------------------------------------------------
    def solve(self, arrays) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(x (n, N), condition estimate (N,), ok (N,)) for flat state arrays of length N.

        ``ok`` is False where the caller must solve by the dense path instead:
        a non-finite result or estimate, or a planned pivot smaller than
        another entry of its column at that state.
        """
        N = arrays[0].shape[0]
        x = np.empty((self.n, N))
        cond = np.empty(N)
        ok = np.empty(N, dtype=bool)
        with np.errstate(all="ignore"):
            for lo in range(0, N, CHUNK):
                hi = min(N, lo + CHUNK)
                e = self._eval(*[a[lo:hi] for a in arrays]) if self._eval is not None else []
                xs, cond[lo:hi], ok[lo:hi] = self._chunk(e, hi - lo)
                for j, v in enumerate(xs):
                    x[j, lo:hi] = v
        return x, cond, ok


def _free_temporaries(lines: list[str], keep) -> list[str]:
    """``lines`` with each temporary deleted after its last use, so that a chunk's
    working set stays small (straight-line code would keep every array alive)."""
    last: dict[str, int] = {}
    for k, line in enumerate(lines):
        for name in re.findall(r"\b_\d+\b", line):
            last[name] = k
    for name in keep:
        last.pop(name, None)
    dead: dict[int, list[str]] = {}
    for name, k in last.items():
        dead.setdefault(k, []).append(name)
    out = []
    for k, line in enumerate(lines):
        out.append(line)
        if k in dead:
            out.append("del " + ", ".join(sorted(dead[k])))
    return out


def _rows3(b, s1, s2, m):
    """A (3, m) right-hand-side row from scalars or arrays."""
    out = np.empty((3, m))
    out[0] = b
    out[1] = s1
    out[2] = s2
    return out
