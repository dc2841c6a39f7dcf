"""Rigid bodies made of rigidly joined elements (paper Eqs. 11-14), and the ground.

A body carries its own frame; every named point and element is given by
constant body-frame coordinates (expressions in the parameters). An
*instant* point is the material point that, at the current instant, sits at a
fixed-frame offset from another point of the body (a rolling disk's contact
point C, always directly below its centre, Eq. 32).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp

from .elements import Element
from .joints import copy_vec, vadd, vec, vscale, vsub

__all__ = ["Point", "RigidBody", "Ground", "GROUND"]

GROUND = "ground"
"""The name of the fixed body."""


@dataclass(frozen=True)
class Point:
    """A named point of a body.

    ``frame = "body"``: ``coords`` are constant body-frame coordinates (2x1).
    ``frame = "instant"``: the material point at fixed-frame offset ``coords``
    from body point ``relative_to`` at the current instant; its velocity and
    acceleration are those of the material point there (Eq. 6), not the
    derivatives of the moving geometric point.
    """

    name: str
    coords: sp.Matrix
    frame: str = "body"
    relative_to: str | None = None

    @property
    def is_instant(self) -> bool:
        return self.frame == "instant"


@dataclass(eq=False)
class RigidBody:
    """A rigid body: composite of elements, with named points.

    Parameters
    ----------
    name : str
    elements : tuple of Element
    points : dict[str, Point]
    orientation : sympy.Expr or None
        phi(q, t), the angle of the body frame's x axis from the fixed x axis
        (counter-clockwise positive) [rad]. None when a joint fixes it.
    position : tuple (point name, sympy.Matrix) or None
        An explicit fixed-frame position of one body point as a function of
        the coordinates and t. None when joints fix it.
    reference_point : str or None
        The default point P of this body's moment equation.
    """

    name: str
    elements: tuple[Element, ...]
    points: dict[str, Point] = field(default_factory=dict)
    orientation: sp.Expr | None = None
    position: tuple[str, sp.Matrix] | None = None
    reference_point: str | None = None

    # -- mass properties: Eqs. (12)-(13) ---------------------------------------
    @property
    def total_mass(self) -> sp.Expr:
        """m = sum m_k. [kg]"""
        return sp.Add(*[e.mass for e in self.elements])

    def first_moment_about(self, point: sp.Matrix) -> sp.Matrix:
        """sum_k m_k (r-bar_k - r_P), body frame: the bracket of Eq. (11). [kg m]"""
        point = copy_vec(point)
        return vadd(vec(0, 0), *[vscale(e.mass, vsub(e.mass_center, point)) for e in self.elements])

    def mass_center(self) -> sp.Matrix:
        """r_G = sum m_k r-bar_k / m, body frame (Eq. 13). [m]"""
        return vscale(sp.S.One / self.total_mass, self.first_moment_about(vec(0, 0)))

    def inertia_about(self, point: sp.Matrix) -> sp.Expr:
        """I_P = sum_k [I-bar_k + m_k d_k^2], d_k = |r-bar_k - r_P| (Eq. 12). [kg m^2]"""
        point = copy_vec(point)
        terms = []
        for e in self.elements:
            d = vsub(e.mass_center, point)
            terms.append(e.I_G + e.mass * (d[0] ** 2 + d[1] ** 2))
        return sp.Add(*terms)

    def centroidal_inertia(self) -> sp.Expr:
        """I_G of the whole body about its mass centre (Eq. 12 with P = G). [kg m^2]"""
        return self.inertia_about(self.mass_center())

    # -- points -------------------------------------------------------------------
    def element(self, name: str) -> Element:
        for e in self.elements:
            if e.name == name:
                return e
        raise KeyError(name)

    def point_names(self) -> list[str]:
        """Named points, plus ``G`` (the composite mass centre) when not named."""
        return list(self.points) + ([] if "G" in self.points else ["G"])

    def body_coords(self, name: str) -> sp.Matrix:
        """Constant body-frame coordinates of a body-frame point (or G)."""
        if name in self.points:
            p = self.points[name]
            if p.is_instant:
                raise ValueError(f"{name!r} is an instant point")
            return copy_vec(p.coords)
        if name == "G":
            return self.mass_center()
        raise KeyError(name)

    @property
    def default_point(self) -> str:
        if self.reference_point is not None:
            return self.reference_point
        return next(iter(self.points)) if self.points else "G"

    def __repr__(self) -> str:
        return f"RigidBody({self.name!r}, elements=[{', '.join(e.name for e in self.elements)}])"


@dataclass(eq=False)
class Ground:
    """The fixed body: its frame is the fixed frame; points are fixed positions."""

    points: dict[str, Point] = field(default_factory=dict)
    name: str = GROUND
    elements: tuple = ()

    def point_names(self) -> list[str]:
        return list(self.points)

    def body_coords(self, name: str) -> sp.Matrix:
        return copy_vec(self.points[name].coords)
