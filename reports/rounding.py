"""How far a printed number may lie from the exact one: the paper's rounding, one model.

The report (``reports/checks.py``) and the tests (``tests/test_example1_published.py``,
``tests/test_cli_solver.py``) compare the solver's Example 1 answer with the paper's
Eq. 30 under the tolerance computed here, and nowhere else.

Model
-----
* A printed number stands for every value within half a unit of its last printed
  digit (:func:`half_unit`); a number marked ``exact`` has no rounding of its own.
* Eq. 30 is the paper's hand solution of its printed Eq. 29. So an Eq. 30 value is
  off from the exact answer by, to first order,

  - every Eq. 29 coefficient's rounding, propagated through the solve:
    ``|A^-1| (h_b + h_A |x|)``, where ``h`` is the coefficient's half unit plus the
    rounding of the problem data the paper computed it from (its m_b in slug, rounded
    to 4 significant figures, for the ``alpha`` column; its g, 5 significant figures,
    for the right-hand sides: the scene's weight is 50 lbm times that g);
  - for a result the paper obtained by back substitution in one row, the rounding of
    the other results it used there: ``sum |A[r, v] / A[r, u]| * half_unit(v)``;
  - half a unit of its own last printed digit.
"""
from __future__ import annotations

import re
from collections.abc import Mapping
from decimal import Decimal
from typing import Any

import numpy as np

__all__ = ["half_unit", "eq29_rounding", "eq30_tolerances", "EQ29_ROWS", "EQ29_UNKNOWNS", "EQ29_BACK_SUBSTITUTION",
           "EQ29_DATA_ROUNDING"]

EQ29_ROWS = ("r1", "r2", "r3")
EQ29_UNKNOWNS = ("R_B", "alpha", "R_A")
EQ29_BACK_SUBSTITUTION = {"R_B": "r2", "R_A": "r3"}
"""Unknown -> the row the paper solved it from, with the other results already rounded
(as ``back_substitution`` in data/published/equations.toml)."""
EQ29_DATA_ROUNDING = {"alpha": "data-m_b-slug", "rhs": "data-g"}
"""Eq. 29 column -> the rounded problem datum its coefficients are proportional to."""


def half_unit(printed: str) -> float:
    """Half a unit in the last printed digit of ``printed``.

    Examples
    --------
    >>> half_unit("12.34")
    0.005
    >>> half_unit("50")
    0.5
    """
    text = printed.strip().lstrip("+-")
    if not re.fullmatch(r"\d+(\.\d*)?", text):
        raise ValueError(f"`printed` must be a plain decimal number, got {printed!r}")
    exponent = Decimal(text).as_tuple().exponent
    return 0.5 * 10.0**exponent


def _rounding(entry: Mapping[str, Any]) -> float:
    return 0.0 if entry.get("exact", False) else half_unit(entry["printed"])


def eq29_rounding(published: Mapping[str, Mapping[str, Any]], key: str) -> float:
    """How far a printed Eq. 29 coefficient (id ``eq29-<row>-<column>``) may lie from the exact
    one: half a unit of its last digit, plus the rounding of the datum the paper computed
    it from (:data:`EQ29_DATA_ROUNDING`), relative, times its size."""
    entry = published[key]
    column = key.rsplit("-", 1)[1]
    datum = EQ29_DATA_ROUNDING.get(column)
    relative = _rounding(published[datum]) / abs(published[datum]["value"]) if datum else 0.0
    return _rounding(entry) + abs(float(entry["value"])) * relative


def eq30_tolerances(published: Mapping[str, Mapping[str, Any]], prefix: str = "eq29",
                    results: str = "eq30") -> dict[str, float]:
    """Tolerance of each Eq. 30 value, in its printed unit (see the module's model).

    Parameters
    ----------
    published : Mapping[str, Mapping]
        ``data/published/example1.toml``'s ``[[value]]`` entries by ``id``.

    Returns
    -------
    dict[str, float]
        ``{"R_B": ..., "alpha": ..., "R_A": ...}``.

    Examples
    --------
    >>> import tomllib
    >>> values = tomllib.load(open("data/published/example1.toml", "rb"))["value"]
    >>> tol = eq30_tolerances({v["id"]: v for v in values})
    >>> {name: round(t, 3) for name, t in tol.items()}
    {'R_B': 0.017, 'alpha': 0.002, 'R_A': 0.025}
    """
    rows, unknowns = EQ29_ROWS, EQ29_UNKNOWNS
    A = np.zeros((len(rows), len(unknowns)))
    hA = np.zeros_like(A)
    b, hb = np.zeros(len(rows)), np.zeros(len(rows))
    for i, row in enumerate(rows):
        for j, column in enumerate([*unknowns, "rhs"]):
            entry = published.get(f"{prefix}-{row}-{column}")
            if entry is None:
                continue  # the unknown does not appear in this row
            value = float(entry["value"])
            h = eq29_rounding(published, f"{prefix}-{row}-{column}")
            if column == "rhs":
                b[i], hb[i] = value, h
            else:
                A[i, j], hA[i, j] = value, h
    x = np.linalg.solve(A, b)
    spread = np.abs(np.linalg.inv(A)) @ (hb + hA @ np.abs(x))
    out = {}
    for k, u in enumerate(unknowns):
        own = _rounding(published[f"{results}-{u}"])
        back = 0.0
        if u in EQ29_BACK_SUBSTITUTION:
            r = rows.index(EQ29_BACK_SUBSTITUTION[u])
            back = sum(abs(A[r, kv] / A[r, k]) * _rounding(published[f"{results}-{v}"])
                       for kv, v in enumerate(unknowns) if v != u and A[r, kv] != 0)
        out[u] = float(spread[k] + back + own)
    return out
