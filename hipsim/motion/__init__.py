"""Motion and load: the :class:`Trajectory` type, the built-in ISO 14242-1 cycle and the readers of gait files.

Layer 1 of hipsim, beside :mod:`hipsim.machine`: it knows nothing of the machine.
"""

from .build import TrajectoryWarning
from .columns import Column, ColumnMap, parse_columns
from .csv_table import load_trajectory_csv
from .gait_events import gait_cycles
from .hip_angles import hip_to_machine, machine_to_hip
from .opensim import load_opensim
from .readers import read_trajectory
from .sources import CycleSource, FileSource, SampledSource
from .trajectories import Trajectory, interpolator, iso14242

__all__ = [
    "Column",
    "ColumnMap",
    "CycleSource",
    "FileSource",
    "SampledSource",
    "Trajectory",
    "TrajectoryWarning",
    "hip_to_machine",
    "gait_cycles",
    "interpolator",
    "iso14242",
    "load_opensim",
    "load_trajectory_csv",
    "machine_to_hip",
    "parse_columns",
    "read_trajectory",
]
