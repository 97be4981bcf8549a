"""The model against synthetic rig logs made by the Pinocchio plant; the log loader's checks; the compare command."""

import json
from dataclasses import asdict

import numpy as np
import pytest
from rig_synthetic import iso_run, machines, write_log
from support import given

from hipsim.cli.main import main
from hipsim.exceptions import TrajectoryError
from hipsim.results import Torques
from hipsim.rig import compare_torques, load_log
from hipsim.rig.compare import detect_period


@pytest.fixture(scope="module")
def iso_log(tmp_path_factory):
    """The ISO cycle on the plant of the true machine, logged with noise, angles and encoders both."""
    path = tmp_path_factory.mktemp("logs") / "iso.csv"
    return write_log(path, iso_run(), np.random.default_rng(11), motion="both")


def test_the_true_machine_explains_the_log(iso_log):
    start, true = machines()
    log = load_log(iso_log, start)
    assert log.motion_from == "encoders" and any("attitude sensor agrees" in note for note in log.notes)
    right, wrong = compare_torques(true, log), compare_torques(start, log)
    for i, entry in right.motor_errors().items():
        # Noise (3 N·mm, 0.003°) and the sticking at reversals are all that is left.
        assert entry["relative_rms_error_away_from_reversals"] < 0.006
        assert entry["relative_rms_error"] < 0.012
        assert wrong.motor_errors()[i]["relative_rms_error"] > 10 * entry["relative_rms_error"]
    parts = sum(right.model[part] for part in Torques.PARTS)
    np.testing.assert_allclose(parts, right.model["total"], rtol=0, atol=1e-12)


def test_the_period_and_phases(iso_log):
    start, _ = machines()
    comparison = compare_torques(start, load_log(iso_log, start))
    assert comparison.period == pytest.approx(1.0, abs=2e-3)
    assert given(comparison.phase_rms).shape == (10, 3) and np.all(given(comparison.phase_rms) > 0)
    assert compare_torques(start, load_log(iso_log, start), period=0).phase_rms is None
    t = np.arange(2000) / 1000.0
    assert detect_period(t, np.column_stack([t, t**2, np.sin(t)])) is None  # not a repeating motion


def test_disagreeing_motion_forms_are_refused(tmp_path):
    start, _ = machines()
    run = iso_run()
    path = write_log(tmp_path / "both.csv", run, np.random.default_rng(1), motion="both")
    lines = path.read_text().splitlines()
    header = lines[0].split(",")
    column = header.index("beta_deg")
    for k in range(1500, len(lines)):  # the attitude sensor slips by 2° from line 1501 on
        cells = lines[k].split(",")
        cells[column] = str(float(cells[column]) + 2.0)
        lines[k] = ",".join(cells)
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(TrajectoryError) as error:
        load_log(path, start)
    text = str(error.value)
    assert "\n" not in text
    assert "line 1501, column 'beta_deg': the attitude sensor and the encoders disagree by 2" in text
    assert load_log(path, start, tolerance_deg=3.0).motion_from == "encoders"


def test_encoders_out_of_reach_name_the_line(tmp_path):
    start, _ = machines()
    path = write_log(tmp_path / "enc.csv", iso_run(), np.random.default_rng(1), motion="encoders")
    lines = path.read_text().splitlines()
    column = lines[0].split(",").index("L_12_mm")
    cells = lines[801].split(",")
    cells[column] = "1500"
    lines[801] = ",".join(cells)
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(
        TrajectoryError, match=r"enc\.csv, line 802: encoder heights L_11_mm … at t = 0\.8 s: no platform orientation"
    ):
        load_log(path, start)


def test_compare_command_writes_the_folder(iso_log, tmp_path, capsys):
    out = tmp_path / "cmp"
    assert main(["compare", "--log", str(iso_log), "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "RMS error" in printed and "M3" in printed and "repeats every" in printed
    for name in (
        "index.html",
        "comparison.json",
        "torques.png",
        "torques.svg",
        "errors.png",
        "phases.png",
        "parts.svg",
    ):
        assert (out / name).is_file(), name
    summary = json.loads((out / "comparison.json").read_text())
    assert set(summary["motors"]) == {"1", "2", "3"} and summary["period_s"] == pytest.approx(1.0, abs=2e-3)
    page = (out / "index.html").read_text()
    assert "data:image/png;base64," in page and "iso.csv" in page


def test_compare_command_bad_log_leaves_nothing(tmp_path, capsys):
    bad = tmp_path / "bad.csv"
    bad.write_text(
        "t_s,Fe_N,alpha_deg,beta_deg,gamma_deg\n" + "\n".join(f"{k / 1000},500,1,2,3" for k in range(500)) + "\n"
    )
    out = tmp_path / "cmp"
    assert main(["compare", "--log", str(bad), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "missing torque columns" in err
    assert not out.exists()
    short = tmp_path / "short.csv"
    short.write_text(
        "t_s,Fe_N,tau_1_Nmm,tau_2_Nmm,tau_3_Nmm,alpha_deg,beta_deg,gamma_deg\n"
        + "\n".join(f"{k / 1000},500,1,2,3,1,2,3" for k in range(100))
        + "\n"
    )
    assert main(["compare", "--log", str(short), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "too short to filter" in err
    assert not out.exists()
    currents = tmp_path / "currents.csv"
    currents.write_text(
        "t_s,Fe_N,current_1_A,current_2_A,current_3_A,alpha_deg,beta_deg,gamma_deg\n"
        + "\n".join(f"{k / 1000},500,1,2,3,1,2,3" for k in range(1000))
        + "\n"
    )
    assert main(["compare", "--log", str(currents), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "no torque constant" in err
    assert not out.exists()


# --- A log in pieces ---------------------------------------------------------------------------

from hipsim.rig.compare import compare_log  # noqa: E402
from hipsim.rig.logs.log import LogPieces  # noqa: E402

#: Pieces give the whole log's values up to round-off: the filters start in another state and the
#: forward kinematics' Newton from another pose, and their last digits differ; relative to the measured torque.
ROUND_OFF = 1e-11


def assert_same_statistics(whole, parts):
    a, b = asdict(whole.summary()), asdict(parts.summary())  # the records' fields, NaN and infinities kept
    assert a["samples"] == b["samples"] and a["period_s"] == pytest.approx(b["period_s"], rel=1e-12)
    for i in "123":
        scale = a["motors"][i]["measured_rms_Nmm"]
        for key, value in a["motors"][i].items():
            other = b["motors"][i][key]
            if key.startswith("relative"):
                assert other == pytest.approx(value, rel=1e-9), (i, key)
            elif key == "peak_error_t_s":
                assert other == value, (i, key)  # the same sample
            elif key == "share_near_reversals":
                assert other == value, (i, key)  # the same samples, counted
            elif key == "model_parts_rms_Nmm":
                for part, rms in value.items():
                    assert abs(other[part] - rms) <= ROUND_OFF * scale, (i, part)
            else:
                assert abs(other - value) <= ROUND_OFF * scale, (i, key, value, other)
    np.testing.assert_allclose(parts.phase_rms, whole.phase_rms, rtol=0, atol=ROUND_OFF * 0.2)
    assert b["cond_inv_min"] == pytest.approx(a["cond_inv_min"], rel=1e-12)


@pytest.mark.parametrize("piece", [777, 1300])  # pieces that cut the 1 s cycle anywhere, shorter than their halo
def test_a_log_in_pieces_gives_the_whole_logs_comparison(iso_log, piece):
    """The statistics of a log compared in pieces against the whole log's, computed by the one-piece route."""
    start, true = machines()
    whole = compare_torques(true, load_log(iso_log, start))
    with LogPieces(iso_log, start, piece=piece) as pieces:
        assert pieces.halo > piece and len(pieces) > 3 * piece  # every piece needs its neighbours
        parts = compare_log(true, pieces)
        same = compare_log(true, pieces, period=whole.period)
    assert_same_statistics(whole, parts)
    assert_same_statistics(whole, same)
    # The figures' samples are the usable samples themselves, fewer when asked.
    np.testing.assert_array_equal(parts.t, whole.t)
    with LogPieces(iso_log, start, piece=piece) as pieces:
        few = compare_log(true, pieces, figure_samples=500)
    assert 400 < few.t.size <= 500 and np.all(np.isin(few.t, whole.t))


def test_one_piece_is_the_whole_log_to_the_last_digit(iso_log):
    start, true = machines()
    whole = compare_torques(true, load_log(iso_log, start))
    with LogPieces(iso_log, start, piece=10**6) as pieces:
        one = compare_log(true, pieces)
    assert one.summary() == whole.summary()


def test_a_log_in_pieces_without_a_filter(tmp_path):
    """Unfiltered, from the attitude sensor (from the encoders, the forward kinematics' round-off, differentiated
    twice at 1 kHz, would be all the difference there is)."""
    start, true = machines()
    path = write_log(tmp_path / "angles.csv", iso_run(), np.random.default_rng(5), motion="angles")
    whole = compare_torques(true, load_log(path, start, cutoff=None))
    with LogPieces(path, start, cutoff=None, piece=900) as pieces:
        assert_same_statistics(whole, compare_log(true, pieces))


# The peak memory of a log in pieces against one four times shorter is measured in scripts/bench.py's rig section
# (bench_compare_memory): tracemalloc slows every allocation, and a measurement is not a law.
