"""The paper's survey, reproduced end to end (for the verification report).

:func:`table1_reproduction` runs the whole chain on the published facts:

1. check Table 1 as printed against its stated N (:func:`analysis.tables.table1_check`);
2. rebuild the respondent-level dataset from the reconstructed counts
   (:func:`analysis.respondents.rebuild_table1_dataset`);
3. read that file back like any export and summarise it (:mod:`analysis.likert`);
4. compare every recomputed cell with the printed one at the printed precision;
5. evaluate the paper's claims (``data/published/claims.toml``) on it.

Everything comes from ``data/published/``; nothing is typed in code.

Example
-------
>>> from analysis.paper import table1_reproduction           # doctest: +SKIP
>>> rep = table1_reproduction("reports/build")               # doctest: +SKIP
>>> [(c.item, c.label) for c in rep.cells if not c.matches]  # doctest: +SKIP
"""
from __future__ import annotations

from dataclasses import dataclass
from decimal import Decimal
from pathlib import Path

from .claims import ClaimsReport, evaluate_claims
from .ingest import read_survey
from .likert import SurveySummary, summarize
from .respondents import RebuiltDataset, rebuild_table1_dataset
from .tables import TableCheck, load_survey_facts, published_dir

__all__ = ["CellComparison", "Table1Reproduction", "table1_reproduction"]

#: File name of the rebuilt dataset inside the output folder.
DATASET_NAME = "table1_rebuilt.csv"


@dataclass
class CellComparison:
    """One Table 1 cell: printed vs recomputed from the rebuilt data.

    Attributes
    ----------
    item : str
        Table row (as printed, e.g. the item number).
    column : str
        Column header of the item in the rebuilt dataset.
    label : str
    published : float
        As printed.
    printed : str
        Printed text.
    recomputed : float
        ``100 * count / N`` rounded half away from zero to the printed precision.
    count : int
    n : int
    matches : bool
    reason : str
    """

    item: str
    column: str
    label: str
    published: float
    printed: str
    recomputed: float
    count: int
    n: int
    matches: bool
    reason: str

    def to_dict(self) -> dict:
        return dict(vars(self))


@dataclass
class Table1Reproduction:
    """Result of :func:`table1_reproduction`."""

    check: TableCheck
    dataset: RebuiltDataset
    summary: SurveySummary
    claims: ClaimsReport
    cells: list[CellComparison]
    decimals: int

    @property
    def mismatches(self) -> list[CellComparison]:
        return [c for c in self.cells if not c.matches]

    def to_dict(self) -> dict:
        return {"n": self.check.n, "decimals": self.decimals,
                "dataset": self.dataset.to_dict(),
                "cells": [c.to_dict() for c in self.cells],
                "table_check": self.check.to_full_dict(),
                "summary": self.summary.to_full_dict(),
                "claims": self.claims.to_dict()}


def table1_reproduction(out_dir: "str | Path", method: str = "wilson",
                        confidence_level: float = 0.95) -> Table1Reproduction:
    """Reproduce Table 1 and the two claims from the published facts.

    Parameters
    ----------
    out_dir : str or Path
        Folder for the rebuilt dataset (created if needed), e.g. ``reports/build``.
    method : {"wilson", "beta"}
        Interval method for shares and claims.
    confidence_level : float

    Returns
    -------
    Table1Reproduction
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    facts = load_survey_facts()
    dataset = rebuild_table1_dataset(out / DATASET_NAME)
    check = dataset.check
    summary = summarize(read_survey(dataset.path, scale=facts.scale), confidence_level, method)
    cells = []
    d = facts.decimals
    for row, it in zip(check.rows, summary.items):
        printed = it.printed_percent(d)
        for c in row.cells:
            ours = Decimal(f"{printed[c.label]:.{d}f}")
            pub = Decimal(c.printed.rstrip("%").strip())
            match = ours == pub
            k = it.counts[c.label]
            if match:
                reason = f"{k}/{it.n} prints as {ours}"
            elif not c.attainable:
                reason = (f"no count out of {it.n} prints as {c.printed}; the data give "
                          f"{k}/{it.n} = {ours}")
            else:
                reason = f"the rebuilt count {k}/{it.n} prints as {ours}"
            cells.append(CellComparison(item=row.item, column=it.item, label=c.label,
                                        published=c.published, printed=c.printed,
                                        recomputed=float(ours), count=k, n=it.n, matches=match,
                                        reason=reason))
    claims = evaluate_claims(published_dir() / "claims.toml", summary, confidence_level, method)
    return Table1Reproduction(check=check, dataset=dataset, summary=summary, claims=claims,
                              cells=cells, decimals=d)
