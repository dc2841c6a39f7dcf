"""Every platform's export, read with no options, counts what an independent tally counts.

Each test writes a small imitation of one platform's real export (its header rows,
metadata columns, matrix/grid layout, encoding) from answers it draws itself, then
tallies the raw cells with plain Python (``collections.Counter`` over the drawn
answers, not through the product) and compares counts, n, missing, excluded and
dropped rows with what ``read_survey`` + ``summarize`` report.
"""
import csv
import io
import json
import random
from collections import Counter

import numpy as np
import openpyxl
import pytest

from analysis.__main__ import main
from analysis.errors import SurveyInputError
from analysis.ingest import read_survey
from analysis.likert import summarize
from analysis.scales import BUILTIN_SCALES

AGREE5 = list(BUILTIN_SCALES["agree5-somewhat"].labels)     # Qualtrics' default wording
AGREE4 = ["Strongly disagree", "Disagree", "Agree", "Strongly agree"]
NA_TEXTS = {"n/a", "not applicable", "does not apply"}


def _draw(seed, n, m, labels, blank=0.1, na=0.05):
    """n x m answers: label text, "" (blank) or "N/A", drawn with a fixed seed."""
    rng = random.Random(seed)
    out = []
    for _ in range(n):
        row = []
        for _ in range(m):
            u = rng.random()
            row.append("" if u < blank else "N/A" if u < blank + na else rng.choice(labels))
        out.append(row)
    return out


def _tally(answers, j, labels):
    """(counts per label, n, missing, excluded) of column j, counted from the cells."""
    col = [row[j].strip() for row in answers]
    c = Counter(col)
    counts = {lab: sum(v for k, v in c.items() if k.casefold() == lab.casefold())
              for lab in labels}
    excluded = sum(v for k, v in c.items() if k.casefold() in NA_TEXTS)
    missing = c.get("", 0)
    return counts, sum(counts.values()), missing, excluded


def _check(summary, answers, labels, names):
    assert [it.item for it in summary.items] == names
    assert summary.respondents == len(answers)
    for j, it in enumerate(summary.items):
        counts, n, missing, excluded = _tally(answers, j, labels)
        assert (it.counts, it.n, it.missing, it.excluded) == (counts, n, missing, excluded)


def _csv(path, rows, encoding="utf-8"):
    buf = io.StringIO()
    csv.writer(buf, lineterminator="\r\n").writerows(rows)
    path.write_bytes(buf.getvalue().encode(encoding))
    return path


STATEMENTS = ["The lectures were clear", "The labs helped me, [really]", "Exams were fair"]
STEM = "How much do you agree with the following statements?"


# ---------------------------------------------------------------------------
# Qualtrics
# ---------------------------------------------------------------------------
def _qualtrics_rows(answers, status_of, numeric=False, section=None):
    head = ["StartDate", "EndDate", "Status", "IPAddress", "Progress", "Duration (in seconds)",
            "Finished", "RecordedDate", "ResponseId", "UserLanguage"]
    fields = [f"Q1_{k + 1}" for k in range(len(STATEMENTS))] + ["Q2", "Q3"]
    texts = [f"{STEM} - {s}" for s in STATEMENTS] + ["Which section are you in?",
                                                     "Any comments?"]
    rows = [head + fields,
            ["Start Date", "End Date", "Response Type", "IP Address", "Progress",
             "Duration (in seconds)", "Finished", "Recorded Date", "Response ID",
             "User Language"] + texts,
            [json.dumps({"ImportId": h.lower()}) for h in head]
            + [json.dumps({"ImportId": f"QID{j}"}) for j in range(len(fields))]]
    for i, row in enumerate(answers):
        st = status_of(i)
        sec = section[i] if section else "Section A"
        rows.append(["2024-03-01 10:00:00", "2024-03-01 10:05:00", st, "10.0.0.1", "100", "300",
                     "1" if numeric else "True", "2024-03-01 10:05:01", f"R_{i:04d}", "EN"]
                    + row + [sec, "fine, thanks" if i % 4 == 0 else ""])
    return rows


def test_export_field_ids_name_items_everywhere_items_are_named(tmp_path, capsys):
    """Regression: --items Q1_3 took the field id, but --reverse, --reliability and a claim's
    item refused it as 'not an item'. Reference: the answers written here; Q1_3 is the
    third statement, 'Exams were fair'."""
    ans = [[AGREE5[(i + k) % 5] for k in range(3)] for i in range(8)]
    f = _csv(tmp_path / "q.csv", _qualtrics_rows(ans, lambda i: "IP Address"))
    data = read_survey(f, reverse=["Q1_3"])
    assert data.reverse == {"Exams were fair"}
    from analysis.reliability import cronbach_alpha_for
    assert cronbach_alpha_for(data, ["Q1_1", "Q1_3"]).items == ["The lectures were clear",
                                                              "Exams were fair"]
    claims = tmp_path / "c.toml"
    claims.write_text('[[claims]]\nid = "fair"\nitem = "Q1_3"\nstatement = "s"\n'
                      'categories = ["Strongly agree"]\ncomparison = ">"\nthreshold = 10\n'
                      'unit = "%"\n')
    assert main(["claims", str(f), str(claims), "--json"]) == 0
    got = json.loads(capsys.readouterr().out)
    # Exams were fair = AGREE5[(i + 2) % 5] for i in 0..7: 'Strongly agree' (index 4) at i = 2, 7
    assert (got["claims"][0]["item"], got["claims"][0]["k"], got["claims"][0]["n"]) == (
        "Exams were fair", 2, 8)


def test_qualtrics_choice_text_drops_preview_and_test_rows(tmp_path, capsys):
    real = _draw(1, 30, 3, AGREE5)
    status = ["IP Address"] * 30
    rows_ans, kinds = [], []
    for i, row in enumerate(real):           # interleave previews and tests
        if i % 7 == 0:
            rows_ans.append(["Strongly agree"] * 3)
            kinds.append("Survey Preview")
        if i % 9 == 0:
            rows_ans.append(["Strongly disagree"] * 3)
            kinds.append("Survey Test")
        rows_ans.append(row)
        kinds.append(status[i])
    f = _csv(tmp_path / "qualtrics.csv", _qualtrics_rows(rows_ans, lambda i: kinds[i]))
    data = read_survey(f)
    assert data.shape == "qualtrics" and data.scale.name == "agree5-somewhat"
    assert data.stems == [STEM] * 3
    _check(summarize(data), real, AGREE5, STATEMENTS)
    reasons = Counter(d.reason for d in data.dropped)
    assert reasons == {"Survey Preview response": kinds.count("Survey Preview"),
                       "Survey Test response": kinds.count("Survey Test")}
    assert main(["summarize", str(f)]) == 0
    out = capsys.readouterr()
    assert f"{kinds.count('Survey Test')} Survey Test responses dropped" in out.err
    assert out.out.count(STEM) == 1                  # the stem is shown once
    html = tmp_path / "q.html"
    assert main(["report", str(f), "-o", str(html)]) == 0
    text = html.read_text()
    assert text.count(f'class="stem">{STEM}<') == 1 and f">{STATEMENTS[0]}<" in text
    # the statement names the item, the export's field id too
    assert read_survey(f, items=["Q1_2"]).items == [STATEMENTS[1]]
    assert read_survey(f, items=["The labs helped me, [really]"]).items == [STATEMENTS[1]]


def _qsf(reverse_listing=True):
    """A Qualtrics survey definition: matrix listing Strongly agree first, section MC."""
    listed = AGREE5[::-1] if reverse_listing else AGREE5
    return {"SurveyEntry": {"SurveyName": "Course survey"}, "SurveyElements": [
        {"Element": "BL", "Payload": []},
        {"Element": "SQ", "PrimaryAttribute": "QID1", "Payload": {
            "QuestionID": "QID1", "DataExportTag": "Q1", "QuestionType": "Matrix",
            "QuestionText": f"<p>{STEM}</p>",
            "Choices": {str(k + 1): {"Display": s} for k, s in enumerate(STATEMENTS)},
            "Answers": {str(k + 1): {"Display": lab} for k, lab in enumerate(listed)}}},
        {"Element": "SQ", "PrimaryAttribute": "QID2", "Payload": {
            "QuestionID": "QID2", "DataExportTag": "Q2", "QuestionType": "MC",
            "QuestionText": "Which section are you in?",
            "Choices": {"1": {"Display": "Section A"}, "2": {"Display": "Section B"}}}},
        {"Element": "SQ", "PrimaryAttribute": "QID3", "Payload": {
            "QuestionID": "QID3", "DataExportTag": "Q3", "QuestionType": "TE",
            "QuestionText": "Any comments?"}}]}


def test_qualtrics_numeric_export_maps_through_the_definition_or_refuses(tmp_path, capsys):
    real = _draw(2, 40, 3, AGREE5, na=0)
    # Qualtrics numbers answers in the order listed: Strongly agree first -> 1
    code = {lab: str(k + 1) for k, lab in enumerate(AGREE5[::-1])}
    coded = [[code[a] if a else "" for a in row] for row in real]
    section = ["1" if i % 3 else "2" for i in range(40)]
    f = _csv(tmp_path / "numeric.csv",
             _qualtrics_rows(coded, lambda i: "2" if i == 5 else "0", numeric=True,
                             section=section))
    real = real[:5] + real[6:]                # status 2 = Survey Test: dropped
    section = section[:5] + section[6:]
    for scale in ([], ["--scale", "agree5-somewhat"]):
        assert main(["summarize", str(f)] + scale) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "--codes" in err and ".qsf" in err
    qsf = tmp_path / "survey.qsf"
    qsf.write_text(json.dumps(_qsf()))
    data = read_survey(f, codes=qsf, group="Q2")
    assert data.items == STATEMENTS                    # the section question is no item
    _check(summarize(data), real, AGREE5, STATEMENTS)
    assert Counter(data.groups["Q2"]) == Counter("Section A" if s == "1" else "Section B"
                                                 for s in section)
    # an item with a 2:1 majority agreeing reads as agreeing, not reversed
    agree = [sum(r[0] in AGREE5[3:] for r in real), sum(r[0] in AGREE5[:2] for r in real)]
    it = summarize(data).items[0]
    assert (it.agree.k, it.disagree.k) == tuple(agree)


def test_qualtrics_legacy_two_header_rows(tmp_path):
    real = _draw(3, 12, 2, AGREE5)
    rows = [["V1", "V2", "V3", "V4", "V5", "V6", "V7", "V8", "V9", "V10", "Q1_1", "Q1_2"],
            ["ResponseID", "ResponseSet", "Name", "ExternalDataReference", "EmailAddress",
             "IPAddress", "Status", "StartDate", "EndDate", "Finished",
             f"{STEM}-{STATEMENTS[0]}", f"{STEM}-{STATEMENTS[2]}"]]
    for i, row in enumerate(real):
        rows.append([f"R_{i}", "Default Response Set", "Anonymous", "", "", "1.2.3.4", "0",
                     "2014-01-01 10:00:00", "2014-01-01 10:10:00", "1"] + row)
    rows.insert(4, ["R_x", "Default Response Set", "", "", "", "", "1", "", "", "1",
                    "Strongly agree", "Strongly agree"])          # a preview (status 1)
    data = read_survey(_csv(tmp_path / "legacy.csv", rows))
    assert data.shape == "qualtrics" and [d.row for d in data.dropped] == [5]
    _check(summarize(data), real, AGREE5, [STATEMENTS[0], STATEMENTS[2]])


# ---------------------------------------------------------------------------
# SurveyMonkey
# ---------------------------------------------------------------------------
def _surveymonkey_rows(real):
    meta = ["Respondent ID", "Collector ID", "Start Date", "End Date", "IP Address",
            "Email Address", "First Name", "Last Name", "Custom Data 1"]
    head = meta + [STEM, "", "", "What is your major?"]
    second = [""] * len(meta) + STATEMENTS + ["Response"]
    rows = [head, second]
    for i, row in enumerate(real):
        rows.append([str(11000000000 + i), "400000001", "03/01/2024 10:00:00 AM",
                     "03/01/2024 10:05:00 AM", "10.0.0.2", "", "", "", ""] + row
                    + ["Physics" if i % 2 else "Maths"])
    return rows


@pytest.mark.parametrize("kind", ["csv", "xlsx"])
def test_surveymonkey_two_header_rows_and_matrix(tmp_path, kind):
    real = _draw(4, 25, 3, AGREE5[:1] + ["Disagree", "Neither agree nor disagree", "Agree"]
                 + AGREE5[4:])
    rows = _surveymonkey_rows(real)
    if kind == "csv":
        f = _csv(tmp_path / "monkey.csv", rows)
    else:
        f = tmp_path / "monkey.xlsx"
        wb = openpyxl.Workbook()
        for r in rows:
            wb.active.append([c if c != "" else None for c in r])
        wb.save(f)
    data = read_survey(f)
    assert data.shape == "surveymonkey" and data.scale.name == "agree5"
    assert data.stems == [STEM] * 3
    _check(summarize(data), real, list(BUILTIN_SCALES["agree5"].labels), STATEMENTS)
    assert "What is your major?" in data.other_columns


# ---------------------------------------------------------------------------
# Canvas, LimeSurvey, Moodle, Microsoft Forms, Google grids
# ---------------------------------------------------------------------------
def test_canvas_student_analysis_four_point(tmp_path, capsys):
    real = _draw(5, 20, 3, ["Strongly Agree", "Agree", "Disagree", "Strongly Disagree"], na=0)
    head = ["name", "id", "sis_id", "section", "section_id", "section_sis_id", "submitted",
            "attempt"]
    for k, s in enumerate(STATEMENTS):
        head += [f"{7001 + k}: {s}", "1.0"]
    head += ["n correct", "n incorrect", "score"]
    rows = [head]
    for i, row in enumerate(real):
        r = [f"Student {i}", str(500 + i), f"S{i}", "PHYS 101 - 01", "42", "", "2024-03-01",
             "1"]
        for a in row:
            r += [a, "0.0" if a == "" else "1.0"]
        rows.append(r + ["3", "0", "3.0"])
    f = _csv(tmp_path / "canvas.csv", rows)
    data = read_survey(f)
    assert data.shape == "canvas" and data.scale.name == "agree4"
    s = summarize(data)
    _check(s, real, AGREE4, STATEMENTS)
    # medians on codes 1..4: numpy on the expanded codes of the tally
    code = {lab.casefold(): k + 1 for k, lab in enumerate(AGREE4)}
    for j, it in enumerate(s.items):
        x = [code[r[j].casefold()] for r in real if r[j]]
        assert it.median == np.median(x) and it.neutral.k == 0


def test_limesurvey_full_text_and_codes_with_definition(tmp_path):
    real = _draw(6, 15, 2, AGREE5)
    meta = ["Response ID", "Date submitted", "Last page", "Start language", "Seed"]
    text_head = meta + [f"{STEM} [{STATEMENTS[0]}]", f"{STEM} [{STATEMENTS[1]}]"]
    rows = [text_head] + [[str(i), "2024-03-01", "2", "en", "123"] + r for i, r in enumerate(real)]
    data = read_survey(_csv(tmp_path / "lime_text.csv", rows))
    assert data.shape == "limesurvey" and data.stems == [STEM, STEM]
    _check(summarize(data), real, AGREE5, STATEMENTS[:2])
    # answer codes A1..A5 with code headings: refused alone, read through the .lss
    code = {lab: f"A{k + 1}" for k, lab in enumerate(AGREE5)}
    rows = [["id", "submitdate", "lastpage", "startlanguage", "seed", "Q1[SQ001]", "Q1[SQ002]"]]
    rows += [[str(i), "2024-03-01", "2", "en", "123"] + [code.get(a, a) for a in r]
             for i, r in enumerate(real)]
    f = _csv(tmp_path / "lime_codes.csv", rows)
    lss = tmp_path / "survey.lss"
    answers = "".join(f"<row><qid>10</qid><code>A{k + 1}</code><answer>{lab}</answer>"
                      f"<sortorder>{k}</sortorder></row>" for k, lab in enumerate(AGREE5))
    subs = "".join(f"<row><qid>{11 + k}</qid><parent_qid>10</parent_qid><title>SQ00{k + 1}"
                   f"</title><question>{s.replace('[', '').replace(']', '')}</question></row>"
                   for k, s in enumerate(STATEMENTS[:2]))
    lss.write_text(f"<?xml version='1.0' encoding='UTF-8'?><document><LimeSurveyDocType>Survey"
                   f"</LimeSurveyDocType><answers><rows>{answers}</rows></answers><questions>"
                   f"<rows><row><qid>10</qid><parent_qid>0</parent_qid><title>Q1</title>"
                   f"<question>{STEM}</question></row></rows></questions><subquestions><rows>"
                   f"{subs}</rows></subquestions></document>")
    data = read_survey(f, codes=lss)
    _check(summarize(data), real, AGREE5,
           [s.replace("[", "").replace("]", "") for s in STATEMENTS[:2]])


def test_moodle_questionnaire_and_msforms(tmp_path):
    real = _draw(7, 10, 2, ["Never", "Rarely", "Sometimes", "Often", "Always"])
    head = ["Response", "Submitted on:", "Institution", "Department", "Course", "Group", "ID",
            "Full name", "Username", f"Q01_rate->{STATEMENTS[0]}", f"Q01_rate->{STATEMENTS[2]}"]
    rows = [head] + [[str(i + 1), "1 March 2024", "", "", "PHYS101", "", str(9 + i),
                      f"Student {i}", f"s{i}"] + r for i, r in enumerate(real)]
    data = read_survey(_csv(tmp_path / "moodle.csv", rows))
    assert data.shape == "moodle"
    _check(summarize(data), real, ["Never", "Rarely", "Sometimes", "Often", "Always"],
           [STATEMENTS[0], STATEMENTS[2]])
    f = tmp_path / "forms.xlsx"
    wb = openpyxl.Workbook()
    wb.active.append(["ID", "Start time", "Completion time", "Email", "Name",
                      "Last modified time", STATEMENTS[0], STATEMENTS[2]])
    real = _draw(8, 9, 2, AGREE5, na=0)
    for i, r in enumerate(real):
        wb.active.append([i + 1, "3/1/24 10:00:00", "3/1/24 10:03:00", "anonymous", None, None]
                         + [a or None for a in r])
    wb.save(f)
    data = read_survey(f)
    assert data.shape == "msforms"
    _check(summarize(data), real, AGREE5, [STATEMENTS[0], STATEMENTS[2]])


def test_google_grid_names_by_row_and_literal_brackets(tmp_path, capsys):
    real = _draw(9, 8, 3, AGREE5, na=0)
    head = ["Timestamp", "Email Address"] + [f"{STEM} [{s}]" for s in STATEMENTS]
    rows = [head] + [["2024/03/01 10:00:00 AM GMT", f"p{i}@x.org"] + r
                     for i, r in enumerate(real)]
    f = _csv(tmp_path / "google.csv", rows)
    data = read_survey(f)
    assert data.stems == [STEM] * 3
    _check(summarize(data), real, AGREE5, STATEMENTS)
    # brackets in a pattern are literal: "[The labs...]" is not a character set
    assert read_survey(f, items=[f"*[{STATEMENTS[1]}]"]).items == [STATEMENTS[1]]
    assert read_survey(f, items=["*[The lec*"]).items == STATEMENTS[:1]   # no set of letters


# ---------------------------------------------------------------------------
# command line: forced shapes, swallowed file names, chart formats
# ---------------------------------------------------------------------------
def test_forced_shape_that_does_not_fit_is_an_error(tmp_path, capsys):
    f = _csv(tmp_path / "wide.csv", [["id", "Q1"], ["1", "Agree"], ["2", "Disagree"],
                                     ["3", "Agree"]])
    for shape in ("qualtrics", "surveymonkey", "canvas", "google"):
        assert main(["summarize", str(f), "--shape", shape]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and f"--shape {shape} does not fit" in err
    with pytest.raises(SurveyInputError, match="does not fit"):
        read_survey(f, shape="qualtrics")


def test_list_options_do_not_swallow_the_file(tmp_path, capsys):
    f = _csv(tmp_path / "w.csv", [["Q1", "Q2", "Q3"]] + _draw(10, 12, 3, AGREE5, na=0))
    assert main(["summarize", "--items", "Q1", "Q2", str(f), "--json"]) == 0
    assert [it["item"] for it in json.loads(capsys.readouterr().out)["items"]] == ["Q1", "Q2"]
    assert main(["summarize", "--reliability", str(f), "--json"]) == 0
    assert "reliability" in json.loads(capsys.readouterr().out)
    assert main(["summarize", "--items", str(f)]) == 2
    assert capsys.readouterr().err.count("\n") == 1


@pytest.mark.parametrize("suffix,magic", [(".png", b"\x89PNG"), (".pdf", b"%PDF"),
                                          (".svg", b"<svg")])
def test_chart_format_follows_suffix(tmp_path, suffix, magic):
    f = _csv(tmp_path / "w.csv", [["Q1"]] + _draw(11, 6, 1, AGREE5, na=0))
    out = tmp_path / f"chart{suffix}"
    assert main(["summarize", str(f), "--chart", str(out)]) == 0
    assert out.read_bytes().startswith(magic)


def test_chart_with_unknown_suffix_is_refused(tmp_path, capsys):
    f = _csv(tmp_path / "w.csv", [["Q1"]] + _draw(11, 6, 1, AGREE5, na=0))
    assert main(["summarize", str(f), "--chart", str(tmp_path / "c.gif")]) == 2
    assert "--chart" in capsys.readouterr().err and not (tmp_path / "c.gif").exists()


# ---------------------------------------------------------------------------
# an export that lost one of its header rows (the tester's files, rows deleted)
# ---------------------------------------------------------------------------
SM_HEAD = ["Respondent ID", "Collector ID", "Start Date", "End Date", "IP Address",
           "Email Address", "First Name", "Last Name", "Custom Data 1",
           "How much do you agree with the following?", "", "Would you recommend this course?"]
SM_ANSWERS = [["114001", "4321", "01/10/2024 10:00:00 AM", "01/10/2024 10:05:00 AM",
               "1.1.1.1", "", "", "", "", "Agree", "Strongly agree", "Agree"],
              ["114002", "4321", "01/10/2024 10:00:00 AM", "01/10/2024 10:05:00 AM",
               "1.1.1.2", "", "", "", "", "Disagree", "", "Strongly disagree"]]
Q_ROWS = [["StartDate", "EndDate", "Status", "ResponseId", "Q1_1", "Q1_2"],
          ["Start Date", "End Date", "Response Type", "Response ID",
           "How much do you agree? - The method is clear",
           "How much do you agree? - The method is useful"],
          ['{"ImportId":"startDate"}', '{"ImportId":"endDate"}', '{"ImportId":"status"}',
           '{"ImportId":"_recordId"}', '{"ImportId":"QID1_1"}', '{"ImportId":"QID1_2"}'],
          ["2024-01-01", "2024-01-01", "IP Address", "R_1", "Strongly agree", "Agree"],
          ["2024-01-01", "2024-01-01", "IP Address", "R_2", "Agree", "Disagree"]]


@pytest.mark.parametrize("case, expect", [
    ("sm-csv", "SurveyMonkey's second header row (the statements row) is missing: row 2 "
               "holds answers (Respondent ID '114001')"),
    ("sm-xlsx", "SurveyMonkey's second header row (the statements row) is missing: row 2 "
                "holds answers (Respondent ID '114001')"),
    ("sm-no-id", "SurveyMonkey's second header row (the statements row) is missing: row 2 "
                 "holds answers (the answer 'Agree')"),
    ("q-no-text", "Qualtrics' question-text header row is missing: row 2 holds the "
                  "{\"ImportId\": ...} row"),
    ("q-no-import", "Qualtrics' third header row ({\"ImportId\": ...}) is missing: row 2 "
                    "holds question text but row 3 holds answers")])
def test_export_missing_a_header_row_is_refused(tmp_path, capsys, case, expect):
    # SurveyMonkey without its statements row: respondent 114001's answers stand where
    # the statements were (the old reader named an item 'Strongly agree' and counted 1
    # respondent of 2); Qualtrics without row 2 or 3 was read as a plain table and
    # refused for an answer '{"ImportId":...}' or a question text not on the scale.
    if case.startswith("sm"):
        rows = [SM_HEAD] + [list(r) for r in SM_ANSWERS]
        if case == "sm-no-id":
            rows[1][0] = rows[1][1] = ""
    else:
        rows = [r for i, r in enumerate(Q_ROWS) if i != (1 if case == "q-no-text" else 2)]
    if case == "sm-xlsx":
        f = tmp_path / "x.xlsx"
        wb = openpyxl.Workbook()
        for r in rows:
            wb.active.append([c if c != "" else None for c in r])
        wb.save(f)
    else:
        f = _csv(tmp_path / "x.csv", rows)
    assert main(["summarize", str(f)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and str(f) in err and expect in err


def test_whole_exports_with_all_header_rows_still_read(tmp_path):
    # the same fixtures with every header row: 2 SurveyMonkey respondents (the statements
    # row restored), 2 Qualtrics respondents
    sm = [SM_HEAD, [""] * 9 + ["The lectures were clear", "The homework helped", "Response"]]
    data = read_survey(_csv(tmp_path / "sm.csv", sm + SM_ANSWERS))
    assert data.shape == "surveymonkey" and data.respondents == 2
    assert data.items[:2] == ["The lectures were clear", "The homework helped"]
    data = read_survey(_csv(tmp_path / "q.csv", Q_ROWS))
    assert data.shape == "qualtrics" and data.respondents == 2


CANVAS_HEAD = ["name", "id", "sis_id", "section", "section_id", "section_sis_id", "submitted",
               "attempt", "101: The lectures were clear", "1.0", "102: The homework helped",
               "1.0", "n correct", "n incorrect", "score"]


def _canvas_row(name, pid, sis, attempt, a, b):
    return [name, pid, sis, "Sec A", "10", "", "2024-01-10 10:00:00 UTC", attempt, a, "0.0",
            b, "0.0", "0", "0", "0"]


def test_canvas_counts_each_students_latest_attempt_once(tmp_path, capsys):
    # the tester's canvas2.csv with Bob's attempts in the other order: the latest
    # attempt (2, row 3) counts and attempt 1 (row 4) is set aside although it comes
    # later in the file. By hand: 2 respondents (Ann, Bob); 'The lectures were clear'
    # Agree 2 (Ann, Bob's attempt 2), Strongly disagree 0 (was 1: attempt 1 counted).
    rows = [CANVAS_HEAD, _canvas_row("Ann", "1", "s1", "1", "Agree", "Agree"),
            _canvas_row("Bob", "2", "s2", "2", "Agree", "Agree"),
            _canvas_row("Bob", "2", "s2", "1", "Strongly disagree", "Disagree")]
    f = _csv(tmp_path / "canvas.csv", rows)
    data = read_survey(f)
    assert data.respondents == 2 and list(data.rows) == [2, 3]
    assert [(d.row, d.reason) for d in data.dropped] == [(4, "earlier attempt")]
    assert "latest attempt" in data.dropped[0].why
    s = summarize(data)
    assert s.items[0].counts == {"Strongly disagree": 0, "Disagree": 0, "Agree": 2,
                                 "Strongly agree": 0}
    assert s.items[1].counts["Disagree"] == 0 and s.items[1].n == 2
    # which attempt is the latest cannot be told from a non-number: refused, not guessed
    rows[3][7] = "first"
    f = _csv(tmp_path / "canvas_bad.csv", rows)
    assert main(["summarize", str(f)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"{f}: row 4, column 'attempt': attempt 'first'" in err


def test_canvas_drop_line_says_what_was_dropped_and_why(tmp_path, capsys):
    """New-user report: the summary of dropped rows said "(not respondents)", which is wrong for a
    Canvas student's earlier attempt (the student is a respondent, counted once). By hand: Bob's
    attempts 1 and 2 (rows 3, 4) give way to attempt 3 (row 5); Ann and Bob count once each."""
    rows = [CANVAS_HEAD, _canvas_row("Ann", "1", "s1", "1", "Agree", "Agree"),
            _canvas_row("Bob", "2", "s2", "2", "Agree", "Agree"),
            _canvas_row("Bob", "2", "s2", "1", "Strongly disagree", "Disagree"),
            _canvas_row("Bob", "2", "s2", "3", "Agree", "Disagree")]
    f = _csv(tmp_path / "canvas.csv", rows)
    assert main(["summarize", str(f)]) == 0
    err = capsys.readouterr().err
    assert "not respondents" not in err and "set aside" not in err  # said once, in the drop line
    assert (f"note: {f}: 2 earlier attempts dropped in all: a student who took the survey more "
            "than once (same id and sis_id) is counted once, with the answers of the latest attempt\n") in err


def test_limesurvey_incomplete_responses_are_counted_with_a_note(tmp_path):
    # the tester's lime.csv: response 3 was never submitted (blank submitdate, row 4).
    # By hand: 3 respondents; Q1[SQ001] n = 3 (Agree, Disagree, Strongly agree);
    # Q1[SQ002] n = 2, 1 missing (response 3 stopped on page 1).
    rows = [["id", "submitdate", "lastpage", "startlanguage", "seed", "Q1[SQ001]",
             "Q1[SQ002]", "Q2"],
            ["1", "2024-01-10 10:00:00", "2", "en", "123", "Agree", "Strongly agree",
             "Disagree"],
            ["2", "2024-01-10 10:00:00", "2", "en", "124", "Disagree", "Agree", "Agree"],
            ["3", "", "1", "en", "125", "Strongly agree", "", ""]]
    data = read_survey(_csv(tmp_path / "lime.csv", rows))
    assert data.shape == "limesurvey" and data.respondents == 3 and not data.dropped
    assert [n for n in data.notes if "incomplete" in n] == [
        f"{tmp_path / 'lime.csv'}: 1 incomplete response (blank 'submitdate', row 4) "
        "counted with the answers given"]
    s = summarize(data)
    assert (s.items[0].n, s.items[1].n, s.items[1].missing) == (3, 2, 1)


def test_canvas_points_columns_listed_by_their_names_in_the_file(tmp_path):
    """Regression: the two '1.0' points columns (columns 10 and 12 of CANVAS_HEAD) were
    listed as '1.0, 1.0.1', a name the file does not have."""
    f = _csv(tmp_path / "canvas.csv", [CANVAS_HEAD, _canvas_row("Ann", "1", "s1", "1", "Agree",
                                                                "Agree")])
    others = read_survey(f).other_columns
    assert "1.0 in column 10" in others and "1.0 in column 12" in others
    assert not any("1.0.1" in c for c in others)


def test_qualtrics_statement_shared_by_two_matrices_keeps_its_text(tmp_path):
    """Regression: 'Before this course - The pace was right' and 'After this course - The
    pace was right' share a statement, and both matrices were named only Q1_1 .. Q2_2."""
    rows = [["StartDate", "Status", "ResponseId", "Q1_1", "Q1_2", "Q2_1", "Q2_2"],
            ["Start Date", "Response Type", "Response ID",
             "Before this course - The pace was right", "Before this course - Slides were clear",
             "After this course - The pace was right", "After this course - Slides were clear"],
            ['{"ImportId":"startDate"}', '{"ImportId":"status"}', '{"ImportId":"_recordId"}',
             '{"ImportId":"QID1_1"}', '{"ImportId":"QID1_2"}', '{"ImportId":"QID2_1"}',
             '{"ImportId":"QID2_2"}']]
    rows += [["2024-01-01", "IP Address", f"R_{i}", "Agree", "Disagree", "Agree", "Agree"]
             for i in range(3)]
    data = read_survey(_csv(tmp_path / "q.csv", rows))
    assert data.items == ["Before this course - The pace was right",
                          "Before this course - Slides were clear",
                          "After this course - The pace was right",
                          "After this course - Slides were clear"]
    assert data.fields == ["Q1_1", "Q1_2", "Q2_1", "Q2_2"]      # still selectable by id


def test_group_takes_a_qualtrics_question_by_its_text(tmp_path, capsys):
    """QA 16 #8: the tool prints Qualtrics' Q2 by its text, but ``--group`` took only the field
    id. Both now give the same comparison, named as typed. By hand: rows 0-5 in 'Sec A'
    (6 respondents), rows 6-11 in 'Sec B' (6)."""
    ans = [[AGREE5[(i + k) % 5] for k in range(3)] for i in range(12)]
    f = _csv(tmp_path / "q.csv", _qualtrics_rows(ans, lambda i: "IP Address",
                                                 section=["Sec A"] * 6 + ["Sec B"] * 6))
    got = {}
    for name in ("Q2", "which section are you in?"):
        assert main(["summarize", str(f), "--group", name, "--json"]) == 0
        out = json.loads(capsys.readouterr().out)["groups"]
        assert out["column"] == {"Q2": "Q2"}.get(name, "Which section are you in?")
        got[name] = [(g["group"], g["respondents"]) for g in out["groups"]]
    assert got["Q2"] == got["which section are you in?"] == [("Sec A", 6), ("Sec B", 6)]
    assert main(["summarize", str(f), "--group", "Section"]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"error: {f}: row 1: no column 'Section'; columns are [") and (
        "question texts are [" in err and "'Which section are you in?'" in err), err


def test_group_by_a_question_text_two_questions_share_is_called_ambiguous(tmp_path, capsys):
    """QA 18 #8: when Q2 and Q3 share the text 'Section' (each then named by its field id),
    ``--group Section`` was refused as 'no column'. It is ambiguous: the line names both
    columns, and either field id is taken."""
    ans = [[AGREE5[(i + k) % 5] for k in range(3)] for i in range(12)]
    rows = _qualtrics_rows(ans, lambda i: "IP Address", section=["Sec A"] * 6 + ["Sec B"] * 6)
    rows[1][-2:] = ["Section", "Section"]
    f = _csv(tmp_path / "q.csv", rows)
    assert main(["summarize", str(f), "--group", "section"]) == 2
    err = capsys.readouterr().err
    assert err == (f"error: {f}: row 1: 'section' is the question text of columns "
                   "['Q2', 'Q3']; name one of them\n"), err
    assert main(["summarize", str(f), "--group", "Q2", "--json"]) == 0
    got = json.loads(capsys.readouterr().out)["groups"]["groups"]
    assert [(g["group"], g["respondents"]) for g in got] == [("Sec A", 6), ("Sec B", 6)]


def test_unfinished_qualtrics_responses_are_counted_with_a_note(tmp_path):
    """QA 16 #9: rows with Finished = False were counted unsaid, while LimeSurvey's
    incomplete responses get a note. Rows here: 3 header rows, responses in rows 4-9; the
    ones at i = 1 and 4 (rows 5 and 8) are unfinished. In a numeric export Finished is 0,
    and the note says 0, as the file writes it."""
    ans = [[AGREE5[(i + k) % 5] for k in range(3)] for i in range(6)]
    for numeric in (False, True):
        rows = _qualtrics_rows(ans, lambda i: "0" if numeric else "IP Address", numeric)
        for i in (1, 4):
            rows[3 + i][6] = "0" if numeric else "False"
        f = _csv(tmp_path / "q.csv", rows)
        if numeric:
            book = tmp_path / "codes.toml"
            book.write_text("[codes]\n" + "".join(f'{k + 1} = "{lab}"\n'
                                                  for k, lab in enumerate(AGREE5)))
            rows = [r[:10] + [str(AGREE5.index(a) + 1) for a in r[10:13]] + r[13:]
                    if k > 2 else r for k, r in enumerate(rows)]
            f = _csv(tmp_path / "q.csv", rows)
        data = read_survey(f, codes=book if numeric else None)
        assert data.respondents == 6 and not data.dropped
        # QA 18 #9: the value as the file writes it (a numeric export's 0 was called False)
        assert [n for n in data.notes if "incomplete" in n] == [
            f"{f}: 2 incomplete responses ('Finished' = {'0' if numeric else 'False'}, rows "
            "5, 8) counted with the answers given"], data.notes
