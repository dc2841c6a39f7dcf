"""Rigid elements and the composite rigid body they form (paper Eqs. 12-13).

Every quantity is a sympy expression in the scene parameters, in body-frame
coordinates (constant in time). Units: masses [kg], lengths [m], moments of
inertia [kg m^2].
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Iterable

import sympy as sp

from .errors import SceneError
from .scene import ELEMENT_KINDS, Element

__all__ = ["ElementProperties", "element_properties", "CompositeBody"]

# Dimensions each element kind needs (see solver.scene.Element.dims).
REQUIRED_DIMS = {
    "slender_bar": ("length",),
    "uniform_disk": ("radius",),
    "thin_ring": ("radius",),
    "rectangular_plate": ("width", "height"),
    "point_mass": (),
    "semicircular_disk": ("radius",),
}
# Kinds with a round rim that can roll (radius = dims["radius"], rim centre =
# Element.center).
ROUND_KINDS = ("uniform_disk", "thin_ring", "semicircular_disk")


@dataclass(frozen=True)
class ElementProperties:
    """Mass properties of one element.

    Attributes
    ----------
    name : str
    mass : sympy.Expr
        m_k. [kg]
    center : sympy.Matrix
        2x1 body-frame position of the element's mass centre (r-bar_k). [m]
    I_G : sympy.Expr
        Centroidal moment of inertia about the k axis (I-bar_k). [kg m^2]
    """

    name: str
    mass: sp.Expr
    center: sp.Matrix
    I_G: sp.Expr


def _validate_element(element: Element) -> None:
    if element.kind not in ELEMENT_KINDS:
        raise SceneError(
            f"element {element.name!r}: kind must be one of {ELEMENT_KINDS}, got {element.kind!r}"
        )
    missing = [d for d in REQUIRED_DIMS[element.kind] if d not in element.dims]
    if missing:
        raise SceneError(
            f"element {element.name!r} ({element.kind}): missing dimension(s) {', '.join(missing)}"
        )


def element_properties(element: Element) -> ElementProperties:
    """Mass, mass centre and centroidal inertia of one element.

    Parameters
    ----------
    element : solver.scene.Element

    Returns
    -------
    ElementProperties

    Raises
    ------
    SceneError
        Unknown kind or a missing dimension.

    Notes
    -----
    Centroidal inertias (about the axis normal to the plane):
    slender bar m l^2/12; uniform disk m r^2/2; thin ring m r^2; rectangular
    plate m (w^2 + h^2)/12; point mass 0; semicircular disk
    (1/2 - 16/(9 pi^2)) m r^2, whose mass centre lies 4 r/(3 pi) from the
    straight edge along the symmetry axis (``Element.angle``).
    """
    _validate_element(element)
    m = sp.sympify(element.mass)
    c = sp.Matrix(element.center)
    d = element.dims
    kind = element.kind
    if kind == "slender_bar":
        inertia = m * d["length"] ** 2 / 12
    elif kind == "uniform_disk":
        inertia = m * d["radius"] ** 2 / 2
    elif kind == "thin_ring":
        inertia = m * d["radius"] ** 2
    elif kind == "rectangular_plate":
        inertia = m * (d["width"] ** 2 + d["height"] ** 2) / 12
    elif kind == "point_mass":
        inertia = sp.Integer(0)
    else:  # semicircular_disk
        r = d["radius"]
        offset = 4 * r / (3 * sp.pi)
        c = c + offset * sp.Matrix([sp.cos(element.angle), sp.sin(element.angle)])
        inertia = (sp.Rational(1, 2) - 16 / (9 * sp.pi**2)) * m * r**2
    return ElementProperties(element.name, m, c, inertia)


class CompositeBody:
    """A rigid body made of rigidly joined elements (paper Eqs. 11-14).

    Parameters
    ----------
    elements : iterable of solver.scene.Element

    Attributes
    ----------
    parts : tuple of ElementProperties
    total_mass : sympy.Expr
        m = sum m_k. [kg]
    """

    def __init__(self, elements: Iterable[Element]):
        self.parts = tuple(element_properties(e) for e in elements)
        if not self.parts:
            raise SceneError("the body has no elements")
        self.total_mass = sp.Add(*[p.mass for p in self.parts])

    def first_moment_about(self, point: sp.Matrix) -> sp.Matrix:
        """sum m_k (r-bar_k - r_P), body frame (the bracket of Eq. 11). [kg m]"""
        point = sp.Matrix(point)
        return sum((p.mass * (p.center - point) for p in self.parts), sp.zeros(2, 1))

    def mass_center(self) -> sp.Matrix:
        """r_G = sum m_k r-bar_k / m, body frame (Eq. 13). [m]"""
        return self.first_moment_about(sp.zeros(2, 1)) / self.total_mass

    def inertia_about(self, point: sp.Matrix) -> sp.Expr:
        """I_P = sum [I-bar_k + m_k d_k^2], d_k = |r-bar_k - r_P| (Eq. 12). [kg m^2]"""
        point = sp.Matrix(point)
        terms = []
        for p in self.parts:
            d = p.center - point
            terms.append(p.I_G + p.mass * (d[0] ** 2 + d[1] ** 2))
        return sp.Add(*terms)

    def centroidal_inertia(self) -> sp.Expr:
        """I_G of the whole body about its mass centre (Eq. 12 with P = G). [kg m^2]"""
        return self.inertia_about(self.mass_center())

    def __repr__(self) -> str:
        names = ", ".join(p.name for p in self.parts)
        return f"CompositeBody([{names}], m={self.total_mass})"
