"""The engines and plants by name: which exist, where each lives, what it needs installed, and loading one only when asked for.

Every choice of an engine or a plant by name goes through here (``hipsim.analyse(...,
model=)``, the streamed runs, the cross-check, the command line's choices),
so that no other module compares an engine's name. An engine is a
:class:`hipsim.engine.Engine`, a plant a :class:`hipsim.engine.Plant`; their
modules are imported on first use (Pinocchio and MuJoCo take a while to load,
and MuJoCo is an optional extra), which is why this is the one module of
hipsim that imports by name (:mod:`importlib`).

>>> from hipsim.analysis.registry import engine_names, make_engine
>>> engine_names()
('analytic', 'pinocchio', 'mujoco')
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..exceptions import ArgumentError, MissingDependencyError

if TYPE_CHECKING:  # the command line reads the names for its choices: no NumPy for that
    from ..engine import Engine, Plant
    from ..machine.parameters import Parameters

__all__ = [
    "ENGINES",
    "PLANTS",
    "Entry",
    "check_names",
    "engine_entry",
    "engine_names",
    "make_engine",
    "make_plant",
    "plant_entry",
    "plant_names",
]


@dataclass(frozen=True)
class Entry:
    """One engine or plant: its name and where it lives, loaded on demand.

    Attributes:
        name: the name users choose it by.
        module: the absolute module path of its class.
        attribute: the class's name in ``module``.
        title: what it is, for messages ("The MuJoCo engine").
        extra: the hipsim extra that installs the package it needs (``pip install 'hipsim[extra]'``); None if none.
        package: that package's import name.
        options: the keyword options of :func:`make_engine` / :func:`make_plant` its class takes.
        flags: (engines) it can carry on through poses out of reach, flagging them (``on_error="flag"``).
        reference: (engines) the model the others are checked against (``hipsim check``).
        joint_forces: (engines) its runs carry the joint forces.
        warm_up: its first run compiles numba kernels (a machine's first run only) before it can report
            progress: a caller may load them first and say so (:func:`hipsim.closed_chain.dynamics.warm_up`).
        aliases: other names it answers to (not offered as choices).
        checked_whole: (engines) ``hipsim check`` compares it on the whole trajectory in memory, against both
            other engines (:func:`hipsim.analysis.crosscheck.compare_mujoco`), rather than streamed against
            the reference (:func:`hipsim.analysis.crosscheck.compare_models`).
    """

    name: str
    module: str
    attribute: str
    title: str
    extra: str | None = None
    package: str | None = None
    options: tuple[str, ...] = ()
    flags: bool = False
    reference: bool = False
    joint_forces: bool = False
    warm_up: bool = False
    aliases: tuple[str, ...] = ()
    checked_whole: bool = False

    def load(self) -> type:
        """The class, its module imported now if not before.

        Raises:
            MissingDependencyError: the package of its extra is not installed (with the install line).
        """
        try:
            module = importlib.import_module(self.module)
        except ImportError as error:
            if self.package is not None and self.extra is not None and error.name == self.package:
                raise MissingDependencyError(self.package, self.extra, self.title) from None
            raise
        return getattr(module, self.attribute)


#: The engines, in the order they are offered.
ENGINES = (
    Entry(
        "analytic",
        "hipsim.analytic.engine",
        "AnalyticModel",
        "The analytic model",
        options=("lever_spin", "on_error"),
        flags=True,
        reference=True,
    ),
    Entry(
        "pinocchio",
        "hipsim.closed_chain.engine",
        "PinocchioModel",
        "The Pinocchio closed-chain model",
        joint_forces=True,
        warm_up=True,
    ),
    Entry(
        "mujoco",
        "hipsim.mujoco_engine",
        "MujocoModel",
        "The MuJoCo engine",
        extra="mujoco",
        package="mujoco",
        joint_forces=True,
        checked_whole=True,
    ),
)

#: The plants of :func:`hipsim.control.simulation.simulate`, in the order they are offered.
PLANTS = (
    # The reduced plant's kernels compile too, but simulate() says so itself.
    Entry(
        "analytic",
        "hipsim.control.simulation",
        "ReducedPlant",
        "The reduced plant",
        options=("lever_spin",),
        aliases=("reduced",),
    ),
    Entry("pinocchio", "hipsim.closed_chain.plant", "PinocchioPlant", "The Pinocchio plant", warm_up=True),
    Entry(
        "mujoco",
        "hipsim.mujoco_engine.plant",
        "MujocoPlant",
        "The MuJoCo engine",
        extra="mujoco",
        package="mujoco",
        options=("integrator",),
    ),
)


def _find(entries: tuple[Entry, ...], argument: str, name: str) -> Entry:
    for entry in entries:
        if name == entry.name or name in entry.aliases:
            return entry
    raise ArgumentError(argument, name, f"one of {', '.join(entry.name for entry in entries)}")


def engine_names(*, optional: bool = True) -> tuple[str, ...]:
    """The engines' names, in order (the command line's choices).

    Args:
        optional: include the engines that need an optional extra (MuJoCo).
    """
    return tuple(entry.name for entry in ENGINES if optional or entry.extra is None)


def check_names() -> tuple[str, ...]:
    """The engines ``hipsim check`` compares with the reference (analytic) model, in order."""
    return tuple(entry.name for entry in ENGINES if not entry.reference)


def engine_entry(name: str) -> Entry:
    """The engine called ``name``, not loaded.

    Raises:
        ArgumentError: no engine has that name (argument ``model``).
    """
    return _find(ENGINES, "model", name)


def make_engine(name: str, params: Parameters, *, on_error: str = "raise", lever_spin: bool = False) -> Engine:
    """The engine called ``name``, built for ``params`` (its module loaded now).

    Args:
        name: one of :func:`engine_names`.
        params: the machine.
        on_error: "raise" at the first pose out of reach or singular, or "flag"
            to mark such samples (the engines that can: the analytic model).
        lever_spin: give the levers the universal joints' spin (the engines that
            take the option: the analytic model; the others always have it).

    Raises:
        ArgumentError: an unknown name, or ``on_error`` other than "raise" for an engine that cannot flag.
        MissingDependencyError: the engine's optional extra is not installed.
    """
    entry = engine_entry(name)
    if on_error != "raise" and not entry.flags:
        raise ArgumentError(
            "on_error",
            on_error,
            "'raise' with the Pinocchio model (it cannot carry on through poses out of reach; the analytic model flags them)",
        )
    given = {"on_error": on_error, "lever_spin": lever_spin}
    return entry.load()(params, **{option: given[option] for option in entry.options})


def plant_names() -> tuple[str, ...]:
    """The plants' names, in order (the command line's choices; ``reduced`` is also the analytic plant)."""
    return tuple(entry.name for entry in PLANTS)


def plant_entry(name: str) -> Entry:
    """The plant called ``name``, not loaded.

    Raises:
        ArgumentError: no plant has that name (argument ``plant``).
    """
    return _find(PLANTS, "plant", name)


def make_plant(name: str, params: Parameters, **options) -> Plant:
    """The plant called ``name``, built for ``params`` (its module loaded now).

    Args:
        name: one of :func:`plant_names` (or ``reduced``).
        params: the plant's machine.
        options: keyword options, each given to the plants that take it and
            ignored by the others: ``lever_spin`` (the reduced plant),
            ``integrator`` (MuJoCo's: "RK4", "Euler", "implicitfast", "implicit").

    Raises:
        ArgumentError: an unknown name, or an option no plant takes.
        MissingDependencyError: the plant's optional extra is not installed.
    """
    entry = plant_entry(name)
    unknown = sorted(set(options) - {option for plant in PLANTS for option in plant.options})
    if unknown:
        raise ArgumentError(
            "options",
            unknown,
            f"options of the plants: {', '.join(sorted({o for plant in PLANTS for o in plant.options}))}",
        )
    return entry.load()(params, **{option: value for option, value in options.items() if option in entry.options})
