"""Fingerprints of set-ups: one SHA-256 of everything that determines a result, to key result files by.

A file of results that a rerun extends (a sweep's rows, a monitor's table)
must hold rows of one set-up only. The set-up is described as plain data
(numbers, text, lists, mappings; NumPy arrays and frozen dataclasses are
turned into plain data by :func:`plain`), written as canonical JSON (keys
sorted, no spaces, floats in Python's shortest round-trip form, so the same
values give the same text on every machine) and hashed with SHA-256
(:func:`fingerprint`). A set-up of several parts keeps one fingerprint per
part, so that a refusal can name what changed (:func:`changed_parts`).

Example:
    >>> from hipsim.fingerprint import fingerprint
    >>> fingerprint({"model": "analytic", "rate_Hz": 1000.0}) == fingerprint({"rate_Hz": 1000.0, "model": "analytic"})
    True
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["canonical_json", "changed_parts", "file_fingerprint", "fingerprint", "part_fingerprints", "plain"]


def plain(value: Any, skip: tuple[str, ...] = ("source",)) -> Any:
    """The value as plain JSON data, the same for equal values.

    Args:
        value: numbers, text, None, lists and tuples, mappings, NumPy arrays
            and scalars, paths, and dataclasses (by their fields).
        skip: dataclass fields left out: where a value came from is not what it is.

    Returns:
        JSON data: a finite float stays a float (written exactly), NaN and
        infinities become ``"nan"``, ``"inf"``, ``"-inf"``; an array becomes
        its dtype, shape and the SHA-256 of its little-endian bytes.

    Raises:
        TypeError: a value of another type (a set-up must be data).
    """
    if value is None or isinstance(value, (bool, str)):
        return value
    if isinstance(value, (int, np.integer)) and not isinstance(value, np.bool_):
        return int(value)
    if isinstance(value, (float, np.floating)):
        number = float(value)
        return number if math.isfinite(number) else repr(number)
    if isinstance(value, np.bool_):
        return bool(value)
    if isinstance(value, np.ndarray):
        array = np.ascontiguousarray(value)
        if array.dtype.kind in "fc":
            array = array.astype(array.dtype.newbyteorder("<"), copy=False)
        return {
            "dtype": array.dtype.str,
            "shape": list(array.shape),
            "sha256": hashlib.sha256(array.tobytes()).hexdigest(),
        }
    if isinstance(value, Path):
        return str(value)
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        # A field added later with ``metadata={"omit_when_none": True}`` is left out while None, so
        # what existed before it keeps its fingerprint (Parameters.geometry: the drawing).
        return {
            f.name: plain(getattr(value, f.name), skip)
            for f in dataclasses.fields(value)
            if f.name not in skip and not (f.metadata.get("omit_when_none") and getattr(value, f.name) is None)
        }
    if isinstance(value, Mapping):
        return {str(key): plain(item, skip) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [plain(item, skip) for item in value]
    raise TypeError(f"a set-up holds data, not {type(value).__name__}")


def canonical_json(value: Any) -> str:
    """The value (:func:`plain`) as canonical JSON: keys sorted, no spaces, ASCII."""
    return json.dumps(plain(value), sort_keys=True, separators=(",", ":"), ensure_ascii=True, allow_nan=False)


def fingerprint(value: Any) -> str:
    """The SHA-256 (64 hex digits) of the value's canonical JSON: equal set-ups, equal fingerprints."""
    return hashlib.sha256(canonical_json(value).encode("ascii")).hexdigest()


def file_fingerprint(path: str | Path) -> str:
    """The SHA-256 of a file's bytes (read in pieces), for a set-up that is a whole file."""
    digest = hashlib.sha256()
    with open(path, "rb") as stream:
        while piece := stream.read(1 << 20):
            digest.update(piece)
    return digest.hexdigest()


def part_fingerprints(parts: Mapping[str, Any]) -> dict[str, str]:
    """One fingerprint per part of a set-up, and ``"setup"``: the fingerprint of them all.

    Args:
        parts: part name → its data (``{"parameters": params, "model": "analytic", …}``).
    """
    each = {name: fingerprint(value) for name, value in parts.items()}
    return each | {"setup": fingerprint(each)}


def changed_parts(recorded: Mapping[str, str], current: Mapping[str, str]) -> list[str]:
    """The parts whose fingerprints differ (a part in only one of them counts), in ``current``'s order."""
    names = [name for name in current if name != "setup"] + [
        name for name in recorded if name not in current and name != "setup"
    ]
    return [name for name in names if recorded.get(name) != current.get(name)]
