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
        assert row.sum_ok == all(c.attainable for c in row.cells)
    assert bad == EXPECTED_UNATTAINABLE


def test_unattainable_cells_explained_by_row_forcing():
    """Each printed row whose cells rounded from its counts add to 99.9 shows its largest
    cell 0.1 higher: the table was forced to show 100 per row."""
    check = table1_check()
    for row in check.rows:
        forced = "adding the row's deficit" in row.reason
        assert forced == (not row.sum_ok)
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
    assert row.sum_ok
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
        assert set(row) == {"item", "cells", "sum_ok"}
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
    assert [c["counts"] for c in row["cells"]] == [[2], [1], [1]] and row["sum_ok"]
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
             if all(r.sum_ok and all(c.attainable for c in r.cells)
                    for r in verify_table(table, n=n, rule=rule).rows)]
    assert rng.feasible_n == exact
    big = verify_table(table, n_range=(4, 1_000_000), rule=rule)
    assert [n for n in big.feasible_n if n <= 120] == exact and big.feasible_n[-1] > 990_000

    def consistent(n):
        return all(r.sum_ok and all(c.attainable for c in r.cells)
                   for r in verify_table(table, n=n, rule=rule).rows)
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
    """sum_ok, uniqueness and the reconstruction agree with enumerating every choice of
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
    assert row.sum_ok == bool(sols) and row.unique == (len(sols) == 1)
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
