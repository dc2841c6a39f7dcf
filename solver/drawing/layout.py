"""Fixing a matplotlib figure's layout before saving: one step shared by every drawing.

Light on purpose (matplotlib only): the survey charts of :mod:`analysis.chart` use it too,
and importing :mod:`solver.drawing.render` would bring in sympy (seconds of start-up).
"""
from __future__ import annotations

from matplotlib import rc_context

__all__ = ["fix_layout"]


def fix_layout(fig) -> None:
    """Solve the figure's layout now, then keep the axes where it put them: no layout engine from
    then on, so that saving keeps this layout (for the scene drawings, the one labels were placed in).

    Not ``set_layout_engine("none")``: that leaves a placeholder engine, and with any engine set
    ``savefig`` draws the whole figure once without output first, then solves the layout again
    in the real draw (two draws and two layouts per file)."""
    engine = fig.get_layout_engine()
    if engine is None:
        return
    engine.execute(fig)  # a placeholder engine (a layout fixed before) does nothing
    with rc_context({"figure.autolayout": False, "figure.constrained_layout.use": False}):
        fig.set_layout_engine(None)  # None falls back to these two settings: both off
