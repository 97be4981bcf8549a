"""Rig logs as the acquisition writes them (issue 47 point 7): the same data written as CSV, as LabVIEW TDMS (npTDMS's
writer) and as HDF5 (h5py's writer) give the same results, bit for bit, in every command that reads a rig log; other
layouts through --columns; units from the channels' properties; bad files one line, exit 2, nothing written.

The data are a snapshot of the analytic model's ISO cycle with rig noise (tests/monitor_synthetic.py), written as CSV
with 10 significant digits; the TDMS and HDF5 files hold those numbers as Python's float() reads them from the CSV.
"""

from __future__ import annotations

import hashlib
import json
import sys
from contextlib import closing
from pathlib import Path

import numpy as np
import pytest
from monitor_synthetic import write_identified, write_snapshot

import hipsim
from hipsim.channels import parse_channel_map, read_channels
from hipsim.cli.main import main
from hipsim.exceptions import MissingDependencyError, TrajectoryError
from hipsim.rig.logs.reader import RigLogFile
from hipsim.stations.logs import read_calibration_log, read_carriage_log

h5py = pytest.importorskip("h5py")
nptdms = pytest.importorskip("nptdms")


def _csv(path: Path) -> tuple[list[str], np.ndarray]:
    """A plain CSV's header and values, each cell read by float(): the numbers the other files are written with."""
    lines = [line for line in path.read_text(encoding="utf-8").splitlines() if line and not line.startswith("#")]
    return lines[0].split(","), np.array([[float(cell) for cell in line.split(",")] for line in lines[1:]])


def write_tdms(path: Path, names, values, group: str = "log", properties=None) -> Path:
    """One group, a channel a column (``properties``: per channel name, its properties)."""
    from nptdms import ChannelObject, GroupObject, TdmsWriter

    with TdmsWriter(str(path)) as writer:
        channels = [
            ChannelObject(group, name, np.ascontiguousarray(values[:, k]), properties=(properties or {}).get(name, {}))
            for k, name in enumerate(names)
        ]
        writer.write_segment([GroupObject(group), *channels])
    return path


def write_hdf5(path: Path, names, values, group: str | None = "log", table: bool = False) -> Path:
    """A dataset a column in ``group`` (None: the root), or one (N, C) dataset with its names in 'columns'."""
    with h5py.File(path, "w") as file:
        where = file if group is None else file.create_group(group)
        if table:
            where.create_dataset("table", data=values).attrs["columns"] = list(names)
        else:
            for k, name in enumerate(names):
                where.create_dataset(name, data=np.ascontiguousarray(values[:, k]))
    return path


@pytest.fixture(scope="module")
def logs(tmp_path_factory):
    """The snapshot as CSV, TDMS, HDF5 (a group of datasets), HDF5 (one table at the root)."""
    folder = tmp_path_factory.mktemp("channels")
    rng = np.random.default_rng(3)
    csv = write_snapshot(folder / "log.csv", hipsim.load_parameters(), 0.1, 2_000_000, rng, cycles=2, rate=200.0)
    names, values = _csv(csv)
    return {
        "csv": csv,
        "tdms": write_tdms(folder / "log.tdms", names, values),
        "hdf5": write_hdf5(folder / "log.h5", names, values),
        "table": write_hdf5(folder / "table.hdf5", names, values, group=None, table=True),
        "names": names,
        "values": values,
    }


FORMATS = ("tdms", "hdf5", "table")


@pytest.mark.parametrize("kind", FORMATS)
def test_the_reader_gives_the_csv_s_samples_bit_for_bit(logs, kind):
    with (
        closing(RigLogFile(logs["csv"], keep=("cycle",))) as csv_log,
        closing(RigLogFile(logs[kind], keep=("cycle",))) as other,
    ):
        a, b = csv_log.read(), other.read()
        for name in ("t", "Fe", "tau", "angles"):
            np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
        np.testing.assert_array_equal(csv_log.kept["cycle"], other.kept["cycle"])
        assert b.lines[0] == 1 and b.lines[-1] == len(b)  # a channel file's "lines": its samples' numbers
        assert other.size == Path(logs[kind]).stat().st_size and len(other.sha256) == 64


def _strip(document):
    """A JSON document without what names the input file (its name, path, hash, size, lines)."""
    if isinstance(document, dict):
        return {
            k: _strip(v)
            for k, v in document.items()
            if k not in {"log", "source", "path", "file", "sha256", "bytes", "provenance", "name", "line", "lines"}
        }
    if isinstance(document, list):
        return [_strip(v) for v in document]
    if isinstance(document, str) and ("log." in document or "table.hdf5" in document):
        return "<file>"
    return document


def test_compare_gives_the_same_results(logs, tmp_path, capsys, quick_figures):
    # The comparison (the path compare takes: the log read in pieces) and the command's JSON on one channel file.
    from hipsim.rig.compare import compare_torques
    from hipsim.rig.logs import LogPieces

    params = hipsim.load_parameters()
    results = {}
    for kind in ("csv", *FORMATS):
        with LogPieces(logs[kind], params) as log:
            results[kind] = _strip(compare_torques(params, log).summary().to_json())
    for kind in FORMATS:
        assert results[kind] == results["csv"], kind
    out = tmp_path / "out"
    assert main(["compare", "--log", str(logs["tdms"]), "--out", str(out), "--summary-format", "json"]) == 0
    capsys.readouterr()
    document = json.loads((out / "comparison.json").read_text(encoding="utf-8"))
    assert document["motors"]["1"]["rms_error_Nmm"] == results["csv"]["motors"]["1"]["rms_error_Nmm"]


def test_monitor_gives_the_same_table(logs, tmp_path, capsys):
    params = write_identified(tmp_path / "identified.toml")
    tables = {}
    for kind in ("csv", *FORMATS):
        out = tmp_path / f"{kind}.csv"
        main(["monitor", "--params", str(params), "--log", str(logs[kind]), "--settle", "0", "--out", str(out)])
        capsys.readouterr()
        from hipsim.rig.monitoring.monitor_table import read_table

        table = read_table(out)
        assert len(table["cycle"]) == 1 and np.isfinite(table["load_friction_mm"][0])
        tables[kind] = {k: v for k, v in table.items() if k not in ("file", "bytes", "sha256")}
    for kind in FORMATS:
        assert json.dumps(tables[kind]) == json.dumps(tables["csv"]), kind  # NaN included, every digit


@pytest.mark.parametrize("command", [["iso-check", "--summary-format", "json", "--trajectory"]])
def test_iso_check_reads_them_as_rig_logs(logs, capsys, command, tmp_path, monkeypatch, quick_figures):
    monkeypatch.chdir(tmp_path)  # its page goes to ./hipsim_iso_check
    outputs = {}
    for kind in ("csv", "tdms"):  # the HDF5 path is the same from the reader on
        status = main([*command, str(logs[kind])])
        outputs[kind] = (status, _strip(json.loads(capsys.readouterr().out)))
    assert outputs["tdms"] == outputs["csv"]


def test_identify_fits_the_same_machine(logs):
    from hipsim.rig import identify, load_log

    start = hipsim.load_parameters()
    fits = {kind: identify([load_log(logs[kind], start)], start) for kind in ("csv", "tdms", "hdf5")}
    for kind in ("tdms", "hdf5"):
        assert [q.value for q in fits[kind].quantities] == [q.value for q in fits["csv"].quantities]
        assert fits[kind].residual_rms.tolist() == fits["csv"].residual_rms.tolist()


# --------------------------------------------------------------------------- other layouts and units


def test_other_layouts_through_the_column_map(logs, tmp_path):
    names, values = logs["names"], logs["values"]
    # Two groups, the channels under the lab's own names: named one by one.
    from nptdms import ChannelObject, GroupObject, TdmsWriter

    path = tmp_path / "two.tdms"
    own = {name: f"ch{k}" for k, name in enumerate(names)}
    with TdmsWriter(str(path)) as writer:
        writer.write_segment(
            [GroupObject("Rig"), GroupObject("Other"), ChannelObject("Other", "x", np.zeros(3))]
            + [ChannelObject("Rig", own[name], np.ascontiguousarray(values[:, k])) for k, name in enumerate(names)]
        )
    with pytest.raises(TrajectoryError, match=r"has 2 groups of channels \('Other', 'Rig'\): name the channels"):
        RigLogFile(path)
    mapping = ",".join(f"{name}=Rig/{own[name]}" for name in names)
    with closing(RigLogFile(path, columns=mapping)) as mapped, closing(RigLogFile(logs["csv"])) as csv_log:
        np.testing.assert_array_equal(mapped.read().tau, csv_log.read().tau)
    # A group read by its names: the same as the file's one group.
    write_tdms(tmp_path / "named.tdms", names, values, group="Rig")
    assert read_channels(tmp_path / "named.tdms", "Rig").names == tuple(names)
    # An HDF5 table's column by its index.
    table = read_channels(logs["table"], f"t_s=table[{names.index('t_s')}],Fe_N=table[{names.index('Fe_N')}]")
    assert table.names == ("t_s", "Fe_N") and table.values[1, 0] == values[1, names.index("t_s")]


def test_units_from_the_channels_properties(tmp_path):
    # Named without units, units in unit_string as LabVIEW writes them: the column names and SI-file units follow.
    values = np.array([[0.0, 1.5, 0.25, 2.0], [0.001, 2.5, -0.5, 3.0]])
    units = {"t": "s", "Fe": "kN", "tau_1": "N·m", "alpha": "°"}
    path = write_tdms(
        tmp_path / "u.tdms", list(units), values, properties={k: {"unit_string": v} for k, v in units.items()}
    )
    table = read_channels(path)
    assert table.names == ("t_s", "Fe_N", "tau_1_Nmm", "alpha_deg")
    np.testing.assert_array_equal(table.values, values * [1.0, 1e3, 1e3, 1.0])
    # A name that states another unit than its channel's is refused, naming both.
    path = write_tdms(
        tmp_path / "c.tdms", ["tau_1_Nmm"], values[:, :1], properties={"tau_1_Nmm": {"unit_string": "N·m"}}
    )
    with pytest.raises(TrajectoryError, match=r"column 'tau_1_Nmm'.*its unit is 'N·m', its name says Nmm"):
        read_channels(path, error=TrajectoryError)
    # Named by the map with its unit: converted to it.
    assert read_channels(path, "tau_1_Nmm=log/tau_1_Nmm").values[1, 0] == 1.0  # 0.001 N·m
    # A waveform's time.
    from nptdms import ChannelObject, GroupObject, TdmsWriter

    path = tmp_path / "w.tdms"
    timing = {"wf_increment": 0.001, "wf_start_offset": 2.0}
    with TdmsWriter(str(path)) as writer:
        writer.write_segment([GroupObject("log"), ChannelObject("log", "Fe_N", np.ones(4), properties=timing)])
    np.testing.assert_array_equal(read_channels(path).values[:, 1], 2.0 + np.arange(4) * 0.001)


def test_the_column_map_s_syntax():
    assert parse_channel_map("t_s=Time/t, Fe_N=Load/Fz ,Rig") == ({"t_s": "Time/t", "Fe_N": "Load/Fz"}, ("Rig",))
    for bad in ("t_s=", "=a/b", "a=b/c,a=d/e"):
        with pytest.raises(ValueError, match="NAME=GROUP/CHANNEL|named twice"):
            parse_channel_map(bad)


# --------------------------------------------------------------------------- bad input


def _bad(argv, capsys, out: Path) -> str:
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("hipsim: error: ")
    assert not out.exists()
    return err[0]


def test_bad_channel_files_one_line_exit_2_nothing_written(logs, tmp_path, capsys):
    out = tmp_path / "out"
    names, values = logs["names"], logs["values"]

    def compare(path, *more):
        return _bad(["compare", "--log", str(path), "--out", str(out), *more], capsys, out)

    # A TDMS file without the named channel: named, with the group's channels.
    err = compare(logs["tdms"], "--columns", "log,Fe_N=log/Fz")
    assert "no channel 'log/Fz' for column 'Fe_N' (group 'log' has " in err and "log.tdms" in err
    # A CSV named .tdms, a text named .h5.
    fake = tmp_path / "fake.tdms"
    fake.write_bytes(logs["csv"].read_bytes())
    assert "not a TDMS file" in compare(fake)
    fake = tmp_path / "fake.h5"
    fake.write_text("t_s,Fe_N\n")
    assert "not an HDF5 file" in compare(fake)
    # An HDF5 dataset of the wrong shape.
    bad = write_hdf5(tmp_path / "shape.h5", names, values)
    with h5py.File(bad, "a") as file:
        file["log"].create_dataset("extra", data=np.zeros((len(values), 3)))
    assert "dataset 'log/extra' has shape" in compare(bad) and "attribute 'columns'" in compare(bad)
    # Named by the map, its columns read by index (the map names only what it reads).
    assert read_channels(bad, "Fe_N=log/extra[1]").values.shape == (len(values), 1)
    # Channels of different lengths.
    short = write_tdms(tmp_path / "short.tdms", ["t_s"], values[:, :1])
    with h5py.File(write_hdf5(tmp_path / "ragged.h5", names, values), "a") as file:
        del file["log/Fe_N"]
        file["log"].create_dataset("Fe_N", data=values[:-1, names.index("Fe_N")])
    assert "has" in compare(tmp_path / "ragged.h5") and "a table's channels are one length" in compare(
        tmp_path / "ragged.h5"
    )
    assert "missing load column 'Fe_N'" in compare(short)
    # A channel file that is no rig log, where a trajectory would do.
    angles = write_tdms(tmp_path / "angles.tdms", ["t_s", "alpha_deg"], values[:, :2])
    assert "has no torques or currents" in _bad(["iso-check", "--trajectory", str(angles)], capsys, out)
    # A column map on a CSV.
    assert "applies to TDMS and HDF5 logs" in compare(logs["csv"], "--columns", "Fe_N=log/Fz")


def test_without_the_extra_one_line_names_it(logs, monkeypatch):
    monkeypatch.setitem(sys.modules, "nptdms", None)
    with pytest.raises(MissingDependencyError, match=r"pip install -U 'hipsim\[tdms\]'"):
        read_channels(logs["tdms"])
    monkeypatch.setitem(sys.modules, "h5py", None)
    with pytest.raises(MissingDependencyError, match=r"pip install -U 'hipsim\[hdf5\]'"):
        read_channels(logs["hdf5"])


def test_calibration_and_carriage_logs(tmp_path):
    rng = np.random.default_rng(1)
    names = [
        "t_s",
        "L_11_mm",
        "L_12_mm",
        "L_13_mm",
        *(f"{a}_{j}_deg" for j in (1, 2) for a in ("alpha", "beta", "gamma")),
    ]
    values = np.round(np.column_stack([np.arange(20) * 0.01, rng.normal(size=(20, 9))]), 9)
    csv = tmp_path / "cal.csv"
    csv.write_text(",".join(names) + "\n" + "".join(",".join(repr(float(v)) for v in row) + "\n" for row in values))
    lead = 0.01
    a = read_calibration_log(csv, lead)
    for path in (write_tdms(tmp_path / "cal.tdms", names, values), write_hdf5(tmp_path / "cal.h5", names, values)):
        b = read_calibration_log(path, lead)
        for name in ("t", "carriages", "sensors"):
            np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
        t, carriages = read_carriage_log(path, lead)  # stations --sliders
        np.testing.assert_array_equal(t, a.t)
        np.testing.assert_array_equal(carriages, a.carriages)


def test_a_long_channel_log_in_windows(tmp_path):
    # Three cycles at 50 Hz in one log, cut into windows of one cycle: the same windows and estimates from the TDMS
    # file (its windows by sample numbers, each window's SHA-256 that of its rows' values) as from the CSV.
    from monitor_synthetic import write_exact

    from hipsim.rig.monitoring.monitor_run import monitor
    from hipsim.rig.monitoring.snapshots import find_snapshots

    csv = write_exact(tmp_path / "long.csv", cycles=3, first_cycle=100)
    names, values = _csv(csv)
    tdms = write_tdms(tmp_path / "long.tdms", names, values)
    (a, _), (b, _) = find_snapshots(csv, window=1), find_snapshots(tdms, window=1)
    assert [(s.first_cycle, s.last_cycle) for s in a] == [(s.first_cycle, s.last_cycle) for s in b]
    spans = [s.lines for s in a]
    assert all(span is not None for span in spans)
    assert [s.lines for s in b] == [(s[0] - 1, s[1] - 1) for s in spans if s is not None]  # the CSV's header: line 1
    rows = b[1].lines
    assert rows is not None
    assert b[1].sha256 == hashlib.sha256(values[rows[0] - 1 : rows[1] - 1].tobytes()).hexdigest()
    one, two = (
        monitor(hipsim.load_parameters(), path, baseline=(100, 102), window=1, baseline_min=2, cutoff=None)
        for path in (csv, tdms)
    )
    for name in ("cycle", "samples", "load_friction_mm", "load_friction_mm_std", "residual_rms_Nmm"):
        assert list(one[name]) == list(two[name]), name


def test_wear_gives_the_same_table(logs, tmp_path, capsys):
    tables = []
    for kind in ("csv", "tdms"):
        out = tmp_path / f"{kind}.csv"
        assert main(["wear", "--trajectory", str(logs[kind]), "--grid", "10x20", "--out", str(out)]) == 0
        tables.append(out.read_bytes())
    capsys.readouterr()
    assert tables[0] == tables[1]  # byte for byte
