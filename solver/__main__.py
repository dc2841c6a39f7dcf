"""Command line: ``python -m solver COMMAND SCENE [options]``.

The commands come from the modules in :data:`COMMAND_MODULES`; each defines
``register(subparsers)`` adding its subcommands with a ``handler``. A module
that is not there (ImportError) is skipped, so the command line works with
whatever parts of the solver are installed. ``python -m solver --help``
lists the commands; ``python -m solver COMMAND --help`` their options.
"""
from __future__ import annotations

import gc

if __name__ == "__main__":  # a short-lived process: see the end of this file
    gc.disable()

import argparse  # noqa: E402
import functools  # noqa: E402
import importlib  # noqa: E402
import sys  # noqa: E402
from collections.abc import Sequence  # noqa: E402

from solver.cli_common import MAX_CPU_SECONDS, OneLineArgumentParser, run_handler  # noqa: E402
from solver.files import MAX_INPUT_BYTES  # noqa: E402
from solver.limits import MAX_UNIT_EXPONENT  # noqa: E402

COMMAND_MODULES = ["solver.cli_instant", "solver.cli_dynamics", "solver.cli_draw", "solver.cli_explain"]

DESCRIPTION = (
    "Planar rigid-body solver built on the generalized Euler equation (moments about any "
    "embedded point P). Scenes are TOML files; see data/scenes/README.md."
)
EPILOG = (
    "examples:\n"
    "  python -m solver solve data/scenes/sliding_bar.toml --point B\n"
    "  python -m solver solve data/scenes/sliding_bar.toml --set beta=\"60 deg\" --json\n"
    "  python -m solver eom data/scenes/disk_bar.toml --latex\n"
    "  python -m solver frequency data/scenes/disk_bar.toml\n"
    "  python -m solver draw data/scenes/slider_crank.toml --fbd -o fbd.svg\n"
    "  python -m solver explain data/scenes/disk_bar.toml --point C -o worked.html\n"
    "bad input: one line 'error: ...' on stderr, exit status 2.\n"
    f"limits: every command stops after {MAX_CPU_SECONDS:g} s of CPU time (SOLVER_MAX_CPU_SECONDS); scenes\n"
    f"are regular files of at most {MAX_INPUT_BYTES} bytes; unit exponents at most {MAX_UNIT_EXPONENT}; the\n"
    "caps of each command are in its --help and in data/scenes/README.md."
)


def build_parser() -> OneLineArgumentParser:
    """The argument parser with every available command registered."""
    parser = OneLineArgumentParser(
        prog="python -m solver",
        description=DESCRIPTION,
        epilog=EPILOG,
        formatter_class=lambda prog: _Formatter(prog, max_help_position=28),
    )
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND", title="commands", required=True)
    for name in COMMAND_MODULES:
        try:
            module = importlib.import_module(name)
        except ImportError:
            continue  # that part of the solver is not installed
        before = set(subparsers.choices)
        try:
            module.register(subparsers)
        except Exception as err:  # noqa: BLE001 - a broken module must not take the others down
            _forget_commands(subparsers, set(subparsers.choices) - before)
            parser.unavailable.append(f"commands from {name} are unavailable ({type(err).__name__}: {err})")
    if parser.unavailable:
        parser.epilog = (parser.epilog or "") + "\nnote: " + "; ".join(parser.unavailable)
    return parser


def _forget_commands(subparsers: argparse._SubParsersAction, names: set[str]) -> None:
    """Remove half-registered subcommands of a module whose register() failed."""
    for command in names:
        subparsers.choices.pop(command, None)
    subparsers._choices_actions[:] = [
        a for a in subparsers._choices_actions if a.dest not in names  # noqa: SLF001 - argparse has no API
    ]


class _Formatter(argparse.RawDescriptionHelpFormatter):
    """Keeps the examples in the epilog as written."""


@functools.cache
def _parser() -> OneLineArgumentParser:
    """The parser of this process: the same for every call of :func:`main` (like the imports of the
    command modules, it is start-up work, built once; parsing does not change it)."""
    return build_parser()


def main(argv: Sequence[str] | None = None) -> int:
    """Parse ``argv`` and run the command; returns the exit status."""
    parser = _parser()
    args, extra = parser.parse_known_args(argv)
    if extra:  # named by the command that did not take them ("python -m solver frequency: ..."), not the top
        command = parser._subparsers._group_actions[0].choices[args.command]  # noqa: SLF001 - argparse has no API
        command.error(f"unrecognized arguments: {' '.join(extra)}")
    return run_handler(args.handler, args)


if __name__ == "__main__":
    # Python's cyclic garbage collector stays off from before the imports to the exit. Each of its
    # full collections walks the whole heap of sympy, scipy, pandas and pint's registry (pint's
    # cached units alone took 0.08 s more to load with it on): a command took 10-25 % more CPU
    # (explain disk_bar 0.67 s against 0.52 s), with the same peak memory (a 20 s simulate, an
    # animation, an exact precision solve: within 3 %), since reference counting frees everything
    # not in a cycle. The heap is frozen before the exit so that the interpreter's last collection
    # skips it too. reports/__main__.py does the same for the report build.
    try:
        status = main()
    finally:
        gc.freeze()
    sys.exit(status)
