"""The in-memory description of one planar problem: a *scene*.

A scene is what a scene file (``data/scenes/*.toml``) says, after parsing and
validation by :mod:`solver.scenefile`. It is pure data: numbers are pint
quantities at the boundary and sympy expressions inside; nothing here derives
or solves. :mod:`solver.derivation` turns a scene into equations.

Conventions (used by every module)
----------------------------------
* Fixed frame: x to the right, y up, k = x cross y out of the plane.
* The body carries its own frame B. Every body point and element is given by
  constant coordinates in B (expressions in the parameters only).
* ``orientation`` is the angle phi(theta) of B's x axis measured from the fixed
  x axis, counter-clockwise positive [rad]. The body's angular velocity and
  acceleration are omega = dphi/dt k and alpha = d2phi/dt2 k; ``alpha`` in
  every result is this k-component, as the paper uses it.
* Where B sits in the plane (its translation) is fixed by the constraints
  (two rails, a rolling element, or a pivot) or, when ``position`` is given,
  by the explicit fixed-frame position of one body point as a function of
  theta.
* Symbols: each parameter is a real sympy Symbol of the same name; the
  coordinate is ``Symbol(coordinate)``, its rate ``Symbol(coordinate + "_dot")``,
  its second derivative ``Symbol(coordinate + "_ddot")``, time ``Symbol("t")``.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import pint
import sympy as sp

from solver.units import si_magnitude

ELEMENT_KINDS = (
    "slender_bar",
    "uniform_disk",
    "thin_ring",
    "rectangular_plate",
    "point_mass",
    "semicircular_disk",
)
POINT_FRAMES = ("body", "instant")
CONSTRAINT_KINDS = ("rail", "rolling", "pivot")
LOAD_KINDS = ("gravity", "force", "couple")


@dataclass(frozen=True)
class Element:
    """One rigid element of the (composite) body, in body-frame coordinates.

    Attributes
    ----------
    name : str
    kind : str
        One of :data:`ELEMENT_KINDS`.
    mass : sympy.Expr
        Mass, in the parameters. [kg]
    center : sympy.Matrix
        2x1 body-frame position of the element's geometric reference point:
        bar midpoint, disk/ring/plate centre, the point mass itself, and for
        a semicircular disk the midpoint of its straight edge. [m]
    angle : sympy.Expr
        Orientation of the element in the body frame [rad]: a bar's axis, a
        plate's width direction, a semicircular disk's symmetry axis (from the
        straight edge towards the curved rim). Irrelevant for disks, rings and
        point masses (0).
    dims : dict[str, sympy.Expr]
        ``length`` (bar), ``radius`` (disk, ring, semicircular disk),
        ``width`` and ``height`` (plate). [m]
    """

    name: str
    kind: str
    mass: sp.Expr
    center: sp.Matrix
    angle: sp.Expr = sp.Integer(0)
    dims: dict[str, sp.Expr] = field(default_factory=dict)


@dataclass(frozen=True)
class Point:
    """A named point of the body.

    frame = "body": ``coords`` are constant body-frame coordinates (2x1) in
        the parameters.
    frame = "instant": the body point that, at the current instant, sits at
        fixed-frame offset ``coords`` from body point ``relative_to`` (for
        example a rolling disk's contact point C, always directly below its
        centre). Its body-frame coordinates are R(-phi) @ coords and thus
        depend on theta; its velocity and acceleration are those of the
        material point there (rigid-body relation, Eq. 6), not the
        derivative of the moving geometric point.
    """

    name: str
    coords: sp.Matrix
    frame: str = "body"
    relative_to: str | None = None


@dataclass(frozen=True)
class Constraint:
    """A kinematic constraint and the reaction unknowns it brings.

    kind = "rail": body point ``point`` moves on the fixed straight line
        through ``origin`` (2x1, fixed frame) with direction angle ``angle``.
        Frictionless: one reaction, ``reactions[0]``, along the rail's left
        normal n = (-sin angle, cos angle); positive pushes the body along n.
    kind = "rolling": element ``element`` (a disk, ring or semicircular
        disk's round rim; radius from its dims) rolls without slipping on the
        fixed straight surface through ``origin`` with direction ``angle``,
        lying on the side of its left normal n. Reactions, in order:
        friction along the surface direction d, normal force along n.
        ``contact_at_zero`` is the distance along d from ``origin`` to the
        contact point when theta = 0.
    kind = "pivot": body point ``point`` is fixed at ``origin``. Reactions:
        x and y components in the fixed frame.

    ``one_sided`` marks reactions that can only push (a support that the
    body can leave); simulation stops when such a reaction would go negative.
    """

    name: str
    kind: str
    reactions: tuple[str, ...]
    point: str | None = None
    element: str | None = None
    origin: sp.Matrix = field(default_factory=lambda: sp.zeros(2, 1))
    angle: sp.Expr = sp.Integer(0)
    contact_at_zero: sp.Expr = sp.Integer(0)
    one_sided: bool = False
    friction_coefficient: sp.Expr | None = None
    friction_reaction: str | None = None  # a rail's friction force (with friction_coefficient)


@dataclass(frozen=True)
class Load:
    """An external load.

    kind = "gravity": every element's weight, magnitude ``magnitude`` (a
        parameter expression for g) along the fixed direction ``direction``
        (2x1, default (0, -1)).
    kind = "force": a force with fixed-frame components ``components``
        (2x1 expressions in parameters, t, and the state) applied at body
        point ``point``.
    kind = "couple": a couple of k-component ``magnitude`` (expression in
        parameters, t and the state). [N m]
    """

    name: str
    kind: str
    point: str | None = None
    components: sp.Matrix | None = None
    magnitude: sp.Expr | None = None
    direction: sp.Matrix = field(default_factory=lambda: sp.Matrix([0, -1]))


@dataclass(frozen=True)
class Scene:
    """A validated planar problem. See the module docstring for conventions.

    Attributes
    ----------
    name, description : str
    source : Path or None
        The file it was read from (for messages).
    parameters : dict[str, pint.Quantity]
        Named parameters as given (after ``--set`` overrides), with units.
    coordinate : str
        Name of the generalized coordinate (``"theta"``).
    state : dict[str, pint.Quantity]
        ``{coordinate: angle, coordinate + "_dot": rate}``.
    orientation : sympy.Expr
        phi(theta), the body frame's angle [rad].
    points : dict[str, Point]
        Named body points.
    elements, constraints, loads : tuples of the dataclasses above.
    position : tuple[str, sympy.Matrix] or None
        Optional explicit placement: (point name, fixed-frame position as a
        function of theta).
    default_point : str
        The reference point P used when none is chosen.
    output_units : dict[str, str]
        Preferred display units by dimension name: ``force``, ``moment``,
        ``length``, ``mass``, ``angle``, ``angular_velocity``,
        ``angular_acceleration``, ``time``.
    """

    name: str
    description: str
    source: Path | None
    parameters: dict[str, pint.Quantity]
    coordinate: str
    state: dict[str, pint.Quantity]
    orientation: sp.Expr
    points: dict[str, Point]
    elements: tuple[Element, ...]
    constraints: tuple[Constraint, ...]
    loads: tuple[Load, ...]
    default_point: str
    position: tuple[str, sp.Matrix] | None = None
    output_units: dict[str, str] = field(default_factory=dict)

    # -- symbols -------------------------------------------------------------
    @property
    def symbols(self) -> dict[str, sp.Symbol]:
        """Parameter symbols by name (real sympy Symbols)."""
        return {name: sp.Symbol(name, real=True) for name in self.parameters}

    @property
    def q(self) -> sp.Symbol:
        return sp.Symbol(self.coordinate, real=True)

    @property
    def qd(self) -> sp.Symbol:
        return sp.Symbol(self.coordinate + "_dot", real=True)

    @property
    def qdd(self) -> sp.Symbol:
        return sp.Symbol(self.coordinate + "_ddot", real=True)

    @property
    def t(self) -> sp.Symbol:
        return sp.Symbol("t", real=True)

    def si_values(self) -> dict[sp.Symbol, float]:
        """Parameter symbol -> value in SI base units (angles in rad)."""
        return {
            sp.Symbol(n, real=True): si_magnitude(q)
            for n, q in self.parameters.items()
        }

    def state_si(self) -> tuple[float, float]:
        """(theta [rad], theta_dot [rad/s]) of the scene's state."""
        q = self.state[self.coordinate].to("rad").magnitude
        qd = self.state[self.coordinate + "_dot"].to("rad/s").magnitude
        return float(q), float(qd)

    def reaction_names(self) -> tuple[str, ...]:
        return tuple(r for c in self.constraints for r in c.reactions)
