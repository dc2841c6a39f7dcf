"""Provenance of a build: git commit, interpreter and package versions, input hashes.

Nothing here records a date or a host name, so two builds from the same
inputs give identical outputs.
"""
from __future__ import annotations

import hashlib
import platform
import subprocess
from dataclasses import dataclass, field
from importlib import metadata
from pathlib import Path

__all__ = ["Provenance", "collect", "input_files", "PACKAGES"]

PACKAGES = ("numpy", "scipy", "sympy", "mpmath", "pandas", "matplotlib", "Jinja2", "Pint", "statsmodels")
"""Packages whose versions the provenance block lists."""

# Inputs of the build, as glob patterns relative to the project root.
INPUT_PATTERNS = (
    "data/**/*",
    "solver/*.py",
    "analysis/*.py",
    "reports/*.py",
    "reports/templates/*",
    "reports/build/bench/*.json",
)

# The report's own benchmark output is not an input (it would rebuild itself).
_OWN_OUTPUTS = frozenset({"report.json"})


@dataclass(frozen=True)
class InputFile:
    """One input file and its SHA-256."""

    path: str
    sha256: str
    size: int


@dataclass(frozen=True)
class Provenance:
    """What a build was made from.

    Attributes
    ----------
    commit : str
        ``git rev-parse HEAD``, or ``"unknown"`` outside a git checkout.
    dirty : bool or None
        Whether tracked files differ from the commit, or untracked ones lie in the folders the
        build reads (:data:`BUILD_FOLDERS`; a README example's ``crank.csv`` at the top does
        not count), None: unknown.
    python : str
        Interpreter version.
    packages : dict[str, str]
        Version of each package in :data:`PACKAGES`.
    inputs : list[InputFile]
        Every input file with its hash, sorted by path.
    """

    commit: str
    dirty: bool | None
    python: str
    packages: dict[str, str]
    inputs: list[InputFile] = field(default_factory=list)

    def to_dict(self) -> dict:
        return {
            "commit": self.commit,
            "dirty": self.dirty,
            "python": self.python,
            "packages": dict(self.packages),
            "inputs": [{"path": f.path, "sha256": f.sha256, "size": f.size} for f in self.inputs],
        }


def input_files(root: Path) -> list[Path]:
    """All input files of the build under ``root`` (sorted, no caches)."""
    found: set[Path] = set()
    for pattern in INPUT_PATTERNS:
        for path in root.glob(pattern):
            if path.is_file() and "__pycache__" not in path.parts and path.name not in _OWN_OUTPUTS:
                found.add(path)
    return sorted(found)


def _sha256(path: Path) -> str:
    digest = hashlib.sha256()
    with path.open("rb") as handle:
        for block in iter(lambda: handle.read(1 << 16), b""):
            digest.update(block)
    return digest.hexdigest()


def _git(root: Path, *args: str) -> str | None:
    try:
        done = subprocess.run(
            ["git", *args], cwd=root, capture_output=True, text=True, timeout=20, check=False
        )
    except (OSError, subprocess.SubprocessError):
        return None
    return done.stdout if done.returncode == 0 else None


def _version(name: str) -> str:
    """``importlib.metadata.version(name)``, read from the header block of the distribution's
    metadata only: the full parse reads the whole description (NumPy's and SciPy's include their
    licences), about 1 ms a package.

    Raises
    ------
    importlib.metadata.PackageNotFoundError
        ``name`` is not installed.
    """
    dist = metadata.distribution(name)
    text = dist.read_text("METADATA") or dist.read_text("PKG-INFO") or ""
    for line in text.split("\n\n", 1)[0].splitlines():
        if line.startswith("Version:"):
            return line[len("Version:"):].strip()
    return dist.version  # (no header block: the full parse decides)


BUILD_FOLDERS = ("solver/", "analysis/", "reports/", "data/")
"""The folders whose untracked files could change a build (its code and its inputs)."""


def _differs(status: str, prefix: str = "") -> bool:
    """Whether ``git status --porcelain`` output shows a change that could reach the build;
    ``prefix``: the project's folder inside its repository (``git rev-parse --show-prefix``), as
    the status names paths from the repository's top."""
    for line in status.splitlines():
        if line.startswith("?? "):
            path = line[3:].strip().strip('"')
            if not path.startswith(prefix) or not path[len(prefix):].startswith(BUILD_FOLDERS):
                continue
        if line.strip():
            return True
    return False


def collect(root: Path) -> Provenance:
    """Collect the provenance of a build from the project at ``root``.

    Parameters
    ----------
    root : pathlib.Path
        Project root (the folder holding ``data/``, ``solver/`` ...).
    """
    _validate_collect(root)
    head = _git(root, "rev-parse", "HEAD")
    status = _git(root, "status", "--porcelain", "--untracked-files=normal", "--", ".")
    prefix = (_git(root, "rev-parse", "--show-prefix") or "").strip()
    packages = {}
    for name in PACKAGES:
        try:
            packages[name] = _version(name)
        except metadata.PackageNotFoundError:
            packages[name] = "not installed"
    inputs = [
        InputFile(str(p.relative_to(root)), _sha256(p), p.stat().st_size) for p in input_files(root)
    ]
    return Provenance(
        commit=head.strip() if head else "unknown",
        dirty=None if status is None else _differs(status, prefix),
        python=platform.python_version(),
        packages=packages,
        inputs=inputs,
    )


def _validate_collect(root: Path) -> None:
    if not Path(root).is_dir():
        raise ValueError(f"`root` must be the project folder, got {str(root)!r}")
