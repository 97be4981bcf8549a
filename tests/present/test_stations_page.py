"""Two stations drawn and written (hipsim.present.stations_page): the verdict block's sentences from a summary made
sample by sample here, each platform's panel of the figure (read back from its lines), the folder written."""

from __future__ import annotations

import json

import numpy as np
import pytest

from hipsim.motion.trajectories import iso14242
from hipsim.present.stations_page import plot_station_errors, station_verdict, write_stations
from hipsim.stations.commands import StationMotion
from hipsim.stations.summary import SlidersSummary, sliders_verdict, station_summary, stations_verdict
from hipsim.stations.tolerance_summary import ToleranceSummary, tolerance_verdict

ERRORS = np.zeros((4, 2, 3))
ERRORS[:, 0, 0] = [1.0, -3.0, 2.0, 0.0]  # m_1 α: peak −3° at t = 0.5 s
ERRORS[:, 1, 2] = [0.0, 0.0, 2.0, -2.0]  # m_2 γ: peak 2°


def motion(errors_deg, desired=None, t=None, control="2") -> StationMotion:
    n = errors_deg.shape[0]
    t = np.arange(n) * 0.5 if t is None else t
    desired = np.zeros((n, 3)) if desired is None else desired
    return StationMotion(t, desired, np.zeros((n, 3)), desired[:, None, :] + np.radians(errors_deg), control)


def test_without_a_load_the_block_says_no_iso_check_and_the_largest_error():
    verdict = station_verdict(station_summary(motion(ERRORS)))
    assert (verdict.state, verdict.word) == ("open", "NO ISO CHECK")
    # RMS over both platforms and angles: √(22/24) = 0.957°
    assert verdict.lines[0] == (
        "--control 2: the largest attitude error is 3° (alpha of m_1, t = 0.5 s); RMS over both platforms and "
        "angles 0.957°."
    )


def test_each_stations_iso_verdict_follows_the_largest_error():
    iso = iso14242(rate=100.0, cycles=2)
    errors = np.zeros((len(iso.t), 2, 3))
    errors[:, 0, 1] = 4.0  # m_1 4° off on β: station 1 fails, station 2 passes
    verdict = station_verdict(station_summary(motion(errors, iso.q, iso.t), iso.Fe, "ISO", periodic=True))
    assert (verdict.state, verdict.word) == ("fail", "FAIL")
    assert verdict.lines[1] == "ISO 14242-1 (tolerances assumed): station 1 FAIL, station 2 PASS"
    assert "(beta of m_1," in verdict.lines[0]


@pytest.mark.parametrize(("control", "roles"), [("1", ("controlled", "following")), ("both", ("controlled",) * 2)])
def test_one_panel_per_platform_with_its_role_and_its_three_angles(control, roles):
    t = np.array([0.0, 0.5, 1.0, 1.5])
    fig = plot_station_errors(t, ERRORS, control)
    assert [ax.get_title(loc="left") for ax in fig.axes] == [f"platform m_{j} ({r})" for j, r in zip((1, 2), roles)]
    for j, ax in enumerate(fig.axes):
        lines = ax.get_lines()[:3]
        assert [line.get_ydata().tolist() for line in lines] == [ERRORS[:, j, k].tolist() for k in range(3)]


def test_a_tolerance_only_folder_and_the_summarys_json(tmp_path):
    """stations.json carries the verdict made beside each analysis (records.Verdict); the page renders it."""
    tolerance = ToleranceSummary(3, 1, 10, {"levers": 0.05}, ())
    files = write_stations(tmp_path / "tol", {"table": "t.csv"}, tolerance=tolerance)
    document = json.loads(files.json.read_text(encoding="utf-8"))
    assert document["verdict"] == tolerance_verdict(tolerance).to_json() and document["table"] == "t.csv"
    assert document["verdict"]["level"] == "NOT MADE" and list(document)[:2] == ["verdict", "provenance"]
    assert files.figure is None and files.index.is_file()
    page = files.index.read_text(encoding="utf-8")
    assert "– TOLERANCES</span>" in page and "<p>Manufacturing tolerances.</p>" in page
    summary = station_summary(motion(ERRORS))
    drawn = write_stations(tmp_path / "run", {}, summary)  # no times: no figure
    document = json.loads(drawn.json.read_text(encoding="utf-8"))
    assert document["summary"]["rms_error_deg"] == pytest.approx(np.sqrt(22 / 24))
    assert document["verdict"] == stations_verdict(summary).to_json()
    assert document["verdict"]["level"] == "NOT MADE" and "state" not in document["verdict"]
    assert "– NO ISO CHECK</span>" in drawn.index.read_text(encoding="utf-8")
    assert drawn.figure is None


def test_a_sliders_folder_says_its_attitudes_and_nothing_else_is_written_without_a_record(tmp_path):
    sliders = SlidersSummary("log.csv", 4, (0.5, 0.0, 0.0), (1.0, 0.0, 0.0))
    files = write_stations(tmp_path / "sl", {"table": "t.csv"}, sliders=sliders)
    document = json.loads(files.json.read_text(encoding="utf-8"))
    assert document["verdict"] == sliders_verdict(sliders).to_json()
    page = files.index.read_text(encoding="utf-8")
    assert "– ATTITUDES</span>" in page and "Both platforms&#39; attitudes from the carriages of log.csv" in page
    with pytest.raises(ValueError, match="give a run's summary"):
        write_stations(tmp_path / "none", {})
    assert not (tmp_path / "none" / "stations.json").exists()


def test_a_desired_motion_that_is_not_iso_is_said_per_station():
    iso = iso14242(rate=100.0, cycles=2)
    half = 0.5 * iso.q  # both stations track it exactly: a motion that is not the ISO waveform
    verdict = station_verdict(station_summary(motion(np.zeros((len(iso.t), 2, 3)), half, iso.t), iso.Fe, "half", True))
    said = [line for line in verdict.lines if line.startswith("Station ")]
    assert [line.split(":")[0] for line in said] == ["Station 1", "Station 2"]
    assert all("the desired motion is not the ISO 14242-1 waveform" in line for line in said)
