"""The corpus of slips (issue 48): for every command and every numeric option, the slips a user makes, each refused or warned.

The corpus is generated from the option table (hipsim/cli/option_table.py): a
new option is covered as soon as it is declared. Each slip is checked where it
enters, through the command's own parser (the converter argparse calls for
that option of that command): no run. A sample goes end to end through
``main``.
"""

from __future__ import annotations

import argparse
import math
import re
from collections.abc import Callable

import numpy as np
import pytest

from hipsim.cli.main import build_parser, main
from hipsim.cli.option_table import ALIASES, OPTIONS, TABLE
from hipsim.cli.options import Option, read_number
from hipsim.cli.parser import command_parsers

#: The slips: name → what it does to one typed number.
SLIPS = {
    "x1000": lambda v: v * 1e3,
    "x0.001": lambda v: v * 1e-3,
    "deg->rad": lambda v: v * math.pi / 180.0,  # degrees meant, radians typed
    "rad->deg": lambda v: v * 180.0 / math.pi,
    "percent": lambda v: v * 100.0,  # a fraction meant, a percentage typed
    "zero": lambda v: 0.0,
    "negative": lambda v: -abs(v) if v else -1.0,
    "nan": lambda v: math.nan,
}
#: Which slips apply to a unit: angles are slipped in deg↔rad, fractions in %, every unit in the rest.
ANGLE_UNITS = {"deg"}
FRACTION_UNITS = {"1", "%"}


def example(option: Option) -> str:
    """A right value of the option as typed: its declared example, else the middle of its plausible range."""
    if option.example:
        return option.example
    low, high = option.plausible or option.hard
    value = math.sqrt(low * high) if low > 0 else (low + high) / 2
    return str(round(value)) if option.kind == "integer" else f"{value:.6g}"


def slipped(option: Option, text: str, slip: str) -> str:
    """The option's text with every number in it slipped."""
    parts = text.split(option.separator) if option.kind == "numbers" else [text]
    out = []
    for part in parts:
        value = SLIPS[slip](float(part))
        out.append("nan" if math.isnan(value) else f"{value:.10g}")
    return option.separator.join(out)


def applies(option: Option, slip: str) -> bool:
    if slip in ("deg->rad", "rad->deg"):
        return option.unit in ANGLE_UNITS
    if slip == "percent":
        return option.unit in FRACTION_UNITS
    return True


def corpus():
    """(command, option, slip, text) for every command's numeric options in the table."""
    parser = build_parser()
    for command, sub in sorted(command_parsers(parser).items()):
        for name in sorted({a.option_strings[0] for a in sub._actions if a.option_strings}):
            option = OPTIONS.get(name)
            if option is None or not option.numeric or not option.corpus:
                continue
            for slip in SLIPS:
                if applies(option, slip):
                    yield command, name, slip, slipped(option, example(option), slip)


CORPUS = list(corpus())
PARSERS = command_parsers(build_parser())


def outcome(command: str, name: str, text: str, capsys) -> str:
    """'refused', 'warned' or 'accepted': the command's own converter of the option on the text."""
    convert = PARSERS[command]._option_string_actions[name].type
    assert callable(convert)
    try:
        convert(text)
    except argparse.ArgumentTypeError:
        return "refused"
    err = capsys.readouterr().err
    return "warned" if err.startswith(f"hipsim: warning: {name}") else "accepted"


#: The corpus by (command, option): one test each, its slips checked together (a test per slip costs the suite time).
GROUPS: dict[tuple[str, str], list[tuple[str, str]]] = {}
for _command, _name, _slip, _text in CORPUS:
    GROUPS.setdefault((_command, _name), []).append((_slip, _text))


@pytest.mark.parametrize(("command", "name"), list(GROUPS), ids=[f"{c} {n}" for c, n in GROUPS])
def test_every_slip_is_refused_or_warned(command, name, capsys):
    option = OPTIONS[name]
    wrong = []
    for slip, text in GROUPS[command, name]:
        result = outcome(command, name, text, capsys)
        if slip in option.undetectable:
            if result != "accepted":
                wrong.append(f"{slip} ({text}) is declared undetectable but is {result}")
        elif result not in ("refused", "warned"):
            wrong.append(f"{slip} ({text}) is accepted without a word")
    assert not wrong, f"hipsim {command} {name}: " + "; ".join(wrong)


def test_the_corpus_covers_every_command_with_numeric_options():
    commands = {c for c, *_ in CORPUS}
    assert {"torques", "simulate", "wear", "monitor", "stations", "calibrate", "identify", "size", "excite"} <= commands
    assert len(CORPUS) > 500  # every command × every numeric option × the slips that apply to its unit


@pytest.mark.parametrize("option", [o for o in TABLE if o.numeric and o.corpus], ids=lambda o: o.name)
def test_each_example_is_right(option):
    """The corpus slips a right value: its example must pass without a word."""
    values, warnings, refusal = read_number(option, example(option))
    assert values and not warnings and refusal is None, (option.name, warnings, refusal)


def test_every_option_is_declared_in_the_table():
    from hipsim.cli.parser import undeclared

    assert undeclared(build_parser()) == [], "declare these in hipsim/cli/option_table.py"


def test_no_name_has_two_meanings():
    names = [o.name for o in TABLE]
    assert len(names) == len(set(names)), "an option declared twice"
    parser = build_parser()
    dests: dict[str, set] = {}
    for sub in command_parsers(parser).values():
        for action in sub._actions:
            for name in action.option_strings:
                if name.startswith("--") and name != "--help":
                    dests.setdefault(name, set()).add(action.dest)  # one name, one value it sets (its arity may differ)
    two = {name: d for name, d in dests.items() if len(d) > 1}
    assert not two, f"options read two ways by different commands: {two}"
    for command, aliases in ALIASES.items():  # an old spelling is no current option of its command
        current = set(PARSERS[command]._option_string_actions)
        assert not set(aliases) & current, command
        assert set(aliases.values()) <= current, command


def test_every_numeric_option_shows_its_unit_in_help():
    parser = build_parser()
    for command, sub in command_parsers(parser).items():
        text = re.sub(r"\s+", " ", sub.format_help())
        for action in sub._actions:
            option = OPTIONS.get(action.option_strings[0]) if action.option_strings else None
            if option is None or not option.numeric or action.help == argparse.SUPPRESS:
                continue
            shown = "dimensionless" if option.unit == "1" else option.unit
            assert f"unit: {shown}" in text, f"hipsim {command} --help: {option.name} without its unit"


# --------------------------------------------------------------------------- a sample end to end


def run(argv, capsys):
    status = main(argv)
    captured = capsys.readouterr()
    return status, captured.out, captured.err


def test_a_head_in_metres_is_refused_in_one_line_and_nothing_is_written(tmp_path, capsys):
    out = tmp_path / "w.csv"
    status, _, err = run(["wear", "--head-diameter", "0.028", "--out", str(out)], capsys)
    assert status == 2 and not out.exists()
    assert err.strip().count("\n") == 0
    assert err.startswith("hipsim: error: wear: --head-diameter 0.028 mm: femoral head diameter must be at least 1")
    assert "in metres?" in err and "heads are 22–60 mm" in err


def test_the_issues_numbers_are_each_refused_or_warned(capsys):
    issue = [
        ("wear", "--head-diameter", "0.028", "refused"),
        ("wear", "--head-diameter", "14", "warned"),
        ("wear", "--wear-factor", "8e-11", "warned"),
        ("wear", "--wear-factor", "0.08", "refused"),
        ("wear", "--cup-grid", "1x1", "refused"),
        ("wear", "--cycles", "0", "refused"),
        ("wear", "--rate", "5", "warned"),
        ("monitor", "--cutoff", "0", "refused"),
        ("monitor", "--cutoff", "-1", "refused"),
        ("monitor", "--baseline", "0.5:1", "warned"),
        ("monitor", "--alarm-rise", "1", "refused"),
        ("calibrate", "--chain-prior", "0.0005", "warned"),
        ("compare", "--torque-constant", "360", "warned"),
    ]
    for command, name, text, expected in issue:
        assert outcome(command, name, text, capsys) == expected, (command, name, text)


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        # no abbreviation of --controller (--control is an option of its own since issue 44: the controlled platform)
        (["simulate", "--controll", "pd"], "unrecognized arguments: --controll pd"),
        (["stations", "--weights", "-1,1"], "--weights '-1,1': -1: weights of the two platforms' squared errors"),
        (["monitor", "--cutoff", "0"], "--cutoff 0 Hz: zero-phase low-pass cutoff must be above 0"),
        (["torques", "--no-such-option"], "unrecognized arguments: --no-such-option"),
    ],
)
def test_usage_errors_are_one_line(argv, message, capsys):
    status, _, err = run(argv, capsys)
    assert status == 2 and err.count("\n") == 1 and err.startswith("hipsim: error:") and message in err, err


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["stations", "--draws", "50"], "stations: --draws applies to --bands: give --bands, or drop --draws"),
        (["sweep", "--seed", "3"], "sweep: --seed applies to --sample: give --sample, or drop --seed"),
        (["monitor", "--poll=5", "--params", "p.toml", "--log", "x"], "monitor: --poll applies to --watch"),
    ],
)
def test_an_option_that_would_do_nothing_is_refused(argv, message, capsys):
    status, _, err = run(argv, capsys)
    assert status == 2 and err == f"hipsim: error: {message}" + err[len(f"hipsim: error: {message}") :]
    assert err.count("\n") == 1 and message in err


def test_an_old_spelling_warns_and_means_the_new(capsys):
    parser = build_parser()
    from hipsim.cli.parser import rewrite_aliases

    words = rewrite_aliases(["torques", "--model=pinocchio", "--rate", "100"])
    assert words == ["torques", "--engine=pinocchio", "--rate", "100"]
    assert "--model is deprecated in 'hipsim torques': use --engine" in capsys.readouterr().err
    assert parser.parse_args(words).engine == "pinocchio"
    assert rewrite_aliases(["wear", "--tolerance", "3"]) == ["wear", "--alike", "3"]
    assert rewrite_aliases(["stations", "--tolerance", "all=0.1"]) == ["stations", "--bands", "all=0.1"]


def test_the_docs_show_the_table():
    from pathlib import Path

    from hipsim.cli.option_table import markdown_table

    page = (Path(__file__).resolve().parents[2] / "docs" / "guide" / "robust-inputs.md").read_text()
    assert markdown_table() in page, "docs/guide/robust-inputs.md: paste hipsim.cli.option_table.markdown_table()"


# --------------------------------------------------------------------------- input files' columns: the issue's slips


@pytest.mark.parametrize(
    ("rows", "message"),
    [
        (
            "0,1e-7\n20,5e-7\n",
            "line 3, column 'cross_shear': cross-shear 20: CS is a ratio from 0 to 0.5; is the column in per cent?",
        ),
        ("0,1e-10\n0.2,5e-10\n", "line 2, column 'k_mm3_per_Nm': a wear factor 1e-10 mm³/(N·m) is 1/1000 of UHMWPE's"),
        ("0,1e-7\n0.2,0.5\n", "line 3, column 'k_mm3_per_Nm': a wear factor 0.5 mm³/(N·m) is"),
    ],
)
def test_a_wear_law_table_in_per_cent_or_per_newton_millimetre_is_refused(tmp_path, rows, message):
    from hipsim.exceptions import FileRowError
    from hipsim.wear.laws import read_wear_law

    path = tmp_path / "law.csv"
    path.write_text("cross_shear,k_mm3_per_Nm\n" + rows)
    with pytest.raises(FileRowError) as error:
        read_wear_law(path)
    assert message in str(error.value)
    path.write_text("cross_shear,k_mm3_per_Nm\n0,1e-7\n0.2,5e-7\n")
    assert read_wear_law(path) is not None  # the same table, right


@pytest.mark.parametrize(
    ("line", "key"),
    [
        ("torque_constant_Nm_A = 0.36 ", "torque_constant_Nm_A = 360  "),
        ("preload_N = 350 ", "preload_N = 0.35"),
    ],
)
def test_a_drive_with_a_torque_constant_or_preload_off_by_1000_is_refused(tmp_path, line, key, capsys):
    from pathlib import Path

    drive = (Path(__file__).resolve().parents[2] / "models" / "drive_example.toml").read_text()
    assert line in drive
    path = tmp_path / "drive.toml"
    path.write_text(drive.replace(line, key))
    assert main(["size", "--drive", str(path), "--rate", "100"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "a unit slip by" in err and key.split("_")[0] in err


def test_json_file_is_deprecated_with_a_warning(capsys):
    args = build_parser().parse_args(["calibrate", "--log", "a.csv", "--out", "c.toml", "--json", "c.json"])
    assert args.json == "c.json"  # still written, for this minor version
    assert capsys.readouterr().err == "hipsim: warning: --json is deprecated: use --summary-format json > FILE\n"


# --------------------------------------------------------------------------- a trajectory file's columns

#: The slips a reader cannot tell from a right file, and why (the corpus holds them accepted).
COLUMN_UNDETECTABLE = {
    ("alpha_deg", "zero"): "a still angle is a planar model's",
    ("beta_deg", "zero"): "a still angle is a planar model's",
    ("gamma_deg", "zero"): "a still angle is a planar model's",
    ("alpha_deg", "negative"): "a sign is a convention the file's own (--columns -COL flips it)",
    ("beta_deg", "negative"): "a sign is a convention the file's own",
    ("gamma_deg", "negative"): "a sign is a convention the file's own",
    ("Fe_N", "zero"): "a test without load (torques warns of the friction the ISO load would add)",
    ("swap", "alpha_deg/gamma_deg"): "any angle may be the widest on this machine's axes",
    ("swap", "beta_deg/gamma_deg"): "as above",
}
COLUMN_SLIPS: dict[str, Callable[[np.ndarray], np.ndarray]] = {
    "x1000": lambda v: v * 1e3,
    "x0.001": lambda v: v * 1e-3,
    "deg->rad": np.radians,
    "percent": lambda v: v * 100.0,
    "zero": lambda v: v * 0.0,
    "negative": lambda v: -v,
    "nan": lambda v: np.where(np.arange(v.size) == 5, np.nan, v),
}


def _iso_columns():
    from hipsim.motion.trajectories import iso14242

    iso = iso14242(rate=100, cycles=1)
    q = np.degrees(iso.q)
    return {"t_s": iso.t, "alpha_deg": q[:, 0], "beta_deg": q[:, 1], "gamma_deg": q[:, 2], "Fe_N": iso.Fe}


def _column_corpus():
    columns = _iso_columns()
    for name in columns:
        for slip, change in COLUMN_SLIPS.items():
            if (slip == "deg->rad" and not name.endswith("_deg")) or (slip == "percent" and name != "Fe_N"):
                continue
            yield name, slip, {**columns, name: change(np.asarray(columns[name], dtype=float))}
    for a, b in (("alpha_deg", "gamma_deg"), ("beta_deg", "gamma_deg"), ("t_s", "Fe_N")):
        yield "swap", f"{a}/{b}", {**columns, a: columns[b], b: columns[a]}


def test_every_column_slip_of_a_trajectory_file_is_refused_or_warned(tmp_path):
    import warnings

    from hipsim.exceptions import HipsimError
    from hipsim.motion import read_trajectory

    wrong = []
    for name, slip, columns in _column_corpus():
        path = tmp_path / "x.csv"
        header = ",".join(columns)
        np.savetxt(
            path, np.column_stack(list(columns.values())), delimiter=",", header=header, comments="", fmt="%.10g"
        )
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                read_trajectory(path)
                result = "warned" if caught else "accepted"
            except HipsimError:
                result = "refused"
        if ((name, slip) in COLUMN_UNDETECTABLE) != (result == "accepted"):
            wrong.append(f"{name} {slip}: {result}")
    assert not wrong, wrong


def test_one_angle_in_radians_among_degrees_is_named_at_its_boundaries():
    from hipsim.plausibility import SMALL_RANGE_DEG, one_radians_slip

    assert one_radians_slip(np.array([43.0, 0.12, 10.0])) == [(1, pytest.approx(0.12 * 180 / math.pi))]
    assert one_radians_slip(np.array([43.0, 0.0, 10.0])) == []  # a still angle: a planar model's
    assert one_radians_slip(np.array([43.0, SMALL_RANGE_DEG, 10.0])) == []  # at the limit: a degree is a real span
    assert one_radians_slip(np.array([4.99, 0.12, 3.0])) == []  # no angle spans a gait's range: nothing to compare with
    assert one_radians_slip(np.array([0.7, 0.12, 0.2])) == []  # all small: radians_slip's case, not this one
