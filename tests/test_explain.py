"""``python -m solver explain``: the worked solution reproduces the paper's equations step by step.

References: the printed equations of Examples 1 and 2 as transcribed in
data/published/equations.toml (Eqs. 16-28 and 31-46) and Eq. 29's numbers in
data/published/example1.toml. Each displayed step is
compared with its printed equation symbolically: the printed symbols (alpha,
a_A, I_P ...) take the values the explanation itself displays, both sides are
reduced modulo sin^2 + cos^2 = 1 (exact polynomial arithmetic, no tolerance),
and the displayed equation must be the printed one times a factor free of the
state and of the unknowns (a factor in the parameters is allowed: Eq. 27 is
compared with the displayed moment equation as it stands, Eq. 28 with the displayed
collected form, where the factor must be 1). Eqs. 43-44 print F_a with the wrong sign (the report
proves it): they must agree at F_a = 0 and differ by exactly 2 F_a r_d otherwise.
"""
from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest
import sympy as sp

from reports.published import load_equations
from solver.explain import explain, render
from solver.display import reduce_trig
from solver.expressions import parse_expression
from solver.io.scenes import load_system

ROOT = Path(__file__).resolve().parents[1]
PUBLISHED = ROOT / "data" / "published" / "equations.toml"

# printed equation id -> (step kind, equation tag, how the printed symbols read the step)
STEP_OF = {
    "eq20-a_A": ("kinematics", "accel:A"), "eq20-a_B": ("kinematics", "accel:B"),
    "eq20-a_x": ("kinematics", "accel:G"), "eq20-a_y": ("kinematics", "accel:G"),
    "eq21": ("euler", "inertia"), "eq24": ("newton", "newton_x"), "eq25": ("newton", "newton_y"),
    "eq27": ("euler", "euler"), "eq28": ("euler", "collected"),
    "eq31": ("kinematics", "accel:P"), "eq35": ("euler", "inertia"),
    "eq38-x": ("kinematics", "accel:Q"), "eq38-y": ("kinematics", "accel:Q"),
    "eq39": ("newton", "newton_x"), "eq40": ("newton", "newton_y"), "eq42": ("euler", "euler"),
    "eq43": ("motion", "eliminated"), "eq44": ("motion", "eom:theta"),
    # the other printed steps: kinematics by component, the forces as vectors (a definition each),
    # the vector forms of Newton (Eqs. 23, 37) and of the moment equation (Eqs. 26, 41)
    "eq23-x": ("newton", "newton_x"), "eq23-y": ("newton", "newton_y"), "eq26": ("euler", "euler"),
    "eq37-x": ("newton", "newton_x"), "eq37-y": ("newton", "newton_y"), "eq41": ("euler", "euler"),
}
# identities: the printed relation holds between the quantities the explanation displays
IDENTITIES = (
    "eq16-x", "eq16-y", "eq17-a_A", "eq17-a_B-x", "eq17-a_B-y", "eq18-a_x", "eq18-a_y", "eq19-x", "eq19-y",
    "eq19-r_BA-x", "eq19-r_BA-y", "eq21-parallel", "eq21-terms", "eq22-W_b", "eq22-R_A", "eq22-R_B-x",
    "eq22-R_B-y", "eq26-r_GA-x", "eq26-r_GA-y",
    "eq31-x_P", "eq31-v_P", "eq32-r_QP-x", "eq32-r_QP-y", "eq32-r_CP-x", "eq32-r_CP-y", "eq33-v_P", "eq33-a_P",
    "eq33-omega", "eq33-alpha", "eq34-disk", "eq34-bar", "eq35-sum", "eq35-parallel", "eq36-W_d", "eq36-W_b",
    "eq36-F_a", "eq36-F_f", "eq36-F_n", "eq41-r_PP",
)
APPROXIMATIONS = ("eq45-sin", "eq45-cos", "eq45-rate")
PAPER_POINT = {"sliding_bar": "A", "disk_bar": "P"}


@pytest.fixture(scope="module")
def paper():
    eqset = load_equations(PUBLISHED)
    systems = {k: load_system(p) for k, p in eqset.scenes.items()}
    expl = {k: explain(s, PAPER_POINT[k], advice=False) for k, s in systems.items()}
    return eqset, systems, expl


def _zero(expr) -> bool:
    reduced = reduce_trig(sp.expand(expr))
    return reduced is not None and reduced == 0  # None: the reduction gave up, which is not a zero


def _printed(tr, system, section):
    """The printed lhs - rhs with every printed symbol read from the explanation's displayed steps."""
    names = dict(system.symbols)
    c = system.free[0]
    names.update({c.name: c.q, f"{c.name}_dot": c.qd, f"{c.name}_ddot": c.qdd})
    for s in tr.symbols:
        names[s] = sp.Symbol(s, real=True)
    lhs = parse_expression(tr.lhs, names, where=tr.id)
    rhs = parse_expression(tr.rhs, names, where=tr.id)
    values = {names[s]: _displayed(m, section, names, tr) for s, m in tr.symbols.items()}
    assume = {names[k]: parse_expression(v, names, where=tr.id) for k, v in tr.assume.items()}
    return (lhs - rhs).xreplace(values).xreplace(assume), assume


def _displayed(m, section, names, tr):
    """The value the explanation displays for a printed symbol's meaning (see equations.toml)."""
    kin, euler, fbd = section.step("kinematics"), section.step("euler"), section.step("fbd")
    P = kin.equations[2].tag.split(":")[1]  # pos:P, the point the kinematics start from
    inertia = euler.equation("inertia")
    if m.quantity == "alpha":
        return kin.equation("alpha").right
    if m.quantity == "omega":
        return kin.equation("omega").right
    if m.quantity == "reaction":
        return sp.Symbol(m.name, real=True)
    if m.quantity == "inertia_about":
        if m.point == P:
            return inertia.left
        assert m.point == "G" and len(inertia.rhs) == 2, tr.id  # one element: I_G is its own term
        return inertia.rhs[0].expr
    if m.quantity == "element_inertia":  # I_G of the element, plus m d^2 when taken about P
        terms = {t.note: t.expr for t in inertia.rhs}
        return terms[f"I_G of {m.element}"] + (terms.get(f"m d^2 of {m.element}", 0) if m.point == P else 0)
    if m.quantity == "relative_position":
        rel = {X: (sp.zeros(2, 1) if X == P else kin.equation(f"rel:{X}").left) for X in (m.point, m.relative_to)}
        vector = rel[m.point] - rel[m.relative_to]
    elif m.quantity == "position":
        assert m.point == P, tr.id
        vector = kin.equation(f"pos:{P}").left
    elif m.quantity in ("velocity", "acceleration"):
        vector = kin.equation(f"{'vel' if m.quantity == 'velocity' else 'accel'}:{m.point}").left
    elif m.quantity == "force":
        vector = fbd.equation(f"force:{m.name}").left
    elif m.quantity == "resultant":
        vector = sum((e.left for e in fbd.equations if e.tag.startswith("force:")), sp.zeros(2, 1))
    else:  # pragma: no cover - every quantity of equations.toml is handled above
        raise AssertionError(m.quantity)
    u = sp.Matrix([parse_expression(x, names, where=tr.id) for x in m.along])
    return (vector.T * u)[0]


def _residual(tr, systems, expl):
    system = systems[tr.scene]
    section = expl[tr.scene].section("body")
    printed, assume = _printed(tr, system, section)
    kind, tag = STEP_OF[tr.id]
    step = section.step(kind) if kind != "motion" else expl[tr.scene].sections[-1].step("motion")
    alpha = section.step("kinematics").equation("alpha").right  # a collected step writes q'' as alpha
    shown = step.equation(tag).residual.xreplace({sp.Symbol("alpha", real=True): alpha}).xreplace(assume)
    if tr.kind == "identity":
        return printed, sp.Integer(1)
    qdd = system.free[0].qdd
    factor = sp.cancel(sp.expand(shown).coeff(qdd) / sp.expand(printed).coeff(qdd))
    factor = reduce_trig(factor)
    assert not factor.has(*system.q, *system.qd, qdd), f"{tr.id}: not proportional (factor {factor})"
    return sp.expand(shown - factor * printed), factor


@pytest.mark.parametrize("eq_id", [k for k in STEP_OF if k not in ("eq43", "eq44")])
def test_each_displayed_step_equals_the_printed_equation(paper, eq_id):
    eqset, systems, expl = paper
    tr = next(e for e in eqset.equations if e.id == eq_id)
    residual, _ = _residual(tr, systems, expl)
    assert _zero(residual), f"{eq_id}: displayed step - printed = {residual}"


def test_eq28_is_the_collected_moment_equation_as_printed(paper):
    """Eq. 28 is shown as its own step: Eq. 27 divided by l_b and collected, the same equation as
    printed up to a pure number (the factor is 1: signed as the paper signs it)."""
    eqset, systems, expl = paper
    tr = next(e for e in eqset.equations if e.id == "eq28")
    residual, factor = _residual(tr, systems, expl)
    assert _zero(residual) and factor == 1


@pytest.mark.parametrize("eq_id", ["eq43", "eq44"])
def test_eqs_43_44_agree_but_for_the_sign_of_F_a(paper, eq_id):
    eqset, systems, expl = paper
    tr = next(e for e in eqset.equations if e.id == eq_id)
    residual, factor = _residual(tr, systems, expl)
    F_a, r_d = sp.symbols("F_a r_d", real=True)
    assert _zero(residual.xreplace({F_a: 0}))
    assert _zero(residual - 2 * factor * F_a * r_d) or _zero(residual + 2 * factor * F_a * r_d)
    assert not _zero(residual)


def test_eq46_natural_frequency(paper):
    """Eq. 46 (F_a = 0, about theta = 0): the displayed omega_n squared equals the printed one squared."""
    eqset, systems, expl = paper
    tr = next(e for e in eqset.equations if e.id == "eq46")
    system = systems["disk_bar"]
    shown = expl["disk_bar"].sections[-1].step("motion").equation("omega_n").right
    printed = parse_expression(tr.rhs, dict(system.symbols), where=tr.id)
    assert _zero(shown**2 - printed**2)


def test_printed_identities_hold_for_the_displayed_quantities(paper):
    """Kinematics (Eqs. 16-20, 31-33), inertia (Eqs. 21, 34-35) and the forces (Eqs. 22, 36): each
    printed symbol read from the step that displays it, the printed relation holds exactly."""
    eqset, systems, expl = paper
    by_id = {e.id: e for e in eqset.equations}
    assert set(IDENTITIES) == {e.id for e in eqset.equations if e.kind == "identity"} - set(STEP_OF)
    for eq_id in IDENTITIES:
        tr = by_id[eq_id]
        printed, _ = _printed(tr, systems[tr.scene], expl[tr.scene].section("body"))
        assert _zero(printed), f"{eq_id}: printed lhs - rhs with the displayed values = {printed}"


def test_eq16_is_a_displayed_step(paper):
    """Eq. 16 is shown as its own step: a_G = a_A/2 + a_B/2, each side equal to the printed side
    (the printed symbols read from the displayed accelerations)."""
    eqset, systems, expl = paper
    system, section = systems["sliding_bar"], expl["sliding_bar"].section("body")
    step = section.step("kinematics").equation("midpoint:G")
    names = dict(system.symbols)
    for i, eq_id in enumerate(("eq16-x", "eq16-y")):
        tr = next(e for e in eqset.equations if e.id == eq_id)
        local = {**names, **{s: sp.Symbol(s, real=True) for s in tr.symbols}}
        values = {local[s]: _displayed(m, section, local, tr) for s, m in tr.symbols.items()}
        for shown, printed in ((step.left[i], tr.lhs), (step.right[i], tr.rhs)):
            assert _zero(shown - parse_expression(printed, local, where=tr.id).xreplace(values)), eq_id


def test_eq45_small_motion_rules_are_displayed(paper):
    """Eq. 45: each printed rule is one of the displayed small-motion rules, in the paper's order,
    shown as an approximation (not an equality)."""
    eqset, systems, expl = paper
    system = systems["disk_bar"]
    shown = [e for e in expl["disk_bar"].sections[-1].step("motion").equations if e.tag.startswith("approx:")]
    assert all(e.approximate for e in shown)
    positions = []
    for eq_id in APPROXIMATIONS:
        tr = next(e for e in eqset.equations if e.id == eq_id)
        printed, _ = _printed(tr, system, expl["disk_bar"].section("body"))
        hits = [i for i, e in enumerate(shown) if _zero(e.residual - printed)]
        assert hits, f"{eq_id}: no displayed rule {printed} ~ 0 among {[e.residual for e in shown]}"
        positions.append(hits[0])
    assert positions == sorted(positions)


def test_eq46_linearised_equation(paper):
    """Eq. 46's first part, theta_ddot + omega_n^2 theta = 0, with the printed omega_n (F_a = 0)."""
    eqset, systems, expl = paper
    system = systems["disk_bar"]
    c = system.free[0]
    shown = expl["disk_bar"].sections[-1].step("motion").equation("linearised").residual
    tr = next(e for e in eqset.equations if e.id == "eq46")
    omega_n = parse_expression(tr.rhs, dict(system.symbols), where=tr.id)
    assert _zero(shown - (c.qdd + omega_n**2 * c.q))


def test_eq29_the_data_entered(paper):
    """Eq. 29 (data/published/example1.toml, four significant figures): each displayed row with the
    data entered is the printed row times a constant (row 1 is Eq. 28 = Eq. 27 / l_b; the explanation
    keeps the moment equation in ft*lbf). Compared as ratios of a row's numbers: each number on
    either side is rounded to 4 significant figures (relative error <= 5e-4), so a ratio of two
    displayed numbers and the same ratio of printed ones agree within 4 x 5e-4 = 2e-3; a wrong
    coefficient (1/3 -> 1/4 in Eq. 28 changes alpha's by a factor 6) is far outside."""
    import tomllib

    printed = {v["id"]: v["value"] for v in tomllib.loads((ROOT / "data/published/example1.toml").read_text())["value"]}
    step = paper[2]["sliding_bar"].sections[-1].step("numbers")
    rows = {"r1": "euler", "r2": "newton_x", "r3": "newton_y"}
    tags = [e.tag for e in step.equations]
    assert tags == [f"numbers:body:{rows[r]}" for r in ("r1", "r2", "r3")]  # the paper's order
    for row, tag in rows.items():
        eq = step.equation(f"numbers:body:{tag}")
        shown = {t.note: float(t.expr.as_coeff_Mul()[0]) for t in eq.lhs}
        shown["rhs"] = float(eq.right)
        paper_row = {k.split("-")[2]: v for k, v in printed.items() if k.startswith(f"eq29-{row}-")}
        assert set(shown) == set(paper_row), (row, shown, paper_row)
        ref = max(paper_row, key=lambda k: abs(paper_row[k]))
        for name, value in paper_row.items():
            if value == 0:
                assert shown[name] == 0
                continue
            assert shown[name] / shown[ref] == pytest.approx(value / paper_row[ref], rel=2e-3), (row, name)


def _answers(expl):
    rows = expl.sections[-1].step("solution").table.rows
    return {r[0]: float(r[1]) for r in rows}


@pytest.mark.parametrize("scene,points", [("sliding_bar", ["B", "G"]), ("disk_bar", ["C", "Q", "G"])])
def test_every_named_point_other_equations_same_answers(paper, scene, points):
    """Other points: a different moment equation, the same unknowns (printed to 6 digits, so the
    values must agree to the last printed digit: rel 1e-5)."""
    _, systems, expl = paper
    base = expl[scene]
    base_euler = base.section("body").step("euler").equation("euler").residual
    for point in points:
        other = explain(systems[scene], point, advice=False)
        euler = other.section("body").step("euler").equation("euler").residual
        assert not _zero(euler - base_euler), point
        for name, value in _answers(base).items():
            assert _answers(other)[name] == pytest.approx(value, rel=1e-5), (point, name)
        check = other.sections[-1].step("check").table.rows
        assert all(float(r[4]) < 1e-9 for r in check), point


def test_inertial_term_and_I_P_alpha_are_separate_terms(paper):
    _, _, expl = paper
    euler = expl["disk_bar"].section("body").step("euler")
    notes = [t.note for t in euler.equation("euler").lhs]
    assert any(n.startswith("inertial term") for n in notes)
    assert [t.note for t in euler.equation("euler").rhs] == ["I_P alpha"]
    per_element = [t.note for t in euler.equation("inertia").rhs]
    assert per_element == ["I_G of disk", "I_G of bar", "m d^2 of bar"]  # the disk's centre is P: d = 0


def test_dropped_unknowns_name_the_line_through_P(paper):
    _, _, expl = paper
    text = " ".join(expl["disk_bar"].section("body").step("dropped").text)
    assert "F_n drops out" in text and "passes through P" in text
    text = " ".join(expl["sliding_bar"].section("body").step("dropped").text)
    assert "R_A drops out" in text and "passes through A" in text


def test_html_escapes_scene_names(tmp_path):
    scene = (ROOT / "data" / "scenes" / "sliding_bar.toml").read_text(encoding="utf-8")
    scene = scene.replace('description = "', 'description = "<script>alert(1)</script> ')
    path = tmp_path / "evil.toml"
    path.write_text(scene, encoding="utf-8")
    expl = explain(load_system(path), advice=False)
    out = render(expl, "html")
    assert "<script>" not in out and "&lt;script&gt;" in out
    assert "<script>" not in render(expl, "markdown")


def test_markdown_escapes_dollar_in_scene_text(tmp_path):
    """A ``$`` of the scene's name or description is text: escaped (``\\$``), so that a KaTeX/MathJax
    Markdown renderer does not set ``$E=mc^2$`` as maths. Outside the ``$$`` display blocks the
    solution writes, no ``$`` is left unescaped."""
    scene = (ROOT / "data" / "scenes" / "sliding_bar.toml").read_text(encoding="utf-8")
    scene = scene.replace('name = "sliding_bar"', 'name = "cost $5 $E=mc^2$"', 1)
    scene = scene.replace('description = "', 'description = "$x$ and ', 1)
    path = tmp_path / "dollar.toml"
    path.write_text(scene, encoding="utf-8")
    out = render(explain(load_system(path), advice=False), "markdown")
    assert r"cost \$5 \$E=mc^2\$" in out and r"\$x\$ and" in out
    prose = re.sub(r"^\$\$\n.*?\n\$\$$", "", out, flags=re.MULTILINE | re.DOTALL)
    assert "E=mc" in prose and re.search(r"(?<!\\)\$", prose) is None


def test_latex_escapes_scene_text(tmp_path):
    scene = (ROOT / "data" / "scenes" / "sliding_bar.toml").read_text(encoding="utf-8")
    scene = scene.replace('description = "', r'description = "$\\input{x} 100% & #1 ')
    path = tmp_path / "tex.toml"
    path.write_text(scene, encoding="utf-8")
    out = render(explain(load_system(path), advice=False), "latex")
    assert r"\$\textbackslash{}input\{x\} 100\% \& \#1" in out
    assert r"\input{x}" not in out


def test_solution_reproduces_eq30(paper):
    """Eq. 30 as printed (data/published/example1.toml: alpha 2.297 rad/s^2, R_B 22.53 lbf, R_A 27.88 lbf,
    four significant figures): the explanation's solution, in the scene's output units, agrees to one unit
    of the last printed digit (the paper back-substitutes already rounded values, see [systems.eq29]
    back_substitution in data/published/equations.toml, so its last digit can be off by one; the
    verification report checks the exact rounding rule)."""
    import tomllib

    printed = {v["id"]: v for v in tomllib.loads((ROOT / "data/published/example1.toml").read_text())["value"]}
    rows = {r[0]: r for r in paper[2]["sliding_bar"].sections[-1].step("solution").table.rows}
    for name in ("alpha", "R_B", "R_A"):
        value = printed[f"eq30-{name}"]["value"]
        last_digit = 10.0 ** -(len(printed[f"eq30-{name}"]["printed"].split(".")[1]))
        assert abs(float(rows[name][1]) - value) <= last_digit, name
    assert rows["R_B"][2] == "lbf" and rows["R_A"][2] == "lbf"


def test_cli_formats_and_bad_input(tmp_path, capsys):
    """The real entry point once (a subprocess); the refusals in-process: one line, status 2,
    nothing written."""
    from solver.__main__ import main

    out = tmp_path / "x.md"
    r = subprocess.run([sys.executable, "-m", "solver", "explain", "data/scenes/disk_bar.toml", "-o", str(out)],
                       cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert out.read_text(encoding="utf-8").startswith("# Worked solution")

    def refused(*args):
        with pytest.raises(SystemExit) as stop:
            main(["explain", *args])
        err = capsys.readouterr().err
        assert stop.value.code == 2 and err.count("\n") == 1 and err.startswith("error: ")
        return err

    assert "'Z'" in refused(str(ROOT / "data/scenes/disk_bar.toml"), "--point", "Z")
    assert "-o" in refused(str(ROOT / "data/scenes/disk_bar.toml"), "-o", str(tmp_path / "missing" / "x.txt"))
    assert "--format" in refused(str(ROOT / "data/scenes/disk_bar.toml"), "--format", "pdf")
    assert not (tmp_path / "missing").exists()


# The point advisor: the expected choice per body, and the textbook reason it holds.
ADVISOR = {
    # Example 1: A's acceleration is along its rail (known from the joint), R_A passes through A, and
    # with Newton x (which has no R_A) it gives alpha and R_B: the paper's choice. B also removes one
    # reaction but needs all three equations; the intersection of the reactions' lines leaves only
    # theta_ddot but its acceleration must be derived first.
    "sliding_bar": {"body": {"A"}},
    # Example 2: the paper takes P (a_P = r_d theta_ddot from rolling, F_n through P); the contact point C
    # removes both floor reactions and gives theta_ddot in one step. Either is the textbook answer.
    "disk_bar": {"body": {"C", "P"}},
    # fixed pivots remove their pin reactions and have no inertial term; the rod and the piston are taken
    # about the pin that joins them to the previous body.
    "slider_crank": {"crank": {"O"}, "rod": {"A"}, "piston": {"B"}},
    "four_bar": {"crank": {"O2"}, "coupler": {"A", "B"}, "rocker": {"O4"}},
    # the upper link is massless with its bob at A: about A only the pivot force's moment remains (a
    # two-force member); the lower link about the pin A removes the pin forces.
    "double_pendulum": {"upper": {"A"}, "lower": {"A"}},
    "cart_pendulum": {"cart": {"C"}, "pendulum": {"C"}},
    "drum_and_block": {"drum": {"O"}, "block": {"P"}},
    "parallel_link_plate": {"link1": {"O"}, "link2": {"O"}, "plate": {"A", "B"}},
}


@pytest.mark.parametrize("scene", sorted(ADVISOR))
def test_advisor_picks_the_textbook_point(scene):
    from solver.analyses.instant import assemble
    from solver.explain import rank_points

    system = load_system(ROOT / "data" / "scenes" / f"{scene}.toml")
    state = assemble(system)
    for body, expected in ADVISOR[scene].items():
        ranked = rank_points(system, body, state)
        assert ranked[0].name in expected, (body, [(c.name, c.unknowns) for c in ranked])
        assert ranked[0].known  # never a point whose acceleration must be derived first


def test_advisor_reasons_for_example_1():
    from solver.analyses.instant import assemble
    from solver.explain import rank_points

    system = load_system(ROOT / "data" / "scenes" / "sliding_bar.toml")
    ranked = {c.name: c for c in rank_points(system, "body", assemble(system))}
    assert ranked["A"].unknowns == ["theta_ddot", "R_B"] and ranked["A"].group == 2
    assert ranked["B"].unknowns == ["theta_ddot", "R_A"] and ranked["B"].group == 3
    assert len(ranked["G"].unknowns) == 3
    instant = [c for c in ranked.values() if c.name.startswith("I(")]
    assert len(instant) == 1 and instant[0].unknowns == ["theta_ddot"] and not instant[0].known


def test_html_worked_solution_draws_each_free_body_diagram(solver_cli, tmp_path):
    """The HTML worked solution shows one drawn free-body diagram per body, labelled with
    that body's reactions as the scene names them (the text formats list them instead)."""
    import re

    out = tmp_path / "crank.html"
    code, _, err = solver_cli("explain", "data/scenes/slider_crank.toml", "-o", str(out))
    assert code == 0, err
    html_text = out.read_text()
    figures = re.findall(r'<figure class="fbd">(.*?)</figure>', html_text, flags=re.S)
    assert len(figures) == 3 and all(f.startswith("<svg") for f in figures)
    # the rod's diagram carries the pin forces at both of its ends (named A_x, A_y, B_x, B_y in the scene)
    rod = next(f for f in figures if "rod: free-body diagram" in f)
    assert all(name in rod for name in ("A_x", "A_y", "B_x", "B_y")), rod[:200]
    # three matplotlib drawings, each numbering its ids alike: in the page each id is its own (QA 19 #10)
    from html_ids import page_ids
    assert page_ids(html_text) == ([], [])


# ------------------------------------------------------------------ every scene the core can express
SCENES = sorted(p.stem for p in (ROOT / "data" / "scenes").glob("*.toml"))


@pytest.fixture(scope="module")
def every_scene(paper):
    """Each shipped scene and its explanation (once per module: formulating is the cost; the
    paper's two scenes come from the ``paper`` fixture)."""
    _, systems, expl = paper
    out = {name: (systems[name], expl[name]) for name in systems}
    for name in SCENES:
        if name not in out:
            system = load_system(ROOT / "data" / "scenes" / f"{name}.toml")
            out[name] = (system, explain(system, advice=False))
    return out


FORMATS = ("text", "markdown", "html", "latex")


@pytest.fixture(scope="module")
def every_rendering(every_scene):
    """Each shipped scene's explanation rendered in each format, once per module: (scene, format)
    -> document. Four tests read these pages (about 1.7 s of CPU to render them all); rendering is
    a pure function of the explanation, so each reads what ``render`` gives."""
    return {(name, fmt): render(expl, fmt) for name, (_, expl) in every_scene.items() for fmt in FORMATS}


def test_every_shipped_scene_explains_in_every_format(every_scene, every_rendering):
    """Contacts in whichever regime holds (slipping, sticking, separated, held redundantly) and
    loop closures included: a section per body, an equation of motion when anything moves freely,
    and each format renders."""
    for name, (system, expl) in every_scene.items():
        assert [s.body for s in expl.sections if s.body is not None] == list(system.bodies), name
        final = expl.sections[-1]
        if system.free:
            assert final.step("motion").equations, name
        if system.contacts:
            assert expl.section(None).step("regime").table is not None, name
        for fmt in FORMATS:
            out = every_rendering[name, fmt]
            assert "Equation of motion" in out or not system.free, (name, fmt)
            if fmt == "latex":
                assert out.count(r"\begin{") == out.count(r"\end{"), name


# A product with a factor 0 (text "*0", "0*"; LaTeX "\cdot 0"; MathML a times sign next to <mn>0</mn>)
TIMES_ZERO = re.compile(r"\*0(?![.\d])|(?<![\w.])0\*(?!\*)|\\cdot 0(?![.\d])"
                        r"|(?:&InvisibleTimes;|×)</mo><mn>0</mn>|<mn>0</mn><mo>(?:&InvisibleTimes;|×)")
# A number with a trailing ".0" (2.0, 0.0, -100.0); a mantissa before an exponent (2.0e-16, the relative
# differences of the check, printed to two significant figures) is not one
POINT_ZERO = re.compile(r"(?<![\w.])\d+\.0(?![\de]|\\times 10|</mn><mo>×</mo><msup>)")


def test_no_times_zero_and_no_trailing_point_zero(every_scene, every_rendering):
    """QA 15 #6: a term that is zero is shown as 0, never as I_P times alpha = 0 (``(m_c*r**2/3)*0``,
    ``0*0``, ``M_{cyl} = 0 \\cdot 0``), and the equations with the data entered write integers as
    integers (``2*x_ddot``, ``= 0``), not ``2.0``/``0.0``: every shipped scene in every format, and
    the test scenes QA 15 named (bodies that only translate, rows with integer data)."""
    pages = dict(every_rendering)
    for name in ("arm_block", "block_incline", "cart_spring", "disk_pend", "driven_four_bar"):
        expl = explain(load_system(ROOT / "tests" / "data" / "multibody" / f"{name}.toml"))
        pages.update({(name, fmt): render(expl, fmt) for fmt in FORMATS})
    for (name, fmt), out in pages.items():
        for pattern in (TIMES_ZERO, POINT_ZERO):
            hit = pattern.search(out)
            assert hit is None, (name, fmt, out[max(0, hit.start() - 80):hit.end() + 20])
    crank = every_scene["slider_crank"][1].section("crank").step("euler")
    assert crank.equation("euler").right == 0
    assert "crank turns at a constant rate (alpha = 0), so I_O alpha = 0." in crank.text


# A force vector named by its own scalar with that scalar negated in a component ("A_x = (-A_x, 0)"),
# as each format writes the vector equation: text, LaTeX/Markdown (a column vector), HTML (MathML).
_SELF_NEGATED = {
    "text": re.compile(r"^ +([A-Za-z]\w*) = \((?:-\1, 0|0, -\1)\)$", re.MULTILINE),
    "markdown": re.compile(r"^(\S+) = \\begin\{pmatrix\}(?:- \1 \\\\ 0|0 \\\\ - \1)\\end\{pmatrix\}$", re.MULTILINE),
    "latex": re.compile(r"^(\S+) = \\begin\{pmatrix\}(?:- \1 \\\\ 0|0 \\\\ - \1)\\end\{pmatrix\}$", re.MULTILINE),
    "html": re.compile(r"<mstyle displaystyle=\"true\"><mrow>(<msub><mi>\w+</mi>(?:<mi>\w+</mi>|<mrow>.*?</mrow>)</msub>)"
                       r"</mrow><mo>=</mo><mrow><mrow><mo>\(</mo>(?:<mrow><mo>\u2212</mo>\1</mrow><mo>,</mo><mn>0</mn>|"
                       r"<mn>0</mn><mo>,</mo><mrow><mo>\u2212</mo>\1</mrow>)<mo>\)</mo>"),
}


def test_free_body_vectors_are_true_as_written(every_scene, every_rendering):
    """A reaction acting on a body against its positive sense (the second body's half of a joint's
    pair) is listed as the vector F_A_x = (-A_x, 0), not as A_x = (-A_x, 0), which is false unless
    A_x = 0 (QA 15 #5): in every format of every shipped scene no force vector is named by a scalar it
    negates. double_pendulum's upper link gets joint A's pair reversed: its list names F_A_x, F_A_y."""
    for name, (system, expl) in every_scene.items():
        for eq in (e for s in expl.steps() for e in s.equations if e.tag.startswith("force:")):
            components = [sp.sympify(c) for c in eq.rhs[0].expr]
            assert -sp.Symbol(eq.name) not in components, (name, eq.name, components)
        for fmt in FORMATS:
            assert _SELF_NEGATED[fmt].search(every_rendering[name, fmt]) is None, (name, fmt)
    text = every_rendering["double_pendulum", "text"]
    assert "F_A_x = (-A_x, 0)" in text and "F_A_y = (0, -A_y)" in text and "    A_x = (A_x, 0)" in text


def _latex_text_mode(doc: str) -> str:
    """A LaTeX document without its maths (``$...$`` and the equation environments) and comments:
    the text that LaTeX sets in text mode."""
    doc = re.sub(r"\\begin\{equation\*\}.*?\\end\{equation\*\}", "", doc, flags=re.DOTALL)
    doc = re.sub(r"(?<!\\)\$.*?(?<!\\)\$", "", doc)
    return re.sub(r"(?m)^%.*$", "", doc)


def test_latex_contact_sentences(every_rendering):
    """QA 15 #4, on incline_ring (its sticking regime rejected, then the impending slip): the units
    of the contact sentences upright after the number (``7.35499\\,\\mathrm{N}``, not the symbol N),
    the comparison inside the maths (a bare ``>`` in text prints as an inverted question mark in
    LaTeX's default OT1 encoding), "least mu = ...", and the slip in words in every format. No
    shipped scene's LaTeX has a bare < or > in text mode; the preamble sets T1 fonts and UTF-8."""
    tex = every_rendering["incline_ring", "latex"]
    assert (r"Rejected: incline sticking needs $|F| = 7.35499\,\mathrm{N} > \mu_{s} N = 6.36961\,\mathrm{N}$ "
            r"(least $\mu = 0.288675$).") in tex
    assert r"friction $F = -\mu_{k} N = -6.36961\,\mathrm{N}$" in tex
    html = every_rendering["incline_ring", "html"]
    assert ('<mn>7.35499</mn><mspace width="0.167em"/><mrow><mi mathvariant="normal">N</mi></mrow><mo>&gt;</mo>'
            in html)
    for fmt in FORMATS:
        out = every_rendering["incline_ring", fmt]
        minus = "\u2212" if fmt == "html" else "-"  # the HTML's minus sign
        assert (f"Rejected: incline starting to slip in the {minus} direction: the sliding at incline would accelerate "
                "in the + direction") in out
        assert "slip - (impending):" not in out and "least mu 0" not in out, fmt
    for name in SCENES:
        doc = every_rendering[name, "latex"]
        assert not re.search(r"[<>]", _latex_text_mode(doc)), name
        assert r"\usepackage[T1]{fontenc}" in doc and r"\usepackage{fontspec}" in doc and "beyond the Latin" not in doc


def test_slip_sign_is_not_a_name_a_scene_can_have(every_rendering):
    """QA 19 #10: incline_ring's coordinate is s, and the friction read "-s mu_k N" (s the sign of
    the sliding velocity), which is the position times mu_k N. The sign is written as the function
    sign(v_slip) in every format: applied in LaTeX (\\operatorname{sign}(v_{slip}), the argument
    outside the operator's name) and in MathML."""
    for fmt in FORMATS:
        out = every_rendering["incline_ring", fmt]
        assert not re.search(r"-s \\?mu", out) and "s the sign" not in out, fmt
    assert "known force -sign(v_slip) mu_k N along the contact line (v_slip the sliding velocity)" in \
        every_rendering["incline_ring", "text"]
    assert "[friction terms (slipping: -sign(v_slip) mu_k N)]" in every_rendering["incline_ring", "text"]
    assert r"$-\operatorname{sign}(v_{slip}) \mu_{k} N$" in every_rendering["incline_ring", "latex"]
    assert ('<mo form="prefix">\u2212</mo>' "<mrow><mi>sign</mi><mo>(</mo><msub><mi>v</mi><mi>slip</mi></msub><mo>)</mo></mrow>"
            "<msub><mi>&#956;</mi><mi>k</mi></msub><mi>N</mi>") in every_rendering["incline_ring", "html"]


def test_latex_escapes_angle_brackets_with_the_report_escape(tmp_path):
    """A scene name with <, > and letters beyond Latin (QA 15 #4): escaped in ``\\section*{...}`` by
    the project's one escape (the report's paper.tex uses the same function), and the document says
    which engine sets those letters."""
    from reports.make_report import latex_escape as report_escape
    from solver.notation import latex_escape

    assert report_escape is latex_escape
    scene = (ROOT / "data" / "scenes" / "sliding_bar.toml").read_text(encoding="utf-8")
    scene = scene.replace('name = "sliding_bar"', 'name = "<b>a > b</b> \u632f\u308a\u5b50"', 1)
    path = tmp_path / "angles.toml"
    path.write_text(scene, encoding="utf-8")
    out = render(explain(load_system(path), advice=False), "latex")
    assert (r"\section*{Worked solution: \textless{}b\textgreater{}a \textgreater{} b\textless{}/b\textgreater{} "
            "\u632f\u308a\u5b50}") in out
    assert not re.search(r"[<>]", _latex_text_mode(out))
    assert "compile it with\n% lualatex or xelatex" in out


def _state_values(system, state):
    vals = {k: sp.Float(v) for k, v in system.si_values().items()}
    vals.update({q: sp.Float(v) for q, v in zip(system.q, state.q)})
    vals.update({qd: sp.Float(v) for qd, v in zip(system.qd, state.qd)})
    vals[system.t] = sp.Float(state.t)
    return vals


def _solve_displayed(system, step, state, unknowns):
    """Solve the displayed equations of motion (and closure rows) at the state for ``unknowns``."""
    import numpy as np

    vals = _state_values(system, state)
    rows = [sp.expand(sp.sympify(e.residual).xreplace(vals)) for e in step.equations
            if e.tag.startswith(("eom:", "closure:"))]
    A = np.array([[float(r.coeff(u)) for u in unknowns] for r in rows])
    b = np.array([-float(r.xreplace({u: 0 for u in unknowns})) for r in rows])
    return dict(zip(map(str, unknowns), np.linalg.solve(A, b)))


def test_slipping_disk_equation_of_motion(every_scene):
    """disk_backspin slides forward with backspin: the shown equations of motion (the normal force
    from Newton along the normal, the friction -mu_k N substituted) give, at the state, the
    accelerations of the mass-centre formulation of the same regime solved numerically, and the
    closed form x'' = -mu g, phi'' = -2 mu g / r (hand derivation: m x'' = -mu m g; about the centre
    I phi'' = -r mu m g with I = m r^2/2). Tolerance 1e-9 relative: both are one linear solve in
    double precision (round-off ~1e-15)."""
    from solver.analyses.regimes import find_regime, regime_system, start_state
    from solver.formulations import formulate

    system, expl = every_scene["disk_backspin"]
    state = start_state(system)
    res = find_regime(system, state.q, state.qd, state.t)
    assert [c.regime.label for c in res.checks] == ["slip +"]
    variant = regime_system(system, res.regimes, state.q, state.qd, state.t)
    motion = expl.sections[-1].step("motion")
    assert "N" in str(motion.equation("from_newton:N").left)
    shown = _solve_displayed(variant, motion, state, [c.qdd for c in variant.free])
    numeric = formulate(variant, "mass_center").numeric().solve(state.q, state.qd, state.t)
    mu, g, r = 0.2, 9.80665, 0.1  # data/scenes/disk_backspin.toml
    for name, closed in (("x_ddot", -mu * g), ("phi_ddot", -2 * mu * g / r)):
        assert shown[name] == pytest.approx(float(numeric[name]), rel=1e-9)
        assert shown[name] == pytest.approx(closed, rel=1e-9)


@pytest.mark.parametrize("scene", ["four_bar", "slider_crank"])
def test_loop_closure_equation_of_motion(every_scene, scene):
    """The constrained form M q'' + ... - C^T lambda = Q, C q'' = gamma, as shown, solved at the state
    for every q'' and the closure multipliers: the same accelerations and multipliers (the closure
    joints' reactions) as the mass-centre formulation solved numerically (an independent set of
    equations: Newton with a_G, Euler about G). 1e-8 relative: two well-conditioned double-precision
    solves (condition numbers below 1e3) agree to ~1e-12."""
    from solver.analyses.instant import assemble
    from solver.formulations import formulate

    system, expl = every_scene[scene]
    state = assemble(system)
    motion = expl.sections[-1].step("motion")
    multipliers = [r.reaction.symbol for r in system.closure]
    assert multipliers and all(motion.equation(f"closure:{m}") for m in multipliers)
    shown = _solve_displayed(system, motion, state, [c.qdd for c in system.free] + multipliers)
    numeric = formulate(system, "mass_center").numeric().solve(state.q, state.qd, state.t)
    for name, value in shown.items():
        assert value == pytest.approx(float(numeric[name]), rel=1e-8, abs=1e-9), name


def test_four_bar_rocker_about_its_fixed_pivot(every_scene):
    """The rocker is placed through the coupler (its pin B), so the placement writes its pivot O4
    along the loop, still only where the closure holds. The pin O4 to the ground holds it: the
    worked solution shows r_O4 = (d, 0) (the ground point of data/scenes/four_bar.toml) with
    v_O4 = a_O4 = 0, and about O4 the moment equation written by hand for a bar of mass m4 and
    length c turning about a fixed end, with the pin force (B_x, B_y) on the rocker at B:

        -m4 g (c/2) cos(theta4) + c (B_y cos(theta4) - B_x sin(theta4)) = (m4 c^2 / 3) theta4''

    Moments about the fixed pivot remove the pivot's reactions O4_x, O4_y and, a_O4 being zero,
    there is no inertial term; the coupler's pin force remains: 3 unknowns, not the five
    (theta2'', theta3'' as well) that the loop-written a_O4 brought in. Exact comparisons."""
    system, expl = every_scene["four_bar"]
    a, b, c, d, m4, g = (sp.Symbol(n, real=True) for n in ("a", "b", "c", "d", "m4", "g"))
    th4, w4, al4 = sp.symbols("theta4 theta4_dot theta4_ddot", real=True)
    Bx, By, O4x, O4y = sp.symbols("B_x B_y O4_x O4_y", real=True)
    rocker = expl.section("rocker")
    kin = rocker.step("kinematics")
    assert list(kin.equation("pos:O4").left) == [d, 0]
    assert list(kin.equation("vel:O4").left) == [0, 0] and list(kin.equation("accel:O4").left) == [0, 0]
    euler = rocker.step("euler").equation("euler")
    assert not any("inertial" in t.note for t in euler.lhs)
    by_hand = -m4 * g * c / 2 * sp.cos(th4) + c * (By * sp.cos(th4) - Bx * sp.sin(th4)) - m4 * c**2 / 3 * al4
    assert sp.expand(euler.residual - by_hand) == 0
    unknowns = list(system.qdd) + [r.symbol for r in system.reactions]
    present = [u for u in unknowns if sp.expand(euler.residual).coeff(u) != 0]
    # by hand: O4_x, O4_y act through O4 (no moment), a_O4 = 0 leaves no theta2'', theta3''; the
    # coupler's pin force at B, a distance c from O4, remains with the rocker's own theta4''
    assert present == [al4, Bx, By]
    said = rocker.step("dropped").text[0]
    assert said == "The moment equation about O4 contains 3 unknowns: theta4_ddot, B_x, B_y."
    # Newton with a_G = alpha x r_G/O4 - omega^2 r_G/O4 (r_G/O4 = c/2 (cos, sin)): the rocker's own angle only
    nx = rocker.step("newton").equation("newton_x").residual
    assert sp.expand(nx - (Bx + O4x + m4 * c / 2 * (al4 * sp.sin(th4) + w4**2 * sp.cos(th4)))) == 0
    ny = rocker.step("newton").equation("newton_y").residual
    assert sp.expand(ny - (By + O4y - m4 * g - m4 * c / 2 * (al4 * sp.cos(th4) - w4**2 * sp.sin(th4)))) == 0
    assert not (a in sp.sympify(nx).free_symbols or b in sp.sympify(ny).free_symbols)
    # true equations, not only tidy ones: the mass-centre route's solution at the state satisfies
    # all three to 1e-9 of their largest term (two double-precision solves agree to ~1e-13)
    from solver.analyses.instant import assemble
    from solver.formulations import formulate

    state = assemble(system)
    numeric = formulate(system, "mass_center").numeric().solve(state.q, state.qd, state.t)
    vals = _state_values(system, state)
    vals.update({u: sp.Float(float(numeric[str(u)])) for u in unknowns})
    for eq in (euler, rocker.step("newton").equation("newton_x"), rocker.step("newton").equation("newton_y")):
        terms = [float(t.xreplace(vals)) for t in sp.Add.make_args(sp.expand(eq.residual))]
        assert abs(sum(terms)) <= 1e-9 * max(map(abs, terms)), eq.label


def test_four_bar_advisor_takes_the_rocker_about_its_fixed_pivot():
    """The advisor, on the same equations as the worked solution: about the rocker's O4 a_O4 = 0
    (fixed), and 3 unknowns (the rocker's angular acceleration and the coupler's pin force; the
    pivot's reactions drop out, see the test above)."""
    from solver.analyses.instant import assemble
    from solver.explain.advisor import advice_step

    system = load_system(ROOT / "data" / "scenes" / "four_bar.toml")
    step = advice_step(system, assemble(system))
    row = next(r for r in step.table.rows if r[:2] == ("rocker", "O4"))
    assert row[3] == "3" and row[4] == "theta4_ddot, B_x, B_y" and row[6] == "0 (fixed)"
    best = next(t for t in step.text if t.startswith("Best point of rocker:"))
    assert best.startswith("Best point of rocker: O4 — the moment equation about O4 holds 3 unknowns")
    assert "a_O4 = 0 (a fixed point)" in best


def test_four_bar_pin_to_the_ground_written_either_way(tmp_path):
    """The pivot pin spelled the other way round (``connects = ["rocker:O4", "ground:O4"]``: the
    rocker first) acts on the rocker at the rocker's own O4, so about O4 its moment equation holds
    the same 3 unknowns as above, and the solution is the same motion: the accelerations equal,
    the O4 reactions opposite in sign (a pin's reactions are the force on its second body, now the
    ground). Equal to round-off (1e-12): the same equations up to that sign."""
    from solver.analyses.instant import solve_instant

    text = (ROOT / "data" / "scenes" / "four_bar.toml").read_text()
    spelled = 'connects = ["ground:O4", "rocker:O4"]'
    assert text.count(spelled) == 1
    path = tmp_path / "four_bar_reversed.toml"
    path.write_text(text.replace(spelled, 'connects = ["rocker:O4", "ground:O4"]'))
    system = load_system(path)
    rocker = explain(system).section("rocker")
    assert rocker.step("dropped").text[0] == "The moment equation about O4 contains 3 unknowns: theta4_ddot, B_x, B_y."
    ours = solve_instant(system).unknowns
    shipped = solve_instant(load_system(ROOT / "data" / "scenes" / "four_bar.toml")).unknowns
    for name, value in shipped.items():
        sign = -1 if name.startswith("O4_") else 1
        assert ours[name].magnitude == pytest.approx(sign * value.magnitude, rel=1e-12, abs=1e-12), name


def test_suggest_point_in_the_contact_regime(capsys):
    """The advisor ranks points in the regime that holds at the state; for contacts that hold a
    body redundantly it says that no point separates their (indeterminate) forces."""
    from solver.__main__ import main

    assert main(["explain", str(ROOT / "data/scenes/incline_ring.toml"), "--suggest-point"]) == 0
    out = capsys.readouterr().out
    assert re.search(r"incline +slip \+", out) and "Best point: C" in out  # the ring slips down the incline
    assert main(["explain", str(ROOT / "data/scenes/crate_tipping.toml"), "--suggest-point"]) == 0
    out = capsys.readouterr().out
    assert "statically indeterminate" in out and "Best point" not in out


def test_suggest_point_in_every_format(solver_cli, tmp_path):
    """--suggest-point honours --format and the -o suffix like the worked solution: the ranking
    table is a Markdown table, an HTML table, a LaTeX tabular (the paper's Example 2 advice: P or C)."""
    scene = "data/scenes/disk_bar.toml"
    code, md, _ = solver_cli("explain", scene, "--suggest-point", "--format", "markdown")
    assert code == 0 and re.search(r"^\| body \| point \|", md, flags=re.M)
    code, _, _ = solver_cli("explain", scene, "--suggest-point", "-o", str(tmp_path / "advice.tex"))
    tex = (tmp_path / "advice.tex").read_text()
    assert code == 0 and tex.startswith("\\documentclass") and "\\begin{tabular}" in tex
    code, page, _ = solver_cli("explain", scene, "--suggest-point", "--format", "html")
    assert code == 0 and "<table><tr><th>body</th><th>point</th>" in page
    assert re.search(r"Best point: [PC] ", page)


def test_html_worked_solution_style_sheet_is_valid(solver_cli):
    """The style sheet is a sequence of ``selector{declarations}`` rules with balanced braces (a
    doubled brace, as an f-string's escape left in a plain string, ends the sheet after its first
    rule in a browser): the embedded maths font for every ``<math>``, equations in blocks that scroll
    sideways by themselves when longer than the page, bordered tables, and each free-body diagram
    drawn at the page's width (its own 331 pt made its labels smaller than the text)."""
    code, page, _ = solver_cli("explain", "data/scenes/sliding_bar.toml", "--format", "html")
    assert code == 0
    css = re.search(r"<style>(.*?)</style>", page, flags=re.S).group(1)
    rules = re.findall(r"\s*([^{}]+)\{([^{}]*)\}", css)
    assert "".join(f"{sel}{{{body}}}" for sel, body in rules).replace(" ", "") == re.sub(r"\s", "", css)
    declared = {sel.strip(): body.replace(" ", "") for sel, body in rules}
    assert 'font-family:"AltEulerMath",math' in declared["math"] and "data:font/woff;base64," in declared["@font-face"]
    assert "overflow-x:auto" in declared[".eq"] and "border:" in declared["td,th"]
    assert "width:100%" in declared["figure.fbd svg"] and "height:auto" in declared["figure.fbd svg"]


def _latex_maths(doc: str) -> list[str]:
    """The maths of a LaTeX document: each equation* block and each inline $...$, with the text of
    every \\text{...} (words, which may name a scene's element) taken out."""
    blocks = re.findall(r"\\begin\{equation\*\}(.*?)\\end\{equation\*\}", doc, re.S)
    prose = re.sub(r"\\begin\{equation\*\}.*?\\end\{equation\*\}", "", doc, flags=re.S).replace(r"\$", "")
    assert prose.count("$") % 2 == 0
    out = []
    for m in blocks + re.findall(r"\$([^$]*)\$", prose):
        while (bare := re.sub(r"\\text\{(?:[^{}]|\{[^{}]*\})*\}", "", m)) != m:
            m = bare
        out.append(m)
    return out


def test_latex_writes_names_units_and_formulae_as_latex(every_scene, every_rendering):
    """New-user report: units were code (``ft / s ** 2``), names were code (``theta_ddot``), notes in
    \\text{} held code, and the unknowns were theta_ddot in the text but alpha in the equations. The
    LaTeX now has no ``**`` or ``_ddot`` anywhere, no ``*`` in maths, balanced braces, units upright,
    and one sentence saying what alpha stands for."""
    for name in every_scene:
        doc = every_rendering[name, "latex"]
        assert "**" not in doc and "_ddot" not in doc and "_dot" not in doc, name
        unescaped = re.sub(r"\\[{}$]", "", doc)
        assert unescaped.count("{") == unescaped.count("}"), name
        # (an element's name in its weight's subscript keeps its underscores, as the force list spells it)
        code = [m for m in _latex_maths(doc) if "*" in m or r"\_" in re.sub(r"W_\{\w+\.[\w\\]+\}", "", m)
                or "textasciicircum" in m]
        assert not code, (name, code[:2])
    example1 = every_rendering["sliding_bar", "latex"]
    assert r"$g$ & $32.174\,\mathrm{ft/s^{2}}$" in example1  # the data table: 32.174 ft/s^2
    assert r"contains 2 unknowns: $\ddot{\theta}$, $R_{B}$." in example1
    assert r"$\alpha$ & $2.29693$ & $\mathrm{rad/s^{2}}$" in example1  # Eq. 30's alpha, unit upright
    assert example1.count(r"Here $\alpha = -\ddot{\theta}$") == 1  # said once, where alpha first stands in
    assert r"\underbrace{- 0.05081 \alpha}_{\text{$\alpha$}}" in example1
    assert r"_{\text{rate terms $\dot{\theta}^{2}$}}" in example1
    example2 = every_rendering["disk_bar", "latex"]
    assert r"$m_{d}$ & $m_{d}\,r_{d}^{2}/2$" in example2  # I_G of the disk, no * or **
    assert r"[$\mathrm{N\,m}$]" in example2
    slipping = every_rendering["disk_backspin", "latex"]  # words stay words, formulae become maths
    assert r"known force $-\operatorname{sign}(v_{slip}) \mu_{k} N$ along the contact line ($v_{slip}$ the sliding velocity)" in slipping
PENDULUM = """name = "pendulum"
[parameters]
m = "2 kg"
L = "0.8 m"
g = "9.81 m/s^2"
[coordinates]
theta = { value = "THETA", rate = "1 rad/s" }
[ground.points]
O = ["0", "0"]
[[bodies]]
name = "bar"
orientation = "theta - pi/2"
points = { O = ["0", "0"], E = ["L", "0"] }
elements = [{ kind = "slender_bar", mass = "m", from = "O", to = "E" }]
[[joints]]
kind = "pin"
name = "O"
connects = ["ground:O", "bar:O"]
[[loads]]
kind = "gravity"
g = "g"
"""


def _pendulum(tmp_path, theta="0 deg"):
    path = tmp_path / "pendulum.toml"
    path.write_text(PENDULUM.replace("THETA", theta), encoding="utf-8")
    return load_system(path)


def _euler_column(step):
    return {row[0]: row[3] for row in step.table.rows}


def test_dropped_unknowns_at_the_state_agree_with_the_advisor(tmp_path, every_scene):
    """A hanging pendulum (theta = 0) about its tip E: O_y's line of action passes through E at
    this state only (its moment coefficient is -L sin theta). The step on the dropped unknowns, the
    point advisor and the equations with the data entered make one decision: 2 unknowns here,
    O_y's coefficient vanishing at this state and not identically. At theta = 30 deg O_y stays."""
    from solver.analyses.instant import assemble
    from solver.explain import rank_points

    system = _pendulum(tmp_path)
    expl = explain(system, "E")
    step = expl.section("bar").step("dropped")
    advisor = {c.name: c for c in rank_points(system, "bar", assemble(system))}["E"]
    assert advisor.unknowns == ["theta_ddot", "O_x"]
    assert _euler_column(step) == {"O_x": "yes", "O_y": "no, at this state"}
    assert "3 unknowns in general" in step.text[0] and "2 at this state (theta_ddot, O_x)" in step.text[0]
    assert any("O_y" in t and "at this state only" in t for t in step.text)
    numbers = expl.sections[-1].step("numbers").equation("numbers:bar:euler")
    assert {t.note for t in numbers.lhs} == {"alpha", "O_x"}
    moved = explain(_pendulum(tmp_path, "30 deg"), "E").section("bar").step("dropped")
    assert _euler_column(moved) == {"O_x": "yes", "O_y": "yes"}
    # the crate at rest, held redundantly (no advisor ranking): F_B's line passes through A at theta = 0
    crate = every_scene["crate_tipping"][1].section("crate").step("dropped")
    assert _euler_column(crate) == {"F_A": "no", "N_A": "no", "F_B": "no, at this state", "N_B": "yes"}


@pytest.mark.parametrize("scene,body,name", [("wheel_on_incline", "body", "C_rolling_hoop"),
                                             ("drum_and_block", "drum", "C_cord")])
def test_a_joint_place_is_named_after_its_joint_and_accepted_by_point(scene, body, name):
    """The place where a joint acts and the scene names no point (the hoop's contact point, the
    drum's cord tangent point) is named C_<joint>, said what it is, and, as the advisor's choice
    for the hoop, taken by --point: the moment equation about it gives the same answers as the
    mass-centre form (round-off only: a relative difference under 1e-9, far above double
    precision's 1e-16 and far below any real disagreement)."""
    from solver.analyses.instant import assemble
    from solver.explain import rank_points

    system = load_system(ROOT / "data" / "scenes" / f"{scene}.toml")
    ranked = rank_points(system, body, assemble(system))
    assert name in {c.name for c in ranked} and not any(c.name.startswith("X") for c in ranked)
    if scene == "wheel_on_incline":
        assert ranked[0].name == name and ranked[0].origin == "point of its joint"
    expl = explain(system, f"{body}:{name}")
    assert expl.points[body] == name
    kinematics = " ".join(expl.section(body).step("kinematics").text)
    assert f"{name} is the point of {body} where joint {name[2:]} acts" in kinematics
    check = expl.sections[-1].step("check").table.rows
    assert all(float(row[4]) < 1e-9 for row in check), check


def test_a_crossing_the_advisor_lists_is_accepted_by_point(solver_cli, tmp_path):
    """QA round 9 item 13: the advisor lists I(O_x,A_y), the place where two reactions' lines of
    action cross, and --point BODY:I(O_x,A_y) takes moments about it, explained in the advisor's
    words. Reference by hand for the upper bar of the double pendulum (O = (0, 0), A = L1 (sin th1,
    -cos th1)): O_x acts along x through O and A_y along y through A, so they cross at
    (L1 sin th1, 0), where the moment equation holds th1_ddot, O_y and A_x; O_y and A_x cross at
    (0, -L1 cos th1), leaving th1_ddot, O_x and A_y. Positions to 1e-12 m (a 2x2 solve of numbers
    below 1: round-off ~1e-16); the answers about the crossing agree with the mass-centre form to
    1e-9 relative, as in the test above."""
    import math

    from solver.analyses.instant import assemble
    from solver.explain import rank_points

    scene = ROOT / "tests" / "data" / "multibody" / "two_bar.toml"
    th1, L1 = math.radians(20.0), 0.6
    expected = {("O_x", "A_y"): ((L1 * math.sin(th1), 0.0), {"th1_ddot", "O_y", "A_x"}),
                ("O_y", "A_x"): ((0.0, -L1 * math.cos(th1)), {"th1_ddot", "O_x", "A_y"})}
    system = load_system(scene)
    ranked = {c.name: c for c in rank_points(system, "upper", assemble(system))}
    for (first, second), (at, held) in expected.items():
        name = f"I({first},{second})"
        assert ranked[name].origin == f"intersection of the lines of action of {first} and {second}"
        assert ranked[name].position == pytest.approx(at, abs=1e-12)
        assert set(ranked[name].unknowns) == held
        expl = explain(load_system(scene), f"upper:{name}")
        assert expl.points["upper"] == name
        kinematics = " ".join(expl.section("upper").step("kinematics").text)
        assert (f"{name} is the point of upper (the body extended) where the lines of action of {first} and "
                f"{second} cross at this instant") in kinematics
        euler = _euler_column(expl.section("upper").step("dropped"))
        assert {r for r, v in euler.items() if v == "yes"} == held - {"th1_ddot"}
        check = expl.sections[-1].step("check").table.rows
        assert all(float(row[4]) < 1e-9 for row in check), check
    # the page with its drawings (an instant point of the body is drawn where it is at the state)
    code, _, err = solver_cli("explain", str(scene), "--point", "upper:I(O_x,A_y)", "-o", str(tmp_path / "w.html"))
    assert code == 0, err
    # two lines of action that do not cross: one line naming the flag, exit 2
    code, out, err = solver_cli("explain", str(scene), "--point", "upper:I(O_x,A_x)")
    assert code == 2 and not out and err.count("\n") == 1
    assert "--point upper:I(O_x,A_x): the lines of action of O_x and A_x are parallel" in err


def test_no_negative_zero_in_the_results(every_scene):
    """A zero prints as 0, never -0 (the crate at rest: x_ddot, theta_ddot; the guide's moment of
    drum_and_block; solve prints 0 too): every table cell of every shipped scene's explanation."""
    zeros = 0
    for name, (_, expl) in every_scene.items():
        for step in expl.steps():
            for row in (step.table.rows if step.table is not None else ()):
                for cell in row:
                    assert not re.fullmatch(r"-0(\.0*)?( .*)?", cell), (name, step.title, row)
                    zeros += cell == "0"
    solution = {r[0]: r[1] for r in every_scene["crate_tipping"][1].sections[-1].step("solution").table.rows}
    assert solution["x_ddot"] == solution["theta_ddot"] == "0"
    assert zeros > 0


def test_check_prints_values_equal_to_print_precision_equal(tmp_path):
    """The mass-centre check prints two values that agree to round-off alike, even when they
    straddle a rounding boundary of the 6 figures shown (159.41249999999997 and the next double
    above 159.4125 print 159.412 and 159.413 with '.6g'): one more digit is shown. Values that
    really differ keep 6 figures and print different."""
    import math

    from solver.cli_common import format_pair

    low = math.nextafter(159.4125, 0.0)
    high = math.nextafter(159.4125, 1e9)
    assert (f"{low:.6g}", f"{high:.6g}") == ("159.412", "159.413")  # the trap this guards against
    x, y = format_pair(low, high)
    assert x == y and x.startswith("159.412")
    assert format_pair(1.0, 1.1) == ("1", "1.1")
    assert format_pair(-0.0, 0.0) == ("0", "0")
    assert format_pair(63.7178, 63.7178 * (1 + 4.5e-16)) == ("63.7178", "63.7178")
    # the pendulum about its tip at 30 deg: both routes agree to ~4e-16, and print alike
    rows = explain(_pendulum(tmp_path, "30 deg"), "E").sections[-1].step("check").table.rows
    assert all(row[1] == row[2] for row in rows), rows


LOADS = (PENDULUM + """[[loads]]
kind = "spring"
between = ["ground:S", "bar:E"]
stiffness = "k"
free_length = "L0"
[[loads]]
kind = "damper"
between = ["ground:S", "bar:E"]
coefficient = "c"
""").replace('O = ["0", "0"]\n[[bodies]]', 'O = ["0", "0"]\nS = ["L", "-L"]\n[[bodies]]').replace(
    'g = "9.81 m/s^2"', 'g = "9.81 m/s^2"\nk = "50 N/m"\nL0 = "0.2 m"\nc = "3 N*s/m"').replace("THETA", "30 deg")


def test_no_collected_form_longer_than_its_equation_and_short_table_cells(tmp_path):
    """A spring and a damper between the ground and the bar's tip: collecting the moment
    equation by unknown spreads their long moments over the coefficients (the collected known
    side ran to 2000 characters), so it is not shown, and the step says so; the free-body table
    refers to the force's vector instead of a 500-character cell. The paper's Example 1 keeps its
    collected form (Eq. 28, test_eq28_is_the_collected_moment_equation_as_printed)."""
    from solver.explain.build import MAX_CELL

    path = tmp_path / "loads.toml"
    path.write_text(LOADS, encoding="utf-8")
    assert 'S = ["L", "-L"]' in LOADS and "kind = \"spring\"" in LOADS
    expl = explain(load_system(path), "O")  # about the pivot: the spring's and damper's moments stay
    euler = expl.section("bar").step("euler")
    assert [e.tag for e in euler.equations] == ["inertia", "euler"]
    assert any("not shown collected" in t for t in euler.text)
    table = expl.section("bar").step("fbd").table
    assert all(len(cell) <= MAX_CELL for row in table.rows for cell in row), table.rows
    assert {row[0]: row[3] for row in table.rows}["spring_2"] == "the vector spring_2 above"


def test_wording_citations_and_grammar(paper, every_scene, every_rendering):
    """The kinematics cite the paper's numbering: its Eq. (6) is the acceleration relation
    a_G = a_P + alpha x r - omega^2 r and its Eq. (15) the same for an element's mass centre; it
    prints no velocity relation, and a_P from the placement is no equation of it. A one-body
    scene's advisor does not speak of other bodies; the slipping friction is not called a
    configuration term; counts agree with their nouns (no "unknown(s)", "give(s)")."""
    from solver.explain.advisor import advice_explanation

    # the paper as printed: (6) a_G = a_P + alpha x r_G/P - omega^2 r_G/P (the text then gets a_Q "via
    # Eq. (6)"); (15) a-bar_k = a_p + alpha x (r-bar_k - r_p) - omega^2 (r-bar_k - r_p); no velocity relation
    kinematics = paper[2]["sliding_bar"].section("body").step("kinematics")
    refs = {e.tag: e.ref for e in kinematics.equations}
    assert refs["vel:A"] == refs["accel:A"] == refs["vel:B"] == refs["vel:G"] == ""
    assert refs["accel:B"] == refs["accel:G"] == "Eq. (6)" and refs["midpoint:G"] == "Eq. (16)"
    one_body = render(advice_explanation(load_system(ROOT / "data/scenes/incline_disk.toml")), "text")
    assert "other bodies" not in one_body and "holds 2 unknowns" in one_body
    eom = every_scene["disk_backspin"][1].sections[-1].step("motion")
    notes = {t.note: sp.sstr(t.expr) for e in eom.equations if e.tag.startswith("eom:") for t in e.lhs}
    assert "mu" in notes["friction terms (slipping: -sign(v_slip) mu_k N)"] and "configuration terms" not in notes
    for name in every_scene:
        out = every_rendering[name, "text"]
        assert "(s)" not in out, (name, out[out.index("(s)") - 80:out.index("(s)") + 20])
    assert "(s)" not in render(advice_explanation(load_system(ROOT / "data/scenes/sliding_bar.toml")), "text")


def test_html_joins_a_negative_term_with_minus_and_keeps_labels(paper):
    """In HTML as in text: a negative term after the first reads "- R_B l_b (...)", never
    "+ -R_B..." (Example 1's moment about A), and a one-term side keeps its label when the
    equation has two labelled terms (the data-entered rows: "... [R_B] = 21.65 [known]"). In
    MathML: a term's row holds its sign in a cell of its own, and no term after it starts with a
    minus; on one line, no "+" or "-" is followed by a term's own minus."""
    from solver.mathml import mathml_text

    out = render(paper[2]["sliding_bar"], "html")
    assert not re.search(r"<mo>[+\-\u2212]</mo>(?:<mrow>)*<mo>[\-\u2212]</mo>", out)
    tables = "".join(re.findall(r'<table class="terms">(.*?)</table>', out))
    rows = re.findall(r"<tr><td>(.*?)</td><td>(.*?)</td><td>(.*?)</td><td>(.*?)</td></tr>", tables)
    signs = [mathml_text(sign) for _, sign, _, _ in rows]
    assert rows and set(signs) <= {"", "=", "+", "\u2212", "\u2248"}, set(signs)  # minus as U+2212
    terms = {sign: [] for sign in signs}
    for (_, _, term, _), sign in zip(rows, signs):
        terms[sign].append(re.sub(r"<math[^>]*><mstyle displaystyle=\"true\">", "", term))
    assert not any(t.startswith((f"<mo>{m}</mo>", f"<mrow><mo>{m}</mo>")) for m in "-\u2212"
                   for s in "+\u2212" for t in terms.get(s, []))
    assert any(t.startswith("<mrow><msub><mi>R</mi><mi>B</mi></msub><mo>&InvisibleTimes;</mo><msub><mi>l</mi>")
               for t in terms["\u2212"]), terms["\u2212"]
    assert any('<span class="note">[known]</span>' == note for *_, note in rows)
    text = render(paper[2]["sliding_bar"], "text")
    assert "[known]" in text  # the text shows the same labels


def test_html_typesets_every_equation_name_and_formula_as_mathml(every_scene, every_rendering):
    """New-user report: the HTML printed the equations as code (``l_b**2*m_b/12``, ``theta_ddot``)
    while Markdown and LaTeX typeset them. Now, for every shipped scene, the page's visible text
    (outside the MathML, the style sheet and the drawings) has no ``**``, no ``a*b`` and no
    ``_dot``/``_ddot`` name, and each equation block is MathML with the rates as accents."""
    for name in every_scene:
        page = every_rendering[name, "html"]
        body = re.sub(r"<style>.*?</style>|<svg.*?</svg>|<math.*?</math>", "", page, flags=re.S)
        text = re.sub(r"<[^>]+>", " ", body)
        assert not re.search(r"\*\*|\w\*\w|_d?dot\b", text), (name, re.findall(r"\S*(?:\*|_d?dot)\S*", text)[:5])
        blocks = re.findall(r'<div class="eq">(.*?)</div>', page, flags=re.S)
        assert blocks and all(b.startswith(("<math", '<table class="terms">')) for b in blocks), name
    page = every_rendering["sliding_bar", "html"]
    assert '<mover accent="true"><mi>&#952;</mi><mo>&#168;</mo></mover>' in page  # theta with two dots
    # a table cell: a number in e-notation as 1.5 x 10^-3, its unit after it unescaped, words escaped
    from solver.explain.mathml_prose import MathmlProse

    cell = MathmlProse([], {}).cell("1.5e-3 ft / s ** 2")
    assert cell.endswith("</math>&#8201;ft/s<sup>2</sup>") and "<mn>10</mn><mn>-3</mn>" in cell, cell
    assert MathmlProse([], {}).text("a_A <b>").endswith(" &lt;b&gt;")


@pytest.mark.parametrize("scene", ["rocking_semicircle", "disk_backspin"])
def test_solution_prints_the_exact_condition_number_in_a_contact_regime(solver_cli, scene):
    """README: the condition number is one quantity, `solve` prints a cheap estimate of it (a lower
    bound) and `explain` its exact value. With a contact (the semicircle's also has a joint limit,
    its rim) explain took solve's estimate (2.53 for the rocking semicircle, 1.15 for the disk) and
    called it the condition number; it prints `precision`'s exact value now (3.79, 1.49), to the
    3 figures it shows. A regime whose sticking contacts hold the body redundantly has a singular
    matrix: said in words, not as "condition number inf"."""
    import json

    path = f"data/scenes/{scene}.toml"
    code, out, err = solver_cli("precision", path, "--json")
    assert code == 0, err
    exact = json.loads(out)["condition_number"]
    code, out, err = solver_cli("solve", path, "--json")
    estimate = json.loads(out)["condition_number_estimate"]
    assert f"{exact:.3g}" != f"{estimate:.3g}"  # the two are told apart at the printed precision
    code, text, err = solver_cli("explain", path)
    assert code == 0, err
    assert f"(condition number {exact:.3g})" in text, re.findall(r"\(condition number [^)]*\)", text)
    code, text, err = solver_cli("explain", "data/scenes/crate_tipping.toml")
    assert "condition number inf)" not in text and "singular, its condition number infinite" in text


def test_what_alpha_stands_for_is_said_once_by_the_content(paper):
    """The sentence saying that alpha stands for -theta_ddot (Example 1: alpha = -theta_ddot, the
    bar turning clockwise as theta grows) is part of the content, in the first step whose equations
    write theta_ddot as alpha (the collected moment equation, Eq. 28), not made up by each renderer:
    every format shows the one sentence of the content, once."""
    import html

    from solver.mathml import mathml_text

    expl = paper[2]["sliding_bar"]
    said = [(s.kind, t) for s in expl.steps() for t in s.text if t.startswith("Here alpha")]
    assert said == [("euler", "Here alpha = -theta_ddot, the angular acceleration of body (k component, "
                              "counter-clockwise positive): the moment equation collected below and the "
                              "equations with the data entered write the unknown theta_ddot as alpha; the "
                              "other equations keep theta_ddot.")]
    assert render(expl, "text").count(said[0][1]) == 1
    assert render(expl, "latex").count(r"Here $\alpha = -\ddot{\theta}$, the angular acceleration") == 1
    assert render(expl, "markdown").count(r"Here alpha = -theta\_ddot, the angular acceleration") == 1
    page = html.unescape(mathml_text(render(expl, "html")))
    assert page.count("Here \u03b1=\u2212\u03b8\u00a8, the angular acceleration") == 1  # (HTML's minus sign)
    # a scene whose equations never write alpha for q'' (two coordinates) says nothing of it
    double = explain(load_system(ROOT / "data" / "scenes" / "double_pendulum.toml"), advice=False)
    assert not any(t.startswith("Here alpha") for s in double.steps() for t in s.text)


def test_data_entered_and_dropped_unknowns_make_one_decision(tmp_path):
    """The equations with the data entered used a cut-off of their own (1e-12 absolute, in output
    units) to call a coefficient zero, the dropped-unknowns step and the advisor another (1e-9 of
    the body's largest coefficient). The hanging pendulum at theta = 1e-9 deg about its tip E: O_y's
    moment coefficient -L sin(theta) is 1.4e-11 m, below the shared cut-off (L = 0.8 m, the largest
    coefficient about 1) and above the other. Both steps now say that the moment equation holds
    theta_ddot and O_x only; Newton y (O_y, theta_ddot) keeps O_y."""
    system = _pendulum(tmp_path, "1e-9 deg")
    expl = explain(system, "E", advice=False)
    assert _euler_column(expl.section("bar").step("dropped")) == {"O_x": "yes", "O_y": "no, at this state"}
    numbers = expl.sections[-1].step("numbers")
    assert {t.note for t in numbers.equation("numbers:bar:euler").lhs} == {"alpha", "O_x"}
    assert "O_y" in {t.note for t in numbers.equation("numbers:bar:newton_y").lhs}


def test_the_data_table_writes_each_unit_as_the_scene_does():
    """Regression: the parameters were printed by pint's default format, its factors sorted by
    name and spaced: ``kt 4.0 m * N``, ``g 9.81 m / s ** 2`` for the scene's "4 N*m" and
    "9.81 m/s^2". The text table now writes ``4 N*m`` and ``9.81 m/s**2``, as the solution's
    own units are written (rad/s**2)."""
    text = render(explain(load_system(ROOT / "tests/data/multibody/pendulum_loads.toml"), advice=False), "text")
    rows = {line.split()[0]: " ".join(line.split()[1:]) for line in
            text.split("Data and state", 1)[1].split("State", 1)[0].splitlines()[3:] if line.strip()}
    assert rows["kt"] == "4 N*m" and rows["ct"] == "0.5 N*m*s" and rows["g"] == "9.81 m/s**2"
    assert rows["c"] == "3 N*s/m" and rows["m"] == "2 kg"


def test_a_flag_in_the_prose_is_text_to_type_and_a_long_name_keeps_its_space():
    """New-user report: the sentence naming the contact point's flag was typeset as maths, ``--point``
    then C with the subscript "contact" (not text a user can type), and ``v_{C contact}`` lost its
    space (LaTeX's maths drops it: "Ccontact") beside a note's ``r_{C\\_contact/P}``."""
    system = load_system(ROOT / "data" / "scenes" / "incline_disk.toml")
    expl = explain(system)
    latex, page = render(expl, "latex"), render(expl, "html")
    assert r"\texttt{--point C\_incline}" in latex and "<code>--point C_incline</code>" in page
    assert r"v_{C\ incline}" in latex and r"r_{C\ incline/C}" in latex
    assert r"C\_incline/" not in latex.replace(r"\texttt{--point C\_incline}", "")


def test_a_scenes_name_and_description_stay_text_in_latex_and_html(tmp_path):
    """QA 21 #9: the README says scene names stay escaped text, but the name and description went
    through the prose-to-maths conversion: a title "theta_dot = 2 rad/s, alpha_max?" became a dotted
    theta and alpha with a subscript, and "src=x" became src with a maths "= x". Expected, written by
    hand: each character as typed, only escaped (LaTeX's _ as \\_, HTML's & as &amp;)."""
    name, description = "Hibbeler 17-94: theta_dot = 2 rad/s, alpha_max?", "Find R_x & m*g when src=x"
    source = (ROOT / "data" / "scenes" / "compound_pendulum.toml").read_text(encoding="utf-8")
    source = re.sub(r'(?m)^name = .*$', f'name = "{name}"', source, count=1)
    source = re.sub(r'(?m)^description = .*$', f'description = "{description}"', source, count=1)
    path = tmp_path / "named.toml"
    path.write_text(source, encoding="utf-8")
    expl = explain(load_system(path))
    latex, page = render(expl, "latex"), render(expl, "html")
    tex_name = r"Hibbeler 17-94: theta\_dot = 2 rad/s, alpha\_max?"
    assert f"\\section*{{Worked solution: {tex_name}}}" in latex
    assert f"Scene {tex_name}; moments about body: O." in latex
    assert r"Find R\_x \& m*g when src=x" in latex
    assert f"<h1>Worked solution: <bdi>{name}</bdi></h1>" in page  # (<bdi>: the minus rule leaves it, QA 22 #8)
    assert f"<p>Scene <bdi>{name}</bdi>; moments about body: " in page
    assert "<p><bdi>Find R_x &amp; m*g when src=x</bdi></p>" in page


def test_a_joint_point_inside_a_subscript_stays_in_it_in_latex_and_html():
    """QA 21 #3: about C_incline the prose ``M_C_incline - r_G/C_incline x m a_C_incline = ...`` was
    typeset as ``$r_{G/C}$\\_incline $x m a_{C incline} ...$``: the subscript ended before
    ``_incline``, which followed as text, the cross product x became the variable x, and
    ``a_{C incline}`` lost its space. Expected, by the convention of the equations' own labels
    (``r_{C\\ incline/C}``): the whole point name in the subscript, words apart, and a cross."""
    expl = explain(load_system(ROOT / "data" / "scenes" / "incline_disk.toml"), "C_incline")
    latex, page = render(expl, "latex"), render(expl, "html")
    assert r"$M_{C\ incline} - r_{G/C\ incline} \times m a_{C\ incline} = I_{C\ incline} \alpha$" in latex
    assert r"\_incline" not in latex.replace(r"\texttt{--point C\_incline}", "")
    assert "</math>_incline" not in page and "<mi>x</mi>" not in page
    r_g_c = "<msub><mi>r</mi><mrow><mi>G</mi><mo>/</mo><mi>C incline</mi></mrow></msub>"
    assert f"{r_g_c}<mo>\u00d7</mo><mi>m</mi>" in page.replace("<mo>&#8290;</mo>", "")


def test_an_unknown_that_drops_out_for_the_parameter_values_is_not_said_to_at_this_state_only(tmp_path):
    """A bar pinned at its end O, moments about K at c = 2L/3 from O (its centre of percussion:
    I_K = m L^2/9 and the inertial term's alpha part -r_G/K x m (alpha k x r_K/O) = +m L^2/9 alpha
    cancel). With c a parameter of its own, theta_ddot's coefficient vanishes for the scene's values
    and at every state, not identically and not because of the state: the text says which."""
    text = PENDULUM.replace("THETA", "30 deg").replace('L = "0.8 m"', 'L = "0.9 m"\nc = "0.6 m"')
    text = text.replace('E = ["L", "0"] }', 'E = ["L", "0"], K = ["c", "0"] }')
    path = tmp_path / "percussion.toml"
    path.write_text(text, encoding="utf-8")
    step = explain(load_system(path), "K").section("bar").step("dropped")
    said = [t for t in step.text if t.startswith("theta_ddot drops out")]
    assert len(said) == 1 and "for the scene's parameter values, at every state" in said[0], step.text
    assert "at this state only" not in said[0]


@pytest.mark.parametrize("scene,point", [("sliding_bar", "G"), ("slider_crank", "G"), ("incline_disk", None)])
def test_configuration_terms_hold_neither_accelerations_nor_a_zero(scene, point, capsys):
    """The equation of motion's configuration terms are what is left once the acceleration (and
    kept reaction) terms are taken out. They were left with the difference between an acceleration
    coefficient and its tidy form (sin**2 + cos**2 - 1 times it), printed phi_ddot among the
    configuration terms (slider_crank about G), an unreduced (1 - cos(beta)**2)/sin(beta)**2
    (sliding_bar about G) and '+ 0' (incline_disk)."""
    from solver.__main__ import main

    assert main(["explain", f"data/scenes/{scene}.toml"] + (["--point", point] if point else [])) == 0
    rows = [x.strip() for x in capsys.readouterr().out.splitlines() if x.endswith("[configuration terms]")]
    assert rows
    for row in rows:
        assert "_ddot" not in row and row != "+ 0    [configuration terms]"
    if scene == "sliding_bar":  # gravity's moment alone: g m_b (l_b/2) cos(theta), as about A (Eq. 29)
        assert rows == ["+ g*l_b*m_b*cos(theta)/2    [configuration terms]"]


@pytest.mark.parametrize("length, per_metre", [(None, 1.0), ("ft", 1 / 0.3048)])
def test_a_moment_equation_divided_by_a_mass_times_a_length_is_an_acceleration(tmp_path, length, per_metre):
    """QA 12 #5. The double pendulum's lower link about its pin A (bob m2 at B, A to B = l2):
    m2 l2 (l1 cos(th1 - th2) th1'' + l2 th2'') = -m2 g l2 sin th2. Divided by m2 l2 it reads
    l1 cos(th1 - th2) th1'' + l2 th2'' = -g sin th2, an acceleration: m/s**2, or ft/s**2 when the
    scene prints lengths in feet (it was labelled N*m). Reference: that closed form at the scene's
    th1 = 30 deg, th2 = 10 deg, l1 = l2 = 1 m, g = 9.80665 m/s**2; the numbers are printed to 4
    significant figures, hence rtol 5e-4."""
    import math

    text = (ROOT / "data" / "scenes" / "double_pendulum.toml").read_text(encoding="utf-8")
    if length:
        text += f'\n[output_units]\nlength = "{length}"\n'
    path = tmp_path / "double_pendulum.toml"
    path.write_text(text, encoding="utf-8")
    expl = explain(load_system(path), advice=False)
    row = expl.sections[-1].step("numbers").equation("numbers:lower:euler")
    assert "divided by m2 l2" in row.label
    assert row.label.endswith(f"[{length or 'm'}/s**2]")
    rhs = float(sum(t.expr for t in row.rhs))
    assert rhs == pytest.approx(-9.80665 * math.sin(math.radians(10)) * per_metre, rel=5e-4)
    lhs = {t.note: float(t.expr.as_coeff_Mul()[0]) for t in row.lhs}
    assert lhs["theta1_ddot"] == pytest.approx(math.cos(math.radians(20)) * per_metre, rel=5e-4)


def test_suggest_point_refuses_a_bad_point_as_explain_does(solver_cli, tmp_path):
    """QA 12 #11: ``--suggest-point --point Z`` printed the advice and exited 0, while ``--point Z``
    alone is refused. Both now give the same one line naming --point (the bar's points are A, B, G
    in the scene file), exit 2, nothing on standard output and no file written; a good point
    still gives the advice."""
    scene = "data/scenes/sliding_bar.toml"
    lines = []
    for extra in ((), ("--suggest-point",), ("--suggest-point", "-o", str(tmp_path / "advice.txt"))):
        code, out, err = solver_cli("explain", scene, *extra, "--point", "Z")
        assert code == 2 and out == "" and err.count("\n") == 1, extra
        lines.append(err)
    assert len(set(lines)) == 1 and "--point Z" in lines[0] and "(points: A, B, G;" in lines[0]
    assert "G_<element>, C_<joint>, I(R1,R2)" in lines[0]  # QA 13 #8: the advisor's points named too
    assert not (tmp_path / "advice.txt").exists()
    code, out, _ = solver_cli("explain", scene, "--suggest-point", "--point", "body:B")
    assert code == 0 and "Best point" in out


def test_the_output_format_follows_the_o_suffix_and_a_contradiction_is_refused(solver_cli, tmp_path):
    """QA 12 #7: ``-o x.docx`` wrote text into a .docx and ``--format html -o x.tex`` HTML into a
    .tex. The format now follows the suffix (.txt text, .md markdown, .html html, .tex latex); a
    suffix that is no format's, or another format's than --format, is one line naming -o, exit 2,
    nothing written. References: each format's own first line (the LaTeX preamble, the HTML
    doctype, the Markdown heading)."""
    scene = "data/scenes/sliding_bar.toml"
    for args, name in ((("-o",), "x.docx"), (("-o",), "x"), (("--format", "html", "-o"), "x.tex"),
                       (("--format", "markdown", "-o"), "x.html"), (("--suggest-point", "-o"), "x.docx")):
        code, out, err = solver_cli("explain", scene, *args, str(tmp_path / name))
        assert code == 2 and out == "" and err.count("\n") == 1, (args, name, err)
        assert err.startswith(f"error: -o {tmp_path / name}: "), err
        assert not (tmp_path / name).exists()
    starts = {"w.tex": "\\documentclass", "w.html": "<!DOCTYPE html>", "w.md": "# Worked solution",
              "w.txt": "Worked solution"}
    for name, start in starts.items():
        code, _, _ = solver_cli("explain", scene, "-o", str(tmp_path / name))
        assert code == 0 and (tmp_path / name).read_text(encoding="utf-8").startswith(start), name
    code, _, _ = solver_cli("explain", scene, "--format", "latex", "-o", str(tmp_path / "v.tex"))
    assert code == 0 and (tmp_path / "v.tex").read_text(encoding="utf-8").startswith("\\documentclass")


@pytest.mark.parametrize("scene", ["sliding_bar", "disk_bar"])
def test_the_sentence_on_alpha_names_the_equations_that_write_it(paper, scene):
    """QA 12 #12: "from here on the equations write theta_ddot as alpha" was followed at once by the
    generalized Euler equation in theta_ddot (Eq. 27's form: I_A alpha with alpha = -theta_ddot) and
    later by the equation of motion in theta_ddot. The paper writes alpha in Eqs. 28-29 only: the
    collected moment equation and the equations with the data entered. The sentence names exactly
    those, and every other equation holds theta_ddot, never alpha."""
    alpha, theta_ddot = sp.Symbol("alpha", real=True), sp.Symbol("theta_ddot", real=True)
    expl = paper[2][scene]
    said = [t for s in expl.steps() for t in s.text if t.startswith("Here alpha")]
    assert len(said) == 1
    assert ": the moment equation collected below and the equations with the data entered write the unknown " \
           "theta_ddot as alpha; the other equations keep theta_ddot." in said[0]
    writes = set()
    for step in expl.steps():
        for eq in step.equations:
            symbols = set().union(*(sp.sympify(t.expr).free_symbols for t in (*eq.lhs, *eq.rhs)))
            if alpha in symbols:
                writes.add("numbers" if step.kind == "numbers" else eq.tag)
                assert theta_ddot not in symbols, (step.kind, eq.tag)
    assert writes == {"collected", "numbers"}
    euler = next(s for s in expl.steps() if s.kind == "euler").equation("euler")
    assert theta_ddot in set().union(*(sp.sympify(t.expr).free_symbols for t in (*euler.lhs, *euler.rhs)))


def test_formats_without_the_drawing_give_the_command_that_draws_it(solver_cli, tmp_path, monkeypatch):
    """QA 12 #6: text, Markdown and LaTeX list the forces but had no free-body drawing and did not
    say where to get one. Each free-body step now gives, in one line, the ``draw --fbd`` command
    for the same scene, --point and --set (quoted for a shell); run as given, it draws the diagram.
    HTML embeds the drawing instead. Reference: the command line written out by hand."""
    import shlex

    scene = str(ROOT / "data" / "scenes" / "slider_crank.toml")
    expected = ["python", "-m", "solver", "draw", scene, "--fbd", "--point", "crank:I(O_x,A_y)",
                "-o", "fbd.svg"]
    for fmt, quote in (("text", ("", "")), ("markdown", ("`", "`")), ("latex", ("\\texttt{", "}"))):
        code, out, _ = solver_cli("explain", scene, "--format", fmt, "--point", "crank:I(O_x, A_y)")
        lines = [line for line in out.splitlines() if "The free-body diagram as a drawing:" in line]
        assert code == 0 and len(lines) == 3, fmt  # one per body: crank, rod, piston
        command = lines[0].split("as a drawing: ", 1)[1]
        assert command.startswith(quote[0]) and command.endswith(quote[1]), fmt
        if fmt == "text":
            assert shlex.split(command) == expected
    code, page, _ = solver_cli("explain", scene, "--format", "html")
    assert code == 0 and "as a drawing" not in page and page.count("<svg") == 3
    # a --set value with a space is quoted, and the command runs as written
    disk = str(ROOT / "data" / "scenes" / "disk_bar.toml")
    code, out, _ = solver_cli("explain", disk, "--set", "theta_dot=2 rad/s")
    line = next(x for x in out.splitlines() if "as a drawing:" in x)
    argv = shlex.split(line.split("as a drawing: ", 1)[1])
    assert argv == ["python", "-m", "solver", "draw", disk, "--fbd", "--set", "theta_dot=2 rad/s", "-o", "fbd.svg"]
    monkeypatch.chdir(tmp_path)
    code, _, _ = solver_cli(*argv[3:])
    assert code == 0 and (tmp_path / "fbd.svg").read_text(encoding="utf-8").count("F_f") >= 1


@pytest.mark.parametrize("command", ["explain", "draw"])
def test_o_naming_a_folder_says_so_not_its_suffix(solver_cli, tmp_path, command):
    """QA 13 #4: once -o's suffix chose explain's format, a folder or a name ending in a slash was
    refused as "unknown file type '(none)'"; the reason is that it names no file (as before)."""
    folder = tmp_path / "out"
    folder.mkdir()
    for name, reason in ((str(folder), "it is a folder"), (str(tmp_path / "new") + "/", "it ends with a slash")):
        code, out, err = solver_cli(command, "data/scenes/sliding_bar.toml", "-o", name)
        assert code == 2 and out == "" and err.count("\n") == 1, err
        assert err.startswith(f"error: -o {name}: ") and reason in err, err
    assert list(folder.iterdir()) == []


def test_the_markdown_draw_command_survives_a_backtick_in_the_path(solver_cli, tmp_path):
    """QA 13 #9: the Markdown line fenced the command in single backticks, so a scene path holding
    one broke the code span. The span's content, read by CommonMark's rule (the fence is the
    opening run of backticks; one space of padding on each side is dropped), must be the command,
    which names the file as written."""
    import shlex
    import shutil

    scene = tmp_path / "bar`s.toml"
    shutil.copy("data/scenes/sliding_bar.toml", scene)
    code, out, err = solver_cli("explain", str(scene), "--format", "markdown")
    assert code == 0, err
    line = next(x for x in out.splitlines() if "as a drawing" in x)
    fence = re.search(r"(`+)", line).group(1)
    rest = line.split(fence, 1)[1]
    close = re.search(r"(?<!`)" + fence + r"(?!`)", rest)  # the first run of the same length closes it
    content = rest[:close.start()]
    content = content[1:-1] if content.startswith(" ") and content.endswith(" ") else content
    words = shlex.split(content)
    assert words[:4] == ["python", "-m", "solver", "draw"] and words[4] == str(scene), words


def test_latex_long_equations_are_set_in_rows_without_losing_a_term(every_scene, every_rendering):
    """An equation too long for one line of the page (the four-bar coupler's Euler equation about A,
    five terms of about 80 em in all, against a text width of about 48 em between the 2 cm margins)
    is set as ``aligned`` rows, one term per row, in the LaTeX and in the Markdown's $$ blocks. Each
    rows form holds exactly the terms of the one-line form: with the alignment marks and row breaks
    taken out, it reads the same (the one-line form rebuilt by the renderer's own join of the terms,
    which the short equations still use)."""
    from solver.explain.render import _LatexMath, _latex_too_wide, _name_latex

    def flat(text):
        return re.sub(r"\s|&|\{\}|\\\\|\\(begin|end)\{aligned\}", "", text)

    rows_seen = 0
    for name, (_, expl) in every_scene.items():
        maths = _LatexMath(expl.symbol_latex)
        for step in expl.steps():
            for eq in step.equations:
                shown = maths.equation(eq)
                relation = r"\approx" if eq.approximate else "="
                lhs = _name_latex(eq.name) if eq.name else maths.join(eq.lhs)
                one_line = f"{lhs} {relation} {maths.join(eq.rhs)}"
                assert flat(shown) == flat(one_line), (name, eq.label)
                rows_seen += _latex_too_wide(eq)
                assert (r"\begin{aligned}" in shown) == _latex_too_wide(eq), (name, eq.label)
    assert rows_seen > 20
    coupler = every_rendering["four_bar", "latex"].split("generalized Euler equation about A (Eq. (10)):")[1]
    block = coupler.split(r"\end{equation*}")[0]
    assert r"\begin{aligned}" in block and block.count(r" \\") == 4, block[:400]
    markdown = every_rendering["four_bar", "markdown"].split("generalized Euler equation about A (Eq. (10)):")[1]
    assert markdown.lstrip().startswith("$$\n\\begin{aligned}"), markdown[:200]


def test_a_point_named_p_is_not_introduced_as_itself(every_rendering):
    """QA 19 #10: drum_and_block's block, whose point is named P, read "P = P." (the disk-bar's
    moments are about its own P too)."""
    pages = [name for (name, fmt), out in every_rendering.items() if fmt == "text" and "P = P." in out]
    assert pages == []
    assert "Kinematics of block from P\nIts velocity" in every_rendering["drum_and_block", "text"]


def test_compound_names_keep_their_parts_in_every_format(every_rendering):
    """QA 19 #4: the crossing point I(A_x,B_y) was typeset r_{I(A\\ x,B\\ y)} in displayed equations
    and r_{I}(A_{x},B_{y})/A in prose (a function divided by A), the element W_upper.bob1 as
    W_{upperbob1}, and "advisor's a_P" as advisor'$s a_P$. Expected forms written by hand."""
    expl = explain(load_system(ROOT / "data" / "scenes" / "four_bar.toml"), "coupler:I(A_x,B_y)", advice=False)
    text = render(expl, "latex")
    assert r"r_{I(A_{x},B_{y})} = \begin{pmatrix}" in text and r"I(A\ x" not in text
    assert r"\omega \times r_{I(A_{x},B_{y})/A}" in text and r"r_{I}(" not in text
    assert "the advisor's $a_{P}$" in text
    assert r"- r_{G/I(A_{x},B_{y})} \times m a_{I(A_{x},B_{y})}" in text  # (QA 20: the prose's r_{G}/I(...))
    page = render(expl, "html")
    assert "<mi>I(A</mi>" not in page
    # (QA 20) in the prose too: v_I(A_x,B_y) is v with a subscript, not v_I applied to (A_x, B_y),
    # and r_G/I(...) not r_G divided by I(...)
    assert re.search(r"<msub><mi>[A-Za-z]</mi><mi>I</mi></msub><mo>\(</mo>", page) is None
    assert "<mo>/</mo><mrow><mi>I</mi>" not in page
    assert ("<msub><mi>r</mi><mrow><mi>I</mi><mo>(</mo><msub><mi>A</mi><mi>x</mi></msub><mo>,</mo>"
            "<msub><mi>B</mi><mi>y</mi></msub><mo>)</mo></mrow></msub>") in page
    assert r"W_{upper.bob1} = \begin{pmatrix}" in every_rendering["double_pendulum", "latex"]


# What a hyphen-minus shown as a minus looks like in HTML: a MathML operator or number sign, or in the
# text a number's sign or an operator between spaces (drawings, code and the style sheet taken out)
_MATHML_HYPHEN = re.compile(r"<mo[^>]*>-</mo>|<mn>-")
_TEXT_HYPHEN = re.compile(r"(?<![\w.-])-(?=\.?\d)|\s-\s")
_NOT_SHOWN_AS_TEXT = re.compile(r"<(svg|style|code|pre)\b.*?</\1>", re.S)


def test_html_shows_every_minus_as_the_minus_sign(every_rendering):
    """QA 20 #7: the worked solution's HTML wrote hyphen-minus in the prose's MathML ("M_O - r_G/O x
    m a_O", the "- omega^2 r" note), in numbers (<mn>-1.703</mn>, the exponent of 10 to the -16) and in
    the free-body table's "(-A_x, 0)", beside U+2212 in the displayed equations. Every shipped
    scene's page now writes U+2212; text, Markdown and LaTeX keep "-"."""
    for (name, fmt), page in every_rendering.items():
        if fmt != "html":
            assert "\u2212" not in page, (name, fmt)
            continue
        hit = _MATHML_HYPHEN.search(page)
        assert hit is None, (name, page[max(0, hit.start() - 120):hit.end() + 40])
        for text in re.split(r"<[^>]*>", _NOT_SHOWN_AS_TEXT.sub("", page)):
            assert _TEXT_HYPHEN.search(text) is None, (name, text)
    page = every_rendering["double_pendulum", "html"]
    # a sign, without the space of a binary minus: (-A_x, 0), as the displayed equations write it
    assert ('<mo>(</mo><mo form="prefix">\u2212</mo><msub><mi>A</mi><mi>x</mi></msub><mo>,</mo><mn>0</mn><mo>)</mo>'
            in page)
    assert "<mo>\u2212</mo><msup><mi>&#969;</mi>" in page  # a = a_O + alpha x r - omega^2 r


def test_minus_signs_leaves_words_ranges_code_and_drawings():
    """The rule's edges, written out by hand: signs and spaced operators become U+2212; a hyphen in a
    word, a range, an exponent written as code (1e-16), a lone "-" cell, a command and a drawing stay."""
    from solver.mathml import minus_signs

    page = ('<p>lhs - rhs, mass-centre, items 1-5, -7.35 N, (-0.3, -r_G, 1e-16</p><td>-</td>'
            '<math><mo>-</mo><mn>-1.703</mn><mo>-&gt;</mo></math><code>--point -1</code>'
            '<svg><text x="-1">-2</text></svg><p class="a-b" id="eq-1">-4</p>')
    m = "\u2212"
    assert minus_signs(page) == (
        f'<p>lhs {m} rhs, mass-centre, items 1-5, {m}7.35 N, ({m}0.3, {m}r_G, 1e-16</p><td>-</td>'
        f'<math><mo>{m}</mo><mn>{m}1.703</mn><mo>-&gt;</mo></math><code>--point -1</code>'
        f'<svg><text x="-1">-2</text></svg><p class="a-b" id="eq-1">{m}4</p>')
    # a scene's own text (<bdi>) and the page's <title> are shown as typed
    assert minus_signs('<title>a - b</title><p>x - <bdi>use -o out - v2</bdi> -1</p>') == (
        f'<title>a - b</title><p>x {m} <bdi>use -o out - v2</bdi> {m}1</p>')


def test_scene_name_and_description_stay_as_typed_in_html(solver_cli, tmp_path):
    """QA 22 #8: the minus rule rewrote the scene's own text: name "pin-bar - v2" became "pin-bar \u2212 v2"
    in <title> and <h1>, a description's "use -o out.html" became "\u2212o", a flag one cannot copy.
    The scene's name and description are data: shown as typed (escaped), while the equations keep
    U+2212 (pin_bar's theta_ddot = -1.5 g sin(theta)/L has one)."""
    name, description = "pin-bar - v2", "Bar - pinned; offset -10 deg, use -o out.html; a<b -x"
    text = (ROOT / "tests/data/multibody/pin_bar.toml").read_text(encoding="utf-8")
    assert text.count('name = "pin_bar"\n') == 1
    scene = tmp_path / "pin.toml"
    scene.write_text(text.replace('name = "pin_bar"\n', f'name = "{name}"\ndescription = "{description}"\n'),
                     encoding="utf-8")
    code, page, err = solver_cli("explain", str(scene), "--format", "html")
    assert code == 0, err
    escaped = description.replace("<", "&lt;")
    assert f"<title>Worked solution: {name}</title>" in page
    assert f"<h1>Worked solution: <bdi>{name}</bdi></h1>" in page
    assert f"<p><bdi>{escaped}</bdi></p>" in page
    assert "pin-bar \u2212" not in page and "\u2212o out" not in page
    assert "<mo>\u2212</mo>" in page or '<mo form="prefix">\u2212</mo>' in page


def test_html_round_off_line_writes_numbers_as_the_tables_do(solver_cli):
    """QA 20 #7: the upright pendulum's "0 to round-off" line printed "computed -2.56e-15, error bound
    1.2e-13" in code notation on a page whose tables write 2.4 x 10 to the -16. The values (README:
    theta_ddot computed -2.56e-15 rad/s**2 beside a bound of 1.2e-13) are now written -2.56 x 10 to the
    -15 and 1.2 x 10 to the -13 rad/s squared, and no prose of the page keeps a number like 1e-16."""
    code, page, _ = solver_cli("explain", str(ROOT / "data/scenes/compound_pendulum.toml"), "--set",
                               "theta=180 deg", "--format", "html")
    assert code == 0
    # the Solution's line (the equations with the data entered give their known side's line before it)
    line = [p for p in page.split("<p>") if p.startswith("0 to round-off")][-1]
    power = "<mrow><mn>{}</mn><mo>\u00d7</mo><msup><mn>10</mn><mn>{}</mn></msup></mrow>"
    assert power.format("\u22122.56", "\u221215") in line
    assert power.format("1.2", "\u221213") + "</math>&#8201;rad/s<sup>2</sup>)" in line
    for text in re.split(r"<[^>]*>", _NOT_SHOWN_AS_TEXT.sub("", page)):
        assert re.search(r"\de[-+\u2212]?\d", text) is None, text


def test_an_element_is_spelled_alike_in_equations_and_force_list(tmp_path):
    """QA 20 #7: an element without a name (the reader names it point_mass_1) had its weight written
    W_{upper.point mass 1} in the equations and gravity:upper.point_mass_1 in the force list and the
    notes; in MathML the "." was an operator, spaced "upper . point mass 1". Each format now spells it
    as the scene reader names it, and the dot is a separator without operator space."""
    text = (ROOT / "data/scenes/double_pendulum.toml").read_text(encoding="utf-8")
    path = tmp_path / "unnamed.toml"
    path.write_text(text.replace('{ name = "bob1", kind', "{ kind"), encoding="utf-8")
    expl = explain(load_system(path))
    tex, page = render(expl, "latex"), render(expl, "html")
    assert "W_{upper.point\\_mass\\_1}" in tex and "gravity:upper.point\\_mass\\_1" in tex
    assert "point\\ mass" not in tex
    assert ('<msub><mi>W</mi><mrow><mi>upper</mi><mo lspace="0" rspace="0">.</mo><mi>point_mass_1</mi>'
            '</mrow></msub>') in page
    assert "<td>gravity:upper.point_mass_1</td>" in page and "point mass 1" not in page
