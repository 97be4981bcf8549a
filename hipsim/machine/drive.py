"""The drive of each linear module: motor and screw ratings that sizing checks the demands against.

Read from a TOML file's ``[motor]`` table (a parameter file's own ``[motor]``
table works too), in the file's units (N·mm, rpm, mm, N).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from ..exceptions import ParameterError
from .parameters import SCHEMA, check_entry, read_toml

__all__ = ["RATING_KEYS", "MotorRatings", "load_ratings"]


#: Keys of the ``[motor]`` table of a ratings file, with their units and what each is checked against.
RATING_KEYS = {
    "rated_torque_Nmm": ("N·mm", "RMS motor torque"),
    "peak_torque_Nmm": ("N·mm", "peak motor torque"),
    "max_speed_rpm": ("rpm", "peak motor speed"),
    "stroke_mm": ("mm", "carriage stroke"),
    "axial_force_N": ("N", "peak axial screw force"),
}


@dataclass(frozen=True)
class MotorRatings:
    """A motor and linear module to check the demands against; None for a figure not given.

    Attributes:
        rated_torque_Nmm: continuous (rated) motor torque in [N·mm], checked against the RMS torque.
        peak_torque_Nmm: peak motor torque in [N·mm], checked against the peak torque.
        max_speed_rpm: maximum motor speed in [rpm].
        stroke_mm: usable stroke of the linear module in [mm], checked against the carriage stroke.
        axial_force_N: permissible axial load of the screw in [N].
        source: the file they came from.
    """

    rated_torque_Nmm: float | None = None
    peak_torque_Nmm: float | None = None
    max_speed_rpm: float | None = None
    stroke_mm: float | None = None
    axial_force_N: float | None = None
    source: str = "<given>"


def load_ratings(path: str | Path) -> MotorRatings:
    """Read a motor/module rating file: TOML with one ``[motor]`` table (or a parameter file, of which only ``[motor]`` is read).

    Example file::

        [motor]
        rated_torque_Nmm = 640      # continuous torque
        peak_torque_Nmm = 1910
        max_speed_rpm = 3000
        stroke_mm = 200             # linear module stroke
        axial_force_N = 2000        # optional: permissible screw load

    Every key is optional (at least one is needed); each must be a positive number.

    Raises:
        ParameterError: naming the file and key of anything missing, unknown or invalid.
    """
    source = str(path)
    raw = read_toml(path, "rating file")
    for section in raw:
        if section not in SCHEMA:  # the parameter file's other tables are allowed, and ignored here
            raise ParameterError("unknown section (expected one [motor] table)", key=section, source=source)
    table = raw.get("motor")
    if not isinstance(table, dict) or not table:
        raise ParameterError(f"expected a [motor] table with any of {', '.join(RATING_KEYS)}", key="motor", source=source)
    # The same keys, units and checks as the parameter file's optional [motor] table.
    values = {key: check_entry("motor", key, value, source) for key, value in table.items()}
    return MotorRatings(**values, source=source)
