"""Modules loaded on first use, so that a command pays only for what it runs.

``python -m solver --help`` builds every subcommand's options; the command
modules name sympy and the derivation at the top, but only a command that
derives touches them. :func:`lazy_module` returns the module object at once
and executes it on the first attribute access (``importlib.util.LazyLoader``).
"""
from __future__ import annotations

import importlib.util
import sys
from types import ModuleType

__all__ = ["lazy_module"]


def lazy_module(name: str) -> ModuleType:
    """The module ``name``, loaded when one of its attributes is first read.

    An already imported module is returned as it is.

    Raises
    ------
    ModuleNotFoundError
        When no module of that name is installed.
    """
    if name in sys.modules:
        return sys.modules[name]
    spec = importlib.util.find_spec(name)
    if spec is None or spec.loader is None:
        raise ModuleNotFoundError(f"no module named {name!r}", name=name)
    loader = importlib.util.LazyLoader(spec.loader)
    spec.loader = loader
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    loader.exec_module(module)
    return module
