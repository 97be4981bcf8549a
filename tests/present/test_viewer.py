"""The meshcat viewer: closed frames, forces and colours, the recorded page (also in a real browser), the human beside the machine.

The human model itself is tested in tests/present/test_human.py, the live server and the page builder in tests/present/test_meshcat_output.py;
screenshots come from hipsim.present.browser.
"""

from __future__ import annotations

import base64
import io
import math
import os
import re
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from fake_clock import FakeClock
from support import SmoothMotion, given

from hipsim.analytic.inverse_kinematics import kinematics as analytic_kinematics
from hipsim.analytic.inverse_kinematics import rotation_matrix
from hipsim.cli.view import run_view, step_through
from hipsim.closed_chain.constraints import closure_residuals
from hipsim.machine.parameters import load_parameters
from hipsim.motion.trajectories import interpolator, iso14242
from hipsim.present.browser import find_browser, screenshot
from hipsim.present.human import HUMAN_PELVIS_POSITION, HUMAN_PELVIS_ROTATION
from hipsim.present.viewer import Viewer, force_scale_for, singularity_colour

FPS = 30.0


# ---------------------------------------------------------------------------
# Helpers
# ---------------------------------------------------------------------------


@pytest.fixture(scope="module")
def offline():
    viewer = Viewer(serve=False)
    yield viewer
    viewer.close()


@pytest.fixture(scope="module")
def iso_motion(offline):
    return offline.motion(iso14242(rate=1000), fps=FPS, forces=True, singularity=True)


@pytest.fixture(scope="module")
def iso_page(offline, iso_motion, tmp_path_factory):
    path = tmp_path_factory.mktemp("page") / "iso.html"
    path.write_text(offline.record(iso_motion), encoding="utf-8")
    return path


def page_commands(html: str) -> list[dict]:
    """The meshcat commands stored in an offline page, decoded."""
    import umsgpack

    block = given(re.search(r"var commands = \[(.*?)\];", html, re.S)).group(1)
    return [umsgpack.unpackb(base64.b64decode(s)) for s in re.findall(r'"([A-Za-z0-9+/=]+)"', block)]


def page_tracks(html: str, fps: float = FPS) -> tuple[dict, dict]:
    """{(node path, track name): (frame indices, values)} of the page's animation, and its options."""
    animations = [c for c in page_commands(html) if c["type"] == "set_animation"]
    assert len(animations) == 1
    tracks = {}
    for entry in animations[0]["animations"]:
        for track in entry["clip"]["tracks"]:
            keys = track["keys"]
            tracks[(entry["path"], track["name"])] = (
                np.array([k["time"] for k in keys]),
                np.array([k["value"] for k in keys], dtype=float),
            )
            assert track["interpolation"] == 2300  # discrete: every frame shown is a closed sample
        assert entry["clip"]["fps"] == pytest.approx(fps)
    return tracks, animations[0]["options"]


def quaternion_matrix(xyzw: np.ndarray) -> np.ndarray:
    """Rotation matrices from three.js quaternions [x, y, z, w], shape (N, 4) -> (N, 3, 3)."""
    return np.array([pin.Quaternion(w, x, y, z).toRotationMatrix() for x, y, z, w in xyzw])


def node(name: str, root: str = "machine") -> str:
    return f"/meshcat/hipsim/{root}/visuals/{name}"


def need_browser() -> str:
    browser = find_browser()
    if browser is None:
        if os.environ.get("HIPSIM_REQUIRE_BROWSER") == "1":
            pytest.fail("HIPSIM_REQUIRE_BROWSER=1 but no chromium on PATH (apt-get install chromium)")
        pytest.skip("chromium is not installed (apt-get install chromium); set HIPSIM_REQUIRE_BROWSER=1 to require it")
    return browser


def load_png(path: Path) -> np.ndarray:
    from PIL import Image

    return np.asarray(Image.open(path).convert("RGB"), dtype=float) / 255.0


def project(points, target, position, size, fov_deg: float = 75.0) -> np.ndarray:
    """Pixel (column, row) of world points seen by meshcat's camera (three.js: vertical fov 75°)."""
    target, position = np.asarray(target, float), np.asarray(position, float)
    width, height = size
    forward = (target - position) / np.linalg.norm(target - position)
    right = np.cross(forward, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    d = np.atleast_2d(points) - position
    x, y, z = d @ right, d @ up, d @ forward
    t = math.tan(math.radians(fov_deg / 2))
    return np.column_stack([(x / (z * t * width / height) + 1) / 2 * width, (1 - y / (z * t)) / 2 * height])


def patch(image: np.ndarray, pixel, radius: int = 5) -> np.ndarray:
    col, row = int(round(pixel[0])), int(round(pixel[1]))
    return image[max(row - radius, 0) : row + radius + 1, max(col - radius, 0) : col + radius + 1].reshape(-1, 3)


# ---------------------------------------------------------------------------
# The module's names
# ---------------------------------------------------------------------------


def test_frames_are_closed_samples(offline, iso_motion):
    motion = iso_motion
    assert len(motion) == 30 and motion.periodic
    assert np.allclose(motion.t, np.arange(30) / FPS)
    assert motion.residual.max() <= 1e-9
    gaps = np.linalg.norm(closure_residuals(offline.chain, motion.q), axis=-1)
    assert gaps.max() <= 1e-9
    # The platform angles shown are the trajectory's at those times.
    assert np.allclose(motion.angles, iso14242(rate=FPS).q, atol=1e-9)


def test_page_shows_closed_frames(offline, iso_motion, iso_page):
    """Read the animation back from the page: every lever tip meets its platform joint in every frame."""
    tracks, options = page_tracks(iso_page.read_text(encoding="utf-8"))
    assert options["play"] is True and options["repetitions"] == math.inf
    l = offline.params.lever_length
    worst = 0.0
    for j in (1, 2):
        for i in (1, 2, 3):
            frames, lever_p = tracks[(node(f"lever_{j}{i}_0"), ".position")]
            assert np.array_equal(frames, np.arange(len(iso_motion)))
            lever_R = quaternion_matrix(tracks[(node(f"lever_{j}{i}_0"), ".quaternion")][1])
            joint_p = tracks[(node(f"platform_{j}_joint_{i}_0"), ".position")][1]
            # The lever is drawn from its universal joint to its tip, centred at l/2 on its z axis.
            tips = lever_p + lever_R[:, :, 2] * l / 2
            worst = max(worst, float(np.linalg.norm(tips - joint_p, axis=1).max()))
    assert worst <= 1e-9, worst


def test_force_arrows_and_lever_colours_follow_the_dynamics(offline, iso_motion, iso_page):
    from hipsim.closed_chain.dynamics import trajectory_dynamics

    motion = iso_motion
    samples = interpolator(iso14242(rate=1000))(np.arange(30) / FPS)  # what the viewer shows
    _, torques = trajectory_dynamics(offline.chain, samples)
    assert np.allclose(motion.F_act, torques.F_act)
    assert np.allclose(np.linalg.norm(motion.F_joint, axis=-1), torques.joint_forces.Fa)
    scale = force_scale_for(max(np.abs(motion.F_act).max(), np.linalg.norm(motion.F_joint, axis=-1).max()))
    assert scale == pytest.approx(1e-3)  # ISO peaks: 268 N on a screw, 80 N on a joint
    tracks, _ = page_tracks(iso_page.read_text(encoding="utf-8"))
    for i in range(3):
        length = tracks[(f"/meshcat/hipsim/forces/screw_{i + 1}/shaft", ".scale")][1][:, 1]
        assert np.allclose(length, np.maximum(np.abs(motion.F_act[:, i]) * scale, 1e-5))
        direction = quaternion_matrix(tracks[(f"/meshcat/hipsim/forces/screw_{i + 1}/shaft", ".quaternion")][1])[
            :, :, 1
        ]
        assert np.allclose(direction[:, 2], np.sign(motion.F_act[:, i]))  # along the screw, with the force
    for j in range(2):
        for i in range(3):
            path = f"/meshcat/hipsim/forces/joint_{j + 1}{i + 1}/shaft"
            direction = quaternion_matrix(tracks[(path, ".quaternion")][1])[:, :, 1]
            length = tracks[(path, ".scale")][1][:, 1]
            assert np.allclose(direction * length[:, None], motion.F_joint[:, j, i] * scale, atol=1e-9)
    cond_inv = analytic_kinematics(offline.params, samples).cond_inv
    assert np.allclose(motion.cond_inv, cond_inv)
    colour = tracks[(node("lever_11_0") + "/<object>", ".material.color")][1]
    assert np.allclose(colour, singularity_colour(cond_inv))
    assert np.allclose(
        singularity_colour([0.0, 0.25, 0.5, 0.9, np.nan]),
        [[0.85, 0.1, 0.1], [0.95, 0.85, 0.1], [0.45, 0.9, 0.1], [0.45, 0.9, 0.1], [0.85, 0.1, 0.1]],
    )


def test_page_is_self_contained(iso_page):
    html = iso_page.read_text(encoding="utf-8")
    # No resource comes from elsewhere: no src/href to a URL, no <link>, no script file.
    assert not re.search(r"""\b(?:src|href)\s*=\s*["']?\s*(?:[a-z]+:)?//""", html, re.I)
    assert not re.search(r"<link\b", html, re.I)
    assert not re.search(r"<script[^>]+src", html, re.I)
    assert "MeshCat.Viewer" in html and "hipsim-legend" in html and "1 mm per N" in html
    kinds = [c["type"] for c in page_commands(html)]
    assert kinds[-1] == "set_animation" and kinds.count("set_object") > 30


def test_show_orientation_and_step_mode(offline):
    q = offline.show_orientation(math.radians(20.0), math.radians(-4.0), math.radians(2.0))
    assert np.linalg.norm(closure_residuals(offline.chain, q), axis=-1).max() <= 1e-9
    with pytest.raises(ValueError, match="a configuration of size nq"):
        offline.show(np.zeros(3))
    shown = []
    out = io.StringIO()
    motion = offline.motion(iso14242(rate=100), fps=10)
    step_through(offline, motion, io.StringIO("\n\nb\nq\n"), out, loop=False, on_frame=lambda k, m: shown.append(k))
    assert shown == [0, 1, 2, 1]
    assert "frame 3/10" in out.getvalue()


def test_play_keeps_real_time_and_skips_the_frames_a_slow_one_overran(offline):
    """On an injected clock: frames at 1/16 s of the clock (binary fractions, so every time is exact)."""
    shown = []
    clock = FakeClock()

    def on_frame(k, motion):
        shown.append(k)
        if k == 2:
            clock.advance(2 / 16)  # sending frame 2 took two frame periods: frame 3's time has passed

    trajectory = SmoothMotion(seed=3)(np.arange(0.0, 0.6, 0.01))
    motion = offline.play(trajectory, speed=2.0, loop=False, fps=16, on_frame=on_frame, clock=clock)
    # 0.59 s of trajectory at twice real time, 16 frames a second of the clock: 5 frames 1/8 s of trajectory apart.
    assert len(motion) == 5 and np.allclose(np.diff(motion.t), 0.125)
    assert shown == [0, 1, 2, 4]  # frame 3 skipped, not shown late; the run rests on its last frame
    assert clock.monotonic() == 5 / 16  # the last frame shown for its whole period, no longer


def test_play_shows_the_last_frame_even_when_the_clock_skipped_it(offline):
    shown = []
    clock = FakeClock()
    trajectory = SmoothMotion(seed=3)(np.arange(0.0, 0.6, 0.01))

    def on_frame(k, motion):
        shown.append(k)
        if k == 3:
            clock.advance(3 / 16)  # past the end

    offline.play(trajectory, speed=2.0, loop=False, fps=16, on_frame=on_frame, clock=clock)
    assert shown == [0, 1, 2, 3, 4]


def test_run_view_writes_the_page(tmp_path):
    out = io.StringIO()
    assert run_view(load_parameters(), iso14242(rate=500), html=tmp_path / "v.html", fps=10, speed=0.5, stream=out) == 0
    text = out.getvalue()
    assert "wrote" in text and "20 frames at 10 fps, speed 0.5x" in text and "closure gap" in text
    tracks, _ = page_tracks((tmp_path / "v.html").read_text(encoding="utf-8"), fps=10)
    frames, _ = tracks[(node("lever_11_0"), ".position")]
    assert len(frames) == 20  # 1 s at 10 fps / 0.5 speed
    assert sorted(p.name for p in tmp_path.iterdir()) == ["v.html"]


# ---------------------------------------------------------------------------
# The human beside the machine
# ---------------------------------------------------------------------------


def test_viewer_moves_the_human_thigh_with_the_platforms():
    with Viewer(serve=False, human=True) as viewer:
        motion = viewer.motion(SmoothMotion(seed=1, amplitude_deg=20.0)(np.linspace(0.0, 1.0, 11)), fps=10)
        html = viewer.record(motion)
    tracks, _ = page_tracks(html, fps=10)
    platform = quaternion_matrix(tracks[(node("platform_1_0"), ".quaternion")][1])
    thigh = quaternion_matrix(tracks[(node("right_upperleg_0", "human"), ".quaternion")][1])
    C = HUMAN_PELVIS_ROTATION
    assert np.abs(np.einsum("ij,njk,lk->nil", C, thigh, C) - platform).max() <= 1e-9
    assert np.allclose(platform, rotation_matrix(motion.angles), atol=1e-9)
    # The left leg stays put: no track for it.
    assert not any("left_upperleg" in path for path, _ in tracks)


# ---------------------------------------------------------------------------
# The page in a real browser
# ---------------------------------------------------------------------------


def _classify(pixels: np.ndarray, colour: str) -> np.ndarray:
    r, g, b = pixels[:, 0], pixels[:, 1], pixels[:, 2]
    return {
        "green": (g > r + 0.15) & (g > b + 0.1),  # platform 1
        "purple": (r > g + 0.1) & (b > g + 0.15),  # platform 2
        "blue": (b > r + 0.25) & (b > g + 0.15),  # carriages
        "grey": (np.abs(r - g) < 0.05) & (np.abs(g - b) < 0.06) & (r < 0.45),  # base plate
        "red": (r > g + 0.35) & (r > b + 0.35),  # the human's right leg
    }[colour]


def test_page_renders_the_animation_in_chromium(offline, iso_motion, iso_page, tmp_path):
    browser = need_browser()
    from hipsim.present.meshcat_scene import _CAMERA

    size = (900, 700)
    target, position = _CAMERA[False]
    images = {}
    for t in (0.1, 0.6):
        images[t] = load_png(screenshot(iso_page, tmp_path / f"t{t}.png", time_s=t, size=size, browser=browser))
        image = images[t]
        assert image.shape == (size[1], size[0], 3)
        # Not blank: many different colours, much of the picture away from the background.
        assert len(np.unique((image * 31).astype(int).reshape(-1, 3), axis=0)) > 50
        k = int(t * FPS)
        data = offline.scene.machine_data
        pin.framesForwardKinematics(offline.chain.model, data, iso_motion.q[k])
        h1, h2 = offline.params.heights
        # Platform 1 on the camera's side of its centre (where the red hip joint ball sits), the base plate.
        platform = data.oMi[offline.chain.model.getJointId("platform_1_rx")]
        checks = [("green", platform.act(np.array([0.07, 0.07, 0.0]))), ("grey", [-0.15, 0.15, 0.0])]
        for i in (1, 2, 3):
            b = data.oMi[offline.chain.model.getJointId(f"slider_{i}")].translation
            checks.append(("blue", b - [0.0, 0.0, (h1 - h2) / 2]))
        pixels = project([p for _, p in checks], target, position, size)
        for (colour, point), pixel in zip(checks, pixels):
            found = _classify(patch(image, pixel, 6), colour)
            assert found.mean() > 0.3, (
                f"t = {t} s: expected {colour} around {pixel} (world {point}), got {patch(image, pixel, 1)}"
            )
        # Platform 2, seen through the levers and carriages: purple somewhere around its centre.
        assert _classify(patch(image, project([0.0, 0.0, h2], target, position, size)[0], 40), "purple").sum() > 20
    # The animation plays: the machine moves between the two times.
    rows, cols = slice(100, 560), slice(250, 650)
    changed = np.abs(images[0.1][rows, cols] - images[0.6][rows, cols]).max(axis=2) > 0.1
    assert changed.mean() > 0.01


def test_human_page_renders_in_chromium(tmp_path):
    browser = need_browser()
    from hipsim.present.meshcat_scene import _CAMERA

    size = (800, 600)
    with Viewer(serve=False, human=True) as viewer:
        page = tmp_path / "human.html"
        page.write_text(viewer.record(iso14242(rate=200), fps=10), encoding="utf-8")
    image = load_png(screenshot(page, tmp_path / "human.png", time_s=0.0, size=size, browser=browser))
    target, position = _CAMERA[True]
    # The right thigh (red), half way down from the hip at heel strike (25° flexion).
    hip = HUMAN_PELVIS_POSITION + HUMAN_PELVIS_ROTATION @ np.array([0.023, -0.1, 0.082])
    thigh = hip + rotation_matrix(iso14242(rate=200).q[:1])[0] @ [0.0, 0.0, -0.2]  # the femur turns as the platforms
    pixel = project(thigh, target, position, size)[0]
    assert _classify(patch(image, pixel, 8), "red").mean() > 0.3, patch(image, pixel, 1)
