"""Commands beyond the instant: ``period``, ``simulate``, ``friction``, ``precision``.

* ``period SCENE --amplitude ANGLE [--tol REL] [--model M] [--json]``: the
  period of free oscillation released from rest at the amplitude (measured
  from the stable equilibrium), from the cheapest model meeting ``--tol``
  (:mod:`solver.fidelity`), beside the linearized period (cf. Eq. 46).
* ``simulate SCENE --t-end T [--method M] [--rtol R] [--atol A] [--out FILE.csv] [--mu MU]``:
  the time history from the scene's state (:mod:`solver.simulate`).
* ``friction SCENE``: for a rolling scene (Example 2) the least friction
  coefficient over a free oscillation (``--amplitude``, ``--mass-ratio``,
  repeatable); for a scene without rolling (Example 1) the release angles at
  which every reaction is >= 0 (``--range``, ``--reactions``).
* ``precision SCENE [--precision P] [--dps N]``: the instantaneous solve in
  float64, exact and mpmath arithmetic, with the condition number.

Angles on the command line take a unit (``"30 deg"``, ``"0.5 rad"``); a bare
number is in degrees. Times likewise (``"10 s"``); a bare number is seconds.
"""
from __future__ import annotations

import argparse
import math
import sys

from solver.cli_common import (
    state_si,
    add_common_arguments,
    float_in,
    format_number,
    int_in,
    format_table,
    freedom_words,
    in_output_units,
    load_scene_from_args,
    print_json,
    round_off_zero_text,
    to_output_units,
)
from solver.errors import InputError

__all__ = ["register"]


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add ``period``, ``simulate``, ``friction`` and ``precision`` to the command line."""
    from solver.limits import IVP_METHODS as METHODS
    from solver.limits import MAX_DPS, MAX_PERIODS, MAX_RHS_EVALUATIONS, MAX_SAMPLES, MAX_T_END, MIN_DPS
    from solver.limits import PERIOD_MODELS as MODELS
    from solver.limits import TOL_MAX, TOL_MIN

    p = subparsers.add_parser(
        "period",
        help="exact period of free oscillation at an amplitude, beside the linearized one",
        description="Period of free oscillation released from rest at ANGLE from the stable equilibrium: "
        "the energy integral with its end singularities removed, or the linearized formula (cf. Eq. 46) "
        "when its error bound meets --tol. Loads other than gravity must be zero, constant or "
        "position-dependent.",
    )
    add_common_arguments(p)
    p.add_argument("--amplitude", required=True, metavar="ANGLE",
                   help='release angle from the equilibrium, e.g. "30 deg" (bare number: degrees)')
    p.add_argument("--tol", type=float_in(TOL_MIN, TOL_MAX), default=1e-10, metavar="REL",
                   help=f"requested relative accuracy of the period, {TOL_MIN:g} to {TOL_MAX:g} (default 1e-10)")
    p.add_argument("--model", choices=MODELS, default="auto",
                   help="force a model instead of the cheapest that meets --tol (default: auto)")
    p.set_defaults(handler=period_command)

    p = subparsers.add_parser(
        "simulate",
        help="time history by solve_ivp; contacts stick, slip and separate as the motion requires",
        description="Integrate the equations of motion from the scene's state. Contacts switch regime "
        "(a sticking contact reaching mu_s N slips, a sliding one coming to rest sticks, a contact whose "
        "normal force reaches zero opens) and every switch is reported; the run stops, and says why, at an "
        "impact, when a regime needs a motion the scene's coordinates cannot describe, or at a "
        "singular configuration. Caps on the work of one run: --t-end at most "
        f"{MAX_T_END:g} s and at most {MAX_PERIODS} periods of small oscillation, at most "
        f"{MAX_RHS_EVALUATIONS} right-hand-side evaluations, at most {MAX_SAMPLES} samples.",
    )
    add_common_arguments(p, method=False)  # --method is the integrator here
    p.add_argument("--t-end", required=True, metavar="T",
                   help=f'end time, e.g. "10 s" (bare number: seconds; at most {MAX_T_END:g} s); the run starts '
                   "at the scene's time (its `time`, 0 unless given)")
    p.add_argument("--method", dest="ivp_method", choices=METHODS, default="DOP853",
                   help="solve_ivp method (default DOP853)")
    p.add_argument("--rtol", type=float_in(1e-13, 0.1), default=1e-9,
                   help="relative tolerance, 1e-13 to 0.1 (default 1e-9)")
    p.add_argument("--atol", type=float_in(1e-300, 1.0), default=1e-12,
                   help="absolute tolerance, 1e-300 to 1 (default 1e-12)")
    p.add_argument("--out", metavar="FILE.csv", default=None,
                   help="write the samples to a CSV file, named .csv (atomically; the place and the suffix are checked "
                   "before the run)")
    p.add_argument("--mu", type=float_in(0.0, 1e6), default=None,
                   help="friction coefficient of every rolling contact (rolling only: a rail's is a scene parameter, "
                   "--set), 0 to 1e6 (default: the scene's, if any)")
    p.add_argument("--samples", type=int_in(2, MAX_SAMPLES), default=None,
                   help=f"number of output samples, 2 to {MAX_SAMPLES} (default: 20 per period, at least 1001)")
    p.add_argument("--animate", metavar="FILE.gif", default=None,
                   help="also write an animation of the scene drawing: .gif, or .mp4 where ffmpeg is installed; "
                   "at most 250 frames (a longer run is sampled evenly), 25 frames per second")
    bar = p.add_mutually_exclusive_group()
    bar.add_argument("--progress", dest="progress", action="store_true", default=None,
                     help="always show a progress bar on stderr")
    bar.add_argument("--no-progress", dest="progress", action="store_false",
                     help="never show a progress bar (default: only on a terminal, for long runs)")
    p.set_defaults(handler=simulate_command)

    p = subparsers.add_parser(
        "friction",
        help="least friction coefficients, release angles, and where motion from rest starts",
        description="One-angle scenes as in the paper: with a rolling contact, the least mu that keeps rolling "
        "without slip over a free oscillation (max |F_f|/F_n over the swing, Eqs. 39-40), per amplitude and "
        "mass ratio; without, the release angles (from rest) at which every reaction is >= 0. Scenes with "
        "contacts that can stick, slip or separate: the regime and the least mu of each contact at the state, "
        "over a motion (--over), and the values of a coordinate or parameter at which a motion from rest "
        "starts (--critical NAME --between LOW HIGH).",
    )
    add_common_arguments(p)
    p.add_argument("--amplitude", action="append", default=[], metavar="ANGLE",
                   help=f"amplitude(s) of the free oscillation (repeatable, at most {MAX_LIST} times; "
                   "default: the scene's theta)")
    p.add_argument("--mass-ratio", action="append", type=float_in(0.0, 1e6, low_open=True), default=[], metavar="R",
                   help=f"m_b/m_d value(s) to tabulate, in (0, 1e6] (repeatable, at most {MAX_LIST} times; "
                   "sets m_b = R m_d)")
    p.add_argument("--ratio-of", default=None, metavar="NUM/DEN",
                   help="the two mass parameters of the ratio (default m_b/m_d); they must be parameters "
                   "of the scene")
    p.add_argument("--range", nargs=2, default=None, metavar=("LOW", "HIGH"),
                   help="release angles searched, without rolling, within -360 deg .. 360 deg "
                   "(default 0 deg 180 deg)")
    p.add_argument("--reactions", default=None, metavar="NAMES",
                   help="comma-separated reactions that must stay >= 0 (default: all)")
    p.add_argument("--critical", default=None, metavar="NAME",
                   help="a coordinate or parameter: the values in --between at which a motion from rest starts "
                   "(a slip against mu_s N, a contact opening, tipping), for scenes with friction contacts")
    p.add_argument("--between", nargs=2, default=None, metavar=("LOW", "HIGH"),
                   help='range searched by --critical, with units, e.g. "20 deg" "89 deg" or "0 N" "400 N"')
    p.add_argument("--over", default=None, metavar="T",
                   help="least friction coefficient of each contact to keep sticking (or rolling) over a "
                   f"motion of T seconds from the scene's state (at most {MAX_OVER_T:g} s)")
    p.set_defaults(handler=friction_command)

    p = subparsers.add_parser(
        "precision",
        help="the instantaneous solve in float64, exact and mpmath arithmetic, with the condition number",
        description="Solve the instantaneous linear system at the scene's state in float64, exactly "
        "(sympy, parameters as exact decimals) and in mpmath at --dps digits; report the condition number "
        "and the relative error of float64.",
    )
    add_common_arguments(p)
    p.add_argument("--precision", dest="precision", choices=("float64", "exact", "mpmath", "all"), default="all",
                   help="arithmetic (default: all three)")
    p.add_argument("--dps", type=int_in(MIN_DPS, MAX_DPS), default=50,
                   help=f"decimal digits for mpmath and printing, {MIN_DPS} to {MAX_DPS} (default 50)")
    p.set_defaults(handler=precision_command)


# -- helpers -----------------------------------------------------------------------------------
MAX_LIST = 20
MAX_OVER_T = 1000.0
"""``friction --over`` simulates at most this long [s]."""
"""Most values of a repeatable ``friction`` option (--amplitude, --mass-ratio)."""
RANGE_LIMIT_DEG = 360.0
"""``friction --range`` searches within -RANGE_LIMIT_DEG .. RANGE_LIMIT_DEG."""


def _angle(text: str, where: str) -> float:
    """An angle in rad from ``"30 deg"`` / ``"0.5 rad"`` / ``"30"`` (degrees), guarded."""
    from solver.units import parse_angle

    return parse_angle(text, where, bare_unit="deg")


def _time(text: str, where: str) -> float:
    """A time in s from ``"10 s"`` / ``"10"`` (seconds), guarded."""
    from solver.units import parse_time

    return parse_time(text, where)


def _system(args, reactions: bool = True):
    from solver.derivation import derive
    from solver.period import OneDofSystem

    scene = load_scene_from_args(args)
    if len(scene.free) != 1 or scene.closure or scene.time_dependent or scene.free[0].kind != "angle":
        independent = [c for c in scene.free if not c.dependent]
        if not independent:  # `frequency` refuses it too: nothing moves freely
            advice = "every motion is prescribed, so nothing oscillates: `solve` and `simulate` give its reactions " \
                     "and driving forces"
        elif scene.time_dependent and len(independent) > 1:  # beyond `frequency` (solver.analyses.modes)
            advice = "use `simulate` for its motion"
        else:
            advice = "use `frequency` for its natural modes or `simulate` for its motion"
        raise InputError(
            f"{scene.label}: {args.command} needs one degree of freedom given by an angle (one free angle "
            f"coordinate, no closure constraints, no prescribed motion); this scene has {freedom_words(scene)}: "
            f"{advice}"
        )
    d = derive(scene, getattr(args, "point", None), getattr(args, "method", "generalized_euler"))
    return scene, d, OneDofSystem.from_derivation(d, reactions=reactions)


def _where(scene) -> str:
    return scene.label


# -- period ------------------------------------------------------------------------------------
def period_command(args: argparse.Namespace) -> int:
    from solver.fidelity import INPUT_ROUNDING, amplitude_sensitivity, period_to_tolerance
    from solver.period import find_equilibrium

    amplitude = _angle(args.amplitude, "--amplitude")
    scene, _, system = _system(args, reactions=False)  # the period needs only M and V
    eq = find_equilibrium(system, near=state_si(scene)[0])
    res = period_to_tolerance(system, amplitude, tol=args.tol, model=args.model, equilibrium=eq)
    shown = to_output_units(res.to_dict(), scene.output_units)
    kappa = None if res.model in ("linear", "integration") else amplitude_sensitivity(system, res, args.tol, eq)
    if args.json:
        payload = {"scene": scene.name}
        payload.update(shown)
        payload["tol"] = args.tol
        payload["amplitude_sensitivity"] = kappa
        print_json(payload)
        return 0
    rows = [
        ("period", format_number(shown["period"]["value"], 12), shown["period"]["unit"]),
        ("period_linear", format_number(shown["period_linear"]["value"], 12), shown["period_linear"]["unit"]),
        ("ratio", format_number(res.ratio, 12), ""),
        ("equilibrium", format_number(shown["equilibrium"]["value"], 10), shown["equilibrium"]["unit"]),
        ("turning points", ", ".join(format_number(x, 10) for x in shown["turning_points"]["value"]),
         shown["turning_points"]["unit"]),
    ]
    print(f"scene   {scene.name}  ({_where(scene)})")
    print(f"amplitude {format_number(shown['amplitude']['value'], 10)} {shown['amplitude']['unit']} "
          "from the equilibrium, released from rest")
    print()
    print(format_table(("name", "value", "unit"), rows, align="lrl"))
    print()
    how = {"elliptic": " (closed form: complete elliptic integrals of the first and third kinds)",
           "quadrature": f" ({res.nodes} nodes, {res.precision})"}.get(res.model, "")
    print(f"model: {res.model}{how}, estimated relative error {res.error_estimate:.2g} (requested {args.tol:g})")
    if kappa is not None:
        floor = kappa * INPUT_ROUNDING
        print(f"sensitivity to the amplitude: a relative change d of the amplitude changes the period by "
              f"{kappa:.3g} d; the amplitude's own rounding ({INPUT_ROUNDING:.2g}) moves it by {floor:.2g}"
              + (", more than the tolerance: the period of the amplitude as typed is known only that closely"
                 if floor > args.tol else ""))
    return 0


# -- simulate ----------------------------------------------------------------------------------
def _simulate_multibody(args, system, t_end) -> int:
    """simulate for n degrees of freedom, closure equations or prescribed motion."""
    from solver.analyses.motion import simulate_system, write_motion_csv

    res = simulate_system(system, t_end, method=args.ivp_method, rtol=args.rtol, atol=args.atol, mu=args.mu,
                          samples=args.samples, point=args.point)
    if args.out is not None:
        write_motion_csv(res, args.out, system.output_units)
    if args.animate is not None:
        _animate(args, system, res.t, [res.columns[c.name][0] for c in system.free],
                 [res.columns[f"{c.name}_dot"][0] for c in system.free])
    if args.json:
        payload = {"scene": system.name, **to_output_units(res.to_dict(system.output_units), system.output_units)}
        if args.out is not None:
            payload["out"] = str(args.out)
        print_json(payload)
        return 0
    _print_run(args, system, res.status, res.reason, res.nfev, res.columns_with_time(system.output_units),
               res.energy_drift, res.events, res.energy_drift_note)
    return 0


def _print_run(args, scene, status: str, reason: str, nfev: int, columns: dict, drift: float | None,
               events=(), no_drift: str = "", zeros=None) -> None:
    """The text of ``simulate``, one layout for one freedom and for n: the scene, the status, the
    integrator, each regime switch, the final sample of every CSV column (``columns``: name ->
    (values, unit) in the output units, as the file has them, an angle in degrees too, as the status
    line gives it; the energy left out; ``zeros``: the unknowns 0 to round-off there, given as 0 with
    the line that says so) and the energy drift (None: not applicable, ``no_drift`` saying why)."""
    t_values, _ = columns["t"]
    print(f"scene   {scene.name}  ({_where(scene)})")
    print(f"status  {status}: {reason}   ({nfev} rhs evaluations, {len(t_values)} samples)")
    print(f"method  {args.ivp_method}  rtol {args.rtol:g}  atol {args.atol:g}")
    if events:
        print()
        print("regime switches:")
        for ev in events:
            t, t_unit = in_output_units(ev["t"], "s", scene.output_units)
            print(f"  t = {format_number(t, 10)} {t_unit}  {ev['joint']}: {ev['from']} -> {ev['to']}  ({ev['cause']})")
    zeros = zeros or {}
    rows = []
    for name, (values, unit) in columns.items():
        value = 0.0 if name in zeros else float(values[-1])
        if name == "energy" or not math.isfinite(value):
            continue
        if unit == "rad":  # (the CSV's unit, and the degrees the status line and `state` lines give)
            degrees, shown = in_output_units(math.degrees(value), "deg", scene.output_units)
            unit = f"rad (= {format_number(degrees, 10)} {shown})"
        rows.append((name, format_number(value, 10), unit))
    print()
    print("final sample:")
    print(format_table(("name", "value", "unit"), rows, align="lrl"))
    if zeros:
        print(round_off_zero_text(zeros, scene.output_units))
    print(f"\nenergy drift over the run: {format_number(drift, 3)} (of the largest kinetic energy)" if drift is not None
          else f"\nenergy drift: not applicable ({no_drift})")
    if args.out is not None:
        units = ", ".join(f"{n} [{u}]" for n, (_, u) in columns.items())
        print(f"\ntime history written to {args.out} (columns in the scene's output units: {units})")
    if args.animate is not None:
        print(f"animation written to {args.animate}")


def simulate_command(args: argparse.Namespace) -> int:
    from solver.files import check_output_path
    from solver.simulate import MAX_T_END, simulate, write_csv

    t_end = _time(args.t_end, "--t-end")
    if not 0 < t_end <= MAX_T_END:
        raise InputError(f"--t-end must be a positive time of at most {MAX_T_END:g} s, got {args.t_end!r}")
    if args.out is not None:
        from solver.drawing import check_format

        check_output_path(args.out, "--out")  # before the run, not after it
        check_format(args.out, (".csv",), "--out")  # CSV text only: not under another format's name
    if args.animate is not None:
        from solver.drawing import check_animation_path

        check_output_path(args.animate, "--animate")  # the place first: a folder is said to be one
        check_animation_path(args.animate, "--animate")  # suffix, ffmpeg for .mp4, the place
    loaded = load_scene_from_args(args)
    if args.mu is not None:
        from solver.analyses.motion import mu_contacts

        mu_contacts(loaded)  # refuses a scene with no rolling contact, which --mu would not change
    if len(loaded.free) != 1 or loaded.closure or len(loaded.bodies) != 1 or loaded.free[0].kind != "angle" \
            or loaded.time_dependent or any(j.friction is not None for j in loaded.contacts):
        # --t-end is the end time; the run starts at the scene's own time (`time`, 0 unless given)
        if not t_end > loaded.time:
            raise InputError(f"--t-end {args.t_end!r} is not after the scene's start time, {loaded.time:g} s "
                             "(its `time`): give the time the run should end at")
        return _simulate_multibody(args, loaded, t_end - loaded.time)
    scene, _, system = _system(args)
    res = simulate(system, t_end, y0=state_si(scene), method=args.ivp_method, rtol=args.rtol, atol=args.atol,
                   mu=args.mu, samples=args.samples, progress=args.progress)
    if args.out is not None:
        write_csv(res, args.out, scene.output_units)
    if args.animate is not None:
        _animate(args, scene, res.t, [res.theta], [res.theta_dot])
    if args.json:
        payload = {"scene": scene.name}
        payload.update(to_output_units(res.to_dict(scene.output_units), scene.output_units))
        if args.out is not None:
            payload["out"] = str(args.out)
        print_json(payload)
        return 0
    zeros = _final_round_off(scene, args, res.theta[-1], res.theta_dot[-1], res.t[-1])
    _print_run(args, scene, res.status, res.reason, res.nfev, res.columns(scene.output_units), res.energy_drift,
               no_drift=res.energy_drift_note, zeros=zeros)
    return 0


def _final_round_off(system, args, q: float, qd: float, t: float) -> dict:
    """The unknowns of a one-freedom run's final sample that are 0 to round-off, as `solve` gives
    them at that state (:func:`solver.analyses.instant.solved_at_state`, its ``zero_to_round_off``):
    the normal force where the contact is lost, computed as -1.3e-14 N beside terms of 20 N. None
    where that state's solve is singular (the run says why it stopped)."""
    from solver.analyses.instant import State, solved_at_state
    from solver.errors import SingularConfigurationError

    try:
        _, extra, _ = solved_at_state(system, args.point, getattr(args, "method", "generalized_euler"),
                                      State((float(q),), (float(qd),), float(t)))
    except (SingularConfigurationError, InputError):
        return {}
    return extra.get("zero_to_round_off", {})


def _animate(args, system, times, q_columns, qd_columns) -> None:
    """``--animate``: the scene drawing along the sampled trajectory (solver.drawing.animate)."""
    from solver.analyses.instant import State
    from solver.drawing import animate

    states = [State(tuple(float(c[k]) for c in q_columns), tuple(float(c[k]) for c in qd_columns), float(times[k]))
              for k in range(len(times))]
    animate(system, times, states, args.animate)  # the line saying so comes last, after the summary


# -- friction ----------------------------------------------------------------------------------
def friction_command(args: argparse.Namespace) -> int:
    from solver.friction import friction_map, release_window
    from solver.period import find_equilibrium

    loaded = load_scene_from_args(args)
    if _contact_mode(args, loaded):
        from solver.cli_contacts import contact_friction

        return contact_friction(args, loaded)

    amplitudes = [_angle(a, "--amplitude") for a in args.amplitude]
    if len(amplitudes) > MAX_LIST or len(args.mass_ratio) > MAX_LIST:
        raise InputError(f"--amplitude and --mass-ratio may each be given at most {MAX_LIST} times")
    window = (0.0, math.pi)
    if args.range is not None:
        window = (_angle(args.range[0], "--range LOW"), _angle(args.range[1], "--range HIGH"))
        limit = math.radians(RANGE_LIMIT_DEG)
        if not (-limit <= window[0] < window[1] <= limit):
            raise InputError(f"--range {args.range[0]} {args.range[1]}: expected LOW < HIGH within "
                             f"-{RANGE_LIMIT_DEG:g} deg .. {RANGE_LIMIT_DEG:g} deg")
    scene, _, system = _system(args)
    if system.friction_pairs:
        eq = find_equilibrium(system, near=state_si(scene)[0])
        amps = amplitudes or [state_si(scene)[0] - eq.q]
        num, den = _ratio_of(args, scene)
        for flag, given in (("--range", args.range), ("--reactions", args.reactions)):
            if given:
                raise InputError(f"{_where(scene)}: {flag} applies to a scene without a rolling contact; "
                                 "this one rolls (its friction is tabulated with --amplitude and --mass-ratio)")
        fmap = friction_map(system, amps, args.mass_ratio or None, ratio_of=(num, den))
        if args.json:
            payload = {"scene": scene.name, "mode": "rolling"}
            payload.update(fmap.to_dict())
            payload["results"] = [[r.to_dict() for r in row] for row in fmap.results]
            print_json(to_output_units(payload, scene.output_units))
            return 0
        print(f"scene   {scene.name}  ({_where(scene)})")
        print(f"least friction coefficient mu_min = max |{system.friction_pairs[0].friction}| / "
              f"{system.friction_pairs[0].normal} over a free oscillation")
        first = f"{fmap.ratio_of[0]}/{fmap.ratio_of[1]}" if fmap.ratio_of else "masses"
        header = (first, *["{:.6g} {}".format(*in_output_units(math.degrees(a), "deg", scene.output_units))
                           for a in fmap.amplitudes])
        rows = [(format_number(r, 6) if fmap.ratio_of else "as in scene",
                 *[format_number(v, 6) if math.isfinite(v) else "lifts off" for v in row])
                for r, row in zip(fmap.mass_ratios, fmap.mu_min)]
        print(format_table(header, rows, align="r" * len(header)))
        return 0
    for flag, given in (("--amplitude", args.amplitude), ("--mass-ratio", args.mass_ratio),
                        ("--ratio-of", args.ratio_of)):
        if given:
            raise InputError(f"{_where(scene)}: {flag} applies to a scene with a rolling contact; this one has "
                             "none (its release angles are searched with --range and --reactions)")
    lo, hi = window
    names = None
    if args.reactions:
        names = [n.strip() for n in args.reactions.split(",") if n.strip()]
    win = release_window(system, names, (lo, hi), theta_dot=state_si(scene)[1])
    if args.json:
        payload = {"scene": scene.name, "mode": "release"}
        payload.update(win.to_dict())
        print_json(to_output_units(payload, scene.output_units))
        return 0
    print(f"scene   {scene.name}  ({_where(scene)})")
    def angle(x: float, digits: int) -> str:
        value, unit = in_output_units(math.degrees(x), "deg", scene.output_units)
        return f"{value:.{digits}g} {unit}"

    print(f"release angles with {', '.join(win.reactions)} >= 0 (searched {angle(lo, 6)} .. {angle(hi, 6)}):")
    if not win.intervals:
        print("  none")
    for iv in win.intervals:
        print(f"  {angle(iv.low, 10)} ({iv.low_reason}) .. {angle(iv.high, 10)} ({iv.high_reason})")
    return 0


def _contact_mode(args, system) -> bool:
    """True when ``friction`` answers for the scene's contacts (regimes) rather than
    the one-angle rolling table or release window of Examples 1 and 2."""
    if args.critical is not None or args.between is not None or args.over is not None:
        return True
    one_angle = (len(system.free) == 1 and not system.closure and not system.time_dependent
                 and system.free[0].kind == "angle")
    if not one_angle or any(j.friction is not None and j.kind == "rail" for j in system.contacts):
        return True
    if any(j.friction_pair for j in system.joints):
        from solver.period import find_equilibrium

        try:
            _, _, one = _system(args)
            find_equilibrium(one, near=system.free[0].value)
        except InputError:
            return True  # no stable equilibrium (a disk rolling down an incline): the contact answers
    return False


def _ratio_of(args: argparse.Namespace, scene) -> tuple[str, str]:
    """The two parameters of ``--ratio-of NUM/DEN``, checked: both named in the scene (when the
    option is given, or mass ratios are asked for) and of the same kind."""
    text = args.ratio_of if args.ratio_of is not None else "m_b/m_d"
    num, sep, den = text.partition("/")
    num, den = num.strip(), den.strip()
    if not sep or not num or not den or "/" in den:
        raise InputError(f"--ratio-of {text!r}: expected two parameter names as NUM/DEN, e.g. m_b/m_d")
    missing = [n for n in (num, den) if n not in scene.parameters]
    if missing and (args.ratio_of is not None or args.mass_ratio):
        raise InputError(f"{_where(scene)}: --ratio-of {text}: {', '.join(missing)} "
                         f"{'is not a parameter' if len(missing) == 1 else 'are not parameters'} of the scene "
                         f"(parameters: {', '.join(scene.parameters)})")
    if not missing and scene.parameters[num].dimensionality != scene.parameters[den].dimensionality:
        raise InputError(f"{_where(scene)}: --ratio-of {text}: {num} and {den} are not quantities "
                         f"of the same kind ({scene.parameters[num]:~P} and {scene.parameters[den]:~P})")
    return num, den


# -- precision ---------------------------------------------------------------------------------
def precision_command(args: argparse.Namespace) -> int:
    from solver.derivation import derive
    from solver.precision import PRECISIONS, solve_precise

    scene = load_scene_from_args(args)
    system, state = _precision_system(scene, args.point, args.method)
    d = derive(system, args.point, args.method)
    which = PRECISIONS if args.precision == "all" else (args.precision,)
    results = [_precise_in_output_units(solve_precise(d, p, args.dps, assembled=state), scene.output_units)
               for p in which]
    regimes = ({j.name: j.current_regime.label for j in system.contacts} if system is not scene else {})
    if args.json:
        from solver.formulations import point_entries, shown_point

        print_json({"scene": scene.name, **point_entries(d.method, shown_point(system, d.method, args.point)),
                    "method": d.method,
                    "condition_number": results[0].condition_number,
                    **({"regime": regimes} if regimes else {}),
                    "solutions": {r.precision: r.to_dict() for r in results}})
        return 0
    print(f"scene   {scene.name}  ({_where(scene)})")
    if regimes:
        print("contacts in the regime that holds at the state (as `solve` finds it): "
              + ", ".join(f"{j}: {r}" for j, r in regimes.items())
              + "; a sliding contact's friction (-mu_k N) and a separated one's forces (0) are not unknowns here")
    float64 = solve_precise(d, "float64", args.dps, assembled=state) if "float64" not in which else None
    float64 = _precise_in_output_units(float64, scene.output_units) if float64 else results[which.index("float64")]
    within = {n for n, b in float64.error_bound.items() if b >= 1 and float(float64.text[n]) != 0}
    print(f"condition number of the linear system (exact; 1-norm, rows and columns equilibrated, so unit-free; "
          f"`solve` prints an estimate of it): {results[0].condition_number:.6g} "
          f"(float64 relative error bound ~ {_bound_text(results[0], [n for n in results[0].unknowns if n in within])})")
    for r in results:
        print()
        print(f"{r.precision}" + (f" ({r.dps} digits)" if r.precision != "float64" else ""))
        rows = [(n, r.text[n], r.units.get(n, ""), *_error_cells(n, r, float64, n in within)) for n in r.unknowns]
        print(format_table(("name", "value", "unit", "float64 rel. error", "its bound"), rows, align="lrlll"))
        if within & set(r.unknowns) and r is results[-1]:
            print()
            print("abs.: a float64 value within its own error bound (0 to round-off, or its digits lost: `solve` "
                  "gives the first as 0): its error and bound are absolute, in the row's unit")
        if r.exact_form:
            print("exact forms (SI units):")
        for n, e in r.exact_form.items():
            print(f"  {n} = {e}")
        if r.note:
            print(f"note: {r.note}")
    sys.stdout.flush()
    return 0


def _error_cells(name: str, result, float64, absolute: bool) -> tuple[str, str]:
    """The two error cells of ``precision``'s row ``name`` in ``result``'s table: float64's relative error
    and bound, or, for a float64 value within its own bound (its relative bound at least 1: no digit
    of it is known, and 0 may be the answer, whose relative error is undefined), the absolute
    ones in the row's unit, marked "abs."."""
    import mpmath

    if not absolute:
        return (f"{result.float64_error.get(name, 0.0):.2g}",
                f"{result.error_bound[name]:.2g}" if name in result.error_bound else "-")
    value = float(float64.text[name])
    with mpmath.workdps(result.dps + 10):
        error = 0 if result.precision == "float64" else abs(mpmath.mpf(value) - mpmath.mpf(result.text[name]))
    return f"abs. {float(error):.2g}", f"abs. {float64.error_bound[name] * abs(value):.2g}"


def _bound_text(result, absolute=()) -> str:
    """The headline float64 bound: cond * 2.2e-16 for the unknowns of the largest scale, and the
    worst unknown's own bound where the equations' terms cancel beside it (each unknown's in the
    tables' "its bound" column). ``absolute``: the unknowns within their own bound, whose rows
    the tables mark "abs." (no relative error is defined against what may be 0): named as such,
    never quoted as a relative bound."""
    normwise = f"{result.condition_number * 2.2e-16:.2g}"
    if not result.error_bound:
        return normwise + " for the unknowns of the largest scale (no bound per unknown: an entry could not be sized)"
    finite = {n: v for n, v in result.error_bound.items() if math.isfinite(v) and n not in absolute}
    worst = max(finite, key=finite.get, default=None)
    within = ""
    if absolute:
        one = len(absolute) == 1
        within = (f"; {', '.join(absolute)} {'is' if one else 'are'} within {'its' if one else 'their'} own "
                  "error bound (0 to round-off, or digits lost): no relative error is defined for "
                  f"{'it' if one else 'them'}, and {'its row gives' if one else 'their rows give'} absolute ones (abs.)")
    if worst is None or finite[worst] <= 100 * result.condition_number * 2.2e-16:
        return normwise + (" for the other unknowns" if absolute else "") + within + "; each unknown's bound in the tables"
    return (f"{normwise} for the unknowns of the largest scale, {finite[worst]:.2g} for {worst}, which the "
            f"equations' cancelling terms dwarf{within}; each unknown's bound in the tables")


def _precise_in_output_units(result, units):
    """``result`` (a :class:`~solver.precision.PreciseSolution`, SI) with its printed values and
    units in the scene's output units (:func:`solver.output_units.output_unit`), converted by the
    exact SI factor of each unit (ft = 0.3048 m exactly) at the answer's own precision, so that
    no digit is lost; the float64 relative errors do not change. The exact forms stay SI."""
    import dataclasses

    import mpmath

    from solver.output_units import output_unit
    from solver.precision import exact_quantity
    from solver.units import Q_

    text, shown_units = dict(result.text), dict(result.units)
    for name, unit in result.units.items():
        target = output_unit(unit, units) if unit and name in text else unit
        if target == unit:
            continue
        factor = exact_quantity(Q_(1, unit)) / exact_quantity(Q_(1, target))
        if result.precision == "float64":
            text[name] = repr(float(text[name]) * float(factor))
        else:
            with mpmath.workdps(result.dps + 10):
                value = mpmath.mpf(text[name]) * mpmath.mpf(str(factor.evalf(result.dps + 15)))
                text[name] = mpmath.nstr(value, result.dps)
        shown_units[name] = target
    return dataclasses.replace(result, text=text, units=shown_units)


def _precision_system(scene, point, method):
    """(system, float64 state) that ``precision`` solves: the scene as written, or, when it has
    contacts, the scene in the contact regime that holds at its state (as ``solve`` finds it):
    there a sliding contact's friction is -mu_k N and a separated one's forces are zero, so
    neither is an unknown of the linear system.

    Raises
    ------
    InputError
        When the regime leaves the split of the forces undetermined (statically
        indeterminate): there is no one linear system to solve precisely.
    """
    if not scene.contacts:
        return scene, None
    from solver.analyses.regimes import SPLIT_NAME, system_in_regime

    variant, regime, _, state = system_in_regime(scene, point, method)
    if regime is not None and regime.indeterminate:
        raise InputError(f"{scene.label}: precision: the sticking contacts hold redundantly "
                         "(statically indeterminate), so the forces have no unique value to compute precisely; "
                         f"`solve` gives the accelerations and {SPLIT_NAME} of the forces")
    return variant, state
