"""The units in which the commands print: the scene's ``[output_units]``, applied in one place.

The solver computes in SI. Every quantity a command prints (text, ``--json``) is an entry
``{"value": ..., "unit": SI unit}`` passed through :func:`to_output_units`, which converts it to
the unit :func:`output_unit` makes from the scene's ``[output_units]`` (documented in
``data/scenes/README.md``): the scene's own unit for a dimension it names, and for a derived
quantity (a speed, a stiffness, a moment of inertia) the unit made of the scene's units for its
parts, SI for the parts the scene does not name.
"""
from __future__ import annotations

import functools
import math
import re
from collections.abc import Mapping
from typing import Any


# What the commands print, by SI (or degree) unit -> how its [output_units] unit is made.
# A base entry names one [output_units] key; a derived entry is a formula over the keys, each
# key standing for the scene's unit or, where the scene gives none, for the SI unit after "|".
# Rates stay per second (ft/s, not ft/min): `time` is the unit of durations (t, a period), and
# angular rates have keys of their own.
# The units are compared as pint parses them, so "m * N" is "N*m" (but "J" is not "N*m").
_OUTPUT_UNIT_RULES = {
    "N": "{force|N}", "N*m": "{moment|N*m}", "m": "{length|m}", "kg": "{mass|kg}", "s": "{time|s}",
    "rad": "{angle|rad}", "deg": "{angle|deg}", "rad/s": "{angular_velocity|rad/s}",
    "rad/s**2": "{angular_acceleration|rad/s**2}",
    "m/s": "{velocity|{length|m}/s}", "m/s**2": "{acceleration|{length|m}/s**2}",
    "N*m/rad": "{moment|N*m}/rad", "N/m": "{force|N}/{length|m}", "kg*m**2": "{mass|kg}*{length|m}**2",
    "N*m*s/rad": "{moment|N*m}*s/rad", "N*s/m": "{force|N}*s/{length|m}",
    "J": "{length|m}*{force|N}",  # work (friction's): a force times a length, ft*lbf in US units
}
# A rule used instead of the one above when the scene names these keys and not the first
# rule's own: a moment of inertia with no mass unit given but a moment unit (ft*lbf) prints in
# that unit times s**2 (ft*lbf*s**2, the slug*ft**2 of US texts), not in kg*ft**2.
_WHEN_NAMED = {"kg*m**2": (("mass",), ("moment",), "{moment|N*m}*s**2")}
_RULE_TERM = re.compile(r"\{(\w+)\|([^{}]*(?:\{[^{}]*\}[^{}]*)*)\}")


def _fill_rule(rule: str, units: Mapping[str, str]) -> tuple[str, bool]:
    """The unit text a rule makes, and whether any scene unit entered it."""
    used = False

    def term(match: re.Match) -> str:
        nonlocal used
        key, fallback = match.group(1), match.group(2)
        if key in units:
            used = True
            text = units[key]
        else:
            text, inner = _fill_rule(fallback, units)
            used = used or inner
        whole = match.start() == 0 and match.end() == len(rule)
        simple = whole or re.fullmatch(r"\w+", text) or (match.start() == 0 and re.fullmatch(r"[\w*]+", text))
        return text if simple else f"({text})"

    return _RULE_TERM.sub(term, rule), used


@functools.lru_cache(maxsize=256)
def _si_rule(unit: str) -> tuple[str, str] | None:
    """(SI spelling, rule) of :data:`_OUTPUT_UNIT_RULES` for ``unit`` (any spelling pint reads
    alike), or None."""
    from solver.units import ureg  # here, not above: `--help` loads no pint

    try:
        parsed = ureg.Unit(unit)
    except Exception:  # noqa: BLE001 - a label pint does not read (e.g. "") is not converted
        return None
    for si, rule in _OUTPUT_UNIT_RULES.items():
        if ureg.Unit(si) == parsed:
            return si, rule
    return None


def output_unit(unit: str, units: Mapping[str, str] | None) -> str:
    """The unit in which a quantity the solver holds in ``unit`` (SI, or deg for angles) is
    printed, given the scene's ``[output_units]``.

    A quantity of a dimension the scene names prints in the scene's unit; a derived quantity
    (a speed, a stiffness, a moment of inertia, ...) prints in the unit made of the scene's
    units for its parts (``ft*lbf/rad`` when ``moment = "ft*lbf"``; ``kg*ft**2`` when only
    ``length = "ft"``); a quantity none of whose parts the scene names prints in SI, spelled
    as in :data:`_OUTPUT_UNIT_RULES` (``N*m``, not ``m * N``); anything else stays in ``unit``.

    >>> output_unit("N*m/rad", {"moment": "ft*lbf"}), output_unit("m/s", {"length": "ft"})
    ('ft*lbf/rad', 'ft/s')
    >>> output_unit("m * N", {"moment": "ft*lbf"}), output_unit("Hz", {"time": "min"})
    ('ft*lbf', 'Hz')
    """
    found = _si_rule(unit)
    if found is None:
        return unit
    units = units or {}
    rule = found[1]
    if found[0] in _WHEN_NAMED:
        own, other, alternative = _WHEN_NAMED[found[0]]
        if not any(k in units for k in own) and all(k in units for k in other):
            rule = alternative
    text, used = _fill_rule(rule, units)
    return text if used else found[0]


def si_unit_of(unit) -> str:
    """The SI unit of :data:`_OUTPUT_UNIT_RULES` of the dimension of the pint ``unit`` (the first
    in the table's order: ``N*m`` before ``J``, ``rad/s**2`` for 1/s**2; an angle's for no
    dimension never), or the SI base units when the table has none (``m**2/s**2``).

    >>> from solver.units import ureg
    >>> si_unit_of(ureg.Unit("N*m/(kg*ft)")), si_unit_of(ureg.Unit("N*m/in")), si_unit_of(ureg.Unit("N*m/kg"))
    ('m/s**2', 'N', 'm**2/s**2')
    """
    from solver.units import ureg

    for si in _OUTPUT_UNIT_RULES:
        if si not in ("rad", "deg") and ureg.Unit(si).dimensionality == unit.dimensionality:
            return si
    return f"{(1.0 * unit).to_base_units().units:~C}" or "1"


def to_output_units(payload: Any, units: Mapping[str, str] | None) -> Any:
    """``payload`` with every ``{"value": ..., "unit": u}`` entry converted to the unit
    :func:`output_unit` gives for ``u`` (values may be numbers or lists of numbers, or lists
    of such lists); the rest unchanged. The one place where printed quantities change unit."""
    if isinstance(payload, list):
        return [to_output_units(item, units) for item in payload]
    if not isinstance(payload, dict):
        return payload
    unit = payload.get("unit")
    target = output_unit(unit, units) if isinstance(unit, str) and "value" in payload else unit
    if target != unit:
        from solver.units import ureg

        factor = float(ureg.Quantity(1.0, unit).to(target).magnitude)
        value = payload["value"] if factor == 1.0 else _scaled(payload["value"], factor)
        return {**payload, "value": value, "unit": target}
    return {key: to_output_units(item, units) for key, item in payload.items()}


SIGNIFICANT_DIGITS = 15
"""A converted value is rounded to this many significant digits: float64 holds 15.95, and the trip
through SI (0.5 ft -> 0.1524 m -> 0.49999999999999994 ft) errs in the 16th-17th; so a value given
in the output unit comes back as given."""


def rounded_at(value: float, resolution: float) -> float:
    """``value`` rounded at the decimal place of ``resolution`` (> 0), the size below which its digits
    are round-off: the nearest double to the decimal number kept (an equilibrium solved to 1e-12 of
    its scale, -0.999999999999998 ft of a spring's 1 ft, is -1.0). What :data:`SIGNIFICANT_DIGITS`
    does for a unit's factor, for a value whose own accuracy is known to be less."""
    if not (value and math.isfinite(value) and resolution > 0 and math.isfinite(resolution)):
        return value
    return round(value, -math.floor(math.log10(resolution)))


def _scaled(value: Any, factor: float) -> Any:
    if getattr(value, "ndim", 0):  # a numpy array (a column of samples): scaled as a whole
        return _rounded(value * factor)
    if isinstance(value, (list, tuple)):
        return [_scaled(v, factor) for v in value]
    return None if value is None else float(f"{float(value) * factor:.{SIGNIFICANT_DIGITS}g}")


def _rounded(values):
    """``values`` (a numpy array) to :data:`SIGNIFICANT_DIGITS` significant digits, vectorised: each
    the nearest double to round(v * 10**k) / 10**k with 10**k exact (|k| <= 22), as ``f"{v:.15g}"``
    reads, up to a tie in the last digit; values whose k falls outside (below 1e-8 or above 1e36
    in size), zeros and non-finite ones are left as they are."""
    import numpy as np

    v = np.asarray(values, dtype=float)
    with np.errstate(all="ignore"):
        k = SIGNIFICANT_DIGITS - 1 - np.floor(np.log10(np.abs(v)))
        ok = np.isfinite(k) & (np.abs(k) <= 22)
        kk = np.where(ok, k, 0.0)
        up, down = 10.0 ** np.maximum(kk, 0), 10.0 ** np.maximum(-kk, 0)
        out = np.where(kk >= 0, np.round(v * up) / up, np.round(v / down) * down)
    return np.where(ok, out, v)


def in_output_units(value: Any, unit: str, units: Mapping[str, str] | None) -> tuple[Any, str]:
    """(value, unit) of one quantity as printed (:func:`to_output_units` of one entry)."""
    entry = to_output_units({"value": value, "unit": unit}, units)
    return entry["value"], entry["unit"]


def columns_in_output_units(columns: Mapping[str, tuple[Any, str]], units: Mapping[str, str] | None
                            ) -> dict[str, tuple[Any, str]]:
    """Columns of samples ``name -> (values, SI unit)`` (a time history) as every output prints
    them: each converted by :func:`in_output_units`, with the unit it is then in."""
    return {name: in_output_units(values, unit, units) for name, (values, unit) in columns.items()}


__all__ = ["rounded_at", "output_unit", "si_unit_of", "to_output_units", "in_output_units", "columns_in_output_units"]
