"""``hipsim params``: the parameter set in use, as a parameter file with each key's meaning and unit."""

from __future__ import annotations

import argparse
import json

from .common import add_machine_options, parameters

__all__ = ["add_parser", "run"]


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Register ``params`` on the main parser's subcommands."""
    params = subparsers.add_parser("params", help="print the parameter set in use, with units")
    add_machine_options(params)
    params.set_defaults(run=run)
    return params


def run(args) -> int:
    """Print the parameter set."""
    from ..machine.parameters import SCHEMA, file_values

    params = parameters(args)
    values = file_values(params)
    print(f"# parameters: {params.source}")
    for section, keys in SCHEMA.items():
        present = [key for key in keys if f"{section}.{key}" in values]  # an optional table may be absent
        if present:
            print(f"\n[{section}]")
        for key in present:
            spec = keys[key]
            value = values[f"{section}.{key}"]
            note = spec.meaning + (f" [{spec.unit}]" if spec.unit else "")
            shown = json.dumps(value).replace("Infinity", "inf")  # TOML spells it inf
            print(f"{key} = {shown}".ljust(60) + f"# {note}")
    if params.geometry is not None:  # per-chain deviations from the drawing (hipsim.machine.chains)
        from ..machine.chains import CONTROL_MEANING, GEOMETRY_KEYS, geometry_table

        print("\n[geometry]")
        for key, value in geometry_table(params.geometry).items():
            note = f"{GEOMETRY_KEYS[key][3]} [mm]" if key in GEOMETRY_KEYS else CONTROL_MEANING
            print(f"{key} = {json.dumps(value)}".ljust(59) + f" # {note}")
    return 0
