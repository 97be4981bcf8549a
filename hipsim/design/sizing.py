"""Sizing: what a run asks of each linear module, checked against a drive the way industrial sizing tools check it.

Pure: it returns data (the report and the command line present it).

Two forces along each screw, defined here once and named apart:

- :func:`motor_thrust`: 2π·τ/p, the motor torque written as a force along the
  screw (what the viewer's magenta arrows draw). It includes the torque that
  spins the screw's own rotor and overcomes its friction.
- :func:`axial_screw_load`: 2π·(τ − τ_L − τ_sf)/p, the force between nut and
  carriage, which is what loads the screw, its nut and its bearings (life,
  buckling, permissible load).

The checks per module (:data:`CHECKS`), each with value, limit, margin and
pass/fail, over every sample of the cycle:

- motor: every (speed, torque) point under the peak curve; the RMS torque at
  the mean speed under the S1 curve; the peak speed; the load-to-rotor inertia
  ratio, the load being the machine's inertia M(q) reflected to the motor along
  the cycle; the winding temperature rise from the copper losses (first-order
  thermal model);
- amplifier: peak and RMS current; regenerated energy per cycle and the mean
  and peak regenerative power (negative motor power);
- lead screw: L10 life in test cycles (ISO 3408-5), critical (whirling)
  speed, buckling load, stroke, permissible axial load.

A check whose data are missing is listed with ``passed`` None and says what
it needs. The formulas are in each function's docstring and the README.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field
from typing import Any, Callable, Iterable, Sequence

import numpy as np

from ..analytic.inverse_kinematics import angular_velocity_map, kinematics
from ..analytic.virtual_work import mass_and_bias, screw_friction_torque
from ..machine.drive import DIRECT, END_FIXINGS, Drive, Gearbox, LeadScrew, Motor, SizingRules
from ..machine.parameters import Parameters
from ..motion.trajectories import Trajectory
from ..results import Run, peak_and_rms
from ..analysis.runs import analyse

__all__ = [
    "CHECKS",
    "STEEL_DENSITY",
    "STEEL_MODULUS",
    "Candidate",
    "Check",
    "Duty",
    "JointSizing",
    "ModuleSizing",
    "ScrewSide",
    "Sizing",
    "axial_screw_load",
    "buckling_load",
    "critical_speed",
    "drive_checks",
    "motor_duty",
    "motor_thrust",
    "rank_drives",
    "reflected_inertia",
    "screw_life",
    "screw_side",
    "sizing",
    "winding_rise",
]

_RPM = 60.0 / (2.0 * math.pi)  # rpm per rad/s

#: Young's modulus [Pa] and density [kg/m³] of screw steel, for critical speed and buckling.
STEEL_MODULUS = 2.06e11
STEEL_DENSITY = 7850.0


@dataclass(frozen=True)
class _CheckKind:
    label: str
    unit: str
    bound: str  # "max": value ≤ limit; "min": value ≥ limit
    basis: str


#: Every check: its label, unit, bound and the rule or standard it follows.
CHECKS = {
    "peak_curve": _CheckKind("torque under the peak curve (worst point)", "N·mm", "max", "every sample's (|n|, |τ_m|) against the peak torque–speed curve"),
    "s1_rms": _CheckKind("RMS torque under the S1 curve at the mean speed", "N·mm", "max", "τ_rms = √(mean τ_m²) against S1(mean |n|), as SIZER/Motioneering do"),
    "max_speed": _CheckKind("peak motor speed", "rpm", "max", "max |n| against the motor's top speed"),
    "inertia_ratio": _CheckKind("load-to-rotor inertia ratio (worst pose)", ":1", "max", "(M_θ,ii/i² + J_g)/J_m, M_θ = the model's M(q) at the screw shafts"),
    "winding_rise": _CheckKind("winding temperature rise (first-order)", "K", "max", "copper loss 3/2·R_pp·(τ_m/k_t)² through R_th with time constant τ_th"),
    "amplifier_peak_current": _CheckKind("peak current", "A", "max", "max |τ_m|/k_t against the amplifier's peak current"),
    "amplifier_rms_current": _CheckKind("RMS current", "A", "max", "τ_rms/k_t against the amplifier's continuous current"),
    "regen_energy": _CheckKind("regenerated energy per cycle", "J", "max", "∫ max(−τ_m·ω_m, 0) dt against the DC link's energy (losses ignored)"),
    "regen_power_mean": _CheckKind("mean regenerative power", "W", "max", "regenerated energy / cycle time against the braking resistor's power"),
    "regen_power_peak": _CheckKind("peak regenerative power", "W", "max", "max(−τ_m·ω_m) against the braking resistor's peak power"),
    "screw_life": _CheckKind("lead screw L10 life", "cycles", "min", "ISO 3408-5: L10 = (C_a/F_m)³·10⁶ rev, F_m the cubic mean over revolutions"),
    "critical_speed": _CheckKind("screw speed against the critical (whirling) speed", "rpm", "max", "n_cr = λ²·d₂/(8π·l²)·√(E/ρ) (Euler–Bernoulli) × safety factor"),
    "buckling": _CheckKind("axial screw load against the buckling load", "N", "max", "F_k = m·π²·E·(π d₂⁴/64)/l² (Euler) × safety factor"),
    "stroke": _CheckKind("carriage stroke", "mm", "max", "max L − min L against the usable stroke"),
    "axial_force": _CheckKind("peak axial screw load", "N", "max", "max |2π(τ − τ_L − τ_sf)/p| against the permissible load"),
}


@dataclass(frozen=True)
class Check:
    """One check of one module.

    Attributes:
        module: i (1, 2, 3).
        name: the key in :data:`CHECKS` (label, unit, bound, basis).
        value: what the cycle gives, in the check's unit; None when it cannot be computed.
        limit: what the part allows (or, for a "min" check, what is required); None when not given.
        margin: the unused fraction of the capacity: 1 − value/limit (or 1 − limit/value for
            a "min" check); negative when it fails; None when not checked.
        passed: True or False; None when not checked (data missing: see ``detail``).
        detail: where the worst point lies, or what is missing.
        trajectory: the trajectory's name.
    """

    module: int
    name: str
    value: float | None
    limit: float | None
    margin: float | None
    passed: bool | None
    detail: str = ""
    trajectory: str = ""

    @property
    def kind(self) -> _CheckKind:
        return CHECKS[self.name]

    def as_dict(self) -> dict[str, Any]:
        return asdict(self) | {"label": self.kind.label, "unit": self.kind.unit, "bound": self.kind.bound, "basis": self.kind.basis}


def _check(module: int, name: str, value, limit, detail: str = "", trajectory: str = "", missing: str = "") -> Check:
    """A :class:`Check`, with its margin and verdict; ``missing`` (what data are absent) makes it unchecked."""
    value = None if value is None else float(value)
    if missing or limit is None or value is None:
        return Check(module, name, value, None if limit is None else float(limit), None, None, f"not checked: {missing}" if missing else detail, trajectory)
    limit = float(limit)
    if CHECKS[name].bound == "max":
        margin = 1.0 - value / limit if limit > 0 else (1.0 if value <= 0 else -math.inf)
        passed = value <= limit
    else:
        margin = 1.0 - limit / value if value > 0 else (1.0 if limit <= 0 else -math.inf)
        passed = value >= limit
    return Check(module, name, value, limit, float(margin), bool(passed), detail, trajectory)


# ---------------------------------------------------------------------------
# The two forces along a screw


def motor_thrust(run: Run) -> np.ndarray:
    """Motor thrust 2π·τ/p in [N], (N, 3): the motor torque as a force along the screw, positive up.

    Includes the torque that accelerates the screw's rotor and overcomes its
    own friction, so it is *not* the load on the screw (that is
    :func:`axial_screw_load`). It is the Pinocchio model's actuator force and
    what the viewer draws as "motor thrust".
    """
    return 2.0 * math.pi * run.torques.total / run.params.lead


def axial_screw_load(run: Run) -> np.ndarray:
    """Axial screw load 2π·(τ − τ_L − τ_sf)/p in [N], (N, 3): the force the nut pushes on its carriage, positive up.

    τ_L is the screw rotor's inertia torque and τ_sf the screw's own friction
    torque (Coulomb with the smooth sign on the motor speed, plus viscous, as
    in :func:`hipsim.analytic.inverse_dynamics`): what is left of the motor
    torque goes through the nut into both sliders of the module. It loads the
    screw, the nut and the bearings (life, buckling, permissible load).
    """
    params, torques = run.params, run.torques
    screw_friction = screw_friction_torque(params, torques.motor_speed)
    return 2.0 * math.pi * (torques.total - torques.screws - screw_friction) / params.lead


# ---------------------------------------------------------------------------
# The machine seen from the screw shafts


def reflected_inertia(params: Parameters, trajectory: Trajectory) -> np.ndarray:
    """M_θ(q): the machine's inertia at the three screw shafts along a trajectory, in [kg·m²], (N, 3, 3).

    From the reduced model τ = M(q)·q̈ + h (:func:`hipsim.analytic.mass_and_bias`,
    levers with the universal joints' spin, as in the Pinocchio model) and the
    screw speeds θ̇ = G·q̇, G = (2π/p)·J·T(q)·S (S the angle signs):
    M_θ = M·G⁻¹, so that the kinetic energy is ½·θ̇ᵀ·M_θ·θ̇. It holds the
    platforms, levers, sliders and screw rotors. M_θ,ii is the inertia motor i
    drives with the other two held.
    """
    M, _ = mass_and_bias(params, trajectory, lever_spin=True)
    kin = kinematics(params, trajectory)
    signs = params.angle_signs
    G = (2.0 * math.pi / params.lead) * (kin.J @ angular_velocity_map(trajectory.q * signs)) * signs
    # M·G⁻¹ = (G⁻ᵀ·Mᵀ)ᵀ
    return np.swapaxes(np.linalg.solve(np.swapaxes(G, 1, 2), np.swapaxes(M, 1, 2)), 1, 2)


def _time_weights(t: np.ndarray, periodic: bool) -> np.ndarray:
    """Each sample's share of the time in [s]: the step after it when periodic, else the trapezoid rule."""
    if t.size < 2:
        return np.ones_like(t)
    steps = np.diff(t)
    if periodic:
        return np.append(steps, steps[0])
    return 0.5 * (np.append(steps, 0.0) + np.insert(steps, 0, 0.0))


def _mean(values: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """Weighted mean over the sample axis; weights (N,) or like values."""
    weights = weights if weights.ndim == values.ndim else weights[:, None]
    return np.sum(values * weights, axis=0) / np.sum(weights, axis=0)


@dataclass(frozen=True, eq=False)
class ScrewSide:
    """What one run asks at the three screw shafts, before any motor or gearbox is chosen.

    Attributes:
        run: the run.
        cycles: test cycles the trajectory holds (life in cycles, energy per cycle).
        weights: each sample's time share in [s], (N,), zero for flagged samples.
        speed: screw speed θ̇ in [rad/s], (N, 3).
        acceleration: θ̈ in [rad/s²], (N, 3).
        torque: screw shaft torque τ in [N·m], (N, 3) (the run's motor torque).
        axial_load: :func:`axial_screw_load` in [N], (N, 3).
        load_inertia: M_θ,ii, the inertia each screw shaft drives, in [kg·m²], (N, 3).
    """

    run: Run
    cycles: float
    weights: np.ndarray
    speed: np.ndarray
    acceleration: np.ndarray
    torque: np.ndarray
    axial_load: np.ndarray
    load_inertia: np.ndarray

    @property
    def duration(self) -> float:
        return float(self.weights.sum())


def screw_side(run: Run, cycles: float = 1.0, load_inertia: bool = True) -> ScrewSide:
    """The screw-shaft demands of a run (flagged samples get no weight).

    Args:
        run: a model run.
        cycles: how many test cycles the trajectory holds (1: it is one cycle).
        load_inertia: False to leave ``load_inertia`` NaN: the reduced model's M(q) costs
            several model runs, and only the inertia-ratio check (a motor with a
            rotor inertia) needs it.
    """
    if not (cycles > 0 and math.isfinite(cycles)):
        raise ValueError(f"cycles must be positive, got {cycles}")
    ok = ~run.flagged
    weights = np.where(ok, _time_weights(run.trajectory.t, run.trajectory.periodic), 0.0)
    inertia = np.full((len(run.t), 3), np.nan)
    if load_inertia and np.any(ok):
        diagonal = np.diagonal(reflected_inertia(run.params, run.trajectory.slice(ok)), axis1=1, axis2=2)
        inertia[ok] = diagonal
    scale = 2.0 * math.pi / run.params.lead
    zero = lambda x: np.where(ok[:, None], x, 0.0)  # noqa: E731 - flagged samples carry NaN
    return ScrewSide(
        run, float(cycles), weights, zero(run.torques.motor_speed), zero(scale * run.Ldd[:, 0]), zero(run.torques.total),
        zero(axial_screw_load(run)), inertia,
    )


@dataclass(frozen=True, eq=False)
class Duty:
    """A motor's duty along the run, through a gearbox.

    Attributes:
        side: the screw-shaft demands.
        drive: the drive train (None: direct, rotor inertia not counted).
        speed: motor speed ω_m = i·θ̇ in [rad/s], (N, 3).
        torque: motor torque τ_m in [N·m], (N, 3): the screw torque through the gearbox
            (÷ i·η when driving, × η/i when driven back) plus (J_m + J_g)·i·θ̈.
        power: τ_m·ω_m in [W], (N, 3); negative when regenerating.
    """

    side: ScrewSide
    drive: Drive | None
    speed: np.ndarray
    torque: np.ndarray
    power: np.ndarray


def motor_duty(side: ScrewSide, drive: Drive | None) -> Duty:
    """The motor's speed, torque and power along the run for a drive (None: direct, no rotor inertia)."""
    gearbox = drive.gearbox if drive is not None and drive.gearbox is not None else DIRECT
    rotor = drive.motor.rotor_inertia if drive is not None and drive.motor.rotor_inertia is not None else 0.0
    i, eta = gearbox.ratio, gearbox.efficiency
    driving = side.torque * side.speed >= 0.0
    through = np.where(driving, side.torque / (i * eta), side.torque * eta / i)
    speed = i * side.speed
    torque = through + (rotor + gearbox.inertia) * i * side.acceleration
    return Duty(side, drive, speed, torque, torque * speed)


# ---------------------------------------------------------------------------
# Formulas with closed forms (tested against hand calculations)


def winding_rise(heating: np.ndarray, weights: np.ndarray, time_constant: float | None) -> tuple[np.ndarray, np.ndarray]:
    """Mean and peak winding temperature rise of a first-order thermal model under a repeated cycle.

    dΔT/dt = (H(t) − ΔT)/τ_th with H = R_th·P_cu(t) the rise each instant's loss
    would settle at. Its cycle-periodic solution is found exactly for H held
    over each sample's time share.

    Args:
        heating: H in [K], (N, k).
        weights: each sample's time share in [s], (N,).
        time_constant: τ_th in [s]; None for the mean only (peak = mean).

    Returns:
        (mean, peak) rise in [K], each (k,).
    """
    mean = _mean(heating, weights)
    if time_constant is None:
        return mean, mean
    decay = np.exp(-weights / time_constant)[:, None]
    # Once through from ΔT = 0 gives ΔT_end = A·0 + B; the periodic start solves x = A·x + B.
    x = np.zeros(heating.shape[1])
    for k in range(heating.shape[0]):
        x = decay[k] * x + (1.0 - decay[k]) * heating[k]
    total_decay = float(np.prod(decay))
    start = x / (1.0 - total_decay) if total_decay < 1.0 else mean
    peak, x = start.copy(), start.copy()
    for k in range(heating.shape[0]):
        x = decay[k] * x + (1.0 - decay[k]) * heating[k]
        peak = np.maximum(peak, x)
    return mean, peak


def screw_life(axial_load: np.ndarray, speed: np.ndarray, weights: np.ndarray, rating: float, preload: float = 0.0) -> tuple[float, float]:
    """L10 life of a ball screw in revolutions, and its equivalent load, per ISO 3408-5.

    Each nut half (or, without preload, each flank direction) carries
    F₁ = F_pr·(1 + F/(2^{3/2}·F_pr))^{3/2}, F₂ = F₁ − F for |F| ≤ 2^{3/2}·F_pr
    (beyond it one half carries everything). Each half's cubic mean over the
    revolutions F_m,k = (Σ F_k³·|n|·Δt / Σ |n|·Δt)^{1/3} gives
    L_k = (C_a/F_m,k)³·10⁶ revolutions, and the nut L = (L₁^{-10/9} + L₂^{-10/9})^{-9/10}.

    Args:
        axial_load: F in [N], (N,), signed.
        speed: screw speed in [rad/s], (N,).
        weights: time shares in [s], (N,).
        rating: dynamic load rating C_a in [N].
        preload: F_pr in [N].

    Returns:
        (L10 in revolutions, equivalent load F_m in [N]: the constant load giving the same life).
    """
    revolutions = np.abs(speed) * weights / (2.0 * math.pi)
    if revolutions.sum() <= 0:
        return math.inf, 0.0
    limit = 2.0**1.5 * preload
    if preload > 0:
        inside = np.abs(axial_load) <= limit
        ratio = np.clip(axial_load / limit, -1.0, 1.0)
        first = np.where(inside, preload * (1.0 + ratio) ** 1.5, np.maximum(axial_load, 0.0))
    else:
        first = np.maximum(axial_load, 0.0)
    second = first - axial_load
    inverse = 0.0
    for half in (first, second):
        cubic_mean = (np.sum(half**3 * revolutions) / revolutions.sum()) ** (1.0 / 3.0)
        if cubic_mean > 0:
            inverse += ((rating / cubic_mean) ** 3 * 1e6) ** (-10.0 / 9.0)
    if inverse == 0.0:
        return math.inf, 0.0
    life = inverse ** (-9.0 / 10.0)
    return float(life), float(rating / (life / 1e6) ** (1.0 / 3.0))


def critical_speed(screw: LeadScrew) -> float:
    """The first bending (whirling) speed of the screw in [rad/s]: n = λ²/l² · √(E·I/(ρ·A)), √(I/A) = d₂/4."""
    lam = END_FIXINGS[screw.end_fixing][0]
    return lam**2 / screw.free_length**2 * screw.root_diameter / 4.0 * math.sqrt(STEEL_MODULUS / STEEL_DENSITY)


def buckling_load(screw: LeadScrew) -> float:
    """Euler buckling load of the screw in [N]: m·π²·E·I/l², I = π·d₂⁴/64, m from the end fixing."""
    m = END_FIXINGS[screw.end_fixing][1]
    return m * math.pi**2 * STEEL_MODULUS * math.pi * screw.root_diameter**4 / 64.0 / screw.free_length**2


# ---------------------------------------------------------------------------
# The checks


def _worst(values: np.ndarray, weights: np.ndarray) -> int:
    """Index of the largest value among the samples that count."""
    return int(np.argmax(np.where(weights > 0, values, -np.inf)))


def drive_checks(side: ScrewSide, drive: Drive, rules: SizingRules | None = None) -> list[Check]:
    """Every check of :data:`CHECKS` for the three modules driven by ``drive`` along one run."""
    rules = rules if rules is not None else drive.rules
    duty = motor_duty(side, drive)
    motor, amplifier, screw = drive.motor, drive.amplifier, drive.screw
    gearbox = drive.gearbox if drive.gearbox is not None else DIRECT
    w = side.weights
    t = side.run.t
    name = side.run.trajectory.name
    speed, torque = np.abs(duty.speed), np.abs(duty.torque)
    tau_rms = np.sqrt(_mean(duty.torque**2, w))
    mean_speed = _mean(speed, w)
    regen = np.maximum(-duty.power, 0.0)
    regen_energy = np.sum(regen * w[:, None], axis=0) / side.cycles
    regen_mean = np.sum(regen * w[:, None], axis=0) / side.duration
    checks: list[Check] = []
    for i in range(3):
        module = i + 1

        def add(key, value, limit, detail="", missing=""):
            checks.append(_check(module, key, value, limit, detail, name, missing))

        # Motor: peak curve, S1, speed.
        if motor.peak is not None:
            available = motor.peak.at(speed[:, i])
            with np.errstate(divide="ignore", invalid="ignore"):
                load = np.where(available > 0, torque[:, i] / available, np.where(torque[:, i] > 0, np.inf, 0.0))
            k = _worst(load, w)
            beyond = " (beyond the curve's top speed)" if available[k] == 0 else ""
            add("peak_curve", torque[k, i] * 1e3, available[k] * 1e3, f"at {speed[k, i] * _RPM:.0f} rpm{beyond}, t = {t[k]:.3f} s")
        else:
            add("peak_curve", torque[:, i].max() * 1e3, None, missing="no peak torque curve")
        if motor.continuous is not None:
            add("s1_rms", tau_rms[i] * 1e3, motor.continuous.at(mean_speed[i]) * 1e3, f"mean speed {mean_speed[i] * _RPM:.0f} rpm")
        else:
            add("s1_rms", tau_rms[i] * 1e3, None, missing="no S1 curve")
        top = motor.top_speed
        add("max_speed", speed[:, i].max() * _RPM, None if top is None else top * _RPM, missing="" if top is not None else "no top speed")

        # Load-to-rotor inertia ratio, the load from M(q) along the cycle.
        load_inertia = side.load_inertia[:, i] / gearbox.ratio**2 + gearbox.inertia
        if motor.rotor_inertia is not None:
            k = _worst(np.nan_to_num(load_inertia, nan=-np.inf), w)
            add("inertia_ratio", load_inertia[k] / motor.rotor_inertia, rules.inertia_ratio_max,
                f"load {load_inertia[k] * 1e4:.3g} kg·cm² at t = {t[k]:.3f} s, rotor {motor.rotor_inertia * 1e4:.3g} kg·cm²")
        else:
            add("inertia_ratio", None, rules.inertia_ratio_max, missing="no rotor inertia")

        # Winding temperature: R_th·P_cu with P_cu = 3/2·R_pp·(τ/k_t)², or scaled from the S1 stall torque.
        heating_per_torque2 = None
        if motor.thermal_resistance is not None and motor.torque_constant is not None and motor.winding_resistance is not None:
            heating_per_torque2 = motor.thermal_resistance * 1.5 * motor.winding_resistance / motor.torque_constant**2
            basis = "R_th given"
        elif motor.continuous is not None and motor.continuous.at(0.0) > 0:
            heating_per_torque2 = rules.rated_winding_rise / float(motor.continuous.at(0.0)) ** 2
            basis = f"R_th from the S1 stall torque at {rules.rated_winding_rise:g} K"
        if heating_per_torque2 is None:
            add("winding_rise", None, rules.winding_rise_max, missing="needs thermal_resistance_K_W, torque_constant_Nm_A and winding_resistance_ohm, or an S1 curve")
        else:
            mean_rise, peak_rise = winding_rise(heating_per_torque2 * duty.torque[:, i : i + 1] ** 2, w, motor.thermal_time_constant)
            how = "peak of the periodic cycle" if motor.thermal_time_constant is not None else "mean (no thermal time constant given)"
            add("winding_rise", peak_rise[0], rules.winding_rise_max, f"{how}; mean {mean_rise[0]:.3g} K; {basis}")

        # Amplifier: currents and regeneration.
        kt = motor.torque_constant
        for key, value, limit_name in (
            ("amplifier_peak_current", None if kt is None else torque[:, i].max() / kt, "peak_current"),
            ("amplifier_rms_current", None if kt is None else tau_rms[i] / kt, "continuous_current"),
        ):
            limit = None if amplifier is None else getattr(amplifier, limit_name)
            missing = "no torque constant" if kt is None else ("" if limit is not None else f"no amplifier {limit_name.replace('_', ' ')}")
            add(key, value, limit, missing=missing)
        for key, value, limit_name in (
            ("regen_energy", regen_energy[i], "dc_bus_energy"),
            ("regen_power_mean", regen_mean[i], "braking_power"),
            ("regen_power_peak", regen[:, i].max(), "braking_peak_power"),
        ):
            limit = None if amplifier is None else getattr(amplifier, limit_name)
            add(key, value, limit, missing="" if limit is not None else f"no {limit_name.replace('_', ' ')} given")

        # Lead screw.
        load = side.axial_load[:, i]
        if screw is not None and screw.dynamic_load_rating is not None:
            life, equivalent = screw_life(load, side.speed[:, i], w, screw.dynamic_load_rating, screw.preload)
            revolutions = np.sum(np.abs(side.speed[:, i]) * w) / (2.0 * math.pi) / side.cycles
            cycles = life / revolutions if revolutions > 0 else math.inf
            add("screw_life", cycles, rules.life_target_cycles,
                f"{life:.3g} rev at {revolutions:.3g} rev/cycle; equivalent load {equivalent:.0f} N (preload {screw.preload:g} N)")
        else:
            add("screw_life", None, rules.life_target_cycles, missing="no dynamic load rating C_a")
        geometry = screw is not None and None not in (screw.root_diameter, screw.free_length, screw.end_fixing)
        missing = "" if geometry else "needs root_diameter_mm, free_length_mm and end_fixing"
        add("critical_speed", np.abs(side.speed[:, i]).max() * _RPM,
            rules.critical_speed_factor * critical_speed(screw) * _RPM if geometry else None,
            f"{rules.critical_speed_factor:g} × critical speed" if geometry else "", missing)
        add("buckling", np.abs(load).max(), rules.buckling_factor * buckling_load(screw) if geometry else None,
            f"{rules.buckling_factor:g} × Euler load" if geometry else "", missing)
        ok = w > 0
        stroke = np.ptp(side.run.L[ok, 0, i]) * 1e3
        limit = None if screw is None or screw.stroke is None else screw.stroke * 1e3
        add("stroke", stroke, limit, missing="" if limit is not None else "no usable stroke given")
        limit = None if screw is None or screw.axial_force is None else screw.axial_force
        add("axial_force", np.abs(load).max(), limit, missing="" if limit is not None else "no permissible axial load given")
    return checks


# ---------------------------------------------------------------------------
# The sizing table of one run


@dataclass(frozen=True)
class ModuleSizing:
    """What linear module i asks at its screw shaft along the trajectory (the motor's torque for a direct drive, rotor not counted).

    Attributes:
        module: i (1, 2, 3).
        tau_peak_Nmm: max |τ_i| in [N·mm].
        tau_rms_Nmm: RMS of τ_i over time in [N·mm].
        speed_peak_rpm: max |θ̇_i| in [rpm].
        speed_mean_rpm: mean |θ̇_i| over time in [rpm].
        power_peak_W: max |τ_i·θ̇_i| in [W].
        motor_thrust_peak_N: max |2π·τ_i/p| in [N] (:func:`motor_thrust`).
        axial_force_peak_N: max |F_axial,i| in [N] (:func:`axial_screw_load`).
        axial_force_cubic_mean_N: cubic mean of |F_axial,i| over the screw's revolutions in [N].
        revolutions_per_cycle: screw revolutions per test cycle.
        load_inertia_max_kgmm2: largest M_θ,ii (the inertia the screw shaft drives) in [kg·mm²].
        regen_energy_J: regenerated energy per cycle at the screw shaft in [J].
        stroke_mm: carriage stroke max L − min L in [mm].
    """

    module: int
    tau_peak_Nmm: float
    tau_rms_Nmm: float
    speed_peak_rpm: float
    speed_mean_rpm: float
    power_peak_W: float
    motor_thrust_peak_N: float
    axial_force_peak_N: float
    axial_force_cubic_mean_N: float
    revolutions_per_cycle: float
    load_inertia_max_kgmm2: float
    regen_energy_J: float
    stroke_mm: float


@dataclass(frozen=True)
class JointSizing:
    """Peak and RMS reaction force magnitude at one joint, in [N]; name ``a_ji`` or ``o_j``."""

    joint: str
    peak_N: float
    rms_N: float


@dataclass(frozen=True, eq=False)
class Sizing:
    """The sizing of one run: the demands per module and joint, and the drive's checks.

    Attributes:
        modules: one :class:`ModuleSizing` per linear module.
        joints: one :class:`JointSizing` per joint, or None when the model gives no joint forces.
        checks: the :class:`Check` list (empty without a drive).
        drive: the drive checked, if any.
        rules: the rules checked against.
        duty: the motor's duty (for the figures); direct and rotor-less without a drive.
    """

    modules: tuple[ModuleSizing, ...]
    joints: tuple[JointSizing, ...] | None
    checks: tuple[Check, ...]
    drive: Drive | None
    rules: SizingRules
    duty: Duty

    @property
    def passed(self) -> bool | None:
        """True if every check made passed, False if any failed, None if none was made."""
        made = [c.passed for c in self.checks if c.passed is not None]
        return None if not made else all(made)

    @property
    def binding(self) -> Check | None:
        """The check with the smallest margin (the binding constraint), or None."""
        return _binding(self.checks)

    def as_dict(self) -> dict[str, Any]:
        """Plain data for JSON."""
        binding = self.binding
        return {
            "modules": [asdict(m) for m in self.modules],
            "joints": None if self.joints is None else [asdict(j) for j in self.joints],
            "drive": None if self.drive is None else _drive_dict(self.drive),
            "rules": asdict(self.rules),
            "checks": [c.as_dict() for c in self.checks],
            "binding": None if binding is None else binding.as_dict(),
            "passed": self.passed,
        }


def _binding(checks: Iterable[Check]) -> Check | None:
    made = [c for c in checks if c.margin is not None]
    return min(made, key=lambda c: c.margin) if made else None


def _drive_dict(drive: Drive) -> dict[str, Any]:
    def plain(x):
        if x is None:
            return None
        out = {}
        for key, value in vars(x).items():
            out[key] = {"speed_rad_s": value.speed.tolist(), "torque_Nm": value.torque.tolist()} if hasattr(value, "speed") else value
        return out

    return {"name": drive.name, "source": drive.source, "motor": plain(drive.motor), "amplifier": plain(drive.amplifier),
            "gearbox": plain(drive.gearbox), "screw": plain(drive.screw)}


def sizing(run: Run, drive: Drive | None = None, rules: SizingRules | None = None, cycles: float = 1.0) -> Sizing:
    """The sizing table of a run, and the checks of a drive along it.

    Args:
        run: a model run (:func:`hipsim.analyse`); joint forces are
            included when it has them (Pinocchio model). Its lead and screw
            inertia are the drive's (to size another screw, run the model with
            ``params.replace(lead=…, screw_inertia=…)``: :func:`rank_drives` does).
        drive: the drive train to check; None for the demands only.
        rules: the rules; None for the drive's (or the defaults).
        cycles: test cycles the trajectory holds.

    Returns:
        The :class:`Sizing`. Values are over the samples the run kept (flagged
        poses, if any, are left out, as in :meth:`hipsim.Run.summary`).
    """
    rules = rules if rules is not None else (drive.rules if drive is not None else SizingRules())
    side = screw_side(run, cycles)
    ok = side.weights > 0
    w = side.weights
    tau_peak, _ = peak_and_rms(side.torque[ok] * 1e3)
    tau_rms = np.sqrt(_mean((side.torque * 1e3) ** 2, w))
    speed_peak, _ = peak_and_rms(side.speed[ok] * _RPM)
    speed_mean = _mean(np.abs(side.speed) * _RPM, w)
    power = side.torque * side.speed
    power_peak, _ = peak_and_rms(power[ok])
    regen = np.sum(np.maximum(-power, 0.0) * w[:, None], axis=0) / cycles
    thrust_peak, _ = peak_and_rms(motor_thrust(run)[ok])
    force_peak, _ = peak_and_rms(side.axial_load[ok])
    revolutions = np.abs(side.speed) * w[:, None] / (2.0 * math.pi)
    with np.errstate(invalid="ignore", divide="ignore"):
        cubic = (np.sum(np.abs(side.axial_load) ** 3 * revolutions, axis=0) / revolutions.sum(axis=0)) ** (1 / 3)
    stroke = np.ptp(run.L[ok, 0], axis=0) * 1e3
    inertia_max = np.nanmax(side.load_inertia[ok], axis=0) * 1e6
    modules = tuple(
        ModuleSizing(
            module=i + 1,
            tau_peak_Nmm=float(tau_peak[i]),
            tau_rms_Nmm=float(tau_rms[i]),
            speed_peak_rpm=float(speed_peak[i]),
            speed_mean_rpm=float(speed_mean[i]),
            power_peak_W=float(power_peak[i]),
            motor_thrust_peak_N=float(thrust_peak[i]),
            axial_force_peak_N=float(force_peak[i]),
            axial_force_cubic_mean_N=float(np.nan_to_num(cubic[i])),
            revolutions_per_cycle=float(revolutions[:, i].sum() / cycles),
            load_inertia_max_kgmm2=float(inertia_max[i]),
            regen_energy_J=float(regen[i]),
            stroke_mm=float(stroke[i]),
        )
        for i in range(3)
    )
    joints = None
    if run.joint_forces is not None:
        Fa_peak, Fa_rms = peak_and_rms(run.joint_forces.Fa[ok])
        Fo_peak, Fo_rms = peak_and_rms(run.joint_forces.Fo[ok])
        joints = tuple(
            JointSizing(f"a_{j + 1}{i + 1}", float(Fa_peak[j, i]), float(Fa_rms[j, i])) for j in range(2) for i in range(3)
        ) + tuple(JointSizing(f"o_{j + 1}", float(Fo_peak[j]), float(Fo_rms[j])) for j in range(2))
    checks = tuple(drive_checks(side, drive, rules)) if drive is not None else ()
    return Sizing(modules, joints, checks, drive, rules, motor_duty(side, drive))


# ---------------------------------------------------------------------------
# Choosing from catalogues


@dataclass(frozen=True, eq=False)
class Candidate:
    """One motor × gearbox × screw combination checked along every cycle.

    Attributes:
        drive: the combination.
        checks: every check, of every module along every trajectory.
    """

    drive: Drive
    checks: tuple[Check, ...]

    @property
    def margin(self) -> float | None:
        """The smallest margin of any check made; None if none was made."""
        binding = self.binding
        return None if binding is None else binding.margin

    @property
    def binding(self) -> Check | None:
        """The check with the smallest margin: the binding constraint."""
        return _binding(self.checks)

    @property
    def passed(self) -> bool | None:
        made = [c.passed for c in self.checks if c.passed is not None]
        return None if not made else all(made)

    @property
    def unchecked(self) -> tuple[str, ...]:
        """The checks not made for want of data, each named once."""
        return tuple(dict.fromkeys(c.name for c in self.checks if c.passed is None))

    def as_dict(self) -> dict[str, Any]:
        binding = self.binding
        return {
            "drive": self.drive.name,
            "motor": self.drive.motor.name,
            "gearbox": None if self.drive.gearbox is None else self.drive.gearbox.name,
            "screw": None if self.drive.screw is None else self.drive.screw.name,
            "passed": self.passed,
            "margin": self.margin,
            "binding": None if binding is None else binding.as_dict(),
            "unchecked": list(self.unchecked),
            "checks": [c.as_dict() for c in self.checks],
        }


def rank_drives(
    params: Parameters,
    trajectories: Sequence[tuple[Trajectory, float]],
    motors: Sequence[tuple[Motor, Any]],
    screws: Sequence[LeadScrew] | None = None,
    gearboxes: Sequence[Gearbox] | None = None,
    rules: SizingRules | None = None,
    progress: Callable[[str], None] | None = None,
) -> list[Candidate]:
    """Every motor × gearbox × screw combination checked along every trajectory, best first.

    For each screw the model runs again with its lead and inertia
    (``params.replace(lead=…, screw_inertia=…)``): the lead changes the motor
    speeds, torques and the reflected inertia, so nothing is rescaled.

    Args:
        params: the machine.
        trajectories: (trajectory, test cycles it holds) pairs, e.g. the ISO cycle and measured gaits.
        motors: (motor, amplifier or None) pairs (:func:`hipsim.machine.drive.load_motor_catalogue`).
        screws: lead screws; None for the machine's own screw (no screw checks).
        gearboxes: gearboxes; None for a direct coupling.
        rules: the rules (default :class:`SizingRules`).
        progress: called with a line of text before each model run.

    Returns:
        The candidates sorted by their smallest margin, largest first (every
        candidate that passes comes before every one that fails), ties broken
        by the next-smallest margin; candidates with no check made come last.
    """
    rules = rules if rules is not None else SizingRules()
    candidates = []
    for screw in screws if screws is not None else [None]:
        machine = params
        if screw is not None:
            changes = {"lead": screw.lead, "screw_inertia": screw.inertia}
            machine = params.replace(**{k: v for k, v in changes.items() if v is not None})
        sides = []
        for trajectory, cycles in trajectories:
            if progress is not None:
                progress(f"{trajectory.name}, lead {machine.lead * 1e3:g} mm" + (f" ({screw.name})" if screw is not None else ""))
            sides.append(screw_side(analyse(machine, trajectory), cycles))
        for motor, amplifier in motors:
            for gearbox in gearboxes if gearboxes is not None else [None]:
                drive = Drive(motor, amplifier, gearbox, screw, rules, source="catalogue")
                checks = tuple(c for side in sides for c in drive_checks(side, drive, rules))
                candidates.append(Candidate(drive, checks))
    def order(candidate: Candidate):
        # Largest smallest margin first; ties broken by the next-smallest margins, and so on.
        margins = sorted(c.margin for c in candidate.checks if c.margin is not None)
        return (not margins, [-m for m in margins])

    return sorted(candidates, key=order)
