"""Drawings of scenes: the configuration, free-body diagrams, animations.

``draw_system(system, state=None, ax=None, fbd=False, point=None)`` returns a
:class:`~solver.drawing.model.Drawing`: the drawn items as data (labels,
anchors, directions; see :mod:`solver.drawing.model`) and the matplotlib
figure. ``animate(system, times, states, path)`` writes a GIF (or an MP4 with
ffmpeg). matplotlib is imported only when something is drawn, so the command
line starts without it.
"""
from __future__ import annotations

import io
import os
import shutil
from pathlib import Path

__all__ = ["draw_system", "scene_title", "fbd_title", "save_figure", "animate", "frame_indices", "check_animation_path", "FORMATS", "ANIMATION_FORMATS", "MAX_FRAMES", "check_format"]

FORMATS = (".svg", ".png", ".pdf")
"""File formats of ``draw``, chosen by the output file's suffix."""
ANIMATION_FORMATS = (".gif", ".mp4")
MAX_FRAMES = 250
"""Most frames an animation has (10 s at :data:`FRAME_RATE`): a longer run is sampled evenly
down to this many. Each frame costs some 30 to 45 ms of CPU (its labels placed as on the still
drawing: about 15 ms of it), so this keeps an animation inside the command's CPU budget (about
11 s for slider_crank.toml's 250 frames)."""
FRAME_RATE = 25
"""Frames per second of an animation."""
DPI = 100
"""Raster resolution [dots per inch] of PNG files and animation frames."""


def check_format(path, allowed, flag: str) -> str:
    """The lower-case suffix of ``path`` if it is one of ``allowed``; a folder or a name ending in a
    slash is refused as :func:`solver.files.check_output_path` refuses it.

    Raises
    ------
    InputError
        Naming ``flag`` and listing the allowed suffixes.
    """
    from ..errors import InputError
    from ..files import check_output_path

    text = str(path)
    if text.endswith(("/", os.sep)) or Path(text).is_dir():  # not a file at all: say that, not its suffix
        check_output_path(path, flag)
    suffix = Path(text).suffix.lower()
    if suffix not in allowed:
        raise InputError(f"{flag} {path}: unknown file type {suffix or '(none)'!r}; use one of "
                         f"{', '.join(allowed)} (the format follows the suffix)")
    return suffix


def draw_system(system, state=None, ax=None, fbd: bool = False, point: str | None = None, bodies=None,
                arrange_labels: bool = True, solution=None, title: str | None = None):
    """Draw a scene at its state (or ``state``), or its free-body diagrams.

    Parameters
    ----------
    system : solver.model.system.System
    state : solver.analyses.instant.State, optional
        A complete state; default: the scene's, with the dependent
        coordinates solved (:func:`solver.analyses.regimes.start_state`: with the contacts open at the
        state left open).
    ax : matplotlib Axes or sequence of Axes, optional
        Where to draw: one Axes for the scene; for ``fbd`` one per body (in
        the order of ``system.bodies``). Default: a new figure.
    fbd : bool
        One free-body diagram per body instead of the scene.
    point : str, optional
        ``BODY:POINT`` or a point name: the point P whose inertial force
        -m a_P the diagrams show (default: each body's reference point).
    bodies : sequence of str, optional
        For ``fbd``: the bodies whose diagrams are drawn (default: all).
    arrange_labels : bool
        Move the labels off each other now (:func:`solver.drawing.render.place_labels`). False
        when the caller draws more on the same figure first and places every panel's labels
        once, in the figure's final layout.
    solution : solver.analyses.instant.InstantSolution, optional
        For ``fbd``: the system's solution about ``point`` when the caller has it already
        (:func:`solver.analyses.instant.solve_instant`); drawn at its state. Default: solved here.
    title : str, optional
        The scene drawing's title (default: the scene's description, wrapped, or its name when it
        has none). A free-body diagram is titled by its body and point P (:func:`fbd_title`).

    Returns
    -------
    solver.drawing.model.Drawing
        The items drawn, and ``figure`` (None when ``ax`` was given).

    Raises
    ------
    InputError
        A bad ``point``; SingularConfigurationError when the state cannot be solved.
    """
    from ..analyses.instant import solve_instant
    from ..analyses.regimes import start_state
    from ..formulations import resolve_points
    from . import render
    from .model import Drawing, free_body_items, scene_items

    points = resolve_points(system, point)  # a bad --point is refused before any work
    if solution is not None:
        if state is not None and state is not solution.state:
            raise ValueError("`state` and `solution` must be of one state: give one of them")
        state = solution.state
    state = start_state(system) if state is None else state
    scene = scene_items(system, state)
    panels = list(system.bodies) if bodies is None else list(bodies)
    unknown = [b for b in panels if b not in system.bodies]
    if unknown:
        raise ValueError(f"`bodies` must name bodies of the scene ({', '.join(system.bodies)}), got {unknown}")
    bodies = list(system.bodies)
    figure = None
    from matplotlib import rc_context

    with rc_context(render.RC):
        if not fbd:
            if ax is None:
                figure, (ax,) = render.new_figure(1, size=5.0)
            render.render_scene(ax, scene, bodies, title=scene_title(system) if title is None else title)
            if arrange_labels:
                render.place_labels(ax.figure, [ax])
            return Drawing(system.name, scene, figure=figure)
        solution = solve_instant(system, point, state=state) if solution is None else solution
        from ..analyses.regimes import with_every_contact_force  # contacts: the regime's forces, each drawn alone

        forces = free_body_items(with_every_contact_force(system), state, solution, points)
        axes = ax
        if axes is None:
            figure, axes = render.new_figure(len(panels), size=4.6)
        elif not isinstance(axes, (list, tuple)):
            axes = [axes]
        if len(axes) != len(panels):
            raise ValueError(f"`ax` must hold one Axes per body drawn ({len(panels)}), got {len(axes)}")
        for a, body in zip(axes, panels):
            render.render_fbd(a, scene, [f for f in forces if f.body == body], body, bodies,
                              title=fbd_title(body, points[body], len(bodies)))
        if solution.extra.get("indeterminate"):
            for a in axes:
                a.set_xlabel(a.get_xlabel() + "\n" + INDETERMINATE_CAPTION)
        if arrange_labels:
            render.place_labels(axes[0].figure, axes)  # labels off each other and off the bodies
    forces = [f for f in forces if f.body in panels]
    return Drawing(system.name, forces, fbd=True, panels=panels, point=points, figure=figure, solution=solution)


INDETERMINATE_CAPTION = "Statically indeterminate: one admissible split of the contact forces (least squeeze)."
"""The line under free-body diagrams whose sticking contacts hold redundantly: the forces drawn are
not forces the equations determine (``solve`` and ``explain`` say it at length,
:data:`solver.analyses.regimes.INDETERMINATE_NOTE`)."""


def scene_title(system) -> str:
    """A scene drawing's title: the scene's description (wrapped at 60 characters), else its name."""
    import textwrap

    return "\n".join(textwrap.wrap(system.description, 60)) if system.description else system.name


def fbd_title(body: str, point: str, bodies: int) -> str:
    """A free-body diagram's title: the moments' point P, and the body's name when the scene has
    several (``rod: free-body diagram, moments about A``)."""
    what = f"free-body diagram, moments about {point}"
    return f"{body}: {what}" if bodies > 1 else what[0].upper() + what[1:]


def figure_bytes(figure, suffix: str, dpi: int = DPI) -> bytes:
    """The figure as SVG, PNG or PDF bytes, reproducible (no dates, fixed SVG ids)."""
    from matplotlib import rc_context

    from .render import RC

    fmt = suffix.lstrip(".")
    metadata = {"svg": {"Date": None, "Creator": None}, "pdf": {"CreationDate": None, "Creator": None,
                                                                "Producer": None}, "png": {"Software": None}}[fmt]
    buf = io.BytesIO()
    with rc_context(RC):
        figure.savefig(buf, format=fmt, dpi=dpi, metadata=metadata)
    return buf.getvalue()


def save_figure(figure, path, flag: str = "-o") -> Path:
    """Write the figure atomically in the format of ``path``'s suffix (.svg, .png, .pdf)."""
    from ..files import write_atomic

    suffix = check_format(path, FORMATS, flag)
    data = figure_bytes(figure, suffix)
    return write_atomic(path, lambda fh: fh.write(data), flag, binary=True)


def check_animation_path(path, flag: str = "--animate") -> str:
    """Refuse, before any work, an animation file that cannot be written: a suffix other than
    .gif or .mp4, .mp4 without ffmpeg, or a place that cannot be written. Returns the suffix."""
    from ..errors import InputError
    from ..files import check_output_path

    suffix = check_format(path, ANIMATION_FORMATS, flag)
    if suffix == ".mp4" and shutil.which("ffmpeg") is None:
        raise InputError(f"{flag} {path}: writing .mp4 needs ffmpeg, which is not installed; use a .gif")
    check_output_path(path, flag)
    return suffix


def animate(system, times, states, path, flag: str = "--animate") -> Path:
    """Write an animation of the scene drawing along a trajectory.

    Parameters
    ----------
    system : solver.model.system.System
    times : sequence of float
        Sample times [s].
    states : sequence of solver.analyses.instant.State
        Complete states at the samples (dependent coordinates solved).
    path : str or Path
        ``.gif`` (Pillow), or ``.mp4`` when ffmpeg is installed.

    Notes
    -----
    At most :data:`MAX_FRAMES` frames: a longer trajectory is sampled evenly.
    Frames play at :data:`FRAME_RATE` per second whatever the run's time scale.
    """
    from ..files import write_atomic
    from . import render
    from .model import PoseFunction, _memo, body_shapes, scene_items

    suffix = check_animation_path(path, flag)
    n = len(states)
    if n == 0 or len(times) != n:
        raise ValueError(f"`times` and `states` must be non-empty and of one length, got {len(times)} and {n}")
    keep = frame_indices(n)
    shapes = _memo(system, "shapes", body_shapes)
    poses = _memo(system, "poses", PoseFunction)
    frames = _fixed_tracks([scene_items(system, states[k], poses(states[k].q, states[k].t), shapes) for k in keep])
    bodies = list(system.bodies)
    # one frame box for the whole run, so that the picture does not jump
    import numpy as np

    boxes = [render._span(f) for f in frames]
    low = np.min([b[0] for b in boxes], axis=0)
    high = np.max([b[1] for b in boxes], axis=0)
    span = float(np.max(high - low)) or 1.0
    from matplotlib import rc_context
    from matplotlib.animation import FFMpegWriter, FuncAnimation

    from matplotlib.figure import Figure

    from ..model.bodies import GROUND

    with rc_context(render.RC):
        figure = Figure(figsize=(4.0, 4.0))
        ax = figure.add_axes((0.0, 0.0, 1.0, 0.93))
        # what is the same in every frame (the fixed ground's guides and supports) is drawn once; the
        # bodies, a ground item that moves with t (a prescribed pivot), and the points every frame: the
        # names of a body's point and a ground point at one place (a pin) are then written once
        fixed = _unchanging([[i for i in f if i.body == GROUND and i.kind != "point"] for f in frames])
        render.render_scene(ax, fixed, bodies, limits=(low, high, span))
        render._setup(ax, low, high, span, "")
        title = figure.suptitle("", fontsize=9)
        name = system.name.replace("$", r"\$")  # a scene name is text, never mathtext
        previous: list = []

        def draw(k):
            for artist in previous:
                artist.remove()
            before = set(ax.get_children())
            render.render_scene(ax, [i for i in frames[k] if i not in fixed], bodies, limits=(low, high, span))
            render.place_labels(figure, [ax])  # as on the scene drawing: off each other and off the bars
            previous[:] = [a for a in ax.get_children() if a not in before]
            title.set_text(f"{name}   t = {times[keep[k]]:.3f} s")
            return []

        if suffix == ".gif":
            data = _gif_bytes(figure, draw, len(frames))
        else:
            movie = FuncAnimation(figure, draw, frames=len(frames), init_func=lambda: [], blit=False)
            import tempfile

            with tempfile.TemporaryDirectory(dir=Path(path).parent) as tmp:
                scratch = Path(tmp) / "frames.mp4"
                movie.save(str(scratch), writer=FFMpegWriter(fps=FRAME_RATE), dpi=DPI)
                data = scratch.read_bytes()
    return write_atomic(path, lambda fh: fh.write(data), flag, binary=True)


def _fixed_tracks(frames: list[list]) -> list[list]:
    """``frames`` with each straight guide of the ground that stays in place (a cart's track) drawn
    alike in every frame, long enough for the whole run: from the first to the last point any
    frame draws it to. A still drawing sizes the line to the scene at its state; frame by frame
    that line travelled with the cart, as if the ground moved (QA 19 #10)."""
    import dataclasses

    import numpy as np

    from ..model.bodies import GROUND

    def track(item):
        return item.kind == "guide" and item.body == GROUND and (item.shape or {}).get("type") == "line"

    runs: dict = {}
    for frame in frames:
        for item in frame:
            if track(item):
                runs.setdefault(item.name, []).append(item)
    merged = {}
    for name, items in runs.items():
        first = items[0]
        if len(items) != len(frames) or any((i.anchor, i.direction) != (first.anchor, first.direction) for i in items):
            continue  # a guide that moves (on a body, or a prescribed ground point) is drawn frame by frame
        o, d = np.array(first.anchor), np.array(first.direction)
        s = [float(d @ (np.array(end) - o)) for i in items for end in i.shape["ends"]]
        ends = ((o + min(s) * d).tolist(), (o + max(s) * d).tolist())
        merged[name] = dataclasses.replace(first, shape={**first.shape, "ends": ends})
    return [[merged.get(i.name, i) if track(i) else i for i in frame] for frame in frames]


def _unchanging(ground: list[list]) -> list:
    """The ground's items drawn alike in every frame (``ground``: each frame's ground items, listed
    in one order, as :func:`~solver.drawing.model.scene_items` lists them)."""
    first = ground[0]
    return [item for k, item in enumerate(first) if all(len(f) == len(first) and f[k] == item for f in ground)]


def frame_indices(n: int, limit: int = MAX_FRAMES) -> list[int]:
    """Indices of the samples shown: all of them, or ``limit`` evenly spread from the first to the last."""
    m = min(n, limit)
    return sorted({round(k * (n - 1) / max(m - 1, 1)) for k in range(m)})


def _gif_bytes(figure, draw, n: int) -> bytes:
    """A looping GIF of ``n`` frames (``draw(k)`` updates the figure), with one palette.

    The palette is taken from the first frame (the drawing's colours do not
    change), so each frame is mapped to it without dithering: far cheaper than
    a palette per frame.
    """
    import numpy as np
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from PIL import Image

    canvas = FigureCanvasAgg(figure)
    figure.set_dpi(DPI)
    images = []
    palette = None
    for k in range(n):
        draw(k)
        canvas.draw()
        frame = Image.fromarray(np.asarray(canvas.buffer_rgba())[..., :3])
        if palette is None:
            palette = frame.quantize(colors=64, method=Image.Quantize.MEDIANCUT)
        images.append(frame.quantize(palette=palette, dither=Image.Dither.NONE))
    buf = io.BytesIO()
    images[0].save(buf, format="GIF", save_all=True, append_images=images[1:], duration=round(1000 / FRAME_RATE),
                   loop=0)
    return buf.getvalue()
