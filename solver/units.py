"""The project's single pint unit registry.

Quantities enter and leave at the public boundary (scene files, command line,
reports); the numeric core works in SI floats or sympy symbols. Import
``ureg`` and ``Q_`` from here, never create another registry.
"""
from __future__ import annotations

import pint

ureg = pint.UnitRegistry()
# pint knows `lb` (pound mass) and `lbf`; spell out the engineering aliases too.
ureg.define("lbm = pound")
Q_ = ureg.Quantity

__all__ = ["ureg", "Q_"]
