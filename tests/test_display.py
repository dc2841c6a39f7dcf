"""Display forms built from structure (solver/display.py): no printed coefficient that
sin^2 + cos^2 = 1 reduces to a constant, and never a different value."""
from __future__ import annotations

import random

import pytest

import sympy as sp

from solver.display import is_identically_zero, numerator_reduces_to_zero, reduce_trig, tidy
from trees import same_tree

phi, beta, g, m, t, W = sp.symbols("phi beta g m t Omega", real=True)
s, c = sp.sin(phi), sp.cos(phi)


def _at(expr, point: dict) -> float:
    """``expr`` in double precision at ``point`` (Symbol -> float): the symbols replaced by sympy
    Floats, each node evaluated as it is rebuilt, sympy's own arithmetic as in ``expr.subs(point)``
    but some 8 times cheaper (subs sorts and matches its arguments first). The tests' tolerances
    assume a double-precision evaluation, which this is."""
    return float(expr.xreplace({x: sp.Float(v) for x, v in point.items()}))


def test_the_issue_denominator_is_three():
    # issue 11: F_f = -g*m*sin(phi)/(2 s^4 + 4 s^2 c^2 + s^2 + 2 c^4 + c^2); the denominator is 3
    shown = tidy(-g * m * s / (2 * s**4 + 4 * s**2 * c**2 + s**2 + 2 * c**4 + c**2))
    assert shown == -g * m * s / 3


def test_pythagoras_inside_a_coefficient_of_time():
    expr = g * sp.cos(W * t) * (sp.sin(beta) ** 2 + sp.cos(beta) ** 2) / (sp.sin(beta) ** 2 + sp.cos(beta) ** 2 + 1)
    assert tidy(expr) == g * sp.cos(W * t) / 2


def test_tidy_keeps_the_value():
    """Random rational functions in sin/cos: the tidied form has the same value at random
    points (to 1e-12 relative: double-precision evaluation of expressions of a few dozen terms)."""
    rng = random.Random(7)
    pieces = [s, c, s**2, c**2, s * c, sp.sin(beta), sp.cos(beta) ** 2, g, m]
    for _ in range(15):
        num = sum(rng.randint(-3, 3) * rng.choice(pieces) * rng.choice(pieces) for _ in range(4))
        den = 1 + s**2 + c**2 + rng.randint(0, 2) * sp.cos(beta) ** 2
        expr = num / den
        shown = tidy(expr)
        for _ in range(3):
            point = {x: rng.uniform(0.1, 1.4) for x in (phi, beta, g, m)}
            a, b = _at(expr, point), _at(shown, point)
            assert abs(a - b) <= 1e-12 * max(1.0, abs(a))


def test_zero_is_decided_exactly():
    assert is_identically_zero(sp.sin(phi - beta) - (s * sp.cos(beta) - c * sp.sin(beta)))
    assert is_identically_zero(s**2 + c**2 - 1)
    assert not is_identically_zero(s**2 - c**2)
    assert reduce_trig(sp.sin(sp.cos(phi))) is None


def test_numerator_reduction_decides_zero_through_denominators():
    """The exact test without cancel: zero only where sin^2 + cos^2 = 1 makes it so, also across
    denominators and tangents; a residual of (sin^2 + cos^2 - 1) times anything nonzero is not zero."""
    assert numerator_reduces_to_zero((1 - c**2) / s - s)
    assert numerator_reduces_to_zero(sp.tan(phi) * c - s)
    assert numerator_reduces_to_zero(sp.sin(2 * phi) / c - 2 * s)
    assert not numerator_reduces_to_zero((1 - c**2) / s - c)
    assert numerator_reduces_to_zero(sp.sin(sp.cos(phi))) is None
    rng = random.Random(11)
    pieces = [s, c, s**2, c * sp.sin(beta), sp.cos(beta) ** 2, g, m]
    for _ in range(10):
        num = sum(rng.randint(1, 3) * rng.choice(pieces) * rng.choice(pieces) for _ in range(3))
        den = 2 + s**2 + rng.randint(0, 2) * sp.cos(beta) ** 2
        assert numerator_reduces_to_zero(num / den - num * (s**2 + c**2) / den)
        assert not numerator_reduces_to_zero(num / den - (num + g) * (s**2 + c**2) / den)


def test_the_polynomial_route_decides_what_it_can_and_leaves_the_rest():
    """The sparse-polynomial route (rational functions of symbols and sin/cos/tan/cot of symbols)
    decides by construction: zero for (sin^2 + cos^2)^k - 1 times anything, over any denominator,
    with odd and even powers of sin up to 7; nonzero once a term is added. It leaves (None) what is
    not such a function, and an expression whose denominator vanishes identically."""
    from solver.display import _ring_numerator_zero

    one = s**2 + c**2
    rng = random.Random(5)
    pieces = [s, c, s**3, c * sp.sin(beta) ** 2, sp.tan(beta), sp.cot(phi), g / m, phi]
    for _ in range(12):
        num = sum(rng.randint(-3, 3) * rng.choice(pieces) * rng.choice(pieces) for _ in range(3)) + s**7
        den = 2 + s**2 + rng.randint(0, 2) * sp.cos(beta) ** 2 * g
        k = rng.randint(1, 3)
        assert _ring_numerator_zero(num / den - num * one**k / den) is True
        assert _ring_numerator_zero(num / den - num * one**k / den + rng.choice(pieces) / 5) is False
    assert _ring_numerator_zero(phi - s) is False  # the angle itself is not a function of sin and cos
    assert _ring_numerator_zero(sp.Rational(3, 4) - sp.Rational(3, 4)) is True
    for outside in (sp.sin(2 * phi) - 2 * s * c, sp.Float(0.25) * g * s - s, sp.sqrt(g) * s, sp.pi * s,
                    g / (one - 1)):
        assert _ring_numerator_zero(outside) is None
    assert numerator_reduces_to_zero(sp.sin(2 * phi) - 2 * s * c)  # (decided once sin(2 phi) is written out)



def test_sums_and_multiples_of_angles_are_decided_by_the_polynomial_route(monkeypatch):
    """sin/cos/tan of a sum or a multiple of angles (Example 1's residuals hold cos(beta - theta),
    also in a denominator) are written out, and the sparse-polynomial route decides: zero for the
    addition and double-angle identities, nonzero once a term is added; the expression route
    (its common denominator by ``_together``) is never asked."""
    import solver.display as display

    def expression_route(e):
        raise AssertionError("the expression route was taken")

    monkeypatch.setattr(display, "_together", expression_route)
    den = sp.sin(beta) ** 2 + 3 * sp.cos(beta) * c * sp.cos(beta - phi)
    identities = (sp.cos(beta - phi) - sp.cos(beta) * c - sp.sin(beta) * s,
                  sp.sin(2 * phi) - 2 * s * c,
                  sp.tan(phi + beta) * (1 - sp.tan(phi) * sp.tan(beta)) - sp.tan(phi) - sp.tan(beta))
    for identity in identities:
        assert numerator_reduces_to_zero(g * identity / den) is True
        assert numerator_reduces_to_zero(g * identity / den + m * s / den) is False

def test_a_constant_ratio_is_found_exactly():
    """constant_value: k for (k num + (sin^2 + cos^2 - 1) anything) / num, by construction; None
    for a ratio that varies or one outside the polynomial route; 0 for zero."""
    from solver.display import constant_value

    rng = random.Random(3)
    pieces = [s, c**3, sp.tan(beta), g, m * sp.cos(beta), phi]
    for _ in range(10):
        num = sum(rng.randint(1, 4) * rng.choice(pieces) * rng.choice(pieces) for _ in range(3)) + s
        k = sp.Rational(rng.randint(-9, 9), rng.randint(1, 5))
        assert constant_value((k * num + (s**2 + c**2 - 1) * rng.choice(pieces)) / num) == k
        assert constant_value((k * num + g * s) / num) is None
    assert constant_value(sp.Rational(-3, 4)) == sp.Rational(-3, 4)
    assert constant_value((s**2 + c**2 - 1) / g) == 0
    assert constant_value(sp.sqrt(g) / sp.sqrt(g * (s**2 + c**2))) is None


def test_eom_mass_is_the_generalized_mass_of_the_kinetic_energy(capsys):
    """`eom` prints M as the theta_ddot coefficient of the projected equation of motion: it must be
    2 T / theta_dot^2 (exact identity after reduction modulo sin^2 + cos^2 = 1)."""
    import json

    from solver.__main__ import main
    from solver.expressions import parse_expression
    from solver.io.scenes import load_system

    for scene in ("sliding_bar", "disk_bar", "wheel_on_incline"):
        path = f"data/scenes/{scene}.toml"
        assert main(["eom", path, "--json"]) == 0
        payload = json.loads(capsys.readouterr().out)
        system = load_system(path)
        c = system.free[0]
        names = {**system.symbols, c.name: c.q, f"{c.name}_dot": c.qd, "t": system.t}
        shown = parse_expression(payload["mass"][0][0], names, where=scene)
        assert is_identically_zero(sp.expand(shown - sp.diff(system.kinetic_energy(), c.qd, 2)))


def test_the_fast_together_is_sympys_together():
    """display._together replaces sympy.together (and tidy_fraction's gathering replaces gcd_terms)
    for speed: it must build the very same expression, so the printed forms do not change. Random
    sums of fractions with symbol, sin/cos and sum denominators, compared structurally."""
    from solver.display import _together

    a, b = sp.symbols("a b", real=True)
    rng = random.Random(5)
    pieces = [s, c, 1 / sp.sin(beta), a, 1 / b, sp.Rational(1, 3), -sp.Rational(5, 6), 1 / (a + b),
              1 / (2 * a + 2 * b) ** 2, 1 / (3 * a - 6 * c), sp.Rational(2, 3) / (a**2 + b), (a - b) ** 2, sp.sqrt(a)]
    for _ in range(100):  # ~0.9 s
        e = sum(rng.randint(-4, 4) * rng.choice(pieces) * rng.choice(pieces) * rng.choice(pieces)
                for _ in range(rng.randint(1, 4)))
        for expr in (e, sp.expand(e)):
            assert same_tree(_together(expr), sp.together(expr))


def test_the_single_term_fraction_is_sympys_cancel():
    """display._single_term_fraction replaces fraction(cancel(...)) for one term over sums (the
    disk-bar's l_b m_b cos(theta)/(2 (m_b + m_d))) for speed: it must give the very same numerator
    and denominator. Random terms over products of sums, with generators shared between numerator
    and denominator (m_b above), integer contents in common, and powers of sums; compared
    structurally, and the fast path must actually be taken on most of them."""
    from solver.display import _single_term_fraction, _together

    a, b, x = sp.symbols("a b x", real=True)
    gens = [a, b, x, c, s, beta]
    rng = random.Random(11)
    taken = 0
    for _ in range(200):  # ~1.2 s; most take the fast path (asserted below)
        num = sp.Rational(rng.choice([-12, -3, -1, 1, 2, 4, 6]), rng.randint(1, 6))
        for _ in range(rng.randint(0, 3)):
            num *= rng.choice(gens) ** rng.choice([1, 1, 2, -1])
        den = 1
        for _ in range(rng.randint(1, 2)):
            den *= sum(rng.randint(1, 6) * rng.choice(gens) ** rng.randint(1, 2)
                       for _ in range(rng.randint(2, 3))) ** rng.choice([1, 1, 2])
        e = num / (den * rng.choice([1, 1, -1, 2, a + 1]))
        fast = _single_term_fraction(e)
        if fast is not None:
            taken += 1
            assert same_tree(fast, sp.fraction(sp.cancel(_together(e)))), e
    assert taken > 100


def test_the_fast_factor_terms_is_sympys():
    """display.factor_monomial_terms replaces sympy.factor_terms on sums of monomials (the display
    of a coefficient over a number) for speed: the very same expression, tree for tree, so the
    printed forms do not change. Random sums with rational coefficients (300: some all negative, some
    with a common monomial, some with an integer term beside fractions) and two that leave the fast
    path (a power of a sum, a function of a sum)."""
    from solver.display import factor_monomial_terms

    x = sp.Symbol("x", real=True)
    gens = [x, g, m, s, c, sp.sin(beta), sp.cos(beta)]
    rng = random.Random(1)
    for _ in range(300):  # ~0.8 s: every branch (signs, common monomials, kept denominators) comes up
        terms = []
        for _ in range(rng.randint(1, 5)):
            mono = sp.Rational(rng.choice([-1, 1]) * rng.randint(1, 12), rng.randint(1, 6))
            for gen in rng.sample(gens, rng.randint(0, 3)):
                mono *= gen ** rng.randint(1, 3)
            terms.append(mono)
        if rng.random() < 0.3:
            common = rng.choice(gens) ** rng.randint(1, 2) * sp.Rational(rng.randint(1, 5), rng.randint(1, 4))
            terms = [t * common for t in terms]
        p = sp.expand(sp.Add(*terms))
        assert same_tree(factor_monomial_terms(p), sp.factor_terms(p)), p
    for other in (g * (x + m) ** 2 / 2 + g * m / 2, sp.sin(x + m) / 3 + m / 6):
        assert same_tree(factor_monomial_terms(other), sp.factor_terms(other))


def test_a_plain_monomial_is_left_as_it_is():
    """tidy returns a rational times symbols and sin/cos of symbols (to positive powers) at once;
    the general path (solver.display._tidy_general) must agree, tree for tree, on such monomials."""
    from solver.display import _plain_monomial, _tidy_general

    rng = random.Random(11)
    factors = [phi, beta, g, m, s, c, sp.sin(beta), sp.cos(beta), s**2, c**3, sp.sin(beta) ** 4, g**2]
    coefficients = [sp.Integer(1), sp.Integer(-1), sp.Rational(1, 2), sp.Rational(-3, 4), sp.Integer(12)]
    for _ in range(60):
        mono = rng.choice(coefficients) * sp.Mul(*rng.sample(factors, rng.randint(1, 4)))
        assert _plain_monomial(mono)
        assert same_tree(_tidy_general(mono), mono)
    # not plain: a sum, a denominator, an argument that is not a symbol
    for other in (phi + g, g / m, sp.sin(2 * phi) * g, sp.Rational(1, 2)):
        assert not _plain_monomial(other)


def test_the_tree_walks_are_sympys():
    """_nodes and tree_size walk the tree with a list for a stack: the same nodes as sympy's atoms and
    the same count as preorder_traversal, on expressions with shared and nested subtrees."""
    from solver.display import _nodes, tree_size

    rng = random.Random(5)
    pieces = [s, c, s**2, 1 / c, sp.sin(beta) ** 3, g, m / 2, sp.sqrt(g * m), (g + m) ** -2]
    for _ in range(40):
        e = sp.Add(*[rng.choice(pieces) * rng.choice(pieces) for _ in range(rng.randint(1, 5))])
        e = e / (1 + rng.choice(pieces)) if rng.random() < 0.5 else e
        assert _nodes(e, sp.Pow) == e.atoms(sp.Pow)
        assert _nodes(e, (sp.sin, sp.cos)) == e.atoms(sp.sin, sp.cos)
        size = sum(1 for _ in sp.preorder_traversal(e))
        assert tree_size(e) == size
        # capped: the same count up to the cap, past it only "more than the cap"
        for cap in (size - 1, size, size + 1):
            assert (tree_size(e, cap) > cap) == (size > cap) and min(tree_size(e, cap), cap) == min(size, cap)


def test_terms_by_power_of_the_rate_as_collect():
    """derivation._by_powers groups an expanded polynomial in theta_dot as sympy.collect(...,
    evaluate=False) does, tree for tree (the eom display tidies each group on its own)."""
    from solver.derivation import _by_powers

    w = sp.Symbol("theta_dot", real=True)
    rng = random.Random(3)
    pieces = [w, w**2, 2 * w, -w / 3, s, g * m, c**2, sp.Rational(3, 2), w**3 * g, sp.sin(beta) / c]
    for _ in range(60):
        e = sp.expand(sum(rng.choice(pieces) * rng.choice(pieces) * rng.choice(pieces) for _ in range(rng.randint(1, 6))))
        ours, theirs = _by_powers(e, w), sp.collect(e, w, evaluate=False)
        assert ours.keys() == theirs.keys() and all(same_tree(v, theirs[k]) for k, v in ours.items())


def test_tidy_linear_removes_the_collected_terms_as_expand_does():
    """display._without_factor(rest, v) is expand(rest - rest.coeff(v)*v) on expanded sums (the
    route tidy_linear took before), tree for tree."""
    from solver.display import _without_factor

    qdd, qd, R = sp.symbols("theta_ddot theta_dot R_A", real=True)
    rng = random.Random(9)
    pieces = [qdd, qd**2, qd, R, s, c**2, g * m, sp.Rational(-1, 2), sp.sin(beta) / c, qd**3, qdd * qd]
    for _ in range(80):
        e = sp.expand(sum(rng.choice(pieces) * rng.choice(pieces) * rng.choice(pieces) for _ in range(rng.randint(1, 6))))
        for v in (qdd, qd**2, R, qd):
            assert same_tree(_without_factor(e, v), sp.expand(e - e.coeff(v) * v))


def test_the_walk_reads_numbers_as_complex_does():
    """The tree walk's numbers (solver.tree_value._double_number, which skips evalf for exact
    halves and integers) are exactly ``complex(e)``: the display's zero test and the scene checks
    must see the same doubles as before (equality, no tolerance)."""
    from solver.tree_value import _double_number

    rng = random.Random(11)
    numbers = [sp.Integer(0), sp.Integer(-1), sp.S.Half, sp.pi, sp.Float("0.1"), sp.Integer(2**53 + 1)]
    for _ in range(3000):
        p = rng.randint(-(2 ** rng.randint(0, 60)), 2 ** rng.randint(0, 60))
        q = 2 ** rng.randint(0, 1100) if rng.random() < 0.5 else rng.randint(1, 10**rng.randint(1, 30))
        numbers.append(sp.Rational(p, q))
    for e in numbers:
        assert _double_number(e) == complex(e), e


def test_the_shared_substitution_is_xreplace():
    """solver.tree_value.substitute (one memo over several expressions) builds the trees that
    ``xreplace`` builds, Float arithmetic at a state included (equality of trees, no tolerance)."""
    from solver.tree_value import substitute

    rng = random.Random(5)
    leaves = [s, c, sp.sin(beta), sp.cos(beta), g, m, t, sp.Rational(1, 3), sp.Integer(2), sp.sqrt(g * m)]
    exprs = []
    for _ in range(60):
        e = rng.choice(leaves)
        for _ in range(rng.randint(1, 8)):
            other = rng.choice(leaves + exprs[-3:])
            e = rng.choice([e + other, e * other, e / (other + 3), e**2 - other])
        exprs.append(e)
    rule = {phi: sp.Float(0.7), beta: sp.Float(-0.3), g: sp.Float(9.81), m: sp.Float(2.5), t: sp.Float(0.1)}
    memo: dict = {}
    for e in exprs:
        assert substitute(e, rule, memo) == e.xreplace(rule)
    partial = {phi: sp.Float(0.7)}  # symbols left: the same symbolic trees
    memo = {}
    for e in exprs:
        assert substitute(e, partial, memo) == e.xreplace(partial)


def test_the_sine_reduction_is_replaces():
    """display._reduce_poly replaces the sine squares in one xreplace when none lies inside another;
    the same tree as sympy's ``replace`` (equality of trees), on random polynomials in sin/cos."""
    from solver.display import _is_sine_square, _lower_sine, _reduce_poly

    rng = random.Random(3)
    pieces = [s, c, s**2, s**3 * c, sp.sin(beta) ** 4, sp.cos(beta), g, m * s**2 * sp.sin(beta) ** 2]
    for _ in range(200):
        p = sp.Add(*[rng.randint(-3, 3) * sp.Mul(*rng.sample(pieces, rng.randint(1, 3))) for _ in range(5)])
        assert _reduce_poly(p) == sp.expand(sp.expand(p).replace(_is_sine_square, _lower_sine))


def test_the_denominator_reduction_is_replaces():
    """display._reduce_denominators by one xreplace (no denominator inside another) builds the tree
    sympy's ``replace`` builds (equality of trees), on random sums of fractions in sin/cos."""
    from solver.display import _is_trig_denominator, _reduce_denominators, _reduce_poly

    rng = random.Random(4)
    dens = [s**2 + c**2, 2 * s**2 + c**2 + s * c, sp.sin(beta) ** 2 + sp.cos(beta) ** 2 + 1, c**2 + 3]
    for _ in range(200):
        e = sp.Add(*[rng.choice([g, m * s, c**3]) * rng.choice(dens) ** -rng.randint(1, 2) for _ in range(3)])
        expected = e.replace(_is_trig_denominator, lambda x: _reduce_poly(x.base) ** x.exp)
        assert _reduce_denominators(e) == expected


def test_other_modules_use_only_the_public_names_of_display():
    """solver.display is used by the commands and the report through its public names (those in
    its ``__all__``): a private helper imported elsewhere would be a second, unannounced interface.
    Every ``from ... display import NAME`` in solver/ and reports/ is checked, read by ``ast``."""
    import ast
    from pathlib import Path

    import solver.display as display

    root = Path(__file__).resolve().parents[1]
    found = []
    for path in sorted([*root.glob("solver/**/*.py"), *root.glob("reports/**/*.py")]):
        if path.name == "display.py" and path.parent.name == "solver":
            continue
        text = path.read_text(encoding="utf-8")
        if "display" not in text:  # no such import without the word: a third of the files, half the parsing
            continue
        for node in ast.walk(ast.parse(text)):
            if isinstance(node, ast.ImportFrom) and (node.module or "").split(".")[-1] == "display":
                found += [(path.name, a.name) for a in node.names]
    assert found, "no module imports from solver.display: the scan is broken"
    assert [(f, n) for f, n in found if n not in display.__all__] == []


def test_the_fast_minus_sign_is_sympys():
    """display.could_extract_minus_sign answers a product from its first factor (the printers ask it
    of every product they print): the same answer as sympy's ``could_extract_minus_sign`` for
    products led by a rational, by no number at all, by a float, and by the infinities sympy treats
    apart (``zoo*x`` equals its negative)."""
    from solver.display import could_extract_minus_sign

    x = sp.Symbol("x", real=True)
    rest = [x, g * m, s**2 * sp.cos(beta), 1 / (x + g), sp.sqrt(2) * x, (g - m) * x]
    leads = [sp.Integer(3), sp.Integer(-2), sp.Rational(-1, 2), sp.Float(-1.5), sp.Float(2.5), sp.pi, -sp.pi,
             sp.oo, -sp.oo, sp.zoo, sp.I, -sp.I, sp.S.One, g, -g]
    products = [lead * r for lead in leads for r in rest]
    assert sum(type(e) is sp.Mul for e in products) > 60
    for e in products:
        assert could_extract_minus_sign(e) == e.could_extract_minus_sign(), e


def test_the_walked_free_symbols_are_sympys():
    """The zero test's probe point is built from the free symbols, found by a plain walk of the tree
    where nothing binds a symbol: sympy's own set, also for trees where something does (a
    derivative, an integral, a substitution, whose bound symbol is not free)."""
    from solver.display import _free_symbols

    x = sp.Symbol("x", real=True)
    f = sp.Function("f")(t)
    exprs = [g * m * s**2 / (x + sp.cos(beta)), sp.sqrt(2) * sp.pi * x**-3, f * sp.sin(f) + W,
             sp.Derivative(f, t) * x, sp.Integral(x * t, (t, 0, 1)) + g, sp.Subs(t * x, t, 1) * m,
             sp.Piecewise((x, x > 0), (g, True)), sp.Integer(3)]
    for e in exprs:
        assert _free_symbols(e) == e.free_symbols, e


def test_eom_text_and_json_of_rolling_and_sliding_contacts_are_tidy(capsys):
    """QA 11: eom printed "x_ddot = k_x_theta*theta_ddot + -L*theta_dot**2*cos(theta)" (the ladder
    whose foot x = L cos(theta) slides; twice differentiated: x'' = -L sin(theta) theta'' - L cos(theta)
    theta'^2) and "psi_ddot = k_psi_s*s_ddot + 0" (the disk rolling down the incline, psi = -s/r);
    eom --json left the disk's generalized mass as m (sin^2 + cos^2)^2/2 + m sin^2 + m cos^2, which is
    m + I/r^2 = 3 m/2 (a uniform disk, I = m r^2/2)."""
    import json

    from solver.__main__ import main

    assert main(["eom", "data/scenes/ladder_leaves_wall.toml"]) == 0
    ladder = capsys.readouterr().out
    assert "  k_x_theta = -L*sin(theta)\n" in ladder
    assert "  x_ddot = k_x_theta*theta_ddot - L*theta_dot**2*cos(theta)\n" in ladder
    assert main(["eom", "data/scenes/incline_disk.toml"]) == 0
    disk = capsys.readouterr().out
    assert "  k_psi_s = -1/r\n" in disk and "  psi_ddot = k_psi_s*s_ddot\n" in disk
    for text in (ladder, disk):
        assert "+ -" not in text and not any(line.endswith(" + 0") for line in text.splitlines())
    assert main(["eom", "data/scenes/incline_disk.toml", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["mass"] == [["3*m/2"]]


def test_a_large_sum_over_polynomial_denominators_is_cancelled():
    """Terms over powers of a sum of masses (moments about a composite's mass centre G carry
    1/(m_1 + m_2)) are put over the factored common denominator and divided by every factor that
    divides the numerator: the result equals sympy's ``cancel`` exactly, and its denominator is a
    product of factors of no higher degree than ``cancel``'s (too large for ``cancel`` itself,
    which tidy skips over MAX_CANCEL_NODES nodes). Random polynomials; exact comparisons.

    The sum is built expanded from p f**k/(12 f**(k+1)) + q f/(4 f**2), which is (p + 3 q)/(12 f) by
    hand: that short form is the reference. Its reduced denominator is the one ``cancel(e)`` gives
    (the same rational function; a reduced denominator is unique up to a constant), found without
    cancelling the long sum; and tidy's result N/D (``together``, an exact rewriting) equals it when
    12 f N - (p + 3 q) D expands to zero modulo sin**2 + cos**2 = 1: a polynomial identity, no gcd
    (cancelling ``shown - e`` was two thirds of the test's CPU)."""
    m1, m2, r, l = sp.symbols("m_1 m_2 r l", positive=True)
    f = m1 + m2
    rng = random.Random(11)
    monomials = [m1, m2, r * l, r**2, l**2 * s, m1 * c, s**2, c**2, sp.Integer(1)]
    for _ in range(12):  # ~0.6 s
        p, q = (sum(rng.randint(-5, 5) * rng.choice(monomials) * rng.choice(monomials) for _ in range(6))
                for _ in range(2))
        k = rng.randint(1, 3)
        e = sp.expand(p * f**k) / sp.expand(12 * f ** (k + 1)) + sp.expand(q * f) / sp.expand(4 * f**2)
        e = sp.expand(e)
        shown = tidy(e)  # equal modulo sin**2 + cos**2 = 1, which tidy also applies
        num, den = sp.fraction(sp.together(shown))
        assert sp.expand((12 * f * num - (p + 3 * q) * den).subs(c**2, 1 - s**2)) == 0
        degree = sp.Poly(sp.fraction(sp.cancel((p + 3 * q) / (12 * f)))[1], m1, m2).total_degree()
        assert sp.Poly(sp.expand(sp.fraction(shown)[1]), m1, m2).total_degree() <= degree


def test_the_equation_of_motion_about_g_is_the_one_about_p(capsys):
    """explain eliminates different reactions about G than about P (Newton's components first), and
    about G the moment equation carries 1/(m_b + m_d) from the composite's mass centre. The
    equation of motion is one equation whichever the point: the printed lines must be the same
    text (they printed a degree-7 over degree-6 polynomial in the masses about G)."""
    from solver.__main__ import main

    for scene, point in (("disk_bar", "P"), ("compound_pendulum", None)):
        lines = []
        for p in ([point] if point else []) + ["G"]:
            assert main(["explain", f"data/scenes/{scene}.toml", "--point", p]) == 0
            out = capsys.readouterr().out.splitlines()
            at = next(i for i, x in enumerate(out) if "equation of motion in theta" in x)
            lines.append(out[at + 1:at + 5])
        if point:
            assert lines[0] == lines[1]
        assert not any("m_d**2" in x or "m_t**2" in x for x in lines[-1])


def _varying_arm() -> str:
    """tests/data/multibody/rot_arm.toml with the arm turned by W t + 3 sin(W t)/10, not W t."""
    from pathlib import Path

    text = (Path(__file__).parent / "data" / "multibody" / "rot_arm.toml").read_text(encoding="utf-8")
    varied = text.replace('"W*t"', '"W*t + 0.3*sin(W*t)"')
    assert varied.count("0.3*sin(W*t)") == 2  # the coordinate's motion and the motor's angle
    return varied


def test_pythagoras_for_any_common_angle():
    """sin(u)**2 + cos(u)**2 = 1 whatever u is: a sum, a multiple, an angle that holds a sine itself
    (a prescribed W t + 3 sin(W t)/10), under a root (a spring's length); and a pair X sin**2 +
    X cos**2 goes also where the rest of the sum keeps its own sin**2 (closed forms by hand)."""
    a, b, r = sp.symbols("a b r", real=True)
    for u in (phi + beta, 2 * phi, W * t + sp.Rational(3, 10) * sp.sin(W * t), sp.sin(phi)):
        one = sp.sin(u) ** 2 + sp.cos(u) ** 2
        assert tidy(m * one) == m
        assert tidy(g * sp.cos(W * t) * one / (a + b)) == g * sp.cos(W * t) / (a + b)
        assert tidy(a * sp.sqrt(r**2 * one) + b) == a * sp.Abs(r) + b
    shown = tidy(-a * s**2 - a * c**2 + b * s**2 + g * s)  # = b sin**2 - a + g sin: no cos**2 left
    assert not shown.has(c) and sp.expand(shown - (b * s**2 - a + g * s)) == 0


def _eom_json(capsys, path) -> dict:
    import json

    from solver.__main__ import main

    assert main(["eom", str(path), "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_eom_of_a_collar_on_an_arm_turned_by_a_varying_motion(tmp_path, capsys):
    """QA 11: the arm turned by phi = W t + 3 sin(W t)/10 printed M = m (sin(phi)**2 + cos(phi)**2).
    By hand (polar coordinates): T = M L**2 phi'**2 / 6 + m (r'**2 + r**2 phi'**2) / 2, so the
    generalized mass of r is m and the equation m r'' - m r phi'**2 + k r (1 - L0/|r|) = 0, with
    phi' = W (1 + 3 cos(W t)/10); V = k (|r| - L0)**2 / 2. No printed form holds sin(phi)**2."""
    from solver.__main__ import main

    path = tmp_path / "arm.toml"
    path.write_text(_varying_arm())
    payload = _eom_json(capsys, path)
    names = {n: sp.Symbol(n, real=True) for n in ("m", "M", "L", "k", "L0", "W", "t", "r", "r_dot", "r_ddot")}
    m_, M_, L_, k_, L0, W_, t_, r, rd, rdd = names.values()
    rate = W_ * (1 + sp.Rational(3, 10) * sp.cos(W_ * t_))
    closed = {"eom": m_ * rdd - m_ * r * rate**2 + k_ * r * (1 - L0 / sp.Abs(r)),
              "kinetic_energy": M_ * L_**2 * rate**2 / 6 + m_ * (rd**2 + r**2 * rate**2) / 2,
              "potential_energy": k_ * (sp.Abs(r) - L0) ** 2 / 2}
    shown = {"eom": payload["eom"][0], "kinetic_energy": payload["kinetic_energy"],
             "potential_energy": payload["potential_energy"]}
    assert payload["mass"] == [["m"]]
    for key, text in shown.items():
        assert "sin(W*t + 3*sin(W*t)/10)" not in text, (key, text)
        assert sp.expand(sp.sympify(text, locals=names) - closed[key]) == 0, key  # (Abs: sympy's own text)
    assert main(["eom", str(path)]) == 0
    out = capsys.readouterr().out
    equations, reactions = out.split("reactions as functions of the state")
    # (the pin's reactions O_x, O_y, now printed tidied (QA 13 #3), hold the arm's direction itself)
    assert "  M = m\n" in out and "sin(W*t + 3*sin(W*t)/10)" not in equations
    assert "sin(W*t + 3*sin(W*t)/10)**2" not in reactions and "cos(W*t + 3*sin(W*t)/10)**2" not in reactions


def test_eom_json_energies_are_tidied(capsys):
    """QA 11: incline_disk's kinetic energy kept m (s'**2 sin(beta)**2 + s'**2 cos(beta)**2)/2. A
    uniform disk: T = m s'**2/2 + (m r**2/2) psi'**2/2 (its centre moves along the incline at s')."""
    payload = _eom_json(capsys, "data/scenes/incline_disk.toml")
    names = {n: sp.Symbol(n, real=True) for n in ("m", "r", "s_dot", "psi_dot")}
    m_, r, sd, pd = names.values()
    assert "beta" not in payload["kinetic_energy"]
    assert sp.expand(sp.sympify(payload["kinetic_energy"], locals=names) - (m_ * sd**2 / 2 + m_ * r**2 * pd**2 / 4)) == 0


def test_eom_of_several_freedoms_is_tidied_after_its_terms_cancel(capsys):
    """A collar on a slot of a turning bar, spring and damper to the hub (tests/data/multibody/
    spring_slot.toml): the equations were printed as built, thousands of characters with
    sqrt(s**2*sin(th)**2 + s**2*cos(th)**2) throughout, the coefficient of s_ddot a difference A - A.
    By hand, in polar coordinates: (M L**2/3 + m s**2) th'' + 2 m s s' th' + g (M L/2 + m s) cos(th)
    = 0 and m s'' - m s th'**2 + m g sin(th) + k s (1 - L0/|s|) + c s' = 0."""
    from solver.__main__ import main

    assert main(["eom", "tests/data/multibody/spring_slot.toml"]) == 0
    lines = capsys.readouterr().out.splitlines()
    shown = [lines[i + 1].strip().removesuffix(" = 0") for i, x in enumerate(lines) if x.startswith("equation for")]
    names = {n: sp.Symbol(n, real=True) for n in ("m", "k", "c", "L0", "M", "L", "g", "th", "s", "th_dot", "s_dot",
                                                  "th_ddot", "s_ddot")}
    m_, k, c_, L0, M_, L_, g_, th, s_, thd, sd, thdd, sdd = names.values()
    closed = [(M_ * L_**2 / 3 + m_ * s_**2) * thdd + 2 * m_ * s_ * sd * thd + g_ * (M_ * L_ / 2 + m_ * s_) * sp.cos(th),
              m_ * sdd - m_ * s_ * thd**2 + m_ * g_ * sp.sin(th) + k * s_ * (1 - L0 / sp.Abs(s_)) + c_ * sd]
    assert len(shown) == 2 and all("sqrt" not in x for x in shown), shown
    for text, reference in zip(shown, closed):
        assert sp.expand(sp.sympify(text, locals=names) - reference) == 0, text


def test_reduce_trig_of_a_polynomial_residual():
    """A residual whose denominator reduces to a number (here 2 sin**2 + 2 cos**2) comes out as the
    polynomial it is modulo sin**2 + cos**2 = 1, as cancel writes it; a true fraction as before."""
    residual = (g * m * (s**2 + c**2) - m * g * c**2 + 3 * g * s**2 * m) / (2 * s**2 + 2 * c**2)
    assert reduce_trig(residual) == sp.expand(2 * g * m * (1 - c**2))  # sin**2 written as 1 - cos**2
    assert reduce_trig(g / (2 - 2 * c**2)) == -g / (2 * c**2 - 2)


def test_one_minus_cos_squared_is_shown_as_the_sine_squared():
    """QA 13 #10: the reduced numerator keeps X - X*cos(u)**2 as X*sin(u)**2 (sliding_bar's
    mass coefficient about G, written by hand: (l/sin b)^2 m (sin^2 b + 3 sin b cos b sin th cos th
    + 3 cos^2 b cos^2 th) / 3, whose last two terms are 3 cos b cos th cos(b - th), QA 15 #7)."""
    l, th = sp.symbols("l_b theta", real=True)
    sb, cb, st, ct = sp.sin(beta), sp.cos(beta), sp.sin(th), sp.cos(th)
    given = l**2 * m * (3 * sb * cb * st * ct + 3 * cb**2 * ct**2 - cb**2 + 1) / (3 * sb**2)
    assert tidy(given) == l**2 * m * (sb**2 + 3 * cb * ct * sp.cos(beta - th)) / (3 * sb**2)


def test_explain_mass_coefficient_and_frequency_refusal_are_tidied(solver_cli):
    """QA 13 #10: what the reader meets in explain (the M term about G) and in frequency's refusal
    (wheel_on_incline's Q, by hand F_0 r cos(Omega t): the rolling hoop's force at its centre
    along the incline times r) shows no 1 - cos**2 and no denominator equal to -1."""
    code, out, _ = solver_cli("explain", "data/scenes/sliding_bar.toml", "--point", "G")
    line = next(x for x in out.splitlines() if x.rstrip().endswith("[M theta_ddot]"))
    assert code == 0 and "cos(beta)**2 + 1" not in line and "sin(beta)**2 +" in line
    code, _, err = solver_cli("frequency", "data/scenes/wheel_on_incline.toml")
    assert code == 2 and "(Q = F_0*r*cos(Omega*t));" in err


def test_affine_value_gives_the_exact_coefficients():
    """solver.tree_value.affine_value of random expressions affine in two unknowns (sums, products with
    the unknowns nested in sums, quotients by known sums) equals sympy's exact coefficients and rest
    at the point, evaluated to 30 digits, within 1e-12 of the largest (double round-off over a few
    dozen operations is ~1e-15 of it; a dropped or wrongly scaled term is off by order one); a
    product of two unknowns and an unknown under sin are refused (NotEvaluable), not evaluated."""
    from solver.tree_value import NotEvaluable, affine_value

    u, w = sp.symbols("u w", real=True)
    rng = random.Random(11)
    leaves = [s, c, sp.sin(beta), g, m, sp.Rational(1, 3), sp.Integer(2)]
    point = {phi: 0.7, beta: -0.3, g: 9.81, m: 2.5}
    for _ in range(40):
        e = rng.choice(leaves) * rng.choice([u, w, u - w])
        for _ in range(rng.randint(1, 6)):
            known = rng.choice(leaves) + rng.choice(leaves)
            e = rng.choice([e + known, e * known, e / (known + 4), e + known * rng.choice([u, w])])
        exact = [e.xreplace({u: 0, w: 0}), sp.expand(e).coeff(u), sp.expand(e).coeff(w)]
        at = {k: sp.Float(v, 30) for k, v in point.items()}
        want = [float(sp.N(x.xreplace(at), 30)) for x in exact]
        got = [v.real for v in affine_value(e, point, [u, w])]
        assert max(abs(a - b) for a, b in zip(got, want)) <= 1e-12 * max(1.0, *map(abs, want)), e
    for bad in (u * w + g, sp.sin(u) * m):
        with pytest.raises(NotEvaluable):
            affine_value(bad, point, [u, w])


def test_expanded_is_sympys_expand():
    """display.expanded distributes polynomials in symbols, rationals and sin/cos of symbols itself:
    the same tree (srepr) as sympy.expand, for the model's own expressions (every scene's kinetic
    energy, its raw equations of motion and the structured reactions' products) and for random
    sums, products and powers of those atoms and of nodes it must leave to sympy (floats, sin of a
    sum, a power of a sum in a denominator, sqrt), with rational coefficients that cancel."""
    from pathlib import Path

    from solver.derivation import derive
    from solver.display import expanded
    from solver.io.scenes import load_system

    def same(e):
        assert same_tree(expanded(e), sp.expand(e)), e

    root = Path(__file__).resolve().parents[1]
    for name in ("sliding_bar", "disk_bar", "wheel_on_incline", "slider_crank"):
        system = load_system(root / "data" / "scenes" / f"{name}.toml")
        same(system.kinetic_energy())
        d = derive(system)
        for eq in d.equations:
            same(eq.expr)
        if len(d.unknowns) == 3:  # the structured reactions' products: (c0 M - c1 f) of the report's examples
            rows = [eq.expr for eq in d.equations]
            same(rows[0] * rows[1] - rows[2] * d.mass)
    rng = random.Random(11)
    atoms = [phi, beta, g, m, s, c, s**2, c**-1, sp.cos(beta) ** 3, 1 / g, sp.Rational(3, 4), sp.Integer(-2)]
    odd = [sp.Float(0.5), sp.sin(phi + beta), 1 / (g + m), sp.sqrt(g), sp.exp(phi)]
    for trial in range(100):
        pool = atoms + (odd if trial % 4 == 0 else [])

        def tree(depth):
            if depth == 0 or rng.random() < 0.3:
                return rng.choice(pool)
            kind = rng.randrange(3)
            parts = [tree(depth - 1) for _ in range(rng.randint(2, 3))]
            if kind == 0:
                return sp.Add(*parts)
            if kind == 1:
                return sp.Mul(*parts)
            return sp.Pow(sp.Add(*parts[:2]), 2)
        same(tree(3 if trial % 5 == 0 else 2))


def test_sympys_expand_passes_make_sympys_tree():
    """display._sympy_expand (expanded's fallback) makes only the passes of sympy.expand that can
    change the tree and stops once the last pass is known to give it back: the same tree (srepr) as
    sympy.expand, on random sums, products, quotients and powers of the nodes it is given (sums in
    denominators, products of such, powers of sums and of products, Abs, sqrt, floats, sin of a
    sum) and of nodes it must hand to sympy.expand whole (exp)."""
    from solver.display import _sympy_expand

    rng = random.Random(5)
    pool = [phi, beta, g, m, s, c**-1, sp.Rational(3, 4), sp.Integer(-2), sp.Float(0.5), sp.Abs(phi - g),
            1 / (g + m), sp.sqrt(g), sp.sin(phi + beta), (g * m) ** sp.Rational(1, 2), (g + m) ** -2]
    for trial in range(100):
        def tree(depth):
            if depth == 0 or rng.random() < 0.25:
                return rng.choice(pool + ([sp.exp(phi)] if trial % 10 == 0 else []))
            kind = rng.randrange(5)
            parts = [tree(depth - 1) for _ in range(rng.randint(2, 3))]
            if kind == 0:
                return sp.Add(*parts)
            if kind == 1:
                return sp.Mul(*parts)
            if kind == 2:
                return parts[0] / sp.Add(*parts[1:])
            if kind == 3:
                return sp.Pow(sp.Mul(*parts[:2]), rng.choice([2, -1, sp.Rational(1, 2)]))
            return sp.Pow(sp.Add(*parts[:2]), rng.choice([2, -2, 3]))
        e = tree(3 if trial % 3 == 0 else 2)
        assert same_tree(_sympy_expand(e), sp.expand(e)), e

def test_sums_of_angle_products_collapse_to_the_angle_difference():
    """sin(a)*sin(b) + cos(a)*cos(b) is shown as cos(a - b), sin(a)*cos(b) - sin(b)*cos(a) as sin(a - b)
    (the angle-addition formulas read backwards, QA 15 #7), common factors of the two terms allowed.
    Random sums of such products over three angles keep their value: equal at random points to
    1e-12 relative (double-precision evaluation of a few dozen operations; a wrong identity errs by
    order 1)."""
    a, b, k = sp.symbols("a b k", real=True)
    sa, ca, sb, cb = sp.sin(a), sp.cos(a), sp.sin(b), sp.cos(b)
    assert tidy(k * (sa * sb + ca * cb)) == k * sp.cos(a - b)
    assert tidy(g * m * (sa * cb - sb * ca)) == g * m * sp.sin(a - b)
    assert tidy(3 * sb * ca - 3 * sa * cb + k) == k - 3 * sp.sin(a - b)
    rng = random.Random(5)
    trig = [sa, ca, sb, cb, s, c, sa * ca, cb**2, sa * sb, ca * cb]  # (squares: a term may pair with one)
    for _ in range(40):
        expr = sum(rng.randint(-3, 3) * rng.choice([g, m, k, 1]) * rng.choice(trig) * rng.choice(trig)
                   for _ in range(5)) + k * (sa * sb + ca * cb)
        shown = tidy(expr)
        for _ in range(3):
            point = {x: rng.uniform(-3.0, 3.0) for x in (a, b, phi, g, m, k)}
            x, y = _at(expr, point), _at(shown, point)
            assert abs(x - y) <= 1e-12 * max(1.0, abs(x)), (expr, shown)


def test_the_collapse_is_tried_only_where_two_angles_occur(monkeypatch):
    """The walk that collapses the sums is skipped where every sin/cos holds the same angle (the
    paper's disk_bar, most one-body scenes): tidy never calls it there."""
    import solver.display as display

    def refuse(e):
        raise AssertionError(f"collapse tried on {e}")

    monkeypatch.setattr(display, "_collapse_angle_sums", refuse)
    tidy.cache_clear()
    tidy(g * m * (s**2 * c + s * c) / (1 + c**2))
    tidy(g * s * c + m * s)
    monkeypatch.undo()
    tidy.cache_clear()
    assert tidy(g * (s * sp.sin(beta) + c * sp.cos(beta))) == g * sp.cos(phi - beta)


def test_double_pendulum_eom_is_the_textbook_one(capsys):
    """`eom` on the double pendulum (point masses m1, m2 on massless links l1, l2) prints the
    equations of textbooks, with cos(theta1 - theta2) and sin(theta1 - theta2) (QA 15 #7): each
    equal to the Lagrange equation derived by hand (exact, after reduction), and no product
    sin(theta1)*sin(theta2) left in any of the printed equations, masses or energies."""
    import json

    from solver.__main__ import main

    assert main(["eom", "data/scenes/double_pendulum.toml", "--json"]) == 0
    out = capsys.readouterr().out
    payload = json.loads(out)
    l1, l2, m1, m2, th1, th2, w1, w2, al1, al2 = sp.symbols(
        "l1 l2 m1 m2 theta1 theta2 theta1_dot theta2_dot theta1_ddot theta2_ddot")
    names = {str(x): x for x in (l1, l2, m1, m2, th1, th2, w1, w2, al1, al2, g)}
    d = th1 - th2
    hand = [(m1 + m2) * l1**2 * al1 + m2 * l1 * l2 * (al2 * sp.cos(d) + w2**2 * sp.sin(d)) + (m1 + m2) * g * l1 * sp.sin(th1),
            m2 * l2**2 * al2 + m2 * l1 * l2 * (al1 * sp.cos(d) - w1**2 * sp.sin(d)) + m2 * g * l2 * sp.sin(th2)]
    for shown, ref in zip(payload["eom"], hand):
        assert is_identically_zero(sp.expand(sp.sympify(shown, locals=names) - ref)), shown
    assert payload["mass"][0][1] == "l1*l2*m2*cos(theta1 - theta2)"
    assert "sin(theta1)*sin(theta2)" not in out and "sin(theta2)*cos(theta1)" not in out


def test_coefficient_is_what_coeff_gives():
    """solver.display.coefficient against sympy's ``coeff`` itself, tree for tree (srepr: the displays
    print these trees): expanded sums of random products with integer, rational and float
    coefficients, for a symbol, a power of it, and a product (which goes to ``coeff``)."""
    from solver.display import coefficient

    x, y, z = sp.symbols("x y z", real=True)
    rng = random.Random(7)
    factors = [x, y, z, x**2, y**3, s, c, s**2, sp.Integer(-1), sp.Rational(-3, 2), sp.Float(0.25), sp.Integer(2)]
    for _ in range(120):  # (120 sums of up to 6 products: 720 comparisons, every kind of term met many times)
        expr = sp.expand(sp.Add(*[sp.Mul(*rng.sample(factors, rng.randint(1, 4))) for _ in range(rng.randint(1, 6))]))
        for v in (x, y, x**2, y**3, s**2, x * y):
            assert same_tree(coefficient(expr, v), expr.coeff(v)), (expr, v)
    assert coefficient(x, x) == 1 and coefficient(x**2, x**2) == 1 and coefficient(x**2, x) == 0


def test_monomials_are_not_identically_zero():
    """is_identically_zero answers a nonzero rational or a plain monomial (symbols, sin/cos of
    symbols, positive powers) without a test; the answer is the exact route's
    (numerator_reduces_to_zero), including monomials tiny at the numeric probes (x**40)."""
    x, y = sp.symbols("x y", real=True)
    rng = random.Random(11)
    factors = [x, y, s, c, x**2, c**3, x**40, sp.Rational(-3, 7), sp.Integer(5)]
    for _ in range(200):
        e = sp.Mul(*rng.sample(factors, rng.randint(1, 4)))
        is_identically_zero.cache_clear()
        assert is_identically_zero(e) is False and numerator_reduces_to_zero(e) is False, e
    assert is_identically_zero(sp.Integer(0)) is True and is_identically_zero(sp.Rational(1, 3)) is False


SPRING_BAR = """name = "spring_bar"
[parameters]
m = "3 kg"
L = "1.2 m"
g = "9.81 m/s^2"
k = "50 N/m"
L0 = "0.3 m"
[coordinates]
theta = { value = "40 deg", rate = "1.5 rad/s" }
[ground.points]
O = ["0", "0"]
S = ["L", "L/2"]
[[bodies]]
name = "bar"
orientation = "theta"
reference_point = "O"
points = { O = ["0", "0"], E = ["L", "0"] }
elements = [{ kind = "slender_bar", mass = "m", from = "O", to = "E" }]
[[joints]]
kind = "pin"
name = "O"
connects = ["ground:O", "bar:O"]
[[loads]]
kind = "gravity"
g = "g"
[[loads]]
kind = "spring"
name = "spr"
between = ["bar:E", "ground:S"]
stiffness = "k"
free_length = "L0"
"""


def test_a_positive_length_is_shown_without_abs(tmp_path, solver_cli):
    """QA 19 #10: a spring from a bar's tip E to the ground point (L, L/2) has length
    L*sqrt(9 - 8 cos(theta) - 4 sin(theta))/2 for L > 0, but eom and explain printed Abs(L) (sympy
    takes sqrt(L**2) of a real L as Abs(L)). L = 1.2 m is positive: no Abs is shown, and the answer
    stays the one by hand: I_O alpha = -m g (L/2) cos(theta) + (moment of the spring about O)."""
    import math

    scene = tmp_path / "spring.toml"
    scene.write_text(SPRING_BAR)
    for argv in (["eom", str(scene)], ["explain", str(scene), "--point", "E"], ["explain", str(scene)]):
        code, out, err = solver_cli(*argv)
        assert code == 0, err
        assert "Abs" not in out and "sqrt(-4*sin(theta) - 8*cos(theta) + 9)" in out, argv
    # by hand: E = L(cos, sin), S = (L, L/2); tension k(|SE| - L0) along E -> S
    m, L, g, k, L0, th = 3.0, 1.2, 9.81, 50.0, 0.3, math.radians(40)
    ex, ey, sx, sy = L * math.cos(th), L * math.sin(th), L, L / 2
    length = math.hypot(sx - ex, sy - ey)
    fx, fy = k * (length - L0) * (sx - ex) / length, k * (length - L0) * (sy - ey) / length
    alpha = (-m * g * L / 2 * math.cos(th) + ex * fy - ey * fx) / (m * L ** 2 / 3)
    assert f"alpha       {alpha:.6g}" in out, alpha    # the solved table prints 6 significant digits


def test_tidy_keeps_abs_outside_a_positive_parameters_block():
    """Outside :func:`positive_parameters` nothing is assumed: sqrt(L**2 X) of a real L is |L| sqrt(X)."""
    L, x = sp.symbols("L x", real=True)
    assert tidy(sp.sqrt(L ** 2 * (x ** 2 + 1))).has(sp.Abs)


def test_a_sum_of_positive_parameters_loses_its_abs_and_the_form_reduces():
    """QA 21 #7: a gear pair with its centres one above the other, radii r1, r2 > 0, printed the
    wheel's reaction term as F_t*(r1**2 + 2*r1*r2 - r1*Abs(r1 + r2) + r2**2)/Abs(r1 + r2). By hand
    |r1 + r2| = r1 + r2, the numerator is r2 (r1 + r2), and the term is F_t*r2; the pitch point's
    offset r1*(r1 + r2)/Abs(r1 + r2) is r1. A difference of them, whose sign the parameters' do not
    decide, keeps its Abs."""
    from types import SimpleNamespace

    from solver.display import positive_parameters

    r1, r2, F = sp.symbols("r1 r2 F_t", real=True)
    system = SimpleNamespace(si_values=lambda: {r1: 0.05, r2: 0.1})
    term = F * (r1**2 + 2 * r1 * r2 - r1 * sp.Abs(r1 + r2) + r2**2) / sp.Abs(r1 + r2)
    with positive_parameters(system):
        assert tidy(term) == F * r2
        assert tidy(r1 * (r1 + r2) / sp.Abs(r1 + r2)) == r1
        assert tidy(sp.Abs(r1 - r2) * F).has(sp.Abs)
    assert tidy(term).has(sp.Abs)  # outside the block nothing is assumed
