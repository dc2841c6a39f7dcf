"""Shared test configuration."""
import atexit
import gc
import os
import sys

import pytest

from hypothesis import HealthCheck, settings

# Symbolic derivations are slow on first call; deadlines would make tests flaky.
settings.register_profile(
    "default", deadline=None, suppress_health_check=[HealthCheck.too_slow]
)
settings.register_profile(
    "ci", deadline=None, suppress_health_check=[HealthCheck.too_slow], derandomize=True
)
settings.load_profile("ci" if os.environ.get("CI") else "default")

# The files whose tests read the report build (``reports.make_report.build_cached``: one build per
# process, about 15 s of CPU). Under ``--dist loadfile`` (make test) they go to one worker as one
# unit, so the session builds the report once instead of once per worker.
REPORT_BUILD_FILES = frozenset({"tests/test_report.py", "tests/test_browser.py", "tests/test_drawing.py",
                                "tests/test_report_text.py"})
# The costliest units first (CPU seconds of each file in one worker of make test, measured with a
# per-test process-time hook, 26 November 2026, the mean of two runs): report build group ~13 (drawing
# 8.4, browser 2.5 and Chromium's own, report 2), display ~12, explain ~9, routes ~6, precision and
# multibody joints ~5 each, friction regimes ~5, multibody scenes and extremes ~4 each, analysis
# institution and compare ~3.3 each, multibody properties ~3.2, analysis tables, period, advised points,
# analysis report and large rates ~2.7 each, analysis ingest and strprint ~2.4 each, the hash-seed
# subprocesses ~2 (waited for, not in the worker's CPU), analysis hostile ~2, fuzz analysis ~1.7, command
# line ~1.7 and its subprocesses, fuzz solver, joint vectors, system derivative and analysis likert ~1.2
# each, friction ~1.1, multibody errors ~1; the rest (each under 1) after them in xdist's order.
# Longest-first keeps the two workers finishing together: xdist alone orders by number of tests,
# which sent the 2-test multibody-properties file (8 s then) last; and a 2 s file left among the last
# units ends one worker that much after the other. Only the order changes, never what runs.
HEAVY_FIRST = ("report-build", "tests/test_display.py", "tests/test_explain.py", "tests/test_routes.py",
               "tests/test_precision.py", "tests/test_multibody_joints.py", "tests/test_friction_regimes.py",
               "tests/test_multibody_scenes.py", "tests/test_extremes.py", "tests/test_analysis_institution.py",
               "tests/test_analysis_compare.py", "tests/test_multibody_properties.py", "tests/test_analysis_tables.py",
               "tests/test_period.py", "tests/test_advised_points.py", "tests/test_analysis_report.py",
               "tests/test_large_rates.py", "tests/test_analysis_ingest.py", "tests/test_strprint.py",
               "tests/test_hash_seed.py", "tests/test_analysis_hostile.py", "tests/test_fuzz_analysis.py",
               "tests/test_cli_solver.py", "tests/test_fuzz_solver.py", "tests/test_joint_vectors.py",
               "tests/test_system_derivative.py", "tests/test_analysis_likert.py", "tests/test_friction.py",
               "tests/test_multibody_errors.py")


# The cyclic garbage collector in a test process. Its full collections walk every live object,
# and a worker's heap is large and mostly long-lived: the imported modules (sympy, scipy,
# matplotlib, the project) and the caches that grow test after test. Measured with
# ``gc.callbacks`` over ``make test`` (25 November 2026): 36 full collections and some 6,000
# younger ones cost about 8.7 s of CPU in the two workers together, 8 % of the suite.
# So, as ``reports.cli.cyclic_gc_paused`` does for the report build: no collection while the
# modules are imported (nothing there is garbage); then after collection, and again after each
# test file (its module fixtures torn down), one collection of what is new and a ``gc.freeze()``
# of what survived it, so later collections walk only what later files create; and young
# collections every 10,000 new objects rather than 700 (test_explain, test_multibody_scenes and
# test_routes: 0.78 s in the collector instead of 1.11 s, 4 full collections instead of 11).
# The permanent generation holds only objects that were alive when frozen; a frozen object that
# dies is still freed by reference counting, and only a cycle formed later among frozen objects
# stays until the process ends (a test process, not the product). No test's result depends on
# when the collector runs.
def _test_process(config) -> bool:
    """True in a process that runs tests (an xdist worker, or pytest without workers)."""
    return hasattr(config, "workerinput") or not getattr(config.option, "numprocesses", None)


# SymPy's caches (``sympy.core.cache``) hold 1,000 results per cached function unless
# SYMPY_CACHE_SIZE says otherwise when sympy is imported. A test process derives many scenes one
# after another and kept evicting what the next test asked for again: with 20,000, test_explain,
# test_multibody_scenes and test_multibody_joints together took 18.0 s of CPU instead of 20.0 s
# (least of 3 runs each, 25 November 2026), for 15 MB more memory. A cache hit returns what the call
# would compute, so no result changes. The variable is set only for that import: the programs the
# tests start (the real command line) run with the environment they were given.
SYMPY_CACHE_SIZE = "20000"


def _import_sympy_with_larger_caches() -> None:
    if "sympy" in sys.modules or "SYMPY_CACHE_SIZE" in os.environ:
        return  # already imported, or the caller chose a size
    os.environ["SYMPY_CACHE_SIZE"] = SYMPY_CACHE_SIZE
    try:
        import sympy  # noqa: F401  (reads the variable once, here)
    finally:
        del os.environ["SYMPY_CACHE_SIZE"]


def pytest_configure(config):
    if _test_process(config):
        gc.disable()
        _import_sympy_with_larger_caches()


def pytest_collection_finish(session):
    if _test_process(session.config):
        gc.enable()
        gc.collect()
        gc.freeze()
        gc.set_threshold(10_000, 10, 10)  # a young collection per 10,000 new objects, not 700
        # Back to one generation for the interpreter's shutdown (after pytest's own last
        # collections, which then stay cheap): frozen objects are not collected at exit, and an
        # extension module's objects kept alive that way are reported as leaks (nanobind).
        atexit.register(gc.unfreeze)


# The end of an xdist worker (make test). Once its session is over (results sent, module and session
# fixtures torn down, pytest unconfigured) the interpreter's own shutdown is left: a last collection
# over the whole heap and the freeing of every object, sympy's caches and each worker's derivations
# included, about 2.5 s of CPU per worker (25 November 2026, two workers: 4.9 s of the suite's
# 119 s), and nothing that anyone reads. The worker ends there instead (os._exit after flushing its
# output), as execnet itself ends a worker that does not stop. Only workers: pytest without -n, the
# controller and the programs the tests start end as usual.
def _end_worker_process() -> None:
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(0)


def pytest_unconfigure(config):
    if hasattr(config, "workerinput"):
        atexit.register(_end_worker_process)  # registered last: the first atexit handler to run


@pytest.hookimpl(trylast=True)
def pytest_runtest_teardown(item, nextitem):
    """After a file's last test (and its module fixtures' teardown): collect, then freeze."""
    if nextitem is None or nextitem.path != item.path:
        gc.collect()
        gc.freeze()


@pytest.hookimpl(optionalhook=True)
def pytest_xdist_make_scheduler(config, log):
    """``--dist loadfile`` with the report-build files as one unit and the costliest units first
    (pytest-xdist hook; other --dist modes are left to xdist)."""
    if config.getvalue("dist") != "loadfile":
        return None
    from xdist.scheduler import LoadFileScheduling

    class ReportGroupedLoadFile(LoadFileScheduling):
        ordered = False

        def _split_scope(self, nodeid: str) -> str:
            scope = super()._split_scope(nodeid)
            return "report-build" if scope in REPORT_BUILD_FILES else scope

        def _assign_work_unit(self, node) -> None:
            if not self.ordered:  # the first call: the work queue is complete
                for scope in reversed(HEAVY_FIRST):
                    if scope in self.workqueue:
                        self.workqueue.move_to_end(scope, last=False)
                self.ordered = True
            super()._assign_work_unit(node)

    return ReportGroupedLoadFile(config, log)


@pytest.fixture
def solver_cli(capsys):
    """Run ``python -m solver ARGV...`` in process: returns (exit code, stdout, stderr)."""
    from solver.__main__ import main

    def run(*argv: str) -> tuple[int, str, str]:
        with pytest.raises(SystemExit) as exc:
            raise SystemExit(main(list(argv)))
        out = capsys.readouterr()
        return exc.value.code, out.out, out.err

    return run


@pytest.fixture
def one_load_per_scene(monkeypatch):
    """Within the test, ``python -m solver`` run in process loads each scene file (with the same
    ``--set`` values) once: its commands read one System, and a derivation the first command
    cached on it (formulation, reactions) serves the next ones, as within one command. Each
    command still parses its arguments, solves, formats and prints its own output. For tests whose
    commands only read the scene: ``explain`` may add a named place to a body, so it is not one.
    Returns the loaded systems by (resolved file, sorted --set items)."""
    from pathlib import Path

    from solver.io import scenes

    load, loaded = scenes.load_system, {}

    def once(path, overrides=None):
        key = (str(Path(path).resolve()), tuple(sorted(dict(overrides or {}).items())))
        if key not in loaded:
            loaded[key] = load(path, overrides)
        return loaded[key]

    monkeypatch.setattr(scenes, "load_system", once)
    return loaded


@pytest.fixture
def analysis_cli(capsys):
    """Run ``python -m analysis ARGV...`` in process: returns (exit code, stdout, stderr)."""
    from analysis.__main__ import main

    def run(*argv: str) -> tuple[int, str, str]:
        code = main(list(argv))
        out = capsys.readouterr()
        return code, out.out, out.err

    return run
