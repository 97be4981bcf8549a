"""Long fields in every table reader of hipsim.tables' rules: a 200 kB cell, a 12,000-column header, a 300 MB header line.

Each is one line naming the file and line (and column), no traceback; the
300 MB line is refused before it is read: under 20 MB read from the file and 100 MB of memory
(counted, not timed, so the check does not depend on the machine's speed).
"""

import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from hipsim.cli.main import main

ROOT = Path(__file__).resolve().parents[1]
CELL = "1" * 200_000  # beyond the csv module's 128 KiB field size limit
HEADER = ",".join(f"c{k}" for k in range(12_000))


def trajectory_with(cell: str) -> str:
    rows = [f"{k / 100},0,0,0" for k in range(20)]
    rows[4] = f"0.04,{cell},0,0"
    return "t_s,alpha_deg,beta_deg,gamma_deg\n" + "\n".join(rows) + "\n"


#: reader → (the command reading it from FILE, writing OUT; the file's text with a 200 kB cell; the line and column named)
READERS = {
    "trajectory": (
        ["torques", "--trajectory", "FILE", "--out", "OUT"],
        trajectory_with(CELL),
        "line 6, column 'alpha_deg'",
    ),
    "variants": (
        ["sweep", "--variants", "FILE", "--workers", "1", "--rate", "100", "--out", "OUT"],
        f"lever.length_mm\n330\n{CELL}\n",
        "line 3, column 'lever.length_mm'",
    ),
    "catalogue": (
        ["size", "--catalogue", "FILE", "--summary-format", "json"],
        f"name,s1_torque_Nm,peak_torque_Nm\nm1,1,2\n{'x' * 200_000},1,2\n",
        "line 3, column 'name'",
    ),
}


def run(tmp_path, capsys, reader: str, text: str):
    path, out = tmp_path / f"{reader}.csv", tmp_path / "out.csv"
    path.write_text(text)
    code = main([{"FILE": str(path), "OUT": str(out)}.get(arg, arg) for arg in READERS[reader][0]])
    captured = capsys.readouterr()
    return code, captured.err, out, captured.out


@pytest.mark.parametrize("reader", READERS)
def test_a_200_kB_cell_is_read_and_refused_on_one_line_naming_line_and_column(tmp_path, capsys, reader):
    code, err, out, printed = run(tmp_path, capsys, reader, READERS[reader][1])
    assert code == 2 and err.count("\n") == 1 and "Traceback" not in err and not printed
    assert READERS[reader][2] in err and len(err) < 400, err
    assert "(200,000 characters)" in err or "200,000 characters;" in err
    assert not out.exists()


@pytest.mark.parametrize("reader", READERS)
def test_a_12000_column_header_is_one_line_naming_the_first_column(tmp_path, capsys, reader):
    code, err, out, printed = run(tmp_path, capsys, reader, HEADER + "\n" + ",".join(["0"] * 12_000) + "\n")
    assert code == 2 and err.count("\n") == 1 and "Traceback" not in err and len(err) < 1500
    assert "line 1" in err and "'c0'" in err
    assert not out.exists() and not printed


#: Reads the file with one reader in a fresh process, printing (MB read from files, peak MB of Python allocations, the
#: error's message). "At once" is measured in bytes read (Linux's /proc/self/io ``rchar``), not in seconds: reading
#: the whole 300 MB would take a fast machine a fraction of a second and a busy one several, but it is 300 MB on both.
PROBE = textwrap.dedent("""
    import sys, tracemalloc
    from hipsim.exceptions import HipsimError
    reader, path = sys.argv[1], sys.argv[2]
    if reader == "trajectory":
        from hipsim.motion.csv_table import load_trajectory_csv as read
    elif reader == "variants":
        from hipsim.design.variants import read_variants as read
    else:
        from hipsim.machine.drive_catalogues import load_motor_catalogue as read

    def bytes_read():
        with open("/proc/self/io") as io:
            return next(int(line.split()[1]) for line in io if line.startswith("rchar:"))

    tracemalloc.start()
    start = bytes_read()
    try:
        read(path)
        message = "read"
    except HipsimError as error:
        message = str(error)
    megabytes_read = (bytes_read() - start) / 1e6
    print(megabytes_read, tracemalloc.get_traced_memory()[1] / 1e6, message, sep="\\n")
""")


@pytest.mark.parametrize("reader", READERS)
def test_a_300_MB_header_line_is_refused_at_once_in_bounded_memory(tmp_path, reader):
    path = tmp_path / "huge.csv"
    with path.open("wb") as stream:  # a header that never ends: its name cells, then a hole of 300 MB (sparse: no disk)
        stream.write(b"t_s,alpha_deg,beta_deg,gamma_deg," + b"c," * 1000)
        stream.truncate(300_000_000)
    done = subprocess.run(
        [sys.executable, "-c", PROBE, reader, str(path)],
        capture_output=True,
        text=True,
        cwd=ROOT,
        env={"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"},
        timeout=60,
    )
    assert done.returncode == 0, done.stderr
    megabytes_read, megabytes, message = done.stdout.splitlines()
    # Two 4 MiB chunks are read (8.4 MB), never the 300 MB.
    assert float(megabytes_read) < 20.0 and float(megabytes) < 100.0, (megabytes_read, megabytes)
    assert (
        message
        == f"{path}, line 1: a line longer than 4 MiB: not a {'trajectory file' if reader == 'trajectory' else reader + ' file' if reader == 'variants' else 'motor catalogue'} (is it the right file?)"
    )
