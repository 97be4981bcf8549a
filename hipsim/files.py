"""Atomic file writes: a reader sees the old file or the whole new one, never half of it."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

from .exceptions import HipsimError

__all__ = ["write_atomic"]


def write_atomic(path: str | Path, text: str | bytes) -> Path:
    """Write a file so that readers see either the old file or the whole new one.

    The text goes to a temporary file beside ``path`` that is renamed over it
    once it is complete; on any failure the temporary file is removed.

    Raises:
        HipsimError: when the folder does not exist or is not writable.
    """
    path = Path(path)
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        raise HipsimError(f"{path}: cannot write, folder '{folder}' does not exist")
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
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise
    return path
