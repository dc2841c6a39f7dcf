"""Time the solver's stages on the two example scenes, each route side by side.

For each scene: load the TOML; derive the linear system (generalized Euler about the default
point) and compile it; solve one instant warm; the whole cold path (load, derive, solve); and the
same instant by the mass-centre route and by the Lagrange route, which runs sympy.physics.mechanics'
LagrangesMethod. "Cold" is a freshly loaded scene (derivations are cached on it) with sympy's
expression cache cleared, untimed, before each repeat. The side-by-side comparison with
KanesMethod building the same equations is tests/bench/bench_explain.py (eom) and
tests/bench/bench_multibody.py (derivation).

Writes reports/build/bench/solver.json and prints a table. Run: make bench
(or .venv/bin/python tests/bench/bench_solver.py).
"""
from __future__ import annotations

import json
import platform
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

import sympy  # noqa: E402

from sympy.core.cache import clear_cache as clear_sympy_cache  # noqa: E402

from solver.derivation import derive, solve_instant  # noqa: E402
from solver.scenefile import load_scene  # noqa: E402

SCENES = {"sliding_bar": ROOT / "data/scenes/sliding_bar.toml", "disk_bar": ROOT / "data/scenes/disk_bar.toml"}
OUT = ROOT / "reports/build/bench/solver.json"
REPEATS = 5


def cold(path: Path) -> dict:
    """A fresh scene (our derivations are cached on it) and sympy's cache cleared: a cold start."""
    clear_sympy_cache()
    return {"scene": load_scene(path)}


def timed(fn, repeats=REPEATS, setup=None):
    """Wall-clock seconds of ``fn(state)`` over ``repeats`` runs, ``state = setup()`` made untimed
    before each (``{}`` without a setup)."""
    times = []
    for _ in range(repeats):
        state = setup() if setup else {}
        t0 = time.perf_counter()
        fn(state)
        times.append(time.perf_counter() - t0)
    return {"median_s": statistics.median(times), "min_s": min(times), "max_s": max(times), "repeats": repeats}


def bench_scene(path: Path) -> dict:
    fresh = lambda: cold(path)  # noqa: E731
    out = {"load": timed(lambda _: load_scene(path))}
    out["derive"] = timed(lambda s: derive(s["scene"]).linear_system(), setup=fresh)
    out["derive_and_compile"] = timed(lambda s: derive(s["scene"]).numeric(), setup=fresh)
    warm = load_scene(path)
    solve_instant(warm)
    out["solve_instant_warm"] = timed(lambda _: solve_instant(warm), repeats=50)
    out["cold_load_derive_solve"] = timed(lambda _: solve_instant(load_scene(path)),
                                          setup=lambda: clear_sympy_cache() or {})
    out["mass_center_cold_derive_solve"] = timed(lambda s: solve_instant(s["scene"], method="mass_center"),
                                                 setup=fresh)
    out["lagrange_cold_derive_solve"] = timed(lambda s: solve_instant(s["scene"], method="lagrange"),
                                              setup=fresh, repeats=3)
    return out


def main() -> int:
    results = {name: bench_scene(path) for name, path in SCENES.items()}
    payload = {
        "benchmark": "solver",
        "python": platform.python_version(),
        "sympy": sympy.__version__,
        "machine": platform.machine(),
        "unit": "seconds (wall clock, perf_counter)",
        "results": results,
    }
    OUT.parent.mkdir(parents=True, exist_ok=True)
    OUT.write_text(json.dumps(payload, indent=2))
    stages = list(next(iter(results.values())))
    width = max(len(s) for s in stages)
    print(f"{'stage':<{width}}  " + "  ".join(f"{n:>14}" for n in results))
    for stage in stages:
        row = "  ".join(f"{results[n][stage]['median_s'] * 1e3:>11.2f} ms" for n in results)
        print(f"{stage:<{width}}  {row}")
    print(f"(medians; written to {OUT.relative_to(ROOT)})")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
