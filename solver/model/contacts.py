"""Contact regimes: stick, slip and separation (Coulomb friction, one-sided contacts).

A *contact* is a joint that holds a point or a rim of one body against a line
or a circle of another: :class:`~solver.model.joints.Rail` (and the corners of a
body resting on a surface, written as one-sided rails),
:class:`~solver.model.joints.Rolling` and
:class:`~solver.model.joints.RollingOnCircle`. It has a *normal* row Phi_n (the
gap: positive when the bodies separate) and a *tangential* row Phi_t (the
relative displacement along the contact's direction d). Its regime decides
which rows hold and which reactions are unknowns:

========================  =========================  ===============================
regime                    rows (reactions)           friction
========================  =========================  ===============================
:class:`Stick`            Phi_t, Phi_n  (F, N)        unknown, needs |F| <= mu_s N
:class:`Slip` (s = +-1)   Phi_n         (N)           -s mu_k N along d (a known load)
:class:`Sliding`          Phi_n         (N)           none (a frictionless rail)
:class:`Separated`        none                        none
========================  =========================  ===============================

s is the sign of the sliding velocity dPhi_t/dt. Because the gradient of each
row is the generalized force of a unit reaction, dPhi_t/dt is the sliding
speed conjugate to F, so the friction power -mu_k N |dPhi_t/dt| is never
positive. The paper stops at the rolling condition |F| <= mu N (after Eq. 46);
these regimes carry Example 2 past it.
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

__all__ = ["Friction", "Regime", "Stick", "Slip", "Sliding", "Separated", "STICK", "SLIDING", "SEPARATED"]


@dataclass(frozen=True)
class Friction:
    """Coulomb coefficients of a contact (dimensionless expressions).

    ``static`` limits sticking (|F| <= mu_s N); ``kinetic`` gives the force
    while sliding (|F| = mu_k N).
    """

    static: sp.Expr
    kinetic: sp.Expr


class Regime:
    """Base class of a contact's regime; see the table in the module docstring."""

    keeps_tangential: bool = False
    keeps_normal: bool = True
    label: str = ""

    def friction_direction(self) -> int:
        """The sign s of the sliding velocity (0 when not sliding)."""
        return 0

    def __eq__(self, other) -> bool:
        return type(self) is type(other) and self.label == other.label

    def __hash__(self) -> int:
        return hash((type(self).__name__, self.label))

    def __repr__(self) -> str:
        return self.label


class Stick(Regime):
    """The contact holds in both directions: rolling without slip, or a point that does not slide."""

    keeps_tangential = True
    label = "stick"


class Slip(Regime):
    """The contact slides with sliding velocity of sign ``direction`` (+1 along d, -1 against it).

    ``impending`` marks a slip about to start from rest: its friction is
    mu_s N, the largest sticking could give, so the slip is consistent only
    when sticking cannot hold (Coulomb's static law); once sliding, mu_k N.
    """

    def __init__(self, direction: int, impending: bool = False):
        if direction not in (1, -1):
            raise ValueError(f"a slip direction is +1 or -1, got {direction!r}")
        self.direction = direction
        self.impending = impending
        self.label = f"slip {'+' if direction > 0 else '-'}" + (" (impending)" if impending else "")

    def coefficient(self, friction: Friction) -> sp.Expr:
        """mu_s while impending, mu_k while sliding."""
        return friction.static if self.impending else friction.kinetic

    def sliding(self) -> "Slip":
        """The same direction, sliding (kinetic friction)."""
        return Slip(self.direction)

    def friction_direction(self) -> int:
        return self.direction


class Sliding(Regime):
    """A frictionless contact sliding either way (a rail as written): the normal row only."""

    label = "slides"


class Separated(Regime):
    """The bodies have parted: no row, no reaction."""

    keeps_normal = False
    label = "separated"


STICK = Stick()
SLIDING = Sliding()
SEPARATED = Separated()
