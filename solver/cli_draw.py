"""The ``draw`` command: a scene's configuration or its free-body diagrams as a figure.

``draw SCENE [--fbd] [--point BODY:POINT] [--set NAME=VALUE] -o FILE``: the
format follows FILE's suffix (.svg, .png, .pdf); the file is written
atomically. matplotlib is imported only when the command runs.
"""
from __future__ import annotations

import argparse

from solver.cli_common import add_common_arguments, load_scene_from_args

__all__ = ["register"]

FORMATS_TEXT = ".svg, .png or .pdf"


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add ``draw`` to the command line."""
    p = subparsers.add_parser(
        "draw",
        help="draw the scene (bodies, points, guides, coordinates) or its free-body diagrams (--fbd)",
        description="Draw the scene at its state: bars as thick segments, disks and rings as circles, plates as "
        "rectangles, every named point labelled, rails and surfaces hatched, each coordinate marked (an arc for an "
        "angle, a dimension line for a length). With --fbd: one free-body diagram per body, every force a labelled "
        "arrow along its direction at the state (reactions with their solved values), couples as curved arrows, "
        "and the inertial force -m a_P dashed at G with the couple -I_P alpha (paper Eq. 10), P from --point.",
    )
    add_common_arguments(p, method=False, json_output=False)
    p.add_argument("--fbd", action="store_true", help="free-body diagrams, one per body")
    p.add_argument("-o", "--output", dest="output", required=True, metavar="FILE",
                   help=f"output file; the format follows its suffix: {FORMATS_TEXT} (written atomically)")
    p.set_defaults(handler=draw_command)


def draw_command(args: argparse.Namespace) -> int:
    from solver.drawing import FORMATS, check_format, draw_system, save_figure
    from solver.files import check_output_path

    check_output_path(args.output, "-o")  # before the work, not after it; a folder is said to be one
    check_format(args.output, FORMATS, "-o")
    system = load_scene_from_args(args)
    drawing = draw_system(system, fbd=args.fbd, point=args.point)
    save_figure(drawing.figure, args.output, "-o")
    what = (f"free-body diagrams of {len(drawing.panels)} bod{'y' if len(drawing.panels) == 1 else 'ies'}"
            if args.fbd else "scene drawing")
    print(f"wrote {args.output} ({what} of {system.name})")
    if args.fbd and drawing.solution.extra.get("indeterminate"):
        print(f"note: statically indeterminate: {drawing.solution.extra['indeterminate']}")
    return 0
