"""Analyses built on the models: runs along a trajectory, the model cross-check, workspace maps, sizing.

Pure: functions here return data; they never print and never import :mod:`hipsim.present`.
"""

from .runs import Result, analyse

__all__ = ["Result", "analyse"]
