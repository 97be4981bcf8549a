"""The rig in the loop: rig logs, the model against them, identification of the machine from them, and the excitation that makes it well posed.

Pure: functions here return data; they never print and never import :mod:`hipsim.present`.
"""

from .compare import Comparison, compare, load_log
from .excitation import Excitation, excitation
from .identification import Identification, identify, regressor
from .logs import MeasuredLog, RigLog, lowpass, read_rig_log

__all__ = [
    "Comparison", "Excitation", "Identification", "MeasuredLog", "RigLog",
    "compare", "excitation", "identify", "load_log", "lowpass", "read_rig_log", "regressor",
]
