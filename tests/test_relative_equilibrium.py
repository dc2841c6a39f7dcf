"""``frequency`` with a motion prescribed in time (solver/analyses/modes.py).

Reference: a collar of mass m slides on an arm turned at the constant rate W in a
horizontal plane, a spring (k, free length L0) pulling it to the hub. In the turning frame
m r'' = m W^2 r - k (r - L0), free of t, so the relative equilibrium and the small
oscillations about it are exact closed forms (any dynamics text, rotating frames):
r_e = k L0 / (k - m W^2), omega_n^2 = k/m - W^2. With gravity in the plane of the arm the
collar's equation holds g sin(W t): time stays explicit and there is nothing to oscillate
about, which must be refused in one line.
"""
from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from solver.__main__ import main

ROT_ARM = """
name = "rot_arm"
[parameters]
m = "0.5 kg"
M = "2 kg"
L = "1 m"
k = "40 N/m"
L0 = "0.3 m"
W = "4 rad/s"
g = "9.81 m/s^2"
[coordinates]
theta = { motion = "W*t" }
r = { value = "0.4 m", rate = "0.5 m/s" }
[ground.points]
O = ["0", "0"]
[[bodies]]
name = "arm"
points = { O = ["0", "0"], E = ["L", "0"] }
elements = [{ kind = "slender_bar", mass = "M", from = "O", to = "E" }]
[[bodies]]
name = "collar"
position = { point = "C", at = ["r*cos(theta)", "r*sin(theta)"] }
points = { C = ["0", "0"] }
elements = [{ kind = "point_mass", mass = "m", at = ["0", "0"] }]
[[joints]]
kind = "pin"
name = "O"
connects = ["ground:O", "arm:O"]
[[joints]]
kind = "motor"
name = "drive"
bodies = ["ground", "arm"]
angle = "W*t"
torque = "T"
[[joints]]
kind = "slider"
name = "sl"
on = "arm"
point = "collar:C"
reactions = ["N", "Mc"]
[[loads]]
kind = "spring"
between = ["arm:O", "collar:C"]
stiffness = "k"
free_length = "L0"
"""

GRAVITY = '\n[[loads]]\nkind = "gravity"\ng = "g"\n'


def _run(capsys, *args):
    try:
        status = main(list(args))
    except SystemExit as stop:
        status = stop.code
    return (status, *capsys.readouterr())


@pytest.mark.parametrize("W", [4.0, 0.0, 7.5])
def test_turning_arm_relative_equilibrium_is_the_closed_form(tmp_path: Path, capsys, W: float) -> None:
    scene = tmp_path / "rot_arm.toml"
    scene.write_text(ROT_ARM)
    m, k, L0 = 0.5, 40.0, 0.3
    status, out, err = _run(capsys, "frequency", str(scene), "--set", f"W={W} rad/s", "--json")
    assert status == 0, err
    payload = json.loads(out)
    # 1e-9: the equilibrium is Newton's to round-off and omega_n^2 comes from a fourth-order
    # central difference, good to ~1e-11 relative (solver/analyses/modes.py)
    assert payload["equilibrium"]["value"] == pytest.approx(k * L0 / (k - m * W**2), rel=1e-9)
    assert payload["omega_n"]["value"] == pytest.approx(math.sqrt(k / m - W**2), rel=1e-9)
    assert payload["equilibrium_relative_to_prescribed_motion"] is True


def test_turning_arm_with_gravity_in_its_plane_is_refused_in_one_line(tmp_path: Path, capsys) -> None:
    scene = tmp_path / "rot_arm_g.toml"
    scene.write_text(ROT_ARM + GRAVITY)
    status, out, err = _run(capsys, "frequency", str(scene))
    assert status == 2 and out == ""
    assert err.count("\n") == 1 and str(scene) in err and "depend on time" in err


def test_a_spring_that_must_pass_its_anchor_to_reach_equilibrium(capsys):
    """QA 11: a 5 kg block on a vertical slider hung from a spring to S (k = 200 N/m, free length
    0.1 m), starting 0.05 m above S. The spring's length is |x|; below S, k (-x - 0.1) = m g gives the
    equilibrium x = -(0.1 + 5 * 9.81 / 200) = -0.34525 m, omega_n = sqrt(200 / 5) rad/s. The
    stiffness differentiates |x| twice (a DiracDelta at x = 0) and failed with an internal NameError.
    Tolerance 1e-9: Newton's round-off on numbers of order 1."""
    path = Path(__file__).parent / "data" / "multibody" / "vertical_spring.toml"
    assert main(["frequency", str(path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["equilibrium"]["value"] == pytest.approx(-(0.1 + 5 * 9.81 / 200), abs=1e-9)
    assert out["omega_n"]["value"] == pytest.approx(math.sqrt(200 / 5), rel=1e-9)


@pytest.mark.parametrize("length_unit", ["m", "ft"])
def test_the_equilibrium_is_printed_to_the_digits_it_is_known_to(tmp_path: Path, capsys, length_unit: str) -> None:
    """QA 17 #7: an equilibrium solved by Newton to about 1e-12 of its scale came out as
    0.375000000000024 ft (cart_us: -0.999999999999998 ft for a spring's 1 ft). Its digits below
    1e-12 of the scale are round-off: here r_e = k L0 / (k - m W^2) = 40 * 0.3 / 32 = 0.375 exactly
    (with L0 = 0.3 ft the same number of ft), and the JSON gives that decimal, in m and in ft."""
    from fractions import Fraction

    scene = tmp_path / "rot_arm.toml"
    text = ROT_ARM.replace('L0 = "0.3 m"', f'L0 = "0.3 {length_unit}"')
    if length_unit == "ft":
        text = text.replace('name = "rot_arm"', 'name = "rot_arm"\noutput_units = { length = "ft" }')
    scene.write_text(text)
    status, out, err = _run(capsys, "frequency", str(scene), "--json")
    assert status == 0, err
    exact = Fraction(40) * Fraction(3, 10) / (Fraction(40) - Fraction(1, 2) * 16)  # in L0's unit
    equilibrium = json.loads(out)["equilibrium"]
    assert equilibrium == {"value": float(exact), "unit": length_unit}
