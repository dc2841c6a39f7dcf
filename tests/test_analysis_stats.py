"""Cronbach's alpha (Feldt interval) and group comparisons (Mann-Whitney / Kruskal, Cliff's delta).

Reference routes
----------------
- alpha = (MS_respondents - MS_residual) / MS_respondents from a two-way ANOVA without
  replication (Hoyt 1941), an independent formula for the same coefficient.
- Feldt (1965) interval: its coverage under the parallel-items normal model is exact, so
  a Monte Carlo run must cover the true alpha about 95% of the time.
- Cliff's delta: brute force over all pairs, and 2U/(n1 n2) - 1 with U from scipy.
"""
import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import stats

from analysis.errors import SurveyInputError
from analysis.groups import cliffs_delta, compare_groups
from analysis.ingest import survey_from_frame
from analysis.reliability import cronbach_alpha, cronbach_alpha_for


def _hoyt(x):
    n, k = x.shape
    grand = x.mean()
    ss_r = k * ((x.mean(axis=1) - grand) ** 2).sum()
    ss_c = n * ((x.mean(axis=0) - grand) ** 2).sum()
    ss_e = ((x - grand) ** 2).sum() - ss_r - ss_c
    ms_r, ms_e = ss_r / (n - 1), ss_e / ((n - 1) * (k - 1))
    return (ms_r - ms_e) / ms_r


# 30 random n x k matrices (~2 ms each): sizes from 3 x 2 to 30 x 6 every run.
@settings(max_examples=30)
@given(st.integers(3, 30), st.integers(2, 6), st.integers(0, 10_000))
def test_alpha_matches_anova_route(n, k, seed):
    rng = np.random.default_rng(seed)
    x = rng.integers(1, 6, size=(n, k)).astype(float) + rng.integers(0, 3, size=(n, 1))
    res = cronbach_alpha(x)
    if res.alpha is None:
        assert x.sum(axis=1).var() == 0
        return
    assert res.alpha == pytest.approx(_hoyt(x), abs=1e-9)      # float round-off only
    assert res.ci[0] <= res.alpha <= res.ci[1]


def test_feldt_interval_coverage():
    rng = np.random.default_rng(1965)
    n, k, rho, sims = 30, 4, 0.4, 600
    true_alpha = k * rho / (1 + (k - 1) * rho)
    hits = 0
    for _ in range(sims):
        t = rng.normal(0, np.sqrt(rho), size=(n, 1))
        x = t + rng.normal(0, np.sqrt(1 - rho), size=(n, k))
        lo, hi = cronbach_alpha(x).ci
        hits += lo <= true_alpha <= hi
    # binomial sd of the coverage at 600 runs is 0.0089; allow 3.5 sd
    assert abs(hits / sims - 0.95) < 0.032


def test_alpha_listwise_and_errors():
    df = pd.DataFrame({"a": ["Definitely Agree", "Neutral", "", "Partially Agree"],
                       "b": ["Partially Agree", "Neutral", "Neutral", "N/A"],
                       "c": ["Definitely Agree", "Partially Disagree", "Neutral", "Neutral"]})
    data = survey_from_frame(df)
    res = cronbach_alpha_for(data)
    assert (res.n, res.left_out) == (2, 2)
    with pytest.raises(SurveyInputError, match="zz"):
        cronbach_alpha_for(data, ["zz"])
    with pytest.raises(ValueError, match="two item columns"):
        cronbach_alpha(np.ones((5, 1)))


# 30 pairs of samples (~5 ms each, scipy's Mann-Whitney U included): ties are certain with 5 levels.
@settings(max_examples=30)
@given(st.lists(st.integers(1, 5), min_size=1, max_size=25),
       st.lists(st.integers(1, 5), min_size=1, max_size=25))
def test_cliffs_delta_three_routes(x, y):
    brute = np.sign(np.subtract.outer(np.array(x), np.array(y))).mean()
    u = stats.mannwhitneyu(x, y, alternative="two-sided").statistic
    d = cliffs_delta(x, y)
    assert d == pytest.approx(brute, abs=1e-12)
    assert d == pytest.approx(2 * u / (len(x) * len(y)) - 1, abs=1e-12)


def test_groups_suppression_and_tests():
    labels = ["Definitely Agree", "Partially Agree", "Neutral", "Partially Disagree"]
    # C (3) and D (2) are under 5; pooled they are 5, so A and B are shown
    rows = ([("A", labels[i % 2]) for i in range(6)] + [("B", labels[2 + i % 2]) for i in range(6)]
            + [("C", labels[0])] * 3 + [("D", labels[3])] * 2)
    df = pd.DataFrame(rows, columns=["section", "q1"])
    data = survey_from_frame(df, group="section")
    comp = compare_groups(data, "Section", min_size=5)
    sup = {g.name: g.suppressed for g in comp.groups}
    assert sup == {"A": False, "B": False, "C": True, "D": True}
    assert "3 respondents < 5" in [g for g in comp.groups if g.name == "C"][0].reason
    it = comp.items[0]
    # A (first) all above B (second): second against first, -1
    assert it.test == "mann-whitney" and it.effect == pytest.approx(-1.0)
    assert "C" not in it.per_group
    comp3 = compare_groups(data, "section", min_size=2)
    assert comp3.items[0].test == "kruskal-wallis"
    h = stats.kruskal([5, 4] * 3, [3, 2] * 3, [5] * 3, [2] * 2).statistic
    assert comp3.items[0].statistic == pytest.approx(h, rel=1e-12)
    with pytest.raises(SurveyInputError, match="term"):
        compare_groups(data, "term")


def test_group_spellings_are_one_group():
    """Regression: "Mon", "mon " and "MON" were three groups (each then suppressed as too
    small) instead of one group of 6 compared against "Wed"."""
    sect = ["Mon", "mon ", "MON", "Mon", "Mon", " mon"] + ["Wed"] * 5
    ans = ["Definitely Agree"] * 6 + ["Neutral"] * 5
    data = survey_from_frame(pd.DataFrame({"section": sect, "q1": ans}), group="section")
    comp = compare_groups(data, "section")
    assert [(g.name, g.respondents, g.suppressed) for g in comp.groups] == [
        ("Mon", 6, False), ("Wed", 5, False)]
    assert comp.items[0].test == "mann-whitney"


def test_alpha_leaves_out_an_item_nobody_answered():
    """Regression: one all-blank item made alpha undefined for everyone.

    By hand, Q1 = 1, 2, 4, 5 and Q2 = 2, 2, 5, 4 (agree5 codes): variances 10/3 and 9/4,
    totals 3, 4, 9, 9 with variance 41/4, so alpha = 2 (1 - (67/12) / (41/4)) = 112/123.
    """
    df = pd.DataFrame({"Q1": ["Strongly disagree", "Disagree", "Agree", "Strongly agree"],
                       "Q2": ["Disagree", "Disagree", "Strongly agree", "Agree"],
                       "Q3": [""] * 4})
    data = survey_from_frame(df, scale="agree5")
    assert data.items == ["Q1", "Q2", "Q3"]
    res = cronbach_alpha_for(data)
    assert res.items == ["Q1", "Q2"] and (res.n, res.left_out) == (4, 0)
    assert res.alpha == pytest.approx(112 / 123, abs=1e-12)     # float sums of small integers
    assert "nobody answered it (n = 0): Q3" in res.note
    one = cronbach_alpha_for(survey_from_frame(df[["Q1", "Q3"]], scale="agree5"))
    assert one.alpha is None and one.note.startswith("fewer than two items have answers")
