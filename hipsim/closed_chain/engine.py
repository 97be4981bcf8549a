"""The Pinocchio closed-chain model behind the common model protocol: ``PinocchioModel(params).run(trajectory) -> Run``."""

from __future__ import annotations

import numpy as np

from ..machine.parameters import Parameters
from ..motion.trajectories import Trajectory
from ..results import Run
from .build import ClosedChainModel, load_model
from .closure import Continuation
from .dynamics import trajectory_dynamics

__all__ = ["PinocchioModel"]


class PinocchioModel:
    """Spec §6: the URDF tree with its six loop closures, closed and solved sample by sample.

    Everything in the :class:`Run` comes from this model: slider motion from
    the closed configurations, the singularity measure from the velocity
    closure's Jacobian, torques and joint forces from one constrained solve.

    Args:
        params: the machine.
        chain: an already loaded closed-chain model of ``params`` (loaded when None).
        parts: split the torques into their parts (spec §4.4); False for the
            total only, a few µs a sample less (one batched RNEA instead of
            three), with the parts NaN (for callers that read the total alone,
            such as fits and checks).
    """

    name = "pinocchio"

    def __init__(self, params: Parameters, chain: ClosedChainModel | None = None, parts: bool = True):
        self.params, self.parts = params, bool(parts)
        self.chain = chain if chain is not None else load_model(params)

    def run(self, trajectory: Trajectory, continuation: Continuation | None = None) -> Run:
        """Closed kinematics and inverse dynamics along ``trajectory``.

        Args:
            trajectory: the motion.
            continuation: for a run in pieces, one :class:`~hipsim.closed_chain.closure.Continuation`
                given to every piece in time order (the pieces then give the one-piece results bit for bit).

        Raises:
            PoseError: at the first sample out of reach or singular.
        """
        kin, dynamics = trajectory_dynamics(self.chain, trajectory, parts=self.parts, continuation=continuation)
        return Run(
            self.name, self.params, trajectory, kin.L, kin.Ld, kin.Ldd, dynamics.torques, kin.cond_inv,
            np.zeros(len(trajectory.t), dtype=bool), joint_forces=dynamics.joint_forces,
        )
