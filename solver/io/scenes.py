"""Load any scene file (one-body or multibody format) as a System."""
from __future__ import annotations

from pathlib import Path
from typing import Mapping

from ..model.system import System

__all__ = ["load_system"]


def load_system(path: str | Path, overrides: Mapping[str, str] | None = None) -> System:
    """Read, check and build the System of a scene file.

    Parameters
    ----------
    path : str or Path
        A scene file in either format (``data/scenes/README.md``).
    overrides : Mapping[str, str], optional
        ``--set`` values: parameters, coordinates (``theta``) and rates
        (``theta_dot``) mapped to quantity strings.

    Raises
    ------
    SceneError
        ``"<file>: <key path>: <what is wrong>"``.

    Examples
    --------
    >>> system = load_system("data/scenes/sliding_bar.toml")
    >>> [r.name for r in system.reactions]
    ['R_A', 'R_B']
    """
    from ..scenefile import _SceneLoader, _validate_load_scene
    from .convert import system_from_scene
    from .multibody import is_multibody, load_multibody

    _validate_load_scene(path, overrides)
    loader = _SceneLoader(Path(path))
    data = loader._read_toml()
    if is_multibody(data):
        return load_multibody(loader, data, dict(overrides or {}))
    return system_from_scene(loader.load(dict(overrides or {}), data))
