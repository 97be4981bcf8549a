"""Atomic file writes: a reader sees the old file or the whole new one, never half of it."""

from __future__ import annotations

import csv
import io
import os
import tempfile
from contextlib import contextmanager
from pathlib import Path
from typing import Iterator, Mapping

import numpy as np

from .exceptions import HipsimError

__all__ = ["check_folder", "make_folder", "output_folder", "write_atomic", "write_columns"]


def check_folder(path: str | Path) -> Path:
    """Check, without creating anything, that an output folder could be made or used.

    For commands that compute before they write: a failed run then leaves no
    empty folder behind, and a bad path is still refused before the work.

    Raises:
        HipsimError: naming the path when it, or the nearest existing folder
            above it, is a file.
    """
    path = Path(path)
    existing = next(p for p in (path, *path.parents) if p.exists() or p == Path(p.anchor or "."))
    if existing.exists() and not existing.is_dir():
        where = "" if existing == path else f" ('{existing}' is a file)"
        raise HipsimError(f"{path}: cannot make the output folder, a file has that name{where}")
    return path


def make_folder(path: str | Path) -> Path:
    """Create an output folder (and its parents) if missing.

    Raises:
        HipsimError: naming the path when it exists as a file or cannot be created.
    """
    path = Path(path)
    try:
        path.mkdir(parents=True, exist_ok=True)
    except FileExistsError:
        raise HipsimError(f"{path}: cannot make the output folder, a file has that name") from None
    except OSError as error:
        raise HipsimError(f"{path}: cannot make the output folder ({error.strerror or error})") from None
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
        HipsimError: as :func:`make_folder`; whatever the body raises, unchanged.
    """
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
    once it is complete; on any failure the temporary file is removed. A
    symbolic link is written through: its target is replaced, the link kept.

    Raises:
        HipsimError: when the folder does not exist, the path is a folder, a
            device, pipe or socket (not a regular file), or a loop of links,
            or the file cannot be written.
    """
    given = Path(path)
    # Through a symbolic link to its target: replacing the link itself would cut it.
    try:
        path = given.resolve() if given.is_symlink() else given
    except (OSError, RuntimeError):  # a loop of links: Python 3.11 and 3.12 raise RuntimeError
        path = given
    if path.is_symlink():  # still a link after resolving (or resolve() gave up): the links go round in a loop
        raise HipsimError(f"{given}: cannot write, its symbolic links go round in a loop")
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        raise HipsimError(f"{given}: cannot write, folder '{folder}' does not exist")
    if path.is_dir():
        raise HipsimError(f"{given}: cannot write, it is a folder")
    if path.exists() and not path.is_file():
        # A device, pipe or socket: renaming a new file over it would destroy it.
        raise HipsimError(f"{given}: not a regular file; hipsim writes results only to regular files")
    mode = "wb" if isinstance(text, bytes) else "w"
    try:
        handle, temporary = tempfile.mkstemp(dir=folder, prefix=f".{path.name}.", suffix=".part")
    except OSError as error:
        raise HipsimError(f"{path}: cannot write ({error.strerror})") from None
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
        raise HipsimError(f"{path}: cannot write ({error.strerror or error})") from None
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise
    return path


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
