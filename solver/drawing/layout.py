"""Fixing a matplotlib figure's layout before saving: one step shared by every drawing.

Light on purpose (matplotlib only): the survey charts of :mod:`analysis.chart` use it too,
and importing :mod:`solver.drawing.render` would bring in sympy (seconds of start-up).

A figure made with ``layout=MeasuredLayout()`` is placed by :func:`measured_layout` (the report's
figures and the scene drawings); :func:`fix_layout` runs a figure's layout engine once and keeps
its result, whichever engine it is.
"""
from __future__ import annotations

import warnings
import weakref

from matplotlib import rc_context
from matplotlib.layout_engine import LayoutEngine

from ..kept import Kept

__all__ = ["fix_layout", "MeasuredLayout", "measured_layout", "agg_renderer", "FontHeights", "font_key", "LAYOUT_PAD",
           "measure_as_vector", "vector_text_metrics"]

LAYOUT_PAD = 3.0
"""Clearance around every panel's texts and between the texts and the figure's edge [points]
(the padding of matplotlib's constrained layout, ``w_pad`` and ``h_pad``)."""


def fix_layout(fig) -> None:
    """Solve the figure's layout now, then keep the axes where it put them: no layout engine from
    then on, so that saving keeps this layout (for the scene drawings, the one labels were placed in).

    Not ``set_layout_engine("none")``: that leaves a placeholder engine, and with any engine set
    ``savefig`` draws the whole figure once without output first, then solves the layout again
    in the real draw (two draws and two layouts per file). A figure without an engine (one
    :func:`measured_layout` placed) is left as it is."""
    engine = fig.get_layout_engine()
    if engine is None:
        return
    engine.execute(fig)  # a placeholder engine (a layout fixed before) does nothing
    with rc_context({"figure.autolayout": False, "figure.constrained_layout.use": False}):
        fig.set_layout_engine(None)  # None falls back to these two settings: both off


class MeasuredLayout(LayoutEngine):
    """A layout engine running :func:`measured_layout` (``Figure(..., layout=MeasuredLayout())``).

    Parameters
    ----------
    pad : float
        Clearance around the texts [points].
    """

    _adjust_compatible = True
    _colorbar_gridspec = True

    def __init__(self, pad: float = LAYOUT_PAD, **kwargs):
        super().__init__(**kwargs)
        self.set(pad=pad)

    def set(self, *, pad: float = LAYOUT_PAD) -> None:
        """Set the clearance [points]."""
        self._params = {"pad": float(pad)}

    def execute(self, fig) -> None:
        """Place the figure's axes (:func:`measured_layout`)."""
        measured_layout(fig, self._params["pad"])


def agg_renderer(fig):
    """The renderer that measures the figure's texts: its canvas's, or an Agg canvas's (a figure
    made without pyplot has a canvas that cannot render), reading each font's heights once
    (:class:`FontHeights`) and each plain text once per process (:class:`_RasterTextSizes`); for a
    figure saved only in vector formats (:func:`measure_as_vector`), measuring each text as those
    formats draw it (:class:`_VectorTextSizes`)."""
    canvas = fig.canvas
    if not hasattr(canvas, "get_renderer"):
        from matplotlib.backends.backend_agg import FigureCanvasAgg

        canvas = FigureCanvasAgg(fig)
    renderer = canvas.get_renderer()
    if not hasattr(renderer, "_get_font_height_metrics"):
        renderer._get_font_height_metrics = FontHeights(renderer.dpi)
    measure = renderer.__dict__.get("get_text_width_height_descent")
    if getattr(fig, _VECTOR_FLAG, False):
        if not isinstance(measure, _VectorTextSizes):
            renderer.get_text_width_height_descent = _VectorTextSizes(renderer)
    elif measure is None and type(renderer) is _agg_renderer_class():
        renderer.get_text_width_height_descent = _RasterTextSizes(renderer)
    return renderer


def _agg_renderer_class():
    from matplotlib.backends.backend_agg import RendererAgg

    return RendererAgg


_VECTOR_FLAG = "_alt_euler_vector_text"
"""The attribute :func:`measure_as_vector` sets on a figure."""


def measure_as_vector(fig) -> None:
    """Lay ``fig`` out with its texts measured as the vector formats (SVG, PDF) draw them, not as a
    PNG would: for a figure that is only ever saved as SVG or PDF (the report's).

    matplotlib's SVG and PDF renderers measure a text from its unhinted glyphs at 72 points to the
    inch (:func:`vector_text_metrics`, the SVG renderer's measure); a PNG's renderer measures it from
    glyphs hinted to the figure's pixels, up to a few percent wider or narrower. With this, the
    layout (the axes' places, the labels' places) is computed from the sizes the saved texts have,
    and each text is measured once per process for the layout and the drawing alike, instead of
    once by each renderer (a text's measure loads each of its glyphs in FreeType, some 30 us a
    character)."""
    setattr(fig, _VECTOR_FLAG, True)


_VECTOR_SIZES: dict = {}
"""(text, font files, size, hinting and kerning factors) -> (width, height, descent) [points]
(:func:`vector_text_metrics`)."""


def vector_text_metrics(s: str, prop, ismath) -> tuple[float, float, float]:
    """Width, height and descent [points] of text ``s`` in font ``prop`` as matplotlib's SVG renderer
    measures it (``matplotlib.textpath.TextToPath.get_text_width_height_descent``: the glyphs
    unhinted, at 72 points to the inch; the PDF renderer's own measure, by another route, is within
    about 0.1 % of it).
    Plain text is measured once per process for each text, font file and size (the SVG renderer
    measures it again for every figure); mathematical text is measured each time."""
    from matplotlib import rcParams
    from matplotlib.font_manager import fontManager
    from matplotlib.textpath import text_to_path

    if ismath:
        return text_to_path.get_text_width_height_descent(s, prop, ismath)
    key = (s, tuple(fontManager._find_fonts_by_props(prop)), prop.get_size_in_points(),
           rcParams["text.hinting_factor"], rcParams["text.kerning_factor"])
    sizes = _VECTOR_SIZES.get(key)
    if sizes is None:
        sizes = _VECTOR_SIZES[key] = text_to_path.get_text_width_height_descent(s, prop, ismath)
    return sizes


class _VectorTextSizes:
    """A measuring renderer's ``get_text_width_height_descent`` for a figure saved only as SVG or PDF
    (:func:`measure_as_vector`): :func:`vector_text_metrics` in the renderer's pixels; TeX text as
    the renderer measures it."""

    def __init__(self, renderer):
        self._renderer = weakref.ref(renderer)  # (the renderer holds this object)
        self._measure = type(renderer).get_text_width_height_descent

    def __call__(self, s, prop, ismath):
        renderer = self._renderer()
        if ismath == "TeX":
            return self._measure(renderer, s, prop, ismath)
        scale = renderer.points_to_pixels(1.0)
        return tuple(value * scale for value in vector_text_metrics(s, prop, ismath))


_RASTER_SIZES = Kept(4096)
"""(text, font files, size, dpi, hinting, hinting and kerning factors, last-resort font) -> (width,
height, descent) [pixels] (:class:`_RasterTextSizes`), the last 4096 kept."""


class _RasterTextSizes:
    """An Agg renderer's ``get_text_width_height_descent``, its plain texts measured once per process
    for each text, font files, size and dpi (:data:`_RASTER_SIZES`).

    matplotlib keeps a renderer's measures for that renderer only, and every drawing makes its own
    (a figure, its canvas): the same labels (a point's name, a force's) were measured again in every
    drawing, each measure laying the text's glyphs out in FreeType. The Agg measure is a function of
    the text, the fonts, their size, the dpi and the hinting and kerning settings alone, which the
    key holds, so a measure kept is the one the renderer would give. Mathematical and TeX text is
    measured by the renderer each time."""

    def __init__(self, renderer):
        self._renderer = weakref.ref(renderer)  # (the renderer holds this object)
        self._measure = type(renderer).get_text_width_height_descent

    def __call__(self, s, prop, ismath):
        renderer = self._renderer()
        if ismath:
            return self._measure(renderer, s, prop, ismath)
        from matplotlib import rcParams
        from matplotlib.font_manager import fontManager

        key = (s, tuple(fontManager._find_fonts_by_props(prop)), prop.get_size_in_points(), renderer.dpi,
               rcParams["text.hinting"], rcParams["text.hinting_factor"], rcParams["text.kerning_factor"],
               rcParams["font.enable_last_resort"])
        return _RASTER_SIZES.get(key, lambda: self._measure(renderer, s, prop, ismath))


_HEIGHT_TABLES = (("OS/2", "sTypoLineGap", "sTypoAscender", "sTypoDescender"), ("hhea", "lineGap", "ascent", "descent"))
"""Where matplotlib's text layout reads a font's heights, in its order (``Text._get_layout``)."""


def font_key(prop) -> tuple:
    """What a ``FontProperties`` holds, as a key for what depends on it alone while the settings stay
    (the fonts matplotlib finds for it, their heights): its family, style, variant, weight,
    stretch, size, file and mathematical family. (A ``FontProperties`` can change after it is
    used as a key; this tuple cannot.)"""
    return (tuple(prop.get_family()), prop.get_style(), prop.get_variant(), prop.get_weight(), prop.get_stretch(),
            prop.get_size_in_points(), prop.get_file(), prop.get_math_fontfamily())


class FontHeights:
    """A font's ascent, descent and line gap [pixels at ``dpi``], as matplotlib's text layout reads
    them from the font's tables, read once per font and size for one renderer.

    ``Text._get_layout`` finds the font and reads two of its tables each time it lays a text out
    (every measure and every draw of every text) unless the renderer answers
    ``_get_font_height_metrics(prop)`` (matplotlib's PDF and PostScript renderers do, for their
    core fonts); a renderer given this object answers with the same numbers, computed by the same
    arithmetic, once per font properties. ``dpi`` must be the figure's while the renderer draws or
    measures (a renderer is made for one dpi)."""

    def __init__(self, dpi: float):
        self.dpi = dpi
        self._known: dict = {}

    def __call__(self, prop) -> tuple:
        key = font_key(prop)
        if key not in self._known:
            self._known[key] = self._read(prop)
        return self._known[key]

    def _read(self, prop) -> tuple:
        from matplotlib.font_manager import fontManager, get_font

        font = get_font(fontManager._find_fonts_by_props(prop))
        for table_name, gap_key, ascent_key, descent_key in _HEIGHT_TABLES:
            table = font.get_sfnt_table(table_name)
            if table is None:
                continue
            scale = 1 / font.get_sfnt_table("head")["unitsPerEm"] * prop.get_size_in_points() * self.dpi / 72
            return table[ascent_key] * scale, -table[descent_key] * scale, table[gap_key] * scale
        return None, None, None  # matplotlib measures "lp" instead


def measured_layout(fig, pad: float = LAYOUT_PAD) -> None:
    """Place the figure's grid of axes so that every text fits, from the texts' measured sizes.

    Each axes gets the room its decorations take beyond its box (tick labels, axis labels, title,
    a legend anchored outside it, its own texts), rows and columns are set apart by the room
    their neighbours take plus ``pad``, and what is left is shared by the grid's height and width
    ratios. The suptitle and the figure's legends keep their places (at the top and the bottom
    edge) and the grid stays clear of them. The texts are measured again in the new places until
    they take the room they were given: the tick labels follow the axes' size (a longer axis may
    get more ticks). After three placings the larger room of the last two measures is kept.

    matplotlib's constrained layout gives the same kind of layout but measures every axes'
    tight box several times over (each a full tick update), which cost about a quarter of
    drawing a report figure.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        Its axes each fill one cell of one grid (``fig.subplots``), axis labels at the left and
        the bottom (matplotlib's default).
    pad : float
        Clearance [points].
    """
    axes = [ax for ax in fig.axes if ax.get_visible()]
    if not axes:
        return
    grid = axes[0].get_subplotspec().get_gridspec()
    nrows, ncols = grid.get_geometry()
    cells = {}
    for ax in axes:
        spec = ax.get_subplotspec()
        if spec.get_gridspec() is not grid or len(spec.rowspan) != 1 or len(spec.colspan) != 1:
            raise ValueError("measured_layout places a grid of one axes per cell")
        cells[(spec.rowspan.start, spec.colspan.start)] = ax
    renderer = agg_renderer(fig)
    px = pad * fig.dpi / 72.0
    top_edge, bottom_edge = _figure_margins(fig, renderer)
    room = None
    for attempt in range(3):
        now = {key: _decorations(ax, renderer) for key, ax in cells.items()}
        if room is not None and all(abs(a - b) <= 0.5 for key in cells for a, b in zip(now[key], room[key])):
            return  # the texts take the room they were given (to half a pixel)
        # the last try keeps the larger room of the two last measures: the texts fit either way
        room = now if attempt < 2 else {key: tuple(map(max, now[key], room[key])) for key in cells}
        _place(fig, cells, room, nrows, ncols, grid, px, top_edge, bottom_edge)


def _figure_margins(fig, renderer) -> tuple[float, float]:
    """Room [pixels] the figure's own texts (its suptitle) and legends take at the top and the
    bottom edge: from the edge to their far side."""
    height = fig.bbox.height
    top = bottom = 0.0
    for artist in [*fig.texts, *fig.legends]:
        if not (artist.get_visible() and artist.get_in_layout()):
            continue
        if hasattr(artist, "get_text") and not artist.get_text():
            continue
        box = artist.get_window_extent(renderer)
        if box.y0 + box.y1 > height:  # in the upper half: room from the top edge
            top = max(top, height - box.y0)
        else:
            bottom = max(bottom, box.y1)
    return top, bottom


def _decorations(ax, renderer) -> tuple[float, ...]:
    """Room [pixels] the axes' texts take beyond its cell (its box before the aspect shrinks it):
    (left, bottom, right, top), and the least width and height of the cell (of its centred title
    and axis labels: a cell narrower than such a text would leave it running past both ends).

    Tick labels, the title, a legend anchored outside and the axes' own texts are measured where
    they stand (each placed relative to the box); the axis labels, which matplotlib places when it
    draws, by their size beyond the tick labels and centred along the axis, as matplotlib places
    them.
    """
    box = ax.get_position().transformed(ax.figure.transFigure)  # as drawn: shrunk to its aspect in its cell
    cell = ax.get_position(original=True).transformed(ax.figure.transFigure)
    boxes = []
    ticks = {}
    for name, axis in (("x", ax.xaxis), ("y", ax.yaxis)):
        if not (ax.axison and axis.get_visible()):
            ticks[name] = []
            continue
        ticks[name] = [t.get_window_extent(renderer) for t in _tick_labels(axis)]
        boxes += ticks[name]
    # a title's three places (centre, left, right), read as matplotlib's own layouts read them; the
    # centred one's width is one the cell must have (below), its height room above
    wide = tall = 0.0
    for title in (ax.title, ax._left_title, ax._right_title):
        if title.get_visible() and title.get_text():
            extent = title.get_window_extent(renderer)
            if title is ax.title:
                wide = extent.width
                extent = extent.from_extents(box.x0, extent.y0, box.x0, extent.y1)
            boxes.append(extent)
    legend = ax.get_legend()
    if legend is not None and legend.get_visible() and legend.get_bbox_to_anchor() is not ax.bbox:
        boxes.append(legend.get_window_extent(renderer))  # anchored elsewhere: may stand outside
    boxes += [t.get_window_extent(renderer) for t in ax.texts
              if t.get_visible() and t.get_in_layout() and t.get_text()]
    left = max([box.x0 - b.x0 for b in boxes], default=0.0)
    right = max([b.x1 - box.x1 for b in boxes], default=0.0)
    bottom = max([box.y0 - b.y0 for b in boxes], default=0.0)
    top = max([b.y1 - box.y1 for b in boxes], default=0.0)
    to_pixels = ax.figure.dpi / 72.0
    label = ax.yaxis.label
    if ax.axison and ax.yaxis.get_visible() and label.get_visible() and label.get_text():
        beyond = max([box.x0 - b.x0 for b in ticks["y"]] + [0.0])
        size = label.get_window_extent(renderer)
        left = max(left, beyond + ax.yaxis.labelpad * to_pixels + size.width)
        tall = size.height  # centred beside the axes: its cell at least as tall, or it runs past both ends
    label = ax.xaxis.label
    if ax.axison and ax.xaxis.get_visible() and label.get_visible() and label.get_text():
        beyond = max([box.y0 - b.y0 for b in ticks["x"]] + [0.0])
        size = label.get_window_extent(renderer)
        bottom = max(bottom, beyond + ax.xaxis.labelpad * to_pixels + size.height)
        wide = max(wide, size.width)  # centred under the axes (a free-body diagram's legend): the cell as wide
    # beyond the cell: an axes shrunk to its aspect leaves part of its cell free around it
    slack = (box.x0 - cell.x0, box.y0 - cell.y0, cell.x1 - box.x1, cell.y1 - box.y1)
    return (*(max(room - free, 0.0) for room, free in zip((left, bottom, right, top), slack)), wide, tall)


def _tick_labels(axis) -> list:
    """The tick labels matplotlib draws on ``axis`` (visible, not empty), with the ticks updated to
    the axis's current size and limits. ``Axis._update_ticks`` is the step matplotlib's own
    drawing and tight boxes take: the major and minor ticks inside the view interval, each
    placed and labelled (the public ``get_ticklabels`` also lists the ticks the locators give
    beyond the interval, which are not drawn)."""
    return [t.label1 for t in axis._update_ticks() if t.label1.get_visible() and t.label1.get_text()]


def _place(fig, cells, room, nrows, ncols, grid, px, top_edge, bottom_edge) -> None:
    """Set each axes' box: the rows' and columns' rooms and clearances taken from the figure's
    size, the rest shared by the grid's ratios."""
    width, height = fig.bbox.width, fig.bbox.height
    lefts = [max((room[k][0] for k in cells if k[1] == c), default=0.0) for c in range(ncols)]
    rights = [max((room[k][2] for k in cells if k[1] == c), default=0.0) for c in range(ncols)]
    bottoms = [max((room[k][1] for k in cells if k[0] == r), default=0.0) for r in range(nrows)]
    tops = [max((room[k][3] for k in cells if k[0] == r), default=0.0) for r in range(nrows)]
    w_ratios = grid.get_width_ratios() or [1.0] * ncols
    h_ratios = grid.get_height_ratios() or [1.0] * nrows
    least_w = [max((room[k][4] for k in cells if k[1] == c), default=0.0) for c in range(ncols)]
    least_h = [max((room[k][5] for k in cells if k[0] == r), default=0.0) for r in range(nrows)]
    free_w = width - (ncols + 1) * px - sum(lefts) - sum(rights)
    free_h = height - top_edge - bottom_edge - (nrows + 1) * px - sum(tops) - sum(bottoms)
    if (free_w < max(0.1 * width, sum(least_w)) or free_h < max(0.1 * height, sum(least_h))):
        # as matplotlib's layouts: a warning, and a cramped figure
        warnings.warn(f"measured_layout: the figure ({fig.get_size_inches()} in) is too small for its texts; "
                      "they may overlap", stacklevel=3)
        free_w, free_h = max(free_w, 0.1 * width), max(free_h, 0.1 * height)
    x, xs = px, []
    for c, w in enumerate(_shares(free_w, w_ratios, least_w)):
        xs.append((x + lefts[c], w))
        x += lefts[c] + w + rights[c] + px
    y, ys = height - top_edge - px, []
    for r, h in enumerate(_shares(free_h, h_ratios, least_h)):  # row 0 at the top
        ys.append((y - tops[r] - h, h))
        y -= tops[r] + h + bottoms[r] + px
    for (r, c), ax in cells.items():
        (x0, w), (y0, h) = xs[c], ys[r]
        ax.set_position((x0 / width, y0 / height, w / width, h / height))


def _shares(free: float, ratios, least) -> list[float]:
    """``free`` shared by ``ratios``, each share at least its ``least`` when there is room for it:
    the shares below their least get it, the others share the rest by their ratios."""
    shares = [free * r / sum(ratios) for r in ratios]
    short = [k for k, (s, m) in enumerate(zip(shares, least)) if s < m]
    rest = free - sum(least[k] for k in short)
    others = [k for k in range(len(ratios)) if k not in short]
    if not short or not others or rest <= 0:
        return shares
    return [least[k] if k in short else rest * ratios[k] / sum(ratios[j] for j in others) for k in range(len(ratios))]
