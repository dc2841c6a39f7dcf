"""Command line: ``python -m analysis <command> ...``.

Commands
--------
``summarize FILE [--scale NAME|FILE] [--items ...] [--group COLUMN [--paired|--independent]] [--chart OUT.svg] [--json]``
    Table 1 for a survey export; ``--json`` prints
    ``{"respondents": int, "ci_method", "confidence_level", "reverse_note", "items":
    [{"item", "reversed", "reversed_statistics", "n", "missing", "excluded", "counts",
    "percent", "agree": {"share", "ci"}, "median", "iqr", "mean", "sd"}], "not_items": [str],
    "not_item_reasons": {str: str}, "dropped": [{"row", "reason"}], "unknown_answers": [{"row",
    "column", "value"}]}``
    (shares 0-1, percents 0-100): every column, row and answer left out is listed; a
    reverse-keyed item's counts are raw, ``reversed_statistics`` names those on reversed codes. With
    ``--group`` the JSON gains ``"groups"``; with ``--reliability`` it gains ``"reliability"``.
``claims FILE CLAIMS [--json]``
    Evaluate a claims TOML file against a survey export.
``verify-table TABLE [--n N | --n-range LO HI] [--json]``
    Check a published percentage table; ``--json`` prints
    ``{"n": int, "rows": [{"item", "cells": [{"label", "published", "attainable",
    "counts"}], "sum_ok", "consistent", "findings"}]}`` (``findings``: what is wrong
    with the row, among ``cell_not_attainable``, ``sum_off``, ``counts_do_not_add_up``;
    ``sum_ok``: the printed sum is one rounding of the printed cells allows). Without N, the range 1..1000 (or ``--n-range``) is
    searched: ``n`` is then the smallest N that makes the whole table attainable (or the
    N attaining the most cells), and ``"n_range"`` and ``"feasible_n"`` are added, and
    per row ``"feasible_n"`` (the first 50 N making that row attainable) and
    ``"feasible_n_count"``.
``report FILE -o OUT.html [--claims CLAIMS] [--group COLUMN [--paired|--independent]]``
    Self-contained HTML report of a survey export.
``rebuild-table1 OUT.csv``
    Write the respondent-level dataset rebuilt from the paper's Table 1.

Bad input prints one line ``error: <file>: row R, column 'C': <what>`` (or naming the
flag, ``--confidence``) on stderr and exits with status 2; nothing is written in part,
and an output path is checked before the work starts. An unexpected error (a bug)
prints one ``internal error`` line and exits with status 1 (``ANALYSIS_DEBUG=1`` shows
the traceback).

Caps (each refused with exit 2): inputs are regular files of at most 1 GiB; at most 5000
columns, 1000 item columns and 10 million cells per survey file, a 1 GiB unpacked .xlsx of
at most 1,048,576 rows, 100 labels per
scale, 1 MiB and a parser-safe nesting depth per TOML file, 1000 claims per file, 300
cells per published table, 100 items per chart (``--chart``, ``report``; a group chart
at most 200 bars), 10,000
group x item pairs (``--group``), 200 names per ``--items``, ``--reverse``, ``--group-order`` or
``--reliability``, ``--n`` and ``--n-range`` up to 1,000,000, ``--respondents``
and ``--min-group`` up to 10,000,000.
"""
from __future__ import annotations

import gc

if __name__ == "__main__":  # a short-lived process: see the end of this file
    gc.disable()

import argparse  # noqa: E402
import functools  # noqa: E402
import json  # noqa: E402
import math  # noqa: E402
import os  # noqa: E402
import sys  # noqa: E402

from ._io import check_output  # noqa: E402
from .errors import SurveyInputError  # noqa: E402

DEFAULT_N_RANGE = (1, 1000)
#: Most respondents ``--respondents`` may declare (absent ones are padded as missing).
MAX_RESPONDENTS = 10_000_000
#: Most names or patterns --items, --reverse and --reliability take.
MAX_NAMES = 200
#: Set to 1 to see the traceback of an internal error.
DEBUG_ENV = "ANALYSIS_DEBUG"
_CAPS = ("caps: inputs are regular files of at most 1 GiB; at most 5000 columns, 1000 "
         "item columns and 10 million cells per survey file, a 1 GiB unpacked .xlsx of at "
         "most 1048576 rows, 100 labels per scale, 1 MiB "
         "per TOML file, 1000 claims per file, 300 cells per published table, 100 items per "
         "chart (--chart, report; 200 bars per group chart), 10000 group x item pairs (--group), "
         "200 names per --items, --reverse, --reliability or --group-order; --n and "
         "--n-range 1..1000000, --respondents and --min-group 1..10000000, --confidence "
         "strictly between 0 and 1, --decimals 0..6")


def _int_in(lo: int, hi: int):
    """argparse type: a whole number in lo..hi (argparse names the flag in the message)."""
    def convert(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"must be a whole number from {lo} to {hi}, "
                                             f"got {text[:40]!r}") from None
        if not lo <= value <= hi:
            raise argparse.ArgumentTypeError(f"must be from {lo} to {hi}, got {text[:40]}")
        return value
    convert.__name__ = "integer"
    return convert


def _encoding(text: str) -> str:
    """argparse type: a text encoding the CSV reader can use (ASCII-compatible, or UTF-16/32)."""
    import codecs
    try:
        name = codecs.lookup(text).name
    except (LookupError, ValueError):
        raise argparse.ArgumentTypeError(f"unknown encoding {text[:40]!r}") from None
    try:
        plain = "q1,Q 2;\t\r\n".encode(name) == b"q1,Q 2;\t\r\n"
        bytes(range(256)).decode(name, errors="replace")
    except (UnicodeError, LookupError, ValueError, TypeError):
        plain = False
    if not (plain or name.startswith(("utf-8", "utf-16", "utf-32"))):
        raise argparse.ArgumentTypeError(f"{text[:40]!r} is not a text encoding for CSV files "
                                         f"(e.g. utf-8, cp1252, latin-1, utf-16)")
    return text


def _confidence(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not 0 < value < 1:               # also refuses nan and inf
        raise argparse.ArgumentTypeError(f"must be a number strictly between 0 and 1 "
                                         f"(e.g. 0.95), got {text[:40]!r}")
    return value


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
    p.add_argument("--sheet", metavar="NAME",
                   help="the sheet of an .xlsx workbook to read (default: the first; a note "
                        "names other sheets holding data)")
    p.add_argument("--encoding", type=_encoding, default=None,
                   help="text encoding of a CSV file (default: UTF-8, else Windows-1252 "
                        "with a note)")
    p.add_argument("--codes", metavar="FILE",
                   help="what numeric answer codes mean: Qualtrics .qsf, LimeSurvey .lss or "
                        "a .toml code map")
    p.add_argument("--reverse", nargs="+", metavar="ITEM", help="reverse-keyed items")
    p.add_argument("--respondents", type=_int_in(1, MAX_RESPONDENTS), metavar="N",
                   help=f"declared respondents, 1..{MAX_RESPONDENTS} (absent ones are "
                        f"missing on every item)")
    p.add_argument("--ci", choices=("wilson", "beta"), default="wilson",
                   help="interval method: Wilson (default) or Clopper-Pearson ('beta')")
    p.add_argument("--confidence", type=_confidence, default=0.95,
                   help="confidence level, strictly between 0 and 1 (default 0.95)")


def _design_options(p: argparse.ArgumentParser) -> None:
    """--paired / --independent: how --group compares two groups whose respondents carry ids."""
    d = p.add_mutually_exclusive_group()
    d.add_argument("--paired", dest="paired", action="store_const", const=True, default=None,
                   help="with --group: pair the two groups' respondents by their id column "
                        "(pre/post; refused when the file cannot be paired)")
    d.add_argument("--independent", dest="paired", action="store_const", const=False,
                   help="with --group: compare the groups as independent samples whatever "
                        "the ids (default: paired only when at least half of each group's "
                        "respondents pair)")


def build_parser() -> argparse.ArgumentParser:
    """The argument parser (exposed for documentation and tests)."""
    from .tables import MAX_N
    parser = _Parser(prog="python -m analysis",
                     description="Likert survey analytics and published-table verification.",
                     epilog=_CAPS)
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)

    s = sub.add_parser("summarize", epilog=_CAPS, help="per-item counts, percentages and intervals")
    _reading_options(s)
    s.add_argument("--group", help="grouping column (group comparisons)")
    _design_options(s)
    s.add_argument("--by", nargs="+", metavar="COLUMN",
                   help="count a large CSV/Parquet file out of core (DuckDB) by these columns "
                        "(e.g. course term section), with institution-wide totals")
    s.add_argument("--group-order", nargs="+", metavar="VALUE",
                   help="order of the groups, e.g. terms (default: as they first appear; "
                        "with --by, sorted as text); with --group, a trend over more than two "
                        "groups is tested only over this order")
    s.add_argument("--table", metavar="OUT.csv",
                   help="also write the summary table (.csv or .xlsx by suffix; with --group "
                        "one row per item and group)")
    s.add_argument("--min-group", type=_int_in(1, MAX_RESPONDENTS), default=5,
                   help="suppress groups smaller than this (default 5)")
    s.add_argument("--reliability", nargs="*", metavar="ITEM",
                   help="Cronbach's alpha for these items (none given: all items)")
    s.add_argument("--decimals", type=_int_in(0, 6), default=1,
                   help="printed decimals of percentages, 0..6 (text output, group lines "
                        "included; default 1)")
    s.add_argument("--percent-method", choices=("round", "largest_remainder"), default="round",
                   help="printed percentages: round each (default) or make rows sum to 100")
    s.add_argument("--chart", metavar="OUT.svg",
                   help="also write the diverging bar chart (.svg, .png or .pdf by suffix)")
    s.add_argument("--order", choices=("questionnaire", "agree"), default="questionnaire",
                   help="item order in the chart (default: as asked)")
    s.add_argument("--json", action="store_true", help="print JSON")

    c = sub.add_parser("claims", epilog=_CAPS, help="evaluate claims (TOML) against a survey")
    _reading_options(c)
    c.add_argument("claims", nargs="?", help="claims .toml file")
    c.add_argument("--json", action="store_true", help="print JSON")

    v = sub.add_parser("verify-table", epilog=_CAPS, help="check a published percentage table")
    v.add_argument("table", help="CSV with an 'item' column and one column per label")
    g = v.add_mutually_exclusive_group()
    g.add_argument("--n", type=_int_in(1, MAX_N), help=f"number of respondents, 1..{MAX_N}")
    g.add_argument("--n-range", type=_int_in(1, MAX_N), nargs=2, metavar=("LO", "HI"),
                   help=f"search N in LO..HI, within 1..{MAX_N} "
                        f"(default {DEFAULT_N_RANGE[0]}..{DEFAULT_N_RANGE[1]})")
    v.add_argument("--rule", choices=("half_away", "half_even", "truncate", "ceil"),
                   default="half_away", help="rounding rule of the table (default half_away)")
    v.add_argument("--decimals", type=_int_in(0, 6),
                   help="printed decimals, 0..6 (default: from each cell)")
    v.add_argument("--full", action="store_true",
                   help="with --json: add nearest values, reconstructed counts and reasons")
    v.add_argument("--json", action="store_true", help="print JSON")

    r = sub.add_parser("report", epilog=_CAPS, help="self-contained HTML report of a survey")
    _reading_options(r)
    r.add_argument("-o", "--output", required=True, help="HTML file to write")
    r.add_argument("--claims", help="claims .toml file to evaluate in the report")
    r.add_argument("--group", help="grouping column (group comparisons)")
    _design_options(r)
    r.add_argument("--min-group", type=_int_in(1, MAX_RESPONDENTS), default=5,
                   help="suppress groups smaller than this (default 5)")
    r.add_argument("--group-order", nargs="+", metavar="VALUE",
                   help="order of the groups, e.g. terms (default: as they first appear); "
                        "a trend over more than two groups is tested only over this order")
    r.add_argument("--title", default=None, help="report title")

    b = sub.add_parser("rebuild-table1", epilog=_CAPS, help="write the dataset rebuilt from the paper's Table 1")
    b.add_argument("output", help="CSV file to write")
    return parser


@functools.cache
def _parser() -> argparse.ArgumentParser:
    """The parser :func:`main` uses, built once per process (some 1.3 ms a build, and the
    tests call ``main`` some 600 times); parsing leaves it as it was."""
    return build_parser()


def _read(args):
    from .ingest import read_survey
    return read_survey(args.file, scale=args.scale, items=args.items, shape=args.shape,
                       unknown="missing" if args.unknown_as_missing else "error",
                       encoding=args.encoding, group=getattr(args, "group", None),
                       reverse=args.reverse, respondents=args.respondents, codes=args.codes,
                       sheet=args.sheet)


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
    values = getattr(args, opts[-1].lstrip("-").replace("-", "_"), None) if opts else None
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


def _standard(obj):
    """``obj`` with every float that is not finite as None: JSON has no Infinity or NaN."""
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else None
    if isinstance(obj, dict):
        return {k: _standard(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_standard(v) for v in obj]
    return obj


def _json(obj) -> str:
    """Standard JSON text of ``obj`` (``allow_nan=False`` guards the rule)."""
    return json.dumps(_standard(obj), indent=2, ensure_ascii=False, allow_nan=False)


def _notes(data) -> None:
    for u in data.unknown_answers:
        sys.stderr.write(f"warning: {u.line(data.source)}\n")
    counts: dict = {}
    for d in data.dropped:
        counts.setdefault(d.reason, []).append(d)
        sys.stderr.write(f"note: {data.source}: row {d.row}: {d.reason} dropped\n")
    for reason, rows in counts.items():
        k = len(rows)
        sys.stderr.write(f"note: {data.source}: {k} {reason}{'s' if k != 1 else ''} dropped "
                         f"in all: {rows[0].why}\n")
    for line in data.note_lines():
        sys.stderr.write(line + "\n")


#: Options of the in-memory route that the out-of-core count (--by) cannot honour, with
#: their defaults: any other value is refused, never ignored.
_NOT_WITH_BY = (("--group", "group", None), ("--chart", "chart", None),
                ("--reliability", "reliability", None), ("--codes", "codes", None),
                ("--shape", "shape", "auto"),
                ("--encoding", "encoding", None), ("--sheet", "sheet", None),
                ("--unknown-as-missing", "unknown_as_missing", False),
                ("--percent-method", "percent_method", "round"))


def _cmd_summarize_by(args) -> int:
    """Large files: counted out of core by DuckDB per group (``--by``)."""
    for flag, name, default in _NOT_WITH_BY:
        if getattr(args, name) != default:
            return _usage_error(f"summarize: {flag} is not available with --by (the "
                                "out-of-core count); use --group on a file that fits memory")
    _check_table_output(args.table)
    from .institution import summarize_by
    res = summarize_by(args.file, args.by, scale=args.scale, items=args.items,
                       min_group=args.min_group, reverse=args.reverse,
                       respondents=args.respondents, confidence_level=args.confidence,
                       method=args.ci, group_order=args.group_order)
    if args.table:
        from .export import write_table
        write_table(res.to_frame(), args.table)
    if args.json:            # on stderr too, as the in-memory route writes them (the text has them)
        sys.stderr.writelines(line + "\n" for line in res.note_lines())
    print(_json(res.to_dict()) if args.json else res.format_text(args.decimals))
    return 0


def _check_lists(args) -> None:
    """Cap the names given to --items, --reverse, --reliability and --group-order (each
    is matched against every column or group)."""
    for flag in ("--items", "--reverse", "--reliability", "--group-order"):
        names = getattr(args, flag[2:].replace("-", "_"), None)
        if names and len(names) > MAX_NAMES:
            raise SurveyInputError(f"{flag}: {len(names)} names; at most {MAX_NAMES}")


def _check_table_output(path) -> None:
    """Refuse a --table path (suffix, folder) before the work starts."""
    if path:
        from .export import table_format
        check_output(path, "--table")
        table_format(path)


def _check_chart_output(path) -> "str | None":
    """The --chart format, after refusing its path (suffix, folder) before the work."""
    if not path:
        return None
    from .chart import chart_format
    check_output(path, "--chart")
    return chart_format(path)


def _check_chart_size(data, what: str) -> None:
    """Refuse a chart past its cap before the summaries are computed."""
    from .chart import MAX_CHART_ITEMS
    if len(data.items) > MAX_CHART_ITEMS:
        raise SurveyInputError(f"{what}: {len(data.items)} items; a chart draws at most "
                               f"{MAX_CHART_ITEMS} (choose some with --items)", data.source)


def _cmd_summarize(args) -> int:
    if args.by or str(args.file).lower().endswith(".parquet"):
        if not args.by:
            return _usage_error("summarize: a Parquet file is counted out of core: give --by "
                                "COLUMN [COLUMN ...] (e.g. --by course term)")
        return _cmd_summarize_by(args)
    from .likert import summarize
    fmt = _check_chart_output(args.chart)
    _check_table_output(args.table)
    data = _read(args)
    if args.chart:
        _check_chart_size(data, "--chart")
    _notes(data)
    summary = summarize(data, args.confidence, args.ci)
    extra = {}
    if args.group:
        from .groups import compare_groups
        extra["groups"] = compare_groups(data, args.group, min_size=args.min_group,
                                         order=args.group_order, paired=args.paired)
    if args.reliability is not None:
        from .reliability import cronbach_alpha_for
        extra["reliability"] = cronbach_alpha_for(data, args.reliability or None,
                                                  confidence_level=args.confidence)
    if args.chart:
        from ._io import atomic_write
        from .chart import diverging_bar, figure_bytes
        if "groups" in extra:
            from .chart import faceted_bar
            fig = faceted_bar(extra["groups"])
        else:
            fig = diverging_bar(summary, order=args.order)
        atomic_write(args.chart, figure_bytes(fig, fmt))
    if args.table:
        from .export import summary_frame, write_table
        frame = (extra["groups"].distribution_frame() if "groups" in extra
                 else summary_frame(summary))
        write_table(frame, args.table)
    if args.json:
        out = summary.to_dict()
        out["notes"] = list(data.notes)    # as --by's JSON: stderr is not all a reader keeps
        out.update({k: v.to_dict() for k, v in extra.items()})
        print(_json(out))
    else:
        print(summary.format_text(args.decimals, args.percent_method))
        if "groups" in extra:
            print(extra["groups"].format_text(args.decimals, args.percent_method))
        if "reliability" in extra:
            print(extra["reliability"].format_text())
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
    print(_json(rep.to_dict()) if args.json else rep.format_text())
    return 0


def _cmd_verify(args) -> int:
    from .tables import read_table_csv, verify_table
    if args.n is None and args.n_range is None:
        return _usage_error("verify-table: give --n N (the number of respondents), or "
                            f"--n-range LO HI to search N (e.g. --n-range {DEFAULT_N_RANGE[0]} "
                            f"{DEFAULT_N_RANGE[1]}); N is never chosen silently")
    table = read_table_csv(args.table)
    if args.n_range and args.n_range[0] > args.n_range[1]:
        raise SurveyInputError(f"--n-range: LO must not exceed HI, got {args.n_range[0]} "
                               f"{args.n_range[1]}")
    if args.n is not None:
        check = verify_table(table, n=args.n, rule=args.rule, decimals=args.decimals)
    else:
        rng = tuple(args.n_range) if args.n_range else DEFAULT_N_RANGE
        check = verify_table(table, n_range=rng, rule=args.rule, decimals=args.decimals)
    if args.json:
        print(_json(check.to_full_dict() if args.full else check.to_dict()))
    else:
        print(check.format_text())
    return 0


def _cmd_report(args) -> int:
    from .report import build_report, report_path
    check_output(args.output, "-o/--output")
    report_path(args.output)
    data = _read(args)
    _check_chart_size(data, "report")
    _notes(data)
    res = build_report(data, args.output, claims=args.claims, group=args.group,
                       min_group=args.min_group, group_order=args.group_order,
                       paired=args.paired, title=args.title,
                       confidence_level=args.confidence, method=args.ci)
    print(f"wrote {res}")
    return 0


def _cmd_rebuild(args) -> int:
    from .respondents import rebuild_table1_dataset
    check_output(args.output, "OUT")
    res = rebuild_table1_dataset(args.output)
    print(f"wrote {res.path}: {res.respondents} respondents x {len(res.items)} items "
          f"(rebuilt from published marginals)")
    return 0


_COMMANDS = {"summarize": _cmd_summarize, "claims": _cmd_claims, "verify-table": _cmd_verify,
             "report": _cmd_report, "rebuild-table1": _cmd_rebuild}


def main(argv: "list[str] | None" = None) -> int:
    """Run the command line; returns the exit status.

    0 done; 2 bad input (one ``error:`` line naming the file and place, or the flag);
    1 an internal error (one line; ``ANALYSIS_DEBUG=1`` re-raises it for the traceback);
    130 interrupted.
    """
    try:
        args = _parser().parse_args(argv)
    except SystemExit as e:            # a bad flag (one line already written) or --help
        return e.code if isinstance(e.code, int) else 2
    try:
        missing = _positionals_from_lists(args, sys.argv[1:] if argv is None else argv)
        if missing:
            return _usage_error(missing)
        _check_lists(args)
        if getattr(args, "paired", None) is not None:
            flag = "--paired" if args.paired else "--independent"
            if getattr(args, "by", None):
                return _usage_error(f"{args.command}: {flag} is not available with --by (the "
                                    f"out-of-core count tests nothing across groups)")
            if not args.group:
                return _usage_error(f"{args.command}: {flag} says how --group compares "
                                    f"groups; give --group COLUMN too")
        return _COMMANDS[args.command](args)
    except SurveyInputError as e:
        return _fail(e.line(), 2)
    except ValueError as e:            # bad option values (messages list the valid ones)
        return _fail(_flag_names(str(e).splitlines()[0] if str(e) else type(e).__name__), 2)
    except BrokenPipeError:            # output piped into e.g. `head`
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    except KeyboardInterrupt:
        return _fail("interrupted", 130)
    except MemoryError:
        return _fail("out of memory: the input asks for more work than this machine holds", 1)
    except Exception as e:  # noqa: BLE001 - last resort: never a bare traceback for users
        if os.environ.get(DEBUG_ENV):
            raise
        text = str(e).splitlines()[0][:200] if str(e) else ""
        return _fail(f"internal error ({type(e).__name__}: {text}); please report it "
                     f"(set {DEBUG_ENV}=1 for the traceback)", 1)


#: Library argument names -> the flags that set them, for messages raised below the CLI.
_FLAGS = {"`scale`": "--scale", "`confidence_level`": "--confidence", "`decimals`": "--decimals",
          "`respondents`": "--respondents", "`min_size`": "--min-group", "`method`": "--ci",
          "`shape`": "--shape", "`rule`": "--rule", "`order`": "--order",
          "`percent_method`": "--percent-method", "`n`": "--n", "`n_range`": "--n-range",
          "`unknown`": "--unknown-as-missing", "`min_group`": "--min-group"}


def _flag_names(message: str) -> str:
    for name, flag in _FLAGS.items():
        message = message.replace(name, flag)
    return message


def _fail(message: str, status: int) -> int:
    sys.stderr.write(f"error: {message}\n")
    return status


if __name__ == "__main__":
    # The cyclic garbage collector stays off for the whole command, as in solver/__main__.py: its
    # full collections walk the heap of pandas, scipy and DuckDB again and again (summarize on a
    # 200,000-row CSV: 1.09 s of CPU with it, 0.89 s without; peak memory within 2 %). The heap is
    # frozen before the exit so that the interpreter's last collection skips it. Not after an
    # error once DuckDB is loaded: its objects then outlive the frozen heap, and its bindings
    # (nanobind) print some 60 "leaked instance" lines after the one error line.
    status = 1
    try:
        status = main()
    finally:
        if status == 0 or "duckdb" not in sys.modules:
            gc.freeze()
    sys.exit(status)
