"""3-vectors by components, for the vectorised model and the compiled kernels alike.

A *vector* here is anything whose components are ``v[0], v[1], v[2]``: a tuple
of three floats in the compiled kernels (values on the stack, nothing on the
heap), or, in the vectorised model, a components-first NumPy array (3, ...) or
a triple of arrays, whose components broadcast against each other (a vector per
sample (3, N) against a vector per leg (3, 3, N) or a constant per leg
(3, 3, 1)). A matrix is given by its rows, each a vector.

The first group of functions is plain arithmetic that returns tuples: numba
compiles them into the kernels that call them (see :func:`jitable`) and
NumPy evaluates the same source on arrays. The second group is for NumPy
only: it writes its result into one array, which the vectorised model needs
where it operates on whole vectors per leg.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "add",
    "cross",
    "cross_array",
    "dot",
    "jitable",
    "matvec",
    "per_leg",
    "register_jitables",
    "scale",
    "stack",
    "sub",
    "transpose_times",
]

_JITABLE: list = []
_registered: set = set()


def jitable(function):
    """Mark a plain function that numba compiles into the compiled functions calling it (``register_jitable``).

    The function itself is returned unchanged, for NumPy callers. numba learns
    of it in :func:`register_jitables`, which :func:`hipsim.physics.laws.jit`
    calls before it compiles anything: so the vectorised model never imports
    numba (0.2 s of every start-up).
    """
    _JITABLE.append(function)
    return function


def register_jitables() -> None:
    """Register every :func:`jitable` function with numba, each once."""
    from numba.extending import register_jitable

    for function in _JITABLE:
        if function not in _registered:
            register_jitable(function)
            _registered.add(function)


# --- Both: plain arithmetic, compiled where a kernel calls it -------------------------


@jitable
def add(a, b):
    """a + b."""
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


@jitable
def sub(a, b):
    """a − b."""
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


@jitable
def scale(a, s):
    """a·s for a scalar (or, in NumPy, per-sample) s."""
    return (a[0] * s, a[1] * s, a[2] * s)


@jitable
def dot(a, b):
    """a·b."""
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@jitable
def cross(a, b):
    """a × b."""
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


@jitable
def matvec(M, v):
    """M·v, M given by its rows."""
    return (dot(M[0], v), dot(M[1], v), dot(M[2], v))


@jitable
def transpose_times(M, v):
    """Mᵀ·v, M given by its rows: the rows weighted by v's components."""
    return add(add(scale(M[0], v[0]), scale(M[1], v[1])), scale(M[2], v[2]))


# --- NumPy only: one components-first array out ------------------------------------------


def stack(v) -> np.ndarray:
    """A triple of component arrays as one components-first array (3, ...); the components broadcast."""
    shape = np.broadcast_shapes(*(np.shape(x) for x in v))
    out = np.empty((3,) + shape)
    out[0], out[1], out[2] = v[0], v[1], v[2]
    return out


def cross_array(a, b) -> np.ndarray:
    """a × b as one components-first array (3, ...), for vectors or triples of component arrays."""
    a0, a1, a2 = a
    b0, b1, b2 = b
    # Written into one array: stacking three temporaries costs a copy and, at
    # 10⁴ samples, fresh pages from the OS.
    out = np.empty((3,) + np.broadcast_shapes(np.shape(a0), np.shape(b0)))
    np.subtract(a1 * b2, a2 * b1, out=out[0])
    np.subtract(a2 * b0, a0 * b2, out=out[1])
    np.subtract(a0 * b1, a1 * b0, out=out[2])
    return out


def per_leg(rows: np.ndarray) -> np.ndarray:
    """Constant vectors given as rows (leg, xyz), components-first (xyz, leg, 1), to broadcast over samples."""
    return rows.T[:, :, None]
