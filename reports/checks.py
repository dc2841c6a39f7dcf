"""Every published number and equation of the paper, checked against computed results.

One :class:`Check` per printed item, in the shape of ``verification.json``:
``{"id", "kind", "published", "published_text", "published_unit", "computed", "computed_unit",
"tolerance", "verdict", "detail"}`` (:meth:`Check.to_json`), plus what the HTML report shows beside
it (MathML, the explanation of a finding).

Tolerances (documented once, applied everywhere)
------------------------------------------------
* A printed number is taken to be correctly rounded: it stands for every value
  within half a unit of its last printed digit (``"12.34"`` -> +/- 0.005).
  Numbers the paper marks as exact (problem data, m_b g = 50 lbf) get a relative
  tolerance of 2e-5: they are exact in the paper's arithmetic, while the scene
  enters pound-mass through pint with the printed g (5 significant figures).
* Eq. 30 was computed by hand from Eq. 29, whose coefficients the paper rounded
  to 4 significant figures, and each result was rounded before it was used in
  the next step. Its tolerance is :func:`reports.rounding.eq30_tolerances`, the
  one model the tests use too (coefficient rounding and the rounded data behind
  it, propagated to first order, plus the back-substituted results' rounding).
* Units: a printed unit is parsed by pint and compared by dimension with the
  computed quantity; values are compared after conversion into the printed
  unit (or, when the printed unit has the wrong dimension, in the dimensionally
  correct unit the paper evidently meant, and the unit gets its own row).
* Table cells: attainable when some integer count k out of N rounds (half away
  from zero) to the printed percentage (exact rational arithmetic, analysis.tables).
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path

import sympy as sp

from reports.equations import DerivedQuantities, EquationOutcome, check_equation
from reports.published import EquationSet, ReportInputError, read_toml
from reports.rounding import eq30_tolerances, half_unit
from solver.expressions import parse_expression
from solver.model.system import derivative
from solver.units import Q_, ureg

__all__ = [
    "Check",
    "VERDICTS",
    "KINDS",
    "equation_checks",
    "example1_value_checks",
    "survey_checks",
    "half_unit",
]

VERDICTS = ("agrees", "disagrees", "not-checkable")
KINDS = ("value", "unit", "equation", "table-cell", "claim")
_SAME_DIMENSION = "same dimension"
"""The tolerance of a printed unit: it agrees when it has the computed quantity's dimension."""
RELATION = {"approximation": "\u2248"}
"""The sign the paper prints between the sides of a transcribed equation, by its kind, when not "=":
a small-motion rule (Eq. 45) is printed with \u2248."""
_EXACT_RTOL = 2e-5
"""Relative tolerance for numbers the paper states as exact. They are exact in the paper's own
arithmetic (m_b in slug is the mass in lbm divided by the printed g, so m_b g is the weight in lbf
exactly), while the scene enters pound-mass through pint (standard gravity to full precision) with the
printed g (5 significant figures): the two differ by up to half a unit in the last digit of g,
relative 0.0005 / 32 ~ 1.6e-5."""


@dataclass
class Check:
    """One row of the verification.

    Attributes
    ----------
    id, kind, published, computed, verdict, detail
        The ``verification.json`` fields.
    label : str
        Short human name ("Eq. (30): alpha").
    section : str
        "example1", "example2" or "survey".
    published_unit, computed_unit, tolerance : str
        For the HTML table.
    explanation : str
        Why it disagrees (for the findings section), when it does.
    published_text : str
        The published value exactly as printed (``"-0.05080"``, ``"50.0"``): the HTML shows it, so
        that its printed precision, which sets the tolerance, is visible; empty when not a number.
    outcome : EquationOutcome or None
        The symbolic comparison behind an equation row.
    """

    id: str
    kind: str
    published: object
    computed: object
    verdict: str
    detail: str
    label: str = ""
    section: str = ""
    published_unit: str = ""
    computed_unit: str = ""
    tolerance: str = ""
    explanation: str = ""
    caveat: str = ""
    published_text: str = ""
    outcome: EquationOutcome | None = field(default=None, repr=False)

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"`kind` must be one of {KINDS}, got {self.kind!r}")
        if self.verdict not in VERDICTS:
            raise ValueError(f"`verdict` must be one of {VERDICTS}, got {self.verdict!r}")

    def to_json(self) -> dict:
        """The exact ``verification.json`` row: the fields above, and what the HTML shows beside them:
        ``published_text`` (the published value as printed, digits and trailing zeros kept: ``"1.50"``
        beside the float 1.5), ``published_unit`` and ``computed_unit`` (as printed; pint's), and
        ``tolerance`` (the test the verdict applied: a half unit of the last printed digit, ``"exact
        zero"``, attainable at the respondents' N, ``"same dimension"``; empty for a claim, whose test
        is its detail)."""
        printed = self.published_text or (self.published if isinstance(self.published, str) else
                                           None if self.published is None else str(self.published))
        return {
            "id": self.id,
            "kind": self.kind,
            "published": self.published,
            "published_text": printed,
            "published_unit": self.published_unit,
            "computed": self.computed,
            "computed_unit": self.computed_unit,
            "tolerance": self.tolerance,
            "verdict": self.verdict,
            "detail": self.detail,
        }


def not_checkable(id_: str, kind: str, published, reason: str, label: str = "", section: str = "") -> Check:
    """A row that cannot be checked, saying why."""
    return Check(id_, kind, published, None, "not-checkable", f"not checkable: {reason}", label=label, section=section)


# --------------------------------------------------------------------------- numbers
def _signed(printed: str | None, value: float) -> str:
    """The printed text with the value's sign: Eq. (29) prints a negative coefficient as a minus
    sign between terms and the magnitude (``0.05080``), and the row shows ``-0.05080``."""
    if not printed:
        return ""
    return "-" + printed if value < 0 and not printed.lstrip().startswith("-") else printed


def _digits(printed: str, extra: int = 3) -> int:
    text = printed.strip()
    decimals = len(text.split(".")[1]) if "." in text else 0
    return decimals + extra


def _fmt(value: float, decimals: int) -> str:
    return f"{value:.{decimals}f}"


def _unit(text: str):
    """pint unit of a printed unit string ("(lbf·s^2)/ft" -> lbf*s**2/ft)."""
    cleaned = text.replace("·", "*").replace("^", "**").strip()
    return ureg.Unit(cleaned) if cleaned else ureg.dimensionless


def _unit_label(unit) -> str:
    return f"{unit:~P}" if unit != ureg.dimensionless else "1"


def _gc_note(unit, magnitude: float, scene) -> str:
    """For a number in lbf (or lbf-based units) computed from a mass in lbm: how it was converted, and
    what the paper's own conversion gives. The project converts by the exact definition (pint: 1 lbf
    is 1 lbm under standard gravity, 32.17405 lbm*ft/s^2); the paper takes 1 lbf = g lbm*ft/s^2 with
    its printed g (32.174 ft/s^2), so each such number of the paper's arithmetic is the project's times
    (exact factor / g). Empty when the unit holds no lbf or the scene has no lbm mass and g."""
    if unit is None or "force_pound" not in str(unit):
        return ""
    g = scene.parameters.get("g")
    if g is None or not any(q.check("[mass]") and q.units == ureg.Unit("lbm") for q in scene.parameters.values()):
        return ""
    exact = float(Q_(1, "lbf").to("lbm*ft/s**2").magnitude)
    g_c = float(g.to("ft/s**2").magnitude)
    return (f"; converted by the exact definition 1 lbf = {exact:.7g} lbm·ft/s² (standard gravity); with "
            f"the paper's 1 lbf = {g_c:.7g} lbm·ft/s² (its g) it is {magnitude * exact / g_c:.8g}, a relative "
            f"difference of {abs(exact / g_c - 1):.2g}")


# --------------------------------------------------------------------------- equations
def equation_checks(eqset: EquationSet, scenes: dict, derivations: dict) -> list[Check]:
    """One ``equation`` row per transcribed printed equation.

    Parameters
    ----------
    eqset : EquationSet
    scenes, derivations : dict
        Keyed like ``eqset.scenes``; derivations about each scene's default point (A; P).
    """
    rows: list[Check] = []
    outcomes: dict[str, EquationOutcome] = {}
    quantities = {key: DerivedQuantities(scenes[key], derivations[key]) for key in derivations}
    for tr in eqset.equations:
        outcome = check_equation(tr, scenes[tr.scene], derivations[tr.scene], quantities[tr.scene])
        outcomes[tr.id] = outcome
        computed = "0" if outcome.residual == 0 else sp.sstr(outcome.residual)
        rows.append(
            Check(
                id=tr.id,
                kind="equation",
                published=f"{tr.lhs} {RELATION.get(tr.kind, '=')} {tr.rhs}",
                computed=f"residual {computed}",
                verdict=outcome.verdict,
                detail=outcome.detail,
                label=f"Eq. ({tr.number})" + (f" {tr.id.split('-', 1)[1]}" if "-" in tr.id else ""),
                tolerance="exact zero",  # the residual of the two sides, tested for zero symbolically
                section="example1" if scenes[tr.scene].name == "sliding_bar" else "example2",
                outcome=outcome,
            )
        )
    # Where does an error enter? Follow derived_from.
    by_id = {r.id: r for r in rows}
    for row in rows:
        tr = row.outcome.transcription
        if row.verdict != "disagrees":
            sources = [by_id[s] for s in tr.derived_from]
            if any(s.verdict == "disagrees" for s in sources) and tr.assume:
                conds = ", ".join(f"{k} = {v}" for k, v in tr.assume.items())
                row.caveat = (
                    f"derived from {', '.join(s.id for s in sources if s.verdict == 'disagrees')}, which "
                    f"disagrees; the error vanishes under this equation's condition ({conds})."
                )
            continue
        sources = [by_id[s] for s in tr.derived_from]
        parts = []
        if row.outcome.diagnosis:
            parts.append(f"In Eq. ({tr.number}), {row.outcome.diagnosis_prose}.")
        if sources and all(s.verdict == "agrees" for s in sources):
            parts.append(
                f"It is obtained from {', '.join(s.label for s in sources)}, which agree with the "
                "derivation, so the error enters in this step."
            )
        elif any(s.verdict == "disagrees" for s in sources):
            bad = [s for s in sources if s.verdict == "disagrees"]
            same = all(
                s.outcome.residual is not None and sp.simplify(s.outcome.residual - row.outcome.residual) == 0
                for s in bad
            )
            parts.append(
                f"It is carried over from {', '.join(s.label for s in bad)}"
                + (" (same residual)." if same else ".")
            )
        row.explanation = " ".join(parts)
    return rows


# --------------------------------------------------------------------------- Example 1 values
def _scene_quantity(scene, name: str):
    if name in scene.parameters:
        return scene.parameters[name]
    if name == scene.coordinate:
        return scene.state[scene.coordinate]
    if name == "omega":
        return scene.state[scene.coordinate + "_dot"]
    return None


def _lambdify_units(exprs: list, scene, extra: dict) -> list:
    """Evaluate parameter expressions with pint quantities (units follow), all in one generated
    function (each expression's arithmetic as when generated alone)."""
    values = {sp.Symbol(n, real=True): q for n, q in scene.parameters.items()}
    values.update(extra)
    symbols = sorted(set().union(*(e.free_symbols for e in exprs)), key=lambda s: s.name)
    for expr in exprs:
        missing = sorted((s for s in expr.free_symbols if s not in values), key=lambda s: s.name)
        if missing:
            raise ReportInputError(f"cannot evaluate {sp.sstr(expr)}: no value for {', '.join(map(str, missing))}")
    fn = sp.lambdify(symbols, list(exprs), modules="numpy")
    return [r if isinstance(r, ureg.Quantity) else Q_(float(r), "") for r in fn(*[values[s] for s in symbols])]


def _system_values(eqset: EquationSet, key: str, scene, deriv) -> tuple[dict, dict]:
    """Coefficient expressions of a printed linear system (e.g. Eq. 29), by (row, unknown|"rhs")."""
    system = eqset.systems[key]
    by_id = {e.id: e for e in eqset.equations}
    unknowns = list(system["unknowns"])
    state = {deriv.q: scene.state[scene.coordinate], deriv.qd: scene.state[scene.coordinate + "_dot"]}
    coefficients: dict[tuple[str, str], object] = {}
    for row, eq_id in system["rows"].items():
        tr = by_id[eq_id]
        names = dict(scene.symbols)
        names.update({deriv.q.name: deriv.q, deriv.qd.name: deriv.qd, deriv.qdd.name: deriv.qdd})
        placeholders = {u: sp.Symbol(u, real=True) for u in unknowns}
        names.update(placeholders)
        lhs = parse_expression(tr.lhs, names, where=f"{tr.where}.lhs")
        rhs = parse_expression(tr.rhs, names, where=f"{tr.where}.rhs")
        expr = lhs - rhs
        for u, sym in placeholders.items():
            coefficients[(row, u)] = derivative(expr, sym)
        coefficients[(row, "rhs")] = -expr.subs({s: 0 for s in placeholders.values()})
    return system, coefficients, state


def example1_value_checks(values_path: Path, eqset: EquationSet, scene, deriv, solution) -> list[Check]:
    """Rows for every printed number of Example 1 (problem data, Eq. 29, Eq. 30).

    Parameters
    ----------
    values_path : pathlib.Path
        ``data/published/example1.toml``.
    eqset : EquationSet
        For ``[systems.eq29]`` (which printed equation each Eq. 29 row comes from).
    scene, deriv
        Example 1's scene and derivation about A.
    solution : solver.derivation.InstantSolution
        The solver's answer at release.
    """
    data = read_toml(values_path)
    entries = data.get("value")
    if not isinstance(entries, list) or not entries:
        raise ReportInputError(f"{values_path}: no [[value]] entries")
    for index, entry in enumerate(entries):
        for key in ("id", "printed", "value", "unit"):
            if key not in entry:
                raise ReportInputError(f"{values_path}: value[{index}]: key '{key}' is missing")
    published = {e["id"]: e for e in entries}
    rows: list[Check] = []

    # ---- Eq. 29: the exact coefficients of the printed (and symbolically checked) equations
    system_key = next(iter(eqset.systems), None)
    system, coefficients, state = _system_values(eqset, system_key, scene, deriv) if system_key else ({}, {}, {})
    # Problem data the paper printed rounded and then computed with (m_b in slug): their
    # rounding propagates into Eq. 29 (first order, in units).
    rounded_data = {}
    for key, entry in published.items():
        base = key[len("data-"):].partition("-")[0] if key.startswith("data-") else None
        if base in scene.parameters and not entry.get("exact", False) and entry.get("printed"):
            unit = _unit(entry["unit"] or entry.get("implied_unit", ""))
            rounded_data[base] = (Q_(half_unit(entry["printed"]), unit), key)
    prefix = system_key or "eq29"
    unknowns = list(system.get("unknowns", []))
    row_names = list(system.get("rows", {}))
    # every printed coefficient's exact value, and its derivative by each rounded datum it holds
    needed = {}
    for row in row_names:
        for column in unknowns + ["rhs"]:
            if f"{prefix}-{row}-{column}" in published:
                expression = coefficients[(row, column)]
                needed[(row, column)] = expression
                for name in rounded_data:
                    symbol = sp.Symbol(name, real=True)
                    if expression.has(symbol):
                        needed[(row, column, name)] = derivative(expression, symbol)
    with_units = dict(zip(needed, _lambdify_units(list(needed.values()), scene, state))) if needed else {}
    for row in row_names:
        for column in unknowns + ["rhs"]:
            key = f"{prefix}-{row}-{column}"
            entry = published.get(key)
            if entry is None:
                continue
            computed_q = with_units[(row, column)]
            unit = _unit(entry.get("implied_unit") or entry["unit"])
            data_effect = 0.0
            data_used = []
            for name, (h_q, data_key) in rounded_data.items():
                if (row, column, name) in with_units:
                    effect = with_units[(row, column, name)] * h_q
                    try:
                        data_effect += abs(float(effect.to(unit).magnitude))
                        data_used.append(data_key)
                    except Exception:  # noqa: BLE001 - incompatible units: no contribution
                        pass
            try:
                magnitude = float(computed_q.to(unit).magnitude)
            except Exception:  # noqa: BLE001 - pint raises several error types for dimension mismatches
                magnitude = float(computed_q.to_base_units().magnitude)
            exact = bool(entry.get("exact", False))
            printed = entry["printed"]
            h = 0.0 if exact or not printed else half_unit(printed)
            value = float(entry["value"])
            tol = (h + data_effect) if h else _EXACT_RTOL * max(1.0, abs(value))
            ok = abs(magnitude - value) <= tol
            within_half = abs(magnitude - value) <= (h if h else tol)
            source_eq = system["rows"][row]
            how = "(exact number)" if not h else "(half a unit in the last printed digit"
            if h and data_used:
                how += (
                    f" + {data_effect:.2g}, the first-order effect of the rounded printed data the paper "
                    f"computed with: {', '.join(data_used)})"
                )
            elif h:
                how += ")"
            if ok and not within_half:
                how += "; outside the half-unit band alone, explained by the paper's rounded data"
            rows.append(
                Check(
                    id=key,
                    kind="value",
                    published=value,
                    published_text=_signed(printed, value),
                    computed=round(magnitude, _digits(printed or "0", 4)),
                    verdict="agrees" if ok else "disagrees",
                    detail=(
                        f"{entry.get('meaning', '')}; computed from {source_eq} (printed form, checked "
                        f"symbolically in row {source_eq}) with the problem data; |difference| = "
                        f"{abs(magnitude - value):.2g}, tolerance {tol:.2g} {how}"
                        + _gc_note(unit, magnitude, scene)
                    ),
                    label=f"Eq. (29) row {row[1:]}: " + ("right side" if column == "rhs" else f"coefficient of {column}"),
                    section="example1",
                    published_unit=entry.get("unit") or "",
                    computed_unit=_unit_label(unit) if unit is not None else "",
                    tolerance=f"±{tol:.2g}",
                    explanation="" if ok else "The printed coefficient is not the rounded value of the exact one.",
                    caveat="" if within_half or not ok else (
                        f"The exact value {magnitude:.{_digits(printed, 2)}f} does not round to the printed "
                        f"{value:.{_digits(printed, 0)}f}; the paper evidently computed with its rounded intermediate data "
                        f"({', '.join(data_used)}), which explains the last digit."
                    ),
                )
            )

    # ---- Eq. 30: the solver's solution vs the printed results
    results_prefix = system.get("results", "eq30")
    # one tolerance model for Eq. 30, shared with the tests (reports/rounding.py)
    tolerance = eq30_tolerances(published, prefix, results_prefix) if unknowns else {}
    for u in unknowns:
        key = f"{results_prefix}-{u}"
        entry = published.get(key)
        if entry is None:
            continue
        if u not in solution.unknowns:
            rows.append(not_checkable(key, "value", entry["value"], f"the solver gives no unknown {u!r}",
                                      section="example1"))
            continue
        computed_q = solution.unknowns[u]
        printed_unit = _unit(entry["unit"])
        value = float(entry["value"])
        unit_ok = computed_q.dimensionality == (1 * printed_unit).dimensionality
        if unit_ok:
            compare_unit = printed_unit
        else:
            # The printed unit has the wrong dimension: compare the number in the unit of the
            # computed quantity expressed with the printed unit's base (rad/s -> rad/s**2).
            compare_unit = computed_q.units
        magnitude = float(computed_q.to(compare_unit).magnitude)
        h = half_unit(entry["printed"])
        tol = tolerance.get(u, h)
        diff = abs(magnitude - value)
        ok = diff <= tol
        within_half = diff <= h
        detail = (
            f"{entry.get('meaning', '')}; solver (generalized Euler about {deriv.point}, confirmed by the "
            f"mass-centre and Lagrange routes in the solver's tests) gives {magnitude:.6g} {_unit_label(compare_unit)}; "
            f"|difference| = {diff:.2g}; tolerance {tol:.2g} = half unit of the last printed digit ({h:.2g})"
            f" + first-order effect of the paper's 4-significant-figure rounding in Eq. 29, of the rounded data"
            f" it computed with and of the results it substituted back ({tol - h:.2g})"
            + _gc_note(compare_unit, magnitude, scene)
        )
        if ok and not within_half:
            detail += "; outside the half-unit band alone, inside once the paper's intermediate rounding is allowed for"
        rows.append(
            Check(
                id=key,
                kind="value",
                published=value,
                published_text=entry["printed"],
                computed=round(magnitude, _digits(entry["printed"])),
                verdict="agrees" if ok else "disagrees",
                detail=detail,
                label=f"Eq. (30): {u}",
                section="example1",
                published_unit=entry["unit"],
                computed_unit=_unit_label(compare_unit),
                tolerance=f"±{tol:.2g}",
                explanation="" if ok else "The printed result is not explained by rounding.",
                caveat="" if within_half or not ok else (
                    f"The exact value {magnitude:.{_digits(entry['printed'], 2)}f} does not round to the printed "
                    f"{entry['printed']}; the difference is within what the paper's 4-significant-figure "
                    "rounding of the Eq. 29 coefficients and of the intermediate results explains."
                ),
            )
        )
        if entry["unit"]:
            expected = _unit_label(compare_unit)
            printed_dim = str((1 * printed_unit).dimensionality)
            computed_dim = str(computed_q.dimensionality)
            rows.append(
                Check(
                    id=f"{key}-unit",
                    kind="unit",
                    published=entry["unit"],
                    computed=expected,
                    verdict="agrees" if unit_ok else "disagrees",
                    detail=f"dimension of the printed unit {printed_dim} vs the computed quantity {computed_dim}",
                    label=f"Eq. (30): unit of {u}",
                    section="example1",
                    published_unit=entry["unit"],
                    computed_unit=expected,
                    tolerance=_SAME_DIMENSION,
                    explanation="" if unit_ok else (
                        f"Eq. ({results_prefix[2:]}) prints the unit of {u} as {entry['unit']} (dimension "
                        f"{(1 * printed_unit).dimensionality:P}), but {u} is computed with dimension "
                        f"{computed_q.dimensionality:P}, unit {expected}."
                        + (
                            f" The number itself agrees (row {key}), so the unit is a typographical slip."
                            if ok else ""
                        )
                    ),
                )
            )

    # ---- problem data: the scene holds what the paper states
    for key, entry in published.items():
        if not key.startswith("data-"):
            continue
        name = key[len("data-"):]
        base, _, _ = name.partition("-")
        target = _scene_quantity(scene, base)
        value = float(entry["value"])
        unit_text = entry["unit"] or entry.get("implied_unit", "")
        if target is None:
            rows.append(not_checkable(key, "value", value, f"scene {scene.name!r} has no quantity {base!r}",
                                      section="example1"))
            continue
        unit = _unit(unit_text)
        try:
            magnitude = float(target.to(unit).magnitude)
        except Exception:  # noqa: BLE001 - any pint conversion failure is a dimension mismatch
            rows.append(
                Check(key, "value", value, str(target), "disagrees",
                      f"{entry.get('meaning', '')}; scene value {target} cannot be expressed in {unit_text}",
                      label=f"Problem data: {name}", section="example1", published_unit=unit_text,
                      explanation="The scene's value has another dimension than the printed one.")
            )
            continue
        exact = bool(entry.get("exact", False))
        h = 0.0 if exact else half_unit(entry["printed"])
        tol = h if h else _EXACT_RTOL * max(1.0, abs(value))
        ok = abs(magnitude - value) <= tol
        rows.append(
            Check(
                id=key,
                kind="value",
                published=value,
                published_text=entry["printed"],
                computed=round(magnitude, _digits(entry["printed"], 4)),
                verdict="agrees" if ok else "disagrees",
                detail=(
                    f"{entry.get('meaning', '')}; scene value {target:~P} = {magnitude:.6g} {_unit_label(unit)}; "
                    + ("exact number" if not h else f"tolerance {tol:.2g} (half a unit in the last printed digit)")
                    + _gc_note(unit, magnitude, scene)
                ),
                label=f"Problem data: {name}",
                section="example1",
                published_unit=unit_text,
                computed_unit=_unit_label(unit),
                tolerance=f"±{tol:.2g}",
                explanation="" if ok else "The printed number does not follow from the problem data.",
            )
        )
        if entry["unit"] and h:
            unit_ok = target.dimensionality == (1 * unit).dimensionality
            rows.append(
                Check(f"{key}-unit", "unit", entry["unit"], _unit_label(unit), "agrees" if unit_ok else "disagrees",
                      f"printed unit {entry['unit']} has the dimension of the quantity ({dict(target.dimensionality)})",
                      label=f"Problem data: unit of {name}", section="example1", published_unit=entry["unit"],
                      computed_unit=_unit_label(unit), tolerance=_SAME_DIMENSION)
            )
    return rows


# --------------------------------------------------------------------------- survey
def _slug(text: str) -> str:
    return re.sub(r"[^a-z0-9]+", "-", text.lower()).strip("-")


@dataclass
class SurveyResults:
    """What the survey part of the report needs (beyond the rows)."""

    facts: object
    table_check: object
    summary: object
    claims: object
    dataset: object
    largest_remainder: dict = field(default_factory=dict)


def survey_checks(dataset_path: Path) -> tuple[list[Check], SurveyResults]:
    """Table 1 cells, the response facts and the two claims.

    Parameters
    ----------
    dataset_path : pathlib.Path
        Where to write the respondent-level dataset rebuilt from Table 1
        (analysis.respondents), which is then read back through the same
        ingestion path an instructor's export takes.
    """
    from analysis.claims import evaluate_claims
    from analysis.ingest import read_survey
    from analysis.likert import summarize

    try:
        from analysis.rounding import largest_remainder, round_fraction
    except ImportError:  # older layout of the analysis package
        from analysis.likert import largest_remainder
        from analysis.likert import round_half_away as round_fraction
    from analysis.respondents import rebuild_table1_dataset
    from analysis.tables import load_table1, published_dir, table1_check, verify_table

    table, facts = load_table1()
    check = table1_check()
    dataset = rebuild_table1_dataset(dataset_path)
    data = read_survey(dataset_path, scale=facts.scale)
    summary = summarize(data)
    claims = evaluate_claims(published_dir() / "claims.toml", summary)
    rows: list[Check] = []
    lr: dict[str, list[float]] = {}

    for index, row in enumerate(check.rows):
        item_no = index + 1
        item = summary.items[index]
        exact_row = [Fraction(item.counts[label] * 100, item.n) for label in check.labels]
        rounded = [float(round_fraction(x, facts.decimals)) for x in exact_row]
        lr_row = [float(x) for x in largest_remainder([item.counts[label] for label in check.labels], facts.decimals)]
        lr[row.item] = lr_row
        for j, cell in enumerate(row.cells):
            computed = rounded[j]
            ok = cell.attainable and math.isclose(computed, cell.published, abs_tol=1e-9)
            detail = (
                f"{cell.reason}; rebuilt dataset: {item.counts[cell.label]}/{item.n} = "
                f"{float(exact_row[j]):.3f}% -> {computed:.{facts.decimals}f}% (half away from zero)"
            )
            explanation = ""
            if not ok:
                # the verdict (what is wrong with the cell and its row) is analysis.tables'
                explanation = (
                    f"Row {row.item}: {row.reason}. "
                    f"The rebuilt dataset has {item.counts[cell.label]}/{item.n} = {float(exact_row[j]):.2f}%, "
                    f"which rounds to {computed:.{facts.decimals}f}%, not the printed {cell.printed}%"
                    + (
                        f"; a largest-remainder rounding (rows forced to 100%) would print "
                        f"{lr_row[j]:.{facts.decimals}f}% too, so only the rule above explains the printed digit"
                        if lr_row[j] != cell.published
                        else "; a largest-remainder rounding (rows forced to 100%) prints it too"
                    )
                    + ". A rounding that forces the row to 100% explains the printed digit but makes the cell "
                    "misstate its own share; the article states no such rule, so the cell is listed as a "
                    "difference, not as an agreement with a caveat."
                )
            rows.append(
                Check(
                    id=f"table1-item{item_no}-{_slug(cell.label)}",
                    kind="table-cell",
                    published=cell.published,
                    published_text=cell.printed,
                    computed=computed,
                    verdict="agrees" if ok else "disagrees",
                    detail=detail,
                    label=f"Table 1, item {row.item}, {cell.label}",
                    section="survey",
                    published_unit="%",
                    computed_unit="%",
                    tolerance=f"attainable at N = {item.n}",  # the test, met or not
                    explanation=explanation,
                )
            )

    # ---- response facts
    search = verify_table(table, n_range=(1, max(facts.enrolled, facts.respondents)))
    rate = facts.respondents / facts.enrolled
    # rows whose counts cannot add up to N, by the row verdicts of analysis.tables
    off_rows = [r for r in check.rows if r.reconstructed is None
                or {"sum_off", "counts_do_not_add_up"} & set(r.findings)]
    most = search.n
    ok = summary.respondents == facts.respondents and most == facts.respondents and not off_rows
    rows.append(
        Check(
            id="response-rate",
            kind="value",
            published=f"{facts.respondents} of {facts.enrolled}",
            computed=f"{summary.respondents} of {facts.enrolled} ({100 * summary.respondents / facts.enrolled:.1f}%)",
            verdict="agrees" if ok else "disagrees",
            detail=(
                f"response rate {facts.respondents}/{facts.enrolled} = {100 * rate:.1f}%; "
                + (f"every item's rebuilt counts add up to N = {facts.respondents}; " if not off_rows else
                   "".join(f"item {r.item}: {r.verdict}; " for r in off_rows))
                + f"among N = 1..{max(facts.enrolled, facts.respondents)}, "
                f"N = {most} makes the most printed cells attainable"
                + (" (no N makes all of them attainable)" if not search.feasible_n else
                   f" (N making every cell attainable: {search.feasible_n})")
            ),
            label="Table 1 note: respondents of enrolled",
            section="survey",
        )
    )

    # ---- claims
    for result in claims.results:
        c = result.claim
        item_no = c.item if isinstance(c.item, int) else summary.items.index(summary.item(c.item)) + 1
        holds = result.verdict_code in ("holds", "sample_only")
        share = f"{100 * result.share:.1f}%" if result.share is not None else "n/a"
        ci = f"[{100 * result.ci[0]:.1f}%, {100 * result.ci[1]:.1f}%]" if result.share is not None else ""
        caveat = ""
        if result.verdict_code == "sample_only":
            caveat = (
                f"True of the {result.n} respondents ({result.k}/{result.n} = {share}), but the 95% "
                f"{result.method.title()} interval {ci} reaches below {100 * c.threshold:.0f}%: with {result.n} "
                "answers the data cannot show that the share in the wider student population clears the threshold."
            )
        rows.append(
            Check(
                id=f"claim-item{item_no}",
                kind="claim",
                published=c.printed or c.statement,
                computed=f"{share} {ci}".strip(),
                verdict=("not-checkable" if result.verdict_code == "no_answers"
                         else "agrees" if holds else "disagrees"),
                detail=f"{c.statement} Verdict: {result.verdict}; {result.reason} "
                f"({result.k}/{result.n}, 95% {result.method.title()} interval {ci}).",
                label=f"Claim about item {item_no}",
                section="survey",
                explanation=("" if holds else f"No valid answers: {result.reason}."
                             if result.verdict_code == "no_answers"
                             else f"The observed share {share} does not satisfy the claim."),
                caveat=caveat,
            )
        )
    results = SurveyResults(facts=facts, table_check=check, summary=summary, claims=claims, dataset=dataset,
                            largest_remainder=lr)
    return rows, results
