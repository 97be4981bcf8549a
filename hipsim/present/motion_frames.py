"""The frames a viewer shows: a trajectory resampled at the display's rate and closed at every sample.

A :class:`Motion` holds the closed samples themselves (never an
interpolation between them), with what is drawn on them: the actuator forces
and each lever's force on its platform (closed-chain inverse dynamics), the
singularity measure, and the human's right-hip angles. :func:`closed_motion`
makes one; :class:`hipsim.present.viewer.Viewer` shows it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from ..exceptions import ArgumentError, PoseError
from ..machine.parameters import Parameters
from ..motion.trajectories import Trajectory, interpolator
from .human import human_hip_angles

__all__ = ["Motion", "closed_motion", "platform_forces"]


@dataclass(frozen=True, eq=False)
class Motion:
    """The closed samples a viewer shows, with what is drawn on them.

    Attributes:
        t: trajectory time of each frame in [s], shape (N,).
        fps: frames per second of the display.
        speed: playback speed (1 = real time).
        angles: platform angles [α, β, γ] in [rad] as the machine turns them
            (angle_signs applied), shape (N, 3).
        q: closed tree configurations, shape (N, nq).
        residual: largest closure gap of each frame in [m], shape (N,).
        F_act: actuator force on each carriage in [N], shape (N, 3), or None.
        F_joint: force each lever exerts on its platform at a_ji, world axes,
            in [N], shape (N, 2, 3, 3), or None.
        cond_inv: singularity measure per frame, shape (N,), or None.
        hip: the human's right-hip joint values [right_hip_Z, right_hip_X,
            right_hip_Y] in [rad], shape (N, 3).
        periodic: the frames tile a period (the animation loops seamlessly).
        name: where the trajectory came from.
    """

    t: np.ndarray
    fps: float
    speed: float
    angles: np.ndarray
    q: np.ndarray
    residual: np.ndarray
    F_act: np.ndarray | None
    F_joint: np.ndarray | None
    cond_inv: np.ndarray | None
    hip: np.ndarray
    periodic: bool
    name: str

    def __len__(self) -> int:
        return self.t.size

    def forces(self) -> tuple[np.ndarray, np.ndarray] | None:
        """(F_act, F_joint) of a motion drawn with forces (both are given or neither); None without."""
        if self.F_act is None or self.F_joint is None:
            return None
        return self.F_act, self.F_joint

    @property
    def rate(self) -> float:
        """Frames per second of trajectory time, fps/speed."""
        return self.fps / self.speed

    @property
    def duration(self) -> float:
        """Trajectory time the frames cover in [s] (a whole period when periodic)."""
        return len(self) / self.rate if self.periodic else float(self.t[-1] - self.t[0])


def _resample(trajectory: Trajectory, rate: float) -> tuple[Trajectory, bool]:
    """The trajectory at ``rate`` samples per second of its time (whole periods if periodic)."""
    t = trajectory.t
    if t.size < 2:
        return trajectory, False
    dt = (t[-1] - t[0]) / (t.size - 1)
    if trajectory.periodic:
        period = t[-1] - t[0] + dt
        n = max(2, int(round(period * rate)))
        times = t[0] + np.arange(n) * (period / n)
    else:
        n = int(math.floor((t[-1] - t[0]) * rate + 1e-9)) + 1
        # Shorter than one frame's step: its first and last samples (a frame one step on would lie beyond its end).
        times = t[0] + np.arange(n) / rate if n >= 2 else np.array([t[0], t[-1]])
    # Sample times that are samples of the trajectory are taken as they are; others are interpolated.
    index = np.clip(np.round((times - t[0]) / dt).astype(int), 0, t.size - 1)
    if np.allclose(t[index], times, rtol=0.0, atol=1e-9 * dt):
        return trajectory.slice(index), trajectory.periodic
    return interpolator(trajectory)(times), trajectory.periodic


def _check_reach(params: Parameters, trajectory: Trajectory) -> None:
    """A pose out of reach named as `torques` names it: by its sample's time (and file line), not a frame's.

    The frames shown lie between the trajectory's samples; a pose out of reach
    among the samples is found there first. Near-singular poses are left to
    the frames, which may show them.
    """
    from ..analytic.inverse_kinematics import kinematics as analytic_kinematics

    heights = np.asarray(analytic_kinematics(params, trajectory, on_error="flag").L).reshape(len(trajectory), -1)
    reached = np.all(np.isfinite(heights), axis=1)
    if not reached.all():
        k = int(np.argmin(reached))
        try:
            analytic_kinematics(
                params, trajectory.slice(slice(k, k + 1))
            )  # the analytic model's message for that sample
        except PoseError as error:
            raise PoseError(error.reason, error.time, k, source=error.source) from None


def platform_forces(chain, Q: np.ndarray, lambdas: np.ndarray) -> np.ndarray:
    """World force of each lever on its platform, −R_tip·λ, shape (N, 2, 3, 3).

    Args:
        chain: the closed-chain model (:func:`hipsim.closed_chain.build.load_model`).
        Q: closed tree configurations, shape (N, nq).
        lambdas: closure forces in each lever tip's frame in [N], shape (N, 2, 3, 3).
    """
    model = chain.model
    data = model.createData()
    tips = [[model.getFrameId(f"lever_{j + 1}{i + 1}_tip") for i in range(3)] for j in range(2)]
    out = np.empty_like(lambdas)
    for k, q in enumerate(Q):
        pin.framesForwardKinematics(model, data, q)
        for j in range(2):
            for i in range(3):
                out[k, j, i] = -data.oMf[tips[j][i]].rotation @ lambdas[k, j, i]
    return out


def closed_motion(
    chain,
    params: Parameters,
    trajectory: Trajectory,
    *,
    fps: float,
    speed: float = 1.0,
    forces: bool = False,
    singularity: bool = False,
) -> Motion:
    """The closed frames that show ``trajectory`` at ``fps`` frames per second, played ``speed`` times real time.

    The trajectory is resampled at fps/speed samples per second of its time
    (whole periods when it is periodic, so that a loop is seamless) and the
    chain closed at every sample with Pinocchio (closure gap ≤ 1e-12 m).

    Args:
        chain: the closed-chain model of ``params``.
        params: the machine.
        trajectory: the motion to show.
        fps: frames per second of the display.
        speed: playback speed, 1 = real time.
        forces: also compute the actuator and joint forces (closed-chain inverse dynamics).
        singularity: also keep the singularity measure of each frame.

    Raises:
        ArgumentError: fps or speed is not a positive number.
        PoseError: a sample is out of reach or singular.
    """
    from ..closed_chain.closure import kinematics
    from ..closed_chain.dynamics import trajectory_dynamics

    if not (fps > 0 and speed > 0 and math.isfinite(fps) and math.isfinite(speed)):
        raise ArgumentError("fps, speed", (fps, speed), "positive numbers")
    rate = fps / speed
    _check_reach(params, trajectory)
    samples, periodic = _resample(trajectory, rate)
    F_act = F_joint = cond_inv = None
    if forces:
        kin, torques = trajectory_dynamics(chain, samples)
        F_act = np.array(torques.F_act)
        F_joint = platform_forces(chain, kin.q, np.asarray(torques.lambdas))
    else:
        kin = kinematics(chain, samples)
    if singularity:
        cond_inv = np.array(kin.cond_inv)
    from ..analytic.inverse_kinematics import rotation_matrix

    hip = human_hip_angles(rotation_matrix(np.asarray(kin.angles)))
    return Motion(
        t=np.array(samples.t),
        fps=float(fps),
        speed=float(speed),
        angles=np.array(kin.angles),
        q=np.array(kin.q),
        residual=np.array(kin.residual),
        F_act=F_act,
        F_joint=F_joint,
        cond_inv=cond_inv,
        hip=hip,
        periodic=periodic,
        name=trajectory.name,
    )
