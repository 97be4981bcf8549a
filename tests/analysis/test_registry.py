"""The engine and plant registry (hipsim.analysis.registry): names, lazy loading, its errors (the
protocols every engine and plant keeps: tests/test_engine.py)."""

from __future__ import annotations

import subprocess
import sys

import pytest

import hipsim
import hipsim.analysis.runs  # the module whose MODELS the registry must match, imported here, not by an earlier test
from hipsim.analysis import registry
from hipsim.exceptions import ArgumentError, MissingDependencyError


def test_the_names_are_the_command_lines_choices():
    assert registry.engine_names() == ("analytic", "pinocchio", "mujoco")
    assert registry.engine_names(optional=False) == ("analytic", "pinocchio")
    assert registry.check_names() == ("pinocchio", "mujoco")
    assert registry.plant_names() == ("analytic", "pinocchio", "mujoco")
    assert hipsim.analysis.runs.MODELS == registry.engine_names()


def test_reduced_is_the_analytic_plant():
    assert registry.plant_entry("reduced") is registry.plant_entry("analytic")


def test_which_engines_and_plants_compile_kernels_before_a_run():
    assert [name for name in registry.engine_names() if registry.engine_entry(name).warm_up] == ["pinocchio"]
    assert [name for name in registry.plant_names() if registry.plant_entry(name).warm_up] == ["pinocchio"]


def test_an_unknown_name_is_one_argument_error():
    with pytest.raises(ArgumentError, match=r"^model: expected one of analytic, pinocchio, mujoco, got 'bogus'$"):
        registry.engine_entry("bogus")
    with pytest.raises(ArgumentError, match=r"^plant: expected one of analytic, pinocchio, mujoco, got 'bogus'$"):
        registry.plant_entry("bogus")
    for run in (
        lambda: hipsim.analyse(model="bogus"),
        lambda: hipsim.analysis.stream_run(hipsim.load_parameters(), hipsim.iso14242(rate=50), "bogus"),
    ):
        with pytest.raises(ArgumentError, match=r"^model: expected one of analytic, pinocchio, mujoco, got 'bogus'$"):
            run()


def test_an_engine_that_cannot_flag_refuses_before_it_loads(monkeypatch):
    monkeypatch.setattr(registry.Entry, "load", lambda self: pytest.fail(f"{self.name} loaded"))
    for name in ("pinocchio", "mujoco"):
        with pytest.raises(ArgumentError, match="'raise' with the Pinocchio model"):
            registry.make_engine(name, hipsim.load_parameters(), on_error="flag")


def test_an_option_no_plant_takes_is_refused():
    with pytest.raises(ArgumentError, match="options"):
        registry.make_plant("analytic", hipsim.load_parameters(), integrater="RK4")


def test_engines_load_only_when_asked_for():
    script = (
        "import sys, hipsim\n"
        "from hipsim.analysis.registry import make_engine, make_plant\n"
        "heavy = ('pinocchio', 'mujoco', 'hipsim.closed_chain', 'hipsim.mujoco_engine')\n"
        "assert not [m for m in heavy if m in sys.modules], [m for m in heavy if m in sys.modules]\n"
        "hipsim.analyse(hipsim.load_parameters(), hipsim.iso14242(rate=50))\n"
        "make_plant('analytic', hipsim.load_parameters())\n"
        "assert not [m for m in heavy if m in sys.modules], [m for m in heavy if m in sys.modules]\n"
    )
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr


def test_a_missing_extra_says_how_to_install_it(monkeypatch):
    monkeypatch.setitem(sys.modules, "mujoco", None)  # `import mujoco` fails as if it were not installed
    for module in [m for m in sys.modules if m.startswith("hipsim.mujoco_engine")]:
        monkeypatch.delitem(sys.modules, module)
    for make in (
        lambda: registry.make_engine("mujoco", hipsim.load_parameters()),
        lambda: registry.make_plant("mujoco", hipsim.load_parameters()),
    ):
        with pytest.raises(
            MissingDependencyError,
            match=r"The MuJoCo engine needs the optional package 'mujoco' .*: pip install -U 'hipsim\[mujoco\]'$",
        ):
            make()


def test_the_registry_names_the_extra_when_the_import_fails_below_it(monkeypatch):
    """Even without the engine package's own check, an ImportError of the extra's package is the install line."""

    def fail(name, package=None):
        raise ModuleNotFoundError("No module named 'mujoco'", name="mujoco")

    monkeypatch.setattr(registry.importlib, "import_module", fail)
    with pytest.raises(MissingDependencyError, match=r"pip install -U 'hipsim\[mujoco\]'"):
        registry.engine_entry("mujoco").load()
    with pytest.raises(ModuleNotFoundError):  # an engine without an extra: the error as it is
        registry.engine_entry("pinocchio").load()
