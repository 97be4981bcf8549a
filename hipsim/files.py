"""Atomic file writes: a reader sees the old file or the whole new one, never half of it.

A write interrupted by Ctrl-C or by SIGTERM (what ``timeout``, ``kill`` and
job schedulers send) removes its temporary ``.part`` file: SIGTERM is turned
into ``SystemExit(143)`` while the file is open, so the clean-up runs as it
does for Ctrl-C (:func:`exit_on_terminate`). ``-`` (or ``/dev/stdout``)
names standard output: the text is written there, as a whole.
"""

from __future__ import annotations

import glob
import math
import os
import signal
import stat
import sys
import tempfile
import threading
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np

from .exceptions import OutputError
from .tables import csv_header, csv_rows, parquet_concat, parquet_table, parquet_writer

__all__ = [
    "STDOUT",
    "ColumnWriter",
    "check_folder",
    "check_output",
    "exit_on_terminate",
    "is_stdout",
    "json_ready",
    "make_folder",
    "output_folder",
    "write_atomic",
    "write_columns",
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
    if (
        threading.current_thread() is not threading.main_thread()
        or signal.getsignal(signal.SIGTERM) is not signal.SIG_DFL
    ):
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


def write_atomic(path: str | os.PathLike, text: str | bytes) -> Path:
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
    given, path = _target(path)
    mode = "wb" if isinstance(text, bytes) else "w"
    with exit_on_terminate():
        try:
            handle, temporary = _temporary_beside(path)
        except OSError as error:
            raise OutputError(path, f"cannot write ({error.strerror})") from None
        try:
            # mkstemp makes the file private (0600); give it the permissions any new file would get.
            umask = os.umask(0)
            os.umask(umask)
            os.chmod(temporary, 0o666 & ~umask)
            text_options: dict[str, Any] = {} if mode == "wb" else {"encoding": "utf-8", "newline": ""}
            with os.fdopen(handle, mode, **text_options) as stream:
                stream.write(text)
            os.replace(temporary, path)
        except OSError as error:  # disk full, permissions, a rename refused
            Path(temporary).unlink(missing_ok=True)
            raise OutputError(path, f"cannot write ({error.strerror or error})") from None
        except BaseException:  # Ctrl-C, SIGTERM (as SystemExit), anything else
            Path(temporary).unlink(missing_ok=True)
            raise
    return path


def _temporary_beside(path: Path) -> tuple[int, str]:
    """A new hidden ``.NAME.PID.XXXX.part`` file beside ``path`` (handle, path).

    A process killed outright (SIGKILL, a power cut) cannot remove its ``.part``
    file; the writer's process id in the name lets the next write of the same
    path remove those whose process no longer runs, and leave a live writer's.
    """
    folder = path.parent if str(path.parent) else Path(".")
    for stale in folder.glob(f".{glob.escape(path.name)}.*.part"):
        pid = stale.name[len(path.name) + 2 :].split(".", 1)[0]
        if pid.isdigit() and not _running(int(pid)):
            stale.unlink(missing_ok=True)
    return tempfile.mkstemp(dir=folder, prefix=f".{path.name}.{os.getpid()}.", suffix=".part")


def _running(pid: int) -> bool:
    """Whether a process with this id runs on this machine (a process of another user counts)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def _target(path) -> tuple[Path, Path]:
    """The path as given and the file a write lands in (through a link), after every check that needs no writing.

    Raises:
        OutputError: as :func:`write_atomic`.
    """
    given = Path(path)
    if str(given) in ("/dev/stderr", "/dev/stdin") or str(given).startswith(("/dev/fd/", "/proc/self/fd/")):
        # Renaming a file over what a descriptor points to would leave the descriptor on the old file.
        raise OutputError(
            given,
            "names one of this process's open files, not a file to write; give a file name (or '-', standard output)",
        )
    # A device, pipe or socket, reached through a link or not (/dev/stderr, /proc/self/fd/N): refused by the
    # name typed, before resolving a link into /proc would turn it into a name no one typed ('pipe:[1234]').
    try:
        mode = os.stat(given).st_mode
    except (OSError, ValueError):
        mode = None
    if mode is not None and not (stat.S_ISREG(mode) or stat.S_ISDIR(mode)):
        raise OutputError(
            given, "not a regular file; hipsim writes results only to regular files (or '-', standard output)"
        )
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
    return given, path


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
    return write_atomic(path, csv_header(columns) + csv_rows(columns))


def check_output(path: str | Path) -> Path:
    """Check, before the work, that an output file could be written: what :func:`write_atomic` would refuse, refused now.

    ``-`` (standard output) passes. Nothing is created.

    Args:
        path: the file to write.

    Returns:
        The path as given.

    Raises:
        OutputError: the folder is missing or not writable, the path is a
            folder, a device, pipe or socket, or a loop of links.
    """
    if is_stdout(path):
        return Path(STDOUT)
    given, target = _target(path)
    folder = target.parent if str(target.parent) else Path(".")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise OutputError(given, f"cannot write, folder '{folder}' is not writable")
    return given


class ColumnWriter:
    """Named columns written piece by piece to one CSV or Parquet file, atomically: the whole file at the end or none.

    The format follows the suffix (``.parquet``: Apache Parquet, pieces
    gathered into row groups of at least :attr:`ROW_GROUP` rows, so that the
    footer the writer keeps in memory does not grow with small pieces;
    anything else: CSV as :func:`write_columns` writes it).
    The pieces go to a temporary ``.part`` file beside the path, renamed over
    it by :meth:`close`; leaving the ``with`` block by an exception (Ctrl-C,
    SIGTERM inside :func:`exit_on_terminate`) removes it. ``-`` writes CSV
    to standard output as the pieces come (it cannot be taken back).

    Args:
        path: the file to write.
        metadata: Parquet only: text key-value metadata for the file (e.g. the parameter set).

    Raises:
        OutputError: as :func:`check_output`, or when a write fails.
    """

    #: Rows a Parquet row group gathers at least (the last one may have fewer).
    ROW_GROUP = 20_000

    def __init__(self, path: str | Path, metadata: Mapping[str, str] | None = None):
        self.path = check_output(path)
        self._gathered: list = []  # Parquet: pieces waiting for their row group
        self.parquet = not is_stdout(path) and self.path.suffix.lower() == ".parquet"
        self.metadata = dict(metadata or {})
        self.names: list[str] | None = None
        self.rows = 0
        self._stream: Any = None
        self._temporary: Any = None
        self._parquet: Any = None
        self._pending: Any = None
        self._executor: Any = None
        if is_stdout(path):
            self._stream = sys.stdout
            return
        self._target = target = _target(self.path)[1]
        try:
            handle, temporary = _temporary_beside(target)
        except OSError as error:
            raise OutputError(self.path, f"cannot write ({error.strerror})") from None
        self._temporary = Path(temporary)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(temporary, 0o666 & ~umask)
        if self.parquet:
            os.close(handle)
        else:
            self._stream = os.fdopen(handle, "w", encoding="utf-8", newline="")

    def write(self, columns: Mapping[str, np.ndarray]) -> None:
        """Append one piece: the same column names, in the same order, every time."""
        names = list(columns)
        if self.names is None:
            self.names = names
            if not self.parquet:
                self._text(csv_header(names))
        elif names != self.names:
            raise OutputError(self.path, f"a piece has the columns {names}, the file {self.names}")
        if self.parquet:
            self._write_parquet(columns)
        else:
            self._text(csv_rows(columns))
        self.rows += len(next(iter(columns.values()))) if columns else 0

    def _text(self, text: str) -> None:
        try:
            self._stream.write(text)
        except OSError as error:
            if isinstance(error, BrokenPipeError):
                raise
            raise OutputError(self.path, f"cannot write ({error.strerror or error})") from None

    def _write_parquet(self, columns: Mapping[str, np.ndarray]) -> None:
        table = parquet_table(columns)
        if self._parquet is None:
            schema = table.schema.with_metadata(self.metadata)
            try:
                self._parquet = parquet_writer(self._temporary, schema)
            except OSError as error:
                raise OutputError(self.path, f"cannot write ({error})") from None
        self._gathered.append(table.replace_schema_metadata(self.metadata))
        if sum(len(piece) for piece in self._gathered) >= self.ROW_GROUP:
            self._write_row_group()

    def _write_row_group(self) -> None:
        """The gathered pieces as one row group, encoded and written on a thread (pyarrow lets go of the GIL) while the next ones are computed."""
        table, self._gathered = parquet_concat(self._gathered), []
        self._finish_pending()
        self._pending = self._thread().submit(self._parquet.write_table, table, row_group_size=len(table))

    def _thread(self):
        if self._executor is None:
            from concurrent.futures import ThreadPoolExecutor

            self._executor = ThreadPoolExecutor(max_workers=1, thread_name_prefix="hipsim-parquet")
        return self._executor

    def _finish_pending(self) -> None:
        """Wait for the piece being written; its error, if any, raised here."""
        pending, self._pending = self._pending, None
        if pending is not None:
            try:
                pending.result()
            except OSError as error:
                raise OutputError(self.path, f"cannot write ({error})") from None

    def close(self) -> Path:
        """Finish the file and put it in place. Returns the path written (``-`` for standard output)."""
        if self.names is None and not self.parquet:
            self._text("")
        if self._temporary is None:
            self._stream.flush()
            return Path(STDOUT)
        try:
            if self.parquet:
                if self._parquet is None:
                    raise OutputError(self.path, "nothing to write")
                if self._gathered:
                    self._write_row_group()
                self._finish_pending()
                self._parquet.close()
                self._executor.shutdown()
            else:
                self._stream.close()
            os.replace(self._temporary, self._target)
        except OSError as error:
            self.abort()
            raise OutputError(self.path, f"cannot write ({error.strerror or error})") from None
        self._temporary = None
        return self.path

    def abort(self) -> None:
        """Drop the temporary file (after a failure); the path keeps what it held before."""
        if self._temporary is None:
            return
        try:
            if self._executor is not None:
                self._executor.shutdown(wait=True, cancel_futures=True)
            if self._parquet is not None:
                self._parquet.close()
            elif self._stream is not None and not self._stream.closed:
                self._stream.close()
        except Exception:  # a broken writer: the file goes anyway
            pass
        self._temporary.unlink(missing_ok=True)
        self._temporary = None

    def __enter__(self) -> ColumnWriter:
        return self

    def __exit__(self, kind, error, traceback) -> None:
        if kind is not None:
            self.abort()


def json_ready(value):
    """``value`` with every NaN and infinity replaced by None (JSON has neither), through dicts, lists and tuples."""
    if isinstance(value, dict):
        return {k: json_ready(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [json_ready(v) for v in value]
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value
