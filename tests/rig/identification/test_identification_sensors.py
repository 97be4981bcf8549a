"""Identification from the logs labs have: motor currents with a torque constant, and slider encoders instead of angles."""

import numpy as np
import pytest
from rig_synthetic import fit_run, machines, write_log

from hipsim.rig import identify, load_log

TORQUE_CONSTANT = 0.36  # N·m/A, the example drive's


@pytest.fixture(scope="module")
def logs(tmp_path_factory):
    """One excitation run of the Pinocchio plant, logged as angles + torques, angles + currents, and encoders + torques."""
    folder = tmp_path_factory.mktemp("sensors")
    run = fit_run(duration=10.0)
    start, _ = machines()
    angles = write_log(folder / "angles.csv", run, np.random.default_rng(5))
    encoders = write_log(folder / "encoders.csv", run, np.random.default_rng(5), motion="encoders")
    # The same torques (same noise) as motor currents: i = τ / k_t, in A.
    text = angles.read_text().splitlines()
    header = text[0].split(",")
    rows = [line.split(",") for line in text[1:]]
    for i in (1, 2, 3):
        k = header.index(f"tau_{i}_Nmm")
        header[k] = f"current_{i}_A"
        for row in rows:
            row[k] = repr(float(row[k]) * 1e-3 / TORQUE_CONSTANT)
    currents = folder / "currents.csv"
    currents.write_text("\n".join([",".join(header)] + [",".join(row) for row in rows]) + "\n")
    return start, angles, currents, encoders


def estimates(result):
    return np.array([e.value for e in result.estimates]), np.array([e.std for e in result.estimates])


def test_currents_with_a_torque_constant_identify_as_the_torques_do(logs):
    start, angles, currents, _ = logs
    by_torque, std = estimates(identify([load_log(angles, start)], start))
    by_current, _ = estimates(identify([load_log(currents, start, torque_constant=TORQUE_CONSTANT)], start))
    # The currents hold the torques to 17 significant digits: the same fit, to a millionth of each standard deviation
    # (the parameters the consistency bounds hold at zero come out at ~1e-9, where round-off is the whole value).
    assert np.all(np.abs(by_current - by_torque) <= 1e-6 * std), np.abs(by_current - by_torque) / std


def test_encoder_logs_identify_the_same_machine_within_its_uncertainty(logs):
    start, angles, _, encoders = logs
    by_angles, std = estimates(identify([load_log(angles, start)], start))
    log = load_log(encoders, start)
    assert log.motion_from == "encoders"
    by_encoders, std_encoders = estimates(identify([log], start))
    # The motion comes from the encoders through forward kinematics instead of the attitude sensor: another
    # route to the same motion, so the estimates agree within their standard deviations.
    assert np.all(np.abs(by_encoders - by_angles) <= 3 * np.hypot(std, std_encoders) + 1e-12 * np.abs(by_angles))
