"""Reading survey exports into a respondent-by-item matrix of scale positions.

Supported shapes (:data:`SHAPES`), detected from the file unless named:

``wide``
    A row per respondent, a column per item (plus any other columns).
``long``
    A row per answer: respondent, item, answer columns (names such as
    ``respondent``/``id``, ``item``/``question``, ``answer``/``response``/``value``).
    Items come in questionnaire order, merged from the order of each respondent's
    rows (first appearance breaks ties); a (respondent, item) pair with no row is
    missing; a pair given twice is an error.
``google``
    Google Forms export: a ``Timestamp`` column, maybe an e-mail column, the
    question text as headers and answers as label text.
``qualtrics``
    Qualtrics export: three header rows (field ids, question text, ``{"ImportId": ...}``);
    responses whose ``Status`` is ``Survey Preview`` are dropped and reported.

CSV files and ``.xlsx`` workbooks (the first sheet, or ``sheet=``; read with openpyxl) are
accepted, a note naming any other sheet that holds data;
``shape="xlsx"`` reads a workbook whatever its file name and detects its layout.
Leading lines that start with ``#`` in a CSV are comments (a header whose first
field is ``#``, such as ``#,Q1,Q2``, is not). The delimiter (comma, semicolon or
tab) is the one that splits the header and the next records into the same number
of fields; a workbook is recognised by its content whatever its file name.

Item columns are detected: a column is an item when it holds at least one label
text of the scale and at least half of its non-blank answers are labels or codes
of the scale (one stray answer then is an error, not a reason to drop the
column); when no column has label texts, columns whose every answer is a numeric
code of the scale are taken (identifier-like and known metadata columns aside). Items may instead
be chosen by name or ``fnmatch`` pattern. Answers match labels ignoring case and
surrounding white space; numeric codes are accepted. An answer that matches no
label raises :class:`~analysis.errors.SurveyInputError` naming file, row, column,
value and the valid labels, unless ``unknown="missing"``, in which case each such
answer is recorded in :attr:`SurveyData.unknown_answers` and counted as missing.

Row numbers count records as a spreadsheet shows them: the (first) header row is
row 1, comment lines count too.

Workbooks are parsed with external entities and entity expansion refused (defusedxml;
the sheet's cells by :mod:`analysis.xlsx_sheet`, with the same refusals) and every cell of the sheet read is read, whatever its ``<dimension>`` record
says. Caps, each refused with one line: :data:`MAX_COLUMNS` columns (or distinct items
of a long file), :data:`MAX_ITEMS` item columns, :data:`MAX_CELLS` cells,
:data:`MAX_XLSX_BYTES` unpacked and :data:`XLSX_MAX_ROWS` rows per workbook.

Public API: :func:`read_survey` (a file) and :func:`survey_from_frame` (a
pandas DataFrame of text), both returning :class:`SurveyData`.
"""
from __future__ import annotations

import codecs
import csv
import datetime
import heapq
import io
import re
import warnings
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np
import pandas as pd

from . import platforms
from .platforms import CODES_HINT
from ._io import (ShortRecords, is_regular_file, read_bytes, refuse_values_beyond_header,
                  short_records_note, sniff_delimiter)
from .dropped import (DROP_WHY, FOOTER, DroppedRow, is_footer_note, is_integer_text,
                      is_na_text as _is_na_text)
from .errors import SurveyInputError
from .xlsx_sheet import SheetFault
from .scales import (BLANK, BUILTIN_SCALES, DECLINED, NOT_APPLICABLE, SHORT_NOT_APPLICABLE, UNKNOWN,
                     Scale, code_key, get_scale, normalize_answer,
                     two_groups_message)

__all__ = ["SHAPES", "UNKNOWN_POLICIES", "SurveyData", "UnknownAnswer", "DroppedRow", "DROP_WHY",
           "read_survey", "survey_from_frame", "choose_items_from_counts", "BLANK",
           "NOT_APPLICABLE", "UNKNOWN"]

#: Valid ``shape`` values.
SHAPES = platforms.SHAPES
#: Valid ``unknown`` values: raise on an unknown answer, or count it as missing.
UNKNOWN_POLICIES = ("error", "missing")
#: Most item columns one survey may have (a cap on the work a file can ask for:
#: summarising takes about a millisecond per item).
MAX_ITEMS = 1000
#: Most columns a survey file may have (reading costs about half a millisecond per column).
MAX_COLUMNS = 5000
#: Largest uncompressed size of an .xlsx workbook's parts (a guard against zip bombs).
MAX_XLSX_BYTES = 1 << 30
#: Most cells (records x columns) one survey file may have: 10 million, twice the
#: one million respondents by five items the benchmark reads.
MAX_CELLS = 10_000_000
#: Rows of a worksheet (Excel's own limit; a row number past it is hostile).
XLSX_MAX_ROWS = 1_048_576

#: Cell codes in :attr:`SurveyData.answers` besides label positions 0..k-1 (defined in
#: :mod:`analysis.scales`): BLANK (-1), NOT_APPLICABLE (-2), UNKNOWN (-3, an unknown
#: answer counted as missing with ``unknown="missing"``).
_NO_MATCH = -9

_ID_LIKE = re.compile(r"^(respondent|respondent[ _]?id|id|response[ _]?id|record|row|#|"
                      r"student|student[ _]?id|participant|participant[ _]?id)$", re.I)
_LONG_RESP, _LONG_ITEM, _LONG_ANSWER = platforms.LONG_RESP, platforms.LONG_ITEM, platforms.LONG_ANSWER


@dataclass(frozen=True)
class UnknownAnswer:
    """An answer that matched no label and was counted as missing."""

    row: int
    column: str
    value: str

    def line(self, source: str) -> str:
        return (f"{source}: row {self.row}, column {self.column!r}: "
                f"unknown answer {self.value!r} counted as missing")


@dataclass
class SurveyData:
    """Answers of every respondent to every item, as positions on one scale.

    Attributes
    ----------
    source : str
        File name (or ``"<dataframe>"``).
    shape : str
        Input shape that was read (one of :data:`SHAPES` except ``"auto"``).
    scale : Scale
    items : list of str
        Item column headers, in questionnaire (column) order.
    item_texts : list of str
        Question text per item (Qualtrics second header row; else the header).
    answers : numpy.ndarray of int8, shape (respondents, items)
        ``0..k-1`` label position on ``scale.labels``; :data:`BLANK` (-1),
        :data:`NOT_APPLICABLE` (-2), :data:`UNKNOWN` (-3).
    rows : numpy.ndarray of int
        Spreadsheet row of each respondent (first row for long files; 0 for
        respondents declared but absent from the file).
    groups : dict of str to numpy.ndarray
        Other columns kept for grouping (text, blank -> ``""``).
    unknown_answers : list of UnknownAnswer
    dropped : list of DroppedRow
    reverse : set of str
        Reverse-keyed items (affects codes, not counts).
    other_columns : list of str
        Columns read but not taken as items (metadata, ids, free text), so that a
        column left out is never left out silently.
    not_item_reasons : dict of str to str
        Why each of ``other_columns`` is not an item, in words.
    comments : list of str
        Leading ``#`` comment lines of a CSV file (without the ``#``).
    stems : list of str
        Question stem of each item ("" for a single question): items are named by
        their statement, and the stem of a grid/matrix is shown once above them.
    fields : list of str
        The export's column header of each item (``Q1_1``, ``Q3[SQ001]``).
    ids : numpy.ndarray of str or None
        Respondent id per respondent (a student id, e-mail or id column), used to
        pair pre/post answers; None when the export has no such column.
    id_column : str
        The column ``ids`` came from.
    notes : list of str
        What reading noticed and the user should know (encoding used, columns left
        out and why, a scale with unused labels); printed by the command line.
    """

    source: str
    shape: str
    scale: Scale
    items: list[str]
    item_texts: list[str]
    answers: np.ndarray
    rows: np.ndarray
    groups: dict = field(default_factory=dict)
    unknown_answers: list[UnknownAnswer] = field(default_factory=list)
    dropped: list[DroppedRow] = field(default_factory=list)
    reverse: set = field(default_factory=set)
    other_columns: list = field(default_factory=list)
    not_item_reasons: dict = field(default_factory=dict)
    comments: list = field(default_factory=list)
    stems: list = field(default_factory=list)
    fields: list = field(default_factory=list)
    notes: list = field(default_factory=list)
    ids: "np.ndarray | None" = None
    id_column: str = ""

    def subset(self, mask) -> "SurveyData":
        """The respondents selected by a boolean mask (or index array), as a new survey."""
        mask = np.asarray(mask)
        return replace(self, answers=self.answers[mask], rows=self.rows[mask],
                       groups={k: v[mask] for k, v in self.groups.items()},
                       ids=None if self.ids is None else self.ids[mask])

    @property
    def respondents(self) -> int:
        """Number of respondents (rows of :attr:`answers`)."""
        return int(self.answers.shape[0])

    def item_index(self, item: "str | int") -> int:
        """Column index of an item given by header (any case/spacing) or 1-based position."""
        if isinstance(item, int) and not isinstance(item, bool):
            if 1 <= item <= len(self.items):
                return item - 1
            raise ValueError(f"item position {item} out of range 1..{len(self.items)}")
        key = normalize_answer(item)
        for j, name in enumerate(self.items):
            if normalize_answer(name) == key:
                return j
        raise ValueError(f"no item {item!r}; items are {self.items!r}")

    def note_lines(self) -> list[str]:
        """:attr:`notes` as every output shows them to the reader (the command line on stderr,
        the HTML report): ``note: ...``, or a warning as it is written (``warning: ...``)."""
        return [note_line(n) for n in self.notes]

    def labels_frame(self) -> pd.DataFrame:
        """Answers as label text (blank -> ``""``, N/A -> ``"N/A"``, unknown -> ``""``)."""
        lut = np.array(list(self.scale.labels) + ["", "N/A", ""], dtype=object)
        idx = np.where(self.answers >= 0, self.answers, len(self.scale.labels) - self.answers - 1)
        return pd.DataFrame(lut[idx], columns=self.items)

    def __repr__(self):
        return (f"SurveyData({self.source!r}, shape={self.shape!r}, scale={self.scale.name!r}, "
                f"respondents={self.respondents}, items={self.items!r})")


def note_line(note: str) -> str:
    """A note as every route prints it: ``note: ...``, or a warning as it is written."""
    return note if note.startswith("warning:") else f"note: {note}"


# ---------------------------------------------------------------------------
# raw reading
# ---------------------------------------------------------------------------
@dataclass
class _Column:
    name: str
    cats: list[str]          # distinct cell texts
    codes: np.ndarray        # index into cats per row
    field: str = ""          # the export's header when ``name`` is the statement text

    def counts(self) -> np.ndarray:
        cached = self.__dict__.get("_counts")
        if cached is None:
            cached = np.bincount(self.codes, minlength=len(self.cats))
            self.__dict__["_counts"] = cached
        return cached


@dataclass
class _Raw:
    source: str
    header: list[str]
    columns: list[_Column]
    first_row: int           # spreadsheet row of the first data record
    nrows: int
    comments: list[str] = field(default_factory=list)             # leading '#' lines
    row_map: "np.ndarray | None" = None   # spreadsheet row per record when not consecutive
    notes: list[str] = field(default_factory=list)
    given: "list[str] | None" = None      # header as written, before a reader renamed any
    short: list = field(default_factory=list)   # (row, fields) of records shorter than the header

    def row_of(self, idx):
        """Spreadsheet row of data record(s) ``idx`` (0-based record indices)."""
        if self.row_map is None:
            return self.first_row + np.asarray(idx, dtype=np.int64)
        return self.row_map[np.asarray(idx, dtype=np.int64)]


def _frame_to_columns(df: pd.DataFrame) -> list[_Column]:
    cols = []
    names = _distinct([str(c) for c in df.columns])
    for j, name in enumerate(names):
        s = df.iloc[:, j]
        if isinstance(s.dtype, pd.CategoricalDtype):
            cats = [str(c) for c in s.cat.categories]
            codes = s.cat.codes.to_numpy()
        elif pd.api.types.infer_dtype(s, skipna=True) == "string":     # text as it is
            codes, uniq = pd.factorize(s.to_numpy(dtype=object), sort=False)
            cats = [str(u) for u in uniq]
        else:
            vals = s.astype(object).where(s.notna(), "")
            codes, uniq = pd.factorize(vals.map(_cell_text), sort=False)
            cats = [str(u) for u in uniq]
        if (codes < 0).any():                 # NaN -> blank
            cats = cats + [""]
            codes = np.where(codes < 0, len(cats) - 1, codes)
        codes = np.asarray(codes)
        small = np.int8 if len(cats) < 128 else np.int16 if len(cats) < 32768 else np.int32
        if codes.dtype.kind != "i" or codes.dtype.itemsize > np.dtype(small).itemsize:
            codes = codes.astype(small)      # a byte a cell, as pandas' category codes were
        cols.append(_Column(str(name), cats, codes))
    return cols


def _cell_text(v) -> str:
    """A workbook cell's value as text: a whole number without ``.0``, TRUE/FALSE as Excel
    writes them, a date cell as its date (``2024-01-15``, not ``2024-01-15 00:00:00``: a time
    only when the cell holds one, as Excel shows a date cell)."""
    if v is None:
        return ""
    if isinstance(v, datetime.datetime):
        return v.date().isoformat() if v.time() == datetime.time() else v.isoformat(" ")
    if isinstance(v, float):
        if v != v:
            return ""
        if v.is_integer():
            return str(int(v))
    if isinstance(v, bool):
        return str(v).upper()
    return str(v)


class _DecodeError(SurveyInputError):
    """The bytes are not text in the encoding tried."""


def _decode_error(raw: bytes, encoding: str, source: str) -> SurveyInputError:
    try:
        raw.decode(encoding)
    except UnicodeDecodeError as e:
        row = raw[:e.start].count(b"\n") + 1
        return _DecodeError(
            f"byte 0x{raw[e.start]:02x} at offset {e.start} is not valid {encoding}; "
            f"give the file's encoding (e.g. --encoding cp1252)", source, row)
    except LookupError:
        return SurveyInputError(f"unknown encoding {encoding!r}", source)
    return SurveyInputError(f"cannot decode as {encoding}", source)


def _read_csv_raw(path: Path, encoding: "str | None") -> tuple[_Raw, list[list[str]]]:
    """A CSV file's records; ``encoding=None`` is UTF-8, else Windows-1252 with a note."""
    if encoding is not None:
        return _read_csv_encoded(path, encoding)
    try:
        return _read_csv_encoded(path, "utf-8")
    except _DecodeError:
        pass
    raw, peek = _read_csv_encoded(path, "cp1252")
    raw.notes.append(f"{path}: not valid UTF-8; read as Windows-1252 (cp1252), the encoding "
                     "Excel on Windows saves CSV in (give --encoding to choose another)")
    return raw, peek


def _read_csv_encoded(path: Path, encoding: str) -> tuple[_Raw, list[list[str]]]:
    source = str(path)
    raw = read_bytes(path)
    if raw.startswith(b"\xef\xbb\xbf"):
        raw = raw[3:]
    elif raw[:2] in (b"\xff\xfe", b"\xfe\xff"):       # UTF-16 with BOM (Excel "Unicode text")
        try:
            raw = raw.decode("utf-16").encode("utf-8")
        except UnicodeDecodeError as e:
            raise SurveyInputError(f"starts like UTF-16 but byte offset {e.start} cannot be "
                                   f"decoded", source) from None
        encoding = "utf-8"
    if _blank(raw):
        raise SurveyInputError("empty file", source)
    try:
        "".encode(encoding)
    except LookupError:
        raise SurveyInputError(f"unknown encoding {encoding!r}", source) from None
    if codecs.lookup(encoding).name.startswith(("utf-16", "utf-32")):
        # the steps below work on ASCII-compatible bytes: re-encode as UTF-8 first
        try:
            raw = raw.decode(encoding).encode("utf-8")
        except UnicodeDecodeError:
            raise _decode_error(raw, encoding, source) from None
        encoding = "utf-8"
    # leading comment lines
    skip = 0
    pos = 0
    # (a header whose first field is "#", as in "#,Q1,Q2", is not a comment)
    while (pos < len(raw) and raw[pos:pos + 1] == b"#"
           and raw[pos + 1:pos + 2] not in (b",", b";", b"\t")):
        nl = raw.find(b"\n", pos)
        if nl < 0:
            pos = len(raw)
        else:
            pos = nl + 1
        skip += 1
    body = raw[pos:]
    if _blank(body):
        raise SurveyInputError("empty file (only comment lines)", source)
    if b"\x00" in body[:4096]:
        raise SurveyInputError("holds NUL bytes: UTF-16 text without a byte-order mark, or "
                               "not a text file; give --encoding utf-16-le (or save as CSV)",
                               source)
    head_text = body[:262144].decode(encoding, errors="replace")
    sep, peek = sniff_delimiter(head_text)
    _check_width(source, max((len(r) for r in peek), default=0), at_least=True)  # before pandas
    lines = body.count(b"\n")                  # lines bound the records from above
    if peek and lines * len(peek[0]) > MAX_CELLS:
        raise SurveyInputError(f"about {lines} records x {len(peek[0])} columns; at most "
                               f"{MAX_CELLS} cells are read", source)
    single = len(peek[0]) <= 1 if peek else True
    trailing = 0
    if single:
        body, lead, trailing = _trim_single_column(body)
        skip += lead
    def read(usecols=None):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", pd.errors.ParserWarning)
            # index_col=False: a data row with a trailing delimiter must not turn the
            # first column into an index and shift every answer one column left.
            # dtype=object: every cell the text the file holds (a "category" read infers
            # numbers, so that sections "01" and "1.0" became one group and id "00123" 123)
            return pd.read_csv(io.BytesIO(body), dtype=object, keep_default_na=False,
                               sep=sep, na_filter=False, encoding=encoding, engine="c",
                               skipinitialspace=False, skip_blank_lines=not single,
                               index_col=False, usecols=usecols), caught
    try:
        try:
            df, caught = read()
        except pd.errors.ParserError as e:
            if not re.search(r"Expected \d+ fields", str(e)) or not peek:
                raise
            # a record longer than the others: refused when it holds a value beyond the
            # header (the rule of both routes); empty fields there are no values, left out
            _values_beyond_header(body, encoding, sep, len(peek[0]), source, skip)
            df, caught = read(range(len(peek[0])))
    except UnicodeDecodeError:
        raise _decode_error(raw, encoding, source) from None
    except pd.errors.EmptyDataError:
        raise SurveyInputError("empty file", source) from None
    except pd.errors.ParserError as e:
        raise _parser_error(e, source, skip) from None
    if any(issubclass(w.category, pd.errors.ParserWarning) for w in caught):
        _values_beyond_header(body, encoding, sep, df.shape[1], source, skip)
    _check_width(source, df.shape[1])
    row_map = None
    if not single and _may_have_blank_lines(body, len(df)) and _BLANK_LINE.search(b"\n" + body):
        row_map = _record_rows(body, encoding, sep, skip, len(df))
    header = [str(c) for c in df.columns]
    comments = [ln.decode(encoding, errors="replace").lstrip("#").strip()
                for ln in raw[:pos].splitlines()]
    first = skip + 2 if row_map is None or not len(row_map) else int(row_map[0])
    out = _Raw(source, header, _frame_to_columns(df), first, len(df), comments, row_map,
               given=None if single else _given_header(body, sep, encoding),
               short=[] if single else _short_records(body, sep, skip))
    if trailing:
        out.notes.append(f"{source}: {trailing} empty line(s) at the end not read as "
                         f"respondents (in a one-column file an empty line elsewhere is a "
                         f"blank answer)")
    return out, peek


def _short_records(body: bytes, sep: str, skip: int) -> list:
    """(spreadsheet row, fields) of each record with fewer fields than the header, which
    pandas pads with blank cells unsaid (``skip`` comment lines above the header)."""
    scan = ShortRecords(sep, b"\n" if b"\n" in body[:262144] or b"\r" not in body else b"\r")
    view = memoryview(body)
    for at in range(0, len(body), 1 << 20):
        scan.feed(view[at:at + (1 << 20)])
    return [(skip + record, fields) for record, fields in scan.close()]


def _note_short_rows(raw: _Raw, keep: np.ndarray, notes: list) -> None:
    """Note the records of ``keep`` (respondents) that were shorter than the header."""
    if not raw.short:
        return
    kept = set(raw.row_of(keep).tolist())
    note = short_records_note(raw.source, [(r, n) for r, n in raw.short if r in kept],
                              len(raw.header))
    if note:
        notes.append(note)


def _parser_error(e: Exception, source: str, skip: int) -> SurveyInputError:
    """pandas' tokenizer error as one line at the spreadsheet row it names (``skip``
    comment lines above the header)."""
    quote = re.search(r"EOF inside string starting at row (\d+)", str(e))
    if quote:                          # pandas counts rows from 0 (the header is its row 0)
        return SurveyInputError("a quoted field opened here is never closed (the file ends "
                                "inside it)", source, int(quote.group(1)) + 1 + skip)
    m = re.search(r"line (\d+)", str(e))
    return SurveyInputError(f"not a well-formed CSV ({str(e).strip().splitlines()[-1]})",
                            source, int(m.group(1)) + skip if m else None)


def _given_header(body: bytes, sep: str, encoding: str) -> list[str]:
    """The header record as written: pandas names a repeated ``Q1`` ``Q1.1`` and a blank
    cell ``Unnamed: 3``, so the header is read again as a data record, by the same parser."""
    first = pd.read_csv(io.BytesIO(body), header=None, nrows=1, dtype=str, sep=sep,
                        keep_default_na=False, na_filter=False, encoding=encoding,
                        engine="c", skipinitialspace=False, index_col=False)
    return [str(v) for v in first.iloc[0]] if len(first) else []


def _trim_single_column(body: bytes) -> tuple[bytes, int, int]:
    """A one-column CSV body without its empty lines before the header and at the end.

    In one column an empty line is a blank answer (as Excel writes a blank cell), except
    before the header and at the end, where it cannot be told from padding. A line holding
    spaces or a tab is a record (a blank answer), wherever it is. Returns the body, the
    number of lines removed before the header, and the number of empty lines removed at
    the end (to be reported).
    """
    lead = re.match(rb"(?:[ \t]*\r?\n)*", body).end()
    head, body = body[:lead].count(b"\n"), body[lead:]
    end = len(body)
    while end and body[end - 1:end] in (b"\n", b"\r"):
        end -= 1
    tail = body[end:]
    trailing = max(tail.count(b"\n") + tail.count(b"\r") - tail.count(b"\r\n") - 1, 0)
    return body[:end] + b"\n", head, trailing


def _blank(b: bytes) -> bool:
    """Only white space (without copying a large file as ``strip`` would)."""
    return not b or b.isspace()


def _may_have_blank_lines(body: bytes, nrows: int) -> bool:
    """False when the line count shows one line per record (no blank line to renumber)."""
    lines = body.count(b"\n") + (0 if body.endswith(b"\n") else 1)
    return lines != nrows + 1


_BLANK_LINE = re.compile(rb"\n[ \t]*\r?\n[^\r\n]")


def _values_beyond_header(body: bytes, encoding: str, sep: str, width: int, source: str,
                          skip: int) -> None:
    """Refuse a record with a value beyond the header's last column
    (:func:`analysis._io.refuse_values_beyond_header`, the rule of both routes)."""
    refuse_values_beyond_header(io.StringIO(body.decode(encoding, errors="replace"), newline=""),
                                sep, width, source, skip)


def _record_rows(body: bytes, encoding: str, sep: str, skip: int, nrows: int):
    """Spreadsheet rows of the data records of a CSV body with blank lines in it.

    pandas skips blank lines; a spreadsheet shows them as rows, so later row numbers
    in messages would be off. Only run when the body has a blank line.
    """
    text = body.decode(encoding, errors="replace")
    rows = []
    reader = csv.reader(io.StringIO(text, newline=""), delimiter=sep)
    line = skip
    header_seen = False
    limit = csv.field_size_limit(len(text) + 1)   # pandas read fields of any size: so do we
    try:
        for rec in reader:
            line += 1
            if len(rec) <= 1 and not "".join(rec).strip():
                continue              # pandas skips it; the spreadsheet row still counts
            if not header_seen:
                header_seen = True
                continue
            rows.append(line)
    except csv.Error:
        return None
    finally:
        csv.field_size_limit(limit)
    if len(rows) != nrows:            # could not align with pandas: keep consecutive rows
        return None
    return np.asarray(rows, dtype=np.int64)


def _check_width(source: str, width: int, at_least: bool = False, row: int = 1) -> None:
    if width > MAX_COLUMNS:
        more = " or more" if at_least else ""
        raise SurveyInputError(f"{width} columns{more}; at most {MAX_COLUMNS} are read",
                               source, row)


#: The parts of a workbook openpyxl reads as it loads it, by the function reading each
#: (a fault there is named by its part, not by openpyxl's exception).
_WORKBOOK_PARTS = {"read_manifest": "its list of parts ([Content_Types].xml)",
                   "read_strings": "its shared strings (xl/sharedStrings.xml)",
                   "read_workbook": "its workbook part (xl/workbook.xml)",
                   "find_sheets": "its sheet list (xl/workbook.xml and its relationships)",
                   "read_properties": "its document properties (docProps/core.xml)",
                   "read_custom": "its custom properties (docProps/custom.xml)",
                   "apply_stylesheet": "its styles (xl/styles.xml)",
                   "read_worksheets": "its sheet list (xl/workbook.xml and its relationships)",
                   "assign_names": "its defined names (xl/workbook.xml)"}


def _xlsx_error(e: Exception, source: str, row: "int | None" = None,
                sheet: "str | None" = None) -> SurveyInputError:
    """One line for a workbook openpyxl cannot read: entities named as refused, malformed XML
    with expat's place, else the part being read and what its reader said (never an
    exception's name alone)."""
    import traceback
    chain, err = [], e
    while err is not None and len(chain) < 10:
        chain.append(err)
        err = err.__cause__ or err.__context__
    part = None
    for x in reversed(chain):                  # the innermost reading step names the part
        for frame in traceback.extract_tb(x.__traceback__):
            part = _WORKBOOK_PARTS.get(frame.name, part)
    where = f"sheet {sheet!r}: " if sheet is not None else f"{part}: " if part else ""
    if any(type(x).__module__.startswith("defusedxml") for x in chain):
        what = ("its XML declares or uses entities (external entities, entity expansion "
                "and entities no declaration defines are refused)")
    elif any(type(x).__name__ in ("ParseError", "ExpatError") for x in chain):
        said = next(str(x) for x in chain if type(x).__name__ in ("ParseError", "ExpatError"))
        what = f"malformed XML ({said[:120]})"
    else:
        inner = chain[-1]
        said = (inner.args[0] if isinstance(inner, KeyError) and inner.args else str(inner))
        said = " ".join(str(said).split())[:160]
        what = said or f"unreadable content ({type(inner).__name__})"
    return SurveyInputError(f"not a readable .xlsx workbook: {where}{what}", source, row)


def _sheet_fault(e, source: str, title: str) -> SurveyInputError:
    """One line for a sheet the fast reader refused (:class:`analysis.xlsx_sheet.SheetFault`),
    naming the place once: the sheet and the cell (whose reference holds its row), else the sheet
    and the row."""
    where = f"sheet {title!r}" + (f", cell {e.cell}" if e.cell else f", row {e.row}" if e.row is not None else "")
    return SurveyInputError(f"{where}: {e.reason}", source)


def _xlsx_rows(content: bytes, source: str, sheet: "str | None" = None):
    """Cell texts of one sheet (the first, or the one named ``sheet``), row by row, every
    cell read; with the sheet's name and the names of the other sheets holding a cell.

    The sheet's ``<dimension>`` record is not trusted (a writer may understate it and
    openpyxl would then drop rows and columns silently). The workbook's parts are
    parsed through defusedxml (openpyxl uses it when installed), the sheet's cells by
    :func:`_sheet_rows`: external entities and entity expansion are refused, as is
    malformed XML, with one line naming the file.
    """
    import zipfile

    import openpyxl
    try:
        size = sum(i.file_size for i in zipfile.ZipFile(io.BytesIO(content)).infolist())
    except Exception as e:  # noqa: BLE001 - zipfile raises several kinds on a broken container
        raise SurveyInputError(f"not a readable .xlsx workbook: not a zip archive, or a "
                               f"damaged or truncated one ({e or type(e).__name__})",
                               source) from None
    if size > MAX_XLSX_BYTES:
        raise SurveyInputError(f"workbook unpacks to {size} bytes; at most {MAX_XLSX_BYTES} "
                               f"are read", source)
    try:
        from .xlsx_sheet import load_read_only
        wb = load_read_only(io.BytesIO(content))
    except Exception as e:  # noqa: BLE001 - BadZipFile, KeyError, InvalidFileException, XML errors ...
        raise _xlsx_error(e, source) from None
    rows, width, ws = [], 0, None
    try:
        ws = _worksheet(wb, sheet, source)
        for r in _sheet_rows(wb, ws, source):
            _check_width(source, len(r))
            width = max(width, len(r))
            if len(rows) >= XLSX_MAX_ROWS:
                raise SurveyInputError(f"more than {XLSX_MAX_ROWS} rows, Excel's limit",
                                       source, len(rows) + 1)
            if (len(rows) + 1) * max(width, 1) > MAX_CELLS:   # rows are padded to the width
                raise SurveyInputError(f"more than {MAX_CELLS} cells (rows x columns) in the "
                                       f"sheet", source, len(rows) + 1)
            rows.append([_cell_text(v) for v in r])
        others = [w.title for w in wb.worksheets if w is not ws and _holds_a_cell(wb, w, source)]
    except SurveyInputError:
        raise
    except SheetFault as e:
        raise _sheet_fault(e, source, ws.title) from None
    except Exception as e:  # noqa: BLE001 - ParseError, EntitiesForbidden ... in the sheet
        raise _xlsx_error(e, source, len(rows) + 1, None if ws is None else ws.title) from None
    finally:
        wb.close()
    return rows, ws.title, others


def _worksheet(wb, sheet: "str | None", source: str):
    """The worksheet named ``sheet`` (exactly, else ignoring case and outer spaces), or the
    first; a name the workbook lacks is refused, listing its sheets."""
    sheets = list(wb.worksheets)
    if not sheets:
        raise SurveyInputError("not a readable .xlsx workbook: it has no worksheet (the parts "
                               "its sheet list names are missing)", source)
    if sheet is None:
        return sheets[0]
    for same in (lambda t: t == sheet, lambda t: t.strip().casefold() == sheet.strip().casefold()):
        hits = [w for w in sheets if same(w.title)]
        if len(hits) == 1:
            return hits[0]
    raise SurveyInputError(f"no sheet {sheet!r} (--sheet); the workbook's sheets are "
                           f"{', '.join(repr(w.title) for w in sheets)}", source)


def _sheet_rows(wb, ws, source: str):
    """The values of a worksheet, row by row, every cell read: the sheet's ``<dimension>``
    record is not trusted (a writer may understate it, and openpyxl would then drop rows and
    columns silently). Parsed by :func:`analysis.xlsx_sheet.sheet_values` (about 9 times
    openpyxl's speed), or by openpyxl when the workbook lacks what that needs."""
    from .xlsx_sheet import sheet_values
    if all(hasattr(wb, a) for a in ("_date_formats", "_timedelta_formats", "epoch")) and all(
            hasattr(ws, a) for a in ("_get_source", "_shared_strings")):
        return sheet_values(wb, ws, MAX_COLUMNS,
                            lambda n, row: _check_width(source, n, at_least=True, row=row))
    ws.reset_dimensions()
    return ws.iter_rows(values_only=True)


def _holds_a_cell(wb, ws, source: str) -> bool:
    """Whether a worksheet holds a cell that is not blank (the first one found ends the scan).

    Asked of the sheets not read, for the hint naming them: a sheet that cannot be read (its
    XML malformed or declaring entities, a shared string out of range, too many columns) is counted as holding
    data, so that the hint names it, and does not refuse the sheet that was read."""
    try:
        for i, r in enumerate(_sheet_rows(wb, ws, source)):
            if i >= XLSX_MAX_ROWS:
                return False
            if any(_cell_text(v).strip() for v in r):
                return True
    except Exception:  # noqa: BLE001 - ParseError, EntitiesForbidden, IndexError, too wide ... in that sheet
        return True
    return False


def _sheets_hint(read: str, others: list[str]) -> str:
    """Words naming the sheets of a workbook not read (``""`` when none holds a cell)."""
    if not others:
        return ""
    names = ", ".join(map(repr, others))
    held = "holds" if len(others) == 1 else "hold"
    return (f"read the first sheet, {read!r}; sheet{'s' if len(others) > 1 else ''} {names} "
            f"also {held} data, not read: give --sheet NAME to read another")


def _read_xlsx_raw(path: Path, sheet: "str | None" = None) -> tuple[_Raw, list[list[str]], str]:
    """The sheet read as a table, its first rows (to detect the layout), and when the first
    sheet was read by default and others hold data, the words naming them (also a note)."""
    source = str(path)
    # from the bytes: openpyxl refuses a workbook whose name does not end in .xlsx
    rows, name, others = _xlsx_rows(read_bytes(path), source, sheet)
    hint = _sheets_hint(name, others) if sheet is None else ""
    first = 0
    while first < len(rows) and not any(c.strip() for c in rows[first]):
        first += 1
    if first >= len(rows):
        raise SurveyInputError(f"empty file (no cells in sheet {name!r})"
                               + (f"; {hint}" if hint else ""), source)
    rows = rows[first:]
    while rows and not any(c.strip() for c in rows[-1]):
        rows.pop()
    width = max(len(r) for r in rows)
    header = rows[0] + [""] * (width - len(rows[0]))
    while width > 0 and header[width - 1] == "" and all(
            len(r) < width or r[width - 1] == "" for r in rows):
        width -= 1
    given = header[:width]
    header = _distinct([h if h else f"column {j + 1}" for j, h in enumerate(given)])
    body = [(r + [""] * width)[:width] for r in rows[1:]]
    df = pd.DataFrame(body, columns=header, dtype=object) if body else pd.DataFrame(
        columns=header)
    peek = [header] + [r for r in body if any(c.strip() for c in r)][:3]
    raw = _Raw(source, header, _frame_to_columns(df), first + 2, len(body), given=given,
               notes=[f"{source}: {hint}"] if hint else [])
    return raw, peek, hint


def _distinct(header: list[str]) -> list[str]:
    """Headers made distinct as pandas' CSV reader does: a repeated ``Q1`` becomes ``Q1.1``."""
    seen = set(header)
    count: dict[str, int] = {}
    out = []
    for h in header:
        if h in count:
            k = count[h]
            while f"{h}.{k}" in seen:
                k += 1
            count[h] = k + 1
            name = f"{h}.{k}"
            seen.add(name)
            out.append(name)
        else:
            count[h] = 1
            out.append(h)
    return out


def _raw_from_frame(df: pd.DataFrame, source: str, first_row: int) -> tuple[_Raw, list]:
    cols = _frame_to_columns(df)
    header = [c.name for c in cols]
    peek = [header]
    for i in range(min(3, len(df))):
        peek.append([c.cats[c.codes[i]] for c in cols])
    return _Raw(source, header, cols, first_row, len(df),
                given=[str(c) for c in df.columns]), peek


# ---------------------------------------------------------------------------
# shapes
# ---------------------------------------------------------------------------
_find = platforms.find_column


def _detect_shape(raw: _Raw, peek: list[list[str]]) -> str:
    found = platforms.detect(raw.header, peek)
    if found is not None:
        return found
    if (_find(raw.header, _LONG_RESP) is not None and _find(raw.header, _LONG_ITEM) is not None
            and _find(raw.header, _LONG_ANSWER) is not None):
        return "long"
    return "wide"


def _is_zip(path: Path) -> bool:
    """True for a zip container (an .xlsx workbook saved under another name)."""
    if not is_regular_file(path):
        return False             # read_bytes names the problem (and a FIFO would block here)
    try:
        with open(path, "rb") as fh:
            return fh.read(4) == b"PK\x03\x04"
    except OSError:
        return False             # read_bytes names the problem


def _validate_read(shape, unknown, respondents):
    if shape not in SHAPES:
        raise ValueError(f"`shape` must be one of {list(SHAPES)}, got {shape!r}")
    if unknown not in UNKNOWN_POLICIES:
        raise ValueError(f"`unknown` must be one of {list(UNKNOWN_POLICIES)}, got {unknown!r}")
    if respondents is not None and (not isinstance(respondents, int) or respondents < 1):
        raise ValueError(f"`respondents` must be a positive integer or None, got {respondents!r}")


def read_survey(path: "str | Path", scale: "str | Scale | None" = None,
                items: "list[str] | None" = None, shape: str = "auto",
                unknown: str = "error", encoding: "str | None" = None,
                group: "str | list[str] | None" = None, reverse: "list[str] | None" = None,
                respondents: int | None = None, codes=None,
                sheet: "str | None" = None) -> SurveyData:
    """Read a survey export.

    Parameters
    ----------
    path : str or Path
        CSV (any shape) or ``.xlsx`` file.
    scale : str, Scale or None
        Built-in scale name, TOML file, or Scale; None detects a built-in scale.
    items : list of str, optional
        Item column names or ``fnmatch`` patterns (case-insensitive); default: detect.
    shape : {"auto", "wide", "long", "google", "qualtrics"}
    unknown : {"error", "missing"}
        What to do with an answer that matches no label.
    encoding : str or None
        Text encoding of a CSV file; None reads UTF-8, and a file that is not valid
        UTF-8 as Windows-1252 (with a note in :attr:`SurveyData.notes`).
    group : str or list of str, optional
        Columns kept for grouping.
    reverse : list of str, optional
        Reverse-keyed items (names or patterns).
    respondents : int, optional
        Declared number of respondents; respondents absent from the file are
        missing on every item. Fewer than the file holds is an error.
    codes : str, Path or Codebook, optional
        What numeric (or short) answer codes mean: a Qualtrics ``.qsf``, a LimeSurvey
        ``.lss`` or a ``.toml`` code map (:mod:`analysis.codebook`). Without it,
        numeric answers are refused unless ``scale`` is a scale file (whose codes are
        stated).
    sheet : str, optional
        The worksheet of a workbook to read (default: the first; a note names any other
        sheet holding data). A name the workbook lacks, or a sheet for a CSV, is an error.

    Returns
    -------
    SurveyData

    Raises
    ------
    SurveyInputError
        Empty or unreadable file, bad encoding, no item columns, mixed scales,
        unknown answers (with ``unknown="error"``), unknown column names, two columns
        named alike (ignoring case and spacing; a Canvas export's points columns aside),
        which readers would otherwise rename (``Q1.1``) without a word.
    ValueError
        Bad option strings (the message lists the valid ones).
    """
    _validate_read(shape, unknown, respondents)
    p, hint = Path(path), ""
    if shape == "xlsx" or p.suffix.lower() in (".xlsx", ".xlsm") or _is_zip(p):
        raw, peek, hint = _read_xlsx_raw(p, sheet)
        if shape == "xlsx":            # a workbook of any layout; a named layout is kept
            shape = "auto"
    elif p.suffix.lower() == ".xls":
        raise SurveyInputError("old .xls workbooks are not supported; save as .xlsx or CSV",
                               str(p))
    elif sheet is not None:
        raise SurveyInputError(f"--sheet {sheet!r}: only a workbook (.xlsx) has sheets",
                               str(p))
    else:
        raw, peek = _read_csv_raw(p, encoding)
    try:
        return _build(raw, peek, scale, items, shape, unknown, group, reverse, respondents,
                      _codebook(codes))
    except SurveyInputError as e:      # the first sheet read by default: name the others
        if not hint:
            raise
        raise SurveyInputError(f"{e.message} ({hint})", e.file, e.row, e.column) from None


def _codebook(codes):
    if codes is None:
        return None
    from .codebook import Codebook, load_codebook
    return codes if isinstance(codes, Codebook) else load_codebook(codes)


def survey_from_frame(df: pd.DataFrame, scale: "str | Scale | None" = None,
                      items: "list[str] | None" = None, shape: str = "auto",
                      unknown: str = "error", group=None, reverse=None,
                      respondents: int | None = None, source: str = "<dataframe>",
                      first_row: int = 2, codes=None) -> SurveyData:
    """Like :func:`read_survey`, for a DataFrame whose cells are answer text.

    ``first_row`` is the spreadsheet row of the frame's first record (for messages).
    """
    _validate_read(shape, unknown, respondents)
    if df.shape[1] == 0:
        raise SurveyInputError("empty table (no columns)", source)
    raw, peek = _raw_from_frame(df, source, first_row)
    if df.isna().to_numpy().any():
        raw.notes.append(f"{source}: empty (NaN) cells are counted as blank answers; "
                         "pandas.read_csv turns \"N/A\" answers into NaN unless given "
                         "keep_default_na=False (or read the file with read_survey)")
    return _build(raw, peek, scale, items, shape, unknown, group, reverse, respondents,
                  _codebook(codes))


def _without_empty_records(raw: _Raw) -> _Raw:
    """The records with a cell that is not blank. A row whose every cell is empty or white space
    (an empty workbook row, or the ``,,,,`` a spreadsheet writes for one when saved as CSV) holds
    no answer and no id: it is not a respondent, as a CSV's empty line is not. A one-column file
    is left as it is (there an empty line is a blank answer)."""
    if len(raw.columns) < 2 or not raw.nrows:
        return raw
    filled = np.zeros(raw.nrows, dtype=bool)
    for c in raw.columns:
        filled |= np.array([bool(str(x).strip()) for x in c.cats] or [False], dtype=bool)[c.codes]
    if filled.all():
        return raw
    return _take_records(raw, np.flatnonzero(filled))


def _take_records(raw: _Raw, keep: np.ndarray) -> _Raw:
    """The records ``keep`` (indices, in order) of ``raw``, each keeping its file row."""
    rows = raw.row_of(keep)
    return replace(raw, columns=[replace(c, codes=c.codes[keep]) for c in raw.columns], nrows=len(keep),
                   row_map=rows, first_row=int(rows[0]) if len(rows) else raw.first_row)


def _build(raw: _Raw, peek, scale, items, shape, unknown, group, reverse, respondents,
           codes=None):
    raw = _without_empty_records(raw)
    given = shape
    if shape == "auto":
        shape = _detect_shape(raw, peek)
    why = platforms.signature_missing(shape, raw.header, peek) if given != "auto" else None
    below = [[c.cats[c.codes[i]] for c in raw.columns] for i in range(min(2, raw.nrows))]
    if not why and below:
        why = platforms.header_row_missing(shape, raw.header, below, int(raw.row_of(0)))
    if why:
        raise SurveyInputError(why, raw.source)
    why = platforms.repeated_column(raw.given or raw.header, shape)
    if why:                    # a reader's renaming (Q1 -> Q1.1) would hide it
        raise SurveyInputError(why, raw.source)
    notes = list(raw.notes)
    extra = platforms.header_rows(shape, raw.header, peek) if raw.nrows else 0
    if raw.nrows <= extra and shape != "long":
        rows = "the header row" if not extra else f"the {extra + 1} header rows"
        raise SurveyInputError(f"no responses below {rows} (an empty row, or one of empty cells, "
                               f"is not a response)", raw.source)
    if shape == "long":           # a footer note is dropped by the rule of a wide file
        keep, footer = _drop_footer(raw, np.arange(raw.nrows))
        _note_short_rows(raw, keep, raw.notes)
        data = _build_long(_take_records(raw, keep) if footer else raw, scale, items, unknown,
                           group, reverse, respondents)
        data.dropped = footer + list(data.dropped)
        return data
    keep = np.arange(extra, raw.nrows)
    dropped: list[DroppedRow] = []
    text_row = ([c.cats[c.codes[0]] for c in raw.columns] if shape == "qualtrics" and extra
                else [""] * len(raw.header))
    if shape == "qualtrics":
        keep, dropped = _drop_qualtrics_tests(raw, keep, text_row)
        if len(keep) == 0:
            raise SurveyInputError(f"no responses below the header (after dropping "
                                   f"{len(dropped)} preview and test rows)", raw.source)
    if shape == "canvas":
        keep, earlier = _drop_earlier_attempts(raw, keep)
        dropped += earlier
    _note_incomplete(raw, keep, notes, shape, text_row)
    keep, footer = _drop_footer(raw, keep)
    dropped += footer
    _note_short_rows(raw, keep, notes)
    names, stems = _item_names(raw, shape, extra, codes)
    rows = raw.row_of(keep)
    exclude = {j for j, h in enumerate(raw.header)
               if not platforms.candidate(shape, h, text_row[j])}
    group_names = _as_list(group)
    group_idx = [column_index(raw.source, raw.header, g, names, text_row)
                 for g in group_names]
    exclude |= set(group_idx)
    keep = _as_slice(keep)
    cols = [(j, _Column(names[j], c.cats, c.codes[keep], c.name))
            for j, c in enumerate(raw.columns)]
    mapped = set()
    if codes is not None:
        cols, mapped = _apply_codebook(cols, codes, exclude - set(group_idx), notes, raw.source)
    scale_obj, item_cols = _choose_items(raw.source, names, cols, exclude, scale, items,
                                         notes=notes,
                                         codes_file=None if codes is None else codes.source)
    if not items:                      # (columns named by --items are items by choice)
        _note_mapped_attributes(raw.source, item_cols, mapped, scale_obj, notes)
    answers, unknowns = _match(raw.source, scale_obj, item_cols, rows, unknown)
    counts = label_counts(answers, scale_obj.k)
    _scale_notes(scale_obj, counts, scale is None, notes)
    chosen = [j for j, _ in item_cols]
    item_idx = set(chosen)                        # built once: the column scan stays linear
    item_names = [names[j] for j in chosen]
    by_index = dict(cols)                   # answer text after any code map
    groups = {group_column_name(raw.header[j], names[j], g): np.array(
        by_index[j].cats, dtype=object)[by_index[j].codes] for g, j in zip(group_names, group_idx)}
    places = _ItemPlaces.of(item_cols)
    others = _other_columns(raw, shape, names, item_idx, lambda j: (
        "grouping column" if j in group_idx else "metadata" if j in exclude
        else _why_not_item(by_index[j], scale_obj, items, False, notes, j, places)))
    data = SurveyData(source=raw.source, shape=shape, scale=scale_obj, items=item_names,
                      item_texts=item_names, answers=answers,
                      rows=np.asarray(rows, dtype=np.int64), groups=groups,
                      unknown_answers=unknowns, dropped=dropped,
                      reverse=_resolve_reverse(raw.source, item_names, reverse,
                                               [raw.columns[j].name for j in chosen]),
                      other_columns=list(others), not_item_reasons=others,
                      comments=list(raw.comments), stems=[stems[j] for j in chosen],
                      fields=[raw.columns[j].name for j in chosen], notes=notes)
    _narrower_items(data, counts, scale is None)
    pid = person_id_column(raw.header)
    if pid is not None:
        c = raw.columns[pid]
        data.ids, data.id_column = np.array(c.cats, dtype=object)[c.codes[keep]], c.name
        _note_repeated_ids(data)
    return _declare(data, respondents)


def _note_repeated_ids(data: "SurveyData") -> None:
    """Note ids (an email, a student id) on more than one row within one value of the
    grouping columns read: each row is still counted, and the note says so with the rows.
    Ids match as answers do (case and spacing ignored)."""
    groups = [[normalize_answer(str(v)) for v in col] for col in data.groups.values()]
    rows_of: dict = {}
    for i, x in enumerate(data.ids):
        k = normalize_answer(str(x))
        if k:
            rows_of.setdefault((k,) + tuple(g[i] for g in groups), []).append(i)
    repeated = [idx for idx in rows_of.values() if len(idx) > 1]
    if repeated:
        data.notes.append(repeated_ids_note(
            data.source, data.id_column, list(data.groups), len(repeated),
            [(str(data.ids[idx[0]]).strip(), [int(data.rows[i]) for i in idx])
             for idx in repeated[:3]]))


def repeated_ids_note(source: str, column: str, groups: list, k: int, shown: list) -> str:
    """The note on ``k`` ids found on more than one row (within one value of the
    ``groups`` columns), naming the first few: ``shown`` lists (id, rows), or (id, number
    of rows) when the rows were not looked up. Both routes (``read_survey`` and
    ``summarize_by``) word it here."""
    listed = "; ".join(f"{x!r} on {rows} rows" if isinstance(rows, int) else
                       f"{x!r} in rows {', '.join(map(str, rows))}" for x, rows in shown)
    more = f"; and {k - len(shown)} more" if k > len(shown) else ""
    within = f" with the same {', '.join(map(repr, groups))}" if groups else ""
    return (f"{source}: column {column!r}: {k} id{'s' if k != 1 else ''} on more than one "
            f"row{within} ({listed}{more}); each row is counted as a respondent: remove "
            f"repeated submissions if they are one person's")


def _other_columns(raw: _Raw, shape: str, names: list[str], item_idx: set, why) -> dict:
    """``{name: reason}`` of the columns that are not items, in file order; ``why(j)``
    gives the reason of column ``j``. A Canvas points column, repeated by design (a
    reader renames the second ``1.0`` to ``1.0.1``), is named by its header as written
    and its position."""
    given = raw.given if raw.given and len(raw.given) == len(names) else raw.header
    out = {}
    for j in range(len(raw.columns)):
        if j in item_idx:
            continue
        if platforms.points_column(shape, given[j]):
            out[f"{given[j].strip()} in column {j + 1}"] = "Canvas points column"
        else:
            out[names[j]] = why(j)
    return out


#: Columns that identify a person, best first: the one rule of both routes for the note on an
#: id on several rows and of pre/post pairing. Every name :data:`_ID_LIKE` leaves out of the
#: items as an identifier is here, but the row numbers (``record``, ``row``, ``#``) and
#: ``response id`` (one per response: it names no person to pair).
_PERSON_ID = ("student id", "student_id", "studentid", "sis_id", "sis user id", "sis id",
              "externalreference", "external reference", "externaldatareference",
              "participant id", "participant_id", "participantid", "respondent id",
              "respondent_id", "respondentid", "id", "username", "user", "user_id", "userid",
              "email address", "email", "recipientemail", "student", "participant", "respondent")


def person_id_column(header: list[str]) -> "int | None":
    """Index of the column that identifies a person (student id, e-mail ...), or None.

    Both routes take the note on repeated ids from it (:func:`read_survey` and
    :func:`analysis.institution.summarize_by`), and ``--group`` its pre/post pairs."""
    return _find(header, _PERSON_ID)


#: Qualtrics ``Status`` values that are not real respondents (text and numeric export).
_QUALTRICS_NOT_RESPONDENTS = {"survey preview": "Survey Preview", "1": "Survey Preview",
                              "survey test": "Survey Test", "2": "Survey Test"}


def _as_slice(keep: np.ndarray):
    """A run of consecutive rows as a slice (a view: no copy of a million codes per column)."""
    if len(keep) and keep[-1] - keep[0] == len(keep) - 1:
        return slice(int(keep[0]), int(keep[-1]) + 1)
    return keep


def _drop_qualtrics_tests(raw: _Raw, keep: np.ndarray, text_row: list[str]):
    """Rows kept and rows dropped: preview and test responses are not respondents."""
    status = _find(raw.header, ("status",))
    if status is None:
        status = _find(text_row, ("status",))        # legacy export: field V7
    if status is None:
        return keep, []
    col = raw.columns[status]
    vals = np.array([normalize_answer(x) for x in col.cats], dtype=object)[col.codes[keep]]
    numeric = all(is_integer_text(v) for v in set(vals) if v != "")
    drop = np.array([v in _QUALTRICS_NOT_RESPONDENTS and (numeric or not is_integer_text(v))
                     for v in vals], dtype=bool)
    dropped = [DroppedRow(int(raw.row_of(keep[i])),
                          f"{_QUALTRICS_NOT_RESPONDENTS[vals[i]]} response")
               for i in np.flatnonzero(drop)]
    return keep[~drop], dropped


def _drop_earlier_attempts(raw: _Raw, keep: np.ndarray):
    """Rows kept and rows dropped: of a Canvas student's attempts only the latest counts (each
    dropped row says why, :data:`DROP_WHY`; the command line sums them up in one line).

    A student is known by ``id`` and ``sis_id`` (rows where both are blank are never
    merged); the latest attempt has the highest ``attempt`` number, and of two rows with
    the same number the later in the file. An attempt that is not a whole number, on a
    student with several rows, is an error: which attempt counts cannot be told.
    """
    at = _find(raw.header, ("attempt",))
    who = [j for j in (_find(raw.header, ("id",)), _find(raw.header, ("sis_id",)))
           if j is not None]
    if at is None or not who:
        return keep, []
    text = {j: np.array([x.strip() for x in raw.columns[j].cats], dtype=object)[
        raw.columns[j].codes[keep]] for j in who + [at]}
    keys = list(zip(*(text[j] for j in who)))
    rows_of: dict = {}
    for i, key in enumerate(keys):
        if any(key):
            rows_of.setdefault(key, []).append(i)
    later = []
    for key, idx in rows_of.items():
        if len(idx) < 2:
            continue
        bad = [i for i in idx if not is_integer_text(text[at][i])]
        if bad:
            raise SurveyInputError(f"row {raw.row_of(keep[bad[0]])}, column "
                                   f"{raw.header[at]!r}: attempt {text[at][bad[0]]!r} is "
                                   "not a whole number, so the "
                                   "student's latest attempt cannot be told", raw.source)
        last = max(idx, key=lambda i: (int(text[at][i]), i))
        later += [i for i in idx if i != last]
    gone = np.zeros(len(keep), dtype=bool)
    gone[later] = True
    dropped = [DroppedRow(int(raw.row_of(keep[i])), "earlier attempt") for i in sorted(later)]
    return keep[~gone], dropped


def _drop_footer(raw: _Raw, keep: np.ndarray):
    """Rows kept and rows dropped: a last row below empty rows with text in its first cell
    only ("Exported by ... on ...") is a note of the exporting tool, not a respondent.
    A number or a label of a built-in scale there is an answer: that row is kept."""
    if len(keep) < 2 or len(raw.columns) < 2:
        return keep, []
    last, before = int(keep[-1]), int(keep[-2])
    if int(raw.row_of(last)) - int(raw.row_of(before)) < 2:
        return keep, []
    if not is_footer_note([c.cats[c.codes[last]] for c in raw.columns]):
        return keep, []           # an answer or a code in the first column: a respondent
    return keep[:-1], [DroppedRow(int(raw.row_of(last)), FOOTER)]


#: How each platform marks a response never completed: the column (its names), the test of
#: its cell text (normalised) and the words saying so (``{value}``: the cells as written).
_INCOMPLETE = {
    "limesurvey": (("submitdate", "date submitted"), lambda t: t == "", "blank {name}"),
    "qualtrics": (("finished",), lambda t: t in ("false", "0"), "{name} = {value}"),
}


def _note_incomplete(raw: _Raw, keep: np.ndarray, notes: list, shape: str,
                     text_row: "list[str] | None" = None) -> None:
    """Note responses never completed (LimeSurvey: a blank ``submitdate``; Qualtrics:
    ``Finished`` False, or 0 in a numeric export): they are counted with the answers they
    hold, as partial respondents, not dropped. ``text_row``: a legacy Qualtrics export's
    question texts, where ``Finished`` is named (its field is ``V10``)."""
    if shape not in _INCOMPLETE:
        return
    names, test, words = _INCOMPLETE[shape]
    j = _find(raw.header, names)
    if j is None and text_row:
        j = _find(text_row, names)
    if j is None:
        return
    col = raw.columns[j]
    codes = col.codes[keep]
    bad = np.array([test(normalize_answer(x)) for x in col.cats], dtype=bool)[codes]
    k = int(bad.sum())
    if k:
        rows = [int(r) for r in raw.row_of(keep[bad][:5])]
        more = f" and {k - 5} more" if k > 5 else ""
        name = (raw.header[j] if _find(raw.header, names) is not None else text_row[j]).strip()
        value = " or ".join(dict.fromkeys(col.cats[c].strip() for c in np.unique(codes[bad])))
        notes.append(f"{raw.source}: {k} incomplete response{'s' if k != 1 else ''} "
                     f"({words.format(name=repr(name), value=value)}, row{'s' if k != 1 else ''} "
                     f"{', '.join(map(str, rows))}{more}) counted with the answers given")


def _item_names(raw: _Raw, shape: str, extra: int, codes) -> tuple[list[str], list[str]]:
    """Statement name and stem of every column (names made distinct)."""
    header = raw.header
    if shape == "surveymonkey":
        second = [c.cats[c.codes[0]] for c in raw.columns]
        pairs = platforms.surveymonkey_names(header, second)
    else:
        texts = ([c.cats[c.codes[0]] for c in raw.columns] if shape == "qualtrics" and extra
                 else header)
        pairs = [platforms.split_stem(shape, h, t if t.strip() else h)
                 for h, t in zip(header, texts)]
    if codes is not None:
        pairs = [(codes.texts.get(h.strip().casefold()) or n,
                  codes.stems.get(h.strip().casefold(), s))
                 for h, (n, s) in zip(header, pairs)]
    return _statement_names(header, pairs)


def header_item_names(header: list[str], peek: list) -> tuple[list[str], list[str]]:
    """Statement name and stem of every column of a file known by its header row and first
    records (``peek``), as :func:`read_survey` names them: a grid row ``Rate each [X]`` is
    item ``X``. :func:`analysis.institution.summarize_by` names its items so, and both
    routes' tables join on ``item``. For exports whose statements are in a second header row
    (Qualtrics, SurveyMonkey), which ``summarize_by`` refuses, the header is taken as is."""
    shape = platforms.detect(header, peek) or "wide"
    return _statement_names(header, [platforms.split_stem(shape, h, h) for h in header])


def _statement_names(header: list[str], pairs: list) -> tuple[list[str], list[str]]:
    """Names made from (statement, stem) ``pairs``: white space collapsed, a repeated
    statement named with its stem, then with its header, then made distinct."""
    names = [" ".join(n.split()) or h for h, (n, _) in zip(header, pairs)]
    # a statement asked under two stems ("Before this course - X", "After this course -
    # X") is named with its stem; only a name repeated even so falls back to the field id
    names = _unique_or(names, [" ".join(f"{s} - {n}".split()) if s.strip() else n
                               for n, (_, s) in zip(names, pairs)])
    names = _unique_or(names, header)
    return _distinct(names), [s for _, s in pairs]


def _unique_or(names: list[str], instead: list[str]) -> list[str]:
    """``names``, each name that is repeated (ignoring case and spacing) replaced by the
    same position of ``instead``."""
    seen: dict[str, int] = {}
    for n in names:
        seen[normalize_answer(n)] = seen.get(normalize_answer(n), 0) + 1
    return [n if seen[normalize_answer(n)] == 1 else alt for n, alt in zip(names, instead)]


def _mostly_codes_of(col: _Column, keys: list[str], m: dict) -> bool:
    """A code map given for any column applies to ``col`` when its answers are whole
    numbers, most of them codes of the map, and it is not an id column. A number the
    map lacks (a typo "6" among codes 1-5) is then an unknown answer, named by its row
    and column, never a reason to leave the whole column out unsaid."""
    if _ID_LIKE.match(col.name.strip()):
        return False
    inside = outside = 0
    for t, k, cnt in zip(col.cats, keys, col.counts()):
        if not cnt or not t.strip() or _is_na_text(t):
            continue
        if k in m:
            inside += int(cnt)
        elif is_integer_text(k):
            outside += int(cnt)
        else:
            return False                 # text that is no code: not a coded column
    return inside > outside


def _apply_codebook(cols, book, exclude, notes, source):
    """Columns with their codes replaced by answer text, where the code map covers them,
    and the indices of those the map's general codes were applied to (by their answers,
    :func:`_mostly_codes_of`, not by a column it names)."""
    from .codebook import Codebook
    out = []
    mapped_general = []
    for j, c in cols:
        m = book.map_for(c.field or c.name)
        if m is None or j in exclude:
            out.append((j, c))
            continue
        general = m is book.default and not book.patterns
        keys = [Codebook.key(t) for t in c.cats]
        used = [k for t, k, cnt in zip(c.cats, keys, c.counts()) if cnt and t.strip()
                and not _is_na_text(t)]
        if general and not _mostly_codes_of(c, keys, m):
            out.append((j, c))              # not a coded item
            continue
        cats = [m.get(k, t) if t.strip() else t for t, k in zip(c.cats, keys)]
        new = _Column(c.name, cats, c.codes, c.field)
        out.append((j, new))
        if general:
            mapped_general.append((j, set(used)))
    # a column coded 1/2 among 5-point items is a question of its own (e.g. a section)
    most = max((len(d) for _, d in mapped_general), default=0)
    narrow = set()
    if book.default is not None and len(book.default) >= 4 and most >= 3:
        narrow = {j for j, d in mapped_general if d == {"1", "2"}}
        for i, (j, c) in enumerate(out):
            if j in narrow:
                old = next(col for jj, col in cols if jj == j)
                out[i] = (j, old)
                notes.append(f"{source}: column {old.field or old.name!r} holds only codes 1 "
                             "and 2 while other items use more: read as a question of its own "
                             "(e.g. a section), not an item; to take it as one, list the item "
                             "columns in the code map: columns = [\"Q1\", \"Q2\"] under "
                             "[codes]")
    return out, {j for j, _ in mapped_general} - narrow


def _note_mapped_attributes(source, chosen, mapped: set, scale: Scale, notes: list) -> None:
    """Say which items the code map's general codes made of a column that does not look like
    an item beside the others (:func:`_looks_like_an_item`: a year of study 1-4 beside 5-point
    items). The map applies to every column whose answers are mostly its codes, so the column
    stays an item, counted; the note says so and how to leave it out."""
    places = _ItemPlaces.of(chosen)
    for j, c in chosen:
        if j in mapped and len(chosen) > 1 and not _looks_like_an_item(j, c, scale, places,
                                                                        taken=True):
            notes.append(f"{source}: column {(c.field or c.name)!r} is read through the code "
                         f"map as an item (its answers are mostly the map's codes), though "
                         f"{_UNLIKE}; if it is {_ATTRIBUTE}, list the item columns in the code "
                         f"map: columns = [\"Q1\", \"Q2\"] under [codes]")


def _scale_notes(scale: Scale, counts: np.ndarray, detected: bool, notes: list) -> None:
    """The notes on the scale read, for wide and long files alike: labels nobody used
    while another scale fits, and (when the scale was ``detected``) a missing label.
    ``counts``: answers per item and label (:func:`label_counts`)."""
    _warn_unused_labels(scale, counts, notes)
    if detected:
        _note_no_neutral(scale, notes)


def scale_fit_notes(source: str, scale: Scale, names: list, counts: np.ndarray,
                    reverse=frozenset(), detected: bool = True) -> tuple[list[str], dict]:
    """The warnings on how the scale fits the answers that :func:`read_survey` gives, for
    :func:`analysis.institution.summarize_by` (which notes a missing label on choosing the
    items): labels nobody used while another scale fits, and items that look as if they
    offered a narrower scale, with those to leave out (:func:`narrower_scale_notes`)."""
    notes: list[str] = []
    _warn_unused_labels(scale, counts, notes)
    more, left_out = narrower_scale_notes(source, scale, names, counts, reverse, detected)
    return notes + more, left_out


def _narrower_items(data: "SurveyData", counts: np.ndarray, detected: bool) -> None:
    """Warn of the items that look as if they offered a narrower scale, and leave out of
    ``data`` those that did (:func:`narrower_scale_notes`), listed with their reason."""
    notes, left_out = narrower_scale_notes(data.source, data.scale, data.items, counts,
                                           data.reverse, detected)
    data.notes += notes
    if not left_out:
        return
    keep = [j for j, name in enumerate(data.items) if name not in left_out]
    data.items = [data.items[j] for j in keep]
    data.item_texts = [data.item_texts[j] for j in keep]
    data.answers = data.answers[:, keep]
    data.stems = [data.stems[j] for j in keep if j < len(data.stems)]
    data.fields = [data.fields[j] for j in keep if j < len(data.fields)]
    data.reverse = {r for r in data.reverse if r not in left_out}
    data.other_columns = list(data.other_columns) + list(left_out)
    data.not_item_reasons = {**data.not_item_reasons, **left_out}


def _note_no_neutral(scale: Scale, notes: list) -> None:
    """Say so when a scale without a neutral answer was detected inside a wider one."""
    if scale.neutral:
        return
    mine = {normalize_answer(x) for x in scale.labels}
    for other in BUILTIN_SCALES.values():
        if other.neutral and mine < {normalize_answer(x) for x in other.labels}:
            lacking = [x for x in other.labels if normalize_answer(x) not in mine]
            named = " or ".join(map(repr, lacking))
            what = "neutral answer" if lacking == list(other.neutral) else f"answer {named}"
            notes.append(f"read as the {scale.k}-point scale {scale.name!r} (no {what} in the "
                         f"data); give --scale {other.name} if the questionnaire offered "
                         f"{named}")
            return


def _warn_unused_labels(scale: Scale, counts: np.ndarray, notes: list) -> None:
    """Note when labels go unused and another built-in scale fits the answers exactly."""
    used = np.flatnonzero(np.asarray(counts).reshape(-1, scale.k).sum(axis=0) > 0)
    if len(used) == scale.k or len(used) == 0:
        return
    got = {normalize_answer(scale.labels[i]) for i in used}
    for other in BUILTIN_SCALES.values():
        if other.name != scale.name and {normalize_answer(x) for x in other.labels} == got:
            unused = [lab for i, lab in enumerate(scale.labels) if i not in set(used.tolist())]
            notes.append(f"warning: scale {scale.name!r} has labels no answer uses "
                         f"({', '.join(unused)}), while scale {other.name!r} fits the answers "
                         f"exactly; give --scale {other.name} if that is the questionnaire's "
                         f"scale (medians and codes depend on it)")
            return


#: Chance below which an item's answers missing every label that only the wider scale has
#: is taken as a sign that the item offered the narrower scale (see :func:`narrower_scale_notes`).
NARROWER_SCALE_CHANCE = 0.05
#: The stricter chance below which such an item, answered on both sides of those labels, is
#: left out of the table (a warning at 5% is cheap; leaving an item out needs firmer evidence:
#: a 5-point item of 13 answers that nobody answered neutrally, where 35% of the others'
#: answers are neutral, is at 0.4% and stays).
NARROWER_SCALE_LEAVE_OUT = 0.001


def label_counts(answers: np.ndarray, k: int) -> np.ndarray:
    """Answers per label of each item, shape (items, k), from a matrix of scale positions."""
    return np.array([np.bincount(np.ascontiguousarray(col[col >= 0]), minlength=k)[:k]
                     for col in answers.T], dtype=np.int64).reshape(answers.shape[1], k)


def _narrower_scales(scale: Scale) -> list:
    """(built-in scale, positions of its labels on ``scale``) for every built-in scale whose
    labels are some of ``scale``'s, in the same order (agree5 in agree7); widest first."""
    mine = [normalize_answer(x) for x in scale.labels]
    out = []
    for other in BUILTIN_SCALES.values():
        theirs = [normalize_answer(x) for x in other.labels]
        if other.k < scale.k and all(t in mine for t in theirs):
            pos = [mine.index(t) for t in theirs]
            if pos == sorted(pos):
                out.append((other, pos))
    return sorted(out, key=lambda t: -t[0].k)


def narrower_scale_notes(source: str, scale: Scale, names: list, counts: np.ndarray,
                         reverse=frozenset(), detected: bool = True) -> tuple[list[str], dict]:
    """Warnings naming the items that look as if they offered a narrower built-in scale, and
    the items left out of the table for it.

    In a file mixing 5-point and 7-point agreement items the whole file is read as the
    wider scale: a 5-point item then lands on codes 1, 2, 4, 6, 7, and its median, IQR,
    mean and SD are wrong (its counts and agreement share are not). An item is a suspect
    when it uses only labels of a narrower built-in scale (agree5 inside agree7), and never
    one of the labels only the wider scale has, while other items do, so often that an item
    of this many answers on the wider scale would miss all of them with a chance below
    :data:`NARROWER_SCALE_CHANCE`: (1 - f) ** n, f being those labels' share of the answers
    of the items using them.

    A suspect whose answers lie on both sides of such a label (``Disagree`` and ``Agree``
    around agree7's ``Somewhat ...``) skipped a middle answer it would have been offered,
    and when the chance is also below :data:`NARROWER_SCALE_LEAVE_OUT` it offered the
    narrower scale. When the scale was ``detected`` (no ``--scale``), such an
    item is left out of the table, as R's ``likert()`` refuses items of unequal numbers of
    levels in one table, with the reason and its statistics on the narrower scale, rather
    than summarized on codes that are not its own. A given ``--scale`` is the questionnaire's
    word, and a suspect answered only at one end (every answer ``Strongly agree``) may be
    a consensus on the wider scale: those are kept, with the warning and both readings.
    Both routes (:func:`read_survey`, :func:`analysis.institution.summarize_by`) call this.

    Parameters
    ----------
    source : str
    scale : Scale
        The scale the answers were read on.
    names : list of str
        Item names, in the order of ``counts``' rows.
    counts : numpy.ndarray of int, shape (items, scale.k)
        Answers per label.
    reverse : set of str
        Reverse-keyed items (their statistics on reversed codes, as in the table).
    detected : bool
        The scale was detected from the answers (not given with ``--scale``).

    Returns
    -------
    notes : list of str
    left_out : dict of str to str
        The items to leave out of the table, each with its reason.
    """
    from .rounding import percent_text
    counts = np.asarray(counts, dtype=np.int64)
    notes, named, left_out = [], set(), {}
    for other, pos in _narrower_scales(scale):
        wider = [i for i in range(scale.k) if i not in pos]
        using = [j for j in range(len(names)) if counts[j, wider].sum()]
        if not using:
            continue
        k_wider, n_using = int(counts[using][:, wider].sum()), int(counts[using].sum())
        f = k_wider / n_using
        found = [j for j in range(len(names)) if j not in named and j not in using
                 and counts[j].sum() and (1 - f) ** int(counts[j].sum()) < NARROWER_SCALE_CHANCE]
        named.update(found)
        around = [j for j in found if detected
                  and (1 - f) ** int(counts[j].sum()) < NARROWER_SCALE_LEAVE_OUT
                  and any(counts[j, :w].sum() and counts[j, w + 1:].sum() for w in wider)]
        words = _NarrowerWords(source, scale, other, pos, wider, names, counts, reverse,
                               percent_text(k_wider, n_using, 0))
        if around:
            notes.append(words.left_out(around))
            left_out.update({names[j]: words.reason() for j in around})
        kept = [j for j in found if j not in around]
        if kept:
            notes.append(words.kept(kept))
    return notes, left_out


@dataclass
class _NarrowerWords:
    """The wording of :func:`narrower_scale_notes` for one narrower scale ``other``."""
    source: str
    scale: Scale
    other: Scale
    pos: list
    wider: list
    names: list
    counts: np.ndarray
    reverse: frozenset
    share: str

    def _stats(self, found: list) -> str:
        from .likert import summarize_tally
        from .rounding import number_text, quartile_texts
        stats = []
        for j in found:
            name = self.names[j]
            it = summarize_tally(np.concatenate([[0, 0, 0], self.counts[j, self.pos]]),
                                 self.other, name, reverse=name in self.reverse)
            stats.append(f"{name!r}{' (reversed)' if it.reverse else ''}: median "
                         f"{number_text(it.median)}, IQR {quartile_texts(it.q1, it.q3)[0]}, mean "
                         f"{number_text(it.mean, 2)}, SD {number_text(it.sd, 2)}")
        lo, hi = (number_text(min(self.other.codes), 0), number_text(max(self.other.codes), 0))
        return f"on {self.other.name!r} (codes {lo}-{hi}) they are {'; '.join(stats)}"

    def _only(self) -> str:
        return " or ".join(repr(self.scale.labels[i]) for i in self.wider)

    def _head(self, found: list) -> str:
        which = ", ".join(repr(self.names[j]) for j in found)
        return f"item{'s' if len(found) > 1 else ''} {which}"

    def kept(self, found: list) -> str:
        return (f"warning: {self.source}: {self._head(found)} never answered {self._only()} "
                f"(labels only scale {self.scale.name!r} has, {self.share}% of the answers to "
                f"the items that use them): if they offered scale {self.other.name!r}, their "
                f"median, IQR, mean, SD (and a Cronbach's alpha with them) are on the wrong "
                f"codes; {self._stats(found)} (summarize them with --items and --scale "
                f"{self.other.name})")

    def left_out(self, found: list) -> str:
        return (f"warning: {self.source}: {self._head(found)} left out of the table: "
                f"{self.reason()}; {self._stats(found)}")

    def reason(self) -> str:
        return (f"answers of scale {self.other.name!r}, not {self.scale.name!r}: never "
                f"{self._only()} ({self.share}% of the answers to the items that use them), "
                f"though its answers lie on both sides of such a label; summarize with "
                f"--items and --scale {self.other.name}, or give --scale {self.scale.name} to "
                f"count it on {self.scale.name!r} codes")


name_matches = platforms.name_matches


def _as_list(x) -> list[str]:
    if x is None:
        return []
    if isinstance(x, str):
        return [x]
    return list(x)


def column_index(source: str, header: list[str], name: str, names: "list[str] | None" = None,
                 texts: "list[str] | None" = None, flag: "str | None" = None) -> int:
    """The column a grouping flag names (``--group`` here, ``--by`` in
    :mod:`analysis.institution`: one rule): by its header, any case and spacing (a header cell
    on two lines is named with one space), else, given the columns' question ``names`` (a
    Qualtrics export's texts, as items are named), by its question text, as ``--items`` takes
    an item (:func:`analysis.platforms.item_matches`). ``texts`` are the question texts as
    the export writes them: a text two questions share (each then named by its field id) is
    refused as ambiguous, naming them. ``flag`` names the flag in the refusal."""
    key = normalize_answer(name)
    for j, h in enumerate(header):
        if normalize_answer(h) == key:
            return j
    named = {j: n for j, n in enumerate(names or []) if normalize_answer(n) != normalize_answer(
        header[j])}
    hits = [j for j, n in named.items() if platforms.item_matches(name, n)]
    if len(hits) == 1:
        return hits[0]
    hits = hits or [j for j, t in enumerate(texts or []) if t.strip() and normalize_answer(
        t) != normalize_answer(header[j]) and platforms.item_matches(name, t)]
    shown = [platforms.spaced_name(h) for h in header]
    if len(hits) > 1:
        raise SurveyInputError(f"{name!r} is the question text of columns "
                               f"{[shown[j] for j in hits]!r}; name one of them", source, 1)
    if hits:
        return hits[0]
    also = f"; question texts are {list(named.values())!r}" if named else ""
    head = f"{flag} {name!r}: no such column" if flag else f"no column {name!r}"
    raise SurveyInputError(f"{head}; columns are {shown!r}{also}", source, 1)


def group_column_name(header: str, text: str, given: str) -> str:
    """A grouping column's name in :attr:`SurveyData.groups` and every output, on both routes:
    its header with white space collapsed (:func:`analysis.platforms.spaced_name`), or its
    question text when the flag named it so (``--group Section`` for Qualtrics' ``Q2``)."""
    if normalize_answer(header) == normalize_answer(given):
        return platforms.spaced_name(header)
    return text


_resolve_reverse = platforms.resolve_reverse


def _declare(data: SurveyData, respondents: int | None) -> SurveyData:
    if respondents is None:
        return data
    from .likert import absent_respondents
    have = data.respondents
    if absent_respondents(respondents, have, data.source):
        pad = np.full((respondents - have, len(data.items)), BLANK, dtype=np.int8)
        data.answers = np.vstack([data.answers, pad])
        data.rows = np.concatenate([data.rows, np.zeros(respondents - have, dtype=np.int64)])
        for g in list(data.groups):
            data.groups[g] = np.concatenate([data.groups[g],
                                             np.array([""] * (respondents - have), dtype=object)])
        if data.ids is not None:
            data.ids = np.concatenate([data.ids, np.array([""] * (respondents - have),
                                                          dtype=object)])
    return data


# ---------------------------------------------------------------------------
# item detection and matching
# ---------------------------------------------------------------------------
def _column_stats(col: _Column, scale: Scale) -> tuple[int, int, int, int]:
    """(non-blank answers, label-text matches, code matches, not-applicable answers).

    Not-applicable texts ("N/A", ...) are counted apart: they fit every scale and are
    common in free-text columns, so they are no evidence that a column is an item.
    """
    keys = col.__dict__.get("_keys")
    if keys is None:                  # each distinct text normalised once, not once per scale
        keys = [(normalize_answer(t), code_key(t), int(c))
                for t, c in zip(col.cats, col.counts()) if c]
        keys = [k for k in keys if k[0] != ""]
        col.__dict__["_keys"] = keys
    answers, code_of = scale.answer_keys(), scale.code_keys()
    nonblank = labels = codes = na = 0
    for key, ck, cnt in keys:
        nonblank += cnt
        m = answers.get(key)
        if m == Scale.NOT_APPLICABLE:
            na += cnt
        elif m is not None:
            labels += cnt
        elif ck is not None and ck in code_of:
            codes += cnt
    return nonblank, labels, codes, na


def _label_item(stats) -> bool:
    """At least one label text, and labels, codes or N/A make up half the answers or more."""
    nonblank, labels, codes, na = stats
    return nonblank > 0 and labels > 0 and 2 * (labels + codes + na) >= nonblank


def _unanswered(stats) -> bool:
    """No answer at all: every cell blank or not applicable."""
    nonblank, labels, codes, na = stats
    return labels == 0 and codes == 0 and nonblank == na


def _code_item(stats) -> bool:
    """Every non-blank answer is a numeric code of the scale (or not applicable)."""
    nonblank, labels, codes, na = stats
    return codes > 0 and codes + na == nonblank


def _numeric_only(col: _Column) -> bool:
    """Every non-blank answer is a whole number 0..11 (or not applicable), and there is one.

    Such a column is a coded item unless a code map says otherwise (ages, years and
    scores lie outside the range).
    """
    seen = False
    for text, cnt in zip(col.cats, col.counts()):
        t = text.strip()
        if not cnt or not t or _is_na_text(t):
            continue
        try:
            v = float(t)
        except ValueError:
            return False
        if not (v == v and v.is_integer() and 0 <= v <= 11):    # scale codes, NPS 0-10
            return False
        seen = True
    return seen


def _refuse_codes(source: str, col: _Column, long: bool, codes_file: "str | None" = None):
    where = f"item {col.name!r}: " if long else ""
    if codes_file:                  # a code map was given: it is the map that falls short
        hint = (f"the code map {codes_file} does not cover them; add the missing codes "
                f"under [codes], or a .qsf/.lss survey definition that has this column")
    else:
        hint = CODES_HINT
    return SurveyInputError(
        f"{where}answers are numeric codes, and which end of the numbering means agreement "
        f"is not known; {hint}", source, None if long else 1,
        None if long else (col.field or col.name))


def unmatched_item(source: str, pattern: str, names: list, long: bool = False):
    """The refusal of an ``--items`` pattern that matches no column (of a long file: no
    item), listing the ``names`` it could match; the words of both routes."""
    what = "item" if long else "column"
    return SurveyInputError(f"no {what} matches item {pattern!r}; {what}s are {names!r}",
                            source, None if long else 1)


def _choose_items(source: str, names: list[str], cols, exclude, scale, items,
                  long: bool = False, notes: "list | None" = None,
                  codes_file: "str | None" = None):
    """The scale and the item columns: named by ``items`` patterns, or detected.

    ``cols`` is a list of (index, _Column); ``names`` are the names listed in messages
    (column headers, or item names of a long file); ``codes_file`` is the code map the
    columns were read through, if any.
    """
    what = "item" if long else "column"
    if items:
        chosen, taken = [], set()
        for pat in items:
            hits = [(j, c) for j, c in cols if platforms.item_matches(pat, c.name, c.field)]
            if not hits:
                raise unmatched_item(source, pat, names, long)
            chosen.extend(h for h in hits if h[0] not in taken)
            taken.update(j for j, _ in hits)
        chosen.sort(key=lambda t: t[0])
        _check_item_count(source, chosen)
        if scale is None:
            for _, c in chosen:
                if _numeric_only(c):
                    raise _refuse_codes(source, c, long, codes_file)
            scale_obj = _detect_scale(source, chosen, require_all=True, long=long)
        else:
            scale_obj = _get_scale(scale, source)
        return scale_obj, chosen
    candidates = [(j, c) for j, c in cols if j not in exclude
                  and (long or not _ID_LIKE.match(c.name.strip()))]
    if scale is None:
        if not any(_label_item(_column_stats(c, s)) for _, c in candidates
                   for s in BUILTIN_SCALES.values()):
            coded = [c for _, c in candidates if _numeric_only(c)]
            if coded:
                raise _refuse_codes(source, coded[0], long, codes_file)
        scale_obj = _detect_scale(source, candidates, require_all=False, long=long)
    else:
        scale_obj = _get_scale(scale, source)
    stats = {j: _column_stats(c, scale_obj) for j, c in candidates}
    chosen = [(j, c) for j, c in candidates if _label_item(stats[j])]
    if not chosen:
        chosen = [(j, c) for j, c in candidates if _code_item(stats[j])]
        if chosen and not scale_obj.numeric_codes:
            raise _refuse_codes(source, chosen[0][1], long, codes_file)
        chosen = _drop_narrow_coded(source, chosen, scale_obj, notes, long)
    if not chosen:
        raise SurveyInputError(
            f"no item columns: no {what}'s answers are labels of scale {scale_obj.name!r} "
            f"({scale_obj.describe_valid()}); name the items with --items or the scale "
            f"with --scale", source)
    _check_item_count(source, chosen)
    # a column that holds another scale's labels is a mixed-scale survey
    chosen_idx = {j for j, _ in chosen}
    for j, c in candidates:
        if j in chosen_idx:
            continue
        for other in BUILTIN_SCALES.values():
            if other.name != scale_obj.name and _label_item(_column_stats(c, other)):
                head = f"item {c.name!r}: " if long else ""
                raise SurveyInputError(
                    f"{head}mixed scales: answers are labels of scale {other.name!r}, while "
                    f"{what} {chosen[0][1].name!r} uses {scale_obj.name!r}; analyse one "
                    f"scale at a time with --items and --scale", source,
                    None if long else 1, None if long else c.name)
    if not long:
        chosen = _unanswered_items(source, chosen, candidates, stats, notes)
    _note_other_not_applicable(source, chosen, scale_obj, notes)
    return scale_obj, chosen


def _note_other_not_applicable(source: str, chosen, scale: Scale, notes: "list | None") -> None:
    """Say which answers besides "N/A" itself were counted under n/a: a decline ("Prefer not
    to say") or a short mark ("NA", "-"), with how many in which item. Both routes come
    here (:func:`_choose_items`), so both say it alike."""
    if notes is None:
        return
    said = {normalize_answer(t): t for t in SHORT_NOT_APPLICABLE + DECLINED
            if scale.match(t, accept_codes=False) == Scale.NOT_APPLICABLE}
    found: dict = {}
    for _, c in chosen:
        for text, cnt in zip(c.cats, c.counts()):
            key = normalize_answer(text)
            if cnt and key in said:
                found.setdefault(key, {}).setdefault(c.name, 0)
                found[key][c.name] += int(cnt)
    if not found:
        return
    parts = []
    for key, per in found.items():
        where = ", ".join(f"{n} in {name!r}" for name, n in per.items())
        why = "declined to answer" if said[key] in DECLINED else "a mark for not applicable"
        parts.append(f"{said[key]!r} ({why}): {where}")
    notes.append(f"{source}: counted under n/a (excluded from n, as 'N/A' is): "
                 + "; ".join(parts))


def choose_items_from_counts(source: str, columns, scale=None, items=None,
                             long: bool = False, fields: "list[str] | None" = None):
    """The scale and the items among columns known only by their answer counts.

    The rule :func:`read_survey` applies (:func:`_choose_items`), for a reader that
    tallies each column's answer texts instead of keeping the rows (the out-of-core
    count of :mod:`analysis.institution`), so that both routes take the same items.

    Parameters
    ----------
    source : str
        File named in messages.
    columns : list of (str, dict of str to int)
        Each candidate column (``long``: each item) with its count per answer text
        (``""`` for a blank cell), in file order; grouping columns left out.
    scale : str, Scale or None
        As :func:`read_survey` takes it (None: detected).
    items : list of str, optional
        Item names or patterns.
    long : bool
        The names are items of a long file, not columns.
    fields : list of str, optional
        Another name of each column that ``items`` may give (its statement text), as
        :func:`read_survey` takes a column by header or statement.

    Returns
    -------
    scale : Scale
    chosen : list of str
        The items, in the order of ``columns``.
    not_items : dict of str to str
        Every other column with the reason it is not an item.
    notes : list of str
    """
    cols = []
    for j, (name, texts) in enumerate(columns):
        cats = [str(t) for t in texts]
        col = _Column(str(name), cats, np.zeros(0, dtype=np.int64),   # counts alone:
                      fields[j] if fields else "")
        col.__dict__["_counts"] = np.array(list(texts.values()), dtype=np.int64)  # no rows
        cols.append((j, col))
    notes: list[str] = []
    scale_obj, chosen = _choose_items(source, [c.name for _, c in cols], cols, set(), scale,
                                      items, long=long, notes=notes)
    if scale is None:
        _note_no_neutral(scale_obj, notes)
    taken = {j for j, _ in chosen}
    places = _ItemPlaces.of(chosen)
    not_items = {c.name: _why_not_item(c, scale_obj, items, long, notes, j, places)
                 for j, c in cols if j not in taken}
    return scale_obj, [c.name for _, c in chosen], not_items, notes


@dataclass(frozen=True)
class _ItemPlaces:
    """The items taken, as :func:`_looks_like_an_item` compares a column with them: how many
    items have each header shape, and the index of the first and of the last item."""
    shapes: dict
    first: int
    last: int

    @classmethod
    def of(cls, items: list) -> "_ItemPlaces":
        """From (index, column) pairs; built once per file, not once per column."""
        shapes: dict = {}
        for _, c in items:
            shapes[_header_shape(c)] = shapes.get(_header_shape(c), 0) + 1
        idx = [i for i, _ in items]
        return cls(shapes, min(idx, default=0), max(idx, default=-1))


def _looks_like_an_item(j: int, col: _Column, scale: Scale, places: _ItemPlaces,
                        taken: bool = False) -> str:
    """How column ``j``, whose answers are codes of ``scale`` (numbers, or the labels a code
    map gave them), looks like an item in codes beside the items at ``places`` (``taken``:
    itself among them); ``""`` when it does not, as a respondent's attribute such as a year
    of study (1-4) or a section (1-3) beside 5-point items does not.

    It looks like one when its answers run from the scale's lowest code to its highest, when
    its header is shaped like an item's (``Q2`` among ``Q1``, ``Q3``: digits aside), or when it
    stands among the items (one before it and one after it). A small class may leave an
    item's end unanswered (2-5), so the span alone does not decide. Both routes and the code
    map's note ask here (:func:`_why_not_item`, :func:`_note_mapped_attributes`).
    """
    used = set()
    for t, n in zip(col.cats, col.counts()):
        m = scale.match(t, accept_codes=False) if n else None
        if n and m is None:
            m = scale.code_keys().get(code_key(t))
        if m is not None and m >= 0:
            used.add(m)
    if {0, scale.k - 1} <= used:
        return "numbers from the scale's lowest code to its highest"
    if places.shapes.get(_header_shape(col), 0) > int(taken):
        return "numbers among the scale's codes, and its name is like the items' names"
    if places.first < j < places.last:
        return "numbers among the scale's codes, and it stands among the items"
    return ""


#: Why a column of codes does not look like an item (:func:`_looks_like_an_item`), in words.
_UNLIKE = ("it does not look like an item: its answers do not run from the lowest code to the "
           "highest, and it is neither named like the items nor placed among them")
#: What such a column may be instead.
_ATTRIBUTE = "an attribute of the respondent (a year of study, a section)"


def _why_not_item(col: _Column, scale: Scale, items, long: bool, notes: list,
                  j: int = -1, places: "_ItemPlaces | None" = None) -> str:
    """Why :func:`_choose_items` left column ``j`` out, in words; ``places``: the items taken
    (:meth:`_ItemPlaces.of`)."""
    if items:
        return "not named by --items"
    if not long and (_ID_LIKE.match(col.name.strip()) or person_id_column([col.name]) == 0):
        return "an identifier column"         # (an email or a username too: pairing's ids)
    if any(repr(col.name) in n for n in notes):
        return "see the note"
    if _unanswered(_column_stats(col, scale)):
        return "no answer in any row"
    answers = [str(c) for c, n in zip(col.cats, col.counts()) if n and str(c).strip()]
    if answers and all(scale.matches_code(c) for c in answers):
        like = _looks_like_an_item(j, col, scale, places or _ItemPlaces.of([]))
        if not like:
            return f"its answers are numbers among the scale's codes, but {_UNLIKE}; taken for {_ATTRIBUTE}"
        reason = (f"its answers are {like}; if it is an item in numeric codes, which end means "
                  f"agreement is not known: {CODES_HINT}")
        note = f"column {col.name!r} is left out of the table: {reason}"
        if note not in notes:  # (both routes ask for the reason of a column once each)
            notes.append(note)
        return reason
    return f"its answers are not labels of scale {scale.name!r}"


def _unanswered_items(source, chosen, candidates, stats, notes):
    """Add the columns nobody answered (blank or not applicable throughout) that are
    named like the items (``Q2`` among ``Q1``, ``Q3``: digits aside, the same header).

    Such a column has no answer to recognise it by. Named like the items it is an item
    with n = 0 (every respondent missing or excluded); otherwise (``Comments``, an id, a
    date) it stays out, and a note says which and why. Nothing is left out silently.
    """
    shapes = {_header_shape(c) for _, c in chosen}
    taken = {j for j, _ in chosen}
    out = list(chosen)
    for j, c in candidates:
        if j in taken or not _unanswered(stats[j]):
            continue
        name = c.field or c.name
        if _header_shape(c) in shapes:
            out.append((j, c))
            why = f"column {name!r} has no answer in any row: counted as an item (n = 0)"
        else:
            why = (f"column {name!r} has no answer in any row, and its name is not like the "
                   f"items' names: not counted as an item (name it with --items to count it)")
        if notes is not None:
            notes.append(f"{source}: {why}")
    out.sort(key=lambda t: t[0])
    _check_item_count(source, out)
    return out


def _header_shape(col: _Column) -> str:
    """A header with every run of digits replaced by ``#`` (``Q12_3`` -> ``q#_#``)."""
    return re.sub(r"\d+", "#", normalize_answer(col.field or col.name))


def _drop_narrow_coded(source, chosen, scale, notes, long):
    """Leave out a coded column holding only codes 1 and 2 among items using three or more.

    In a numeric export, a question such as "Which section?" coded 1/2 is all codes of
    a five-point scale too; it is reported in the notes, not taken as an item.
    """
    if scale.k < 4 or long:
        return chosen
    used = {j: {_code_text(t) for t, cnt in zip(c.cats, c.counts()) if cnt and t.strip()
                and not _is_na_text(t)} for j, c in chosen}
    if max((len(u) for u in used.values()), default=0) < 3:
        return chosen
    keep = []
    for j, c in chosen:
        if used[j] == {"1", "2"}:
            if notes is not None:
                notes.append(f"{source}: column {(c.field or c.name)!r} holds only codes 1 "
                             f"and 2 while other items use more: read as a question of its own (e.g. a section), not an "
                             f"item; name it with --items to take it as one")
        else:
            keep.append((j, c))
    return keep


def _code_text(text: str) -> str:
    from .codebook import Codebook
    return Codebook.key(text)


def _check_item_count(source: str, chosen: list) -> None:
    if len(chosen) > MAX_ITEMS:
        raise SurveyInputError(f"{len(chosen)} item columns; at most {MAX_ITEMS} are analysed "
                               f"at once (choose some with --items)", source)


def _get_scale(scale, source) -> Scale:
    return get_scale(scale)          # ValueError lists the built-in names


def _detect_scale(source, cols, require_all: bool, long: bool = False) -> Scale:
    """The built-in scale whose labels every item-like column uses."""
    what = "item" if long else "column"
    per_col = []
    for j, c in cols:
        fits, empty = {}, True
        for s in BUILTIN_SCALES.values():
            st = _column_stats(c, s)
            empty = empty and _unanswered(st)
            if _label_item(st):
                fits[s.name] = st[1] / st[0]
        if not fits and require_all and not empty:     # an item nobody answered fits any
            raise SurveyInputError(
                f"{'item ' + repr(c.name) + ': ' if long else ''}answers are not labels of any "
                f"built-in scale ({', '.join(BUILTIN_SCALES)}); give --scale (a name or a "
                ".toml file)", source, None if long else 1, None if long else c.name)
        if fits:
            per_col.append((c.name, fits))
    if not per_col or not any(f for _, f in per_col):
        raise SurveyInputError(
            "no item columns: no column's answers are labels of a built-in scale "
            f"({', '.join(BUILTIN_SCALES)}); give --scale (a name or a .toml file), or, "
            "for answer codes, --codes (a .qsf, .lss or .toml code map)", source)
    common = None
    for name, fits in per_col:
        common = set(fits) if common is None else common & set(fits)
    if not common:
        a = per_col[0]
        for b in per_col[1:]:
            if not set(a[1]) & set(b[1]):
                raise SurveyInputError(
                    f"mixed scales: {what} {a[0]!r} uses {sorted(a[1]) or 'no known scale'}, "
                    f"{what} {b[0]!r} uses {sorted(b[1]) or 'no known scale'}; analyse one "
                    f"scale at a time with --items and --scale", source,
                    None if long else 1, None if long else b[0])
        raise SurveyInputError("mixed scales: no one scale fits every item column", source)
    order = list(BUILTIN_SCALES)

    def score(name):
        return (-sum(f[name] for _, f in per_col if name in f),
                BUILTIN_SCALES[name].k, order.index(name))
    return BUILTIN_SCALES[min(common, key=score)]


def _lut(scale: Scale, cats: list[str]) -> np.ndarray:
    lut = np.empty(len(cats), dtype=np.int8)
    for i, text in enumerate(cats):
        m = scale.match(text)
        lut[i] = _NO_MATCH if m is None else m
    return lut


def _map_column(source, scale, name, cats, codes, rows, unknown):
    """Scale positions of one column's answers; unknown answers raise or become UNKNOWN."""
    a = _lut(scale, cats)[codes]
    unknowns: list[UnknownAnswer] = []
    bad = a == _NO_MATCH
    if bad.any():
        where = np.flatnonzero(bad)
        if not scale.numeric_codes:
            for i in where:
                text = cats[codes[i]]
                if scale.matches_code(text) and _numeric_only(
                        _Column(name, [text], np.zeros(1, dtype=np.int64))):
                    raise SurveyInputError(
                        f"numeric answer {text!r}: which end of the numbering means "
                        f"agreement is not known; {CODES_HINT}", source, int(rows[i]), name)
        if unknown == "error":
            i = int(where[0])
            text = cats[codes[i]]
            shown = repr(text) if len(text) <= 60 else repr(text[:57]) + "..."
            raise SurveyInputError(
                f"answer {shown} is not on scale {scale.name!r}; valid labels: "
                f"{scale.describe_valid()} (or use --unknown-as-missing)",
                source, int(rows[i]), name)
        unknowns = [UnknownAnswer(int(rows[i]), name, cats[codes[i]]) for i in where]
        a[bad] = UNKNOWN
    return a, unknowns


def _match(source, scale, item_cols, rows, unknown):
    answers = np.empty((len(rows), len(item_cols)), dtype=np.int8, order="F")   # columns contiguous
    unknowns: list[UnknownAnswer] = []
    for k, (_, col) in enumerate(item_cols):
        answers[:, k], found = _map_column(source, scale, col.name, col.cats, col.codes, rows,
                                           unknown)
        unknowns.extend(found)
    unknowns.sort(key=lambda u: (u.row, u.column))
    return answers, unknowns


# ---------------------------------------------------------------------------
# long shape
# ---------------------------------------------------------------------------
def _questionnaire_order(resp_code: np.ndarray, item_code: np.ndarray, nitem: int) -> list[int]:
    """Item codes in questionnaire order, from the order of each respondent's rows.

    First appearance alone misorders items when the first respondents skipped one (a
    long export often leaves unanswered items out): item B answered only from the
    second respondent on would come after C. Each respondent's rows say "A before B";
    these precedences are merged (Kahn's algorithm, ties by first appearance). Rows
    that contradict each other fall back to first appearance.
    """
    if nitem <= 1:
        return list(range(nitem))
    order = np.argsort(resp_code, kind="stable")
    r, i = resp_code[order], item_code[order]
    same = (r[1:] == r[:-1]) & (i[1:] != i[:-1])
    pairs = np.unique(i[:-1][same] * nitem + i[1:][same])
    succ: list[list[int]] = [[] for _ in range(nitem)]
    indeg = np.zeros(nitem, dtype=np.int64)
    for pr in pairs.tolist():
        a, b = divmod(pr, nitem)
        succ[a].append(b)
        indeg[b] += 1
    ready = [k for k in range(nitem) if indeg[k] == 0]
    heapq.heapify(ready)
    out = []
    while ready:
        k = heapq.heappop(ready)
        out.append(k)
        for b in succ[k]:
            indeg[b] -= 1
            if indeg[b] == 0:
                heapq.heappush(ready, b)
    if len(out) != nitem:          # contradictory orders: keep first appearance
        return list(range(nitem))
    return out


def _refuse_two_groups(source, col, resp_code, resp_ids, first_idx, rows) -> None:
    """Raise at the first row (in file order) whose grouping value is not a spelling of the
    one on its respondent's first row (:func:`analysis.scales.two_groups_message`)."""
    key = pd.factorize(pd.Series([normalize_answer(str(c)) for c in col.cats], dtype=object))[0]
    at = key[col.codes]
    bad = np.flatnonzero(at != at[first_idx[resp_code]])
    if bad.size:
        i = int(bad[np.argmin(rows[bad])])
        first = col.cats[col.codes[first_idx[resp_code[i]]]]
        raise SurveyInputError(two_groups_message(str(resp_ids[resp_code[i]]), col.name, first,
                                                  col.cats[col.codes[i]]),
                               source, int(rows[i]), col.name)


def _build_long(raw: _Raw, scale, items, unknown, group, reverse, respondents):
    source = raw.source
    ri, ii, ai = (_find(raw.header, _LONG_RESP), _find(raw.header, _LONG_ITEM),
                  _find(raw.header, _LONG_ANSWER))
    for idx, what, names in ((ri, "respondent", _LONG_RESP), (ii, "item", _LONG_ITEM),
                             (ai, "answer", _LONG_ANSWER)):
        if idx is None:
            raise SurveyInputError(f"long shape needs a {what} column (one of {list(names)}); "
                                   f"header is {raw.header!r}", source, 1)
    rows = raw.row_of(np.arange(raw.nrows))
    rc, ic, ac = raw.columns[ri], raw.columns[ii], raw.columns[ai]
    rkeys = np.array([x.strip() for x in rc.cats], dtype=object)
    blank_r = rkeys[rc.codes] == ""
    if blank_r.any():
        i = int(np.flatnonzero(blank_r)[0])
        raise SurveyInputError("blank respondent id", source, int(rows[i]), rc.name)
    ikeys = np.array([x.strip() for x in ic.cats], dtype=object)
    blank_i = ikeys[ic.codes] == ""
    if blank_i.any():
        i = int(np.flatnonzero(blank_i)[0])
        raise SurveyInputError("blank item name", source, int(rows[i]), ic.name)
    resp_code, resp_ids = pd.factorize(pd.Series(rkeys[rc.codes]), sort=False)
    item_code, item_names = pd.factorize(pd.Series(ikeys[ic.codes]), sort=False)
    if len(item_names) > MAX_COLUMNS:         # as many as a wide file's columns, at most
        raise SurveyInputError(f"{len(item_names)} distinct items; at most {MAX_COLUMNS} are "
                               f"read", source, None, ic.name)
    perm = _questionnaire_order(resp_code, item_code, len(item_names))
    inv = np.empty(len(perm), dtype=np.int64)
    inv[perm] = np.arange(len(perm))
    item_code = inv[item_code]
    item_names = [str(item_names[k]) for k in perm]
    nresp, nitem = len(resp_ids), len(item_names)
    # choose items among the item names, by pattern or by detection
    # each item's answers, split once (a scan per item was quadratic in the items)
    by_item = np.argsort(item_code, kind="stable")
    parts = np.split(ac.codes[by_item], np.cumsum(np.bincount(item_code, minlength=nitem))[:-1])
    per_item = [(k, _Column(item_names[k], ac.cats, parts[k])) for k in range(nitem)]
    notes = list(raw.notes)
    scale_obj, chosen = _choose_items(source, item_names, per_item, set(), scale, items,
                                      long=True, notes=notes)
    wanted = [k for k, _ in chosen]
    pos = {k: p for p, k in enumerate(wanted)}
    sel = np.isin(item_code, wanted)
    r_sel, i_sel, rows_sel = resp_code[sel], np.array([pos[k] for k in item_code[sel]],
                                                      dtype=np.int64), rows[sel]
    flat = r_sel * len(wanted) + i_sel
    order = np.argsort(flat, kind="stable")
    dup = np.flatnonzero(np.diff(flat[order]) == 0)
    if dup.size:           # the repeat whose second row comes first in the file
        later = order[dup + 1]
        i = int(later[np.argmin(rows_sel[later])])
        raise SurveyInputError(
            f"respondent {resp_ids[r_sel[i]]!r} answers item {item_names[wanted[i_sel[i]]]!r} "
            f"twice", source, int(rows_sel[i]), ac.name)
    a, unknowns = _map_column(source, scale_obj, ac.name, ac.cats, ac.codes[sel], rows_sel,
                              unknown)
    answers = np.full((nresp, len(wanted)), BLANK, dtype=np.int8)
    answers[r_sel, i_sel] = a
    counts = label_counts(answers, scale_obj.k)
    _scale_notes(scale_obj, counts, scale is None, notes)
    first_idx = np.full(nresp, np.iinfo(np.int64).max, dtype=np.int64)
    np.minimum.at(first_idx, resp_code, np.arange(raw.nrows))
    first_rows = raw.row_of(first_idx)
    groups = {}
    for g in _as_list(group):
        why = platforms.long_column_refusal("--group", g, raw.header)
        if why:
            raise SurveyInputError(why, source)
        col = raw.columns[column_index(source, raw.header, g)]
        _refuse_two_groups(source, col, resp_code, resp_ids, first_idx, rows)
        groups[platforms.spaced_name(col.name)] = np.array(col.cats, dtype=object)[
            col.codes][first_idx]
    names = [item_names[k] for k in wanted]
    places = _ItemPlaces.of(chosen)
    data = SurveyData(source=source, shape="long", scale=scale_obj, items=names,
                      item_texts=list(names), answers=answers, rows=first_rows,
                      groups=groups, unknown_answers=unknowns,
                      reverse=_resolve_reverse(source, names, reverse),
                      other_columns=[item_names[k] for k in range(nitem) if k not in wanted],
                      not_item_reasons={item_names[k]: _why_not_item(
                          per_item[k][1], scale_obj, items, True, notes, k, places)
                          for k in range(nitem) if k not in wanted},
                      comments=list(raw.comments), notes=notes)
    _narrower_items(data, counts, scale is None)
    return _declare(data, respondents)
