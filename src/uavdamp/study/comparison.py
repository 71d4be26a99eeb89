"""The closed-loop study: every input case, isolator stiffness and damping strategy, with metrics.

For each case and stiffness, each strategy named in the config (``study.strategies``, `uavdamp.study.strategies`)
runs on its plant (`uavdamp.platform.plants`: platform.backend for the isolated mount, Exudyn for the rigid one and for
laws switching every step; `plant` records which); every registered metric (`uavdamp.study.metrics`) is applied to
each run, and responses and metrics are stacked over (case, stiffness, strategy) with xarray.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import xarray as xr

from uavdamp.camera.optics import CameraModel
from uavdamp.contract import NonFiniteDemand, SolverFailed, on_grid
from uavdamp.platform import PlatformParams
from uavdamp.platform.params import StrokeBudget
from uavdamp.platform.plants import Plants
from uavdamp.platform.stroke import stroke_budget
from uavdamp.progress import bar
from uavdamp.settings import attached, require, setting
from uavdamp.signals import tracking
from uavdamp.signals.tracking import TrackerOptions
from uavdamp.sources.excitation import ExcitationOptions, case_motion
from uavdamp.study import metrics, strategies

KEPT = (
    "camera_displacement",
    "camera_yaw",
    "camera_pitch",
    "damping",
    "isolator_stroke",
    "demand_updates",
    "demands_clipped",
)  # response variables kept


@dataclass(frozen=True, kw_only=True)
class StudyOptions:
    """The runs' view of the config's ``study`` section (cases, run length, filter and figures left out), with the
    top-level ``camera`` section attached (the image metrics need it; without it they are skipped)."""

    strategies: tuple[str, ...] = setting()
    stiffness: tuple[float, ...] = setting("stiffness_n_m")  # N m-1
    passive_damping: float = setting("passive_damping_n_s_m")  # N s m-1
    optimal_candidates: int = setting()  # log-spaced candidate C of the optimal passive search
    early_s: float = setting()  # s, end of the window of peak_early
    settle_s: float = setting()  # s, start of the window of std_settled
    tracking: TrackerOptions = setting()
    camera: CameraModel | None = attached()

    def validate(self) -> None:
        require(len(set(self.strategies)) == len(self.strategies), "study.strategies", "names must be unique")
        require(len(set(self.stiffness)) == len(self.stiffness), "study.stiffness_n_m", "values must be unique")


@dataclass(frozen=True)
class Figures:
    """The cases of the paper-style figures (``study.figures``): Figs. 10 and 11, then 12 and 13."""

    case_1: str = setting()
    case_2: str = setting()


@dataclass(frozen=True, kw_only=True)
class StudySection(StudyOptions, ExcitationOptions):
    """The config section ``study``: the cases (`ExcitationOptions`), the runs (`StudyOptions`) and the figures."""

    figures: Figures = setting()
    # K or the tracker band outside the reference table's ranges: refused unless true
    # (`uavdamp.config.checks.extrapolation`)
    allow_extrapolation: bool = setting(default=False)

    def validate(self) -> None:
        StudyOptions.validate(self)
        ExcitationOptions.validate(self)
        for key in ("case_1", "case_2"):
            name = getattr(self.figures, key)
            require(
                name in self.cases,
                f"study.figures.{key}",
                f"{name!r} is not a case of study.cases ({sorted(self.cases)})",
            )
        for key in ("early_s", "settle_s"):
            value = getattr(self, key)
            require(
                value < self.duration_s,
                f"study.{key}",
                f"({value} s) must lie inside study.duration_s ({self.duration_s} s)",
            )


def run_study(
    cases: xr.Dataset,
    params: PlatformParams,
    model,
    options: StudyOptions,
    progress: bool = False,
    budget: StrokeBudget | None = None,
) -> xr.Dataset:
    """Simulate every case x stiffness x strategy; return the comparison dataset (`progress`: a console bar; with
    a stroke `budget`, every run's stroke budget, `uavdamp.platform.stroke`; the cases' ``warning``, if any, as
    ``input_warning``)."""
    plants = Plants(params)
    time = cases.time.values
    per_case = []
    shown = bar(cases.sizes["case"] * len(options.stiffness), "study", "case x K") if progress else None
    for case in cases.case.values:
        mount = case_motion(cases, case)
        per_stiffness = []
        for stiffness in options.stiffness:

            def run(strategy, stiffness=stiffness, mount=mount):
                return plants.for_run(strategy.mount, strategy.law).run(
                    time, mount, stiffness=stiffness, law=strategy.law
                )

            context = strategies.Context(options, params, model, float(stiffness), run)
            per_stiffness.append(_one_case_and_stiffness(context, options.strategies, str(case)))
            if shown is not None:
                shown.update()
        per_case.append(_concat(per_stiffness, "stiffness"))
    if shown is not None:
        shown.close()
    ds = _concat(per_case, "case")
    ds = _finish(ds.transpose("case", "stiffness", "strategy", ...), cases, options, params)
    if budget is not None and "peak_stroke" in ds:
        ds = ds.merge(stroke_budget(budget, params, ds.stiffness, ds.peak_stroke))
    if cases.attrs.get("warning"):  # a case's source flagged (a run flown on an unconverged trim)
        ds.attrs["input_warning"] = cases.attrs["warning"]
    return ds


def _concat(datasets: list[xr.Dataset], dim: str) -> xr.Dataset:
    """Datasets on the same time grid stacked along a new dimension `dim` (variable attributes from the first)."""
    return xr.concat(
        datasets, dim=dim, data_vars="all", coords="minimal", compat="override", join="exact", combine_attrs="override"
    )


def _one_case_and_stiffness(context: strategies.Context, names, case: str = "?") -> xr.Dataset:
    """Runs and metrics of every strategy for one case and stiffness, stacked over `strategy`; a law's non-finite
    demand is a NonFiniteDemand, a stopped solver a SolverFailed, each naming the strategy, the case and K."""
    runs, info = [], {}
    for name in names:
        try:
            strategy = strategies.build(name, context)
            response = context.run(strategy)
        except (NonFiniteDemand, SolverFailed) as error:
            raise type(error)(
                f"study.strategies {name!r}, study.cases.{case}, K = {context.stiffness:g} N m-1: {error}"
            ) from None
        run = xr.merge([response[list(KEPT)], metrics.evaluate(response, context.options)])
        runs.append(run.assign(plant=((), response.attrs["plant"], {"units": "1", "long_name": "plant of the run"})))
        for key, (value, units, long_name) in strategy.info.items():
            info[key] = ((), value, {"units": units, "long_name": long_name})
    return _concat(runs, "strategy").assign(info)


def _finish(ds: xr.Dataset, cases: xr.Dataset, options: StudyOptions, params: PlatformParams) -> xr.Dataset:
    """Coordinate metadata, the input on the solver grid and the tracked frequencies."""
    grid_time = ds.time.values
    kept = ("case", "stiffness", "strategy", "axis", "mount_axis", "time", "frame")
    ds = ds.drop_vars([c for c in ds.coords if c not in kept])
    ds = ds.assign_coords(
        case=cases.case,
        axis=cases.axis,
        mount_axis=cases.mount_axis,
        stiffness=("stiffness", np.asarray(options.stiffness), {"units": "N m-1", "long_name": "isolator stiffness K"}),
        strategy=("strategy", list(options.strategies), {"units": "1", "long_name": "damping strategy"}),
        time=("time", grid_time, {"units": "s", "long_name": "time"}),
    )
    on_solver_grid = [on_grid(cases.time.values, case_motion(cases, c), params.time_step)[1] for c in cases.case]
    for name, values in (
        ("mount_displacement", [m.translation for m in on_solver_grid]),
        ("mount_rotation", [m.rotation for m in on_solver_grid]),
    ):  # the input exactly as the plants resampled it
        ds[name] = (("case", "mount_axis", "time"), np.asarray(values), dict(cases[name].attrs))
    ds = ds.assign_coords(describe_rows(cases, options.strategies))
    ds.attrs = options.camera.attrs() if options.camera is not None else {}
    tracked = tracked_frequencies(cases, options, params.update_period)
    ds = ds.merge(tracked)
    ds.attrs.update(tracked.attrs)  # the band-edge warning, if any
    return ds


def describe_rows(cases: xr.Dataset, names) -> dict:
    """`case_description` and `strategy_description`: one sentence per case (the excitation's `description`) and
    per strategy (`uavdamp.study.strategies.describe`), so the comparison says what its rows are."""
    out = {
        "strategy_description": (
            "strategy",
            [strategies.describe(n) for n in names],
            {"units": "1", "long_name": "what the damping strategy is"},
        )
    }
    if "description" in cases:
        text = [str(v) for v in cases.description.values]
        out["case_description"] = ("case", text, {"units": "1", "long_name": "what the input case is"})
    return out


def tracked_frequencies(cases: xr.Dataset, options: StudyOptions, update_period: float) -> xr.Dataset:
    """`tracked_freq` (case, axis, update_time), Hz: what the ANFIS law sees every update (s)."""
    time = cases.time.values
    rows, update = [], None
    for case in cases.case.values:
        row = []
        for axis in cases.axis.values:
            signal = cases.mount_displacement.sel(case=case, mount_axis=axis).values
            update, freq = tracking.track(time, signal, update_period=update_period, options=options.tracking)
            row.append(freq)
        rows.append(row)
    freq = np.asarray(rows)
    edge = at_band_edge(freq, options.tracking)
    band = f"[{options.tracking.min_freq_hz:g}, {options.tracking.max_freq_hz:g}] Hz"
    edge_attrs = f"within {band_edge_tolerance(options.tracking):g} Hz of the band's edge {band}"
    estimates = np.isfinite(freq).sum(axis=-1)
    share = np.divide(edge.sum(axis=-1), estimates, out=np.zeros(estimates.shape), where=estimates > 0)
    warning = band_edge_warning(share, [str(c) for c in cases.case.values], [str(a) for a in cases.axis.values], band)
    out = xr.Dataset(
        {
            "band_edge_share": (
                ("case", "axis"),
                share,
                {"units": "1", "long_name": f"share of the tracked updates at the band's edge ({edge_attrs})"},
            ),
            "at_band_edge": (
                ("case", "axis", "update_time"),
                edge.astype(np.int8),
                {"units": "1", "long_name": f"1 where tracked_freq sat at the tracker's band edge: {edge_attrs}"},
            ),
            "band_edge_updates": (
                ("case", "axis"),
                edge.sum(axis=-1).astype(np.int64),
                {"units": "1", "long_name": f"updates whose tracked_freq sat at the band edge ({edge_attrs})"},
            ),
            "tracked_freq": (
                ("case", "axis", "update_time"),
                freq,
                {
                    "units": "Hz",
                    "long_name": f"dominant input frequency tracked at each update ({options.tracking.method}; "
                    "NaN: too early)",
                },
            ),
        },
        coords={"update_time": ("update_time", update, {"units": "s", "long_name": "damping update time"})},
    )
    if warning:
        out.attrs["band_edge_warning"] = warning
    return out


BAND_EDGE_WARN_SHARE = 0.05  # a case's tracked updates at the band's edge above this share: the run says so


def band_edge_warning(share: np.ndarray, cases: list[str], axes: list[str], band: str) -> str:
    """The run's warning (empty: none) for every (case, axis) whose share (case, axis) of tracked updates at the
    tracker band's edge exceeds BAND_EDGE_WARN_SHARE: the input's line may lie outside the band."""
    over = [
        f"{case} {axis}: {100 * share[i, j]:.0f} %"
        for i, case in enumerate(cases)
        for j, axis in enumerate(axes)
        if share[i, j] > BAND_EDGE_WARN_SHARE
    ]
    if not over:
        return ""
    return (
        f"tracked frequency at the band's edge {band} in more than {100 * BAND_EDGE_WARN_SHARE:.0f} % of the updates "
        f"({'; '.join(over)}): the input's line may lie outside study.tracking's band (and the ANFIS's)"
    )


def band_edge_tolerance(tracker: TrackerOptions) -> float:
    """Hz: the tracker's frequency resolution 1 / (window_s x zero_padding), the FFT bin of its band search."""
    return 1.0 / (tracker.window * tracker.zero_padding)


def at_band_edge(freq: np.ndarray, tracker: TrackerOptions) -> np.ndarray:
    """True where a tracked frequency (Hz; NaN: no estimate) lies within `band_edge_tolerance` of min_freq_hz or
    max_freq_hz: the search ended at the band's edge, so the input's line may lie beyond it (and beyond the
    frequencies the ANFIS is trained on)."""
    tol = band_edge_tolerance(tracker)
    freq = np.asarray(freq, dtype=float)
    with np.errstate(invalid="ignore"):
        return (np.abs(freq - tracker.min_freq_hz) <= tol) | (np.abs(tracker.max_freq_hz - freq) <= tol)
