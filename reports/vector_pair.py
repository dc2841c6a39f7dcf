"""One figure as SVG and as PDF from a single drawing pass.

The report inlines each figure as SVG and writes its PDF twin next to paper.tex. Saving the
two separately draws the figure twice: every artist, tick and text laid out again for the
second file. Here matplotlib draws once into a renderer that hands every drawing call to both
matplotlib's SVG renderer and its PDF renderer (both at 72 points to the inch). The SVG is
byte for byte what ``savefig`` writes; the PDF is too, but for texts anchored by the SVG
renderer's measure of their width (see :class:`_BothRenderers`; the tests hold both).
"""
from __future__ import annotations

import io
import itertools
import logging
import math
from contextlib import contextmanager
from functools import lru_cache

import matplotlib as mpl
from matplotlib.backend_bases import FigureCanvasBase
from matplotlib.backends import backend_pdf
from matplotlib.backends.backend_mixed import MixedModeRenderer
from matplotlib.backends.backend_pdf import Op, PdfFile, RendererPdf
from matplotlib.backends.backend_svg import RendererSVG
from matplotlib.font_manager import FontPath, fontManager, get_font
from matplotlib.ft2font import LoadFlags

from solver.drawing.layout import FontHeights, fix_layout, font_key, vector_text_metrics

__all__ = ["svg_and_pdf"]

_DRAWING_CALLS = ("draw_path", "draw_markers", "draw_path_collection", "draw_quad_mesh",
                  "draw_gouraud_triangles", "draw_image", "open_group", "close_group",
                  "start_rasterizing", "stop_rasterizing", "start_filter", "stop_filter")


class _BothRenderers:
    """A renderer passing each drawing call to an SVG and a PDF renderer.

    Questions the artists ask while drawing (text extents, canvas size, points to pixels) are
    answered by the SVG renderer, so the SVG is the one ``savefig`` writes. The PDF renderer
    measures a text's width up to about 0.1 % apart (another route to the same font metrics), so
    a centred or right-aligned text, or a legend's frame, can lie that much (hundredths of a
    point) from where the PDF alone puts it; nothing else differs. Text positions come with y downwards (SVG's ``flipy``); the PDF renderer gets them
    with y upwards.
    """

    def __init__(self, svg, pdf):
        self._svg, self._pdf = svg, pdf
        self._height = svg.get_canvas_width_height()[1]
        self._get_font_height_metrics = FontHeights(72)  # the fonts' heights read once (both at 72 dpi)
        for name in _DRAWING_CALLS:
            setattr(self, name, self._both(name))

    def _both(self, name):
        first, second = getattr(self._svg, name), getattr(self._pdf, name)

        def call(*args, **kwargs):
            first(*args, **kwargs)
            second(*args, **kwargs)
        return call

    def __getattr__(self, name):
        return getattr(self._svg, name)

    def new_gc(self):
        return self._pdf.new_gc()  # a PDF graphics context: the SVG renderer reads the same properties

    def get_text_width_height_descent(self, s, prop, ismath):
        """The SVG renderer's measure of a text (:func:`solver.drawing.layout.vector_text_metrics`,
        which measured it for the layout already)."""
        if ismath == "TeX":
            return self._svg.get_text_width_height_descent(s, prop, ismath)
        return vector_text_metrics(s, prop, ismath)

    def draw_text(self, gc, x, y, s, prop, angle, ismath=False, mtext=None):
        self._svg.draw_text(gc, x, y, s, prop, angle, ismath=ismath, mtext=mtext)
        self._pdf.draw_text(gc, x, self._height - y, s, prop, angle, ismath=ismath, mtext=mtext)

    def draw_tex(self, gc, x, y, s, prop, angle, *, mtext=None):
        self._svg.draw_tex(gc, x, y, s, prop, angle, mtext=mtext)
        self._pdf.draw_tex(gc, x, self._height - y, s, prop, angle, mtext=mtext)


@lru_cache(maxsize=1024)
def _laid_out(font, size: float, s: str, features, language) -> tuple:
    """``font._layout(s)`` (unhinted, as the PDF renderer lays a text out) of ``font`` set to ``size``
    [points at 72 dpi] by the caller, made once per process for each text: the figures repeat
    tick labels, legends and captions."""
    return tuple(font._layout(s, LoadFlags.NO_HINTING, features=features, language=language))


def _frozen(value):
    """A text's font features or language as a key (lists as tuples)."""
    if isinstance(value, list):
        return tuple(_frozen(v) for v in value)
    return value


class _PdfRenderer(RendererPdf):
    """matplotlib's PDF renderer, writing plain text without loading each glyph's outline.

    ``RendererPdf.draw_text`` lays a text out with ``matplotlib._text_helpers.layout``, which loads
    every glyph (its outline, in FreeType) as it goes; the PDF text only needs the glyphs' indices,
    positions and kerns, which the layout itself gives (the glyphs embedded in the file are loaded
    again when the fonts are written, as before). Skipping the loads halves the cost of the PDF's
    texts; the operators written are the same, in the same order. Mathematical text, the core
    fonts and texts with a link go through matplotlib's own method.

    The renderer also remembers, for the one file it writes, the fonts found for each set of font
    properties and each glyph's place in the file's font subsets (the file's character tracker
    gives the same answer for the same glyph every time it is asked): a figure's texts repeat
    both many times."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._found_fonts: dict = {}  # font_key(prop) -> the font files matplotlib finds for it
        self._glyph_codes: dict = {}  # (font file, face, characters, glyph) -> (subset, character code)

    def _get_font_ttf(self, prop):
        """The font of ``prop`` at its size, as matplotlib's ``_get_font_ttf`` gives it (cleared and set
        to the size at 72 dpi), its files found once per set of properties."""
        key = font_key(prop)
        files = self._found_fonts.get(key)
        if files is None:
            files = self._found_fonts[key] = fontManager._find_fonts_by_props(prop)
        try:
            font = get_font(files)
            font.clear()
            font.set_size(prop.get_size_in_points(), 72)
            return font
        except RuntimeError:  # as matplotlib says it
            logging.getLogger(RendererPdf._get_font_ttf.__module__).warning(
                "The PostScript/PDF backend does not currently support the selected font (%s).", files)
            raise

    def _track(self, item):
        """(subset, character code) of a laid-out glyph in this file (the character tracker's
        ``track_glyph``, asked once per glyph)."""
        key = (item.ft_object.fname, item.ft_object.face_index, item.char, item.glyph_index)
        found = self._glyph_codes.get(key)
        if found is None:
            found = self._glyph_codes[key] = self.file._character_tracker.track_glyph(
                item.ft_object, item.char, item.glyph_index)
        return found

    def draw_text(self, gc, x, y, s, prop, angle, ismath=False, mtext=None):
        if ismath or mpl.rcParams["pdf.use14corefonts"] or gc.get_url() is not None:
            return super().draw_text(gc, x, y, s, prop, angle, ismath=ismath, mtext=mtext)
        self.check_gc(gc, gc._rgb)
        fontsize = prop.get_size_in_points()
        features = mtext.get_fontfeatures() if mtext is not None else None
        language = mtext.get_language() if mtext is not None else None
        font = self._get_font_ttf(prop)
        fonttype = mpl.rcParams["pdf.fonttype"]
        chunk = []  # [kern, char, char, ...], the kerns in points, no zero kerns

        def flush():
            if chunk:
                self.file.output([-1000 * next(group) / fontsize if kind is float  # a kern
                                  else self._encode_glyphs(group, fonttype)
                                  for kind, group in itertools.groupby(chunk, type)], Op.showkern)
                chunk.clear()
        a = math.radians(angle)
        self.file.output(Op.gsave)
        self.file.output(math.cos(a), math.sin(a), -math.sin(a), math.cos(a), x, y, Op.concat_matrix)
        self.file.output(Op.begin_text)
        prev_font, prev_start_x = None, 0
        for item in _laid_out(font, fontsize, s, _frozen(features), _frozen(language)):
            subset, charcode = self._track(item)
            if (item.ft_object, subset) != prev_font:
                flush()
                name = self.file.fontName(FontPath(item.ft_object.fname, item.ft_object.face_index), subset)
                self.file.output(name, fontsize, Op.selectfont)
                self._setup_textpos(item.x, 0, 0, prev_start_x, 0, 0)
                prev_font, prev_start_x = (item.ft_object, subset), item.x
            if item.y:
                flush()
                self.file.output(item.y, Op.textrise)
            if item.prev_kern:
                chunk.append(item.prev_kern)
            chunk.append(charcode)
            if item.y:
                flush()
                self.file.output(0, Op.textrise)
        flush()
        self.file.output(Op.end_text)
        self.file.output(Op.grestore)


_GLYPH_PROCEDURES: dict = {}
"""(font file, glyph index) -> (glyph name, the PDF procedure that draws it), for every PDF this
process writes (:func:`_glyph_procedures`)."""


def _glyph_procedures(font_path, glyph_indices) -> dict:
    """``matplotlib.backends.backend_pdf._get_pdf_charprocs``, each glyph's procedure made once per
    process: the glyph's name -> its procedure, in the order of ``glyph_indices``, as that function
    gives them. Every figure's PDF embeds the glyphs it uses (a Type 3 font subset); the report's
    figures share most of them, and making one loads the glyph's outline and writes its path."""
    for glyph in glyph_indices:
        if (font_path, glyph) not in _GLYPH_PROCEDURES:
            (name, procedure), = _MAKE_PROCEDURES(font_path, [glyph]).items()
            _GLYPH_PROCEDURES[font_path, glyph] = (name, procedure)
    return dict(_GLYPH_PROCEDURES[font_path, glyph] for glyph in glyph_indices)


_MAKE_PROCEDURES = getattr(backend_pdf, "_get_pdf_charprocs", None)
_GET_FONT = getattr(backend_pdf, "get_font", None)
_UNSCALED = LoadFlags.NO_SCALE | LoadFlags.NO_HINTING

_ADVANCES: dict = {}
"""(font file, glyph index) -> the glyph's unscaled advance width [font units], for every PDF this
process writes (:class:`_FontAdvancesOnce`)."""


class _Advance:
    """The one field of a loaded glyph that the Type 3 widths ask for."""

    __slots__ = ("horiAdvance",)

    def __init__(self, advance):
        self.horiAdvance = advance


class _FontAdvancesOnce:
    """The font matplotlib's PDF backend embeds (``get_font(file)``), each glyph's unscaled advance
    width read once per process: the Type 3 widths array loads the glyph of every character code
    from the subset's first to its last (the glyph 0 for the codes not used), in every figure, to
    read that one number, a property of the font file alone. Everything else is the font's own."""

    def __init__(self, font, path):
        self._font, self._path = font, path

    def __getattr__(self, name):
        return getattr(self._font, name)

    def load_glyph(self, glyph, *args, **kwargs):
        flags = args[0] if args else kwargs.get("flags")
        if flags != _UNSCALED or len(args) + len(kwargs) != 1:
            return self._font.load_glyph(glyph, *args, **kwargs)
        key = (self._path, glyph)
        advance = _ADVANCES.get(key)
        if advance is None:
            advance = _ADVANCES[key] = _Advance(self._font.load_glyph(glyph, flags=flags).horiAdvance)
        return advance


def _embedded_font(path):
    """``get_font(path)`` as the PDF backend's font embedding gets it (:class:`_FontAdvancesOnce`)."""
    return _FontAdvancesOnce(_GET_FONT(path), path)


@contextmanager
def _fonts_embedded_once():
    """While the block runs, matplotlib's PDF backend makes Type 3 glyph procedures through
    :func:`_glyph_procedures` and reads glyph widths through :class:`_FontAdvancesOnce` (nothing
    changes where matplotlib has no such functions, or for another font type)."""
    if _MAKE_PROCEDURES is None or _GET_FONT is None or mpl.rcParams["pdf.fonttype"] != 3:
        yield
        return
    backend_pdf._get_pdf_charprocs = _glyph_procedures
    backend_pdf.get_font = _embedded_font
    try:
        yield
    finally:
        backend_pdf._get_pdf_charprocs = _MAKE_PROCEDURES
        backend_pdf.get_font = _GET_FONT


class _PairCanvas(FigureCanvasBase):
    """A canvas whose one output format, ``svgpdf``, is the pair of files (see :func:`svg_and_pdf`)."""

    filetypes = {"svgpdf": "SVG and PDF, one drawing"}

    def print_svgpdf(self, sink, *, bbox_inches_restore=None, svg_metadata=None, pdf_metadata=None,
                     **_colours):
        """The body of matplotlib's ``print_svg`` and ``print_pdf``, with one ``figure.draw``. (Like
        them it ignores the face and edge colours and the orientation ``print_figure`` passes: the
        figure's own colours are set by ``print_figure`` itself.)"""
        image_dpi = self.figure.dpi
        self.figure.dpi = 72  # points to the inch of both formats
        width, height = self.figure.get_size_inches()
        svg_out, pdf_out = io.StringIO(), io.BytesIO()
        pdf_file = PdfFile(pdf_out, metadata=pdf_metadata)
        try:
            pdf_file.newPage(width, height)
            svg = MixedModeRenderer(self.figure, width, height, image_dpi,
                                    RendererSVG(width * 72, height * 72, svg_out, image_dpi=image_dpi,
                                                metadata=svg_metadata),
                                    bbox_inches_restore=bbox_inches_restore)
            pdf = MixedModeRenderer(self.figure, width, height, image_dpi,
                                    _PdfRenderer(pdf_file, image_dpi, height, width),
                                    bbox_inches_restore=bbox_inches_restore)
            self.figure.draw(_BothRenderers(svg, pdf))
            svg.finalize()
            pdf.finalize()
            with _fonts_embedded_once():  # the fonts are embedded here
                pdf_file.finalize()
        finally:
            pdf_file.close()
        sink["svg"], sink["pdf"] = svg_out.getvalue(), pdf_out.getvalue()


def svg_and_pdf(fig, svg_metadata: dict | None = None, pdf_metadata: dict | None = None) -> tuple[str, bytes]:
    """The figure's SVG text and PDF bytes, drawn once, in the layout :func:`solver.drawing.layout.fix_layout`
    fixes (the figure keeps it).

    Parameters
    ----------
    fig : matplotlib.figure.Figure
    svg_metadata, pdf_metadata : dict, optional
        As ``savefig(..., metadata=...)`` takes them for each format.

    Returns
    -------
    (str, bytes)
        The SVG document (with its XML prolog) and the PDF file, as ``savefig`` writes them.
    """
    fix_layout(fig)  # with a layout engine left, savefig would lay the figure out with the pair renderer
    previous = fig.canvas
    sink: dict = {}
    try:
        _PairCanvas(fig).print_figure(sink, format="svgpdf", svg_metadata=svg_metadata, pdf_metadata=pdf_metadata)
    finally:
        fig.set_canvas(previous)
    return sink["svg"], sink["pdf"]
