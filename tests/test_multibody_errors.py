"""Bad multibody input on the command line: exit status 2, nothing on stdout,
and ONE line on stderr naming the file and the joint (or body) at fault, with
the freedom count or the condition number where they are the reason.

The scenes are variations of data/scenes/slider_crank.toml written to tmp_path:
each variation is a textual edit of the shipped file, checked to have applied.
"""
from __future__ import annotations

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


def one_line_error(solver_cli, path: Path) -> str:
    code, out, err = solver_cli("solve", str(path), "--json")
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
