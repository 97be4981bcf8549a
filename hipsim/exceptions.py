"""The errors hipsim raises.

Every error names what is wrong and where: the file, the key, the row and
column, or the sample time. The command line prints ``str(error)`` as one line
and exits non-zero; library users catch :class:`HipsimError`.
"""

from __future__ import annotations

__all__ = [
    "HipsimError",
    "ParameterError",
    "TrajectoryError",
    "PoseError",
    "ModelError",
    "CatalogueError",
]


class HipsimError(Exception):
    """Base class of every error hipsim raises on purpose."""


class ParameterError(HipsimError):
    """A parameter file or override is invalid.

    Attributes:
        key: dotted key of the offending entry, e.g. ``"lever.length_mm"``.
        value: the offending value, if there is one.
        source: the file (or ``--set``) the entry came from.
    """

    def __init__(self, message: str, key: str | None = None, value=None, source: str | None = None):
        where = []
        if source:
            where.append(str(source))
        if key:
            where.append(f"key '{key}'")
        prefix = ", ".join(where)
        super().__init__(f"{prefix}: {message}" if prefix else message)
        self.key = key
        self.value = value
        self.source = source


class TrajectoryError(HipsimError):
    """A trajectory (file or arrays) is invalid.

    Attributes:
        source: the file the trajectory came from, if any.
        line: 1-based line of the file, if the problem is on one line.
        column: the column name, if the problem is in one column.
    """

    def __init__(self, message: str, source: str | None = None, line: int | None = None, column: str | None = None):
        where = []
        if source:
            where.append(str(source))
        if line is not None:
            where.append(f"line {line}")
        if column:
            where.append(f"column '{column}'")
        prefix = ", ".join(where)
        super().__init__(f"{prefix}: {message}" if prefix else message)
        self.source = source
        self.line = line
        self.column = column


class PoseError(HipsimError):
    """A platform orientation is out of reach or singular.

    Attributes:
        time: the sample time in [s] of the first offending sample.
        index: its sample index.
        source: the trajectory's name (its file), if known.
    """

    def __init__(self, message: str, time: float, index: int, source: str | None = None):
        where = f"t = {time:.6g} s (sample {index})"
        super().__init__(f"{source}, {where}: {message}" if source else f"{where}: {message}")
        self.time = time
        self.index = index


class ModelError(HipsimError):
    """A model description (URDF, closure file) is inconsistent or cannot be closed."""


class CatalogueError(HipsimError):
    """A motor, screw or gearbox catalogue (CSV) or drive file is invalid.

    Attributes:
        source: the file.
        line: 1-based line of the file, if the problem is on one line.
        column: the column name, if the problem is in one column.
    """

    def __init__(self, message: str, source: str | None = None, line: int | None = None, column: str | None = None):
        where = [str(source)] if source else []
        if line is not None:
            where.append(f"line {line}")
        if column:
            where.append(f"column '{column}'")
        prefix = ", ".join(where)
        super().__init__(f"{prefix}: {message}" if prefix else message)
        self.source = source
        self.line = line
        self.column = column
