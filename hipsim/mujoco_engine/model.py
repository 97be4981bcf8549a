"""The MuJoCo engine: the machine's MJCF compiled (:func:`load_model`) and run behind the engine protocol (:class:`MujocoModel`).

Its parts, each reading MuJoCo only: :mod:`~hipsim.mujoco_engine.machine`
(the compiled model and its closure rows), :mod:`~hipsim.mujoco_engine.closure`
(the chain closed sample by sample), :mod:`~hipsim.mujoco_engine.friction`,
:mod:`~hipsim.mujoco_engine.dynamics` (rigid inverse dynamics) and
:mod:`~hipsim.mujoco_engine.trajectory` (both along a trajectory, in one pass).
"""

from __future__ import annotations

import numpy as np

from ..engine import PieceNeeds
from ..exceptions import ArgumentError
from ..machine.parameters import Parameters, load_parameters
from ..results import Run
from .machine import MujocoMachine
from .mjcf import compile_mjcf, mjcf_text
from .trajectory import trajectory_dynamics

__all__ = ["MujocoModel", "load_model"]


def load_model(params: Parameters | None = None, settings=None) -> MujocoMachine:
    """The hip simulator as a compiled MuJoCo model, from one parameter set.

    Args:
        params: the machine, SI; None for the published machine.
        settings: :class:`~hipsim.mujoco_engine.mjcf.MjcfSettings` (time step,
            integrator, closure softness); None for the defaults.
    """
    params = load_parameters() if params is None else params
    return MujocoMachine(compile_mjcf(mjcf_text(params, settings, keyframe=False)), params)


class MujocoModel:
    """The MuJoCo engine behind the engine protocol (:class:`hipsim.engine.Engine`): ``MujocoModel(params).run(trajectory) -> Run``.

    Slider motion, singularity measure, torques and joint forces all come from
    MuJoCo: M and bias from MuJoCo, the rigid closure solved with its
    constraint Jacobian, friction as applied forces (the laws of
    :mod:`hipsim.physics.laws`).

    Args:
        params: the machine.
        machine: ``load_model(params)`` for these very params, to skip building it.
    """

    name = "mujoco"
    #: No overlap and no state: each piece closes its chain from the levers upright.
    pieces = PieceNeeds()

    def __init__(self, params: Parameters, machine: MujocoMachine | None = None):
        if machine is not None and machine.params is not params:
            raise ArgumentError("machine", machine, "load_model(params) of the same params object")
        self.params = params
        self.machine = load_model(params) if machine is None else machine

    def piece_state(self, offset: int, previous: None) -> None:
        """None: nothing is carried between pieces."""
        return None

    def run(self, trajectory, state: None = None) -> Run:
        """Closed kinematics and inverse dynamics along ``trajectory`` (``state``: unused, the engine carries none).

        Raises:
            PoseError: at the first sample out of reach or singular.
        """
        kin, dynamics = trajectory_dynamics(self.machine, trajectory)
        return Run(
            self.name,
            self.params,
            trajectory,
            kin.L,
            kin.Ld,
            kin.Ldd,
            dynamics.torques,
            kin.cond_inv,
            np.zeros(len(trajectory.t), dtype=bool),
            joint_forces=dynamics.joint_forces,
        )
