"""Group comparisons of Likert items over a grouping column (section, term, ...).

Per shown group and item: the distribution (counts and percent per label), n, the
agreement share, median, IQR, mean and SD of the codes (the same numbers as
:func:`~analysis.likert.summarize` on that group alone). Groups come in data order
(first appearance) or in a given ``order`` (e.g. terms as the user lists them).

Direction: every signed number compares the later group in the group order with the
earlier one, and is positive when the later (second) group answers higher; each
compared item says so in ``direction`` (text, HTML, JSON). For a reverse-keyed item
"higher" is on the reversed codes.

Two groups: Mann-Whitney U (``scipy.stats.mannwhitneyu``, two-sided; U is the second
group's) with Cliff's delta of the second group against the first as the ordinal effect
size. In a paired design (pre/post: the same respondents in both groups, matched by
the respondent ids :attr:`~analysis.ingest.SurveyData.ids`) the pairs are compared
instead with the Wilcoxon signed-rank test (``scipy.stats.wilcoxon`` on second minus
first group, zero differences dropped) and the matched-pairs rank-biserial correlation
:math:`r = (T^+ - T^-)/(T^+ + T^-)` (Kerby 2014), positive when the second group
answers higher. The design is paired when asked (``paired=True``), or, by default,
when the ids found once in each group are at least ``min_size`` and at least
:data:`AUTO_PAIR_SHARE` of each group's respondents: a few shared ids (students who
moved section) leave the groups independent samples, with a note that they are not
fully so. More groups: Kruskal-Wallis H (``scipy.stats.kruskal``) with
epsilon-squared, :math:`H/(n-1)`, and, when ``order`` places every group compared (an
order that means something, such as terms), a trend over the groups in that order:
Spearman's rho between the group's position and the answer code
(``scipy.stats.spearmanr``). The order of first appearance in a file means nothing, so
it gets no trend (``trend_note`` says why). When several items are tested, p-values are
also given Holm-adjusted (``statsmodels`` ``multipletests(method="holm")``): the tests
across the groups as one family, the trends as another.

Cliff's delta of sample A against sample B (here A is the second group, B the first) is

.. math::  \\delta = P(X_A > X_B) - P(X_A < X_B) = \\frac{2U_A}{n_A n_B} - 1,

computed here by sorting and binary search (no n_A * n_B pair matrix).

Groups with fewer respondents than ``min_size`` (default 5) are suppressed: their
results are not shown and they take no part in the tests; the reason is given. As the
survey's total is shown beside the groups, the smallest other groups are suppressed too
when a small group would otherwise be the total minus the groups shown
(:mod:`analysis.disclosure`).
Group values match as answers do, ignoring case and white space ("Mon", " mon ").

Public API: :func:`compare_groups` -> :class:`GroupComparison` (``to_dict()``,
``format_text()``, ``distribution_frame()``), :func:`cliffs_delta`,
:func:`rank_biserial_paired`.
"""
from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field

import numpy as np
from scipy import stats

from .disclosure import BLANK_GROUP, respondents_text, suppress_groups
from .errors import SurveyInputError
from .ingest import SurveyData
from .likert import REVERSE_MARK, REVERSE_NOTE, REVERSED_STATISTICS
from .rounding import number_text, quartile_texts, significant_text
from .scales import group_names, normalize_answer, order_groups, validate_group_order

__all__ = ["GroupInfo", "ItemComparison", "GroupComparison", "compare_groups", "cliffs_delta",
           "rank_biserial_paired"]

#: Most (reported groups x items) one comparison computes (about half a millisecond each).
MAX_GROUP_CELLS = 10_000
#: The automatic rule pairs two groups by respondent id only when the ids found once in
#: each group pair at least this share of each group's respondents (and at least
#: ``min_size`` of them): a few ids shared by two sections do not make a pre/post design.
AUTO_PAIR_SHARE = 0.5
#: Values of ``compare_groups(..., paired=)``: the automatic rule, pairs required, none.
PAIRED_CHOICES = (None, True, False)


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


def rank_biserial_paired(d) -> float:
    """Matched-pairs rank-biserial correlation of paired differences ``d`` (-1..1).

    Zero differences are dropped (as ``scipy.stats.wilcoxon`` does by default); the
    absolute differences are ranked (ties get mean ranks) and
    ``r = (T+ - T-) / (T+ + T-)``.
    """
    d = np.asarray(d, dtype=float)
    d = d[d != 0]
    if d.size == 0:
        raise ValueError("rank_biserial_paired needs a non-zero difference")
    ranks = stats.rankdata(np.abs(d))
    tp, tm = ranks[d > 0].sum(), ranks[d < 0].sum()
    return float((tp - tm) / (tp + tm))


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
        ``"cliffs_delta"`` or ``"rank_biserial_paired"`` (second group against the first)
        or ``"epsilon_squared"`` (no sign).
    effect : float or None
    per_group : dict
        Per shown group: n, missing, excluded, counts and percent per label, agreement
        share, median, IQR, mean and SD of the codes.
    note : str
    p_holm : float or None
        Holm-adjusted p-value over the items tested.
    pairs : int
        Respondents paired across the two groups (Wilcoxon test), else 0.
    pairs_unchanged : int
        Of those, the pairs that gave the same answer both times: the Wilcoxon test and the
        effect leave them out (zero differences dropped), so they are counted apart.
    trend : dict or None
        More than two groups in an order that means something (``order`` places every
        one): Spearman ``rho``, ``p_value`` and ``p_holm`` (over the items' trends, a
        family of their own) of code on group position, and the ``groups`` in order.
    reverse : bool
        Reverse-keyed: tests and median, IQR, mean, SD on reversed codes; counts raw.
    direction : str
        Which way the signed numbers point, in words ("" when nothing was tested).
    """

    item: str
    test: str
    statistic: float | None
    p_value: float | None
    effect_name: str
    effect: float | None
    per_group: dict
    note: str = ""
    p_holm: float | None = None
    pairs: int = 0
    pairs_unchanged: int = 0
    trend: dict | None = None
    reverse: bool = False
    direction: str = ""

    @property
    def pairs_text(self) -> str:
        """The pairs tested, in words, with those left out as unchanged (text and HTML)."""
        if not self.pairs_unchanged:
            return f"{self.pairs} pairs"
        return (f"{self.pairs} pairs ({self.pairs_unchanged} unchanged: left out of the test "
                f"and the effect)")

    def to_dict(self) -> dict:
        return {"item": self.item, "reversed": self.reverse, "direction": self.direction,
                "reversed_statistics": list(REVERSED_STATISTICS) if self.reverse else [],
                "test": self.test, "statistic": self.statistic,
                "p_value": self.p_value, "p_holm": self.p_holm, "effect_name": self.effect_name,
                "effect": self.effect, "pairs": self.pairs, "pairs_unchanged": self.pairs_unchanged,
                "trend": self.trend,
                "per_group": self.per_group, "note": self.note}


@dataclass
class GroupComparison:
    """All items compared over one grouping column."""

    column: str
    min_size: int
    groups: list[GroupInfo]
    items: list[ItemComparison] = field(default_factory=list)
    labels: list = field(default_factory=list)
    summaries: dict = field(default_factory=dict, repr=False)   # shown group -> SurveySummary
    paired_by: str = ""
    note: str = ""
    pairing: str = ""            # how ids were paired, or why not (groups sharing ids)
    design: str = ""             # "paired" or "independent" (two or more groups compared)
    trend_note: str = ""         # why no trend over the groups is tested (more than two)
    coverage: str = ""           # which groups the tests compare, when some are suppressed
    left_out: int = 0            # respondents of the suppressed groups, in no test
    multiplicity: str = ""       # which p-values are Holm-adjusted together

    @property
    def shown(self) -> list[str]:
        """Names of the groups shown (not suppressed), in order."""
        return [g.name for g in self.groups if not g.suppressed]

    def to_dict(self) -> dict:
        return {"column": self.column, "min_size": self.min_size, "design": self.design,
                "paired_by": self.paired_by, "note": self.note, "pairing": self.pairing,
                "trend_note": self.trend_note, "multiplicity": self.multiplicity,
                "tested_groups": self.shown if self.design else [],
                "left_out": self.left_out, "coverage": self.coverage,
                "groups": [g.to_dict() for g in self.groups],
                "items": [i.to_dict() for i in self.items]}

    def distribution_frame(self):
        """Per shown group and item (pandas): the group, named by its column as ``--by`` names
        it, the item, the group's respondents (as ``--by``'s table), the columns of every
        summary table (:func:`analysis.export.item_columns`), then the item's test across the
        groups."""
        import pandas as pd
        from .export import item_columns
        rows = []
        for j, it in enumerate(self.items):
            for g in it.per_group:
                one = self.summaries[g].items[j]
                row = {self.column: g, "item": it.item, "respondents": one.respondents,
                       **item_columns(one, self.labels)}
                row.update({"test": it.test, "p": it.p_value, "p (Holm)": it.p_holm})
                rows.append(row)
        return pd.DataFrame(rows)

    def printed(self, j: int, group: str, decimals: int = 1, method: str = "round"):
        """Item ``j`` of a shown group as printed: (percent per label, agreement percent),
        by the rule of the main table (:meth:`~analysis.likert.ItemSummary.printed_percent`)."""
        it = self.summaries[group].items[j]
        return it.printed_percent(decimals, method), it.agree.percent_text(decimals)

    def format_text(self, decimals: int = 1, method: str = "round") -> str:
        """Tests per item, then one line per shown group with its distribution, printed
        to ``decimals`` places by ``method`` as the main table prints it."""
        out = [f"groups by {self.column!r} (groups under {respondents_text(self.min_size)} suppressed)"
               + (f"; paired by {self.paired_by!r}" if self.paired_by else "")]
        for g in self.groups:
            out.append(f"  {g.name}: {respondents_text(g.respondents)}"
                       + (f" -- suppressed: {g.reason}" if g.suppressed else ""))
        if self.note:
            out.append(f"  note: {self.note}")
        if self.coverage:
            out.append(f"  coverage: {self.coverage}")
        if self.pairing:
            out.append(f"  pairing: {self.pairing}")
        if self.trend_note:
            out.append(f"  {self.trend_note}")
        if self.multiplicity:
            out.append(f"  multiplicity: {self.multiplicity}")
        width = max([len(g) for g in self.shown] + [5])
        for j, it in enumerate(self.items):
            name = it.item + (REVERSE_MARK if it.reverse else "")
            if it.test == "none":
                out.append(f"  {name}: no test ({it.note})")
            else:
                holm = "" if it.p_holm is None else f", Holm p = {significant_text(it.p_holm)}"
                pairs = f" on {it.pairs_text}" if it.pairs else ""
                out.append(f"  {name}: {it.test}{pairs} statistic "
                           f"{significant_text(it.statistic)}, p = {significant_text(it.p_value)}{holm}, "
                           f"{it.effect_name} = {number_text(it.effect, 3)}")
                out.append(f"    direction: {it.direction}")
                if it.note:
                    out.append(f"    note: {it.note}")
            if it.trend:
                holm = ("" if it.trend["p_holm"] is None
                        else f", Holm p = {significant_text(it.trend['p_holm'])}")
                out.append(f"    trend over {' -> '.join(it.trend['groups'])}: Spearman rho = "
                           f"{number_text(it.trend['rho'], 3)}, "
                           f"p = {significant_text(it.trend['p_value'])}{holm}")
            for g, d in it.per_group.items():
                pp, agree = self.printed(j, g, decimals, method)
                dist = " ".join(f"{lab} " + ("-" if pp[lab] is None else f"{pp[lab]:.{decimals}f}%")
                                for lab in self.labels)          # no percent of nobody
                agree = "-" if agree == "-" else f"{agree}%"
                out.append(f"    {g:<{width}} n={d['n']:<4} agree {agree:>4} | {dist} | "
                           f"median {number_text(d['median'])} IQR {quartile_texts(d['q1'], d['q3'])[0]} "
                           f"mean {number_text(d['mean'], 2)} SD {number_text(d['sd'], 2)}")
        if any(it.reverse for it in self.items):
            out.append(f"  {REVERSE_NOTE}")
        return "\n".join(out)


def _validate_groups(data, column, min_size, order, paired):
    if not isinstance(data, SurveyData):
        raise TypeError(f"`data` must be SurveyData, got {type(data).__name__}")
    if not isinstance(min_size, int) or min_size < 1:
        raise ValueError(f"`min_size` must be a positive integer, got {min_size!r}")
    if not any(paired is c for c in PAIRED_CHOICES):
        raise ValueError(f"`paired` must be one of {list(PAIRED_CHOICES)}, got {paired!r}")
    validate_group_order(order)
    for name in data.groups:
        if normalize_answer(name) == normalize_answer(column):
            return name
    raise SurveyInputError(f"no grouping column {column!r} was read; read the survey with "
                           f"group={column!r} (columns kept: {list(data.groups)})", data.source)


def _group_values(texts: list[str], order, source):
    """(group index per respondent, group names in order, their keys in order).

    Spellings of one value ("Mon", " mon ") are one group, named by its commonest
    spelling; groups come in first-appearance order, or in ``order``.
    """
    counts: dict[str, int] = {}
    for t in texts:
        counts[t] = counts.get(t, 0) + 1
    named = group_names(counts)
    keys = [named[t][0] for t in texts]
    first: dict[str, int] = {}
    for i, k in enumerate(keys):
        first.setdefault(k, i)
    name_of = {k: nm for k, nm in named.values()}
    ranked, = order_groups([(sorted(first, key=first.get), name_of)], order, source)
    index = {k: g for g, k in enumerate(ranked)}
    inverse = np.array([index[k] for k in keys], dtype=np.int64)
    names = [BLANK_GROUP if k == "" else name_of[k] for k in ranked]
    return inverse, names, ranked


def compare_groups(data: SurveyData, column: str, min_size: int = 5,
                   order: "list[str] | None" = None,
                   paired: "bool | None" = None) -> GroupComparison:
    """Compare every item across the values of a grouping column.

    Parameters
    ----------
    data : SurveyData
        Read with ``group=column``.
    column : str
        Grouping column.
    min_size : int
        Groups with fewer respondents are suppressed (reason given); so are paired
        tests on fewer pairs.
    order : list of str, optional
        Group order (e.g. terms); default: order of first appearance in the data.
    paired : bool or None
        How two groups' respondents are paired by :attr:`SurveyData.ids` (pre/post).
        None (default): the automatic rule, pairs only when the ids found once in each
        group are at least ``min_size`` and at least :data:`AUTO_PAIR_SHARE` of each
        group's respondents; else independent samples, with a note when some ids are in
        both groups. True: pairs required (``--paired``; refused when the file has no id
        column, other than two groups are compared, or fewer than ``min_size`` ids pair).
        False: independent samples whatever the ids (``--independent``).

    Returns
    -------
    GroupComparison
    """
    from .likert import summarize
    name = _validate_groups(data, column, min_size, order, paired)
    inverse, values, keys = _group_values([str(v) for v in data.groups[name]], order,
                                          data.source)
    sizes = np.bincount(inverse, minlength=len(values))
    # respondents of each group, found once (a scan per group was quadratic in the groups)
    members = np.split(np.argsort(inverse, kind="stable"), np.cumsum(sizes)[:-1])
    infos, shown, withheld = _group_infos(values, sizes, min_size)
    if len(shown) * len(data.items) > MAX_GROUP_CELLS:
        raise SurveyInputError(
            f"grouping column {name!r}: {len(shown)} groups x {len(data.items)} items; at most "
            f"{MAX_GROUP_CELLS} group-item pairs are compared (raise --min-group or choose "
            f"--items)", data.source)
    comp = GroupComparison(column=name, min_size=min_size, groups=infos,
                           labels=list(data.scale.labels), note=withheld.note)
    for g in shown:
        comp.summaries[str(values[g])] = summarize(data.subset(members[g]))
    pairs, comp.pairing = _pairs(data, inverse, shown, sizes, values, min_size, paired)
    if pairs is not None:
        comp.paired_by = data.id_column
    comp.design = "" if len(shown) < 2 else "independent" if pairs is None else "paired"
    comp.left_out = int(sizes.sum() - sizes[shown].sum())
    comp.coverage = _coverage(infos, comp.left_out) if comp.design else ""
    unordered = _unordered([str(values[g]) for g in shown], [keys[g] for g in shown], order)
    comp.trend_note = _trend_note(unordered, order) if len(shown) > 2 else ""
    _test_items(comp, data, [str(values[g]) for g in shown], [members[g] for g in shown],
                pairs, min_size, trend=not unordered)
    comp.multiplicity = _holm(comp.items)
    return comp


def _test_items(comp, data, names, members, pairs, min_size, trend) -> None:
    """Test every item over the shown groups (``names``, their rows ``members``), adding
    an :class:`ItemComparison` per item to ``comp``; ``trend``: the groups' order means
    something, so a trend over it is tested."""
    scale = data.scale
    for j, item in enumerate(data.items):
        rev = item in data.reverse
        codes = np.array(scale.reversed_codes() if rev else scale.codes, dtype=float)
        a = data.answers[:, j]
        per = {nm: _per_group(comp.summaries[nm].items[j]) for nm in names}
        samples = []
        for rows in members:
            sel = a[rows]
            samples.append(codes[sel[sel >= 0]])
        it = _test_item(item, samples, names, per, codes, a, pairs, min_size, trend)
        it.reverse = rev
        if rev and it.direction:
            it.direction += " (on the reversed codes)"
        comp.items.append(it)


def _quoted(name) -> str:
    """A group name or id in quotes as the file writes it (``'"q'<'``, where ``repr`` would
    print ``'"q\\'<'``); only a character that would break the line (a line break, a control
    character) is escaped."""
    text = "".join(c if c.isprintable() else c.encode("unicode_escape").decode("ascii")
                   for c in str(name))
    return f"'{text}'"


def _coverage(infos, left_out) -> str:
    """The groups the tests compare and the respondents they leave out, when suppression
    withheld some groups ("" when every group is compared)."""
    hidden = [g for g in infos if g.suppressed]
    if not hidden:
        return ""
    shown = [g for g in infos if not g.suppressed]
    total = sum(g.respondents for g in infos)
    return (f"the tests compare {len(shown)} of the {len(infos)} groups "
            f"({', '.join(_quoted(g.name) for g in shown)}: {total - left_out} of {total} "
            f"respondents); the {left_out} respondent{'s' if left_out != 1 else ''} of the "
            f"suppressed group{'s' if len(hidden) != 1 else ''} "
            f"({', '.join(_quoted(g.name) for g in hidden)}) "
            f"{'are' if left_out != 1 else 'is'} left out, for disclosure reasons")


def _unordered(names, keys, order) -> list:
    """The compared groups (``names``, matched by ``keys``) that ``order`` (--group-order)
    does not place: all of them when no order is given. A trend needs none."""
    placed = {normalize_answer(o) for o in order or ()}
    return [nm for nm, k in zip(names, keys) if k not in placed]


def _trend_note(unordered, order) -> str:
    """Why no trend over the groups is tested ("" when one is)."""
    if not unordered:
        return ""
    if not order:
        return ("no trend over the groups: they come in the order in which they first "
                "appear in the file, which orders nothing (sorting the file would change "
                "it); give --group-order to test a trend over an order that means something, "
                "such as terms")
    return (f"no trend over the groups: --group-order does not place "
            f"{', '.join(_quoted(n) for n in unordered[:5])}{' ...' if len(unordered) > 5 else ''}"
            f", and a trend needs an order over every group compared")


def _group_infos(values, sizes, min_size):
    """(GroupInfo per group, indices of the shown groups, the Suppression): groups under
    ``min_size`` and their complements (:func:`analysis.disclosure.suppress_groups`) are
    withheld, each with its reason."""
    withheld = suppress_groups(sizes, min_size, [str(v) for v in values])
    infos, shown = [], []
    for g, val in enumerate(values):
        size = int(sizes[g])
        if size < min_size:
            infos.append(GroupInfo(str(val), size, True,
                                   f"{size} respondent{'s' if size != 1 else ''} < {min_size}: "
                                   f"too few to report without identifying people"))
        elif withheld.withheld(g):
            infos.append(GroupInfo(str(val), size, True,
                                   "complementary suppression: with it shown, a smaller group "
                                   "would be the total minus the groups shown"))
        else:
            infos.append(GroupInfo(str(val), size, False))
            shown.append(g)
    return infos, shown, withheld


def _per_group(it) -> dict:
    return {"n": it.n, "missing": it.missing, "excluded": it.excluded,
            "counts": dict(it.counts), "percent": dict(it.percent),
            "agree_share": it.agree.share, "median": it.median, "iqr": it.iqr, "q1": it.q1, "q3": it.q3,
            "mean": it.mean, "sd": it.sd}


def _ids_by_group(data, inverse, shown, values):
    """Per shown group: its ids found on one row ({key: row}) and every id key it has; and
    the ids on more than one row of a group, as the file writes them (for the note)."""
    ids = np.array([normalize_answer(str(x)) for x in data.ids], dtype=object)
    once, seen, twice = [], [], []
    for g in shown:
        rows = np.flatnonzero((inverse == g) & (ids != ""))
        keys = ids[rows]
        uniq, cnt = np.unique(keys, return_counts=True)
        single = set(uniq[cnt == 1].tolist())
        once.append({k: r for k, r in zip(keys, rows) if k in single})
        seen.append(set(uniq.tolist()))
        twice += [f"{_quoted(str(data.ids[rows[keys == k][0]]).strip())} {int(c)} times in "
                  f"{values[g]}" for k, c in zip(uniq, cnt) if c > 1]
    return once, seen, twice


def _refuse_pairing(data, shown, values, common, min_size) -> None:
    """Refuse ``paired=True`` (``--paired``) when the data cannot be paired: no id column,
    other than two groups compared, or fewer than ``min_size`` ids once in each."""
    if data.ids is None:
        raise SurveyInputError(
            "--paired: the file has no column identifying respondents (a student id, "
            "respondent, participant, user or email column), so nobody can be paired; "
            "without --paired the groups are compared as independent samples", data.source)
    if len(shown) != 2:
        raise SurveyInputError(
            f"--paired: the paired test compares two groups, and {len(shown)} "
            f"{'is' if len(shown) == 1 else 'are'} compared ({[str(values[g]) for g in shown]})",
            data.source)
    if common is not None and len(common) < min_size:
        raise SurveyInputError(
            f"--paired: {len(common)} id{'s' if len(common) != 1 else ''} in column "
            f"{data.id_column!r} answered once in both {_quoted(values[shown[0]])} and "
            f"{_quoted(values[shown[1]])}, fewer than --min-group {min_size}: too few pairs "
            f"for a paired test", data.source)


def _pairs(data, inverse, shown, sizes, values, min_size, paired):
    """How the compared groups are paired by respondent id.

    Returns ((row in first group, row in second) per pair, or None for independent
    samples; the pairing note, "" when there is nothing to say). ``paired`` None applies
    the automatic rule (:data:`AUTO_PAIR_SHARE`), True requires pairs (refused when the
    data have none, :func:`_refuse_pairing`), False forbids them.
    """
    if paired is True:
        _refuse_pairing(data, shown, values, None, min_size)
    if data.ids is None or len(shown) < 2:
        return None, ""
    once, seen, twice = _ids_by_group(data, inverse, shown, values)
    shared = sum(1 for c in Counter(k for ks in seen for k in ks).values() if c > 1)
    parts = []
    if twice:
        parts.append(f"ids on more than one row of a group are not paired "
                     f"({', '.join(twice[:3])}{' ...' if len(twice) > 3 else ''})")
    if len(shown) > 2:
        if shared:
            parts.append(_not_independent(shared, "more than one group"))
        return None, "; ".join(parts)
    common = [k for k in once[0] if k in once[1]]
    if paired is True:
        _refuse_pairing(data, shown, values, common, min_size)
    n0, n1 = (int(sizes[g]) for g in shown)
    names = [str(values[g]) for g in shown]
    enough = len(common) >= min_size
    most = len(common) >= AUTO_PAIR_SHARE * n0 and len(common) >= AUTO_PAIR_SHARE * n1
    if paired is False or (paired is None and not (enough and most)):
        if shared:                   # said only when some respondents are in both groups
            if paired is False:
                why = "compared as independent samples (--independent)"
            else:
                short = (f"fewer than {min_size}" if not enough else f"fewer than half of "
                         f"{names[0]}'s {n0} or {names[1]}'s {n1} respondents")
                why = (f"{len(common)} id{'s' if len(common) != 1 else ''} answered once in "
                       f"both groups, {short}: compared as independent samples")
            parts.append(f"{why}, though {_not_independent(shared, 'both groups')}"
                         + (" (--paired pairs them)" if paired is None and enough else ""))
        return None, "; ".join(parts)
    left = n0 + n1 - 2 * len(common)
    out = (f" and leaves out {left} of the {n0 + n1} respondents (in one group only, without "
           f"an id, or on more than one row of a group)" if left else "")
    parts.append(f"{len(common)} ids answered once in both groups (of {n0} respondents in "
                 f"{names[0]} and {n1} in {names[1]}){' (--paired)' if paired else ''}: the "
                 f"signed-rank test uses these {len(common)} pairs{out}")
    return (np.array([once[0][k] for k in common], dtype=np.int64),
            np.array([once[1][k] for k in common], dtype=np.int64)), "; ".join(parts)


def _not_independent(shared: int, where: str) -> str:
    """The note that some respondents answered in several of the compared groups."""
    return (f"{shared} id{'s appear' if shared != 1 else ' appears'} in {where}, so the "
            f"samples are not fully independent")


def _direction(first: str, second: str) -> str:
    """The sign convention of a two-group effect, in words."""
    return f"{second} vs {first}: positive when {second} answers higher"


def _test_item(item, samples, names, per, codes, a, pairs, min_size,
               trend=True) -> ItemComparison:
    """Test one item over the shown groups (``samples`` and ``names`` in group order),
    with more than two groups a trend over their order too when ``trend``.

    Two groups are compared second against first (Wilcoxon on post - pre, Mann-Whitney U
    of the second group, Cliff's delta of the second against the first), so that every
    signed number is positive when the second group answers higher.
    """
    usable = [(nm, s) for nm, s in zip(names, samples) if s.size]
    if len(usable) < 2:
        return ItemComparison(item, "none", None, None, "", None, per,
                              "fewer than two groups with answers to compare after suppression")
    silent = [nm for nm, s in zip(names, samples) if not s.size]
    note = (f"{', '.join(_quoted(nm) for nm in silent)} gave no answer to this item: the test "
            f"compares the other groups" if silent else "")
    names, usable = [u[0] for u in usable], [u[1] for u in usable]
    allx = np.concatenate(usable)
    if np.all(allx == allx[0]):
        return ItemComparison(item, "none", None, None, "", None, per, "every answer is the same")
    if pairs is not None:
        return _paired_item(item, per, names, codes, a, pairs, min_size)
    if len(usable) == 2:
        first, second = usable
        res = stats.mannwhitneyu(second, first, alternative="two-sided")
        return ItemComparison(item, "mann-whitney", float(res.statistic), float(res.pvalue),
                              "cliffs_delta", cliffs_delta(second, first), per, note,
                              direction=_direction(*names) + f"; U is {names[1]}'s")
    res = stats.kruskal(*usable)
    out = ItemComparison(item, "kruskal-wallis", float(res.statistic), float(res.pvalue),
                         "epsilon_squared", float(res.statistic / (allx.size - 1)), per, note,
                         direction="epsilon_squared has no sign")
    if trend:
        position = np.concatenate([np.full(s.size, k, dtype=float)
                                   for k, s in enumerate(usable)])
        rho = stats.spearmanr(position, allx)
        out.trend = {"rho": float(rho.statistic), "p_value": float(rho.pvalue),
                     "p_holm": None, "groups": names}
        out.direction = (f"trend rho positive when later groups in the order "
                         f"{' -> '.join(names)} answer higher; epsilon_squared has no sign")
    return out


def _paired_item(item, per, names, codes, a, pairs, min_size) -> ItemComparison:
    """The Wilcoxon signed-rank test of one item on the pairs that answered it both times
    (second group minus first); no test with fewer than ``min_size`` such pairs, or when
    every pair answered the same both times. Paired samples are never tested as
    independent ones."""
    both = (a[pairs[0]] >= 0) & (a[pairs[1]] >= 0)
    pre, post = codes[a[pairs[0][both]]], codes[a[pairs[1][both]]]
    n = int(both.sum())
    if n < min_size:
        return ItemComparison(item, "none", None, None, "", None, per,
                              f"{n} pair{'s' if n != 1 else ''} answered this item in both "
                              f"groups, fewer than {min_size}: too few for the paired test",
                              pairs=n)
    unchanged = int(np.sum(post == pre))
    if unchanged == n:
        return ItemComparison(item, "none", None, None, "", None, per,
                              f"each of the {n} pairs gave the same answer both times: no "
                              f"change to test", pairs=n, pairs_unchanged=unchanged)
    if n - unchanged < min_size:  # the test and the effect see only the pairs that changed
        return ItemComparison(item, "none", None, None, "", None, per,
                              f"{n - unchanged} of the {n} pairs changed their answer, fewer than "
                              f"{min_size}: too few for the paired test (it leaves the unchanged out)",
                              pairs=n, pairs_unchanged=unchanged)
    res = stats.wilcoxon(post, pre)       # two-sided: min(T+, T-), no sign
    return ItemComparison(item, "wilcoxon-signed-rank", float(res.statistic),
                          float(res.pvalue), "rank_biserial_paired",
                          rank_biserial_paired(post - pre), per, pairs=n,
                          pairs_unchanged=unchanged, direction=_direction(*names))


def _holm(items) -> str:
    """Holm-adjust the items' p-values, in two families: the tests across the groups, and
    the trends over the groups' order (a hypothesis of another kind, so adjusted on their
    own). Returns the sentence saying so ("" when no family has two p-values)."""
    from statsmodels.stats.multitest import multipletests
    said = []
    tested = [it for it in items if it.p_value is not None]
    if len(tested) >= 2:
        for it, p in zip(tested, multipletests([it.p_value for it in tested], method="holm")[1]):
            it.p_holm = float(p)
        said.append(f"the p-values of the {len(tested)} items tested are Holm-adjusted "
                    f"together")
    trends = [it for it in items if it.trend]
    if len(trends) >= 2:
        adjusted = multipletests([it.trend["p_value"] for it in trends], method="holm")[1]
        for it, p in zip(trends, adjusted):
            it.trend["p_holm"] = float(p)
        said.append(f"the {len(trends)} trend p-values as a family of their own")
    return "; ".join(said)
