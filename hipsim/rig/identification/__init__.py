"""Identification of the machine from rig logs: what is identified, the regressor, the fit, its uncertainty, and the excitation.

Modules: :mod:`~hipsim.rig.identification.quantities` (the dynamic
parameters motor torques are linear in), :mod:`~hipsim.rig.identification.regressor`
(τ = Y·θ and its rows along a log), :mod:`~hipsim.rig.identification.base`
(the base parameters), :mod:`~hipsim.rig.identification.prior`,
:mod:`~hipsim.rig.identification.fit` (the fit),
:mod:`~hipsim.rig.identification.consistency` (physical consistency),
:mod:`~hipsim.rig.identification.validation` (held-out logs),
:mod:`~hipsim.rig.identification.uncertainty` (bands forward),
:mod:`~hipsim.rig.identification.summary` (what ``identify`` reports, as records),
:mod:`~hipsim.rig.identification.excitation` (trajectories that make the fit
well posed) and :mod:`~hipsim.rig.identification.excitation_summary` (their
peaks, verdict against the rig's limits and summary). The functions named like a module (``regressor``,
``excitation``) are reached through their modules, or as ``hipsim.rig.regressor``
and ``hipsim.rig.excitation``.
"""

from .base import BaseParameters, base_parameters
from .excitation import Excitation
from .fit import BaseEstimate, Identification, IdentifiedQuantity, identify
from .quantities import QUANTITIES, Quantity, standard_values, with_values
from .regressor import rows_per_independent_row
from .uncertainty import Covariance, read_covariance

__all__ = [
    "QUANTITIES",
    "BaseEstimate",
    "BaseParameters",
    "Covariance",
    "Excitation",
    "Identification",
    "IdentifiedQuantity",
    "Quantity",
    "base_parameters",
    "identify",
    "read_covariance",
    "rows_per_independent_row",
    "standard_values",
    "with_values",
]
