"""The analytic model behind the engine protocol (:class:`hipsim.engine.Engine`): ``AnalyticModel(params).run(trajectory) -> Run``."""

from __future__ import annotations

import numpy as np

from ..engine import PieceNeeds
from ..exceptions import ArgumentError, PoseError
from ..machine.parameters import Parameters
from ..motion.trajectories import Trajectory
from ..results import Run
from .chain_dynamics import chain_inverse_dynamics, chain_motion, chain_slider_motion
from .inverse_kinematics import kinematics
from .virtual_work import inverse_dynamics

__all__ = ["AnalyticModel"]


class AnalyticModel:
    """Spec §3–4, vectorised over time.

    Args:
        params: the machine.
        lever_spin: give the levers the spin their universal joints impose
            (the physics the Pinocchio model has) instead of the spec's
            spin-free levers.
        on_error: "raise" at the first pose out of reach or singular, or
            "flag" to carry such samples as NaN and mark them in ``Run.flagged``.
    """

    name = "analytic"
    #: One sample of overlap, and the wrap-around: the detection of a singularity crossed between two samples
    #: sees the same neighbours in a piece as in one run. A piece of 20,000 samples is some 60 MB of working
    #: arrays and a few ms.
    pieces = PieceNeeds(overlap=1, wraps_around=True, chunk=20_000)

    def __init__(self, params: Parameters, lever_spin: bool = False, on_error: str = "raise"):
        if on_error not in ("raise", "flag"):
            raise ArgumentError("on_error", on_error, "'raise' or 'flag'")
        self.params, self.lever_spin, self.on_error = params, bool(lever_spin), on_error

    def piece_state(self, offset: int, previous: bool | None) -> bool:
        """True: nothing is carried between pieces, a piece may come in any order and be flagged throughout."""
        return True

    def run(self, trajectory: Trajectory, state: bool | None = None) -> Run:
        """Slider motion, motor torques and their parts, and the singularity measure along ``trajectory``.

        Args:
            trajectory: the motion and load.
            state: None (or False) for a whole run; True (:meth:`piece_state`'s) when the
                trajectory is one piece of a longer run, which may be flagged throughout.

        Raises:
            PoseError: a pose out of reach or singular (with ``on_error="raise"``),
                or every sample flagged (unless the trajectory is a piece).
        """
        if self.params.geometry is not None:
            return self._run_chains(trajectory)
        kin = kinematics(self.params, trajectory, on_error=self.on_error)
        if np.all(kin.flagged) and not state:
            raise PoseError(
                f"all {len(trajectory)} samples are out of reach or singular; nothing to compute",
                float(trajectory.t[0]),
                0,
                source=trajectory.name,
            )
        with np.errstate(invalid="ignore", divide="ignore"):  # flagged samples are NaN and stay NaN
            torques = inverse_dynamics(self.params, kin, trajectory.Fe, lever_spin=self.lever_spin)
        return Run(self.name, self.params, trajectory, kin.L, kin.Ld, kin.Ldd, torques, kin.cond_inv, kin.flagged)

    def _run_chains(self, trajectory: Trajectory) -> Run:
        """A per-chain machine (:mod:`hipsim.analytic.chain_dynamics`): the trajectory is the controlled platform's.

        A pose out of reach or singular of either platform raises, whatever ``on_error`` says
        (a per-chain machine carries no flagged samples).
        """
        motion = chain_motion(self.params, trajectory)
        torques = chain_inverse_dynamics(self.params, motion, trajectory.Fe, lever_spin=self.lever_spin)
        L, Ld, Ldd = chain_slider_motion(self.params, motion)
        flagged = np.zeros(len(trajectory.t), dtype=bool)
        return Run(self.name, self.params, trajectory, L, Ld, Ldd, torques, motion.controlled.cond_inv, flagged)
