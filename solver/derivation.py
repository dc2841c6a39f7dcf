"""The one-degree-of-freedom view of the multibody core, and the public entry points.

``derive`` returns a :class:`Derivation`: the equations of a system (a
:class:`~solver.model.system.System`, or a one-body
:class:`~solver.scene.Scene`, converted once and cached on it) by a route
about a point, with the symbolic results the one-degree-of-freedom analyses
(period, friction, fidelity, the report) use: the equation of motion
normalised to ``M(q) qdd + 1/2 M'(q) qd^2 + V'(q) - Q(q, qd, t) == 0`` (T =
1/2 M qd^2 the kinetic energy, V the potential of gravity and springs, Q the
generalized force of the other loads), the reactions in closed form, the
energies. Everything is computed by :mod:`solver.formulations` and
:mod:`solver.analyses` on the System; this module adds no second code path.

Routes (``method=``): ``"generalized_euler"`` (Newton + Eq. 10/11 about P),
``"mass_center"`` (Eqs. 1-2), ``"lagrange"`` (Lagrange's equations with
multipliers, sympy.physics.mechanics).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Mapping

import numpy as np
import pint
import sympy as sp

from .analyses.instant import CONDITION_LIMIT, InstantSolution, NumericModel, State
from .analyses.instant import solve_instant as _solve_system
from .errors import InputError, NoRestoringError, SceneError, SingularConfigurationError
from .kept import Kept
from .formulations import METHODS, NamedEquation, formulate
from .io.convert import system_from_scene
from .display import expanded
from .model.system import System, derivative, second_derivative
from .scene import Scene
from .strprint import lambdify
from .units import Q_

__all__ = [
    "METHODS",
    "CONDITION_LIMIT",
    "Derivation",
    "NamedEquation",
    "InstantSolution",
    "FrequencyResult",
    "as_system",
    "derive",
    "solve_instant",
    "natural_frequency",
]


def as_system(scene) -> System:
    """The System of a System or a one-body Scene (converted once, cached on the scene)."""
    if isinstance(scene, System):
        return scene
    if isinstance(scene, Scene):
        return system_from_scene(scene)
    raise TypeError(f"`scene` must be a solver.model.system.System or solver.scene.Scene, got {type(scene).__name__}")


def scene_label(scene) -> str:
    return as_system(scene).label


@dataclass
class FrequencyResult:
    """Small oscillations about the stable equilibrium.

    Attributes
    ----------
    omega_n : pint.Quantity
        Natural frequency, sqrt(V''(q_e) / M(q_e)). [rad/s]
    equilibrium : pint.Quantity
        q_e with V'(q_e) = 0, V''(q_e) > 0. [rad, or m for a length coordinate]
    stiffness : pint.Quantity
        V''(q_e). [N*m/rad, or N/m]
    mass : pint.Quantity
        M(q_e), the generalized mass. [kg*m**2, or kg]
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
            **{name: {"value": float(q.to(unit).magnitude), "unit": unit}
               for name, q, unit in zip(("equilibrium", "stiffness", "mass"), (self.equilibrium, self.stiffness, self.mass),
                                        _FREQUENCY_UNITS["length" if self.equilibrium.check("[length]") else "angle"])},
        }


def berkowitz_det(A: sp.Matrix) -> sp.Expr:
    """``A.det(method="berkowitz")``, remembered per process (the last 256, a :class:`solver.kept.Kept`): a
    scene loaded again (a command after another, each test of a suite) gives the same matrices, and
    their division-free determinants are most of a derivation's cost. The key is the matrix's
    entries (sympy objects, equal only when structurally the same) and the domain they are held in
    (matrices compare equal across domains)."""
    key = (A.as_immutable(), A._rep.domain)  # noqa: SLF001 - the domain has no public name
    return _DETERMINANTS.get(key, lambda: A.det(method="berkowitz"))


_DETERMINANTS = Kept(256)


class _OneDofNumeric:
    """The numeric model of a one-coordinate system, called with scalar or array q, qd."""

    def __init__(self, model: NumericModel, system: System):
        self.model = model
        self.system = system
        self.names = model.names
        self.n = model.n
        body = next(iter(system.bodies)) if len(system.bodies) == 1 else None
        c = system.free[0]
        self._alpha = None
        if body is not None:
            al = system.alpha(body)
            values = system.si_values()
            params = sorted(values, key=str)
            self._alpha = lambdify((c.q, c.qd, c.qdd, system.t, *params), al, "numpy")
            self._pv = [values[p] for p in params]

    def matrices(self, q, qd, t=0.0):
        return self.model.matrices([q], [qd], t)

    def condition_number(self, A):
        from .analyses.instant import condition_numbers

        return condition_numbers(A)

    def solve(self, q, qd, t=0.0):
        res = self.model.solve([q], [qd], t)
        if self._alpha is not None:
            qdd = res[self.names[0]]
            with np.errstate(all="ignore"):
                res["alpha"] = np.broadcast_to(np.asarray(self._alpha(np.asarray(q, float), np.asarray(qd, float), qdd, t, *self._pv), float), np.shape(qdd))
        return res

    def qdd(self, q, qd, t=0.0):
        return self.solve(q, qd, t)[self.names[0]]


class Derivation:
    """The equations of one system by one route about one point (see the module docstring).

    Attributes
    ----------
    scene : Scene or System
        What was derived.
    system : System
    point : str
    method : str
    q, qd, qdd, t : sympy.Symbol
        The (single) free coordinate's symbols and time.
    unknowns : tuple of sympy.Symbol
        (qdd, *reactions).
    equations : tuple of NamedEquation
    omega, alpha : sympy.Expr
        Of the (single) body.
    reaction_units : dict[str, str]
    """

    def __init__(self, scene, point: str | None, method: str):
        system = as_system(scene)
        self.scene = scene
        self.system = system
        self.formulation = formulate(system, method, point)
        self.point = point if point is not None else next(iter(self.formulation.points.values()))
        self.method = method
        self.unknowns = self.formulation.unknowns
        self.equations = self.formulation.equations
        self.t = system.t
        self.reaction_units = {r.name: r.unit for r in system.reactions}
        if len(system.free) == 1:
            c = system.free[0]
            self.q, self.qd, self.qdd = c.q, c.qd, c.qdd
        else:
            self.q = self.qd = self.qdd = None
        self._body = next(iter(system.bodies)) if len(system.bodies) == 1 else None
        self._cache: dict = {}

    def _one_dof(self, what: str):
        if self.q is None:
            raise InputError(f"{self.system.label}: {what} needs one degree of freedom; this system has "
                             f"{len(self.system.free)} coordinates")
        if self.system.closure:
            raise InputError(f"{self.system.label}: {what} needs a system without closure constraints")

    def _memo(self, key, build):
        if key not in self._cache:
            self._cache[key] = build()
        return self._cache[key]

    # -- one body -------------------------------------------------------------------------
    def _only_body(self) -> str:
        if self._body is None:
            raise InputError(f"{self.system.label}: this accessor needs a one-body system")
        return self._body

    @property
    def omega(self):
        return self.system.omega(self._only_body())

    @property
    def alpha(self):
        return self.system.alpha(self._only_body())

    def position(self, point: str) -> sp.Matrix:
        return self.system.point_position(self._only_body(), point)

    def velocity(self, point: str) -> sp.Matrix:
        return self.system.point_velocity(self._only_body(), point)

    def acceleration(self, point: str) -> sp.Matrix:
        return self.system.point_acceleration(self._only_body(), point)

    def mass_center(self) -> sp.Matrix:
        return self.system.bodies[self._only_body()].mass_center()

    @property
    def total_mass(self):
        return self.system.bodies[self._only_body()].total_mass

    def inertia_about(self, point: str) -> sp.Expr:
        """I_P of the body about a named point (Eq. 12), instant points included."""
        s, b = self.system, self._only_body()
        body = s.bodies[b]
        if s.is_body_point(b, point):
            return body.inertia_about(body.body_coords(point))
        rel = (s.point_position(b, point) - s.origin(b))
        phi = s.angle(b)
        coords = sp.Matrix([[sp.cos(phi), sp.sin(phi)], [-sp.sin(phi), sp.cos(phi)]]) * rel
        return body.inertia_about(coords)

    @property
    def element_mass_centers(self) -> dict[str, sp.Matrix]:
        b = self._only_body()
        return {e.name: self.system.body_point(b, e.mass_center) for e in self.system.bodies[b].elements}

    # -- energies ---------------------------------------------------------------------------
    @property
    def kinetic_energy(self):
        return self.system.kinetic_energy()

    @property
    def potential_energy(self):
        return self.system.potential_energy()

    @property
    def generalized_force(self):
        self._one_dof("the generalized force")
        return self.system.generalized_forces()[0]

    @property
    def mass(self):
        """M(q): T = 1/2 M qd^2."""
        self._one_dof("the generalized mass")
        return self._memo("mass", lambda: expanded(second_derivative(self.kinetic_energy, self.qd)))

    # -- the system ---------------------------------------------------------------------------
    def linear_system(self):
        return self.formulation.linear_system()

    @property
    def eom(self) -> sp.Expr:
        """M qdd + 1/2 M' qd^2 + V' - Q (== 0), reactions eliminated (tidied for display)."""
        self._one_dof("the scalar equation of motion")

        def build():
            from .analyses.eom import equations_of_motion

            raw = equations_of_motion(self.formulation)[0]
            c = derivative(raw, self.qdd)
            rest = raw.xreplace({self.qdd: 0})
            return _tidy(c) * self.qdd + _tidy_by_rate(rest, self.qd)
        return self._memo("eom", build)

    @property
    def reactions(self) -> dict[str, sp.Expr]:
        """Each reaction as a function of (q, qd, t, params), qdd eliminated.

        Cramer's rule with division-free (Berkowitz) determinants: the only
        denominator is det(A), which vanishes exactly where the system is
        singular (LU pivoting could divide by entries that vanish at regular
        configurations, such as sin(theta) at theta = 0).
        """
        def build():
            A, b = self.linear_system()
            structured = self._solution_by_structure(A, b)
            if structured is not None:
                return structured
            det = berkowitz_det(A)
            x = []
            for i in range(A.shape[1]):
                Ai = A.copy()
                Ai[:, i] = b
                x.append(berkowitz_det(Ai) / det)
            return {str(s): x[i] for i, s in enumerate(self.unknowns)}
        sol = self._memo("solution", build)
        n = len(self.system.free)
        return {k: v for i, (k, v) in enumerate(sol.items()) if i >= n}

    def _solution_by_structure(self, A, b):
        """The solution from the structure of a one-freedom system: qdd = -f / M from the equation
        of motion M qdd + f = 0, then each reaction from a row that holds it alone among the
        reactions not yet found, with a pivot free of the state (a parameter or a number, never
        zero at a regular configuration). None when the rows do not allow that (then Cramer).

        Each reaction r = c0 + c1 qdd becomes (c0 M - c1 f) / M: the only denominator is the
        generalized mass M > 0, like det(A) of Cramer's rule but far cheaper to form and display.
        """
        if self.q is None or self.system.closure or A.shape[0] != A.shape[1]:
            return None
        state = {self.q, self.qd, self.t}
        n = A.shape[1]
        found: dict[int, sp.Expr] = {}  # column -> expression in qdd and earlier reactions
        used: set[int] = set()
        while len(found) < n - 1:
            progress = False
            for i in range(A.shape[0]):
                if i in used:
                    continue
                open_cols = [j for j in range(1, n) if j not in found and A[i, j] != 0]
                if len(open_cols) != 1:
                    continue
                j = open_cols[0]
                pivot = A[i, j]
                if pivot.free_symbols & state:
                    continue
                rest = b[i] - A[i, 0] * self.qdd - sp.Add(*[A[i, k] * found[k] for k in found])
                found[j] = expanded(rest / pivot)
                used.add(i)
                progress = True
            if not progress:
                return None
        raw = self._raw_eom()
        M = raw.coeff(self.qdd)
        f = expanded(raw - M * self.qdd)
        out = {str(self.qdd): -f / M}
        parts = {}
        for j in range(1, n):
            c1 = found[j].coeff(self.qdd)
            c0 = expanded(found[j] - c1 * self.qdd)
            num = expanded(c0 * M - c1 * f)
            out[str(self.unknowns[j])] = num / M
            parts[str(self.unknowns[j])] = (num, M)
        self._cache["reaction_parts"] = parts
        return out

    @property
    def reaction_fractions(self) -> dict[str, tuple[sp.Expr, sp.Expr]] | None:
        """(numerator, denominator) of each reaction when the structured solve applied, else None."""
        self.reactions
        return self._cache.get("reaction_parts")

    def _raw_eom(self) -> sp.Expr:
        from .analyses.eom import equations_of_motion

        return expanded(equations_of_motion(self.formulation)[0])

    @property
    def qdd_solution(self) -> sp.Expr:
        self._one_dof("qdd_solution")
        self.reactions
        return self._cache["solution"][str(self.qdd)]

    def numeric(self):
        """The vectorised numeric model (one coordinate: called with q, qd arrays)."""
        model = self.formulation.numeric()
        if self.q is None:
            return model
        return self._memo("numeric", lambda: _OneDofNumeric(model, self.system))

    def __repr__(self) -> str:
        return f"Derivation(scene={self.system.name!r}, point={self.point!r}, method={self.method!r})"


def derive(scene, point: str | None = None, method: str = "generalized_euler") -> Derivation:
    """Derive the equations of ``scene`` about ``point`` by ``method``.

    Parameters
    ----------
    scene : System or Scene
    point : str, optional
        Reference point P: ``BODY:POINT``, or a point name (for a one-body
        system any named point or ``"G"``); default each body's reference point.
    method : {"generalized_euler", "mass_center", "lagrange"}

    Returns
    -------
    Derivation
        Cached on the system (cleared by ``System.reset()``).

    Raises
    ------
    ValueError
        Unknown method (the message lists :data:`METHODS`).
    SceneError
        Unknown point, or a system whose joints cannot place its bodies.
    """
    from .formulations import resolve_points

    system = as_system(scene)
    formulate(system, method, point)  # validates the method, the model and the point
    points = tuple(sorted(resolve_points(system, point).items()))
    return system._memo(("derivation", points, method), lambda: Derivation(scene, point, method))


def solve_instant(scene, point: str | None = None, method: str = "generalized_euler") -> InstantSolution:
    """Every acceleration and reaction at the scene's state (see :func:`solver.analyses.instant.solve_instant`).

    Examples
    --------
    Paper Example 1 at release (Eq. 30; the paper prints alpha with the unit rad/s):

    >>> from solver.io.scenes import load_system
    >>> sol = solve_instant(load_system("data/scenes/sliding_bar.toml"), "A")
    >>> from reports.published import published_example1_alpha  # doctest: +SKIP
    """
    return _solve_system(as_system(scene), point, method)


def _tidy(expr: sp.Expr) -> sp.Expr:
    """Display form of a derived coefficient, from its structure (never in solve paths):
    numerator and denominator reduced modulo sin**2 + cos**2 = 1 (:func:`solver.display.tidy`),
    not a generic ``simplify``."""
    from .display import tidy

    return tidy(expr)


def _tidy_by_rate(expr: sp.Expr, qd: sp.Symbol, *more: sp.Symbol) -> sp.Expr:
    """Display form term by term in powers of theta_dot, each coefficient tidied on its own; with
    ``more`` rates, by the powers of each in turn (a kinetic energy: by qd1**2, qd1*qd2, ...)."""
    try:
        parts = {sp.S.One: expanded(expr)}
        for x in (qd, *more):
            parts = {k * k2: v2 for k, v in parts.items() for k2, v2 in _by_powers(v, x).items()}
        return sp.Add(*[_tidy(v) * k for k, v in parts.items()])
    except (sp.PolynomialError, ValueError):  # pragma: no cover - defensive
        return _tidy(expr)


def _by_powers(expr: sp.Expr, x: sp.Symbol) -> dict:
    """``sympy.collect(expr, x, evaluate=False)`` of an expanded polynomial in ``x``: {x**k: the sum
    of its terms divided by x**k}, in one pass over the terms (collect parses every factor of
    every term generically). Falls back to ``collect`` when ``x`` appears other than as a plain
    factor to a positive integer power (inside a function, say)."""
    groups: dict = {}
    for t in sp.Add.make_args(expr):
        k = 0
        for f in sp.Mul.make_args(t):
            base, exp = f.as_base_exp()
            if base == x and exp.is_Integer and exp > 0:
                k = int(exp)
            elif f.has(x):
                return sp.collect(expr, x, evaluate=False)
        groups.setdefault(k, []).append(t / x**k if k else t)
    return {(x**k if k else sp.S.One): sp.Add(*terms) for k, terms in groups.items()}


def natural_frequency(scene, method: str = "generalized_euler", one_dof=None) -> FrequencyResult:
    """Small-oscillation natural frequency of a one-coordinate system about its stable equilibrium.

    Parameters
    ----------
    scene : System or Scene
    method : str
        Route for M(q) and the loads (all agree).
    one_dof : solver.period.OneDofSystem, optional
        The scene's one-degree-of-freedom model when the caller has it (its compiled functions
        are then shared with the caller's period and friction work); default: built here.

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
    Every load that depends on position only is included: the effective
    potential V_eff = V - int Q dq of :class:`solver.period.OneDofSystem`, whose
    equilibrium search (:func:`solver.period.find_equilibrium`, the one place
    it is done) ``period`` uses too, so the two agree. Linearising
    M qdd + 1/2 M' qd^2 + V_eff' = 0 about q_e gives
    omega_n^2 = V_eff''(q_e) / M(q_e) (cf. Eq. 46 for Example 2).
    """
    from .period import OneDofSystem, find_equilibrium

    system = as_system(scene)
    if one_dof is None:
        d = derive(system, None, method)
        one_dof = OneDofSystem.from_derivation(d, reactions=False)  # M and V only: no reactions needed
    eq = find_equilibrium(one_dof, near=system.free[0].value)
    w = eq.omega
    q_unit, k_unit, m_unit = _FREQUENCY_UNITS[system.free[0].kind]
    return FrequencyResult(
        omega_n=Q_(w, "rad/s"),
        equilibrium=Q_(eq.q, q_unit),
        stiffness=Q_(eq.stiffness, k_unit),
        mass=Q_(eq.mass, m_unit),
        period=Q_(2 * math.pi / w, "s"),
    )


# coordinate kind -> units of (q_e, V'' [a stiffness], M [a generalized mass]), SI
_FREQUENCY_UNITS = {"angle": ("rad", "N*m/rad", "kg*m**2"), "length": ("m", "N/m", "kg")}
