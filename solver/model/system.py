"""The planar multibody system: coordinates, bodies, joints, loads and their kinematics.

A :class:`System` holds what a scene file says. From it, and cached on it
(cleared by :meth:`System.reset` whenever the model changes, as
``sympy.physics.mechanics.System`` clears its equations), it derives:

* the **placement** of every body: its angle phi_b(q, t) and the position of its
  frame's origin r_b(q, t). An angle is given by the scene (``orientation``) or
  implied by a joint (a slider, a motor, rolling on a circle); a position is
  given explicitly, fixed by one joint (rolling on a circle with a position
  angle) or solved from the joint equations that are linear in the body's
  translation (pins, rails, rolling on a line, cords, actuators), using those
  of joints to bodies already placed.
* the **closure** equations: every joint equation that the placement does not
  satisfy identically (a loop of a four-bar or a slider-crank). They tie the
  *dependent* coordinates (given with a ``guess``) to the free ones.
* the **kinematics** of every point: positions, velocities and accelerations
  from each body's origin by the rigid-body relation (paper Eqs. 6 and 15).

Conventions: fixed frame x right, y up, k out of the plane; every angle and
angular rate is a k-component, counter-clockwise positive. Each coordinate
``q`` has the sympy symbols ``q``, ``q_dot`` and ``q_ddot``; time is ``t``.
A prescribed coordinate (``motion``) is replaced by its function of t.
"""
from __future__ import annotations

import math
import random
from dataclasses import dataclass, field
from functools import cached_property, lru_cache
from typing import Iterable

import numpy as np
import pint
import sympy as sp

from ..errors import SceneError
from ..tree_value import NotEvaluable, real_value, tree_value
from ..units import si_magnitude
from .bodies import GROUND, Ground, RigidBody
from .joints import (Actuator, Contact, Joint, Motor, Pin, copy_vec, dot, k_cross, rotation, times_zero_is_zero,
                     vadd, vec, xy)
from .loads import Load

__all__ = ["Coordinate", "System", "ClosureRow", "RedundantConstraints", "derivative"]

_IDENTICAL_TOL = 1e-9


@dataclass(frozen=True)
class Coordinate:
    """A generalized coordinate.

    Attributes
    ----------
    name : str
    kind : str
        ``"angle"`` [rad] or ``"length"`` [m].
    value, rate : float
        SI value and rate at the scene's state (for a dependent coordinate the
        value is the guess that picks the assembly branch; the rate is solved).
    dependent : bool
        Solved from the closure equations.
    motion : sympy.Expr or None
        Prescribed coordinate: its function of t.
    """

    name: str
    kind: str = "angle"
    value: float = 0.0
    rate: float = 0.0
    dependent: bool = False
    motion: sp.Expr | None = None
    given: tuple | None = None  # (value, rate) pint quantities as written, for exact arithmetic

    # The symbols, made once per coordinate (it is frozen): sympy's Symbol() costs about 2 us a call,
    # and a command asks for them hundreds of times.
    @cached_property
    def q(self) -> sp.Symbol:
        return sp.Symbol(self.name, real=True)

    @cached_property
    def qd(self) -> sp.Symbol:
        return sp.Symbol(self.name + "_dot", real=True)

    @cached_property
    def qdd(self) -> sp.Symbol:
        return sp.Symbol(self.name + "_ddot", real=True)

    @property
    def unit(self) -> str:
        return "rad" if self.kind == "angle" else "m"

    @property
    def prescribed(self) -> bool:
        return self.motion is not None


def derivative(expr, x: sp.Symbol, free: set | None = None):
    """``sympy.diff(expr, x)`` of an expression in a symbol: the same object, without the generic
    preparation of ``Derivative``'s arguments and its final pass over the result (3 to 8 times
    faster on the model's expressions; the model differentiates tens of them per command).

    It takes the path ``Derivative(expr, x, evaluate=True)`` takes for one symbol: 0 when ``x`` is
    not free in ``expr``, else ``expr._eval_derivative_n_times(x, 1)``; for a sum or a product
    (:func:`_sum_or_product_derivative`) the terms' and factors' derivatives are taken the same
    way, as sympy's rules for them take each by ``diff``. Anything else (not an expression, one
    that cannot be differentiated, a result that holds an unevaluated derivative) goes to
    ``sympy.diff`` itself. ``free``: ``expr.free_symbols`` when the caller has it.
    """
    if not isinstance(expr, sp.Expr) or isinstance(expr, sp.Derivative) or not isinstance(x, sp.Symbol) \
            or not hasattr(expr, "_eval_derivative"):
        return sp.diff(expr, x)
    if x not in (expr.free_symbols if free is None else free):
        return sp.S.Zero
    if expr.is_Symbol:  # x itself (the only symbol free in it): sympy's Piecewise of the order gives 1
        return sp.S.One
    return _derivative_of(expr, x)


@lru_cache(maxsize=50000)
def _derivative_of(expr: sp.Expr, x: sp.Symbol):
    """:func:`derivative` of an expression in which ``x`` is free, remembered per process (the last
    50000): a scene loaded again (a command after another, each test of a suite) differentiates the
    same expressions, and sympy objects are equal only when they are structurally the same, so an
    equal argument gives the object a new derivation would."""
    out = _sum_or_product_derivative(expr, x)
    if out is None:
        out = expr._eval_derivative_n_times(x, sp.S.One)
    if out is None or out.has(sp.Derivative):
        return sp.diff(expr, x)
    return out


def _sum_or_product_derivative(expr, x: sp.Symbol):
    """The derivative of a sum, a product, a power, a sine or a cosine in ``x`` by sympy's own rule
    for it, each term's, factor's or argument's derivative taken by :func:`derivative` (the same
    object as its ``diff``, which the rule asks for); None for any other node.

    The rules, as ``Add._eval_derivative``, ``Mul._eval_derivative_n_times``,
    ``Pow._eval_derivative`` and ``Function._eval_derivative`` apply them to one derivative: the sum
    of the terms' derivatives; for a product, in the order of the general Leibniz rule's index
    tuples (``multinomial_coefficients_iterator``), the product of the factors with one of them
    differentiated, times its coefficient 1; for b**e, b**e (e' log(b) + b' e / b); for f(a), the
    sum (of one term) f'(a) a', or 0 when a' is zero. Only the exact classes: a subclass may have
    rules of its own. A product whose differentiated factor is 0 is left out where it is 0
    (:func:`solver.model.joints.times_zero_is_zero`: no other factor can be infinite), as ``Add``
    leaves out a 0 term: sympy would build it only to ask each factor whether it is finite."""
    kind = type(expr)
    if kind is sp.Add:
        return sp.Add(*[derivative(a, x) for a in expr.args])
    if kind is sp.sin or kind is sp.cos:
        da = derivative(expr.args[0], x)
        return sp.Add() if da.is_zero else sp.Add(expr.fdiff(1) * da)
    if kind is sp.Pow:
        base, exp = expr.args
        return expr * (derivative(exp, x) * sp.log(base) + derivative(base, x) * exp / base)
    if kind is not sp.Mul:
        return None
    args = expr.args
    if not expr.is_commutative:
        from sympy.ntheory.multinomial import multinomial_coefficients_iterator

        return sp.Add(*[c * sp.Mul(*[derivative(a, x) if k else a for k, a in zip(ks, args)])
                        for ks, c in multinomial_coefficients_iterator(len(args), 1)])
    terms = []
    for i in _leibniz_order(len(args)):
        factors = (*args[:i], derivative(args[i], x), *args[i + 1:])
        if not times_zero_is_zero(factors):  # a product with a factor 0 is 0 (Add drops it), unless
            terms.append(sp.Mul(*factors))   # a factor may be infinite (times the coefficient 1)
    return sp.Add(*terms)


_LEIBNIZ: dict[int, tuple[int, ...]] = {}
"""Number of factors -> the indices of the factor differentiated, in the order of
``multinomial_coefficients_iterator(n, 1)`` (a table of sympy's order, filled as needed)."""


def _leibniz_order(n: int) -> tuple[int, ...]:
    """The order in which sympy's rule for a product of ``n`` factors differentiates them (:data:`_LEIBNIZ`)."""
    order = _LEIBNIZ.get(n)
    if order is None:
        from sympy.ntheory.multinomial import multinomial_coefficients_iterator

        order = _LEIBNIZ[n] = tuple(ks.index(1) for ks, _ in multinomial_coefficients_iterator(n, 1))
    return order


def second_derivative(expr, x: sp.Symbol):
    """``sympy.diff(expr, x, 2)``: the same object, by :func:`derivative` where sympy's path is that
    of a sum twice over (its own rule for a sum applied to ``expr``, then to the derivative), and
    then, as sympy ends every derivative of order above one, ``factor_terms(signsimp(...))`` of a
    result that is not zero. Any other case goes to ``sympy.diff`` itself (the generalized mass
    ``d2T/dqd2``, taken once per derivation, costs a fifth of sympy's time this way)."""
    if type(expr) is not sp.Add or not isinstance(x, sp.Symbol):
        return sp.diff(expr, x, 2)
    first = derivative(expr, x)
    if type(first) is not sp.Add or first == expr:
        return sp.diff(expr, x, 2)
    second = derivative(first, x)
    if second.has(sp.Derivative):
        return sp.diff(expr, x, 2)
    if second.is_zero:
        return second
    from sympy.core.exprtools import factor_terms
    from sympy.simplify.simplify import signsimp

    return factor_terms(signsimp(second))


class RedundantConstraints(SceneError):
    """Closure equations that are dependent at the state (statically indeterminate reactions)."""


class _Unplaceable(SceneError):
    """A body that the joints cannot place (reported with the freedom count by ``validate``)."""


@dataclass(frozen=True)
class ClosureRow:
    """A joint equation the placement does not satisfy identically."""

    joint: Joint
    index: int
    expr: sp.Expr

    @property
    def reaction(self):
        return self.joint.reactions[self.index]


class System:
    """A planar multibody system (see the module docstring).

    Parameters
    ----------
    name : str
    parameters : dict[str, pint.Quantity]
    coordinates : list of Coordinate
    bodies : list of RigidBody
    joints : list of Joint
    loads : list of Load
    ground : Ground, optional
    time : float
        The instant of the state [s] (prescribed motions are evaluated there).
    source : str, optional
        File name used in messages.
    output_units : dict[str, str], optional
    description : str
    """

    def __init__(self, name: str, parameters: dict, coordinates: Iterable[Coordinate],
                 bodies: Iterable[RigidBody], joints: Iterable[Joint] = (), loads: Iterable[Load] = (),
                 ground: Ground | None = None, time: float = 0.0, source: str | None = None,
                 output_units: dict | None = None, description: str = ""):
        self.name = name
        self.description = description
        self.parameters = dict(parameters)
        self.coordinates = list(coordinates)
        self.bodies: dict[str, RigidBody] = {b.name: b for b in bodies}
        self.joints: list[Joint] = list(joints)
        self.loads: list[Load] = list(loads)
        self.ground = ground or Ground()
        self.time = float(time)
        self.source = source
        self.output_units = dict(output_units or {})
        self.t = sp.Symbol("t", real=True)
        self.reset()

    # -- cache ---------------------------------------------------------------------------
    def reset(self) -> None:
        """Forget every derived result (call after changing the model)."""
        self._cache: dict = {}

    def _memo(self, key, build):
        if key not in self._cache:
            self._cache[key] = build()
        return self._cache[key]

    def add_body(self, body: RigidBody) -> None:
        self.bodies[body.name] = body
        self.reset()

    def add_joint(self, joint: Joint) -> None:
        self.joints.append(joint)
        self.reset()

    def add_load(self, load: Load) -> None:
        self.loads.append(load)
        self.reset()

    @property
    def label(self) -> str:
        return self.source if self.source is not None else f"scene {self.name!r}"

    def fail(self, what: str) -> SceneError:
        return SceneError(f"{self.label}: {what}")

    # -- symbols and values -----------------------------------------------------------------
    @property
    def symbols(self) -> dict[str, sp.Symbol]:
        return {n: sp.Symbol(n, real=True) for n in self.parameters}

    def si_values(self) -> dict[sp.Symbol, float]:
        """Parameter symbol -> SI value (angles in rad)."""
        return self._memo("si", lambda: {
            sp.Symbol(n, real=True): si_magnitude(q) for n, q in self.parameters.items()
        })

    @property
    def free(self) -> list[Coordinate]:
        """Coordinates that are not prescribed (independent and dependent)."""
        return [c for c in self.coordinates if not c.prescribed]

    @property
    def independent(self) -> list[Coordinate]:
        return [c for c in self.free if not c.dependent]

    @property
    def dependent(self) -> list[Coordinate]:
        return [c for c in self.free if c.dependent]

    @property
    def q(self) -> list[sp.Symbol]:
        return [c.q for c in self.free]

    @property
    def qd(self) -> list[sp.Symbol]:
        return [c.qd for c in self.free]

    @property
    def qdd(self) -> list[sp.Symbol]:
        return [c.qdd for c in self.free]

    @property
    def motion_subs(self) -> dict[sp.Symbol, sp.Expr]:
        """Prescribed coordinate -> its function of t (and rates -> derivatives)."""
        def build():
            out = {}
            for c in self.coordinates:
                if c.prescribed:
                    out[c.q] = c.motion
                    out[c.qd] = sp.diff(c.motion, self.t)
                    out[c.qdd] = sp.diff(c.motion, self.t, 2)
            return out
        return self._memo("motion", build)

    @property
    def time_dependent(self) -> bool:
        """True when a body's placement depends on time (prescribed motion, a driver, a moving support)."""
        t = self.t
        return self._memo("time_dependent", lambda: any(
            sp.sympify(x).has(t) for origin, phi in self.poses.values() for x in (*origin, phi)))

    def prescribe(self, expr):
        """Replace prescribed coordinates by their functions of t."""
        subs = self.motion_subs
        if not subs:
            return expr
        return expr.xreplace(subs)

    # -- time derivative ---------------------------------------------------------------------
    def D(self, expr):
        """d/dt of an expression (or Matrix) in (q, q_dot, t) with prescribed motion substituted."""
        if isinstance(expr, sp.MatrixBase):  # a mutable 2-vector by components (vec: no matrix machinery)
            if type(expr) is sp.MutableDenseMatrix and expr.shape == (2, 1):
                return vec(*(self.D(x) for x in xy(expr)))
            return expr.applyfunc(self.D)
        expr = sp.sympify(expr)
        present = expr.free_symbols
        terms = [derivative(expr, self.t, present)] if self.t in present else []
        for c in self.free:  # only the symbols present: the rest differentiate to 0
            if c.q in present:
                terms.append(derivative(expr, c.q, present) * c.qd)
            if c.qd in present:
                terms.append(derivative(expr, c.qd, present) * c.qdd)
        return sp.Add(*terms)

    # -- placement -----------------------------------------------------------------------------
    def _pose_fn(self, poses):
        def pose(name):
            if name == GROUND:
                return sp.zeros(2, 1), sp.Integer(0)
            return poses[name]
        return pose

    @property
    def poses(self) -> dict[str, tuple[sp.Matrix, sp.Expr]]:
        """Body name -> (origin r_b(q, t), angle phi_b(q, t)), prescribed motion substituted."""
        return self._memo("poses", self._place)[0]

    @property
    def placement_rows(self) -> set[tuple[str, int]]:
        """(joint name, row index) of the joint equations used to place the bodies."""
        return self._memo("poses", self._place)[1]

    def _state_values(self) -> dict[sp.Symbol, float]:
        vals = dict(self.si_values())
        for c in self.coordinates:
            vals[c.q] = c.value
            vals[c.qd] = c.rate
        vals[self.t] = self.time
        return vals

    def _num(self, expr, values, exact: bool = False) -> float:
        """``expr`` at ``values`` (nan where it is not a finite real number). For the rank and
        identity decisions, which compare with tolerances far above round-off, in double precision
        by one tree walk (:func:`solver.tree_value.tree_value`); ``exact``: by sympy's evalf (a
        value the model keeps, such as a phase)."""
        expr = sp.sympify(expr)
        if not exact:
            try:
                value = tree_value(expr, values)
            except (ZeroDivisionError, OverflowError):
                return float("nan")
            except (NotEvaluable, KeyError, TypeError, ValueError):
                pass
            else:
                return real_value(value)
        try:
            return float(expr.xreplace({k: sp.Float(values[k]) for k in expr.free_symbols if k in values}).evalf())
        except (TypeError, ValueError):
            return float("nan")

    def _joint_touching(self, body):
        for j in self.joints:
            if body in j.bodies:
                yield j, (j.first if j.second == body else j.second)

    def _place(self):
        t = self.t
        poses: dict[str, tuple] = {}
        phis = {n: (None if b.orientation is None else self.prescribe(sp.sympify(b.orientation)))
                for n, b in self.bodies.items()}
        used: set[tuple[str, int]] = set()
        pending = list(self.bodies)
        pose = self._pose_fn(poses)
        values = self._state_values()
        X, Y = sp.symbols("_X _Y", real=True)
        while pending:
            progress = False
            for name in list(pending):
                body = self.bodies[name]
                if phis[name] is None:
                    for j, other in self._joint_touching(name):
                        if other == GROUND or other in poses:
                            o = j.orientation_of(name, pose, t)
                            if o is not None:
                                phis[name] = self.prescribe(o)
                                used.add((j.name, j.orientation_row))
                                break
                if phis[name] is None:
                    continue
                phi = phis[name]
                origin = None
                if body.position is not None:
                    pname, at = body.position
                    origin = self.prescribe(sp.Matrix(at)) - rotation(phi) * body.body_coords(pname)
                if origin is None:
                    trial = dict(poses)
                    trial[name] = (sp.zeros(2, 1), phi)
                    for j, other in self._joint_touching(name):
                        if other == GROUND or other in poses:
                            o = j.place(name, self._pose_fn(trial), t)
                            if o is not None:
                                origin = self.prescribe(o)
                                used.update((j.name, k) for k in j.place_rows)
                                break
                if origin is None:
                    origin, rows_used = self._place_linear(name, phi, poses, values, X, Y)
                    if origin is not None:
                        used.update(rows_used)
                if origin is not None:
                    poses[name] = (copy_vec(origin), phi)
                    pending.remove(name)
                    progress = True
            if not progress:
                reasons = []
                for n in pending:
                    if phis[n] is None:
                        reasons.append(f"body {n!r}: its angle is neither given (`orientation`) nor fixed by a joint "
                                       "(slider, motor, rolling_on_circle with position_angle), so its joints leave it "
                                       "free to turn")
                    else:
                        reasons.append(f"body {n!r}: its joints to placed bodies do not fix its position (needs a pin, "
                                       "two rails, a rolling contact, a cord with a guide, or `position`)")
                raise _Unplaceable(f"{self.label}: cannot place " + "; ".join(reasons))
        return poses, used

    def _place_linear(self, name, phi, poses, values, X, Y):
        trial = dict(poses)
        trial[name] = (vec(X, Y), phi)
        pose = self._pose_fn(trial)
        candidates = []
        for j, other in self._joint_touching(name):
            if not (other == GROUND or other in poses):
                continue
            try:
                rows = j.rows(pose, self.t)
            except ValueError:
                continue
            for k, row in enumerate(rows):
                a, b = derivative(row, X), derivative(row, Y)
                if a == 0 and b == 0:
                    continue
                if a.has(X, Y) or b.has(X, Y):
                    continue  # not linear in the translation (rows hold X, Y only through the origin)
                candidates.append((j.placement_priority, j, k, a, b, row))
        candidates.sort(key=lambda c: (c[0], c[1].row_rank(c[2])))
        chosen = []
        for cand in candidates:
            trial_rows = chosen + [cand]
            M = np.array([[self._num(c[3], values), self._num(c[4], values)] for c in trial_rows])
            if np.all(np.isfinite(M)) and np.linalg.matrix_rank(M, tol=1e-9 * max(1.0, np.abs(M).max())) == len(trial_rows):
                chosen.append(cand)
            if len(chosen) == 2:
                break
        if len(chosen) < 2:
            if len(candidates) >= 2 and len({id(c[1]) for c in candidates}) >= 2 and len(chosen) == 1:
                names = ", ".join(dict.fromkeys(repr(c[1].name) for c in candidates))
                raise self.fail(
                    f"impossible geometry: the joints {names} cannot fix the position of body {name!r}: "
                    f"their lines are parallel (or their equations dependent) at the scene's state"
                )
            return None, set()
        (_, j1, k1, a1, b1, r1), (_, j2, k2, a2, b2, r2) = chosen
        c1 = r1.xreplace({X: 0, Y: 0})
        c2 = r2.xreplace({X: 0, Y: 0})
        det = a1 * b2 - a2 * b1
        x = (-c1 * b2 + c2 * b1) / det
        y = (-a1 * c2 + a2 * c1) / det
        return vec(x, y), {(j1.name, k1), (j2.name, k2)}

    # -- validation --------------------------------------------------------------------------------
    def validate(self) -> None:
        """One pass over the whole model: freedoms against reactions, then placement and closure.

        Each body has 3 freedoms; each reaction unknown removes one. The
        coordinates (free ones, less one per closure equation) must describe
        exactly the freedoms that remain.

        Raises
        ------
        SceneError
            Naming the bodies and joints and the counts when the system is over-
            or under-constrained, or a body cannot be placed.
        """
        def check():
            sliding = [j.name for j in self.joints if getattr(j, "needs_regime", False)]
            if sliding:
                raise self.fail(
                    f"the friction force of {', '.join(map(repr, sliding))} depends on whether and which way "
                    f"the contact slides: `solve`, `simulate` and `friction` find the regime; this command "
                    f"needs joints whose equations do not change"
                )
            n_bodies = len(self.bodies)
            removed = len(self.reactions)
            left = 3 * n_bodies - removed
            described = len(self.free) - len(self.closure)
            joints = ", ".join(f"{j.name} ({j.kind}, {j.freedoms_removed})" for j in self.joints) or "none"
            if len(self.closure) > len(self.dependent):
                names = ", ".join(dict.fromkeys(repr(r.joint.name) for r in self.closure))
                if all(isinstance(r.joint, Contact) and r.joint.friction is not None and r.index == 0
                       and r.joint.current_regime.keeps_tangential for r in self.closure):  # rows slipping releases
                    raise self.fail(
                        f"the contact(s) {names} can slip (the scene gives coordinates for that): "
                        f"`solve`, `simulate` and `friction` find which regime holds; this command needs "
                        f"joints whose equations do not change"
                    )
                raise self.fail(
                    f"joint(s) {names} are not satisfied by the bodies' given orientations and positions for "
                    f"every value of the coordinates ({len(self.closure)} closure equation(s), "
                    f"{len(self.dependent)} dependent coordinate(s)): fix the orientation/position, or give "
                    f"as many coordinates a `guess` (dependent) as there are closure equations"
                )
            counts = (f"{n_bodies} bod{'y' if n_bodies == 1 else 'ies'} x 3 freedoms - {removed} removed by the "
                      f"joints [{joints}] = {left}, but the coordinates describe {described}")
            if left > described:
                raise self.fail(
                    f"under-constrained: {counts}; a body can move in ways no coordinate describes: add a joint "
                    f"(e.g. a second rail, a slider instead of a rail, a motor for a prescribed motion) "
                    f"or a coordinate"
                )
            if left < described:
                raise self.fail(
                    f"over-constrained: {counts}; remove a joint or mark a coordinate dependent "
                    f"(guess = ...) or prescribed (motion = ...)"
                )
            return True
        try:
            self.poses  # placement first: its errors name the body
        except _Unplaceable as err:
            left = 3 * len(self.bodies) - len(self.reactions)
            joints = ", ".join(f"{j.name} ({j.kind}, {j.freedoms_removed})" for j in self.joints) or "none"
            raise self.fail(
                f"under-constrained: {len(self.bodies)} bod{'y' if len(self.bodies) == 1 else 'ies'} x 3 "
                f"freedoms - {len(self.reactions)} removed by the joints [{joints}] = {left}, and the scene fixes "
                f"motions that no joint holds: {str(err.args[0]).split(': cannot place ', 1)[-1]}"
            ) from None
        self._memo("validated", check)

    # -- kinematics -------------------------------------------------------------------------------
    def angle(self, body: str) -> sp.Expr:
        """phi_b(q, t) [rad] (0 for the ground)."""
        return sp.Integer(0) if body == GROUND else self.poses[body][1]

    def origin(self, body: str) -> sp.Matrix:
        return sp.zeros(2, 1) if body == GROUND else self.poses[body][0]

    def omega(self, body: str) -> sp.Expr:
        """omega_b = d phi_b / dt (k-component) [rad/s]."""
        if body == GROUND:
            return sp.Integer(0)
        return self._memo(("omega", body), lambda: self.D(self.angle(body)))

    def alpha(self, body: str) -> sp.Expr:
        """alpha_b = d omega_b / dt (k-component), linear in the q_ddot [rad/s^2]."""
        if body == GROUND:
            return sp.Integer(0)
        return self._memo(("alpha", body), lambda: self.D(self.omega(body)))

    def body_point(self, body: str, coords: sp.Matrix) -> sp.Matrix:
        """Fixed-frame position of the body point with body-frame ``coords``."""
        if body == GROUND:
            return copy_vec(coords)
        (ox, oy), phi = xy(self.origin(body)), self.angle(body)
        c, s = sp.cos(phi), sp.sin(phi)
        x, y = xy(coords)
        # o + R(phi) (x, y), by components (2-vector Matrix arithmetic is slow in sympy)
        return vec(ox + c * x - s * y, oy + s * x + c * y)

    def _origin_velocity(self, body):
        return self._memo(("v0", body), lambda: self.D(self.origin(body)))

    def _origin_acceleration(self, body):
        return self._memo(("a0", body), lambda: self.D(self._origin_velocity(body)))

    def _resolve(self, body: str, point: str):
        """(kind, data) of a named point: ('body', coords) or ('instant', (ref, offset))."""
        holder = self.ground if body == GROUND else self.bodies.get(body)
        if holder is None:
            raise self.fail(f"unknown body {body!r} (bodies: {', '.join(self.bodies)})")
        if point in holder.points:
            p = holder.points[point]
            if p.is_instant:
                return "instant", (p.relative_to, copy_vec(p.coords))
            return "body", copy_vec(p.coords)
        if point == "G" and body != GROUND:
            return "body", holder.mass_center()
        names = holder.point_names()
        raise self.fail(f"point {point!r} is not a point of body {body!r} (points: {', '.join(names)})")

    def point_position(self, body: str, point: str) -> sp.Matrix:
        """Fixed-frame position of a named point (``G`` = the body's mass centre)."""
        def build():
            kind, data = self._resolve(body, point)
            if kind == "instant":
                ref, offset = data
                return vadd(self.point_position(body, ref), offset)
            return self.body_point(body, data)
        return self._memo(("pos", body, point), build)

    def point_velocity(self, body: str, point: str) -> sp.Matrix:
        """Velocity of the material point at ``point`` (Eq. 6): v_O + omega x (r - r_O)."""
        def build():
            if body == GROUND:
                return sp.zeros(2, 1)
            (rx, ry), (ox, oy) = xy(self.point_position(body, point)), xy(self.origin(body))
            (vx, vy), w = xy(self._origin_velocity(body)), self.omega(body)
            return vec(vx - w * (ry - oy), vy + w * (rx - ox))
        return self._memo(("vel", body, point), build)

    def point_acceleration(self, body: str, point: str) -> sp.Matrix:
        """Acceleration of the material point at ``point`` by the rigid-body
        relation from the body's origin (Eqs. 6, 15):
        a = a_O + alpha x r - omega^2 r, r = r_point - r_O. Linear in the q_ddot."""
        def build():
            if body == GROUND:
                return sp.zeros(2, 1)
            return self.material_acceleration(body, self.point_position(body, point))
        return self._memo(("acc", body, point), build)

    def material_acceleration(self, body: str, r: sp.Matrix) -> sp.Matrix:
        """Acceleration of the body's material point at fixed-frame position r (Eq. 15)."""
        (px, py), (ox, oy) = xy(r), xy(self.origin(body))
        rx, ry = px - ox, py - oy
        (ax, ay), al, w2 = xy(self._origin_acceleration(body)), self.alpha(body), self.omega(body) ** 2
        return vec(ax - al * ry - w2 * rx, ay + al * rx - w2 * ry)

    def is_body_point(self, body: str, point: str) -> bool:
        return self._resolve(body, point)[0] == "body"

    def fixed_point(self, body: str):
        """The point of ``body`` that a pin to the ground holds still, or None.

        Returns
        -------
        (Pin, str or None, sympy.Matrix, sympy.Matrix) or None
            The joint, the body's name for the point (None when it has none),
            its body-frame coordinates and its fixed-frame place (the ground's
            point: ground points never move).
        """
        def build():
            if body == GROUND:
                return None
            for j in self.joints:
                if isinstance(j, Pin) and {j.first, j.second} == {GROUND, body}:
                    coords, place = ((j.at_second, j.at_first) if j.first == GROUND else (j.at_first, j.at_second))
                    b = self.bodies[body]
                    name = next((n for n, p in b.points.items() if not p.is_instant
                                 and all(sp.expand(x - y) == 0 for x, y in zip(p.coords, coords))), None)
                    return j, name, copy_vec(coords), copy_vec(place)
            return None
        return self._memo(("fixed", body), build)

    def point_kinematics(self, body: str, point: str) -> tuple[sp.Matrix, sp.Matrix, sp.Matrix]:
        """Position, velocity and acceleration of a named point on the motion the joints allow.

        Those of :meth:`point_position`, :meth:`point_velocity` and
        :meth:`point_acceleration` (the placement, true for every value of the
        coordinates), except on a body that a pin to the ground holds
        (:meth:`fixed_point`) but that the placement reaches through other
        bodies (a four-bar's rocker, placed through the coupler): there the
        placement writes the pivot along the loop, fixed only where the closure
        equations hold. The motion is then carried from the pivot F, at its
        fixed place with v_F = a_F = 0, by the rigid-body relation
        (Eqs. 6, 15): r = r_F + r_/F, v = omega x r_/F,
        a = alpha x r_/F - omega^2 r_/F, r_/F from the placement (the body's own
        angle only). Used for the moment equation about P; the placement's
        kinematics stay where the equations must hold off the loop too (the
        multipliers' equations, Kane's projection, Lagrange's equations).
        """
        def build():
            r = self.point_position(body, point)
            held = self.fixed_point(body)
            if held is not None:
                r_F = self.body_point(body, held[2])
                if any(sp.expand(x - y) != 0 for x, y in zip(r_F, held[3])):
                    rel = vec(r[0] - r_F[0], r[1] - r_F[1])
                    w, al = self.omega(body), self.alpha(body)
                    return (vec(held[3][0] + rel[0], held[3][1] + rel[1]), vec(-w * rel[1], w * rel[0]),
                            vec(-al * rel[1] - w**2 * rel[0], al * rel[0] - w**2 * rel[1]))
            return r, self.point_velocity(body, point), self.point_acceleration(body, point)
        return self._memo(("kinematics", body, point), build)

    # -- joints: reactions, closure ---------------------------------------------------------------
    @property
    def reactions(self):
        """Every reaction unknown, in joint order."""
        return [r for j in self.joints for r in j.reactions]

    @property
    def closure(self) -> list[ClosureRow]:
        """The joint equations not satisfied identically by the placement."""
        return self._memo("closure", self._closure)

    def _closure(self) -> list[ClosureRow]:
        pose = self._pose_fn(self.poses)
        used = self.placement_rows
        values = self._state_values()
        rng = random.Random(12345)
        samples = []
        for _ in range(3):
            v = dict(values)
            for c in self.free:
                v[c.q] = c.value + rng.uniform(-0.4, 0.4) * (1.0 if c.kind == "angle" else max(abs(c.value), 0.1))
            v[self.t] = self.time + rng.uniform(0.1, 0.5)
            samples.append(v)
        out = []
        for j in self.joints:
            self._bind_prescribed(j)
            self._bind_phase(j, pose, values)
            if all((j.name, k) in used for k in range(len(j.reactions))):
                continue  # every row (one per reaction) placed a body: none is left to check
            rows = j.rows(pose, self.t)
            for k, row in enumerate(rows):
                if (j.name, k) in used:
                    continue
                row = self.prescribe(sp.sympify(row))
                if row == 0:
                    continue
                scale = 1.0 + sum(abs(self._num(term, values)) for term in sp.Add.make_args(row))
                if all(abs(self._num(row, s)) <= _IDENTICAL_TOL * scale for s in [values] + samples):
                    continue
                out.append(ClosureRow(j, k, row))
        return out

    def _bind_phase(self, j: Joint, pose, values) -> None:
        """A gear mesh's (or a rolling-on-circle contact's) phase: the value that satisfies it at the state."""
        if getattr(j, "phase_from_state", False) and (j.name, 0) not in self.placement_rows:
            j.phase = sp.Integer(0)
            r0 = self._num(self.prescribe(sp.sympify(j.rows(pose, self.t)[0])), values, exact=True)
            j.phase = sp.Integer(1)
            r1 = self._num(self.prescribe(sp.sympify(j.rows(pose, self.t)[0])), values, exact=True)
            j.phase = sp.Float(-r0 / (r1 - r0))  # the row is affine in the phase: zero at the state
            j.phase_from_state = False

    def _bind_prescribed(self, j: Joint) -> None:
        """A motor or actuator without its own motion drives what the coordinates prescribe."""
        if isinstance(j, Motor) and j.angle is None and j.prescribed is None:
            rel = self.angle(j.second) - self.angle(j.first)
            j.prescribed = rel
        if isinstance(j, Actuator) and j.position is None and j.prescribed is None:
            pose = self._pose_fn(self.poses)
            o = pose(j.first)
            d = rotation(o[1]) * sp.Matrix([sp.cos(j.angle), sp.sin(j.angle)])
            p = self.body_point(j.second, j.point)
            th = self.body_point(j.first, j.through)
            j.prescribed = (d.T * (p - th))[0]

    # -- loads ------------------------------------------------------------------------------------
    @property
    def applied_loads(self):
        """Every applied (non-reaction) force and couple, with prescribed motion substituted."""
        def build():
            out = []
            for load in self.loads:
                for a in load.applied(self):
                    out.append(type(a)(
                        a.name, a.kind, a.body,
                        None if a.force is None else self.prescribe(copy_vec(a.force)),
                        a.at, self.prescribe(sp.sympify(a.couple)), a.point,
                    ))
            return out
        return self._memo("applied", build)

    def joint_loads(self):
        """Every reaction as unit loads on bodies (JointLoad), for the Newton-Euler equations."""
        def build():
            pose = self._pose_fn(self.poses)
            return [jl for j in self.joints for jl in j.loads(pose, self.t)]
        return self._memo("joint_loads", build)

    # -- energies ---------------------------------------------------------------------------------
    def potential_energy(self) -> sp.Expr:
        """V(q, t) of the conservative loads (gravity, springs). [J]"""
        def build():
            terms = [load.potential(self) for load in self.loads if load.conservative]
            return self.prescribe(sp.Add(*[t for t in terms if t is not None]))
        return self._memo("V", build)

    def kinetic_energy(self) -> sp.Expr:
        """T = sum over elements of 1/2 m_k |v_k|^2 + 1/2 I-bar_k omega^2. [J]"""
        def build():
            terms = []
            for name, body in self.bodies.items():
                w = self.omega(name)
                for e in body.elements:
                    v = self._origin_velocity(name) + k_cross(w, rotation(self.angle(name)) * e.mass_center)
                    terms.append(e.mass * (v[0] ** 2 + v[1] ** 2) / 2 + e.I_G * w**2 / 2)
            return sp.Add(*terms)
        return self._memo("T", build)

    def generalized_forces(self) -> list[sp.Expr]:
        """Q_i of the non-conservative loads (forces, couples, dampers), by partial velocities."""
        def build():
            out = []
            for c in self.free:
                terms = []
                for load in self.loads:
                    if load.conservative:
                        continue
                    for a in load.applied(self):
                        if a.force is not None:
                            if a.point is not None:
                                v = self.point_velocity(*a.point)
                            else:
                                raise self.fail(f"load {a.name!r}: no point to take its velocity")
                            terms.append(dot(a.force, (derivative(v[0], c.qd), derivative(v[1], c.qd))))
                        if a.couple != 0:
                            terms.append(a.couple * derivative(self.omega(a.body), c.qd))
                out.append(self.prescribe(sp.Add(*terms)))
            return out
        return self._memo("Q", build)

    # -- model limits -----------------------------------------------------------------------------
    def limits(self) -> list[tuple[str, sp.Expr]]:
        pose = self._pose_fn(self.poses)
        return [lim for j in self.joints for lim in j.limits(pose)]

    def copy(self, coordinates=None, joints=None, time=None) -> "System":
        """A new system with the same bodies, loads and parameters (derived results not shared)."""
        return System(self.name, self.parameters, self.coordinates if coordinates is None else coordinates,
                      self.bodies.values(), self.joints if joints is None else joints, self.loads, self.ground,
                      time=self.time if time is None else time, source=self.source,
                      output_units=self.output_units, description=self.description)

    # -- contact regimes --------------------------------------------------------------------------
    @property
    def contacts(self) -> list[Joint]:
        """The contacts that can change regime: friction, or a one-sided normal force."""
        return [j for j in self.joints if isinstance(j, Contact)
                and (j.friction is not None or j.normal_reaction.one_sided)]

    def with_regimes(self, regimes: dict, q=None, qd=None, t=None, redundant_ok: bool = False) -> "System":
        """A copy of this system with contacts in the given regimes, at a state.

        Parameters
        ----------
        regimes : dict[str, Regime]
            Joint name -> regime (see :mod:`solver.model.contacts`); other
            joints are kept as they are.
        q, qd : sequences of float, optional
            Values and rates of the free coordinates (the scene's by default).
            Stick rows that the scene did not state are bound to this state.
        t : float, optional
        redundant_ok : bool
            Return the copy even when its closure equations are dependent
            (for a check of statically indeterminate forces); its coordinates
            are then all independent and it does not validate.

        The dependent coordinates are re-chosen: as many as the copy has
        closure equations, those whose columns of the closure Jacobian are
        independent (coordinates the scene marks dependent first).

        Raises
        ------
        RedundantConstraints
            The closure equations are dependent at the state (a body held by
            more contacts than it has freedoms: the contact forces are
            statically indeterminate).
        """
        from dataclasses import replace as _replace

        free = self.free
        q = [c.value for c in free] if q is None else list(q)
        qd = [c.rate for c in free] if qd is None else list(qd)
        values = dict(zip((c.name for c in free), zip(q, qd)))
        coords = [c if c.prescribed else _replace(c, value=float(values[c.name][0]), rate=float(values[c.name][1]),
                                                  dependent=False, given=None)
                  for c in self.coordinates]
        joints = [j.in_regime(regimes[j.name]) if j.name in regimes else j for j in self.joints]
        new = self.copy(coordinates=coords, joints=joints, time=self.time if t is None else float(t))
        rows = new.closure
        if rows:
            J = sp.Matrix([r.expr for r in rows]).jacobian(sp.Matrix(new.q))
            vals = {**new._state_values(), new.t: new.time}
            Jn = np.array([[new._num(x, vals) for x in row] for row in J.tolist()], dtype=float)
            marked = {c.name for c in self.free if c.dependent}
            order = sorted(range(len(free)), key=lambda i: (free[i].name not in marked, -i))
            chosen: list[int] = []
            for i in order:
                trial = chosen + [i]
                if np.linalg.matrix_rank(Jn[:, trial], tol=1e-9 * max(1.0, np.abs(Jn).max())) == len(trial):
                    chosen = trial
                if len(chosen) == len(rows):
                    break
            if len(chosen) < len(rows):
                if redundant_ok:
                    return new
                names = ", ".join(dict.fromkeys(repr(r.joint.name) for r in rows))
                raise RedundantConstraints(f"{self.label}: the contacts {names} hold more than the "
                                           f"coordinates can move: their forces are statically indeterminate")
            dep = {free[i].name for i in chosen}
            new.coordinates = [_replace(c, dependent=c.name in dep) for c in coords]
            new.reset()
        return new

    def __repr__(self) -> str:
        return (f"System({self.name!r}, bodies=[{', '.join(self.bodies)}], "
                f"coordinates=[{', '.join(c.name for c in self.coordinates)}], joints={len(self.joints)})")
