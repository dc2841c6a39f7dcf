"""Drawings checked against the scenes, as data (solver.drawing.model), not as images.

Every shipped scene is drawn (configuration and free-body diagrams). The test
then asks the scene, by its own route, what must be there: every named point
of every body and of the ground, every coordinate, every guide, and on every
free-body diagram every reaction (on both bodies it joins), every load and the
inertial force. Each reaction arrow must point along the direction that the
joint's geometry gives (worked out here from the joint's data, per kind),
times the sign of the solved value, reversed on the joint's first body.
"""
from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from reports.figures import PAPER_SCENE_FIGURES
from solver.__main__ import main
from solver.analyses.instant import solve_instant
from solver.analyses.regimes import start_state
from solver.drawing import draw_system
from solver.io.scenes import load_system
from solver.model.bodies import GROUND

ROOT = Path(__file__).resolve().parents[1]
SCENES = sorted((ROOT / "data" / "scenes").glob("*.toml"))

# Directions are unit vectors computed in float64 by two routes (sympy xreplace here,
# compiled numpy in the product) from the same few trigonometric evaluations: they agree
# to ~1e-15; 1e-9 leaves room for the dependent coordinates' Newton solve (1e-13 residual).
DIRECTION_TOL = 1e-9
# Positions [m] likewise; the scenes are 0.01 m to 2 m across.
POSITION_TOL = 1e-9
# The coordinate names the drawings write as Greek letters, as the paper prints them
GREEK = {"theta": "\u03b8", "phi": "\u03c6", "alpha": "\u03b1", "beta": "\u03b2", "psi": "\u03c8",
         "omega": "\u03c9"}
MINUS = "\u2212"


def _value(expr, system, state) -> float:
    """An expression of the state evaluated by sympy substitution (the test's own route)."""
    vals = dict(system.si_values())
    vals.update(dict(zip(system.q, state.q)))
    vals.update(dict(zip(system.qd, state.qd)))
    vals[system.t] = state.t
    return float(sp.sympify(expr).xreplace({k: sp.Float(v) for k, v in vals.items()}).evalf())


def _written(unit: str) -> str:
    """A unit as a label writes it: a product with a middle dot (N·m), as the paper prints it."""
    return unit.replace("*", "\u00b7")


def _unit(angle: float) -> np.ndarray:
    return np.array([math.cos(angle), math.sin(angle)])


def _reaction_direction(joint, k: int, system, state):
    """The positive sense of reaction k of ``joint`` on its second body, from the joint's data.

    Returns a unit vector for a force, or +1 for a counter-clockwise couple.
    """
    phi1 = _value(system.angle(joint.first), system, state)
    if joint.kind == "pin":
        return np.eye(2)[k]  # fixed-frame x and y components
    if joint.kind in ("rail", "pin_in_slot", "slider"):
        if k == 1:
            return 1  # the slider's couple
        a = phi1 + _value(joint.angle, system, state)
        return np.array([-math.sin(a), math.cos(a)])  # the line's left normal
    if joint.kind == "rolling":
        a = phi1 + _value(joint.angle, system, state)
        return _unit(a) if k == 0 else np.array([-math.sin(a), math.cos(a)])  # friction along, normal across
    if joint.kind == "motor":
        return 1
    if joint.kind == "cord":
        return -np.array([_value(c, system, state) for c in joint.direction])  # pulls the second body to the drum
    raise AssertionError(f"no independent direction for a {joint.kind} joint: add one to this test")


@pytest.mark.parametrize("path", SCENES, ids=[p.stem for p in SCENES])
def test_drawing_matches_the_scene(path):
    system = load_system(path)
    state = start_state(system)
    scene = draw_system(system, state)
    fbd = draw_system(system, state, fbd=True)

    # every named point of every body (and G) and of the ground, at its place
    points = {(i.body, i.name): np.array(i.anchor) for i in scene.of_kind("point")}
    for name, body in system.bodies.items():
        for p in body.point_names():
            assert (name, p) in points, f"{path.name}: point {name}:{p} not labelled"
            where = np.array([_value(x, system, state) for x in system.point_position(name, p)])
            np.testing.assert_allclose(points[(name, p)], where, atol=POSITION_TOL)
    for p in system.ground.points:
        assert (GROUND, p) in points, f"{path.name}: ground point {p} not labelled"
    labels = {i.label for i in scene.items}
    # each point labelled by its name; with several bodies a mass centre by its body's (G_rod): no
    # two mass centres share a label (other names are the scene's: parallel_link_plate has two O)
    named = {(i.body, i.name) for i in scene.items
             if i.label == (f"G_{i.body}" if i.name == "G" and len(system.bodies) > 1 else i.name)}
    assert {(i.body, i.name) for i in scene.of_kind("point")} <= named
    places = {}
    for i in (i for i in scene.of_kind("point") if i.name == "G"):
        assert np.allclose(places.setdefault(i.label, i.anchor), i.anchor, atol=POSITION_TOL), \
            f"{path.name}: two places labelled {i.label!r}"
    # every coordinate marked (a prescribed one too), every line guide drawn
    marked = {i.name for i in scene.of_kind("coordinate")}
    assert marked == {c.name for c in system.coordinates}, f"{path.name}: coordinates marked {marked}"
    for i in scene.of_kind("coordinate"):  # by its name, a Greek one as the paper writes it (QA10 item 6)
        assert GREEK.get(i.name, i.name) in i.label and not set(GREEK) & set(i.label.split()), i.label
    guides = {i.name for i in scene.of_kind("guide", "support")}
    for j in system.joints:
        if j.kind in ("rail", "slider", "pin_in_slot", "rolling", "rolling_on_circle", "cord") or \
                (j.kind == "pin" and GROUND in j.bodies):
            assert j.name in guides, f"{path.name}: joint {j.name} ({j.kind}) not drawn"
    # every element drawn
    elements = {(i.body, i.name) for i in scene.of_kind("element")}
    assert elements == {(b, e.name) for b, body in system.bodies.items() for e in body.elements}
    assert labels  # the drawing has text

    # free-body diagrams: every reaction on both bodies, along the joint's direction x sign of the solved value
    solution = fbd.solution  # the solve the diagrams show: its signs decide the arrows
    assert solution.state == state and fbd.panels == list(system.bodies)
    for joint in system.joints:
        for k, reaction in enumerate(joint.reactions):
            value = float(solution.unknowns[reaction.name].to_base_units().magnitude)
            positive = _reaction_direction(joint, k, system, state)
            for body, side in ((joint.second, 1), (joint.first, -1)):
                if body == GROUND:
                    continue
                drawn = [i for i in fbd.on(body) if i.name == reaction.name]
                assert len(drawn) == 1, f"{path.name}: reaction {reaction.name} on {body}: {drawn}"
                item = drawn[0]
                assert reaction.name in item.label and _written(item.unit) in item.label
                if item.direction is None and item.turn == 0:  # drawn as zero: it must be negligible
                    assert item.value == 0.0
                    # ZERO_FORCE: below 1e-9 of the largest force on the body (round-off of the solve)
                    assert abs(value) < 1e-6 * max(1.0, max(abs(float(q.to_base_units().magnitude))
                                                            for q in solution.unknowns.values()))
                    continue
                if isinstance(positive, int):
                    assert item.turn == positive * side * np.sign(value), f"{reaction.name} on {body}"
                else:
                    np.testing.assert_allclose(item.direction, positive * side * np.sign(value), atol=DIRECTION_TOL,
                                               err_msg=f"{path.name}: {reaction.name} on {body}")
    # every load on every body it acts on; weights at G pointing along gravity
    for load in system.loads:
        if load.kind == "gravity":
            g_dir = np.array([_value(c, system, state) for c in load.direction])
            for body in system.bodies:
                (item,) = [i for i in fbd.on(body) if i.name == load.name]
                np.testing.assert_allclose(item.direction, g_dir / np.linalg.norm(g_dir), atol=DIRECTION_TOL)
                where = [_value(x, system, state) for x in system.point_position(body, "G")]
                np.testing.assert_allclose(item.anchor, where, atol=POSITION_TOL)
        elif load.kind == "force":
            (item,) = [i for i in fbd.on(load.body) if i.name == load.name]
            f = np.array([_value(c, system, state) for c in load.components])
            if np.linalg.norm(f) == 0:
                assert item.direction is None and item.value == 0.0
            else:
                np.testing.assert_allclose(item.direction, f / np.linalg.norm(f), atol=DIRECTION_TOL)
        else:
            bodies = [b for b in (getattr(load, "body", None), getattr(load, "first", None),
                                  getattr(load, "second", None), *(getattr(load, "a", ("",))[:1]),
                                  *(getattr(load, "b", ("",))[:1])) if b in system.bodies]
            for body in bodies:
                assert any(i.name == load.name for i in fbd.on(body)), f"{load.name} on {body}"
    # the inertial force of Eq. 10, dashed, on every body
    for body in system.bodies:
        inertial = [i for i in fbd.on(body) if i.kind == "inertial"]
        assert len(inertial) == 1 and inertial[0].label.startswith(f"|{MINUS}m a_{fbd.point[body]}| = ")
        _assert_no_moment_about_P(fbd, points[(body, fbd.point[body])], body, path.name)
    _assert_sizes_in_labels(fbd, path.name)
    _assert_labels_apart(fbd.figure, path.name)  # draws the diagrams: the later checks read that drawing
    _assert_arrows_apart(fbd.figure, path.name)
    _assert_couples_apart(fbd.figure, path.name)
    _assert_labels_off_arrows(fbd.figure, path.name, drawn=True)
    _assert_labels_by_what_they_name(fbd, scene.items, path.name, drawn=True)


def _four_figures(text: str, value: float) -> bool:
    """Whether ``text`` writes ``value`` to 4 significant figures, its trailing zeros kept as the
    other labels keep theirs (QA10: "|-m a_A| = 19.5 lbf" beside "|R_A| = 27.88 lbf"): 4 digits from
    the first non-zero one, and within half a unit of the 4th figure of ``value`` (0 as "0")."""
    if value == 0:
        return text == "0"
    digits = text.split("e")[0].replace(".", "").lstrip("0")
    unit = 10.0 ** (math.floor(math.log10(abs(value))) - 3)
    return len(digits) == 4 and digits.isdigit() and abs(float(text) - value) <= 0.5 * unit * (1 + 1e-12)


def _size_of(label: str, name: str, unit: str) -> str:
    """The size a label ``|name| = size unit`` writes (None when the label is not of that form)."""
    import re

    m = re.fullmatch(rf"(?:.*: )?\|{re.escape(name)}\| = (\S+) {re.escape(_written(unit))}", label)
    return m and m.group(1)


def _assert_sizes_in_labels(fbd, where):
    """The convention of the diagrams, stated under each of them: arrows (arcs) in the actual sense,
    labels ``|X| = size``: no label carries a sign, each gives the size of the value its item holds."""
    for item in fbd.items:
        if item.kind in ("force", "couple", "inertial", "inertial_couple"):
            size = re.search(rf"\| = (\S+) {re.escape(_written(item.unit))}$", item.label)
            assert size and _four_figures(size.group(1), abs(item.value)) and "= -" not in item.label, \
                f"{where}: {item.label!r} (value {item.value})"
    for ax in fbd.figure.axes:
        if ax.get_visible():
            legend = ax.get_xlabel()
            assert "actual sense" in legend and "|X| = its size" in legend, f"{where}: no convention under a diagram"


# Two labels' boxes may share at most 1 display pixel (at the figure's 100 dpi, 0.72 pt) each way:
# the renderer measures text from font metrics and rounds to whole pixels, so boxes that touch can
# report a 1-pixel intersection; anything visible as overlapping text is several pixels (the labels
# are 7-8 pt, about 10 pixels high). Without the label placer 14 of the 17 shipped scenes fail this.
LABEL_OVERLAP_TOL = 1.0


# Two arrows within 30 deg of parallel (or of opposite) can be read as one; at a larger angle they are
# told apart at a glance. Such arrows must not touch (a gap under 5 % of an arrow's length, about 5 px
# on a 4.6 inch panel, or crossing) unless they are opposite arrows leaving one point, and the heads
# of opposite ones must not meet (closer than 15 % of an arrow's length).
NEAR_PARALLEL = math.radians(30)
TOUCHING = 0.05
HEADS_MEET = 0.15


def _gap(a0, a1, b0, b1) -> float:
    """Least distance between two segments, by sampling each finely (the test's own route)."""
    s = np.linspace(0, 1, 401)[:, None]
    pa, pb = a0 + s * (a1 - a0), b0 + s * (b1 - b0)
    # the least of the 401 x 401 distances, as np.linalg.norm(pa[:, None] - pb[None], axis=2) gives
    # each (sqrt(dx**2 + dy**2)), with one square root: sqrt is monotone, so the same float
    dx, dy = pa[:, 0, None] - pb[None, :, 0], pa[:, 1, None] - pb[None, :, 1]
    return float(np.sqrt(np.min(dx * dx + dy * dy)))


def _assert_arrows_apart(figure, where):
    """No two force arrows are drawn so that they read as one: on top of each other (drum_and_block's
    block drew its dashed -m a_P over the cord tension, slider_crank's piston its weight over N_cyl),
    end to end on one line, or head to head (disk_bar's weight from G ran down into F_n's head at C)."""
    from matplotlib.patches import FancyArrowPatch

    for ax in figure.axes:
        arrows = [tuple(np.array(p, float) for p in a._posA_posB) for a in ax.patches if isinstance(a, FancyArrowPatch)]
        length = max((np.linalg.norm(b - a) for a, b in arrows), default=0.0)
        arrows = [(a, b) for a, b in arrows if np.linalg.norm(b - a) > 0.5 * length]  # not an arc's head
        for i, (a0, a1) in enumerate(arrows):
            for b0, b1 in arrows[:i]:
                ua, ub = (a1 - a0) / np.linalg.norm(a1 - a0), (b1 - b0) / np.linalg.norm(b1 - b0)
                if abs(ua[0] * ub[1] - ua[1] * ub[0]) > math.sin(NEAR_PARALLEL):
                    continue
                opposite = ua @ ub < 0
                what = f"{where}: arrows {a0}->{a1} and {b0}->{b1} in {ax.get_title()!r}"
                if opposite:
                    assert np.linalg.norm(a1 - b1) >= HEADS_MEET * length, f"{what} meet head to head"
                if opposite and np.linalg.norm(a0 - b0) < 1e-9 * length:
                    continue  # two forces leaving one point, opposite
                assert _gap(a0, a1, b0, b1) >= TOUCHING * length, f"{what} touch"


def _assert_labels_off_arrows(figure, where, drawn=False):
    """No label lies across a force arrow, its shaft or its head (drum_and_block's "-m a_P" had its
    minus sign under the head of the T arrow). The head: the segment across the tip as wide as the
    head drawn ("-|>" at mutation scale 11 pt: 2.2 pt each side). A box's outer pixel is allowed
    (LABEL_OVERLAP_TOL: the renderer's rounding). ``drawn``: see :func:`_assert_labels_apart`."""
    from matplotlib.patches import FancyArrowPatch

    from solver.drawing.render import label_boxes

    if not drawn:
        figure.canvas.draw()
    for ax in (a for a in figure.axes if a.get_visible()):
        ends = [tuple(ax.transData.transform(np.array(q, float)) for q in p._posA_posB)
                for p in ax.patches if isinstance(p, FancyArrowPatch)]
        longest = max((np.linalg.norm(b - a) for a, b in ends), default=0.0)
        half = 2.2 * figure.dpi / 72
        shafts = []
        for a, b in ends:
            if np.linalg.norm(b - a) > 0.5 * longest:
                across = np.array([a[1] - b[1], b[0] - a[0]]) / np.linalg.norm(b - a)
                shafts += [a + np.linspace(0, 1, 400)[:, None] * (b - a),
                           b + np.linspace(-half, half, 20)[:, None] * across]
        texts = [t.get_text() for t in ax.texts if t.get_visible() and t.get_text()]
        for text, box in zip(texts, label_boxes(ax)):
            for pts in shafts:
                inside = ((pts[:, 0] > box.x0 + LABEL_OVERLAP_TOL) & (pts[:, 0] < box.x1 - LABEL_OVERLAP_TOL)
                          & (pts[:, 1] > box.y0 + LABEL_OVERLAP_TOL) & (pts[:, 1] < box.y1 - LABEL_OVERLAP_TOL))
                assert not inside.any(), f"{where}: label {text!r} lies on an arrow in {ax.get_title()!r}"


def _assert_couples_apart(figure, where):
    """No two couples' arcs overlap: each is drawn around its own centre, at least two radii from
    any other (the centre of an arc from three of its points, the test's own route)."""
    for ax in figure.axes:
        arcs = [np.column_stack(line.get_data()).astype(float) for line in ax.lines]
        arcs = [xy for xy in arcs if len(xy) == 39]  # a couple's arc: 40 samples less the arrowhead's end
        circles = []
        for xy in arcs:
            (x1, y1), (x2, y2), (x3, y3) = xy[0], xy[19], xy[-1]
            d = 2 * (x1 * (y2 - y3) + x2 * (y3 - y1) + x3 * (y1 - y2))
            cx = ((x1**2 + y1**2) * (y2 - y3) + (x2**2 + y2**2) * (y3 - y1) + (x3**2 + y3**2) * (y1 - y2)) / d
            cy = ((x1**2 + y1**2) * (x3 - x2) + (x2**2 + y2**2) * (x1 - x3) + (x3**2 + y3**2) * (x2 - x1)) / d
            circles.append((np.array([cx, cy]), math.dist((cx, cy), (x1, y1))))
        for i, (c, r) in enumerate(circles):
            for c2, r2 in circles[:i]:
                assert np.linalg.norm(c - c2) >= r + r2, f"{where}: couple arcs overlap in {ax.get_title()!r}"


def _assert_labels_apart(figure, where, drawn=False):
    """No two labels overlap, and none is cut off by the figure's edge, in the final layout.

    ``drawn``: the figure was drawn for an earlier check of the same test and not changed since, so
    its layout is the final one (matplotlib leaves a figure ``stale`` after drawing it: the label
    placer moves texts while drawing; drawing it again gives the same boxes, and costs 0.04-0.12 s
    of CPU a diagram). By default the figure is drawn here."""
    from solver.drawing.render import label_boxes

    if not drawn:
        figure.canvas.draw()  # the final layout, as saved
    shown = [ax for ax in figure.axes if ax.get_visible()]
    # a panel's background would hide the end of a neighbour's label that runs into it (slider_crank's
    # "-A_x = 751.9 N" lost its " N" under the rod's panel): no panel has one, and the labels of all
    # panels are kept apart together
    assert not any(ax.patch.get_visible() for ax in shown), f"{where}: a panel with a background"
    boxes = [b for ax in shown for b in label_boxes(ax)]
    texts = [t.get_text() for ax in shown for t in ax.texts if t.get_visible() and t.get_text()]
    frame = figure.bbox
    for text, box in zip(texts, boxes):  # inside the figure: a label past its edge is cut off
        assert (box.x0 >= frame.x0 - LABEL_OVERLAP_TOL and box.x1 <= frame.x1 + LABEL_OVERLAP_TOL
                and box.y0 >= frame.y0 - LABEL_OVERLAP_TOL and box.y1 <= frame.y1 + LABEL_OVERLAP_TOL), \
            f"{where}: label {text!r} is cut off by the figure's edge ({box.extents} in {frame.extents})"
    for i, a in enumerate(boxes):
        for j in range(i):
            b = boxes[j]
            wide = min(a.x1, b.x1) - max(a.x0, b.x0)
            high = min(a.y1, b.y1) - max(a.y0, b.y0)
            assert wide <= LABEL_OVERLAP_TOL or high <= LABEL_OVERLAP_TOL, \
                f"{where}: labels {texts[i]!r} and {texts[j]!r} overlap ({wide:.1f} x {high:.1f} px)"


# A bar is drawn 5 pt wide (solver.drawing.render._element): a label must clear its centre line by
# half that, less LABEL_OVERLAP_TOL, or the stroke runs through the text.
BAR_HALF_WIDTH_PT = 2.5


def _sample(a, b, n=200):
    return a + np.linspace(0, 1, n)[:, None] * (b - a)


def _to_box(box, pts) -> float:
    """Least distance [display pixels] from a label's box to the points ``pts`` (0 inside)."""
    dx = np.maximum(np.maximum(box.x0 - pts[:, 0], pts[:, 0] - box.x1), 0.0)
    dy = np.maximum(np.maximum(box.y0 - pts[:, 1], pts[:, 1] - box.y1), 0.0)
    return float(np.min(np.hypot(dx, dy)))


def _assert_labels_by_what_they_name(fbd, scene, where, drawn=False):
    """On every free-body diagram, no label is crossed by its body's bars or frame (QA9 item 11: a
    couple's label lay across the bar), and each label of a drawn force or couple is nearer an arrow
    or arc of that force or couple than any other (the weight's label sat by A's reaction at A): the
    nearest arrow must point along the force and lie on its line of action through its point; the
    nearest arc must turn its way, dashed for the inertial couple; no two labels share the nearest.
    ``scene``: the scene's drawn items (solver.drawing.model.scene_items), which give the bars;
    ``drawn``: see :func:`_assert_labels_apart`."""
    from matplotlib.patches import FancyArrowPatch

    from solver.drawing.render import label_boxes

    if not drawn:  # the layout as saved
        fbd.figure.canvas.draw()
    shown = [ax for ax in fbd.figure.axes if ax.get_visible()]
    for ax, body in zip(shown, fbd.panels):
        to = ax.transData.transform
        bars = [_sample(*(to(np.array(e, float)) for e in i.shape["ends"])) for i in scene
                if i.body == body and i.kind == "element" and i.shape["type"] == "bar"]
        bars += [_sample(to(np.array(p, float)), to(np.array(q, float))) for i in scene
                 if i.body == body and i.kind == "link" for p, q in zip(i.shape["points"][:-1], i.shape["points"][1:])]
        ends = [tuple(np.array(q, float) for q in p._posA_posB) for p in ax.patches if isinstance(p, FancyArrowPatch)]
        longest = max((np.linalg.norm(b - a) for a, b in ends), default=0.0)
        arrows = [(a, b) for a, b in ends if np.linalg.norm(b - a) > 0.5 * longest]  # not an arc's head
        arcs = [line for line in ax.lines if len(line.get_xdata()) == 39]  # as in _assert_couples_apart
        drawn = [_sample(to(a), to(b)) for a, b in arrows] + [to(np.column_stack(a.get_data()).astype(float))
                                                               for a in arcs]

        def names(k, item):  # whether drawn thing k may be the arrow or arc of item
            if k < len(arrows):
                a, b = arrows[k]
                u = (b - a) / np.linalg.norm(b - a)
                r = np.array(item.anchor) - a
                return item.direction is not None and np.allclose(u, item.direction, atol=DIRECTION_TOL) and \
                    abs(r[0] * u[1] - r[1] * u[0]) <= 0.5 * longest and \
                    min(np.linalg.norm(r), np.linalg.norm(np.array(item.anchor) - b)) <= 0.5 * longest
            xy = np.column_stack(arcs[k - len(arrows)].get_data()).astype(float)
            c = xy.mean(axis=0)  # inside the 270 deg arc: the sense from the turn of its first step
            (x0, y0), (x1, y1) = xy[0] - c, xy[1] - xy[0]
            turn = np.sign(x0 * y1 - y0 * x1)
            dashed = arcs[k - len(arrows)].get_linestyle() == "--"
            return item.turn == turn and dashed == (item.kind == "inertial_couple")

        items = {i.label: i for i in fbd.on(body) if i.direction is not None or i.turn != 0}
        nearest = {}
        texts = [t.get_text() for t in ax.texts if t.get_visible() and t.get_text()]
        for text, box in zip(texts, label_boxes(ax)):
            what = f"{where}: label {text!r} in {ax.get_title()!r}"
            grown = BAR_HALF_WIDTH_PT * fbd.figure.dpi / 72 - LABEL_OVERLAP_TOL
            assert all(_to_box(box, pts) >= grown for pts in bars), f"{what} is crossed by the body"
            if text in items:
                gaps = [_to_box(box, pts) for pts in drawn]
                k = int(np.argmin(gaps))
                assert names(k, items[text]), f"{what} is nearer another arrow or arc than its own"
                assert k not in nearest, f"{what} and {nearest.get(k)!r} are by one arrow or arc"
                nearest[k] = text


def _assert_no_moment_about_P(fbd, P, body, where):
    """Eq. 10 read off the drawing: the drawn forces and couples, with the dashed -m a_P at G
    and -I_P alpha, have zero moment about P (each arrow's size is in shape["size"], SI). An
    arrow drawn the wrong way, at the wrong point or with the wrong size breaks the balance."""
    moment, scale = 0.0, 0.0
    for i in fbd.on(body):
        if i.kind in ("force", "inertial") and i.direction is not None:
            r = np.array(i.anchor) - P
            f = i.shape["size"] * np.array(i.direction)
            moment += r[0] * f[1] - r[1] * f[0]
            scale += abs(r[0] * f[1]) + abs(r[1] * f[0])
        elif i.kind in ("couple", "inertial_couple"):
            moment += i.turn * i.shape["size"]
            scale += i.shape["size"]
    # round-off of sums of ~10 products of float64 values: 1e-9 of the largest term
    assert abs(moment) <= 1e-9 * max(scale, 1e-12), f"{where}: moment about {body}:{fbd.point[body]} = {moment}"


def test_free_body_values_by_the_walk_and_by_the_compiled_fallback():
    """The values the free-body diagrams draw: by one tree walk, or, where a node is one the walk
    does not know (atan2), by numpy for the whole list; nan where a value is not real, either way.
    (1e-15 relative: a few double-precision operations; the reference is the math module.)"""
    from solver.drawing.model import _evaluate

    system = load_system(SCENES[0])
    state = start_state(system)
    q, x = system.q[0], state.q[0]
    walked = _evaluate(system, [sp.sin(q) + 1, sp.sqrt(-1 - q**2)], state)
    compiled = _evaluate(system, [sp.sin(q) + 1, sp.sqrt(-1 - q**2), sp.atan2(q, 1)], state)
    for values in (walked, compiled):
        assert values[0] == pytest.approx(math.sin(x) + 1, rel=1e-15)
        assert math.isnan(values[1])
    assert compiled[2] == pytest.approx(math.atan2(x, 1), rel=1e-15)


def test_inertial_force_follows_the_kinematics_of_the_paper():
    """Example 2 about P: x_P = r_d theta (Eq. 31), so a_P = r_d theta_ddot i and the dashed
    arrow is -(m_d + m_b) r_d theta_ddot i. Example 1 about A: A runs on the horizontal rail,
    so -m a_A is horizontal."""
    system = load_system(ROOT / "data" / "scenes" / "disk_bar.toml")
    drawing = draw_system(system, fbd=True)
    (item,) = drawing.of_kind("inertial")
    theta_ddot = float(solve_instant(system).unknowns["theta_ddot"].magnitude)
    p = {k: float(v.to_base_units().magnitude) for k, v in system.parameters.items()}
    expected = -(p["m_d"] + p["m_b"]) * p["r_d"] * theta_ddot
    # the label's 4 significant figures are not used: value is the float itself (1e-12: round-off)
    assert item.value == pytest.approx(abs(expected), rel=1e-12)
    np.testing.assert_allclose(item.direction, [np.sign(expected), 0.0], atol=DIRECTION_TOL)

    system = load_system(ROOT / "data" / "scenes" / "sliding_bar.toml")
    (item,) = draw_system(system, fbd=True, point="A").of_kind("inertial")
    assert abs(item.direction[1]) < DIRECTION_TOL and item.unit == "lbf"


@pytest.mark.parametrize("suffix,magic", [(".svg", b"<?xml"), (".png", b"\x89PNG"), (".pdf", b"%PDF")])
def test_draw_command_writes_the_format_of_the_suffix(tmp_path, suffix, magic, capsys):
    out = tmp_path / f"crank{suffix}"
    fbd = ["--fbd"] if suffix == ".svg" else []  # one diagram of each kind is enough to check the format
    status = main(["draw", str(ROOT / "data" / "scenes" / "sliding_bar.toml"), *fbd, "-o", str(out)])
    assert status == 0
    assert out.read_bytes().startswith(magic)
    assert [p.name for p in tmp_path.iterdir()] == [out.name]  # nothing left behind


def test_draw_command_refuses_an_unknown_suffix(tmp_path, capsys):
    out = tmp_path / "crank.jpg"
    with pytest.raises(SystemExit) as stop:
        main(["draw", str(ROOT / "data" / "scenes" / "sliding_bar.toml"), "-o", str(out)])
    assert stop.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("error: -o ") and ".svg" in err
    assert not out.exists() and list(tmp_path.iterdir()) == []


def test_simulate_animates_the_trajectory(tmp_path, capsys):
    """simulate --animate: one GIF frame per sample (under the cap), from the multibody path."""
    from PIL import Image

    out = tmp_path / "crank.gif"
    status = main(["simulate", str(ROOT / "data" / "scenes" / "slider_crank.toml"), "--t-end", "0.01 s",
                   "--samples", "4", "--animate", str(out), "--json"])
    assert status == 0
    with Image.open(out) as gif:
        assert gif.format == "GIF" and gif.n_frames == 4


def test_animation_draws_the_cart_track_once_and_long_enough(tmp_path, monkeypatch):
    """QA 19 #10: cart_pendulum's track (the slider's hatched line) was sized to the scene of each
    frame, so it travelled with the cart. It is drawn once, before the frames, and reaches past
    the cart's centre C in every frame (the cart moves +x at 0.5 m/s from x = 0 over 1 s)."""
    from solver.drawing import render

    drawn = []
    original = render.render_scene
    monkeypatch.setattr(render, "render_scene", lambda ax, items, *a, **k: (drawn.append(list(items)),
                                                                             original(ax, items, *a, **k))[1])
    out = tmp_path / "cart.gif"
    assert main(["simulate", str(ROOT / "data" / "scenes" / "cart_pendulum.toml"), "--t-end", "1 s",
                 "--samples", "6", "--animate", str(out)]) == 0
    fixed, frames = drawn[0], drawn[1:]
    assert len(frames) == 6
    track = [i for i in fixed if i.kind == "guide" and i.name == "track"]
    assert len(track) == 1 and not any(i.kind == "guide" for f in frames for i in f)
    (x0, y0), (x1, y1) = track[0].shape["ends"]
    cart = [i.anchor[0] for f in frames for i in f if i.kind == "point" and i.body == "cart" and i.name == "C"]
    assert len(cart) == 6 and cart[-1] - cart[0] > 0.3, cart    # the cart does move along the track
    assert y0 == y1 == 0 and min(x0, x1) < min(cart) and max(x0, x1) > max(cart)


@pytest.mark.parametrize("scene", ["slider_crank.toml", "disk_bar.toml"])  # the multibody route; the one-body one
def test_simulate_says_once_and_last_that_the_animation_was_written(tmp_path, capsys, scene):
    """QA 11: the line saying the animation was written came first, before the run's summary (or
    not at all): like the other outputs' lines it comes once, after the file is written."""
    out = tmp_path / "run.gif"
    assert main(["simulate", str(ROOT / "data" / "scenes" / scene), "--t-end", "0.01 s", "--samples", "2",
                 "--animate", str(out)]) == 0
    lines = capsys.readouterr().out.strip().splitlines()
    assert out.stat().st_size > 0
    assert lines[-1] == f"animation written to {out}" and sum("animation" in line for line in lines) == 1, lines


def test_animation_frames_are_capped_and_spread():
    from solver.drawing import MAX_FRAMES, frame_indices

    assert frame_indices(3) == [0, 1, 2]
    many = frame_indices(10 * MAX_FRAMES + 7)
    assert len(many) == MAX_FRAMES and many[0] == 0 and many[-1] == 10 * MAX_FRAMES + 6
    steps = np.diff(many)
    assert steps.max() - steps.min() <= 1  # evenly spread


@pytest.mark.skipif(__import__("shutil").which("ffmpeg") is not None, reason="ffmpeg is installed here")
def test_mp4_without_ffmpeg_is_one_line_before_the_run(tmp_path, capsys):
    out = tmp_path / "run.mp4"
    with pytest.raises(SystemExit) as stop:
        main(["simulate", str(ROOT / "data" / "scenes" / "disk_bar.toml"), "--t-end", "1 s", "--animate", str(out)])
    assert stop.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--animate" in err and "ffmpeg" in err and not out.exists()


def test_paper_figures_1_to_3_are_drawn_from_the_scenes(tmp_path_factory):
    """paper.html embeds Figures 1-3 as inline SVG, with the rod's pin forces as the solver
    gives them; paper.tex includes their PDF twins, which the build writes."""
    import re

    from reports.make_report import build_cached

    out = Path(build_cached(tmp_path_factory.getbasetemp() / "report_build", ROOT)["out"])
    html = (out / "paper.html").read_text(encoding="utf-8")
    tex = (out / "paper.tex").read_text(encoding="utf-8")
    system = load_system(ROOT / "data" / "scenes" / "slider_crank.toml")
    solution = solve_instant(system)
    for n, stem in ((1, "figure1_slider_crank"), (2, "figure2_sliding_bar"), (3, "figure3_disk_bar")):
        figure = re.search(rf'<figure id="figure{n}">(.*?)</figure>', html, re.S)
        assert figure and "<svg" in figure.group(1), f"Figure {n} missing from paper.html"
        assert f"figures/{stem}.pdf" in tex and (out / "figures" / f"{stem}.pdf").stat().st_size > 1000
    # the captions in the paper's notation in both outputs (QA10 item 6): θ (φ) and −m a_P in the HTML, as
    # maths in the TeX (pdflatex knows no Unicode minus or Greek letter in text)
    captions = re.findall(r"<figcaption>(Figure \d.*?)</figcaption>", html, re.S)
    assert len(captions) == 3 and all(("\u03b8" in c or "\u03c6" in c) and "\u2212m a_" in c
                                       and "theta" not in c and "phi" not in c for c in captions)
    tex_captions = [line for line in tex.splitlines() if line.startswith("\\par\\medskip{\\small Figure")]
    assert len(tex_captions) == 3 and all(("\\ensuremath{\\theta}" in c or "\\ensuremath{\\phi}" in c) and "\\ensuremath{-}m a" in c
                                          and "\u2212" not in c and "theta =" not in c for c in tex_captions)
    rod = re.search(r'<figure id="figure1">(.*?)</figure>', html, re.S).group(1)
    for name in ("A_x", "A_y", "B_x", "B_y"):  # on the rod, sizes to 4 significant figures (the arrows give the sense)
        size = re.search(rf"\|{name}\| = (\S+) N", rod)
        assert size and _four_figures(size.group(1), abs(solution.unknowns[name].magnitude)), name


@pytest.mark.parametrize("name, scene_file, body, number", PAPER_SCENE_FIGURES)
def test_paper_figures_keep_their_labels_apart(name, scene_file, body, number, paper_figure):
    """Figures 1-3 place both panels' labels once, in the whole figure's layout (the scene is
    drawn with arrange_labels=False): as saved, no two labels overlap in either panel."""
    figure, _ = paper_figure(scene_file, name, number, body)
    assert sum(len(ax.texts) for ax in figure.axes) > 4  # both panels carry labels
    _assert_labels_apart(figure, name)


def test_the_command_line_starts_without_matplotlib():
    """matplotlib is imported only when something is drawn: no module that registering the
    commands imports (cli_draw, cli_dynamics, the drawing package itself) imports it at the top."""
    import ast

    for module in ("solver/cli_draw.py", "solver/cli_dynamics.py", "solver/drawing/__init__.py", "solver/__main__.py"):
        tree = ast.parse((ROOT / module).read_text(encoding="utf-8"))
        top = [n for n in tree.body if isinstance(n, (ast.Import, ast.ImportFrom))]
        names = [a.name for n in top for a in n.names] + [n.module or "" for n in top if isinstance(n, ast.ImportFrom)]
        assert not any(n.split(".")[0] in ("matplotlib", "PIL") or n.endswith("render") for n in names), module


@pytest.mark.parametrize("name, zeros", [("drum_and_block", {"axle_x", "N_guide"}), ("ladder_leaves_wall", {"N_top"})])
def test_a_zero_force_is_a_label_not_an_arrow(name, zeros):
    """A reaction that is zero at the state has no direction to show: its free-body diagram draws
    no arrow for it (once a faint arrow along its positive sense, which reads as a force) and lists
    it in its label as zero. Checked on the rendered panels: no arrow has an end at the force's
    point and lies along its line (another force at the same point, such as axle_y beside axle_x,
    lies across it); the label `|NAME| = 0 UNIT` is on the panel."""
    import matplotlib.pyplot as plt
    from matplotlib.patches import FancyArrowPatch

    system = load_system(ROOT / "data" / "scenes" / f"{name}.toml")
    drawing = draw_system(system, fbd=True)
    try:
        zero = [i for i in drawing.items if i.kind == "force" and i.direction is None and i.name in zeros]
        assert {i.name for i in zero} == zeros  # the premise: these are the scene's zero reactions
        panels = dict(zip(drawing.panels, drawing.figure.axes))
        for item in zero:
            ax = panels[item.body]
            assert f"|{item.name}| = 0 {_written(item.unit)}" in {t.get_text() for t in ax.texts}
            positive = np.asarray(item.shape["positive"], float)
            for patch in ax.patches:
                if not (isinstance(patch, FancyArrowPatch) and getattr(patch, "_posA_posB", None)):
                    continue
                a, b = (np.asarray(p, float) for p in patch._posA_posB)
                along = b - a
                # ends within 1e-9 of the panel's size (round-off), direction within 1e-6 rad
                at_point = min(np.hypot(*(a - item.anchor)), np.hypot(*(b - item.anchor))) <= 1e-9 * np.hypot(*along)
                parallel = abs(along[0] * positive[1] - along[1] * positive[0]) <= 1e-6 * np.hypot(*along)
                assert not (at_point and parallel), f"{name}: {item.name} is drawn as an arrow"
    finally:
        plt.close(drawing.figure)


def test_a_moving_ground_point_is_drawn_where_it_is_at_each_time(tmp_path, monkeypatch):
    """A pivot on a prescribed path (ground point P = [A sin(w t), 0], A = 0.1 m, w = 5 rad/s):
    draw, the free-body diagram and each animation frame show P, its support and the bar's end O
    where the path puts them at that frame's time (they were refused with an internal error)."""
    from solver.analyses.instant import State
    from solver.drawing import render

    scene = ROOT / "tests" / "data" / "multibody" / "moving_pivot.toml"
    system = load_system(scene)
    at = State(q=start_state(system).q, qd=(0.0,), t=0.3)
    pivot = (0.1 * math.sin(5 * 0.3), 0.0)  # the path at t = 0.3 s, by hand
    drawn = draw_system(system, at)
    for item in drawn.of_kind("point", "support"):
        if item.body == GROUND or item.name == "O":
            np.testing.assert_allclose(item.anchor, pivot, atol=POSITION_TOL, err_msg=item.label)
    fbd = draw_system(system, at, fbd=True)
    pin = [i for i in fbd.items if i.name in ("pin_1_x", "pin_1_y")]  # the pin's reactions act at the pivot
    assert len(pin) == 2 and all(i.anchor == pytest.approx(pivot, abs=POSITION_TOL) for i in pin)

    frames = []
    keep = render.render_scene
    monkeypatch.setattr(render, "render_scene", lambda ax, items, *a, **k: frames.append(items) or keep(ax, items, *a, **k))
    out = tmp_path / "pivot.gif"
    assert main(["simulate", str(scene), "--t-end", "0.3 s", "--samples", "2", "--animate", str(out)]) == 0
    from PIL import Image

    with Image.open(out) as gif:
        assert gif.n_frames == 2
    # the first call draws what never changes (nothing of the ground here: its one point moves), then one per frame
    supports = [[i.anchor for i in items if i.kind == "support"] for items in frames[1:]]
    assert supports[0][0] == pytest.approx((0.0, 0.0), abs=POSITION_TOL)  # t = 0
    assert supports[1][0] == pytest.approx(pivot, abs=POSITION_TOL)  # t = 0.3 s


def test_labels_give_sizes_and_arrows_the_sense_for_reactions_and_loads_alike():
    """A bar on a pin at 30 deg, turning at 1 rad/s, with a spring and a damper from the ground point
    S = (L, -L) to its tip E. O_x is solved negative and the damper shortens (its tension
    c dL/dt < 0, a push): both are drawn as arrows in their actual sense labelled with their size,
    and the diagram says so under it. Before, O_x was an arrow to the left labelled "O_x = -17.96 N"
    and the damper's push was labelled "damper_3 = 1.697 N", a magnitude, unlike the reactions."""
    system = load_system(ROOT / "tests" / "data" / "multibody" / "pendulum_loads.toml")
    fbd = draw_system(system, fbd=True)
    o_x = float(fbd.solution.unknowns["O_x"].to("N").magnitude)
    assert o_x < 0
    (item,) = [i for i in fbd.items if i.name == "O_x"]
    assert _four_figures(_size_of(item.label, "O_x", "N"), -o_x), item.label
    np.testing.assert_allclose(item.direction, [-1.0, 0.0], atol=DIRECTION_TOL)  # O_x < 0 on the bar: to the left

    # the damper by hand: E = L (sin th, -cos th), v_E = L th' (cos th, sin th), tension c u.(v_E - 0), u from S to E
    L, c, th, th_dot = 0.8, 3.0, math.radians(30), 1.0
    E, S = L * np.array([math.sin(th), -math.cos(th)]), np.array([L, -L])
    u = (E - S) / np.linalg.norm(E - S)
    tension = c * float(u @ (L * th_dot * np.array([math.cos(th), math.sin(th)])))
    assert tension < 0  # the damper is being shortened: it pushes E away from S
    (item,) = [i for i in fbd.items if i.name == "damper_3"]
    assert _four_figures(_size_of(item.label, "damper_3", "N"), -tension), item.label
    np.testing.assert_allclose(item.direction, u, atol=DIRECTION_TOL)
    legend = fbd.figure.axes[0].get_xlabel()
    assert legend.startswith("Arrows and arcs: each force and couple in its actual sense at this state; |X| = its size.")


def test_springs_and_dampers_are_drawn_between_their_points():
    """The scene drawing of a bar with a spring and a damper from the ground point S = (L, -L) to its
    tip E (L = 0.8 m, theta = 30 deg): each is an item between S and E, the spring drawn as a
    zigzag from S to E, the damper as a dashpot beside it (before, S was drawn alone, floating)."""
    system = load_system(ROOT / "tests" / "data" / "multibody" / "pendulum_loads.toml")
    drawing = draw_system(system)
    L, th = 0.8, math.radians(30)
    S, E = np.array([L, -L]), L * np.array([math.sin(th), -math.cos(th)])  # by hand
    for kind, name in (("spring", "spring_2"), ("damper", "damper_3")):
        (item,) = [i for i in drawing.of_kind(kind) if i.name == name]
        np.testing.assert_allclose(np.array(item.shape["ends"]), [S, E], atol=POSITION_TOL)
        assert item.label == name
    (ax,) = drawing.figure.axes
    lines = [np.column_stack(line.get_data()).astype(float) for line in ax.lines]
    lines = [xy for xy in lines if len(xy) > 1]  # not the points' dots
    along = (E - S) / np.linalg.norm(E - S)
    side = lambda xy: np.sign((xy - S) @ np.array([-along[1], along[0]]))  # noqa: E731 - which side of line S-E
    from_S = [xy for xy in lines if np.allclose(xy[0], S, atol=POSITION_TOL)]
    to_E = [xy for xy in lines if np.allclose(xy[-1], E, atol=POSITION_TOL)]
    # the spring: one polyline from S to E crossing its own lane's centre line 8 times or more (a zigzag)
    zigzags = [xy for xy in from_S if np.allclose(xy[-1], E, atol=POSITION_TOL) and len(xy) >= 12]
    assert len(zigzags) == 1
    middle = zigzags[0][3:-3]  # the coils, off the lane: their sides about the lane's centre alternate
    lane_centre = middle.mean(axis=0)
    turns = np.sign((middle - lane_centre) @ np.array([-along[1], along[0]]))
    assert np.count_nonzero(np.diff(turns[turns != 0])) >= 6
    # the damper: its own rod from S and rod to E, on the other side of S-E than the spring's coils
    damper_rods = [xy for xy in from_S + to_E if len(xy) == 3]
    assert len(damper_rods) == 2 and {side(xy[1]) for xy in damper_rods} == {-side(lane_centre)}


@pytest.mark.parametrize("scene, point, rates, bodies", [
    ("data/scenes/disk_bar.toml", None, None, None),  # the weight from G ran into F_n's head at C
    ("data/scenes/disk_bar.toml", "C", (3.0,), None),  # -m a_C lay on the weight, both down from G
    ("data/scenes/slider_crank.toml", None, None, None),  # the piston's weight close beside N_cyl
    ("data/scenes/drum_and_block.toml", None, None, ["block"]),  # as explain draws it: -m a_P's label on T's head
    ("tests/data/multibody/pendulum_loads.toml", None, None, None),  # four couples' arcs, one inside another
])
def test_free_body_diagrams_keep_arrows_couples_and_labels_apart(scene, point, rates, bodies):
    """The overlaps a new user found, by general rules: arrows that would read as one are drawn
    arriving at their point, or beside it; couples (free vectors) each at its own place on the body."""
    from solver.analyses.instant import State

    system = load_system(ROOT / scene)
    state = start_state(system)
    if rates is not None:
        state = State(q=state.q, qd=rates, t=state.t)
    fbd = draw_system(system, state, fbd=True, point=point, bodies=bodies)
    _assert_arrows_apart(fbd.figure, scene)
    _assert_couples_apart(fbd.figure, scene)
    _assert_labels_apart(fbd.figure, scene)
    _assert_labels_off_arrows(fbd.figure, scene, drawn=True)


def test_labels_stay_off_the_bars_and_by_what_they_name():
    """QA9 item 11: on the upper bar the damper's couple label lay across the bar and the weight's
    arrow, the weight's label sat by A (nearer A's reaction than the weight), and on the lower bar the
    damper's label lay under B, away from both arcs. (Every shipped scene is checked alike in
    test_drawing_matches_the_scene.)"""
    system = load_system(ROOT / "tests" / "data" / "multibody" / "two_bar_springs.toml")
    state = start_state(system)
    fbd = draw_system(system, state, fbd=True)
    _assert_labels_off_arrows(fbd.figure, "two_bar_springs")
    _assert_labels_apart(fbd.figure, "two_bar_springs", drawn=True)
    from solver.drawing.model import scene_items

    _assert_labels_by_what_they_name(fbd, scene_items(system, state), "two_bar_springs", drawn=True)


def test_animation_frames_name_a_pin_once(tmp_path, monkeypatch):
    """In each frame the pin O (the ground's point O and the bar's point O at one place) is named once,
    as in the still drawing; the ground's name, drawn once for all frames under the bar's, made a
    smudged double "O". The spring and damper move with the bar: they are drawn in every frame."""
    from solver.drawing import render

    seen = []
    keep = render.render_scene

    def record(ax, items, *a, **k):
        keep(ax, items, *a, **k)
        seen.append(([t.get_text() for t in ax.texts], {i.kind for i in items}))

    monkeypatch.setattr(render, "render_scene", record)
    out = tmp_path / "bar.gif"
    scene = ROOT / "tests" / "data" / "multibody" / "pendulum_loads.toml"
    assert main(["simulate", str(scene), "--t-end", "0.2 s", "--samples", "2", "--animate", str(out)]) == 0
    frames = seen[1:]  # the first call draws what never changes
    assert len(frames) == 2
    for texts, kinds in frames:
        assert texts.count("O") == 1, texts
        assert {"spring", "damper"} <= kinds


def test_torsional_springs_and_dampers_are_drawn_about_their_pin():
    """The bar's torsional spring and damper act between the ground and the bar, which the pin O
    at (0, 0) joins: each is drawn about O (before, neither was drawn at all). The spring is a
    spiral: its distance from O grows along it, through two turns; the damper an arc at one
    distance from O, outside the spiral."""
    system = load_system(ROOT / "tests" / "data" / "multibody" / "pendulum_loads.toml")
    drawing = draw_system(system)
    found = {i.kind: i for i in drawing.of_kind("torsional_spring", "torsional_damper")}
    assert set(found) == {"torsional_spring", "torsional_damper"}
    for item in found.values():
        np.testing.assert_allclose(item.anchor, (0.0, 0.0), atol=POSITION_TOL)
        assert item.label == item.name
    (ax,) = drawing.figure.axes
    lines = [np.column_stack(line.get_data()).astype(float) for line in ax.lines]
    radii = [np.hypot(xy[:, 0], xy[:, 1]) for xy in lines if len(xy) > 40]  # the long curves
    spirals = [r for r in radii if np.all(np.diff(r) > 0)]
    arcs = [r for r in radii if np.ptp(r) < 1e-9 * r.max()]
    assert len(spirals) == 1 and len(arcs) == 1
    (xy,) = [xy for xy in lines if len(xy) > 40 and np.all(np.diff(np.hypot(xy[:, 0], xy[:, 1])) > 0)]
    turned = np.sum(np.diff(np.unwrap(np.arctan2(xy[:, 1], xy[:, 0]))))
    assert turned == pytest.approx(4 * math.pi, rel=1e-9)  # two turns, counter-clockwise
    assert arcs[0][0] > spirals[0][-1]  # the damper outside the spring


# The measured layout against matplotlib's own measure of each panel after drawing (Axes.get_tightbbox
# for layouts: tick labels, axis labels across their axis, title, legends; as in matplotlib's
# constrained layout, an axis label longer than its panel may run past the panel's ends). 1 px: the
# layout and the check round text extents alike but place the axis labels by two routes (sums of
# sizes in the layout, matplotlib's positions in the check).
LAYOUT_TOL_PX = 1.0


def _awkward_figure(rows: int, cols: int, aspect: bool = False):
    """Texts of every kind the report's figures have, made long: wide tick labels, a two-line axis
    label, a legend anchored above its panel, a suptitle and a figure legend at the bottom edge;
    with ``aspect``, square panels (as the scene drawings) under a legend wider than its panel."""
    from matplotlib.figure import Figure

    from solver.drawing.layout import MeasuredLayout

    fig = Figure(figsize=(7.0, 4.5), layout=MeasuredLayout())
    axes = fig.subplots(rows, cols, squeeze=False, sharex=cols == 1).ravel()
    for k, ax in enumerate(axes):
        x = np.linspace(0.0, 10.0 ** (k + 1), 50)
        ax.plot(x, -123456.0 * np.sin(x / x[-1] * 6) * (k + 1), label=f"curve {k}")
        ax.set_ylabel(f"R_{k}\n[lbf·ft/s²]")
        ax.set_title(f"panel {k}: its title")
    axes[0].legend(loc="lower center", bbox_to_anchor=(0.5, 1.1), ncol=2)
    axes[-1].set_xlabel("release angle theta [deg] (from rest)\nsecond line of the label")
    if aspect:
        for ax in axes:
            ax.set_aspect("equal", adjustable="box")
            ax.set_ylim(-0.5 * ax.get_xlim()[1], 0.5 * ax.get_xlim()[1])
        axes[0].set_xlabel("Arrows and arcs: each force and couple in its actual sense at this state; |X| = "
                           "its size.\nDashed: the inertial terms at G (Eq. 10), a legend wider than its panel")
    fig.suptitle("A suptitle above every panel", fontsize=12)
    fig.legend(["figure legend at the bottom edge"], loc="outside lower center")
    return fig, list(axes)


@pytest.mark.parametrize("rows, cols, aspect", [(2, 1, False), (1, 2, False), (3, 1, False), (1, 2, True)])
def test_measured_layout_fits_every_text_and_wastes_no_room(rows, cols, aspect):
    """Every panel's texts (matplotlib's tight box of the panel, as drawn, and its axis labels) lie
    inside the figure, clear of the other panels, of the suptitle and of the figure legend; and the
    layout leaves no more than its clearance between the outermost texts and the figure's edges
    (square panels excepted: their aspect leaves room free on two sides)."""
    from matplotlib.transforms import Bbox

    from solver.drawing.layout import LAYOUT_PAD, agg_renderer

    fig, axes = _awkward_figure(rows, cols)
    renderer = agg_renderer(fig)
    fig.draw(renderer)  # the layout engine runs, then every text is placed as saved
    frame = fig.bbox
    # a title and the axis labels are given their whole size (so that two panels' titles cannot meet and
    # a legend under a square panel is not cut off)
    boxes = [Bbox.union([ax.get_tightbbox(renderer, for_layout_only=True),
                         *(t.get_window_extent(renderer) for t in (ax.title, ax.xaxis.label, ax.yaxis.label)
                           if t.get_text())])
             for ax in axes]
    figure_texts = [t.get_window_extent(renderer) for t in fig.texts] + \
                   [leg.get_window_extent(renderer) for leg in fig.legends]
    for k, box in enumerate(boxes):
        assert frame.x0 - LAYOUT_TOL_PX <= box.x0 and box.x1 <= frame.x1 + LAYOUT_TOL_PX, f"panel {k} cut off"
        assert frame.y0 - LAYOUT_TOL_PX <= box.y0 and box.y1 <= frame.y1 + LAYOUT_TOL_PX, f"panel {k} cut off"
        for other in boxes[:k] + figure_texts:
            wide = min(box.x1, other.x1) - max(box.x0, other.x0)
            high = min(box.y1, other.y1) - max(box.y0, other.y0)
            assert wide <= LAYOUT_TOL_PX or high <= LAYOUT_TOL_PX, f"panel {k} overlaps {other.extents}"
    if aspect:
        return
    pad = LAYOUT_PAD * fig.dpi / 72.0
    used = [min(b.x0 for b in boxes), min(b.y0 for b in boxes), max(b.x1 for b in boxes), max(b.y1 for b in boxes)]
    # the room left at each edge: the clearance, plus the figure legend (bottom) and suptitle (top)
    bottom = max(b.y1 for b in figure_texts[1:])
    top = frame.y1 - figure_texts[0].y0
    for edge, room in zip(("left", "bottom", "right", "top"),
                          (used[0] - frame.x0, used[1] - bottom, frame.x1 - used[2], frame.y1 - top - used[3])):
        assert room <= pad + LAYOUT_TOL_PX, f"{edge}: {room:.1f} px left unused"


def test_a_given_solution_is_drawn_as_the_one_solved_here():
    """draw_system takes the caller's instant solution (the report's, shared by its checks and
    Figure 2) and draws exactly what it draws when it solves the state itself; a state other
    than the solution's is refused."""
    from matplotlib.figure import Figure

    system = load_system(ROOT / "data" / "scenes" / "sliding_bar.toml")
    solution = solve_instant(system)
    drawn = []
    for given in (None, solution):
        axes = Figure().subplots(1, 1, squeeze=False).ravel().tolist()
        fbd = draw_system(system, None if given else solution.state, ax=axes, fbd=True, solution=given)
        drawn.append([(i.kind, i.label, i.anchor, i.direction) for i in fbd.items])
    assert drawn[0] == drawn[1] and len(drawn[0]) > 3
    with pytest.raises(ValueError, match="one state"):
        draw_system(system, start_state(system), ax=[Figure().add_subplot()], fbd=True, solution=solution)


MULTIBODY = ROOT / "tests" / "data" / "multibody"


def test_a_prescribed_coordinate_is_marked_and_said_to_be_prescribed():
    """QA10 item 12: the four-bar's driven crank angle th2 (motion = pi/3 + W t) was not marked,
    th3 and th4 were. Every coordinate is marked; th2's arc sweeps pi/3 at t = 0 from the fixed
    frame's x axis to the crank (its value by the motion, computed here), labelled as prescribed."""
    system = load_system(MULTIBODY / "driven_four_bar.toml")
    scene = draw_system(system, start_state(system))
    marks = {i.name: i for i in scene.of_kind("coordinate")}
    assert set(marks) == {"th2", "th3", "th4"}
    th2 = marks["th2"]
    assert th2.label == "th2 (prescribed)" and "prescribed" not in marks["th3"].label
    assert th2.shape["end"] - th2.shape["start"] == pytest.approx(math.pi / 3, abs=DIRECTION_TOL)
    assert th2.body == "crank"


def test_each_mass_centre_is_named_by_its_body():
    """QA10 item 12: rot_arm's collar (its C and G at one place) and the arm's G read "C, G G".
    With several bodies each G is named after its body, so that no two places share a label."""
    for path in (MULTIBODY / "rot_arm.toml", ROOT / "data" / "scenes" / "slider_crank.toml"):
        system = load_system(path)
        scene = draw_system(system, start_state(system))
        centres = {i.body: i.label for i in scene.of_kind("point") if i.name == "G"}
        assert centres == {body: f"G_{body}" for body in system.bodies}, path.name
    system = load_system(ROOT / "data" / "scenes" / "sliding_bar.toml")  # one body: its G is G
    assert {i.label for i in draw_system(system, start_state(system)).of_kind("point") if i.name == "G"} == {"G"}


def _assert_scene_labels_clear(ax, items, where):
    """On a scene drawing (or an animation frame) drawn from ``items``: no two labels overlap and
    no label is crossed by a bar (BAR_HALF_WIDTH_PT from its centre line, as on the diagrams)."""
    from solver.drawing.render import label_boxes

    _assert_labels_apart(ax.figure, where)
    to = ax.transData.transform
    bars = [_sample(*(to(np.array(e, float)) for e in i.shape["ends"])) for i in items
            if i.kind == "element" and i.shape["type"] == "bar"]
    grown = BAR_HALF_WIDTH_PT * ax.figure.dpi / 72 - LABEL_OVERLAP_TOL
    texts = [t.get_text() for t in ax.texts if t.get_visible() and t.get_text()]
    for text, box in zip(texts, label_boxes(ax)):
        assert all(_to_box(box, pts) >= grown for pts in bars), f"{where}: label {text!r} is crossed by a bar"


@pytest.mark.parametrize(("scene", "t_end"), [
    ("cart_spring.toml", "1.206 s"),  # frame 100 of 3 s: "theta" lay under the bar and on the G label
    ("rot_arm.toml", "1 s"),  # the last frame: "r = 0.3114 m" and "spring_1" lay on the arm
])
def test_animation_frames_keep_labels_off_each_other_and_the_bars(scene, t_end, tmp_path, monkeypatch):
    """QA10 item 12: the rule that keeps labels off each other and off the bars on the still drawing
    holds in every animation frame (two frames here: the start and the state the QA round saw)."""
    from solver.drawing import render

    system = load_system(MULTIBODY / scene)
    still = draw_system(system, start_state(system))
    _assert_scene_labels_clear(still.figure.axes[0], still.items, scene)
    frames, checked, keep_render = [], [], render.render_scene

    def check(event):  # each frame as written to the file: after its draw(k), when the canvas draws
        if event.canvas.figure.alt_euler_checking:
            return  # the check's own draw
        event.canvas.figure.alt_euler_checking = True
        _assert_scene_labels_clear(event.canvas.figure.axes[0], frames[-1], f"{scene} frame {len(checked)}")
        event.canvas.figure.alt_euler_checking = False
        checked.append(len(frames))

    def record(ax, items, *a, **k):
        keep_render(ax, items, *a, **k)
        frames.append(items)
        if not hasattr(ax.figure, "alt_euler_checking"):
            ax.figure.alt_euler_checking = False
            ax.figure.canvas.mpl_connect("draw_event", check)

    monkeypatch.setattr(render, "render_scene", record)
    out = tmp_path / "run.gif"
    assert main(["simulate", str(MULTIBODY / scene), "--t-end", t_end, "--samples", "2", "--animate", str(out)]) == 0
    assert checked == [2, 3]  # each of the two frames, drawn after what never changes


@pytest.fixture(scope="module")
def paper_figure():
    """``paper_figure(scene_file, name, number, body)``: (the matplotlib figure of one of the paper's
    Figures 1-3 as the report saves it, drawn; the figure's result). Each figure is drawn once per
    module, when a test first asks for it (about 0.2 s of CPU a figure): the four tests of the paper's
    figures only read it (no test changes a figure; each check that measures labels draws it again)."""
    from reports import figures

    done = {}

    def get(scene_file, name, number, body):
        if name not in done:
            drawn = []
            keep = figures._result
            with pytest.MonkeyPatch.context() as patch:
                patch.setattr(figures, "_result", lambda n, fig, *rest: drawn.append(fig) or keep(n, fig, *rest))
                result = figures.scene_figure(ROOT / "data" / "scenes" / scene_file, name, number, body)
            (figure,) = drawn
            figure.canvas.draw()
            done[name] = figure, result
        return done[name]

    return get


def _ring_outlines(ax):
    """Each unfilled circle drawn on ``ax`` (a ring, a rim, a circular guide) as display points 1 pixel
    apart or closer, with its stroke's half width [pixels] (the test's own route: centre and radius)."""
    from matplotlib.patches import Circle

    out = []
    for p in ax.patches:
        if isinstance(p, Circle) and not (p.get_fill() and p.get_facecolor()[3] > 0) and p.get_edgecolor()[3] > 0:
            a = np.linspace(0, 2 * math.pi, 2000)
            xy = np.column_stack([p.center[0] + p.radius * np.cos(a), p.center[1] + p.radius * np.sin(a)])
            out.append((ax.transData.transform(xy), 0.5 * p.get_linewidth() * ax.figure.dpi / 72))
    return out


@pytest.mark.parametrize("name, scene_file, body, number", PAPER_SCENE_FIGURES)
def test_paper_figures_labels_clear_rings_and_by_their_dots(name, scene_file, body, number, paper_figure):
    """QA10 item 5. No label is crossed by a ring's outline (Figure 1's "|-I_A alpha| = 10.03 N·m" lay
    across the big-end ring at A: the stroke must clear the box by its half width, less the 1 pixel of
    LABEL_OVERLAP_TOL); a point's label is nearer its own dot than any other point's ("G_crank" stood
    above the ring at A, nearer A's dot than its own on OA), and no farther than 3 label heights."""
    from solver.drawing.render import label_boxes

    figure, _ = paper_figure(scene_file, name, number, body)
    for ax in (a for a in figure.axes if a.get_visible()):
        rings = _ring_outlines(ax)
        dots = [ax.transData.transform(np.column_stack(line.get_data()).astype(float))[0] for line in ax.lines
                if len(line.get_xdata()) == 1 and line.get_marker() == "o" and line.get_color() == "black"]
        texts = [t for t in ax.texts if t.get_visible() and t.get_text()]
        for t, box in zip(texts, label_boxes(ax)):
            for pts, half in rings:
                assert _to_box(box, pts) >= half - LABEL_OVERLAP_TOL, f"{name}: {t.get_text()!r} crossed by a ring"
            if hasattr(t, "xy") and t.get_text() and t.get_fontsize() == 8:  # a point's name (8 pt, at its dot)
                own = ax.transData.transform(np.array(t.xy, float))
                gaps = [_to_box(box, d[None, :]) for d in dots]
                mine = _to_box(box, own[None, :])
                assert mine <= min(gaps) + 1e-9, f"{name}: {t.get_text()!r} is nearer another point's dot"
                assert mine <= 3 * box.height, f"{name}: {t.get_text()!r} is {mine:.0f} px from its dot"


# The head of a force arrow ("-|>" at mutation scale 11 pt) is 4.4 pt long and 2.2 pt wide each side;
# a point's dot (marker 2.5 pt) has a radius of 1.25 pt. The arrow's end, its head and as much shaft
# again, must clear every dot not at its tip by the two together, or the head sits on that dot.
HEAD_LENGTH_PT = 4.4
HEAD_CLEAR_PT = 2.2 + 1.25


@pytest.mark.parametrize("name, scene_file, body, number", PAPER_SCENE_FIGURES)
def test_paper_figures_titles_heads_and_notation(name, scene_file, body, number, paper_figure):
    """QA10 items 5 and 6. Panel titles are not the scene's file name ("disk_bar") nor
    "free-body diagram (P = P)" but say which point the moments are taken about; no force arrow's
    head ends on the dot of a point other than one at its tip (Figure 3's weight, drawn arriving at G,
    ended on P's dot); the labels and the caption write θ, α, −m a_P, −I_P α, not theta, alpha, -m a_P."""
    figure, result = paper_figure(scene_file, name, number, body)
    system = load_system(ROOT / "data" / "scenes" / scene_file)
    scene_ax, fbd_ax = [a for a in figure.axes if a.get_visible()]
    assert scene_ax.get_title() not in (system.name, Path(scene_file).stem) and scene_ax.get_title()
    point = result.facts["point"]
    assert fbd_ax.get_title().lower().endswith(f"free-body diagram, moments about {point.lower()}"), fbd_ax.get_title()
    from matplotlib.patches import FancyArrowPatch

    dots = [fbd_ax.transData.transform(np.column_stack(line.get_data()).astype(float))[0] for line in fbd_ax.lines
            if len(line.get_xdata()) == 1 and line.get_marker() == "o"]
    ends = [tuple(fbd_ax.transData.transform(np.array(q, float)) for q in p._posA_posB)
            for p in fbd_ax.patches if isinstance(p, FancyArrowPatch)]
    longest = max(np.linalg.norm(b - a) for a, b in ends)
    pixels = figure.dpi / 72
    for a, b in ((a, b) for a, b in ends if np.linalg.norm(b - a) > 0.5 * longest):  # not an arc's head
        end = _sample(b + 2 * HEAD_LENGTH_PT * pixels * (a - b) / np.linalg.norm(a - b), b)
        for d in dots:
            if np.linalg.norm(b - d) < 1e-6:
                continue  # the arrow's own point, at its tip (a push)
            gap = float(np.min(np.linalg.norm(end - d, axis=1)))
            assert gap >= HEAD_CLEAR_PT * pixels, f"{name}: an arrow's head ends on a point's dot ({gap:.1f} px)"
    words = " ".join(t.get_text() for ax in (scene_ax, fbd_ax) for t in ax.texts) + " " + result.caption
    for ascii_name in ("theta", "alpha", "phi", "-m a_", "-I_"):
        assert ascii_name not in words, f"{name}: {ascii_name!r} written in ASCII"
    assert f"\u2212m a_{point}" in result.caption and f"\u2212I_{point} \u03b1" in result.caption


# A coordinate's arc ends in a "-|>" head at mutation scale 10 pt: 4 pt long. Its drawn line must be
# at least 1.5 heads long, or the mark is all head (QA10: Figure 3's 10 deg theta arc was 5.2 px at
# 100 dpi under a 5.6 px head, on the bar; Figure 1's phi 4.0 px).
COORDINATE_HEAD_PT = 4.0


@pytest.mark.parametrize("name, scene_file, body, number", PAPER_SCENE_FIGURES)
def test_paper_figures_coordinate_arcs_are_more_than_their_heads(name, scene_file, body, number, paper_figure):
    from matplotlib.colors import to_hex

    figure, _ = paper_figure(scene_file, name, number, body)
    ax = [a for a in figure.axes if a.get_visible()][0]
    arcs = [line for line in ax.lines if len(line.get_xdata()) == 39 and to_hex(line.get_color()) == to_hex("0.15")]
    assert arcs, f"{name}: no coordinate arc drawn"
    for line in arcs:
        xy = ax.transData.transform(np.column_stack(line.get_data()).astype(float))
        length = float(np.sum(np.linalg.norm(np.diff(xy, axis=0), axis=1)))
        assert length >= 1.5 * COORDINATE_HEAD_PT * figure.dpi / 72, f"{name}: a coordinate's arc {length:.1f} px"


def test_a_given_load_keeps_its_size_and_arrow_beside_huge_forces(tmp_path):
    """QA 12 #10: at theta_dot = 1e50 rad/s the disk_bar contact force is about 1e99 N, and the
    weight was labelled ``|m g| = 0 N`` with no arrow: the zero rule (1e-9 of the largest force,
    for the solve's round-off) took it for round-off. A load the scene gives is exact: its label
    prints its size, (m_d + m_b) g = 5.5 kg x 9.80665 m/s**2 = 53.94 N from the scene file (4
    significant figures as every label), and it is drawn downwards, every arrow being of one length."""
    system = load_system(ROOT / "data" / "scenes" / "disk_bar.toml", {"theta_dot": "1e50 rad/s"})
    fbd = draw_system(system, fbd=True)
    weight = next(i for i in fbd.items if i.kind == "force" and i.label.startswith("gravity"))
    assert weight.label == f"gravity: |m g| = {(4 + 1.5) * 9.80665:.2f} N"
    assert weight.direction == pytest.approx((0.0, -1.0), abs=1e-12)
    assert max(i.value for i in fbd.items if i.kind == "force") > 1e98  # the huge forces beside it
    import matplotlib.pyplot as plt

    plt.close(fbd.figure)
    assert main(["draw", str(ROOT / "data" / "scenes" / "disk_bar.toml"), "--fbd", "--set", "theta_dot=1e50 rad/s",
                 "-o", str(tmp_path / "fast.svg")]) == 0
    assert "53.94" in (tmp_path / "fast.svg").read_text(encoding="utf-8")


def test_covered_counts_the_points_strictly_inside_each_grown_box():
    """render._covered (which leaves out the points far from every box before testing) counts as a plain
    loop over every point does: strictly inside the box grown by the point's pad, whatever the pads."""
    from solver.drawing.render import _covered

    rng = np.random.default_rng(7)
    boxes = np.sort(rng.uniform(0, 40, (30, 2, 2)), axis=1).transpose(0, 2, 1).reshape(30, 4)[:, [0, 2, 1, 3]]
    points = rng.uniform(-200, 240, (500, 2))
    points[:50] = boxes[rng.integers(0, 30, 50)][:, :2]  # on a corner: not strictly inside unless padded
    pads = rng.uniform(0, 5, 500)
    for pad in (0.0, 2.5, pads):
        each = np.broadcast_to(pad, (500,))
        expected = [sum(1 for (x, y), p in zip(points, each) if x0 - p < x < x1 + p and y0 - p < y < y1 + p)
                    for x0, y0, x1, y1 in boxes]
        assert _covered(boxes, points, pad).tolist() == expected
    assert _covered(boxes, points[:0]).tolist() == [0] * 30


@pytest.mark.parametrize("dpi", [72, 100, 150])
def test_font_heights_give_matplotlibs_own_text_boxes(dpi):
    """A renderer given layout.FontHeights (each font's heights read once) lays texts out exactly as
    matplotlib does reading the font's tables every time: the same boxes, to the last bit, for
    one- and two-line texts at several sizes, weights and dpi (with linespacing "normal", the line gap
    counts)."""
    from matplotlib.backends.backend_agg import RendererAgg
    from matplotlib.figure import Figure

    from solver.drawing.layout import FontHeights

    fig = Figure(figsize=(4, 3), dpi=dpi)
    texts = [fig.text(0.1, 0.1 + 0.1 * k, s, fontsize=size, fontweight=weight, linespacing=spacing)
             for k, (s, size, weight, spacing) in enumerate([
                 ("A", 8, "normal", 1.2), ("Ag\nlp", 9, "bold", 1.2), ("−m a_P (n = 22)", 7, "normal", 1.2),
                 ("two\nlines", 10, "normal", 2.0), ("θ̈ = 19.50", 11.5, "normal", 1.2),
                 ("gap\nkept", 9, "normal", "normal")])]
    plain = RendererAgg(400, 300, dpi)
    hooked = RendererAgg(400, 300, dpi)
    hooked._get_font_height_metrics = FontHeights(dpi)
    for t in texts:
        assert t.get_window_extent(hooked).bounds == t.get_window_extent(plain).bounds, t.get_text()


@pytest.mark.parametrize("dpi", [72, 100, 150])
def test_a_figure_measured_as_vector_sizes_its_texts_as_the_svg_renderer_draws_them(dpi):
    """layout.measure_as_vector: the layout's renderer measures each text as matplotlib's own SVG
    renderer does (its boxes in points, scaled to the figure's pixels: the reference is the SVG
    renderer, a separate route), also for a text measured before by another figure; a figure not
    so marked keeps the PNG renderer's (hinted) measure, which differs for a long text."""
    import io

    from matplotlib.backends.backend_agg import RendererAgg
    from matplotlib.backends.backend_svg import RendererSVG
    from matplotlib.figure import Figure

    from solver.drawing.layout import agg_renderer, measure_as_vector

    svg = RendererSVG(400, 300, io.StringIO())
    specs = [("A", 8, "normal"), ("|−m a_A| = 19.50 lbf", 7, "normal"), ("largest relative error", 9, "bold")]
    for _ in range(2):  # the second figure's texts were measured by the first
        fig = Figure(figsize=(4, 3), dpi=dpi)
        measure_as_vector(fig)
        texts = [fig.text(0.1, 0.1 + 0.2 * k, s, fontsize=size, fontweight=weight)
                 for k, (s, size, weight) in enumerate(specs)]
        renderer = agg_renderer(fig)
        for t in texts:
            prop = t.get_fontproperties()
            # exact up to the one multiplication by dpi/72 (a float's last bit)
            assert np.allclose(renderer.get_text_width_height_descent(t.get_text(), prop, False),
                               [v * dpi / 72 for v in svg.get_text_width_height_descent(t.get_text(), prop, False)],
                               rtol=1e-15, atol=0), t.get_text()
    plain = Figure(figsize=(4, 3), dpi=dpi)
    long = plain.text(0.1, 0.1, "largest relative error of the period", fontsize=9)
    hinted = agg_renderer(plain).get_text_width_height_descent(long.get_text(), long.get_fontproperties(), False)
    assert hinted == RendererAgg(400, 300, dpi).get_text_width_height_descent(long.get_text(),
                                                                             long.get_fontproperties(), False)
    vector = svg.get_text_width_height_descent(long.get_text(), long.get_fontproperties(), False)
    assert hinted[0] != vector[0] * dpi / 72


@pytest.mark.parametrize("scene,indeterminate", [("ladder_friction", True), ("crate_tipping", True),
                                                  ("sliding_bar", False)])
def test_a_free_body_diagram_says_when_its_contact_forces_are_one_split_of_many(scene, indeterminate):
    """QA 19 #8: the ladder's and the crate's sticking contacts hold redundantly (solve says so), yet
    the diagram showed the least-squeeze split under the usual caption, as if determined. The
    sliding bar's reactions are determined: no such line."""
    from solver.drawing import INDETERMINATE_CAPTION

    drawing = draw_system(load_system(ROOT / "data" / "scenes" / f"{scene}.toml"), fbd=True)
    captions = [ax.get_xlabel() for ax in drawing.figure.axes if ax.get_xlabel()]
    assert captions and all((INDETERMINATE_CAPTION in c) == indeterminate for c in captions), captions
    assert bool(drawing.solution.extra.get("indeterminate")) == indeterminate



def _readme_gears(tmp_path, theta1: str) -> Path:
    """data/scenes/README.md's `gears` example (a pinion r1 = 0.1 m at O1 = (0, 0) meshing with a wheel
    r2 = 0.3 m at O2 = (0.4 m, 0)), as a scene file with the pinion at ``theta1``."""
    text = (Path(__file__).resolve().parents[1] / "data/scenes/README.md").read_text(encoding="utf-8")
    block = re.search(r'```toml\n(name = "gears"\n.*?)```', text, flags=re.S).group(1)
    path = tmp_path / "gears.toml"
    path.write_text(block.replace('value = "0 deg"', f'value = "{theta1}"'), encoding="utf-8")
    return path


@pytest.mark.parametrize("theta1", [0.0, 30.0])
def test_a_disks_angle_is_marked_on_the_disk_clear_of_the_other_gear(tmp_path, theta1):
    """QA 19: in README's gears drawing the pinion's angle was marked by a dotted line from O1 running
    across the wheel, its label sat on the wheel's pivot O2 at theta1 = 0, at 30 deg the arc lay inside
    the wheel's disk, and no line on the disk showed what turns. Now a radius of the pinion is drawn at
    its angle; the arc and the reference line stay inside the pinion (r1 = 0.1 m from O1); the label,
    where the figure's layout leaves it, lies outside the wheel's disk (0.3 m about O2 = (0.4, 0)) and
    off O2. README's data; distances in metres, 1e-9 for round-off."""
    drawing = draw_system(load_system(_readme_gears(tmp_path, f"{theta1} deg")))
    (mark,) = drawing.of_kind("coordinate")
    ax = drawing.figure.axes[0]
    assert mark.shape["rim"] == pytest.approx(0.1) and mark.shape["radius"] < 0.1
    assert mark.shape["end"] == pytest.approx(math.radians(theta1))
    lines = [np.column_stack(line.get_data()) for line in ax.lines]
    ends = {tuple(np.round(xy[-1], 9)) for xy in lines if len(xy) == 2 and np.allclose(xy[0], (0, 0), atol=1e-9)}
    along = (round(0.1 * math.cos(math.radians(theta1)), 9), round(0.1 * math.sin(math.radians(theta1)), 9))
    assert (0.1, 0.0) in ends  # the dotted reference line, to the pinion's rim
    radius = [xy for xy in lines if len(xy) == 2 and np.allclose(xy[-1], along, atol=1e-9)
              and abs(xy[0, 0] * along[1] - xy[0, 1] * along[0]) < 1e-9]  # on the line O1-rim at theta1
    assert radius  # the radius that turns with the pinion, to its rim at theta1
    for xy in lines:  # nothing of the mark reaches past the pinion's rim into the wheel
        if np.allclose(xy[0], (0, 0), atol=1e-9) or any(xy is r for r in radius):
            assert np.all(np.hypot(xy[:, 0], xy[:, 1]) <= 0.1 + 1e-9)
    (label,) = [t for t in ax.texts if t.get_text() == mark.label]
    box = label.get_window_extent(drawing.figure.canvas.get_renderer())
    corners = ax.transData.inverted().transform([[box.x0, box.y0], [box.x1, box.y0], [box.x0, box.y1], [box.x1, box.y1]])
    assert all(np.hypot(x - 0.4, y) > 0.3 for x, y in corners), corners  # not on the wheel
