"""Matplotlib rendering of a :class:`~solver.drawing.model.Drawing` (Agg, no pyplot).

Bodies: bars as thick segments, disks as filled circles, rings as hollow
circles, plates as rectangles, semicircular disks as half discs, point masses
as dots, elements given by an inertia as a small circle (or their rim).
Guides are lines or circles hatched on the side of the ground; linear springs are zigzags and
dampers dashpots (a cylinder and a piston) between their two points; torsional springs are
spirals and torsional dampers rotary dashpots about the pin joining their bodies. Forces are
arrows of one length starting at their point of application (the label gives
the size), couples curved arrows; the inertial terms are dashed. A couple's arc is drawn clear of
the force arrows (:func:`_couple_places`). Labels are placed last (:func:`place_labels`): off each
other, the arrows and the lines (a bar's stroke with its width), and each nearer the arrow or arc it
names than any other.
"""
from __future__ import annotations

import math
from functools import lru_cache

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402
from matplotlib.patches import Circle, FancyArrowPatch, Polygon, Rectangle, Wedge  # noqa: E402

from .layout import MeasuredLayout, agg_renderer, fix_layout  # noqa: E402
from ..notation import typeset_text  # noqa: E402
from .model import CONVENTION, DrawnItem  # noqa: E402

__all__ = ["new_figure", "render_scene", "render_fbd", "place_labels", "label_boxes", "fix_layout", "RC",
           "connector_paths"]

RC = {"svg.hashsalt": "alt-euler-drawing", "svg.fonttype": "none", "font.size": 8}
"""Deterministic SVG (fixed ids, text kept as text)."""

BODY_COLOURS = ["#1f5fa8", "#b5521b", "#2e7d32", "#7b1fa2", "#00838f", "#8d6e00"]
FORCE_COLOUR = "#c62828"
INERTIAL_COLOUR = "#6a1b9a"


def new_figure(panels: int = 1, size: float = 4.2) -> tuple[Figure, list]:
    """A figure with ``panels`` square axes side by side (at most 3 a row)."""
    cols = min(panels, 3)
    rows = math.ceil(panels / cols)
    fig = Figure(figsize=(size * cols, size * rows), layout=MeasuredLayout())
    axes = fig.subplots(rows, cols, squeeze=False).ravel().tolist()
    for ax in axes[panels:]:
        ax.set_visible(False)
    return fig, axes[:panels]


def _span(items: list[DrawnItem]) -> tuple[np.ndarray, np.ndarray, float]:
    pts = []
    for i in items:
        if i.kind == "link":
            pts += list(i.shape["points"])
        if i.kind in ("element", "point", "support"):
            pts.append(i.anchor)
            r = i.shape.get("radius", 0.0) or 0.0
            for end in i.shape.get("ends", ()):
                pts.append(end)
            if r:
                pts += [(i.anchor[0] - r, i.anchor[1] - r), (i.anchor[0] + r, i.anchor[1] + r)]
            w = max(i.shape.get("width", 0.0), i.shape.get("height", 0.0))
            if w:
                pts += [(i.anchor[0] - w, i.anchor[1] - w), (i.anchor[0] + w, i.anchor[1] + w)]
    pts = np.array(pts) if pts else np.zeros((1, 2))
    low, high = pts.min(axis=0), pts.max(axis=0)
    return low, high, float(np.max(high - low)) or 1.0


def _setup(ax, low, high, span, title):
    pad = 0.35 * span
    ax.set_xlim(low[0] - pad, high[0] + pad)
    ax.set_ylim(low[1] - pad, high[1] + pad)
    ax.set_aspect("equal", adjustable="box")
    ax.set_xticks([])
    ax.set_yticks([])
    for side in ax.spines.values():
        side.set_visible(False)
    ax.patch.set_visible(False)  # no background: a label running past the panel stays readable over its neighbour
    if title:
        ax.set_title(title.replace("$", r"\$"), fontsize=9)  # a scene name is text, never mathtext


def _add_patch(ax, patch) -> None:
    """Add a patch to ``ax`` as ``add_patch`` does, without growing the data limits by it: every
    drawing sets its limits itself (:func:`_setup`), and measuring each patch for them (building
    an arrow's whole path) took about a third of the time of drawing the shapes."""
    ax.add_artist(patch)


def _colour(body, bodies):
    return BODY_COLOURS[bodies.index(body) % len(BODY_COLOURS)] if body in bodies else "0.3"


def _element(ax, item: DrawnItem, colour, faint=False):
    s = item.shape
    alpha = 0.35 if faint else 1.0
    t = s["type"]
    if t == "bar":
        (x0, y0), (x1, y1) = s["ends"]
        ax.plot([x0, x1], [y0, y1], color=colour, linewidth=5, solid_capstyle="round", alpha=alpha, zorder=2)
    elif t in ("disk", "ring", "rim"):
        _add_patch(ax, Circle(s["centre"], s["radius"], facecolor=colour if t == "disk" else "none",
                            edgecolor=colour, linewidth=2.5, alpha=(0.3 if t == "disk" else 1.0) * alpha, zorder=1))
    elif t == "plate":
        w, h, a = s["width"], s["height"], s["angle"]
        c = np.array(s["centre"])
        corner = c - 0.5 * (w * np.array([math.cos(a), math.sin(a)]) + h * np.array([-math.sin(a), math.cos(a)]))
        _add_patch(ax, Rectangle(corner.tolist(), w, h, angle=math.degrees(a), facecolor=colour, edgecolor=colour,
                               alpha=0.35 * alpha, linewidth=2, zorder=1))
    elif t == "half_disk":
        a = math.degrees(s["angle"])
        _add_patch(ax, Wedge(s["centre"], s["radius"], a - 90, a + 90, facecolor=colour, edgecolor=colour,
                           alpha=0.35 * alpha, linewidth=2, zorder=1))
    elif t == "dot":
        ax.plot(*s["centre"], "o", color=colour, markersize=9, alpha=alpha, zorder=3)
    else:  # marker: a body given by its inertia only
        ax.plot(*s["centre"], "o", markerfacecolor="none", markeredgecolor=colour, markersize=12, alpha=alpha, zorder=3)


def _hatch_line(ax, ends, hatch, span, dashed=False):
    (x0, y0), (x1, y1) = ends
    ax.plot([x0, x1], [y0, y1], color="0.2", linewidth=1.2, linestyle="--" if dashed else "-", zorder=0)
    if dashed:
        return
    a, b = np.array(ends[0]), np.array(ends[1])
    h = np.array(hatch) * 0.035 * span
    along = (b - a) / (np.linalg.norm(b - a) or 1.0)
    starts = a + np.linspace(0, 1, 28)[:, None] * (b - a)
    ends = starts + h - 0.6 * np.linalg.norm(h) * along
    ax.add_collection(LineCollection(np.stack([starts, ends], axis=1), colors="0.45", linewidths=0.7, zorder=0))


def _hatch_circle(ax, centre, radius, inside, span):
    _add_patch(ax, Circle(centre, radius, facecolor="none", edgecolor="0.2", linewidth=1.2, zorder=0))
    d = 0.035 * span * (-1 if inside else 1)
    a = np.linspace(0, 2 * math.pi, 40, endpoint=False)
    u = np.stack([np.cos(a), np.sin(a)], axis=1)
    starts = np.array(centre) + radius * u
    ends = starts + d * u + 0.02 * span * np.stack([-u[:, 1], u[:, 0]], axis=1)
    ax.add_collection(LineCollection(np.stack([starts, ends], axis=1), colors="0.45", linewidths=0.7, zorder=0))


def _support(ax, item, span):
    x, y = item.anchor
    s = item.shape.get("size", 0.05 * span)
    _add_patch(ax, Polygon([(x, y), (x - 0.6 * s, y - s), (x + 0.6 * s, y - s)], closed=True, facecolor="0.85",
                         edgecolor="0.2", linewidth=1, zorder=0))
    _hatch_line(ax, ((x - 0.9 * s, y - s), (x + 0.9 * s, y - s)), (0, -0.4), s * 3)


def _arc(ax, centre, radius, start, end, colour, label, dashed=False, arrow=True, label_at=None):
    ts = np.linspace(start, end, 40)
    xs = centre[0] + radius * np.cos(ts)
    ys = centre[1] + radius * np.sin(ts)
    drawn = ax.plot(xs[:-1], ys[:-1], color=colour, linewidth=1.2, linestyle="--" if dashed else "-", zorder=4)
    if arrow:
        head = FancyArrowPatch((xs[-3], ys[-3]), (xs[-1], ys[-1]), arrowstyle="-|>", mutation_scale=10,
                               color=colour, linewidth=1.2, zorder=4)
        _add_patch(ax, head)
        drawn.append(head)
    mid = 0.5 * (start + end)
    out = 1.2 if abs(end - start) > 0.6 else 1.6  # a short arc: its label further out, clear of the lines
    at = label_at or (centre[0] + out * radius * math.cos(mid), centre[1] + out * radius * math.sin(mid))
    text = ax.annotate(label, tuple(at),
                       xytext=(0, 0), textcoords="offset points", fontsize=7, color=colour, ha="center",
                       va="center", zorder=6)
    _label_of(text, drawn)
    return text


CONNECTOR_WIDTH = 0.03
"""Half the width of a drawn spring's zigzag or damper's cylinder, as a fraction of the scene's span."""


def connector_paths(kind: str, a, b, width: float, lane: float = 0.0) -> list[np.ndarray]:
    """The polylines of a spring (``kind="spring"``: a zigzag) or a damper (a dashpot) from ``a`` to ``b``.

    Parameters
    ----------
    kind : str
        ``spring`` or ``damper``.
    a, b : array-like
        The two points [m].
    width : float
        Half the symbol's width [m].
    lane : float
        Its place across the line a-b, in lanes ``3.5 * width`` apart: several between
        the same points are drawn side by side, joined to the points by short cross bars.

    Returns
    -------
    list of numpy.ndarray
        Each an (n, 2) polyline; the first starts at ``a`` and the last ends at ``b``.
    """
    a, b = np.asarray(a, float), np.asarray(b, float)
    length = float(np.linalg.norm(b - a))
    along = (b - a) / length if length > 0 else np.array([1.0, 0.0])
    across = np.array([-along[1], along[0]])
    shift = 3.5 * width * lane * across
    p, q = a + shift, b + shift  # the lane's ends, joined to a and b by cross bars

    def at(s, w=0.0):  # the point a fraction s along the lane, w across it
        return p + s * (q - p) + w * across

    if kind == "spring":
        turns = 8  # half-waves of the zigzag, on the middle 60 % of the length
        zig = [at(0.2 + 0.6 * (k + 0.5) / turns, width * (1 if k % 2 == 0 else -1)) for k in range(turns)]
        return [np.array([a, p, at(0.2), *zig, at(0.8), q, b])]
    cylinder = [at(0.7, width), at(0.3, width), at(0.3, -width), at(0.7, -width)]  # closed at a's end, open at b's
    return [np.array([a, p, at(0.3)]), np.array(cylinder),  # a's rod, the cylinder, the piston and b's rod
            np.array([at(0.55, 0.75 * width), at(0.55, -0.75 * width)]), np.array([at(0.55), q, b])]


def torsional_paths(kind: str, centre, width: float, lane: int = 0) -> list[np.ndarray]:
    """The polylines of a torsional spring (``kind="torsional_spring"``: a spiral of two turns
    growing out from ``centre``) or damper (a rotary dashpot: an arc of 270 degrees, with a vane
    across it) about ``centre``; the ``lane``-th about one place lies outside the ones before it.

    Returns
    -------
    list of numpy.ndarray
        Each an (n, 2) polyline [m].
    """
    c = np.asarray(centre, float)
    outer = (2.2 + 1.6 * lane) * width
    if kind == "torsional_spring":
        a = np.linspace(0.0, 4 * math.pi, 97)  # two turns, the radius growing from a third of `outer`
        r = outer * (1 + 2 * a / (4 * math.pi)) / 3
        return [c + np.column_stack([r * np.cos(a), r * np.sin(a)])]
    a = np.linspace(math.pi / 4, 7 * math.pi / 4, 73)
    arc = c + outer * np.column_stack([np.cos(a), np.sin(a)])
    vane = c + np.outer([outer - 0.6 * width, outer + 0.6 * width], [math.cos(math.pi), math.sin(math.pi)])
    return [arc, vane]


def _torsion(ax, item: DrawnItem, span: float, faint: bool = False) -> None:
    width = CONNECTOR_WIDTH * span
    s = item.shape
    paths = torsional_paths(s["type"], s["centre"], width, s.get("lane", 0))
    for path in paths:
        ax.plot(path[:, 0], path[:, 1], color="0.25", linewidth=1.1, alpha=0.35 if faint else 1.0, zorder=1)
    end = paths[0][-1]
    ax.annotate(item.label, end.tolist(), xytext=(3, -3), textcoords="offset points", fontsize=7, color="0.25",
                ha="left", va="top", zorder=6)


def _connector(ax, item: DrawnItem, span: float, faint: bool = False) -> None:
    width = CONNECTOR_WIDTH * span
    s = item.shape
    for path in connector_paths(s["type"], *s["ends"], width, s.get("lane", 0.0)):
        ax.plot(path[:, 0], path[:, 1], color="0.25", linewidth=1.1, alpha=0.35 if faint else 1.0, zorder=1)
    a, b = np.asarray(s["ends"][0], float), np.asarray(s["ends"][1], float)
    along = (b - a) / (np.linalg.norm(b - a) or 1.0)
    across = np.array([-along[1], along[0]])
    side = 1 if s.get("lane", 0.0) >= 0 else -1
    where = (a + b) / 2 + (3.5 * width * s.get("lane", 0.0) + side * 2.2 * width) * across
    ax.annotate(item.label, where.tolist(), xytext=(0, 0), textcoords="offset points", fontsize=7, color="0.25",
                ha="center", va="center", zorder=6)


def _points(ax, items, bodies, span):
    """Every named point as a dot; the names of the points at one place (a pin's two halves, a
    bob's G) written once, together."""
    places: list = []  # [anchor, [names]]
    for i in items:
        if i.kind != "point":
            continue
        (dot,) = ax.plot(*i.anchor, "o", color="black", markersize=2.5, zorder=5)
        here = next((p for p in places if math.dist(p[0], i.anchor) < 1e-3 * span), None)
        if here is None:
            places.append([i.anchor, [i.label], dot])
        elif i.label not in here[1]:
            here[1].append(i.label)
    for anchor, names, dot in places:
        text = ax.annotate(", ".join(names), anchor, xytext=(4, 4), textcoords="offset points", fontsize=8, zorder=6)
        text.alt_euler_dot = dot  # placed next to it (place_labels)


def render_scene(ax, items: list[DrawnItem], bodies: list[str], title: str = "", faint: bool = False,
                 limits=None) -> None:
    """Draw the scene's items (bodies, points, guides, coordinates) on ``ax``."""
    low, high, span = limits or _span(items)
    for i in items:
        if i.kind == "element":
            _element(ax, i, _colour(i.body, bodies), faint)
        elif i.kind == "link":
            xs, ys = zip(*i.shape["points"])
            ax.plot(xs, ys, color=_colour(i.body, bodies), linewidth=1.2, alpha=0.35 if faint else 1.0, zorder=1)
        elif i.kind == "guide":
            s = i.shape
            if s["type"] == "line":
                _hatch_line(ax, s["ends"], s["hatch"], span, s.get("dashed", False))
            elif s["type"] == "circle":
                _hatch_circle(ax, s["centre"], s["radius"], s["hatch_inside"], span)
            elif s["type"] == "cord":
                (x0, y0), (x1, y1) = s["ends"]
                ax.plot([x0, x1], [y0, y1], color="0.3", linewidth=1, zorder=1)
        elif i.kind == "support":
            _support(ax, i, span)
        elif i.kind in ("spring", "damper"):
            _connector(ax, i, span, faint)
        elif i.kind in ("torsional_spring", "torsional_damper"):
            _torsion(ax, i, span, faint)
        elif i.kind == "coordinate":
            s = i.shape
            if s["type"] == "arc":
                label = _arc(ax, s["centre"], s["radius"], s["start"], s["end"], "0.15", i.label,
                             arrow=abs(s["end"] - s["start"]) > 0.05, label_at=s.get("label_at"))
                ref = s["start"]
                c = np.array(s["centre"])
                # the reference line, just past the arc; on a disk, to its rim, beside the radius that turns
                out = s["rim"] if "rim" in s else min(1.6 * s["radius"], s["radius"] + 0.1 * span)
                ax.plot([c[0], c[0] + out * math.cos(ref)], [c[1], c[1] + out * math.sin(ref)],
                        color="0.4", linewidth=0.7, linestyle=":", zorder=3)
                if "rim" in s:  # the radius that turns, in two halves: the label stays near the outer one
                    u = s["rim"] * np.array([math.cos(s["end"]), math.sin(s["end"])])
                    for k, (a, b) in enumerate(((c, c + 0.5 * u), (c + 0.5 * u, c + u))):
                        half = ax.plot([a[0], b[0]], [a[1], b[1]], color="0.15", linewidth=1.0, zorder=3,
                                       solid_capstyle="butt")
                    arc = label.alt_euler_names if abs(s["end"] - s["start"]) > 0.05 else []  # (an angle of 0: a dot)
                    label.alt_euler_names = [*half, *arc]
            elif s["type"] == "dimension":
                a, b = np.array(s["ends"][0]), np.array(s["ends"][1])
                off = np.array([0.0, -0.12 * span])
                _add_patch(ax, FancyArrowPatch((a + off).tolist(), (b + off).tolist(), arrowstyle="<|-|>",
                                             mutation_scale=8, color="0.15", linewidth=0.9, zorder=4))
                for p in (a, b):
                    ax.plot([p[0], p[0] + off[0] * 1.2], [p[1], p[1] + off[1] * 1.2], color="0.4", linewidth=0.6)
                m = 0.5 * (a + b) + off
                ax.annotate(i.label, m.tolist(), xytext=(0, -9), textcoords="offset points", ha="center",
                            fontsize=7, zorder=6)
            else:
                ax.annotate(i.label, i.anchor, xytext=(6, -10), textcoords="offset points", fontsize=7)
    _points(ax, items, bodies, span)
    if limits is None:
        _setup(ax, low, high, span, title)


def _crowd(tips, at, span) -> int:
    """How many labels were already placed near ``at`` (to stack the next one below them)."""
    return sum(1 for t in tips[:-1] if abs(t[0] - at[0]) + abs(t[1] - at[1]) < 0.08 * span)


NEAR_ANGLE = math.radians(30.0)
"""Arrows within this angle of parallel (or of opposite) can be read as one: they are kept apart.
Arrows crossing at a larger angle are told apart at a glance, as in any textbook diagram."""
TOUCH = 0.1
"""Two such arrows closer than this fraction of an arrow's length lie on one another (about 10
pixels on a 4.6 inch panel: closer, two shafts and their heads run together)."""
HEAD_GAP = 0.25
"""Two such arrows with the heads of opposite ones, or the head of one and the tail of the other,
closer than this fraction of an arrow's length read as arrows meeting head to head, or as one
arrow drawn in two pieces."""
SIDE_STEP = 0.12
"""How far an arrow is moved sideways, as a fraction of an arrow's length, when both of its ends
at its point are taken (about 12 pixels on a 4.6 inch panel: a clear gap between two arrows)."""


def _segment_gap(a0, a1, b0, b1) -> float:
    """The least distance between segments a0-a1 and b0-b1 (0 when they cross); either may be a
    point (its two ends equal)."""
    def side(p, q, r):
        return (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])

    if side(a0, a1, b0) * side(a0, a1, b1) < 0 and side(b0, b1, a0) * side(b0, b1, a1) < 0:
        return 0.0

    def to_segment(p, q0, q1):
        d = q1 - q0
        t = min(1.0, max(0.0, float((p - q0) @ d) / float(d @ d))) if float(d @ d) > 0 else 0.0
        return float(np.linalg.norm(p - (q0 + t * d)))

    return min(to_segment(a0, b0, b1), to_segment(a1, b0, b1), to_segment(b0, a0, a1), to_segment(b1, a0, a1))


def _reads_as_one(seg, other, length) -> bool:
    """Whether arrow ``seg`` (tail, tip) would be read together with the drawn arrow ``other``.

    Only arrows within :data:`NEAR_ANGLE` of parallel or opposite can be: when a head is close to
    the other's head (opposite arrows) or tail (parallel ones, :data:`HEAD_GAP`), or when they
    touch or lie on one another (:data:`TOUCH`), unless they are opposite arrows leaving one
    point (tail to tail, as textbooks draw two forces at a point on one line)."""
    a0, a1 = (np.asarray(p, float) for p in seg)
    b0, b1 = (np.asarray(p, float) for p in other)
    la, lb = float(np.linalg.norm(a1 - a0)), float(np.linalg.norm(b1 - b0))
    if la == 0 or lb == 0:
        return False
    ua, ub = (a1 - a0) / la, (b1 - b0) / lb
    if abs(ua[0] * ub[1] - ua[1] * ub[0]) > math.sin(NEAR_ANGLE):
        return False
    opposite = float(ua @ ub) < 0
    near = math.dist(a1, b1) if opposite else min(math.dist(a1, b0), math.dist(a0, b1))
    if near < HEAD_GAP * length:
        return True
    if _segment_gap(a0, a1, b0, b1) > TOUCH * length:
        return False
    return not (opposite and math.dist(a0, b0) <= TOUCH * length)


def _head_on_dot(tail, tip, at, dots, length, segments=()) -> bool:
    """Whether the head of arrow ``tail``-``tip`` (its last :data:`TOUCH` arrow lengths) ends on the
    dot of a point other than the arrow's own point ``at``, or, moved off ``at``, on another arrow of
    ``segments`` (within :data:`TOUCH` arrow lengths): it would read as acting there (disk_bar's
    weight, drawn arriving at G, ended on P's dot; moved aside, on the shaft of -m a_P)."""
    tail, tip = np.asarray(tail, float), np.asarray(tip, float)
    back = tip + TOUCH * (tail - tip) / (float(np.linalg.norm(tail - tip)) or 1.0) * length
    ends = [(np.asarray(d, float),) * 2 for d in dots if math.dist(d, at) > 1e-9 * length]
    if math.dist(tip, at) > 1e-9 * length:  # (arriving at its own point it may meet an arrow leaving it)
        ends += [tuple(np.asarray(p, float) for p in seg) for seg in segments]
    return any(_segment_gap(back, tip, a, b) < TOUCH * length for a, b in ends)


def _arrow_place(at, direction, length, pushing, segments, dots=()):
    """Where to draw a force's arrow: (tail, tip, sideways normal or None); recorded in ``segments``.

    Tried in order, the first that no earlier arrow would be read with (:func:`_reads_as_one`) wins:
    leaving its point (a pull) or arriving at it (``pushing``: a force towards the body), then the
    other of the two, then each of the two moved sideways by :data:`SIDE_STEP` arrow lengths, one side
    then the other, up to three steps (the last try is kept when all clash). Only the drawing moves: the force's point of application (the
    model's anchor) is unchanged."""
    x, y = at
    d = np.asarray(direction, float)
    leaving = ((x, y), (x + length * d[0], y + length * d[1]))
    arriving = ((x - length * d[0], y - length * d[1]), (x, y))
    first, second = (arriving, leaving) if pushing else (leaving, arriving)
    normal = np.array([-d[1], d[0]])
    tries = [(first, None), (second, None)]
    for step in (1, 2, 3):
        for way in (first, second):
            for side in (1, -1):
                shift = side * step * SIDE_STEP * length * normal
                tries.append(((tuple(np.add(way[0], shift)), tuple(np.add(way[1], shift))), side * normal))
    for (tail, tip), moved in tries:
        if not any(_reads_as_one((tail, tip), other, length) for other in segments) and \
                not _head_on_dot(tail, tip, (x, y), dots, length, segments):
            break
    segments.append((tail, tip))
    return tail, tip, moved


def _force_arrow(ax, item: DrawnItem, length, colour, dashed, tips, centre=None, segments=None, dots=()):
    direction = item.direction
    x, y = item.anchor
    span = length / 0.45
    if direction is None:  # a zero force (a reaction or an applied one): a mark at its point and its label
        tips.append((x, y))
        ax.plot(x, y, "x", color=colour, markersize=5, zorder=6)
        ax.annotate(item.label, (x, y), xytext=(5, -10 - 9 * _crowd(tips, (x, y), span)), textcoords="offset points",
                    fontsize=7, color=colour)
        return
    # a force pushing towards the body's mass centre (within 60 deg): drawn ending at its point, from outside
    pushing = centre is not None and (centre[0] - x) * direction[0] + (centre[1] - y) * direction[1] > \
        0.5 * math.dist(centre, (x, y)) + 1e-9 * length
    tail, tip, moved = _arrow_place((x, y), direction, length, pushing, [] if segments is None else segments, dots)
    arrow = FancyArrowPatch(tail, tip, arrowstyle="-|>", mutation_scale=11, color=colour,
                            linewidth=1.6, linestyle="--" if dashed else "-", zorder=7)
    _add_patch(ax, arrow)
    leaves = math.dist(tail, (x, y)) <= math.dist(tip, (x, y))  # the label goes at the free end of the arrow
    label_at = tip if leaves else tail
    tips.append(label_at)
    right = (1 if leaves else -1) * direction[0] >= 0
    if moved is not None and abs(moved[0]) > 0.3:  # moved aside: the label on that side, off the other arrow
        right = moved[0] > 0
    text = ax.annotate(item.label, label_at, xytext=(3 if right else -3, 3 - 9 * _crowd(tips, label_at, span)),
                       textcoords="offset points", fontsize=7, color=colour, ha="left" if right else "right", zorder=8)
    _label_of(text, [arrow])


def render_fbd(ax, scene_items: list[DrawnItem], forces: list[DrawnItem], body: str, bodies: list[str],
               title: str = "") -> None:
    """One free-body diagram: the body (faint), its points, its forces and couples."""
    own = [i for i in scene_items if i.body == body and i.kind in ("element", "link", "point")]
    low, high, span = _span(own)
    span = max(span, 1e-9)
    render_scene(ax, own, bodies, faint=True, limits=(low, high, span))
    length = 0.45 * span
    centre = next((i.anchor for i in own if i.kind == "point" and i.name == "G"), None)
    tips: list = []
    segments: list = []  # the arrows drawn so far, (tail, tip)
    # the arrows first: the couples' arcs are placed clear of them; -m a_P first of all, leaving G as
    # Eq. 10 draws it, so that no other arrow's head lands on it (disk_bar's weight did)
    for item in sorted(forces, key=lambda i: i.kind != "inertial"):
        if item.kind in ("force", "inertial"):
            colour = INERTIAL_COLOUR if item.kind == "inertial" else FORCE_COLOUR
            _force_arrow(ax, item, length, colour, dashed=item.kind == "inertial", tips=tips, centre=centre,
                         segments=segments, dots=[i.anchor for i in own if i.kind == "point"])
    arcs = _couple_places(forces, own, span, segments)
    for item in forces:
        if item.kind in ("force", "inertial"):
            continue
        if item.turn == 0:  # a zero couple: its label only
            colour = INERTIAL_COLOUR if item.kind == "inertial_couple" else FORCE_COLOUR
            tips.append(item.anchor)
            ax.annotate(item.label, item.anchor, xytext=(6, -12 - 9 * _crowd(tips, item.anchor, span)),
                        textcoords="offset points", fontsize=7, color=colour, zorder=8)
        else:
            colour = INERTIAL_COLOUR if item.kind == "inertial_couple" else FORCE_COLOUR
            where, r, a0 = arcs[id(item)]
            _arc(ax, where, r, a0, a0 + 1.5 * math.pi * item.turn, colour, item.label,
                 dashed=item.kind == "inertial_couple")
    pts = [i.anchor for i in forces] + [low.tolist(), high.tolist()]
    pts += [(i.anchor[0] + s * length * i.direction[0], i.anchor[1] + s * length * i.direction[1])
            for i in forces if i.direction is not None for s in (-1, 1)]
    pts = np.array(pts)
    _setup(ax, pts.min(axis=0), pts.max(axis=0), max(span, float(np.max(pts.max(axis=0) - pts.min(axis=0)))) * 0.5,
           title)
    ax.set_xlabel(fbd_legend(forces), fontsize=7, color="0.25")


COUPLE_RADIUS = 0.1
"""A couple's arc radius, as a fraction of the body's span; arcs at one place grow by 0.04 each."""


def _couple_places(forces: list[DrawnItem], own: list[DrawnItem], span: float, arrows=()) -> dict:
    """Where each couple's arc is drawn: id(item) -> (centre, radius, start angle).

    A couple is a free vector: its moment is the same about every point, so its arc may be
    drawn anywhere on the body or beside it. Each takes its own place, the nearest to its anchor
    that is at least 2.5 radii from every arc drawn before and :data:`ARC_CLEARANCE` radii from every
    force arrow in ``arrows`` ((tail, tip) pairs: an arrow through an arc leaves no room for the
    labels of either): its anchor, a named point of the body, a point halfway between G and a named
    point, or one of these moved 2.5 radii up, down, left or right. When none is clear of the arrows,
    the nearest clear of the arcs. The inertial couple -I_P alpha is placed first and keeps G, beside
    -m a_P. Only when every place is taken do arcs share one, with growing radii.
    """
    r = COUPLE_RADIUS * span
    named = [np.asarray(i.anchor, float) for i in own if i.kind == "point"]
    G = next((np.asarray(i.anchor, float) for i in own if i.kind == "point" and i.name == "G"), None)
    halfway = [(G + p) / 2 for p in named] if G is not None else []
    moved = [p + 2.5 * r * np.array(d) for p in named + halfway for d in ((1, 0), (0, 1), (-1, 0), (0, -1))]
    turning = sorted((i for i in forces if i.kind in ("couple", "inertial_couple") and i.turn != 0),
                     key=lambda i: i.kind != "inertial_couple")  # stable: the inertial couple first
    taken: list = []  # [centre, arcs there]

    def clear_of_arrows(p):
        return all(_segment_gap(p, p, np.asarray(a, float), np.asarray(b, float)) >= ARC_CLEARANCE * r
                   for a, b in arrows)

    out = {}
    for k, item in enumerate(turning):
        anchor = np.asarray(item.anchor, float)
        places = sorted([anchor, *named, *halfway], key=lambda p: float(np.linalg.norm(p - anchor)))
        if item.kind != "inertial_couple":
            places = sorted(places + moved, key=lambda p: (not clear_of_arrows(p), float(np.linalg.norm(p - anchor))))
        free = next((p for p in places if all(np.linalg.norm(p - c) >= 2.5 * r for c, _ in taken)), None)
        if free is None:  # no room: around the least used place, a larger arc
            spot = min(taken, key=lambda t: t[1])
            spot[1] += 1
            centre, radius = spot[0], r + 0.04 * span * (spot[1] - 1)
        else:
            taken.append([free, 1])
            centre, radius = free, r
        start = math.radians(30 + 100 * k)
        ending = [(np.asarray(a, float), np.asarray(b, float)) for a, b in arrows]
        inside = [(a, b) for a, b in ending if 1e-9 * span < np.linalg.norm(b - centre) < 1.5 * radius]
        if inside:  # an arrow's head inside the arc: the arc's 90 degree gap turned to where its shaft
            # comes in, the arc's tail beside it (its head, a quarter turn on, clear of the arrow's head)
            enter = _entry(*inside[0], centre, radius)
            start = math.atan2(*(enter - centre)[::-1]) + item.turn * math.pi / 8
        out[id(item)] = (tuple(centre.tolist()), radius, start)
    return out


def _entry(tail, tip, centre, radius) -> np.ndarray:
    """Where segment ``tail``-``tip`` (its tip inside the circle) crosses the circle, nearest the tail
    (the tail itself when it is inside too)."""
    d, f = tip - tail, tail - centre
    a, b, c = float(d @ d), 2 * float(f @ d), float(f @ f) - radius**2
    disc = b * b - 4 * a * c
    if a == 0 or disc < 0 or c <= 0:
        return tail
    return tail + (-b - math.sqrt(disc)) / (2 * a) * d


ARC_CLEARANCE = 1.6
"""Least distance from a couple's arc's centre to a force arrow, in arc radii, where a place is
free: the arc (1 radius) and its label's line beside it."""


def fbd_legend(forces: list[DrawnItem]) -> str:
    """The text under a free-body diagram: the sign convention of its labels and what is dashed."""
    inertial = [typeset_text(i.name) for i in forces if i.kind in ("inertial", "inertial_couple")]
    dashed = f"\nDashed: the inertial terms {' and '.join(inertial)} at G (Eq. 10)." if inertial else ""
    return CONVENTION.replace("$", r"\$") + dashed


# -- label placement -------------------------------------------------------------------------------

LABEL_PAD = 1.5
"""Clearance kept between two labels [display pixels at the figure's dpi]."""

_STEPS = (0.0, 5.0, 9.0, 13.0, 18.0, 24.0, 31.0, 40.0, 50.0)
"""Distances [points] a label may move from where it was put, tried nearest first."""


def label_boxes(ax, renderer=None) -> list:
    """The display-space bounding boxes (matplotlib Bbox) of the visible labels drawn on ``ax``."""
    renderer = renderer or agg_renderer(ax.figure)
    return [t.get_window_extent(renderer) for t in ax.texts if t.get_visible() and t.get_text()]


OBSTACLE_STEP = 3.0
"""Spacing [display pixels] of the points sampled along drawn lines and arrows for the label
placer: less than the height of a 7-point label (about 10 pixels at 100 dpi), so that a label
laid across a line always covers some of its points."""


def _head(tail, tip, scale: float) -> np.ndarray:
    """Display points filling an arrow's head ("-|>": 0.4 of the mutation ``scale`` [pixels] long,
    0.2 of it to each side), so that a label does not cover the head either."""
    length = float(np.linalg.norm(tip - tail)) or 1.0
    back, across = (tail - tip) / length, np.array([tail[1] - tip[1], tip[0] - tail[0]]) / length
    s, w = np.meshgrid(np.linspace(0, 0.4 * scale, 5), np.linspace(-0.2 * scale, 0.2 * scale, 5))
    return tip + s.reshape(-1, 1) * back + (w * (1 - s / (0.4 * scale))).reshape(-1, 1) * across


@lru_cache(maxsize=256)
def _fractions(n: int) -> np.ndarray:
    """``np.linspace(0, 1, n)`` as a column, made once per ``n`` (:func:`_drawn_points` asks for a few
    sizes hundreds of times); read only."""
    column = np.linspace(0, 1, n)[:, None]
    column.flags.writeable = False
    return column


def _drawn_points(ax) -> list:
    """Display points along what is drawn on ``ax``, which labels avoid covering: one
    ``(artist, points, pad, kind)`` per line or patch, ``pad`` [pixels] half its stroke's width
    (a bar is 5 points wide: a label clear of its centre line may still lie on its stroke), ``kind``
    ``arrow`` (a force's or an arc's), ``stroke`` (a line: a bar, a body's frame, an arc, a guide and
    its hatching),
    ``ring`` (a circle's outline, not filled: a ring, a rim, a circular guide) or ``mark`` (a point's
    dot, pad its radius; a filled shape's edge)."""
    def along(a, b):  # a point every OBSTACLE_STEP pixels: no label slips between two of them
        n = max(2, int(np.linalg.norm(b - a) / OBSTACLE_STEP) + 1)
        return a + _fractions(n) * (b - a)

    to_pixels = ax.figure.dpi / 72.0
    out = []
    for line in ax.lines:
        xy = line.get_transform().transform(np.column_stack(line.get_data()).astype(float))
        pts = np.vstack([xy] + [along(a, b) for a, b in zip(xy[:-1], xy[1:])])
        if len(xy) > 1:
            out.append((line, pts, 0.5 * line.get_linewidth() * to_pixels, "stroke"))
        else:  # a dot: its marker's radius
            out.append((line, pts, 0.5 * max(line.get_markersize(), line.get_linewidth()) * to_pixels, "mark"))
    for lines in ax.collections:  # a guide's hatching
        if isinstance(lines, LineCollection) and len(lines.get_segments()):
            xy = [lines.get_transform().transform(np.asarray(seg, float)) for seg in lines.get_segments()]
            pts = np.vstack([along(a, b) for seg in xy for a, b in zip(seg[:-1], seg[1:])])
            out.append((lines, pts, 0.5 * float(np.max(lines.get_linewidths())) * to_pixels, "stroke"))
    for patch in ax.patches:
        if isinstance(patch, FancyArrowPatch) and getattr(patch, "_posA_posB", None):
            a, b = (ax.transData.transform(np.array(p, float)) for p in patch._posA_posB)
            pts = np.vstack([along(a, b), _head(a, b, patch.get_mutation_scale() * to_pixels)])
            out.append((patch, pts, 0.5 * patch.get_linewidth() * to_pixels, "arrow"))
        else:  # a ring's or circle's outline (not filled): a label keeps off it (QA10: the big-end ring
            # at A ran through the label of -I_A alpha); a filled shape's edge (a disk, a plate) bounds
            # a pale area a label may lie on: a mark
            verts = np.asarray(patch.get_verts(), float)
            if len(verts) > 1 and patch.get_edgecolor()[3] > 0 and patch.get_linewidth() > 0:
                pts = np.vstack([along(a, b) for a, b in zip(verts[:-1], verts[1:])])
                filled = patch.get_fill() and patch.get_facecolor()[3] > 0
                out.append((patch, pts, 0.5 * patch.get_linewidth() * to_pixels, "mark" if filled else "ring"))
    return out


def _label_of(text, artists) -> None:
    """Record on the label ``text`` the artists it names (a force's arrow; a couple's arc and its
    head): :func:`place_labels` keeps it nearer them than any other label's arrow or arc."""
    text.alt_euler_names = list(artists)


STRAY_MARGIN = 6.0
"""A label is read as naming the arrow or arc nearest to it: it is kept at least this much [display
pixels] nearer its own than any other label's (the width of a stroke and a half)."""

OWNER_GAP = 3.0
"""Gap [display pixels] between a label and its own arrow or arc, beyond the stroke's half width,
for the places tried beside them."""


def _beside(box, owner: np.ndarray, gap: float) -> np.ndarray:
    """Moves [display pixels] that put the measured ``box`` (x0, y0, x1, y1) beside its owner's
    drawn ``owner`` points: at nine places along them, on each of 8 sides, ``gap`` clear and
    ``gap`` + 6 and ``gap`` + 12 pixels clear (the last clears a ring beside the arc or arrow)."""
    w, h = box[2] - box[0], box[3] - box[1]
    centre = np.array([box[0] + box[2], box[1] + box[3]]) / 2
    picks = owner[np.linspace(0, len(owner) - 1, 9).round().astype(int)]
    sides = np.array([(math.cos(a), math.sin(a)) for a in np.linspace(0, 2 * math.pi, 8, endpoint=False)])
    sides = np.sign(sides.round(6))  # right, up-right, up ...: the box's edge or corner towards the point
    reach = np.vstack([sides * np.array([w / 2 + g, h / 2 + g]) for g in (gap, gap + 6.0, gap + 12.0)])
    return (picks[:, None, :] + reach[None, :, :] - centre).reshape(-1, 2)


def place_labels(fig, axes) -> None:
    """Move the labels of ``axes`` off each other, and off the drawn shapes where possible.

    Greedy, in drawing order. The places tried: each label's own, the offsets in 8 directions
    :data:`_STEPS` points away from it, and for a label naming an arrow or arc (:func:`_label_of`)
    the places beside that arrow or arc (:func:`_beside`). Of these it takes the first least in order:
    cut off by the figure's edge; overlapping a label placed before it on any of ``axes`` (with
    :data:`LABEL_PAD` clearance: a label may run past its panel, which has no background); lying on
    an arrow (its shaft or head); crossed by a line (a bar's or an arc's stroke, with its width); for
    a point's label, crossed by a ring, then further than :data:`NEXT_TO` from its dot (each only
    when a place is not: the nearest place otherwise); not at least :data:`STRAY_MARGIN` nearer its own
    arrow or arc (dot) than any other label's (so that it cannot be read as naming another); crossed
    by a ring's outline; covering a point's dot or a filled shape's edge; then the nearest to its own
    arrow or arc (the nearest to its own place for other labels), and covering the fewest drawn points.
    Text extents come from the renderer after the layout is fixed (labels are taken out of the
    layout so that moving them cannot move the axes). A label's offset is in points,
    so each candidate box is its measured box moved by the offset (measured once, not per try).
    """
    texts = {id(ax): [t for t in ax.texts if t.get_visible() and t.get_text() and hasattr(t, "xyann")]
             for ax in axes}
    for k, group in texts.items():  # first the labels naming an arrow or arc: they have less room
        texts[k] = sorted(group, key=lambda t: not hasattr(t, "alt_euler_names"))
    for group in texts.values():
        for t in group:
            t.set_in_layout(False)
    renderer = agg_renderer(fig)
    _final_layout(fig, axes)
    directions = [(math.cos(a), math.sin(a)) for a in np.linspace(0, 2 * math.pi, 8, endpoint=False)]
    offsets = np.array([(0.0, 0.0)] + [(step * d[0], step * d[1]) for step in _STEPS[1:] for d in directions])
    steps = np.array([0] + [k for k in range(1, len(_STEPS)) for _ in directions])  # the step of each offset
    to_pixels = fig.dpi / 72.0
    placed = np.zeros((0, 4))  # x0, y0, x1, y1 of the labels placed so far, on every panel (they may cross)
    for ax in axes:
        drawn = _drawn_points(ax)
        where = {id(artist): (pts, pad) for artist, pts, pad, _ in drawn}
        groups = {kind: _pooled([(pts, pad) for _, pts, pad, k in drawn if k == kind])
                  for kind in ("arrow", "stroke", "ring", "mark")}
        owners = {id(t): [where[id(a)] for a in getattr(t, "alt_euler_names", ()) if id(a) in where]
                  for t in texts[id(ax)]}
        owners = {k: (np.vstack([p for p, _ in v]), max(pad for _, pad in v)) for k, v in owners.items() if v}
        dots = {id(t): where[id(t.alt_euler_dot)] for t in texts[id(ax)]
                if id(getattr(t, "alt_euler_dot", None)) in where}  # a point's label: its dot
        for t in texts[id(ax)]:
            base = np.array(t.xyann, float)
            b = t.get_window_extent(renderer)
            box = np.array([b.x0, b.y0, b.x1, b.y1])
            moves = offsets * to_pixels
            own, mates = (dots, dots) if id(t) in dots else (owners, owners)  # a point's label: among dots
            own = own.get(id(t))
            if own is not None:
                moves = np.vstack([moves, _beside(box, own[0], OWNER_GAP + own[1])])
            boxes = box + np.tile(moves, 2)
            others = [o[0] for k, o in mates.items() if k != id(t)]
            rank = np.concatenate([steps, np.zeros(len(boxes) - len(steps))])
            best = _best_place(boxes, placed, groups, None if own is None else own[0], others, rank,
                               fig.bbox.extents, NEXT_TO + own[1] if id(t) in dots else None)
            t.xyann = tuple(base + moves[best] / to_pixels)
            placed = np.vstack([placed, boxes[best]])  # (its measured box, moved by the offset chosen)


NEXT_TO = 12.0
"""Farthest [display pixels, beyond the dot's radius] a point's label is put from its dot (QA10:
"G_crank" stood above the ring at A, away from its dot on OA): it may cross a line rather than
move further (a 7-point label is about 10 pixels high at 100 dpi)."""


def _best_place(boxes, placed, groups: dict, own, others: list, rank, frame, next_to=None) -> int:
    """The index of the box a label takes, by the order of :func:`place_labels`.

    ``boxes``: the places tried (rows x0, y0, x1, y1) [display pixels]; ``placed``: the labels'
    boxes so far; ``groups``: the drawn points and their pads by kind (:func:`_drawn_points`,
    :func:`_pooled`); ``own``: the points of the arrow or arc the label names (None: it names none),
    ``others`` those of the other labels'; ``rank``: each try's step from the label's own place;
    ``frame``: the figure's extents; ``next_to``: for a point's label (``own`` its dot), the farthest
    from it [display pixels] a place is taken before farther ones, when one clear of the arrows,
    lines and rings that does not stray is so near.

    The order's criteria are applied one at a time, each to the places the ones before left tied,
    and whether a place strays (the costliest test) is asked of the places in the order of the
    criteria after it, until one does not: the first place in the order, each test computed only
    for the places it can still decide between."""
    at = np.arange(len(boxes))  # the places still in the running
    at = at[_least(_cut_off(boxes, frame))]
    at = at[_least(_overlaps(boxes[at], placed, LABEL_PAD))]
    on_arrows = _covered(boxes[at], *groups["arrow"])
    keep = _least(on_arrows > 0)
    at, on_arrows = at[keep], on_arrows[keep]
    crossed = _covered(boxes[at], *groups["stroke"])
    keep = _least(crossed > 0)
    at, on_arrows, crossed = at[keep], on_arrows[keep], crossed[keep]
    if next_to is not None:  # a point's label: off the rings first (one around the point: outside it)
        keep = _least(_covered(boxes[at], *groups["ring"]) > 0)
        at, on_arrows, crossed = at[keep], on_arrows[keep], crossed[keep]
    chosen = boxes[at]
    on_marks = _covered(chosen, *groups["mark"])
    on_rings = _covered(chosen, *groups["ring"]) > 0
    if own is None:
        return int(at[np.lexsort((on_arrows + crossed + on_marks, rank[at], on_marks > 0, on_rings))[0]])
    near = _box_distance(chosen, own)
    far = near > max(next_to, near.min()) if next_to is not None else np.zeros(len(at), dtype=bool)
    order = np.lexsort((on_arrows + crossed + on_marks, np.floor(near / OBSTACLE_STEP), on_marks > 0, far, on_rings))
    clear = order[~on_rings[order]]
    # the first place in this order that does not stray; off the rings, one nearer its own by half the
    # margin is taken before one on a ring; when every place strays, the first merely nearer its own
    passes = [(clear, STRAY_MARGIN), (clear, STRAY_MARGIN / 2)] if len(clear) < len(order) else []
    for places, margin in passes + [(order, STRAY_MARGIN), (order, 0.0)]:
        for start in range(0, len(places), _STRAY_BATCH):
            batch = places[start:start + _STRAY_BATCH]
            reach = near[batch] + margin
            stray = np.zeros(len(batch), dtype=bool)
            for other in others:
                stray |= _box_distance(chosen[batch], other) < reach
            if not stray.all():
                return int(at[batch[np.argmin(stray)]])
    return int(at[order[0]])  # every place strays


_STRAY_BATCH = 8
"""Places asked at a time whether they stray (:func:`_best_place`): the first few usually settle it."""


def _least(values: np.ndarray) -> np.ndarray:
    """Where ``values`` take their least value (a mask)."""
    return values == values.min()


def _pooled(drawn: list) -> tuple[np.ndarray, np.ndarray]:
    """The drawn points of several lines or patches (pairs of points and pad) as one array of points
    and one of their pads."""
    if not drawn:
        return np.zeros((0, 2)), np.zeros(0)
    return (np.vstack([pts for pts, _ in drawn]),
            np.concatenate([np.full(len(pts), pad, dtype=float) for pts, pad in drawn]))


def _box_distance(boxes: np.ndarray, points: np.ndarray) -> np.ndarray:
    """For each box (rows x0, y0, x1, y1), the distance from it to the nearest of ``points`` (0 inside;
    infinite when there are none)."""
    if not len(points):
        return np.full(len(boxes), np.inf)
    x, y = points[None, :, 0], points[None, :, 1]
    dx = boxes[:, 0:1] - x
    np.maximum(dx, x - boxes[:, 2:3], out=dx)
    np.maximum(dx, 0.0, out=dx)
    dy = boxes[:, 1:2] - y
    np.maximum(dy, y - boxes[:, 3:4], out=dy)
    np.maximum(dy, 0.0, out=dy)
    return np.hypot(dx, dy, out=dx).min(axis=1)


def _final_layout(fig, axes) -> None:
    """Fix the axes' places as drawing would: the layout, then each axes' aspect."""
    fix_layout(fig)
    for ax in axes:
        ax.apply_aspect()


def _overlaps(boxes: np.ndarray, placed: np.ndarray, pad: float) -> np.ndarray:
    """For each box (rows x0, y0, x1, y1), how many of ``placed`` it overlaps with ``pad`` clearance."""
    if not len(placed):
        return np.zeros(len(boxes), dtype=int)
    a, p = boxes[:, None, :], placed[None, :, :]
    hit = (a[..., 0] < p[..., 2] + pad) & (p[..., 0] < a[..., 2] + pad) & \
          (a[..., 1] < p[..., 3] + pad) & (p[..., 1] < a[..., 3] + pad)
    return hit.sum(axis=1)


def _cut_off(boxes: np.ndarray, frame) -> np.ndarray:
    """For each box, whether any of it lies outside the figure's ``frame`` (x0, y0, x1, y1)."""
    x0, y0, x1, y1 = frame
    return (boxes[:, 0] < x0) | (boxes[:, 1] < y0) | (boxes[:, 2] > x1) | (boxes[:, 3] > y1)


def _covered(boxes: np.ndarray, points: np.ndarray, pad=0.0) -> np.ndarray:
    """For each box, how many of the drawn ``points`` lie strictly inside it grown by ``pad`` [pixels]
    on every side (a stroke's half width: the stroke of a line through such a point touches the box);
    ``pad`` one number, or one per point."""
    if not len(points) or not len(boxes):
        return np.zeros(len(boxes), dtype=int)
    pad = np.broadcast_to(np.asarray(pad, dtype=float), (len(points),))
    # Only the points near the boxes can be inside one: a point more than the largest pad (and a
    # pixel, against rounding) beyond every box is left out before the exact test (the places tried
    # for a label lie around it, the drawn points over the whole panel)
    reach = float(pad.max()) + 1.0
    near = ((points[:, 0] > boxes[:, 0].min() - reach) & (points[:, 0] < boxes[:, 2].max() + reach) &
            (points[:, 1] > boxes[:, 1].min() - reach) & (points[:, 1] < boxes[:, 3].max() + reach))
    points, pad = points[near], pad[near][None, :]
    x, y = points[None, :, 0], points[None, :, 1]
    inside = (x > boxes[:, 0:1] - pad) & (x < boxes[:, 2:3] + pad) & (y > boxes[:, 1:2] - pad) & \
        (y < boxes[:, 3:4] + pad)
    return np.count_nonzero(inside, axis=1)
