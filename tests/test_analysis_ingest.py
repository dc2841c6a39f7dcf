"""Reading survey exports: every shape counts exactly, and bad input gets one clear line.

Reference values: the truth is the random response matrix each test draws itself; the
files are rendered from it in each export shape with messy case, white space, blanks
and not-applicable answers (numeric codes are refused without a code map: see
tests/test_analysis_platforms.py). The invariant counted + missing + excluded =
respondents must hold per item, and counts must equal the matrix's own tallies.
"""
import csv
import io
import json

import numpy as np
import openpyxl
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from analysis.__main__ import main
from analysis.errors import SurveyInputError
from analysis.ingest import read_survey
from analysis.likert import summarize
from analysis.scales import BUILTIN_SCALES

PAPER = BUILTIN_SCALES["paper"]
LABELS = list(PAPER.labels)
CODES = {lab: str(int(c)) for lab, c in zip(PAPER.labels, PAPER.codes)}
SHAPES = ("wide", "long", "google", "qualtrics", "xlsx")
NA, BLANK = -2, -1


def _messy(draw, label: str) -> str:
    """A label as a careless export might write it."""
    kind = draw(st.integers(0, 9))
    if kind == 1:
        text = label.upper()
    elif kind == 2:
        text = label.lower()
    elif kind == 3:
        text = label.replace(" ", "   ")
    else:
        text = label
    return draw(st.sampled_from(["", " ", "  ", "\t"])) + text + draw(st.sampled_from(["", " ", "  "]))


@st.composite
def surveys(draw):
    """(truth matrix, rendered cell texts): each item has at least one label answer."""
    n = draw(st.integers(1, 12))
    m = draw(st.integers(1, 4))
    cell = st.integers(-2, 4)
    truth = np.array([[draw(cell) for _ in range(m)] for _ in range(n)], dtype=int)
    for j in range(m):                       # at least one real answer per item
        if not (truth[:, j] >= 0).any():
            truth[draw(st.integers(0, n - 1)), j] = draw(st.integers(0, 4))
        # labels must be the majority answer kind; keep N/A from outnumbering them
    texts = [[("" if v == BLANK else draw(st.sampled_from(["Not applicable", " n/a ", "N/A"])))
              if v < 0 else _messy(draw, LABELS[v]) for v in row] for row in truth]
    return truth, texts


def _write(tmp_path, shape, truth, texts):
    n, m = truth.shape
    names = [f"Q{j + 1}" for j in range(m)]
    path = tmp_path / ("s.xlsx" if shape == "xlsx" else f"{shape}.csv")
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    if shape == "wide":
        w.writerow(["id", "section"] + names)
        for i, row in enumerate(texts):
            w.writerow([i + 1, "AB"[i % 2]] + row)
    elif shape == "long":
        w.writerow(["respondent", "item", "answer"])
        for i, row in enumerate(texts):
            for j, t in enumerate(row):
                if truth[i, j] == BLANK and j > 0 and (i + j) % 2:
                    continue                 # a blank may also be an absent row
                w.writerow([f"r{i}", names[j], t])
    elif shape == "google":
        w.writerow(["Timestamp", "Email Address"]
                   + [f'Question {j + 1}, "quoted", text' for j in range(m)])
        for i, row in enumerate(texts):
            w.writerow([f"2024/01/0{1 + i % 9} 10:00:00", f"p{i}@example.org"] + row)
    elif shape == "qualtrics":
        w.writerow(["StartDate", "Status", "Progress", "Finished", "ResponseId"] + names)
        w.writerow(["Start Date", "Response Type", "Progress", "Finished", "Response ID"]
                   + [f"Question text {j}" for j in range(m)])
        w.writerow(['{"ImportId":"startDate"}', '{"ImportId":"status"}', '{"ImportId":"progress"}',
                    '{"ImportId":"finished"}', '{"ImportId":"_recordId"}']
                   + [f'{{"ImportId":"QID{j + 1}"}}' for j in range(m)])
        for i, row in enumerate(texts):
            if i % 3 == 0:                  # a preview response: must be dropped
                w.writerow(["2024-01-01", "Survey Preview", "100", "True", f"R_p{i}"]
                           + ["Definitely Agree"] * m)
            w.writerow(["2024-01-01", "IP Address", "100", "True", f"R_{i}"] + row)
    elif shape == "xlsx":
        wb = openpyxl.Workbook()
        ws = wb.active
        ws.append(["id"] + names)
        for i, row in enumerate(texts):
            ws.append([i + 1] + [int(t) if t.strip().isdigit() else (t or None) for t in row])
        wb.save(path)
        return path
    path.write_text(buf.getvalue(), encoding="utf-8")
    return path


@pytest.mark.parametrize("shape", SHAPES)
def test_every_shape_counts_exactly(tmp_path_factory, shape):
    # 25 surveys per shape (~10 ms each, ~25 ms for xlsx; about 1.7 s for the five shapes): enough
    # for every shape to meet blank answers, quotes and repeated labels each run.
    @settings(max_examples=25, suppress_health_check=[HealthCheck.function_scoped_fixture])
    @given(surveys())
    def check(sample):
        truth, texts = sample
        folder = tmp_path_factory.mktemp(shape)
        path = _write(folder, shape, truth, texts)
        data = read_survey(path)
        assert data.shape == (shape if shape != "xlsx" else "wide")
        s = summarize(data)
        n, m = truth.shape
        assert s.respondents == n
        names = ([f'Question {j + 1}, "quoted", text' for j in range(m)] if shape == "google"
                 else [f"Question text {j}" for j in range(m)] if shape == "qualtrics"
                 else [f"Q{j + 1}" for j in range(m)])     # Qualtrics items: by their text
        got = [it.item for it in s.items]
        # long files carry no column order: items come in order of first appearance
        assert (sorted(got) if shape == "long" else got) == names
        for it in s.items:
            col = truth[:, names.index(it.item)]
            assert [it.counts[lab] for lab in LABELS] == [int((col == k).sum()) for k in range(5)]
            assert it.missing == int((col == BLANK).sum())
            assert it.excluded == int((col == NA).sum())
            assert it.n + it.missing + it.excluded == s.respondents   # the invariant
        if shape == "qualtrics":
            assert len(data.dropped) == len(range(0, n, 3))
    check()


# --------------------------------------------------------------------------- errors
def _one_line_error(capsys, argv):
    assert main(argv) == 2
    cap = capsys.readouterr()
    assert cap.out == ""
    assert cap.err.count("\n") == 1 and cap.err.startswith("error: ")
    return cap.err


@pytest.mark.parametrize("shape, row", [("wide", 3), ("google", 3), ("qualtrics", 6), ("long", 5)])
def test_unknown_answer_named(tmp_path, capsys, shape, row):
    truth = np.array([[0, 1], [2, 3]])
    texts = [[LABELS[v] for v in r] for r in truth]
    texts[1][1] = " Agreee "
    path = _write(tmp_path, shape, truth, texts)
    err = _one_line_error(capsys, ["summarize", str(path)])
    assert f"error: {path}: row {row}, column " in err
    assert "' Agreee '" in err and "Definitely Agree, Partially Agree" in err
    # with --unknown-as-missing every unknown answer is reported and counted missing
    assert main(["summarize", str(path), "--unknown-as-missing", "--json"]) == 0
    cap = capsys.readouterr()
    out = json.loads(cap.out)
    assert cap.err.count("unknown answer ' Agreee ' counted as missing") == 1
    item = out["items"][1]
    assert item["missing"] == 1 and item["n"] + item["missing"] + item["excluded"] == 2


def test_stray_answer_does_not_drop_column(tmp_path, capsys):
    f = tmp_path / "w.csv"
    f.write_text("q1,q2\nDefinitely Agree,Neutral\nNeutral,Maybe\nNeutral,Neutral\n")
    err = _one_line_error(capsys, ["summarize", str(f)])
    assert "row 3, column 'q2'" in err and "'Maybe'" in err


def test_bad_inputs(tmp_path, capsys):
    empty = tmp_path / "empty.csv"
    empty.write_text("")
    assert "empty file" in _one_line_error(capsys, ["summarize", str(empty)])
    latin = tmp_path / "latin.csv"
    latin.write_bytes(b"q1,\x93the method\x94 is caf\xe9-proof\nNeutral,Neutral\nNeutral,Neutral\n"
                      b"Neutral,Neutral\n")
    # Excel on Windows: not UTF-8, read as Windows-1252 with a note naming it
    assert main(["summarize", str(latin), "--json"]) == 0
    out = capsys.readouterr()
    assert [(it["item"], it["counts"]["Neutral"]) for it in json.loads(out.out)["items"]] == [
        ("q1", 3), ("\u201cthe method\u201d is caf\u00e9-proof", 3)]
    assert "Windows-1252" in out.err
    latin.write_bytes("q1,q2\nNeutral,Neutral\nNeutral,Neutral\n".encode() + b"Neutral,N\xe9utral\n")
    err = _one_line_error(capsys, ["summarize", str(latin), "--encoding", "utf-8"])
    assert "row 4" in err and "0xe9" in err
    noitems = tmp_path / "noitems.csv"
    noitems.write_text("name,age\nAda,36\nBob,41\n")
    assert "no item columns" in _one_line_error(capsys, ["summarize", str(noitems)])
    mixed = tmp_path / "mixed.csv"
    mixed.write_text("q1,q2\nDefinitely Agree,Often\nNeutral,Never\n")
    assert "mixed scales" in _one_line_error(capsys, ["summarize", str(mixed)])
    ok = tmp_path / "ok.csv"
    ok.write_text("q1\nNeutral\nNeutral\nNeutral\n")
    assert "3 responses" in _one_line_error(capsys, ["summarize", str(ok), "--respondents", "2"])
    assert main(["summarize", str(ok), "--respondents", "5", "--json"]) == 0
    item = json.loads(capsys.readouterr().out)["items"][0]
    assert (item["n"], item["missing"]) == (3, 2)
    out = tmp_path / "r.html"
    _one_line_error(capsys, ["report", str(mixed), "-o", str(out)])
    assert not out.exists() and list(tmp_path.glob(".r.html*")) == []   # nothing half-written


def test_numeric_codes_and_custom_scale(tmp_path):
    scale = tmp_path / "conf.toml"
    scale.write_text('name = "confidence"\nlabels = ["Not at all", "Slightly", "Fairly", "Very"]\n'
                     'not_applicable = ["skip"]\n[aliases]\n"very much" = "Very"\n')
    f = tmp_path / "c.csv"
    f.write_text("id,q1,q2\n1,VERY MUCH,4\n2, fairly ,skip\n3,1,\n")
    s = summarize(read_survey(f, scale=str(scale), items=["q*"]))
    assert [it.counts for it in s.items] == [
        {"Not at all": 1, "Slightly": 0, "Fairly": 1, "Very": 1},
        {"Not at all": 0, "Slightly": 0, "Fairly": 0, "Very": 1}]
    assert (s.items[1].excluded, s.items[1].missing) == (1, 1)
    with pytest.raises(SurveyInputError, match="labels"):
        bad = tmp_path / "bad.toml"
        bad.write_text('labels = "x"\n')
        read_survey(f, scale=str(bad))
    with pytest.raises(ValueError, match="agree5"):
        read_survey(f, scale="nonsense")


def test_shipped_custom_scale_and_semicolons(tmp_path):
    from pathlib import Path
    scale = Path(__file__).resolve().parents[1] / "data" / "scales" / "confidence4.toml"
    f = tmp_path / "s.csv"
    f.write_text("id;q1\n1;very CONFIDENT\n2;not confident\n3;Did not attempt\n4;\n")
    it = summarize(read_survey(f, scale=str(scale))).items[0]
    assert (it.n, it.missing, it.excluded) == (2, 1, 1)
    assert it.counts["Very confident"] == it.counts["Not at all confident"] == 1
    assert it.agree.share == 0.5


def test_utf16_tab_export_and_other_columns_listed(tmp_path):
    f = tmp_path / "excel_unicode.txt"
    f.write_bytes("id\tq1\tcomment\n1\tNeutral\tfine\n2\tDefinitely Agree\t\n".encode("utf-16"))
    data = read_survey(f)
    assert data.items == ["q1"] and data.other_columns == ["id", "comment"]
    assert summarize(data).items[0].n == 2


def test_not_applicable_is_no_evidence_of_an_item(tmp_path):
    """A free-text column where people wrote "N/A" is not an item; numeric items may hold N/A.

    Regression: "N/A" counted as a label, so a comment column of "N/A"s and remarks was taken
    as an item (and its remarks raised unknown-answer errors), a column of only "N/A" became
    an item, and a numeric-coded item with one "N/A" was chosen while an all-code item was not.
    """
    f = tmp_path / "q.csv"
    f.write_text("id,Q1,Q2,Comments\n1,Neutral,Definitely Agree,N/A\n"
                 "2,Partially Agree,N/A,N/A\n3,Neutral,Neutral,ok\n")
    data = read_survey(f)
    assert data.items == ["Q1", "Q2"] and data.other_columns == ["id", "Comments"]
    coded = tmp_path / "codes.csv"
    coded.write_text("id,Q1,Q2,Note\n1,1,2,N/A\n2,5,N/A,\n3,4,3,N/A\n")
    for scale in (None, "agree5"):             # codes alone do not say which end agrees
        with pytest.raises(SurveyInputError, match="numeric codes.*--codes"):
            read_survey(coded, scale=scale)
    book = tmp_path / "map.toml"
    book.write_text('[codes]\n1 = "Strongly disagree"\n2 = "Disagree"\n'
                    '3 = "Neither agree nor disagree"\n4 = "Agree"\n5 = "Strongly agree"\n')
    s = summarize(read_survey(coded, codes=book))
    assert [it.item for it in s.items] == ["Q1", "Q2"]
    assert [(it.n, it.missing, it.excluded) for it in s.items] == [(3, 0, 0), (2, 0, 1)]


def test_csv_layout_quirks(tmp_path, capsys):
    """Delimiters and blank lines as spreadsheets write them.

    Regressions: a semicolon file whose quoted question text has a comma was split on
    commas (no items found); rows after a blank line were misnumbered in errors; a blank
    answer written as an empty line in a one-column file was dropped; a workbook with a
    repeated header crashed with a traceback.
    """
    semi = tmp_path / "semi.csv"
    semi.write_bytes(b'Name;"Q1, the method";Q2\r\nAda;Neutral;Definitely Agree\r\n'
                     b'Bob;Partially Agree;Neutral\r\n')
    assert read_survey(semi).items == ["Q1, the method", "Q2"]
    comma = tmp_path / "comma.csv"
    comma.write_text('Timestamp,"Q1; about P; any point",Q2\n1,Neutral,Neutral\n2,Neutral,Neutral\n')
    assert read_survey(comma).items == ["Q1; about P; any point", "Q2"]
    gaps = tmp_path / "gaps.csv"
    gaps.write_bytes(b"q1,q2\r\n\r\nNeutral,Neutral\r\n  \r\n\r\nNeutral,Maybe\r\n\r\n")
    assert "row 6, column 'q2'" in _one_line_error(capsys, ["summarize", str(gaps)])
    one = tmp_path / "one.csv"
    one.write_text("q1\nNeutral\n\nNeutral\n  \nPartially Agree\n\n\n")
    it = summarize(read_survey(one)).items[0]
    assert (it.respondents, it.n, it.missing) == (5, 3, 2)
    # a last line of spaces is a blank answer too (it was stripped as padding, losing a
    # respondent); the empty lines after it are padding, and are reported
    spaced = tmp_path / "spaced.csv"
    spaced.write_bytes(b"q1\r\nNeutral\r\n \r\n\r\n\r\n")
    data = read_survey(spaced)
    it = summarize(data).items[0]
    assert (it.respondents, it.n, it.missing) == (2, 1, 1)
    assert any("2 empty line(s) at the end" in note for note in data.notes), data.notes
    # (a repeated header, once renamed q1.1 as pandas does, is refused: see
    # test_repeated_column_names_are_refused)


def test_long_items_in_questionnaire_order_when_first_rows_skip_one(tmp_path):
    """A long export that leaves out unanswered items still lists items as asked.

    Regression: items came in order of first appearance, so Q2 (skipped by the first
    respondent) was listed after Q3.
    """
    f = tmp_path / "long.csv"
    f.write_text("respondent,item,answer\nr1,Q1,Neutral\nr1,Q3,Neutral\n"
                 "r2,Q1,Neutral\nr2,Q2,Definitely Agree\nr2,Q3,N/A\n")
    s = summarize(read_survey(f))
    assert [it.item for it in s.items] == ["Q1", "Q2", "Q3"]
    assert [(it.n, it.missing, it.excluded) for it in s.items] == [(2, 0, 0), (1, 1, 0), (1, 0, 1)]
    assert s.item("Q2").counts["Definitely Agree"] == 1


def test_header_whose_first_field_is_hash_is_not_a_comment(tmp_path):
    """Regression: a "#,Q1,Q2" header was skipped as a comment line, so the first
    respondent's answers became the headers and that respondent was lost."""
    f = tmp_path / "h.csv"
    f.write_text("# exported from the LMS\n#,Q1,Q2\n1,Neutral,Neutral\n2,Definitely Agree,\n")
    data = read_survey(f)
    assert data.items == ["Q1", "Q2"] and data.respondents == 2
    assert data.comments == ["exported from the LMS"] and list(data.rows) == [3, 4]


def test_trailing_delimiters_short_rows_and_misnamed_files(tmp_path, capsys):
    """Regressions: a trailing comma on each data row made pandas take the first column
    as an index, shifting every answer one column left (silently); a value beyond the
    header was dropped; a short first row switched the delimiter to ';'; binary input
    and a workbook saved as .csv ended in tracebacks."""
    trail = tmp_path / "trail.csv"
    trail.write_text("q1,q2\nNeutral,Definitely Agree,\nPartially Agree,Neutral,\n")
    s = summarize(read_survey(trail))
    assert s.item("q1").counts["Neutral"] == 1 and s.item("q1").counts["Partially Agree"] == 1
    assert s.item("q2").counts["Definitely Agree"] == 1 and s.item("q2").missing == 0
    extra = tmp_path / "extra.csv"
    extra.write_text("q1,q2\nNeutral,Definitely Agree,\nPartially Agree,Neutral,Neutral\n")
    assert "row 3: 3 fields, but the header has 2" in _one_line_error(capsys, ["summarize", str(extra)])
    short = tmp_path / "short.csv"
    short.write_text("q1,q2\nNeutral\nNeutral,Neutral\n")
    s = summarize(read_survey(short))
    assert [(it.n, it.missing) for it in s.items] == [(2, 0), (1, 1)]
    binary = tmp_path / "bin.csv"
    binary.write_bytes(b"\x7fELF\x02\x01\x01\x00\x00\x00\r\x00\x03\x00>\x00\x01\x00\x00\x00\n\xff")
    _one_line_error(capsys, ["summarize", str(binary)])
    u16 = tmp_path / "u16.csv"                      # UTF-16 without a byte-order mark
    u16.write_bytes("q1\nNeutral\n".encode("utf-16-le"))
    assert "utf-16-le" in _one_line_error(capsys, ["summarize", str(u16)])
    assert read_survey(u16, encoding="utf_16_le").respondents == 1
    wb = openpyxl.Workbook()
    wb.active.append(["q1"])
    wb.active.append(["Neutral"])
    wb.save(tmp_path / "book.csv")
    assert read_survey(tmp_path / "book.csv").respondents == 1


def test_shape_named_for_a_workbook_is_kept(tmp_path):
    """Regression: for a .xlsx file a named shape (e.g. ``wide`` for a sheet whose columns
    happen to be called respondent/item/answer) was replaced by detection."""
    wb = openpyxl.Workbook()
    wb.active.append(["respondent", "item", "answer"])
    wb.active.append(["Neutral", "Definitely Agree", "Neutral"])
    wb.save(tmp_path / "w.xlsx")
    data = read_survey(tmp_path / "w.xlsx", shape="wide")
    assert data.shape == "wide" and data.items == ["item", "answer"]   # respondent: an id
    assert read_survey(tmp_path / "w.xlsx", shape="xlsx").shape == "long"


# --------------------------------------------------------------------------- repeated names
AGREE_CODES = ('[codes]\n1 = "Strongly disagree"\n2 = "Disagree"\n'
               '3 = "Neither agree nor disagree"\n4 = "Agree"\n5 = "Strongly agree"\n')
# respondent, first column, second column (codes 1-5 as a Qualtrics numeric export has them)
REPEATED_ROWS = [["r1", "1", "5"], ["r2", "2", "4"], ["r3", "3", "4"], ["r4", "5", "1"]]


def _survey_file(tmp_path, header, suffix):
    path = tmp_path / f"survey{suffix}"
    if suffix == ".csv":
        with open(path, "w", newline="", encoding="utf-8") as fh:
            csv.writer(fh).writerows([header] + REPEATED_ROWS)
    else:
        from tests.xlsx_factory import workbook
        path.write_bytes(workbook([header] + REPEATED_ROWS))
    return path


@pytest.mark.parametrize("suffix", [".csv", ".xlsx"])
@pytest.mark.parametrize("header, message", [
    (["respondent", "Q1", "Q1"], "columns 2 and 3 are both named 'Q1'; rename one"),
    # names are matched ignoring case and spacing (--items, --group, DuckDB): ambiguous too
    (["respondent", "Q1", "q1 "], "columns 2 and 3 are named 'Q1' and 'q1 ', which differ "
                                  "only in case or spacing"),
])
def test_repeated_column_names_are_refused(tmp_path, capsys, suffix, header, message):
    """Two columns named alike stop the read with one line naming the file, the name and
    both positions, exit status 2.

    Regression: `respondent,Q1,Q1` gave items Q1 and Q1.1 (pandas' renaming of a
    repeated header) with no note, and a workbook did the same on purpose."""
    path = _survey_file(tmp_path, header, suffix)
    book = tmp_path / "map.toml"
    book.write_text(AGREE_CODES)
    err = _one_line_error(capsys, ["summarize", str(path), "--codes", str(book)])
    assert err.startswith(f"error: {path}: {message}")
    with pytest.raises(SurveyInputError, match="rename one"):
        read_survey(path, codes=book)


@pytest.mark.parametrize("suffix", [".csv", ".xlsx"])
def test_a_real_column_named_like_a_renamed_one_is_read(tmp_path, suffix):
    """A header that merely ends in ".1" (`Q1.1` next to `Q1`) is a name of its own: both
    items are read, with the counts of the rows above (by hand: Q1 has codes 1, 2, 3, 5,
    Q1.1 has 5, 4, 4, 1)."""
    path = _survey_file(tmp_path, ["respondent", "Q1", "Q1.1"], suffix)
    book = tmp_path / "map.toml"
    book.write_text(AGREE_CODES)
    s = summarize(read_survey(path, codes=book))
    assert [it.item for it in s.items] == ["Q1", "Q1.1"]
    labels = ["Strongly disagree", "Disagree", "Neither agree nor disagree", "Agree",
              "Strongly agree"]
    assert [[it.counts[lab] for lab in labels] for it in s.items] == [[1, 1, 1, 0, 1],
                                                                      [1, 0, 0, 2, 1]]


def test_repeated_names_in_a_frame_and_canvas_points_columns():
    """A DataFrame with two columns named alike is refused as a file is; a Canvas export's
    points columns (`1.0` after each question) repeat by design and are not compared
    (tests/test_analysis_platforms.py reads such an export)."""
    import pandas as pd

    from analysis.ingest import survey_from_frame
    from analysis.platforms import repeated_column
    df = pd.DataFrame([["Neutral", "Neutral"]], columns=["Q1", "Q1"])
    with pytest.raises(SurveyInputError, match="columns 1 and 2 are both named 'Q1'"):
        survey_from_frame(df, source="frame")
    canvas = ["name", "sis_id", "1: first", "1.0", "2: second", "1.0"]
    assert repeated_column(canvas, "canvas") is None
    assert repeated_column(canvas, "wide") == "columns 4 and 6 are both named '1.0'; rename one"
    assert repeated_column(["Q1", "Q1", "Q1", "Q2", "Q2"]) == (
        "columns 1, 2 and 3 are all named 'Q1'; rename all but one (1 more name repeats)")


def test_an_item_nobody_answered_is_shown_not_dropped(tmp_path, capsys):
    """The tester's edge.csv: Q2 is blank in all four rows. Named like Q1 and Q3 it is an
    item with n = 0 and all 4 respondents missing (by hand: 4 blank cells). Blank columns
    not named like the items (free text, a date) stay out, and a note says so; the id
    column stays out as before."""
    f = tmp_path / "edge.csv"
    f.write_text("id,Q1,Q2,Q3,Comments,Submitted\n1,Agree,,N/A,,\n2,Disagree,,Agree,,\n"
                 "3,Strongly agree,,N/A,,\n4,Agree,,Disagree,,\n")
    assert main(["summarize", str(f), "--json"]) == 0
    captured = capsys.readouterr()
    out = json.loads(captured.out)
    items = {it["item"]: it for it in out["items"]}
    assert list(items) == ["Q1", "Q2", "Q3"]
    assert (items["Q2"]["n"], items["Q2"]["missing"], items["Q2"]["excluded"]) == (0, 4, 0)
    assert items["Q2"]["agree"] == {"share": None, "ci": [None, None]}
    assert items["Q3"]["excluded"] == 2                       # the two N/A
    assert out["not_items"] == ["id", "Comments", "Submitted"]
    for name in ("Comments", "Submitted"):
        assert (f"column {name!r} has no answer in any row, and its name is not like the "
                f"items' names: not counted as an item") in captured.err
    # named with --items, the unanswered column is read too (it fits any scale)
    data = read_survey(f, items=["Q1", "Q2", "Q3"])
    assert data.items == ["Q1", "Q2", "Q3"] and (data.answers[:, 1] < 0).all()
    assert main(["summarize", str(f)]) == 0
    q2 = next(ln for ln in capsys.readouterr().out.splitlines() if ln.startswith("Q2"))
    assert q2.split()[:2] == ["Q2", "-"]                  # no percentage of nobody


@pytest.mark.parametrize("suffix", [".csv", ".xlsx"])
def test_empty_rows_are_not_respondents_and_a_footer_is_dropped_with_its_row(tmp_path, suffix):
    """Four students, two empty rows between them, then four empty rows and an export note
    in the first cell of spreadsheet row 11 (header 1, s1-s2 rows 2-3, empty 4-5, s3-s4
    rows 6-7, empty 8-10). An empty row holds no answers: 4 respondents, none missing, in
    both formats; the note is dropped with its row and reason, not counted missing."""
    from tests.xlsx_factory import workbook
    rows = [["Student", "Q1", "Q2"], ["s1", "Agree", "Disagree"], ["s2", "Agree", "Agree"],
            [], [], ["s3", "Disagree", "Agree"], ["s4", "Agree", "Agree"], [], [], [],
            ["Exported by J. Smith on 2024-10-05"]]
    path = tmp_path / f"s{suffix}"
    if suffix == ".csv":
        path.write_text("\n".join(",".join(r) for r in rows) + "\n")
    else:
        path.write_bytes(workbook(rows))
    data = read_survey(path)
    assert data.respondents == 4
    assert data.rows.tolist() == [2, 3, 6, 7]
    assert [(d.row, d.reason) for d in data.dropped] == [(11, "text-only footer row")]
    s = summarize(data)
    assert [(it.n, it.missing) for it in s.items] == [(4, 0), (4, 0)]
    # an answer in the first column is a respondent, however far below: never a footer
    rows[-1] = ["Strongly agree"]
    rows[0][0] = "Q0"
    if suffix == ".csv":
        path.write_text("\n".join(",".join(r) for r in rows) + "\n")
    else:
        path.write_bytes(workbook(rows))
    data = read_survey(path)
    assert data.respondents == 5 and data.dropped == [] and data.rows[-1] == 11


def test_a_code_the_map_lacks_is_an_error_at_its_row(tmp_path, capsys):
    """Regression: Q1 holding codes 2-5 and one typo '6' (row 6: header row 1, then
    respondents 1-5) vanished from the items with no reason. It is an unknown answer
    named by file, row, column and value, with or without --items."""
    f = tmp_path / "typo.csv"
    f.write_text("id,Q1,Q2\n1,5,4\n2,4,4\n3,3,5\n4,4,5\n5,6,2\n6,2,3\n")
    book = tmp_path / "map.toml"
    book.write_text(AGREE_CODES)
    for extra in ([], ["--items", "Q*"]):
        err = _one_line_error(capsys, ["summarize", str(f), "--codes", str(book), *extra])
        assert err.startswith(f"error: {f}: row 6, column 'Q1': answer '6' is not on scale"), err
    # columns = [...] written under [codes] (as the note advising it says) is taken
    # as the map's columns, not refused as a code
    inside = tmp_path / "inside.toml"
    inside.write_text(AGREE_CODES + 'columns = ["Q2"]\n')
    data = read_survey(f, codes=inside)
    assert data.items == ["Q2"] and data.other_columns == ["id", "Q1"]
    # a column of codes the map does not cover is refused naming the map, not asking
    # for --codes, which was given
    wild = tmp_path / "wild.csv"
    wild.write_text("id,Q1\n1,7\n2,8\n3,1\n")
    err = _one_line_error(capsys, ["summarize", str(wild), "--codes", str(book),
                                   "--items", "Q1"])
    assert f"the code map {book} does not cover them" in err and "give the survey" not in err


def test_narrow_scale_note_names_the_missing_label_in_both_layouts(tmp_path):
    """Regressions: with 'Sometimes' answered and 'Rarely' not, the note said 'no neutral
    answer' and advised --scale frequency5 'if the questionnaire offered Sometimes'; a long
    file read as agree4 gave no note at all, while the same answers wide did."""
    freq = tmp_path / "freq.csv"
    freq.write_text("Q1,Q2\nOften,Always\nSometimes,Often\nNever,Sometimes\n")
    notes = read_survey(freq).notes
    assert any("(no answer 'Rarely' in the data); give --scale frequency5 if the "
               "questionnaire offered 'Rarely'" in n for n in notes), notes
    wide = tmp_path / "wide.csv"
    wide.write_text("respondent,Q1\nr1,Agree\nr2,Disagree\nr3,Strongly agree\n")
    long = tmp_path / "long.csv"
    long.write_text("respondent,item,answer\nr1,Q1,Agree\nr2,Q1,Disagree\n"
                    "r3,Q1,Strongly agree\n")
    want = ("read as the 4-point scale 'agree4' (no neutral answer in the data); give --scale "
            "agree5 if the questionnaire offered 'Neither agree nor disagree'")
    for f, shape in ((wide, "wide"), (long, "long")):
        data = read_survey(f)
        assert data.shape == shape and want in data.notes, (shape, data.notes)


def test_declines_and_short_na_marks_are_excluded_alike_on_both_routes(tmp_path, capsys):
    """QA 10 item 9: "Prefer not to say" stopped seven.csv as an answer not on the scale, and
    "NA" and "-" stopped variants.csv. They take no position on the scale: counted under n/a
    (excluded from n) with "N/A", by the in-memory route and by --by alike, and one note
    names them with the reason. By hand, Q2 below: 'Agree' once -> n = 1; a blank cell ->
    missing 1; 'Prefer not to say', 'prefer not to answer ', 'NA', '-', 'N/A' -> n/a 5
    (1 + 1 + 5 = 7 respondents). Counts are exact: no tolerance."""
    f = tmp_path / "declined.csv"
    f.write_text("id,Sec,Q1,Q2\n1,A,Agree,Agree\n2,A,Disagree,Prefer not to say\n"
                 "3,A,Agree,prefer not to answer \n4,B,Strongly agree,NA\n5,B,Agree,-\n"
                 "6,B,Disagree,N/A\n7,B,Agree,\n")
    got, notes = {}, {}
    for route, extra, key in (("memory", [], "items"),
                              ("by", ["--by", "Sec", "--min-group", "1"], "overall")):
        assert main(["summarize", str(f), "--json", *extra]) == 0, route
        out = capsys.readouterr()
        got[route] = {it["item"]: (it["n"], it["missing"], it["excluded"])
                      for it in json.loads(out.out)[key]}
        notes[route] = [ln for ln in json.loads(out.out)["notes"] if "counted under n/a" in ln]
    assert got["memory"] == got["by"] == {"Q1": (7, 0, 0), "Q2": (1, 1, 5)}
    for note in notes.values():
        assert len(note) == 1, notes
        assert "'Prefer not to say' (declined to answer): 1 in 'Q2'" in note[0], note
        assert "'NA' (a mark for not applicable): 1 in 'Q2'" in note[0], note


def test_a_long_file_drops_its_footer_as_by_does(tmp_path, capsys):
    """QA 10 item 5: a long file ending, below an empty row, in "Exported by ..." in its first
    cell stopped the in-memory route ("blank respondent id" on the note's row), while --by
    dropped it as a footer. Both drop it now, naming row 9 (header 1, answers rows 2-7,
    ',,,' row 8). By hand: Q1 answered by a1, a2 (a3 has no Q1 row: missing 1), Q2 by a1,
    a2 and 'N/A' from a3 -> Q1 (2, 1, 0), Q2 (2, 0, 1) as (n, missing, n/a); exact counts."""
    f = tmp_path / "long_footer.csv"
    f.write_text("course,respondent,item,answer\nE1,a1,Q1,Agree\nE1,a1,Q2,Disagree\n"
                 "E1,a2,Q1,Strongly agree\nE1,a2,Q2,Agree\nE1,a3,Q2,N/A\nE1,a3,Q3,\n,,,\n"
                 "Exported by Canvas 2024-01-01,,,\n")
    got = {}
    for route, extra, key in (("memory", [], "items"),
                              ("by", ["--by", "course", "--min-group", "1"], "overall")):
        assert main(["summarize", str(f), "--json", "--items", "Q1", "Q2", *extra]) == 0, route
        out = json.loads(capsys.readouterr().out)
        got[route] = {it["item"]: (it["n"], it["missing"], it["excluded"]) for it in out[key]}
        assert [(d["row"], d["reason"]) for d in out["dropped"]] == [
            (9, "text-only footer row")], out["dropped"]
    assert got["memory"] == got["by"] == {"Q1": (2, 1, 0), "Q2": (2, 0, 1)}


def _two_sheet_workbook(path, sheets: dict) -> None:
    """A workbook of the named sheets, in order, each holding its rows."""
    wb = openpyxl.Workbook()
    wb.remove(wb.active)
    for name, rows in sheets.items():
        ws = wb.create_sheet(name)
        for r in rows:
            ws.append(r)
    wb.save(path)


def test_a_workbook_names_the_sheets_it_did_not_read(tmp_path, capsys):
    """QA 10 item 1: two_terms.xlsx ("Fall 2023" 2 respondents here, "Spring 2024" 3) was
    summarized from its first sheet with no word of the second; multi.xlsx (an "Info" sheet
    before the answers) failed with "no item columns" naming no sheet. By hand: the first
    sheet has 2 rows of answers, the second 3. Exact counts: no tolerance."""
    f = tmp_path / "two_terms.xlsx"
    _two_sheet_workbook(f, {"Fall 2023": [["id", "Q1"], ["a", "Agree"], ["b", "Disagree"]],
                            "Spring 2024": [["id", "Q1"], ["c", "Agree"], ["d", "Agree"],
                                            ["e", "Disagree"]],
                            "Empty": []})
    assert main(["summarize", str(f), "--json"]) == 0
    out = capsys.readouterr()
    assert json.loads(out.out)["respondents"] == 2
    assert ("read the first sheet, 'Fall 2023'; sheet 'Spring 2024' also holds data, not read: "
            "give --sheet NAME") in out.err                    # 'Empty' holds nothing
    assert main(["summarize", str(f), "--json", "--sheet", "Spring 2024"]) == 0
    out = capsys.readouterr()
    assert json.loads(out.out)["respondents"] == 3 and "--sheet" not in out.err
    assert main(["summarize", str(f), "--sheet", "Summer"]) == 2
    err = capsys.readouterr().err
    assert err == (f"error: {f}: no sheet 'Summer' (--sheet); the workbook's sheets are "
                   f"'Fall 2023', 'Spring 2024', 'Empty'\n")
    g = tmp_path / "multi.xlsx"
    _two_sheet_workbook(g, {"Info": [["Course survey"], ["exported 2024-01-01"]],
                            "Responses": [["id", "Q1"], ["a", "Agree"]]})
    assert main(["summarize", str(g)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith(f"error: {g}: no item columns"), err
    assert "(read the first sheet, 'Info'; sheet 'Responses' also holds data" in err, err
    c = tmp_path / "s.csv"
    c.write_text("Q1\nAgree\n")
    assert main(["summarize", str(c), "--sheet", "Responses"]) == 2
    assert "--sheet 'Responses': only a workbook (.xlsx) has sheets" in capsys.readouterr().err


def test_cells_are_read_as_the_text_the_file_holds_on_both_routes(tmp_path, capsys):
    """QA 16 #2: a CSV read with ``dtype="category"`` under pandas 3 turned numeric-looking
    text into numbers: sections '01', '1', '1.0', '001' became one group '1.0', id '00123'
    was named '123', ids '0123' and '123' were taken for one person. The references are the
    cells as written below; every count is exact (no tolerance)."""
    from analysis.institution import summarize_by
    sections = ["01", "1", "1.0", "001"]
    f = tmp_path / "zeros.csv"
    f.write_text("student_id,section,Q1\n" + "".join(
        f"S{g}{k},{sec},{LABELS[k % 5]}\n" for g, sec in enumerate(sections) for k in range(5)))
    data = read_survey(f, group="section")
    assert list(dict.fromkeys(data.groups["section"])) == sections
    res = summarize_by(f, ["section"])
    assert res.groups == sorted((s,) for s in sections) and res.respondents.tolist() == [5] * 4
    order = ["001", "1.0", "1", "01"]          # --group-order takes the values as written
    for extra in (["--group", "section"], ["--by", "section"]):
        assert main(["summarize", str(f), "--json", *extra, "--group-order", *order]) == 0
        out = json.loads(capsys.readouterr().out)
        got = ([g["group"] for g in out["groups"]["groups"]] if "--group" in extra else
               [r["section"] for r in out["rows"] if r["section"] != "(all)"])
        assert got == order, (extra, got)
    # ids: two rows of '00123' are one id, named as written; '0123'/'123' and
    # '00456'/'456.0' are four different ids (no note on either route)
    g = tmp_path / "ids.csv"
    g.write_text("student_id,Term,Q1\n00123,T,Agree\n00456,T,Disagree\n00123,T,Agree\n")
    want = "('00123' in rows 2, 4)"
    assert any(want in n for n in read_survey(g, group="Term").notes)
    assert any(want in n for n in summarize_by(g, ["Term"], min_group=1).notes)
    g.write_text("student_id,Term,Q1\n0123,T,Agree\n123,T,Disagree\n00456,T,Agree\n"
                 "456.0,T,Agree\n")
    for notes in (read_survey(g, group="Term").notes,
                  summarize_by(g, ["Term"], min_group=1).notes):
        assert not any("more than one row" in n for n in notes), notes
    # a long file: respondents '007', '7', '0008' are three people on both routes
    h = tmp_path / "long.csv"
    h.write_text("respondent,item,answer,term\n" + "".join(
        f"{r},{q},Agree,T\n" for r in ("007", "7", "0008") for q in ("1", "2")))
    assert read_survey(h).respondents == 3
    assert summarize_by(h, ["term"], min_group=1).respondents.tolist() == [3]


def test_a_workbook_date_cell_reads_as_excel_shows_it(tmp_path):
    """QA 16 #2: a date cell (midnight) printed as '2024-01-15 00:00:00' and made a group
    apart from the text cell '2024-01-15'. Excel shows a date cell of a date format without
    the time; one holding a time keeps it. References: the cell values written below."""
    import datetime as dt
    f = tmp_path / "dates.xlsx"
    wb = openpyxl.Workbook()
    ws = wb.active
    for row in (["Term", "Q1"], [dt.datetime(2024, 1, 15), "Agree"], ["2024-01-15", "Agree"],
                [dt.datetime(2024, 8, 20, 10, 30), "Disagree"]):
        ws.append(row)
    wb.save(f)
    data = read_survey(f, group="Term")
    assert data.groups["Term"].tolist() == ["2024-01-15", "2024-01-15", "2024-08-20 10:30:00"]


def test_items_of_a_narrower_scale_among_wider_ones_are_named_with_their_statistics(tmp_path, capsys):
    """QA 16 #3: a file mixing 5-point and 7-point agreement items is read as agree7, and the
    5-point items' median, IQR, mean and SD sit on codes 1, 2, 4, 6, 7, unsaid. Both routes
    name those items, word for word, with their statistics on agree5. By hand, on codes
    1-5: Q1 = 1,1,2,2,3,3,4,4,5,5: median 3, quartiles 2 and 4 (numpy's linear rule), mean 3,
    SD sqrt(20/9) = 1.49; Q2 = 5,5,5,4: median 5, quartiles 4.75 and 5 (IQR 0.25, printed
    to two places as every IQR), mean 4.75, SD sqrt(0.75/3) = 0.50. Q3 answers 'Somewhat ...' 8 times of 10 (80%):
    an item of n answers on agree7 misses both such labels with chance 0.2**n (Q2:
    0.0016), below the 5% the note asks for.

    QA 18: Q1 answers on both sides of 'Somewhat disagree' and 'Somewhat agree' and never
    them: it offered agree5, and a table on agree7 codes gave its median as 4 (codes 1, 1,
    2, 2, 4, 4, 6, 6, 7, 7), not 3. With the scale detected it is left out of the table on
    both routes (as R's likert() refuses items of unequal levels in one table), its reason
    listed and its agree5 statistics given; Q2 (every answer at the agreeing end: maybe a
    consensus on agree7) stays, warned; a given --scale agree7 keeps both, warned."""
    from analysis.institution import summarize_by
    a5 = list(BUILTIN_SCALES["agree5"].labels)
    q1 = [a5[i // 2] for i in range(10)]
    q2 = ["Strongly agree"] * 3 + ["Agree"] + [""] * 6
    q3 = ["Somewhat disagree"] * 4 + ["Somewhat agree"] * 4 + ["Agree", "Strongly agree"]
    f = tmp_path / "mixed.csv"
    f.write_text("term,Q1,Q2,Q3\n" + "".join(f"T,{a},{b},{c}\n" for a, b, c in zip(q1, q2, q3)))
    why = ("answers of scale 'agree5', not 'agree7': never 'Somewhat disagree' or 'Somewhat "
           "agree' (80% of the answers to the items that use them), though its answers lie on "
           "both sides of such a label; summarize with --items and --scale agree5, or give "
           "--scale agree7 to count it on 'agree7' codes")
    left = (f"warning: {f}: item 'Q1' left out of the table: {why}; on 'agree5' (codes 1-5) "
            "they are 'Q1': median 3.0, IQR 2.00, mean 3.00, SD 1.49")
    kept = (f"warning: {f}: item 'Q2' never answered 'Somewhat disagree' or 'Somewhat "
            "agree' (labels only scale 'agree7' has, 80% of the answers to the items that use "
            "them): if they offered scale 'agree5', their median, IQR, mean, SD (and a "
            "Cronbach's alpha with them) are on the wrong codes; on 'agree5' (codes 1-5) they "
            "are 'Q2': median 5.0, IQR 0.25, mean 4.75, SD 0.50 (summarize them with --items "
            "and --scale agree5)")
    data = read_survey(f)
    assert data.scale.name == "agree7" and left in data.notes and kept in data.notes, data.notes
    assert data.items == ["Q2", "Q3"] and data.not_item_reasons["Q1"] == why
    assert summarize(data).to_dict()["not_item_reasons"]["Q1"] == why
    by = summarize_by(f, ["term"], min_group=1)
    assert left in by.notes and kept in by.notes and by.items == ["Q2", "Q3"], by.notes
    assert by.not_items["Q1"] == why and by.tallies.shape[1] == 2
    given = read_survey(f, scale="agree7")
    assert given.items == ["Q1", "Q2", "Q3"] and [n for n in given.notes if "Q1" in n] == [
        kept.replace("item 'Q2'", "items 'Q1', 'Q2'").replace(
            "they are 'Q2'", "they are 'Q1': median 3.0, IQR 2.00, mean 3.00, SD 1.49; 'Q2'")]
    # the statistics the note gives are those of the items read on agree5 by themselves
    alone = summarize(read_survey(f, items=["Q1", "Q2"], scale="agree5"))
    assert [(it.mean, it.iqr) for it in alone.items] == [(3.0, 2.0), (4.75, 0.25)]
    # a claim or --reliability naming Q1 is refused with the reason it is no item
    claims = tmp_path / "c.toml"
    claims.write_text('[[claims]]\nid = "c"\nitem = "Q1"\nstatement = "s"\ncategories = '
                      '["Agree"]\ncomparison = ">"\nthreshold = 10\nunit = "%"\n')
    capsys.readouterr()
    for argv in (["claims", str(f), str(claims)], ["summarize", str(f), "--reliability", "Q1", "Q3"]):
        assert main(argv) == 2
        last = capsys.readouterr().err.splitlines()[-1]
        assert last.startswith("error: ") and f"(left out of the table: {why})" in last, last
    # an agree5 file: a 3-answer item without 'Neither ...' is no sign (Q1 uses it in 2
    # answers of 10, 20%: chance 0.8**3 = 0.51 of missing it); 20 such answers are
    # (0.8**20 = 0.012): named as agree4, its codes 1, 2, 3, 4
    g = tmp_path / "five.csv"
    rows = [(a5[i // 2], "Agree" if i < 3 else "") for i in range(10)]
    g.write_text("term,Q1,Q2\n" + "".join(f"T,{a},{b}\n" for a, b in rows))
    assert not any("never answered" in n for n in read_survey(g).notes)
    rows = [(a5[i // 2] if i < 10 else "", "Agree") for i in range(20)]
    g.write_text("term,Q1,Q2\n" + "".join(f"T,{a},{b}\n" for a, b in rows))
    note, = [n for n in read_survey(g).notes if "never answered" in n]
    assert ("item 'Q2' never answered 'Neither agree nor disagree'" in note
            and "on 'agree4' (codes 1-4) they are 'Q2': median 3.0, IQR 0.00, mean 3.00, SD 0.00"
            in note), note


def test_short_rows_are_named_on_both_routes(tmp_path, capsys):
    """QA 16 #6: a row with fewer fields than the header was padded with blanks unsaid (a
    longer one is refused). Spreadsheet rows here: header 1, row 3 has 2 of 4 fields, row 4
    holds a quoted line break (one record, 4 fields: not short), row 5 is empty (no
    respondent), row 7 has 3 fields, row 9 is empty and row 10 a footer dropped as such (not
    named)."""
    from analysis.institution import summarize_by
    f = tmp_path / "short.csv"
    f.write_text('id,T,Q1,Q2\n1,A,Agree,Disagree\n2,A\n3,A,"Agree",Agree\n\n4,A,Agree,Agree\n'
                 '5,A,Agree\n6,A,Agree,Agree\n\nExported by Canvas\n')
    want = (f"{f}: 2 rows with fewer fields than the header's 4 (row 3 has 2, row 7 has 3): "
            "the missing cells are read as blank answers (a line break in an unquoted cell "
            "splits a record in two: check the export)")
    data = read_survey(f)
    assert want in data.notes and data.respondents == 6, data.notes
    assert [d.row for d in data.dropped] == [10]
    res = summarize_by(f, ["T"], min_group=1)
    assert want in res.notes and res.respondents.tolist() == [6], res.notes
    for extra in ([], ["--by", "T", "--min-group", "1"]):     # QA 16 #11: --by --json wrote
        assert main(["summarize", str(f), "--json", *extra]) == 0   # its notes in JSON only
        out = capsys.readouterr()
        assert f"note: {want}\n" in out.err and want in json.loads(out.out)["notes"], extra
    f.write_text(f.read_text().replace('3,A,"Agree",Agree', '3,A,"Agree\nmore",Agree'))
    with pytest.raises(SurveyInputError, match="row 4, column 'Q1': answer 'Agree\\\\nmore'"):
        read_survey(f)          # the record is whole; its Q1 is not an answer: refused there


def test_a_value_beyond_the_header_is_refused_alike_on_both_routes(tmp_path, capsys):
    """QA 18 #6: ``--by`` (DuckDB) read a row with one field too many by inventing a column
    ``column3``, while the in-memory route refused it with pandas' tokenizer text. Both routes
    now apply one rule: a value beyond the header's last column is refused at its row; empty
    fields there (a delimiter too many) are no values, on both routes, and make no column.
    Rows here: header 1; the long one is row 4 (in ``late`` row 3 is long but blank)."""
    rows = "id,T,Q1\n1,A,Agree\n2,A,Disagree\n3,B,Agree{}\n4,B,Agree\n"
    bad = tmp_path / "bad.csv"
    bad.write_text(rows.format(",Extra"))
    for by in ([], ["--by", "T", "--min-group", "1"]):
        assert main(["summarize", str(bad), *by]) == 2
        err = capsys.readouterr().err
        assert err == (f"error: {bad}: row 4: 4 fields, but the header has 3: value 'Extra' "
                       "has no column\n"), (by, err)
    for blank in (",", ",,"):
        ok = tmp_path / "blank.csv"
        ok.write_text(rows.format(blank))
        assert main(["summarize", str(ok), "--json"]) == 0
        one = json.loads(capsys.readouterr().out)
        assert main(["summarize", str(ok), "--json", "--by", "T", "--min-group", "1"]) == 0
        out = capsys.readouterr()
        by = json.loads(out.out)
        assert "column" not in out.err, out.err       # no invented 'column3' noted
        assert [(i["item"], i["n"]) for i in one["items"]] == [("Q1", 4)]
        assert [(r["item"], r["n"]) for r in by["overall"]] == [("Q1", 4)], by["overall"]
        assert by["respondents"] == one["respondents"] == 4


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.lists(st.sampled_from(["", "a", "b c", 'x"y', "p,q", "l\nm", " "]),
                         min_size=0, max_size=4), min_size=1, max_size=8),
       st.integers(1, 9), st.sampled_from(["\n", "\r\n"]))
def test_the_short_record_scan_agrees_with_the_csv_module(records, chunk, newline):
    """The byte scan behind the note (``analysis._io.ShortRecords``), fed in chunks of any
    size, finds the records Python's csv module reads with fewer fields than the first,
    those holding no cell text aside. Reference: ``csv.writer`` writes the records (quoting
    what needs it), ``csv.reader`` reads them back."""
    from analysis._io import ShortRecords
    buf = io.StringIO(newline="")
    csv.writer(buf, lineterminator=newline).writerows([["h1", "h2", "h3"]] + records)
    text = buf.getvalue()
    back = list(csv.reader(io.StringIO(text, newline="")))
    want = [(i + 1, len(r)) for i, r in enumerate(back)
            if len(r) < 3 and "".join(r).strip(' \t\r\n"')]
    scan = ShortRecords(",", newline.encode())
    data = text.encode()
    for at in range(0, len(data), chunk):
        scan.feed(data[at:at + chunk])
    assert scan.close() == want
    assert scan.longer == sum(len(r) > 3 for r in back)     # (the long-row check's trigger)


@pytest.mark.parametrize("route", [[], ["--by", "Q1"]])
def test_a_numeric_column_among_labelled_items_says_codes_would_bring_it_in(analysis_cli, tmp_path, route):
    """QA 19 #2: a Google Forms linear-scale question (answers 1-5) beside labelled grid items was
    set aside as 'not labels of scale agree5', as if it were a comment column, with no note; a file
    of that column alone is refused with the --codes hint. Now the reason and a note say so."""
    f = tmp_path / "mixed.csv"
    f.write_text("id,Q1,Q2,Q3,Year\n1,Agree,4,Disagree,1\n2,Disagree,1,Neither agree nor disagree,4\n"
                 "3,Strongly agree,5,Agree,2\n")  # (Year 1-4 beside 5-point items: no item in codes, QA 20)
    code, out, err = analysis_cli("summarize", str(f), "--json", *route)
    assert code == 0, err
    result = json.loads(out)
    notes = " ".join(result["notes"])
    assert "'Q2' is left out of the table: its answers are numbers from the scale's lowest code" in notes and "--codes" in notes
    assert "'Year'" not in notes
    assert len([n for n in result["notes"] if "'Q2'" in n]) == 1  # (QA 20: it was given twice)
    assert "Q2" not in result.get("items", {}) and "Q2" in json.dumps(result.get("not_items"))


#: QA 21 #2's file: Q1 in codes 1-5, Q2 in codes nobody answered 1 to (2-5), Q3 labelled; Year
#: 1-4 ahead of the items. "The pace was right" (2-4) stands between two labelled statements.
_CODED_BESIDE_LABELS = ("id,Year,Q1,Q2,Q3\na,1,1,2,Agree\nb,2,5,3,Disagree\nc,3,3,4,Agree\n"
                        "d,4,2,5,Strongly agree\ne,2,4,4,Neutral\nf,1,5,2,Agree\n")
_CODED_AMONG_STATEMENTS = ("id,Section,I learned a lot,The pace was right,Labs helped\n"
                           "a,1,Agree,2,Disagree\nb,2,Disagree,3,Agree\nc,3,Strongly agree,4,Agree\n")


@pytest.mark.parametrize("route", [[], ["--by", "id"]])
@pytest.mark.parametrize("text, coded, attribute", [
    (_CODED_BESIDE_LABELS, ["Q1", "Q2"], "Year"),
    (_CODED_AMONG_STATEMENTS, ["The pace was right"], "Section")])
def test_an_item_in_codes_missing_an_end_keeps_the_codes_hint(analysis_cli, tmp_path, route, text,
                                                               coded, attribute):
    """QA 21 #2 (regression from 8d7f39a): Q2, answered 2-5 (nobody chose 1), was listed as 'its
    answers are not labels of scale agree5', with no note and no word of --codes, because only a
    column using both end codes got them. By hand: Q2 is shaped like Q3 (Q#), "The pace was right"
    stands between two labelled items; Year (1-4) and Section (1-3) stand ahead of the items,
    named otherwise, using neither end, so they get no --codes note, and no 'not labels' reason
    either (their answers are codes of the scale)."""
    f = tmp_path / "coded.csv"
    f.write_text(text)
    code, out, err = analysis_cli("summarize", str(f), "--json", "--min-group", "1", *route)
    assert code == 0, err
    result = json.loads(out)
    reasons = result["not_item_reasons"]
    for name in coded:
        assert "--codes" in reasons[name], reasons[name]
        assert [n for n in result["notes"] if f"{name!r} is left out" in n and "--codes" in n]
    assert not any(repr(attribute) in n for n in result["notes"])
    assert reasons[attribute] == ("its answers are numbers among the scale's codes, but it does not "
                                  "look like an item: its answers do not run from the lowest code to "
                                  "the highest, and it is neither named like the items nor placed "
                                  "among them; taken for an attribute of the respondent (a year of "
                                  "study, a section)")


def test_a_code_map_says_when_it_makes_an_item_of_a_year_of_study(analysis_cli, tmp_path):
    """QA 21 #2: with a code map 1..5, Year (1-4, ahead of Q1-Q3) became an item with no word.
    The README's map applies to every column whose answers are mostly its codes, so Year stays
    counted (by hand: 1, 2, 3, 4, 2, 1 -> SD 2, D 2, N 1, A 1, SA 0), and a note names it and the
    way to leave it out; Q1-Q3, like each other, get no note."""
    f = tmp_path / "coded.csv"
    f.write_text(_CODED_BESIDE_LABELS)
    m = tmp_path / "map.toml"
    m.write_text('[codes]\n1 = "Strongly disagree"\n2 = "Disagree"\n3 = "Neutral"\n4 = "Agree"\n'
                 '5 = "Strongly agree"\n')
    code, out, err = analysis_cli("summarize", str(f), "--codes", str(m), "--json")
    assert code == 0, err
    result = json.loads(out)
    year = next(it for it in result["items"] if it["item"] == "Year")
    assert list(year["counts"].values()) == [2, 2, 1, 1, 0]
    said = [n for n in result["notes"] if "column 'Year' is read through the code map as an item" in n]
    assert len(said) == 1 and 'columns = ["Q1", "Q2"]' in said[0], result["notes"]
    assert not any(f"'{q}'" in n for n in result["notes"] for q in ("Q1", "Q2", "Q3"))
