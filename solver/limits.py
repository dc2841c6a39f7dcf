"""The solver's option lists and caps on work, in one import-light module.

The command line states these in its ``--help``; reading them from here lets
``python -m solver --help`` build every subcommand's options without loading
sympy, scipy or pint (the modules that enforce them import them from here, so
each value still lives in one place).
"""
from __future__ import annotations

__all__ = [
    "FORMULATION_METHODS", "PERIOD_MODELS", "TOL_MIN", "TOL_MAX", "PRECISIONS", "MIN_DPS", "MAX_DPS",
    "IVP_METHODS", "MAX_T_END", "MAX_PERIODS", "MAX_SAMPLES", "MAX_RHS_EVALUATIONS", "MAX_UNIT_EXPONENT",
]

# -- formulations (solver.formulations.METHODS) ------------------------------------------------
FORMULATION_METHODS = ("generalized_euler", "mass_center", "lagrange")
"""Routes to the equations; the first is the default."""

# -- period (solver.period, solver.fidelity) -----------------------------------------------------
PERIOD_MODELS = ("auto", "linear", "elliptic", "quadrature", "integration")
"""Models of the period, cheapest first after ``auto`` (:mod:`solver.fidelity`)."""
# Tolerances outside this range are refused: below TOL_MIN float64 cannot hold
# the answer, above TOL_MAX the word "period" has lost its meaning.
TOL_MIN = 1e-15
TOL_MAX = 0.1

# -- precision (solver.precision) ------------------------------------------------------------------
PRECISIONS = ("float64", "exact", "mpmath")
MIN_DPS = 5
"""Fewest decimal digits for mpmath and printing."""
MAX_DPS = 4000
"""Most decimal digits: the exact and mpmath answers are printed through Python
integers, whose conversion to text stops at 4300 digits; 4000 leaves room for the
guard digits and takes about 10 s."""

# -- simulate (solver.simulate) --------------------------------------------------------------------
IVP_METHODS = ("RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA")
"""``solve_ivp`` methods accepted by ``simulate --method``."""
MAX_T_END = 1e6
"""Longest run [s] (about 11.6 days of motion)."""
MAX_PERIODS = 2_000
"""Longest run in linearized periods of oscillation, when the system has one."""
MAX_SAMPLES = 200_001
"""Most output samples (each holds the state, alpha, every reaction and the energy)."""
MAX_RHS_EVALUATIONS = 500_000
"""Most right-hand-side evaluations of one run (about 8 s of CPU time); a run that
needs more is refused, naming the time it had reached."""

# -- units (solver.units) -------------------------------------------------------------------------
MAX_UNIT_EXPONENT = 12
"""Largest size of an exponent in a unit, as written (``m**12``) and after
combining (``(m**4)**4`` has 16 and is refused)."""
