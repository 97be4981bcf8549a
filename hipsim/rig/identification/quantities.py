"""The identified quantities: the machine's dynamic parameters that the motor torques are linear in.

Each :class:`Quantity` names its parameter-file key (``lever.mass_kg``, or a
component of an inertia, ``platform.inertia_kgmm2[xy]``) and from it finds its
own field of :class:`~hipsim.machine.parameters.Parameters`
(:data:`~hipsim.machine.parameters.ATTRIBUTES`): it reads its value from a
machine and writes it back, so θ, the vector of :data:`QUANTITIES`, goes to and
from a machine without indices kept by hand (:func:`standard_values`,
:func:`with_values`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ...machine.parameters import ATTRIBUTES, Parameters

__all__ = [
    "AXES",
    "BLOCKS",
    "BOUNDED",
    "FRICTION",
    "QUANTITIES",
    "Quantity",
    "friction_unit",
    "standard_values",
    "symmetric",
    "with_values",
]

#: An inertia's six components, by name: their row and column in the matrix.
AXES = {"xx": (0, 0), "yy": (1, 1), "zz": (2, 2), "xy": (0, 1), "xz": (0, 2), "yz": (1, 2)}


def symmetric(values: Sequence[float]) -> np.ndarray:
    """The symmetric 3x3 matrix of (xx, yy, zz, xy, xz, yz)."""
    matrix = np.zeros((3, 3))
    for value, (a, b) in zip(values, AXES.values()):
        matrix[a, b] = matrix[b, a] = value
    return matrix


@dataclass(frozen=True)
class Quantity:
    """One parameter of the regressor.

    Attributes:
        key: the parameter file's key (``lever.mass_kg``), with a component for inertias (``platform.inertia_kgmm2[xy]``).
        label: short name for tables (``m_l``).
        unit: the file's unit.
        scale: SI value of one file unit.
        part: the torque part (spec §4.4) its column lands in.
        nominal: a typical magnitude in SI, for scaling where the starting value is zero.
        nonnegative: True for masses, rotor inertias and friction coefficients.
    """

    key: str
    label: str
    unit: str
    scale: float
    part: str
    nominal: float
    nonnegative: bool = False

    @property
    def attribute(self) -> str:
        """Its field of :class:`~hipsim.machine.parameters.Parameters`, dotted (``lever_mass``, ``friction.hip_mu``)."""
        return ATTRIBUTES[self.key.partition("[")[0]]

    @property
    def name(self) -> str:
        """The name :meth:`Parameters.replace` takes it by (``lever_mass``, ``hip_mu``)."""
        return self.attribute.rpartition(".")[2]

    @property
    def component(self) -> tuple[int, int] | None:
        """Row and column in its inertia matrix, or None for a scalar."""
        axes = self.key.partition("[")[2].rstrip("]")
        return AXES[axes] if axes else None

    def read(self, params: Parameters) -> float:
        """Its value in a machine, SI."""
        value: Any = params  # walks down the dotted attribute: a sub-record, then a number or matrix
        for part in self.attribute.split("."):
            value = getattr(value, part)
        return value[self.component] if self.component is not None else value

    def write(self, changes: dict[str, Any], params: Parameters, value: float) -> None:
        """Put ``value`` (SI) into ``changes`` for :meth:`Parameters.replace` of ``params`` (an inertia's matrix filled in place)."""
        if self.component is None:
            changes[self.name] = float(value)
            return
        if self.name not in changes:
            changes[self.name] = np.array(getattr(params, self.name), dtype=float)
        a, b = self.component
        changes[self.name][a, b] = changes[self.name][b, a] = value


def _inertia(body: str, label: str, part: str, nominal: float) -> list[Quantity]:
    return [
        Quantity(
            f"{body}.inertia_kgmm2[{axes}]",
            f"{label},{axes}",
            "kg·mm²",
            1e-6,
            part,
            nominal,
            nonnegative=axes[0] == axes[1],
        )
        for axes in AXES
    ]


#: The regressor's parameters, in the order base parameters are chosen (the first of a dependent group names it).
QUANTITIES: tuple[Quantity, ...] = (
    *_inertia("platform", "I_m", "platforms", 0.3),
    Quantity("slider.mass_kg", "m_L", "kg", 1.0, "sliders", 3.0, True),
    Quantity("screw.inertia_kgmm2", "I_L", "kg·mm²", 1e-6, "screws", 5e-5, True),
    *_inertia("lever", "I_l", "levers", 0.03),
    Quantity("lever.mass_kg", "m_l", "kg", 1.0, "levers", 1.5, True),
    Quantity("friction.hip_mu", "μ_h", "", 1.0, "friction", 0.1, True),
    Quantity("friction.thrust_mu", "μ_t", "", 1.0, "friction", 0.03, True),
    Quantity("friction.screw_coulomb_Nmm", "τ_c,screw", "N·mm", 1e-3, "friction", 0.05, True),
    Quantity("friction.screw_viscous_Nmm_s_rad", "b_screw", "N·mm·s/rad", 1e-3, "friction", 2e-4, True),
    Quantity("friction.guide_coulomb_N", "F_c,guide", "N", 1.0, "friction", 15.0, True),
    Quantity("friction.guide_viscous_N_s_mm", "b_guide", "N·s/mm", 1e3, "friction", 40.0, True),
    Quantity("friction.ujoint_coulomb_Nmm", "τ_c,U", "N·mm", 1e-3, "friction", 0.05, True),
    Quantity("friction.ujoint_viscous_Nmm_s_rad", "b_U", "N·mm·s/rad", 1e-3, "friction", 0.005, True),
    Quantity("friction.sjoint_coulomb_Nmm", "τ_c,S", "N·mm", 1e-3, "friction", 0.05, True),
    Quantity("friction.sjoint_viscous_Nmm_s_rad", "b_S", "N·mm·s/rad", 1e-3, "friction", 0.005, True),
)

#: The friction coefficients, in the order of QUANTITIES.
FRICTION: tuple[Quantity, ...] = tuple(q for q in QUANTITIES if q.part == "friction")
#: The inertia blocks whose consistency is a semidefinite constraint: indices of xx … yz in QUANTITIES, by body.
BLOCKS: dict[str, list[int]] = {
    body: [k for k, q in enumerate(QUANTITIES) if q.component is not None and q.key.partition(".")[0] == body]
    for body in dict.fromkeys(q.key.partition(".")[0] for q in QUANTITIES if q.component is not None)
}
#: The parameters bounded below by zero (inertias are held by their blocks instead).
BOUNDED: list[int] = [
    k for k, q in enumerate(QUANTITIES) if q.nonnegative and not any(k in block for block in BLOCKS.values())
]


def standard_values(params: Parameters) -> np.ndarray:
    """θ of a machine in SI, in the order of :data:`QUANTITIES`, (P,)."""
    return np.array([q.read(params) for q in QUANTITIES], dtype=float)


def with_values(params: Parameters, theta: np.ndarray, source: str | None = None) -> Parameters:
    """The machine ``params`` with θ (SI, order of :data:`QUANTITIES`) in place of its dynamic parameters."""
    theta = np.asarray(theta, dtype=float)
    changes: dict[str, Any] = {}
    for quantity, value in zip(QUANTITIES, theta, strict=True):
        quantity.write(changes, params, value)
    if source is not None:
        changes["source"] = source
    return params.replace(**changes)


def friction_unit(params: Parameters, name: str) -> Parameters:
    """The machine whose only friction is coefficient ``name`` (a :class:`~hipsim.machine.parameters.Friction` field) set to one.

    Everything else of the friction law — radii, the platform mass in the
    thrust bearing's load, the smooth sign's ε, and any option of the law —
    is kept from ``params``, so the column is the law's own, per unit coefficient.
    For ``hip_mu`` and ``thrust_mu`` the column is the friction moment per unit μ at the machine's radius.
    """
    return params.replace(**{q.name: 1.0 if q.name == name else 0.0 for q in FRICTION})
