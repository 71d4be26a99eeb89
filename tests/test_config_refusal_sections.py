"""Config refusal for at least one key of every config section (issue 17), and an unknown key per section.

tests/test_config_checks.py holds the cross-section checks and the Snakemake run that refuses before any job;
this file walks the sections through the same validation (schema, then `uavdamp.checks`). The error must name
the offending key by its path in the schema.
"""

from __future__ import annotations

import pytest
from snakemake.exceptions import WorkflowError
from test_config_checks import _merged, _validate_and_check


def _path(*keys: str) -> str:
    return "schema" + "".join(f"['properties']['{k}']" for k in keys)


# section: (override merged over quick.yaml, text the error must contain)
BAD = {
    "helicopter.fuselage": ({"helicopter": {"fuselage": {"mass": -1.0}}}, _path("helicopter", "fuselage", "mass")),
    "helicopter.main_rotor": (
        {"helicopter": {"main_rotor": {"n_blades": 1}}},
        _path("helicopter", "main_rotor", "n_blades"),
    ),
    "helicopter.solver": ({"helicopter": {"solver": {"step": -0.001}}}, _path("helicopter", "solver", "step")),
    "helicopter.imbalance": ({"helicopter": {"imbalance": {"blade": 9}}}, _path("helicopter", "imbalance", "blade")),
    "platform.structure": (
        {"platform": {"structure": {"camera_mass_kg": 0.0}}},
        _path("platform", "structure", "camera_mass_kg"),
    ),
    "platform.structure.modes": (
        {"platform": {"structure": {"natural_frequencies_hz": [6.7, 6.7, 4.5]}}},
        "[6.7, 6.7, 4.5] has non-unique elements",
    ),
    "platform.solver": ({"platform": {"solver": {"time_step_s": 0.0}}}, _path("platform", "solver", "time_step_s")),
    "platform.response": (
        {"platform": {"response": {"amplitude_m": -1.0}}},
        _path("platform", "response", "amplitude_m"),
    ),
    "platform.backend": ({"platform": {"backend": "analog"}}, "'analog' is not one of ['linear', 'exudyn']"),
    "reference_table": ({"reference_table": {"flat_tolerance": -0.1}}, _path("reference_table", "flat_tolerance")),
    "reference_table.n_chunks": ({"reference_table": {"n_chunks": 0}}, _path("reference_table", "n_chunks")),
    "anfis": ({"anfis": {"train_fraction": 1.5}}, _path("anfis", "train_fraction")),
    "anfis.selection": ({"anfis": {"selection": {"folds": 1}}}, _path("anfis", "selection", "folds")),
    "study": ({"study": {"duration_s": -2.0}}, _path("study", "duration_s")),
    "study.tracking": ({"study": {"tracking": {"method": "music"}}}, "'music' is not one of ['fft', 'esprit']"),
    "study.cases": (
        {"study": {"cases": {"case1": {"amplitude_reading": "rms"}}}},
        "'rms' is not one of ['peak', 'dominant']",
    ),
    "camera": ({"camera": {"exposure_s": -1.0}}, _path("camera", "exposure_s")),
    "camera.image": ({"camera": {"image_width_px": 0}}, _path("camera", "image_width_px")),
}

UNKNOWN = {
    "top": ({"camerra": {"x": 1}}, "('camerra' was unexpected)"),
    "helicopter": ({"helicopter": {"rotor_count": 2}}, "('rotor_count' was unexpected)"),
    "platform": ({"platform": {"isolator": {"stiffnes_n_m": 5.0}}}, "('stiffnes_n_m' was unexpected)"),
    "reference_table": ({"reference_table": {"window_s": [0.0, 1.0]}}, "('window_s' was unexpected)"),
    "anfis": ({"anfis": {"epoch": 3}}, "('epoch' was unexpected)"),
    "study": ({"study": {"tracking": {"windw_s": 1.0}}}, "('windw_s' was unexpected)"),
    "camera": ({"camera": {"iso": 100}}, "('iso' was unexpected)"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_a_bad_value_in_every_section_is_refused_naming_the_key(case):
    override, message = BAD[case]
    with pytest.raises((ValueError, WorkflowError)) as error:
        _validate_and_check(_merged(override))
    assert message in str(error.value), str(error.value)[-2000:]


@pytest.mark.parametrize("section", sorted(UNKNOWN))
def test_an_unknown_key_in_every_section_is_refused_naming_it(section):
    override, message = UNKNOWN[section]
    with pytest.raises(WorkflowError, match="Additional properties are not allowed") as error:
        _validate_and_check(_merged(override))
    assert message in str(error.value), str(error.value)[-2000:]
