"""The analytic model (spec §3–4): inverse kinematics and virtual-work inverse dynamics, vectorised over time.

Pure NumPy (and numba for the single-state kernel); it never imports Pinocchio.
"""

from .engine import AnalyticModel
from .forward_kinematics import forward_kinematics, solve_pose
from .inverse_kinematics import Kinematics, kinematics
from .virtual_work import inverse_dynamics, mass_and_bias, mechanical_energy

__all__ = [
    "AnalyticModel",
    "Kinematics",
    "forward_kinematics",
    "inverse_dynamics",
    "kinematics",
    "mass_and_bias",
    "mechanical_energy",
    "solve_pose",
]
