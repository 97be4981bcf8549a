"""A log's sensors against the prediction from its carriages, with the calibration's uncertainty; Fig. 7 (issue 44.6)."""

import json
import math

import numpy as np
import pytest
from stations_synthetic import deviated, synthetic_log, write_log

import hipsim
from hipsim.analytic.stations import platform_attitude
from hipsim.cli.main import main
from hipsim.machine.chains import ChainGeometry
from hipsim.present.fig7 import Curve, plot_fig7
from hipsim.stations.logs import read_desired
from hipsim.stations.sensor_check import compare_sensors, prediction_std


@pytest.fixture(scope="module")
def drawing():
    return hipsim.load_parameters()


def test_differences_by_hand(drawing):
    """m_1's α measured 0.1°, 0.3°, −0.2° above predicted: RMS √(0.14/3), mean 0.0667, peak 0.3 at t = 1 ms."""
    t = np.array([0.0, 0.001, 0.002])
    predicted = np.zeros((3, 2, 3))
    measured = predicted.copy()
    measured[:, 0, 0] = np.radians([0.1, 0.3, -0.2])
    c = compare_sensors(drawing, t, predicted, measured)
    e = c.entry(1, "alpha")
    assert (e.rms_deg, e.mean_deg, e.peak_deg, e.peak_at_s) == pytest.approx((math.sqrt(0.14 / 3), 0.2 / 3, 0.3, 0.001))
    assert c.entry(2, "gamma").rms_deg == 0.0 and e.prediction_std_deg is None
    assert c.to_json()["entries"][0]["prediction_std_deg"] is None and c.uncertainty == "none"


def test_prediction_std_is_the_sensitivity_times_the_deviation(drawing):
    """One value uncertain (lever 12, σ = 0.1 mm): the spread is |∂q/∂δ|·σ, against moving that lever by σ."""
    q = np.radians([[10.0, 4.0, -6.0]])
    L = hipsim.analytic.stations.carriages_for_platform(drawing, q, 1)
    sigma = np.zeros(len(ChainGeometry.names()))
    k = ChainGeometry.names().index("lever_12")
    sigma[k] = 1e-4
    spread = prediction_std(drawing, np.repeat(q[:, None], 2, axis=1), np.diag(sigma**2))[0, 0]
    moved = drawing.replace(geometry=ChainGeometry.from_vector(sigma))
    shifted = platform_attitude(moved, L, 1, q0=q[0])[0]
    assert spread == pytest.approx(np.abs(shifted - q[0]), rel=2e-3)
    assert spread.max() > 1e-6


def test_fig7_panels_in_the_papers_order_share_one_axis():
    t = np.linspace(0, 1, 11)
    fig = plot_fig7(t, [Curve("m_1", np.zeros((11, 3))), Curve("m_2", np.ones((11, 3)))])
    axes = fig.axes
    assert [ax.get_title(loc="left").split()[0] for ax in axes] == ["AA", "IER", "FE"]
    assert axes[0].get_shared_y_axes().joined(axes[0], axes[2])
    assert len(axes[1].lines) == 2


def test_stations_sliders_with_sensors(drawing, tmp_path, capsys):
    g = deviated(seed=2, size_mm=0.2)
    t, L, true, sensors = synthetic_log(drawing, g, 60, seed=4, noise_deg=0.0)
    log = write_log(tmp_path / "log.csv", t, L, sensors)
    out = tmp_path / "out"
    assert main(["stations", "--sliders", str(log), "--out", str(out), "--summary-format", "json"]) == 0
    document = json.loads(capsys.readouterr().out)
    entries = document["sensors"]["entries"]
    # The drawing predicts; the log is the built machine's: measured − predicted is the machine's deviation.
    predicted = np.stack([platform_attitude(drawing, L, j, q0=true[0, 0]) for j in (1, 2)], axis=1)
    expected = np.sqrt(np.mean(np.degrees(true - predicted) ** 2, axis=0)).ravel()
    assert [e["rms_deg"] for e in entries] == pytest.approx(expected, rel=1e-6)
    assert (out / "fig7.png").exists() and (out / "fig7.svg").exists()
    assert read_desired(log) is None  # a calibration log has no desired motion; a simulated run has


def test_the_desired_motion_of_a_simulated_run(tmp_path):
    log = tmp_path / "run.csv"
    log.write_text("t_s,alpha_des_deg,beta_des_deg,gamma_des_deg\n0,1,2,3\n0.001,4,5,6\n")
    desired = read_desired(log)
    assert desired is not None
    assert np.degrees(desired) == pytest.approx(np.array([[1, 2, 3], [4, 5, 6]]))


def test_a_log_with_half_the_sensors_is_refused(drawing, tmp_path, capsys):
    t, L, _, sensors = synthetic_log(drawing, None, 10, seed=1)
    log = tmp_path / "half.csv"
    names = ["t_s", "L_11_mm", "L_12_mm", "L_13_mm", "alpha_1_deg", "beta_1_deg", "gamma_1_deg"]
    values = np.column_stack([t, L * 1e3, np.degrees(sensors[:, 0])])
    np.savetxt(log, values, delimiter=",", header=",".join(names), comments="", fmt="%.12g")
    assert main(["stations", "--sliders", str(log), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert "attitude sensor of platform 2: missing column(s) alpha_2_deg, beta_2_deg, gamma_2_deg" in err
    assert not (tmp_path / "out").exists()


def test_the_calibrations_covariance_carries_its_correlations(drawing):
    """Levers 12 and 13 anticorrelated (σ = 0.1 mm each, ρ = −1): the spread is |J₁₂ − J₁₃|·σ, not √(J₁₂² + J₁₃²)·σ."""
    from hipsim.stations.sensitivity import attitude_jacobian
    from hipsim.stations.sensor_check import calibration_covariance

    record = {
        "kind": "kinematic calibration",
        "estimated": ["lever_12", "lever_13"],
        "covariance_mm2": [[0.01, -0.01], [-0.01, 0.01]],
        "std_mm": [0.0] * len(ChainGeometry.names()),
    }
    covariance = calibration_covariance(record)
    assert covariance is not None
    q = np.repeat(np.radians([[10.0, 4.0, -6.0]])[:, None], 2, axis=1)
    names = ChainGeometry.names()
    J = attitude_jacobian(drawing, q)[0, 0]
    a, b = J[:, names.index("lever_12")], J[:, names.index("lever_13")]
    assert prediction_std(drawing, q, covariance)[0, 0] == pytest.approx(np.abs(a - b) * 1e-4, rel=1e-9)
    old = calibration_covariance(
        {"kind": "kinematic calibration", "std_mm": [0.1 if n in ("lever_12", "lever_13") else 0.0 for n in names]}
    )
    assert old is not None
    assert prediction_std(drawing, q, old)[0, 0] == pytest.approx(np.hypot(a, b) * 1e-4, rel=1e-9)
    assert calibration_covariance({"kind": "dynamic identification"}) is None
