"""hipsim: kinematics, closed-chain dynamics and control of the 2(3PUS+S) hip joint simulator.

A few calls give what the command line gives:

```python
import hipsim

params = hipsim.load_parameters()                 # the published machine (SI inside)
trajectory = hipsim.iso14242(rate=1000)           # or hipsim.read_trajectory("gait.csv" / "walk.mot")
run = hipsim.analyse(params, trajectory)          # analytic model; model="pinocchio" for the other
run.torques.total                                 # (N, 3) motor torques in N·m; parts in run.torques.PARTS
run.columns()["tau_1_Nmm"]                        # the CSV columns of spec §7.5
run.write_csv("iso.csv")
```

Each layer is a subpackage: `hipsim.machine`, `hipsim.motion`, `hipsim.analytic`,
`hipsim.closed_chain`, `hipsim.control`, `hipsim.analysis`, `hipsim.present`, `hipsim.cli`
(markdown, not reStructuredText: this docstring heads the API reference's home page).
"""

from .exceptions import (
    ArgumentError,
    ClosureError,
    HipsimError,
    ModelError,
    OutputError,
    ParameterError,
    PoseError,
    TrajectoryError,
)
from .version import __version__ as __version__

__all__ = [
    "ArgumentError",
    "ClosureError",
    "HipsimError",
    "JointForces",
    "ModelError",
    "OutputError",
    "ParameterError",
    "Parameters",
    "PoseError",
    "Run",
    "Torques",
    "Trajectory",
    "TrajectoryError",
    "analyse",
    "iso14242",
    "load_parameters",
    "load_trajectory_csv",
    "monitor",
    "read_trajectory",
    "slender_levers",
]

#: Where each public name lives: its module is imported on first use.
_HOMES = {
    "analyse": "analysis.runs",
    "JointForces": "results",
    "Run": "results",
    "Torques": "results",
    "Parameters": "machine.parameters",
    "load_parameters": "machine.parameters",
    "slender_levers": "machine.parameters",
    "Trajectory": "motion.trajectories",
    "iso14242": "motion.trajectories",
    "load_trajectory_csv": "motion.readers",
    "read_trajectory": "motion.readers",
    "monitor": "rig.monitoring.monitor_run",
}
#: The subpackages an eager ``import hipsim`` used to load, still reachable as attributes (``hipsim.motion``).
_SUBPACKAGES = ("analysis", "analytic", "arrays", "files", "machine", "motion", "physics", "results")


def __getattr__(name: str):
    """A public name or subpackage, imported on first use (PEP 562), so that ``import hipsim`` loads no NumPy, SciPy or xacro."""
    home = _HOMES.get(name, name if name in _SUBPACKAGES else None)
    # Absolute imports: ``from . import x`` would first ask this very function for x.
    if home == "analysis.runs":
        import hipsim.analysis.runs as module
    elif home == "machine.parameters":
        import hipsim.machine.parameters as module
    elif home == "motion.trajectories":
        import hipsim.motion.trajectories as module
    elif home == "motion.readers":
        import hipsim.motion.readers as module
    elif home == "rig.monitoring.monitor_run":
        import hipsim.rig.monitoring.monitor_run as module
    elif home == "results":
        import hipsim.results as module
    elif home == "analysis":
        import hipsim.analysis as module
    elif home == "analytic":
        import hipsim.analytic as module
    elif home == "arrays":
        import hipsim.arrays as module
    elif home == "files":
        import hipsim.files as module
    elif home == "machine":
        import hipsim.machine as module
    elif home == "motion":
        import hipsim.motion as module
    elif home == "physics":
        import hipsim.physics as module
    else:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = module if name in _SUBPACKAGES else getattr(module, name)
    globals()[name] = value  # later look-ups skip this function
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__) | set(_SUBPACKAGES))
