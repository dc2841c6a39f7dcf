"""Verification of published percentage tables.

Given a table of printed percentages (a row per item, a column per answer) and
the number of respondents N, decide for every cell whether some whole number of
respondents k gives that percentage at the printed precision, reconstruct the
counts, and check that each row's counts can add up to N. When N is not stated,
list the N in a range that make the whole table attainable.

Attainability rule
------------------
A printed value p with d decimals is attainable by a count k out of N when::

    round(100 * k / N, d) == p

evaluated in exact rational arithmetic (``fractions.Fraction``), so no binary
floating-point error can decide a tie. ``round`` is, by default, *half away from
zero* (``rule="half_away"``, what hand calculators and spreadsheets print);
``"half_even"`` (banker's rounding, Python's ``round``), ``"truncate"`` and
``"ceil"`` are available to test other ways a table might have been produced.
The printed precision d is taken from each cell's text (``"50.0"`` has one
decimal) unless given.

Rows and their verdicts
-----------------------
Each row's verdict names what is wrong (:data:`FINDINGS`), each with its evidence:

- ``cell_not_attainable``: a cell no count out of N gives (with the nearest
  attainable values);
- ``sum_off``: the printed sum is one no rounding of the printed cells allows. A cell
  printed p at d decimals stands for an exact share in p's rounding interval (half
  away from zero: ``[p - h, p + h)``, h = half a unit of the d-th decimal, cut to
  0..100); the row is off when no choice of shares in those intervals adds up to
  100 (``sum_ok`` false). This depends only on the printed precision, not on N;
- ``counts_do_not_add_up``: every cell attainable and the sum within rounding, yet no
  choice of one attainable count per cell adds up to N (a subset-sum over the
  candidate sets).

A row is ``consistent`` when every cell is attainable and its counts can add up to
N (then its sum is necessarily within rounding). The counts
are reconstructed even for a row with unattainable cells, taking the count
nearest each such cell, and among choices adding up to N the one closest to the
printed values. For such rows two known ways of producing a table are tested and
named when they reproduce the printed row exactly: rounding every cell and then
adding the row's deficit to its largest cell so the row shows 100, and
largest-remainder rounding. A non-zero printed cell needs at least one
respondent, so an N below a row's number of non-zero cells is bad input.

Public API
----------
- :func:`read_table_csv` -- read a CSV with an ``item`` column and one column per label.
- :func:`verify_table` -- check a :class:`PublishedTable` for one N or a range of N.
- :func:`table1_check` -- the paper's Table 1 against its stated respondents,
  read from ``data/published/`` (returns a :class:`TableCheck`).
- :func:`attainable_counts`, :func:`nearest_attainable` -- the cell-level rule.

Every result is a dataclass with ``to_dict()``; :meth:`TableCheck.to_dict` gives
the command line's ``--json`` shape, :meth:`TableCheck.to_full_dict` adds the
nearest attainable values, reconstructed counts and reasons.
"""
from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass, field
from decimal import Decimal, InvalidOperation
from fractions import Fraction
from pathlib import Path

import numpy as np

from ._io import read_bytes, read_toml
from .errors import SurveyInputError
from .rounding import (ROUNDING_RULES, _validate_rule, largest_remainder, round_fraction,
                       rounding_interval)

__all__ = ["ROUNDING_RULES", "PublishedTable", "CellCheck", "RowCheck", "TableCheck",
           "read_table_csv", "verify_table", "table1_check", "published_dir",
           "round_fraction", "attainable_counts", "nearest_attainable", "load_table1",
           "FINDINGS"]

#: Largest N searched for a single table (guards against accidental huge ranges).
MAX_N = 1_000_000
#: Most printed cells (rows x labels) one table may have: checking a range of N
#: costs about 30 ms per cell at the full 1..MAX_N range.
MAX_TABLE_CELLS = 300
#: Largest table file read.
MAX_TABLE_BYTES = 1 << 20


def published_dir() -> Path:
    """Folder holding the paper's values as printed (``data/published/``)."""
    return Path(__file__).resolve().parents[1] / "data" / "published"


def attainable_counts(printed: Fraction, decimals: int, n: int,
                      rule: str = "half_away") -> list[int]:
    """All counts k in 0..n with ``round(100 k / n, decimals) == printed``.

    Parameters
    ----------
    printed : Fraction or str
        The printed percentage (exact, e.g. ``Fraction("4.5")``).
    decimals : int
        Printed precision.
    n : int
        Number of respondents (the denominator), n >= 1.
    rule : str
        Rounding rule, see :func:`round_fraction`.

    Returns
    -------
    list of int
        Ascending; empty when the printed value is not attainable.
    """
    p = Fraction(printed)
    start = _bracket(p, decimals, n, rule)

    def first(above: bool) -> int:
        """Smallest k in 0..n+1 printing above p (above) or at least p (not above)."""
        lo, hi = start                    # rounding is non-decreasing in k: bisect
        while lo < hi:
            mid = (lo + hi) // 2
            r = round_fraction(Fraction(100 * mid, n), decimals, rule)
            if r > p or (r == p and not above):
                hi = mid
            else:
                lo = mid + 1
        return lo
    return list(range(first(False), first(True)))


def _bracket(p: Fraction, decimals: int, n: int, rule: str) -> tuple[int, int]:
    """Where :func:`attainable_counts` bisects: counts ``lo..hi`` within 0..n+1 holding both
    its answers. A rounded value lies less than one printed step ``u = 10**-decimals`` from
    the exact one, so every k with ``100 k / n <= p - u`` prints below p, and every k with
    ``100 k / n >= p + u`` above it: about ``2 u n / 100`` counts are left, not n + 2.
    The whole range 0..n+1 when n or decimals is not a Python int, or n < 1."""
    if type(n) is not int or type(decimals) is not int or n < 1:
        return 0, n + 1
    _validate_rule(rule)              # as the first rounding of the whole range would
    # in integers: p = a / b, u = un / ud, (p -+ u) n / 100 = (a ud -+ b un) n / (100 b ud)
    a, b = p.numerator, p.denominator
    un, ud = (1, 10**decimals) if decimals >= 0 else (10**-decimals, 1)
    den = 100 * b * ud
    lo = min(max((a * ud - b * un) * n // den + 1, 0), n + 1)
    return lo, max(min(-(-(a * ud + b * un) * n // den), n + 1), lo)


def nearest_attainable(printed: Fraction, decimals: int, n: int,
                       rule: str = "half_away") -> tuple[list[int], list[Fraction]]:
    """Counts whose exact percentage lies nearest the printed value, and what they print as.

    Returns
    -------
    counts : list of int
        One count, or two when the printed value lies exactly between them.
    values : list of Fraction
        ``round(100 k / n, decimals)`` for each count.
    """
    p = Fraction(printed)
    k0 = p * n / 100
    cands = sorted({min(max(math.floor(k0), 0), n), min(max(math.ceil(k0), 0), n)})
    dist = {k: abs(Fraction(100 * k, n) - p) for k in cands}
    best = min(dist.values())
    counts = [k for k in cands if dist[k] == best]
    return counts, [round_fraction(Fraction(100 * k, n), decimals, rule) for k in counts]


def _fmt(value: Fraction, decimals: int) -> str:
    q = Decimal(value.numerator) / Decimal(value.denominator)
    return f"{q:.{decimals}f}"


# ---------------------------------------------------------------------------
# the table as printed
# ---------------------------------------------------------------------------
@dataclass(frozen=True)
class PublishedTable:
    """A percentage table as printed.

    Attributes
    ----------
    items : tuple of str
        Row labels (the ``item`` column), in printed order.
    labels : tuple of str
        Answer labels (column headers), in printed order.
    cells : tuple of tuple of str
        Cell text as printed (``"4.5"``; a trailing ``%`` is allowed).
    source : str
        Where the table came from (file name), for messages.
    rows : tuple of int
        Spreadsheet row of each item in the file (default: header in row 1, no gaps).
    """

    items: tuple[str, ...]
    labels: tuple[str, ...]
    cells: tuple[tuple[str, ...], ...]
    source: str = "<table>"
    rows: tuple[int, ...] = ()

    def row_of(self, i: int) -> int:
        """Spreadsheet row of item ``i`` (for messages)."""
        return self.rows[i] if i < len(self.rows) else i + 2

    def value(self, i: int, j: int) -> tuple[Fraction, int]:
        """Exact value and printed decimals of cell (i, j)."""
        return _parse_cell(self.cells[i][j], self.source, self.row_of(i), self.labels[j])


def _parse_cell(text: str, source: str, row: int, column: str) -> tuple[Fraction, int]:
    t = str(text).strip()
    if t.endswith("%"):
        t = t[:-1].strip()
    if t.count(",") == 1 and t.replace(",", "").isdigit():
        t = t.replace(",", ".")          # decimal comma ("27,3"), as European tables print
    if t == "":
        raise SurveyInputError("blank cell; every cell needs a printed percentage",
                               source, row, column)
    try:
        d = Decimal(t)
    except InvalidOperation:
        raise SurveyInputError(f"not a percentage: {text!r}", source, row, column) from None
    if not d.is_finite() or d < 0 or d > 100:
        raise SurveyInputError(f"percentage must be between 0 and 100, got {text!r}",
                               source, row, column)
    exp = d.as_tuple().exponent
    decimals = max(0, -exp) if isinstance(exp, int) else 0
    return Fraction(d), decimals


def read_table_csv(path: "str | Path", item_column: str = "item",
                   encoding: str = "utf-8-sig") -> PublishedTable:
    """Read a published table from CSV: an ``item`` column and one column per label.

    Comma, semicolon or tab delimited (detected); a cell may end in ``%`` and may use a
    decimal comma (``27,3``). Rows are numbered as a spreadsheet shows them. UTF-8 (with
    or without a byte-order mark) and UTF-16 with a byte-order mark are read. At most
    :data:`MAX_TABLE_CELLS` cells and :data:`MAX_TABLE_BYTES` bytes.

    Raises
    ------
    SurveyInputError
        Missing or empty file, undecodable bytes, no ``item`` column, fewer than
        two label columns, ragged rows, or a cell that is not a percentage (the
        error names the row and column).
    """
    p = Path(path)
    src = str(p)
    raw = read_bytes(p)
    if len(raw) > MAX_TABLE_BYTES:
        raise SurveyInputError(f"{len(raw)} bytes; a table file may have at most "
                               f"{MAX_TABLE_BYTES}", src)
    if raw[:4] == b"PK\x03\x04":
        raise SurveyInputError("a workbook (.xlsx), not a CSV table; save the table as CSV", src)
    if raw[:2] in (b"\xff\xfe", b"\xfe\xff"):     # UTF-16 with BOM (Excel "Unicode text")
        encoding = "utf-16"
    try:
        text = raw.decode(encoding)
    except UnicodeDecodeError as e:
        line = raw[:e.start].count(b"\n") + 1
        raise SurveyInputError(f"byte 0x{raw[e.start]:02x} is not valid {encoding}",
                               src, line) from None
    from ._io import sniff_delimiter
    sep, _ = sniff_delimiter(text[:65536])
    try:
        records = list(csv.reader(io.StringIO(text, newline=""), delimiter=sep))
    except csv.Error as e:
        raise SurveyInputError(f"not a well-formed CSV ({e})", src) from None
    # keep each record's spreadsheet row: blank lines still count as rows
    numbered = [(r, rec) for r, rec in enumerate(records, start=1) if any(c.strip() for c in rec)]
    if not numbered:
        raise SurveyInputError("empty file", src)
    head_row, first = numbered[0]
    header = [h.strip() for h in first]
    keys = [h.casefold() for h in header]
    if item_column.casefold() not in keys:
        raise SurveyInputError(f"no {item_column!r} column; header is {header!r}", src, head_row)
    ic = keys.index(item_column.casefold())
    labels = tuple(h for j, h in enumerate(header) if j != ic)
    if len(labels) < 2:
        raise SurveyInputError("needs at least two label columns besides the item column", src,
                               head_row)
    for j, lab in enumerate(labels):
        if not lab or lab.casefold() in [x.casefold() for x in labels[:j]]:
            raise SurveyInputError(f"label column {j + 1} is {'blank' if not lab else 'repeated'}"
                                   f" ({lab!r}); labels are {list(labels)!r}", src, head_row)
    if len(numbered) < 2:
        raise SurveyInputError("no table rows below the header", src)
    if (len(numbered) - 1) * len(labels) > MAX_TABLE_CELLS:
        raise SurveyInputError(f"{len(numbered) - 1} rows x {len(labels)} labels; a table may "
                               f"have at most {MAX_TABLE_CELLS} cells", src)
    items, cells, rows = [], [], []
    for r, row in numbered[1:]:
        if len(row) != len(header):
            raise SurveyInputError(f"{len(row)} cells, header has {len(header)}", src, r)
        items.append(row[ic].strip())
        cells.append(tuple(c for j, c in enumerate(row) if j != ic))
        rows.append(r)
    table = PublishedTable(tuple(items), labels, tuple(cells), src, tuple(rows))
    for i in range(len(items)):          # fail early on bad cells, naming the place
        for j in range(len(labels)):
            table.value(i, j)
    return table


# ---------------------------------------------------------------------------
# results
# ---------------------------------------------------------------------------
@dataclass
class CellCheck:
    """One printed cell checked against N.

    Attributes
    ----------
    item, label : str
        Row and column.
    published : float
        The printed value.
    printed : str
        The printed text.
    decimals : int
        Printed precision.
    attainable : bool
        Some count k gives the printed value.
    counts : list of int
        All such counts (empty when not attainable).
    nearest_counts : list of int
        Counts whose exact percentage is nearest the printed value.
    nearest_values : list of float
        What those counts print as; equal to ``published`` when attainable.
    reason : str
        One sentence explaining the verdict.
    """

    item: str
    label: str
    published: float
    printed: str
    decimals: int
    attainable: bool
    counts: list[int]
    nearest_counts: list[int]
    nearest_values: list[float]
    reason: str

    def to_dict(self) -> dict:
        """The ``--json`` cell: label, published, attainable, counts."""
        return {"label": self.label, "published": self.published,
                "attainable": self.attainable, "counts": list(self.counts)}

    def to_full_dict(self) -> dict:
        d = self.to_dict()
        d.update(printed=self.printed, decimals=self.decimals,
                 nearest_counts=list(self.nearest_counts),
                 nearest_values=list(self.nearest_values), reason=self.reason)
        return d


#: Row findings, in the order a verdict names them, with their labels in text output.
FINDINGS = {"cell_not_attainable": "CELL NOT ATTAINABLE",
            "sum_off": "SUM OFF",
            "counts_do_not_add_up": "COUNTS DO NOT ADD UP TO N"}


@dataclass
class RowCheck:
    """One row checked against N.

    Attributes
    ----------
    item : str
        Row label.
    cells : list of CellCheck
    sum_ok : bool
        The printed sum is one rounding allows: the exact shares the printed cells
        stand for (each within its rounding interval, from the printed precision)
        can add up to 100. Independent of N.
    consistent : bool
        Every cell is attainable and some choice of candidate counts adds up to N.
    findings : list of str
        What is wrong, as keys of :data:`FINDINGS` (empty when consistent):
        ``cell_not_attainable`` (some cell no count gives), ``sum_off`` (not
        ``sum_ok``), ``counts_do_not_add_up`` (every cell attainable and the sum
        within rounding, yet no choice of counts adds up to N).
    verdict : str
        One line: each finding's label (:data:`FINDINGS`) with its evidence, or ``"ok"``.
    printed_sum : float
        Sum of the printed values (as printed, exactly).
    exact_total : (float, float)
        Least and greatest total of exact shares that print as the row's cells (the
        verdict says whether each end is reached).
    reconstructed : list of int or None
        Counts that add up to N, taking for each cell a candidate count (or, for
        a cell that is not attainable, the count nearest its printed value) and,
        among several such choices, the one closest to the printed values.
        None when no such choice exists.
    unique : bool
        Exactly one choice of candidate counts adds up to N.
    reason : str
        The verdict with how the row could have been produced, when known.
    """

    item: str
    cells: list[CellCheck]
    sum_ok: bool
    consistent: bool
    findings: list[str]
    verdict: str
    printed_sum: float
    exact_total: tuple[float, float]
    reconstructed: list[int] | None
    unique: bool
    reason: str

    def to_dict(self) -> dict:
        """The ``--json`` row: item, cells, sum_ok, consistent, findings."""
        return {"item": self.item, "cells": [c.to_dict() for c in self.cells],
                "sum_ok": self.sum_ok, "consistent": self.consistent,
                "findings": list(self.findings)}

    def to_full_dict(self) -> dict:
        d = self.to_dict()
        d.update(cells=[c.to_full_dict() for c in self.cells], verdict=self.verdict,
                 printed_sum=self.printed_sum, exact_total=list(self.exact_total),
                 reconstructed=self.reconstructed, unique=self.unique, reason=self.reason)
        return d


#: N values listed per row (text and JSON) when a range was searched; the rest are counted.
SHOWN_N = 50


@dataclass
class RowRange:
    """The N of a searched range that make one row attainable (every cell attainable and
    counts adding up to N).

    Attributes
    ----------
    first : list of int
        The smallest of them, at most :data:`SHOWN_N`.
    count : int
        How many N of the range do.
    counts : list of int or None
        Counts of the row at the smallest such N (None when there is none).
    """

    first: list[int]
    count: int
    counts: list[int] | None

    def text(self) -> str:
        """``17 (counts 7,5,5), 34, 51``; ``none``; past :data:`SHOWN_N`, ``... (K in all)``."""
        if not self.first:
            return "none"
        head = f"{self.first[0]} (counts {','.join(map(str, self.counts or []))})"
        more = f", ... ({self.count} in all)" if self.count > len(self.first) else ""
        return ", ".join([head] + [str(n) for n in self.first[1:]]) + more


@dataclass
class TableCheck:
    """A published table checked against a number of respondents.

    Attributes
    ----------
    n : int
        The N the rows were checked against (the stated N, or with a range
        the smallest N that makes the whole table attainable; when none does,
        the N attaining the most cells).
    rows : list of RowCheck
    rule : str
        Rounding rule used.
    source : str
        Table file.
    n_range : tuple of int or None
        The range searched, when N was not stated.
    feasible_n : list of int or None
        With a range: every N that makes the whole table attainable.
    row_ranges : list of RowRange or None
        With a range: per row (in order), the N that make that row attainable.
    best_cells : int or None
        With a range: the most cells attainable at one N (at :attr:`n` when no N makes
        the whole table attainable).
    """

    n: int
    rows: list[RowCheck]
    rule: str
    source: str
    n_range: tuple[int, int] | None = None
    feasible_n: list[int] | None = None
    labels: list[str] = field(default_factory=list)
    row_ranges: list[RowRange] | None = None
    best_cells: int | None = None

    @property
    def all_attainable(self) -> bool:
        """Every cell attainable and every row can sum to N."""
        return all(r.consistent for r in self.rows)

    @property
    def unattainable(self) -> list[CellCheck]:
        """Cells no count can produce."""
        return [c for r in self.rows for c in r.cells if not c.attainable]

    def counts_table(self) -> dict[str, list[int] | None]:
        """Reconstructed counts per item (None for a row that cannot be rebuilt)."""
        return {r.item: r.reconstructed for r in self.rows}

    def to_dict(self) -> dict:
        """The command line's ``--json`` shape: ``{"n": int, "rows": [...]}``.

        When N was searched in a range, ``"n_range": [lo, hi]`` and ``"feasible_n"``
        (every N making the whole table attainable) are added, and to each row
        ``"feasible_n"`` (the first :data:`SHOWN_N` N making that row attainable) and
        ``"feasible_n_count"`` (how many N in the range do).
        """
        out = {"n": self.n, "rows": [r.to_dict() for r in self.rows]}
        if self.n_range is not None:
            out["n_range"] = list(self.n_range)
            out["feasible_n"] = list(self.feasible_n or [])
            for row, rr in zip(out["rows"], self.row_ranges or []):
                row.update(feasible_n=list(rr.first), feasible_n_count=rr.count)
        return out

    def to_full_dict(self) -> dict:
        """Everything: the ``--json`` fields plus nearest values, reconstruction and reasons."""
        return {"n": self.n, "rule": self.rule, "source": self.source,
                "labels": list(self.labels),
                "n_range": list(self.n_range) if self.n_range else None,
                "feasible_n": self.feasible_n,
                "all_attainable": self.all_attainable,
                "rows": [r.to_full_dict() for r in self.rows]}

    def format_text(self) -> str:
        """Human-readable report (one line per cell that is not attainable). With a range
        of N: the N making the whole table attainable; when there is none, the N making
        each row attainable and why the rows are checked against the N they are."""
        out = [f"{self.source}: checked against N = {self.n} (rounding: {self.rule})"]
        if self.n_range is not None:
            out = self._range_text()
        for r in self.rows:
            rec = "" if r.reconstructed is None else "; counts " + ",".join(map(str, r.reconstructed))
            d = max(c.decimals for c in r.cells)
            said = "" if r.findings else f" (printed sum {r.printed_sum:.{d}f})"
            out.append(f"  {r.item}: {r.verdict}{said}{rec}")
            for c in r.cells:
                if not c.attainable:
                    out.append(f"    {c.label} = {c.printed}: {c.reason}")
        bad = len(self.unattainable)
        total = sum(len(r.cells) for r in self.rows)
        out.append(f"{total - bad} of {total} cells attainable")
        return "\n".join(out)

    def _range_text(self) -> list[str]:
        """The head of :meth:`format_text` when N was searched in :attr:`n_range`."""
        lo, hi = self.n_range
        fn = self.feasible_n or []
        if fn:
            shown = ", ".join(map(str, fn[:SHOWN_N])) + (" ..." if len(fn) > SHOWN_N else "")
            return [f"{self.source}: checked against N = {self.n}, the smallest N in {lo}..{hi} "
                    f"making the whole table attainable (rounding: {self.rule})",
                    f"N in {lo}..{hi} making the whole table attainable: {shown}"]
        total = sum(len(r.cells) for r in self.rows)
        out = [f"{self.source}: N not stated; searched {lo}..{hi} (rounding: {self.rule})",
               f"N in {lo}..{hi} making the whole table attainable: none; N making each row "
               f"attainable (the counts at the smallest):"]
        out += [f"  {r.item}: {rr.text()}" + ("" if rr.count or r.sum_ok else
                                             " (SUM OFF whatever N: see below)")
                for r, rr in zip(self.rows, self.row_ranges or [])]
        out.append(f"checked against N = {self.n}, the smallest N in {lo}..{hi} at which the "
                   f"most cells are attainable ({self.best_cells} of {total}):")
        return out

    def __repr__(self):
        return (f"TableCheck(n={self.n}, rows={len(self.rows)}, "
                f"unattainable={[(c.item, c.label) for c in self.unattainable]})")


# ---------------------------------------------------------------------------
# checking
# ---------------------------------------------------------------------------
def _validate_verify(table, n, n_range, rule, decimals):
    if not isinstance(table, PublishedTable):
        raise TypeError(f"`table` must be a PublishedTable, got {type(table).__name__}")
    _validate_rule(rule)
    if len(table.items) * len(table.labels) > MAX_TABLE_CELLS:
        raise SurveyInputError(f"{len(table.items) * len(table.labels)} cells; a table may have "
                               f"at most {MAX_TABLE_CELLS}", table.source)
    if (n is None) == (n_range is None):
        raise ValueError("give exactly one of `n` and `n_range`")
    if n is not None and (not isinstance(n, int) or isinstance(n, bool) or n < 1 or n > MAX_N):
        raise SurveyInputError(f"N must be a whole number from 1 to {MAX_N}, got {n!r}",
                               table.source)
    if n_range is not None:
        lo, hi = n_range
        if not (isinstance(lo, int) and isinstance(hi, int)) or lo < 1 or hi < lo or hi > MAX_N:
            raise SurveyInputError(
                f"N range must satisfy 1 <= LO <= HI <= {MAX_N}, got {lo!r}..{hi!r}", table.source)
    if decimals is not None and (not isinstance(decimals, int) or decimals < 0 or decimals > 6):
        raise ValueError(f"`decimals` must be an integer 0..6 or None, got {decimals!r}")


def _validate_n_needed(table: PublishedTable, n: int) -> None:
    """Every non-zero printed cell needs at least one respondent: N below that is bad input."""
    for i, item in enumerate(table.items):
        nonzero = sum(1 for j in range(len(table.labels)) if table.value(i, j)[0] > 0)
        if n < nonzero:
            raise SurveyInputError(
                f"N = {n} is smaller than the counts need: row {item!r} has {nonzero} non-zero "
                f"cells, so at least {nonzero} respondents", table.source, table.row_of(i))


def _check_cell(item, label, value, dec, text, n, rule) -> CellCheck:
    counts = attainable_counts(value, dec, n, rule)
    near_k, near_v = nearest_attainable(value, dec, n, rule)
    shown = text.strip().rstrip("%").strip()
    if counts:
        ks = (", ".join(map(str, counts)) if len(counts) <= 4
              else f"each of {counts[0]}..{counts[-1]}")
        reason = f"attainable: {ks} of {n} print as {shown}"
        near_k, near_v = list(counts), [value] * len(counts)
    else:
        alts = " or ".join(f"{_fmt(v, dec)} ({k}/{n})" for k, v in zip(near_k, near_v))
        exact = " / ".join(f"{k}/{n} = {float(Fraction(100 * k, n)):.4g}%" for k in near_k)
        reason = (f"not attainable: no count out of {n} rounds to {shown}; "
                  f"nearest attainable {alts}, exact {exact}")
    return CellCheck(item=item, label=label, published=float(value), printed=text.strip(),
                     decimals=dec, attainable=bool(counts), counts=counts,
                     nearest_counts=near_k, nearest_values=[float(v) for v in near_v],
                     reason=reason)


def _run(options: list[int]) -> tuple[int, int]:
    """``(lo, hi)`` of a set of counts that is a run of consecutive integers.

    Every candidate set here is one: the counts that print as one value (rounding
    is monotone in k), and the one or two counts nearest a printed value.
    """
    lo, hi = options[0], options[-1]
    if hi - lo + 1 != len(options):
        raise RuntimeError(f"counts {options!r} are not consecutive")   # a bug, not input
    return lo, hi


def _sum_reachable(runs: list[tuple[int, int]], n: int) -> bool:
    """Some choice of one count per run adds up to ``n``: every sum between the
    sums of the smallest and of the largest counts is reachable."""
    return sum(lo for lo, _ in runs) <= n <= sum(hi for _, hi in runs)


def _unique_sum(runs: list[tuple[int, int]], n: int) -> bool:
    """Exactly one choice of one count per run adds up to ``n`` (given one exists).

    With two runs of more than one count and ``n`` strictly between the extreme sums,
    a solution has a count above its minimum and another below its maximum: moving
    one respondent between them gives a second solution. Otherwise the choice is forced.
    """
    if not _sum_reachable(runs, n):
        return False
    variable = sum(1 for lo, hi in runs if hi > lo)
    return (variable <= 1 or n == sum(lo for lo, _ in runs)
            or n == sum(hi for _, hi in runs))


def _reconstruct(options: list[list[int]], targets: list[Fraction], n: int) -> list[int] | None:
    """Choice of one option per cell summing to n, closest to the printed values.

    Minimises ``sum |100 k_i / n - p_i|`` over runs of consecutive counts. The cost
    of each cell is convex in its count, so starting every cell at its smallest count
    and adding respondents one at a time where the cost falls most (or rises least)
    is optimal; the steps come in three kinds (towards the target by a whole count,
    the one step across it, away from it), taken in bulk, so the work does not grow
    with N. Equal steps go to the earlier cell.
    """
    runs = [_run(o) for o in options]
    if not _sum_reachable(runs, n):
        return None
    counts = [lo for lo, _ in runs]
    left = n - sum(counts)
    goal = [p * n / 100 for p in targets]             # exact count each printed value implies
    below = [max(0, min(hi, math.floor(t)) - lo) for (lo, hi), t in zip(runs, goal)]
    for i in range(len(counts)):                      # whole steps towards the target
        step = min(left, below[i])
        counts[i] += step
        left -= step
    across = sorted((2 * counts[i] + 1 - 2 * goal[i], i) for i in range(len(counts))
                    if counts[i] < runs[i][1] and counts[i] < goal[i] < counts[i] + 1
                    and below[i] == counts[i] - runs[i][0])
    for _, i in across:                               # the step across the target
        if left == 0:
            break
        counts[i] += 1
        left -= 1
    for i in range(len(counts)):                      # away from the target
        step = min(left, runs[i][1] - counts[i])
        counts[i] += step
        left -= step
    return counts


def _explain_adjustment(counts: list[int], printed: list[Fraction], cells: list[CellCheck],
                        n: int, rule: str) -> str:
    """A known way the printed row could come from ``counts``, or ``""``.

    Tested: (a) every cell rounded, then the row's rounding deficit added to its
    largest cell so the row shows 100; (b) largest-remainder (Hamilton) rounding.
    """
    decs = [c.decimals for c in cells]
    rounded = [round_fraction(Fraction(100 * k, n), d, rule) for k, d in zip(counts, decs)]
    if rounded == printed:
        return ""
    deficit = 100 - sum(rounded)
    off = [j for j in range(len(counts)) if rounded[j] != printed[j]]
    big = max(range(len(counts)), key=lambda j: counts[j])
    if (sum(printed) == 100 and deficit != 0 and off == [big]
            and printed[big] - rounded[big] == deficit):
        return (f"consistent with rounding every cell and adding the row's deficit of "
                f"{_fmt(deficit, max(decs))} to its largest cell, so that the row shows 100")
    if len(set(decs)) == 1 and sum(printed) == 100:
        if largest_remainder(counts, decs[0]) == printed:
            return "consistent with largest-remainder rounding, so that the row shows 100"
    return ""


def _exact_total(cells: list[CellCheck], values: list[Fraction], rule: str):
    """Whether 100 is among the totals of exact shares that print as the row's cells;
    the least and greatest such total and whether each is reached. A cell printed with
    more decimals than the rounding keeps is taken at its face value."""
    lo = hi = Fraction(0)
    lo_closed = hi_closed = True
    for c, v in zip(cells, values):
        band = rounding_interval(v, c.decimals, rule) or (v, v, True, True)
        lo, hi = lo + band[0], hi + band[1]
        lo_closed, hi_closed = lo_closed and band[2], hi_closed and band[3]
    ok = (lo < 100 < hi) or (lo == 100 and lo_closed) or (hi == 100 and hi_closed)
    return ok, lo, hi, lo_closed, hi_closed


def _verdict(cells, values, n, rule, rec, strict) -> tuple[bool, list[str], str, tuple]:
    """sum_ok, the findings and the one-line verdict of a checked row.

    The verdict names each finding by its label in :data:`FINDINGS`, then its evidence.
    """
    d = max(c.decimals for c in cells)
    printed = _fmt(sum(values), d)
    sum_ok, lo, hi, lo_closed, hi_closed = _exact_total(cells, values, rule)
    total = (f"{'[' if lo_closed else '('}{_fmt(lo, d + 1)}, {_fmt(hi, d + 1)}"
             f"{']' if hi_closed else ')'}")
    found: dict[str, str] = {}
    bad = [c for c in cells if not c.attainable]
    if bad:
        found["cell_not_attainable"] = "; ".join(
            f"{c.label} = {c.printed} (nearest attainable "
            + " or ".join(f"{v:.{c.decimals}f} = {k}/{n}"
                          for k, v in zip(c.nearest_counts, c.nearest_values)) + ")"
            for c in bad)
    if not sum_ok:
        found["sum_off"] = (f"printed sum {printed}, but the printed cells stand for exact "
                            f"shares totalling {total}, which excludes 100")
    elif not bad and not _sum_reachable(strict, n):
        ks = sum(a for a, _ in strict), sum(b for _, b in strict)
        found["counts_do_not_add_up"] = (
            f"every cell attainable and printed sum {printed} within rounding of 100, but "
            f"the counts they allow total {ks[0]}" + (f" to {ks[1]}" if ks[1] > ks[0] else "")
            + f", never N = {n}")
    said = [f"{FINDINGS[f]}: {why}" for f, why in found.items()]
    if bad and sum_ok:
        said.append(f"printed sum {printed} within rounding of 100 (exact totals {total})")
    if bad and rec is None:
        said.append("with the nearest attainable values no choice of counts adds up to N")
    return sum_ok, list(found), "; ".join(said) or "ok", (float(lo), float(hi))


def _check_row(table: PublishedTable, i: int, n: int, rule: str, decimals) -> RowCheck:
    item, cells, values = table.items[i], [], []
    for j, label in enumerate(table.labels):
        value, dec = table.value(i, j)
        dec = dec if decimals is None else decimals
        values.append(value)
        cells.append(_check_cell(item, label, value, dec, table.cells[i][j], n, rule))
    all_ok = all(c.counts for c in cells)
    strict = [_run(c.counts) for c in cells] if all_ok else []
    consistent = all_ok and _sum_reachable(strict, n)
    unique = consistent and _unique_sum(strict, n)
    loose = [c.counts if c.attainable else c.nearest_counts for c in cells]
    rec = _reconstruct(loose, values, n)
    sum_ok, findings, verdict, total = _verdict(cells, values, n, rule, rec, strict)
    reason = verdict
    if not all_ok and rec is not None:
        reason += "; with the nearest attainable values the counts add up to N"
        why = _explain_adjustment(rec, values, cells, n, rule)
        if why:
            reason += f"; {why}"
            for c in cells:
                if not c.attainable:
                    c.reason += f" ({why})"
    return RowCheck(item=item, cells=cells, sum_ok=sum_ok, consistent=consistent,
                    findings=findings, verdict=verdict, printed_sum=float(sum(values)),
                    exact_total=total, reconstructed=rec, unique=unique, reason=reason)


def _check_rows(table: PublishedTable, n: int, rule: str, decimals) -> list[RowCheck]:
    return [_check_row(table, i, n, rule, decimals) for i in range(len(table.items))]


def verify_table(table: PublishedTable, n: int | None = None,
                 n_range: tuple[int, int] | None = None, rule: str = "half_away",
                 decimals: int | None = None) -> TableCheck:
    """Check every printed cell of ``table`` against a number of respondents.

    Parameters
    ----------
    table : PublishedTable
        The table as printed (see :func:`read_table_csv`).
    n : int, optional
        Stated number of respondents (the denominator of every row).
    n_range : (int, int), optional
        Inclusive range of N to search when N is not stated.
    rule : {"half_away", "half_even", "truncate", "ceil"}
        How the table's author rounded; default half away from zero.
    decimals : int, optional
        Printed precision; by default read from each cell's text.

    Returns
    -------
    TableCheck

    Raises
    ------
    SurveyInputError
        N out of range, or smaller than a row's non-zero cells need (names the
        table file and row).
    ValueError
        Unknown ``rule`` (lists the valid rules), both or neither of ``n`` and ``n_range``.

    Notes
    -----
    A cell is attainable when ``round(100 k / N, d) == p`` for some integer
    ``0 <= k <= N`` (exact rational arithmetic). A row is ``consistent`` when one may
    choose an attainable count per cell so that the counts add up to N; its ``findings``
    and ``verdict`` say what is wrong otherwise (see the module's notes).
    """
    _validate_verify(table, n, n_range, rule, decimals)
    _validate_n_needed(table, n if n is not None else n_range[1])
    labels = list(table.labels)
    if n is not None:
        return TableCheck(n=n, rows=_check_rows(table, n, rule, decimals), rule=rule,
                          source=table.source, labels=labels)
    lo, hi = n_range
    score, row_ok = _scan_n(table, lo, hi, rule, decimals)
    ok = np.logical_and.reduce(row_ok) if row_ok else np.ones(score.size, dtype=bool)
    feasible = [int(x) for x in np.flatnonzero(ok) + lo]
    best_n = int(np.argmax(score)) + lo           # first N attaining the most cells
    shown = feasible[0] if feasible else best_n
    ranges = []
    for i, row in enumerate(row_ok):
        ns = np.flatnonzero(row)
        first = [int(x) + lo for x in ns[:SHOWN_N]]
        counts = _check_row(table, i, first[0], rule, decimals).reconstructed if first else None
        ranges.append(RowRange(first=first, count=int(ns.size), counts=counts))
    return TableCheck(n=shown, rows=_check_rows(table, shown, rule, decimals), rule=rule,
                      source=table.source, n_range=(lo, hi), feasible_n=feasible, labels=labels,
                      row_ranges=ranges, best_cells=int(score[shown - lo]))


def _count_bounds(value: Fraction, dec: int, n: "np.ndarray", rule: str):
    """Smallest and largest count k with ``round(100 k / n, dec) == value``, for many n.

    The counts that print as one value form a run of consecutive integers (rounding
    is monotone), so two bounds describe them; empty when ``lo > hi``. In integers,
    with ``y = 100 S k / n``, ``S = 10**dec`` and ``P = value * S``:
    half_away ``P - 1/2 <= y < P + 1/2``; half_even the same, both ends closed for
    even P and open for odd P; truncate ``P <= y < P + 1``; ceil ``P - 1 < y <= P``.
    """
    S = 10 ** dec
    Pf = value * S
    if Pf.denominator != 1:          # more printed decimals than the rounding keeps
        return np.ones_like(n), np.zeros_like(n)
    P = Pf.numerator

    def ceil_div(a, b):
        return -((-a) // b)
    if rule in ("half_away", "half_even"):
        a, b, d = (2 * P - 1) * n, (2 * P + 1) * n, 200 * S
        if rule == "half_away" or P % 2 == 1:
            lo = a // d + 1 if rule == "half_even" else ceil_div(a, d)
            hi = ceil_div(b, d) - 1
        else:
            lo, hi = ceil_div(a, d), b // d
    elif rule == "truncate":
        lo, hi = ceil_div(P * n, 100 * S), ceil_div((P + 1) * n, 100 * S) - 1
    else:  # ceil
        lo, hi = ((P - 1) * n) // (100 * S) + 1, (P * n) // (100 * S)
    return np.maximum(lo, 0), np.minimum(hi, n)


def _scan_n(table, lo_n: int, hi_n: int, rule: str, decimals) -> tuple:
    """For every N in lo_n..hi_n at once: (attainable cells, [row consistent, per row]).

    A row is consistent when each cell has a count and the sum of the smallest counts
    <= N <= the sum of the largest (every sum in between is reachable, the sets being
    runs of consecutive integers). Vectorised over N: a range up to MAX_N takes
    seconds, where checking each N in turn took hours.
    """
    n = np.arange(lo_n, hi_n + 1, dtype=np.int64)
    score = np.zeros(n.size, dtype=np.int64)
    rows = []
    for i in range(len(table.items)):
        ok = np.ones(n.size, dtype=bool)
        sum_lo = np.zeros(n.size, dtype=np.int64)
        sum_hi = np.zeros(n.size, dtype=np.int64)
        for j in range(len(table.labels)):
            value, dec = table.value(i, j)
            klo, khi = _count_bounds(value, dec if decimals is None else decimals, n, rule)
            have = klo <= khi
            score += have
            ok &= have
            sum_lo += klo
            sum_hi += khi
        rows.append(ok & (sum_lo <= n) & (n <= sum_hi))
    return score, rows


# ---------------------------------------------------------------------------
# the paper's Table 1
# ---------------------------------------------------------------------------
@dataclass(frozen=True)
class SurveyFacts:
    """Response facts printed with a table (from ``data/published/survey.toml``)."""

    table_id: str
    title: str
    respondents: int
    enrolled: int
    decimals: int
    scale: str
    labels: tuple[str, ...]
    item_ids: tuple[str, ...]
    item_texts: tuple[str, ...]
    table_file: Path


def load_survey_facts(path: "str | Path | None" = None) -> SurveyFacts:
    """Read ``survey.toml`` (respondents, enrolled, items, scale, table id)."""
    p = Path(path) if path is not None else published_dir() / "survey.toml"
    data = read_toml(p)
    try:
        t, r = data["table"], data["response"]
        items = data["items"]
        return SurveyFacts(table_id=str(t["id"]), title=str(t.get("title", "")),
                           respondents=int(r["respondents"]), enrolled=int(r["enrolled"]),
                           decimals=int(t["decimals"]), scale=str(t.get("scale", "paper")),
                           labels=tuple(data["scale"]["labels"]),
                           item_ids=tuple(str(x["id"]) for x in items),
                           item_texts=tuple(str(x["text"]) for x in items),
                           table_file=p.parent / str(t["file"]))
    except KeyError as e:
        raise SurveyInputError(f"key {e.args[0]!r}: missing", str(p)) from None


def load_table1() -> tuple[PublishedTable, SurveyFacts]:
    """The paper's Table 1 as printed and its response facts."""
    facts = load_survey_facts()
    return read_table_csv(facts.table_file), facts


def table1_check(rule: str = "half_away") -> TableCheck:
    """Check the paper's Table 1 against its stated number of respondents.

    Reads ``data/published/table1.csv`` and ``survey.toml``; nothing is typed in code.

    Returns
    -------
    TableCheck
        ``.rows[i].reconstructed`` holds the rebuilt counts per item,
        ``.unattainable`` the printed cells no count can give.
    """
    table, facts = load_table1()
    return verify_table(table, n=facts.respondents, rule=rule, decimals=facts.decimals)
