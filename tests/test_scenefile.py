"""Tests for the scene loader (solver/scenefile.py) and the shipped scenes.

Each class of bad input is made by editing one line of a shipped example
scene, so every case differs from a valid file in exactly the way it names;
the test checks that the loader refuses it with a SceneError whose single
line names the file, the key path and the problem.
"""
from __future__ import annotations

from pathlib import Path

import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from solver.errors import SceneError
from solver.scene import Scene
from solver.scenefile import load_scene
from solver.units import Q_

SCENES = Path(__file__).resolve().parents[1] / "data" / "scenes"
SLIDING_BAR = SCENES / "sliding_bar.toml"
DISK_BAR = SCENES / "disk_bar.toml"

# Paper Example 1 data (paper text above Eq. 16): m_b = 50 lbm, l_b = 4 ft,
# beta = 45 deg, released from rest at theta = 30 deg.
EXAMPLE1 = {"m_b": Q_(50, "lb"), "l_b": Q_(4, "ft"), "beta": Q_(45, "deg")}


def _sym(name: str) -> sp.Symbol:
    return sp.Symbol(name, real=True)


# -- the two examples load with the paper's structure ---------------------------------------


def test_sliding_bar_loads_with_paper_data() -> None:
    scene = load_scene(SLIDING_BAR)
    assert isinstance(scene, Scene)
    for name, expected in EXAMPLE1.items():
        # exact decimal data: compared in SI to 1e-12 relative (float conversion only)
        assert scene.parameters[name].to_base_units().magnitude == pytest.approx(
            expected.to_base_units().magnitude, rel=1e-12
        )
    assert scene.state_si() == pytest.approx((sp.pi.evalf() / 6, 0.0), rel=1e-12)
    assert scene.default_point == "A"
    assert set(scene.points) == {"A", "B", "G"}
    assert scene.reaction_names() == ("R_A", "R_B")
    assert scene.orientation == sp.pi - _sym("theta")
    (bar,) = scene.elements
    assert bar.kind == "slender_bar" and bar.dims["length"] == _sym("l_b")
    assert list(bar.center) == [_sym("l_b") / 2, 0]
    rail_b = scene.constraints[1]
    assert rail_b.point == "B" and rail_b.angle == -_sym("beta")
    assert scene.output_units["force"] == "lbf"


def test_disk_bar_loads_with_paper_structure() -> None:
    scene = load_scene(DISK_BAR)
    assert scene.default_point == "P"
    assert scene.reaction_names() == ("F_f", "F_n")
    assert scene.orientation == -_sym("theta")  # Eq. 33: omega = -theta_dot k
    contact = scene.points["C"]
    assert contact.frame == "instant" and contact.relative_to == "P"
    assert list(contact.coords) == [0, -_sym("r_d")]  # Eq. 32: r_C/P = -r_d j
    assert list(scene.points["Q"].coords) == [0, -_sym("l_b") / 2]
    disk, bar = scene.elements
    assert disk.kind == "uniform_disk" and disk.dims["radius"] == _sym("r_d")
    assert bar.dims["length"] == _sym("l_b")
    (rolling,) = scene.constraints
    assert rolling.kind == "rolling" and rolling.element == "disk"
    force = [load for load in scene.loads if load.kind == "force"][0]
    assert force.point == "P" and list(force.components) == [_sym("F_a"), 0]


@pytest.mark.parametrize("path", sorted(SCENES.glob("*.toml")), ids=lambda p: p.name)
def test_every_shipped_scene_loads(path: Path) -> None:
    from solver.io.scenes import load_system

    system = load_system(path)
    if system.contacts:  # contacts that stick, slip or separate: some regime must hold at the state
        from solver.analyses.regimes import find_regime

        assert find_regime(system).regimes.keys() == {j.name for j in system.contacts}
    else:
        system.validate()
    for body in system.bodies.values():  # each body's reference point is one of its points (or G)
        assert body.default_point in body.point_names()


# -- overrides -------------------------------------------------------------------------------


def test_overrides_replace_parameters_and_state() -> None:
    scene = load_scene(SLIDING_BAR, {"beta": "90 deg", "theta_dot": "1.5 rad/s", "theta": "0.2 rad"})
    assert scene.parameters["beta"].to("deg").magnitude == pytest.approx(90)
    assert scene.state_si() == pytest.approx((0.2, 1.5))


@pytest.mark.parametrize(
    ("overrides", "message"),
    [
        ({"beta": "2 m"}, "--set beta: '2 m' is a length, but beta is"),
        ({"m_b": "3 ft"}, "--set m_b: '3 ft' is a length"),
        ({"theta": "1 rad/s"}, "--set theta:"),
        ({"zeta": "1"}, "--set zeta: unknown name 'zeta'"),
        ({"m_b": "-3 kg"}, "--set m_b: mass must not be negative"),
        ({"m_b": "50 pounds of feathers"}, "--set m_b: unknown unit"),
        ({"beta": "0 deg"}, "impossible geometry"),  # B's rail becomes parallel to A's
    ],
)
def test_bad_overrides(overrides: dict[str, str], message: str) -> None:
    with pytest.raises(SceneError) as info:
        load_scene(SLIDING_BAR, overrides)
    assert message in str(info.value)
    assert str(info.value).startswith(str(SLIDING_BAR) + ": ")


# -- bad input: one edit each ---------------------------------------------------------------

BAR = SLIDING_BAR.read_text()
DISK = DISK_BAR.read_text()


def _edit(text: str, old: str, new: str) -> str:
    assert old in text, old  # the edit must apply, or the case tests nothing
    return text.replace(old, new, 1)


BAD = [
    # (label, scene text, key path, words of the message)
    ("unknown top key", "colour = 'red'\n" + BAR, "colour", "valid keys for a scene file"),
    ("unknown element key", _edit(BAR, 'to   = "B"', 'to   = "B"\nwidth = "l_b"'),
     "elements[0].width", "valid keys for a slender_bar element: angle, center, from"),
    ("mass in ft", _edit(BAR, '"50 lbm"', '"50 ft"'), "elements[0].mass", "is a length, but a mass is needed"),
    ("g as a speed", _edit(BAR, '"32.174 ft/s^2"', '"32.174 ft/s"'), "loads[0].g", "an acceleration is needed"),
    ("angle given a length", _edit(BAR, 'angle    = "-beta"', 'angle    = "-l_b"'),
     "constraints[1].angle", "is a length, but an angle"),
    ("dimension mismatch in a sum", _edit(BAR, 'G = ["l_b/2", "0"]', 'G = ["l_b/2 + beta", "0"]'),
     "points.G[0]", "adds"),
    ("bare number as length", _edit(BAR, 'B = ["l_b", "0"]', 'B = ["4", "0"]'), "points.B[0]", "bare number"),
    ("missing parameter", _edit(BAR, 'l_b  = "4 ft"', ''), "points.B[0]", "unknown name 'l_b'"),
    # (the period's compiled potential differences use symbols named so: a parameter of that
    # name would be silently taken for one of them)
    ("name of an internal symbol", _edit(BAR, 'l_b  = "4 ft"', 'l_b  = "4 ft"\n__c0 = "1 ft"'),
     "parameters.__c0", "names starting with '__' are reserved"),
    # (explain writes a body's angular acceleration as alpha: a parameter alpha was printed as,
    # and merged with, that unknown, giving a wrong equation)
    ("parameter named alpha", _edit(BAR, 'l_b  = "4 ft"', 'l_b  = "4 ft"\nalpha = "1 rad"'),
     "parameters.alpha", "the angular acceleration alpha"),
    ("missing key", _edit(BAR, 'mass = "m_b"', ''), "elements[0]", "missing key 'mass'"),
    ("negative mass", _edit(BAR, '"50 lbm"', '"-50 lbm"'), "parameters.m_b", "must not be negative"),
    ("massless body", _edit(BAR, '"50 lbm"', '"0 lbm"'), "elements", "the body has no mass"),
    ("zero length", _edit(BAR, '"4 ft"', '"0 ft"'), "parameters.l_b", "must be positive"),
    ("duplicate element", BAR + '\n[[elements]]\nname = "bar"\nkind = "point_mass"\nmass = "m_b"\nat = "A"\n',
     "elements[1].name", "duplicate element name 'bar'"),
    ("duplicate reaction", _edit(BAR, 'reaction = "R_B"', 'reaction = "R_A"'),
     "constraints[1].reaction", "duplicate reaction name 'R_A'"),
    ("reference point not in body", _edit(BAR, 'reference_point = "A"', 'reference_point = "O"'),
     "body.reference_point", "'O' is not a point of the body (points: A, B, G)"),
    ("element at unknown point", _edit(BAR, 'to   = "B"', 'to   = "Z"'), "elements[0].to", "unknown point 'Z'"),
    ("rail at unknown point", _edit(BAR, 'point    = "B"', 'point    = "Z"'), "constraints[1].point", "unknown point 'Z'"),
    ("rolling bar", _edit(DISK, 'element         = "disk"', 'element         = "bar"'),
     "constraints[0].element", "cannot roll"),
    ("parallel rails", _edit(BAR, 'angle    = "-beta"', 'angle    = "pi"'),
     "constraints[1].angle", "impossible geometry"),
    ("one rail only", BAR.split("[[constraints]]          # B")[0] + '[[loads]]\nkind = "gravity"\ng = "g"\n',
     "constraints", "placement is not determined"),
    ("over-constrained", BAR + '\n[[constraints]]\nkind = "pivot"\npoint = "G"\n', "constraints", "over-constrained"),
    ("unknown element kind", _edit(BAR, '"slender_bar"', '"rod"'), "elements[0].kind",
     "valid kinds: slender_bar, uniform_disk, thin_ring, rectangular_plate, point_mass, semicircular_disk"),
    ("unknown constraint kind", _edit(BAR, 'kind     = "rail"', 'kind     = "slot"'), "constraints[0].kind",
     "valid kinds: rail, rolling, pivot"),
    ("unknown load kind", _edit(BAR, 'kind = "gravity"', 'kind = "wind"'), "loads[0].kind",
     "valid kinds: gravity, force, couple"),
    ("code in an expression", _edit(BAR, 'angle    = "-beta"', "angle    = \"__import__('os').system('true')\""),
     "constraints[1].angle", "not allowed"),
    ("bad unit", _edit(BAR, '"50 lbm"', '"50 lbz"'), "parameters.m_b", "unknown unit 'lbz'"),
    ("output unit of wrong dimension", _edit(BAR, 'force  = "lbf"', 'force  = "ft"'),
     "output_units.force", "is a length, but force needs a force"),
    ("unknown output unit key", _edit(BAR, 'force  = "lbf"', 'speed  = "ft/s"'), "output_units.speed", "valid keys"),
    ("rate without time", _edit(BAR, 'rate  = "0 rad/s"', 'rate  = "0 rad"'), "coordinate.rate", "angular velocity"),
    ("force of wrong dimension", _edit(DISK, 'components = ["F_a", "0"]', 'components = ["F_a*t", "0"]'),
     "loads[1].components[0]", "a force is needed"),
    ("position disagrees with rolling", _edit(DISK, 'orientation     = "-theta"',
     'orientation     = "-theta"\nposition = { point = "P", at = ["r_d*theta", "2*r_d"] }'),
     "body.position", "disagrees with constraints[0] (rolling)"),
]


@pytest.mark.parametrize(("label", "text", "key", "words"), BAD, ids=[case[0] for case in BAD])
def test_bad_scene_is_refused_with_key_path(tmp_path: Path, label: str, text: str, key: str, words: str) -> None:
    path = tmp_path / "scene.toml"
    path.write_text(text)
    with pytest.raises(SceneError) as info:
        load_scene(path)
    message = str(info.value)
    assert message.startswith(f"{path}: {key}: "), message
    assert words in message, message
    assert "\n" not in message


def test_toml_syntax_error_names_the_line(tmp_path: Path) -> None:
    path = tmp_path / "broken.toml"
    path.write_text(_edit(BAR, 'm_b  = "50 lbm"', 'm_b  = 50 lbm"'))
    line = 1 + BAR.splitlines().index('m_b  = "50 lbm"          # bar mass')
    with pytest.raises(SceneError, match=rf"TOML syntax error: .*line {line}, column"):
        load_scene(path)


def test_missing_file_is_a_scene_error(tmp_path: Path) -> None:
    with pytest.raises(SceneError, match="cannot read the scene file"):
        load_scene(tmp_path / "nope.toml")


def test_consistent_explicit_position_is_accepted(tmp_path: Path) -> None:
    # x_P = r_d theta, y_P = r_d is exactly what the rolling contact implies (Eq. 31).
    path = tmp_path / "placed.toml"
    path.write_text(_edit(DISK, 'orientation     = "-theta"',
                          'orientation     = "-theta"\nposition = { point = "P", at = ["r_d*theta", "r_d"] }'))
    scene = load_scene(path)
    assert scene.position == ("P", sp.Matrix([_sym("r_d") * _sym("theta"), _sym("r_d")]))


# -- properties --------------------------------------------------------------------------------

# Units of several dimensions; only those of the right dimension may load.
UNITS = ["kg", "lbm", "slug", "g", "ft", "m", "s", "N", "lbf", "deg", "ft/s^2", "m/s**2", ""]
MASS_UNITS = {"kg", "lbm", "slug", "g"}
ACCELERATION_UNITS = {"ft/s^2", "m/s**2"}


@pytest.mark.parametrize("unit", UNITS)
def test_dimension_of_each_parameter_is_checked_where_used(unit: str) -> None:
    # m_b is used as an element mass, g as gravity: each must have its dimension.
    for name, valid in (("m_b", MASS_UNITS), ("g", ACCELERATION_UNITS)):
        overrides = {name: f"7 {unit}".strip()}
        if unit in valid:
            load_scene(SLIDING_BAR, overrides)
        else:
            with pytest.raises(SceneError, match=rf"--set {name}: .* is "):
                load_scene(SLIDING_BAR, overrides)


@settings(max_examples=30)  # one small TOML load each (~20 ms)
@given(st.integers(-4, 4), st.floats(-1e-3, 1e-3))
def test_rails_are_refused_exactly_when_parallel(turns: int, offset_deg: float) -> None:
    # B's rail at angle -beta is parallel to A's (angle 0) iff beta is a
    # multiple of 180 deg. The loader's tolerance is 1e-9 on sin(beta); the
    # smallest non-zero offset tried is 1e-6 deg = 1.7e-8 rad, well above it.
    beta = 180.0 * turns + (offset_deg if abs(offset_deg) >= 1e-6 else 0.0)
    overrides = {"beta": f"{beta!r} deg"}
    if beta % 180.0 == 0.0:
        with pytest.raises(SceneError, match="impossible geometry"):
            load_scene(SLIDING_BAR, overrides)
    else:
        assert load_scene(SLIDING_BAR, overrides).parameters["beta"].to("deg").magnitude == pytest.approx(beta)


def test_byte_order_mark_is_accepted(tmp_path: Path) -> None:
    # Regression: a UTF-8 file with a byte-order mark was a "TOML syntax error at line 1, column 1".
    path = tmp_path / "bom.toml"
    path.write_bytes(b"\xef\xbb\xbf" + (SCENES / "sliding_bar.toml").read_bytes())
    assert load_scene(path).parameters == load_scene(SCENES / "sliding_bar.toml").parameters


PENDULUM_G = """name = "pendulum"
[parameters]
m = "2 kg"
L = "0.8 m"
g = "9.81 m/s^2"
[coordinates]
theta = { value = "30 deg", rate = "1 rad/s" }
[ground.points]
O = ["0", "0"]
[[bodies]]
name = "bar"
orientation = "theta - pi/2"
points = { O = ["0", "0"], E = ["L", "0"], G = ["GX", "0"] }
elements = [{ kind = "slender_bar", mass = "m", from = "O", to = "E" }]
[[joints]]
kind = "pin"
name = "O"
connects = ["ground:O", "bar:O"]
"""


@pytest.mark.parametrize("name, words", [
    ("alpha", "'alpha' is reserved (a function, a constant, time t, or the angular acceleration alpha)"),
    ("theta_ddot", "'theta_ddot' is a rate of coordinate 'theta' (its velocity or acceleration)"),
])
def test_a_parameter_cannot_take_a_name_the_solver_writes(tmp_path: Path, solver_cli, name: str, words: str) -> None:
    """Regression: a torsional spring's free angle given as a parameter named alpha was accepted,
    and explain then printed ``-9.573*alpha [alpha] = 6.548``: the parameter merged with the unknown
    angular acceleration alpha (a parameter theta_ddot alike). Refused at load, at the parameter."""
    text = PENDULUM_G.replace("GX", "L/2").replace('g = "9.81 m/s^2"', f'g = "9.81 m/s^2"\n{name} = "1 rad"')
    path = tmp_path / "pend.toml"
    path.write_text(text, encoding="utf-8")
    code, _, err = solver_cli("explain", str(path))
    assert code == 2 and err.count("\n") == 1
    assert err.startswith(f"error: {path}: parameters.{name}: {words}"), err


@pytest.mark.parametrize("gx,refused", [("L", True), ("L/2", False), ("L - L/2", False)])
def test_a_point_named_G_must_be_the_mass_centre(tmp_path: Path, solver_cli, gx: str, refused: bool) -> None:
    """G names the mass centre in every equation (Eqs. 1-2, 10): a user point G elsewhere (the bar's
    tip, L) is refused at load in one line naming the file and the place; a G at the mass centre
    (L/2 of a uniform bar), however written, is accepted."""
    text = PENDULUM_G.replace("GX", gx)
    path = tmp_path / "pend_G.toml"
    path.write_text(text, encoding="utf-8")
    code, _, err = solver_cli("solve", str(path))
    if refused:
        assert code == 2 and err.count("\n") == 1
        assert err.startswith(f"error: {path}: bodies[0].points.G: G is reserved for the mass centre"), err
    else:
        assert code == 0, err


def test_the_one_body_format_checks_G_too(tmp_path: Path) -> None:
    """The same rule in the one-body format (the sliding bar's G moved to the end A)."""
    text = SLIDING_BAR.read_text(encoding="utf-8")
    path = tmp_path / "bar.toml"
    path.write_text(text.replace("G = [", "G = [\"0\", \"0\"]\nG_old = [", 1), encoding="utf-8")
    with pytest.raises(SceneError, match=r"points\.G: G is reserved for the mass centre"):
        load_scene(path)
