"""The errors hipsim raises.

Every error names what is wrong and where: the file, the key, the row and
column, or the sample time. The command line prints ``str(error)`` as one line
and exits non-zero; library users catch :class:`HipsimError`.

A message quotes what the user typed or a file held, so ``str(error)`` is
made safe to print (:func:`printable`): control characters (a NUL byte, a
terminal escape) are shown escaped (``\\x00``), and a message grown huge by a
quoted 200 kB cell is shortened in its middle.
"""

from __future__ import annotations

import re
import unicodedata

__all__ = [
    "ArgumentError",
    "CalibrationError",
    "CatalogueError",
    "ClosureError",
    "ExcitationError",
    "FileRowError",
    "HipsimError",
    "IdentificationError",
    "ModelError",
    "MissingDependencyError",
    "OutputError",
    "ParameterError",
    "PoseError",
    "TrajectoryError",
    "printable",
]

#: The longest message printed whole, in characters; a longer one keeps its start and end.
MAX_MESSAGE = 1200
#: The longest quoted text ('…') printed whole, in characters; a longer one keeps its start and end.
MAX_QUOTE = 100
_QUOTED = re.compile(rf"(?<![\w'])'([^']{{{MAX_QUOTE + 1},}})'(?![\w'])")  # not an apostrophe: the drive's screw


def printable(text: str) -> str:
    """The text safe to print on one line: control characters escaped (``\\x00``, ``\\n``), a long quote or a huge text cut in its middle.

    Idempotent: escaping leaves no control character to escape again, and a shortened quote is short.
    """
    if any(unicodedata.category(c) in ("Cc", "Cf", "Zl", "Zp") for c in text):
        text = "".join(_escaped(c) for c in text)
    text = _QUOTED.sub(_shortened, text)
    if len(text) > MAX_MESSAGE:
        head, tail = MAX_MESSAGE * 2 // 3, MAX_MESSAGE // 4
        text = f"{text[:head]} … [{len(text) - head - tail:,} characters left out] … {text[-tail:]}"
    return text


def _shortened(quoted: re.Match) -> str:
    inner = quoted.group(1)
    return f"'{inner[:60]}…{inner[-20:]}' ({len(inner):,} characters)"


def _escaped(c: str) -> str:
    if unicodedata.category(c) not in ("Cc", "Cf", "Zl", "Zp"):
        return c
    return repr(c)[1:-1] if c.isascii() else f"\\u{ord(c):04x}"


class HipsimError(Exception):
    """Base class of every error hipsim raises on purpose; ``str()`` gives its message :func:`printable`."""

    def __str__(self) -> str:
        return printable(super().__str__())


def _placed(message: str, *where) -> str:
    """``"A, B: message"`` from the parts of the place that are known (None and empty parts left out)."""
    known = [str(part) for part in where if part]
    return f"{', '.join(known)}: {message}" if known else message


class ArgumentError(HipsimError, ValueError):
    """A function argument is out of its domain or has the wrong shape.

    Also a :class:`ValueError`, so code that catches that keeps working.

    Attributes:
        name: the argument (or field) name.
        value: the offending value.
        expected: what was expected, in words.
    """

    def __init__(self, name: str, value, expected: str):
        shown = f"shape {value.shape}" if hasattr(value, "shape") and getattr(value, "ndim", False) else repr(value)
        super().__init__(f"{name}: expected {expected}, got {shown}")
        self.name = name
        self.value = value
        self.expected = expected


class OutputError(HipsimError):
    """A result cannot be written where it was asked to go.

    Attributes:
        path: the path as given.
        reason: why, in words.
    """

    def __init__(self, path, reason: str):
        super().__init__(f"{path}: {reason}")
        self.path = path
        self.reason = reason


class ClosureError(HipsimError):
    """The closed chain cannot be closed at a configuration: the levers do not reach, or the closure is singular.

    Attributes:
        gap: the closure gap left in [m] (0 when the loops closed but the pose is singular).
        iterations: the iterations spent.
        reason: what went wrong, in words.
    """

    def __init__(self, reason: str, gap: float = 0.0, iterations: int = 0):
        super().__init__(reason)
        self.reason = reason
        self.gap = gap
        self.iterations = iterations


class ParameterError(HipsimError):
    """A parameter file or override is invalid.

    Attributes:
        key: dotted key of the offending entry, e.g. ``"lever.length_mm"``.
        value: the offending value, if there is one.
        source: the file (or ``--set``) the entry came from.
    """

    def __init__(self, message: str, key: str | None = None, value=None, source: str | None = None):
        super().__init__(_placed(message, source, key and f"key '{key}'"))
        self.key = key
        self.value = value
        self.source = source


class FileRowError(HipsimError):
    """A table read from a file is invalid; the base of :class:`TrajectoryError` and :class:`CatalogueError`.

    Attributes:
        source: the file, if any.
        line: 1-based line of the file, if the problem is on one line.
        column: the column name, if the problem is in one column.
    """

    def __init__(self, message: str, source: str | None = None, line: int | None = None, column: str | None = None):
        super().__init__(_placed(message, source, line is not None and f"line {line}", column and f"column '{column}'"))
        self.source = source
        self.line = line
        self.column = column


class TrajectoryError(FileRowError):
    """A trajectory (file or arrays) is invalid (source, line and column as in :class:`FileRowError`)."""


class PoseError(HipsimError):
    """A platform orientation is out of reach or singular.

    The message reads ``SOURCE, t = TIME s, line LINE: REASON``: the
    trajectory's source as it was given (a file's path as typed), the sample
    time, and the file's line when the sample is one of a file's rows (see
    :meth:`hipsim.Trajectory.line_at`); parts that are not known are left out.

    Attributes:
        reason: what is wrong with the pose, without the place.
        time: the sample time in [s] of the first offending sample.
        index: its 0-based index in the trajectory that was computed.
        source: the trajectory's name (a file's path as typed), if known.
        line: the 1-based line of the file that holds the sample, if known.
    """

    def __init__(self, message: str, time: float, index: int, source: str | None = None, line: int | None = None):
        super().__init__(_placed(message, source, f"t = {time:.6g} s", line is not None and f"line {line}"))
        self.reason = message
        self.time = time
        self.index = index
        self.source = source
        self.line = line


class ModelError(HipsimError):
    """A model description (URDF, closure file) is inconsistent or cannot be closed."""


class MissingDependencyError(HipsimError):
    """An optional part of hipsim needs a package that is not installed.

    The message says how to install it in one line.

    Attributes:
        package: the missing package's import name, e.g. ``"mujoco"``.
        extra: the hipsim extra that installs it, e.g. ``"mujoco"``.
        found: the version installed when it is too old, else None.
    """

    def __init__(self, package: str, extra: str, what: str, found: str | None = None):
        problem = f"version {found} is too old" if found else "it is not installed"
        super().__init__(f"{what} needs the optional package '{package}' ({problem}): pip install -U 'hipsim[{extra}]'")
        self.package = package
        self.extra = extra
        self.found = found


class CatalogueError(FileRowError):
    """A motor, screw or gearbox catalogue (CSV) or drive file is invalid (source, line and column as in :class:`FileRowError`)."""


class CalibrationError(HipsimError):
    """A kinematic calibration cannot be made from its logs: it does not converge, or its machine leaves the workspace.

    Attributes:
        reason: what went wrong, in words (the log and sample time where one is to blame).
    """

    def __init__(self, reason: str):
        super().__init__(reason)
        self.reason = reason


class IdentificationError(HipsimError):
    """Logs that cannot give an identification: none given, too few samples, nothing determined, an implausible result.

    Attributes:
        logs: the logs fitted, by name (empty when none was given).
        reason: what went wrong, in words, without the logs' names.
    """

    def __init__(self, reason: str, logs: tuple[str, ...] = ()):
        super().__init__(_placed(reason, ", ".join(logs)))
        self.logs = tuple(logs)
        self.reason = reason


class ExcitationError(HipsimError):
    """No excitation (a motion designed to identify or calibrate the machine) meets its limits.

    Attributes:
        reason: what could not be met, in words, with what to relax.
    """

    def __init__(self, reason: str):
        super().__init__(reason)
        self.reason = reason
