"""The plant's block order (hipsim.closed_chain.plant_kernel.block_order) on a six-joint tree by hand. The compiled
bias forces against Pinocchio: closed_chain/test_tree_kernel.py."""

import numpy as np

from hipsim.closed_chain.plant_kernel import block_order

#: (parent, velocity slot) per joint: two chains of three from the universe, slots 0-2 and 3-5.
JOINTS = np.array([[-1, -1], [0, 0], [1, 1], [2, 2], [0, 3], [4, 4], [5, 5]])


def test_the_closure_reaching_fewer_joints_is_solved_first():
    # Closure 0 joins the chains' tips (reaches all six slots), closure 1 the first tip to the ground (slots 0-2):
    # closure 1's three rows on slots 0-2 are a block of their own, then closure 0's rows on slots 3-5.
    columns, blocks = block_order(JOINTS, np.array([[6, 3], [3, 0]]), np.array([3, 4, 5, 0, 1, 2]))
    np.testing.assert_array_equal(columns, [0, 1, 2, 3, 4, 5])
    np.testing.assert_array_equal(blocks, [[3, 4, 5, 0, 1, 2], [3, 3, 3, 6, 6, 6]])


def test_independent_closures_keep_the_given_order():
    columns, blocks = block_order(JOINTS, np.array([[6, 0], [3, 0]]), np.array([3, 4, 5, 0, 1, 2]))
    np.testing.assert_array_equal(columns, [3, 4, 5, 0, 1, 2])
    np.testing.assert_array_equal(blocks, [[0, 1, 2, 3, 4, 5], [3, 3, 3, 6, 6, 6]])
