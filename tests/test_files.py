"""Tests for solver/files.py: regular files only, bounded sizes and nesting, outputs
checked before the work and written atomically."""
from __future__ import annotations

import os
import stat
from pathlib import Path

import pytest

from solver.errors import InputError
from solver.files import (
    MAX_TOML_DEPTH,
    check_output_path,
    read_regular_file,
    read_toml,
    write_atomic,
)


def test_fifo_and_devices_are_refused_without_blocking(tmp_path: Path) -> None:
    fifo = tmp_path / "scene.toml"
    os.mkfifo(fifo)  # opening it for reading would block until a writer comes
    with pytest.raises(InputError, match=r"FIFO \(named pipe\), not a regular file"):
        read_regular_file(fifo, "scene")
    with pytest.raises(InputError, match="character device"):
        read_regular_file("/dev/zero", "scene")
    with pytest.raises(InputError, match="a folder"):
        read_regular_file(tmp_path, "scene")


def test_size_cap(tmp_path: Path) -> None:
    big = tmp_path / "big.toml"
    big.write_bytes(b"#" * 101)
    assert read_regular_file(big, "x", max_bytes=101) == b"#" * 101  # the cap itself is allowed
    with pytest.raises(InputError, match="101 bytes long; the limit is 100"):
        read_regular_file(big, "x", max_bytes=100)


def test_a_file_that_grows_after_it_is_opened_is_read_to_the_cap(tmp_path: Path, monkeypatch) -> None:
    """The read goes by the size the open file reports, then on to the cap: a file longer than
    that size (it grew since) is read whole when within the cap, refused when past it."""
    grown = tmp_path / "grown.toml"
    grown.write_bytes(b"#" * 200)
    real_stat, real_fstat = os.stat, os.fstat

    def stale(real):  # the size it had when checked and opened
        return lambda *args: os.stat_result((*real(*args)[:6], 10, *real(*args)[7:]))

    monkeypatch.setattr("solver.files.os.stat", stale(real_stat))
    monkeypatch.setattr("solver.files.os.fstat", stale(real_fstat))
    assert read_regular_file(grown, "x", max_bytes=1000) == b"#" * 200
    assert read_regular_file(grown, "x", max_bytes=200) == b"#" * 200
    with pytest.raises(InputError, match="longer than the limit of 150 bytes"):
        read_regular_file(grown, "x", max_bytes=150)


@pytest.mark.parametrize("depth", [MAX_TOML_DEPTH, MAX_TOML_DEPTH + 1, 50_000])
def test_toml_nesting_is_bounded(tmp_path: Path, depth: int) -> None:
    # key = [[...]] adds the array levels below the top table (level 1)
    path = tmp_path / "deep.toml"
    levels = depth - 1
    path.write_text("x = " + "[" * levels + "]" * levels + "\n")
    if depth <= MAX_TOML_DEPTH:
        assert "x" in read_toml(path, "deep")
    else:
        with pytest.raises(InputError, match=f"^deep: tables or arrays nested deeper than {MAX_TOML_DEPTH}"):
            read_toml(path, "deep")


def test_toml_values_python_cannot_hold(tmp_path: Path) -> None:
    path = tmp_path / "long.toml"
    path.write_text("m = " + "9" * 5000 + "\n")  # beyond Python's 4300-digit int conversion limit
    with pytest.raises(InputError, match="^long: a value TOML cannot hold"):
        read_toml(path, "long")


def test_output_path_is_checked_before_work(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="it is a folder"):
        check_output_path(tmp_path, "--out")
    with pytest.raises(InputError, match="does not exist"):
        check_output_path(tmp_path / "missing" / "x.csv", "--out")
    (tmp_path / "afile").write_text("")  # a path through a file: said so (QA 14 #6: "does not exist")
    with pytest.raises(InputError, match="afile is a file, not a folder"):
        check_output_path(tmp_path / "afile" / "x.csv", "--out")
    with pytest.raises(InputError, match="character device"):
        check_output_path("/dev/null", "--out")
    assert check_output_path(tmp_path / "ok.csv", "--out") == tmp_path / "ok.csv"


@pytest.mark.skipif(os.geteuid() == 0, reason="root may write into read-only folders")
def test_unwritable_folder_is_refused(tmp_path: Path) -> None:
    locked = tmp_path / "locked"
    locked.mkdir(mode=0o500)
    with pytest.raises(InputError, match="is not writable"):
        check_output_path(locked / "x.csv", "--out")


def test_atomic_write_leaves_nothing_on_failure(tmp_path: Path) -> None:
    target = tmp_path / "out.csv"
    write_atomic(target, lambda fh: fh.write("a,b\n"), "--out")
    assert target.read_text() == "a,b\n"

    def broken(fh):
        fh.write("half")
        raise OSError(28, "No space left on device")

    with pytest.raises(InputError, match="cannot write there .No space left on device"):
        write_atomic(target, broken, "--out")
    assert target.read_text() == "a,b\n"  # the old file is intact
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.csv"]  # no temporary file left


def test_user_cache_dir_is_private_or_absent(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from solver.files import CACHE_ENV, user_cache_dir

    monkeypatch.delenv(CACHE_ENV, raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    folder = user_cache_dir("pint")
    assert folder == tmp_path / "cache" / "alt-euler" / "pint"
    assert folder.is_dir() and folder.stat().st_mode & 0o077 == 0  # created private
    # a folder others may write into is not used (someone could plant data in it)
    folder.chmod(0o777)
    assert user_cache_dir("pint") is None
    # a place that cannot be a folder: no cache, no error
    (tmp_path / "file").write_text("x")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "file"))
    assert user_cache_dir("pint") is None
    # switched off
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache2"))
    monkeypatch.setenv(CACHE_ENV, "1")
    assert user_cache_dir("pint") is None and not (tmp_path / "cache2").exists()


def test_atomic_write_gives_the_mode_open_would(tmp_path: Path) -> None:
    """mkstemp creates 0600 files; a written output gets what ``open(path, "w")`` gives instead:
    a new file 0666 less the umask, a replaced file keeps its own mode (a shared page stays readable)."""
    old = os.umask(0o027)
    try:
        new = write_atomic(tmp_path / "new.html", lambda fh: fh.write("x"), "-o")
        assert stat.S_IMODE(new.stat().st_mode) == 0o640  # 0666 & ~0027
        kept = tmp_path / "kept.html"
        kept.write_text("old")
        kept.chmod(0o604)
        write_atomic(kept, lambda fh: fh.write("new"), "-o")
        assert stat.S_IMODE(kept.stat().st_mode) == 0o604 and kept.read_text() == "new"
    finally:
        os.umask(old)


def test_output_path_ending_in_a_slash_is_refused(tmp_path: Path) -> None:
    """``x.svg/`` names a folder that does not exist, not the file x.svg (pathlib drops the slash)."""
    with pytest.raises(InputError, match=r"^-o .*x\.svg/: not a file name \(it ends with a slash\)$"):
        check_output_path(f"{tmp_path}/x.svg/", "-o")
    assert not (tmp_path / "x.svg").exists()


def test_explain_output_it_cannot_write_is_one_line(solver_cli, tmp_path: Path) -> None:
    """A destination that cannot be written (a folder that does not exist, a path through a file, a
    trailing slash) is refused before any work: one line naming -o, exit status 2, nothing written."""
    blocker = tmp_path / "file"
    blocker.write_text("")
    for target in (tmp_path / "missing" / "x.md", blocker / "x.html", f"{tmp_path}/x.md/"):
        code, out, err = solver_cli("explain", "data/scenes/sliding_bar.toml", "-o", str(target))
        assert code == 2 and out == "" and err.count("\n") == 1 and err.startswith("error: -o "), err
        assert "Traceback" not in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["file"]


def test_survey_outputs_share_the_write(tmp_path: Path) -> None:
    """The survey analytics write through the same mechanics (mode of a plain open, trailing slash
    refused), with their own error type."""
    from analysis._io import atomic_write
    from analysis.errors import SurveyInputError

    old = os.umask(0o022)
    try:
        assert stat.S_IMODE(atomic_write(tmp_path / "t.csv", "a,b\n").stat().st_mode) == 0o644
    finally:
        os.umask(old)
    with pytest.raises(SurveyInputError, match="ends with a slash"):
        atomic_write(f"{tmp_path}/u.csv/", "a\n")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["t.csv"]
