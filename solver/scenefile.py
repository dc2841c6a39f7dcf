"""Read a scene file (TOML) into a validated :class:`solver.scene.Scene`.

The format is documented, with both of the paper's examples walked through,
in ``data/scenes/README.md``. This module is the one place where a scene is
checked: every problem a user can make in a scene file (a misspelt key, a
parameter used but never defined, a mass given in feet, a negative length,
two parallel rails, a body whose placement is not fixed, ...) is reported
here as a :class:`~solver.errors.SceneError` with one line of the form
``"<file>: <key path>: <what is wrong>"``, before anything is derived.

Expressions in the file go through the whitelist parser
:func:`solver.expressions.parse_expression`; quantities (``"50 lbm"``) are
split into a number and a unit, and only the unit is handed to pint.
"""
from __future__ import annotations

import keyword
import math
import re
import unicodedata
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pint
import sympy as sp
from pint.util import UnitsContainer

from solver import files, units
from solver.errors import ExpressionError, InputError, SceneError
from solver.expressions import RESERVED_NAMES, SOLVER_NAMES, parse_expression
from solver.scene import (
    CONSTRAINT_KINDS,
    ELEMENT_KINDS,
    LOAD_KINDS,
    Constraint,
    Element,
    Load,
    Point,
    Scene,
)
from solver.tree_value import NotEvaluable, tree_value
from solver.units import ureg

# -- the format's keys ---------------------------------------------------------------

TOP_KEYS = (
    "name", "description", "parameters", "coordinate", "body", "points",
    "elements", "constraints", "loads", "output_units",
)
COORDINATE_KEYS = ("name", "value", "rate")
BODY_KEYS = ("orientation", "reference_point", "position")
ANGLE_KEYS = frozenset({"orientation", "angle", "relative_angle", "position_angle", "free_angle"})
"""The keys whose expression is an angle, in both scene formats (``[body] orientation``, a rail's
``angle``, a slider's ``relative_angle``, a rolling contact's ``position_angle``, a torsional
spring's ``free_angle``); a prescribed coordinate's ``motion`` is one when its dimension says so,
and gets the same checks (:meth:`_SceneLoader._check_angle_arguments`)."""
POSITION_KEYS = ("point", "at")
POINT_KEYS = ("at", "relative_to", "offset")

ELEMENT_COMMON = ("name", "kind", "mass")
ELEMENT_KEYS: dict[str, tuple[str, ...]] = {
    "slender_bar": ("from", "to", "center", "length", "angle"),
    "uniform_disk": ("center", "radius"),
    "thin_ring": ("center", "radius"),
    "rectangular_plate": ("center", "width", "height", "angle"),
    "point_mass": ("at",),
    "semicircular_disk": ("center", "radius", "angle"),
}
ROUND_KINDS = ("uniform_disk", "thin_ring", "semicircular_disk")
"""Element kinds with a round rim that can roll."""

CONSTRAINT_COMMON = ("kind", "name", "one_sided")
CONSTRAINT_KEYS: dict[str, tuple[str, ...]] = {
    "rail": ("point", "through", "angle", "reaction", "friction", "friction_coefficient"),
    "rolling": (
        "element", "through", "angle", "contact_at_zero", "friction", "normal",
        "friction_coefficient",
    ),
    "pivot": ("point", "at", "reaction_x", "reaction_y"),
}
FREEDOMS_REMOVED = {"rail": 1, "rolling": 2, "pivot": 2}
"""How many of the body's two translational freedoms each constraint fixes."""

LOAD_COMMON = ("kind", "name")
LOAD_KEYS: dict[str, tuple[str, ...]] = {
    "gravity": ("g", "direction"),
    "force": ("point", "components"),
    "couple": ("moment",),
}

# -- dimensions -------------------------------------------------------------------------

DIMENSIONLESS = UnitsContainer()
MASS = ureg.get_dimensionality("kg")
LENGTH = ureg.get_dimensionality("m")
TIME = ureg.get_dimensionality("s")
RATE = ureg.get_dimensionality("1/s")
ACCELERATION = ureg.get_dimensionality("m/s^2")
FORCE = ureg.get_dimensionality("N")
MOMENT = ureg.get_dimensionality("N*m")

OUTPUT_UNIT_DIMENSIONS: dict[str, UnitsContainer] = {
    "force": FORCE,
    "moment": MOMENT,
    "length": LENGTH,
    "mass": MASS,
    "angle": DIMENSIONLESS,
    "angular_velocity": RATE,
    "angular_acceleration": ureg.get_dimensionality("1/s^2"),
    "acceleration": ACCELERATION,
    "velocity": ureg.get_dimensionality("m/s"),
    "time": TIME,
}

_DIMENSION_WORDS = {
    DIMENSIONLESS: "an angle or pure number",
    MASS: "a mass",
    LENGTH: "a length",
    TIME: "a time",
    RATE: "an angular velocity (1/time)",
    ACCELERATION: "an acceleration",
    FORCE: "a force",
    MOMENT: "a moment (force x length)",
    FORCE / LENGTH: "a stiffness (force per length, e.g. N/m)",
    FORCE * TIME / LENGTH: "a damping coefficient (force per speed, e.g. N*s/m)",
    MOMENT * TIME: "a torsional damping coefficient (moment per angular velocity, e.g. N*m*s/rad)",
}

_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
_QUANTITY = re.compile(r"^\s*([+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?)\s*(.*?)\s*$")
MAX_NAME_LENGTH = 100
"""Longest scene ``name`` [characters]."""
MAX_DESCRIPTION_LENGTH = 1000
"""Longest scene ``description`` [characters]."""
_GEOMETRY_TOL = 1e-9  # relative tolerance for "parallel" and "consistent" checks


def describe_dimension(dim: UnitsContainer) -> str:
    """Words for a dimension, e.g. ``"a length"`` or ``"[mass] / [time]"``."""
    if dim in _DIMENSION_WORDS:
        return _DIMENSION_WORDS[dim]
    return str(dim)


def parse_quantity(text: Any, where: str) -> pint.Quantity:
    """Parse ``"<number> <unit>"`` (``"50 lbm"``, ``"32.174 ft/s^2"``, ``"0.3"``).

    :func:`solver.units.parse_quantity` (the guarded reader: only the unit
    reaches pint, after its length, exponents and nesting are checked), with
    its error as a :class:`~solver.errors.SceneError`.

    Raises
    ------
    SceneError
        ``"<where>: ..."`` when the text is not a finite number followed by a
        known unit, or is refused by the guards.
    """
    try:
        return units.parse_quantity(text, where)
    except InputError as err:
        raise SceneError(str(err)) from None


def load_scene(path: str | Path, overrides: Mapping[str, str] | None = None) -> Scene:
    """Read, check and build a scene from a TOML scene file.

    Parameters
    ----------
    path : str or Path
        The scene file (format: ``data/scenes/README.md``).
    overrides : Mapping[str, str], optional
        ``--set`` values: a parameter name or the state (``theta``,
        ``theta_dot``) mapped to a quantity string such as ``"90 deg"``. The
        dimension must match the value in the file.

    Returns
    -------
    Scene
        The validated scene; parameters and state as pint quantities,
        geometry as sympy expressions in the parameter symbols.

    Raises
    ------
    SceneError
        ``"<file>: <key path>: <what is wrong>"`` for any problem: unreadable
        file, TOML syntax (with line and column), unknown keys or kinds (the
        valid ones listed), missing keys, names used but not defined, wrong
        dimensions, non-positive masses or lengths, duplicate names, unknown
        points or elements, rolling on a non-round element, parallel rails,
        a body whose placement is not fixed or is over-constrained, bad
        output units, and bad overrides.

    Examples
    --------
    >>> scene = load_scene("data/scenes/sliding_bar.toml", {"beta": "60 deg"})
    >>> scene.default_point, scene.reaction_names()
    ('A', ('R_A', 'R_B'))
    """
    _validate_load_scene(path, overrides)
    return _SceneLoader(Path(path)).load(dict(overrides or {}))


def _validate_load_scene(path: Any, overrides: Any) -> None:
    if not isinstance(path, (str, Path)):
        raise TypeError(f"`path` must be a str or Path, got {type(path).__name__}")
    if overrides is not None:
        if not isinstance(overrides, Mapping):
            raise TypeError(f"`overrides` must be a mapping, got {type(overrides).__name__}")
        for key, value in overrides.items():
            if not isinstance(key, str) or not isinstance(value, str):
                raise TypeError(f"`overrides` must map str to str, got {key!r}: {value!r}")


# -- dimension analysis of sympy expressions ---------------------------------------------


class _DimensionError(Exception):
    pass


def _dimension(expr: sp.Expr, dims: Mapping[sp.Symbol, UnitsContainer]) -> UnitsContainer:
    """The physical dimension of ``expr`` given each symbol's dimension.

    Sums must add like to like, function arguments (sin, exp, ...) must be
    dimensionless, and powers of dimensional bases need a numeric exponent.
    """
    if expr.is_Symbol:
        return dims[expr]
    if expr.is_number:
        return DIMENSIONLESS
    if expr.is_Add:
        found: UnitsContainer | None = None
        for term in expr.args:
            d = _dimension(term, dims)
            if found is None:
                found = d
            elif d != found:
                raise _DimensionError(
                    f"adds {describe_dimension(found)} to {describe_dimension(d)} "
                    f"({sp.sstr(term)})"
                )
        return found if found is not None else DIMENSIONLESS
    if expr.is_Mul:
        out = DIMENSIONLESS
        for factor in expr.args:
            out = out * _dimension(factor, dims)
        return out
    if expr.is_Pow:
        base, exponent = expr.args
        d_base = _dimension(base, dims)
        d_exp = _dimension(exponent, dims)
        if d_exp != DIMENSIONLESS:
            raise _DimensionError(f"the exponent {sp.sstr(exponent)} has a unit")
        if d_base == DIMENSIONLESS:
            return DIMENSIONLESS
        if not exponent.is_number:
            raise _DimensionError(
                f"{sp.sstr(base)} has a unit and is raised to a non-numeric power"
            )
        return d_base ** float(exponent)
    if isinstance(expr, (sp.Abs, sp.Min, sp.Max)):
        arg_dims = {_dimension(a, dims) for a in expr.args}
        if len(arg_dims) > 1:
            raise _DimensionError(f"{sp.sstr(expr)} mixes different dimensions")
        return arg_dims.pop()
    if isinstance(expr, sp.atan2):
        if _dimension(expr.args[0], dims) != _dimension(expr.args[1], dims):
            raise _DimensionError(f"atan2 arguments differ in dimension in {sp.sstr(expr)}")
        return DIMENSIONLESS
    if isinstance(expr, sp.sign):
        _dimension(expr.args[0], dims)
        return DIMENSIONLESS
    if isinstance(expr, sp.Function):
        for arg in expr.args:
            if _dimension(arg, dims) != DIMENSIONLESS:
                raise _DimensionError(
                    f"the argument of {type(expr).__name__} must be an angle or pure "
                    f"number, but {sp.sstr(arg)} is {describe_dimension(_dimension(arg, dims))}"
                )
        return DIMENSIONLESS
    raise _DimensionError(f"cannot determine the dimension of {sp.sstr(expr)}")


# -- the loader ---------------------------------------------------------------------------


@dataclass
class _Names:
    """Symbols available in the different kinds of expression."""

    params: dict[str, sp.Symbol]
    with_q: dict[str, sp.Symbol]
    with_state_t: dict[str, sp.Symbol]


class _SceneLoader:
    """Reads one file; every check lives in one of its ``_read_*`` methods."""

    def __init__(self, path: Path):
        self.path = path
        self.label = str(path)
        self.overrides: Mapping[str, str] = {}  # the --set values (the key an error names)

    # -- messages ----------------------------------------------------------------
    def fail(self, key: str, what: str) -> SceneError:
        return SceneError(f"{self.label}: {key}: {what}" if key else f"{self.label}: {what}")

    def check_keys(self, table: Mapping[str, Any], valid: tuple[str, ...], key: str, what: str) -> None:
        for name in table:
            if name not in valid:
                raise self.fail(
                    f"{key}.{name}" if key else name,
                    f"unknown key {name!r} (valid keys for {what}: {', '.join(sorted(valid))})",
                )

    def kind_of(self, spec: Mapping[str, Any], key: str, what: str,
                kinds: tuple[str, ...], common: tuple[str, ...], keys: Mapping[str, tuple[str, ...]]) -> str:
        """Read ``spec.kind`` (one of ``kinds``) and check the table's keys against that kind's."""
        kind = self.text(self.require(spec, "kind", key, f"one of {', '.join(kinds)}"), f"{key}.kind")
        if kind not in keys:
            raise self.fail(f"{key}.kind", f"unknown {what} kind {kind!r} (valid kinds: {', '.join(kinds)})")
        self.check_keys(spec, common + keys[kind], key, f"a {kind} {what}")
        return kind

    def require(self, table: Mapping[str, Any], name: str, key: str, what: str) -> Any:
        if name not in table:
            raise self.fail(key, f"missing key {name!r} ({what})")
        return table[name]

    def table(self, value: Any, key: str) -> dict[str, Any]:
        if not isinstance(value, dict):
            raise self.fail(key, f"expected a table, got {type(value).__name__} {value!r}")
        return value

    def array_of_tables(self, value: Any, key: str) -> list[dict[str, Any]]:
        if not isinstance(value, list) or not all(isinstance(v, dict) for v in value):
            raise self.fail(key, f"expected an array of tables ([[{key}]] sections)")
        return value

    def text(self, value: Any, key: str) -> str:
        if not isinstance(value, str):
            raise self.fail(key, f"expected text in quotes, got {type(value).__name__} {value!r}")
        return value

    def scene_texts(self, data: dict) -> tuple[str, str]:
        """The scene's ``name`` (default: the file's stem) and ``description``, each text of at most
        its length (:data:`MAX_NAME_LENGTH`, :data:`MAX_DESCRIPTION_LENGTH`) on one line with no
        control character: a NUL or an escape would reach the terminal, the HTML, the .tex and the
        SVG (where XML refuses it) as they are. Both formats read them here."""
        out = []
        for key, default, limit in (("name", self.path.stem, MAX_NAME_LENGTH), ("description", "", MAX_DESCRIPTION_LENGTH)):
            text = self.text(data.get(key, default), key)
            if len(text) > limit:
                raise self.fail(key, f"{len(text)} characters long; the limit is {limit}")
            bad = next(((i, ch) for i, ch in enumerate(text) if unicodedata.category(ch) == "Cc"), None)
            if bad is not None:
                raise self.fail(key, f"control character U+{ord(bad[1]):04X} at character {bad[0] + 1}; "
                                     f"a scene's {key} is one line of printable text")
            out.append(text)
        return out[0], out[1]

    def identifier(self, value: Any, key: str, what: str) -> str:
        name = self.text(value, key)
        if not _NAME.match(name) or keyword.iskeyword(name):
            raise self.fail(
                key, f"{what} {name!r} is not a valid name (letters, digits and _, not starting with a digit)"
            )
        if name.startswith("__"):  # the solver's internal symbols (solver.period) start so
            raise self.fail(key, f"{what} {name!r}: names starting with '__' are reserved")
        return name

    def boolean(self, value: Any, key: str) -> bool:
        if not isinstance(value, bool):
            raise self.fail(key, f"expected true or false, got {value!r}")
        return value

    # -- expressions ----------------------------------------------------------------
    def _where_allowed(self, name: str) -> str:
        """Where the state's name ``name`` (a coordinate, a rate or t) may be used, in each format
        (data/scenes/README.md, "Where each name may be used"; the one-body format's "Expressions")."""
        multibody = "t" in self.names.with_q  # (the one-body format's orientation and position take no t)
        loads = "force components and couple moments"
        if name == "t":
            return ("t is allowed only in ground points, orientation, position.at, position_angle, motion, motor "
                    f"angle, actuator position and {loads}" if multibody else f"t is allowed only in {loads}")
        if name not in self.names.with_q:
            return f"a rate is allowed only in {loads}"
        return (f"a coordinate is allowed only in orientation, position.at, position_angle and {loads}" if multibody
                else f"the coordinate is allowed only in body.orientation, body.position and {loads}")

    def expr(self, value: Any, key: str, names: Mapping[str, sp.Symbol], need: UnitsContainer) -> sp.Expr:
        """Parse an expression and check its dimension is ``need``."""
        if isinstance(value, bool):
            raise self.fail(key, f"expected an expression, got {value!r}")
        if isinstance(value, int):
            value = str(value)
        elif isinstance(value, float):
            if not math.isfinite(value):
                raise self.fail(key, f"{value!r} is not a finite number")
            value = repr(value)
        elif not isinstance(value, str):
            raise self.fail(key, f"expected an expression in quotes, got {type(value).__name__} {value!r}")
        try:
            result = parse_expression(value, names, f"{self.label}: {key}")
        except ExpressionError as err:
            message = str(err)
            state_names = set(self.names.with_state_t) - set(names)
            unknown = re.search(r"unknown name '(\w+)'", message)
            if unknown and unknown.group(1) in state_names:
                message += f"; {unknown.group(1)} cannot be used here: {self._where_allowed(unknown.group(1))}"
            elif _QUANTITY.match(value) and _QUANTITY.match(value).group(2):
                message += (
                    "; quantities with units belong in [parameters] (e.g. m_1 = \"2 kg\"), "
                    "expressions then use the parameter's name"
                )
            raise SceneError(message) from None
        if result == 0:
            return result
        try:
            dim = _dimension(result, self.dims)
        except _DimensionError as err:
            raise self.fail(key, f"{err} in {value!r}") from None
        if dim != need:
            if result.is_Symbol and result.name in self.parameters:
                quantity = self.parameters[result.name]
                got = f"parameter {result.name} = {quantity:~P} is {describe_dimension(dim)}"
            elif dim == DIMENSIONLESS and result.is_number:
                got = f"{value!r} is a bare number without a unit (define a parameter with a unit)"
            else:
                got = f"{value!r} is {describe_dimension(dim)}"
            raise self.fail(key, f"{got}, but {describe_dimension(need)} is needed here")
        self._check_angle_arguments(result, key, value)
        return result

    def _check_angle_arguments(self, expr: sp.Expr, key: str, value: str, is_angle: bool | None = None) -> None:
        """The checks of a parameter used as an angle: in ``expr`` when it is one (``is_angle``; by
        default when ``key`` ends in a key of :data:`ANGLE_KEYS`), and in the argument of each of its
        trigonometric functions.

        A bare number of more than a turn is refused (:meth:`_check_bare_turns`), as is a parameter
        whose unit measures no angle (:func:`solver.units.not_angular`): ``100 percent``, which pint
        reads as 1 rad, or a frequency in Hz taken as radians per second (:meth:`_check_cycles`).
        A pure number (``mu = "30 percent"``) or a frequency elsewhere stays one.
        """
        if is_angle is None:
            is_angle = key.rsplit(".", 1)[-1] in ANGLE_KEYS
        if is_angle:
            self._check_bare_turns(expr, key, value)
        calls = sorted(expr.atoms(sp.sin, sp.cos, sp.tan, sp.cot, sp.sec, sp.csc), key=sp.default_sort_key)
        for angle, call in ([(expr, None)] if is_angle else []) + [(c.args[0], c) for c in calls]:
            where = "" if call is None else f" (in {sp.sstr(call)})"
            for symbol in sorted(angle.free_symbols, key=str):
                quantity = self.parameters.get(symbol.name)
                if quantity is None or quantity.units == ureg.dimensionless or quantity.dimensionality:
                    continue
                what = units.not_angular(quantity.units)
                if what is not None:
                    raise self.fail(self._parameter_key(symbol.name),
                                    f"{quantity.magnitude:g} {quantity.units} is {what}, not an angle, but {value!r} at "
                                    f"{key} takes {symbol.name} as one{where}: give it in deg or rad")
            self._check_cycles(angle, key, value, where)

    def _check_cycles(self, angle: sp.Expr, key: str, value: str, where: str) -> None:
        """A parameter in ``Hz`` (``kHz``, ``Hz/s``) counts cycles, 2 pi rad each, where pint would
        read it as radians per second. In an angle, each parameter that is or was (in the file,
        before ``--set``) a rate is checked in the role :meth:`_frequency_roles` finds: read as
        radians per time (``omega*t``), it must not be in Hz
        (:func:`solver.units.check_rate_unit`: ``omega = "15.9 Hz"`` would turn at 15.9 rad/s, not
        100); counting cycles (``2*pi*f*t``), it must not have an angular unit
        (:func:`solver.units.check_cycle_unit`: ``f = "30 rpm"`` in the file or ``--set f="15.9
        rev/s"`` would turn 2 pi times too fast). The refusal names the parameter
        (``--set NAME`` or ``parameters.NAME``) and the key that uses it."""
        for name, counts_cycles in self._frequency_roles(angle).items():
            text = self.overrides.get(name, self.parameter_texts.get(name))
            args = (self.parameters[name], text, f"{self.label}: {self._parameter_key(name)}",
                    f"{name} in {value!r} at {key}{where}")
            try:
                if counts_cycles:
                    units.check_cycle_unit(*args)
                else:
                    units.check_rate_unit(*args, also=f"; or keep the frequency and write 2*pi*{name} (a cycle is "
                                                      "2 pi rad)")
            except InputError as err:
                raise SceneError(str(err)) from None

    def _frequency_roles(self, angle: sp.Expr) -> dict[str, bool]:
        """The role in ``angle`` of each parameter that is a rate (``Hz``, ``rpm``, ``rad/s``, ``Hz/s``,
        in the file or by ``--set``): True where it counts cycles, that is where every term holding it (to a net
        nonzero power: ``f/f0`` is a pure number) also holds ``pi`` or a parameter with an angle unit
        (:func:`solver.units.is_angle_unit`), which turn cycles into an angle (``2*pi*f*t``,
        ``turn*f*t`` with ``turn = "1 rev"`` or ``"360 deg"``); False where a term reads it as radians
        per time (``f*t``)."""
        names = {name for name, q in self.parameters.items() if q.dimensionality in (RATE, RATE ** 2)}
        roles: dict[str, bool] = {}
        for term in sp.Add.make_args(sp.expand(angle)):
            powers = {b.name: e for b, e in term.as_powers_dict().items() if b.is_Symbol and b.name in names}
            if not powers or sum(powers.values()) == 0:
                continue
            cycles = term.has(sp.pi) or any(units.is_angle_unit(self.parameters[s.name]) for s in term.free_symbols
                                            if s.name in self.parameters)
            for name in powers:
                roles[name] = roles.get(name, True) and cycles
        return roles

    def _parameter_key(self, name: str) -> str:
        """Where parameter ``name`` was given: ``--set NAME`` or ``parameters.NAME``."""
        return f"--set {name}" if name in self.overrides else f"parameters.{name}"

    def _check_bare_turns(self, expr: sp.Expr, key: str, value: str) -> None:
        """A constant term of an angle (a key of :data:`ANGLE_KEYS`) written as a bare number, or a
        parameter given as one, is radians: refused beyond a full turn, where degrees were
        surely meant (``theta - 90`` would turn the body by 90 rad, 14 turns). A term with pi
        (``theta - pi/2``) or a parameter with its unit (``q = "90 deg"``) says what it is."""
        bare_terms, turned = [], 0.0
        for term in sp.Add.make_args(sp.expand(expr)):  # (k*(theta - 90) and theta - 5 - q too)
            if term.has(sp.pi):
                continue
            bare = {}
            for symbol in term.free_symbols:
                quantity = self.parameters.get(symbol.name)
                if quantity is None or quantity.units != ureg.dimensionless:
                    break  # a coordinate, t, or a parameter with a unit
                bare[symbol] = float(quantity.magnitude)
            else:
                bare_terms.append(term)
                turned += float(term.xreplace(bare)) if bare else float(term)
        if 2 * math.pi < abs(turned) <= units.MAX_ANGLE_TURNS * 2 * math.pi:  # (beyond: the cap's refusal)
            constant = sp.Add(*bare_terms)
            what = f"{sp.sstr(constant)} = {turned:g}" if constant.free_symbols else f"{turned:g}"
            raise self.fail(key, f"{value!r} adds {what} rad ({turned / (2 * math.pi):.3g} "
                                 "turns): a bare number in an angle is radians; for degrees give the angle as a "
                                 "parameter with its unit (q = \"90 deg\", then theta - q), or use pi (pi/2)")

    def vector(self, value: Any, key: str, names: Mapping[str, sp.Symbol], need: UnitsContainer) -> sp.Matrix:
        if not isinstance(value, list) or len(value) != 2:
            raise self.fail(key, f"expected a pair [x, y] of expressions, got {value!r}")
        from .model.joints import vec

        return vec(*(self.expr(v, f"{key}[{i}]", names, need) for i, v in enumerate(value)))

    def si(self, expr: sp.Expr, key: str, extra: dict | None = None) -> float:
        """Numeric SI value of a parameter expression (for sign and geometry checks; ``extra``:
        values of further symbols, such as the coordinate): in double precision by one tree walk
        (:func:`solver.tree_value.tree_value`), by sympy's evalf where the walk cannot go (an
        unknown function, a missing parameter, a division by zero)."""
        values = {**self.si_values, **extra} if extra else self.si_values
        try:
            value = tree_value(expr, values)
        except (NotEvaluable, KeyError, ZeroDivisionError, OverflowError, TypeError, ValueError):
            try:
                value = complex(expr.evalf(subs=values))
            except (TypeError, ValueError):
                raise self.fail(key, f"cannot evaluate {sp.sstr(expr)} with the given parameters") from None
        if not math.isfinite(value.real) or abs(value.imag) > 1e-12 * max(1.0, abs(value.real)):
            raise self.fail(key, f"{sp.sstr(expr)} is not a finite real number for the given parameters")
        return value.real

    def smooth_in_q(self, expr: sp.Expr, key: str) -> sp.Expr:
        """Refuse abs, sign, min and max of anything holding the coordinate in an expression
        that is differentiated twice (orientation, position): their derivatives are Dirac
        deltas and steps, which no solver route can evaluate."""
        kinks = [f for f in expr.atoms(sp.Abs, sp.sign, sp.Min, sp.Max) if f.has(self.q)]
        if kinks:
            raise self.fail(key, f"{sp.sstr(kinks[0])} is not differentiable in {self.coordinate} "
                                 "(this expression is differentiated twice); write a smooth formula")
        return expr

    def bounded_angle(self, expr: sp.Expr, key: str) -> sp.Expr:
        """An angle expression whose value at the scene's state is within
        :data:`solver.units.MAX_ANGLE_TURNS` turns (``"1e300*theta"`` has no meaningful sine)."""
        value = self.si(expr, key, {self.q: self.state_q}) if expr.free_symbols - {self.q} <= set(self.si_values) \
            else None
        if value is not None:
            try:
                units.check_angle(value, f"{self.label}: {key}", f"{value:.6g} rad")
            except InputError as err:
                raise SceneError(str(err)) from None
        return expr

    def positive(self, expr: sp.Expr, key: str, what: str) -> sp.Expr:
        value = self.si(expr, key)
        if not value > 0:
            raise self.fail(key, f"{what} must be positive, got {sp.sstr(expr)} = {value:.6g} (SI)")
        return expr

    def nonnegative(self, expr: sp.Expr, key: str, what: str) -> sp.Expr:
        """``expr``, refused when its value is negative (a spring's stiffness, a damper's coefficient:
        a negative one would push the ends apart the more they part, or feed energy in)."""
        value = self.si(expr, key)
        if not value >= 0:
            raise self.fail(key, f"{what} must not be negative, got {sp.sstr(expr)} = {value:.6g} (SI)")
        return expr

    # -- the whole file ----------------------------------------------------------------
    def load(self, overrides: dict[str, str], data: dict[str, Any] | None = None) -> Scene:
        """The Scene of the file (``data``: its parsed TOML when the caller has read it already)."""
        data = self._read_toml() if data is None else data
        self.overrides = overrides
        self.check_keys(data, TOP_KEYS, "", "a scene file")
        if "coordinate" not in data and "body" not in data:  # nor [coordinates]/[[bodies]]: not multibody
            raise self.fail("", "not a scene: neither the multibody format ([coordinates] and [[bodies]]) nor "
                                "the one-body format ([coordinate] and [body]) was found (data/scenes/README.md)")
        name, description = self.scene_texts(data)

        self._read_parameters(self.table(self.require(data, "parameters", "parameters", "the table [parameters]"), "parameters"))
        coordinate, state = self._read_coordinate(
            self.table(self.require(data, "coordinate", "coordinate", "the table [coordinate]"), "coordinate")
        )
        self._apply_overrides(overrides, coordinate, state)
        self._check_angles(coordinate, state, overrides)
        self.state_q = float(state[coordinate].to("rad").magnitude)
        self._setup_symbols(coordinate)

        body = self.table(self.require(data, "body", "body", "the table [body] with orientation"), "body")
        self.check_keys(body, BODY_KEYS, "body", "[body]")
        orientation = self.smooth_in_q(self.bounded_angle(self.expr(
            self.require(body, "orientation", "body", "the body frame's angle as a function of the coordinate"),
            "body.orientation", self.names.with_q, DIMENSIONLESS,
        ), "body.orientation"), "body.orientation")
        points = self._read_points(self.table(self.require(data, "points", "points", "the table [points]"), "points"))
        elements = self._read_elements(
            self.array_of_tables(self.require(data, "elements", "elements", "at least one [[elements]] entry"), "elements"),
            points,
        )
        self.check_mass_centre_name(points, elements, "points")
        position = self._read_position(body, points)
        constraints = self._read_constraints(
            self.array_of_tables(self.require(data, "constraints", "constraints", "at least one [[constraints]] entry"), "constraints"),
            points, elements,
        )
        loads = self._read_loads(self.array_of_tables(data.get("loads", []), "loads"), points)
        output_units = self._read_output_units(self.table(data.get("output_units", {}), "output_units"))

        if "reference_point" in body:
            default_point = self.text(body["reference_point"], "body.reference_point")
            if default_point not in points:
                raise self.fail(
                    "body.reference_point",
                    f"{default_point!r} is not a point of the body (points: {', '.join(points)})",
                )
        else:
            default_point = next(iter(points))

        self._check_placement(orientation, position, points, elements, constraints)
        return Scene(
            name=name,
            description=description,
            source=self.path,
            parameters=dict(self.parameters),
            coordinate=coordinate,
            state=state,
            orientation=orientation,
            points=points,
            elements=tuple(elements),
            constraints=tuple(constraints),
            loads=tuple(loads),
            default_point=default_point,
            position=position,
            output_units=output_units,
        )

    def _read_toml(self) -> dict[str, Any]:
        """The parsed file: a regular file of bounded size and nesting (:func:`solver.files.read_toml`)."""
        try:
            return files.read_toml(self.path, self.label)
        except InputError as err:
            raise SceneError(str(err).replace(f"{self.label}: cannot read the file", f"{self.label}: cannot read the scene file", 1)) from None

    # -- parameters and state -----------------------------------------------------------
    def _read_parameters(self, table: dict[str, Any]) -> None:
        self.parameters: dict[str, pint.Quantity] = {}
        self.parameter_texts: dict[str, Any] = {}
        """Each parameter as the file writes it (for messages)."""
        for name, value in table.items():
            key = f"parameters.{name}"
            self.identifier(name, key, "parameter name")
            if name in RESERVED_NAMES or name in SOLVER_NAMES:
                raise self.fail(key, f"{name!r} is reserved (a function, a constant, time t, or the angular "
                                     f"acceleration alpha) and cannot be a parameter name")
            self.parameters[name] = parse_quantity(value, f"{self.label}: {key}")
            self.parameter_texts[name] = value

    def _read_coordinate(self, table: dict[str, Any]) -> tuple[str, dict[str, pint.Quantity]]:
        self.check_keys(table, COORDINATE_KEYS, "coordinate", "[coordinate]")
        coordinate = self.identifier(table.get("name", "theta"), "coordinate.name", "coordinate name")
        reserved = {coordinate, coordinate + "_dot", coordinate + "_ddot"}
        for name in self.parameters:
            if name in reserved:
                raise self.fail(f"parameters.{name}", f"{name!r} is the coordinate or its rate and cannot also be a parameter")
        if coordinate in RESERVED_NAMES or coordinate in SOLVER_NAMES:
            raise self.fail("coordinate.name", f"{coordinate!r} is reserved; use e.g. \"theta\"")
        value_text = self.require(table, "value", "coordinate", "the coordinate's value, e.g. \"30 deg\"")
        value = parse_quantity(value_text, f"{self.label}: coordinate.value")
        rate_text = self.require(table, "rate", "coordinate", "the coordinate's rate, e.g. \"0 rad/s\"")
        rate = units.zero_in(parse_quantity(rate_text, f"{self.label}: coordinate.rate"), "rad/s")  # (as --set)
        self._check_state_dimension(value, DIMENSIONLESS, "coordinate.value", "an angle", value_text)
        self.set_angle(value, value_text, coordinate, "coordinate.value")
        self._check_state_dimension(rate, RATE, "coordinate.rate", "an angular velocity such as \"0 rad/s\"", rate_text)
        self.set_rate(rate, rate_text, coordinate + "_dot", "coordinate.rate")
        return coordinate, {coordinate: value, coordinate + "_dot": rate}

    def _check_state_dimension(self, quantity: pint.Quantity, need: UnitsContainer, key: str, what: str,
                               text: str | None = None) -> None:
        """Refuse ``quantity`` unless it has dimension ``need`` (``what`` in words); the message
        shows ``text``, the value as the user typed it, when given."""
        if quantity.dimensionality != need:
            shown = f"{quantity:~P}" if text is None else repr(text)
            raise self.fail(key, f"{shown} is {describe_dimension(quantity.dimensionality)}, but {what} is needed")

    def _apply_overrides(self, overrides: dict[str, str], coordinate: str, state: dict[str, pint.Quantity]) -> None:
        self.overridden: set[str] = set()
        for name, text in overrides.items():
            key = f"--set {name}"
            quantity = parse_quantity(text, f"{self.label}: {key}")
            if name in self.parameters:
                old = self.parameters[name]
                quantity = units.zero_in(quantity, old.units)
                if quantity.dimensionality != old.dimensionality:
                    raise self.fail(
                        key,
                        f"{text!r} is {describe_dimension(quantity.dimensionality)}, but {name} is "
                        f"{describe_dimension(old.dimensionality)} (in the scene: {old:~P})",
                    )
                self.set_angular(old, quantity, text, name)
                self.parameters[name] = quantity
                self.overridden.add(name)
            elif name in state:
                need = DIMENSIONLESS if name == coordinate else RATE
                quantity = units.zero_in(quantity, "rad" if need == DIMENSIONLESS else "rad/s")
                self._check_state_dimension(quantity, need, key, "an angle" if need == DIMENSIONLESS else "an angular velocity",
                                            text)
                if name == coordinate:
                    self.set_angle(quantity, text, name)
                else:
                    self.set_rate(quantity, text, name)
                state[name] = quantity
            else:
                valid = ", ".join([*self.parameters, *state])
                raise self.fail(key, f"unknown name {name!r} (parameters and state: {valid})")

    def set_angle(self, quantity: pint.Quantity, text: str, name: str, key: str | None = None) -> None:
        """An angle, given by ``--set NAME`` or in the file at ``key`` (``coordinate.value``): refused
        without its unit (:func:`solver.units.check_angle_unit`)."""
        try:
            units.check_angle_unit(quantity, text, f"{self.label}: {key or '--set ' + name}", name)
        except InputError as err:
            raise SceneError(str(err)) from None

    def set_rate(self, quantity: pint.Quantity, text: str, name: str, key: str | None = None) -> None:
        """An angular velocity, given by ``--set NAME`` or in the file at ``key``: refused in a unit
        that measures no angle per time, such as Hz (:func:`solver.units.check_rate_unit`); an
        angular acceleration likewise (Hz/s)."""
        try:
            units.check_rate_unit(quantity, text, f"{self.label}: {key or '--set ' + name}", name)
        except InputError as err:
            raise SceneError(str(err)) from None

    def set_angular(self, old: pint.Quantity, quantity: pint.Quantity, text: str, name: str) -> None:
        """``--set NAME`` of a parameter: an angle, an angular velocity or acceleration when the scene
        gives it in an angle unit (``45 deg``, ``10 rad/s``, ``2 rad/s^2``), checked as such (a parameter the scene gives in Hz or
        1/s is a frequency or a plain rate, and takes Hz)."""
        if units.is_angle_unit(old):
            self.set_angle(quantity, text, name)
        elif old.dimensionality in (RATE, RATE ** 2) and units.angle_power(old.units) == 1:  # rad/s, rpm, rad/s^2
            self.set_rate(quantity, text, name)

    def _check_angles(self, coordinate: str, state: dict[str, pint.Quantity], overrides: Mapping[str, str]) -> None:
        """Every parameter and state value must lie within :data:`solver.units.MAX_SI_MAGNITUDE`
        (SI), and the coordinate's value and every parameter given with an angle unit within
        :data:`solver.units.MAX_ANGLE_TURNS` turns (beyond it float64 sines are meaningless)."""
        self.check_angle_sizes({coordinate: (state[coordinate], "coordinate.value")}, overrides)
        keys = {name: "coordinate.value" if name == coordinate else "coordinate.rate" for name in state}
        self.check_magnitudes({**self.parameters, **state}, overrides, keys)

    def check_angle_sizes(self, angles: Mapping[str, tuple[pint.Quantity, str]], overrides: Mapping[str, str]) -> None:
        """The cap on angles, for both scene formats: each of ``angles`` (name -> (quantity, its key
        in the file)) and every parameter given with an angle unit within
        :data:`solver.units.MAX_ANGLE_TURNS` turns, named ``--set NAME`` when overridden."""
        angles = {**angles, **{n: (q, f"parameters.{n}") for n, q in self.parameters.items()
                               if units.is_angle_unit(q) and n not in angles}}
        for name, (quantity, key) in angles.items():
            key = f"--set {name}" if name in overrides else key
            try:
                units.check_angle(float(quantity.to("rad").magnitude), f"{self.label}: {key}", f"{quantity.magnitude:g} {quantity.units:~}")
            except InputError as err:
                raise SceneError(str(err)) from None

    def check_magnitudes(self, quantities: Mapping[str, pint.Quantity], overrides: Mapping[str, str],
                         keys: Mapping[str, str] | None = None) -> None:
        """Every parameter (and given state value) within :func:`solver.units.check_si_magnitude`'s
        range, for both scene formats; the key named is ``--set NAME`` when the value came from the
        command line, else ``keys[name]`` or ``parameters.NAME``."""
        for name, quantity in quantities.items():
            key = f"--set {name}" if name in overrides else (keys or {}).get(name, f"parameters.{name}")
            try:
                units.check_si_magnitude(quantity, f"{self.label}: {key}")
            except InputError as err:
                raise SceneError(str(err)) from None

    def _setup_symbols(self, coordinate: str) -> None:
        params = {n: sp.Symbol(n, real=True) for n in self.parameters}
        q = sp.Symbol(coordinate, real=True)
        qd = sp.Symbol(coordinate + "_dot", real=True)
        t = sp.Symbol("t", real=True)
        self.names = _Names(
            params=params,
            with_q={**params, coordinate: q},
            with_state_t={**params, coordinate: q, coordinate + "_dot": qd, "t": t},
        )
        self.dims = {params[n]: quantity.dimensionality for n, quantity in self.parameters.items()}
        self.dims.update({q: DIMENSIONLESS, qd: RATE, t: TIME})
        self.si_values = {
            params[n]: units.si_magnitude(quantity) for n, quantity in self.parameters.items()
        }
        self.coordinate = coordinate
        self.q = q
        # Lengths are sizes: positive (a negative offset is written "-d"). A mass may be zero (a
        # massless element is a legitimate limit, e.g. Example 2 without its bar) but not negative;
        # the body as a whole must have mass (checked with the elements).
        for name, quantity in self.parameters.items():
            dim = quantity.dimensionality
            if (dim == LENGTH and not quantity.magnitude > 0) or (dim == MASS and not quantity.magnitude >= 0):
                key = f"--set {name}" if name in self.overridden else f"parameters.{name}"
                what = "must be positive" if dim == LENGTH else "must not be negative"
                raise self.fail(
                    key,
                    f"{describe_dimension(dim)[2:]} {what}, got {quantity:~P} "
                    "(masses and lengths are sizes; write a negative offset as \"-d\" in the expression)",
                )

    # -- points and elements --------------------------------------------------------------
    def _read_points(self, table: dict[str, Any], where: str = "points") -> dict[str, Point]:
        """The named points of a body; ``where``: the place of the table in the file (``points``,
        ``bodies[0].points``), named in every message."""
        if not table:
            raise self.fail(where, "no points defined; name at least the reference point, e.g. A = [\"0\", \"0\"]")
        points: dict[str, Point] = {}
        instants: list[tuple[str, dict[str, Any]]] = []
        for name, value in table.items():
            key = f"{where}.{name}"
            self.identifier(name, key, "point name")
            if isinstance(value, list):
                points[name] = Point(name, self.vector(value, key, self.names.params, LENGTH))
                continue
            spec = self.table(value, key)
            self.check_keys(spec, POINT_KEYS, key, "a point (use at = [x, y], or relative_to + offset)")
            if "at" in spec:
                if "offset" in spec or "relative_to" in spec:
                    raise self.fail(key, "give either at (body frame) or relative_to + offset (fixed-frame offset), not both")
                points[name] = Point(name, self.vector(spec["at"], f"{key}.at", self.names.params, LENGTH))
            else:
                instants.append((name, spec))
        for name, spec in instants:
            key = f"{where}.{name}"
            base = self.text(self.require(spec, "relative_to", key, "the body point this point is measured from"), f"{key}.relative_to")
            if base not in points:
                raise self.fail(
                    f"{key}.relative_to",
                    f"{base!r} is not a body-frame point (body-frame points: {', '.join(points)})",
                )
            offset = self.vector(self.require(spec, "offset", key, "its fixed-frame offset [dx, dy]"), f"{key}.offset", self.names.params, LENGTH)
            points[name] = Point(name, offset, frame="instant", relative_to=base)
        return {name: points[name] for name in table}  # file order

    def check_mass_centre_name(self, points: Mapping[str, Point], elements, key: str) -> None:
        """Refuse a point named ``G`` that is not the body's mass centre (sum m_k c_k / sum m_k of
        its ``elements``): ``G`` names the mass centre everywhere (Eqs. 1-2, 10, the inertial term
        -r_G/P x m a_P), so a G elsewhere would put that name on two places. ``key``: the place of the
        points table in the file (``points``, ``bodies[0].points``)."""
        if "G" not in points:
            return
        where = f"{key}.G"
        if points["G"].frame != "body":
            raise self.fail(where, "G is reserved for the mass centre; an instant point cannot be named G")
        total = sp.Add(*[e.mass for e in elements])
        if not self.si(total, where) > 0:
            return  # no mass centre to compare with (a massless body is refused where its elements are read)
        centres = [_mass_centre(e) for e in elements]  # component by component: 2-vector Matrix arithmetic is slow
        centre = [sp.Add(*[e.mass * c[i] for e, c in zip(elements, centres)]) / total for i in range(2)]
        given = points["G"].coords
        values = [(self.si(centre[i], where), self.si(sp.sympify(given[i]), where)) for i in range(2)]
        size = max([1e-300] + [abs(x) for pair in values for x in pair]
                   + [abs(self.si(sp.sympify(p.coords[i]), where)) for p in points.values() if p.frame == "body"
                      for i in range(2)])
        # the same place to round-off of the parameter arithmetic (~1e-16 relative to the body's size)
        if all(abs(c - g) <= 1e-9 * size for c, g in values):
            return
        shown = ", ".join(f"{c:.6g}" for c, _ in values)
        raise self.fail(where, f"G is reserved for the mass centre, which is at ({shown}) m in the body frame, "
                               f"not at [{', '.join(sp.sstr(x) for x in given)}]; give this point another name")

    def _place(self, value: Any, key: str, points: Mapping[str, Point]) -> sp.Matrix:
        """A body-frame position: a point name or a pair of expressions."""
        if isinstance(value, str):
            if value not in points:
                raise self.fail(key, f"unknown point {value!r} (points: {', '.join(points)})")
            if points[value].frame != "body":
                raise self.fail(key, f"point {value!r} is an instant point; elements need body-frame points")
            return points[value].coords
        return self.vector(value, key, self.names.params, LENGTH)

    def _read_elements(self, entries: list[dict[str, Any]], points: Mapping[str, Point]) -> list[Element]:
        if not entries:
            raise self.fail("elements", "the body has no elements")
        elements: list[Element] = []
        seen: set[str] = set()
        for i, spec in enumerate(entries):
            key = f"elements[{i}]"
            kind = self.kind_of(spec, key, "element", ELEMENT_KINDS, ELEMENT_COMMON, ELEMENT_KEYS)
            name = self.identifier(spec.get("name", f"{kind}_{i + 1}"), f"{key}.name", "element name")
            if name in seen:
                raise self.fail(f"{key}.name", f"duplicate element name {name!r}")
            seen.add(name)
            mass = self.expr(self.require(spec, "mass", key, "the element's mass, e.g. mass = \"m_b\""), f"{key}.mass", self.names.params, MASS)
            value = self.si(mass, f"{key}.mass")
            if not value >= 0:
                raise self.fail(f"{key}.mass", f"the mass must not be negative, got {sp.sstr(mass)} = {value:.6g} (SI)")
            elements.append(self._element_geometry(spec, key, kind, name, mass, points))
        total = sum(self.si(e.mass, "elements") for e in elements)
        if not total > 0:
            raise self.fail("elements", "the body has no mass: every element's mass is zero (a massless element is allowed, a massless body is not)")
        return elements

    def _length(self, spec: dict[str, Any], dim: str, key: str) -> sp.Expr:
        expr = self.expr(self.require(spec, dim, key, f"the {dim}"), f"{key}.{dim}", self.names.params, LENGTH)
        return self.positive(expr, f"{key}.{dim}", f"the {dim}")

    def _angle(self, spec: dict[str, Any], key: str) -> sp.Expr:
        return self.bounded_angle(self.expr(spec.get("angle", 0), f"{key}.angle", self.names.params, DIMENSIONLESS),
                                  f"{key}.angle")

    def _element_geometry(self, spec, key, kind, name, mass, points) -> Element:
        if kind == "slender_bar":
            if "from" in spec or "to" in spec:
                clash = [k for k in ("center", "length", "angle") if k in spec]
                if clash:
                    raise self.fail(key, f"give a bar either from/to or center/length/angle, not both (also has {', '.join(clash)})")
                start = self._place(self.require(spec, "from", key, "the bar's first end"), f"{key}.from", points)
                end = self._place(self.require(spec, "to", key, "the bar's second end"), f"{key}.to", points)
                length, angle = self._segment(start, end, key)
                center = (start + end) / 2
            else:
                center = self._place(self.require(spec, "center", key, "the bar's midpoint (or give from/to)"), f"{key}.center", points)
                length = self._length(spec, "length", key)
                angle = self._angle(spec, key)
            return Element(name, kind, mass, center, angle, {"length": length})
        if kind == "point_mass":
            at = self._place(self.require(spec, "at", key, "where the mass sits"), f"{key}.at", points)
            return Element(name, kind, mass, at, sp.Integer(0), {})
        center = self._place(self.require(spec, "center", key, "the element's centre"), f"{key}.center", points)
        if kind == "rectangular_plate":
            dims = {"width": self._length(spec, "width", key), "height": self._length(spec, "height", key)}
            return Element(name, kind, mass, center, self._angle(spec, key), dims)
        dims = {"radius": self._length(spec, "radius", key)}
        angle = self._angle(spec, key) if kind == "semicircular_disk" else sp.Integer(0)
        return Element(name, kind, mass, center, angle, dims)

    def _segment(self, start: sp.Matrix, end: sp.Matrix, key: str) -> tuple[sp.Expr, sp.Expr]:
        """Length and direction angle of a bar from its two ends, kept simple
        for the common axis-aligned case (no sqrt(l**2) = Abs(l))."""
        dx, dy = sp.expand(end[0] - start[0]), sp.expand(end[1] - start[1])
        if self.si(dx, f"{key}.to") == 0 and self.si(dy, f"{key}.to") == 0:
            raise self.fail(f"{key}.to", "the bar's two ends coincide (its length would be 0)")
        if dy == 0 and dx != 0:
            sign = 1 if self.si(dx, f"{key}.to") > 0 else -1
            length, angle = sign * dx, (sp.Integer(0) if sign > 0 else sp.pi)
        elif dx == 0 and dy != 0:
            sign = 1 if self.si(dy, f"{key}.to") > 0 else -1
            length, angle = sign * dy, sign * sp.pi / 2
        else:
            length, angle = sp.sqrt(dx**2 + dy**2), sp.atan2(dy, dx)
        self.positive(length, f"{key}.to", "the bar's length (distance from `from` to `to`)")
        return length, angle

    def _read_position(self, body: dict[str, Any], points: Mapping[str, Point]) -> tuple[str, sp.Matrix] | None:
        if "position" not in body:
            return None
        spec = self.table(body["position"], "body.position")
        self.check_keys(spec, POSITION_KEYS, "body.position", "body.position")
        point = self.text(self.require(spec, "point", "body.position", "the body point whose path is given"), "body.position.point")
        if point not in points or points[point].frame != "body":
            raise self.fail("body.position.point", f"{point!r} is not a body-frame point (points: {', '.join(points)})")
        at = self.vector(self.require(spec, "at", "body.position", "its fixed-frame position [x(theta), y(theta)]"), "body.position.at", self.names.with_q, LENGTH)
        for i, component in enumerate(at):
            self.smooth_in_q(component, f"body.position.at[{i}]")
        return point, at

    # -- constraints ---------------------------------------------------------------------------
    def _read_constraints(self, entries, points, elements) -> list[Constraint]:
        if not entries:
            raise self.fail("constraints", "no constraints: the body's placement is not determined")
        by_name = {e.name: e for e in elements}
        constraints: list[Constraint] = []
        names: set[str] = set()
        reactions: dict[str, str] = {}
        for i, spec in enumerate(entries):
            key = f"constraints[{i}]"
            kind = self.kind_of(spec, key, "constraint", CONSTRAINT_KINDS, CONSTRAINT_COMMON, CONSTRAINT_KEYS)
            one_sided = self.boolean(spec.get("one_sided", False), f"{key}.one_sided")
            if kind in ("rail", "pivot"):
                point = self.text(self.require(spec, "point", key, "the body point it holds"), f"{key}.point")
                if point not in points:
                    raise self.fail(f"{key}.point", f"unknown point {point!r} (points: {', '.join(points)})")
                if points[point].frame != "body":
                    raise self.fail(f"{key}.point", f"{point!r} is an instant point; a {kind} needs a body-frame point")
                origin_key = "through" if kind == "rail" else "at"
                origin = self.vector(spec.get(origin_key, [0, 0]), f"{key}.{origin_key}", self.names.params, LENGTH)
                if kind == "rail":
                    angle = self.bounded_angle(
                        self.expr(spec.get("angle", 0), f"{key}.angle", self.names.params, DIMENSIONLESS), f"{key}.angle")
                    reaction_names = [(f"{key}.reaction", spec.get("reaction", f"R_{point}"))]
                else:
                    angle = sp.Integer(0)
                    reaction_names = [
                        (f"{key}.reaction_x", spec.get("reaction_x", f"R_{point}x")),
                        (f"{key}.reaction_y", spec.get("reaction_y", f"R_{point}y")),
                    ]
                constraint_name = spec.get("name", f"{kind}_{point}")
                extra: dict[str, Any] = {"point": point}
                if kind == "rail":
                    extra.update(self._rail_friction(spec, key, point, one_sided, reactions))
            else:  # rolling
                element = self.text(self.require(spec, "element", key, "the round element that rolls"), f"{key}.element")
                if element not in by_name:
                    raise self.fail(f"{key}.element", f"unknown element {element!r} (elements: {', '.join(by_name)})")
                if by_name[element].kind not in ROUND_KINDS:
                    raise self.fail(
                        f"{key}.element",
                        f"element {element!r} is a {by_name[element].kind}, which cannot roll "
                        f"(rolling needs one of: {', '.join(ROUND_KINDS)})",
                    )
                origin = self.vector(spec.get("through", [0, 0]), f"{key}.through", self.names.params, LENGTH)
                angle = self.bounded_angle(
                    self.expr(spec.get("angle", 0), f"{key}.angle", self.names.params, DIMENSIONLESS), f"{key}.angle")
                contact = self.expr(spec.get("contact_at_zero", 0), f"{key}.contact_at_zero", self.names.params, LENGTH)
                reaction_names = [
                    (f"{key}.friction", spec.get("friction", "F_f")),
                    (f"{key}.normal", spec.get("normal", "F_n")),
                ]
                constraint_name = spec.get("name", f"rolling_{element}")
                extra = {"element": element, "contact_at_zero": contact}
                if "friction_coefficient" in spec:
                    mu = self.expr(spec["friction_coefficient"], f"{key}.friction_coefficient", self.names.params, DIMENSIONLESS)
                    if self.si(mu, f"{key}.friction_coefficient") < 0:
                        raise self.fail(f"{key}.friction_coefficient", f"must not be negative, got {sp.sstr(mu)}")
                    extra["friction_coefficient"] = mu
            constraint_name = self.identifier(constraint_name, f"{key}.name", "constraint name")
            if constraint_name in names:
                raise self.fail(f"{key}.name", f"duplicate constraint name {constraint_name!r}")
            names.add(constraint_name)
            reaction_list = []
            for rkey, rname in reaction_names:
                rname = self.identifier(rname, rkey, "reaction name")
                self._check_reaction_name(rname, rkey, reactions)
                reactions[rname] = rkey
                reaction_list.append(rname)
            constraints.append(
                Constraint(
                    name=constraint_name, kind=kind, reactions=tuple(reaction_list), origin=origin,
                    angle=angle, one_sided=one_sided, **extra,
                )
            )
        return constraints

    def _rail_friction(self, spec, key, point, one_sided, seen) -> dict[str, Any]:
        """A rail's Coulomb friction (``friction_coefficient``, its force named by ``friction``):
        a one-sided contact that can stick, slide or separate (see the multibody format)."""
        if "friction_coefficient" not in spec:
            if "friction" in spec:
                raise self.fail(f"{key}.friction", "names the rail's friction force: give friction_coefficient too")
            return {}
        if not one_sided:
            raise self.fail(f"{key}.one_sided", "a rail with friction is a contact that can separate: give "
                            "one_sided = true (friction on a two-sided guide is not modelled)")
        mu = self.expr(spec["friction_coefficient"], f"{key}.friction_coefficient", self.names.params, DIMENSIONLESS)
        if not self.si(mu, f"{key}.friction_coefficient") >= 0:
            raise self.fail(f"{key}.friction_coefficient", f"must not be negative, got {sp.sstr(mu)}")
        name = self.identifier(spec.get("friction", f"F_{point}"), f"{key}.friction", "reaction name")
        self._check_reaction_name(name, f"{key}.friction", seen)
        seen[name] = f"{key}.friction"
        return {"friction_coefficient": mu, "friction_reaction": name}

    def _check_reaction_name(self, name: str, key: str, seen: Mapping[str, str]) -> None:
        taken = {"alpha", "t", self.coordinate, self.coordinate + "_dot", self.coordinate + "_ddot"}
        if name in seen:
            raise self.fail(key, f"duplicate reaction name {name!r} (also used at {seen[name]})")
        if name in self.parameters:
            raise self.fail(key, f"reaction name {name!r} is already a parameter")
        if name in taken or name in RESERVED_NAMES:
            raise self.fail(key, f"reaction name {name!r} is reserved")

    # -- loads and units -------------------------------------------------------------------------
    def _read_loads(self, entries: list[dict[str, Any]], points: Mapping[str, Point]) -> list[Load]:
        loads: list[Load] = []
        names: set[str] = set()
        for i, spec in enumerate(entries):
            key = f"loads[{i}]"
            kind = self.kind_of(spec, key, "load", LOAD_KINDS, LOAD_COMMON, LOAD_KEYS)
            name = self.identifier(spec.get("name", kind if kind == "gravity" else f"{kind}_{i + 1}"), f"{key}.name", "load name")
            self.distinct_load(name, kind, key, names, any(load.kind == "gravity" for load in loads))
            if kind == "gravity":
                g = self.expr(self.require(spec, "g", key, "the gravitational acceleration, e.g. g = \"g\""), f"{key}.g", self.names.params, ACCELERATION)
                self.positive(g, f"{key}.g", "g")
                loads.append(Load(name, kind, magnitude=g, direction=self.unit_direction(spec, key)))
            elif kind == "force":
                point = self.text(self.require(spec, "point", key, "the body point where it acts"), f"{key}.point")
                if point not in points:
                    raise self.fail(f"{key}.point", f"unknown point {point!r} (points: {', '.join(points)})")
                components = self.vector(
                    self.require(spec, "components", key, "its fixed-frame components [Fx, Fy]"),
                    f"{key}.components", self.names.with_state_t, FORCE,
                )
                loads.append(Load(name, kind, point=point, components=components))
            else:
                moment = self.expr(self.require(spec, "moment", key, "its k-component, counter-clockwise positive"), f"{key}.moment", self.names.with_state_t, MOMENT)
                loads.append(Load(name, kind, magnitude=moment))
        return loads

    def distinct_load(self, name: str, kind: str, key: str, names: set[str], has_gravity: bool) -> None:
        """Refuse a load whose name an earlier load has, or a second gravity load (a pasted block
        would double g unsaid); record ``name`` in ``names``."""
        if name in names:
            raise self.fail(f"{key}.name", f"duplicate load name {name!r}" + (" (only one gravity load is allowed)"
                                                                            if kind == "gravity" and has_gravity else ""))
        if kind == "gravity" and has_gravity:
            raise self.fail(key, "a second gravity load (gravity acts once on every element)")
        names.add(name)

    def unit_direction(self, spec: dict[str, Any], key: str) -> sp.Matrix:
        """``spec``'s ``direction`` (default straight down), scaled to unit length: a direction
        says which way and never how much, so ["1", "-1"] does not make gravity sqrt(2) times
        stronger, and ["1e-13", "0"] is the x axis. The zero vector is refused: every component
        exactly 0, or 0 to round-off (no larger than its own float64 error bound,
        :func:`solver.analyses.instant.round_off_bound`: sin(beta) at
        beta = 180 deg, 1.2e-16 beside its terms of 3.1, has no sign); such a component beside
        others that are not is taken as 0."""
        from .analyses.instant import entry_sizes, round_off_bound

        where = f"{key}.direction"
        direction = self.vector(spec.get("direction", [0, -1]), where, self.names.params, DIMENSIONLESS)
        values = [self.si(c, where) for c in direction]
        if not any(values):
            raise self.fail(where, "the direction is the zero vector")
        sizes = entry_sizes(list(direction), self.si_values)
        bounds = [] if sizes is None else [round_off_bound(s) for s in sizes]
        if bounds and all(abs(v) <= e for v, e in zip(values, bounds)):
            shown = " and ".join(f"{sp.sstr(c)} = {v:.3g} (error bound {e:.2g})"
                                 for c, v, e in zip(direction, values, bounds) if v)
            raise self.fail(where, f"the direction is the zero vector to round-off: {shown}, within float64's "
                                   "error of 0, says no way")
        if bounds:  # a component that is 0 to round-off is 0 (["sin(beta)", "1e-15"] at 180 deg is straight up)
            direction = sp.Matrix([0 if abs(v) <= e else c for c, v, e in zip(direction, values, bounds)])
            values = [0.0 if abs(v) <= e else v for v, e in zip(values, bounds)]
        norm = math.hypot(*values)
        return direction / sp.sqrt(direction[0] ** 2 + direction[1] ** 2) if abs(norm - 1.0) > 1e-12 else direction

    def _read_output_units(self, table: dict[str, Any]) -> dict[str, str]:
        chosen: dict[str, str] = {}
        for name, value in table.items():
            key = f"output_units.{name}"
            if name not in OUTPUT_UNIT_DIMENSIONS:
                raise self.fail(key, f"unknown key {name!r} (valid keys: {', '.join(OUTPUT_UNIT_DIMENSIONS)})")
            text = self.text(value, key)
            try:
                dim = ureg.get_dimensionality(units.parse_unit(text, f"{self.label}: {key}"))
            except InputError as err:
                raise SceneError(str(err)) from None
            if dim != OUTPUT_UNIT_DIMENSIONS[name]:
                raise self.fail(
                    key, f"{text!r} is {describe_dimension(dim)}, but {name} needs {describe_dimension(OUTPUT_UNIT_DIMENSIONS[name])}"
                )
            if name.startswith("angle") or name.startswith("angular"):
                what = units.not_angular(units.parse_unit(text, key))
                if what is not None:  # percent, Hz: pint would print a number of radians in them
                    raise self.fail(key, f"{text!r} is {what}, but {name} needs an angle unit (deg, rad, rev...)")
            chosen[name] = text
        return chosen

    # -- placement ------------------------------------------------------------------------------
    def _check_placement(self, orientation, position, points, elements, constraints) -> None:
        """The constraints must fix the body's two translational freedoms,
        exactly, with a geometry that exists (rails not parallel)."""
        removed = sum(FREEDOMS_REMOVED[c.kind] for c in constraints)
        summary = ", ".join(f"{c.kind} ({FREEDOMS_REMOVED[c.kind]})" for c in constraints)
        if removed < 2:
            raise self.fail(
                "constraints",
                f"the body's placement is not determined: the constraints fix {removed} of its 2 "
                f"translational freedoms [{summary}]; add a second rail, or use a pivot or a rolling contact",
            )
        if removed > 2:
            raise self.fail(
                "constraints",
                f"the body is over-constrained: the constraints fix {removed} translational freedoms "
                f"but it has only 2 [{summary}]; a single coordinate cannot then change",
            )
        rails = [(i, c) for i, c in enumerate(constraints) if c.kind == "rail"]
        if len(rails) == 2:
            (i1, r1), (i2, r2) = rails
            if r1.point == r2.point:
                raise self.fail(
                    f"constraints[{i2}].point",
                    f"both rails hold point {r1.point!r}, which fixes it; use a pivot there, or put the second rail on another point",
                )
            a1 = self.si(r1.angle, f"constraints[{i1}].angle")
            a2 = self.si(r2.angle, f"constraints[{i2}].angle")
            if abs(math.sin(a2 - a1)) < _GEOMETRY_TOL:
                raise self.fail(
                    f"constraints[{i2}].angle",
                    f"impossible geometry: the rails of constraints[{i1}] and constraints[{i2}] are parallel "
                    f"(directions {math.degrees(a1):.6g} deg and {math.degrees(a2):.6g} deg), so they cannot fix the body",
                )
        if not orientation.has(self.q) and (position is None or not position[1].has(self.q)):
            raise self.fail(
                "body.orientation",
                f"the body cannot move: neither its orientation nor its position depends on {self.coordinate}",
            )
        if position is not None:
            self._check_position_consistent(orientation, position, points, elements, constraints)

    def _check_position_consistent(self, orientation, position, points, elements, constraints) -> None:
        """An explicit position must agree with every constraint (checked at a few angles)."""
        name, at = position
        ref = points[name].coords
        by_name = {e.name: e for e in elements}
        q0 = self.state_q
        for q in (q0, q0 + 0.37, q0 - 0.51):
            subs = {**self.si_values, self.q: q}
            phi = float(orientation.evalf(subs=subs))
            rot = sp.Matrix([[math.cos(phi), -math.sin(phi)], [math.sin(phi), math.cos(phi)]])

            def fixed(body_coords: sp.Matrix) -> tuple[float, float]:
                value = at + rot * (body_coords - ref)
                return float(value[0].evalf(subs=subs)), float(value[1].evalf(subs=subs))

            for i, c in enumerate(constraints):
                ox, oy = (float(v.evalf(subs=subs)) for v in c.origin)
                if c.kind == "rolling":
                    element = by_name[c.element]
                    px, py = fixed(element.center)
                    ang = float(c.angle.evalf(subs=subs))
                    gap = -math.sin(ang) * (px - ox) + math.cos(ang) * (py - oy) - float(element.dims["radius"].evalf(subs=subs))
                    scale = float(element.dims["radius"].evalf(subs=subs))
                else:
                    px, py = fixed(points[c.point].coords)
                    if c.kind == "rail":
                        ang = float(c.angle.evalf(subs=subs))
                        gap = -math.sin(ang) * (px - ox) + math.cos(ang) * (py - oy)
                    else:
                        gap = math.hypot(px - ox, py - oy)
                    scale = max(1.0, math.hypot(px, py), math.hypot(ox, oy))
                if abs(gap) > 1e-7 * max(scale, 1e-12):
                    raise self.fail(
                        "body.position",
                        f"the given position of {name!r} disagrees with constraints[{i}] ({c.kind}) at "
                        f"{self.coordinate} = {math.degrees(q):.6g} deg (off by {gap:.3g} m)",
                    )


__all__ = ["load_scene", "parse_quantity", "describe_dimension", "OUTPUT_UNIT_DIMENSIONS"]


def _mass_centre(element) -> sp.Matrix:
    """The body-frame mass centre of an element of either format (a semicircular disk's is off its
    ``center``, the midpoint of its straight edge)."""
    from solver.model.elements import ELEMENT_CLASSES

    if hasattr(element, "mass_center"):
        return sp.Matrix(element.mass_center)
    return ELEMENT_CLASSES[element.kind](element.name, sp.sympify(element.mass), sp.Matrix(element.center),
                                         sp.sympify(element.angle), dict(element.dims)).mass_center
