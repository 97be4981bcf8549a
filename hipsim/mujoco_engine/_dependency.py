"""The optional ``mujoco`` package, or a one-line error that says how to install it."""

from __future__ import annotations

from ..exceptions import MissingDependencyError

__all__ = ["MIN_VERSION", "mujoco"]

#: Oldest MuJoCo release the engine is tested with (site-to-site ``connect``, ``mj_jacDot``, ``MjSpec``).
MIN_VERSION = (3, 3)

try:
    import mujoco
except ImportError:
    raise MissingDependencyError("mujoco", "mujoco", "The MuJoCo engine") from None


def _version(text: str) -> tuple[int, ...]:
    parts = []
    for part in text.split(".")[:2]:
        digits = "".join(c for c in part if c.isdigit())
        parts.append(int(digits) if digits else 0)
    return tuple(parts)


if _version(mujoco.__version__) < MIN_VERSION:
    raise MissingDependencyError(
        "mujoco", "mujoco", f"The MuJoCo engine (mujoco >= {'.'.join(map(str, MIN_VERSION))})", found=mujoco.__version__
    )
