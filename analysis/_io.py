"""File input and output shared by the analysis modules.

- :func:`read_bytes` -- a file's bytes, with one-line errors for missing/unreadable files.
- :func:`read_toml` -- a TOML file, with one-line errors naming the file.
- :func:`spreadsheet_safe` -- neutralise a CSV cell that a spreadsheet would run as a formula.
- :func:`check_output` -- refuse an output path that cannot take a file (before the work).
- :func:`atomic_write` -- write to a temporary file in the same folder, then rename.
- :func:`sniff_delimiter` -- a CSV text's delimiter, the one rule of both survey routes.
"""
from __future__ import annotations

import csv
import io
import os
import stat
from pathlib import Path

from .errors import SurveyInputError


#: Largest input file read (a survey export, table or TOML file).
MAX_INPUT_BYTES = 1 << 30


def is_regular_file(path: "str | Path") -> bool:
    """True for an existing regular file (not a folder, FIFO or device such as /dev/zero)."""
    try:
        return stat.S_ISREG(os.stat(path).st_mode)
    except (OSError, ValueError):
        return False


def read_bytes(path: "str | Path") -> bytes:
    """The bytes of ``path``; SurveyInputError (naming the file) for a missing or unreadable
    file, one that is not a regular file (a FIFO would block, /dev/zero never end), or one
    larger than :data:`MAX_INPUT_BYTES`."""
    p = Path(path)
    try:
        st = os.stat(p)
    except FileNotFoundError:
        raise SurveyInputError("no such file", str(p)) from None
    except (OSError, ValueError) as e:
        raise SurveyInputError(f"cannot read: {getattr(e, 'strerror', None) or e}",
                               str(p)) from None
    if stat.S_ISDIR(st.st_mode):
        raise SurveyInputError("is a folder, not a file", str(p))
    if not stat.S_ISREG(st.st_mode):
        raise SurveyInputError("not a regular file (a pipe or device is not read)", str(p))
    if st.st_size > MAX_INPUT_BYTES:
        raise SurveyInputError(f"{st.st_size} bytes; at most {MAX_INPUT_BYTES} are read",
                               str(p))
    try:
        return p.read_bytes()
    except OSError as e:
        raise SurveyInputError(f"cannot read: {e.strerror}", str(p)) from None


#: Largest TOML file read (claims and scale files are a few kilobytes).
MAX_TOML_BYTES = 1 << 20


def read_toml(path: "str | Path") -> dict:
    """A TOML file as a dict; SurveyInputError (naming the file) on any problem.

    Files above :data:`MAX_TOML_BYTES`, nesting too deep for the parser, and
    integers too long to convert are refused like syntax errors.
    """
    import tomllib                  # here: its import compiles regular expressions
    raw = read_bytes(path)
    if len(raw) > MAX_TOML_BYTES:
        raise SurveyInputError(f"{len(raw)} bytes; a TOML file may have at most "
                               f"{MAX_TOML_BYTES}", str(path))
    try:
        return tomllib.loads(raw.decode("utf-8-sig"))      # Notepad may write a BOM
    except UnicodeDecodeError as e:
        raise SurveyInputError(f"not valid UTF-8 (byte offset {e.start})", str(path)) from None
    except tomllib.TOMLDecodeError as e:
        raise SurveyInputError(f"invalid TOML: {e}", str(path)) from None
    except RecursionError:
        raise SurveyInputError("invalid TOML: arrays or tables nested too deeply",
                               str(path)) from None
    except ValueError as e:              # e.g. an integer past Python's digit limit
        raise SurveyInputError(f"invalid TOML: {str(e).split(';')[0]}", str(path)) from None


_FORMULA_START = ("=", "+", "-", "@", "\t", "\r")


def spreadsheet_safe(cell) -> str:
    """A CSV cell a spreadsheet will not run as a formula: text starting with
    ``=``, ``+``, ``-``, ``@``, tab or CR gets a leading apostrophe (OWASP's advice)."""
    text = str(cell)
    return "'" + text if text.startswith(_FORMULA_START) else text


def check_output(path: "str | Path", flag: str = "") -> Path:
    """Refuse an output path that cannot take a file, before any work is done.

    Parameters
    ----------
    path : str or Path
    flag : str
        The command-line name of the option (``-o/--output``), for the message.

    Raises
    ------
    SurveyInputError
        ``path`` is an existing folder (or other non-regular file), or its folder
        does not exist.
    """
    p = Path(path)
    what = f"{flag}: " if flag else ""
    if os.fspath(path).endswith(("/", os.sep)):
        raise SurveyInputError(f"{what}ends with a slash; give a file name to write", os.fspath(path))
    if p.is_dir():
        raise SurveyInputError(f"{what}is a folder; give a file name to write", str(p))
    if p.exists() and not p.is_file():
        raise SurveyInputError(f"{what}is not a regular file", str(p))
    folder = p.parent if str(p.parent) else Path(".")
    if not folder.is_dir():
        raise SurveyInputError(f"{what}output folder does not exist", str(p))
    return p


def atomic_write(path: "str | Path", data: "str | bytes", encoding: str = "utf-8") -> Path:
    """Write ``data`` to ``path`` so that readers see either nothing or the whole file, with the
    mode a plain ``open`` would give (:func:`solver.files.replace_atomically`, the one place where
    the project's atomic writes are done).

    Raises
    ------
    SurveyInputError
        The path is a folder, the folder does not exist or cannot be written.
    """
    from solver.files import replace_atomically

    p = check_output(path)
    raw = data.encode(encoding) if isinstance(data, str) else data
    try:
        replace_atomically(p, lambda fh: fh.write(raw), binary=True)
    except OSError as e:
        raise SurveyInputError(f"cannot write: {e.strerror or type(e).__name__}", str(p)) from None
    return p


_DELIMITERS = (",", ";", "\t")


def sniff_delimiter(head_text: str) -> tuple[str, list[list[str]]]:
    """The delimiter (comma, semicolon or tab) and the first few records.

    The delimiter that splits the header into the most fields wins, among those that
    split the next records into as many (quotes respected, so a question text with
    commas in a semicolon file, or with semicolons in a comma file, does not mislead);
    ties go to the comma.
    """
    best = None
    for sep in _DELIMITERS:
        recs = []
        try:
            for rec in csv.reader(io.StringIO(head_text, newline=""), delimiter=sep):
                if rec and any(c.strip() for c in rec):
                    recs.append(rec)
                if len(recs) >= 6:
                    break
        except csv.Error:             # not text a CSV reader takes: pandas will say what
            pass
        if not recs:
            continue
        width = len(recs[0])
        consistent = width > 1 and all(len(r) == width for r in recs[1:5])
        key = (consistent, width)
        if best is None or key > best[0]:
            best = (key, sep, recs[:4])
    if best is None:
        return ",", []
    return best[1], best[2]


class ShortRecords:
    """The records of a CSV text with fewer fields than its header, found in one pass over
    its bytes in chunks (numpy on each chunk: no per-record Python loop), so that both
    survey routes can say which rows a reader padded with blank cells.

    A record's fields are its delimiters outside quotes plus one: a byte is inside a quoted
    cell when an odd number of ``"`` come before it (an escaped ``""`` counts twice). A record
    holding no cell text (an empty line, ``,,``) is not listed: it is no respondent.

    Parameters
    ----------
    sep : str
        The delimiter (one ASCII character).
    newline : bytes
        The byte ending a record: ``b"\\n"`` (also for ``\\r\\n``) or ``b"\\r"``.

    Attributes
    ----------
    found : list of (int, int)
        (record number, fields) of each short record; the header is record 1, and every
        line ending outside quotes starts a new record (empty lines count).
    width : int
        Fields of the header (record 1).
    last : int
        The last record holding cell text.
    longer : int
        Records with more fields than the header (their values beyond it are looked at by
        :func:`refuse_values_beyond_header`).
    """

    def __init__(self, sep: str, newline: bytes = b"\n"):
        self.sep, self.newline = ord(sep), newline[-1]
        self.found: list = []
        self.width = self.last = self.longer = 0
        self._inside, self._seps, self._text, self._record = 0, 0, False, 1
        self._blank = b' \t\r\n"' + sep.encode("ascii")

    def feed(self, chunk: bytes) -> None:
        """Scan the next bytes of the text."""
        import numpy as np
        a = np.frombuffer(chunk, dtype=np.uint8)
        quotes = np.flatnonzero(a == 34)

        def outside(pos):
            if not len(quotes):
                return pos if not self._inside else pos[:0]
            return pos[(np.searchsorted(quotes, pos) + self._inside) % 2 == 0]
        ends = outside(np.flatnonzero(a == self.newline))
        seps = np.bincount(np.searchsorted(ends, outside(np.flatnonzero(a == self.sep))),
                           minlength=len(ends) + 1)
        seps[0] += self._seps
        starts = np.concatenate([[0], ends + 1])
        if len(ends) and not self.width:
            self.width = int(seps[0]) + 1
        for i in np.flatnonzero(seps[:len(ends)] + 1 < self.width).tolist():
            self._close(i, int(seps[i]) + 1, chunk[starts[i]:ends[i]])
        self.longer += int(np.count_nonzero(seps[:len(ends)] + 1 > self.width))
        for i in range(len(ends) - 1, -1, -1):      # the last record holding text, usually
            if self._holds_text(chunk[starts[i]:ends[i]]) or (i == 0 and self._text):
                self.last = self._record + i        # the chunk's last one
                break
        self._record += len(ends)
        tail = chunk[starts[-1]:]
        self._text = (self._text if not len(ends) else False) or self._holds_text(tail)
        self._seps = int(seps[-1])
        self._inside = (self._inside + len(quotes)) % 2

    def close(self) -> list:
        """The short records, once every byte was fed (a last record without a line end
        counted too)."""
        if self._text:
            self.last = self._record
            if self._seps + 1 < self.width:
                self.found.append((self._record, self._seps + 1))
            self.longer += self._seps + 1 > self.width
        self._text = False
        return self.found

    def _close(self, i: int, fields: int, body: bytes) -> None:
        if self._holds_text(body) or (i == 0 and self._text):
            self.found.append((self._record + i, fields))

    def _holds_text(self, body: bytes) -> bool:
        return bool(bytes(body).translate(None, delete=self._blank))


def short_records_note(source: str, short: list, width: int) -> "str | None":
    """The note naming the rows with fewer fields than the header (``short``: (spreadsheet
    row, fields)), one wording for both routes; None when there are none."""
    if not short:
        return None
    shown = ", ".join(f"row {r} has {n}" for r, n in short[:5])
    more = f", and {len(short) - 5} more" if len(short) > 5 else ""
    k = len(short)
    return (f"{source}: {k} row{'s' if k != 1 else ''} with fewer fields than the header's "
            f"{width} ({shown}{more}): the missing cells are read as blank answers (a line "
            f"break in an unquoted cell splits a record in two: check the export)")


def refuse_values_beyond_header(text, sep: str, width: int, source: str, skip: int = 0) -> None:
    """Raise when a CSV record holds a value beyond the header's last column: that value has
    no column, and reading it as one (DuckDB invents ``column3``) or leaving it out would
    both be silent. Empty fields there (a delimiter ending a line) are no values. The one rule
    of both survey routes, worded once.

    Parameters
    ----------
    text : file-like
        The CSV text from its header record (opened with ``newline=""``), read as a stream.
    sep : str
        The delimiter.
    width : int
        Fields of the header record.
    source : str
        The file, for the message.
    skip : int
        Lines above the header (comment lines), so that rows are numbered as a spreadsheet
        shows them.

    Raises
    ------
    SurveyInputError
        ``row R: N fields, but the header has W: value 'x' has no column``, or a record
        Python's csv module cannot read.
    """
    line = skip
    limit = csv.field_size_limit(1 << 30)       # pandas and DuckDB read fields of any size
    try:
        for rec in csv.reader(text, delimiter=sep):
            line += 1
            if len(rec) > width:
                extra = [c for c in rec[width:] if c.strip()]
                if extra:
                    raise SurveyInputError(
                        f"{len(rec)} fields, but the header has {width}: value "
                        f"{extra[0]!r} has no column", source, line)
    except csv.Error as e:
        raise SurveyInputError(f"not a well-formed CSV ({e})", source, line + 1) from None
    finally:
        csv.field_size_limit(limit)
