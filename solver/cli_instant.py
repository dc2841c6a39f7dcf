"""Commands about one instant or the equations themselves: ``solve``, ``eom``,
``frequency``.

* ``solve``: the angular acceleration alpha (k-component, as in the paper),
  theta_ddot and every reaction at the scene's state, from the linear system
  of Newton's law (Eq. 1 / 14), the moment equation about P (Eq. 10 / 11)
  and the constraint accelerations. A table in the scene's output units, or
  ``--json``.
* ``eom``: the equation of motion in the coordinate with the reactions
  eliminated, the generalized mass, and each reaction as a function of the
  state; text, ``--latex`` or ``--json`` (expressions as sympy strings).
* ``frequency``: the natural frequency of small oscillations about the
  stable equilibrium (cf. Eq. 46), in rad/s, Hz and as a period.
"""
from __future__ import annotations

import argparse
import math
import signal
import threading

import sympy as sp

from solver import derivation
from solver.cli_common import (
    add_common_arguments,
    check_finite,
    format_number,
    format_table,
    load_scene_from_args,
    print_json,
    quantity_entry,
    state_text,
    to_output_units,
)
from solver.errors import InputError
from solver.scene import Scene


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add ``solve``, ``eom`` and ``frequency`` to the command line."""
    p = subparsers.add_parser(
        "solve",
        help="angular acceleration and reactions at the scene's state",
        description="Solve for alpha, theta_ddot and every reaction at the scene's state "
        "(Newton, Eq. 1/14, with the moment equation about P, Eq. 10/11).",
    )
    add_common_arguments(p)
    p.set_defaults(handler=solve_command)

    p = subparsers.add_parser(
        "eom",
        help="equation of motion and reactions as functions of the state",
        description="The equation of motion in the coordinate (reactions eliminated), the "
        "generalized mass and each reaction as a function of the state.",
    )
    add_common_arguments(p, json_output=False)
    fmt = p.add_mutually_exclusive_group()
    fmt.add_argument("--json", action="store_true", help="print one JSON object (expressions as strings)")
    fmt.add_argument("--latex", action="store_true", help="print LaTeX")
    p.set_defaults(handler=eom_command)

    p = subparsers.add_parser(
        "frequency",
        help="natural frequency of small oscillations about the stable equilibrium",
        description="Natural frequency of small oscillations about the stable equilibrium under "
        "gravity (other loads set aside), cf. Eq. 46. It does not depend on P; --point is "
        "accepted for uniformity and checked.",
    )
    add_common_arguments(p)
    p.set_defaults(handler=frequency_command)


def _where(scene: Scene) -> str:
    return str(scene.source) if scene.source is not None else scene.name


# -- solve -----------------------------------------------------------------------------------


def solve_command(args: argparse.Namespace) -> int:
    """``solve``: alpha, theta_ddot and every reaction at the scene's state.

    Examples
    --------
    The paper's Example 1 (``data/scenes/sliding_bar.toml``) gives Eq. (30),
    alpha = 2.297 rad/s^2, R_A = 27.88 lbf, R_B = 22.53 lbf (the paper's R_B is
    rounded from its own 4-figure Eq. 29; within the tolerance of
    :func:`reports.rounding.eq30_tolerances`):

    >>> import contextlib, io, json
    >>> from solver.__main__ import main
    >>> with contextlib.redirect_stdout(io.StringIO()) as out:
    ...     status = main(["solve", "data/scenes/sliding_bar.toml", "--json"])
    >>> unknowns = json.loads(out.getvalue())["unknowns"]
    >>> status, [f"{unknowns[n]['value']:.4g} {unknowns[n]['unit']}" for n in ("alpha", "R_A", "R_B")]
    (0, ['2.297 rad/s**2', '27.88 lbf', '22.54 lbf'])
    """
    scene = load_scene_from_args(args)
    solution = derivation.solve_instant(scene, args.point, args.method)
    result = solution.to_dict(scene.output_units)
    unknowns = result["unknowns"]
    check_finite({name: entry["value"] for name, entry in unknowns.items()}, _where(scene))
    check_finite({"condition number": result["condition_number"]}, _where(scene))
    if args.json:
        print_json(
            {
                "scene": scene.name,
                "point": solution.point,
                "method": solution.method,
                "unknowns": unknowns,
                "condition_number": float(result["condition_number"]),
            }
        )
        return 0
    rows = [
        (name, format_number(entry["value"]), entry["unit"]) for name, entry in unknowns.items()
    ]
    print(f"scene   {scene.name}  ({_where(scene)})")
    timed = any(_uses_time(load, scene) for load in scene.loads)
    print(f"state   {state_text(scene)}" + ("   (loads taken at t = 0 s)" if timed else ""))
    print(f"point   {solution.point}   method  {solution.method}")
    print()
    print(format_table(("name", "value", "unit"), rows, align="lrl"))
    print()
    print(f"condition number of the system (rows and columns equilibrated, so unit-free): {format_number(result['condition_number'], 3)}")
    print("alpha is the k-component of the angular acceleration (counter-clockwise positive).")
    return 0


def _uses_time(load, scene: Scene) -> bool:
    exprs = [load.magnitude] if load.components is None else list(load.components)
    return any(e is not None and e.has(scene.t) for e in exprs)


# -- eom -------------------------------------------------------------------------------------


def eom_command(args: argparse.Namespace) -> int:
    scene = load_scene_from_args(args)
    d = derivation.derive(scene, args.point, args.method)
    eom = d.eom
    mass = _display_form(d.mass, _collect_trig)
    # Display form only: cancel common factors (removes removable 0/0 points
    # such as a sin(theta) in both numerator and denominator).
    reactions = {name: _display_form(expr) for name, expr in d.reactions.items()}
    if args.json:
        print_json(
            {
                "scene": scene.name,
                "point": d.point,
                "method": d.method,
                "coordinate": scene.coordinate,
                "eom": str(eom),
                "mass": str(mass),
                "kinetic_energy": str(d.kinetic_energy),
                "potential_energy": str(d.potential_energy),
                "generalized_force": str(d.generalized_force),
                "reactions": {name: str(expr) for name, expr in reactions.items()},
                "reaction_units": dict(d.reaction_units),
            }
        )
        return 0
    q = scene.coordinate
    if args.latex:
        names = _latex_names(scene)

        def latex(expr: sp.Expr) -> str:
            return sp.latex(expr, symbol_names=names)

        print(f"% {scene.name}: equation of motion (about {d.point}, {d.method}); reactions eliminated")
        print(f"{latex(eom)} = 0")
        print(f"% generalized mass M({q})")
        print(f"M = {latex(mass)}")
        print("% reactions as functions of the state")
        for name, expr in reactions.items():
            print(f"{sp.latex(sp.Symbol(name))} = {latex(expr)}")
        return 0
    print(f"scene   {scene.name}  ({_where(scene)})")
    print(f"point   {d.point}   method  {d.method}")
    print()
    print(f"equation of motion ({q}_ddot is the second derivative of {q}):")
    print(f"  {sp.sstr(eom)} = 0")
    print()
    print(f"generalized mass M({q}) (kinetic energy T = 1/2 M {q}_dot**2):")
    print(f"  M = {sp.sstr(mass)}")
    print()
    print("reactions as functions of the state:")
    for name, expr in reactions.items():
        print(f"  {name} = {sp.sstr(expr)}    [{d.reaction_units.get(name, '')}]")
    return 0


DISPLAY_BUDGET_S = 4.0
"""Most CPU time spent tidying one expression for display [s]."""
DISPLAY_MAX_OPS = 200
"""Expressions larger than this are printed as derived (cancel gets slow)."""


class _OutOfTime(Exception):
    pass


def _collect_trig(expr: sp.Expr) -> sp.Expr:
    """Expand, then let sin**2 + cos**2 = 1 combine (e.g. a generalized mass)."""
    return sp.trigsimp(sp.expand(expr))


def _display_form(expr: sp.Expr, tidy_with=sp.cancel) -> sp.Expr:
    """A readable equivalent of ``expr`` for printing (never used to compute).

    ``tidy_with`` (default ``sympy.cancel``, which removes common factors and
    with them removable 0/0 points such as a sin(theta) above and below) can
    be slow, so it is
    tried only on moderate expressions and within :data:`DISPLAY_BUDGET_S`
    of CPU time (on the main thread of a POSIX system); otherwise the
    derived form is printed unchanged.
    """
    ops = sp.count_ops(expr)
    if ops > DISPLAY_MAX_OPS:
        return expr
    timed = hasattr(signal, "SIGPROF") and threading.current_thread() is threading.main_thread()
    if timed:
        def _alarm(signum, frame):
            raise _OutOfTime

        previous = signal.signal(signal.SIGPROF, _alarm)
        signal.setitimer(signal.ITIMER_PROF, DISPLAY_BUDGET_S)
    try:
        tidy = tidy_with(expr)
    except (_OutOfTime, sp.PolynomialError, ValueError, TypeError):
        return expr
    finally:
        if timed:
            signal.setitimer(signal.ITIMER_PROF, 0)
            signal.signal(signal.SIGPROF, previous)
    return tidy if sp.count_ops(tidy) <= ops else expr


def _latex_names(scene: Scene) -> dict[sp.Symbol, str]:
    """theta_dot -> \\dot{\\theta}, theta_ddot -> \\ddot{\\theta}."""
    base = sp.latex(scene.q)
    return {scene.qd: rf"\dot{{{base}}}", scene.qdd: rf"\ddot{{{base}}}"}


# -- frequency -------------------------------------------------------------------------------


def frequency_command(args: argparse.Namespace) -> int:
    scene = load_scene_from_args(args)
    if args.point is not None:
        derivation.derive(scene, args.point, args.method)  # checks the point (SceneError)
    result = derivation.natural_frequency(scene, args.method)
    omega = float(result.omega_n.to("rad/s").magnitude)
    period = float(result.period.to("s").magnitude)
    equilibrium = float(result.equilibrium.to("rad").magnitude)
    check_finite({"omega_n": omega, "period": period, "equilibrium": equilibrium}, _where(scene))
    if not omega > 0:
        raise InputError(f"{_where(scene)}: the natural frequency came out as {omega}; no oscillation")
    payload = to_output_units(result.to_dict(), scene.output_units)
    payload["frequency"] = {"value": omega / (2 * math.pi), "unit": "Hz"}
    if args.json:
        print_json({"scene": scene.name, "method": args.method, **payload})
        return 0
    q = scene.coordinate
    eq_deg = math.degrees(equilibrium)
    print(f"scene   {scene.name}  ({_where(scene)})")
    print(f"small oscillations about the stable equilibrium {q} = {format_number(eq_deg)} deg "
          f"({format_number(equilibrium)} rad), gravity only")
    print()
    rows = [
        ("omega_n", format_number(payload["omega_n"]["value"]), payload["omega_n"]["unit"]),
        ("frequency", format_number(omega / (2 * math.pi)), "Hz"),
        ("period", format_number(payload["period"]["value"]), payload["period"]["unit"]),
        ("stiffness", format_number(payload["stiffness"]["value"]), payload["stiffness"]["unit"]),
        ("mass", format_number(payload["mass"]["value"]), payload["mass"]["unit"]),
    ]
    print(format_table(("name", "value", "unit"), rows, align="lrl"))
    print()
    print(f"omega_n**2 = V''({q}_e) / M({q}_e): stiffness of the potential over the generalized mass.")
    return 0


__all__ = ["register", "solve_command", "eom_command", "frequency_command", "quantity_entry"]
