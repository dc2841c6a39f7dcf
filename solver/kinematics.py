"""Planar kinematics of the scene's body as functions of the coordinate theta.

The body's orientation phi(theta) is given by the scene; its translation is
fixed by the constraints (two rails, a rolling element, a pivot) or by an
explicit position. Every position is a sympy 2x1 Matrix in the fixed frame,
in theta and the parameters; velocities and accelerations follow by the chain
rule (d/dt = theta_dot d/dtheta), and for "instant" points by the rigid-body
relation (paper Eqs. 6 and 15).

Expressions are kept unsimplified on purpose: they are built small and are
only simplified for display.
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .bodies import ROUND_KINDS, CompositeBody
from .errors import SceneError
from .scene import Scene

__all__ = ["rotation", "cross_k", "k_cross", "ReactionForce", "BodyKinematics", "scene_label"]

# A rail pair whose normals' cross product is below this (|sin| of the angle
# between the rails) cannot place the body: the 2x2 system is singular.
PARALLEL_TOLERANCE = 1e-9


def scene_label(scene: Scene) -> str:
    """The name used in messages: the scene's file if known, else its name."""
    return str(scene.source) if scene.source is not None else f"scene {scene.name!r}"


def rotation(phi: sp.Expr) -> sp.Matrix:
    """2x2 rotation matrix R(phi) (body frame -> fixed frame)."""
    c, s = sp.cos(phi), sp.sin(phi)
    return sp.Matrix([[c, -s], [s, c]])


def cross_k(a: sp.Matrix, b: sp.Matrix) -> sp.Expr:
    """k-component of a x b for in-plane vectors."""
    return a[0] * b[1] - a[1] * b[0]


def k_cross(w: sp.Expr, r: sp.Matrix) -> sp.Matrix:
    """(w k) x r for an in-plane vector r."""
    return sp.Matrix([-w * r[1], w * r[0]])


def _unit(angle: sp.Expr) -> sp.Matrix:
    return sp.Matrix([sp.cos(angle), sp.sin(angle)])


def _left_normal(angle: sp.Expr) -> sp.Matrix:
    return sp.Matrix([-sp.sin(angle), sp.cos(angle)])


@dataclass(frozen=True)
class ReactionForce:
    """One reaction unknown: symbol, line of action and where it acts.

    Attributes
    ----------
    name : str
    symbol : sympy.Symbol
    constraint : str
        Name of the constraint that brings it.
    direction : sympy.Matrix
        2x1 fixed-frame unit vector; the force is ``symbol * direction``.
    at : str
        Name of the point it acts at (a scene point, or ``"<constraint>.contact"``).
    position : sympy.Matrix
        2x1 fixed-frame position of the application point, in theta.
    """

    name: str
    symbol: sp.Symbol
    constraint: str
    direction: sp.Matrix
    at: str
    position: sp.Matrix


class BodyKinematics:
    """Placement, positions, velocities and accelerations of the body.

    Parameters
    ----------
    scene : solver.scene.Scene

    Attributes
    ----------
    body : solver.bodies.CompositeBody
    q, qd, qdd, t : sympy.Symbol
    phi, omega, alpha : sympy.Expr
        Orientation and its first and second time derivatives
        (k-components). alpha is linear in qdd.
    origin : sympy.Matrix
        Fixed-frame position of the body frame's origin, in theta.
    R : sympy.Matrix
        Rotation body -> fixed frame.
    reactions : tuple of ReactionForce

    Raises
    ------
    SceneError
        Unknown points or elements in constraints, an unsupported constraint
        combination, a non-round rolling element, or parallel rails.
    """

    def __init__(self, scene: Scene):
        self.scene = scene
        self.label = scene_label(scene)
        self.body = CompositeBody(scene.elements)
        self.q, self.qd, self.qdd, self.t = scene.q, scene.qd, scene.qdd, scene.t
        self.phi = sp.sympify(scene.orientation)
        self.dphi = sp.diff(self.phi, self.q)
        self.ddphi = sp.diff(self.dphi, self.q)
        self.omega = self.dphi * self.qd
        self.alpha = self.ddphi * self.qd**2 + self.dphi * self.qdd
        self.R = rotation(self.phi)
        self._cache: dict = {}
        self._validate()
        self.origin = self._place()
        self.reactions = self._reactions()
        if scene.position is not None:
            self._check_position_consistent()

    # -- validation -------------------------------------------------------
    def _validate(self) -> None:
        scene = self.scene
        for c in scene.constraints:
            if c.kind in ("rail", "pivot"):
                if c.point not in scene.points:
                    raise SceneError(
                        f"{self.label}: constraint {c.name!r}: point {c.point!r} is not a point of "
                        f"the body (points: {', '.join(scene.points)})"
                    )
                if scene.points[c.point].frame != "body":
                    raise SceneError(
                        f"{self.label}: constraint {c.name!r}: point {c.point!r} must be a body-frame point"
                    )
            elif c.kind == "rolling":
                element = self._element(c.element, c.name)
                if element.kind not in ROUND_KINDS:
                    raise SceneError(
                        f"{self.label}: constraint {c.name!r}: element {c.element!r} is a {element.kind}; "
                        f"only {', '.join(ROUND_KINDS)} can roll"
                    )
            else:
                raise SceneError(
                    f"{self.label}: constraint {c.name!r}: kind must be one of rail, rolling, pivot, got {c.kind!r}"
                )
            expected = {"rail": 1, "rolling": 2, "pivot": 2}[c.kind]
            if len(c.reactions) != expected:
                raise SceneError(
                    f"{self.label}: constraint {c.name!r} ({c.kind}) needs {expected} reaction name(s), "
                    f"got {len(c.reactions)}"
                )
        names = scene.reaction_names()
        if len(names) != 2:
            raise SceneError(
                f"{self.label}: the body has one degree of freedom, so its constraints must bring exactly "
                f"2 reaction unknowns (two rails, one rolling element, or one pivot); got {len(names)}: "
                f"{', '.join(names) or 'none'}"
            )
        clash = (set(names) & set(scene.parameters)) | {n for n in names if names.count(n) > 1}
        if clash:
            raise SceneError(
                f"{self.label}: reaction name(s) {', '.join(sorted(clash))} repeat or clash with parameter names"
            )

    def _element(self, name, where):
        for e in self.scene.elements:
            if e.name == name:
                return e
        raise SceneError(
            f"{self.label}: constraint {where!r}: element {name!r} is not an element of the body "
            f"(elements: {', '.join(e.name for e in self.scene.elements)})"
        )

    # -- placement ---------------------------------------------------------
    def _place(self) -> sp.Matrix:
        scene = self.scene
        R = self.R
        if scene.position is not None:
            name, where = scene.position
            if name not in scene.points or scene.points[name].frame != "body":
                raise SceneError(
                    f"{self.label}: position: {name!r} is not a body-frame point of the body "
                    f"(points: {', '.join(scene.points)})"
                )
            return sp.Matrix(where) - R * scene.points[name].coords
        kinds = sorted(c.kind for c in scene.constraints)
        if kinds == ["pivot"]:
            c = scene.constraints[0]
            return sp.Matrix(c.origin) - R * scene.points[c.point].coords
        if kinds == ["rolling"]:
            c = scene.constraints[0]
            element = self._element(c.element, c.name)
            r = element.dims["radius"]
            # Rolling without slip: the contact point advances by -r dphi
            # along the surface direction d (a clockwise roll moves along +d).
            s = c.contact_at_zero - r * (self.phi - self.phi.subs(self.q, 0))
            center = sp.Matrix(c.origin) + s * _unit(c.angle) + r * _left_normal(c.angle)
            return center - R * sp.Matrix(element.center)
        if kinds == ["rail", "rail"]:
            return self._place_on_rails(*scene.constraints)
        raise SceneError(
            f"{self.label}: unsupported constraint set ({', '.join(kinds)}): use two rails, one rolling "
            f"element, one pivot, or an explicit position"
        )

    def _place_on_rails(self, c1, c2) -> sp.Matrix:
        # n_i . (r_O + R p_i - o_i) = 0 for both rails: 2x2 linear in r_O.
        n1, n2 = _left_normal(c1.angle), _left_normal(c2.angle)
        det = cross_k(n1, n2)
        det_value = det.subs(self.scene.si_values()) if det.free_symbols else det
        try:
            parallel = abs(float(det_value)) < PARALLEL_TOLERANCE
        except TypeError:  # unresolved symbols: treat as non-parallel
            parallel = False
        if parallel:
            raise SceneError(
                f"{self.label}: impossible geometry: rails {c1.name!r} and {c2.name!r} are parallel "
                f"(angles {c1.angle} and {c2.angle}), they cannot fix the body's position"
            )
        p1 = self.R * self.scene.points[c1.point].coords
        p2 = self.R * self.scene.points[c2.point].coords
        rhs1 = (n1.T * (sp.Matrix(c1.origin) - p1))[0]
        rhs2 = (n2.T * (sp.Matrix(c2.origin) - p2))[0]
        # Cramer's rule for [n1^T; n2^T] r_O = [rhs1; rhs2].
        x = (rhs1 * n2[1] - n1[1] * rhs2) / det
        y = (n1[0] * rhs2 - rhs1 * n2[0]) / det
        return sp.Matrix([x, y])

    def _check_position_consistent(self) -> None:
        """An explicit position must satisfy every constraint (checked at three angles)."""
        q0, _ = self.scene.state_si()
        values = self.scene.si_values()
        for c in self.scene.constraints:
            if c.kind == "rail":
                res = [(_left_normal(c.angle).T * (self.position(c.point) - sp.Matrix(c.origin)))[0]]
            elif c.kind == "pivot":
                res = list(self.position(c.point) - sp.Matrix(c.origin))
            else:
                element = self._element(c.element, c.name)
                r = element.dims["radius"]
                center = self.body_point(sp.Matrix(element.center))
                n, d = _left_normal(c.angle), _unit(c.angle)
                res = [(n.T * (center - sp.Matrix(c.origin)))[0] - r,
                       (d.T * sp.diff(center, self.q))[0] + r * self.dphi]  # no slip
            for q in (q0, q0 + 0.3, q0 - 0.7):
                for e in res:
                    try:
                        v = float(sp.sympify(e).subs(values).subs(self.q, q))
                    except TypeError:
                        continue  # unresolved symbols: cannot check
                    if abs(v) > 1e-9:
                        raise SceneError(
                            f"{self.label}: position of {self.scene.position[0]!r} violates constraint "
                            f"{c.name!r} ({c.kind}) at {self.q} = {q:.6g} rad (residual {v:.3g})"
                        )

    def _reactions(self) -> tuple[ReactionForce, ...]:
        out = []
        for c in self.scene.constraints:
            syms = [sp.Symbol(n, real=True) for n in c.reactions]
            if c.kind == "rail":
                pos = self.position(c.point)
                out.append(ReactionForce(c.reactions[0], syms[0], c.name, _left_normal(c.angle), c.point, pos))
            elif c.kind == "pivot":
                pos = self.position(c.point)
                for name, sym, d in zip(c.reactions, syms, (sp.Matrix([1, 0]), sp.Matrix([0, 1]))):
                    out.append(ReactionForce(name, sym, c.name, d, c.point, pos))
            else:  # rolling: friction along d, normal along n, at the contact point
                pos = self.contact_position(c)
                for name, sym, d in zip(c.reactions, syms, (_unit(c.angle), _left_normal(c.angle))):
                    out.append(ReactionForce(name, sym, c.name, d, f"{c.name}.contact", pos))
        return tuple(out)

    def contact_position(self, constraint) -> sp.Matrix:
        """Fixed-frame position of a rolling element's contact point."""
        element = self._element(constraint.element, constraint.name)
        center = self.body_point(sp.Matrix(element.center))
        return center - element.dims["radius"] * _left_normal(constraint.angle)

    # -- points ------------------------------------------------------------
    def body_point(self, coords: sp.Matrix) -> sp.Matrix:
        """Fixed-frame position of the body point with body coordinates ``coords``."""
        return self.origin + self.R * sp.Matrix(coords)

    def has_point(self, name: str) -> bool:
        return name in self.scene.points or name == "G"

    def _check_point(self, name: str) -> None:
        if not self.has_point(name):
            raise SceneError(
                f"{self.label}: point {name!r} is not a point of the body "
                f"(points: {', '.join(list(self.scene.points) + (['G'] if 'G' not in self.scene.points else []))})"
            )

    def position(self, name: str) -> sp.Matrix:
        """Fixed-frame position of a named point ("G" = composite mass centre if not named)."""
        self._check_point(name)
        key = ("pos", name)
        if key not in self._cache:
            if name in self.scene.points:
                p = self.scene.points[name]
                if p.frame == "instant":
                    self._check_point(p.relative_to)
                    val = self.position(p.relative_to) + sp.Matrix(p.coords)
                else:
                    val = self.body_point(p.coords)
            else:
                val = self.body_point(self.body.mass_center())
            self._cache[key] = val
        return self._cache[key]

    def _instant_offset(self, name: str):
        p = self.scene.points.get(name)
        if p is not None and p.frame == "instant":
            return p.relative_to, sp.Matrix(p.coords)
        return None

    def velocity(self, name: str) -> sp.Matrix:
        """Velocity of the material body point at ``name`` (Eq. 6 for instant points)."""
        self._check_point(name)
        key = ("vel", name)
        if key not in self._cache:
            inst = self._instant_offset(name)
            if inst is not None:
                ref, c = inst
                val = self.velocity(ref) + k_cross(self.omega, c)
            else:
                val = sp.diff(self.position(name), self.q) * self.qd
            self._cache[key] = val
        return self._cache[key]

    def acceleration(self, name: str) -> sp.Matrix:
        """Acceleration of the material body point at ``name`` (Eq. 6 for instant points)."""
        a0, a1 = self.acceleration_parts(name)
        return a0 + a1 * self.qdd

    def acceleration_parts(self, name: str) -> tuple[sp.Matrix, sp.Matrix]:
        """(a0, a1) with acceleration = a0 + a1 * theta_ddot (a0 holds the theta_dot^2 terms)."""
        self._check_point(name)
        key = ("acc", name)
        if key not in self._cache:
            inst = self._instant_offset(name)
            if inst is not None:
                ref, c = inst
                a0, a1 = self.acceleration_parts(ref)
                # Eq. (6): a = a_ref + alpha x c - omega^2 c, alpha = ddphi qd^2 + dphi qdd
                val = (a0 + k_cross(self.ddphi * self.qd**2, c) - self.omega**2 * c,
                       a1 + k_cross(self.dphi, c))
            else:
                val = self.differentiated_acceleration_parts(self.position(name))
            self._cache[key] = val
        return self._cache[key]

    def differentiated_acceleration(self, r: sp.Matrix) -> sp.Matrix:
        """d2r/dt2 of a position r(theta) by the chain rule."""
        a0, a1 = self.differentiated_acceleration_parts(r)
        return a0 + a1 * self.qdd

    def differentiated_acceleration_parts(self, r: sp.Matrix) -> tuple[sp.Matrix, sp.Matrix]:
        """(r'' qd^2, r') so that d2r/dt2 = r'' qd^2 + r' qdd (' = d/dtheta)."""
        r_q = sp.diff(r, self.q)
        return sp.diff(r_q, self.q) * self.qd**2, r_q

    @property
    def alpha_parts(self) -> tuple[sp.Expr, sp.Expr]:
        """(phi'' qd^2, phi') so that alpha = phi'' qd^2 + phi' qdd."""
        return self.ddphi * self.qd**2, self.dphi

    def rigid_acceleration(self, r: sp.Matrix, at: str) -> sp.Matrix:
        """Acceleration of the body point at fixed-frame position r, from point
        ``at`` by the rigid-body relation (Eq. 15):
        a = a_P + alpha x (r - r_P) - omega^2 (r - r_P)."""
        rel = r - self.position(at)
        return self.acceleration(at) + k_cross(self.alpha, rel) - self.omega**2 * rel

    def element_mass_centers(self) -> dict[str, sp.Matrix]:
        """Fixed-frame positions of the element mass centres (r-bar_k)."""
        return {p.name: self.body_point(p.center) for p in self.body.parts}

    def partial_velocity(self, name: str) -> sp.Matrix:
        """d v / d theta_dot of the material point at ``name``."""
        return sp.diff(self.velocity(name), self.qd)

    def time_derivative(self, expr: sp.Expr) -> sp.Expr:
        """d/dt of an expression in (theta, theta_dot, t)."""
        return sp.diff(expr, self.q) * self.qd + sp.diff(expr, self.qd) * self.qdd + sp.diff(expr, self.t)
