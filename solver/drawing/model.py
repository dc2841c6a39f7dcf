"""What a drawing of a scene shows, as data: bodies, points, guides, coordinates, forces.

The drawing is computed here without matplotlib, as a list of
:class:`DrawnItem` (a label, an anchor point, a direction), so that tests
check it against the scene without reading images; :mod:`solver.drawing.render`
only turns the items into lines and text.

Positions are fixed-frame SI values [m] at a complete state (the dependent
coordinates solved by :func:`solver.analyses.instant.assemble`). The free-body
diagram of a body holds every force acting on it at the state: the joint
reactions with their solved values (:func:`solver.analyses.instant.solve_instant`),
the weight at the body's mass centre G, the applied forces, couples, springs
and dampers, and the inertial force -m a_P drawn at G with the couple
-I_P alpha: the moment equation about P (paper Eq. 10) says that these, with
the real forces, have zero moment about P.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import sympy as sp

from ..model.bodies import GROUND
from ..notation import typeset_text
from ..strprint import lambdify
from ..tree_value import DOUBLE, NotEvaluable, real_value, tree_value

__all__ = ["DrawnItem", "Drawing", "BodyShape", "scene_items", "free_body_items", "PoseFunction",
           "body_shapes", "ZERO_FORCE", "CONVENTION", "size_label", "figures_text"]

CONVENTION = "Arrows and arcs: each force and couple in its actual sense at this state; |X| = its size."
"""The free-body diagrams' sign convention, written under every diagram: an arrow (a couple's arc)
points the way the force (couple) acts at the state, and its label gives the size, never a sign.
A reaction solved negative (O_x = -6.772 N) is an arrow against its positive sense labelled
|O_x| = 6.772 N; a spring in compression an arrow pushing its point, labelled with the size of the
tension. Both bodies a joint connects show its reaction by the same label, the arrows opposite."""

ZERO_FORCE = 1e-9
"""A force or couple whose size is below this fraction of the largest on the
same diagram is drawn as zero (no direction): the solve's round-off (about
1e-12 relative) is far below it, and no drawn length could show it."""


@dataclass(frozen=True)
class DrawnItem:
    """One labelled thing on a drawing.

    Attributes
    ----------
    kind : str
        ``element``, ``link`` (the light frame of a body of point masses),
        ``point``, ``guide``, ``support``, ``coordinate``, ``spring`` and
        ``damper`` (a linear spring or damper between its two points),
        ``torsional_spring`` and ``torsional_damper`` (about the pin joining their
        bodies), ``force``, ``couple``, ``inertial`` (dashed force) or
        ``inertial_couple`` (dashed couple).
    label : str
        The text written next to it.
    anchor : tuple of float
        Fixed-frame position [m]: a point's place, a force's point of
        application, a coordinate's arc centre.
    direction : tuple of float or None
        Unit vector of a force as it acts at the state; None for a zero
        force and for items without a direction.
    turn : int
        +1 counter-clockwise, -1 clockwise, 0 none (couples, angle arcs).
    body : str or None
        The body it belongs to (``ground`` for the ground).
    name : str or None
        The scene's name: point, reaction, load or coordinate name.
    value : float or None
        The named quantity in ``unit``, signed as the solve gives it: a reaction as solved (on
        both bodies it acts on), a spring's or damper's tension, a couple's counter-clockwise
        moment; a size for a weight, an applied force vector and the inertial force. The label
        shows its size (:data:`CONVENTION`), the direction or turn its sense.
    unit : str
    shape : dict
        Geometry for the renderer (segment ends, radius, arc angles ...).
    """

    kind: str
    label: str
    anchor: tuple[float, float]
    direction: tuple[float, float] | None = None
    turn: int = 0
    body: str | None = None
    name: str | None = None
    value: float | None = None
    unit: str = ""
    shape: dict = field(default_factory=dict)


@dataclass
class Drawing:
    """A scene drawing (``fbd=False``) or its free-body diagrams (``fbd=True``).

    Attributes
    ----------
    scene : str
    items : list of DrawnItem
        The scene (bodies, points, guides, coordinates), or, for ``fbd``,
        every diagram's items (each with its ``body``).
    fbd : bool
    panels : list of str
        The bodies, one diagram each (``fbd``); empty for the scene drawing.
    point : dict
        Body -> the point P of its moment equation (``fbd``).
    figure : matplotlib.figure.Figure or None
    solution : solver.analyses.instant.InstantSolution or None
        The solve whose reactions the diagrams show (``fbd``).
    """

    scene: str
    items: list[DrawnItem]
    fbd: bool = False
    panels: list[str] = field(default_factory=list)
    point: dict = field(default_factory=dict)
    figure: object = None
    solution: object = None

    def of_kind(self, *kinds: str) -> list[DrawnItem]:
        return [i for i in self.items if i.kind in kinds]

    def on(self, body: str) -> list[DrawnItem]:
        """The items of one free-body diagram (or of one body in the scene)."""
        return [i for i in self.items if i.body == body]


# --------------------------------------------------------------------------- numbers
def _si(system, t: float | None = None) -> dict:
    """The substitution that turns a scene expression into a number: every parameter's SI value,
    and ``t`` [s] when given (a ground point may move with time)."""
    si = {k: sp.Float(v) for k, v in system.si_values().items()}
    if t is not None:
        si[system.t] = sp.Float(t)
    return si


def _constant(expr, si) -> float:
    """An expression of the parameters (and of ``t`` when ``si`` holds it) as a float."""
    value = sp.sympify(expr).xreplace(si)
    return float(value.evalf())


def _vec(m, si) -> np.ndarray:
    return np.array([_constant(m[0], si), _constant(m[1], si)])


def _rot(phi: float) -> np.ndarray:
    c, s = math.cos(phi), math.sin(phi)
    return np.array([[c, -s], [s, c]])


class PoseFunction:
    """Every body's placement (origin x, y and angle) as one compiled numpy function of (q, t)."""

    def __init__(self, system):
        values = system.si_values()
        self.params = sorted(values, key=str)
        self.param_values = [values[p] for p in self.params]
        self.bodies = list(system.bodies)
        exprs = []
        for name in self.bodies:
            origin, phi = system.poses[name]
            exprs += [origin[0], origin[1], phi]
        self._f = lambdify((*system.q, system.t, *self.params), exprs, "numpy", cse=True)

    def __call__(self, q, t) -> dict[str, tuple[np.ndarray, float]]:
        out = self._f(*q, t, *self.param_values)
        return {name: (np.array([float(out[3 * i]), float(out[3 * i + 1])]), float(out[3 * i + 2]))
                for i, name in enumerate(self.bodies)}


def _evaluate(system, exprs: list, state, accelerations: dict | None = None) -> list[float]:
    """Expressions in (q, q_dot, q_ddot, t, parameters) at a state, as floats: one walk of the trees
    in double precision (:func:`solver.tree_value.tree_value`, shared subtrees once), or one compiled
    call where a node is not one the walk knows (nan where a value is not a finite real number)."""
    values = system.si_values()
    params = sorted(values, key=str)
    qdd = [sp.Symbol(str(c.qdd), real=True) for c in system.free]
    args = (*system.q, *system.qd, *qdd, system.t, *params)
    acc = [float((accelerations or {}).get(str(c.qdd), 0.0)) for c in system.free]
    numbers = (*state.q, *state.qd, *acc, state.t, *[values[p] for p in params])
    exprs = [sp.sympify(e) for e in exprs]
    point, memo = {a: complex(float(v)) for a, v in zip(args, numbers)}, {}
    try:
        return [real_value(tree_value(e, point, DOUBLE, memo)) for e in exprs]
    except (NotEvaluable, KeyError, TypeError, ZeroDivisionError, OverflowError, ValueError):
        pass  # (numpy's answer instead: inf or nan where the walk stopped)
    f = lambdify(args, exprs, "numpy", cse=True)
    with np.errstate(all="ignore"):
        out = f(*numbers)
    return [float(v) for v in out]


def _memo(system, key, build):
    """Cached on the system (cleared with its other derived results by System.reset)."""
    return system._memo(("drawing", key), lambda: build(system))  # noqa: SLF001 - the system's own cache


# --------------------------------------------------------------------------- the bodies
@dataclass
class BodyShape:
    """The body-frame geometry of one body (constant), placed by its pose."""

    name: str
    points: dict  # name -> body-frame np.ndarray (and "G")
    instant: dict  # name -> (reference point, fixed-frame offset np.ndarray)
    elements: list  # (element, centre np.ndarray, angle float, dims {key: float})

    def position(self, point: str, pose) -> np.ndarray:
        origin, phi = pose
        if point in self.instant:
            ref, offset = self.instant[point]
            return self.position(ref, pose) + offset
        return origin + _rot(phi) @ self.points[point]


def body_shapes(system) -> dict[str, BodyShape]:
    """Body-frame points, instant points and elements of every body, evaluated once."""
    si = _si(system)
    out = {}
    for name, body in system.bodies.items():
        points, instant = {}, {}
        for pname, p in body.points.items():
            if p.is_instant:
                instant[pname] = (p.relative_to, _instant_offset(system, p, si))
            else:
                points[pname] = _vec(p.coords, si)
        if "G" not in points and "G" not in instant:
            points["G"] = _vec(body.mass_center(), si)
        elements = [(e, _vec(e.center, si), _constant(e.angle, si), {k: _constant(v, si) for k, v in e.dims.items()})
                    for e in body.elements]
        out[name] = BodyShape(name, points, instant, elements)
    return out


def _instant_offset(system, p, si) -> np.ndarray:
    """The fixed-frame offset of the instant point ``p`` from its reference point [m]: a constant, or,
    for one given as a function of the coordinates (a joint's point ``C_<joint>`` or a crossing of two
    lines of action ``I(R1,R2)``, as ``--point`` adds them),
    its value at the scene's state, where the worked solution takes moments about it."""
    coords = sp.Matrix(p.coords)
    if not coords.free_symbols & {*system.q, system.t}:
        return _vec(coords, si)
    from ..analyses.regimes import start_state

    state = start_state(system)
    at = {**si, **dict(zip(system.q, map(sp.Float, state.q))), system.t: sp.Float(state.t)}
    return _vec(coords, at)


def _element_item(body: str, element, centre, angle, dims, pose) -> DrawnItem:
    origin, phi = pose
    c = origin + _rot(phi) @ centre
    a = phi + angle
    axis = np.array([math.cos(a), math.sin(a)])
    kind = element.kind
    if kind == "slender_bar":
        half = dims["length"] / 2 * axis
        shape = {"type": "bar", "ends": ((c - half).tolist(), (c + half).tolist())}
    elif kind in ("uniform_disk", "thin_ring"):
        shape = {"type": "disk" if kind == "uniform_disk" else "ring", "centre": c.tolist(), "radius": dims["radius"]}
    elif kind == "rectangular_plate":
        shape = {"type": "plate", "centre": c.tolist(), "width": dims["width"], "height": dims["height"],
                 "angle": a}
    elif kind == "semicircular_disk":
        shape = {"type": "half_disk", "centre": c.tolist(), "radius": dims["radius"], "angle": a}
    elif kind == "point_mass":
        shape = {"type": "dot", "centre": c.tolist()}
    else:  # gyration / centroidal inertia: a rim when it has a radius, else a small marker circle
        shape = {"type": "rim" if "radius" in dims else "marker", "centre": c.tolist(),
                 "radius": dims.get("radius", 0.0)}
    return DrawnItem("element", element.name, tuple(c.tolist()), body=body, name=element.name, shape=shape)


_EXTENDED = ("slender_bar", "uniform_disk", "thin_ring", "rectangular_plate", "semicircular_disk")


def _light_link(body: str, shape: BodyShape, pose) -> DrawnItem | None:
    """A body of point masses only (a bob on a light rod): a thin line through its named points."""
    if any(e.kind in _EXTENDED or "radius" in dims for e, _, _, dims in shape.elements):
        return None
    names = [p for p in shape.points if p != "G"]
    if len(names) < 2:
        return None
    path = [shape.position(p, pose).tolist() for p in names]
    return DrawnItem("link", f"{body} (light link)", tuple(path[0]), body=body, name=body,
                     shape={"type": "polyline", "points": path})


def _scale(system, shapes, poses, t: float) -> tuple[np.ndarray, np.ndarray]:
    """Bounding box (low, high) of every point and element of the scene at time ``t`` [m]."""
    pts = [np.asarray(_ground_point(system, n, t)) for n in system.ground.points]
    for name, shape in shapes.items():
        for p in list(shape.points) + list(shape.instant):
            pts.append(shape.position(p, poses[name]))
        for e, centre, angle, dims in shape.elements:
            c = poses[name][0] + _rot(poses[name][1]) @ centre
            r = max([dims.get("radius", 0.0), dims.get("length", 0.0) / 2,
                     math.hypot(dims.get("width", 0.0), dims.get("height", 0.0)) / 2])
            pts += [c - r, c + r]
    pts = np.array(pts) if pts else np.zeros((1, 2))
    return pts.min(axis=0), pts.max(axis=0)


def _ground_point(system, name, t: float) -> list[float]:
    """Where a ground point is at time ``t`` [s] (a ground point's path may be a function of t)."""
    return _vec(system.ground.points[name].coords, _si(system, t)).tolist()


# --------------------------------------------------------------------------- the scene
def scene_items(system, state, poses=None, shapes=None) -> list[DrawnItem]:
    """Everything the scene drawing shows at ``state`` (a complete State).

    Bodies by their elements, every named point of every body (and G) and of
    the ground, the guides of the joints (rails, sliders and rolling lines as
    hatched lines, circles of rolling on a circle, fixed pins as supports,
    cords as lines), the linear springs and dampers between their two points, the
    torsional ones about the pin joining their bodies, and every free coordinate: an arc for an angle, a dimension line for a length.
    """
    shapes = shapes or _memo(system, "shapes", body_shapes)
    poses = poses or _memo(system, "poses", PoseFunction)(state.q, state.t)
    items: list[DrawnItem] = []
    for name, shape in shapes.items():
        for e, centre, angle, dims in shape.elements:
            items.append(_element_item(name, e, centre, angle, dims, poses[name]))
        link = _light_link(name, shape, poses[name])
        if link is not None:
            items.append(link)
    for name, shape in shapes.items():
        for p in list(shape.points) + list(shape.instant):
            pos = shape.position(p, poses[name])
            items.append(DrawnItem("point", point_label(p, name, shapes), tuple(pos.tolist()), body=name, name=p))
    for p in system.ground.points:
        items.append(DrawnItem("point", p, tuple(_ground_point(system, p, state.t)), body=GROUND, name=p))
    low, high = _scale(system, shapes, poses, state.t)
    items += _guides(system, shapes, poses, low, high, state.t)
    items += _connectors(system, shapes, poses, state.t)
    items += _coordinates(system, state, shapes, poses, float(np.max(high - low)) or 1.0)
    return items


def point_label(point: str, body: str, shapes) -> str:
    """A point's label on the scene drawing: its name, but a mass centre's ``G_<body>`` when there
    are several bodies (each has its G; two "G" side by side do not say whose is whose)."""
    return f"G_{body}" if point == "G" and len(shapes) > 1 else point


def _pose_of(poses, body):
    return (np.zeros(2), 0.0) if body == GROUND else poses[body]


def _at(system, poses, body, coords, t: float) -> np.ndarray:
    """Fixed-frame place of a point given by its coordinates in ``body``'s frame, at time ``t``."""
    origin, phi = _pose_of(poses, body)
    return origin + _rot(phi) @ _vec(coords, _si(system, t))


def _guides(system, shapes, poses, low, high, t: float) -> list[DrawnItem]:
    from ..model import joints as J

    si = _si(system, t)
    span = float(np.max(high - low)) or 1.0
    items = []
    for j in system.joints:
        first_phi = _pose_of(poses, j.first)[1]
        if isinstance(j, (J.Rail, J.Rolling, J.Actuator)):  # Rail covers PinInSlot and Slider
            o = _at(system, poses, j.first, j.through, t)
            a = first_phi + _constant(j.angle, si)
            d = np.array([math.cos(a), math.sin(a)])
            n = np.array([-d[1], d[0]])
            # the line across the whole scene: from the projections of the box's corners
            corners = [np.array([x, y]) for x in (low[0], high[0]) for y in (low[1], high[1])]
            s = [float(d @ (c - o)) for c in corners]
            ends = (o + (min(s) - 0.15 * span) * d, o + (max(s) + 0.15 * span) * d)
            kind = "rolling line" if isinstance(j, J.Rolling) else ("actuator" if isinstance(j, J.Actuator) else j.kind)
            items.append(DrawnItem("guide", f"{j.name} ({kind})", tuple(o.tolist()), tuple(d.tolist()),
                                   body=j.first, name=j.name,
                                   shape={"type": "line", "ends": (ends[0].tolist(), ends[1].tolist()),
                                          "hatch": (-n).tolist(), "dashed": isinstance(j, J.Actuator)}))
        elif isinstance(j, J.RollingOnCircle):
            O = _at(system, poses, j.first, j.circle_center, t)
            R = _constant(j.circle_radius, si)
            items.append(DrawnItem("guide", f"{j.name} (rolling on a circle)", tuple(O.tolist()), body=j.first,
                                   name=j.name, shape={"type": "circle", "centre": O.tolist(), "radius": R,
                                                       "hatch_inside": not j.inside}))
        elif isinstance(j, J.Pin) and GROUND in j.bodies:
            at = _at(system, poses, GROUND, j.at_first if j.first == GROUND else j.at_second, t)
            items.append(DrawnItem("support", f"{j.name} (pin)", tuple(at.tolist()), body=GROUND, name=j.name,
                                   shape={"type": "pin_support", "size": 0.06 * span}))
        elif isinstance(j, J.Cord):
            tangent = j.tangent_point(lambda b: _sym_pose(system, poses, b))
            start = np.array([float(v) for v in tangent.xreplace(si)])
            end = _at(system, poses, j.second, j.point, t)
            items.append(DrawnItem("guide", f"{j.name} (cord)", tuple(start.tolist()), body=j.first, name=j.name,
                                   shape={"type": "cord", "ends": (start.tolist(), end.tolist())}))
    return items


def _connectors(system, shapes, poses, t: float) -> list[DrawnItem]:
    """Each linear spring (a zigzag) and damper (a dashpot) between its two points.

    Several between the same two points are drawn side by side, as in parallel: ``shape["lane"]``
    is each one's place across the line joining the points (0 for a single one, then -0.5, 0.5
    for two ...), in lanes (:func:`solver.drawing.render.connector_paths`).
    """
    def place(body, point):
        if body == GROUND:
            return np.array(_ground_point(system, point, t))
        return shapes[body].position(point, poses[body])

    loads = [load for load in system.loads if load.kind in ("spring", "damper")]
    pairs = [frozenset((tuple(load.a), tuple(load.b))) for load in loads]
    items = []
    for load, pair in zip(loads, pairs):
        same = [other for other, p in zip(loads, pairs) if p == pair]
        lane = same.index(load) - (len(same) - 1) / 2
        a, b = place(*load.a), place(*load.b)
        body = next((name for name, _ in (load.a, load.b) if name != GROUND), GROUND)
        items.append(DrawnItem(load.kind, load.name, tuple(((a + b) / 2).tolist()), body=body, name=load.name,
                               shape={"type": load.kind, "ends": (a.tolist(), b.tolist()), "lane": lane}))
    return items + _torsional(system, shapes, poses, t)


def _torsional(system, shapes, poses, t: float) -> list[DrawnItem]:
    """Each torsional spring (a spiral) and damper (a rotary dashpot) about the pin joining its two
    bodies, or about the moving body's G when no pin joins them. Several about one place are drawn
    one outside another: ``shape["lane"]`` counts them from the inside (0, 1, ...)."""
    from ..model import joints as J

    loads = [load for load in system.loads if load.kind in ("torsional_spring", "torsional_damper")]
    items: list[DrawnItem] = []
    for load in loads:
        pair = {load.first, load.second}
        pin = next((j for j in system.joints if isinstance(j, J.Pin) and set(j.bodies) == pair), None)
        body = load.second if load.second != GROUND else load.first
        if pin is not None:
            centre = _at(system, poses, pin.first, pin.at_first, t)
        elif "G" in shapes[body].points:
            centre = shapes[body].position("G", poses[body])
        else:
            centre = poses[body][0]
        lane = sum(1 for i in items if math.dist(i.anchor, centre) < 1e-9)
        items.append(DrawnItem(load.kind, load.name, tuple(np.asarray(centre, float).tolist()), body=body,
                               name=load.name, shape={"type": load.kind, "centre": list(map(float, centre)),
                                                      "lane": lane}))
    return items


def _sym_pose(system, poses, body):
    origin, phi = _pose_of(poses, body)
    return sp.Matrix([origin[0], origin[1]]), sp.Float(phi)


def _coordinates(system, state, shapes, poses, span) -> list[DrawnItem]:
    """An arc for each free angle coordinate, a dimension line for each length coordinate."""
    items = []
    si = _si(system, state.t)
    driven = [(c, _constant(c.motion, si)) for c in system.coordinates if c.prescribed]
    for c, value in [*zip(system.free, state.q), *driven]:
        item = (_angle_mark(system, c, value, shapes, poses, span) if c.kind == "angle"
                else _length_mark(system, c, value, shapes, poses))
        if item is None:  # no body turns (or moves) with it alone: its value is written instead
            body = next(iter(shapes))
            where = shapes[body].position("G", poses[body]) if "G" in shapes[body].points else poses[body][0]
            shown = f"{figures_text(math.degrees(value))} deg" if c.kind == "angle" else f"{figures_text(value)} m"
            item = DrawnItem("coordinate", typeset_text(f"{_mark_name(c)} = {shown}"), tuple(where.tolist()), name=c.name,
                             value=math.degrees(value) if c.kind == "angle" else value,
                             unit="deg" if c.kind == "angle" else "m", shape={"type": "text"})
        items.append(item)
    return items


def _mark_name(c) -> str:
    """A coordinate's label: its name as the paper writes it (theta as θ), said to be prescribed
    when it is (a motor drives it)."""
    name = typeset_text(c.name)
    return f"{name} (prescribed)" if c.prescribed else name


def _turns_with(system, body: str, c):
    """d phi_body / d c: +-1 when the body turns with the coordinate alone (for a prescribed one,
    when its angle changes as the motion does), else something else."""
    if not c.prescribed:
        return sp.diff(system.angle(body), c.q)
    speed = sp.diff(c.motion, system.t)
    return sp.cancel(sp.diff(system.angle(body), system.t) / speed) if speed != 0 else sp.nan


ARC_LENGTH = 0.08
"""Least length of a coordinate's arc, as a fraction of the scene's span (about 3 arrowheads)."""


def _angle_mark(system, c, value, shapes, poses, span):
    for name, body in system.bodies.items():
        rate = _turns_with(system, name, c)
        if rate not in (1, -1):
            continue
        shape = shapes[name]
        # measured from the body's first bar (its axis) when it has one, else from its reference point
        bar = next(((e, ctr, ang, dims) for e, ctr, ang, dims in shape.elements if e.kind == "slender_bar"), None)
        origin, phi = poses[name]
        if bar is not None:
            e, ctr, ang, dims = bar
            centre = origin + _rot(phi) @ (ctr - dims["length"] / 2 * np.array([math.cos(ang), math.sin(ang)]))
            axis = ang
        else:
            centre = shape.position(body.default_point, poses[name]) if body.default_point in shape.points \
                else origin
            axis = 0.0
        end = phi + axis
        start = end - int(rate) * value
        # a small angle's arc drawn further out, so that it is longer than its arrowhead (QA10: theta's
        # 10 deg arc at 0.16 span was all head, on the bar), within the bar and 0.4 span
        longest = min(0.4 * span, 0.9 * dims["length"]) if bar is not None else 0.4 * span
        radius = min(max(0.16 * span, ARC_LENGTH * span / max(abs(end - start), 1e-9)), max(longest, 0.16 * span))
        arc = {"type": "arc", "centre": centre.tolist(), "radius": radius, "start": start, "end": end}
        rim = _round_rim(shape, poses[name], centre) if bar is None else None
        if rim is not None:  # a disk turns: a radius drawn on it shows the turn, the arc inside its rim
            others = [disk for other in shapes if other != name for disk in _round_parts(shapes[other], poses[other])]
            arc.update(radius=min(radius, RIM_ARC * rim), rim=rim,
                       label_at=_clear_place(centre, rim + LABEL_GAP * span, 0.5 * (start + end), others,
                                             LABEL_GAP * span).tolist())
        return DrawnItem("coordinate", _mark_name(c), tuple(centre.tolist()), turn=1 if end >= start else -1, body=name,
                         name=c.name, value=math.degrees(value), unit="deg", shape=arc)
    return None


RIM_ARC = 0.7
"""A disk's angle arc is drawn at this fraction of its radius, inside the disk (not over its neighbours)."""
LABEL_GAP = 0.06
"""How far outside a disk's rim its angle's label is set, as a fraction of the scene's span (about
the label's half width), and the least room it leaves to another body's rim."""


def _round_parts(shape, pose):
    """(centre, radius) of each round element of a body (disk, ring, half disk) at the pose."""
    origin, phi = pose
    return [(origin + _rot(phi) @ ctr, dims["radius"]) for e, ctr, ang, dims in shape.elements if "radius" in dims]


def _round_rim(shape, pose, centre):
    """The radius of the body's largest round element centred at ``centre`` (the point its angle is
    marked about), or None when it has none."""
    radii = [r for c, r in _round_parts(shape, pose) if np.linalg.norm(c - centre) <= 1e-9 * (1 + r)]
    return max(radii) if radii else None


def _clear_place(centre, distance: float, toward: float, others, gap: float):
    """A point ``distance`` from ``centre``, in the direction ``toward`` or the nearest to it in steps of
    30 degrees (counter-clockwise first) that is at least ``gap`` outside every circle of ``others``
    ((centre, radius) pairs); ``toward`` itself when none is."""
    for k in (0, 1, -1, 2, -2, 3, -3, 4, -4, 5, -5, 6):
        a = toward + k * math.pi / 6
        p = centre + distance * np.array([math.cos(a), math.sin(a)])
        if all(np.linalg.norm(p - c) >= r + gap for c, r in others):
            return p
    return centre + distance * np.array([math.cos(toward), math.sin(toward)])


def _length_mark(system, c, value, shapes, poses):
    for name, body in system.bodies.items():
        if sp.diff(system.angle(name), c.q) != 0:
            continue
        u = sp.diff(system.origin(name), c.q)
        if any(s in u.free_symbols for s in (*system.q, system.t)) or u == sp.zeros(2, 1):
            continue
        u = _vec(u, _si(system))
        point = body.default_point if body.default_point in shapes[name].points else "G"
        tip = shapes[name].position(point, poses[name])
        base = tip - value * u
        return DrawnItem("coordinate", c.name, tuple(base.tolist()), direction=None, body=name, name=c.name,
                         value=value, unit="m", shape={"type": "dimension", "ends": (base.tolist(), tip.tolist())})
    return None


# --------------------------------------------------------------------------- free-body diagrams
def free_body_items(system, state, solution, points: dict[str, str]) -> list[DrawnItem]:
    """Every force and couple on every body at the state, and the inertial terms about ``points``.

    Parameters
    ----------
    system : solver.model.system.System
    state : solver.analyses.instant.State
        Complete state (the solution's).
    solution : solver.analyses.instant.InstantSolution
        Solved accelerations and reactions at ``state``.
    points : dict
        Body -> the point P of its moment equation (solver.formulations.resolve_points).
    """
    fb = _FreeBodies(system, state, solution)
    joint_loads = [(jl, fb.pair(jl.force), fb.pair(jl.at), fb.slot(jl.couple)) for jl in system.joint_loads()]
    applied = [(load, a, fb.pair(None if a.force is None else system.prescribe(sp.Matrix(a.force))), fb.pair(a.at),
                fb.slot(system.prescribe(sp.sympify(a.couple))), fb.pair(_other_end(system, load, a)))
               for load in system.loads for a in load.applied(system)]
    motion = {body: system.point_kinematics(body, p) for body, p in points.items()}  # as the worked solution
    inertial = {body: (fb.pair(motion[body][2]), fb.slot(system.alpha(body)), fb.pair(motion[body][0]))
                for body in points}
    fb.evaluate()
    items = _reaction_items(fb, joint_loads) + _load_items(fb, applied) + _inertial_items(fb, inertial, points)
    return _mark_zeros(items)


def _other_end(system, load, applied):
    """A spring's or damper's far end (fixed-frame position) from the point ``applied`` acts at; else None."""
    if load.kind not in ("spring", "damper") or applied.point is None:
        return None
    other = load.b if applied.point == tuple(load.a) else load.a
    return system.prescribe(system.point_position(*other))


class _FreeBodies:
    """What the free-body diagrams share: units, solved values, placement, and every symbolic
    quantity they need, collected by :meth:`slot` and evaluated in one compiled call."""

    def __init__(self, system, state, solution):
        self.system, self.state = system, state
        from ..output_units import output_unit

        self.force_unit = output_unit("N", system.output_units)  # the scene's [output_units]
        self.moment_unit = output_unit("N*m", system.output_units)
        self.solved = {name: float(q.to_base_units().magnitude) for name, q in solution.unknowns.items()}
        self.shapes = _memo(system, "shapes", body_shapes)
        self.poses = _memo(system, "poses", PoseFunction)(state.q, state.t)
        self.si = _si(system, state.t)
        self.exprs: list = []
        self.vals: list[float] = []

    def slot(self, expr) -> int:
        self.exprs.append(expr)
        return len(self.exprs) - 1

    def pair(self, vector):
        return None if vector is None else (self.slot(vector[0]), self.slot(vector[1]))

    def evaluate(self) -> None:
        accelerations = {k: v for k, v in self.solved.items() if k.endswith("_ddot")}
        self.vals = _evaluate(self.system, self.exprs, self.state, accelerations)

    def vec(self, pair) -> np.ndarray:
        return np.array([self.vals[pair[0]], self.vals[pair[1]]])

    def force(self, newtons: float) -> float:
        from ..units import Q_

        return float(Q_(newtons, "N").to(self.force_unit).magnitude)

    def moment(self, newton_metres: float) -> float:
        from ..units import Q_

        return float(Q_(newton_metres, "N*m").to(self.moment_unit).magnitude)

    def where(self, body: str, point: str) -> np.ndarray:
        """A body point's position (or the body frame's origin when the body has no such point)."""
        shape = self.shapes[body]
        return shape.position(point, self.poses[body]) if point in shape.points else self.poses[body][0]

    def mass_centre(self, body: str) -> np.ndarray:
        return _mass_centre(self.system, self.shapes, self.poses, body)


def _reaction_items(fb: _FreeBodies, joint_loads) -> list[DrawnItem]:
    """Each reaction on each body it acts on, by its name and solved value (the joint's direction
    on its first body is the opposite of that on its second, so the arrows are opposite)."""
    items = []
    for jl, f, at, c in joint_loads:
        body, r = jl.body, jl.reaction
        if body == GROUND:  # the ground has no diagram
            continue
        value = fb.solved[r.name]
        if f is not None:  # the force on this body: value times the joint's direction on it
            unit_vec = fb.vec(f)
            items.append(_force("force", r.name, fb.vec(at), value * unit_vec, unit_vec, body, r.name,
                                fb.force(value), fb.force_unit))
        else:  # a couple (slider, motor), drawn at the body's reference point
            items.append(_couple("couple", r.name, fb.where(body, fb.system.bodies[body].default_point),
                                 value * fb.vals[c], body, r.name, fb.moment(value), fb.moment_unit))
    return items


def _load_items(fb: _FreeBodies, applied) -> list[DrawnItem]:
    """Applied forces and couples (springs, dampers too); each body's weight as one force at G.

    ``applied`` holds (load, applied load, force slots, place slots, couple slot, the other end's
    place slots for a spring or damper, else None)."""
    items, weights = [], {}
    for load, a, f, at, c, other in applied:
        if a.body not in fb.system.bodies:  # the ground's share of a spring or damper
            continue
        if load.kind == "gravity":  # the resultant of the elements' weights acts at G
            weights[(a.body, load.name)] = weights.get((a.body, load.name), np.zeros(2)) + fb.vec(f)
            continue
        if f is not None:
            vec, where = fb.vec(f), fb.vec(at)
            size = float(np.hypot(*vec))
            if other is not None:  # a spring or damper: its tension, positive when it pulls towards the other end
                size = math.copysign(size, float(vec @ (fb.vec(other) - where)))
            items.append(_force("force", a.name, where, vec, None, a.body, load.name, fb.force(size), fb.force_unit))
        if a.force is None or sp.sympify(a.couple) != 0:
            m = fb.vals[c]
            items.append(_couple("couple", a.name, fb.where(a.body, "G"), m, a.body, load.name, fb.moment(m),
                                 fb.moment_unit))
    for (body, name), vec in weights.items():
        items.append(_force("force", f"{name}: m g", fb.mass_centre(body), vec, None, body, name,
                            fb.force(float(np.hypot(*vec))), fb.force_unit))
    return [DrawnItem(i.kind, i.label, i.anchor, i.direction, i.turn, i.body, i.name, i.value, i.unit,
                      {**i.shape, "given": True}) for i in items]  # exact: no round-off for _mark_zeros to clear


def _inertial_items(fb: _FreeBodies, inertial, points) -> list[DrawnItem]:
    """Eq. (10): the inertial force -m a_P at G and the couple -I_P alpha, for each body's P."""
    items = []
    for body, (acc, alpha, at) in inertial.items():
        p = points[body]
        m = _constant(fb.system.bodies[body].total_mass, fb.si)
        vec = -m * fb.vec(acc)
        G = fb.mass_centre(body)
        items.append(_force("inertial", f"-m a_{p}", G, vec, None, body, f"-m a_{p}",
                            fb.force(float(np.hypot(*vec))), fb.force_unit))
        # Eq. (12): I_P = I_G + m |r_G/P|^2, P where the point is at this instant
        I_P = _constant(fb.system.bodies[body].centroidal_inertia(), fb.si) + m * float(np.sum((G - fb.vec(at)) ** 2))
        moment = -I_P * fb.vals[alpha]
        items.append(_couple("inertial_couple", f"-I_{p} alpha", G, moment, body, f"-I_{p} alpha",
                             fb.moment(moment), fb.moment_unit))
    return items


def _mass_centre(system, shapes, poses, body) -> np.ndarray:
    origin, phi = poses[body]
    return origin + _rot(phi) @ _vec(system.bodies[body].mass_center(), _si(system))


def _force(kind, label, at, vec, positive, body, name, value, unit) -> DrawnItem:
    size = float(np.hypot(*vec))
    direction = tuple((vec / size).tolist()) if size > 0 else None
    shape = {"size": size}
    if positive is not None:  # a reaction: its positive sense (a zero one is drawn as a label, not along it)
        shape["positive"] = tuple((positive / (float(np.hypot(*positive)) or 1.0)).tolist())
    return DrawnItem(kind, label, tuple(float(x) for x in at), direction, body=body, name=name, value=value,
                     unit=unit, shape=shape)


def _couple(kind, label, at, moment, body, name, value, unit) -> DrawnItem:
    turn = 1 if moment > 0 else (-1 if moment < 0 else 0)
    return DrawnItem(kind, label, tuple(float(x) for x in at), turn=turn, body=body, name=name, value=value,
                     unit=unit, shape={"size": abs(float(moment))})


def size_label(name: str, value: float, unit: str) -> str:
    """The label of a drawn force or couple under :data:`CONVENTION`: ``|name| = size unit``, the
    size to 4 significant figures (:func:`figures_text`), in the paper's notation
    (:func:`solver.notation.typeset_text`: -I_A alpha as −I_A α).

    Examples
    --------
    >>> size_label("O_x", -6.7716, "N")
    '|O_x| = 6.772 N'
    >>> size_label("gravity: m g", 19.62, "N")
    'gravity: |m g| = 19.62 N'
    >>> size_label("M", 2.5, "N*m")
    '|M| = 2.500 N\u00b7m'
    >>> size_label("-I_A alpha", -19.5, "N*m") == "|\u2212I_A \u03b1| = 19.50 N\u00b7m"
    True
    """
    head, sep, symbol = name.rpartition(": ")
    unit = unit.replace("*", "\u00b7")  # a product of units as N·m, not code's N*m
    return typeset_text(f"{head}{sep}|{symbol}| = {figures_text(abs(value))} {unit}")


def figures_text(value: float, digits: int = 4) -> str:
    """``value`` to ``digits`` significant figures with its trailing zeros: 19.50, not the 19.5 of
    ``f"{value:.4g}"`` (the ``g`` format drops them, so one label showed 3 figures beside others'
    4); a whole number without a trailing point (1235, not 1235.); zero as 0.

    >>> figures_text(19.5), figures_text(1234.5), figures_text(0.0), figures_text(123456.0)
    ('19.50', '1234', '0', '1.235e+05')
    """
    if value == 0:
        return "0"
    mantissa, e, exponent = f"{value:#.{digits}g}".partition("e")
    return mantissa.rstrip(".") + e + exponent


def _mark_zeros(items: list[DrawnItem]) -> list[DrawnItem]:
    """Solved forces (couples) below ZERO_FORCE of the largest force (couple) on the same body lose
    their direction: round-off of the solve. A load the scene gives (a weight, an applied force, a
    spring's) is exact: it keeps its size and its arrow, of the one length every arrow has, however
    large the others (disk_bar's weight, 53.94 N, beside 1e99 N at theta_dot = 1e50 rad/s)."""
    out = []
    for item in items:
        group = ("couple", "inertial_couple") if item.kind in ("couple", "inertial_couple") else ("force", "inertial")
        same = [i.shape["size"] for i in items if i.body == item.body and i.kind in group]
        biggest = max(same) if same else 0.0
        size = item.shape.get("size", 0.0)
        zero = size == 0 if item.shape.get("given") else size <= ZERO_FORCE * biggest
        value = 0.0 if zero else item.value
        label = size_label(item.label, value, item.unit)
        out.append(DrawnItem(item.kind, label, item.anchor, None if zero else item.direction, 0 if zero else item.turn,
                             item.body, item.name, value, item.unit, {**item.shape, "zero": zero}))
    return out
