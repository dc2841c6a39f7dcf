"""Scene objects built directly in Python (independent of the TOML loader).

Example 1 and Example 2 follow /work/notes/example_scenes.md (geometry checked
against paper Eqs. 17-22 and 31-36); ``composite_scene`` builds random
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
