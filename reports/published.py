"""Reading what the paper printed (``data/published/``) for the report's checks.

Everything here validates its file completely and raises
:class:`ReportInputError` with one line naming the file, the place (table,
index, key) and what is wrong. Expression text is kept as text; it is parsed
later by :func:`solver.expressions.parse_expression` (a whitelist parser),
never evaluated.
"""
from __future__ import annotations

import tomllib
from dataclasses import dataclass, field
from pathlib import Path

from solver.errors import InputError

__all__ = [
    "ReportInputError",
    "SymbolMeaning",
    "Transcription",
    "EquationSet",
    "load_equations",
    "read_toml",
    "EQUATION_KINDS",
    "QUANTITIES",
]

EQUATION_KINDS = ("identity", "relation", "eom", "frequency", "approximation")
"""How a printed equation is compared (see data/published/equations.toml)."""

QUANTITIES = {
    "alpha": (),
    "omega": (),
    "acceleration": ("point", "along"),
    "reaction": ("name",),
    "inertia_about": ("point",),
    "natural_frequency": (),
    "position": ("point", "along"),
    "relative_position": ("point", "relative_to", "along"),
    "velocity": ("point", "along"),
    "force": ("name", "along"),
    "resultant": ("along",),
    "element_inertia": ("element", "point"),
}
"""Derived quantities a printed symbol may stand for, with their required keys."""

STATE_NAMES = ("theta", "theta_dot", "t", "F_a")
"""Names that ``assume`` and ``about`` may set (state, time, or a load parameter)."""


class ReportInputError(InputError):
    """A published-data file the report cannot use (one line: file, place, problem)."""


@dataclass(frozen=True)
class SymbolMeaning:
    """Which derived quantity a printed symbol stands for."""

    symbol: str
    quantity: str
    point: str | None = None
    name: str | None = None
    along: tuple[str, str] | None = None
    relative_to: str | None = None
    element: str | None = None


@dataclass(frozen=True)
class Transcription:
    """One printed equation, transcribed as printed.

    Attributes
    ----------
    id : str
        Check id, e.g. ``"eq44"``.
    number : str
        The paper's equation number.
    scene : str
        Key of the scene in ``[scenes]`` of the file.
    kind : str
        One of :data:`EQUATION_KINDS`.
    lhs, rhs : str
        Both sides as printed, in the whitelist expression syntax.
    symbols : dict[str, SymbolMeaning]
        Meanings of the printed symbols that are not scene parameters or the state.
    assume : dict[str, str]
        Conditions the paper imposes (e.g. ``theta_dot = 0``).
    about : dict[str, str]
        State of a linearisation (kind ``frequency``).
    derived_from : tuple[str, ...]
        Ids of the printed equations this one is obtained from.
    note : str
    where : str
        ``"<file>: equation[i] (id ...)"`` for messages.
    """

    id: str
    number: str
    scene: str
    kind: str
    lhs: str
    rhs: str
    symbols: dict[str, SymbolMeaning] = field(default_factory=dict)
    assume: dict[str, str] = field(default_factory=dict)
    about: dict[str, str] = field(default_factory=dict)
    derived_from: tuple[str, ...] = ()
    note: str = ""
    where: str = ""


@dataclass(frozen=True)
class EquationSet:
    """The transcriptions, the scene files they refer to, and printed ranges."""

    path: Path
    scenes: dict[str, Path]
    equations: tuple[Transcription, ...]
    ranges: dict[str, dict]
    systems: dict[str, dict] = field(default_factory=dict)


def read_toml(path: Path) -> dict:
    """Read a TOML file; unreadable or malformed -> ReportInputError (one line)."""
    path = Path(path)
    try:
        with path.open("rb") as handle:
            return tomllib.load(handle)
    except FileNotFoundError:
        raise ReportInputError(f"{path}: file not found") from None
    except (OSError, UnicodeDecodeError) as err:
        raise ReportInputError(f"{path}: cannot read: {err}") from None
    except tomllib.TOMLDecodeError as err:
        raise ReportInputError(f"{path}: not valid TOML: {err}") from None


def _str(table: dict, key: str, where: str, required: bool = True, default: str = "") -> str:
    if key not in table:
        if required:
            raise ReportInputError(f"{where}: key '{key}' is missing")
        return default
    value = table[key]
    if not isinstance(value, str) or (required and not value.strip()):
        raise ReportInputError(f"{where}: key '{key}' must be a non-empty string, got {value!r}")
    return value


def _str_table(value: object, where: str, allowed: tuple[str, ...] | None = None) -> dict[str, str]:
    if not isinstance(value, dict):
        raise ReportInputError(f"{where}: must be a table of name = \"expression\", got {value!r}")
    out = {}
    for key, text in value.items():
        if allowed is not None and key not in allowed:
            raise ReportInputError(f"{where}.{key}: unknown name; valid: {', '.join(allowed)}")
        if not isinstance(text, str) or not text.strip():
            raise ReportInputError(f"{where}.{key}: must be an expression string, got {text!r}")
        out[key] = text
    return out


def _meaning(symbol: str, spec: object, where: str) -> SymbolMeaning:
    if not isinstance(spec, dict):
        raise ReportInputError(f"{where}: must be a table with a 'quantity' key, got {spec!r}")
    quantity = _str(spec, "quantity", where)
    if quantity not in QUANTITIES:
        raise ReportInputError(
            f"{where}.quantity: unknown quantity {quantity!r}; valid: {', '.join(QUANTITIES)}"
        )
    required = QUANTITIES[quantity]
    unknown = set(spec) - {"quantity", *required}
    if unknown:
        raise ReportInputError(
            f"{where}: unknown key(s) {', '.join(sorted(unknown))} for quantity {quantity!r}; "
            f"valid: {', '.join(('quantity',) + required)}"
        )
    along = None
    if "along" in required:
        raw = spec.get("along")
        if not (isinstance(raw, list) and len(raw) == 2 and all(isinstance(x, str) for x in raw)):
            raise ReportInputError(f"{where}.along: must be two expression strings [x, y], got {raw!r}")
        along = (raw[0], raw[1])
    return SymbolMeaning(
        symbol=symbol,
        quantity=quantity,
        point=_str(spec, "point", where) if "point" in required else None,
        name=_str(spec, "name", where) if "name" in required else None,
        along=along,
        relative_to=_str(spec, "relative_to", where) if "relative_to" in required else None,
        element=_str(spec, "element", where) if "element" in required else None,
    )


def load_equations(path: Path) -> EquationSet:
    """Load and validate ``data/published/equations.toml``.

    Parameters
    ----------
    path : pathlib.Path

    Returns
    -------
    EquationSet

    Raises
    ------
    ReportInputError
        One line naming the file, the equation (index and id) and the key.
    """
    path = Path(path)
    data = read_toml(path)
    _validate_equations(path, data)
    root = path.parent.parent.parent  # data/published/equations.toml -> project root
    scenes = {key: root / value for key, value in data["scenes"].items()}
    equations = []
    for index, entry in enumerate(data["equation"]):
        where = f"{path}: equation[{index}] (id {entry.get('id', '?')!r})"
        symbols_raw = entry.get("symbols", {})
        if not isinstance(symbols_raw, dict):
            raise ReportInputError(f"{where}.symbols: must be a table")
        symbols = {
            name: _meaning(name, spec, f"{where}.symbols.{name}") for name, spec in symbols_raw.items()
        }
        derived_from = entry.get("derived_from", [])
        if not (isinstance(derived_from, list) and all(isinstance(x, str) for x in derived_from)):
            raise ReportInputError(f"{where}.derived_from: must be a list of equation ids")
        equations.append(
            Transcription(
                id=entry["id"],
                number=_str(entry, "number", where),
                scene=entry["scene"],
                kind=entry["kind"],
                lhs=_str(entry, "lhs", where),
                rhs=_str(entry, "rhs", where),
                symbols=symbols,
                assume=_str_table(entry.get("assume", {}), f"{where}.assume", STATE_NAMES),
                about=_str_table(entry.get("about", {}), f"{where}.about", STATE_NAMES),
                derived_from=tuple(derived_from),
                note=_str(entry, "note", where, required=False),
                where=where,
            )
        )
    ids = {e.id for e in equations}
    for eq in equations:
        for source in eq.derived_from:
            if source not in ids:
                raise ReportInputError(f"{eq.where}.derived_from: unknown equation id {source!r}")
        if eq.kind in ("frequency", "approximation") and not eq.about:
            raise ReportInputError(f"{eq.where}: kind {eq.kind!r} needs an 'about' table")
    ranges = data.get("ranges", {})
    if not isinstance(ranges, dict):
        raise ReportInputError(f"{path}: 'ranges' must be a table")
    systems = data.get("systems", {})
    for key, system in systems.items():
        where = f"{path}: systems.{key}"
        if not isinstance(system, dict):
            raise ReportInputError(f"{where}: must be a table")
        for need in ("scene", "rows", "unknowns"):
            if need not in system:
                raise ReportInputError(f"{where}: key '{need}' is missing")
        if system["scene"] not in scenes:
            raise ReportInputError(f"{where}.scene: unknown scene {system['scene']!r}")
        for row, eq_id in system["rows"].items():
            if eq_id not in ids:
                raise ReportInputError(f"{where}.rows.{row}: unknown equation id {eq_id!r}")
        for unknown, row in system.get("back_substitution", {}).items():
            if unknown not in system["unknowns"] or row not in system["rows"]:
                raise ReportInputError(
                    f"{where}.back_substitution.{unknown}: must name an unknown and a row, got {row!r}"
                )
    return EquationSet(path=path, scenes=scenes, equations=tuple(equations), ranges=ranges, systems=systems)


_TOP_KEYS = ("schema", "scenes", "equation", "ranges", "systems")
_EQUATION_KEYS = (
    "id", "number", "scene", "kind", "lhs", "rhs", "symbols", "assume", "about", "derived_from", "note",
)


def _validate_equations(path: Path, data: dict) -> None:
    unknown = set(data) - set(_TOP_KEYS)
    if unknown:
        raise ReportInputError(
            f"{path}: unknown top-level key(s) {', '.join(sorted(unknown))}; valid: {', '.join(_TOP_KEYS)}"
        )
    if data.get("schema") != 1:
        raise ReportInputError(f"{path}: key 'schema' must be 1, got {data.get('schema')!r}")
    scenes = data.get("scenes")
    if not isinstance(scenes, dict) or not scenes:
        raise ReportInputError(f"{path}: table 'scenes' (name = \"path\") is missing or empty")
    for key, value in scenes.items():
        if not isinstance(value, str):
            raise ReportInputError(f"{path}: scenes.{key}: must be a path string, got {value!r}")
    entries = data.get("equation")
    if not isinstance(entries, list) or not entries:
        raise ReportInputError(f"{path}: no [[equation]] entries")
    seen: set[str] = set()
    for index, entry in enumerate(entries):
        where = f"{path}: equation[{index}]"
        if not isinstance(entry, dict):
            raise ReportInputError(f"{where}: must be a table")
        bad = set(entry) - set(_EQUATION_KEYS)
        if bad:
            raise ReportInputError(
                f"{where}: unknown key(s) {', '.join(sorted(bad))}; valid: {', '.join(_EQUATION_KEYS)}"
            )
        eq_id = _str(entry, "id", where)
        if eq_id in seen:
            raise ReportInputError(f"{where}: duplicate id {eq_id!r}")
        seen.add(eq_id)
        where = f"{where} (id {eq_id!r})"
        scene = _str(entry, "scene", where)
        if scene not in scenes:
            raise ReportInputError(
                f"{where}.scene: unknown scene {scene!r}; valid: {', '.join(scenes)}"
            )
        kind = _str(entry, "kind", where)
        if kind not in EQUATION_KINDS:
            raise ReportInputError(
                f"{where}.kind: unknown kind {kind!r}; valid: {', '.join(EQUATION_KINDS)}"
            )
