"""Where a meshcat scene goes: a live server on the loopback interface, or one offline HTML page.

:class:`hipsim.present.viewer.Viewer` draws through a meshcat Visualizer whose window
is one of these: an :class:`OfflineWindow` keeps the scene tree a server
would keep, with no server; a :class:`LiveWindow` sends every command over
ZMQ to a :class:`Server`; a :class:`TeeWindow` does both, so that a live
viewer can also write its page.

The live server (meshcat's ZMQ and web servers) runs in a child process and
listens on the loopback interface only; it ends with :meth:`Server.close`
or when this process ends, however it ends. The offline page
(:func:`offline_page`) is built here from the scene, without a server:
three.js and the meshcat viewer inlined, every mesh and the recorded
animation (a :func:`DiscreteAnimation`, each frame held until the next) as
data in the page, nothing fetched from the network. Append ``#t=0.25`` to
the page's address to open it paused at 0.25 s of the animation.
:func:`hipsim.present.browser.screenshot` renders such a page in headless
Chromium (tests, docs).

meshcat is imported on first use, not with this module.
"""

from __future__ import annotations

import base64
import os
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path
from typing import Any

from ..exceptions import HipsimError

__all__ = [
    "DiscreteAnimation",
    "LiveWindow",
    "OfflineWindow",
    "Server",
    "TeeWindow",
    "offline_page",
]

# The meshcat server, run as a child process: meshcat's own ZMQ/web bridge, with
# its web server bound to 127.0.0.1 (meshcat binds it to every interface and
# uses host only in the URL) and its ZMQ socket on tcp://127.0.0.1. It exits
# when its standard input closes, i.e. when the parent goes away, however.
# It is code run with ``python -c``, not a module of hipsim: the child imports
# meshcat only, so it needs neither hipsim on its sys.path nor this file's place.
_SERVER_CODE = r"""
import os, sys, threading
from meshcat.servers import zmqserver

class LoopbackBridge(zmqserver.ZMQWebSocketBridge):
    def make_app(self):
        app = super().make_app()
        listen = app.listen
        def listen_on_loopback(port, **kwargs):
            kwargs["address"] = "127.0.0.1"
            return listen(port, **kwargs)
        app.listen = listen_on_loopback
        return app

def watch_parent():
    try:
        while sys.stdin.buffer.read(65536):
            pass
    finally:
        os._exit(0)

threading.Thread(target=watch_parent, daemon=True).start()
bridge = LoopbackBridge(host="127.0.0.1")
print("zmq_url=" + bridge.zmq_url, flush=True)
print("web_url=" + bridge.web_url, flush=True)
try:
    bridge.run()
except KeyboardInterrupt:
    pass
"""


# ---------------------------------------------------------------------------
# Windows: where meshcat commands go
# ---------------------------------------------------------------------------


class OfflineWindow:
    """A meshcat window without a server: keeps the scene tree the server would keep, to write a page."""

    def __init__(self):
        from meshcat.servers.tree import SceneTree

        self.tree = SceneTree()
        self.web_url = None
        self.server_proc = None

    def send(self, command) -> None:
        import umsgpack
        from meshcat.servers.tree import SceneTree, find_node

        data = command.lower()
        kind = data["type"]
        path = [p for p in data.get("path", "").split("/") if p]
        packed = umsgpack.packb(data)
        if kind == "delete":
            if path:
                parent = find_node(self.tree, path[:-1])
                parent.pop(path[-1], None)
            else:
                self.tree = SceneTree()
            return
        node = find_node(self.tree, path)
        if kind == "set_object":
            node.object, node.properties = packed, []
        elif kind == "set_transform":
            node.transform = packed
        elif kind == "set_property":
            node.properties.append(packed)
        elif kind == "set_animation":
            node.animation = packed

    def commands(self) -> list[bytes]:
        """The scene as meshcat commands: objects, properties, transforms, then the animations.

        Animations go last so that they bind to the objects they animate.
        """
        from meshcat.servers.tree import walk

        out, animations = [], []
        for node in walk(self.tree):
            if node.object is not None:
                out.append(node.object)
            out.extend(node.properties)
            if node.transform is not None:
                out.append(node.transform)
            if node.animation is not None:
                animations.append(node.animation)
        return out + animations

    def close(self) -> None:
        pass


class LiveWindow:
    """A meshcat window talking to a meshcat server over ZMQ (meshcat's ViewerWindow, without its prints)."""

    def __init__(self, zmq_url: str, web_url: str, timeout_s: float = 30.0):
        import zmq

        self.zmq_url, self.web_url, self.server_proc = zmq_url, web_url, None
        self.context: Any = zmq.Context.instance()
        self.socket = self.context.socket(zmq.REQ)
        self.socket.setsockopt(zmq.LINGER, 0)
        self.socket.setsockopt(zmq.RCVTIMEO, int(timeout_s * 1000))
        self.socket.setsockopt(zmq.SNDTIMEO, int(timeout_s * 1000))
        self.socket.connect(zmq_url)
        # ZMQ sockets must not be used from two threads at once: one request at a time.
        self._lock = threading.Lock()

    def send(self, command) -> None:
        import umsgpack
        import zmq

        data = command.lower()
        frames = [data["type"].encode("utf-8"), data["path"].encode("utf-8"), umsgpack.packb(data)]
        with self._lock:
            if self.socket is None:
                raise HipsimError("the viewer is closed")
            try:
                self.socket.send_multipart(frames)
                self.socket.recv()
            except zmq.Again:
                raise HipsimError(f"the meshcat server at {self.zmq_url} does not answer") from None

    def close(self) -> None:
        with self._lock:
            if self.socket is not None:
                self.socket.close(linger=0)
                self.socket = None


class TeeWindow:
    """Sends every command to the live server and keeps the same scene offline (for :meth:`hipsim.present.viewer.Viewer.record`)."""

    def __init__(self, live: LiveWindow, offline: OfflineWindow):
        self.live, self.offline = live, offline
        self.web_url, self.server_proc = live.web_url, None

    def send(self, command) -> None:
        self.offline.send(command)
        self.live.send(command)

    def close(self) -> None:
        self.live.close()


class Server:
    """A meshcat server in a child process, on 127.0.0.1; ended by :meth:`close` or when this process ends."""

    def __init__(self, timeout_s: float = 30.0):
        self._log = tempfile.TemporaryFile()
        env = dict(os.environ, PYTHONUNBUFFERED="1")
        self.process = subprocess.Popen(
            [sys.executable, "-u", "-c", _SERVER_CODE],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=self._log,
            env=env,
            start_new_session=True,  # Ctrl-C in a terminal reaches this process, which then ends the server
        )
        zmq_url: str | None = None
        web_url: str | None = None
        lines = []
        deadline = time.monotonic() + timeout_s
        stdout = self.process.stdout
        assert stdout is not None  # stdout=PIPE
        while zmq_url is None or web_url is None:  # the server prints zmq_url first
            line = stdout.readline().decode("utf-8", "replace").strip()
            if not line:
                if self.process.poll() is not None or time.monotonic() > deadline:
                    self.close()
                    self._log.seek(0)
                    detail = self._log.read().decode("utf-8", "replace").strip().splitlines()[-3:]
                    raise HipsimError("the meshcat server did not start: " + (" / ".join(detail) or "no output"))
                continue
            lines.append(line)
            if line.startswith("zmq_url="):
                zmq_url = line.split("=", 1)[1]
            elif line.startswith("web_url="):
                web_url = line.split("=", 1)[1]
        self.zmq_url, self.web_url = zmq_url, web_url

    @property
    def pid(self) -> int:
        return self.process.pid

    def close(self) -> None:
        if self.process.poll() is None:
            self.process.terminate()
            try:
                self.process.wait(timeout=5)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
        for stream in (self.process.stdin, self.process.stdout):
            if stream is not None:
                stream.close()
        self._log.close()


# ---------------------------------------------------------------------------
# The offline page
# ---------------------------------------------------------------------------


def _discrete_animation_class():
    from meshcat.animation import Animation

    class DiscreteAnimation(Animation):
        """meshcat's Animation with step interpolation: each key holds until the next (three.js InterpolateDiscrete)."""

        def lower(self):
            lowered = super().lower()
            for entry in lowered:
                for track in entry["clip"]["tracks"]:
                    track["interpolation"] = 2300  # THREE.InterpolateDiscrete
            return lowered

    return DiscreteAnimation


def DiscreteAnimation(default_framerate: float):
    """A meshcat Animation whose keys hold until the next one (the class is made on first use, so that importing this module does not import meshcat)."""
    return _discrete_animation_class()(default_framerate=default_framerate)


_PAGE = """<!DOCTYPE html>
<html>
<head>
<meta charset="utf-8">
<title>{title}</title>
<style>
  body {{ margin: 0; }}
  #meshcat-pane {{ width: 100vw; height: 100vh; overflow: hidden; }}
  #hipsim-legend {{ position: absolute; left: 10px; bottom: 10px; max-width: 60vw; padding: 6px 10px;
    font: 13px/1.4 sans-serif; color: #222; background: rgba(255, 255, 255, 0.8); border-radius: 4px; }}
</style>
</head>
<body>
<div id="meshcat-pane"></div>
<div id="hipsim-legend">{legend}</div>
<script>
{viewer_js}
</script>
<script>
var viewer = new MeshCat.Viewer(document.getElementById("meshcat-pane"));
(function () {{
  // The scene, in order: objects, properties, transforms, then the animation.
  var commands = [
{commands}
  ];
  for (var k = 0; k < commands.length; k++) {{
    var text = atob(commands[k]);
    var bytes = new Uint8Array(text.length);
    for (var i = 0; i < text.length; i++) bytes[i] = text.charCodeAt(i);
    viewer.handle_command_bytearray(bytes);
  }}
}})();
// Open paused at a time of the animation: page.html#t=0.25 (seconds).
function hipsimSeek() {{
  var match = /[#&]t=([-+0-9.eE]+)/.exec(window.location.hash);
  if (!match) return;
  var time = parseFloat(match[1]);
  var animator = viewer.animator;
  animator.pause();
  animator.seek(time);
  animator.display_progress(time);
  document.title = "{title} (t = " + time + " s)";
}}
hipsimSeek();
window.addEventListener("hashchange", hipsimSeek);
</script>
</body>
</html>
"""


def offline_page(commands: list[bytes], title: str, legend: list[str]) -> str:
    """A self-contained page: meshcat's viewer script inlined and the scene's commands as base64 data."""
    import html

    import meshcat

    viewer_js = (Path(meshcat.__file__).parent / "viewer" / "dist" / "main.min.js").read_text(encoding="utf-8")
    encoded = ",\n".join(f'"{base64.b64encode(c).decode("ascii")}"' for c in commands)
    return _PAGE.format(
        title=html.escape(title),
        legend="<br>".join(legend),
        viewer_js=viewer_js.replace("</script", "<\\/script"),
        commands=encoded,
    )
