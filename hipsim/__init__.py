"""hipsim: kinematics, closed-chain dynamics and control of the 2(3PUS+S) hip joint simulator."""

from .exceptions import HipsimError, ModelError, ParameterError, PoseError, TrajectoryError
from .parameters import Parameters, load_parameters, slender_levers

__all__ = [
    "HipsimError",
    "ModelError",
    "ParameterError",
    "Parameters",
    "PoseError",
    "TrajectoryError",
    "load_parameters",
    "slender_levers",
]
