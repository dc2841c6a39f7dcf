"""Per-item summaries: Table 1 recomputed from the rebuilt dataset, rounding rules, codes.

Reference values
----------------
- Table 1 as printed and N: data/published/table1.csv, survey.toml.
- Printed precision one decimal -> a recomputed cell matches when equal at one decimal; the
  three cells no count out of 22 can produce (Definitely Agree of #2, #3, #4: hand check
  13/22 = 59.09, 14/22 = 63.64, 12/22 = 54.55, printed 59.2, 63.7, 54.6) are printed exactly
  one unit (0.1) above the recomputed value.
- Median / quartiles: numpy.quantile on the expanded codes (independent of the count-based route).
"""
import csv
import json
from decimal import Decimal
from fractions import Fraction

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from analysis.__main__ import main
from analysis.ingest import read_survey, survey_from_frame
from analysis.likert import summarize
from analysis.rounding import largest_remainder, round_fraction
from analysis.respondents import rebuild_table1_dataset
from analysis.tables import load_table1


@pytest.fixture(scope="module")
def rebuilt(tmp_path_factory):
    path = tmp_path_factory.mktemp("t1") / "table1_rebuilt.csv"
    rebuild_table1_dataset(path)
    return path


UNATTAINABLE = {("#2", "Definitely Agree"), ("#3", "Definitely Agree"),
                ("#4", "Definitely Agree")}     # module docstring (hand check)


def test_table1_recomputed_from_shipped_dataset(rebuilt):
    table, facts = load_table1()
    s = summarize(read_survey(rebuilt))
    assert s.respondents == facts.respondents
    assert read_survey(rebuilt).scale.name == facts.scale
    unit = Decimal(1).scaleb(-facts.decimals)
    assert len(s.items) == len(table.items)
    for i, it in enumerate(s.items):
        assert it.n == facts.respondents and it.missing == 0 and it.excluded == 0
        printed = it.printed_percent(facts.decimals)
        for j, label in enumerate(table.labels):
            published = Decimal(table.cells[i][j])
            ours = Decimal(f"{printed[label]:.{facts.decimals}f}")
            if (table.items[i], label) in UNATTAINABLE:    # printed one unit above any count
                assert published - ours == unit, (it.item, label)
            else:
                assert ours == published, (it.item, label)
    # rows recomputed from counts add to 100 +- rounding; largest remainder makes it exact
    for it in s.items:
        assert sum(Fraction(str(v)) for v in it.printed_percent(1, "largest_remainder").values()) == 100


def test_summarize_json_shape(rebuilt, capsys):
    assert main(["summarize", str(rebuilt), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert set(out) == {"respondents", "ci_method", "confidence_level", "reverse_note", "items",
                        "not_items", "not_item_reasons", "dropped", "unknown_answers", "notes"}
    # the rebuilt file's id column is left out of the table, and said so, with why
    assert out["not_items"] == ["respondent"] and out["dropped"] == out["unknown_answers"] == []
    assert set(out["not_item_reasons"]) == {"respondent"} and out["not_item_reasons"]["respondent"]
    for item in out["items"]:
        assert {"item", "n", "missing", "counts", "percent", "agree"} <= set(item)
        assert set(item["agree"]) == {"share", "ci"} and len(item["agree"]["ci"]) == 2
        assert 0 <= item["agree"]["ci"][0] <= item["agree"]["share"] <= item["agree"]["ci"][1] <= 1
        assert sum(item["percent"].values()) == pytest.approx(100, abs=1e-9)  # float sum
    assert out["notes"] == []


def test_round_half_away_is_not_bankers():
    # 1/8 = 12.5 %: half away gives 13, Python's round gives 12
    assert round_fraction(Fraction(100, 8), 0) == 13 and round(12.5) == 12
    assert round_fraction(Fraction(1, 40) * 100, 0) == 3       # 2.5 -> 3


# 50 rows (~1.5 ms each: pure fractions): cheap, so ties, zeros and 0-2 decimals all come up every run.
@settings(max_examples=50)
@given(st.lists(st.integers(0, 500), min_size=2, max_size=7).filter(lambda c: sum(c) > 0),
       st.integers(0, 2))
def test_largest_remainder_properties(counts, decimals):
    vals = largest_remainder(counts, decimals)
    assert sum(vals) == 100
    n = sum(counts)
    step = Fraction(1, 10 ** decimals)
    for v, c in zip(vals, counts):
        exact = Fraction(100 * c, n)
        assert exact - step < v < exact + step            # never moves a cell a full unit
        assert (v / step).denominator == 1


# 30 answer lists (~15 ms each: a survey frame and its summary): even and odd lengths, blanks and
# one-label columns each run; numpy's quantiles are the independent route.
@settings(max_examples=30)
@given(st.lists(st.sampled_from(["Definitely Agree", "Partially Agree", "Neutral",
                                 "Partially Disagree", "Definitely Disagree", ""]),
                min_size=1, max_size=40).filter(lambda xs: any(xs)))
def test_median_iqr_match_numpy(answers):
    df = pd.DataFrame({"q": answers})
    data = survey_from_frame(df, scale="paper", items=["q"])
    it = summarize(data).items[0]
    codes = np.array([data.scale.codes[data.scale.labels.index(a)] for a in answers if a])
    assert it.median == pytest.approx(np.quantile(codes, 0.5), abs=1e-12)
    assert (it.q1, it.q3) == pytest.approx((np.quantile(codes, 0.25), np.quantile(codes, 0.75)),
                                           abs=1e-12)
    assert it.mean == pytest.approx(codes.mean(), abs=1e-12)


def test_reverse_keying_changes_codes_not_counts():
    df = pd.DataFrame({"q1": ["Definitely Agree", "Neutral", "Partially Agree"],
                       "q2": ["Definitely Agree", "Neutral", "Partially Agree"]})
    data = survey_from_frame(df, reverse=["q2"])
    s = summarize(data)
    a, b = s.items
    assert a.counts == b.counts and a.agree.share == b.agree.share
    lo, hi = min(data.scale.codes), max(data.scale.codes)     # reverse = lo + hi - code
    assert b.median == lo + hi - a.median and b.reverse and not a.reverse


def test_table1_reproduction_chain(tmp_path):
    from analysis.paper import table1_reproduction
    rep = table1_reproduction(tmp_path)
    assert rep.dataset.path.parent == tmp_path
    unattainable = {(c.item, c.label) for c in rep.check.unattainable}
    assert {(c.item, c.label) for c in rep.mismatches} == unattainable == UNATTAINABLE
    assert [r.verdict_code for r in rep.claims.results] == ["sample_only", "sample_only"]
    json_ready = rep.to_dict()
    assert len(json_ready["cells"]) == 25


def test_shares_printed_by_the_same_rule_as_cells(tmp_path, capsys):
    """5/16 = 31.25 % prints 31.3 as a cell and as the agreement share (half away from zero).

    Regression: the share went through float formatting (31.2) beside a cell showing 31.3;
    and ``--decimals -1`` ended in a traceback instead of one line and status 2.
    """
    scale = tmp_path / "yn.toml"
    scale.write_text('labels = ["No", "Yes"]\npositive = ["Yes"]\nnegative = ["No"]\n')
    f = tmp_path / "s.csv"
    f.write_text("q1\n" + "Yes\n" * 5 + "No\n" * 11)
    assert main(["summarize", str(f), "--scale", str(scale)]) == 0
    row = capsys.readouterr().out.splitlines()[2]
    assert "31.3% (5)" in row and "31.3% [" in row and "31.2" not in row
    out = tmp_path / "r.html"
    assert main(["report", str(f), "--scale", str(scale), "-o", str(out)]) == 0
    html = out.read_text()
    svg_start, svg_end = html.index("<svg"), html.index("</svg>")   # chart coordinates aside
    assert "31.2" not in html[:svg_start] + html[svg_end:]
    assert main(["summarize", str(f), "--scale", str(scale), "--decimals", "-1"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--decimals" in err and "Traceback" not in err


from tests.test_analysis_institution import SURVEY3  # noqa: E402 - one copy of the tester's file

# The tester's survey.csv: survey3.csv's sections A and B (its first twelve respondents).
SURVEY = "".join(SURVEY3.splitlines(keepends=True)[:13])


def test_reverse_keyed_items_are_marked_in_text_json_and_table(tmp_path, capsys):
    """A reversed item's statistics sit beside raw counts: every output says so.

    By hand, Q3 of the tester's survey.csv: SD 2, D 4, N 2, A 3, SA 1 (raw). Reversed
    codes (SD=5 .. SA=1) give the mean (2*5 + 4*4 + 2*3 + 3*2 + 1*1) / 12 = 39/12 = 3.25;
    the raw codes would give 33/12 = 2.75.
    """
    import csv as _csv
    f, table = tmp_path / "survey.csv", tmp_path / "t.csv"
    f.write_text(SURVEY)
    assert main(["summarize", str(f), "--reverse", "Q3", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    q1, q3 = out["items"][0], out["items"][2]
    assert (q1["reversed"], q1["reversed_statistics"]) == (False, [])
    assert (q3["reversed"], q3["reversed_statistics"]) == (True, ["median", "iqr", "mean", "sd"])
    assert list(q3["counts"].values()) == [2, 4, 2, 3, 1] and q3["mean"] == 3.25
    assert "raw, not reversed" in out["reverse_note"]
    assert main(["summarize", str(f), "--reverse", "Q3", "--table", str(table)]) == 0
    text = capsys.readouterr().out
    lines = text.splitlines()
    assert [ln.split()[:2] for ln in lines if ln.startswith("Q3")] == [["Q3", "(R)"]]
    assert any(ln.startswith("(R) reverse-keyed item: counts") for ln in lines)
    rows = list(_csv.DictReader(table.read_text(encoding="utf-8-sig").splitlines()))
    assert [(r["item"], r["reversed"]) for r in rows][1:3] == [("Q2", "False"), ("Q3", "True")]
    assert rows[2]["statistics on reversed codes"] == "median, iqr, mean, sd"
    assert rows[2]["mean"] == "3.25" and rows[2]["Strongly disagree (count)"] == "2"


def test_summary_text_rounds_interval_bounds_by_the_one_rule():
    """summarize's text printed the agreement interval with Python's ``:.1%`` (half to even on the float);
    it follows the one rule (half away from zero, analysis.rounding) as its shares do. Bounds of 0.0625
    and 0.8125 (exact in binary, made up: ties by design) print 6.3% and 81.3% (``:.1%``: 6.2%, 81.2%)."""
    import pandas as pd

    from analysis.likert import Proportion, summarize_dataframe

    s = summarize_dataframe(pd.DataFrame({"q": ["Definitely Agree"] * 13 + ["Neutral"] * 3}))
    s.items[0].agree = Proportion(13, 16, 13 / 16, (0.0625, 0.8125), "wilson", 0.95)
    assert "81.3% [6.3%, 81.3%]" in s.format_text()


def test_count_columns_stay_aligned_with_ten_million_respondents(tmp_path):
    """Regression: with --respondents 10000000 the 7-digit missing count overflowed its
    5-wide column and stood under 'n'. Each count must end where its header ends."""
    from analysis.ingest import read_survey
    from analysis.likert import summarize
    f = tmp_path / "s.csv"
    f.write_text("Q1\nAgree\nDisagree\nN/A\n")
    text = summarize(read_survey(f, respondents=10_000_000)).format_text()
    head, row = text.splitlines()[1], text.splitlines()[2]
    # Q1: n = 2, missing = 10,000,000 - 3 = 9,999,997, n/a = 1
    for name, value in (("n", "2"), ("miss", "9999997"), ("n/a", "1")):
        end = head.index(f" {name} ") + 1 + len(name)
        assert row[end - len(value):end] == value and row[end - len(value) - 1] == " ", (
            name, head, row)


def test_every_printed_statistic_rounds_half_away_from_zero(tmp_path, capsys):
    """Regression: mean and IQR were printed half to even (IQR 2.25 as "2.2", mean 2.625 as
    "2.62") while percentages round half away from zero. The values below are exact in
    binary, so a tie is a tie. References: Q1 codes 1,1,2,2,3,4,4,4 (twice, in sections A
    and B): mean 21/8 = 2.625, IQR by numpy.percentile 2.25; Q2 codes 3 x 6, 4 x 2: IQR 0.25.
    Printed half away from zero: mean 2.63 on every route (text, --group, --by, HTML). The IQR
    and its quartiles print to two places, exact for whole-number codes (QA 19 #10: one place
    printed 2.3 (1.8-4.0), which does not subtract): 2.25 (1.75-4.00), and 0.25."""
    labels = ["Strongly disagree", "Disagree", "Neither agree nor disagree", "Agree",
              "Strongly agree"]
    q1, q2 = [1, 1, 2, 2, 3, 4, 4, 4], [3, 3, 3, 3, 3, 3, 4, 4]
    assert np.mean(q1) == 2.625
    iqr = [float(np.subtract(*np.percentile(q, [75, 25]))) for q in (q1, q2)]
    assert iqr == [2.25, 0.25]
    f = tmp_path / "ties.csv"
    f.write_text("id,Section,Q1,Q2\n" + "".join(
        f"{s}{k},{s},{labels[a - 1]},{labels[b - 1]}\n"
        for s in "AB" for k, (a, b) in enumerate(zip(q1, q2))))
    assert main(["summarize", str(f)]) == 0
    rows = capsys.readouterr().out.splitlines()
    assert rows[2].split()[-7:-4] == ["2.5", "2.25", "2.63"], rows[2]   # median IQR mean
    assert rows[3].split()[-7:-4] == ["3.0", "0.25", "3.25"], rows[3]
    for extra in (["--group", "Section"], ["--by", "Section"]):
        assert main(["summarize", str(f), *extra, "--min-group", "1"]) == 0
        out = capsys.readouterr().out
        assert "IQR 2.25 mean 2.63" in out and "IQR 0.25 mean 3.25" in out, out
        assert "2.62" not in out
    html = tmp_path / "r.html"
    assert main(["report", str(f), "-o", str(html)]) == 0
    text = html.read_text()
    assert "<td>2.25 (1.75&ndash;4.00)</td>" in text and "<td>2.63</td>" in text, text
    assert main(["report", str(f), "-o", str(html), "--group", "Section", "--min-group", "1"]) == 0
    assert "<td>2.25</td><td>2.63</td>" in html.read_text()    # the groups' table: IQR, mean
    table = tmp_path / "t.csv"
    assert main(["summarize", str(f), "--table", str(table)]) == 0
    rows = list(csv.DictReader(table.read_text(encoding="utf-8-sig").splitlines()))
    assert [(r["IQR"], r["Q1"], r["Q3"]) for r in rows] == [("2.25", "1.75", "4.0"), ("0.25", "3.0", "3.25")]
    # the one rule beyond two places and in significant digits (1/64, 1/32 exact in binary)
    from analysis.rounding import number_text, significant_text
    assert (number_text(1 / 32, 4), number_text(-0.0625, 3)) == ("0.0313", "-0.063")
    assert (significant_text(1 / 64), significant_text(0.03125, 3)) == ("0.01563", "0.0313")


def test_no_percentage_of_nobody_in_any_output(tmp_path, capsys):
    """QA 10 item 3: an item with n = 0 (Q2 all blank, Q3 all N/A) printed 0.0 for every label
    in JSON, and a group with n = 0 printed 0.0% per label in --group's text. A share of no
    answers does not exist: every percentage is null in JSON, blank in --table (as agree (%)),
    "-" in the text of both tables and absent from the HTML group table. Q1 (3 answers) keeps
    its percentages (by hand: 1 of 3 = 33.3%). No tolerance: counts and nulls are exact."""
    f = tmp_path / "e.csv"
    f.write_text("id,Sec,Q1,Q2,Q3\n1,A,Agree,,N/A\n2,A,Disagree,,N/A\n3,A,Strongly agree,,N/A\n")
    assert main(["summarize", str(f), "--json"]) == 0
    items = {it["item"]: it for it in json.loads(capsys.readouterr().out)["items"]}
    assert items["Q1"]["percent"]["Disagree"] == pytest.approx(100 / 3)   # float division
    for q in ("Q2", "Q3"):
        assert items[q]["n"] == 0 and set(items[q]["percent"].values()) == {None}, items[q]
    table = tmp_path / "t.csv"
    assert main(["summarize", str(f), "--table", str(table)]) == 0
    rows = {r["item"]: r for r in pd.read_csv(table, encoding="utf-8-sig").to_dict("records")}
    assert all(np.isnan(rows["Q2"][f"{lab} (%)"]) for lab in ("Disagree", "Agree"))
    # --respondents 5 puts 2 declared respondents in the (blank) group: n = 0 there
    assert main(["summarize", str(f), "--group", "Sec", "--respondents", "5",
                 "--min-group", "1"]) == 0
    blank = [ln for ln in capsys.readouterr().out.splitlines() if "(blank) n=0" in ln]
    assert len(blank) == 3 and all("%" not in ln for ln in blank), blank
    html = tmp_path / "r.html"
    assert main(["report", str(f), "-o", str(html), "--group", "Sec", "--respondents", "5",
                 "--min-group", "1"]) == 0
    cells = [ln for ln in html.read_text().split("<td>(blank)</td>")[1:]]
    assert len(cells) == 3 and all(c.split("</tr>")[0].count("<td>&ndash; (0)</td>") == 4
                                   for c in cells), cells
