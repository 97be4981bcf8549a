"""The prior of an identification: the starting machine's values and how uncertain they are.

Every base parameter is estimated with a prior N(θ_b0, diag(s_b²)) instead of
being dropped when the logs excite it weakly (:mod:`hipsim.rig.identification.fit`).
θ_b0 is the starting machine's base parameters; s_b comes from each standard
parameter's prior standard deviation s:

- by default :data:`DEFAULT_RELATIVE` of its size, max(|value|, a typical value
  where the value is zero): 30 % for masses and inertias, 50 % for friction
  coefficients;
- overridden per parameter by the starting file's optional
  ``[identification.prior]`` table or by ``hipsim identify --prior``, each entry
  a parameter's label, key or key prefix (``"μ_h"``,
  ``"friction.hip_mu"``, ``"lever"``) and either an absolute standard deviation
  in the file's unit (a number ≥ 0; 0 holds the parameter at its value) or a
  relative one (a text such as ``"10 %"``);

and s_b,k = √(s_k² + Σ_j β_kj² s_j²) over the parameters folded into it (each
base parameter's own prior; diagonal, so a parameter the logs cannot see comes
back exactly at its prior).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from ...exceptions import ArgumentError, ParameterError
from ...machine.parameters import Parameters
from .base import BaseParameters
from .identified_file import identification_table
from .quantities import QUANTITIES, standard_values

__all__ = ["DEFAULT_RELATIVE", "HELD", "Prior", "parse_prior_option", "prior", "prior_table", "standard_std"]

#: Default prior standard deviation, relative to each parameter's size, by kind.
DEFAULT_RELATIVE = {"inertial": 0.30, "friction": 0.50}
#: The relative standard deviation a prior of 0 (held at its value) stands for: far below any data's reach.
HELD = 1e-9


def _sizes(theta: np.ndarray) -> np.ndarray:
    return np.array([abs(theta[k]) if theta[k] != 0 else q.nominal for k, q in enumerate(QUANTITIES)])


def _matches(name: str) -> list[int]:
    return [k for k, q in enumerate(QUANTITIES) if name in (q.label, q.key) or q.key.startswith(name)]


def _entry(name: str, value: Any, source: str) -> tuple[list[int], float | None, float | None]:
    """The parameters an entry names and its absolute (file units) or relative standard deviation."""
    matches = _matches(name)
    if not matches:
        known = ", ".join(q.label for q in QUANTITIES)
        raise ParameterError(
            f"prior of '{name}': no such parameter (known: {known}, or a key prefix such as 'lever')", source=source
        )
    if isinstance(value, str):
        text = value.strip()
        if not text.endswith("%"):
            raise ParameterError(
                f"prior of '{name}': expected a number in the parameter's unit or a percentage such as '10 %', got {value!r}",
                source=source,
            )
        try:
            relative = float(text[:-1]) / 100
        except ValueError:
            raise ParameterError(
                f"prior of '{name}': expected a percentage such as '10 %', got {value!r}", source=source
            ) from None
        if not (math.isfinite(relative) and relative >= 0):
            raise ParameterError(
                f"prior of '{name}': the uncertainty must be a non-negative percentage, got {value!r}", source=source
            )
        return matches, None, relative
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) or value < 0:
        raise ParameterError(
            f"prior of '{name}': the uncertainty must be a non-negative number, got {value!r}", source=source
        )
    return matches, float(value), None


def prior_table(path: str | Path | None) -> dict[str, Any]:
    """The ``[identification.prior]`` table of a parameter file (empty without one, or for None).

    An identified file's ``[identification]`` table has a ``prior`` column of its own (the prior means, one per base
    parameter): such a file, the start of a new fit, brings no prior table, and the defaults apply around its values.
    """
    if path is None:
        return {}
    table = identification_table(path)
    entries = table.get("prior", {})
    if isinstance(entries, list) and isinstance(table.get("base"), list):
        return {}
    if not isinstance(entries, dict):
        raise ParameterError(
            "expected a table of parameter = uncertainty", key="identification.prior", source=str(path)
        )
    return entries


def parse_prior_option(text: str) -> dict[str, str | float]:
    """``--prior "μ_h=0.02,lever=10 %"`` → {"μ_h": 0.02, "lever": "10 %"}."""
    out: dict[str, str | float] = {}
    for item in text.split(","):
        if not item.strip():
            continue
        name, sep, value = item.partition("=")
        if not sep or not name.strip() or not value.strip():
            raise ArgumentError("--prior", item.strip(), "NAME=STD or NAME=PERCENT %, comma-separated")
        value = value.strip()
        if value.endswith("%"):
            out[name.strip()] = value
        else:
            try:
                out[name.strip()] = float(value)
            except ValueError:
                raise ArgumentError(f"--prior: {name.strip()}", value, "a number or a percentage") from None
    return out


def standard_std(params: Parameters, entries: Mapping[str, Any] | None = None, source: str = "prior") -> np.ndarray:
    """Each standard parameter's prior standard deviation in SI, (P,) (module docstring)."""
    theta = standard_values(params)
    size = _sizes(theta)
    std = np.array([DEFAULT_RELATIVE["friction" if q.part == "friction" else "inertial"] for q in QUANTITIES]) * size
    for name, value in dict(entries or {}).items():
        matches, absolute, relative = _entry(str(name), value, source)
        for k in matches:
            std[k] = absolute * QUANTITIES[k].scale if absolute is not None else relative * size[k]
    return np.maximum(std, HELD * size)


class Prior:
    """The base parameters' prior: mean θ_b0 and standard deviation s_b, SI.

    Attributes:
        mean: (r,) the starting machine's base parameters.
        std: (r,) their prior standard deviations.
        standard: (P,) the standard parameters' prior standard deviations.
    """

    def __init__(self, base: BaseParameters, params: Parameters, standard: np.ndarray):
        T = base.transform
        self.mean = T @ standard_values(params)
        self.std = np.sqrt((T**2) @ standard**2)
        self.standard = standard


def prior(
    base: BaseParameters, params: Parameters, entries: Mapping[str, Any] | None = None, source: str = "prior"
) -> Prior:
    """The prior of ``base`` from the starting machine and the overrides ``entries`` (module docstring)."""
    return Prior(base, params, standard_std(params, entries, source))
