"""The machine in MuJoCo: the third engine, beside the analytic and the Pinocchio models.

Needs the optional ``mujoco`` package (``pip install 'hipsim[mujoco]'``);
importing this package without it raises
:class:`~hipsim.exceptions.MissingDependencyError`, whose message says so in
one line.

- :mod:`~hipsim.mujoco_engine.mjcf`: the MJCF of any parameter set
  (:func:`mjcf_text`, :func:`write_mjcf`), converted from the same URDF and
  closure declaration as the Pinocchio model, with the settings it states.
- :mod:`~hipsim.mujoco_engine.machine` (the compiled model and its closure
  rows), :mod:`~hipsim.mujoco_engine.closure`, :mod:`~hipsim.mujoco_engine.friction`,
  :mod:`~hipsim.mujoco_engine.dynamics` and :mod:`~hipsim.mujoco_engine.trajectory`:
  closed-chain kinematics and rigid inverse dynamics through MuJoCo's own
  functions (:func:`trajectory_dynamics`).
- :mod:`~hipsim.mujoco_engine.model`: :func:`load_model` and
  :class:`MujocoModel`, which runs them behind the engine protocol
  (:class:`hipsim.engine.Engine`; ``MujocoModel(params).run(trajectory) -> hipsim.Run``,
  also ``hipsim.analyse(..., model="mujoco")``).
- :mod:`~hipsim.mujoco_engine.plant`: :class:`MujocoPlant`, MuJoCo's forward
  dynamics as a plant of :func:`hipsim.control.simulation.simulate`.
"""

from .closure import MujocoKinematics
from .dynamics import MujocoDynamics
from .machine import MujocoMachine
from .mjcf import KEYFRAME, MjcfSettings, mjcf_text, write_mjcf
from .model import MujocoModel, load_model
from .plant import MujocoPlant
from .trajectory import trajectory_dynamics

__all__ = [
    "KEYFRAME",
    "MjcfSettings",
    "MujocoDynamics",
    "MujocoKinematics",
    "MujocoMachine",
    "MujocoModel",
    "MujocoPlant",
    "load_model",
    "mjcf_text",
    "trajectory_dynamics",
    "write_mjcf",
]
