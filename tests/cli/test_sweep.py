"""The sweep command's own logic (hipsim.cli.sweep): a key given twice; the ranges to sweep on, as the options take
them. The summary (best variants on an edge, nearest failing neighbours): design/test_sweep_summary.py; the sweep
itself: design/test_sweep.py."""

from __future__ import annotations

import pytest

from hipsim.cli import sweep as sweep_cli
from hipsim.design.sweep_edges import Edge
from hipsim.design.variants import key_ref
from hipsim.exceptions import HipsimError


def test_a_key_given_twice_is_refused():
    key = key_ref("lever.length_mm")
    seen = {key}
    with pytest.raises(HipsimError, match="--grid lever.length_mm is given twice"):
        sweep_cli._unique(key_ref("lever.length_mm"), seen, "--grid")
    assert sweep_cli._unique(key_ref("screw.lead_mm"), seen, "--grid").name == "screw.lead_mm"


def test_the_ranges_to_sweep_on_as_the_options_take_them():
    edges = [
        Edge("lever.length_mm", "upper", 350.0, 330.0, 350.0, 5.0, (320.0, 360.0)),
        Edge("screw.lead_mm", "lower", 5.0, 5.0, 10.0, None, (4.5, 12.25)),  # a sample: no step
    ]
    assert sweep_cli._extend(edges) == "sweep on, e.g. lever.length_mm=320:360:5 screw.lead_mm=4.5:12.25"
