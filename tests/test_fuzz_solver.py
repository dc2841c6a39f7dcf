"""Fuzz the solver's input boundary through the command line, in process.

Hypothesis generates hostile and harmless inputs of four kinds: unit strings,
scene expressions, whole scene files (mutations of the shipped scenes) and
command-line flag values. Every run must end in exactly one of two ways:

* exit 2 with exactly one ``error: ...`` line on stderr, nothing on stdout,
  never ``internal error`` or a traceback; or
* exit 0 with the correct answer, from an independent reference:
  the ladder closed form (Example 1 with beta = 90 deg, see
  tests/test_cli_solver.py), which is independent of the bar's mass and, at
  rest, of how the coordinate is written (alpha and the reactions depend on
  the body's angle phi0 alone); the Example 2 period by mpmath quadrature of
  Eq. 44 (tests/references.py); energy conservation for time histories.

Inputs known to be hostile must give exit 2. No run may take more than
:data:`CPU_LIMIT` seconds of CPU time: the command line's own work cap is
lowered to :data:`CLI_CAP` for these tests, so a stall would surface as a
refusal (and a hang as a failed time check), never as a stuck suite.

Example counts (4 to 20 per test, about 80 runs in all) are chosen for speed:
the file adds about 4 s of CPU time to ``make test``. A refused input costs a few ms in
process, an answered one 50-100 ms, a new expression a derivation (0.1-0.5 s),
a period its 30-digit reference quadrature (0.3 s). The hostile pools are small
and listed, so each run draws a different part of them; hypothesis's database
replays any failure first. Raise the counts locally for a deeper search.
"""
from __future__ import annotations

import json
import math
import os
import time
from pathlib import Path
from unittest import mock

import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from tests.references import ex2_reference_period

ROOT = Path(__file__).resolve().parents[1]
SLIDING_BAR = ROOT / "data" / "scenes" / "sliding_bar.toml"
DISK_BAR = ROOT / "data" / "scenes" / "disk_bar.toml"

CLI_CAP = "4"
"""SOLVER_MAX_CPU_SECONDS for these runs [s]."""
CPU_LIMIT = 8.0
"""Most CPU time one run may take here [s]: the cap plus the command's start-up."""

def fuzz(examples: int) -> settings:
    """Settings for one fuzz test: ``examples`` examples, no wall-clock deadline (noisy on a
    shared machine; CPU time is checked instead), the in-process runner fixture allowed."""
    return settings(
        max_examples=examples,
        deadline=None,
        suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
    )

# -- the references ---------------------------------------------------------------------------
# Example 1 with beta = 90 deg is the ladder. In the scene's units: g = 32.174 ft/s^2,
# l = 4 ft, m = 50 lbm; 1 lbf = 0.45359237 kg * 9.80665 m/s^2 and 1 ft = 0.3048 m exactly.
G_FT, L_FT = 32.174, 4.0
WEIGHT_LBF = 50 * G_FT * 0.3048 / 9.80665
LBF_IN_N = 0.45359237 * 9.80665


def ladder(phi0: float) -> dict[str, float]:
    """alpha [rad/s^2] and R_A, R_B [lbf] at rest with the body's angle phi0 (= pi - ladder angle).

    theta_l'' = -(3 g / (2 l)) cos(theta_l); R_B = m (l/2)(-sin theta_l theta_l'');
    R_A = m g + m (l/2)(cos theta_l theta_l''); alpha = phi'' = -theta_l''.
    """
    th = math.pi - phi0
    thdd = -(3 * G_FT / (2 * L_FT)) * math.cos(th)
    mass = WEIGHT_LBF / G_FT  # lbf s^2 / ft
    return {
        "alpha": -thdd,
        "R_A": WEIGHT_LBF + mass * (L_FT / 2) * math.cos(th) * thdd,
        "R_B": mass * (L_FT / 2) * (-math.sin(th) * thdd),
    }


ALPHA_SCALE = 3 * G_FT / (2 * L_FT)


def assert_ladder(out: str, phi0: float, mass_free: bool = False) -> None:
    """The solver's JSON answer against :func:`ladder`.

    Tolerance: the solver solves a 4x4 system of condition number ``cond`` (estimated) in float64
    (error about cond * 1e-16 relative to the scale of the terms), and both sides
    evaluate phi0 through a few float operations (about 1e-15): 1e-12 * (1 + cond),
    relative to the scale of each quantity (3 g / 2 l for alpha, the weight for the
    reactions), is far above that and far below any wrong formula.
    """
    result = json.loads(out)
    ref = ladder(phi0)
    tol = 1e-12 * (1 + result["condition_number_estimate"])
    u = result["unknowns"]
    assert u["alpha"]["unit"] == "rad/s**2"
    assert abs(u["alpha"]["value"] - ref["alpha"]) <= tol * ALPHA_SCALE, (u, ref)
    ra, rb = (u[n]["value"] * (1 / LBF_IN_N if u[n]["unit"] == "N" else 1.0) for n in ("R_A", "R_B"))
    assert {u["R_A"]["unit"], u["R_B"]["unit"]} <= {"lbf", "N"}
    if mass_free:  # the mass is not known to the test: the reactions' ratio is
        assert abs(ra * ref["R_B"] - rb * ref["R_A"]) <= tol * (abs(ra) + abs(rb)) * WEIGHT_LBF, (u, ref)
    else:
        assert abs(ra - ref["R_A"]) <= tol * WEIGHT_LBF and abs(rb - ref["R_B"]) <= tol * WEIGHT_LBF, (u, ref)


# -- running ----------------------------------------------------------------------------------


def run(solver_cli, *argv: str) -> tuple[int, str, str]:
    """One in-process run under the lowered work cap; checks the time and the two allowed endings."""
    with mock.patch.dict(os.environ, {"SOLVER_MAX_CPU_SECONDS": CLI_CAP}):
        start = time.process_time()
        code, out, err = solver_cli(*argv)
        used = time.process_time() - start
    assert used < CPU_LIMIT, f"{argv}: {used:.1f} s of CPU time"
    assert code in (0, 2), (argv, code, err)
    if code == 2:
        assert out == "", (argv, out)
        assert err.count("\n") == 1 and err.startswith("error: "), (argv, err)
        assert "internal error" not in err and "Traceback" not in err, (argv, err)
    else:
        assert err == "", (argv, err)
    return code, out, err


# -- strategies -------------------------------------------------------------------------------
MASS_UNITS = ["kg", "g", "lbm", "lb", "slug", "tonne", "mg"]
OTHER_UNITS = ["m", "ft", "s", "deg", "rad", "N", "lbf", "zz", "m2", "%", "µg", "é"]
EXPONENTS = ["2", "-1", "0.5", "(2)", "12", "13", "1e9", "9**9", "(9**9**9)", "10**300", "x", "", "2**2", "2.5.5"]


@st.composite
def unit_texts(draw) -> str:
    """Products of 1-3 factors ``name[**exponent]``, sometimes in parentheses with an outer power."""
    factors = []
    for _ in range(draw(st.integers(1, 3))):
        name = draw(st.sampled_from(MASS_UNITS + OTHER_UNITS))
        if draw(st.booleans()):
            name += draw(st.sampled_from(["**", "^"])) + draw(st.sampled_from(EXPONENTS))
        factors.append(name)
    text = draw(st.sampled_from(["*", "/", " "])).join(factors)
    if draw(st.integers(0, 4)) == 0:
        text = f"({text})**" + draw(st.sampled_from(EXPONENTS))
    if draw(st.integers(0, 6)) == 0:
        text = draw(st.sampled_from(["(" * 5 + text + ")" * 5, text * 40, text + ")", "(" + text]))
    return text


NUMBERS = ["1", "50", "2.5e-3", "1e300", "1e-400", "1e999", "0", "-3", "7.", ".5", "1_000", "0x10"]


SIMPLE_MASSES = st.builds(lambda name, form: form.format(name), st.sampled_from(MASS_UNITS),
                          st.sampled_from(["{}", "({})", "{}**1", "{}^(1)", "{}*m/m", "{} ", "{}*s**2/s^2"]))


@fuzz(20)
@given(number=st.sampled_from(["1", "50", "2.5e-3", "7."]) | st.sampled_from(NUMBERS),
       unit=SIMPLE_MASSES | unit_texts())
def test_fuzz_mass_unit_strings(solver_cli, number: str, unit: str) -> None:
    code, out, _ = run(solver_cli, "solve", str(SLIDING_BAR), "--set", "beta=90 deg",
                       "--set", f"m_b={number} {unit}", "--json")
    event(f"exit {code}")
    hostile = any(piece in unit for piece in ("9**9", "10**300", "1e9", "**13", "^13", "**x", "^x", "é"))
    if hostile:
        assert code == 2
    if code == 0:  # the mass may be anything that is a mass: alpha and R_A/R_B do not depend on it
        assert_ladder(out, math.radians(150), mass_free=True)


# Expressions: a small tree with its own float value, so the test knows phi0 without
# evaluating any text; hostile pieces are listed.
@st.composite
def orientation(draw, depth: int = 0):
    """(text, value at theta = 30 deg, depends on theta)."""
    th = math.radians(30)
    kind = draw(st.sampled_from(["theta", "num", "neg", "add", "mul", "pow", "func"] if depth < 3 else ["theta", "num"]))
    if kind == "theta":
        return "theta", th, True
    if kind == "num":
        text, value = draw(st.sampled_from([("2", 2.0), ("0.5", 0.5), ("pi", math.pi), ("3", 3.0), ("1/3", 1 / 3)]))
        return text, value, False
    a_text, a_val, a_dep = draw(orientation(depth + 1))
    if kind == "neg":
        return f"-({a_text})", -a_val, a_dep
    if kind == "pow":
        k = draw(st.integers(1, 3))
        return f"({a_text})**{k}", a_val**k, a_dep
    if kind == "func":
        name, f = draw(st.sampled_from([("sin", math.sin), ("cos", math.cos), ("atan", math.atan)]))
        return f"{name}({a_text})", f(a_val), a_dep
    b_text, b_val, b_dep = draw(orientation(depth + 1))
    if kind == "add":
        return f"({a_text}) + ({b_text})", a_val + b_val, a_dep or b_dep
    return f"({a_text})*({b_text})", a_val * b_val, a_dep or b_dep


HOSTILE_EXPRESSIONS = [
    "theta**(10**300)", "9**9**9", "1e999", "theta**13", "(theta + 1)**99", "theta**(1/10**6)",
    "__import__('os').system('true')", "theta.real", "theta[0]", "(lambda: 1)()", "'a'",
    "theta if theta else 1", "sin(theta, 1)", "exp(710)", "cos(10**200)", "1/0", "sqrt(-1)",
    "theta" + " + theta" * 200, "(" * 150 + "theta" + ")" * 150, "sin(x=theta)", "theta @ theta",
    "[theta]", "theta\x00", "theta;1", "1e-400*theta**0",
]


def _scene(tmp_path: Path, text: str) -> str:
    path = tmp_path / "fuzz.toml"
    path.write_bytes(text.encode("utf-8", "surrogatepass") if isinstance(text, str) else text)
    return str(path)


@fuzz(15)
@given(tree=orientation(), hostile=st.none() | st.sampled_from(HOSTILE_EXPRESSIONS))
def test_fuzz_orientation_expressions(solver_cli, tmp_path_factory, tree, hostile) -> None:
    text, phi0, depends = tree
    if hostile is not None:
        text = f"pi - theta + ({hostile})"
    source = SLIDING_BAR.read_text().replace('orientation     = "pi - theta"', f"orientation = {json.dumps(text)}")
    scene = _scene(tmp_path_factory.mktemp("expr"), source)
    code, out, _ = run(solver_cli, "solve", scene, "--set", "beta=90 deg", "--json")
    event(f"exit {code}")
    if hostile is not None or not depends:
        assert code == 2
    elif code == 0:  # at rest the answer depends on the body's angle phi0 alone (or it is singular: exit 2)
        assert_ladder(out, phi0)


def test_an_angle_whose_derivative_is_zero_to_round_off_is_a_singular_configuration(solver_cli, tmp_path) -> None:
    # Found by the property above: the bar's angle sin(3 theta) has d(angle)/d(theta) = 3 cos(3 theta),
    # exactly 0 at theta = 30 deg, computed as 1.8e-16. The equilibrated condition number did not see
    # the round-off column, and every unknown (its bound far above it) was printed as "0 to round-off".
    # At 30 deg theta_ddot is undetermined (exit 2, named singular); at 29 deg the bar is at rest at
    # angle sin(87 deg) rad, and the answer is the ladder's (the tolerance of assert_ladder).
    source = SLIDING_BAR.read_text().replace('orientation     = "pi - theta"', 'orientation = "sin(3*theta)"')
    scene = _scene(tmp_path, source)
    code, out, err = run(solver_cli, "solve", scene, "--set", "beta=90 deg", "--json")
    assert code == 2 and "singular configuration at theta = 30 deg" in err, (code, out, err)
    code, out, err = run(solver_cli, "solve", scene, "--set", "beta=90 deg", "--set", "theta=29 deg", "--json")
    assert code == 0, err
    assert_ladder(out, math.sin(math.radians(87)))


# Scene files: harmless edits (the answer must not change) and hostile ones (refused).
HOSTILE_VALUES = [
    "50 lbm**9**9**9", "50 kg**1e9", "1e999", "theta**(10**300)", "9**9**9", "__import__('os')",
    "1" * 600, "1e300 deg", "-4 ft", "0 lbm", "(((((((((((m)))))))))))", "4 ft" + "*ft/ft" * 40, "\x00", "",
]
KEYS = ['m_b  = "50 lbm"', 'l_b  = "4 ft"', 'g    = "32.174 ft/s^2"', 'value = "30 deg"', 'rate  = "0 rad/s"',
        'orientation     = "pi - theta"', 'B = ["l_b", "0"]', 'mass = "m_b"', 'angle    = "-beta"',
        'force  = "lbf"', 'kind     = "rail"']


@st.composite
def hostile_scene(draw) -> bytes:
    text = SLIDING_BAR.read_text()
    how = draw(st.sampled_from(["value", "deep", "bigint", "inf", "bytes", "duplicate", "unknown", "type"]))
    if how == "value":
        line = draw(st.sampled_from(KEYS))
        key = line.split("=")[0]
        return text.replace(line, f"{key}= {json.dumps(draw(st.sampled_from(HOSTILE_VALUES)))}").encode()
    if how == "deep":
        n = draw(st.sampled_from([9, 50, 1000, 100_000]))
        return (text + "\nx = " + "[" * n + "]" * n + "\n").encode()
    if how == "bigint":
        return text.replace('m_b  = "50 lbm"', "m_b = " + "9" * draw(st.sampled_from([400, 5000]))).encode()
    if how == "inf":
        return text.replace('m_b  = "50 lbm"', "m_b = " + draw(st.sampled_from(["inf", "nan", "1e400"]))).encode()
    if how == "bytes":  # may land in a comment, where it is harmless: "maybe"
        at = draw(st.integers(0, len(text)))
        junk = draw(st.sampled_from([b"\xff\xfe", b"\x00", b"\xc3", b"[[", b"= =", b'"""']))
        raw = text.encode()
        return ("maybe", raw[:at] + junk + raw[at:])
    if how == "duplicate":
        return text.replace('g    = "32.174 ft/s^2"', 'g    = "32.174 ft/s^2"\ng = "1 ft/s^2"').encode()
    if how == "unknown":
        return text.replace("[coordinate]", "[coordinate]\nvalu = \"30 deg\"").encode()
    line = draw(st.sampled_from(KEYS))
    key = line.split("=")[0]
    return text.replace(line, f"{key}= {draw(st.sampled_from(['[1, 2]', '{a = 1}', 'true', '1979-05-27']))}").encode()


@st.composite
def harmless_scene(draw) -> bytes:
    text = SLIDING_BAR.read_text()
    if draw(st.booleans()):
        text = text.replace("\n", "\n# " + draw(st.text(alphabet="abc xyz=[]\"'", max_size=20)) + "\n", 3)
    if draw(st.booleans()):
        text = text.replace("\n", "\r\n")
    raw = text.encode()
    return (b"\xef\xbb\xbf" + raw) if draw(st.booleans()) else raw


@fuzz(20)
@given(source=hostile_scene().map(lambda s: s if isinstance(s, tuple) else ("hostile", s))
       | harmless_scene().map(lambda b: ("harmless", b)))
def test_fuzz_scene_files(solver_cli, tmp_path_factory, source) -> None:
    kind, raw = source
    path = tmp_path_factory.mktemp("scene") / "fuzz.toml"
    path.write_bytes(raw)
    code, out, err = run(solver_cli, "solve", str(path), "--set", "beta=90 deg", "--json")
    if kind == "harmless":
        assert code == 0, err
    if kind == "hostile":
        assert code == 2
    if code == 0:
        assert_ladder(out, math.radians(150))
    else:
        assert err.startswith(f"error: {path}: "), err  # names the file (and the place)


# Command-line flag values.
HOSTILE_FLAG_VALUES = ["1e12 s", "-1", "nan", "inf", "1 kg", "30 deg**9**9**9", "1" * 5000, "", "0",
                       "1e400", "--json", "1e-400 s", "1 s**2", "0x10"]


@fuzz(16)
@given(case=st.sampled_from(["t-end", "samples", "dps", "amplitude", "mass-ratio", "ratio-of", "range", "rtol"]),
       value=st.sampled_from(HOSTILE_FLAG_VALUES))
def test_fuzz_hostile_flag_values(solver_cli, tmp_path_factory, case: str, value: str) -> None:
    disk, bar = str(DISK_BAR), str(SLIDING_BAR)
    if value in ("-1", "0") and case in ("amplitude", "range"):
        value = f"{value} m"  # a negative or zero angle is a good angle: make it hostile
    argv = {
        "t-end": ("simulate", disk, "--t-end", value),
        "samples": ("simulate", disk, "--t-end", "1 s", "--samples", value),
        "dps": ("precision", bar, "--dps", value),
        "amplitude": ("period", disk, "--amplitude", value),
        "mass-ratio": ("friction", disk, "--mass-ratio", value),
        "ratio-of": ("friction", disk, "--ratio-of", value),
        "range": ("friction", bar, "--range", value, "30 deg"),
        "rtol": ("simulate", disk, "--t-end", "1 s", "--rtol", value),
    }[case]
    code, _, err = run(solver_cli, *argv)
    assert code == 2
    flag = f"--{case}"
    assert flag in err or "argument" in err, err  # the flag by its command-line name


@fuzz(4)
@given(degrees=st.floats(1.0, 150.0), unit=st.sampled_from([("deg", 1.0), ("", 1.0), ("rad", math.pi / 180),
                                                             ("arcmin", 60.0), ("turn", 1 / 360)]))
def test_fuzz_good_amplitudes_give_the_reference_period(solver_cli, degrees: float, unit) -> None:
    name, per_degree = unit
    code, out, err = run(solver_cli, "period", str(DISK_BAR), "--amplitude", f"{degrees * per_degree!r} {name}".strip(),
                         "--json")
    assert code == 0, err
    period = json.loads(out)["period"]
    assert period["unit"] == "s"
    # the solver is asked for 1e-10 (default --tol) and the reference is a 30-digit quadrature;
    # the amplitude passes through one unit conversion (a few ulp): 1e-9 relative
    assert period["value"] == pytest.approx(ex2_reference_period(math.radians(degrees)), rel=1e-9)


@fuzz(4)
@given(t_end=st.sampled_from(["0.5 s", "1", "0.01 min", "300 ms"]), samples=st.sampled_from([None, "2", "17", "1001"]))
def test_fuzz_good_simulations_conserve_energy(solver_cli, tmp_path_factory, t_end: str, samples) -> None:
    out_csv = tmp_path_factory.mktemp("sim") / "run.csv"
    argv = ["simulate", str(DISK_BAR), "--t-end", t_end, "--out", str(out_csv), "--json"]
    if samples:
        argv += ["--samples", samples]
    code, out, err = run(solver_cli, *argv)
    assert code == 0, err
    result = json.loads(out)
    seconds = {"0.5 s": 0.5, "1": 1.0, "0.01 min": 0.6, "300 ms": 0.3}[t_end]
    assert result["status"] == "completed"
    assert result["t_end"]["value"] == pytest.approx(seconds, rel=1e-15)  # the end time as asked
    assert result["samples"] == (int(samples) if samples else 1001)
    assert len(out_csv.read_text().splitlines()) == result["samples"] + 1  # header + every sample
    # Example 2 with F_a = 0 is conservative; DOP853 at rtol 1e-9 over < 1 period keeps the
    # energy to ~1e-9 of the kinetic scale: 1e-6 is the law's margin, not the integrator's
    assert result["energy_drift"] < 1e-6
