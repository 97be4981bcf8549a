"""Progress on long work (issue 47 point 8): ``wear`` on fine grids and ``monitor``'s first run draw a tqdm bar on a
terminal (hipsim.cli.common.progress, as ``sweep`` does) and nothing elsewhere; the wear maps' steps, counted by hand,
and the maps the same to the last bit whatever the steps."""

from __future__ import annotations

import io
import sys

import numpy as np
import pytest

import hipsim
from hipsim.cli import common
from hipsim.wear import maps as wear_maps_module
from hipsim.wear.points import cup_grid


def _maps(progress=None, piece=250):
    cycle = hipsim.iso14242(rate=200.0, cycles=1)  # 201 samples
    return wear_maps_module.wear_maps(cycle, 1.0, points=cup_grid(8, 16), piece=piece, progress=progress)


def test_the_wear_maps_steps_by_hand(monkeypatch):
    calls = []
    monkeypatch.setattr(wear_maps_module, "POINTS_PER_STEP", 50)
    maps = _maps(lambda done, total: calls.append((done, total)), piece=60)
    points = maps.points.w.shape[0]
    # 201 samples in pieces of 60: 4 pieces; the points in parts of 50: ⌈P/50⌉ parts.
    parts = -(-points // 50)
    total = 4 + parts
    assert calls == [(k, total) for k in range(1, total + 1)]


def test_the_steps_change_nothing(monkeypatch):
    whole = _maps()
    monkeypatch.setattr(wear_maps_module, "POINTS_PER_STEP", 7)
    split = _maps(lambda done, total: None)
    for name in ("sliding_mm", "work_N_per_mm", "cross_shear", "principal"):
        np.testing.assert_array_equal(getattr(whole, name), getattr(split, name), err_msg=name)


def test_the_bar_on_a_terminal_only(monkeypatch):
    monkeypatch.setattr(sys, "stderr", io.StringIO())
    assert common.progress("wear", " steps") is None  # not a terminal: silent
    terminal = io.StringIO()
    terminal.isatty = lambda: True  # type: ignore[method-assign]
    monkeypatch.setattr(sys, "stderr", terminal)
    update = common.progress("wear", " steps")
    assert update is not None
    pytest.importorskip("tqdm")
    from tqdm import tqdm

    made = []
    original = tqdm.__init__

    def init(self, *args, **options):
        made.append(options)
        options["delay"] = 0.0
        original(self, *args, **options)

    monkeypatch.setattr(tqdm, "__init__", init)
    for done in (1, 2, 3):
        update(done, 3)
    assert made and made[0]["desc"] == "wear" and made[0]["unit"] == " steps" and made[0]["total"] == 3
    drawn = terminal.getvalue()
    assert drawn.startswith("\rwear:") and "/3.00" in drawn and "steps" in drawn  # drawn on standard error
    assert drawn.endswith("\r")  # and cleared when done (leave=False): the command's own lines follow
