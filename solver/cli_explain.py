"""``python -m solver explain``: a worked solution of a scene, and the point advisor.

    python -m solver explain SCENE [--point BODY:POINT] [--format text|markdown|html|latex] [-o FILE]
    python -m solver explain SCENE --suggest-point
"""
from __future__ import annotations

import argparse
import os
import tempfile
from pathlib import Path

from solver.cli_common import (
    add_point_option,
    add_scene_argument,
    add_set_option,
    format_table,
    load_scene_from_args,
)
from solver.errors import InputError

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
                   help="output format (default: from the -o suffix .txt/.md/.html/.tex, else text)")
    p.add_argument("-o", "--output", metavar="FILE", default=None,
                   help="write to FILE (replaced whole, never half-written) instead of standard output")
    p.add_argument("--suggest-point", action="store_true",
                   help="only the point advisor: rank the candidate points P of every body")
    add_set_option(p)
    p.set_defaults(handler=explain_command)


def _format(args) -> str:
    if args.format is not None:
        return args.format
    if args.output is not None:
        return _SUFFIX_FORMAT.get(Path(args.output).suffix.lower(), "text")
    return "text"


def explain_command(args: argparse.Namespace) -> int:
    from solver.explain import explain, render

    fmt = _format(args)
    _check_output(args.output)
    system = load_scene_from_args(args)
    if args.suggest_point:
        text = _suggestion_text(system)
    else:
        explanation = explain(system, args.point)
        if fmt == "html":  # the free-body diagrams drawn (the other formats list the forces)
            from solver.explain.figures import attach_figures

            attach_figures(explanation, system, args.point)
        text = render(explanation, fmt)
    if args.output is None:
        print(text, end="" if text.endswith("\n") else "\n")
    else:
        _write_atomic(args.output, text)
    return 0


def _suggestion_text(system) -> str:
    from solver.analyses.instant import assemble
    from solver.explain.advisor import rank_points

    out = [f"scene   {system.name}  ({system.source or system.name})", ""]
    if system.contacts:  # the points are ranked in the contact regime that holds at the state
        from solver.explain.build import system_in_regime

        system, regime, _, state = system_in_regime(system, None)
        if regime is not None:
            out.append("contact regime at the state: "
                       + ", ".join(f"{c.joint}: {c.regime.label}" for c in regime.checks))
            if regime.indeterminate:
                out.append("the sticking contacts hold the bodies redundantly (their forces are statically "
                           "indeterminate): no choice of P separates them, so no point is ranked")
                return "\n".join(out)
            out.append("")
    else:
        state = assemble(system)
    for body in system.bodies:
        ranked = rank_points(system, body, state)
        best = ranked[0]
        out.append(f"body {body}: take P = {best.name}: {best.reason()}.")
        rows = [(c.name, c.origin, str(len(c.unknowns)), ", ".join(c.unknowns),
                 str(c.group) if c.group else "-", "0 (fixed)" if c.fixed else "known" if c.known else "derive") for c in ranked]
        out.append(format_table(("point", "what", "unknowns", "which", "solvable group", "a_P"), rows))
        out.append("")
    return "\n".join(out)


def _check_output(path: str | None) -> None:
    if path is None:
        return
    target = Path(path)
    parent = target.parent if str(target.parent) else Path(".")
    if not parent.is_dir():
        raise InputError(f"-o {path}: the folder {str(parent)!r} does not exist")
    if target.exists() and not target.is_file():
        raise InputError(f"-o {path}: exists and is not a regular file")


def _write_atomic(path: str, text: str) -> None:
    target = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=".explain-", dir=str(target.parent) if str(target.parent) else ".")
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(text)
        os.replace(tmp, target)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise
