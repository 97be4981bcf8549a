"""``hipsim wear --weighings FILE`` / ``--test DIR``: a wear test's gravimetric result per station, its wear factors
fitted, its wear predicted over the motion each station had, and the test's report (the guide's page "A wear test's
report"). The options are declared in :mod:`hipsim.cli.wear`; their ranges are checked here, where they enter.
"""

from __future__ import annotations

import argparse
import math
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

from ..exceptions import HipsimError

__all__ = ["WORKERS_RANGE", "add_test_options", "run_test"]

#: --workers' hard range (the other options' ranges live with their laws: hipsim.wear.gravimetric, hipsim.wear.factors).
WORKERS_RANGE = (1, 64)

#: A test folder's files, by role (each used when present and not given by its option).
TEST_FILES = {
    "weighings": "weighings.csv",
    "stations": "stations.csv",
    "snapshots": "snapshots",
    "params": "params.toml",
    "friction": "friction.csv",
}


def add_test_options(wear: argparse.ArgumentParser) -> None:
    """The gravimetric test's options (docs/guide/wear-test.md), declared here, each with its unit and range."""
    test = wear.add_argument_group("a wear test's weighings (ISO 14242-2) and report")
    test.add_argument(
        "--weighings",
        metavar="FILE",
        help="the cups' masses: CSV columns cycle, station, mass_mg, and the soak control as station 'soak' "
        "(or 'soak_NAME') or a column soak_mg; gives each station's wear rate with its 95 %% interval",
    )
    test.add_argument(
        "--density",
        type=float,
        metavar="MG_PER_MM3",
        help="the cups' density in mg/mm³, in (0, 25] (default 0.935, UHMWPE)",
    )
    test.add_argument(
        "--balance-noise",
        type=float,
        metavar="MG",
        help="the balance's noise, one reading's standard deviation in mg, in (0, 100]: each station's residuals are "
        "held to 3 times √2 times it (default: to the other stations' median residual)",
    )
    test.add_argument(
        "--from",
        dest="from_cycle",
        type=float,
        metavar="CYCLE",
        help="the steady-state rate from this cycle on, a whole number ≥ 0 (default: bedding-in found from the data)",
    )
    test.add_argument(
        "--station",
        action="append",
        metavar="NAME=SOURCE",
        help="the motion station NAME had: iso, FILE, FILE:1, FILE:2 (stations output), FILE:desired (simulate "
        "output), or snapshots:J (the --snapshots motion with station load Fe_J_N); repeatable (default: the "
        "snapshots, station by station, else the built-in cycle)",
    )
    test.add_argument(
        "--snapshots",
        action="append",
        metavar="PATH",
        help="the monitor's snapshot logs (files, folders, patterns; a 'cycle' column; needs --params): each stands for "
        "its interval of cycles; repeatable",
    )
    test.add_argument("--friction", metavar="FILE", help="the monitor's table (hipsim monitor --out), for the report")
    test.add_argument(
        "--test",
        metavar="DIR",
        help="a test's folder: weighings.csv, and when present stations.csv, snapshots/, params.toml, friction.csv "
        "(the options above override); the report goes to DIR/report unless --report",
    )
    low, high = WORKERS_RANGE
    test.add_argument(
        "--workers",
        type=int,
        metavar="N",
        help=f"worker processes for the snapshots' maps, {low} to {high} (default 1)",
    )


def _test_folder(args, notes: list[str]) -> None:
    """Fill the options a test folder's files stand for (module constants), noting each file taken."""
    if not args.test:
        return
    folder = Path(args.test)
    if not folder.is_dir():
        raise HipsimError(f"--test: {folder} is not a folder")
    found = {role: folder / name for role, name in TEST_FILES.items() if (folder / name).exists()}
    if args.weighings is None:
        if "weighings" not in found:
            raise HipsimError(f"--test: {folder} has no {TEST_FILES['weighings']} (or give --weighings)")
        args.weighings = str(found["weighings"])
    if args.params is None and "params" in found:
        args.params = str(found["params"])
    if args.friction is None and "friction" in found:
        args.friction = str(found["friction"])
    if not args.snapshots and not args.station:
        if "snapshots" in found:
            args.snapshots = [str(found["snapshots"])]
        elif "stations" in found:
            args.station = [f"{j}={found['stations']}:{j}" for j in ("1", "2")]
            notes.append(f"{found['stations']}: stations named 1 and 2 take its platforms 1 and 2")
    if args.report is None:
        args.report = str(folder / "report")
    notes.append("test folder " + str(folder) + ": " + ", ".join(str(path.name) for path in found.values()))


def _checked(args) -> int | None:
    """--from and --workers checked at entry (one line each)."""
    low, high = WORKERS_RANGE
    if args.workers is not None and not low <= args.workers <= high:
        raise HipsimError(
            f"--workers: expected a whole number of worker processes in [{low}, {high}], got {args.workers}"
        )
    if args.from_cycle is None:
        return None
    c = args.from_cycle
    if not (math.isfinite(c) and c >= 0 and c == round(c)):
        raise HipsimError(f"--from: expected a cycle, a whole number ≥ 0, got {c:g}")
    return int(c)


def _given(args, parse_law):
    from ..wear.factors import ForceTrackFactor
    from ..wear.laws import WearFactor
    from ..wear.test_result import GivenFactor

    if args.wear_law or args.area_law is not None:
        raise HipsimError(
            "with --weighings a law is given as --wear-factor K:KIND; the fitted k(CS) table is written for --wear-law"
        )
    law = parse_law(args)
    if isinstance(law, WearFactor):
        return GivenFactor(law.k, "local")
    if isinstance(law, ForceTrackFactor):
        return GivenFactor(law.k, "force-track")
    return None


def _integrals(args, spec, setup, points, read_motion):
    """A source's per-cycle integrals, its file, the notes, and its error against ISO (None for the built-in cycle
    or a motion of fewer than two heel strikes)."""
    from ..motion.trajectories import Trajectory
    from ..wear import wear_maps
    from ..wear.factors import motion_integrals
    from ..wear.test_context import iso_error, motion_error

    motion, cycle_time, name, path, notes = read_motion(args, spec)
    error = None
    if isinstance(motion, Trajectory):
        try:
            error = motion_error(iso_error(motion), f"{name}, against ISO 14242-1 by gait phase")
        except HipsimError:
            pass  # one heel strike: no phase to compare by; a stations output's own error columns may still say
    return motion_integrals(wear_maps(motion, cycle_time, setup, points)), path, notes, error


def _machine(path: str, overrides: tuple[str, ...]):
    """The parameter set from its file and --set overrides (a worker loads its own: a Parameters does not pickle)."""
    from ..machine.parameters import load_parameters, parse_override

    return load_parameters(
        path, dict(parse_override(text, source="--set") for text in overrides), overrides_source="--set"
    )


def _snapshot_task(task):
    """One snapshot's per-cycle integrals per station load column, and its angle errors against ISO (sum of squares,
    samples, largest) (a worker's job; top level to be picklable)."""
    import numpy as np

    from ..motion.trajectories import Trajectory
    from ..rig.monitoring.snapshot_log import read_snapshot
    from ..wear import wear_maps
    from ..wear.accumulate import whole_cycles
    from ..wear.factors import motion_integrals
    from ..wear.test_context import iso_error

    snapshot, machine, torque_constant, js, setup, points = task
    params = _machine(*machine)
    # The log's reader knows the drawing (its forward kinematics takes both platforms alike); each platform's own
    # motion comes from the per-chain machine below.
    drawing = params if params.geometry is None else params.replace(geometry=None)
    read = read_snapshot(snapshot, drawing, torque_constant)
    trajectory = read.log.trajectory.slice(read.log.usable)
    cycle = float(read.cycles.mean())
    out = {}
    for j in js:
        t = trajectory
        loads = None
        if j and read.loads is not None and len(read.loads) == len(read.log.trajectory):
            loads = read.loads[:, int(j) - 1]
            t = Trajectory(t.t, t.q, t.qd, t.qdd, loads[read.log.usable], f"{t.name}:Fe_{j}_N")
        own = _platform_motion(snapshot, params, read, j, loads)
        t = own if own is not None else t
        whole, cycle_time = whole_cycles(t)
        errors = iso_error(t)
        out[j] = (
            motion_integrals(wear_maps(whole, cycle_time, setup, points)),
            np.sum(errors**2, axis=0),
            len(errors),
            np.max(np.abs(errors), axis=0),
            own is not None,
        )
    return cycle, snapshot.path, snapshot.sha256, out


def _worker(task):
    """:func:`_snapshot_task` in a worker process: a refusal comes back as its one line (an error with arguments of
    its own may not unpickle in the parent)."""
    try:
        return _snapshot_task(task)
    except HipsimError as error:
        return str(error)


def _platform_motion(snapshot, params, read, j: str, loads):
    """Platform j's own motion: the log's carriages through that platform's forward kinematics (per-chain geometry),
    filtered and differentiated as the log's motion is, its usable samples; None when the machine has no per-chain
    geometry, the log no carriage readings, or the snapshot is a window of a long log."""
    if params.geometry is None or snapshot.lines is not None or j not in ("1", "2"):
        return None
    from ..analytic.stations import platform_attitude
    from ..exceptions import TrajectoryError
    from ..rig.logs.smoothing import smooth_motion
    from ..stations.logs import read_carriage_log

    log = read.log
    try:
        _, carriages = read_carriage_log(snapshot.path, params.lead)
    except TrajectoryError:
        return None
    if len(carriages) != len(log.trajectory):
        return None
    t = log.trajectory.t
    q = platform_attitude(params, carriages, int(j), t=t, q0=log.trajectory.q[0], source=snapshot.path)
    load = loads if loads is not None else log.trajectory.Fe
    return smooth_motion(t, q, load, log.cutoff, f"{snapshot.path}:platform {j}", log.sample_rate).slice(log.usable)


def _exposures(args, gravimetry, setup, points, notes: list[str], inputs: dict, read_motion, errors: dict):
    """Per station its Exposure (snapshots, a source per station, or the built-in cycle); ``errors`` filled with the
    snapshots' motion errors against ISO per station."""
    import numpy as np

    from ..wear.accumulate import Exposure, snapshot_intervals
    from ..wear.test_context import MotionError

    names = [rate.station for rate in gravimetry.stations]
    first = min(rate.cycles[0] for rate in gravimetry.stations)
    last = max(rate.cycles[-1] for rate in gravimetry.stations)
    specs: dict[str, str] = {}
    for text in args.station or ():
        name, sep, spec = text.partition("=")
        if not sep or not name or not spec:
            raise HipsimError(f"--station: expected NAME=SOURCE, got '{text}'")
        if name not in names:
            raise HipsimError(f"--station: no station '{name}' in the weighings (stations: {', '.join(names)})")
        specs[name] = spec
    if args.snapshots:
        for k, name in enumerate(names):
            specs.setdefault(name, f"snapshots:{k + 1}" if k < 2 else "snapshots")
    exposures = {}
    snapshot_js = {name: spec.partition(":")[2] for name, spec in specs.items() if spec.split(":")[0] == "snapshots"}
    if snapshot_js:
        if not args.snapshots:
            raise HipsimError("--station NAME=snapshots: give the snapshots with --snapshots")
        cycles, motions = _snapshot_motions(args, setup, points, sorted(set(snapshot_js.values())), inputs)
        boundaries = snapshot_intervals(np.array(cycles), first, last)
        for name, j in snapshot_js.items():
            what = f"the monitor's {len(cycles)} snapshots" + (f", load Fe_{j}_N" if j else ", load Fe_N")
            if any(m[j][4] for m in motions):
                what += f", platform {j}'s own motion from the carriages (per-chain geometry)"
            exposures[name] = Exposure(name, boundaries, tuple(m[j][0] for m in motions), what)
            squares, count = sum(m[j][1] for m in motions), sum(m[j][2] for m in motions)
            largest = np.max([m[j][3] for m in motions], axis=0)
            rms = np.sqrt(squares / count)
            errors[name] = MotionError(
                f"{what}, against ISO 14242-1 by gait phase",
                (float(rms[0]), float(rms[1]), float(rms[2])),
                (float(largest[0]), float(largest[1]), float(largest[2])),
            )
        notes.append(
            f"each snapshot's motion stands for the cycles from the midpoint with the one before to the midpoint with "
            f"the one after ({len(cycles)} snapshots, cycles {cycles[0]:.0f} to {cycles[-1]:.0f})"
        )
    for name in names:
        if name in exposures:
            continue
        spec = specs.get(name, "iso")
        integrals, path, more, error = _integrals(args, spec, setup, points, read_motion)
        if error is not None:
            errors[name] = error
        notes += [f"station {name}: {note}" for note in more]
        if path:
            inputs[f"motion of station {name}"] = path
        if name not in specs:
            notes.append(f"station {name}: no motion given, the built-in ISO cycle taken (--station NAME=SOURCE)")
        exposures[name] = Exposure(name, np.array([first, max(last, first + 1)], dtype=float), (integrals,), spec)
    return exposures


def _snapshot_motions(args, setup, points, js, inputs):
    from ..rig.monitoring.snapshots import find_snapshots
    from .common import parameters

    if args.params is None:
        raise HipsimError("--snapshots: give --params (the machine whose encoders the logs read)")
    parameters(args)  # checked here, once, with its warnings; each worker loads its own
    machine = (args.params, tuple(args.overrides))
    found, skipped = find_snapshots(args.snapshots, torque_constant=args.torque_constant)
    if skipped:
        raise HipsimError(f"--snapshots: {skipped[0].path} is still being written")
    if not found:
        raise HipsimError("--snapshots: no snapshot found")
    tasks = [(snapshot, machine, args.torque_constant, js, setup, points) for snapshot in found]
    workers = args.workers or 1
    if workers > 1:
        with ProcessPoolExecutor(max_workers=workers) as pool:
            results = list(pool.map(_worker, tasks))
        failed = next((r for r in results if isinstance(r, str)), None)
        if failed is not None:
            raise HipsimError(failed)
    else:
        results = [_snapshot_task(task) for task in tasks]
    results.sort(key=lambda r: r[0])
    inputs["snapshots"] = [path for _, path, _, _ in results]
    return [r[0] for r in results], [r[3] for r in results]


def run_test(args, setup, points, read_motion, parse_law) -> int:
    """The test's result: table (--out), summary, and page (--report).

    Args:
        args: the parsed options of ``hipsim wear``.
        setup, points: the cup and its points.
        read_motion: ``hipsim.cli.wear.read_motion`` (a source's motion), passed in: wear imports this module.
        parse_law: ``hipsim.cli.wear._law`` (the law the options give).
    """
    from ..files import check_folder, check_output
    from ..motion.sources import CycleSource
    from ..present.pages import require_pdf_renderer
    from ..wear import wear_maps
    from ..wear.factors import motion_integrals
    from ..wear.gravimetric import gravimetry
    from ..wear.test_result import wear_test
    from ..wear.weighings import read_weighings
    from ..wear.weighings_checks import check_gravimetry, duplicate_stations
    from .wear_test_output import context, print_result, write_outputs

    notes: list[str] = []
    _test_folder(args, notes)
    if args.compare:
        raise HipsimError("--compare and --weighings: give one")
    from_cycle = _checked(args)
    given = _given(args, parse_law)
    if Path(args.out).suffix.lower() == ".parquet":
        raise HipsimError(f"--out {args.out}: the table of stops is CSV (it has a text column, the station)")
    check_output(args.out)
    if args.report:
        check_folder(Path(args.report))
    if args.pdf:
        if not args.report:
            raise HipsimError("--pdf prints the page: give --report DIR")
        require_pdf_renderer()
    weighed = read_weighings(args.weighings)
    duplicate = duplicate_stations(weighed)
    if duplicate:
        raise HipsimError(f"--weighings {args.weighings}: {duplicate}")
    result_gravimetry = gravimetry(weighed, args.density, from_cycle)
    check = check_gravimetry(weighed, result_gravimetry, args.balance_noise)
    notes += [f"self-check: IMPLAUSIBLE: {finding}" for finding in check.findings]
    inputs: dict = {"weighings": args.weighings, "friction": args.friction}
    # The reference first: its kernels loaded here, the snapshots' worker processes (forked) start with them.
    reference = motion_integrals(wear_maps(CycleSource(1000.0, 1, 1.0), 1.0, setup, points))
    errors: dict = {}
    exposures = _exposures(args, result_gravimetry, setup, points, notes, inputs, read_motion, errors)
    result = wear_test(result_gravimetry, exposures, given, reference)
    for rate in result_gravimetry.stations:
        if rate.bedding_in == "detected":
            notes.append(
                f"station {rate.station}: bedding-in found up to cycle {rate.from_cycle} "
                f"({rate.bedding_in_rate_mg_per_Mc:.3g} mg/Mc before it); the rate is fitted from there (--from says otherwise)"
            )
        notes += [outlier.describe() for outlier in rate.outliers]
    stations_context = context(args, result, errors)
    written = write_outputs(args, result, stations_context, notes, inputs)
    print_result(args, result, stations_context, notes, written)
    from ..records import exit_status

    return exit_status([result.verdict])  # DIFFERENT exits 1, as every verdict's failing level (docs/guide/outputs.md)
