"""``friction`` for scenes with contacts that stick, slip or separate.

* at the state: the regime that holds, and the least friction coefficient of
  each contact that keeps it sticking (rolling), a rolling contact without a
  coefficient included;
* ``--over T``: the least coefficient over a motion, with the friction
  assumed sufficient (max |F|/N along the run);
* ``--critical NAME --between LOW HIGH``: the values of a coordinate or a
  parameter at which a motion from rest starts (:mod:`solver.analyses.thresholds`),
  or, when there is none in the range, the regime that holds throughout it.

The one-angle answers of Examples 1 and 2 (the rolling table over a free
oscillation, the release window) stay in :mod:`solver.cli_dynamics`.
"""
from __future__ import annotations

import argparse
import math

from solver.cli_common import format_number, format_table, output_unit, print_json, state_text, to_output_units
from solver.errors import InputError


def contact_friction(args: argparse.Namespace, system) -> int:
    """Answer ``friction`` from the scene's contacts."""
    if not system.contacts:
        raise InputError(f"{system.label}: friction: the scene has no contact with friction or a one-sided force")
    for flag, given in (("--amplitude", args.amplitude), ("--mass-ratio", args.mass_ratio),
                        ("--ratio-of", args.ratio_of), ("--range", args.range), ("--reactions", args.reactions)):
        if given:
            raise InputError(f"{system.label}: {flag} applies to the one-angle rolling table or release window; "
                             "this scene is answered from its contacts (--critical, --between, --over)")
    if (args.critical is None) != (args.between is None):
        raise InputError("--critical and --between go together: --critical NAME --between LOW HIGH")
    from solver.formulations import resolve_points

    resolve_points(system, getattr(args, "point", None))  # checked: regimes and least mu do not depend on P
    payload = {"scene": system.name, "mode": "contacts"}
    units = system.output_units  # times and forces as the text prints them (--critical picks its own unit)
    payload["at_state"] = to_output_units(_at_state(system), units)
    if args.over is not None:
        payload["over_motion"] = to_output_units(_over(system, args.over), units)
    if args.critical is not None:
        payload["critical"] = _critical(system, args.critical, args.between)
    if args.json:
        print_json(payload)
        return 0
    _print(system, payload)
    return 0


def _at_state(system) -> dict:
    """The regime at the state and, per contact, the least mu that keeps it sticking."""
    from solver.analyses.regimes import find_regime, least_friction, start_state

    st = start_state(system)
    regime = find_regime(system, st.q, st.qd, st.t)
    return {"state": state_text(system, st), "regime": {c.joint: c.to_dict() for c in regime.checks},
            "indeterminate": regime.indeterminate, "least_mu": least_friction(system, st)}


def _over(system, text) -> dict:
    from solver.analyses.motion import simulate_system
    from solver.analyses.regimes import holding
    from solver.units import parse_time

    T = parse_time(text, "--over")
    from solver.cli_dynamics import MAX_OVER_T

    if not 0 < T <= MAX_OVER_T:
        raise InputError(f"--over must be a positive time of at most {MAX_OVER_T:g} s, got {text!r}")
    held = holding(system)
    res = simulate_system(held, T, rtol=1e-10, atol=1e-12, samples=2001)
    out = {"t_end": {"value": float(res.t[-1]), "unit": "s"}, "status": res.status, "reason": res.reason,
           "least_mu": {}}
    for j in held.contacts:
        F, N = j.pair
        if F is None or F.name not in res.columns:
            continue
        f, n = res.columns[F.name][0], res.columns[N.name][0]
        ratio = [abs(a) / b if b > 0 else math.inf for a, b in zip(f, n)]
        k = max(range(len(ratio)), key=ratio.__getitem__)
        out["least_mu"][j.name] = {"value": float(ratio[k]), "at_t": {"value": float(res.t[k]), "unit": "s"}}
    return out


def _critical(system, name, between) -> dict:
    """Onsets of motion from rest as ``name`` (a coordinate or a parameter) sweeps ``between``."""
    from solver.analyses.thresholds import onsets
    from solver.units import Q_, parse_angle, parse_quantity

    flags = ("--between LOW", "--between HIGH")
    coord = next((c for c in system.free if c.name == name), None)
    if coord is not None and coord.kind == "angle":  # bare numbers are degrees, as for every angle flag
        low, high = (parse_angle(v, f) for v, f in zip(between, flags))
        unit = output_unit("deg", system.output_units)
        scale = float(Q_(1.0, unit).to("rad").magnitude)
    else:
        if coord is not None:  # a length, printed in the scene's output length
            shown = parse_quantity(f"1 {output_unit('m', system.output_units)}", "--critical").units
        elif name in system.parameters:
            shown = system.parameters[name].units
        else:
            raise InputError(f"{system.label}: --critical {name}: not a coordinate or a parameter "
                             f"(coordinates: {', '.join(c.name for c in system.free)}; "
                             f"parameters: {', '.join(system.parameters)})")
        low, high = (_in_units_of(parse_quantity(v, f), shown, f, v) for v, f in zip(between, flags))
        unit = format(shown, "~") or "1"
        scale = float((1 * shown).to_base_units().magnitude)
    found = onsets(system, name, low, high)
    out = {"name": name, "unit": unit, "between": [low / scale, high / scale],
           "onsets": [{**o.to_dict(unit), "value": o.value / scale} for o in found], "throughout": None}
    if not found:
        out.update(_throughout(system, name, low, high, scale, unit))
    return out


def _throughout(system, name, low, high, scale, unit) -> dict:
    """With no onset in [low, high]: the regime at rest there, each contact's label
    (``throughout``), checked at both ends and the middle; or a ``note`` saying why not."""
    from solver.analyses.regimes import AmbiguousRegime, NoConsistentRegime
    from solver.analyses.thresholds import regime_at_rest

    found = {}
    for value in (low, 0.5 * (low + high), high):
        try:
            res = regime_at_rest(system, name, value)
        except (NoConsistentRegime, AmbiguousRegime) as err:
            return {"note": f"at {name} = {format_number(value / scale, 6)} {unit}: {err}"}
        found[value] = {joint: regime.label for joint, regime in res.regimes.items()}
    if len({tuple(sorted(v.items())) for v in found.values()}) > 1:
        at = "; ".join(f"{name} = {format_number(v / scale, 6)} {unit}: {_regime_words(r)}" for v, r in found.items())
        return {"note": f"no onset was found, but the regime at rest is not the same across the range ({at})"}
    return {"throughout": found[low]}


def _regime_words(regimes: dict) -> str:
    """'every contact sticks', or each contact with what it does ('floor slips (+ along its line)')."""
    if all(label == "stick" for label in regimes.values()):
        return "every contact sticks"

    def verb(label: str) -> str:
        if label.startswith("slip"):
            return f"slips ({label.split()[1]} along its line)"
        return {"stick": "sticks", "slides": "slides", "separated": "separates"}.get(label, label)
    return ", ".join(f"{joint} {verb(label)}" for joint, label in regimes.items())


def _in_units_of(q, unit, flag, text) -> float:
    """``q`` in SI, after checking that it has the dimension of ``unit``."""
    if q.dimensionality != (1 * unit).dimensionality:
        raise InputError(f"{flag} {text!r}: expected a quantity in {format(unit, '~') or 'plain numbers'}")
    value = float(q.to_base_units().magnitude)
    if not math.isfinite(value):
        raise InputError(f"{flag} {text!r}: must be finite")
    return value


def _print(system, payload) -> None:
    at = payload["at_state"]
    print(f"scene   {system.name}  ({system.label})")
    print(f"state   {at['state']}")
    print()
    print("contacts at the state:")
    for joint, check in at["regime"].items():
        print(f"  {joint}: {check['regime']}: {check['reason']}")
    if at["indeterminate"]:
        print("  (statically indeterminate: the split of the sticking forces is not determined)")
    print()
    print("least friction coefficient to keep each contact sticking (rolling) at the state:")
    rows = [(j, format_number(v["value"], 10) if v["value"] is not None else "-", v["note"])
            for j, v in at["least_mu"].items()]
    print(format_table(("contact", "mu_min", "note"), rows, align="lrl"))
    if "over_motion" in payload:
        over = payload["over_motion"]

        def time(entry: dict) -> str:  # already in the scene's output units
            return f"{format_number(entry['value'], 6)} {entry['unit']}"

        print()
        print(f"least friction coefficient over the motion to t = {time(over['t_end'])} "
              f"({over['status']}: {over['reason']}):")
        for j, v in over["least_mu"].items():
            print(f"  {j}: mu_min = {format_number(v['value'], 10)} (at t = {time(v['at_t'])})")
    if "critical" in payload:
        c = payload["critical"]
        print()
        unit = "" if c["unit"] in ("", "1", "dimensionless") else f" {c['unit']}"  # a pure number has none
        print(f"motion from rest as {c['name']} goes from {format_number(c['between'][0], 6)} to "
              f"{format_number(c['between'][1], 6)}{unit}:")
        if c["throughout"] is not None:
            print(f"  no regime change in the range: from rest, {_regime_words(c['throughout'])} throughout")
        elif not c["onsets"]:
            print(f"  no regime change found in the range; {c['note']}")
        for o in c["onsets"]:
            what = ", ".join(f"{k} {v}" for k, v in o["regimes"].items())
            side = "above" if o["starts"] else "below"
            print(f"  {c['name']} = {format_number(o['value'], 12)}{unit}: {what} is possible {side} it")
