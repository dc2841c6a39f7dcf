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

from .kinematics import BodyKinematics, cross_k, k_cross

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
    row, rhs : tuple of sympy.Expr and sympy.Expr, optional
        When known from the construction: the coefficients of the unknowns
        (theta_ddot, reactions...) and the right-hand side, so that
        ``expr == row . unknowns - rhs``.
    """

    name: str
    expr: sp.Expr
    ref: str
    row: tuple | None = None
    rhs: sp.Expr | None = None


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


def _assemble(name, ref, const, coef_qdd, coef_reactions, kin) -> NamedEquation:
    """expr = const + coef_qdd qdd + sum coef_R R, with its row and rhs."""
    unknown_terms = [coef_qdd * kin.qdd] + [c * r.symbol for c, r in zip(coef_reactions, kin.reactions)]
    expr = sp.Add(const, *unknown_terms)
    return NamedEquation(name, expr, ref, row=(coef_qdd, *coef_reactions), rhs=-const)


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
      = m a_P + alpha x S - omega^2 S,  S = sum_k m_k (r_k - r_P)
    M_P - S x a_P = [sum_k (I_P)_k] alpha                     (Eq. 11)
    with (I_P)_k = I_k + m_k d_k^2 (Eq. 12). For a single element these are
    Eqs. (1), (6) and (10). Each equation is assembled term by term as
    constant + coefficient x unknown (the system is linear in theta_ddot and
    the reactions), so the linear system needs no differentiation.
    """
    forces, couples = applied_loads(kin, include_reactions=False)
    r_P = kin.position(point)
    a0, a1 = kin.acceleration_parts(point)
    al0, al1 = kin.alpha_parts
    w2 = kin.omega**2
    centers = kin.element_mass_centers()
    composite = len(kin.body.parts) > 1
    newton_ref = "Eq. (14)" if composite else "Eq. (1)"
    euler_ref = "Eq. (11)" if composite else "Eq. (10)"
    m = kin.body.total_mass
    # S = sum m_k (r_k - r_P), the bracket of Eq. (11)
    S = sum((p.mass * (centers[p.name] - r_P) for p in kin.body.parts), sp.zeros(2, 1))
    # Eq. (12): I_P; body-frame differences keep it free of theta for body points.
    if _is_body_point(kin, point):
        I_P = kin.body.inertia_about(_body_coords(kin, point))
    else:
        I_P = sp.Add(*[p.I_G + p.mass * ((centers[p.name] - r_P).T * (centers[p.name] - r_P))[0]
                       for p in kin.body.parts])

    # constant part (unknowns = 0): applied loads, velocity-squared inertia terms
    newton0 = _resultant(forces) - (m * a0 + k_cross(al0, S) - w2 * S)
    euler0 = _moment_about(forces, couples, r_P) - cross_k(S, a0) - I_P * al0
    # coefficient of theta_ddot
    newton1 = -(m * a1 + k_cross(al1, S))
    euler1 = -cross_k(S, a1) - I_P * al1
    # coefficients of the reactions
    rx = [r.direction[0] for r in kin.reactions]
    ry = [r.direction[1] for r in kin.reactions]
    rm = [cross_k(r.position - r_P, r.direction) for r in kin.reactions]
    return (
        _assemble("Newton x", newton_ref, newton0[0], newton1[0], rx, kin),
        _assemble("Newton y", newton_ref, newton0[1], newton1[1], ry, kin),
        _assemble(f"Euler about {point}", euler_ref, euler0, euler1, rm, kin),
    )


def mass_center_equations(kin: BodyKinematics) -> tuple[NamedEquation, ...]:
    """Newton about G (Eq. 1) and Euler about G (Eq. 2, with Eq. 5).

    Notes
    -----
    r_G = sum_k m_k r_k / m (Eq. 13), a_G = d2 r_G / dt2, F = m a_G (Eq. 1),
    M_G = I_G alpha (Eqs. 2, 5) with I_G = sum_k [I_k + m_k |r_k - r_G|^2].
    """
    forces, couples = applied_loads(kin, include_reactions=False)
    m = kin.body.total_mass
    r_G = kin.body_point(kin.body.mass_center())
    g0, g1 = kin.differentiated_acceleration_parts(r_G)
    al0, al1 = kin.alpha_parts
    I_G = kin.body.centroidal_inertia()
    newton0 = _resultant(forces) - m * g0
    euler0 = _moment_about(forces, couples, r_G) - I_G * al0
    newton1 = -m * g1
    euler1 = -I_G * al1
    rx = [r.direction[0] for r in kin.reactions]
    ry = [r.direction[1] for r in kin.reactions]
    rm = [cross_k(r.position - r_G, r.direction) for r in kin.reactions]
    return (
        _assemble("Newton x", "Eq. (1)", newton0[0], newton1[0], rx, kin),
        _assemble("Newton y", "Eq. (1)", newton0[1], newton1[1], ry, kin),
        _assemble("Euler about G", "Eq. (2)", euler0, euler1, rm, kin),
    )
