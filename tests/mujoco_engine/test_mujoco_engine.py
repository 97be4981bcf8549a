"""The MuJoCo engine's commands: mjcf, check --engine mujoco, simulate --plant mujoco, and each without MuJoCo.
The engine's modules have their own files: test_mjcf.py, test_model.py, test_friction.py, test_plant.py, test_trajectory.py.

Skipped when ``mujoco`` is not installed or too old (the ``test`` extra installs it).
"""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

mujoco = pytest.importorskip("mujoco")

import hipsim  # noqa: E402
from hipsim.exceptions import MissingDependencyError  # noqa: E402

try:
    import hipsim.mujoco_engine  # noqa: F401  (the engine refuses a MuJoCo too old)
except MissingDependencyError as error:  # installed, but a release the engine refuses
    pytest.skip(str(error), allow_module_level=True)

from hipsim.cli.main import main  # noqa: E402
from hipsim.mujoco_engine.mjcf import keyframe_gap  # noqa: E402


def test_mjcf_command_writes_a_model_that_loads(tmp_path, capsys):
    out = tmp_path / "machine.xml"
    assert (
        main(["mjcf", "--out", str(out), "--set", "screw.lead_mm=5", "--integrator", "Euler", "--timestep", "1"]) == 0
    )
    printed = capsys.readouterr().out
    assert f"wrote {out}" in printed and "6 connect closures" in printed and "Euler, time step 1 ms" in printed
    model = mujoco.MjModel.from_xml_path(str(out))
    assert model.actuator_gear[0, 0] == pytest.approx(2 * np.pi / 0.005, rel=1e-15)
    assert keyframe_gap(model) <= 1e-9
    assert main(["mjcf", "--out", str(tmp_path)]) == 2  # a folder
    capsys.readouterr()
    assert main(["mjcf", "--out", str(out), "--timestep", "-1"]) == 2
    assert capsys.readouterr().err.startswith(
        "hipsim: error: mjcf: --timestep -1 ms: MuJoCo's time step must be above 0"
    )


def test_check_with_mujoco_passes(capsys):
    assert main(["check", "--engine", "mujoco", "--rate", "100"]) == 0
    printed = capsys.readouterr().out
    assert "-> mujoco-analytic" in printed and "-> mujoco-pinocchio" in printed and "Fa_23_N" in printed


def test_simulate_with_the_mujoco_plant_reports_the_gap(tmp_path, capsys):
    out = tmp_path / "sim.csv"
    assert main(["simulate", "--plant", "mujoco", "--controller", "pd", "--cycles", "0.05", "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "mujoco" in printed and "closure gap" in printed and out.exists()


def test_without_mujoco_the_commands_say_how_to_install_it(tmp_path):
    # One process for the three commands (each with its own stderr): a process costs 1–2 s of imports.
    script = (
        "import contextlib, io, json, sys; sys.modules['mujoco'] = None\n"  # `import mujoco` fails as if not installed
        "from hipsim.cli.main import main\n"
        "done = []\n"
        "for args in json.loads(sys.argv[1]):\n"
        "    err = io.StringIO()\n"
        "    with contextlib.redirect_stderr(err):\n"
        "        done.append((main(args), err.getvalue()))\n"
        "print(json.dumps(done))\n"
    )
    commands = [
        ["mjcf", "--out", str(tmp_path / "m.xml")],
        ["check", "--engine", "mujoco", "--rate", "50"],
        ["simulate", "--plant", "mujoco", "--cycles", "0.01", "--out", str(tmp_path / "s.csv")],
    ]
    ran = subprocess.run(
        [sys.executable, "-c", script, json.dumps(commands)], capture_output=True, text=True, timeout=120
    )
    assert ran.returncode == 0 and not ran.stderr.strip(), ran.stderr
    results = json.loads(ran.stdout.strip().splitlines()[-1])
    assert len(results) == len(commands)
    for args, (status, err) in zip(commands, results):
        assert status == 2, args
        lines = err.strip().splitlines()
        assert len(lines) == 1 and "pip install -U 'hipsim[mujoco]'" in lines[0], (args, err)
    assert not list(tmp_path.iterdir())
