"""Benchmark: what accuracy costs for the dynamics, and how fast the instantaneous solve runs.

1. Work-precision, Example 2 period (data/scenes/disk_bar.toml, F_a = 0) at
   amplitudes 5..170 deg, error against a reference from mpmath's tanh-sinh
   quadrature of the raw energy integral at 30 digits (agreement of two
   precisions, 30 and 40 digits, is checked below 1e-14), versus wall time, for
   - the linearized formula T0 (Eq. 46),
   - the energy-integral quadrature (solver.period.exact_period) at tol 1e-3..1e-12,
   - solve_ivp RK45, DOP853, Radau, LSODA at rtol 1e-3..1e-12, the period from
     the turning point (theta_dot = 0 event) after half a swing.
   Times are per call on a system that is already compiled (the one-off
   derivation + lambdify cost is reported separately).
2. Throughput of the instantaneous Example 1 solve (data/scenes/sliding_bar.toml)
   on a 1000 x 1000 grid of (theta, beta): vectorised closed-form reactions
   (lambdified with cse), a vectorised batched numpy.linalg.solve of the 3x3
   systems, a per-configuration numpy.linalg.solve loop (timed on a 20 000
   subset and extrapolated), and the closed forms derived through
   sympy.physics.mechanics (method="lagrange") lambdified and vectorised.
   Target: >= 1e6 configurations per second.
3. float64 against mpmath at 50 digits on a 40 x 40 subgrid: the largest
   relative error, where, and the condition number there.

Writes reports/build/bench/dynamics.json and reports/build/bench/work_precision.svg.
Run: ``.venv/bin/python tests/bench/bench_dynamics.py`` (or ``make bench``).
"""
from __future__ import annotations

import json
import math
import platform
import statistics
import sys
import time
import warnings
from pathlib import Path

import mpmath
import numpy as np
import sympy as sp

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from solver.derivation import derive  # noqa: E402
from solver.period import OneDofSystem, exact_period, find_equilibrium  # noqa: E402
from solver.scenefile import load_scene  # noqa: E402
from solver.simulate import period_by_integration  # noqa: E402

OUT = ROOT / "reports" / "build" / "bench"
AMPLITUDES_DEG = (5, 30, 60, 90, 120, 150, 170)
TOLS = (1e-3, 1e-6, 1e-9, 1e-12)
IVP_METHODS = ("RK45", "DOP853", "Radau", "LSODA")
GRID = 1000  # GRID x GRID configurations
LOOP_SUBSET = 20_000
SUBGRID = 40
TARGET_RATE = 1e6


def _timed(fn, min_time=0.05, max_repeats=50):
    """Median wall time of fn() over repeats (at least 3, until min_time is spent)."""
    times, out = [], None
    t_start = time.perf_counter()
    while len(times) < 3 or (time.perf_counter() - t_start < min_time and len(times) < max_repeats):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), out


# ----------------------------------------------------------------------------- 1. work-precision
def reference_period(system: OneDofSystem, amplitude: float, dps: int) -> float:
    """mpmath tanh-sinh of T = 2 int sqrt(M / (2 (V(a) - V))) over [-a, a] (symmetric V, q_e = 0)."""
    subs = dict(zip(system.params, system.values))
    M = sp.lambdify(system.q, system.mass.xreplace(subs), "mpmath")
    V = sp.lambdify(system.q, system.potential.xreplace(subs), "mpmath")
    with mpmath.workdps(dps):
        a = mpmath.mpf(amplitude)
        Va = V(a)

        def f(x):
            d = Va - V(x)
            return mpmath.sqrt(M(x) / (2 * d)) if d > 0 else mpmath.mpf(0)

        return float(2 * mpmath.quad(f, [-a, 0, a]))


def work_precision():
    t0 = time.perf_counter()
    scene = load_scene(ROOT / "data/scenes/disk_bar.toml")
    system = OneDofSystem.from_derivation(derive(scene))
    eq = find_equilibrium(system)
    Mf, d2V = system.mass_fn(), system.potential_fn(2)
    exact_period(system, 0.3, tol=1e-6, equilibrium=eq)  # compile
    period_by_integration(system, 0.3, "RK45", rtol=1e-3, equilibrium=eq)
    setup = time.perf_counter() - t0
    rows = []
    ref_check = []
    for deg in AMPLITUDES_DEG:
        a = math.radians(deg)
        ref = reference_period(system, a, 30)
        ref40 = reference_period(system, a, 40)
        ref_check.append(abs(ref - ref40) / ref40)

        # the closed form itself (Eq. 46 generalised): compiled M and V'' at the known equilibrium
        t_lin, T0 = _timed(lambda: 2 * math.pi * math.sqrt(float(Mf(eq.q)) / float(d2V(eq.q))))
        rows.append(dict(amplitude_deg=deg, method="linear", tol=None, time_s=t_lin, error=abs(T0 - ref) / ref))
        for tol in TOLS:
            t, res = _timed(lambda: exact_period(system, a, tol=tol, equilibrium=eq))
            rows.append(dict(amplitude_deg=deg, method="quadrature", tol=tol, time_s=t,
                             error=abs(res.period - ref) / ref, nodes=res.nodes, precision=res.precision))
        for m in IVP_METHODS:
            for tol in TOLS:
                t, res = _timed(lambda: period_by_integration(system, a, m, rtol=tol, equilibrium=eq),
                                min_time=0.02, max_repeats=5)
                rows.append(dict(amplitude_deg=deg, method=m, tol=tol, time_s=t, error=abs(res.period - ref) / ref,
                                 nfev=res.nfev))
    # what each accuracy costs: the cheapest method reaching it at every amplitude (worst-case time)
    costs = {}
    methods = ["linear", "quadrature", *IVP_METHODS]
    for target in TOLS:
        best = None
        for m in methods:
            for tol in ([None] if m == "linear" else TOLS):
                sel = [r for r in rows if r["method"] == m and r["tol"] == tol]
                if sel and all(r["error"] <= target for r in sel):
                    worst = max(r["time_s"] for r in sel)
                    if best is None or worst < best[2]:
                        best = (m, tol, worst, max(r["error"] for r in sel))
        costs[f"{target:g}"] = (None if best is None else
                                dict(method=best[0], setting=best[1], max_time_s=best[2], max_error=best[3]))
    # per method: time to reach each target (cheapest setting), worst over amplitudes
    per_method = {}
    for m in methods:
        per_method[m] = {}
        for target in TOLS:
            opts = []
            for tol in ([None] if m == "linear" else TOLS):
                sel = [r for r in rows if r["method"] == m and r["tol"] == tol]
                if sel and all(r["error"] <= target for r in sel):
                    opts.append(max(r["time_s"] for r in sel))
            per_method[m][f"{target:g}"] = min(opts) if opts else None
    return dict(setup_s=setup, reference_agreement_30_vs_40_digits=max(ref_check), rows=rows,
                cheapest_per_accuracy=costs, time_to_accuracy=per_method)


def plot(wp, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 4.2), sharey=True)
    colors = dict(linear="k", quadrature="C3", RK45="C0", DOP853="C1", Radau="C2", LSODA="C4")
    for ax, deg in zip(axes, (30, 150)):
        for m, c in colors.items():
            sel = [r for r in wp["rows"] if r["method"] == m and r["amplitude_deg"] == deg]
            x = [r["time_s"] for r in sel]
            y = [max(r["error"], 1e-17) for r in sel]
            ax.loglog(x, y, "o-" if m != "linear" else "s", color=c, label=m, ms=4)
        ax.set_title(f"Example 2 period, amplitude {deg} deg")
        ax.set_xlabel("wall time per call [s]")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("relative error vs 30-digit reference")
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


# ----------------------------------------------------------------------------- 2. throughput
def _lambdified(d, exprs):
    scene = d.scene
    params = [sp.Symbol(n, real=True) for n in scene.parameters]
    f = sp.lambdify((d.q, d.qd, d.t, *params), exprs, modules="numpy", cse=True)
    values = {p: float(scene.parameters[p.name].to_base_units().magnitude) for p in params}
    return f, params, values


def throughput():
    scene = load_scene(ROOT / "data/scenes/sliding_bar.toml")
    t0 = time.perf_counter()
    d = derive(scene)
    A, b = d.linear_system()
    closed = [d.qdd_solution] + [d.reactions[n] for n in ("R_A", "R_B")]
    f_closed, params, values = _lambdified(d, closed)
    f_Ab, _, _ = _lambdified(d, list(A) + list(b))
    compile_s = time.perf_counter() - t0

    th = np.radians(np.linspace(1.0, 89.0, GRID))
    be = np.radians(np.linspace(10.0, 170.0, GRID))
    TH, BE = np.meshgrid(th, be, indexing="ij")
    TH, BE = TH.ravel(), BE.ravel()
    n = TH.size
    args = [values[p] if p.name != "beta" else BE for p in params]

    def closed_form():
        with np.errstate(all="ignore"):
            return np.stack([np.broadcast_to(v, TH.shape) for v in f_closed(TH, 0.0, 0.0, *args)], axis=-1)

    def batched():
        with np.errstate(all="ignore"):
            e = [np.broadcast_to(np.asarray(v, float), TH.shape) for v in f_Ab(TH, 0.0, 0.0, *args)]
        Am = np.stack(e[:9], axis=-1).reshape(n, 3, 3)
        bm = np.stack(e[9:], axis=-1)
        return np.linalg.solve(Am, bm[..., None])[..., 0]

    t_closed, X_closed = _timed(closed_form, min_time=0.5, max_repeats=5)
    t_batched, X_batched = _timed(batched, min_time=0.5, max_repeats=5)
    finite = np.all(np.isfinite(X_closed), axis=1)
    agree = float(np.max(np.abs(X_closed[finite] - X_batched[finite]) /
                         np.maximum(np.abs(X_batched[finite]), 1.0)))

    idx = np.random.default_rng(1).choice(n, LOOP_SUBSET, replace=False)
    scalar_args = [values[p] for p in params]
    bi = [p.name for p in params].index("beta")

    def loop():
        out = np.empty((LOOP_SUBSET, 3))
        for k, i in enumerate(idx):
            a = list(scalar_args)
            a[bi] = BE[i]
            e = f_Ab(TH[i], 0.0, 0.0, *a)
            out[k] = np.linalg.solve(np.array(e[:9], float).reshape(3, 3), np.array(e[9:], float))
        return out

    t_loop_subset, X_loop = _timed(loop, min_time=0.0, max_repeats=1)
    loop_agree = float(np.max(np.abs(X_loop - X_batched[idx]) / np.maximum(np.abs(X_batched[idx]), 1.0)))

    t0 = time.perf_counter()
    dl = derive(scene, method="lagrange")
    lag_exprs = [dl.qdd_solution] + [dl.reactions[n] for n in ("R_A", "R_B")]
    f_lag, lparams, lvalues = _lambdified(dl, lag_exprs)
    lagrange_setup = time.perf_counter() - t0
    largs = [lvalues[p] if p.name != "beta" else BE for p in lparams]

    def lagrange():
        with np.errstate(all="ignore"):
            return np.stack([np.broadcast_to(v, TH.shape) for v in f_lag(TH, 0.0, 0.0, *largs)], axis=-1)

    t_lag, X_lag = _timed(lagrange, min_time=0.5, max_repeats=5)
    fin2 = finite & np.all(np.isfinite(X_lag), axis=1)
    lag_agree = float(np.max(np.abs(X_lag[fin2] - X_batched[fin2]) / np.maximum(np.abs(X_batched[fin2]), 1.0)))
    return dict(
        configurations=n,
        grid=dict(theta_deg=[1.0, 89.0], beta_deg=[10.0, 170.0], points=[GRID, GRID]),
        derive_and_compile_s=compile_s,
        vectorised_closed_form=dict(time_s=t_closed, rate_per_s=n / t_closed,
                                    nonfinite=int(np.count_nonzero(~finite))),
        vectorised_batched_solve=dict(time_s=t_batched, rate_per_s=n / t_batched),
        per_configuration_loop=dict(subset=LOOP_SUBSET, subset_time_s=t_loop_subset,
                                    rate_per_s=LOOP_SUBSET / t_loop_subset,
                                    extrapolated_full_grid_s=t_loop_subset * n / LOOP_SUBSET,
                                    note="timed on a random subset and extrapolated linearly"),
        sympy_mechanics_lagrange=dict(derive_and_compile_s=lagrange_setup, time_s=t_lag, rate_per_s=n / t_lag),
        max_relative_disagreement=dict(closed_vs_batched=agree, loop_vs_batched=loop_agree,
                                       lagrange_vs_batched=lag_agree),
        target_rate_per_s=TARGET_RATE,
        target_met=bool(max(n / t_closed, n / t_batched) >= TARGET_RATE),
    )


# ----------------------------------------------------------------------------- 3. float64 vs mpmath
def float_vs_exact():
    scene = load_scene(ROOT / "data/scenes/sliding_bar.toml")
    d = derive(scene)
    A, b = d.linear_system()
    params = [sp.Symbol(n, real=True) for n in scene.parameters]
    args = (d.q, d.qd, d.t, *params)
    f64 = sp.lambdify(args, list(A) + list(b), "numpy")
    fmp = sp.lambdify(args, list(A) + list(b), "mpmath")
    from solver.precision import exact_quantity

    exact = {p: exact_quantity(scene.parameters[p.name]) for p in params}
    th = np.radians(np.linspace(1.0, 89.0, SUBGRID))
    be = np.radians(np.linspace(1.0, 179.0, SUBGRID))
    worst = dict(error=-1.0)
    errors, conds = [], []
    scale = np.array([32.174 * 0.3048 / (4 * 0.3048), 50 * 0.45359237 * 32.174 * 0.3048,
                      50 * 0.45359237 * 32.174 * 0.3048])  # g / l_b for theta_ddot, m_b g for forces
    with mpmath.workdps(50):
        pm = {p: mpmath.mpf(str(sp.N(v, 60))) for p, v in exact.items()}
        for t_deg, t in zip(np.linspace(1.0, 89.0, SUBGRID), th):
            for b_deg, bb in zip(np.linspace(1.0, 179.0, SUBGRID), be):
                # the same configuration in both arithmetics: angles are the float64 grid values
                vals64 = [float(pm[p]) if p.name != "beta" else bb for p in params]
                e = f64(t, 0.0, 0.0, *vals64)
                A64 = np.array(e[:9], float).reshape(3, 3)
                x64 = np.linalg.solve(A64, np.array(e[9:], float))
                valsmp = [pm[p] if p.name != "beta" else mpmath.mpf(bb) for p in params]
                em = fmp(mpmath.mpf(t), 0, 0, *valsmp)
                xm = mpmath.lu_solve(mpmath.matrix([em[0:3], em[3:6], em[6:9]]), mpmath.matrix(em[9:]))
                xm = np.array([float(v) for v in xm])
                rel = np.abs(x64 - xm) / np.maximum(np.abs(xm), 1e-300)
                normwise = float(np.max(np.abs(x64 - xm) / np.maximum(np.abs(xm), 1e-3 * scale)))
                cond = float(np.linalg.cond(A64))
                errors.append(normwise)
                conds.append(cond)
                k = int(np.argmax(rel))
                if rel[k] > worst["error"]:
                    worst = dict(error=float(rel[k]), unknown=str(d.unknowns[k]), theta_deg=float(t_deg),
                                 beta_deg=float(b_deg), value=float(xm[k]), condition_number=cond,
                                 normwise_error=normwise)
    errors, conds = np.array(errors), np.array(conds)
    i = int(np.argmax(errors))
    return dict(
        subgrid=dict(theta_deg=[1.0, 89.0], beta_deg=[1.0, 179.0], points=[SUBGRID, SUBGRID]),
        reference="mpmath 50 digits, same lambdified system, exact decimal parameters",
        largest_componentwise_relative_error=worst,
        largest_normwise_error=dict(error=float(errors[i]), condition_number=float(conds[i])),
        median_normwise_error=float(np.median(errors)),
        condition_number_range=[float(conds.min()), float(conds.max())],
        error_over_cond_eps_max=float(np.max(errors / (conds * np.finfo(float).eps))),
    )


def main() -> int:
    warnings.simplefilter("ignore")
    OUT.mkdir(parents=True, exist_ok=True)
    t_all = time.perf_counter()
    wp = work_precision()
    plot(wp, OUT / "work_precision.svg")
    tp = throughput()
    fe = float_vs_exact()
    result = dict(
        benchmark="dynamics",
        machine=dict(python=platform.python_version(), platform=platform.platform(), processor=platform.machine()),
        work_precision=wp,
        throughput=tp,
        float64_vs_mpmath=fe,
        total_s=time.perf_counter() - t_all,
    )
    (OUT / "dynamics.json").write_text(json.dumps(result, indent=2))

    print(f"dynamics bench ({result['total_s']:.1f} s); wrote {OUT / 'dynamics.json'} and work_precision.svg")
    print(f"  reference: mpmath 30 vs 40 digits agree to {wp['reference_agreement_30_vs_40_digits']:.1e}")
    print("  Example 2 period, cheapest model per accuracy over amplitudes 5..170 deg (worst-case time):")
    for target, c in wp["cheapest_per_accuracy"].items():
        if c is None:
            print(f"    {target:>6}: none reached it at every amplitude")
        else:
            setting = "" if c["setting"] is None else f" at {c['setting']:g}"
            print(f"    {target:>6}: {c['method']}{setting}, {c['max_time_s'] * 1e3:.2f} ms, "
                  f"max error {c['max_error']:.1e}")
    lin = [r for r in wp["rows"] if r["method"] == "linear"]
    print(f"  linearized formula (Eq. 46), {max(r['time_s'] for r in lin) * 1e6:.1f} us per call; relative error: "
          + ", ".join(f"{r['amplitude_deg']} deg {r['error']:.1e}" for r in lin))
    print("  time to reach each accuracy at every amplitude [ms] (- = not reached):")
    for m, d in wp["time_to_accuracy"].items():
        cells = "  ".join(f"{k}:{'-' if v is None else f'{v * 1e3:.2f}'}" for k, v in d.items())
        print(f"    {m:<10} {cells}")
    print(f"  Example 1 instantaneous solve, {tp['configurations']:,} configurations:")
    print(f"    vectorised closed form   {tp['vectorised_closed_form']['rate_per_s']:.3g} /s")
    print(f"    vectorised batched solve {tp['vectorised_batched_solve']['rate_per_s']:.3g} /s")
    print(f"    per-configuration loop   {tp['per_configuration_loop']['rate_per_s']:.3g} /s "
          f"(timed on {LOOP_SUBSET:,}, extrapolated {tp['per_configuration_loop']['extrapolated_full_grid_s']:.1f} s)")
    print(f"    sympy.physics.mechanics  {tp['sympy_mechanics_lagrange']['rate_per_s']:.3g} /s "
          f"(+ {tp['sympy_mechanics_lagrange']['derive_and_compile_s']:.2f} s to derive and compile)")
    print(f"    target >= {TARGET_RATE:.0e}/s met: {tp['target_met']}")
    w = fe["largest_componentwise_relative_error"]
    print(f"  float64 vs mpmath (50 digits): largest relative error {w['error']:.2e} in {w['unknown']} at "
          f"theta = {w['theta_deg']:.4g} deg, beta = {w['beta_deg']:.4g} deg (value {w['value']:.3g}, "
          f"condition number {w['condition_number']:.3g}); normwise max {fe['largest_normwise_error']['error']:.2e} "
          f"at cond {fe['largest_normwise_error']['condition_number']:.3g}; condition numbers "
          f"{fe['condition_number_range'][0]:.3g}..{fe['condition_number_range'][1]:.3g}, "
          f"max error / (cond eps) = {fe['error_over_cond_eps_max']:.2g}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
