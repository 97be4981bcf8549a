"""Helpers of the motion readers' law tests: a call with its trajectory warnings silenced, and the error it raises."""

from __future__ import annotations

import warnings

import pytest

from hipsim import TrajectoryError
from hipsim.motion.build import TrajectoryWarning


def quiet(call):
    """``call()`` with hipsim's trajectory warnings silenced (the test is about its result or its error)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TrajectoryWarning)
        return call()


def error_of(call) -> TrajectoryError:
    """The :class:`TrajectoryError` that ``call()`` raises (warnings silenced); the test fails if it raises none."""
    with pytest.raises(TrajectoryError) as info:
        quiet(call)
    return info.value
