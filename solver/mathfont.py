"""The maths font the HTML outputs carry, so that MathML looks the same on every machine.

Chromium draws MathML with whatever maths font the system has; with none, the
dots of theta_dot and theta_ddot come out nearly invisible and the limits of a
sum collide with its sigma. The pages (the report's, and the worked solution's of
``solver explain --format html``) therefore embed their own OpenType maths font,
"AltEuler Math", a subset of DejaVu Math TeX Gyre (Bitstream Vera license, renamed) with
its MATH table, made by ``solver/fonts/make_math_font.py`` and committed as
``solver/fonts/alteuler-math.woff``. It is inlined as a base64 ``data:`` URL:
the pages load nothing from outside.
"""
from __future__ import annotations

import base64
from functools import lru_cache
from pathlib import Path

from markupsafe import Markup

__all__ = ["FAMILY", "FONT_FILE", "font_face_css"]

FAMILY = "AltEuler Math"
FONT_FILE = Path(__file__).resolve().parent / "fonts" / "alteuler-math.woff"


@lru_cache(maxsize=1)
def font_face_css() -> Markup:
    """CSS: the ``@font-face`` of the embedded maths font and its use for every ``<math>``.

    Raises
    ------
    FileNotFoundError
        When the committed font file is missing (a broken checkout).
    """
    data = base64.b64encode(FONT_FILE.read_bytes()).decode("ascii")
    # The base64 alphabet and the fixed text below contain nothing that could end the <style> element.
    return Markup(
        f'@font-face {{ font-family: "{FAMILY}"; font-style: normal; font-weight: normal; font-display: block; '
        f'src: url("data:font/woff;base64,{data}") format("woff"); }}\n'
        f'  math {{ font-family: "{FAMILY}", math; }}'
    )
