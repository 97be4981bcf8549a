"""hipsim.mujoco_engine._dependency: MuJoCo's version read as numbers, so that 3.10 is newer than 3.3.1."""

from __future__ import annotations

import pytest

pytest.importorskip("mujoco")

from hipsim.mujoco_engine._dependency import MIN_VERSION, _version


def test_versions_compare_as_numbers():
    assert _version("3.3.1") == (3, 3, 1)
    assert _version("3.10.0") == (3, 10, 0)
    assert _version("3.10.0") >= MIN_VERSION  # as text, "3.10.0" < "3.3.1"
    assert _version("3.3.1.dev7") == (3, 3, 1)  # a fourth part is dropped
    assert _version("4") == (4,)


def test_the_oldest_accepted_release_is_3_3_1():
    assert MIN_VERSION == (3, 3, 1)
    assert _version("3.3.1") >= MIN_VERSION
    assert _version("3.3.0") < MIN_VERSION  # its mj_jacDot is wrong
    assert _version("3.3") < MIN_VERSION
    assert _version("3.x.2") == (3, 0, 2)  # a part without digits reads as 0
