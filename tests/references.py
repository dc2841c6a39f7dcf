"""Closed-form and high-precision reference periods shared by the period tests.

Both are computed without any code from ``solver``:

* ``elliptic_period``: the simple pendulum's exact period 4 K(k^2) sqrt(l/g),
  k = sin(a/2), via ``scipy.special.ellipkm1`` (accurate near a = pi).
* ``ex2_reference_period``: Example 2 with F_a = 0, from Eq. 44 (whose F_a
  sign does not matter here), T = 2 int_{-a}^{a} sqrt(M / (2 (V(a) - V))) by
  mpmath's tanh-sinh quadrature at 30 digits.
"""
from __future__ import annotations

import functools
import math

import mpmath
from scipy.special import ellipkm1

EX2 = dict(m_d=4.0, r_d=0.25, m_b=1.5, l_b=0.2, g=9.80665)
"""The values in data/scenes/disk_bar.toml (chosen, not the paper's), SI."""


def elliptic_period(amplitude: float, length: float, gravity: float) -> float:
    """Closed form 4 K(sin^2(a/2)) sqrt(l/g)."""
    return 4.0 * float(ellipkm1(math.cos(amplitude / 2) ** 2)) * math.sqrt(length / gravity)


def ex2_reference_period(amplitude: float, p=EX2) -> float:
    """Eq. 44 (F_a = 0): T = 2 int sqrt(M / (2 (V(a) - V))) by mpmath tanh-sinh at 30 digits.

    Computed once per process for each amplitude and set of values (about 0.09 s of CPU a
    quadrature; test_period asks for the same amplitudes in several tests)."""
    return _ex2_reference_period(float(amplitude), tuple(sorted(p.items())))


@functools.lru_cache(maxsize=None)
def _ex2_reference_period(amplitude: float, values: tuple) -> float:
    """:func:`ex2_reference_period` for ``values``, the items of its ``p``."""
    p = dict(values)
    with mpmath.workdps(30):
        md, rd, mb, lb, gg = (mpmath.mpf(repr(p[k])) for k in ("m_d", "r_d", "m_b", "l_b", "g"))
        a = mpmath.mpf(amplitude)

        def f(x):
            M = (mpmath.mpf(3) / 2 * md + mb) * rd**2 + mb * lb**2 / 3 - mb * rd * lb * mpmath.cos(x)
            dV = mb * gg * lb / 2 * (mpmath.cos(x) - mpmath.cos(a))
            # a node rounded onto an end point (integrable singularity there): contributes nothing
            return mpmath.sqrt(M / (2 * dV)) if dV > 0 else mpmath.mpf(0)

        return float(2 * mpmath.quad(f, [-a, 0, a]))
