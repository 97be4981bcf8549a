"""The Pinocchio closed-chain model behind the engine protocol (:class:`hipsim.engine.Engine`): ``PinocchioModel(params).run(trajectory) -> Run``."""

from __future__ import annotations

import numpy as np

from ..engine import PieceNeeds
from ..exceptions import ArgumentError
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
    #: No overlap: a Continuation carries the closure solver from one piece to the next. Its working arrays
    #: take ~4 kB a sample (~10 MB a piece of 2,500, 0.08 s of its time), and its process also carries
    #: numba's compiler (~100 MB).
    pieces = PieceNeeds(chunk=2_500)

    def __init__(self, params: Parameters, chain: ClosedChainModel | None = None, parts: bool = True):
        self.params, self.parts = params, bool(parts)
        self.chain = chain if chain is not None else load_model(params)

    def piece_state(self, offset: int, previous: Continuation | None) -> Continuation:
        """A new :class:`~hipsim.closed_chain.closure.Continuation` for the first piece, the previous one for the next.

        Raises:
            ArgumentError: the piece does not start where the previous one stopped.
        """
        if offset == 0:
            return Continuation()
        if previous is None or previous.samples != offset:
            raise ArgumentError("start", offset, "pieces of a Pinocchio run in time order, from 0")
        return previous

    def run(self, trajectory: Trajectory, state: Continuation | None = None) -> Run:
        """Closed kinematics and inverse dynamics along ``trajectory``.

        Args:
            trajectory: the motion.
            state: for a run in pieces, one :class:`~hipsim.closed_chain.closure.Continuation`
                given to every piece in time order (the pieces then give the one-piece results
                bit for bit); :meth:`piece_state` hands it out.

        Raises:
            PoseError: at the first sample out of reach or singular.
        """
        kin, dynamics = trajectory_dynamics(self.chain, trajectory, parts=self.parts, continuation=state)
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
