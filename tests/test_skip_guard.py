"""The CI's skip guard (conftest.py's ``--expected-skips``): a skip the list does not name fails the run."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

from conftest import read_expected_skips, unexpected_skips

HERE = Path(__file__).parent


def test_an_entry_names_itself_and_the_ids_it_prefixes(tmp_path):
    listed = tmp_path / "skips.txt"
    listed.write_text("# why\ntests/test_a.py::test_one  # the reason\n\ntests/test_b.py\n")
    expected = read_expected_skips(listed)
    assert expected == ["tests/test_a.py::test_one", "tests/test_b.py"]
    skipped = ["tests/test_a.py::test_one", "tests/test_a.py::test_two", "tests/test_b.py::test_x[1]"]
    assert unexpected_skips(skipped, expected) == ["tests/test_a.py::test_two"]
    assert unexpected_skips([], expected) == [] and unexpected_skips(skipped, []) == skipped


def _run(tmp_path: Path, listed: str) -> subprocess.CompletedProcess[str]:
    shutil.copy(HERE / "conftest.py", tmp_path / "conftest.py")
    (tmp_path / "test_s.py").write_text(
        "import pytest\n\ndef test_ok():\n    pass\n\ndef test_gone():\n    pytest.skip('no such thing')\n"
    )
    (tmp_path / "skips.txt").write_text(listed)
    command = [
        sys.executable,
        "-m",
        "pytest",
        "-q",
        "-p",
        "no:cacheprovider",
        "-o",
        "addopts=",
        "--rootdir",
        str(tmp_path),
    ]
    return subprocess.run(
        [*command, "--expected-skips", str(tmp_path / "skips.txt"), str(tmp_path)],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        env=_own_run_env(),
    )


def _own_run_env() -> dict[str, str]:
    """This process's environment without what would make the inner run part of this one: CI's pytest options
    (PYTEST_ADDOPTS: the expected skips, coverage) and pytest-cov's settings for the subprocesses it measures."""
    return {
        name: value
        for name, value in os.environ.items()
        if name != "PYTEST_ADDOPTS" and not name.startswith("COV_CORE")
    }


def test_an_unlisted_skip_fails_the_run_and_is_named(tmp_path):
    run = _run(tmp_path, "test_s.py::test_ok  # listed, but it passes: the skip below is not\n")
    assert run.returncode == 1, run.stdout + run.stderr
    assert "1 skipped test(s) not listed as expected" in run.stdout and "test_s.py::test_gone" in run.stdout
