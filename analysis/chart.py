"""Diverging stacked bar chart of Likert items (matplotlib).

Each item is one bar of its valid answers (percent of n). Disagreeing answers
extend left of zero, agreeing answers right, and neutral answers are split half
on each side of the centre line. Items are drawn in questionnaire order (top to
bottom) unless ``order="agree"`` sorts them by agreement share; each item's
label carries its n.

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

from .errors import SurveyInputError
from .likert import SurveySummary

__all__ = ["ORDERS", "MAX_CHART_ITEMS", "diverging_bar", "figure_svg"]

#: Valid ``order`` values.
ORDERS = ("questionnaire", "agree")
#: Most items one chart draws (drawing takes about 25 ms per item; the figure grows
#: half an inch per item).
MAX_CHART_ITEMS = 100

_NEG = ("#b2182b", "#d6604d", "#f4a582")      # strongest first
_POS = ("#2166ac", "#4393c3", "#92c5de")
_NEU = "#bdbdbd"


def _plain(text: str) -> str:
    """Text shown literally by matplotlib (no mathtext)."""
    return str(text).replace("\\", "\\\\").replace("$", r"\$")


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


def diverging_bar(summary: SurveySummary, order: str = "questionnaire",
                  title: str | None = None, wrap: int = 40) -> Figure:
    """Diverging stacked bar chart of every item's answers.

    Parameters
    ----------
    summary : SurveySummary
    order : {"questionnaire", "agree"}
        Item order top to bottom: as asked, or by agreement share (highest first).
    title : str, optional
    wrap : int
        Wrap item labels at this many characters.

    Returns
    -------
    matplotlib.figure.Figure
    """
    _validate_chart(summary, order)
    scale = summary.scale
    items = list(summary.items)
    if order == "agree":
        items.sort(key=lambda it: -(it.agree.share or 0.0))
    code = dict(zip(scale.labels, scale.codes))
    drawn = sorted(scale.labels, key=lambda lab: code[lab])     # left to right
    colors = _colors(scale)
    neutral = set(scale.neutral)
    negative = set(scale.negative)
    fig = Figure(figsize=(8.5, 1.0 + 0.55 * len(items)), layout="constrained")
    ax = fig.add_subplot()
    y = np.arange(len(items))[::-1]
    pct = np.array([[100.0 * it.counts[lab] / it.n if it.n else 0.0 for lab in drawn]
                    for it in items]).reshape(len(items), len(drawn))
    away = np.array([lab in negative for lab in drawn]) + 0.5 * np.array(
        [lab in neutral for lab in drawn])
    left = -(pct @ away)                  # negative answers, and half the neutral, left of 0
    for j, lab in enumerate(drawn):       # one call per label: the work grows with the items
        w = pct[:, j]
        shown = w > 0
        ax.barh(y[shown], w[shown], left=left[shown], color=colors[lab], edgecolor="white",
                linewidth=0.5, height=0.7)
        for yi, lo, wi in zip(y[w >= 8], left[w >= 8], w[w >= 8]):
            ax.text(lo + wi / 2, yi, f"{wi:.0f}", ha="center", va="center", fontsize=7,
                    color="white" if lab not in neutral else "black")
        left = left + w
    names = ["\n".join(textwrap.wrap(_plain(it.item), wrap) or [""]) + f"\n(n = {it.n})"
             for it in items]
    ax.set_yticks(y, names, fontsize=8)
    ax.axvline(0, color="black", linewidth=0.8)
    ax.set_xlim(-100, 100)
    ticks = np.arange(-100, 101, 25)
    ax.set_xticks(ticks, [f"{abs(t):.0f}%" for t in ticks], fontsize=8)
    ax.set_xlabel("percent of valid answers (neutral split across the centre)", fontsize=8)
    for side in ("top", "right"):
        ax.spines[side].set_visible(False)
    ax.legend([Patch(facecolor=colors[lab]) for lab in drawn],
              [_plain(lab) for lab in drawn], loc="upper center",
              bbox_to_anchor=(0.5, -0.18 if len(items) > 2 else -0.35), ncol=min(5, scale.k),
              fontsize=7, frameon=False)
    if title:
        ax.set_title(_plain(title), fontsize=10)
    return fig


def figure_svg(fig: Figure) -> str:
    """SVG text of a figure (text as text, reproducible ids)."""
    buf = io.StringIO()
    with rc_context({"svg.fonttype": "none", "svg.hashsalt": "analysis"}):
        fig.savefig(buf, format="svg", metadata={"Date": None, "Creator": None})
    svg = buf.getvalue()
    start = svg.find("<svg")
    return svg[start:] if start >= 0 else svg

