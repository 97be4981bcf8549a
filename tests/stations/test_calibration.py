"""Kinematic calibration of the two stations, checked on logs of a known per-chain machine computed by hand.

The logs come from tests/stations_synthetic.py (SciPy's rotations, the chain
equations written out, Newton on a central-difference Jacobian): another route
than hipsim.analytic.stations, which the calibration uses.
"""

from __future__ import annotations

import jsonschema
import numpy as np
import pytest
from stations_synthetic import (
    deviated,
    motion,
    reference_attitude,
    reference_carriages,
    synthetic_log,
    write_log,
)

from hipsim.analytic.stations import carriages_for_platform
from hipsim.cli.documents import schema
from hipsim.cli.main import main
from hipsim.exceptions import CalibrationError, TrajectoryError
from hipsim.machine.chains import ChainGeometry
from hipsim.machine.parameters import load_parameters
from hipsim.motion.trajectories import iso14242
from hipsim.stations import CalibrationLog, calibrate
from hipsim.stations import calibration as calibration_module
from hipsim.stations import deviations as dv
from hipsim.stations.commands import attitudes
from hipsim.stations.logs import read_calibration_log
from hipsim.stations.sensitivity import structure

NOISE_DEG = 0.05


@pytest.fixture(scope="module")
def drawing():
    return load_parameters()


@pytest.fixture(scope="module")
def truth():
    return deviated(seed=3, size_mm=0.3)


@pytest.fixture(scope="module")
def train(drawing, truth):
    t, L, _, sensors = synthetic_log(drawing, truth, 2000, seed=1, noise_deg=NOISE_DEG)
    return CalibrationLog("train", t, L, sensors)


@pytest.fixture(scope="module")
def fitted(drawing, train):
    return calibrate([train], drawing)


@pytest.fixture(scope="module")
def held_out(drawing, truth):
    """A motion not fitted: carriages and the true (noise-free) attitudes of both platforms."""
    t, L, true, _ = synthetic_log(drawing, truth, 400, seed=2, noise_deg=0.0)
    return t, L, true


def _rms_deg(x):
    return np.degrees(np.sqrt((x**2).mean(axis=0)))


def test_held_out_predictions_are_well_below_the_noise(drawing, fitted, held_out):
    t, L, true = held_out
    after = _rms_deg(attitudes(fitted.machine, L, true) - true)
    before = _rms_deg(attitudes(drawing, L, true) - true)
    assert np.all(after < NOISE_DEG / 10), after
    assert before.max() > NOISE_DEG, (
        before
    )  # the drawing predicts worse than the sensors read: a fit that did nothing fails
    assert np.allclose(np.degrees(fitted.noise), NOISE_DEG, rtol=0.1)  # the noise read back from the residuals
    assert np.all(np.degrees(fitted.residual_rms) < NOISE_DEG * 1.1)


def test_the_controlled_platform_tracks_within_the_calibrations_uncertainty(drawing, truth, fitted):
    desired = iso14242(rate=50).q
    sigma = fitted.prediction_std(np.stack([desired, desired], axis=1))
    for j in (1, 2):
        L = carriages_for_platform(fitted.machine, desired, j)
        error = reference_attitude(drawing, truth, j, L, desired) - desired
        assert np.all(np.abs(error) <= 3 * sigma[:, j - 1]), np.max(np.abs(error) / sigma[:, j - 1])
        uncalibrated = (
            reference_attitude(drawing, truth, j, carriages_for_platform(drawing, desired, j), desired) - desired
        )
        assert np.max(np.abs(uncalibrated) / sigma[:, j - 1]) > 10  # the uncalibrated command is far outside it


def test_what_no_log_can_see_is_a_real_symmetry(drawing):
    seen = structure(drawing, offsets=False)
    assert seen.rank == 45  # 42 of the chains and centres, and the stack-up's seat: its lift varies with m_2's tilt
    assert [dv.names()[k] for k in seen.independent[-3:]] == ["spline_x_1", "spline_y_1", "spline_z_1"]
    assert [dv.names()[k] for k in seen.dependent] == [f"centre_{a}_{j}" for j in (1, 2) for a in "xyz"]
    again = structure(drawing, offsets=False, seed=1)
    assert np.array_equal(again.independent, seen.independent)
    assert np.allclose(again.coefficients, seen.coefficients, atol=1e-8)
    # Moving platform 1's centre and its three U-joints by the same horizontal step changes no reading (hand route).
    d = 1e-3
    shifted = ChainGeometry.zeros().replace(
        centre=np.array([[d, 0.0, 0.0], [0.0, 0.0, 0.0]]),
        ujoint=np.array([[[d, 0.0]] * 3, [[0.0, 0.0]] * 3]),
    )
    _, q = motion(50, seed=4)
    assert np.allclose(
        reference_carriages(drawing, shifted, 1, q), reference_carriages(drawing, None, 1, q), atol=1e-14
    )
    # ... and lifting it with its three sliders too: centre_z folds into the slider offsets.
    assert seen.definitions()[-1].endswith("centre_z_2")


def test_sensor_offsets_per_log(drawing, truth):
    offsets = [[0.3, -0.2, 0.5, -0.1, 0.25, 0.4], [-0.2, 0.1, -0.3, 0.2, -0.15, 0.0]]
    logs = []
    for k, o in enumerate(offsets):
        t, L, _, sensors = synthetic_log(drawing, truth, 1000, seed=10 + k, noise_deg=NOISE_DEG, offsets_deg=o)
        logs.append(CalibrationLog(f"log{k}", t, L, sensors))
    fit = calibrate(logs, drawing, offsets=True)
    # The zero of each sensor is not known (it trades with the unseen tilt of the joint pattern), but the drift between
    # logs is, and so are the predictions up to a constant.
    drift = np.degrees(fit.offsets[0] - fit.offsets[1]).ravel()
    assert np.allclose(drift, np.subtract(offsets[0], offsets[1]), atol=0.01), drift
    t, L, true = synthetic_log(drawing, truth, 400, seed=2, noise_deg=0.0)[:3]
    difference = attitudes(fit.machine, L, true) - true
    assert np.all(_rms_deg(difference - difference.mean(axis=0)) < NOISE_DEG / 5)
    # The offsets hide nothing more than the translations: what they imitate is estimated, the trade named.
    assert fit.unseen == [f"centre_{a}_{j}" for j in (1, 2) for a in "xyz"]
    assert fit.confounded and all(c.explained >= 0.9 and c.values for c in fit.confounded)


def test_a_sensor_far_from_the_encoders_is_refused(drawing, train):
    sensors = np.array(train.sensors)
    sensors[700, 0, 1] += np.radians(10.0)
    with pytest.raises(CalibrationError, match=r"t = 1\.4 s, column 'beta_1_deg'"):
        calibrate([CalibrationLog("bad", train.t, train.carriages, sensors)], drawing)


def test_carriages_out_of_reach_are_refused(drawing, train):
    carriages = np.array(train.carriages)
    carriages[5:, 0] += 0.5
    with pytest.raises(CalibrationError, match="does not reach"):
        calibrate([CalibrationLog("far", train.t, carriages, train.sensors)], drawing)


def test_a_noise_free_log_converges_to_the_truth_in_a_few_iterations(drawing, truth, held_out, fitted):
    """Noise-free, the residuals and the posterior spread fall to round-off (~1e-14 m, below any relative step):
    the absolute floor of 0.1 nm stops the fit; its machine predicts a motion it did not see to round-off. (The
    structure is the drawing's, as ``fitted``'s: given, not found again.)"""
    t, L, true = held_out
    fit = calibrate([CalibrationLog("noise-free", t, L, true)], drawing, structure_of=fitted.structure)
    assert 3 <= fit.iterations <= 8, fit.iterations
    assert np.all(fit.noise <= 1e-11)  # the residuals' noise is at its floor (1e-12 rad), not a sensor's
    _, L2, true2, _ = synthetic_log(drawing, truth, 100, seed=5, noise_deg=0.0)
    assert np.abs(attitudes(fit.machine, L2, true2) - true2).max() < 1e-11  # rad; the drawing is off by ~1e-4


def test_a_fit_that_does_not_converge_is_refused(drawing, train, monkeypatch):
    monkeypatch.setattr(calibration_module, "MAX_ITERATIONS", 1)
    with pytest.raises(CalibrationError, match="did not converge"):
        calibrate([train], drawing)


def test_reading_a_log(tmp_path, train):
    path = write_log(tmp_path / "log.csv", train.t, train.carriages, train.sensors)
    log = read_calibration_log(path, 0.01)
    assert np.allclose(log.carriages, train.carriages, atol=1e-14)
    assert np.allclose(log.sensors, train.sensors, atol=1e-13)
    # The motor angles instead of the encoders: L = p·angle/360°.
    lines = path.read_text().splitlines()
    names = lines[0].replace("L_1", "motor_").replace("_mm", "_deg").split(",")
    rows = [[float(x) for x in line.split(",")] for line in lines[1:]]
    motor = np.array(rows)
    motor[:, 1:4] *= 1e-3 / 0.01 * 360.0
    np.savetxt(tmp_path / "motor.csv", motor, delimiter=",", header=",".join(names), comments="", fmt="%.15g")
    assert np.allclose(read_calibration_log(tmp_path / "motor.csv", 0.01).carriages, train.carriages, atol=1e-12)
    text = path.read_text().splitlines()
    header = text[0].split(",")
    keep = [k for k, name in enumerate(header) if not name.startswith(("alpha_1", "beta_1", "gamma_1"))]
    (tmp_path / "no_sensor.csv").write_text("\n".join(",".join(line.split(",")[k] for k in keep) for line in text))
    with pytest.raises(TrajectoryError, match="no attitude sensor of platform 1: missing column"):
        read_calibration_log(tmp_path / "no_sensor.csv", 0.01)
    text[4] = text[4].replace(text[4].split(",")[2], "x", 1)
    (tmp_path / "cell.csv").write_text("\n".join(text))
    with pytest.raises(TrajectoryError, match=r"line 5, column 'L_12_mm'"):
        read_calibration_log(tmp_path / "cell.csv", 0.01)


def test_calibrate_command(tmp_path, drawing, truth, train, capsys):
    train_csv = write_log(tmp_path / "train.csv", train.t, train.carriages, train.sensors)
    t, L, _, sensors = synthetic_log(drawing, truth, 300, seed=2, noise_deg=NOISE_DEG)
    held_csv = write_log(tmp_path / "held.csv", t, L, sensors)
    out = tmp_path / "calibrated.toml"
    argv = ["calibrate", "--log", str(train_csv), "--validate", str(held_csv), "--out", str(out)]
    assert main([*argv, "--summary-format", "json"]) == 0
    import json

    document = json.loads(capsys.readouterr().out)
    jsonschema.Draft202012Validator(schema("calibrate")).validate(document)  # what ``hipsim schema calibrate`` says
    assert document["self_check"]["verdict"]["level"] == "PASS" and document["out"] == str(out)
    summary = document["summary"]
    assert np.max(summary["validation"][0]["rms_deg"]) < NOISE_DEG * 1.2
    assert np.max(summary["validation"][0]["start_rms_deg"]) > NOISE_DEG * 2
    machine = load_parameters(out)
    assert machine.geometry is not None
    assert "# Calibrated by hipsim calibrate" in out.read_text()
    from hipsim.rig.identification.identified_file import read_identified_file

    found = read_identified_file(out)
    assert found is not None and found.provenance is not None and found.logs == (str(train_csv),)
    assert found.table["kind"] == "kinematic calibration"
    # Bad input: one line, status 2, nothing written.
    (tmp_path / "bad.csv").write_text("t_s,L_11_mm,L_12_mm,L_13_mm\n0,500,500,500\n0.1,500,500,500\n")
    again = tmp_path / "again.toml"
    assert main(["calibrate", "--log", str(tmp_path / "bad.csv"), "--out", str(again)]) == 2
    error = capsys.readouterr().err
    assert error.count("\n") == 1 and "attitude sensor of platform 1" in error
    assert not again.exists()


def test_a_designed_calibration_motion_is_better_posed_than_the_iso_cycle(drawing):
    from hipsim.rig.identification.excitation import Limits
    from hipsim.stations.excitation import calibration_excitation

    limits = Limits.for_machine(drawing, max_angle=np.radians(20.0))
    design = calibration_excitation(drawing, frequency=0.2, harmonics=4, limits=limits, seeds=2)
    assert design.condition_number < design.iso_condition_number / 5
    assert design.peaks.angle_deg <= 20.0 + 1e-9
    assert design.peaks.speed_mm_s <= limits.max_speed * 1e3
    assert design.peaks.cond_inv_min >= limits.min_cond_inv


def test_limits_no_calibration_motion_meets_are_an_excitation_error(drawing):
    """A singularity measure above any pose's (1.1 > 1, the isotropic pose's): no candidate passes, and the error is
    the excitation's kind, naming what to relax."""
    from hipsim.exceptions import ExcitationError
    from hipsim.rig.identification.excitation import Limits
    from hipsim.stations.excitation import calibration_excitation

    limits = Limits.for_machine(drawing, max_angle=np.radians(20.0), min_cond_inv=1.1)
    with pytest.raises(ExcitationError, match="no calibration motion within the limits: relax --max-angle"):
        calibration_excitation(drawing, frequency=0.2, harmonics=2, limits=limits, seeds=1)
