"""The report's and the paper's words and notation (QA round 10, reader: items 1-4, 7-14).

Reference facts are taken from the paper (/work/shared/paper.md, data/published/) and from hand
arithmetic written out in each test, never from the build's own output:

* Eq. 45 is printed with "≈" (sin θ ≈ θ, cos θ ≈ 1, sin θ θ̇² ≈ 0).
* 1 lbf is, by definition, 0.45359237 kg x 9.80665 m/s², i.e. 9.80665/0.3048 = 32.17404856 lbm·ft/s²;
  the paper divides by its g, 32.174. A force computed from 50 lbm therefore is, in the paper's
  arithmetic, the project's value times 32.17404856/32.174.
"""
from __future__ import annotations

import html
import json
import re
from pathlib import Path

import pytest

from reports.make_report import ROOT, build_cached, latex_escape

EXACT_LBF = 9.80665 / 0.3048  # lbm·ft/s² in 1 lbf: standard gravity in ft/s² (definitions of lbf and ft)
PAPER_G = 32.174  # the paper's g and its divisor (paper, Example 1 data: m_b = 50/32.174)


@pytest.fixture(scope="module")
def built(tmp_path_factory) -> dict:
    """The session's build (shared with tests/test_report.py through build_cached)."""
    return build_cached(tmp_path_factory.getbasetemp() / "report_build", ROOT)


@pytest.fixture(scope="module")
def rows(built) -> dict:
    data = json.loads((Path(built["out"]) / "verification.json").read_text(encoding="utf-8"))
    return {r["id"]: r for r in data["checks"]}


def _page(built, name: str) -> str:
    return (Path(built["out"]) / name).read_text(encoding="utf-8")


def _visible(text: str) -> str:
    """HTML as read: tags dropped, entities decoded, white space collapsed."""
    return re.sub(r"\s+", " ", html.unescape(re.sub(r"<[^>]+>", " ", text)))


def test_eq45_is_printed_with_approximately_equal(built, rows):
    """QA 1: Eq. 45's rules were shown as equalities; the paper prints ≈."""
    for eq_id, text in (("eq45-sin", "sin(theta) ≈ theta"), ("eq45-cos", "cos(theta) ≈ 1"),
                        ("eq45-rate", "sin(theta)*theta_dot^2 ≈ 0")):
        assert rows[eq_id]["published"] == text
        cell = re.search(rf'<tr id="row-{eq_id}">(.*?)</tr>', _page(built, "report.html"), flags=re.S).group(1)
        printed = re.findall(r"<td[^>]*>(.*?)</td>", cell, flags=re.S)[2]
        assert "<mo>\u2248</mo>" in printed and "<mo>=</mo>" not in printed, eq_id
    assert rows["eq44"]["published"].count(" = ") == 1  # an equation stays an equation


def test_one_lbf_conversion_stated_with_the_papers_arithmetic_beside_it(built, rows):
    """QA 2: the words said "50 lbm under standard gravity is exactly 50 lbf" and "50/32.174" beside
    numbers converted by the exact lbf (49.9999 lbf, 1.5540475 slug). The project keeps the exact
    definition and says so; each lbf number also gives what the paper's 1 lbf = 32.174 lbm·ft/s² makes
    of it. By hand: 50 lbm x 32.174 ft/s² / 32.174 = 50 lbf; 50/32.174 = 1.5540499 slug."""
    assert "exactly 50 lbf" not in json.dumps(rows, ensure_ascii=False)
    for row_id, papers in (("eq29-r3-rhs", 50.0), ("data-m_b-slug", 50 / PAPER_G)):
        detail = rows[row_id]["detail"]
        assert "exact definition 1 lbf = 32.17405 lbm·ft/s²" in detail, row_id
        stated = float(re.search(r"\(its g\) it is (-?[0-9.]+)", detail).group(1))
        assert stated == pytest.approx(papers, rel=1e-7), row_id  # printed to 8 significant figures
        assert rows[row_id]["computed"] == pytest.approx(papers * PAPER_G / EXACT_LBF, rel=1e-6), row_id
    for row_id in ("eq30-R_A", "eq30-R_B"):  # the paper's arithmetic: the project's value x 32.17405/32.174
        stated = float(re.search(r"\(its g\) it is (-?[0-9.]+)", rows[row_id]["detail"]).group(1))
        assert stated == pytest.approx(rows[row_id]["computed"] * EXACT_LBF / PAPER_G, rel=1e-6), row_id
    sentence = _visible(re.search(r'<p id="units-gc">(.*?)</p>', _page(built, "paper.html"), flags=re.S).group(1))
    assert "g_c = 32.17405 (ft·lbm/s²)/lbf, the exact definition" in sentence
    assert "The article divides by its g instead, 32.174" in sentence
    assert latex_escape(sentence.strip()) in re.sub(r"\s+", " ", _page(built, "paper.tex"))


def test_friction_ratio_peaks_at_both_turning_points(built):
    """QA 7: the paper said the friction ratio peaks "at an angle of -30 deg"; |F_f|/F_n at rest at
    ±θ0 is the same by the symmetry of Eqs. 39-40 with θ̇ = 0 (F_f and the sin θ terms change sign,
    F_n does not), so it peaks at both turning points, θ0 = π/6 = 30 deg (paper, Eq. 45's range)."""
    page = _visible(_page(built, "paper.html"))
    assert "(equally at both turning points, ±30 deg)" in page
    assert "at an angle of" not in page
    assert "(equally at both turning points, \\ensuremath{\\pm}30 deg)" in _page(built, "paper.tex")


def test_inertia_displays_cite_the_papers_own_equations(built):
    """QA 8: Example 1's I_A display cited Eq. (12) only; the paper's equation for the bar's I_A is
    Eq. (21), and for the disk-bar body's I_P Eq. (35) (paper.md), each term following Eq. (12)."""
    page = _visible(_page(built, "paper.html"))
    tex = re.sub(r"\s+", " ", _page(built, "paper.tex"))
    for point, number in (("A", "21"), ("P", "35")):
        text = f"moment of inertia about {point}, per element (parallel axes) (Eq. ({number}); each term by Eq. (12)):"
        assert text in page, text
        assert latex_escape(text) in tex, text


def test_example2_says_alpha_is_minus_theta_ddot(built):
    """QA 9: Example 2 gave only the angular velocity, and its numbers table listed α and θ̈ with
    opposite signs unexplained. The paper's Eq. (33) prints α = −θ̈ k: the kinematics now say so, and
    the table's two numbers are opposite (by hand, both shown to the same 4 significant figures)."""
    page = _visible(_page(built, "paper.html"))
    assert "(k-components, Eq. (33)), so α and θ̈ carry opposite signs in the numbers below" in page
    tex = _page(built, "paper.tex")
    assert ("(k-components, Eq. (33)), so \\ensuremath{\\alpha} and \\ensuremath{\\ddot{\\theta}} carry opposite "
            "signs") in tex
    body = re.search(r'<table id="ex2-results">(.*?)</table>', _page(built, "paper.html"), flags=re.S).group(1)
    cells = dict(re.findall(r'<tr data-unknown="([^"]+)">.*?<td class="num">([^<]*)</td>', body, flags=re.S))
    shown = {name: float(cell.split()[0].replace("\u2212", "-")) for name, cell in cells.items()}  # the minus sign U+2212
    assert shown["alpha"] == -shown["theta_ddot"]


def _all_checks_cells(page: str) -> dict[str, list[str]]:
    """{row id: [cell texts]} of report.html's "All checks" tables."""
    found = {}
    for row_id, body in re.findall(r'<tr id="row-([^"]+)">(.*?)</tr>', page, flags=re.S):
        found[row_id] = [_visible(c).strip() for c in re.findall(r"<td[^>]*>(.*?)</td>", body, flags=re.S)]
    return found


def test_cosmetics_plural_units_and_tolerances(built, rows):
    """QA 14: "3 cell(s)"; eq30-alpha's detail "unit printed as rad/s (dimensionally rad/s^2)"; printed
    units with a caret ("ft/s^2") beside pint's "ft/s²"; disagreeing rows with an empty tolerance cell.
    By hand: Table 1 items #2-#4 each have one unattainable cell (59.2, 63.7, 54.6 out of 22): 3 cells."""
    paper_page = _visible(_page(built, "paper.html"))
    assert "3 cells of the published table print a percentage" in paper_page
    assert "cell(s)" not in paper_page and "cell(s)" not in _page(built, "paper.tex")
    assert "(dimensionally" not in rows["eq30-alpha"]["detail"]
    cells = _all_checks_cells(_page(built, "report.html"))
    for row_id, texts in cells.items():
        for text in texts[2:5]:  # printed, computed, tolerance
            assert "^" not in text, (row_id, text)
        if rows[row_id]["verdict"] == "disagrees":
            assert texts[4], row_id  # the tolerance the verdict was judged by
    assert cells["data-m_b-slug-unit"][2] == "(lbf·s²)/ft"


def test_table_cells_rounding_explains_are_findings_said_as_such(built):
    """QA 11: item #4's cell was listed as a finding while its words said largest-remainder rounding
    "does print this value", and items #2, #3 were explained by another rule. All three cells
    (59.2, 63.7, 54.6; by hand 13/22, 14/22, 12/22 round to 59.1, 63.6, 54.5) now say the same thing
    in their finding: the row-to-100 rule explains the digit, and why that keeps them findings."""
    page = _visible(_page(built, "report.html"))
    findings = page[page.index("Findings that differ from the paper"):page.index("How the checks work")]
    for item, printed, rounded in (("2", "59.2", "59.1"), ("3", "63.7", "63.6"), ("4", "54.6", "54.5")):
        block = findings[findings.index(f"(table1-item{item}-definitely-agree)"):]
        block = block[:block.index("Evidence:")]
        assert f"which rounds to {rounded}%, not the printed {printed}%" in block, item
        assert "so the cell is listed as a difference, not as an agreement with a caveat" in block, item
        assert "does print this value" not in block, item


def test_claim3_read_among_the_item2_group_is_bounded_by_the_marginals(built):
    """QA 13: "upwards of 85% of this same group" may mean among the 20 who agreed with item 2. By
    hand from Table 1 (20 and 19 of 22 agree with items 2 and 3): at most 22 - 20 = 2 of item 3's 19
    are outside the group, so at least 17 of the 20 (85.0%), at most 19/20 = 95.0%; 85.0% is not over 85%."""
    sentence = ("that is among the 20 respondents who agreed with item 2, the share is not in the table, since "
                "which answers go together is unknown: the counts allow from 17/20 = 85.0% to 19/20 = 95.0%, "
                "so on this reading the share is at least 85.0% but not certainly over 85%.")
    assert _visible(_page(built, "paper.html")).count(sentence) == 1
    assert _visible(_page(built, "report.html")).count(sentence) == 2  # the caveat and its row
    assert latex_escape(sentence) in re.sub(r"\s+", " ", _page(built, "paper.tex"))


def test_a_reading_naming_no_claim_is_one_line(built, tmp_path):
    """Bad input: a [[readings]] entry naming a claim that is not evaluated is refused naming the file
    and the place."""
    from reports.paper import claim_readings
    from reports.published import ReportInputError

    survey = built["context"]["survey"]
    bad = tmp_path / "survey.toml"
    bad.write_text('[[readings]]\nclaim = "item9"\ngroup = "item2-usefulness"\nprinted = "x"\n', encoding="utf-8")
    with pytest.raises(ReportInputError, match=r"survey\.toml: readings\[0\]\.claim: no evaluated claim 'item9'"):
        claim_readings(survey, bad)


def _idea(text: str, start: str, end: str) -> str:
    return re.sub(r"\s+", " ", text[text.index(start):text.index(end)])


def test_eq11_symbols_defined_and_the_inertial_force_reversed(built):
    """QA 3 and 4: Eq. 11's x_k, y_k and (I_P)_k were never defined (paper, below Eq. 11: element k's mass
    centre r̄_k - r_P and its inertia about P by Eq. 12); the inertial force "moving with the acceleration
    of P" is -m a_P, opposite to it; the prose wrote "alpha" where the displays write α. Checked in
    paper.tex, whose symbols are the displays' own LaTeX, and in paper.html's visible text."""
    tex = _idea(_page(built, "paper.tex"), "\\section{The idea}", "\\begin{figure}")
    eq11 = tex[tex.index("\\tag{10}"):tex.index("\\tag{11}")]
    for symbol in ("{x}_{k}", "{y}_{k}", "{I_{P}}_{k}", "{m}_{k}"):
        assert symbol in eq11.split("\\begin{equation*}")[1], symbol  # the display uses it ...
    assert ("${m}_{k}$ is the mass of element $k$, ${x}_{k}$ and ${y}_{k}$ the components of the offset of its "
            "mass centre from $P$, and ${I_{P}}_{k}$ its moment of inertia about $P$ (Eq. 12)") in tex  # ... defined
    assert "inertial force \\ensuremath{-}$m$ $a_{P}$ applied at the mass centre" in tex
    assert "reversed in direction" in tex and "$\\alpha$ is the k-component" in tex
    page = _idea(_visible(_page(built, "paper.html")), "1. The idea", "Figure 1")
    for text in (tex, page):
        assert "moving with the acceleration" not in text and "alpha is" not in text


def test_paper_tex_says_what_the_html_says_and_sets_under_pdflatex(built):
    """QA 12: paper.tex lacked "Here M_P is the moment of the external forces about P ...", the lead-in
    "Claims made about these answers:" and how the counts were reconstructed; and it held Unicode −, ×, ²
    in \\text{} and lists, which pdflatex cannot set. Every character outside ASCII left must be one
    inputenc's utf8 maps under T1 (en dash, curly quotes)."""
    page = _visible(_page(built, "paper.html"))
    tex = re.sub(r"\s+", " ", _page(built, "paper.tex"))
    for sentence in ("is the moment of the external forces about", "Claims made about these answers:",
                     "the counts behind them were reconstructed (each cell's percentage must come from a whole "
                     "number of the 22 respondents)", "The statements, as worded on the survey:",
                     "Lagrange's equations built with sympy.physics.mechanics",
                     "linearising the equation of motion about the hanging equilibrium gives a harmonic oscillator"):
        assert sentence in page, sentence
        assert latex_escape(sentence) in tex, sentence
    assert "$M_{P}$ is the moment of the external forces about $P$" in tex
    assert set(ch for ch in tex if ord(ch) > 127) <= {"\u2013", "\u201c", "\u201d"}


def test_verification_json_keeps_the_printed_text_units_and_tolerance(built, rows):
    """QA 10: verification.json stored printed numbers as floats only (-0.0508 for the printed 0.05080
    with its minus between terms, 50.0 for 50), without the units and the tolerance the HTML shows.
    By hand from example1.toml and table1.csv: the texts below; the half unit of 32.174 is 0.0005."""
    assert rows["eq29-r1-alpha"]["published_text"] == "-0.05080" and rows["eq29-r1-alpha"]["published"] == -0.0508
    assert rows["data-m_b"]["published_text"] == "50" and rows["data-m_b"]["published_unit"] == "lbm"
    assert rows["data-g"]["tolerance"] == "±0.0005"
    assert rows["table1-item1-definitely-agree"]["published_text"] == "50.0"
    assert rows["eq30-alpha-unit"]["tolerance"] == "same dimension"
    assert rows["eq44"]["tolerance"] == "exact zero"
    assert "wilson" not in rows["claim-item3"]["detail"]  # "Wilson", as the HTML writes it
    cells = _all_checks_cells(_page(built, "report.html"))
    for row_id, row in rows.items():  # the HTML's tolerance column is the JSON's field
        assert cells[row_id][4] == row["tolerance"], row_id


def test_an_untracked_file_outside_the_build_folders_does_not_make_the_tree_dirty(tmp_path):
    """README walkthrough: running the README's examples writes crank.csv, worked.html, ... at the top
    of the checkout, and the report's provenance then said the working tree had uncommitted changes,
    though nothing the build reads had changed (as ``git describe --dirty`` ignores untracked files).
    An untracked file where the build reads (a new scene under data/) still counts, and so does any
    change to a tracked file. A real git repository, made here, gives the status lines."""
    import shutil
    import subprocess

    from reports.provenance import collect

    if shutil.which("git") is None:
        pytest.skip("git is not installed")

    def git(*argv):
        subprocess.run(["git", "-c", "user.email=t@t", "-c", "user.name=t", *argv], cwd=tmp_path, check=True,
                       capture_output=True)

    (tmp_path / "data").mkdir()
    (tmp_path / "data" / "a.toml").write_text("a = 1\n")
    git("init", "-q")
    git("add", ".")
    git("commit", "-q", "-m", "x")
    assert collect(tmp_path).dirty is False
    (tmp_path / "crank.csv").write_text("t\n")
    assert collect(tmp_path).dirty is False
    (tmp_path / "data" / "b.toml").write_text("b = 1\n")
    assert collect(tmp_path).dirty is True
    (tmp_path / "data" / "b.toml").unlink()
    (tmp_path / "data" / "a.toml").write_text("a = 2\n")
    assert collect(tmp_path).dirty is True
    # QA 23 #4: the project in a folder of a larger repository (git names paths from the top)
    git("checkout", "-q", "--", ".")
    (tmp_path / "proj" / "data").mkdir(parents=True)
    (tmp_path / "proj" / "data" / "c.toml").write_text("c = 1\n")
    git("add", ".")
    git("commit", "-q", "-m", "y")
    assert collect(tmp_path / "proj").dirty is False
    (tmp_path / "proj" / "solver").mkdir()
    (tmp_path / "proj" / "solver" / "new.py").write_text("x = 1\n")
    assert collect(tmp_path / "proj").dirty is True
    (tmp_path / "data" / "b.toml").write_text("b = 1\n")  # outside the project: not its change
    (tmp_path / "proj" / "solver" / "new.py").unlink()
    assert collect(tmp_path / "proj").dirty is False
