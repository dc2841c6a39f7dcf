"""The project's single pint unit registry, and the guarded way into it.

Quantities enter and leave at the public boundary (scene files, command line,
reports); the numeric core works in SI floats or sympy symbols. Import
``ureg`` and ``Q_`` from here, never create another registry.

Text from a file or the command line never reaches pint unchecked: pint
evaluates the exponents in a unit string exactly, so ``"kg**9**9**9"`` would
make it compute an integer with hundreds of millions of digits (a hang).
:func:`parse_unit`, :func:`parse_quantity` and :func:`parse_angle` check the
text first (:func:`check_unit_text`: length, characters, exponents, nesting)
and the parsed unit afterwards (its exponents and its factor to SI). Every
caller that reads a unit or a quantity from a user goes through them.

Limits
------
:data:`MAX_QUANTITY_LENGTH`, :data:`MAX_UNIT_LENGTH`, :data:`MAX_UNIT_EXPONENT`,
:data:`MAX_UNIT_NESTING`, :data:`MAX_MAGNITUDE` and :data:`MAX_ANGLE_TURNS`
(stated in ``data/scenes/README.md``).
"""
from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Any

import pint

from solver.errors import InputError
from solver.files import user_cache_dir



def _registry() -> pint.UnitRegistry:
    """The registry, from pint's cache of its parsed definitions when a private per-user
    cache folder exists (:func:`solver.files.user_cache_dir`; it saves about 0.3 s per
    command), else parsed afresh.

    One cache folder per pint installation: pint's cached definitions record the folder they
    were read from and resolve their ``@import`` lines against it, so a cache written by
    another installation (another virtual environment, or one since deleted) would fail and
    every run would parse afresh."""
    import hashlib

    place = hashlib.blake2b(str(Path(pint.__file__).parent).encode(), digest_size=8).hexdigest()
    folder = user_cache_dir(f"pint-{place}")
    if folder is not None:
        try:
            return pint.UnitRegistry(cache_folder=folder)
        except Exception:  # noqa: BLE001 - a damaged cache only costs the time it was to save
            pass
    return pint.UnitRegistry()


ureg = _registry()
# pint knows `lb` (pound mass) and `lbf`; spell out the engineering aliases too.
ureg.define("lbm = pound")
ureg.define("@alias turn = rev")  # rev/s, as a rotation rate is written (pint has revolution and rpm)
Q_ = ureg.Quantity

MAX_QUANTITY_LENGTH = 200
"""Longest accepted quantity text, number and unit together [characters]."""
MAX_UNIT_LENGTH = 100
"""Longest accepted unit text [characters]."""
from solver.limits import MAX_UNIT_EXPONENT  # noqa: E402 - also stated by --help, without pint
MAX_UNIT_NESTING = 3
"""Deepest nesting of parentheses in a unit text."""
MAX_MAGNITUDE = 1e300
"""A quantity's number must be 0 or between 1/MAX_MAGNITUDE and MAX_MAGNITUDE in
size (as the constants of expressions); so must a unit's factor to SI."""
MAX_ANGLE_TURNS = 1000
"""Largest accepted size of a state angle or an angle on the command line
[turns] (360000 deg, about 6283 rad). Beyond it sin and cos of a float64
angle lose their digits (1e300 deg has no meaningful sine)."""
MAX_ANGLE_RAD = 2 * math.pi * MAX_ANGLE_TURNS
""":data:`MAX_ANGLE_TURNS` in radians."""

_UNIT_CHARS = re.compile(r"^[A-Za-z0-9_ .*/^()+\-°µμΩ%]*$")
_SUPERSCRIPTS = {"²": "**2", "³": "**3"}
_TOKEN = re.compile(
    r"\s*(?:(?P<pow>\*\*|\^)|(?P<num>(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)|(?P<name>[A-Za-z_°µμΩ%][A-Za-z0-9_°µμΩ%]*)"
    r"|(?P<op>[*/()+\-.]))"
)
_NUMBER_EXP = r"[+-]?\s*(?:\d{1,3}(?:\.\d{1,6})?|\.\d{1,6})"
_EXPONENT = re.compile(rf"\s*(?:\(\s*(?P<paren>{_NUMBER_EXP})\s*\)|(?P<bare>{_NUMBER_EXP}))")
_QUANTITY = re.compile(r"^\s*([+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?)\s*(.*?)\s*$")


def check_unit_text(text: str, where: str) -> str:
    """Check a unit text before pint sees it; return it with ``²``/``³`` spelled ``**2``/``**3``.

    Parameters
    ----------
    text : str
        The unit as written, e.g. ``"ft/s^2"``.
    where : str
        Where it came from (``"scene.toml: parameters.g"``, ``"--amplitude"``);
        it starts every error message.

    Returns
    -------
    str
        The text to hand to pint.

    Raises
    ------
    InputError
        Longer than :data:`MAX_UNIT_LENGTH`; a character no unit uses; an
        exponent that is not a plain number of size at most
        :data:`MAX_UNIT_EXPONENT` (``kg**1e9``, ``kg**x``); a power of a power
        (``kg**9**9``); parentheses unbalanced or nested deeper than
        :data:`MAX_UNIT_NESTING`; a number of more than 15 characters.

    Examples
    --------
    >>> check_unit_text("ft/s²", "demo")
    'ft/s**2'
    >>> check_unit_text("kg**9**9**9", "demo")
    Traceback (most recent call last):
    ...
    solver.errors.InputError: demo: a power of a power in unit 'kg**9**9**9' (write one exponent, at most 12 in size)
    """
    if len(text) > MAX_UNIT_LENGTH:
        raise InputError(f"{where}: unit text is {len(text)} characters long; the limit is {MAX_UNIT_LENGTH}")
    for sup, plain in _SUPERSCRIPTS.items():
        text = text.replace(sup, plain)
    if not _UNIT_CHARS.match(text):
        bad = next(c for c in text if not _UNIT_CHARS.match(c))
        raise InputError(f"{where}: character {bad!r} is not allowed in unit {text!r}")
    depth, pos, after_exponent = 0, 0, False
    while pos < len(text):
        token = _TOKEN.match(text, pos)
        if token is None or token.end() == pos:
            if text[pos:].strip() == "":
                break
            raise InputError(f"{where}: cannot read unit {text!r} at column {pos + 1}")
        pos = token.end()
        if token.group("pow"):
            if after_exponent:
                raise InputError(
                    f"{where}: a power of a power in unit {text!r} "
                    f"(write one exponent, at most {MAX_UNIT_EXPONENT} in size)"
                )
            exponent = _EXPONENT.match(text, pos)
            if exponent is None:
                raise InputError(
                    f"{where}: the exponent in unit {text!r} must be a plain number "
                    f"of size at most {MAX_UNIT_EXPONENT}, e.g. m**2"
                )
            value = float((exponent.group("paren") or exponent.group("bare")).replace(" ", ""))
            if abs(value) > MAX_UNIT_EXPONENT or _EXPONENT_TAIL.match(text, exponent.end()):
                raise InputError(
                    f"{where}: the exponent in unit {text!r} must be a plain number "
                    f"of size at most {MAX_UNIT_EXPONENT}, e.g. m**2"
                )
            pos, after_exponent = exponent.end(), True
            continue
        after_exponent = False
        if token.group("num") and len(token.group("num")) > 15:
            raise InputError(f"{where}: number {token.group('num')[:20]!r}... in unit {text!r} is too long")
        op = token.group("op")
        if op == "(":
            depth += 1
            if depth > MAX_UNIT_NESTING:
                raise InputError(f"{where}: parentheses nested deeper than {MAX_UNIT_NESTING} in unit {text!r}")
        elif op == ")":
            depth -= 1
            if depth < 0:
                raise InputError(f"{where}: unbalanced parentheses in unit {text!r}")
    if depth != 0:
        raise InputError(f"{where}: unbalanced parentheses in unit {text!r}")
    return text


# an exponent must end at an operator, a parenthesis or the end (not "m**2e9", "m**2.5.5")
_EXPONENT_TAIL = re.compile(r"[0-9A-Za-z_.]")


def parse_unit(text: str, where: str) -> pint.Unit:
    """A pint unit from user text, guarded (:func:`check_unit_text`, then the parsed unit's
    exponents and its factor to SI).

    Raises
    ------
    InputError
        ``"<where>: ..."`` for any unit text that is refused or unknown.

    Examples
    --------
    >>> parse_unit("ft*lbf", "demo")
    <Unit('foot * force_pound')>
    """
    if not isinstance(text, str):
        raise InputError(f"{where}: expected a unit written as text, got {type(text).__name__} {text!r}")
    checked = check_unit_text(text, where)
    try:
        unit = ureg.parse_units(checked) if checked.strip() else ureg.dimensionless
    except Exception as err:  # noqa: BLE001 - pint raises several types for bad unit text
        raise InputError(f"{where}: unknown unit {text!r} ({_short(err)})") from None
    exponents = [abs(float(power)) for _, power in unit._units.items()]  # noqa: SLF001 - no public API
    if any(p > MAX_UNIT_EXPONENT for p in exponents):
        raise InputError(f"{where}: unit {text!r} has an exponent larger than {MAX_UNIT_EXPONENT}")
    try:
        factor = si_magnitude(Q_(1.0, unit))
    except Exception as err:  # noqa: BLE001 - overflow or pint trouble: refuse the unit
        raise InputError(f"{where}: unit {text!r} cannot be converted to SI ({_short(err)})") from None
    if not (math.isfinite(factor) and 1 / MAX_MAGNITUDE <= abs(factor) <= MAX_MAGNITUDE):
        raise InputError(f"{where}: unit {text!r} is out of range (its factor to SI is {factor:g})")
    return unit


def parse_quantity(text: Any, where: str) -> pint.Quantity:
    """Parse ``"<number> <unit>"`` (``"50 lbm"``, ``"32.174 ft/s^2"``, ``"0.3"``), guarded.

    The number is read here (no arithmetic from the text is evaluated); only
    the unit reaches pint, through :func:`parse_unit`. A TOML number (int or
    float) is a pure number.

    Raises
    ------
    InputError
        ``"<where>: ..."`` when the text is longer than
        :data:`MAX_QUANTITY_LENGTH`, the number is not finite or is outside
        1e-300 .. 1e300 in size (0 is allowed), or the unit is refused.

    Examples
    --------
    >>> parse_quantity("32.174 ft/s^2", "demo")
    <Quantity(32.174, 'foot / second ** 2')>
    >>> parse_quantity("50 kg**1e9", "demo")
    Traceback (most recent call last):
    ...
    solver.errors.InputError: demo: the exponent in unit 'kg**1e9' must be a plain number of size at most 12, e.g. m**2
    """
    if isinstance(text, bool):
        raise InputError(f"{where}: expected a quantity such as \"4 ft\", got {text!r}")
    if isinstance(text, (int, float)):
        try:
            number, unit_text = float(text), ""
        except OverflowError:
            raise InputError(f"{where}: the number {str(text)[:20]}... is too large") from None
    elif isinstance(text, str):
        if len(text) > MAX_QUANTITY_LENGTH:
            raise InputError(f"{where}: quantity text is {len(text)} characters long; the limit is {MAX_QUANTITY_LENGTH}")
        match = _QUANTITY.match(text)
        if match is None or (match.group(2) and not (match.group(2)[0].isalpha() or match.group(2)[0] in "(°%µμΩ")):
            raise InputError(
                f"{where}: expected a number followed by a unit, such as \"4 ft\" or \"45 deg\", got {text!r}"
            )
        number, unit_text = float(match.group(1)), match.group(2)
    else:
        raise InputError(f"{where}: expected a quantity such as \"4 ft\", got {type(text).__name__} {text!r}")
    check_magnitude(number, where, text)
    unit = parse_unit(unit_text, where) if unit_text else ureg.dimensionless
    if unit_text and unit.dimensionless and not _plain_dimensionless(unit):
        raise InputError(
            f"{where}: {unit_text!r} has no dimension but is not one of the plain units "
            f"({', '.join(DIMENSIONLESS_UNITS)}); write e.g. \"30 deg\" or a bare number"
        )
    return Q_(number, unit)


ANGLE_UNITS = ("radian", "degree", "arcminute", "arcsecond", "turn", "revolution", "gradian")
"""The angle units (and their symbols and pint's aliases: ``deg``, ``rev``, ``grad``, ``gon``)."""
PURE_NUMBER_UNITS = ("percent",)
"""Dimensionless units that are not angles: a pure number (a ratio, a friction coefficient), never
an angle or an angular velocity (100 percent is not 1 rad, nor a 100 % slope's 45 deg)."""
DIMENSIONLESS_UNITS = ANGLE_UNITS + PURE_NUMBER_UNITS
"""The units a dimensionless quantity may carry: one of these, to the power 1
(``"30 deg**2"`` or ``"2 ft/m"`` would be silently taken as a scaled pure number)."""
_PLAIN_NAMES = frozenset(ureg.get_name(n) for n in DIMENSIONLESS_UNITS)  # pint's names: gradian is grade


def _plain_dimensionless(unit: pint.Unit) -> bool:
    items = list(unit._units.items())  # noqa: SLF001 - no public API
    return len(items) == 1 and items[0][1] == 1 and ureg.get_name(items[0][0]) in _PLAIN_NAMES


def not_angular(unit) -> str | None:
    """The one test of whether a unit of an angle's, an angular velocity's or an angular
    acceleration's dimension measures one. None when it does: an angle unit (rad, deg, turn,
    gradian...), alone or per time or time squared (rad/s, rpm, rev/s^2), or for a rate a time unit
    alone to a negative power (``1/s``, ``s^-2``, as SI writes rad/s and rad/s^2); else what the
    unit measures instead, in words. pint reads every dimensionless unit as a number of radians,
    so without this 100 percent would be 1 rad, 2 Hz (cycles per second) 2 rad/s and 1 Hz/s
    1 rad/s^2.

    Examples
    --------
    >>> not_angular(ureg.Unit("deg")), not_angular(ureg.Unit("rev/min")), not_angular(ureg.Unit("1/s"))
    (None, None, None)
    >>> not_angular(ureg.Unit("rev/s^2")), not_angular(ureg.Unit("s^-2"))
    (None, None)
    >>> not_angular(ureg.Unit("percent")), not_angular(ureg.Unit("kHz")), not_angular(ureg.Unit("Hz/s"))
    ('a pure number', 'a frequency (cycles or counts per time)', 'a frequency per time (cycles or counts per time squared)')
    """
    if angle_power(unit) == 1:
        return None
    names = list(unit._units)  # noqa: SLF001
    dim = ureg.get_dimensionality(unit)
    if not names or (dim.get("[time]", 0) < 0 and len(dim) == 1
                     and all(ureg.get_dimensionality(n) == _TIME for n in names)):
        return None  # a bare number (the callers' rule on those applies), or 1/s, 1/s^2
    if not dim:
        return "a pure number"
    return "a frequency (cycles or counts per time)" if dim == _TIME_INVERSE else \
        "a frequency per time (cycles or counts per time squared)"


def angle_power(unit) -> float:
    """The power of the radian in ``unit`` written in SI base units: 1 for deg, rev/s and rpm, 0 for
    percent, 1/s and Hz (pint keeps the radian as a base unit of no dimension)."""
    _, base = ureg.get_base_units(unit)
    return base._units.get("radian", 0)  # noqa: SLF001 - no public API


_TIME = ureg.get_dimensionality("s")
_TIME_INVERSE = ureg.get_dimensionality("1/s")


def check_rate_unit(quantity: pint.Quantity, text: Any, where: str, name: str, also: str = "") -> None:
    """The rule for an angular velocity or acceleration given as a quantity (a coordinate's rate in a
    scene file or by ``--set``, a parameter the scene gives as one or uses as one in an angle): its
    unit measures an angle per time or time squared (:func:`not_angular`); ``Hz`` counts cycles, so
    ``2 Hz`` and ``1 Hz/s`` are refused with the two readings (and ``also``, a further way out, at
    the message's end).

    Examples
    --------
    >>> check_rate_unit(Q_(2, "Hz"), "2 Hz", "--set theta_dot", "theta_dot")
    Traceback (most recent call last):
    ...
    solver.errors.InputError: --set theta_dot: '2 Hz' is a frequency (cycles or counts per time), but theta_dot is an angular velocity: give "2 rev/s" (12.5664 rad/s) for turns per second, or "2 rad/s"
    >>> check_rate_unit(Q_(1, "Hz/s"), "1 Hz/s", "--set al", "al")
    Traceback (most recent call last):
    ...
    solver.errors.InputError: --set al: '1 Hz/s' is a frequency per time (cycles or counts per time squared), but al is an angular acceleration: give "1 rev/s^2" (6.28319 rad/s^2) for turns per second squared, or "1 rad/s^2"
    """
    kinds = {_TIME_INVERSE: ("an angular velocity", "s", "per second"),
             _TIME_INVERSE ** 2: ("an angular acceleration", "s^2", "per second squared")}
    if quantity.dimensionality not in kinds:
        return
    what = not_angular(quantity.units)
    if what is not None:
        kind, per, words = kinds[quantity.dimensionality]
        number = float(quantity.to(f"1/{per}").magnitude)
        raise InputError(f"{where}: {str(text)!r} is {what}, but {name} is {kind}: give "
                         f"\"{number:g} rev/{per}\" ({2 * math.pi * number:g} rad/{per}) for turns {words}, "
                         f"or \"{number:g} rad/{per}\"{also}")


def check_cycle_unit(quantity: pint.Quantity, text: Any, where: str, name: str) -> None:
    """The mirror of :func:`check_rate_unit`, for a frequency used to count cycles (a scene's ``f``
    in ``2*pi*f*t``, where ``2*pi`` turns cycles into radians): its unit must not measure an angle
    per time, since pint reads ``15.9 rev/s`` as 100 per second, and ``2*pi*f`` would then turn 2 pi
    times too fast. ``Hz``, ``1/s`` and ``Hz/s`` pass.

    Examples
    --------
    >>> check_cycle_unit(Q_(2, "Hz"), "2 Hz", "--set f", "f")
    >>> check_cycle_unit(Q_(120, "rpm"), "120 rpm", "--set f", "f")
    Traceback (most recent call last):
    ...
    solver.errors.InputError: --set f: '120 rpm' is an angular velocity, but f counts cycles per second (a frequency): give "2 Hz" for 2 turns per second
    """
    kinds = {_TIME_INVERSE: ("an angular velocity", "second", "Hz", "s"),
             _TIME_INVERSE ** 2: ("an angular acceleration", "second squared", "Hz/s", "s^2")}
    if quantity.dimensionality not in kinds or angle_power(quantity.units) != 1:
        return
    kind, words, unit, per = kinds[quantity.dimensionality]
    number = float(quantity.to(f"rev/{per}").magnitude)
    raise InputError(f"{where}: {str(text)!r} is {kind}, but {name} counts cycles per {words} (a frequency): "
                     f"give \"{number:g} {unit}\" for {number:g} turns per {words}")


def check_magnitude(number: float, where: str, text: Any = None) -> float:
    """``number`` if it is finite and 0 or between 1/:data:`MAX_MAGNITUDE` and
    :data:`MAX_MAGNITUDE` in size; otherwise an :class:`InputError` naming ``where``.

    (A written ``1e-400`` would otherwise become 0 without a word.)
    """
    shown = text if text is not None else number
    if not math.isfinite(number):
        raise InputError(f"{where}: the number in {shown!r} is not finite")
    if number != 0 and not (1 / MAX_MAGNITUDE <= abs(number) <= MAX_MAGNITUDE):
        raise InputError(
            f"{where}: the number in {shown!r} is out of range (0, or 1e-300 to 1e300 in size)"
        )
    match = _QUANTITY.match(text) if isinstance(text, str) else None
    if number == 0 and match is not None and re.search(r"[1-9]", match.group(1)):
        raise InputError(f"{where}: the number in {shown!r} is too small (it rounds to 0)")
    return number


MAX_SI_MAGNITUDE = 1e100
"""A scene's parameters and state, in SI units, must be 0 or between 1/MAX_SI_MAGNITUDE and
MAX_SI_MAGNITUDE in size: products of a few of them then stay within float64's normal range.
A 1e200 ft bar would overflow its own moment of inertia; a 1e-150 kg, 1e-150 m bar has
m l**2 = 1e-450, which underflows to 0 (its answers came out 0.5 % off, then "singular")."""


def unit_text(unit) -> str:
    """A unit in short ASCII, its factors in the order the scene wrote them (``N*m``, ``m/s**2``,
    ``ft*lbf/rad``): pint's own formats sort them by name (``m * N``).

    >>> unit_text(parse_quantity("10 N*m", "x").units), unit_text(parse_quantity("9.81 m/s^2", "x").units)
    ('N*m', 'm/s**2')
    """
    return ureg.formatter.format_unit(unit, "~C", sort_func=lambda factors, registry: factors)


def si_magnitude(quantity: pint.Quantity) -> float:
    """``float(quantity.to_base_units().magnitude)``, the value in SI base units, without building
    the converted quantity: for a unit without an offset, the magnitude times the unit's factor
    to the base units (:meth:`pint.UnitRegistry.get_base_units`, which pint keeps), the product
    pint's own conversion forms (so the same float to the last bit); a unit with an offset (degC)
    takes pint's conversion. A scene is read with a dozen of these, about 12 us each by pint."""
    if not quantity._ok_for_muldiv():  # noqa: SLF001 - pint's own test for an offset unit
        return float(quantity.to_base_units().magnitude)
    factor, _ = ureg.get_base_units(quantity.units)
    return float(quantity.magnitude * factor)


def check_si_magnitude(quantity: pint.Quantity, where: str) -> pint.Quantity:
    """``quantity`` if its SI magnitude is 0 or between 1/:data:`MAX_SI_MAGNITUDE` and
    :data:`MAX_SI_MAGNITUDE` in size; else an :class:`InputError` naming ``where`` and the limit.

    Examples
    --------
    >>> check_si_magnitude(Q_(1e200, "ft"), "parameters.l_b")
    Traceback (most recent call last):
    ...
    solver.errors.InputError: parameters.l_b: 1e+200 ft is 3.048e+199 in SI units; the limit is 1e+100 in size
    >>> check_si_magnitude(Q_(1e-150, "lbm"), "parameters.m_b")
    Traceback (most recent call last):
    ...
    solver.errors.InputError: parameters.m_b: 1e-150 lbm is 4.536e-151 in SI units; a value that is not 0 must be at least 1e-100 in size (smaller ones underflow in products such as m*l**2)
    """
    value = si_magnitude(quantity)
    if not abs(value) <= MAX_SI_MAGNITUDE:
        raise InputError(
            f"{where}: {quantity.magnitude:g} {quantity.units:~} is {value:.4g} in SI units; the limit is "
            f"{MAX_SI_MAGNITUDE:g} in size"
        )
    if value != 0 and abs(value) < 1 / MAX_SI_MAGNITUDE:
        raise InputError(
            f"{where}: {quantity.magnitude:g} {quantity.units:~} is {value:.4g} in SI units; a value that is not 0 "
            f"must be at least {1 / MAX_SI_MAGNITUDE:g} in size (smaller ones underflow in products such as m*l**2)"
        )
    return quantity


def check_angle(value_rad: float, where: str, text: Any = None) -> float:
    """``value_rad`` if its size is at most :data:`MAX_ANGLE_TURNS` turns; else an
    :class:`InputError` naming ``where`` and the limit.

    Examples
    --------
    >>> check_angle(0.5, "demo")
    0.5
    >>> check_angle(1e300, "coordinate.value", "1e300 deg")
    Traceback (most recent call last):
    ...
    solver.errors.InputError: coordinate.value: the angle '1e300 deg' is too large (at most 1000 turns, 360000 deg, in size)
    """
    if not (math.isfinite(value_rad) and abs(value_rad) <= MAX_ANGLE_RAD * (1 + 1e-15)):  # (1000 turns' rounding)
        shown = text if text is not None else f"{value_rad} rad"
        raise InputError(
            f"{where}: the angle {shown!r} is too large (at most {MAX_ANGLE_TURNS} turns, "
            f"{360 * MAX_ANGLE_TURNS} deg, in size)"
        )
    return value_rad


def check_angle_unit(quantity: pint.Quantity, text: Any, where: str, name: str) -> None:
    """The one rule for an angle given as a quantity, in a scene file (a coordinate's value or
    guess) and by ``--set`` (a coordinate, or a parameter the scene gives in an angle unit): it
    needs its unit, since a bare number would be read as radians here while ``--amplitude`` reads
    one as degrees; 0 is 0 in any unit and passes.

    Raises
    ------
    InputError
        ``"<where>: '45' has no unit, but theta is an angle: ..."``.

    Examples
    --------
    >>> check_angle_unit(Q_(0), "0", "--set theta", "theta")
    >>> check_angle_unit(Q_(45), "45", "--set theta", "theta")
    Traceback (most recent call last):
    ...
    solver.errors.InputError: --set theta: '45' has no unit, but theta is an angle: give "45 deg" or "45 rad"
    """
    if not is_angle_unit(quantity) and not quantity.dimensionality and quantity.magnitude != 0:
        number = f"{quantity.magnitude:g}"
        if quantity.units != ureg.dimensionless:  # percent
            raise InputError(f"{where}: {str(text)!r} is {not_angular(quantity.units)}, not an angle; {name} is an "
                             f"angle: give it in deg or rad")
        raise InputError(f"{where}: {str(text)!r} has no unit, but {name} is an angle: give \"{number} deg\" or "
                         f"\"{number} rad\"")


def zero_in(quantity: pint.Quantity, unit) -> pint.Quantity:
    """``--set``'s rule for a bare zero: ``quantity`` written as a number without a unit and
    equal to 0 (``"0"``, ``"0.0"``, ``"-0"``) is 0 in ``unit``, since zero is zero in every unit;
    any other quantity is returned as it is (a nonzero bare number stays a pure number, which
    the caller's dimension check refuses where a dimension is needed).

    Examples
    --------
    >>> zero_in(Q_(0), "rad/s"), zero_in(Q_(2), "rad/s")
    (<Quantity(0.0, 'radian / second')>, <Quantity(2, 'dimensionless')>)
    """
    if is_bare_zero(quantity):
        return Q_(0.0, unit)
    return quantity


def is_bare_zero(quantity: pint.Quantity) -> bool:
    """A zero written without a unit (``"0"``, ``"-0"``, ``0.0``): it says nothing of its kind.

    Examples
    --------
    >>> is_bare_zero(Q_(0)), is_bare_zero(Q_(0, "m")), is_bare_zero(Q_(1))
    (True, False, False)
    """
    return quantity.units == ureg.dimensionless and quantity.magnitude == 0


def is_angle_unit(quantity: pint.Quantity) -> bool:
    """True for a dimensionless quantity with an angle unit (``deg``, ``rad``, ``turn``; not
    ``percent``, :func:`not_angular`): an angle."""
    # not quantity.dimensionality: pint's .dimensionless, without converting to the root units first
    return (not quantity.dimensionality and quantity.units != ureg.dimensionless  # (its text is not "dimensionless")
            and not_angular(quantity.units) is None)


def parse_angle(text: Any, where: str, bare_unit: str = "deg") -> float:
    """An angle in rad from ``"30 deg"``, ``"0.5 rad"`` or a bare number in ``bare_unit``.

    Raises
    ------
    InputError
        Not an angle, or larger than :data:`MAX_ANGLE_TURNS` turns.

    Examples
    --------
    >>> round(parse_angle("180 deg", "--amplitude"), 12)
    3.14159265359
    """
    q = parse_quantity(text, where)
    if not q.dimensionless or (q.units != ureg.dimensionless and not is_angle_unit(q)):  # not percent
        raise InputError(f"{where}: expected an angle such as \"30 deg\", got {text!r}")
    value = float(Q_(float(q.magnitude), bare_unit).to("rad").magnitude) if not is_angle_unit(q) \
        else float(q.to("rad").magnitude)
    return check_angle(value, where, text)


def parse_time(text: Any, where: str) -> float:
    """A time in s from ``"10 s"``, ``"2 min"`` or a bare number (seconds).

    Raises
    ------
    InputError
        Not a time.
    """
    q = parse_quantity(text, where)
    if q.units == ureg.dimensionless:
        return float(q.magnitude)
    if q.dimensionality != ureg.get_dimensionality("s"):
        raise InputError(f"{where}: expected a time such as \"10 s\", got {text!r}")
    return float(q.to("s").magnitude)


def _short(err: Exception, limit: int = 120) -> str:
    text = " ".join(str(err).split())
    return text if len(text) <= limit else text[:limit] + "..."


__all__ = [
    "ureg", "Q_", "check_unit_text", "parse_unit", "parse_quantity", "parse_angle", "parse_time", "si_magnitude",
    "check_magnitude", "check_angle", "check_angle_unit", "check_rate_unit", "check_cycle_unit", "not_angular", "angle_power", "zero_in", "unit_text", "check_si_magnitude", "MAX_SI_MAGNITUDE", "is_angle_unit", "DIMENSIONLESS_UNITS",
    "ANGLE_UNITS", "PURE_NUMBER_UNITS",
    "MAX_QUANTITY_LENGTH", "MAX_UNIT_LENGTH", "MAX_UNIT_EXPONENT", "MAX_UNIT_NESTING",
    "MAX_MAGNITUDE", "MAX_ANGLE_TURNS", "MAX_ANGLE_RAD",
]
