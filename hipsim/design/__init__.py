"""Designing the machine: parameter variants, drive sizing, design sweeps and workspace maps.

Pure: functions here return data; they never print and never import :mod:`hipsim.present`.
"""

from .sizing import sizing

__all__ = ["sizing"]
