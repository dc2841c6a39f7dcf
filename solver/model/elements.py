"""Rigid elements and their mass properties (paper Eqs. 12-13).

Each element kind is a class that knows its mass, the body-frame position of
its mass centre (r-bar_k) and its centroidal moment of inertia (I-bar_k).
Every quantity is a sympy expression in the scene parameters, in body-frame
coordinates (constant in time). Units: [kg], [m], [kg m^2].
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar

import sympy as sp

__all__ = [
    "Element", "SlenderBar", "UniformDisk", "ThinRing", "RectangularPlate", "PointMass",
    "SemicircularDisk", "GyrationElement", "InertiaElement", "ELEMENT_CLASSES", "ROUND_KINDS",
]


@dataclass(frozen=True, eq=False)
class Element:
    """One rigid element of a (composite) body, in body-frame coordinates.

    Attributes
    ----------
    name : str
    mass : sympy.Expr
        m_k. [kg]
    center : sympy.Matrix
        2x1 body-frame position of the element's geometric reference point:
        bar midpoint, disk/ring/plate centre, the point mass itself, and for a
        semicircular disk the midpoint of its straight edge. [m]
    angle : sympy.Expr
        Orientation in the body frame [rad]: a bar's axis, a plate's width
        direction, a semicircular disk's symmetry axis (from the straight edge
        towards the rim).
    dims : dict[str, sympy.Expr]
        ``length`` (bar), ``radius`` (disk, ring, semicircle), ``width`` and
        ``height`` (plate), ``radius_of_gyration`` or ``inertia``. [m], [kg m^2]
    """

    kind: ClassVar[str] = ""
    required: ClassVar[tuple[str, ...]] = ()
    round: ClassVar[bool] = False

    name: str
    mass: sp.Expr
    center: sp.Matrix
    angle: sp.Expr = sp.Integer(0)
    dims: dict = field(default_factory=dict)

    @property
    def mass_center(self) -> sp.Matrix:
        """r-bar_k: body-frame position of the element's mass centre. [m]"""
        from .joints import copy_vec

        return copy_vec(self.center)

    @property
    def I_G(self) -> sp.Expr:
        """I-bar_k: centroidal moment of inertia about the k axis. [kg m^2]"""
        raise NotImplementedError

    @property
    def radius(self) -> sp.Expr:
        """Rim radius of a round element (the circle that rolls). [m]"""
        return self.dims["radius"]

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self.name!r}, mass={self.mass})"


class SlenderBar(Element):
    """A slender uniform bar: I-bar = m l^2 / 12."""

    kind = "slender_bar"
    required = ("length",)

    @property
    def I_G(self):
        return self.mass * self.dims["length"] ** 2 / 12


class UniformDisk(Element):
    """A uniform disk: I-bar = m r^2 / 2 (Eq. 34)."""

    kind = "uniform_disk"
    required = ("radius",)
    round = True

    @property
    def I_G(self):
        return self.mass * self.dims["radius"] ** 2 / 2


class ThinRing(Element):
    """A thin ring (hoop): I-bar = m r^2."""

    kind = "thin_ring"
    required = ("radius",)
    round = True

    @property
    def I_G(self):
        return self.mass * self.dims["radius"] ** 2


class RectangularPlate(Element):
    """A uniform rectangular plate: I-bar = m (w^2 + h^2) / 12."""

    kind = "rectangular_plate"
    required = ("width", "height")

    @property
    def I_G(self):
        return self.mass * (self.dims["width"] ** 2 + self.dims["height"] ** 2) / 12


class PointMass(Element):
    """A particle rigidly attached to the body: I-bar = 0."""

    kind = "point_mass"

    @property
    def I_G(self):
        return sp.Integer(0)


class SemicircularDisk(Element):
    """A uniform semicircular disk.

    Its mass centre lies 4 r / (3 pi) from the straight edge along the symmetry
    axis (``angle``); I-bar = (1/2 - 16 / (9 pi^2)) m r^2.
    """

    kind = "semicircular_disk"
    required = ("radius",)
    round = True

    @property
    def mass_center(self):
        from .joints import vadd, vec, vscale

        offset = 4 * self.dims["radius"] / (3 * sp.pi)
        return vadd(self.center, vscale(offset, vec(sp.cos(self.angle), sp.sin(self.angle))))

    @property
    def I_G(self):
        return (sp.Rational(1, 2) - 16 / (9 * sp.pi**2)) * self.mass * self.dims["radius"] ** 2


class GyrationElement(Element):
    """A body given by its mass and centroidal radius of gyration k: I-bar = m k^2.

    With ``radius`` also given it is round (a wheel or drum that can roll or
    carry a cord) of that rim radius.
    """

    kind = "gyration"
    required = ("radius_of_gyration",)

    @property
    def round(self):  # type: ignore[override]
        return "radius" in self.dims

    @property
    def I_G(self):
        return self.mass * self.dims["radius_of_gyration"] ** 2


class InertiaElement(Element):
    """A body given by its mass and centroidal moment of inertia I-bar.

    With ``radius`` also given it is round (a rim of that radius).
    """

    kind = "centroidal_inertia"
    required = ("inertia",)

    @property
    def round(self):  # type: ignore[override]
        return "radius" in self.dims

    @property
    def I_G(self):
        return self.dims["inertia"]


ELEMENT_CLASSES: dict[str, type[Element]] = {
    cls.kind: cls
    for cls in (SlenderBar, UniformDisk, ThinRing, RectangularPlate, PointMass, SemicircularDisk,
                GyrationElement, InertiaElement)
}
"""Element kind (the scene's ``kind`` key) -> class."""

ROUND_KINDS = tuple(k for k, c in ELEMENT_CLASSES.items() if c.round is True) + ("gyration", "centroidal_inertia")
"""Kinds that may have a rim (those with an optional ``radius`` need it given)."""
