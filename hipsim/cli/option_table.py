"""Every option of every ``hipsim`` command, declared once: name, meaning, unit, hard and plausible ranges.

The parser of each command is checked against this table when it is built
(:func:`hipsim.cli.parser.apply_table`): an option a command adds that is not
here is a programming error, a number outside its hard range is refused, one
outside its plausible range is warned of. The corpus of slips in the tests
(tests/cli/test_option_table_slips.py) is generated from the numeric rows, so a new
option is covered as soon as it is declared.

Ranges: the hard range holds every value that has a meaning (a cutoff above
0 Hz, a friction rise below 1); the plausible range what a hip simulator's lab
types (ISO 14242-1: 1 Hz, 300–3000 N, heads of 22–60 mm). Where a range is a
choice (the spec is silent), the docs say so: docs/guide/robust-inputs.md.
"""

from __future__ import annotations

import math

from .options import Option

__all__ = ["ALIASES", "NEEDS", "OPTIONS", "TABLE", "markdown_table"]

INF = math.inf


def _n(name, meaning, unit, hard, plausible=None, typical="", **kw) -> Option:
    return Option(name, meaning, unit, "number", hard, plausible=plausible, typical=typical, **kw)


def _i(name, meaning, unit, hard, plausible=None, typical="", **kw) -> Option:
    return Option(name, meaning, unit, "integer", hard, plausible=plausible, typical=typical, **kw)


def _ns(name, meaning, unit, hard, plausible, separator, count=None, typical="", **kw) -> Option:
    return Option(
        name,
        meaning,
        unit,
        "numbers",
        hard,
        plausible=plausible,
        typical=typical,
        separator=separator,
        count=count,
        **kw,
    )


def _k(name, meaning, kind="text", **kw) -> Option:
    return Option(name, meaning, "", kind, **kw)


#: The table: one row an option, whichever commands take it.
TABLE: tuple[Option, ...] = (
    # --- the motion (every command that runs a motion)
    _n("--rate", "sample rate", "Hz", (0, 1e6), (10, 1e5), "rates are 100 to 10,000 Hz", open_low=True),
    _n(
        "--cycles",
        "number of built-in cycles",
        "cycles",
        (0, 1e7),
        (0.005, 100),
        "runs take 0.01 to 100 cycles",
        open_low=True,
        example="1",
        unit_slips=False,
    ),
    _n("--frequency", "cycle frequency", "Hz", (0, 100), (0.2, 5), "ISO 14242-1 runs at 1 Hz", open_low=True),
    _n("--period", "cycle period", "s", (0, 1e4), (0.2, 5), "ISO 14242-1's cycle lasts 1 s", open_low=True),
    _n(
        "--resample",
        "even sample rate for a file",
        "Hz",
        (0, 1e6),
        (20, 1e5),
        "rates are 100 to 10,000 Hz",
        open_low=True,
    ),
    _n(
        "--cutoff",
        "zero-phase low-pass cutoff",
        "Hz",
        (0, 1e5),
        (1, 500),
        "gait labs filter at 6 Hz, rig logs at 20 Hz",
        open_low=True,
    ),
    _k("--no-filter", "no low-pass filter of the measured signals", "flag"),
    _k("--trajectory", "trajectory file", "file"),
    _k("--columns", "column map of a trajectory file"),
    _k("--side", "which hip of an OpenSim file", "choice"),
    _k("--load-column", "column of the load F_e"),
    _k("--load", "load from a second file", "file"),
    _k("--load-scale", "scaling of a --load file (K or MIN:MAX in N)"),
    _k("--body-weight", "body weight for a load in %BW (kg, or N with the suffix N)"),
    # --- the machine, the output, the page
    _k("--params", "parameter file", "file"),
    _k("--set", "parameter override KEY=VALUE"),
    _k("--out", "where the result is written", "file"),
    _k("--summary-format", "summary on standard output: table or json", "choice"),
    _k("--title", "page title"),
    _k("--author", "page author"),
    _k("--rig", "rig name"),
    _k("--pdf", "also print the page to PDF", "flag"),
    _k("--report", "folder of the page", "file"),
    _k("--table", "per-sample table", "file"),
    _k("--strict", "a machine limit crossed is an error", "flag"),
    _k("--json", "also write the summary as JSON", "file", deprecated="--summary-format json > FILE"),
    # --- models and engines
    _k("--engine", "which model computes (analytic, pinocchio, mujoco)", "choice"),
    _k("--plant", "the simulated plant's model", "choice"),
    _k("--integrator", "MuJoCo's integrator", "choice"),
    _k("--controller", "the tracking controller", "choice"),
    _k("--mismatch", "plant off from the controller's model"),
    _n("--servo-rate", "servo rate", "Hz", (0, 1e6), (100, 1e5), "servo rates are 1 to 20 kHz", open_low=True),
    _n("--step", "integration step", "ms", (0, 100), (0.001, 10), "steps are 0.05 to 1 ms", open_low=True),
    _n("--timestep", "MuJoCo's time step", "ms", (0, 100), (0.001, 10), "steps are 0.05 to 1 ms", open_low=True),
    _n(
        "--torque-limit",
        "motor torque limit",
        "N·mm",
        (0, INF),
        (10, 1e6),
        "limits are 1,000 to 100,000 N·mm",
        open_low=True,
    ),
    _k("--flag-bad-poses", "mark unreachable poses instead of stopping", "flag"),
    _k("--iso-tolerance", "ISO 14242-1 tolerances of a verdict (alpha=3,...,load=3%,frequency=0.1)"),
    # --- wear
    _n(
        "--head-diameter",
        "femoral head diameter",
        "mm",
        (1, 100),
        (22, 60),
        "heads are 22–60 mm",
        slips=((0.5, "a radius, not a diameter"),),
    ),
    _n(
        "--wear-factor",
        "Archard's wear factor k",
        "mm³/(N·m)",
        (0, 1e-3),
        (1e-9, 1e-5),
        "UHMWPE on CoCr: k is 1e-8 to 1e-6 mm³/(N·m)",
        slips=((1e6, "in 10⁻⁶ mm³/(N·m)"),),
        tail=":",  # K:KIND (local or the contact-area law's), read by the command
    ),
    _n(
        "--area-law",
        "contact-area law's C",
        "1",
        (0, 1),
        (1e-7, 1e-4),
        "C is about 1e-5",
        open_low=True,
        example="1e-5",
    ),
    _k("--wear-law", "k against cross-shear, a CSV", "file"),
    _ns(
        "--cup-grid",
        "the cup grid's polar bands and azimuth sectors",
        "bands x sectors",
        (8, 2000),
        (10, 1000),
        "x",
        2,
        "grids are 30x60 to 180x360 (coarser grids misstate the worn area)",
        example="90x180",
    ),
    _n(
        "--cycle-time",
        "length of one wear cycle",
        "s",
        (0, 1e4),
        (0.2, 5),
        "ISO 14242-1's cycle lasts 1 s",
        open_low=True,
    ),
    _n(
        "--alike",
        "the tolerance within which two wear sources are alike",
        "%",
        (0, 100),
        (0.5, 50),
        "typical 1 to 20 %",
    ),
    _ns(
        "--cup-mount",
        "the cup's orientation α,β,γ",
        "deg",
        (-180, 180),
        (-60, 60),
        ",",
        3,
        "mounts tilt by 0 to 45°",
        example="5,-3,20",
        undetectable=("x0.001", "deg->rad", "zero", "negative"),  # small, zero and negative tilts are as right
    ),
    _k("--compare", "compare two wear sources"),
    _k("--iso-load", "the built-in ISO load at the motion's times", "flag"),
    _k("--moving", "which part the platform carries", "choice"),
    _k("--platform", "which platform of a stations output", "choice"),
    _k("--points", "cup points to compute at", "file"),
    _k("--self-check", "the wear model's analytic checks", "flag"),
    _k("--sequence", "Euler sequence of the angles"),
    _n(
        "--torque-constant",
        "motor torque constant",
        "N·m/A",
        (0, 1000),
        (0.01, 10),
        "servo motors have 0.1 to 5 N·m/A",
        open_low=True,
    ),
    # --- rig logs: compare, identify, calibrate, monitor
    _k("--log", "rig log(s)", "file"),
    _k("--validate", "held-out log(s) to check a fit on", "file"),
    _n(
        "--log-period",
        "the log's period (0: not periodic)",
        "s",
        (0, 1e4),
        (0.2, 5),
        "gait logs repeat every 1 s",
        special=(0.0,),
        undetectable=("zero",),  # 0 means "not periodic"
    ),
    _n("--accept", "largest RMS error accepted", "%", (0, 100), (1, 50), "verdicts accept 5 to 20 %", open_low=True),
    _n(
        "--angle-tolerance",
        "largest disagreement of attitude sensor and encoders",
        "deg",
        (0, 90),
        (0.05, 10),
        "sensors agree within 0.1 to 2°",
        open_low=True,
    ),
    _k("--prior", "prior standard deviations NAME=STD,... in the parameters' units"),
    _n(
        "--chain-prior",
        "prior standard deviation of every per-chain value",
        "mm",
        (0, 100),
        (0.01, 10),
        "machined parts deviate by 0.05 to 2 mm",
        open_low=True,
    ),
    _k("--fix", "parameters held at their starting values"),
    _k("--base", "print the base parameters and stop", "flag"),
    _k("--spin-free-levers", "levers without the universal joints' spin", "flag"),
    _k("--no-plausibility-check", "skip the check of the logged signals", "flag"),
    _k("--force", "write an implausible fit, its warning kept in the provenance", "flag"),
    _k("--sensor-offset", "estimate a sensor offset per log", "choice"),
    _ns(
        "--baseline",
        "the baseline's cycles FROM:TO",
        "cycles",
        (0, 1e12),
        (1000, 1e8),
        ":",
        2,
        "baselines start after running-in, 250,000 to 1,000,000 cycles",
        example="250000:750000",
    ),
    _n(
        "--alarm-rise",
        "the alarm's change of the hip friction coefficient",
        "1",
        (0, 1),
        (0.002, 0.1),
        "alarms are set at 0.005 to 0.05",
        open_low=True,
        open_high=True,
    ),
    _i("--window", "a window's length in a long log", "cycles", (1, 1e9), (2, 1e4), example="100"),
    _n(
        "--poll",
        "the time between looks at the logs",
        "s",
        (0, 86400),
        (1, 3600),
        "polls every 10 s to 10 min",
        open_low=True,
    ),
    _n(
        "--settle",
        "the settling time of a log being written",
        "s",
        (0, 3600),
        (0.5, 600),
        "typical 1 to 60 s",
        special=(0.0,),
        undetectable=("zero",),  # 0: no wait, for logs written whole
    ),
    _k("--watch", "keep watching the logs", "flag"),
    _k("--on-alarm", "command run on an alarm"),
    _k("--restart", "replace an existing --out", "flag"),
    # --- workers
    _i("--workers", "worker processes (1: in this process)", "processes", (1, 4096), (1, 256)),
    _k("--scheduler", "a running dask scheduler's address"),
    _i("--batch-size", "variants per task", "variants", (1, 1e9), (1, 10000)),
    # --- stations
    _k("--control", "which platform the carriages serve", "choice"),
    _ns("--weights", "weights of the two platforms' squared errors", "1", (0, 1e6), (0.01, 10), ",", 2, example="1,1"),
    _k("--bands", "per-chain deviation bands FILE or KEY=V,... in mm"),
    _i("--draws", "machines drawn", "draws", (1, 1e8), (20, 1e6), "100 to 10,000 draws"),
    _i("--seed", "random seed", "", (0, 2**32 - 1), corpus=False),
    _k("--sliders", "a log's carriages", "file"),
    # --- sweep
    _k("--grid", "a sweep's grid axis KEY=START:STOP:STEP in the key's unit"),
    _k("--variants", "a CSV of variants", "file"),
    _k("--range", "a key's range KEY=LOW:HIGH for --sample"),
    _i("--sample", "random variants drawn", "variants", (1, 1e9), (2, 1e6)),
    _k("--spread", "a key's spread KEY=SIGMA or KEY=±X for --sample"),
    _k("--pareto", "Pareto front of two columns X,Y"),
    _k("--drive", "drive file", "file"),
    # --- size
    _k("--catalogue", "motor catalogue", "file"),
    _k("--screws", "lead screw catalogue", "file"),
    _k("--gearboxes", "gearbox catalogue", "file"),
    _k("--rank", "catalogue order", "choice"),
    _i("--top", "best catalogue combinations shown", "combinations", (1, 1e9), (1, 1000), example="10"),
    _n(
        "--inertia-ratio",
        "largest load-to-rotor inertia ratio",
        "1",
        (0, 1e4),
        (1, 100),
        "drives allow 5 to 30",
        open_low=True,
    ),
    _n(
        "--life-cycles",
        "screw L10 life to reach",
        "cycles",
        (0, 1e12),
        (1e5, 1e9),
        "tests run 5 to 20 million cycles",
        open_low=True,
    ),
    _k("--without-iso", "leave out the built-in ISO cycle", "flag"),
    _k("--motor", "drive file to check", "file"),
    _k("--simulate", "also simulate both controllers", "flag"),
    # --- excite
    _n(
        "--duration", "length of the excitation", "s", (0, 1e5), (1, 3600), "excitations last 10 to 60 s", open_low=True
    ),
    _i("--harmonics", "harmonics per series", "harmonics", (1, 1000), (1, 30)),
    _i("--iterations", "optimiser iterations per start", "iterations", (1, 1e7), (1, 10000)),
    _i("--seeds", "random starts of the optimiser", "starts", (1, 10000), (1, 100)),
    _ns(
        "--load-range",
        "the load range MIN:MAX",
        "N",
        (0, 1e5),
        (10, 5000),
        ":",
        2,
        "ISO 14242-1: 300 to 3000 N",
        example="300:3000",
    ),
    _n("--max-acceleration", "slider acceleration limit", "mm/s²", (0, 1e7), (100, 1e5), open_low=True),
    _n("--max-angle", "largest |angle|", "deg", (0, 90), (3, 60), "gait angles reach 10 to 45°", open_low=True),
    _n(
        "--max-speed",
        "slider speed limit",
        "mm/s",
        (0, 1e5),
        (10, 5000),
        "sliders run at 50 to 1000 mm/s",
        open_low=True,
    ),
    _n("--min-cond-inv", "smallest singularity measure", "1", (0, 1), (0.01, 0.9), open_low=True),
    _k("--for", "what the motion is for", "choice"),
    # --- view, urdf, mjcf, workspace
    _i("--fps", "frames per second of playback", "fps", (1, 1000), (5, 240)),
    _n("--speed", "playback speed", "×", (0, 1000), (0.01, 100), open_low=True),
    _k("--frame-by-frame", "one frame per Enter", "flag"),
    _k("--html", "write an offline page", "file"),
    _k("--human", "the human model's hip beside the machine", "flag"),
    _k("--forces", "arrows for the forces", "flag"),
    _k("--singularity", "colour the levers by the singularity measure", "flag"),
    _k("--closures", "also write the closure file", "file"),
    _ns(
        "--deltas",
        "the offsets δ A:B:STEP",
        "deg",
        (-180, 180),
        (-180, 180),
        ":",
        3,
        example="-90:90:1",
        undetectable=("x0.001", "deg->rad", "zero", "negative"),  # the command checks START < STOP, STEP > 0
    ),
    _ns(
        "--gamma",
        "the rotations γ",
        "deg",
        (-180, 180),
        (-90, 90),
        ",",
        example="-12,-8,-4,0,4",
        undetectable=("x0.001", "deg->rad", "zero", "negative"),  # small and negative rotations are as right
    ),
)

#: Options the branches of this round add (issue 48's note: declared here as they merge; a row for an option no
#: command has yet is harmless, and the corpus covers it once a command adds it).
PARALLEL: tuple[Option, ...] = (
    # simulate's plant (issue 44)
    _k("--plant-params", "the plant's own machine file", "file"),
    _k("--feedback", "what closes the loop: encoders or sensors", "choice"),
    _n(
        "--encoder-step",
        "the encoders' resolution in carriage travel",
        "mm",
        (0, 1),
        (1e-5, 0.1),
        "encoders resolve 0.1 to 10 µm",
        special=(0.0,),
        undetectable=("zero",),  # 0: exact encoders
        example="0.001",
    ),
    _n(
        "--sensor-noise",
        "the attitude sensor's white noise",
        "deg",
        (0, 5),
        (0.001, 1),
        "sensors are 0.01 to 0.2° noisy",
        special=(0.0,),
        undetectable=("zero",),  # 0: a noiseless sensor
        example="0.05",
    ),
    _n(
        "--sensor-drift",
        "the sensor zero's drift",
        "deg/min",
        (-10, 10),
        (-1, 1),
        "zeros drift by under 0.1°/min",
        example="0.01",
        undetectable=("x0.001", "zero", "negative", "deg->rad", "rad->deg"),  # small, none, either sign: as right
    ),
    _i("--sensor-seed", "the sensor noise's seed", "", (0, 2**32 - 1), corpus=False),
    _k("--fig7", "also draw the paper's Fig. 7", "flag"),
    # learn and export (issue 45)
    _k("--commands", "the carriage command file", "file"),
    _k("--previous", "the command file the logged run executed", "file"),
    _i("--learn", "cycles of learning", "cycles", (1, 100), (1, 50), example="10"),
    _n("--counts-per-rev", "encoder counts per motor revolution", "counts", (1, 1e9), (100, 1e6), example="10000"),
    _n("--gain", "the learning gain γ", "1", (0, 10), (0.05, 2), "gains are 0.3 to 1", open_low=True, example="0.5"),
    _n(
        "--q-cutoff", "the learning filter's cutoff", "Hz", (0, 1e5), (1, 100), "Q filters at 5 to 30 Hz", open_low=True
    ),
    _n(
        "--drive-lag",
        "the drive position loop's time constant",
        "ms",
        (0, 1000),
        (0.1, 100),
        "drives lag 1 to 20 ms",
        special=(0.0,),
        undetectable=("zero",),  # 0: no lag
        example="5",
    ),
    # the monitor's files (weario)
    _i("--baseline-min", "snapshots the baseline needs", "snapshots", (2, 1e9), (3, 1000), example="5"),
    _i(
        "--acknowledge",
        "alarms acknowledged up to this cycle",
        "cycles",
        (0, 1e13),
        (1e4, 1e8),
        "alarms are acknowledged at 0.1 to 20 million cycles",
        example="1000000",
    ),
    # the gravimetric report (wearreport)
    _k("--weighings", "the cups' weighings", "file"),
    _n("--density", "the cups' density", "mg/mm³", (0, 25), (0.5, 2), "UHMWPE: 0.935 mg/mm³", open_low=True),
    _n(
        "--balance-noise",
        "the balance's noise, one reading's standard deviation",
        "mg",
        (0, 100),
        (0.001, 1),
        "a microbalance reads a cup to 0.01 to 0.1 mg (a value in g or µg?)",
        open_low=True,
    ),
    _i(
        "--from",
        "the steady-state rate from this cycle",
        "cycles",
        (0, 1e13),
        (1e4, 1e8),
        "bedding-in lasts 0.5 to 2 million cycles",
        example="1000000",
    ),
    _k("--station", "the motion a station had NAME=SOURCE"),
    _k("--snapshots", "the monitor's snapshot logs", "file"),
    _k("--friction", "the monitor's table", "file"),
    _k("--test", "a test's folder", "file"),
)

TABLE = TABLE + PARALLEL

#: The table by name.
OPTIONS: dict[str, Option] = {option.name: option for option in TABLE}

#: Options that do nothing without another, per command: typed without it, refused (never silently ignored).
#: (Conditions on a value, --weights with --control both, --alike with --compare, are the commands' own checks.)
NEEDS: dict[str, dict[str, str]] = {
    "stations": {"--draws": "--bands", "--seed": "--bands"},
    "sweep": {"--seed": "--sample"},
    "monitor": {"--poll": "--watch"},  # --on-alarm without --watch: the command says so itself
}

#: Old spellings kept one minor version, per command: old → new. Each warns when used.
ALIASES: dict[str, dict[str, str]] = {
    "torques": {"--model": "--engine"},
    "report": {"--model": "--engine"},
    "sweep": {"--model": "--engine", "--tolerance": "--spread"},
    "simulate": {"--tolerance": "--iso-tolerance", "--mujoco-integrator": "--integrator"},
    "iso-check": {"--tolerance": "--iso-tolerance"},
    "wear": {"--tolerance": "--alike", "--grid": "--cup-grid"},
    "stations": {"--tolerance": "--bands"},
    "compare": {"--tolerance": "--angle-tolerance", "--period": "--log-period"},
    "identify": {"--tolerance": "--angle-tolerance"},
    "calibrate": {"--prior": "--chain-prior"},
    "size": {"--format": "--summary-format"},
    "excite": {"--load": "--load-range"},
    "view": {"--step": "--frame-by-frame"},
}


def markdown_table() -> str:
    """The numeric options as the docs show them (docs/guide/robust-inputs.md; a test holds the page to it)."""
    lines = [
        "| option | meaning | unit | hard range (else refused) | plausible (else warned) |",
        "|---|---|---|---|---|",
    ]
    for option in sorted((o for o in TABLE if o.numeric), key=lambda o: o.name):
        unit = "—" if option.unit in ("", "1") else option.unit
        plausible = "—" if option.plausible is None else f"{option.plausible[0]:g} to {option.plausible[1]:g}"
        lines.append(f"| `{option.name}` | {option.meaning} | {unit} | {option.range_text()} | {plausible} |")
    return "\n".join(lines) + "\n"
