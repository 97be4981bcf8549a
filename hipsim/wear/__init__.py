"""What each specimen went through: slide tracks, cross-shear, work and predicted wear on the cup, from any motion.

Beside :mod:`hipsim.analysis` and :mod:`hipsim.design`: it reads motion
(:mod:`hipsim.motion`) and nothing of the machine's models. Pure: functions
return data. The definitions are in the guide's page "Slide tracks, cross-shear
and wear" and in :mod:`hipsim.wear.maps`; a test's weighings, the wear factors
fitted from them and the wear over the test in "A wear test's report".
"""

from .factors import ForceTrackFactor, parse_wear_factor
from .gravimetric import Gravimetry, gravimetry
from .kinematics import CupSetup, relative_motion, sequence_rotation
from .laws import ContactAreaLaw, CrossShearLaw, Wear, WearFactor, predict_wear, read_wear_law
from .maps import WearMaps, wear_maps
from .points import CupPoints, cup_grid, cup_points
from .test_result import WearTest, wear_test
from .tracks import Tracks, cycle_tracks
from .weighings import Weighings, read_weighings

__all__ = [
    "ContactAreaLaw",
    "CrossShearLaw",
    "CupPoints",
    "CupSetup",
    "ForceTrackFactor",
    "Gravimetry",
    "Tracks",
    "Wear",
    "WearFactor",
    "WearMaps",
    "WearTest",
    "Weighings",
    "cup_grid",
    "cup_points",
    "cycle_tracks",
    "gravimetry",
    "parse_wear_factor",
    "predict_wear",
    "read_wear_law",
    "read_weighings",
    "relative_motion",
    "sequence_rotation",
    "wear_maps",
    "wear_test",
]
