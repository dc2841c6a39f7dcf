"""Benchmark: the multibody core against sympy.physics.mechanics, side by side in one run.

1. Deriving the equations of the double pendulum and of the slider-crank: this
   project (scene file -> System -> Newton and the generalized Euler equation
   about each body's point -> linear system A x = b) against KanesMethod on
   the same systems built directly with sympy.physics.mechanics (frames,
   points, bodies, kanes_equations; the slider-crank with the crank angle as
   the coordinate and the rod angle and piston position as dependent ones).
   Cold: every run builds from nothing (new System, new symbols); CPU time,
   least of 7 runs of each in this process, the two sides alternating (the
   machine is shared: other load only adds time).
2. The instantaneous solve of a 4-body chain (four pinned bars, 4 coordinates,
   8 reactions: a 12 x 12 system) vectorised over 1e6 random states (the
   structured solve of solver/analyses/structured.py); best of 5, in CPU time
   and wall time.

Writes reports/build/bench/multibody.json.
"""
from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

sys.path.insert(0, str(ROOT / "tests"))

from scenes_factory import chain_toml  # noqa: E402
from solver.formulations import formulate  # noqa: E402
from solver.io.scenes import load_system  # noqa: E402

CHAIN = chain_toml((0.1, 0.2, 0.3, 0.4))


def ours(path: Path) -> float:
    t0 = time.process_time()
    system = load_system(path)
    formulate(system).linear_system()
    return time.process_time() - t0


def kane_double_pendulum() -> float:
    import sympy as sp
    from sympy.physics import mechanics as me

    t0 = time.process_time()
    q1, q2 = me.dynamicsymbols("q1 q2")
    u1, u2 = me.dynamicsymbols("u1 u2")
    m1, m2, l1, l2, g = sp.symbols("m1 m2 l1 l2 g", positive=True)
    N = me.ReferenceFrame("N")
    A = N.orientnew("A", "Axis", [q1, N.z])
    B = N.orientnew("B", "Axis", [q2, N.z])
    A.set_ang_vel(N, u1 * N.z)
    B.set_ang_vel(N, u2 * N.z)
    O = me.Point("O")
    O.set_vel(N, 0)
    P = O.locatenew("P", l1 * A.x)
    P.v2pt_theory(O, N, A)
    R = P.locatenew("R", l2 * B.x)
    R.v2pt_theory(P, N, B)
    bodies = [me.Particle("p1", P, m1), me.Particle("p2", R, m2)]
    loads = [(P, -m1 * g * N.y), (R, -m2 * g * N.y)]
    km = me.KanesMethod(N, q_ind=[q1, q2], u_ind=[u1, u2], kd_eqs=[q1.diff() - u1, q2.diff() - u2])
    km.kanes_equations(bodies, loads)
    km.mass_matrix, km.forcing  # noqa: B018 - force evaluation
    return time.process_time() - t0


def kane_slider_crank() -> float:
    import sympy as sp
    from sympy.physics import mechanics as me

    t0 = time.process_time()
    th, ph, x = me.dynamicsymbols("theta phi x")
    w1, w2, v = me.dynamicsymbols("w1 w2 v")
    r, l, mc, ms, mp, g = sp.symbols("r l m_c m_s m_p g", positive=True)
    N = me.ReferenceFrame("N")
    C = N.orientnew("C", "Axis", [th, N.z])
    Rf = N.orientnew("R", "Axis", [ph, N.z])
    C.set_ang_vel(N, w1 * N.z)
    Rf.set_ang_vel(N, w2 * N.z)
    O = me.Point("O")
    O.set_vel(N, 0)
    A = O.locatenew("A", r * C.x)
    A.v2pt_theory(O, N, C)
    B = A.locatenew("B", l * Rf.x)
    B.v2pt_theory(A, N, Rf)
    Pp = O.locatenew("Pp", x * N.x)
    Pp.set_vel(N, v * N.x)
    Gc = O.locatenew("Gc", r / 2 * C.x)
    Gc.v2pt_theory(O, N, C)
    Gr = A.locatenew("Gr", l / 2 * Rf.x)
    Gr.v2pt_theory(A, N, Rf)
    crank = me.RigidBody("crank", Gc, C, mc, (me.inertia(C, 0, 0, mc * r**2 / 12), Gc))
    rod = me.RigidBody("rod", Gr, Rf, ms, (me.inertia(Rf, 0, 0, ms * l**2 / 12), Gr))
    piston = me.Particle("piston", Pp, mp)
    loop = B.pos_from(O) - x * N.x
    conf = [loop.dot(N.x), loop.dot(N.y)]
    vel = [sp.diff(c, me.dynamicsymbols._t).subs({th.diff(): w1, ph.diff(): w2, x.diff(): v}) for c in conf]
    km = me.KanesMethod(N, q_ind=[th], q_dependent=[ph, x], u_ind=[w1], u_dependent=[w2, v],
                        kd_eqs=[th.diff() - w1, ph.diff() - w2, x.diff() - v],
                        configuration_constraints=conf, velocity_constraints=vel)
    loads = [(Gc, -mc * g * N.y), (Gr, -ms * g * N.y), (Pp, -mp * g * N.y)]
    km.kanes_equations([crank, rod, piston], loads)
    km.mass_matrix, km.forcing  # noqa: B018
    return time.process_time() - t0


def best_of_alternating(f, g, n=7) -> tuple[float, float]:
    """Least CPU time of n runs of f and of g, run in turns."""
    a, b = [], []
    for _ in range(n):
        a.append(f())
        b.append(g())
    return min(a), min(b)


def main() -> None:
    out = ROOT / "reports" / "build" / "bench"
    out.mkdir(parents=True, exist_ok=True)
    ours(ROOT / "data/scenes/double_pendulum.toml")  # imports and registries loaded once, as for Kane
    kane_double_pendulum()
    rows = {}
    for name, path, kane in (("double_pendulum", ROOT / "data/scenes/double_pendulum.toml", kane_double_pendulum),
                             ("slider_crank", ROOT / "data/scenes/slider_crank.toml", kane_slider_crank)):
        a, b = best_of_alternating(lambda: ours(path), kane)
        rows[name] = {"ours_s": a, "kanes_method_s": b, "ratio": a / b}
        print(f"derive {name:16s} ours {a * 1e3:8.1f} ms   KanesMethod {b * 1e3:8.1f} ms   ratio {a / b:.2f}")

    tmp = out / "chain4.toml"
    tmp.write_text(CHAIN)
    system = load_system(tmp)
    model = formulate(system).numeric()
    model.structured()  # built once per model, like the lambdified functions
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 1_000_000
    rng = np.random.default_rng(0)
    q = [rng.uniform(-1.5, 1.5, n) for _ in range(4)]
    qd = [rng.uniform(-2, 2, n) for _ in range(4)]
    runs = []
    for _ in range(5):  # best of 5: the machine is shared
        c0, w0 = time.process_time(), time.perf_counter()
        res = model.solve(q, qd, 0.0)
        runs.append((time.process_time() - c0, time.perf_counter() - w0))
        assert np.all(np.isfinite(res["q1_ddot"]))
    cpu, wall = min(r[0] for r in runs), min(r[1] for r in runs)
    # numpy here runs on one thread, so CPU time is the wall time of an idle machine
    rows["chain4_solve"] = {"states": n, "cpu_seconds": cpu, "wall_seconds": wall,
                            "states_per_second": n / cpu, "states_per_wall_second": n / wall}
    print(f"4-body chain, {n:.0e} states: {cpu:.2f} s CPU ({wall:.2f} s wall), {n / cpu:.3g} states/s")
    (out / "multibody.json").write_text(json.dumps(rows, indent=2))


if __name__ == "__main__":
    main()
