"""What every ``python -m solver`` command shares.

Command modules (``solver.cli_instant``, ``solver.cli_dynamics``) each define
``register(subparsers)``; inside it they build their subcommands with the
helpers here so that options look and behave the same everywhere:

>>> def register(subparsers):                                  # doctest: +SKIP
...     p = subparsers.add_parser("solve", help="...")
...     add_common_arguments(p)            # SCENE --point --method --set --json
...     p.set_defaults(handler=_solve)     # handler(args) -> int exit status
...
... def _solve(args):
...     scene = load_scene_from_args(args)  # applies --set, raises SceneError
...     ...
...     print_json({...})                   # refuses NaN/inf

Bad input anywhere (an :class:`~solver.errors.InputError` from loading,
deriving or solving, a bad ``--set``, an argparse usage error) ends in ONE
line ``error: ...`` on stderr and exit status 2, without a traceback:
:func:`run_handler` and :class:`OneLineArgumentParser` do this.
"""
from __future__ import annotations

import argparse
import contextlib
import json
import math
import os
import signal
import sys
import threading
import warnings
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from typing import TYPE_CHECKING, Any, NoReturn

if TYPE_CHECKING:  # annotations only: pint loads in ~0.3 s, which --help does not need
    import pint

from solver.errors import InputError
from solver.files import MAX_INPUT_BYTES
from solver.output_units import in_output_units, output_unit, to_output_units  # noqa: F401 - re-exported for the commands

EXIT_OK = 0
EXIT_INTERNAL = 1
EXIT_INPUT = 2

DEBUG_ENV = "SOLVER_DEBUG"
"""Set this environment variable to 1 to see tracebacks of internal errors."""


class UsageError(InputError):
    """A malformed command line (raised by :class:`OneLineArgumentParser`)."""


class OneLineArgumentParser(argparse.ArgumentParser):
    """An ArgumentParser whose usage errors are one ``error: ...`` line, exit 2.

    (argparse's own handler prints the whole usage block first.) Subparsers
    made from it inherit the behaviour.
    """

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.unavailable: list[str] = []  # command modules that failed to register

    def error(self, message: str) -> NoReturn:
        note = f"; note: {'; '.join(self.unavailable)}" if self.unavailable else ""
        fail(f"{self.prog}: {message} (see {self.prog} --help){note}")


MAX_MESSAGE_LENGTH = 600
"""Longest error line printed [characters]; a longer message (one quoting a huge input)
is cut, ending in "..."."""


def one_line(message: str) -> str:
    """Collapse a message to one line (no embedded newlines), at most :data:`MAX_MESSAGE_LENGTH` long."""
    text = " ".join(str(message).split())
    return text if len(text) <= MAX_MESSAGE_LENGTH else text[: MAX_MESSAGE_LENGTH - 3] + "..."


def fail(message: str, status: int = EXIT_INPUT) -> NoReturn:
    """Print ``error: <message>`` as one line on stderr and exit."""
    sys.stderr.write(f"error: {one_line(message)}\n")
    sys.stderr.flush()
    raise SystemExit(status)


# -- options -----------------------------------------------------------------------------


def add_scene_argument(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("scene", metavar="SCENE",
                        help=f"scene file (TOML, a regular file of at most {MAX_INPUT_BYTES} bytes), "
                        "e.g. data/scenes/sliding_bar.toml")


def add_set_option(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--set",
        dest="overrides",
        metavar="NAME=VALUE",
        action="append",
        default=[],
        help='override a parameter or the state, with its unit: --set beta="90 deg" '
        f'--set theta_dot="1.5 rad/s" (repeatable, at most {MAX_OVERRIDES})',
    )


def _point_value(text: str) -> str:
    """``--point``'s text, spaces inside an ``I(R1, R2)`` taken out (solver.explain.build.read_point_name)."""
    from solver.explain.build import read_point_name

    return read_point_name(text)


def add_point_option(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--point",
        metavar="BODY:POINT",
        type=_point_value,
        default=None,
        help="reference point P of a body's moment equation: BODY:POINT, or a point name (every body "
        "that has it; for a one-body scene any point or G), or a point the advisor names (G_<element>, "
        "C_<joint>, BODY:I(R1,R2); `explain --suggest-point` lists them); default: each body's reference_point",
    )


def add_method_option(parser: argparse.ArgumentParser) -> None:
    from solver.limits import FORMULATION_METHODS as METHODS

    parser.add_argument(
        "--method",
        choices=METHODS,
        default=METHODS[0],
        help=f"route to the equations (default: {METHODS[0]})",
    )


def add_json_option(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--json", action="store_true", help="print one JSON object instead of text")


def add_common_arguments(
    parser: argparse.ArgumentParser, *, point: bool = True, method: bool = True, json_output: bool = True
) -> None:
    """Add SCENE, ``--point``, ``--method``, ``--set`` and ``--json`` (each optional but SCENE)."""
    add_scene_argument(parser)
    if point:
        add_point_option(parser)
    if method:
        add_method_option(parser)
    add_set_option(parser)
    if json_output:
        add_json_option(parser)


def int_in(low: int, high: int) -> Callable[[str], int]:
    """An argparse ``type=``: an integer in [low, high]. argparse names the flag in the
    one-line error (``argument --samples: ...``)."""

    def parse(text: str) -> int:
        try:
            value = int(text.strip()) if len(text) <= 30 else None
        except ValueError:
            value = None
        if value is None or not low <= value <= high:
            raise argparse.ArgumentTypeError(f"expected an integer from {low} to {high}, got {text[:40]!r}")
        return value

    return parse


def float_in(low: float, high: float, *, low_open: bool = False) -> Callable[[str], float]:
    """An argparse ``type=``: a finite number in [low, high] (or (low, high] with ``low_open``)."""

    def parse(text: str) -> float:
        try:
            value = float(text) if len(text) <= 40 else math.nan
        except ValueError:
            value = math.nan
        above = value > low if low_open else value >= low
        if not (math.isfinite(value) and above and value <= high):
            bracket = "(" if low_open else "["
            raise argparse.ArgumentTypeError(
                f"expected a number in {bracket}{low:g}, {high:g}], got {text[:40]!r}")
        return value

    return parse


MAX_OVERRIDES = 50
"""Most ``--set`` options one command takes."""


def parse_overrides(items: Iterable[str]) -> dict[str, str]:
    """``["beta=90 deg", ...]`` -> ``{"beta": "90 deg"}``.

    Raises
    ------
    UsageError
        An item without ``=``, an empty name or value, or a name given twice.
    """
    out: dict[str, str] = {}
    items = list(items)
    if len(items) > MAX_OVERRIDES:
        raise UsageError(f"--set: {len(items)} given; the limit is {MAX_OVERRIDES}")
    for item in items:
        name, sep, value = item.partition("=")
        name, value = name.strip(), value.strip()
        if not sep or not name or not value:
            raise UsageError(f"--set {item!r}: expected NAME=VALUE, e.g. --set beta=\"90 deg\"")
        if name in out:
            raise UsageError(f"--set {name}: given twice ({out[name]!r} and {value!r})")
        out[name] = value
    return out


def load_scene_from_args(args: argparse.Namespace):
    """Load ``args.scene`` (either format) as a System, with ``args.overrides`` (``--set``) applied."""
    from solver.io.scenes import load_system

    return load_system(args.scene, parse_overrides(getattr(args, "overrides", []) or []))


def state_si(system) -> tuple[float, float]:
    """(value, rate) of the single free coordinate (SI) of a one-degree-of-freedom system.

    Raises
    ------
    InputError
        When the system has more than one free coordinate.
    """
    free = system.free
    if len(free) != 1 or system.closure:
        raise InputError(
            f"{system.label}: this command needs one degree of freedom without closure constraints; "
            f"the scene has {freedom_words(system)}"
        )
    return free[0].value, free[0].rate


def freedom_words(system) -> str:
    """How many independent coordinates a system has, named, and what else moves it:
    ``1 independent coordinate (theta2), theta3, theta4 dependent on it through closure
    constraints`` (for messages that refuse a system)."""
    independent = [c.name for c in system.free if not c.dependent]
    dependent = [c.name for c in system.free if c.dependent]
    text = f"{len(independent)} independent coordinate(s) ({', '.join(independent) or 'none'})"
    if dependent:
        text += f", {', '.join(dependent)} dependent through closure constraints"
    elif system.closure:
        text += " and closure constraints"
    if system.time_dependent:
        text += ", and motion prescribed in time"
    return text


# -- output --------------------------------------------------------------------------------


def check_finite(values: Mapping[str, float], context: str) -> None:
    """Refuse to print NaN or infinity as an answer.

    Raises
    ------
    InputError
        Naming the first non-finite entry.
    """
    for name, value in values.items():
        if not math.isfinite(float(value)):
            raise InputError(
                f"{context}: {name} is not a finite number ({value}); the configuration is "
                "singular or the parameters are out of range, so no answer is printed"
            )


def quantity_entry(quantity: pint.Quantity, unit: str | None = None) -> dict[str, Any]:
    """``{"value": float, "unit": str}`` for JSON, converted to ``unit`` if given."""
    if unit is not None:
        quantity = quantity.to(unit)
        unit_text = unit
    else:
        unit_text = f"{quantity.units:~}" or "dimensionless"
    return {"value": float(quantity.magnitude), "unit": unit_text}


def print_json(payload: Any) -> None:
    """Print ``payload`` as JSON; NaN or infinity anywhere is refused."""
    try:
        text = json.dumps(payload, indent=2, allow_nan=False)
    except ValueError:
        raise InputError("the result contains a value that is not a finite number; nothing printed") from None
    print(text)


def format_number(value: float, digits: int = 6) -> str:
    """Readable fixed-significance number (``-0`` shown as ``0``)."""
    if value == 0:
        value = 0.0
    return f"{value:.{digits}g}"


def digits_lost_text(lost: dict, units: Mapping[str, str] | None = None) -> str:
    """The sentence on the unknowns whose digits cancellation took (``digits_lost`` of a solve,
    :func:`solver.analyses.instant.solution_in_regime`), its bounds in the scene's ``[output_units]``:
    `solve` prints it as a warning and `explain` beside its solution."""
    lost = to_output_units(lost, units)
    parts = [f"{name} lost {v['digits']:.0f} of float64's 16 digits (error up to "
             f"{format_number(v['error_bound']['value'], 2)} {v['error_bound']['unit']})" for name, v in lost.items()]
    return ("cancellation: the terms of the equations are far larger than these unknowns (large rates): "
            + "; ".join(parts) + "; the printed digits beyond those left are round-off")


def round_off_zero_text(zeros: dict, units: Mapping[str, str] | None = None) -> str:
    """The line on the unknowns given as 0 because they are no larger than their own error bound
    (``zero_to_round_off`` of a solve, :func:`solver.analyses.instant.round_off_zeros`), in the
    scene's ``[output_units]``."""
    zeros = to_output_units(zeros, units)
    parts = [f"{name} (computed {format_number(v['computed']['value'], 3)}, error bound "
             f"{format_number(v['error_bound']['value'], 2)} {v['error_bound']['unit']})" for name, v in zeros.items()]
    return "0 to round-off (a value within its own error bound is given as 0): " + "; ".join(parts)


def format_pair(a: float, b: float, digits: int = 6) -> tuple[str, str]:
    """Two values to compare, printed so that values equal to the printed precision print equal.

    Each is printed to ``digits`` significant figures (:func:`format_number`); when the texts
    differ only because the two values straddle a rounding boundary (they differ by less than a
    unit of the last digit shown), one more digit is shown, up to 17 (all of a double), until
    the texts agree or the digits show a real difference.
    """
    scale = max(abs(a), abs(b))
    for d in range(digits, 18):
        x, y = format_number(a, d), format_number(b, d)
        if x == y or abs(a - b) >= 10.0 ** (1 - d) * scale:
            return x, y
    return x, y


def format_table(header: Sequence[str], rows: Sequence[Sequence[str]], align: str | None = None) -> str:
    """A plain text table; ``align`` is one letter per column, ``l`` or ``r``."""
    align = align or "l" * len(header)
    widths = [max(len(str(r[i])) for r in [header, *rows]) for i in range(len(header))]

    def line(cells: Sequence[str]) -> str:
        parts = [
            str(c).rjust(w) if a == "r" else str(c).ljust(w) for c, w, a in zip(cells, widths, align)
        ]
        return "  ".join(parts).rstrip()

    rule = "  ".join("-" * w for w in widths)
    return "\n".join([line(header), rule, *(line(r) for r in rows)])


def state_text(system, state=None) -> str:
    """``theta = 30 deg, theta_dot = 0 rad/s`` (angles in degrees, rates in rad/s, lengths in m,
    each in the scene's ``[output_units]`` where it names one)."""
    parts = []
    q = [c.value for c in system.free] if state is None else state.q
    qd = [c.rate for c in system.free] if state is None else state.qd
    units = system.output_units

    def part(name: str, value: float, unit: str) -> str:
        value, unit = in_output_units(value, unit, units)
        return f"{name} = {format_number(value)} {unit}"

    for c, v, r in zip(system.free, q, qd):
        if c.kind == "angle":
            parts += [part(c.name, math.degrees(v), "deg"), part(f"{c.name}_dot", r, "rad/s")]
        else:
            parts += [part(c.name, v, "m"), part(f"{c.name}_dot", r, "m/s")]
    if system.time_dependent:
        parts.append(part("t", system.time if state is None else state.t, "s"))
    return ", ".join(parts)


# -- running ---------------------------------------------------------------------------------


MAX_CPU_SECONDS = 20.0
"""CPU time one command may use [s] before it is stopped with one ``error:`` line and
status 2 (a backstop behind the caps on sizes, exponents, steps and samples: an
expression that makes the symbolic work explode, for example). The environment
variable ``SOLVER_MAX_CPU_SECONDS`` changes it."""
CPU_ENV = "SOLVER_MAX_CPU_SECONDS"


class WorkLimitExceeded(BaseException):
    """The command used up its CPU time (a BaseException, so that no ``except
    Exception`` in a library can swallow it)."""


def cpu_seconds_allowed() -> float:
    """:data:`MAX_CPU_SECONDS`, or the value of ``SOLVER_MAX_CPU_SECONDS`` if it is a positive number."""
    try:
        value = float(os.environ.get(CPU_ENV, ""))
    except ValueError:
        return MAX_CPU_SECONDS
    return value if math.isfinite(value) and value > 0 else MAX_CPU_SECONDS


@contextlib.contextmanager
def cpu_budget(seconds: float) -> Iterator[None]:
    """Raise :class:`WorkLimitExceeded` once the process has used ``seconds`` more CPU time
    (user time, ``ITIMER_VIRTUAL``; again every second if a library swallowed it).
    Without SIGVTALRM, or off the main thread, it does nothing."""
    if not hasattr(signal, "SIGVTALRM") or threading.current_thread() is not threading.main_thread():
        yield
        return

    def _out_of_time(signum: int, frame: Any) -> None:
        raise WorkLimitExceeded

    previous = signal.signal(signal.SIGVTALRM, _out_of_time)
    signal.setitimer(signal.ITIMER_VIRTUAL, seconds, 1.0)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_VIRTUAL, 0)
        signal.signal(signal.SIGVTALRM, previous)


def run_handler(handler: Callable[[argparse.Namespace], int | None], args: argparse.Namespace) -> int:
    """Run a command handler; bad input -> one ``error:`` line and status 2.

    The handler runs within :func:`cpu_budget` (:data:`MAX_CPU_SECONDS`), with
    Python warnings silenced (numpy's overflow warnings would print lines
    before the one error line; a non-finite answer is refused by
    :func:`check_finite` instead). Numeric overflow, recursion too deep and
    memory exhausted are reported as input too large (status 2). An
    unexpected exception (a bug, not bad input) is reported on one line with
    status 1; set ``SOLVER_DEBUG=1`` to see its traceback instead.
    """
    seconds = cpu_seconds_allowed()
    try:
        with warnings.catch_warnings(), cpu_budget(seconds):
            warnings.simplefilter("ignore")
            status = handler(args)
    except WorkLimitExceeded:
        fail(f"the request needed more than {seconds:g} s of CPU time, the solver's cap on work "
             f"(set {CPU_ENV} to change it); simpler expressions, a shorter run or fewer values need less",
             EXIT_INPUT)
    except OverflowError as err:
        fail(f"a number grew out of floating-point range ({err}); the scene's values or the options "
             "are too large", EXIT_INPUT)
    except (RecursionError, MemoryError) as err:
        fail(f"the input is too large or too deeply nested to process ({type(err).__name__})", EXIT_INPUT)
    except InputError as err:
        fail(str(err), EXIT_INPUT)
    except ValueError as err:  # bad option strings from the library (listing the valid ones)
        fail(str(err), EXIT_INPUT)
    except KeyboardInterrupt:
        fail("interrupted", 130)
    except BrokenPipeError:  # output piped into `head` and closed: not an error
        try:
            sys.stdout = open(os.devnull, "w")  # noqa: SIM115 - swallow the final flush
        except OSError:
            pass
        return EXIT_OK
    except Exception as err:  # noqa: BLE001 - last resort: never a bare traceback for users
        if os.environ.get(DEBUG_ENV):
            raise
        fail(f"internal error ({type(err).__name__}: {err}); please report it "
             f"(set {DEBUG_ENV}=1 for the traceback)", EXIT_INTERNAL)
    return EXIT_OK if status is None else int(status)


__all__ = [
    "OneLineArgumentParser",
    "UsageError",
    "add_common_arguments",
    "add_scene_argument",
    "add_set_option",
    "add_point_option",
    "add_method_option",
    "add_json_option",
    "parse_overrides",
    "load_scene_from_args",
    "check_finite",
    "quantity_entry",
    "output_unit",
    "to_output_units",
    "in_output_units",
    "print_json",
    "format_number",
    "digits_lost_text",
    "round_off_zero_text",
    "format_pair",
    "format_table",
    "state_text",
    "state_si",
    "freedom_words",
    "run_handler",
    "cpu_budget",
    "cpu_seconds_allowed",
    "int_in",
    "float_in",
    "fail",
    "MAX_CPU_SECONDS",
    "MAX_OVERRIDES",
    "EXIT_OK",
    "EXIT_INPUT",
]
