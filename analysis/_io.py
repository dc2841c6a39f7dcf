"""File input and output shared by the analysis modules.

- :func:`read_bytes` -- a file's bytes, with one-line errors for missing/unreadable files.
- :func:`read_toml` -- a TOML file, with one-line errors naming the file.
- :func:`atomic_write` -- write to a temporary file in the same folder, then rename.
"""
from __future__ import annotations

import os
import tempfile
from pathlib import Path

from .errors import SurveyInputError


def read_bytes(path: "str | Path") -> bytes:
    """The bytes of ``path``; SurveyInputError (naming the file) if it cannot be read."""
    p = Path(path)
    try:
        return p.read_bytes()
    except FileNotFoundError:
        raise SurveyInputError("no such file", str(p)) from None
    except OSError as e:
        raise SurveyInputError(f"cannot read: {e.strerror}", str(p)) from None


def read_toml(path: "str | Path") -> dict:
    """A TOML file as a dict; SurveyInputError (naming the file) on any problem."""
    import tomllib                  # here: its import compiles regular expressions
    raw = read_bytes(path)
    try:
        return tomllib.loads(raw.decode("utf-8-sig"))      # Notepad may write a BOM
    except UnicodeDecodeError as e:
        raise SurveyInputError(f"not valid UTF-8 (byte offset {e.start})", str(path)) from None
    except tomllib.TOMLDecodeError as e:
        raise SurveyInputError(f"invalid TOML: {e}", str(path)) from None


def atomic_write(path: "str | Path", data: "str | bytes", encoding: str = "utf-8") -> Path:
    """Write ``data`` to ``path`` so that readers see either nothing or the whole file.

    Raises
    ------
    SurveyInputError
        The folder does not exist or cannot be written.
    """
    p = Path(path)
    folder = p.parent if str(p.parent) else Path(".")
    if not folder.is_dir():
        raise SurveyInputError("output folder does not exist", str(p))
    raw = data.encode(encoding) if isinstance(data, str) else data
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{p.name}.", suffix=".tmp", dir=folder)
    except OSError as e:
        raise SurveyInputError(f"cannot write: {e.strerror}", str(p)) from None
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(raw)
        mask = os.umask(0)
        os.umask(mask)
        os.chmod(tmp, 0o666 & ~mask)      # mkstemp creates 0600; give the usual mode
        os.replace(tmp, p)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise
    return p
