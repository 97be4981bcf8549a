"""An interrupted sweep on a local dask cluster leaves no scratch space behind (no /tmp/dask-scratch-space, no folder of its own)."""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

pytest.importorskip("distributed")

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM])
def test_an_interrupted_sweep_removes_its_dask_scratch_space(tmp_path, signum):
    temporary = tmp_path / "tmp"  # the process's temporary folder (TMPDIR), where dask would put dask-scratch-space
    temporary.mkdir()
    out = tmp_path / "s.csv"
    env = dict(os.environ, TMPDIR=str(temporary), PYTHONPATH=str(ROOT))
    command = [
        sys.executable,
        "-m",
        "hipsim",
        "sweep",
        "--workers",
        "2",
        "--rate",
        "100",
        "--grid",
        "lever.length_mm=300:360:0.01",
        "--out",
        str(out),
    ]
    process = subprocess.Popen(
        command, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, cwd=tmp_path
    )
    try:
        deadline = time.monotonic() + 120
        while not any(temporary.rglob("*.dirlock")) and process.poll() is None and time.monotonic() < deadline:
            time.sleep(0.2)  # until the workers have made their scratch folders
        assert process.poll() is None, process.communicate()[1]
        assert any(temporary.rglob("*.dirlock")), "the workers made no scratch folder under TMPDIR"
        process.send_signal(signum)
        _, err = process.communicate(timeout=60)
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()
    assert process.returncode == (130 if signum == signal.SIGINT else 143), err
    assert list(temporary.iterdir()) == [], (sorted(str(p) for p in temporary.rglob("*")), err)
