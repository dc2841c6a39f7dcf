"""Dotted rates in LaTeX and MathML: the dots over the name's nucleus, the subscript beside it.

The reference is sympy's own notation for a name with a modifier, which puts the accent on the
nucleus before the subscript (``Symbol("thdot_1")`` prints ``\\dot{th}_{1}``): for each coordinate
name, the product's dotted name of ``th1`` must equal sympy's print of ``thdot_1``. Before, the
dot covered the whole subscripted name (``\\dot{th_{1}}``).
"""
from __future__ import annotations

import xml.dom.minidom

import sympy as sp
import pytest

from solver.mathml import mathml_body
from solver.notation import dotted_latex

# (coordinate name, the same name with sympy's modifier before the subscript)
NAMES = [("theta", "theta{}"), ("x", "x{}"), ("th1", "th{}_1"), ("theta_A", "theta{}_A"),
         ("phi12", "phi{}_12"), ("Th_2", "Th{}_2")]


@pytest.mark.parametrize("name,modified", NAMES)
@pytest.mark.parametrize("accent", ["dot", "ddot"])
def test_dotted_latex_is_sympys_modifier_notation(name, modified, accent):
    assert dotted_latex(sp.Symbol(name), accent) == sp.latex(sp.Symbol(modified.format(accent)))


@pytest.mark.parametrize("name,nucleus,sub", [("th1_dot", "th", "1"), ("theta_A_ddot", "\u03b8", "A")])
def test_mathml_dots_the_nucleus_and_keeps_the_subscript(name, nucleus, sub):
    """The MathML tree: msub(mover(nucleus, accent), subscript), not mover(msub(...), accent)."""
    dom = xml.dom.minidom.parseString(f"<math>{mathml_body(sp.Symbol(name))}</math>")
    top = dom.documentElement.firstChild
    assert top.tagName == "msub", top.toxml()
    over, subscript = top.childNodes
    assert over.tagName == "mover" and over.firstChild.firstChild.data == nucleus, top.toxml()
    assert subscript.firstChild.data == sub
