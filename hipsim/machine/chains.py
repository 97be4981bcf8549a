"""Per-chain geometry: each of the six P-U-S chains and each platform's rotation centre as built, not as drawn.

The drawing (spec §1, §7.1) makes the two platforms alike: the same joint
circle, one lever length, the sliders of a carriage h_1 − h_2 apart, so both
platforms always turn alike. A real machine is built to tolerance. The
optional ``[geometry]`` table of the parameter file holds each chain's
*deviation from the drawing* (platform j = 1, 2; module i = 1, 2, 3), in mm;
a key left out is zero, and a table that is all zero (or no table) is the
drawing, bit for bit (:func:`geometry_from_table` returns None for it).

With the carriage reading L_i of module i (what its encoder reads: the
drawing's L_1i), chain ji is

    b_ji = c_i + (u_ji,x, u_ji,y, 0) + (L_i + h_j − h_1 + s_ji)·ẑ      (U-joint centre)
    a_ji = o_j + R_j·(r⁰_i + δr_ji),   o_j = h_j·ẑ + δo_j             (platform joint)
    |a_ji − b_ji| = l + δl_ji                                          (lever)

with u_ji the U-joint centre's horizontal offset from its screw axis (base
axes), s_ji the slider's height offset on its carriage, δr_ji the platform
joint's offset in platform axes, δl_ji the lever's length deviation and δo_j
the rotation centre's offset (base axes). :class:`Chains` holds the resolved
absolute values; ``Parameters.chains`` builds them. The U-joints' first axes
stay the drawing's (ẑ × c_i/|c_i|): a centre offset moves the joint, not its axis.

The intermediate chain (``spline_seat_mm``): joint 1's head stands, through a
thrust bearing and the ball spline's shaft, on a seat in joint 2's acetabulum,
which turns with platform m_2. The spline holds the head on the vertical axis
and lets it slide along it; the shaft's end rests on the seat, a point e in m_2's
axes from its rotation centre (e = 0 on the drawing: the seat on joint 2's centre,
so m_2's turning does not move it). m_1's rotation centre then rides up and
down with m_2's attitude:

    o_1 = h_1·ẑ + δo_1 + ẑ·[ẑᵀ·(R_2 − I)·e]                           (stack-up)

(:func:`stackup_lift`). In the URDF tree (Pinocchio, MuJoCo: :func:`per_chain_urdf`) the chain is
built as it is: m_1's spherical joint rides a massless prismatic-Z body (the spline shaft, on the axis),
whose end carries two massless horizontal slides (X, Y) with a frame ``spline_1_tip`` that a 3-D point
closure holds on the seat ``platform_2_seat`` = o_2 + R_2·e (frame of m_2): three more coordinates and
three more closure rows, so the mobility stays 3 and the shaft's end slides freely across the seat. As in
the analytic model the shaft has no mass and its axial slide no friction; the load F_e presses on m_1's
centre and does work now. Lifting o_1 by Δz at fixed carriages is the same as lowering
all three of m_1's carriage readings by Δz, which is how every kinematic model applies it.

Example:
    >>> import numpy as np
    >>> g = ChainGeometry.zeros().replace(lever=np.array([[0.0, 0.0, 0.0], [0.0, 0.3e-3, 0.0]]))
    >>> lever_mm = geometry_table(g)["lever_offset_mm"]  # chains 11 … 23, in mm
    >>> lever_mm[4]
    0.3
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..arrays import readonly
from ..exceptions import ParameterError

__all__ = [
    "CHAIN_LABELS",
    "CONTROL_MEANING",
    "GEOMETRY_KEYS",
    "ChainGeometry",
    "Chains",
    "MAX_DEVIATION",
    "STACKUP_CLOSURE",
    "STACKUP_JOINTS",
    "STACKUP_KEY",
    "geometry_from_table",
    "geometry_table",
    "per_chain_urdf",
    "refuse_stackup",
    "stackup_lift",
]

_MM = 1e-3

#: The chains in the file's row order: platform j, module i.
CHAIN_LABELS = ("11", "12", "13", "21", "22", "23")

#: Largest deviation magnitude a file may give, in [m]: a built machine, not another design.
MAX_DEVIATION = 0.05

#: The ``[geometry]`` keys: file key → (field of :class:`ChainGeometry`, rows, row length (0: a number per row), meaning).
GEOMETRY_KEYS: dict[str, tuple[str, int, int, str]] = {
    "ujoint_offset_mm": (
        "ujoint",
        6,
        2,
        "U-joint centre b_ji off its screw axis, horizontal [x, y] in base axes, per chain 11 12 13 21 22 23",
    ),
    "slider_offset_mm": (
        "slider",
        6,
        0,
        "U-joint centre b_ji above its drawing height on the carriage, per chain",
    ),
    "joint_offset_mm": (
        "joint",
        6,
        3,
        "platform joint a_ji off e·[cos φ_i, sin φ_i, 0], [x, y, z] in platform axes, per chain",
    ),
    "lever_offset_mm": ("lever", 6, 0, "lever length l_ji minus l, per chain"),
    "centre_offset_mm": ("centre", 2, 3, "rotation centre o_j off (0, 0, h_j), [x, y, z] in base axes, per platform"),
    "spline_seat_mm": (
        "spline",
        1,
        3,
        "intermediate chain: the seat of joint 1's spline shaft in m_2's axes from o_2, [x, y, z]; "
        "m_1's centre rides ẑ·(R_2 − I)·e up and down with m_2",
    ),
}

#: The ``[geometry]`` key of the intermediate chain's stack-up.
STACKUP_KEY = "spline_seat_mm"

#: The tree's intermediate chain with a stack-up (:func:`per_chain_urdf`): the spline's axial slide carrying m_1's
#: spherical joint, and the shaft end's two horizontal slides on the seat.
STACKUP_JOINTS = ("spline_1_z", "spline_1_tip_x", "spline_1_tip_y")
#: The seat closure: the spline shaft's end (frame 1) meets the seat point on m_2 (frame 2).
STACKUP_CLOSURE = ("spline_1_tip", "platform_2_seat")

#: What the ``control`` key of ``[geometry]`` means.
CONTROL_MEANING = "the platform whose motion a trajectory gives (1 or 2; the other follows the carriages)"

_SHAPES = {
    "ujoint": (2, 3, 2),
    "slider": (2, 3),
    "joint": (2, 3, 3),
    "lever": (2, 3),
    "centre": (2, 3),
    "spline": (3,),
}
#: Values of the six chains and two centres (the vector before the stack-up was added, which ``from_vector`` still takes).
CHAIN_COUNT = 48


@dataclass(frozen=True, eq=False)
class ChainGeometry:
    """Each chain's deviation from the drawing, in [m] (j = platform index 0, 1; i = module index 0, 1, 2).

    Attributes:
        ujoint: U-joint centre's horizontal offset from its screw axis [x, y] in base axes, (2, 3, 2).
        slider: U-joint centre's height offset on its carriage, (2, 3).
        joint: platform joint's offset in platform axes [x, y, z], (2, 3, 3).
        lever: lever length deviation, (2, 3).
        centre: rotation centre's offset [x, y, z] in base axes, (2, 3).
        spline: the intermediate chain's seat e, [x, y, z] in m_2's axes from o_2, (3,) (module docstring).
        control: the platform whose motion a trajectory gives (1 or 2; the paper controls m_2, the default);
            the carriages follow from its inverse kinematics and the other platform follows them.
    """

    ujoint: np.ndarray
    slider: np.ndarray
    joint: np.ndarray
    lever: np.ndarray
    centre: np.ndarray
    spline: np.ndarray = dataclasses.field(default_factory=lambda: np.zeros(3))
    control: int = 2

    def __post_init__(self):
        if self.control not in (1, 2) or isinstance(self.control, bool):
            raise ParameterError(
                f"expected 1 or 2 (the controlled platform), got {self.control!r}", key="geometry.control"
            )
        for name, shape in _SHAPES.items():
            value = readonly(np.array(getattr(self, name), dtype=float))
            if value.shape != shape:
                raise ParameterError(f"expected shape {shape}, got {value.shape}", key=f"geometry.{name}")
            if not np.all(np.isfinite(value)):
                raise ParameterError("expected finite numbers", key=f"geometry.{name}")
            object.__setattr__(self, name, value)

    @classmethod
    def zeros(cls) -> ChainGeometry:
        """The drawing: every deviation zero."""
        fields: dict[str, Any] = {name: np.zeros(shape) for name, shape in _SHAPES.items()}
        return cls(**fields)

    def is_drawing(self) -> bool:
        """True when every deviation is exactly zero."""
        return all(not np.any(getattr(self, name)) for name in _SHAPES)

    def replace(self, **changes) -> ChainGeometry:
        """A copy with some fields changed, e.g. ``g.replace(lever=np.full((2, 3), 1e-4))``."""
        return dataclasses.replace(self, **changes)

    @staticmethod
    def names() -> tuple[str, ...]:
        """The 51 scalar values' names, in the order of :meth:`as_vector`.

        ``ujoint_x_11`` … ``ujoint_y_23``, ``slider_11`` … ``slider_23``,
        ``joint_x_11`` … ``joint_z_23``, ``lever_11`` … ``lever_23``,
        ``centre_x_1`` … ``centre_z_2`` (chain ji: platform j, module i), then the stack-up
        ``spline_x_1``, ``spline_y_1``, ``spline_z_1`` (it moves platform 1).
        """
        out: list[str] = []
        for name, shape in _SHAPES.items():
            if name == "spline":
                out += [f"spline_{axis}_1" for axis in "xyz"]
            elif name == "centre":
                out += [f"centre_{axis}_{j}" for j in (1, 2) for axis in "xyz"]
            elif len(shape) == 2:
                out += [f"{name}_{label}" for label in CHAIN_LABELS]
            else:
                out += [f"{name}_{axis}_{label}" for label in CHAIN_LABELS for axis in "xyz"[: shape[2]]]
        return tuple(out)

    def as_vector(self) -> np.ndarray:
        """The 51 deviations in [m] as one vector, in the order of :meth:`names`."""
        return np.concatenate([getattr(self, name).ravel() for name in _SHAPES])

    @classmethod
    def from_vector(cls, x: np.ndarray) -> ChainGeometry:
        """The inverse of :meth:`as_vector` (``x`` in [m], shape (51,); or (48,): the chains' alone, no stack-up)."""
        x = np.asarray(x, dtype=float)
        sizes = [math.prod(shape) for shape in _SHAPES.values()]
        if x.shape == (CHAIN_COUNT,):
            x = np.concatenate([x, np.zeros(sum(sizes) - CHAIN_COUNT)])
        if x.shape != (sum(sizes),):
            raise ParameterError(f"expected {sum(sizes)} deviations, got shape {x.shape}", key="geometry")
        parts = np.split(x, np.cumsum(sizes)[:-1])
        fields: dict[str, Any] = {name: part.reshape(shape) for (name, shape), part in zip(_SHAPES.items(), parts)}
        return cls(**fields)


@dataclass(frozen=True, eq=False)
class Chains:
    """The six chains resolved to absolute values, in [m] (index j = platform 0, 1; i = module 0, 1, 2).

    Chain ji's U-joint centre is ``b_ji = screw_points[j, i] + L_i·ẑ`` for the
    carriage reading L_i, its platform joint ``a_ji = centres[j] + R_j·platform_points[j, i]``,
    and ``|a_ji − b_ji| = lever_lengths[j, i]``.

    Attributes:
        screw_points: U-joint centre at carriage reading 0, (2, 3, 3): c_i + (u_ji, h_j − h_1 + s_ji).
        platform_points: platform joints in platform axes, r⁰_i + δr_ji, (2, 3, 3).
        lever_lengths: l + δl_ji, (2, 3).
        centres: rotation centres o_j = h_j·ẑ + δo_j at home (m_1's rides on m_2: :func:`stackup_lift`), (2, 3).
        spline_seat: the intermediate chain's seat e in m_2's axes, (3,) (zero: m_1's centre fixed).
        drawing: True when these are the drawing's values (no deviations).
    """

    screw_points: np.ndarray
    platform_points: np.ndarray
    lever_lengths: np.ndarray
    centres: np.ndarray
    spline_seat: np.ndarray = dataclasses.field(default_factory=lambda: np.zeros(3))
    drawing: bool = False

    @property
    def stacked(self) -> bool:
        """True when m_1's centre rides on m_2 (a non-zero spline seat)."""
        return bool(np.any(self.spline_seat))

    def __post_init__(self):
        for name, shape in (
            ("screw_points", (2, 3, 3)),
            ("platform_points", (2, 3, 3)),
            ("lever_lengths", (2, 3)),
            ("centres", (2, 3)),
            ("spline_seat", (3,)),
        ):
            value = readonly(np.array(getattr(self, name), dtype=float))
            if value.shape != shape:
                raise ParameterError(f"expected shape {shape}, got {value.shape}", key=name)
            object.__setattr__(self, name, value)

    @classmethod
    def build(
        cls,
        screw_points: np.ndarray,
        platform_points: np.ndarray,
        lever_length: float,
        heights: np.ndarray,
        geometry: ChainGeometry | None,
    ) -> Chains:
        """The chains of a drawing (c_i (3, 3), r⁰_i (3, 3), l, h_j (2,) in [m]) with ``geometry``'s deviations (None: none)."""
        g = ChainGeometry.zeros() if geometry is None else geometry
        heights = np.asarray(heights, dtype=float)
        screw = np.repeat(np.asarray(screw_points, dtype=float)[None], 2, axis=0)
        screw[..., :2] += g.ujoint
        screw[..., 2] += (heights - heights[0])[:, None] + g.slider
        platform = np.asarray(platform_points, dtype=float)[None] + g.joint
        centres = np.zeros((2, 3))
        centres[:, 2] = heights
        return cls(
            screw_points=screw,
            platform_points=platform,
            lever_lengths=lever_length + g.lever,
            centres=centres + g.centre,
            spline_seat=g.spline,
            drawing=geometry is None,
        )


def geometry_from_table(table: Any, source: str) -> ChainGeometry | None:
    """The ``[geometry]`` table of a parameter file, checked and in SI; None when it is all zero (the drawing).

    Args:
        table: the table as TOML reads it (keys of :data:`GEOMETRY_KEYS`, each optional, in mm).
        source: the file, for errors.

    Raises:
        ParameterError: naming the file and key of an unknown key, a wrong shape, a number that is not
            finite or a deviation beyond :data:`MAX_DEVIATION`.
    """
    if not isinstance(table, Mapping):
        raise ParameterError("expected a [geometry] table", key="geometry", source=source)
    fields: dict[str, Any] = {}
    for key, value in table.items():
        if key == "control":
            if value not in (1, 2) or isinstance(value, bool):
                raise ParameterError(
                    f"expected 1 or 2 (the platform whose motion a trajectory gives), got {value!r}",
                    key="geometry.control",
                    source=source,
                )
            fields["control"] = int(value)
            continue
        if key not in GEOMETRY_KEYS:
            raise ParameterError(
                f"unknown key (known in [geometry]: control, {', '.join(GEOMETRY_KEYS)})",
                key=f"geometry.{key}",
                source=source,
            )
        name, rows, width, _ = GEOMETRY_KEYS[key]
        if rows == 1:  # one row, written flat: spline_seat_mm = [x, y, z]
            numbers = _rows([value], 1, width, f"geometry.{key}", source, shown=value)
        else:
            numbers = _rows(value, rows, width, f"geometry.{key}", source)
        fields[name] = numbers.reshape(_SHAPES[name]) * _MM
    geometry = ChainGeometry.zeros().replace(**fields)
    return None if geometry.is_drawing() else geometry


def _rows(value: Any, rows: int, width: int, key: str, source: str, shown: Any = None) -> np.ndarray:
    """A list of ``rows`` numbers (width 0) or of ``rows`` lists of ``width`` numbers, checked, in the file's unit.

    ``shown``: the value as the file wrote it, for messages (a single row is written flat); None for ``value``.
    """
    shown = value if shown is None else shown

    def number(x):
        return isinstance(x, (int, float)) and not isinstance(x, bool)

    def fail(expected):
        raise ParameterError(f"expected {expected}, got {shown!r}", key=key, source=source)

    axes = ", ".join("xyz"[:width])
    expected = (
        f"a list of {rows} numbers"
        if width == 0
        else f"[{axes}] in mm"
        if rows == 1
        else f"{rows} rows of [{axes}] in mm"
    )
    if not isinstance(value, list) or len(value) != rows:
        fail(expected)
    if width == 0:
        if not all(map(number, value)):
            fail(expected)
    elif not all(isinstance(row, list) and len(row) == width and all(map(number, row)) for row in value):
        fail(expected)
    numbers = np.array(value, dtype=float)
    if not np.all(np.isfinite(numbers)):
        fail("finite numbers")
    if np.any(np.abs(numbers) > MAX_DEVIATION / _MM):
        raise ParameterError(
            f"a deviation from the drawing of at most {MAX_DEVIATION / _MM:g} mm, got {shown!r}",
            key=key,
            source=source,
        )
    return numbers


def geometry_table(geometry: ChainGeometry) -> dict[str, Any]:
    """The ``[geometry]`` table of a parameter file (``control``, then every deviation in mm, 15 significant digits); reads back the same."""
    out: dict[str, Any] = {"control": geometry.control}
    for key, (name, rows, width, _) in GEOMETRY_KEYS.items():
        values = np.vectorize(lambda x: float(f"{x:.15g}"))(getattr(geometry, name) / _MM)
        if rows == 1:
            out[key] = values.reshape(width).tolist()
        else:
            out[key] = values.reshape(rows, width).tolist() if width else values.reshape(rows).tolist()
    return out


def refuse_stackup(chains: Chains, what: str, source: str | None = None) -> None:
    """Refuse, in one line, a stack-up (non-zero ``spline_seat_mm``) where ``what`` (a dynamics model) does not model it.

    Raises:
        ParameterError: naming the key, the value and what cannot use it.
    """
    if chains.stacked:
        raise ParameterError(
            f"the intermediate chain's stack-up ({', '.join(f'{x * 1e3:g}' for x in chains.spline_seat)} mm) moves m_1's "
            f"rotation centre with m_2, which {what} does not model (stations, calibrate, the analytic, Pinocchio and "
            "MuJoCo models and plants do)",
            key=f"geometry.{STACKUP_KEY}",
            source=source,
        )


def stackup_lift(spline_seat: np.ndarray, p2: np.ndarray) -> np.ndarray:
    """How far m_1's rotation centre rides up, Δz = ẑᵀ·(R_2 − I)·e in [m], (N,), at m_2's platform angles.

    With R = Rz(γ)·Ry(β)·Rx(α), ẑᵀR = (−sin β, cos β·sin α, cos β·cos α).

    Args:
        spline_seat: the seat e in m_2's axes in [m], (3,), or one per sample (N, 3).
        p2: m_2's platform angles [α, β, γ] in [rad] (after the angle signs), (N, 3).
    """
    e = np.asarray(spline_seat, dtype=float)
    p2 = np.asarray(p2, dtype=float)
    sa, ca = np.sin(p2[:, 0]), np.cos(p2[:, 0])
    sb, cb = np.sin(p2[:, 1]), np.cos(p2[:, 1])
    return -sb * e[..., 0] + cb * sa * e[..., 1] + (cb * ca - 1.0) * e[..., 2]


def _number(value: float) -> str:
    return repr(float(value))


def per_chain_urdf(doc: Any, chains: Chains, screw_points: np.ndarray) -> None:
    """Move the drawing's URDF (an xml.dom document of ``hip_simulator.urdf.xacro``'s expansion) onto per-chain geometry, in place.

    Chain ji's U-joint (joint ``u1_ji``, on carriage i whose frame is at c_i + L_i·ẑ) moves to
    ``chains.screw_points[j, i] − c_i``; lever ji's centre of mass, drawing and tip frame to its own length;
    platform j's centre (joint ``platform_j_rz``) to ``chains.centres[j]``; its joint frames
    (``platform_j_joint_i_fixed``) to ``chains.platform_points[j, i]``. With a stack-up, m_1's spherical joint
    moves onto the intermediate chain (:data:`STACKUP_JOINTS`, the seat closure :data:`STACKUP_CLOSURE`; module docstring).

    Args:
        doc: the URDF document.
        chains: the resolved chains (:attr:`hipsim.machine.parameter_set.Parameters.chains`).
        screw_points: the drawing's c_i in [m], (3, 3).
    """
    joints = {element.getAttribute("name"): element for element in doc.getElementsByTagName("joint")}
    links = {element.getAttribute("name"): element for element in doc.getElementsByTagName("link")}

    def set_origin(element, xyz):
        element.getElementsByTagName("origin")[0].setAttribute("xyz", " ".join(_number(x) for x in xyz))

    for j in range(2):
        set_origin(joints[f"platform_{j + 1}_rz"], chains.centres[j])
        for i in range(3):
            name = f"{j + 1}{i + 1}"
            set_origin(joints[f"u1_{name}"], chains.screw_points[j, i] - np.array([*screw_points[i, :2], 0.0]))
            set_origin(joints[f"platform_{j + 1}_joint_{i + 1}_fixed"], chains.platform_points[j, i])
            length = chains.lever_lengths[j, i]
            set_origin(joints[f"lever_{name}_tip_fixed"], (0.0, 0.0, length))
            lever = links[f"lever_{name}"]
            for origin in lever.getElementsByTagName("origin"):  # its inertial and its visual, at mid-length
                origin.setAttribute("xyz", f"0 0 {_number(length / 2)}")
            for cylinder in lever.getElementsByTagName("cylinder"):
                cylinder.setAttribute("length", _number(length))
    if chains.stacked:
        _stackup_urdf(doc, joints, chains)
    for visual in doc.getElementsByTagName("visual"):  # the drawn hip joints at the rotation centres
        name = visual.getAttribute("name")
        if name in ("hip_joint_1", "hip_joint_2"):
            set_origin(visual, chains.centres[int(name[-1]) - 1])


def _stackup_urdf(doc: Any, joints: dict, chains: Chains) -> None:
    """Put m_1's spherical joint on the spline's axial slide and add the shaft end's horizontal slides and the seat frame.

    At zero joint values the tree is the machine at home: the slide's body at o_1, the shaft's end at the seat
    o_2 + e (all slides zero), so the seat closure holds with m_2 level.
    """
    robot = doc.documentElement

    def element(tag: str, **attributes: str):
        node = doc.createElement(tag)
        for key, value in attributes.items():
            node.setAttribute(key, value)
        return node

    def joint(name: str, kind: str, parent: str, child: str, xyz, axis: str | None = None) -> None:
        node = element("joint", name=name, type=kind)
        node.appendChild(element("parent", link=parent))
        node.appendChild(element("child", link=child))
        node.appendChild(element("origin", xyz=" ".join(_number(x) for x in xyz), rpy="0 0 0"))
        if axis is not None:
            node.appendChild(element("axis", xyz=axis))
            node.appendChild(element("limit", lower="-0.1", upper="0.1", effort="100000", velocity="1"))
        robot.appendChild(node)
        robot.appendChild(element("link", name=child))  # massless: the analytic model's shaft has no mass

    slide, tip_x, tip_y = STACKUP_JOINTS
    tip, seat = STACKUP_CLOSURE
    joint(slide, "prismatic", "base_link", "spline_1", chains.centres[0], "0 0 1")
    rz = joints["platform_1_rz"]
    rz.getElementsByTagName("parent")[0].setAttribute("link", "spline_1")
    rz.getElementsByTagName("origin")[0].setAttribute("xyz", "0.0 0.0 0.0")
    joint(
        tip_x,
        "prismatic",
        "spline_1",
        "spline_1_slide_x",
        chains.centres[1] + chains.spline_seat - chains.centres[0],
        "1 0 0",
    )
    joint(tip_y, "prismatic", "spline_1_slide_x", "spline_1_slide_y", (0.0, 0.0, 0.0), "0 1 0")
    joint(f"{tip}_fixed", "fixed", "spline_1_slide_y", tip, (0.0, 0.0, 0.0))
    joint(f"{seat}_fixed", "fixed", "platform_2", seat, chains.spline_seat)
