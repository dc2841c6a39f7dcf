"""Where the paper's assumptions about the supports hold.

Example 2 (rolling disk with a bar, Eqs. 39-40): rolling without slip needs
|F_f| <= mu F_n at every instant. Over a free oscillation released from rest
at amplitude theta0, energy conservation gives the rate as a function of the
angle alone,

    theta_dot^2(theta) = 2 (V(theta0) - V(theta)) / M(theta),

and the reactions (theta_ddot eliminated) become functions of theta alone.
:func:`least_friction` returns the least coefficient

    mu_min(theta0) = max over [theta1, theta0] of |F_f| / F_n

that keeps the disk rolling, and where along the swing it is needed;
:func:`friction_map` tabulates it against amplitude and mass ratio m_b/m_d.
If F_n would reach zero the disk would leave the floor: no mu suffices.

Example 1 (bar on two rails, Eqs. 24-25 and 28): :func:`release_window`
finds the release angles (from rest, for the scene's beta) at which every
rail reaction is >= 0, i.e. both ends stay pressed on their supports. Each
reaction is numerator / denominator (sympy ``together``); interval ends are
roots of the numerators (a reaction reaching zero) or of the denominator (a
singular configuration), found by bracketing on a fine grid and ``brentq``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Sequence

import numpy as np
import sympy as sp
from scipy.optimize import brentq, minimize_scalar

from .errors import InputError
from .strprint import lambdify
from .period import Equilibrium, OneDofSystem, find_equilibrium, turning_points

__all__ = [
    "FrictionResult",
    "FrictionMap",
    "least_friction",
    "friction_map",
    "ReleaseInterval",
    "ReleaseWindow",
    "release_window",
]


# --------------------------------------------------------------------------- Example 2
@dataclass(frozen=True)
class FrictionResult:
    """Least friction coefficient for rolling over one free oscillation.

    Attributes
    ----------
    mu_min : float
        max |F_f| / F_n over the swing (``inf`` if the disk would lift off).
    theta_at_max : float
        Angle where the maximum occurs. [rad]
    amplitude : float
        Release angle minus equilibrium. [rad]
    friction, normal : float
        F_f and F_n there. [N]
    contact : str
        The rolling constraint.
    lifts_off : bool
        True when F_n <= 0 somewhere on the swing.
    turning_points : tuple[float, float]  [rad]
    """

    mu_min: float
    theta_at_max: float
    amplitude: float
    friction: float
    normal: float
    contact: str
    lifts_off: bool
    turning_points: tuple[float, float]

    def to_dict(self) -> dict:
        return {
            "mu_min": self.mu_min if math.isfinite(self.mu_min) else None,
            "lifts_off": self.lifts_off,
            "theta_at_max": {"value": math.degrees(self.theta_at_max), "unit": "deg"},
            "amplitude": {"value": math.degrees(self.amplitude), "unit": "deg"},
            "F_f": {"value": self.friction, "unit": "N"},
            "F_n": {"value": self.normal, "unit": "N"},
            "contact": self.contact,
            "turning_points": {"value": [math.degrees(x) for x in self.turning_points], "unit": "deg"},
        }


def _validate_least_friction(system: OneDofSystem, amplitude: float, samples: int) -> None:
    if not isinstance(system, OneDofSystem):
        raise TypeError(f"`system` must be a OneDofSystem, got {type(system).__name__}")
    if not system.friction_pairs:
        raise InputError(f"{system.name}: the scene has no rolling contact; friction needs one")
    if not (math.isfinite(amplitude) and amplitude != 0):
        raise InputError(f"{system.name}: amplitude must be a non-zero finite angle, got {amplitude!r}")
    if samples < 16:
        raise ValueError(f"`samples` must be >= 16, got {samples!r}")


def least_friction(
    system: OneDofSystem,
    amplitude: float,
    samples: int = 2001,
    equilibrium: Equilibrium | None = None,
) -> FrictionResult:
    """Least mu that keeps the (first) rolling contact from slipping over a free oscillation.

    Parameters
    ----------
    system : OneDofSystem
        Needs a rolling contact (``friction_pairs``) and Q depending on q at most.
    amplitude : float
        Release from rest at q_e + amplitude. [rad]
    samples : int
        Angles sampled between the turning points (Chebyshev spacing, denser
        at the turning points); the maximum is then refined by a bounded
        scalar search.

    Returns
    -------
    FrictionResult

    Notes
    -----
    theta_dot^2 = 2 (V(q0) - V(q)) / M(q) (energy), both signs of
    theta_dot are checked; F_f and F_n from the Derivation's reactions
    (Eqs. 39-40 with theta_ddot from Eq. 44 for Example 2).
    """
    _validate_least_friction(system, amplitude, samples)
    eq = equilibrium if equilibrium is not None else find_equilibrium(system)
    q1, q0 = turning_points(system, eq, amplitude)
    release = eq.q + amplitude
    pair = system.friction_pairs[0]
    V = system.potential_fn(0)
    M = system.mass_fn()
    R = system.reactions_fn()
    V0 = float(V(release))

    def state(q):
        q = np.asarray(q, dtype=float)
        with np.errstate(all="ignore"):
            w2 = np.maximum(2.0 * (V0 - V(q)) / M(q), 0.0)
        return q, np.sqrt(w2)

    def ratio(q, sign):
        q, w = state(q)
        r = R(q, sign * w, 0.0)
        ff, fn = r[pair.friction], r[pair.normal]
        with np.errstate(all="ignore"):
            return np.where(fn > 0, np.abs(ff) / np.where(fn > 0, fn, 1.0), np.inf), ff, fn

    k = np.arange(samples)
    grid = 0.5 * (q0 + q1) - 0.5 * (q0 - q1) * np.cos(math.pi * k / (samples - 1))
    best = (-1.0, q0, 1.0, 0.0, 0.0)
    lifts = False
    for sign in (1.0, -1.0):
        rr, ff, fn = ratio(grid, sign)
        if np.any(fn <= 0):
            lifts = True
            i = int(np.argmin(fn))
            return FrictionResult(math.inf, float(grid[i]), amplitude, float(ff[i]), float(fn[i]), pair.constraint,
                                  True, (q1, q0))
        i = int(np.argmax(rr))
        # refine between the neighbouring samples
        lo, hi = grid[max(i - 1, 0)], grid[min(i + 1, samples - 1)]
        if hi > lo:
            res = minimize_scalar(lambda x: -float(ratio(np.array([x]), sign)[0][0]), bounds=(lo, hi),
                                  method="bounded", options={"xatol": 1e-12 * max(1.0, abs(q0))})
            cand = [(float(rr[i]), float(grid[i])), (-float(res.fun), float(res.x))]
        else:
            cand = [(float(rr[i]), float(grid[i]))]
        val, x = max(cand)
        if val > best[0]:
            _, ffx, fnx = ratio(np.array([x]), sign)
            best = (val, x, sign, float(ffx[0]), float(fnx[0]))
    return FrictionResult(best[0], best[1], amplitude, best[3], best[4], pair.constraint, lifts, (q1, q0))


@dataclass(frozen=True)
class FrictionMap:
    """mu_min over a grid of amplitudes and mass ratios.

    Attributes
    ----------
    amplitudes : numpy.ndarray  [rad]
    mass_ratios : numpy.ndarray
        m_b / m_d (the ``ratio_of`` parameters); [nan] when the scene's own
        masses were used (``ratio_of`` empty).
    mu_min : numpy.ndarray
        shape (len(mass_ratios), len(amplitudes)); ``inf`` where the disk lifts off.
    ratio_of : tuple[str, str] or ()
        (numerator parameter, denominator parameter), e.g. ("m_b", "m_d");
        empty when the scene has no such parameters and no ratios were asked for.
    """

    amplitudes: np.ndarray
    mass_ratios: np.ndarray
    mu_min: np.ndarray
    ratio_of: tuple[str, str] = ("m_b", "m_d")
    results: list = field(default_factory=list, repr=False)

    def to_dict(self) -> dict:
        """JSON-ready dict; ``mass_ratio`` is None when the scene's own masses were used
        (it has no ``ratio_of`` parameters and no ratios were asked for)."""
        ratio = ({"of": list(self.ratio_of), "value": [float(r) for r in self.mass_ratios]}
                 if self.ratio_of else None)
        return {
            "amplitudes": {"value": [math.degrees(a) for a in self.amplitudes], "unit": "deg"},
            "mass_ratio": ratio,
            "mu_min": [[float(v) if math.isfinite(v) else None for v in row] for row in self.mu_min],
        }


def _validate_friction_map(system: OneDofSystem, amplitudes, mass_ratios, ratio_of) -> None:
    if not isinstance(system, OneDofSystem):
        raise TypeError(f"`system` must be a OneDofSystem, got {type(system).__name__}")
    if len(list(amplitudes)) == 0:
        raise InputError("give at least one amplitude")
    if len(ratio_of) != 2 or not all(ratio_of):
        raise InputError(f"the mass ratio must name two parameters as NUM/DEN, got {'/'.join(ratio_of)!r}")
    if mass_ratios is None and not _has_ratio(system, ratio_of):
        return  # no ratio asked for: the scene's own masses are used
    for name in ratio_of:
        system.value_of(name)  # raises naming the parameters


def _has_ratio(system: OneDofSystem, ratio_of) -> bool:
    names = {p.name for p in system.params}
    return all(name in names for name in ratio_of)


def friction_map(
    system: OneDofSystem,
    amplitudes: Sequence[float],
    mass_ratios: Sequence[float] | None = None,
    ratio_of: tuple[str, str] = ("m_b", "m_d"),
    samples: int = 1001,
) -> FrictionMap:
    """mu_min(amplitude, m_b/m_d): the numerator mass is set to ratio * denominator mass.

    Raises
    ------
    InputError
        Unknown mass parameters, non-positive ratios.
    """
    _validate_friction_map(system, amplitudes, mass_ratios, ratio_of)
    amps = np.asarray([float(a) for a in amplitudes])
    if mass_ratios is None and not _has_ratio(system, ratio_of):
        eq = find_equilibrium(system)
        row = [least_friction(system, float(a), samples=samples, equilibrium=eq) for a in amps]
        return FrictionMap(amps, np.array([math.nan]), np.array([[r.mu_min for r in row]]), (), [row])
    if mass_ratios is None:
        ratios = np.array([system.value_of(ratio_of[0]) / system.value_of(ratio_of[1])])
    else:
        ratios = np.asarray([float(r) for r in mass_ratios])
    if np.any(~np.isfinite(ratios)) or np.any(ratios <= 0):
        raise InputError(f"mass ratios must be positive and finite, got {[float(r) for r in ratios]}")
    base = system.value_of(ratio_of[1])
    out = np.empty((ratios.size, amps.size))
    results = []
    for i, r in enumerate(ratios):
        s = system.with_values(**{ratio_of[0]: r * base})
        eq = find_equilibrium(s)
        row = []
        for j, a in enumerate(amps):
            res = least_friction(s, float(a), samples=samples, equilibrium=eq)
            out[i, j] = res.mu_min
            row.append(res)
        results.append(row)
    return FrictionMap(amps, ratios, out, tuple(ratio_of), results)


# --------------------------------------------------------------------------- Example 1
@dataclass(frozen=True)
class ReleaseInterval:
    """A range of release angles with every considered reaction >= 0.

    Attributes
    ----------
    low, high : float  [rad]
    low_reason, high_reason : str
        What bounds it: ``"R_A = 0"``, ``"singular"`` or ``"range"``.
    """

    low: float
    high: float
    low_reason: str
    high_reason: str


@dataclass(frozen=True)
class ReleaseWindow:
    """Release angles (from rest) at which the supports keep pressing.

    Attributes
    ----------
    intervals : tuple[ReleaseInterval, ...]
    reactions : tuple[str, ...]
    search_range : tuple[float, float]  [rad]
    """

    intervals: tuple[ReleaseInterval, ...]
    reactions: tuple[str, ...]
    search_range: tuple[float, float]

    def contains(self, theta: float) -> bool:
        return any(iv.low <= theta <= iv.high for iv in self.intervals)

    def to_dict(self) -> dict:
        return {
            "reactions": list(self.reactions),
            "search_range": {"value": [math.degrees(x) for x in self.search_range], "unit": "deg"},
            "intervals": [
                {"low": {"value": math.degrees(iv.low), "unit": "deg"},
                 "high": {"value": math.degrees(iv.high), "unit": "deg"},
                 "low_bound": iv.low_reason, "high_bound": iv.high_reason}
                for iv in self.intervals
            ],
        }


def _validate_release_window(system, reactions, search_range, samples) -> tuple[str, ...]:
    if not isinstance(system, OneDofSystem):
        raise TypeError(f"`system` must be a OneDofSystem, got {type(system).__name__}")
    names = tuple(reactions) if reactions is not None else tuple(system.reactions)
    unknown = [n for n in names if n not in system.reactions]
    if unknown or not names:
        raise InputError(
            f"{system.name}: unknown reaction(s) {', '.join(unknown) or '(none given)'}; "
            f"reactions are {', '.join(system.reactions)}"
        )
    lo, hi = search_range
    if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
        raise InputError(f"the release range must be two finite angles, low < high, got {search_range!r}")
    if samples < 16:
        raise ValueError(f"`samples` must be >= 16, got {samples!r}")
    return names


def _numerators_denominator(system: OneDofSystem, names, theta_dot: float):
    """[(name, numerator(q), denominator(q))] with reaction = numerator / denominator.

    With the Derivation's linear system: Cramer's rule, numerator det(A_i)
    (column i replaced by b) and denominator det(A), both smooth in q. Without
    it: sympy ``together`` of the reaction expression.
    """
    parts = []
    if system.system_matrix is not None:
        Ab = system.linear_system_fn()

        def dets(q, i):
            A, b = Ab(q, theta_dot, 0.0)
            if i is None:
                return np.linalg.det(A)
            Ai = A.copy()
            Ai[..., :, i] = b
            return np.linalg.det(Ai)

        for n in names:
            i = system.unknown_names.index(n)
            parts.append((n, (lambda i: (lambda q: dets(q, i)))(i), lambda q: dets(q, None)))
        return parts
    subs = dict(zip(system.params, system.values))
    for n in names:
        expr = system.reactions[n].xreplace(subs).subs({system.qd: theta_dot, system.t: 0})
        num, den = sp.fraction(sp.together(expr))
        parts.append((n, lambdify(system.q, num, "numpy"), lambdify(system.q, den, "numpy")))
    return parts


def release_window(
    system: OneDofSystem,
    reactions: Sequence[str] | None = None,
    search_range: tuple[float, float] = (0.0, math.pi),
    theta_dot: float = 0.0,
    samples: int = 7201,
) -> ReleaseWindow:
    """Release angles in ``search_range`` with every reaction in ``reactions`` >= 0.

    Parameters
    ----------
    system : OneDofSystem
    reactions : sequence of str, optional
        Default: every reaction of the system (for Example 1: R_A and R_B).
    search_range : (low, high)
        Angles searched. [rad]
    theta_dot : float
        Rate at release (0: from rest). [rad/s]
    samples : int
        Grid for bracketing sign changes.

    Returns
    -------
    ReleaseWindow
        Closed intervals; an end at a singular configuration (denominator
        zero) is reported as such (the reactions are unbounded there).

    Notes
    -----
    Example 1: R_A, R_B from Eqs. 24, 25, 28 (with omega = theta_dot).
    """
    names = _validate_release_window(system, reactions, search_range, samples)
    lo, hi = search_range
    grid = np.linspace(lo, hi, samples)
    parts = _numerators_denominator(system, names, theta_dot)

    # breakpoints: (angle, label)
    cuts: list[tuple[float, str]] = []
    for n, fnum, fden in parts:
        for f, label in ((fnum, f"{n} = 0"), (fden, "singular")):
            v = np.broadcast_to(np.asarray(f(grid), dtype=float), grid.shape)
            scale = float(np.max(np.abs(v[np.isfinite(v)]), initial=0.0)) or 1.0
            tiny = 1e-13 * scale
            s = np.sign(np.where(np.abs(v) <= tiny, 0.0, v))
            for i in range(samples - 1):
                if s[i] * s[i + 1] < 0:
                    r = brentq(lambda x: float(f(x)), grid[i], grid[i + 1], xtol=1e-15, rtol=1e-15, disp=False)
                    cuts.append((float(r), label))
                elif s[i] == 0 and (i == 0 or s[i - 1] != 0):
                    cuts.append((float(grid[i]), label))

    def ok(x: float) -> bool:
        for _, fnum, fden in parts:
            d = float(fden(x))
            if d == 0:
                return False
            if float(fnum(x)) * d < 0:
                return False
        return True

    cuts.sort()
    edges = [(lo, "range")] + cuts + [(hi, "range")]
    intervals: list[ReleaseInterval] = []
    for (a, ra), (b, rb) in zip(edges[:-1], edges[1:]):
        if b <= a:
            continue
        if ok(0.5 * (a + b)):
            if intervals and intervals[-1].high == a and ra != "singular":
                # a reaction touches zero without changing sign there: one interval
                prev = intervals.pop()
                intervals.append(ReleaseInterval(prev.low, b, prev.low_reason, rb))
            else:
                intervals.append(ReleaseInterval(a, b, ra, rb))
    return ReleaseWindow(tuple(intervals), names, (lo, hi))
