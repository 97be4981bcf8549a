"""Building the closed-chain model (hipsim.closed_chain.build): the hip's six closures and armature from the parameters,
and a closure declaration that does not fit the URDF refused naming what is wrong. The model against MuJoCo's and the
analytic one: mujoco_engine/test_mjcf.py, analytic/test_chain_dynamics.py."""

import copy

import numpy as np
import pytest

import hipsim
from hipsim.closed_chain.build import load_closed_chain, load_model
from hipsim.exceptions import ModelError
from hipsim.machine.model_files import closure_declaration, urdf_text


@pytest.fixture(scope="module")
def params():
    return hipsim.load_parameters()


def test_the_hip_has_six_closures_and_the_screws_armature(params):
    chain = load_model(params.replace(lead=0.005, screw_inertia=80e-6))
    assert chain.n_closures == 6 and chain.model.nv == 21
    armature = np.asarray(chain.model.armature)
    np.testing.assert_allclose(armature[chain.actuated_v], 80e-6 * (2 * np.pi / 0.005) ** 2, rtol=1e-15)
    assert np.count_nonzero(armature) == 3


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (lambda d: d.pop("name_mot"), "the closure declaration: missing key 'name_mot'"),
        (lambda d: d["closed_loop"][0].__setitem__(0, "nowhere"), "closure frame 'nowhere' is not in the URDF"),
        (lambda d: d["type"].__setitem__(0, "2d"), "closure type '2d' of"),
        (lambda d: d["type"].pop(), "type must list one of '3d'/'6d' per closed_loop pair (6)"),
    ],
    ids=["key", "frame", "type", "count"],
)
def test_a_declaration_that_does_not_fit_is_refused(params, change, message):
    declaration = copy.deepcopy(closure_declaration(params))  # a cached declaration stays whole
    change(declaration)
    with pytest.raises(ModelError) as refused:
        load_closed_chain(urdf_text(params), declaration)
    assert message in str(refused.value)
