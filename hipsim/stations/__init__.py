"""Two stations on one set of carriages: per-chain calibration, carriage commands for one platform or both, tolerances.

- :mod:`~hipsim.stations.deviations`: the 51 per-chain values (48 of the chains and centres, 3 of the stack-up) as one vector δ;
- :mod:`~hipsim.stations.sensitivity`: how the attitudes move with δ, and what any log can see of it;
- :mod:`~hipsim.stations.calibration`: kinematic calibration from the encoders and both attitude sensors;
- :mod:`~hipsim.stations.calibration_summary`: what ``calibrate`` reports, as records (and the held-out check);
- :mod:`~hipsim.stations.logs`: calibration logs read from their files;
- :mod:`~hipsim.stations.commands`: carriage commands (``control`` 1, 2 or both) and the attitudes they give;
- :mod:`~hipsim.stations.summary`: per platform and angle, RMS and peak errors;
- :mod:`~hipsim.stations.tolerance`: Monte Carlo of manufacturing tolerances and the sensitivity table;
- :mod:`~hipsim.stations.excitation`: a motion that makes the calibration well-posed.
"""

from .calibration import Calibration, CalibrationLog, calibrate
from .commands import CONTROLS, StationMotion, attitudes, station_commands
from .tolerance import ToleranceResult, parse_tolerances, tolerance_draws

__all__ = [
    "CONTROLS",
    "Calibration",
    "CalibrationLog",
    "StationMotion",
    "ToleranceResult",
    "attitudes",
    "calibrate",
    "parse_tolerances",
    "station_commands",
    "tolerance_draws",
]
