"""Response scales: ordered answer labels with numeric codes.

A :class:`Scale` lists its labels in questionnaire order, gives each a numeric
code, and says which labels count as agreeing (``positive``), neutral and
disagreeing (``negative``). Answers such as "Not applicable" are neither: they
are *excluded* from every denominator and reported apart.

Built-in scales (:data:`BUILTIN_SCALES`): ``paper`` (the five-point scale of the
paper's questionnaire, Definitely Agree ... Definitely Disagree), ``agree5``
(Strongly disagree ... Strongly agree), ``agree5-somewhat`` (with "Somewhat"),
``agree7``, the four-point ``agree4`` (Strongly disagree, Disagree, Agree, Strongly
agree) and ``frequency4`` (Never, Sometimes, Often, Always), ``frequency5`` and
``satisfaction5``. When no scale is named, the
built-in scale whose labels every item column uses is chosen (the best label
match, then the fewest labels, then this order). Custom scales come from a small
TOML file (:func:`load_scale`)::

    name = "confidence4"
    labels = ["Not at all", "Slightly", "Fairly", "Very"]   # questionnaire order
    codes = [1, 2, 3, 4]                 # optional; default 1..k
    positive = ["Fairly", "Very"]        # optional; default codes above the middle
    negative = ["Not at all", "Slightly"]
    neutral = []
    not_applicable = ["N/A"]             # optional
    [aliases]                            # optional other spellings
    "not at all confident" = "Not at all"

Matching of answers ignores case and surrounding white space
(:meth:`Scale.match`). Numeric answers are read only through a scale file's codes
(``Scale.numeric_codes``) or a code map / survey definition
(:mod:`analysis.codebook`): the built-in scales never guess which end of an export's
numbering means agreement.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path

from ._io import read_toml
from .errors import SurveyInputError

__all__ = ["Scale", "BUILTIN_SCALES", "get_scale", "load_scale", "normalize_answer",
           "DEFAULT_NOT_APPLICABLE", "DECLINED", "SHORT_NOT_APPLICABLE"]

#: Cell codes of an answer matrix besides label positions 0..k-1 (see
#: :attr:`analysis.ingest.SurveyData.answers`): blank, not applicable, and an unknown
#: answer counted as missing.
BLANK = -1
NOT_APPLICABLE = -2
UNKNOWN = -3

#: Most labels a scale may have (answers are stored as small integers).
MAX_LABELS = 100

#: Answers that decline the question: no position on the scale, so counted, like "N/A",
#: under n/a (excluded from n), never as an answer and never as a blank.
DECLINED = ("Prefer not to say", "Prefer not to answer")

#: Short marks a spreadsheet holds for "not applicable" (they match as answers do, so "na"
#: and "n/a " too); a cell left empty is a blank (missing), not one of these.
SHORT_NOT_APPLICABLE = ("NA", "-")

#: Answers treated as "not applicable" (the n/a count) unless a scale names its own: the
#: one list both routes (``read_survey`` and ``summarize_by``) match answers against.
DEFAULT_NOT_APPLICABLE = ("Not applicable", "N/A", "Does not apply") + SHORT_NOT_APPLICABLE \
    + DECLINED

_SPACE = re.compile(r"\s+")


def normalize_answer(text: str) -> str:
    """Key used to match an answer to a label.

    Surrounding white space is removed, inner runs of white space collapse to
    one space and case is folded, so ``"  definitely   AGREE "`` matches
    ``"Definitely Agree"``.
    """
    return _SPACE.sub(" ", str(text).strip()).casefold()


def group_names(spellings: dict) -> dict:
    """The group each spelling of a grouping value belongs to, named once for both routes.

    Spellings of one value ("Sec 1", "sec 1 ") are one group: they match as answers do
    (:func:`normalize_answer`). The group is named by its commonest spelling (inner white
    space collapsed), ties broken by the larger text.

    Parameters
    ----------
    spellings : dict
        Respondents per spelling; a spelling is a text or a tuple of texts (one per
        grouping column, matched column by column).

    Returns
    -------
    dict
        ``{spelling: (key, name)}``: the normalised key and the group's name, both of the
        spelling's type.
    """
    def key(sp):
        return (tuple(normalize_answer(v) for v in sp) if isinstance(sp, tuple)
                else normalize_answer(sp))

    def tidy(sp):
        return (tuple(" ".join(v.split()) for v in sp) if isinstance(sp, tuple)
                else " ".join(sp.split()))

    tally: dict = {}
    for sp, n in spellings.items():
        per = tally.setdefault(key(sp), {})
        per[tidy(sp)] = per.get(tidy(sp), 0) + n
    name = {k: max(per, key=lambda t: (per[t], t)) for k, per in tally.items()}
    return {sp: (key(sp), name[key(sp)]) for sp in spellings}


def validate_group_order(order) -> None:
    """Refuse an ``order`` (``--group-order``) that is not a list of texts."""
    if order is not None and (isinstance(order, str) or not all(isinstance(o, str) for o in order)):
        raise ValueError(f"`order` must be a list of group names, got {order!r}")


def order_groups(columns: list, order, source: str) -> list:
    """Each grouping column's values in the order ``--group-order`` asks, for both routes.

    Parameters
    ----------
    columns : list of (list, dict)
        Per grouping column: its values' keys (:func:`normalize_answer`) in the default
        order, and ``{key: name}`` to list them by in a refusal.
    order : list of str or None
        Values to put first, in this order (matched as answers are; a repeat counts once);
        the others follow in the default order.
    source : str
        File named in a refusal.

    Returns
    -------
    list of list
        Per column, the keys in the order asked.

    Raises
    ------
    SurveyInputError
        A value of ``order`` that is no grouping column's value (the values are listed).
    """
    if not order:
        return [list(ranked) for ranked, _ in columns]
    for o in order:
        if not any(normalize_answer(o) in name_of for _, name_of in columns):
            ranked = [k for r, _ in columns for k in r]          # every column's values
            name_of = {k: v for _, names in columns for k, v in names.items()}
            shown = [name_of[k] for k in ranked[:20]]
            more = f" and {len(ranked) - 20} more" if len(ranked) > 20 else ""
            which = "the grouping column" if len(columns) == 1 else "any grouping column"
            raise SurveyInputError(f"--group-order names {o!r}, which is not a value of "
                                   f"{which}; values are {shown}{more}", source)
    want = list(dict.fromkeys(normalize_answer(o) for o in order))
    out = []
    for ranked, name_of in columns:
        first = [k for k in want if k in name_of]
        chosen = set(first)
        out.append(first + [k for k in ranked if k not in chosen])
    return out


def two_groups_message(respondent: str, column: str, first: str, other: str) -> str:
    """The one refusal of both routes when a long file's rows of one respondent give two
    groups (values that are not spellings of one value, :func:`group_names`): the file
    contradicts itself, and counting the respondent in both groups, or in the first only,
    would each be a guess made without a word.

    >>> two_groups_message("s1", "Section", "A", " ")
    "respondent 's1' is in two groups by 'Section': 'A' on an earlier row, (blank) on this one; a respondent's rows must give one group"
    """
    from .disclosure import BLANK_GROUP
    from .platforms import spaced_name

    def shown(v):
        return repr(v) if str(v).strip() else BLANK_GROUP
    return (f"respondent {respondent!r} is in two groups by {spaced_name(column)!r}: "
            f"{shown(first)} on an earlier row, {shown(other)} on this one; a respondent's rows "
            f"must give one group")


def _code_key(text: str) -> str | None:
    """Canonical form of a numeric answer (``"5"``, ``"5.0"``, ``" 5 "`` -> ``"5"``)."""
    t = str(text).strip()
    try:
        value = float(t)
    except ValueError:
        return None
    if value != value or value in (float("inf"), float("-inf")):
        return None
    if value.is_integer():
        return str(int(value))
    return repr(value)


#: Public name of the canonical form of a numeric answer (``" 5.0 "`` -> ``"5"``).
def code_key(text) -> "str | None":
    """Canonical form of a numeric answer, or None (see :meth:`Scale.code_keys`)."""
    return _code_key(text)


@dataclass(frozen=True)
class Scale:
    """An ordered response scale.

    Parameters
    ----------
    name : str
        Short name (``"paper"``, ``"agree5"``, ...).
    labels : tuple of str
        Answer labels in questionnaire order.
    codes : tuple of float
        Numeric code of each label (same order). Higher codes mean more
        agreement / frequency / satisfaction.
    positive, neutral, negative : tuple of str
        Labels counted as agreeing (the top box(es)), neutral and disagreeing.
    not_applicable : tuple of str
        Answers excluded from denominators and reported apart.
    aliases : dict
        Other spellings, mapped to a label.
    description : str
        One line for listings.
    numeric_codes : bool
        Numeric answers may be read through ``codes``. False for the built-in
        scales: an export's numbers follow the order the survey author listed the
        choices in, which the built-in scale cannot know (a Qualtrics numeric export
        may code "Strongly agree" as 1). True for a scale file, whose author states
        the codes (``codes``, or 1..k in the order of ``labels``).
    """

    name: str
    labels: tuple[str, ...]
    codes: tuple[float, ...]
    positive: tuple[str, ...]
    neutral: tuple[str, ...]
    negative: tuple[str, ...]
    not_applicable: tuple[str, ...] = DEFAULT_NOT_APPLICABLE
    aliases: dict = field(default_factory=dict, compare=False, hash=False)
    description: str = ""
    numeric_codes: bool = field(default=False, compare=False)

    def __post_init__(self):
        _validate_scale(self)

    # -- lookup -------------------------------------------------------------
    @property
    def k(self) -> int:
        """Number of labels."""
        return len(self.labels)

    def _lookup(self) -> dict:
        cache = self.__dict__.get("_lookup_cache")
        if cache is None:
            cache = {}
            for i, label in enumerate(self.labels):
                cache[normalize_answer(label)] = i
            for alias, label in self.aliases.items():
                cache[normalize_answer(alias)] = self.labels.index(label)
            for na in self.not_applicable:
                cache.setdefault(normalize_answer(na), -2)
            codes = {}
            for i, code in enumerate(self.codes):
                codes[_code_key(code)] = i
            object.__setattr__(self, "_lookup_cache", cache)
            object.__setattr__(self, "_code_cache", codes)
        return cache

    def match(self, answer: str, accept_codes: bool = True) -> int | None:
        """Index of the label an answer stands for.

        Returns
        -------
        int or None
            ``0 .. k-1`` for a label, :data:`Scale.NOT_APPLICABLE` (-2) for a
            not-applicable answer, :data:`Scale.BLANK` (-1) for a blank answer,
            ``None`` when the answer matches nothing.
        """
        key = normalize_answer(answer)
        if key == "":
            return self.BLANK
        hit = self._lookup().get(key)
        if hit is not None:
            return hit
        if accept_codes and self.numeric_codes:
            ck = _code_key(key)
            if ck is not None:
                return self.__dict__["_code_cache"].get(ck)
        return None

    def answer_keys(self) -> dict:
        """``normalize_answer(text) -> label index`` (or :data:`NOT_APPLICABLE`) for every
        label, alias and not-applicable text: :meth:`match` without codes, for callers
        that normalise each distinct answer once."""
        return self._lookup()

    def code_keys(self) -> dict:
        """``code_key(code) -> label index`` for the numeric codes."""
        self._lookup()
        return self.__dict__["_code_cache"]

    def matches_label(self, answer: str) -> bool:
        """True when ``answer`` is one of the label texts (or an alias / N/A text)."""
        key = normalize_answer(answer)
        return key != "" and key in self._lookup()

    def matches_code(self, answer: str) -> bool:
        """True when ``answer`` is one of the numeric codes."""
        self._lookup()
        ck = _code_key(answer)
        return ck is not None and ck in self.__dict__["_code_cache"]

    BLANK = -1
    NOT_APPLICABLE = -2

    # -- derived ------------------------------------------------------------
    def index(self, label: str) -> int:
        """Index of a label given in any case / spacing; ValueError if unknown."""
        i = self.match(label, accept_codes=False)
        if i is None or i < 0:
            raise ValueError(
                f"label {label!r} is not on scale {self.name!r}; valid labels: "
                + ", ".join(self.labels))
        return i

    def reversed_codes(self) -> tuple[float, ...]:
        """Codes for a reverse-keyed item: ``min + max - code``."""
        lo, hi = min(self.codes), max(self.codes)
        return tuple(lo + hi - c for c in self.codes)

    def describe_valid(self) -> str:
        """The valid answers, for error messages."""
        codes = ", ".join(_code_key(c) for c in self.codes)
        na = ", ".join(self.not_applicable)
        text = ", ".join(self.labels) + (f" (or codes {codes})" if self.numeric_codes else "")
        if na:
            text += f"; not applicable: {na}"
        return text

    def to_dict(self) -> dict:
        """Plain-data form (for JSON)."""
        return {"name": self.name, "labels": list(self.labels),
                "codes": list(self.codes), "positive": list(self.positive),
                "neutral": list(self.neutral), "negative": list(self.negative),
                "not_applicable": list(self.not_applicable)}

    def __repr__(self):
        return f"Scale({self.name!r}, labels={list(self.labels)!r})"


def _finite(x) -> bool:
    """A finite number that fits a float (``10**400`` does not)."""
    try:
        return math.isfinite(x)
    except (OverflowError, TypeError):
        return False


#: Largest magnitude of a scale code. Means and SDs sum codes (squared) over up to
#: 10 million answers: with codes up to 1e6 the sums stay far below float's range and
#: keep 1e-6 relative precision; a Likert code is a small number in any real scale.
MAX_CODE = 1e6


def _bad_code(codes) -> "int | None":
    """0-based index of the first code that is not a finite number within ``MAX_CODE``."""
    for i, c in enumerate(codes):
        if not _finite(c) or abs(c) > MAX_CODE:
            return i
    return None


def _validate_scale(s: Scale) -> None:
    where = f"scale {s.name!r}"
    if not isinstance(s.name, str) or not s.name.strip():
        raise ValueError("scale `name` must be a non-empty string")
    if len(s.labels) < 2:
        raise ValueError(f"{where}: needs at least two labels, got {list(s.labels)!r}")
    if len(s.labels) > MAX_LABELS:
        raise ValueError(f"{where}: {len(s.labels)} labels; at most {MAX_LABELS}")
    if len(s.codes) != len(s.labels):
        raise ValueError(f"{where}: {len(s.codes)} codes for {len(s.labels)} labels")
    if _bad_code(s.codes) is not None:    # nan would match nothing; 1e308 overflows a mean
        raise ValueError(f"{where}: codes must be finite numbers within +-{MAX_CODE:g}, got "
                         f"{list(s.codes)!r}")
    keys = [normalize_answer(x) for x in s.labels]
    if len(set(keys)) != len(keys) or "" in keys:
        raise ValueError(f"{where}: labels must be distinct and non-blank (ignoring case), "
                         f"got {list(s.labels)!r}")
    if len({float(c) for c in s.codes}) != len(s.codes):
        raise ValueError(f"{where}: codes must be distinct, got {list(s.codes)!r}")
    for group_name in ("positive", "neutral", "negative"):
        for lab in getattr(s, group_name):
            if lab not in s.labels:
                raise ValueError(f"{where}: {group_name} label {lab!r} is not one of "
                                 f"{list(s.labels)!r}")
    groups = list(s.positive) + list(s.neutral) + list(s.negative)
    if len(set(groups)) != len(groups):
        raise ValueError(f"{where}: a label is in more than one of positive/neutral/negative")
    for na in s.not_applicable:
        if normalize_answer(na) in keys:
            raise ValueError(f"{where}: not-applicable answer {na!r} is also a label")
    for alias, lab in s.aliases.items():
        if lab not in s.labels:
            raise ValueError(f"{where}: alias {alias!r} points to {lab!r}, "
                             f"which is not one of {list(s.labels)!r}")


def _make(name, labels, codes, positive, neutral, negative, description, aliases=None):
    return Scale(name=name, labels=tuple(labels), codes=tuple(float(c) for c in codes),
                 positive=tuple(positive), neutral=tuple(neutral), negative=tuple(negative),
                 aliases=dict(aliases or {}), description=description)


_PAPER = ("Definitely Agree", "Partially Agree", "Neutral", "Partially Disagree",
          "Definitely Disagree")
_AGREE5 = ("Strongly disagree", "Disagree", "Neither agree nor disagree", "Agree",
           "Strongly agree")
_AGREE5S = ("Strongly disagree", "Somewhat disagree", "Neither agree nor disagree",
            "Somewhat agree", "Strongly agree")
_AGREE7 = ("Strongly disagree", "Disagree", "Somewhat disagree",
           "Neither agree nor disagree", "Somewhat agree", "Agree", "Strongly agree")
_FREQ5 = ("Never", "Rarely", "Sometimes", "Often", "Always")
_AGREE4 = ("Strongly disagree", "Disagree", "Agree", "Strongly agree")
_FREQ4 = ("Never", "Sometimes", "Often", "Always")
_SAT5 = ("Very dissatisfied", "Dissatisfied", "Neither satisfied nor dissatisfied",
         "Satisfied", "Very satisfied")

#: Built-in scales by name. Order matters for automatic detection (first wins ties).
BUILTIN_SCALES: dict[str, Scale] = {
    "paper": _make("paper", _PAPER, (5, 4, 3, 2, 1), _PAPER[:2], _PAPER[2:3], _PAPER[3:],
                   "five-point scale of the paper's questionnaire (Definitely Agree first)"),
    "agree5": _make("agree5", _AGREE5, (1, 2, 3, 4, 5), _AGREE5[3:], _AGREE5[2:3], _AGREE5[:2],
                    "five-point Likert agreement", {"Neutral": _AGREE5[2]}),
    "agree5-somewhat": _make("agree5-somewhat", _AGREE5S, (1, 2, 3, 4, 5), _AGREE5S[3:],
                             _AGREE5S[2:3], _AGREE5S[:2],
                             "five-point agreement with 'Somewhat' (Qualtrics default)",
                             {"Neutral": _AGREE5S[2]}),
    "agree7": _make("agree7", _AGREE7, range(1, 8), _AGREE7[4:], _AGREE7[3:4], _AGREE7[:3],
                    "seven-point Likert agreement", {"Neutral": _AGREE7[3]}),
    "agree4": _make("agree4", _AGREE4, (1, 2, 3, 4), _AGREE4[2:], (), _AGREE4[:2],
                    "four-point agreement, no neutral (e.g. Canvas surveys)"),
    "frequency4": _make("frequency4", _FREQ4, (1, 2, 3, 4), _FREQ4[2:], (), _FREQ4[:2],
                        "four-point frequency (Never, Sometimes, Often, Always)"),
    "frequency5": _make("frequency5", _FREQ5, (1, 2, 3, 4, 5), _FREQ5[3:], _FREQ5[2:3], _FREQ5[:2],
                        "five-point frequency (Never ... Always)"),
    "satisfaction5": _make("satisfaction5", _SAT5, (1, 2, 3, 4, 5), _SAT5[3:], _SAT5[2:3], _SAT5[:2],
                           "five-point satisfaction", {"Neutral": _SAT5[2]}),
}


#: Other names accepted for the built-in scales.
ALIASES = {"definitely5": "paper", "likert5": "agree5", "agreement": "agree5",
           "agreement5": "agree5", "likert7": "agree7", "agreement7": "agree7",
           "frequency": "frequency5", "satisfaction": "satisfaction5"}


def get_scale(name_or_path: "str | Path | Scale") -> Scale:
    """A built-in scale by name, or a custom scale from a TOML file.

    Raises
    ------
    ValueError
        Unknown name (the message lists the built-in names).
    SurveyInputError
        The TOML file is unreadable or invalid.
    """
    if isinstance(name_or_path, Scale):
        return name_or_path
    text = str(name_or_path)
    key = ALIASES.get(text.strip().lower(), text.strip().lower())
    if key in BUILTIN_SCALES:
        return BUILTIN_SCALES[key]
    if text.lower().endswith(".toml") or Path(text).is_file():
        return load_scale(text)
    raise ValueError(f"`scale` must be one of {list(BUILTIN_SCALES)} or a .toml file, "
                     f"got {text!r}")


def load_scale(path: "str | Path") -> Scale:
    """Read a custom scale from TOML (see the module docstring for the keys).

    Raises
    ------
    SurveyInputError
        Missing file, TOML syntax error, or a key with a bad value (named).
    """
    p = Path(path)
    data = read_toml(p)
    allowed = {"name", "labels", "codes", "positive", "neutral", "negative",
               "not_applicable", "aliases", "description"}
    for key in data:
        if key not in allowed:
            raise SurveyInputError(f"key {key!r}: unknown key; allowed: {sorted(allowed)}", str(p))
    labels = data.get("labels")
    if not isinstance(labels, list) or not all(isinstance(x, str) for x in labels):
        raise SurveyInputError("key 'labels': must be a list of strings", str(p))
    k = len(labels)
    codes = data.get("codes", list(range(1, k + 1)))
    if (not isinstance(codes, list) or len(codes) != k
            or not all(isinstance(c, (int, float)) and not isinstance(c, bool) for c in codes)):
        raise SurveyInputError(f"key 'codes': must be a list of {k} numbers", str(p))
    bad = _bad_code(codes)
    if bad is not None:
        raise SurveyInputError(f"key 'codes': must be finite numbers within +-{MAX_CODE:g}; "
                               f"code {bad + 1} is {codes[bad]!r}", str(p))
    mid = (min(codes) + max(codes)) / 2 if codes else 0
    default_pos = [lab for lab, c in zip(labels, codes) if c > mid]
    default_neg = [lab for lab, c in zip(labels, codes) if c < mid]
    default_neu = [lab for lab, c in zip(labels, codes) if c == mid]
    groups = {}
    for key, default in (("positive", default_pos), ("neutral", default_neu),
                         ("negative", default_neg), ("not_applicable", list(DEFAULT_NOT_APPLICABLE))):
        value = data.get(key, default)
        if not isinstance(value, list) or not all(isinstance(x, str) for x in value):
            raise SurveyInputError(f"key {key!r}: must be a list of strings", str(p))
        groups[key] = tuple(value)
    aliases = data.get("aliases", {})
    if not isinstance(aliases, dict) or not all(isinstance(v, str) for v in aliases.values()):
        raise SurveyInputError("key 'aliases': must be a table of strings", str(p))
    name = data.get("name", p.stem)
    try:
        return Scale(name=str(name), labels=tuple(labels), codes=tuple(float(c) for c in codes),
                     aliases=dict(aliases), description=str(data.get("description", "")),
                     numeric_codes=True, **groups)
    except ValueError as e:
        raise SurveyInputError(str(e), str(p)) from None
