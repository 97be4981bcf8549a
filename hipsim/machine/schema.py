"""The parameter file's layout: every section and key, with its unit, SI scale, bound and meaning.

:data:`SCHEMA` is what :func:`hipsim.machine.parameters.load_parameters` checks a
file against and what :func:`hipsim.machine.toml_writer.parameter_toml` writes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

__all__ = ["OPTIONAL_SECTIONS", "SCHEMA", "Key", "plausible_ranges"]

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
    # The plausible range (low, high) for this class of machine, in the file's unit: values
    # outside load with a warning (:func:`hipsim.machine.parameters.implausible`); None: no range (flags, signs).
    # Zero is plausible too for a key that may be zero and for inertias: a part left out of the model.
    plausible: tuple[float, float] | None = None


#: Every section and key the parameter file must contain, with its SI scale and bound.
SCHEMA: dict[str, dict[str, Key]] = {
    "environment": {
        "gravity_m_s2": Key(
            "float", 1.0, "nonnegative", unit="m/s²", meaning="gravity g along -Z", plausible=(0.0, 10.0)
        ),
    },
    "base": {
        "screw_radius_mm": Key(
            "float", _MM, "positive", unit="mm", meaning="E, screw axes radius", plausible=(50.0, 1000.0)
        ),
        "screw_angles_deg": Key(
            "vector", _DEG, "none", 3, "deg", "θ_i, screw base angles", limit=360.0, plausible=(-360.0, 360.0)
        ),
    },
    "platform": {
        "joint_radius_mm": Key(
            "float", _MM, "positive", unit="mm", meaning="e, platform joint radius", plausible=(30.0, 600.0)
        ),
        "home_offset_deg": Key(
            "float",
            _DEG,
            "none",
            unit="deg",
            meaning="δ, platform joint offset",
            limit=360.0,
            plausible=(-360.0, 360.0),
        ),
        "heights_mm": Key(
            "vector", _MM, "positive", 2, "mm", "h_1, h_2, platform centre heights", plausible=(100.0, 3000.0)
        ),
        "mass_kg": Key(
            "float", 1.0, "nonnegative", unit="kg", meaning="m_m, platform mass (estimate)", plausible=(2.0, 200.0)
        ),
        "inertia_kgmm2": Key("inertia", _KGMM2, unit="kg·mm²", meaning="I_m, platform inertia", plausible=(2.5e4, 4e6)),
    },
    "lever": {
        "length_mm": Key("float", _MM, "positive", unit="mm", meaning="l, lever length", plausible=(100.0, 1000.0)),
        "mass_kg": Key("float", 1.0, "nonnegative", unit="kg", meaning="m_l, lever mass", plausible=(0.1, 15.0)),
        "inertia_kgmm2": Key("inertia", _KGMM2, unit="kg·mm²", meaning="I_l, lever inertia", plausible=(10.0, 3e5)),
    },
    "slider": {
        "mass_kg": Key("float", 1.0, "nonnegative", unit="kg", meaning="m_L, slider mass", plausible=(0.3, 30.0)),
    },
    "screw": {
        "lead_mm": Key("float", _MM, "positive", unit="mm", meaning="p, screw lead", plausible=(1.0, 50.0)),
        "inertia_kgmm2": Key(
            "float", _KGMM2, "nonnegative", unit="kg·mm²", meaning="I_L, screw inertia", plausible=(1.0, 1000.0)
        ),
    },
    "friction": {
        "epsilon_rad_s": Key(
            "float", 1.0, "positive", unit="rad/s", meaning="ε of the smooth sign", plausible=(1e-6, 0.1)
        ),
        "hip_radius_mm": Key("float", _MM, "nonnegative", unit="mm", meaning="r_h", plausible=(5.0, 40.0)),
        "hip_mu": Key("float", 1.0, "nonnegative", meaning="μ_h", plausible=(0.0, 1.0)),
        "thrust_radius_mm": Key("float", _MM, "nonnegative", unit="mm", meaning="r_t", plausible=(10.0, 300.0)),
        "thrust_mu": Key("float", 1.0, "nonnegative", meaning="μ_t", plausible=(0.0, 1.0)),
        "screw_coulomb_Nmm": Key(
            "float", _NMM, "nonnegative", unit="N·mm", meaning="screw Coulomb torque", plausible=(0.0, 500.0)
        ),
        "screw_viscous_Nmm_s_rad": Key(
            "float", _NMM, "nonnegative", unit="N·mm·s/rad", meaning="screw viscous", plausible=(0.0, 5.0)
        ),
        "guide_coulomb_N": Key(
            "float", 1.0, "nonnegative", unit="N", meaning="slider guide Coulomb force", plausible=(0.0, 500.0)
        ),
        "guide_viscous_N_s_mm": Key(
            "float", 1.0 / _MM, "nonnegative", unit="N·s/mm", meaning="guide viscous", plausible=(0.0, 5.0)
        ),
        "ujoint_coulomb_Nmm": Key(
            "float", _NMM, "nonnegative", unit="N·mm", meaning="U-joint Coulomb moment", plausible=(0.0, 1e4)
        ),
        "ujoint_viscous_Nmm_s_rad": Key(
            "float", _NMM, "nonnegative", unit="N·mm·s/rad", meaning="U-joint viscous", plausible=(0.0, 1e4)
        ),
        "sjoint_coulomb_Nmm": Key(
            "float", _NMM, "nonnegative", unit="N·mm", meaning="S-joint Coulomb moment", plausible=(0.0, 1e4)
        ),
        "sjoint_viscous_Nmm_s_rad": Key(
            "float", _NMM, "nonnegative", unit="N·mm·s/rad", meaning="S-joint viscous", plausible=(0.0, 1e4)
        ),
        "thrust_bearing_axial_only": Key(
            "bool",
            meaning="thrust bearing resists only rotation about the platform's z axis (false: along ω)",
            default=False,
        ),
    },
    "convention": {
        "angle_signs": Key("signs", 1.0, "none", 3, meaning="sign flips of α, β, γ"),
    },
    "control": {
        "servo_rate_Hz": Key(
            "float", 1.0, "positive", unit="Hz", meaning="servo (controller) rate", plausible=(100.0, 1e5)
        ),
        "integration_step_ms": Key(
            "float", 1e-3, "positive", unit="ms", meaning="plant integration step (RK4)", plausible=(1e-3, 10.0)
        ),
        "kp_Nm_rad": Key(
            "vector",
            1.0,
            "nonnegative",
            3,
            "N·m/rad",
            "K_p, platform moment per orientation error",
            plausible=(0.0, 1e6),
        ),
        "kd_Nm_s_rad": Key(
            "vector", 1.0, "nonnegative", 3, "N·m·s/rad", "K_d, platform moment per rate error", plausible=(0.0, 1e5)
        ),
        "torque_limit_Nmm": Key(
            "float",
            _NMM,
            "positive",
            unit="N·mm",
            meaning="motor torque limit (inf: none)",
            finite=False,
            plausible=(10.0, math.inf),
        ),
    },
    # Optional: the motor and linear module to check a design against (hipsim report).
    "motor": {
        "rated_torque_Nmm": Key(
            "float",
            1.0,
            "positive",
            unit="N·mm",
            meaning="rated (continuous) motor torque, vs RMS",
            plausible=(10.0, 1e5),
        ),
        "peak_torque_Nmm": Key(
            "float", 1.0, "positive", unit="N·mm", meaning="peak motor torque", plausible=(10.0, 1e5)
        ),
        "max_speed_rpm": Key(
            "float", 1.0, "positive", unit="rpm", meaning="maximum motor speed", plausible=(100.0, 2e4)
        ),
        "stroke_mm": Key(
            "float", 1.0, "positive", unit="mm", meaning="usable stroke of the linear module", plausible=(10.0, 2000.0)
        ),
        "axial_force_N": Key(
            "float", 1.0, "positive", unit="N", meaning="permissible axial screw load", plausible=(100.0, 1e6)
        ),
    },
}

#: Sections whose keys may each be left out (their values are kept in the file's units).
OPTIONAL_SECTIONS = {"motor"}


def plausible_ranges() -> dict[str, tuple[float, float, str]]:
    """Each key's plausible range for this class of machine, by dotted key: (low, high, unit), in the file's unit."""
    return {
        f"{section}.{key}": (*spec.plausible, spec.unit)
        for section, keys in SCHEMA.items()
        for key, spec in keys.items()
        if spec.plausible is not None
    }
