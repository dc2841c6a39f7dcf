"""Time histories of a one-degree-of-freedom scene by ``scipy.integrate.solve_ivp``.

The state is y = (theta, theta_dot); the right-hand side is the compiled
(lambdified with common subexpressions) theta_ddot of the equation of motion
M(q) q'' + 1/2 M'(q) q'^2 + V'(q) = Q(q, q', t) (for Example 2 the paper's
Eq. 44 with the sign of F_a corrected). After the run the dense output is
sampled and the angular acceleration alpha, every reaction (with theta_ddot
eliminated, Eqs. 39-40 for Example 2, Eqs. 24-25 and 28 for Example 1) and the
mechanical energy are evaluated on the samples.

Terminal events stop a run when

* a one-sided reaction (a rolling contact's normal force, or a constraint
  marked ``one_sided``) would turn negative: the body leaves its support;
* a rolling contact would need more friction than it has:
  |F_f| > mu F_n (mu from the constraint's ``friction_coefficient`` or the
  ``mu`` argument);
* a rolling semicircular disk's contact point reaches the end of its curved
  rim (``OneDofSystem.limits``): past it the model does not hold.

The result says why the run stopped.
"""
from __future__ import annotations

import csv
import math
import os
import sys
from dataclasses import dataclass, field
from pathlib import Path
from types import SimpleNamespace
from typing import Any, Callable, Mapping

import numpy as np
import sympy as sp
from scipy.integrate import DOP853, DenseOutput, solve_ivp

from .errors import InputError
from .files import write_atomic
from .period import Equilibrium, OneDofSystem, find_equilibrium
from .strprint import lambdify

__all__ = [
    "METHODS",
    "StopEvent",
    "SimulationResult",
    "simulate",
    "period_by_integration",
    "write_csv",
    "MAX_T_END",
    "MAX_PERIODS",
    "MAX_SAMPLES",
    "MAX_RHS_EVALUATIONS",
]

# Caps on the work one run may ask for (stated in ``simulate --help`` and the README);
# they live in solver.limits so that the command line's --help reads them without scipy.
from .limits import IVP_METHODS as METHODS  # noqa: E402
from .limits import MAX_PERIODS, MAX_RHS_EVALUATIONS, MAX_SAMPLES, MAX_T_END  # noqa: E402,F401


class _TooManySteps(Exception):
    """Raised inside the integrator when a run exceeds :data:`MAX_RHS_EVALUATIONS`."""

    def __init__(self, t: float):
        super().__init__(t)
        self.t = t


@dataclass(frozen=True)
class StopEvent:
    """Why and where a run stopped early.

    Attributes
    ----------
    kind : str
        ``"lost_contact"`` (a one-sided reaction reached zero), ``"slip"``
        (|F_f| reached mu F_n), ``"singular"`` (the constraints stop
        determining the motion) or ``"model_limit"`` (a semicircular disk's
        contact point reached the end of its curved rim).
    reaction : str
        The reaction concerned (the normal force for a slip; for
        ``"model_limit"`` the condition that stopped holding).
    constraint : str
    time : float  [s]
    theta, theta_dot : float  [rad], [rad/s]
    """

    kind: str
    reaction: str
    constraint: str
    time: float
    theta: float
    theta_dot: float


@dataclass(frozen=True)
class SimulationResult:
    """Sampled time history of a run.

    Attributes
    ----------
    t, theta, theta_dot, theta_ddot, alpha, energy : numpy.ndarray
        [s], [rad], [rad/s], [rad/s^2], [rad/s^2], [J].
    reactions : dict[str, numpy.ndarray]
        Every reaction on the samples. [N or N m]
    reaction_units : dict[str, str]
    status : str
        ``"completed"``, ``"lost_contact"``, ``"slip"``, ``"singular"``, ``"model_limit"`` or ``"failed"``.
    reason : str
        One sentence: why the run stopped.
    event : StopEvent or None
    method : str
    rtol, atol : float
    nfev : int
        Right-hand-side evaluations of the integration (with DOP853, the three more that
        each sampled step's interpolant takes are not counted).
    sol : callable or None
        Dense output y(t) of the integrator.
    """

    t: np.ndarray
    theta: np.ndarray
    theta_dot: np.ndarray
    theta_ddot: np.ndarray
    alpha: np.ndarray
    reactions: dict[str, np.ndarray]
    energy: np.ndarray
    reaction_units: dict[str, str]
    status: str
    reason: str
    event: StopEvent | None
    method: str
    rtol: float
    atol: float
    nfev: int
    sol: Any = field(default=None, repr=False)
    conserved: np.ndarray | None = field(default=None, repr=False)
    kinetic_max: float = 0.0

    @property
    def energy_drift(self) -> float | None:
        """max |H - H(0)| on the samples, relative to the largest kinetic energy of the run.

        H = 1/2 M qd^2 + V_eff(q) is conserved by the exact motion (gravity plus loads
        that depend on the position at most; V_eff includes their potential). The scale
        ``kinetic_max`` (1/2 M qd^2 on the samples and the integrator's steps) does not
        depend on where V = 0 is put (a pendulum's E(0) may be 0 or huge). None when
        the loads depend on time or rate (they do work: nothing is conserved), and when nothing
        moved (no kinetic energy to scale a change by, even a change of 0).
        """
        if self.conserved is None or not self.kinetic_max > 0:
            return None
        H = self.conserved
        return float(np.max(np.abs(H - H[0]))) / self.kinetic_max

    @property
    def energy_drift_note(self) -> str:
        """Why :attr:`energy_drift` is None (the words of :data:`solver.analyses.motion.NO_DRIFT`);
        empty when it is a number."""
        from .analyses.motion import NO_DRIFT

        if self.energy_drift is not None:
            return ""
        return NO_DRIFT["work"] if self.conserved is None else NO_DRIFT["rest"]

    def columns(self, units: Mapping[str, str] | None = None) -> dict[str, tuple[np.ndarray, str]]:
        """Ordered columns name -> (values, unit) as written to CSV: SI, or in the units of a
        scene's ``[output_units]`` (:func:`solver.output_units.columns_in_output_units`)."""
        cols = {
            "t": (self.t, "s"),
            "theta": (self.theta, "rad"),
            "theta_dot": (self.theta_dot, "rad/s"),
            "theta_ddot": (self.theta_ddot, "rad/s**2"),
            "alpha": (self.alpha, "rad/s**2"),
        }
        for name, values in self.reactions.items():
            cols[name] = (values, self.reaction_units.get(name, "N"))
        cols["energy"] = (self.energy, "J")
        if units:
            from .output_units import columns_in_output_units

            return columns_in_output_units(cols, units)
        return cols

    def to_dict(self, units: Mapping[str, str] | None = None) -> dict:
        """Summary for ``--json``: final state, reason, counts, and the unit of each column of the
        samples (SI, or as ``units``, a scene's ``[output_units]``, makes them: as the CSV has them)."""
        out = {
            "status": self.status,
            "reason": self.reason,
            "t_end": {"value": float(self.t[-1]), "unit": "s"},
            "theta_end": {"value": float(self.theta[-1]), "unit": "rad"},
            "theta_dot_end": {"value": float(self.theta_dot[-1]), "unit": "rad/s"},
            "energy_drift": self.energy_drift,
            "method": self.method,
            "rtol": self.rtol,
            "atol": self.atol,
            "nfev": self.nfev,
            "samples": int(self.t.size),
            "columns": {name: unit for name, (_, unit) in self.columns(units).items()},
        }
        if self.event is not None:
            out["event"] = {
                "kind": self.event.kind,
                "reaction": self.event.reaction,
                "constraint": self.event.constraint,
                "time": {"value": self.event.time, "unit": "s"},
                "theta": {"value": self.event.theta, "unit": "rad"},
            }
        return out

    def __repr__(self) -> str:
        return (f"SimulationResult(status={self.status!r}, t_end={float(self.t[-1]):.6g} s, "
                f"samples={self.t.size}, method={self.method!r}, reason={self.reason!r})")


def write_csv(result: SimulationResult, path: str | os.PathLike, units: Mapping[str, str] | None = None) -> Path:
    """Write the samples as CSV, atomically (temporary file in the same folder, then rename).

    The header row names each column with its unit, ``name [unit]`` (``t [s], theta [rad],
    theta_dot [rad/s], theta_ddot [rad/s**2], alpha [rad/s**2], <reactions...>, energy [J]``),
    as :func:`solver.analyses.motion.write_motion_csv` does; the values are SI, or in the units
    ``units`` (a scene's ``[output_units]``) makes them (:meth:`SimulationResult.columns`).
    """
    cols = result.columns(units)

    def write(fh) -> None:
        w = csv.writer(fh)
        w.writerow([f"{name} [{unit}]" for name, (_, unit) in cols.items()])
        data = np.column_stack([v for v, _ in cols.values()])
        for row in data:
            w.writerow([repr(float(x)) for x in row])

    return write_atomic(path, write, "--out")


# --------------------------------------------------------------------------- helpers
class _Progress:
    """A tqdm bar on stderr driven by the integrator's time (only forward moves count)."""

    def __init__(self, t_end: float, enabled: bool | None):
        self.bar = None
        auto = enabled is None
        if auto:
            enabled = sys.stderr.isatty()
        if enabled:
            from tqdm import tqdm

            # delay: in auto mode a short run finishes before the bar would appear
            self.bar = tqdm(total=t_end, file=sys.stderr, unit="s", delay=0.5 if auto else 0.0,
                            bar_format="{l_bar}{bar}| {n:.3g}/{total:.3g} s simulated [{elapsed}<{remaining}]")
        self.done = 0.0
        self.step = t_end / 500.0

    def wrap(self, f: Callable) -> Callable:
        if self.bar is None:
            return f

        def g(t, y):
            if t - self.done > self.step:
                self.bar.update(t - self.done)
                self.done = t
            return f(t, y)

        return g

    def close(self, t_final: float) -> None:
        if self.bar is not None:
            if t_final > self.done:
                self.bar.update(t_final - self.done)
            self.bar.close()


def _validate_simulate(system, t_end, method, rtol, atol, mu, samples) -> None:
    if not isinstance(system, OneDofSystem):
        raise TypeError(f"`system` must be a OneDofSystem, got {type(system).__name__}")
    if method not in METHODS:
        raise ValueError(f"`method` must be one of {METHODS}, got {method!r}")
    if not (isinstance(t_end, (int, float)) and math.isfinite(t_end) and 0 < t_end <= MAX_T_END):
        raise InputError(f"--t-end must be a positive time of at most {MAX_T_END:g} s, got {t_end!r} s")
    if not (0 < rtol < 1 and math.isfinite(rtol)):
        raise InputError(f"--rtol must lie in (0, 1), got {rtol!r}")
    if not (0 < atol and math.isfinite(atol)):
        raise InputError(f"--atol must be positive, got {atol!r}")
    if mu is not None and not (math.isfinite(mu) and mu >= 0):
        raise InputError(f"--mu must be a non-negative number, got {mu!r}")
    if samples is not None and (int(samples) != samples or not 2 <= samples <= MAX_SAMPLES):
        raise InputError(f"--samples must be an integer from 2 to {MAX_SAMPLES}, got {samples!r}")


def simulate(
    system: OneDofSystem,
    t_end: float,
    y0: tuple[float, float] | None = None,
    method: str = "DOP853",
    rtol: float = 1e-9,
    atol: float = 1e-12,
    mu: float | None = None,
    samples: int | None = None,
    progress: bool | None = None,
    events: bool = True,
) -> SimulationResult:
    """Integrate the equation of motion from ``y0`` over [0, t_end].

    Parameters
    ----------
    system : OneDofSystem
    t_end : float
        End time. [s]
    y0 : (theta, theta_dot), optional
        Initial state [rad, rad/s]; default: the system's ``initial`` state
        is not stored, so callers pass the scene's state (``scene.state_si()``).
    method : str
        One of :data:`METHODS` (solve_ivp methods).
    rtol, atol : float
        Integrator tolerances.
    mu : float, optional
        Friction coefficient for every rolling contact; overrides the
        scene's ``friction_coefficient``. Without either, slip is not checked.
    samples : int, optional
        Number of uniformly spaced output samples (default: 20 per
        linearized period, at least 1001, at most 200001).
    progress : bool or None
        Progress bar on stderr: None = when stderr is a terminal and the run
        is long, True = always, False = never.
    events : bool
        Stop on loss of contact / slip (default True).

    Returns
    -------
    SimulationResult

    Raises
    ------
    InputError
        Bad times or tolerances.
    ValueError
        Unknown ``method`` (lists the valid ones).
    """
    _validate_simulate(system, t_end, method, rtol, atol, mu, samples)
    if y0 is None:
        y0 = (0.0, 0.0)
    q0, qd0 = float(y0[0]), float(y0[1])
    qdd, vals, plain = system.qdd_scalar_parts()
    if not plain:  # (numpy's lambdified function: its number as a Python float)
        compiled = qdd
        qdd = lambda q, qd, t, *v: float(compiled(q, qd, t, *v))  # noqa: E731
    _check_periods(system, q0, float(t_end))
    calls = 0

    # (the compiled theta_ddot called directly: a long run calls the rhs hundreds of thousands
    # of times, and each wrapper around it cost about as much as the stepper's own work per call)
    def state_rate(t, y):
        q, qd = y.tolist()  # Python floats: the math-module rhs runs faster on them than on numpy scalars
        return (qd, qdd(q, qd, t, *vals))

    def rhs(t, y):
        nonlocal calls
        calls += 1
        if calls > MAX_RHS_EVALUATIONS:
            raise _TooManySteps(float(t))
        q, qd = y.tolist()
        return (qd, qdd(q, qd, t, *vals))

    # event functions -------------------------------------------------------
    scalar_R = system.reaction_scalar_fns() if (events and system.reactions) else {}
    ev_funcs: list[Callable] = []
    ev_info: list[tuple[str, str, str]] = []
    for name in system.one_sided:
        if name in scalar_R:
            f = scalar_R[name]
            fn = (lambda f: (lambda t, y: f(*y.tolist(), t)))(f)
            ev_funcs.append(fn)
            ev_info.append(("lost_contact", name, system.reaction_constraints.get(name, name)))
    for pair in system.friction_pairs:
        m = mu if mu is not None else pair.mu
        if m is None or pair.friction not in scalar_R or pair.normal not in scalar_R:
            continue
        ff, fn_ = scalar_R[pair.friction], scalar_R[pair.normal]
        fn = (lambda ff, fn_, m: (lambda t, y: m * fn_(*y.tolist(), t) - abs(ff(*y.tolist(), t))))(ff, fn_, m)
        ev_funcs.append(fn)
        ev_info.append(("slip", pair.normal, pair.constraint))
    for text, g in system.limits:
        gf = lambdify((system.q,) + system.params, g, "math")
        fn = (lambda gf: (lambda t, y: float(gf(y[0], *system.values))))(gf)
        ev_funcs.append(fn)
        ev_info.append(("model_limit", text, ""))
    for fn in ev_funcs:
        fn.terminal = True
        fn.direction = -1
    # already violated at the start?
    for fn, (kind, name, cons) in zip(ev_funcs, ev_info):
        if fn(0.0, np.array((q0, qd0))) < 0:
            ev = StopEvent(kind, name, cons, 0.0, q0, qd0)
            return _finish(system, None, np.array([0.0]), method, rtol, atol, 1, ev,
                           _reason(system, ev, mu, at_start=True), kind,
                           y_single=(q0, qd0))

    det = system.singularity_fn() if events else None
    if det is not None:
        d0 = det(q0, qd0, 0.0)
        if not (math.isfinite(d0) and abs(d0) > 1e-12):
            from .errors import SingularConfigurationError

            raise SingularConfigurationError(
                f"{system.name}: singular configuration at the start ({system.q} = {math.degrees(q0):.6g} deg): "
                "the constraints do not determine the motion"
            )
        sing = lambda t, y: det(*y.tolist(), t)  # noqa: E731
        sing.terminal = True
        sing.direction = 0
        ev_funcs.append(sing)
        ev_info.append(("singular", "", "constraints"))

    bar = _Progress(float(t_end), progress)
    try:
        with np.errstate(all="ignore"):
            # y0 as an array: the event functions read every state with ``tolist`` (Python floats)
            sol = solve_ivp(bar.wrap(rhs), (0.0, float(t_end)), np.array([q0, qd0]),
                            method=_lazy_dop853(state_rate, system.name) if method == "DOP853" else method, rtol=rtol,
                            atol=atol, dense_output=True, events=ev_funcs or None)
    except (ZeroDivisionError, ValueError, OverflowError) as exc:
        bar.close(0.0)
        raise InputError(f"{system.name}: integration failed: {exc}") from None
    except _TooManySteps as exc:
        bar.close(0.0)
        raise InputError(
            f"{system.name}: --t-end {float(t_end):g} s: the run needed more than {MAX_RHS_EVALUATIONS} "
            f"right-hand-side evaluations (the cap on work) and had reached t = {exc.t:.6g} s; "
            "shorten --t-end or loosen --rtol/--atol"
        ) from None
    bar.close(float(sol.t[-1]))
    event = None
    status = "completed"
    if sol.status == -1 and len(sol.t) < 2:  # no step taken: nothing to sample
        raise InputError(f"{system.name}: the integration failed at the start ({sol.message}); "
                         "loosen --rtol/--atol")
    if sol.status == -1:
        status = "failed"
        reason = f"integration failed at t = {sol.t[-1]:.6g} s: {sol.message}"
    elif sol.status == 1:
        for k, te in enumerate(sol.t_events):
            if len(te):
                kind, name, cons = ev_info[k]
                ye = sol.y_events[k][0]
                event = StopEvent(kind, name, cons, float(te[0]), float(ye[0]), float(ye[1]))
                break
        status = event.kind if event else "completed"
        reason = _reason(system, event, mu) if event else "stopped by an event"
    else:
        reason = f"reached t = {t_end:g} s"
    t_final = float(sol.t[-1])
    if samples is None:
        try:
            T0 = find_equilibrium(system, near=q0).period
            samples = int(min(max(1001, 20 * t_final / T0 + 1), 200001))
        except InputError:
            samples = 1001
    t = np.linspace(0.0, t_final, int(samples))
    return _finish(system, sol, t, method, rtol, atol, int(sol.nfev), event, reason, status)


class _LazyDenseOutput(DenseOutput):
    """DOP853's interpolant of one step, built on its first call.

    The 7th-order interpolant costs three more right-hand-side evaluations per step, and
    ``solve_ivp`` builds it for every step of a run that has events or keeps its dense
    output. Long runs sample a small share of their steps (2001 samples over the 25,000
    steps of 1000 periods), so each step keeps only what the interpolant is made from (a
    copy of the stages, the step's ends and its length) and makes it when asked: the
    same arithmetic on the same numbers, so the same values to the last bit. ``fun`` is
    the right-hand side without the run's evaluation count and cap: the count is the
    integration's, and these evaluations (three per sampled step) come after it. An
    evaluation that fails there is reported as the integration's failures are (InputError,
    "integration failed"), not as a traceback."""

    def __init__(self, solver: DOP853, shared: tuple):
        super().__init__(solver.t_old, solver.t)
        # (this step's own numbers only: what every step of the run shares is in ``shared``, made
        # once per run, and the namespace the interpolant is made from is built when asked for)
        self._step = (solver.K_extended.copy(), solver.h_previous, solver.y_old, solver.y, solver.f)
        self._shared = shared
        self._made = None

    def _call_impl(self, t):
        if self._made is None:
            K, h, y_old, y, f = self._step
            n, n_stages, a_extra, c_extra, d, fun, label = self._shared
            state = SimpleNamespace(K_extended=K, h_previous=h, t_old=self.t_old, y_old=y_old, y=y,
                                    t=self.t, f=f, n=n, n_stages=n_stages, A_EXTRA=a_extra,
                                    C_EXTRA=c_extra, D=d, fun=fun)
            try:
                with np.errstate(all="ignore"):
                    self._made = DOP853._dense_output_impl(state)
            except (ZeroDivisionError, ValueError, OverflowError) as exc:
                raise InputError(f"{label}: integration failed: {exc}") from None
            self._step = None
        return self._made._call_impl(t)


def _lazy_dop853(fun: Callable, label: str = "simulate") -> type:
    """scipy's DOP853, taking the same steps, with :class:`_LazyDenseOutput` interpolants."""

    def as_array(t, y):
        return np.asarray(fun(t, y), dtype=float)

    class LazyDOP853(DOP853):
        _shared = None

        def _dense_output_impl(self):
            if self._shared is None:
                self._shared = (self.n, self.n_stages, self.A_EXTRA, self.C_EXTRA, self.D, as_array, label)
            return _LazyDenseOutput(self, self._shared)

    return LazyDOP853


def _check_periods(system: OneDofSystem, q0: float, t_end: float) -> None:
    """Refuse, before integrating, a run longer than :data:`MAX_PERIODS` linearized periods."""
    try:
        period = find_equilibrium(system, near=q0).period
    except InputError:  # no stable equilibrium: only the evaluation cap applies
        return
    if math.isfinite(period) and period > 0 and t_end > MAX_PERIODS * period:
        raise InputError(
            f"{system.name}: --t-end {t_end:g} s spans {t_end / period:.3g} periods of small oscillation "
            f"({period:.4g} s each); the cap on work is {MAX_PERIODS} periods"
        )


def _reason(system: OneDofSystem, ev: StopEvent, mu: float | None, at_start: bool = False) -> str:
    when = "at the start" if at_start else f"at t = {ev.time:.6g} s"
    where = f"({system.q} = {math.degrees(ev.theta):.6g} deg, {system.qd} = {ev.theta_dot:.6g} rad/s)"
    if ev.kind == "singular":
        return (f"singular configuration reached {when} {where}: the constraints stop determining the "
                "motion (the linear system's determinant vanishes)")
    if ev.kind == "model_limit":
        return (f"the model's limit is reached {when} {where}: it holds only while {ev.reaction} "
                "(there the straight edge meets the surface)")
    if ev.kind == "lost_contact":
        return (f"{ev.reaction} would turn negative {when} {where}: the body leaves the support of "
                f"constraint {ev.constraint}")
    m = mu
    if m is None:
        m = next((p.mu for p in system.friction_pairs if p.normal == ev.reaction), None)
    return (f"rolling at {ev.constraint} would need more friction than mu = {m:g} gives {when} {where}: "
            f"|friction| > mu * {ev.reaction}, the disk starts to slip")


def _finish(system, sol, t, method, rtol, atol, nfev, event, reason, status, y_single=None) -> SimulationResult:
    if sol is not None:
        y = sol.sol(t)
        if event is not None:  # the last sample is exactly the event state
            y[:, -1] = (event.theta, event.theta_dot)
        q, qd = y[0], y[1]
    else:
        q, qd = np.array([y_single[0]]), np.array([y_single[1]])
    with np.errstate(all="ignore"):
        qdd = np.asarray(system.qdd_fn()(q, qd, t), dtype=float) + 0.0 * q
        alpha = system.alpha_fn()(q, qd, qdd)
        reactions = system.reactions_fn()(q, qd, t)
        energy = system.energy_fn()(q, qd)
        kinetic = 0.5 * system.mass_fn()(q) * np.asarray(qd, dtype=float) ** 2
        kinetic_max = float(np.nanmax(kinetic)) if kinetic.size else 0.0
        if sol is not None and len(sol.sol.ts) > 1:
            # samples may alias with the motion (e.g. two per period, both at rest):
            # the integrator's own steps resolve it
            ys = sol.y[:, :: max(1, len(sol.t) // 200000)]  # the states at the steps' ends
            ks = 0.5 * system.mass_fn()(ys[0]) * ys[1] ** 2
            kinetic_max = max(kinetic_max, float(np.nanmax(ks)))
        conserved = None
        if system.is_conservative:
            try:
                conserved = kinetic + system.potential_fn(0)(q)
            except InputError:  # a position-dependent load without a closed-form potential
                conserved = None
    return SimulationResult(t=t, theta=q, theta_dot=qd, theta_ddot=qdd, alpha=alpha, reactions=reactions,
                            energy=np.asarray(energy, dtype=float), reaction_units=dict(system.reaction_units),
                            status=status, reason=reason, event=event, method=method, rtol=rtol, atol=atol,
                            nfev=nfev, sol=sol.sol if sol is not None else None,
                            conserved=None if conserved is None else np.asarray(conserved, dtype=float),
                            kinetic_max=kinetic_max if math.isfinite(kinetic_max) else 0.0)


# --------------------------------------------------------------------------- period by integration
@dataclass(frozen=True)
class IntegratedPeriod:
    """Period from the time between turning points of an integrated free oscillation.

    Attributes
    ----------
    period : float  [s]
    nfev : int
    method : str
    rtol : float
    """

    period: float
    nfev: int
    method: str
    rtol: float


def _validate_period_by_integration(method: str, rtol: float, amplitude: float) -> None:
    if method not in METHODS:
        raise ValueError(f"`method` must be one of {METHODS}, got {method!r}")
    if not (0 < rtol < 1):
        raise InputError(f"rtol must lie in (0, 1), got {rtol!r}")
    if not (math.isfinite(amplitude) and amplitude != 0):
        raise InputError(f"amplitude must be a non-zero finite angle, got {amplitude!r}")


def period_by_integration(
    system: OneDofSystem,
    amplitude: float,
    method: str = "DOP853",
    rtol: float = 1e-10,
    atol: float | None = None,
    equilibrium: Equilibrium | None = None,
) -> IntegratedPeriod:
    """Period of a release from rest at q_e + amplitude by ``solve_ivp`` and an event.

    Released from rest at q0 the rate first takes the sign opposite to the
    amplitude and returns to zero at the far turning point after half a
    period (time reversal symmetry of a conservative system); the event
    theta_dot = 0 (located on the dense output) gives T = 2 t_half.
    """
    _validate_period_by_integration(method, rtol, amplitude)
    eq = equilibrium if equilibrium is not None else find_equilibrium(system)
    if not system.is_conservative:
        system.effective_potential()  # raises the explanatory InputError
    qdd = system.qdd_scalar_fn()
    # generalized force of position-dependent loads is already in qdd
    rhs = lambda t, y: (y[1], qdd(*y.tolist(), t))  # noqa: E731  (Python floats: see simulate's rhs)
    sgn = 1.0 if amplitude > 0 else -1.0

    def turn(t, y):
        return y[1]

    turn.terminal = True
    turn.direction = sgn  # rate goes from -sgn back through zero
    T0 = eq.period
    if atol is None:
        atol = rtol * max(abs(amplitude), 1e-300) * 1e-2
    with np.errstate(all="ignore"):
        sol = solve_ivp(rhs, (0.0, 50.0 * T0), [eq.q + amplitude, 0.0], method=method, rtol=rtol, atol=atol,
                        events=turn, dense_output=False)
    te = sol.t_events[0]
    te = te[te > 0.05 * T0]
    if not len(te):
        raise InputError(f"{system.name}: no turning point found within 50 linearized periods")
    return IntegratedPeriod(2.0 * float(te[0]), int(sol.nfev), method, rtol)
