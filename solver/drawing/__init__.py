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
import shutil
from pathlib import Path

__all__ = ["draw_system", "save_figure", "animate", "FORMATS", "ANIMATION_FORMATS", "MAX_FRAMES", "check_format"]

FORMATS = (".svg", ".png", ".pdf")
"""File formats of ``draw``, chosen by the output file's suffix."""
ANIMATION_FORMATS = (".gif", ".mp4")
MAX_FRAMES = 600
"""Most frames an animation has: a longer run is sampled evenly down to this many."""
FRAME_RATE = 25
"""Frames per second of an animation."""
DPI = 100
"""Raster resolution [dots per inch] of PNG files and animation frames."""


def check_format(path, allowed, flag: str) -> str:
    """The lower-case suffix of ``path`` if it is one of ``allowed``.

    Raises
    ------
    InputError
        Naming ``flag`` and listing the allowed suffixes.
    """
    from ..errors import InputError

    suffix = Path(str(path)).suffix.lower()
    if suffix not in allowed:
        raise InputError(f"{flag} {path}: unknown file type {suffix or '(none)'!r}; use one of "
                         f"{', '.join(allowed)} (the format follows the suffix)")
    return suffix


def draw_system(system, state=None, ax=None, fbd: bool = False, point: str | None = None):
    """Draw a scene at its state (or ``state``), or its free-body diagrams.

    Parameters
    ----------
    system : solver.model.system.System
    state : solver.analyses.instant.State, optional
        A complete state; default: the scene's, with the dependent
        coordinates solved (:func:`solver.analyses.instant.assemble`).
    ax : matplotlib Axes or sequence of Axes, optional
        Where to draw: one Axes for the scene; for ``fbd`` one per body (in
        the order of ``system.bodies``). Default: a new figure.
    fbd : bool
        One free-body diagram per body instead of the scene.
    point : str, optional
        ``BODY:POINT`` or a point name: the point P whose inertial force
        -m a_P the diagrams show (default: each body's reference point).

    Returns
    -------
    solver.drawing.model.Drawing
        The items drawn, and ``figure`` (None when ``ax`` was given).

    Raises
    ------
    InputError
        A bad ``point``; SingularConfigurationError when the state cannot be solved.
    """
    from ..analyses.instant import assemble, solve_instant
    from ..formulations import resolve_points
    from . import render
    from .model import Drawing, free_body_items, scene_items

    points = resolve_points(system, point)  # a bad --point is refused before any work
    state = assemble(system) if state is None else state
    scene = scene_items(system, state)
    bodies = list(system.bodies)
    figure = None
    from matplotlib import rc_context

    with rc_context(render.RC):
        if not fbd:
            if ax is None:
                figure, (ax,) = render.new_figure(1, size=5.0)
            render.render_scene(ax, scene, bodies, title=system.name)
            return Drawing(system.name, scene, figure=figure)
        solution = solve_instant(system, point, state=state)
        forces = free_body_items(system, state, solution, points)
        axes = ax
        if axes is None:
            figure, axes = render.new_figure(len(bodies), size=4.6)
        elif not isinstance(axes, (list, tuple)):
            axes = [axes]
        if len(axes) != len(bodies):
            raise ValueError(f"`ax` must hold one Axes per body ({len(bodies)}), got {len(axes)}")
        for a, body in zip(axes, bodies):
            render.render_fbd(a, scene, [f for f in forces if f.body == body], body, bodies,
                              title=f"{body}: free-body diagram (P = {points[body]})")
    return Drawing(system.name, forces, fbd=True, panels=bodies, point=points, figure=figure)


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
    from ..errors import InputError
    from ..files import check_output_path, write_atomic
    from . import render
    from .model import PoseFunction, body_shapes, scene_items

    suffix = check_format(path, ANIMATION_FORMATS, flag)
    if suffix == ".mp4" and shutil.which("ffmpeg") is None:
        raise InputError(f"{flag} {path}: writing .mp4 needs ffmpeg, which is not installed; use a .gif")
    check_output_path(path, flag)
    n = len(states)
    if n == 0 or len(times) != n:
        raise ValueError(f"`times` and `states` must be non-empty and of one length, got {len(times)} and {n}")
    keep = sorted({round(k * (n - 1) / max(min(n, MAX_FRAMES) - 1, 1)) for k in range(min(n, MAX_FRAMES))})
    shapes = body_shapes(system)
    poses = PoseFunction(system)
    frames = [scene_items(system, states[k], poses(states[k].q, states[k].t), shapes) for k in keep]
    bodies = list(system.bodies)
    # one frame box for the whole run, so that the picture does not jump
    import numpy as np

    boxes = [render._span(f) for f in frames]
    low = np.min([b[0] for b in boxes], axis=0)
    high = np.max([b[1] for b in boxes], axis=0)
    span = float(np.max(high - low)) or 1.0
    from matplotlib import rc_context
    from matplotlib.animation import FFMpegWriter, FuncAnimation, PillowWriter

    with rc_context(render.RC):
        figure, (ax,) = render.new_figure(1, size=4.0)

        def draw(k):
            ax.clear()
            render.render_scene(ax, frames[k], bodies, limits=(low, high, span))
            render._setup(ax, low, high, span, f"{system.name}   t = {times[keep[k]]:.3f} s")
            return []

        movie = FuncAnimation(figure, draw, frames=len(frames), blit=False)
        writer = PillowWriter(fps=FRAME_RATE) if suffix == ".gif" else FFMpegWriter(fps=FRAME_RATE)
        target = Path(path)
        import tempfile

        with tempfile.TemporaryDirectory(dir=target.parent) as tmp:
            scratch = Path(tmp) / f"frames{suffix}"
            movie.save(str(scratch), writer=writer, dpi=DPI)
            data = scratch.read_bytes()
    return write_atomic(path, lambda fh: fh.write(data), flag, binary=True)
