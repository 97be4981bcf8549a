"""What each command prints with ``--summary-format json``: one record per document, and the schema of each.

A document is the command's summary record (made by the layer that computed
it) with what the command wrote beside it (paths, the provenance block).
:data:`SCHEMAS` names every document by the command (and mode) that prints
it; ``hipsim schema COMMAND`` prints its JSON Schema, generated from the
records' type hints (:meth:`hipsim.records.Record.json_schema`).

Imported when a command prints, never when the parser is built (the summary
records load NumPy).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, ClassVar

from ..analysis.crosscheck_summary import CrossCheckSummary
from ..control.simulation_summary import SimulationSummary
from ..design.feasibility_summary import FeasibilitySummary
from ..design.sizing_summary import MarginBandSummary, SizingSummary
from ..fit_checks import FitCheckSummary
from ..motion.iso_verdict import IsoCheckSummary
from ..records import Record, Verdict, flattened, optional
from ..results import RunSummary
from ..rig.compare_summary import ComparisonSummary
from ..rig.identification.excitation_summary import CalibrationExcitationSummary, ExcitationSummary
from ..rig.identification.summary import BaseListing, IdentificationSummary
from ..rig.monitoring.monitor_summary import MonitorSummary
from ..stations.calibration_summary import CalibrationSummary
from ..stations.sensor_check import SensorComparison
from ..stations.summary import SlidersSummary, StationSummary
from ..stations.tolerance_summary import ToleranceSummary
from ..wear.summary import WearComparison, WearSummary
from .documents_more import MORE_SCHEMAS

__all__ = [
    "COMMAND_LINES",
    "SCHEMAS",
    "CalibrateRun",
    "CompareRun",
    "ExciteCalibrationRun",
    "ExciteRun",
    "IdentifyRun",
    "IsoCheckRun",
    "MonitorRun",
    "ReportFiles",
    "ReportRun",
    "SimulateRun",
    "StationsRun",
    "StationsSliders",
    "StationsTolerance",
    "TorquesRun",
    "WearCompare",
    "WearRun",
    "schema",
]


@dataclass(frozen=True)
class StationsRun(Record):
    """``hipsim stations`` on a desired motion: the verdict, the summary, the per-sample table and the page written."""

    schema_version: ClassVar[str] = "2"  # 2: verdict, the run's records.Verdict (stations_verdict), added

    verdict: Verdict
    summary: StationSummary
    table: str
    index: str
    provenance: dict[str, Any]


@dataclass(frozen=True)
class WearRun(Record):
    """``hipsim wear`` on one motion: the verdict (NOT MADE: not rated), the summary's keys, the notes, the table and
    the page written."""

    schema_version: ClassVar[str] = "2"  # 2: verdict, the run's records.Verdict (wear.summary.run_verdict), added

    verdict: Verdict
    summary: WearSummary = flattened()
    notes: tuple[str, ...] = ()
    table: str = ""
    index: str | None = optional()


@dataclass(frozen=True)
class WearCompare(Record):
    """``hipsim wear --compare A B``: the comparison's keys (as ``wear.json``), the page and the table written."""

    schema_version: ClassVar[str] = "2"  # 2: verdict is a records.Verdict (level, judged, not_judged, numbers)

    comparison: WearComparison = flattened()
    index: str = ""
    table: str = ""


@dataclass(frozen=True)
class StationsSliders(Record):
    """``hipsim stations --sliders LOG``: both platforms from the log's carriages, the table and the page written."""

    sliders: SlidersSummary
    table: str
    index: str
    provenance: dict[str, Any]
    sensors: SensorComparison | None = optional()  # the log's sensors against the prediction, when it has them


@dataclass(frozen=True)
class StationsTolerance(Record):
    """``hipsim stations --bands SPEC``: the tolerance study and the page written."""

    tolerance: ToleranceSummary
    index: str
    provenance: dict[str, Any]


@dataclass(frozen=True)
class IsoCheckRun(Record):
    """``hipsim iso-check``: the run's verdict, its check per quantity and per cycle, and the page written."""

    schema_version: ClassVar[str] = "2"  # 2: verdict, a records.Verdict (PASS/FAIL), for the boolean passed

    check: IsoCheckSummary = flattened()
    index: str = ""


@dataclass(frozen=True)
class SimulateRun(Record):
    """``hipsim simulate``: per controller the run's summary with the ISO 14242-1 verdict, the mismatch, the CSVs."""

    simulations: tuple[SimulationSummary, ...]
    mismatch: dict[str, float]
    csv: tuple[str, ...]


@dataclass(frozen=True)
class CycleOf(Record):
    """Which cycle (from 1) the smallest singularity measure falls in, and how far into it in [s]."""

    cond_inv_min_cycle: int
    cond_inv_min_t_in_cycle_s: float


@dataclass(frozen=True)
class TorquesRun(Record):
    """``hipsim torques``: the run's summary keys, the cycle of its smallest singularity measure (a run of more than
    one cycle), and the table written (``csv`` or ``parquet``, the path given; ``-`` for standard output)."""

    summary: RunSummary = flattened()
    cycle: CycleOf | None = field(default=None, metadata={"flatten": True, "omit_none": True})
    csv: str | None = optional()
    parquet: str | None = optional()


@dataclass(frozen=True)
class ReportFiles(Record):
    """The page a command wrote, and its PDF (None when not printed)."""

    report: str
    pdf: str | None


@dataclass(frozen=True)
class MonitorRun(Record):
    """``hipsim monitor``: the run's summary keys (its verdict first), the table written (None: none), the
    provenance, the page if asked."""

    schema_version: ClassVar[str] = "2"  # 2: verdict, the state's records.Verdict (MonitorResult.verdict), added

    summary: MonitorSummary = flattened()
    out: str | None = None
    provenance: dict[str, Any] = field(default_factory=dict)
    report: ReportFiles | None = field(default=None, metadata={"flatten": True, "omit_none": True})


@dataclass(frozen=True)
class CompareRun(Record):
    """``hipsim compare`` (as ``comparison.json``): the acceptance verdict, the provenance, the comparison's keys, and
    the model's 95 % band per motor when the parameter file carries a covariance."""

    schema_version: ClassVar[str] = "2"  # 2: verdict is a records.Verdict (level, judged, not_judged, numbers)

    verdict: Verdict
    provenance: dict[str, Any]
    comparison: ComparisonSummary = flattened()
    model_band95: dict[str, dict[str, float | None]] | None = optional()


@dataclass(frozen=True)
class ReportRun(Record):
    """``hipsim report``: the run's summary keys, the sizing (None without a drive), the page (and PDF) written, the
    drive's verdict (:func:`hipsim.design.checks.checks_verdict`; NOT MADE without a drive), the provenance, and the
    margins' bands with an identified file's covariance."""

    schema_version: ClassVar[str] = "2"  # 2: verdict is a records.Verdict; rating_check gone (the verdict's level)

    summary: RunSummary = field(metadata={"flatten": True})  # field() itself: mypy then knows it has no default
    sizing: SizingSummary | None
    index: str
    pdf: str | None
    verdict: Verdict
    provenance: dict[str, Any]
    margin_bands: tuple[MarginBandSummary, ...] | None = optional()


# --- the fits and their motions: identify, calibrate, excite ------------------------------------------------------


@dataclass(frozen=True)
class IdentifyRun(Record):
    """``hipsim identify`` (and ``--json``'s file): provenance, self-check and verdict, the fit's keys, files written.

    ``toml`` is the parameter file written, ``json`` the ``--json`` file (None: none)."""

    provenance: dict[str, Any]
    self_check: FitCheckSummary
    summary: IdentificationSummary = flattened()
    toml: str = ""
    json: str | None = None


@dataclass(frozen=True)
class CalibrateRun(Record):
    """``hipsim calibrate`` (and ``--json``'s file): the summary, self-check and verdict, file written, provenance."""

    summary: CalibrationSummary
    self_check: FitCheckSummary
    out: str
    provenance: dict[str, Any]


@dataclass(frozen=True)
class ExciteRun(Record):
    """``hipsim excite``: the design's summary keys (its verdict against the rig's limits) and the CSV written."""

    summary: ExcitationSummary = flattened()
    csv: str = ""


@dataclass(frozen=True)
class ExciteCalibrationRun(Record):
    """``hipsim excite --for calibration``: the calibration motion's summary keys and the CSV written."""

    summary: CalibrationExcitationSummary = flattened()
    csv: str = ""


#: Command (and mode) → the record of what it prints with ``--summary-format json``.
SCHEMAS: dict[str, type[Record]] = {
    "check": CrossCheckSummary,
    "compare": CompareRun,
    "feasible": FeasibilitySummary,
    "iso-check": IsoCheckRun,
    "monitor": MonitorRun,
    "report": ReportRun,
    "simulate": SimulateRun,
    "stations": StationsRun,
    "torques": TorquesRun,
    "stations-sliders": StationsSliders,
    "stations-tolerance": StationsTolerance,
    "wear": WearRun,
    "wear-compare": WearCompare,
    # the fits and their motions
    "identify": IdentifyRun,
    "identify-base": BaseListing,
    "calibrate": CalibrateRun,
    "excite": ExciteRun,
    "excite-calibration": ExciteCalibrationRun,
    **MORE_SCHEMAS,  # size, sweep, workspace, the wear test, the plant-and-model simulate
}


#: Document → the command line that prints it (after ``hipsim``, before ``--summary-format json``): the schema's
#: title. A mode is its command with the option that selects it; an option the command requires is named by its
#: metavar (each line parses with the real parser: tests/cli/test_documents.py).
COMMAND_LINES: dict[str, str] = {
    "check": "check",
    "compare": "compare --log FILE",
    "feasible": "feasible",
    "iso-check": "iso-check",
    "monitor": "monitor --params FILE --log DIR_OR_FILES",
    "report": "report --out DIR",
    "simulate": "simulate",
    "stations": "stations",
    "torques": "torques",
    "stations-sliders": "stations --sliders LOG",
    "stations-tolerance": "stations --bands SPEC",
    "wear": "wear",
    "wear-compare": "wear --compare A B",
    "identify": "identify --log FILE --out FILE",
    "identify-base": "identify --base",
    "calibrate": "calibrate --log FILE --out FILE",
    "excite": "excite --out FILE",
    "excite-calibration": "excite --for calibration --out FILE",
    "size": "size",
    "size-catalogue": "size --catalogue CSV",
    "simulate-plant": "simulate --plant-params FILE",
    "sweep": "sweep",
    "workspace": "workspace",
    "wear-test": "wear --weighings FILE",
}


def schema(command: str) -> dict[str, Any]:
    """The JSON Schema of ``command``'s ``--summary-format json`` document (a key of :data:`SCHEMAS`), titled by the
    command line that prints it (:data:`COMMAND_LINES`)."""
    return SCHEMAS[command].json_schema(command, COMMAND_LINES[command])
