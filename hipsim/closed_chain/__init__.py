"""The Pinocchio closed-chain model (spec §6): URDF tree plus six loop closures, and its forward-dynamics plant."""

from .engine import PinocchioModel
from .model import ClosedChainModel, Continuation, inverse_dynamics, kinematics, load_model, trajectory_dynamics

__all__ = ["ClosedChainModel", "Continuation", "PinocchioModel", "inverse_dynamics", "kinematics", "load_model", "trajectory_dynamics"]
