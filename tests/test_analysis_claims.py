"""The paper's two claims (data/published/claims.toml) evaluated on the rebuilt Table 1 data.

Reference values
----------------
- Thresholds, categories and items: data/published/claims.toml (as printed, "over 90%", "upwards of 85%").
- Agree counts: from the Table 1 reconstruction (analysis.tables), 20/22 for item 2 and 19/22 for item 3.
- Wilson interval: closed form (Wilson 1927), written out here independently of statsmodels:
  centre (k + z^2/2)/(n + z^2), half-width z sqrt(k(n-k)/n + z^2/4)/(n + z^2).
- Clopper-Pearson: scipy.stats.beta quantiles.
"""
import json
import math
import re
import tomllib

import pytest
from scipy import stats

from analysis.__main__ import main
from analysis.claims import VERDICTS, evaluate_claims, load_claims
from analysis.errors import SurveyInputError
from analysis.ingest import read_survey
from analysis.likert import proportion, summarize
from analysis.respondents import rebuild_table1_dataset
from analysis.tables import published_dir, table1_check

CLAIMS = published_dir() / "claims.toml"
EXPECTED_AGREE = {2: (20, 22), 3: (19, 22)}   # module docstring


def _wilson(k, n, level=0.95):
    z = stats.norm.ppf(1 - (1 - level) / 2)
    centre = (k + z * z / 2) / (n + z * z)
    half = z * math.sqrt(k * (n - k) / n + z * z / 4) / (n + z * z)
    return centre - half, centre + half


@pytest.fixture(scope="module")
def rebuilt(tmp_path_factory):
    path = tmp_path_factory.mktemp("t1") / "table1_rebuilt.csv"
    rebuild_table1_dataset(path)
    return path


def test_paper_claims(rebuilt):
    raw = tomllib.loads(CLAIMS.read_text())["claims"]
    report = evaluate_claims(CLAIMS, summarize(read_survey(rebuilt)))
    check = table1_check()
    assert len(report.results) == len(raw) == 2
    for spec, res in zip(raw, report.results):
        row = check.rows[spec["item"] - 1]
        k_expected = sum(row.reconstructed[:2])
        assert (res.k, res.n) == EXPECTED_AGREE[spec["item"]] == (k_expected, check.n)
        assert res.claim.threshold == pytest.approx(spec["threshold"] / 100, abs=1e-12)
        lo, hi = _wilson(res.k, res.n)
        # statsmodels vs closed form: same formula, only float rounding differs
        assert res.ci == pytest.approx((lo, hi), abs=1e-12)
        assert res.share > res.claim.threshold > res.ci[0]
        assert res.verdict == VERDICTS["sample_only"] == "holds for this sample only"


def test_verdicts_and_clopper_pearson():
    # 95/100 > 0.8 with a lower bound well above: holds; 50/100 > 0.8: does not hold
    from analysis.claims import Claim, evaluate_claim
    import pandas as pd
    from analysis.likert import summarize_dataframe
    df = pd.DataFrame({"q": ["Definitely Agree"] * 95 + ["Neutral"] * 5,
                       "r": ["Partially Agree"] * 50 + ["Definitely Disagree"] * 50})
    s = summarize_dataframe(df)
    up = Claim("a", "q", ("Definitely Agree", "partially agree"), ">", 0.8)
    down = Claim("b", 2, ("Definitely Agree", "Partially Agree"), ">", 0.8)
    below = Claim("c", "r", ("definitely disagree",), "<", 0.55)
    assert evaluate_claim(up, s).verdict_code == "holds"
    assert evaluate_claim(down, s).verdict_code == "does_not_hold"
    assert evaluate_claim(below, s).verdict_code == "sample_only"
    p = proportion(19, 22, method="beta")
    lo = stats.beta.ppf(0.025, 19, 4)
    hi = stats.beta.ppf(0.975, 20, 3)
    assert p.ci == pytest.approx((lo, hi), abs=1e-9)  # two libraries, same quantiles


def test_cli_claims_json(rebuilt, capsys):
    assert main(["claims", str(rebuilt), str(CLAIMS), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert [c["verdict"] for c in out["claims"]] == ["holds for this sample only"] * 2


@pytest.mark.parametrize("body, key", [
    ('[[claims]]\nitem = 2\ncategories = ["Definitely Agree"]\ncomparison = "=>"\nthreshold = 90\n',
     "claims[0].comparison"),
    ('[[claims]]\nitem = 2\ncategories = []\nthreshold = 90\n', "claims[0].categories"),
    ('[[claims]]\nitem = 2\ncategories = ["Definitely Agree"]\nthreshold = 190\n',
     "claims[0].threshold"),
    ('claims = 3', "claims"),
    ('[[claims]\n', "invalid TOML"),
    ('claims = [1, 2]', "claims[0]"),
    ('[[claims]]\nitem = 0\ncategories = ["Neutral"]\nthreshold = 10\n', "claims[0].item"),
    ('[[claims]]\nitem = -1\ncategories = ["Neutral"]\nthreshold = 10\n', "claims[0].item"),
    ('[[claims]]\nitem = 2\ncategories = ["Neutral"]\nthreshold = 10\ncomparision = "<"\n',
     "claims[0].comparision"),
    ('claim = []\n', "unknown key 'claim'"),
    ('[[claims]]\nitem = 2\ncategories = ["Neutral"]\nthreshold = nan\n', "claims[0].threshold"),
    ("claims = " + "[" * 50_000 + "]" * 50_000 + "\n", "nested too deeply"),
])
def test_bad_claims_files(tmp_path, rebuilt, capsys, body, key):
    f = tmp_path / "c.toml"
    f.write_text(body)
    assert main(["claims", str(rebuilt), str(f)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and str(f) in err and key in err
    with pytest.raises(SurveyInputError, match=re.escape(key)):
        load_claims(f)


def test_typo_key_lists_allowed_keys(tmp_path, rebuilt, capsys):
    """Regression: ``comparision = "<"`` was ignored and the default ``>`` used."""
    f = tmp_path / "c.toml"
    f.write_text('[[claims]]\nitem = 2\ncategories = ["Neutral"]\nthreshold = 10\n'
                 'comparision = "<"\n')
    assert main(["claims", str(rebuilt), str(f)]) == 2
    err = capsys.readouterr().err
    assert "unknown key" in err and "'comparison'" in err and "'threshold'" in err


def test_item_positions_are_one_based(rebuilt):
    """Regression: item = 0 scored the last item and -1 the one before (list indexing)."""
    s = summarize(read_survey(rebuilt))
    assert s.item(1).item == "item1" and s.item(len(s.items)).item == s.items[-1].item
    for bad in (0, -1, len(s.items) + 1):
        with pytest.raises(IndexError, match="out of range"):
            s.item(bad)


def test_claim_on_missing_item(tmp_path, rebuilt, capsys):
    f = tmp_path / "c.toml"
    f.write_text('[[claims]]\nitem = "item9"\ncategories = ["Neutral"]\nthreshold = 10\n')
    assert main(["claims", str(rebuilt), str(f)]) == 2
    assert "item9" in capsys.readouterr().err


def test_claims_file_named_and_bom_accepted(tmp_path, capsys):
    """A bad category names the claims file; a TOML file saved with a BOM (Notepad) is read.

    Regression: the error said ``<claims>`` instead of the file; a BOM was "invalid TOML".
    """
    f = tmp_path / "s.csv"
    f.write_text("q1\nNeutral\nDefinitely Agree\n")
    good = tmp_path / "bom.toml"
    good.write_bytes(b'\xef\xbb\xbf[[claims]]\nitem = 1\ncategories = ["Neutral"]\n'
                     b'comparison = ">"\nthreshold = 10\n')
    assert main(["claims", str(f), str(good)]) == 0
    assert "1/2 = 50.0%" in capsys.readouterr().out
    bad = tmp_path / "bad.toml"
    bad.write_text('[[claims]]\nitem = 1\ncategories = ["Agree"]\nthreshold = 10\n')
    assert main(["claims", str(f), str(bad)]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"error: {bad}: ") and "'Agree'" in err and err.count("\n") == 1


def test_category_listed_twice_is_refused(tmp_path, rebuilt, capsys):
    """Regression: ["Neutral", "neutral"] counted the same answers twice (share doubled)."""
    f = tmp_path / "c.toml"
    f.write_text('[[claims]]\nitem = 1\ncategories = ["Neutral", " neutral"]\nthreshold = 5\n')
    assert main(["claims", str(rebuilt), str(f)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and str(f) in err and "listed twice" in err


def test_claim_on_an_item_nobody_answered_cannot_be_evaluated(tmp_path, capsys):
    """Regression: 0/0 valid answers gave "does not hold".

    By hand: Q2 is blank in all three rows, so n = 0 and there is no share. Q1 has 2
    Agree of 3; the 95 % Wilson lower bound is (2 + 1.92 - 1.96 sqrt(2/3 + 0.96)) /
    (3 + 3.84) = 0.21 > 0.10, so its claim "> 10 %" holds: one claim of each kind.
    """
    f = tmp_path / "nb.csv"
    f.write_text("Q1,Q2\nAgree,\nDisagree,\nAgree,\n")
    toml = tmp_path / "nb.toml"
    toml.write_text('[[claims]]\nid="q2"\nitem="Q2"\ncategories=["Agree"]\ncomparison="<"\n'
                    'threshold=90\n\n[[claims]]\nid="q1"\nitem="Q1"\ncategories=["Agree"]\n'
                    'comparison=">"\nthreshold=10\n')
    assert main(["claims", str(f), str(toml)]) == 0
    out = capsys.readouterr().out
    assert "q2: Q2 share 0/0 = n/a < 90%: cannot be evaluated: no valid answers" in out
    assert "does not hold\n" not in out.replace("0 does not hold", "")
    assert main(["claims", str(f), str(toml), "--json"]) == 0
    rep = json.loads(capsys.readouterr().out)
    q2 = rep["claims"][0]
    assert (q2["verdict_code"], q2["verdict"], q2["n"]) == (
        "no_answers", "cannot be evaluated: no valid answers", 0)
    assert rep["verdict_counts"] == {"holds": 1, "sample_only": 0, "does_not_hold": 0,
                                     "no_answers": 1}
    html = tmp_path / "r.html"
    assert main(["report", str(f), "--claims", str(toml), "-o", str(html)]) == 0
    text = html.read_text()
    assert 'class="no_answers">cannot be evaluated: no valid answers' in text
    assert "0 do not hold, 1 cannot be evaluated" in text and "does not hold" not in text


def test_claims_text_rounds_interval_bounds_by_the_one_rule():
    """New-user report: `claims` printed its interval bounds with Python's ``:.1%`` (half to even on the
    float) while shares and every other printed percentage round half away from zero
    (analysis.rounding). Bounds of 0.0625 and 0.8125 are exact in binary and lie half-way at one
    decimal: the rule prints 6.3% and 81.3% (``:.1%`` gave 6.2% and 81.2%)."""
    from analysis.claims import Claim, ClaimResult, ClaimsReport
    from analysis.likert import Proportion

    share = Proportion(13, 16, 13 / 16, (0.0625, 0.8125), "wilson", 0.95)  # made-up bounds: ties by design
    result = ClaimResult(Claim("c", "q", ("Definitely Agree",), ">", 0.5), "q", share, "sample_only",
                         VERDICTS["sample_only"], "")
    text = ClaimsReport([result], "s.csv", "c.toml", 16).format_text()
    assert "share 13/16 = 81.3% [6.3%, 81.3%] > 50%" in text


def test_explanation_names_the_verdict_in_percent():
    """ClaimResult.explanation, the one text report.html, the paper and `analysis report` show: every
    verdict opens with its name, shares and bounds in percent by the one rule. By hand: 95/100 = 95.0%
    over 80% (Wilson lower bound 88.8% > 80%: holds); 50/100 = 50.0% not over 80%."""
    from analysis.claims import Claim, evaluate_claim
    import pandas as pd
    from analysis.likert import summarize_dataframe
    s = summarize_dataframe(pd.DataFrame({"q": ["Definitely Agree"] * 95 + ["Neutral"] * 5,
                                          "r": ["Partially Agree"] * 50 + ["Definitely Disagree"] * 50}))
    up = evaluate_claim(Claim("a", "q", ("Definitely Agree",), ">", 0.8), s).explanation()
    lo, hi = _wilson(95, 100)
    assert up.startswith(f"Holds: 95/100 = 95.0% of those who answered, over 80%, and the whole 95% Wilson "
                         f"interval ({100 * lo:.1f}% to {100 * hi:.1f}%) is over 80%")
    down = evaluate_claim(Claim("b", "r", ("Partially Agree",), ">", 0.8), s).explanation()
    assert down.startswith("Does not hold: 50/100 = 50.0% of those who answered is not over 80%")
