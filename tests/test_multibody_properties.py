"""Properties of random open chains: the answers depend on neither the point
about which each body's moments are taken nor the route.

A random chain (hypothesis) has 2-4 links. The base link hangs from a ground
pin, or rides a slider (it translates along a line at a random angle), or has a
point on a rail (it translates along the line and turns). Each further link is
pinned to the previous one's far end. A link is a slender bar with, sometimes,
a disk or a point mass at an off-axis point X. Loads: gravity, a constant force
at some link's X, a couple on some link, a linear spring from the ground pin to
some link's X. The scene is written as TOML text and read by ``load_system``,
like a user's file. Each link's ``reference_point`` is drawn at random from its
points (P near end, D far end, X, G mass centre); the generalized Euler route
about those points, about every link's X (``--point X``) and the mass-centre
route must give the same accelerations and reactions at several random
states, and so must the Lagrange route (fewer examples: it costs 0.3-2 s per
system).

Tolerance: per entry, 1e-10 of the entry plus 1e-13 x condition number x the
largest entry of the same kind in either answer (forces, moments, and the
accelerations of both coordinate kinds together). Why: the solver and the
comparison both solve linear systems in double precision; the error of such a
solve is bounded by about cond x 2.2e-16 x the size of the solution's entries,
times a modest growth factor (< 1e3) for the round-off made while evaluating
the matrix entries (lambdified expressions of a few hundred operations); cond
is reported by the solver and capped below. An acceleration whose true value
is 0 (a slider at rest in balance) comes out as round-off of the size of the
others: m/s^2 and rad/s^2 are compared on one scale, as the links are 0.2-1.5 m
long (a slider's s_ddot of -1e-16 against -0.0, with no other length
coordinate, failed the per-unit scale).
"""
from __future__ import annotations

import math
import tempfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from solver.formulations import formulate
from solver.io.scenes import load_system

ROOT = Path(__file__).resolve().parents[1]
COND_MAX = 1e7  # random chains worse conditioned than this are skipped (the tolerance scales with cond)
N_STATES = 4  # states per system, solved at once by the vectorised model

_pos = st.floats(0.1, 1.0)


def _clean(strategy):
    """Values as a scene would write them: the quantity guard refuses sizes below 1e-300, so a
    drawn 1e-301 becomes 0 (the same number to any tolerance used here)."""
    return strategy.map(lambda v: 0.0 if abs(v) < 1e-12 else v)
_mass = st.floats(0.2, 5.0)


@st.composite
def chains(draw, max_links: int = 4):
    """(TOML text, number of free coordinates, random states) of a random open chain."""
    n = draw(st.integers(2, max_links))
    base = draw(st.sampled_from(["pin", "slider", "rail"]))
    params = {"g": "9.81 m/s^2", "a0": f"{draw(_clean(st.floats(-60, 60, allow_subnormal=False))):.17g} deg"}
    coords, bodies, joints, loads = [], [], [], []
    for i in range(1, n + 1):
        params[f"L{i}"] = f"{draw(_pos):.17g} m"
        params[f"m{i}"] = f"{draw(_mass):.17g} kg"
        params[f"xx{i}"] = f"{draw(_pos):.17g} m"
        params[f"xy{i}"] = f"{draw(_pos):.17g} m"
        sx, sy = draw(st.sampled_from(["", "-"])), draw(st.sampled_from(["", "-"]))
        elements = [f'{{ name = "bar", kind = "slender_bar", mass = "m{i}", from = "P", to = "D" }}']
        extra = draw(st.sampled_from(["none", "disk", "point_mass"]))
        if extra != "none":
            params[f"me{i}"] = f"{draw(_mass):.17g} kg"
            if extra == "disk":
                params[f"re{i}"] = f"{draw(st.floats(0.02, 0.2)):.17g} m"
                elements.append(f'{{ name = "disk", kind = "uniform_disk", mass = "me{i}", center = "X", radius = "re{i}" }}')
            else:
                elements.append(f'{{ name = "bob", kind = "point_mass", mass = "me{i}", at = "X" }}')
        ref = draw(st.sampled_from(["P", "D", "X", "G"]))
        lines = [f'name = "b{i}"', f'reference_point = "{ref}"',
                 f'points = {{ P = ["0", "0"], D = ["L{i}", "0"], X = ["{sx}xx{i}", "{sy}xy{i}"] }}',
                 f'elements = [{", ".join(elements)}]']
        if i == 1 and base in ("slider", "rail"):
            coords.append(("s", "length"))
            lines.append('position = { point = "P", at = ["s*cos(a0)", "s*sin(a0)"] }')
            kind = "slider" if base == "slider" else "rail"
            joints.append(f'kind = "{kind}"\nname = "base"\npoint = "b1:P"\nangle = "a0"')
        if not (i == 1 and base == "slider"):
            coords.append((f"q{i}", "angle"))
            lines.append(f'orientation = "q{i}"')
        if i == 1 and base == "pin":
            joints.append('kind = "pin"\nname = "base"\nconnects = ["ground:O", "b1:P"]')
        if i > 1:
            joints.append(f'kind = "pin"\nname = "J{i}"\nconnects = ["b{i - 1}:D", "b{i}:P"]')
        bodies.append("\n".join(lines))
    loads.append('kind = "gravity"\ng = "g"')
    if draw(st.booleans()):
        params["Fx"], params["Fy"] = (f"{draw(_clean(st.floats(0.0, 20.0, allow_subnormal=False))):.17g} N" for _ in range(2))
        loads.append(f'kind = "force"\npoint = "b{draw(st.integers(1, n))}:X"\ncomponents = ["Fx", "-Fy"]')
    if draw(st.booleans()):
        params["Cm"] = f"{draw(_clean(st.floats(0.0, 5.0, allow_subnormal=False))):.17g} N*m"
        loads.append(f'kind = "couple"\nbody = "b{draw(st.integers(1, n))}"\nmoment = "-Cm"')
    if draw(st.booleans()):
        params["k_s"], params["l0"] = f"{draw(st.floats(1.0, 100.0)):.17g} N/m", f"{draw(_pos):.17g} m"
        loads.append(f'kind = "spring"\nbetween = ["ground:O", "b{draw(st.integers(1, n))}:X"]\n'
                     'stiffness = "k_s"\nfree_length = "l0"')
    text = ['name = "chain"', "[parameters]", *(f'{k} = "{v}"' for k, v in params.items()), "[coordinates]"]
    for c, kind in coords:
        text.append(f'{c} = {{ value = "{"0.1 m" if kind == "length" else "0.3 rad"}", '
                    f'rate = "{"0 m/s" if kind == "length" else "0 rad/s"}" }}')
    text += ["[ground.points]", 'O = ["0", "0"]']
    text += [f"[[bodies]]\n{b}" for b in bodies]
    text += [f"[[joints]]\n{j}" for j in joints]
    text += [f"[[loads]]\n{ld}" for ld in loads]
    angle = _clean(st.floats(-math.pi, math.pi, allow_subnormal=False))
    states = []
    for _ in range(N_STATES):
        q = [draw(_clean(st.floats(-0.5, 0.5))) if k == "length" else draw(angle) for _, k in coords]
        qd = [draw(_clean(st.floats(-3.0, 3.0))) for _ in coords]
        states.append((q, qd))
    return "\n".join(text) + "\n", len(coords), states


def load(text: str):
    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / "chain.toml"
        path.write_text(text)
        return load_system(path)


def answers(system, method, point, states):
    model = formulate(system, method, point).numeric()
    n = len(system.free)
    q = [np.array([s[0][i] for s in states]) for i in range(n)]
    qd = [np.array([s[1][i] for s in states]) for i in range(n)]
    return model.solve(q, qd, np.zeros(len(states))), model.names


def assert_same(system, a, b, label):
    """Entries of two answers agree (tolerance: module docstring)."""
    cond = np.maximum(a[0]["condition_number"], b[0]["condition_number"])
    units = {str(c.qdd): "acceleration" for c in system.free}
    units.update({r.name: r.unit for r in system.reactions})
    assert set(a[1]) == set(b[1]) == set(units)
    for k in range(len(cond)):
        largest = {}
        for name in a[1]:
            size = max(abs(a[0][name][k]), abs(b[0][name][k]))
            largest[units[name]] = max(largest.get(units[name], 0.0), size)
        for name in a[1]:
            x, y = a[0][name][k], b[0][name][k]
            tol = 1e-10 * abs(x) + 1e-13 * cond[k] * largest[units[name]]
            assert abs(x - y) <= tol, f"{label}, state {k}: {name} = {x!r} vs {y!r} (cond {cond[k]:.3g})"


def _well_posed(system, states):
    res, _ = answers(system, "mass_center", None, states)
    return bool(np.all(res["condition_number"] < COND_MAX))


# The Newton-Euler routes cost ~0.2-0.3 s per route and system (CPU, building and
# lambdifying the equations): 5 examples of 2-4 links, three routes each, at 4
# states each, ~4 s in all (the new multibody tests must stay near 20 s together).
@settings(max_examples=5)
@given(chains())
def test_points_and_newton_euler_routes_agree(chain):
    text, n, states = chain
    system = load(text)
    assert len(system.free) == n
    assume(_well_posed(system, states))
    reference = answers(system, "mass_center", None, states)
    assert_same(system, answers(system, "generalized_euler", None, states), reference, "scene's points")
    assert_same(system, answers(system, "generalized_euler", "X", states), reference, "every body about X")


# The Lagrange route costs 1.5-3.5 s per system of 2-3 links (CPU, measured):
# 2 examples keep this test near 5 s (the Newton-Euler property above covers 4
# links; the six scenes' tests run the Lagrange route on every scene).
@settings(max_examples=2)
@given(chains(max_links=3))
def test_lagrange_route_agrees(chain):
    text, n, states = chain
    system = load(text)
    assume(_well_posed(system, states))
    assert_same(system, answers(system, "lagrange", None, states),
                answers(system, "generalized_euler", None, states), "lagrange vs generalized_euler")



def test_lagrange_equations_are_lagranges_methods():
    """The Lagrange route forms its equations term by term (``lagrange._formed``) rather than
    through ``LagrangesMethod``, to skip the mass and forcing matrices it never reads; the result
    must be the very expression tree (== is structural in sympy) and the multipliers of
    ``LagrangesMethod(...).form_lagranges_equations()`` on the same inputs. The inputs exercise
    every term: a bar in body coordinates (x, y, phi) with a Lagrangian holding gravity, two
    constraint rows (its end pinned at the origin), a force at a point of the bar (through that
    point's velocity) and a couple on its frame (through the frame's angular velocity)."""
    import sympy as sp
    from sympy.physics import mechanics as me

    from solver.formulations.lagrange import _formed

    x, y, phi = me.dynamicsymbols("x y phi")
    m, l, g, c, k = sp.symbols("m l g c k", positive=True)
    N = me.ReferenceFrame("N")
    B = N.orientnew("B", "Axis", [phi, N.z])
    O = me.Point("O")
    O.set_vel(N, 0)
    G = O.locatenew("G", x * N.x + y * N.y)
    G.set_vel(N, x.diff() * N.x + y.diff() * N.y)
    bar = me.RigidBody("bar", G, B, m, (me.inertia(B, 0, 0, m * l**2 / 12), G))
    L = sp.expand(me.Lagrangian(N, bar) - m * g * y)
    rows = [x - l / 2 * sp.cos(phi), y - l / 2 * sp.sin(phi)]
    tip = G.locatenew("T", l / 2 * B.x)
    tip.v2pt_theory(G, N, B)
    forcelist = [(tip, -c * x.diff() * N.x + k * N.y), (B, -c * phi.diff() * N.z)]
    method = me.LagrangesMethod(L, [x, y, phi], hol_coneqs=rows, forcelist=forcelist, frame=N)
    assert _formed(L, [x, y, phi], rows, forcelist, N) == (method.form_lagranges_equations().as_immutable(),
                                                            tuple(method.lam_vec))
