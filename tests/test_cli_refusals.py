"""Command-line options that are refused, or apply, as their help and the READMEs say
(solver/cli_dynamics.py, solver/__main__.py, the --set rules of solver/units.py read by both scene
loaders). Each refusal is one ``error:`` line on stderr, exit status 2, naming the flag or the
``--set`` name and the file where one is involved, with nothing written.

Reference values are closed forms: a disk sliding down a 30 deg incline from rest has
s'' = g (sin(beta) - mu cos(beta)) (Coulomb friction mu N, N = m g cos(beta)).
"""
from __future__ import annotations

import json
import math
import re
from pathlib import Path

import pytest

from solver.__main__ import main

ROOT = Path(__file__).resolve().parents[1]
SCENES = ROOT / "data" / "scenes"

TABLE_ROD = (Path(__file__).parent / "data" / "multibody" / "table_rod.toml").read_text(encoding="utf-8")


def _run(capsys, *args: str) -> tuple[int, str, str]:
    try:
        status = main(list(args))
    except SystemExit as stop:
        status = stop.code
    return (status, *capsys.readouterr())


def _one_line(status: int, out: str, err: str) -> str:
    assert status == 2 and out == "", err
    assert err.startswith("error: ") and err.count("\n") == 1 and "Traceback" not in err
    return err


@pytest.fixture()
def table_rod(tmp_path: Path) -> str:
    path = tmp_path / "table_rod.toml"
    path.write_text(TABLE_ROD)
    return str(path)


# -- simulate --mu: rolling contacts only --------------------------------------------------------

@pytest.mark.parametrize("scene", ["ladder_leaves_wall.toml", "compound_pendulum.toml"])
def test_simulate_mu_on_a_scene_without_rolling_contact_is_refused_naming_the_file(capsys, scene: str) -> None:
    # rails only (the old message named no file); no contact at all (--mu was ignored silently)
    err = _one_line(*_run(capsys, "simulate", str(SCENES / scene), "--t-end", "0.2", "--mu", "0.2"))
    assert str(SCENES / scene) in err and "--mu" in err and "no rolling contact" in err


def test_simulate_mu_still_sets_a_rolling_contact(capsys) -> None:
    mu, beta, g = 0.05, math.radians(30), 9.80665  # incline_disk.toml: 30 deg, g = 9.80665 m/s^2
    status, out, err = _run(capsys, "simulate", str(SCENES / "incline_disk.toml"), "--t-end", "0.5", "--mu", str(mu),
                            "--samples", "3", "--json")
    assert status == 0, err
    # it needs tan(30 deg)/3 = 0.19 to roll: with 0.05 it slides. 1e-9: the integrator's rtol is 1e-9
    # and s'' is constant along the slide
    assert json.loads(out)["final"]["s_ddot"]["value"] == pytest.approx(g * (math.sin(beta) - mu * math.cos(beta)),
                                                                       rel=1e-9)


# -- simulate --out: CSV only --------------------------------------------------------------------

def test_simulate_out_with_another_suffix_is_refused_before_the_run(capsys, tmp_path: Path) -> None:
    target = tmp_path / "run.xlsx"
    err = _one_line(*_run(capsys, "simulate", str(SCENES / "compound_pendulum.toml"), "--t-end", "0.1",
                          "--out", str(target)))
    assert "--out" in err and ".xlsx" in err and ".csv" in err
    assert not any(tmp_path.iterdir())  # nothing written, not even a temporary file


# -- --set: the angle rules, one-body and multibody formats alike ---------------------------------

@pytest.mark.parametrize("fmt", ["multibody", "one-body"])
def test_set_an_angle_with_a_length_blames_set_and_says_what_each_is(capsys, table_rod: str, fmt: str) -> None:
    scene = table_rod if fmt == "multibody" else str(SCENES / "sliding_bar.toml")
    err = _one_line(*_run(capsys, "solve", scene, "--set", "theta=45 m"))
    assert "--set theta" in err and "a length" in err and "angle" in err and ".rate" not in err


def test_set_a_length_with_an_angle_blames_set(capsys) -> None:
    err = _one_line(*_run(capsys, "solve", str(SCENES / "cart_pendulum.toml"), "--set", "x=10 deg"))
    assert "--set x:" in err and "is an angle, but x is a length" in err


@pytest.mark.parametrize("setting", ["theta=45", "beta=90"])
def test_set_a_bare_number_for_an_angle_asks_for_its_unit(capsys, table_rod: str, setting: str) -> None:
    name, _, number = setting.partition("=")
    scene = table_rod if name == "theta" else str(SCENES / "sliding_bar.toml")  # a coordinate; a deg parameter
    err = _one_line(*_run(capsys, "solve", scene, "--set", setting))
    assert f"--set {name}" in err and "no unit" in err and f'"{number} deg"' in err


@pytest.mark.parametrize("fmt", ["multibody", "one-body"])
def test_a_bare_angle_in_the_scene_file_is_refused_as_on_set(capsys, tmp_path: Path, table_rod: str, fmt: str) -> None:
    """A coordinate's value "0.5" was read as 0.5 rad (theta = 28.65 deg) while --set theta=0.5 was
    refused: the file follows --set's rule, one line naming the file and the key, exit 2; a bare 0
    is still taken (from rest at theta = 0 the rod on the table edge has
    theta'' = -m g a / (m L**2/12 + m a**2); the sliding bar's file: 30 deg written "0")."""
    source = Path(table_rod) if fmt == "multibody" else SCENES / "sliding_bar.toml"
    text = source.read_text(encoding="utf-8")
    written = re.search(r'(value = )"(\d+(\.\d+)? deg)"', text)
    path = tmp_path / "bare.toml"
    path.write_text(text.replace(written.group(0), f'{written.group(1)}"0.5"', 1))
    err = _one_line(*_run(capsys, "solve", str(path)))
    key = "coordinates.theta.value" if fmt == "multibody" else "coordinate.value"
    assert f"{path}: {key}: '0.5' has no unit, but theta is an angle" in err and '"0.5 deg"' in err
    path.write_text(text.replace(written.group(0), f'{written.group(1)}"0"', 1))
    status, out, err = _run(capsys, "solve", str(path), "--json")
    assert status == 0, err
    if fmt == "multibody":
        m, L, a, g = 3.0, 1.2, 0.2, 9.81  # table_rod.toml; 1e-12: one small linear solve, round-off only
        expected = -m * g * a / (m * L**2 / 12 + m * a**2)
        assert json.loads(out)["unknowns"]["theta_ddot"]["value"] == pytest.approx(expected, rel=1e-12)


def test_every_shipped_scene_still_loads() -> None:
    """The shipped scenes give every angle its unit (the rule above refuses a bare one)."""
    from solver.io.scenes import load_system

    files = sorted([*SCENES.glob("*.toml"), *(ROOT / "tests" / "data").rglob("*.toml")])
    assert len(files) > 30
    for path in files:
        load_system(str(path))


def test_set_zero_and_an_angle_with_its_unit_are_taken(capsys, table_rod: str) -> None:
    m, L, a, g = 3.0, 1.2, 0.2, 9.81  # the rod on the table edge, from rest: I_O theta'' = -m g a cos(theta)
    for setting, degrees in (("theta=0", 0.0), ("theta=45 deg", 45.0), ("theta=0.125 turn", 45.0)):
        status, out, err = _run(capsys, "solve", table_rod, "--set", setting, "--json")
        assert status == 0, err
        expected = -m * g * a * math.cos(math.radians(degrees)) / (m * L**2 / 12 + m * a**2)
        # 1e-12: one small linear solve, round-off only
        assert json.loads(out)["unknowns"]["theta_ddot"]["value"] == pytest.approx(expected, rel=1e-12)


def test_set_a_bare_zero_is_taken_for_any_quantity(capsys) -> None:
    """QA 11: --set theta_dot=0 was refused ("0.0 is an angle or pure number, but an angular velocity
    is needed") while --set theta=0 was taken; zero is zero in every unit. References, from rest:
    the compound pendulum (one-body format) I_O theta'' = -(m_p a/2 + m_t a) g sin(theta) with
    I_O = m_p (a^2 + b^2)/12 + m_p (a/2)^2 + m_t a^2 (its file: 2 kg, 0.6 m, 0.1 m, 0.5 kg); the block
    on the vertical slider with its spring's stiffness set to 0 falls freely, x'' = -g (9.81 m/s^2).
    Tolerance 1e-12: one small linear solve, round-off only."""
    m_p, a, b, m_t, g, theta = 2.0, 0.6, 0.1, 0.5, 9.80665, math.radians(20)
    I_O = m_p * (a**2 + b**2) / 12 + m_p * (a / 2) ** 2 + m_t * a**2
    status, out, err = _run(capsys, "solve", str(SCENES / "compound_pendulum.toml"), "--set", "theta_dot=0", "--json")
    assert status == 0, err
    expected = -(m_p * a / 2 + m_t * a) * g * math.sin(theta) / I_O
    assert json.loads(out)["unknowns"]["theta_ddot"]["value"] == pytest.approx(expected, rel=1e-12)
    block = str(Path(__file__).parent / "data" / "multibody" / "vertical_spring.toml")
    status, out, err = _run(capsys, "solve", block, "--set", "k=0", "--set", "x_dot=0.0", "--json")
    assert status == 0, err
    assert json.loads(out)["unknowns"]["x_ddot"]["value"] == pytest.approx(-9.81, rel=1e-12)


@pytest.mark.parametrize(("scene", "setting", "needed"), [
    ("compound_pendulum.toml", "theta_dot=2", "an angular velocity is needed"),
    ("cart_pendulum.toml", "x_dot=1.50", "is not a speed"),
    ("cart_pendulum.toml", "theta_dot=3", "is not an angular velocity"),
])
def test_set_a_bare_nonzero_rate_is_refused_as_typed(capsys, scene: str, setting: str, needed: str) -> None:
    """A nonzero number without its unit keeps the rule (refused); the message shows it as typed
    ('1.50', not 1.5)."""
    name, _, typed = setting.partition("=")
    err = _one_line(*_run(capsys, "solve", str(SCENES / scene), "--set", setting))
    assert f"--set {name}: {typed!r} " in err and needed in err


@pytest.mark.parametrize("where", ["file", "set"])
def test_the_angle_cap_holds_for_multibody_coordinates(capsys, tmp_path: Path, table_rod: str, where: str) -> None:
    if where == "file":
        scene = tmp_path / "big.toml"
        scene.write_text(TABLE_ROD.replace('value = "0 deg"', 'value = "1e7 deg"'))
        err = _one_line(*_run(capsys, "solve", str(scene)))
        assert "coordinates.theta.value" in err
    else:
        err = _one_line(*_run(capsys, "solve", table_rod, "--set", "theta=1e7 deg"))
        assert "--set theta" in err
    assert "1000 turns" in err


def test_the_angle_cap_lets_1000_turns_pass(capsys, table_rod: str) -> None:
    for text in ("360000 deg", "-1000 turn"):  # the cap itself, whatever its rounding in radians
        status, _, err = _run(capsys, "solve", table_rod, "--set", f"theta={text}")
        assert status == 0, err


# -- period on a fully driven scene; unknown flags named by their command -------------------------

def test_period_of_a_fully_driven_scene_does_not_send_to_frequency(capsys) -> None:
    scene = str(SCENES / "slider_crank.toml")
    err = _one_line(*_run(capsys, "period", scene, "--amplitude", "10 deg"))
    assert "`frequency`" not in err and "prescribed" in err
    _one_line(*_run(capsys, "frequency", scene))  # which would refuse it too


@pytest.mark.parametrize("command, required", [("frequency", ()), ("solve", ()), ("period", ("--amplitude", "10")),
                                               ("simulate", ("--t-end", "0.1")), ("draw", ("-o", "x.svg")),
                                               ("explain", ())])
def test_an_unknown_flag_is_named_with_its_command(capsys, command: str, required: tuple[str, ...]) -> None:
    err = _one_line(*_run(capsys, command, str(SCENES / "compound_pendulum.toml"), *required, "--mu", "0.3", "--bogus"))
    unknown = "--bogus" if command == "simulate" else "--mu 0.3 --bogus"  # --mu is one of simulate's
    assert f"python -m solver {command}: unrecognized arguments: {unknown} " in err


@pytest.mark.parametrize("scene", ["compound_pendulum", "double_pendulum"])  # the one-body format, multibody
@pytest.mark.parametrize("key, text, where", [("name", r"a\u0000b", "U+0000 at character 2"),
                                              ("description", r"red \u001b[31m", "U+001B at character 5")])
def test_a_control_character_in_a_scenes_name_or_description_is_refused(capsys, tmp_path, scene, key, text, where):
    """QA 21 #8: a TOML ``\\u0000`` or ``\\u001b`` in ``name`` or ``description`` was accepted and
    copied into the SVG (then no longer XML), the HTML, the .tex and the terminal. It is refused at
    read, in one line naming the file, the key and the character, by both formats' reader."""
    source = (SCENES / f"{scene}.toml").read_text(encoding="utf-8")
    head, table, rest = source.partition("\n[")  # the top-level keys come before the first table
    head = "\n".join(line for line in head.splitlines() if not line.startswith((f"{key} ", f"{key}=")))
    path = tmp_path / "ctl.toml"
    path.write_text(f'{key} = "{text}"\n' + head + table + rest, encoding="utf-8")
    for command in (["solve", str(path)], ["draw", str(path), "-o", str(tmp_path / "x.svg")]):
        err = _one_line(*_run(capsys, *command))
        assert err == f"error: {path}: {key}: control character {where}; a scene's {key} is one line of printable text\n"
    assert not (tmp_path / "x.svg").exists()


@pytest.mark.parametrize("scene, old, new, key, why", [
    ("double_pendulum", 'g = "g"', 'g = "g*theta1/theta1"', "loads[0].g",
     "theta1 cannot be used here: a coordinate is allowed only in orientation, position.at, position_angle "
     "and force components and couple moments"),
    ("double_pendulum", 'orientation = "theta2 - pi/2"', 'orientation = "theta2_dot - pi/2"', "bodies[1].orientation",
     "theta2_dot cannot be used here: a rate is allowed only in force components and couple moments"),
    ("compound_pendulum", 'g    = "g"', 'g    = "g*theta/theta"', "loads[0].g",
     "theta cannot be used here: the coordinate is allowed only in body.orientation, body.position and force "
     "components and couple moments"),
    ("compound_pendulum", 'orientation     = "theta - pi/2"', 'orientation     = "theta + t - pi/2"',
     "body.orientation", "t cannot be used here: t is allowed only in force components and couple moments"),
])
def test_a_state_name_where_it_is_not_allowed_says_where_it_is(capsys, tmp_path, scene, old, new, key, why):
    """QA 21 #10: a coordinate in a torsional spring's free_angle was refused with "the coordinate is
    allowed only in body.orientation, body.position and loads; its rate and t only in force and
    couple loads": the refused key was itself in loads, and t is allowed in ground points, motion,
    motor angle, orientation and position too. The message now says, for the name refused, where
    it may be used, by data/scenes/README.md's table "Where each name may be used" (multibody) and
    its one-body "Expressions" (the coordinate in orientation, position and force and couple loads,
    its rate and t in those loads only)."""
    source = (SCENES / f"{scene}.toml").read_text(encoding="utf-8")
    assert source.count(old) == 1
    path = tmp_path / "state_name.toml"
    path.write_text(source.replace(old, new), encoding="utf-8")
    err = _one_line(*_run(capsys, "solve", str(path)))
    assert err.startswith(f"error: {path}: {key}: unknown name ") and err.endswith(f"; {why}\n"), err


def test_an_element_centre_on_a_one_element_body_is_said_to_be_g(capsys) -> None:
    """QA 21 #11: --point coupler:G_slender_bar_1 on four_bar (each link one slender bar) was refused
    with a list ending "or one the advisor names ...: G_<element>", the very form refused. The advisor
    names G_<element> on bodies of several elements only; on a body of one, its centre is G."""
    for point, bodies in (("coupler:G_slender_bar_1", "coupler"), ("G_slender_bar_1", "crank, coupler, rocker")):
        err = _one_line(*_run(capsys, "solve", str(SCENES / "four_bar.toml"), "--point", point))
        assert err.endswith(f"; slender_bar_1 is the only element of {bodies}, whose mass centre is G: G_<element> "
                            "names an element's mass centre on a body of several elements)\n"), err
        assert "or one the advisor names" not in err


def test_explain_says_total_mass_m_once_when_it_is_the_scenes_m(capsys, tmp_path) -> None:
    """QA 21 #11: a one-element body whose mass parameter is m read 'total mass m = m.'"""
    assert main(["explain", str(ROOT / "tests" / "data" / "multibody" / "pin_bar.toml")]) == 0  # one bar of mass m
    out = capsys.readouterr().out
    assert "1 element, total mass m." in out and "total mass m = m" not in out
    assert main(["explain", str(SCENES / "slider_crank.toml")]) == 0
    out = capsys.readouterr().out
    assert "Body crank: 1 element, total mass m = m_c." in out
