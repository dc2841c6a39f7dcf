"""Per-item summaries of Likert answers (the paper's Table 1 for any class).

For every item: counts and percentages per answer label, the valid n, blank
(missing) and not-applicable (excluded) answers, the agreement (top box),
neutral and disagreement shares with confidence intervals, and the median and
interquartile range of the codes. Mean and standard deviation of the codes are
given only as a labelled extra (the codes are ordinal).

Invariant, per item: ``n + missing + excluded == respondents``.

Percentages and rounding
------------------------
``percent`` holds exact shares of the valid n, ``100 * count / n``. Printed
percentages (:meth:`ItemSummary.printed_percent`) are rounded to ``decimals``
places *half away from zero* (:func:`analysis.rounding.round_fraction`), computed on exact fractions (so 45/2 prints 22.5
at 0 decimals as 23, not as Python's banker's 22). With
``method="largest_remainder"`` (Hamilton's method) each row is made to add up to
exactly 100: every share is first cut down to ``decimals`` places, then the
missing units go, one each, to the labels with the largest remainders (ties to
the label printed first).

Intervals
---------
``method="wilson"`` (default, Wilson 1927) is computed here in closed form, with the
formula and operation order of :func:`statsmodels.stats.proportion.proportion_confint`
and the normal quantile of :class:`statistics.NormalDist` (no scipy import, which
would cost more than reading a large file); ``"beta"`` (Clopper-Pearson exact) comes
from ``proportion_confint``.

Public API
----------
:func:`summarize` (a :class:`~analysis.ingest.SurveyData`),
:func:`summarize_dataframe` (a DataFrame of answer text), :func:`proportion`;
results :class:`SurveySummary`, :class:`ItemSummary`, :class:`Proportion`, each with
``to_dict()``. ``SurveySummary.to_dict()`` is the ``summarize --json`` shape.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from fractions import Fraction

import numpy as np

from .disclosure import respondents_text
from .rounding import (largest_remainder, largest_remainder_tie, number_text, percent_text, quartile_texts,
                       round_fraction, share_percent_text)

__all__ = ["CI_METHODS", "PERCENT_METHODS", "absent_respondents", "Proportion", "ItemSummary", "SurveySummary",
           "proportion", "summarize", "summarize_dataframe"]

#: Valid interval methods (statsmodels names): Wilson score, Clopper-Pearson.
CI_METHODS = ("wilson", "beta")
#: Valid printed-percentage methods.
PERCENT_METHODS = ("round", "largest_remainder")
#: Names of the interval methods as printed.
CI_NAMES = {"wilson": "Wilson", "beta": "Clopper-Pearson"}
#: Printed after a reverse-keyed item's name, explained by :data:`REVERSE_NOTE`.
REVERSE_MARK = " (R)"
REVERSE_NOTE = ("(R) reverse-keyed item: counts, percentages and agreement are the answers as "
                "given (raw, not reversed); median, IQR, mean and SD use the reversed codes")
#: The statistics a reverse-keyed item gives on reversed codes (counts stay raw).
REVERSED_STATISTICS = ("median", "iqr", "mean", "sd")


def interval_label(confidence_level: float, method: str) -> str:
    """The interval as printed, e.g. ``"95% Wilson interval"``."""
    return f"{100 * confidence_level:.10g}% {CI_NAMES[method]} interval"


def absent_respondents(declared: "int | None", have: int, source: str) -> int:
    """Respondents declared (``--respondents``) but absent from the file (0 if none declared).

    They are counted as missing on every item, so that the invariant
    ``n + missing + excluded == respondents`` holds for the declared number.

    Raises
    ------
    SurveyInputError
        Fewer respondents declared than the file holds.
    """
    if declared is None:
        return 0
    if declared < have:
        from .errors import SurveyInputError
        raise SurveyInputError(f"{declared} respondents declared, but the file holds {have} "
                               f"responses", source)
    return declared - have


def _validate_ci(method, confidence_level):
    if method not in CI_METHODS:
        raise ValueError(f"`method` must be one of {list(CI_METHODS)}, got {method!r}")
    if not (0 < confidence_level < 1):
        raise ValueError(f"`confidence_level` must be in (0, 1), got {confidence_level!r}")


@dataclass(frozen=True)
class Proportion:
    """k successes out of n, with a confidence interval.

    Attributes
    ----------
    k, n : int
    share : float or None
        k / n (None when n == 0).
    ci : (float, float) or (None, None)
        Interval at ``confidence_level`` by ``method``.
    method : str
        ``"wilson"`` or ``"beta"`` (Clopper-Pearson).
    confidence_level : float
    """

    k: int
    n: int
    share: float | None
    ci: tuple
    method: str
    confidence_level: float

    def confidence_interval(self, confidence_level: float = 0.95,
                            method: str = "wilson") -> tuple[float, float]:
        """Interval for the share at another level or by another method."""
        return proportion(self.k, self.n, confidence_level, method).ci

    def percent_text(self, decimals: int = 1) -> str:
        """The share in percent as printed: the exact ``100 k / n`` rounded half away from
        zero (the rule of :meth:`ItemSummary.printed_percent`, so 5/16 prints 31.3 both as
        a category and as a share); ``"-"`` when n == 0."""
        if self.n == 0:
            return "-"
        return percent_text(self.k, self.n, decimals)

    def to_dict(self) -> dict:
        return {"share": self.share, "ci": list(self.ci)}

    def __repr__(self):
        if self.share is None:
            return f"Proportion({self.k}/{self.n})"
        return (f"Proportion({self.k}/{self.n} = {self.share:.4f}, "
                f"{self.confidence_level:.0%} {self.method} CI [{self.ci[0]:.4f}, {self.ci[1]:.4f}])")


def proportion(k: int, n: int, confidence_level: float = 0.95,
               method: str = "wilson") -> Proportion:
    """Share k/n with its confidence interval (statsmodels ``proportion_confint``).

    Parameters
    ----------
    k, n : int
        Successes and trials (0 <= k <= n).
    confidence_level : float
        E.g. 0.95.
    method : {"wilson", "beta"}
        Wilson score interval or Clopper-Pearson ("beta").

    Returns
    -------
    Proportion
    """
    _validate_ci(method, confidence_level)
    k, n = int(k), int(n)
    if n < 0 or k < 0 or k > n:
        raise ValueError(f"need 0 <= k <= n, got k={k}, n={n}")
    if n == 0:
        return Proportion(0, 0, None, (None, None), method, confidence_level)
    if method == "wilson":
        lo, hi = _wilson(k, n, 1 - confidence_level)
    else:
        from statsmodels.stats.proportion import proportion_confint   # heavy: only when used
        lo, hi = proportion_confint(k, n, alpha=1 - confidence_level, method=method)
    # the bounds are exact at the ends; clear floating-point dust (e.g. 5e-17 for k = 0)
    lo = 0.0 if k == 0 else min(max(float(lo), 0.0), 1.0)
    hi = 1.0 if k == n else min(max(float(hi), 0.0), 1.0)
    return Proportion(k, n, k / n, (float(lo), float(hi)), method, confidence_level)


def _wilson(k: int, n: int, alpha: float) -> tuple[float, float]:
    """Wilson score interval (statsmodels' formula: centre and half-width over 1 + z^2/n)."""
    from statistics import NormalDist
    crit = NormalDist().inv_cdf(1 - alpha / 2)
    q = k / n
    crit2 = crit ** 2
    denom = 1 + crit2 / n
    center = (q + crit2 / (2 * n)) / denom
    dist = crit * math.sqrt(q * (1.0 - q) / n + crit2 / (4.0 * n ** 2)) / denom
    return center - dist, center + dist


def _weighted_quantile(codes: np.ndarray, counts: np.ndarray, q: float) -> float | None:
    """numpy's default (linear) quantile of the values ``codes`` repeated ``counts`` times."""
    n = int(counts.sum())
    if n == 0:
        return None
    order = np.argsort(codes)
    v, c = codes[order], counts[order]
    cum = np.cumsum(c)
    h = (n - 1) * q
    lo, hi = math.floor(h), math.ceil(h)
    vlo = v[np.searchsorted(cum, lo + 1)]
    vhi = v[np.searchsorted(cum, hi + 1)]
    return float(vlo + (h - lo) * (vhi - vlo))


@dataclass
class ItemSummary:
    """Summary of one item.

    Attributes
    ----------
    item : str
        Column header.
    text : str
        Question text (when the export carries it; else the header).
    labels : list of str
        Scale labels in questionnaire order.
    counts : dict of str to int
        Answers per label.
    n : int
        Valid answers (sum of counts).
    missing : int
        Blank answers (and unknown answers counted as missing).
    excluded : int
        Not-applicable answers.
    respondents : int
    percent : dict of str to float
        Exact ``100 * count / n`` (0-100); None for every label when n == 0 (no percent
        of nobody: JSON ``null``, printed "-", as the agreement share).
    agree, neutral, disagree : Proportion
        Shares of n answering a positive / neutral / negative label.
    median, q1, q3 : float or None
        Of the codes (reverse-keyed items use reversed codes).
    mean, sd : float or None
        Extra, labelled: mean and sample sd of the codes (ordinal data!).
    reverse : bool
        Item is reverse-keyed.
    unknown : int
        Unknown answers counted as missing.
    stem : str
        Question stem of a grid/matrix item ("" for a single question).
    """

    item: str
    text: str
    labels: list[str]
    counts: dict[str, int]
    n: int
    missing: int
    excluded: int
    respondents: int
    percent: dict[str, "float | None"]
    agree: Proportion
    neutral: Proportion
    disagree: Proportion
    median: float | None
    q1: float | None
    q3: float | None
    mean: float | None
    sd: float | None
    reverse: bool = False
    unknown: int = 0
    stem: str = ""
    field: str = ""              # the export's field id (Q1_4), also naming the item

    @property
    def iqr(self) -> float | None:
        """Interquartile range of the codes, q3 - q1."""
        return None if self.q1 is None else self.q3 - self.q1

    def printed_percent(self, decimals: int = 1, method: str = "round") -> dict:
        """Percentages as they would be printed (None for every label when n == 0).

        Parameters
        ----------
        decimals : int
            Places after the decimal point.
        method : {"round", "largest_remainder"}
            Round each cell half away from zero, or make the row add up to 100.
        """
        if method not in PERCENT_METHODS:
            raise ValueError(f"`method` must be one of {list(PERCENT_METHODS)}, got {method!r}")
        if isinstance(decimals, bool) or not isinstance(decimals, int) or not 0 <= decimals <= 6:
            raise ValueError(f"`decimals` must be an integer 0..6, got {decimals!r}")
        cs = [self.counts[lab] for lab in self.labels]
        if self.n == 0:
            return {lab: None for lab in self.labels}
        if method == "round":
            vals = [round_fraction(Fraction(100 * c, self.n), decimals, "half_away") for c in cs]
        else:
            vals = largest_remainder(cs, decimals)
        return {lab: float(v) for lab, v in zip(self.labels, vals)}

    def rounding_tie(self, decimals: int = 1) -> str:
        """How largest-remainder rounding of this item broke a tie between equal remainders, or ``""``
        (:func:`analysis.rounding.largest_remainder_tie`)."""
        return largest_remainder_tie(list(self.labels), [self.counts[lab] for lab in self.labels], decimals)

    def to_dict(self) -> dict:
        """The ``summarize --json`` item (plus ``excluded`` for the invariant)."""
        return {"item": self.item, "reversed": self.reverse,
                "reversed_statistics": self.reversed_statistics, "n": self.n,
                "missing": self.missing, "excluded": self.excluded, "counts": dict(self.counts),
                "percent": dict(self.percent), "agree": self.agree.to_dict(),
                "median": self.median, "iqr": self.iqr, "mean": self.mean, "sd": self.sd}

    @property
    def reversed_statistics(self) -> list:
        """The statistics given on reversed codes (none unless reverse-keyed; counts,
        percentages and shares are always of the answers as given)."""
        return list(REVERSED_STATISTICS) if self.reverse else []

    def to_full_dict(self) -> dict:
        d = self.to_dict()
        d.update(text=self.text, stem=self.stem, respondents=self.respondents,
                 neutral=self.neutral.to_dict(), disagree=self.disagree.to_dict(),
                 ci_method=self.agree.method, median=self.median, q1=self.q1, q3=self.q3,
                 iqr=self.iqr, extra_mean_of_codes=self.mean, extra_sd_of_codes=self.sd,
                 reverse=self.reverse, unknown_as_missing=self.unknown)
        return d

    def __repr__(self):
        cs = ", ".join(f"{k}={v}" for k, v in self.counts.items())
        return (f"ItemSummary({self.item!r}, n={self.n}, missing={self.missing}, "
                f"excluded={self.excluded}, {cs})")


@dataclass
class SurveySummary:
    """Summaries of every item of one survey.

    Attributes
    ----------
    respondents : int
    items : list of ItemSummary
    scale : Scale
    source, shape : str
    unknown_answers, dropped : list
        Reports from reading (see :class:`~analysis.ingest.SurveyData`).
    ci_method : str
    confidence_level : float
    """

    respondents: int
    items: list[ItemSummary]
    scale: object
    source: str
    shape: str
    unknown_answers: list = field(default_factory=list)
    dropped: list = field(default_factory=list)
    ci_method: str = "wilson"
    confidence_level: float = 0.95
    other_columns: list = field(default_factory=list)
    not_item_reasons: dict = field(default_factory=dict)

    def item(self, name: "str | int") -> ItemSummary:
        """An item by header (any case) or 1-based position."""
        if isinstance(name, int) and not isinstance(name, bool):
            if not 1 <= name <= len(self.items):      # 0 and -1 must not index from the end
                raise IndexError(f"item position {name} out of range 1..{len(self.items)}")
            return self.items[name - 1]
        key = str(name).strip().casefold()
        for it in self.items:
            if it.item.strip().casefold() == key:
                return it
        for it in self.items:               # else by its export field id, as --items
            if it.field and it.field.strip().casefold() == key:
                return it
        raise KeyError(f"no item {name!r}; items are {[i.item for i in self.items]}")

    def to_frame(self):
        """One row per item as a pandas DataFrame (see :func:`analysis.export.summary_frame`)."""
        from .export import summary_frame
        return summary_frame(self)

    def to_dict(self) -> dict:
        """The ``summarize --json`` shape.

        ``{"respondents": int, "items": [...], "not_items": [str], "not_item_reasons": {str: str},
        "dropped": [{"row", "reason"}], "unknown_answers": [{"row", "column", "value"}]}``: every
        column left out of the table (with why, as the ``--by`` route gives it) and every row or
        answer not counted is listed, as the text output lists them. Each item says whether it is ``reversed`` and which
        statistics use reversed codes (``reversed_statistics``; counts stay raw);
        ``reverse_note`` says so in words when an item is reversed.
        """
        note = REVERSE_NOTE if any(i.reverse for i in self.items) else ""
        return {"respondents": self.respondents, "ci_method": self.ci_method,
                "confidence_level": self.confidence_level, "reverse_note": note,
                "items": [i.to_dict() for i in self.items],
                "not_items": list(self.other_columns),
                "not_item_reasons": {c: self.not_item_reasons.get(c, "") for c in self.other_columns},
                "dropped": [vars(d) for d in self.dropped],
                "unknown_answers": [vars(u) for u in self.unknown_answers]}

    def to_full_dict(self) -> dict:
        return {"respondents": self.respondents, "source": self.source, "shape": self.shape,
                "scale": self.scale.to_dict(), "ci_method": self.ci_method,
                "confidence_level": self.confidence_level,
                "items": [i.to_full_dict() for i in self.items],
                "unknown_answers": [vars(u) for u in self.unknown_answers],
                "dropped": [vars(d) for d in self.dropped],
                "other_columns": list(self.other_columns)}

    def format_text(self, decimals: int = 1, method: str = "round") -> str:
        """Plain-text Table 1 with n, missing and the agreement interval."""
        labels = list(self.scale.labels)
        out = [f"{self.source}: {respondents_text(self.respondents)}, scale {self.scale.name!r}, "
               f"shape {self.shape}"]
        width = max([len(_name(i)) for i in self.items] + [4])
        cw = max([len(lab) for lab in labels] + [14])
        head = f"{'item':<{width}}  " + "  ".join(f"{lab:>{cw}}" for lab in labels)
        # count columns as wide as the largest count (10 million respondents: 8 digits)
        nw = max([5] + [len(str(v)) for i in self.items for v in (i.n, i.missing, i.excluded)])
        out.append(head + f"  {'n':>{nw}} {'miss':>{nw}} {'n/a':>{nw}}  {'median':>6} {'IQR':>5} "
                   f"{'mean':>5} {'SD':>5}  agree "
                   f"[{interval_label(self.confidence_level, self.ci_method)}]")
        stem = ""
        for it in self.items:
            if it.stem and it.stem != stem:
                out.append(f"{it.stem}")         # a grid's question, once above its rows
            stem = it.stem
            pp = it.printed_percent(decimals, method)
            cells = "  ".join(f"{(f'{pp[lab]:.{decimals}f}%' if it.n else '-') + f' ({it.counts[lab]})':>{cw}}"
                              for lab in labels)           # no percent of nobody
            ag = it.agree
            agree = ("-" if ag.share is None else
                     f"{ag.percent_text(decimals)}% [{share_percent_text(ag.ci[0], decimals)}%, "
                     f"{share_percent_text(ag.ci[1], decimals)}%]")
            out.append(f"{_name(it):<{width}}  {cells}  {it.n:>{nw}} {it.missing:>{nw}} "
                       f"{it.excluded:>{nw}}  {number_text(it.median):>6} {quartile_texts(it.q1, it.q3)[0]:>5} "
                       f"{number_text(it.mean, 2):>5} {number_text(it.sd, 2):>5}  {agree}")
        if any(it.reverse for it in self.items):
            out.append(REVERSE_NOTE)
        if method == "largest_remainder":  # a tie the rounded row depends on is stated
            out += [f"{_name(it)}: {it.rounding_tie(decimals)}" for it in self.items if it.rounding_tie(decimals)]
        for d in self.dropped:
            out.append(f"dropped row {d.row}: {d.reason}")
        if self.other_columns:
            out.append(not_items_text({c: self.not_item_reasons.get(c, "")
                                       for c in self.other_columns}))
        return "\n".join(out)


def not_items_text(reasons: dict) -> str:
    """The line listing the columns left out of the table, each with its reason (both
    routes)."""
    return "not items (left out of the table): " + ", ".join(
        f"{name} ({why})" if why else name for name, why in reasons.items())


def left_out_words(reasons: dict, name) -> str:
    """``" (left out of the table: REASON)"`` when ``name`` (any case and spacing) is a
    column left out with a reason, else ``""``: a refusal naming an item that is not one
    says why (claims, ``--reliability``)."""
    from .scales import normalize_answer
    key = normalize_answer(str(name))
    why = next((r for c, r in reasons.items() if normalize_answer(c) == key and r), "")
    return f" (left out of the table: {why})" if why else ""


def _name(it: ItemSummary) -> str:
    """An item's name as printed, marked when reverse-keyed."""
    return it.item + (REVERSE_MARK if it.reverse else "")


def _validate_summarize(data, confidence_level, method):
    from .ingest import SurveyData
    if not isinstance(data, SurveyData):
        raise TypeError(f"`data` must be SurveyData, got {type(data).__name__}")
    _validate_ci(method, confidence_level)


def summarize(data: SurveyData, confidence_level: float = 0.95,
              method: str = "wilson") -> SurveySummary:
    """Summarise every item of a survey.

    Parameters
    ----------
    data : SurveyData
        From :func:`~analysis.ingest.read_survey` or :func:`~analysis.ingest.survey_from_frame`.
    confidence_level : float
        Level of the share intervals.
    method : {"wilson", "beta"}
        Interval method (statsmodels ``proportion_confint``).

    Returns
    -------
    SurveySummary
    """
    _validate_summarize(data, confidence_level, method)
    scale = data.scale
    out = []
    for j, name in enumerate(data.items):
        tally = _tally(data.answers[:, j], scale.k)
        out.append(summarize_tally(
            tally, scale, name, text=data.item_texts[j], respondents=data.respondents,
            reverse=name in data.reverse, stem=data.stems[j] if j < len(data.stems) else "",
            confidence_level=confidence_level, method=method))
        out[-1].field = data.fields[j] if j < len(data.fields) else ""
    return SurveySummary(respondents=data.respondents, items=out, scale=scale,
                         source=data.source, shape=data.shape,
                         unknown_answers=list(data.unknown_answers), dropped=list(data.dropped),
                         ci_method=method, confidence_level=confidence_level,
                         other_columns=list(data.other_columns),
                         not_item_reasons=dict(data.not_item_reasons))


def _tally(col: np.ndarray, k: int) -> np.ndarray:
    """Counts of the codes -3..k-1 of one int8 answer column, shifted to 0..k+2.

    One pass without a copy: the int8 codes are read as uint8 (-3..-1 become 253..255).
    """
    t = np.bincount(np.ascontiguousarray(col).view(np.uint8), minlength=256)
    return np.concatenate([t[253:256], t[:k]])


def summarize_tally(tally, scale, name: str, text: str = "", respondents: "int | None" = None,
                    reverse: bool = False, stem: str = "", confidence_level: float = 0.95,
                    method: str = "wilson") -> ItemSummary:
    """One item's summary from its tally (the one route to every item's numbers).

    Parameters
    ----------
    tally : array of int, length ``scale.k + 3``
        Answers per code shifted by 3: unknown (counted missing), not applicable,
        blank, then one count per label in scale order.
    scale : Scale
    name, text, stem : str
    respondents : int, optional
        Default: the tally's total.
    reverse : bool
        Reverse-keyed (reversed codes for median, quartiles, mean, SD).
    """
    from .scales import BLANK, NOT_APPLICABLE, UNKNOWN
    tally = np.asarray(tally, dtype=np.int64)
    k = scale.k
    labels = list(scale.labels)
    pos = [labels.index(x) for x in scale.positive]
    neu = [labels.index(x) for x in scale.neutral]
    neg = [labels.index(x) for x in scale.negative]
    unknown = int(tally[UNKNOWN + 3])
    excluded = int(tally[NOT_APPLICABLE + 3])
    missing = int(tally[BLANK + 3]) + unknown
    cnt = tally[3:3 + k]
    n = int(cnt.sum())
    counts = {lab: int(c) for lab, c in zip(labels, cnt)}
    percent = {lab: (100.0 * int(c) / n if n else None) for lab, c in zip(labels, cnt)}
    rev = reverse
    codes = np.array(scale.reversed_codes() if rev else scale.codes, dtype=float)
    median = _weighted_quantile(codes, cnt, 0.5)
    q1 = _weighted_quantile(codes, cnt, 0.25)
    q3 = _weighted_quantile(codes, cnt, 0.75)
    if n:
        mean = float((codes * cnt).sum() / n)
        sd = float(math.sqrt(((codes - mean) ** 2 * cnt).sum() / (n - 1))) if n > 1 else None
    else:
        mean = sd = None
    return ItemSummary(
        item=name, text=text or name, labels=labels, counts=counts, n=n,
        missing=missing, excluded=excluded,
        respondents=int(tally.sum()) if respondents is None else int(respondents),
        percent=percent,
        agree=proportion(int(cnt[pos].sum()), n, confidence_level, method),
        neutral=proportion(int(cnt[neu].sum()), n, confidence_level, method),
        disagree=proportion(int(cnt[neg].sum()), n, confidence_level, method),
        median=median, q1=q1, q3=q3, mean=mean, sd=sd, reverse=rev, unknown=unknown, stem=stem)


def summarize_dataframe(df, scale=None, items=None, shape: str = "auto",
                        unknown: str = "error", confidence_level: float = 0.95,
                        method: str = "wilson", **kwargs) -> SurveySummary:
    """Summarise a DataFrame of answer text (see :func:`~analysis.ingest.survey_from_frame`)."""
    from .ingest import survey_from_frame
    data = survey_from_frame(df, scale=scale, items=items, shape=shape, unknown=unknown, **kwargs)
    return summarize(data, confidence_level, method)
