"""``hipsim urdf``: the URDF of the published machine is the one shipped in models/, the messages go where the
output does not (standard error when a file is written to standard output), and --closures may not be --out."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
import yaml

import hipsim
from hipsim.cli.main import main

MODELS = Path(hipsim.__file__).resolve().parent.parent / "models"


def same(a: Any, b: Any) -> bool:
    """Two parsed YAML documents equal, numbers to 1e-12 (the shipped file writes 54.91e-6 by hand)."""
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() == b.keys() and all(same(a[k], b[k]) for k in a)
    if isinstance(a, list) and isinstance(b, list):
        return len(a) == len(b) and all(same(x, y) for x, y in zip(a, b))
    if isinstance(a, float) or isinstance(b, float):
        return bool(a == pytest.approx(b, rel=1e-12))
    return bool(a == b)


def test_the_published_urdf_is_the_shipped_one(tmp_path, capsys):
    out, closures = tmp_path / "m.urdf", tmp_path / "m.yaml"
    assert main(["urdf", "--out", str(out), "--closures", str(closures)]) == 0
    assert out.read_text() == (MODELS / "hip_simulator.urdf").read_text()
    written, shipped = (yaml.safe_load(path.read_text()) for path in (closures, MODELS / "hip_simulator.yaml"))
    assert same(written, shipped)
    assert capsys.readouterr().out == f"wrote {out}\nwrote {closures}\n"


def test_a_urdf_on_standard_output_sends_the_messages_to_standard_error(capsys):
    assert main(["urdf", "--out", "-"]) == 0
    captured = capsys.readouterr()
    assert captured.out == (MODELS / "hip_simulator.urdf").read_text()
    assert captured.err.startswith("wrote ")


def test_the_closure_file_cannot_be_the_urdf(tmp_path, capsys):
    out = tmp_path / "m.urdf"
    assert main(["urdf", "--out", str(out), "--closures", str(out)]) == 2
    assert "--closures" in capsys.readouterr().err
    assert not out.exists()  # nothing written
