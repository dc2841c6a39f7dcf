"""The instantaneous solve in float64, exact and mpmath arithmetic (solver.precision).

Independent references:
* exact SI values of the units by their definitions: 1 lb = 0.45359237 kg,
  1 ft = 0.3048 m (exact), 1 deg = pi/180;
* Example 1: the 3x3 system of the paper's Eqs. 24, 25 and 28 typed here and
  solved by sympy with exact parameters (no code shared with the Derivation);
* the paper's printed alpha (Eq. 30), read from data/published/example1.toml;
* the float64 error bound cond(A) * eps.
"""
from __future__ import annotations

import json
import math
import re
import tomllib
from functools import lru_cache
from pathlib import Path

import mpmath
import pytest
import sympy as sp

from solver.precision import exact_quantity, solve_precise
from solver.units import Q_

BAR = "data/scenes/sliding_bar.toml"
PUBLISHED = Path("data/published/example1.toml")


@lru_cache(maxsize=None)
def derivation(**overrides):
    from solver.derivation import derive
    from solver.scenefile import load_scene

    return derive(load_scene(BAR, dict(overrides)))


def paper_eqs_exact(theta, beta):
    """(alpha, R_A, R_B) from Eqs. 24, 25, 28 with exact data, omega = 0."""
    m = sp.Rational(50) * sp.Rational("0.45359237")
    l = 4 * sp.Rational("0.3048")
    g = sp.Rational("32.174") * sp.Rational("0.3048")
    a, RA, RB = sp.symbols("alpha R_A R_B")
    eqs = [
        sp.sin(beta) * RB - m * (sp.cos(theta) / sp.tan(beta) + sp.sin(theta) / 2) * l * a,  # Eq. 24
        RA + sp.cos(beta) * RB + m * sp.cos(theta) * l * a / 2 - m * g,  # Eq. 25
        sp.cos(beta - theta) * RB + (sp.Rational(1, 3) - sp.sin(theta) / 2 * (sp.cos(theta) / sp.tan(beta)
                                                                          + sp.sin(theta))) * m * l * a
        - sp.cos(theta) * m * g / 2,  # Eq. 28
    ]
    sol = sp.solve(eqs, [a, RA, RB], dict=True)[0]
    return sol[a], sol[RA], sol[RB]


def test_exact_unit_values():
    assert exact_quantity(Q_("50 lbm")) == sp.Rational(50) * sp.Rational("0.45359237")
    assert exact_quantity(Q_("4 ft")) == sp.Rational(762, 625)
    assert exact_quantity(Q_("32.174 ft/s^2")) == sp.Rational("32.174") * sp.Rational("0.3048")
    assert exact_quantity(Q_("45 deg")) == sp.pi / 4
    assert exact_quantity(Q_("1 lbf")) == sp.Rational("4.4482216152605")


def test_exact_solution_equals_paper_system():
    res = solve_precise(derivation(), "exact", dps=60)
    alpha, RA, RB = paper_eqs_exact(sp.pi / 6, sp.pi / 4)
    for mine, ref in ((res.unknowns["alpha"], alpha), (res.unknowns["R_A"], RA), (res.unknowns["R_B"], RB)):
        assert sp.simplify(sp.radsimp(mine - ref)) == 0  # exactly equal, not just to 60 digits
    # the paper rounds alpha to 4 significant figures: within one unit of the last printed digit
    published = {v["id"]: v for v in tomllib.loads(PUBLISHED.read_text())["value"]}
    assert abs(float(res.unknowns["alpha"]) - published["eq30-alpha"]["value"]) <= 1e-3


def test_mpmath_agrees_with_exact_and_float64_within_its_bound():
    ex = solve_precise(derivation(), "exact", dps=50)
    mp = solve_precise(derivation(), "mpmath", dps=50)
    fl = solve_precise(derivation(), "float64")
    for name in ("alpha", "theta_ddot", "R_A", "R_B"):
        with mpmath.workdps(50):
            ref = mpmath.mpf(str(sp.N(ex.unknowns[name], 60)))
            assert abs(mp.unknowns[name] - ref) <= abs(ref) * mpmath.mpf(10) ** -45  # 50 digits, 5 spare
    # float64 against the paper's system solved exactly here (not the solver's own exact route)
    refs = dict(zip(("alpha", "R_A", "R_B"), paper_eqs_exact(sp.pi / 6, sp.pi / 4)))
    for name, ref in refs.items():
        with mpmath.workdps(50):
            exact = mpmath.mpf(str(sp.N(ref, 60)))
            error = float(abs((mpmath.mpf(fl.unknowns[name]) - exact) / exact))
        # Wilkinson: float64 within cond(A) * eps of the exact value, with a factor 10 to spare
        assert error <= 10 * fl.condition_number * 2.2e-16
        # and the error the solver reports is that error (references agree to ~1e-45 relative)
        assert mp.float64_error[name] == pytest.approx(error, rel=1e-9, abs=1e-30)


def test_exact_with_an_angle_without_closed_trig_values():
    d = derivation(theta="37 deg", beta="61.5 deg", theta_dot="0.75 rad/s")
    ex = solve_precise(d, "exact", dps=40)
    mp = solve_precise(d, "mpmath", dps=40)
    for name in ("alpha", "R_A", "R_B"):
        # both printed to 40 digits; allow 5 digits for the last-digit rounding of each
        with mpmath.workdps(45):
            a, b = mpmath.mpf(ex.text[name]), mpmath.mpf(mp.text[name])
            assert abs(a - b) <= mpmath.mpf(10) ** -35 * abs(b)


def test_bad_options():
    with pytest.raises(ValueError, match="float64"):
        solve_precise(derivation(), "quad")
    from solver.errors import InputError

    with pytest.raises(InputError, match="dps"):
        solve_precise(derivation(), "mpmath", dps=2)


def test_cli_precision(capsys):
    from solver.__main__ import main

    code = main(["precision", BAR, "--json", "--dps", "30"])
    data = json.loads(capsys.readouterr().out)
    assert code == 0 and set(data["solutions"]) == {"float64", "exact", "mpmath"}
    assert data["condition_number"] > 1
    alpha = data["solutions"]["exact"]["unknowns"]["alpha"]
    assert alpha["unit"] == "rad/s**2"
    # the printed 30 digits against the paper's Eqs. 24, 25, 28 solved exactly here; a correctly
    # rounded 30-digit text is within half a unit of its last digit (5e-30 relative, with 2 to spare)
    with mpmath.workdps(40):
        ref = mpmath.mpf(str(sp.N(paper_eqs_exact(sp.pi / 6, sp.pi / 4)[0], 45)))
        assert abs(mpmath.mpf(alpha["text"]) - ref) <= mpmath.mpf(10) ** -29 * abs(ref)
        assert len(alpha["text"].replace(".", "").lstrip("0")) >= 30


def test_exact_with_pi_outside_the_trigonometric_functions():
    # Regression (fuzzing): the rocking semicircle's system about its contact point C holds pi
    # itself (the centroid offset 4 r / (3 pi)); the exact solve failed with CoercionFailed.
    from solver.derivation import derive
    from solver.scenefile import load_scene

    d = derive(load_scene("data/scenes/rocking_semicircle.toml"), "C")
    ex = solve_precise(d, "exact", dps=40)
    mp = solve_precise(d, "mpmath", dps=40)
    for name in mp.unknowns:
        # exact and mpmath are independent arithmetics printed to 40 digits: 1e-35 relative
        with mpmath.workdps(45):
            a, b = mpmath.mpf(ex.text[name]), mpmath.mpf(mp.text[name])
            assert abs(a - b) <= mpmath.mpf(10) ** -35 * abs(b)


# -- every shipped scene; closure constraints, contacts, prescribed motion ------------------------
SCENES = sorted(Path("data/scenes").glob("*.toml"))


@pytest.mark.parametrize("scene", SCENES, ids=[s.stem for s in SCENES])
def test_precision_runs_on_every_shipped_scene_solve_solves(solver_cli, one_load_per_scene, scene: Path) -> None:
    # Regression: four_bar, double_pendulum, cart_pendulum ended in an internal error (lambdify
    # was given None for the coordinate of a one-coordinate system), slider_crank in a false
    # "singular configuration" (sin of the dependent angle's rational value has no closed form),
    # ladder_leaves_wall in "joints not satisfied" (the contact regime solve finds was not used).
    # Precision answers wherever `solve` gives a unique answer; where the forces have no unique
    # value (statically indeterminate sticking contacts, as `solve` says) it refuses in one line.
    # (`precision` runs first, on the freshly loaded scene; `solve` then reads the same one.)
    status, out, err = solver_cli("precision", str(scene), "--dps", "20")  # every arithmetic
    solved, solve_out, _ = solver_cli("solve", str(scene), "--json")
    assert solved == 0
    indeterminate = "indeterminate" in json.loads(solve_out)
    if indeterminate:
        assert status == 2 and out == "" and err.count("\n") == 1, err
        assert err.startswith("error: ") and "statically indeterminate" in err, err
    else:
        assert (status, err) == (0, ""), err
        assert "mpmath (20 digits)" in out


def test_four_bar_precision_matches_solve_to_the_bound_it_states(solver_cli) -> None:
    # The float64 solve (`solve`) and the 50-digit one differ by no more than the bound
    # `precision` prints, cond(A) * 2.2e-16 relative to the whole solution vector (a normwise
    # bound: a small component such as B_x may be off by more, relative to itself). The exact
    # solve (rational arithmetic, sympy DomainMatrix) and the mpmath one (LU at 50 digits) are
    # two routes through the same equations: they agree to the digits both carry (tolerance:
    # 1e-45 relative, 5 of the 50 digits left for the rounding of the last places).
    four_bar = "data/scenes/four_bar.toml"
    status, out, err = solver_cli("precision", four_bar, "--json")
    assert status == 0, err
    payload = json.loads(out)
    status, solve_out, err = solver_cli("solve", four_bar, "--json")
    assert status == 0, err
    solved = json.loads(solve_out)["unknowns"]
    precise = payload["solutions"]["mpmath"]["unknowns"]
    exact = payload["solutions"]["exact"]["unknowns"]
    assert set(precise) == set(solved) == set(exact)
    bound = payload["condition_number"] * 2.2e-16
    diff = math.sqrt(sum((solved[n]["value"] - precise[n]["value"]) ** 2 for n in precise))
    size = math.sqrt(sum(precise[n]["value"] ** 2 for n in precise))
    assert diff <= bound * size
    for n in precise:
        assert precise[n]["unit"] == solved[n]["unit"]
        a, b = mpmath.mpf(precise[n]["text"]), mpmath.mpf(exact[n]["text"])
        assert abs(a - b) <= mpmath.mpf("1e-45") * max(abs(b), size)
    assert "theta3, theta4" in payload["solutions"]["exact"]["note"]


def test_period_counts_independent_coordinates(solver_cli) -> None:
    # Regression: "3 free coordinate(s) (theta2, theta3, theta4)" for the four-bar, whose
    # theta3 and theta4 follow from theta2 through the loop closure.
    status, out, err = solver_cli("period", "data/scenes/four_bar.toml", "--amplitude", "10 deg")
    assert (status, out) == (2, "") and err.count("\n") == 1
    assert "1 independent coordinate(s) (theta2), theta3, theta4 dependent through closure constraints" in err


def test_condition_number_one_concept_named_by_kind(capsys):
    """One condition number, two ways of getting it, each output naming which it prints: `solve`
    prints the cheap estimate (`condition_number_estimate`), `precision` the exact value
    (`condition_number`), and `explain` the same exact value. Reference: the definition applied
    here to the equations' matrix at the state, with numpy: A scaled by its columns' and then its
    rows' largest entries, then ||As||_1 ||As^-1||_1 (np.linalg.cond with p=1). The estimate is a
    lower bound by construction (||As^-1 z||_1 / ||z||_1 <= ||As^-1||_1)."""
    import numpy as np

    from solver.__main__ import main

    d = derivation()
    system = d.system
    c = system.free[0]
    values = {k: sp.Float(v) for k, v in system.si_values().items()}
    values.update({c.q: sp.Float(c.value), c.qd: sp.Float(c.rate), system.t: sp.Float(system.time)})
    A = np.array(d.linear_system()[0].xreplace(values).evalf(), dtype=float)
    As = A / np.max(np.abs(A), axis=0)
    As = As / np.max(np.abs(As), axis=1)[:, None]
    reference = np.linalg.cond(As, 1)

    assert main(["precision", BAR, "--precision", "float64", "--json"]) == 0
    exact = json.loads(capsys.readouterr().out)["condition_number"]
    assert exact == pytest.approx(reference, rel=1e-12)  # the same float64 inverse, up to round-off
    assert main(["solve", BAR, "--json"]) == 0
    solved = json.loads(capsys.readouterr().out)
    assert "condition_number" not in solved
    assert 1 <= solved["condition_number_estimate"] <= exact * (1 + 1e-12)
    assert main(["solve", BAR]) == 0
    assert "condition number estimate" in capsys.readouterr().out
    assert main(["explain", BAR]) == 0
    assert f"(condition number {exact:.3g})" in capsys.readouterr().out


# the rod on a table edge, turning at 2 rad/s at the state
TABLE_ROD = (Path(__file__).parent / "data" / "multibody" / "table_rod.toml").read_text(
    encoding="utf-8").replace('rate = "0 rad/s"', 'rate = "2 rad/s"')
DISK_SLIP = (Path(__file__).parent / "data" / "multibody" / "disk_slip.toml").read_text(encoding="utf-8")


def _exact_forms(capsys, path: Path) -> dict[str, tuple[sp.Expr, dict]]:
    """name -> (exact form, the values its "at ..." line lists), from `precision --json`."""
    from solver.__main__ import main

    assert main(["precision", str(path), "--precision", "exact", "--json"]) == 0
    forms = json.loads(capsys.readouterr().out)["solutions"]["exact"]["exact"]
    out = {}
    for name, text in forms.items():
        form, _, at = text.partition("   at ")
        values = dict(part.split(" = ") for part in at.split(", ")) if at else {}
        names = {n: sp.Symbol(n) for n in re.findall(r"[A-Za-z_]\w*", form)
                 if n not in ("sin", "cos", "sqrt", "Abs", "pi")}  # beta a symbol, not sympy's beta()
        out[name] = (sp.sympify(form, locals=names), {k: sp.sympify(v) for k, v in values.items()})
    return out


def test_exact_forms_keep_the_rates_and_list_every_value_they_need(tmp_path, capsys):
    # Regression: the rates were substituted into the exact forms without being listed, so
    # that O_x read "2943*sin(theta)*cos(theta)/400 - 12*cos(theta)/5   at theta = 0" (the
    # -12/5 is -m a theta_dot**2 with theta_dot = 2, nowhere said). Reference: the rod pinned
    # at O with its centre G at a from O: I_O = m L**2/12 + m a**2, theta_ddot =
    # -m g a cos(theta)/I_O, and Newton along x: O_x = m a_Gx = -m a (theta_ddot sin(theta) +
    # theta_dot**2 cos(theta)). Exact data, so the forms must agree identically.
    path = tmp_path / "table_rod.toml"
    path.write_text(TABLE_ROD)
    forms = _exact_forms(capsys, path)
    th, thd = sp.symbols("theta theta_dot")
    m, L, a, g = 3, sp.Rational(6, 5), sp.Rational(1, 5), sp.Rational(981, 100)
    thdd = -m * g * a * sp.cos(th) / (m * L**2 / 12 + m * a**2)
    expected = {"theta_ddot": thdd, "O_x": -m * a * (thdd * sp.sin(th) + thd**2 * sp.cos(th))}
    for name, closed in expected.items():
        form, at = forms[name]
        assert sp.simplify(form - closed) == 0
        # every symbol of the form is given its value, and these are the state's
        assert {str(s) for s in form.free_symbols} <= set(at)
    assert forms["O_x"][1] == {"theta": 0, "theta_dot": 2}


def test_exact_forms_are_tidied(tmp_path, capsys):
    # Regression: "s_ddot = (9810*sin(beta) - 981*cos(beta))/(1000*sin(beta)**2 +
    # 1000*cos(beta)**2)". The slipping disk (mu_k = 0.1): N = m g cos(beta), and
    # m s_ddot = m g sin(beta) - mu N, so s_ddot = g (sin(beta) - mu cos(beta)).
    path = tmp_path / "disk_slip.toml"
    path.write_text(DISK_SLIP)
    forms = _exact_forms(capsys, path)
    beta = sp.Symbol("beta")
    g, mu = sp.Rational(981, 100), sp.Rational(1, 10)
    expected = {"s_ddot": g * (sp.sin(beta) - mu * sp.cos(beta)), "N": 4 * g * sp.cos(beta)}
    for name, closed in expected.items():
        form = forms[name][0]
        assert sp.expand(form - closed) == 0  # equal as written: no sin**2 + cos**2 left to reduce


def test_exact_solve_with_an_irrational_number_and_the_advisor_point(solver_cli):
    """QA 13 #1: the four-bar about its crank's instant centre I(O2_y, A_x), whose coordinate is
    sqrt(3)/20, stopped with sympy's "expected an expression convertible to a rational function ...
    got sqrt(3)/20" (exit 2). Irrational numbers are now generators of the field as the angles'
    sines are. By hand: [[sqrt(3), 1], [1, sqrt(3)]] x = [1, 0] has det 2 and x = (sqrt(3)/2, -1/2);
    with pi and E, [[pi, 0], [0, E]] x = [sqrt(2), pi] gives (sqrt(2)/pi, pi/E)."""
    from solver.precision import _exact_solve

    r3 = sp.sqrt(3)
    x = _exact_solve(sp.Matrix([[r3, 1], [1, r3]]), sp.Matrix([1, 0]), {}, "test")
    assert sp.simplify(x[0] - r3 / 2) == 0 and sp.simplify(x[1] + sp.Rational(1, 2)) == 0
    x = _exact_solve(sp.Matrix([[sp.pi, 0], [0, sp.E]]), sp.Matrix([sp.sqrt(2), sp.pi]), {}, "test")
    assert sp.simplify(x[0] - sp.sqrt(2) / sp.pi) == 0 and sp.simplify(x[1] - sp.pi / sp.E) == 0
    code, out, err = solver_cli("precision", "tests/data/multibody/driven_four_bar.toml", "--point", "crank:I(O2_y,A_x)")
    assert code == 0 and "exact (50 digits)" in out, err
