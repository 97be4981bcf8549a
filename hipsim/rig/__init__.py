"""The rig in the loop: rig logs, the model against them, identification of the machine from them, and the excitation that makes it well posed.

Modules: :mod:`~hipsim.rig.reader` (the CSV reader), :mod:`~hipsim.rig.filtering`
(the zero-phase low-pass), :mod:`~hipsim.rig.logs` (the one log type the models
take, in memory or in pieces), :mod:`~hipsim.rig.reversals`,
:mod:`~hipsim.rig.compare`; for identification :mod:`~hipsim.rig.quantities`,
:mod:`~hipsim.rig.regressor`, :mod:`~hipsim.rig.identification` (the fit) and
:mod:`~hipsim.rig.consistency`; :mod:`~hipsim.rig.excitation`.

Pure: functions here return data; they never print and never import :mod:`hipsim.present`.
"""

from .compare import Comparison, compare, compare_log
from .excitation import Excitation, excitation
from .filtering import lowpass
from .identification import Identification, identify
from .logs import Log, LogPieces, MeasuredLog, load_log
from .monitor_run import monitor
from .quantities import QUANTITIES
from .reader import RigLog, read_rig_log
from .regressor import regressor

__all__ = [
    "QUANTITIES",
    "Comparison",
    "Excitation",
    "Identification",
    "Log",
    "LogPieces",
    "MeasuredLog",
    "RigLog",
    "compare",
    "compare_log",
    "excitation",
    "identify",
    "load_log",
    "lowpass",
    "monitor",
    "read_rig_log",
    "regressor",
]
