"""Analyses on the multibody core: the instantaneous solve, equations of motion,
kinematics at a state, equilibrium and natural modes, and time histories."""
