"""The structured solve of large batches (solver/analyses/structured.py) against
the plain linear solve.

Reference: for each state, numpy.linalg.solve of the formulation's sympy A and b
(``Formulation.linear_system()``), lambdified here on their own (no common
subexpressions, parameters as arguments): an independent evaluation of the same
equations, solved by LAPACK with partial pivoting. The structured path builds
its matrix differently (derivatives of the equations, parameters folded in),
eliminates in a planned pivot order and writes its arithmetic out entry by entry.

Systems: a chain of four pinned bars (12 x 12, the benchmark's system) and the
shipped slider-crank (a motor-driven crank, a composite rod, a dependent rod
angle; 10 x 10 with time in the matrix).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from solver.analyses.instant import STRUCTURED_MIN_STATES
from solver.errors import SingularConfigurationError
from solver.formulations import formulate
from solver.io.scenes import load_system

from scenes_factory import chain_toml

ROOT = Path(__file__).resolve().parents[1]
N = STRUCTURED_MIN_STATES + 904  # large enough to take the structured path

CHAIN = chain_toml()


def reference(system, q, qd, t):
    """x (N, n) by numpy.linalg.solve of the independently evaluated sympy A, b."""
    A, b = formulate(system).linear_system()
    values = system.si_values()
    params = sorted(values, key=str)
    args = (*system.q, *system.qd, system.t, *params)
    f = sp.lambdify(args, [*A, *b], modules="numpy", cse=False)
    n = A.shape[0]
    with np.errstate(all="ignore"):
        vals = f(*q, *qd, t, *[values[p] for p in params])
    vals = np.stack([np.broadcast_to(np.asarray(v, float), t.shape) for v in vals], axis=-1)
    An, bn = vals[:, : n * n].reshape(-1, n, n), vals[:, n * n:, None]
    return np.linalg.solve(An, bn)[..., 0], np.linalg.cond(An, 1)


def random_states(system, rng, spread):
    k = len(system.q)
    q = [rng.uniform(-spread, spread, N) for _ in range(k)]
    qd = [rng.uniform(-3, 3, N) for _ in range(k)]
    return q, qd, rng.uniform(0, 0.1, N)


@pytest.fixture(scope="module")
def chain(tmp_path_factory):
    path = tmp_path_factory.mktemp("chain") / "chain4.toml"
    path.write_text(CHAIN)
    return load_system(path)


@pytest.fixture(scope="module")
def slider_crank():
    return load_system(ROOT / "data/scenes/slider_crank.toml")


@pytest.mark.parametrize("name,spread", [("chain", 3.0), ("slider_crank", 1.2)])
def test_structured_solve_agrees_with_the_plain_solve(name, spread, request):
    system = request.getfixturevalue(name)
    model = formulate(system).numeric()
    assert model.structured().usable and model.structured().pivots > 0  # the fast path is really taken
    q, qd, t = random_states(system, np.random.default_rng(7), spread)
    res = model.solve(q, qd, t)
    x = np.stack([res[u] for u in model.names], axis=-1)
    ref, cond = reference(system, q, qd, t)
    # Both solves are Gaussian elimination with partial pivoting (the structured
    # one uses a planned pivot only where it is the largest entry of its column,
    # else the state goes to LAPACK), so both are backward stable to ~n eps; each
    # differs from the exact solution by ~cond_1(A) * n * eps ~ cond * 3e-15
    # relative to the size of x. 1e-12 * cond leaves a factor ~300 for the
    # round-off of the two different evaluations of A and b.
    err = np.max(np.abs(x - ref), axis=-1) / np.max(np.abs(ref), axis=-1)
    assert np.all(err <= 1e-12 * cond), np.max(err / cond)
    # and in fact to ~1e-11 on these well-conditioned states
    assert np.median(cond) < 1e5 and np.max(err) < 1e-9
    # The condition estimate is the dense path's quantity (the same formula on
    # the same equilibrated matrix): equal to round-off in the scales.
    A, b = model.matrices([v[:200] for v in q], [v[:200] for v in qd], t[:200])
    _, est = model._solve_with_estimate(A, b)
    np.testing.assert_allclose(res["condition_number"][:200], est, rtol=1e-9)


def test_a_singular_state_in_a_batch_is_reported(slider_crank):
    """phi = 90 deg: the closure's acceleration row (y of the piston pin, l cos(phi)
    phi'') vanishes, so A is singular there; one such state among thousands of
    regular ones must raise, never give NaN."""
    model = formulate(slider_crank).numeric()
    q, qd, t = random_states(slider_crank, np.random.default_rng(3), 0.5)
    q[0][1234] = np.pi / 2
    with pytest.raises(SingularConfigurationError, match=r"phi = 90 deg.*condition number"):
        model.solve(q, qd, t)
    q[0][1234] = 0.3
    res = model.solve(q, qd, t)
    assert all(np.all(np.isfinite(v)) for v in res.values())


@pytest.mark.parametrize("scene", sorted(p.stem for p in (ROOT / "data" / "scenes").glob("*.toml")))
def test_one_state_walk_equals_the_compiled_matrices(scene):
    """A state solved once takes A and b from one walk over the expression trees
    (``NumericModel.matrices(..., once=True)``) instead of the lambdified function. Same
    expressions, evaluated in another order and without common subexpressions: each entry agrees
    to round-off, a few ulps of the largest term it sums (relative 1e-12 of the matrix's scale
    leaves room for cancellations of up to ~1e3 in an entry). The model is not compiled for it."""
    from solver.analyses.instant import assemble
    from solver.analyses.regimes import system_in_regime
    from solver.formulations import Formulation, resolve_points

    system = load_system(ROOT / "data" / "scenes" / f"{scene}.toml")
    if system.contacts:  # the equations of the contact regime that holds at the state
        system, _, _, state = system_in_regime(system, None)
    else:
        state = assemble(system)
    # the equations as written (Formulation itself: formulate() refuses a contact that may change
    # regime, or one held redundantly; their equations are still the model's)
    model = Formulation(system, "generalized_euler", resolve_points(system, None)).numeric()
    A1, b1 = model.matrices(state.q, state.qd, state.t, once=True)
    assert model._f is None  # the walk served: nothing compiled
    A2, b2 = model.matrices(state.q, state.qd, state.t)
    scale = max(np.abs(A2).max(), np.abs(b2).max())
    assert np.allclose(A1, A2, rtol=1e-12, atol=1e-12 * scale) and np.allclose(b1, b2, rtol=1e-12, atol=1e-12 * scale)
