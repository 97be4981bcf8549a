"""Frozen, shape-checked arrays for hipsim's result and parameter dataclasses."""

from __future__ import annotations

import numpy as np

from .exceptions import ArgumentError

__all__ = ["check_shapes", "readonly"]


def readonly(array) -> np.ndarray:
    """A read-only copy of ``array`` (floats, or integers and booleans kept as they are)."""
    out = np.array(array)  # a copy, so freezing it leaves the caller's array alone
    if out.dtype.kind not in "iub":
        out = out.astype(float)
    out.setflags(write=False)
    return out


def check_shapes(obj, shapes: dict[str, tuple], samples: int | None = None) -> None:
    """Freeze the named array fields of a frozen dataclass and check their shapes.

    Args:
        obj: the dataclass instance (its fields are replaced by read-only copies).
        shapes: field name → expected shape; "N" stands for the sample count.
        samples: the sample count; None to take it from the first field's first axis.

    Raises:
        ArgumentError: naming the class, the field and both shapes.
    """
    for name, shape in shapes.items():
        value = readonly(getattr(obj, name))
        if samples is None:
            samples = value.shape[0] if value.ndim else 0
        expected = tuple(samples if s == "N" else s for s in shape)
        if value.shape != expected:
            raise ArgumentError(f"{type(obj).__name__}.{name}", value, f"shape {expected}")
        object.__setattr__(obj, name, value)
