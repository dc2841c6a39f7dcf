"""Benchmark: summarising one million respondents by five items.

Writes a 1,000,000 x 5 wide CSV of the paper's labels (messy case and blanks
included) into a temporary folder, then times

- ``pandas.read_csv`` of the same file (C engine, default dtypes), the baseline, and
  with ``dtype="category"`` (what analysis itself asks the parser for);
- ``analysis`` reading + item detection + label matching + summaries
  (``read_survey`` then ``summarize``), the thing measured.

Best of 3 runs each. Targets: summarise under 2 s, and within 3x of the pandas read.
Results: reports/build/bench/analysis.json.

Run: ``.venv/bin/python tests/bench/bench_analysis.py`` (or ``make bench``).
"""
from __future__ import annotations

import json
import platform
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from analysis.ingest import read_survey  # noqa: E402
from analysis.likert import summarize  # noqa: E402
from analysis.scales import BUILTIN_SCALES  # noqa: E402

ROWS, ITEMS, REPEATS = 1_000_000, 5, 3
TARGET_SECONDS, TARGET_RATIO = 2.0, 3.0


def _make_csv(path: Path) -> None:
    rng = np.random.default_rng(20240601)
    labels = list(BUILTIN_SCALES["paper"].labels)
    vocab = np.array(labels + [lab.lower() for lab in labels] + [f" {labels[0]} ", ""],
                     dtype=object)
    cols = {f"item{j + 1}": vocab[rng.integers(0, len(vocab), ROWS)] for j in range(ITEMS)}
    pd.DataFrame(cols).to_csv(path, index=False)


def _best(fn) -> float:
    times = []
    for _ in range(REPEATS):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def main() -> int:
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "survey_1M.csv"
        t0 = time.perf_counter()
        _make_csv(path)
        gen = time.perf_counter() - t0
        size = path.stat().st_size
        t_pandas = _best(lambda: pd.read_csv(path))
        # the same parser setting analysis uses (categorical columns), for a like-for-like view
        t_pandas_cat = _best(lambda: pd.read_csv(path, dtype="category", keep_default_na=False,
                                                 na_filter=False))
        result = {}

        def run():
            result["s"] = summarize(read_survey(path))
        t_ours = _best(run)
    s = result["s"]
    ok_inv = all(it.n + it.missing + it.excluded == s.respondents for it in s.items)
    out = {
        "rows": ROWS, "items": ITEMS, "file_bytes": size, "repeats": REPEATS,
        "generate_seconds": round(gen, 3),
        "pandas_read_csv_seconds": round(t_pandas, 3),
        "pandas_read_csv_category_seconds": round(t_pandas_cat, 3),
        "summarize_seconds": round(t_ours, 3),
        "ratio_to_pandas_read": round(t_ours / t_pandas, 3),
        "target_seconds": TARGET_SECONDS, "target_ratio": TARGET_RATIO,
        "meets_time_target": t_ours < TARGET_SECONDS,
        "meets_ratio_target": t_ours / t_pandas <= TARGET_RATIO,
        "invariant_holds": ok_inv, "respondents": s.respondents,
        "python": platform.python_version(), "pandas": pd.__version__, "numpy": np.__version__,
        "machine": platform.machine(),
    }
    dest = ROOT / "reports" / "build" / "bench"
    dest.mkdir(parents=True, exist_ok=True)
    (dest / "analysis.json").write_text(json.dumps(out, indent=2) + "\n")
    print(f"analysis: summarise {ROWS:,} x {ITEMS}: {t_ours:.3f} s "
          f"(pandas.read_csv {t_pandas:.3f} s, as categories {t_pandas_cat:.3f} s, "
          f"ratio {t_ours / t_pandas:.2f}; "
          f"targets < {TARGET_SECONDS} s, <= {TARGET_RATIO}x) -> {dest / 'analysis.json'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
