"""Small-group suppression that subtraction cannot undo (complementary suppression).

A group with fewer respondents than the threshold is not shown (primary suppression).
Every output that shows groups also shows the total over all respondents, so one
suppressed group would be the total minus the groups shown, exactly. Statistical
agencies therefore suppress further cells (complementary suppression): here the
smallest shown groups are withheld too, one at a time, until the withheld groups are
at least two and hold together at least the threshold of respondents. The total minus
the shown groups then reveals only the pooled answers of several groups, themselves
a group large enough to show.

Public API: :func:`suppress_groups` -> :class:`Suppression`; :data:`BLANK_GROUP`.
"""
from __future__ import annotations

from dataclasses import dataclass, field

__all__ = ["BLANK_GROUP", "Suppression", "suppress_groups", "respondents_text", "count_text"]


def count_text(n: int, noun: str) -> str:
    """``"1 group"``, ``"5 groups"``: a count of a regular ``noun`` as a sentence says it."""
    return f"{n} {noun}{'' if n == 1 else 's'}"


def respondents_text(n: int) -> str:
    """``"1 respondent"``, ``"5 respondents"``: a count of respondents as a sentence says it."""
    return count_text(n, "respondent")

#: The name every output (text, JSON, tables, HTML) gives the group of blank grouping
#: values, on both routes (``--group`` and ``--by``).
BLANK_GROUP = "(blank)"


@dataclass
class Suppression:
    """Which groups are withheld, and why.

    Attributes
    ----------
    primary : list of int
        Groups (indices) under the threshold.
    complementary : list of int
        Groups at or above the threshold withheld so that no primary group can be
        recovered from the total and the groups shown.
    note : str
        One sentence saying what was withheld and why ("" when nothing was).
    """

    primary: list = field(default_factory=list)
    complementary: list = field(default_factory=list)
    note: str = ""

    def withheld(self, g: int) -> bool:
        """Group ``g`` is not shown."""
        return g in self.primary or g in self.complementary


def suppress_groups(sizes, min_size: int, names=None) -> Suppression:
    """Groups to withhold: those under ``min_size`` and their complements.

    Parameters
    ----------
    sizes : sequence of int
        Respondents per group.
    min_size : int
        Smallest group shown.
    names : sequence of str, optional
        Group names for the note (default: the indices).

    Returns
    -------
    Suppression

    Notes
    -----
    The withheld set W starts as the groups under ``min_size``. While W is non-empty
    and either holds a single group or fewer than ``min_size`` respondents in all, the
    smallest shown group (the first of equal ones) joins it. When every group is
    withheld the total is all that is shown, and it holds every respondent.

    Examples
    --------
    >>> s = suppress_groups([6, 6, 2], 5)
    >>> s.primary, s.complementary
    ([2], [0])
    """
    sizes = [int(x) for x in sizes]
    names = [str(g) for g in range(len(sizes))] if names is None else [str(x) for x in names]
    primary = [g for g, x in enumerate(sizes) if x < min_size]
    if not primary:
        return Suppression()
    shown = sorted((g for g, x in enumerate(sizes) if x >= min_size), key=lambda g: (sizes[g], g))
    extra = []
    while shown and (len(primary) + len(extra) < 2
                     or sum(sizes[g] for g in primary + extra) < min_size):
        extra.append(shown.pop(0))
    note = ""
    if extra:
        pooled = ", ".join(repr(names[g]) for g in primary)
        what = (f"the answers of group {pooled}" if len(primary) == 1
                else f"the pooled answers of groups {pooled}")
        note = (f"{', '.join(repr(names[g]) for g in extra)} also withheld (complementary "
                f"suppression): otherwise the total minus the groups shown would give {what}, "
                f"fewer than {respondents_text(min_size)}")
    return Suppression(primary=primary, complementary=extra, note=note)
