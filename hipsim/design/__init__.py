"""Designing the machine: parameter variants, drive sizing, design sweeps and workspace maps.

Pure: functions here return data; they never print and never import :mod:`hipsim.present`.
"""

from .ranking import rank_drives
from .sizing import sizing

__all__ = ["rank_drives", "sizing"]
