"""The physics every engine shares: small-vector algebra, rotation maps, the friction laws, the screw transmission and the numba plumbing.

Below :mod:`hipsim.machine` in nothing: the engines (:mod:`hipsim.analytic`,
:mod:`hipsim.closed_chain`, :mod:`hipsim.mujoco_engine`) import these laws and
never each other.
"""
