"""Reading the cell values of one worksheet of an .xlsx workbook, fast and safely.

openpyxl's read-only worksheet builds objects for every cell it parses (an inline string
becomes a rich-text tree), about 18 microseconds a cell: 9 s for a sheet of 50,000 rows
of 9 answers. :func:`sheet_values` parses the sheet's XML with expat directly and keeps
only the values, the way openpyxl's ``iter_rows(values_only=True)`` gives them (shared and
inline strings, numbers, booleans, error codes, dates by the cell's number format), and
takes the shared strings, the date formats and the epoch from the workbook openpyxl
loaded. The XML may declare no entity (expansion and external entities are refused, as
defusedxml refuses them, with its exceptions).

Where openpyxl drops or misreads without a word, this reader refuses with
:class:`SheetFault`, naming the row and cell: a row written out of order or twice (openpyxl
skips it), a cell written twice in a row (the last one won), a negative shared-string index
(counted from the end), and a cell its type cannot hold (a bare ValueError or IndexError).
"""
from __future__ import annotations

import re
from xml.parsers import expat

__all__ = ["SheetFault", "load_read_only", "sheet_values"]

_COLUMN = re.compile(r"[A-Za-z]{1,4}")      # XFD is Excel's last; 4 letters reach 475,254
_NUMBERS: dict = {}            # column letters -> column number, filled as met


def load_read_only(source):
    """``openpyxl.load_workbook(source, read_only=True, data_only=True)`` without its scan of
    each sheet for a ``<dimension>`` record: a sheet that has none (openpyxl writes none in
    some modes) was parsed to its end once per sheet, before any row was read (half the time
    of reading a sheet of 50,000 rows). Nothing here uses the record: every cell is read."""
    import openpyxl
    from openpyxl.worksheet._read_only import ReadOnlyWorksheet
    size = ReadOnlyWorksheet.__dict__.get("_get_size")
    if size is not None:
        ReadOnlyWorksheet._get_size = lambda self: None
    try:
        return openpyxl.load_workbook(source, read_only=True, data_only=True)
    finally:
        if size is not None:
            ReadOnlyWorksheet._get_size = size


def _column_number(ref: str) -> int:
    """1-based column of a cell reference (``"AB12"`` -> 28). A reference that does not
    start with column letters raises ValueError, as in openpyxl."""
    letters = ref.rstrip("0123456789")
    n = _NUMBERS.get(letters)
    if n is None:
        if not _COLUMN.fullmatch(letters):
            raise ValueError(f"cell reference {ref[:20]!r} names no column")
        n = 0
        for ch in letters.upper():
            n = n * 26 + ord(ch) - 64
        _NUMBERS[letters] = n
    return n


_MAIN = "http://schemas.openxmlformats.org/spreadsheetml/2006/main"
"""The worksheet's namespace (openpyxl's ``SHEET_MAIN_NS``): elements of any other are not cells."""


def _local(name: str) -> str:
    """The local name of an element of the worksheet's namespace, "" for any other (expat gives
    ``namespace}name``): a ``<c>`` of a foreign namespace is no cell, as openpyxl reads it."""
    namespace, _, local = name.rpartition("}")
    return local if namespace == _MAIN else ""


def _refuse_entities(*_args):
    from defusedxml import EntitiesForbidden
    raise EntitiesForbidden("entity declared in a worksheet", None, None, None, None, None)


def _refuse_external(*_args):
    from defusedxml import ExternalReferenceForbidden
    raise ExternalReferenceForbidden(None, None, None, None)


class SheetFault(ValueError):
    """A worksheet whose XML cannot be read as written: a cell that is not what its type
    says, a row out of order or repeated, a damaged zip member.

    Attributes
    ----------
    row : int or None
        The sheet's row (1-based) the fault is in, None when it is in no row.
    cell : str or None
        The cell's reference (``"B10"``), None for a fault of a whole row or part.
    reason : str
        What is wrong, in words.
    """

    def __init__(self, row: "int | None", cell: "str | None", reason: str):
        super().__init__(reason)
        self.row, self.cell, self.reason = row, cell, reason


def _letters(column: int) -> str:
    """Column letters of a 1-based column number (28 -> ``"AB"``)."""
    out = ""
    while column > 0:
        column, rest = divmod(column - 1, 26)
        out = chr(65 + rest) + out
    return out


class _Cells:
    """The expat handlers: the values of each row, as openpyxl's parser reads them."""

    def __init__(self, wb, ws, max_columns: int):
        self.strings = ws._shared_strings
        self.dates, self.spans = wb._date_formats, wb._timedelta_formats
        self.epoch, self.max_columns = wb.epoch, max_columns
        self.rows: list = []            # (row number, {column: value}) ready to be yielded
        self.row, self.cells, self.column = 0, {}, 0
        self.kind = self.style = None
        self.text: "list | None" = None      # the characters of a <v> or an inline <t>
        self.value = None
        self.inline = self.phonetic = 0

    def start(self, name, attrs):
        name = _local(name)
        if name == "c":
            ref = attrs.get("r")
            try:
                self.column = _column_number(ref) if ref else self.column + 1
            except ValueError as e:
                raise SheetFault(self.row, None, str(e)) from None
            named = ref[len(ref.rstrip("0123456789")):] if ref else ""
            if named and int(named) != self.row:  # (openpyxl puts it in row `named`, over that row's own)
                raise SheetFault(self.row, None, f"the cell {ref[:20]!r} is written inside row {self.row} of "
                                 "the sheet's XML; which row holds it is not known")
            if self.column > self.max_columns:
                raise _TooWide(self.column, self.row)
            if self.column in self.cells:
                raise SheetFault(self.row, self._ref(), "the cell is written twice in the "
                                 "sheet's XML; which value holds is not known")
            self.kind, style = attrs.get("t", "n"), attrs.get("s", 0) or 0
            try:
                self.style = int(style)
            except ValueError:
                raise self._fault(f"its style s={style[:20]!r} is not a number") from None
            self.value, self.inline = None, 0
        elif name == "v" or (name == "t" and self.inline and not self.phonetic):
            self.text = []
        elif name == "is" and self.kind == "inlineStr":  # (another type's <is> is ignored, as by openpyxl)
            self.inline, self.value = 1, ""
        elif name == "rPh":
            self.phonetic += 1
        elif name == "row":
            self._next_row(attrs.get("r"))

    def _next_row(self, r: "str | None") -> None:
        """Start the row numbered ``r`` (the next one when None). Rows are read in the order
        the XML gives them: a number not above the last one (a row out of order or repeated,
        which openpyxl drops unsaid) is refused, as is one that is no row number."""
        try:
            number = int(r) if r else self.row + 1
        except ValueError:
            raise SheetFault(self.row + 1, None, f"row number r={r[:20]!r} is not a "
                             "number") from None
        if number < 1:
            raise SheetFault(None, None, f"a row is numbered {number}; rows are numbered "
                             "from 1")
        if number <= self.row:
            how = "twice" if number == self.row else "again or out of order"
            raise SheetFault(number, None, f"the sheet's XML writes this row {how} (after "
                             f"row {self.row}); rows are read only in order, each once: "
                             f"re-save the sheet in Excel or export it as CSV")
        self.row, self.cells, self.column = number, {}, 0

    def _ref(self) -> str:
        return f"{_letters(self.column)}{self.row}"

    def _fault(self, reason: str) -> SheetFault:
        return SheetFault(self.row, self._ref(), reason)

    def chars(self, data):
        if self.text is not None:
            self.text.append(data)

    def end(self, name):
        name = _local(name)
        if name == "v" and self.text is not None:
            if self.kind != "inlineStr":  # an inline string's value is its <is> alone, as openpyxl reads it
                self.value = "".join(self.text) or None
            self.text = None
        elif name == "t" and self.text is not None:
            self.value += "".join(self.text)
            self.text = None
        elif name == "rPh":
            self.phonetic -= 1
        elif name == "c":
            self.cells[self.column] = self._typed()
        elif name == "row":
            self.rows.append((self.row, self.cells))

    def _typed(self):
        """The cell's value by its type (openpyxl's ``WorkSheetParser.parse_cell``, values
        only); a value its type cannot hold raises :class:`SheetFault` naming the cell."""
        value, kind = self.value, self.kind
        if value is None or kind == "inlineStr":
            return value if kind == "inlineStr" else None
        if kind == "n":
            real = "." in value or "e" in value or "E" in value
            try:
                number = float(value) if real else int(value)
            except ValueError:
                raise self._fault(f"its value {value[:20]!r} is not a number") from None
            if self.style in self.dates:
                from openpyxl.utils.datetime import from_excel
                try:
                    return from_excel(number, self.epoch, timedelta=self.style in self.spans)
                except (OverflowError, ValueError):
                    return "#VALUE!"
            return number
        if kind == "s":
            try:
                index = int(value)
            except ValueError:
                raise self._fault(f"its shared-string index {value[:20]!r} is not a "
                                  "number") from None
            if not 0 <= index < len(self.strings):     # (a negative index would count from the end)
                raise self._fault(f"shared string {index} does not exist (the workbook has "
                                  f"{len(self.strings)})")
            return self.strings[index]
        if kind == "b":
            if value.strip() not in ("0", "1"):
                raise self._fault(f"its boolean value {value[:20]!r} is not 0 or 1")
            return value.strip() == "1"
        if kind == "d":
            from openpyxl.utils.datetime import from_ISO8601
            try:
                return from_ISO8601(value)
            except ValueError:
                raise self._fault(f"its date {value[:30]!r} is not an ISO 8601 date") from None
        return value                    # "str" (a formula's text), "e" (an error code)


class _TooWide(Exception):
    """A cell beyond the column cap (its column number in ``args[0]``, its row in ``args[1]``)."""


def sheet_values(wb, ws, max_columns: int, too_wide):
    """The rows of a read-only worksheet as tuples of values, as openpyxl's
    ``ws.iter_rows(values_only=True)`` yields them after ``ws.reset_dimensions()``: a row
    the XML leaves out is an empty tuple, cells missing in a row are None, every row as
    long as its last cell.

    ``too_wide(column, row)`` is called, and must raise, at a cell beyond column
    ``max_columns``, before its row is built (a hostile ``r="ZZZ1"`` would otherwise ask for
    18,278 cells a row).

    Raises
    ------
    SheetFault
        A cell its type cannot hold, a cell or row written twice, a row out of order, a zip
        member whose compressed data is damaged.
    defusedxml.EntitiesForbidden, defusedxml.ExternalReferenceForbidden
        The XML declares entities or refers to an external one.
    xml.parsers.expat.ExpatError
        Malformed XML.
    """
    cells = _Cells(wb, ws, max_columns)
    parser = expat.ParserCreate(namespace_separator="}")
    parser.buffer_text = True
    parser.StartElementHandler, parser.EndElementHandler = cells.start, cells.end
    parser.CharacterDataHandler = cells.chars
    parser.EntityDeclHandler = parser.UnparsedEntityDeclHandler = _refuse_entities
    parser.ExternalEntityRefHandler = _refuse_external
    parser.SkippedEntityHandler = _refuse_entities  # an entity no declaration defines (an external DTD's)
    parser.SetParamEntityParsing(expat.XML_PARAM_ENTITY_PARSING_NEVER)
    counter = [1]
    with ws._get_source() as src:
        while True:
            chunk = _read(src, getattr(ws, "_worksheet_path", "the sheet's part"))
            try:
                parser.Parse(chunk, not chunk)
            except _TooWide as e:
                too_wide(*e.args)
                raise
            except Exception:
                yield from _ready(cells, counter)   # the rows before the fault, so that the
                raise                               # error names the row it is in
            yield from _ready(cells, counter)
            if not chunk:
                return


def _read(src, part: str) -> bytes:
    """The next MiB of a zip member; a member whose compressed data or checksum is damaged
    raises :class:`SheetFault` naming it (zipfile and zlib name only their own error)."""
    import zipfile
    import zlib
    try:
        return src.read(1 << 20)
    except (zipfile.BadZipFile, zlib.error, EOFError) as e:
        raise SheetFault(None, None, f"the zip member {part} is damaged ({e or type(e).__name__}"
                         f"): its compressed data or checksum is wrong") from None


def _ready(cells: _Cells, counter: list):
    """The rows parsed so far, as tuples, each row the XML leaves out as ``()``; ``counter``
    holds the next row number to yield (rows come in order: :meth:`_Cells._next_row`)."""
    for number, row in cells.rows:
        while counter[0] < number:
            counter[0] += 1
            yield ()
        counter[0] += 1
        yield tuple(row.get(c) for c in range(1, max(row, default=0) + 1))
    cells.rows = []
