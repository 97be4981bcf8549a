"""Atomic file writes: a reader sees the old file or the whole new one, never half of it.

A write interrupted by Ctrl-C or by SIGTERM (what ``timeout``, ``kill`` and
job schedulers send) removes its temporary ``.part`` file: SIGTERM is turned
into ``SystemExit(143)`` while the file is open, so the clean-up runs as it
does for Ctrl-C (:func:`exit_on_terminate`). ``-`` (or ``/dev/stdout``)
names standard output: the text is written there, as a whole.
"""

from __future__ import annotations

import csv
import math
import io
import os
import signal
import stat
import sys
import tempfile
import threading
from contextlib import contextmanager
from pathlib import Path
from typing import Iterator, Mapping

import numpy as np

from .exceptions import OutputError

__all__ = [
    "STDOUT", "check_folder", "exit_on_terminate", "is_stdout", "json_ready", "make_folder", "output_folder", "write_atomic", "write_columns",
]

#: The name of standard output as an output path.
STDOUT = "-"
#: Paths that name this process's standard output.
_STDOUT_NAMES = ("-", "/dev/stdout", "/dev/fd/1", "/proc/self/fd/1")


def is_stdout(path) -> bool:
    """True when ``path`` names standard output: ``-`` or ``/dev/stdout`` (also /dev/fd/1, /proc/self/fd/1)."""
    return path is not None and str(path) in _STDOUT_NAMES


def _refuse_stdout_folder(path) -> None:
    if is_stdout(path):
        raise OutputError(path, "standard output cannot hold a folder of files; give a folder name")


@contextmanager
def exit_on_terminate() -> Iterator[None]:
    """Within the body, SIGTERM raises ``SystemExit(143)`` so that clean-up code (``finally``, ``except BaseException``) runs.

    By default SIGTERM ends Python at once, leaving temporary files behind;
    Ctrl-C already raises KeyboardInterrupt. Only from the main thread, and
    only where SIGTERM still has its default action (a handler someone else
    installed is left alone); the previous handler comes back on exit.
    """
    if threading.current_thread() is not threading.main_thread() or signal.getsignal(signal.SIGTERM) is not signal.SIG_DFL:
        yield
        return

    def terminate(signum, frame):
        raise SystemExit(128 + signum)

    signal.signal(signal.SIGTERM, terminate)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, signal.SIG_DFL)


def check_folder(path: str | Path) -> Path:
    """Check, without creating anything, that an output folder could be made or used.

    For commands that compute before they write: a failed run then leaves no
    empty folder behind, and a bad path is still refused before the work.

    Raises:
        OutputError: naming the path when it, or the nearest existing folder
            above it, is a file.
    """
    _refuse_stdout_folder(path)
    path = Path(path)
    existing = next(p for p in (path, *path.parents) if p.exists() or p == Path(p.anchor or "."))
    if existing.exists() and not existing.is_dir():
        where = "" if existing == path else f" ('{existing}' is a file)"
        raise OutputError(path, f"cannot make the output folder, a file has that name{where}")
    return path


def make_folder(path: str | Path) -> Path:
    """Create an output folder (and its parents) if missing.

    Raises:
        OutputError: naming the path when it exists as a file or cannot be created.
    """
    _refuse_stdout_folder(path)
    path = Path(path)
    try:
        path.mkdir(parents=True, exist_ok=True)
    except FileExistsError:
        raise OutputError(path, "cannot make the output folder, a file has that name") from None
    except OSError as error:
        raise OutputError(path, f"cannot make the output folder ({error.strerror or error})") from None
    return path


@contextmanager
def output_folder(path: str | Path) -> Iterator[Path]:
    """Make an output folder for one run, and take it back if the run fails.

    Use it around the writing only, after the computing, so that a run that
    fails early never touches the disk. If the body raises (a write refused,
    a full disk, Ctrl-C), every folder this call created and that is still
    empty is removed again, deepest first; a folder that existed before, or
    that holds anything, is left alone.

    Raises:
        OutputError: as :func:`make_folder`; whatever the body raises, unchanged.
    """
    _refuse_stdout_folder(path)
    path = Path(path)
    # Deepest first; lexists, so that a dangling link is not taken for a missing folder of ours.
    missing = [p for p in (path, *path.parents) if not os.path.lexists(p)]
    try:
        make_folder(path)
        yield path
    except BaseException:
        for folder in missing:
            try:
                folder.rmdir()  # refuses a folder that is not empty: the run wrote something, or someone else did
            except FileNotFoundError:
                continue  # already gone; the ones above may still be empty
            except OSError:
                break  # not empty (or not ours to remove): the folders above it hold it, so are not empty either
        raise


def write_atomic(path: str | Path, text: str | bytes) -> Path:
    """Write a file so that readers see either the old file or the whole new one.

    The text goes to a temporary file beside ``path`` that is renamed over it
    once it is complete; on any failure, Ctrl-C or SIGTERM the temporary file
    is removed. A symbolic link is written through: its target is replaced,
    the link kept. ``-`` or ``/dev/stdout`` writes the text to standard output.

    Returns:
        The path written (``Path("-")`` for standard output).

    Raises:
        OutputError: when the folder does not exist, the path is a folder, a
            device, pipe or socket (not a regular file), or a loop of links,
            or the file cannot be written.
    """
    if is_stdout(path):
        _write_stdout(text)
        return Path(STDOUT)
    given = Path(path)
    if str(given) in ("/dev/stderr", "/dev/stdin") or str(given).startswith(("/dev/fd/", "/proc/self/fd/")):
        # Renaming a file over what a descriptor points to would leave the descriptor on the old file.
        raise OutputError(given, "names one of this process's open files, not a file to write; give a file name (or '-', standard output)")
    # A device, pipe or socket, reached through a link or not (/dev/stderr, /proc/self/fd/N): refused by the
    # name typed, before resolving a link into /proc would turn it into a name no one typed ('pipe:[1234]').
    try:
        mode = os.stat(given).st_mode
    except (OSError, ValueError):
        mode = None
    if mode is not None and not (stat.S_ISREG(mode) or stat.S_ISDIR(mode)):
        raise OutputError(given, "not a regular file; hipsim writes results only to regular files (or '-', standard output)")
    # Through a symbolic link to its target: replacing the link itself would cut it.
    try:
        path = given.resolve() if given.is_symlink() else given
    except (OSError, RuntimeError):  # a loop of links: Python 3.11 and 3.12 raise RuntimeError
        path = given
    if path.is_symlink():  # still a link after resolving (or resolve() gave up): the links go round in a loop
        raise OutputError(given, "cannot write, its symbolic links go round in a loop")
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        raise OutputError(given, f"cannot write, folder '{folder}' does not exist")
    if path.is_dir():
        raise OutputError(given, "cannot write, it is a folder")
    if path.exists() and not path.is_file():
        # A device, pipe or socket: renaming a new file over it would destroy it.
        raise OutputError(given, "not a regular file; hipsim writes results only to regular files")
    mode = "wb" if isinstance(text, bytes) else "w"
    with exit_on_terminate():
        try:
            handle, temporary = tempfile.mkstemp(dir=folder, prefix=f".{path.name}.", suffix=".part")
        except OSError as error:
            raise OutputError(path, f"cannot write ({error.strerror})") from None
        try:
            # mkstemp makes the file private (0600); give it the permissions any new file would get.
            umask = os.umask(0)
            os.umask(umask)
            os.chmod(temporary, 0o666 & ~umask)
            with os.fdopen(handle, mode, **({} if mode == "wb" else {"encoding": "utf-8", "newline": ""})) as stream:
                stream.write(text)
            os.replace(temporary, path)
        except OSError as error:  # disk full, permissions, a rename refused
            Path(temporary).unlink(missing_ok=True)
            raise OutputError(path, f"cannot write ({error.strerror or error})") from None
        except BaseException:  # Ctrl-C, SIGTERM (as SystemExit), anything else
            Path(temporary).unlink(missing_ok=True)
            raise
    return path


def _write_stdout(text: str | bytes) -> None:
    """The whole text to standard output (bytes to its binary buffer), flushed."""
    if isinstance(text, bytes):
        sys.stdout.flush()
        sys.stdout.buffer.write(text)
        sys.stdout.buffer.flush()
    else:
        sys.stdout.write(text)
        sys.stdout.flush()


def write_columns(path: str | Path, columns: Mapping[str, np.ndarray]) -> Path:
    """Write named columns of equal length as a CSV file, atomically; 12 significant digits.

    Args:
        path: the CSV file.
        columns: column name (with its unit) → values, each of shape (N,).
    """
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(columns)
    for row in np.column_stack(list(columns.values())):
        writer.writerow([f"{x:.12g}" for x in row])
    return write_atomic(path, buffer.getvalue())


def json_ready(value):
    """``value`` with every NaN and infinity replaced by None (JSON has neither), through dicts, lists and tuples."""
    if isinstance(value, dict):
        return {k: json_ready(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [json_ready(v) for v in value]
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value
