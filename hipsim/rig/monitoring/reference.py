"""The reference machine the monitor holds fixed: an identified parameter file, and the lever spin it was fitted with."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

from ...exceptions import ArgumentError, ParameterError
from ...machine.parameters import Parameters, load_parameters

__all__ = ["identified_file", "reference"]


def identified_file(path: str | Path) -> bool:
    """The lever spin an identified parameter file was fitted with (True: on); refused when the file is not identified.

    An identified file is recognised by an ``[identification]`` table or by the
    comment header ``hipsim identify`` writes (``# Identified by hipsim identify``);
    the lever spin is read from its ``# Model: … lever spin on|off`` line (default on).

    Raises:
        ParameterError: naming the file when it holds no identified values.
    """
    source = str(path)
    try:
        text = Path(path).read_text(encoding="utf-8-sig")
    except OSError as error:
        raise ParameterError(f"cannot read ({error.strerror})", source=source) from None
    header = any(line.startswith("# Identified by hipsim identify") for line in text.splitlines())
    try:
        table = "identification" in tomllib.loads(text)
    except tomllib.TOMLDecodeError:
        table = False
    if not (header or table):
        raise ParameterError(
            "holds no identified values (no [identification] table, no '# Identified by hipsim identify' header): "
            "the monitor holds the machine at identified values; run hipsim identify on a log of the rig first",
            source=source,
        )
    spin = re.search(r"^# Model: .*lever spin (on|off)", text, re.MULTILINE)
    return spin is None or spin.group(1) == "on"


def reference(path: str | Path | None, params: Parameters | None = None) -> tuple[Parameters, bool]:
    """The reference machine and its lever spin from an identified parameter file (checked, :func:`identified_file`)."""
    if params is not None:
        return params, True
    if path is None:
        raise ArgumentError("path", path, "an identified parameter file, or the parameters")
    spin = identified_file(path)
    return load_parameters(path), spin
