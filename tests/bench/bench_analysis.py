"""Benchmark the survey analytics against what a user would otherwise run, side by side.

Three comparisons, each timed as CPU time (user + system) of a fresh process, taken
from ``os.wait4`` for that process alone (started by a small launcher, see ``_run``), best of ``REPEATS`` runs, the two sides
alternating so that machine load hits both alike:

1. ``python -m analysis summarize FILE --json`` on a 1,000,000 x 5 wide CSV of
   agreement labels (messy case, blanks) against a pandas script reading the same
   file with ``dtype="category"`` and calling ``value_counts`` on every column.
   Target: ratio <= 1.2.
2. ``python -m analysis summarize LONG --by course term --json`` on a long CSV of
   10,000,000 answers (200 courses x 3 terms, 5 items), counted out of core by DuckDB.
   Peak memory is the process's maximum resident set size. Target: below half the
   file's size.
3. ``python -m analysis --help`` against ``python -c "import numpy, scipy"``.
   Target: ratio <= 1.5.

The data files are generated into a temporary folder here (never by ``make test``).
Results: reports/build/bench/analysis.json.

Run: ``.venv/bin/python tests/bench/bench_analysis.py`` (or ``make bench``).
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

import numpy as np
import pandas as pd

ROOT = Path(__file__).resolve().parents[2]
PY = sys.executable
ROWS, ITEMS, REPEATS = 1_000_000, 5, 3
LONG_ANSWERS, COURSES, TERMS = 10_000_000, 200, ("2024SP", "2024FA", "2025SP")
TARGET_RATIO, TARGET_MEMORY_SHARE, TARGET_HELP_RATIO = 1.2, 0.5, 1.5
LABELS = ("Strongly disagree", "Disagree", "Neither agree nor disagree", "Agree",
          "Strongly agree")

BASELINE = """
import sys
import pandas as pd
df = pd.read_csv(sys.argv[1], dtype="category")
for c in df.columns:
    df[c].value_counts(dropna=False)
"""


def _make_wide(path: Path) -> None:
    rng = np.random.default_rng(20240601)
    vocab = np.array(list(LABELS) + [lab.lower() for lab in LABELS] + [f" {LABELS[0]} ", ""],
                     dtype=object)
    cols = {f"item{j + 1}": vocab[rng.integers(0, len(vocab), ROWS)] for j in range(ITEMS)}
    pd.DataFrame(cols).to_csv(path, index=False)


def _make_long(path: Path) -> None:
    """course, term, respondent, item, answer: 5 answers per respondent, 5 % blank."""
    rng = np.random.default_rng(20240602)
    people = LONG_ANSWERS // ITEMS
    chunk = 200_000
    with open(path, "w", newline="") as fh:
        fh.write("course,term,respondent,item,answer\n")
        for start in range(0, people, chunk):
            m = min(chunk, people - start)
            course = np.repeat(rng.integers(0, COURSES, m), ITEMS)
            term = np.repeat(rng.integers(0, len(TERMS), m), ITEMS)
            resp = np.repeat(np.arange(start, start + m), ITEMS)
            item = np.tile(np.arange(1, ITEMS + 1), m)
            ans = rng.integers(0, len(LABELS) + 1, m * ITEMS)      # last: blank
            vocab = np.array(list(LABELS) + [""], dtype=object)
            frame = pd.DataFrame({
                "course": pd.Categorical.from_codes(course, [f"C{c:03d}" for c in range(COURSES)]),
                "term": pd.Categorical.from_codes(term, list(TERMS)),
                "respondent": resp, "item": item, "answer": vocab[ans]})
            frame["item"] = "Q" + frame["item"].astype(str)
            frame.to_csv(fh, header=False, index=False)


# Linux keeps a process's peak RSS across exec from the image it was forked from, so a
# child of this (large) process would report at least this process's size. A small
# launcher process starts the command and reports the command's own rusage.
LAUNCHER = """
import json, os, subprocess, sys
proc = subprocess.Popen(sys.argv[1:], stdout=subprocess.DEVNULL)
_, status, ru = os.wait4(proc.pid, 0)
print(json.dumps([os.waitstatus_to_exitcode(status), ru.ru_utime + ru.ru_stime, ru.ru_maxrss]))
"""


def _run(cmd: list[str]) -> tuple[float, int]:
    """(CPU seconds, peak RSS in bytes) of one process, from its own rusage."""
    res = subprocess.run([PY, "-c", LAUNCHER, *cmd], capture_output=True, text=True, cwd=ROOT)
    code, cpu, maxrss = json.loads(res.stdout.strip().splitlines()[-1])
    if code != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed: {res.stderr.strip()[:300]}")
    return cpu, maxrss * (1 if sys.platform == "darwin" else 1024)


def _side_by_side(a: list[str], b: list[str], repeats: int = REPEATS):
    """Best CPU time of a and of b, alternating runs; and a's peak RSS."""
    ta, tb, rss = [], [], 0
    for _ in range(repeats):
        t, r = _run(a)
        ta.append(t)
        rss = max(rss, r)
        tb.append(_run(b)[0])
    return min(ta), min(tb), rss


def main() -> int:
    out = {"python": platform.python_version(), "pandas": pd.__version__,
           "numpy": np.__version__, "machine": platform.machine(), "repeats": REPEATS}
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        wide, long, script = tmp / "survey_1M.csv", tmp / "answers_10M.csv", tmp / "baseline.py"
        script.write_text(BASELINE)
        t0 = time.perf_counter()
        _make_wide(wide)
        _make_long(long)
        out["generate_seconds"] = round(time.perf_counter() - t0, 1)

        ours, base, _ = _side_by_side([PY, "-m", "analysis", "summarize", str(wide), "--json"],
                                      [PY, str(script), str(wide)])
        out["summary_1M_x_5"] = {
            "file_bytes": wide.stat().st_size, "analysis_cpu_seconds": round(ours, 3),
            "pandas_category_value_counts_cpu_seconds": round(base, 3),
            "ratio": round(ours / base, 3), "target_ratio": TARGET_RATIO,
            "meets_target": ours / base <= TARGET_RATIO}

        cpu, rss = _run([PY, "-m", "analysis", "summarize", str(long), "--by", "course", "term",
                         "--json"])
        size = long.stat().st_size
        out["long_10M_by_course_term"] = {
            "answers": LONG_ANSWERS, "courses": COURSES, "terms": len(TERMS),
            "file_bytes": size, "peak_rss_bytes": rss, "cpu_seconds": round(cpu, 3),
            "peak_rss_share_of_file": round(rss / size, 3),
            "target_share": TARGET_MEMORY_SHARE, "meets_target": rss / size < TARGET_MEMORY_SHARE}

    ours, base, _ = _side_by_side([PY, "-m", "analysis", "--help"],
                                  [PY, "-c", "import numpy, scipy"], repeats=5)
    out["help"] = {"analysis_help_cpu_seconds": round(ours, 3),
                   "import_numpy_scipy_cpu_seconds": round(base, 3),
                   "ratio": round(ours / base, 3), "target_ratio": TARGET_HELP_RATIO,
                   "meets_target": ours / base <= TARGET_HELP_RATIO}

    dest = ROOT / "reports" / "build" / "bench"
    dest.mkdir(parents=True, exist_ok=True)
    (dest / "analysis.json").write_text(json.dumps(out, indent=2) + "\n")
    s, m, h = out["summary_1M_x_5"], out["long_10M_by_course_term"], out["help"]
    print(f"analysis: 1M x 5 summary {s['ratio']:.2f}x pandas category+value_counts CPU "
          f"(target <= {TARGET_RATIO}); 10M answers by course x term: peak RSS "
          f"{m['peak_rss_share_of_file']:.2f} of the file (target < {TARGET_MEMORY_SHARE}); "
          f"--help {h['ratio']:.2f}x import numpy, scipy (target <= {TARGET_HELP_RATIO}) "
          f"-> {dest / 'analysis.json'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
