"""Institution-scale counting (DuckDB, out of core) agrees with a tally and with ``summarize``.

References: answers drawn here are tallied per (course, term, item) with ``Counter``; the
institution-wide distribution must equal the small-file route (``read_survey`` +
``summarize``) on the same file, item by item.
"""
import csv
import json
import random
from collections import Counter

import pytest

from analysis.__main__ import main
from analysis.errors import SurveyInputError
from analysis.institution import summarize_by
from analysis.scales import BUILTIN_SCALES

AGREE5 = list(BUILTIN_SCALES["agree5"].labels)
ITEMS = ["Q1", "Q2", "Q3"]


def _long(tmp_path, seed=1, n=120):
    rng = random.Random(seed)
    rows = []
    for r in range(n):
        course, term = rng.choice(["C1", "C2", "C3"]), rng.choice(["2024FA", "2025SP"])
        for q in ITEMS:
            if rng.random() < 0.1:
                continue                                 # no row: missing
            a = "" if rng.random() < 0.05 else "N/A" if rng.random() < 0.03 else rng.choice(AGREE5)
            rows.append([course, term, f"r{r}", q, a])
    rows.append(["C9", "2025SP", "lonely", "Q1", "Agree"])   # a group of one: suppressed
    # and one of four: suppressed; pooled the two hold five, so no other group is withheld
    rows += [["C8", "2025SP", f"few{k}", "Q1", "Disagree"] for k in range(4)]
    f = tmp_path / "long.csv"
    with open(f, "w", newline="") as fh:
        csv.writer(fh).writerows([["course", "term", "respondent", "item", "answer"]] + rows)
    return f, rows


def test_long_file_by_course_and_term_matches_a_tally(tmp_path):
    f, rows = _long(tmp_path)
    res = summarize_by(f, ["course", "term"])
    assert res.shape == "long" and res.scale.name == "agree5" and res.items == ITEMS
    people = {}
    for c, t, r, q, a in rows:
        people.setdefault((c, t), set()).add(r)
    for g, key in enumerate(res.groups):
        assert res.respondents[g] == len(people[key])
        for i, it in enumerate(res.group_summaries(g)):
            cells = Counter(a for c, t, r, q, a in rows if (c, t) == key and q == ITEMS[i])
            assert it.counts == {lab: cells.get(lab, 0) for lab in AGREE5}
            assert it.excluded == cells.get("N/A", 0)
            # blank answers plus respondents of the group with no row for the item
            assert it.missing == cells.get("", 0) + len(people[key]) - sum(cells.values())
    sup = [r for r in res.rows() if r.get("suppressed")]
    assert [(r["course"], r["term"]) for r in sup] == [("C8", "2025SP"), ("C9", "2025SP")]


def test_overall_equals_the_small_file_route_and_parquet_equals_csv(tmp_path, capsys):
    f, _ = _long(tmp_path, seed=2)
    assert main(["summarize", str(f), "--json"]) == 0
    small = json.loads(capsys.readouterr().out)["items"]
    assert main(["summarize", str(f), "--by", "term", "--json"]) == 0
    big = json.loads(capsys.readouterr().out)
    assert big["overall"] == small
    import duckdb
    pq = tmp_path / "long.parquet"
    duckdb.sql(f"COPY (SELECT * FROM read_csv('{f}', all_varchar=true)) TO '{pq}' "
               "(FORMAT parquet)")
    a, b = summarize_by(f, ["course", "term"]), summarize_by(pq, ["course", "term"])
    assert a.groups == b.groups and (a.tallies == b.tallies).all()
    # a memory limit DuckDB cannot work in is raised and retried, with the same counts
    c = summarize_by(f, ["course", "term"], memory_limit="1MB")
    assert (c.tallies == a.tallies).all()


def test_wide_file_and_refusals(tmp_path, capsys):
    rng = random.Random(3)
    rows = [["section", "Student ID", *ITEMS]]
    rows += [[rng.choice("AB"), str(i)] + [rng.choice(AGREE5 + [""]) for _ in ITEMS]
             for i in range(40)]
    f = tmp_path / "wide.csv"
    with open(f, "w", newline="") as fh:
        csv.writer(fh).writerows(rows)
    res = summarize_by(f, ["section"])
    assert res.shape == "wide" and res.items == ITEMS
    for g, (sec,) in enumerate(res.groups):
        for i, it in enumerate(res.group_summaries(g)):
            cells = Counter(r[2 + i] for r in rows[1:] if r[0] == sec)
            assert (it.counts, it.missing) == ({lab: cells.get(lab, 0) for lab in AGREE5},
                                               cells.get("", 0))
    coded = tmp_path / "coded.csv"
    coded.write_text("term,Q1\nA,1\nA,5\nB,3\n")
    with pytest.raises(SurveyInputError, match="numeric codes"):
        summarize_by(coded, ["term"])
    assert main(["summarize", str(f), "--by", "nosuch"]) == 2
    assert "--by 'nosuch'" in capsys.readouterr().err


def _parquet_with_names(path, first, second):
    """A Parquet file whose two answer columns are named ``first`` and ``second``.

    DuckDB writes distinct names only, so the file is written with the placeholders QAAA
    and QBBB, which are then replaced in the footer's schema (same length: the Thrift
    strings keep their sizes; the data pages, holding only answers, are untouched)."""
    import duckdb
    con = duckdb.connect()
    con.execute(f"COPY (SELECT * FROM (VALUES ('C1', 'Disagree', 'Agree'), "
                f"('C1', 'Agree', 'Agree')) AS t(course, QAAA, QBBB)) TO '{path}' "
                f"(FORMAT parquet)")
    con.close()
    data = path.read_bytes()
    assert data.count(b"QAAA") == data.count(b"QBBB") == 2      # schema + column chunk
    path.write_bytes(data.replace(b"QAAA", first.encode()).replace(b"QBBB", second.encode()))
    return path


def test_repeated_column_names_refused_out_of_core(tmp_path, capsys):
    """The DuckDB route reads the names as written and refuses two columns named alike,
    as the in-memory route does (DuckDB itself renames a repeated Q1 to Q1_1).
    A real column named Q1.1 is counted as itself (by hand: C1 answers Disagree, Agree to
    Q1 and Agree, Agree to Q1.1)."""
    dup = tmp_path / "dup.csv"
    dup.write_text("course,Q1,Q1\nC1,Disagree,Agree\nC1,Agree,Agree\n")
    pq = _parquet_with_names(tmp_path / "dup.parquet", "Q1xx", "Q1xx")
    for path in (dup, pq):
        assert main(["summarize", str(path), "--by", "course"]) == 2
        err = capsys.readouterr().err
        name = "Q1" if path is dup else "Q1xx"
        assert err == f"error: {path}: columns 2 and 3 are both named {name!r}; rename one\n"
    for path in (tmp_path / "ok.csv", _parquet_with_names(tmp_path / "ok.parquet", "Q1xx", "Q1.1")):
        if path.suffix == ".csv":
            path.write_text("course,Q1xx,Q1.1\nC1,Disagree,Agree\nC1,Agree,Agree\n")
        res = summarize_by(path, ["course"], scale="agree5")
        assert res.items == ["Q1xx", "Q1.1"]
        counts = {it.item: it.counts for it in res.overall()}
        assert (counts["Q1xx"]["Disagree"], counts["Q1xx"]["Agree"]) == (1, 1)
        assert counts["Q1.1"]["Agree"] == 2


# The tester's survey3.csv: sections A and B of six respondents, C of two.
SURVEY3 = """id,Section,Q1,Q2,Q3,Q4,Q5
1,A,Strongly agree,Agree,Disagree,Neutral,Strongly agree
2,A,Agree,Agree,Strongly disagree,Agree,
3,A,Neutral,,Agree,Agree,Agree
4,A,Agree,Strongly agree,Disagree,Strongly agree,Agree
5,A,Strongly disagree,Disagree,Strongly agree,Disagree,Neutral
6,A,Agree,Neutral,Neutral,Agree,Agree
7,B,Disagree,Disagree,Agree,Neutral,Disagree
8,B,Neutral,Agree,Strongly disagree,,Neutral
9,B,Strongly agree,Strongly agree,Disagree,Agree,Agree
10,B,Agree,Neutral,Neutral,Strongly disagree,
11,B,Disagree,Disagree,Agree,Neutral,Disagree
12,B,,Agree,Disagree,Agree,Strongly agree
13,C,Strongly disagree,Strongly disagree,Strongly disagree,Strongly disagree,Strongly disagree
14,C,Strongly disagree,Strongly disagree,Strongly disagree,Strongly disagree,Strongly disagree
"""


def test_by_honours_reverse_interval_and_declared_respondents(tmp_path, capsys):
    """--by applies --reverse, --ci, --confidence and --respondents as the in-memory route.

    By hand, Q3 over all 14 respondents: SD 4, D 4, N 2, A 3, SA 1. Reversed codes
    (SD=5 .. SA=1) sum to 4*5 + 4*4 + 2*3 + 3*2 + 1*1 = 49, mean 49/14 = 3.5; sorted they
    are 1 2 2 2 3 3 4 | 4 4 4 5 5 5 5, median 4. Q1 overall: 6 agree of 13 answers, one
    blank. The Clopper-Pearson interval at 50 % is the 25 % quantile of Beta(6, 13 - 6 + 1)
    and the 75 % quantile of Beta(6 + 1, 13 - 6) (scipy.stats.beta, not the product's
    statsmodels route).
    """
    from scipy.stats import beta
    f = tmp_path / "survey3.csv"
    f.write_text(SURVEY3)
    assert main(["summarize", str(f), "--by", "Section", "--reverse", "Q3", "--ci", "beta",
                 "--confidence", "0.5", "--respondents", "20", "--min-group", "2",
                 "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert (out["ci_method"], out["confidence_level"], out["reversed"]) == ("beta", 0.5, ["Q3"])
    q1, q3 = out["overall"][0], out["overall"][2]
    assert (q3["mean"], q3["median"]) == (3.5, 4.0)
    # 14 answered the file, 20 declared: the six absent are missing on every item
    assert (out["respondents"], q1["n"], q1["missing"], q3["missing"]) == (20, 13, 7, 6)
    lo, hi = beta.ppf(0.25, 6, 8), beta.ppf(0.75, 7, 7)
    # both are inverse incomplete beta functions to double precision: 1e-9 allows for
    # the two libraries' different iterations
    assert q1["agree"]["ci"] == pytest.approx([lo, hi], abs=1e-9)
    blank = [r for r in out["rows"] if r["Section"] == "(blank)" and r["item"] == "Q1"]
    assert [(r["respondents"], r["n"], r["missing"]) for r in blank] == [(6, 0, 6)]
    # text: the interval is named, the reversed item marked
    assert main(["summarize", str(f), "--by", "Section", "--reverse", "Q3", "--ci", "beta",
                 "--confidence", "0.5"]) == 0
    text = capsys.readouterr().out
    assert "50% Clopper-Pearson interval" in text and "(all): Q3 (R): " in text
    # a typo is refused, as the in-memory route refuses it
    assert main(["summarize", str(f), "--by", "Section", "--reverse", "NOPE"]) == 2
    assert "reverse-keyed item 'NOPE' is not an item" in capsys.readouterr().err
    assert main(["summarize", str(f), "--by", "Section", "--shape", "long"]) == 2
    assert capsys.readouterr().err.startswith("error: python -m analysis summarize: --shape is "
                                              "not available with --by")


def test_by_takes_the_items_the_in_memory_route_takes(tmp_path, capsys):
    """Regression: --by read the term and comments columns as items and refused the file.

    By hand: Q1 and Q2 hold agree4 labels; term holds F23/S24 and Comments holds one
    label ("Agree") among three answers, under the half the in-memory rule asks for, so
    neither is an item. Q1: SD 1, D 1, A 2, SA 0; Q2: D 1, A 1, SA 1 and one blank."""
    f = tmp_path / "m.csv"
    f.write_text("section,term,Q1,Q2,Comments\nA,F23,Agree,Disagree,good\n"
                 "B,S24,Disagree,,too fast\nA,S24,Agree,Strongly agree,\n"
                 "B,F23,Strongly disagree,Agree,Agree\n")
    want = {"Q1": ({"Strongly disagree": 1, "Disagree": 1, "Agree": 2, "Strongly agree": 0}, 0),
            "Q2": ({"Strongly disagree": 0, "Disagree": 1, "Agree": 1, "Strongly agree": 1}, 1)}
    assert main(["summarize", str(f), "--group", "section", "--min-group", "1", "--json"]) == 0
    small = json.loads(capsys.readouterr().out)
    assert main(["summarize", str(f), "--by", "section", "--min-group", "1", "--json"]) == 0
    big = json.loads(capsys.readouterr().out)
    for items in (small["items"], big["overall"]):
        assert {it["item"]: (it["counts"], it["missing"]) for it in items} == want
    assert small["not_items"] == big["not_items"] == ["section", "term", "Comments"]
    assert big["not_item_reasons"]["term"] == "its answers are not labels of scale 'agree4'"
    assert big["not_item_reasons"]["section"] == "grouping column"
    assert main(["summarize", str(f), "--by", "section", "--min-group", "1"]) == 0
    assert "not items (left out of the table): section (grouping column), term (its " in \
        capsys.readouterr().out


def test_blank_grouping_value_has_one_name_on_every_output(tmp_path, capsys):
    """Regression: --by --json named the blank section "" while its text and --group said
    "(blank)". By hand: two respondents with no section, one Agree and one Disagree."""
    f = tmp_path / "b.csv"
    f.write_text("section,Q1\nA,Agree\n,Agree\nA,Disagree\n,Disagree\n")
    assert main(["summarize", str(f), "--by", "section", "--min-group", "1", "--json"]) == 0
    rows = json.loads(capsys.readouterr().out)["rows"]
    blank = [r for r in rows if r["section"] not in ("(all)", "A")]
    assert [(r["section"], r["n"], r["Agree (count)"]) for r in blank] == [("(blank)", 2, 1)]
    table = tmp_path / "t.csv"
    assert main(["summarize", str(f), "--by", "section", "--min-group", "1",
                 "--table", str(table)]) == 0
    assert "\n(blank): Q1: n=2 " in capsys.readouterr().out
    assert "\n(blank),Q1," in table.read_text()
    assert main(["summarize", str(f), "--group", "section", "--min-group", "1", "--json"]) == 0
    groups = json.loads(capsys.readouterr().out)["groups"]["groups"]
    assert [g["group"] for g in groups] == ["A", "(blank)"]


def test_by_refuses_an_answer_given_twice_as_the_in_memory_route_does(tmp_path, capsys):
    """A (respondent, item) pair on two rows would be counted twice: counted + missing +
    excluded would exceed the respondents. Both routes refuse it naming the second row
    (spreadsheet row 5: header row 1, then r1 Q1, r1 Q2, r2 Q1, and r1's Q1 again)."""
    f = tmp_path / "dup.csv"
    f.write_text("respondent,course,item,answer\nr1,A,Q1,Agree\nr1,A,Q2,Agree\n"
                 "r2,A,Q1,Disagree\n r1 ,A,Q1 ,Disagree\n")
    want = f"{f}: row 5, column 'answer': respondent 'r1' answers item 'Q1' twice"
    for extra in ([], ["--by", "course"]):
        assert main(["summarize", str(f), *extra]) == 2
        assert capsys.readouterr().err.strip() == f"error: {want}"
    import duckdb
    pq = tmp_path / "dup.parquet"
    duckdb.sql(f"COPY (SELECT * FROM read_csv('{f}', all_varchar=true)) TO '{pq}' "
               "(FORMAT parquet)")
    with pytest.raises(SurveyInputError, match="row 5, column 'answer': respondent 'r1'"):
        summarize_by(pq, ["course"])
    # two pairs repeated: both routes name the one whose second row comes first (r1's,
    # row 4), whatever order respondents first appear in or hashes fall in
    two = tmp_path / "two.csv"
    two.write_text("respondent,course,item,answer\nr2,A,Q1,Agree\nr1,A,Q1,Agree\n"
                   "r1,A,Q1,Agree\nr2,A,Q1,Agree\n")
    want = f"{two}: row 4, column 'answer': respondent 'r1' answers item 'Q1' twice"
    for extra in ([], ["--by", "course"]):
        assert main(["summarize", str(two), *extra]) == 2
        assert capsys.readouterr().err.strip() == f"error: {want}"
    # a blank id or item name was counted (or its answer dropped) unsaid under --by
    for body, want in (("r1,A,Q1,Agree\n ,A,Q1,Agree\n", "row 3, column 'respondent': blank "
                        "respondent id"),
                       ("r1,A,Q1,Agree\nr2,A, ,Agree\n", "row 3, column 'item': blank item "
                        "name")):
        blank = tmp_path / "blank.csv"
        blank.write_text("respondent,course,item,answer\n" + body)
        for extra in ([], ["--by", "course"]):
            assert main(["summarize", str(blank), *extra]) == 2
            assert capsys.readouterr().err.strip() == f"error: {blank}: {want}"


@pytest.mark.parametrize("shape", ["wide", "long"])
def test_by_merges_spellings_of_a_group_value_as_group_does(tmp_path, capsys, shape):
    """'Sec 1', 'sec 1 ' and 'Sec  1' are one group of 5 under --group; --by must agree
    (named by the commonest spelling), not make three suppressed groups."""
    secs = ["Sec 1", "Sec 1", "Sec 1", "sec 1 ", "Sec  1"] + ["Sec 2"] * 5
    f = tmp_path / "g.csv"
    if shape == "wide":
        rows = [["Section", "Q1"]] + [[s, "Agree"] for s in secs]
    else:
        rows = [["respondent", "Section", "item", "answer"]]
        rows += [[f"r{i}", s, q, "Agree"] for i, s in enumerate(secs) for q in ("Q1", "Q2")]
    with open(f, "w", newline="") as fh:
        csv.writer(fh).writerows(rows)
    res = summarize_by(f, ["Section"])
    assert res.groups == [("Sec 1",), ("Sec 2",)]
    assert res.respondents.tolist() == [5, 5]
    assert main(["summarize", str(f), "--group", "Section", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)["groups"]["groups"]
    sizes = {g["group"]: g["respondents"] for g in out}
    assert sizes == {"Sec 1": 5, "Sec 2": 5}


def test_by_errors_name_the_place_and_the_real_cause(tmp_path, capsys):
    """Regressions: a Windows-1252 or UTF-16 file gave 'cannot read as CSV/Parquet (... CSV
    Error on Line: 1)'; a Qualtrics export's statement row was counted as answers ('answer
    "How much ... - The lectures were clear" is not on scale', no row); a typo answer was
    named without its row or column."""
    def err_of(path, *by):
        assert main(["summarize", str(path), "--by", *by]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and err.startswith(f"error: {path}: "), err
        return err
    cp = tmp_path / "cp.csv"        # 0x92 (a curly apostrophe): offset 11 + 8 + 4, row 3
    cp.write_bytes(b"Section,Q1\nA,Agree\nB it\x92s,Agree\n")
    assert "row 3: byte 0x92 at offset 23 is not UTF-8; --by reads UTF-8 only" in err_of(
        cp, "Section")
    u16 = tmp_path / "u16.csv"
    u16.write_bytes("Section,Q1\nA,Agree\n".encode("utf-16"))
    assert "row 1: UTF-16 text" in err_of(u16, "Section")
    q = tmp_path / "q.csv"
    with open(q, "w", newline="") as fh:
        csv.writer(fh).writerows([
            ["ResponseId", "Q1_1", "Section"],
            ["Response ID", "How much do you agree? - The lectures were clear", "Section"],
            ['{"ImportId":"_recordId"}', '{"ImportId":"QID1_1"}', '{"ImportId":"QID2"}'],
            ["R_1", "Agree", "A"]])
    assert "row 2: a Qualtrics export: rows 2-3 are header rows" in err_of(q, "Section")
    # the advice removes those rows only (it said "the rows below the first header row": every answer)
    assert err_of(q, "Section").rstrip().endswith("or delete rows 2-3 (and keep row 1 and the answers below)")
    typo = tmp_path / "typo.csv"    # header row 1; 'Agre' in row 3, column Q2
    typo.write_text("Term,Q1,Q2\nF,Agree,Disagree\nF,Agree,Agre\n")
    assert "row 3, column 'Q2': answer 'Agre' is not on scale" in err_of(typo, "Term")
    long = tmp_path / "long.csv"    # long: the answer column, row 4
    long.write_text("respondent,term,item,answer\nr1,F,Q1,Agree\nr1,F,Q2,Neutral\n"
                    "r2,F,Q2,Agre\n")
    assert "row 4, column 'answer': answer 'Agre' is not on scale" in err_of(long, "term")


@pytest.mark.parametrize("suffix", [".csv", ".xlsx"])
def test_by_table_writes_counts_as_whole_numbers(tmp_path, capsys, suffix):
    """Regression: with a suppressed group (blank counts) the count columns became floats
    and the CSV said '36.0'. Reference: the tally of the rows written by ``_long``."""
    f, rows = _long(tmp_path)
    out = tmp_path / f"t{suffix}"
    assert main(["summarize", str(f), "--by", "course", "term", "--table", str(out)]) == 0
    if suffix == ".csv":
        with open(out, encoding="utf-8-sig", newline="") as fh:
            table = list(csv.DictReader(fh))
    else:
        import openpyxl
        got = list(openpyxl.load_workbook(out).active.iter_rows(values_only=True))
        table = [dict(zip(got[0], r)) for r in got[1:]]
    q1 = next(r for r in table if r["course"] == "(all)" and r["item"] == "Q1")
    answered = sum(1 for c, t, r, q, a in rows if q == "Q1" and a in AGREE5)
    assert str(q1["n"]) == str(answered) and str(q1["Agree (count)"]).isdigit()
    assert any(r["suppressed"] and r["n"] in ("", None) for r in table)


def test_both_routes_give_each_column_left_out_the_same_reason(tmp_path, capsys):
    """Regression: the in-memory route listed 'not items: id, term, Comments' without a
    reason; --by gave one per column. By hand: section groups, id is an identifier,
    term and Comments hold no agree4 labels (see the test above)."""
    f = tmp_path / "m.csv"
    f.write_text("section,id,term,Q1,Q2,Comments\nA,1,F23,Agree,Disagree,good\n"
                 "B,2,S24,Disagree,,too fast\nA,3,S24,Agree,Strongly agree,\n"
                 "B,4,F23,Strongly disagree,Agree,Agree\n")
    from analysis.ingest import read_survey
    small = read_survey(f, group="section").not_item_reasons
    big = summarize_by(f, ["section"]).not_items
    assert small == {"section": "grouping column", "id": "an identifier column",
                     "term": "its answers are not labels of scale 'agree4'",
                     "Comments": "its answers are not labels of scale 'agree4'"}
    assert big == small
    assert main(["summarize", str(f)]) == 0
    assert ("not items (left out of the table): section (its answers are not labels of scale "
            "'agree4'), id (an identifier column), term (") in capsys.readouterr().out


def test_both_routes_note_an_id_on_two_rows_of_a_group_alike(tmp_path, capsys, monkeypatch):
    """Regression: a@x.edu answering twice was counted twice unsaid. Both routes count both
    rows and give one note, word for word, naming its rows (2 and 4: header row 1)."""
    f = tmp_path / "g.csv"
    f.write_text("Section,Email Address,Q1\nA,a@x.edu,Agree\nA,b@x.edu,Agree\n"
                 "A, A@x.edu,Disagree\nB,c@x.edu,Agree\nB,a@x.edu,Agree\n")
    want = (f"{f}: column 'Email Address': 1 id on more than one row with the same 'Section' "
            f"('a@x.edu' in rows 2, 4); each row is counted as a respondent: remove repeated "
            f"submissions if they are one person's")
    from analysis.ingest import read_survey
    data = read_survey(f, group="Section")
    assert data.respondents == 5 and want in data.notes, data.notes
    res = summarize_by(f, ["Section"])
    assert res.respondents.tolist() == [3, 2] and want in res.notes, res.notes
    # a file too large to read again for the rows: how many rows, not which
    import analysis.institution as institution
    monkeypatch.setattr(institution, "_MAX_REREAD", 0)
    notes = summarize_by(f, ["Section"]).notes          # of the spellings, the least as text
    assert any("('A@x.edu' on 2 rows); each row is counted" in n for n in notes), notes


def test_by_names_a_repeated_id_as_the_file_writes_it(tmp_path, monkeypatch):
    """Regression: --by matched ids in lower case and named them so ('s1' in rows 2, 4)
    where the file, and --group's note, have 'S1'. Reference: the ids as written below."""
    f = tmp_path / "dup.csv"
    f.write_text("student_id,Term,Q1\nS1,Fall,Agree\nS2,Fall,Agree\nS1,Fall,Disagree\n"
                 "Ab7,Fall,Agree\n ab7 ,Fall,Agree\n")
    want = "('S1' in rows 2, 4; 'Ab7' in rows 5, 6)"
    from analysis.ingest import read_survey
    assert any(want in n for n in read_survey(f, group="Term").notes)
    assert any(want in n for n in summarize_by(f, ["Term"], min_group=1).notes)
    import analysis.institution as institution
    monkeypatch.setattr(institution, "_MAX_REREAD", 0)        # counted by DuckDB only
    notes = summarize_by(f, ["Term"], min_group=1).notes
    assert any("('S1' on 2 rows; 'Ab7' on 2 rows)" in n for n in notes), notes


def test_both_routes_drop_a_footer_row_alike(tmp_path, capsys):
    """Regression: an export note below empty rows ("Exported by ..." in the first cell of
    spreadsheet row 9: header 1, answers 2-5, empty 6-8) was a fifth respondent of a
    (blank) group under --by, missing on every item, while summarize dropped it. Both
    routes now drop that row, naming it, and count 4 respondents, none missing."""
    f = tmp_path / "footer.csv"
    f.write_text("Student,Section,Q1,Q2\ns1,A,Agree,Disagree\ns2,A,Agree,Neutral\n"
                 "s3,B,Strongly agree,Agree\ns4,B,Disagree,Agree\n\n\n\n"
                 "Exported by J. Smith on 2024-10-05,,,\n")
    res = summarize_by(f, ["Section"], min_group=1)
    assert res.groups == [("A",), ("B",)] and res.respondents.tolist() == [2, 2]
    assert [(d.row, d.reason) for d in res.dropped] == [(9, "text-only footer row")]
    assert [(it.n, it.missing) for it in res.overall()] == [(4, 0), (4, 0)]
    assert main(["summarize", str(f), "--by", "Section"]) == 0
    assert "dropped row 9: text-only footer row" in capsys.readouterr().out
    assert main(["summarize", str(f), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["dropped"] == [
        {"row": 9, "reason": "text-only footer row"}]
    # the same cells on an earlier row too: a respondent there, so nothing is dropped
    # (DuckDB cannot tell the two rows apart), and the note says so
    twice = tmp_path / "twice.csv"
    twice.write_text(f.read_text().replace("s4,B,Disagree,Agree\n", "s4,B,Disagree,Agree\n"
                                           "Exported by J. Smith on 2024-10-05,,,\n"))
    res = summarize_by(twice, ["Section"], min_group=1)
    assert res.dropped == [] and int(res.respondents.sum()) == 6
    assert any("2 rows have these cells" in n for n in res.notes)


def test_both_routes_refuse_a_respondent_in_two_groups(tmp_path, capsys):
    """Regression: in a long file whose rows of respondent s1 say Section A (row 2) and
    then B (row 3), --by counted s1 in both groups (3 respondents for 2 people) and
    --group silently put s1's B answer in group A. The file contradicts itself: both
    routes refuse it at row 3. Spellings of one value ('A', ' a') are one group, not two."""
    f = tmp_path / "torn.csv"
    f.write_text("respondent,item,answer,Section\ns1,Q1,Agree,A\ns1,Q2,Agree,B\n"
                 "s2,Q1,Disagree,A\ns2,Q2,Agree,A\n")
    want = (f"error: {f}: row 3, column 'Section': respondent 's1' is in two groups by "
            f"'Section': 'A' on an earlier row, 'B' on this one; a respondent's rows must "
            f"give one group")
    for extra in (["--group", "Section"], ["--by", "Section"]):
        assert main(["summarize", str(f), *extra, "--min-group", "1"]) == 2
        assert capsys.readouterr().err.strip() == want
    f.write_text(f.read_text().replace("s1,Q2,Agree,B", "s1,Q2,Agree, a"))
    res = summarize_by(f, ["Section"], min_group=1)
    assert res.groups == [("A",)] and res.respondents.tolist() == [2]


def test_rows_of_empty_cells_are_not_respondents_on_either_route(tmp_path, capsys):
    """Regression: a form export re-saved by a spreadsheet writes ',,,' for an empty row and ends
    with a comma-free note. Spreadsheet rows: header 1, s1 2, ',,,' 3, s2-s4 4-6, ',,,' 7-8, the note 9.
    summarize counted each ',,,' row as a respondent missing on every item (and, the note then not
    being below empty rows, the note too); under --by DuckDB's sniffer read the whole header as one
    column. Both routes: 4 respondents, none missing, the note dropped at row 9."""
    f = tmp_path / "resaved.csv"
    f.write_text("Student,Term,Q1,Q2\r\ns1,F,Agree,Disagree\r\n,,,\r\ns2,F,Agree,Neutral\r\n"
                 "s3,S,Strongly agree,Agree\r\ns4,S,Disagree,Agree\r\n,,,\r\n,,,\r\n"
                 "Exported by Google Forms on 2024-05-01\r\n")
    res = summarize_by(f, ["Term"], min_group=1)
    assert res.groups == [("F",), ("S",)] and res.respondents.tolist() == [2, 2]
    assert [(it.n, it.missing) for it in res.overall()] == [(4, 0), (4, 0)]
    assert [(d.row, d.reason) for d in res.dropped] == [(9, "text-only footer row")]
    assert main(["summarize", str(f), "--group", "Term", "--min-group", "1", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["respondents"] == 4 and [(i["n"], i["missing"]) for i in out["items"]] == [(4, 0), (4, 0)]
    assert out["dropped"] == [{"row": 9, "reason": "text-only footer row"}]
    assert {g["group"]: g["respondents"] for g in out["groups"]["groups"]} == {"F": 2, "S": 2}


def test_by_refuses_a_canvas_export_with_what_to_do(tmp_path, capsys):
    """Regression: --by on a Canvas quiz export said "columns 10 and 12 are both named '1.0';
    rename one" (its points columns repeat by design) while --group reads the file, keeping
    each student's latest attempt. --by now says it does not read the layout and what does."""
    f = tmp_path / "canvas.csv"
    f.write_text("name,id,sis_id,section,section_id,section_sis_id,submitted,attempt,"
                 "11111: I understand it,1.0,11112: FBDs are easier,1.0,n correct,n incorrect,score\n"
                 "Ann,1,s1,Sec 1,10,,2024-03-01 10:00:00 UTC,1,Agree,0,Disagree,0,0,0,0\n"
                 "Ann,1,s1,Sec 1,10,,2024-03-02 10:00:00 UTC,2,Strongly Agree,0,Agree,0,0,0,0\n"
                 "Bob,2,s2,Sec 1,10,,2024-03-01 10:00:00 UTC,1,Disagree,0,Disagree,0,0,0,0\n")
    assert main(["summarize", str(f), "--by", "section"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith(f"error: {f}: row 1: a Canvas quiz export: --by does "
                                                   "not read its layout"), err
    assert main(["summarize", str(f), "--group", "section", "--min-group", "1", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["respondents"] == 2  # Ann's latest attempt, and Bob


def test_every_route_writes_the_same_table_columns(tmp_path, capsys):
    """Regression: --table wrote three schemas: percentages but no interval with --group, an
    interval but no percentages with --by (as agree_share/agree_ci_low, iqr, sd), both alone.
    Now the item columns are one list in one order; --by's institution-wide row equals the
    plain table's row; --group's and --by's rows of a group agree (the same respondents)."""
    import pandas as pd
    f = tmp_path / "s.csv"
    rows = [["sid", "Section", "Q1", "Q2"]] + [
        [f"s{i}", "AB"[i % 2], ["Agree", "Disagree", "Strongly agree"][i % 3],
         ["Neutral", "Agree"][i % 2]] for i in range(12)]
    with open(f, "w", newline="") as fh:
        csv.writer(fh).writerows(rows)
    tables = {}
    for name, extra in (("plain", []), ("group", ["--group", "Section"]), ("by", ["--by", "Section"])):
        out = tmp_path / f"{name}.csv"
        assert main(["summarize", str(f), *extra, "--table", str(out)]) == 0
        tables[name] = pd.read_csv(out, encoding="utf-8-sig")
    capsys.readouterr()
    plain, group, by = tables["plain"], tables["group"], tables["by"]
    columns = list(plain.columns[2:])                       # after item and stem
    assert columns[:3] == ["reversed", "statistics on reversed codes", "n"]
    # QA 18 #9: the --group table had no respondents column where --by's has one
    assert list(group.columns[:3]) == ["Section", "item", "respondents"] and list(group.columns[3:-3]) == columns
    assert list(by.columns[:3]) == ["Section", "item", "respondents"] and list(by.columns[3:]) == columns
    numbers = ["respondents"] + [c for c in columns if c not in ("reversed", "statistics on reversed codes")]
    everyone = by[by["Section"] == "(all)"].reset_index(drop=True)
    pd.testing.assert_frame_equal(everyone[numbers[1:]], plain[numbers[1:]], check_dtype=False)
    for section in ("A", "B"):
        a = group[group["Section"] == section].reset_index(drop=True)[numbers]
        b = by[by["Section"] == section].reset_index(drop=True)[numbers]
        pd.testing.assert_frame_equal(a, b, check_dtype=False)


def test_a_parquet_file_with_typed_columns_is_counted_as_its_csv(tmp_path):
    """Regression: a Parquet export whose id and term columns are integers failed the whole count
    ("counting failed (Binder Error: No function matches ... trim(INTEGER ...") since ids are
    matched trimmed as texts. The file is now read as text, as a CSV is: the same groups, counts
    and respondents as the CSV of the same rows."""
    import duckdb
    csv_file, pq = tmp_path / "t.csv", tmp_path / "t.parquet"
    csv_file.write_text("id,term,Q1,Q2\n1,2023,Agree,Disagree\n2,2023,Disagree,Agree\n"
                        "3,2024,Agree,Agree\n4,2024,,Disagree\n")
    duckdb.sql(f"COPY (SELECT id::INTEGER AS id, term::INTEGER AS term, Q1, Q2 FROM "
               f"read_csv('{csv_file}', all_varchar = true)) TO '{pq}' (FORMAT parquet)")
    assert [t for (t,) in duckdb.sql(f"SELECT column_type FROM (DESCRIBE SELECT * FROM '{pq}')").fetchall()][:2] \
        == ["INTEGER", "INTEGER"]
    a, b = summarize_by(csv_file, ["term"], min_group=1), summarize_by(pq, ["term"], min_group=1)
    assert a.groups == b.groups == [("2023",), ("2024",)]
    assert a.respondents.tolist() == b.respondents.tolist() == [2, 2]
    assert (a.tallies == b.tallies).all()


def test_both_routes_read_quoted_line_breaks_alike(tmp_path, capsys):
    """Regression: --by refused a Google Forms export with a two-line comment ("counting
    failed (CSV Error on Line: 10)": DuckDB's parallel scanner cannot pad short rows around
    a quoted line break) and one with a line break in a quoted header cell, Excel style
    (LF in the cell, CRLF between rows: "Error when sniffing file"). The reference is a
    ``Counter`` of the answers written; both routes must give it, under one item name."""
    rng = random.Random(7)
    header = ["Timestamp", "Section", "The lectures\nwere clear", "Q2", "Comments"]
    rows = []
    for r in range(40):
        q1 = rng.choice(AGREE5 + ["", "N/A"])
        comment = "Line1\nLine2" if r % 9 == 3 else "ok"
        rows.append([f"2024/09/{r % 28 + 1:02d} 10:00:00 AM EST", rng.choice("AB"), q1,
                     rng.choice(AGREE5), comment])
    f = tmp_path / "google.csv"
    with open(f, "w", newline="", encoding="utf-8") as fh:    # csv's own CRLF rows
        csv.writer(fh).writerows([header] + rows)
    assert b"\nwere clear" in f.read_bytes() and b"Line1\nLine2" in f.read_bytes()
    want = [Counter(r[j] for r in rows) for j in (2, 3)]
    assert main(["summarize", str(f), "--json"]) == 0
    small = json.loads(capsys.readouterr().out)["items"]
    assert main(["summarize", str(f), "--by", "Section", "--json"]) == 0
    big = json.loads(capsys.readouterr().out)
    names = ["The lectures were clear", "Q2"]
    for route in (small, big["overall"]):
        assert [it["item"] for it in route] == names
        for it, cells in zip(route, want):
            assert it["counts"] == {lab: cells.get(lab, 0) for lab in AGREE5}
            assert (it["missing"], it["excluded"]) == (cells.get("", 0), cells.get("N/A", 0))
    assert big["respondents"] == 40 and big["overall"] == small
    # two threads: DuckDB's parallel scanner refuses the file and the serial one reads it
    two = summarize_by(f, ["Section"], threads=2)
    assert (two.tallies == summarize_by(f, ["Section"]).tallies).all()


def test_both_flags_name_a_two_line_header_cell_with_one_space(tmp_path, capsys):
    """QA 21 #4: --by "Class section" was refused ("no such column") for a header cell written
    on two lines, which --group takes, and --group printed the column as 'Class\\nsection'.
    By hand: sections A (a, b) and B (c, d); Q1 answers Agree, Strongly agree | Agree, Disagree."""
    f = tmp_path / "nl.csv"
    f.write_bytes(b'\xef\xbb\xbfid,"Class\nsection",Q1,Q2\na,A,Agree,Disagree\n'
                  b'b,A,Strongly agree,Neutral\nc,B,Agree,Agree\nd,B,Disagree,Agree\n')
    assert main(["summarize", str(f), "--by", "Class section", "--min-group", "1", "--json"]) == 0
    big = json.loads(capsys.readouterr().out)
    assert big["by"] == ["Class section"]
    q1 = {r["Class section"]: [r[f"{lab} (count)"] for lab in AGREE5] for r in big["rows"]
          if r["item"] == "Q1"}
    assert q1 == {"(all)": [0, 1, 0, 2, 1], "A": [0, 0, 0, 1, 1], "B": [0, 1, 0, 1, 0]}
    assert main(["summarize", str(f), "--by", "Class section", "--min-group", "1"]) == 0
    assert "groups by Class section; scale" in capsys.readouterr().out
    assert main(["summarize", str(f), "--group", "Class section", "--min-group", "1"]) == 0
    assert "groups by 'Class section' (" in capsys.readouterr().out
    assert main(["summarize", str(f), "--by", "Section", "--min-group", "1"]) == 2
    assert capsys.readouterr().err.endswith(
        "--by 'Section': no such column; columns are ['id', 'Class section', 'Q1', 'Q2']\n")


def test_by_reads_a_quote_first_met_after_row_20480(tmp_path):
    """Regression: DuckDB's sniffer saw no quote in its 20,480-row sample, read the file
    as unquoted, and split the row with "Strongly\\nagree" in two (a blank respondent id
    was refused). The quote is now given. Reference: a ``Counter`` of the answers."""
    rows = [["C1", f"r{r}", "Q1", AGREE5[r % 5]] for r in range(21000)]
    rows[-1][3] = "Strongly\nagree"                   # read as "Strongly agree"
    f = tmp_path / "late.csv"
    with open(f, "w", newline="") as fh:
        csv.writer(fh, lineterminator="\n").writerows(
            [["course", "respondent", "item", "answer"]] + rows)
    cells = Counter(" ".join(r[3].split()) for r in rows)
    it, = summarize_by(f, ["course"]).overall()
    assert it.counts == {lab: cells[lab] for lab in AGREE5} and it.respondents == 21000


def test_by_refuses_a_workbook_in_one_line(tmp_path, capsys):
    """Regression: --by read an .xlsx as CSV text and said "byte 0xba at offset 11 is not
    UTF-8". It now names the format it reads, for a workbook by name or by content."""
    from tests.xlsx_factory import workbook
    data = workbook([["id", "Term", "Q1"], ["s1", "Fall", "Agree"]])
    for name, what in (("w.xlsx", ".xlsx (a workbook)"),
                       ("w.csv", "a zip container (an .xlsx workbook?)")):
        f = tmp_path / name
        f.write_bytes(data)
        assert main(["summarize", str(f), "--by", "Term"]) == 2
        err = capsys.readouterr().err
        assert err == (f"error: {f}: --by reads CSV or Parquet, not {what}: summarize it "
                       f"without --by, or save it as CSV UTF-8\n"), err


def test_by_takes_group_order_as_group_does(tmp_path, capsys):
    """Regression: --by refused --group-order and listed the groups alphabetically. It now
    orders them as asked (matched as --group matches, ' spring  2024' is 'Spring 2024'),
    the others after in text order, and refuses a value no group has in the same words as
    --group. Reference: the order written below."""
    f = tmp_path / "terms.csv"
    f.write_text("id,Term,Q1\n" + "".join(
        f"s{k}{t[0]},{t},Agree\n" for t in ["Fall 2023", "Spring 2024", "Summer 2024"]
        for k in range(5)))
    order = [" spring  2024", "Fall 2023"]
    res = summarize_by(f, ["Term"], group_order=order)
    assert res.groups == [("Spring 2024",), ("Fall 2023",), ("Summer 2024",)]
    assert res.respondents.tolist() == [5, 5, 5]
    assert main(["summarize", str(f), "--by", "Term", "--group-order", *order, "--json"]) == 0
    rows = json.loads(capsys.readouterr().out)["rows"]
    assert list(dict.fromkeys(r["Term"] for r in rows)) == ["(all)", "Spring 2024", "Fall 2023",
                                                            "Summer 2024"]
    errors = []
    for route in (["--by", "Term"], ["--group", "Term"]):
        assert main(["summarize", str(f), *route, "--group-order", "Winter"]) == 2
        errors.append(capsys.readouterr().err.splitlines(keepends=True)[-1])   # notes aside
    assert errors[0] == errors[1] == (
        f"error: {f}: --group-order names 'Winter', which is not a value of the grouping "
        f"column; values are ['Fall 2023', 'Spring 2024', 'Summer 2024']\n"), errors


def test_grouping_a_long_file_by_its_own_columns_is_refused_in_one_line(tmp_path, capsys):
    """QA 16 #7: ``--by item`` on a long file leaked DuckDB's "Catalog Error: Table with name
    VALUES does not exist!", and ``--by respondent`` said "no item columns" of agree5 answers.
    Both flags, on both routes, now say which column it is. Run as a command too: after an
    error with DuckDB loaded, its bindings printed some 60 "leaked instance" lines at exit."""
    import subprocess
    import sys
    from pathlib import Path
    f = tmp_path / "long.csv"
    f.write_text("Respondent,Item,Answer,term\n007,1,Agree,F\n007,2,Disagree,F\n"
                 "7,1,Neutral,F\n7,2,Agree,F\n")
    for flag in ("--by", "--group"):
        for col, what in (("item", "item"), ("RESPONDENT", "respondent"), ("answer", "answer")):
            assert main(["summarize", str(f), flag, col, "--min-group", "1"]) == 2
            assert capsys.readouterr().err == (
                f"error: {f}: {flag} {col}: {what.capitalize()!r} is the long file's {what} "
                "column (Respondent, Item, Answer); group by another column\n")
    r = subprocess.run([sys.executable, "-m", "analysis", "summarize", str(f), "--by", "item"],
                       cwd=Path(__file__).resolve().parents[1], capture_output=True, text=True)
    assert r.returncode == 2 and r.stderr.count("\n") == 1, r.stderr
    assert main(["summarize", str(f), "--by", "term", "--min-group", "1", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["respondents"] == 2


def test_both_routes_name_a_google_grid_item_by_its_statement(tmp_path, capsys):
    """QA 16 #11: summarize named Google Forms grid rows by statement ('Clear'), --by by the
    whole header ('Rate [Clear]'), so the two routes' tables did not join on 'item'. Both now
    name them as read_survey does, take --items and --reverse by either name, and agree on
    the counts. By hand: 'Clear' Agree x3, Disagree x1; 'Fast' Agree, Disagree, Neutral x2."""
    f = tmp_path / "g.csv"
    f.write_text("Timestamp,Section,Rate [Clear],Rate [Fast]\n"
                 "2024/03/01 10:00:00,A,Agree,Agree\n2024/03/01 10:01:00,A,Agree,Disagree\n"
                 "2024/03/01 10:02:00,B,Agree,Neutral\n2024/03/01 10:03:00,B,Disagree,Neutral\n")
    got = {}
    for route, extra, key in (("memory", [], "items"), ("by", ["--by", "Section"], "overall")):
        assert main(["summarize", str(f), "--json", "--min-group", "1", "--items", "Clear",
                     "Rate [Fast]", "--reverse", "Rate [Clear]", *extra]) == 0, route
        out = json.loads(capsys.readouterr().out)
        got[route] = [(it["item"], it["n"], it["counts"]["Agree"], it["reversed"])
                      for it in out[key]]
    assert got["memory"] == got["by"] == [("Clear", 4, 3, True), ("Fast", 4, 1, False)]


def test_both_routes_warn_of_labels_no_answer_uses(tmp_path):
    """--by gave no word where summarize warned that the scale read has labels nobody used
    while another built-in scale fits the answers exactly (read as agree7, answers on the
    five agree5 labels). The warning is now the same on both routes, word for word."""
    from analysis.ingest import read_survey
    f = tmp_path / "five.csv"
    f.write_text("T,Q1,Q2\n" + "".join(f"A,{a},{b}\n" for a, b in zip(AGREE5, AGREE5[::-1])))
    want = ("warning: scale 'agree7' has labels no answer uses (Somewhat disagree, Somewhat "
            "agree), while scale 'agree5' fits the answers exactly; give --scale agree5 if that "
            "is the questionnaire's scale (medians and codes depend on it)")
    assert want in read_survey(f, scale="agree7").notes
    assert want in summarize_by(f, ["T"], scale="agree7", min_group=1).notes


def test_an_items_pattern_matching_nothing_is_refused_alike_on_both_routes(tmp_path, capsys):
    """QA 18 #9: ``--by ... --items Nope`` said 'no item columns to count' without naming
    'Nope', and with a good name beside it listed the grid's header form, not the statement
    names --by takes. Both routes now give the in-memory route's line, naming the pattern and
    listing the columns by the names items go by."""
    f = tmp_path / "google.csv"
    f.write_text("Timestamp,Section,Rate each statement [Clear],Rate each statement [Too hard]\n"
                 + "".join(f"2024-01-0{i} 10:00,{'AB'[i % 2]},Agree,Disagree\n" for i in range(1, 7)))
    want = (f"error: {f}: row 1: no column matches item 'Nope'; columns are ['Timestamp', "
            "'Section', 'Clear', 'Too hard']\n")
    for items in (["Nope"], ["Clear", "Nope"]):
        for by in ([], ["--by", "Section", "--min-group", "1"]):
            assert main(["summarize", str(f), "--items", *items, *by]) == 2
            assert capsys.readouterr().err == want, (items, by)


def test_an_empty_file_is_called_empty_on_both_routes(tmp_path, capsys):
    """An empty CSV (or one of blank lines) was refused by --by as having no column 'Q1'
    among ['column0'], a column DuckDB made up; the in-memory route calls it empty."""
    for text in ("", "\n\n  \n"):
        f = tmp_path / "empty.csv"
        f.write_text(text)
        for by in ([], ["--by", "Q1"]):
            assert main(["summarize", str(f), *by]) == 2
            assert capsys.readouterr().err == f"error: {f}: empty file\n", (text, by)
