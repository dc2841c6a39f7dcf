"""Every point the point advisor names is accepted by every command that takes ``--point``
(solver.formulations.resolve_points, the one place that reads it, makes a point named after a
joint, ``C_<joint>``, or after two reactions, ``BODY:I(R1,R2)``, a point of its body through the
worked solution's own rule, solver.explain.build.add_joint_point).

Reference: the mass-centre route (Eqs. 1-2), which takes no reference point, so it is
independent of the point under test. By Eq. 10 moments about any point of the body give the
same accelerations and reactions. Tolerances: the routes agree to round-off of a small linear
solve (~1e-13 relative), 1e-9 allows for the conditioning; printed numbers (explain's table,
6 significant figures; the diagram's labels, 4) are compared to half a unit of their last digit.
"""
from __future__ import annotations

import re
from pathlib import Path

import pytest

from solver.__main__ import main
from solver.analyses.instant import solve_instant
from solver.analyses.regimes import start_state
from solver.explain.advisor import rank_points
from solver.analyses.regimes import system_in_regime
from solver.explain.build import explain
from solver.io.scenes import load_system

ROOT = Path(__file__).resolve().parents[1]

RING_MASS = """
name = "ring_mass"
[parameters]
M = "2 kg"
R = "0.3 m"
m = "0.8 kg"
e = "0.2 m"
g = "9.81 m/s^2"
[coordinate]
name = "theta"
value = "30 deg"
rate = "2 rad/s"
[body]
orientation = "-theta"
reference_point = "C"
[points]
C = ["0", "0"]
Q = ["e", "0"]
[[elements]]
name = "hoop"
kind = "thin_ring"
mass = "M"
center = "C"
radius = "R"
[[elements]]
name = "lump"
kind = "point_mass"
mass = "m"
at = "Q"
[[constraints]]
kind = "rolling"
element = "hoop"
friction = "F"
normal = "N"
[[loads]]
kind = "gravity"
g = "g"
"""

DISK_PEND = (Path(__file__).parent / "data" / "multibody" / "disk_pend.toml").read_text(encoding="utf-8")

DBAR = """
name = "dbar"
[parameters]
m1 = "2 kg"
m2 = "1 kg"
L1 = "1 m"
L2 = "0.6 m"
g = "9.81 m/s^2"
[coordinates]
th1 = { value = "30 deg", rate = "1 rad/s" }
th2 = { value = "-20 deg", rate = "-2 rad/s" }
[ground.points]
O = ["0", "0"]
[[bodies]]
name = "upper"
orientation = "th1 - pi/2"
points = { O = ["0", "0"], A = ["L1", "0"] }
elements = [{ kind = "slender_bar", mass = "m1", from = "O", to = "A" }]
[[bodies]]
name = "lower"
orientation = "th2 - pi/2"
points = { A = ["0", "0"], B = ["L2", "0"] }
elements = [{ kind = "slender_bar", mass = "m2", from = "A", to = "B" }]
[[joints]]
kind = "pin"
name = "O"
connects = ["ground:O", "upper:O"]
[[joints]]
kind = "pin"
name = "A"
connects = ["upper:A", "lower:A"]
[[loads]]
kind = "gravity"
g = "g"
"""

# a disk on a 30 deg incline whose rolling closure does not hold at the state as written (its
# centre is placed off the contact at zero): a contact the regime search opens to start
DISK_SLIP = (Path(__file__).parent / "data" / "multibody" / "disk_slip.toml").read_text(encoding="utf-8")

SCENES = {"ring_mass": (RING_MASS, {}), "disk_pend": (DISK_PEND, {}), "dbar": (DBAR, {}),
          "incline_disk": (None, {}), "disk_slips": (DISK_SLIP, {}), "disk_rolls": (DISK_SLIP, {"mu": "0.5"})}


def _scene(tmp_path: Path, key: str) -> tuple[str, dict]:
    text, sets = SCENES[key]
    if text is None:
        return str(ROOT / "data" / "scenes" / f"{key}.toml"), sets
    path = tmp_path / f"{key}.toml"
    path.write_text(text)
    return str(path), sets


def _advised(path: str, sets: dict) -> list[str]:
    """``BODY:NAME`` of every point the advisor lists (in the contact regime that holds, as explain)."""
    system = load_system(path, sets)
    state = start_state(system)
    if system.contacts:
        system, _, _, state = system_in_regime(system, None)
    return [f"{body}:{c.name}" for body in system.bodies for c in rank_points(system, body, state)]


def _reference(path: str, sets: dict) -> dict[str, float]:
    solution = solve_instant(load_system(path, sets), None, "mass_center")
    return {k: float(q.magnitude) for k, q in solution.unknowns.items()}


@pytest.mark.parametrize("key", list(SCENES))
def test_solve_about_every_advised_point_gives_the_mass_centre_answers(tmp_path: Path, key: str) -> None:
    path, sets = _scene(tmp_path, key)
    reference = _reference(path, sets)
    points = _advised(path, sets)
    assert any(re.search(r":(C_|I\()", p) for p in points)  # the case under test: a point no scene names
    for point in points:
        got = solve_instant(load_system(path, sets), point)
        assert set(got.unknowns) == set(reference), point
        for name, value in reference.items():
            assert float(got.unknowns[name].magnitude) == pytest.approx(value, rel=1e-9, abs=1e-9), (point, name)


def _unnamed(points: list[str]) -> list[str]:
    return [p for p in points if re.search(r":(C_|I\()", p)]


@pytest.mark.parametrize("key", list(SCENES))
def test_explain_and_the_free_body_diagrams_take_every_point_the_advisor_names(tmp_path: Path, key: str) -> None:
    from solver.drawing import draw_system

    path, sets = _scene(tmp_path, key)
    reference = _reference(path, sets)
    for point in _unnamed(_advised(path, sets)):
        expl = explain(load_system(path, sets), point)
        step = next(s for sec in expl.sections for s in sec.steps if s.kind == "solution")
        for name, value, _unit in step.table.rows:  # 6 significant figures
            assert float(value) == pytest.approx(reference[name], rel=5e-6, abs=1e-9), (point, name)
        drawing = draw_system(load_system(path, sets), fbd=True, point=point)
        body, _, name = point.partition(":")
        assert drawing.point[body] == name
        labels = {i.name: i.label for i in drawing.items if i.kind == "force" and i.name in reference}
        assert labels, point
        for reaction, label in labels.items():  # "|O_x| = 9.672 N": 4 significant figures
            size = float(re.search(r"= (\S+)", label)[1])
            assert size == pytest.approx(abs(reference[reaction]), rel=5e-4, abs=1e-9), (point, label)
        import matplotlib.pyplot as plt

        plt.close(drawing.figure)


@pytest.mark.parametrize("command", [("solve",), ("explain",), ("draw", "--fbd", "-o", "fbd.svg"), ("precision",),
                                     ("simulate", "--t-end", "0.1"), ("friction",)])
def test_a_bad_point_on_a_contact_scene_is_one_plain_line(tmp_path: Path, capsys, command) -> None:
    # simulate and friction took any --point and went on (the answers do not depend on P, but a
    # typo must not pass for a point)
    path, _ = _scene(tmp_path, "disk_slips")
    extra = [str(tmp_path / a) if a.endswith(".svg") else a for a in command[1:]]
    try:
        status = main([command[0], path, *extra, "--point", "Z"])
    except SystemExit as stop:
        status = stop.code
    out, err = capsys.readouterr()
    assert status == 2 and out == ""
    assert err.count("\n") == 1 and "--point Z" in err and err.count("'Z'") == 1
    assert "regime" not in err and "Painlev" not in err


def test_simulate_about_an_advised_point_gives_the_default_motion(tmp_path: Path) -> None:
    from solver.analyses.motion import simulate_system

    # 1e-8: both runs integrate the same equations to rtol 1e-9 (they differ by round-off in each
    # step, which the integrator's step choice can amplify to about its tolerance)
    for key, point in (("disk_slips", "C_incline"), ("dbar", "upper:I(O_x,A_y)")):
        path, sets = _scene(tmp_path, key)
        runs = [simulate_system(load_system(path, sets), 0.3, samples=3, point=p) for p in (None, point)]
        for name, (column, _unit) in runs[0].columns.items():
            assert list(runs[1].columns[name][0]) == pytest.approx(list(column), rel=1e-8, abs=1e-10), (key, name)


def test_a_crossing_point_with_spaces_gives_the_mass_centre_answers(capsys) -> None:
    """QA 11: --point "crank:I(O_x, A_y)" (a space after the comma, as one writes it) was refused as
    not a point of the crank. Spaces inside I(...) are taken out; the answers are the mass-centre
    route's (its own reference point: none)."""
    import json

    path = str(ROOT / "data" / "scenes" / "slider_crank.toml")
    reference = _reference(path, {})
    assert main(["solve", path, "--point", "crank:I( O_x ,  A_y)", "--json"]) == 0
    got = json.loads(capsys.readouterr().out)
    assert got["point"] == "crank:I(O_x,A_y)"
    for name, value in reference.items():
        assert got["unknowns"][name]["value"] == pytest.approx(value, rel=1e-9, abs=1e-9), name


@pytest.mark.parametrize(("point", "why"), [
    ("crank:I(O2_x, A_y)", "'O2_x' is not a reaction"),  # no such reaction
    ("crank:I(O_x)", "'I(O_x)' is not of the form I(R1,R2)"),  # one reaction only
    ("I(O_x, B_y)", "O_x and B_y do not both act on one body"),  # on the crank and on the rod
])
def test_a_bad_crossing_point_names_the_form_expected(capsys, point: str, why: str) -> None:
    path = str(ROOT / "data" / "scenes" / "slider_crank.toml")
    try:
        status = main(["solve", path, "--point", point])
    except SystemExit as stop:
        status = stop.code
    out, err = capsys.readouterr()
    assert status == 2 and out == "" and err.count("\n") == 1 and err.startswith(f"error: {path}: --point ")
    assert why in err and "expected BODY:I(R1,R2)" in err and "crank: O_x, O_y, A_x, A_y" in err, err


def test_an_element_centre_the_advisor_lists_is_accepted_by_every_command(tmp_path: Path, capsys) -> None:
    """QA 12 #4: the advisor lists the slider-crank rod's element centre ``rod G_shank`` (the
    shank's mass centre, a point of the rod the scene does not name), yet ``--point rod:G_shank``
    was refused as not a point of the rod by solve, explain and draw --fbd. Each takes it now, with
    the mass-centre route's answers (solve: JSON to round-off, 1e-9 as above; explain's table and
    the diagram's labels to their printed digits)."""
    import json

    from solver.drawing import draw_system

    path = str(ROOT / "data" / "scenes" / "slider_crank.toml")
    reference = _reference(path, {})
    centres = [p for p in _advised(path, {}) if re.search(r":G_", p)]
    assert centres == ["rod:G_shank"]
    for point in centres:
        assert main(["solve", path, "--point", point, "--json"]) == 0
        got = json.loads(capsys.readouterr().out)["unknowns"]
        for name, value in reference.items():
            assert got[name]["value"] == pytest.approx(value, rel=1e-9, abs=1e-9), (point, name)
        expl = explain(load_system(path), point)
        step = next(s for sec in expl.sections for s in sec.steps if s.kind == "solution")
        for name, value, _unit in step.table.rows:  # 6 significant figures
            assert float(value) == pytest.approx(reference[name], rel=5e-6, abs=1e-9), (point, name)
        assert main(["draw", path, "--fbd", "--point", point, "-o", str(tmp_path / "fbd.svg")]) == 0
        drawing = draw_system(load_system(path), fbd=True, point=point)
        body, _, name = point.partition(":")
        assert drawing.point[body] == name
        import matplotlib.pyplot as plt

        plt.close(drawing.figure)


def test_a_crossing_is_written_in_the_coordinates_and_its_acceleration_derived() -> None:
    """QA 15 #8: about I(N_A,N_B) the worked solution printed r_I = (x, 0.939692620785908*L), the
    state's value of L sin(theta) frozen into the symbolic kinematics, and said that a_I follows
    from the joints while the advisor's table said "derive". By hand for ladder_leaves_wall
    (A = (x, 0) on the floor, the body's angle pi - theta, B = (x - L cos th, L sin th) on the wall):
    N_A acts along y through A and N_B along x through B, so they cross at (x, L sin th); the
    material point there moves as v_A + omega x r_I/A with omega = -th', r_I/A = (0, L sin th):
    v_I = (x' + L th' sin th, 0), a_I = (x'' + L th'' sin th, -L th'^2 sin th). Exact comparisons;
    and no Float in the body's equations."""
    import sympy as sp

    x, th, L = (sp.Symbol(n, real=True) for n in ("x", "theta", "L"))
    xd, thd, xdd, thdd = (sp.Symbol(n, real=True) for n in ("x_dot", "theta_dot", "x_ddot", "theta_ddot"))
    name = "I(N_A,N_B)"
    expected = {f"pos:{name}": (x, L * sp.sin(th)), f"vel:{name}": (xd + L * thd * sp.sin(th), 0),
                f"accel:{name}": (xdd + L * thdd * sp.sin(th), -L * thd**2 * sp.sin(th))}
    expl = explain(load_system(ROOT / "data" / "scenes" / "ladder_leaves_wall.toml"), name)
    section = expl.section("ladder")
    kinematics = section.step("kinematics")
    for tag, (ex, ey) in expected.items():
        got = kinematics.equation(tag).right
        assert sp.expand(got[0] - ex) == 0 and sp.expand(got[1] - ey) == 0, (tag, got)
    floats = {f for step in section.steps for e in step.equations for t in (*e.lhs, *e.rhs)
              for f in sp.sympify(t.expr).atoms(sp.Float)}
    assert not floats, floats
    assert "derived" in kinematics.text[0] and "follow from the joints" not in kinematics.text[0]
    advice = {row[1]: row[-1] for row in expl.sections[-1].step("advice").table.rows}
    assert advice[name] == "derive"


def test_about_the_mass_centre_no_acceleration_is_derived():
    """QA 19: `explain double_pendulum.toml --suggest-point` listed `lower B ... a_P derive`, though the
    lower body is a point mass at B: about its mass centre r_G/B = 0, the inertial term
    -r_G/B x m a_B vanishes (Eq. 10), and no a_B is needed. The same holds for G of any body (the
    sliding bar's G, a derived point before). The scene data put the bob at B (lower's only element)."""
    dp = load_system(ROOT / "data/scenes/double_pendulum.toml")
    state = start_state(dp)
    (b,) = [c for c in rank_points(dp, "lower", state) if c.name == "B"]
    assert b.needless and not b.known
    assert b.cost == "B is the mass centre: the inertial term -r_G/B x m a_B vanishes, so a_B is not needed"
    bar = load_system(ROOT / "data/scenes/sliding_bar.toml")
    (g,) = [c for c in rank_points(bar, "body", start_state(bar)) if c.name == "G"]
    assert g.needless and "a_G is not needed" in g.cost and "derived" not in g.cost
    (advice,) = [s for s in explain(dp).steps() if s.kind == "advice"]
    row = [r for r in advice.table.rows if r[:2] == ("lower", "B")]
    assert row and row[0][-1] == "not needed (G)"


TRACK = (ROOT / "tests/data/multibody/disk_in_track.toml").read_text(encoding="utf-8")


def test_a_contact_point_on_a_circle_is_written_in_the_coordinates(tmp_path: Path, capsys) -> None:
    """QA 21 #1: about C_track (data/scenes/README's disk_in_track, a disk of radius r rolling inside a
    track of radius R) the contact point was placed at the state's offset with cos 30 deg frozen in as
    0.866025403784439: the worked solution printed floats, named a twin C_track', said F and N drop out
    "at this state only", and precision's "exact" theta_ddot was wrong from its 17th digit.

    By hand: the centre P is at (R - r)(sin th, -cos th) and the contact point r further along the
    same ray, at R (sin th, -cos th); rolling makes the contact point's velocity 0. The moment about
    it: -m g r sin th = I_C alpha with I_C = 3 m r^2 / 2 and alpha = -(R - r) th''/r, so
    th'' = -2 g sin th / (3 (R - r)) = -2 (9.81)(1/2) / (3 (0.4)) = -8.175 rad/s^2 exactly, and
    F = m (R - r) th'' + m g sin th (Newton along the tangent) = 3.27 N exactly."""
    import json
    import sympy as sp

    th, R = sp.Symbol("theta", real=True), sp.Symbol("R", real=True)
    path = tmp_path / "track.toml"
    path.write_text(TRACK)
    expl = explain(load_system(path), "C_track")
    kinematics = expl.section("disk").step("kinematics")
    for tag, (ex, ey) in {"pos:C_track": (R * sp.sin(th), -R * sp.cos(th)), "vel:C_track": (0, 0)}.items():
        got = kinematics.equation(tag).right
        assert sp.expand(got[0] - ex) == 0 and sp.expand(got[1] - ey) == 0, (tag, got)
    floats = {f for step in expl.section("disk").steps for e in step.equations for t in (*e.lhs, *e.rhs)
              for f in sp.sympify(t.expr).atoms(sp.Float)}
    assert not floats, floats
    assert main(["explain", str(path), "--point", "C_track"]) == 0
    text = capsys.readouterr().out
    assert "C_track'" not in text and "at this state only" not in text
    assert "F drops out of the moment equation: its line of action passes through C_track." in text
    assert main(["precision", str(path), "--point", "C_track", "--precision", "exact", "--json"]) == 0
    exact = json.loads(capsys.readouterr().out)["solutions"]["exact"]["unknowns"]
    assert exact["theta_ddot"]["text"] == "-8.175" + "0" * 46
    assert exact["F"]["text"] == "3.27" + "0" * 47
