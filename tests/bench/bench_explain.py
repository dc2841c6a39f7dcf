"""Benchmark: `eom` and `explain` on the paper's scenes against sympy.physics.mechanics, side by side.

For each of the two paper scenes (Example 1, sliding bar; Example 2, disk-bar):

* ours: the whole command in this process (``python -m solver eom SCENE`` and
  ``python -m solver explain SCENE``, output discarded): a new System from the
  scene file, the derivation, the display forms and the printing;
* KanesMethod, the tool a user would otherwise pick, building the same equations
  that ``eom`` prints: the equation of motion (``kanes_equations``, ``mass_matrix``,
  ``forcing``) and the reactions as functions of the state. Kane's method leaves the
  reactions out, so they are brought in as Kane and Levinson do, with auxiliary speeds
  (the body translated along the reactions' directions), and the auxiliary equations,
  with u' from the equation of motion entered, are solved as the linear system they
  are (``linear_eq_to_matrix``, ``LUsolve``; ``sympy.solve`` would take 4 times as
  long). Before timing, the bench checks that these reactions equal ``eom``'s at the
  state (:func:`check_same_reactions`), so both sides are proven to build the same
  equations. This is the target's comparison (issue 11: "building the same equations").
  The equation of motion alone (no auxiliary speeds) is timed too and its ratios are
  written beside (``*_ratio_to_eom_only``), because that is the smaller job.

Each run is cold for this project (new System; the display caches cleared);
sympy's own cache serves both sides alike. Median of repeated runs, each with the
garbage collector off as ``timeit`` does, in CPU time of this process (the machine is
shared: wall time would measure the neighbours). Target (issues 11/12): ours at most half
of KanesMethod (ratio <= 0.5).

Figures (2026-11-26, 03:35 UTC, two runs on an idle machine): sliding_bar KanesMethod 40 ms (the
equation of motion alone 19 ms), eom 7 ms (0.17-0.19x; 0.35-0.39x the equation of motion alone),
explain 14-16 ms (0.35-0.40x; 0.72-0.86x); disk_bar KanesMethod 44-45 ms (22-23 ms), eom 6-7 ms
(0.15-0.17x; 0.29-0.33x), explain 16-19 ms (0.36-0.43x; 0.72-0.84x). Where explain's time goes
(sliding_bar, thread CPU per run, fastest of 25, 2026-11-26 04:30 UTC, a loaded machine): the scene
load 2.2 ms, the Euler step 2.4 (its moment equation collected by unknown 1.0), the formulations 2.0,
the equation of motion 1.6, the kinematics 1.5, the rendering 1.4, the advisor 1.0 (and its rows at
the state 0.5), the numbers at the state 0.9, the mass-centre check 0.8; tidying about 3 ms of these
and printing about 2. The numbers at the state come from one walk of each equation's tree
(tree_value.affine_value), not from the symbolic linear system. disk_bar's contact adds the regime
search, once (about 2.6 ms: the mass-centre check solves in the regime found and tests its
conditions again, without a second search; the contact kinematics are walked, not compiled, for the
state's few calls). Under the neighbours' load every figure moves by up to a half.

Writes reports/build/bench/explain.json.
"""
from __future__ import annotations

import contextlib
import gc
import io
import json
import math
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

import sympy as sp  # noqa: E402
from sympy.physics import mechanics as me  # noqa: E402

from solver.__main__ import main  # noqa: E402
from solver.display import is_identically_zero, tidy  # noqa: E402
from solver.io.scenes import load_system  # noqa: E402
from solver.units import ureg  # noqa: E402

RUNS = 9
SCENES = {"sliding_bar": ROOT / "data/scenes/sliding_bar.toml", "disk_bar": ROOT / "data/scenes/disk_bar.toml"}


def kane_sliding_bar(reactions: bool = True):
    """Example 1 with KanesMethod: the equation of motion and, with ``reactions``, the rail reactions
    R_A, R_B as functions of the state (auxiliary speeds: the bar translated along the two rails'
    normals, as Kane and Levinson bring non-contributing forces into evidence)."""
    th, u, ua, ub = me.dynamicsymbols("theta u ua ub")
    m, l, beta, g = sp.symbols("m_b l_b beta g", positive=True)
    R_A, R_B = sp.symbols("R_A R_B")
    N = me.ReferenceFrame("N")
    B = N.orientnew("B", "Axis", [sp.pi - th, N.z])
    B.set_ang_vel(N, -u * N.z)
    O = me.Point("O")
    O.set_vel(N, 0)
    n_B = sp.sin(beta) * N.x + sp.cos(beta) * N.y  # the inclined rail's normal at B (Eq. 21)
    # A on the horizontal rail, B on the rail at -beta (Eq. 19): x_A from the rail geometry
    xA = l * (sp.sin(beta) * sp.cos(th) - sp.sin(th) * sp.cos(beta)) / sp.sin(beta)
    A = O.locatenew("A", xA * N.x)
    A.set_vel(N, A.pos_from(O).dt(N).subs(th.diff(), u) + ((ua * N.y + ub * n_B) if reactions else 0))
    G = A.locatenew("G", l / 2 * B.x)
    G.v2pt_theory(A, N, B)
    bar = me.RigidBody("bar", G, B, m, (me.inertia(B, 0, 0, m * l**2 / 12), G))
    loads = [(G, -m * g * N.y)]
    if reactions:
        Bp = A.locatenew("B", l * B.x)
        Bp.v2pt_theory(A, N, B)
        loads += [(A, R_A * N.y), (Bp, R_B * n_B)]
    return _kane_equations(N, th, u, [ua, ub] if reactions else [], [bar], loads, [R_A, R_B])


def kane_disk_bar(reactions: bool = True):
    """Example 2 with KanesMethod: the equation of motion and, with ``reactions``, the floor's
    friction F_f and normal force F_n at the contact C as functions of the state (auxiliary speeds:
    the composite translated along i and j)."""
    th, u, ua, ub = me.dynamicsymbols("theta u ua ub")
    md, rd, mb, lb, g, Fa = sp.symbols("m_d r_d m_b l_b g F_a", real=True)
    F_f, F_n = sp.symbols("F_f F_n")
    N = me.ReferenceFrame("N")
    D = N.orientnew("D", "Axis", [-th, N.z])
    D.set_ang_vel(N, -u * N.z)
    O = me.Point("O")
    O.set_vel(N, 0)
    P = O.locatenew("P", rd * th * N.x + rd * N.y)  # rolling without slipping (Eq. 31)
    P.set_vel(N, rd * u * N.x + ((ua * N.x + ub * N.y) if reactions else 0))
    Q = P.locatenew("Q", -lb / 2 * D.y)
    Q.v2pt_theory(P, N, D)
    disk = me.RigidBody("disk", P, D, md, (me.inertia(D, 0, 0, md * rd**2 / 2), P))
    bar = me.RigidBody("bar", Q, D, mb, (me.inertia(D, 0, 0, mb * lb**2 / 12), Q))
    loads = [(P, -md * g * N.y + Fa * N.x), (Q, -mb * g * N.y)]
    if reactions:
        C = P.locatenew("C", -rd * N.y)  # the contact point (Eq. 32)
        C.v2pt_theory(P, N, D)
        loads.append((C, F_f * N.x + F_n * N.y))
    return _kane_equations(N, th, u, [ua, ub] if reactions else [], [disk, bar], loads, [F_f, F_n])


def _kane_equations(N, th, u, aux, bodies, loads, unknowns) -> dict:
    """``kanes_equations``, then M and the forcing; with auxiliary speeds also the reactions as
    functions of the state: the auxiliary equations with u' = forcing/M entered, solved as the
    linear system they are (``linear_eq_to_matrix`` and ``LUsolve``)."""
    km = me.KanesMethod(N, q_ind=[th], u_ind=[u], kd_eqs=[th.diff() - u], u_auxiliary=aux)
    km.kanes_equations(bodies, loads)
    mass, forcing = km.mass_matrix, km.forcing
    if not aux:
        return {}
    equations = km.auxiliary_eqs.subs(u.diff(), forcing[0] / mass[0, 0])
    a, b = sp.linear_eq_to_matrix(list(equations), unknowns)
    solved = a.LUsolve(b)
    state = {th: sp.Symbol("theta"), u: sp.Symbol("theta_dot")}
    return {str(r): solved[i].xreplace(state) for i, r in enumerate(unknowns)}


KANE = {"sliding_bar": kane_sliding_bar, "disk_bar": kane_disk_bar}


def command(*argv: str) -> None:
    tidy.cache_clear()
    is_identically_zero.cache_clear()
    with contextlib.redirect_stdout(io.StringIO()):
        status = main(list(argv))
    if status != 0:
        raise SystemExit(f"{argv}: exit status {status}")


def median_time(fn, *args) -> float:
    """Median CPU time of ``RUNS`` calls, each with the garbage collector off (as ``timeit``
    does: a full collection over sympy's cache lands on whichever call triggers it)."""
    fn(*args)  # warm-up: imports
    times = []
    for _ in range(RUNS):
        gc.collect()
        gc.disable()
        try:
            t0 = time.process_time()
            fn(*args)
            times.append(time.process_time() - t0)
        finally:
            gc.enable()
    return statistics.median(times)


def check_same_reactions(name: str, path: Path) -> dict:
    """The KanesMethod side builds the same equations as ``eom``: its reactions, evaluated at the
    scene's state with the scene's SI values, equal the values ``eom --json`` prints (converted
    to newtons). Relative tolerance 1e-9: both are double-precision evaluations of exact
    expressions of a few hundred operations (about 1e-14 apart in practice); a wrong
    direction, point or sign in either would differ in the first digits."""
    system = load_system(path)
    coordinate = system.coordinates[0]
    values = {s.name: v for s, v in system.si_values().items()}
    values.update(theta=coordinate.value, theta_dot=coordinate.rate)
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        main(["eom", str(path), "--json"])
    ours = json.loads(printed.getvalue())["reactions_at_state"]
    compared = {}
    for reaction, expr in KANE[name]().items():
        kane = float(expr.xreplace({s: values[s.name] for s in expr.free_symbols}))
        mine = ureg.Quantity(ours[reaction]["value"], ours[reaction]["unit"]).to("N").magnitude
        if not math.isclose(kane, mine, rel_tol=1e-9):
            raise SystemExit(f"bench: {name} {reaction}: KanesMethod gives {kane!r} N, eom {mine!r} N")
        compared[reaction] = {"kanes_method_N": kane, "eom_N": mine}
    return compared


def main_bench() -> dict:
    out = {"runs": RUNS, "target_ratio": 0.5, "scenes": {}}
    for name, path in SCENES.items():
        same = check_same_reactions(name, path)
        kane = median_time(KANE[name])
        kane_eom = median_time(KANE[name], False)
        eom = median_time(command, "eom", str(path))
        explain = median_time(command, "explain", str(path))
        out["scenes"][name] = {
            "kanes_method_s": kane, "kanes_method_eom_only_s": kane_eom, "eom_s": eom, "explain_s": explain,
            "eom_ratio": eom / kane, "explain_ratio": explain / kane,
            "eom_ratio_to_eom_only": eom / kane_eom, "explain_ratio_to_eom_only": explain / kane_eom,
            "eom_meets_target": eom / kane <= 0.5, "explain_meets_target": explain / kane <= 0.5,
            "reactions_compared": same,
        }
        print(f"{name}: KanesMethod {kane * 1e3:.0f} ms (equation of motion alone {kane_eom * 1e3:.0f} ms); "
              f"eom {eom * 1e3:.0f} ms ({eom / kane:.2f}x; {eom / kane_eom:.2f}x the EOM alone); "
              f"explain {explain * 1e3:.0f} ms ({explain / kane:.2f}x; {explain / kane_eom:.2f}x the EOM alone)")
    return out


if __name__ == "__main__":
    result = main_bench()
    target = ROOT / "reports" / "build" / "bench" / "explain.json"
    target.parent.mkdir(parents=True, exist_ok=True)
    target.write_text(json.dumps(result, indent=2) + "\n", encoding="utf-8")
    print(f"wrote {target.relative_to(ROOT)}")
