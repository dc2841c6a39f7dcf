"""Results of pure functions kept for the life of a process.

A scene loaded again (a command after another in one process, each test of a suite) gives
structurally the same sympy expressions, and some functions of them cost most of a derivation:
printing an expression into code (:func:`solver.strprint.lambdify`), Lagrange's equations
(:mod:`solver.formulations.lagrange`), division-free determinants
(:func:`solver.derivation.berkowitz_det`) and exact inverses
(:mod:`solver.analyses.instant`); a worked solution's LaTeX and its choice of which words are
maths (:mod:`solver.explain.render`), and a drawing's text measures
(:mod:`solver.drawing.layout`), repeat in the same way. Each keeps its last results in a
:class:`Kept`, keyed by values that compare structurally (sympy objects are equal only when
they are the same tree), never by ``id()``. A function whose arguments are themselves the key
(:func:`solver.model.system.derivative`) uses ``functools.lru_cache`` instead.
"""
from __future__ import annotations

from collections import OrderedDict
from typing import Callable, Hashable


class Kept:
    """The last ``size`` results of a pure function, by key (least recently used goes first).

    Parameters
    ----------
    size : int
        How many results are kept.

    Examples
    --------
    >>> squares = Kept(2)
    >>> squares.get(3, lambda: 3 * 3), squares.get(3, lambda: 0)
    (9, 9)
    >>> squares.get(None, lambda: 16)  # a None key: made, not kept
    16
    >>> len(squares)
    1
    """

    def __init__(self, size: int):
        self.size = size
        self._found: OrderedDict = OrderedDict()

    def get(self, key: Hashable | None, make: Callable):
        """The result kept for ``key``, else ``make()`` (kept unless ``key`` is None)."""
        if key is None:
            return make()
        if key in self._found:
            self._found.move_to_end(key)
            return self._found[key]
        found = self._found[key] = make()
        if len(self._found) > self.size:
            self._found.popitem(last=False)
        return found

    def __len__(self) -> int:
        return len(self._found)

    def clear(self) -> None:
        self._found.clear()


__all__ = ["Kept"]
