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

from solver.lazy import lazy_module
from solver.cli_common import (
    add_common_arguments,
    check_finite,
    digits_lost_text,
    round_off_zero_text,
    format_number,
    format_table,
    load_scene_from_args,
    print_json,
    quantity_entry,
    state_text,
    output_unit,
    in_output_units,
    to_output_units,
)
from solver.errors import InputError

# loaded on first use: `--help` and the argument errors need neither (about 1 s of start-up)
sp = lazy_module("sympy")
derivation = lazy_module("solver.derivation")


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add ``solve``, ``eom`` and ``frequency`` to the command line."""
    p = subparsers.add_parser(
        "solve",
        help="every acceleration and reaction at the scene's state",
        description="Solve for the second derivative of every coordinate (and alpha for a one-body scene), "
        "every reaction and every driving force or torque at the scene's state (per body: Newton, Eq. 1/14, "
        "with the moment equation about P, Eq. 10/11; plus the closure equations).",
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
        "kinematics",
        help="positions, velocities and accelerations of every named point at the state",
        description="Positions, velocities and accelerations of every named point, and each body's "
        "omega and alpha, at the scene's state (accelerations from the instantaneous solve).",
    )
    add_common_arguments(p)
    p.set_defaults(handler=kinematics_command)

    p = subparsers.add_parser(
        "frequency",
        help="natural frequencies and mode shapes about the stable equilibrium",
        description="Natural frequencies and mode shapes of small oscillations about the stable "
        "equilibrium nearest the scene's state, with every load that depends on position only (gravity, "
        "springs, constant forces and couples), cf. Eq. 46. It does not depend on P; --point is "
        "accepted for uniformity and checked.",
    )
    add_common_arguments(p)
    p.set_defaults(handler=frequency_command)


def _where(scene) -> str:
    return scene.label


# -- solve -----------------------------------------------------------------------------------


def solve_command(args: argparse.Namespace) -> int:
    """``solve``: every coordinate's second derivative and every reaction at the scene's state.

    Examples
    --------
    The paper's Example 1 (``data/scenes/sliding_bar.toml``) reproduces Eq. (30)
    within the tolerance its printed precision implies
    (:func:`reports.rounding.eq30_tolerances`; the published values are read
    from ``data/published/example1.toml``):

    >>> import contextlib, io, json, tomllib
    >>> from reports.rounding import eq30_tolerances
    >>> from solver.__main__ import main
    >>> with contextlib.redirect_stdout(io.StringIO()) as out:
    ...     status = main(["solve", "data/scenes/sliding_bar.toml", "--json"])
    >>> unknowns = json.loads(out.getvalue())["unknowns"]
    >>> published = {v["id"]: v for v in tomllib.load(open("data/published/example1.toml", "rb"))["value"]}
    >>> tol = eq30_tolerances(published)
    >>> status, [abs(unknowns[n]["value"] - published[f"eq30-{n}"]["value"]) <= tol[n] for n in ("alpha", "R_A", "R_B")]
    (0, [True, True, True])
    """
    from solver.formulations import point_entries, point_text

    system = load_scene_from_args(args)
    solution = derivation.solve_instant(system, args.point, args.method)
    result = solution.to_dict(system.output_units)
    unknowns = result["unknowns"]
    check_finite({name: entry["value"] for name, entry in unknowns.items()}, _where(system))
    if "indeterminate" not in result:
        check_finite({"condition number estimate": result["condition_number_estimate"]}, _where(system))
    if args.json:
        payload = {
            "scene": system.name,
            **point_entries(solution.method, solution.point),
            "method": solution.method,
            "unknowns": unknowns,
            "condition_number_estimate": result["condition_number_estimate"],
        }
        for key in ("regime", "indeterminate", "warning", "digits_lost", "zero_to_round_off"):
            if key in result:
                payload[key] = to_output_units(result[key], system.output_units)
        if system.dependent or system.time_dependent or "regime" in result:  # the solved state is part of the answer
            payload["state"] = _state_payload(system, solution.state)
        print_json(payload)
        return 0
    rows = [
        (name, format_number(entry["value"]), entry["unit"]) for name, entry in unknowns.items()
    ]
    print(f"scene   {system.name}  ({_where(system)})")
    timed = any(_has_time(a, system) for a in system.applied_loads)
    print(f"state   {state_text(system, solution.state)}" + ("   (loads taken at the scene's time)" if timed else ""))
    print(f"method  {solution.method}   point  {point_text(solution.method, solution.point)}")
    print()
    print(format_table(("name", "value", "unit"), rows, align="lrl"))
    print()
    if "regime" in result:
        print("contacts:")
        for joint, check in result["regime"].items():
            print(f"  {joint}: {check['regime']}: {check['reason']}")
        print()
    if "indeterminate" in result:
        print(f"statically indeterminate: {result['indeterminate']}")
    else:
        print("condition number estimate of the system (1-norm, rows and columns equilibrated, so unit-free; a lower "
              f"bound, `precision` gives the exact value): {format_number(result['condition_number_estimate'], 3)}")
    if "warning" in result:
        print(f"warning: {result['warning']}")
    if "digits_lost" in result:
        print(f"warning: {digits_lost_text(result['digits_lost'], system.output_units)}")
    if "zero_to_round_off" in result:
        print(round_off_zero_text(result["zero_to_round_off"], system.output_units))
    if "alpha" in unknowns:
        print("alpha is the k-component of the angular acceleration (counter-clockwise positive).")
    return 0


def _state_payload(system, state) -> dict:
    out = {}
    for c, v, r in zip(system.free, state.q, state.qd):
        out[c.name] = {"value": v, "unit": c.unit}
        out[f"{c.name}_dot"] = {"value": r, "unit": f"{c.unit}/s"}
    out["t"] = {"value": state.t, "unit": "s"}
    return to_output_units(out, system.output_units)


def _has_time(load, system) -> bool:
    exprs = [load.couple] + ([] if load.force is None else list(load.force))
    return any(sp.sympify(e).has(system.t) for e in exprs)


# -- kinematics ------------------------------------------------------------------------------


def kinematics_command(args: argparse.Namespace) -> int:
    from solver.analyses.kinematics import kinematics_at

    system = load_scene_from_args(args)
    result = to_output_units(kinematics_at(system, args.point, args.method), system.output_units)
    if args.json:
        print_json({"scene": system.name, **result})
        return 0
    from solver.analyses.regimes import start_state

    print(f"scene   {system.name}  ({_where(system)})")
    print(f"state   {state_text(system, start_state(system))}")
    print()
    rows = []
    for body, b in result["bodies"].items():
        rows.append((body, "omega", format_number(b["omega"]["value"]), b["omega"]["unit"]))
        rows.append((body, "alpha", format_number(b["alpha"]["value"]), b["alpha"]["unit"]))
    print(format_table(("body", "quantity", "value", "unit"), rows, align="llrl"))
    print()
    rows = []
    for name, p in result["points"].items():
        for what in ("position", "velocity", "acceleration"):
            x, y = p[what]["value"]
            rows.append((name, what, format_number(x), format_number(y), p[what]["unit"]))
    print(format_table(("point", "quantity", "x", "y", "unit"), rows, align="llrrl"))
    if "zero_to_round_off" in result:
        print()
        print(round_off_zero_text(result["zero_to_round_off"]))  # (already in the output units)
    return 0


# -- eom -------------------------------------------------------------------------------------


def eom_command(args: argparse.Namespace) -> int:
    from solver.display import positive_parameters

    system = _in_regime_at_state(load_scene_from_args(args), args)
    _refuse_zero_length_at_state(system)
    with positive_parameters(system):  # |L| shown as L for a parameter of positive value
        return _eom_shown(args, system)


def _eom_shown(args: argparse.Namespace, system) -> int:
    """The equation(s) of motion of ``system`` as ``eom`` prints them."""
    from solver.formulations import point_text, shown_point

    if len(system.free) != 1 or system.closure:
        return _eom_multi(args, system)
    d = derivation.derive(system, args.point, args.method)
    eom = d.eom
    # The qdd coefficient of the equation of motion is the generalized mass M (T = 1/2 M qd^2):
    # the equations are projected on the partial velocities, so it is already tidied there.
    mass = eom.coeff(d.qdd)
    # Display form only: cancel common factors (removes removable 0/0 points
    # such as a sin(theta) in both numerator and denominator).
    reactions, untidied = _reactions_display(d)
    at_state = _reactions_at_state(system, d)
    q = system.free[0].name
    text = _printer()
    shown = shown_point(system, d.method, args.point)
    if args.json:
        print_json(_eom_payload(system, d.method, shown, [q], [eom], [[mass]], d.kinetic_energy, d.potential_energy,
                                {q: d.generalized_force}, reactions, at_state, text, args.regimes))
        return 0
    if args.latex:
        names = _latex_names(system)

        def latex(expr: sp.Expr) -> str:
            return sp.latex(expr, symbol_names=names)

        about = f"about {shown}, " if shown is not None else ""
        print(f"% {system.name}: equation of motion ({about}{d.method}); reactions eliminated")
        if _regime_line(args):
            print(f"% {_regime_line(args)}")
        print(f"{latex(eom)} = 0")
        print(f"% generalized mass M({q})")
        print(f"M = {latex(mass)}")
        print("% reactions as functions of the state (SI)")
        for name, expr in reactions.items():
            print(f"{sp.latex(sp.Symbol(name))} = {latex(expr)}")
        return 0
    print(f"scene   {system.name}  ({_where(system)})")
    print(f"method  {d.method}   point  {point_text(d.method, shown)}")
    if _regime_line(args):
        print(_regime_line(args))
    print()
    print(f"equation of motion ({q}_ddot is the second derivative of {q}):")
    print(f"  {text(eom)} = 0")
    print()
    print(f"generalized mass M({q}) (kinetic energy T = 1/2 M {q}_dot**2):")
    print(f"  M = {text(mass)}")
    print()
    print("reactions as functions of the state (SI parameters give SI values), and their values at the state:")
    for name, expr in reactions.items():
        entry = at_state[name]
        left_out = _why_left_out(expr, untidied.get(name))
        print(f"  {name} = ({left_out}; --json and --latex print it)" if left_out else f"  {name} = {text(expr)}")
        print(f"      = {format_number(entry['value'])} {entry['unit']} at the state")
    return 0


def _in_regime_at_state(system, args):
    """``system``, or with contacts that can stick, slip or separate the system in the regime that
    holds at the state, as `solve` and `explain` find it (:func:`solver.analyses.regimes.system_in_regime`),
    the regime printed first (text and LaTeX) or kept for the JSON (``args.regimes``)."""
    args.regimes = {}
    if not system.contacts:
        return system
    from solver.analyses.regimes import SPLIT_NAME, system_in_regime

    variant, found, warning, _ = system_in_regime(system, args.point)
    if found is None or (all(found.regimes[j.name] == j.current_regime for j in system.contacts)
                         and _as_written(system)):
        return system  # the scene as written (rolling as it rolls): nothing to say
    args.regimes = {name: r.label for name, r in found.regimes.items()}
    held = ", ".join(f"{j}: {r}" for j, r in args.regimes.items())
    if found.indeterminate:
        raise InputError(f"{system.label}: eom: in the contact regime that holds at the state ({held}) sticking "
                         "contacts hold redundantly (statically indeterminate); eom needs a regime whose "
                         f"equations determine every reaction: `solve` gives the motion and {SPLIT_NAME} of the forces")
    rubbing = [j.name for j in system.contacts if j.friction is not None and found.regimes[j.name].friction_direction()]
    if rubbing:  # the friction -s mu_k N is a multiple of a reaction, which the elimination does not carry
        raise InputError(f"{system.label}: eom: in the contact regime that holds at the state ({held}) "
                         f"{', '.join(map(repr, rubbing))} slides with friction -mu_k N, a force set by a reaction "
                         "that eom's elimination of the reactions does not carry: `explain` writes the equations of "
                         "motion in this regime, `solve` and `simulate` solve them")
    return variant


def _refuse_zero_length_at_state(system) -> None:
    """Refuse, as ``solve`` does, a state where a spring or damper has zero length: its force has no
    direction there, and the equations printed would be undefined (a term over Abs(d + x) = 0).
    Only an exact zero: a picometre away the forms are defined and ``solve`` answers there too.
    A state that does not assemble is left to the commands that solve at it."""
    if all(load.line_length(system) is None for load in system.loads):
        return
    from solver.analyses.instant import assemble, refuse_zero_length

    try:
        state = assemble(system)
    except InputError:
        return
    refuse_zero_length(system, state.q, state.qd, state.t, within=0.0)  # only where the forms are undefined


def _regime_line(args) -> str | None:
    """The line saying in which contact regime the equations are written (None: the scene's own)."""
    if not args.regimes:
        return None
    held = ", ".join(f"{j}: {r}" for j, r in args.regimes.items())
    return (f"contacts  in the regime that holds at the state (as `solve` finds it): {held}; the equations "
            "hold while it lasts")


def _as_written(system) -> bool:
    """Whether the scene's equations hold as written (no coordinate kept for a slip or a gap)."""
    from solver.errors import SceneError

    try:
        system.validate()
    except SceneError:
        return False
    return True


def _eom_payload(system, method, point, coordinates, eqs, mass, kinetic, potential, forces, reactions, at_state,
                 text, regimes=None) -> dict:
    """The one schema of ``eom --json``, whatever the number of freedoms: ``eom`` (one expression
    == 0 per independent coordinate, in the order of ``coordinates``), ``mass`` (the matrix of
    their coefficients of the independent accelerations: the generalized mass), the energies,
    ``generalized_forces`` by coordinate, ``reactions`` (closed forms; null where none is derived,
    with several freedoms or a loop) and each reaction's value at the state. Expressions are SI
    (``expression_units``); ``reaction_units`` and ``reactions_at_state`` are the scene's output
    units, as everywhere else."""
    from solver.formulations import point_entries

    return {
        "scene": system.name, **point_entries(method, point), "method": method,
        "coordinates": list(coordinates), "dependent": [c.name for c in system.dependent],
        "eom": [text(e) for e in eqs],
        "mass": [[text(m) for m in row] for row in mass],
        "kinetic_energy": text(_energy_display(kinetic, system)),
        "potential_energy": text(_energy_display(potential, system)),
        "generalized_forces": {name: text(_energy_display(q, system)) for name, q in forces.items()},
        "expression_units": "SI: the expressions give SI values from SI values of the parameters, "
                            "coordinates and rates",
        "reactions": None if reactions is None else {name: text(expr) for name, expr in reactions.items()},
        "reaction_units": {name: entry["unit"] for name, entry in at_state.items()},
        "reactions_at_state": at_state,
        **({"regime": regimes} if regimes else {}),  # the contacts' regime at the state, when eom is written in it
    }


def _energy_display(energy: sp.Expr, system) -> sp.Expr:
    """The display form of an energy or a generalized force: by the powers of the rates (a kinetic
    energy is quadratic in them), each coefficient by the display tidy (sin(u)**2 + cos(u)**2 = 1
    for any angle u)."""
    from solver.derivation import _tidy, _tidy_by_rate

    rates = [c.qd for c in system.free]
    return _tidy_by_rate(energy, *rates) if rates else _tidy(energy)


def _printer():
    """``str`` of expressions (sympy's text) for one command's output, common subexpressions printed once."""
    from solver.strprint import FastStrPrinter

    printer = FastStrPrinter()
    return printer.doprint


def _eom_multi(args, system) -> int:
    """n equations of motion M(q) q'' = f(q, q', t) (reactions eliminated)."""
    from solver.analyses.eom import equations_of_motion
    from solver.formulations import formulate

    f = formulate(system, args.method, args.point)
    independent = [c for c in system.free if not c.dependent]
    if not independent:
        raise InputError(f"{system.label}: eom: every motion is prescribed (no degree of freedom): there is no "
                         "equation of motion (use `solve` or `simulate` for the driving forces and reactions)")
    if system.closure:  # in the independent coordinates, the closure reactions projected out
        from solver.analyses.eom import reduced_equations_of_motion

        eqs, coords = reduced_equations_of_motion(f)
        shown = [e if _over_display_ops(e) else _tidy_multi(e, system) for e in eqs]
    else:
        eqs, coords = equations_of_motion(f), list(system.free)
        shown = [_tidy_multi(e, system) for e in eqs]
    text = _printer()
    if args.json:
        from solver.analyses.instant import solve_instant
        from solver.formulations import shown_point

        # tidied as `shown` is: by the display tidy, a mass too large for it printed as derived
        mass = [[_display_form(sp.diff(e, u.qdd), _tidy_display) for u in coords] for e in eqs]
        solution = solve_instant(system, args.point, args.method)
        at_state = {r.name: to_output_units(quantity_entry(solution.unknowns[r.name]), system.output_units)
                    for r in system.reactions}
        forces = dict(zip((c.name for c in system.free), system.generalized_forces()))
        print_json(_eom_payload(system, f.method, shown_point(system, f.method, args.point), [c.name for c in coords],
                                shown, mass, system.kinetic_energy(), system.potential_energy(), forces, None,
                                at_state, text, args.regimes))
        return 0
    if args.latex:
        from .notation import rate_latex_names

        names = rate_latex_names(system.free)
        print(f"% {system.name}: equations of motion ({f.method}); reactions eliminated")
        if _regime_line(args):
            print(f"% {_regime_line(args)}")
        for c, e in zip(coords, shown):
            print(f"% for {c.name}")
            print(f"{sp.latex(e, symbol_names=names)} = 0")
        return 0
    print(f"scene   {system.name}  ({_where(system)})")
    print(f"method  {f.method}   {len(coords)} degree(s) of freedom: {', '.join(c.name for c in coords)}")
    if _regime_line(args):
        print(_regime_line(args))
    if system.dependent:
        print(f"dependent coordinates {', '.join(c.name for c in system.dependent)} follow from the closure "
              "equations (their values and rates appear as symbols)")
    print()
    if system.closure:
        _print_projection(f, text)
        return 0
    for c, e in zip(coords, shown):
        print(f"equation for {c.name} (reactions eliminated):")
        print(f"  {text(e)} = 0")
        print()
    return 0


def _print_projection(f, text) -> None:
    """The equations of a system with closure equations as built (:class:`solver.analyses.eom.Projection`),
    each part tidied on its own: every coordinate's equation E_q (closure reactions left out), the
    velocity ratios k = dv'/du', and the dependent accelerations from the closure differentiated
    twice; the equation for u is E_u + sum_v k_v E_v = 0 (written out whole, it runs to thousands
    of characters)."""
    from solver.analyses.eom import projection
    from solver.display import tidy, tidy_linear
    from solver.strprint import join_sum

    p = projection(f)
    system = f.system
    qdd = [c.qdd for c in system.free]
    qd = [c.qd for c in system.free]
    rates = [a * b for i, a in enumerate(qd) for b in qd[i:]]
    for k, u in enumerate(p.independent):
        terms = [f"E_{u.name}"] + [f"k_{v.name}_{u.name}*E_{v.name}" for v in p.dependent]
        print(f"equation for {u.name} (reactions eliminated: the coordinates' equations projected on the motions "
              "the closure allows, with the velocity ratios k):")
        print(f"  {' + '.join(terms)} = 0")
        print()
    print("where each coordinate's equation (its closure reactions drop out of the sum) is")
    for c, e in zip(system.free, p.equations):
        print(f"  E_{c.name} = {text(tidy_linear(e, qdd + rates))}")
    print("the velocity ratios (the closure's Jacobian, dv' = k du') are")
    for j, v in enumerate(p.dependent):
        for k, u in enumerate(p.independent):
            print(f"  k_{v.name}_{u.name} = {text(tidy(p.ratios[j, k]))}")
    print("and the dependent accelerations, from the closure equations differentiated twice:")
    for j, (v, a) in enumerate(zip(p.dependent, p.dependent_rate_terms)):
        rest = tidy_linear(a, rates)
        terms = [f"k_{v.name}_{u.name}*{u.name}_ddot" for u in p.independent] + ([] if rest == 0 else [text(rest)])
        print(f"  {v.name}_ddot = {join_sum(terms)}")
    print()


def _tidy_multi(expr, system):
    from solver.derivation import _tidy_by_rate

    expr = sp.expand(expr)  # (terms that cancel go: a spring's coefficient of s_ddot, built as A - A, is 0)
    parts = []
    for c in system.free:
        coef = expr.xreplace({x.qdd: (1 if x is c else 0) for x in system.free}) - expr.xreplace({x.qdd: 0 for x in system.free})
        parts.append(_display_form(coef, _tidy_display) * c.qdd)
    rest = expr.xreplace({x.qdd: 0 for x in system.free})
    return sp.Add(*parts) + _tidy_by_rate(rest, system.free[0].qd)


DISPLAY_BUDGET_S = 4.0
"""Most CPU time spent tidying one expression for display [s]."""
DISPLAY_MAX_OPS = 200
"""Expressions larger than this are printed as derived (cancel gets slow)."""


def _over_display_ops(expr) -> bool:
    """Whether ``expr`` has more than :data:`DISPLAY_MAX_OPS` operations (``sympy.count_ops``).
    A tree of more than ten nodes an operation is taken as over without counting: count_ops
    walks the whole tree (about 1 s for a 100,000-node reaction of the plate on two links), and
    an operation of these equations holds a few nodes at most (``x - y``: five)."""
    from .display import tree_size

    cap = 10 * DISPLAY_MAX_OPS
    return tree_size(expr, cap) > cap or sp.count_ops(expr) > DISPLAY_MAX_OPS
DISPLAY_MAX_NODES = 1500
"""A reaction's closed form with more expression-tree nodes than this is not printed in the text
output (the paper scenes' have under 100; a plate on two links, solved by Cramer's rule, has
tens of thousands): its value at the state is, and --json and --latex give the expression."""


REACTION_TIDY_MAX_NODES = 10000
"""A reaction's closed form (from the general solve) with more nodes than this is not given to the
display tidy (rot_arm's T has 6092 and tidies in 0.17 s of CPU to 6 nodes; the plate on two
links, solved by Cramer's rule, has 19,000 to 26,000 a reaction, about 0.7 s each to tidy)."""


def _why_left_out(expr, untidied: str | None) -> str | None:
    """Why ``eom``'s text leaves out a reaction's closed form (the words in place of it), or None
    when it is printed. The one rule, after the display tidy (:func:`_reactions_display`): a form
    of more than :data:`DISPLAY_MAX_NODES` nodes, or one the tidy did not reach (``untidied``, the
    reason) of more than :data:`DISPLAY_MAX_OPS` operations (printed, hundreds of operations that
    nothing reduced)."""
    from solver.display import tree_size

    size = tree_size(expr, DISPLAY_MAX_NODES)
    if size > DISPLAY_MAX_NODES:
        done = untidied or "after the display tidy"
        return f"a closed form of {tree_size(expr)} nodes {done}, too long to read here"
    if untidied is not None and _over_display_ops(expr):
        return f"a closed form of {sp.count_ops(expr)} operations {untidied}, left as derived"
    return None


class _OutOfTime(Exception):
    pass


def _collect_trig(expr: sp.Expr) -> sp.Expr:
    """Expand, then let sin**2 + cos**2 = 1 combine (e.g. a generalized mass)."""
    return sp.trigsimp(sp.expand(expr))


def _tidy_display(expr: sp.Expr) -> sp.Expr:
    """The structural display form (:func:`solver.display.tidy`): numerator and denominator
    reduced modulo sin**2 + cos**2 = 1, no generic simplify."""
    from solver.display import tidy

    return tidy(expr)


def _reactions_display(d) -> tuple[dict, dict]:
    """Display forms of the reactions: numerator over the generalized mass from the structured
    solve (each part tidied on its own), else the closed form by the display tidy
    (:func:`solver.display.tidy`, up to :data:`REACTION_TIDY_MAX_NODES` nodes and within
    :data:`DISPLAY_BUDGET_S`). Returns (forms by name, {name: why the tidy did not reach it})."""
    from solver.display import tidy, tidy_fraction, tree_size

    parts = d.reaction_fractions
    if parts is not None:
        memo: dict = {}  # the reactions share their denominator (the generalized mass)
        return {name: tidy_fraction(num, den, memo) for name, (num, den) in parts.items()}, {}
    forms, untidied = {}, {}
    for name, expr in d.reactions.items():
        shown = None
        if tree_size(expr, REACTION_TIDY_MAX_NODES) > REACTION_TIDY_MAX_NODES:
            untidied[name] = f"(over the {REACTION_TIDY_MAX_NODES} the display tidy takes on)"
        else:
            shown = _within_budget(lambda e: tidy(e, REACTION_TIDY_MAX_NODES), expr)
            if shown is None:
                untidied[name] = f"(the display tidy did not finish within {DISPLAY_BUDGET_S:g} s)"
        forms[name] = expr if shown is None else shown
    return forms, untidied


def _reactions_at_state(system, d) -> dict:
    """Each reaction's value at the scene's state, in the scene's output units."""
    from solver.units import Q_

    if d.reaction_fractions is not None:  # evaluate the closed forms at the state: no lambdify needed
        from solver.tree_value import substitute

        c = system.free[0]
        values = {k: sp.Float(v) for k, v in system.si_values().items()}
        values.update({c.q: sp.Float(c.value), c.qd: sp.Float(c.rate), system.t: sp.Float(system.time)})
        memo: dict = {}  # the reactions share their denominator and terms
        quantities = {name: Q_(float(substitute(expr, values, memo)), d.reaction_units[name])
                      for name, expr in d.reactions.items()}
        check_finite({n: q.magnitude for n, q in quantities.items()}, f"{system.label}: eom")
    else:
        from solver.analyses.instant import solve_instant as solve

        solution = solve(system, d.point, d.method)
        quantities = {name: solution.unknowns[name] for name in d.reactions}
    return {name: to_output_units(quantity_entry(q), system.output_units) for name, q in quantities.items()}


def _display_form(expr: sp.Expr, tidy_with=None) -> sp.Expr:
    """A readable equivalent of ``expr`` for printing (never used to compute).

    ``tidy_with`` (default ``sympy.cancel``, which removes common factors and
    with them removable 0/0 points such as a sin(theta) above and below) can
    be slow, so it is
    tried only on moderate expressions and within :data:`DISPLAY_BUDGET_S`
    of CPU time (on the main thread of a POSIX system); otherwise the
    derived form is printed unchanged.
    """
    tidy_with = sp.cancel if tidy_with is None else tidy_with
    if _over_display_ops(expr):
        return expr
    tidy = _within_budget(tidy_with, expr)
    return tidy if tidy is not None and sp.count_ops(tidy) <= sp.count_ops(expr) else expr


def _within_budget(tidy_with, expr: sp.Expr) -> sp.Expr | None:
    """``tidy_with(expr)``, or None when it takes more than :data:`DISPLAY_BUDGET_S` of CPU time
    (timed on the main thread of a POSIX system) or sympy gives up on it."""
    timed = hasattr(signal, "SIGPROF") and threading.current_thread() is threading.main_thread()
    if timed:
        def _alarm(signum, frame):
            raise _OutOfTime

        previous = signal.signal(signal.SIGPROF, _alarm)
        signal.setitimer(signal.ITIMER_PROF, DISPLAY_BUDGET_S)
    try:
        return tidy_with(expr)
    except (_OutOfTime, sp.PolynomialError, ValueError, TypeError):
        return None
    finally:
        if timed:
            signal.setitimer(signal.ITIMER_PROF, 0)
            signal.signal(signal.SIGPROF, previous)


def _latex_names(system) -> dict[sp.Symbol, str]:
    """theta_dot -> \\dot{\\theta}, theta_ddot -> \\ddot{\\theta} (:func:`solver.notation.rate_latex_names`)."""
    from .notation import rate_latex_names

    return rate_latex_names(system.free[:1])


# -- frequency -------------------------------------------------------------------------------


def frequency_command(args: argparse.Namespace) -> int:
    scene = load_scene_from_args(args)
    if len(scene.free) != 1 or scene.closure or scene.time_dependent:
        return _modes_command(args, scene)
    if args.point is not None:
        derivation.derive(scene, args.point, args.method)  # checks the point (SceneError)
    result = derivation.natural_frequency(scene, args.method)
    omega = float(result.omega_n.to("rad/s").magnitude)
    period = float(result.period.to("s").magnitude)
    equilibrium = float(result.equilibrium.to_base_units().magnitude)  # rad or m
    check_finite({"omega_n": omega, "period": period, "equilibrium": equilibrium}, _where(scene))
    if not omega > 0:
        raise InputError(f"{_where(scene)}: the natural frequency came out as {omega}; no oscillation")
    payload = to_output_units(result.to_dict(), scene.output_units)
    payload["frequency"] = {"value": omega / (2 * math.pi), "unit": "Hz"}
    if args.json:
        print_json({"scene": scene.name, "method": args.method, **payload})
        return 0
    q = scene.free[0].name if scene.free else "q"
    angle = scene.free[0].kind == "angle"
    eq_value, eq_unit = in_output_units(math.degrees(equilibrium) if angle else equilibrium,
                                        "deg" if angle else "m", scene.output_units)
    in_rad = f" ({format_number(equilibrium)} rad)" if angle and eq_unit != "rad" else ""
    print(f"scene   {scene.name}  ({_where(scene)})")
    print(f"small oscillations about the stable equilibrium {q} = {format_number(eq_value)} {eq_unit}{in_rad}, "
          "every position-dependent load included")
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


def _modes_command(args, system) -> int:
    from solver.analyses.modes import modes
    from solver.formulations import formulate

    formulate(system, args.method, args.point)  # checks the point
    result = modes(system, args.method)
    units = system.output_units
    payload = to_output_units(result.to_dict(units), units)
    if len(result.modes) == 1:  # one freedom: also the keys of the one-coordinate answer
        (name, value), = result.equilibrium_in(units).items()
        mode = payload["modes"][0]
        payload = {"omega_n": mode["omega_n"], "frequency": mode["frequency"], "period": mode["period"],
                   **payload, "equilibrium": value}
    if system.time_dependent:
        payload["equilibrium_relative_to_prescribed_motion"] = True
    if args.json:
        print_json({"scene": system.name, "method": args.method, **payload})
        return 0
    print(f"scene   {system.name}  ({_where(system)})")
    eq = ", ".join("{} = {} {}".format(k, format_number(v[0]), v[1]) for k, v in (
        (k, in_output_units(math.degrees(v), "deg", units) if result.units[k] == "rad" else in_output_units(v, result.units[k], units))
        for k, v in result.equilibrium.items()))
    print(f"small oscillations about the stable equilibrium {eq}")
    if system.time_dependent:
        print("(relative to the prescribed motion: in its frame the equations do not depend on time)")
    print()
    omega_unit, period_unit = output_unit("rad/s", units), output_unit("s", units)
    rows = []
    for i, m in enumerate(payload["modes"], 1):
        shape = ", ".join(f"{k}: {format_number(v['value'], 4)} {v['unit']}" for k, v in m["shape"].items())
        period = m["period"]["value"]
        rows.append((str(i), format_number(m["omega_n"]["value"]), format_number(m["frequency"]["value"]),
                     "-" if period is None or not math.isfinite(period) else format_number(period), shape))
    print(format_table(("mode", f"omega_n [{omega_unit}]", "f [Hz]", f"period [{period_unit}]", "shape"), rows,
                       align="rrrrl"))
    print("\na shape gives the coordinates' amplitudes relative to one another, each in its own unit.")
    if any(m.omega == 0 for m in result.modes):
        print("a mode with omega_n = 0 is a neutral direction: nothing restores it.")
    return 0


__all__ = ["register", "solve_command", "eom_command", "frequency_command", "quantity_entry"]
