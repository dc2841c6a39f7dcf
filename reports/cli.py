"""``python -m reports``: the command line of the report build.

Kept apart from :mod:`reports.make_report` so that a bad option or a folder that is not
the project ends in one line at once, before the build's dependencies (sympy, matplotlib,
the solver) are imported.
"""
from __future__ import annotations

import argparse
import gc
import sys
from contextlib import contextmanager
from pathlib import Path

from reports.published import ReportInputError
from solver.errors import InputError

__all__ = ["main", "validate_build", "cyclic_gc_paused"]

ROOT = Path(__file__).resolve().parent.parent
DESCRIPTION = "Build the verification report and the reproducible paper (``make report``)."


def validate_build(root, pdf) -> None:
    """Refuse a build that cannot start: an unknown ``pdf`` choice, or ``root`` without ``data/``."""
    if pdf not in ("auto", "never"):
        raise ValueError(f"`pdf` must be one of ('auto', 'never'), got {pdf!r}")
    if not (Path(root) / "data").is_dir():
        raise ReportInputError(f"{root}: not the project root (no data/ folder)")


@contextmanager
def cyclic_gc_paused():
    """Run a block with Python's cyclic garbage collector off, then restore its previous state.

    A build allocates a great many short-lived sympy and matplotlib objects on top of the large heap
    of the imported modules, and each full collection walks all of it: in a cold build of about 4 s
    of CPU, five full collections took 0.33 s and the younger ones another 0.1 s. Reference counting
    still frees every object that is not part of a cycle; the cycles left (figures, sympy caches)
    held some 13 MB more at the end of a build. Nothing the build computes depends on when the
    collector runs. The first collection after the block walks what the block left (about 0.2 s
    after a build): ``python -m reports`` keeps the collector off until it exits instead.
    """
    was_enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was_enabled:
            gc.enable()


def main(argv: list[str] | None = None) -> int:
    """Command line: ``python -m reports [--out DIR] [--root DIR] [--pdf auto|never]``."""
    parser = argparse.ArgumentParser(prog="python -m reports", description=DESCRIPTION)
    parser.add_argument("--out", type=Path, default=None, help="output folder (default reports/build)")
    parser.add_argument("--root", type=Path, default=ROOT, help="project root (default: this checkout)")
    parser.add_argument("--pdf", choices=("auto", "never"), default="auto",
                        help="build paper.pdf when a LaTeX engine exists (auto) or never")
    args = parser.parse_args(argv)
    try:
        validate_build(args.root, args.pdf)
        from reports.make_report import build  # the build's dependencies, only now

        result = build(args.root, args.out, pdf=args.pdf)
    except (InputError, ValueError) as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    except Exception as err:  # noqa: BLE001 - survey input errors come from another package
        if type(err).__name__ == "SurveyInputError":
            print(f"error: {err}", file=sys.stderr)
            return 2
        raise
    c = result["counts"]
    print(
        f"report: {len(result['written'])} files in {result['out']} "
        f"({c['agrees']} agree, {c['disagrees']} disagree, {c['not-checkable']} not checkable; "
        f"{result['timings']['total']:.1f} s)"
    )
    return 0
