"""Claims about survey shares, stated in TOML and evaluated with honest uncertainty.

A claims file holds ``[[claims]]`` tables::

    [[claims]]
    id = "item2-usefulness"
    item = 2                        # 1-based position in questionnaire order, or a column header
    categories = ["Definitely Agree", "Partially Agree"]
    comparison = ">"                # one of >, >=, <, <=
    threshold = 90
    unit = "%"                      # "%" (0-100) or "fraction" (0-1)
    statement = "..."               # optional, shown in reports
    printed = "over 90%"            # optional, the wording as printed
    table_item = "#2"               # optional, the item's row label in the printed table
    decimals = 0                    # optional, decimals of the threshold as printed

Any other key (a typo such as ``comparision``) is refused, naming it and listing
the allowed keys, rather than silently replaced by a default. Positions start at
1: ``item = 0`` or a negative position is refused.

Verdicts (:data:`VERDICTS`)
---------------------------
``holds``
    The observed share satisfies the comparison *and* the whole confidence
    interval does (for ``>``/``>=`` its lower bound clears the threshold, for
    ``<``/``<=`` its upper bound); the reason names the bound.
``holds for this sample only``
    The observed share satisfies the comparison but the interval reaches the
    other side of the threshold: it describes these respondents, but the data
    cannot rule out a population share on the other side.
``does not hold``
    The observed share does not satisfy the comparison.
``cannot be evaluated: no valid answers``
    Nobody gave the item a valid answer (every answer blank or not applicable): there
    is no share to compare, so the claim neither holds nor fails.

:meth:`ClaimsReport.verdict_counts` counts the claims per verdict, each verdict its own
category.

Public API: :func:`load_claims`, :func:`evaluate_claims` (returns
:class:`ClaimsReport` with ``to_dict()``), :func:`evaluate_claim`.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from ._io import read_toml
from .errors import SurveyInputError
from .likert import (CI_METHODS, Proportion, SurveySummary, interval_label, left_out_words,
                     proportion)
from .rounding import number_text, share_percent_text, significant_text
from .scales import normalize_answer

__all__ = ["COMPARISONS", "VERDICTS", "Claim", "ClaimResult", "ClaimsReport", "load_claims",
           "evaluate_claim", "evaluate_claims"]

COMPARISONS = (">", ">=", "<", "<=")
#: Keys a ``[[claims]]`` table may hold.
CLAIM_KEYS = frozenset({"id", "item", "categories", "comparison", "threshold", "unit",
                        "statement", "printed", "table_item", "decimals"})
#: Most claims one file may hold.
MAX_CLAIMS = 1000


def _short(value) -> str:
    """``repr`` of a value from the file, cut to one short line."""
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."
#: verdict code -> wording
VERDICTS = {
    "holds": "holds (the whole interval clears the threshold)",
    "sample_only": "holds for this sample only",
    "does_not_hold": "does not hold",
    "no_answers": "cannot be evaluated: no valid answers",
}


@dataclass(frozen=True)
class Claim:
    """One claim: the share of ``item`` answering one of ``categories`` ``comparison`` ``threshold``.

    ``threshold`` is stored as a fraction (0-1); ``printed`` keeps the wording.
    """

    id: str
    item: "str | int"
    categories: tuple[str, ...]
    comparison: str
    threshold: float
    statement: str = ""
    printed: str = ""

    def to_dict(self) -> dict:
        return {"id": self.id, "item": self.item, "categories": list(self.categories),
                "comparison": self.comparison, "threshold": self.threshold,
                "statement": self.statement, "printed": self.printed}


@dataclass
class ClaimResult:
    """A claim checked against data.

    Attributes
    ----------
    claim : Claim
    item : str
        The item's column header.
    proportion : Proportion
        Respondents in the categories (``k``) out of valid answers (``n``), the
        share and its interval; ``k``, ``n``, ``share``, ``ci``, ``method`` and
        ``confidence_level`` are also available directly.
    verdict_code : {"holds", "sample_only", "does_not_hold", "no_answers"}
    verdict : str
        Wording from :data:`VERDICTS`.
    reason : str
    """

    claim: Claim
    item: str
    proportion: Proportion
    verdict_code: str
    verdict: str
    reason: str

    k = property(lambda self: self.proportion.k)
    n = property(lambda self: self.proportion.n)
    share = property(lambda self: self.proportion.share)
    ci = property(lambda self: self.proportion.ci)
    method = property(lambda self: self.proportion.method)
    confidence_level = property(lambda self: self.proportion.confidence_level)

    def explanation(self) -> str:
        """The verdict explained in words, the one text every report shows (report.html, the paper,
        ``analysis report``): counts, the share and interval bounds in percent by the one rounding rule
        (:mod:`analysis.rounding`), and what the interval means for the claim."""
        c, n = self.claim, self.n
        if self.share is None:
            return f"Cannot be evaluated: {self.reason}."
        words = {">": "over", ">=": "at least", "<": "under", "<=": "at most"}[c.comparison]
        threshold, share = f"{words} {100 * c.threshold:g}%", f"{self.k}/{n} = {self.proportion.percent_text(1)}%"
        label = interval_label(self.confidence_level, self.method)
        bounds = f"{share_percent_text(self.ci[0])}% to {share_percent_text(self.ci[1])}%"
        if self.verdict_code == "does_not_hold":
            return f"Does not hold: {share} of those who answered is not {threshold} ({label}: {bounds})."
        if self.verdict_code == "holds":
            return (f"Holds: {share} of those who answered, {threshold}, and the whole {label} "
                    f"({bounds}) is {threshold}, so the data support the claim beyond these "
                    "respondents too.")
        side = "below" if c.comparison in (">", ">=") else "above"
        return (f"Holds for this sample only: {share} of those who answered, {threshold}; but the {label} "
                f"({bounds}) reaches {side} {100 * c.threshold:g}%, so with {n} answers the data cannot show that "
                f"the share among students in general is {threshold}.")

    def to_dict(self) -> dict:
        return {"id": self.claim.id, "item": self.item, "categories": list(self.claim.categories),
                "comparison": self.claim.comparison, "threshold": self.claim.threshold,
                "printed": self.claim.printed, "statement": self.claim.statement,
                "k": self.k, "n": self.n, "share": self.share, "ci": list(self.ci),
                "ci_method": self.method, "confidence_level": self.confidence_level,
                "verdict": self.verdict, "verdict_code": self.verdict_code,
                "reason": self.reason}


@dataclass
class ClaimsReport:
    """All claims of one file checked against one survey."""

    results: list[ClaimResult]
    source: str
    claims_file: str
    respondents: int
    method: str = "wilson"
    confidence_level: float = 0.95
    extra: dict = field(default_factory=dict)

    def to_dict(self) -> dict:
        """``claims --json`` shape: ``{"source", "claims_file", "respondents", "claims": [...]}``."""
        return {"source": self.source, "claims_file": self.claims_file,
                "respondents": self.respondents, "ci_method": self.method,
                "confidence_level": self.confidence_level,
                "verdict_counts": self.verdict_counts(),
                "claims": [r.to_dict() for r in self.results]}

    def verdict_counts(self) -> dict:
        """Claims per verdict code (every code of :data:`VERDICTS`, zeros included)."""
        counts = dict.fromkeys(VERDICTS, 0)
        for r in self.results:
            counts[r.verdict_code] += 1
        return counts

    def format_text(self) -> str:
        out = [f"{self.source}: claims from {self.claims_file} "
               f"({self.confidence_level:.0%} {self.method} intervals)"]
        for r in self.results:
            share = "n/a" if r.share is None else f"{r.proportion.percent_text(1)}%"
            ci = "" if r.share is None else f" [{share_percent_text(r.ci[0])}%, {share_percent_text(r.ci[1])}%]"
            out.append(f"  {r.claim.id}: {r.item} share {r.k}/{r.n} = {share}{ci} "
                       f"{r.claim.comparison} {100 * r.claim.threshold:g}%: {r.verdict}")
        counts = self.verdict_counts()
        out.append(f"  {len(self.results)} claim{'s' if len(self.results) != 1 else ''}: "
                   + ", ".join(f"{counts[c]} {VERDICTS[c].split(' (')[0]}" for c in VERDICTS))
        return "\n".join(out)


def load_claims(path: "str | Path") -> list[Claim]:
    """Read a claims TOML file (see the module docstring).

    Raises
    ------
    SurveyInputError
        Missing file, TOML error, or a bad key (named as ``claims[i].key``).
    """
    p = Path(path)
    src = str(p)
    data = read_toml(p)
    unknown = sorted(set(data) - {"claims"})
    if unknown:
        raise SurveyInputError(f"unknown key {unknown[0]!r}; the file holds [[claims]] tables "
                               f"only", src)
    entries = data.get("claims")
    if not isinstance(entries, list) or not entries:
        raise SurveyInputError("key 'claims': needs at least one [[claims]] table", src)
    if len(entries) > MAX_CLAIMS:
        raise SurveyInputError(f"key 'claims': {len(entries)} claims; at most {MAX_CLAIMS}", src)
    out = []
    for i, e in enumerate(entries):
        where = f"claims[{i}]"
        if not isinstance(e, dict):
            raise SurveyInputError(f"key '{where}': must be a [[claims]] table, got "
                                   f"{_short(e)}", src)
        extra = sorted(set(e) - CLAIM_KEYS)
        if extra:
            raise SurveyInputError(f"key '{where}.{extra[0]}': unknown key; allowed: "
                                   f"{sorted(CLAIM_KEYS)}", src)

        def bad(key, what):
            return SurveyInputError(f"key '{where}.{key}': {what}", src)
        item = e.get("item")
        if isinstance(item, bool) or not isinstance(item, (int, str)) or item == "":
            raise bad("item", f"must be a column header or a 1-based position, "
                              f"got {_short(item)}")
        if isinstance(item, int) and item < 1:
            raise bad("item", f"positions start at 1 (the first item), got {item}")
        cats = e.get("categories")
        if not isinstance(cats, list) or not cats or not all(isinstance(c, str) for c in cats):
            raise bad("categories", "must be a non-empty list of answer labels")
        comp = e.get("comparison", ">")
        if comp not in COMPARISONS:
            raise bad("comparison", f"must be one of {list(COMPARISONS)}, got {_short(comp)}")
        thr = e.get("threshold")
        if isinstance(thr, bool) or not isinstance(thr, (int, float)):
            raise bad("threshold", f"must be a number, got {_short(thr)}")
        unit = e.get("unit", "%")
        if unit not in ("%", "fraction"):
            raise bad("unit", f"must be one of ['%', 'fraction'], got {_short(unit)}")
        try:
            frac = float(thr) / 100 if unit == "%" else float(thr)
        except OverflowError:            # an integer past the float range
            frac = float("inf")
        if not 0 <= frac <= 1:
            raise bad("threshold", f"must lie in 0..100 % (0..1 as a fraction), "
                                   f"got {_short(thr)}")
        out.append(Claim(id=str(e.get("id", f"claim{i + 1}")), item=item,
                         categories=tuple(cats), comparison=comp, threshold=float(frac),
                         statement=str(e.get("statement", "")), printed=str(e.get("printed", ""))))
    return out


def _satisfies(x: float, comparison: str, threshold: float) -> bool:
    return {">": x > threshold, ">=": x >= threshold,
            "<": x < threshold, "<=": x <= threshold}[comparison]


def evaluate_claim(claim: Claim, summary: SurveySummary, confidence_level: float = 0.95,
                   method: str = "wilson", source: str = "<claims>") -> ClaimResult:
    """Evaluate one claim against a survey summary.

    Raises
    ------
    SurveyInputError
        The claim names an item or a category the survey does not have.
    """
    if method not in CI_METHODS:
        raise ValueError(f"`method` must be one of {list(CI_METHODS)}, got {method!r}")
    try:
        it = summary.item(claim.item)
    except (KeyError, IndexError):
        raise SurveyInputError(
            f"claim {claim.id!r}: no item {claim.item!r}"
            f"{left_out_words(summary.not_item_reasons, claim.item)}; items are "
            f"{[i.item for i in summary.items]} (or positions 1..{len(summary.items)})",
            source) from None
    keys = {normalize_answer(lab): lab for lab in it.labels}
    k, seen = 0, set()
    for cat in claim.categories:
        lab = keys.get(normalize_answer(cat))
        if lab is None and summary.scale is not None:     # an alias ("Neutral") as answers
            m = summary.scale.match(cat, accept_codes=False)
            lab = it.labels[m] if m is not None and m >= 0 else None
        if lab is None:
            raise SurveyInputError(f"claim {claim.id!r}: category {cat!r} is not a label; "
                                   f"labels are {it.labels}", source)
        if lab in seen:                  # counting it twice would inflate the share
            raise SurveyInputError(f"claim {claim.id!r}: category {cat!r} is listed twice "
                                   f"(as {lab!r})", source)
        seen.add(lab)
        k += it.counts[lab]
    p = proportion(k, it.n, confidence_level, method)
    if p.share is None:
        code = "no_answers"
        reason = (f"no valid answers to this item ({it.missing} missing, {it.excluded} not "
                  f"applicable): there is no share to compare with the threshold")
    elif not _satisfies(p.share, claim.comparison, claim.threshold):
        code = "does_not_hold"
        reason = (f"observed share {number_text(p.share, 4)} is not {claim.comparison} "
                  f"{significant_text(claim.threshold, 6)}")
    else:
        bound = p.ci[0] if claim.comparison in (">", ">=") else p.ci[1]
        side = "lower" if claim.comparison in (">", ">=") else "upper"
        if _satisfies(bound, claim.comparison, claim.threshold):
            code = "holds"
            reason = (f"the interval's {side} bound {number_text(bound, 4)} clears "
                      f"{significant_text(claim.threshold)}")
        else:
            code = "sample_only"
            reason = (f"observed share {number_text(p.share, 4)} {claim.comparison} "
                      f"{significant_text(claim.threshold)}, but the interval's {side} bound "
                      f"{number_text(bound, 4)} does not clear it")
    return ClaimResult(claim=claim, item=it.item, proportion=p, verdict_code=code,
                       verdict=VERDICTS[code], reason=reason)


def evaluate_claims(claims: "list[Claim] | str | Path", summary: SurveySummary,
                    confidence_level: float = 0.95, method: str = "wilson",
                    claims_file: "str | None" = None) -> ClaimsReport:
    """Evaluate every claim (a list, or a claims TOML file) against a survey summary.

    ``claims_file`` names the file a list of claims was read from (for messages).

    Returns
    -------
    ClaimsReport
    """
    src = str(claims_file) if claims_file else "<claims>"
    if isinstance(claims, (str, Path)):
        src = str(claims)
        claims = load_claims(claims)
    results = [evaluate_claim(c, summary, confidence_level, method, src) for c in claims]
    return ClaimsReport(results=results, source=summary.source, claims_file=src,
                        respondents=summary.respondents, method=method,
                        confidence_level=confidence_level)
