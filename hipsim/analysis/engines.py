"""Moved: :func:`~hipsim.analysis.crosscheck.compare_mujoco` is in :mod:`hipsim.analysis.crosscheck` with the other comparisons.

Kept only until ``hipsim.cli`` imports it from there.
"""

from .crosscheck import compare_mujoco

__all__ = ["compare_mujoco"]
