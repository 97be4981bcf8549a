"""What the charts and the checks find, per snapshot and over the test: alarms and notices (which station, which way),
the worst case of a shared load, the load cell, snapshots missing from the sequence, incomplete and duplicate ones.

The two stations' mean is charted always (:func:`~hipsim.rig.monitoring.control_chart.chart`, ``worst`` = 2 on a
two-station machine: a change d of the mean is up to 2d in one station); each station's own term is charted too
when the logs separate the stations (per-station loads that vary differently) in at least the baseline's
snapshots. A snapshot whose stations are separated is judged by its stations' charts (full threshold, the station
named); any other by the mean's worst case.

A change of the load term is the specimen's friction *or* the load cell's calibration: the fit sees the friction
moment per newton *measured*, so a load cell reading (1 + g) times the true load gives a/(1 + g): a gain drift g
reads as Δμ_h = −g/(1 + g)·a₀/r_h (±3 % as ∓0.005 on the published machine). Every flag's sentence says so, with
the drift that would explain the change; where the logs carry the commanded load (``Fe_cmd_N``) the measured over
commanded load per snapshot (``load_gain``) is compared with its baseline mean and a drift beyond
:data:`LOAD_GAIN_DRIFT` is flagged in the snapshot's note.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ...exceptions import ArgumentError
from ...records import Record
from .control_chart import MIN_BASELINE, Chart, chart
from .snapshots import Skipped

__all__ = [
    "INCOMPLETE",
    "LOAD_GAIN_DRIFT",
    "Finding",
    "Findings",
    "change_text",
    "duplicates",
    "check_acknowledged",
    "find",
    "hold",
    "load_cell_text",
    "missing_cycles",
]

#: A snapshot with fewer samples than this fraction of the median snapshot's is marked incomplete.
INCOMPLETE = 0.9
#: A drift of the measured over the commanded load beyond this fraction since the baseline is flagged.
LOAD_GAIN_DRIFT = 0.01


@dataclass(frozen=True, eq=False)
class Findings:
    """The charts over the rows and what they find.

    Attributes:
        mean: the chart of the two stations' mean (or the one station's) load term.
        stations: the per-station charts (station 1, station 2), or None when the logs do not separate them.
        flag: per snapshot the flag's text ("" none; "alarm: …", "notice: …").
        alarm: per snapshot 1 for an alarm, else 0.
        first: the first alarm's description (JSON-ready), or None.
        latest_notice: the last notice's description, or None.
        load_gain_change: per snapshot the measured over commanded load relative to its baseline mean, minus 1 (NaN
            without the commanded load or its baseline).
        notes: per snapshot the notes (incomplete, cut, load-cell drift).
        state: per snapshot "ALARM" (an alarm raised here or before and not acknowledged), "NOTICE", "OK", or
            "NO BASELINE" (:func:`hold`).
        acknowledged: per snapshot the cycle of the acknowledgement that takes effect there (NaN: none).
        raised_at: the first cycle of the alarm held at the last snapshot, or None.
    """

    mean: Chart
    stations: tuple[Chart, Chart] | None
    flag: list[str]
    alarm: np.ndarray
    first: Finding | None
    latest_notice: Finding | None
    load_gain_change: np.ndarray
    notes: list[str]
    state: list[str]
    acknowledged: np.ndarray
    raised_at: int | None

    @property
    def alarm_held(self) -> bool:
        """Whether an alarm is held at the last snapshot (raised and not acknowledged): exit status 1."""
        return bool(self.state) and self.state[-1] == "ALARM"

    def acknowledgements(self) -> tuple[int, ...]:
        """The acknowledged cycles recorded in the table, ascending."""
        return tuple(int(a) for a in self.acknowledged[np.isfinite(self.acknowledged)])


def _gain_for(change: float, a0_mm: float, hip_radius_mm: float) -> float:
    """The load-cell gain drift g that alone reads as a change ``change`` of μ_h: a₀/(a₀ + Δa) − 1."""
    return a0_mm / (a0_mm + change * hip_radius_mm) - 1.0


def load_cell_text(change: float, a0_mm: float, hip_radius_mm: float, gain_change: float = math.nan) -> str:
    """The sentence on the load-cell alternative to a change of μ_h, and what the commanded load says when logged.

    Args:
        change: the change of μ_h.
        a0_mm: the baseline's load term in [mm].
        hip_radius_mm: r_h in [mm].
        gain_change: the snapshot's measured over commanded load relative to the baseline's, minus 1 (NaN: not logged).
    """
    g = _gain_for(change, a0_mm, hip_radius_mm)
    three = 0.03 / 1.03 * a0_mm / hip_radius_mm
    text = (
        "or the load cell's calibration: the load term cannot tell friction from a load-cell gain drift, and a drift "
        f"of {100 * g:+.1f} % alone reads as this change (±3 % reads as ∓{three:.4f}); "
    )
    if not math.isfinite(gain_change):
        return text + (
            "tell them apart by checking the load cell against a reference load, or log the commanded load "
            "(Fe_cmd_N) to compare with the measured one per snapshot"
        )
    if abs(gain_change) > LOAD_GAIN_DRIFT:
        return text + (
            f"the commanded load logged with it says the measured load drifted by {100 * gain_change:+.1f} % since "
            "the baseline: check the load cell's calibration"
        )
    return text + (
        f"the commanded load logged with it agrees with the measured one within {LOAD_GAIN_DRIFT:.0%} of the "
        "baseline's ratio: not the load cell"
    )


def change_text(change: float, worst: float, where: str) -> str:
    """``"+0.0074 in the two stations' mean: up to +0.015 in one of them"``, or ``"+0.015 in station 2"``."""
    if worst > 1:
        return f"{change:+.4f} in the two stations' mean: up to {worst * change:+.4f} in one of them"
    return f"{change:+.4f} in {where}"


@dataclass(frozen=True)
class Finding(Record):
    """An alarm or a notice as the summary says it: the snapshot (first cycle, file), alarm or notice, where (the
    stations' mean, a station), rise or fall, the change of μ_h and its standard deviation, the worst case in one
    station, the load friction term and its change from the baseline in [mm], and the sentence."""

    cycle: int
    file: str
    kind: str
    where: str
    direction: str
    hip_mu_change: float
    hip_mu_change_std: float
    worst_case_change: float
    load_friction_mm: float
    load_friction_change_mm: float
    text: str


def _describe(
    k: int, rows, c: Chart, where: str, a0_mm: float, hip_radius_mm: float, kind: str, gain_change: float
) -> Finding:
    change = float(c.change[k])
    return Finding(
        int(rows[k]["cycle"]),
        str(rows[k]["file"]),
        kind,
        where,
        "rise" if change > 0 else "fall",
        change,
        float(c.change_std[k]),
        c.worst * change,
        float(rows[k]["load_friction_mm"]),
        float(rows[k]["load_friction_mm"]) - c.mean,
        f"{kind}: the hip friction coefficient {'rose' if change > 0 else 'fell'} by "
        + change_text(change, c.worst, where)
        + f" ± {c.change_std[k] * c.worst:.2g}: the specimen's friction, "
        + load_cell_text(change, a0_mm, hip_radius_mm, gain_change),
    )


def hold(
    cycles: Sequence[int],
    alarm: Sequence[int] | np.ndarray,
    flag: Sequence[str],
    acknowledge: Sequence[int],
    charted: bool = True,
) -> tuple[list[str], np.ndarray, int | None]:
    """An alarm held until acknowledged: each snapshot's state, where each acknowledgement is recorded, the alarm held.

    An acknowledgement at cycle C acknowledges every alarm raised at a snapshot of first cycle ≤ C, from the first
    snapshot of cycle ≥ C on (there it is recorded); an alarm raised after C is held anew. A snapshot's state is
    "ALARM" while an alarm raised there or before is not acknowledged, else "NOTICE" for a notice, else "OK"
    ("NO BASELINE" throughout while the chart cannot start, ``charted`` False).

    Args:
        cycles: each snapshot's first cycle, ascending.
        alarm: 1 where the snapshot is an alarm.
        flag: each snapshot's flag ("notice: …" for a notice).
        acknowledge: acknowledged cycles.
        charted: whether the chart could start.

    Returns:
        (state per snapshot, acknowledged cycle recorded per snapshot (NaN: none), first cycle of the alarm held at
        the last snapshot or None).
    """
    acks = sorted(set(int(a) for a in acknowledge))
    recorded = np.full(len(cycles), math.nan)
    state: list[str] = []
    pending: list[int] = []  # first cycles of the alarms raised so far and not acknowledged
    done = 0  # acknowledgements taken into account
    for k, cycle in enumerate(cycles):
        if alarm[k]:
            pending.append(int(cycle))
        while done < len(acks) and acks[done] <= cycle:
            recorded[k] = acks[done]
            pending = [c for c in pending if c > acks[done]]
            done += 1
        if not charted:
            state.append("NO BASELINE")
        else:
            state.append("ALARM" if pending else ("NOTICE" if "notice" in flag[k] else "OK"))
    raised = pending[0] if pending else None
    return state, recorded, raised


def check_acknowledged(
    acknowledge: Sequence[int], cycles: Sequence[int], alarm: Sequence[int] | np.ndarray, last: int
) -> None:
    """New acknowledgements checked: each must cover an alarm raised at or before it, and not lie past the last cycle.

    Raises:
        ArgumentError: naming the cycle and the alarms there are.
    """
    raised = [int(c) for c, a in zip(cycles, alarm) if a]
    said = ", ".join(f"{c:,}" for c in raised[:10]) or "none"
    for c in acknowledge:
        if isinstance(c, bool) or not isinstance(c, (int, np.integer)) or c < 0:
            raise ArgumentError("acknowledge", c, "a cycle, a whole number ≥ 0")
        if not any(r <= c for r in raised) or c > last:  # past the last snapshot it would be recorded nowhere
            raise ArgumentError(
                "acknowledge",
                c,
                f"the cycle of a raised alarm, at most the last snapshot's cycle {last:,} (alarms raised at: {said})",
            )


def find(
    rows: Sequence[dict[str, Any]],
    hip_radius_mm: float,
    two_stations: bool,
    baseline: tuple[int, int],
    alarm_rise: float,
    baseline_min: int = MIN_BASELINE,
    acknowledge: Sequence[int] = (),
) -> Findings:
    """The charts over the rows (sorted by cycle) and what they find (module docstring); an alarm held until one of
    ``acknowledge`` (cycles) covers it (:func:`hold`)."""
    cycles = [int(r["cycle"]) for r in rows]

    def column(name: str) -> np.ndarray:
        return np.array([float(r[name]) for r in rows])

    mean = chart(
        cycles,
        column("load_friction_mm"),
        column("load_friction_mm_std"),
        hip_radius_mm,
        baseline,
        alarm_rise,
        worst=2.0 if two_stations else 1.0,
        baseline_min=baseline_min,
    )
    separated = np.array([r["stations"] == "separated" for r in rows], dtype=bool)
    stations: tuple[Chart, Chart] | None = None
    if two_stations and separated.any():
        each = [
            chart(
                cycles,
                column(f"load_friction_{p}_mm"),
                column(f"load_friction_{p}_mm_std"),
                hip_radius_mm,
                baseline,
                alarm_rise,
                baseline_min=baseline_min,
            )
            for p in (1, 2)
        ]
        if all(not c.note for c in each):
            stations = (each[0], each[1])
    gain = column("load_gain") if rows else np.zeros(0)
    inside = (mean.phase == "baseline") & np.isfinite(gain)
    gain_change = gain / float(np.mean(gain[inside])) - 1.0 if inside.any() else np.full(len(rows), math.nan)
    flag, alarm = [], np.zeros(len(rows), dtype=int)
    first: Finding | None = None
    latest: Finding | None = None
    for k in range(len(rows)):
        if stations is not None and separated[k]:
            judged = [(c, f"station {p + 1}") for p, c in enumerate(stations)]
        else:
            judged = [(mean, "the two stations' mean" if two_stations else "the station")]
        texts = []
        for c, where in judged:
            kind = c.flag[k]
            if not kind:
                continue
            verb = "rises" if c.change[k] > 0 else "falls"
            texts.append(f"{kind}: {where} {verb}" + (" (up to twice in one station)" if c.worst > 1 else ""))
            described = _describe(k, rows, c, where, c.mean, hip_radius_mm, kind, float(gain_change[k]))
            if kind == "alarm":
                alarm[k] = 1
                first = first or described
            else:
                latest = described
        flag.append("; ".join(texts))
    notes = _notes(rows, gain_change)
    state, recorded, raised = hold(cycles, alarm, flag, acknowledge, not mean.note)
    return Findings(mean, stations, flag, alarm, first, latest, gain_change, notes, state, recorded, raised)


def _notes(rows, gain_change: np.ndarray) -> list[str]:
    samples = np.array([int(r["samples"]) for r in rows]) if rows else np.zeros(0, dtype=int)
    typical = float(np.median(samples)) if rows else 0.0
    notes = []
    for k, row in enumerate(rows):
        said = [row["note"]] if row["note"] else []
        if samples[k] < INCOMPLETE * typical:
            said.append(f"incomplete: {samples[k]:,} of {typical:,.0f} samples")
        if abs(gain_change[k]) > LOAD_GAIN_DRIFT:
            said.append(f"load cell: measured over commanded load {100 * gain_change[k]:+.1f} % since the baseline")
        notes.append("; ".join(said))
    return notes


def missing_cycles(cycles: Sequence[int]) -> list[int]:
    """The first cycles of snapshots missing from a regular sequence: gaps beyond 1.5 times the spacing.

    The spacing is the median of the spacings near the smallest (within 1.5 times it) when they are a third of all
    or more (several snapshots missing do not widen it), else the median spacing. Needs three snapshots or more.
    """
    first = sorted(set(int(c) for c in cycles))
    if len(first) < 3:
        return []
    steps = np.diff(first)
    regular = steps[steps <= 1.5 * steps.min()]
    spacing = float(np.median(regular if 3 * regular.size >= steps.size else steps))
    missing = []
    for before, after in zip(first, first[1:]):
        if after - before > 1.5 * spacing:
            k = 1
            while before + k * spacing < after - 0.5 * spacing:
                missing.append(int(round(before + k * spacing)))
                k += 1
    return missing


def duplicates(rows: list[dict[str, Any]], paths: dict[str, str]) -> tuple[list[dict[str, Any]], list[Skipped]]:
    """Rows (sorted by cycle) whose cycles another's already cover are skipped: each cycle in one snapshot only."""
    kept: list[dict[str, Any]] = []
    left: list[Skipped] = []
    for row in rows:
        before = kept[-1] if kept else None
        if before is not None and int(row["cycle"]) <= int(before["last_cycle"]) and row["file"] != before["file"]:
            path = paths.get(row["file"], row["file"])
            left.append(
                Skipped(
                    row["file"],
                    path,
                    f"{path}: covers cycles {row['cycle']}-{row['last_cycle']}, as does {before['file']} "
                    f"({before['cycle']}-{before['last_cycle']}): each cycle in one snapshot only (a copied file?)",
                    "duplicate",
                    size=None if row.get("bytes") is None else int(row["bytes"]),
                    sha256=row.get("sha256", ""),
                )
            )
            continue
        kept.append(row)
    return kept, left
