"""Scene objects built directly in Python (independent of the TOML loader).

Example 1 and Example 2 follow the walk-throughs in data/scenes/README.md
(geometry checked against paper Eqs. 17-22 and 31-36); ``composite_scene`` builds random
composite bodies for the hypothesis properties.
"""
from __future__ import annotations

import sympy as sp

from solver.scene import Constraint, Element, Load, Point, Scene
from solver.units import Q_

S = lambda name: sp.Symbol(name, real=True)  # noqa: E731
theta = S("theta")
t = S("t")


def example1(theta_deg=30.0, theta_dot=0.0, beta_deg=45.0, extra_loads=()) -> Scene:
    """Paper Example 1: bar AB, A on a horizontal rail, B on a rail at -beta (Eqs. 16-30)."""
    m_b, l_b, beta, g = S("m_b"), S("l_b"), S("beta"), S("g")
    return Scene(
        name="sliding_bar",
        description="Example 1 (factory)",
        source=None,
        parameters={"m_b": Q_(50, "lbm"), "l_b": Q_(4, "ft"), "beta": Q_(beta_deg, "deg"),
                    "g": Q_(32.174, "ft/s**2")},
        coordinate="theta",
        state={"theta": Q_(theta_deg, "deg"), "theta_dot": Q_(theta_dot, "rad/s")},
        orientation=sp.pi - theta,
        points={
            "A": Point("A", sp.Matrix([0, 0])),
            "B": Point("B", sp.Matrix([l_b, 0])),
            "G": Point("G", sp.Matrix([l_b / 2, 0])),
        },
        elements=(Element("bar", "slender_bar", m_b, sp.Matrix([l_b / 2, 0]), sp.Integer(0), {"length": l_b}),),
        constraints=(
            Constraint("rail_A", "rail", ("R_A",), point="A"),
            Constraint("rail_B", "rail", ("R_B",), point="B", angle=-beta),
        ),
        loads=(Load("gravity", "gravity", magnitude=g), *extra_loads),
        default_point="A",
        output_units={"force": "lbf"},
    )


def example2(theta_deg=10.0, theta_dot=0.0, F_a=None, values=None) -> Scene:
    """Paper Example 2: disk (centre P) rolling on the floor, bar PQ rigidly attached (Eqs. 31-46).

    Values are our own realistic SI choices (the paper gives none).
    """
    m_d, r_d, m_b, l_b, g = S("m_d"), S("r_d"), S("m_b"), S("l_b"), S("g")
    F = S("F_a") if F_a is None else F_a
    params = {"m_d": Q_(4, "kg"), "r_d": Q_(0.25, "m"), "m_b": Q_(1.5, "kg"), "l_b": Q_(0.2, "m"),
              "g": Q_(9.80665, "m/s**2"), "F_a": Q_(0, "N")}
    params.update(values or {})
    return Scene(
        name="disk_bar",
        description="Example 2 (factory)",
        source=None,
        parameters=params,
        coordinate="theta",
        state={"theta": Q_(theta_deg, "deg"), "theta_dot": Q_(theta_dot, "rad/s")},
        orientation=-theta,
        points={
            "P": Point("P", sp.Matrix([0, 0])),
            "Q": Point("Q", sp.Matrix([0, -l_b / 2])),
            "C": Point("C", sp.Matrix([0, -r_d]), frame="instant", relative_to="P"),
        },
        elements=(
            Element("disk", "uniform_disk", m_d, sp.Matrix([0, 0]), sp.Integer(0), {"radius": r_d}),
            Element("bar", "slender_bar", m_b, sp.Matrix([0, -l_b / 2]), -sp.pi / 2, {"length": l_b}),
        ),
        constraints=(Constraint("floor", "rolling", ("F_f", "F_n"), element="disk"),),
        loads=(Load("gravity", "gravity", magnitude=g), Load("push", "force", point="P",
                                                            components=sp.Matrix([F, 0]))),
        default_point="P",
        output_units={},
    )


# ---------------------------------------------------------------------------
# Random composite bodies (hypothesis strategies). Numbers are exact rationals
# so the symbolic work stays small; only theta, theta_dot and t stay symbolic.
from hypothesis import strategies as st  # noqa: E402

KINDS = ("slender_bar", "uniform_disk", "thin_ring", "rectangular_plate", "point_mass", "semicircular_disk")
ROUND = ("uniform_disk", "thin_ring", "semicircular_disk")


def _rat(lo, hi, den=20):
    return st.integers(int(lo * den), int(hi * den)).map(lambda v: sp.Rational(v, den))


def _dims(draw, kind):
    size = _rat(0.1, 1.0)
    return {
        "slender_bar": lambda: {"length": draw(size)},
        "uniform_disk": lambda: {"radius": draw(size)},
        "thin_ring": lambda: {"radius": draw(size)},
        "rectangular_plate": lambda: {"width": draw(size), "height": draw(size)},
        "point_mass": lambda: {},
        "semicircular_disk": lambda: {"radius": draw(size)},
    }[kind]()


@st.composite
def random_scene(draw, constraint=None):
    """A random composite body (1-4 elements) under a random constraint set.

    Points: "A", "B", "K" (random body points), "I" (an instant point at a
    random fixed-frame offset from "K"); "G" is the composite mass centre.
    """
    g = sp.Symbol("g", real=True)
    kind_of_constraint = constraint or draw(st.sampled_from(("pivot", "rolling", "rails")))
    n = draw(st.integers(1, 4))
    coord = _rat(-1, 1)
    elements = []
    for i in range(n):
        kind = draw(st.sampled_from(ROUND if (i == 0 and kind_of_constraint == "rolling") else KINDS))
        elements.append(Element(f"e{i}", kind, draw(_rat(0.2, 5)), sp.Matrix([draw(coord), draw(coord)]),
                                draw(_rat(-3, 3)), _dims(draw, kind)))
    A = sp.Matrix([draw(coord), draw(coord)])
    B = A + sp.Matrix([draw(_rat(0.3, 1.5)), draw(_rat(-1, 1))])
    K = sp.Matrix([draw(coord), draw(coord)])
    points = {
        "A": Point("A", A), "B": Point("B", B), "K": Point("K", K),
        "I": Point("I", sp.Matrix([draw(coord), draw(coord)]), frame="instant", relative_to="K"),
    }
    if kind_of_constraint == "pivot":
        constraints = (Constraint("pin", "pivot", ("R_x", "R_y"), point=draw(st.sampled_from(["A", "K"])),
                                  origin=sp.Matrix([draw(coord), draw(coord)])),)
    elif kind_of_constraint == "rolling":
        constraints = (Constraint("ground", "rolling", ("F_f", "F_n"), element="e0",
                                  origin=sp.Matrix([draw(coord), draw(coord)]), angle=draw(_rat(-0.5, 0.5)),
                                  contact_at_zero=draw(coord)),)
    else:
        a1 = draw(_rat(-1.5, 1.5))
        a2 = a1 + draw(st.sampled_from([-1, 1])) * draw(_rat(0.5, 2.6))  # far from parallel
        constraints = (
            Constraint("rail1", "rail", ("R_1",), point="A", origin=sp.Matrix([draw(coord), draw(coord)]), angle=a1),
            Constraint("rail2", "rail", ("R_2",), point="B", origin=sp.Matrix([draw(coord), draw(coord)]), angle=a2),
        )
    sign = draw(st.sampled_from([1, -1]))
    orientation = sign * theta + draw(_rat(-3, 3))
    qd = sp.Symbol("theta_dot", real=True)
    loads = [Load("gravity", "gravity", magnitude=g,
                  direction=sp.Matrix([0, -1]) if draw(st.booleans()) else
                  sp.Matrix([sp.Rational(3, 5), -sp.Rational(4, 5)]))]
    if draw(st.booleans()):
        loads.append(Load("push", "force", point=draw(st.sampled_from(["A", "B", "K", "I"])),
                          components=sp.Matrix([draw(_rat(-20, 20)) + draw(_rat(-5, 5)) * sp.sin(t),
                                                draw(_rat(-20, 20)) + draw(_rat(-2, 2)) * qd])))
    if draw(st.booleans()):
        loads.append(Load("torque", "couple", magnitude=draw(_rat(-10, 10)) + draw(_rat(-2, 2)) * qd))
    state = {"theta": Q_(float(draw(_rat(-3, 3, 100))), "rad"), "theta_dot": Q_(float(draw(_rat(-3, 3))), "rad/s")}
    return Scene(
        name="random", description="random composite", source=None,
        parameters={"g": Q_(9.81, "m/s**2")}, coordinate="theta", state=state,
        orientation=orientation, points=points, elements=tuple(elements), constraints=constraints,
        loads=tuple(loads), default_point="A",
    )


def chain_toml(rates=(0.0, 0.0, 0.0, 0.0)) -> str:
    """A multibody scene (TOML text): a chain of pinned uniform bars hanging from the ground,
    one angle coordinate each (10, 20, 30, ... deg) with the given rates [rad/s]."""
    coords = "".join(f'q{i} = {{ value = "{10 * i} deg", rate = "{w} rad/s" }}\n'
                     for i, w in enumerate(rates, start=1))
    bodies = "".join(f"""
[[bodies]]
name = "b{i}"
orientation = "q{i}"
points = {{ O = ["0", "0"], E = ["l", "0"] }}
elements = [{{ kind = "slender_bar", mass = "m", from = "O", to = "E" }}]
[[joints]]
kind = "pin"
connects = ["{'ground:O' if i == 1 else f'b{i - 1}:E'}", "b{i}:O"]
""" for i in range(1, len(rates) + 1))
    return f"""
name = "chain{len(rates)}"
[parameters]
m = "1 kg"
l = "0.5 m"
g = "9.80665 m/s^2"
[coordinates]
{coords}[ground.points]
O = ["0", "0"]
{bodies}
[[loads]]
kind = "gravity"
g = "g"
"""
