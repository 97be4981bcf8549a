"""The per-chain values as one vector: what calibration estimates and tolerance analysis draws.

A machine's :class:`~hipsim.machine.chains.ChainGeometry` holds each chain's
deviation from the drawing: per platform j and module i the U-joint centre's
horizontal offset from its screw axis (x, y), the slider's height offset on its
carriage, the platform joint's offset in platform axes (x, y, z) and the lever
length's; per platform the rotation centre's offset (x, y, z). Here they are
one vector δ of :data:`COUNT` = 51 values in [m], in the order of
:meth:`ChainGeometry.as_vector` (names :func:`names`: ``ujoint_x_11`` …
``centre_z_2``, then the intermediate chain's seat ``spline_x_1`` … ``spline_z_1``, which moves platform 1). δ = 0 is the drawing; a manufacturing tolerance bounds δ and
a calibration's prior is centred on the starting file's δ.

Every value moves one platform's slider equations only, and a chain's values
only its own leg (:func:`platform_columns`).
"""

from __future__ import annotations

from functools import cache

import numpy as np

from ..exceptions import ArgumentError
from ..machine.chains import ChainGeometry
from ..machine.parameters import Parameters

__all__ = [
    "COUNT",
    "FAMILIES",
    "deviation",
    "family",
    "machine",
    "names",
    "platform_columns",
    "platform_of",
]

#: The families a tolerance names (``--bands ujoint=0.1,...``), as the fields of :class:`ChainGeometry`.
FAMILIES = ("ujoint", "slider", "joint", "lever", "centre", "spline")


@cache
def names() -> tuple[str, ...]:
    """The name of each entry of δ (:meth:`ChainGeometry.names`): ``ujoint_x_11`` … ``lever_23``, ``centre_x_1`` … ``centre_z_2``."""
    return ChainGeometry.names()


COUNT = len(names())


def family(name: str) -> str:
    """The tolerance family of an entry of δ by name (``joint_z_21`` → ``joint``)."""
    head = name.split("_", 1)[0]
    if head not in FAMILIES or name not in names():
        raise ArgumentError("name", name, "an entry of the per-chain vector (see names())")
    return head


def platform_of(name: str) -> int:
    """The platform (1 or 2) an entry of δ moves."""
    return int(name.rsplit("_", 1)[1][0])


@cache
def platform_columns(j: int) -> np.ndarray:
    """The entries of δ that move platform j (1 or 2): its chains' and its centre's, in δ's order."""
    return np.array([k for k, name in enumerate(names()) if platform_of(name) == j])


def deviation(params: Parameters) -> np.ndarray:
    """δ in [m], (COUNT,), of a machine (zero for the drawing)."""
    return np.zeros(COUNT) if params.geometry is None else params.geometry.as_vector()


def machine(params: Parameters, delta: np.ndarray) -> Parameters:
    """The machine ``params`` with its chains' deviations set to δ in [m] (COUNT,).

    Always a per-chain machine (even for δ = 0), so that every value is differentiated along one code path; the
    file's controlled platform (``[geometry] control``) is kept.
    """
    delta = np.asarray(delta, dtype=float)
    if delta.shape != (COUNT,):
        raise ArgumentError("delta", delta, f"shape ({COUNT},)")
    geometry = ChainGeometry.from_vector(delta)
    if params.geometry is not None:
        geometry = geometry.replace(control=params.geometry.control)
    return params.replace(geometry=geometry)
