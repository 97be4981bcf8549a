"""The rig in the loop: rig logs, the model against them, identification of the machine from them, monitoring a wear test.

By job: :mod:`hipsim.rig.logs` (the reader, the low-pass, the one log type the
models take), :mod:`hipsim.rig.compare` (the model's torques against a log's),
:mod:`hipsim.rig.identification` (the regressor, base parameters, prior, the fit,
its uncertainty, the excitation that makes it well posed),
:mod:`hipsim.rig.monitoring` (a long wear test's friction, snapshot by
snapshot, and its control chart), and :mod:`hipsim.rig.plausibility` (a log's
signals against what the machine can produce).

Pure: functions here return data; they never print and never import :mod:`hipsim.present`.
"""

from .compare import Comparison, compare_log, compare_torques
from .identification.excitation import Excitation, excitation
from .identification.fit import Identification, identify
from .identification.quantities import QUANTITIES
from .identification.regressor import regressor
from .logs.log import Log, LogPieces, MeasuredLog, load_log
from .logs.reader import RigLog, read_rig_log
from .logs.smoothing import lowpass
from .monitoring.monitor_run import monitor

__all__ = [
    "QUANTITIES",
    "Comparison",
    "Excitation",
    "Identification",
    "Log",
    "LogPieces",
    "MeasuredLog",
    "RigLog",
    "compare_log",
    "compare_torques",
    "excitation",
    "identify",
    "load_log",
    "lowpass",
    "monitor",
    "read_rig_log",
    "regressor",
]
