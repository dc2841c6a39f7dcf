"""Bad multibody input on the command line: exit status 2, nothing on stdout,
and ONE line on stderr naming the file and the joint (or body) at fault, with
the freedom count or the condition number where they are the reason.

The scenes are variations of data/scenes/slider_crank.toml written to tmp_path:
each variation is a textual edit of the shipped file, checked to have applied.
"""
from __future__ import annotations

import json
import math
import re
from pathlib import Path

import pytest

from solver.analyses.instant import solve_instant
from solver.errors import SceneError, SingularConfigurationError
from solver.io.scenes import load_system

SLIDER_CRANK = Path(__file__).resolve().parent.parent / "data" / "scenes" / "slider_crank.toml"

CYLINDER_SLIDER = 'kind = "slider"                  # the cylinder: the piston slides along the x axis without turning'
CYLINDER_REACTIONS = 'reactions = ["N_cyl", "M_cyl"]'
PISTON = 'name = "piston"\nreference_point = "B"'
CRANK = 'name = "crank"\nreference_point = "O"'
MOTOR_START = '[[joints]]\nkind = "motor"'
CRANK_PIN = '[[joints]]\nkind = "pin"                     # crank pin'


def variant(tmp_path: Path, edits: list[tuple[str, str]], extra: str = "", name: str = "variant.toml") -> Path:
    """The slider-crank file with each (old, new) replaced exactly once, plus ``extra`` appended."""
    text = SLIDER_CRANK.read_text()
    for old, new in edits:
        assert text.count(old) == 1, f"edit does not apply: {old!r}"
        text = text.replace(old, new)
    path = tmp_path / name
    path.write_text(text + extra)
    return path


def one_line_error(solver_cli, path: Path, *argv: str) -> str:
    code, out, err = solver_cli("solve", str(path), "--json", *argv)
    assert code == 2, f"exit {code}; stdout {out[:300]!r}; stderr {err!r}"
    assert out == ""  # nothing half-written
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert "Traceback" not in err and "internal error" not in err
    assert lines[0].startswith(f"error: {path}:") or lines[0].startswith(f"error: {path.name}:"), lines[0]
    return lines[0]


def dead_centre(tmp_path: Path, guesses=('"-1 deg"', '"2 deg"')) -> Path:
    """The piston driven by an actuator through dead centre at t = 0 (x_B = r + l - c t^2);
    the crank turns freely on its bearing: its angle theta is a dependent coordinate."""
    motor_block = SLIDER_CRANK.read_text()
    motor = motor_block[motor_block.index(MOTOR_START):motor_block.index(CRANK_PIN)]
    return variant(tmp_path, [
        ('phi = { guess = "-10 deg" }', f'phi = {{ guess = {guesses[0]} }}\ntheta = {{ guess = {guesses[1]} }}'),
        ('omega   = "100 rad/s"', 'c = "50 m/s^2"'),
        ('time = "0.004 s"', 'time = "0 s"'),
        (CRANK, 'name = "crank"\norientation = "theta"\nreference_point = "O"'),
        (motor, ""),
    ], extra='\n[[joints]]\nkind = "actuator"\nname = "push"\npoint = "piston:B"\n'
             'position = "r + l - c*t^2"\nforce = "F_push"\n', name="dead_centre.toml")


# --------------------------------------------------------------------------- freedom counts
def test_extra_pin_is_over_constrained_with_the_count(solver_cli, tmp_path):
    path = variant(tmp_path, [], extra='\n[[joints]]\nkind = "pin"\nname = "B2"\nconnects = ["rod:B", "piston:B"]\n')
    line = one_line_error(solver_cli, path)
    # 3 bodies x 3 freedoms - (2 + 1 + 2 + 2 + 2 + 2) = -2 freedoms, none described
    assert "over-constrained" in line and "B2 (pin, 2)" in line
    assert "11 removed" in line and "= -2" in line and "describe 0" in line


def test_rail_with_given_piston_orientation_is_under_constrained_with_the_count(solver_cli, tmp_path):
    path = variant(tmp_path, [(CYLINDER_SLIDER, 'kind = "rail"'), (CYLINDER_REACTIONS, 'reaction = "N_cyl"'),
                              (PISTON, 'name = "piston"\norientation = "0"\nreference_point = "B"')])
    line = one_line_error(solver_cli, path)
    # 9 freedoms - 8 removed = 1 left; phi less its one closure equation describes 0
    assert "under-constrained" in line and "cylinder (rail, 1)" in line
    assert "8 removed" in line and "= 1" in line and "describe 0" in line


def test_rail_instead_of_slider_is_under_constrained_with_the_count(solver_cli, tmp_path):
    path = variant(tmp_path, [(CYLINDER_SLIDER, 'kind = "rail"'), (CYLINDER_REACTIONS, 'reaction = "N_cyl"')])
    line = one_line_error(solver_cli, path)
    assert "piston" in line or "cylinder" in line
    assert "under-constrained" in line and "8 removed" in line and "= 1" in line


def test_rail_instead_of_slider_names_the_piston(solver_cli, tmp_path):
    """What the message already does well: one line, exit 2, the body that cannot be placed."""
    path = variant(tmp_path, [(CYLINDER_SLIDER, 'kind = "rail"'), (CYLINDER_REACTIONS, 'reaction = "N_cyl"')])
    assert "'piston'" in one_line_error(solver_cli, path)


# --------------------------------------------------------------------------- singular configuration
def test_dead_centre_from_exact_guesses_is_singular(solver_cli, tmp_path):
    """Guesses exactly at dead centre: the closure is met at once and the system is singular."""
    line = one_line_error(solver_cli, dead_centre(tmp_path, ('"0 deg"', '"0 deg"')))
    assert "singular configuration" in line and "condition number" in line and "'push'" in line


def test_dead_centre_is_singular(solver_cli, tmp_path):
    line = one_line_error(solver_cli, dead_centre(tmp_path))
    assert "singular configuration" in line and "condition number" in line and "'push'" in line


def test_dead_centre_is_singular_through_the_api(tmp_path):
    system = load_system(dead_centre(tmp_path))
    with pytest.raises(SingularConfigurationError, match="condition number"):
        solve_instant(system)


# --------------------------------------------------------------------------- inconsistent prescribed motion
def test_two_motors_prescribing_different_angles(solver_cli, tmp_path):
    path = variant(tmp_path, [], extra='\n[[joints]]\nkind = "motor"\nname = "drive2"\nbodies = ["ground", "crank"]\n'
                                       'angle = "omega*t + 0.1"\ntorque = "M_drive2"\n')
    line = one_line_error(solver_cli, path)
    assert "'drive2'" in line and "not satisfied" in line


def test_motor_angle_disagrees_with_the_prescribed_orientation(solver_cli, tmp_path):
    path = variant(tmp_path, [('phi = { guess = "-10 deg" }', 'phi = { guess = "-10 deg" }\ntheta = { motion = "2*omega*t" }'),
                              (CRANK, 'name = "crank"\norientation = "theta"\nreference_point = "O"')])
    line = one_line_error(solver_cli, path)
    assert "'drive'" in line and "not satisfied" in line


def test_unreachable_actuator_position(solver_cli, tmp_path):
    """An actuator prescribing the piston beyond reach (x_B > r + l): no assembly exists."""
    path = dead_centre(tmp_path)
    path.write_text(path.read_text().replace('position = "r + l - c*t^2"', 'position = "1.5*(r + l) - c*t^2"'))
    line = one_line_error(solver_cli, path)
    assert "'push'" in line and "cannot be satisfied" in line


def test_the_same_refusal_through_the_api(tmp_path):
    """The Python API raises the one-line error's class (SceneError), with the same text."""
    path = variant(tmp_path, [], extra='\n[[joints]]\nkind = "pin"\nname = "B2"\nconnects = ["rod:B", "piston:B"]\n')
    with pytest.raises(SceneError, match=r"over-constrained: .*B2 \(pin, 2\).*= -2"):
        solve_instant(load_system(path))


# --------------------------------------------------------------------------- options
def test_setting_the_rate_of_a_dependent_coordinate_is_refused(solver_cli):
    code, out, err = solver_cli("solve", str(SLIDER_CRANK), "--set", "phi_dot=5 rad/s", "--json")
    assert code == 2 and out == "" and len(err.strip().splitlines()) == 1, (code, out[:200], err)
    assert "--set phi_dot" in err


def test_unknown_body_in_point_names_the_flag(solver_cli):
    code, out, err = solver_cli("solve", str(SLIDER_CRANK), "--point", "nobody:A")
    assert code == 2 and out == "" and len(err.strip().splitlines()) == 1
    assert "--point nobody:A" in err and "'nobody'" in err


def test_unknown_point_of_a_body_names_the_flag(solver_cli):
    code, out, err = solver_cli("solve", str(SLIDER_CRANK), "--point", "rod:Q")
    assert code == 2 and out == "" and len(err.strip().splitlines()) == 1
    assert "--point" in err and "'Q'" in err


def prescribed_crank(tmp_path: Path) -> Path:
    """The crank's angle as a prescribed coordinate theta (motion = omega t); the motor drives what it prescribes."""
    return variant(tmp_path, [('phi = { guess = "-10 deg" }', 'phi = { guess = "-10 deg" }\ntheta = { motion = "omega*t" }'),
                              (CRANK, 'name = "crank"\norientation = "theta"\nreference_point = "O"'),
                              ('angle = "omega*t"\n', '')], name="prescribed.toml")


@pytest.mark.parametrize("override", ["theta=10 deg", "theta_dot=1 rad/s"])
def test_setting_a_prescribed_coordinate_is_refused(solver_cli, tmp_path, override):
    code, out, err = solver_cli("solve", str(prescribed_crank(tmp_path)), "--set", override, "--json")
    assert code == 2 and out == "" and len(err.strip().splitlines()) == 1, (code, out[:200], err)
    assert f"--set {override.split('=')[0]}" in err


# -- scene-file messages (QA round 10, item 14) ---------------------------------------------------

SPRING_K = ('omega   = "100 rad/s"', 'omega   = "100 rad/s"\nk = "200 N/m"\nc = "3 N*s/m"')


def spring(ends: str, stiffness: str = "k", kind: str = "spring", key: str = "stiffness") -> str:
    return f'\n[[loads]]\nkind = "{kind}"\nbetween = [{ends}]\n{key} = "{stiffness}"\n'


@pytest.mark.parametrize("text", ["", 'name = "x"\n[parameters]\nm = "1 kg"\n'])
def test_a_file_in_neither_format_says_so(solver_cli, tmp_path, text):
    # Regression: "parameters: missing key 'parameters'" (empty file) and "coordinate: missing key
    # 'coordinate'" (only [parameters]): the one-body format was assumed.
    path = tmp_path / "neither.toml"
    path.write_text(text)
    line = one_line_error(solver_cli, path)
    assert "neither the multibody format ([coordinates] and [[bodies]])" in line
    assert "nor the one-body format ([coordinate] and [body])" in line


def test_a_stiffness_of_the_wrong_dimension_names_the_quantity(solver_cli, tmp_path):
    # Regression: "... is a force, but [mass] / [time] ** 2 is needed here".
    path = variant(tmp_path, [('omega   = "100 rad/s"', 'omega   = "100 rad/s"\nk = "200 N"')],
                   spring('"ground:O", "piston:B"'))
    line = one_line_error(solver_cli, path)
    assert "loads[1].stiffness" in line and "a stiffness (force per length, e.g. N/m) is needed" in line


@pytest.mark.parametrize(("extra", "key", "words"), [
    (spring('"ground:O", "piston:B"', "-k"), "loads[1].stiffness", "a stiffness must not be negative"),
    (spring('"ground:O", "piston:B"', "-c", "damper", "coefficient"),
     "loads[1].coefficient", "a damping coefficient must not be negative"),
    (spring('"piston:B", "piston:B"'), "loads[1].between", "both ends are piston:B"),
])
def test_a_negative_spring_or_one_from_a_point_to_itself_is_refused(solver_cli, tmp_path, extra, key, words):
    # Regression: both were accepted silently (a spring of zero length has no direction).
    line = one_line_error(solver_cli, variant(tmp_path, [SPRING_K], extra))
    assert f": {key}: {words}" in line


# -- loop closure (QA round 10, item 15) ------------------------------------------------------------

FOUR_BAR = """
name = "fourbar"
[parameters]
a = "0.1 m"
b = "{b}"
c = "0.3 m"
d = "0.35 m"
m2 = "1 kg"
m3 = "2 kg"
m4 = "1.5 kg"
W = "10 rad/s"
g = "9.81 m/s^2"
[coordinates]
th2 = {{ motion = "pi/3 + W*t" }}
th3 = {{ guess = "20 deg" }}
th4 = {{ guess = "80 deg" }}
[ground.points]
O2 = ["0", "0"]
O4 = ["d", "0"]
[[bodies]]
name = "crank"
orientation = "th2"
points = {{ O2 = ["0", "0"], A = ["a", "0"] }}
elements = [{{ kind = "slender_bar", mass = "m2", from = "O2", to = "A" }}]
[[bodies]]
name = "coupler"
orientation = "th3"
points = {{ A = ["0", "0"], B = ["b", "0"] }}
elements = [{{ kind = "slender_bar", mass = "m3", from = "A", to = "B" }}]
[[bodies]]
name = "rocker"
orientation = "th4"
points = {{ O4 = ["0", "0"], B = ["c", "0"] }}
elements = [{{ kind = "slender_bar", mass = "m4", from = "O4", to = "B" }}]
[[joints]]
kind = "pin"
name = "O2"
connects = ["ground:O2", "crank:O2"]
[[joints]]
kind = "motor"
name = "drive"
bodies = ["ground", "crank"]
torque = "T"
[[joints]]
kind = "pin"
name = "A"
connects = ["crank:A", "coupler:A"]
[[joints]]
kind = "pin"
name = "B"
connects = ["coupler:B", "rocker:B"]
[[joints]]
kind = "pin"
name = "O4"
connects = ["ground:O4", "rocker:O4"]
[[loads]]
kind = "gravity"
g = "g"
"""


def test_a_loop_that_can_never_close_is_said_to(solver_cli, tmp_path):
    # Regression: a 5 mm coupler (the crank pin A is 0.312 m from O4 at th2 = 60 deg, beyond the
    # coupler plus rocker's 0.305 m) was reported as "no configuration near the dependent
    # coordinates' guesses satisfies it; check the prescribed motion and the guesses".
    path = tmp_path / "fb_noclose.toml"
    path.write_text(FOUR_BAR.format(b="0.005 m"))
    line = one_line_error(solver_cli, path)
    assert "the loop cannot close there, the geometry does not allow it" in line
    assert "near the dependent coordinates' guesses" not in line


def test_a_dependent_angle_is_reported_in_the_turn_of_its_guess(solver_cli, tmp_path):
    # Regression: --set th3="200 deg" gave th3 = 656.006 deg, 1.3 turns from the guess. Reference:
    # the loop itself, a e(th2) + b e(th3) = (d, 0) + c e(th4) with th2 = 60 deg, checked at the
    # printed state to 1e-12 m (the closure is solved to ~1e-13 of the lengths' size); each
    # reported angle lies within half a turn of its guess (th4's guess stays 80 deg).
    path = tmp_path / "fourbar.toml"
    path.write_text(FOUR_BAR.format(b="0.4 m"))
    code, out, err = solver_cli("solve", str(path), "--set", "th3=200 deg", "--json")
    assert code == 0, err
    state = json.loads(out)["state"]
    th2, th3, th4 = math.radians(60.0), state["th3"]["value"], state["th4"]["value"]
    assert abs(th3 - math.radians(200.0)) <= math.pi and abs(th4 - math.radians(80.0)) <= math.pi
    gap = (0.1 * math.cos(th2) + 0.4 * math.cos(th3) - 0.35 - 0.3 * math.cos(th4),
           0.1 * math.sin(th2) + 0.4 * math.sin(th3) - 0.3 * math.sin(th4))
    assert max(map(abs, gap)) <= 1e-12


def test_a_loop_that_closes_away_from_the_guesses_names_where(solver_cli, tmp_path):
    # From th3 = 180 deg, th4 = 90 deg Newton's method does not reach the loop's closure; the
    # starts around the circles do, and the message names that configuration. Reference: the
    # loop a e(th2) + b e(th3) = (d, 0) + c e(th4) at th2 = 60 deg, at the printed angles (6
    # digits: 5e-4 deg, under 4e-6 m on the 0.4 m coupler; 1e-5 m allows it).
    path = tmp_path / "fourbar.toml"
    path.write_text(FOUR_BAR.format(b="0.4 m"))
    code, out, err = solver_cli("solve", str(path), "--set", "th3=180 deg", "--set", "th4=90 deg")
    assert code == 2 and out == "" and len(err.strip().splitlines()) == 1, err
    found = re.search(r"but one does at th3 = (\S+) deg, th4 = (\S+) deg: give guesses near it", err)
    assert found, err
    th2, th3, th4 = math.radians(60.0), *(math.radians(float(v)) for v in found.groups())
    gap = (0.1 * math.cos(th2) + 0.4 * math.cos(th3) - 0.35 - 0.3 * math.cos(th4),
           0.1 * math.sin(th2) + 0.4 * math.sin(th3) - 0.3 * math.sin(th4))
    assert max(map(abs, gap)) <= 1e-5


# --------------------------------------------------------------------------- a spring of zero length
MULTIBODY = Path(__file__).resolve().parent / "data" / "multibody"


@pytest.mark.parametrize("argv", [
    ("solve", "cart_spring.toml", "x=-1 m"),  # anchor S at x = -d = -1 m: length |d + x| = 0
    ("precision", "cart_spring.toml", "x=-1 m"),
    ("explain", "cart_spring.toml", "x=-1 m"),
    ("frequency", "rot_arm.toml", "r=0 m"),  # the collar on the hub, where the spring is anchored
    ("eom", "cart_spring.toml", "x=-1 m"),  # QA 11: printed a term over Abs(d + x), 0 at the state
    ("eom", "rot_arm.toml", "r=0 m"),
])
def test_a_spring_of_zero_length_is_named_not_the_joints(solver_cli, argv):
    """QA 11: where a spring's two points coincide its direction d/|d| is 0/0, so the right-hand
    side is undefined, not the matrix: the message named the joints the matrix's (meaningless)
    null vector involved (the pin 'P', the motor 'drive'). It must name the spring instead; `eom`
    refuses there the same way rather than print equations undefined at the state."""
    command, scene, setting = argv
    path = MULTIBODY / scene
    code, out, err = solver_cli(command, str(path), "--set", setting)
    assert code == 2 and out == "", (code, out[:300])
    assert err.count("\n") == 1 and err.startswith(f"error: {path}: singular configuration at "), err
    assert "spring 'spring_1' has zero length there" in err and "joint" not in err, err


def test_eom_answers_a_picometre_from_zero_length_as_solve_does(solver_cli):
    """eom refuses only where its printed forms are undefined, the exact zero length; at r = 1e-13 m
    (QA 13) it refused while solve answered. The collar's equation of motion holds r/|r| (the
    spring's direction from the hub), defined at every r but 0, so eom prints it."""
    code, out, err = solver_cli("eom", str(MULTIBODY / "rot_arm.toml"), "--set", "r=1e-13 m")
    assert code == 0 and err == "", err
    assert "equation of motion" in out and "r_ddot" in out
    code, _, _ = solver_cli("solve", str(MULTIBODY / "rot_arm.toml"), "--set", "r=1e-13 m")
    assert code == 0


SCENES = Path(__file__).resolve().parent.parent / "data" / "scenes"


def edited(tmp_path: Path, scene: str, old: str, new: str) -> Path:
    """``data/scenes/<scene>.toml`` with ``old`` replaced once by ``new``, written to tmp_path."""
    text = (SCENES / f"{scene}.toml").read_text()
    assert text.count(old) == 1, old
    path = tmp_path / f"{scene}.toml"
    path.write_text(text.replace(old, new))
    return path


def test_a_bare_zero_coordinate_value_needs_its_kind(solver_cli, tmp_path):
    """QA 13 #6: a bare "0" cannot tell a length from an angle. Without a rate that tells it, the
    value's (or guess's) own key is named and a unit asked for; with `rate = "0.5 m/s"` the
    coordinate is the length x = 0 m."""
    ladder = edited(tmp_path, "ladder_leaves_wall", 'x     = { guess = "1.4 m" }', 'x     = { guess = "0" }')
    line = one_line_error(solver_cli, ladder)
    assert "coordinates.x.guess: a bare 0" in line and '"0 m"' in line and '"0 deg"' in line
    cart = edited(tmp_path, "cart_pendulum", 'x     = { value = "0 m", rate = "0.5 m/s" }',
                  'x     = { value = "0", rate = "0" }')
    line = one_line_error(solver_cli, cart)
    assert "coordinates.x.value: a bare 0" in line
    cart.write_text(cart.read_text().replace('rate = "0" }', 'rate = "0.5 m/s" }'))
    code, out, err = solver_cli("solve", str(cart))
    assert code == 0 and "state   x = 0 m, x_dot = 0.5 m/s," in out, err


def test_a_bare_zero_rate_in_the_file_is_taken_as_on_set(solver_cli, tmp_path):
    """QA 13 #7: `rate = "0"` in either format is 0 rad/s, as `--set theta_dot=0` is (zero is
    zero in every unit); a bare nonzero rate is refused and echoed as typed ('2', not 2.0)."""
    cases = [("sliding_bar", 'rate  = "0 rad/s"', 'rate  = "{}"', "coordinate.rate"),
             ("cart_pendulum", 'theta = { value = "20 deg", rate = "0 rad/s" }',
              'theta = {{ value = "20 deg", rate = "{}" }}', "coordinates.theta.rate")]
    for scene, old, new, key in cases:
        path = edited(tmp_path, scene, old, new.format("0"))
        code, out, err = solver_cli("solve", str(path))
        assert code == 0 and "theta_dot = 0 rad/s" in out.splitlines()[1], err
        path = edited(tmp_path, scene, old, new.format("2"))
        line = one_line_error(solver_cli, path)
        assert f"{key}: '2' is" in line


@pytest.mark.parametrize("motion", ["0", "0*t", "0*omega*t"])
def test_a_motion_that_is_zero_at_every_time_names_its_key(solver_cli, tmp_path, motion):
    """A prescribed motion that is 0 at every t is 0 in every unit: it cannot tell a length from an
    angle. It was taken for an angle, and a slider's length coordinate then failed at the point
    that uses it, naming another key ('x' is an angle ..., at bodies[0].position.at[0]). Now the
    motion's own key is named, with what to write instead."""
    path = prescribed_crank(tmp_path)
    path.write_text(path.read_text().replace('theta = { motion = "omega*t" }', f'theta = {{ motion = "{motion}" }}'))
    line = one_line_error(solver_cli, path)
    assert "coordinates.theta.motion" in line and "does not tell an angle from a length" in line


@pytest.mark.parametrize("guess, branch", [("90 deg", -5.58686), ("-90 deg", -5.58686), ("270 deg", 185.587)])
def test_a_guess_where_the_closure_jacobian_vanishes_still_assembles(solver_cli, guess, branch):
    """QA 17 #2: slider_crank with the rod's guess at 90 deg, where the closure's Jacobian l cos(phi)
    vanishes: Newton's first step was 1e16 rad and the state printed phi = -1.02681e+18 deg (an angle
    with no digit left) with a full table of reactions. With each step turning an angle by at most
    1 rad, it reaches a branch of the loop, as the guesses 89 deg and 91 deg did. Reference: the
    rod's angle from the geometry by hand, sin(phi) = -r sin(theta) / l with the crank's theta =
    omega t at t = 0.004 s, omega = 100 rad/s, r = 0.05 m, l = 0.2 m (the scene's data); the
    printed 6 digits."""
    code, out, err = solver_cli("solve", str(SLIDER_CRANK), "--set", f"phi={guess}")
    assert code == 0, err
    theta = 100 * 0.004
    principal = math.degrees(math.asin(-0.05 * math.sin(theta) / 0.2))
    assert round(branch, 2) in (round(principal, 2), round(180 - principal, 2))
    assert f"phi = {branch:g} deg" in out.splitlines()[1], out.splitlines()[1]


# --------------------------------------------------------------------------- loads (QA 19 #3, #7)
PIN_BAR = Path(__file__).resolve().parent / "data" / "multibody" / "pin_bar.toml"
PENDULUM = PIN_BAR.read_text().split("[[loads]]")[0]  # the bar on its pin, m = 1 kg, L = 1 m, no load
GRAVITY = '[[loads]]\nkind = "gravity"\ng = "g"\n'


def test_a_tilted_gravity_direction_says_which_way_not_how_much(tmp_path):
    """direction = ["1", "-1"] is the unit vector (1, -1)/sqrt(2): before, the weight was sqrt(2)
    times too large. Reference by hand: about the pin, I_O alpha = (r_G/O x m g d)_z with
    I_O = m L^2/3 and r_G/O = (L/2)(sin theta, -cos theta), so
    alpha = 3 g (cos theta - sin theta) / (2 sqrt(2) L), with pin_bar's L = 1 m and theta = 30 deg.
    Tolerance: a few round-offs of O(10)."""
    path = tmp_path / "tilted.toml"
    path.write_text(PENDULUM + GRAVITY + 'direction = ["1", "-1"]\n')
    alpha = solve_instant(load_system(path)).unknowns["theta_ddot"].to("rad/s**2").magnitude
    theta = math.radians(30)
    assert alpha == pytest.approx(3 * 9.81 * (math.cos(theta) - math.sin(theta)) / (2 * math.sqrt(2) * 1.0), rel=1e-13)


def test_a_tiny_gravity_direction_is_a_direction_and_a_round_off_one_is_refused(solver_cli, tmp_path):
    """QA 20 #6: direction = ["1e-13", "0"] was refused as the zero vector (an absolute 1e-12 on a
    quantity with no scale); it is the x axis. Reference by hand, as the tilted test: gravity
    along +x gives alpha = 3 g cos(theta) / (2 L), L = 1 m, theta = 30 deg. Zero stays refused:
    exactly (s = 0 by --set) or to round-off (sin(b) at b = 180 deg is 1.2e-16 beside its term
    pi, within float64's error of 0)."""
    path = tmp_path / "tiny.toml"
    scene = PENDULUM.replace("[parameters]\n", '[parameters]\nb = "180 deg"\ns = "1"\n') + GRAVITY + 'direction = [X, "0"]\n'
    path.write_text(scene.replace("X", '"1e-13"'))
    alpha = solve_instant(load_system(path)).unknowns["theta_ddot"].to("rad/s**2").magnitude
    assert alpha == pytest.approx(3 * 9.81 * math.cos(math.radians(30)) / 2, rel=1e-13)  # (a few round-offs of 10)
    # QA 22: beside a component that is not, one that is 0 to round-off is 0, not a tilt: ["1e-13", "sin(b)"]
    # is the x axis (sin(b) = 1.2e-16 had tilted it by 50 deg)
    path.write_text(scene.replace('direction = [X, "0"]', 'direction = ["1e-13", "sin(b)"]'))
    alpha = solve_instant(load_system(path)).unknowns["theta_ddot"].to("rad/s**2").magnitude
    assert alpha == pytest.approx(3 * 9.81 * math.cos(math.radians(30)) / 2, rel=1e-13)
    for component, argv, words in (('"s"', ("--set", "s=0"), "the direction is the zero vector"),
                                   ('"sin(b)"', (), "the direction is the zero vector to round-off: sin(b) = 1.22e-16")):
        path.write_text(scene.replace("X", component))
        line = one_line_error(solver_cli, path, *argv)
        assert ": loads[0].direction: " in line and words in line, line


@pytest.mark.parametrize("extra,place,words", [
    (GRAVITY + 'direction = ["0", "0"]\n', "loads[0].direction", "the direction is the zero vector"),
    (GRAVITY + GRAVITY, "loads[1].name", "only one gravity load is allowed"),
    (GRAVITY + GRAVITY.replace('g = "g"', 'name = "weight"\ng = "g"'), "loads[1]", "a second gravity load"),
    (GRAVITY + '[[loads]]\nkind = "couple"\nname = "gravity"\nbody = "bar"\nmoment = "m*g*L"\n',
     "loads[1].name", "duplicate load name 'gravity'"),
    ('[[loads]]\nkind = "force"\npoint = "ground:O"\ncomponents = ["m*g", "0"]\n', "loads[0].point", "on the ground moves nothing"),
    ('[[loads]]\nkind = "couple"\nbody = "ground"\nmoment = "m*g*L"\n', "loads[0].body", "on the ground moves nothing"),
])
def test_loads_that_would_act_twice_or_on_nothing_are_refused(solver_cli, tmp_path, extra, place, words):
    """Each was accepted without a word: a pasted gravity block doubled g, a zero direction
    switched gravity off, a force on the ground did nothing."""
    path = tmp_path / "loads.toml"
    path.write_text(PENDULUM + extra)
    line = one_line_error(solver_cli, path)
    assert f": {place}: " in line and words in line, line


def test_a_load_on_two_ground_points_and_a_name_taken_first_by_another_load(solver_cli, tmp_path):
    """QA 20: a spring between two ground points was accepted (forces on the ground are refused);
    a couple named gravity before the gravity load was refused as if there were two gravity loads."""
    grounded = PENDULUM.replace('[ground.points]\nO = ["0", "0"]', '[ground.points]\nO = ["0", "0"]\nS = ["L", "0"]')
    assert grounded != PENDULUM
    path = tmp_path / "spring.toml"
    path.write_text(grounded + '[[loads]]\nkind = "spring"\nbetween = ["ground:O", "ground:S"]\nstiffness = "m*g/L"\n')
    line = one_line_error(solver_cli, path)
    assert ": loads[0].between: " in line and "both ends are on the ground" in line
    path.write_text(PENDULUM + '[[loads]]\nkind = "couple"\nname = "gravity"\nbody = "bar"\nmoment = "m*g*L"\n' + GRAVITY)
    line = one_line_error(solver_cli, path)
    assert ": loads[1].name: duplicate load name 'gravity'" in line and "only one gravity" not in line
