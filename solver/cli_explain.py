"""``python -m solver explain``: a worked solution of a scene, and the point advisor.

    python -m solver explain SCENE [--point BODY:POINT] [--format text|markdown|html|latex] [-o FILE]
    python -m solver explain SCENE --suggest-point
"""
from __future__ import annotations

import argparse
from pathlib import Path

from solver.cli_common import (
    add_point_option,
    add_scene_argument,
    add_set_option,
    load_scene_from_args,
)

FORMATS = ("text", "markdown", "html", "latex")
_SUFFIX_FORMAT = {".txt": "text", ".md": "markdown", ".html": "html", ".htm": "html", ".tex": "latex"}


def register(subparsers: argparse._SubParsersAction) -> None:
    p = subparsers.add_parser(
        "explain",
        help="worked solution at the scene's state (kinematics, forces, Newton, Euler about P, solution, check)",
        description="A worked solution of the scene at its state, per body: data, kinematics from P, the "
        "free-body forces, Newton's equations, the generalized Euler equation about P with the inertial term "
        "and I_P alpha apart, the unknowns that drop out; then the point advisor, the equation of motion, "
        "the solution in the scene's output units and the mass-centre check.",
    )
    add_scene_argument(p)
    add_point_option(p)
    p.add_argument("--format", choices=FORMATS, default=None,
                   help="output format (default: text; with -o, the suffix's: .txt text, .md markdown, .html html, "
                   ".tex latex); an -o suffix that is none of these, or another format's, is refused")
    p.add_argument("-o", "--output", metavar="FILE", default=None,
                   help="write to FILE (replaced whole, never half-written) instead of standard output")
    p.add_argument("--suggest-point", action="store_true",
                   help="only the point advisor: rank the candidate points P of every body")
    add_set_option(p)
    p.set_defaults(handler=explain_command)


def _format(args) -> str:
    """The output format: --format, else the -o suffix's, else text. An -o suffix that is no
    format's, or that is another format's than --format, is refused naming -o (nothing written)."""
    if args.output is None:
        return args.format or "text"
    from solver.drawing import check_format
    from solver.errors import InputError

    implied = _SUFFIX_FORMAT[check_format(args.output, tuple(_SUFFIX_FORMAT), "-o")]
    if args.format is not None and args.format != implied:
        wanted = " or ".join(k for k, v in _SUFFIX_FORMAT.items() if v == args.format)
        raise InputError(f"-o {args.output}: the suffix is {implied}'s, not {args.format}'s (--format "
                         f"{args.format}); give a {wanted} file or leave out --format")
    return implied


def explain_command(args: argparse.Namespace) -> int:
    from solver.display import positive_parameters

    fmt = _format(args)
    _check_output(args.output)
    system = load_scene_from_args(args)
    with positive_parameters(system):  # |L| shown as L for a parameter of positive value
        text = _explained(args, system, fmt)
    if args.output is None:
        print(text, end="" if text.endswith("\n") else "\n")
    else:
        _write_atomic(args.output, text)
    return 0


def _explained(args: argparse.Namespace, system, fmt: str) -> str:
    """The worked solution (or, with --suggest-point, the advice) as ``explain`` writes it."""
    from solver.explain import explain, render

    if args.suggest_point:  # the advisor alone, in the same formats
        from solver.explain.advisor import advice_explanation
        from solver.formulations import resolve_points

        resolve_points(system, args.point)  # a bad --point is refused here too, in the same line
        text = render(advice_explanation(system), fmt)
    else:
        explanation = explain(system, args.point)
        if fmt == "html":  # the free-body diagrams drawn (the other formats list the forces)
            from solver.explain.figures import attach_figures

            attach_figures(explanation, system, args.point)
        else:  # and say the command that draws them
            from solver.explain.figures import attach_drawing_commands

            attach_drawing_commands(explanation, args.scene, args.point, args.overrides)
        text = render(explanation, fmt)
    return text


def _check_output(path: str | None) -> None:
    """The -o destination checked before any work (:func:`solver.files.check_output_path`)."""
    if path is not None:
        from solver.files import check_output_path

        check_output_path(path, "-o")


def _write_atomic(path: str, text: str) -> None:
    from solver.files import write_atomic

    write_atomic(path, lambda fh: fh.write(text), "-o")
