"""The parts of a linear module's drive train, in SI units: the motor and its torque–speed curves, servo amplifier, gearbox, lead screw, and the sizing rules.

A torque–speed curve is a list of speeds and a list of torques: the S1
(continuous) and the peak curve of a motor data sheet. Speeds must rise
strictly; torques must not be negative; between points the curve is linear,
below the first point it holds the first torque, beyond the last point it is
zero (the motor cannot go faster). A single torque without speeds is a flat
curve at every speed (the old scalar ratings ``rated_torque_Nmm`` and
``peak_torque_Nmm`` are read that way).

Drive files are read by :mod:`hipsim.machine.drive`, catalogues by
:mod:`hipsim.machine.drive_catalogues`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..arrays import readonly

__all__ = [
    "DIRECT",
    "END_FIXINGS",
    "Amplifier",
    "Drive",
    "Gearbox",
    "LeadScrew",
    "Motor",
    "SizingRules",
    "TorqueSpeedCurve",
]

#: End fixings of a lead screw: (λ of the first bending mode, Euler buckling factor m = π²/(K·l)²·l²/π², i.e. 1/K²).
#: λ·l are the roots of the beam equations (Euler–Bernoulli); 1/K² from the effective length K·l.
END_FIXINGS = {
    "fixed-free": (1.8751, 0.25),
    "supported-supported": (math.pi, 1.0),
    "fixed-supported": (3.9266, 2.046),
    "fixed-fixed": (4.7300, 4.0),
}


# ---------------------------------------------------------------------------
# The parts


@dataclass(frozen=True, eq=False)
class TorqueSpeedCurve:
    """A motor's torque limit against speed.

    Attributes:
        speed: speeds in [rad/s], (K,), rising strictly, ≥ 0; a single point with ``flat`` for a flat curve.
        torque: torques in [N·m], (K,), ≥ 0.
    """

    speed: np.ndarray
    torque: np.ndarray

    def __post_init__(self):
        speed = readonly(np.atleast_1d(np.asarray(self.speed, dtype=float)))
        torque = readonly(np.atleast_1d(np.asarray(self.torque, dtype=float)))
        if speed.ndim != 1 or speed.shape != torque.shape or speed.size == 0:
            raise ValueError(
                f"TorqueSpeedCurve: speed {speed.shape} and torque {torque.shape} must be equal non-empty 1-D arrays"
            )
        if np.any(np.diff(speed) <= 0) or np.any(speed < 0) or np.any(torque < 0):
            raise ValueError("TorqueSpeedCurve: speeds must rise strictly from ≥ 0 and torques must not be negative")
        object.__setattr__(self, "speed", speed)
        object.__setattr__(self, "torque", torque)

    @property
    def flat(self) -> bool:
        """True for a single point: the same torque at every speed."""
        return self.speed.size == 1

    @property
    def end_speed(self) -> float:
        """The last speed of the curve in [rad/s]; infinity for a flat curve."""
        return math.inf if self.flat else float(self.speed[-1])

    def at(self, speed) -> np.ndarray:
        """The torque limit in [N·m] at speeds in [rad/s] (either sign), zero beyond the curve's end."""
        speed = np.abs(np.asarray(speed, dtype=float))
        if self.flat:
            return np.full(speed.shape, float(self.torque[0]))
        return np.interp(speed, self.speed, self.torque, left=float(self.torque[0]), right=0.0)


@dataclass(frozen=True, eq=False)
class Motor:
    """A servo motor; None for a figure the data sheet does not give (the checks that need it say so).

    Attributes:
        name: the motor's name.
        continuous: the S1 (continuous duty) torque–speed curve.
        peak: the peak torque–speed curve.
        max_speed: the highest permitted speed in [rad/s] (default: the end of the peak curve).
        rotor_inertia: J_m in [kg·m²].
        torque_constant: k_t in [N·m/A] (per RMS phase current).
        winding_resistance: R_pp, phase-to-phase, in [Ω] (copper loss 3/2·R_pp·I², star winding).
        thermal_time_constant: τ_th of the winding in [s].
        thermal_resistance: R_th, winding to ambient, in [K/W].
        rated_power: the data sheet's rated power in [W] (ranks a catalogue; no check uses it).
        cost: a price or any cost figure, lower first (breaks ties in a ranked catalogue).
    """

    name: str
    continuous: TorqueSpeedCurve | None = None
    peak: TorqueSpeedCurve | None = None
    max_speed: float | None = None
    rotor_inertia: float | None = None
    torque_constant: float | None = None
    winding_resistance: float | None = None
    thermal_time_constant: float | None = None
    thermal_resistance: float | None = None
    rated_power: float | None = None
    cost: float | None = None

    @property
    def top_speed(self) -> float | None:
        """The highest speed in [rad/s]: ``max_speed``, else the end of the peak (or S1) curve; None if unknown."""
        if self.max_speed is not None:
            return self.max_speed
        for curve in (self.peak, self.continuous):
            if curve is not None and not curve.flat:
                return curve.end_speed
        return None


@dataclass(frozen=True)
class Amplifier:
    """The servo amplifier (drive) of a motor and its DC link; None for a figure not given.

    Attributes:
        peak_current: in [A] (RMS phase current).
        continuous_current: in [A].
        dc_bus_energy: regenerated energy the DC link capacitors take in without a braking resistor, in [J].
        braking_power: continuous power of the braking resistor in [W].
        braking_peak_power: peak power of the braking resistor (chopper) in [W].
    """

    peak_current: float | None = None
    continuous_current: float | None = None
    dc_bus_energy: float | None = None
    braking_power: float | None = None
    braking_peak_power: float | None = None


@dataclass(frozen=True)
class Gearbox:
    """A gearbox (or belt stage) between motor and screw.

    Attributes:
        name: its name.
        ratio: i = motor speed / screw speed [–].
        efficiency: η in (0, 1], the same in both directions of power flow.
        inertia: its inertia referred to the motor shaft in [kg·m²].
    """

    name: str
    ratio: float = 1.0
    efficiency: float = 1.0
    inertia: float = 0.0


#: The motor coupled straight to the screw.
DIRECT = Gearbox("direct", 1.0, 1.0, 0.0)


@dataclass(frozen=True)
class LeadScrew:
    """A lead (ball) screw and its nut; None for a figure not given.

    Attributes:
        name: its name.
        lead: p in [m] per turn; None to keep the machine's.
        inertia: I_L, the screw's inertia about its axis, in [kg·m²]; None to keep the machine's.
        dynamic_load_rating: C_a in [N] (ISO 3408-5; of one nut half for a preloaded double nut).
        preload: F_pr in [N], the nut's preload (0 for none).
        root_diameter: d_2 in [m], for the critical speed and buckling load.
        free_length: unsupported length l between the bearings (or bearing and nut) in [m].
        end_fixing: one of :data:`END_FIXINGS`.
        stroke: usable stroke of the linear module in [m].
        axial_force: permissible axial load in [N].
    """

    name: str
    lead: float | None = None
    inertia: float | None = None
    dynamic_load_rating: float | None = None
    preload: float = 0.0
    root_diameter: float | None = None
    free_length: float | None = None
    end_fixing: str | None = None
    stroke: float | None = None
    axial_force: float | None = None

    def __post_init__(self):
        if self.end_fixing is not None and self.end_fixing not in END_FIXINGS:
            raise ValueError(f"LeadScrew.end_fixing: expected one of {', '.join(END_FIXINGS)}, got {self.end_fixing!r}")


@dataclass(frozen=True)
class SizingRules:
    """What a design must meet (the defaults are the usual industrial rules; each settable).

    Attributes:
        inertia_ratio_max: largest load-to-rotor inertia ratio [–] (10:1 by default).
        life_target_cycles: lead screw L10 life to reach, in test cycles (ISO 14242-1: 5×10⁶).
        winding_rise_max: largest winding temperature rise in [K].
        rated_winding_rise: the rise at which the S1 stall torque is rated, in [K] (servo data sheets:
            100 K over 40 °C ambient); sets R_th when the motor gives none.
        critical_speed_factor: fraction of the screw's critical (whirling) speed allowed [–].
        buckling_factor: fraction of the screw's Euler buckling load allowed [–].
    """

    inertia_ratio_max: float = 10.0
    life_target_cycles: float = 5e6
    winding_rise_max: float = 100.0
    rated_winding_rise: float = 100.0
    critical_speed_factor: float = 0.8
    buckling_factor: float = 0.5


@dataclass(frozen=True)
class Drive:
    """One linear module's drive train: the same for all three modules.

    Attributes:
        motor: the motor.
        amplifier: its servo amplifier, or None.
        gearbox: the gearbox between motor and screw, or None for a direct coupling.
        screw: the lead screw, or None.
        rules: the sizing rules that came with it.
        source: where it came from.
    """

    motor: Motor
    amplifier: Amplifier | None = None
    gearbox: Gearbox | None = None
    screw: LeadScrew | None = None
    rules: SizingRules = field(default_factory=SizingRules)
    source: str = "<given>"

    @property
    def name(self) -> str:
        """ "motor", "motor + gearbox", "motor + gearbox + screw"."""
        parts = [self.motor.name]
        if self.gearbox is not None and self.gearbox is not DIRECT:
            parts.append(self.gearbox.name)
        if self.screw is not None:
            parts.append(self.screw.name)
        return " + ".join(parts)
