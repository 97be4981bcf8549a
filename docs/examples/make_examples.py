"""Writes the README's worked example files (run from the repository root: python docs/examples/make_examples.py).

Both hold one cycle of hipsim's built-in ISO 14242-1 approximation (spec §7.2), the
formulas written out here, as a gait lab would hand it over: the hip's ISB joint angles
(flexion, adduction, internal rotation of the Z–X–Y chain, not the machine's α, β, γ),
the resultant hip force in % body weight of a 75 kg subject, time in % of the cycle.
They are examples of the formats, not measured data and not the standard's tables.

- gait_lab_export.csv: a spreadsheet export: semicolons, decimal commas, a comment line,
  the lab's own column names, an event column, every 2 % of the cycle.
- iso_hip_right.mot: the same motion as OpenSim inverse kinematics writes it (right hip,
  degrees, tab separated, 100 Hz, time in s for a 1 s cycle), with the force in N.
"""

from pathlib import Path

import numpy as np
from scipy.interpolate import PchipInterpolator

HERE = Path(__file__).parent
BODY_WEIGHT_N = 75 * 9.80665  # 75 kg


def iso_cycle(s):
    """Platform angles α, β, γ [deg] and load [N] at cycle fractions s (spec §7.2)."""
    w = 2 * np.pi * s
    alpha = 3.5 + 21.5 * np.cos(w)
    beta = 1.5 + 5.5 * np.cos(w - np.radians(40))
    gamma = -4.0 + 6.0 * np.cos(w - np.pi)
    knots_s = np.array([0.0, 0.12, 0.32, 0.50, 0.62])
    knots_f = np.array([300.0, 3000.0, 1500.0, 3000.0, 300.0])
    load = PchipInterpolator(np.concatenate([knots_s - 1, knots_s, knots_s + 1, [2.0]]), np.concatenate([knots_f] * 3 + [[300.0]]))(np.mod(s, 1.0))
    return np.stack([alpha, beta, gamma], axis=1), load


def hip_angles(q_deg):
    """ISB hip chain angles [deg] of platform angles: R = Rz(γ)Ry(β)Rx(α), R_h = CᵀRC = Rz(f)Rx(a)Ry(r)."""
    C = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])  # pelvis x, y, z → machine Y, Z, X
    out = []
    for a, b, g in np.radians(q_deg):
        ca, sa, cb, sb, cg, sg = np.cos(a), np.sin(a), np.cos(b), np.sin(b), np.cos(g), np.sin(g)
        R = np.array([[cg, -sg, 0], [sg, cg, 0], [0, 0, 1]]) @ np.array([[cb, 0, sb], [0, 1, 0], [-sb, 0, cb]]) @ np.array([[1, 0, 0], [0, ca, -sa], [0, sa, ca]])
        Rh = C.T @ R @ C
        out.append([np.arctan2(-Rh[0, 1], Rh[1, 1]), np.arcsin(Rh[2, 1]), np.arctan2(-Rh[2, 0], Rh[2, 2])])
    return np.degrees(out)


def lab_export():
    s = np.arange(0, 101, 2) / 100
    q, load = iso_cycle(s)
    hip = hip_angles(q)
    events = {0: "heel strike (right)", 62: "toe off (right)", 100: "heel strike (right)"}
    lines = [
        "# Example export written for hipsim's README (not measured data): the built-in ISO 14242-1 approximation",
        "# as hip joint angles (ISB chain, right hip) and resultant hip force in % body weight (75 kg).",
        "Cycle [%];Hip Flexion [deg];Hip Adduction [deg];Hip Int. Rotation [deg];F res [%BW];Event",
    ]
    for k, x in enumerate(s):
        # 7 decimals of %BW: the peak maps back onto 3000 N to 1e-9 (4 gave 3000.0001 N, a false crossing of the load limit)
        cells = [f"{100 * x:.1f}", *(f"{v:.6f}" for v in hip[k]), f"{100 * load[k] / BODY_WEIGHT_N:.7f}"]
        lines.append(";".join(c.replace(".", ",") for c in cells) + ";" + events.get(round(100 * x), ""))
    (HERE / "gait_lab_export.csv").write_text("\n".join(lines) + "\n", encoding="utf-8")


def opensim_mot():
    t = np.arange(101) / 100
    q, load = iso_cycle(t)
    hip = hip_angles(q)
    labels = ["time", "hip_flexion_r", "hip_adduction_r", "hip_rotation_r", "knee_angle_r", "hip_force_N"]
    lines = ["iso_hip_right", "version=1", f"nRows={t.size}", f"nColumns={len(labels)}", "inDegrees=yes", "endheader", "\t".join(labels)]
    for k in range(t.size):
        knee = 5.0 + 25.0 * (1.0 - np.cos(2 * np.pi * t[k]))  # a column hipsim does not read
        lines.append("\t".join(f"{v:.8f}" for v in (t[k], *hip[k], knee, load[k])))
    (HERE / "iso_hip_right.mot").write_text("\n".join(lines) + "\n", encoding="utf-8")


if __name__ == "__main__":
    lab_export()
    opensim_mot()
