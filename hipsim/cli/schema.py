"""``hipsim schema``: the JSON Schema of a command's ``--summary-format json`` output, generated from its records."""

from __future__ import annotations

import argparse
import json

from ..exceptions import HipsimError

__all__ = ["add_parser", "run"]


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Register ``schema`` on the main parser's subcommands."""
    p = subparsers.add_parser(
        "schema",
        help="the JSON Schema of a command's --summary-format json output (no COMMAND: the list)",
        description="Prints the JSON Schema (draft 2020-12, versioned) of what COMMAND prints with --summary-format "
        "json, generated from the typed records the command prints; without COMMAND, the commands that have one.",
    )
    p.add_argument("name", nargs="?", metavar="COMMAND", help="e.g. stations, wear-compare, iso-check")
    p.set_defaults(run=run)
    return p


def run(args) -> int:
    """Print the schema, or the list of documents."""
    from .documents import SCHEMAS, schema

    if args.name is None:
        for name, record in SCHEMAS.items():
            print(f"{name:22s} {(record.__doc__ or '').strip().splitlines()[0]}")
        return 0
    if args.name not in SCHEMAS:
        raise HipsimError(
            f"schema: no command '{args.name}' prints a JSON summary; expected one of {', '.join(SCHEMAS)}"
        )
    print(json.dumps(schema(args.name), indent=2))
    return 0
