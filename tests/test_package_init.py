"""hipsim/__init__.py's lazy names (PEP 562): each home it names is a module that defines the name."""

from __future__ import annotations

import importlib

import hipsim


def test_every_lazy_name_lives_in_the_module_its_home_names():
    for name, home in hipsim._HOMES.items():
        module = importlib.import_module(f"hipsim.{home}")  # a stale path (a module moved) fails here
        assert getattr(module, name) is getattr(hipsim, name), name
        assert name in hipsim.__all__, name
