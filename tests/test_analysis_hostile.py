"""Malformed and hostile input to ``python -m analysis``: the cases of issue 10, one by one.

Every case ends in one of two ways: exit 2 with exactly one ``error:`` line naming the file
and place (or the flag by its command-line name), or exit 0 with every respondent counted.
Reference counts are the rows the test itself wrote (5 respondents), never the product.
"""
import csv
import io
import json

import pytest

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
    """Regression: malformed XML and entities raised a traceback from iter_rows."""
    good = xf.workbook(ROWS)
    f = tmp_path / "x.xlsx"
    f.write_bytes(xf.truncated(good) if kind == "truncated" else xf.with_entity(good, kind))
    code, out, err = analysis_cli("summarize", str(f))
    _one_error_line(code, err, str(f), needle)
    assert "root:" not in out + err                     # nothing of /etc/passwd


@pytest.mark.parametrize("argv, flag", [
    (["summarize", "{f}", "--chart", "{d}"], "--chart"),
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
