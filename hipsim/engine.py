"""The contracts every engine and every plant keeps, so that runs, streams, checks and simulations need not know which one they drive.

An **engine** (the analytic model, the Pinocchio closed-chain model, the
MuJoCo engine) is built for one machine and computes a
:class:`~hipsim.results.Run` along a trajectory: ``engine.run(trajectory,
state)``. A run in pieces (:mod:`hipsim.analysis.streaming`) gives the
one-piece results to the last digit when it honours what the engine states in
:class:`PieceNeeds` (the samples each piece must see before its own, whether
a periodic motion's first piece follows its last sample) and carries the
state :meth:`Engine.piece_state` hands out from one piece to the next (the
Pinocchio model's :class:`~hipsim.closed_chain.closure.Continuation`).

A **plant** is what :func:`hipsim.control.simulation.simulate` integrates; it
may offer its forward dynamics compiled (:class:`Plant`).

The engines and plants are found by name in :mod:`hipsim.analysis.registry`,
which loads them only when asked for.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Protocol, runtime_checkable

import numpy as np

from .machine.parameters import Parameters
from .motion.trajectories import Trajectory
from .results import Run

__all__ = ["Engine", "PieceNeeds", "Plant"]


@dataclass(frozen=True)
class PieceNeeds:
    """What a run in pieces must give an engine for its pieces to add up to the one-piece run.

    Attributes:
        overlap: samples before each piece (after the first) that the piece's
            run must see again, its halo; they are run and dropped.
        wraps_around: the first piece of a periodic motion is run after the
            motion's last sample (sample 0 follows it).
        chunk: samples per piece when the caller does not say (memory and
            time are set by it, the results are not).
    """

    overlap: int = 0
    wraps_around: bool = False
    chunk: int = 20_000


@runtime_checkable
class Engine(Protocol):
    """A model of the machine that computes a :class:`~hipsim.results.Run` along a trajectory.

    Attributes:
        name: the engine's name in :mod:`hipsim.analysis.registry`, and the
            ``model`` of its runs.
        params: the machine it was built for.
        pieces: what a run in pieces needs (:class:`PieceNeeds`).
    """

    name: str
    params: Parameters
    pieces: PieceNeeds

    def piece_state(self, offset: int, previous: Any) -> Any:
        """The state to run the piece that starts ``offset`` samples into the run with.

        Args:
            offset: index in the whole run of the piece's first sample
                (negative when the piece starts with the wrap-around sample).
            previous: the state the previous piece ran with (None before the first).

        Raises:
            ArgumentError: the engine cannot run that piece next (pieces out of order).
        """

    def run(self, trajectory: Trajectory, state: Any = None) -> Run:
        """The run along ``trajectory``: slider motion, torques and their parts, the singularity measure.

        Args:
            trajectory: the motion and load.
            state: None for a whole run; for a piece of a longer run, what
                :meth:`piece_state` gave (it may be updated in place).

        Raises:
            PoseError: at a sample out of reach or singular (index and time of ``trajectory``).
        """


class Plant(Protocol):
    """What :func:`~hipsim.control.simulation.simulate` integrates. The state x is a flat vector.

    A plant may also offer ``advance(t, x, tau, loads, h, substeps)``, the
    state after ``substeps`` RK4 steps (as
    :meth:`~hipsim.control.simulation.ReducedPlant.advance`), to integrate a
    servo period in one call; and, with it, ``angle_slots``: (angle indices,
    rate indices, signs) such that the gait angles and rates are
    signs·x[indices], so that the built-in controllers run compiled around it
    (as for :class:`~hipsim.closed_chain.plant.PinocchioPlant`). A plant whose
    forward dynamics are compiled whole may offer ``compiled_kernel()``: the
    parameters of :mod:`hipsim.analytic.kernel` its state x = [q, q̇] follows
    (or None), so that the whole servo loop runs compiled (as for
    :class:`~hipsim.control.simulation.ReducedPlant`). A plant that also offers
    ``readings(x)`` (the carriages and both platforms' attitudes, as all three
    built-in plants do) can be driven by a controller that knows another machine
    (:func:`hipsim.control.machine_loop.run_machine`).
    """

    params: Parameters  # the plant's machine: servo defaults, and the motor speeds of the result
    name: str  # for tables (optional: the class name otherwise)

    def initial_state(self, desired: Trajectory) -> np.ndarray:
        """The state at the first sample of ``desired`` (position and velocity)."""

    def derivative(self, t: float, x: np.ndarray, tau: np.ndarray, Fe: float) -> np.ndarray:
        """dx/dt under motor torques tau in [N·m] and load Fe in [N]."""

    def angles(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Platform orientation [α, β, γ] in [rad] and its rate in [rad/s] in state x."""
