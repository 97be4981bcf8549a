"""The suite's set-up: test processes in parallel (pytest-xdist) over one warmed numba cache.

pyproject.toml's addopts start a worker process a core (at most four; two on
a 2-core machine) and share the tests out file by file (``--dist loadfile``: a
file's module fixtures are built once). On a machine's first run every worker
would compile the same numba kernels at once (tens of seconds each, and again
in every command a test starts in a subprocess until the cache is written), so
each worker first warms the groups below in turn, each under a lock, starting
at its own: the first worker compiles the closed-chain kernels while the second
compiles the reduced plant's, then each loads the other's group from the cache
numba writes next to the sources (and matplotlib's font list is built once).
A run in one process (``-n 0``) skips the warm-up: there its cost would only move.

The files that take longest run first, so that the workers finish together
instead of one waiting on a long file picked up last.

``--expected-skips FILE``: the run fails on any skipped test the file does not
list (a node id or a prefix of one, one a line, ``#`` comments saying why);
.ci/run sets it, so that a test silently skipped in CI (a missing dependency, a
browser not found) is a failure there, not a line in the summary.

``quick_figures`` (a fixture) and ``figures_undrawn`` (for module fixtures): a
report's figures built but not drawn, in the tests that read a page's text, its
JSON or an exit status; drawing was most of the suite's end-to-end time.
"""

from __future__ import annotations

import contextlib
import hashlib
import io
import os
import tempfile
import warnings
from pathlib import Path

import pytest

#: Test files by decreasing time, by their path under tests/ (the sums of each file's ``--durations=0`` entries, README's
#: command in a fresh worktree, 29 Nov, less what that day's cuts saved): scheduled first.
SLOW_FIRST = [
    "test_docs.py",
    "test_files.py",
    "test_cli.py",
    "test_schemas.py",
    "closed_chain/test_dynamics.py",
    "present/test_viewer.py",
    "rig/identification/test_identification_accuracy.py",
    "stations/test_commands.py",
    "present/test_pages.py",
    "rig/identification/test_uncertainty_forward.py",
    "present/test_report.py",
    "design/test_sweep_scratch.py",
    "present/test_meshcat_output.py",
    "test_layers.py",
    "closed_chain/test_plant.py",
    "rig/identification/test_identification.py",
    "design/test_sweep.py",
    "cli/test_simulate_plant.py",
    "test_channels_logs.py",
    "mujoco_engine/test_plant.py",
    "mujoco_engine/test_mujoco_engine.py",
    "rig/monitoring/test_monitor_run.py",
    "cli/test_iso_check.py",
    "rig/test_plausibility.py",
    "present/test_monitor_page.py",
    "analytic/test_kernel.py",
    "rig/identification/test_identified_file.py",
]


def warm_closed_chain() -> None:
    """The Pinocchio model's kernels: a closed-chain run with its inverse dynamics, then its plant under the compiled control."""
    import hipsim
    from hipsim.closed_chain.plant import PinocchioPlant
    from hipsim.control import AugmentedPD, WorkspacePD, simulate
    from hipsim.motion.trajectories import iso14242_at

    params = hipsim.load_parameters()
    hipsim.analyse(params, hipsim.iso14242(rate=200), model="pinocchio")
    plant = PinocchioPlant(params)
    for controller in (WorkspacePD(params), AugmentedPD(params, iso14242_at, params.control.servo_rate, 0.003)):
        simulate(plant, controller, iso14242_at, 0.003)
    simulate(plant, WorkspacePD(params), iso14242_at, 0.003, compiled=False)  # the plant's advance() on its own


def warm_reduced_plant() -> None:
    """The analytic model's single-state kernels and the compiled servo loop on the reduced plant, both controllers."""
    import hipsim
    from hipsim.control import AugmentedPD, ReducedPlant, WorkspacePD, simulate
    from hipsim.motion.trajectories import iso14242_at

    params = hipsim.load_parameters()
    plant = ReducedPlant(params)
    for controller in (WorkspacePD(params), AugmentedPD(params, iso14242_at, params.control.servo_rate, 0.003)):
        simulate(plant, controller, iso14242_at, 0.003)


def warm_wear() -> None:
    """The wear maps' kernels (slide tracks, cross-shear): independent of the plants', so the worker that has warmed the
    reduced plant compiles them (2.3 s of CPU) while the other is still on the closed chain, instead of waiting idle."""
    from hipsim.motion.trajectories import iso14242
    from hipsim.wear import cup_grid, wear_maps

    # (The refinement's direction_pass, for long motions in pieces, compiles in its own test.)
    wear_maps(iso14242(rate=100), 1.0, points=cup_grid(3, 6, 14.0))


def warm_matplotlib() -> None:
    """Matplotlib's font list, which its first import on a machine builds (and two processes would build twice)."""
    from matplotlib import font_manager  # noqa: F401


#: The groups, each warmed by one worker while the other warms the next.
WARM_UPS = [warm_closed_chain, warm_reduced_plant, warm_wear, warm_matplotlib]


def _lock_path(root: Path, name: str) -> Path:
    key = hashlib.sha1(str(root.resolve()).encode()).hexdigest()[:12]
    return Path(tempfile.gettempdir()) / f"hipsim-warm-up-{key}-{name}.lock"


def warm_up(root: Path, worker: int) -> None:
    """Warm every group, starting at the worker's own, one process per group at a time.

    Args:
        root: the checkout, naming the locks (another checkout's cache is its own).
        worker: the xdist worker's number (gw0 → 0).
    """
    import fcntl

    order = WARM_UPS[worker % len(WARM_UPS) :] + WARM_UPS[: worker % len(WARM_UPS)]
    for group in order:
        with open(_lock_path(root, group.__name__), "w") as lock:
            fcntl.flock(lock, fcntl.LOCK_EX)  # the other worker compiling this group: wait, then load its cache
            try:
                with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
                    group()
            except Exception as error:  # an optimisation only: the tests themselves say what is wrong
                warnings.warn(
                    f"numba warm-up {group.__name__} failed, the tests compile as they go: {error!r}", stacklevel=1
                )
            finally:
                fcntl.flock(lock, fcntl.LOCK_UN)


def _figure_digest(fig) -> str:
    """A digest of what a figure shows: its titles, labels, texts and every line's and collection's data."""
    import numpy as np

    digest = hashlib.sha256(str(fig.get_suptitle() if hasattr(fig, "get_suptitle") else "").encode())
    for ax in fig.axes:
        digest.update(
            "|".join((ax.get_title(), ax.get_xlabel(), ax.get_ylabel(), *(t.get_text() for t in ax.texts))).encode()
        )
        for line in ax.get_lines():
            digest.update(f"{line.get_label()}".encode() + np.asarray(line.get_xydata(), float).tobytes())
        for collection in ax.collections:
            for path in collection.get_paths():
                digest.update(np.asarray(path.vertices, float).tobytes())
        for image in ax.get_images():
            digest.update(np.asarray(image.get_array(), float).tobytes())
    return digest.hexdigest()


@contextlib.contextmanager
def figures_undrawn():
    """Figures built in full but not drawn: ``Figure.savefig`` writes a stand-in PNG or SVG naming a digest of the figure.

    Drawing is most of a report's time (7 figures, each drawn twice: about 4 s of the 4.5 s of
    ``hipsim report --rate 100``). Tests whose assertions are about a page's text, its JSON, the
    files a command writes or its exit status use this; the drawn figures themselves are checked
    where the drawing is the point (tests/present/test_report.py's full report, the browser tests, the
    rig, monitor and wear pages). The stand-in depends on every plotted value, so two runs that
    differ write different figures and a rerun of the same one the same bytes, as drawing does.
    """
    from matplotlib.figure import Figure

    drawn = Figure.savefig

    def undrawn(self, fname, *args, format=None, **kwargs):
        fmt = format or (Path(fname).suffix.lstrip(".") if isinstance(fname, (str, os.PathLike)) else None)
        if fmt == "png":
            data = b"\x89PNG\r\n\x1a\n" + b"hipsim test stand-in " + _figure_digest(self).encode()
        elif fmt == "svg":
            data = f'<svg xmlns="http://www.w3.org/2000/svg"><desc>{_figure_digest(self)}</desc></svg>\n'.encode()
        else:
            return drawn(self, fname, *args, format=format, **kwargs)
        if isinstance(fname, (str, os.PathLike)):
            Path(fname).write_bytes(data)
        else:
            fname.write(data)

    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(Figure, "savefig", undrawn)
        yield


@pytest.fixture
def quick_figures():
    """See :func:`figures_undrawn`: a test's figures built but not drawn."""
    with figures_undrawn():
        yield


def pytest_addoption(parser):
    parser.addoption(
        "--expected-skips",
        metavar="FILE",
        default=None,
        help="fail the run on any skipped test this file (node ids or prefixes, one a line) does not list",
    )


def read_expected_skips(path: Path) -> list[str]:
    """The node ids (or prefixes) a file lists, one a line, without blank lines and ``#`` comments."""
    lines = (line.split("#", 1)[0].strip() for line in path.read_text().splitlines())
    return [line for line in lines if line]


def unexpected_skips(skipped: list[str], expected: list[str]) -> list[str]:
    """The skipped node ids that no expected entry names (an entry names itself and the ids it is a prefix of)."""
    return [nodeid for nodeid in skipped if not any(nodeid.startswith(entry) for entry in expected)]


class SkipGuard:
    """Collects the skipped tests' ids (xdist forwards the workers' reports) and fails the session on an unlisted one."""

    def __init__(self, expected: list[str]) -> None:
        self.expected = expected
        self.skipped: list[str] = []

    def pytest_runtest_logreport(self, report: pytest.TestReport) -> None:
        if report.skipped and not hasattr(report, "wasxfail"):
            self.skipped.append(report.nodeid)

    def pytest_sessionfinish(self, session: pytest.Session, exitstatus: int) -> None:
        unexpected = unexpected_skips(self.skipped, self.expected)
        if unexpected:
            reporter = session.config.pluginmanager.get_plugin("terminalreporter")
            if reporter is not None:
                reporter.write_line(
                    f"{len(unexpected)} skipped test(s) not listed as expected (--expected-skips):", red=True
                )
                for nodeid in unexpected:
                    reporter.write_line(f"  {nodeid}")
            if session.exitstatus == pytest.ExitCode.OK:
                session.exitstatus = pytest.ExitCode.TESTS_FAILED


def pytest_configure(config):
    listed = config.getoption("--expected-skips")
    if listed is not None and getattr(config, "workerinput", None) is None:  # the controller sees every report
        config.pluginmanager.register(SkipGuard(read_expected_skips(Path(listed))), "hipsim-skip-guard")


@pytest.hookimpl(trylast=True)
def pytest_sessionstart(session):
    """A worker's warm-up, after pytest-cov has started measuring in it (its own sessionstart): the modules the
    warm-up imports then count their module-level lines as run, as they do in a serial run."""
    worker = getattr(session.config, "workerinput", None)
    if worker is None or os.name != "posix":  # the controller, or a serial run
        return
    warm_up(Path(str(session.config.rootpath)), int(worker["workerid"].removeprefix("gw")))


def pytest_collection_modifyitems(session, config, items):
    """The slowest files first, each file's tests in their own order."""
    rank = {name: k for k, name in enumerate(SLOW_FIRST)}
    tests = Path(__file__).resolve().parent
    items.sort(key=lambda item: rank.get(_under(item.path, tests), len(rank)))  # stable: a file's order is kept


def _under(path: Path, tests: Path) -> str:
    """A test file's path under tests/ ("rig/test_compare.py"), as SLOW_FIRST names it."""
    try:
        return path.resolve().relative_to(tests).as_posix()
    except ValueError:  # a test collected from outside tests/
        return path.name


def pytest_unconfigure(config):
    """The controller, once every worker is done, removes the warm-up locks: a run leaves nothing in the temporary folder."""
    if getattr(config, "workerinput", None) is not None or os.name != "posix":
        return
    for group in WARM_UPS:
        with contextlib.suppress(OSError):
            _lock_path(Path(str(config.rootpath)), group.__name__).unlink()
