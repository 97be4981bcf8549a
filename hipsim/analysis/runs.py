"""One call for a model run: :func:`analyse` picks the model, runs it and returns a :class:`~hipsim.results.Run`."""

from __future__ import annotations

from ..machine.parameters import Parameters, load_parameters
from ..motion.trajectories import Trajectory, iso14242
from ..results import Run
from .registry import engine_names, make_engine

__all__ = ["MODELS", "analyse"]

#: The models :func:`analyse` runs, by name (:func:`hipsim.analysis.registry.engine_names`).
MODELS = engine_names()


def analyse(
    params: Parameters | None = None,
    trajectory: Trajectory | None = None,
    model: str = "analytic",
    on_error: str = "raise",
    lever_spin: bool = False,
) -> Run:
    """Run a model along a trajectory: slider motion, motor torques and their parts.

    Args:
        params: the machine; None for the published one.
        trajectory: the motion and load; None for one ISO 14242-1 cycle at 1 kHz.
        model: "analytic" (spec §4), "pinocchio" (spec §6, adds joint forces) or
            "mujoco" (the same machine in MuJoCo; needs the ``mujoco`` extra).
        on_error: "raise" at the first pose out of reach or singular, or "flag"
            to mark such samples (analytic model only).
        lever_spin: analytic model only: give the levers the universal joints'
            spin (see :func:`hipsim.analytic.inverse_dynamics`).

    Returns:
        The :class:`~hipsim.results.Run`.
    """
    params = params if params is not None else load_parameters()
    trajectory = trajectory if trajectory is not None else iso14242()
    # The engine loads only when asked for; MissingDependencyError, with the install line, without its extra.
    return make_engine(model, params, on_error=on_error, lever_spin=lever_spin).run(trajectory)
