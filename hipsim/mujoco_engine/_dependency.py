"""The optional ``mujoco`` package, or a one-line error that says how to install it."""

from __future__ import annotations

from ..exceptions import MissingDependencyError

__all__ = ["MIN_VERSION", "mujoco"]

#: Oldest MuJoCo release that gives the engine's results: 3.3.0's ``mj_jacDot`` is wrong (by 1.6 m/s² on a
#: two-hinge test), 3.3.1 fixed it. Before 3.7 the RK4 plant's closure gaps are larger (1e-6 m, not 1e-8 m).
MIN_VERSION = (3, 3, 1)

try:
    import mujoco
except ImportError:
    raise MissingDependencyError("mujoco", "mujoco", "The MuJoCo engine") from None


def _version(text: str) -> tuple[int, ...]:
    parts = []
    for part in text.split(".")[:3]:
        digits = "".join(c for c in part if c.isdigit())
        parts.append(int(digits) if digits else 0)
    return tuple(parts)


if _version(mujoco.__version__) < MIN_VERSION:
    raise MissingDependencyError(
        "mujoco", "mujoco", f"The MuJoCo engine (mujoco >= {'.'.join(map(str, MIN_VERSION))})", found=mujoco.__version__
    )
