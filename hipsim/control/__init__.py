"""Trajectory-tracking control (spec §8): the controllers, the servo loop and the reduced plant."""

from .controllers import AugmentedPD, Sample, WorkspacePD
from .simulation import ReducedPlant, Simulation, apply_mismatch, simulate

__all__ = ["AugmentedPD", "ReducedPlant", "Sample", "Simulation", "WorkspacePD", "apply_mismatch", "simulate"]
