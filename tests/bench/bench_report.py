"""Benchmark: a cold `make report` build (venv present), and the no-op second run.

1. Cold build: ``python -m reports --out TMP`` in a fresh interpreter (no sympy
   or lambdify caches, no previous outputs), timed end to end as a user would
   see it; the build's own phase timings are read back from its output line.
2. No-op: after one ``make report``, a second ``make report`` must run nothing
   (``make -n report`` lists no build command); its wall time.

Target: cold build under 60 s on this machine (2 cores, shared).
Results: reports/build/bench/report.json (not an input of the report itself).

Run: ``.venv/bin/python tests/bench/bench_report.py`` (or ``make bench``).
"""
from __future__ import annotations

import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
TARGET_SECONDS = 60.0


def main() -> int:
    env = dict(os.environ, PYTHONDONTWRITEBYTECODE="1")
    with tempfile.TemporaryDirectory(prefix="bench-report-") as tmp:
        out = Path(tmp) / "build"
        start = time.perf_counter()
        done = subprocess.run([sys.executable, "-m", "reports", "--out", str(out), "--pdf", "never"],
                              cwd=ROOT, env=env, capture_output=True, text=True, check=False)
        cold = time.perf_counter() - start
        if done.returncode != 0:
            print(done.stderr.strip(), file=sys.stderr)
            return 1
        files = sorted(str(p.relative_to(out)) for p in out.rglob("*") if p.is_file())
    # the no-op: bring reports/build up to date once, then ask make whether anything is left to do
    subprocess.run(["make", "report"], cwd=ROOT, capture_output=True, text=True, check=False)
    dry = subprocess.run(["make", "-n", "report"], cwd=ROOT, capture_output=True, text=True, check=False)
    start = time.perf_counter()
    noop = subprocess.run(["make", "report"], cwd=ROOT, capture_output=True, text=True, check=False)
    noop_s = time.perf_counter() - start
    up_to_date = noop.returncode == 0 and "-m reports" not in dry.stdout + noop.stdout
    result = {
        "cold_build_s": round(cold, 3),
        "target_s": TARGET_SECONDS,
        "meets_target": cold < TARGET_SECONDS,
        "build_output": done.stdout.strip().splitlines()[-1] if done.stdout.strip() else "",
        "files": files,
        "second_make_up_to_date": up_to_date,
        "second_make_s": round(noop_s, 3),
        "machine": {"python": platform.python_version(), "cpus": os.cpu_count(), "platform": platform.platform()},
    }
    dest = ROOT / "reports" / "build" / "bench"
    dest.mkdir(parents=True, exist_ok=True)
    (dest / "report.json").write_text(json.dumps(result, indent=2) + "\n", encoding="utf-8")
    print(f"report: cold build {cold:.1f} s (target < {TARGET_SECONDS:.0f} s), {len(files)} files; "
          f"second make: {'up to date' if result['second_make_up_to_date'] else 'WOULD REBUILD'} "
          f"({noop_s:.2f} s) -> {dest / 'report.json'}")
    return 0 if result["meets_target"] and result["second_make_up_to_date"] else 1


if __name__ == "__main__":
    sys.exit(main())
