"""Regenerate ``alteuler-math.woff``: a subset of DejaVu Math TeX Gyre for the HTML outputs.

Not run by the build: the subset is committed (users' machines have only
Python). Run it by hand after changing the character set:

    apt-get install fonts-dejavu-extra   # Debian 12: fonts-dejavu-extra 2.37-6, DejaVu Math TeX Gyre 2.37
    .venv/bin/python solver/fonts/make_math_font.py

The source is DejaVu Math TeX Gyre: Bitstream Vera glyphs under the Bitstream
Vera license, DejaVu changes and the maths extensions in the public domain
(LICENSE-alteuler-math.txt here). That license allows modified fonts under a
name without "Bitstream" or "Vera": the subset is called "AltEuler Math". It
keeps the OpenType MATH table (accent placement, stretchy operators, limits)
for the characters below, with the glyph variants and constructions they need.

Why this font: at screen sizes its dots above (theta_dot, theta_ddot) are
larger and darker than Latin Modern Math's, whose single dot is a faint pixel
in scripts; tests/test_browser.py measures them.
"""
from __future__ import annotations

import sys
from pathlib import Path

from fontTools import subset
from fontTools.ttLib import TTFont

SOURCE = Path("/usr/share/fonts/truetype/dejavu/DejaVuMathTeXGyre.ttf")
TARGET = Path(__file__).with_name("alteuler-math.woff")
FAMILY = "AltEuler Math"

RANGES = [
    (0x20, 0x7E),        # Basic Latin
    (0xA0, 0xA0), (0xA8, 0xA8), (0xAC, 0xAC), (0xAF, 0xB1), (0xB4, 0xB4), (0xB7, 0xB7), (0xD7, 0xD7),
    (0xF7, 0xF7),        # Latin-1: diaeresis U+00A8 (the two dots of theta_ddot), macron, degree, plus-minus, times
    (0x2C6, 0x2DD),      # spacing modifiers: dot above U+02D9 (theta_dot), hat, tilde, caron, breve
    (0x300, 0x30F),      # combining accents
    (0x391, 0x3C9),      # Greek
    (0x3D1, 0x3D1), (0x3D5, 0x3D6), (0x3F0, 0x3F1), (0x3F5, 0x3F5),  # Greek symbol variants
    (0x2000, 0x200B),    # spaces
    (0x2032, 0x2037),    # primes
    (0x2061, 0x2064),    # function application, invisible times, separator, plus
    (0x210E, 0x210E),    # Planck constant: the italic h of the mathematical italic alphabet
    (0x2113, 0x2113),    # script l
    (0x2190, 0x2195), (0x21D0, 0x21D5),  # arrows
    (0x2202, 0x2202), (0x2206, 0x2207), (0x2211, 0x221E),  # partial, Delta, nabla, sum .. infinity, root
    (0x2223, 0x2225), (0x2227, 0x222B),  # divides, parallel, and, or, cap, cup, integral
    (0x2248, 0x2248), (0x2260, 0x2265), (0x22C5, 0x22C5),  # approx, not equal, <=, >=, dot operator
    (0x2308, 0x230B),    # ceilings, floors
    (0x239B, 0x23B3),    # bracket pieces (stretchy parentheses and braces)
    (0x27E8, 0x27E9),    # angle brackets
    (0x1D434, 0x1D467),  # mathematical italic Latin: single-letter <mi> are drawn in these
    (0x1D6A4, 0x1D6A5),  # dotless italic i, j
    (0x1D6E2, 0x1D71B),  # mathematical italic Greek
]


def main() -> int:
    if not SOURCE.is_file():
        print(f"error: {SOURCE} not found (apt-get install fonts-dejavu-extra)", file=sys.stderr)
        return 2
    font = TTFont(str(SOURCE))
    if "MATH" not in font:
        print(f"error: {SOURCE} has no OpenType MATH table", file=sys.stderr)
        return 2
    options = subset.Options()
    options.layout_features = ["ssty", "dtls", "flac", "kern"]  # script-size alternates, dotless bases, flat accents
    options.name_IDs = ["*"]
    options.name_legacy = True
    options.notdef_outline = True
    options.glyph_names = False
    options.hinting = False
    options.flavor = "woff"
    subsetter = subset.Subsetter(options)
    unicodes = [u for low, high in RANGES for u in range(low, high + 1)]
    subsetter.populate(unicodes=unicodes)
    subsetter.subset(font)
    names = font["name"]
    for record in names.names:  # the derived font's own name (GUST Font License, clause 1)
        if record.nameID in (1, 16):
            record.string = FAMILY
        elif record.nameID == 4:
            record.string = f"{FAMILY} Regular"
        elif record.nameID == 6:
            record.string = FAMILY.replace(" ", "") + "-Regular"
        elif record.nameID == 3:
            record.string = f"{FAMILY}: subset of DejaVu Math TeX Gyre 2.37"
    font.flavor = "woff"
    font.save(str(TARGET))
    print(f"wrote {TARGET} ({TARGET.stat().st_size} bytes, {len(font.getGlyphOrder())} glyphs)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
