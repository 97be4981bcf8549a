"""The viewer's scene helpers (hipsim.present.meshcat_scene): the singularity colours, the arrow scale and its steps,
and the arrows' poses, by hand. The scene on a machine and its page: present/test_viewer.py."""

from __future__ import annotations

import numpy as np
import pytest

from hipsim.exceptions import ArgumentError
from hipsim.present import meshcat_scene as scene
from hipsim.present.motion_frames import Motion


def test_the_singularity_colours_between_and_beyond_their_stops():
    red, yellow, green = (rgb for _, rgb in scene.SINGULARITY_STOPS)
    colours = scene.singularity_colour([-1.0, 0.0, 0.125, 0.25, 0.5, 2.0, np.nan])
    expected = np.array([red, red, np.add(red, yellow) / 2, yellow, green, green, red])  # clamped; NaN counts as 0
    np.testing.assert_allclose(colours, expected, atol=1e-15)
    assert scene.singularity_colour(0.5).shape == (3,)


def test_the_arrow_scale_is_the_largest_step_that_keeps_the_longest_arrow_short():
    assert scene.force_scale_for(300.0) == 1e-3  # 300 N · 1 mm/N = 0.3 m: at the limit, accepted
    assert scene.force_scale_for(300.001) == 0.5e-3
    assert scene.force_scale_for(1500.0) == pytest.approx(0.2e-3)
    assert scene.force_scale_for(1e12) == scene._SCALES[-1] == pytest.approx(0.2e-7)  # the smallest step at most
    assert scene.force_scale_for(10.0, longest=0.001) == pytest.approx(1e-4)
    assert scene.scale_text(0.5e-3) == "0.5 mm per N"


def forces_motion(F_act, F_joint) -> Motion:
    n = 1
    return Motion(
        np.zeros(n), 10.0, 1.0, np.zeros((n, 3)), np.zeros((n, 7)), np.zeros(n),
        F_act, F_joint, None, np.zeros((n, 3)), False, "m",
    )  # fmt: skip


def test_a_motions_scale_is_for_its_peak_force_by_length():
    joint = np.zeros((1, 2, 3, 3))
    joint[0, 1, 0] = [0.0, 300.0, 400.0]  # 500 N by length, above every carriage's 450 N
    motion = forces_motion(np.array([[450.0, -10.0, 0.0]]), joint)
    assert scene.arrow_scale(motion) == 0.5e-3  # 500 N · 0.5 mm/N = 0.25 m; 1 mm/N would be 0.5 m
    assert scene.arrow_scale(motion, 2e-3) == 2e-3  # as given
    with pytest.raises(ArgumentError, match="a motion with forces, or a force_scale"):
        scene.arrow_scale(forces_motion(None, None))


@pytest.mark.parametrize("d", [[0.0, 1.0, 0.0], [0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [1.0, 2.0, -2.0]])
def test_the_rotation_takes_y_onto_the_direction(d):
    R = scene._rotation_y_to(np.array(d))
    unit = np.array(d) / np.linalg.norm(d)
    np.testing.assert_allclose(R @ [0.0, 1.0, 0.0], unit, atol=1e-15)
    np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-15)
    assert np.linalg.det(R) == pytest.approx(1.0)


def test_an_arrow_from_its_tail_along_its_force():
    shaft, length, head = scene._arrow_pose(np.array([1.0, 0.0, 0.0]), np.array([0.0, 0.0, 200.0]), 1e-3)
    assert length == pytest.approx(0.2)
    np.testing.assert_allclose(shaft[:3, 3], [1.0, 0.0, 0.1], atol=1e-15)  # the shaft's middle
    np.testing.assert_allclose(head[:3, 3], [1.0, 0.0, 0.2 + 0.5 * scene._HEAD_LENGTH], atol=1e-15)
    _, zero, head = scene._arrow_pose(np.zeros(3), np.zeros(3), 1e-3)  # no force: the shortest arrow, upwards
    assert zero == scene._MIN_ARROW and head[2, 3] > 0
    names = [name for name, _ in scene._arrow_names()]
    assert names == ["screw_1", "screw_2", "screw_3"] + [f"joint_{j}{i}" for j in (1, 2) for i in (1, 2, 3)]
