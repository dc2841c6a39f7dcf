"""Planar rigid-body solver built on the generalized Euler equation (paper Eq. 10-15)."""
