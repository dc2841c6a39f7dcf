"""Comparisons across sections and terms, and results an instructor can reuse.

References: per-group counts are tallied from the drawn cells with ``Counter``; the paired
test is ``scipy.stats.wilcoxon`` on pairs matched here by a dict on the student id; the
matched-pairs rank-biserial correlation comes from the Wilcoxon statistic
(``r = (S - 2 min(T+, T-)) / S`` with ``S = n (n + 1) / 2``, signed by the larger sum);
Holm's adjustment is written out (sorted p times the number of hypotheses left, running
maximum).
"""
import csv
import io
import json
import random
import re
from collections import Counter

import numpy as np
import openpyxl
import pytest
from scipy import stats

from analysis.__main__ import main
from analysis.groups import compare_groups
from analysis.ingest import read_survey
from analysis.likert import summarize
from analysis.scales import BUILTIN_SCALES

AGREE5 = list(BUILTIN_SCALES["agree5"].labels)
CODE = {lab: k + 1 for k, lab in enumerate(AGREE5)}
TERMS = ["Spring 2024", "Fall 2023", "Fall 2024"]      # not alphabetical on purpose


def _two_terms(tmp_path, seed=3, n=40):
    """Pre/post file: the same students answer in two terms (plus a few in one only)."""
    rng = random.Random(seed)
    rows = [["Student ID", "Term", "Q1", "Q2", "Comment"]]
    for i in range(n):
        pre = [rng.choice(AGREE5[:4]) for _ in range(2)]
        post = [rng.choice(AGREE5[1:]) if rng.random() < 0.9 else "" for _ in range(2)]
        rows.append([f"s{i:03d}", "Pre", *pre, ""])
        if i % 8 != 0:
            rows.append([f"s{i:03d}", "Post", *post, "=cmd()"])
    rows.append(["", "Post", "Agree", "Agree", ""])         # no id: unpaired
    buf = io.StringIO()
    csv.writer(buf).writerows(rows)
    f = tmp_path / "prepost.csv"
    f.write_text(buf.getvalue())
    return f, rows[1:]


def test_pre_post_paired_by_id_matches_scipy(tmp_path, capsys):
    f, rows = _two_terms(tmp_path)
    data = read_survey(f, group="Term")
    comp = compare_groups(data, "Term")
    assert comp.shown == ["Pre", "Post"] and comp.paired_by == "Student ID"
    pre = {r[0]: r for r in rows if r[1] == "Pre"}
    post = {r[0]: r for r in rows if r[1] == "Post" and r[0]}
    for j, it in enumerate(comp.items):
        pairs = [(CODE[pre[k][2 + j]], CODE[post[k][2 + j]]) for k in pre
                 if k in post and pre[k][2 + j] and post[k][2 + j]]
        x, y = np.array(pairs).T
        ref = stats.wilcoxon(y, x)
        assert it.test == "wilcoxon-signed-rank" and it.pairs == len(pairs)
        # QA 19 #6: the pairs the test leaves out (same answer twice) are counted apart
        assert 0 < it.pairs_unchanged == int(np.sum(x == y))
        assert f"({it.pairs_unchanged} unchanged: left out of the test and the effect)" in it.pairs_text
        assert it.to_dict()["pairs_unchanged"] == it.pairs_unchanged
        assert (it.statistic, it.p_value) == pytest.approx((ref.statistic, ref.pvalue), rel=1e-12)
        d = (y - x)[y != x]
        s_total = d.size * (d.size + 1) / 2
        sign = 1 if np.sum(stats.rankdata(np.abs(d))[d > 0]) > s_total / 2 else -1
        assert it.effect == pytest.approx(sign * (s_total - 2 * ref.statistic) / s_total,
                                          abs=1e-12)      # float sums of ranks only
        # per-group distribution against a tally of the cells
        for g in ("Pre", "Post"):
            cells = Counter(r[2 + j] for r in rows if r[1] == g)
            per = it.per_group[g]
            assert per["counts"] == {lab: cells.get(lab, 0) for lab in AGREE5}
            assert per["missing"] == cells.get("", 0)
    # Holm over the two items, written out
    p = sorted((it.p_value, k) for k, it in enumerate(comp.items))
    holm = {}
    running = 0.0
    for i, (pv, k) in enumerate(p):
        running = max(running, min(1.0, (len(p) - i) * pv))
        holm[k] = running
    assert [it.p_holm for it in comp.items] == pytest.approx([holm[0], holm[1]], rel=1e-12)
    # text and HTML show the per-group distributions, not only p-values
    assert main(["summarize", str(f), "--group", "Term", "--decimals", "0"]) == 0
    out = capsys.readouterr().out
    pre_agree = 100 * comp.items[0].per_group["Pre"]["agree_share"]
    assert re.search(rf"Pre +n=40 +agree +{pre_agree:.0f}%", out)
    assert "Holm p" in out and "pairs" in out
    html = tmp_path / "r.html"
    assert main(["report", str(f), "--group", "Term", "-o", str(html)]) == 0
    text = html.read_text()
    assert "Answers per group" in text and text.count("<svg") == 2      # faceted chart too


def test_unpaired_without_ids_and_order_as_given(tmp_path, capsys):
    rng = random.Random(5)
    rows = [["Term", "Q1"]] + [[t, rng.choice(AGREE5)] for t in TERMS for _ in range(12)]
    # suppressed: 2 < 5 and 3 < 5; pooled they are 5, so no shown group is withheld too
    rows += [["Fall 2025", "Agree"]] * 2 + [["Spring 2026", "Disagree"]] * 3
    f = tmp_path / "terms.csv"
    f.write_text("\n".join(",".join(r) for r in rows) + "\n")
    data = read_survey(f, group="Term")
    order = ["Fall 2023", "Spring 2024", "Fall 2024"]
    comp = compare_groups(data, "Term", order=order)
    assert comp.shown == order and comp.paired_by == ""
    it = comp.items[0]
    assert it.test == "kruskal-wallis" and list(it.per_group) == order
    assert "Fall 2025" not in it.per_group            # small cell suppressed everywhere
    assert "Spring 2026" not in it.per_group
    pos = [k for t in order for k, r in enumerate(rows[1:]) if r[0] == t]
    x = [order.index(rows[1 + k][0]) for k in pos]
    y = [CODE[rows[1 + k][1]] for k in pos]
    rho = stats.spearmanr(x, y)
    assert (it.trend["rho"], it.trend["p_value"]) == pytest.approx((rho.statistic, rho.pvalue),
                                                                   rel=1e-12)
    assert compare_groups(data, "Term").shown == TERMS          # data order by default
    png = tmp_path / "facets.png"
    assert main(["summarize", str(f), "--group", "Term", "--group-order", *order,
                 "--chart", str(png), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert list(out["groups"]["items"][0]["per_group"]) == order
    assert png.read_bytes().startswith(b"\x89PNG")
    # the file name after --group-order is the positional, not one more group name
    assert main(["summarize", "--group", "Term", "--group-order", *order[::-1], str(f),
                 "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert list(out["groups"]["items"][0]["per_group"]) == order[::-1]


def test_tables_csv_xlsx_neutralise_formulas_and_match_json(tmp_path, capsys):
    f = tmp_path / "s.csv"
    f.write_text('"=HYPERLINK(""http://x"")",@SUM(A1),Q3\nAgree,Disagree,Agree\n'
                 "Strongly agree,Agree,Neutral\nAgree,,Disagree\n")
    assert main(["summarize", str(f), "--json"]) == 0
    ref = json.loads(capsys.readouterr().out)["items"]
    for suffix in (".csv", ".xlsx"):
        out = tmp_path / f"table{suffix}"
        assert main(["summarize", str(f), "--table", str(out)]) == 0
        if suffix == ".csv":
            recs = list(csv.DictReader(io.StringIO(out.read_text(encoding="utf-8-sig"))))
        else:
            ws = openpyxl.load_workbook(out).active
            vals = [[c.value for c in r] for r in ws.iter_rows()]
            assert all(c.data_type != "f" for r in ws.iter_rows() for c in r)
            recs = [dict(zip(vals[0], v)) for v in vals[1:]]
        assert [r["item"] for r in recs] == ['\'=HYPERLINK("http://x")', "'@SUM(A1)", "Q3"]
        for r, it in zip(recs, ref):
            assert int(r["n"]) == it["n"] and int(r["missing"]) == it["missing"]
            assert float(r["median"]) == it["median"] and float(r["SD"]) == pytest.approx(
                it["sd"], rel=1e-9)                  # CSV text round trip of a float
            assert int(r["Agree (count)"]) == it["counts"]["Agree"]


def test_chart_has_title_and_end_totals(tmp_path):
    f = tmp_path / "s.csv"
    f.write_text("Q1\n" + "Agree\n" * 3 + "Disagree\n" + "Neutral\n")
    out = tmp_path / "c.svg"
    assert main(["summarize", str(f), "--chart", str(out)]) == 0
    svg = out.read_text()
    assert "s.csv: answers per item" in svg
    assert ">60%<" in svg and ">20%<" in svg            # 3/5 agree, 1/5 disagree


def test_claims_upper_bound_and_neutral_category(tmp_path, capsys):
    f = tmp_path / "s.csv"
    f.write_text("Q1\n" + "Agree\n" * 2 + "Neither agree nor disagree\n" * 3
                 + "Disagree\n" * 45 + "\n")
    claims = tmp_path / "c.toml"
    claims.write_text('[[claims]]\nitem = 1\ncategories = ["Agree"]\ncomparison = "<"\n'
                      'threshold = 30\n[[claims]]\nitem = 1\ncategories = ["Neutral"]\n'
                      'comparison = "<="\nthreshold = 50\n')
    assert main(["claims", str(f), str(claims), "--json"]) == 0
    res = json.loads(capsys.readouterr().out)["claims"]
    assert res[0]["verdict_code"] == "holds" and "upper bound" in res[0]["reason"]
    assert "lower" not in res[0]["verdict"]
    assert (res[1]["k"], res[1]["n"]) == (3, 50)        # "Neutral" = the neutral label


def test_verify_table_needs_n_or_a_range(capsys):
    from analysis.tables import published_dir
    assert main(["verify-table", str(published_dir() / "table1.csv")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--n" in err and "--n-range" in err


def test_python_api_gives_the_cli_numbers_and_keeps_na_as_text(tmp_path, capsys):
    import pandas as pd

    import analysis
    f = tmp_path / "s.csv"
    f.write_text("Q1,Q2\nAgree,N/A\nN/A,Disagree\nAgree,Agree\n,Agree\n")
    frame = analysis.summarize(analysis.read_survey(f)).to_frame()
    assert main(["summarize", str(f), "--json"]) == 0
    cli = json.loads(capsys.readouterr().out)["items"]
    assert list(frame["excluded"]) == [1, 1] == [it["excluded"] for it in cli]   # "N/A" x 1
    assert list(frame["n"]) == [it["n"] for it in cli]
    assert list(frame["median"]) == [it["median"] for it in cli]
    # a frame read by pandas with its defaults has lost "N/A": said in the notes
    data = analysis.survey_from_frame(pd.read_csv(f))
    assert any("keep_default_na=False" in n for n in data.notes)


def test_no_suppressed_group_is_the_total_minus_the_shown_groups(tmp_path, capsys):
    """Complementary suppression, on both routes (--group and --by).

    The tester's survey3.csv: sections A and B of six respondents, C of two answering
    Strongly disagree to every item. C is under 5; were A and B shown beside the total,
    C would be total - A - B exactly. So the smaller of the others (A and B tie at 6:
    the first, A) is withheld too, and total - shown pools A and C: 8 respondents, never
    C's answers alone (by hand, C's counts are 2 Strongly disagree and nothing else).
    """
    from tests.test_analysis_institution import SURVEY3
    f = tmp_path / "survey3.csv"
    f.write_text(SURVEY3)
    c_counts = {lab: (2 if lab == "Strongly disagree" else 0) for lab in AGREE5}

    def remainder(total, shown):
        return {lab: total[lab] - sum(s[lab] for s in shown) for lab in AGREE5}

    assert main(["summarize", str(f), "--group", "Section", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    groups = {g["group"]: g for g in out["groups"]["groups"]}
    assert [g for g in groups if not groups[g]["suppressed"]] == ["B"]
    assert "complementary suppression" in out["groups"]["note"]
    hidden = out["respondents"] - sum(g["respondents"] for g in groups.values()
                                      if not g["suppressed"])
    assert hidden == 8 >= 5
    for total, comp in zip(out["items"], out["groups"]["items"]):
        rest = remainder(total["counts"], [d["counts"] for d in comp["per_group"].values()])
        assert list(comp["per_group"]) == ["B"] and rest != c_counts

    assert main(["summarize", str(f), "--by", "Section", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    shown = [r for r in out["rows"] if r["Section"] != "(all)" and "suppressed" not in r]
    assert {r["Section"] for r in shown} == {"B"}
    assert any("complementary suppression" in n for n in out["notes"])
    for total in out["overall"]:
        rows = [r for r in shown if r["item"] == total["item"]]
        rest = remainder(total["counts"], [{lab: r[f"{lab} (count)"] for lab in AGREE5}
                                           for r in rows])
        assert rest != c_counts


PREPOST = """student_id,Term,Q1,Q2
1,Pre,Disagree,Neutral
2,Pre,Strongly disagree,Agree
3,Pre,Agree,Disagree
4,Pre,Strongly disagree,Strongly disagree
5,Pre,Agree,Strongly agree
6,Pre,Strongly disagree,Neutral
7,Pre,Disagree,Neutral
8,Pre,Strongly disagree,Strongly disagree
1,Post,Disagree,Strongly agree
2,Post,Neutral,Strongly disagree
3,Post,Strongly agree,Agree
4,Post,Neutral,Disagree
5,Post,Strongly agree,Agree
6,Post,Neutral,Strongly disagree
7,Post,Disagree,Strongly agree
8,Post,Strongly disagree,Disagree
"""


def test_group_lines_round_as_the_main_table(tmp_path, capsys):
    """Group lines follow --decimals and --percent-method with the half-away rule.

    By hand, Post answers Q1: SD 1, D 2, N 3, A 0, SA 2 of 8, i.e. 12.5, 25, 37.5, 0,
    25 %. Half away from zero at 0 decimals: 13, 25, 38, 0, 25 (Python's round would
    give 12 and 38). Largest remainder at 0 decimals: floors 12, 25, 37, 0, 25 leave 1
    unit; the remainders .5 (SD) and .5 (N) tie, so the first label printed (SD) gets
    it: 13, 25, 37, 0, 25 (adds up to 100). At 2 decimals: 12.50 25.00 37.50 0.00 25.00.
    Post agreement on Q1: 2 of 8 = 25 %; on Q2 (A 2, SA 2): 4 of 8 = 50 %.
    """
    f = tmp_path / "prepost.csv"
    f.write_text(PREPOST)

    def post_q1(*flags):
        assert main(["summarize", str(f), "--group", "Term", *flags]) == 0
        lines = capsys.readouterr().out.splitlines()
        q1 = lines.index(next(ln for ln in lines if ln.startswith("  Q1:")))
        return next(ln for ln in lines[q1:] if ln.strip().startswith("Post"))

    def cells(line):
        return re.findall(r"(?:disagree|Disagree|Agree|agree) ([0-9.]+)%", line.split("|")[1])

    assert cells(post_q1("--decimals", "0")) == ["13", "25", "38", "0", "25"]
    assert cells(post_q1("--decimals", "0", "--percent-method", "largest_remainder")) == [
        "13", "25", "37", "0", "25"]
    line = post_q1("--decimals", "2")
    assert cells(line) == ["12.50", "25.00", "37.50", "0.00", "25.00"]
    assert re.search(r"agree 25\.00%", line)


# Pre and post answers (agree5 codes 1..5), worked by hand. Unpaired, post against pre:
# Cliff's delta = sum over post x of (#pre below x - #pre above x) / 25
#   = (-1 + 2 + 2 + 4 + 4) / 25 = 11/25; U of post = 2 + 3.5 + 3.5 + 4.5 + 4.5 = 18
#   (pairs where post is higher, ties half), and 2 U / 25 - 1 = 11/25 too.
# Paired (ids s1..s5), post - pre = -2, 2, 1, 2, 1: |d| ranks 1s -> 1.5, 2s -> 4;
#   T+ = 4 + 1.5 + 4 + 1.5 = 11, T- = 4, r = (11 - 4) / 15 = 7/15; two-sided statistic 4.
PRE_POST = [("s1", 4, 2), ("s2", 1, 3), ("s3", 2, 3), ("s4", 2, 4), ("s5", 3, 4)]


def test_effect_sizes_point_the_same_way_with_and_without_ids(tmp_path, capsys):
    """Regression: Cliff's delta was first minus second, the paired rank-biserial second
    minus first, so one pre->post improvement read -1 without ids and +1 with them."""
    lab = BUILTIN_SCALES["agree5"].labels
    rows = [(i, t, lab[c - 1]) for i, pre, post in PRE_POST for t, c in (("Pre", pre), ("Post", post))]
    with_id, no_id = tmp_path / "pp.csv", tmp_path / "pp_noid.csv"
    with_id.write_text("id,Term,Q1\n" + "".join(f"{i},{t},{a}\n" for i, t, a in rows))
    no_id.write_text("Term,Q1\n" + "".join(f"{t},{a}\n" for _, t, a in rows))
    want = {(with_id, False): ("rank_biserial_paired", 7 / 15, 4),
            (no_id, False): ("cliffs_delta", 11 / 25, 18),
            (with_id, True): ("rank_biserial_paired", -7 / 15, 4),     # statistic has no sign
            (no_id, True): ("cliffs_delta", -11 / 25, 25 - 18)}        # U of Pre
    for (f, flipped), (name, effect, statistic) in want.items():
        order = ["Post", "Pre"] if flipped else ["Pre", "Post"]
        assert main(["summarize", str(f), "--group", "Term", "--scale", "agree5",
                     "--group-order", *order, "--json"]) == 0
        it = json.loads(capsys.readouterr().out)["groups"]["items"][0]
        assert (it["effect_name"], it["statistic"]) == (name, statistic)
        assert it["effect"] == pytest.approx(effect, abs=1e-12)     # sums of halves and ranks
        assert it["direction"].startswith(f"{order[1]} vs {order[0]}: positive when "
                                          f"{order[1]} answers higher")
    assert main(["summarize", str(no_id), "--group", "Term", "--scale", "agree5"]) == 0
    out = capsys.readouterr().out
    assert "cliffs_delta = 0.440" in out and "direction: Post vs Pre: positive when Post" in out
    html = tmp_path / "r.html"
    assert main(["report", str(with_id), "--group", "Term", "--scale", "agree5",
                 "-o", str(html)]) == 0
    text = html.read_text()
    assert "rank_biserial_paired = 0.467" in text and "Post vs Pre: positive when Post" in text


def _prepost(tmp_path, pre, post):
    """A pre/post file: ``pre`` and ``post`` are lists of (student id, Q1 answer)."""
    f = tmp_path / "pp.csv"
    rows = [["student_id", "Term", "Q1"]] + [[s, "Pre", a] for s, a in pre] + \
        [[s, "Post", a] for s, a in post]
    with open(f, "w", newline="") as fh:
        csv.writer(fh).writerows(rows)
    return f


def test_pairing_says_why_the_paired_test_was_not_used(tmp_path, capsys):
    """Regressions: a student submitting Pre twice fell out of the pairing, which then had
    4 pairs (< 5) and went to Mann-Whitney unsaid; 5 pairs that never changed were
    tested as independent groups under a header saying 'paired'."""
    # s1 twice in Pre (rows 2 and 7: header row 1, s1-s5 rows 2-6, s1 again row 7)
    f = _prepost(tmp_path, [(f"s{k}", "Disagree") for k in range(1, 6)] + [("s1", "Agree")],
                 [(f"s{k}", "Agree") for k in range(1, 6)])
    data = read_survey(f, group="Term")
    assert any("'student_id': 1 id on more than one row with the same 'Term' ('s1' in rows "
               "2, 7)" in n for n in data.notes), data.notes
    comp = compare_groups(data, "Term")
    assert comp.paired_by == "" and comp.items[0].test == "mann-whitney"
    assert "'s1' 2 times in Pre" in comp.pairing
    assert "4 ids answered once in both groups, fewer than 5" in comp.pairing
    # five pairs, every one the same both times: paired, and no change to test
    same = [(f"s{k}", AGREE5[k - 1]) for k in range(1, 6)]
    comp = compare_groups(read_survey(_prepost(tmp_path, same, same), group="Term"), "Term")
    it = comp.items[0]
    assert comp.paired_by == "student_id" and (it.test, it.pairs) == ("none", 5)
    assert "same answer both times" in it.note
    assert main(["summarize", str(tmp_path / "pp.csv"), "--group", "Term", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["groups"]["items"][0]["pairs"] == 5


def test_repeated_email_is_noted_with_its_rows(tmp_path, capsys):
    """One address on rows 2 and 4 (header row 1): both rows counted, and said so."""
    f = tmp_path / "g.csv"
    f.write_text("Email Address,Q1\na@x.edu,Agree\nb@x.edu,Agree\n A@x.edu,Disagree\n")
    assert main(["summarize", str(f)]) == 0
    err = capsys.readouterr().err
    assert "column 'Email Address': 1 id on more than one row ('a@x.edu' in rows 2, 4)" in err


def test_chart_labels_are_drawn_as_written(tmp_path):
    """Regression: a label 'C:\\Users\\me' was drawn 'C:\\\\Users\\\\me' (backslashes doubled);
    dollars must stay literal too (no mathtext), in item names and group panel titles."""
    f = tmp_path / "s.csv"
    with open(f, "w", newline="") as fh:
        csv.writer(fh).writerows([["Saved to C:\\Users\\me", "Paid $50 (vs $20)", "Section"]]
                                 + [["Agree", "Disagree", "AB"[i % 2]] for i in range(10)])
    for extra in ([], ["--group", "Section"]):
        out = tmp_path / "c.svg"
        assert main(["summarize", str(f), "--chart", str(out), *extra]) == 0
        svg = out.read_text()
        assert "Saved to C:\\Users\\me" in svg and "\\\\" not in svg
        assert "Paid $50 (vs $20)" in svg


def test_long_item_labels_do_not_overlap_in_the_chart(tmp_path):
    """Regression: an eight-line label overlapped its neighbour's. Reference: the drawn
    label boxes (matplotlib's own text extents), which must not share any height."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from analysis.chart import diverging_bar
    long_name = "I understand the difference between " * 6 + "the forms."
    f = tmp_path / "s.csv"
    with open(f, "w", newline="") as fh:
        csv.writer(fh).writerows([[f"Q{k} short" for k in range(1, 6)] + [long_name]
                                  + [f"Q{k} short" for k in range(7, 13)]]
                                 + [["Agree"] * 5 + ["Disagree"] + ["Agree"] * 6] * 4)
    fig = diverging_bar(summarize(read_survey(f)))
    FigureCanvasAgg(fig).draw()
    boxes = sorted((t.get_window_extent().y0, t.get_window_extent().y1)
                   for t in fig.axes[0].get_yticklabels())
    assert len(boxes) == 12
    for (lo0, hi0), (lo1, hi1) in zip(boxes, boxes[1:]):
        assert hi0 <= lo1, boxes


@pytest.mark.parametrize("column", ["respondent", "Student", "participant", "RespondentID"])
def test_an_id_repeated_in_any_identifier_column_is_noted(tmp_path, capsys, column):
    """QA 10 item 2: dupresp.csv's id column `respondent` was listed as an identifier column,
    yet its repeated S1 (rows 2 and 4: header row 1) got no note, on both routes: the note
    looked only for the pairing names (student id, email ...). Every name the reader leaves
    out of the items as an identifier, but row numbers, is a person id now: one list."""
    from analysis.ingest import _ID_LIKE, person_id_column
    f = tmp_path / "dupresp.csv"
    f.write_text(f"{column},Q1,Q2\nS1,Agree,Agree\nS2,Disagree,Agree\nS1,Agree,Agree\n"
                 "S3,Agree,Disagree\n")
    want = f"column {column!r}: 1 id on more than one row ('S1' in rows 2, 4)"
    assert main(["summarize", str(f)]) == 0
    assert want in capsys.readouterr().err
    assert main(["summarize", str(f), "--json"]) == 0          # in the JSON too, as --by's
    assert any(want in n for n in json.loads(capsys.readouterr().out)["notes"])
    assert main(["summarize", str(f), "--by", "Q2", "--min-group", "1"]) == 0
    assert f"column {column!r}: 1 id on more than one row with the same 'Q2'" in capsys.readouterr().out
    spellings = ["respondent", "respondent id", "respondent_id", "respondentid", "id", "student",
                 "student id", "student_id", "participant", "participant id", "participantid"]
    assert all(_ID_LIKE.match(s) and person_id_column([s]) == 0 for s in spellings)


def test_a_long_file_read_as_wide_notes_its_repeated_respondents(tmp_path, capsys):
    """QA 10 item 2: long.csv forced wide (--shape wide) counted 2 rows per student as 2
    respondents with no note. By hand: s0 on rows 2-3, s1 on rows 4-5."""
    f = tmp_path / "long.csv"
    f.write_text("respondent,item,answer\ns0,Q1,Agree\ns0,Q2,Disagree\ns1,Q1,Agree\n"
                 "s1,Q2,Agree\n")
    assert main(["summarize", str(f), "--shape", "wide"]) == 0
    assert ("column 'respondent': 2 ids on more than one row ('s0' in rows 2, 3; 's1' in rows "
            "4, 5)") in capsys.readouterr().err


def _overlap(tmp_path, shared=6, size=40):
    """QA 16 #1's overlap.csv rebuilt: two independent sections of ``size`` students each
    (ids S000.. and, from S(size - shared) on, the second section), ``shared`` ids in both
    as after a section change. Q1 differs sharply: Sec A answers Neutral..Strongly agree,
    Sec B Strongly disagree..Neutral. Returns the file and {section: {id: Q1 code}}."""
    a_ids = [f"S{k:03d}" for k in range(size)]
    b_ids = [f"S{k:03d}" for k in range(size - shared, 2 * size - shared)]
    rows, q1 = [["student_id", "Section", "Q1", "Q2"]], {"Sec A": {}, "Sec B": {}}
    for sec, ids, codes in (("Sec A", a_ids, (3, 4, 4, 5)), ("Sec B", b_ids, (1, 1, 2, 3))):
        for k, sid in enumerate(ids):
            c = codes[k % 4]
            q1[sec][sid] = c
            rows.append([sid, sec, AGREE5[c - 1], AGREE5[(k * 7) % 5]])
    f = tmp_path / "overlap.csv"
    with open(f, "w", newline="") as fh:
        csv.writer(fh).writerows(rows)
    return f, q1


def _json_groups(capsys, *argv):
    assert main(["summarize", *map(str, argv), "--json"]) == 0
    return json.loads(capsys.readouterr().out)["groups"]


def test_a_few_shared_ids_do_not_turn_two_sections_into_pre_post(tmp_path, capsys):
    """QA 16 #1: six ids in both of two sections of 40 made --group run the signed-rank
    test on those six pairs (p = 0.0625) under a "pre/post" heading, where the independent
    test finds the difference (p ~ 1e-13). The automatic rule pairs only when at least half
    of each group's respondents pair; --paired and --independent decide it explicitly."""
    f, q1 = _overlap(tmp_path)
    ref = stats.mannwhitneyu(list(q1["Sec B"].values()), list(q1["Sec A"].values()),
                             alternative="two-sided")
    assert ref.pvalue < 1e-10                      # the difference the data were built with
    for flags in ([], ["--independent"]):
        g = _json_groups(capsys, f, "--group", "Section", *flags)
        it = g["items"][0]
        assert (g["design"], g["paired_by"], it["test"]) == ("independent", "", "mann-whitney")
        # scipy on the codes the test wrote; same inputs and method, so only float noise
        assert (it["statistic"], it["p_value"]) == pytest.approx((ref.statistic, ref.pvalue),
                                                                 rel=1e-12)
        assert "6 ids appear in both groups, so the samples are not fully independent" in \
            g["pairing"]
    assert main(["summarize", str(f), "--group", "Section"]) == 0
    out = capsys.readouterr().out
    assert "pre/post" not in out and "paired by" not in out
    assert "fewer than half of Sec A's 40 or Sec B's 40 respondents: compared as " \
           "independent samples" in out
    # --paired: the six pairs, as asked, and how many respondents the test leaves out
    g = _json_groups(capsys, f, "--group", "Section", "--paired")
    it = g["items"][0]
    both = sorted(set(q1["Sec A"]) & set(q1["Sec B"]))
    pre, post = (np.array([q1[s][k] for k in both]) for s in ("Sec A", "Sec B"))
    ref = stats.wilcoxon(post, pre)
    assert (g["design"], it["test"], it["pairs"]) == ("paired", "wilcoxon-signed-rank", 6)
    assert (it["statistic"], it["p_value"]) == pytest.approx((ref.statistic, ref.pvalue),
                                                             rel=1e-12)
    assert "leaves out 68 of the 80 respondents" in g["pairing"]       # 80 - 2 x 6


def test_the_automatic_pairing_rule_at_half_of_each_group(tmp_path, capsys):
    """The rule's edge, by hand: Pre and Post of 10 respondents each with 5 ids in both
    pair (5 >= 10 / 2); with 4 ids in both (and --min-group 3, so the count of pairs is
    not what stops it) they do not, and the note says so. --independent on a genuine
    pre/post file gives Mann-Whitney on all answers (scipy)."""
    def prepost(n_shared):
        pre = [(f"s{k}", AGREE5[k % 3]) for k in range(10)]
        post = [(f"s{k}" if k < n_shared else f"t{k}", AGREE5[2 + k % 3]) for k in range(10)]
        return _prepost(tmp_path, pre, post), pre, post

    f, pre, post = prepost(5)
    g = _json_groups(capsys, f, "--group", "Term")
    assert (g["design"], g["items"][0]["pairs"]) == ("paired", 5)
    assert "leaves out 10 of the 20 respondents" in g["pairing"]
    f, pre, post = prepost(4)
    g = _json_groups(capsys, f, "--group", "Term", "--min-group", "3")
    assert g["design"] == "independent" and g["items"][0]["test"] == "mann-whitney"
    assert g["pairing"].startswith("4 ids answered once in both groups, fewer than half of "
                                   "Pre's 10 or Post's 10 respondents")
    f, pre, post = prepost(10)
    g = _json_groups(capsys, f, "--group", "Term", "--independent")
    ref = stats.mannwhitneyu([CODE[a] for _, a in post], [CODE[a] for _, a in pre],
                             alternative="two-sided")
    it = g["items"][0]
    assert (g["design"], it["pairs"]) == ("independent", 0)
    assert (it["statistic"], it["p_value"]) == pytest.approx((ref.statistic, ref.pvalue),
                                                             rel=1e-12)
    assert "10 ids appear in both groups" in g["pairing"]
    html = tmp_path / "r.html"
    assert main(["report", str(f), "--group", "Term", "--independent", "-o", str(html)]) == 0
    assert "mann-whitney" in html.read_text() and "Paired design" not in html.read_text()
    assert main(["report", str(f), "--group", "Term", "-o", str(html)]) == 0
    assert "Paired design: respondents answering once in both groups are paired by student_id" \
        in html.read_text()


@pytest.mark.parametrize("argv, words", [
    (["nuid.csv", "--group", "Term", "--paired"],
     "nuid.csv: --paired: the file has no column identifying respondents"),
    (["three.csv", "--group", "Term", "--paired"],
     "three.csv: --paired: the paired test compares two groups, and 3 are compared"),
    (["few.csv", "--group", "Term", "--paired"],
     "few.csv: --paired: 4 ids in column 'student_id' answered once in both 'Pre' and "
     "'Post', fewer than --min-group 5"),
    (["few.csv", "--paired"], "--paired says how --group compares groups; give --group"),
    (["few.csv", "--by", "Term", "--independent"], "--independent is not available with --by"),
    (["few.csv", "--group", "Term", "--paired", "--independent"],
     "argument --independent: not allowed with argument --paired"),
])
def test_paired_and_independent_are_refused_when_the_data_contradict_them(
        tmp_path, capsys, argv, words):
    """One line naming the flag, exit 2, no output (the reader's notes may come first): no
    ids to pair, three groups, four pairs under --min-group 5, no --group, --by, and both
    flags at once."""
    (tmp_path / "nuid.csv").write_text("Term,Q1\n" + "Pre,Agree\nPost,Disagree\n" * 5)
    (tmp_path / "three.csv").write_text(
        "id,Term,Q1\n" + "".join(f"s{k},{t},Agree\n" for k in range(5)
                                 for t in ("Pre", "Mid", "Post")))
    _prepost(tmp_path, [(f"s{k}", "Agree") for k in range(6)],
             [(f"s{k}" if k < 4 else f"t{k}", "Disagree") for k in range(6)]).rename(
        tmp_path / "few.csv")
    argv = [str(tmp_path / argv[0]), *argv[1:]]
    assert main(["summarize", *argv]) == 2
    cap = capsys.readouterr()
    errors = [ln for ln in cap.err.splitlines() if not ln.startswith("note: ")]
    assert cap.out == "" and len(errors) == 1 and words in errors[0], cap.err


def _holm_by_hand(p):
    """Holm's step-down adjustment written out: sorted p times the hypotheses left, running
    maximum, capped at 1; returned in the input order."""
    out, running = [0.0] * len(p), 0.0
    for i, k in enumerate(sorted(range(len(p)), key=lambda k: p[k])):
        running = max(running, min(1.0, (len(p) - i) * p[k]))
        out[k] = running
    return out


def test_a_trend_is_tested_only_over_an_order_the_user_states(tmp_path, capsys):
    """QA 16 #4: with no --group-order the "trend over groups" ran over the order of first
    appearance, so sorting the file turned p = 0.14 into p = 0.004 with the sign flipped,
    and its p was in no Holm family. Now: no trend without a stated order (one note says
    why), Kruskal-Wallis the same for both row orders, and with --group-order the trend
    is Spearman over the stated order (scipy), Holm-adjusted over the items' trends."""
    rng = random.Random(16)
    rows = [(sec, rng.choice(AGREE5[k:k + 3]), rng.choice(AGREE5))
            for k, sec in enumerate(["Sec A", "Sec B", "Sec C"]) for _ in range(12)]
    mixed, by_name = tmp_path / "mixed.csv", tmp_path / "sorted.csv"
    for f, order in ((mixed, rng.sample(rows, len(rows))), (by_name, sorted(rows, reverse=True))):
        f.write_text("Section,Q1,Q2\n" + "".join(f"{s},{a},{b}\n" for s, a, b in order))
    runs = [_json_groups(capsys, f, "--group", "Section") for f in (mixed, by_name)]
    for g in runs:
        assert g["trend_note"].startswith("no trend over the groups: they come in the order "
                                          "in which they first appear in the file")
        for j, it in enumerate(g["items"]):
            ref = stats.kruskal(*[[CODE[r[1 + j]] for r in rows if r[0] == s]
                                  for s in ("Sec A", "Sec B", "Sec C")])
            assert it["trend"] is None and it["direction"] == "epsilon_squared has no sign"
            assert (it["statistic"], it["p_value"]) == pytest.approx(
                (ref.statistic, ref.pvalue), rel=1e-12)      # same data, same method
    assert main(["summarize", str(mixed), "--group", "Section"]) == 0
    assert "Spearman" not in capsys.readouterr().out
    order = ["Sec C", "Sec A", "Sec B"]
    for f in (mixed, by_name):
        g = _json_groups(capsys, f, "--group", "Section", "--group-order", *order)
        assert g["trend_note"] == ""
        p_ref = []
        for j, it in enumerate(g["items"]):
            x = [order.index(r[0]) for r in rows]
            ref = stats.spearmanr(x, [CODE[r[1 + j]] for r in rows])
            assert (it["trend"]["rho"], it["trend"]["p_value"]) == pytest.approx(
                (ref.statistic, ref.pvalue), rel=1e-12)     # ties ranked the same way
            p_ref.append(ref.pvalue)
        assert [it["trend"]["p_holm"] for it in g["items"]] == pytest.approx(
            _holm_by_hand(p_ref), rel=1e-12)
        # the main tests keep their own family: the trends do not enter it
        assert [it["p_holm"] for it in g["items"]] == pytest.approx(
            _holm_by_hand([it["p_value"] for it in g["items"]]), rel=1e-12)
        assert "the 2 trend p-values as a family of their own" in g["multiplicity"]
    g = _json_groups(capsys, mixed, "--group", "Section", "--group-order", "Sec B")
    assert all(it["trend"] is None for it in g["items"])
    assert "--group-order does not place 'Sec A', 'Sec C'" in g["trend_note"]
    html = tmp_path / "r.html"
    assert main(["report", str(mixed), "--group", "Section", "-o", str(html)]) == 0
    text = html.read_text()
    assert "No trend over the groups" in text and "trend rho" not in text


def test_group_names_are_quoted_as_the_file_writes_them(tmp_path, capsys):
    """QA 18 #9: the coverage line quoted group names with Python's repr, so a section named
    "q'< printed as '"q\\'<' (a backslash the file does not hold). Groups: S1 (10), "q'< (12),
    S3 (3, suppressed), S4 (20; S1 withheld by complementary suppression), as in the test
    below."""
    rng = random.Random(5)
    odd = '"q\'<'
    rows = [(s, rng.choice(AGREE5)) for s, n in (("S1", 10), (odd, 12), ("S3", 3), ("S4", 20))
            for _ in range(n)]
    f = tmp_path / "odd.csv"
    with open(f, "w", newline="") as fh:
        csv.writer(fh).writerows([("section", "Q1")] + rows)
    g = _json_groups(capsys, f, "--group", "section")
    assert g["coverage"].startswith("the tests compare 2 of the 4 groups ('\"q'<', 'S4': 32 "
                                    "of 45 respondents)"), g["coverage"]


def test_the_test_says_which_groups_it_covers_after_suppression(tmp_path, capsys):
    """QA 16 #5: sections of 10, 12, 3 and 20; S3 (< 5) is suppressed and S1 withheld by
    complementary suppression, and the test then silently compared S2 with S4 only. By
    hand: 2 of 4 groups, 32 of 45 respondents, 13 left out. The test is Mann-Whitney on
    S2 and S4 (scipy). With --min-group 3 every group is shown; S3 left Q2 blank, so Q2's
    Kruskal-Wallis covers the other three, and says so."""
    rng = random.Random(5)
    rows = [(s, rng.choice(AGREE5), "" if s == "S3" else rng.choice(AGREE5))
            for s, n in (("S1", 10), ("S2", 12), ("S3", 3), ("S4", 20)) for _ in range(n)]
    f = tmp_path / "supp.csv"
    f.write_text("section,Q1,Q2\n" + "".join(",".join(r) + "\n" for r in rows))
    want = ("the tests compare 2 of the 4 groups ('S2', 'S4': 32 of 45 respondents); the 13 "
            "respondents of the suppressed groups ('S1', 'S3') are left out, for disclosure "
            "reasons")
    g = _json_groups(capsys, f, "--group", "section")
    assert (g["tested_groups"], g["left_out"], g["coverage"]) == (["S2", "S4"], 13, want)
    it = g["items"][0]
    ref = stats.mannwhitneyu([CODE[r[1]] for r in rows if r[0] == "S4"],
                             [CODE[r[1]] for r in rows if r[0] == "S2"], alternative="two-sided")
    assert (it["statistic"], it["p_value"]) == pytest.approx((ref.statistic, ref.pvalue),
                                                             rel=1e-12)
    assert main(["summarize", str(f), "--group", "section"]) == 0
    assert f"  coverage: {want}\n" in capsys.readouterr().out
    html = tmp_path / "r.html"
    assert main(["report", str(f), "--group", "section", "-o", str(html)]) == 0
    assert "Coverage: the tests compare 2 of the 4 groups (&#39;S2&#39;, &#39;S4&#39;: 32 of " \
           "45 respondents); the 13 respondents" in html.read_text()
    capsys.readouterr()                                  # the report's "wrote ..." line
    g = _json_groups(capsys, f, "--group", "section", "--min-group", "3")
    assert (g["coverage"], g["left_out"], g["tested_groups"]) == ("", 0, ["S1", "S2", "S3", "S4"])
    it = g["items"][1]
    ref = stats.kruskal(*[[CODE[r[2]] for r in rows if r[0] == s] for s in ("S1", "S2", "S4")])
    assert (it["statistic"], it["p_value"]) == pytest.approx((ref.statistic, ref.pvalue),
                                                             rel=1e-12)
    assert it["note"] == "'S3' gave no answer to this item: the test compares the other groups"


def test_a_paired_item_with_too_few_pairs_is_not_tested_as_independent(tmp_path, capsys):
    """Ten students answer Pre and Post (a paired design by the rule); only three answer
    Q2 at Post. Those 3 pairs are under --min-group 5, and testing Q2's 10 + 3 answers as
    independent samples would treat the same students as different ones: no test, with
    the reason. Q1 (10 pairs) is the signed-rank test (scipy)."""
    rows = [["student_id", "Term", "Q1", "Q2"]]
    pre = [(k % 3) + 1 for k in range(10)]
    post = [(k % 3) + 3 for k in range(10)]
    rows += [[f"s{k}", "Pre", AGREE5[pre[k] - 1], "Agree"] for k in range(10)]
    rows += [[f"s{k}", "Post", AGREE5[post[k] - 1], "Disagree" if k < 3 else ""]
             for k in range(10)]
    f = tmp_path / "pp.csv"
    with open(f, "w", newline="") as fh:
        csv.writer(fh).writerows(rows)
    g = _json_groups(capsys, f, "--group", "Term")
    q1, q2 = g["items"]
    ref = stats.wilcoxon(post, pre)
    assert (g["design"], q1["test"], q1["pairs"]) == ("paired", "wilcoxon-signed-rank", 10)
    assert (q1["statistic"], q1["p_value"]) == pytest.approx((ref.statistic, ref.pvalue),
                                                             rel=1e-12)
    assert (q2["test"], q2["pairs"], q2["p_value"]) == ("none", 3, None)
    assert q2["note"] == ("3 pairs answered this item in both groups, fewer than 5: too few "
                          "for the paired test")


def test_a_paired_item_is_tested_only_on_enough_pairs_that_changed(analysis_cli, tmp_path):
    """QA 20 #3: with 9 of 10 pairs unchanged, the Wilcoxon test (which drops zero differences)
    ran on one pair and printed p = 1 and a 'perfect' effect of 1.000; an item no pair changed on
    gave pairs_unchanged 0. Now both have no test and count the unchanged pairs."""
    rows = ["student_id,Term,Q1,Q2"]
    for i in range(10):
        same = "Agree" if i % 2 else "Disagree"  # Q2: every student answers as before
        rows.append(f"s{i},Pre,Agree,{same}")
        rows.append(f"s{i},Post,{'Strongly agree' if i == 0 else 'Agree'},{same}")
    f = tmp_path / "prepost.csv"
    f.write_text("\n".join(rows) + "\n")
    code, out, err = analysis_cli("summarize", str(f), "--group", "Term", "--group-order", "Pre", "Post", "--json")
    assert code == 0, err
    items = {it["item"]: it for it in json.loads(out)["groups"]["items"]}
    q1, q2 = items["Q1"], items["Q2"]
    assert (q1["test"], q1["pairs"], q1["pairs_unchanged"]) == ("none", 10, 9)
    assert "1 of the 10 pairs changed their answer" in q1["note"]
    assert (q2["test"], q2["pairs"], q2["pairs_unchanged"]) == ("none", 10, 10)


def test_a_count_of_one_group_is_singular_and_an_email_is_an_identifier(tmp_path, analysis_cli):
    """QA 21 #11: --by printed "2 respondents in 1 groups", and the Email column used for pairing
    was left out as "its answers are not labels of scale 'agree5'". By hand: one section (A), two
    rows; Email identifies the respondent (analysis.ingest's person-id list names it)."""
    f = tmp_path / "one.csv"
    f.write_text("Email,Sec,Q1\na@x.edu,A,Agree\nb@x.edu,A,Disagree\n")
    code, out, err = analysis_cli("summarize", str(f), "--by", "Sec", "--min-group", "1")
    assert code == 0, err
    assert f"{f}: 2 respondents in 1 group by Sec; scale" in out, out
    for route in ([], ["--by", "Sec", "--min-group", "1"]):
        code, out, err = analysis_cli("summarize", str(f), "--json", *route)
        assert code == 0, err
        assert json.loads(out)["not_item_reasons"]["Email"] == "an identifier column"
    one = tmp_path / "single.csv"
    one.write_text("Email,Q1\na@x.edu,Agree\n")
    code, out, err = analysis_cli("summarize", str(one))
    assert code == 0, err
    assert f"{one}: 1 respondent, scale" in out, out


def test_a_count_of_one_respondent_is_singular(tmp_path, analysis_cli):
    """QA 19 #10: ``--min-group 1`` printed "groups under 1 respondents suppressed", and a group of
    one "b: 1 respondents". Section b has one respondent, a has two."""
    f = tmp_path / "one.csv"
    f.write_text("Section,Q1\na,Agree\na,Disagree\nb,Agree\n")
    code, out, err = analysis_cli("summarize", str(f), "--group", "Section", "--min-group", "1")
    assert code == 0, err
    assert "(groups under 1 respondent suppressed)" in out and "  b: 1 respondent\n" in out, out
    assert "  a: 2 respondents\n" in out and "1 respondents" not in out + err
    code, out, err = analysis_cli("summarize", str(f), "--group", "Section", "--min-group", "2")
    assert code == 0, err
    assert "(groups under 2 respondents suppressed)" in out and "  b: 1 respondent -- suppressed" in out, out
