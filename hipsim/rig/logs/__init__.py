"""Rig logs: the CSV reader, the low-pass measured signals need, the one log type the models take, and the reversals.

Modules: :mod:`~hipsim.rig.logs.reader` (a CSV file scanned once, its samples
in SI units), :mod:`~hipsim.rig.logs.blocks` (the file's bytes read, hashed and
decoded a block at a time for the reader), :mod:`~hipsim.rig.logs.smoothing` (the zero-phase low-pass and
the windows it sets), :mod:`~hipsim.rig.logs.log` (the log the models take,
in memory or in pieces) and :mod:`~hipsim.rig.logs.reversals` (the samples
around each motor's reversal).
"""

from .log import DEFAULT_CUTOFF, DEFAULT_TOLERANCE_DEG, Log, LogInfo, LogPieces, MeasuredLog, load_log
from .reader import RigLog, RigLogFile, read_rig_log
from .reversals import reversal_mask
from .smoothing import lowpass, smooth_motion

__all__ = [
    "DEFAULT_CUTOFF",
    "DEFAULT_TOLERANCE_DEG",
    "Log",
    "LogInfo",
    "LogPieces",
    "MeasuredLog",
    "RigLog",
    "RigLogFile",
    "load_log",
    "lowpass",
    "read_rig_log",
    "reversal_mask",
    "smooth_motion",
]
