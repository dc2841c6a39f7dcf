"""Time histories (solver.simulate) against the paper's equations and closed forms.

Independent references:
* Example 2 with a horizontal force F_a at P: theta_ddot from Eq. 44 with the
  sign of F_a corrected (right side +F_a r_d, data/scenes/README.md, Example 2), F_f and
  F_n from Eqs. 39 and 40, alpha = -theta_ddot (Eq. 33), all typed here;
* the potential of a constant F_a is -F_a r_d theta (x_P = r_d theta, Eq. 31),
  so E - F_a r_d theta is conserved;
* string pendulum: tension m g cos + m l w^2 vanishes where
  cos theta* = (2 g - l w0^2) / (3 g) (energy + radial Newton, closed form);
* the exact period from solver.period (itself checked against elliptic integrals).
"""
from __future__ import annotations

import csv
from pathlib import Path
import json
import math
import os
from functools import lru_cache

import numpy as np
import pytest
import sympy as sp

from solver.errors import InputError
from solver.period import OneDofSystem, exact_period
from solver.simulate import simulate, write_csv

SCENE = "data/scenes/disk_bar.toml"
EX2 = dict(m_d=4.0, r_d=0.25, m_b=1.5, l_b=0.2, g=9.80665)


@lru_cache(maxsize=None)
def ex2(**overrides) -> OneDofSystem:
    from solver.derivation import derive
    from solver.scenefile import load_scene

    return OneDofSystem.from_derivation(derive(load_scene(SCENE, dict(overrides))))


def paper_ex2(theta, theta_dot, F_a=0.0, p=EX2):
    """(theta_ddot, F_f, F_n) from Eqs. 44 (sign of F_a corrected), 39 and 40."""
    md, rd, mb, lb, g = (p[k] for k in ("m_d", "r_d", "m_b", "l_b", "g"))
    s, c = np.sin(theta), np.cos(theta)
    M = (1.5 * md + mb) * rd**2 + mb * lb**2 / 3 - mb * rd * lb * c
    qdd = (F_a * rd - 0.5 * mb * rd * lb * s * theta_dot**2 - 0.5 * mb * g * lb * s) / M
    F_f = (md + mb) * rd * qdd + 0.5 * mb * lb * (theta_dot**2 * s - qdd * c) - F_a  # Eq. 39
    F_n = (md + mb) * g + 0.5 * mb * lb * (theta_dot**2 * c + qdd * s)  # Eq. 40
    return qdd, F_f, F_n


def test_example2_history_against_paper_equations():
    F_a = 2.0
    s = ex2(F_a="2 N")
    res = simulate(s, 3.0, y0=(math.radians(10), 0.0), rtol=1e-10, atol=1e-12)
    assert res.status == "completed"
    qdd, F_f, F_n = paper_ex2(res.theta, res.theta_dot, F_a)
    # same state, closed-form evaluation: agreement to rounding of the two formulae
    np.testing.assert_allclose(res.theta_ddot, qdd, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(res.alpha, -qdd, rtol=1e-9, atol=1e-12)  # Eq. 33
    np.testing.assert_allclose(res.reactions["F_f"], F_f, rtol=1e-9, atol=1e-10)
    np.testing.assert_allclose(res.reactions["F_n"], F_n, rtol=1e-9)
    # conserved: E - F_a r_d theta; integrator error at rtol 1e-10 over 3 s
    E = res.energy - F_a * EX2["r_d"] * res.theta
    assert np.ptp(E) / np.ptp(res.energy) < 1e-7
    assert res.theta[-1] > res.theta[0]  # a push along +i increases theta (x_P = r_d theta)


def test_free_oscillation_returns_after_the_exact_period():
    s = ex2()
    a = math.radians(30)
    T = exact_period(s, a, tol=1e-13).period
    res = simulate(s, T, y0=(a, 0.0), rtol=1e-12, atol=1e-14, samples=11)
    # DOP853 at rtol 1e-12 over one period: state good to ~1e-10
    assert res.theta[-1] == pytest.approx(a, abs=1e-9)
    assert res.theta_dot[-1] == pytest.approx(0.0, abs=1e-9)
    assert res.energy_drift < 1e-10


def test_string_pendulum_loses_tension_where_the_closed_form_says():
    q, qd, qdd, t = sp.symbols("theta theta_dot theta_ddot t", real=True)
    m, l, g = sp.symbols("m l g", real=True)
    s = OneDofSystem(q, qd, qdd, t, mass=m * l**2, potential=-m * g * l * sp.cos(q),
                     reactions={"T": m * g * sp.cos(q) + m * l * qd**2}, one_sided=("T",),
                     reaction_constraints={"T": "string"}, params=(m, l, g), values=(2.0, 1.5, 9.81))
    w0 = 5.0
    res = simulate(s, 10.0, y0=(0.0, w0), rtol=1e-11, atol=1e-13)
    assert res.status == "lost_contact" and res.event.reaction == "T"
    expected = math.acos((2 * 9.81 - 1.5 * w0**2) / (3 * 9.81))
    # event located on the dense output by brentq: angle good to ~1e-9
    assert res.event.theta == pytest.approx(expected, abs=1e-8)
    assert "T would turn negative" in res.reason and "string" in res.reason
    assert res.reactions["T"][-1] == pytest.approx(0.0, abs=1e-6)


def test_disk_leaves_the_floor():
    s = ex2()
    res = simulate(s, 5.0, y0=(0.0, 25.0), rtol=1e-11, atol=1e-12)
    assert res.status == "lost_contact" and res.event.reaction == "F_n"
    _, _, F_n = paper_ex2(res.event.theta, res.event.theta_dot)
    assert abs(F_n) < 1e-6 * EX2["g"] * (EX2["m_d"] + EX2["m_b"])  # Eq. 40 is zero there
    assert math.cos(res.event.theta) < 0  # bar above the centre: the only place it can happen


def test_slip_event_mid_swing():
    s = ex2()
    # start at the bottom with the rate of a 170 deg swing
    M0 = (1.5 * EX2["m_d"] + EX2["m_b"]) * EX2["r_d"] ** 2 + EX2["m_b"] * EX2["l_b"] ** 2 / 3 \
        - EX2["m_b"] * EX2["r_d"] * EX2["l_b"]
    dV = 0.5 * EX2["m_b"] * EX2["g"] * EX2["l_b"] * (1 - math.cos(math.radians(170)))
    w = math.sqrt(2 * dV / M0)
    # the least mu of that swing, from Eqs. 39-40 with the rate from energy on a fine grid (here,
    # not from the solver): above 0.07, so mu = 0.07 must slip, at the first angle where
    # |F_f|/F_n reaches 0.07
    grid = np.linspace(0.0, math.radians(170), 200_001)
    V = lambda q: -0.5 * EX2["m_b"] * EX2["g"] * EX2["l_b"] * np.cos(q)  # noqa: E731
    md, rd, mb, lb = EX2["m_d"], EX2["r_d"], EX2["m_b"], EX2["l_b"]
    M = (1.5 * md + mb) * rd**2 + mb * lb**2 / 3 - mb * rd * lb * np.cos(grid)
    rate = np.sqrt(np.maximum(2 * (V(math.radians(170)) - V(grid)) / M, 0.0))
    _, F_f, F_n = paper_ex2(grid, rate)
    ratio = np.abs(F_f) / F_n
    assert ratio.max() > 0.071  # comfortably above mu
    first = grid[np.argmax(ratio >= 0.07)]
    res = simulate(s, 10.0, y0=(0.0, w), rtol=1e-11, atol=1e-13, mu=0.07)
    assert res.status == "slip" and res.event.time > 0.1
    # the grid step is 8.5e-4 deg: the event is within one step of the first crossing
    assert math.degrees(res.event.theta) == pytest.approx(math.degrees(first), abs=1e-3)
    _, F_f, F_n = paper_ex2(res.event.theta, res.event.theta_dot)
    assert abs(F_f) / F_n == pytest.approx(0.07, rel=1e-7)
    # before the event the ratio stayed below mu
    _, F_f, F_n = paper_ex2(res.theta[:-1], res.theta_dot[:-1])
    assert np.all(np.abs(F_f) / F_n <= 0.07 * (1 + 1e-9))
    assert "mu = 0.07" in res.reason


def test_csv_is_written_atomically(tmp_path, monkeypatch):
    res = simulate(ex2(), 1.0, y0=(0.2, 0.0), samples=51)
    out = tmp_path / "run.csv"
    write_csv(res, out)
    with open(out, newline="") as fh:
        rows = list(csv.reader(fh))
    assert rows[0] == ["t [s]", "theta [rad]", "theta_dot [rad/s]", "theta_ddot [rad/s**2]", "alpha [rad/s**2]",
                       "F_f [N]", "F_n [N]", "energy [J]"]
    assert res.to_dict()["columns"]["theta_dot"] == "rad/s" and res.to_dict()["columns"]["F_n"] == "N"
    assert len(rows) == 52
    np.testing.assert_allclose([float(r[1]) for r in rows[1:]], res.theta, rtol=0, atol=0)  # repr round-trips
    # a failure while writing leaves neither the target nor a temporary file
    target = tmp_path / "broken.csv"

    def boom(*args, **kwargs):
        raise OSError("disk full")

    monkeypatch.setattr("solver.simulate.np.column_stack", boom)
    with pytest.raises(InputError, match="cannot write there .disk full"):  # one line naming the place
        write_csv(res, target)
    assert sorted(os.listdir(tmp_path)) == ["run.csv"]
    with pytest.raises(InputError, match="does not exist"):
        write_csv(res, tmp_path / "missing" / "x.csv")


def test_bad_options():
    with pytest.raises(ValueError, match="RK45"):
        simulate(ex2(), 1.0, method="Euler")
    with pytest.raises(InputError, match="t-end"):
        simulate(ex2(), -1.0)


def test_cli_simulate(solver_cli, tmp_path):
    out = tmp_path / "h.csv"
    code, text, _ = solver_cli("simulate", SCENE, "--t-end", "2 s", "--rtol", "1e-10", "--out", str(out),
                         "--json", "--no-progress")
    assert code == 0
    data = json.loads(text)
    assert data["status"] == "completed" and data["t_end"] == {"value": 2.0, "unit": "s"}
    assert out.exists()
    code, text, err = solver_cli("simulate", SCENE, "--t-end", "2 kg")
    assert code == 2 and err.count("\n") == 1
    code, text, err = solver_cli("simulate", SCENE, "--t-end", "1", "--out", str(tmp_path / "no" / "x.csv"))
    assert code == 2 and "does not exist" in err


def test_progress_bar_when_forced(capsys):
    simulate(ex2(), 1.0, y0=(0.2, 0.0), progress=True, samples=11)
    assert "simulated" in capsys.readouterr().err


def _pendulum(constant=0.0, force=0.0, time_force=False) -> OneDofSystem:
    """Simple pendulum m l^2 qdd = -m g l sin q + Q; V carries an arbitrary constant (its datum)."""
    q, qd, qdd, t = sp.symbols("theta theta_dot theta_ddot t", real=True)
    m, l, g, F = sp.symbols("m l g F", real=True)
    Q = F * l * (sp.cos(t) if time_force else 1)
    return OneDofSystem(q, qd, qdd, t, mass=m * l**2, potential=-m * g * l * sp.cos(q) + constant * m * g * l,
                        generalized_force=Q, params=(m, l, g, F), values=(2.0, 1.5, 9.81, force))


def test_energy_drift_does_not_depend_on_the_potential_datum():
    # Regression: released at 90 deg the pendulum's E(0) is 0 with the pivot as datum, and the
    # drift was reported as ~0.5 for an accurate run (scale max(|E(0)|, range of E)).
    y0 = (math.pi / 2, 0.0)
    drifts = [simulate(_pendulum(c), 10.0, y0=y0, rtol=1e-10, atol=1e-12).energy_drift for c in (0.0, 1e3)]
    # DOP853 at rtol 1e-10 over ~4 periods: relative drift ~1e-9; the datum must not matter
    assert drifts[0] < 1e-7 and drifts[1] < 1e-7
    assert drifts[0] == pytest.approx(drifts[1], rel=0.5)  # same motion; only round-off in H differs


def test_energy_drift_counts_the_work_of_position_loads_and_is_none_for_time_loads():
    # A constant moment F l does work F l theta: E alone changes by ~10% over the run, while
    # E - F l theta (= 1/2 M qd^2 + V_eff) is conserved. A time-dependent load conserves nothing.
    y0 = (0.3, 0.0)
    assert simulate(_pendulum(force=2.0), 5.0, y0=y0, rtol=1e-10, atol=1e-12).energy_drift < 1e-7
    assert simulate(_pendulum(force=2.0, time_force=True), 1.0, y0=y0).energy_drift is None


def test_energy_column_is_gravity_energy_even_after_the_effective_potential_was_compiled():
    # Regression: energy_fn and potential_fn(0) shared a cache key, so whichever was built
    # first answered for both (V_eff drops constants and includes the loads' potential).
    s = _pendulum(constant=5.0, force=2.0)
    s.potential_fn(0)(0.0)
    m, l, g = 2.0, 1.5, 9.81
    assert float(s.energy_fn()(0.0, 0.0)) == pytest.approx(4 * m * g * l, rel=1e-14)  # -mgl + 5 mgl


def test_interpolants_made_on_demand_are_scipys():
    """simulate's DOP853 makes each step's interpolant only when asked (solver.simulate._lazy_dop853):
    it must take scipy's steps and give scipy's eager dense output exactly (the same arithmetic on the
    same numbers: compared bit for bit, no tolerance), at sample times inside steps and at their ends."""
    from scipy.integrate import solve_ivp

    from solver.simulate import _lazy_dop853

    def f(t, y):  # a pendulum with a time-dependent drive: every stage value matters
        return (y[1], -9.81 * math.sin(y[0]) + 0.3 * math.cos(2.0 * t))

    args = dict(t_span=(0.0, 7.0), y0=np.array([1.2, 0.0]), rtol=1e-9, atol=1e-12, dense_output=True)
    eager = solve_ivp(f, method="DOP853", **args)
    lazy = solve_ivp(f, method=_lazy_dop853(f), **args)
    assert np.array_equal(eager.t, lazy.t) and np.array_equal(eager.y, lazy.y)
    t = np.concatenate([np.linspace(0.0, 7.0, 1001), eager.t])
    assert np.array_equal(eager.sol(t), lazy.sol(t))
    # and the interpolants were made only for the steps asked about, not for every step
    assert lazy.nfev < eager.nfev


def test_an_interpolant_that_fails_later_is_an_input_error():
    """A right-hand side that fails at an interpolant's extra stages (made after the run, when a
    sample is asked for) is reported as a failed integration, one InputError, not a traceback."""
    from scipy.integrate import solve_ivp

    from solver.simulate import _lazy_dop853

    broken = []

    def f(t, y):
        if broken:
            raise ZeroDivisionError("float division by zero")
        return (y[1], -y[0])

    sol = solve_ivp(f, (0.0, 3.0), np.array([1.0, 0.0]), method=_lazy_dop853(f, "oscillator"), dense_output=True)
    broken.append(True)
    with pytest.raises(InputError, match="oscillator: integration failed: float division by zero"):
        sol.sol(1.5)


def test_t_end_is_the_end_time_for_a_scene_that_starts_later(solver_cli):
    """--t-end is an end time (its help says so): the slider-crank scene starts at its `time`,
    t = 0.004 s, so --t-end 0.006 s runs 2 ms and its last sample is at 0.006 s (it was run for
    0.006 s, to 0.010 s); an end before the start is refused in one line naming the flag."""
    scene = "data/scenes/slider_crank.toml"
    code, out, err = solver_cli("simulate", scene, "--t-end", "0.006 s", "--samples", "3", "--json")
    assert code == 0, err
    result = json.loads(out)
    assert result["status"] == "completed" and result["t_final"] == {"value": 0.006, "unit": "s"}
    code, out, err = solver_cli("simulate", scene, "--t-end", "0.002 s")
    assert code == 2 and out == "" and err.count("\n") == 1
    assert "--t-end '0.002 s' is not after the scene's start time, 0.004 s" in err


@pytest.mark.parametrize("scene", ["data/scenes/sliding_bar.toml", "data/scenes/double_pendulum.toml"])
def test_simulate_columns_carry_the_output_units(solver_cli, tmp_path, scene):
    """`simulate --json` names the unit of every column of the samples, in the scene's output units,
    and the CSV file is in those units, each column headed `name [unit]`, for the one-angle route
    and the multibody route alike. Example 1 (lbm/ft, output in lbf): the first sample is the
    release state, so R_A and R_B there are the paper's Eq. (30) values in lbf (tolerance: the one
    the printed precision implies, reports.rounding.eq30_tolerances)."""
    import tomllib

    from reports.rounding import eq30_tolerances

    out = tmp_path / "run.csv"
    code, text, err = solver_cli("simulate", scene, "--t-end", "0.05 s", "--samples", "11", "--out", str(out),
                                 "--json", *(["--no-progress"] if "sliding" in scene else []))
    assert code == 0, err
    columns = json.loads(text)["columns"]
    with open(out, newline="") as fh:
        rows = list(csv.reader(fh))
    assert rows[0] == [f"{name} [{unit}]" for name, unit in columns.items()]
    assert columns["t"] == "s"
    if "sliding" not in scene:
        assert columns["O_x"] == "N"  # an SI scene stays SI
        return
    assert columns["R_A"] == columns["R_B"] == "lbf"
    published = {v["id"]: v for v in tomllib.load(open("data/published/example1.toml", "rb"))["value"]}
    tol = eq30_tolerances(published)
    first = dict(zip(columns, map(float, rows[1])))
    for name in ("R_A", "R_B"):
        assert abs(first[name] - published[f"eq30-{name}"]["value"]) <= tol[name], name


@pytest.mark.parametrize("scene", ["tests/data/multibody/pin_bar.toml", "data/scenes/double_pendulum.toml"])
def test_one_freedom_and_n_freedoms_print_one_layout(solver_cli, tmp_path, scene):
    """QA 15 #11: the one-freedom text had another layout ("final state", theta in deg while the CSV
    has rad, no theta_ddot). Both now print the final sample of every CSV column but the energy, in
    the CSV's units, under the same headings. The CSV's last row is the reference: the text prints
    10 significant digits of the same number."""
    csv = tmp_path / "run.csv"
    code, out, err = solver_cli("simulate", scene, "--t-end", "0.2", "--out", str(csv))
    assert code == 0, err
    lines = csv.read_text().splitlines()
    header = [h.rsplit(" [", 1) for h in lines[0].split(",")]
    last = [float(v) for v in lines[-1].split(",")]
    assert "final sample:" in out and "energy drift over the run:" in out and "method  DOP853" in out
    table = out.split("final sample:")[1].split("\n\n")[0].splitlines()[3:]
    printed = {row.split()[0]: (float(row.split()[1]), row.split()[2]) for row in table}
    expected = {name: (value, unit[:-1]) for (name, unit), value in zip(header, last) if name != "energy"}
    assert list(printed) == list(expected)
    for name, (value, unit) in expected.items():
        # 1e-9: 10 significant digits printed (half a unit of the 10th is 5e-10 relative)
        assert printed[name][1] == unit and printed[name][0] == pytest.approx(value, rel=1e-9, abs=1e-12), name


def test_the_readme_says_which_simulate_json_field_to_match(solver_cli):
    """QA 17 #7: the one-freedom `reason` changed from 'reached t_end = 0.5 s' to 'reached t = 0.5 s'
    (as n freedoms say it) and the README did not say so; a consumer matching the words broke. The
    README names `status` as the field to match and quotes the reason as simulate writes it, for one
    freedom (pin_bar) and for two (double_pendulum)."""
    from pathlib import Path

    readme = Path("README.md").read_text(encoding="utf-8")
    for scene in ("tests/data/multibody/pin_bar.toml", "data/scenes/double_pendulum.toml"):
        code, out, err = solver_cli("simulate", scene, "--t-end", "0.5", "--json")
        assert code == 0, err
        payload = json.loads(out)
        assert payload["status"] == "completed" and f"`{payload['reason']}`" in readme
    assert "`status` is the field to match" in readme


AT_REST = ("--set", "theta=0 deg", "--set", "theta_dot=0 rad/s")  # hanging straight down, still


@pytest.mark.parametrize("scene, why, extra", [
    ("data/scenes/ladder_friction.toml", "nothing moved", ()),  # at rest, sticking, gravity only (n freedoms)
    ("data/scenes/disk_backspin.toml", "a contact slid: its friction did work", ()),  # it slips, then rolls
    # QA 22 #6: the motor prescribes the crank; the rod's angle is dependent, not free
    ("data/scenes/slider_crank.toml", "every motion is prescribed", ()),
    # QA 22 #6: one freedom at rest printed "energy drift over the run: 0" (of a largest kinetic energy 0)
    ("tests/data/multibody/pin_bar.toml", "nothing moved", AT_REST),
    ("data/scenes/compound_pendulum.toml", "nothing moved", AT_REST),
    # QA 23 #5: a constant push that moves nothing (the crate held by friction) does no work
    ("data/scenes/crate_tipping.toml", "nothing moved", ()),
])
def test_energy_drift_says_why_it_is_not_applicable(solver_cli, scene, why, extra):
    """QA 20 #7: the ladder at rest under gravity alone ended with "energy drift: not applicable (the
    loads depend on time or rate: they do work)", though its loads are conservative and it never moved:
    the run had no kinetic energy to scale a drift by. Each run now gives its own reason. (The ladder's
    final rates are 0, which the test reads from the text itself.)"""
    code, out, err = solver_cli("simulate", scene, "--t-end", "0.01 s", *extra)
    assert code == 0, err
    last = out.strip().splitlines()[-1]
    assert last.startswith("energy drift: not applicable (" + why), last
    assert "do work" not in last
    if "ladder" in scene or extra:
        rates = [row.split() for row in out.split("final sample:")[1].splitlines() if "_dot " in row]
        assert rates and all(float(r[1]) == 0 for r in rates)


# the same disk on the outside of the cylinder, released near its top
DISK_ON_CYLINDER = (Path(__file__).parent / "data/multibody/disk_in_track.toml").read_text(encoding="utf-8").replace(
    'name = "disk_in_track"', 'name = "disk_on_cylinder"').replace('side = "inside"', 'side = "outside"').replace(
    'position_angle = "theta - pi/2"', 'position_angle = "pi/2 - theta"')


def test_the_final_sample_at_contact_loss_gives_n_as_zero_and_the_angle_in_degrees_too(tmp_path, capsys):
    """QA 21 #5: a disk rolling off the top of a cylinder stops where N would turn negative; the
    final sample printed N = -1.279311409e-14 N (round-off of terms of 20 N) and theta in rad
    beside a status line in deg (the CSV's unit, kept: QA 15 #11; the degrees now beside it). By hand (energy, rolling disk T = 3/4 m v^2, v = (R + r) th', and
    N = m g cos th - m (R + r) th'^2 = 0): cos th = (3 (R + r) th0'^2 + 4 g cos th0) / (7 g),
    53.1501 deg; the run locates it to its tolerances (rtol 1e-9), so 1e-7 relative."""
    from solver.__main__ import main

    path = tmp_path / "top.toml"
    path.write_text(DISK_ON_CYLINDER, encoding="utf-8")
    assert main(["simulate", str(path), "--t-end", "2"]) == 0
    text = capsys.readouterr().out
    rows = {line.split()[0]: line.split()[1:] for line in text.split("final sample:")[1].splitlines()[3:]
            if line.strip() and not line.startswith("0 to")}
    expected = math.acos((3 * 0.6 * 2.0**2 + 4 * 9.81 * math.cos(math.radians(30))) / (7 * 9.81))
    value, unit, equals, degrees, deg = rows["theta"]  # the CSV's rad, and the status line's deg
    assert (unit, equals, deg) == ("rad", "(=", "deg)")
    assert float(value) == pytest.approx(expected, rel=1e-7)
    assert float(degrees) == pytest.approx(math.degrees(expected), rel=1e-7)
    assert rows["N"] == ["0", "N"]
    assert "0 to round-off (a value within its own error bound is given as 0): N (computed" in text
