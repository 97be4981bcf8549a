"""The contracts of every engine and plant (hipsim.engine): each registered one keeps its protocol, runs a piece and
accepts the next piece in order; what a run in pieces needs by default."""

from __future__ import annotations

import pytest

import hipsim
from hipsim.analysis import registry
from hipsim.engine import Engine, PieceNeeds


def test_a_run_in_pieces_needs_nothing_by_default():
    needs = PieceNeeds()
    assert (needs.overlap, needs.wraps_around, needs.chunk) == (0, False, 20_000)


def test_an_object_without_run_is_not_an_engine():
    class Half:
        name, params, pieces = "half", None, PieceNeeds()

        def piece_state(self, offset, previous):
            return None

    assert not isinstance(Half(), Engine)


@pytest.mark.parametrize("name", registry.engine_names())
def test_every_engine_keeps_the_protocol(name):
    if name == "mujoco":
        pytest.importorskip("mujoco")
    params = hipsim.load_parameters()
    engine = registry.make_engine(name, params)
    assert isinstance(engine, Engine)
    assert engine.name == name and engine.params is params and isinstance(engine.pieces, PieceNeeds)
    assert engine.pieces.chunk >= 1 and engine.pieces.overlap >= 0
    state = engine.piece_state(0, None)
    trajectory = hipsim.iso14242(rate=50).slice(slice(0, 5))
    run = engine.run(trajectory, state)
    assert run.model == name and len(run.trajectory.t) == 5
    assert (run.joint_forces is not None) == registry.engine_entry(name).joint_forces
    engine.piece_state(5, state)  # the next piece in order is accepted


@pytest.mark.parametrize("name", registry.plant_names())
def test_every_plant_keeps_the_protocol(name):
    if name == "mujoco":
        pytest.importorskip("mujoco")
    params = hipsim.load_parameters()
    plant = registry.make_plant(name, params, lever_spin=True, integrator="RK4")
    assert plant.params is params
    x = plant.initial_state(hipsim.iso14242(rate=50).slice(slice(0, 1)))
    q, qd = plant.angles(x)
    assert q.shape == (3,) and qd.shape == (3,)
    kernel = getattr(plant, "compiled_kernel", lambda: None)()
    assert (kernel is not None) == (name == "analytic")
