"""What ``size``, ``sweep``, ``workspace``, the wear test (``wear --weighings``) and the plant-and-model ``simulate``
print with ``--summary-format json``: their documents' records, listed in :data:`MORE_SCHEMAS` (merged into
:data:`hipsim.cli.documents.SCHEMAS`).

Imported when a command prints or ``hipsim schema`` runs, never when the parser is built.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..design.sizing_summary import RankingSummary, SizingSummary
from ..records import Record, flattened

__all__ = ["MORE_SCHEMAS", "SizeRun"]


@dataclass(frozen=True)
class SizeRun(Record):
    """``hipsim size`` on one drive: per trajectory (its name the key) the sizing, the drive's checks and verdict."""

    trajectories: dict[str, SizingSummary] = flattened()


#: Command (and mode) → the record of what it prints with ``--summary-format json``.
MORE_SCHEMAS: dict[str, type[Record]] = {
    "size": SizeRun,
    "size-catalogue": RankingSummary,
}
