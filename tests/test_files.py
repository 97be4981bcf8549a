"""Atomic output files: never half a file, never over something that is not a regular file."""

import os

import numpy as np
import pytest

from hipsim.exceptions import HipsimError
from hipsim.files import check_folder, make_folder, output_folder, write_atomic, write_columns


def test_atomic_write_leaves_old_file_on_failure(tmp_path):
    target = tmp_path / "out.csv"
    target.write_text("old")

    with pytest.raises(TypeError):  # fails half-way, after the temporary file is open
        write_atomic(target, 12345)  # type: ignore[arg-type]  # neither text nor bytes, on purpose
    assert target.read_text() == "old"
    assert list(tmp_path.iterdir()) == [target]


def test_atomic_write_into_missing_folder(tmp_path):
    with pytest.raises(HipsimError, match="does not exist"):
        write_atomic(tmp_path / "nope" / "out.csv", "x")


def test_a_pipe_is_refused_and_left_alone(tmp_path):
    """Renaming a file over a pipe (or a device such as /dev/null) would destroy it."""
    pipe = tmp_path / "pipe"
    os.mkfifo(pipe)
    with pytest.raises(HipsimError, match="pipe: not a regular file"):
        write_atomic(pipe, "x")
    assert pipe.is_fifo()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["pipe"]  # no temporary file left either


def test_a_symbolic_link_is_written_through(tmp_path):
    (tmp_path / "data").mkdir()
    target = tmp_path / "data" / "target.csv"
    target.write_text("old")
    link = tmp_path / "link.csv"
    link.symlink_to(target)
    write_atomic(link, "new")
    assert link.is_symlink() and target.read_text() == "new"


def test_a_dangling_link_into_a_missing_folder_is_refused(tmp_path):
    link = tmp_path / "link.csv"
    link.symlink_to(tmp_path / "gone" / "target.csv")
    with pytest.raises(HipsimError, match="link.csv: cannot write, folder .*gone.* does not exist"):
        write_atomic(link, "x")


def test_check_folder_creates_nothing_and_names_a_file_in_the_way(tmp_path):
    check_folder(tmp_path / "a" / "b")
    assert list(tmp_path.iterdir()) == []
    (tmp_path / "file").write_text("x")
    with pytest.raises(HipsimError, match="'.*file' is a file"):
        check_folder(tmp_path / "file" / "sub")
    with pytest.raises(HipsimError, match="a file has that name"):
        make_folder(tmp_path / "file")


def test_a_loop_of_links_is_refused_and_left_alone(tmp_path):
    """resolve() gives up on a loop (RuntimeError before Python 3.13): one line, not a traceback."""
    (tmp_path / "a").symlink_to(tmp_path / "b")
    (tmp_path / "b").symlink_to(tmp_path / "a")
    with pytest.raises(HipsimError, match="a: cannot write, its symbolic links go round in a loop"):
        write_atomic(tmp_path / "a", "x")
    assert (tmp_path / "a").is_symlink() and (tmp_path / "b").is_symlink()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a", "b"]


def test_a_link_to_a_pipe_is_refused_and_both_left_alone(tmp_path):
    pipe = tmp_path / "pipe"
    os.mkfifo(pipe)
    link = tmp_path / "link.csv"
    link.symlink_to(pipe)
    with pytest.raises(HipsimError, match="link.csv: not a regular file"):
        write_columns(link, {"t [s]": np.arange(3.0)})
    assert link.is_symlink() and pipe.is_fifo()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["link.csv", "pipe"]


def test_a_chain_of_links_is_written_through_to_the_end(tmp_path):
    target = tmp_path / "target.csv"
    target.write_text("old")
    (tmp_path / "one").symlink_to(target)
    (tmp_path / "two").symlink_to(tmp_path / "one")
    write_columns(tmp_path / "two", {"t [s]": np.array([0.0, 0.5])})
    assert (tmp_path / "one").is_symlink() and (tmp_path / "two").is_symlink()
    assert target.read_text() == "t [s]\n0\n0.5\n"


class Refused(Exception):
    """Stands in for whatever stops a run half-way."""


def test_output_folder_takes_back_the_folders_a_failed_run_made(tmp_path):
    out = tmp_path / "a" / "b" / "c"

    def refused_run():
        with output_folder(out) as folder:
            assert folder == out and out.is_dir()
            raise Refused

    with pytest.raises(Refused):
        refused_run()
    assert list(tmp_path.iterdir()) == []


def test_output_folder_takes_them_back_on_ctrl_c_too(tmp_path):
    with pytest.raises(KeyboardInterrupt):
        with output_folder(tmp_path / "out"):
            raise KeyboardInterrupt
    assert list(tmp_path.iterdir()) == []


def test_output_folder_never_removes_a_folder_that_was_there(tmp_path):
    (tmp_path / "a").mkdir()
    with pytest.raises(Refused):
        with output_folder(tmp_path / "a" / "b"):
            raise Refused
    assert [p.name for p in tmp_path.iterdir()] == ["a"] and list((tmp_path / "a").iterdir()) == []
    with pytest.raises(Refused):
        with output_folder(tmp_path / "a"):
            raise Refused
    assert (tmp_path / "a").is_dir()


def test_output_folder_keeps_what_was_written_and_the_folders_holding_it(tmp_path):
    def refused_run():
        with output_folder(tmp_path / "a" / "b") as folder:
            write_atomic(folder / "half.csv", "x")
            raise Refused

    with pytest.raises(Refused):
        refused_run()
    assert (tmp_path / "a" / "b" / "half.csv").read_text() == "x"


def test_output_folder_keeps_the_folder_of_a_run_that_succeeds(tmp_path):
    with output_folder(tmp_path / "a" / "b") as folder:
        pass
    assert folder.is_dir() and list(folder.iterdir()) == []


# --------------------------------------------------------------------------- SIGTERM and standard output

import signal  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import textwrap  # noqa: E402

#: Runs a hipsim call in a fresh process whose os.replace first sends SIGTERM to the process itself:
#: the signal arrives while the temporary file is complete and not yet renamed, as a `timeout` would.
_TERMINATED_DURING_RENAME = textwrap.dedent(
    """
    import os, signal, sys, time
    real_replace = os.replace
    def replace(source, target):
        os.kill(os.getpid(), signal.SIGTERM)
        time.sleep(30)  # the signal ends this sleep; without a handler the process dies here
        real_replace(source, target)
    os.replace = replace
    {call}
    """
)


def _terminated(call: str, cwd) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-c", _TERMINATED_DURING_RENAME.format(call=call)],
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=120,
    )


def test_sigterm_during_a_write_removes_the_part_file(tmp_path):
    done = _terminated(
        f"from hipsim.files import write_atomic; write_atomic({str(tmp_path / 'out.csv')!r}, 'x' * 100000)", tmp_path
    )
    assert done.returncode == 128 + signal.SIGTERM, done.stderr
    assert list(tmp_path.iterdir()) == []  # no out.csv, no hidden .out.csv.*.part


def test_sigterm_during_torques_leaves_no_part_file(tmp_path):
    call = "from hipsim.cli.main import main; sys.exit(main(['torques', '--rate', '200', '--out', 'out.csv']))"
    done = _terminated(call, tmp_path)
    assert done.returncode == 128 + signal.SIGTERM, done.stderr
    assert "Traceback" not in done.stderr
    assert list(tmp_path.iterdir()) == []


def test_a_handler_someone_installed_is_left_alone(tmp_path):
    from hipsim.files import exit_on_terminate

    def mine(signum, frame):
        pass

    previous = signal.signal(signal.SIGTERM, mine)
    try:
        with exit_on_terminate():
            assert signal.getsignal(signal.SIGTERM) is mine
        assert signal.getsignal(signal.SIGTERM) is mine
    finally:
        signal.signal(signal.SIGTERM, previous)
    with exit_on_terminate():
        assert signal.getsignal(signal.SIGTERM) not in (signal.SIG_DFL, mine)
    assert signal.getsignal(signal.SIGTERM) is signal.SIG_DFL


def _hipsim(*args, cwd):
    done = subprocess.run([sys.executable, "-m", "hipsim", *args], cwd=cwd, capture_output=True, text=True, timeout=120)
    return done.returncode, done.stdout, done.stderr


@pytest.mark.parametrize("out", ["-", "/dev/stdout"])
def test_out_to_standard_output_with_the_summary_on_standard_error(tmp_path, out):
    status, stdout, stderr = _hipsim("torques", "--rate", "100", "--out", out, cwd=tmp_path)
    assert status == 0, stderr
    rows = stdout.splitlines()
    assert rows[0].startswith("t_s,alpha_deg,beta_deg,gamma_deg,Fe_N,L_11_mm") and len(rows) == 101
    assert np.allclose([float(r.split(",")[0]) for r in rows[1:]], np.arange(100) / 100)
    assert "Sliders" in stderr and "wrote the CSV to standard output (100 rows" in stderr
    assert list(tmp_path.iterdir()) == []  # no file called '-'


def test_urdf_to_standard_output(tmp_path):
    status, stdout, stderr = _hipsim("urdf", "--out", "-", cwd=tmp_path)
    assert status == 0 and stdout.lstrip().startswith("<?xml") and "</robot>" in stdout and "wrote -" in stderr
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["torques", "--out", "/dev/stderr"], "/dev/stderr: names one of this process's open files"),
        (["torques", "--out", "/dev/fd/1"], None),  # standard output by another name: written there
        (["report", "--out", "-"], "-: standard output cannot hold a folder of files"),
        (["workspace", "--out", "-"], "-: standard output cannot hold a folder of files"),
        (["simulate", "--cycles", "0.01", "--out", "-"], "--out - takes one CSV: choose one controller"),
    ],
)
def test_standard_output_where_it_cannot_be_is_refused_in_one_line(tmp_path, args, message):
    status, stdout, stderr = _hipsim(*args, cwd=tmp_path)
    if message is None:
        assert status == 0 and stdout.startswith("t_s,"), stderr
        return
    assert status == 2, stderr
    lines = stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("hipsim: error: ") and message in lines[0], stderr
    assert "pipe:[" not in stderr
    assert list(tmp_path.iterdir()) == []


def test_output_errors_carry_the_path_and_the_reason(tmp_path):
    from hipsim.exceptions import HipsimError, OutputError

    missing = tmp_path / "no_such_folder" / "out.csv"
    with pytest.raises(OutputError) as info:
        write_atomic(missing, "x")
    assert isinstance(info.value, HipsimError)
    assert str(info.value.path) == str(missing) and "does not exist" in info.value.reason
    assert str(info.value) == f"{missing}: {info.value.reason}"


def test_a_killed_writers_part_file_is_removed_by_the_next_write_a_live_ones_kept(tmp_path):
    import subprocess
    import sys

    from hipsim.files import ColumnWriter, write_atomic

    # A process that has ended: its id is free (it was reaped), as a SIGKILL'd run's is.
    ended = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True)
    dead_pid = int(ended.stdout)
    live = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
    try:
        for name in ("out.csv", "table.csv"):
            (tmp_path / f".{name}.{dead_pid}.abc123.part").write_text("half a file")
            (tmp_path / f".{name}.{live.pid}.def456.part").write_text("being written")
        (tmp_path / ".other.csv.1.xyz.part").write_text("another file's")
        write_atomic(tmp_path / "out.csv", "a\n1\n")
        writer = ColumnWriter(tmp_path / "table.csv")
        writer.write({"a": np.array([1.0])})
        writer.close()
        left = sorted(p.name for p in tmp_path.glob(".*.part"))
        assert left == sorted(
            [f".out.csv.{live.pid}.def456.part", f".table.csv.{live.pid}.def456.part", ".other.csv.1.xyz.part"]
        )
        assert (tmp_path / "out.csv").read_text() == "a\n1\n"
    finally:
        live.kill()
        live.wait()
