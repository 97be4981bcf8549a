"""Trajectory files for the readers' tests: the ISO cycle (spec §7.2) and small tables written as CSV text.

Written here by string formatting of the formulas, never by the code under test.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from hipsim.motion.trajectories import ANGLE_NAMES, iso14242_angles, iso14242_load

DEG = math.pi / 180.0


def csv_text(t, q, load=None, unit="deg", fmt=repr) -> str:
    """CSV text of t [s], q [rad] (written in ``unit``) and optionally F_e [N]."""
    columns = ["t_s", *(f"{a}_{unit}" for a in ANGLE_NAMES)] + (["Fe_N"] if load is not None else [])
    angles = np.degrees(q) if unit == "deg" else np.asarray(q)
    lines = [",".join(columns)]
    for k in range(len(t)):
        row = [t[k], *angles[k]] + ([load[k]] if load is not None else [])
        lines.append(",".join(fmt(float(v)) for v in row))
    return "\n".join(lines) + "\n"


def write_iso_csv(path: Path, rate: float, cycles: float, closing: bool, unit="deg", with_load=True):
    """The ISO cycle sampled at ``rate`` over ``cycles``, with the closing row t = cycles/f if asked."""
    n = int(round(cycles * rate)) + (1 if closing else 0)
    t = np.arange(n) / rate
    q, qd, qdd = iso14242_angles(t)
    load = iso14242_load(t) if with_load else None
    path.write_text(csv_text(t, q, load, unit))
    return t, q, qd, qdd, load


def relative_errors(traj, qd, qdd):
    """Per-sample, per-angle error of qd and qdd relative to each angle's peak."""
    m = len(traj)
    e1 = np.abs(traj.qd - qd[:m]) / np.abs(qd).max(axis=0)
    e2 = np.abs(traj.qdd - qdd[:m]) / np.abs(qdd).max(axis=0)
    return e1, e2


def small_csv(rows=None, header="t_s,alpha_deg,beta_deg,gamma_deg,Fe_N", n=10) -> list[str]:
    """A valid CSV as lines: header (line 1) then rows at 100 Hz (row k on line k + 2)."""
    if rows is None:
        t = np.arange(n) / 100.0
        q, _, _ = iso14242_angles(t)
        load = iso14242_load(t)
        rows = [",".join(repr(float(v)) for v in (t[k], *np.degrees(q[k]), load[k])) for k in range(n)]
    return [header, *rows]


def write_lines(path: Path, lines: list[str]) -> Path:
    path.write_text("\n".join(lines) + "\n")
    return path


def set_cell(lines: list[str], line: int, column: int, value: str) -> list[str]:
    """Replace the cell at 1-based file line ``line`` and 0-based column."""
    out = list(lines)
    cells = out[line - 1].split(",")
    cells[column] = value
    out[line - 1] = ",".join(cells)
    return out


def assert_traj_error(info, path: Path, line: int | None = None, column: str | None = None):
    message = str(info.value)
    assert str(path) in message, message
    assert info.value.source == str(path)
    if line is not None:
        assert f"line {line}" in message, message
        assert info.value.line == line
    if column is not None:
        assert f"'{column}'" in message, message


def iso_rows(n=101, rate=100.0):
    """(t, angles in degrees (N, 3), load) of the ISO cycle, the closing row included when n = rate + 1."""
    t = np.arange(n) / rate
    q, _, _ = iso14242_angles(t)
    return t, np.degrees(q), iso14242_load(t)


def canonical(path, t, deg, load):
    rows = [",".join(repr(float(v)) for v in (t[k], *deg[k], load[k])) for k in range(len(t))]
    return write_lines(path, ["t_s,alpha_deg,beta_deg,gamma_deg,Fe_N", *rows])


def assert_same_trajectory(a, b, exact=True):
    for name in ("t", "q", "qd", "qdd", "Fe"):
        x, y = getattr(a, name), getattr(b, name)
        if exact:
            np.testing.assert_array_equal(x, y, err_msg=name)
        else:
            np.testing.assert_allclose(x, y, rtol=1e-9, atol=1e-12 * max(1.0, float(np.abs(y).max())), err_msg=name)
    assert a.periodic == b.periodic


def iso_file(path, t, load=True):
    q, _, _ = iso14242_angles(t)
    path.write_text(csv_text(t, q, iso14242_load(t) if load else None))
    return path
