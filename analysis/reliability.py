"""Internal consistency of items named as a scale: Cronbach's alpha with Feldt's interval.

pingouin (which offers ``cronbach_alpha``) is not installed in this project, so
alpha is computed here from its definition and the interval from the F
distribution in :mod:`scipy.stats`:

.. math::

    \\alpha = \\frac{k}{k-1}\\left(1 - \\frac{\\sum_i s_i^2}{s_T^2}\\right)

with k items, item variances :math:`s_i^2` and the variance :math:`s_T^2` of
respondents' total scores (sample variances, ddof = 1), on the respondents who
answered every item (listwise deletion; the number left out is reported).

Feldt (1965) interval at level :math:`1-\\gamma`, with n respondents,
:math:`d_1 = n-1`, :math:`d_2 = (n-1)(k-1)`:

.. math::

    \\left[\\,1 - (1-\\alpha)\\,F_{1-\\gamma/2}(d_1, d_2),\\;
           1 - (1-\\alpha)\\,F_{\\gamma/2}(d_1, d_2)\\,\\right]

References
----------
Cronbach, L. J. (1951). Coefficient alpha and the internal structure of tests.
Psychometrika 16, 297-334.
Feldt, L. S. (1965). The approximate sampling distribution of Kuder-Richardson
reliability coefficient twenty. Psychometrika 30, 357-370.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import stats

from .errors import SurveyInputError
from .ingest import SurveyData
from .likert import left_out_words
from .platforms import item_matches
from .respondents import PAIRING_UNKNOWN
from .rounding import number_text

__all__ = ["ReliabilityResult", "cronbach_alpha", "cronbach_alpha_for"]


@dataclass
class ReliabilityResult:
    """Cronbach's alpha of a set of items.

    Attributes
    ----------
    items : list of str
    alpha : float or None
        None when it is undefined (fewer than 2 complete respondents, or zero
        total-score variance); ``note`` says why.
    ci : (float, float) or (None, None)
        Feldt (1965) interval.
    n : int
        Respondents with every item answered (used).
    left_out : int
        Respondents left out for a blank or not-applicable answer.
    confidence_level : float
    note : str
    """

    items: list[str]
    alpha: float | None
    ci: tuple
    n: int
    left_out: int
    confidence_level: float
    note: str = ""

    def to_dict(self) -> dict:
        return {"items": list(self.items), "alpha": self.alpha, "ci": list(self.ci),
                "ci_method": "feldt1965", "confidence_level": self.confidence_level,
                "n": self.n, "left_out": self.left_out, "note": self.note}

    def format_text(self) -> str:
        if self.alpha is None:
            return f"Cronbach's alpha ({', '.join(self.items)}): undefined: {self.note}"
        a, lo, hi = (number_text(x, 3) for x in (self.alpha, *self.ci))
        return (f"Cronbach's alpha ({', '.join(self.items)}): {a} "
                f"[{lo}, {hi}] ({self.confidence_level:.0%} Feldt), "
                f"n = {self.n}, left out {self.left_out}" + (f"; {self.note}" if self.note else ""))

    def __repr__(self):
        a = "undefined" if self.alpha is None else f"{self.alpha:.4f}"
        return f"ReliabilityResult(alpha={a}, ci={self.ci}, n={self.n}, items={self.items})"


def _validate_alpha(scores, confidence_level):
    x = np.asarray(scores, dtype=float)
    if x.ndim != 2 or x.shape[1] < 2:
        raise ValueError(f"`scores` must be a 2-D array with at least two item columns, "
                         f"got shape {x.shape}")
    if not 0 < confidence_level < 1:
        raise ValueError(f"`confidence_level` must be in (0, 1), got {confidence_level!r}")
    return x


def cronbach_alpha(scores, confidence_level: float = 0.95, items=None) -> ReliabilityResult:
    """Cronbach's alpha and Feldt's interval from a respondents-by-items array.

    Parameters
    ----------
    scores : array_like, shape (respondents, items)
        Item codes; NaN marks a missing answer (the respondent is left out).
    confidence_level : float
    items : list of str, optional
        Item names for the result.

    Returns
    -------
    ReliabilityResult
    """
    x = _validate_alpha(scores, confidence_level)
    names = list(items) if items is not None else [f"item{j + 1}" for j in range(x.shape[1])]
    complete = ~np.isnan(x).any(axis=1)
    xc = x[complete]
    n, k = xc.shape
    left = int((~complete).sum())
    if n < 2:
        return ReliabilityResult(names, None, (None, None), n, left, confidence_level,
                                 "fewer than two respondents answered every item")
    item_var = xc.var(axis=0, ddof=1).sum()
    total_var = xc.sum(axis=1).var(ddof=1)
    if total_var == 0:
        return ReliabilityResult(names, None, (None, None), n, left, confidence_level,
                                 "total scores do not vary")
    alpha = k / (k - 1) * (1 - item_var / total_var)
    d1, d2 = n - 1, (n - 1) * (k - 1)
    g = 1 - confidence_level
    lo = 1 - (1 - alpha) * stats.f.ppf(1 - g / 2, d1, d2)
    hi = 1 - (1 - alpha) * stats.f.ppf(g / 2, d1, d2)
    return ReliabilityResult(names, float(alpha), (float(lo), float(hi)), n, left,
                             confidence_level)


def cronbach_alpha_for(data: SurveyData, items=None,
                       confidence_level: float = 0.95) -> ReliabilityResult:
    """Cronbach's alpha for items of a survey named as a scale (default: all items).

    Reverse-keyed items (``data.reverse``) enter with reversed codes. An item nobody
    answered (n = 0) is left out, with a note (it would leave out every respondent).

    Raises
    ------
    SurveyInputError
        An item name or pattern that matches no item, or fewer than two items.
    """
    if items:
        idx = []
        for pat in items:
            hits = [j for j, nm in enumerate(data.items) if item_matches(
                pat, nm, data.fields[j] if j < len(data.fields) else "")]
            if not hits:
                raise SurveyInputError(f"reliability item {pat!r} is not an item"
                                       f"{left_out_words(data.not_item_reasons, pat)}; items "
                                       f"are {data.items!r}", data.source)
            idx.extend(j for j in hits if j not in idx)
    else:
        idx = list(range(len(data.items)))
    if len(idx) < 2:
        raise SurveyInputError("Cronbach's alpha needs at least two items", data.source)
    unanswered = [data.items[j] for j in idx if not (data.answers[:, j] >= 0).any()]
    idx = [j for j in idx if data.items[j] not in unanswered]
    notes = [f"left out of alpha, as nobody answered {'it' if len(unanswered) == 1 else 'them'} "
             f"(n = 0): {', '.join(unanswered)}"] if unanswered else []
    if any(PAIRING_UNKNOWN in c for c in data.comments):
        notes.append("the file was rebuilt from per-item marginals: alpha describes an "
                     "arbitrary pairing of answers, not the respondents")
    if len(idx) < 2:
        return ReliabilityResult([data.items[j] for j in idx], None, (None, None), 0,
                                 data.respondents, confidence_level,
                                 "; ".join(["fewer than two items have answers"] + notes))
    cols = []
    for j in idx:
        rev = data.items[j] in data.reverse
        codes = np.array(data.scale.reversed_codes() if rev else data.scale.codes, dtype=float)
        a = data.answers[:, j]
        cols.append(np.where(a >= 0, codes[np.clip(a, 0, None)], np.nan))
    res = cronbach_alpha(np.column_stack(cols), confidence_level, [data.items[j] for j in idx])
    res.note = "; ".join(([res.note] if res.note else []) + notes)
    return res
