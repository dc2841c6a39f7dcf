"""Newton-Euler equations of every body, by two routes (paper Eqs. 1, 2, 6, 10-15).

* :func:`generalized_euler_equations`: for each body, Newton in the composite
  form (Eq. 14, each element's acceleration from a_P by Eq. 15) and the
  generalized Euler equation about an embedded point P of that body
  (Eq. 10; Eq. 11 for a composite body)::

      M_P - [sum_k m_k (r_k - r_P)] x a_P = [sum_k (I_P)_k] alpha

  with (I_P)_k = I-bar_k + m_k d_k^2 (Eq. 12).
* :func:`mass_center_equations`: for each body, Newton about its mass centre G
  (Eq. 1, a_G by differentiating r_G of Eq. 13 twice) and Euler about G
  (Eq. 2 with Eq. 5, M_G = I_G alpha).

Both add the acceleration form of every closure equation (d^2 Phi / dt^2 = 0).
Each equation is an expression ``== 0``, linear in the unknowns: the second
derivatives of the free coordinates and the reactions.
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from ..model.joints import xy

__all__ = [
    "NamedEquation", "body_equations", "generalized_euler_equations", "mass_center_equations", "closure_equations",
]


@dataclass(frozen=True)
class NamedEquation:
    """One scalar equation ``expr == 0``.

    Attributes
    ----------
    name : str
        What it is, e.g. ``"Euler about A"`` or ``"rod: Newton x"``.
    expr : sympy.Expr
    ref : str
        The paper equation it instantiates, e.g. ``"Eq. (11)"``.
    body : str or None
        The body it belongs to (None for a closure equation).
    """

    name: str
    expr: sp.Expr
    ref: str
    body: str | None = None


def _label(system, body: str, text: str) -> str:
    return text if len(system.bodies) == 1 else f"{body}: {text}"


def _loads_on(system, body: str):
    """(forces [((Fx, Fy), (x, y))], couples [C]) on ``body``: applied loads and
    reactions (symbols). Vectors as component pairs: 2-vector Matrix arithmetic
    is slow in sympy."""
    forces, couples = [], []
    for a in system.applied_loads:
        if a.body != body:
            continue
        if a.force is not None:
            forces.append((xy(a.force), xy(a.at)))
        if a.couple != 0:
            couples.append(a.couple)
    for jl in system.joint_loads():
        if jl.body != body:
            continue
        sym = jl.reaction.symbol
        if jl.force is not None:
            fx, fy = xy(jl.force)
            forces.append(((sym * fx, sym * fy), xy(jl.at)))
        if jl.couple != 0:
            couples.append(sym * jl.couple)
    return forces, couples


def _resultant(forces) -> tuple:
    return sp.Add(*[f[0] for f, _ in forces]), sp.Add(*[f[1] for f, _ in forces])


def _moment_about(forces, couples, r_P) -> sp.Expr:
    """M_P: k-component of sum (r_i - r_P) x F_i, plus the couples."""
    x, y = xy(r_P)
    return sp.Add(*[(at[0] - x) * f[1] - (at[1] - y) * f[0] for f, at in forces], *couples)


def generalized_euler_equations(system, points: dict[str, str]) -> list[NamedEquation]:
    """Newton (Eq. 14 with Eq. 15) and the generalized Euler equation (Eq. 11)
    about the point ``points[body]`` of every body, then the closure equations.

    Notes
    -----
    For body b with elements k and reference point P::

        a_k = a_P + alpha x (r_k - r_P) - omega^2 (r_k - r_P)      (Eq. 15)
        F = sum_k m_k a_k = m a_P + alpha x S - omega^2 S           (Eq. 14)
        M_P - S x a_P = [sum_k (I_P)_k] alpha,  S = sum_k m_k (r_k - r_P)   (Eq. 11)

    For a single element these are Eqs. (1), (6) and (10).
    """
    out = []
    for name in system.bodies:
        out += body_equations(system, name, points[name])
    return out + closure_equations(system)


def body_equations(system, name: str, P: str, a_P=None) -> list[NamedEquation]:
    """Newton x, Newton y and the generalized Euler equation about P of one body (see
    :func:`generalized_euler_equations`); ``a_P``: P's acceleration, by default the placement's
    (:meth:`System.point_acceleration`)."""
    body = system.bodies[name]
    composite = len(body.elements) > 1
    r_P = xy(system.point_position(name, P))  # components: a Matrix index costs about 1 us
    a_P = xy(system.point_acceleration(name, P) if a_P is None else a_P)
    w, al = system.omega(name), system.alpha(name)
    centers = [xy(system.body_point(name, e.mass_center)) for e in body.elements]
    S = [sp.Add(*[e.mass * (c[k] - r_P[k]) for e, c in zip(body.elements, centers)]) for k in (0, 1)]
    if system.is_body_point(name, P):
        I_P = body.inertia_about(body.body_coords(P))
    else:  # an instant point: the distances from the elements change with the configuration
        I_P = sp.Add(*[e.I_G + e.mass * ((c[0] - r_P[0]) ** 2 + (c[1] - r_P[1]) ** 2)
                       for e, c in zip(body.elements, centers)])
    forces, couples = _loads_on(system, name)
    m = body.total_mass
    F = _resultant(forces)
    w2 = w**2
    newton = (F[0] - (m * a_P[0] - al * S[1] - w2 * S[0]),   # alpha k x S = (-alpha S_y, alpha S_x)
              F[1] - (m * a_P[1] + al * S[0] - w2 * S[1]))
    euler = _moment_about(forces, couples, r_P) - (S[0] * a_P[1] - S[1] * a_P[0]) - I_P * al
    nref = "Eq. (14)" if composite else "Eq. (1)"
    eref = "Eq. (11)" if composite else "Eq. (10)"
    return [
        NamedEquation(_label(system, name, "Newton x"), newton[0], nref, name),
        NamedEquation(_label(system, name, "Newton y"), newton[1], nref, name),
        NamedEquation(_label(system, name, f"Euler about {P}"), euler, eref, name),
    ]


def mass_center_equations(system) -> list[NamedEquation]:
    """Newton about each body's mass centre (Eq. 1) and Euler about it (Eqs. 2, 5),
    then the closure equations.

    Notes
    -----
    r_G = sum_k m_k r_k / m (Eq. 13); a_G = d^2 r_G / dt^2 by differentiating
    r_G itself (not by Eq. 15); F = m a_G; M_G = I_G alpha.
    """
    out = []
    for name, body in system.bodies.items():
        r_G = system.body_point(name, body.mass_center())
        a_G = system.D(system.D(r_G))
        al = system.alpha(name)
        forces, couples = _loads_on(system, name)
        m = body.total_mass
        F = _resultant(forces)
        a_x, a_y = xy(a_G)
        newton = (F[0] - m * a_x, F[1] - m * a_y)
        euler = _moment_about(forces, couples, r_G) - body.centroidal_inertia() * al
        out += [
            NamedEquation(_label(system, name, "Newton x"), newton[0], "Eq. (1)", name),
            NamedEquation(_label(system, name, "Newton y"), newton[1], "Eq. (1)", name),
            NamedEquation(_label(system, name, "Euler about G"), euler, "Eq. (2)", name),
        ]
    return out + closure_equations(system)


def closure_equations(system) -> list[NamedEquation]:
    """d^2 Phi / dt^2 = 0 for every closure equation Phi of the placement."""
    out = []
    for row in system.closure:
        acc = system.D(system.D(row.expr))
        out.append(NamedEquation(f"closure {row.joint.name} ({row.reaction.name})", acc,
                                 "constraint, acceleration form"))
    return out
