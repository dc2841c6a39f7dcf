"""Exact rounding of percentages (shared by table verification and summaries).

All arithmetic is on :class:`fractions.Fraction`, so a value exactly half-way
between two printed values is recognised as such (binary floats cannot).

- :func:`round_fraction` -- round to ``decimals`` places by a named rule
  (:data:`ROUNDING_RULES`); ``"half_away"`` (half away from zero) is the
  project's documented rule for printed percentages.
- :func:`percent_text` -- ``100 k / n`` as printed (half away from zero): every
  printed share, percentage and chart label goes through it.
- :func:`share_percent_text` -- a share that is not a count ratio (an interval bound)
  in percent by the same rule.
- :func:`number_text`, :func:`significant_text` -- any other printed statistic (median,
  IQR, mean, SD, an effect size; a p-value to significant digits) by the same rule, on
  the decimal value Python writes for the float (``repr``: 2.675, not the binary
  2.67499999...).
- :func:`quartile_values`, :func:`quartile_texts` -- the interquartile range with its
  quartiles, printed so that the IQR is the printed Q3 minus the printed Q1.
- :func:`rounding_interval` -- every exact percentage that prints as a given
  value: the tolerance a printed precision implies.
- :func:`largest_remainder` -- Hamilton's method: percentages of counts that
  add up to exactly 100; :func:`largest_remainder_tie` says when equal remainders
  straddled the last unit handed out, and how that tie was broken.
"""
from __future__ import annotations

import math
from fractions import Fraction

__all__ = ["ROUNDING_RULES", "round_fraction", "percent_text", "share_percent_text",
           "number_text", "significant_text", "QUARTILE_DECIMALS", "quartile_values", "quartile_texts",
           "rounding_interval", "largest_remainder",
           "largest_remainder_tie"]

#: Valid values of the ``rule`` argument.
ROUNDING_RULES = ("half_away", "half_even", "truncate", "ceil")


def round_fraction(x: Fraction, decimals: int, rule: str = "half_away") -> Fraction:
    """Round an exact rational to ``decimals`` places by ``rule``.

    Parameters
    ----------
    x : Fraction
        Value to round (here a percentage ``100 k / N``).
    decimals : int
        Places after the decimal point (negative: to tens, hundreds ...).
    rule : {"half_away", "half_even", "truncate", "ceil"}
        Tie handling / direction. ``half_away`` rounds halves away from zero.

    Returns
    -------
    Fraction
        The rounded value, exactly.
    """
    _validate_rule(rule)
    # On the integers of y = x 10**decimals = num / den (den > 0): the same values as Fraction
    # arithmetic gives, without building a Fraction per step (tables.attainable_counts rounds
    # some hundred thousand percentages in a N search)
    x = x if isinstance(x, Fraction) else Fraction(x)
    num, den = x.numerator, x.denominator
    if decimals >= 0:
        num *= 10**decimals
    else:
        den *= 10**-decimals
    if rule == "ceil":  # towards +infinity (percentages are not negative)
        m = -(-num // den)
    else:
        a = abs(num)
        if rule == "half_away":
            m = (2 * a + den) // (2 * den)  # floor(|y| + 1/2)
        elif rule == "half_even":
            m, rem = divmod(a, den)  # |y| = m + rem / den
            if 2 * rem > den or (2 * rem == den and m % 2 == 1):
                m += 1
        else:  # truncate
            m = a // den
        m = -m if num < 0 else m
    return Fraction(m, 10**decimals) if decimals >= 0 else Fraction(m * 10**-decimals)


def percent_text(k: int, n: int, decimals: int = 1) -> str:
    """The percentage ``100 k / n`` as printed: exact, rounded half away from zero.

    Parameters
    ----------
    k, n : int
        Part and whole (n > 0).
    decimals : int
        Places after the decimal point.

    Examples
    --------
    >>> percent_text(1, 8, 0), percent_text(1, 8, 1)
    ('13', '12.5')
    """
    return f"{float(round_fraction(Fraction(100 * int(k), int(n)), decimals)):.{decimals}f}"


def share_percent_text(share: float, decimals: int = 1) -> str:
    """A share 0..1 that is no count ratio (an interval bound) in percent as printed: the
    float's exact value times 100, rounded half away from zero like :func:`percent_text`
    (Python's ``f"{x:.1%}"`` rounds half to even, so 0.0625 would print 6.2).

    Examples
    --------
    >>> share_percent_text(0.0625), share_percent_text(0.8125, 0)
    ('6.3', '81')
    """
    return f"{float(round_fraction(Fraction(share) * 100, decimals)):.{decimals}f}"


def _decimal_value(x: float) -> Fraction:
    """The decimal value Python writes for ``x`` (``repr``, the shortest text that reads
    back as ``x``), exactly: a mean of 107/40 is the float 2.67499999..., written 2.675."""
    return Fraction(repr(float(x)))


def number_text(x, decimals: int = 1, none: str = "-") -> str:
    """A statistic (median, IQR, mean, SD, an effect size) to ``decimals`` places, half away
    from zero on its decimal value (:func:`_decimal_value`), as every percentage is printed;
    ``none`` when there is no value, ``nan``/``inf`` as Python writes them.

    Examples
    --------
    >>> number_text(3.25), number_text(0.25), number_text(2.625, 2), number_text(-0.0625, 3)
    ('3.3', '0.3', '2.63', '-0.063')
    """
    if x is None:
        return none
    if not math.isfinite(x):
        return str(float(x))
    return f"{float(round_fraction(_decimal_value(x), decimals)):.{decimals}f}"


QUARTILE_DECIMALS = 2
"""Places of a printed quartile and IQR. The quartiles of whole-number codes (numpy's and R's
default linear rule) are multiples of 0.25, so two places print them exactly: 0.75 (3.25-4.00),
where one place would print 0.8 (3.3-4.0) and the reader who subtracts would get 0.7."""


def quartile_values(q1, q3, decimals: int = QUARTILE_DECIMALS) -> tuple:
    """The IQR, Q1 and Q3 as printed: each quartile to ``decimals`` places by the rule of
    :func:`number_text`, and the IQR their difference (exact), so that the printed IQR is
    always the printed Q3 minus the printed Q1. ``(None, None, None)`` without quartiles.

    Examples
    --------
    >>> quartile_values(3.25, 4.0), quartile_values(2.124, 3.126)  # the IQR 1.002 prints as 1.01
    ((0.75, 3.25, 4.0), (1.01, 2.12, 3.13))
    """
    if q1 is None or q3 is None:
        return None, None, None
    lo, hi = (round_fraction(_decimal_value(q), decimals) for q in (q1, q3))
    return float(hi - lo), float(lo), float(hi)


def quartile_texts(q1, q3, decimals: int = QUARTILE_DECIMALS, none: str = "-") -> tuple[str, str, str]:
    """``(IQR, Q1, Q3)`` as text, by :func:`quartile_values` (``none`` for each when there are
    no quartiles).

    Examples
    --------
    >>> quartile_texts(3.25, 4.0), quartile_texts(None, None)
    (('0.75', '3.25', '4.00'), ('-', '-', '-'))
    """
    values = quartile_values(q1, q3, decimals)
    return tuple(none if v is None else f"{v:.{decimals}f}" for v in values)


def significant_text(x, digits: int = 4) -> str:
    """``x`` to ``digits`` significant digits by the rule of :func:`number_text`, written as
    ``f"{x:.4g}"`` writes it (trailing zeros dropped; ``1e-05`` form below 1e-4 and from
    10**digits), where ``.4g`` rounds the binary value half to even.

    Examples
    --------
    >>> significant_text(0.015625), significant_text(1 / 64, 3), significant_text(2.5e-7, 1)
    ('0.01563', '0.0156', '3e-07')
    """
    if x is None or not math.isfinite(x) or x == 0:
        return f"{x:.{digits}g}" if x is not None else "-"
    exact = _decimal_value(x)
    e = _exponent(exact)
    r = round_fraction(exact, digits - 1 - e)
    e = _exponent(r)                          # 9.9996 -> 10.00: one place more
    if -4 <= e < digits:
        return _strip(f"{float(r):.{max(digits - 1 - e, 0)}f}")
    mant = _strip(f"{float(r / Fraction(10) ** e):.{digits - 1}f}")
    return f"{mant}e{e:+03d}"


def _exponent(q: Fraction) -> int:
    """The power of ten of the leading digit of ``q`` (non-zero), exactly."""
    a = abs(q)
    e = len(str(a.numerator)) - len(str(a.denominator))
    return e if a >= Fraction(10) ** e else e - 1


def _strip(text: str) -> str:
    """Trailing zeros (and a bare point) dropped, as ``%g`` drops them."""
    return text.rstrip("0").rstrip(".") if "." in text else text


def _validate_rule(rule: str) -> None:
    if rule not in ROUNDING_RULES:
        raise ValueError(f"`rule` must be one of {list(ROUNDING_RULES)}, got {rule!r}")


def rounding_interval(printed: Fraction, decimals: int, rule: str = "half_away"
                      ) -> "tuple[Fraction, Fraction, bool, bool] | None":
    """Every exact percentage in 0..100 that ``rule`` prints as ``printed``.

    Parameters
    ----------
    printed : Fraction
        The printed percentage, exactly.
    decimals : int
        Printed precision.
    rule : {"half_away", "half_even", "truncate", "ceil"}

    Returns
    -------
    (lo, hi, lo_closed, hi_closed) or None
        The interval of exact values (each end included when its flag is true);
        None when ``printed`` has more decimals than the rounding keeps.

    Notes
    -----
    With u = 10**-decimals and h = u / 2 the values printing as p are
    half_away ``[p - h, p + h)``; half_even ``[p - h, p + h]`` when p / u is even,
    ``(p - h, p + h)`` when odd; truncate ``[p, p + u)``; ceil ``(p - u, p]``;
    each cut to 0..100 (a percentage), where a cut end is included.

    Examples
    --------
    >>> rounding_interval(Fraction("4.5"), 1)
    (Fraction(89, 20), Fraction(91, 20), True, False)
    """
    _validate_rule(rule)
    p = Fraction(printed)
    u = Fraction(1, 10 ** decimals)
    if (p / u).denominator != 1:
        return None
    h = u / 2
    if rule == "half_away":
        lo, hi, lc, hc = p - h, p + h, True, False
    elif rule == "half_even":
        even = (p / u).numerator % 2 == 0
        lo, hi, lc, hc = p - h, p + h, even, even
    elif rule == "truncate":
        lo, hi, lc, hc = p, p + u, True, False
    else:  # ceil
        lo, hi, lc, hc = p - u, p, False, True
    if lo < 0:
        lo, lc = Fraction(0), True
    if hi > 100:
        hi, hc = Fraction(100), True
    return lo, hi, lc, hc


def largest_remainder(counts: list[int], decimals: int = 1) -> list[Fraction]:
    """Percentages of ``counts`` that add up to exactly 100 (Hamilton's method).

    Each share ``100 c / n`` is truncated to ``decimals`` places; the units still
    missing from 100 go one each to the largest remainders (ties: first label).
    """
    floors, order, left = _hamilton(counts, decimals)
    for i in order[:left]:
        floors[i] += 1
    return [Fraction(f, 10 ** decimals) for f in floors]


def _hamilton(counts: list[int], decimals: int):
    """(truncated shares in units of the last place, indices by falling remainder with ties to the
    first, units left to hand out)."""
    n = sum(counts)
    if n == 0:
        return [0] * len(counts), list(range(len(counts))), 0
    units = 100 * 10 ** decimals
    quotas = [Fraction(c * units, n) for c in counts]
    floors = [math.floor(q) for q in quotas]
    order = sorted(range(len(counts)), key=lambda i: (-(quotas[i] - floors[i]), i))
    return floors, order, units - sum(floors)


def largest_remainder_tie(labels: list[str], counts: list[int], decimals: int = 1) -> str:
    """The sentence stating how :func:`largest_remainder` broke a tie, or ``""`` when none decided.

    A tie decides when cells with equal remainders straddle the last unit handed out: some get
    it and some do not. :func:`largest_remainder` gives it to the first label in scale order.

    Examples
    --------
    Three answers of 7 (3, 3, 1): A and B share 42.857...%, and one of them gets the last tenth
    (Table 1's item #4 has such a tie; the report states it from the published data):

    >>> largest_remainder_tie(["A", "B", "C"], [3, 3, 1])
    'A and B tie for the last 0.1 (equal remainders): it goes to the first in scale order, A (42.9 and 42.8; the other way 42.8 and 42.9)'
    >>> largest_remainder_tie(["A", "B", "C"], [2, 1, 1])  # 50 and 25 and 25: nothing to hand out
    ''
    """
    floors, order, left = _hamilton(counts, decimals)
    if left <= 0 or left >= len(order):
        return ""
    n, units = sum(counts), 100 * 10 ** decimals
    rem = {i: Fraction(counts[i] * units, n) - floors[i] for i in order}
    tied = [i for i in order if rem[i] == rem[order[left - 1]]]
    won, lost = [i for i in tied if i in order[:left]], [i for i in tied if i not in order[:left]]
    if not won or not lost:
        return ""
    unit, shown = Fraction(1, 10 ** decimals), largest_remainder(counts, decimals)

    def values(xs):
        return " and ".join(f"{float(x):.{decimals}f}" for x in xs)

    swapped = ""
    if len(won) == len(lost) == 1:  # one unit between two cells: the row the other way round
        swapped = f"; the other way {values([shown[i] - unit if i in won else shown[i] + unit for i in tied])}"
    return (f"{' and '.join(labels[i] for i in tied)} tie for the last {float(unit):.{decimals}f} "
            f"(equal remainders): it goes to the first in scale order, {', '.join(labels[i] for i in won)} "
            f"({values([shown[i] for i in tied])}{swapped})")
