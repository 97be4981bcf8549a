"""hipsim: kinematics, closed-chain dynamics and control of the 2(3PUS+S) hip joint simulator.

A few calls give what the command line gives::

    import hipsim

    params = hipsim.load_parameters()                 # the published machine (SI inside)
    trajectory = hipsim.iso14242(rate=1000)           # or hipsim.read_trajectory("gait.csv" / "walk.mot")
    result = hipsim.analyse(params, trajectory)       # analytic model; model="pinocchio" for the other
    result.torques.tau                                # (N, 3) motor torques in N·m, parts in tau_m … tau_f
    result.columns()["tau_1_Nmm"]                     # the CSV columns of spec §7.5
    result.write_csv("iso.csv")

The physics is in pure functions over arrays: :func:`kinematics` and
:func:`inverse_dynamics`.
"""

from .analytic.virtual_work import Torques, inverse_dynamics, mechanical_energy
from .exceptions import HipsimError, ModelError, ParameterError, PoseError, TrajectoryError
from .analytic.inverse_kinematics import Kinematics, kinematics
from .machine.parameters import Parameters, load_parameters, slender_levers
from .analysis.runs import Result, analyse
from .motion import Trajectory, iso14242, load_trajectory_csv, read_trajectory

__version__ = "0.1.0"

__all__ = [
    "HipsimError",
    "Kinematics",
    "ModelError",
    "ParameterError",
    "Parameters",
    "PoseError",
    "Result",
    "Torques",
    "Trajectory",
    "TrajectoryError",
    "analyse",
    "inverse_dynamics",
    "iso14242",
    "kinematics",
    "load_parameters",
    "load_trajectory_csv",
    "mechanical_energy",
    "read_trajectory",
    "slender_levers",
]
