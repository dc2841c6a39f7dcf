"""One-degree-of-freedom energy model and the exact period of free oscillation.

The scene's equation of motion in its coordinate q (``theta``) has the form

    M(q) q'' + 1/2 M'(q) q'^2 + V'(q) = Q(q, q', t)

(the normalised ``Derivation.eom``; for Example 2 this is the paper's Eq. 44
with the sign of F_a corrected). :class:`OneDofSystem` holds M, V, Q, the
angular acceleration and the reactions as sympy expressions and compiles them
once into numeric functions. The rest of the dynamics modules
(:mod:`solver.simulate`, :mod:`solver.friction`, :mod:`solver.fidelity`) work
on it.

With Q depending on q alone the energy E = 1/2 M q'^2 + V - int Q dq is
conserved, and released from rest at q0 the system swings between q0 and the
other turning point q1 (V(q1) = V(q0)) with the period

    T = 2 int_{q1}^{q0} sqrt( M(q) / (2 (V(q0) - V(q))) ) dq .

The integrand has inverse square-root singularities at both turning points.
:func:`exact_period` removes them with the substitution
q = q_m + h sin(u) (q_m the midpoint, h the half-width): then
(q0 - q)(q - q1) = h^2 cos^2 u, and

    T = 2 int_{-pi/2}^{pi/2} sqrt( M(q) / (2 g(q)) ) du ,
    g(q) = (V(q0) - V(q)) / ((q0 - q)(q - q1)) > 0 ,

a smooth integrand whose even, periodic extension in u makes the midpoint
rule (Gauss-Chebyshev quadrature of the first kind) converge geometrically;
the rule with 3n nodes contains the one with n, so one evaluation gives the
sum and its error estimate. Near the turning points V(q0) - V(q) is a
difference of nearly equal numbers: it is written once per scene without
cancellation (products of half-differences, :func:`_difference`) and each node
is measured from its nearer turning point, so the float64 sum keeps its
accuracy at every amplitude; when the round-off estimate still threatens the
requested tolerance the sum is evaluated in mpmath at higher precision.

When M and V are affine in cos q and sin q with the same phase (M = A + B cos x,
V = -C cos x + const in x = q - q_c, q_c the minimum of V: the pendulum, the
disk-bar of Example 2, the rocking semicircle), :func:`elliptic_period` gives
the period in closed form. With k = sin(a/2) and sin(x/2) = k sin(phi),

    T = 4 sqrt((A + B) / C) [R_F(0, 1 - k^2, 1 - m) - (m/3) R_J(0, 1 - k^2, 1 - m, 1)],
    m = 2 B k^2 / (A + B),

Carlson's complete elliptic integrals of the first and third kinds
(scipy.special.elliprf, elliprj; B = 0 leaves 4 sqrt(A/C) K(k) of the pendulum).

The linearized period about the stable equilibrium q_e is
T_0 = 2 pi sqrt(M(q_e) / V''(q_e)) (paper Eq. 46 for Example 2).
"""
from __future__ import annotations

import bisect
import functools
import math
from dataclasses import dataclass, field, replace
from typing import Any, Callable

import mpmath
import numpy as np
import sympy as sp
from scipy.optimize import brentq

from .errors import InputError, NoRestoringError
from .display import tidy
from .model.system import derivative
from .strprint import lambdify

__all__ = [
    "QuadratureError",
    "FrictionPair",
    "OneDofSystem",
    "Equilibrium",
    "PeriodResult",
    "find_equilibrium",
    "turning_points",
    "linear_period",
    "exact_period",
    "EllipticForm",
    "elliptic_form",
    "elliptic_period",
    "PERIOD_METHODS",
    "TOL_MIN",
    "TOL_MAX",
    "check_limits",
]

from .limits import TOL_MAX, TOL_MIN  # noqa: E402 - the accepted range of tolerances
_EPS = float(np.finfo(float).eps)
_MAX_NODES = 2**17
_MP_DPS = 34


class QuadratureError(InputError):
    """The period quadrature did not converge to the tolerance (very near the separatrix)."""


# --------------------------------------------------------------------------- model
@dataclass(frozen=True)
class FrictionPair:
    """The two reactions of one rolling contact and its friction coefficient.

    Attributes
    ----------
    constraint : str
        Name of the rolling constraint.
    friction, normal : str
        Reaction names: tangential (friction) and normal force. [N]
    mu : float or None
        Coefficient of static friction given by the scene, if any.
    """

    constraint: str
    friction: str
    normal: str
    mu: float | None = None


def _drop_constants(V: sp.Expr, q: sp.Symbol) -> sp.Expr:
    """V without its additive terms free of q (they do not change the motion, but a large
    constant such as m_d g r_d would swamp the differences V(q0) - V(q) in float64)."""
    expanded = sp.expand(V)
    if sp.count_ops(expanded) > 4 * sp.count_ops(V) + 20:
        return V
    return sp.Add(*[term for term in sp.Add.make_args(expanded) if term.has(q)])


def check_limits(system: "OneDofSystem", q: float, what: str) -> None:
    """InputError when a model limit g(q) >= 0 of ``system`` fails at ``q`` [rad]."""
    for i, (text, g) in enumerate(system.limits):  # compiled once per system (each period checks both ends)
        value = float(_scalar(system, ("limit", i), (system.q,), lambda g=g: sp.sympify(g))(q, *system.values))
        if value < -1e-12:
            raise InputError(
                f"{system.name}: {system.q} = {math.degrees(q):.6g} deg ({what}) is outside the model: "
                f"it holds only while {text} (there the straight edge meets the surface)"
            )


@dataclass(frozen=True, eq=False)
class OneDofSystem:
    """A one-degree-of-freedom system in the energy form of its equation of motion.

    All expressions are sympy in the coordinate ``q``, its rate ``qd``, time
    ``t`` and the parameter symbols ``params`` (whose numeric SI values are
    ``values``); the reactions and ``alpha`` have theta_ddot already
    eliminated where the Derivation provides them so.

    Attributes
    ----------
    q, qd, qdd, t : sympy.Symbol
    mass : sympy.Expr
        Generalized mass M(q). [kg m^2 for an angle]
    potential : sympy.Expr
        Potential energy V(q) of gravity. [J]
    generalized_force : sympy.Expr
        Q(q, qd, t) of the other (non-gravity) loads. [N m]
    alpha : sympy.Expr
        k-component of the angular acceleration in (q, qd, qdd). [rad/s^2]
    reactions : dict[str, sympy.Expr]
        Reactions in (q, qd, t) with qdd eliminated. [N or N m]
    reaction_units : dict[str, str]
    one_sided : tuple[str, ...]
        Reactions that can only push (simulation stops when one turns negative).
    friction_pairs : tuple[FrictionPair, ...]
    reaction_constraints : dict[str, str]
        Reaction name -> name of the constraint that brings it (for messages).
    system_matrix, system_rhs : sympy.Matrix, optional
        The instantaneous linear system A @ unknowns = b of the Derivation
        (unknowns = (theta_ddot, *reactions), named in ``unknown_names``).
        When given, reactions are computed by solving it numerically, which
        stays finite where the closed-form reaction expressions have a
        removable 0/0 (e.g. Example 2's expressions at theta = 0).
    unknown_names : tuple[str, ...]
    params : tuple[sympy.Symbol, ...]
    values : tuple[float, ...]
        SI values of ``params``.
    name : str
        For messages (the scene file).
    limits : tuple of (str, sympy.Expr)
        Conditions g(q) >= 0 for the model to hold, each with a description: a
        semicircular disk rolls on its curved rim only while the contact point
        lies on the rim (``Rolling.limits``).
    kind : str
        The coordinate's kind, ``"angle"`` or ``"length"`` (for messages: a restoring
        moment or force, rad or m).
    """

    q: sp.Symbol
    qd: sp.Symbol
    qdd: sp.Symbol
    t: sp.Symbol
    mass: sp.Expr
    potential: sp.Expr
    generalized_force: sp.Expr = sp.Integer(0)
    alpha: sp.Expr | None = None
    reactions: dict[str, sp.Expr] = field(default_factory=dict)
    reaction_units: dict[str, str] = field(default_factory=dict)
    one_sided: tuple[str, ...] = ()
    friction_pairs: tuple[FrictionPair, ...] = ()
    reaction_constraints: dict[str, str] = field(default_factory=dict)
    system_matrix: sp.Matrix | None = None
    system_rhs: sp.Matrix | None = None
    unknown_names: tuple[str, ...] = ()
    params: tuple[sp.Symbol, ...] = ()
    values: tuple[float, ...] = ()
    name: str = "system"
    limits: tuple[tuple[str, sp.Expr], ...] = ()
    kind: str = "angle"
    _cache: dict = field(default_factory=dict, repr=False, compare=False)

    # -- construction ---------------------------------------------------------
    @classmethod
    def from_derivation(cls, derivation: Any, reactions: bool = True) -> "OneDofSystem":
        """Build the model from a :class:`solver.derivation.Derivation`.

        Uses ``mass``, ``potential_energy``, ``generalized_force``, ``alpha``,
        ``reactions``, ``reaction_units`` and the scene's constraints (rolling
        normal forces are always one-sided; ``Constraint.one_sided`` marks the
        others). Parameter values are the scene's SI values. ``reactions=False``
        skips the reactions and the linear system (the period does not need
        them; deriving them is most of a one-off derivation's cost).
        """
        system = derivation.system
        si = system.si_values()
        params = tuple(si)
        values = tuple(float(v) for v in si.values())
        subs = dict(si)
        one_sided: list[str] = []
        pairs: list[FrictionPair] = []
        owners: dict[str, str] = {}
        for j in system.joints:
            owners.update({r.name: j.name for r in j.reactions})
            one_sided.extend(j.one_sided)
            if j.friction_pair is not None:
                friction, normal, mu = j.friction_pair
                mu = None if mu is None else float(sp.sympify(mu).xreplace(subs))
                pairs.append(FrictionPair(j.name, friction, normal, mu))
        want = reactions
        reactions = dict(derivation.reactions) if want else {}
        A, b = derivation.linear_system() if want else (None, None)
        units = dict(getattr(derivation, "reaction_units", {}) or {})
        return cls(
            q=derivation.q,
            qd=derivation.qd,
            qdd=derivation.qdd,
            t=derivation.t,
            mass=derivation.mass,
            potential=derivation.potential_energy,
            generalized_force=derivation.generalized_force,
            alpha=derivation.alpha if want and len(derivation.system.bodies) == 1 else None,
            reactions=reactions,
            reaction_units={k: units.get(k, "N") for k in reactions},
            one_sided=tuple(one_sided),
            friction_pairs=tuple(pairs),
            reaction_constraints=owners,
            system_matrix=A,
            system_rhs=b,
            unknown_names=tuple(str(u) for u in derivation.unknowns),
            params=params,
            values=values,
            name=system.label,
            limits=tuple(system.limits()),
            kind=system.free[0].kind if len(system.free) == 1 else "angle",
        )

    def with_values(self, **changes: float) -> "OneDofSystem":
        """A copy with some parameter values changed (SI), sharing the compiled code."""
        names = [p.name for p in self.params]
        values = list(self.values)
        for key, val in changes.items():
            if key not in names:
                raise InputError(
                    f"{self.name}: unknown parameter {key!r}; parameters are {', '.join(names)}"
                )
            values[names.index(key)] = float(val)
        return replace(self, values=tuple(values), _cache=self._cache)

    @property
    def restoring(self) -> tuple[str, str]:
        """What restores the coordinate and its SI unit, for messages: ("moment", "rad") for an
        angle, ("force", "m") for a length."""
        return ("force", "m") if self.kind == "length" else ("moment", "rad")

    def value_of(self, name: str) -> float:
        names = [p.name for p in self.params]
        if name not in names:
            raise InputError(f"{self.name}: the scene has no parameter {name!r}; parameters are {', '.join(names)}")
        return self.values[names.index(name)]

    # -- derived expressions --------------------------------------------------
    def _memo(self, key, build):
        if key not in self._cache:
            self._cache[key] = build()
        return self._cache[key]

    def _active_force(self) -> tuple[sp.Expr, tuple[str, ...]]:
        """Q with the parameters whose value is 0 set to 0 (``--set F_0="0 N"`` switches a
        time-dependent push off), and the names of those parameters."""
        zeros = {p: sp.Integer(0) for p, v in zip(self.params, self.values) if v == 0}
        Q = sp.sympify(self.generalized_force)
        return (Q.xreplace(zeros) if zeros else Q), tuple(sorted(p.name for p in zeros))

    @property
    def is_conservative(self) -> bool:
        """True when Q depends on q at most (then the energy integral applies)."""
        Q, _ = self._active_force()
        return not ({self.qd, self.t} & Q.free_symbols)

    def effective_potential(self) -> sp.Expr:
        """V(q) - int_0^q Q(s) ds: the potential of gravity plus the position-dependent loads.

        Additive constants of V are dropped (they do not change the motion).

        Raises
        ------
        InputError
            When Q depends on the rate or on time (no potential exists).
        """

        Q, zeros = self._active_force()

        def build():
            if not self.is_conservative:
                raise InputError(
                    f"{self.name}: the loads' generalized force depends on the rate or on time "
                    f"(Q = {tidy(Q)}); free oscillation needs them constant or position-dependent "
                    "(set them to zero with --set)"
                )
            V = _drop_constants(sp.sympify(self.potential), self.q)
            if Q == 0:
                return V
            s = sp.Dummy("s", real=True)
            work = sp.integrate(Q.subs(self.q, s), (s, 0, self.q))
            if work.has(sp.Integral):
                raise InputError(f"{self.name}: cannot integrate the generalized force Q = {tidy(Q)} into a potential")
            return V - work

        return self._memo(("V_eff", zeros), build)

    def qdd_expression(self) -> sp.Expr:
        """theta_ddot = (Q - 1/2 M' qd^2 - V') / M  (the normalised eom solved for qdd)."""

        def build():
            M = self.mass
            return (self.generalized_force - sp.Rational(1, 2) * derivative(M, self.q) * self.qd**2
                    - derivative(self.potential, self.q)) / M

        return self._memo("qdd", build)

    # -- compiled functions (args: state..., *params) --------------------------
    def _fn(self, key: str, args: tuple, expr_builder: Callable[[], Any], modules) -> Callable:
        def build():
            f = lambdify(tuple(args) + self.params, expr_builder(), modules, cse=True)
            return f

        return self._memo((key, str(modules)), build)

    def mass_fn(self) -> Callable[[Any], Any]:
        f = self._fn("M", (self.q,), lambda: self.mass, "numpy")
        vals = self.values
        return lambda q: np.asarray(f(q, *vals), dtype=float) + 0.0 * np.asarray(q, dtype=float)

    def potential_fn(self, derivative: int = 0, precision: str = "float64") -> Callable[[Any], Any]:
        """V_eff^(derivative)(q) as a function.

        ``precision``: ``"float64"`` (vectorised), ``"scalar"`` (a Python float in,
        a float out, through the ``math`` module: about 20 times cheaper per call,
        for root finding) or ``"mpmath"``.
        """
        def expr():
            # a spring's length |e| differentiates to sign(e) and then to 2 DiracDelta(e): zero wherever
            # e != 0, and at e = 0 the spring's line, so its force, is undefined anyway
            return sp.diff(self.effective_potential(), self.q, derivative).replace(sp.DiracDelta, lambda *a: sp.S.Zero)

        key = (f"V{derivative}", self._zero_parameters())  # V_eff depends on which loads are switched off
        if precision == "mpmath":
            f = self._fn(key, (self.q,), expr, "mpmath")
            mvals = [mpmath.mpf(v) for v in self.values]
            return lambda q: f(q, *mvals)
        vals = self.values
        if precision == "scalar":
            f = _scalar(self, key, (self.q,), expr)
            return lambda q: float(f(q, *vals))
        f = self._fn(key, (self.q,), expr, "numpy")
        return lambda q: np.asarray(f(q, *vals), dtype=float) + 0.0 * np.asarray(q, dtype=float)

    def _zero_parameters(self) -> tuple[str, ...]:
        """Names of the parameters whose value is 0 (memoised per set of values: the same
        as :meth:`_active_force` reports, without its symbolic substitution)."""
        return self._memo(("zeros", self.values), lambda: self._active_force()[1])

    def qdd_fn(self) -> Callable:
        """Vectorised theta_ddot(q, qd, t)."""
        f = self._fn("qdd", (self.q, self.qd, self.t), self.qdd_expression, "numpy")
        vals = self.values
        return lambda q, qd, t: f(q, qd, t, *vals)

    def qdd_scalar_fn(self) -> Callable[[float, float, float], float]:
        """theta_ddot(q, qd, t) on Python floats (``math`` module: the fast rhs)."""
        f, vals, _ = self.qdd_scalar_parts()
        return lambda q, qd, t: float(f(q, qd, t, *vals))

    def qdd_scalar_parts(self) -> tuple[Callable, tuple[float, ...], bool]:
        """(f, values, plain): theta_ddot = f(q, qd, t, *values), lambdified for the ``math`` module
        (``plain`` True: on Python floats it gives a Python number, float or a constant int) or,
        where ``math`` lacks a function, for numpy (``plain`` False: convert with ``float``).
        For a right-hand side called hundreds of thousands of times without the wrapper of
        :meth:`qdd_scalar_fn`."""
        try:
            f = self._fn("qdd", (self.q, self.qd, self.t), self.qdd_expression, "math")
            f(0.1, 0.2, 0.0, *self.values)
            return f, self.values, True
        except (NameError, TypeError, AttributeError, KeyError, ZeroDivisionError, ValueError, OverflowError):
            return self._fn("qdd", (self.q, self.qd, self.t), self.qdd_expression, "numpy"), self.values, False

    def linear_system_fn(self) -> Callable[[Any, Any, Any], tuple[np.ndarray, np.ndarray]]:
        """Vectorised (A, b) of the instantaneous linear system, shapes (..., n, n) and (..., n)."""
        if self.system_matrix is None:
            raise InputError(f"{self.name}: no instantaneous linear system attached")
        A, b = self.system_matrix, self.system_rhs
        n = A.shape[0]
        f = self._fn("Ab", (self.q, self.qd, self.t), lambda: list(A) + list(b), "numpy")
        vals = self.values

        def g(q, qd, t):
            q, qd, t = np.broadcast_arrays(np.asarray(q, dtype=float), np.asarray(qd, dtype=float),
                                           np.asarray(t, dtype=float))
            with np.errstate(all="ignore"):
                out = f(q, qd, t, *vals)
            out = [np.broadcast_to(np.asarray(v, dtype=float), q.shape) for v in out]
            Am = np.stack(out[: n * n], axis=-1).reshape(q.shape + (n, n))
            bm = np.stack(out[n * n:], axis=-1)
            return Am, bm

        return g

    def _solve_fn(self) -> Callable:
        """Vectorised unknowns by solving A x = b; singular states give nan (the solver's
        one singularity decision: the condition estimate of ``solve_with_estimate``
        above CONDITION_LIMIT; no SVD)."""
        from .analyses.instant import CONDITION_LIMIT, solve_with_estimate

        Ab = self.linear_system_fn()

        def g(q, qd, t):
            A, b = Ab(q, qd, t)
            x, cond = solve_with_estimate(A, b)
            bad = ~(cond <= CONDITION_LIMIT)
            return np.where(bad[..., None], np.nan, x)

        return g

    def reactions_fn(self) -> Callable[[Any, Any, Any], dict[str, np.ndarray]]:
        """Vectorised reactions(q, qd, t) -> {name: array} (nan at singular configurations)."""
        names = tuple(self.reactions)
        if not names:
            return lambda q, qd, t: {}
        if self.system_matrix is not None:
            solve = self._solve_fn()
            idx = [self.unknown_names.index(n) for n in names]

            def gs(q, qd, t):
                x = solve(q, qd, t)
                return {n: np.array(x[..., i], dtype=float) for n, i in zip(names, idx)}

            return gs
        f = self._fn("R", (self.q, self.qd, self.t), lambda: [self.reactions[n] for n in names], "numpy")
        vals = self.values

        def g(q, qd, t):
            shape = np.broadcast(np.asarray(q), np.asarray(qd), np.asarray(t)).shape
            with np.errstate(all="ignore"):
                out = f(q, qd, t, *vals)
            return {n: np.broadcast_to(np.asarray(v, dtype=float), shape).copy() for n, v in zip(names, out)}

        return g

    def _scalar_solver(self) -> Callable[[float, float, float], tuple[list[float], float]]:
        """(unknowns, det of the row-scaled A) at one state, on Python floats.

        ``math``-lambdified A and b and Gaussian elimination with partial
        pivoting in pure Python: about 20x cheaper per call than numpy for a
        3x3 system, which matters inside event functions. The last state is
        remembered, so several events at the same (t, y) cost one solve: the
        solver is memoised per set of parameter values, so the reaction events
        (:meth:`reaction_scalar_fns`) and the singularity event
        (:meth:`singularity_fn`) share it (they used to solve the same state twice
        per integration step).
        """
        return self._memo(("scalar_solver", self.values), self._new_scalar_solver)

    def _new_scalar_solver(self) -> Callable[[float, float, float], tuple[list[float], float]]:
        """A fresh :meth:`_scalar_solver` (with its own last-state memory)."""

        def build():
            A, b = self.system_matrix, self.system_rhs
            args = (self.q, self.qd, self.t) + self.params
            try:
                f = lambdify(args, list(A) + list(b), "math", cse=True)
                f(0.1, 0.2, 0.0, *self.values)
            except (NameError, TypeError, AttributeError, KeyError, ZeroDivisionError, ValueError, OverflowError):
                f = lambdify(args, list(A) + list(b), "numpy", cse=True)
            return f, A.shape[0]

        f, n = self._memo("Ab_scalar", build)
        vals = self.values
        last: dict = {}

        eliminate = _eliminate3 if n == 3 else (lambda e: _eliminate(e, n))

        def solve(q, qd, t):
            key = (q, qd, t)
            if last.get("key") == key:
                return last["out"]
            out = eliminate([float(v) for v in f(q, qd, t, *vals)])
            last.update(key=key, out=out)
            return out

        return solve

    def reaction_scalar_fns(self) -> dict[str, Callable[[float, float, float], float]]:
        """Each reaction(q, qd, t) on Python floats (for event functions)."""
        if self.system_matrix is not None:
            solve = self._scalar_solver()
            idx = {n: self.unknown_names.index(n) for n in self.reactions}
            return {n: (lambda i: (lambda q, qd, t: solve(q, qd, t)[0][i]))(i) for n, i in idx.items()}
        R = self.reactions_fn()
        return {n: (lambda n: (lambda q, qd, t: float(R(q, qd, t)[n])))(n) for n in self.reactions}

    def singularity_fn(self) -> Callable[[float, float, float], float] | None:
        """det(A) of the row-scaled linear system as a scalar function (None without a system).

        Changes sign where the constraints stop determining the motion.
        """
        if self.system_matrix is None:
            return None
        solve = self._scalar_solver()
        return lambda q, qd, t: solve(q, qd, t)[1]

    def alpha_fn(self) -> Callable:
        """Vectorised alpha(q, qd, qdd) (k-component of the angular acceleration)."""
        expr = self.alpha if self.alpha is not None else self.qdd
        f = self._fn("alpha", (self.q, self.qd, self.qdd), lambda: expr, "numpy")
        vals = self.values

        def g(q, qd, qdd):
            shape = np.broadcast(np.asarray(q), np.asarray(qd), np.asarray(qdd)).shape
            return np.broadcast_to(np.asarray(f(q, qd, qdd, *vals), dtype=float), shape).copy()

        return g

    def energy_fn(self) -> Callable:
        """Vectorised mechanical energy E(q, qd) = 1/2 M qd^2 + V (gravity only). [J]"""
        M = self.mass_fn()
        f = self._fn("V_gravity", (self.q,), lambda: self.potential, "numpy")  # not "V0": that is V_eff (potential_fn)
        vals = self.values
        return lambda q, qd: 0.5 * M(q) * np.asarray(qd) ** 2 + np.asarray(f(q, *vals), dtype=float) + 0.0 * np.asarray(q)


# --------------------------------------------------------------------------- equilibrium
@dataclass(frozen=True)
class Equilibrium:
    """A stable equilibrium of V_eff.

    Attributes
    ----------
    q : float
        Coordinate. [rad]
    mass : float
        M(q_e).
    stiffness : float
        V_eff''(q_e) > 0.
    """

    q: float
    mass: float
    stiffness: float

    @property
    def omega(self) -> float:
        """Small-oscillation angular frequency sqrt(k / M). [rad/s]"""
        return math.sqrt(self.stiffness / self.mass)

    @property
    def period(self) -> float:
        """Linearized period 2 pi / omega. [s]"""
        return 2.0 * math.pi / self.omega


def _validate_find_equilibrium(system: OneDofSystem, near: float, span: float) -> None:
    if not isinstance(system, OneDofSystem):
        raise TypeError(f"`system` must be a OneDofSystem, got {type(system).__name__}")
    if not (math.isfinite(near) and math.isfinite(span) and span > 0):
        raise ValueError(f"`near` must be finite and `span` positive, got near={near!r}, span={span!r}")


def find_equilibrium(system: OneDofSystem, near: float = 0.0, span: float = 2.0 * math.pi) -> Equilibrium:
    """The stable equilibrium of V_eff (minimum) nearest to ``near``.

    Searches [near - span, near + span] for sign changes of V_eff' from - to +.

    Raises
    ------
    NoRestoringError
        No minimum with positive stiffness (e.g. a massless bar on a rolling
        disk: V is constant, no restoring moment).
    """
    _validate_find_equilibrium(system, near, span)
    # one search per model, place and parameter values (a report asks it for the frequency, the
    # period and the friction of one example)
    return system._memo(("equilibrium", near, span, system.values),
                        lambda: _find_equilibrium(system, near, span))


def _find_equilibrium(system: OneDofSystem, near: float, span: float) -> Equilibrium:
    """:func:`find_equilibrium`, searched."""
    V_expr = system.effective_potential()
    flat = system._memo(("flat", system.values), lambda: (
        not V_expr.has(system.q)
        or derivative(V_expr, system.q).xreplace(dict(zip(system.params, system.values))) == 0))
    what, unit = system.restoring
    if flat:
        raise NoRestoringError(
            f"{system.name}: the potential energy does not depend on {system.q} "
            f"(no restoring {what}: no oscillation, no period)"
        )
    dV = system.potential_fn(1)
    d2V = system.potential_fn(2)
    grid = np.linspace(near - span, near + span, 4097)
    with np.errstate(all="ignore"):
        d = dV(grid)
    scale = float(np.nanmax(np.abs(d))) if np.any(np.isfinite(d)) else 0.0
    if not scale > 0:
        raise NoRestoringError(f"{system.name}: no restoring {what} near {system.q} = {near:g} {unit}")
    candidates: list[float] = []
    for i in _rising_through_zero(d):
        if d[i + 1] == 0:
            root = grid[i + 1]
        else:
            root = brentq(lambda x: float(dV(x)), grid[i], grid[i + 1], xtol=1e-300, rtol=4 * _EPS, maxiter=200,
                          disp=False)  # a very flat root (V' ~ x^5): keep the last bracket
        candidates.append(float(root))
    stable = []
    with np.errstate(all="ignore"):
        h = np.abs(np.asarray(d2V(grid), dtype=float))
    # V'' at the round-off level of its size elsewhere counts as 0 (a flat minimum such as
    # V ~ x^6 has no linear oscillation), as in natural_frequency
    k_floor = 1e-12 * (float(np.nanmax(h)) if np.any(np.isfinite(h)) else 0.0)
    for r in candidates:
        k = float(d2V(r))
        m = float(system.mass_fn()(r))
        if k > k_floor and k > 0 and m > 0 and math.isfinite(k):
            stable.append(Equilibrium(r, m, k))
    if not stable:
        raise NoRestoringError(
            f"{system.name}: no stable equilibrium (minimum of the potential with positive stiffness) "
            f"within {span:g} {unit} of {system.q} = {near:g} {unit}"
        )
    return min(stable, key=lambda e: (abs(e.q - near), e.q))


def _rising_through_zero(d: np.ndarray) -> np.ndarray:
    """The indices i, in order, where the samples ``d`` of V' rise through zero from d[i] to d[i+1]
    (both finite): d[i] < 0 <= d[i+1], or d[i] = 0 between d[i-1] < 0 and d[i+1] > 0."""
    a, b = d[:-1], d[1:]
    before = np.concatenate(([np.nan], d[:-2]))  # d[i-1]; none before the first sample
    rising = (a < 0) & (0 <= b) | (a == 0) & (before < 0) & (0 < b)
    return np.flatnonzero(rising & np.isfinite(a) & np.isfinite(b))


def linear_period(system: OneDofSystem, equilibrium: Equilibrium | None = None) -> float:
    """Linearized period T0 = 2 pi sqrt(M(q_e) / V''(q_e)) [s] (paper Eq. 46 for Example 2)."""
    eq = equilibrium if equilibrium is not None else find_equilibrium(system)
    return eq.period


# --------------------------------------------------------------------------- turning points
# Below this many float64 ulps of |V| the rise V(q0) - V(q_e) places the far turning
# point to worse than ~1e-8 relative in float64 (its error is eps |V| / (2 rise)).
_RESOLVED = 1e8


def _small_amplitude_turning_point(system: OneDofSystem, equilibrium: Equilibrium, amplitude: float) -> float:
    """Far turning point of a release at q_e + amplitude when float64 cannot resolve V there.

    Solves V(q1) = V(q_e + amplitude) with mpmath, at enough digits for the rise
    k a^2 / 2; the start q_e - amplitude is the quadratic approximation (kept if the
    root finder strays).
    """
    qe, a = equilibrium.q, amplitude
    guess = qe - a
    if a == 0.0 or qe + a == qe:
        return guess
    dps = _MP_DPS + max(0, int(math.ceil(-2.0 * math.log10(abs(a)))))
    Vmp = system.potential_fn(0, precision="mpmath")
    with mpmath.workdps(dps):
        mq0 = mpmath.mpf(qe) + mpmath.mpf(a)
        V0 = Vmp(mq0)
        try:
            root = mpmath.findroot(lambda x: Vmp(x) - V0, mpmath.mpf(guess))
        except (ValueError, ZeroDivisionError):
            return guess
        q1 = float(root)
    if not (math.isfinite(q1) and 0.5 * abs(a) <= abs(q1 - qe) <= 2.0 * abs(a) and (q1 - qe) * a < 0):
        return guess
    return q1

def _separatrix_error(system: OneDofSystem, amplitude: float, q_max: float, where: str) -> InputError:
    return InputError(
        f"{system.name}: amplitude {math.degrees(amplitude):.6g} deg is at or past the separatrix: "
        f"the unstable equilibrium at {system.q} = {math.degrees(q_max):.6g} deg {where}; "
        "released there the body does not oscillate (no period)"
    )


_WELL_NODES = 8192  # grid points per side of the equilibrium (spacing 4 pi / 8192 = 1.5e-3 rad)


# --------------------------------------------------------------------------- potential differences
# V(q_ref) - V(q) near a turning point q_ref is a difference of nearly equal numbers: in
# float64 it loses about log10(|V| / (V(q_ref) - V(q))) digits (at 1 deg, 2 log10(1/q0) = 7
# digits from the amplitude alone). Written as products (cos b - cos a = -2 sin((a+b)/2)
# sin((b-a)/2), term by term) with q_ref - q formed exactly, it keeps its relative accuracy.
# (Symbols, not Dummies: lambdify would rename Dummies and re-evaluate sin(a - b) into
# -sin(b - a), one more array operation; the scene loader refuses names starting with "__")
_HALF = sp.Symbol("__half_step", real=True)  # (q_ref - q) / 2, given exactly by the caller
_COS2 = sp.Symbol("__cos2", real=True)  # cos^2 u of a quadrature node (_float_sums)
_DIFF_OPS = 400  # larger potentials are differenced directly (the round-off estimate says so)


def _difference(expr: sp.Expr, q: sp.Symbol) -> tuple[sp.Expr, sp.Expr | None]:
    """(D, B): D = expr(q_ref) - expr(q) without cancellation, and B >= |D| the size its
    round-off scales with (about eps B), or None when that is |D| itself.

    D is in q and H = (q_ref - q) / 2 (``_HALF``, which the caller forms exactly); q_ref
    itself enters only function values, as q + 2 H (rounded like q itself: harmless there,
    unlike in a difference).

    B differs from |D| where D adds differences of both signs (a sum, or the product rule):
    there the round-off is eps times the sum of their magnitudes. Functions without a product
    formula here are differenced directly, with B = |f(q_ref)| + |f(q)|.
    """
    if sp.count_ops(expr) > _DIFF_OPS:
        return _plain_difference(expr, q)
    return _diff(sp.sympify(expr), q, {})


def _at_ref(e: sp.Expr, q: sp.Symbol) -> sp.Expr:
    """e(q_ref), q_ref = q + 2 H."""
    return e.xreplace({q: q + 2 * _HALF})


def _plain_difference(e: sp.Expr, q: sp.Symbol) -> tuple[sp.Expr, sp.Expr]:
    e0 = _at_ref(e, q)
    return e0 - e, sp.Abs(e0) + sp.Abs(e)


def _size(D: sp.Expr, B: sp.Expr | None) -> sp.Expr:
    return sp.Abs(D) if B is None else B


def _diff(e: sp.Expr, q: sp.Symbol, memo: dict) -> tuple[sp.Expr, sp.Expr | None]:
    """One node of :func:`_difference` (memoised per sub-expression)."""
    if e in memo:
        return memo[e]
    if not e.has(q):
        out = (sp.Integer(0), None)
    elif e == q:
        out = (2 * _HALF, None)
    elif isinstance(e, sp.Add):
        parts = [_diff(t, q, memo) for t in e.args if t.has(q)]
        D = sp.Add(*[d for d, _ in parts])
        out = (D, parts[0][1] if len(parts) == 1 else sp.Add(*[_size(d, b) for d, b in parts]))
    elif isinstance(e, sp.Mul):
        c, f = e.as_independent(q, as_Add=False)
        factors = sp.Mul.make_args(f)
        D, B = _diff(factors[0], q, memo)
        head = factors[0]
        for g in factors[1:]:  # product rule: D(h g) = D(h) g(q_ref) + h D(g)
            Dg, Bg = _diff(g, q, memo)
            g0 = _at_ref(g, q)
            D, B = D * g0 + head * Dg, _size(D, B) * sp.Abs(g0) + sp.Abs(head) * _size(Dg, Bg)
            head = head * g
        out = (c * D, None if B is None else sp.Abs(c) * B)
    elif isinstance(e, sp.Pow) and not e.exp.has(q):
        out = _diff_power(e.base, e.exp, q, memo)
    elif isinstance(e, (sp.sin, sp.cos, sp.sinh, sp.cosh, sp.tan, sp.atan, sp.exp, sp.log)):
        out = _diff_function(e, q, memo)
    else:
        out = _plain_difference(e, q)
    memo[e] = out
    return out


def _scaled(D: sp.Expr, inner: tuple[sp.Expr, sp.Expr | None]) -> sp.Expr | None:
    """B of a function of an argument whose difference is ``inner``: relative round-off carried over."""
    Da, Ba = inner
    return None if Ba is None else sp.Abs(D) * Ba / sp.Abs(Da)


def _diff_power(b: sp.Expr, n: sp.Expr, q: sp.Symbol, memo: dict) -> tuple[sp.Expr, sp.Expr | None]:
    """b(q_ref)^n - b(q)^n: a geometric sum for small integer n, else b^n expm1(n log1p(Db / b))."""
    from sympy.codegen.cfunctions import expm1, log1p

    inner = _diff(b, q, memo)
    Db = inner[0]
    b0 = _at_ref(b, q)
    if n.is_Integer and 0 < n <= 8:
        D = Db * sp.Add(*[b0**i * b ** (n - 1 - i) for i in range(int(n))])
    elif n.is_Integer and -8 <= n < 0:
        D = -Db * sp.Add(*[b0**i * b ** (-n - 1 - i) for i in range(int(-n))]) / (b0 ** (-n) * b ** (-n))
    else:
        D = b**n * expm1(n * log1p(Db / b))
    return D, _scaled(D, inner)


def _diff_function(e: sp.Expr, q: sp.Symbol, memo: dict) -> tuple[sp.Expr, sp.Expr | None]:
    """sin, cos, sinh, cosh, tan, atan, exp, log of an argument a: products of the
    half-difference (Da / 2) or quotients of the difference."""
    from sympy.codegen.cfunctions import expm1, log1p

    a = e.args[0]
    inner = _diff(a, q, memo)
    Da = inner[0]
    mid = _at_ref(a, q) - Da / 2  # (a(q) + a(q_ref)) / 2: q + H for a = q
    if isinstance(e, sp.cos):
        D = -2 * sp.sin(mid) * sp.sin(Da / 2)
    elif isinstance(e, sp.sin):
        D = 2 * sp.cos(mid) * sp.sin(Da / 2)
    elif isinstance(e, sp.cosh):
        D = 2 * sp.sinh(mid) * sp.sinh(Da / 2)
    elif isinstance(e, sp.sinh):
        D = 2 * sp.cosh(mid) * sp.sinh(Da / 2)
    elif isinstance(e, sp.tan):
        D = sp.sin(Da) / (sp.cos(a) * sp.cos(_at_ref(a, q)))
    elif isinstance(e, sp.atan):
        D = sp.atan2(Da, 1 + a * _at_ref(a, q))  # the angle of (1 + i a0) / (1 + i a), no wrap
    elif isinstance(e, sp.exp):
        D = e * expm1(Da)
    else:
        D = log1p(Da / a)
    return D, _scaled(D, inner)


class _OnFirstCall:
    """A function built by ``build()`` when it is first called (and kept)."""

    def __init__(self, build: Callable[[], Callable]):
        self._build, self._f = build, None

    def __call__(self, *args):
        if self._f is None:
            self._f = self._build()
        return self._f(*args)


@dataclass(frozen=True)
class _Compiled:
    """The compiled potential and mass of one set of parameter values, for the period
    (memoised on the system: fetching and wrapping them per call cost more than a small
    quadrature)."""

    V: Callable  # vectorised
    dV: Callable
    local: Callable  # q -> (V(q), V'(q), V''(q)) on Python floats
    integrand: Callable  # (q, (q_ref - q) / 2, cos^2 u) arrays -> sqrt(M cos^2 u / D), see _float_sums;
    # with ``sized`` also B / |D|
    newton: Callable  # (q, q_ref) Python floats -> (V(q_ref) - V(q), V'(q), V''(q))
    sized: bool  # False: the difference's round-off is eps |D| (no sum of both signs)
    wells: dict = field(default_factory=dict)  # (q_e, reach) -> _Well


def _fold(expr: sp.Expr, variables: tuple, coefficients: dict) -> sp.Expr:
    """``expr`` with each largest part of a sum or product free of ``variables`` that holds
    parameters made a symbol (``coefficients``: that part -> its symbol): a number per
    parameter values instead of array operations per call (A + B cos q rather than four
    terms added to an array)."""
    if expr.is_number:
        return expr
    if not expr.has(*variables):  # a lone parameter too (k in k q): lambdify is given no parameters
        return coefficients.setdefault(expr, sp.Symbol(f"__c{len(coefficients)}"))  # not Dummy: see _HALF
    if not expr.args:
        return expr
    if isinstance(expr, (sp.Add, sp.Mul)):
        free, dep = expr.as_independent(*variables, as_Add=isinstance(expr, sp.Add))
        return expr.func(_fold(free, variables, coefficients),
                         *[_fold(a, variables, coefficients) for a in expr.func.make_args(dep)])
    return expr.func(*[_fold(a, variables, coefficients) for a in expr.args])


def _bound(system: OneDofSystem, key, expr: Callable[[], Any], args: tuple = ()) -> Callable:
    """The vectorised lambdified ``expr`` of (q, *args) (one expression or a tuple), its
    q-free parts folded (:func:`_fold`, memoised per ``key``) and evaluated for the
    parameter values; a result free of q is broadcast over q."""
    def build():
        coefficients: dict = {}
        body, variables = expr(), (system.q, *args)
        body = tuple(_fold(sp.sympify(e), variables, coefficients) for e in body) if isinstance(body, tuple) \
            else _fold(sp.sympify(body), variables, coefficients)
        unbound = sp.Tuple(*(body if isinstance(body, tuple) else (body,))).free_symbols \
            - set(variables) - set(coefficients.values())
        if unbound:  # would be evaluated as sympy objects, node by node (slow, then a TypeError)
            raise RuntimeError(f"_bound: {sorted(map(str, unbound))} left unfolded in {key!r}")
        return (lambdify((*coefficients.values(), system.q, *args), body, "numpy", cse=True),
                lambdify(system.params, list(coefficients), "numpy", cse=True))

    f, c = system._memo((key, "folded"), build)
    with np.errstate(all="ignore"):
        vals = tuple(float(v) for v in c(*system.values))
        probe = f(*vals, np.array([0.3, 0.7]), *[np.array([0.4, 0.9])] * len(args))
    several = isinstance(probe, (tuple, list))
    if all(np.shape(x) == (2,) for x in (probe if several else (probe,))):
        return functools.partial(f, *vals)
    if several:
        return lambda q, *rest: tuple(x + 0.0 * q for x in f(*vals, q, *rest))
    return lambda q, *rest: f(*vals, q, *rest) + 0.0 * q


def _potential_difference(system: OneDofSystem) -> tuple[sp.Expr, sp.Expr | None]:
    """:func:`_difference` of V_eff with its terms grouped by their q-dependent factor
    (so that c1 cos q + c2 cos q is one difference, not a sum of two); memoised per
    switched-off loads."""
    def build():
        groups: dict = {}
        for term in sp.Add.make_args(sp.sympify(system.effective_potential())):
            c, f = term.as_independent(system.q, as_Add=False)
            groups[f] = groups.get(f, 0) + c
        return _difference(sp.Add(*[c * f for f, c in groups.items()]), system.q)

    return system._memo(("V difference", system._zero_parameters()), build)


def _eliminate(e: list[float], n: int) -> tuple[list[float], float]:
    """(x, det): A x = b by Gaussian elimination with partial pivoting on Python floats, A's rows
    first scaled by their largest |entry| (det is the scaled A's); ``e`` holds A row by row, then b.
    ([nan] * n, 0.0) when a pivot is 0. Pivots and scales are the first largest (as ``max``
    chooses), and each sum starts from 0 (as ``sum`` does)."""
    M = [e[i * n:(i + 1) * n] + [e[n * n + i]] for i in range(n)]
    det = 1.0
    for row in M:  # row scaling for a meaningful determinant
        s = max(abs(x) for x in row[:n]) or 1.0
        row[:] = [x / s for x in row]
    for c in range(n):
        p = max(range(c, n), key=lambda r: abs(M[r][c]))
        if M[p][c] == 0.0:
            return [math.nan] * n, 0.0
        if p != c:
            M[c], M[p] = M[p], M[c]
            det = -det
        det *= M[c][c]
        for r in range(c + 1, n):
            k = M[r][c] / M[c][c]
            if k:
                M[r] = [x - k * y for x, y in zip(M[r], M[c])]
    x = [0.0] * n
    for r in range(n - 1, -1, -1):
        x[r] = (M[r][n] - sum(M[r][j] * x[j] for j in range(r + 1, n))) / M[r][r]
    return x, det


def _scaled_row(a: float, b: float, c: float, d: float) -> list[float]:
    """[a, b, c, d] over the first largest of |a|, |b|, |c| (1 when they are all 0)."""
    s = abs(a)
    t = abs(b)
    if t > s:
        s = t
    t = abs(c)
    if t > s:
        s = t
    s = s or 1.0
    return [a / s, b / s, c / s, d / s]


def _eliminate3(e: list[float]) -> tuple[list[float], float]:
    """:func:`_eliminate` for n = 3 written out: the same operations in the same order, so the
    same numbers to the last bit, at about a third of the time (it runs in event functions, at
    every step of an integration)."""
    M = [_scaled_row(e[0], e[1], e[2], e[9]), _scaled_row(e[3], e[4], e[5], e[10]),
         _scaled_row(e[6], e[7], e[8], e[11])]
    det = 1.0
    for c in (0, 1):
        p, best = c, abs(M[c][c])
        for r in range(c + 1, 3):
            a = abs(M[r][c])
            if a > best:
                p, best = r, a
        if M[p][c] == 0.0:
            return [math.nan] * 3, 0.0
        if p != c:
            M[c], M[p] = M[p], M[c]
            det = -det
        P = M[c]
        pivot = P[c]
        det *= pivot
        for r in range(c + 1, 3):
            R = M[r]
            k = R[c] / pivot
            if k:
                M[r] = [R[0] - k * P[0], R[1] - k * P[1], R[2] - k * P[2], R[3] - k * P[3]]
    r0, r1, r2 = M
    if r2[2] == 0.0:
        return [math.nan] * 3, 0.0
    det *= r2[2]
    x2 = (r2[3] - 0) / r2[2]  # (0: the empty sum's int, as in _eliminate)
    x1 = (r1[3] - sum([r1[2] * x2])) / r1[1]
    x0 = (r0[3] - sum([r0[1] * x1, r0[2] * x2])) / r0[0]
    return [x0, x1, x2], det


def _scalar(system: OneDofSystem, key, args: tuple, expr: Callable[[], Any]) -> Callable:
    """``expr`` lambdified for Python floats (the ``math`` module, about 20 times cheaper per
    call than numpy on one number), or numpy where ``math`` lacks a function."""
    try:
        f = system._fn(key, args, expr, "math")
        f(*[0.1 * (k + 1) for k in range(len(args))], *system.values)
        return f
    except (NameError, TypeError, AttributeError, KeyError, ZeroDivisionError, ValueError, OverflowError):
        return system._fn(key, args, expr, "numpy")


def _compiled(system: OneDofSystem) -> _Compiled:
    def build():
        from .display import reduce_trig

        zeros, vals = system._zero_parameters(), system.values
        dV = lambda d: sp.diff(system.effective_potential(), system.q, d)  # noqa: E731
        V = [_bound(system, (f"V{d}", zeros), lambda d=d: dV(d)) for d in (0, 1)]
        D, B = _potential_difference(system)
        def integrand():  # (built at its first use: the turning points alone, as least_friction
            # wants them, need no quadrature) sin^2 + cos^2 in M reduced first (fewer array operations per node)
            f = sp.sqrt((reduce_trig(sp.sympify(system.mass)) or system.mass) * _COS2 / D)
            return _bound(system, ("integrand", zeros), lambda: f if B is None else (f, B / sp.Abs(D)),
                          (_HALF, _COS2))
        newton = _scalar(system, ("Newton", zeros), (system.q, _HALF), lambda: [D, dV(1), dV(2)])
        local = _scalar(system, ("V, V', V''", zeros), (system.q,), lambda: [dV(0), dV(1), dV(2)])
        return _Compiled(V[0], V[1], lambda q: local(q, *vals), _OnFirstCall(integrand),
                         lambda q, ref: newton(q, 0.5 * (ref - q), *vals), B is not None)

    key = ("period functions", system.values)
    fns = system._cache.get(key)  # (looked up first: this runs twice per period)
    return fns if fns is not None else system._memo(key, build)


@dataclass(frozen=True)
class _WellSide:
    """One side of the potential well, scanned once: q_e + s d on a uniform grid of d."""

    q: np.ndarray  # the grid, moving away from q_e
    V: np.ndarray  # V_eff there
    rising: int  # leading grid points where V rises strictly (the next one is at or past a maximum)
    climb_q: list  # q[:rising] and V[:rising] as Python floats (bisect in V, then index in q:
    climb_V: list  # cheaper per release than numpy's searchsorted and scalar indexing)


@dataclass(frozen=True)
class _Well:
    """The potential well about q_e out to ``reach`` on both sides (memoised per parameter
    values: an amplitude sweep scans it once)."""

    step: float
    scale: float  # the largest |V'| on the grid (the flatness tests are relative to it)
    sides: dict  # +1 / -1 -> _WellSide
    Ve: float  # V_eff(q_e)


def _well(fns: _Compiled, qe: float, reach: float) -> _Well:
    def build():
        d = np.linspace(0.0, reach, _WELL_NODES + 1)[1:]
        grids = {s: qe + s * d for s in (1.0, -1.0)}
        slopes = {s: s * fns.dV(q) for s, q in grids.items()}
        scale = max(float(np.max(np.abs(v))) for v in slopes.values())
        sides = {}
        for s, q in grids.items():
            flat = np.nonzero(slopes[s] <= 1e-12 * scale)[0]
            rising, V = int(flat[0]) if flat.size else q.size, fns.V(q)
            sides[s] = _WellSide(q, V, rising, q[:rising].tolist(), V[:rising].tolist())
        return _Well(reach / _WELL_NODES, scale, sides, fns.local(qe)[0])

    well = fns.wells.get((qe, reach))  # per parameter values, as the functions
    if well is None:
        well = fns.wells[qe, reach] = build()
    return well


def _far_turning_point(fns: _Compiled, q0: float, V0: float, bracket: tuple[float, float],
                       values: tuple[float, float]) -> tuple[float, float, float]:
    """The root x of V(x) = V0 = V(q0) in ``bracket`` (V there: ``values``, either side of
    V0), V'(x) and V''(x).

    Newton steps on V(q0) - V(x) written without cancellation (``fns.newton``: at small
    amplitudes the plain difference would place the root to a few digits only), from the
    linear interpolation of the scan, until the next step (step^2 / last step, in the
    quadratic convergence) would be below an ulp; brentq on the same difference if a step
    leaves the bracket.
    """
    (lo, hi), (V_lo, V_hi) = bracket, values
    x = hi if V_hi == V0 else lo + (hi - lo) * (V0 - V_lo) / (V_hi - V_lo)
    left, right = (lo, hi) if lo < hi else (hi, lo)
    last = 0.0  # the previous step (none yet)
    for _ in range(8):
        D, slope, curvature = fns.newton(x, q0)
        step = D / slope if slope else math.nan
        if not (math.isfinite(step) and left <= x + step <= right):
            break
        x += step
        if abs(step) ** 3 <= 0.1 * _EPS * abs(x) * last * last:
            return x, slope, curvature
        last = abs(step)
    x = brentq(lambda x: fns.newton(x, q0)[0], left, right, xtol=1e-300, rtol=4 * _EPS, maxiter=500, disp=False)
    return (x, *fns.local(x)[1:])


def turning_points(system: OneDofSystem, equilibrium: Equilibrium, amplitude: float) -> tuple[float, float]:
    """Both turning points (q1, q0) of a release from rest at q0 = q_e + amplitude.

    Returns the pair sorted (low, high). The well about q_e is scanned once per
    parameter values (:func:`_well`); each release then costs a bisection in the
    scan and one root search.

    Raises
    ------
    InputError
        When the release point is at or past the separatrix (a maximum of
        V_eff lies between q_e and q0, or the other side's barrier is lower
        than V_eff(q0)).
    """
    return _swing(system, equilibrium, amplitude)[0]


def _swing(system: OneDofSystem, equilibrium: Equilibrium, amplitude: float) -> tuple[tuple[float, float], float]:
    """:func:`turning_points`, and max |q V''(q) / V'(q)| over the two (the relative change of
    V' there per relative change of q: the quadrature's round-off estimate uses it)."""
    qe = equilibrium.q
    q0 = qe + amplitude
    s = 1.0 if amplitude > 0 else -1.0
    fns = _compiled(system)
    well = _well(fns, qe, 4.0 * max(abs(amplitude), math.pi))
    (V0, slope0, curvature0), Ve = fns.local(q0), well.Ve
    # A tiny amplitude raises V by less than float64 resolves: place the far turning
    # point in higher precision (no maximum can lie that close to a minimum).
    if not V0 - Ve > _RESOLVED * _EPS * max(abs(V0), abs(Ve)):
        q1 = _small_amplitude_turning_point(system, equilibrium, amplitude)
        return (min(q0, q1), max(q0, q1)), max(abs(x * c / v) for x in (q0, q1) for _, v, c in (fns.local(x),))
    near, far = well.sides[s], well.sides[-s]
    # same side: V must rise monotonically from q_e to q0
    if min(int(abs(amplitude) / well.step), near.q.size) > near.rising:  # grid points short of q0 (or at it)
        raise _separatrix_error(system, amplitude, float(near.q[near.rising]),
                                "lies between the equilibrium and the release point")
    if not s * slope0 > 1e-12 * well.scale:
        raise _separatrix_error(system, amplitude, q0, "lies between the equilibrium and the release point")
    # other side: V rises until it reaches V0, with no maximum on the way
    j = bisect.bisect_left(far.climb_V, V0)
    if j == far.rising:
        if far.rising == far.q.size:
            raise InputError(
                f"{system.name}: released at {system.q} = {math.degrees(q0):.6g} deg the body does not come back "
                f"within {math.degrees(well.step * _WELL_NODES):.6g} deg of the equilibrium (not an oscillation)"
            )
        raise _separatrix_error(system, amplitude, float(far.q[far.rising]),
                                "on the far side is lower than the release point")
    below = (qe, Ve) if j == 0 else (far.climb_q[j - 1], far.climb_V[j - 1])
    q1, slope1, curvature1 = _far_turning_point(fns, q0, V0, (below[0], far.climb_q[j]), (below[1], far.climb_V[j]))
    # a turning point at a (numerically) flat potential is the separatrix itself
    flat = 1e-9 * well.scale
    if abs(slope1) <= flat or abs(slope0) <= flat:
        raise _separatrix_error(system, amplitude, q1 if abs(slope1) <= flat else q0, "is reached exactly")
    if system.limits:
        for turn in (q0, q1):
            check_limits(system, turn, "a turning point of the swing")
    sensitivity = max(abs(q0 * curvature0 / slope0), abs(q1 * curvature1 / slope1))
    return ((q1, q0) if q1 < q0 else (q0, q1)), sensitivity


# --------------------------------------------------------------------------- period
@dataclass(frozen=True)
class PeriodResult:
    """The period of free oscillation released from rest.

    Attributes
    ----------
    period : float
        Period T. [s]
    period_linear : float
        Linearized period T0 about the equilibrium. [s]
    ratio : float
        T / T0.
    amplitude : float
        Release point minus equilibrium. [rad]
    equilibrium : float
        Stable equilibrium q_e. [rad]
    turning_points : tuple[float, float]
        (q1, q0) sorted. [rad]
    model : str
        ``"linear"``, ``"elliptic"`` (closed form), ``"quadrature"`` or ``"integration"``.
    error_estimate : float
        Estimated relative error of ``period``.
    nodes : int
        Quadrature nodes (or integrator steps) used.
    precision : str
        ``"float64"`` or ``"mpmath"``.
    """

    period: float
    period_linear: float
    ratio: float
    amplitude: float
    equilibrium: float
    turning_points: tuple[float, float]
    model: str
    error_estimate: float
    nodes: int = 0
    precision: str = "float64"

    def to_dict(self) -> dict:
        """JSON-ready dict: ``{"period": {"value", "unit"}, "period_linear": {...}, "ratio", ...}``."""
        return {
            "period": {"value": self.period, "unit": "s"},
            "period_linear": {"value": self.period_linear, "unit": "s"},
            "ratio": self.ratio,
            "model": self.model,
            "error_estimate": self.error_estimate,
            "amplitude": {"value": math.degrees(self.amplitude), "unit": "deg"},
            "equilibrium": {"value": math.degrees(self.equilibrium), "unit": "deg"},
            "turning_points": {"value": [math.degrees(x) for x in self.turning_points], "unit": "deg"},
            "nodes": self.nodes,
            "precision": self.precision,
        }


# --------------------------------------------------------------------------- closed form
# Carlson's R_F and R_J are accurate to a few ulps (scipy.special, Carlson 1995); the
# arguments cos^2(a/2) and M(a)/M(0) carry one rounding each. 16 eps bounds the sum.
_ELLIPTIC_ERROR = 16 * _EPS
# A sin x term in M (in the coordinate x = q - q_c) smaller than this, relative to M's
# coefficients, is round-off of the phase: M is taken as A + B cos x.
_PHASE_TOL = 1e-13


@dataclass(frozen=True)
class EllipticForm:
    """M = A + B cos(q - center), V_eff = -C cos(q - center) + const (C > 0).

    Attributes
    ----------
    center : float
        The minimum of V_eff (the stable equilibrium). [rad]
    A, B : float
        Generalized mass M = A + B cos(q - center). [kg m^2]
    C : float
        Depth of the potential, V_eff = -C cos(q - center) + const. [J]
    """

    center: float
    A: float
    B: float
    C: float


def _affine_in_cos_sin(expr: sp.Expr, q: sp.Symbol) -> tuple[sp.Expr, sp.Expr, sp.Expr] | None:
    """(c0, c1, c2) with expr = c0 + c1 cos q + c2 sin q identically, or None.

    ``expr`` may hold q only in sin and cos of q plus a constant (expanded to sin q and
    cos q), polynomially; sin^2 = 1 - cos^2
    is applied exactly (polynomial remainder), so cos^2 + sin^2 terms are recognised.
    """
    S, C = sp.Dummy("S"), sp.Dummy("C")
    e = sp.expand_trig(sp.sympify(expr)).xreplace({sp.sin(q): S, sp.cos(q): C})  # cos(q - c) -> cos q, sin q
    if e.has(q):
        return None
    try:
        _, rem = sp.div(sp.Poly(e, S, C), sp.Poly(S**2 + C**2 - 1, S, C))
    except (sp.PolynomialError, sp.GeneratorsError, sp.CoercionFailed):
        return None
    terms = rem.as_dict()
    if any(m not in ((0, 0), (0, 1), (1, 0)) and sp.expand(c) != 0 for m, c in terms.items()):
        return None
    return (sp.sympify(terms.get((0, 0), 0)), sp.sympify(terms.get((0, 1), 0)), sp.sympify(terms.get((1, 0), 0)))


def elliptic_form(system: OneDofSystem, equilibrium: Equilibrium) -> EllipticForm | None:
    """The closed-form structure of ``system`` about ``equilibrium``, or None when it has none.

    The symbolic test (M and V_eff affine in cos q and sin q) is done once per
    system; the numbers once per set of parameter values.
    """
    def symbolic():
        try:
            V = system.effective_potential()
        except InputError:
            return None  # rate- or time-dependent loads: no potential
        M = _affine_in_cos_sin(system.mass, system.q)
        W = _affine_in_cos_sin(V, system.q)
        return None if M is None or W is None else (M, W[1:])

    def numeric():
        shape = system._memo(("elliptic-symbolic", system._active_force()[1]), symbolic)
        if shape is None:
            return None
        subs = dict(zip(system.params, system.values))
        (a0, a1, a2), (b1, b2) = [[float(sp.sympify(c).xreplace(subs)) for c in part] for part in shape]
        C = math.hypot(b1, b2)  # V = b1 cos q + b2 sin q = -C cos(q - phi)
        if not (C > 0 and all(math.isfinite(v) for v in (a0, a1, a2, C))):
            return None
        phi = math.atan2(-b2, -b1)
        turns = round((equilibrium.q - phi) / (2 * math.pi))
        center = phi + 2 * math.pi * turns
        if abs(center - equilibrium.q) > 1e-6 * (1 + abs(center)):
            return None  # not the minimum of this V (cannot happen for a cosine; kept as a guard)
        B = a1 * math.cos(phi) + a2 * math.sin(phi)
        B_sin = a2 * math.cos(phi) - a1 * math.sin(phi)
        if abs(B_sin) > _PHASE_TOL * (abs(a0) + abs(a1) + abs(a2)):
            return None  # M out of phase with V: no closed form of this kind
        if not a0 + B > 0:
            return None
        return EllipticForm(center, a0, B, C)

    key = ("elliptic", system.values, equilibrium.q)
    cache = system._cache
    return cache[key] if key in cache else system._memo(key, numeric)


@functools.lru_cache(maxsize=1)
def _carlson():
    """scipy.special's R_F and R_J (imported on first use: scipy.special costs start-up)."""
    from scipy.special import elliprf, elliprj

    return elliprf, elliprj


def elliptic_period(form: EllipticForm, amplitude: float) -> float:
    """Period [s] of the swing released from rest at ``form.center + amplitude`` (|amplitude| < pi).

    Notes
    -----
    With x = q - center, T = 4 int_0^a sqrt(M(x) / (2 C (cos x - cos a))) dx. The
    substitution sin(x/2) = k sin(phi), k = sin(a/2), gives
    T = 4 sqrt((A+B)/C) int_0^(pi/2) sqrt((1 - m s^2) / (1 - k^2 s^2)) dphi (s = sin phi,
    m = 2 B k^2 / (A + B)), and with t = 1/s^2 - 1 that integral is
    R_F(0, 1-k^2, 1-m) - (m/3) R_J(0, 1-k^2, 1-m, 1) (module docstring).
    ``1 - k^2 = cos^2(a/2)`` and ``1 - m = M(a)/M(0)`` are formed without cancellation.

    Examples
    --------
    The pendulum (B = 0) at 90 deg: T / T0 = 2 K(1/2) / pi = 1.18034...

    >>> T0 = 2 * math.pi
    >>> print(f"{elliptic_period(EllipticForm(0.0, 1.0, 0.0, 1.0), math.pi / 2) / T0:.10f}")
    1.1803405990
    """
    elliprf, elliprj = _carlson()
    half = 0.5 * abs(amplitude)
    k2, y = math.sin(half) ** 2, math.cos(half) ** 2
    M0 = form.A + form.B
    m = 2.0 * form.B * k2 / M0
    z = (form.A + form.B * math.cos(amplitude)) / M0
    integral = float(elliprf(0.0, y, z))
    if m != 0.0:
        integral -= m / 3.0 * float(elliprj(0.0, y, z, 1.0))
    return 4.0 * math.sqrt(M0 / form.C) * integral



PERIOD_METHODS = ("auto", "elliptic", "quadrature")
"""``exact_period(method=...)``: the closed form where the structure admits it, else the quadrature."""


def _elliptic_result(system: OneDofSystem, form: EllipticForm, amplitude: float, T0: float) -> PeriodResult:
    """The closed-form PeriodResult; the separatrix (|amplitude| >= pi) and model limits refused."""
    if not abs(amplitude) < math.pi:
        raise _separatrix_error(system, amplitude, form.center + math.copysign(math.pi, amplitude),
                                "is reached at or before the release point")
    turns = (form.center - abs(amplitude), form.center + abs(amplitude))
    if system.limits:
        for turn in turns:
            check_limits(system, turn, "a turning point of the swing")
    T = elliptic_period(form, amplitude)
    return PeriodResult(T, T0, T / T0, amplitude, form.center, turns, "elliptic", _ELLIPTIC_ERROR, 0, "float64")


def _validate_exact_period(system: OneDofSystem, amplitude: float, tol: float, precision: str,
                           method: str = "auto") -> None:
    valid = ("auto", "float64", "mpmath")
    if precision not in valid:
        raise ValueError(f"`precision` must be one of {valid}, got {precision!r}")
    if method not in PERIOD_METHODS:
        raise ValueError(f"`method` must be one of {PERIOD_METHODS}, got {method!r}")
    if not isinstance(system, OneDofSystem):
        raise TypeError(f"`system` must be a OneDofSystem, got {type(system).__name__}")
    if not math.isfinite(amplitude):
        raise InputError(f"{system.name}: amplitude must be a finite angle, got {amplitude!r}")
    if not (TOL_MIN <= tol <= TOL_MAX):
        raise InputError(f"tolerance must lie in [{TOL_MIN:g}, {TOL_MAX:g}], got {tol!r}")


@dataclass(frozen=True)
class _Nodes:
    """The 3n midpoint nodes u_k of (-pi/2, pi/2) in increasing order, as the numbers the
    sum needs (the same for every call); every third one from the second on is a node of
    the n-node rule. The nodes below the middle are measured from q1, the others from q0."""

    sin: np.ndarray  # sin u
    half: np.ndarray  # (end - q) / (2 h): -(1 + sin u) / 2 below the middle, (1 - sin u) / 2 above
    cos2: np.ndarray  # cos^2 u = (q0 - q)(q - q1) / h^2
    weights: np.ndarray  # (2, 3n): the means over the 3n nodes and over the n-node rule's


@functools.lru_cache(maxsize=32)
def _nodes(n: int) -> _Nodes:
    u = -0.5 * math.pi + math.pi * (np.arange(3 * n) + 0.5) / (3 * n)
    w = 0.25 * math.pi - 0.5 * u
    below, above = 2.0 * np.cos(w) ** 2, 2.0 * np.sin(w) ** 2  # 1 + sin u, 1 - sin u without cancellation
    lower = np.arange(3 * n) < 3 * n // 2
    weights = np.zeros((2, 3 * n))
    weights[0], weights[1, 1::3] = 1.0 / (3 * n), 1.0 / n
    out = _Nodes(np.sin(u), 0.5 * np.where(lower, -below, above), below * above, weights)
    for a in (out.sin, out.half, out.cos2, out.weights):
        a.flags.writeable = False
    return out


_SQRT2_PI = math.sqrt(2.0) * math.pi  # 2 pi / sqrt(2): T = 2 pi mean sqrt(M / (2 g))


def _float_sums(fns: _Compiled, ends: tuple[float, float], n: int, err_ends: float):
    """The midpoint rule in u with 3n and with n nodes: (T, T_n, round-off estimate, ok).

    Each node q = q_m + h sin(u) lies at the exact distance h (1 + sin u) from q1 or
    h (1 - sin u) from q0, whichever is nearer; its integrand
    sqrt(M (q0 - q)(q - q1) / (2 D)) = sqrt(M h^2 cos^2 u / (2 D)) takes
    D = V(end) - V(q) (= V(q0) - V(q), both ends being roots) from that distance without
    cancellation (:func:`_difference`). The float64 numbers q, q1, q0 enter only sums of
    function values, so D keeps its relative accuracy, a few ulps (times B / |D| where it
    adds differences of both signs), however close the node to an end and however small
    the amplitude. The turning points need only be the nearest floats to the roots.
    ``err_ends``: the relative round-off that the rounded arguments of V bring (see
    :func:`_level_sum`), added to the estimate.
    """
    q1, q0 = ends
    nodes = _nodes(n)
    h = 0.5 * (q0 - q1)
    q = 0.5 * (q0 + q1) + h * nodes.sin
    with np.errstate(all="ignore"):
        out = fns.integrand(q, h * nodes.half, nodes.cos2)  # times h / sqrt(2)
        f, cond = out if fns.sized else (out, None)
        mean, mean_n = (nodes.weights @ f).tolist()
        if not math.isfinite(mean):  # M > 0 and D > 0 at every node, else nan
            return math.nan, math.nan, math.inf, False
        # D to 2 ulps relative (times B / |D|), half of it in f; M and the sum 2 ulps
        err = 2.0 * _EPS * (1.0 if cond is None else float(nodes.weights[0] @ (f * cond)) / mean)
    return _SQRT2_PI * h * mean, _SQRT2_PI * h * mean_n, err + 2.0 * _EPS + err_ends, True


@functools.lru_cache(maxsize=16)
def _mp_nodes(n: int, dps: int) -> tuple:
    """(sin u, sin(w)**2, cos(w)**2) at each of :func:`_mp_sum`'s 3n nodes, u = -pi/2 + pi (k + 1/2) / (3n),
    w = pi/4 - u/2, in mpmath at ``dps`` digits: the same for every system and amplitude, so made
    once (the same numbers, made at the same precision, as made at each call)."""
    with mpmath.workdps(dps):
        out = []
        for k in range(3 * n):
            u = -mpmath.pi / 2 + mpmath.pi * (k + mpmath.mpf(1) / 2) / (3 * n)
            w = mpmath.pi / 4 - u / 2
            out.append((mpmath.sin(u), mpmath.sin(w) ** 2, mpmath.cos(w) ** 2))
        return tuple(out)


def _mp_sum(system, q0, q1, n, dps=_MP_DPS):
    """The same midpoint sums (3n and n nodes) with V0 - V(q) and the nodes in mpmath at
    ``dps`` digits: (T, T_n, ok). ``q0`` is the release point (exact), ``q1`` the other
    turning point, found again at that precision (either order)."""
    Vmp = system.potential_fn(0, precision="mpmath")
    M = system.mass_fn()
    with mpmath.workdps(dps):
        mq0, mq1 = mpmath.mpf(q0), mpmath.mpf(q1)
        V0 = Vmp(mq0)
        # sharpen the far turning point in the higher precision
        try:
            mq1 = mpmath.findroot(lambda x: Vmp(x) - V0, mq1, tol=mpmath.mpf(10) ** (-dps + 4))
        except (ValueError, ZeroDivisionError):
            pass
        qm, h = (mq0 + mq1) / 2, (mq0 - mq1) / 2
        total, coarse = mpmath.mpf(0), mpmath.mpf(0)
        for k, (sin_u, sin2_w, cos2_w) in enumerate(_mp_nodes(n, dps)):
            d0 = 2 * h * sin2_w
            d1 = 2 * h * cos2_w
            q = qm + h * sin_u
            g = (V0 - Vmp(q)) / (d0 * d1)
            if not g > 0:
                return math.nan, math.nan, False
            term = mpmath.sqrt(mpmath.mpf(float(M(float(q)))) / (2 * g))
            total += term
            coarse += term if k % 3 == 1 else 0
        return float(2 * mpmath.pi / (3 * n) * total), float(2 * mpmath.pi / n * coarse), True


def exact_period(
    system: OneDofSystem,
    amplitude: float,
    tol: float = 1e-10,
    equilibrium: Equilibrium | None = None,
    precision: str = "auto",
    method: str = "auto",
) -> PeriodResult:
    """Period of free oscillation released from rest at q_e + amplitude, to relative ``tol``.

    Parameters
    ----------
    system : OneDofSystem
    amplitude : float
        Release point minus the stable equilibrium (either sign). [rad]
    tol : float
        Requested relative accuracy, in [1e-15, 0.1].
    equilibrium : Equilibrium, optional
        Found with :func:`find_equilibrium` when not given.
    precision : {"auto", "float64", "mpmath"}
        Arithmetic of the quadrature's potential differences; ``"auto"`` switches
        to mpmath when the estimated round-off exceeds tol / 4.
    method : {"auto", "elliptic", "quadrature"}
        ``"auto"``: the closed form (:func:`elliptic_period`) when M and V_eff
        admit it and its error bound meets ``tol``, else the quadrature.

    Returns
    -------
    PeriodResult
        ``model="elliptic"`` (error estimate: the round-off bound of the
        elliptic integrals) or ``model="quadrature"`` (error estimate: the
        difference between the sums with n and 3n nodes plus the round-off
        estimate, an upper bound since the convergence is geometric; ``nodes``
        is 3n).

    Raises
    ------
    InputError
        Amplitude at or past the separatrix, tolerance out of range, or no
        convergence within 2**17 nodes.
    NoRestoringError
        No stable equilibrium.

    Notes
    -----
    T = 2 int sqrt(M / (2 (V(q0) - V))) dq with q = q_m + h sin u (module
    docstring); T0 from paper Eq. 46 generalised: 2 pi sqrt(M(q_e)/V''(q_e)).
    """
    _validate_exact_period(system, amplitude, tol, precision, method)
    eq = equilibrium if equilibrium is not None else find_equilibrium(system)
    if method != "quadrature":
        form = elliptic_form(system, eq)
        if form is None and method == "elliptic":
            raise InputError(f"{system.name}: the period has no closed form here (M and the potential are not "
                             f"both affine in cos and sin of {system.q} with one phase); use the quadrature")
        if form is not None and (method == "elliptic" or _ELLIPTIC_ERROR <= tol):
            return _elliptic_result(system, form, amplitude, eq.period)
    if amplitude == 0.0:
        return PeriodResult(eq.period, eq.period, 1.0, 0.0, eq.q, (eq.q, eq.q), "quadrature", 0.0, 0, "float64")
    return _quadrature_period(system, eq, amplitude, tol, precision)


# The arithmetics the quadrature tries in turn, cheapest first (``precision`` argument).
_LEVELS = {"auto": ("float64", "mpmath"), "float64": ("float64",), "mpmath": ("mpmath",)}


def _level_sum(system: OneDofSystem, level: str, ends: tuple[float, float], amplitude: float,
               sensitivity: float) -> Callable:
    """n -> (T with 3n nodes, T_n with n, round-off estimate, ok): the midpoint sums in one
    arithmetic between ``ends`` = (q1, q0), float64 roots (:func:`_float_sums`; mpmath finds
    the far one again at its working precision). ``sensitivity``: see :func:`_swing`."""
    q1, q0 = ends
    if level == "mpmath":
        # V0 - V(q) shrinks like amplitude**2: add digits for small amplitudes
        dps = _MP_DPS + max(0, int(math.ceil(-2.0 * math.log10(abs(amplitude)))))

        release, root = (q0, q1) if amplitude > 0 else (q1, q0)  # the root is found again

        def mp_sums(n):
            T, T_n, ok = _mp_sum(system, release, root, n, dps=dps)
            return T, T_n, 10.0 ** (-_MP_DPS + 8), ok
        return mp_sums
    fns = _compiled(system)
    # V's argument at a node is q (or q - c) rounded: an error eps |q| that moves D by
    # eps |q| V'', relative eps |q| |V'' / V'| where V' is smallest, at the ends (large
    # near the separatrix, or for a small swing about q_e != 0); half of it in f.
    err_ends = 0.5 * _EPS * sensitivity
    return lambda n: _float_sums(fns, ends, n, err_ends)


def _first_nodes(amplitude: float) -> int:
    """The first n, chosen a priori: 8 up to 1 rad, doubled per doubling of the amplitude
    beyond (the integrand's nearest complex singularity nears the interval as the swing
    nears the separatrix; for the disk-bar at 1e-12 this is one sum up to 170 deg)."""
    return 8 if abs(amplitude) <= 1.0 else 8 * 2 ** math.ceil(math.log2(abs(amplitude)))


def _next_nodes(n: int, change: float, tol: float) -> int:
    """The next n (a power of 2 times 8) for the n-node sum to reach tol / 4 when the error of
    the last one, ``change`` (relative), falls geometrically with n: between 2 n and 16 n."""
    want = n * math.log(tol / 4) / math.log(change) if 0.0 < change < 1.0 else 16 * n
    return n * 2 ** min(4, max(1, math.ceil(math.log2(max(want, 1.0) / n))))


def _quadrature_period(system: OneDofSystem, eq: Equilibrium, amplitude: float, tol: float,
                       precision: str) -> PeriodResult:
    """The midpoint sums with 3n and n nodes (module docstring), n from :func:`_first_nodes`
    up (:func:`_next_nodes`), until the two agree to tol / 2, in the cheapest arithmetic whose
    round-off estimate stays within tol / 4."""
    (q1, q0), sensitivity = _swing(system, eq, amplitude)
    levels = _LEVELS[precision]
    for level in levels:
        sums = _level_sum(system, level, (q1, q0), amplitude, sensitivity)
        n = _first_nodes(amplitude)
        while 3 * n <= _MAX_NODES:
            T, T_n, err_round, ok = sums(n)
            if not ok or (not err_round <= tol / 4 and level != levels[-1]):
                break  # the next arithmetic (the last one reports its estimate as it is)
            change = abs(T - T_n) / abs(T)
            if change <= tol / 2:
                est = max(change + err_round, 2 * _EPS)
                T0 = eq.period
                return PeriodResult(T, T0, T / T0, amplitude, eq.q, (q1, q0), "quadrature",
                                    est, 3 * n, "mpmath" if level == "mpmath" else "float64")
            n = _next_nodes(n, change, tol)
        else:
            raise QuadratureError(
                f"{system.name}: the period quadrature did not reach tolerance {tol:g} with {_MAX_NODES} nodes "
                f"at amplitude {math.degrees(amplitude):.6g} deg (too close to the separatrix)"
            )
        if level == "mpmath":
            raise QuadratureError(
                f"{system.name}: the potential difference is not resolved at amplitude "
                f"{math.degrees(amplitude):.6g} deg even in mpmath arithmetic"
            )
    raise InputError(
        f"{system.name}: the potential difference is not resolved in float64 at amplitude "
        f"{math.degrees(amplitude):.6g} deg; use precision='mpmath'"
    )
