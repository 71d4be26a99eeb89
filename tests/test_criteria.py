"""The grid's camera criteria: windows, blur against closed forms, the chosen criterion reaching the ANFIS, and
what a change of the choice reruns."""

from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr
import yaml
from conftest import copy_workflow, load_config, planned_rules, snakemake
from test_learning import OPTIONS
from test_reference_table import synthetic_grid

from uavdamp import criterion, learning
from uavdamp.camera import CameraModel

CAM = CameraModel.from_config(load_config()["camera"])
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
    weights, samples, shape = criterion.exposure_weights(time, CAM, (0.5, 2.0))
    blur = criterion.pair_blur_p95(path_a[samples], path_b[samples], weights, shape)
    np.testing.assert_allclose(blur, T * np.hypot(r[:, None], s[None, :]), rtol=1e-9)
    first = criterion.first_order_image_path(CAM, np.array([[[1e-3], [2e-3], [1e-4], [3e-4]]]))  # y, z, psi, theta
    np.testing.assert_allclose(first[0, :, 0], [F * (1e-4 + 1e-3 / D), F * (2e-3 / D - 3e-4)], rtol=1e-12)


def test_chosen_criterion_reaches_the_anfis():
    """Three criteria x two windows, each with its own optimal C: the ANFIS learns the chosen one's, and its
    regret is scored on that criterion's grid slice."""
    fy, fz, k = np.linspace(3, 12, 5), np.linspace(3, 12, 4), np.geomspace(10, 1000, 3)
    c = np.geomspace(0.1, 10, 9)
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
        _, record, _ = learning.train(table, grid, options, {"criterion": name, "window": window})
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
    result = snakemake(workdir, "-n", "-j1", "all", "--configfile", configfile, timeout=300)
    assert result.returncode == 0, result.stderr[-3000:]
    return planned_rules(result)


def test_choosing_another_criterion_reruns_table_anfis_study_not_the_grid(tmp_path):
    """A dry run after every output is in place (empty files, marked done with --touch): reference_table.criterion
    or .window reruns the table, the ANFIS and the study; the camera (the blur criterion) reruns the chunks too.
    (--touch records each job's params only while its outputs are missing: touch, create the files, touch.)"""
    work = copy_workflow(tmp_path)
    assert snakemake(work, "-j1", "--touch", "all", "--configfile", "config/quick.yaml").returncode == 0
    result = snakemake(work, "-n", "-j1", "all", "--configfile", "config/quick.yaml", timeout=300)
    outputs = [
        path.strip()
        for line in result.stdout.splitlines()
        if line.strip().startswith("output:")
        for path in line.split("output:", 1)[1].split(",")
    ]
    assert "reports/figures/reference_table_criteria.png" in outputs and "reports/figures/study_blur.png" in outputs
    for path in outputs:
        target = work / path
        if path.endswith("study_strategies"):
            target.mkdir(parents=True, exist_ok=True)
        else:
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_text("")
    assert snakemake(work, "-j1", "--touch", "all", "--configfile", "config/quick.yaml").returncode == 0
    assert _planned(work, "config/quick.yaml") == set()
    quick = yaml.safe_load((work / "config" / "quick.yaml").read_text())
    edits = {
        "criterion": ({"reference_table": {"criterion": "blur"}}, {"reference_table", "anfis", "study", "all"}),
        "window": ({"reference_table": {"window": "steady"}}, {"reference_table", "anfis", "study", "all"}),
        "camera": (
            {"camera": {"exposure_s": 2.0e-3}},
            {"reference_table_chunk", "reference_table", "anfis", "study", "all"},
        ),
    }
    for name, (edit, expected) in edits.items():
        edited = {**quick, **{k: {**quick.get(k, {}), **v} for k, v in edit.items()}}
        (work / "config" / f"edit_{name}.yaml").write_text(yaml.safe_dump(edited))
        assert _planned(work, f"config/edit_{name}.yaml") == expected, name


def test_figures_draw_every_criterion_window_and_strategy():
    """The criteria heatmaps: one column per (criterion, window), one row per K, the learnt one marked; the blur
    and sharp-frame figures: one panel per (case, K), one box or bar per strategy."""
    from uavdamp.plots.reference_table import criteria_figure
    from uavdamp.plots.study import blur_distribution_figure, sharp_fraction_figure

    rng = np.random.default_rng(4)
    table = criterion.reference_table(synthetic_grid(rng.uniform(1, 2, (3, 2, 3, 2, 2, 4)), ("transient", "steady")))
    table.attrs.update(criterion="blur", window="steady")
    fig = criteria_figure(table)
    titles = [ax.get_title() for ax in fig.axes]
    assert sum("gain" in t for t in titles) == 3 * 2 * 2 and any("blur, steady (learnt)" in t for t in titles)
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
