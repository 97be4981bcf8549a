"""The meshcat viewer: closed frames, the offline page in a real browser, the live server, the human model."""

from __future__ import annotations

import base64
import io
import math
import os
import re
import signal
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

from hipsim.kinematics import kinematics as analytic_kinematics
from hipsim.kinematics import rotation_matrix
from hipsim.parameters import load_parameters
from hipsim.pinocchio_model import closure_residuals
from hipsim.trajectories import interpolator, iso14242
from hipsim.viewer import (
    HUMAN_PELVIS_ROTATION,
    Viewer,
    find_browser,
    force_scale_for,
    human_hip_angles,
    load_human,
    run_view,
    screenshot,
    singularity_colour,
)
from support import SmoothMotion

REPO = Path(__file__).resolve().parents[1]
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

    block = re.search(r"var commands = \[(.*?)\];", html, re.S).group(1)
    return [umsgpack.unpackb(base64.b64decode(s)) for s in re.findall(r'"([A-Za-z0-9+/=]+)"', block)]


def page_tracks(html: str, fps: float = FPS) -> tuple[dict, dict]:
    """{(node path, track name): (frame indices, values)} of the page's animation, and its options."""
    animations = [c for c in page_commands(html) if c["type"] == "set_animation"]
    assert len(animations) == 1
    tracks = {}
    for entry in animations[0]["animations"]:
        for track in entry["clip"]["tracks"]:
            keys = track["keys"]
            tracks[(entry["path"], track["name"])] = (np.array([k["time"] for k in keys]), np.array([k["value"] for k in keys], dtype=float))
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


def listening_sockets(pid: int | None = None) -> list[tuple[str, int]]:
    """(address, port) of the TCP sockets in LISTEN state, of one process or of all, from /proc."""
    inodes = None
    if pid is not None:
        inodes = set()
        for fd in Path(f"/proc/{pid}/fd").iterdir():
            try:
                target = os.readlink(fd)
            except OSError:
                continue
            if target.startswith("socket:["):
                inodes.add(target[8:-1])
    out = []
    for table, v6 in (("/proc/net/tcp", False), ("/proc/net/tcp6", True)):
        try:
            lines = Path(table).read_text().splitlines()[1:]
        except OSError:
            continue
        for line in lines:
            fields = line.split()
            local, state, inode = fields[1], fields[3], fields[9]
            if state != "0A" or (inodes is not None and inode not in inodes):
                continue
            address, port = local.split(":")
            raw = bytes.fromhex(address)
            if v6:
                # Four 32-bit words, each in host (little-endian) order.
                raw = b"".join(raw[k : k + 4][::-1] for k in range(0, 16, 4))
                import ipaddress

                text = str(ipaddress.IPv6Address(raw))
            else:
                text = ".".join(str(b) for b in raw[::-1])
            out.append((text, int(port, 16)))
    return out


def children(pid: int) -> list[int]:
    found = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[1]) == pid:
            found.append(int(stat.parent.name))
    return found


def alive(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"


def wait_until(condition, timeout: float) -> bool:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if condition():
            return True
        time.sleep(0.05)
    return condition()


# ---------------------------------------------------------------------------
# The frames shown are closed configurations
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
    from hipsim.pinocchio_model import trajectory_dynamics

    motion = iso_motion
    samples = interpolator(iso14242(rate=1000))(np.arange(30) / FPS)  # what the viewer shows
    _, torques = trajectory_dynamics(offline.chain, samples)
    assert np.allclose(motion.F_act, torques.F_act)
    assert np.allclose(np.linalg.norm(motion.F_joint, axis=-1), torques.Fa)
    scale = force_scale_for(max(np.abs(motion.F_act).max(), np.linalg.norm(motion.F_joint, axis=-1).max()))
    assert scale == pytest.approx(1e-3)  # ISO peaks: 268 N on a screw, 80 N on a joint
    tracks, _ = page_tracks(iso_page.read_text(encoding="utf-8"))
    for i in range(3):
        length = tracks[(f"/meshcat/hipsim/forces/screw_{i + 1}/shaft", ".scale")][1][:, 1]
        assert np.allclose(length, np.maximum(np.abs(motion.F_act[:, i]) * scale, 1e-5))
        direction = quaternion_matrix(tracks[(f"/meshcat/hipsim/forces/screw_{i + 1}/shaft", ".quaternion")][1])[:, :, 1]
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
    assert np.allclose(singularity_colour([0.0, 0.25, 0.5, 0.9, np.nan]), [[0.85, 0.1, 0.1], [0.95, 0.85, 0.1], [0.45, 0.9, 0.1], [0.45, 0.9, 0.1], [0.85, 0.1, 0.1]])


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
    with pytest.raises(ValueError):
        offline.show(np.zeros(3))
    shown = []
    out = io.StringIO()
    offline.play(iso14242(rate=100), step=True, loop=False, fps=10, input=io.StringIO("\n\nb\nq\n"), stream=out, on_frame=lambda k, m: shown.append(k))
    assert shown == [0, 1, 2, 1]
    assert "frame 3/10" in out.getvalue()


def test_play_keeps_real_time(offline):
    shown = []
    trajectory = SmoothMotion(seed=3)(np.arange(0.0, 0.6, 0.01))
    start = time.monotonic()
    offline.play(trajectory, speed=2.0, loop=False, fps=20, on_frame=lambda k, m: shown.append(k))
    elapsed = time.monotonic() - start
    # 0.6 s of trajectory at twice real time: 0.3 s, in 6 frames 0.05 s apart in trajectory time.
    assert 0.25 <= elapsed <= 2.0
    assert shown == sorted(shown) and shown[0] == 0 and shown[-1] == 5


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
# The human model
# ---------------------------------------------------------------------------


@pytest.fixture(scope="module")
def human():
    model, _ = load_human()
    return model, model.createData()


def _human_pose(human, alpha, beta, gamma):
    model, data = human
    R = rotation_matrix(np.radians([[alpha, beta, gamma]]))[0]
    angles = human_hip_angles(R)
    q = pin.neutral(model)
    for name, value in zip(("right_hip_Z", "right_hip_X", "right_hip_Y"), angles):
        q[model.joints[model.getJointId(name)].idx_q] = value
    pin.forwardKinematics(model, data, q)
    C = HUMAN_PELVIS_ROTATION
    joint = {name: data.oMi[model.getJointId(name)] for name in ("right_hip_Z", "right_hip_Y", "right_knee_Z", "right_ankle_X")}
    femur = C @ joint["right_hip_Y"].rotation @ C.T  # femur rotation, world axes, relative to standing
    knee = C @ (joint["right_knee_Z"].translation - joint["right_hip_Z"].translation)  # world axes
    toes = C @ joint["right_ankle_X"].rotation[:, 0]  # the foot's anterior axis, world axes
    return R, angles, femur, knee, toes


def test_human_model_hip_axes_are_as_documented(human):
    """The URDF's right hip: Z (mediolateral, +z to the right) flexion, X about −x, Y about +y; ISB pelvis axes."""
    model, _ = human
    axes = {}
    for name in ("right_hip_Z", "right_hip_X", "right_hip_Y", "left_hip_Z"):
        joint = model.joints[model.getJointId(name)]
        axes[name] = joint.shortname()
    assert axes["right_hip_Z"] == "JointModelRZ"
    assert axes["right_hip_X"] in ("JointModelRX", "JointModelRevoluteUnaligned")
    data = model.createData()
    pin.forwardKinematics(model, data, pin.neutral(model))
    right = data.oMi[model.getJointId("right_hip_Z")].translation
    left = data.oMi[model.getJointId("left_hip_Z")].translation
    assert right[2] > 0 > left[2]  # pelvis z points to the subject's right
    assert data.oMi[model.getJointId("right_knee_Z")].translation[1] < right[1]  # y up: the knee is below


def test_human_femur_turns_exactly_as_the_platform(human):
    rng = np.random.default_rng(5)
    for angles in rng.uniform(-30.0, 30.0, (20, 3)):
        R, _, femur, _, _ = _human_pose(human, *angles)
        assert np.abs(femur - R).max() <= 1e-12


def test_human_anatomical_signs(human):
    # Positive α is flexion: the knee moves forward (+Y, where the subject faces) and up.
    _, hip, _, knee, _ = _human_pose(human, 20.0, 0.0, 0.0)
    assert knee[1] > 0.1 and knee[2] > -0.439 + 0.02 and hip[0] == pytest.approx(math.radians(20.0))
    _, _, _, knee_ext, _ = _human_pose(human, -15.0, 0.0, 0.0)
    assert knee_ext[1] < -0.05  # extension: backward
    # Positive β is adduction: the right knee moves medially, towards −X (the subject's left).
    _, hip, _, knee, _ = _human_pose(human, 0.0, 10.0, 0.0)
    assert knee[0] < -0.07 and hip[1] == pytest.approx(math.radians(-10.0))  # the model's right_hip_X > 0 is abduction
    # Positive γ is internal rotation: the toes turn medially (towards −X).
    _, hip, _, knee, toes = _human_pose(human, 0.0, 0.0, 15.0)
    assert toes[0] == pytest.approx(-math.sin(math.radians(15.0))) and hip[2] == pytest.approx(math.radians(15.0))
    assert np.allclose(knee, [0.0, 0.0, -0.439])  # rotation leaves the knee where it is


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
    from hipsim.viewer import _CAMERA

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
        data = offline._machine_data
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
            assert found.mean() > 0.3, f"t = {t} s: expected {colour} around {pixel} (world {point}), got {patch(image, pixel, 1)}"
        # Platform 2, seen through the levers and carriages: purple somewhere around its centre.
        assert _classify(patch(image, project([0.0, 0.0, h2], target, position, size)[0], 40), "purple").sum() > 20
    # The animation plays: the machine moves between the two times.
    rows, cols = slice(100, 560), slice(250, 650)
    changed = np.abs(images[0.1][rows, cols] - images[0.6][rows, cols]).max(axis=2) > 0.1
    assert changed.mean() > 0.01


def test_human_page_renders_in_chromium(tmp_path):
    browser = need_browser()
    from hipsim.viewer import _CAMERA, HUMAN_PELVIS_POSITION

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


# ---------------------------------------------------------------------------
# The live server
# ---------------------------------------------------------------------------


def test_live_server_listens_on_loopback_only():
    viewer = Viewer()
    try:
        pid = viewer.server_pid
        sockets = listening_sockets(pid)
        assert len(sockets) >= 2, sockets  # ZMQ and web
        assert all(address == "127.0.0.1" for address, _ in sockets), sockets
        assert re.fullmatch(r"http://127\.0\.0\.1:\d+/static/", viewer.url)
        port = int(viewer.url.split(":")[2].split("/")[0])
        assert ("127.0.0.1", port) in sockets
        with urllib.request.urlopen(viewer.url, timeout=10) as response:
            assert response.status == 200 and b"<html" in response.read().lower()
        viewer.play(iso14242(rate=100), loop=False, fps=20)
    finally:
        viewer.close()
    assert wait_until(lambda: not alive(pid), 5.0)
    assert all(port != p for _, p in listening_sockets())


_SCRIPT = """
import sys
from hipsim.viewer import run_view
sys.exit(run_view(forces=True, singularity=True))
"""


def test_view_command_ends_cleanly_on_ctrl_c():
    child = subprocess.Popen(
        [sys.executable, "-c", _SCRIPT], cwd=REPO, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        env={**os.environ, "PYTHONPATH": str(REPO)},
    )  # fmt: skip
    try:
        line = ""
        deadline = time.monotonic() + 30
        while "http://" not in line and time.monotonic() < deadline:
            line = child.stdout.readline()
            if not line and child.poll() is not None:
                break
        assert "http://127.0.0.1:" in line, (line, child.stderr.read() if child.poll() is not None else "")
        port = int(re.search(r"127\.0\.0\.1:(\d+)", line).group(1))
        servers = children(child.pid)
        assert len(servers) == 1
        time.sleep(0.7)  # playing
        assert child.poll() is None
        child.send_signal(signal.SIGINT)
        out, err = child.communicate(timeout=10)
    finally:
        if child.poll() is None:
            child.kill()
            child.wait()
    assert child.returncode in (0, 130), err
    assert "Traceback" not in err, err
    assert "stopped" in out
    assert wait_until(lambda: not alive(servers[0]), 5.0)
    assert all(port != p for _, p in listening_sockets())


def test_server_ends_with_its_parent():
    script = "from hipsim.viewer import Viewer; import time; v = Viewer(); print(v.server_pid, flush=True); time.sleep(60)"
    child = subprocess.Popen([sys.executable, "-c", script], cwd=REPO, stdout=subprocess.PIPE, text=True, env={**os.environ, "PYTHONPATH": str(REPO)})
    try:
        server = int(child.stdout.readline())
        assert alive(server)
    finally:
        child.kill()  # no clean-up code runs
        child.wait()
    assert wait_until(lambda: not alive(server), 5.0)
