"""A one-body scene in the original format, as a :class:`~solver.model.system.System`.

The original format ([coordinate], [body], [points], [[elements]],
[[constraints]]) describes one body with one coordinate. Its constraints
become joints to the ground: ``rail`` -> :class:`Rail`, ``pivot`` ->
:class:`Pin`, ``rolling`` -> :class:`Rolling` (with the no-slip reference of
the format: the contact point is ``contact_at_zero`` along the surface when
the coordinate is 0). The system is cached on the scene that owns it.
"""
from __future__ import annotations

import sympy as sp

from ..model.contacts import Friction
from ..model.bodies import GROUND, Point, RigidBody
from ..model.elements import ELEMENT_CLASSES
from ..model.joints import Pin, Rail, Reaction, Rolling, copy_vec
from ..model.loads import Couple, Force, Gravity
from ..model.system import Coordinate, System

__all__ = ["system_from_scene", "BODY"]

BODY = "body"
"""The name of the one body of a scene in the original format."""


def system_from_scene(scene) -> System:
    """The System of a :class:`solver.scene.Scene` (cached on the scene)."""
    cached = scene.__dict__.get("_system")
    if cached is not None:
        return cached
    system = _build(scene)
    object.__setattr__(scene, "_system", system)
    return system


def _build(scene) -> System:
    q = scene.q
    value, rate = scene.state_si()
    coordinate = Coordinate(scene.coordinate, "angle", value, rate,
                            given=(scene.state[scene.coordinate], scene.state[scene.coordinate + "_dot"]))
    elements = tuple(
        ELEMENT_CLASSES[e.kind](e.name, sp.sympify(e.mass), copy_vec(e.center), sp.sympify(e.angle), dict(e.dims))
        for e in scene.elements
    )
    points = {n: Point(n, copy_vec(p.coords), p.frame, p.relative_to) for n, p in scene.points.items()}
    body = RigidBody(BODY, elements, points, sp.sympify(scene.orientation), scene.position, scene.default_point)
    by_name = {e.name: e for e in elements}
    joints = []
    for c in scene.constraints:
        reactions = tuple(Reaction(r, c.name, "N", c.one_sided) for r in c.reactions)
        if c.kind == "rail":
            mu = c.friction_coefficient
            friction = {} if mu is None else {"friction": Friction(mu, mu),
                                              "pair": (Reaction(c.friction_reaction, c.name), reactions[0])}
            joints.append(Rail(c.name, GROUND, BODY, reactions, point=points[c.point].coords,
                               through=copy_vec(c.origin), angle=sp.sympify(c.angle), **friction))
        elif c.kind == "pivot":
            joints.append(Pin(c.name, GROUND, BODY, reactions, at_first=copy_vec(c.origin),
                              at_second=points[c.point].coords))
        else:
            e = by_name[c.element]
            friction, normal = reactions
            joints.append(Rolling(
                c.name, GROUND, BODY, (Reaction(friction.name, c.name), Reaction(normal.name, c.name, "N", True)),
                element=e.name, center=copy_vec(e.center), radius=e.dims["radius"],
                through=copy_vec(c.origin), angle=sp.sympify(c.angle),
                s_ref=sp.sympify(c.contact_at_zero), phi_ref=sp.sympify(scene.orientation).subs(q, 0),
                friction=None if c.friction_coefficient is None else Friction(c.friction_coefficient, c.friction_coefficient),
                semicircle_axis=e.angle if e.kind == "semicircular_disk" else None,
            ))
    loads = []
    for load in scene.loads:
        if load.kind == "gravity":
            loads.append(Gravity(load.name, sp.sympify(load.magnitude), sp.Matrix(load.direction)))
        elif load.kind == "force":
            loads.append(Force(load.name, BODY, load.point, sp.Matrix(load.components)))
        else:
            loads.append(Couple(load.name, BODY, sp.sympify(load.magnitude)))
    return System(
        scene.name, scene.parameters, [coordinate], [body], joints, loads,
        source=str(scene.source) if scene.source is not None else None,
        output_units=scene.output_units, description=scene.description,
    )
