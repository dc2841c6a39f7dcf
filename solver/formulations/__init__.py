"""The equations of a system, by a chosen route, and their elimination.

Routes (``method=``), all linear in the same unknowns (the second derivatives
of the free coordinates, then every reaction):

* ``"generalized_euler"``: per body, Newton (Eq. 1 / Eq. 14 with Eq. 15) and
  the generalized Euler equation about a point P of that body (Eq. 10 / 11);
* ``"mass_center"``: per body, Eqs. (1)-(2) about its mass centre G;
* ``"lagrange"``: Lagrange's equations with multipliers in body coordinates, built
  with ``sympy.physics.mechanics`` and formed as its ``LagrangesMethod`` forms them.

A :class:`Formulation` is cached on its system (cleared with the system).
"""
from __future__ import annotations

import sympy as sp

from ..errors import SceneError
from .newton_euler import NamedEquation, generalized_euler_equations, mass_center_equations

__all__ = ["METHODS", "Formulation", "formulate", "NamedEquation", "resolve_points", "POINT_FREE_METHODS",
           "shown_point", "point_entries", "point_text"]

from ..limits import FORMULATION_METHODS as METHODS  # noqa: E402 - one place, read by --help too


POINT_FREE_METHODS = {
    "mass_center": "mass_center takes each body's moments about its own mass centre G (Eqs. 1-2), "
                   "so it has no reference point P; --point is checked but not used",
    "lagrange": "lagrange writes Lagrange's equations, which have no moment equation and so no "
                "reference point P; --point is checked but not used",
}
"""The routes whose equations use no reference point P, each with what it does instead (printed
beside a ``point`` of null in place of a point the route did not use)."""


def shown_point(system, method: str, point: str | None) -> str | None:
    """The reference point(s) the equations of ``method`` are written about, as the commands print
    them: ``point`` as given, or each body's default (``A``; ``crank:O,rod:A`` for several bodies);
    None for a route that uses no reference point (:data:`POINT_FREE_METHODS`)."""
    if method in POINT_FREE_METHODS:
        return None
    if point is not None:
        return point
    points = resolve_points(system, None)
    return ",".join(f"{b}:{p}" for b, p in points.items()) if len(points) > 1 else next(iter(points.values()))


def point_entries(method: str, shown: str | None) -> dict:
    """The ``point`` entry of a command's JSON (:func:`shown_point`), with a ``point_note`` saying
    what the route does instead when it uses no reference point."""
    if shown is None and method in POINT_FREE_METHODS:
        return {"point": None, "point_note": POINT_FREE_METHODS[method]}
    return {"point": shown}


def point_text(method: str, shown: str | None) -> str:
    """The same for a command's text output: the point, or "none (" the route's note ")"."""
    if shown is None and method in POINT_FREE_METHODS:
        return f"none ({POINT_FREE_METHODS[method]})"
    return str(shown)


ADVISED_POINTS = "; or one the advisor names, as explain --suggest-point lists them: G_<element>, C_<joint>, I(R1,R2)"
"""The places a --point may also name besides a body's named points (:func:`resolve_points`)."""


def resolve_points(system, point: str | None) -> dict[str, str]:
    """The reference point of every body from a ``--point`` value.

    ``point`` is ``None`` (each body's default), ``BODY:POINT`` (that body's
    point; the others keep their defaults), or a bare ``POINT`` (a point name:
    for a one-body system, that body's point; otherwise every body that has a
    point of that name uses it). A name the point advisor gives to a place where no named point
    is (``C_<joint>``, ``BODY:I(R1,R2)``) becomes an instant point of its body first, by the
    worked solution's own rule (:func:`solver.explain.build.add_joint_point`).
    """
    points = {name: body.default_point for name, body in system.bodies.items()}
    if point is None:
        return points
    owner, _, wanted = point.rpartition(":")
    if not any(wanted in b.point_names() for n, b in system.bodies.items() if n == owner or not owner):
        from ..explain.build import add_joint_point  # the advisor's C_<joint> and BODY:I(R1,R2), as explain

        add_joint_point(system, point)
    if ":" in point:
        body, name = point.split(":", 1)
        if body not in system.bodies:
            raise SceneError(f"{system.label}: --point {point}: unknown body {body!r} "
                             f"(bodies: {', '.join(system.bodies)})")
        targets = [body]
    else:
        name = point
        targets = [b for b, body in system.bodies.items() if name in body.point_names()]
        if not targets and len(system.bodies) == 1:
            body = next(iter(system.bodies.values()))
            raise SceneError(f"{system.label}: --point {point}: point {name!r} is not a point of the body "
                             f"{body.name!r} (points: {', '.join(body.point_names())}"
                             f"{_advised_points(system.bodies.values(), name)})")
        if not targets:
            every = sorted({f"{b}:{p}" for b, body in system.bodies.items() for p in body.point_names()})
            raise SceneError(f"{system.label}: --point {point}: no body has a point {name!r} "
                             f"(points: {', '.join(every)}{_advised_points(system.bodies.values(), name)})")
    for body in targets:
        if name not in system.bodies[body].point_names():
            raise SceneError(
                f"{system.label}: --point {point}: point {name!r} is not a point of the body {body!r} "
                f"(points: {', '.join(system.bodies[body].point_names())}"
                f"{_advised_points([system.bodies[body]], name)})"
            )
        points[body] = name
    return points


def _advised_points(bodies, name: str) -> str:
    """The end of a refused ``--point``'s list of points: :data:`ADVISED_POINTS`, or, for the name
    ``G_<element>`` of the only element of one of ``bodies``, that such a body's mass centre is G
    (the advisor names ``G_<element>`` on bodies of several elements only)."""
    alone = [b.name for b in bodies if len(b.elements) == 1 and f"G_{b.elements[0].name}" == name]
    if alone:
        return (f"; {name[2:]} is the only element of {', '.join(alone)}, whose mass centre is G: G_<element> "
                "names an element's mass centre on a body of several elements")
    return ADVISED_POINTS


class Formulation:
    """The equations of ``system`` by ``method`` about ``points`` (body -> point).

    Attributes
    ----------
    unknowns : tuple of sympy.Symbol
        (q_ddot of each free coordinate, then each reaction).
    equations : tuple of NamedEquation
    """

    def __init__(self, system, method: str, points: dict[str, str]):
        self.system = system
        self.method = method
        self.points = dict(points)
        self.unknowns = tuple(system.qdd) + tuple(r.symbol for r in system.reactions)
        if method == "generalized_euler":
            eqs = generalized_euler_equations(system, self.points)
        elif method == "mass_center":
            eqs = mass_center_equations(system)
        else:
            from .lagrange import lagrange_equations

            eqs = lagrange_equations(system)
        self.equations = tuple(eqs)
        self._system_matrices = None
        self._numeric = None

    def linear_system(self) -> tuple[sp.Matrix, sp.Matrix]:
        """(A, b) with A @ unknowns = b. The equations are affine in the
        unknowns by construction, so coefficients follow by substitution."""
        if self._system_matrices is None:
            zero = {u: sp.Integer(0) for u in self.unknowns}
            rows_A, rows_b = [], []
            for e in self.equations:
                coefficients, rest = _affine_parts(e.expr, self.unknowns, zero)
                rows_b.append(-rest)
                rows_A.append(coefficients)
            self._system_matrices = (sp.Matrix(rows_A), sp.Matrix(rows_b))
        return self._system_matrices

    def numeric(self):
        """The lambdified, vectorised model (built once)."""
        if self._numeric is None:
            from ..analyses.instant import NumericModel

            self._numeric = NumericModel(self)
        return self._numeric

    def __repr__(self) -> str:
        return f"Formulation({self.system.name!r}, method={self.method!r}, points={self.points})"


def _coefficients(expr, unknowns, zero) -> list:
    """The coefficient of each unknown in ``expr``, which is affine in them (:func:`_affine_parts`)."""
    return _affine_parts(expr, unknowns, zero)[0]


def _affine_parts(expr, unknowns, zero) -> tuple[list, sp.Expr]:
    """(the coefficient of each unknown, ``expr.xreplace(zero)``) of ``expr``, which is affine in
    the unknowns (``zero``: each unknown -> 0).

    Term by term: a term that is a product with the unknown as a plain factor
    (and no other unknown) contributes the product of its other factors; any
    other term t contributes t(u = 1, others = 0) - t(all = 0), exact for an
    affine term and cheaper than substituting into the whole expression. The
    rest is the sum of the terms with the unknowns set to 0, in their order: the
    sum ``xreplace`` rebuilds, without a second walk over the terms free of them."""
    coef: dict = {u: [] for u in unknowns}
    rest = []
    for term in sp.Add.make_args(expr):
        present = [u for u in unknowns if term.has(u)]
        if not present:
            rest.append(term)
            continue
        if len(present) == 1 and term.is_Mul and present[0] in term.args:
            u = present[0]
            factors = list(term.args)
            factors.remove(u)
            if not any(f.has(u) for f in factors):
                coef[u].append(sp.Mul(*factors))
                rest.append(sp.Integer(0))  # (the product with a factor 0)
                continue
        t0 = term.xreplace(zero)
        rest.append(t0)
        for u in present:
            coef[u].append(term.xreplace({**zero, u: sp.Integer(1)}) - t0)
    return [sp.Add(*coef[u]) for u in unknowns], sp.Add(*rest)


def formulate(system, method: str = "generalized_euler", point: str | None = None) -> Formulation:
    """The (cached) formulation of ``system`` by ``method`` about ``point``.

    Raises
    ------
    ValueError
        Unknown method (the message lists :data:`METHODS`).
    SceneError
        Unknown point.
    """
    if method not in METHODS:
        raise ValueError(f"`method` must be one of {METHODS}, got {method!r}")
    system.validate()
    points = resolve_points(system, point)
    key = ("formulation", method, tuple(sorted(points.items())) if method == "generalized_euler" else None)
    return system._memo(key, lambda: Formulation(system, method, points))
