"""Atomic output files: never half a file, never over something that is not a regular file."""

import os

import pytest

from hipsim.exceptions import HipsimError
from hipsim.files import check_folder, make_folder, write_atomic


def test_atomic_write_leaves_old_file_on_failure(tmp_path):
    target = tmp_path / "out.csv"
    target.write_text("old")

    with pytest.raises(TypeError):  # fails half-way, after the temporary file is open
        write_atomic(target, 12345)
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
