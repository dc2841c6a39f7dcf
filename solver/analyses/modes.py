"""Equilibrium and small oscillations of a system with any number of degrees of freedom.

At rest (every rate zero) the instantaneous solve gives the accelerations
u'' = g(u) of the independent coordinates u (dependent ones follow from the
closure equations). An equilibrium solves g(u_e) = 0; linearising,
u'' = J (u - u_e) with J = dg/du, and the natural frequencies are
omega_i = sqrt(lambda_i) for the eigenvalues lambda_i of -J (= M^-1 K), the
mode shapes its eigenvectors. Every load that depends on position only is
included (gravity, springs, constant forces and couples); dampers vanish at
rest; loads that depend on time have no equilibrium and are refused. With a
motion prescribed in time (an arm turned at a constant rate) and one free
coordinate, the equilibrium is relative to that motion: it is accepted when
it is one at every time, the equations in the moving frame being free of t
(a collar on a turning arm with a spring to the hub: r_e = k L0 / (k - m W^2),
omega_n^2 = k/m - W^2); otherwise refused, saying why.

J is taken by fourth-order central differences of g (step 1e-3 of each
coordinate's scale), whose truncation error, h^4 g^(5) / 30 ~ 1e-13 relative,
and round-off, eps |g| / h ~ 1e-13, keep the frequencies to about 1e-11.

With several coordinates the equilibrium is the stable one nearest the state among those
found by Newton's method on g and by a descent of the potential energy to the bottom of the
well the state lies in, each also with its angles moved by whole turns towards the state
(:func:`_nearest_stable`); Newton alone may end at a saddle or a maximum. For one coordinate without closure equations the equilibrium comes from
:func:`solver.period.find_equilibrium` (a scan of the effective potential,
robust to any starting state), so ``frequency`` and ``period`` agree.
"""
from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
import sympy as sp

from ..errors import InputError, NoRestoringError
from .instant import assemble

__all__ = ["Mode", "ModesResult", "modes"]

EQUILIBRIUM_RESOLUTION = 1e-12
"""An equilibrium coordinate is found to about this fraction of its scale (1 rad; a length's own size,
at least 0.1 m): Newton's residual test is 1e-12 of the accelerations. Nearer 0 it is 0, and its
digits below it are round-off, not printed (:meth:`ModesResult.equilibrium_in`)."""
_STEP = 1e-3
_NEWTON = 50
_DESCENT = 200  # steps of _descend (each a Jacobian: 4 n + 1 evaluations of u'')


@dataclass
class Mode:
    """One natural mode: angular frequency [rad/s] and shape (largest component 1), each component
    in its coordinate's SI unit (:attr:`ModesResult.units`: an x of 0.06 beside a theta of 1 is
    0.06 m per rad)."""

    omega: float
    shape: dict[str, float]

    @property
    def frequency(self) -> float:
        return self.omega / (2 * math.pi)

    @property
    def period(self) -> float:
        return 2 * math.pi / self.omega if self.omega > 0 else math.inf


@dataclass
class ModesResult:
    """Small oscillations about a stable equilibrium.

    Attributes
    ----------
    equilibrium : dict[str, float]
        Every free coordinate's value there (SI).
    modes : list of Mode
        Ascending frequencies; a neutral direction (no restoring force, e.g. a
        free cart's position) has omega = 0.
    units : dict[str, str]
        Coordinate units.
    resolution : dict[str, float]
        Each coordinate's round-off distance (SI): :data:`EQUILIBRIUM_RESOLUTION` of its scale,
        the digits of the equilibrium below it are not printed (:meth:`equilibrium_in`).
    """

    equilibrium: dict[str, float]
    modes: list[Mode]
    units: dict[str, str]
    resolution: dict[str, float] = field(default_factory=dict)

    def to_dict(self, units: Mapping[str, str] | None = None) -> dict:
        """JSON-ready dict; ``units``: the scene's ``[output_units]``, in which each shape is given
        (:meth:`shape_in`)."""
        coords = self.equilibrium_in(units)
        return {
            "equilibrium": coords,
            "equilibrium_coordinates": coords,
            "modes": [
                {"omega_n": {"value": m.omega, "unit": "rad/s"},
                 "frequency": {"value": m.frequency, "unit": "Hz"},
                 "period": {"value": m.period if math.isfinite(m.period) else None, "unit": "s"},
                 "shape": self.shape_in(m, units)}
                for m in self.modes
            ],
        }

    def equilibrium_in(self, units: Mapping[str, str] | None) -> dict:
        """Each coordinate's equilibrium ``{"value", "unit"}`` in its output unit, rounded at its
        :attr:`resolution` there (:func:`solver.output_units.rounded_at`): the spring's rest length of
        1 ft, solved as -0.3047999999999994 m, reads -1 ft, not -0.999999999999998 ft."""
        from solver.output_units import in_output_units, rounded_at

        out = {}
        for k, v in self.equilibrium.items():
            value, unit = in_output_units(v, self.units[k], units)
            factor = abs(in_output_units(1.0, self.units[k], units)[0])
            out[k] = {"value": rounded_at(value, self.resolution.get(k, 0.0) * factor), "unit": unit}
        return out

    def shape_in(self, mode: Mode, units: Mapping[str, str] | None) -> dict:
        """``mode``'s shape as printed: each component in its coordinate's output unit
        (:func:`solver.output_units.to_output_units`), scaled again so that the largest printed
        component is 1 (in SI 1 m beside 0.89 rad prints as 3.281 ft beside 0.89 rad; here 1 ft
        beside 0.27 rad)."""
        from solver.output_units import to_output_units

        shape = to_output_units({k: {"value": v, "unit": self.units[k]} for k, v in mode.shape.items()}, units)
        largest = max((e["value"] for e in shape.values()), key=abs, default=0.0)
        if largest:
            shape = {k: {**e, "value": e["value"] / largest} for k, e in shape.items()}
        return shape


def _accelerations(system, method, t=None):
    """g(u): independent accelerations at rest at time ``t`` (the scene's by default), u -> u''."""
    from ..formulations import formulate

    model = formulate(system, method).numeric()
    free = system.free
    ind = [i for i, c in enumerate(free) if not c.dependent]
    names = [str(free[i].qdd) for i in ind]
    t = system.time if t is None else t

    last = [c.value for c in free]  # continuation: dependent coordinates start from the last solution

    def g(u):
        q = list(last)
        for k, i in enumerate(ind):
            q[i] = u[k]
        state = assemble(system, q, [0.0] * len(free), t)
        last[:] = state.q
        res = model.solve(state.q, state.qd, t)
        return np.array([float(res[n]) for n in names])
    return g, ind


def _jacobian(g, u, scales):
    n = len(u)
    J = np.empty((n, n))
    for j in range(n):
        h = _STEP * scales[j]
        e = np.zeros(n)
        e[j] = h
        J[:, j] = (-g(u + 2 * e) + 8 * g(u + e) - 8 * g(u - e) + g(u - 2 * e)) / (12 * h)
    return J


def _check_time_independent(system):
    """Refuse a load that depends on time; with motion prescribed in time, where every load moves
    with it, :func:`_check_autonomous` decides instead (one free coordinate only)."""
    t = system.t
    for a in ([] if system.time_dependent else system.applied_loads):
        exprs = [a.couple] + ([] if a.force is None else list(a.force))
        if any(sp.sympify(e).has(t) for e in exprs):
            raise InputError(f"{system.label}: load {a.name!r} depends on time, so there is no equilibrium to "
                             "oscillate about (set it to zero with --set)")
    if system.time_dependent and len([c for c in system.free if not c.dependent]) > 1:
        raise InputError(f"{system.label}: the motion is prescribed as a function of time, and the rates of "
                         "several free coordinates couple through it (Coriolis terms): `frequency` gives "
                         "small oscillations relative to a prescribed motion for one free coordinate only")


_LATER = (0.7071, 1.7321, 3.1416)
"""Time offsets [s] at which a relative equilibrium is tested again (:func:`_check_autonomous`):
three unrelated ones, so that no prescribed motion of a plausible rate repeats at all three."""


def _check_autonomous(system, method, u, J, scales):
    """Refuse an equilibrium ``u`` (Jacobian ``J``) of a system with motion prescribed in time
    unless it is one at every time: the accelerations at rest vanish there and ``J`` is the same
    at each offset of :data:`_LATER`. Then the equations relative to the prescribed motion do not
    depend on time (an arm turned at a constant rate, with nothing fixed in the ground acting
    on what it carries) and the small oscillations about ``u`` are exact in that frame.

    The tolerances: g(u) of an equilibrium is round-off of the instantaneous solve (about 1e-12
    of the accelerations' scale |J| x scale), and ``J`` by differences is good to about 1e-11
    (module docstring); 1e-7 is far above both and far below any real time dependence."""
    size = float(np.max(np.abs(J) * scales[np.newaxis, :])) or 1.0
    for dt in _LATER:
        g, _ = _accelerations(system, method, system.time + dt)
        if np.max(np.abs(g(u))) > 1e-7 * size or np.max(np.abs(_jacobian(g, u, scales) - J)) > 1e-7 * np.max(np.abs(J)):
            raise InputError(f"{system.label}: the prescribed motion makes the equations of motion depend on "
                             "time (the loads or the geometry change along it, not only its rate): there is no "
                             "equilibrium, even relative to it, to oscillate about (`simulate` gives the motion)")


def modes(system, method: str = "generalized_euler") -> ModesResult:
    """Equilibrium nearest the scene's state and the natural modes about it.

    Raises
    ------
    NoRestoringError
        No stable equilibrium near the state.
    InputError
        No degrees of freedom, or loads that depend on time.
    """
    free = system.free
    ind = [c for c in free if not c.dependent]
    if not ind:
        raise InputError(f"{system.label}: no degrees of freedom (every motion is prescribed): no oscillation")
    _check_time_independent(system)
    g, idx = _accelerations(system, method)
    scales = np.array([1.0 if c.kind == "angle" else max(abs(c.value), 0.1) for c in ind])
    u = np.array([c.value for c in ind], dtype=float)
    if len(ind) == 1 and not system.closure and not system.time_dependent:
        u = np.array([_one_dof_equilibrium(system, method, u[0])])
    elif len(ind) == 1 and ind[0].kind == "angle":
        u = np.array([_scan_one_angle(g, u[0], system)])
    else:
        u = _nearest_stable(g, u, scales, system, np.array([c.kind == "angle" for c in ind]))
    J = _jacobian(g, u, scales)
    lam, vec = np.linalg.eig(-J)
    tries = 0
    while np.any(lam.real < -1e-9 * max(1.0, float(np.max(np.abs(lam))))) and tries < 8:
        # an unstable equilibrium: step off it along an unstable direction and search again
        k = int(np.argmin(lam.real))
        direction = vec[:, k].real / np.max(np.abs(vec[:, k].real))
        step = (0.5 * (1 + tries // 2)) * (1 if tries % 2 == 0 else -1)
        try:
            u_new = _newton(g, u + step * direction * scales, scales, system)
        except NoRestoringError:
            tries += 1
            continue
        u = u_new
        J = _jacobian(g, u, scales)
        lam, vec = np.linalg.eig(-J)
        tries += 1
    if system.time_dependent:  # an equilibrium relative to the prescribed motion, if the motion allows one
        _check_autonomous(system, method, u, J, scales)
    if np.max(np.abs(lam.imag)) > 1e-6 * max(1.0, np.max(np.abs(lam.real))):
        raise NoRestoringError(f"{system.label}: the linearised motion about the equilibrium is not oscillatory "
                               "(complex eigenvalues)")
    lam = lam.real
    vec = vec.real
    # along a neutral direction (a free cart's x) every point is an equilibrium: the state's
    # own value, not where Newton's round-off left it (x = -3.7e-13 m for x = 0)
    u = _back_along_neutral(g, u, np.array([c.value for c in ind], dtype=float), scales, system)
    tol = 1e-9 * max(1.0, float(np.max(np.abs(lam))))
    # an equilibrium at round-off distance from 0 is 0
    eq = {c.name: (0.0 if abs(x) < EQUILIBRIUM_RESOLUTION * sc else float(x)) for c, x, sc in zip(ind, u, scales)}
    if np.any(lam < -tol):
        raise NoRestoringError(
            f"{system.label}: the equilibrium found near the state ("
            + ", ".join(f"{name} = {v:.6g}" for name, v in eq.items())
            + ") is unstable: no small oscillations about it")
    if np.all(np.abs(lam) <= tol):
        raise NoRestoringError(f"{system.label}: no restoring force in any coordinate: no small oscillations")
    order = np.argsort(lam)
    out = []
    for k in order:
        v = vec[:, k]
        v = v / v[np.argmax(np.abs(v))]
        v = np.where(np.abs(v) < 1e-12, 0.0, v)  # round-off of an uncoupled direction
        omega = math.sqrt(max(lam[k], 0.0)) if abs(lam[k]) > tol else 0.0
        out.append(Mode(omega, {c.name: float(x) for c, x in zip(ind, v)}))
    return ModesResult(eq, out, {c.name: c.unit for c in ind},
                       {c.name: EQUILIBRIUM_RESOLUTION * sc for c, sc in zip(ind, scales)})


def _unstable(J) -> bool:
    """True when u'' = J (u - u_e) has a direction that runs away: an eigenvalue of -J (omega^2)
    below -1e-9 of the largest in size (the test :func:`modes` applies to the equilibrium it keeps)."""
    lam = np.linalg.eigvals(-J)
    return bool(np.any(lam.real < -1e-9 * max(1.0, float(np.max(np.abs(lam))))))


def _nearest_stable(g, u0, scales, system, angles):
    """The stable equilibrium nearest ``u0`` of several coordinates, among Newton's root from u0,
    the bottom of the well u0 lies in (:func:`_descend`) and Newton's roots from these two with
    their angles (``angles``, a mask) moved by whole turns towards u0 (the same configuration
    where the loads repeat over a turn): the nearest stable one (in coordinate scales), or
    Newton's root when none is stable (:func:`modes` steps off it).

    Newton alone converges to whichever equilibrium its steps reach, a saddle or a maximum as
    readily as a minimum (a double pendulum from (20, -40) deg reached (0, -180) deg).
    """
    found = []
    for search in (_newton, _descend):
        try:
            found.append(search(g, np.array(u0, dtype=float), scales, system))
        except NoRestoringError:
            continue
    if not found:
        raise NoRestoringError(f"{system.label}: no equilibrium found near the scene's state")
    for u in list(found):
        turns = np.where(angles, np.round((u0 - u) / (2 * math.pi)), 0.0)
        if np.any(turns):
            try:
                found.append(_newton(g, u + 2 * math.pi * turns, scales, system))
            except NoRestoringError:
                continue
    stable = [u for u in found if not _unstable(_jacobian(g, u, scales))]
    return min(stable or found[:1], key=lambda u: float(np.linalg.norm((u - u0) / scales)))


def _descend(g, u0, scales, system):
    """The bottom of the potential well that ``u0`` lies in.

    Follows u' = g(u), the motion from rest under a damping that swamps inertia, along which
    the potential energy only falls, so that it ends in a minimum, not at a saddle or a
    maximum: pseudo-transient continuation (Kelley and Keyes 1998), linearly implicit Euler
    steps u += (I / h - J)^-1 g(u). h doubles after each step, so that the steps become
    Newton's where no direction is unstable, and halves after a step too long to trust (over a
    quarter of a coordinate's scale, then cut to that). Where a direction is unstable (an
    eigenvalue of J with real part mu > 0), h <= 1 / (2 mu) keeps the step going down the
    slope, away from the saddle; started on the saddle (or a maximum) itself, where g is
    round-off (steps under 1e-10 of the scales), a step of 1e-3 of the scales leaves it along
    the fastest unstable direction. Newton's method (:func:`_newton`) finishes once no
    direction is unstable and the steps are under 1e-3 of the scales, and the equilibrium is
    taken back along its neutral directions (:func:`_back_along_neutral`).
    """
    n, u = len(u0), u0
    h = None
    for _ in range(_DESCENT):
        r = g(u)
        J = _jacobian(g, u, scales)
        mu, ways = np.linalg.eig(J)
        size = float(np.max(np.abs(mu)))
        if not (size > 0 and np.all(np.isfinite(r))):
            break
        h = 0.1 / size if h is None else h
        fastest = float(np.max(mu.real))
        if fastest > 1e-9 * size:
            h = min(h, 0.5 / fastest)
        step = np.linalg.solve(np.eye(n) / h - J, r)
        if fastest > 1e-9 * size and np.max(np.abs(step) / scales) < 1e-10:  # on a saddle or a maximum
            way = ways[:, int(np.argmax(mu.real))].real  # (g round-off there): off it the fastest way down
            step = 1e-3 * scales * way / np.max(np.abs(way))
        longest = float(np.max(np.abs(step) / scales))
        if longest > 0.25:
            step, h = step * (0.25 / longest), 0.5 * h
        else:
            h = 2.0 * h
        u = u + step
        if fastest <= 1e-9 * size and longest < 1e-3:
            return _back_along_neutral(g, _newton(g, u, scales, system), u0, scales, system)
    raise NoRestoringError(f"{system.label}: no equilibrium found near the scene's state")


def _back_along_neutral(g, u, u0, scales, system):
    """The equilibrium ``u`` moved along its neutral directions (those J does not change g
    along: a free cart's position) to the point nearest ``u0`` (in coordinate scales), then
    Newton's; ``u`` itself if Newton fails there. The descent drifts along them as the
    coordinates it falls in pull them (the cart moves as the pendulum falls), though every
    point along them is as much an equilibrium."""
    J = _jacobian(g, u, scales) * scales[np.newaxis, :]  # d g / d (u / scales)
    _, sigma, vt = np.linalg.svd(J)
    neutral = vt[sigma <= 1e-9 * max(float(sigma[0]), 1e-300)]
    if not len(neutral):
        return u
    back = u + scales * (neutral.T @ (neutral @ ((u0 - u) / scales)))
    try:
        return _newton(g, back, scales, system)
    except NoRestoringError:
        return u


def _newton(g, u, scales, system):
    for _ in range(_NEWTON):
        r = g(u)
        if np.all(np.abs(r) < 1e-12 * (1 + np.abs(r).max())):
            return u
        J = _jacobian(g, u, scales)
        step, *_ = np.linalg.lstsq(J, -r, rcond=1e-10)
        step = np.clip(step, -0.5 * scales, 0.5 * scales)
        u = u + step
        if not np.all(np.isfinite(u)):
            break
        if np.all(np.abs(step) < 1e-14 * scales):
            return u
    if np.all(np.abs(g(u)) < 1e-9):
        return u
    raise NoRestoringError(f"{system.label}: no equilibrium found near the scene's state")


def _one_dof_equilibrium(system, method, near):
    from ..derivation import derive
    from ..period import OneDofSystem, find_equilibrium

    return find_equilibrium(OneDofSystem.from_derivation(derive(system, None, method), reactions=False),
                            near=near).q


def _scan_one_angle(g, u0, system):
    """The stable equilibrium nearest u0 of one angle coordinate with closure equations:
    a scan of u'' = g(u) over u0 +/- pi (continuing the assembly) for sign changes from + to -."""
    from scipy.optimize import brentq

    def f(x):
        return float(g(np.array([x]))[0])

    found = []
    for sign in (1, -1):  # walk away from u0 both ways so the assembly follows continuously
        grid = u0 + sign * np.linspace(0.0, math.pi, 181)
        vals = []
        for x in grid:
            try:
                vals.append(f(x))
            except InputError:
                break
        for i in range(len(vals) - 1):
            a, b = (grid[i], grid[i + 1]) if sign > 0 else (grid[i + 1], grid[i])
            fa, fb = (vals[i], vals[i + 1]) if sign > 0 else (vals[i + 1], vals[i])
            if fa > 0 >= fb:
                f(grid[i])  # restore the assembly near the bracket
                found.append(brentq(f, a, b, xtol=1e-14, rtol=1e-15))
                break
    if not found:
        raise NoRestoringError(f"{system.label}: no stable equilibrium within pi of the state")
    return min(found, key=lambda x: abs(x - u0))
