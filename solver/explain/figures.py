"""The free-body diagrams of a worked solution, drawn by :mod:`solver.drawing`.

Each step with a ``figure_request`` (one body's free-body diagram) gets the
drawing as inline SVG in ``Step.figure_svg``; the HTML rendering shows it, the
other formats keep the list of forces and say, in one line, the ``draw --fbd`` command that
draws it (:func:`attach_drawing_commands`). The SVG is the project's own
(matplotlib escapes every label taken from the scene).
"""
from __future__ import annotations

__all__ = ["attach_figures", "attach_drawing_commands"]


def attach_figures(explanation, system, point: str | None = None) -> None:
    """Draw the free-body diagram of every step that asks for one (in place): the system solved
    at its state once, by the first drawing, and each body's drawn from that solution."""
    from solver.drawing import draw_system, figure_bytes

    solution = None
    for section in explanation.sections:
        for step in section.steps:
            request = step.figure_request
            if not request or not request.get("fbd"):
                continue
            drawing = draw_system(system, fbd=True, point=point, bodies=[request["body"]], solution=solution)
            solution = drawing.solution
            svg = figure_bytes(drawing.figure, ".svg").decode("utf-8")
            step.figure_svg = svg[svg.find("<svg"):]  # inline: without the XML prolog and doctype


def attach_drawing_commands(explanation, scene: str, point: str | None = None, overrides=()) -> None:
    """Give every step that asks for a free-body diagram (in place) the command that draws it, which
    the rendering says in one line (``figure_request["command"]``): ``python -m solver draw SCENE --fbd [--point P] [--set NAME=VALUE ...] -o
    fbd.svg`` with the scene file, ``--point`` and ``--set`` values of the worked solution, each
    quoted for a POSIX shell where it needs to be. For the formats that do not embed the drawing."""
    import shlex

    words = ["python", "-m", "solver", "draw", scene, "--fbd"]
    words += ["--point", point] if point is not None else []
    for value in overrides:
        words += ["--set", value]
    command = " ".join(shlex.quote(w) for w in [*words, "-o", "fbd.svg"])
    for section in explanation.sections:
        for step in section.steps:
            request = step.figure_request
            if request and request.get("fbd"):
                request["command"] = command  # each format writes it as a line to type
