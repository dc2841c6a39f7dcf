"""From a scene to its equations and answers, by a chosen route.

``derive`` builds a :class:`Derivation` (symbolic: equations, equation of
motion, reactions, energies); ``solve_instant`` solves the linear system at the
scene's state; ``natural_frequency`` linearises about the stable equilibrium.

Routes (``method=``):

* ``"generalized_euler"``: Newton (Eq. 1 / Eq. 14 with Eq. 15) and the
  generalized Euler equation about the embedded point P (Eq. 10 / Eq. 11).
* ``"mass_center"``: Eqs. (1)-(2) about the composite mass centre G.
* ``"lagrange"``: Lagrange's equation and Kane's auxiliary equations built with
  ``sympy.physics.mechanics`` (see :mod:`solver.lagrange`).

The equation of motion is normalised to
``M(q) qdd + 1/2 M'(q) qd^2 + V'(q) - Q(q, qd, t) == 0``, where
T = 1/2 M qd^2 is the kinetic energy, V the gravitational potential and Q the
generalized force of the other applied loads.
"""
from __future__ import annotations

import math
from collections import OrderedDict
from dataclasses import dataclass
from typing import Mapping

import numpy as np
import pint
import sympy as sp

from .errors import InputError, NoRestoringError, SceneError, SingularConfigurationError
from .euler import NamedEquation, applied_loads, generalized_euler_equations, mass_center_equations
from .kinematics import BodyKinematics, scene_label
from .scene import Scene
from .units import Q_

__all__ = [
    "METHODS",
    "CONDITION_LIMIT",
    "Derivation",
    "NamedEquation",
    "NumericModel",
    "InstantSolution",
    "FrequencyResult",
    "derive",
    "solve_instant",
    "natural_frequency",
    "clear_cache",
]

METHODS = ("generalized_euler", "mass_center", "lagrange")
# Above this condition number (of the row/column-equilibrated system matrix)
# the answer is treated as meaningless: SingularConfigurationError.
CONDITION_LIMIT = 1e12
_CACHE_SIZE = 128

# Which scene.output_units key converts which SI unit.
_DIMENSION_OF_UNIT = {"N": "force", "N*m": "moment", "rad/s**2": "angular_acceleration"}


# ---------------------------------------------------------------------------
# caching: scenes are frozen but hold dicts (unhashable), so key by identity
# and keep the scene alive in the entry so that its id cannot be reused.
_kinematics_cache: "OrderedDict[int, tuple[Scene, BodyKinematics]]" = OrderedDict()
_derivation_cache: "OrderedDict[tuple, tuple[Scene, Derivation]]" = OrderedDict()


_mechanics_cache: "OrderedDict[int, tuple]" = OrderedDict()


def clear_cache() -> None:
    """Forget every cached kinematics model, mechanics route and derivation."""
    _kinematics_cache.clear()
    _mechanics_cache.clear()
    _derivation_cache.clear()


def _remember(cache: OrderedDict, key, scene: Scene, value):
    cache[key] = (scene, value)
    cache.move_to_end(key)
    while len(cache) > _CACHE_SIZE:
        cache.popitem(last=False)
    return value


def _kinematics(scene: Scene) -> BodyKinematics:
    hit = _kinematics_cache.get(id(scene))
    if hit is not None and hit[0] is scene:
        return hit[1]
    return _remember(_kinematics_cache, id(scene), scene, BodyKinematics(scene))


def _mechanics_route(scene: Scene):
    """The sympy.physics.mechanics route of a scene (independent of P), cached."""
    from .lagrange import lagrange_route

    hit = _mechanics_cache.get(id(scene))
    if hit is not None and hit[0] is scene:
        return hit[1]
    return _remember(_mechanics_cache, id(scene), scene, lagrange_route(scene))


# ---------------------------------------------------------------------------
@dataclass
class InstantSolution:
    """The angular acceleration and every reaction at one state.

    Attributes
    ----------
    unknowns : dict[str, pint.Quantity]
        ``alpha`` and ``theta_ddot`` [rad/s**2], each reaction [N] or [N*m].
    condition_number : float
        2-norm condition number of the row/column-equilibrated system matrix.
    point, method : str
    theta, theta_dot : pint.Quantity
        The state solved at.
    scene : str
        The scene's name.
    """

    unknowns: dict[str, pint.Quantity]
    condition_number: float
    point: str
    method: str
    theta: pint.Quantity | None = None
    theta_dot: pint.Quantity | None = None
    scene: str | None = None

    def to_dict(self, units: Mapping[str, str] | None = None) -> dict:
        """JSON-ready dict; ``units`` maps dimension names (``force``,
        ``moment``, ``angular_acceleration``) to display units (e.g. ``lbf``)."""
        units = dict(units or {})
        out = {}
        for name, qty in self.unknowns.items():
            si = _unit_string(qty)
            target = units.get(_DIMENSION_OF_UNIT.get(si, ""), si)
            out[name] = {"value": float(qty.to(target).magnitude), "unit": target}
        head = {"scene": self.scene} if self.scene is not None else {}
        return {
            **head,
            "point": self.point,
            "method": self.method,
            "unknowns": out,
            "condition_number": float(self.condition_number),
        }

    def __repr__(self) -> str:
        vals = ", ".join(f"{k}={v:.6g~P}" for k, v in self.unknowns.items())
        return f"InstantSolution({vals}, cond={self.condition_number:.3g}, point={self.point!r}, method={self.method!r})"


def _unit_string(qty: pint.Quantity) -> str:
    for s in _DIMENSION_OF_UNIT:
        if qty.units == Q_(1, s).units:
            return s
    return str(qty.units)


@dataclass
class FrequencyResult:
    """Small oscillations about the stable equilibrium.

    Attributes
    ----------
    omega_n : pint.Quantity
        Natural frequency, sqrt(V''(q_e) / M(q_e)). [rad/s]
    equilibrium : pint.Quantity
        q_e with V'(q_e) = 0, V''(q_e) > 0. [rad]
    stiffness : pint.Quantity
        V''(q_e). [N*m/rad]
    mass : pint.Quantity
        M(q_e), the generalized mass. [kg*m**2]
    period : pint.Quantity
        2 pi / omega_n. [s]
    """

    omega_n: pint.Quantity
    equilibrium: pint.Quantity
    stiffness: pint.Quantity
    mass: pint.Quantity
    period: pint.Quantity

    def to_dict(self) -> dict:
        """JSON-ready dict of values and units."""
        return {
            "omega_n": {"value": float(self.omega_n.to("rad/s").magnitude), "unit": "rad/s"},
            "period": {"value": float(self.period.to("s").magnitude), "unit": "s"},
            "equilibrium": {"value": float(self.equilibrium.to("rad").magnitude), "unit": "rad"},
            "stiffness": {"value": float(self.stiffness.to("N*m/rad").magnitude), "unit": "N*m/rad"},
            "mass": {"value": float(self.mass.to("kg*m**2").magnitude), "unit": "kg*m**2"},
        }


# ---------------------------------------------------------------------------
class NumericModel:
    """Numeric, numpy-vectorised form of a derivation (lambdified once, cse=True).

    Methods take arrays (or scalars) of theta [rad], theta_dot [rad/s] and t
    [s], broadcast together; results are SI.
    """

    def __init__(self, derivation: "Derivation", values: Mapping[sp.Symbol, float] | None = None):
        d = derivation
        self.derivation = d
        self.label = scene_label(d.scene)
        values = dict(d.scene.si_values() if values is None else values)
        A, b = d.linear_system()
        self.n = A.shape[0]
        self.names = tuple(str(u) for u in d.unknowns)
        self.reaction_constraints = {r.name: r.constraint for r in d._kin.reactions}
        params = sorted(values, key=str)
        self._param_values = tuple(values[p] for p in params)
        args = (d.q, d.qd, d.t, *params)
        entries = list(A) + list(b) + [d._kin.dphi, d._kin.ddphi]
        allowed = set(args)
        stray = set().union(*[sp.sympify(e).free_symbols for e in entries]) - allowed
        if stray:
            raise SceneError(
                f"{self.label}: undefined name(s) {', '.join(sorted(map(str, stray)))} in the scene's expressions"
            )
        self._f = sp.lambdify(args, entries, modules="numpy", cse=True)

    def _evaluate(self, q, qd, t):
        q, qd, t = np.broadcast_arrays(
            np.asarray(q, dtype=float), np.asarray(qd, dtype=float), np.asarray(t, dtype=float)
        )
        with np.errstate(all="ignore"):
            vals = self._f(q, qd, t, *self._param_values)
        vals = [np.broadcast_to(np.asarray(v, dtype=float), q.shape) for v in vals]
        n = self.n
        A = np.stack(vals[: n * n], axis=-1).reshape(q.shape + (n, n))
        b = np.stack(vals[n * n : n * n + n], axis=-1)
        return q, qd, A, b, vals[-2], vals[-1]

    def matrices(self, q, qd, t=0.0):
        """(A, b) with A @ unknowns = b, shapes (..., n, n) and (..., n)."""
        _, _, A, b, _, _ = self._evaluate(q, qd, t)
        return A, b

    def condition_number(self, A: np.ndarray) -> np.ndarray:
        """Condition number of the row/column-equilibrated A (inf if degenerate)."""
        with np.errstate(all="ignore"):
            col = np.max(np.abs(A), axis=-2, keepdims=True)
            As = A / np.where(col > 0, col, np.nan)
            row = np.max(np.abs(As), axis=-1, keepdims=True)
            As = As / np.where(row > 0, row, np.nan)
        bad = ~np.all(np.isfinite(As), axis=(-2, -1))
        As = np.where(bad[..., None, None], 0.0, As)
        cond = np.linalg.cond(As + np.where(bad[..., None, None], np.eye(self.n), 0.0))
        return np.where(bad | ~np.isfinite(cond), np.inf, cond)

    def _singular(self, q, A, cond):
        idx = np.unravel_index(int(np.argmax(cond)), cond.shape) if cond.ndim else ()
        theta = float(q[idx])
        c = float(cond[idx])
        involved = []
        M = A[idx]
        if np.all(np.isfinite(M)):
            colscale = np.max(np.abs(M), axis=0)
            colscale[colscale == 0] = 1.0
            _, _, vt = np.linalg.svd(M / colscale)
            v = np.abs(vt[-1])
            for name, weight in zip(self.names[1:], v[1:]):
                constraint = self.reaction_constraints[name]
                if weight > 0.1 and constraint not in involved:
                    involved.append(constraint)
        if not involved:
            involved = list(dict.fromkeys(self.reaction_constraints.values()))
        cond_text = "infinite" if not math.isfinite(c) else f"{c:.3g}"
        raise SingularConfigurationError(
            f"{self.label}: singular configuration at {self.derivation.q} = {math.degrees(theta):.6g} deg "
            f"({theta:.6g} rad): the equations of constraint(s) {', '.join(involved)} do not determine "
            f"the motion (condition number {cond_text} > {CONDITION_LIMIT:.0e})"
        )

    def solve(self, q, qd, t=0.0) -> dict[str, np.ndarray]:
        """theta_ddot, alpha and every reaction (SI) at the given states.

        Raises
        ------
        SingularConfigurationError
            If any state's system is singular or has condition number > 1e12.
        """
        q, qd, A, b, dphi, ddphi = self._evaluate(q, qd, t)
        cond = self.condition_number(A)
        if np.any(cond > CONDITION_LIMIT):
            self._singular(q, A, cond)
        x = np.linalg.solve(A, b[..., None])[..., 0]
        out = {name: x[..., i] for i, name in enumerate(self.names)}
        out["alpha"] = ddphi * qd**2 + dphi * x[..., 0]
        out["condition_number"] = cond
        return out

    def qdd(self, q, qd, t=0.0) -> np.ndarray:
        """theta_ddot [rad/s^2] at the given states."""
        return self.solve(q, qd, t)[self.names[0]]


# ---------------------------------------------------------------------------
class Derivation:
    """The equations of one scene by one route about one point.

    Attributes
    ----------
    scene : Scene
    point : str
        The reference point P (for ``mass_center`` the equations are about G
        whatever P is; for ``lagrange`` P is not used).
    method : str
    q, qd, qdd, t : sympy.Symbol
    unknowns : tuple of sympy.Symbol
        (qdd, *reactions) in ``scene.reaction_names()`` order.
    equations : tuple of NamedEquation
    omega, alpha : sympy.Expr
        k-components of the angular velocity and acceleration (alpha linear in qdd).
    mass, kinetic_energy, potential_energy, generalized_force : sympy.Expr
        M(q), T(q, qd) = 1/2 M qd^2, V(q) (gravity), Q(q, qd, t) (other loads).
    reaction_units : dict[str, str]
    """

    def __init__(self, scene: Scene, point: str, method: str):
        self.scene = scene
        self.point = point
        self.method = method
        kin = _kinematics(scene)
        self._kin = kin
        self.q, self.qd, self.qdd, self.t = kin.q, kin.qd, kin.qdd, kin.t
        self.omega, self.alpha = kin.omega, kin.alpha
        self.unknowns = (self.qdd, *[r.symbol for r in kin.reactions])
        self.reaction_units = {r.name: "N" for r in kin.reactions}
        if method == "generalized_euler":
            self.equations = generalized_euler_equations(kin, point)
        elif method == "mass_center":
            self.equations = mass_center_equations(kin)
        else:
            route = _mechanics_route(scene)
            self.equations = route.equations
            self._lagrange = route
        self._energy = None
        self._system = None
        self._eom = None
        self._reactions = None
        self._numeric = None

    # -- energies (lazy) ----------------------------------------------------
    def _energies(self):
        if self._energy is None:
            if self.method == "lagrange":
                r = self._lagrange
                self._energy = (r.kinetic_energy, r.potential_energy, r.generalized_force, r.mass)
            else:
                self._energy = _energies(self._kin)
        return self._energy

    @property
    def kinetic_energy(self) -> sp.Expr:
        """T(q, qd) = 1/2 M(q) qd^2."""
        return self._energies()[0]

    @property
    def potential_energy(self) -> sp.Expr:
        """V(q), gravity."""
        return self._energies()[1]

    @property
    def generalized_force(self) -> sp.Expr:
        """Q(q, qd, t) of the non-gravity applied loads."""
        return self._energies()[2]

    @property
    def mass(self) -> sp.Expr:
        """M(q), the generalized mass."""
        return self._energies()[3]

    # -- kinematics ------------------------------------------------------------
    def position(self, point: str) -> sp.Matrix:
        """Fixed-frame position of a named point (2x1, in q)."""
        return self._kin.position(point)

    def velocity(self, point: str) -> sp.Matrix:
        """Velocity of the material point (2x1, in q, qd); Eq. 6 for instant points."""
        return self._kin.velocity(point)

    def acceleration(self, point: str) -> sp.Matrix:
        """Acceleration of the material point (2x1, in q, qd, qdd); Eq. 6 for instant points."""
        return self._kin.acceleration(point)

    def mass_center(self) -> sp.Matrix:
        """Composite mass centre in the body frame (Eq. 13)."""
        return self._kin.body.mass_center()

    @property
    def total_mass(self) -> sp.Expr:
        return self._kin.body.total_mass

    def inertia_about(self, point: str) -> sp.Expr:
        """I_P of the whole body about a named point (sum of Eq. 12)."""
        kin = self._kin
        kin._check_point(point)
        p = kin.scene.points.get(point)
        if p is None or p.frame == "body":
            coords = sp.Matrix(p.coords) if p is not None else kin.body.mass_center()
            return kin.body.inertia_about(coords)
        # instant point: its body coordinates are R(-phi) (r_P - r_O)
        coords = kin.R.T * (kin.position(point) - kin.origin)
        return kin.body.inertia_about(coords)

    @property
    def element_mass_centers(self) -> dict[str, sp.Matrix]:
        return self._kin.element_mass_centers()

    # -- the system --------------------------------------------------------
    def linear_system(self) -> tuple[sp.Matrix, sp.Matrix]:
        """(A, b) with A @ unknowns = b, from the equations (linear in the unknowns)."""
        if self._system is None and all(e.row is not None for e in self.equations):
            A = sp.Matrix([list(e.row) for e in self.equations])
            b = sp.Matrix([e.rhs for e in self.equations])
            self._system = (A, b)
        if self._system is None:
            # The equations are affine in the unknowns by construction, so the
            # coefficients follow from substitutions (much cheaper than diff).
            zero = {u: sp.Integer(0) for u in self.unknowns}
            rows_b, rows_A = [], []
            for e in self.equations:
                e0 = e.expr.xreplace(zero)
                rows_b.append(-e0)
                rows_A.append([e.expr.xreplace({**zero, u: sp.Integer(1)}) - e0 for u in self.unknowns])
            self._system = (sp.Matrix(rows_A), sp.Matrix(rows_b))
        return self._system

    @property
    def eom(self) -> sp.Expr:
        """Equation of motion (== 0), reactions eliminated, normalised to
        M qdd + 1/2 M' qd^2 + V' - Q."""
        if self._eom is None:
            if self.method == "lagrange":
                raw = self._lagrange.eom
                self._eom = _tidy(sp.diff(raw, self.qdd)) * self.qdd + _tidy_by_rate(raw.subs(self.qdd, 0), self.qd)
            else:
                A, _ = self.linear_system()
                # Left null vector of the two reaction columns: their cross product.
                u, v = A[:, 1], A[:, 2]
                w = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
                reduced = sp.Add(*[wi * e.expr for wi, e in zip(w, self.equations)])
                reduced = reduced.subs({s: 0 for s in self.unknowns[1:]})
                c = sp.diff(reduced, self.qdd)
                rest = reduced.subs(self.qdd, 0)
                # normalise the qdd coefficient to M(q) (the reduced equation is
                # proportional to Lagrange's: ideal constraints do no work)
                k = _tidy(self.mass / c)
                self._eom = _tidy(self.mass) * self.qdd + _tidy_by_rate(rest * k, self.qd)
        return self._eom

    @property
    def reactions(self) -> dict[str, sp.Expr]:
        """Each reaction as a function of (q, qd, t, params), qdd eliminated."""
        if self._reactions is None:
            # Cramer's rule with division-free (Berkowitz) determinants: the only
            # denominator is det(A), which vanishes exactly where the system is
            # singular (LU pivoting would divide by entries that may vanish at
            # regular configurations, e.g. sin(theta) at theta = 0).
            A, b = self.linear_system()
            det = A.det(method="berkowitz")
            x = []
            for i in range(A.shape[1]):
                Ai = A.copy()
                Ai[:, i] = b
                x.append(Ai.det(method="berkowitz") / det)
            self._reactions = {str(s): x[i] for i, s in enumerate(self.unknowns) if i > 0}
            self._qdd_solution = x[0]
        return self._reactions

    @property
    def qdd_solution(self) -> sp.Expr:
        """theta_ddot as a function of (q, qd, t, params)."""
        self.reactions
        return self._qdd_solution

    def numeric(self) -> NumericModel:
        """The lambdified, vectorised numeric model (built once)."""
        if self._numeric is None:
            self._numeric = NumericModel(self)
        return self._numeric

    def __repr__(self) -> str:
        return f"Derivation(scene={self.scene.name!r}, point={self.point!r}, method={self.method!r})"


def _tidy(expr: sp.Expr) -> sp.Expr:
    """Display clean-up of a derived expression: ``simplify`` when the
    expression is small, else a bounded ``cancel`` (never in solve paths)."""
    try:
        if sp.count_ops(expr) <= 600:
            return sp.simplify(expr)
        return sp.cancel(sp.together(expr))
    except (sp.PolynomialError, ValueError):  # pragma: no cover - defensive
        return expr


def _tidy_by_rate(expr: sp.Expr, qd: sp.Symbol) -> sp.Expr:
    """Display clean-up term by term in powers of theta_dot (trigsimp each
    coefficient; cheaper and more readable than simplifying the whole)."""
    try:
        parts = sp.collect(sp.expand(expr), qd, evaluate=False)
        return sp.Add(*[sp.factor_terms(sp.trigsimp(v)) * k for k, v in parts.items()])
    except (sp.PolynomialError, ValueError):  # pragma: no cover - defensive
        return _tidy(expr)


def _energies(kin: BodyKinematics):
    """T, V, Q and M from the kinematics (used by the Newton-Euler routes)."""
    q, qd = kin.q, kin.qd
    centers = kin.element_mass_centers()
    M_terms = []
    for part in kin.body.parts:
        r_q = sp.diff(centers[part.name], q)
        M_terms.append(part.mass * (r_q[0] ** 2 + r_q[1] ** 2) + part.I_G * kin.dphi**2)
    M = sp.Add(*M_terms)
    T = M * qd**2 / 2
    V_terms = []
    for load in kin.scene.loads:
        if load.kind == "gravity":
            g = sp.Matrix(load.direction) * load.magnitude
            V_terms += [-part.mass * (g.T * centers[part.name])[0] for part in kin.body.parts]
    V = sp.Add(*V_terms)
    forces, couples = applied_loads(kin, include_reactions=False)
    Q_terms = []
    for f in forces:
        if f.kind == "force":
            Q_terms.append((f.force.T * kin.partial_velocity(f.point))[0])
    Q_terms += [c * kin.dphi for _, c in couples]
    return T, V, sp.Add(*Q_terms), M


# ---------------------------------------------------------------------------
def _validate_derive(scene: Scene, point: str | None, method: str) -> str:
    if method not in METHODS:
        raise ValueError(f"`method` must be one of {METHODS}, got {method!r}")
    if not isinstance(scene, Scene):
        raise TypeError(f"`scene` must be a solver.scene.Scene, got {type(scene).__name__}")
    point = scene.default_point if point is None else point
    names = list(scene.points) + (["G"] if "G" not in scene.points else [])
    if point not in names:
        raise SceneError(
            f"{scene_label(scene)}: point {point!r} is not a point of the body (points: {', '.join(names)})"
        )
    return point


def derive(scene: Scene, point: str | None = None, method: str = "generalized_euler") -> Derivation:
    """Derive the equations of ``scene`` about ``point`` by ``method``.

    Parameters
    ----------
    scene : Scene
    point : str, optional
        Reference point P (default ``scene.default_point``); any named point
        or ``"G"`` (the composite mass centre).
    method : {"generalized_euler", "mass_center", "lagrange"}

    Returns
    -------
    Derivation
        Cached per (scene object, point, method).

    Raises
    ------
    ValueError
        Unknown method (the message lists :data:`METHODS`).
    SceneError
        Unknown point, or a scene whose constraints cannot place the body.
    """
    point = _validate_derive(scene, point, method)
    key = (id(scene), point, method)
    hit = _derivation_cache.get(key)
    if hit is not None and hit[0] is scene:
        return hit[1]
    return _remember(_derivation_cache, key, scene, Derivation(scene, point, method))


def solve_instant(scene: Scene, point: str | None = None, method: str = "generalized_euler") -> InstantSolution:
    """Angular acceleration and reactions at the scene's state.

    Returns
    -------
    InstantSolution

    Raises
    ------
    SingularConfigurationError
        Singular or badly conditioned system (condition number > 1e12).
    """
    d = derive(scene, point, method)
    q, qd = scene.state_si()
    from .kinematics import scene_label
    from .period import rim_limits

    for text, g in rim_limits(scene, d.q):
        if float(g.subs(scene.si_values()).subs(d.q, q)) < -1e-12:
            raise InputError(
                f"{scene_label(scene)}: {d.q} = {math.degrees(q):.6g} deg is outside the model: it holds only "
                f"while {text} (there the straight edge meets the surface)"
            )
    res = d.numeric().solve(q, qd, 0.0)
    unknowns = {
        "alpha": Q_(float(res["alpha"]), "rad/s**2"),
        str(d.qdd): Q_(float(res[str(d.qdd)]), "rad/s**2"),
    }
    for name, unit in d.reaction_units.items():
        unknowns[name] = Q_(float(res[name]), unit)
    return InstantSolution(
        unknowns,
        float(res["condition_number"]),
        d.point,
        method,
        theta=Q_(q, "rad"),
        theta_dot=Q_(qd, "rad/s"),
        scene=scene.name,
    )


def _validate_frequency(scene: Scene) -> None:
    if not isinstance(scene, Scene):
        raise TypeError(f"`scene` must be a solver.scene.Scene, got {type(scene).__name__}")


def natural_frequency(scene: Scene, method: str = "generalized_euler") -> FrequencyResult:
    """Small-oscillation natural frequency about the stable equilibrium.

    Parameters
    ----------
    scene : Scene
    method : str
        Route for M(q) and V(q) (all agree).

    Returns
    -------
    FrequencyResult

    Raises
    ------
    NoRestoringError
        No equilibrium with V'' > 0 (including a constant potential, e.g. a
        massless bar on a rolling disk) or no inertia there.

    Notes
    -----
    Gravity only (other loads set aside). The equilibrium q_e solves
    V'(q_e) = 0 with V''(q_e) > 0, searched over q0 +/- 2 pi around the
    scene's state q0 and taken nearest to it (ties: nearest to 0).
    Linearising M qdd + 1/2 M' qd^2 + V' = 0 about q_e gives
    omega_n^2 = V''(q_e) / M(q_e) (cf. Eq. 46 for Example 2).
    """
    _validate_frequency(scene)
    d = derive(scene, None, method)
    label = scene_label(scene)
    values = scene.si_values()
    q = d.q
    V = d.potential_energy.subs(values)
    dV = sp.diff(V, q)
    ddV = sp.diff(dV, q)
    M = d.mass.subs(values)
    stray = (dV.free_symbols | ddV.free_symbols | M.free_symbols) - {q}
    if stray:
        raise SceneError(f"{label}: undefined name(s) {', '.join(sorted(map(str, stray)))}")
    f_dV = sp.lambdify(q, dV, "numpy")
    f_ddV = sp.lambdify(q, ddV, "numpy")
    f_M = sp.lambdify(q, M, "numpy")
    # additive constants (e.g. m g r_d of a rolling disk) do not set the scale of V's variation
    from .period import _drop_constants

    f_V = sp.lambdify(q, _drop_constants(V, q), "numpy")
    q0, _ = scene.state_si()
    grid = np.linspace(q0 - 2 * np.pi, q0 + 2 * np.pi, 2881)
    with np.errstate(all="ignore"):
        g = np.broadcast_to(np.asarray(f_dV(grid), dtype=float), grid.shape)
        h = np.broadcast_to(np.asarray(f_ddV(grid), dtype=float), grid.shape)
        v = np.broadcast_to(np.asarray(f_V(grid), dtype=float), grid.shape)
    gmax = float(np.nanmax(np.abs(g))) if np.any(np.isfinite(g)) else 0.0
    vmax = float(np.nanmax(np.abs(v))) if np.any(np.isfinite(v)) else 0.0
    # V' at round-off level of V's own terms counts as zero (a float cancellation)
    if dV == 0 or gmax <= 1e-13 * vmax:
        raise NoRestoringError(
            f"{label}: no restoring moment: the potential energy does not change with {q} "
            f"(V' = V'' = 0; no mass off the rolling/pivot axis), so there are no small oscillations"
        )
    scale = float(np.nanmax(np.abs(h))) if np.any(np.isfinite(h)) else 0.0
    from scipy.optimize import brentq

    candidates = []
    for i in range(len(grid) - 1):
        a, b = g[i], g[i + 1]
        if not (np.isfinite(a) and np.isfinite(b)):
            continue
        if a < 0 <= b or (a == 0 and b > 0):  # V' from - to +: a minimum of V
            root = grid[i] if a == 0 else brentq(f_dV, grid[i], grid[i + 1], xtol=1e-14, disp=False)
            candidates.append(float(root))
    stable = [r for r in candidates if float(f_ddV(r)) > 1e-12 * scale]
    if candidates and not stable:
        raise NoRestoringError(
            f"{label}: no restoring moment: V'' = 0 at the equilibrium {q} = {candidates[0]:.6g} rad "
            f"(neutral, not stable), so there are no small oscillations"
        )
    if not stable:
        raise NoRestoringError(
            f"{label}: no stable equilibrium (V' = 0 with V'' > 0) within 2 pi of {q} = {q0:.6g} rad: "
            f"gravity gives no restoring moment"
        )
    qe = min(stable, key=lambda r: (round(abs(r - q0), 9), abs(r)))
    k = float(f_ddV(qe))
    m = float(f_M(qe))
    if not (m > 0 and np.isfinite(m)):
        raise NoRestoringError(f"{label}: the generalized mass M({q}) at the equilibrium is {m:.3g}: no inertia")
    w = math.sqrt(k / m)
    return FrequencyResult(
        omega_n=Q_(w, "rad/s"),
        equilibrium=Q_(qe, "rad"),
        stiffness=Q_(k, "N*m/rad"),
        mass=Q_(m, "kg*m**2"),
        period=Q_(2 * math.pi / w, "s"),
    )
