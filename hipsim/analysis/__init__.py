"""Analyses built on the models: runs along a trajectory, the model cross-check, workspace maps, sizing.

Pure: functions here return data; they never print and never import :mod:`hipsim.present`.
"""

from .compare import Comparison, compare, load_log
from .crosscheck import compare_models, differences
from .excitation import Excitation, excitation
from .identification import Identification, identify, regressor
from .runs import analyse
from .sizing import sizing
from .streaming import stream_run

__all__ = [
    "Comparison",
    "Excitation",
    "Identification",
    "analyse",
    "compare",
    "compare_models",
    "differences",
    "excitation",
    "identify",
    "load_log",
    "regressor",
    "sizing",
    "stream_run",
]
