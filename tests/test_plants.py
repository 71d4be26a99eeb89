"""Which plant runs what: the configured backend for isolated runs, Exudyn for the rigid mount and per-step laws."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import PLATFORM as CONFIG
from conftest import load_config, planar_cases, platform_from, study_options_of

from uavdamp.damping import laws
from uavdamp.platform import ExudynPlant
from uavdamp.platform.linear_plant import LinearPlant
from uavdamp.platform.plants import Plants
from uavdamp.study import comparison as study


@pytest.mark.parametrize(
    ("backend", "mount", "law", "expected"),
    [
        ("linear", "isolated", laws.Constant(2.0), LinearPlant),
        ("linear", "isolated", laws.Schedule([2.0, 5.0]), LinearPlant),
        ("linear", "rigid", None, ExudynPlant),
        ("linear", "isolated", laws.Skyhook(200.0, 0.0, CONFIG["solver"]["time_step_s"]), ExudynPlant),
        ("exudyn", "isolated", laws.Constant(2.0), ExudynPlant),
    ],
)
def test_plant_choice(backend, mount, law, expected):
    plants = Plants(platform_from({**CONFIG, "backend": backend}))
    plant = plants.for_run(mount, law)
    assert isinstance(plant, expected) and plant.mount == mount
    assert plants.for_run(mount, law) is plant  # built once


def test_study_on_the_linear_plant_matches_exudyn():
    """Passive and best-constant runs of a three-line input (7.07 Hz and its +-1 Hz sidebands, as the helicopter's
    Z input) at K = 10 and 1000 N/m: the study's criterion on either backend within 0.5 %."""
    t = np.arange(0, 2.0 + 1e-9, 0.004)
    lines = [(6.07, 0.5e-3), (7.07, 1.0e-3), (7.99, 0.8e-3)]
    y = sum(a * np.sin(2 * np.pi * f * t) for f, a in lines)
    z = sum(a * np.cos(2 * np.pi * f * t + 0.3) for f, a in lines)
    cases = planar_cases("lines", t, y, z)
    config = load_config("quick.yaml")
    cfg = {k: v for k, v in config["study"].items() if k not in ("cases", "duration_s", "highpass_hz", "figures")}
    options = study_options_of({**cfg, "strategies": ["passive", "optimal_passive"]})
    out = {}
    for backend in ("linear", "exudyn"):
        platform = {k: v for k, v in config["platform"].items() if k not in ("response", "stroke")} | {
            "backend": backend
        }
        out[backend] = study.run_study(cases, platform_from(platform), None, options)
    assert set(out["linear"].plant.values.ravel()) == {"linear"}
    assert set(out["exudyn"].plant.values.ravel()) == {"exudyn"}

    def criterion(ds):
        return np.sqrt((ds.camera_displacement.std("time") ** 2).sum("axis"))

    np.testing.assert_allclose(criterion(out["linear"]), criterion(out["exudyn"]), rtol=5e-3)
