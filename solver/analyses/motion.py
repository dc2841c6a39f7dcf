"""Time histories of a system with any number of degrees of freedom.

The state is the independent coordinates u and their rates. At every step the
dependent coordinates and rates follow from the closure equations
(:func:`~solver.analyses.instant.assemble`, continued from the previous step)
and the instantaneous solve gives the accelerations and every reaction, so
the closure is satisfied to round-off at every output point (no drift).
``scipy.integrate.solve_ivp`` integrates u'' with terminal events:

* ``lost_contact``: a one-sided reaction (a normal force, a cord's tension)
  would change sign;
* ``slip``: a rolling contact needs more friction than mu N;
* ``model_limit``: a joint's model stops holding (a semicircle past its rim);
* ``singular``: the equations stop determining the motion (a linkage at a
  dead centre), detected by the condition number.

With no degree of freedom left (every motion prescribed), the run is inverse
dynamics: the reactions and driving forces at each sample time.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import sympy as sp
from scipy.integrate import solve_ivp

from ..errors import InputError, SingularConfigurationError
from .instant import assemble

__all__ = ["MotionResult", "simulate_system", "MAX_SAMPLES", "MAX_EVALUATIONS"]

MAX_SAMPLES = 200001
"""Most output samples of one run."""
MAX_EVALUATIONS = 1_000_000
"""Most right-hand-side evaluations of one run (the run stops with status ``work_limit``)."""


class _Stop(Exception):
    def __init__(self, kind, detail, t):
        super().__init__(detail)
        self.kind, self.detail, self.t = kind, detail, t


@dataclass
class MotionResult:
    """A time history.

    Attributes
    ----------
    t : ndarray
        Sample times [s].
    columns : dict[str, (ndarray, str)]
        Each coordinate, rate and second derivative, and each reaction, with its SI unit.
    status : str
        ``completed``, ``lost_contact``, ``slip``, ``model_limit``, ``singular``,
        ``work_limit`` or ``failed``.
    reason : str
    nfev : int
    energy_drift : float or None
        max |E - E(0)| / max T over the run, for a system whose loads are all
        conservative; None otherwise.
    """

    t: np.ndarray
    columns: dict
    status: str
    reason: str
    nfev: int = 0
    energy_drift: float | None = None
    events: list = field(default_factory=list)

    def to_dict(self) -> dict:
        last = {k: {"value": float(v[-1]), "unit": u} for k, (v, u) in self.columns.items()}
        return {"status": self.status, "reason": self.reason, "t_final": {"value": float(self.t[-1]), "unit": "s"},
                "samples": int(len(self.t)), "nfev": self.nfev, "final": last,
                "energy_drift": self.energy_drift}


def _conservative(system) -> bool:
    t = system.t
    if any(sp.sympify(x).has(t) for origin, phi in system.poses.values() for x in (*origin, phi)):
        return False
    return all(load.conservative for load in system.loads)


def simulate_system(system, t_end: float, method: str = "DOP853", rtol: float = 1e-9, atol: float = 1e-12,
                    mu: float | None = None, samples: int | None = None, route: str = "generalized_euler") -> MotionResult:
    """Integrate ``system`` from its state over [t0, t0 + t_end].

    Raises
    ------
    InputError
        Bad times, tolerances or sample counts (naming the flag).
    """
    from ..formulations import formulate

    if not (math.isfinite(t_end) and t_end > 0):
        raise InputError(f"--t-end must be a positive, finite time, got {t_end!r}")
    if samples is not None and not (2 <= samples <= MAX_SAMPLES):
        raise InputError(f"--samples must lie in 2..{MAX_SAMPLES}, got {samples!r}")
    model = formulate(system, route).numeric()
    free = system.free
    ind = [i for i, c in enumerate(free) if not c.dependent]
    t0 = system.time
    start = assemble(system)
    last_q = list(start.q)
    names = model.names
    reactions = system.reactions
    one_sided = [r.name for r in reactions if r.one_sided]
    pairs = [j.friction_pair for j in system.joints if j.friction_pair is not None]
    subs = system.si_values()
    limits = [(text, sp.lambdify((*system.q, system.t, *subs), g, "math")) for text, g in system.limits()]
    pvals = list(subs.values())
    counter = [0]

    def full_state(t, y):
        q = list(last_q)
        qd = [0.0] * len(free)
        for k, i in enumerate(ind):
            q[i] = y[k]
            qd[i] = y[len(ind) + k]
        st = assemble(system, q, qd, t)
        last_q[:] = st.q
        return st

    def solve_at(t, y):
        counter[0] += 1
        if counter[0] > MAX_EVALUATIONS:
            raise _Stop("work_limit", f"more than {MAX_EVALUATIONS} evaluations", t)
        st = full_state(t, y)
        try:
            res = model.solve(st.q, st.qd, t)
        except SingularConfigurationError as err:
            raise _Stop("singular", str(err), t) from None
        return st, res

    def rhs(t, y):
        _, res = solve_at(t, y)
        return np.concatenate([y[len(ind):], [float(res[names[i]]) for i in ind]])

    events, info = [], []
    for name in one_sided:
        def ev(t, y, name=name):
            return float(solve_at(t, y)[1][name])
        events.append(ev)
        info.append(("lost_contact", name))
    for friction, normal, mu_expr in pairs:
        m = mu if mu is not None else (None if mu_expr is None else float(sp.sympify(mu_expr).xreplace(subs)))
        if m is None:
            continue
        def ev(t, y, f=friction, n=normal, m=m):
            res = solve_at(t, y)[1]
            return m * float(res[n]) - abs(float(res[f]))
        events.append(ev)
        info.append(("slip", friction))
    for text, fn in limits:
        def ev(t, y, fn=fn):
            st = full_state(t, y)
            return float(fn(*st.q, t, *pvals))
        events.append(ev)
        info.append(("model_limit", text))
    for ev in events:
        ev.terminal = True
        ev.direction = -1

    n = int(samples) if samples is not None else 1001
    status, reason = "completed", f"reached t = {t0 + t_end:g} s"
    if not ind:  # inverse dynamics: nothing to integrate
        ts = np.linspace(t0, t0 + t_end, n)
        return _sample(system, model, ts, None, ind, status, "every motion is prescribed: inverse dynamics", 0,
                       start)
    y0 = np.array([start.q[i] for i in ind] + [start.qd[i] for i in ind])
    for ev, (kind, what) in zip(events, info):
        if ev(t0, y0) < 0:
            raise InputError(f"{system.label}: at the start already: {_describe(kind, what)}")
    try:
        with np.errstate(all="ignore"):
            sol = solve_ivp(rhs, (t0, t0 + t_end), y0, method=method, rtol=rtol, atol=atol, dense_output=True,
                            events=events or None)
    except _Stop as stop:
        return _partial(system, model, t0, stop, ind, start)
    t_final = float(sol.t[-1])
    if sol.status == -1:
        status, reason = "failed", f"integration failed at t = {t_final:.6g} s: {sol.message}"
    elif sol.status == 1:
        for k, te in enumerate(sol.t_events):
            if len(te):
                kind, what = info[k]
                status, reason = kind, f"at t = {te[0]:.6g} s: {_describe(kind, what)}"
                t_final = float(te[0])
                break
    ts = np.linspace(t0, t_final, n)
    return _sample(system, model, ts, sol.sol, ind, status, reason, int(sol.nfev), start)


def _describe(kind, what) -> str:
    return {
        "lost_contact": f"the one-sided reaction {what} would change sign (contact lost / cord slack)",
        "slip": f"rolling would need more friction than mu times the normal force (friction {what})",
        "model_limit": f"the model stops holding: {what}",
    }.get(kind, what)


def _partial(system, model, t0, stop, ind, start):
    t_end = stop.t if stop.t is not None and stop.t > t0 else t0
    ts = np.array([t0])
    res = _sample(system, model, ts, None, ind, stop.kind, f"at t = {t_end:.6g} s: {stop.detail}", 0, start)
    return res


def _sample(system, model, ts, dense, ind, status, reason, nfev, start):
    free = system.free
    cols: dict[str, list] = {}
    last = list(start.q)
    kept_t = []
    for t in ts:
        q = list(last)
        qd = list(start.qd)
        if dense is not None:
            y = dense(t)
            for k, i in enumerate(ind):
                q[i] = y[k]
                qd[i] = y[len(ind) + k]
        try:
            st = assemble(system, q, qd, float(t))
            res = model.solve(st.q, st.qd, float(t))
        except (InputError, SingularConfigurationError) as err:
            if not kept_t:
                raise
            status, reason = "singular", f"at t = {t:.6g} s: {err}"
            break
        last = list(st.q)
        kept_t.append(float(t))
        for c, v, r in zip(free, st.q, st.qd):
            cols.setdefault(c.name, []).append(v)
            cols.setdefault(f"{c.name}_dot", []).append(r)
        for name in model.names:
            cols.setdefault(name, []).append(float(res[name]))
    units = {}
    for c in free:
        units[c.name] = c.unit
        units[f"{c.name}_dot"] = f"{c.unit}/s"
        units[str(c.qdd)] = f"{c.unit}/s**2"
    for r in system.reactions:
        units[r.name] = r.unit
    columns = {k: (np.array(v), units.get(k, "")) for k, v in cols.items()}
    drift = _energy_drift(system, columns, np.array(kept_t)) if _conservative(system) and free else None
    return MotionResult(np.array(kept_t), columns, status, reason, nfev, drift)


def _energy_drift(system, columns, ts):
    T = system.kinetic_energy()
    V = system.potential_energy()
    args = (*system.q, *system.qd, system.t, *system.si_values())
    f = sp.lambdify(args, [T, V], "numpy")
    vals = [columns[c.name][0] for c in system.free] + [columns[f"{c.name}_dot"][0] for c in system.free]
    pv = list(system.si_values().values())
    with np.errstate(all="ignore"):
        Tv, Vv = (np.broadcast_to(np.asarray(x, float), ts.shape) for x in f(*vals, ts, *pv))
    E = Tv + Vv
    scale = float(np.max(np.abs(Tv))) if len(Tv) else 0.0
    if not scale > 0:
        return None
    return float(np.max(np.abs(E - E[0])) / scale)


def write_motion_csv(result: MotionResult, path) -> None:
    """Write t and every column (SI) to ``path`` atomically (:func:`solver.files.write_atomic`)."""
    import csv

    from ..files import write_atomic

    names = list(result.columns)

    def write(fh):
        w = csv.writer(fh)
        w.writerow(["t [s]"] + [f"{n} [{result.columns[n][1]}]" for n in names])
        for i, t in enumerate(result.t):
            w.writerow([repr(float(t))] + [repr(float(result.columns[n][0][i])) for n in names])

    write_atomic(path, write, "--out")
