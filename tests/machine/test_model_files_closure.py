"""The closure file of a parameter set (hipsim.machine.model_files.closure_text) and `hipsim urdf --closures`."""

from __future__ import annotations

import math

import numpy as np
import pytest
import yaml

from hipsim import load_parameters
from hipsim.cli.main import main
from hipsim.closed_chain.build import load_closed_chain
from hipsim.machine.model_files import closure_file_path, closure_text, urdf_text, write_closures


@pytest.mark.parametrize(("lead_mm", "inertia_kgmm2"), [(10.0, 54.91), (5.0, 80.0), (16.0, 0.001), (2.5, 1e-5)])
def test_transmission_follows_the_parameters(lead_mm, inertia_kgmm2):
    params = load_parameters(overrides={"screw.lead_mm": lead_mm, "screw.inertia_kgmm2": inertia_kgmm2})
    content = yaml.safe_load(closure_text(params))
    shipped = yaml.safe_load(closure_file_path().read_text(encoding="utf-8"))
    for key in ("closed_loop", "type", "name_mot"):
        assert content[key] == shipped[key]
    for joint in content["name_mot"]:
        entry = content["transmission"][joint]
        # Read back by YAML as numbers (PyYAML needs "1.0e-08", not "1e-08"), exactly the parameter set's.
        assert isinstance(entry["lead_m"], float) and isinstance(entry["rotor_inertia_kgm2"], float)
        assert entry["lead_m"] == params.lead
        assert entry["rotor_inertia_kgm2"] == params.screw_inertia


def test_urdf_and_closure_file_alone_make_the_machine(tmp_path):
    """A loader given only the two files (no hipsim parameters) gets the changed lead and rotor inertia."""
    params = load_parameters(overrides={"screw.lead_mm": 5.0, "screw.inertia_kgmm2": 80.0})
    path = write_closures(params, tmp_path / "machine.yaml")
    chain = load_closed_chain(urdf_text(params), path, gravity=params.gravity)
    assert chain.lead == pytest.approx(0.005, rel=1e-15)
    np.testing.assert_allclose(chain.model.armature[chain.actuated_v], 80e-6 * (2 * math.pi / 0.005) ** 2, rtol=1e-14)
    assert chain.n_closures == 6


def test_urdf_command_writes_the_closure_file(tmp_path, capsys):
    urdf, closures = tmp_path / "m.urdf", tmp_path / "m.yaml"
    assert main(["urdf", "--out", str(urdf), "--closures", str(closures), "--set", "screw.lead_mm=5"]) == 0
    assert f"wrote {closures}" in capsys.readouterr().out
    assert yaml.safe_load(closures.read_text())["transmission"]["slider_2"]["lead_m"] == 0.005
    assert main(["urdf", "--out", str(urdf), "--closures", str(urdf)]) == 2
    assert "--closures" in capsys.readouterr().err
