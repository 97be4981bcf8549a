"""What each specimen went through: slide tracks, cross-shear, work and predicted wear on the cup, from any motion.

Beside :mod:`hipsim.analysis` and :mod:`hipsim.design`: it reads motion
(:mod:`hipsim.motion`) and nothing of the machine's models. Pure: functions
return data. The definitions are in the guide's page "Slide tracks, cross-shear
and wear" and in :mod:`hipsim.wear.maps`.
"""

from .kinematics import CupSetup, relative_motion, sequence_rotation
from .laws import ContactAreaLaw, CrossShearLaw, Wear, WearFactor, predict_wear, read_wear_law
from .maps import WearMaps, wear_maps
from .points import CupPoints, cup_grid, cup_points
from .tracks import Tracks, cycle_tracks

__all__ = [
    "ContactAreaLaw",
    "CrossShearLaw",
    "CupPoints",
    "CupSetup",
    "Tracks",
    "Wear",
    "WearFactor",
    "WearMaps",
    "cup_grid",
    "cup_points",
    "cycle_tracks",
    "predict_wear",
    "read_wear_law",
    "relative_motion",
    "sequence_rotation",
    "wear_maps",
]
