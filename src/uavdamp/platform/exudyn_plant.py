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
from uavdamp.contract import DamperBounds, Observation, SolverFailed
from uavdamp.excitation import on_grid
from uavdamp.platform.model import build
from uavdamp.platform.params import PlatformParams


@dataclass
class RunState:
    """What one run carries between pre-step calls."""

    time: np.ndarray  # s, solver grid
    y: np.ndarray  # m, mount input on the grid (read-only)
    z: np.ndarray
    y_offsets: list  # the same as Python floats: cheaper to hand to Exudyn once per step
    z_offsets: list
    law: object  # the damping law (None for the rigid mount)
    steps_per_update: int
    applied: np.ndarray  # N s m-1, damping applied from each grid point on
    c: float = math.nan  # N s m-1, damping in force
    integral: np.ndarray = field(default_factory=lambda: np.zeros(0))  # servo angle integrals, rad s
    force: np.ndarray = field(default_factory=lambda: np.zeros(0))  # servo I forces, N m


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
        mbs.SetObjectParameter(model.constraints[0], "offset", run.y_offsets[n + 1])
        mbs.SetObjectParameter(model.constraints[1], "offset", run.z_offsets[n + 1])
        if run.law is not None and n > 0 and n % run.steps_per_update == 0:
            self._set_damping(self._demand(n))
        run.applied[n] = run.c
        if self._servo_i:  # servos' I term, explicit: integrate the angle errors, hold for the step
            q = mbs.systemData.GetODE2Coordinates()
            for j, ki in self._servo_i:
                run.integral[j] += h * q[model.q0 + j]
                run.force[j] = -ki * run.integral[j]
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
            mount_y=run.y[: n + 1],
            mount_z=run.z[: n + 1],
            base_velocity=mount_v + np.array([v[i["iso_y"]], v[i["iso_z"]]]),
            mount_velocity=mount_v,
            stroke=np.array([q[i["iso_y"]], q[i["iso_z"]]]),
        )
        return contract.clip(run.law(observation), self.bounds, observation.t_now)

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

    def run(self, time, mount_y, mount_z, *, stiffness: float | None = None, law=None) -> xr.Dataset:
        """Solve one run and return the response dataset (`uavdamp.contract.RESPONSE_VARIABLES`).

        time (s, from 0, increasing), mount_y, mount_z (m): prescribed fuselage displacement at the mount,
        interpolated linearly onto the solver grid (step params.time_step, up to time[-1]).
        stiffness: isolator K, N m-1 (default: the configured K). law: a damping law (`uavdamp.contract.DampingLaw`,
        e.g. `uavdamp.laws.Constant`), required for the isolated mount and ignored by the rigid one (its damping
        output is NaN). The law's update period (None: the configured one) must be a multiple
        of the time step. Initial state: undeformed; the mount moves with the input's initial velocity, the base
        is at rest (isolated) or moves with the mount (rigid), the platform is at rest relative to the base.
        Raises ValueError for bad arguments, SolverFailed if the solver stops early; an exception raised by the
        law stops the run and is re-raised.
        """
        if self.clamped:
            raise ValueError("a clamped platform has no mount input: use eigen()")
        h = self.params.time_step
        grid, y, z = on_grid(time, mount_y, mount_z, h)
        isolated = self.mount == "isolated"
        stiffness, law, steps_per_update = contract.prepare_run(self, stiffness, law)
        y.flags.writeable = z.flags.writeable = False  # a law sees views of these
        n = self.model.n
        self._run = RunState(
            grid,
            y,
            z,
            y.tolist(),
            z.tolist(),
            law,
            steps_per_update or 1,
            np.full(grid.size, math.nan),
            integral=np.zeros(n),
            force=np.zeros(n),
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
        q[i["mount_y"]], q[i["mount_z"]] = run.y[0], run.z[0]
        v[i["mount_y"]], v[i["mount_z"]] = (run.y[1] - run.y[0]) / h, (run.z[1] - run.z[0]) / h
        if run.law is not None:
            v[i["iso_y"]], v[i["iso_z"]] = -v[i["mount_y"]], -v[i["mount_z"]]
            self._pvec[i["iso_y"]] = self._pvec[i["iso_z"]] = stiffness
            self._set_damping(self._demand(0, q, v))
        mbs.SetObjectParameter(model.tree, "jointPControlVector", self._pvec)
        mbs.SetObjectParameter(model.tree, "jointDControlVector", self._dvec)
        mbs.SetObjectParameter(model.tree, "jointForceVector", np.zeros(model.n))
        mbs.SetObjectParameter(model.constraints[0], "offset", float(run.y[0]))
        mbs.SetObjectParameter(model.constraints[1], "offset", float(run.z[0]))
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
        q = np.asarray(mbs.GetSensorStoredData(model.sensors["coordinates"]))[:, 1:]
        rates = np.asarray(mbs.GetSensorStoredData(model.sensors["rates"]))[:, 1:]
        if not success or camera.shape[0] != grid.size:
            raise SolverFailed(
                f"solver stopped at t = {self._solver.it.currentTime:.6g} s of {grid[-1]:.6g} s "
                f"({camera.shape[0]} of {grid.size} samples)"
            )
        applied = run.applied
        applied[-1] = run.c
        mount = np.stack([q[:, i["mount_y"]], q[:, i["mount_z"]]])  # as solved: the constraints' result
        base, stroke_rate = mount.copy(), np.zeros((2, grid.size))
        if run.law is not None:
            base += np.stack([q[:, i["iso_y"]], q[:, i["iso_z"]]])
            stroke_rate = np.stack([rates[:, i["iso_y"]], rates[:, i["iso_z"]]])
        else:
            applied[:] = math.nan
        angle = {name: (q[:, i[name]] if name in i else np.zeros(grid.size)) for name in ("yaw", "pitch")}
        values = {
            "camera_displacement": (camera[:, 1:] - model.camera_local)[:, 1:3].T,  # (axis, time), y and z
            "camera_yaw": angle["yaw"],
            "camera_pitch": angle["pitch"],
            "damping": applied,
            "mount_displacement": mount,
            "base_displacement": base,
            "isolator_velocity": stroke_rate,
        }
        attrs = {
            **contract.response_attrs(self, stiffness),
            "law": getattr(run.law, "name", "none"),
            "newton_iterations": self.newton_iterations,
            "jacobian_updates": self.jacobian_updates,
        }
        return contract.response_dataset(grid, values, attrs)
