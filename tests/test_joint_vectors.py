"""solver.model.joints.rotate and dot build the same expressions as sympy's Matrix products, vec
the same matrices as sympy's Matrix constructor, vadd, vsub and vscale the same as sympy's Matrix
sum, difference and scalar product, and xy reads the entries sympy's indexing reads.

The joints' equations are written with them instead of 2x2 Matrix products (which
cost ~0.1 ms each); every later display is built from these expressions, so
they must be the same trees (srepr), not merely equal values. The reference is
sympy's own Matrix arithmetic.
"""
from __future__ import annotations

import itertools

import sympy as sp

from solver.model.joints import copy_vec, dot, rotate, rotation, vadd, vec, vscale, vsub, xy
from trees import same_tree

x, y, th, beta, l_b = sp.symbols("x y theta beta l_b", real=True)
# entries of the kinds the scenes hold: zeros and ones (dropped by the sparse product), rationals,
# floats, symbols, sums and products (where a -1 or a rational could be distributed differently)
ENTRIES = [sp.Integer(0), sp.Integer(1), sp.Rational(1, 2), sp.Integer(-3), sp.Float(0.5), th, -l_b / 2, x + y,
           l_b * sp.cos(beta) - x, 2 * (x - y)]
ANGLES = [sp.Integer(0), sp.pi - th, th, -th, sp.pi / 2, sp.Integer(1), 2 * th + beta, sp.pi]


def test_rotate_and_dot_same_trees_as_matrix_products():
    for phi, a, b in itertools.product(ANGLES, ENTRIES, ENTRIES):
        v, w = sp.Matrix([a, b]), sp.Matrix([b, a])
        assert same_tree(list(rotate(phi, v)), list(rotation(phi) * v))
        assert same_tree(dot(w, v), (w.T * v)[0])


def test_vec_is_the_matrix_sympy_builds():
    """Same entries (trees), same internal domain (ZZ/QQ for rationals, else EXRAW) and sparse
    representation, same class: arithmetic and printing of the result cannot tell them apart.
    Python numbers are included, which the constructor sympifies."""
    for a, b in itertools.product(ENTRIES + [0, 2, 0.25], repeat=2):
        ours, theirs = vec(a, b), sp.Matrix([a, b])
        assert type(ours) is type(theirs)
        assert same_tree(list(ours), list(theirs))
        assert ours._rep.domain == theirs._rep.domain
        assert ours._rep.rep == theirs._rep.rep  # the same sparse dict of the same entries
        for mine, sympys in ((ours._rep, theirs._rep), (ours._rep.rep, theirs._rep.rep)):  # and attributes
            assert type(mine) is type(sympys)
            assert {k: v for k, v in vars(mine).items() if k != "rep"} == \
                {k: v for k, v in vars(sympys).items() if k != "rep"}


def test_copy_vec_is_the_copy_sympy_makes():
    """Of the matrices vec builds and of those sympy's constructor and arithmetic build (every domain,
    a row left empty by a sum that cancels): the same class, entries, sparse dict and attributes,
    and a copy (changing it leaves the original as it was)."""
    for a, b in itertools.product(ENTRIES, repeat=2):
        for v in (vec(a, b), sp.Matrix([a, b]), sp.Matrix([a, b]) + sp.Matrix([b, a]), sp.Matrix([a, b]) - sp.Matrix([a, 0])):
            ours, theirs = copy_vec(v), v.copy()
            assert type(ours) is type(theirs)
            assert ours._rep.rep == theirs._rep.rep and ours._rep.domain == theirs._rep.domain
            for mine, sympys in ((ours._rep, theirs._rep), (ours._rep.rep, theirs._rep.rep)):
                assert type(mine) is type(sympys)
                assert {k: w for k, w in vars(mine).items() if k != "rep"} == \
                    {k: w for k, w in vars(sympys).items() if k != "rep"}
            before = list(v)  # (sympy expressions are immutable: these are the entries as they were)
            ours[0] = x**7
            assert same_tree(list(v), before)


def test_xy_reads_what_indexing_reads():
    """Every internal domain (ZZ, QQ, EXRAW) and both the sparse matrices vec builds and the ones
    sympy's constructor and arithmetic build; a pair is read as it is."""
    for a, b in itertools.product(ENTRIES, repeat=2):
        for v in (vec(a, b), sp.Matrix([a, b]), sp.Matrix([a, b]) + sp.Matrix([b, a]), sp.zeros(2, 1)):
            assert same_tree(list(xy(v)), [v[0], v[1]])
    assert xy((x, y)) == (x, y)


def test_vector_sum_difference_and_scaling_same_trees_as_matrix_arithmetic():
    for a, b in itertools.product(ENTRIES, repeat=2):
        v, w = sp.Matrix([a, b]), sp.Matrix([b, a])
        assert same_tree(list(vadd(v, w, v)), list(v + w + v))
        assert same_tree(list(vsub(v, w)), list(v - w))
        for k in (a, -th**2, sp.S.Half, -1):
            assert same_tree(list(vscale(k, w)), list(k * w))
        for d in (2, l_b + x):  # a division: the mass centre over the total mass, a midpoint's half
            assert same_tree(list(vscale(sp.S.One / d, w)), list(w / d))
