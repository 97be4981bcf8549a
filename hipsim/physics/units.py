"""Unit conversions at the edges: hipsim computes in SI and converts only where it reads or prints.

Each factor multiplies a value in the first unit of its name to give it in the
second: ``speed_rad_s * RPM_PER_RAD_S`` is the speed in rpm.
"""

from __future__ import annotations

import math

__all__ = ["RAD_S_PER_RPM", "RPM_PER_RAD_S"]

#: rpm per rad/s: a motor speed θ̇ in [rad/s] times this is in [rpm].
RPM_PER_RAD_S = 60.0 / (2.0 * math.pi)

#: rad/s per rpm: a rating in [rpm] times this is in [rad/s].
RAD_S_PER_RPM = 2.0 * math.pi / 60.0
