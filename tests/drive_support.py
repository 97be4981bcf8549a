"""Helpers of the drive and sizing tests: constant screw-shaft demands, a check by name, curves in rpm, files in a folder."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from hipsim.design.demand import ScrewSide
from hipsim.machine.drive_parts import TorqueSpeedCurve

RPM = 2 * math.pi / 60  # rad/s per rpm


def write(tmp_path, text, name="motors.csv") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def constant_side(run, speed, torque, axial=0.0, acceleration=0.0, inertia=1e-4, cycles=1.0) -> ScrewSide:
    """Screw-shaft demands held constant over the run's 1 s (100 samples of 10 ms): closed forms apply."""
    n = len(run.t)
    full = lambda x: np.full((n, 3), float(x))
    return ScrewSide(
        run, cycles, np.full(n, 0.01), full(speed), full(acceleration), full(torque), full(axial), full(inertia)
    )


def only(checks, name, module=1):
    (check,) = [c for c in checks if c.name == name and c.module == module]
    return check


def curve(speeds_rpm, torques_Nm):
    return TorqueSpeedCurve(np.asarray(speeds_rpm, dtype=float) * RPM, torques_Nm)
