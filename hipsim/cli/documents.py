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

from dataclasses import dataclass
from typing import Any

from ..records import Record
from ..stations.summary import StationSummary

__all__ = ["SCHEMAS", "StationsRun", "schema"]


@dataclass(frozen=True)
class StationsRun(Record):
    """``hipsim stations`` on a desired motion: the summary, the per-sample table and the page written."""

    summary: StationSummary
    table: str
    index: str
    provenance: dict[str, Any]


#: Command (and mode) → the record of what it prints with ``--summary-format json``.
SCHEMAS: dict[str, type[Record]] = {
    "stations": StationsRun,
}


def schema(command: str) -> dict[str, Any]:
    """The JSON Schema of ``command``'s ``--summary-format json`` document (a key of :data:`SCHEMAS`)."""
    return SCHEMAS[command].json_schema(command)
