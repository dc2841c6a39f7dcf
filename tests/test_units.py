"""Tests for solver/units.py: the guarded way from user text to pint.

Reference values: unit factors are the SI definitions (1 ft = 0.3048 m exactly,
1 lb = 0.45359237 kg exactly, 1 deg = pi/180 rad), typed here from those
definitions, never taken from pint or the solver.
"""
from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from solver.errors import InputError
from solver.units import (
    MAX_ANGLE_RAD,
    MAX_UNIT_EXPONENT,
    MAX_UNIT_LENGTH,
    check_unit_text,
    parse_angle,
    parse_quantity,
    parse_time,
    parse_unit,
    si_magnitude,
    ureg,
)


@settings(max_examples=300, deadline=None)  # 300 draws: well under a second
@given(st.sampled_from(["lbm", "ft", "deg", "ft/s^2", "lbf", "ft*lbf", "rad/s", "in", "turn", "rpm", "g", "percent",
                        "degC", "degF", "kelvin"]),
       st.floats(min_value=-1e6, max_value=1e6, allow_nan=False))
def test_si_magnitude_is_pints_conversion_to_the_bit(unit: str, value: float) -> None:
    # the reference is pint's own conversion (the path si_magnitude shortens), for units with an
    # offset (degC, degF) too: the same float, not only a close one
    q = ureg.Quantity(value, parse_unit(unit, "here"))
    assert si_magnitude(q) == float(q.to_base_units().magnitude)


@pytest.mark.parametrize(
    ("text", "si", "unit"),
    [
        ("50 lbm", 50 * 0.45359237, "kg"),
        ("4 ft", 4 * 0.3048, "m"),
        ("32.174 ft/s^2", 32.174 * 0.3048, "m/s**2"),
        ("32.174 ft/s²", 32.174 * 0.3048, "m/s**2"),
        ("2 (m/s)**2", 2.0, "m**2/s**2"),
        ("3 m ** -2", 3.0, "1/m**2"),
        ("1.5 kg*m**(2)", 1.5, "kg*m**2"),
        ("0.3", 0.3, ""),
    ],
)
def test_good_quantities_keep_their_value(text: str, si: float, unit: str) -> None:
    q = parse_quantity(text, "here")
    # unit factors are exact decimals; pint's float chain is within a few ulp
    assert q.to_base_units().magnitude == pytest.approx(si, rel=1e-15)
    assert q.dimensionality == (ureg.get_dimensionality(unit) if unit else ureg.dimensionless.dimensionality)


@pytest.mark.parametrize(
    ("text", "words"),
    [
        ("50 lbm**9**9**9", "a power of a power"),
        ("1 kg**9**9**9", "a power of a power"),
        ("30 deg**9**9**9", "a power of a power"),
        ("50 kg**1e9", "must be a plain number"),
        ("1 m**13", "must be a plain number"),
        ("1 kg**(9**9)", "must be a plain number"),
        ("1 m**x", "must be a plain number"),
        ("1 (m**4)**4", f"exponent larger than {MAX_UNIT_EXPONENT}"),
        ("1 ((((m))))", "nested deeper"),
        ("1 m*(s", "unbalanced"),
        ("1 m" + "*m" * 60, f"the limit is {MAX_UNIT_LENGTH}"),
        ("1 mé", "not allowed"),
        ("1e400 kg", "not finite"),
        ("1e301 kg", "out of range"),
        ("1e-400 kg", "rounds to 0"),
        ("1 parsec**12/yoctometer**12", "out of range"),
        ("1 kg; import os", "not allowed"),
        ("nan kg", "expected a number"),
        ("1 m*" + "9" * 20, "too long"),
    ],
)
def test_hostile_units_are_refused_before_pint(text: str, words: str) -> None:
    with pytest.raises(InputError, match=r"^here: ") as info:
        parse_quantity(text, "here")
    assert words in str(info.value)
    assert "\n" not in str(info.value)


# 60 texts over the 17-symbol unit alphabet (~1 ms each): cheap, so many shapes per run.
@settings(max_examples=60)
@given(st.text(alphabet="m s k g * / ^ ( ) 0 1 9 . e -", max_size=40))
def test_any_unit_text_is_decided_quickly(text: str) -> None:
    # Property: every text over the unit alphabet is either a unit or one InputError
    # (never another exception, never pint computing a huge exponent).
    try:
        unit = parse_unit(text, "here")
    except InputError as err:
        assert str(err).startswith("here: ")
    else:
        assert all(abs(p) <= MAX_UNIT_EXPONENT for _, p in unit._units.items())


def test_check_unit_text_spells_superscripts() -> None:
    assert check_unit_text("kg*m²/s³", "x") == "kg*m**2/s**3"


def test_angles() -> None:
    assert parse_angle("180 deg", "--amplitude") == pytest.approx(math.pi, rel=1e-15)
    assert parse_angle("30", "--amplitude") == pytest.approx(math.pi / 6, rel=1e-15)  # bare: degrees
    assert parse_angle("0.5 rad", "--amplitude") == 0.5
    with pytest.raises(InputError, match=r"^--amplitude: the angle '1e300 deg' is too large"):
        parse_angle("1e300 deg", "--amplitude")
    with pytest.raises(InputError, match="expected an angle"):
        parse_angle("3 m", "--amplitude")
    assert parse_angle(f"{MAX_ANGLE_RAD} rad", "x") == MAX_ANGLE_RAD  # the limit itself is accepted


def test_times() -> None:
    assert parse_time("2 min", "--t-end") == 120.0
    assert parse_time("10", "--t-end") == 10.0
    with pytest.raises(InputError, match=r"^--t-end: expected a time"):
        parse_time("10 m", "--t-end")
    with pytest.raises(InputError, match=r"^--t-end: expected a time"):
        parse_time("10 deg", "--t-end")


# QA 15 #3: every unit the "plain units" message lists is taken, and an angle or an angular velocity
# is refused in a unit that measures none. References: 1 gradian = pi/200 rad (a right angle is
# 100 gradians), 1 rev/s = 2 pi rad/s, 1 rpm = 2 pi/60 rad/s (definitions); 1e-12: unit factors'
# round-off only.
@pytest.mark.parametrize("spelling", ["gradian", "grad", "gon"])
def test_gradians_are_angles(spelling: str) -> None:
    assert parse_angle(f"100 {spelling}", "--amplitude") == pytest.approx(math.pi / 2, rel=1e-12)


def test_every_unit_the_plain_units_message_lists_is_taken() -> None:
    with pytest.raises(InputError) as err:
        parse_quantity("2 ft/m", "demo")
    listed = err.value.args[0].split("plain units (")[1].split(")")[0].split(", ")
    assert {"gradian", "revolution", "percent"} <= set(listed)
    for name in listed:
        parse_quantity(f"1 {name}", "demo")  # raises if refused


@pytest.mark.parametrize("text", ["50 percent", "50 %"])
def test_percent_is_no_angle(text: str) -> None:
    with pytest.raises(InputError, match="expected an angle"):
        parse_angle(text, "--amplitude")
    with pytest.raises(InputError, match="expected a time"):
        parse_time(text, "--t-end")
    assert parse_quantity(text, "demo").to("").magnitude == pytest.approx(0.5, rel=1e-12)  # a pure number still


@pytest.mark.parametrize("scene, setting, name", [
    ("data/scenes/sliding_bar.toml", "theta_dot=0.5 Hz", "theta_dot"),      # one-body format, the state
    ("tests/data/multibody/pin_bar.toml", "theta_dot=2 kHz", "theta_dot"),  # multibody format, the state
    ("tests/data/multibody/pin_bar.toml", "theta_dot=2 Bq", "theta_dot"),
    ("data/scenes/slider_crank.toml", "omega=16 Hz", "omega"),             # a parameter the scene gives in rad/s
])
def test_a_frequency_is_refused_for_an_angular_velocity(solver_cli, scene, setting, name) -> None:
    code, out, err = solver_cli("solve", scene, "--set", setting)
    assert (code, out, err.count("\n")) == (2, "", 1), err
    assert f"--set {name}:" in err and "is a frequency" in err and "rev/s" in err and "rad/s" in err


@pytest.mark.parametrize("scene, setting", [("data/scenes/sliding_bar.toml", "beta=100 percent"),
                                            ("tests/data/multibody/pin_bar.toml", "theta=50 percent")])
def test_percent_is_refused_for_an_angle(solver_cli, scene, setting) -> None:
    code, out, err = solver_cli("solve", scene, "--set", setting)
    assert (code, out, err.count("\n")) == (2, "", 1) and "not an angle" in err


def test_turns_per_second_and_rpm_are_taken(solver_cli) -> None:
    import json

    for setting, rad_s in (("theta_dot=2 rev/s", 4 * math.pi), ("theta_dot=60 rpm", 2 * math.pi),
                           ("theta_dot=3 rad/min", 0.05)):
        code, out, err = solver_cli("kinematics", "tests/data/multibody/pin_bar.toml", "--set", setting, "--json")
        assert code == 0, err
        omega = json.loads(out)["bodies"]["bar"]["omega"]
        assert omega["unit"] == "rad/s" and omega["value"] == pytest.approx(rad_s, rel=1e-12)


def test_a_rate_in_hz_in_the_scene_file_and_output_units_in_percent_are_refused(solver_cli, tmp_path) -> None:
    text = open("tests/data/multibody/pin_bar.toml", encoding="utf-8").read()
    for old, new, key in (('rate = "1 rad/s"', 'rate = "2 Hz"', "coordinates.theta.rate:"),
                          ('name = "pin_bar"', 'name = "pin_bar"\noutput_units = { angle = "percent" }', "output_units.angle:"),
                          ('name = "pin_bar"', 'name = "pin_bar"\noutput_units = { angular_velocity = "Hz" }',
                           "output_units.angular_velocity:")):
        path = tmp_path / "s.toml"
        path.write_text(text.replace(old, new), encoding="utf-8")
        code, out, err = solver_cli("solve", str(path))
        assert (code, out, err.count("\n")) == (2, "", 1) and key in err, err


# QA 17 #5: the same 2 pi confusion one derivative further, and percent as an angle in the file.
def test_a_frequency_per_time_is_refused_for_an_angular_acceleration(solver_cli) -> None:
    """driven_coord's al (given as 2 rad/s^2) took "1 Hz/s" as 1 rad/s^2; 1 rev/s^2 is 2 pi rad/s^2
    (definition) and stays taken, as does SI's 1/s^2. The crank's alpha is al at t = 0 (th = w t +
    al t^2 / 2, the scene's motion), so the JSON alpha is the angular acceleration set."""
    import json

    code, out, err = solver_cli("solve", "tests/data/multibody/driven_coord.toml", "--set", "al=1 Hz/s")
    assert (code, out, err.count("\n")) == (2, "", 1), err
    assert "--set al:" in err and "angular acceleration" in err and '"1 rev/s^2"' in err and '"1 rad/s^2"' in err
    for setting, rad_s2 in (("al=1 rev/s^2", 2 * math.pi), ("al=3 s^-2", 3.0)):
        code, out, err = solver_cli("solve", "tests/data/multibody/driven_coord.toml", "--set", setting, "--json")
        assert code == 0, err
        assert json.loads(out)["unknowns"]["alpha"]["value"] == pytest.approx(rad_s2, rel=1e-12)


@pytest.mark.parametrize("old, new, key", [
    ('beta = "45 deg"', 'beta = "100 percent"', "parameters.beta:"),   # a rail's angle = "-beta"
    ('g    = "32.174 ft/s^2"', 'g    = "32.174 ft/s^2"\nphi = "50 %"', "parameters.phi:")])
def test_percent_is_refused_where_the_file_uses_a_parameter_as_an_angle(solver_cli, tmp_path, old, new, key) -> None:
    """/tmp/qa17/sb_pct.toml gave beta = "100 percent" and was solved with beta = 1 rad. A parameter
    in an angle key or in a sine's argument is now refused in its unit of percent; the second case
    adds phi to the bar's mass, m_b*cos(phi)**2 (pure numbers as factors), while mu = "30 percent"
    as a plain factor stays taken (test_percent_is_no_angle)."""
    text = open("data/scenes/sliding_bar.toml", encoding="utf-8").read().replace(old, new)
    if "phi" in new:
        text = text.replace('mass = "m_b"', 'mass = "m_b*cos(phi)**2"')
    path = tmp_path / "s.toml"
    path.write_text(text, encoding="utf-8")
    code, out, err = solver_cli("solve", str(path))
    assert (code, out, err.count("\n")) == (2, "", 1), err
    assert key in err and "not an angle" in err and "deg or rad" in err


@pytest.mark.parametrize("orientation, parameter, refused", [
    ("theta - 90", "", True),                 # degrees meant: 90 rad is 14 turns
    ("theta - q", 'q = "90"\n', True),        # the same through a bare parameter
    ("theta - q", 'q = "90 deg"\n', False),   # the unit says what it is
    ("theta - pi/2", "", False),
    ("theta + 6", "", False),                 # under a turn: radians may well be meant
    ("theta - pi/2", 'f = "-90"\n', True),   # (QA 20) a torsional spring's free angle, through a parameter
    ("2*(theta - 45)", "", True),             # (QA 20) inside a product
    ("theta - 4 - q", 'q = "86"\n', True),   # (QA 20) one constant written in two terms
])
def test_a_bare_number_beyond_a_turn_in_an_orientation_is_refused(solver_cli, tmp_path, orientation, parameter,
                                                                  refused) -> None:
    """QA 19 #5: orientation = "theta - 90" was read as 90 rad with no word (the bar hung 5157 deg
    off), while a bare number is refused for a coordinate's value and for --set."""
    text = open("tests/data/multibody/pin_bar.toml", encoding="utf-8").read()
    old = 'orientation = "theta - pi/2"'
    assert text.count(old) == 1 and text.count("[parameters]\n") == 1
    text = text.replace(old, f'orientation = "{orientation}"').replace("[parameters]\n", "[parameters]\n" + parameter)
    if parameter.startswith("f ="):
        text += '[[loads]]\nkind = "torsional_spring"\nbodies = ["ground", "bar"]\nstiffness = "m*g*L"\nfree_angle = "f"\n'
    where = "loads[1].free_angle:" if parameter.startswith("f =") else "bodies[0].orientation:"
    path = tmp_path / "s.toml"
    path.write_text(text, encoding="utf-8")
    code, out, err = solver_cli("solve", str(path))
    if refused:
        assert (code, out, err.count("\n")) == (2, "", 1), err
        assert where in err and "bare number in an angle is radians" in err and "14.3 turns" in err, err
    else:
        assert code == 0, err


# QA 20 #1: a prescribed angle's motion and a rolling contact's position_angle get the angle checks.
@pytest.mark.parametrize("scene, old, new, parameter, key, refusal", [
    ("tests/data/multibody/driven_coord.toml", 'motion = "w*t + al*t**2/2"', 'motion = "w*t + al*t**2/2 + 90"', "",
     "coordinates.th.motion:", "bare number in an angle is radians"),
    ("tests/data/multibody/driven_coord.toml", 'motion = "w*t + al*t**2/2"', 'motion = "w*t + al*t**2/2 + q"',
     'q = "50 percent"\n', "parameters.q:", "not an angle"),
    ("tests/data/multibody/driven_coord.toml", 'motion = "w*t + al*t**2/2"', 'motion = "w*t + al*t**2/2 + q"',
     'q = "90 deg"\n', None, None),
    ("tests/data/multibody/disk_in_bowl.toml", 'position_angle = "psi"', 'position_angle = "psi - 90"', "",
     "joints[0].position_angle:", "bare number in an angle is radians"),
    ("tests/data/multibody/disk_in_bowl.toml", 'position_angle = "psi"', 'position_angle = "psi - q"',
     'q = "50 percent"\n', "parameters.q:", "not an angle"),
])
def test_a_prescribed_motion_and_a_position_angle_are_checked_as_angles(solver_cli, tmp_path, scene, old, new,
                                                                        parameter, key, refusal) -> None:
    """QA 20 #1: th = { motion = "w*t + al*t**2/2 + 90" } turned the crank 90 rad further with no word,
    and a percent parameter there was 0.5 rad; orientation = "theta - 90" was refused. A parameter
    with its angle unit stays taken."""
    text = open(scene, encoding="utf-8").read()
    assert text.count(old) == 1 and text.count("[parameters]\n") == 1
    path = tmp_path / "s.toml"
    path.write_text(text.replace(old, new).replace("[parameters]\n", "[parameters]\n" + parameter), encoding="utf-8")
    code, out, err = solver_cli("solve", str(path))
    if refusal is None:
        assert code == 0, err
    else:
        assert (code, out, err.count("\n")) == (2, "", 1), err
        assert key in err and refusal in err, err


def test_a_frequency_in_an_angle_is_refused_without_2_pi(solver_cli, tmp_path) -> None:
    """QA 20 #1: al = "1 Hz/s" in driven_coord's [parameters] was taken as 1 rad/s^2 (--set refused it),
    and slider_crank's omega = "15.9155 Hz" in the motor's angle = "omega*t" turned the crank at
    15.9 rad/s instead of 100. Hz counts cycles of 2 pi rad: both are refused as --set refuses a
    rate in Hz, while 2*pi*f*t turns the crank at 2 pi x 15.9155 rad/s (by hand)."""
    import json

    cases = [("tests/data/multibody/driven_coord.toml", 'al = "2 rad/s^2"', 'al = "1 Hz/s"', None,
              ["parameters.al:", "is a frequency per time", '"1 rev/s^2"', "coordinates.th.motion", "2*pi*al"]),
             ("data/scenes/slider_crank.toml", 'omega   = "100 rad/s"', 'omega = "15.9155 Hz"', None,
              ["parameters.omega:", "is a frequency", '"15.9155 rev/s"', "'omega*t' at joints[1].angle"]),
             ("data/scenes/slider_crank.toml", 'omega   = "100 rad/s"', 'f = "15.9155 Hz"', ('"omega*t"', '"2*pi*f*t"'),
              None)]
    for scene, old, new, also, words in cases:
        text = open(scene, encoding="utf-8").read()
        assert text.count(old) == 1
        text = text.replace(old, new)
        if also:
            assert text.count(also[0]) == 1
            text = text.replace(*also)
        path = tmp_path / "s.toml"
        path.write_text(text, encoding="utf-8")
        if words is not None:
            code, out, err = solver_cli("solve", str(path))
            assert (code, out, err.count("\n")) == (2, "", 1), err
            assert all(w in err for w in words), err
            continue
        code, out, err = solver_cli("kinematics", str(path), "--json")
        assert code == 0, err
        omega = json.loads(out)["bodies"]["crank"]["omega"]
        # the crank's rate is the motor's, d(2 pi f t)/dt; rtol: a few float64 roundings
        assert omega["unit"] == "rad/s" and omega["value"] == pytest.approx(2 * math.pi * 15.9155, rel=1e-12)


def _hz_scene(tmp_path, scene: str, replacements) -> str:
    """``scene`` with each (old, new) of ``replacements`` made once, written to tmp_path."""
    text = open(scene, encoding="utf-8").read()
    for old, new in replacements:
        assert text.count(old) == 1, old
        text = text.replace(old, new)
    path = tmp_path / "s.toml"
    path.write_text(text, encoding="utf-8")
    return str(path)


@pytest.mark.parametrize("scene, replacements, omega", [
    # slider_crank's motor turns at d(angle)/dt = f * turn = 15.9155 Hz x 2 pi rad
    ("data/scenes/slider_crank.toml", [('omega   = "100 rad/s"', 'f = "15.9155 Hz"\nturn = "1 rev"'),
                                       ('"omega*t"', '"f*t*turn"')], 2 * math.pi * 15.9155),
    ("data/scenes/slider_crank.toml", [('omega   = "100 rad/s"', 'f = "15.9155 Hz"\nturn = "360 deg"'),
                                       ('"omega*t"', '"turn*f*t"')], 2 * math.pi * 15.9155),
    # th = A sin(2 pi f t): at t = 0, th_dot = A 2 pi f with A = 30 deg = pi/6 rad, f = 2 Hz
    ("tests/data/multibody/driven_coord.toml",
     [('al = "2 rad/s^2"', 'f = "2 Hz"\nA = "30 deg"\nturn = "1 rev"'),
      ('"w*t + al*t**2/2"', '"A*sin(turn*f*t)"')], math.pi / 6 * 2 * math.pi * 2),
])
def test_a_cycle_given_as_an_angle_parameter_counts_cycles(solver_cli, tmp_path, scene, replacements, omega) -> None:
    """QA 22 #4: the Hz rule took only pi as what turns cycles into an angle, and refused correct
    scenes whose cycle is a parameter in an angle unit (turn = "1 rev" or "360 deg")."""
    import json

    code, out, err = solver_cli("kinematics", _hz_scene(tmp_path, scene, replacements), "--json")
    assert code == 0, err
    got = json.loads(out)["bodies"]["crank"]["omega"]
    # rtol: a few float64 roundings
    assert got["unit"] == "rad/s" and got["value"] == pytest.approx(omega, rel=1e-12)


@pytest.mark.parametrize("value, hz", [("15.9155 rev/s", "15.9155 Hz"), ("100 rad/s", "15.9155 Hz"),
                                       ("954.93 rpm", "15.9155 Hz")])
def test_set_of_a_cycle_count_in_an_angular_unit_is_refused(solver_cli, tmp_path, value, hz) -> None:
    """QA 22 #5: slider_crank with f = "15.9155 Hz" and angle = "2*pi*f*t" turned the crank 2 pi times
    too fast, silently, after --set f="15.9155 rev/s" (pint reads it as 100 per second). In 2*pi*f*t
    f counts cycles: an angular velocity is refused, asking for Hz (15.9155 rev/s = 100 rad/s
    = 954.93 rpm = 15.9155 Hz by hand)."""
    path = _hz_scene(tmp_path, "data/scenes/slider_crank.toml",
                     [('omega   = "100 rad/s"', 'f = "15.9155 Hz"'), ('"omega*t"', '"2*pi*f*t"')])
    code, out, err = solver_cli("solve", path, "--set", f"f={value}")
    assert (code, out, err.count("\n")) == (2, "", 1), err
    assert "--set f:" in err and f"{value!r} is an angular velocity" in err and "'2*pi*f*t' at joints[1].angle" in err
    assert f'"{hz}"' in err, err


@pytest.mark.parametrize("given", ["954.93 rpm", "100 rad/s"])
def test_a_cycle_count_given_in_an_angular_unit_in_the_file_is_refused(solver_cli, tmp_path, given) -> None:
    """QA 23 #2: the rule held only for a parameter given in Hz, so f = "954.93 rpm" in the file with
    angle = "2*pi*f*t" turned the crank at 2 pi x 100 rad/s, silently (as --set f="954.93 rpm" on the
    Hz file is refused). In 2*pi*f*t f counts cycles, however the file gives it: refused, naming
    parameters.f and asking for Hz (954.93 rpm = 100 rad/s = 15.9155 Hz by hand)."""
    path = _hz_scene(tmp_path, "data/scenes/slider_crank.toml",
                     [('omega   = "100 rad/s"', f'f = "{given}"'), ('"omega*t"', '"2*pi*f*t"')])
    code, out, err = solver_cli("solve", path)
    assert (code, out, err.count("\n")) == (2, "", 1), err
    assert ": parameters.f:" in err and "'2*pi*f*t' at joints[1].angle" in err and '"15.9155 Hz"' in err, err


def test_set_of_a_frequency_read_as_radians_takes_an_angular_unit(solver_cli, tmp_path) -> None:
    """The other role of the same rule: where the file reads a frequency as radians per time
    (omega*t, refused in Hz), --set of omega in rad/s is what the term needs and is taken."""
    import json

    path = _hz_scene(tmp_path, "data/scenes/slider_crank.toml", [('omega   = "100 rad/s"', 'omega = "15.9155 Hz"')])
    code, out, err = solver_cli("kinematics", path, "--set", "omega=100 rad/s", "--json")
    assert code == 0, err
    assert json.loads(out)["bodies"]["crank"]["omega"]["value"] == pytest.approx(100, rel=1e-12)  # rtol: roundings
