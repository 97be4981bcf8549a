"""Runs in pieces: the same CSV and summary as one piece, trajectory sources, Parquet in and out, atomic streamed output."""

import math
import sys

import numpy as np
import pyarrow.parquet as pq
import pytest
from support import given

import hipsim
from hipsim.analysis.crosscheck import compare_models
from hipsim.analysis.streaming import stream_run
from hipsim.cli.main import main
from hipsim.exceptions import MissingDependencyError, OutputError, PoseError, TrajectoryError
from hipsim.files import ColumnWriter, check_output
from hipsim.motion.readers import read_trajectory
from hipsim.motion.sources import CycleSource, FileSource, SampledSource
from hipsim.motion.trajectories import Trajectory
from hipsim.results import ExactSum
from hipsim.tables import csv_rows


@pytest.fixture(scope="module")
def params():
    return hipsim.load_parameters()


def streamed(params, source, chunk, **options):
    pieces: list = []
    summary = stream_run(params, source, chunk=chunk, write=pieces.append, **options)
    return "".join(csv_rows(piece) for piece in pieces), summary, pieces


def write_cycle_csv(path, rate=200, cycles=1.0, closed=True):
    """The ISO cycle's angles and load as a CSV file (the last row repeating the first when ``closed``: a periodic file)."""
    trajectory = hipsim.iso14242(rate=rate, cycles=cycles)
    n = len(trajectory) + (1 if closed else 0)
    t = np.arange(n) / rate
    q = np.degrees(np.vstack([trajectory.q, trajectory.q[:1]]) if closed else trajectory.q)
    load = np.append(trajectory.Fe, trajectory.Fe[0]) if closed else trajectory.Fe
    rows = "".join(f"{t[k]:.6f},{q[k, 0]:.15g},{q[k, 1]:.15g},{q[k, 2]:.15g},{load[k]:.15g}\n" for k in range(n))
    path.write_text("t_s,alpha_deg,beta_deg,gamma_deg,Fe_N\n" + rows)
    return path


@pytest.mark.parametrize("chunk", [97, 250, 10_000])
def test_analytic_pieces_give_the_one_piece_csv_and_summary_to_the_last_digit(params, chunk):
    one = hipsim.analyse(params, hipsim.iso14242(rate=500, cycles=1.3))  # 650 samples: pieces cut mid-cycle
    text, summary, pieces = streamed(params, CycleSource(rate=500, cycles=1.3), chunk)
    assert len(pieces) == math.ceil(650 / chunk)
    assert text == csv_rows(one.columns())
    assert summary == one.summary()


@pytest.mark.parametrize("chunk", [1, 2, 77])
def test_pinocchio_pieces_give_the_one_piece_columns_and_summary_to_the_last_digit(params, chunk):
    """The closure solver's state goes on from piece to piece (pieces of one and two samples included)."""
    trajectory = hipsim.iso14242(rate=300, cycles=1 if chunk > 2 else 0.2)
    one = hipsim.analyse(params, trajectory, model="pinocchio")
    source = CycleSource(rate=300) if chunk > 2 else CycleSource(rate=300, cycles=0.2)
    _, summary, pieces = streamed(params, source, chunk, model="pinocchio")
    columns = {name: np.concatenate([p[name] for p in pieces]) for name in pieces[0]}
    assert list(columns) == list(one.columns())
    for name, values in one.columns().items():
        np.testing.assert_array_equal(columns[name], values, err_msg=name)
    assert summary == one.summary()


def test_pinocchio_pieces_out_of_order_are_refused(params):
    from hipsim.analysis.streaming import PieceRunner

    source = CycleSource(rate=100)
    runner = PieceRunner(params, source, "pinocchio")
    runner.run(0, source.piece(0, 10))
    with pytest.raises(hipsim.HipsimError, match="in time order"):
        runner.run(20, source.piece(20, 30))


@pytest.mark.parametrize("closed", [True, False])
def test_file_pieces_share_one_spline_with_the_whole_file(params, tmp_path, closed):
    path = write_cycle_csv(tmp_path / "gait.csv", closed=closed)
    whole = read_trajectory(path)
    assert whole.periodic == closed
    source = FileSource.read(path)
    assert len(source) == len(whole) and source.periodic == closed
    for start, stop in ((0, 13), (13, 101), (101, len(whole))):
        piece = source.piece(start, stop)
        for name in ("t", "q", "qd", "qdd", "Fe", "lines"):
            np.testing.assert_array_equal(getattr(piece, name), getattr(whole, name)[start:stop], err_msg=name)
    text, summary, _ = streamed(params, source, 37)
    one = hipsim.analyse(params, whole)
    assert text == csv_rows(one.columns()) and summary == one.summary()


def test_resampled_file_pieces_equal_the_resampled_trajectory(tmp_path):
    path = write_cycle_csv(tmp_path / "gait.csv", closed=True)
    whole = read_trajectory(path, resample=333.0)
    source = FileSource.read(path, resample=333.0)
    joined = [source.piece(a, min(a + 50, len(source))) for a in range(0, len(source), 50)]
    for name in ("t", "q", "qd", "qdd", "Fe"):
        np.testing.assert_array_equal(np.concatenate([getattr(p, name) for p in joined]), getattr(whole, name))


def test_a_bad_file_gives_the_readers_error(tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text(
        "t_s,alpha_deg,beta_deg,gamma_deg\n" + "".join(f"{k / 100},0,0,{'x' if k == 4 else 0}\n" for k in range(8))
    )
    with pytest.raises(TrajectoryError) as whole:
        read_trajectory(bad)
    with pytest.raises(TrajectoryError) as piecewise:
        FileSource.read(bad)
    assert str(piecewise.value) == str(whole.value) and "line 6" in str(whole.value)


def test_a_crossing_at_a_piece_boundary_is_caught_as_in_one_piece(params):
    """δ = 5°: between γ = −7.3° and −4.1° the motion steps over the singularity at γ = −5° (tests/analytic/test_inverse_kinematics.py)."""
    machine = params.replace(home_offset=np.radians(5.0))
    gamma = np.radians([-9.7, -7.3, -4.1, -1.9])
    coarse = Trajectory(
        np.arange(4) * 0.1,
        np.column_stack([np.zeros(4), np.zeros(4), gamma]),
        np.zeros((4, 3)),
        np.zeros((4, 3)),
        np.zeros(4),
    )
    with pytest.raises(PoseError, match="passes through a singular pose") as error:
        stream_run(machine, coarse, chunk=2)  # the crossing is the first sample of the second piece
    assert error.value.index == 2 and error.value.time == pytest.approx(0.2)
    text, summary, pieces = streamed(machine, SampledSource(coarse), 2, on_error="flag")
    one = hipsim.analyse(machine, coarse, on_error="flag")
    assert text == csv_rows(one.columns()) and summary == one.summary()
    assert [p["flagged"].tolist() for p in pieces] == [[0.0, 0.0], [1.0, 0.0]]


def test_a_pose_error_names_the_sample_of_the_whole_run(params):
    far = Trajectory(
        np.arange(8) * 0.01,
        np.radians([[0, 0, g] for g in (0, 0, 0, 0, 0, 180, 0, 0)]),
        np.zeros((8, 3)),
        np.zeros((8, 3)),
        np.zeros(8),
    )
    for model in ("analytic", "pinocchio"):
        with pytest.raises(PoseError) as error:
            stream_run(params, far, model=model, chunk=3)
        assert error.value.index == 5 and error.value.time == pytest.approx(0.05)


def test_check_in_pieces_gives_the_one_piece_differences(params):
    trajectory = hipsim.iso14242(rate=200)
    one, pieces = compare_models(params, trajectory, chunk=10_000), compare_models(params, trajectory, chunk=33)
    for a, b in zip(one, pieces):
        assert a.name == b.name and a.required == b.required
        for (name, absolute, relative), (name_b, absolute_b, relative_b) in zip(a.rows, b.rows):
            assert name == name_b
            # Differences between two models of ~1e-14 of the peak: the pieces' Pinocchio runs move them by as much.
            assert absolute_b == pytest.approx(absolute, rel=0.5, abs=1e-10) and relative_b < 1e-8 or not b.required


def test_exact_sum_does_not_depend_on_the_pieces():
    rng = np.random.default_rng(3)
    values = rng.standard_normal((5000, 2)) * np.exp(rng.uniform(-30, 30, (5000, 2)))
    whole, pieces = ExactSum(2), ExactSum(2)
    whole.add(values)
    for start in range(0, 5000, 333):
        pieces.add(values[start : start + 333])
    expected = [math.fsum(values[:, c]) for c in range(2)]  # correctly rounded, by another route
    assert whole.total().tolist() == expected == pieces.total().tolist()


def test_column_writer_is_atomic(tmp_path):
    path = tmp_path / "run.csv"
    path.write_text("old\n")

    def interrupted():
        with ColumnWriter(path) as writer:
            writer.write({"a_s": np.arange(3.0)})
            raise RuntimeError("interrupted")

    with pytest.raises(RuntimeError, match="interrupted"):
        interrupted()
    assert path.read_text() == "old\n" and not list(tmp_path.glob(".*part"))
    with ColumnWriter(path) as writer:
        writer.write({"a_s": np.arange(2.0), "b_N": np.array([0.5, np.nan])})
        writer.write({"a_s": np.array([2.0]), "b_N": np.array([1e-13])})
        writer.close()
    assert path.read_text() == "a_s,b_N\n0,0.5\n1,nan\n2,1e-13\n"


def test_parquet_writer_is_atomic_and_keeps_the_pieces_in_order(tmp_path, monkeypatch):
    path = tmp_path / "run.parquet"
    monkeypatch.setattr(ColumnWriter, "ROW_GROUP", 200)  # pieces of 70 rows gathered three at a time

    def interrupted():
        with ColumnWriter(path, {"note": "x"}) as writer:
            writer.write({"a_s": np.arange(3.0)})
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        interrupted()
    assert not path.exists() and not list(tmp_path.glob(".*part"))
    with ColumnWriter(path, {"note": "x"}) as writer:
        for start in range(0, 1000, 70):
            writer.write({"a_s": np.arange(start, min(start + 70, 1000), dtype=float)})
        writer.close()
    parquet = pq.ParquetFile(path)
    assert [parquet.metadata.row_group(k).num_rows for k in range(parquet.metadata.num_row_groups)] == [
        210,
        210,
        210,
        210,
        160,
    ]
    assert parquet.schema_arrow.metadata[b"note"] == b"x"
    np.testing.assert_array_equal(parquet.read().column("a_s").to_numpy(), np.arange(1000.0))


@pytest.mark.parametrize(
    ("bad", "reason"), [("missing/x.csv", "does not exist"), (".", "is a folder"), ("/dev/null", "not a regular file")]
)
def test_outputs_are_checked_before_the_work(tmp_path, monkeypatch, capsys, bad, reason):
    import hipsim.analysis.streaming as streaming

    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(streaming, "stream_run", lambda *a, **k: pytest.fail("ran before the output was checked"))
    assert main(["torques", "--out", bad]) == 2
    assert reason in capsys.readouterr().err
    with pytest.raises(OutputError):
        check_output(bad)


def test_parquet_out_has_the_csv_columns_and_the_parameters(tmp_path, capsys):
    csv_path, parquet_path = tmp_path / "run.csv", tmp_path / "run.parquet"
    assert main(["torques", "--rate", "200", "--set", "lever.length_mm=330", "--out", str(csv_path)]) == 0
    assert main(["torques", "--rate", "200", "--set", "lever.length_mm=330", "--out", str(parquet_path)]) == 0
    table = pq.read_table(parquet_path)
    reference = np.genfromtxt(csv_path, delimiter=",", names=True)
    header = csv_path.read_text().splitlines()[0].split(",")
    assert table.column_names == header
    for name in header:
        np.testing.assert_allclose(table.column(name).to_numpy(), reference[name], rtol=1e-11, atol=1e-9)
    metadata = {k.decode(): v.decode() for k, v in table.schema.metadata.items()}
    assert metadata["hipsim.version"] == hipsim.__version__
    assert "length_mm = 330.0" in metadata["hipsim.parameters"]
    assert not list(tmp_path.glob(".*part"))


def test_parquet_trajectory_reads_as_the_csv(tmp_path):
    import pyarrow as pa

    csv_path = write_cycle_csv(tmp_path / "gait.csv", closed=True)
    data = np.genfromtxt(csv_path, delimiter=",", names=True)
    table = pa.table({name: data[name] for name in given(data.dtype.names)})
    pq.write_table(table, tmp_path / "gait.parquet")
    a, b = read_trajectory(csv_path), read_trajectory(tmp_path / "gait.parquet")
    assert b.periodic and len(a) == len(b)
    for name in ("t", "q", "qd", "qdd", "Fe"):
        np.testing.assert_allclose(getattr(b, name), getattr(a, name), rtol=0, atol=1e-9)
    pq.write_table(table.drop(["gamma_deg"]), tmp_path / "short.parquet")
    with pytest.raises(TrajectoryError, match="missing angle column 'gamma_deg'"):
        read_trajectory(tmp_path / "short.parquet")
    with pytest.raises(TrajectoryError, match="no such trajectory file"):
        read_trajectory(tmp_path / "none.parquet")


def test_run_to_dataframe(params, monkeypatch):
    run = hipsim.analyse(params, hipsim.iso14242(rate=100))
    frame = run.to_dataframe()
    assert list(frame.columns) == list(run.columns()) and len(frame) == 100
    np.testing.assert_array_equal(frame["tau_1_Nmm"].to_numpy(), run.torques.total[:, 0] * 1e3)
    monkeypatch.setitem(sys.modules, "pandas", None)  # as if not installed
    with pytest.raises(MissingDependencyError, match=r"pip install -U 'hipsim\[pandas\]'"):
        run.to_dataframe()


# --------------------------------------------------------------------------- scripts: JSON summaries, exit codes, version


def test_version(capsys):
    with pytest.raises(SystemExit) as done:
        main(["--version"])
    assert done.value.code == 0 and capsys.readouterr().out.strip() == f"hipsim {hipsim.__version__}"


def test_check_summary_as_json(capsys):
    import json

    assert main(["check", "--rate", "100", "--summary-format", "json"]) == 0
    document = json.loads(capsys.readouterr().out)
    assert document["agree"] is True and document["samples"] == 100
    assert [c["name"] for c in document["comparisons"]] == ["exact", "published", "published+spin"]
    spin = document["comparisons"][2]
    assert spin["required"] and spin["worst"] <= document["tolerance"]
    assert {row["column"] for row in spin["columns"]} >= {"tau_1_Nmm", "L_11_mm", "cond_inv"}
    import jsonschema

    from hipsim.cli.documents import schema

    jsonschema.validate(document, schema("check"))  # the published contract (hipsim schema check)


@pytest.mark.usefixtures(
    "quick_figures"
)  # exit statuses and text: the figures are drawn in tests/present/test_report.py
def test_report_exits_1_and_says_so_when_the_drive_fails(tmp_path, capsys):
    """A motor rated far below the machine's torques (30 N·mm continuous against ~200 N·mm RMS) fails its check."""
    import json

    weak = tmp_path / "weak.toml"
    weak.write_text('[motor]\nname = "too small"\ns1_torque_Nmm = 30\npeak_torque_Nmm = 60\nmax_speed_rpm = 6000\n')
    common = ["report", "--rate", "100", "--engine", "analytic", "--motor", str(weak)]
    assert main([*common, "--out", str(tmp_path / "r1")]) == 1
    captured = capsys.readouterr()
    assert "rating check: FAIL: " in captured.out and "checks of too small pass" in captured.out
    assert "exit status 1" in captured.err
    assert (tmp_path / "r1" / "index.html").exists()  # the report is written all the same
    assert main([*common, "--out", str(tmp_path / "r2"), "--summary-format", "json"]) == 1
    document = json.loads(capsys.readouterr().out)
    import jsonschema

    from hipsim.cli.documents import schema

    jsonschema.validate(document, schema("report"))  # the published contract (hipsim schema report)
    assert (
        document["verdict"]["level"] == "FAIL"
        and document["sizing"]["passed"] is False
        and document["motors"]["1"]["tau_rms_Nmm"] > 30
    )
    strong = tmp_path / "strong.toml"
    strong.write_text('[motor]\nname = "big"\ns1_torque_Nmm = 5000\npeak_torque_Nmm = 9000\nmax_speed_rpm = 6000\n')
    assert (
        main(["report", "--rate", "100", "--engine", "analytic", "--motor", str(strong), "--out", str(tmp_path / "r3")])
        == 0
    )


def test_the_version_is_the_packages_own():
    """hipsim.__version__ (in every Parquet file and `hipsim --version`) is the one pyproject.toml declares."""
    import tomllib
    from pathlib import Path

    declared = tomllib.loads((Path(__file__).parents[2] / "pyproject.toml").read_text())["project"]["version"]
    assert hipsim.__version__ == declared
