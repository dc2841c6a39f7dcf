"""Institution-scale counting: many courses x sections x terms, files larger than memory.

The answers are counted by DuckDB (an embedded columnar engine) straight from the
CSV or Parquet file, out of core: memory stays bounded by ``memory_limit`` whatever the
file's size, and DuckDB spills to a temporary folder when its hash tables would not
fit. One scan of the file yields the answers per (grouping values, item, answer
text) and the respondents per group; the institution-wide distribution is the sum of
the groups' tallies (no second scan). Answer texts are then matched to the scale in
Python (there are few distinct texts), and every per-group and institution-wide item
summary comes from :func:`analysis.likert.summarize_tally`, the same route as
``summarize`` on a small file, so the numbers agree.

Layouts: *long* (a row per answer: respondent, item, answer columns, named as in
:mod:`analysis.ingest`) or *wide* (a row per respondent, a column per item). Which
columns (or, long, which items) are items, and on which scale, is decided from the
counted answer texts by :func:`analysis.ingest.choose_items_from_counts`, the rule of
``read_survey``: so a term or a comments column is left out here as it is there, and
listed among the ``not_items`` with the reason. In a long file a respondent of a group
with no row for an item is missing on it (respondents per group are distinct
respondent ids); ids and item names are trimmed and an answer given twice by one
respondent is refused, as ``read_survey`` does. Spellings of a grouping value that differ
only in case or spacing are one group, by the rule of ``--group``
(:func:`analysis.scales.group_names`).

Two columns named alike (ignoring case and spacing, as DuckDB does) are refused: DuckDB
would rename the second ``Q1_1`` without a word.

pandas is not imported on this path (it would cost more memory than the counting).

Public API: :func:`summarize_by` -> :class:`GroupedSummary`.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import platforms
from ._io import (ShortRecords, is_regular_file, refuse_values_beyond_header, short_records_note,
                  sniff_delimiter)
from .disclosure import BLANK_GROUP, count_text, respondents_text, suppress_groups
from .dropped import FOOTER, DroppedRow, is_footer_note
from .errors import SurveyInputError
from .export import reversal_columns
from .likert import (REVERSE_MARK, REVERSE_NOTE, _validate_ci, absent_respondents,
                     interval_label, not_items_text)
from .rounding import number_text, quartile_texts, share_percent_text
from .scales import (Scale, group_names, normalize_answer, order_groups, two_groups_message,
                     validate_group_order)

__all__ = ["GroupedSummary", "summarize_by", "DEFAULT_MEMORY_LIMIT"]

#: DuckDB's memory limit unless given: the counting spills to disk beyond it.
DEFAULT_MEMORY_LIMIT = "48MB"
#: If DuckDB runs out of memory that it cannot spill, the count is retried with the
#: limit multiplied by these factors (a count that fails is worse than one that uses more).
_RETRY_FACTORS = (1, 4, 16)
_MAX_GROUP_COLUMNS = 8
_BUFFER, _MAX_LINE = 8 * 2 ** 20, 2 ** 20        # CSV read buffer; longest line accepted
#: White space trimmed from respondent ids and item names (as Python's ``str.strip``
#: trims the common ones in ``read_survey``).
_WS = "' \t\n\r\x0b\x0c\u00a0'"
#: Repeated (respondent, item) pairs looked at to name the one met first in the file.
_MAX_REPEATS = 1000
#: Largest file read again (in Python, a few seconds) to give the rows of repeated ids in
#: a note; beyond it the note gives how many rows each id is on.
_MAX_REREAD = 64 * 2 ** 20


@dataclass
class GroupedSummary:
    """Item summaries per group (e.g. course x term) and institution-wide.

    Attributes
    ----------
    source : str
    by : list of str
        Grouping columns.
    scale : Scale
    items : list of str
    groups : list of tuple of str
        Grouping values, sorted as text or by ``group_order`` (a blank value is "" here;
        outputs name it :data:`~analysis.disclosure.BLANK_GROUP`, see :meth:`group_names`).
    respondents : numpy.ndarray of int, shape (groups,)
    tallies : numpy.ndarray of int, shape (groups, items, k + 3)
        Per group and item: unknown (0), not applicable (1), blank/absent (2), then
        the count of each label (the layout of :func:`analysis.likert.summarize_tally`).
    shape : str
        ``"long"`` or ``"wide"``.
    min_group : int
        Groups with fewer respondents are suppressed in outputs (small cells).
    not_items : dict of str to str
        Columns (long: items) not counted as items, each with the reason.
    fields : list of str
        A wide file's header of each item (items are named by statement, as
        :func:`analysis.ingest.read_survey` names them: ``Rate [Clear]`` is ``Clear``).
    """

    source: str
    by: list
    scale: Scale
    items: list
    groups: list
    respondents: np.ndarray
    tallies: np.ndarray
    shape: str
    min_group: int = 5
    notes: list = field(default_factory=list)
    reverse: set = field(default_factory=set)
    ci_method: str = "wilson"
    confidence_level: float = 0.95
    not_items: dict = field(default_factory=dict)
    fields: list = field(default_factory=list)     # a wide file's header of each item
    dropped: list = field(default_factory=list)

    def _item_summaries(self, tally, respondents: int, confidence_level, method) -> list:
        """Summaries of every item from one (items, k + 3) tally (the one route,
        :func:`analysis.likert.summarize_tally`; reversal and interval as declared)."""
        from .likert import summarize_tally
        level = self.confidence_level if confidence_level is None else confidence_level
        return [summarize_tally(tally[i], self.scale, name, respondents=respondents,
                                reverse=name in self.reverse, confidence_level=level,
                                method=method or self.ci_method)
                for i, name in enumerate(self.items)]

    def overall(self, confidence_level=None, method=None) -> list:
        """Institution-wide item summaries (the sum of every group's tally); the interval
        by :attr:`ci_method` at :attr:`confidence_level` unless given."""
        return self._item_summaries(self.tallies.sum(axis=0), int(self.respondents.sum()),
                                    confidence_level, method)

    def group_summaries(self, g: int, confidence_level=None, method=None) -> list:
        """Item summaries of group ``g`` (an index into :attr:`groups`)."""
        return self._item_summaries(self.tallies[g], int(self.respondents[g]),
                                    confidence_level, method)

    def group_names(self, g: int) -> list:
        """The grouping values of group ``g`` as every output names them (a blank value
        as :data:`~analysis.disclosure.BLANK_GROUP`, as ``--group`` names it)."""
        return [v or BLANK_GROUP for v in self.groups[g]]

    def suppression(self):
        """The groups withheld: under :attr:`min_group`, and their complements (the
        institution-wide totals are shown, see :mod:`analysis.disclosure`)."""
        return suppress_groups(self.respondents, self.min_group,
                               [" / ".join(self.group_names(g)) for g in range(len(self.groups))])

    def suppressed(self, g: int) -> bool:
        """Group ``g`` is withheld (small, or its complement)."""
        return self.suppression().withheld(g)

    def _why(self, g: int) -> str:
        if int(self.respondents[g]) < self.min_group:
            return f"fewer than {respondents_text(self.min_group)}"
        return ("complementary suppression: with it shown, a smaller group would be the "
                "total minus the groups shown")

    def rows(self) -> list[dict]:
        """One record per (group, item), institution-wide first; suppressed groups blanked."""
        out = []
        withheld = self.suppression()
        for g in [None] + list(range(len(self.groups))):
            values = ["(all)"] * len(self.by) if g is None else self.group_names(g)
            key = dict(zip(self.by, values))
            if g is not None and withheld.withheld(g):
                out.append({**key, "item": "", "respondents": int(self.respondents[g]),
                            "suppressed": self._why(g)})
                continue
            sums = self.overall() if g is None else self.group_summaries(g)
            for it in sums:
                rec = {**key, "item": it.item, **reversal_columns(it),
                       "respondents": it.respondents, "n": it.n,
                       "missing": it.missing, "excluded": it.excluded}
                rec.update({f"{lab} (count)": it.counts[lab] for lab in it.labels})
                rec.update({"agree_share": it.agree.share, "agree_ci_low": it.agree.ci[0],
                            "agree_ci_high": it.agree.ci[1], "median": it.median,
                            "iqr": it.iqr, "mean": it.mean, "sd": it.sd})
                out.append(rec)
        return out

    def to_frame(self):
        """One row per (group, item), institution-wide first, with the columns of every summary
        table (:func:`analysis.export.item_columns`) after the grouping columns, the item and
        its respondents; a suppressed group is one row saying why. Counts stay whole numbers
        (nullable ``Int64``, blank in a suppressed group's row, where a float column would
        print ``36.0``)."""
        import pandas as pd
        from .export import item_columns
        rows = []
        withheld = self.suppression()
        for g in [None] + list(range(len(self.groups))):
            key = dict(zip(self.by, ["(all)"] * len(self.by) if g is None else self.group_names(g)))
            if g is not None and withheld.withheld(g):
                rows.append({**key, "item": "", "respondents": int(self.respondents[g]),
                             "suppressed": self._why(g)})
                continue
            for it in (self.overall() if g is None else self.group_summaries(g)):
                rows.append({**key, "item": it.item, "respondents": it.respondents,
                             **item_columns(it, it.labels)})
        frame = pd.DataFrame(rows)
        counts = [c for c in frame.columns if c in ("respondents", "n", "missing", "excluded")
                  or str(c).endswith(" (count)")]
        return frame.astype({c: "Int64" for c in counts})

    def to_dict(self) -> dict:
        return {"source": self.source, "by": list(self.by), "shape": self.shape,
                "scale": self.scale.name, "min_group": self.min_group,
                "ci_method": self.ci_method, "confidence_level": self.confidence_level,
                "reversed": [n for n in self.items if n in self.reverse],
                "respondents": int(self.respondents.sum()), "groups": len(self.groups),
                "overall": [it.to_dict() for it in self.overall()], "rows": self.rows(),
                "not_items": list(self.not_items), "not_item_reasons": dict(self.not_items),
                "dropped": [vars(d) for d in self.dropped], "notes": self._all_notes()}

    def _all_notes(self) -> list:
        note = self.suppression().note
        kinds: dict = {}
        for d in self.dropped:
            kinds.setdefault(d.reason, []).append(d)
        dropped = [f"{len(rows)} {reason}{'s' if len(rows) != 1 else ''} dropped in all: "
                   f"{rows[0].why}" for reason, rows in kinds.items()]
        return dropped + list(self.notes) + ([note] if note else [])

    def note_lines(self) -> list[str]:
        """The notes as every output shows them (``note: ...``, a warning as written), as
        :meth:`analysis.ingest.SurveyData.note_lines` gives the in-memory route's."""
        from .ingest import note_line
        return [note_line(n) for n in self._all_notes()]

    def format_text(self, decimals: int = 1) -> str:
        """One line per (group, item), institution-wide first; the agreement share printed
        to ``decimals`` places by the project's rounding rule, with its interval."""
        out = [f"{self.source}: {respondents_text(int(self.respondents.sum()))} in "
               f"{count_text(len(self.groups), 'group')} by {', '.join(self.by)}; scale "
               f"{self.scale.name!r}; {self.shape} file counted out of core (DuckDB); agreement with its "
               f"{interval_label(self.confidence_level, self.ci_method)}"]
        labels = list(self.scale.labels)
        withheld = self.suppression()
        for g in [None] + list(range(len(self.groups))):
            head = " / ".join(["(all)"] * len(self.by) if g is None
                              else self.group_names(g))
            if g is not None and withheld.withheld(g):
                out.append(f"{head}: suppressed ({self._why(g)})")
                continue
            for it in (self.overall() if g is None else self.group_summaries(g)):
                dist = " ".join(str(it.counts[lab]) for lab in labels)
                ag = it.agree
                agree = ("-" if ag.share is None else f"{ag.percent_text(decimals)}% "
                         f"[{share_percent_text(ag.ci[0], decimals)}%, {share_percent_text(ag.ci[1], decimals)}%]")
                stats = " ".join(f"{k} {v}" for k, v in (
                    ("median", number_text(it.median)), ("IQR", quartile_texts(it.q1, it.q3)[0]),
                    ("mean", number_text(it.mean, 2)), ("SD", number_text(it.sd, 2))))
                mark = REVERSE_MARK if it.reverse else ""
                out.append(f"{head}: {it.item}{mark}: n={it.n} missing={it.missing} "
                           f"n/a={it.excluded} counts [{dist}] agree {agree} {stats}")
        out.append("counts in scale order: " + ", ".join(labels))
        if self.not_items:
            out.append(not_items_text(self.not_items))
        if self.reverse:
            out.append(REVERSE_NOTE)
        out.extend(f"dropped {'the last row' if d.row is None else f'row {d.row}'}: {d.reason}"
                   for d in self.dropped)
        out.extend(self.note_lines())
        return "\n".join(out)


def _quote(name: str) -> str:
    return '"' + name.replace('"', '""') + '"'


def _head(path: Path) -> str:
    """The first 256 KiB of a CSV file as text (a byte-order mark removed)."""
    with open(path, "rb") as f:
        return f.read(262144).decode("utf-8", errors="replace").lstrip("\ufeff")


def _delimiter(path: Path) -> str:
    """The CSV file's delimiter by the in-memory route's rule (:func:`analysis._io.sniff_delimiter`),
    from its first 256 KiB: DuckDB's own sniffer took a footer line with no comma as the sign of
    a one-column file."""
    return sniff_delimiter(_head(path))[0]


def _header_newline(head: str) -> "str | None":
    """The line break ending the first record (``"\\r\\n"``, ``"\\n"`` or ``"\\r"``), line breaks
    inside quotes skipped; None when the text holds no complete record.

    DuckDB's sniffer could not settle on one when a quoted header cell holds a line break
    other than the one between records (Excel writes ``\\n`` in a cell, ``\\r\\n`` between
    rows): given the header's, it reads such a file as Python's csv module does.
    """
    quoted = False
    for j, ch in enumerate(head):
        if ch == '"':
            quoted = not quoted
        elif not quoted and ch in "\r\n":
            if ch == "\r" and head[j + 1:j + 2] == "\n":
                return "\r\n"
            return ch if j + 1 < len(head) or ch == "\n" else None
    return None


def _csv_sql(path: Path, header: bool = True, parallel: bool = True) -> str:
    """``read_csv(...)`` of a CSV file as text: its delimiter and line break given, the quote
    ``"`` (doubled inside quotes) as Python's csv module reads it, short rows padded with blanks
    (as pandas reads them), small read buffers (DuckDB's default is 32 MB per buffer), so that
    memory stays bounded. DuckDB's sniffer, left to itself, reads a file with no quote in its
    first 20,480 rows as one with no quoting: a later quoted line break split a row in two.

    ``parallel=False`` turns DuckDB's parallel scanner off: it cannot pad short rows in a file
    with quoted line breaks (a comment on two lines) and refuses such a file
    (:class:`_SerialScanNeeded`). The serial scanner reads it, at the same CPU time on one
    thread (``summarize_by`` of 1,000,000 long rows: 1.07 s, parallel 1.11 s), so one thread
    reads serially and more threads fall back to it when refused.
    """
    head = _head(path)
    newline = _header_newline(head)
    line = "" if newline is None else f"new_line = {_literal(repr(newline)[1:-1])}, "
    return (f"read_csv({_literal(path)}, all_varchar = true, header = {str(header).lower()}, "
            f"delim = {_literal(sniff_delimiter(head)[0])}, quote = '\"', escape = '\"', {line}"
            f"null_padding = true, "
            f"parallel = {str(parallel).lower()}, "
            f"buffer_size = {_BUFFER}, max_line_size = {_MAX_LINE})")


class _SerialScanNeeded(Exception):
    """DuckDB's parallel CSV scanner met a quoted line break it cannot pad rows around."""


def _source_sql(path: Path, parallel: bool = True) -> str:
    """The file as a table of text, as a CSV is read: a Parquet file's typed columns (an integer
    id, numeric codes) cast to VARCHAR, so that ids, items and answers are matched as texts on
    both formats (a trim of an integer column failed the whole count)."""
    if path.suffix.lower() == ".parquet":
        return f"(SELECT COLUMNS(*)::VARCHAR FROM read_parquet({_literal(path)}))"
    return _csv_sql(path, parallel=parallel)


def _empty(line: str) -> bool:
    """Whether a CSV line holds no cell text: nothing but delimiters, quotes and white space."""
    return not line.strip(' \t\r\n,;"')


def _last_line(path: Path) -> "tuple[str, bool] | None":
    """The last line of a CSV file with cell text, and whether an empty line (:func:`_empty`)
    comes just before it; None when the file's tail has no such pair (only the last 2 MiB
    are read)."""
    with open(path, "rb") as f:
        f.seek(0, 2)
        size = f.tell()
        f.seek(max(0, size - 2 * _MAX_LINE))
        tail = f.read().decode("utf-8", errors="replace")
    lines = tail.splitlines()
    while lines and _empty(lines[-1]):
        lines.pop()
    if len(lines) < 3 or (size > 2 * _MAX_LINE and len(lines) < 4):
        return None                           # (a first line read from mid-file is cut)
    return lines[-1], _empty(lines[-2])


def _answer_rows(con, src: str, path: Path, header: list[str]):
    """``(source, dropped, notes)``: the rows of ``src`` that can be respondents, by the rules
    of the in-memory reader. A row whose every cell is blank is not one
    (:func:`analysis.ingest.read_survey` skips it as an empty line); nor is a CSV file's
    text-only footer row (:func:`analysis.dropped.is_footer_note`), which is dropped with its
    row. The footer is left out by its cells: when other rows have the same cells it is kept,
    with a note, rather than dropping a respondent."""
    if len(header) < 2:
        return src, [], []
    blank = [f"coalesce(trim({_quote(h)}, {_WS}), '') = ''" for h in header]
    src = f"(SELECT * FROM {src} WHERE NOT ({' AND '.join(blank)}))"
    last = None if path.suffix.lower() == ".parquet" else _last_line(path)
    if last is None or not last[1]:
        return src, [], []
    import csv
    cells = next(csv.reader([last[0]], delimiter=_delimiter(path)), [])
    cells += [""] * (len(header) - len(cells))            # a short row is padded, as it is read
    if len(cells) != len(header) or not is_footer_note(cells):
        return src, [], []
    cond = " AND ".join([f"trim({_quote(header[0])}, {_WS}) = {_literal(cells[0].strip())}"] + blank[1:])
    alike = con.execute(f"SELECT count(*) FROM {src} WHERE {cond}").fetchone()[0]
    if alike != 1:
        return src, [], [f"the last row ({cells[0].strip()!r} in its first cell only) looks like "
                         f"a {FOOTER}, but {alike} rows have these cells: all are counted as "
                         f"respondents"]
    row = None
    if path.stat().st_size <= _MAX_REREAD:
        for row, _ in _records(path, [header[0]]):
            pass
    return f"(SELECT * FROM {src} WHERE NOT ({cond}))", [DroppedRow(row, FOOTER)], []


def _scan_records(path: Path) -> "ShortRecords | None":
    """The fields of each record of a CSV file, counted by the in-memory route's byte scan
    (:class:`analysis._io.ShortRecords`, 1 MiB at a time); a record with a value beyond the
    header's last column is refused as that route refuses it
    (:func:`analysis._io.refuse_values_beyond_header`: DuckDB read it by inventing a column),
    and so is an empty file. None for a Parquet file."""
    if path.suffix.lower() == ".parquet":
        return None
    if not _head(path).strip():
        raise SurveyInputError("empty file", str(path))    # (DuckDB reads a column 'column0')
    newline = _header_newline(_head(path)) or "\n"
    scan = ShortRecords(_delimiter(path), newline[-1].encode())
    with open(path, "rb") as f:
        while chunk := f.read(1 << 20):
            scan.feed(chunk)
    scan.close()
    if scan.longer:
        with open(path, encoding="utf-8", errors="replace", newline="") as text:
            if text.read(1) != "\ufeff":
                text.seek(0)
            refuse_values_beyond_header(text, _delimiter(path), scan.width, str(path))
    return scan


def _short_rows(scan: "ShortRecords | None", path: Path, width: int, dropped: list) -> list[str]:
    """The note naming the rows with fewer fields than the header (DuckDB pads them with
    blank cells, as pandas does), the rows ``dropped`` aside, as the in-memory route words it
    (:func:`analysis._io.short_records_note`), from the file's ``scan``."""
    if scan is None or width < 2:
        return []
    # a footer whose row was not looked up is the last record holding text
    gone = {scan.last if d.row is None else d.row for d in dropped}
    note = short_records_note(str(path), [(r, n) for r, n in scan.found if r not in gone], width)
    return [note] if note else []


def _given_header(con, path: Path, header: list[str]) -> list[str]:
    """The column names as the file writes them (``header`` is DuckDB's, made distinct).

    A CSV's first record is read again as data; a Parquet file's names come from its
    schema (the root's children, in order).
    """
    lit = "'" + str(path).replace("'", "''") + "'"
    if path.suffix.lower() == ".parquet":
        rows = con.execute(f"SELECT name, num_children FROM parquet_schema({lit})").fetchall()
        names, i = [], 1
        while i < len(rows):                       # skip each top-level column's subtree
            names.append(rows[i][0])
            left = rows[i][1] or 0
            i += 1
            while left:
                left += (rows[i][1] or 0) - 1
                i += 1
    else:
        first = con.execute(f"SELECT * FROM {_csv_sql(path, header=False, parallel=False)} "
                            "LIMIT 1").fetchone()
        names = ["" if v is None else str(v) for v in (first or ())]
    return names if len(names) == len(header) else header


#: File signatures of formats --by does not read (the first bytes), with their names.
_OTHER_FORMATS = ((b"PK\x03\x04", "a zip container (an .xlsx workbook?)"),
                  (b"\xd0\xcf\x11\xe0", "an old Office file (.xls)"),
                  (b"\x1f\x8b", "gzip-compressed data"), (b"%PDF", "a PDF document"),
                  (b"PAR1", "a Parquet file named other than .parquet"))
_WORKBOOKS = (".xlsx", ".xlsm", ".xls", ".ods")


def _not_csv_or_parquet(path: Path) -> "str | None":
    """What a file named as a workbook, or starting with a known binary signature, is;
    None for a ``.parquet`` file and for anything else (read as CSV text)."""
    suffix = path.suffix.lower()
    if suffix == ".parquet":
        return None
    if suffix in _WORKBOOKS:
        return f"{suffix} (a workbook)"
    with open(path, "rb") as f:
        head = f.read(4)
    return next((what for magic, what in _OTHER_FORMATS if head.startswith(magic)), None)


def _validate_by(path, by, min_group, respondents=None, confidence_level=0.95,
                 method="wilson", group_order=None):
    p = Path(path)
    if not p.exists():
        raise SurveyInputError("no such file", str(p))
    if not is_regular_file(p):            # a FIFO would block DuckDB, /dev/zero never end
        raise SurveyInputError("not a regular file (a folder, pipe or device is not read)",
                               str(p))
    other = _not_csv_or_parquet(p)
    if other:
        raise SurveyInputError(f"--by reads CSV or Parquet, not {other}: summarize it without "
                               f"--by, or save it as CSV UTF-8", str(p))
    if not by or len(by) > _MAX_GROUP_COLUMNS:
        raise ValueError(f"--by needs 1..{_MAX_GROUP_COLUMNS} grouping columns, got {by!r}")
    if not isinstance(min_group, int) or min_group < 1:
        raise ValueError(f"--min-group must be a positive integer, got {min_group!r}")
    if respondents is not None and (not isinstance(respondents, int) or respondents < 1):
        raise ValueError(f"`respondents` must be a positive integer or None, got {respondents!r}")
    _validate_ci(method, confidence_level)
    validate_group_order(group_order)
    return p


def summarize_by(path: "str | Path", by: "list[str]", scale=None, items=None,
                 min_group: int = 5, memory_limit: str = DEFAULT_MEMORY_LIMIT,
                 threads: int = 1, reverse=None, respondents: "int | None" = None,
                 confidence_level: float = 0.95, method: str = "wilson",
                 group_order: "list[str] | None" = None) -> GroupedSummary:
    """Count a large survey file by grouping columns, out of core.

    Parameters
    ----------
    path : str or Path
        CSV (UTF-8, header row) or Parquet file, long or wide layout.
    by : list of str
        Grouping columns (course, term, section ...).
    scale : str, Scale or None
        Built-in name, TOML file or Scale; None detects the built-in scale all answers use.
    items : list of str, optional
        Item names or ``*`` patterns (wide: columns; long: values of the item column).
    min_group : int
        Groups with fewer respondents are suppressed in the outputs.
    memory_limit : str
        DuckDB's memory limit (it spills to a temporary folder beyond it).
    threads : int
        DuckDB threads (each holds its own read buffers and hash tables).
    reverse : list of str, optional
        Reverse-keyed items (names or patterns, as ``read_survey`` takes them).
    respondents : int, optional
        Declared respondents; those absent from the file belong to no group: they are
        counted missing on every item in the group of blank grouping values (as
        ``summarize --group`` counts them in its ``(blank)`` group).
    confidence_level : float
    method : {"wilson", "beta"}
        Interval of the agreement shares (as :func:`analysis.likert.summarize`).
    group_order : list of str, optional
        Grouping values to list first, in this order (``--group-order``, the rule of
        ``--group``: :func:`analysis.scales.order_groups`); a value may be of any grouping
        column, and the groups sort column by column. Otherwise the values sort as text.

    Returns
    -------
    GroupedSummary
    """
    import duckdb
    p = _validate_by(path, by, min_group, respondents, confidence_level, method, group_order)
    size, unit = _split_limit(memory_limit)
    for factor in _RETRY_FACTORS:
        limit = f"{size * factor}{unit}"
        try:
            try:          # one thread: the serial scanner, as fast and never refused
                res = _count(p, by, scale, items, min_group, limit, threads, threads > 1)
            except _SerialScanNeeded:           # quoted line breaks: the serial scanner
                res = _count(p, by, scale, items, min_group, limit, threads, parallel=False)
            break
        except duckdb.OutOfMemoryException:
            continue
    else:
        raise SurveyInputError(f"counting needs more than {size * _RETRY_FACTORS[-1]}{unit} "
                               f"of memory; give a larger memory limit", str(p))
    res.reverse = platforms.resolve_reverse(res.source, res.items, reverse, res.fields or None)
    from .ingest import scale_fit_notes
    notes, left_out = scale_fit_notes(res.source, res.scale, res.items,
                                      res.tallies.sum(axis=0)[:, 3:], res.reverse, scale is None)
    res.notes += notes
    if left_out:                # items of a narrower scale, as read_survey leaves them out
        keep = [j for j, name in enumerate(res.items) if name not in left_out]
        res.items = [res.items[j] for j in keep]
        res.fields = [res.fields[j] for j in keep if j < len(res.fields)]
        res.tallies = res.tallies[:, keep]
        res.reverse = {r for r in res.reverse if r not in left_out}
        res.not_items = {**res.not_items, **left_out}
    res.ci_method, res.confidence_level = method, confidence_level
    _declare(res, respondents)
    _order(res, group_order)
    return res


def _order(res: GroupedSummary, order) -> None:
    """Put the groups in the order ``order`` asks (:func:`analysis.scales.order_groups`, as
    ``--group`` does; the groups' values are already one spelling each)."""
    if not order:
        return
    columns = []
    for c in range(len(res.by)):
        values = list(dict.fromkeys(key[c] for key in res.groups))
        columns.append(([normalize_answer(v) for v in values],
                        {normalize_answer(v): v for v in values}))
    ranked = order_groups(columns, order, res.source)
    rank = [{k: i for i, k in enumerate(r)} for r in ranked]
    new = sorted(range(len(res.groups)), key=lambda g: [
        rank[c][normalize_answer(v)] for c, v in enumerate(res.groups[g])])
    res.groups = [res.groups[g] for g in new]
    res.respondents, res.tallies = res.respondents[new], res.tallies[new]


def _declare(res: GroupedSummary, respondents: "int | None") -> None:
    """Add the declared respondents absent from the file, missing on every item, to the
    group of blank grouping values (created when the file has none)."""
    pad = absent_respondents(respondents, int(res.respondents.sum()), res.source)
    if not pad:
        return
    blank = ("",) * len(res.by)
    if blank not in res.groups:
        g = sorted(res.groups + [blank]).index(blank)
        res.groups.insert(g, blank)
        res.respondents = np.insert(res.respondents, g, 0)
        res.tallies = np.insert(res.tallies, g, 0, axis=0)
    g = res.groups.index(blank)
    res.respondents[g] += pad
    res.tallies[g, :, 2] += pad                  # 2: blank (missing), see GroupedSummary
    res.notes.append(f"{pad} declared respondents absent from the file are counted as missing "
                     f"on every item, in the group of blank {', '.join(res.by)}")


def _split_limit(limit: str) -> tuple[int, str]:
    import re
    m = re.fullmatch(r"\s*(\d+)\s*([KMGT]i?B)\s*", str(limit), re.I)
    if not m:
        raise ValueError(f"`memory_limit` must look like '48MB', got {limit!r}")
    return int(m.group(1)), m.group(2)


def _count(p, by, scale, items, min_group, memory_limit, threads,
           parallel: bool = True) -> GroupedSummary:
    import duckdb
    import tempfile
    spill = tempfile.TemporaryDirectory(prefix="analysis-duckdb-")
    con = duckdb.connect(config={"memory_limit": memory_limit, "threads": int(threads),
                                 "preserve_insertion_order": False,
                                 "temp_directory": spill.name})
    try:
        scan = _scan_records(p)
        src = _source_sql(p, parallel)
        try:
            header = [r[0] for r in con.execute(f"DESCRIBE SELECT * FROM {src}").fetchall()]
        except duckdb.OutOfMemoryException:
            raise
        except duckdb.Error as e:
            _check_serial(e, parallel)
            bad = _not_utf8(p)
            if bad is not None:
                raise SurveyInputError(bad[1], str(p), bad[0]) from None
            raise SurveyInputError(f"cannot read as CSV/Parquet ({str(e).splitlines()[0]})",
                                   str(p)) from None
        if scan is not None and 0 < scan.width < len(header):
            header = header[:scan.width]    # columns DuckDB made of empty fields past the header
        src, dropped, footer_notes = _answer_rows(con, src, p, header)
        footer_notes += _short_rows(scan, p, len(header), dropped)
        _refuse_header_rows(con, src, p, header)
        why = platforms.repeated_column(_given_header(con, p, header))
        if why:                     # DuckDB renames a repeated Q1 to Q1_1 (and q1 too)
            raise SurveyInputError(why, str(p))
        from .ingest import column_index, group_column_name, header_item_names
        peek = [header] if p.suffix.lower() == ".parquet" else sniff_delimiter(_head(p))[1]
        statements = dict(zip(header, header_item_names(header, peek)[0]))
        gcols, shown = [], []              # as the file names them; as outputs print them
        for b in by:
            why = platforms.long_column_refusal("--by", b, header)
            if why:
                raise SurveyInputError(why, str(p))
            j = column_index(str(p), header, b, list(statements.values()), flag="--by")
            gcols.append(header[j])
            shown.append(group_column_name(header[j], statements[header[j]], b))
        ri, ii, ai = (platforms.find_column(header, platforms.LONG_RESP),
                      platforms.find_column(header, platforms.LONG_ITEM),
                      platforms.find_column(header, platforms.LONG_ANSWER))
        left_out, idcol = {}, None
        if None not in (ri, ii, ai):
            shape = "long"
            rows = _count_long(con, src, gcols, header[ri], header[ii], header[ai], p)
        else:
            shape = "wide"
            idcols = {header[j] for j in range(len(header)) if platforms.find_column(
                [header[j]], platforms.LONG_RESP) is not None}
            cand = [h for h in header if h not in gcols and h not in idcols]
            if items:
                from .ingest import unmatched_item
                for pat in items:         # a pattern matching no column, as read_survey says
                    if not any(platforms.item_matches(pat, h, statements[h]) for h in header):
                        raise unmatched_item(str(p), pat, [statements[h] for h in header])
                cand = [h for h in cand if any(platforms.item_matches(pat, h, statements[h])
                                               for pat in items)]
            left_out = {h: ("grouping column" if h in gcols else
                            "an identifier column" if h in idcols else "not named by --items")
                        for h in header if h not in cand}
            if not cand:
                raise SurveyInputError("no item columns to count", str(p), 1)
            from .ingest import person_id_column
            pid = person_id_column(header)
            idcol = header[pid] if pid is not None and header[pid] not in gcols else None
            rows = _count_wide(con, src, gcols, cand, idcol)
            repeats = [r for r in rows if r[len(gcols) + 2] == 2]
            spelled = (_id_spellings(con, src, idcol, [r[len(gcols) + 1] for r in repeats[:3]])
                       if repeats and p.stat().st_size > _MAX_REREAD else {})
            rows = _merge_spellings([r for r in rows if r[len(gcols) + 2] == 0],
                                    len(gcols), cand[0])
    except duckdb.OutOfMemoryException:
        raise
    except duckdb.Error as e:
        _check_serial(e, parallel)
        raise SurveyInputError(f"counting failed ({str(e).splitlines()[0]})", str(p)) from None
    finally:
        con.close()
        spill.cleanup()
    locate = _locator(p, None if shape == "wide" else (header[ii], header[ai]))
    res = _assemble(str(p), gcols, shape, rows, scale, items, min_group,
                    cand if shape == "wide" else None, locate,
                    statements if shape == "wide" else None)
    res.by = shown
    res.dropped, res.notes = dropped, footer_notes + res.notes
    if shape == "wide" and idcol is not None:
        note = _repeated_ids(p, gcols, idcol, repeats, spelled, shown)
        res.notes += [note] if note else []
    if shape == "wide":         # in the file's column order, named as read_survey names them
        res.not_items = {statements[h]: left_out.get(h) or res.not_items[h] for h in header
                         if h in left_out or h in res.not_items}
        res.fields = list(res.items)
        res.items = [statements[n] for n in res.items]
    return res


def _check_serial(error: Exception, parallel: bool) -> None:
    """Raise :class:`_SerialScanNeeded` when ``error`` is DuckDB's parallel scanner asking for
    the serial one (its message names ``parallel=false``)."""
    if parallel and "parallel=false" in str(error).replace(" ", ""):
        raise _SerialScanNeeded from None


def _locator(path: Path, long_columns: "tuple[str, str] | None"):
    """``locate(item, text) -> (row, column)`` of the first row giving answer ``text`` to
    ``item``: a wide file's item column, or a long file's (item, answer) columns."""
    if long_columns is None:
        return lambda item, text: (_find_row(path, [(item, text, False)]), item)
    item_col, answer_col = long_columns
    return lambda item, text: (_find_row(path, [(answer_col, text, False),
                                                (item_col, item, True)]), answer_col)


def _count_long(con, src, gcols, resp, item, answer, path: Path):
    """One scan: answers per (groups, item, answer) and distinct respondents per group.

    Respondent ids and item names count trimmed, as ``read_survey`` reads them; a
    respondent answering one item twice is refused as there. The scan's third grouping
    set is a 64-bit hash of each (respondent, item) pair, of which only repeated hashes
    are kept; a repeat is then confirmed on the pair itself (a collision is no error),
    and pairs that repeat only once trimmed are looked for when a padded id or item
    name exists. Spellings of one grouping value are one group
    (:func:`analysis.scales.group_names`).
    """
    g = ", ".join(_quote(c) for c in gcols)
    r, i, a = _quote(resp), _quote(item), _quote(answer)
    con.execute(f"""
        CREATE TEMP TABLE agg AS SELECT * FROM (
            SELECT {g}, {i} AS __item, {a} AS __answer, {r} AS __resp, __h,
                   GROUPING({i}) AS __gi, GROUPING({r}) AS __gr, count(*) AS __c
            FROM (SELECT *, hash({r}, {i}) AS __h FROM {src})
            GROUP BY GROUPING SETS (({g}, {i}, {a}), ({g}, {r}), (__h)))
        WHERE NOT (__gi = 1 AND __gr = 1 AND __c = 1)""")
    for col, what, where in ((resp, "blank respondent id", "__gi = 1 AND __gr = 0 AND "
                              f"coalesce(trim(__resp, {_WS}), '') = ''"),
                             (item, "blank item name", "__gi = 0 AND __gr = 1 AND "
                              f"coalesce(trim(__item, {_WS}), '') = ''")):
        if con.execute(f"SELECT 1 FROM agg WHERE {where} LIMIT 1").fetchone():
            raise SurveyInputError(what, str(path), _find_row(path, [(col, "", True)]), col)
    _refuse_repeated_pairs(con, src, path, resp, item, answer)
    spelled = con.execute(f"SELECT {g}, count(*) FROM agg WHERE __gi = 1 AND __gr = 0 "
                          f"GROUP BY ALL").fetchall()
    named = _group_map({_raw_key(row[:-1]): row[-1] for row in spelled})
    ng = len(gcols)
    con.execute("CREATE TEMP TABLE gmap AS SELECT * FROM (VALUES " + ", ".join(
        "(" + ", ".join(_literal(v) for v in raw + name) + ")" for raw, name in named.items())
        + ") AS t(" + ", ".join([f"r{j}" for j in range(ng)] + [f"n{j}" for j in range(ng)])
        + ")")
    on = " AND ".join(f"coalesce(agg.{_quote(c)}, '') = gmap.r{j}" for j, c in enumerate(gcols))
    names = ", ".join(f"gmap.n{j}" for j in range(ng))
    torn = con.execute(f"SELECT trim(__resp, {_WS}) FROM agg JOIN gmap ON {on} WHERE __gi = 1 "
                       f"AND __gr = 0 GROUP BY 1 HAVING count(DISTINCT [{names}]) > 1 "
                       f"LIMIT {_MAX_REPEATS}").fetchall()
    if torn:
        _refuse_two_groups(path, resp, gcols, {t for (t,) in torn})
    rows = con.execute(f"""
        SELECT {names}, __item, __answer, 0, sum(__c) FROM agg JOIN gmap ON {on}
            WHERE __gi = 0 AND __gr = 1 GROUP BY ALL
        UNION ALL
        SELECT {names}, NULL, NULL, 1, count(DISTINCT trim(__resp, {_WS})) FROM agg
            JOIN gmap ON {on} WHERE __gi = 1 AND __gr = 0 GROUP BY ALL""").fetchall()
    merged: dict = {}                 # item names trimmed (few rows: in Python, by strip)
    for row in rows:
        key = row[:ng] + (None if row[ng] is None else str(row[ng]).strip(),) + row[ng + 1:-1]
        merged[key] = merged.get(key, 0) + row[-1]
    return [k + (c,) for k, c in merged.items()]


def _refuse_two_groups(path: Path, resp: str, gcols: list, torn: set) -> None:
    """Raise at the first row (in file order) where one of the ``torn`` respondents gives a
    group that is not a spelling of the one on their first row, as ``read_survey`` does
    (:func:`analysis.scales.two_groups_message`). The file is read again: error path only."""
    first: dict = {}
    for row, (who, *values) in _records(path, [resp, *gcols]):
        who = who.strip()
        if who not in torn:
            continue
        seen = first.setdefault(who, values)
        for col, was, now in zip(gcols, seen, values):
            if normalize_answer(was) != normalize_answer(now):
                raise SurveyInputError(two_groups_message(who, col, was, now), str(path), row, col)
    raise SurveyInputError(f"respondents in two groups by "
                           f"{', '.join(map(platforms.spaced_name, gcols))}, e.g. "
                           f"{min(torn)!r}", str(path))


def _refuse_repeated_pairs(con, src, path: Path, resp: str, item: str, answer: str) -> None:
    """Raise naming the (respondent, item) pair given twice whose second row comes first,
    if any (as ``read_survey`` names it)."""
    r, i = _quote(resp), _quote(item)
    hashes = [h for (h,) in con.execute("SELECT __h FROM agg WHERE __gi = 1 AND __gr = 1 "
                                        f"LIMIT {_MAX_REPEATS}").fetchall()]
    pairs = []
    if hashes:                                        # confirmed on the pairs themselves
        pairs = con.execute(f"SELECT {r}, {i} FROM {src} WHERE hash({r}, {i}) IN "
                            f"({', '.join(['?'] * len(hashes))}) GROUP BY ALL "
                            f"HAVING count(*) > 1", hashes).fetchall()
    if not pairs and con.execute(
            f"SELECT 1 FROM agg WHERE (__gi = 1 AND __gr = 0 AND __resp <> trim(__resp, {_WS})) "
            f"OR (__gi = 0 AND __gr = 1 AND __item <> trim(__item, {_WS})) LIMIT 1").fetchone():
        pairs = con.execute(f"SELECT trim({r}, {_WS}), trim({i}, {_WS}) FROM {src} GROUP BY ALL "
                            f"HAVING count(*) > 1 LIMIT {_MAX_REPEATS}").fetchall()
    if pairs:
        pair, row = _earliest_repeat(path, resp, item, {
            tuple("" if v is None else str(v).strip() for v in p) for p in pairs})
        raise SurveyInputError(f"respondent {pair[0]!r} answers item {pair[1]!r} twice",
                               str(path), row, answer)


def _not_utf8(path: Path) -> "tuple[int, str] | None":
    """(row, why) when a CSV file is not UTF-8 text, the only encoding --by reads; None
    when it is (or is Parquet). Read in blocks, on the error path only."""
    if path.suffix.lower() == ".parquet":
        return None
    fix = ("--by reads UTF-8 only: save the file as CSV UTF-8, or summarize it without "
           "--by (which reads Windows-1252 and takes --encoding)")
    with open(path, "rb") as f:
        head = f.read(4)
        if head[:2] in (b"\xff\xfe", b"\xfe\xff") or b"\x00" in head:
            return 1, f"UTF-16 text (byte-order mark or NUL bytes); {fix}"
        f.seek(0)
        carry, offset, row = b"", 0, 1          # offset: of ``carry`` in the file
        while True:
            block = f.read(1 << 20)
            data = carry + block
            try:
                data.decode("utf-8")
                carry = b""
            except UnicodeDecodeError as e:
                if block and e.reason == "unexpected end of data":
                    carry = data[e.start:]      # a character split across two blocks
                    data = data[:e.start]
                else:
                    row += data[:e.start].count(b"\n")
                    return row, (f"byte 0x{data[e.start]:02x} at offset {offset + e.start} "
                                 f"is not UTF-8; {fix}")
            if not block:
                return None
            offset += len(data)
            row += data.count(b"\n")


def _refuse_header_rows(con, src: str, path: Path, header: list[str]) -> None:
    """Refuse an export with header rows below the first (Qualtrics' question text and
    import ids, SurveyMonkey's statements): DuckDB would count them as answers; and a Canvas
    quiz export, whose attempts and points columns only the in-memory route reads."""
    first = [["" if v is None else str(v) for v in r]
             for r in con.execute(f"SELECT * FROM {src} LIMIT 3").fetchall()]
    peek = [header] + first
    shape = platforms.detect(header, peek)
    if shape == "canvas":
        raise SurveyInputError(
            "a Canvas quiz export: --by does not read its layout (a points column after each "
            "question, a row per attempt of which the latest counts): summarize it without --by, "
            "with --group section", str(path), 1)
    extra = platforms.header_rows(shape, header, peek) if shape else 0
    if extra:
        rows = "rows 2-3 are header rows" if extra == 2 else "row 2 is a header row"
        name = {"qualtrics": "Qualtrics", "surveymonkey": "SurveyMonkey"}.get(shape, shape)
        raise SurveyInputError(
            f"a {name} export: {rows} (statement texts), not answers; --by "
            f"counts files with one header row: summarize the export without --by, or "
            f"delete {'rows 2-3' if extra == 2 else 'row 2'} (and keep row 1 and the answers "
            f"below)", str(path), 2)


def _literal(v: str) -> str:
    return "'" + str(v).replace("'", "''") + "'"


def _raw_key(values) -> tuple:
    return tuple("" if v is None else str(v) for v in values)


def _group_map(spelled: dict) -> dict:
    """``{raw grouping values: group name values}``, by the one rule of ``--group``."""
    return {raw: name for raw, (_key, name) in group_names(spelled).items()}


def _records(path: Path, columns: list[str]):
    """``(spreadsheet row, cell texts of columns)`` of every data row, in file order (the
    header is row 1); nothing when a column cannot be found. The file is read again:
    for error messages only."""
    if path.suffix.lower() == ".parquet":
        yield from _parquet_records(path, columns)
        return
    try:
        sep = _delimiter(path)
    except OSError:
        return
    import csv
    with open(path, encoding="utf-8", errors="replace", newline="") as f:
        reader = csv.reader(f, delimiter=sep or ",")
        header = next(reader, [])
        if any(c not in header for c in columns):
            return
        idx = [header.index(c) for c in columns]
        for row, rec in enumerate(reader, start=2):
            yield row, tuple(rec[j] if j < len(rec) else "" for j in idx)


def _parquet_records(path: Path, columns: list[str]):
    """:func:`_records` of a Parquet file (DuckDB reads it; a CSV file needs no connection)."""
    import duckdb
    con = duckdb.connect()
    try:
        cur = con.execute(f"SELECT file_row_number, {', '.join(map(_quote, columns))} FROM "
                          f"read_parquet({_literal(path)}, file_row_number = true) "
                          f"ORDER BY file_row_number")
        while batch := cur.fetchmany(10_000):
            for rec in batch:
                yield int(rec[0]) + 2, tuple("" if v is None else str(v) for v in rec[1:])
    except (duckdb.Error, OSError):
        return
    finally:
        con.close()


def _find_row(path: Path, tests: list) -> "int | None":
    """Spreadsheet row of the first row where every ``(column, value, trimmed)`` test holds
    (the cell, trimmed when ``trimmed``, equals ``value``); None when not found."""
    for row, cells in _records(path, [c for c, _, _ in tests]):
        if all((x.strip() if t else x) == v for x, (_, v, t) in zip(cells, tests)):
            return row
    return None


def _earliest_repeat(path: Path, resp: str, item: str, pairs: set):
    """(pair, row) of the (respondent, item) pair among ``pairs`` whose second row comes
    first in the file, both trimmed; the in-memory route names the same one."""
    seen: set = set()
    for row, (who, what) in _records(path, [resp, item]):
        key = (who.strip(), what.strip())
        if key in pairs:
            if key in seen:
                return key, row
            seen.add(key)
    return min(pairs), None


def _count_wide(con, src, gcols, cand, idcol=None):
    """Answers per (groups, item, answer) in one scan; with ``idcol``, also the ids
    (trimmed, lower case) found on more than one row of a group, as rows of kind 2."""
    g = ", ".join(_quote(c) for c in gcols)
    cols = [_quote(c) for c in cand]
    names = [_literal(c) for c in cand]
    kinds = ["0"] * len(cand)
    if idcol is not None:
        cols.append(f"lower(trim({_quote(idcol)}, {_WS}))")
        names.append(_literal(idcol))
        kinds.append("2")
    # lists unnested side by side: one row per (respondent, item), blank answers kept
    sql = f"""
        SELECT {g}, item, answer, kind, count(*) FROM (
            SELECT {g}, unnest([{', '.join(names)}]) AS item,
                   unnest([{', '.join(cols)}]) AS answer, unnest([{', '.join(kinds)}]) AS kind
            FROM {src})
        GROUP BY ALL HAVING kind = 0 OR (count(*) > 1 AND coalesce(answer, '') <> '')"""
    return con.execute(sql).fetchall()


def _id_spellings(con, src: str, idcol: str, keys: list) -> dict:
    """``{id trimmed and in lower case: the id as the file writes it}`` for ``keys`` (one scan;
    of several spellings of one id, the least as text)."""
    c = f"trim({_quote(idcol)}, {_WS})"
    return dict(con.execute(f"SELECT lower({c}), min({c}) FROM {src} WHERE lower({c}) IN "
                            f"({', '.join(['?'] * len(keys))}) GROUP BY 1", keys).fetchall())


def _repeated_ids(path: Path, gcols, idcol: str, repeats: list, spelled: dict,
                  shown: list) -> "str | None":
    """The note of :func:`analysis.ingest.repeated_ids_note` on the kind-2 rows of
    :func:`_count_wide` (ids matched in lower case), naming the first three ids as the file
    writes them (on their first row, as ``read_survey`` does) with their rows, found by reading
    the file again; a file too long for that gives the rows' number and the ``spelled`` ids.
    The grouping columns are named as ``shown``."""
    from .ingest import repeated_ids_note
    if not repeats:
        return None
    ng = len(gcols)
    first = {(_raw_key(r[:ng]), str(r[ng + 1])): [] for r in repeats[:3]}
    if path.stat().st_size > _MAX_REREAD:      # too long to read again in Python: counts
        return repeated_ids_note(str(path), idcol, list(shown), len(repeats),
                                 [(spelled.get(r[ng + 1], str(r[ng + 1])), int(r[ng + 3]))
                                  for r in repeats[:3]])
    written = {}
    for row, cells in _records(path, list(gcols) + [idcol]):
        key = (tuple(cells[:ng]), cells[ng].strip().lower())
        if key in first:
            first[key].append(row)
            written.setdefault(key, cells[ng].strip())
    return repeated_ids_note(str(path), idcol, list(shown), len(repeats),
                             [(written.get(k, k[1]), rows) for k, rows in first.items()])


def _merge_spellings(rows, ng: int, first_item) -> list:
    """Wide rows (a row per respondent) with the spellings of a grouping value merged
    (:func:`analysis.scales.group_names`); respondents per spelling are the answers to
    the first item column."""
    spelled: dict = {}
    for r in rows:
        if r[ng] == first_item:
            k = _raw_key(r[:ng])
            spelled[k] = spelled.get(k, 0) + r[ng + 3]
    named = _group_map(spelled)
    merged: dict = {}
    for r in rows:
        k = named[_raw_key(r[:ng])] + tuple(r[ng:ng + 3])
        merged[k] = merged.get(k, 0) + r[ng + 3]
    return [k + (c,) for k, c in merged.items()]


def _answer_counts(rows, ng: int, wide_items) -> list:
    """(name, {answer text: count}) per counted column (long: per item), over all groups;
    a blank cell is the text ``""``. Wide columns in file order, long items sorted."""
    per: dict = {}
    for r in rows:
        if not r[ng + 2] and r[ng] is not None:
            texts = per.setdefault(r[ng], {})
            t = "" if r[ng + 1] is None else r[ng + 1]
            texts[t] = texts.get(t, 0) + r[ng + 3]
    names = list(wide_items) if wide_items is not None else sorted(per, key=str)
    return [(str(n), per.get(n, {})) for n in names]


def _assemble(source, gcols, shape, rows, scale, items, min_group,
              wide_items=None, locate=None, statements=None) -> GroupedSummary:
    """Tallies from the aggregated rows: items and scale chosen by the in-memory rule
    (:func:`analysis.ingest.choose_items_from_counts`), texts matched, groups indexed.
    ``locate(item, text)`` gives the (row, column) an unknown answer is named by."""
    from .ingest import choose_items_from_counts
    ng = len(gcols)
    counted = _answer_counts(rows, ng, wide_items)
    scale_obj, names, not_items, notes = choose_items_from_counts(
        source, counted, scale, items, long=shape == "long",
        fields=None if statements is None else [statements[n] for n, _ in counted])
    index_item = {n: i for i, n in enumerate(names)}
    texts = {t: c for n, tx in counted if n in index_item for t, c in tx.items() if t != ""}
    keys = sorted({tuple("" if v is None else str(v) for v in r[:ng]) for r in rows})
    index_group = {k: i for i, k in enumerate(keys)}
    k = scale_obj.k
    tallies = np.zeros((len(keys), len(names), k + 3), dtype=np.int64)
    respondents = np.zeros(len(keys), dtype=np.int64)
    lut = {}
    for t in texts:
        m = scale_obj.match(t)
        if m is None:
            item = next(n for n, tx in counted if n in index_item and t in tx)
            row, column = locate(item, t) if locate else (None, None)
            raise SurveyInputError(f"answer {t!r} is not on scale {scale_obj.name!r}; valid "
                                   f"labels: {scale_obj.describe_valid()}", source, row, column)
        lut[t] = m + 3
    for r in rows:
        g = index_group[tuple("" if v is None else str(v) for v in r[:ng])]
        if r[ng + 2]:
            respondents[g] += r[ng + 3]
            continue
        i = index_item.get(None if r[ng] is None else str(r[ng]))
        if i is None:
            continue
        pos = 2 if r[ng + 1] is None or r[ng + 1] == "" else lut[r[ng + 1]]
        tallies[g, i, pos] += r[ng + 3]
    if shape == "wide":
        respondents = tallies[:, 0, :].sum(axis=1) if names else respondents
    else:            # respondents with no row for an item are missing on it
        tallies[:, :, 2] += np.maximum(respondents[:, None] - tallies.sum(axis=2), 0)
    return GroupedSummary(source=source, by=list(gcols), scale=scale_obj, items=names,
                          groups=keys, respondents=respondents, tallies=tallies, shape=shape,
                          min_group=min_group, notes=notes, not_items=not_items)
