"""External loads: gravity, forces, couples, linear and torsional springs and dampers.

Each load kind is a class that says which forces and couples it applies to
which bodies (:meth:`Load.applied`), and, when it is conservative, its
potential energy (:meth:`Load.potential`). Expressions are in the
coordinates, their rates, t and the parameters; the system resolves point
positions and velocities.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar, TYPE_CHECKING

import sympy as sp

from .joints import vscale

if TYPE_CHECKING:  # pragma: no cover
    from .system import System

__all__ = [
    "AppliedLoad", "Load", "Gravity", "Force", "Couple", "Spring", "TorsionalSpring", "Damper",
    "TorsionalDamper", "LOAD_CLASSES",
]


@dataclass(frozen=True)
class AppliedLoad:
    """A force (2x1, fixed frame) at fixed-frame position ``at`` on ``body``, or a couple.

    Attributes
    ----------
    name : str
    kind : str
        The load's kind (``gravity``, ``force``, ``couple``, ``spring`` ...).
    body : str
    force : sympy.Matrix or None
    at : sympy.Matrix or None
    couple : sympy.Expr
    point : tuple (body, point name) or None
        The named material point it acts at (None for gravity at an element's
        mass centre), for generalized forces by partial velocities.
    """

    name: str
    kind: str
    body: str
    force: sp.Matrix | None = None
    at: sp.Matrix | None = None
    couple: sp.Expr = sp.Integer(0)
    point: tuple[str, str] | None = None


@dataclass(eq=False)
class Load:
    """Base class of the load kinds."""

    kind: ClassVar[str] = ""
    conservative: ClassVar[bool] = False
    name: str

    def applied(self, system: "System") -> list[AppliedLoad]:
        raise NotImplementedError

    def potential(self, system: "System") -> sp.Expr | None:
        """Potential energy V [J] of a conservative load, else None."""
        return None

    def line_length(self, system: "System") -> sp.Expr | None:
        """The distance between the two points a spring or damper joins [m], else None.

        Where it is zero the load's line of action, and so its force, is undefined."""
        return None


@dataclass(eq=False)
class Gravity(Load):
    """Every element's weight m_k g along ``direction``, at its mass centre."""

    kind: ClassVar[str] = "gravity"
    conservative: ClassVar[bool] = True
    g: sp.Expr = sp.Integer(0)
    direction: sp.Matrix = field(default_factory=lambda: sp.Matrix([0, -1]))

    def applied(self, system):
        out = []
        for body in system.bodies.values():
            for e in body.elements:
                at = system.body_point(body.name, e.mass_center)
                out.append(AppliedLoad(f"{self.name}:{e.name}" if len(system.bodies) == 1 else
                                       f"{self.name}:{body.name}.{e.name}",
                                       self.kind, body.name, vscale(e.mass * self.g, self.direction), at))
        return out

    def potential(self, system):
        terms = []
        for body in system.bodies.values():
            for e in body.elements:
                r = system.body_point(body.name, e.mass_center)
                terms.append(-e.mass * self.g * (self.direction.T * r)[0])
        return sp.Add(*terms)


@dataclass(eq=False)
class Force(Load):
    """A force with fixed-frame ``components`` (functions of the state and t)
    applied at point ``point`` of body ``body``."""

    kind: ClassVar[str] = "force"
    body: str = ""
    point: str = ""
    components: sp.Matrix = field(default_factory=lambda: sp.zeros(2, 1))

    def applied(self, system):
        at = system.point_position(self.body, self.point)
        return [AppliedLoad(self.name, self.kind, self.body, sp.Matrix(self.components), at,
                            point=(self.body, self.point))]


@dataclass(eq=False)
class Couple(Load):
    """A couple of k-component ``moment`` (counter-clockwise positive) on ``body``."""

    kind: ClassVar[str] = "couple"
    body: str = ""
    moment: sp.Expr = sp.Integer(0)

    def applied(self, system):
        return [AppliedLoad(self.name, self.kind, self.body, couple=self.moment)]


def _segment(system, a, b):
    ra = system.point_position(*a)
    rb = system.point_position(*b)
    d = rb - ra
    length = sp.sqrt(d[0] ** 2 + d[1] ** 2)
    return ra, rb, d, length


@dataclass(eq=False)
class Spring(Load):
    """A linear spring between point ``a`` and point ``b`` (each (body, point);
    the body may be the ground): tension k (L - free_length) along the line."""

    kind: ClassVar[str] = "spring"
    conservative: ClassVar[bool] = True
    a: tuple[str, str] = ("", "")
    b: tuple[str, str] = ("", "")
    stiffness: sp.Expr = sp.Integer(0)
    free_length: sp.Expr = sp.Integer(0)

    def applied(self, system):
        ra, rb, d, length = _segment(system, self.a, self.b)
        tension = self.stiffness * (length - self.free_length)
        u = d / length
        out = []
        for (body, point), at, sign in ((self.a, ra, 1), (self.b, rb, -1)):
            if body in system.bodies:
                out.append(AppliedLoad(self.name, self.kind, body, sign * tension * u, at, point=(body, point)))
        return out

    def potential(self, system):
        _, _, _, length = _segment(system, self.a, self.b)
        return self.stiffness * (length - self.free_length) ** 2 / 2

    def line_length(self, system):
        return _segment(system, self.a, self.b)[3]


@dataclass(eq=False)
class Damper(Load):
    """A linear viscous damper between points ``a`` and ``b``: force
    c dL/dt along the line, resisting the change of length."""

    kind: ClassVar[str] = "damper"
    a: tuple[str, str] = ("", "")
    b: tuple[str, str] = ("", "")
    coefficient: sp.Expr = sp.Integer(0)

    def applied(self, system):
        ra, rb, d, length = _segment(system, self.a, self.b)
        u = d / length
        va = system.point_velocity(*self.a)
        vb = system.point_velocity(*self.b)
        rate = (u.T * (vb - va))[0]
        tension = self.coefficient * rate
        out = []
        for (body, point), at, sign in ((self.a, ra, 1), (self.b, rb, -1)):
            if body in system.bodies:
                out.append(AppliedLoad(self.name, self.kind, body, sign * tension * u, at, point=(body, point)))
        return out

    def line_length(self, system):
        return _segment(system, self.a, self.b)[3]


def _relative_angle(system, first, second):
    return system.angle(second) - system.angle(first)


@dataclass(eq=False)
class TorsionalSpring(Load):
    """A torsional spring between bodies ``first`` and ``second`` (either may
    be the ground): couple -k (phi_2 - phi_1 - free_angle) on the second, the
    opposite on the first."""

    kind: ClassVar[str] = "torsional_spring"
    conservative: ClassVar[bool] = True
    first: str = ""
    second: str = ""
    stiffness: sp.Expr = sp.Integer(0)
    free_angle: sp.Expr = sp.Integer(0)

    def applied(self, system):
        moment = -self.stiffness * (_relative_angle(system, self.first, self.second) - self.free_angle)
        return [AppliedLoad(self.name, self.kind, body, couple=sign * moment)
                for body, sign in ((self.second, 1), (self.first, -1)) if body in system.bodies]

    def potential(self, system):
        return self.stiffness * (_relative_angle(system, self.first, self.second) - self.free_angle) ** 2 / 2


@dataclass(eq=False)
class TorsionalDamper(Load):
    """A torsional damper between ``first`` and ``second``: couple
    -c (omega_2 - omega_1) on the second, the opposite on the first."""

    kind: ClassVar[str] = "torsional_damper"
    first: str = ""
    second: str = ""
    coefficient: sp.Expr = sp.Integer(0)

    def applied(self, system):
        rate = system.omega(self.second) - system.omega(self.first)
        moment = -self.coefficient * rate
        return [AppliedLoad(self.name, self.kind, body, couple=sign * moment)
                for body, sign in ((self.second, 1), (self.first, -1)) if body in system.bodies]


LOAD_CLASSES: dict[str, type[Load]] = {
    cls.kind: cls for cls in (Gravity, Force, Couple, Spring, Damper, TorsionalSpring, TorsionalDamper)
}
"""Load kind (the scene's ``kind`` key) -> class."""
