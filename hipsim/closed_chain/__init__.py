"""The Pinocchio closed-chain model (spec §6): URDF tree plus six loop closures, and its forward-dynamics plant."""

from .engine import PinocchioModel
from .model import ClosedChainModel, inverse_dynamics, kinematics, load_model, trajectory_dynamics

__all__ = ["ClosedChainModel", "PinocchioModel", "inverse_dynamics", "kinematics", "load_model", "trajectory_dynamics"]
