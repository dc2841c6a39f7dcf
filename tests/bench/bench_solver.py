"""Time the solver on the two example scenes, against sympy.physics.mechanics.

For each scene: load the TOML, derive (generalized Euler about the default
point; cache cleared before each repeat), eliminate to the equation of motion,
lambdify, solve one instant, and the whole cold path; then the same problem
built and solved through sympy.physics.mechanics (Kane's method with
auxiliary speeds; and LagrangesMethod for the equation of motion). Caches
(ours and sympy's) are cleared before every cold repeat.

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

from solver.derivation import clear_cache as clear_derivations  # noqa: E402
from solver.derivation import derive, solve_instant  # noqa: E402
from solver.lagrange import lagrange_route  # noqa: E402
from solver.scenefile import load_scene  # noqa: E402

SCENES = {"sliding_bar": ROOT / "data/scenes/sliding_bar.toml", "disk_bar": ROOT / "data/scenes/disk_bar.toml"}
OUT = ROOT / "reports/build/bench/solver.json"
REPEATS = 5


def clear_cache():
    """Cold start: forget our derivations and sympy's own expression cache."""
    clear_derivations()
    clear_sympy_cache()


def timed(fn, repeats=REPEATS, setup=None):
    """Wall-clock seconds of ``fn()`` over ``repeats`` runs (``setup()`` untimed before each)."""
    times = []
    for _ in range(repeats):
        if setup:
            setup()
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return {"median_s": statistics.median(times), "min_s": min(times), "max_s": max(times), "repeats": repeats}


def bench_scene(path: Path) -> dict:
    scene = load_scene(path)
    out = {}
    out["load"] = timed(lambda: load_scene(path))
    out["derive"] = timed(lambda: derive(scene).linear_system(), setup=clear_cache)
    out["eom"] = timed(lambda: derive(scene).eom, setup=clear_cache)
    out["lambdify"] = timed(lambda: derive(scene).numeric(), setup=clear_cache)
    derive(scene).numeric()
    out["solve_instant_warm"] = timed(lambda: solve_instant(scene), repeats=50)
    out["cold_load_derive_solve"] = timed(lambda: solve_instant(load_scene(path)), setup=clear_cache)
    # sympy.physics.mechanics: Kane's equations + auxiliary speeds, then the same numeric solve
    out["mechanics_kane_build"] = timed(lambda: lagrange_route(scene, "kane"), setup=clear_cache, repeats=3)
    out["mechanics_lagranges_method_build"] = timed(
        lambda: lagrange_route(scene, "lagrange"), setup=clear_cache, repeats=3
    )
    out["mechanics_cold_derive_solve"] = timed(
        lambda: solve_instant(scene, method="lagrange"), setup=clear_cache, repeats=3
    )
    out["mass_center_cold_derive_solve"] = timed(
        lambda: solve_instant(scene, method="mass_center"), setup=clear_cache
    )
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
