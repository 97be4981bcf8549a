"""The parameter file's layout: every section and key, with its unit, SI scale, bound and meaning.

:data:`SCHEMA` is what :func:`hipsim.machine.parameters.load_parameters` checks a
file against and what :func:`hipsim.machine.toml_writer.parameter_toml` writes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

__all__ = ["OPTIONAL_SECTIONS", "SCHEMA", "Key"]

_MM = 1e-3
_KGMM2 = 1e-6
_NMM = 1e-3
_DEG = math.pi / 180.0


@dataclass(frozen=True)
class Key:
    """One entry of the parameter file: its shape, SI scale, bound and meaning."""

    kind: str  # "float", "vector", "inertia", "signs", "bool"
    scale: float = 1.0
    bound: str = "none"  # "positive", "nonnegative", "none"
    length: int = 0  # for vectors
    unit: str = ""
    meaning: str = ""
    finite: bool = True  # False to allow inf (e.g. "no limit")
    # Largest magnitude, in the file's unit: far beyond any machine of this kind, so
    # only a typo or a unit slip reaches it, and the physics never meets overflow.
    limit: float = 1e9
    # The value of a key that files may leave out (keys added after files were
    # written, so that those files still load); None: the key is required.
    default: Any = None

#: Every section and key the parameter file must contain, with its SI scale and bound.
SCHEMA: dict[str, dict[str, Key]] = {
    "environment": {
        "gravity_m_s2": Key("float", 1.0, "nonnegative", unit="m/s²", meaning="gravity g along -Z"),
    },
    "base": {
        "screw_radius_mm": Key("float", _MM, "positive", unit="mm", meaning="E, screw axes radius"),
        "screw_angles_deg": Key("vector", _DEG, "none", 3, "deg", "θ_i, screw base angles", limit=360.0),
    },
    "platform": {
        "joint_radius_mm": Key("float", _MM, "positive", unit="mm", meaning="e, platform joint radius"),
        "home_offset_deg": Key("float", _DEG, "none", unit="deg", meaning="δ, platform joint offset", limit=360.0),
        "heights_mm": Key("vector", _MM, "positive", 2, "mm", "h_1, h_2, platform centre heights"),
        "mass_kg": Key("float", 1.0, "nonnegative", unit="kg", meaning="m_m, platform mass (estimate)"),
        "inertia_kgmm2": Key("inertia", _KGMM2, unit="kg·mm²", meaning="I_m, platform inertia"),
    },
    "lever": {
        "length_mm": Key("float", _MM, "positive", unit="mm", meaning="l, lever length"),
        "mass_kg": Key("float", 1.0, "nonnegative", unit="kg", meaning="m_l, lever mass"),
        "inertia_kgmm2": Key("inertia", _KGMM2, unit="kg·mm²", meaning="I_l, lever inertia"),
    },
    "slider": {
        "mass_kg": Key("float", 1.0, "nonnegative", unit="kg", meaning="m_L, slider mass"),
    },
    "screw": {
        "lead_mm": Key("float", _MM, "positive", unit="mm", meaning="p, screw lead"),
        "inertia_kgmm2": Key("float", _KGMM2, "nonnegative", unit="kg·mm²", meaning="I_L, screw inertia"),
    },
    "friction": {
        "epsilon_rad_s": Key("float", 1.0, "positive", unit="rad/s", meaning="ε of the smooth sign"),
        "hip_radius_mm": Key("float", _MM, "nonnegative", unit="mm", meaning="r_h"),
        "hip_mu": Key("float", 1.0, "nonnegative", meaning="μ_h"),
        "thrust_radius_mm": Key("float", _MM, "nonnegative", unit="mm", meaning="r_t"),
        "thrust_mu": Key("float", 1.0, "nonnegative", meaning="μ_t"),
        "screw_coulomb_Nmm": Key("float", _NMM, "nonnegative", unit="N·mm", meaning="screw Coulomb torque"),
        "screw_viscous_Nmm_s_rad": Key("float", _NMM, "nonnegative", unit="N·mm·s/rad", meaning="screw viscous"),
        "guide_coulomb_N": Key("float", 1.0, "nonnegative", unit="N", meaning="slider guide Coulomb force"),
        "guide_viscous_N_s_mm": Key("float", 1.0 / _MM, "nonnegative", unit="N·s/mm", meaning="guide viscous"),
        "ujoint_coulomb_Nmm": Key("float", _NMM, "nonnegative", unit="N·mm", meaning="U-joint Coulomb moment"),
        "ujoint_viscous_Nmm_s_rad": Key("float", _NMM, "nonnegative", unit="N·mm·s/rad", meaning="U-joint viscous"),
        "sjoint_coulomb_Nmm": Key("float", _NMM, "nonnegative", unit="N·mm", meaning="S-joint Coulomb moment"),
        "sjoint_viscous_Nmm_s_rad": Key("float", _NMM, "nonnegative", unit="N·mm·s/rad", meaning="S-joint viscous"),
        "thrust_bearing_axial_only": Key(
            "bool", meaning="thrust bearing resists only rotation about the platform's z axis (false: along ω)", default=False
        ),
    },
    "convention": {
        "angle_signs": Key("signs", 1.0, "none", 3, meaning="sign flips of α, β, γ"),
    },
    "control": {
        "servo_rate_Hz": Key("float", 1.0, "positive", unit="Hz", meaning="servo (controller) rate"),
        "integration_step_ms": Key("float", 1e-3, "positive", unit="ms", meaning="plant integration step (RK4)"),
        "kp_Nm_rad": Key("vector", 1.0, "nonnegative", 3, "N·m/rad", "K_p, platform moment per orientation error"),
        "kd_Nm_s_rad": Key("vector", 1.0, "nonnegative", 3, "N·m·s/rad", "K_d, platform moment per rate error"),
        "torque_limit_Nmm": Key("float", _NMM, "positive", unit="N·mm", meaning="motor torque limit (inf: none)", finite=False),
    },
    # Optional: the motor and linear module to check a design against (hipsim report).
    "motor": {
        "rated_torque_Nmm": Key("float", 1.0, "positive", unit="N·mm", meaning="rated (continuous) motor torque, vs RMS"),
        "peak_torque_Nmm": Key("float", 1.0, "positive", unit="N·mm", meaning="peak motor torque"),
        "max_speed_rpm": Key("float", 1.0, "positive", unit="rpm", meaning="maximum motor speed"),
        "stroke_mm": Key("float", 1.0, "positive", unit="mm", meaning="usable stroke of the linear module"),
        "axial_force_N": Key("float", 1.0, "positive", unit="N", meaning="permissible axial screw load"),
    },
}

#: Sections whose keys may each be left out (their values are kept in the file's units).
OPTIONAL_SECTIONS = {"motor"}
