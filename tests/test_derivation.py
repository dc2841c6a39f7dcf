"""The derivation API: contract shapes, errors, kinematics of named points, caching,
vectorised numerics.

References: Example 2's kinematics as printed in the paper (Eqs. 31-33, 38)
written in sympy below; everything else is checked against the contract
(the solver's documented API) or against another route.
"""
from __future__ import annotations

import dataclasses
import json
import math

import numpy as np
import pytest
import sympy as sp

from solver.derivation import (
    METHODS,
    as_system,
    derive,
    natural_frequency,
    solve_instant,
)
from solver.errors import NoRestoringError, SceneError, SingularConfigurationError
from solver.scene import Constraint, Element, Load, Point, Scene
from solver.units import Q_

from scenes_factory import example1, example2

S = lambda n: sp.Symbol(n, real=True)  # noqa: E731
th, thd, thdd = S("theta"), S("theta_dot"), S("theta_ddot")
r_d, l_b = S("r_d"), S("l_b")


def is_zero(expr) -> bool:
    return sp.simplify(sp.expand(expr)) == 0


# -- errors -----------------------------------------------------------------------
def test_unknown_method_lists_methods():
    with pytest.raises(ValueError) as err:
        derive(example1(), None, "newton")
    for m in METHODS:
        assert m in str(err.value)


def test_unknown_point_names_point_and_lists_points():
    with pytest.raises(SceneError, match=r"'Z'.*A, B, G"):
        solve_instant(example1(), "Z")


def test_parallel_rails_impossible_geometry():
    # beta = 0: both rails horizontal
    with pytest.raises(SceneError, match="impossible geometry.*parallel"):
        solve_instant(example1(beta_deg=0.0))
    with pytest.raises(SceneError, match="impossible geometry"):
        solve_instant(example1(beta_deg=180.0))


def _point_mass_pendulum(orientation, mass_at_pivot=True):
    c = sp.zeros(2, 1) if mass_at_pivot else sp.Matrix([0, -1])
    return Scene(
        name="pm", description="", source=None, parameters={"g": Q_(9.81, "m/s**2")},
        coordinate="theta", state={"theta": Q_(0.0, "rad"), "theta_dot": Q_(0.0, "rad/s")},
        orientation=orientation, points={"O": Point("O", sp.zeros(2, 1))},
        elements=(Element("bob", "point_mass", sp.Integer(2), c),),
        constraints=(Constraint("pin", "pivot", ("R_x", "R_y"), point="O"),),
        loads=(Load("gravity", "gravity", magnitude=S("g")),), default_point="O",
    )


def test_singular_configuration_names_theta_constraint_and_condition():
    # A point mass sitting on the pivot has no inertia about it: theta_ddot is undetermined.
    scene = _point_mass_pendulum(th)
    with pytest.raises(SingularConfigurationError) as err:
        solve_instant(scene)
    msg = str(err.value)
    assert "theta = 0" in msg and "pin" in msg and "condition number" in msg
    assert "nan" not in msg.lower()


def test_stationary_orientation_is_singular_at_that_theta():
    # phi = theta^2: phi'(0) = 0, the body cannot turn at theta = 0 (M(0) = 0)
    scene = _point_mass_pendulum(th**2, mass_at_pivot=False)
    with pytest.raises(SingularConfigurationError, match="theta = 0 deg"):
        solve_instant(scene)
    # ... but the model is fine elsewhere (vectorised call, finite values)
    res = derive(scene).numeric().solve(np.array([0.5, 1.0]), np.array([0.0, 0.3]))
    assert np.all(np.isfinite(res["theta_ddot"]))


def test_wrong_reaction_count():
    s = example1()
    bad = dataclasses.replace(s, constraints=s.constraints[:1])
    with pytest.raises(SceneError, match=r"under-constrained: 1 body x 3 freedoms - 1 removed .* = 2, and the scene fixes motions that no joint holds"):
        derive(bad)


# -- results, units, JSON ------------------------------------------------------------
def test_instant_solution_contract_and_units():
    s = example1()
    sol = solve_instant(s)
    assert set(sol.unknowns) == {"alpha", "theta_ddot", "R_A", "R_B"}
    assert str(sol.unknowns["alpha"].units) == "radian / second ** 2"
    d = sol.to_dict(s.output_units)
    json.dumps(d)
    assert d["unknowns"]["R_A"]["unit"] == "lbf"
    assert d["unknowns"]["alpha"]["unit"] == "rad/s**2"
    # lbf value = N value / (0.45359237 kg * 9.80665 m/s^2), exactly by definition
    n = sol.unknowns["R_A"].to("N").magnitude
    assert d["unknowns"]["R_A"]["value"] == pytest.approx(n / (0.45359237 * 9.80665), rel=1e-12)
    Q_(1, d["unknowns"]["R_A"]["unit"])  # pint-parsable
    assert all(math.isfinite(v["value"]) for v in d["unknowns"].values())
    assert math.isfinite(d["condition_number_estimate"]) and d["condition_number_estimate"] >= 1


def test_frequency_result_dict():
    f = natural_frequency(example2()).to_dict()
    assert f["omega_n"]["unit"] == "rad/s"
    assert f["period"]["value"] == pytest.approx(2 * math.pi / f["omega_n"]["value"])


def test_frequency_from_the_callers_one_dof_model_is_the_same():
    """The caller's one-degree-of-freedom model (with reactions, as the report builds it) gives
    the frequency natural_frequency finds with its own model: the same M and V, so equal floats."""
    from solver.period import OneDofSystem

    scene = example2(theta_deg=20.0)
    shared = natural_frequency(scene, one_dof=OneDofSystem.from_derivation(derive(scene)))
    assert shared.to_dict() == natural_frequency(scene).to_dict()


def test_reactions_and_units_attributes():
    d = derive(example2(), "P")
    assert [str(u) for u in d.unknowns] == ["theta_ddot", "F_f", "F_n"]
    assert d.reaction_units == {"F_f": "N", "F_n": "N"}
    # symbolic reactions agree with the numeric solve
    s = example2(theta_deg=20.0, theta_dot=1.0)
    d = derive(s, "Q")
    sol = solve_instant(s, "Q")
    vals = {**s.si_values(), th: math.radians(20.0), thd: 1.0, S("t"): 0.0}
    for name, expr in d.reactions.items():
        assert float(expr.subs(vals)) == pytest.approx(sol.unknowns[name].magnitude, rel=1e-10)
    assert float(d.qdd_solution.subs(vals)) == pytest.approx(sol.unknowns["theta_ddot"].magnitude, rel=1e-10)


# -- kinematics of named points (Eqs. 31-33, 38) ----------------------------------
def test_example2_point_kinematics():
    d = derive(example2(), "P")
    # Eq. (31): x_P = r_d theta on the floor y = r_d
    assert is_zero(d.position("P")[0] - r_d * th) and is_zero(d.position("P")[1] - r_d)
    # Eq. (32): r_Q/P = -(l_b/2)(sin th, cos th)
    rQP = d.position("Q") - d.position("P")
    assert is_zero(rQP[0] + l_b / 2 * sp.sin(th)) and is_zero(rQP[1] + l_b / 2 * sp.cos(th))
    # Eq. (33): omega = -theta_dot, alpha = -theta_ddot
    assert d.omega == -thd and d.alpha == -thdd
    # Eq. (38): a_Q
    aQ = d.acceleration("Q")
    assert is_zero(aQ[0] - (r_d * thdd + l_b / 2 * (thd**2 * sp.sin(th) - thdd * sp.cos(th))))
    assert is_zero(aQ[1] - l_b / 2 * (thd**2 * sp.cos(th) + thdd * sp.sin(th)))
    # C is an instant point: the material point at the contact has zero velocity
    # (rolling without slip) and acceleration r_d theta_dot^2 j, though its
    # geometric position r_d theta i moves.
    assert is_zero(d.velocity("C")[0]) and is_zero(d.velocity("C")[1])
    assert is_zero(d.acceleration("C")[0]) and is_zero(d.acceleration("C")[1] - r_d * thd**2)
    assert is_zero(d.position("C")[0] - r_d * th) and d.position("C")[1] == 0


def test_mass_properties_accessors():
    d = derive(example2(), "P")
    m_d, m_b = S("m_d"), S("m_b")
    # Eq. (35): I_P = 1/2 m_d r_d^2 + 1/3 m_b l_b^2
    assert is_zero(d.inertia_about("P") - (m_d * r_d**2 / 2 + m_b * l_b**2 / 3))
    assert is_zero(d.total_mass - (m_d + m_b))
    # Eq. (13)
    assert is_zero(d.mass_center()[1] + m_b * l_b / 2 / (m_d + m_b))
    assert set(d.element_mass_centers) == {"disk", "bar"}
    # G (unnamed in this scene) is accepted as a point: the composite mass centre
    assert is_zero(d.position("G")[1] - (r_d - m_b * l_b * sp.cos(th) / 2 / (m_d + m_b)))
    # the instant point's inertia, I_C = I_P + m r^2 - 2 ... evaluated through Eq. (12)
    rel = d.position("C") - d.element_mass_centers["bar"]
    I_C = m_d * r_d**2 / 2 + m_d * r_d**2 + m_b * l_b**2 / 12 + m_b * (rel[0] ** 2 + rel[1] ** 2)
    assert is_zero(d.inertia_about("C") - I_C)


def test_eom_is_eq44_with_the_sign_of_F_a_corrected():
    # Reference: the paper's Eq. 44 written here, with +F_a r_d on the right (the
    # paper prints -F_a r_d; Eqs. 39 and 42 give +), for every route.
    m_d, m_b, g, F_a = S("m_d"), S("m_b"), S("g"), S("F_a")
    eq44 = (((sp.Rational(3, 2) * m_d + m_b) * r_d**2 + m_b * l_b**2 / 3 - m_b * r_d * l_b * sp.cos(th)) * thdd
            + m_b * r_d * l_b * sp.sin(th) * thd**2 / 2 + m_b * g * l_b * sp.sin(th) / 2 - F_a * r_d)
    for method in METHODS:
        d = derive(example2(), "P", method)
        assert is_zero(d.eom - eq44), method


def test_linear_system_shape_and_equation_refs():
    d = derive(example1(), "A")
    A, b = d.linear_system()
    assert A.shape == (3, 3) and b.shape == (3, 1)
    assert [e.ref for e in d.equations] == ["Eq. (1)", "Eq. (1)", "Eq. (10)"]
    d2 = derive(example2(), "P")
    assert [e.ref for e in d2.equations] == ["Eq. (14)", "Eq. (14)", "Eq. (11)"]
    # the equations are exactly A x - b
    A2, b2 = d2.linear_system()
    x = sp.Matrix(d2.unknowns)
    for i, e in enumerate(d2.equations):
        assert sp.expand(e.expr - (A2 * x)[i] + b2[i]) == 0


# -- caching and numerics --------------------------------------------------------------
def test_cache_per_scene_point_method():
    s = example1()
    d1 = derive(s, "A")
    assert derive(s, "A") is d1 and derive(s) is d1  # default point is A
    assert derive(s, "B") is not d1
    assert derive(example1(), "A") is not d1  # another scene object
    assert d1.numeric() is d1.numeric()
    as_system(s).reset()  # the model changed: every derived result is forgotten
    assert derive(s, "A") is not d1


def test_numeric_is_vectorised_and_matches_solve_instant():
    s = example2(theta_deg=10.0, theta_dot=0.5)
    nm = derive(s).numeric()
    q = np.linspace(-1, 1, 7)
    res = nm.solve(q, 0.5)
    assert res["theta_ddot"].shape == (7,)
    assert np.all(np.isfinite(res["F_f"]))
    one = solve_instant(s)
    r1 = nm.solve(math.radians(10.0), 0.5)
    assert float(r1["F_n"]) == pytest.approx(one.unknowns["F_n"].magnitude, rel=1e-12)
    A, b = nm.matrices(q, 0.5)
    assert A.shape == (7, 3, 3) and b.shape == (7, 3)


def test_explicit_position_equals_constraint_placement():
    # Example 1 with A's position given explicitly, x_A = l_b sin(beta - theta)/sin(beta)
    s = example1(theta_deg=35.0, theta_dot=0.7)
    beta = S("beta")
    pos = sp.Matrix([l_b * sp.sin(beta - th) / sp.sin(beta), 0])
    explicit = dataclasses.replace(s, position=("A", pos))
    a = solve_instant(s, "B").unknowns
    b = solve_instant(explicit, "B").unknowns
    for k in a:
        assert b[k].magnitude == pytest.approx(a[k].magnitude, rel=1e-12)
    # a position that breaks a rail is refused
    bad = dataclasses.replace(s, position=("A", sp.Matrix([l_b * sp.cos(th), 0])))
    with pytest.raises(SceneError, match="joint\\(s\\) 'rail_B' are not satisfied"):
        derive(bad)


def test_symbolic_reactions_regular_where_the_system_is():
    # theta = 0 is a regular configuration of Example 2: the symbolic reactions
    # must evaluate there (no spurious 1/sin(theta) from pivoting).
    s = example2(theta_deg=0.0, theta_dot=0.0)
    d = derive(s, "P")
    vals = {**s.si_values(), th: 0.0, thd: 0.0, S("t"): 0.0}
    sol = solve_instant(s, "P")
    for name, expr in d.reactions.items():
        v = complex(expr.subs(vals))
        assert v.imag == 0 and math.isfinite(v.real)
        assert v.real == pytest.approx(sol.unknowns[name].magnitude, rel=1e-12, abs=1e-12)
