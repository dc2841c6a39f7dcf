"""Workbooks built byte by byte for the hostile-input tests (openpyxl + zipfile).

``workbook(rows)`` writes an ordinary .xlsx with openpyxl (inline strings); the other
helpers rewrite its first sheet's XML the way a careless or hostile writer would: a
``<dimension>`` record that understates the data, truncated XML, a DOCTYPE with an
external entity (XXE) or with nested entities (entity expansion).
"""
from __future__ import annotations

import io
import re
import zipfile

import openpyxl

SHEET = "xl/worksheets/sheet1.xml"
_DECL = re.compile(rb"^<\?xml[^>]*\?>")
_DIMENSION = re.compile(rb'<dimension ref="[^"]*"\s*/>')


def workbook(rows: list[list]) -> bytes:
    """An .xlsx whose first sheet holds ``rows`` (as openpyxl writes it)."""
    wb = openpyxl.Workbook()
    ws = wb.active
    for r in rows:
        ws.append(r)
    buf = io.BytesIO()
    wb.save(buf)
    return buf.getvalue()


def rewrite_sheet(data: bytes, edit) -> bytes:
    """The workbook with its first sheet's XML replaced by ``edit(xml_bytes)``."""
    zin = zipfile.ZipFile(io.BytesIO(data))
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as z:
        for info in zin.infolist():
            body = zin.read(info.filename)
            z.writestr(info.filename, edit(body) if info.filename == SHEET else body)
    return out.getvalue()


def with_dimension(data: bytes, ref: str) -> bytes:
    """Replace the sheet's ``<dimension ref=...>`` record (e.g. ``"A1:B3"``)."""
    return rewrite_sheet(data, lambda x: _DIMENSION.sub(f'<dimension ref="{ref}"/>'.encode(), x))


def truncated(data: bytes, keep: float = 0.5) -> bytes:
    """The sheet's XML cut after ``keep`` of its bytes (malformed XML)."""
    return rewrite_sheet(data, lambda x: x[:max(1, int(len(x) * keep))])


def with_entity(data: bytes, kind: str = "xxe") -> bytes:
    """A DOCTYPE declaring an external entity (``"xxe"``) or an expanding one
    (``"bomb"``), used in the first text cell."""
    if kind == "xxe":
        doctype = b'<!DOCTYPE w [<!ENTITY e SYSTEM "file:///etc/passwd">]>'
    else:
        defs = b'<!ENTITY e0 "lol">' + b"".join(
            b"<!ENTITY e%d \"%s\">" % (i, b"&e%d;" % (i - 1) * 10) for i in range(1, 9))
        doctype = b"<!DOCTYPE w [" + defs.replace(b"e8", b"e") + b"]>"

    def edit(x: bytes) -> bytes:
        body = _DECL.sub(b"", x).replace(b"<t>", b"<t>&e;", 1)
        return b'<?xml version="1.0"?>' + doctype + body
    return rewrite_sheet(data, edit)


_INLINE = re.compile(rb'<c ([^>]*?)t="inlineStr"([^>]*)><is><t[^>]*>(.*?)</t></is></c>', re.S)


def with_shared_strings(data: bytes) -> bytes:
    """The workbook with its first sheet's inline strings moved to a shared-strings part
    (``t="s"`` cells holding an index), as Excel saves text."""
    table: list[bytes] = []

    def share(m):
        table.append(m.group(3))
        return b'<c ' + m.group(1) + b't="s"' + m.group(2) + b'><v>%d</v></c>' % (len(table) - 1)
    sheet = _INLINE.sub(share, zipfile.ZipFile(io.BytesIO(data)).read(SHEET))
    sst = (b'<?xml version="1.0" encoding="UTF-8"?><sst xmlns="http://schemas.openxmlformats.org/'
           b'spreadsheetml/2006/main" count="%d" uniqueCount="%d">' % (len(table), len(table))
           + b"".join(b'<si><t xml:space="preserve">' + t + b"</t></si>" for t in table)
           + b"</sst>")
    zin = zipfile.ZipFile(io.BytesIO(data))
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as z:
        for info in zin.infolist():
            body = zin.read(info.filename)
            if info.filename == SHEET:
                body = sheet
            elif info.filename == "[Content_Types].xml":
                body = body.replace(b"</Types>", b'<Override PartName="/xl/sharedStrings.xml" '
                                    b'ContentType="application/vnd.openxmlformats-officedocument.'
                                    b'spreadsheetml.sharedStrings+xml"/></Types>')
            elif info.filename == "xl/_rels/workbook.xml.rels":
                body = body.replace(b"</Relationships>", b'<Relationship Id="rIdSST" Type="http'
                                    b'://schemas.openxmlformats.org/officeDocument/2006/'
                                    b'relationships/sharedStrings" Target="sharedStrings.xml"/>'
                                    b"</Relationships>")
            z.writestr(info.filename, body)
        z.writestr("xl/sharedStrings.xml", sst)
    return out.getvalue()
