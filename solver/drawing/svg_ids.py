"""SVG made ready to inline in an HTML page: one step shared by every page that shows a figure.

matplotlib numbers the ids of every SVG it writes the same way (``figure_1``, ``axes_1``,
``patch_1``, clip paths, markers), so two figures inlined in one page repeat them: invalid HTML,
and a reference (``url(#p...)``, ``xlink:href="#m..."``) would reach the first figure's
definition if two figures ever differed in one. :func:`inline_svg` gives each figure's ids a
prefix of its own, and their references with them.

Standard library only: the survey report (:mod:`analysis.report`) uses it without sympy.
"""
from __future__ import annotations

import re
from functools import lru_cache

__all__ = ["inline_svg"]

_ID = re.compile(r'\bid="([^"]+)"')
_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_.-]*")


@lru_cache(maxsize=16)  # a figure shown on two pages (the report's and the paper's) is scoped once
def inline_svg(svg: str, prefix: str) -> str:
    """The ``<svg>`` element of ``svg`` with every id prefixed, to inline in an HTML page.

    Parameters
    ----------
    svg : str
        SVG text as matplotlib writes it; an XML prolog and doctype before ``<svg`` are dropped.
    prefix : str
        Prepended to each id, unique to this figure within the page (a figure's name, or its
        number on the page). It starts with a letter, and holds letters, digits, ``_ . -``.

    Returns
    -------
    str
        The SVG with each ``id="X"`` written ``id="PREFIX-X"``, and each reference to such an
        id (``url(#X)``, ``href="#X"``, ``xlink:href="#X"``) changed alike. A reference to a name
        the figure does not define is left as it is. The same input gives the same output.

    Raises
    ------
    ValueError
        A prefix that is not a valid id start (the message repeats it).
    """
    if not _NAME.fullmatch(prefix):
        raise ValueError(f"SVG id prefix must start with a letter and hold letters, digits, '_', '.', '-'; "
                         f"got {prefix!r}")
    start = svg.find("<svg")
    svg = svg[start:] if start >= 0 else svg
    defined = set(_ID.findall(svg))
    if not defined:
        return svg

    def scoped(match: re.Match) -> str:
        head, name, tail = match.group(1), match.group(2), match.group(3)
        return f"{head}{prefix}-{name}{tail}" if name in defined else match.group(0)

    return re.sub(r'(\bid="|url\(#|href="#)([^")]+)([")])', scoped, svg)
