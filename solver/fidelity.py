"""Pick the cheapest model of the period that meets a requested accuracy.

Models, cheapest first:

``"linear"``
    T0 = 2 pi sqrt(M(q_e) / V''(q_e)) (paper Eq. 46 for Example 2). Its
    relative error follows from the amplitude series of the period,
    T = T0 (1 + c2 a^2 + O(a^3)), with c2 from the scene's M and V
    (:func:`amplitude_coefficient`). It is accepted when
    ``MARGIN * |c2| a^2 <= tol`` and the series is clearly in its
    asymptotic regime (|c2| a^2 <= 1e-2, a <= 0.35 rad).
``"elliptic"``
    The closed form in complete elliptic integrals (:func:`solver.period.elliptic_period`),
    where M and V are affine in cos and sin of the coordinate with one phase
    (the pendulum, Example 2's disk-bar); exact to round-off (about 4e-15).
``"quadrature"``
    The energy integral (:func:`solver.period.exact_period`), to ``tol``.
``"integration"``
    ``solve_ivp`` (DOP853) between turning points, used only when the
    quadrature cannot converge; its error estimate is the difference
    between runs at rtol and rtol / 100.

Derivation of c2 (Landau & Lifshitz, Mechanics, section 28): with
x = q - q_e, M = m0 + m1 x + m2 x^2 + ..., V = k/2 x^2 + v3 x^3 + v4 x^4 + ...,
the coordinate s = int sqrt(M) dx has unit mass; in s the motion is
s'' + w0^2 s + e2 s^2 + e3 s^3 = 0 with w0^2 = k / m0, whose frequency is
w = w0 + (3 e3 / (8 w0) - 5 e2^2 / (12 w0^3)) A^2. Back in x this gives

    c2 = (4 k^2 m0 m2 - k^2 m1^2 - 24 k m0^2 v4 - 12 k m0 m1 v3 + 60 m0^2 v3^2)
         / (16 k^2 m0^2)

(1/16 for the simple pendulum; 1/16 + m_b r_d l_b / (8 M(0)) for Example 2).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import sympy as sp

from .errors import InputError
from .period import (TOL_MAX, TOL_MIN, Equilibrium, OneDofSystem, PeriodResult, QuadratureError, exact_period,
                     find_equilibrium, turning_points)

__all__ = ["MODELS", "MARGIN", "SeriesCoefficients", "amplitude_coefficient", "period_to_tolerance",
           "amplitude_sensitivity", "INPUT_ROUNDING"]

INPUT_ROUNDING = 2.0 ** -52
"""Relative uncertainty of an amplitude as the solver holds it: a double's rounding (2**-53) and
the degree-to-radian conversion's (another 2**-53 at most)."""

from .limits import PERIOD_MODELS as MODELS  # noqa: E402 - one place, read by --help too
# Safety factor on the leading series term: the next terms (a^3, a^4) are
# below |c2| a^2 in the accepted regime, so twice the leading term bounds them.
MARGIN = 2.0
_SERIES_LIMIT = 1e-2
_AMPLITUDE_LIMIT = 0.35
_C2_FLOOR = 1e-9
"""|c2| at or below this is taken as a vanishing leading term: the series is not trusted."""


@dataclass(frozen=True)
class SeriesCoefficients:
    """Taylor data at the equilibrium and the period's amplitude coefficient.

    Attributes
    ----------
    m0, m1, m2 : float
        M(q_e + x) = m0 + m1 x + m2 x^2 + ...
    k, v3, v4 : float
        V(q_e + x) - V(q_e) = k/2 x^2 + v3 x^3 + v4 x^4 + ...
    c2 : float
        T = T0 (1 + c2 a^2 + O(a^3)). [1/rad^2]
    """

    m0: float
    m1: float
    m2: float
    k: float
    v3: float
    v4: float
    c2: float


def _validate_amplitude_coefficient(system: OneDofSystem) -> None:
    if not isinstance(system, OneDofSystem):
        raise TypeError(f"`system` must be a OneDofSystem, got {type(system).__name__}")


def amplitude_coefficient(system: OneDofSystem, equilibrium: Equilibrium | None = None) -> SeriesCoefficients:
    """c2 of T = T0 (1 + c2 a^2 + ...) from the series of M and V about q_e (module docstring)."""
    _validate_amplitude_coefficient(system)
    eq = equilibrium if equilibrium is not None else find_equilibrium(system)
    q = system.q
    subs = dict(zip(system.params, system.values))
    M = sp.sympify(system.mass).xreplace(subs)
    V = sp.sympify(system.effective_potential()).xreplace(subs)

    def at(expr, n):
        return float(sp.diff(expr, q, n).subs(q, eq.q).evalf(30))

    m0, m1, m2 = at(M, 0), at(M, 1), at(M, 2) / 2
    k, v3, v4 = at(V, 2), at(V, 3) / 6, at(V, 4) / 24
    # the closed form divided through by k^2 m0^2 (no under/overflow for tiny or huge k, m0)
    r1, r2, s3, s4 = m1 / m0, m2 / m0, v3 / k, v4 / k
    c2 = (4 * r2 - r1**2 - 24 * s4 - 12 * r1 * s3 + 60 * s3**2) / 16
    return SeriesCoefficients(m0, m1, m2, k, v3, v4, c2)


def _validate_period_to_tolerance(system, amplitude, tol, model) -> None:
    if model not in MODELS:
        raise ValueError(f"`model` must be one of {MODELS}, got {model!r}")
    if not (TOL_MIN <= tol <= TOL_MAX):
        raise InputError(f"--tol must lie in [{TOL_MIN:g}, {TOL_MAX:g}], got {tol!r}")
    if not math.isfinite(amplitude):
        raise InputError(f"--amplitude must be a finite angle, got {amplitude!r}")


def period_to_tolerance(
    system: OneDofSystem,
    amplitude: float,
    tol: float = 1e-10,
    model: str = "auto",
    equilibrium: Equilibrium | None = None,
) -> PeriodResult:
    """The period of free oscillation from the cheapest model that meets ``tol``.

    Parameters
    ----------
    system : OneDofSystem
    amplitude : float
        Release from rest at q_e + amplitude. [rad]
    tol : float
        Requested relative accuracy.
    model : {"auto", "linear", "elliptic", "quadrature", "integration"}
        ``"auto"`` picks; the others force a model (``"linear"`` then reports
        its error estimate, which may exceed tol).

    Returns
    -------
    PeriodResult
        ``model`` and ``error_estimate`` say which model answered and how
        accurate it is estimated to be.

    Raises
    ------
    InputError
        Separatrix, non-conservative loads, bad tolerance.
    NoRestoringError
        No stable equilibrium.
    """
    _validate_period_to_tolerance(system, amplitude, tol, model)
    eq = equilibrium if equilibrium is not None else find_equilibrium(system)
    T0 = eq.period
    if model == "linear" or (model == "auto" and abs(amplitude) <= _AMPLITUDE_LIMIT
                             and MARGIN * _C2_FLOOR * amplitude**2 <= tol):
        # auto skips computing c2 where no c2 could pass: beyond _AMPLITUDE_LIMIT the series is
        # never trusted, and MARGIN |c2| a^2 <= tol would need |c2| <= _C2_FLOOR, which is refused
        if amplitude == 0.0:
            return PeriodResult(T0, T0, 1.0, 0.0, eq.q, (eq.q, eq.q), "linear", 0.0, 0, "float64")
        coeff = system._memo(("c2", system.values, eq.q), lambda: amplitude_coefficient(system, eq))
        lead = abs(coeff.c2) * amplitude**2
        regime = lead <= _SERIES_LIMIT and abs(amplitude) <= _AMPLITUDE_LIMIT and abs(coeff.c2) > _C2_FLOOR
        if model == "linear" or (regime and MARGIN * lead <= tol):
            q1, q0 = turning_points(system, eq, amplitude)  # refuses the separatrix here too
            est = MARGIN * lead if regime else max(MARGIN * lead, 1.0)
            return PeriodResult(T0, T0, 1.0, amplitude, eq.q, (q1, q0), "linear", est, 0, "float64")
    if model in ("auto", "elliptic", "quadrature"):
        try:
            return exact_period(system, amplitude, tol=tol, equilibrium=eq,
                                method="auto" if model == "auto" else model)
        except QuadratureError:
            if model == "quadrature":
                raise
    return _integrated(system, amplitude, tol, eq)


def _integrated(system: OneDofSystem, amplitude: float, tol: float, eq: Equilibrium) -> PeriodResult:
    from .simulate import period_by_integration

    q1, q0 = turning_points(system, eq, amplitude)
    rtol = max(tol / 10.0, 1e-13)
    a = period_by_integration(system, amplitude, "DOP853", rtol=rtol, equilibrium=eq)
    b = period_by_integration(system, amplitude, "DOP853", rtol=max(rtol / 100.0, 2.3e-14), equilibrium=eq)
    est = max(abs(a.period - b.period) / b.period, 2.2e-16)
    T = b.period
    return PeriodResult(T, eq.period, T / eq.period, amplitude, eq.q, (q1, q0), "integration", est,
                        a.nfev + b.nfev, "float64")


def amplitude_sensitivity(system: OneDofSystem, result, tol: float, equilibrium: Equilibrium | None = None) -> float:
    """The relative condition number of the period in the amplitude, kappa = (a / T) dT/da.

    A relative change d of the amplitude a changes the period by about kappa d; the amplitude as
    the solver holds it carries a relative rounding of :data:`INPUT_ROUNDING`, so no model can give
    the period of the amplitude as typed closer than kappa * INPUT_ROUNDING. kappa is small at
    small amplitudes (2 c2 a**2) and grows without bound towards the separatrix (T ~ -log of the
    distance to it). By a central difference of the period at a (1 +- h) (the same model and
    tolerance as ``result``), h = 1e-6, or ten times smaller until a (1 + h) stays short of the
    separatrix; its own error, relative, is about (h kappa)**2 + error / h: ample for a
    sensitivity near the separatrix, where kappa is large.
    """
    a, T = result.amplitude, result.period
    if a == 0.0:
        return 0.0

    def period_at(x):
        return period_to_tolerance(system, x, tol=tol, model=result.model, equilibrium=equilibrium).period

    h = 1e-6
    while True:
        try:
            return abs((period_at(a * (1 + h)) - period_at(a * (1 - h))) / (2 * h * T))
        except InputError:  # a (1 + h) is past the separatrix: a smaller step, down to 1e-13
            if h < 1e-12:
                raise
            h /= 10
