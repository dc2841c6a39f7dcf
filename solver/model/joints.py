"""Joints: one class per kind, each owning its reactions and its equations.

A joint connects a *first* body (or the ground) to a *second* body. Each
reaction unknown it brings acts on the second body as written (a force along a
named direction at a named point, or a couple) and, equal and opposite, on the
first body. Every reaction pairs with one constraint equation
Phi_k(poses, t) = 0 whose gradient with respect to the second body's pose
(x, y, phi) is exactly the generalized force of a unit reaction: the reaction
is the Lagrange multiplier of its equation. Freedoms removed = number of
reactions.

A joint is evaluated against a *pose provider* ``pose(body) -> (origin, phi)``
(fixed-frame position of the body frame's origin and the body's angle), so the
same equations serve the placed system (poses as functions of the
coordinates) and the Lagrange route (poses as free body coordinates).

Kinds: :class:`Pin`, :class:`Rail` (a point on a line; :class:`PinInSlot` is
the same on another body), :class:`Slider` (prismatic), :class:`Rolling` (on
a line), :class:`RollingOnCircle`, :class:`GearMesh`, :class:`Cord` (wound on
a drum), :class:`Motor` (driven rotation) and :class:`Actuator` (driven
translation).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property, lru_cache
from typing import Callable, ClassVar

import sympy as sp
from sympy.polys.domains import EXRAW as _EXRAW
from sympy.polys.domains import QQ as _QQ
from sympy.polys.domains import ZZ as _ZZ
from sympy.polys.matrices import DomainMatrix as _DomainMatrix
from sympy.polys.matrices.sdm import SDM as _SDM

from .contacts import SLIDING, STICK, Friction, Regime

__all__ = [
    "Reaction", "JointLoad", "Joint", "Pin", "Rail", "PinInSlot", "Slider", "Rolling",
    "RollingOnCircle", "GearMesh", "Cord", "Motor", "Actuator", "JOINT_CLASSES",
    "vec", "xy", "vadd", "vsub", "vscale", "rotation", "cross_k", "k_cross", "Contact",
    "finite_by_structure", "times_zero_is_zero",
]

Pose = Callable[[str], tuple[sp.Matrix, sp.Expr]]


def vec(x, y) -> sp.Matrix:
    """The column ``sp.Matrix([x, y])``, the same matrix (entries, domain and type) built from its
    sparse representation directly: sympy's generic constructor parses its input first, about 40 us
    a call, and the model builds tens of 2-vectors per command."""
    x = x if isinstance(x, sp.Basic) else sp.sympify(x)
    y = y if isinstance(y, sp.Basic) else sp.sympify(y)
    if not (isinstance(x, sp.Expr) and isinstance(y, sp.Expr)):
        return sp.Matrix([x, y])  # sympy's deprecation warning for non-expressions
    rows = {}
    if _nonzero(x):
        rows[0] = {0: x}
    if _nonzero(y):
        rows[1] = {0: y}
    if x.is_Rational and y.is_Rational:  # sympy's domain for numbers: integers ZZ, rationals QQ
        rep = _DomainMatrix(rows, (2, 1), _EXRAW).convert_to(_ZZ if x.is_Integer and y.is_Integer else _QQ)
    else:  # expressions: the sparse representation sympy's DomainMatrix would hold, made directly
        rep = _exraw_column(rows)
    return sp.MutableDenseMatrix._fromrep(rep)


def _exraw_column(rows: dict):
    """``DomainMatrix.from_rep(SDM(rows, (2, 1), EXRAW))``: the same objects with the same attributes,
    set directly (``SDM``'s constructor checks every index of the dict, about half of ``vec``'s time;
    the rows here are 0 and 1 of column 0 by construction)."""
    sdm = _SDM.__new__(_SDM)
    dict.update(sdm, rows)
    sdm.shape, sdm.rows, sdm.cols, sdm.domain = (2, 1), 2, 1, _EXRAW
    rep = object.__new__(_DomainMatrix)
    rep.rep, rep.shape, rep.domain = sdm, (2, 1), _EXRAW
    return rep


def _nonzero(x) -> bool:
    """``x != 0``: compared only for a number (about 0.7 us each); any other expression differs
    from the number 0 (sympy's equality is structural)."""
    return x != 0 if not isinstance(x, sp.Expr) or x.is_Number else True


@lru_cache(maxsize=4096)
def finite_by_structure(e: sp.Expr) -> bool:
    """Whether ``e`` is built only from finite numbers and finite symbols (a real symbol is one) by
    sums, products, positive integer powers, sine and cosine: then no value of its symbols makes it
    infinite, so sympy's assumptions never find ``e.is_finite`` False. False when not so built (it
    may still be finite).

    ``0 * e`` is then 0 as sympy makes it: ``Mul.flatten`` gives nan for 0 times a factor whose
    ``is_finite`` is False, else 0, and asks every factor to decide (the first time for each object,
    through its assumption rules); callers that know the product is 0 skip the asking."""
    if e.is_Number or e.is_Symbol:
        return e.is_finite is True
    if e.is_Add or e.is_Mul:
        return all(finite_by_structure(a) for a in e.args)
    if e.is_Pow:
        return e.exp.is_Integer and e.exp > 0 and finite_by_structure(e.base)
    if isinstance(e, (sp.sin, sp.cos)):
        return finite_by_structure(e.args[0])
    return False


def times_zero_is_zero(factors) -> bool:
    """Whether a product of ``factors`` (sympy expressions) of which one is the number 0 is 0: every
    other factor is finite by its structure (:func:`finite_by_structure`). False when no factor is 0,
    or when another factor could be infinite (sympy then asks it)."""
    zero = False
    for f in factors:
        if f is sp.S.Zero:
            zero = True
        elif not finite_by_structure(f):
            return False
    return zero


def xy(v) -> tuple:
    """``(v[0], v[1])`` of a 2-vector (a column Matrix or a pair): read from a mutable matrix's
    sparse representation directly when its entries are expressions (sympy's indexing costs about
    1 us an entry, and the model reads hundreds of them per command)."""
    if type(v) is sp.MutableDenseMatrix:
        rep = v._rep
        if type(rep.rep) is _SDM and rep.shape == (2, 1):
            domain, r0, r1 = rep.domain, rep.rep.get(0), rep.rep.get(1)
            x, y = (r0[0] if r0 else domain.zero), (r1[0] if r1 else domain.zero)
            return (x, y) if domain is _EXRAW else (domain.to_sympy(x), domain.to_sympy(y))
    return v[0], v[1]


def copy_vec(v) -> sp.Matrix:
    """``sp.Matrix(v)``: a new mutable matrix with the entries of ``v``; for a mutable sympy matrix
    its copy (the same entries and domain, about 2 us; the generic constructor parses its input
    again, about 12 us, and the model copies its points and mass centres tens of times a command).
    A column of expressions is copied as ``copy`` copies it (each row's dict copied), its objects
    made by :func:`_exraw_column`."""
    if type(v) is not sp.MutableDenseMatrix:
        return sp.Matrix(v)
    rep = v._rep
    if rep.domain is _EXRAW and type(rep.rep) is _SDM and rep.shape == (2, 1):
        return sp.MutableDenseMatrix._fromrep(_exraw_column({i: r.copy() for i, r in rep.rep.items()}))
    return v.copy()


def vadd(a, *rest) -> sp.Matrix:
    """a + b + ... of 2-vectors, added left to right by components: the entries of sympy's Matrix
    sum (each such sum costs tens of microseconds in sympy's matrix machinery)."""
    x, y = xy(a)
    for v in rest:
        vx, vy = xy(v)
        x, y = x + vx, y + vy
    return vec(x, y)


def vsub(a, b) -> sp.Matrix:
    """a - b of 2-vectors by components (the entries of sympy's Matrix difference)."""
    (ax, ay), (bx, by) = xy(a), xy(b)
    return vec(ax - bx, ay - by)


def vscale(k, v) -> sp.Matrix:
    """k v for a scalar k and a 2-vector v by components (the entries of sympy's ``k * v``)."""
    x, y = xy(v)
    if isinstance(k, sp.Expr):  # a zero component stays 0 without asking k whether it is finite
        return vec(sp.S.Zero if times_zero_is_zero((k, x)) else k * x, sp.S.Zero if times_zero_is_zero((k, y)) else k * y)
    return vec(k * x, k * y)


def rotation(phi: sp.Expr) -> sp.Matrix:
    """R(phi): body frame -> fixed frame."""
    c, s = sp.cos(phi), sp.sin(phi)
    return sp.Matrix([[c, -s], [s, c]])


def _sum_of_products(row, v) -> sp.Expr:
    """sum_k row_k v_k over the pairs with both nonzero: an entry of sympy's Matrix product (its
    sparse product adds exactly those with ``Add``), without the matrix machinery (for finite entries)."""
    return sp.Add(*[a * b for a, b in zip(xy(row), xy(v)) if _nonzero(a) and _nonzero(b)])


def rotate(phi: sp.Expr, v) -> sp.Matrix:
    """R(phi) v for a 2-vector v: the same expressions as ``rotation(phi) * v``, by components
    (2x2 Matrix products cost ~0.1 ms each in sympy); for phi = 0 (the ground's frame) ``v``'s
    entries as they are, what the sums reduce to there."""
    if phi is sp.S.Zero:  # (an exact 0: a float 0.0 would make 1.0*x)
        return vec(*xy(v))
    c, s = sp.cos(phi), sp.sin(phi)
    return vec(_sum_of_products((c, -s), v), _sum_of_products((s, c), v))


def dot(a, b) -> sp.Expr:
    """a . b of 2-vectors: the same expression as ``(a.T * b)[0]``."""
    return _sum_of_products(a, b)


def cross_k(a: sp.Matrix, b: sp.Matrix) -> sp.Expr:
    """k-component of a x b for in-plane vectors."""
    (ax, ay), (bx, by) = xy(a), xy(b)
    return ax * by - ay * bx


def k_cross(w: sp.Expr, r: sp.Matrix) -> sp.Matrix:
    """(w k) x r for an in-plane vector r."""
    x, y = xy(r)
    return vec(-w * y, w * x)


def _unit(angle: sp.Expr) -> sp.Matrix:
    return vec(sp.cos(angle), sp.sin(angle))


def _left_normal(angle: sp.Expr) -> sp.Matrix:
    return vec(-sp.sin(angle), sp.cos(angle))


def _line(pose: Pose, body: str, angle: sp.Expr) -> tuple[sp.Matrix, sp.Matrix]:
    """(direction d, left normal n) in the fixed frame of a line at ``angle`` in ``body``'s frame."""
    phi = pose(body)[1]
    return rotate(phi, _unit(angle)), rotate(phi, _left_normal(angle))


def _at(pose: Pose, body: str, coords: sp.Matrix) -> sp.Matrix:
    origin, phi = pose(body)
    return vadd(origin, rotate(phi, coords))


@dataclass(frozen=True)
class Reaction:
    """One reaction unknown.

    Attributes
    ----------
    name : str
        As the scene names it (``R_A``, ``F_f``, ``M_drive``).
    joint : str
        The joint that brings it.
    unit : str
        ``"N"`` (a force) or ``"N*m"`` (a couple).
    one_sided : bool
        True when it can only push (or, for a cord, only pull): a contact that
        can separate. Simulation stops when it would change sign.
    """

    name: str
    joint: str
    unit: str = "N"
    one_sided: bool = False

    @cached_property
    def symbol(self) -> sp.Symbol:
        """Made once per reaction (it is frozen; sympy's Symbol() costs about 2 us a call)."""
        return sp.Symbol(self.name, real=True)


@dataclass(frozen=True)
class JointLoad:
    """A reaction as a load on one body (for the free-body diagram).

    ``force`` is the 2x1 fixed-frame force per unit reaction (None for a
    couple), applied at fixed-frame position ``at``; ``couple`` is the
    k-moment per unit reaction (0 for a force).
    """

    reaction: Reaction
    body: str
    force: sp.Matrix | None
    at: sp.Matrix | None
    couple: sp.Expr = sp.Integer(0)


@dataclass(eq=False)
class Joint:
    """Base class. Subclasses set :attr:`kind`, :attr:`reaction_units` and the equations.

    Attributes
    ----------
    name : str
    first, second : str
        Body names (``"ground"`` for the fixed frame). Reactions act on
        ``second`` as written and oppositely on ``first``.
    reactions : tuple of Reaction
    """

    kind: ClassVar[str] = ""
    reaction_units: ClassVar[tuple[str, ...]] = ()
    default_one_sided: ClassVar[tuple[bool, ...]] = ()
    placement_priority: ClassVar[int] = 9
    """Order in which joints' equations linear in a body's translation are used to place it."""
    orientation_row: ClassVar[int | None] = None
    """The row that :meth:`orientation_of` satisfies, when the joint can give a body's angle."""
    place_rows: ClassVar[tuple[int, ...]] = ()
    """The rows that :meth:`place` satisfies, when the joint can place a body alone."""

    name: str
    first: str
    second: str
    reactions: tuple[Reaction, ...] = ()

    @property
    def bodies(self) -> tuple[str, str]:
        return (self.first, self.second)

    @property
    def freedoms_removed(self) -> int:
        return len(self.reactions)

    # -- equations -----------------------------------------------------------------
    def rows(self, pose: Pose, t: sp.Symbol) -> list[sp.Expr]:
        """Phi_k(poses, t), one per reaction, in reaction order."""
        raise NotImplementedError

    def loads(self, pose: Pose, t: sp.Symbol) -> list[JointLoad]:
        """Each reaction as unit loads on the second body and, opposite, on the first."""
        out = []
        on_first = self._first_body_point(pose)
        for reaction, (force, at, couple) in zip(self.reactions, self._unit_loads(pose, t)):
            for body, sign in ((self.second, 1), (self.first, -1)):
                out.append(JointLoad(
                    reaction, body,
                    None if force is None else vscale(sign, force),
                    at if body == self.second or on_first is None else on_first,
                    sign * couple,
                ))
        return out

    def _first_body_point(self, pose: Pose) -> sp.Matrix | None:
        """Where the reactions act on the first body when that is its own point (a pin's
        ``at_first``), rather than the second body's point (the same place wherever the joint
        holds); None: the second body's point (:meth:`_unit_loads`)."""
        return None

    def _unit_loads(self, pose: Pose, t: sp.Symbol):
        """(force per unit reaction or None, application point, couple) per reaction."""
        raise NotImplementedError

    # -- placement -----------------------------------------------------------------
    def orientation_of(self, body: str, pose: Pose, t: sp.Symbol) -> sp.Expr | None:
        """The angle of ``body`` implied by this joint, given the other body's pose, or None."""
        return None

    def _relative_orientation(self, body: str, pose: Pose, rel: sp.Expr | None) -> sp.Expr | None:
        """The angle of ``body`` when the second body's angle is the first's plus ``rel``."""
        if rel is None:
            return None
        if body == self.second:
            return pose(self.first)[1] + rel
        if body == self.first:
            return pose(self.second)[1] - rel
        return None

    def place(self, body: str, pose: Pose, t: sp.Symbol) -> sp.Matrix | None:
        """The origin of ``body`` fully fixed by this joint alone (given its angle), or None."""
        return None

    def row_rank(self, k: int) -> int:
        """Preference of row ``k`` for placing a body among this joint's rows (lower first)."""
        return 0

    # -- model limits and contact data ----------------------------------------------
    def limits(self, pose: Pose) -> list[tuple[str, sp.Expr]]:
        """Conditions g >= 0 under which the joint's model holds, with a description."""
        return []

    @property
    def one_sided(self) -> tuple[str, ...]:
        return tuple(r.name for r in self.reactions if r.one_sided)

    @property
    def friction_pair(self):
        """(friction reaction, normal reaction, mu expression or None), or None."""
        return None

    def __repr__(self) -> str:
        names = ", ".join(r.name for r in self.reactions)
        return f"{type(self).__name__}({self.name!r}, {self.first} -> {self.second}, [{names}])"



# --------------------------------------------------------------------------- contacts
class Contact:
    """What every contact joint shares (mixed into :class:`Rail`, :class:`Rolling`
    and :class:`RollingOnCircle`): its rows and loads in each regime of
    :mod:`solver.model.contacts`.

    A contact class provides ``contact_rows(pose) -> (Phi_t, Phi_n)`` (Phi_t
    without the stick phase), ``contact_frame(pose) -> (d, n, at)`` and
    ``as_written`` (the regime the scene states: pure rolling for rolling
    contacts; sliding, :data:`~solver.model.contacts.SLIDING`, for a rail). Its fields
    ``friction`` (:class:`~solver.model.contacts.Friction` or None),
    ``regime``, ``pair`` (the friction and normal reactions, F possibly None)
    and ``phase`` (the stick row's constant) are declared by each class.
    """

    @property
    def current_regime(self) -> Regime:
        return self.regime if self.regime is not None else self.as_written

    @property
    def friction_reaction(self) -> Reaction | None:
        return self.pair[0]

    @property
    def normal_reaction(self) -> Reaction:
        return self.pair[1]

    @property
    def extra_reactions(self) -> tuple:
        """Reactions beyond F and N that hold while the contact touches (a slider's couple)."""
        return ()

    @property
    def needs_regime(self) -> bool:
        """True when the sliding direction, hence the friction force, depends on the motion."""
        return self.current_regime == SLIDING and self.friction is not None

    def in_regime(self, regime: Regime) -> "Joint":
        """A copy of this contact in ``regime`` (its reactions and rows follow the regime).

        A stick regime binds its phase (the constant of the tangential row)
        to the state the copy is made at: where the contact sticks again.
        """
        from dataclasses import replace

        F, N = self.pair
        if regime.keeps_tangential:
            if F is None:
                raise ValueError(f"contact {self.name!r} has no friction reaction to stick with")
            reactions = (F, N, *self.extra_reactions)
        elif regime.keeps_normal:
            reactions = (N, *self.extra_reactions)
        else:
            reactions = ()
        bind = regime.keeps_tangential
        return replace(self, regime=regime, reactions=reactions, phase=sp.Integer(0) if bind else self.phase,
                       phase_from_state=bind or getattr(self, "phase_from_state", False))

    def row_rank(self, k: int) -> int:
        """A sticking contact places a body by its normal row first: its tangential row,
        the one that slipping releases, then stays a closure equation."""
        return 1 if self.current_regime.keeps_tangential and k == 0 else 0

    def _regime_rows(self, pose) -> list[sp.Expr]:
        Pt, Pn = self.contact_rows(pose)
        r = self.current_regime
        if not r.keeps_normal:
            return []
        return [Pt - self.phase, Pn] if r.keeps_tangential else [Pn]

    def _regime_loads(self, pose):
        d, n, at = self.contact_frame(pose)
        r = self.current_regime
        if not r.keeps_normal:
            return []
        if r.keeps_tangential:
            return [(d, at, 0), (n, at, 0)]
        mu = 0 if self.friction is None or not r.friction_direction() else r.coefficient(self.friction)
        return [(vsub(n, vscale(r.friction_direction() * mu, d)), at, 0)]

    @property
    def friction_pair(self):
        """(friction reaction, normal reaction, mu_s or None) while sticking, else None."""
        if not self.current_regime.keeps_tangential:
            return None
        return (self.pair[0].name, self.pair[1].name, None if self.friction is None else self.friction.static)

# --------------------------------------------------------------------------- pin
@dataclass(eq=False, repr=False)
class Pin(Joint):
    """A pin (revolute joint): point ``at_first`` of the first body and
    ``at_second`` of the second coincide. Reactions: the fixed-frame x and y
    components of the force on the second body. Removes 2 freedoms."""

    kind: ClassVar[str] = "pin"
    placement_priority: ClassVar[int] = 0
    reaction_units: ClassVar[tuple[str, ...]] = ("N", "N")
    at_first: sp.Matrix = field(default_factory=lambda: sp.zeros(2, 1))
    at_second: sp.Matrix = field(default_factory=lambda: sp.zeros(2, 1))

    def rows(self, pose, t):
        d = _at(pose, self.second, self.at_second) - _at(pose, self.first, self.at_first)
        return [d[0], d[1]]

    def _unit_loads(self, pose, t):
        at = _at(pose, self.second, self.at_second)
        return [(vec(1, 0), at, 0), (vec(0, 1), at, 0)]

    def _first_body_point(self, pose):
        """The first body's own pin point: its reactions' moment about that point is then zero in
        every configuration, not only where the loop closes (a pin to the ground written
        ``["rocker:O4", "ground:O4"]``: the rocker's moment about its pivot holds no pivot force)."""
        return _at(pose, self.first, self.at_first)


# --------------------------------------------------------------------------- rail
@dataclass(eq=False, repr=False)
class Rail(Contact, Joint):
    """Point ``point`` of the second body moves on the straight line of the
    first body through ``through`` with direction ``angle`` (first body's
    frame). As written, frictionless: one reaction along the line's left
    normal n = (-sin a, cos a), positive pushing the second body along n.

    With ``friction`` (a one-sided contact, e.g. a ladder's foot or a crate's
    corner) it is a :class:`Contact`: sticking adds the friction reaction
    along d = (cos a, sin a) and the row d.(p - o) = phase; sliding puts
    -s mu_k N along d; separating removes the row.
    """

    kind: ClassVar[str] = "rail"
    placement_priority: ClassVar[int] = 4
    reaction_units: ClassVar[tuple[str, ...]] = ("N",)
    as_written: ClassVar[Regime] = SLIDING
    point: sp.Matrix = field(default_factory=lambda: sp.zeros(2, 1))
    through: sp.Matrix = field(default_factory=lambda: sp.zeros(2, 1))
    angle: sp.Expr = sp.Integer(0)
    friction: Friction | None = None
    regime: Regime | None = None
    pair: tuple = ()
    phase: sp.Expr = sp.Integer(0)
    phase_from_state: bool = False

    def __post_init__(self):
        if not self.pair and self.reactions:
            self.pair = (None, self.reactions[0])

    def _normal(self, pose):
        return _line(pose, self.first, self.angle)[1]

    def contact_rows(self, pose):
        d, n = _line(pose, self.first, self.angle)
        rel = vsub(_at(pose, self.second, self.point), _at(pose, self.first, self.through))
        return dot(d, rel), dot(n, rel)

    def contact_frame(self, pose):
        d, n = _line(pose, self.first, self.angle)
        return d, n, _at(pose, self.second, self.point)

    def rows(self, pose, t):
        return self._regime_rows(pose)

    def _unit_loads(self, pose, t):
        return self._regime_loads(pose)


@dataclass(eq=False, repr=False)
class PinInSlot(Rail):
    """A pin of the second body in a straight slot of the first body: the
    same equations as :class:`Rail` (one reaction normal to the slot)."""

    kind: ClassVar[str] = "pin_in_slot"


# --------------------------------------------------------------------------- slider
@dataclass(eq=False, repr=False)
class Slider(Rail):
    """A slider (prismatic joint): the second body translates along the first
    body's line without turning relative to it. Reactions: the normal force
    (along the left normal, at ``point``) and the couple that keeps the
    relative angle at ``relative_angle``. Removes 2 freedoms.

    With ``friction`` (a block resting on a surface, one-sided) it is a
    :class:`Contact` like a rail: sticking adds the friction force and the
    row d.(p - o) = phase, sliding puts -s mu_k N along d, and separating
    (the block lifts off) removes every row, the couple's too."""

    kind: ClassVar[str] = "slider"
    placement_priority: ClassVar[int] = 5
    reaction_units: ClassVar[tuple[str, ...]] = ("N", "N*m")
    relative_angle: sp.Expr = sp.Integer(0)
    couple: Reaction | None = None

    def __post_init__(self):
        super().__post_init__()
        if self.couple is None and len(self.reactions) >= 2:
            self.couple = self.reactions[-1]

    @property
    def extra_reactions(self) -> tuple:
        return () if self.couple is None else (self.couple,)

    @property
    def orientation_row(self) -> int | None:
        """The relative-angle row: last while the slider touches."""
        regime = self.current_regime
        if not regime.keeps_normal:
            return None
        return 2 if regime.keeps_tangential else 1

    def rows(self, pose, t):
        if not self.current_regime.keeps_normal:
            return []
        _, phi1 = pose(self.first)
        _, phi2 = pose(self.second)
        return self._regime_rows(pose) + [phi2 - phi1 - self.relative_angle]

    def _unit_loads(self, pose, t):
        if not self.current_regime.keeps_normal:
            return []
        return self._regime_loads(pose) + [(None, None, 1)]

    def orientation_of(self, body, pose, t):
        if not self.current_regime.keeps_normal:
            return None
        return self._relative_orientation(body, pose, self.relative_angle)


# --------------------------------------------------------------------------- rolling on a line
@dataclass(eq=False, repr=False)
class Rolling(Contact, Joint):
    """Round element of the second body (rim centre ``center``, radius
    ``radius``, body frame) rolls without slipping on the straight line of the
    first body through ``through`` with direction ``angle``, on the side of the
    line's left normal n. Reactions, in order: friction along the line's
    direction d, normal force along n (one-sided), both at the contact point.

    Equations: n.(c - o) - r = 0 (contact) and
    d.(c - o) + r (phi_2 - phi_1 - phi_ref) - s_ref = 0 (no slip, integrated:
    the contact point advances by -r dphi along d; Eq. 31 for Example 2).
    As a :class:`Contact` it may also slip or separate.
    """

    kind: ClassVar[str] = "rolling"
    placement_priority: ClassVar[int] = 1
    reaction_units: ClassVar[tuple[str, ...]] = ("N", "N")
    element: str = ""
    center: sp.Matrix = field(default_factory=lambda: sp.zeros(2, 1))
    radius: sp.Expr = sp.Integer(1)
    through: sp.Matrix = field(default_factory=lambda: sp.zeros(2, 1))
    angle: sp.Expr = sp.Integer(0)
    s_ref: sp.Expr = sp.Integer(0)
    phi_ref: sp.Expr = sp.Integer(0)
    friction: Friction | None = None
    semicircle_axis: sp.Expr | None = None
    regime: Regime | None = None
    pair: tuple = ()
    phase: sp.Expr = sp.Integer(0)
    phase_from_state: bool = False
    as_written: ClassVar[Regime] = STICK

    def __post_init__(self):
        if not self.pair and len(self.reactions) == 2:
            self.pair = tuple(self.reactions)

    def _frame(self, pose):
        return _line(pose, self.first, self.angle)

    def contact_rows(self, pose):
        d, n = self._frame(pose)
        c = _at(pose, self.second, self.center)
        o = _at(pose, self.first, self.through)
        _, phi1 = pose(self.first)
        _, phi2 = pose(self.second)
        return ((d.T * (c - o))[0] + self.radius * (phi2 - phi1 - self.phi_ref) - self.s_ref,
                (n.T * (c - o))[0] - self.radius)

    def rows(self, pose, t):
        return self._regime_rows(pose)

    def contact_point(self, pose) -> sp.Matrix:
        d, n = self._frame(pose)
        return _at(pose, self.second, self.center) - self.radius * n

    def contact_frame(self, pose):
        d, n = self._frame(pose)
        return d, n, self.contact_point(pose)

    def _unit_loads(self, pose, t):
        return self._regime_loads(pose)

    def limits(self, pose):
        if self.semicircle_axis is None:
            return []
        # The contact point lies on the curved rim while the symmetry axis points
        # within 90 deg of -n (towards the surface).
        _, phi1 = pose(self.first)
        _, phi2 = pose(self.second)
        g = sp.cos(phi2 + self.semicircle_axis - (phi1 + self.angle - sp.pi / 2))
        return [(f"the contact point of {self.element!r} ({self.name}) stays on its curved rim", g)]


# --------------------------------------------------------------------------- rolling on a circle
@dataclass(eq=False, repr=False)
class RollingOnCircle(Contact, Joint):
    """Round element of the second body rolls without slipping on a circle of
    the first body (centre ``circle_center``, radius ``circle_radius``, first
    body's frame), outside or inside it. Reactions: friction along the
    tangent e_t = k x e (e the unit vector from the circle's centre to the
    element's), normal force (one-sided) along e outside, -e inside.

    Equations, with psi the angle of e relative to the first body and
    R_c = R + r (outside) or R - r (inside):
    |c - O| - R_c = 0 (outside; R_c - |c - O| inside) and the integrated
    no-slip condition R_c psi -/+ r (phi_2 - phi_1) = const
    (r phi_2' = (R + r) psi' outside, r phi_2' = -(R - r) psi' inside, for a
    fixed circle). ``position_angle`` (an expression in the coordinates), when
    given, places the element: psi = position_angle; the body's angle then
    follows from rolling unless the body gives it.
    """

    kind: ClassVar[str] = "rolling_on_circle"
    orientation_row: ClassVar[int | None] = 0
    place_rows: ClassVar[tuple[int, ...]] = (1,)
    as_written: ClassVar[Regime] = STICK
    reaction_units: ClassVar[tuple[str, ...]] = ("N", "N")
    element: str = ""
    center: sp.Matrix = field(default_factory=lambda: sp.zeros(2, 1))
    radius: sp.Expr = sp.Integer(1)
    circle_center: sp.Matrix = field(default_factory=lambda: sp.zeros(2, 1))
    circle_radius: sp.Expr = sp.Integer(1)
    inside: bool = False
    position_angle: sp.Expr | None = None
    phase: sp.Expr = sp.Integer(0)
    phase_from_state: bool = True
    friction: Friction | None = None
    regime: Regime | None = None
    pair: tuple = ()

    def __post_init__(self):
        if not self.pair and len(self.reactions) == 2:
            self.pair = tuple(self.reactions)

    @property
    def _Rc(self):
        return self.circle_radius - self.radius if self.inside else self.circle_radius + self.radius

    def _geometry(self, pose):
        c = _at(pose, self.second, self.center)
        O = _at(pose, self.first, self.circle_center)
        rel = c - O
        return c, O, rel, self._distance(rel), rel / self._distance(rel)

    def _distance(self, rel):
        """|rel|, the distance of the element's centre from the circle's. The radius of the centre's
        path R +- r itself when the centre is placed on that path (the scene's position angle):
        ``sqrt(R**2 - 2*R*r + r**2)`` carried through the worked solution hid that an inertial term
        is zero. R +- r is positive: the scene refuses an inside circle not larger than the element."""
        d2 = rel[0] ** 2 + rel[1] ** 2
        from ..display import is_identically_zero

        return self._Rc if is_identically_zero(d2 - self._Rc ** 2) else sp.sqrt(d2)

    def contact_rows(self, pose):
        c, O, rel, dist, e = self._geometry(pose)
        _, phi1 = pose(self.first)
        _, phi2 = pose(self.second)
        psi = sp.atan2(rel[1], rel[0]) - phi1
        normal = self._Rc - dist if self.inside else dist - self._Rc
        sign = 1 if self.inside else -1
        return self._Rc * psi + sign * self.radius * (phi2 - phi1), normal

    def rows(self, pose, t):
        return self._regime_rows(pose)

    def contact_point(self, pose):
        c, O, rel, dist, e = self._geometry(pose)
        return c + self.radius * e if self.inside else c - self.radius * e

    def contact_frame(self, pose):
        c, O, rel, dist, e = self._geometry(pose)
        return sp.Matrix([-e[1], e[0]]), (-e if self.inside else e), self.contact_point(pose)

    def _unit_loads(self, pose, t):
        return self._regime_loads(pose)

    def orientation_of(self, body, pose, t):
        if body != self.second or self.position_angle is None or self.current_regime != STICK:
            return None
        _, phi1 = pose(self.first)
        sign = 1 if self.inside else -1
        # from the no-slip equation with psi = position_angle
        return phi1 + (self.phase - self._Rc * self.position_angle) / (sign * self.radius)

    def place(self, body, pose, t):
        if body != self.second or self.position_angle is None or self.current_regime != STICK:
            return None
        origin1, phi1 = pose(self.first)
        _, phi2 = pose(self.second)
        O = origin1 + rotation(phi1) * self.circle_center
        c = O + self._Rc * _unit(phi1 + self.position_angle)
        return c - rotation(phi2) * self.center


# --------------------------------------------------------------------------- gears
@dataclass(eq=False, repr=False)
class GearMesh(Joint):
    """Two pitch circles (round elements, one on each body) mesh without
    slipping, externally or internally (the second inside the first's ring).
    Reaction: the tangential tooth force on the second body at the pitch
    point, along e_t = k x e (e from the first gear's centre to the second's).

    Equation (external): r_1 (phi_1 - psi) + r_2 (phi_2 - psi) = const, psi the
    angle of e; internal: r_1 (phi_1 - psi) - r_2 (phi_2 - psi) = const. The
    constant is the mesh's phase at the scene's state. The centre distance is
    held by the bodies' other joints.
    """

    kind: ClassVar[str] = "gear"
    reaction_units: ClassVar[tuple[str, ...]] = ("N",)
    center_first: sp.Matrix = field(default_factory=lambda: sp.zeros(2, 1))
    center_second: sp.Matrix = field(default_factory=lambda: sp.zeros(2, 1))
    radius_first: sp.Expr = sp.Integer(1)
    radius_second: sp.Expr = sp.Integer(1)
    internal: bool = False
    phase: sp.Expr = sp.Integer(0)
    phase_from_state: bool = True

    def _e(self, pose):
        c1 = _at(pose, self.first, self.center_first)
        c2 = _at(pose, self.second, self.center_second)
        rel = c2 - c1
        dist = sp.sqrt(rel[0] ** 2 + rel[1] ** 2)
        return c1, c2, rel, dist

    def rows(self, pose, t):
        c1, c2, rel, dist = self._e(pose)
        psi = sp.atan2(rel[1], rel[0])
        _, phi1 = pose(self.first)
        _, phi2 = pose(self.second)
        r1, r2 = self.radius_first, self.radius_second
        s = -1 if self.internal else 1
        # signed so that its gradient is the generalized force of a unit tooth force along e_t
        return [-(r1 * (phi1 - psi) + s * r2 * (phi2 - psi)) + self.phase]

    def _unit_loads(self, pose, t):
        c1, c2, rel, dist = self._e(pose)
        e = rel / dist
        et = sp.Matrix([-e[1], e[0]])
        # the pitch point: r_1 from the first centre along e (outside the second's centre for internal)
        at = c1 + self.radius_first * e
        return [(et, at, 0)]


# --------------------------------------------------------------------------- cord on a drum
@dataclass(eq=False, repr=False)
class Cord(Joint):
    """An inextensible cord wound on a drum of the first body (rim centre
    ``center``, radius ``radius``) whose straight free part runs along the
    fixed direction ``direction`` (unit, fixed frame) from the drum to point
    ``point`` of the second body. ``winds`` says which sense of the drum's
    rotation (relative to ... the fixed frame) winds the cord up: ``"ccw"`` or
    ``"cw"``. Reaction: the tension T (one-sided, >= 0), pulling the second
    body towards the drum (along -direction) and the drum along +direction
    at the tangent point.

    Equation: direction.(p - c) + s r phi_1 - length = 0 (s = +1 for ccw,
    -1 for cw), ``length`` the free length when phi_1 = 0; written with the
    sign that makes T the multiplier.
    """

    kind: ClassVar[str] = "cord"
    placement_priority: ClassVar[int] = 3
    reaction_units: ClassVar[tuple[str, ...]] = ("N",)
    default_one_sided: ClassVar[tuple[bool, ...]] = (True,)
    center: sp.Matrix = field(default_factory=lambda: sp.zeros(2, 1))
    radius: sp.Expr = sp.Integer(1)
    direction: sp.Matrix = field(default_factory=lambda: sp.Matrix([0, -1]))
    point: sp.Matrix = field(default_factory=lambda: sp.zeros(2, 1))
    winds: str = "ccw"
    length: sp.Expr = sp.Integer(0)

    @property
    def _s(self):
        return 1 if self.winds == "ccw" else -1

    def rows(self, pose, t):
        p = _at(pose, self.second, self.point)
        c = _at(pose, self.first, self.center)
        _, phi1 = pose(self.first)
        free = (self.direction.T * (p - c))[0]
        return [-(free + self._s * self.radius * phi1 - self.length)]

    def tangent_point(self, pose):
        d = self.direction
        side = sp.Matrix([-d[1], d[0]]) * self._s
        return _at(pose, self.first, self.center) + self.radius * side

    def _unit_loads(self, pose, t):
        return [(-self.direction, _at(pose, self.second, self.point), 0)]

    def loads(self, pose, t):
        reaction = self.reactions[0]
        return [
            JointLoad(reaction, self.second, -self.direction, _at(pose, self.second, self.point)),
            JointLoad(reaction, self.first, sp.Matrix(self.direction), self.tangent_point(pose)),
        ]


# --------------------------------------------------------------------------- drivers
@dataclass(eq=False, repr=False)
class Motor(Joint):
    """A rotary driver: the second body's angle relative to the first is
    ``angle(t)``, or, when ``angle`` is None, is prescribed by the scene's
    coordinates. Reaction: the driving torque on the second body (and its
    opposite on the first). Removes 1 freedom; usually paired with a pin."""

    kind: ClassVar[str] = "motor"
    orientation_row: ClassVar[int | None] = 0
    reaction_units: ClassVar[tuple[str, ...]] = ("N*m",)
    angle: sp.Expr | None = None
    prescribed: sp.Expr | None = None  # set by the system when angle is None

    def rows(self, pose, t):
        _, phi1 = pose(self.first)
        _, phi2 = pose(self.second)
        target = self.angle if self.angle is not None else self.prescribed
        if target is None:
            raise ValueError(f"motor {self.name!r}: its relative angle is not prescribed")
        return [phi2 - phi1 - target]

    def _unit_loads(self, pose, t):
        return [(None, None, 1)]

    def orientation_of(self, body, pose, t):
        return self._relative_orientation(body, pose, self.angle)


@dataclass(eq=False, repr=False)
class Actuator(Joint):
    """A linear driver: point ``point`` of the second body is at distance
    ``position(t)`` from ``through`` along the first body's direction
    ``angle`` (or, when ``position`` is None, the scene's coordinates
    prescribe it). Reaction: the driving force along that direction on the
    second body. Removes 1 freedom; usually paired with a slider."""

    kind: ClassVar[str] = "actuator"
    placement_priority: ClassVar[int] = 2
    reaction_units: ClassVar[tuple[str, ...]] = ("N",)
    point: sp.Matrix = field(default_factory=lambda: sp.zeros(2, 1))
    through: sp.Matrix = field(default_factory=lambda: sp.zeros(2, 1))
    angle: sp.Expr = sp.Integer(0)
    position: sp.Expr | None = None
    prescribed: sp.Expr | None = None

    def _direction(self, pose):
        return _line(pose, self.first, self.angle)[0]

    def rows(self, pose, t):
        p = _at(pose, self.second, self.point)
        o = _at(pose, self.first, self.through)
        target = self.position if self.position is not None else self.prescribed
        if target is None:
            raise ValueError(f"actuator {self.name!r}: its position is not prescribed")
        return [(self._direction(pose).T * (p - o))[0] - target]

    def _unit_loads(self, pose, t):
        return [(self._direction(pose), _at(pose, self.second, self.point), 0)]


JOINT_CLASSES: dict[str, type[Joint]] = {
    cls.kind: cls
    for cls in (Pin, Rail, PinInSlot, Slider, Rolling, RollingOnCircle, GearMesh, Cord, Motor, Actuator)
}
"""Joint kind (the scene's ``kind`` key) -> class."""
