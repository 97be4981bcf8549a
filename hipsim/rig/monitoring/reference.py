"""The reference machine the monitor holds fixed: an identified parameter file, and the lever spin it was fitted with."""

from __future__ import annotations

from pathlib import Path

from ...exceptions import ArgumentError, ParameterError
from ...machine.parameters import Parameters, load_parameters
from ..identification.identified_file import read_identified_file

__all__ = ["identified_file", "reference"]


def identified_file(path: str | Path) -> bool:
    """The lever spin an identified parameter file was fitted with (True: on); refused when the file is not identified.

    Read through :func:`hipsim.rig.identification.identified_file.read_identified_file`: the ``[identification]``
    table's ``lever_spin`` (an old file's ``# Model: … lever spin on|off`` header line when it has no table).

    Raises:
        ParameterError: naming the file when it holds no identified values.
    """
    found = read_identified_file(path)
    if found is None:
        raise ParameterError(
            "holds no identified values (no [identification] table, no '# Identified by hipsim identify' header): "
            "the monitor holds the machine at identified values; run hipsim identify on a log of the rig first",
            source=str(path),
        )
    return found.lever_spin


def reference(path: str | Path | None, params: Parameters | None = None) -> tuple[Parameters, bool]:
    """The reference machine and its lever spin from an identified parameter file (checked, :func:`identified_file`)."""
    if params is not None:
        return params, True
    if path is None:
        raise ArgumentError("path", path, "an identified parameter file, or the parameters")
    spin = identified_file(path)
    return load_parameters(path), spin
