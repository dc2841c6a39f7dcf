"""The maths font of the report's HTML pages: :mod:`solver.mathfont`, where the worked
solution's HTML takes it from too (one font, one ``@font-face``)."""
from __future__ import annotations

from solver.mathfont import FAMILY, FONT_FILE, font_face_css

__all__ = ["FAMILY", "FONT_FILE", "font_face_css"]
