"""The tests' "same tree" comparison: what ``srepr(a) == srepr(b)`` says, without printing both."""
from __future__ import annotations


def same_tree(a, b) -> bool:
    """True when ``a`` and ``b`` are the same sympy tree, as equal ``srepr`` texts would say.

    Sympy's ``==`` compares trees node for node: the class of each node, its arguments in order, a
    number's class and value (a Float's precision too) and a symbol's name and assumptions. It is the
    structure ``srepr`` prints, compared without building two texts (printing them was about 1 s of
    test_display's CPU). The class check adds what ``==`` leaves out at the top, a Python int against
    an Integer (``0 == Integer(0)``). Tuples and lists (a numerator and denominator, a vector's
    entries) are compared item for item.

    Parameters
    ----------
    a, b
        Sympy expressions, or tuples or lists of them.

    Returns
    -------
    bool
        Whether the two are the same tree.
    """
    if isinstance(a, (tuple, list)) or isinstance(b, (tuple, list)):
        return type(a) is type(b) and len(a) == len(b) and all(map(same_tree, a, b))
    return type(a) is type(b) and a == b
