"""Tests for the scene's ``[output_units]`` across the commands (solver/output_units.py).

Reference values
----------------
Every expected value is a closed form evaluated here, converted with the exact
definitions of the US customary units (never with pint, which the product uses):

* ``FT = 0.3048`` m per ft (international yard and pound agreement, 1959);
* ``LBF = 4.4482216152605`` N per lbf (0.45359237 kg x 9.80665 m/s**2, by definition);
* ``FT_LBF = 1.3558179483314004`` N*m per ft*lbf (FT * LBF).

Scenes:

* a slender bar of mass m, length L on a smooth incline of angle beta, held at its end A
  by a slider (normal force N, moment M_s): s_ddot = g sin(beta), N = m g cos(beta),
  M_s = m g cos(beta) L / 2 (the weight's moment about A, the bar lying along the incline);
  A = s (cos beta, -sin beta), so v_A = s_dot (cos beta, -sin beta) and
  a_A = s_ddot (cos beta, -sin beta);
* a simple pendulum (point mass m on a massless arm L): stiffness of the potential
  V'' = m g L [N*m/rad], generalized mass m L**2 [kg*m**2].

Tolerance: the solver evaluates the same closed forms in floating point (a linear solve,
sums of a few terms), so the relative difference is round-off, ~1e-15; 1e-9 leaves room
and still catches any wrong factor (the smallest unit slip, m vs ft, is a factor 3.28).
"""
from __future__ import annotations

import json
import math
import re
from pathlib import Path

import pytest

from solver.__main__ import main
from solver.output_units import output_unit

FT = 0.3048  # m per ft, exact by definition (1959 agreement)
LBF = 4.4482216152605  # N per lbf, exact by definition (0.45359237 kg * 9.80665 m/s**2)
FT_LBF = 1.3558179483314004  # N*m per ft*lbf = FT * LBF
REL = 1e-9  # round-off of a few float operations is ~1e-15; a unit slip is a factor >= 3

M, L, BETA, G = 5.0, 2.0, math.radians(30.0), 9.81
S, S_DOT = 1.0, 2.0  # the incline's state [m, m/s]

INCLINE = f"""
name = "incline_bar"
[parameters]
m = "{M} kg"
L = "{L} m"
beta = "30 deg"
g = "{G} m/s^2"
[coordinates]
s = {{ value = "{S} m", rate = "{S_DOT} m/s" }}
[[bodies]]
name = "bar"
orientation = "-beta"
position = {{ point = "A", at = ["s*cos(beta)", "-s*sin(beta)"] }}
reference_point = "A"
points = {{ A = ["0", "0"], B = ["L", "0"] }}
elements = [{{ kind = "slender_bar", mass = "m", from = "A", to = "B" }}]
[[joints]]
kind = "slider"
name = "incline"
point = "bar:A"
angle = "-beta"
reactions = ["N", "M_s"]
relative_angle = "-beta"
[[loads]]
kind = "gravity"
g = "g"
[output_units]
force = "lbf"
moment = "ft*lbf"
length = "ft"
"""

PENDULUM_US = """
name = "pend_us"
[parameters]
m = "2 kg"
L = "1 m"
g = "9.81 m/s^2"
[coordinate]
name = "theta"
value = "10 deg"
rate = "0 rad/s"
[body]
orientation = "theta - pi/2"
reference_point = "O"
[points]
O = ["0","0"]
T = ["L","0"]
[[elements]]
kind = "point_mass"
mass = "m"
at = "T"
[[constraints]]
kind = "pivot"
point = "O"
[[loads]]
kind = "gravity"
g = "g"
[output_units]
force = "lbf"
moment = "ft*lbf"
length = "ft"
"""


def _run(capsys: pytest.CaptureFixture[str], *args: str) -> str:
    status = main(list(args))
    out = capsys.readouterr().out
    assert status == 0
    return out


@pytest.fixture
def incline(tmp_path: Path) -> str:
    path = tmp_path / "incline.toml"
    path.write_text(INCLINE)
    return str(path)


def test_eom_solve_and_kinematics_print_in_the_scenes_units(incline: str, capsys: pytest.CaptureFixture[str]) -> None:
    # Regression: eom printed M_s as "42.4785 m * N" (the moment key was matched on the exact
    # text "N*m"), solve printed s_ddot in m/s**2, kinematics printed m, m/s and m/s**2.
    n, m_s, s_ddot = M * G * math.cos(BETA), M * G * math.cos(BETA) * L / 2, G * math.sin(BETA)
    direction = (math.cos(BETA), -math.sin(BETA))

    at_state = json.loads(_run(capsys, "eom", incline, "--json"))["reactions_at_state"]
    assert at_state["M_s"]["unit"] == "ft*lbf" and at_state["N"]["unit"] == "lbf"
    assert at_state["M_s"]["value"] == pytest.approx(m_s / FT_LBF, rel=REL)
    assert at_state["N"]["value"] == pytest.approx(n / LBF, rel=REL)
    text = _run(capsys, "eom", incline)
    assert f"= {m_s / FT_LBF:.6g} ft*lbf at the state" in text and "m * N" not in text

    unknowns = json.loads(_run(capsys, "solve", incline, "--json"))["unknowns"]
    assert unknowns["s_ddot"]["unit"] == "ft/s**2"
    assert unknowns["s_ddot"]["value"] == pytest.approx(s_ddot / FT, rel=REL)
    assert f"state   s = {S / FT:.6g} ft, s_dot = {S_DOT / FT:.6g} ft/s" in _run(capsys, "solve", incline)

    kin = json.loads(_run(capsys, "kinematics", incline, "--json"))
    a = kin["points"]["bar:A"]
    expected = {"position": (S, "ft"), "velocity": (S_DOT, "ft/s"), "acceleration": (s_ddot, "ft/s**2")}
    for what, (size, unit) in expected.items():
        assert a[what]["unit"] == unit
        assert a[what]["value"] == pytest.approx([size * d / FT for d in direction], rel=REL)
    assert kin["state"]["s"] == {"value": pytest.approx(S / FT, rel=REL), "unit": "ft"}
    text = _run(capsys, "kinematics", incline)
    assert " m/s" not in text and " m\n" not in text and "ft/s**2" in text


def test_frequency_derives_stiffness_and_inertia_units(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    # Regression: stiffness printed in N*m/rad and the generalized mass in kg*m**2 although the
    # scene set moment = "ft*lbf" and length = "ft". Stiffness = moment/rad; the moment of
    # inertia = moment * s**2 (the scene gives no mass unit but a moment unit: ft*lbf*s**2, the
    # slug*ft**2 of US texts, not the mixed kg*ft**2).
    scene = tmp_path / "pend_us.toml"
    scene.write_text(PENDULUM_US)
    m, arm, g = 2.0, 1.0, 9.81
    payload = json.loads(_run(capsys, "frequency", str(scene), "--json"))
    assert payload["stiffness"]["unit"] == "ft*lbf/rad"
    assert payload["stiffness"]["value"] == pytest.approx(m * g * arm / FT_LBF, rel=REL)
    assert payload["mass"]["unit"] == "ft*lbf*s**2"
    assert payload["mass"]["value"] == pytest.approx(m * arm**2 / FT_LBF, rel=REL)  # kg*m**2 = N*m*s**2
    text = _run(capsys, "frequency", str(scene))
    assert "N*m/rad" not in text and "kg*m**2" not in text and "ft*lbf/rad" in text


@pytest.mark.parametrize(("si", "units", "expected"), [
    ("m * N", {"moment": "ft*lbf"}, "ft*lbf"),            # any spelling pint reads as N*m
    ("m * N", {}, "N*m"),                                  # unconverted, spelled as documented
    ("N*m/rad", {"moment": "ft*lbf"}, "ft*lbf/rad"),
    ("kg*m**2", {"mass": "lb", "length": "ft"}, "lb*ft**2"),
    ("kg*m**2", {"force": "lbf"}, "kg*m**2"),              # neither part named: SI stays
    ("kg*m**2", {"moment": "ft*lbf", "length": "ft"}, "ft*lbf*s**2"),  # no mass unit: from the moment's
    ("kg*m**2", {"mass": "lb", "moment": "ft*lbf"}, "lb*m**2"),  # a mass unit given: mass * length**2
    ("m/s", {"length": "ft", "time": "min"}, "ft/s"),      # rates stay per second
    ("m/s**2", {"acceleration": "g0"}, "g0"),              # an explicit key wins
    ("N/m", {"force": "lbf", "length": "inch"}, "lbf/inch"),
    ("Hz", {"time": "min"}, "Hz"),                         # no rule: unchanged
])
def test_output_unit_rules(si: str, units: dict, expected: str) -> None:
    assert output_unit(si, units) == expected


def test_precision_prints_in_the_scenes_units_without_losing_digits(incline: str,
                                                                   capsys: pytest.CaptureFixture[str]) -> None:
    # Regression: precision printed every value in SI whatever [output_units] said. It now
    # converts by the exact decimal definitions of the units, so a 30-digit answer keeps its
    # 30 digits: the closed forms below (exact data: m = 5, g = 9.81, beta = 30 deg, L = 2),
    # evaluated at 40 digits, agree with the printed text to 2 units of its 30th digit.
    import mpmath

    payload = json.loads(_run(capsys, "precision", incline, "--precision", "mpmath", "--dps", "30", "--json"))
    unknowns = payload["solutions"]["mpmath"]["unknowns"]
    with mpmath.workdps(40):
        ft, lbf = mpmath.mpf("0.3048"), mpmath.mpf("4.4482216152605")  # exact definitions (see top)
        weight_normal = 5 * mpmath.mpf("9.81") * mpmath.sqrt(3) / 2  # m g cos(beta) [N]
        expected = {"N": (weight_normal / lbf, "lbf"),
                    "M_s": (weight_normal * 2 / 2 / (ft * lbf), "ft*lbf"),  # m g cos(beta) L / 2
                    "s_ddot": (mpmath.mpf("9.81") / 2 / ft, "ft/s**2")}  # g sin(beta)
        for name, (value, unit) in expected.items():
            assert unknowns[name]["unit"] == unit
            assert abs(mpmath.mpf(unknowns[name]["text"]) - value) <= 2 * mpmath.mpf(10) ** -29 * abs(value)


BLOCK_ON_SPRING = """
name = "block_spring"
[parameters]
m = "2 kg"
k = "200 N/m"
[coordinates]
x = { value = "0.1 m", rate = "0 m/s" }
[ground.points]
A0 = ["0", "0"]
[[bodies]]
name = "block"
orientation = "0"
position = { point = "A", at = ["x", "0"] }
points = { A = ["0", "0"] }
elements = [{ kind = "point_mass", mass = "m", at = "A" }]
[[joints]]
kind = "slider"
name = "floor"
point = "block:A"
angle = "0"
relative_angle = "0"
reactions = ["N", "M_s"]
[[loads]]
kind = "spring"
name = "s"
stiffness = "k"
between = ["block:A", "ground:A0"]
[output_units]
force = "lbf"
length = "ft"
"""


def test_frequency_of_a_length_coordinate(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    # Regression: a block on a spring (x, a length) printed its stiffness k as "200 N*m/rad" and
    # its mass m as "21.5 kg*ft**2", the units of an angle coordinate. For a length coordinate
    # V'' = k [N/m -> force/length] and M = m [kg]; omega_n = sqrt(k / m) = 10 rad/s.
    scene = tmp_path / "block.toml"
    scene.write_text(BLOCK_ON_SPRING)
    payload = json.loads(_run(capsys, "frequency", str(scene), "--json"))
    assert payload["stiffness"]["unit"] == "lbf/ft"
    assert payload["stiffness"]["value"] == pytest.approx(200.0 * FT / LBF, rel=REL)
    assert payload["mass"] == {"value": pytest.approx(2.0, rel=REL), "unit": "kg"}
    # the equilibrium x = 0 comes from a root search that stops within ~1e-15 m of it
    assert payload["equilibrium"] == {"value": pytest.approx(0.0, abs=1e-12), "unit": "ft"}
    assert payload["omega_n"]["value"] == pytest.approx(math.sqrt(200.0 / 2.0), rel=REL)


# A ladder of mass m, length L: end A on a rough floor (mu_s = mu_k = MU), end B on a smooth
# wall; theta is its angle with the floor. Sticking at rest: N_A = m g, and moments about A give
# the wall's N_B = m g cot(theta) / 2 = |F_A|. Over a run the only force that works apart from
# gravity is the floor's friction, so its work is the change of T + V with
# T = m L**2 theta_dot**2 / 6 (G at mid-length, I_G = m L**2 / 12) and V = m g L sin(theta) / 2.
LADDER_M, LADDER_L, MU = 15.0, 3.0, 0.4
LADDER_US = f"""
name = "ladder_us"
[parameters]
m = "{LADDER_M} kg"
L = "{LADDER_L} m"
mu = "{MU}"
g = "{G} m/s^2"
[coordinates]
theta = {{ value = "60 deg", rate = "0 rad/s" }}
[[bodies]]
name = "ladder"
orientation = "pi - theta"
reference_point = "A"
points = {{ A = ["0", "0"], B = ["L", "0"] }}
elements = [{{ kind = "slender_bar", mass = "m", from = "A", to = "B" }}]
[[joints]]
kind = "rail"
name = "floor"
point = "ladder:A"
angle = "0"
reaction = "N_A"
one_sided = true
friction = "F_A"
friction_coefficient = "mu"
[[joints]]
kind = "rail"
name = "wall"
point = "ladder:B"
angle = "-pi/2"
reaction = "N_B"
one_sided = true
[[loads]]
kind = "gravity"
g = "g"
[output_units]
force = "lbf"
length = "ft"
moment = "ft*lbf"
"""


def test_contact_sentences_and_friction_work_print_in_the_scenes_units(tmp_path: Path,
                                                                        capsys: pytest.CaptureFixture[str]) -> None:
    # Regression: the contacts' sentences said "friction F_A = -mu_k N_A = -52.5536 N" beside a
    # table in lbf, and simulate printed friction_work_floor in J beside v_slip in ft/s.
    scene = tmp_path / "ladder_us.toml"
    scene.write_text(LADDER_US)
    weight = LADDER_M * G

    def needs(theta_deg: float) -> str:  # |F_A| and mu_s N_A of the sticking ladder, in lbf
        f = weight / math.tan(math.radians(theta_deg)) / 2
        return f"|F_A| = {f / LBF:.6g} lbf", f"mu_s N_A = {MU * weight / LBF:.6g} lbf"

    holds = _run(capsys, "solve", str(scene))
    assert "sticks: {} <= {}".format(*needs(60.0)) in holds
    rejected = _run(capsys, "explain", str(scene), "--set", "theta=45 deg")
    assert "floor sticking needs {} > {}".format(*needs(45.0)) in rejected
    for text in (holds, rejected, _run(capsys, "solve", str(scene), "--set", "theta=45 deg")):
        assert not re.search(r"\d N\b", text)  # no force left in newtons

    run = json.loads(_run(capsys, "simulate", str(scene), "--set", "theta=45 deg", "--t-end", "0.5", "--json"))
    last = run["final"]
    assert last["theta"]["unit"] == "rad" and last["friction_work_floor"]["unit"] == "ft*lbf"
    theta, rate = last["theta"]["value"], last["theta_dot"]["value"]
    work = (LADDER_M * LADDER_L**2 * rate**2 / 6
            + weight * LADDER_L / 2 * (math.sin(theta) - math.sin(math.radians(45.0))))
    # the work is integrated with the motion (rtol 1e-9 by default): 1e-6 leaves room for its
    # error and still catches J for ft*lbf (a factor 1.36)
    assert last["friction_work_floor"]["value"] == pytest.approx(work / FT_LBF, rel=1e-6)


def test_a_value_given_in_the_output_unit_comes_back_as_given(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """QA 15 #11: `kinematics --json` echoed x = "0.5 ft" as 0.49999999999999994 ft and x_dot = "1 ft/s" as
    0.9999999999999999 ft/s (the trip through SI). Converted values are rounded to 15 significant digits
    (float64 holds 15.95), so the decimals given come back exactly; every command prints through the one
    conversion, so the simulate CSV's first row is checked too. No tolerance: exact decimals."""
    scene = tmp_path / "cart_ft.toml"
    scene.write_text((Path("data/scenes/cart_pendulum.toml")).read_text() + '\n[output_units]\nlength = "ft"\n')
    sets = ("--set", "x=0.5 ft", "--set", "x_dot=1 ft/s", "--set", "theta=0.1 rad")
    state = json.loads(_run(capsys, "kinematics", str(scene), *sets, "--json"))["state"]
    assert (state["x"]["value"], state["x"]["unit"]) == (0.5, "ft")
    assert (state["x_dot"]["value"], state["x_dot"]["unit"]) == (1.0, "ft/s")
    csv = tmp_path / "run.csv"
    _run(capsys, "simulate", str(scene), *sets, "--t-end", "0.01", "--out", str(csv))
    header, first = csv.read_text().splitlines()[:2]
    row = dict(zip(header.split(","), first.split(",")))
    assert row["x [ft]"] == "0.5" and row["x_dot [ft/s]"] == "1.0"
