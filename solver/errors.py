"""Errors that reach a user as one line (the command line prints ``str(err)``
and exits with status 2). Every message names the file and the place (key,
point, constraint) and what is wrong."""
from __future__ import annotations


class InputError(Exception):
    """Bad input: a scene, an option or a value the solver cannot accept."""


class ExpressionError(InputError):
    """An expression in a scene that the whitelist parser refuses."""


class SceneError(InputError):
    """A scene file that is malformed, incomplete or physically impossible."""


class SingularConfigurationError(InputError):
    """The equations have no unique solution at this configuration (or are so
    badly conditioned that the answer would be meaningless). The message says
    which configuration and which constraint, with the condition number."""


class NoRestoringError(InputError):
    """A small-oscillation question asked of a system with no stable
    equilibrium or no restoring moment (for example a massless bar on a
    rolling disk): reported instead of a frequency of zero or NaN."""
