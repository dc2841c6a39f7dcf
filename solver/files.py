"""Reading and writing files at the solver's boundary, guarded.

Every file the solver reads (a scene) or writes (``simulate --out``) goes
through this module:

* :func:`read_regular_file`: regular files only, checked *before* opening
  (a FIFO would block forever, ``/dev/zero`` never ends), at most
  :data:`MAX_INPUT_BYTES`;
* :func:`read_toml`: that, decoded as UTF-8 (a byte-order mark is allowed)
  and parsed as TOML, nested at most :data:`MAX_TOML_DEPTH` deep;
* :func:`check_output_path`: a destination checked before any work is done
  (its folder exists and is writable; it is not a folder or a device);
* :func:`write_atomic`: write to a temporary file in the same folder and
  rename it over the destination, so nothing is ever half-written;
* :func:`user_cache_dir`: the per-user folder for caches that only speed
  things up (pint's parsed unit definitions), or None when there is no safe one.

Every problem is an :class:`~solver.errors.InputError` of one line that
starts with ``where`` (the file, or the flag that named it).
"""
from __future__ import annotations

import os
import stat
import tempfile
import tomllib
from collections.abc import Callable
from pathlib import Path
from typing import IO, Any

from solver.errors import InputError

MAX_INPUT_BYTES = 1_000_000
"""Largest file the solver reads [bytes] (the shipped scenes are about 3 kB)."""
MAX_TOML_DEPTH = 8
"""Deepest nesting of tables and arrays in a TOML file (a scene needs 4)."""
MAX_TOML_ITEMS = 1000
"""Most entries in one TOML table or array (parameters, points, elements, ...)."""


def _kind(mode: int) -> str:
    for test, name in ((stat.S_ISDIR, "a folder"), (stat.S_ISFIFO, "a FIFO (named pipe)"),
                       (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
                       (stat.S_ISSOCK, "a socket")):
        if test(mode):
            return name
    return "not a regular file"


def read_regular_file(path: str | os.PathLike, where: str, max_bytes: int = MAX_INPUT_BYTES) -> bytes:
    """The bytes of a regular file of at most ``max_bytes``.

    The path is checked with ``stat`` before it is opened (a FIFO, a device
    such as ``/dev/zero`` or a folder is refused without blocking), opened
    non-blocking and checked again, and read to at most ``max_bytes + 1``.

    Raises
    ------
    InputError
        ``"<where>: ..."``: missing or unreadable, not a regular file, or too large.

    Examples
    --------
    >>> read_regular_file("/dev/zero", "scene")
    Traceback (most recent call last):
    ...
    solver.errors.InputError: scene: cannot read the file: it is a character device, not a regular file
    """
    try:
        info = os.stat(path)
        if not stat.S_ISREG(info.st_mode):
            raise InputError(f"{where}: cannot read the file: it is {_kind(info.st_mode)}, not a regular file")
        if info.st_size > max_bytes:
            raise InputError(f"{where}: the file is {info.st_size} bytes long; the limit is {max_bytes}")
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
        with os.fdopen(fd, "rb") as fh:
            opened = os.fstat(fh.fileno())
            if not stat.S_ISREG(opened.st_mode):  # replaced since the check
                raise InputError(f"{where}: cannot read the file: it is not a regular file")
            # to at most max_bytes + 1 bytes: first the size it has (read(max_bytes + 1) would set
            # aside a buffer of that size, most of the time of a small file), then on if it grew
            data = fh.read(min(opened.st_size, max_bytes) + 1)
            if len(data) == min(opened.st_size, max_bytes) + 1 and len(data) <= max_bytes:
                data += fh.read(max_bytes + 1 - len(data))
    except OSError as err:
        raise InputError(f"{where}: cannot read the file ({err.strerror or err})") from None
    if len(data) > max_bytes:
        raise InputError(f"{where}: the file is longer than the limit of {max_bytes} bytes")
    return data


def read_toml(path: str | os.PathLike, where: str, max_bytes: int = MAX_INPUT_BYTES,
              max_depth: int = MAX_TOML_DEPTH) -> dict[str, Any]:
    """Read and parse a TOML file, guarded (:func:`read_regular_file`, UTF-8, depth).

    Raises
    ------
    InputError
        ``"<where>: ..."``: unreadable, not UTF-8, a TOML syntax error (with
        line and column), a number TOML cannot hold, or tables and arrays
        nested deeper than ``max_depth``.
    """
    raw = read_regular_file(path, where, max_bytes)
    try:
        # utf-8-sig: a byte-order mark (saved by some Windows editors) is not an error
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as err:
        raise InputError(f"{where}: not UTF-8 text (byte {err.start})") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise InputError(f"{where}: TOML syntax error: {err}") from None
    except RecursionError:
        raise InputError(f"{where}: tables or arrays nested deeper than {max_depth} levels") from None
    except ValueError as err:  # e.g. an integer longer than Python's 4300-digit limit
        raise InputError(f"{where}: a value TOML cannot hold ({' '.join(str(err).split())[:120]})") from None
    check_depth(data, where, max_depth)
    return data


def check_depth(data: Any, where: str, max_depth: int = MAX_TOML_DEPTH, max_items: int = MAX_TOML_ITEMS) -> None:
    """Refuse tables and arrays nested deeper than ``max_depth``, or holding more than
    ``max_items`` entries (iteratively, no recursion)."""
    stack = [(data, 1)]
    while stack:
        value, depth = stack.pop()
        if isinstance(value, (dict, list)):
            if depth > max_depth:
                raise InputError(f"{where}: tables or arrays nested deeper than {max_depth} levels")
            if len(value) > max_items:
                raise InputError(f"{where}: a table or array with {len(value)} entries; the limit is {max_items}")
            items = value.values() if isinstance(value, dict) else value
            stack.extend((item, depth + 1) for item in items)


def check_output_path(path: str | os.PathLike, where: str) -> Path:
    """Check, before any work, that ``path`` can be written: its folder exists and is
    writable, and it is not itself a folder, a device or a FIFO.

    Raises
    ------
    InputError
        ``"<where> <path>: ..."`` naming what is wrong.
    """
    text = os.fspath(path)
    path = Path(path)
    label = f"{where} {path}"
    if str(path) in ("", ".") or path.name in ("", ".", "..") or text.endswith(("/", os.sep)):
        raise InputError(f"{where} {text}: not a file name" + (" (it ends with a slash)" if text.endswith(("/", os.sep)) else ""))
    folder = path.parent
    if not folder.is_dir():
        raise InputError(f"{label}: {folder} is a file, not a folder" if folder.exists()
                         else f"{label}: folder {folder} does not exist")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise InputError(f"{label}: folder {folder} is not writable")
    try:
        info = os.stat(path)
    except FileNotFoundError:
        return path
    except OSError as err:
        raise InputError(f"{label}: cannot write there ({err.strerror or err})") from None
    if not stat.S_ISREG(info.st_mode):
        raise InputError(f"{label}: it is {_kind(info.st_mode)}; give a file name")
    return path


def write_atomic(path: str | os.PathLike, write: Callable[[IO], None], where: str, *, binary: bool = False) -> Path:
    """Write a text file (or, with ``binary``, a bytes file) atomically: ``write(fh)`` fills a
    temporary file in the same folder, which then replaces ``path`` (:func:`replace_atomically`).
    On any failure nothing is left behind.

    Raises
    ------
    InputError
        The destination is refused (:func:`check_output_path`) or the write fails.
    """
    path = check_output_path(path, where)
    try:
        replace_atomically(path, write, binary=binary)
    except OSError as err:
        raise InputError(f"{where} {path}: cannot write there ({err.strerror or err})") from None
    return path


def replace_atomically(path: Path, write: Callable[[IO], None], *, binary: bool = False) -> None:
    """The mechanics of every atomic write of the project (the solver's :func:`write_atomic` and the
    survey analytics' ``analysis._io.atomic_write``): ``write(fh)`` fills a temporary file in
    ``path``'s folder, which gets the mode a plain ``open`` would give (an existing file's mode is
    kept; a new file gets 0666 less the umask, not mkstemp's private 0600) and then replaces
    ``path`` in one rename. On any failure the temporary file is removed and the error (OSError
    or whatever ``write`` raised) propagates; ``path`` is untouched."""
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with (os.fdopen(fd, "wb") if binary else os.fdopen(fd, "w", newline="", encoding="utf-8")) as fh:
            write(fh)
        os.chmod(tmp, _mode_for(path))
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def _mode_for(path: Path) -> int:
    """The permission bits ``open(path, "w")`` would leave: those of the existing regular file,
    else 0666 less the process's umask."""
    try:
        return stat.S_IMODE(os.stat(path).st_mode)
    except OSError:
        mask = os.umask(0o022)  # reading the umask means setting it: put it straight back
        os.umask(mask)
        return 0o666 & ~mask


CACHE_ENV = "ALT_EULER_NO_CACHE"
"""Set this environment variable (to anything but empty) to use no on-disk cache."""


def user_cache_dir(name: str) -> Path | None:
    """``$XDG_CACHE_HOME/alt-euler/NAME`` (default ``~/.cache``), created private, or None.

    A cache only saves time, so every problem gives None (the caller works
    without): the folder cannot be created, is not a folder, belongs to another
    user, is writable by group or others (someone else could plant data in it),
    or :data:`CACHE_ENV` is set.
    """
    if os.environ.get(CACHE_ENV):
        return None
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    folder = Path(base) / "alt-euler" / name
    try:
        folder.mkdir(mode=0o700, parents=True, exist_ok=True)
        info = folder.lstat()
    except (OSError, RuntimeError):
        return None
    if (not stat.S_ISDIR(info.st_mode) or info.st_uid != os.getuid() or info.st_mode & 0o022
            or not os.access(folder, os.W_OK | os.X_OK)):
        return None
    return folder


__all__ = [
    "user_cache_dir",
    "MAX_INPUT_BYTES", "MAX_TOML_DEPTH", "MAX_TOML_ITEMS", "read_regular_file", "read_toml", "check_depth",
    "check_output_path", "write_atomic", "replace_atomically",
]
