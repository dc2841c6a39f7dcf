"""Verification of published percentage tables (analysis.tables) against the paper's Table 1.

Reference values
----------------
- Table 1 cells, N = 22 respondents, printed precision: read from data/published/ (as printed).
- Counts behind each row at N = 22 (hand check: k/22 * 100 rounded to one decimal,
  e.g. 13/22 = 59.09..., 14/22 = 63.63..., 12/22 = 54.54...)::

      #1  11  6  3  2  0        #4  12  7  2  1  0
      #2  13  7  0  1  1        #5   5  6  6  5  0
      #3  14  5  2  0  1

  Each row adds up to 22; every count prints as the published cell, except the
  Definitely Agree cells of #2, #3 and #4, which print 0.1 higher than any count gives
  (59.1, 63.6, 54.5 printed as 59.2, 63.7, 54.6). ``test_expected_counts_hand_check``
  holds these facts with decimal arithmetic, apart from the product.
"""
import csv
import itertools
import json
from decimal import ROUND_HALF_UP, Decimal
from fractions import Fraction

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from analysis.__main__ import main
from analysis.errors import SurveyInputError
from analysis.tables import (MAX_TABLE_CELLS, ROUNDING_RULES, PublishedTable, attainable_counts, load_table1,
                             published_dir, read_table_csv, round_fraction, table1_check,
                             verify_table)

EXPECTED_COUNTS = {  # hand check at N = 22, see module docstring
    "#1": [11, 6, 3, 2, 0],
    "#2": [13, 7, 0, 1, 1],
    "#3": [14, 5, 2, 0, 1],
    "#4": [12, 7, 2, 1, 0],
    "#5": [5, 6, 6, 5, 0],
}
# (item, label) -> nearest attainable printed value at N = 22 (13/22, 14/22, 12/22 at one decimal)
EXPECTED_UNATTAINABLE = {("#2", "Definitely Agree"): "59.1",
                         ("#3", "Definitely Agree"): "63.6",
                         ("#4", "Definitely Agree"): "54.5"}


def _published_rows():
    with open(published_dir() / "table1.csv", newline="", encoding="utf-8") as fh:
        return list(csv.DictReader(fh))


def _brute_attainable(printed: str, n: int) -> list[int]:
    """Independent route: decimal.Decimal ROUND_HALF_UP over every k (no Fractions)."""
    p = Decimal(printed)
    q = Decimal(1).scaleb(p.as_tuple().exponent)
    return [k for k in range(n + 1)
            if (Decimal(100 * k) / Decimal(n)).quantize(q, rounding=ROUND_HALF_UP) == p]


def test_expected_counts_hand_check():
    """The hand-checked counts of the docstring reproduce the published rows: each row adds
    up to N, and k/N rounded half-up to one decimal is the printed cell, except the three
    cells printed one unit (0.1) higher."""
    _, facts = load_table1()
    rows = {r["item"]: r for r in _published_rows()}
    labels = [c for c in _published_rows()[0] if c != "item"]
    off = {}
    for item, counts in EXPECTED_COUNTS.items():
        assert sum(counts) == facts.respondents == 22
        for label, k in zip(labels, counts):
            ours = (Decimal(100 * k) / Decimal(22)).quantize(Decimal("0.1"), ROUND_HALF_UP)
            printed = Decimal(rows[item][label])
            if ours != printed:
                assert printed - ours == Decimal("0.1"), (item, label)
                off[(item, label)] = str(ours)
    assert off == EXPECTED_UNATTAINABLE


def test_table1_as_published():
    """Every published cell is judged as the brute-force rule says; the three known cells fail."""
    check = table1_check()
    _, facts = load_table1()
    assert check.n == facts.respondents
    rows = {r["item"]: r for r in _published_rows()}
    bad = {}
    for row in check.rows:
        # printed rows add up to 100.0 exactly (as printed)
        assert sum(Decimal(rows[row.item][c.label]) for c in row.cells) == Decimal("100.0")
        for c in row.cells:
            printed = rows[row.item][c.label]
            assert c.counts == _brute_attainable(printed, check.n)
            assert c.published == float(printed)
            if not c.attainable:
                bad[(row.item, c.label)] = f"{c.nearest_values[0]:.1f}"
        assert row.reconstructed == EXPECTED_COUNTS[row.item]
        assert sum(row.reconstructed) == check.n
        assert row.consistent == all(c.attainable for c in row.cells)
        assert row.sum_ok                  # 100.0 printed: no sum finding on any row
    assert bad == EXPECTED_UNATTAINABLE


def test_unattainable_cells_explained_by_row_forcing():
    """Each printed row whose cells rounded from its counts add to 99.9 shows its largest
    cell 0.1 higher: the table was forced to show 100 per row."""
    check = table1_check()
    for row in check.rows:
        forced = "adding the row's deficit" in row.reason
        assert forced == (not row.consistent)
        assert all(("adding the row's deficit" in c.reason) == (not c.attainable) for c in row.cells)


def test_unknown_n_search_contains_no_n_but_stated_best():
    """No N in 1..300 attains the whole table; N = 22 attains the most cells."""
    table, facts = load_table1()
    check = verify_table(table, n_range=(1, 300))
    assert check.feasible_n == []
    assert check.n == facts.respondents


# 40 rows (~4 ms each) spread over the four rounding rules and 0-2 decimals: each rule meets ~10 rows a run.
@settings(max_examples=40)
@given(st.lists(st.integers(0, 40), min_size=2, max_size=6).filter(lambda c: sum(c) > 0),
       st.integers(0, 2), st.sampled_from(ROUNDING_RULES))
def test_round_trip_random_rows(counts, decimals, rule):
    """Percentages printed from real counts are always attainable, rows can sum to N,
    and the true N is among the N that make the table attainable."""
    n = sum(counts)
    printed = [round_fraction(Fraction(100 * c, n), decimals, rule) for c in counts]
    cells = tuple(f"{Decimal(p.numerator) / Decimal(p.denominator):.{decimals}f}" for p in printed)
    labels = tuple(f"L{j}" for j in range(len(counts)))
    table = PublishedTable(("q",), labels, (cells,))
    check = verify_table(table, n=n, rule=rule)
    row = check.rows[0]
    assert all(c.attainable for c in row.cells)
    assert row.consistent and row.sum_ok and row.findings == []
    for c, k in zip(row.cells, counts):
        assert k in c.counts
    if 100 / n > 10 ** -decimals:      # one count per printed step: reconstruction is exact
        assert row.reconstructed == counts
    ranged = verify_table(table, n_range=(max(1, n - 3), n + 3), rule=rule)
    assert n in ranged.feasible_n


def test_rounding_rules_differ_on_ties():
    # 22.5 exactly: half-away gives 23, half-even gives 22, truncate 22, ceil 23
    x = Fraction(45, 2)
    assert [round_fraction(x, 0, r) for r in ROUNDING_RULES] == [23, 22, 22, 23]
    assert attainable_counts(Fraction(0), 1, 22) == [0]
    with pytest.raises(ValueError, match="half_away"):
        round_fraction(x, 0, "bankers")


def test_cli_json_shape(tmp_path, capsys):
    _, facts = load_table1()
    assert main(["verify-table", str(published_dir() / "table1.csv"), "--n",
                 str(facts.respondents), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert set(out) == {"n", "rows"} and out["n"] == facts.respondents
    for row in out["rows"]:
        assert set(row) == {"item", "cells", "sum_ok", "consistent", "findings"}
        for cell in row["cells"]:
            assert set(cell) == {"label", "published", "attainable", "counts"}
    flags = {(r["item"], c["label"]) for r in out["rows"] for c in r["cells"] if not c["attainable"]}
    assert flags == set(EXPECTED_UNATTAINABLE)


@pytest.mark.parametrize("text, where", [
    ("item,A,B\nq1,50.0,5O.0\n", "row 2, column 'B'"),
    ("item,A,B\nq1,50.0,150\n", "row 2, column 'B'"),
    ("item,A,B\nq1,50.0\n", "row 2"),
    ("name,A,B\nq1,50.0,50.0\n", "row 1"),
    ("", "empty file"),
])
def test_bad_tables_one_line(tmp_path, capsys, text, where):
    f = tmp_path / "t.csv"
    f.write_text(text)
    assert main(["verify-table", str(f), "--n", "10"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith(f"error: {f}") and where in err
    with pytest.raises(SurveyInputError):
        read_table_csv(f)


def test_bad_n(tmp_path, capsys):
    assert main(["verify-table", str(published_dir() / "table1.csv"), "--n", "0"]) == 2
    assert main(["verify-table", str(published_dir() / "table1.csv"), "--n-range", "9", "3"]) == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 2 and all(e.startswith("error: ") for e in err)


def test_cli_range_lists_feasible_n(tmp_path, capsys):
    # thirds print as 33.3 / 66.7 at one decimal only when N is a multiple of 3 (below 30)
    f = tmp_path / "t.csv"
    f.write_text("item,A,B,C\nq1,33.3,33.3,33.3\nq2,66.7,33.3,0.0\n")
    assert main(["verify-table", str(f), "--n-range", "1", "29", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["feasible_n"] == list(range(3, 30, 3)) and out["n"] == 3


def test_n_smaller_than_counts_need(capsys):
    # Table 1 rows have up to four non-zero cells: N = 3 cannot produce them
    table, _ = load_table1()
    need = max(sum(1 for x in row if Decimal(x) > 0) for row in table.cells)
    assert main(["verify-table", str(published_dir() / "table1.csv"), "--n", str(need - 1)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "smaller than the counts need" in err
    assert main(["verify-table", str(published_dir() / "table1.csv"), "--n", str(need)]) == 0


def test_table_csv_as_european_spreadsheets_write_it(tmp_path, capsys):
    """Semicolons with decimal commas are read; rows keep their numbers past blank lines;
    a repeated label column is refused.

    Regressions: a semicolon table failed with "no 'item' column"; an error after a blank
    line named the wrong row; two 'Agree' columns were checked as if distinct.
    """
    semi = tmp_path / "semi.csv"
    semi.write_bytes(b"\xef\xbb\xbfItem;Agree;Neutral;Disagree\r\nQ1;\"50,0 %\";25,0;25,0\r\n")
    assert main(["verify-table", str(semi), "--n", "4", "--json"]) == 0
    row = json.loads(capsys.readouterr().out)["rows"][0]
    assert [c["counts"] for c in row["cells"]] == [[2], [1], [1]] and row["consistent"]
    gaps = tmp_path / "gaps.csv"
    gaps.write_text("item,Agree,Neutral,Disagree\n\nQ1,50,25,25\n\nQ2,50,x,25\n")
    assert main(["verify-table", str(gaps), "--n", "4"]) == 2
    assert "row 5, column 'Neutral'" in capsys.readouterr().err
    dup = tmp_path / "dup.csv"
    dup.write_text("item,Agree,agree,Disagree\nQ1,50,25,25\n")
    assert main(["verify-table", str(dup), "--n", "4"]) == 2
    assert "repeated" in capsys.readouterr().err


@pytest.mark.parametrize("rule", ROUNDING_RULES)
def test_n_search_matches_per_n_check_and_scales(rule):
    """The vectorised N search agrees with checking each N exactly (subset sums over the
    candidate counts), and a range up to MAX_N answers at once.

    Regression: the search checked each N in turn (about 2.5 ms per N at Table 1's size,
    growing with N), so ``--n-range 1 1000000`` ran for hours.
    """
    table, _ = load_table1()
    rng = verify_table(table, n_range=(4, 120), rule=rule)   # every row has 4 non-zero cells
    exact = [n for n in range(4, 121)
             if all(r.consistent for r in verify_table(table, n=n, rule=rule).rows)]
    assert rng.feasible_n == exact
    big = verify_table(table, n_range=(4, 1_000_000), rule=rule)
    assert [n for n in big.feasible_n if n <= 120] == exact and big.feasible_n[-1] > 990_000

    def consistent(n):
        return all(r.consistent for r in verify_table(table, n=n, rule=rule).rows)
    mid = max(n for n in big.feasible_n if n <= 3000)    # spot check past the exact range
    assert consistent(mid) and (mid - 1 in big.feasible_n) == consistent(mid - 1)


def _brute_row(printed: list[str], n: int):
    """Independent route for one row: every tuple of counts adding up to n, each cell
    judged by Decimal half-up rounding. Returns (solutions, nearest-cost function)."""
    cand = [_brute_attainable(p, n) for p in printed]
    sols = [ks for ks in itertools.product(*[range(n + 1)] * len(printed))
            if sum(ks) == n and all(k in c for k, c in zip(ks, cand))]
    return sols, cand


# 60 rows (~3 ms each; the brute-force oracle enumerates at most 13**4 count tuples): cheap, so many.
@settings(max_examples=60)
@given(st.lists(st.integers(0, 1000), min_size=2, max_size=4), st.integers(1, 12))
def test_row_check_matches_enumeration(tenths, n):
    """Consistency, uniqueness and the reconstruction agree with enumerating every choice of
    counts (small N, any printed values, including rows that do not add up to 100)."""
    printed = [f"{Decimal(t) / 10:.1f}" for t in tenths]
    table = PublishedTable(("q",), tuple(f"L{j}" for j in range(len(printed))),
                           (tuple(printed),))
    nonzero = sum(1 for p in printed if Decimal(p) > 0)
    if n < nonzero:
        with pytest.raises(SurveyInputError, match="smaller than the counts need"):
            verify_table(table, n=n)
        return
    row = verify_table(table, n=n).rows[0]
    sols, cand = _brute_row(printed, n)
    assert [c.counts for c in row.cells] == cand
    assert row.consistent == bool(sols) and row.unique == (len(sols) == 1)
    # reconstruction: counts adding up to n, each attainable (or nearest when not),
    # with the least total distance to the printed values; checked by enumeration
    loose = [c.counts or c.nearest_counts for c in row.cells]
    options = [ks for ks in itertools.product(*loose) if sum(ks) == n]
    if not options:
        assert row.reconstructed is None
        return

    def cost(ks):
        return sum(abs(Fraction(100 * k, n) - Fraction(p)) for k, p in zip(ks, printed))
    assert tuple(row.reconstructed) in options
    assert cost(row.reconstructed) == min(cost(ks) for ks in options)


def test_documented_maximum_n_answers():
    """Regression: ``--n 1000000`` (the documented maximum) ran for about 5 minutes.

    At N = 10**6 a one-decimal percentage p is exactly p * 10**4 respondents, and every
    Table 1 row adds up to 100.0, so the reconstruction must be exactly that."""
    table, _ = load_table1()
    check = verify_table(table, n=1_000_000)
    assert check.all_attainable
    for i, row in enumerate(check.rows):
        assert row.reconstructed == [int(Decimal(x) * 10_000) for x in table.cells[i]]
        assert not row.unique          # 100 counts print as each cell: many choices


def test_utf16_table_and_size_caps(tmp_path, capsys):
    """A UTF-16 table (as Excel saves "Unicode text") is read like the UTF-8 one; a table
    past MAX_TABLE_CELLS is refused with one line."""
    src = (published_dir() / "table1.csv").read_text(encoding="utf-8")
    f16 = tmp_path / "t16.csv"
    f16.write_bytes(src.replace("\n", "\r\n").encode("utf-16"))
    assert main(["verify-table", str(f16), "--n", "22", "--json"]) == 0
    out16 = json.loads(capsys.readouterr().out)
    assert main(["verify-table", str(published_dir() / "table1.csv"), "--n", "22", "--json"]) == 0
    assert out16 == json.loads(capsys.readouterr().out)
    big = tmp_path / "big.csv"
    big.write_text("item,A,B\n" + "".join(f"q{i},50,50\n" for i in range(MAX_TABLE_CELLS)))
    assert main(["verify-table", str(big), "--n", "2"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"at most {MAX_TABLE_CELLS} cells" in err


# --------------------------------------------------------------------------- row verdicts
def test_table1_verdict_names_the_unattainable_cell(capsys):
    """The paper's rows #2-#4 add up to 100.0 as printed: their verdict is the cell no count
    gives, with the nearest attainable value, and no sum verdict.

    Regression: `verify-table table1.csv --n 22` printed "SUM NOT OK (printed sum 100.0)".
    Hand check of row #2 (59.2, 31.8, 0.0, 4.5, 4.5 at one decimal, half away from zero):
    a cell printed p stands for an exact share in [p - 0.05, p + 0.05), 0.0 for [0, 0.05),
    so the exact shares total 59.15 + 31.75 + 0 + 4.45 + 4.45 = 99.80 to
    59.25 + 31.85 + 0.05 + 4.55 + 4.55 = 100.25, and 100 lies inside.
    """
    check = table1_check()
    findings = {r.item: r.findings for r in check.rows}
    assert findings == {"#1": [], "#2": ["cell_not_attainable"], "#3": ["cell_not_attainable"],
                        "#4": ["cell_not_attainable"], "#5": []}
    row2 = check.rows[1]
    assert row2.exact_total == (99.8, 100.25)
    assert main(["verify-table", str(published_dir() / "table1.csv"), "--n", "22"]) == 0
    lines = capsys.readouterr().out.splitlines()
    line2 = next(x for x in lines if x.strip().startswith("#2:"))
    assert line2.strip().startswith(
        "#2: CELL NOT ATTAINABLE: Definitely Agree = 59.2 (nearest attainable 59.1 = 13/22)")
    assert "within rounding of 100 (exact totals [99.80, 100.25))" in line2
    assert not [x for x in lines if "SUM" in x or "COUNTS DO NOT" in x]


@pytest.mark.parametrize("cells, n, findings, words", [
    # 9/22 = 40.909 -> 40.9, 13/22 = 59.091 -> 59.1, 1/22 = 4.545 -> 4.5: every cell
    # attainable; exact shares total [40.85 + 59.05 + 4.45, 40.95 + 59.15 + 4.55) =
    # [104.35, 104.65), never 100
    (("40.9", "59.1", "4.5"), 22, ["sum_off"],
     "SUM OFF: printed sum 104.5, but the printed cells stand for exact shares totalling "
     "[104.35, 104.65), which excludes 100"),
    # the same with 59.2, which no count out of 22 gives: both findings
    (("40.9", "59.2", "4.5"), 22, ["cell_not_attainable", "sum_off"],
     "CELL NOT ATTAINABLE: B = 59.2 (nearest attainable 59.1 = 13/22); SUM OFF: "
     "printed sum 104.6"),
    # 33.4 is only 334/1000 and 33.3 only 333/1000: 334 + 334 + 333 = 1001, while the
    # printed sum 100.1 is within rounding (exact totals [99.95, 100.25))
    (("33.4", "33.4", "33.3"), 1000, ["counts_do_not_add_up"],
     "COUNTS DO NOT ADD UP TO N: every cell attainable and printed sum 100.1 within "
     "rounding of 100, but the counts they allow total 1001, never N = 1000"),
    # whole percentages, half away from zero: 50 stands for [49.5, 50.5), 51 for
    # [50.5, 51.5); 99/200 = 49.5% -> 50 and 101/200 = 50.5% -> 51 add up: a printed
    # sum of 101 is within rounding, at its closed end
    (("50", "51"), 200, [], "ok"),
    # 49 stands for [48.5, 49.5), 50 for [49.5, 50.5): totals below 100 (the open end)
    (("49", "50"), 200, ["sum_off"],
     "SUM OFF: printed sum 99, but the printed cells stand for exact shares totalling "
     "[98.0, 100.0), which excludes 100"),
])
def test_row_verdict_names_what_is_wrong(tmp_path, capsys, cells, n, findings, words):
    """Each finding is named for what it is; the sum verdict only when no exact shares
    that print as the row's cells (the printed precision's rounding intervals) add up
    to 100. Expected counts and totals by hand, in the comments."""
    labels = tuple("ABC"[:len(cells)])
    row = verify_table(PublishedTable(("q",), labels, (cells,)), n=n).rows[0]
    assert row.findings == findings
    assert row.sum_ok == ("sum_off" not in findings)
    assert row.consistent == (findings == [])
    assert row.verdict.startswith(words)
    f = tmp_path / "t.csv"
    f.write_text("item," + ",".join(labels) + "\nq," + ",".join(cells) + "\n")
    assert main(["verify-table", str(f), "--n", str(n)]) == 0
    assert f"q: {words}" in capsys.readouterr().out
    assert main(["verify-table", str(f), "--n", str(n), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)["rows"][0]
    assert out["findings"] == findings and out["sum_ok"] == row.sum_ok


@settings(max_examples=60)
@given(st.integers(0, 10_000), st.integers(1, 10_000), st.integers(0, 3),
       st.sampled_from(ROUNDING_RULES))
def test_rounding_interval_is_what_prints_as_the_value(k, n, decimals, rule):
    """The interval behind a printed value (the sum verdict's tolerance) holds exactly the
    shares that round to it: the share itself, each included end, and nothing just past an
    end or at an excluded end (checked with round_fraction, point by point)."""
    from analysis.rounding import rounding_interval
    x = Fraction(100 * min(k, n), n)
    p = round_fraction(x, decimals, rule)
    lo, hi, lo_closed, hi_closed = rounding_interval(p, decimals, rule)
    assert lo <= x <= hi
    eps = Fraction(1, 10 ** (decimals + 6))          # far below one printed unit
    assert (round_fraction(lo, decimals, rule) == p) == lo_closed
    assert (round_fraction(hi, decimals, rule) == p) == hi_closed
    assert lo == 0 or round_fraction(lo - eps, decimals, rule) != p
    assert hi == 100 or round_fraction(hi + eps, decimals, rule) != p
    if lo < hi:                                      # (ceil prints only 0 itself as 0)
        assert round_fraction(lo + eps, decimals, rule) == p == round_fraction(hi - eps, decimals,
                                                                               rule)


def test_largest_remainder_tie_of_table1_item4_is_stated(tmp_path, capsys):
    """Table 1, item #4 printed 54.6, 31.8, 9.1, 4.5, 0.0: counts 12, 7, 2, 1, 0 of 22. By hand, in
    tenths of a percent: quotas 545.45, 318.18, 90.91, 45.45, 0; truncated they sum to 998, so two
    tenths go to the largest remainders: Neutral (0.91), then Definitely Agree and Partially
    Disagree tie (10/22 each) for the last one. The printed row gave it to Definitely Agree (the
    first label); the other way gives 54.5 and 4.6. The tie is stated wherever the largest-remainder
    row is shown: summarize's text, and (reports/paper.py) under the paper's survey table."""
    from analysis.rounding import largest_remainder, largest_remainder_tie

    labels = ["Definitely Agree", "Partially Agree", "Neutral", "Partially Disagree", "Definitely Disagree"]
    assert largest_remainder([12, 7, 2, 1, 0], 1) == [Fraction(x) for x in ("54.6", "31.8", "9.1", "4.5", "0")]
    tie = largest_remainder_tie(labels, [12, 7, 2, 1, 0], 1)
    assert tie == ("Definitely Agree and Partially Disagree tie for the last 0.1 (equal remainders): it goes "
                   "to the first in scale order, Definitely Agree (54.6 and 4.5; the other way 54.5 and 4.6)")
    assert largest_remainder_tie(labels, [14, 5, 2, 0, 1], 1) == ""  # item #3: remainders all differ
    assert largest_remainder_tie(["a", "b"], [1, 1], 1) == ""  # 50.0 each: nothing left to hand out

    from analysis.respondents import rebuild_table1_dataset
    from reports.paper import rounding_ties

    path = tmp_path / "t1.csv"
    rebuild_table1_dataset(path)
    assert main(["summarize", str(path), "--percent-method", "largest_remainder"]) == 0
    assert f"item4: {tie}" in capsys.readouterr().out
    assert main(["summarize", str(path)]) == 0
    assert "tie for the last" not in capsys.readouterr().out  # rounded cell by cell: no tie to state

    from types import SimpleNamespace

    from analysis.ingest import read_survey
    from analysis.likert import summarize

    facts = load_table1()[1]
    sentence = rounding_ties(SimpleNamespace(summary=summarize(read_survey(path)), facts=facts))
    assert sentence == f"In the published table, row #4 (12, 7, 2, 1, 0 of 22) is what largest-remainder rounding prints, with a tie: {tie}."


def test_range_with_no_feasible_n_explains_the_n_checked_and_each_rows_n(tmp_path, capsys):
    """Regression: with no N making the whole table attainable the text said "checked against
    N = 60" with no reason, and hid that Q3 (41.2/29.4/29.4) is 7/5/5 of 17. References by
    hand: 7/17 = 41.18%, 5/17 = 29.41%, so Q3 fits N = 17, 34, 51, 68, 85 (the rounded
    shares of 17k recur; no other N up to 100 gives 41.2 and 29.4 at once); Q1's thirds fit
    multiples of 3; Q2 prints 105.0 (off at any N). At 60, Q1 and =cmd (10/20/70 = 6/12/42)
    are attainable and Q2's cells (30/15/18): 9 of 12 cells, more than at any smaller N
    (which would need Q3, attainable only at multiples of 17, with Q1 at multiples of 3)."""
    f = tmp_path / "pub.csv"
    f.write_text("item,Agree,Neutral,Disagree\nQ1,33.3,33.3,33.3\nQ2,50.0,25.0,30.0\n"
                 "Q3,41.2,29.4,29.4\n=cmd,10,20,70\n")
    assert main(["verify-table", str(f), "--n-range", "1", "100"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[1].startswith("N in 1..100 making the whole table attainable: none")
    assert "  Q3: 17 (counts 7,5,5), 34, 51, 68, 85" in lines
    assert "  Q1: 3 (counts 1,1,1), " + ", ".join(str(n) for n in range(6, 100, 3)) in lines
    assert "  Q2: none (SUM OFF whatever N: see below)" in lines
    assert ("checked against N = 60, the smallest N in 1..100 at which the most cells are "
            "attainable (9 of 12):") in lines
    assert main(["verify-table", str(f), "--n-range", "1", "100", "--json"]) == 0
    rows = json.loads(capsys.readouterr().out)["rows"]
    assert [(r["item"], r["feasible_n_count"]) for r in rows][:3] == [("Q1", 33), ("Q2", 0),
                                                                    ("Q3", 5)]
    assert rows[2]["feasible_n"] == [17, 34, 51, 68, 85]
