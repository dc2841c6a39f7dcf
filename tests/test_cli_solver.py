"""Tests for the solver command line (solver/__main__.py, cli_common.py,
cli_instant.py).

Reference values
----------------
* Example 1 (sliding bar): alpha, R_A, R_B as printed in Eq. (30), read from
  data/published/example1.toml (never typed here).
* Example 1 with beta = 90 deg is the classic ladder (A on the floor, B on a
  vertical wall): closed form, independent of the solver. With
  c = cos(theta), s = sin(theta):
  theta_ddot = -(3 g / (2 l)) c (any theta_dot), and from Newton on G at
  (l/2)(c, s): R_B = m (l/2)(-s theta_ddot - c theta_dot^2),
  R_A = m g + m (l/2)(c theta_ddot - s theta_dot^2).
* Example 2: the equation of motion of Eq. (44) with the sign of F_a
  corrected (data/scenes/README.md, Example 2: a push +F_a i at P does
  positive work F_a r_d per unit theta, since x_P = r_d theta by Eq. 31), and omega_n of Eq. (46).

A few runs go through a real subprocess (exit status, stderr, no traceback);
the rest call ``main()`` in-process to keep the suite fast.
"""
from __future__ import annotations

import json
import os
import math
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest
import sympy as sp

from reports.rounding import eq30_tolerances
from solver import cli_instant
from solver.__main__ import COMMAND_MODULES, build_parser, main
from solver.errors import SingularConfigurationError
from solver.expressions import parse_expression

ROOT = Path(__file__).resolve().parents[1]
SLIDING_BAR = ROOT / "data" / "scenes" / "sliding_bar.toml"
DISK_BAR = ROOT / "data" / "scenes" / "disk_bar.toml"
PUBLISHED = ROOT / "data" / "published" / "example1.toml"


def _published() -> dict[str, dict]:
    """Eq. (30) values by unknown name, as recorded (value, unit, sig_figs)."""
    table = tomllib.loads(PUBLISHED.read_text())
    return {v["id"].removeprefix("eq30-"): v for v in table["value"] if v["id"].startswith("eq30-")}


def _tolerance(name: str) -> float:
    """Tolerance of a printed Eq. (30) value: the one model the report uses
    (reports/rounding.py: the paper's 4-significant-figure rounding of Eq. 29 and
    of its data, propagated to first order, plus half a unit of the printed digit)."""
    table = tomllib.loads(PUBLISHED.read_text())
    return eq30_tolerances({v["id"]: v for v in table["value"]})[name]


def run_cli(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "solver", *args],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=240,
    )


def run_main(capsys: pytest.CaptureFixture[str], *args: str) -> tuple[int, str, str]:
    try:
        status = main(list(args))
    except SystemExit as stop:  # usage and input errors exit through fail()
        status = stop.code
    out, err = capsys.readouterr()
    return status, out, err


# -- Example 1 against the published values ------------------------------------------------


def test_solve_json_sliding_bar_matches_published_eq30(capsys: pytest.CaptureFixture[str]) -> None:
    # In process (main() is what `python -m solver` runs); the real entry point is exercised by
    # the subprocess cases of test_bad_input_is_one_line_exit_2 and the --help probe below.
    status, out, err = run_main(capsys, "solve", str(SLIDING_BAR), "--json")
    assert status == 0, err
    result = json.loads(out)
    assert set(result) == {"scene", "point", "method", "unknowns", "condition_number_estimate"}
    assert result["point"] == "A" and result["method"] == "generalized_euler"
    unknowns = result["unknowns"]
    published = _published()
    for name in ("alpha", "R_A", "R_B"):
        entry = published[name]
        assert unknowns[name]["value"] == pytest.approx(entry["value"], abs=_tolerance(name)), name
    # The paper prints alpha's unit as rad/s (a typo); the answer is in rad/s**2.
    assert unknowns["alpha"]["unit"] == "rad/s**2"
    assert unknowns["R_A"]["unit"] == unknowns["R_B"]["unit"] == "lbf"
    assert unknowns["theta_ddot"]["value"] == pytest.approx(-unknowns["alpha"]["value"], rel=1e-12)
    assert math.isfinite(result["condition_number_estimate"]) and result["condition_number_estimate"] >= 1


@pytest.mark.parametrize(
    ("point", "method"),
    [("B", "generalized_euler"), ("G", "generalized_euler"), ("A", "mass_center"), ("B", "lagrange")],
)
def test_solve_any_point_and_method_matches_published(
    capsys: pytest.CaptureFixture[str], point: str, method: str
) -> None:
    status, out, err = run_main(capsys, "solve", str(SLIDING_BAR), "--point", point, "--method", method, "--json")
    assert status == 0, err
    result = json.loads(out)
    # the mass-centre and Lagrange routes use no reference point: they say so rather than echo --point
    shown = point if method == "generalized_euler" else None
    assert result["point"] == shown and result["method"] == method
    assert ("point_note" in result) == (shown is None)
    for name, entry in _published().items():
        assert result["unknowns"][name]["value"] == pytest.approx(entry["value"], abs=_tolerance(name))


@pytest.mark.parametrize("method", ["mass_center", "lagrange"])
def test_a_route_without_reference_point_does_not_echo_point(capsys: pytest.CaptureFixture[str], method: str,
                                                            one_load_per_scene) -> None:
    """`--point` with a route that takes no moments about P (mass_center: about each G; lagrange: no
    moment equation) is checked but not used: every output that names the point says null with the
    route's note, in JSON and text alike (solve, eom of a one- and a two-freedom scene, precision),
    and a point the body does not have is still refused. (The commands read each scene once.)"""
    double = str(ROOT / "data" / "scenes" / "double_pendulum.toml")
    for argv in (["solve", str(SLIDING_BAR), "--point", "B"], ["eom", str(SLIDING_BAR), "--point", "B"],
                 ["eom", double, "--point", "lower:A"], ["precision", str(SLIDING_BAR), "--point", "B"]):
        status, out, err = run_main(capsys, *argv, "--method", method, "--json")
        assert status == 0, err
        result = json.loads(out)
        assert result["point"] is None and result["method"] == method, argv
        assert method in result["point_note"] and "not used" in result["point_note"]
    for argv in (["solve", str(SLIDING_BAR), "--point", "B"], ["eom", str(SLIDING_BAR), "--point", "B"]):
        status, out, err = run_main(capsys, *argv, "--method", method)
        assert status == 0, err
        assert f"point  none ({method} " in out and "point  B" not in out
    status, out, err = run_main(capsys, "solve", str(SLIDING_BAR), "--point", "Z", "--method", method, "--json")
    assert status == 2 and "'Z'" in err and out == ""


@pytest.mark.parametrize("theta_dot", [0.0, 1.5])
def test_set_beta_90_gives_the_ladder_closed_form(capsys: pytest.CaptureFixture[str], theta_dot: float) -> None:
    status, out, err = run_main(
        capsys, "solve", str(SLIDING_BAR), "--json",
        "--set", "beta=90 deg", "--set", f"theta_dot={theta_dot} rad/s", "--set", "theta=0.4 rad",
    )
    assert status == 0, err
    u = json.loads(out)["unknowns"]
    # SI data of the scene: 50 lbm, 4 ft, 32.174 ft/s^2
    m, l, g = 50 * 0.45359237, 4 * 0.3048, 32.174 * 0.3048
    c, s = math.cos(0.4), math.sin(0.4)
    qdd = -3 * g / (2 * l) * c
    r_b = m * (l / 2) * (-s * qdd - c * theta_dot**2)
    r_a = m * g + m * (l / 2) * (c * qdd - s * theta_dot**2)
    lbf = 4.4482216152605  # N per lbf (exact definition)
    # Both sides are exact formulas in double precision: 1e-9 relative.
    assert u["theta_ddot"]["value"] == pytest.approx(qdd, rel=1e-9)
    assert u["alpha"]["value"] == pytest.approx(-qdd, rel=1e-9)
    assert u["R_B"]["value"] == pytest.approx(r_b / lbf, rel=1e-9)
    assert u["R_A"]["value"] == pytest.approx(r_a / lbf, rel=1e-9)


def test_solve_table_is_readable(capsys: pytest.CaptureFixture[str]) -> None:
    status, out, _ = run_main(capsys, "solve", str(SLIDING_BAR))
    assert status == 0
    lines = out.splitlines()
    header = next(line for line in lines if line.startswith("name"))
    assert header.split() == ["name", "value", "unit"]
    row = next(line for line in lines if line.startswith("R_A "))
    assert row.split()[2] == "lbf"
    assert "nan" not in out.lower() and "inf" not in out.lower()


# -- Example 2: eom and frequency --------------------------------------------------------------


def test_eom_json_has_one_schema_in_output_units(capsys: pytest.CaptureFixture[str]) -> None:
    """`eom --json` gives the same keys, of the same types, for one freedom (Example 1, in lbm/ft) and
    for two (the double pendulum); the units it names for the reactions are those of the values it
    prints (the scene's lbf), not SI. Reference for `mass`: d2T/(dqd_i dqd_j) of the kinetic energy
    the same output prints, parsed back and compared exactly after expand/trigsimp."""
    double = str(ROOT / "data" / "scenes" / "double_pendulum.toml")
    payloads = {}
    for scene in (str(SLIDING_BAR), double):
        status, out, err = run_main(capsys, "eom", scene, "--json")
        assert status == 0, err
        payloads[scene] = json.loads(out)
    bar, pendulum = payloads[str(SLIDING_BAR)], payloads[double]
    assert list(bar) == list(pendulum)
    for key in bar:
        if bar[key] is not None and pendulum[key] is not None:
            assert type(bar[key]) is type(pendulum[key]), key
    assert bar["reaction_units"] == {"R_A": "lbf", "R_B": "lbf"}
    assert {n: e["unit"] for n, e in bar["reactions_at_state"].items()} == bar["reaction_units"]
    assert "SI" in bar["expression_units"]
    assert pendulum["coordinates"] == ["theta1", "theta2"] and len(pendulum["eom"]) == 2
    assert set(pendulum["reactions_at_state"]) == {"O_x", "O_y", "A_x", "A_y"} and pendulum["reactions"] is None
    names = {n: sp.Symbol(n, real=True) for n in ("m1", "m2", "l1", "l2", "g", "theta1", "theta2", "theta1_dot",
                                                   "theta2_dot", "theta1_ddot", "theta2_ddot")}
    T = parse_expression(pendulum["kinetic_energy"], names, "kinetic_energy")
    rates = [names["theta1_dot"], names["theta2_dot"]]
    for i, row in enumerate(pendulum["mass"]):
        for j, entry in enumerate(row):
            M = parse_expression(entry, names, "mass")
            assert sp.trigsimp(sp.expand(M - sp.diff(T, rates[i], rates[j]))) == 0, (i, j)




def _disk_symbols() -> dict[str, sp.Symbol]:
    names = ["m_d", "r_d", "m_b", "l_b", "g", "F_a", "theta", "theta_dot", "theta_ddot", "t"]
    return {n: sp.Symbol(n, real=True) for n in names}


def test_eom_json_disk_bar_is_corrected_eq44(capsys: pytest.CaptureFixture[str]) -> None:
    status, out, err = run_main(capsys, "eom", str(DISK_BAR), "--json")
    assert status == 0, err
    result = json.loads(out)
    names = _disk_symbols()
    # Read our own output back with the whitelist parser (no sympify).
    assert result["coordinates"] == ["theta"]
    eom = parse_expression(result["eom"][0], names, "eom --json")
    m_d, r_d, m_b, l_b, g, F_a, th, thd, thdd = (names[n] for n in
                                                  ["m_d", "r_d", "m_b", "l_b", "g", "F_a", "theta", "theta_dot", "theta_ddot"])
    eq44 = (
        ((sp.Rational(3, 2) * m_d + m_b) * r_d**2 + sp.Rational(1, 3) * m_b * l_b**2 - m_b * r_d * l_b * sp.cos(th)) * thdd
        + sp.Rational(1, 2) * m_b * r_d * l_b * sp.sin(th) * thd**2
        + sp.Rational(1, 2) * m_b * g * l_b * sp.sin(th)
        - F_a * r_d  # Eq. 44 prints -F_a r_d on the right: sign corrected (see module docstring)
    )
    assert sp.expand(eom - eq44) == 0  # both polynomial in sin/cos: expand suffices
    assert set(result["reactions"]) == {"F_f", "F_n"}
    assert all("theta" in text for text in result["reactions"].values())


def test_eom_latex_uses_dot_notation(capsys: pytest.CaptureFixture[str]) -> None:
    status, out, _ = run_main(capsys, "eom", str(DISK_BAR), "--latex")
    assert status == 0
    assert r"\ddot{\theta}" in out and "theta_{dot}" not in out


def test_frequency_json_disk_bar_is_eq46(capsys: pytest.CaptureFixture[str]) -> None:
    status, out, err = run_main(capsys, "frequency", str(DISK_BAR), "--json")
    assert status == 0, err
    result = json.loads(out)
    # Eq. (46) with the scene's chosen values (data/scenes/disk_bar.toml).
    m_d, r_d, m_b, l_b, g = 4.0, 0.25, 1.5, 0.2, 9.80665
    omega = math.sqrt(0.5 * m_b * g * l_b / ((1.5 * m_d + m_b) * r_d**2 + m_b * l_b * (l_b / 3 - r_d)))
    assert result["omega_n"]["unit"] == "rad/s"
    # Closed form vs root-found equilibrium + derivatives: 1e-9 relative.
    assert result["omega_n"]["value"] == pytest.approx(omega, rel=1e-9)
    assert result["period"]["value"] == pytest.approx(2 * math.pi / omega, rel=1e-9)
    assert result["frequency"]["value"] == pytest.approx(omega / (2 * math.pi), rel=1e-9)


# -- bad input: one line, exit 2, no traceback --------------------------------------------------


# A real process for one case (a usage error: the exit status and the absence of a traceback at
# the interpreter level; it needs no heavy import, so it costs little). The rest runs in process:
# the same code path, about 2 s of start-up and imports less each; an exception escaping main()
# would fail the test there as surely as a traceback in a subprocess. test_explain runs a real
# `python -m solver` through a whole derivation.
SUBPROCESS_CASES = {
    ("solve", str(SLIDING_BAR), "--frobnicate"),
}


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (("solve", "data/scenes/no_such_scene.toml"), "cannot read the scene file"),
        (("solve", str(SLIDING_BAR), "--point", "Z"), "--point Z: point 'Z' is not a point of the body 'body'"),
        (("explain", "data/scenes/compound_pendulum.toml", "--point", "Z"), "--point Z: point 'Z' is not a point"),
        (("simulate", str(SLIDING_BAR), "--t-end", "1 s", "--animate", "tests"), "--animate tests: it is a folder"),
        (("draw", str(SLIDING_BAR), "-o", "tests"), "-o tests: it is a folder"),
        (("solve", str(SLIDING_BAR), "--method", "newton"), "invalid choice: 'newton'"),
        (("solve", str(SLIDING_BAR), "--set", "m_b=50 ft"), "--set m_b: '50 ft' is a length"),
        (("solve", str(SLIDING_BAR), "--set", "beta"), "expected NAME=VALUE"),
        (("solve", str(SLIDING_BAR), "--set", "beta=0 deg"), "impossible geometry"),
        (("solve", str(SLIDING_BAR), "--frobnicate"), "unrecognized arguments"),
        (("transmogrify", str(SLIDING_BAR)), "invalid choice"),
    ],
)
def test_bad_input_is_one_line_exit_2(
    capsys: pytest.CaptureFixture[str], args: tuple[str, ...], words: str
) -> None:
    # A real process for SUBPROCESS_CASES (exit status and no traceback at the
    # interpreter level), in-process for the rest (same code path, faster).
    if args in SUBPROCESS_CASES:
        done = run_cli(*args)
        status, out, err = done.returncode, done.stdout, done.stderr
    else:
        status, out, err = run_main(capsys, *args)
    assert status == 2, (out, err)
    assert "Traceback" not in err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), err
    assert words in lines[0]
    assert out == ""


def test_toml_syntax_error_exit_2(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    bad = tmp_path / "bad.toml"
    bad.write_text("[parameters\nm = '1 kg'\n")
    status, out, err = run_main(capsys, "solve", str(bad))
    assert status == 2 and out == ""
    assert err.startswith(f"error: {bad}: TOML syntax error:") and "line 1" in err
    assert err.count("\n") == 1


def test_singular_configuration_exit_2(monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    # Stand-in: the derivation reports a singular system; the CLI must pass
    # its message through as one line, exit 2.
    def singular(scene, point=None, method="generalized_euler"):
        raise SingularConfigurationError("x.toml: singular at theta = 90 deg (rail_B), condition number 1e+17")

    monkeypatch.setattr(cli_instant.derivation, "solve_instant", singular)
    status, out, err = run_main(capsys, "solve", str(SLIDING_BAR))
    assert status == 2 and out == ""
    assert err == "error: x.toml: singular at theta = 90 deg (rail_B), condition number 1e+17\n"


def test_non_finite_answer_is_never_printed(monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    real = cli_instant.derivation.solve_instant

    def with_nan(scene, point=None, method="generalized_euler"):
        solution = real(scene, point, method)
        solution.unknowns["R_B"] = solution.unknowns["R_B"] * float("nan")
        return solution

    monkeypatch.setattr(cli_instant.derivation, "solve_instant", with_nan)
    for extra in ((), ("--json",)):
        status, out, err = run_main(capsys, "solve", str(SLIDING_BAR), *extra)
        assert status == 2 and out == ""
        assert "R_B is not a finite number" in err


def test_help_lists_the_commands() -> None:
    text = build_parser().format_help()
    for command in ("solve", "eom", "frequency"):
        assert command in text
    assert COMMAND_MODULES[0] == "solver.cli_instant"


# -- the extra scenes: closed forms for pivot, plate, point mass, semicircular rolling ----------


def _frequency(capsys: pytest.CaptureFixture[str], scene: str) -> float:
    status, out, err = run_main(capsys, "frequency", str(ROOT / "data" / "scenes" / scene), "--json")
    assert status == 0, err
    return json.loads(out)["omega_n"]["value"]


def test_compound_pendulum_frequency_closed_form(capsys: pytest.CaptureFixture[str]) -> None:
    # Values from data/scenes/compound_pendulum.toml; omega^2 = g m d_G / I_O
    # (parallel axes, Eq. 12: plate m(a^2+b^2)/12 + m(a/2)^2, tip m_t a^2).
    m_p, a, b, m_t, g = 2.0, 0.6, 0.1, 0.5, 9.80665
    inertia = m_p * (a**2 + b**2) / 12 + m_p * (a / 2) ** 2 + m_t * a**2
    omega = math.sqrt(g * (m_p * a / 2 + m_t * a) / inertia)
    assert _frequency(capsys, "compound_pendulum.toml") == pytest.approx(omega, rel=1e-9)  # exact formulas


def test_rocking_semicircle_frequency_closed_form(capsys: pytest.CaptureFixture[str]) -> None:
    # Values from data/scenes/rocking_semicircle.toml. Rolling about the
    # contact point at theta = 0, which lies r - c below G (c = 4r/(3 pi)):
    # omega^2 = m g c / (I_G + m (r - c)^2).
    m, r, g = 1.2, 0.1, 9.80665
    c = 4 * r / (3 * math.pi)
    inertia_g = (0.5 - 16 / (9 * math.pi**2)) * m * r**2
    omega = math.sqrt(m * g * c / (inertia_g + m * (r - c) ** 2))
    assert _frequency(capsys, "rocking_semicircle.toml") == pytest.approx(omega, rel=1e-9)  # exact formulas


PENDULUM_IN_MINUTES = """
[parameters]
m = "2 kg"
L = "1.5 m"
g = "9.81 m/s^2"
[coordinate]
value = "30 deg"
rate = "0 rad/s"
[body]
orientation = "theta - pi/2"
[points]
O = ["0", "0"]
M = ["L", "0"]
[[elements]]
kind = "point_mass"
mass = "m"
at = "M"
[[constraints]]
kind = "pivot"
point = "O"
[[loads]]
kind = "gravity"
g = "g"
[output_units]
force = "lbf"
time = "min"
angular_velocity = "rpm"
angle = "deg"
"""


def test_every_command_prints_in_the_scenes_output_units(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    # Regression: only `solve` honoured [output_units]; frequency, period, simulate and
    # friction printed rad/s, s, rad and N whatever the scene asked for.
    # Reference: simple pendulum, omega_n = sqrt(g / L), T0 = 2 pi / omega_n (closed forms).
    from solver.units import ureg

    scene = tmp_path / "pendulum.toml"
    scene.write_text(PENDULUM_IN_MINUTES)
    omega = math.sqrt(9.81 / 1.5)
    runs = {cmd: json.loads(run_main(capsys, *cmd.split(), str(scene), "--json")[1])
            for cmd in ("frequency", "period --amplitude 1e-3", "simulate --t-end 0.5", "friction")}
    checks = [
        (runs["frequency"]["omega_n"], "rpm", omega, "rad/s"),
        (runs["frequency"]["period"], "min", 2 * math.pi / omega, "s"),
        (runs["period --amplitude 1e-3"]["period_linear"], "min", 2 * math.pi / omega, "s"),
        (runs["simulate --t-end 0.5"]["t_end"], "min", 0.5, "s"),
    ]
    for entry, unit, si_value, si_unit in checks:
        assert entry["unit"] == unit
        # pint-parsable, and the same quantity (unit conversion only: round-off)
        assert ureg.Quantity(entry["value"], entry["unit"]).to(si_unit).magnitude == pytest.approx(si_value, rel=1e-12)
    assert runs["simulate --t-end 0.5"]["theta_end"]["unit"] == "deg"
    assert runs["friction"]["search_range"] == {"value": [0.0, 180.0], "unit": "deg"}


# -- issue 10: hostile input at the boundary ---------------------------------------------------
# Each case of the issue's corpus that reached the solver: one line naming the flag or the file
# place, exit 2, nothing on stdout, and fast (the guards act before pint, sympy or the integrator
# see the input; the in-process runner would hang here if one did not).


def _scene_with(tmp_path: Path, old: str, new: str, base: Path = SLIDING_BAR) -> str:
    text = base.read_text()
    assert old in text
    path = tmp_path / "hostile.toml"
    path.write_text(text.replace(old, new, 1))
    return str(path)


HOSTILE_CLI = [
    (("solve", str(SLIDING_BAR), "--set", "m_b=1 kg**9**9**9"), "--set m_b: a power of a power"),
    (("period", str(DISK_BAR), "--amplitude", "30 deg**9**9**9"), "--amplitude: a power of a power"),
    (("simulate", str(DISK_BAR), "--t-end", "1e12 s"), "--t-end must be a positive time of at most"),
    (("simulate", str(DISK_BAR), "--t-end", "1 s", "--samples", "1000000000"), "argument --samples:"),
    (("simulate", str(DISK_BAR), "--t-end", "1 s", "--out", "/dev/null"), "--out /dev/null: it is a character device"),
    (("solve", "/dev/zero"), "/dev/zero: cannot read the scene file: it is a character device"),
    (("precision", str(SLIDING_BAR), "--dps", "5000"), "argument --dps: expected an integer from 5 to 4000"),
    (("solve", str(SLIDING_BAR), "--set", "theta=1e300 deg"), "--set theta: the angle '1e+300 deg' is too large"),
    (("friction", str(DISK_BAR), "--ratio-of", "zz/yy"), "--ratio-of zz/yy: zz, yy are not parameters"),
    (("friction", str(DISK_BAR), "--mass-ratio", "-1"), "argument --mass-ratio:"),
    (("friction", str(DISK_BAR), "--mass-ratio", "nan"), "argument --mass-ratio:"),
    (("friction", str(SLIDING_BAR), "--range", "10", "5"), "--range 10 5: expected LOW < HIGH"),
    (("friction", str(SLIDING_BAR), "--amplitude", "30"), "--amplitude applies to a scene with a rolling contact"),
    (("simulate", str(DISK_BAR), "--t-end", "1 s", "--rtol", "1e-300"), "argument --rtol:"),
    (("simulate", str(DISK_BAR), "--t-end", "1 s", "--atol", "1e-300", "--rtol", "1e-13"),
     "the integration failed at the start"),
    (("solve", str(DISK_BAR), "--set", "theta_dot=1e200 rad/s"), "--set theta_dot: 1e+200 rad / s is 1e+200 in SI"),
    (("solve", str(SLIDING_BAR), "--set", "l_b=1e200 ft"), "--set l_b: 1e+200 ft is 3.048e+199 in SI units"),
]


@pytest.mark.parametrize(("args", "words"), HOSTILE_CLI)
def test_issue10_hostile_flags_are_one_line(solver_cli, args: tuple[str, ...], words: str) -> None:
    status, out, err = solver_cli(*args)
    assert (status, out) == (2, ""), err
    assert err.count("\n") == 1 and err.startswith("error: ") and "internal error" not in err, err
    assert words in err


HOSTILE_SCENES = [
    ('m_b  = "50 lbm"', 'm_b  = "50 lbm**9**9**9"', "parameters.m_b: a power of a power"),
    ('m_b  = "50 lbm"', 'm_b  = "50 kg**1e9"', "parameters.m_b: the exponent in unit 'kg**1e9'"),
    ('force  = "lbf"', 'force  = "lbf' + "*ft/ft" * 40 + '"', "output_units.force: unit text is 243 characters long; the limit is 100"),
    ('value = "30 deg"', 'value = "1e300 deg"', "coordinate.value: the angle '1e+300 deg' is too large"),
    ('orientation     = "pi - theta"', 'orientation = "pi - theta**(10**300)"',
     "body.orientation: the exponent of 'theta' must be at most 12"),
    ('name = "sliding_bar"', 'name = "sliding_bar"\nx = ' + "[" * 5000 + "]" * 5000, "nested deeper than 8"),
    ('orientation     = "pi - theta"', 'orientation = "1e300*theta"', "body.orientation: the angle '5.23599e+299 rad'"),
    ('angle    = "-beta"', 'angle = "1e300"', "constraints[1].angle: the angle '1e+300 rad' is too large"),
    ('orientation     = "pi - theta"', 'orientation = "pi - abs(theta)"',
     "body.orientation: Abs(theta) is not differentiable in theta"),
    ("[parameters]", "[parameters]\n" + "".join(f'p{i} = "1 kg"\n' for i in range(1001)),
     "a table or array with 1005 entries; the limit is 1000"),
]


@pytest.mark.parametrize(("old", "new", "words"), HOSTILE_SCENES)
@pytest.mark.parametrize("command", ["solve", "eom", "precision"])
def test_issue10_hostile_scenes_are_one_line(solver_cli, tmp_path: Path, old: str, new: str, words: str,
                                             command: str) -> None:
    scene = _scene_with(tmp_path, old, new)
    status, out, err = solver_cli(command, scene)
    assert (status, out) == (2, ""), err
    assert err.count("\n") == 1 and err.startswith(f"error: {scene}: "), err
    assert words in err


def test_issue10_fifo_scene_does_not_block(solver_cli, tmp_path: Path) -> None:
    fifo = tmp_path / "scene.toml"
    os.mkfifo(fifo)
    status, out, err = solver_cli("solve", str(fifo))
    assert (status, out) == (2, "")
    assert err == f"error: {fifo}: cannot read the scene file: it is a FIFO (named pipe), not a regular file\n"


def test_issue10_out_folder_is_refused_before_the_run(solver_cli, tmp_path: Path, monkeypatch) -> None:
    import solver.simulate

    def no_run(*args, **kwargs):  # the check must come first: the integrator is never reached
        raise AssertionError("simulate ran before --out was checked")

    monkeypatch.setattr(solver.simulate, "simulate", no_run)
    status, out, err = solver_cli("simulate", str(DISK_BAR), "--t-end", "1 s", "--out", str(tmp_path))
    assert (status, out) == (2, "")
    assert err == f"error: --out {tmp_path}: it is a folder; give a file name\n"
    assert list(tmp_path.iterdir()) == []  # nothing written


def test_cpu_cap_stops_a_runaway_request(solver_cli, tmp_path: Path, monkeypatch) -> None:
    # A stand-in for symbolic work that never ends (the cap is the backstop behind the guards).
    monkeypatch.setenv("SOLVER_MAX_CPU_SECONDS", "0.2")
    monkeypatch.setattr(cli_instant.derivation, "solve_instant", lambda *a, **k: _spin())
    status, out, err = solver_cli("solve", str(SLIDING_BAR))
    assert (status, out) == (2, "")
    assert err.startswith("error: the request needed more than 0.2 s of CPU time") and err.count("\n") == 1


def test_warnings_never_precede_the_error_line(solver_cli, monkeypatch) -> None:
    import warnings

    import numpy as np

    def overflowing(*args, **kwargs):
        np.float64(1e200) ** 2  # numpy warns: overflow encountered
        warnings.warn("a library's note", UserWarning)
        raise SingularConfigurationError("x.toml: alpha is not a finite number")

    monkeypatch.setattr(cli_instant.derivation, "solve_instant", overflowing)
    status, out, err = solver_cli("solve", str(SLIDING_BAR))
    assert (status, out, err) == (2, "", "error: x.toml: alpha is not a finite number\n")


def _spin() -> None:
    while True:
        try:
            sum(range(10_000))
        except Exception:  # noqa: BLE001 - a library swallowing exceptions must not defeat the cap
            pass


def test_help_loads_neither_sympy_nor_scipy_nor_pint() -> None:
    # Start-up (issue 12): every subcommand's options are built for --help without the heavy
    # libraries (about 1.5 s of CPU); they load on first use. A fresh interpreter, since this
    # test process has long imported them.
    probe = ("import sys; from solver.__main__ import build_parser; build_parser().format_help(); "
             "print(sorted(m for m in ('sympy', 'scipy', 'pint', 'numpy', 'solver.derivation') if m in sys.modules "
             "and not type(sys.modules[m]).__name__ == '_LazyModule'))")
    done = subprocess.run([sys.executable, "-c", probe], cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "[]"


def test_a_multibody_point_error_names_its_full_place(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    """A point of a body in the multibody format is named with its body's place in the file:
    bodies[0].points.E, not points.E (which is the one-body format's [points] table)."""
    text = (ROOT / "data" / "scenes" / "double_pendulum.toml").read_text(encoding="utf-8")
    assert 'A = ["l1", "0"]' in text
    path = tmp_path / "arity.toml"
    path.write_text(text.replace('A = ["l1", "0"]', 'A = ["l1"]', 1), encoding="utf-8")
    status, out, err = run_main(capsys, "solve", str(path))
    assert status == 2 and out == ""
    assert err.startswith(f"error: {path}: bodies[0].points.A: expected a pair"), err


def test_kinematics_gives_round_off_as_zero_and_keeps_true_small_values(capsys):
    """QA 21 #5: the piston of slider_crank slides on the line y = 0 (its slider), so its y velocity
    and acceleration are exactly 0; kinematics printed -8.88e-16 m/s and -2.84e-14 m/s**2, the
    round-off of the rod's cancelling terms. They are now 0, with the line that says so, as `solve`
    does. A true small value is kept: the compound pendulum at theta = 1e-9 rad, at rest, has by
    hand theta'' = -g (m_p a/2 + m_t a) sin(theta) / I_O with
    I_O = m_p (a^2 + b^2)/12 + m_p (a/2)^2 + m_t a^2, and its tip T = a (sin th, -cos th)
    accelerates at a theta'' (cos th, sin th), 1.3e-8 and 1.3e-17 m/s**2 (rtol 1e-12: a few
    roundings of a handful of operations)."""
    assert main(["kinematics", "data/scenes/slider_crank.toml", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    for point in ("rod:B", "piston:B", "piston:G"):
        for what in ("velocity", "acceleration"):
            assert out["points"][point][what]["value"][1] == 0.0
            assert f"{point} {what} y" in out["zero_to_round_off"]
    assert main(["kinematics", "data/scenes/slider_crank.toml"]) == 0
    text = capsys.readouterr().out
    table = text.split("0 to round-off")[0]
    assert "e-16" not in table and "e-14" not in table
    assert "0 to round-off (a value within its own error bound is given as 0): rod:B velocity y (computed" in text

    assert main(["kinematics", "data/scenes/compound_pendulum.toml", "--set", "theta=1e-9 rad", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    m_p, a, b, m_t, g, th = 2.0, 0.6, 0.1, 0.5, 9.80665, 1e-9
    I_O = m_p * (a**2 + b**2) / 12 + m_p * (a / 2) ** 2 + m_t * a**2
    thdd = -g * (m_p * a / 2 + m_t * a) * math.sin(th) / I_O
    got = out["points"]["body:T"]["acceleration"]["value"]
    assert got[0] == pytest.approx(a * thdd * math.cos(th), rel=1e-12)
    assert got[1] == pytest.approx(a * thdd * math.sin(th), rel=1e-12)
    assert "zero_to_round_off" not in out
