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
from scipy.integrate._ivp.rk import Dop853DenseOutput

from ..errors import InputError, SingularConfigurationError
from .instant import assemble
from ..strprint import lambdify

__all__ = ["MotionResult", "simulate_system", "mu_contacts", "MAX_SAMPLES", "MAX_EVALUATIONS"]

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
        conservative and that moved; None otherwise, ``energy_drift_note`` saying why.
    """

    t: np.ndarray
    columns: dict
    status: str
    reason: str
    nfev: int = 0
    energy_drift: float | None = None
    events: list = field(default_factory=list)
    energy_drift_note: str = ""
    """Why ``energy_drift`` is None (:data:`NO_DRIFT`); empty when it is a number."""

    def columns_with_time(self, units=None) -> dict:
        """``t`` and every column, name -> (values, unit), as the CSV file has them: SI, or in the
        units ``units`` (a scene's ``[output_units]``) makes them."""
        from ..output_units import columns_in_output_units

        return columns_in_output_units({"t": (self.t, "s"), **self.columns}, units)

    def to_dict(self, units=None) -> dict:
        """Summary for ``--json``; ``columns`` names the unit of each column of the CSV file
        (:meth:`columns_with_time`)."""
        last = {k: {"value": float(v[-1]), "unit": u} for k, (v, u) in self.columns.items()}
        columns = {name: unit for name, (_, unit) in self.columns_with_time(units).items()}
        return {"status": self.status, "reason": self.reason, "t_final": {"value": float(self.t[-1]), "unit": "s"},
                "samples": int(len(self.t)), "nfev": self.nfev, "final": last, "columns": columns,
                "energy_drift": self.energy_drift,
                "events": [{**e, "t": float(e["t"]), "state": {k: float(v) for k, v in e.get("state", {}).items()}}
                           for e in self.events]}


NO_DRIFT = {
    "work": "the loads depend on time or rate: they do work",
    "rest": "nothing moved: no kinetic energy to measure a change of energy by",
    "prescribed": "every motion is prescribed: nothing moves freely",
    "slid": "a contact slid: its friction did work",
    "regimes": "the contacts changed regime during the run",
}
"""Why a run has no energy drift (``simulate`` prints "energy drift: not applicable (WHY)")."""


def _conservative(system) -> bool:
    t = system.t
    if any(sp.sympify(x).has(t) for origin, phi in system.poses.values() for x in (*origin, phi)):
        return False
    return all(load.conservative for load in system.loads)


def simulate_system(system, t_end: float, method: str = "DOP853", rtol: float = 1e-9, atol: float = 1e-12,
                    mu: float | None = None, samples: int | None = None, route: str = "generalized_euler",
                    point: str | None = None) -> MotionResult:
    """Integrate ``system`` from its state over [t0, t0 + t_end], switching contact regimes, with
    each body's moment equation about ``point`` (``--point``; the motion does not depend on it).

    A run is a chain of *segments*, each in one regime of the contacts
    (:mod:`solver.analyses.regimes`). A segment ends at an event: a sticking
    contact reaching mu_s N (it slips), a sliding one coming to rest (it
    sticks or reverses), a normal force reaching zero (the contact opens), or
    a gap closing (an impact: the run stops, impacts are not modelled). The
    regime that holds after the event is found at the event's state, and the
    run goes on. When the scene's coordinates cannot describe the new regime
    the run stops there with status ``slip`` or ``lost_contact``.

    Raises
    ------
    InputError
        Bad times, tolerances or sample counts (naming the flag).
    """
    if not (math.isfinite(t_end) and t_end > 0):
        raise InputError(f"--t-end must be a positive, finite time, got {t_end!r}")
    if samples is not None and not (2 <= samples <= MAX_SAMPLES):
        raise InputError(f"--samples must lie in 2..{MAX_SAMPLES}, got {samples!r}")
    if mu is not None:
        system = _with_mu(system, mu)
    from .regimes import start_state

    t0 = system.time
    start = start_state(system)
    from ..formulations import resolve_points

    resolve_points(system, point)  # a bad --point is refused before the run
    run = _Run(system, route, method, rtol, atol, point)
    segments, status, reason = run.go(start, t0, t0 + t_end)
    n = int(samples) if samples is not None else 1001
    t_final = segments[-1].t1
    ts = np.linspace(t0, t_final, n) if t_final > t0 else np.array([t0])
    res = _sample(system, segments, ts, status, reason, run.nfev)
    res.events = run.switches
    return res


def mu_contacts(system) -> list[str]:
    """The contacts ``--mu`` sets: the rolling ones (on a line or a circle), by name.

    Raises
    ------
    InputError
        The scene has none (a rail's coefficient is a parameter of the scene, set by ``--set``).
    """
    from ..model.joints import Rolling, RollingOnCircle

    names = [j.name for j in system.joints if isinstance(j, (Rolling, RollingOnCircle))]
    if not names:
        raise InputError(f"{system.label}: --mu: the scene has no rolling contact, and --mu sets the friction "
                         "coefficient of rolling contacts only (a rail's friction_coefficient is the scene's: "
                         "change its parameter with --set)")
    return names


def _with_mu(system, mu):
    """``--mu``: the friction coefficient of every rolling contact replaced by ``mu``."""
    from dataclasses import replace

    from ..model.contacts import Friction

    if not (math.isfinite(mu) and mu >= 0):
        raise InputError(f"--mu must be a finite number >= 0, got {mu!r}")
    value = sp.Float(mu)
    contacts = set(mu_contacts(system))
    return system.copy(joints=[replace(j, friction=Friction(value, value)) if j.name in contacts else j
                               for j in system.joints])


def _segment_system(base, regimes, state):
    """The system of a segment: the scene's own when its contacts are as written
    and it validates, else its copy in ``regimes`` made at the segment's first
    state (a stick row's phase is bound there)."""
    from ..errors import SceneError

    if all(regimes.get(j.name, j.current_regime) == j.current_regime for j in base.contacts):
        try:
            base.validate()
            return base
        except SceneError:
            pass
    return base.with_regimes(regimes, state.q, state.qd, state.t)


@dataclass
class _Segment:
    system: object
    model: object
    ind: list
    dense: object
    t0: float
    t1: float
    start: object
    work0: np.ndarray
    kin: list = field(default_factory=list)
    last_q: list = field(default_factory=list)


class _Run:
    """The chain of segments of one run (see :func:`simulate_system`)."""

    def __init__(self, base, route, method, rtol, atol, point=None):
        self.base, self.route, self.method, self.rtol, self.atol = base, route, method, rtol, atol
        self.point = point
        self.nfev = 0
        self.switches: list[dict] = []
        self.contacts = [j.name for j in base.contacts]

    def go(self, start, t0, t1):
        """(segments, status, reason) of the run from ``start`` to ``t1``."""
        found = self._first_regime(start)
        regimes = found.regimes if found is not None else {}
        segments, work, state = [], np.zeros(len(self.contacts)), start
        for _ in range(MAX_SWITCHES + 1):
            if found is not None and found.indeterminate:
                return self._at_rest(segments, found, state, work, t1)
            system = _segment_system(self.base, regimes, state) if found is not None else self.base
            seg, stop = self._segment(system, regimes, state, work, t1)
            segments.append(seg)
            if stop is None:
                return segments, "completed", f"reached t = {t1:g} s"
            kind, what, te = stop
            if kind not in ("slip", "lost_contact", "stick") or what not in regimes:  # (a cord going slack)
                return segments, kind, f"at t = {te:.6g} s: {_describe(kind, what)}"
            state, work = _state_at(seg, te), _work_at(seg, te)
            found, why = self._switch(regimes, kind, what, state)
            if found is None:
                return segments, kind, why
            regimes = found.regimes
        return segments, "work_limit", f"more than {MAX_SWITCHES} regime switches (chattering)"

    def _first_regime(self, start):
        """The regime at the start (None without contacts)."""
        from .regimes import NoConsistentRegime, find_regime

        if not self.contacts:
            return None
        try:
            return find_regime(self.base, start.q, start.qd, start.t, self.point)
        except NoConsistentRegime as err:
            raise InputError(f"{self.base.label}: at the start already: {str(err).split(': ', 1)[-1]}") from None

    def _switch(self, regimes, kind, what, state):
        """The regime after an event at ``state`` (and the switches recorded), or (None, why the run stops)."""
        from ..errors import SceneError
        from .regimes import find_regime

        te, old = state.t, regimes[what]
        try:  # the regime left holds at the event only with equality: ruled out (a stop may reverse)
            found = find_regime(self.base, state.q, state.qd, te, self.point, exclude={what: old} if kind != "stick" else None)
        except SceneError as err:
            return None, (f"at t = {te:.6g} s: {_describe(kind, what)}; the motion after it: "
                          f"{str(err).split(': ', 1)[-1]}")
        at = {c.name: v for c, v in zip(self.base.free, state.q)}
        at.update({f"{c.name}_dot": v for c, v in zip(self.base.free, state.qd)})
        self.switches.append({"t": te, "joint": what, "from": old.label, "to": found.regimes[what].label,
                              "cause": _describe(kind, what), "state": at})
        for name in self.contacts:
            if name != what and found.regimes[name] != regimes[name]:
                self.switches.append({"t": te, "joint": name, "from": regimes[name].label,
                                      "to": found.regimes[name].label, "cause": f"with {what}"})
        return found, None

    def _at_rest(self, segments, found, state, work, t1):
        """Sticking contacts hold everything redundantly: the state stays (loads constant in time)."""
        segments.append(_rest_segment(found, state, work, t1))
        if self.base.time_dependent:
            return segments, "failed", ("the contacts hold at rest redundantly (statically "
                                        "indeterminate) under loads that change with time: not followed")
        from .regimes import SPLIT_SHOWN

        return segments, "completed", (f"reached t = {t1:g} s at rest: the sticking contacts hold, statically "
                                       f"indeterminate; {SPLIT_SHOWN}")

    def _segment(self, system, regimes, state, work, t1):
        from ..formulations import formulate

        model = formulate(system, self.route, self.point).numeric()
        free = system.free
        ind = [i for i, c in enumerate(free) if not c.dependent]
        t0 = state.t
        kin = _contact_functions(system, regimes or {})
        last_q = list(state.q)
        seg = _Segment(system, model, ind, None, t0, t0, state, np.array(work, float), kin, last_q)
        if not ind:  # inverse dynamics: nothing to integrate
            seg.t1 = t1
            return seg, None
        names = model.names
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
            if self.nfev + counter[0] > MAX_EVALUATIONS:
                raise _Stop("work_limit", f"more than {MAX_EVALUATIONS} evaluations", t)
            st = full_state(t, y)
            try:
                res = model.solve(st.q, st.qd, t)
            except SingularConfigurationError as err:
                raise _Stop("singular", str(err), t) from None
            return st, res

        def rhs(t, y):
            st, res = solve_at(t, y)
            qdd = [float(res[names[i]]) for i in ind]
            power = [c.power(st, res, t) for c in kin]
            return np.concatenate([y[len(ind):2 * len(ind)], qdd, power])

        events, info = _events(system, regimes or {}, kin, solve_at, full_state)
        y0 = np.array([state.q[i] for i in ind] + [state.qd[i] for i in ind] + list(work), dtype=float)
        for ev, (kind, what) in zip(events, info):
            if ev(t0, y0) < 0 and not regimes:
                raise InputError(f"{system.label}: at the start already: {_describe(kind, what)}")
        try:
            with np.errstate(all="ignore"):
                sol = solve_ivp(rhs, (t0, t1), y0, method=self.method, rtol=self.rtol, atol=self.atol,
                                dense_output=True, events=events or None)
        except _Stop as stop:
            self.nfev += counter[0]
            seg.t1 = stop.t if stop.t is not None and stop.t > t0 else t0
            return seg, (stop.kind, stop.detail, seg.t1)
        self.nfev += int(sol.nfev)
        seg.dense, seg.t1 = sol.sol, float(sol.t[-1])
        if sol.status == -1:
            return seg, ("failed", f"integration failed: {sol.message}", seg.t1)
        if sol.status == 1:
            hits = [(te[0], k) for k, te in enumerate(sol.t_events) if len(te)]
            te, k = min(hits)
            seg.t1 = float(te)
            kind, what = info[k]
            return seg, (kind, what, float(te))
        return seg, None


MAX_SWITCHES = 100
"""Most regime switches in one run (more: status ``work_limit``, a chattering contact)."""


@dataclass
class _ContactFunctions:
    """One contact in a segment: its kinematics and, while it slides, its friction -s mu_k N."""

    name: str
    normal: str
    friction: str | None
    slide: int
    mu_k: float
    fn: object

    def friction_force(self, res):
        """The friction force (scalar or array, like the solve's ``res``)."""
        if self.slide == 0:
            return res[self.friction] if self.friction in res else 0.0
        return -self.slide * self.mu_k * res[self.normal]

    def slip_speed(self, st, t) -> float:
        if self.fn is None:  # a segment at rest
            return 0.0
        return self.fn(st.q, st.qd, [0.0] * len(st.q), t)[3]

    def power(self, st, res, t) -> float:
        """F dPhi_t/dt: the friction's power (0 while sticking or separated)."""
        if self.slide == 0:
            return 0.0
        return float(self.friction_force(res)) * self.slip_speed(st, t)


def _contact_functions(system, regimes):
    """A :class:`_ContactFunctions` per contact of ``system`` in ``regimes``."""
    from .regimes import _kin

    pv = system.si_values()
    out = []
    for j in system.contacts:
        r = regimes.get(j.name, j.current_regime)
        slide = r.friction_direction()
        mu_k = 0.0 if j.friction is None or not slide else float(sp.sympify(r.coefficient(j.friction)).xreplace(pv))
        F = j.pair[0]
        out.append(_ContactFunctions(j.name, j.pair[1].name, None if F is None else F.name, slide, mu_k,
                                     lambda q, qd, qdd, t, name=j.name: _kin(system, name, q, qd, qdd, t)))
    return out


def _events(system, regimes, kin, solve_at, full_state):
    """Terminal events of a segment, with (kind, what) for each."""
    from ..model.contacts import SEPARATED

    events, info = [], []
    by_name = {c.name: c for c in kin}
    contact_normals = set()
    for j in system.contacts:
        r = regimes.get(j.name, j.current_regime)
        c = by_name[j.name]
        if r is SEPARATED:
            def gap(t, y, c=c):
                st = full_state(t, y)
                return c.fn(st.q, st.qd, [0.0] * len(st.q), t)[0]
            events.append(gap)
            info.append(("impact", j.name))
            continue
        contact_normals.add(j.pair[1].name)
        if j.pair[1].one_sided:
            events.append(lambda t, y, n=j.pair[1].name: float(solve_at(t, y)[1][n]))
            info.append(("lost_contact", j.name))
        if r.keeps_tangential and j.friction is not None:
            mu_s = float(sp.sympify(j.friction.static).xreplace(system.si_values()))
            def ev(t, y, f=j.pair[0].name, n=j.pair[1].name, m=mu_s):
                res = solve_at(t, y)[1]
                return m * float(res[n]) - abs(float(res[f]))
            events.append(ev)
            info.append(("slip", j.name))
        elif c.slide:
            events.append(lambda t, y, c=c: c.slide * c.slip_speed(full_state(t, y), t))
            info.append(("stick", j.name))
    for r in system.reactions:
        if r.one_sided and r.name not in contact_normals:
            events.append(lambda t, y, n=r.name: float(solve_at(t, y)[1][n]))
            info.append(("lost_contact", r.name))
    pvals = list(system.si_values().values())
    for text, g in system.limits():
        fn = lambdify((*system.q, system.t, *system.si_values()), g, "math")
        events.append(lambda t, y, fn=fn: float(fn(*full_state(t, y).q, t, *pvals)))
        info.append(("model_limit", text))
    for ev in events:
        ev.terminal = True
        ev.direction = -1
    return events, info


def _describe(kind, what) -> str:
    return {
        "lost_contact": f"the one-sided reaction of {what} would change sign (contact lost / cord slack)",
        "slip": f"sticking at {what} would need more friction than mu_s times the normal force",
        "stick": f"the sliding at {what} comes to rest",
        "impact": f"the gap at {what} closes (an impact: impacts are not modelled)",
        "model_limit": f"the model stops holding: {what}",
    }.get(kind, what)


class _Fixed:
    """The 'model' of a segment at rest: the same values at every time."""

    def __init__(self, values):
        self.values = values

    def solve(self, q, qd, t):
        return self.values


def _rest_segment(found, state, work, t1):
    """A segment in which redundantly sticking contacts hold everything at rest."""
    seg = _Segment(found.system, _Fixed(dict(found.values)), [], None, state.t, t1, state, np.array(work, float),
                   [], list(state.q))
    seg.kin = [_ContactFunctions(j.name, j.pair[1].name, None if j.pair[0] is None else j.pair[0].name, 0, 0.0,
                                 None) for j in found.system.contacts]
    seg.rest = True
    return seg


def _state_at(seg, t):
    """The complete state of a segment at time t."""
    if getattr(seg, "rest", False):
        return type(seg.start)(tuple(seg.start.q), tuple(seg.start.qd), float(t))
    q, qd = list(seg.last_q), list(seg.start.qd)
    if seg.dense is not None:
        y = seg.dense(t)
        n = len(seg.ind)
        for k, i in enumerate(seg.ind):
            q[i], qd[i] = y[k], y[n + k]
    st = assemble(seg.system, q, qd, float(t))
    seg.last_q = list(st.q)
    return st


@dataclass
class _State:
    q: tuple
    qd: tuple


def _states_at(seg, tk):
    """(q, qd): one array per free coordinate at the times ``tk`` of a segment."""
    nfree = len(seg.system.free)
    if seg.dense is not None and not seg.system.dependent:
        Y = np.asarray(seg.dense(tk), float).reshape(-1, len(tk))
        q = [np.full(len(tk), v, float) for v in seg.start.q]
        qd = [np.full(len(tk), v, float) for v in seg.start.qd]
        for k, i in enumerate(seg.ind):
            q[i], qd[i] = Y[k], Y[len(seg.ind) + k]
        return q, qd
    states = [_state_at(seg, t) for t in tk]
    return ([np.array([s.q[i] for s in states]) for i in range(nfree)],
            [np.array([s.qd[i] for s in states]) for i in range(nfree)])


def _first_good(seg, tk) -> int:
    """How many of the samples ``tk`` solve before the first singular one."""
    for m, t in enumerate(tk):
        try:
            st = _state_at(seg, t)
            seg.model.solve(st.q, st.qd, float(t))
        except (InputError, SingularConfigurationError):
            return m
    return len(tk)


def _work_at(seg, t):
    if seg.dense is None:
        return np.array(seg.work0)
    return np.asarray(seg.dense(t)[2 * len(seg.ind):], float)


def _works_at(seg, tk) -> np.ndarray:
    """The friction work of every contact at the times ``tk`` of a segment: one row per time, as
    :func:`_work_at` gives each. DOP853's interpolants are evaluated at all the times together
    (their arithmetic is elementwise, so a time's numbers are those of a call at it alone); the
    other methods' (a matrix product, which may round otherwise) one time at a time."""
    n = len(tk)
    if seg.dense is not None and all(isinstance(i, Dop853DenseOutput) for i in seg.dense.interpolants):
        return np.asarray(seg.dense(tk), float)[2 * len(seg.ind):].T.reshape(n, -1)
    return np.array([_work_at(seg, t) for t in tk]).reshape(n, -1)


def _sample(base, segments, ts, status, reason, nfev):
    """Columns at the times ``ts``: coordinates, rates, accelerations, every reaction
    (a sliding contact's friction -s mu_k N, a separated contact's forces 0), each
    friction contact's sliding speed and the work its friction has done. Each
    segment's samples are solved together (vectorised)."""
    free = base.free
    cols: dict[str, list] = {}
    kept_t: list[float] = []
    bounds = [seg.t1 for seg in segments[:-1]]
    owner = np.searchsorted(bounds, ts, side="left") if bounds else np.zeros(len(ts), int)
    for k, seg in enumerate(segments):
        tk = ts[owner == k]
        if not len(tk):
            continue
        try:
            q, qd = _states_at(seg, tk)
            res = seg.model.solve(q, qd, tk)
        except (InputError, SingularConfigurationError) as err:
            good = _first_good(seg, tk)
            if not kept_t and not good:
                raise
            status, reason = "singular", f"at t = {tk[good]:.6g} s: {err}"
            tk = tk[:good]
            if not len(tk):
                break
            q, qd = _states_at(seg, tk)
            res = seg.model.solve(q, qd, tk)
        n = len(tk)
        kept_t.extend(float(t) for t in tk)
        for c, v, r in zip(free, q, qd):
            cols.setdefault(c.name, []).extend(np.broadcast_to(v, (n,)))
            cols.setdefault(f"{c.name}_dot", []).extend(np.broadcast_to(r, (n,)))
        for c in free:
            cols.setdefault(str(c.qdd), []).extend(np.broadcast_to(res[str(c.qdd)], (n,)))
        for r in base.reactions + [j.pair[0] for j in base.contacts if j.pair[0] is not None]:
            if r.name in cols and len(cols[r.name]) == len(kept_t):
                continue
            contact = next((c for c in seg.kin if r.name in (c.friction, c.normal)), None)
            if contact is not None and r.name == contact.friction:
                value = contact.friction_force(res)
            else:
                value = res[r.name] if r.name in res else 0.0
            cols.setdefault(r.name, []).extend(np.broadcast_to(value, (n,)))
        work = _works_at(seg, tk)
        kin = {c.name: c for c in seg.kin}
        for i, j in enumerate(base.contacts):
            if j.friction is None:
                continue
            speed = [kin[j.name].slip_speed(_State(tuple(float(x[m]) for x in q), tuple(float(x[m]) for x in qd)),
                                            float(tk[m])) for m in range(n)] if kin[j.name].fn else [0.0] * n
            cols.setdefault(f"v_slip_{j.name}", []).extend(speed)
            cols.setdefault(f"friction_work_{j.name}", []).extend(work[:, i])
        if status == "singular":
            break
    units = {}
    for c in free:
        units[c.name] = c.unit
        units[f"{c.name}_dot"] = f"{c.unit}/s"
        units[str(c.qdd)] = f"{c.unit}/s**2"
    for r in base.reactions:
        units[r.name] = r.unit
    for j in base.contacts:
        if j.pair[0] is not None:
            units[j.pair[0].name] = "N"
        units[f"v_slip_{j.name}"] = "m/s"
        units[f"friction_work_{j.name}"] = "J"
    columns = {k: (np.array(v), units.get(k, "")) for k, v in cols.items()}
    slid = any(np.any(np.abs(columns[f"friction_work_{j.name}"][0]) > 0)
               for j in base.contacts if f"friction_work_{j.name}" in columns)
    drift, why = _energy_drift(base, columns, np.array(kept_t), slid, segments)
    if _prescribed(segments) and len(segments) == 1 and status == "completed":
        reason = "every motion is prescribed: inverse dynamics"
    return MotionResult(np.array(kept_t), columns, status, reason, nfev, drift, energy_drift_note=why)


def _prescribed(segments) -> bool:
    """True when no segment of the run has an independent coordinate to integrate and none is held
    at rest by sticking contacts: every motion is prescribed (a dependent coordinate, such as a
    slider-crank's rod angle, follows the prescribed ones and is not free)."""
    return not any(seg.ind or getattr(seg, "rest", False) for seg in segments)


def _energy_drift(system, columns, ts, slid: bool, segments) -> tuple[float | None, str]:
    """(max |E - E(0)| / max T over the samples, "") where the energy is conserved and something
    moved; else (None, why the drift says nothing: the words of :data:`NO_DRIFT`)."""
    if _prescribed(segments):
        return None, NO_DRIFT["prescribed"]
    still = all(not np.any(columns[f"{c.name}_dot"][0]) for c in system.free)
    if still and not any(sp.sympify(x).has(system.t) for origin, phi in system.poses.values() for x in (*origin, phi)):
        return None, NO_DRIFT["rest"]  # (before the loads: a constant push that moves nothing does no work)
    if not _conservative(system):
        return None, NO_DRIFT["work"]
    if slid:
        return None, NO_DRIFT["slid"]
    if len(segments) > 1:
        return None, NO_DRIFT["regimes"]
    T = system.kinetic_energy()
    V = system.potential_energy()
    args = (*system.q, *system.qd, system.t, *system.si_values())
    f = lambdify(args, [T, V], "numpy")
    vals = [columns[c.name][0] for c in system.free] + [columns[f"{c.name}_dot"][0] for c in system.free]
    pv = list(system.si_values().values())
    with np.errstate(all="ignore"):
        Tv, Vv = (np.broadcast_to(np.asarray(x, float), ts.shape) for x in f(*vals, ts, *pv))
    E = Tv + Vv
    scale = float(np.max(np.abs(Tv))) if len(Tv) else 0.0
    if not scale > 0:
        return None, NO_DRIFT["rest"]
    return float(np.max(np.abs(E - E[0])) / scale), ""


def write_motion_csv(result: MotionResult, path, units=None) -> None:
    """Write t and every column to ``path`` atomically (:func:`solver.files.write_atomic`), each
    headed ``name [unit]``: SI, or in the units ``units`` (a scene's ``[output_units]``) makes them."""
    import csv

    from ..files import write_atomic

    cols = result.columns_with_time(units)

    def write(fh):
        w = csv.writer(fh)
        w.writerow([f"{n} [{unit}]" for n, (_, unit) in cols.items()])
        for row in zip(*(values for values, _ in cols.values())):
            w.writerow([repr(float(x)) for x in row])

    write_atomic(path, write, "--out")
