"""hipsim: kinematics, closed-chain dynamics and control of the 2(3PUS+S) hip joint simulator.

A few calls give what the command line gives::

    import hipsim

    params = hipsim.load_parameters()                 # the published machine (SI inside)
    trajectory = hipsim.iso14242(rate=1000)           # or hipsim.read_trajectory("gait.csv" / "walk.mot")
    run = hipsim.analyse(params, trajectory)          # analytic model; model="pinocchio" for the other
    run.torques.total                                 # (N, 3) motor torques in N·m; parts in run.torques.PARTS
    run.columns()["tau_1_Nmm"]                        # the CSV columns of spec §7.5
    run.write_csv("iso.csv")

Each layer is a subpackage: :mod:`hipsim.machine`, :mod:`hipsim.motion`,
:mod:`hipsim.analytic`, :mod:`hipsim.closed_chain`, :mod:`hipsim.control`,
:mod:`hipsim.analysis`, :mod:`hipsim.present`, :mod:`hipsim.cli`.
"""

from .analysis.runs import analyse
from .exceptions import ArgumentError, ClosureError, HipsimError, ModelError, OutputError, ParameterError, PoseError, TrajectoryError
from .machine.parameters import Parameters, load_parameters, slender_levers
from .motion import Trajectory, iso14242, load_trajectory_csv, read_trajectory
from .results import JointForces, Run, Torques

__version__ = "0.3.0"

__all__ = [
    "ArgumentError",
    "ClosureError",
    "HipsimError",
    "JointForces",
    "ModelError",
    "OutputError",
    "ParameterError",
    "Parameters",
    "PoseError",
    "Run",
    "Torques",
    "Trajectory",
    "TrajectoryError",
    "analyse",
    "iso14242",
    "load_parameters",
    "load_trajectory_csv",
    "read_trajectory",
    "slender_levers",
]
