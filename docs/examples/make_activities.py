"""Writes the activity examples of the guide's page "A wear test's report" (run from the repository root:
python docs/examples/make_activities.py).

Synthesised, not measured: one cycle of each activity as OpenSim inverse
kinematics writes it (right hip, ISB angles in degrees, tab separated, 100
samples per cycle plus the closing one), each curve a periodic PCHIP through
key values (percent of the cycle, degrees) read off published mean curves. The
numbers are approximate group means, as the sources plot them; they are
examples of activities as the literature compares them, not a standard.

- jogging_hip_right.mot: jogging at about 3 m/s, stride 0.72 s, stance 40 %
  (Novacheck 1998, "The biomechanics of running", Gait & Posture 7:77-95,
  hip sagittal range -10° to +40°; frontal and transverse about ±7° and ±6°).
  Its load is a second file, jogging_hip_force.sto: one stance peak, 5.5 BW
  against 4.8 BW walking at 5 km/h (Bergmann et al. 1993, J Biomech 26:969-990),
  so 3000 N x 5.5/4.8 = 3440 N on the ISO scale; 300 N in flight and swing as a
  simulator keeps the cup seated.
- stair_up_hip_right.mot: stair ascent, cycle 1.4 s, stance 62 % (hip flexion
  +60° at foot contact to +5° at toe-off and back; adduction ±6°, rotation ±5°;
  Protopapadaki et al. 2007, Clin Biomech 22:203-210; Nadeau et al. 2003, Clin
  Biomech 18:950-959). Its load is in the file (hip_force_N): the ISO twin-peak
  profile scaled by 251/238, stair ascent's peak over walking's (Bergmann et
  al. 2001, J Biomech 34:859-871), peaks 3164 N.
"""

from pathlib import Path

import numpy as np
from scipy.interpolate import PchipInterpolator

HERE = Path(__file__).parent


def periodic(knots_pct, values, s):
    """A periodic PCHIP through (percent of the cycle, value) knots, at cycle fractions s."""
    x = np.asarray(knots_pct, dtype=float) / 100.0
    y = np.asarray(values, dtype=float)
    xs = np.concatenate([x - 1, x, x + 1])
    return PchipInterpolator(xs, np.concatenate([y, y, y]))(np.mod(s, 1.0))


def write_mot(path: Path, name: str, t, columns: dict) -> None:
    labels = ["time", *columns]
    lines = [name, "version=1", f"nRows={t.size}", f"nColumns={len(labels)}", "inDegrees=yes", "endheader", "\t".join(labels)]
    for k in range(t.size):
        lines.append("\t".join(f"{v:.8f}" for v in (t[k], *(c[k] for c in columns.values()))))
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


def jogging():
    period = 0.72
    s = np.arange(101) / 100
    t = s * period
    flexion = periodic([0, 20, 40, 60, 85], [30, 10, -10, 15, 40], s)
    adduction = periodic([0, 15, 40, 70], [2, 8, -2, -7], s)
    rotation = periodic([0, 20, 45, 75], [2, 6, -6, -2], s)
    knee = periodic([0, 15, 40, 70], [15, 40, 20, 95], s)
    write_mot(HERE / "jogging_hip_right.mot", "jogging_hip_right", t, {
        "hip_flexion_r": flexion, "hip_adduction_r": adduction, "hip_rotation_r": rotation, "knee_angle_r": knee,
    })
    force = periodic([0, 5, 20, 38, 42, 90], [300, 600, 3440, 600, 300, 300], s)
    write_mot(HERE / "jogging_hip_force.sto", "jogging_hip_force", t, {"hip_force_N": force})


def stair_up():
    period = 1.4
    s = np.arange(101) / 100
    t = s * period
    flexion = periodic([0, 30, 62, 85], [60, 25, 5, 65], s)
    adduction = periodic([0, 20, 50, 80], [0, 6, 2, -6], s)
    rotation = periodic([0, 25, 55, 80], [0, 5, -5, -2], s)
    knee = periodic([0, 30, 62, 85], [60, 20, 10, 90], s)
    # ISO 14242-1's twin peak (spec §7.2: 300 N, 3000 N at 12 %, 1500 N at 32 %, 3000 N at 50 %, 300 N from 62 %),
    # scaled by 251/238 and placed on stair ascent's longer stance (62 % of the cycle, as ISO's).
    scale = 251.0 / 238.0
    force = periodic([0, 12, 32, 50, 62], [300, 3000 * scale, 1500 * scale, 3000 * scale, 300], s)
    write_mot(HERE / "stair_up_hip_right.mot", "stair_up_hip_right", t, {
        "hip_flexion_r": flexion, "hip_adduction_r": adduction, "hip_rotation_r": rotation, "knee_angle_r": knee,
        "hip_force_N": force,
    })


if __name__ == "__main__":
    jogging()
    stair_up()
