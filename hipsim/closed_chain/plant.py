"""The closed-chain Pinocchio model as a simulation plant (spec §6, §8).

:class:`PinocchioPlant` integrates the forward dynamics of the whole kinematic
tree of :func:`hipsim.closed_chain.build.load_model` (3 sliders, 12 universal-joint
angles, each platform's spherical joint as rz-ry-rx revolutes: 21 coordinates)
with its six lever-tip ↔ platform-joint closures enforced as constraints. It
is the independent counterpart of :class:`hipsim.control.simulation.ReducedPlant` (the
3-DOF analytic model with lever spin); the two must agree.

State. x = [q, v], the tree's 21 coordinates and 21 velocities. All joints
are revolute or prismatic, so q is a plain vector and dq/dt = v. The state is
redundant (18 closure equations): :meth:`PinocchioPlant.initial_state` closes
the chain at the first sample with :func:`hipsim.closed_chain.closure.kinematics`
(gap ≤ 1e-12 m, J_c v = 0), and the integrator keeps it close (below).

Derivative. dx/dt = [v, a] with a the constrained forward dynamics

    M a + h(q, v) = τ + J_cᵀ λ,   J_c a = −J̇_c v − K_d·(J_c v) − K_p·g(q)

with g the closure gaps R₁ᵀ(p₁ − p₂) and the generalised forces

    τ = Sᵀ·(2π/p)·τ_motor − Q_f(q, v, F_e):

the actuator force (2π/p)·τ_motor on each slider's prismatic joint (the
screw's rotor inertia is the joint's armature), minus the friction
generalised forces Q_f of spec §4.3 / §7.3 — the laws of
:mod:`hipsim.physics.laws`, as the closed-chain inverse dynamics adds them
(:func:`hipsim.closed_chain.friction.friction_forces`), so inverse then forward
dynamics is consistent. Three routes solve it (``route``, :data:`ROUTES`):

* ``"compiled"`` (the default): all of it compiled, no Pinocchio call on the
  way (:mod:`~hipsim.closed_chain.plant_step`): the tree's forward kinematics
  and CRBA (:mod:`~hipsim.closed_chain.tree_kernel`, from the model's joint
  placements, axes and inertias read once; held equal to ``pin.crba``'s at
  construction), then the closure solver below; :meth:`PinocchioPlant.advance`
  runs a servo period's RK4 steps in one compiled call, and
  :func:`hipsim.control.simulate` the built-in controllers' whole loop around
  them (:meth:`PinocchioPlant.compiled_stepper`). The same arithmetic as
  ``"kernel"`` but for M's rounding (~1e-15 relative).
* ``"kernel"``: ``pin.crba`` in the WORLD convention (M with the
  armature, and the joints' world placements and Jacobians as by-products),
  then one compiled call (:func:`~hipsim.closed_chain.plant_kernel.constrained_acceleration`)
  that evaluates h by Newton–Euler, the closures' frames, Jacobian and drift,
  and solves exactly by coordinate partitioning (18 eliminated coordinates,
  platform 1's three angles kept; with a stack-up platform 2's, see :meth:`PinocchioPlant._kernel_arguments`). It agrees with the converged
  ``constraintDynamics`` to 1e-14 m/s², on and off the closures.
* ``"constraint_dynamics"``: Pinocchio's ``pin.constraintDynamics``
  (``initConstraintDynamics`` once per plant; Data and constraint Data are
  created once and reused), with the proximal settings below.

``pin.lcaba`` (Pinocchio 4.1's loop-constrained ABA, O(n + m)) was tried as a
third: on this 21-coordinate, 18-row tree it is no faster than
``constraintDynamics`` at equal accuracy (μ = 1e-6 and three proximal
iterations for 3e-9 m/s²; with μ = 1e-12 its error is 4e-3 m/s²), and it
ignores the Baumgarte corrector, so the closures would drift. For the default friction (hip joint, thrust bearing,
slider guides and screw; no U/S-joint friction) Q_f is evaluated by one
compiled function (numba, calling the same laws): the platform's angular
Jacobian is T(q) of spec §2, so the platform moment τ_mf(ω = T·q̇) maps to
Q = Tᵀ·τ_mf; the plant checks once, at construction, that the tree's platform
joints really give T and R(q) (else, and whenever the U or S joints have
friction, it falls back on :func:`~hipsim.closed_chain.friction.friction_forces`
with Pinocchio's Jacobians: same laws, slower).

Settings (constructor arguments):

* Proximal solver (the ``"constraint_dynamics"`` route): ``pin.ProximalSettings(1e-12, 1e-12, mu=1e-12, max_iter=2)``.
  Away from singular poses the closure Jacobian has full row rank (18 of 21
  columns: mobility 3), so the KKT system is regular and μ only guards against
  rank loss near singularities (with μ = 0, Pinocchio 4.1 returns NaN on a
  rank-deficient J_c: checked with a duplicated closure). The first proximal iteration solves the μ-regularised
  system (μ in [1/kg], added to the Delassus matrix J_c M⁻¹ J_cᵀ, whose
  smallest eigenvalue here is ≈ 0.012 /kg), a relative bias of
  μ/σ_min ≈ 1e-10 (measured 3e-10 m/s² on |a| ≈ 10); the second removes it
  (measured 8e-14 m/s² from the inverse dynamics' a); a third changes λ by
  exactly 0, so two is the right cap. Each iteration costs ~0.7 µs. (4.1's
  ``absolute_residual`` stays at a few N even at convergence, so only the
  relative test on the change of λ can stop the loop early; with 1e-12 N it
  does not before the cap.)
* Drift stabilisation: Baumgarte, the same scalar gains on every closure,
  K_p = ω_n², K_d = 2 ω_n (critically damped: g̈ + K_d ġ + K_p g = 0) with
  ω_n = 10 rad/s, i.e. K_p = 100 s⁻², K_d = 20 s⁻¹. Why so low: the
  corrector acts on the gaps RK4 produces, and RK4's intermediate stages
  (x + h/2·k₁ …) leave the closure manifold by O(h²) while its combined step
  is accurate to O(h⁵); the corrector turns the stage gaps into K_p·g and
  K_d·ġ accelerations, so high gains inject stage error into the step. Along
  1–5 s of the ISO cycle under the workspace PD at the default 0.5 ms step
  the largest gap was 5e-11 m (growing) without correction, 1.3e-13 m with
  ω_n = 10, and 3e-11 m / 1e-9 m / 2e-8 m with ω_n = 200 / 1000 / 3000
  (ω_n = 3000 diverged at a 1 ms step); of the gains tried (ω_n = 0 … 3000,
  and K_d alone) ω_n = 10 gave the smallest gaps at steps of 0.25, 0.5 and
  1 ms, and they did not grow over 5 s. It is far inside RK4's stability
  region (ω_n h = 0.005) and damps a gap with a 0.1 s time constant,
  fast against the drift it corrects. The corrector's price in the
  motion: with it the Pinocchio and reduced plants agree to 4e-12° over
  0.2 s, without it to 2e-13° (both far below anything measurable).

Angles. :meth:`PinocchioPlant.angles` reads platform 1's spherical joint,
coordinates rx, ry, rz = α, β, γ (R = Rz(γ)·Ry(β)·Rx(α)), and multiplies
them by ``params.angle_signs`` (the model's angles are the platform's; the
gait angles differ by those sign flips, as in the analytic model).

Cost (27 Nov, Python 3.11, pin 4.1, best single calls on a shared 2-core
machine): ``crba`` 2.6 µs and the compiled solve 4.6 µs (1.2 µs of it numba
unboxing 13 arguments), 7.4 µs, against ``constraintDynamics`` (CRBA, bias
forces, the constraint Cholesky, two proximal solves) 12.5 µs; ``lcaba``
14.7 µs at μ = 1e-6 and three iterations; the ``"compiled"`` route's
derivative inside its loop ~4–5 µs (forward kinematics 0.7, CRBA 0.7–1.1,
the solve 2.4–3). The generalised forces add ~1 µs
(one compiled call, most of it in passing the arguments), the rest (call,
slicing, concatenating [v, a]) ~1 µs. See scripts/bench.py and docs/guide/speed.md.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from ..exceptions import ArgumentError
from ..machine.parameters import Parameters
from ..motion.trajectories import Trajectory
from ..physics import laws
from ..physics.orientation import angular_velocity_map
from ..physics.transmission import radians_per_travel
from .build import ClosedChainModel, load_model, require_layout
from .closure import kinematics
from .friction import friction_forces
from .plant_kernel import block_order, constrained_acceleration, tree_constants
from .plant_step import acceleration as compiled_acceleration
from .plant_step import advance as compiled_advance
from .plant_step import generalised_forces, rk4_stage
from .tree_kernel import tree_geometry
from .workspace import _joint_placement_views

__all__ = ["PinocchioPlant", "DEFAULT_BAUMGARTE", "DEFAULT_PROXIMAL", "ROUTES"]


#: Baumgarte gains (K_p [1/s²], K_d [1/s]): critically damped at ω_n = 10 rad/s.
DEFAULT_BAUMGARTE = (10.0**2, 2.0 * 10.0)
#: Proximal settings (absolute accuracy, relative accuracy [N], μ [1/kg], max iterations).
DEFAULT_PROXIMAL = (1e-12, 1e-12, 1e-12, 2)
#: The forward dynamics' routes: all compiled (:mod:`~hipsim.closed_chain.plant_step`: the tree's kinematics and
#: inertia, the closure solver, a servo period's RK4 steps in one call), the compiled closure solver
#: (:mod:`~hipsim.closed_chain.plant_kernel`) after ``pin.crba``, or ``pin.constraintDynamics``. The same
#: equations, fastest first.
ROUTES = ("compiled", "kernel", "constraint_dynamics")


class PinocchioPlant:
    """Forward dynamics of the closed-chain Pinocchio model; state x = [q, v] of the tree.

    Args:
        params: the plant's machine (SI).
        baumgarte: (K_p, K_d) of the closure drift stabilisation, in [1/s²]
            and [1/s]; (0, 0) switches it off.
        mu: proximal regularisation of the constrained dynamics in [1/kg] (> 0).
        max_iter: proximal iterations at most.
        chain: ``load_model(params)`` for these very params, to skip
            building it again (its constraint models are copied, not modified).
        route: how a derivative is evaluated (:data:`ROUTES`): ``"compiled"``, all of
            it compiled (falls back on ``"kernel"`` for a tree whose joints are not
            plain revolute or prismatic ones, or whose compiled inertia differs from
            ``pin.crba``'s), ``"kernel"``, the compiled closure solver after ``pin.crba``
            (falls back on ``"constraint_dynamics"`` for a tree with multi-DoF joints,
            or where Pinocchio's placements cannot be viewed), or
            ``"constraint_dynamics"``; :attr:`route` says which runs. mu and max_iter
            only concern the last.

    Raises:
        ValueError: mu not positive, or a chain built from other parameters.

    A plant reuses its Pinocchio Data and buffers from call to call: do not
    share one between threads.
    """

    name = "pinocchio"

    def __init__(
        self,
        params: Parameters,
        baumgarte: tuple[float, float] = DEFAULT_BAUMGARTE,
        mu: float = DEFAULT_PROXIMAL[2],
        max_iter: int = DEFAULT_PROXIMAL[3],
        chain: ClosedChainModel | None = None,
        route: str = "compiled",
    ):
        if route not in ROUTES:
            raise ArgumentError("route", route, f"one of {', '.join(ROUTES)}")
        if not mu > 0:
            raise ArgumentError("mu", mu, "a positive proximal regularisation")
        if chain is not None and chain.params is not params:
            raise ArgumentError("chain", chain, "load_model(params) of the same params object")
        if route == "constraint_dynamics" and params.geometry is not None and params.chains.stacked:
            # The stack-up's shaft end is massless: M is singular there, and Pinocchio's constraint Cholesky gives NaN.
            raise ArgumentError("route", route, "'compiled' or 'kernel' with a stack-up (its massless slides)")
        self.params = params
        self.chain = load_model(params) if chain is None else chain
        layout = self.chain.layout
        if layout is None:
            raise ArgumentError("chain", chain, "the hip's tree (load_model), whose layout names its joints")
        model = self.model = self.chain.model
        self.nq, self.nv = model.nq, model.nv
        self.data = model.createData()
        # Own copies of the closures, so that the gains do not leak into the caller's model.
        self.constraint_models = pin.StdVec_RigidConstraintModel()
        self.baumgarte = (float(baumgarte[0]), float(baumgarte[1]))
        for cm in self.chain.constraint_models:
            copy = pin.RigidConstraintModel(cm)
            copy.setBaumgarteCorrectorParameters(pin.BaumgarteCorrectorParameters(*self.baumgarte))
            self.constraint_models.append(copy)
        self.constraint_datas = pin.StdVec_RigidConstraintData()
        for cm in self.constraint_models:
            self.constraint_datas.append(cm.createData())
        pin.initConstraintDynamics(model, self.data, self.constraint_models, self.constraint_datas)
        self.proximal = pin.ProximalSettings(DEFAULT_PROXIMAL[0], DEFAULT_PROXIMAL[1], float(mu), int(max_iter))

        self._stages = np.empty((4, self.nq + self.nv))  # RK4's k₁ … k₄, reused by advance()
        # Where advance() evaluates a stage, with persistent views of its q and v for Pinocchio.
        self._y = np.empty(self.nq + self.nv)
        self._y_q, self._y_v = self._y[: self.nq], self._y[self.nq :]
        # Generalised forces: a buffer that only the actuated and friction entries write to.
        self._tau = np.zeros(self.nv)
        self._sliders = [int(k) for k in layout.slider_v]
        self._platforms = [tuple(int(k) for k in layout.platform_v[j]) for j in range(2)]  # (rx, ry, rz)
        # Where the hot path reads and writes: (rx, ry, rz, their velocity slots in x) and (slider, its velocity slot).
        self._platform_slots = np.array([(*p, *(k + self.nq for k in p)) for p in self._platforms], dtype=np.int64)
        self._slider_slots = np.array([(s, s + self.nq) for s in self._sliders], dtype=np.int64)
        self._angles = layout.platform_v[0].copy()
        self._rates = self._angles + self.nq
        self._signs = np.asarray(params.angle_signs, dtype=float).copy()
        self._force_gain = radians_per_travel(params.lead)
        # A plain tuple: numba unboxes it several times faster than the named one (0.4 µs against 2.7 µs a call).
        self._friction = tuple(laws.friction_record(params.friction))
        self._weight = float(params.platform_mass * params.gravity)
        self._fast = not laws.lever_joint_friction_on(params.friction) and self._platform_follows_the_spec()
        #: The closed-form friction's arguments (:func:`~hipsim.closed_chain.plant_step.generalised_forces`).
        # With a stack-up the load presses m_1's centre down the spline's slide (hipsim.machine.chains).
        self._lifted = np.ascontiguousarray(layout.stackup_v[:1], dtype=np.int64)
        self._forces = (
            self._friction,
            self._weight,
            self._force_gain,
            self._platform_slots,
            self._slider_slots,
            self._lifted,
        )
        # For the general friction path and the diagnostics: their own Data, not the dynamics'.
        self._jdata = model.createData()
        self._jdatas = pin.StdVec_RigidConstraintData()
        for cm in self.constraint_models:
            self._jdatas.append(cm.createData())
        self._kernel = self._kernel_arguments() if route in ("compiled", "kernel") else None
        self._tree = self._tree_arguments() if route == "compiled" and self._kernel is not None else None
        #: The route derivatives take (:data:`ROUTES`).
        self.route = (
            "compiled" if self._tree is not None else "kernel" if self._kernel is not None else "constraint_dynamics"
        )
        self._a = np.empty(self.nv)  # the kernel's acceleration, reused by advance()

    # -- the Plant protocol -------------------------------------------------

    def initial_state(self, desired: Trajectory) -> np.ndarray:
        """The closed state at desired's first sample: q, v of the tree (J_c v = 0)."""
        kin = kinematics(self.chain, desired.slice(slice(0, 1)))
        return np.concatenate([kin.q[0], kin.v[0]])

    def derivative(self, t: float, x: np.ndarray, tau: np.ndarray, Fe: float) -> np.ndarray:
        """[v, a] under motor torques tau [N·m] (3,) and load Fe [N]."""
        nq = self.nq
        q, v = x[:nq], x[nq:]
        buf = self._fill_forces(x, tau, Fe)
        if self._tree is not None:
            a = np.empty(self.nv)
            compiled_acceleration(np.ascontiguousarray(x, dtype=float), buf, *self._tree, a)
        elif self._kernel is not None:
            data, views, constants = self._kernel
            pin.crba(self.model, data, q, pin.Convention.WORLD)
            a = np.empty(self.nv)
            constrained_acceleration(*views, x, buf, *constants, a)
        else:
            a = pin.constraintDynamics(
                self.model, self.data, q, v, buf, self.constraint_models, self.constraint_datas, self.proximal
            )
        return np.concatenate((v, a))

    def advance(
        self, t: float, x: np.ndarray, tau: np.ndarray, loads: np.ndarray, h: float, substeps: int
    ) -> np.ndarray:
        """The state after ``substeps`` classic RK4 steps of h [s] from x at time t [s], under motor torques tau [N·m].

        ``loads`` are the loads F_e in [N] at every half step, (2·substeps + 1,).
        The same steps as :func:`hipsim.control.simulate` takes through
        :meth:`derivative`, with fewer Python crossings: between two
        ``constraintDynamics`` calls one compiled call (:func:`_rk4_stage`)
        keeps the last stage's derivative, forms the next stage's state and its
        generalised forces, in reused arrays. A subclass that overrides
        :meth:`derivative` is stepped through it.
        """
        x = np.array(x, dtype=float)
        tau = np.array(tau, dtype=float)  # writable, as the loops' own: a read-only tau compiled the steps again
        # The compiled stages index by these sizes: check them here, where a wrong one can be named.
        if x.shape != self._y.shape:
            raise ArgumentError("x", x, f"a state [q, v] of shape {self._y.shape}")
        if tau.shape != (3,):
            raise ArgumentError("tau", tau, "three motor torques in N·m")
        if self._fast and type(self).derivative is PinocchioPlant.derivative:
            model, data, cms, cds, proximal = (
                self.model,
                self.data,
                self.constraint_models,
                self.constraint_datas,
                self.proximal,
            )
            y, q, v, k, buf = self._y, self._y_q, self._y_v, self._stages, self._tau
            forces = self._forces
            if self._tree is not None:
                compiled_advance(
                    x, tau, np.ascontiguousarray(loads, dtype=float), float(h), int(substeps), forces, *self._tree,
                    y, k, buf, self._a,
                )  # fmt: skip
                return x
            a = buf  # stage 0 reads no derivative
            if self._kernel is not None:
                kdata, views, constants, world, a = *self._kernel, pin.Convention.WORLD, self._a
                for step in range(substeps):
                    for s in range(4):
                        rk4_stage(s, x, y, k, a, h, buf, tau, float(loads[2 * step + (s + 1) // 2]), *forces)
                        pin.crba(model, kdata, q, world)
                        constrained_acceleration(*views, y, buf, *constants, a)
                    rk4_stage(4, x, y, k, a, h, buf, tau, 0.0, *forces)
                return x
            for step in range(substeps):
                for s in range(4):
                    rk4_stage(s, x, y, k, a, h, buf, tau, float(loads[2 * step + (s + 1) // 2]), *forces)
                    a = pin.constraintDynamics(model, data, q, v, buf, cms, cds, proximal)
                rk4_stage(4, x, y, k, a, h, buf, tau, 0.0, *forces)
            return x
        nq = self.nq
        k = self._stages
        if type(self).derivative is not PinocchioPlant.derivative or self._kernel is not None or self._tree is not None:

            def rate(y, Fe, out):
                out[:] = self.derivative(t, y, tau, Fe)
        else:
            model, data, cms, cds, proximal = (
                self.model,
                self.data,
                self.constraint_models,
                self.constraint_datas,
                self.proximal,
            )

            def rate(y, Fe, out):
                out[:nq] = y[nq:]
                out[nq:] = pin.constraintDynamics(
                    model, data, y[:nq], y[nq:], self._fill_forces(y, tau, Fe), cms, cds, proximal
                )

        for s in range(substeps):
            rate(x, loads[2 * s], k[0])
            rate(x + h / 2 * k[0], loads[2 * s + 1], k[1])
            rate(x + h / 2 * k[1], loads[2 * s + 1], k[2])
            rate(x + h * k[2], loads[2 * s + 2], k[3])
            x = x + h / 6 * (k[0] + 2 * k[1] + 2 * k[2] + k[3])
        return x

    def compiled_stepper(self) -> tuple | None:
        """This plant's RK4 steps compiled, for the compiled servo loop (:mod:`hipsim.control.closed_chain_loop`), or None.

        ``(forces, tree, scratch, y, stages, buf, a)`` as
        :func:`~hipsim.closed_chain.plant_step.advance` takes them (its work
        arrays are this plant's: one run at a time). None unless the route is
        ``"compiled"`` with the closed-form friction, and for a subclass: it may
        change the equations (its derivative, its steps), which the compiled
        loop would not see.
        """
        if self._tree is None or not self._fast or type(self) is not PinocchioPlant:
            return None
        return (self._forces, *self._tree, self._y, self._stages, self._tau, self._a)

    @property
    def angle_slots(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Where the gait angles sit in the state: (angle indices, rate indices, signs), angles = signs·x[indices] (as :meth:`angles`).

        With it :func:`hipsim.control.simulate` runs the built-in controllers
        compiled around :meth:`advance`.
        """
        return self._angles, self._rates, self._signs

    def angles(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Gait angles [α, β, γ] in [rad] and their rates in [rad/s], from platform 1's spherical joint."""
        return self._signs * x[self._angles], self._signs * x[self._rates]

    @property
    def reading_slots(self) -> tuple[np.ndarray, np.ndarray, int]:
        """Where :meth:`readings` reads in x: (slider coordinates (3,), platform coordinates (2, 3), nq), for compiled loops."""
        layout = require_layout(self.chain)
        return (
            np.ascontiguousarray(layout.slider_v, dtype=np.int64),
            np.ascontiguousarray(layout.platform_v, dtype=np.int64),
            int(self.nq),
        )

    def readings(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """The carriages' readings L_1i [m] and rates [m/s], (3,), and both platforms' gait angles [rad] and rates [rad/s], (2, 3).

        The slider joints are the carriages' readings (the drawing's L_1i, per chain the encoders').
        """
        nq, platforms, sliders = self.nq, require_layout(self.chain).platform_v, self._sliders
        return (
            x[sliders].copy(),
            x[[nq + k for k in sliders]].copy(),
            self._signs * x[platforms],
            self._signs * x[platforms + nq],
        )

    # -- diagnostics --------------------------------------------------------

    @property
    def closed_form_friction(self) -> bool:
        """True when Q_f is evaluated in closed form (no U/S-joint friction), False on the numpy path."""
        return self._fast

    def generalised_forces(self, x: np.ndarray, tau: np.ndarray, Fe: float) -> np.ndarray:
        """The tree's generalised forces Sᵀ(2π/p)·τ − Q_f(q, v, F_e) that :meth:`derivative` applies, (nv,)."""
        return self._fill_forces(np.asarray(x, dtype=float), np.asarray(tau, dtype=float), Fe).copy()

    def closure_residual(self, x: np.ndarray) -> tuple[float, float]:
        """Largest closure gap |p₁ − p₂| in [m] and largest closure velocity |J_c v| (per closure) in [m/s]."""
        q, v = x[: self.nq], x[self.nq :]
        model, data = self.model, self._jdata
        pin.computeJointJacobians(model, data, q)
        for cm, cd in zip(self.constraint_models, self._jdatas):
            cm.calc(model, data, cd)
        gaps = np.array([cd.c1Mc2.translation for cd in self._jdatas])
        J = pin.getConstraintsJacobian(model, data, self.constraint_models, self._jdatas)
        rates = (J @ v).reshape(-1, 3)
        return float(np.linalg.norm(gaps, axis=1).max()), float(np.linalg.norm(rates, axis=1).max())

    def energy(self, x: np.ndarray) -> tuple[float, float]:
        """Kinetic (screw rotors' armature included) and gravitational potential energy in [J]."""
        q, v = x[: self.nq], x[self.nq :]
        kinetic = pin.computeKineticEnergy(self.model, self._jdata, q, v)
        return float(kinetic), float(pin.computePotentialEnergy(self.model, self._jdata, q))

    # -- internals ----------------------------------------------------------

    def _fill_forces(self, x: np.ndarray, tau: np.ndarray, Fe: float) -> np.ndarray:
        """Write Sᵀ(2π/p)·τ − Q_f into the reused buffer and return it."""
        buf = self._tau
        if self._fast:
            return generalised_forces(
                buf,
                x,
                tau,
                float(Fe),
                self._friction,
                self._weight,
                self._force_gain,
                self._platform_slots,
                self._slider_slots,
                self._lifted,
            )
        nq = self.nq
        buf[:] = -friction_forces(self.chain, x[:nq], x[nq:], Fe, data=self._jdata)
        for i, s in enumerate(self._sliders):
            buf[s] += self._force_gain * tau[i]
        buf[self._lifted] -= Fe
        return buf

    def _kernel_arguments(self) -> tuple | None:
        """The compiled route's Data, its views (``data.M``, ``data.J``, ``data.oMi``) and constants, or None where it cannot run.

        It needs one velocity per joint (revolute, prismatic: the hip's tree),
        and Pinocchio's placements as views (:mod:`~hipsim.closed_chain.workspace`).
        """
        model = self.model
        if model.nq != model.nv or any(joint.nv != 1 for joint in list(model.joints)[1:]):
            return None
        data = model.createData()
        rotations, origins = _joint_placement_views(model, data)
        if rotations is None:
            return None
        # The independent coordinates: platform 1's angles; with a stack-up platform 2's, from which the seat, the
        # carriages and then m_1 follow block by block (from m_1's, m_1 needs the lift, the lift m_2, m_2 the
        # carriages, the carriages m_1: one 21×21 block, 1.3x the time).
        angles = np.asarray(self._platforms[1 if require_layout(self.chain).stackup_v.size else 0], dtype=np.int64)
        others = np.setdiff1d(np.arange(model.nv), angles)
        if 3 * len(self.constraint_models) != others.size:
            return None
        bodies, joints = tree_constants(model)
        closures = np.array([[cm.joint1_id, cm.joint2_id] for cm in self.constraint_models], dtype=np.int64)
        others, blocks = block_order(joints, closures, others)
        order = np.zeros((2, model.nv), dtype=np.int64)
        order[0] = np.concatenate([angles, others])
        order[1, others], order[1, angles] = np.arange(others.size), others.size + np.arange(3)
        placements = np.array(
            [[cm.joint1_placement.homogeneous, cm.joint2_placement.homogeneous] for cm in self.constraint_models]
        )
        settings = np.array([*self.baumgarte, *model.gravity.linear])
        return (
            data,
            (data.M, data.J, rotations, origins),
            (bodies, joints, closures, placements, order, blocks, settings),
        )

    def _tree_arguments(self) -> tuple | None:
        """The compiled route's tree and scratch arrays (:func:`~hipsim.closed_chain.plant_step.acceleration`), or None where it cannot run.

        It needs plain revolute and prismatic joints (:func:`~hipsim.closed_chain.tree_kernel.tree_geometry`),
        and its inertia must be ``pin.crba``'s: checked here at random configurations.
        """
        model = self.model
        geometry = tree_geometry(model)
        if geometry is None or self._kernel is None:
            return None
        armature = np.array(model.armature, dtype=float)
        tree = (*geometry, armature, *self._kernel[2])
        nj, nv = model.njoints, model.nv
        scratch = (np.empty((nj, 3, 3)), np.empty((nj, 3)), np.empty((6, nv)), np.empty((nv, nv)), np.empty((nj, 13)))
        rng, data = np.random.default_rng(2024), model.createData()
        for _ in range(3):
            q = rng.uniform(-1.0, 1.0, model.nq)
            y, a = np.concatenate([q, rng.normal(size=nv)]), np.empty(nv)
            compiled_acceleration(y, np.zeros(nv), tree, scratch, a)
            M = pin.crba(model, data, q, pin.Convention.WORLD)
            M = np.triu(M) + np.triu(M, 1).T
            scale = np.abs(M).max()
            if not (
                np.allclose(scratch[3], M, rtol=0.0, atol=1e-12 * scale)
                and np.allclose(scratch[2], data.J, rtol=0.0, atol=1e-12)
            ):
                return None
        return tree, scratch

    def _platform_follows_the_spec(self) -> bool:
        """Do the platforms turn by R(q) of spec §2, with world angular Jacobians T(q) (columns rx, ry, rz)?

        The closed-form path computes both from the platform's joint angles; checked here at random poses.
        """
        rng = np.random.default_rng(12345)
        model, data = self.model, self.model.createData()
        frames = [model.frames[model.getFrameId(f"platform_{j}")] for j in (1, 2)]
        for _ in range(3):
            q = rng.uniform(-1.0, 1.0, self.nq)
            pin.computeJointJacobians(model, data, q)
            for (ix, iy, iz), frame in zip(self._platforms, frames):
                angles = q[[ix, iy, iz]]
                T = angular_velocity_map(angles[None])[0]
                R = np.array(laws.rotation(np.cos(angles), np.sin(angles)))
                placement = data.oMi[frame.parentJoint] * frame.placement
                if not (
                    np.allclose(data.J[3:, [ix, iy, iz]], T, rtol=0.0, atol=1e-12)
                    and np.allclose(placement.rotation, R, rtol=0.0, atol=1e-12)
                ):
                    return False
        return True
