"""The free-body diagrams of a worked solution, drawn by :mod:`solver.drawing`.

Each step with a ``figure_request`` (one body's free-body diagram) gets the
drawing as inline SVG in ``Step.figure_svg``; the HTML rendering shows it, the
other formats keep the list of forces. The SVG is the project's own
(matplotlib escapes every label taken from the scene).
"""
from __future__ import annotations

__all__ = ["attach_figures"]


def attach_figures(explanation, system, point: str | None = None) -> None:
    """Draw the free-body diagram of every step that asks for one (in place)."""
    from solver.drawing import draw_system, figure_bytes

    for section in explanation.sections:
        for step in section.steps:
            request = step.figure_request
            if not request or not request.get("fbd"):
                continue
            drawing = draw_system(system, fbd=True, point=point, bodies=[request["body"]])
            svg = figure_bytes(drawing.figure, ".svg").decode("utf-8")
            step.figure_svg = svg[svg.find("<svg"):]  # inline: without the XML prolog and doctype
