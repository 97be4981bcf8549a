"""Where scenes go: the offline page holds the scene in order; the live server listens on loopback only and ends with its parent or on Ctrl-C."""

from __future__ import annotations

import base64
import os
import re
import signal
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import numpy as np
import pytest
from support import given

from hipsim.motion.trajectories import iso14242
from hipsim.present.meshcat_output import DiscreteAnimation, OfflineWindow, offline_page
from hipsim.present.viewer import Viewer

REPO = Path(__file__).resolve().parents[2]


# ---------------------------------------------------------------------------
# Helpers
# ---------------------------------------------------------------------------


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
# The offline page
# ---------------------------------------------------------------------------


# meshcat 0.3 warns, when first imported, that pyzmq's event loop is deprecated (hipsim.present.viewer imports it quietly too).
@pytest.mark.filterwarnings("ignore:zmq.eventloop.ioloop is deprecated:DeprecationWarning")
def test_offline_page_holds_the_scene_with_the_animation_last():
    """Every command the window keeps, base64 in the page, in order: the animation after the objects it animates."""
    import meshcat
    import meshcat.geometry as mg
    import umsgpack

    window = OfflineWindow()
    vis = meshcat.Visualizer(window=window)
    vis["box"].set_object(mg.Box([0.1, 0.2, 0.3]))
    vis["box"].set_transform(np.eye(4))
    vis["gone"].set_object(mg.Sphere(0.05))
    vis["gone"].delete()  # a deleted node leaves the page
    animation = DiscreteAnimation(default_framerate=10.0)
    for k in range(3):
        T = np.eye(4)
        T[0, 3] = 0.1 * k
        with animation.at_frame(vis, k) as frame:
            frame["box"].set_transform(T)
    vis.set_animation(animation)
    vis["ball"].set_object(mg.Sphere(0.05))  # sent after the animation, still before it in the page
    html = offline_page(window.commands(), "a <title> & more", ["first line", "second <b>line</b>"])

    block = given(re.search(r"var commands = \[(.*?)\];", html, re.S)).group(1)
    encoded = re.findall(r'"([A-Za-z0-9+/=]+)"', block)
    assert encoded == [base64.b64encode(c).decode("ascii") for c in window.commands()]
    commands = [umsgpack.unpackb(base64.b64decode(e)) for e in encoded]
    assert [(c["type"], c["path"]) for c in commands] == [
        ("set_object", "/meshcat/box"),
        ("set_transform", "/meshcat/box"),
        ("set_object", "/meshcat/ball"),
        ("set_animation", ""),
    ]
    tracks = [t for entry in commands[-1]["animations"] for t in entry["clip"]["tracks"]]
    assert tracks and all(t["interpolation"] == 2300 for t in tracks)  # discrete: each frame held until the next
    assert "<title>a &lt;title&gt; &amp; more</title>" in html and "first line<br>second <b>line</b>" in html
    # meshcat's script is inlined, its own "</script" escaped: the page's scripts end where they should.
    assert html.count("</script>") == 2 and "MeshCat.Viewer" in html


# ---------------------------------------------------------------------------
# The live server
# ---------------------------------------------------------------------------


def test_live_server_listens_on_loopback_only():
    viewer = Viewer()
    try:
        pid, url = given(viewer.server_pid), given(viewer.url)
        sockets = listening_sockets(pid)
        assert len(sockets) >= 2, sockets  # ZMQ and web
        assert all(address == "127.0.0.1" for address, _ in sockets), sockets
        assert re.fullmatch(r"http://127\.0\.0\.1:\d+/static/", url)
        port = int(url.split(":")[2].split("/")[0])
        assert ("127.0.0.1", port) in sockets
        with urllib.request.urlopen(url, timeout=10) as response:
            assert response.status == 200 and b"<html" in response.read().lower()
        viewer.play(iso14242(rate=100), loop=False, fps=20)
    finally:
        viewer.close()
    assert wait_until(lambda: not alive(pid), 5.0)
    assert all(port != p for _, p in listening_sockets())


_SCRIPT = """
import sys
from hipsim.cli import main
sys.exit(main(["view", "--forces", "--singularity"]))
"""


def test_view_command_ends_cleanly_on_ctrl_c():
    child = subprocess.Popen(
        [sys.executable, "-c", _SCRIPT],
        cwd=REPO,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "PYTHONPATH": str(REPO)},
    )
    try:
        line = ""
        deadline = time.monotonic() + 30
        while "http://" not in line and time.monotonic() < deadline:
            line = given(child.stdout).readline()
            if not line and child.poll() is not None:
                break
        assert "http://127.0.0.1:" in line, (line, given(child.stderr).read() if child.poll() is not None else "")
        port = int(given(re.search(r"127\.0\.0\.1:(\d+)", line)).group(1))
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
    script = "from hipsim.present.viewer import Viewer; import time; v = Viewer(); print(v.server_pid, flush=True); time.sleep(60)"
    child = subprocess.Popen(
        [sys.executable, "-c", script],
        cwd=REPO,
        stdout=subprocess.PIPE,
        text=True,
        env={**os.environ, "PYTHONPATH": str(REPO)},
    )
    try:
        server = int(given(child.stdout).readline())
        assert alive(server)
    finally:
        child.kill()  # no clean-up code runs
        child.wait()
    assert wait_until(lambda: not alive(server), 5.0)
