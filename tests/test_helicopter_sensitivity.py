"""Helicopter sensitivity runs: run names, parameter changes, dominant-line reading."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from conftest import helicopter_of, solver_options

from uavdamp import io
from uavdamp.helicopter import Spectrum
from uavdamp.helicopter import model as H
from uavdamp.helicopter import sensitivity as S


@pytest.fixture(scope="module")
def heli(default_config) -> H.Helicopter:
    return helicopter_of(default_config["helicopter"])


def test_run_names_parse():
    assert S.parse_run_name("lag_damping_n_m_s_rad=300") == ("lag_damping_n_m_s_rad", 300.0)
    assert S.parse_run_name("hinge_offset_m=1e-05") == ("hinge_offset_m", 1e-5)
    parameter, value = S.parse_run_name("baseline")
    assert parameter == "baseline" and np.isnan(value)
    for bad in ("lag=3", "lag_damping_n_m_s_rad=", "lag_damping_n_m_s_rad"):
        with pytest.raises(ValueError, match="expected 'baseline' or '<parameter>=<value>'"):
            S.parse_run_name(bad)


def test_config_runs_name_known_parameters(default_config, quick_config):
    for cfg in (default_config, quick_config):
        assert set(cfg["helicopter"]["sensitivity"]["parameters"]) <= set(S.PARAMETERS)


def test_varied_changes_one_parameter(heli):
    h = S.varied(heli, "lag_damping_n_m_s_rad", 300.0)
    assert h.main_rotor.lag_damping == 300.0 and h.main_rotor.lag_stiffness == heli.main_rotor.lag_stiffness
    h = S.varied(heli, "fuselage_ixx_scale", 1.3)
    assert h.fuselage.inertia == pytest.approx((1.3 * heli.fuselage.inertia[0], *heli.fuselage.inertia[1:]))
    assert h.fuselage.inertia_xz == pytest.approx(1.3 * heli.fuselage.inertia_xz)
    h = S.varied(heli, "fuselage_inertia_scale", 0.8)
    assert h.fuselage.inertia == pytest.approx(tuple(0.8 * i for i in heli.fuselage.inertia))
    assert S.varied(heli, "imbalance_mass_factor", 0.25).imbalance.mass_factor == 0.25
    assert S.varied(heli, "baseline", np.nan) is heli
    with pytest.raises(ValueError, match="sensitivity parameter 'tail_length'"):
        S.varied(heli, "tail_length", 1.0)
    with pytest.raises(ValueError, match="main_rotor.hinge_offset_m"):
        S.varied(heli, "hinge_offset_m", -0.1)


def test_dominant_lines_of_known_sines():
    """Two sines per axis: the larger one is the dominant line, with its amplitude; the 1/rev line is read
    at the rotor speed. Frequencies on the FFT grid (20 s record, zero padding 8)."""
    dt, duration = 0.005, 20.0
    t = np.arange(0.0, duration, dt)
    grid = 2 * np.pi / (8 * duration)
    w_rotor, w_peak = 44.4, round(50.6 / grid) * grid
    z = 1e-3 * np.sin(w_peak * t) + 4e-4 * np.sin(w_rotor * t)
    y = 1.5e-2 * np.sin(w_rotor * t) + 1e-3 * np.sin(5.0 * t)  # the 5 rad/s line is below the search band
    run = xr.Dataset(
        {"mount_displacement": (("mount", "axis", "time"), np.stack([0 * t, y, z])[None])},
        coords={"mount": ["cg"], "axis": list(H.AXES), "time": t},
    )
    ds = S.dominant_lines(run, rotor_omega_rad_s=w_rotor, min_omega_rad_s=20.0, zero_padding=8)
    assert float(ds.dominant_omega.sel(axis="z")) == pytest.approx(w_peak, abs=1e-9)
    assert float(ds.dominant_amplitude.sel(axis="z")) == pytest.approx(1e-3, rel=0.01)
    assert float(ds.rotor_line_amplitude.sel(axis="z")) == pytest.approx(4e-4, rel=0.02)
    assert float(ds.dominant_omega.sel(axis="y")) == pytest.approx(w_rotor, abs=grid)
    assert float(ds.dominant_amplitude.sel(axis="y")) == pytest.approx(1.5e-2, rel=0.02)


def test_short_run_records_every_parameter(heli):
    options = solver_options(duration=1.0, step=0.0025, output_step=0.005)
    ds = S.run(heli, "lag_damping_n_m_s_rad=300", options)
    io.check_metadata(ds)
    assert ds.mount_displacement.dims == ("run", "mount", "axis", "time")
    assert ds.parameter.values.tolist() == ["lag_damping_n_m_s_rad"]
    assert ds.lag_damping_n_m_s_rad.values[0] == 300.0 and ds.hinge_offset_m.values[0] == heli.main_rotor.hinge_offset
    assert ds.fuselage_ixx_scale.values[0] == 1.0
    both = S.combine(
        [ds, S.run(heli, "baseline", options)],
        rotor_omega_rad_s=heli.main_rotor.omega_rad_s,
        spectrum=Spectrum(min_omega_rad_s=20.0, zero_padding=8),
    )
    io.check_metadata(both)
    assert both.dominant_omega.dims == ("run", "axis") and both.sizes["run"] == 2
    assert both.run.values.tolist() == ["lag_damping_n_m_s_rad=300", "baseline"]
    assert both.lag_damping_n_m_s_rad.values.tolist() == [300.0, heli.main_rotor.lag_damping]
