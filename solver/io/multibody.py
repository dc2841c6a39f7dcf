"""Reading a multibody scene file ([coordinates], [[bodies]], [[joints]]) into a System.

The format is documented in ``data/scenes/README.md``. Every check names the
file and the key path (``joints[2].connects``) and says what is allowed. The
one-body format of the original scenes is read by :mod:`solver.scenefile`
and converted by :mod:`solver.io.convert`; both formats share the quantity,
expression and dimension checks of that module.
"""
from __future__ import annotations

import math
from typing import Any, Mapping

import sympy as sp

from .. import units
from ..errors import ExpressionError, SceneError
from ..expressions import RESERVED_NAMES, SOLVER_NAMES
from ..model.bodies import GROUND, Ground, Point, RigidBody
from ..model.contacts import Friction
from ..model.elements import ELEMENT_CLASSES
from ..model.joints import (Actuator, Cord, GearMesh, Motor, Pin, PinInSlot, Rail, Reaction, Rolling,
                            RollingOnCircle, Slider)
from ..model.loads import Couple, Damper, Force, Gravity, Spring, TorsionalDamper, TorsionalSpring
from ..model.system import Coordinate, System
from ..scenefile import (ACCELERATION, DIMENSIONLESS, ELEMENT_KEYS, FORCE, LENGTH, MASS, MOMENT, RATE, TIME,
                         _Names, _SceneLoader, describe_dimension)

__all__ = ["is_multibody", "load_multibody"]

TOP_KEYS = ("name", "description", "time", "parameters", "coordinates", "ground", "bodies", "joints",
            "loads", "output_units")
BODY_KEYS = ("name", "orientation", "position", "reference_point", "points", "elements")
COORD_KEYS = ("value", "rate", "guess", "motion")
STIFFNESS = MOMENT / LENGTH ** 2  # N/m
DAMPING = FORCE * TIME / LENGTH
TORSION_STIFFNESS = MOMENT
TORSION_DAMPING = MOMENT * TIME

ELEMENT_KINDS_V2 = dict(ELEMENT_KEYS)
ELEMENT_KINDS_V2["gyration"] = ("center", "radius_of_gyration", "radius")
ELEMENT_KINDS_V2["centroidal_inertia"] = ("center", "inertia", "radius")

JOINT_KEYS: dict[str, tuple[str, ...]] = {
    "pin": ("connects", "reactions"),
    "rail": ("point", "on", "through", "angle", "reaction", "one_sided", "friction", "friction_coefficient",
             "static_friction", "kinetic_friction"),
    "pin_in_slot": ("point", "on", "through", "angle", "reaction", "one_sided"),
    "slider": ("point", "on", "through", "angle", "relative_angle", "reactions", "one_sided", "friction",
               "friction_coefficient", "static_friction", "kinetic_friction"),
    "rolling": ("element", "on", "through", "angle", "contact_at_zero", "friction", "normal",
                "friction_coefficient", "static_friction", "kinetic_friction"),
    "rolling_on_circle": ("element", "on", "center", "radius", "side", "position_angle", "friction", "normal",
                          "friction_coefficient", "static_friction", "kinetic_friction"),
    "gear": ("elements", "internal", "reaction"),
    "cord": ("drum", "point", "direction", "winds", "length", "tension"),
    "motor": ("bodies", "angle", "torque"),
    "actuator": ("point", "on", "through", "angle", "position", "force"),
}
LOAD_KEYS_V2: dict[str, tuple[str, ...]] = {
    "gravity": ("g", "direction"),
    "force": ("point", "components"),
    "couple": ("body", "moment"),
    "spring": ("between", "stiffness", "free_length"),
    "damper": ("between", "coefficient"),
    "torsional_spring": ("bodies", "stiffness", "free_angle"),
    "torsional_damper": ("bodies", "coefficient"),
}


def is_multibody(data: Mapping[str, Any]) -> bool:
    """True for the multibody format (it has [[bodies]] or [coordinates])."""
    return "bodies" in data or "coordinates" in data


def load_multibody(loader: _SceneLoader, data: dict, overrides: dict[str, str]) -> System:
    """Build the System of a parsed multibody scene file (``loader`` gives messages and checks)."""
    return _MultibodyReader(loader).read(data, overrides)


class _MultibodyReader:
    def __init__(self, loader: _SceneLoader):
        self.L = loader

    def fail(self, key, what):
        return self.L.fail(key, what)

    # -- the file ---------------------------------------------------------------------------------
    def read(self, data: dict, overrides: dict[str, str]) -> System:
        L = self.L
        L.overrides = overrides
        L.check_keys(data, TOP_KEYS, "", "a multibody scene file")
        name, description = L.scene_texts(data)
        L._read_parameters(L.table(data.get("parameters", {}), "parameters"))
        coords = L.table(L.require(data, "coordinates", "coordinates", "the table [coordinates]"), "coordinates")
        self._read_coordinates(coords, overrides)
        self._setup_symbols()
        time_value = 0.0
        if "time" in data:
            time_q = self._quantity(data["time"], "time")
            if time_q.dimensionality != TIME:
                raise self.fail("time", f"{time_q:~P} is not a time")
            time_value = float(time_q.to("s").magnitude)
        self._finish_coordinates()
        ground = self._read_ground(L.table(data.get("ground", {}), "ground"))
        bodies = [self._read_body(spec, i) for i, spec in
                  enumerate(L.array_of_tables(L.require(data, "bodies", "bodies", "at least one [[bodies]] entry"), "bodies"))]
        self.ground = ground
        self.bodies = {b.name: b for b in bodies}
        if len(self.bodies) != len(bodies):
            raise self.fail("bodies", "two bodies have the same name")
        self.reaction_names: dict[str, str] = {}
        joints = [self._read_joint(spec, i) for i, spec in enumerate(L.array_of_tables(data.get("joints", []), "joints"))]
        names = [j.name for j in joints]
        for i, n in enumerate(names):
            if names.index(n) != i:
                raise self.fail(f"joints[{i}].name", f"duplicate joint name {n!r}")
        loads = self._read_loads(data)
        output_units = L._read_output_units(L.table(data.get("output_units", {}), "output_units"))
        system = System(name, L.parameters, self.coordinates, bodies, joints, loads, ground=ground,
                        time=time_value, source=L.label, output_units=output_units, description=description)
        return system

    def _quantity(self, value, key):
        from ..scenefile import parse_quantity

        return parse_quantity(value, f"{self.L.label}: {key}")

    # -- coordinates -------------------------------------------------------------------------------
    def _read_coordinates(self, table: dict, overrides: dict[str, str]) -> None:
        L = self.L
        if not table:
            raise self.fail("coordinates", "no coordinates: name at least one, e.g. theta = { value = \"30 deg\", rate = \"0 rad/s\" }")
        self.raw_coords = {}
        for cname, spec in table.items():
            key = f"coordinates.{cname}"
            L.identifier(cname, key, "coordinate name")
            if cname in RESERVED_NAMES or cname in SOLVER_NAMES | {"ground"} or cname in L.parameters:
                raise self.fail(key, f"{cname!r} is reserved or already a parameter")
            for rate in (f"{cname}_dot", f"{cname}_ddot"):
                if rate in L.parameters:
                    raise self.fail(f"parameters.{rate}", f"{rate!r} is a rate of coordinate {cname!r} (its velocity or "
                                                          f"acceleration) and cannot also be a parameter")
            spec = L.table(spec, key)
            L.check_keys(spec, COORD_KEYS, key, "a coordinate (value + rate, guess, or motion)")
            given = [k for k in ("value", "guess", "motion") if k in spec]
            if len(given) != 1:
                raise self.fail(key, "give exactly one of value (with rate), guess (a dependent coordinate) or motion (prescribed)")
            self.raw_coords[cname] = spec
        self.overrides = dict(overrides)
        for oname, text in overrides.items():
            base = oname[:-4] if oname.endswith("_dot") else oname
            if oname in L.parameters:
                continue
            if base in table and isinstance(table[base], dict) and "motion" in table[base]:
                raise self.fail(f"--set {oname}", f"{base} is prescribed (motion = {table[base]['motion']!r}); "
                                "its value and rate follow from the time: set a parameter of the motion or `time`")
            if oname.endswith("_dot") and base in table and isinstance(table[base], dict) and "guess" in table[base]:
                raise self.fail(f"--set {oname}", f"{base} is a dependent coordinate: its rate is solved from the "
                                "closure equations, not given")
            if base not in table:
                valid = ", ".join([*L.parameters, *table, *(f"{c}_dot" for c in table)])
                raise self.fail(f"--set {oname}", f"unknown name {oname!r} (parameters and state: {valid})")
        # parameters overridden
        for oname, text in overrides.items():
            if oname in L.parameters:
                q = units.zero_in(self._quantity(text, f"--set {oname}"), L.parameters[oname].units)
                if q.dimensionality != L.parameters[oname].dimensionality:
                    raise self.fail(f"--set {oname}", f"{text!r} has the wrong dimension for {oname}")
                L.set_angular(L.parameters[oname], q, text, oname)
                L.parameters[oname] = q
        L.check_magnitudes(L.parameters, self.overrides)
        L.check_angle_sizes({}, self.overrides)

    def _setup_symbols(self):
        L = self.L
        params = {n: sp.Symbol(n, real=True) for n in L.parameters}
        coords = {c: sp.Symbol(c, real=True) for c in self.raw_coords}
        rates = {f"{c}_dot": sp.Symbol(f"{c}_dot", real=True) for c in self.raw_coords}
        t = sp.Symbol("t", real=True)
        L.names = _Names(params=params, with_q={**params, **coords, "t": t},
                         with_state_t={**params, **coords, **rates, "t": t})
        self.with_t = {**params, "t": t}
        L.dims = {params[n]: q.dimensionality for n, q in L.parameters.items()}
        L.dims[t] = TIME
        L.si_values = {params[n]: units.si_magnitude(q) for n, q in L.parameters.items()}
        L.coordinate = "coordinates"
        # the one-body loader's angle bounds evaluate at its coordinate's state: here element and
        # line angles hold parameters only, so no coordinate takes part
        L.q, L.state_q = sp.Symbol("_no_coordinate"), 0.0
        L.overridden = {n for n in self.overrides if n in L.parameters}
        # coordinate kinds from their value/guess/motion
        self.kinds = {}
        self.given_values = {}
        for cname, spec in self.raw_coords.items():
            if "motion" in spec:
                expr = self._motion_expr(spec["motion"], f"coordinates.{cname}.motion")
                self.kinds[cname] = ("motion", expr)
            else:
                key = "value" if "value" in spec else "guess"
                q = self._quantity(spec[key], f"coordinates.{cname}.{key}")
                if q.dimensionality not in (DIMENSIONLESS, LENGTH):
                    raise self.fail(f"coordinates.{cname}.{key}", f"{q:~P} is neither an angle nor a length")
                kind = "angle" if q.dimensionality == DIMENSIONLESS else "length"
                if units.is_bare_zero(q):
                    kind = self._kind_of_bare_zero(cname, spec, key)
                    q = units.zero_in(q, "rad" if kind == "angle" else "m")
                if kind == "angle":  # a bare number refused as --set refuses it (a bare 0 passes)
                    L.set_angle(q, spec[key], cname, f"coordinates.{cname}.{key}")
                if cname in self.overrides:  # the scene's value decides the kind; --set gives one of it
                    text = self.overrides[cname]
                    q = units.zero_in(self._quantity(text, f"--set {cname}"), "rad" if kind == "angle" else "m")
                    if q.dimensionality != (DIMENSIONLESS if kind == "angle" else LENGTH):
                        what = "an angle" if units.is_angle_unit(q) else describe_dimension(q.dimensionality)
                        raise self.fail(f"--set {cname}", f"{text!r} is {what}, but "
                                        f"{cname} is {'an angle' if kind == 'angle' else 'a length'} "
                                        f"(in the scene: {spec[key]!r})")
                    if kind == "angle":
                        L.set_angle(q, text, cname)
                self.given_values[cname] = q
                v = float(q.to("rad" if kind == "angle" else "m").magnitude)
                if kind == "angle":  # the cap on angles, as for the one-body format and --amplitude
                    L.check_angle_sizes({cname: (q, f"coordinates.{cname}.{key}")}, self.overrides)
                self.kinds[cname] = (kind, v)
            sym = coords[cname]
            kind = self.kinds[cname][0]
            if kind == "motion":
                kind = "angle" if self._dim(self.kinds[cname][1]) == DIMENSIONLESS else "length"
            L.dims[sym] = DIMENSIONLESS if kind == "angle" else LENGTH
            L.dims[rates[f"{cname}_dot"]] = RATE if kind == "angle" else LENGTH / TIME

    def _kind_of_bare_zero(self, cname: str, spec: dict, key: str) -> str:
        """``"angle"`` or ``"length"`` for a coordinate whose value (or guess) is a bare 0, which
        cannot tell them apart: the kind its rate in the file gives (``"0.5 m/s"``: a length).

        Raises
        ------
        SceneError
            When the rate is absent or is a bare zero too: one line naming the key, asking for a unit.
        """
        if "rate" in spec:
            rate = self._quantity(spec["rate"], f"coordinates.{cname}.rate")
            if rate.dimensionality == RATE:
                return "angle"
            if rate.dimensionality == LENGTH / TIME:
                return "length"
        raise self.fail(f"coordinates.{cname}.{key}", f"a bare 0 does not tell an angle from a length; write "
                        f"\"0 m\" (or another length unit) or \"0 deg\" (or another angle unit)")

    def _dim(self, expr):
        from ..scenefile import _dimension

        return _dimension(expr, self.L.dims)

    def _motion_expr(self, value, key):
        from ..scenefile import _DimensionError, _dimension
        from ..expressions import parse_expression

        L = self.L
        text = L.text(value, key)
        try:
            expr = parse_expression(text, self.with_t, f"{L.label}: {key}")
        except ExpressionError as err:  # the message already names the place
            raise SceneError(str(err)) from None
        if expr == 0:  # zero in every unit: it cannot say whether the coordinate is an angle or a length
            raise self.fail(key, f"{text!r} is 0 at every t, which does not tell an angle from a length: write 0 "
                            "where the coordinate is used, or give the motion in the scene's parameters (e.g. \"v*t\")")
        try:
            dim = _dimension(expr, L.dims)
        except _DimensionError as err:
            raise self.fail(key, str(err)) from None
        if dim not in (DIMENSIONLESS, LENGTH):
            raise self.fail(key, "a motion must be an angle or a length as a function of t")
        L._check_angle_arguments(expr, key, text, is_angle=dim == DIMENSIONLESS)  # an angle's checks, as orientation's
        return expr

    def _finish_coordinates(self):
        L = self.L
        out = []
        for cname, spec in self.raw_coords.items():
            kind, data = self.kinds[cname]
            if kind == "motion":
                k = "angle" if self._dim(data) == DIMENSIONLESS else "length"
                out.append(Coordinate(cname, k, 0.0, 0.0, motion=data))
                continue
            dependent = "guess" in spec
            rate = 0.0
            if not dependent:
                rkey = f"{cname}_dot"
                text = self.overrides.get(rkey, L.require(spec, "rate", f"coordinates.{cname}", "its rate, e.g. \"0 rad/s\""))
                where = f"coordinates.{cname}.rate" if rkey not in self.overrides else f"--set {rkey}"
                q = units.zero_in(self._quantity(text, where), "rad/s" if kind == "angle" else "m/s")
                need = RATE if kind == "angle" else LENGTH / TIME
                if q.dimensionality != need:  # (shown as typed, in the file as on --set)
                    raise self.fail(where, f"{text!r} is not {'an angular velocity' if kind == 'angle' else 'a speed'}")
                L.set_rate(q, text, rkey, None if rkey in self.overrides else where)
                L.check_magnitudes({rkey: q}, self.overrides, {rkey: where})  # the SI cap, as on parameters
                rate = float(q.to_base_units().magnitude)
            elif "rate" in spec:
                raise self.fail(f"coordinates.{cname}.rate", "a dependent coordinate's rate is solved, not given")
            if not math.isfinite(data) or abs(data) > 1e6:
                raise self.fail(f"coordinates.{cname}", f"value {data:g} out of range (|value| <= 1e6 SI)")
            given = None if dependent else (self.given_values[cname], q)
            out.append(Coordinate(cname, kind, data, rate, dependent=dependent, given=given))
        self.coordinates = out

    # -- ground and bodies ---------------------------------------------------------------------------
    def _read_ground(self, table: dict) -> Ground:
        L = self.L
        L.check_keys(table, ("points",), "ground", "[ground]")
        points = {}
        for pname, value in L.table(table.get("points", {}), "ground.points").items():
            key = f"ground.points.{pname}"
            L.identifier(pname, key, "point name")
            points[pname] = Point(pname, L.vector(value, key, self.with_t, LENGTH))
        return Ground(points)

    def _read_body(self, spec: dict, i: int) -> RigidBody:
        L = self.L
        key = f"bodies[{i}]"
        L.check_keys(spec, BODY_KEYS, key, "a body")
        name = L.identifier(L.require(spec, "name", key, "the body's name"), f"{key}.name", "body name")
        if name == GROUND:
            raise self.fail(f"{key}.name", "'ground' is the fixed frame's name")
        raw_points = L._read_points(L.table(L.require(spec, "points", key, "its named points"), f"{key}.points"),
                                     f"{key}.points")
        elements = self._read_elements(L.array_of_tables(L.require(spec, "elements", key, "at least one element"),
                                                         f"{key}.elements"), raw_points, key)
        L.check_mass_centre_name(raw_points, elements, f"{key}.points")
        points = {n: Point(n, sp.Matrix(p.coords), p.frame, p.relative_to) for n, p in raw_points.items()}
        orientation = None
        if "orientation" in spec:
            orientation = L.expr(spec["orientation"], f"{key}.orientation", L.names.with_q, DIMENSIONLESS)
        position = None
        if "position" in spec:
            ps = L.table(spec["position"], f"{key}.position")
            L.check_keys(ps, ("point", "at"), f"{key}.position", "a position")
            pname = L.text(L.require(ps, "point", f"{key}.position", "the point whose path is given"), f"{key}.position.point")
            if pname not in points or points[pname].frame != "body":
                raise self.fail(f"{key}.position.point", f"{pname!r} is not a body-frame point of {name!r}")
            position = (pname, L.vector(L.require(ps, "at", f"{key}.position", "[x, y]"), f"{key}.position.at",
                                        L.names.with_q, LENGTH))
        ref = spec.get("reference_point")
        if ref is not None:
            ref = L.text(ref, f"{key}.reference_point")
            if ref not in points and ref != "G":
                raise self.fail(f"{key}.reference_point", f"{ref!r} is not a point of {name!r} (points: {', '.join(points)})")
        return RigidBody(name, elements, points, orientation, position, ref)

    def _read_elements(self, entries, points, bkey):
        L = self.L
        from ..scene import Element as OldElement

        if not entries:
            raise self.fail(f"{bkey}.elements", "the body has no elements")
        out = []
        for i, spec in enumerate(entries):
            key = f"{bkey}.elements[{i}]"
            kind = L.kind_of(spec, key, "element", tuple(ELEMENT_KINDS_V2), ("name", "kind", "mass"), ELEMENT_KINDS_V2)
            ename = L.identifier(spec.get("name", f"{kind}_{i + 1}"), f"{key}.name", "element name")
            mass = L.expr(L.require(spec, "mass", key, "the element's mass"), f"{key}.mass", L.names.params, MASS)
            if not L.si(mass, f"{key}.mass") >= 0:
                raise self.fail(f"{key}.mass", "the mass must not be negative")
            if kind in ("gyration", "centroidal_inertia"):
                center = L._place(spec.get("center", [0, 0]), f"{key}.center", points)
                dims = {}
                if kind == "gyration":
                    dims["radius_of_gyration"] = L._length(spec, "radius_of_gyration", key)
                else:
                    inertia = L.expr(L.require(spec, "inertia", key, "I-bar"), f"{key}.inertia", L.names.params, MASS * LENGTH**2)
                    if not L.si(inertia, f"{key}.inertia") >= 0:
                        raise self.fail(f"{key}.inertia", "must not be negative")
                    dims["inertia"] = inertia
                if "radius" in spec:
                    dims["radius"] = L._length(spec, "radius", key)
                out.append(ELEMENT_CLASSES[kind](ename, mass, center, sp.Integer(0), dims))
                continue
            old = L._element_geometry(spec, key, kind, ename, mass, points)
            assert isinstance(old, OldElement)
            out.append(ELEMENT_CLASSES[kind](old.name, old.mass, sp.Matrix(old.center), old.angle, dict(old.dims)))
        if len({e.name for e in out}) != len(out):
            raise self.fail(f"{bkey}.elements", "two elements have the same name")
        if not sum(L.si(e.mass, f"{bkey}.elements") for e in out) > 0:
            raise self.fail(f"{bkey}.elements", "the body has no mass (a massless element is allowed, a massless body is not)")
        return tuple(out)

    # -- references -----------------------------------------------------------------------------------
    def body_name(self, value, key) -> str:
        name = self.L.text(value, key)
        if name != GROUND and name not in self.bodies:
            raise self.fail(key, f"unknown body {name!r} (bodies: ground, {', '.join(self.bodies)})")
        return name

    def point_ref(self, value, key) -> tuple[str, str, sp.Matrix]:
        """'body:point' (or a ground point 'ground:O') of a joint -> (body, point, body-frame coords)."""
        body, point, holder = self._split_point(value, key)
        if body != GROUND and point in holder.points and holder.points[point].is_instant:
            raise self.fail(key, f"{point!r} is an instant point; joints need points fixed in the body")
        coords = holder.body_coords(point)
        return body, point, coords

    def element_ref(self, value, key):
        body, ename = self._split_ref(value, key, "BODY:ELEMENT such as \"wheel:disk\"")
        if body == GROUND:
            raise self.fail(key, "the ground has no elements")
        try:
            e = self.bodies[body].element(ename)
        except KeyError:
            names = ", ".join(x.name for x in self.bodies[body].elements)
            raise self.fail(key, f"{ename!r} is not an element of {body!r} (elements: {names})") from None
        if not e.round:
            raise self.fail(key, f"element {ename!r} is a {e.kind} without a rim; it needs a radius (disk, ring, semicircle, or radius = ...)")
        return body, e

    def reaction(self, value, key, joint, unit="N", one_sided=False) -> Reaction:
        L = self.L
        rname = L.identifier(value, key, "reaction name")
        taken = {*SOLVER_NAMES, *L.parameters, *self.raw_coords, *(f"{c}_dot" for c in self.raw_coords),
                 *(f"{c}_ddot" for c in self.raw_coords)}
        if rname in self.reaction_names:
            raise self.fail(key, f"duplicate reaction name {rname!r} (also used at {self.reaction_names[rname]})")
        if rname in taken or rname in RESERVED_NAMES:
            raise self.fail(key, f"reaction name {rname!r} is reserved or already a parameter/coordinate")
        self.reaction_names[rname] = key
        return Reaction(rname, joint, unit, one_sided)

    def _point_on_line(self, spec, key, what):
        """A point of one body held on a line of another (``point``, ``on``, ``through``, ``angle``):
        (body, its point's body-frame coords, the line's body, through, angle)."""
        L = self.L
        body, _, coords = self.point_ref(L.require(spec, "point", key, what), f"{key}.point")
        on = self.body_name(spec.get("on", GROUND), f"{key}.on")
        self._distinct(on, body, key)
        through, angle = self.line(spec, key, on)
        return body, coords, on, through, angle

    def line(self, spec, key, on):
        L = self.L
        through = L.vector(spec.get("through", [0, 0]), f"{key}.through", L.names.params, LENGTH)
        angle = L.expr(spec.get("angle", 0), f"{key}.angle", L.names.params, DIMENSIONLESS)
        return through, angle

    # -- joints ------------------------------------------------------------------------------------------
    def _read_joint(self, spec: dict, i: int):
        L = self.L
        key = f"joints[{i}]"
        kind = L.kind_of(spec, key, "joint", tuple(JOINT_KEYS), ("kind", "name"), JOINT_KEYS)
        name = L.identifier(spec.get("name", f"{kind}_{i + 1}"), f"{key}.name", "joint name")
        return getattr(self, f"_joint_{kind}")(spec, key, name)

    def _names(self, spec, key, field_name, defaults):
        L = self.L
        value = spec.get(field_name, defaults)
        if isinstance(value, str):
            value = [value]
        if not isinstance(value, list) or len(value) != len(defaults):
            raise self.fail(f"{key}.{field_name}", f"expected {len(defaults)} name(s), got {value!r}")
        return value

    def _joint_pin(self, spec, key, name):
        L = self.L
        pair = L.require(spec, "connects", key, "the two coinciding points, e.g. [\"ground:O\", \"crank:O\"]")
        if not isinstance(pair, list) or len(pair) != 2:
            raise self.fail(f"{key}.connects", "expected two points [\"BODY:POINT\", \"BODY:POINT\"]")
        b1, _, c1 = self.point_ref(pair[0], f"{key}.connects[0]")
        b2, _, c2 = self.point_ref(pair[1], f"{key}.connects[1]")
        self._distinct(b1, b2, key)
        rx, ry = self._names(spec, key, "reactions", [f"{name}_x", f"{name}_y"])
        reactions = (self.reaction(rx, f"{key}.reactions[0]", name), self.reaction(ry, f"{key}.reactions[1]", name))
        return Pin(name, b1, b2, reactions, at_first=c1, at_second=c2)

    def _distinct(self, b1, b2, key):
        if b1 == b2:
            raise self.fail(key, f"a joint connects two different bodies, got {b1!r} twice")

    def _joint_rail(self, spec, key, name, cls=Rail):
        L = self.L
        body, coords, on, through, angle = self._point_on_line(spec, key, "the point held on the line, BODY:POINT")
        one_sided = L.boolean(spec.get("one_sided", False), f"{key}.one_sided")
        r = self.reaction(spec.get("reaction", f"N_{name}"), f"{key}.reaction", name, "N", one_sided)
        friction = self._friction(spec, key)
        if friction is None:
            return cls(name, on, body, (r,), point=coords, through=through, angle=angle)
        if not one_sided:
            raise self.fail(f"{key}.one_sided", "a rail with friction is a contact that can separate: give "
                            "one_sided = true (friction on a two-sided guide is not modelled)")
        f = self.reaction(spec.get("friction", f"F_{name}"), f"{key}.friction", name)
        return cls(name, on, body, (r,), point=coords, through=through, angle=angle, friction=friction,
                   pair=(f, r))

    def _joint_pin_in_slot(self, spec, key, name):
        return self._joint_rail(spec, key, name, PinInSlot)

    def _joint_slider(self, spec, key, name):
        L = self.L
        body, coords, on, through, angle = self._point_on_line(spec, key, "the point of the sliding body on the line")
        rel = L.expr(spec.get("relative_angle", 0), f"{key}.relative_angle", L.names.params, DIMENSIONLESS)
        n, m = self._names(spec, key, "reactions", [f"N_{name}", f"M_{name}"])
        one_sided = L.boolean(spec.get("one_sided", False), f"{key}.one_sided")
        reactions = (self.reaction(n, f"{key}.reactions[0]", name, "N", one_sided),
                     self.reaction(m, f"{key}.reactions[1]", name, "N*m"))
        friction = self._friction(spec, key)
        if friction is None:
            return Slider(name, on, body, reactions, point=coords, through=through, angle=angle, relative_angle=rel)
        if not one_sided:
            raise self.fail(f"{key}.one_sided", "a slider with friction is a block resting on a surface: give "
                            "one_sided = true (friction on a two-sided guide is not modelled)")
        f = self.reaction(spec.get("friction", f"F_{name}"), f"{key}.friction", name)
        return Slider(name, on, body, reactions, point=coords, through=through, angle=angle, relative_angle=rel,
                      friction=friction, pair=(f, reactions[0]))

    def _friction(self, spec, key) -> Friction | None:
        """Coulomb coefficients: ``friction_coefficient`` (static = kinetic), or
        ``static_friction`` and ``kinetic_friction`` (kinetic <= static)."""
        L = self.L
        given = [k for k in ("friction_coefficient", "static_friction", "kinetic_friction") if k in spec]
        if not given:
            return None
        if "friction_coefficient" in given and len(given) > 1:
            raise self.fail(f"{key}.friction_coefficient", "give either friction_coefficient or "
                            "static_friction and kinetic_friction, not both")
        if given == ["static_friction"] or given == ["kinetic_friction"]:
            raise self.fail(f"{key}.{given[0]}", "give both static_friction and kinetic_friction")
        values = {}
        for k in given:
            mu = L.expr(spec[k], f"{key}.{k}", L.names.params, DIMENSIONLESS)
            v = L.si(mu, f"{key}.{k}")
            if not (v >= 0 and math.isfinite(v)):
                raise self.fail(f"{key}.{k}", "must be a finite number >= 0")
            values[k] = (mu, v)
        if "friction_coefficient" in values:
            mu = values["friction_coefficient"][0]
            return Friction(mu, mu)
        (ms, vs), (mk, vk) = values["static_friction"], values["kinetic_friction"]
        if vk > vs:
            raise self.fail(f"{key}.kinetic_friction", f"must not exceed static_friction ({vk:g} > {vs:g})")
        return Friction(ms, mk)

    def _joint_rolling(self, spec, key, name):
        L = self.L
        body, e = self.element_ref(L.require(spec, "element", key, "the rolling element, BODY:ELEMENT"), f"{key}.element")
        on = self.body_name(spec.get("on", GROUND), f"{key}.on")
        self._distinct(on, body, key)
        through, angle = self.line(spec, key, on)
        s_ref = L.expr(spec.get("contact_at_zero", 0), f"{key}.contact_at_zero", L.names.params, LENGTH)
        f = self.reaction(spec.get("friction", f"F_{name}"), f"{key}.friction", name)
        n = self.reaction(spec.get("normal", f"N_{name}"), f"{key}.normal", name, "N", True)
        return Rolling(name, on, body, (f, n), element=e.name, center=sp.Matrix(e.center), radius=e.radius,
                       through=through, angle=angle, s_ref=s_ref, phi_ref=sp.Integer(0), friction=self._friction(spec, key),
                       semicircle_axis=e.angle if e.kind == "semicircular_disk" else None)

    def _joint_rolling_on_circle(self, spec, key, name):
        L = self.L
        body, e = self.element_ref(L.require(spec, "element", key, "the rolling element, BODY:ELEMENT"), f"{key}.element")
        on = self.body_name(spec.get("on", GROUND), f"{key}.on")
        self._distinct(on, body, key)
        center = L.vector(spec.get("center", [0, 0]), f"{key}.center", L.names.params, LENGTH)
        radius = L._length(spec, "radius", key)
        side = L.text(spec.get("side", "outside"), f"{key}.side")
        if side not in ("inside", "outside"):
            raise self.fail(f"{key}.side", f"must be \"inside\" or \"outside\", got {side!r}")
        if side == "inside" and not L.si(radius, key) > L.si(e.radius, key):
            raise self.fail(f"{key}.radius", "rolling inside needs a circle larger than the element")
        pa = None
        if "position_angle" in spec:
            pa = L.expr(spec["position_angle"], f"{key}.position_angle", L.names.with_q, DIMENSIONLESS)
        f = self.reaction(spec.get("friction", f"F_{name}"), f"{key}.friction", name)
        n = self.reaction(spec.get("normal", f"N_{name}"), f"{key}.normal", name, "N", True)
        return RollingOnCircle(name, on, body, (f, n), element=e.name, center=sp.Matrix(e.center), radius=e.radius,
                               circle_center=center, circle_radius=radius, inside=side == "inside",
                               position_angle=pa, friction=self._friction(spec, key))

    def _joint_gear(self, spec, key, name):
        L = self.L
        pair = L.require(spec, "elements", key, "the two pitch circles [\"BODY:ELEMENT\", \"BODY:ELEMENT\"]")
        if not isinstance(pair, list) or len(pair) != 2:
            raise self.fail(f"{key}.elements", "expected two elements")
        b1, e1 = self.element_ref(pair[0], f"{key}.elements[0]")
        b2, e2 = self.element_ref(pair[1], f"{key}.elements[1]")
        self._distinct(b1, b2, key)
        internal = L.boolean(spec.get("internal", False), f"{key}.internal")
        r = self.reaction(spec.get("reaction", f"F_{name}"), f"{key}.reaction", name)
        return GearMesh(name, b1, b2, (r,), center_first=sp.Matrix(e1.center), center_second=sp.Matrix(e2.center),
                        radius_first=e1.radius, radius_second=e2.radius, internal=internal)

    def _joint_cord(self, spec, key, name):
        L = self.L
        b1, e = self.element_ref(L.require(spec, "drum", key, "the drum, BODY:ELEMENT"), f"{key}.drum")
        b2, _, coords = self.point_ref(L.require(spec, "point", key, "where the cord is tied, BODY:POINT"), f"{key}.point")
        self._distinct(b1, b2, key)
        direction = L.unit_direction(spec, key)
        winds = L.text(spec.get("winds", "ccw"), f"{key}.winds")
        if winds not in ("ccw", "cw"):
            raise self.fail(f"{key}.winds", f"must be \"ccw\" or \"cw\", got {winds!r}")
        length = L.expr(L.require(spec, "length", key, "the free length of cord when the drum's angle is 0"),
                        f"{key}.length", L.names.params, LENGTH)
        r = self.reaction(spec.get("tension", f"T_{name}"), f"{key}.tension", name, "N", True)
        return Cord(name, b1, b2, (r,), center=sp.Matrix(e.center), radius=e.radius, direction=direction,
                    point=coords, winds=winds, length=length)

    def _joint_motor(self, spec, key, name):
        L = self.L
        pair = L.require(spec, "bodies", key, "[\"FIRST\", \"SECOND\"]: the torque acts on the second")
        if not isinstance(pair, list) or len(pair) != 2:
            raise self.fail(f"{key}.bodies", "expected two body names")
        b1 = self.body_name(pair[0], f"{key}.bodies[0]")
        b2 = self.body_name(pair[1], f"{key}.bodies[1]")
        self._distinct(b1, b2, key)
        angle = None
        if "angle" in spec:
            angle = L.expr(spec["angle"], f"{key}.angle", self.with_t, DIMENSIONLESS)
        r = self.reaction(spec.get("torque", f"M_{name}"), f"{key}.torque", name, "N*m")
        return Motor(name, b1, b2, (r,), angle=angle)

    def _joint_actuator(self, spec, key, name):
        L = self.L
        body, coords, on, through, angle = self._point_on_line(spec, key, "the driven point, BODY:POINT")
        position = None
        if "position" in spec:
            position = L.expr(spec["position"], f"{key}.position", self.with_t, LENGTH)
        r = self.reaction(spec.get("force", f"F_{name}"), f"{key}.force", name)
        return Actuator(name, on, body, (r,), point=coords, through=through, angle=angle, position=position)

    # -- loads ------------------------------------------------------------------------------------------
    def _read_load(self, spec: dict, i: int):
        L = self.L
        key = f"loads[{i}]"
        kind = L.kind_of(spec, key, "load", tuple(LOAD_KEYS_V2), ("kind", "name"), LOAD_KEYS_V2)
        name = L.identifier(spec.get("name", kind if kind == "gravity" else f"{kind}_{i + 1}"), f"{key}.name", "load name")
        names = L.names.with_state_t
        if kind == "gravity":
            g = L.positive(L.expr(L.require(spec, "g", key, "g"), f"{key}.g", L.names.params, ACCELERATION), f"{key}.g", "g")
            return Gravity(name, g, L.unit_direction(spec, key))
        if kind == "force":
            body, point, _ = self._load_point(L.require(spec, "point", key, "BODY:POINT"), f"{key}.point")
            self._not_on_ground(body, f"{key}.point")
            comps = L.vector(L.require(spec, "components", key, "[Fx, Fy]"), f"{key}.components", names, FORCE)
            return Force(name, body, point, comps)
        if kind == "couple":
            body = self.body_name(L.require(spec, "body", key, "the body it acts on"), f"{key}.body")
            self._not_on_ground(body, f"{key}.body")
            moment = L.expr(L.require(spec, "moment", key, "its k-component"), f"{key}.moment", names, MOMENT)
            return Couple(name, body, moment)
        if kind in ("spring", "damper"):
            pair = L.require(spec, "between", key, "[\"BODY:POINT\", \"BODY:POINT\"]")
            if not isinstance(pair, list) or len(pair) != 2:
                raise self.fail(f"{key}.between", "expected two points")
            a = self._load_point(pair[0], f"{key}.between[0]")[:2]
            b = self._load_point(pair[1], f"{key}.between[1]")[:2]
            if a == b:
                raise self.fail(f"{key}.between", f"both ends are {':'.join(a)}: a {kind} joins two different points")
            if a[0] == GROUND and b[0] == GROUND:
                raise self.fail(f"{key}.between", f"both ends are on the ground: the {kind} acts on nothing that moves")
            if kind == "spring":
                k = L.expr(L.require(spec, "stiffness", key, "k"), f"{key}.stiffness", L.names.params, STIFFNESS)
                L.nonnegative(k, f"{key}.stiffness", "a stiffness")
                free = L.expr(spec.get("free_length", 0), f"{key}.free_length", L.names.params, LENGTH)
                return Spring(name, a, b, k, free)
            c = L.expr(L.require(spec, "coefficient", key, "c"), f"{key}.coefficient", L.names.params, DAMPING)
            return Damper(name, a, b, L.nonnegative(c, f"{key}.coefficient", "a damping coefficient"))
        pair = L.require(spec, "bodies", key, "[\"FIRST\", \"SECOND\"]")
        if not isinstance(pair, list) or len(pair) != 2:
            raise self.fail(f"{key}.bodies", "expected two body names")
        b1 = self.body_name(pair[0], f"{key}.bodies[0]")
        b2 = self.body_name(pair[1], f"{key}.bodies[1]")
        if kind == "torsional_spring":
            k = L.expr(L.require(spec, "stiffness", key, "k"), f"{key}.stiffness", L.names.params, TORSION_STIFFNESS)
            L.nonnegative(k, f"{key}.stiffness", "a stiffness")
            free = L.expr(spec.get("free_angle", 0), f"{key}.free_angle", L.names.params, DIMENSIONLESS)
            return TorsionalSpring(name, b1, b2, k, free)
        c = L.expr(L.require(spec, "coefficient", key, "c"), f"{key}.coefficient", L.names.params, TORSION_DAMPING)
        return TorsionalDamper(name, b1, b2, L.nonnegative(c, f"{key}.coefficient", "a damping coefficient"))

    def _not_on_ground(self, body, key):
        if body == GROUND:
            raise self.fail(key, "a force or couple on the ground moves nothing; name the body it acts on")

    def _read_loads(self, data):
        """The ``[[loads]]``, each name once and gravity at most once (the checks of the
        one-body reader, :meth:`solver.scenefile._SceneLoader.distinct_load`)."""
        loads, names = [], set()
        for i, spec in enumerate(self.L.array_of_tables(data.get("loads", []), "loads")):
            load = self._read_load(spec, i)
            kind = "gravity" if isinstance(load, Gravity) else "other"  # (distinct_load asks only this)
            self.L.distinct_load(load.name, kind, f"loads[{i}]", names,
                                 any(isinstance(done, Gravity) for done in loads))
            loads.append(load)
        return loads

    def _load_point(self, value, key):
        """'body:point' of a load (instant points allowed) -> (body, point, None)."""
        body, point, _ = self._split_point(value, key)
        return body, point, None

    def _split_ref(self, value, key, what):
        """'BODY:NAME' -> (a known body or 'ground', NAME)."""
        text = self.L.text(value, key)
        if ":" not in text:
            raise self.fail(key, f"expected {what}, got {text!r}")
        body, name = text.split(":", 1)
        return self.body_name(body, key), name

    def _split_point(self, value, key):
        """'BODY:POINT' -> (body, point, the body or ground holding it), both checked."""
        body, point = self._split_ref(value, key, "BODY:POINT such as \"crank:A\" or \"ground:O\"")
        holder = self.ground if body == GROUND else self.bodies[body]
        if point not in holder.points and not (point == "G" and body != GROUND):
            raise self.fail(key, f"{point!r} is not a point of {body!r} (points: {', '.join(holder.points) or 'none'})")
        return body, point, holder
