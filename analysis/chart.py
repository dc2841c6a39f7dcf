"""Diverging stacked bar chart of Likert items (matplotlib).

Each item is one bar of its valid answers (percent of n). Disagreeing answers
extend left of zero, agreeing answers right, and neutral answers are split half
on each side of the centre line. Items are drawn in questionnaire order (top to
bottom) unless ``order="agree"`` sorts them by agreement share; each item's
label carries its n. The disagreeing and agreeing totals stand at the bar ends, and
the figure has a title. :func:`faceted_bar` draws one panel per item with a bar per
group (sections, terms) in the comparison's order.

The figure is built with :class:`matplotlib.figure.Figure` directly (no pyplot
state, no GUI backend). :func:`figure_svg` renders it to SVG text with the text
kept as text and a fixed hash salt, so the output is reproducible. Input text
(item names) is escaped for matplotlib's mathtext (``$``) and, by matplotlib,
for XML.

Public API: :func:`diverging_bar` -> ``Figure``, :func:`figure_svg` -> ``str``.
"""
from __future__ import annotations

import io
import textwrap

import numpy as np
from matplotlib import rc_context
from matplotlib.colors import to_hex
from matplotlib.figure import Figure
from matplotlib.patches import Patch
from solver.drawing.layout import MeasuredLayout, fix_layout  # matplotlib only (no sympy): the one layout step

from .errors import SurveyInputError
from .likert import SurveySummary
from .rounding import percent_text

__all__ = ["ORDERS", "CHART_FORMATS", "MAX_CHART_ITEMS", "MAX_CHART_BARS", "diverging_bar",
           "faceted_bar", "figure_svg", "figure_bytes", "chart_format"]

#: Chart file formats, chosen by the output file's suffix.
CHART_FORMATS = ("svg", "png", "pdf")

#: Valid ``order`` values.
ORDERS = ("questionnaire", "agree")
#: Most items one chart draws (drawing takes about 25 ms per item; the figure grows
#: half an inch per item).
MAX_CHART_ITEMS = 100
#: Most bars (items x groups shown) one faceted group chart draws: its panels cost more
#: than plain bars, and the figure grows about 0.4 inch per bar.
MAX_CHART_BARS = 200

_NEG = ("#b2182b", "#d6604d", "#f4a582")      # strongest first
_POS = ("#2166ac", "#4393c3", "#92c5de")
_NEU = "#bdbdbd"
#: Label lines (8 pt) one bar's row (0.55 in) holds; a longer label gets a taller row.
_LINES_PER_ROW = 3
#: Resolution of a PNG chart, and the one the layout measures the texts at: rendered text
#: is not equally wide at every resolution (a 26-character label measured 1.50 in at 100 dpi
#: and drew 1.55 in at 150, its first character cut off at the figure's left edge).
DPI = 150


def _plain(text: str) -> str:
    """Text shown literally by matplotlib (no mathtext).

    Mathtext starts only at an unescaped ``$``; with every ``$`` escaped, matplotlib
    draws ``\\$`` as ``$`` and leaves backslashes as they are (doubling them would
    draw them doubled).
    """
    return str(text).replace("$", r"\$")


def _colors(scale) -> dict:
    labels = list(scale.labels)
    code = dict(zip(labels, scale.codes))
    neg = sorted(scale.negative, key=lambda lab: code[lab])          # most negative first
    pos = sorted(scale.positive, key=lambda lab: -code[lab])         # most positive first
    out = {lab: _NEU for lab in scale.neutral}
    for i, lab in enumerate(neg):
        out[lab] = _NEG[min(i, 2)] if len(neg) <= 3 else to_hex(
            (0.7 + 0.25 * i / len(neg), 0.1 + 0.5 * i / len(neg), 0.15 + 0.45 * i / len(neg)))
    for i, lab in enumerate(pos):
        out[lab] = _POS[min(i, 2)] if len(pos) <= 3 else to_hex(
            (0.1 + 0.5 * i / len(pos), 0.4 + 0.3 * i / len(pos), 0.67 + 0.2 * i / len(pos)))
    for lab in labels:
        out.setdefault(lab, _NEU)
    return out


def _validate_chart(summary, order):
    if not isinstance(summary, SurveySummary):
        raise TypeError(f"`summary` must be a SurveySummary, got {type(summary).__name__}")
    if order not in ORDERS:
        raise ValueError(f"`order` must be one of {list(ORDERS)}, got {order!r}")
    if len(summary.items) > MAX_CHART_ITEMS:
        raise SurveyInputError(f"{len(summary.items)} items; a chart draws at most "
                               f"{MAX_CHART_ITEMS} (choose some with --items)", summary.source)


def _draw_bars(ax, bars, scale, wrap: int) -> float:
    """Draw one diverging bar per (name, counts, n), top to bottom, with end totals.

    The disagreeing total is printed beyond the left end of each bar, the agreeing total
    beyond the right end (percent of valid answers, neutral not included in either).
    One ``barh`` call per label, so the work grows with the bars only once. A bar whose
    wrapped label takes more than three lines gets a row as tall as its label, so that
    labels never overlap. Returns the height of the rows, in bars.
    """
    names = ["\n".join(textwrap.wrap(_plain(name), wrap) or [""]) + f"\n(n = {n})"
             for name, _, n in bars]
    rows = np.array([max(1.0, (nm.count("\n") + 1) / _LINES_PER_ROW) for nm in names])
    y = rows.sum() - (np.cumsum(rows) - rows / 2) - 0.5      # 0.5: as np.arange when all 1
    code = dict(zip(scale.labels, scale.codes))
    drawn = sorted(scale.labels, key=lambda lab: code[lab])     # left to right
    colors = _colors(scale)
    neutral, negative, positive = set(scale.neutral), set(scale.negative), set(scale.positive)
    pct = np.array([[100.0 * counts[lab] / n if n else 0.0 for lab in drawn]
                    for _, counts, n in bars]).reshape(len(bars), len(drawn))
    away = np.array([lab in negative for lab in drawn]) + 0.5 * np.array(
        [lab in neutral for lab in drawn])
    start = -(pct @ away)                 # negative answers, and half the neutral, left of 0
    left = start
    for j, lab in enumerate(drawn):
        w = pct[:, j]
        shown = w > 0
        ax.barh(y[shown], w[shown], left=left[shown], color=colors[lab], edgecolor="white",
                linewidth=0.5, height=0.7)
        for b in np.flatnonzero(w >= 8):
            _, counts, n = bars[b]
            ax.text(left[b] + w[b] / 2, y[b], percent_text(counts[lab], n, 0), ha="center",
                    va="center", fontsize=7, color="white" if lab not in neutral else "black")
        left = left + w
    for yi, (_, counts, n), lo, hi in zip(y, bars, start, left):
        if n:                         # totals printed by the rule of every printed percentage
            d = percent_text(sum(counts[lab] for lab in negative), n, 0)
            a = percent_text(sum(counts[lab] for lab in positive), n, 0)
            ax.text(lo - 1.5, yi, f"{d}%", ha="right", va="center", fontsize=7,
                    color=_NEG[0], fontweight="bold")
            ax.text(hi + 1.5, yi, f"{a}%", ha="left", va="center", fontsize=7,
                    color=_POS[0], fontweight="bold")
    ax.set_yticks(y, names, fontsize=8)
    # the grid and the centre line behind the bars: drawn over them they ran through the count
    # labels (the 0 % line through every neutral count, a grid line through every count)
    ax.set_axisbelow(True)
    ax.axvline(0, color="black", linewidth=0.8, zorder=0.9)
    ax.set_xlim(-115, 115)
    ticks = np.arange(-100, 101, 25)
    ax.set_xticks(ticks, [f"{abs(t):.0f}%" for t in ticks], fontsize=8)
    for side in ("top", "right"):
        ax.spines[side].set_visible(False)
    return float(rows.sum())


def _legend(fig, scale, ncol_anchor) -> None:
    code = dict(zip(scale.labels, scale.codes))
    drawn = sorted(scale.labels, key=lambda lab: code[lab])
    colors = _colors(scale)
    fig.legend([Patch(facecolor=colors[lab]) for lab in drawn], [_plain(lab) for lab in drawn],
               loc="outside lower center", ncol=min(5, scale.k), fontsize=7, frameon=False)


def diverging_bar(summary: SurveySummary, order: str = "questionnaire",
                  title: str | None = None, wrap: int = 40) -> Figure:
    """Diverging stacked bar chart of every item's answers.

    Parameters
    ----------
    summary : SurveySummary
    order : {"questionnaire", "agree"}
        Item order top to bottom: as asked, or by agreement share (highest first).
    title : str, optional
        Default: the file name and "answers per item".
    wrap : int
        Wrap item labels at this many characters.

    Returns
    -------
    matplotlib.figure.Figure
        Disagreeing and agreeing totals (percent of valid answers) stand at the bar ends.
    """
    _validate_chart(summary, order)
    items = list(summary.items)
    if order == "agree":
        items.sort(key=lambda it: -(it.agree.share or 0.0))
    fig = Figure(figsize=(8.5, 1.6 + 0.55 * len(items)), dpi=DPI, layout=MeasuredLayout())
    ax = fig.add_subplot()
    rows = _draw_bars(ax, [(it.item, it.counts, it.n) for it in items], summary.scale, wrap)
    fig.set_size_inches(8.5, 1.6 + 0.55 * rows)      # taller rows for long labels
    centre = "neutral split across the centre; " if summary.scale.neutral else ""
    ax.set_xlabel(f"percent of valid answers ({centre}totals: disagree left, agree right)",
                  fontsize=8)
    _legend(fig, summary.scale, len(items))
    if title is None:
        from pathlib import Path
        title = f"{Path(summary.source).name}: answers per item"
    if title:
        fig.suptitle(_plain(title), fontsize=10)
    return fig


def faceted_bar(comparison, title: str | None = None, wrap: int = 60) -> Figure:
    """Diverging bars per group, one panel (facet) per item, groups in the comparison's order.

    Parameters
    ----------
    comparison : GroupComparison
        From :func:`~analysis.groups.compare_groups`; suppressed groups are not drawn.
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    from .groups import GroupComparison
    if not isinstance(comparison, GroupComparison):
        raise TypeError(f"`comparison` must be a GroupComparison, got "
                        f"{type(comparison).__name__}")
    shown = comparison.shown
    if not shown or not comparison.summaries:
        raise ValueError("no group to draw: every group is suppressed (--min-group)")
    first = comparison.summaries[shown[0]]
    scale = first.scale
    nitems = len(first.items)
    if nitems > MAX_CHART_ITEMS or nitems * len(shown) > MAX_CHART_BARS:
        raise SurveyInputError(
            f"{nitems} items x {len(shown)} groups; a group chart draws at most "
            f"{MAX_CHART_ITEMS} items and {MAX_CHART_BARS} bars (choose some with --items or "
            f"raise --min-group)", first.source)
    fig = Figure(figsize=(8.5, 1.4 + nitems * (0.5 + 0.42 * len(shown))), dpi=DPI,
                 layout=MeasuredLayout())
    axes = fig.subplots(nitems, 1, squeeze=False)[:, 0]
    for j, ax in enumerate(axes):
        bars = [(g, comparison.summaries[g].items[j].counts, comparison.summaries[g].items[j].n)
                for g in shown]
        _draw_bars(ax, bars, scale, 30)
        ax.set_title("\n".join(textwrap.wrap(_plain(first.items[j].item), wrap)), fontsize=9,
                     loc="left")
    axes[-1].set_xlabel("percent of valid answers (totals: disagree left, agree right)",
                        fontsize=8)
    _legend(fig, scale, nitems)
    fig.suptitle(_plain(title or f"Answers by {comparison.column}"), fontsize=10)
    return fig


def figure_svg(fig: Figure) -> str:
    """SVG text of a figure (text as text, reproducible ids)."""
    fix_layout(fig)
    buf = io.StringIO()
    with rc_context({"svg.fonttype": "none", "svg.hashsalt": "analysis"}):
        fig.savefig(buf, format="svg", metadata={"Date": None, "Creator": None})
    svg = buf.getvalue()
    start = svg.find("<svg")
    return svg[start:] if start >= 0 else svg



def chart_format(path) -> str:
    """The chart format of an output file name by its suffix (``.svg``, ``.png``, ``.pdf``).

    Raises
    ------
    ValueError
        Another suffix (the message names ``--chart`` and the valid suffixes).
    """
    from pathlib import Path
    fmt = Path(str(path)).suffix.lower().lstrip(".")
    if fmt not in CHART_FORMATS:
        raise ValueError(f"--chart {str(path)!r}: the file name must end in "
                         f"{', '.join('.' + f for f in CHART_FORMATS)} (the format follows it)")
    return fmt


def figure_bytes(fig: Figure, fmt: str = "svg") -> bytes:
    """A figure as SVG, PNG (:data:`DPI`) or PDF bytes, without dates (reproducible)."""
    if fmt == "svg":
        return figure_svg(fig).encode("utf-8")
    if fmt not in CHART_FORMATS:
        raise ValueError(f"`fmt` must be one of {list(CHART_FORMATS)}, got {fmt!r}")
    buf = io.BytesIO()
    meta = {"CreationDate": None} if fmt == "pdf" else {"Software": None}
    fix_layout(fig)
    fig.savefig(buf, format=fmt, dpi=DPI, metadata=meta)
    return buf.getvalue()
