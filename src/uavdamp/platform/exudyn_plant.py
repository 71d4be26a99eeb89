"""The Exudyn plant: the platform model stepped in time by Exudyn's implicit solver (the reference plant).

It implements the `uavdamp.contract.Plant` contract. Per step (a pre-step function, before the step that ends
at t): the mount constraints' offsets are set from the input, the damping law is asked for C at its update
times (Observation of the state at the start of the step; the value acts from then on), and the servos'
integral terms are integrated explicitly and applied as joint forces held for the step.
"""

from __future__ import annotations

import math
import time as _time
from dataclasses import dataclass, field

import exudyn as exu
import numpy as np
import xarray as xr

from uavdamp import contract
from uavdamp.contract import DamperBounds, MountMotion, Observation, SolverFailed, line_of_sight, on_grid
from uavdamp.platform.model import MOUNT_LINKS, build, mount_coordinates
from uavdamp.platform.params import PlatformParams


@dataclass
class RunState:
    """What one run carries between pre-step calls."""

    time: np.ndarray  # s, solver grid
    input: MountMotion  # the mount motion on the grid
    u: np.ndarray  # (n, 6) the mount links' coordinates on the grid (read-only): m, then rad
    offsets: list  # the same as Python floats per mount link: cheaper to hand to Exudyn once per step
    law: object  # the damping law (None for the rigid mount)
    steps_per_update: int
    applied: np.ndarray  # N s m-1, damping applied from each grid point on
    c: float = math.nan  # N s m-1, damping in force
    integral: np.ndarray = field(default_factory=lambda: np.zeros(0))  # servo angle integrals, rad s
    force: np.ndarray = field(default_factory=lambda: np.zeros(0))  # servo I forces, N m
    clips: dict = field(default_factory=contract.new_clip_count)  # demands made and clipped (`contract.counted_clip`)


SOLVER_KEYS = (
    "platform.solver.time_step_s",
    "platform.isolator.damping_max_n_s_m",
    "platform.structure.servo_damping_ratio",
)


class ExudynPlant:
    """A platform model built once and solved many times with different K, laws and inputs.

    mount: "isolated" (spring K and damper C in y and z) or "rigid" (the base follows the mount);
    body: "full" or "lumped" (one mass, default the platform's total mass, on the isolator; the "camera" is that
    mass); clamped=True: base fixed to ground, for `eigen` only.
    """

    name = "exudyn"

    def __init__(
        self,
        params: PlatformParams,
        *,
        mount: str = "isolated",
        body: str = "full",
        lumped_mass: float | None = None,
        clamped: bool = False,
    ):
        t0 = _time.perf_counter()
        self.model = build(params, mount=mount, body=body, lumped_mass=lumped_mass, clamped=clamped)
        self.params, self.mount, self.body, self.clamped = self.model.params, mount, body, clamped
        self.bounds = DamperBounds.from_params(self.params)
        self._pvec, self._dvec = self.model.pvec.copy(), self.model.dvec.copy()
        self._servo_i = [(j, ki) for j, ki in enumerate(self.model.servo_ki) if ki > 0]
        if not clamped:
            self.model.mbs.SetPreStepUserFunction(self._pre_step)
        self._solver = exu.MainSolverImplicitSecondOrder()
        self.build_time = _time.perf_counter() - t0
        self._error: Exception | None = None
        self._run: RunState | None = None
        self.newton_iterations = self.jacobian_updates = 0
        self.solve_time = 0.0

    @property
    def joint_stiffness(self) -> np.ndarray:
        """Designed displacement spring (N m-1) and yaw, pitch servo P gains (N m rad-1)."""
        return self.model.joint_stiffness

    def eigen(self) -> tuple[np.ndarray, np.ndarray]:
        """Undamped natural frequencies (Hz, ascending) and mode shapes (columns) by Exudyn.

        Clamped: the platform's three modes. Otherwise the mount is held still, the isolator has the stiffness
        of the last run (before any run: the configured K) and the shapes run over all tree coordinates.
        """
        values, vectors = self.model.mbs.ComputeODE2Eigenvalues(ignoreAlgebraicEquations=False)
        values = np.asarray(values)
        order = np.argsort(values)
        return np.sqrt(np.abs(values[order])) / (2 * np.pi), np.asarray(vectors)[:, order]

    def _settings(self, end_time: float, steps: int) -> exu.SimulationSettings:
        ss = exu.SimulationSettings()
        ss.timeIntegration.endTime = end_time
        ss.timeIntegration.numberOfSteps = steps
        ss.timeIntegration.verboseMode = 0
        ss.timeIntegration.newton.useModifiedNewton = True
        ss.timeIntegration.newton.relativeTolerance = 1e-6  # changes results by < 1e-6 relative
        ss.timeIntegration.generalizedAlpha.spectralRadius = 0.9
        ss.solution.file.write = False
        ss.solution.sensors.writePeriod = self.params.time_step
        ss.show.computationTime = False
        ss.show.statistics = False
        return ss

    # ------------------------------------------------------------------ per step

    def _pre_step(self, mbs, t: float) -> bool:
        """Called by Exudyn before the step that ends at t; an exception stops the solver, re-raised by run."""
        try:
            return self._prepare_step(mbs, t)
        except Exception as error:  # noqa: BLE001 - kept and re-raised unchanged after the solver stops
            self._error = error
            return False

    def _prepare_step(self, mbs, t: float) -> bool:
        """Input offsets, damping update, servo I term for the step ending at t (state still at t - h)."""
        run, model = self._run, self.model
        h = self.params.time_step
        n = int(round(t / h)) - 1  # the step runs from grid point n to n + 1
        for constraint, offsets in zip(model.constraints, run.offsets, strict=True):
            mbs.SetObjectParameter(constraint, "offset", offsets[n + 1])
        if run.law is not None and n > 0 and n % run.steps_per_update == 0:
            self._set_damping(self._demand(n))
        run.applied[n] = run.c
        if self._servo_i:  # servos' I term, explicit: integrate the angle errors, hold for the step
            q = mbs.systemData.GetODE2Coordinates()
            for j, ki in self._servo_i:
                run.integral[j] += h * q[model.q0 + j]
                run.force[j] = model.static_forces[j] - ki * run.integral[j]
            mbs.SetObjectParameter(model.tree, "jointForceVector", run.force)
        return True

    def _demand(self, n: int, q: np.ndarray | None = None, v: np.ndarray | None = None) -> float:
        """The law's demand at grid point n, clipped; q, v: tree coordinates and rates (default: the solver's)."""
        model, run = self.model, self._run
        lo, hi = model.q0, model.q0 + model.n
        q = model.mbs.systemData.GetODE2Coordinates()[lo:hi] if q is None else q
        v = model.mbs.systemData.GetODE2Coordinates_t()[lo:hi] if v is None else v
        i = model.link_index
        mount_v = np.array([v[i["mount_y"]], v[i["mount_z"]]])
        observation = Observation(
            t_now=float(run.time[n]),
            time=run.time[: n + 1],
            mount=run.u[: n + 1],
            base_velocity=mount_v + np.array([v[i["iso_y"]], v[i["iso_z"]]]),
            mount_velocity=mount_v,
            stroke=np.array([q[i["iso_y"]], q[i["iso_z"]]]),
        )
        return contract.counted_clip(run.law, observation, self.bounds, run.clips)

    def _set_damping(self, c: float) -> None:
        """Put C (N s m-1) on both isolator dampers; tell the solver to refresh its Jacobian."""
        if c == self._run.c:
            return
        self._run.c = c
        i = self.model.link_index
        self._dvec[i["iso_y"]] = self._dvec[i["iso_z"]] = c
        self.model.mbs.SetObjectParameter(self.model.tree, "jointDControlVector", self._dvec)
        self.model.mbs.solverSignalJacobianUpdate = True

    # ------------------------------------------------------------------ a run

    def run(self, time, mount: MountMotion, *, stiffness: float | None = None, law=None) -> xr.Dataset:
        """Solve one run and return the response dataset (`uavdamp.contract.RESPONSE_VARIABLES`).

        time (s, from 0, increasing), mount: the prescribed mount motion (`uavdamp.contract.MountMotion`),
        interpolated linearly onto the solver grid (step params.time_step, up to time[-1]).
        stiffness: isolator K, N m-1 (default: the configured K). law: a damping law (`uavdamp.contract.DampingLaw`,
        e.g. `uavdamp.damping.laws.Constant`), required for the isolated mount and ignored by the rigid one (its damping
        output is NaN). The law's update period (None: the configured one) must be a multiple
        of the time step. Initial state: undeformed; the mount moves with the input's initial velocity, the base
        is at rest (isolated) or moves with the mount (rigid), the platform is at rest relative to the base.
        Raises ValueError for bad arguments, SolverFailed if the solver stops early; an exception raised by the
        law stops the run and is re-raised.
        """
        if self.clamped:
            raise ValueError("a clamped platform has no mount input: use eigen()")
        h = self.params.time_step
        grid, motion = on_grid(time, mount, h)
        isolated = self.mount == "isolated"
        stiffness, law, steps_per_update = contract.prepare_run(self, stiffness, law)
        u = mount_coordinates(motion)
        u.flags.writeable = False  # a law sees views of these
        n = self.model.n
        self._run = RunState(
            grid,
            motion,
            u,
            [u[:, k].tolist() for k in range(u.shape[1])],
            law,
            steps_per_update or 1,
            np.full(grid.size, math.nan),
            integral=np.zeros(n),
            force=self.model.static_forces.copy(),
        )
        self._initialise(stiffness)
        self._error = None
        t0 = _time.perf_counter()
        steps = grid.size - 1
        success = self._solver.SolveSystem(self.model.mbs, self._settings(steps * h, steps))
        self.solve_time = _time.perf_counter() - t0
        self.newton_iterations = int(self._solver.it.newtonStepsCount)
        self.jacobian_updates = int(self._solver.it.newtonJacobiCount)
        if self._error is not None:
            raise self._error
        return self._response(success, stiffness if isolated else math.nan)

    def _initialise(self, stiffness: float) -> None:
        """Initial state, stiffness and first damping of a run (see `run`)."""
        model, run = self.model, self._run
        mbs, i, h = model.mbs, model.link_index, self.params.time_step
        q, v = np.zeros(model.n), np.zeros(model.n)
        mount = [i[name] for name in MOUNT_LINKS]
        q[mount], v[mount] = run.u[0], (run.u[1] - run.u[0]) / h
        if run.law is not None:
            v[i["iso_y"]], v[i["iso_z"]] = -v[i["mount_y"]], -v[i["mount_z"]]
            self._pvec[i["iso_y"]] = self._pvec[i["iso_z"]] = stiffness
            self._set_damping(self._demand(0, q, v))
        mbs.SetObjectParameter(model.tree, "jointPControlVector", self._pvec)
        mbs.SetObjectParameter(model.tree, "jointDControlVector", self._dvec)
        mbs.SetObjectParameter(model.tree, "jointForceVector", model.static_forces)
        for constraint, offsets in zip(model.constraints, run.offsets, strict=True):
            mbs.SetObjectParameter(constraint, "offset", offsets[0])
        ode2, ode2_t = np.zeros(mbs.systemData.ODE2Size()), np.zeros(mbs.systemData.ODE2Size())
        ode2[model.q0 : model.q0 + model.n] = q
        ode2_t[model.q0 : model.q0 + model.n] = v
        mbs.systemData.SetODE2Coordinates(ode2, configuration=exu.ConfigurationType.Initial)
        mbs.systemData.SetODE2Coordinates_t(ode2_t, configuration=exu.ConfigurationType.Initial)
        mbs.solverSignalJacobianUpdate = True

    def _response(self, success: bool, stiffness: float) -> xr.Dataset:
        """The response dataset from the sensors (raises SolverFailed if the run stopped early)."""
        model, run = self.model, self._run
        mbs, i, grid = model.mbs, model.link_index, run.time
        camera = np.asarray(mbs.GetSensorStoredData(model.sensors["camera"]))
        if not success or camera.shape[0] != grid.size:
            raise SolverFailed(
                f"solver stopped at t = {self._solver.it.currentTime:.6g} s of {grid[-1]:.6g} s "
                f"({camera.shape[0]} of {grid.size} samples) at K = {stiffness:g} N m-1; the keys that set the step "
                f"and the stiffest force it resolves: {', '.join(SOLVER_KEYS)}"
            )
        q = np.asarray(mbs.GetSensorStoredData(model.sensors["coordinates"]))[:, 1:]
        rates = np.asarray(mbs.GetSensorStoredData(model.sensors["rates"]))[:, 1:]
        rotation = np.asarray(mbs.GetSensorStoredData(model.sensors["camera_rotation"]))[:, 1:].reshape(-1, 3, 3)
        base = np.asarray(mbs.GetSensorStoredData(model.sensors["base"]))[:, 1:]
        applied = run.applied
        applied[-1] = run.c
        stroke, stroke_rate = np.zeros((2, grid.size)), np.zeros((2, grid.size))
        if run.law is not None:
            stroke = np.stack([q[:, i["iso_y"]], q[:, i["iso_z"]]])
            stroke_rate = np.stack([rates[:, i["iso_y"]], rates[:, i["iso_z"]]])
        else:
            applied[:] = math.nan
        yaw, pitch = line_of_sight(rotation[:, :, 0])
        values = {
            "camera_displacement": (camera[:, 1:] - model.camera_local)[:, 1:3].T,  # (axis, time), y and z
            "camera_yaw": yaw,
            "camera_pitch": pitch,
            "damping": applied,
            "mount_displacement": run.input.translation,
            "mount_rotation": run.input.rotation,
            "base_displacement": base[:, 1:3].T,
            "isolator_stroke": stroke,
            "isolator_velocity": stroke_rate,
        }
        attrs = {
            **contract.response_attrs(self, stiffness),
            "law": getattr(run.law, "name", "none"),
            "newton_iterations": self.newton_iterations,
            "jacobian_updates": self.jacobian_updates,
        }
        return contract.response_dataset(grid, values, attrs, run.clips)
