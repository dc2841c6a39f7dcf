"""Reading the cell values of one worksheet of an .xlsx workbook, fast and safely.

openpyxl's read-only worksheet builds objects for every cell it parses (an inline string
becomes a rich-text tree), about 18 microseconds a cell: 9 s for a sheet of 50,000 rows
of 9 answers. :func:`sheet_values` parses the sheet's XML with expat directly and keeps
only the values, the way openpyxl's ``iter_rows(values_only=True)`` gives them (shared and
inline strings, numbers, booleans, error codes, dates by the cell's number format), and
takes the shared strings, the date formats and the epoch from the workbook openpyxl
loaded. The XML may declare no entity (expansion and external entities are refused, as
defusedxml refuses them, with its exceptions).
"""
from __future__ import annotations

import re
from xml.parsers import expat

__all__ = ["load_read_only", "sheet_values"]

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
            self.column = _column_number(ref) if ref else self.column + 1
            if self.column > self.max_columns:
                raise _TooWide(self.column)
            self.kind, self.style = attrs.get("t", "n"), int(attrs.get("s", 0) or 0)
            self.value, self.inline = None, 0
        elif name == "v" or (name == "t" and self.inline and not self.phonetic):
            self.text = []
        elif name == "is" and self.kind == "inlineStr":  # (another type's <is> is ignored, as by openpyxl)
            self.inline, self.value = 1, ""
        elif name == "rPh":
            self.phonetic += 1
        elif name == "row":
            r = attrs.get("r")
            self.row = int(r) if r else self.row + 1
            self.cells, self.column = {}, 0

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
        only)."""
        value, kind = self.value, self.kind
        if value is None or kind == "inlineStr":
            return value if kind == "inlineStr" else None
        if kind == "n":
            number = float(value) if ("." in value or "e" in value or "E" in value) else int(value)
            if self.style in self.dates:
                from openpyxl.utils.datetime import from_excel
                try:
                    return from_excel(number, self.epoch, timedelta=self.style in self.spans)
                except (OverflowError, ValueError):
                    return "#VALUE!"
            return number
        if kind == "s":
            return self.strings[int(value)]
        if kind == "b":
            return bool(int(value))
        if kind == "d":
            from openpyxl.utils.datetime import from_ISO8601
            return from_ISO8601(value)
        return value                    # "str" (a formula's text), "e" (an error code)


class _TooWide(Exception):
    """A cell beyond the column cap (its column number in ``args[0]``)."""


def sheet_values(wb, ws, max_columns: int, too_wide):
    """The rows of a read-only worksheet as tuples of values, as openpyxl's
    ``ws.iter_rows(values_only=True)`` yields them after ``ws.reset_dimensions()``: a row
    the XML leaves out is an empty tuple, cells missing in a row are None, every row as
    long as its last cell.

    ``too_wide(column)`` is called, and must raise, at a cell beyond column ``max_columns``,
    before its row is built (a hostile ``r="ZZZ1"`` would otherwise ask for 18,278 cells a row).

    Raises
    ------
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
            chunk = src.read(1 << 20)
            try:
                parser.Parse(chunk, not chunk)
            except _TooWide as e:
                too_wide(e.args[0])
                raise
            except Exception:
                yield from _ready(cells, counter)   # the rows before the fault, so that the
                raise                               # error names the row it is in
            yield from _ready(cells, counter)
            if not chunk:
                return


def _ready(cells: _Cells, counter: list):
    """The rows parsed so far, as tuples, each row the XML leaves out as ``()``; ``counter``
    holds the next row number to yield."""
    for number, row in cells.rows:
        while counter[0] < number:
            counter[0] += 1
            yield ()
        if counter[0] == number:             # (a repeated row number is skipped, as openpyxl does)
            counter[0] += 1
            yield tuple(row.get(c) for c in range(1, max(row, default=0) + 1))
    cells.rows = []
