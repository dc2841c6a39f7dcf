"""Benchmark: `eom` and `explain` on the paper's scenes against sympy.physics.mechanics, side by side.

For each of the two paper scenes (Example 1, sliding bar; Example 2, disk-bar):

* ours: the whole command in this process (``python -m solver eom SCENE`` and
  ``python -m solver explain SCENE``, output discarded): a new System from the
  scene file, the derivation, the display forms and the printing;
* KanesMethod: the same body built directly with sympy.physics.mechanics
  (frames, points, rigid bodies, gravity, ``kanes_equations``, then
  ``mass_matrix`` and ``forcing``), the tool a user would otherwise pick.
  It gives the equation of motion only, not the reactions nor a worked solution.

Each run is cold for this project (new System; the display caches cleared);
sympy's own cache serves both sides alike. Median of repeated runs, each with the
garbage collector off as ``timeit`` does, in CPU time of this process (the machine is shared: wall time would measure the neighbours). Target
(issue 11/12): ours at most half of KanesMethod (ratio <= 0.5).

Last figures (2026-11-25, 23:40 UTC, branch xpd_build, 2 cores shared at load 2-4; main measured
alongside in the same minutes, three runs each): sliding_bar KanesMethod 19-23 ms, eom 6-7 ms
(0.3-0.4x), explain 18-20 ms (0.8-0.9x; main 20-27 ms, 0.9-1.2x); disk_bar KanesMethod 23-25 ms, eom
5-9 ms (0.2-0.4x), explain 22-24 ms (0.9-1.0x; main 23-28 ms, 1.0x). Where explain's time goes
(sliding_bar, wall time per run): tidying and printing the displayed forms about 7 ms; the scene file,
the placement and the two formulations about 5 ms (eom pays most of them too); the numbers at the
state (the equations with the data entered, both formulations' matrices, the advisor) about 3 ms.
disk_bar's contact adds the regime search twice (generalized Euler, then the mass-centre check),
about 7 ms, most of it compiling the contact kinematics and the numeric models. Under the neighbours'
load every figure moves by up to a half.

Writes reports/build/bench/explain.json.
"""
from __future__ import annotations

import contextlib
import gc
import io
import json
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

RUNS = 9
SCENES = {"sliding_bar": ROOT / "data/scenes/sliding_bar.toml", "disk_bar": ROOT / "data/scenes/disk_bar.toml"}


def kane_sliding_bar() -> None:
    th, u = me.dynamicsymbols("theta u")
    m, l, beta, g = sp.symbols("m_b l_b beta g", positive=True)
    N = me.ReferenceFrame("N")
    B = N.orientnew("B", "Axis", [sp.pi - th, N.z])
    B.set_ang_vel(N, -u * N.z)
    O = me.Point("O")
    O.set_vel(N, 0)
    # A on the horizontal rail, B on the rail at -beta (Eq. 19): x_A from the rail geometry
    xA = l * (sp.sin(beta) * sp.cos(th) - sp.sin(th) * sp.cos(beta)) / sp.sin(beta)
    A = O.locatenew("A", xA * N.x)
    A.set_vel(N, A.pos_from(O).dt(N).subs(th.diff(), u))
    G = A.locatenew("G", l / 2 * B.x)
    G.v2pt_theory(A, N, B)
    bar = me.RigidBody("bar", G, B, m, (me.inertia(B, 0, 0, m * l**2 / 12), G))
    km = me.KanesMethod(N, q_ind=[th], u_ind=[u], kd_eqs=[th.diff() - u])
    km.kanes_equations([bar], [(G, -m * g * N.y)])
    km.mass_matrix, km.forcing  # noqa: B018 - force evaluation


def kane_disk_bar() -> None:
    th, u = me.dynamicsymbols("theta u")
    md, rd, mb, lb, g, Fa = sp.symbols("m_d r_d m_b l_b g F_a", real=True)
    N = me.ReferenceFrame("N")
    D = N.orientnew("D", "Axis", [-th, N.z])
    D.set_ang_vel(N, -u * N.z)
    O = me.Point("O")
    O.set_vel(N, 0)
    P = O.locatenew("P", rd * th * N.x + rd * N.y)  # rolling without slipping (Eq. 31)
    P.set_vel(N, rd * u * N.x)
    Q = P.locatenew("Q", -lb / 2 * D.y)
    Q.v2pt_theory(P, N, D)
    disk = me.RigidBody("disk", P, D, md, (me.inertia(D, 0, 0, md * rd**2 / 2), P))
    bar = me.RigidBody("bar", Q, D, mb, (me.inertia(D, 0, 0, mb * lb**2 / 12), Q))
    km = me.KanesMethod(N, q_ind=[th], u_ind=[u], kd_eqs=[th.diff() - u])
    km.kanes_equations([disk, bar], [(P, -md * g * N.y + Fa * N.x), (Q, -mb * g * N.y)])
    km.mass_matrix, km.forcing  # noqa: B018


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


def main_bench() -> dict:
    out = {"runs": RUNS, "target_ratio": 0.5, "scenes": {}}
    for name, path in SCENES.items():
        kane = median_time(KANE[name])
        eom = median_time(command, "eom", str(path))
        explain = median_time(command, "explain", str(path))
        out["scenes"][name] = {
            "kanes_method_s": kane, "eom_s": eom, "explain_s": explain,
            "eom_ratio": eom / kane, "explain_ratio": explain / kane,
            "eom_meets_target": eom / kane <= 0.5, "explain_meets_target": explain / kane <= 0.5,
        }
        print(f"{name}: KanesMethod {kane * 1e3:.0f} ms; eom {eom * 1e3:.0f} ms ({eom / kane:.1f}x); "
              f"explain {explain * 1e3:.0f} ms ({explain / kane:.1f}x)")
    return out


if __name__ == "__main__":
    result = main_bench()
    target = ROOT / "reports" / "build" / "bench" / "explain.json"
    target.parent.mkdir(parents=True, exist_ok=True)
    target.write_text(json.dumps(result, indent=2) + "\n", encoding="utf-8")
    print(f"wrote {target.relative_to(ROOT)}")
