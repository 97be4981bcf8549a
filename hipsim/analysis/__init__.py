"""Model runs: one call picks a model and runs it along a trajectory, in one piece or streamed, and the models' cross-check.

Pure: functions here return data; they never print and never import :mod:`hipsim.present`.
"""

from .crosscheck import compare_models, differences
from .runs import analyse
from .streaming import stream_run

__all__ = ["analyse", "compare_models", "differences", "stream_run"]
