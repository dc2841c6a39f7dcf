"""reports.vector_pair: the SVG and the PDF of one drawing against matplotlib's own ``savefig``.

The reference is matplotlib saving each format on its own (two drawings), not the product.
"""
from __future__ import annotations

import io
import re
import zlib

import numpy as np
from matplotlib import rc_context
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure
from matplotlib.patches import Circle, FancyArrowPatch

from reports.figures import RC
from reports.vector_pair import svg_and_pdf

SVG_META = {"Date": None, "Creator": None}
PDF_META = {"CreationDate": None, "Creator": None, "Producer": None}
ANCHOR_TOL_PT = 0.2
"""How far a PDF number may lie from savefig's [points]: the SVG renderer, which measures the texts
for both files, and the PDF renderer get a text's width by two routes to the same font metrics
that differ by up to about 0.1 % of the width. Only positions derived from text widths can move: a
centred text's anchor by half of that (the widest below, the title, is 281 pt: 0.14 pt), a
right-aligned one's or the legend frame's by all of it (those texts are under 100 pt: 0.1 pt)."""


def _figure() -> Figure:
    """Every kind of artist the report's figures use: lines and markers, a legend, titles, rotated
    and aligned texts, text with unicode, arrows, patches, collections, shared axes, a grid."""
    fig = Figure(figsize=(6.0, 4.0), layout="constrained")
    ax, ax2 = fig.subplots(2, 1, sharex=True)
    x = np.linspace(0.0, 6.0, 50)
    ax.plot(x, np.sin(x), label="sin x")
    ax.plot(x[::5], np.cos(x[::5]), "o--", label="cos x, markers")
    ax.legend(loc="best", fontsize=8)
    ax.set_ylabel("value [rad/s²]")
    ax.annotate("right-aligned label", (3.0, 0.5), xytext=(-3, 3), textcoords="offset points", ha="right")
    ax.annotate("centred", (1.0, -0.5), ha="center", va="center", color="tab:red")
    ax2.add_patch(Circle((2.0, 0.0), 0.5, facecolor="tab:blue", alpha=0.3))
    ax2.add_patch(FancyArrowPatch((1.0, 0.0), (4.0, 0.5), arrowstyle="-|>", mutation_scale=11, linestyle="--"))
    ax2.add_collection(LineCollection([[(0, 0), (1, 1)], [(1, 0), (2, 1)]], colors="0.45"))
    ax2.set_xlabel("time t [s] (from rest)")
    ax2.set_ylim(-1, 1.5)
    fig.suptitle("One drawing, two files: an example title of some length", fontsize=10)
    return fig


def _saved(fig, fmt: str, metadata: dict):
    buf = io.StringIO() if fmt == "svg" else io.BytesIO()
    fig.savefig(buf, format=fmt, metadata=metadata)
    return buf.getvalue()


def _pdf_tokens(data: bytes) -> list[list[bytes]]:
    """The tokens of each stream of a PDF file, decompressed."""
    out = []
    for m in re.finditer(rb"stream\n(.*?)\nendstream", data, re.S):
        body = m.group(1)
        try:
            body = zlib.decompress(body)
        except zlib.error:
            pass
        out.append(body.split())
    return out


def test_one_drawing_gives_savefig_svg_and_pdf():
    with rc_context(RC):
        fig = _figure()
        svg, pdf = svg_and_pdf(fig, SVG_META, PDF_META)
        # (the pair first: it fixes the layout, which savefig then finds done)
        alone_svg, alone_pdf = _saved(fig, "svg", SVG_META), _saved(fig, "pdf", PDF_META)
    assert svg == alone_svg
    ours, theirs = _pdf_tokens(pdf), _pdf_tokens(alone_pdf)
    assert [len(s) for s in ours] == [len(s) for s in theirs]
    number = re.compile(rb"^-?\d+(\.\d*)?$")
    moved = []
    for a, b in zip(ours, theirs):
        for s, t in zip(a, b):
            if s != t:
                assert number.match(s) and number.match(t), (s, t)  # only numbers may differ
                moved.append(abs(float(s) - float(t)))
    assert max(moved, default=0.0) <= ANCHOR_TOL_PT
    assert b"/Producer" not in pdf and b"CreationDate" not in pdf


def test_canvas_is_given_back_and_figure_saves_again():
    fig = _figure()
    canvas = fig.canvas
    with rc_context(RC):
        svg_and_pdf(fig, SVG_META, PDF_META)
    assert fig.canvas is canvas
    assert fig.dpi == 100  # the 72 points to the inch of the vector files do not stay behind
    assert _saved(fig, "svg", SVG_META).startswith("<?xml")


def test_glyph_procedures_made_once_are_matplotlibs():
    """vector_pair._glyph_procedures (each glyph's PDF procedure made once per process) gives what
    matplotlib's own _get_pdf_charprocs gives, names and order, whatever was asked before."""
    from matplotlib.backends import backend_pdf
    from matplotlib.font_manager import FontPath, findfont, get_font

    from reports import vector_pair

    path = FontPath(findfont("DejaVu Sans"), 0)
    font = get_font(path)
    glyphs = [font.get_char_index(ord(c)) for c in "θ̈ = 19.50 N·m, −m a_P"]
    make = backend_pdf._get_pdf_charprocs  # matplotlib's own (the pair puts it back after each file)
    assert make is not vector_pair._glyph_procedures
    for asked in (glyphs[:5], glyphs, glyphs[::-1], glyphs[3:9]):
        ours = vector_pair._glyph_procedures(path, asked)
        theirs = make(path, asked)
        assert list(ours.items()) == list(theirs.items())


def test_fonts_embedded_once_give_matplotlibs_bytes(monkeypatch):
    """With the glyph procedures and widths remembered across files (vector_pair._fonts_embedded_once),
    the PDF is byte for byte the one matplotlib's own font embedding writes from the same drawing,
    cold and with both memos filled by an earlier file."""
    import contextlib

    from reports import vector_pair

    with rc_context(RC):
        fig = _figure()
        svg_and_pdf(fig, SVG_META, PDF_META)  # fixes the layout; fills the memos
        _, remembered = svg_and_pdf(fig, SVG_META, PDF_META)
        vector_pair._ADVANCES.clear()
        vector_pair._GLYPH_PROCEDURES.clear()
        _, cold = svg_and_pdf(fig, SVG_META, PDF_META)
        monkeypatch.setattr(vector_pair, "_fonts_embedded_once", contextlib.nullcontext)
        _, plain = svg_and_pdf(fig, SVG_META, PDF_META)
    assert remembered == plain and cold == plain
    assert b"/Widths" in plain


def test_the_benchmark_figure_labels_its_log_axes_in_plain_text():
    """The work-precision figure's log axes read 10 with a superscript exponent at each power of
    ten, written as text (10⁻³) rather than through matplotlib's mathtext parser, which took 0.3 s
    of a report build; values between powers get no label."""
    from reports.figures import _powers_of_ten, benchmark_figure
    from matplotlib.figure import Figure

    series = {"A": [(1e-3, 1e-2), (1e-2, 1e-8)], "B": [(1e-4, 1e-1), (3e-2, 1e-12)]}
    svg = benchmark_figure(series, "title", "time [s]", "error").svg
    assert "10\u207b\u00b9\u00b2" in svg and "10\u207b\u00b3" in svg and "$" not in svg
    ax = Figure().subplots()
    ax.set_xscale("log")
    _powers_of_ten(ax)
    label = ax.xaxis.get_major_formatter()
    assert [label(v, 0) for v in (1e-3, 1.0, 100.0, 2e-3, 50.0)] == ["10\u207b\u00b3", "10\u2070", "10\u00b2", "", ""]
