"""The grid's camera criteria: windows, blur against closed forms, the chosen criterion reaching the ANFIS, and
what a change of the choice reruns."""

from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr
import yaml
from conftest import ANFIS_OPTIONS as OPTIONS
from conftest import anfis_options as typed
from conftest import (
    camera_of,
    copy_workflow,
    displacement_grid,
    load_config,
    planned_rules,
    snakemake_dry,
    synthetic_grid,
)

from uavdamp.anfis import training as learning
from uavdamp.contract import DamperBounds
from uavdamp.reference_table import criteria as criterion
from uavdamp.reference_table import grid, sine_batch
from uavdamp.study import strategies

CAM = camera_of(load_config()["camera"])
F, T, D = CAM.focal_px, CAM.exposure_s, CAM.scene_distance_m


def response(time, y=0.0, z=0.0, yaw=0.0, pitch=0.0) -> xr.Dataset:
    """A response dataset with the variables the criteria read (m, rad), broadcast over `time` (s)."""
    y, z, yaw, pitch = (np.broadcast_to(np.asarray(v, dtype=float), time.shape) for v in (y, z, yaw, pitch))
    return xr.Dataset(
        {
            "camera_displacement": (("axis", "time"), np.stack([y, z])),
            "camera_yaw": ("time", yaw),
            "camera_pitch": ("time", pitch),
        },
        coords={"time": time, "axis": ["y", "z"]},
    )


def test_windows_select_what_they_say():
    """y = A1 sin up to 1 s, A2 sin after, the camera still then yawing at w: each window sees only its part."""
    t = np.arange(20001) * 1e-4  # s, 0 .. 2 s
    a1, a2, w = 1e-3, 3e-3, 0.02  # m, m, rad/s
    omega = 2 * np.pi * 5.0
    y = np.where(t <= 1.0, a1, a2) * np.sin(omega * t)
    yaw = np.where(t <= 1.0, 0.0, w * (t - 1.0))
    windows = {"early": (0.0, 1.0), "late": (1.0, 2.0)}
    (disp_early, disp_late), (los_early, los_late), (blur_early, blur_late) = criterion.response_criteria(
        response(t, y=y, yaw=yaw), windows, CAM
    )
    assert disp_early == pytest.approx(a1 / math.sqrt(2), rel=1e-3)
    assert disp_late == pytest.approx(a2 / math.sqrt(2), rel=1e-3)
    assert los_early == 0.0
    assert los_late == pytest.approx(w / math.sqrt(12), rel=1e-3)  # std of a ramp over 1 s
    assert blur_early <= F * a1 * omega * T / D  # translation only: at most its fastest image rate x T
    assert blur_late == pytest.approx(F * (w + a2 * omega / D) * T, rel=0.02)  # yaw rate + at most the translation's
    assert blur_late >= F * (w - a2 * omega / D) * T


@pytest.mark.parametrize("case", ["rate", "fast_jitter", "translation"])
def test_blur_criterion_against_closed_forms(case):
    """tests/test_image_quality.py's closed forms through the blur criterion: constant angular rate w: f_px w T
    (exact pinhole: f_px (tan(w t_b) - tan(w t_a)), the 95th percentile over the frames t_a = k / frame rate);
    sinusoidal pitch jitter of amplitude A much faster than the exposure: ~2 A f_px; translation d per exposure
    at distance D: f_px d / D."""
    t = np.arange(200001) * 1e-5  # s, 2 s
    if case == "rate":
        w = 0.05  # rad/s
        t_a = np.arange(int((2.0 - T) * CAM.frame_rate_hz) + 1) / CAM.frame_rate_hz
        exact = np.percentile(F * (np.tan(w * (t_a + T)) - np.tan(w * t_a)), 95)
        assert exact == pytest.approx(F * w * T, rel=0.01)  # psi <= 0.1 rad: tan is within 1 % of linear
        ds, expected, rel = response(t, yaw=w * t), exact, 1e-9
    elif case == "fast_jitter":
        amp = 2e-4  # rad, at 2 kHz: 8 periods per 4 ms exposure
        ds, expected, rel = response(t, pitch=amp * np.sin(2 * np.pi * 2000.0 * t)), 2 * amp * F, 2e-3
    else:
        d = 5e-3  # m per exposure
        ds, expected, rel = response(t, z=d / T * t), F * d / D, 1e-9
    assert criterion.blur_criterion(ds, CAM, (0.0, 2.0)) == pytest.approx(expected, rel=rel)


def test_batched_pair_blur_is_the_blur_of_each_summed_path():
    """Image rates r_i (u) and s_j (v) on the two axes: every pair's summed path blurs by T hypot(r_i, s_j)."""
    time = np.arange(1001) * 2e-3  # s, the default grid's step
    r, s = np.array([10.0, 200.0, 1500.0]), np.array([0.0, 50.0, 700.0, 3000.0])  # px/s
    path_a = np.zeros((time.size, 2, r.size))
    path_a[:, 0] = time[:, None] * r
    path_b = np.zeros((time.size, 2, s.size))
    path_b[:, 1] = time[:, None] * s
    weights, samples, shape = sine_batch.exposure_weights(time, CAM, (0.5, 2.0))
    blur = sine_batch.pair_blur_p95(path_a[samples], path_b[samples], weights, shape)
    np.testing.assert_allclose(blur, T * np.hypot(r[:, None], s[None, :]), rtol=1e-9)
    first = sine_batch.first_order_image_path(CAM, np.array([[[1e-3], [2e-3], [1e-4], [3e-4]]]))  # y, z, psi, theta
    np.testing.assert_allclose(first[0, :, 0], [F * (1e-4 + 1e-3 / D), F * (2e-3 / D - 3e-4)], rtol=1e-12)


def test_chosen_criterion_reaches_the_anfis():
    """Three criteria x two windows, each with its own optimal C: the ANFIS learns the chosen one's, and its
    regret is scored on that criterion's grid slice."""
    fy, fz, k = np.linspace(3, 12, 5), np.linspace(3, 12, 4), np.geomspace(10, 1000, 3)
    c = np.geomspace(0.01, 100, 17)  # log10 C* in [-0.91, 0.81]: every optimum inside the grid
    FY, FZ, K = np.meshgrid(fy, fz, k, indexing="ij")
    values = np.empty((3, 2, fy.size, fz.size, k.size, c.size))
    for i in range(3):
        for w in range(2):  # log10 C* differs per criterion and window; criterion 1 + (log10 C - log10 C*)^2
            best = -0.8 + 0.3 * i + 0.2 * w + 0.05 * FY - 0.03 * FZ + 0.1 * np.log10(K)
            values[i, w] = 1 + (np.log10(c) - best[..., None]) ** 2
    grid = synthetic_grid(values, windows=("transient", "steady"))
    grid = grid.assign_coords(freq_y=fy, freq_z=fz, stiffness=k, damping=c)
    table = criterion.reference_table(grid)
    options = {**OPTIONS, "epochs": 10, "log_stiffness": True, "log_damping": True}
    for name, window in (("blur", "steady"), ("displacement", "transient")):
        _, record, _ = learning.train(table, grid, typed(options), (name, window))
        expected = table.damping_opt.sel(criterion=name, window=window).transpose(*learning.INPUTS).values.ravel()
        np.testing.assert_array_equal(record.damping_reference.values, expected)
        assert (record.attrs["criterion"], record.attrs["window"]) == (name, window)
        chosen = xr.Dataset({"criterion": grid[criterion.variable(name)].sel(window=window, drop=True)})
        X = np.column_stack([record[n].values for n in learning.INPUTS])
        np.testing.assert_allclose(
            record.regret.values, learning.regret(chosen, X, record.damping_predicted.values), rtol=1e-12
        )
        np.testing.assert_allclose(learning.regret(chosen, X, record.damping_reference.values), 1.0, rtol=1e-12)


def _planned(workdir, configfile: str) -> set[str]:
    result = snakemake_dry(workdir, "-n", "-j1", "all", "--configfile", configfile)
    assert result.returncode == 0, result.stderr[-3000:]
    return planned_rules(result)


@pytest.mark.slow
def test_choosing_another_criterion_reruns_table_anfis_study_not_the_grid(tmp_path):
    """A dry run after every output is in place (empty files, marked done with --touch): reference_table.criterion
    or .window reruns the table, the ANFIS and the study; the camera (the blur criterion) reruns the chunks too.
    (--touch records each job's params only while its outputs are missing: touch, create the files, touch.)"""
    work = copy_workflow(tmp_path)
    assert snakemake_dry(work, "-j1", "--touch", "all", "--configfile", "config/quick.yaml").returncode == 0
    result = snakemake_dry(work, "-n", "-j1", "all", "--configfile", "config/quick.yaml")
    outputs = [
        path.strip()
        for line in result.stdout.splitlines()
        if line.strip().startswith("output:")
        for path in line.split("output:", 1)[1].split(",")
    ]
    assert (
        "reports-quick/figures/reference_table_criteria.png" in outputs
        and "reports-quick/figures/study_blur.png" in outputs
    )
    for path in outputs:  # every output a file (the study's strategies figures too: one per case)
        target = work / path
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_text("")
    assert snakemake_dry(work, "-j1", "--touch", "all", "--configfile", "config/quick.yaml").returncode == 0
    assert _planned(work, "config/quick.yaml") == set()
    quick = yaml.safe_load((work / "config" / "quick.yaml").read_text())
    edits = {
        "criterion": (
            {"reference_table": {"criterion": "blur"}},
            {"reference_table", "reference_table_stroke", "anfis", "study", "summary", "all"},
        ),
        "window": (
            {"reference_table": {"window": "steady"}},
            {"reference_table", "reference_table_stroke", "anfis", "study", "summary", "all"},
        ),
        "camera": (
            {"camera": {"exposure_s": 2.0e-3}},
            {"reference_table_chunk", "reference_table", "reference_table_stroke", "anfis", "study", "summary", "all"}
            | {"payload"},  # the payload stage scores its runs with the same camera
        ),
    }
    for name, (edit, expected) in edits.items():
        edited = {**quick, **{k: {**quick.get(k, {}), **v} for k, v in edit.items()}}
        (work / "config" / f"edit_{name}.yaml").write_text(yaml.safe_dump(edited))
        assert _planned(work, f"config/edit_{name}.yaml") == expected, name


def test_figures_draw_every_criterion_window_and_strategy():
    """The criteria heatmaps: one row per (criterion, window), one column per K, the learnt one marked; the blur
    and sharp-frame figures: one panel per (case, K), one box or bar per strategy."""
    from uavdamp.plots.reference_table import criteria_figure
    from uavdamp.plots.study import blur_distribution_figure, sharp_fraction_figure

    rng = np.random.default_rng(4)
    table = criterion.reference_table(synthetic_grid(rng.uniform(1, 2, (3, 2, 3, 2, 2, 4)), ("transient", "steady")))
    table.attrs.update(criterion="blur", window="steady")
    fig = criteria_figure(table)
    titles = [ax.get_title() for ax in fig.axes]
    assert sum("gain" in t for t in titles) == 3 * 2 * 2
    assert any("blur\nsteady (learnt)" in ax.get_ylabel() for ax in fig.axes)
    blur = rng.lognormal(0, 1, (2, 2, 3, 30))
    ds = xr.Dataset(
        {
            "frame_blur": (("case", "stiffness", "strategy", "frame"), blur),
            "sharp_fraction": (("case", "stiffness", "strategy"), (blur <= 1).mean(-1)),
        },
        coords={"case": ["case1", "case2"], "stiffness": [10.0, 1000.0], "strategy": ["passive", "anfis", "skyhook"]},
        attrs={"camera_sharp_threshold_px": 1.0},
    )
    fig = blur_distribution_figure(ds)
    assert len(fig.axes) == 4 and all(len(ax.get_xticklabels()) == 3 for ax in fig.axes)
    bars = sharp_fraction_figure(ds).axes[0].patches
    np.testing.assert_allclose(sorted(b.get_height() for b in bars), np.sort(ds.sharp_fraction.values.ravel()))


# ----------------------------------------------------------------------------------------------------
# The camera criterion and the reference-table reductions against closed forms (planted bugs the mutation run found).

DT = 1e-3  # s


def displacement(t: np.ndarray, y: np.ndarray, z: np.ndarray) -> xr.DataArray:
    return xr.DataArray(np.stack([y, z]), dims=("axis", "time"), coords={"axis": ["y", "z"], "time": t})


def two_halves(amp_y: tuple[float, float], amp_z: tuple[float, float], freq_hz: float = 4.0):
    """0 before t = 1 s; sines of amplitude a0 on [1, 1.5] s and a1 on (1.5, 2] s; zero after 2 s (to 3 s)."""
    t = np.round(np.arange(0, 3 + DT / 2, DT), 9)
    phase = np.sin(2 * np.pi * freq_hz * (t - 1.0))
    first, second = (t >= 1.0) & (t <= 1.5), (t > 1.5) & (t <= 2.0)
    y = np.where(first, amp_y[0], 0.0) * phase + np.where(second, amp_y[1], 0.0) * phase
    z = np.where(first, amp_z[0], 0.0) * phase + np.where(second, amp_z[1], 0.0) * phase
    return t, y, z


def sampled_sine_variance(n_periods_samples: int, n_samples: int) -> float:
    """Variance (1/N) of sin over n_samples points that hold whole periods (n_periods_samples of them) plus zeros.

    sum sin^2 over whole periods sampled uniformly = (samples in whole periods) / 2, sum sin = 0 (N > 2 per period).
    """
    return 0.5 * n_periods_samples / n_samples


def test_window_after_zero_selects_only_the_window():
    """Kills 'window ignored' and 'window halved': the sine sits in [1, 2] s, zeros elsewhere (3 s record).

    Window [1, 2] s: 1001 samples, the 1000 of four whole 4 Hz periods (the sample at 2 s is sin = 0), so
    sigma^2 = A^2 (1000 / 2) / 1001 exactly (1/N, mean exactly 0).
    """
    a_y, a_z = 2e-3, 1e-3
    t, y, z = two_halves((a_y, a_y), (a_z, a_z))
    expected = math.sqrt((a_y**2 + a_z**2) * sampled_sine_variance(1000, 1001))
    assert criterion.camera_criterion(displacement(t, y, z), (1.0, 2.0)) == pytest.approx(expected, rel=1e-12)


def test_window_end_is_honoured_when_the_amplitude_changes_halfway():
    """Kills 'window halved': amplitude 1 mm on [1, 1.5] s, 3 mm on (1.5, 2] s; window [1, 2] s.

    Each half holds two whole 4 Hz periods (500 samples); sum of squares A1^2 250 + A2^2 250 over 1001 samples;
    the mean is 0. A halved window ([1, 1.5] s) would give 1 mm / sqrt(2) * sqrt(500 / 501), far from this.
    """
    t, y, z = two_halves((1e-3, 3e-3), (0.0, 0.0))
    expected = math.sqrt((1e-3**2 * 250 + 3e-3**2 * 250) / 1001)
    assert criterion.camera_criterion(displacement(t, y, z), (1.0, 2.0)) == pytest.approx(expected, rel=1e-12)
    first_half = math.sqrt(1e-3**2 * 250 / 501)
    assert criterion.camera_criterion(displacement(t, y, z), (1.0, 1.5)) == pytest.approx(first_half, rel=1e-12)


def test_standard_deviation_is_the_1_over_n_one():
    """Kills ddof=1: four samples (+a, -a, +a, -a) have sigma = a exactly (1/N); ddof=1 gives a sqrt(4/3)."""
    t = np.array([0.0, 0.1, 0.2, 0.3])
    y = np.array([1.0, -1.0, 1.0, -1.0]) * 3e-3
    got = criterion.camera_criterion(displacement(t, y, np.zeros(4)), (0.0, 0.3))
    assert got == pytest.approx(3e-3, rel=1e-14)


def test_window_with_fewer_than_two_samples_is_refused():
    t = np.array([0.0, 0.1, 0.2, 0.3])
    with pytest.raises(ValueError, match=r"window \[0.15, 0.19\] s holds fewer than 2 samples"):
        criterion.camera_criterion(displacement(t, t, t), (0.15, 0.19))
    # the window's edges are inclusive (to 1e-12 s): [0.1, 0.2] holds the two samples 0.1 and 0.2
    assert criterion.camera_criterion(displacement(t, t, 0 * t), (0.1, 0.2)) == pytest.approx(0.05, rel=1e-12)


# ----------------------------------------------------------------------------------------- reference table


def table_of(ds: xr.Dataset, *args, **kwargs) -> xr.Dataset:
    """The displacement, transient-window table of a synthetic grid (what the ANFIS learns by default)."""
    return criterion.select_table(criterion.reference_table(ds, *args, **kwargs), "displacement", "transient")


def test_overall_best_stiffness_and_its_damping_by_construction():
    """Kills 'stiffness_opt off by one index' and 'damping_at_stiffness_opt always the first K'.

    Every cell holds 1.0 except one planted minimum per frequency pair at a (K, C) chosen by hand.
    """
    values = np.ones((2, 2, 4, 5))
    planted = {(0, 0): (2, 3, 0.1), (0, 1): (0, 1, 0.2), (1, 0): (3, 4, 0.3), (1, 1): (1, 0, 0.4)}
    for (i, j), (k, c, v) in planted.items():
        values[i, j, k, c] = v
        values[i, j, (k + 1) % 4, (c + 2) % 5] = 0.9  # another K's best C differs: the first-K answer is wrong
    table = table_of(displacement_grid(values))
    stiffness, damping = [10.0, 20.0, 50.0, 100.0], [1.0, 2.0, 4.0, 8.0, 16.0]
    for (i, j), (k, c, v) in planted.items():
        assert float(table.stiffness_opt[i, j]) == stiffness[k]
        assert float(table.damping_at_stiffness_opt[i, j]) == damping[c]
        assert float(table.criterion_at_stiffness_opt[i, j]) == v


def test_flat_band_by_construction():
    """Kills 'the flat band reduced to the optimum': criterion 1.2, 1.04, 1.0, 1.05, 1.5 over C = 1..16.

    Within (1 + 0.05) of the optimum 1.0: C = 2, 4, 8 (1.05 is on the edge: inclusive). Within 1.03: C = 4 alone.
    """
    values = np.ones((1, 1, 1, 5))
    values[0, 0, 0] = [1.2, 1.04, 1.0, 1.05, 1.5]
    table = table_of(displacement_grid(values), flat_tolerance=0.05)
    assert float(table.damping_flat_min.squeeze()) == 2.0
    assert float(table.damping_flat_max.squeeze()) == 8.0
    assert "within 5%" in table.damping_flat_min.attrs["long_name"]
    narrow = table_of(displacement_grid(values), flat_tolerance=0.03)
    assert float(narrow.damping_flat_min.squeeze()) == float(narrow.damping_flat_max.squeeze()) == 4.0


@pytest.mark.filterwarnings("ignore:All-NaN slice:RuntimeWarning", "ignore:Mean of empty slice:RuntimeWarning")
def test_flat_band_of_an_all_failed_cell_is_nan():
    values = np.ones((1, 1, 2, 5))
    values[0, 0, 1] = np.nan
    table = table_of(displacement_grid(values))
    assert np.isnan(table.damping_flat_min.values[0, 0, 1]) and np.isnan(table.damping_flat_max.values[0, 0, 1])
    assert table.damping_flat_min.values[0, 0, 0] == 1.0 and table.damping_flat_max.values[0, 0, 0] == 16.0
    assert np.isnan(table.damping_opt.values[0, 0, 1])


def test_scheduling_gain_is_exactly_seven_thirds_on_the_fixture():
    """Kills 'scheduling gain as a max': tests/test_reference_table.py's fixture, worked by hand.

    At K index 1 the best C is C0 (0.2) for f_y index 0 and C3 (0.2) for f_y 1, 2; all other cells 1.0.
    Mean over the 9 frequency pairs: C0 (3 * 0.2 + 6) / 9 = 0.733, C3 (6 * 0.2 + 3) / 9 = 0.467, C1, C2 1:
    the best constant is C3. criterion(C3) / criterion_opt: 1.0 / 0.2 = 5 for the 3 pairs with f_y 0, 1 for
    the other 6; mean 21 / 9 = 7 / 3 (a max would give 5). damping_opt spread: C3 / C0 = 8 / 1.
    """
    values = np.ones((3, 3, 2, 4))
    values[..., 0, 2] = 0.5
    values[0, :, 1, 0] = 0.2
    values[1:, :, 1, 3] = 0.2
    table = table_of(displacement_grid(values))
    assert float(table.scheduling_gain[1]) == pytest.approx(7 / 3, rel=1e-14)
    assert float(table.scheduling_gain[0]) == 1.0
    assert float(table.damping_best_constant[1]) == 8.0 and float(table.damping_best_constant[0]) == 4.0
    np.testing.assert_array_equal(
        table.criterion_best_constant.values[:, :, 1], np.where(np.arange(3)[:, None] == 0, 1.0, 0.2) * np.ones((3, 3))
    )
    assert float(table.damping_opt_spread[1]) == 8.0 and float(table.damping_opt_spread[0]) == 1.0


def test_ties_take_the_smallest_damping_and_failures_are_counted():
    values = np.full((1, 1, 2, 5), 0.7)
    values[0, 0, 0, [1, 3, 4]] = 0.3
    values[0, 0, 1, :] = 0.3  # all equal at K index 1: C = 1 and the smaller K (index 0 also 0.3) wins
    ds = displacement_grid(values)
    ds["failed"] = (grid.DIMS, np.zeros(values.shape, np.int8), {"units": "1", "long_name": "failed"})
    ds["failed"][0, 0, 1, 2] = 1
    table = table_of(ds)
    assert table.damping_opt.values[0, 0].tolist() == [2.0, 1.0]
    assert float(table.stiffness_opt.squeeze()) == 10.0 and float(table.damping_at_stiffness_opt.squeeze()) == 2.0
    assert table.attrs["n_failed_points"] == 1 and table.attrs["tie_rule"] == "smallest damping among equal minima"
    assert table_of(displacement_grid(values)).attrs["n_failed_points"] == 0


def test_optimal_passive_ties_take_the_smallest_damping():
    """Kills 'optimal-passive ties resolved to the largest C': a cost flat at its minimum over C in [2, 50]."""
    bounds = DamperBounds(0.0, 200.0)
    candidates = np.geomspace(0.5, 200.0, 12)

    def cost(c: float) -> float:
        return 1.0 + max(0.0, math.log(2.0 / c)) + max(0.0, math.log(c / 50.0))

    c_best, value = strategies.best_constant(cost, candidates, bounds)
    assert value == 1.0
    first_flat = candidates[candidates >= 2.0][0]  # the smallest candidate on the flat part
    assert c_best <= first_flat and cost(c_best) == 1.0


def test_the_parabola_gain_is_the_drop_to_the_vertex_within_the_bracket():
    """y = (x - 0.3)^2 + 1 at x = -1, 0, 1: the vertex (0.3, 1) lies 0.09 below y(0) = 1.09 on [-1, 1]; on [-1, 0.2]
    the least value is the parabola's at 0.2, 1.01; at a monotone grid edge nothing is promised; a non-finite point
    promises anything (refine)."""
    x = np.array([-1.0, 0.0, 1.0])
    y = (x - 0.3) ** 2 + 1.0
    assert strategies.parabola_gain(x, y, -1.0, 1.0) == pytest.approx(0.09, abs=1e-12)
    assert strategies.parabola_gain(x, y, -1.0, 0.2) == pytest.approx(0.08, abs=1e-12)
    assert strategies.parabola_gain(x + 1.0, -(x**2) - 2.0 * x, 1.0, 2.0) == pytest.approx(0.0, abs=1e-12)
    assert strategies.parabola_gain(x, np.array([1.0, math.inf, 2.0]), -1.0, 1.0) == math.inf
    assert strategies.parabola_gain(x[:2], y[:2], -1.0, 0.0) == math.inf


@pytest.mark.parametrize(
    ("best_c", "min_gain", "refines"),
    [(3.0, 0.01, False), (3.0, 0.001, True), (3.0, 0.0, True), (90.0, 0.02, False), (90.0, 0.005, True)],
)
def test_best_constant_refines_only_where_the_parabola_promises_min_gain(best_c, min_gain, refines):
    """cost = (log C - log best_c)^2 on 5 log-spaced candidates over [1, 100] N s/m: the nearest candidate (3.16 for
    3, the grid's edge 100 for 90) costs 0.0028 (0.0111), and the parabola through the nearest three (exact for this
    cost) promises all of it. Above that min_gain the grid's best is kept after 5 evaluations; below it Brent
    refines to best_c within 1 %."""
    candidates = np.geomspace(1.0, 100.0, 5)
    seen = []

    def cost(c: float) -> float:
        seen.append(c)
        return (math.log(c) - math.log(best_c)) ** 2

    c_best, value = strategies.best_constant(cost, candidates, DamperBounds(0.0, 200.0), min_gain=min_gain)
    nearest = candidates[np.argmin(np.abs(np.log(candidates / best_c)))]
    promised = (math.log(nearest) - math.log(best_c)) ** 2
    assert 0.001 < promised < 0.02
    if refines:
        assert len(seen) > candidates.size and abs(math.log(c_best / best_c)) < 0.01 and value < 1e-4
    else:
        assert len(seen) == candidates.size and c_best == nearest and value == promised


TABLE_METADATA = {  # name: (dims, units, long_name) of every variable reference_table returns (flat_tolerance 0.05)
    "damping_opt": (("freq_y", "freq_z", "stiffness"), "N s m-1", "damping minimising the criterion at each stiffness"),
    "criterion_opt": (("freq_y", "freq_z", "stiffness"), "m", "criterion at damping_opt (displacement)"),
    "damping_flat_min": (("freq_y", "freq_z", "stiffness"), "N s m-1", "smallest damping within 5% of criterion_opt"),
    "damping_flat_max": (("freq_y", "freq_z", "stiffness"), "N s m-1", "largest damping within 5% of criterion_opt"),
    "stiffness_opt": (("freq_y", "freq_z"), "N m-1", "stiffness of the overall best (K, C)"),
    "damping_at_stiffness_opt": (("freq_y", "freq_z"), "N s m-1", "damping of the overall best (K, C)"),
    "criterion_at_stiffness_opt": (("freq_y", "freq_z"), "m", "criterion of the overall best (K, C) (displacement)"),
    "damping_opt_spread": (("stiffness",), "1", "max / min of damping_opt over the input frequencies"),
    "damping_best_constant": (
        ("stiffness",),
        "N s m-1",
        "single damping minimising the mean criterion over all frequencies",
    ),
    "criterion_best_constant": (
        ("freq_y", "freq_z", "stiffness"),
        "m",
        "criterion with damping_best_constant (displacement)",
    ),
    "scheduling_gain": (("stiffness",), "1", "mean of criterion_best_constant / criterion_opt over the frequencies"),
    "optimum_at_grid_edge": (
        ("freq_y", "freq_z", "stiffness"),
        "1",
        "damping_opt on an edge of the C grid (reference_table.damping_n_s_m): 1 bottom, 2 top (a bound inside the "
        "damper's range, not an optimum), 3 the damper's own bound, 0 interior",
    ),
    "grid_edge_share": ((), "1", "share of cells whose damping_opt is a grid bound"),
}


def test_every_table_variable_carries_its_dims_units_and_long_name():
    """The NetCDF contract (CF units, long_name), written out here: a changed unit or name fails."""
    values = np.random.default_rng(5).uniform(0.1, 1.0, (2, 3, 2, 4))
    ds = displacement_grid(values)
    table = table_of(ds)
    assert set(table.data_vars) == set(TABLE_METADATA)
    for name, (dims, units, long_name) in TABLE_METADATA.items():
        assert table[name].dims == dims, name
        attrs = {k: v for k, v in table[name].attrs.items() if not k.startswith("flag_")}  # CF flags: below
        assert attrs == {"units": units, "long_name": long_name}, name
    assert table.optimum_at_grid_edge.attrs["flag_values"].tolist() == [0, 1, 2, 3]
    assert table.optimum_at_grid_edge.attrs["flag_meanings"] == "interior at_grid_bottom at_grid_top at_damper_bound"
    assert table.attrs == {
        "flat_tolerance": 0.05,
        "tie_rule": "smallest damping among equal minima",
        "n_failed_points": 0,
        "criterion": "displacement",
        "window": "transient",
    }
    for coord in ("freq_y", "freq_z", "stiffness"):
        xr.testing.assert_identical(table[coord], ds[coord])
    assert "damping" not in table.coords
    assert criterion.CRITERION_ATTRS == {
        "units": "m",
        "long_name": "camera displacement sqrt(var y + var z) over the window (displacement_std)",
    }


def test_table_with_nan_cells_is_nan_where_all_failed_and_finite_elsewhere():
    values = np.random.default_rng(6).uniform(0.1, 1.0, (2, 2, 2, 3))
    values[1, 1] = np.nan  # every K and C failed at this frequency pair
    with np.errstate(all="ignore"):
        table = table_of(displacement_grid(values))
    for name in ("stiffness_opt", "damping_at_stiffness_opt", "criterion_at_stiffness_opt"):
        assert np.isnan(table[name].values[1, 1]) and np.all(np.isfinite(table[name].values.ravel()[:3])), name
    assert np.all(np.isfinite(table.scheduling_gain)) and np.all(np.isfinite(table.damping_best_constant))


def test_grid_edge_flags_by_construction():
    """On C = 1, 2, 4, 8: an optimum at the first or last C is a grid bound (1, 2) unless that C is the damper's own
    bound (3, inclusive); one step inside is interior (0), no optimum (-1) is 0; int8 flags (CF flag_values)."""
    c = np.array([1.0, 2.0, 4.0, 8.0])
    ic = np.array([-1, 0, 1, 2, 3])
    assert criterion.grid_edge(ic, c, None).tolist() == [0, 1, 0, 0, 2]
    assert criterion.grid_edge(ic, c, (0.5, 10.0)).tolist() == [0, 1, 0, 0, 2]
    assert criterion.grid_edge(ic, c, (1.0, 8.0)).tolist() == [0, 3, 0, 0, 3]
    assert criterion.grid_edge(ic, c, (1.0, 10.0)).tolist() == [0, 3, 0, 0, 2]
    assert criterion.grid_edge(ic, c, (0.5, 8.0)).tolist() == [0, 1, 0, 0, 3]
    assert criterion.grid_edge(ic, c, None).dtype == np.int8


def test_the_default_flat_band_units_and_edge_share_by_construction():
    """Criterion 2.4, 2.08, 2.0, 2.1, 3.0 rad over C = 1..16 in one cell and its optimum on the top edge in the
    other: the default 5 % band is C = 2-8 (2.1 = 1.05 x 2.0, inclusive), the criterion keeps its units, and half
    the cells are grid bounds."""
    values = np.ones((1, 1, 2, 5))
    values[0, 0, 0] = [2.4, 2.08, 2.0, 2.1, 3.0]
    values[0, 0, 1] = [5.0, 4.0, 3.0, 2.0, 1.0]
    da = displacement_grid(values)[criterion.variable("displacement")].isel(window=0).reset_coords(drop=True)
    table = criterion.optimum(da.assign_attrs(units="rad"))
    assert float(table.damping_flat_min[0, 0, 0]) == 2.0 and float(table.damping_flat_max[0, 0, 0]) == 8.0
    assert table.criterion_opt.attrs["units"] == "rad"
    bare = da.copy()
    bare.attrs = {}
    assert criterion.optimum(bare).criterion_opt.attrs["units"] == "m"  # no units: the displacement criterion's
    assert table.optimum_at_grid_edge.values.ravel().tolist() == [0, 2]
    assert float(table.grid_edge_share) == 0.5
    bounded = criterion.optimum(da, damper_bounds=(0.5, 16.0))
    assert bounded.optimum_at_grid_edge.values.ravel().tolist() == [0, 3] and float(bounded.grid_edge_share) == 0.0


def test_the_table_keeps_the_windows_criteria_failures_and_bounds():
    """reference_table over two windows: their start and end coordinates, the criterion coordinate with its CF
    attributes, the failed points counted (0 without a `failed` variable) and the damper's bounds recorded;
    select_grid drops the window; the refusals list what the grid and table hold."""
    values = np.random.default_rng(2).uniform(0.1, 1.0, (2, 2, 3, 2, 2, 4))  # criteria, windows, grid
    grid = synthetic_grid(values, windows=("transient", "steady"))
    grid = grid.assign_coords(window_start=("window", [0.0, 0.5]), window_end=("window", [1.0, 1.0]))
    grid["failed"][0, 0, 0, 0] = 1
    table = criterion.reference_table(grid, damper_bounds=(0.1, 10.0))
    assert table.window_start.values.tolist() == [0.0, 0.5] and table.window_end.values.tolist() == [1.0, 1.0]
    assert table.criterion.attrs == {"units": "1", "long_name": "camera criterion minimised"}
    assert table.criterion.dtype == object
    assert table.attrs["n_failed_points"] == 1 and table.attrs["damper_bounds_n_s_m"] == [0.1, 10.0]
    edge = table.optimum_at_grid_edge.values  # the bounds are the C grid's ends: an edge optimum is the damper's
    assert np.isin(edge, 3).any() and not np.isin(edge, (1, 2)).any()
    assert "n_failed_points" in criterion.reference_table(grid.drop_vars("failed")).attrs
    assert criterion.reference_table(grid.drop_vars("failed")).attrs["n_failed_points"] == 0
    assert "damper_bounds_n_s_m" not in criterion.reference_table(grid).attrs
    chosen = criterion.select_grid(grid, "displacement", "steady")
    assert "window" not in chosen.coords and chosen.dims == ("freq_y", "freq_z", "stiffness", "damping")
    with pytest.raises(ValueError, match=r"the grid holds no criterion variable \(\['criterion_displacement'"):
        criterion.reference_table(grid.drop_vars([v for v in grid.data_vars if v.startswith("criterion_")]))
    with pytest.raises(ValueError, match=r"the grid holds no 'criterion_blur'"):
        criterion.select_grid(grid, "blur", "steady")
    with pytest.raises(ValueError, match=r"'nope' is not one of \['displacement'"):
        criterion.check_choice("nope", "steady", ["steady"])
    with pytest.raises(ValueError, match=r"'late' is not one of reference_table.windows \['transient', 'steady'\]"):
        criterion.check_choice("displacement", "late", ["transient", "steady"])
    with pytest.raises(ValueError, match=r"'blur' is not in the table \(\['displacement', 'line_of_sight'\]\)"):
        criterion.select_table(table, "blur", "steady")


def test_window_steps_are_the_run_grids_samples_inside_the_window():
    """A 1 s run on a 0.1 s grid has samples 0..10; [0.3, 0.4] holds 3 and 4 (two samples: enough), [0.35, 0.4]
    only 4 (refused, naming the window); the whole run holds all 11."""
    from uavdamp.reference_table.sine_batch import window_steps

    assert window_steps(1.0, (0.3, 0.4), 0.1).tolist() == [3, 4]
    assert window_steps(1.0, (0.0, 1.0), 0.1).tolist() == list(range(11))
    with pytest.raises(ValueError, match=r"window \[0.35, 0.4\] s holds fewer than 2 samples"):
        window_steps(1.0, (0.35, 0.4), 0.1)
