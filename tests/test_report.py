"""The verification report: end-to-end build, the findings, and that the checks can fail.

Reference facts come from the paper (data/published/) and from the hand
derivations below (the Example 2 walk-through in data/scenes/README.md gives the
same sign argument):

* Eqs. 43 and 44 print the applied force F_a with the wrong sign. Eliminating
  F_f = (...) - F_a (Eq. 39) from Eq. 42 gives -F_a r_d inside the bracket of
  Eq. 43, so the correct equation of motion ends in "= +F_a r_d"; the printed
  forms therefore differ from the derivation by exactly 2 F_a r_d.
* Eq. 30 prints alpha's unit as rad/s: an angular acceleration is rad/s^2.
* Table 1's Definitely Agree cells of items 2-4 cannot come from any count out
  of N = 22 at one decimal (13/22, 14/22 and 12/22 print one tenth lower).
* Everything else printed in the two examples holds.
"""
from __future__ import annotations

import copy
import csv
import dataclasses
import html
import json
import re
import shutil
import subprocess
import sys
from pathlib import Path

import jinja2
import numpy as np
import pytest
import sympy as sp

from html_ids import page_ids
from reports.checks import KINDS, VERDICTS, example1_value_checks, half_unit
from reports.equations import check_equation, is_zero
from reports.make_report import (ROOT, TEMPLATES, TemplateCache, build_cached, html_environment, latex_environment,
                                 latex_escape, main, write_template_cache)
from reports.paper import example_steps, survey_table
from reports.published import ReportInputError, load_equations
from solver.derivation import derive, solve_instant
from solver.scenefile import load_scene

PUBLISHED = ROOT / "data" / "published"
# The printed equations that are wrong, and by how much (hand derivation, see module docstring).
EXPECTED_RESIDUAL = {"eq43": "2*F_a*r_d", "eq44": "2*F_a*r_d"}
# Printed numbers/units that are wrong: alpha's unit (Eq. 30) and three Table 1 cells.
EXPECTED_OTHER_DISAGREEMENTS = {
    "eq30-alpha-unit",
    "table1-item2-definitely-agree",
    "table1-item3-definitely-agree",
    "table1-item4-definitely-agree",
}
# Equations the issue requires at least (ids are eqNN or eqNN-<part>).
REQUIRED_EQUATIONS = ("20", "24", "25", "28", "39", "40", "42", "43", "44", "46")


@pytest.fixture(scope="module")
def built(tmp_path_factory) -> dict:
    """One build per session, into a temporary folder, through the code path of `make report`."""
    return build_cached(tmp_path_factory.getbasetemp() / "report_build", ROOT)


@pytest.fixture(scope="module")
def verification(built) -> list[dict]:
    return json.loads((Path(built["out"]) / "verification.json").read_text(encoding="utf-8"))["checks"]


@pytest.fixture(scope="module")
def equations():
    eqset = load_equations(PUBLISHED / "equations.toml")
    scenes = {k: load_scene(p) for k, p in eqset.scenes.items()}
    return eqset, scenes, {k: derive(s) for k, s in scenes.items()}


# --------------------------------------------------------------------------- outputs and schema
def test_each_page_has_unique_ids_and_every_reference_resolves(built):
    """Seven inline figures in paper.html, each of them in report.html: each figure's ids (matplotlib
    numbers them alike in every SVG: figure_1, axes_1, clip paths) are its own, and each ``url(#X)``
    or ``href="#X"`` reaches an id of the page (QA 19 #10 counted 120 repeated ids in each page)."""
    for name in ("report.html", "paper.html"):
        text = (Path(built["out"]) / name).read_text(encoding="utf-8")
        assert text.count("<svg") >= 6, name
        assert page_ids(text) == ([], []), name


def test_pages_show_every_minus_as_the_minus_sign(built):
    """QA 20 #7: report.html and paper.html write a minus as U+2212, as the worked solution's HTML does:
    in the tables' numbers (-6.937 lbf s^2), the checks' details ("printed lhs - rhs", "cos(beta -
    theta)"), and MathML; no hyphen-minus shows as a sign or a spaced operator outside drawings and code.
    paper.tex and verification.json keep "-"."""
    shown = re.compile(r"<mo>-</mo>|<mn>-|>[^<]*(?:(?<![\w.-])-(?=\.?\d)|\s-\s)[^<]*<")
    for name in ("report.html", "paper.html"):
        text = (Path(built["out"]) / name).read_text(encoding="utf-8")
        text = re.sub(r"<(svg|style|code|pre)\b.*?</\1>", "", text, flags=re.S)
        hit = shown.search(text)
        assert hit is None, (name, hit and hit.group(0)[:200])
        assert "\u2212" in text
    assert "\u2212" not in (Path(built["out"]) / "verification.json").read_text(encoding="utf-8")


def test_build_writes_every_output(built):
    out = Path(built["out"])
    for name in ("report.html", "paper.html", "paper.tex", "verification.json"):
        assert (out / name).stat().st_size > 1000, name
    assert {p.suffix for p in (out / "figures").iterdir()} == {".svg", ".pdf"}
    tex = (out / "paper.tex").read_text(encoding="utf-8")
    assert "\\VAR{" not in tex and "\\BLOCK{" not in tex and tex.rstrip().endswith("\\end{document}")
    # environments balanced (a LaTeX engine is optional, so check the structure here)
    begins = re.findall(r"\\begin\{(\w+\*?)\}", tex)
    ends = re.findall(r"\\end\{(\w+\*?)\}", tex)
    assert sorted(begins) == sorted(ends)
    assert tex.count("{") - tex.count("\\{") == tex.count("}") - tex.count("\\}")
    # LaTeX numbers nothing itself: the article's equation numbers are tags and the figures' captions
    # number themselves ("Figure 1, redrawn ..."), so "Eq. (10)" and "Figure 3" mean the article's
    assert "\\caption{" not in tex and not re.search(r"\\begin\{equation\}(?![^\n]*\n[^\n]*\\tag)", tex)
    assert re.findall(r"\\tag\{(\d+)\}", tex) == ["10", "11", "14", "14"]


def test_printed_column_shows_the_value_as_printed(built):
    """The "printed" column of the HTML shows each published number as data/published records it
    (trailing zeros kept: they set the printed precision and with it the tolerance), with the
    value's sign where the paper prints the sign apart (Eq. 29's minus between terms)."""
    page = (Path(built["out"]) / "report.html").read_text(encoding="utf-8")

    def printed_cell(row_id):
        row = re.search(rf'<tr id="row-{row_id}">(.*?)</tr>', page, flags=re.S).group(1)
        return re.sub(r"\s+", " ", re.findall(r"<td[^>]*>(.*?)</td>", row, flags=re.S)[2]).strip()

    assert printed_cell("eq29-r1-alpha") == "\u22120.05080"  # example1.toml: printed "0.05080", value -0.05080, a minus sign
    assert printed_cell("table1-item1-definitely-agree") == "50.0 %"  # table1.csv prints 50.0


def test_paper_says_which_survey_cells_differ_from_the_published_table(built):
    """The paper's survey table shows the rebuilt counts' percentages; the three published cells no
    count out of 22 gives (59.2, 63.7, 54.6, as table1.csv prints them) are named under it with the
    percentage shown, by hand 13/22 = 59.09, 14/22 = 63.64, 12/22 = 54.55 -> 59.1, 63.6, 54.5, in
    both renderings."""
    html_text = (Path(built["out"]) / "paper.html").read_text(encoding="utf-8")
    tex = (Path(built["out"]) / "paper.tex").read_text(encoding="utf-8")
    for item, printed, shown in (("#2", "59.2", "59.1"), ("#3", "63.7", "63.6"), ("#4", "54.6", "54.5")):
        assert f"item {item}, Definitely Agree printed {printed} %, shown {shown} %" in html_text
        assert f"item \\{item}, Definitely Agree printed {printed} \\%, shown {shown} \\%" in tex


def test_claim_verdicts_explained_once_and_alike_in_report_and_paper(built):
    """New-user report: report.html showed each claim twice (the check's detail with shares as 0.9091 and
    "wilson", then a caveat in percent), and the paper gave no explanation. Both now show the statement
    and ClaimResult.explanation(), the one text. By hand: item 2, 20/22 = 90.91% -> 90.9%; item 3,
    19/22 = 86.36% -> 86.4%; the Wilson bounds (closed form, tests/test_analysis_claims.py) 72.2 to 97.5
    and 66.7 to 95.3 reach below 90% and 85%."""
    import html as html_module
    import re

    out = Path(built["out"])
    texts = {name: html_module.unescape(re.sub(r"<[^>]+>", " ", (out / name).read_text(encoding="utf-8")))
             for name in ("report.html", "paper.html")}
    tex = (out / "paper.tex").read_text(encoding="utf-8")
    for share, bounds, threshold in (("20/22 = 90.9%", "72.2% to 97.5%", "90%"),
                                     ("19/22 = 86.4%", "66.7% to 95.3%", "85%")):
        sentence = (f"Holds for this sample only: {share} of those who answered, over {threshold}; but the 95% "
                    f"Wilson interval ({bounds}) reaches below {threshold},")
        assert texts["paper.html"].count(sentence) == 1
        assert texts["report.html"].count(sentence) == 2  # the caveat, and its row among all checks
        assert sentence.replace("%", "\\%") in tex
    for name, text in texts.items():
        assert "0.9091" not in text and "wilson interval" not in text, name  # one format: percent, "Wilson"


def test_verification_json_schema_and_required_rows(verification):
    ids = [row["id"] for row in verification]
    assert len(ids) == len(set(ids)), "duplicate ids"
    for row in verification:
        assert set(row) == {"id", "kind", "published", "published_text", "published_unit", "computed",
                            "computed_unit", "tolerance", "verdict", "detail"}, row
        assert row["kind"] in KINDS and row["verdict"] in VERDICTS, row
        assert isinstance(row["detail"], str) and row["detail"], row
    present = set(ids)
    for number in REQUIRED_EQUATIONS:
        assert any(re.fullmatch(rf"eq{number}(-.+)?", i) for i in present), f"no row for Eq. {number}"
    # every printed Eq. 29/30 number of Example 1, and its unit where one is printed
    import tomllib

    printed = tomllib.loads((PUBLISHED / "example1.toml").read_text(encoding="utf-8"))["value"]
    for entry in printed:
        assert entry["id"] in present, entry["id"]
    assert {"eq30-alpha-unit", "eq30-R_A-unit", "eq30-R_B-unit"} <= present
    # every Table 1 cell, the response facts, both claims
    with (PUBLISHED / "table1.csv").open(encoding="utf-8") as handle:
        table = list(csv.DictReader(handle))
    for number, row in enumerate(table, start=1):
        for label in row:
            if label != "item":
                slug = re.sub(r"[^a-z0-9]+", "-", label.lower()).strip("-")
                assert f"table1-item{number}-{slug}" in present
    assert {"response-rate", "claim-item2", "claim-item3"} <= present


def test_findings_match_the_known_errors_of_the_paper(verification):
    verdicts = {row["id"]: row for row in verification}
    disagreeing = {i for i, row in verdicts.items() if row["verdict"] == "disagrees"}
    assert disagreeing == set(EXPECTED_RESIDUAL) | EXPECTED_OTHER_DISAGREEMENTS
    assert not [i for i, row in verdicts.items() if row["verdict"] == "not-checkable"]
    for eq_id, residual in EXPECTED_RESIDUAL.items():
        computed = sp.sympify(verdicts[eq_id]["computed"].removeprefix("residual "))  # our own output, not input
        assert sp.simplify(computed - sp.sympify(residual)) == 0, verdicts[eq_id]
    # Eq. 30's numbers agree (alpha's magnitude too); only the printed unit is wrong.
    for key in ("eq30-alpha", "eq30-R_A", "eq30-R_B"):
        assert verdicts[key]["verdict"] == "agrees", verdicts[key]


def test_table_cell_findings_carry_the_row_verdict_of_verify_table(built):
    """The report explains a Table 1 finding with the verdict `verify-table` gives (one
    place decides it): the cell no count out of 22 gives, never a sum verdict, since the
    printed rows add up to 100.0 (hand check in tests/test_analysis_tables.py).

    Regression: the report derived its own "raised to make the row total 100%" story,
    while `verify-table` called the same rows "SUM NOT OK"."""
    from analysis.tables import table1_check

    verdicts = {row.item: row for row in table1_check().rows}
    context_rows = {r.id: r for r in built["context"]["rows"]}
    for cell_id in sorted(EXPECTED_OTHER_DISAGREEMENTS - {"eq30-alpha-unit"}):
        item = "#" + re.fullmatch(r"table1-item(\d)-.*", cell_id).group(1)
        explanation = context_rows[cell_id].explanation
        assert explanation.startswith(f"Row {item}: {verdicts[item].reason}"), explanation
        assert "CELL NOT ATTAINABLE: Definitely Agree" in explanation
        assert "SUM" not in explanation


def test_every_disagreement_is_explained_first_in_the_html(built, verification):
    html = (Path(built["out"]) / "report.html").read_text(encoding="utf-8")
    findings_at = html.index('id="findings"')
    all_rows_at = html.index('id="all"')
    for row in verification:
        if row["verdict"] == "disagrees":
            anchor = html.find(f'id="finding-{row["id"]}"')
            assert findings_at < anchor < all_rows_at, f"{row['id']} not listed among the findings"
    context_rows = {r.id: r for r in built["context"]["rows"]}
    for row in verification:
        if row["verdict"] == "disagrees":
            assert context_rows[row["id"]].explanation, f"{row['id']} has no explanation"
    # self-contained: equations as MathML, no script, nothing fetched from the network
    assert html.count("<math") >= 40 and "<script" not in html
    assert not re.search(r'(src|href)\s*=\s*"(https?:)?//', html)


# --------------------------------------------------------------------------- the comparison can fail
@pytest.mark.parametrize(
    ("eq_id", "side", "old", "new"),
    [
        ("eq28", "lhs", "1/3", "1/4"),                    # a changed coefficient
        ("eq24", "lhs", "sin(beta)*R_B -", "-sin(beta)*R_B -"),  # a changed sign
        ("eq39", "rhs", "(m_d + m_b)", "(m_d + 2*m_b)"),  # a changed mass term
        ("eq46", "rhs", "3/2*m_d", "1/2*m_d"),            # a wrong frequency
        ("eq20-a_B", "rhs", "sin(beta)", "tan(beta)"),    # a wrong kinematic relation
        ("eq36-F_f", "rhs", "F_f", "-F_f"),               # a force along the wrong direction
        ("eq41", "lhs", "r_CPx*F_fy - r_CPy*F_fx", "r_CPy*F_fx - r_CPx*F_fy"),  # a cross product reversed
        ("eq45-cos", "rhs", "1", "1 + theta"),            # a small-motion rule wrong to first order
    ],
)
def test_mutated_transcription_disagrees(equations, eq_id, side, old, new):
    eqset, scenes, derivs = equations
    tr = next(e for e in eqset.equations if e.id == eq_id)
    assert check_equation(tr, scenes[tr.scene], derivs[tr.scene]).verdict == "agrees"
    text = getattr(tr, side)
    assert old in text, f"mutation target {old!r} not in {eq_id}.{side}"
    mutated = dataclasses.replace(tr, **{side: text.replace(old, new, 1)})
    outcome = check_equation(mutated, scenes[tr.scene], derivs[tr.scene])
    assert outcome.verdict == "disagrees"
    assert outcome.residual != 0


def test_the_tree_walk_evaluates_as_sympy_does():
    """The one tree walk (solver.tree_value) behind the report's numeric zero test (mpmath) and the
    display's quick nonzero test (double precision), against sympy's own evalf at 40 digits: equal
    to 1e-25 relative in mpmath at 30 digits, and to 1e-13 in double precision (about 20 roundings
    of 1.1e-16 each, well inside)."""
    import mpmath

    from solver.tree_value import DOUBLE, mpmath_arithmetic, tree_value

    a, b, c = sp.symbols("a b c", real=True)
    expr = (sp.sin(a) ** 2 * sp.tan(b) - sp.sqrt(c) / (3 * sp.cos(a - b)) + sp.pi * a ** sp.Rational(3, 2)
            + sp.exp(-c) * sp.Abs(a - 2 * b) - sp.log(c) / 7)
    point = {a: sp.Rational(5, 7), b: sp.Rational(11, 13), c: sp.Rational(17, 19)}
    with mpmath.workdps(30):
        walked = tree_value(expr, {k: mpmath.mpf(v.p) / v.q for k, v in point.items()}, mpmath_arithmetic())
    double = tree_value(expr, {k: float(v) for k, v in point.items()}, DOUBLE)
    with mpmath.workdps(40):
        exact = mpmath.mpf(str(expr.xreplace(point).evalf(40)))
        assert abs((walked - exact) / exact) < mpmath.mpf("1e-25")
        assert abs((double - exact) / exact) < 1e-13 and double.imag == 0
    assert is_zero(sp.sin(a) ** 2 + sp.cos(a) ** 2 - 1, [sp.Integer(1)])[0]
    assert not is_zero(sp.sin(a) ** 2 + sp.cos(a) ** 2 - 1 + sp.Rational(1, 10**15), [sp.Integer(1)])[0]


def test_the_compiled_tree_walk_gives_the_walks_numbers():
    """solver.tree_value.tree_program (the zero test's trees walked once, run at each point) gives
    tree_value's numbers to the last bit at every point, with shared subtrees and a precision change
    between calls (its numbers made again), the trees' free symbols, and NotEvaluable for a node the
    walk does not know (the zero test then falls back to lambdify). tree_value itself is held
    against sympy's evalf above."""
    import mpmath

    from solver.tree_value import NotEvaluable, mpmath_arithmetic, tree_program, tree_value

    a, b, c = sp.symbols("a b c", real=True)
    shared = sp.sin(a - b) ** 2 / (c + sp.Rational(1, 3))
    exprs = [shared * sp.cos(a) - sp.sqrt(c) * shared + sp.pi * a ** sp.Rational(3, 2),
             sp.exp(-c) * sp.Abs(a - 2 * b) + shared ** 3 - sp.log(c) / 7, sp.Integer(5) / 3]
    program, symbols = tree_program(exprs, mpmath_arithmetic())
    assert symbols == {a, b, c}
    for digits in (30, 45, 30):
        with mpmath.workdps(digits):
            for n in (1, 2, 3):
                point = {a: mpmath.mpf(5 * n) / 7, b: mpmath.mpf(11) / (13 * n), c: mpmath.mpf(17) / 19 + n}
                got = program(point)
                want = [tree_value(e, point, mpmath_arithmetic(), {}) for e in exprs]
                assert [mpmath.mpf(x)._mpf_ for x in got] == [mpmath.mpf(x)._mpf_ for x in want]
    with pytest.raises(NotEvaluable):
        tree_program([sp.besselj(a, b) + a], mpmath_arithmetic())


def test_correcting_the_sign_of_F_a_makes_eq44_agree(equations):
    eqset, scenes, derivs = equations
    tr = next(e for e in eqset.equations if e.id == "eq44")
    fixed = dataclasses.replace(tr, rhs=tr.rhs.replace("-F_a*r_d", "F_a*r_d"))
    outcome = check_equation(fixed, scenes[tr.scene], derivs[tr.scene])
    assert outcome.verdict == "agrees" and outcome.residual == 0
    wrong = check_equation(tr, scenes[tr.scene], derivs[tr.scene])
    assert "wrong sign" in wrong.diagnosis


def test_a_changed_published_value_disagrees(equations, tmp_path):
    eqset, scenes, derivs = equations
    text = (PUBLISHED / "example1.toml").read_text(encoding="utf-8")
    entry = re.search(r'id = "eq30-R_B"\nprinted = "([0-9.]+)"\nvalue = ([0-9.]+)', text)
    assert entry, "eq30-R_B not found in example1.toml"
    printed = float(entry.group(1))
    # Off by ten half-units: well outside any rounding tolerance.
    moved = f"{printed + 10 * 2 * half_unit(entry.group(1)):.2f}"
    changed = text.replace(entry.group(0), f'id = "eq30-R_B"\nprinted = "{moved}"\nvalue = {moved}')
    path = tmp_path / "example1.toml"
    path.write_text(changed, encoding="utf-8")
    scene = scenes["sliding_bar"]
    rows = {r.id: r for r in example1_value_checks(path, eqset, scene, derivs["sliding_bar"], solve_instant(scene))}
    assert rows["eq30-R_B"].verdict == "disagrees"
    assert rows["eq30-R_A"].verdict == "agrees"


def test_example_steps_builds_the_steps_asked_as_the_full_set_has_them(equations):
    # The build asks each example for the steps its paper shows (EX1_STEPS, EX2_STEPS): those must
    # be the very renderings of the full set, and a name that is no step is refused.
    eqset, scenes, derivs = equations
    key = list(eqset.scenes)[1]  # Example 2
    full = example_steps(scenes[key], derivs[key], at_rest=False)
    some = example_steps(scenes[key], derivs[key], at_rest=False, parts=("omega", "eom"))
    assert set(some) == {"omega", "eom"}
    assert some["omega"] == full["omega"] and some["eom"] == full["eom"]
    with pytest.raises(ValueError, match="`parts` must name steps of .*, got nonsense"):
        example_steps(scenes[key], derivs[key], at_rest=False, parts=("eom", "nonsense"))


def test_provenance_versions_are_the_installed_distributions():
    # Read from the metadata's header block alone; the reference is importlib.metadata's full parse.
    from importlib import metadata

    from reports.provenance import PACKAGES, _version

    for name in PACKAGES:
        try:
            expected = metadata.version(name)
        except metadata.PackageNotFoundError:
            continue
        assert _version(name) == expected, name
    with pytest.raises(metadata.PackageNotFoundError):
        _version("no-such-distribution-alt-euler")


def test_half_unit_follows_printed_digits():
    assert half_unit("12.34") == pytest.approx(0.005)
    assert half_unit("0.04560") == pytest.approx(0.000005)
    assert half_unit("50") == pytest.approx(0.5)
    with pytest.raises(ValueError, match="plain decimal"):
        half_unit("1e3")


# --------------------------------------------------------------------------- templates
def test_strict_undefined_fails_on_a_missing_value(built):
    env = html_environment()
    context = dict(built["context"])
    del context["counts"]
    with pytest.raises(jinja2.UndefinedError, match="counts"):
        env.get_template("report.html.j2").render(**context)
    with pytest.raises(jinja2.UndefinedError):
        latex_environment().get_template("paper.tex.j2").render()


def test_template_cache_serves_code_only_under_the_settings_it_was_compiled_with(tmp_path, monkeypatch):
    """The templates' compiled code kept on disk (TemplateCache) is used again by a new environment with
    the same settings, not by one whose settings compile the template differently, and is not written
    while Python writes no bytecode (PYTHONDONTWRITEBYTECODE)."""
    folder, cache = tmp_path / "templates", tmp_path / "cache"
    folder.mkdir()
    (folder / "t.j2").write_text("{% if x %}\n<b>{{ x }}</b>\n{% endif %}\n", encoding="utf-8")

    def environment(**options):
        return jinja2.Environment(loader=jinja2.FileSystemLoader(str(folder)), bytecode_cache=TemplateCache(cache),
                                  **options)

    # jinja's defaults: the newline after each tag kept, no escaping, the file's last newline dropped
    plain = "\n<b><</b>\n"
    monkeypatch.setattr(sys, "dont_write_bytecode", True)
    assert environment().get_template("t.j2").render(x="<") == plain
    assert not cache.exists()
    monkeypatch.setattr(sys, "dont_write_bytecode", False)
    assert environment().get_template("t.j2").render(x="<") == plain
    assert len(list(cache.iterdir())) == 1

    def no_compiling(*_args, **_kwargs):
        raise AssertionError("compiled again")
    again = environment()
    monkeypatch.setattr(again, "compile", no_compiling)
    assert again.get_template("t.j2").render(x="<") == plain
    # trim_blocks drops the newline after a tag, autoescape escapes "<": compiled anew, into a file of its own
    assert environment(trim_blocks=True, autoescape=True).get_template("t.j2").render(x="<") == "<b>&lt;</b>\n"
    assert len(list(cache.iterdir())) == 2
    # the project's own templates: write_template_cache compiles each, and the build's environments load them
    assert write_template_cache() == sorted(p.name for p in TEMPLATES.glob("*.j2"))
    for env, name in ((html_environment(), "report.html.j2"), (latex_environment(), "paper.tex.j2")):
        monkeypatch.setattr(env, "compile", no_compiling)
        env.get_template(name)


def test_text_from_input_is_escaped(built):
    context = dict(built["context"])
    attack = "<script>alert(1)</script> & <img src=x onerror=alert(2)>"
    row = context["rows"][0]  # shared with the cached build: restored below
    saved = (row.detail, row.label)
    survey = copy.copy(context["survey"])
    survey.facts = dataclasses.replace(survey.facts, item_texts=(attack,) + survey.facts.item_texts[1:])
    context["survey"] = survey
    context["survey_table"] = survey_table(survey)  # the table and statements both renderings show
    env = html_environment()
    try:
        row.detail = row.label = attack
        for name in ("report.html.j2", "paper.html.j2"):
            html = env.get_template(name).render(**context)
            assert "<script>" not in html and "<img src=x" not in html, name
            assert "&lt;script&gt;alert(1)&lt;/script&gt; &amp; &lt;img" in html, name
    finally:
        row.detail, row.label = saved
    assert latex_escape("50% of {x}_1 & $y$ \\ ^~") == (
        r"50\% of \{x\}\_1 \& \$y\$ \textbackslash{} \textasciicircum{}\textasciitilde{}"
    )


# --------------------------------------------------------------------------- bad input
def _copy_project(tmp_path: Path) -> Path:
    root = tmp_path / "project"
    shutil.copytree(ROOT / "data", root / "data", ignore=shutil.ignore_patterns("__pycache__"))
    return root


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ('\nkind = "identity"', '\nkind = "guess"', "kind: unknown kind 'guess'; valid:"),
        ('\nlhs = "a_x"', '\nlhs = "a_x.__class__"', "attribute"),
        ('alpha = { quantity = "alpha" }', 'alpha = { quantity = "beta" }', "unknown quantity 'beta'"),
    ],
)
def test_bad_equation_file_is_one_line_exit_2_nothing_written(tmp_path, capsys, old, new, message):
    root = _copy_project(tmp_path)
    path = root / "data" / "published" / "equations.toml"
    path.write_text(path.read_text(encoding="utf-8").replace(old, new, 1), encoding="utf-8")
    out = tmp_path / "out"
    assert main(["--root", str(root), "--out", str(out), "--pdf", "never"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "equations.toml" in err and message in err, err
    assert not out.exists() or not any(out.iterdir())
    assert not list(tmp_path.glob(".report-*")), "staging folder left behind"


def test_load_equations_names_file_and_place(tmp_path):
    path = tmp_path / "equations.toml"
    path.write_text('schema = 1\n[scenes]\ns = "x.toml"\n[[equation]]\nid = "e1"\nscene = "t"\n', encoding="utf-8")
    with pytest.raises(ReportInputError, match=r"equations.toml: equation\[0\] \(id 'e1'\).scene: unknown scene 't'"):
        load_equations(path)


def test_the_collector_pause_restores_the_state_it_found():
    """build() pauses the cyclic collector; a caller's process must get back the state it had."""
    import gc

    from reports.cli import cyclic_gc_paused

    was = gc.isenabled()
    try:
        for before in (True, False):
            (gc.enable if before else gc.disable)()
            with pytest.raises(KeyError):  # restored on the way out of a failure too
                with cyclic_gc_paused():
                    assert not gc.isenabled()
                    raise KeyError("inside")
            assert gc.isenabled() is before
    finally:
        (gc.enable if was else gc.disable)()


def test_command_line_has_no_traceback_on_bad_root(tmp_path):
    done = subprocess.run([sys.executable, "-m", "reports", "--root", str(tmp_path), "--out", str(tmp_path / "o")],
                          cwd=ROOT, capture_output=True, text=True, timeout=120, check=False)
    assert done.returncode == 2
    assert "Traceback" not in done.stderr and len(done.stderr.strip().splitlines()) == 1


def test_paper_shows_the_inertial_term_apart_in_both_outputs(built):
    """issue 11: every moment equation keeps the moments of the forces, the inertial term and I_P alpha
    apart; both Newton components; the one-step alternative about C; paper.tex says what paper.html says."""
    out = Path(built["out"])
    html_text = (out / "paper.html").read_text(encoding="utf-8")
    tex = (out / "paper.tex").read_text(encoding="utf-8")
    for text in (html_text, tex):
        # the labels under the terms, with a minus sign (not a hyphen): Example 1 about A, Example 2 about P and C
        # (paper.tex writes the minus sign as pdflatex sets it: \ensuremath{-})
        assert text.count("inertial term \u2212r") + text.count("inertial term \\ensuremath{-}r") >= 3
        assert "I_G of disk" in text or r"I\_G of disk" in text
        assert "one-step alternative about C" in text
        assert "y component" in text and "x component" in text
        assert "Why A:" in text and "Why P:" in text
    assert "is the angular acceleration, the" not in html_text  # the old wording tied to Example 1
    assert r"\toprule point & $x$ & $y$" in tex  # the kinematics table


# --------------------------------------------------------------------------- paper: units, Example 2's numbers, choice of P
def _html_table(page: str, table_id: str) -> dict[str, list[str]]:
    """{unknown: [text of each cell after the name]} of a paper.html results table."""
    import html as html_mod

    body = re.search(rf'<table id="{table_id}">(.*?)</table>', page, flags=re.S).group(1)
    rows = re.findall(r'<tr data-unknown="([^"]+)">(.*?)</tr>', body, flags=re.S)
    return {name: [html_mod.unescape(c).strip() for c in re.findall(r'<td class="num">(.*?)</td>', cells, flags=re.S)]
            for name, cells in rows}


def _tex_rows(tex: str, after: str, names) -> dict[str, list[str]]:
    """{unknown: [cells after the name]} of the paper.tex tabular that follows the text ``after``,
    LaTeX escapes of units turned back into the characters paper.html shows (rows found by the name's
    LaTeX, as reports.mathml writes it)."""
    from reports.mathml import to_latex

    start = tex.index(after)
    body = tex[start:tex.index(r"\end{tabular}", start)]
    plain = body.replace(r"\textsuperscript{2}", "²").replace(r"\ensuremath{\cdot}", "·")
    found = {}
    for name in names:
        line = re.search(rf"^\${re.escape(to_latex(sp.Symbol(name, real=True)))}\$ & (.*?) \\\\$", plain, flags=re.M)
        found[name] = [c.strip() for c in line.group(1).split("&")]
    return found


def _number(text: str) -> float:
    """The number a cell starts with, its sign the HTML's minus sign U+2212 or LaTeX's "-"."""
    return float(text.split()[0].replace("\u2212", "-"))


def test_example1_states_g_c_and_shows_forces_before_the_division(built):
    """Student report: 50 lbm and 32.174 ft/s^2 give lbm*ft/s^2, the table lbf. The paper must say so,
    with g_c (pint's 1 lbf in lbm*ft/s^2), and each force in lbm*ft/s^2 must be its lbf value times g_c."""
    import html as html_mod
    import tomllib

    printed = {v["id"]: v for v in tomllib.loads((PUBLISHED / "example1.toml").read_text(encoding="utf-8"))["value"]}
    g_c = printed["data-g"]["value"]  # 32.174: the paper's g, standard gravity in ft/s^2, i.e. 1 lbf in lbm*ft/s^2
    tolerance = half_unit(printed["data-g"]["printed"])  # the paper prints 5 significant figures: +-0.0005
    out = Path(built["out"])
    page = (out / "paper.html").read_text(encoding="utf-8")
    tex = (out / "paper.tex").read_text(encoding="utf-8")
    sentence = html_mod.unescape(re.search(r'<p id="units-gc">(.*?)</p>', page, flags=re.S).group(1))
    assert "consistent set of units" in sentence and "lbf" in sentence and "lbm" in sentence
    shown_factor = float(re.search(r"g_c = ([0-9.]+) ", sentence).group(1))
    assert abs(shown_factor - g_c) <= tolerance, sentence
    # one source of words: paper.tex carries the same sentence, escaped for LaTeX
    assert latex_escape(sentence) in tex
    # each force: value in lbf and in lbm*ft/s^2; their ratio is g_c. Both are shown to 4 significant
    # figures (each off by at most half a unit in the 4th figure, 5e-4 relative), hence rel=1e-3.
    table = _html_table(page, "ex1-results")
    forces = {name: cells for name, cells in table.items() if cells[0].endswith("lbf")}
    assert set(forces) == {"R_A", "R_B"}
    for name, (in_lbf, consistent) in forces.items():
        assert consistent.endswith("lbm/s²"), consistent
        assert _number(consistent) / _number(in_lbf) == pytest.approx(g_c, rel=1e-3), name
    # the student's own figure: R_B of about 725 lbm*ft/s^2 (22.53 lbf printed, Eq. 30, times 32.174 = 724.9;
    # +-1 covers the paper's 4-figure rounding of R_B, 0.005 lbf * 32.174 = 0.16, and ours)
    assert _number(forces["R_B"][1]) == pytest.approx(printed["eq30-R_B"]["value"] * g_c, abs=1.0)
    assert _tex_rows(tex, "\\subsection*{Numbers at release}", forces) == forces  # the same numbers in paper.tex


def test_example2_numbers_table_holds_the_solver_values(built):
    """Example 2's table: theta_ddot, alpha, F_f, F_n at the scene's state, against the closed forms
    Eq. 44 (F_a = 0, so its sign error does not matter), Eq. 39, Eq. 40 and alpha = -theta_ddot (Eq. 33)."""
    import math

    from references import EX2

    scene = load_scene(ROOT / "data/scenes/disk_bar.toml")  # the input: its state and F_a
    th = scene.state["theta"].to("rad").magnitude
    assert scene.state["theta_dot"].magnitude == 0 and scene.parameters["F_a"].magnitude == 0  # as the forms below
    md, rd, mb, lb, g = (EX2[k] for k in ("m_d", "r_d", "m_b", "l_b", "g"))
    mass = (1.5 * md + mb) * rd**2 + mb * lb**2 / 3 - mb * rd * lb * math.cos(th)  # Eq. 44's bracket
    thdd = -0.5 * mb * g * lb * math.sin(th) / mass  # Eq. 44 at rest, F_a = 0
    expected = {
        "theta_ddot": (thdd, "rad/s²"),
        "alpha": (-thdd, "rad/s²"),
        "F_f": ((md + mb) * rd * thdd - 0.5 * mb * lb * thdd * math.cos(th), "N"),  # Eq. 39
        "F_n": ((md + mb) * g + 0.5 * mb * lb * thdd * math.sin(th), "N"),  # Eq. 40
    }
    out = Path(built["out"])
    table = _html_table((out / "paper.html").read_text(encoding="utf-8"), "ex2-results")
    assert set(table) == set(expected)
    for name, (value, unit) in expected.items():
        (cell,) = table[name]
        assert cell.split(" ", 1)[1] == unit, cell
        # shown to 4 significant figures: off by at most half a unit in the 4th figure (5e-4 relative)
        assert _number(cell) == pytest.approx(value, rel=5e-4), name
    tex = (out / "paper.tex").read_text(encoding="utf-8")
    shown = {name: [cell.replace("\u2212", "-") for cell in cells] for name, cells in table.items()}  # HTML's minus sign
    assert _tex_rows(tex, "Solving the equations at the state of the data table:", expected) == shown


def test_example2_says_both_points_work(built):
    """Student report: "Why P" then "the advisor's first choice is C". Both work; the words come from the
    advisor. By hand: about P, F_n (vertical through C, below P) drops out but F_f does not; about C both
    contact forces drop out, leaving theta_ddot alone."""
    import html as html_mod

    out = Path(built["out"])
    page = html_mod.unescape((out / "paper.html").read_text(encoding="utf-8"))
    tex = (out / "paper.tex").read_text(encoding="utf-8")
    for text in (page, tex.replace(r"\_", "_")):
        assert "first choice is" not in text
        assert "The point advisor ranks C first; both points work" in text
        assert "Both P and C work" in text
        # theta_ddot as the paper writes it (θ̈; \ddot{\theta} in LaTeX), not the code name
        text = text.replace("\\ensuremath{\\ddot{\\theta}}", "\u03b8\u0308")
        assert "about P, whose moment equation holds 2 unknowns (\u03b8\u0308, F_f)" in text
        assert "holds 1 unknown (\u03b8\u0308), which it gives on its own: a one-step alternative" in text


def test_survey_table_and_statements_alike_in_both_renderings(built):
    """QA: paper.tex's survey table showed counts only while the note under it spoke of percentages
    shown, and it lacked the five statements. Both renderings now carry the same cells, by hand for
    item #2: 13, 7, 0, 1, 1 of 22 -> 59.1, 31.8, 0.0, 4.5, 4.5 %; and both quote each statement as
    worded on the survey (the wording below is the paper's, Table 1, item 2)."""
    out = Path(built["out"])
    html_text = (out / "paper.html").read_text(encoding="utf-8")
    tex = (out / "paper.tex").read_text(encoding="utf-8")
    expected = ["#2", "13 (59.1%)", "7 (31.8%)", "0 (0.0%)", "1 (4.5%)", "1 (4.5%)", "22", "90.9%"]
    row = re.search(r"<tr><td[^>]*>#2</td>(.*?)</tr>", html_text, flags=re.S).group(1)
    assert ["#2", *re.findall(r"<td[^>]*>(.*?)</td>", row)][:8] == expected
    tex_row = re.search(r"^\\#2 & .*\\\\$", tex, flags=re.M).group(0)
    tex_cells = [c.strip().replace("\\%", "%").replace("\\#", "#") for c in tex_row.rstrip("\\").split(" & ")]
    assert tex_cells[:8] == expected
    statement = ("I recognize that the alternative form of Euler's equation could offer an advantage over the "
                 "other two standard forms of this equation for the solution of some dynamics problems.")
    assert "as worded on the survey" in html_text and "as worded on the survey" in tex
    assert f"<li class=\"small\">“{statement.replace(chr(39), '&#39;')}”</li>" in html_text
    assert f"\\item ``{statement}''" in tex


def test_both_renderings_number_the_same_displays(built):
    """QA: paper.tex tagged section 1's displays (10), (11), (14), (14) while paper.html numbered none.
    Both now take the number from the display (paper.Shown.number). The article numbers them Eq. 10
    (single body), Eq. 11 (composite body) and Eq. 14 (Newton's law, x and y components)."""
    out = Path(built["out"])
    html_text = (out / "paper.html").read_text(encoding="utf-8")
    tex = (out / "paper.tex").read_text(encoding="utf-8")
    html_numbers = re.findall(r'<div class="numbered"><math.*?</math><span class="eqno">\((\d+)\)</span></div>',
                              html_text, flags=re.S)
    assert html_numbers == re.findall(r"\\tag\{(\d+)\}", tex) == ["10", "11", "14", "14"]


def test_printed_equation_column_shows_the_transcription_as_written(built):
    """QA: the "printed" column showed sympy's evaluated form (Eq. 46 as sqrt(2)*sqrt(...)/2, Eq. 44's
    terms reordered), not the transcription. It is now drawn from the transcribed text: the terms in
    the order data/published/equations.toml writes them, typed here by hand from the paper (Eq. 44:
    inertia bracket times theta_ddot, then the theta_dot squared term, then gravity, = -F_a r_d;
    Eq. 46: one root over the whole fraction)."""
    page = (Path(built["out"]) / "report.html").read_text(encoding="utf-8")

    def printed_cell(row_id):
        row = re.search(rf'<tr id="row-{row_id}">(.*?)</tr>', page, flags=re.S).group(1)
        return re.findall(r"<td[^>]*>(.*?)</td>", row, flags=re.S)[2]

    def visible(markup):
        text = html.unescape(re.sub(r"<[^>]+>", " ", markup).replace("&InvisibleTimes;", "")
                             .replace("&ApplyFunction;", ""))
        return re.sub(r"\s+", "", text)

    assert visible(printed_cell("eq44")) == (
        "((32md+mb)rd2+13mblb2\u2212mbrdlbcos(\u03b8))\u03b8\u00a8"
        + "+12mbrdlbsin(\u03b8)\u03b8\u02d92+12mbglbsin(\u03b8)=\u2212Fard")
    eq46 = printed_cell("eq46")
    assert re.search(r"<mo>=</mo><msqrt><mrow><mfrac>", eq46) and "<mn>2</mn></msqrt>" not in eq46
    assert visible(eq46) == "\u03c9n=12mbglb(32md+mb)rd2+mblb(13lb\u2212rd)"


def test_paper_tex_long_displays_break_and_the_survey_table_fits(built):
    """QA: paper.tex's nine-column survey table (about 20 cm) and three one-line displays (Example 1's
    moment equation about A with its labelled terms, the R_A expression, Example 2's equation about C)
    ran past the 16.6 cm text block. No TeX engine here, so structurally: the table is scaled to
    \\textwidth, and those displays are multline* with each labelled term whole on one line (a break
    inside braces would not compile). R_A's display was one of them until the display tidy wrote
    sin(b)**2*cos(th) + sin(b)*sin(th)*cos(b) as sin(b)*sin(b + th) (QA 15 #7): it is now short, one
    line."""
    tex = (Path(built["out"]) / "paper.tex").read_text(encoding="utf-8")
    assert re.search(r"\\resizebox\{\\textwidth\}\{!\}\{%\n\\begin\{tabular\}\{lrrrrrrrr\}", tex)
    displays = re.findall(r"\\begin\{(multline\*|equation\*)\}\n(.*?)\n\\end\{\1\}", tex, flags=re.S)

    def lines_of(marker):
        found = [(env, body.split(" \\\\\n")) for env, body in displays if marker in body]
        assert len(found) == 1, marker
        return found[0]

    for marker in ("about A}}", "about C}}"):
        env, lines = lines_of(marker)
        assert env == "multline*" and len(lines) >= 2, marker
        for line in lines:  # braces balance on every line: no term is cut
            assert line.count("{") == line.count("}"), line
    env, lines = lines_of("R_{A} = g m_{b}")
    assert env == "equation*" and len(lines) == 1 and r"\sin{\left(\beta + \theta \right)}" in lines[0]


def test_no_code_notation_in_the_prose_and_labels(built):
    """QA: prose and labels showed code: "1 / [time] ** 2", "F_a*r_d", "theta_ddot", underbrace labels
    "gravity:bar", figure units "ft*lbf"/"N*m", a dimensionless "1" after a number. By hand: alpha's
    dimension is 1/[time]² (rad/s², the radian being dimensionless); the wrong term of Eq. 43 is
    F_a r_d; Eq. (29) row 1's coefficient of R_B is cos 15° = 0.96592583, a pure number."""
    out = Path(built["out"])
    pages = {name: (out / name).read_text(encoding="utf-8") for name in ("paper.html", "report.html", "paper.tex")}
    for name, text in pages.items():
        visible = html.unescape(re.sub(r"<[^>]*>", " ", text))  # attributes (data-unknown=...) are not shown
        for code in ("** 2", "F_a*r_d", "{'[", "theta_ddot", "gravity:bar", "gravity:disk", "ft*lbf", "N*m",
                     "lbf*ft", "0.96592583 1 "):
            assert code not in visible, f"{name}: {code!r} shown"
    assert "computed with dimension 1/[time]², unit rad/s²" in pages["paper.html"]
    assert "the term F_a·r_d on the left-hand side has the wrong sign" in pages["paper.html"]
    assert "holds 2 unknowns (θ\u0308, R_B)" in pages["paper.html"]
    assert "holds 2 unknowns (\\ensuremath{\\ddot{\\theta}}, R\\_B)" in pages["paper.tex"]
    assert "{\\text{weight of bar}}" in pages["paper.tex"] and ">weight of bar</mtext>" in pages["paper.html"]
    assert re.search(r"\| = [0-9.]+ (ft·lbf|N·m)<", pages["paper.html"])
    # Eq. (30)'s lbf·s²/ft is a mass: the detail names its dimension [mass], not a Python dict
    assert "has the dimension of the quantity ([mass])" in pages["report.html"]


def test_paper_tex_says_what_paper_html_says(built):
    """QA: paper.tex lacked the HTML's sub-headings, "Moment of inertia about A", the composite I_P, the
    sentence on the moment equation about A, and the lead-in and list before Eq. (43); it had "At release:"
    followed by an unrelated sentence. The shared sentences now come from paper.PROSE; here every one of
    them, and the headings, must appear in both renderings (typed out for the ones the QA named)."""
    out = Path(built["out"])
    page = html.unescape(re.sub(r"<[^>]+>", "", (out / "paper.html").read_text(encoding="utf-8")))
    tex = (out / "paper.tex").read_text(encoding="utf-8")
    flat_tex = re.sub(r"\s+", " ", tex)
    flat_page = re.sub(r"\s+", " ", page)
    for sentence in ("The moment equation about A holds only the reaction at the other end and the angular "
                     "acceleration", "The article's printed versions of this step differ from the derivation:",
                     "Moment of inertia about A:", "moment of inertia of the composite body about P:",
                     "Kinematics at release", "Numbers at release", "Numbers at the chosen state",
                     "Small oscillations", "The one-step alternative about C"):
        assert sentence in flat_page, sentence
        assert latex_escape(sentence) in flat_tex, sentence
    assert re.search(r"differ from the derivation:\n\\begin\{itemize\}\n\\item \\textbf\{Eq\. \(43\)\}", tex)
    assert "At release:" not in tex and "\\subsection*{Numbers at release}" in tex


def test_mathml_minus_is_the_minus_sign_and_the_heading_reads(built):
    """QA: MathML wrote a minus as a hyphen (<mo>-</mo>) while the prose used U+2212; and section 5's
    title, "Where the article and the computation part", lacked its verb's particle ("part ways")."""
    out = Path(built["out"])
    for name in ("paper.html", "report.html"):
        text = (out / name).read_text(encoding="utf-8")
        assert "<mo>-</mo>" not in text and "<mo>\u2212</mo>" in text, name
    assert "Where the article and the computation part ways" in (out / "paper.html").read_text(encoding="utf-8")
    assert "\\section{Where the article and the computation part ways}" in (out / "paper.tex").read_text(
        encoding="utf-8")


def test_result_and_survey_columns_keep_the_printed_precision(built):
    """QA: the "in ft·lbm/s²" column printed "725" next to "897.1", and the survey's computed column "50 %"
    next to the printed "50.0 %". By hand: R_B = 22.54 lbf x 32.174 = 725.0 ft·lbm/s² to 4 figures;
    11/22 = 50.0 % at the printed one decimal; 0/22 = 0.0 %."""
    out = Path(built["out"])
    paper_page = (out / "paper.html").read_text(encoding="utf-8")
    table = re.search(r'<table id="ex1-results">(.*?)</table>', paper_page, flags=re.S).group(1)
    assert '<td class="num">725.0 ft·lbm/s²</td>' in table and '<td class="num">897.1 ft·lbm/s²</td>' in table
    page = (out / "report.html").read_text(encoding="utf-8")

    def cells(row_id):
        row = re.search(rf'<tr id="row-{row_id}">(.*?)</tr>', page, flags=re.S).group(1)
        return [re.sub(r"\s+", " ", c).strip() for c in re.findall(r"<td[^>]*>(.*?)</td>", row, flags=re.S)[2:4]]

    assert cells("table1-item1-definitely-agree") == ["50.0 %", "50.0 %"]
    assert cells("table1-item5-definitely-disagree") == ["0.0 %", "0.0 %"]


def test_figures_titled_by_content_and_the_motion_legend_clear_of_the_curves(built, monkeypatch):
    """QA: the Likert chart's title was a file name ("table1_respondents.csv: ..."), and the legend of
    example2_motion sat over the curves' third maxima. The legend now stands above the plot: its box
    must lie wholly above the top axes, where no curve is drawn."""
    from reports import figures

    svg = (Path(built["out"]) / "figures" / "likert.svg").read_text(encoding="utf-8")
    assert ".csv" not in svg and "Survey answers per item" in svg
    captured = {}
    monkeypatch.setattr(figures, "_result", lambda name, fig, caption, facts: captured.setdefault("fig", fig))
    scene = load_scene(ROOT / "data" / "scenes" / "disk_bar.toml")
    # omega_n = 1.8855 rad/s: the paper's data (paper.html, section 3); 30 deg, the amplitude it treats as small
    figures.example2_free_motion(scene, derive(scene), np.radians(30.0), 1.8855)
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    fig = captured["fig"]
    renderer = FigureCanvasAgg(fig).get_renderer()
    fig.draw(renderer)  # runs the figure's layout engine
    top = fig.axes[0]
    legend_box = top.get_legend().get_window_extent(renderer)
    assert legend_box.y0 >= top.get_window_extent(renderer).y1 - 1  # 1 px: rounding of the layout


def test_the_errors_of_eqs_43_44_sit_under_the_elimination_they_print(built):
    """QA 12 #13: the list of the article's errors in Eqs. 43-44 (the friction force eliminated
    between the horizontal balance and the moment equation about P, giving the equation of motion)
    stood under the heading "The one-step alternative about C", which is not that step. In both
    paper.html and paper.tex it now follows the elimination and its equation of motion, under
    "Equations", before "Numbers at the chosen state" and the alternative about C."""
    out = Path(built["out"])
    for name in ("paper.html", "paper.tex"):
        text = html.unescape((out / name).read_text(encoding="utf-8"))  # paper.html writes ' as &#39;
        section = text[text.index("A disk rolling with a rigidly attached bar"):]
        found = section.index("The article's printed versions of this step differ")
        assert section.index("Eliminating the friction force") < found < section.index("Numbers at the chosen state"), name
        assert found < section.index("The one-step alternative about C"), name  # its heading
        listed = section[found:section.index("Numbers at the chosen state")]
        assert "43" in listed and "44" in listed, name


def test_a_cache_folder_that_is_a_file_leaves_the_templates_to_be_compiled(tmp_path):
    """QA 13 #5: with reports/__pycache__/templates replaced by a file, reading the cache raised
    NotADirectoryError out of the build. An unreadable cache only costs the compiling."""
    folder, cache = tmp_path / "templates", tmp_path / "cache"
    folder.mkdir()
    (folder / "t.j2").write_text("<b>{{ x }}</b>", encoding="utf-8")
    cache.write_text("not a folder", encoding="utf-8")
    env = jinja2.Environment(loader=jinja2.FileSystemLoader(str(folder)), bytecode_cache=TemplateCache(cache, write=True))
    assert env.get_template("t.j2").render(x=1) == "<b>1</b>"
    assert cache.read_text(encoding="utf-8") == "not a folder"


def test_a_truncated_or_damaged_cache_file_leaves_the_template_to_be_compiled(tmp_path):
    """QA 14 #2: a cache file holding jinja's header and nothing more raised EOFError, one with a
    damaged body UnpicklingError, out of the build. Either only costs the compiling."""
    from jinja2.bccache import bc_magic

    folder, cache = tmp_path / "templates", tmp_path / "cache"
    folder.mkdir()
    (folder / "t.j2").write_text("<b>{{ x }}</b>", encoding="utf-8")

    def rendered():
        env = jinja2.Environment(loader=jinja2.FileSystemLoader(str(folder)),
                                 bytecode_cache=TemplateCache(cache, write=True))
        return env.get_template("t.j2").render(x=1)

    assert rendered() == "<b>1</b>"  # writes the cache file
    (written,) = cache.iterdir()
    checksum = written.read_bytes()[len(bc_magic):]
    for damaged in (bc_magic, bc_magic + checksum[:20] + b"\x00garbage"):
        written.write_bytes(damaged)
        assert rendered() == "<b>1</b>"


def test_a_display_wider_than_the_page_is_laid_out_one_term_a_row(built):
    """QA 20 #7: paper.html's Example 2 moment equation about C was one display wider than a 1000 px
    page, scrolled inside its box and cut when printed. It is now laid out as the worked solution's
    HTML lays out its equations, one term a row with its note beside it: three terms on the left (the
    weight's moment, F_a's, the inertial term) and I_C alpha on the right, four rows. The displays that
    fit (about P, Example 1's about A) stay one row each."""
    from solver.mathml import mathml_width

    page = (Path(built["out"]) / "paper.html").read_text(encoding="utf-8")
    about_c = re.findall(r"generalized Euler equation about C \(Eq\. \(11\)\):</p>\s*(<div class=\"terms-eq\">.*?</table></div>)",
                         page, flags=re.S)
    assert len(about_c) == 1  # the one display about C, laid out as a table of terms
    rows = re.findall(r"<tr>(.*?)</tr>", about_c[0], flags=re.S)
    notes = [re.sub(r"<[^>]*>", "", re.search(r'<span class="note">(.*?)</span>', r, re.S).group(1)) for r in rows]
    assert notes == ["moment of weight of bar about C", "moment of F_a about C",
                     "inertial term \u2212r_G/C \u00d7 m a_C", "I_C alpha"]
    assert max(mathml_width(r) for r in rows) < 50  # each row well inside the page (75 units wide)
    for point in ("P", "A"):
        display = re.search(rf"generalized Euler equation about {point} \(Eq\. \(1[01]\)\):</p>\s*<(\w+)", page)
        assert display.group(1) == "math", point
