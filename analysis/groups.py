"""Group comparisons of Likert items over a grouping column (section, term, ...).

Two groups: Mann-Whitney U (``scipy.stats.mannwhitneyu``, two-sided) with
Cliff's delta as the ordinal effect size. More groups: Kruskal-Wallis H
(``scipy.stats.kruskal``) with epsilon-squared, :math:`H/(n-1)`.

Cliff's delta of group A against group B is

.. math::  \\delta = P(X_A > X_B) - P(X_A < X_B) = \\frac{2U_A}{n_A n_B} - 1,

computed here by sorting and binary search (no n_A * n_B pair matrix).

Groups with fewer respondents than ``min_size`` (default 5) are suppressed: their
results are not shown and they take no part in the tests; the reason is given.
Group values match as answers do, ignoring case and white space ("Mon", " mon ").

Public API: :func:`compare_groups` -> :class:`GroupComparison` (``to_dict()``,
``format_text()``), :func:`cliffs_delta`.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy import stats

from .errors import SurveyInputError
from .ingest import SurveyData
from .scales import normalize_answer

__all__ = ["GroupInfo", "ItemComparison", "GroupComparison", "compare_groups", "cliffs_delta"]

BLANK_GROUP = "(blank)"
#: Most (reported groups x items) one comparison computes (about half a millisecond each).
MAX_GROUP_CELLS = 10_000


def cliffs_delta(x, y) -> float:
    """Cliff's delta of sample x against sample y (ordinal effect size, -1..1).

    Computed from sorted values: for each x, the number of y below minus above.
    """
    x = np.asarray(x, dtype=float)
    y = np.sort(np.asarray(y, dtype=float))
    if x.size == 0 or y.size == 0:
        raise ValueError("cliffs_delta needs two non-empty samples")
    below = np.searchsorted(y, x, side="left")
    above = y.size - np.searchsorted(y, x, side="right")
    return float((below - above).sum() / (x.size * y.size))


@dataclass
class GroupInfo:
    """One value of the grouping column."""

    name: str
    respondents: int
    suppressed: bool
    reason: str = ""

    def to_dict(self) -> dict:
        return {"group": self.name, "respondents": self.respondents,
                "suppressed": self.suppressed, "reason": self.reason}


@dataclass
class ItemComparison:
    """One item compared across the shown groups.

    Attributes
    ----------
    item : str
    test : str
        ``"mann-whitney"``, ``"kruskal-wallis"`` or ``"none"`` (with ``note``).
    statistic, p_value : float or None
    effect_name : str
        ``"cliffs_delta"`` (first shown group against the second) or ``"epsilon_squared"``.
    effect : float or None
    per_group : dict
        Per shown group: valid n, median code and agreement share.
    note : str
    """

    item: str
    test: str
    statistic: float | None
    p_value: float | None
    effect_name: str
    effect: float | None
    per_group: dict
    note: str = ""

    def to_dict(self) -> dict:
        return {"item": self.item, "test": self.test, "statistic": self.statistic,
                "p_value": self.p_value, "effect_name": self.effect_name,
                "effect": self.effect, "per_group": self.per_group, "note": self.note}


@dataclass
class GroupComparison:
    """All items compared over one grouping column."""

    column: str
    min_size: int
    groups: list[GroupInfo]
    items: list[ItemComparison] = field(default_factory=list)

    def to_dict(self) -> dict:
        return {"column": self.column, "min_size": self.min_size,
                "groups": [g.to_dict() for g in self.groups],
                "items": [i.to_dict() for i in self.items]}

    def format_text(self) -> str:
        out = [f"groups by {self.column!r} (groups under {self.min_size} respondents suppressed)"]
        for g in self.groups:
            out.append(f"  {g.name}: {g.respondents} respondents"
                       + (f" -- suppressed: {g.reason}" if g.suppressed else ""))
        for it in self.items:
            if it.test == "none":
                out.append(f"  {it.item}: no test ({it.note})")
                continue
            out.append(f"  {it.item}: {it.test} statistic {it.statistic:.4g}, p = {it.p_value:.4g}, "
                       f"{it.effect_name} = {it.effect:.3f}")
        return "\n".join(out)


def _validate_groups(data, column, min_size):
    if not isinstance(data, SurveyData):
        raise TypeError(f"`data` must be SurveyData, got {type(data).__name__}")
    if not isinstance(min_size, int) or min_size < 1:
        raise ValueError(f"`min_size` must be a positive integer, got {min_size!r}")
    for name in data.groups:
        if normalize_answer(name) == normalize_answer(column):
            return name
    raise SurveyInputError(f"no grouping column {column!r} was read; read the survey with "
                           f"group={column!r} (columns kept: {list(data.groups)})", data.source)


def compare_groups(data: SurveyData, column: str, min_size: int = 5) -> GroupComparison:
    """Compare every item across the values of a grouping column.

    Parameters
    ----------
    data : SurveyData
        Read with ``group=column``.
    column : str
        Grouping column.
    min_size : int
        Groups with fewer respondents are suppressed (reason given).

    Returns
    -------
    GroupComparison
    """
    name = _validate_groups(data, column, min_size)
    # spellings of one value ("Mon", " mon ") are one group, named by its commonest spelling
    texts = [str(v) for v in data.groups[name]]
    keys = np.array([normalize_answer(t) for t in texts], dtype=object)
    keys_u, inverse = np.unique(keys, return_inverse=True)
    spelled: list[dict] = [{} for _ in keys_u]
    for g, t in zip(inverse, texts):
        t = " ".join(t.split())
        spelled[g][t] = spelled[g].get(t, 0) + 1
    values = np.array([BLANK_GROUP if k == "" else max(sp, key=lambda t: (sp[t], t))
                       for k, sp in zip(keys_u, spelled)], dtype=object)
    infos, shown = [], []
    sizes = np.bincount(inverse, minlength=len(values))
    # respondents of each group, found once (a scan per group was quadratic in the groups)
    members = np.split(np.argsort(inverse, kind="stable"), np.cumsum(sizes)[:-1])
    for g, val in enumerate(values):
        size = int(sizes[g])
        if size < min_size:
            infos.append(GroupInfo(str(val), size, True,
                                   f"{size} respondent{'s' if size != 1 else ''} < {min_size}: "
                                   f"too few to report without identifying people"))
        else:
            infos.append(GroupInfo(str(val), size, False))
            shown.append(g)
    if len(shown) * len(data.items) > MAX_GROUP_CELLS:
        raise SurveyInputError(
            f"grouping column {name!r}: {len(shown)} groups x {len(data.items)} items; at most "
            f"{MAX_GROUP_CELLS} group-item pairs are compared (raise --min-group or choose "
            f"--items)", data.source)
    comp = GroupComparison(column=name, min_size=min_size, groups=infos)
    scale = data.scale
    pos = [scale.labels.index(x) for x in scale.positive]
    for j, item in enumerate(data.items):
        rev = item in data.reverse
        codes = np.array(scale.reversed_codes() if rev else scale.codes, dtype=float)
        a = data.answers[:, j]
        samples, per = [], {}
        for g in shown:
            sel = a[members[g]]
            sel = sel[sel >= 0]
            x = codes[sel]
            samples.append(x)
            per[str(values[g])] = {
                "n": int(x.size),
                "median": float(np.median(x)) if x.size else None,
                "agree_share": float(np.isin(sel, pos).mean()) if x.size else None}
        usable = [s for s in samples if s.size]
        if len(usable) < 2:
            comp.items.append(ItemComparison(item, "none", None, None, "", None, per,
                                             "fewer than two groups to compare after suppression"))
            continue
        allx = np.concatenate(usable)
        if np.all(allx == allx[0]):
            comp.items.append(ItemComparison(item, "none", None, None, "", None, per,
                                             "every answer is the same"))
            continue
        if len(usable) == 2:
            res = stats.mannwhitneyu(usable[0], usable[1], alternative="two-sided")
            comp.items.append(ItemComparison(item, "mann-whitney", float(res.statistic),
                                             float(res.pvalue), "cliffs_delta",
                                             cliffs_delta(usable[0], usable[1]), per))
        else:
            res = stats.kruskal(*usable)
            n = allx.size
            comp.items.append(ItemComparison(item, "kruskal-wallis", float(res.statistic),
                                             float(res.pvalue), "epsilon_squared",
                                             float(res.statistic / (n - 1)), per))
    return comp
