"""One snapshot read: by the rig-log reader, once, with the monitor's own columns (the cycle counter, per-station and commanded loads).

:func:`read_snapshot` opens the snapshot's file once through
:class:`~hipsim.rig.logs.reader.RigLogFile` (a window of a long log: only its
lines), so a snapshot is read by the rules and checks of every rig log, and
keeps beside the samples the ``cycle`` counter (checked: whole, ≥ 0,
non-decreasing), the per-station loads ``Fe_1_N``, ``Fe_2_N`` and the
commanded load ``Fe_cmd_N`` when the file has them. The log the models take
(:class:`~hipsim.rig.logs.log.LogPieces`) is made from that one scan.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...exceptions import TrajectoryError
from ...machine.parameters import Parameters
from ..logs.log import DEFAULT_TOLERANCE_DEG, LogPieces, MeasuredLog
from ..logs.reader import RigLogFile
from .snapshots import COMMANDED_LOAD, CYCLE_COLUMN, STATION_LOADS, Snapshot, check_counter

__all__ = ["SnapshotLog", "read_snapshot"]


@dataclass(frozen=True, eq=False)
class SnapshotLog:
    """A snapshot as the fit takes it.

    Attributes:
        log: the log the models take (filtered, differentiated).
        cycles: the cycle counter per sample, (N,).
        loads: the per-station loads in [N], (N, 2), or None when the file has not both.
        load_gain: the measured load over the commanded, least squares Σ F·F_cmd / Σ F_cmd², or NaN without
            ``Fe_cmd_N`` (or a commanded load of zero throughout).
    """

    log: MeasuredLog
    cycles: np.ndarray
    loads: np.ndarray | None
    load_gain: float


def read_snapshot(
    snapshot: Snapshot,
    params: Parameters,
    torque_constant: float | None = None,
    cutoff: float | None = 20.0,
    tolerance_deg: float = DEFAULT_TOLERANCE_DEG,
    rate: float | None = None,
    columns: str | None = None,
) -> SnapshotLog:
    """Read one snapshot (its file once; a window: its lines).

    Args:
        snapshot: the snapshot.
        params: the machine (the encoders' forward kinematics).
        torque_constant: the motors' torque constant in [N·m/A], for logs of currents.
        cutoff: low-pass cutoff in [Hz], or None.
        tolerance_deg: the attitude sensor's allowed disagreement with the encoders in [deg].
        rate: sample rate in [Hz] to read the times from the sample index (stamps too coarse), or None.
        columns: a TDMS or HDF5 snapshot's column map (:mod:`hipsim.channels`), or None.

    Raises:
        TrajectoryError: naming the file, line and column: the reader's errors, no ``cycle`` column, a counter that
            is not whole or decreases, a negative station load, a snapshot too short for its filter.
    """
    source = snapshot.path
    keep = (CYCLE_COLUMN, *STATION_LOADS, COMMANDED_LOAD)
    raw = RigLogFile(source, torque_constant, keep=keep, rate=rate, lines=snapshot.lines, columns=columns)
    try:
        kept = raw.kept
        if CYCLE_COLUMN not in kept:
            raise TrajectoryError(
                f"no '{CYCLE_COLUMN}' column: a snapshot needs the machine's cycle counter", source=source
            )
        cycles = check_counter(kept[CYCLE_COLUMN], raw.lines, source)
        loads = None
        if all(name in kept for name in STATION_LOADS):
            loads = np.column_stack([kept[name] for name in STATION_LOADS])
            if (loads < 0).any():
                k, j = np.argwhere(loads < 0)[0]
                raise TrajectoryError(
                    f"load {loads[k, j]:g} N is negative (a station's load is a magnitude)",
                    source=source,
                    line=int(raw.lines[k]),
                    column=STATION_LOADS[j],
                )
        gain = math.nan
        if COMMANDED_LOAD in kept:
            commanded = kept[COMMANDED_LOAD]
            square = float(commanded @ commanded)
            if square > 0:
                gain = float(raw.read().Fe @ commanded) / square
        with LogPieces(source, params, torque_constant, cutoff, tolerance_deg, raw=raw) as pieces:
            log = pieces.whole()
    finally:
        raw.close()
    return SnapshotLog(log, cycles, loads, gain)
