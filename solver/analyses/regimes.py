"""Which contact regime holds at a state: stick, slip or separation (Coulomb).

For every contact that can change (:attr:`System.contacts`: friction, or a
one-sided normal force) the candidates at a state follow from its kinematics:

* a gap that is open or opening: separated;
* touching and sliding (dPhi_t/dt != 0): slip in the direction of the sliding
  velocity, or separation;
* touching at rest: stick, slip either way (impending motion), or separation.

Each combination is solved as its own system (:meth:`System.with_regimes`)
and kept when it is *consistent*: normal forces press (N >= 0); sticking
friction stays in the cone (|F| <= mu_s N); an impending slip accelerates the
way it slides (s d2Phi_t/dt2 >= 0); a separating contact does not penetrate
(d2Phi_n/dt2 >= 0). Among consistent combinations, Coulomb's rule prefers
sticking to slipping and contact to separation; when several remain that no
rule orders, or none is consistent (Painlevé's paradox), the solver says so
instead of choosing. A redundant stick (a body held by more contacts than it
has freedoms, as a ladder resting against a wall) holds when some split of
the indeterminate forces keeps every contact inside its cone; the split shown
is the least-squeeze one (:data:`SPLIT_SHOWN`), which the physics alone fixes.
"""
from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field

import numpy as np
import sympy as sp

from ..errors import InputError, SceneError
from ..model.contacts import SEPARATED, STICK, Regime, Slip
from ..model.system import RedundantConstraints
from ..output_units import in_output_units
from ..strprint import lambdify

__all__ = ["RegimeResult", "ContactCheck", "find_regime", "contact_kinematics", "MAX_CONTACTS",
           "NoConsistentRegime", "AmbiguousRegime", "regime_system", "solve_in_regime", "start_state",
           "regime_at_state", "regime_error_bounds", "recheck", "least_friction", "holding", "with_every_contact_force", "SPLIT_NAME", "SPLIT_SHOWN",
           "INDETERMINATE_NOTE"]

MAX_CONTACTS = 4
"""Most contacts that can change regime in one scene (at most 4**4 = 256 combinations are tried)."""

TOL = 1e-9
"""Relative tolerance of the sign tests (forces against the largest force; rates and
accelerations against the largest of the state's): round-off of the solve is ~1e-13,
so 1e-9 separates a zero from a sign without accepting real violations."""

SPLIT_MARGIN = 1e-3
"""How far inside its friction cone the shown split of a redundant stick keeps each contact
(N >= d, |F| <= mu_s N - d), d this fraction of the largest force of the least-norm solution
(which does not depend on P): the split shown is then visibly sticking, not slipping."""

SPLIT_NAME = "the least-squeeze split"
"""The name of the split of statically indeterminate forces every command shows."""

SPLIT_SHOWN = (f"{SPLIT_NAME} is shown: of the splits that keep every sticking contact inside its friction "
               f"cone by at least {SPLIT_MARGIN:g} of the largest force of the least-norm solution of the "
               "equations (by less where none does), the one of least norm (the smallest sum of squared forces, "
               "in SI units), which no choice of P or method changes")
"""Which split of statically indeterminate forces every command shows (:func:`_redundant_stick`)."""

INDETERMINATE_NOTE = ("the sticking contacts hold redundantly: the accelerations are determined, "
                      "the split of their forces is not; " + SPLIT_SHOWN)
"""The one wording of a redundant stick's note (``solve``, ``explain``, ``simulate``)."""

GAP_TOL = 1e-6
"""A gap (or a closing speed) below this, relative to the largest coordinate (rate), counts
as closed: an assembled state satisfies its closure to ~1e-13 and an event root lands
within ~1e-12 of its switch, while a gap that has really opened is far larger."""


class NoConsistentRegime(SceneError):
    """No combination of contact regimes satisfies Coulomb's and Signorini's conditions."""


class AmbiguousRegime(SceneError):
    """Several combinations are consistent and no rule orders them (Painlevé's paradox)."""


@dataclass
class ContactCheck:
    """One contact's regime at a state, and why it holds."""

    joint: str
    regime: Regime
    reason: str
    normal: float = 0.0
    friction: float = 0.0
    needed_mu: float | None = None

    def to_dict(self) -> dict:
        out = {"joint": self.joint, "regime": self.regime.label, "reason": self.reason,
               "normal_force": {"value": self.normal, "unit": "N"},
               "friction_force": {"value": self.friction, "unit": "N"}}
        if self.needed_mu is not None:
            out["least_mu"] = self.needed_mu
        return out


@dataclass
class RegimeResult:
    """The regime that holds at a state.

    Attributes
    ----------
    regimes : dict[str, Regime]
    system : System
        The system in that regime (the scene's own when nothing changed).
    values : dict[str, float]
        Every unknown of that system (SI), plus each sliding contact's friction.
    checks : list of ContactCheck
    indeterminate : bool
        True when sticking contacts hold a body redundantly: the motion is
        determined, the split of their forces is not (``values`` then holds
        the least-squeeze split, :data:`SPLIT_SHOWN`).
    rejected : list of str
        The other combinations tried and why each fails.
    """

    regimes: dict
    system: object
    values: dict
    checks: list = field(default_factory=list)
    indeterminate: bool = False
    rejected: list = field(default_factory=list)


def regime_system(system, regimes: dict, q=None, qd=None, t=None):
    """``system`` itself when ``regimes`` is what the scene states and its
    coordinates describe it, else its copy in them at the state."""
    if all(_same(j, regimes.get(j.name)) for j in system.contacts):
        try:
            system.validate()
            return system
        except SceneError:
            pass
    key = ("regime", tuple(sorted((n, r.label) for n, r in regimes.items())))

    def build():
        try:
            return system.with_regimes(regimes, q, qd, t)
        except SceneError as err:  # remembered too: the same combination fails the same way
            return err
    # Cached on the system for instantaneous analyses, which use the copy's acceleration-level
    # equations only (a stick row's phase, bound at the first state, does not enter them).
    variant = system._memo(key, build)
    if isinstance(variant, SceneError):
        raise variant
    return variant


def _same(joint, regime) -> bool:
    return regime is None or regime == joint.current_regime


def contact_kinematics(system):
    """Per contact (joint name): a :class:`_KinematicsAt` of (q, qd, qdd, t) giving
    (Phi_n, dPhi_n, d2Phi_n, dPhi_t, d2Phi_t) in ``system``'s coordinates, and the parameters'
    values (cached on the system)."""
    def build():
        pose = system._pose_fn(system.poses)
        values = system.si_values()
        params = sorted(values, key=str)
        pv = [values[p] for p in params]
        args = (*system.q, *system.qd, *system.qdd, system.t, *params)
        out = {}
        for j in system.contacts:
            Pt, Pn = (system.prescribe(sp.sympify(x)) for x in j.contact_rows(pose))
            dPn, dPt = system.D(Pn), system.D(Pt)
            out[j.name] = (_KinematicsAt(args, [Pn, dPn, system.D(dPn), dPt, system.D(dPt)]), pv)
        return out
    return system._memo("contact_kinematics", build)


class _KinematicsAt:
    """Expressions in ``args`` as a function of their values, a list of floats: for the first
    :attr:`WALKS` calls by one walk of the trees each (:func:`solver.tree_value.tree_value`; a solve
    or a worked solution asks at two or three states), then compiled (``lambdify`` with common
    subexpressions, which costs as much as a few hundred walks: a simulation asks at every step
    and event). An expression the walk does not know, or a value it cannot give (a division by
    zero, a complex number), goes to the compiled function."""

    WALKS = 8

    def __init__(self, args, exprs):
        self.args, self.exprs, self.walks, self._f = args, exprs, 0, None

    def __call__(self, *values) -> list[float]:
        if self._f is None and self.walks < self.WALKS:
            self.walks += 1
            walked = self._walked(values)
            if walked is not None:
                return walked
        if self._f is None:
            self._f = lambdify(self.args, self.exprs, "math", cse=True)
        return [float(v) for v in self._f(*values)]

    def _walked(self, values):
        from ..tree_value import NotEvaluable, tree_value

        point, memo, out = dict(zip(self.args, map(float, values))), {}, []
        try:
            for e in self.exprs:
                v = tree_value(e, point, memo=memo)
                if v.imag != 0:
                    return None
                out.append(v.real)
        except (NotEvaluable, KeyError, TypeError, ValueError, ZeroDivisionError, OverflowError):
            return None
        return out


def _kin(system, name, q, qd, qdd, t):
    f, pv = contact_kinematics(system)[name]
    return f(*q, *qd, *qdd, t, *pv)


def _candidates(system, q, qd, t) -> dict[str, list[Regime]]:
    """The regimes each contact may be in, from its kinematics at the state."""
    zero_acc = [0.0] * len(q)
    scale_v = 1.0 + max((abs(v) for v in qd), default=0.0)
    scale_q = 1.0 + max((abs(v) for v in q), default=0.0)
    out = {}
    for j in system.contacts:
        gap, vgap, _, vt, _ = _kin(system, j.name, q, qd, zero_acc, t)
        one_sided = j.normal_reaction.one_sided
        if one_sided and (gap > GAP_TOL * scale_q or vgap > TOL * scale_v):
            out[j.name] = [SEPARATED]
            continue
        if one_sided and vgap < -GAP_TOL * scale_v and abs(gap) <= GAP_TOL * scale_q:
            raise InputError(f"{system.label}: contact {j.name!r} is closing at {vgap:.6g} (an impact): "
                             "impacts are not modelled")
        if j.friction is None:
            tangential = [j.current_regime]
        elif abs(vt) > TOL * scale_v:
            tangential = [Slip(1 if vt > 0 else -1)]
        else:
            tangential = [STICK, Slip(1, impending=True), Slip(-1, impending=True)]
        out[j.name] = tangential + ([SEPARATED] if one_sided else [])
    return out


def _rank(regime) -> int:
    """Coulomb's preference: sticking (or frictionless sliding) 0, slipping 1, separation 2."""
    if not regime.keeps_normal:
        return 2
    return 0 if regime.keeps_tangential or regime.friction_direction() == 0 else 1


def find_regime(system, q=None, qd=None, t=None, point=None, method="generalized_euler",
                exclude: dict | None = None) -> RegimeResult:
    """The contact regime that holds at the state (the scene's by default).

    ``exclude`` (joint -> regime) rules a regime out for a contact: the one it
    leaves at an event of a simulation, whose condition holds there only
    with equality.

    Raises
    ------
    NoConsistentRegime, AmbiguousRegime
        With every combination tried and why it fails.
    InputError
        An impact at the state, or too many contacts (:data:`MAX_CONTACTS`).
    """
    if len(system.contacts) > MAX_CONTACTS:
        raise InputError(f"{system.label}: {len(system.contacts)} contacts can change regime; at most "
                         f"{MAX_CONTACTS} are searched")
    from ..formulations import resolve_points

    resolve_points(system, point)  # a bad --point: its own one line, not once per regime tried
    if q is None:
        st = start_state(system)
        q, qd, t = st.q, st.qd, st.t
    t = system.time if t is None else float(t)
    cands = _candidates(system, q, qd, t)
    for name, regime in (exclude or {}).items():
        cands[name] = [r for r in cands[name] if r != regime] or cands[name]
    names = list(cands)
    combos = sorted(itertools.product(*(cands[n] for n in names)),
                    key=lambda c: (sum(_rank(r) for r in c), [_rank(r) for r in c]))
    consistent, rejected = [], []
    for combo in combos:
        regimes = dict(zip(names, combo))
        if any(_dominates(c.regimes, regimes) for c in consistent):
            continue  # a preferred combination already holds
        label = ", ".join(f"{n} {_in_words(r)}" for n, r in regimes.items())
        try:
            res = solve_in_regime(system, regimes, q, qd, t, point, method)
        except RedundantConstraints:
            res = _redundant_stick(system, regimes, q, qd, t, point, method)
        except SceneError as err:
            rejected.append(f"{label}: the scene cannot describe it ({_short(err)})")
            continue
        if isinstance(res, str):
            rejected.append(res if res.startswith(label) else f"{label}: {res}")  # (not "A sticking: A sticking needs")
            continue
        res = _now_sliding(system, res, q, qd, t, point, method)
        if isinstance(res, str):
            rejected.append(f"{label}: {res}")
            continue
        consistent.append(res)
    if not consistent:
        raise NoConsistentRegime(f"{system.label}: no contact regime is consistent at the state "
                                 f"(Painlevé's paradox, or a motion the scene cannot describe): "
                                 + "; ".join(rejected))
    if len(consistent) > 1:
        labels = [", ".join(f"{n}: {r.label}" for n, r in c.regimes.items()) for c in consistent]
        raise AmbiguousRegime(f"{system.label}: several contact regimes are consistent at the state and "
                              f"Coulomb's law does not choose between them (Painlevé's paradox): "
                              + " | ".join(labels))
    out = consistent[0]
    out.rejected = rejected
    return out


def regime_at_state(system, state=None, point=None, method="generalized_euler"):
    """The regime for an instantaneous solve: (RegimeResult or None, warning or None, state).

    When no regime is consistent but the scene as written can be solved (a
    normal force that would pull, where the scene's coordinates cannot
    describe the separation), that solve stands, with a warning saying so.
    """
    state = start_state(system) if state is None else state
    try:
        return find_regime(system, state.q, state.qd, state.t, point, method), None, state
    except NoConsistentRegime as err:
        try:
            system.validate()
        except SceneError:
            raise err from None
        return None, "the scene as written is solved, but " + str(err).split(": ", 1)[-1], state


def system_in_regime(system, point=None, method="generalized_euler"):
    """The system in the contact regime that holds at the scene's state, as ``solve`` finds it:
    (that system, :class:`RegimeResult` or None, warning or None, state). None and the system itself
    when no regime is consistent but the scene as written solves (:func:`regime_at_state`); a regime
    whose sticking contacts hold redundantly keeps every contact row (its forces' split
    open: ``RegimeResult.indeterminate``)."""
    from ..model.system import RedundantConstraints

    res, warning, state = regime_at_state(system, None, point, method)
    if res is None:
        return system, None, warning, state
    try:
        variant = regime_system(system, res.regimes, state.q, state.qd, state.t)
    except RedundantConstraints:  # held redundantly: every contact row kept, the forces' split open
        variant = system.with_regimes(res.regimes, state.q, state.qd, state.t, redundant_ok=True)
    return variant, res, warning, state


def _now_sliding(system, res, q, qd, t, point, method):
    """An impending slip that holds starts: the same regime with kinetic friction."""
    if not any(getattr(r, "impending", False) for r in res.regimes.values()):
        return res
    kinetic = {n: (r.sliding() if getattr(r, "impending", False) else r) for n, r in res.regimes.items()}
    out = solve_in_regime(system, kinetic, q, qd, t, point, method, strict_direction=False)
    if isinstance(out, str):
        return f"it starts to slip, but then {out}"
    out.checks = [ContactCheck(c.joint, kinetic[c.joint], c.reason + _starts_to_slip(system, c.joint)
                               if getattr(res.regimes[c.joint], "impending", False) else c.reason,
                               c.normal, c.friction, c.needed_mu)
                  for c in out.checks]
    return out


def _starts_to_slip(system, joint: str) -> str:
    """The words added to the reason of a contact whose impending slip starts: mu_s N overcome, then
    sliding with mu_k N; for a coefficient of 0, that there is no friction to overcome or slide with."""
    contact = next(j for j in system.contacts if j.name == joint)
    pv = system.si_values()
    friction = contact.friction
    mu_s, mu_k = (0.0, 0.0) if friction is None else \
        (float(sp.sympify(mu).xreplace(pv)) for mu in (friction.static, friction.kinetic))
    start = "it slips at once (mu_s = 0: no friction holds it)" if mu_s == 0 else "it starts to slip (mu_s N overcome)"
    return f"; {start}, then slides " + ("without friction (mu_k = 0)" if mu_k == 0 else "with mu_k N")


def start_state(system):
    """The scene's state, completed (:func:`~solver.analyses.instant.assemble`).

    When the closure equations cannot all hold, some one-sided contacts are
    open at the state: the subsets of them are tried, fewest first, and the
    first whose remaining closure assembles, with those gaps open and the
    coordinates the scene gives (not guesses) unchanged, is taken.
    """
    from itertools import combinations

    from .instant import assemble

    try:
        return assemble(system)
    except (InputError, SceneError) as first:
        error = first
    sided = [j for j in system.contacts if j.normal_reaction.one_sided]
    given = {c.name for c in system.free if not c.dependent}
    for k in range(1, len(sided) + 1):
        for subset in combinations(sided, k):
            try:
                variant = system.with_regimes({j.name: SEPARATED for j in subset})
                if any(c.dependent and c.name in given for c in variant.free):
                    continue  # it would move a coordinate the scene gives
                st = assemble(variant)
            except (InputError, SceneError):
                continue
            gaps = [_kin(variant, j.name, st.q, st.qd, [0.0] * len(st.q), st.t)[0] for j in subset]
            if all(g >= 0 for g in gaps):
                return st
    raise error


def _dominates(a: dict, b: dict) -> bool:
    """True when ``a`` is preferred to ``b`` for every contact (sticking, then contact)."""
    return all(_rank(a[n]) <= _rank(b[n]) for n in a) and any(_rank(a[n]) < _rank(b[n]) for n in a)


def _short(err) -> str:
    text = str(err)
    return text.split(": ", 1)[-1][:200]


class NotDescribable(SceneError):
    """A regime that needs motions the scene's coordinates do not describe (or forbids ones they do)."""


class _Augmented:
    """The equations of every contact at once, from which each regime is a selection.

    One formulation of the system with every contact that can stick sticking
    (all friction and normal reactions unknown, all their rows kept) gives
    A x = b. A regime keeps the columns of its reactions and the rows of its
    equations; a sliding contact's friction -s mu N along d adds -s mu times
    the friction's column (the generalized force of a unit force along d at
    the contact) to the normal force's column. Rows a placement satisfies
    identically are not in A: a regime that drops such a row's reaction
    leaves more equations than unknowns, which is how a regime the scene's
    coordinates cannot describe shows. Cached on the system by (point, method).
    """

    def __init__(self, system, point, method):
        from ..formulations import Formulation, resolve_points
        from .instant import NumericModel

        sticking = {j.name: (STICK if j.friction is not None else j.current_regime) for j in system.contacts}
        variant = system.with_regimes(sticking, redundant_ok=True)
        self.variant = variant
        self.model = NumericModel(Formulation(variant, method, resolve_points(variant, point)))
        self.names = list(self.model.names)
        self.qdd = [str(c.qdd) for c in variant.free]
        body_rows = 3 * len(variant.bodies)
        self.body_rows = list(range(body_rows))
        self.row_of = {(r.joint.name, r.reaction.name): body_rows + k for k, r in enumerate(variant.closure)}
        self.contacts = {j.name: j for j in variant.contacts}

    def select(self, regimes):
        """(rows, columns, [(normal column, friction column, factor expression)]) of ``regimes``."""
        cols, rows, mods = list(self.qdd), list(self.body_rows), []
        for j in self.variant.joints:
            r = regimes.get(j.name) if j.name in self.contacts else None
            if r is None:
                kept = list(j.reactions)
            elif r.keeps_tangential:
                kept = [*j.pair, *j.extra_reactions]
            elif r.keeps_normal:
                kept = [j.pair[1], *j.extra_reactions]
                if r.friction_direction() and j.friction is not None:
                    mods.append((j.pair[1].name, j.pair[0].name,
                                 -r.friction_direction() * sp.sympify(r.coefficient(j.friction))))
            else:
                kept = []
            for reaction in kept:
                cols.append(reaction.name)
                if (j.name, reaction.name) in self.row_of:
                    rows.append(self.row_of[(j.name, reaction.name)])
        return rows, cols, mods

    def system_of(self, regimes, q, qd, t):
        """(A, b, column names) of ``regimes`` at the state (A square)."""
        rows, cols, mods = self.select(regimes)
        if len(rows) != len(cols):
            raise NotDescribable(f"{self.variant.label}: it leaves {len(rows)} equations for {len(cols)} unknowns: "
                                 "the scene's coordinates do not describe its motion")
        A, b = self.model.matrices(q, qd, t)
        pv = self.variant.si_values()
        return (*self.pick(np.array(A, float), np.array(b, float), rows, cols,
                           [(n, f, float(e.xreplace(pv))) for n, f, e in mods]), cols)

    def pick(self, A, b, rows, cols, mods):
        """The regime's square system from the full one (stacks allowed): a slide's
        friction column folded into its normal column, then its rows and columns."""
        index = {n: i for i, n in enumerate(self.names)}
        for n, f, factor in mods:
            A[..., :, index[n]] += factor * A[..., :, index[f]]
        c = [index[name] for name in cols]
        return A[..., rows, :][..., :, c], b[..., rows]


def _augmented(system, point, method):
    return system._memo(("augmented", point, method), lambda: _Augmented(system, point, method))


def solve_in_regime(system, regimes, q, qd, t, point=None, method="generalized_euler",
                    strict_direction: bool = True):
    """Solve ``system`` with its contacts in ``regimes`` at the state and check
    every contact's condition: a :class:`RegimeResult`, or a string saying which
    condition fails. ``strict_direction=False`` skips the direction test of a
    slip starting from rest (for the kinetic solve after the impending one:
    with mu_k < mu_s it accelerates the assumed way by construction).

    Raises
    ------
    NotDescribable
        The scene's coordinates do not describe the regime.
    RedundantConstraints
        Its equations are singular because contacts hold redundantly (a stick
        at rest): see :func:`_redundant_stick`.
    """
    from .instant import CONDITION_LIMIT, refine, solve_with_estimate

    if method == "lagrange" or regime_system(system, regimes, q, qd, t) is system:
        # the scene as written (its own solve, unchanged), or Lagrange's equations, which are in
        # body coordinates: solve the regime's own system
        return _solve_variant(system, regimes, q, qd, t, point, method, strict_direction)
    aug = _augmented(system, point, method)
    A, b, cols = aug.system_of(regimes, q, qd, t)
    x, cond = solve_with_estimate(A, b)  # the solver's one singularity decision
    cond = float(cond)
    if not cond <= CONDITION_LIMIT:
        if all(r.keeps_tangential or r == SEPARATED or not r.friction_direction() for r in regimes.values()):
            raise RedundantConstraints(f"{system.label}: singular with every contact holding")
        return f"its equations are singular (condition number {cond:.3g})"
    if A.ndim == 2:  # refined once, as the solve without contacts: left with the round-off of A and b only,
        x = refine(A, b, x)  # which regime_error_bounds bounds (crate_tipping's x_ddot, exactly 0, was -1.4e-16)
    values = dict(zip(cols, map(float, x)))
    values["condition_number"] = cond
    qdd = [values[c] for c in aug.qdd]
    checks, failure = _check(aug.variant, regimes, q, qd, qdd, t, values, strict_direction)
    if failure:
        return failure
    return RegimeResult(dict(regimes), system, values, checks)


def _solve_variant(system, regimes, q, qd, t, point, method, strict_direction):
    from ..errors import SingularConfigurationError
    from ..formulations import formulate

    variant = regime_system(system, regimes, q, qd, t)
    try:
        res = formulate(variant, method, point).numeric().solve(q, qd, t, once=True)
    except SingularConfigurationError as err:
        return f"its equations are singular ({_short(err)})"
    values = {k: float(v) for k, v in res.items()}
    qdd = [values[str(c.qdd)] for c in variant.free]
    checks, failure = _check(variant, regimes, q, qd, qdd, t, values, strict_direction)
    if failure:
        return failure
    return RegimeResult(dict(regimes), system, values, checks)


def regime_error_bounds(system, regime: RegimeResult, q, qd, t, point=None, method="generalized_euler"):
    """(names, bounds): each unknown's float64 error bound in ``regime`` at the state, by the
    solver's one bound (:func:`solver.analyses.instant.error_bounds`) on the very system
    :func:`solve_in_regime` solves (the variant's own, or the regime's selection of the augmented
    system, a slide's friction column folded into its normal's with its sizes), or None where
    the sizes cannot be evaluated, the regime's split of forces is indeterminate or its system is
    singular. A sliding contact's friction -s mu_k N errs by mu_k times N's bound."""
    from ..errors import SingularConfigurationError
    from ..formulations import formulate
    from .instant import _state_text, error_bounds, singular_to_round_off, solve_with_estimate

    if regime.indeterminate:
        return None
    regimes = regime.regimes
    if method == "lagrange" or regime_system(system, regimes, q, qd, t) is system:
        variant = regime_system(system, regimes, q, qd, t)
        model = formulate(variant, method, point).numeric()
        res = model.solve(q, qd, t, once=True, bounds=True)  # (its singularity decision with the round-off)
        names, bound = list(model.names), res.get("error_bound")
    else:
        aug = _augmented(system, point, method)
        A, b, names = aug.system_of(regimes, q, qd, t)
        x, _ = solve_with_estimate(A, b)
        sizes = aug.model._sizes(q, qd, t, walked=aug.model.walked)
        if sizes is None:
            return None
        rows, cols, mods = aug.select(regimes)
        pv = aug.variant.si_values()
        size_A, size_b = aug.pick(sizes[0].copy(), sizes[1].copy(), rows, cols,
                                  [(n, f, abs(float(e.xreplace(pv)))) for n, f, e in mods])
        if singular_to_round_off(A, b, size_A) is not None:
            raise SingularConfigurationError(
                f"{system.label}: singular configuration at {_state_text(system, q, qd, t, ())}: with the contacts "
                f"{', '.join(f'{k} {v.label}' for k, v in regimes.items())}, the equations do not determine the "
                "motion (an entry of their matrix that is 0 to round-off taken as 0)")
        bound = error_bounds(A, b, x, size_A, size_b)
        variant = aug.variant
    if bound is None or not np.all(np.isfinite(bound)):
        return None
    of = dict(zip(names, bound))
    pv = variant.si_values()
    for j in variant.contacts:  # a slide's friction, -s mu_k N, from its normal force
        r = regimes.get(j.name, j.current_regime)
        F, N = j.pair
        if F is not None and F.name not in of and N.name in of and not r.keeps_tangential and r.friction_direction() \
                and j.friction is not None:
            mu_k = abs(float(sp.sympify(r.coefficient(j.friction)).xreplace(pv)))
            names.append(F.name)
            of[F.name] = mu_k * of[N.name]
    return list(names), np.array([of[n] for n in names], dtype=float)


def recheck(system, regime: RegimeResult, q, qd, t, values: dict, point=None, method="generalized_euler") -> list:
    """``regime``'s contact checks redone with ``values`` (its values with those that are 0 to
    round-off set to 0, :func:`solver.analyses.instant.round_off_zeros`), so that the reasons
    print the forces the table does; its own checks where the variant cannot be had or a
    check fails on them (a condition that held by round-off only)."""
    if regime.indeterminate:
        return regime.checks
    try:
        variant = regime_system(system, regime.regimes, q, qd, t) if method == "lagrange" or \
            regime_system(system, regime.regimes, q, qd, t) is system else _augmented(system, point, method).variant
    except SceneError:
        return regime.checks
    qdd = [values[str(c.qdd)] for c in variant.free]
    checks, failure = _check(variant, regime.regimes, q, qd, qdd, t, dict(values))
    return regime.checks if failure else checks


def _check(variant, regimes, q, qd, qdd, t, values, strict_direction=True):
    forces = [abs(v) for k, v in values.items() if k in {r.name for r in variant.reactions}]
    fscale = max(forces, default=0.0) + 1e-300
    ascale = 1.0 + max((abs(a) for a in qdd), default=0.0)
    vscale = 1.0 + max((abs(v) for v in qd), default=0.0)
    qscale = 1.0 + max((abs(v) for v in q), default=0.0)
    pv = variant.si_values()
    checks = []
    for j in variant.contacts:
        r = regimes.get(j.name, j.current_regime)
        gap, vgap, an, vt, at = _kin(variant, j.name, q, qd, qdd, t)
        F, N = j.pair
        if r is SEPARATED:
            closed = gap <= GAP_TOL * qscale and vgap <= TOL * vscale
            if closed and an < -TOL * ascale:
                return [], f"{j.name} separated would penetrate (gap acceleration {an:.6g})"
            checks.append(ContactCheck(j.name, r, f"the gap opens (gap acceleration {an:.6g} >= 0)" if closed
                                       else f"apart (gap = {_shown(gap, 'm', variant)}, opening speed = {_shown(vgap, 'm/s', variant)})"))
            continue
        n = values[N.name]
        if N.one_sided and n < -TOL * fscale:
            return [], f"{j.name} would pull ({N.name} = {_shown(n, 'N', variant)} < 0)"
        if r.keeps_tangential:
            f = values[F.name]
            mu_s = math.inf if j.friction is None else float(sp.sympify(j.friction.static).xreplace(pv))
            need = abs(f) / n if n > 0 else (0.0 if f == 0 else math.inf)
            if abs(f) > mu_s * n + TOL * fscale:
                return [], (f"{j.name} sticking needs |{F.name}| = {_shown(abs(f), 'N', variant)} > mu_s {N.name} = "
                            f"{_shown(mu_s * n, 'N', variant)} (least mu = {need:.6g})")
            why = (f"sticks: |{F.name}| = {_shown(abs(f), 'N', variant)} <= mu_s {N.name} = {_shown(mu_s * n, 'N', variant)}"
                   if math.isfinite(mu_s) else "rolls without slip (no friction limit given)")
            checks.append(ContactCheck(j.name, r, why, n, f, need))
            continue
        s = r.friction_direction()
        mu_k = 0.0 if j.friction is None or not s else float(sp.sympify(r.coefficient(j.friction)).xreplace(pv))
        f = -s * mu_k * n + 0.0  # (no -0.0 for a normal force of 0)
        if F is not None:
            values[F.name] = f
        if strict_direction and s and s * at < -TOL * ascale and abs(vt) <= TOL * vscale:
            return [], f"the sliding at {j.name} would accelerate in the {'-' if s > 0 else '+'} direction, against the slip"
        friction = f"{F.name} = " if F is not None else "= "  # the slip's sign written out, not as s
        why = ("slides without friction" if j.friction is None else  # (a scene may name a coordinate s)
               f"slides ({'+' if s > 0 else '-'} along its line): friction {friction}{'-' if s > 0 else ''}"
               f"mu_k {N.name} = {_shown(f, 'N', variant)}")
        checks.append(ContactCheck(j.name, r, why, n, f))
    return checks, None


def _in_words(regime: Regime) -> str:
    """A contact's regime in words for a sentence (``slip - (impending)`` as "starting to slip in the
    - direction"): the labels are names for tables and JSON, and their bare signs read badly in prose."""
    if isinstance(regime, Slip):
        return (f"{'starting to slip' if regime.impending else 'slipping'} in the "
                f"{'+' if regime.direction > 0 else '-'} direction")
    return {STICK.label: "sticking", SEPARATED.label: "separated"}.get(regime.label, regime.label)


def _shown(value: float, unit: str, system) -> str:
    """``value`` (in the SI ``unit``) as the commands print it, in the scene's ``[output_units]``
    (:func:`solver.output_units.in_output_units`): ``52.5536 N``, or ``11.8145 lbf``."""
    value, unit = in_output_units(value, unit, system.output_units)
    return f"{value:.6g} {unit}"


def _redundant_stick(system, regimes, q, qd, t, point=None, method="generalized_euler"):
    """A redundant stick: the least-squeeze split of the indeterminate forces (:data:`SPLIT_SHOWN`),
    or a string saying why no split keeps every contact inside its cone.

    Notes
    -----
    The equations about any point P (and the mass-centre form) are row combinations of
    one another, so A x = b has the same solutions x = x0 + Z y whichever P wrote them:
    x0 of least norm (SI), Z an orthonormal basis of the forces' free directions. Of
    the y keeping every contact :data:`SPLIT_MARGIN` of the largest force of x0 inside its
    cone (N >= d, |F| <= mu_s N - d), the one of least norm is taken (:func:`_least_norm_point`);
    when no y does, of those inside with no margin. |x|^2 = |x0|^2 + |y|^2, so this is the
    split of least norm among the admissible ones: unique (a strictly convex function on a
    convex set) and set by the physics alone, neither by P nor by how the rows are written.
    """
    aug = _augmented(system, point, "generalized_euler" if method == "lagrange" else method)
    A, b, names = aug.system_of(regimes, q, qd, t)
    family = _solution_family(A, b, [names.index(c) for c in aug.qdd])
    if isinstance(family, str):
        return family
    x0, Z = family
    G = _cone_rows(aug, regimes, names)
    forces = [abs(x0[i]) for i, n in enumerate(names) if n not in aug.qdd]
    fscale = max(forces, default=0.0)
    for margin in (SPLIT_MARGIN * fscale, 0.0):  # inside by the margin, else inside at all
        y = _least_norm_point(G @ Z, -margin - G @ x0, TOL * fscale)
        if y is not None:
            break
    else:
        return "no split of the indeterminate contact forces stays inside every friction cone"
    values = dict(zip(names, map(float, x0 + Z @ y)))
    checks = [ContactCheck(j.name, regimes.get(j.name, j.current_regime),
                           "sticks (statically indeterminate: splits of the forces inside every cone exist)",
                           values[j.pair[1].name], values[j.pair[0].name] if j.pair[0] else 0.0)
              for j in aug.variant.contacts if regimes.get(j.name) is not SEPARATED]
    return RegimeResult(dict(regimes), system, values, checks, indeterminate=True)


def _solution_family(A, b, accelerations):
    """(x0, Z): every solution of the singular A x = b is x0 + Z y, x0 the one of least
    (SI) norm and Z's columns orthonormal; or a string when A x = b has no solution or
    leaves an acceleration (a column in ``accelerations``) undetermined.

    The rank is the solver's singularity decision on the equilibrated matrix (singular
    values under 1 / :data:`~solver.analyses.instant.CONDITION_LIMIT` of the largest are
    zero); x0 and Z are then taken in SI, with no column scaling, which would change the norm.
    """
    from .instant import CONDITION_LIMIT, _equilibrate

    As, row, col = _equilibrate(A)
    bs = b / row
    U, s, Vt = np.linalg.svd(As)
    rank = int(np.sum(s > s[0] / CONDITION_LIMIT)) if s.size and s[0] > 0 else 0
    ys = Vt[:rank].T @ ((U[:, :rank].T @ bs) / s[:rank])
    if np.abs(As @ ys - bs).max(initial=0.0) > TOL * (np.abs(As) @ np.abs(ys) + np.abs(bs)).max(initial=0.0):
        return "no set of forces satisfies the equations (inconsistent)"
    Z, _ = np.linalg.qr(Vt[rank:].T / col[:, None])  # A (v / col) = 0 when As v = 0
    x = ys / col
    x0 = x - Z @ (Z.T @ x)  # the particular solution's free part taken out: the least norm
    if Z.size and np.abs(Z[accelerations]).max(initial=0.0) > TOL:
        return "the sticking contacts leave the accelerations undetermined"
    # round-off of the SVD (1e-16 where a body is held at rest) kept out of the accelerations:
    # the free directions move forces only, and an acceleration under TOL of the largest unknown
    # (equilibrated; the sign tests' threshold) is zero
    Z[accelerations] = 0.0
    small = np.abs(x0 * col) <= TOL * np.abs(x0 * col).max(initial=0.0)
    x0[accelerations] = np.where(small[accelerations], 0.0, x0[accelerations])
    return x0, Z


def _cone_rows(aug, regimes, names):
    """G with G x <= -d for every contact at least d inside its cone: a one-sided
    N >= d (-N <= -d); a sticking contact with friction +-F - mu_s N <= -d."""
    pv = aug.variant.si_values()
    rows = []
    for j in aug.variant.contacts:
        r = regimes.get(j.name, j.current_regime)
        if not r.keeps_normal:
            continue
        F, N = j.pair
        iN = names.index(N.name)
        if N.one_sided:
            rows.append(np.zeros(len(names)))
            rows[-1][iN] = -1.0
        if r.keeps_tangential and j.friction is not None:
            mu = float(sp.sympify(j.friction.static).xreplace(pv))
            for sgn in (1.0, -1.0):
                rows.append(np.zeros(len(names)))
                rows[-1][[names.index(F.name), iN]] = sgn, -mu
    return np.array(rows).reshape(len(rows), len(names))


def _least_norm_point(C, d, tol):
    """The y of least Euclidean norm with C y <= d (each row to ``tol``), or None when none has.

    At the optimum y = -C_S^T lam (lam >= 0) for a set S of active rows (KKT), which may be
    taken linearly independent (at most len(y) rows): y is then the least-norm solution of
    C_S y = d_S. Every such set is tried and the feasible solution of least norm kept (few
    rows and free directions: at most 3 rows per contact, :data:`MAX_CONTACTS` contacts).
    """
    m, k = C.shape
    size = np.linalg.norm(C, axis=1)
    free = size <= 1e-12 * size.max(initial=0.0)  # rows y does not enter: 0 <= d
    if np.any(d[free] < -tol):
        return None
    Cn, dn = C / np.where(free, 1.0, size)[:, None], d / np.where(free, 1.0, size)
    best = None
    for n in range(min(k, m) + 1):
        for S in itertools.combinations(np.flatnonzero(~free), n):
            CS = Cn[list(S)]
            if n and np.linalg.matrix_rank(CS, tol=1e-9) < n:
                continue
            y = CS.T @ np.linalg.solve(CS @ CS.T, dn[list(S)]) if n else np.zeros(k)
            if np.all(C @ y <= d + tol) and (best is None or y @ y < best @ best):
                best = y
    return best


def least_friction(system, state) -> dict:
    """Per contact that can stick or roll: the least mu that keeps it so at ``state``.

    The contacts asked about are those with a friction coefficient and those
    that roll without one (a rolling contact the scene gives no coefficient
    rolls by assumption; the least mu that keeps it rolling is still |F| / N).
    A frictionless rail, which slides freely, is not asked about. Every
    touching contact asked about is assumed to stick; the least coefficient
    is then |F| / N. A contact already sliding, open, or held redundantly
    (statically indeterminate forces) gets a note instead.
    """
    from ..formulations import formulate

    q, qd, t = state.q, state.qd, state.t
    out, regimes = {}, {}
    scale_v = 1.0 + max((abs(v) for v in qd), default=0.0)
    for j in system.contacts:
        if j.friction is None and not j.current_regime.keeps_tangential:
            continue  # frictionless: it slides, no coefficient to find
        gap, vgap, _, vt, _ = _kin(system, j.name, q, qd, [0.0] * len(q), t)
        if j.normal_reaction.one_sided and gap > GAP_TOL * (1.0 + max(map(abs, q), default=0.0)):
            out[j.name] = {"value": None, "note": "apart at the state"}
        elif abs(vt) > TOL * scale_v:
            out[j.name] = {"value": None, "note": f"sliding at the state (at {vt:.6g})"}
        else:
            regimes[j.name] = STICK
    if not regimes:
        return out
    try:
        variant = regime_system(system, regimes, q, qd, t)
        res = formulate(variant).numeric().solve(q, qd, t, once=True)
    except RedundantConstraints:
        for name in regimes:
            out[name] = {"value": None, "note": "statically indeterminate (held redundantly): see --critical"}
        return out
    for j in variant.contacts:
        if j.name in regimes:
            out[j.name] = _ratio_entry(j, float(res[j.pair[0].name]), float(res[j.pair[1].name]), variant)
    return out


def _ratio_entry(joint, f, n, system) -> dict:
    """The least-mu entry of a sticking (rolling) contact: |F|/N, with a note on how it was found."""
    F, N = (r.name for r in joint.pair)
    if not n > 0:
        return {"value": math.inf, "note": f"{N} = {_shown(n, 'N', system)} pulls"}
    given = ("no coefficient given: it rolls by assumption" if joint.friction is None else
             f"the scene's mu_s = {float(sp.sympify(joint.friction.static).xreplace(system.si_values())):g}")
    return {"value": abs(f) / n, "note": f"|{F}|/{N} with {F} = {_shown(f, 'N', system)}, {N} = {_shown(n, 'N', system)} ({given})"}


def holding(system):
    """A copy of ``system`` in which every contact with friction sticks (rolls) without limit."""
    from dataclasses import replace

    sticking = {j.name: STICK for j in system.contacts if j.friction is not None}
    new = system.with_regimes(sticking) if sticking else system
    if sticking:
        new.joints = [replace(j, friction=None) if j.name in sticking else j for j in new.joints]
        new.reset()
    return new


def with_every_contact_force(system):
    """``system`` with every contact's friction and normal force as reactions (sticking form),
    for showing forces: a sliding contact's friction (-s mu_k N) and a separated contact's
    zero forces are then drawn along their own directions. The system itself without contacts."""
    if not system.contacts:
        return system
    return _augmented(system, None, "generalized_euler").variant
