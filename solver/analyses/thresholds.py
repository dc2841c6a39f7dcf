"""Where motion starts from rest: the threshold of a coordinate or a parameter.

At rest, a contact regime other than sticking everywhere (slipping from rest,
a contact opening, tipping about a corner) *starts* when it becomes
consistent (:mod:`solver.analyses.regimes`): its normal forces press, its
impending slips accelerate the way they slide against mu_s N, and its opening
gaps accelerate apart. Each of those conditions is a smooth function of a
chosen quantity (a coordinate such as a ladder's angle, or a parameter such
as a push force), so the onset of each regime is a root of the smallest of
them, found by a scan and ``scipy.optimize.brentq`` to round-off. Examples:
the ladder's critical angle tan(theta) = (1 - mu_A mu_B)/(2 mu_A), the push
that slides a crate (mu_s m g) or tips it (m g w / (2 h)).
"""
from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np
import sympy as sp

from ..errors import InputError, SceneError
from ..strprint import lambdify
from ..model.contacts import SEPARATED, STICK, Slip
from .instant import CONDITION_LIMIT, solve_with_estimate

__all__ = ["Onset", "onsets", "regime_at_rest", "MAX_SCAN"]

MAX_SCAN = 2001
"""Most scan points of one search."""


@dataclass
class Onset:
    """A regime that becomes consistent (``starts``) or stops being so at ``value``."""

    regimes: dict
    value: float
    starts: bool

    @property
    def label(self) -> str:
        return ", ".join(f"{n}: {r.label}" for n, r in self.regimes.items())

    def to_dict(self, unit: str) -> dict:
        return {"regimes": {n: r.label for n, r in self.regimes.items()}, "value": self.value, "unit": unit,
                "starts": self.starts}


def onsets(system, name: str, low: float, high: float, scan: int = 201) -> list[Onset]:
    """Every value of ``name`` in [low, high] (SI) at which a motion from rest starts or stops being possible.

    Parameters
    ----------
    system : System
        The scene (its state supplies every other coordinate; rates are zero).
    name : str
        An independent coordinate or a parameter.

    Raises
    ------
    InputError
        Unknown name, a coordinate that is dependent or prescribed, a scene
        with dependent coordinates, or a bad range.
    """
    from .regimes import start_state

    if not (math.isfinite(low) and math.isfinite(high) and low < high):
        raise InputError(f"--between: expected LOW < HIGH, got {low!r} .. {high!r}")
    if not (2 <= scan <= MAX_SCAN):
        raise InputError(f"--scan must lie in 2..{MAX_SCAN}, got {scan!r}")
    coords = [c.name for c in system.free]
    if name not in coords and name not in system.parameters:
        raise InputError(f"{system.label}: --critical {name}: not a coordinate or a parameter "
                         f"(coordinates: {', '.join(coords)}; parameters: {', '.join(system.parameters)})")
    if system.dependent or any(c.prescribed for c in system.coordinates):
        raise InputError(f"{system.label}: --critical needs a scene whose coordinates are all free and independent")
    if not system.contacts:
        raise InputError(f"{system.label}: --critical: the scene has no contact with friction or a one-sided force")
    st = start_state(system)
    q = np.array(st.q, float)
    grid = np.linspace(low, high, scan)
    out = []
    for regimes in _motion_regimes(system):
        try:
            margin = _margin_function(system, regimes, name, q, st.t)
        except SceneError:
            continue  # the scene's coordinates cannot describe this motion
        values = margin(grid)
        for k in range(scan - 1):
            a, b = values[k], values[k + 1]
            if np.isfinite(a) and np.isfinite(b) and (a < 0) != (b < 0):
                from scipy.optimize import brentq

                root = brentq(lambda v: float(margin(np.array([v]))[0]), grid[k], grid[k + 1],
                              xtol=1e-15 * max(1.0, abs(grid[k])), rtol=4 * np.finfo(float).eps)
                out.append(Onset(regimes, float(root), bool(b >= 0)))
    return sorted(out, key=lambda o: o.value)


def regime_at_rest(system, name: str, value: float):
    """The regime that holds at rest with ``name`` (a coordinate or a parameter) at ``value`` (SI).

    The other coordinates keep the scene's values, every rate is zero, as in
    :func:`onsets`. Where :func:`onsets` finds no onset in a range, this regime
    holds throughout it.

    Returns
    -------
    RegimeResult
        See :func:`solver.analyses.regimes.find_regime`.

    Raises
    ------
    NoConsistentRegime, AmbiguousRegime
        As :func:`~solver.analyses.regimes.find_regime`.
    """
    from ..units import Q_
    from .regimes import find_regime, start_state

    st = start_state(system)
    q = list(st.q)
    names = [c.name for c in system.free]
    if name in names:
        q[names.index(name)] = float(value)
        at = system
    else:  # a copy with the parameter changed, its SI value in the parameter's base units
        at = system.copy()
        at.parameters[name] = Q_(float(value), (1 * system.parameters[name]).to_base_units().units)
    return find_regime(at, q, [0.0] * len(q), st.t)


def _motion_regimes(system):
    """Every combination of regimes at rest except holding everywhere (slips are impending)."""
    options = []
    for j in system.contacts:
        opts = [STICK if j.friction is not None else j.current_regime]
        if j.friction is not None:
            opts += [Slip(1, impending=True), Slip(-1, impending=True)]
        if j.normal_reaction.one_sided:
            opts.append(SEPARATED)
        options.append([(j.name, r) for r in opts])
    holding = tuple(o[0] for o in options)
    for combo in itertools.product(*options):
        if combo != holding:
            yield dict(combo)


def _margin_function(system, regimes, name, q, t):
    """The smallest (scaled) consistency condition of ``regimes`` at rest, as a vectorised function of
    ``name``, from the system with every contact formulated once (:class:`solver.analyses.regimes._Augmented`)."""
    from .regimes import GAP_TOL, NotDescribable, _augmented

    aug = _augmented(system, None, "generalized_euler")
    rows, names, mods = aug.select(regimes)
    if len(rows) != len(names):
        raise NotDescribable(f"{system.label}: the scene's coordinates do not describe this motion")
    if len(aug.qdd) <= len(rows) - len(aug.body_rows):
        raise SceneError(f"{system.label}: no freedom is left: not a motion")
    variant = aug.variant
    A, b = aug.model.formulation.linear_system()
    values = variant.si_values()
    x_sym = sp.Symbol(name, real=True)
    state = {c.q: v for c, v in zip(variant.free, q)}
    subs = {**{p: v for p, v in values.items() if str(p) != name}, **{k: v for k, v in state.items() if str(k) != name},
            **{s: 0 for s in variant.qd}, variant.t: t}
    m, k_all = A.shape
    fAb = lambdify(x_sym, [sp.sympify(e).xreplace(subs) for e in list(A) + list(b)], "numpy")
    fmods = lambdify(x_sym, [e.xreplace(subs) for _, _, e in mods] or [0], "numpy")
    pose = variant._pose_fn(variant.poses)
    qdd_syms = list(variant.qdd)
    conds = []  # (kind, index or expression)
    for j in variant.contacts:
        r = regimes[j.name]
        Pt, Pn = (variant.prescribe(sp.sympify(e)) for e in j.contact_rows(pose))
        if r is SEPARATED:
            conds.append(("gap", [Pn.xreplace(subs), variant.D(variant.D(Pn)).xreplace(subs)]))
            continue
        F, N = j.pair
        conds.append(("normal", names.index(N.name)))
        if r == STICK and j.friction is not None:
            conds.append(("cone", (names.index(F.name), names.index(N.name), sp.sympify(j.friction.static).xreplace(subs))))
        elif r.friction_direction():
            conds.append(("slide", (r.friction_direction(), variant.D(variant.D(Pt)).xreplace(subs))))
    kin_exprs = []
    for kind, data in conds:
        if kind == "gap":
            kin_exprs += data
        elif kind == "slide":
            kin_exprs.append(data[1])
        elif kind == "cone":
            kin_exprs.append(data[2])
    fkin = lambdify((x_sym, *qdd_syms), kin_exprs, "numpy")

    def square(v):
        vals = [np.broadcast_to(np.asarray(e, float), v.shape) for e in fAb(v)]
        Af = np.stack(vals[: m * k_all], axis=-1).reshape(v.shape + (m, k_all))
        bf = np.stack(vals[m * k_all:], axis=-1)
        factors = [np.broadcast_to(np.asarray(e, float), v.shape) for e in fmods(v)]
        for (n, f, _), factor in zip(mods, factors):  # a slide's friction column folded in, per value
            i, jf = aug.names.index(n), aug.names.index(f)
            Af[..., :, i] += factor[..., None] * Af[..., :, jf]
        return aug.pick(Af, bf, rows, names, [])

    def margin(v):
        v = np.asarray(v, float)
        Am, bm = square(v)
        x, cond = solve_with_estimate(Am, bm)  # the solver's one singularity decision:
        x[~(cond <= CONDITION_LIMIT)] = np.nan  # past it the regime does not determine the motion
        qdd = [x[..., names.index(str(s))] for s in qdd_syms]
        kin = [np.broadcast_to(np.asarray(e, float), v.shape) for e in fkin(v, *qdd)]
        nreact = len(names) - len(qdd_syms)
        fscale = np.max(np.abs(x[..., len(qdd_syms):]), axis=-1) + 1e-300 if nreact else np.ones(v.shape)
        ascale = 1.0 + np.max(np.abs(np.stack(qdd, -1)), axis=-1) if qdd else np.ones(v.shape)
        out = np.full(v.shape, np.inf)
        k = 0
        for kind, data in conds:
            if kind == "gap":
                gap, acc = kin[k], kin[k + 1]
                k += 2
                value = np.where(gap > GAP_TOL, np.inf, acc / ascale)  # an open gap sets no condition
            elif kind == "normal":
                value = x[..., data] / fscale
            elif kind == "cone":
                iF, iN, _ = data
                value = (kin[k] * x[..., iN] - np.abs(x[..., iF])) / fscale
                k += 1
            else:
                value = data[0] * kin[k] / ascale
                k += 1
            out = np.minimum(out, value)
        return out

    return margin
