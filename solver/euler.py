"""The Newton-Euler equations of the scene's body (paper Eqs. 1, 2, 10, 11, 14, 15).

Two routes:

* ``generalized_euler_equations``: Newton in the composite form (Eq. 14, with
  each element's acceleration from a_P by Eq. 15) and the generalized Euler
  equation about an embedded point P (Eq. 10 / Eq. 11)::

      M_P - [sum_k m_k (r_k - r_P)] x a_P = [sum_k (I_P)_k] alpha

* ``mass_center_equations``: Newton about the composite mass centre G
  (Eq. 1, a_G by differentiating Eq. 13) and Euler about G (Eq. 2 with Eq. 5,
  M_G = I_G alpha).

Each equation is returned as ``expr == 0``, linear in theta_ddot and the
reaction symbols.
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .kinematics import BodyKinematics, cross_k

__all__ = [
    "NamedEquation",
    "AppliedForce",
    "applied_loads",
    "generalized_euler_equations",
    "mass_center_equations",
]


@dataclass(frozen=True)
class NamedEquation:
    """One scalar equation ``expr == 0``.

    Attributes
    ----------
    name : str
        What it is, e.g. ``"Euler about A"``.
    expr : sympy.Expr
    ref : str
        The paper equation it instantiates, e.g. ``"Eq. (11)"``.
    """

    name: str
    expr: sp.Expr
    ref: str


@dataclass(frozen=True)
class AppliedForce:
    """A force acting on the body.

    Attributes
    ----------
    name : str
    force : sympy.Matrix
        2x1 fixed-frame components (may contain reaction symbols).
    position : sympy.Matrix
        2x1 fixed-frame application point, in theta.
    kind : str
        ``"gravity"``, ``"force"`` or ``"reaction"``.
    point : str or None
        Named body point it acts at (None for gravity at element centres and
        for rolling contacts, whose material point is the contact point).
    """

    name: str
    force: sp.Matrix
    position: sp.Matrix
    kind: str
    point: str | None = None


def applied_loads(kin: BodyKinematics, include_reactions: bool = True):
    """Forces and couples acting on the body.

    Returns
    -------
    forces : list of AppliedForce
        Gravity on each element at its mass centre, point forces, and (when
        ``include_reactions``) each reaction times its direction.
    couples : list of (name, sympy.Expr)
        k-components of applied couples.
    """
    forces: list[AppliedForce] = []
    couples: list[tuple[str, sp.Expr]] = []
    centers = kin.element_mass_centers()
    for load in kin.scene.loads:
        if load.kind == "gravity":
            g = sp.Matrix(load.direction) * load.magnitude
            for part in kin.body.parts:
                forces.append(
                    AppliedForce(f"{load.name}:{part.name}", part.mass * g, centers[part.name], "gravity")
                )
        elif load.kind == "force":
            forces.append(
                AppliedForce(load.name, sp.Matrix(load.components), kin.position(load.point), "force", load.point)
            )
        elif load.kind == "couple":
            couples.append((load.name, sp.sympify(load.magnitude)))
    if include_reactions:
        for r in kin.reactions:
            point = r.at if r.at in kin.scene.points else None
            forces.append(AppliedForce(r.name, r.symbol * r.direction, r.position, "reaction", point))
    return forces, couples


def _resultant(forces) -> sp.Matrix:
    return sum((f.force for f in forces), sp.zeros(2, 1))


def _moment_about(forces, couples, r_P: sp.Matrix) -> sp.Expr:
    """M_P: k-component of sum (r_i - r_P) x F_i plus the couples."""
    terms = [cross_k(f.position - r_P, f.force) for f in forces]
    terms += [c for _, c in couples]
    return sp.Add(*terms)


def _is_body_point(kin: BodyKinematics, point: str) -> bool:
    p = kin.scene.points.get(point)
    return p is None or p.frame == "body"  # "G" (unnamed) is a body point


def _body_coords(kin: BodyKinematics, point: str) -> sp.Matrix:
    p = kin.scene.points.get(point)
    return sp.Matrix(p.coords) if p is not None else kin.body.mass_center()


def generalized_euler_equations(kin: BodyKinematics, point: str) -> tuple[NamedEquation, ...]:
    """Newton (Eq. 14 with Eq. 15) and the generalized Euler equation about P (Eq. 11).

    Parameters
    ----------
    kin : BodyKinematics
    point : str
        The embedded reference point P (a body point, an instant point, or
        "G").

    Returns
    -------
    tuple of NamedEquation
        ``Newton x``, ``Newton y``, ``Euler about P``, each ``expr == 0``.

    Notes
    -----
    a_k = a_P + alpha x (r_k - r_P) - omega^2 (r_k - r_P)   (Eq. 15)
    F = sum_k m_k a_k                                         (Eq. 14)
    M_P - [sum_k m_k (r_k - r_P)] x a_P = [sum_k (I_P)_k] alpha  (Eq. 11)
    with (I_P)_k = I_k + m_k d_k^2 (Eq. 12). For a single element these are
    Eqs. (1), (6) and (10).
    """
    forces, couples = applied_loads(kin)
    r_P = kin.position(point)
    a_P = kin.acceleration(point)
    centers = kin.element_mass_centers()
    composite = len(kin.body.parts) > 1
    newton_ref = "Eq. (14)" if composite else "Eq. (1)"
    euler_ref = "Eq. (11)" if composite else "Eq. (10)"

    # Eq. (15) for each element, Eq. (14) for the body.
    inertia_force = sp.zeros(2, 1)
    first_moment = sp.zeros(2, 1)
    for part in kin.body.parts:
        rel = centers[part.name] - r_P
        a_k = kin.rigid_acceleration(centers[part.name], point)
        inertia_force += part.mass * a_k
        first_moment += part.mass * rel
    newton = _resultant(forces) - inertia_force

    # Eq. (12): I_P; body-frame differences keep it free of theta for body points.
    if _is_body_point(kin, point):
        I_P = kin.body.inertia_about(_body_coords(kin, point))
    else:
        I_P = sp.Add(*[p.I_G + p.mass * ((centers[p.name] - r_P).T * (centers[p.name] - r_P))[0]
                       for p in kin.body.parts])
    # Eq. (11)
    euler = _moment_about(forces, couples, r_P) - cross_k(first_moment, a_P) - I_P * kin.alpha
    return (
        NamedEquation("Newton x", newton[0], newton_ref),
        NamedEquation("Newton y", newton[1], newton_ref),
        NamedEquation(f"Euler about {point}", euler, euler_ref),
    )


def mass_center_equations(kin: BodyKinematics) -> tuple[NamedEquation, ...]:
    """Newton about G (Eq. 1) and Euler about G (Eq. 2, with Eq. 5).

    Notes
    -----
    r_G = sum_k m_k r_k / m (Eq. 13), a_G = d2 r_G / dt2, F = m a_G (Eq. 1),
    M_G = I_G alpha (Eqs. 2, 5) with I_G = sum_k [I_k + m_k |r_k - r_G|^2].
    """
    forces, couples = applied_loads(kin)
    m = kin.body.total_mass
    r_G = kin.body_point(kin.body.mass_center())
    a_G = kin.differentiated_acceleration(r_G)
    newton = _resultant(forces) - m * a_G
    I_G = kin.body.centroidal_inertia()
    euler = _moment_about(forces, couples, r_G) - I_G * kin.alpha
    return (
        NamedEquation("Newton x", newton[0], "Eq. (1)"),
        NamedEquation("Newton y", newton[1], "Eq. (1)"),
        NamedEquation("Euler about G", euler, "Eq. (2)"),
    )
