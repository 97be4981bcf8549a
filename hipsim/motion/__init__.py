"""Motion and load: the :class:`Trajectory` type, the built-in ISO 14242-1 cycle and the readers of gait files.

Layer 1 of hipsim, beside :mod:`hipsim.machine`: it knows nothing of the machine.
"""

from .rig_logs import MeasuredLog, RigLog, lowpass, read_rig_log
from .trajectories import Trajectory, interpolator, iso14242, load_trajectory_csv

__all__ = ["MeasuredLog", "RigLog", "Trajectory", "interpolator", "iso14242", "load_trajectory_csv", "lowpass", "read_rig_log"]
