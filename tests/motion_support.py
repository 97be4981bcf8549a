"""Helpers of the motion readers' law tests: a call with its trajectory warnings silenced, the error it raises, and
the tiny tables the readers read (eight rows at 100 Hz, whole-number angles and loads) as CSV, .mot and Parquet."""

from __future__ import annotations

import warnings

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from hipsim import TrajectoryError
from hipsim.motion.build import TrajectoryWarning


def quiet(call):
    """``call()`` with hipsim's trajectory warnings silenced (the test is about its result or its error)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TrajectoryWarning)
        return call()


def error_of(call) -> TrajectoryError:
    """The :class:`TrajectoryError` that ``call()`` raises (warnings silenced); the test fails if it raises none."""
    with pytest.raises(TrajectoryError) as info:
        quiet(call)
    return info.value


N = 8
T = np.arange(N) / 100.0
ALPHA = 10.0 + np.arange(N)  # [deg]
BETA = 2.0 * np.arange(N)
GAMMA = -1.0 * np.arange(N)
LOAD = 1000.0 + 100.0 * np.arange(N)  # [N]
Q = np.radians(np.column_stack([ALPHA, BETA, GAMMA]))


def csv_file(path, load=True, closing=False) -> str:
    header = "t_s,alpha_deg,beta_deg,gamma_deg" + (",Fe_N" if load else "")
    rows = [
        ",".join(f"{v:g}" for v in (T[k], ALPHA[k], BETA[k], GAMMA[k], *((LOAD[k],) if load else ()))) for k in range(N)
    ]
    path.write_text("\n".join([header, *rows]) + "\n")
    return str(path)


def mot_file(path, load=True) -> str:
    labels = "time\thip_flexion_r\thip_adduction_r\thip_rotation_r\thip_flexion_l\thip_adduction_l\thip_rotation_l"
    lines = ["ik", "inDegrees=yes", "endheader", labels + ("\tF" if load else "")]
    for k in range(N):
        values = [T[k], ALPHA[k], 0.0, 0.0, -ALPHA[k], 0.0, 0.0] + ([LOAD[k]] if load else [])
        lines.append("\t".join(f"{v:g}" for v in values))
    path.write_text("\n".join(lines) + "\n")
    return str(path)


def parquet_file(path, columns: dict) -> str:
    pq.write_table(pa.table(columns), path)
    return str(path)


def own_columns(load=True) -> dict:
    columns = {"t_s": T, "alpha_deg": ALPHA, "beta_deg": BETA, "gamma_deg": GAMMA}
    return {**columns, "Fe_N": LOAD} if load else columns
