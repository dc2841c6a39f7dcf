"""Command line: ``python -m analysis <command> ...``.

Commands
--------
``summarize FILE [--scale NAME|FILE] [--items ...] [--group COLUMN] [--chart OUT.svg] [--json]``
    Table 1 for a survey export; ``--json`` prints
    ``{"respondents": int, "items": [{"item", "n", "missing", "excluded", "counts",
    "percent", "agree": {"share", "ci"}}]}`` (shares 0-1, percents 0-100). With
    ``--group`` the JSON gains ``"groups"``; with ``--reliability`` it gains ``"reliability"``.
``claims FILE CLAIMS [--json]``
    Evaluate a claims TOML file against a survey export.
``verify-table TABLE [--n N | --n-range LO HI] [--json]``
    Check a published percentage table; ``--json`` prints
    ``{"n": int, "rows": [{"item", "cells": [{"label", "published", "attainable",
    "counts"}], "sum_ok"}]}``. Without N, the range 1..1000 (or ``--n-range``) is
    searched: ``n`` is then the smallest N that makes the whole table attainable (or the
    N attaining the most cells), and ``"n_range"`` and ``"feasible_n"`` are added.
``report FILE -o OUT.html [--claims CLAIMS]``
    Self-contained HTML report of a survey export.
``rebuild-table1 OUT.csv``
    Write the respondent-level dataset rebuilt from the paper's Table 1.

Bad input prints one line ``error: <file>: row R, column 'C': <what>`` on stderr
and exits with status 2; nothing is written in part.
"""
from __future__ import annotations

import argparse
import json
import sys

from .errors import SurveyInputError

DEFAULT_N_RANGE = (1, 1000)


class _Parser(argparse.ArgumentParser):
    def error(self, message):          # one line, exit 2 (argparse prints usage otherwise)
        sys.stderr.write(f"error: {self.prog}: {message}\n")
        raise SystemExit(2)


def _reading_options(p: argparse.ArgumentParser) -> None:
    from .platforms import SHAPES
    p.add_argument("file", nargs="?",
                   help="survey export: CSV or .xlsx (wide, long, Google Forms, Microsoft "
                        "Forms, Qualtrics, SurveyMonkey, Canvas, LimeSurvey, Moodle)")
    p.add_argument("--scale", help="built-in scale name or a scale .toml file (default: detect)")
    p.add_argument("--items", nargs="+", metavar="ITEM",
                   help="item columns by name or pattern (default: detect)")
    p.add_argument("--shape", choices=SHAPES, default="auto", help="input shape (default: detect)")
    p.add_argument("--unknown-as-missing", action="store_true",
                   help="count answers that match no label as missing (each one is reported)")
    p.add_argument("--encoding", default=None,
                   help="text encoding of a CSV file (default: UTF-8, else Windows-1252 "
                        "with a note)")
    p.add_argument("--codes", metavar="FILE",
                   help="what numeric answer codes mean: Qualtrics .qsf, LimeSurvey .lss or "
                        "a .toml code map")
    p.add_argument("--reverse", nargs="+", metavar="ITEM", help="reverse-keyed items")
    p.add_argument("--respondents", type=int, metavar="N",
                   help="declared respondents (absent ones are missing on every item)")
    p.add_argument("--ci", choices=("wilson", "beta"), default="wilson",
                   help="interval method: Wilson (default) or Clopper-Pearson ('beta')")
    p.add_argument("--confidence", type=float, default=0.95, help="confidence level")


def build_parser() -> argparse.ArgumentParser:
    """The argument parser (exposed for documentation and tests)."""
    parser = _Parser(prog="python -m analysis",
                     description="Likert survey analytics and published-table verification.")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)

    s = sub.add_parser("summarize", help="per-item counts, percentages and intervals")
    _reading_options(s)
    s.add_argument("--group", help="grouping column (group comparisons)")
    s.add_argument("--by", nargs="+", metavar="COLUMN",
                   help="count a large CSV/Parquet file out of core (DuckDB) by these columns "
                        "(e.g. course term section), with institution-wide totals")
    s.add_argument("--group-order", nargs="+", metavar="VALUE",
                   help="order of the groups, e.g. terms (default: as they first appear)")
    s.add_argument("--table", metavar="OUT.csv",
                   help="also write the summary table (.csv or .xlsx by suffix; with --group "
                        "one row per item and group)")
    s.add_argument("--min-group", type=int, default=5,
                   help="suppress groups smaller than this (default 5)")
    s.add_argument("--reliability", nargs="*", metavar="ITEM",
                   help="Cronbach's alpha for these items (none given: all items)")
    s.add_argument("--decimals", type=int, default=1, help="printed decimals (text output)")
    s.add_argument("--percent-method", choices=("round", "largest_remainder"), default="round",
                   help="printed percentages: round each (default) or make rows sum to 100")
    s.add_argument("--chart", metavar="OUT.svg",
                   help="also write the diverging bar chart (.svg, .png or .pdf by suffix)")
    s.add_argument("--order", choices=("questionnaire", "agree"), default="questionnaire",
                   help="item order in the chart (default: as asked)")
    s.add_argument("--json", action="store_true", help="print JSON")

    c = sub.add_parser("claims", help="evaluate claims (TOML) against a survey")
    _reading_options(c)
    c.add_argument("claims", nargs="?", help="claims .toml file")
    c.add_argument("--json", action="store_true", help="print JSON")

    v = sub.add_parser("verify-table", help="check a published percentage table")
    v.add_argument("table", help="CSV with an 'item' column and one column per label")
    g = v.add_mutually_exclusive_group()
    g.add_argument("--n", type=int, help="number of respondents")
    g.add_argument("--n-range", type=int, nargs=2, metavar=("LO", "HI"),
                   help=f"search N in LO..HI (default {DEFAULT_N_RANGE[0]}..{DEFAULT_N_RANGE[1]})")
    v.add_argument("--rule", choices=("half_away", "half_even", "truncate", "ceil"),
                   default="half_away", help="rounding rule of the table (default half_away)")
    v.add_argument("--decimals", type=int, help="printed decimals (default: from each cell)")
    v.add_argument("--full", action="store_true",
                   help="with --json: add nearest values, reconstructed counts and reasons")
    v.add_argument("--json", action="store_true", help="print JSON")

    r = sub.add_parser("report", help="self-contained HTML report of a survey")
    _reading_options(r)
    r.add_argument("-o", "--output", required=True, help="HTML file to write")
    r.add_argument("--claims", help="claims .toml file to evaluate in the report")
    r.add_argument("--group", help="grouping column (group comparisons)")
    r.add_argument("--min-group", type=int, default=5, help="suppress groups smaller than this")
    r.add_argument("--group-order", nargs="+", metavar="VALUE",
                   help="order of the groups, e.g. terms (default: as they first appear)")
    r.add_argument("--title", default=None, help="report title")

    b = sub.add_parser("rebuild-table1", help="write the dataset rebuilt from the paper's Table 1")
    b.add_argument("output", help="CSV file to write")
    return parser


def _read(args):
    from .ingest import read_survey
    return read_survey(args.file, scale=args.scale, items=args.items, shape=args.shape,
                       unknown="missing" if args.unknown_as_missing else "error",
                       encoding=args.encoding, group=getattr(args, "group", None),
                       reverse=args.reverse, respondents=args.respondents, codes=args.codes)


def _positionals_from_lists(args, argv) -> "str | None":
    """Give back positionals swallowed by a list option (``--items Q1 Q2 FILE``).

    ``--items``, ``--reverse`` and ``--reliability`` take any number of values, so a file
    name after them is read as one more value; it is taken back from the option given
    last on the command line. Returns the error message when a positional is missing.
    """
    positionals = {"summarize": ("file",), "report": ("file",), "claims": ("file", "claims")}
    wanted = [p for p in positionals.get(args.command, ()) if getattr(args, p) is None]
    if not wanted:
        return None
    opts = [a for a in argv if a in ("--items", "--reverse", "--reliability", "--group-order",
                                     "--by")]
    values = getattr(args, opts[-1].lstrip("-"), None) if opts else None
    if not values or len(values) < len(wanted):
        return f"{args.command}: the following arguments are required: {', '.join(wanted)}"
    taken = values[len(values) - len(wanted):]
    del values[len(values) - len(wanted):]
    for name, value in zip(wanted, taken):
        setattr(args, name, value)
    if opts[-1] != "--reliability" and not values:
        return f"{args.command}: {opts[-1]} needs at least one value before the file name"
    return None


def _usage_error(message: str) -> int:
    sys.stderr.write(f"error: python -m analysis {message}\n")
    return 2


def _notes(data) -> None:
    for u in data.unknown_answers:
        sys.stderr.write(f"warning: {u.line(data.source)}\n")
    counts: dict = {}
    for d in data.dropped:
        counts[d.reason] = counts.get(d.reason, 0) + 1
        sys.stderr.write(f"note: {data.source}: row {d.row}: {d.reason} dropped\n")
    for reason, k in counts.items():
        sys.stderr.write(f"note: {data.source}: {k} {reason}{'s' if k != 1 else ''} dropped "
                         f"in all (not respondents)\n")
    for note in getattr(data, "notes", []):
        sys.stderr.write(note if note.startswith("warning:") else f"note: {note}")
        sys.stderr.write("\n")


def _cmd_summarize_by(args) -> int:
    """Large files: counted out of core by DuckDB per group (``--by``)."""
    for flag, value in (("--group", args.group), ("--chart", args.chart),
                        ("--reliability", args.reliability), ("--codes", args.codes)):
        if value is not None:
            return _usage_error(f"summarize: {flag} is not available with --by (the "
                                "out-of-core count); use --group on a file that fits memory")
    from .institution import summarize_by
    res = summarize_by(args.file, args.by, scale=args.scale, items=args.items,
                       min_group=args.min_group)
    if args.table:
        import pandas as pd
        from .export import table_format, write_table
        table_format(args.table)
        write_table(pd.DataFrame(res.rows()), args.table)
    print(json.dumps(res.to_dict(), indent=2, ensure_ascii=False) if args.json
          else res.format_text())
    return 0


def _cmd_summarize(args) -> int:
    if args.by or str(args.file).lower().endswith(".parquet"):
        if not args.by:
            return _usage_error("summarize: a Parquet file is counted out of core: give --by "
                                "COLUMN [COLUMN ...] (e.g. --by course term)")
        return _cmd_summarize_by(args)
    from .likert import summarize
    data = _read(args)
    _notes(data)
    summary = summarize(data, args.confidence, args.ci)
    extra = {}
    if args.group:
        from .groups import compare_groups
        extra["groups"] = compare_groups(data, args.group, min_size=args.min_group,
                                         order=args.group_order)
    if args.reliability is not None:
        from .reliability import cronbach_alpha_for
        extra["reliability"] = cronbach_alpha_for(data, args.reliability or None,
                                                  confidence_level=args.confidence)
    if args.chart:
        from ._io import atomic_write
        from .chart import chart_format, diverging_bar, figure_bytes
        fmt = chart_format(args.chart)
        if "groups" in extra:
            from .chart import faceted_bar
            fig = faceted_bar(extra["groups"])
        else:
            fig = diverging_bar(summary, order=args.order)
        atomic_write(args.chart, figure_bytes(fig, fmt))
    if args.table:
        from .export import summary_frame, table_format, write_table
        table_format(args.table)
        frame = (extra["groups"].distribution_frame() if "groups" in extra
                 else summary_frame(summary))
        write_table(frame, args.table)
    if args.json:
        out = summary.to_dict()
        out.update({k: v.to_dict() for k, v in extra.items()})
        print(json.dumps(out, indent=2, ensure_ascii=False))
    else:
        print(summary.format_text(args.decimals, args.percent_method))
        for v in extra.values():
            print(v.format_text())
    return 0


def _cmd_claims(args) -> int:
    from .claims import evaluate_claims, load_claims
    claims = load_claims(args.claims)       # check the claims file before reading data
    data = _read(args)
    _notes(data)
    from .likert import summarize
    rep = evaluate_claims(claims, summarize(data, args.confidence, args.ci),
                          confidence_level=args.confidence, method=args.ci,
                          claims_file=args.claims)
    print(json.dumps(rep.to_dict(), indent=2, ensure_ascii=False) if args.json
          else rep.format_text())
    return 0


def _cmd_verify(args) -> int:
    from .tables import read_table_csv, verify_table
    if args.n is None and args.n_range is None:
        return _usage_error("verify-table: give --n N (the number of respondents), or "
                            f"--n-range LO HI to search N (e.g. --n-range {DEFAULT_N_RANGE[0]} "
                            f"{DEFAULT_N_RANGE[1]}); N is never chosen silently")
    table = read_table_csv(args.table)
    if args.n is not None:
        check = verify_table(table, n=args.n, rule=args.rule, decimals=args.decimals)
    else:
        rng = tuple(args.n_range) if args.n_range else DEFAULT_N_RANGE
        check = verify_table(table, n_range=rng, rule=args.rule, decimals=args.decimals)
    if args.json:
        print(json.dumps(check.to_full_dict() if args.full else check.to_dict(), indent=2,
                         ensure_ascii=False))
    else:
        print(check.format_text())
    return 0


def _cmd_report(args) -> int:
    from .report import build_report
    data = _read(args)
    _notes(data)
    res = build_report(data, args.output, claims=args.claims, group=args.group,
                       min_group=args.min_group, group_order=args.group_order, title=args.title,
                       confidence_level=args.confidence, method=args.ci)
    print(f"wrote {res}")
    return 0


def _cmd_rebuild(args) -> int:
    from .respondents import rebuild_table1_dataset
    res = rebuild_table1_dataset(args.output)
    print(f"wrote {res.path}: {res.respondents} respondents x {len(res.items)} items "
          f"(rebuilt from published marginals)")
    return 0


_COMMANDS = {"summarize": _cmd_summarize, "claims": _cmd_claims, "verify-table": _cmd_verify,
             "report": _cmd_report, "rebuild-table1": _cmd_rebuild}


def main(argv: "list[str] | None" = None) -> int:
    """Run the command line; returns the exit status (2 for bad input)."""
    args = build_parser().parse_args(argv)
    try:
        missing = _positionals_from_lists(args, sys.argv[1:] if argv is None else argv)
        if missing:
            return _usage_error(missing)
        return _COMMANDS[args.command](args)
    except SurveyInputError as e:
        sys.stderr.write(f"error: {e.line()}\n")
        return 2
    except ValueError as e:            # bad option values (messages list the valid ones)
        msg = str(e).splitlines()[0] if str(e) else type(e).__name__
        sys.stderr.write(f"error: {msg}\n")
        return 2
    except BrokenPipeError:            # output piped into e.g. `head`
        import os
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0


if __name__ == "__main__":
    sys.exit(main())
