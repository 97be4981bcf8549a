"""The Pinocchio closed-chain model (spec §6): URDF tree plus six loop closures, and its forward-dynamics plant.

Computed with Pinocchio's kinematics, Jacobians and RNEA, independently of
the analytic model (:mod:`hipsim.analytic`), so that the two can check each
other. Modules, by job:

* :mod:`~hipsim.closed_chain.build`: loading the URDF and the closure file (:func:`load_model`);
* :mod:`~hipsim.closed_chain.solver`: each model's per-thread solver state (workspace, K's block order, batched RNEAs);
* :mod:`~hipsim.closed_chain.workspace`: Pinocchio's Data read through strided views; K's block-triangular order;
* :mod:`~hipsim.closed_chain.closure_kernel`: the compiled arithmetic between Pinocchio's calls;
* :mod:`~hipsim.closed_chain.constraints`: the closures at given configurations (residuals, Jacobian, rank);
* :mod:`~hipsim.closed_chain.closure`: the closure solver, closed kinematics along a trajectory (:func:`kinematics`);
* :mod:`~hipsim.closed_chain.rnea`, :mod:`~hipsim.closed_chain.friction`: the tree's batched RNEA, friction as generalised forces;
* :mod:`~hipsim.closed_chain.dynamics`: the closed-chain inverse dynamics (:func:`inverse_dynamics`, :func:`trajectory_dynamics`);
* :mod:`~hipsim.closed_chain.engine`: the model behind the common model protocol (:class:`PinocchioModel`);
* :mod:`~hipsim.closed_chain.plant`: the forward-dynamics plant; its compiled parts:
  :mod:`~hipsim.closed_chain.tree_kernel` (the tree's kinematics and CRBA),
  :mod:`~hipsim.closed_chain.plant_kernel` (the closure solver), :mod:`~hipsim.closed_chain.plant_step` (RK4).
"""

from .build import ClosedChainModel, load_model
from .closure import Continuation, kinematics
from .dynamics import inverse_dynamics, trajectory_dynamics
from .engine import PinocchioModel

__all__ = [
    "ClosedChainModel",
    "Continuation",
    "PinocchioModel",
    "inverse_dynamics",
    "kinematics",
    "load_model",
    "trajectory_dynamics",
]
