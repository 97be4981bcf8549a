"""Analyses built on the models: runs along a trajectory, the model cross-check, workspace maps, sizing.

Pure: functions here return data; they never print and never import :mod:`hipsim.present`.
"""

from .crosscheck import compare_models, differences
from .runs import analyse
from .sizing import sizing

__all__ = ["analyse", "compare_models", "differences", "sizing"]
