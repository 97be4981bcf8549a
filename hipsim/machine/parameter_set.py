"""The machine's parameter set in SI units: :class:`Parameters` and its :class:`Friction` and :class:`ControlSettings`.

Frozen dataclasses; build them with :func:`hipsim.machine.parameters.load_parameters`
(the file, checked and converted), change them with :meth:`Parameters.replace`.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass
from functools import cached_property
from types import MappingProxyType

import numpy as np

from ..arrays import readonly
from ..exceptions import ParameterError
from .chains import ChainGeometry, Chains

__all__ = ["FRICTION_COEFFICIENTS", "ControlSettings", "Friction", "Parameters", "slender_levers"]


@dataclass(frozen=True, eq=False)
class Friction:
    """Friction coefficients, SI. Coulomb terms use the smooth sign ŝ(w) = w/√(w² + ε²).

    Attributes:
        epsilon: ε of the smooth sign in [rad/s] (slider guides use it on the motor speed).
        hip_radius: r_h in [m]; hip_mu: μ_h.
        thrust_radius: r_t in [m]; thrust_mu: μ_t.
        screw_coulomb: [N·m]; screw_viscous: [N·m·s/rad], on the motor shaft.
        guide_coulomb: [N]; guide_viscous: [N·s/m], on each slider.
        ujoint_coulomb: [N·m]; ujoint_viscous: [N·m·s/rad], lever relative to slider.
        sjoint_coulomb: [N·m]; sjoint_viscous: [N·m·s/rad], lever relative to platform.
        thrust_bearing_axial_only: False for the publication's central-chain
            friction (the thrust bearing's moment along ŝ(ω), like the hip
            joint's); True for a bearing that resists only rotation about its
            own axis, the platform's z axis (:func:`hipsim.physics.laws.central_friction_moment`).
    """

    epsilon: float
    hip_radius: float
    hip_mu: float
    thrust_radius: float
    thrust_mu: float
    screw_coulomb: float
    screw_viscous: float
    guide_coulomb: float
    guide_viscous: float
    ujoint_coulomb: float
    ujoint_viscous: float
    sjoint_coulomb: float
    sjoint_viscous: float
    thrust_bearing_axial_only: bool = False


@dataclass(frozen=True, eq=False)
class ControlSettings:
    """Servo loop settings (spec §8), SI.

    Attributes:
        servo_rate: controller rate in [Hz].
        integration_step: plant integration step in [s], at most one servo period.
        kp: K_p per angle α, β, γ in [N·m/rad], shape (3,).
        kd: K_d per angle in [N·m·s/rad], shape (3,).
        torque_limit: motor torque limit in [N·m]; inf for none.
    """

    servo_rate: float
    integration_step: float
    kp: np.ndarray
    kd: np.ndarray
    torque_limit: float

    def __post_init__(self):
        for name in ("kp", "kd"):
            value = readonly(np.asarray(getattr(self, name), dtype=float))
            if value.shape != (3,):
                raise ParameterError(f"expected shape (3,), got {value.shape}", key=f"control.{name}", value=value)
            object.__setattr__(self, name, value)


@dataclass(frozen=True, eq=False)
class Parameters:
    """The machine, in SI units. Build it with :func:`load_parameters`.

    Attributes:
        gravity: g in [m/s²], along -Z.
        screw_radius: E in [m].
        screw_angles: θ_i in [rad], shape (3,).
        joint_radius: e in [m].
        home_offset: δ in [rad].
        heights: h_1, h_2 in [m], shape (2,).
        platform_mass: m_m in [kg] (not published; an estimate by default).
        platform_inertia: I_m about o_j in platform axes in [kg·m²], shape (3, 3).
        lever_length: l in [m].
        lever_mass: m_l in [kg].
        lever_inertia: I_l about its centre in lever axes in [kg·m²], shape (3, 3).
        slider_mass: m_L in [kg].
        lead: p in [m] per motor turn.
        screw_inertia: I_L in [kg·m²].
        friction: the :class:`Friction` coefficients.
        angle_signs: ±1 per angle α, β, γ, shape (3,).
        control: the :class:`ControlSettings` (servo rate, gains, limits).
        motor: the optional motor and module ratings, by key of the file's
            ``[motor]`` table, in its units (N·mm, rpm, mm, N); empty if none.
        source: where the values came from (file and overrides).
        geometry: the per-chain deviations from the drawing (the file's ``[geometry]``
            table, :mod:`hipsim.machine.chains`); None for the drawing.
    """

    gravity: float
    screw_radius: float
    screw_angles: np.ndarray
    joint_radius: float
    home_offset: float
    heights: np.ndarray
    platform_mass: float
    platform_inertia: np.ndarray
    lever_length: float
    lever_mass: float
    lever_inertia: np.ndarray
    slider_mass: float
    lead: float
    screw_inertia: float
    friction: Friction
    angle_signs: np.ndarray
    control: ControlSettings
    motor: Mapping[str, float] = dataclasses.field(default_factory=lambda: MappingProxyType({}))
    source: str = "<built in>"
    # Left out of fingerprints while None, so the drawing's keep theirs (hipsim.fingerprint.plain).
    geometry: ChainGeometry | None = dataclasses.field(default=None, metadata={"omit_when_none": True})

    def __post_init__(self):
        if self.geometry is not None and not isinstance(self.geometry, ChainGeometry):
            raise ParameterError(
                f"expected a ChainGeometry or None, got {type(self.geometry).__name__}", key="geometry"
            )
        for name, shape in (
            ("screw_angles", (3,)),
            ("heights", (2,)),
            ("platform_inertia", (3, 3)),
            ("lever_inertia", (3, 3)),
            ("angle_signs", (3,)),
        ):
            value = readonly(np.asarray(getattr(self, name), dtype=float))
            if value.shape != shape:
                raise ParameterError(f"expected shape {shape}, got {value.shape}", key=name, value=value)
            object.__setattr__(self, name, value)

    @cached_property
    def platform_angles(self) -> np.ndarray:
        """φ_i = θ_i + δ in [rad], shape (3,)."""
        return readonly(self.screw_angles + self.home_offset)

    @cached_property
    def screw_points(self) -> np.ndarray:
        """c_i, the screw feet on the base plane in [m], shape (3, 3) (row i = c_i)."""
        th = self.screw_angles
        return readonly(self.screw_radius * np.stack([np.cos(th), np.sin(th), np.zeros(3)], axis=1))

    @cached_property
    def platform_points(self) -> np.ndarray:
        """r⁰_i, the platform joints in platform axes in [m], shape (3, 3) (row i = r⁰_i)."""
        ph = self.platform_angles
        return readonly(self.joint_radius * np.stack([np.cos(ph), np.sin(ph), np.zeros(3)], axis=1))

    @cached_property
    def ujoint_axes(self) -> np.ndarray:
        """u1_i = ẑ × c_i/|c_i|, the universal joints' first (slider-fixed) axes, shape (3, 3)."""
        th = self.screw_angles
        return readonly(np.stack([-np.sin(th), np.cos(th), np.zeros(3)], axis=1))

    @cached_property
    def chains(self) -> Chains:
        """The six chains and two rotation centres, absolute, with the per-chain deviations (the drawing's without)."""
        return Chains.build(self.screw_points, self.platform_points, self.lever_length, self.heights, self.geometry)

    @property
    def per_chain(self) -> bool:
        """True when the machine has per-chain geometry (a ``[geometry]`` table that is not the drawing)."""
        return self.geometry is not None

    def require_drawing(self, what: str) -> None:
        """Refuse a per-chain machine in one line: ``what`` (e.g. "the reduced plant") uses the drawing's geometry only.

        Raises:
            ParameterError: naming the file's ``[geometry]`` table, when the machine has one.
        """
        if self.geometry is not None:
            raise ParameterError(
                f"per-chain geometry is not supported by {what} yet (it assumes both platforms alike); remove "
                "the [geometry] table to run on the drawing (torques, check, feasible, sweep, params, urdf and "
                "mjcf take it)",
                key="geometry",
                source=self.source,
            )

    def replace(self, **changes) -> Parameters:
        """A copy with some attributes changed, e.g. ``params.replace(lever_mass=0.0)``."""
        if "friction" not in changes:
            friction_changes = {k: changes.pop(k) for k in list(changes) if k in _FRICTION_FIELDS}
            if friction_changes:
                changes["friction"] = dataclasses.replace(self.friction, **friction_changes)
        if "control" not in changes:
            control_changes = {k: changes.pop(k) for k in list(changes) if k in _CONTROL_FIELDS}
            if control_changes:
                changes["control"] = dataclasses.replace(self.control, **control_changes)
        return dataclasses.replace(self, **changes)


_FRICTION_FIELDS = {f.name for f in dataclasses.fields(Friction)}

#: The friction coefficients proper, in the order of :class:`Friction`: what scales when friction is
#: off by a fraction (not the smooth sign's ε, the friction radii or the bearing's switch).
FRICTION_COEFFICIENTS = tuple(
    f.name
    for f in dataclasses.fields(Friction)
    if f.name not in ("epsilon", "hip_radius", "thrust_radius", "thrust_bearing_axial_only")
)
_CONTROL_FIELDS = {f.name for f in dataclasses.fields(ControlSettings)}


def slender_levers(params: Parameters) -> Parameters:
    """The cross-check configuration of spec §7.4: each lever a slender rod.

    I_l becomes diag(I_t, I_t, 0), I_t the mean of the two transverse values, so
    that the lever's spin about its own axis carries no energy.
    """
    inertia = params.lever_inertia
    transverse = 0.5 * (inertia[0, 0] + inertia[1, 1])
    return params.replace(lever_inertia=np.diag([transverse, transverse, 0.0]))
