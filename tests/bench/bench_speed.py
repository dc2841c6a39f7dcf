"""Benchmark: speed where users wait (issue 12), every target side by side in one run.

CPU time (user + system, ``resource.getrusage``) rather than wall time: the machine
is shared (2 cores, several developers), and CPU time is what a command costs
whatever else runs. Each figure is the median of a few runs; each ratio is against
the tool a user would otherwise pick, measured in the same run.

1. Start-up of whole commands (children's CPU time), against the floor
   ``python -c "import numpy, scipy"`` plus a small ``scipy.integrate.quad``:
   ``solver --help`` and ``analysis --help`` at most 1.5x, ``solve`` and ``frequency``
   on a shipped scene at most 3x, ``period --tol 1e-12`` at most 4x, ``eom`` at most 6x.
   Every command runs once before it is timed (compiled bytecode and pint's definition
   cache exist, as for a user's second command).
2. The exact period of Example 2 (data/scenes/disk_bar.toml) to 1e-12, in process, at
   every amplitude 1..179 deg: :func:`solver.period.exact_period` (the closed form in
   elliptic integrals, which this scene's structure admits; at most 20 us a call and
   at most 3x the quadrature below) and its quadrature route (``method="quadrature"``,
   the route of scenes without a closed form), against a hand-written
   ``scipy.integrate.quad`` of the same energy integral (M = A - B cos, V = -C cos typed
   from the paper's Eqs. 44-46 with the scene's values; the faster of two ways of
   writing it at each amplitude: the substitution q = a sin u, and the algebraic
   end-point weight). The closed form's error against mpmath (tanh-sinh at 40 digits)
   at most 1e-13.
3. ``make report``: a cold build (fresh output folder; the project's bytecode written
   beforehand, as by a user's first build: the Python bytecode of solver/, analysis/ and
   reports/, and the compiled code of the report's Jinja templates, the templates' bytecode,
   written by :func:`reports.make_report.write_template_cache` into the git-ignored
   reports/__pycache__/templates/) at most 1.5x the CPU time of
   importing the build's third-party dependencies (every third-party module the build
   loads, listed by the build itself; the two timed in turns, the least of five runs
   each: on a shared machine a ratio from three moved by about 0.1); a second
   ``make report`` does nothing, in under 0.1 s.
4. ``make test``: the whole suite on 2 workers (``pytest -n 2 --dist loadfile --max-worker-restart=0``, as ``make test``) in
   under 60 s of wall time (also reported: its CPU time). ``BENCH_SKIP_TESTS=1`` skips it.

Writes reports/build/bench/speed.json: ``targets`` (one row per target: measured,
limit, unit, meets), then the details. The report shows the targets as a table.
Run: ``.venv/bin/python tests/bench/bench_speed.py`` (or ``make bench``).
"""
from __future__ import annotations

import gc
import json
import math
import os
import platform
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
OUT = ROOT / "reports" / "build" / "bench"
PY = sys.executable
SCENES = ROOT / "data" / "scenes"
FLOOR = [PY, "-c", "import numpy, scipy; from scipy.integrate import quad; quad(lambda x: x * x, 0.0, 1.0)"]
STARTUP = [  # (name, argv after python, limit as a multiple of the floor)
    ("solver --help", ["-m", "solver", "--help"], 1.5),
    ("analysis --help", ["-m", "analysis", "--help"], 1.5),
    ("solve sliding_bar", ["-m", "solver", "solve", str(SCENES / "sliding_bar.toml")], 3.0),
    ("frequency disk_bar", ["-m", "solver", "frequency", str(SCENES / "disk_bar.toml")], 3.0),
    ("period disk_bar --tol 1e-12",
     ["-m", "solver", "period", str(SCENES / "disk_bar.toml"), "--amplitude", "30 deg", "--tol", "1e-12"], 4.0),
    ("eom disk_bar", ["-m", "solver", "eom", str(SCENES / "disk_bar.toml")], 6.0),
]
REPEATS = 3
REPORT_ROUNDS = 5  # floor and cold build in turns (3. make report)
PERIOD_TOL = 1e-12
ELLIPTIC_LIMIT_US = 20.0
PERIOD_RATIO_LIMIT = 3.0
ELLIPTIC_ERROR_LIMIT = 1e-13
REPORT_RATIO_LIMIT = 1.5
NOOP_LIMIT_S = 0.1
TEST_LIMIT_S = 60.0


def _children_cpu() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def run_cpu(argv: list[str], cwd: Path = ROOT, env: dict | None = None) -> tuple[float, float, int]:
    """(CPU seconds, wall seconds, exit status) of one child process."""
    before, start = _children_cpu(), time.perf_counter()
    done = subprocess.run(argv, cwd=cwd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                          check=False)
    return _children_cpu() - before, time.perf_counter() - start, done.returncode


def median_cpu(argv: list[str], repeats: int = REPEATS) -> float:
    run_cpu(argv)  # warm: bytecode and caches as a user's second command finds them
    times = []
    for _ in range(repeats):
        cpu, _, status = run_cpu(argv)
        if status != 0:
            raise SystemExit(f"bench: {' '.join(argv)} exited with {status}")
        times.append(cpu)
    return statistics.median(times)


def cpu_per_call(*fns, min_time: float = 0.005, max_calls: int = 100_000, rounds: int = 10):
    """CPU seconds per call of each fn(), over enough calls to spend min_time: the least of ``rounds``.

    The least, as ``timeit`` advises: on a shared machine the other rounds measure the
    neighbours too (the same rule for our route and for the hand-written ``quad``). As in
    ``timeit``, the garbage collector is off while the calls are timed, and a first round
    is discarded (first-call costs are not per-call costs). Several functions are timed
    side by side, round by round in turn, so that a change in the neighbours' load falls on
    all of them alike; many short rounds (5 ms) give the least a better chance of a quiet
    moment, since a neighbour's burst can double every figure for seconds on this machine.
    Returns one figure, or a tuple with one per function."""
    for fn in fns:
        fn()
    gc.disable()
    try:
        spent = [[_round(fn, min_time, max_calls) for fn in fns] for _ in range(rounds + 1)][1:]
    finally:
        gc.enable()
    least = tuple(min(r[i] for r in spent) for i in range(len(fns)))
    return least[0] if len(fns) == 1 else least


def _round(fn, min_time: float, max_calls: int) -> float:
    calls, start = 0, time.process_time()
    while True:
        fn()
        calls += 1
        spent = time.process_time() - start
        if spent >= min_time or calls >= max_calls:
            return spent / calls


# ----------------------------------------------------------------------------- 1. start-up
def startup() -> dict:
    floor = median_cpu(FLOOR)
    rows = {}
    for name, args, limit in STARTUP:
        cpu = median_cpu([PY, *args])
        rows[name] = {"cpu_s": round(cpu, 3), "ratio": round(cpu / floor, 2), "limit": limit}
    return {"floor_cpu_s": round(floor, 3), "commands": rows}


# ----------------------------------------------------------------------------- 2. the exact period
def _disk_bar_by_hand():
    """M, V of Example 2 typed from the paper (Eqs. 44-46) with the scene's SI values."""
    import tomllib

    from solver.units import parse_quantity

    p = tomllib.loads((SCENES / "disk_bar.toml").read_text(encoding="utf-8"))["parameters"]
    v = {k: float(parse_quantity(p[k], k).to_base_units().magnitude) for k in ("m_d", "r_d", "m_b", "l_b", "g")}
    A = 1.5 * v["m_d"] * v["r_d"] ** 2 + v["m_b"] * v["r_d"] ** 2 + v["m_b"] * v["l_b"] ** 2 / 3
    B = v["m_b"] * v["r_d"] * v["l_b"]
    C = v["m_b"] * v["g"] * v["l_b"] / 2
    return A, B, C


def _quad_periods(A, B, C):
    """Two hand-written quad routes of T = 2 int sqrt(M / (2 (V(a) - V))) dq, -a..a."""
    from scipy.integrate import quad

    def by_substitution(a):
        Va = -C * math.cos(a)

        def f(u):  # q = a sin u removes both end singularities
            q = a * math.sin(u)
            dv = Va + C * math.cos(q)
            return math.sqrt((A - B * math.cos(q)) / (2 * dv)) * a * math.cos(u) if dv > 0 else \
                math.sqrt((A - B * math.cos(a)) * a / (2 * C * math.sin(a)))
        return 2 * quad(f, -math.pi / 2, math.pi / 2, epsabs=0.0, epsrel=PERIOD_TOL, limit=200)[0]

    def by_weight(a):
        Va = -C * math.cos(a)

        def f(q):  # the weight 1/sqrt((q + a)(a - q)) carries the singularities
            d = (a - q) * (q + a)
            dv = Va + C * math.cos(q)
            return math.sqrt((A - B * math.cos(q)) * d / (2 * dv)) if d > 0 and dv > 0 else \
                math.sqrt((A - B * math.cos(a)) * 2 * a / (2 * C * math.sin(a)))
        return 2 * quad(f, -a, a, weight="alg", wvar=(-0.5, -0.5), epsabs=0.0, epsrel=PERIOD_TOL, limit=200)[0]

    return by_substitution, by_weight


def _mpmath_period(A, B, C, a, dps=40):
    import mpmath

    with mpmath.workdps(dps):
        a = mpmath.mpf(a)

        def f(q):  # the raw singular integrand: tanh-sinh handles the end singularities
            dv = C * (mpmath.cos(q) - mpmath.cos(a))
            return mpmath.sqrt((A - B * mpmath.cos(q)) / (2 * dv)) if dv > 0 else mpmath.mpf(0)
        return float(2 * mpmath.quad(f, [-a, 0, a]))


def period() -> dict:
    import warnings

    from solver.derivation import derive
    from solver.io.scenes import load_system
    from solver.period import OneDofSystem, exact_period, find_equilibrium

    system = OneDofSystem.from_derivation(derive(load_system(SCENES / "disk_bar.toml"), None, "generalized_euler"),
                                          reactions=False)
    eq = find_equilibrium(system)
    A, B, C = _disk_bar_by_hand()
    subst, weight = _quad_periods(A, B, C)
    rows = []
    worst = {"elliptic_us": 0.0, "elliptic_ratio": 0.0, "quadrature_ratio": 0.0, "quad_disagreement": 0.0}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # quad's "roundoff error is detected" at the largest amplitudes
        for deg in range(1, 180):
            a = math.radians(deg)
            auto = exact_period(system, a, tol=PERIOD_TOL, equilibrium=eq)
            quadrature = exact_period(system, a, tol=PERIOD_TOL, equilibrium=eq, method="quadrature")
            t_auto, t_quadrature, t_subst, t_weight = cpu_per_call(
                lambda: exact_period(system, a, tol=PERIOD_TOL, equilibrium=eq),
                lambda: exact_period(system, a, tol=PERIOD_TOL, equilibrium=eq, method="quadrature"),
                lambda: subst(a), lambda: weight(a))
            t_quad = min(t_subst, t_weight)
            row = {"deg": deg, "model": auto.model, "auto_us": t_auto * 1e6, "quadrature_us": t_quadrature * 1e6,
                   "quad_us": t_quad * 1e6, "quad_substitution_us": t_subst * 1e6, "quad_weight_us": t_weight * 1e6,
                   "quadrature_nodes": quadrature.nodes, "quadrature_precision": quadrature.precision,
                   "quadrature_vs_auto": abs(quadrature.period - auto.period) / auto.period,
                   "quad_vs_auto": abs(subst(a) - auto.period) / auto.period}
            rows.append(row)
            worst["elliptic_us"] = max(worst["elliptic_us"], row["auto_us"])
            worst["elliptic_ratio"] = max(worst["elliptic_ratio"], t_auto / t_quad)
            worst["quadrature_ratio"] = max(worst["quadrature_ratio"], t_quadrature / t_quad)
            worst["quad_disagreement"] = max(worst["quad_disagreement"], row["quad_vs_auto"])
    errors = {}
    for deg in (1, 5, 30, 60, 90, 120, 150, 170, 175, 179):
        a = math.radians(deg)
        ref = _mpmath_period(A, B, C, a)
        errors[str(deg)] = abs(exact_period(system, a, tol=PERIOD_TOL, equilibrium=eq).period - ref) / ref
    worst["elliptic_error"] = max(errors.values())
    return {"worst": worst, "elliptic_error_vs_mpmath": errors, "amplitudes": rows}


# ----------------------------------------------------------------------------- 3. make report
_DEPS_SCRIPT = """
import json, sys, tempfile
from reports.make_report import build
with tempfile.TemporaryDirectory() as tmp:
    build(out=__import__("pathlib").Path(tmp), pdf="never", log=lambda *a: None)
ours = {"solver", "analysis", "reports", "tests"}
skip = set(sys.stdlib_module_names) | ours | {"__main__", "_distutils_hack", "_virtualenv"}
print(json.dumps(sorted(m for m in sys.modules if m.split(".")[0] not in skip and not m.startswith("_"))))
"""

# Imports every module of the list that imports on its own (a few entries of sys.modules are
# aliases or are made by their package and cannot be imported by name).
_IMPORT_ALL = """
import importlib, json, sys
for name in json.loads(sys.argv[1]):
    try:
        importlib.import_module(name)
    except Exception:
        pass
"""


def _compile_sources() -> None:
    """Write the bytecode of the project's own modules and of the report's templates, as a user's
    first ``make report`` does (``make report`` writes both even where PYTHONDONTWRITEBYTECODE is
    set, as ``make test`` does).

    A cold build means a fresh output folder, not uncompiled sources: with
    PYTHONDONTWRITEBYTECODE set (as in some shells) every timed build would compile
    solver/, analysis/ and reports/ from source again (about 0.3 s), and the Jinja templates
    (about 0.07 s), while the floor's third-party modules load from their installed bytecode.
    The templates' compiled code is written by the product's own function
    (:func:`reports.make_report.write_template_cache`), as ``compileall`` writes Python's."""
    import compileall

    from reports.make_report import write_template_cache

    for package in ("solver", "analysis", "reports"):
        compileall.compile_dir(str(ROOT / package), quiet=1)
    write_template_cache()


def report() -> dict:
    """The cold build against importing every third-party module the build loads (top-level
    packages alone would leave out e.g. scipy.integrate and matplotlib's backends, which
    ``import scipy`` and ``import matplotlib`` do not load).

    The floor and the build are timed in turns (floor, build, floor, build, ...,
    :data:`REPORT_ROUNDS` rounds), and each is the least of its runs, as :func:`cpu_per_call`
    takes (the neighbours' load only ever adds CPU time: cache and core sharing). On this shared machine a floor timed apart from the
    builds, with medians, moved the ratio by a third between runs.

    The floor is the whole ``python -c "import ..."`` process, as the issue times its floors and
    as a user would time it: the imports and the interpreter's teardown of what they loaded (about
    0.5 s of the floor's 1.9 s here). ``python -m reports`` skips its own teardown (os._exit once
    every file is written). So that this is visible, the same imports are also timed ending by
    os._exit, and the build's ratio to them is reported beside the target's
    (``cold_ratio_to_imports_without_teardown``)."""
    listed = subprocess.run([PY, "-c", _DEPS_SCRIPT], cwd=ROOT, capture_output=True, text=True, check=True)
    deps = json.loads(listed.stdout.strip().splitlines()[-1])
    importable = sorted({d.split(".")[0] for d in deps})
    _compile_sources()
    floor_argv = [PY, "-c", _IMPORT_ALL, json.dumps(deps)]
    bare_argv = [PY, "-c", _IMPORT_ALL + "import os\nos._exit(0)\n", json.dumps(deps)]
    run_cpu(floor_argv)  # warm, as median_cpu does
    floors, bare, cold = [], [], []
    for _ in range(REPORT_ROUNDS):
        floors.append(run_cpu(floor_argv)[0])
        bare.append(run_cpu(bare_argv)[0])
        with tempfile.TemporaryDirectory(prefix="bench-speed-") as tmp:
            cpu, wall, status = run_cpu([PY, "-m", "reports", "--out", str(Path(tmp) / "build"), "--pdf", "never"])
            if status != 0:
                raise SystemExit("bench: the report build failed")
            cold.append((cpu, wall))
    run_cpu(["make", "report"])  # bring reports/build up to date
    noop = [run_cpu(["make", "report"]) for _ in range(REPEATS)]
    dry = subprocess.run(["make", "-n", "report"], cwd=ROOT, capture_output=True, text=True, check=False)
    return {"deps": importable, "deps_modules": len(deps),
            "deps_import_cpu_s": round(min(floors), 3),
            "cold_build_cpu_s": round(min(c for c, _ in cold), 3),
            "cold_build_wall_s": round(min(w for _, w in cold), 3),
            "cold_ratio": round(min(c for c, _ in cold) / min(floors), 2),
            "deps_import_without_teardown_cpu_s": round(min(bare), 3),
            "cold_ratio_to_imports_without_teardown": round(min(c for c, _ in cold) / min(bare), 2),
            "pairs": [{"imports_cpu_s": round(f, 3), "cold_build_cpu_s": round(c, 3)}
                      for (c, _), f in zip(cold, floors)],
            "noop_wall_s": round(statistics.median(w for _, w, _ in noop), 4),
            "noop_cpu_s": round(statistics.median(c for c, _, _ in noop), 4),
            "noop_runs_nothing": "-m reports" not in dry.stdout}


# ----------------------------------------------------------------------------- 4. make test
def tests() -> dict:
    """``make test`` itself, after a collection that writes the bytecode of the project and of
    pytest's rewritten test modules (as a user's first run does)."""
    run_cpu([PY, "-m", "pytest", "--collect-only", "-q", "-p", "no:cacheprovider"],
            env={**os.environ, "PYTHONDONTWRITEBYTECODE": ""})
    cpu, wall, status = run_cpu(["make", "test"])
    return {"wall_s": round(wall, 1), "cpu_s": round(cpu, 1), "passed": status == 0}


def _target(name, measured, limit, unit, detail="") -> dict:
    return {"name": name, "measured": measured, "limit": limit, "unit": unit,
            "meets": bool(measured <= limit), "detail": detail}


def main() -> int:
    result = {"startup": startup(), "period": period(), "report": report()}
    if not os.environ.get("BENCH_SKIP_TESTS"):
        result["tests"] = tests()
    s, p, r = result["startup"], result["period"]["worst"], result["report"]
    targets = [_target(f"start-up: {name}", row["ratio"], row["limit"], "x floor",
                       f"{row['cpu_s']:.2f} s CPU; floor {s['floor_cpu_s']:.2f} s")
               for name, row in s["commands"].items()]
    targets += [
        _target("exact period (closed form), slowest of 1..179 deg", round(p["elliptic_us"], 1), ELLIPTIC_LIMIT_US, "us",
                "CPU per call, tol 1e-12"),
        _target("exact period against hand-written quad, worst ratio", round(p["elliptic_ratio"], 3),
                PERIOD_RATIO_LIMIT, "x quad", "the closed form, at every amplitude 1..179 deg"),
        _target("quadrature route against hand-written quad, worst ratio", round(p["quadrature_ratio"], 2),
                PERIOD_RATIO_LIMIT, "x quad", "method='quadrature' (scenes without a closed form)"),
        _target("closed form against mpmath (40 digits), worst relative error", p["elliptic_error"],
                ELLIPTIC_ERROR_LIMIT, "", "amplitudes 1..179 deg"),
        _target("make report cold, against importing its dependencies", r["cold_ratio"], REPORT_RATIO_LIMIT, "x imports",
                f"{r['cold_build_cpu_s']:.1f} s CPU; imports {r['deps_import_cpu_s']:.2f} s "
                f"({r['deps_import_without_teardown_cpu_s']:.2f} s without the interpreter's teardown: "
                f"{r['cold_ratio_to_imports_without_teardown']:.2f}x)"),
        _target("make report, second run (no-op)", r["noop_wall_s"], NOOP_LIMIT_S, "s wall",
                "runs nothing" if r["noop_runs_nothing"] else "WOULD REBUILD"),
    ]
    if "tests" in result:
        t = result["tests"]
        targets.append(_target("make test on 2 workers", t["wall_s"], TEST_LIMIT_S, "s wall",
                               f"{t['cpu_s']:.0f} s CPU; {'passed' if t['passed'] else 'FAILED'}"))
    result = {"targets": targets, **result,
              "machine": {"python": platform.python_version(), "cpus": os.cpu_count(),
                          "platform": platform.platform(), "load_average": os.getloadavg()}}
    OUT.mkdir(parents=True, exist_ok=True)
    (OUT / "speed.json").write_text(json.dumps(result, indent=1) + "\n", encoding="utf-8")
    width = max(len(t["name"]) for t in targets)
    for t in targets:
        print(f"{t['name']:<{width}}  {t['measured']:>10.4g} {t['unit']:<9} (limit {t['limit']:g})  "
              f"{'meets' if t['meets'] else 'MISSES'}  {t['detail']}")
    print(f"-> {OUT / 'speed.json'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
