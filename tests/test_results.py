"""The CSV contract (spec §7.5), the summary, atomic writes, and the README example."""

import csv
import math
import re
from pathlib import Path

import numpy as np
import pytest
from support import given

import hipsim
from hipsim.results import column_names, rms_and_signed_peak

README = Path(__file__).resolve().parents[1] / "README.md"


def test_the_rms_and_the_signed_peak_of_an_error():
    """1, −3, 3, 2 at 0, 0.1, 0.2, 0.3 s: RMS √(23/4); the peak −3 (the first of equal magnitudes, its sign kept)."""
    t = np.array([0.0, 0.1, 0.2, 0.3])
    assert rms_and_signed_peak(t, np.array([1.0, -3.0, 3.0, 2.0])) == (math.sqrt(23 / 4), -3.0, 0.1)
    assert rms_and_signed_peak(t, np.array([1.0, 3.0, -3.0, 2.0])) == (math.sqrt(23 / 4), 3.0, 0.1)


@pytest.fixture(scope="module")
def result():
    return hipsim.analyse()


def test_columns_follow_the_contract(result):
    columns = result.columns()
    assert list(columns) == column_names()
    # Units at the edge: mm, N·mm, rpm, degrees.
    np.testing.assert_allclose(columns["L_12_mm"], result.L[:, 0, 1] * 1e3)
    np.testing.assert_allclose(columns["tau_f_3_Nmm"], result.torques.friction[:, 2] * 1e3)
    np.testing.assert_allclose(columns["speed_2_rpm"], columns["Ld_12_mm_s"] / 10.0 * 60.0)
    np.testing.assert_allclose(columns["alpha_deg"][0], 25.0)
    parts = sum(columns[f"{p}_1_Nmm"] for p in ("tau_m", "tau_l", "tau_s", "tau_L", "tau_f"))  # spec §7.5
    np.testing.assert_allclose(parts, columns["tau_1_Nmm"], atol=1e-9)


def test_csv_round_trip(result, tmp_path):
    path = result.write_csv(tmp_path / "iso.csv")
    with open(path) as stream:
        rows = list(csv.reader(stream))
    assert rows[0] == column_names()
    assert len(rows) == 1 + len(result.trajectory)
    table = np.array(rows[1:], dtype=float)
    np.testing.assert_allclose(table, np.column_stack(list(result.columns().values())), rtol=1e-11, atol=1e-11)
    assert not list(tmp_path.glob(".*part"))


def test_summary_values(result):
    summary = result.summary()
    torques = result.torques
    assert summary.sliders["12"].L_max_mm == pytest.approx(result.L[:, 0, 1].max() * 1e3)
    assert summary.sliders["23"].stroke_mm == pytest.approx(np.ptp(result.L[:, 1, 2]) * 1e3)
    motor = summary.motors["1"]
    assert motor.tau_rms_Nmm == pytest.approx(math.sqrt(np.mean((torques.total[:, 0] * 1e3) ** 2)))
    assert motor.tau_peak_Nmm >= max(getattr(motor, f"{p}_max_Nmm") for p in ("tau_m", "tau_l", "tau_s", "tau_L"))
    assert summary.cond_inv_min == pytest.approx(result.cond_inv.min())
    assert summary.cond_inv_min_t_s == pytest.approx(result.t[np.argmin(result.cond_inv)])


def test_readme_library_example_runs(tmp_path, monkeypatch):
    """The README's library example, run as written."""
    text = README.read_text()
    block = given(re.search(r"## Library\n\n```python\n(.*?)```", text, re.S)).group(1)
    monkeypatch.chdir(tmp_path)
    exec(compile(block, "README.md", "exec"), {})
    assert (tmp_path / "iso_2kHz.csv").stat().st_size > 100_000


def test_ci_runs_the_readme_test_command():
    """The README's second command is what CI runs, verbatim."""
    commands = given(re.search(r"## Two commands.*?```sh\n(.*?)```", README.read_text(), re.S)).group(1)
    lines = [line for line in commands.splitlines() if line and not line.startswith("#")]
    assert len(lines) == 2 and "hipsim torques" in lines[0] and "pytest" in lines[1]
    ci = (README.parent / ".ci" / "run").read_text()
    assert lines[1] in ci.splitlines()
