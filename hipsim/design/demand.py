"""What a run asks at the three screw shafts, and of a motor driving them through a gearbox: the demand along the run.

Two forces along each screw, defined here once and named apart:

- :func:`motor_thrust`: 2π·τ/p, the motor torque written as a force along the
  screw (what the viewer's magenta arrows draw). It includes the torque that
  spins the screw's own rotor and overcomes its friction.
- :func:`axial_screw_load`: 2π·(τ − τ_L − τ_sf)/p, the force between nut and
  carriage, which is what loads the screw, its nut and its bearings (life,
  buckling, permissible load).

:func:`screw_side` gathers a run's speeds, torques, loads and reflected
inertia per sample with each sample's time share; :func:`motor_duty` carries
them through a drive's gearbox to its motor.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..analytic.inverse_kinematics import angular_velocity_map, kinematics
from ..analytic.virtual_work import mass_and_bias, screw_friction_torque
from ..machine.drive_parts import DIRECT, Drive
from ..machine.parameters import Parameters
from ..motion.trajectories import Trajectory
from ..physics.transmission import angle_from_travel, radians_per_travel
from ..results import Run

__all__ = [
    "Duty",
    "ScrewSide",
    "axial_screw_load",
    "motor_duty",
    "motor_thrust",
    "reflected_inertia",
    "screw_side",
]


# ---------------------------------------------------------------------------
# The two forces along a screw


def motor_thrust(run: Run) -> np.ndarray:
    """Motor thrust 2π·τ/p in [N], (N, 3): the motor torque as a force along the screw, positive up.

    Includes the torque that accelerates the screw's rotor and overcomes its
    own friction, so it is *not* the load on the screw (that is
    :func:`axial_screw_load`). It is the Pinocchio model's actuator force and
    what the viewer draws as "motor thrust".
    """
    return angle_from_travel(run.torques.total, run.params.lead)


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
    return angle_from_travel(torques.total - torques.screws - screw_friction, params.lead)


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
    G = radians_per_travel(params.lead) * (kin.J @ angular_velocity_map(trajectory.q * signs)) * signs
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
    scale = radians_per_travel(run.params.lead)
    zero = lambda x: np.where(ok[:, None], x, 0.0)  # noqa: E731 - flagged samples carry NaN
    return ScrewSide(
        run,
        float(cycles),
        weights,
        zero(run.torques.motor_speed),
        zero(scale * run.Ldd[:, 0]),
        zero(run.torques.total),
        zero(axial_screw_load(run)),
        inertia,
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
