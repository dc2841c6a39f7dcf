"""Malformed and hostile input to ``python -m analysis``: the cases of issue 10, one by one.

Every case ends in one of two ways: exit 2 with exactly one ``error:`` line naming the file
and place (or the flag by its command-line name), or exit 0 with every respondent counted.
Reference counts are the rows the test itself wrote (5 respondents), never the product.
"""
import csv
import datetime as dt
import io
import json
import re

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from analysis.ingest import MAX_COLUMNS, MAX_ITEMS
import xlsx_factory as xf

ROWS = [["q1", "q2"]] + [["Definitely Agree", "Neutral"]] * 3 + [["Neutral", ""]] * 2
# written above: q1 = 3 Definitely Agree + 2 Neutral; q2 = 3 Neutral + 2 blank
EXPECTED = {"q1": ({"Definitely Agree": 3, "Neutral": 2}, 0), "q2": ({"Neutral": 3}, 2)}


def _one_error_line(code, err, *needles):
    assert code == 2, err
    assert err.count("\n") == 1 and err.startswith("error: ") and "Traceback" not in err, err
    for n in needles:
        assert n in err, (n, err)


def _holds_every_row(out: str):
    data = json.loads(out)
    assert data["respondents"] == 5
    for item in data["items"]:
        counts, missing = EXPECTED[item["item"]]
        assert {k: v for k, v in item["counts"].items() if v} == counts
        assert item["missing"] == missing and item["n"] + item["missing"] + item["excluded"] == 5
    assert {i["item"] for i in data["items"]} == set(EXPECTED)


@pytest.mark.parametrize("ref", ["A1:B3", "A1:A6", "A1:A1", "Z99:ZZ100"])
def test_xlsx_dimension_record_is_not_trusted(tmp_path, analysis_cli, ref):
    """Regression: a <dimension> understating the data reported 2 respondents of 5, and one
    hiding a column dropped or refused it."""
    f = tmp_path / "d.xlsx"
    f.write_bytes(xf.with_dimension(xf.workbook(ROWS), ref))
    code, out, err = analysis_cli("summarize", str(f), "--json")
    assert code == 0, err
    _holds_every_row(out)


@pytest.mark.parametrize("kind, needle", [("truncated", "malformed XML"),
                                          ("xxe", "entities"), ("bomb", "entities")])
def test_xlsx_bad_xml_one_line(tmp_path, analysis_cli, kind, needle):
    """Regression: malformed XML and entities raised a traceback from iter_rows. QA 18 #7:
    the line names the sheet the fault is in."""
    good = xf.workbook(ROWS)
    f = tmp_path / "x.xlsx"
    f.write_bytes(xf.truncated(good) if kind == "truncated" else xf.with_entity(good, kind))
    code, out, err = analysis_cli("summarize", str(f))
    _one_error_line(code, err, str(f), needle, "sheet 'Sheet': ")
    assert "root:" not in out + err                     # nothing of /etc/passwd


@pytest.mark.parametrize("argv, flag", [
    (["summarize", "{f}", "--chart", "{d}"], "--chart"),
    (["summarize", "{f}", "--table", "{d}"], "--table"),
    (["report", "{f}", "-o", "{d}"], "-o/--output"),
    (["rebuild-table1", "{d}"], "OUT"),
])
def test_output_path_that_is_a_folder(tmp_path, analysis_cli, argv, flag):
    """Regression: an existing folder as output raised IsADirectoryError after the work."""
    f = tmp_path / "s.xlsx"
    f.write_bytes(xf.workbook(ROWS))
    d = tmp_path / "out"
    d.mkdir()
    code, out, err = analysis_cli(*[a.format(f=f, d=d) for a in argv])
    _one_error_line(code, err, str(d), flag, "folder")
    assert list(d.iterdir()) == [] and sorted(p.name for p in tmp_path.iterdir()) == ["out", "s.xlsx"]


@pytest.mark.parametrize("argv, flag", [
    (["--confidence", "1.5"], "--confidence"), (["--confidence", "nan"], "--confidence"),
    (["--decimals", "-1"], "--decimals"), (["--decimals", "99"], "--decimals"),
    (["--respondents", "0"], "--respondents"), (["--min-group", "0"], "--min-group"),
    (["--respondents", "10" * 3000], "--respondents"),
    (["--encoding", "idna"], "--encoding"), (["--encoding", "nosuch"], "--encoding"),
])
def test_flags_named_by_their_command_line_name(tmp_path, analysis_cli, argv, flag):
    """Regression: messages named `confidence_level`, `decimals`, `respondents`, `min_size`."""
    f = tmp_path / "s.xlsx"
    f.write_bytes(xf.workbook(ROWS))
    code, _, err = analysis_cli("summarize", str(f), *argv)
    _one_error_line(code, err, flag)
    assert "`" not in err and "_level" not in err and "min_size" not in err


def test_scale_with_nan_code_refused(tmp_path, analysis_cli):
    """Regression: codes = [1, nan, 3] was accepted and every agreement share became 0%."""
    scale = tmp_path / "s.toml"
    scale.write_text('labels = ["Low", "Mid", "High"]\ncodes = [1, nan, 3]\n')
    f = tmp_path / "s.csv"
    f.write_text("q1\nLow\nHigh\n")
    code, _, err = analysis_cli("summarize", str(f), "--scale", str(scale))
    _one_error_line(code, err, str(scale), "codes", "finite")


@pytest.mark.parametrize("codes", ["[1, 1e308]", "[-2e6, 1]"])
def test_scale_with_huge_code_refused(tmp_path, analysis_cli, codes):
    """Regression: codes = [1, 1e308] overflowed the mean to inf (exit 0, JSON Infinity);
    a code beyond 1e6 in magnitude is refused naming the file and the key."""
    scale = tmp_path / "s.toml"
    scale.write_text(f'labels = ["A", "B"]\ncodes = {codes}\n')
    f = tmp_path / "s.csv"
    f.write_text("q1\nA\nB\nA\nB\n")
    code, _, err = analysis_cli("summarize", str(f), "--scale", str(scale), "--json")
    _one_error_line(code, err, str(scale), "key 'codes'", "code 1" if "-" in codes else "code 2")


def test_json_output_is_standard():
    """JSON has no Infinity or NaN: a float that is not finite is written null."""
    from analysis.__main__ import _json

    def refuse(name):
        raise AssertionError(f"non-standard JSON constant {name}")
    text = _json({"mean": float("inf"), "sd": [float("nan"), 1.5], "n": 3})
    assert json.loads(text, parse_constant=refuse) == {"mean": None, "sd": [None, 1.5], "n": 3}


def test_deep_scale_toml_one_line(tmp_path, analysis_cli):
    scale = tmp_path / "s.toml"
    scale.write_text("labels = " + "[" * 50_000 + "]" * 50_000 + "\n")
    f = tmp_path / "s.csv"
    f.write_text("q1\nLow\n")
    code, _, err = analysis_cli("summarize", str(f), "--scale", str(scale))
    _one_error_line(code, err, str(scale), "nested too deeply")


def test_wide_survey_refused_by_cap_before_reading(tmp_path, analysis_cli):
    """Regression: 100,000 columns never finished (quadratic scan); now the column cap
    refuses it from the header, and a file just under the caps is read in full."""
    f = tmp_path / "wide.csv"
    n = 100_000
    f.write_text(",".join(f"q{j}" for j in range(n)) + "\n" + ",".join(["Neutral"] * n) + "\n")
    code, _, err = analysis_cli("summarize", str(f))
    _one_error_line(code, err, str(f), f"at most {MAX_COLUMNS}")
    many = tmp_path / "many.csv"
    k = MAX_ITEMS + 1
    many.write_text(",".join(f"q{j}" for j in range(k)) + "\n" + ",".join(["Neutral"] * k) + "\n")
    code, _, err = analysis_cli("summarize", str(many))
    _one_error_line(code, err, f"{k} item columns", f"at most {MAX_ITEMS}")


def test_invalid_code_column_listed_in_json(tmp_path, analysis_cli):
    """Regression: a column of codes off the scale was "not items" in the text only."""
    f = tmp_path / "s.csv"
    f.write_text("q1,q2,codes\nNeutral,Neutral,7\nNeutral,Neutral,9\n")
    code, out, err = analysis_cli("summarize", str(f), "--json")
    assert code == 0, err
    assert json.loads(out)["not_items"] == ["codes"]
    code, text, _ = analysis_cli("summarize", str(f))
    assert "not items (left out of the table): codes" in text


def test_rebuilt_csv_neutralises_formulas(tmp_path, analysis_cli, monkeypatch):
    """Labels are data: a label such as ``=HYPERLINK(...)`` is written with a leading
    apostrophe, and a newline in it cannot leave its comment line."""
    import analysis.respondents as resp
    from analysis.tables import PublishedTable, verify_table
    table = PublishedTable(("#1", "#2"), ("=HYPERLINK(\"x\")", "+1", "-\nDisagree"),
                           (("50.0", "25.0", "25.0"), ("50.0", "50.0", "0.0")), "t.csv")
    monkeypatch.setattr(resp, "table1_check", lambda: verify_table(table, n=4))
    out = tmp_path / "r.csv"
    code, _, err = analysis_cli("rebuild-table1", str(out))
    assert code == 0, err
    text = out.read_text()
    head = text.index("respondent,")
    assert all(ln.startswith("#") for ln in text[:head].splitlines())
    rows = list(csv.reader(io.StringIO(text[head:])))
    assert rows[0] == ["respondent", "item1", "item2"] and len(rows) == 1 + 4
    cells = [c for r in rows[1:] for c in r[1:]]
    assert set(cells) == {"'=HYPERLINK(\"x\")", "'+1", "'-\nDisagree"}
    assert not any(c[:1] in ("=", "+", "-", "@", "\t", "\r") for r in rows for c in r)


def test_internal_error_is_one_line(tmp_path, analysis_cli, monkeypatch):
    """A bug (not bad input) gives one ``internal error`` line and exit 1, no traceback."""
    import analysis.__main__ as cli

    def boom(args):
        raise ZeroDivisionError("division by zero")
    monkeypatch.setitem(cli._COMMANDS, "summarize", boom)
    code, _, err = analysis_cli("summarize", "x.csv")
    assert code == 1 and err.count("\n") == 1 and "internal error (ZeroDivisionError" in err


def test_pipes_devices_and_folders_are_not_read(tmp_path, analysis_cli):
    """Regression (solver side of issue 10, same in analysis): a FIFO blocked forever and
    /dev/zero never ended."""
    import os
    fifo = tmp_path / "fifo.csv"
    os.mkfifo(fifo)
    for path in (fifo, "/dev/zero", tmp_path):
        code, _, err = analysis_cli("summarize", str(path))
        _one_error_line(code, err, str(path))
    code, _, err = analysis_cli("verify-table", "/dev/zero", "--n", "3")
    _one_error_line(code, err, "/dev/zero", "regular file")


def test_workbook_row_and_cell_caps(tmp_path, analysis_cli, monkeypatch):
    """A row number far down the sheet (openpyxl yields every empty row before it) and a
    sheet whose rows x columns pass the cell cap are refused while reading. The caps are
    lowered here so that the test reads a few rows, not a million."""
    import analysis.ingest as ingest
    monkeypatch.setattr(ingest, "XLSX_MAX_ROWS", 50)
    far = xf.rewrite_sheet(xf.workbook(ROWS), lambda x: x.replace(
        b"</sheetData>", b'<row r="999999999"><c r="A999999999" t="inlineStr"><is><t>Neutral'
        b"</t></is></c></row></sheetData>"))
    f = tmp_path / "far.xlsx"
    f.write_bytes(far)
    code, _, err = analysis_cli("summarize", str(f))
    _one_error_line(code, err, str(f), "row 51", "more than 50 rows")
    monkeypatch.setattr(ingest, "MAX_CELLS", 9)        # 5 respondents x 2 items + header = 12
    g = tmp_path / "ok.xlsx"
    g.write_bytes(xf.workbook(ROWS))
    code, _, err = analysis_cli("summarize", str(g))
    _one_error_line(code, err, "more than 9 cells")
    c = tmp_path / "s.csv"
    c.write_text("q1,q2\n" + "Neutral,Neutral\n" * 5)
    code, _, err = analysis_cli("summarize", str(c))
    _one_error_line(code, err, "at most 9 cells")


def test_work_caps_for_groups_charts_and_names(tmp_path, analysis_cli, monkeypatch):
    """Group comparisons, charts and name lists are capped before their work is done."""
    f = tmp_path / "g.csv"
    f.write_text("g,q1,q2\n" + "".join(f"g{i},Neutral,Definitely Agree\n" for i in range(30)))
    import analysis.groups as groups
    monkeypatch.setattr(groups, "MAX_GROUP_CELLS", 40)   # 30 groups x 2 items = 60
    code, _, err = analysis_cli("summarize", str(f), "--group", "g", "--min-group", "1")
    _one_error_line(code, err, "30 groups x 2 items", "--min-group")
    code, out, err = analysis_cli("summarize", str(f), "--group", "g", "--min-group", "2",
                                  "--json")       # every group suppressed: nothing to compare
    assert code == 0 and all(g["suppressed"] for g in json.loads(out)["groups"]["groups"])
    import analysis.chart as chart
    monkeypatch.setattr(chart, "MAX_CHART_ITEMS", 1)
    code, _, err = analysis_cli("summarize", str(f), "--chart", str(tmp_path / "c.svg"))
    _one_error_line(code, err, "--chart", "at most 1")
    assert not (tmp_path / "c.svg").exists()
    code, _, err = analysis_cli("summarize", str(f), "--items", *[f"q{i}" for i in range(201)])
    _one_error_line(code, err, "--items", "at most 200")


def test_group_chart_capped_in_bars(tmp_path, analysis_cli, monkeypatch):
    """The faceted group chart (items x groups bars) has its own cap; nothing half-written."""
    f = tmp_path / "g.csv"
    f.write_text("g,q1,q2\n" + "".join(f"{g},Neutral,Definitely Agree\n" for g in "ab" * 5))
    import analysis.chart as chart
    monkeypatch.setattr(chart, "MAX_CHART_BARS", 3)        # 2 items x 2 groups = 4 bars
    out = tmp_path / "c.svg"
    code, _, err = analysis_cli("summarize", str(f), "--group", "g", "--chart", str(out))
    _one_error_line(code, err, str(f), "2 items x 2 groups", "--min-group")
    assert not out.exists()
    monkeypatch.setattr(chart, "MAX_CHART_BARS", 4)        # at the cap: drawn
    code, _, err = analysis_cli("summarize", str(f), "--group", "g", "--chart", str(out))
    assert code == 0 and out.read_text().startswith("<svg"), err


def test_long_file_with_too_many_items(tmp_path, analysis_cli, monkeypatch):
    import analysis.ingest as ingest
    monkeypatch.setattr(ingest, "MAX_COLUMNS", 3)
    f = tmp_path / "long.csv"
    f.write_text("respondent,item,answer\n" + "".join(f"r1,i{k},Neutral\n" for k in range(4)))
    code, _, err = analysis_cli("summarize", str(f))
    _one_error_line(code, err, "4 distinct items", "at most 3")


@pytest.mark.parametrize("text, row", [('a,b\n"unterminated,x\n', 2),
                                       ('Q1,Q2\nAgree,Agree\nAgree,"oops\nAgree,Agree\n', 3)])
def test_unclosed_quote_named_at_its_row(tmp_path, analysis_cli, text, row):
    """Regression: pandas' 0-based 'EOF inside string starting at row 1' was passed on for
    a quote opened on row 2 (the header is row 1 everywhere else)."""
    f = tmp_path / "m.csv"
    f.write_text(text)
    code, _, err = analysis_cli("summarize", str(f))
    _one_error_line(code, err, f"{f}: row {row}: a quoted field opened here is never closed")


def _prefixed(xml: bytes) -> bytes:
    """The sheet's XML with its namespace written as a prefix (``<x:c>``), as some writers do."""
    xml = re.sub(rb"<(/?)(?=[A-Za-z])", rb"<\1x:", xml)
    return xml.replace(b'<x:worksheet xmlns="', b'<x:worksheet xmlns:x="', 1)


@settings(max_examples=40, deadline=None)
@given(st.lists(st.lists(st.one_of(
    st.none(), st.text(max_size=6), st.integers(-10**12, 10**12),
    st.floats(allow_nan=False, allow_infinity=False, width=32), st.booleans(),
    st.datetimes(min_value=dt.datetime(1901, 1, 1), max_value=dt.datetime(2100, 1, 1)),
    st.sampled_from(["Agree", "  N/A ", "<&>\"'", "=1+1", "x\ny"])), max_size=5),
    min_size=1, max_size=6), st.booleans(), st.booleans(), st.booleans())
def test_the_fast_sheet_reader_gives_openpyxls_values(rows, write_only, shared, prefixed):
    """QA 16 #10: reading a sheet through openpyxl took about 18 us a cell (50,000 rows of 9
    answers: 8.9 s), so it is parsed with expat by ``analysis.xlsx_sheet``. Reference:
    openpyxl's own ``iter_rows(values_only=True)`` on the same workbook, whose cells hold
    text, numbers, booleans, dates, blanks and empty rows; written in openpyxl's normal
    and write-only modes, with its text as inline or (as Excel saves it) shared strings, and
    with the sheet's namespace as a prefix."""
    import openpyxl
    from openpyxl.cell.cell import ILLEGAL_CHARACTERS_RE
    from analysis.xlsx_sheet import load_read_only, sheet_values
    rows = [[ILLEGAL_CHARACTERS_RE.sub("", v) if isinstance(v, str) else v for v in r]
            for r in rows]
    wb = openpyxl.Workbook(write_only=write_only)
    ws = wb.create_sheet() if write_only else wb.active
    for r in rows:
        ws.append(r)
    buf = io.BytesIO()
    wb.save(buf)
    data = xf.with_shared_strings(buf.getvalue()) if shared else buf.getvalue()
    data = xf.rewrite_sheet(data, _prefixed) if prefixed else data
    ref = openpyxl.load_workbook(io.BytesIO(data), read_only=True, data_only=True)
    ref_ws = ref.worksheets[0]
    ref_ws.reset_dimensions()
    want = [tuple(r) for r in ref_ws.iter_rows(values_only=True)]
    fast = load_read_only(io.BytesIO(data))
    assert list(sheet_values(fast, fast.worksheets[0], 5000, None)) == want


def test_the_fast_sheet_reader_reads_odd_cells_as_openpyxl_or_refuses(tmp_path, analysis_cli):
    """QA 18 #1-3, three sheets the fast reader misread without a word: an entity that no
    declaration defines (a DOCTYPE naming an external DTD, which is not fetched) was dropped
    (``Dis&foo;agree`` read ``Disagree``); a ``<c>`` of a foreign namespace was read as a cell (a
    phantom answer); an inline string holding both ``<is>`` and ``<v>`` took the ``<v>``, and a
    shared-string cell with an ``<is>`` child failed on it. Reference: openpyxl's own reader for
    the last two (the first it refuses too); ours refuses the first in one line, exit 2."""
    import openpyxl
    from analysis.xlsx_sheet import load_read_only, sheet_values
    base = xf.workbook([["id", "Q1", "Q2"], [1, "Agree", "Disagree"], [2, "Agree", "Agree"]])

    def third_row(cells: bytes):
        return lambda x: re.sub(rb'<row r="3".*?</row>', b'<row r="3">' + cells + b"</row>", x, flags=re.S)
    odd = {"foreign": xf.rewrite_sheet(base, third_row(
               b'<c r="A3"><v>2</v></c><q:c xmlns:q="urn:other" r="B3"><q:v>7</q:v></q:c>')),
           "both": xf.rewrite_sheet(base, third_row(
               b'<c r="A3"><v>2</v></c><c r="B3" t="inlineStr"><is><t>Agree</t></is><v>Neutral</v></c>')),
           "is_in_number": xf.rewrite_sheet(base, third_row(
               b'<c r="A3"><v>2</v><is><t>Agree</t></is></c><c r="B3" t="inlineStr"><is><t>Agree</t></is></c>'))}
    for name, data in odd.items():
        ref = openpyxl.load_workbook(io.BytesIO(data), read_only=True, data_only=True).worksheets[0]
        ref.reset_dimensions()
        fast = load_read_only(io.BytesIO(data))
        def trimmed(rows):  # openpyxl gives the foreign <c> a column of its own, holding None
            return [tuple(r)[:max([i + 1 for i, v in enumerate(r) if v is not None], default=0)] for r in rows]
        assert trimmed(sheet_values(fast, fast.worksheets[0], 5000, None)) == trimmed(ref.iter_rows(values_only=True)), name
    assert list(sheet_values(*(lambda w: (w, w.worksheets[0]))(load_read_only(io.BytesIO(odd["both"]))), 5000, None))[2] == (2, "Agree")
    undefined = xf.rewrite_sheet(base, lambda x: re.sub(rb"^<\?xml[^>]*\?>", b"", x).replace(
        b"<t>Disagree", b"<t>Dis&foo;agree", 1).join([b'<?xml version="1.0"?><!DOCTYPE worksheet SYSTEM "x.dtd">', b""]))
    path = tmp_path / "undefined.xlsx"
    path.write_bytes(undefined)
    code, out, err = analysis_cli("summarize", str(path))
    assert (code, out, err.count("\n")) == (2, "", 1) and "entit" in err, (code, out, err)


def test_a_fault_in_a_sheet_not_read_does_not_refuse_the_sheet_read(analysis_cli, tmp_path):
    """QA 18 #4: a second sheet declaring entities refused the whole workbook, with --sheet naming
    the good one too, and the error named a row of the sheet read. That sheet is only scanned
    for the hint naming the sheets not read: it is named there, and the sheet read is read."""
    import openpyxl
    wb = openpyxl.Workbook()
    wb.active.title = "Data"
    for r in [["id", "Q1"], [1, "Agree"], [2, "Disagree"]]:
        wb.active.append(r)
    wb.create_sheet("Evil").append(["x"])
    buf = io.BytesIO()
    wb.save(buf)
    evil = "xl/worksheets/sheet2.xml"
    zin = __import__("zipfile").ZipFile(io.BytesIO(buf.getvalue()))
    out = io.BytesIO()
    with __import__("zipfile").ZipFile(out, "w") as z:
        for info in zin.infolist():
            body = zin.read(info.filename)
            if info.filename == evil:
                body = re.sub(rb"^<\?xml[^>]*\?>", b"", body).replace(b"<t>x", b"<t>&e;x", 1)
                body = b'<?xml version="1.0"?><!DOCTYPE w [<!ENTITY e "lol">]>' + body
            z.writestr(info.filename, body)
    path = tmp_path / "two.xlsx"
    path.write_bytes(out.getvalue())
    for argv in ([], ["--sheet", "Data"]):
        code, text, err = analysis_cli("summarize", str(path), "--json", *argv)
        assert code == 0, err
        assert json.loads(text)["respondents"] == 2
    assert "'Evil' also holds data" in analysis_cli("summarize", str(path))[2]


# the sheet written by xf.workbook(_FOUR): rows 1-4, cells A (id) and B (answer)
_FOUR = [["id", "Q1"], [1, "Agree"], [2, "Disagree"], [3, "Agree"]]


def _row(xml: bytes, r: int) -> bytes:
    return re.search(rb'<row r="%d">.*?</row>' % r, xml, re.S).group(0)


@pytest.mark.parametrize("edit, row", [
    # row 3 written a second time at the end (its second copy was dropped unsaid)
    (lambda x: x.replace(b"</sheetData>", _row(x, 3).replace(b"Disagree", b"Agree") + b"</sheetData>"), 3),
    # row 2 moved after row 4: out of order (it was dropped unsaid: 2 respondents of 3)
    (lambda x: x.replace(_row(x, 2), b"").replace(b"</sheetData>", _row(x, 2) + b"</sheetData>"), 2),
    # row 3 written twice in a row
    (lambda x: x.replace(_row(x, 3), _row(x, 3) * 2), 3),
    # a row numbered 0 before the header (it was dropped unsaid)
    (lambda x: x.replace(b"<sheetData>", b'<sheetData><row r="0"><c r="A0" t="n"><v>9</v></c></row>'), None),
])
def test_rows_out_of_order_or_repeated_are_refused(tmp_path, analysis_cli, edit, row):
    """QA 18 #5: the fast reader (as openpyxl) skipped a row whose number was not above the
    last one read, so a row written again or out of order was lost without a word. Which of
    two copies holds is not known, so such a sheet is refused, naming the sheet and the row."""
    f = tmp_path / "rows.xlsx"
    f.write_bytes(xf.rewrite_sheet(xf.workbook(_FOUR), edit))
    code, out, err = analysis_cli("summarize", str(f))
    _one_error_line(code, err, str(f), *([f"sheet 'Sheet', row {row}: "] if row else ["sheet 'Sheet'", "numbered 0"]))
    assert out == ""


def _cell(ref: bytes, new: bytes):
    """An edit replacing the cell ``ref`` of the sheet's XML by ``new``."""
    return lambda x: re.sub(rb'<c r="%s"[^>]*>.*?</c>' % ref, new, x, count=1, flags=re.S)


@pytest.mark.parametrize("edit, shared, needles", [
    (_cell(b"A3", b'<c r="A3" s="x"><v>2</v></c>'), False, ["sheet 'Sheet', cell A3: ", "style"]),
    (_cell(b"A3", b'<c r="A3" t="b"><v>true</v></c>'), False, ["sheet 'Sheet', cell A3: ", "'true'"]),
    (_cell(b"A3", b'<c r="A3"><v>1,5</v></c>'), False, ["sheet 'Sheet', cell A3: ", "'1,5'"]),
    (_cell(b"B3", b'<c r="B3" t="s"><v>99</v></c>'), True, ["sheet 'Sheet', cell B3: ", "shared string 99"]),
    # a negative index read the last shared string ('Agree') in Disagree's place, unsaid
    (_cell(b"B3", b'<c r="B3" t="s"><v>-1</v></c>'), True, ["sheet 'Sheet', cell B3: ", "shared string -1"]),
    (_cell(b"B3", b'<c r="3" t="inlineStr"><is><t>Agree</t></is></c>'), False, ["sheet 'Sheet', row 3: ", "'3' names no column"]),
    (_cell(b"B3", b'<c r="B3"><v>2</v></c><c r="B3"><v>3</v></c>'), False, ["sheet 'Sheet', cell B3: ", "twice"]),
    # (QA 20) a cell naming row 9 inside row 3: read as row 3's, where openpyxl puts it in row 9
    (_cell(b"B3", b'<c r="B9" t="inlineStr"><is><t>Agree</t></is></c>'), False, ["sheet 'Sheet', row 3: ", "'B9'", "inside row 3"]),
    (_cell(b"B3", b'<c r="XFD3"><v>2</v></c>'), False, ["row 3: ", "16384 columns"]),
])
def test_a_bad_cell_is_named_by_its_reference(tmp_path, analysis_cli, edit, shared, needles):
    """QA 18 #7: a cell its type cannot hold was refused as 'not a readable .xlsx workbook:
    ValueError' (or IndexError), and a cell too far right as in row 1. The line names the sheet,
    the row and the cell, and says what is wrong. QA 20 #7: it named the place twice ("row 2:
    sheet 'Form Responses 1', cell E2: ..."); the cell's reference holds its row, so a cell's
    fault is named by the sheet and the cell alone, a row's by the sheet and the row."""
    book = xf.workbook(_FOUR)
    f = tmp_path / "cell.xlsx"
    f.write_bytes(xf.rewrite_sheet(xf.with_shared_strings(book) if shared else book, edit))
    code, out, err = analysis_cli("summarize", str(f))
    _one_error_line(code, err, str(f), *needles)
    assert "Error" not in err and out == ""
    rest = err.split(".xlsx: ", 1)[1]  # the place named once: no "row 3: sheet 'Sheet', cell A3: "
    assert re.match(r"(sheet 'Sheet', cell [AB]3|sheet 'Sheet', row 3|row 3): (?!sheet |cell [A-Z]+\d)", rest), err


def test_a_damaged_or_broken_workbook_is_named_in_words(tmp_path, analysis_cli):
    """QA 18 #7: a flipped byte in the compressed sheet gave 'row 1: not a readable .xlsx
    workbook: error' (zlib's class name), a truncated file '(BadZipFile)', a missing part
    'KeyError'-like text or 'IndexError'. Each line now names the part and what is wrong."""
    import zipfile
    good = xf.workbook(_FOUR)
    info = zipfile.ZipFile(io.BytesIO(good)).getinfo(xf.SHEET)
    start = info.header_offset + 30 + len(info.filename) + len(info.extra)
    flipped = bytearray(good)
    for k in range(8):                          # several bytes, so that inflating surely fails
        flipped[start + info.compress_size // 3 + k] ^= 0xFF

    def without(part):
        zin, out = zipfile.ZipFile(io.BytesIO(good)), io.BytesIO()
        with zipfile.ZipFile(out, "w") as z:
            for i in zin.infolist():
                if i.filename != part:
                    z.writestr(i.filename, zin.read(i.filename))
        return out.getvalue()
    cases = {"damaged": (bytes(flipped), ["sheet 'Sheet'", xf.SHEET, "damaged"]),
             "truncated": (good[:len(good) // 2], ["not a zip archive"]),
             "no_workbook": (without("xl/workbook.xml"), ["xl/workbook.xml"]),
             "no_sheet": (without(xf.SHEET), ["no worksheet"])}
    for name, (data, needles) in cases.items():
        f = tmp_path / f"{name}.xlsx"
        f.write_bytes(data)
        code, out, err = analysis_cli("summarize", str(f))
        _one_error_line(code, err, str(f), *needles)
        assert not re.search(r"\b(error|[A-Z]\w+(Error|File))$", err.strip()), err
