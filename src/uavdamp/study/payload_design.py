"""The payload's design in closed form, beside the runs: the mounts' six rigid-body modes, the gimbal's loops
(crossovers and margins per stabilised axis) and what each mount passes from the mount's motion to the line of
sight (`uavdamp.study.transmissibility`), as one dataset (the payload stage's ``payload/design.nc``).
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from uavdamp.platform.gimbal import AXES
from uavdamp.platform.gimbal_loop import design_report
from uavdamp.platform.six_axis import DOFS, axis_transmissibility, dominant_dofs, rigid_body_modes
from uavdamp.platform.wire_rope import post_yield, sine_transmissibility
from uavdamp.study import transmissibility
from uavdamp.study.payload_runs import gimbal_params, gimbal_payload, isolator


def _modes(section) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(mount, mode) frequencies Hz and dominant-DOF labels at the middle C (rigid: NaN and ""), the mode shapes
    (mount, dof, mode) at the reference point scaled to a largest coordinate of +1 (m or rad per unit of it), and
    the wire-rope mount's fully yielded modes (`uavdamp.platform.wire_rope.post_yield`; NaN on the other mounts)."""
    freqs = np.full((len(section.mounts), len(DOFS)), math.nan)
    yielded = freqs.copy()
    shapes = np.full((len(section.mounts), len(DOFS), len(DOFS)), math.nan)
    labels = np.full(freqs.shape, "", dtype=object)
    for j, mount in enumerate(section.mounts):
        found = isolator(section, mount, section.middle_damping)
        if found is not None:
            freqs[j], phi = rigid_body_modes(found)
            labels[j] = ["+".join(d) for d in dominant_dofs(phi, found.payload)]
            largest = phi[np.argmax(np.abs(phi), axis=0), np.arange(phi.shape[1])]
            shapes[j] = phi / largest
        if mount == "wire_rope":
            yielded[j] = rigid_body_modes(post_yield(found, section.wire_rope.params()))[0]
    return freqs, labels.astype(str), shapes, yielded


WIRE_ROPE_FREQ_HZ = np.geomspace(1.0, 40.0, 25)  # Hz, the wire rope's time-domain curves (choice: 1-40 Hz)
WIRE_ROPE_AMPLITUDES_M = (1e-4, 1e-3, 3e-3)  # m, their mount sines (choice: about the cases' lateral strokes)


def isolator_curves(section) -> xr.Dataset:
    """The isolator maker's per-axis curve |payload translation / mount translation| along x, y, z at the middle C:
    the six-axis isolator's in closed form (`six_axis.axis_transmissibility`) and the wire rope's at each of
    `WIRE_ROPE_AMPLITUDES_M` in the time domain (`wire_rope.sine_transmissibility`), on `WIRE_ROPE_FREQ_HZ`; empty
    without a wire-rope mount."""
    if "wire_rope" not in section.mounts:
        return xr.Dataset()
    c = section.middle_damping
    found = isolator(section, "wire_rope", c)
    c_semi = [c] * len(found.semi_active)
    wire = section.wire_rope.params()
    curves = np.stack(
        [sine_transmissibility(found, wire, WIRE_ROPE_FREQ_HZ, a, c_semi) for a in WIRE_ROPE_AMPLITUDES_M]
    )
    linear = axis_transmissibility(found, WIRE_ROPE_FREQ_HZ, c_semi)[:, :3].T
    dims = ("excitation_amplitude", "direction", "isolator_frequency")
    text = "payload translation per mount translation along the axis (a mount sine of that amplitude along it alone)"
    return xr.Dataset(
        {
            "wire_rope_transmissibility": (dims, curves, {"units": "1", "long_name": f"wire rope: {text}"}),
            "six_axis_transmissibility": (
                dims[1:],
                linear,
                {"units": "1", "long_name": f"six-axis, closed form: {text}"},
            ),
        },
        coords={
            "excitation_amplitude": (
                "excitation_amplitude",
                list(WIRE_ROPE_AMPLITUDES_M),
                {"units": "m", "long_name": "mount sine amplitude"},
            ),
            "isolator_frequency": (
                "isolator_frequency",
                WIRE_ROPE_FREQ_HZ,
                {"units": "Hz", "long_name": "mount sine frequency (per-axis curves)"},
            ),
            "direction": ("direction", ["x", "y", "z"], {"units": "1", "long_name": "mount translation direction"}),
        },
    )


def design_dataset(section) -> xr.Dataset:
    """The mounts' six rigid-body modes (Hz, at the middle C; rigid: NaN; the wire rope's small-amplitude and fully
    yielded) with their dominant DOFs beside the gimbal's designed and achieved loop crossovers and margins per
    stabilised axis (`gimbal_loop.design_report`) and the transmissibility to the line of sight
    (`uavdamp.study.transmissibility.dataset`); `section` a `uavdamp.study.payload.PayloadSection`."""
    freqs, labels, shapes, yielded = _modes(section)
    p = gimbal_params(section)
    report = design_report(p)
    axes = list(report.axis.values)
    designed = [p.rate_crossover_hz[AXES.index(a)] for a in axes]
    per_axis = {
        "rate_crossover_design": (designed, "Hz", "rate loop crossover specified"),
        "rate_crossover": (report.rate_crossover_hz.values, "Hz", "rate loop crossover achieved"),
        "rate_phase_margin": (report.rate_phase_margin_deg.values, "degree", "rate loop phase margin achieved"),
        "whole_phase_margin": (
            report.whole_phase_margin_deg.values,
            "degree",
            "whole loop phase margin (at the torque)",
        ),
        "whole_gain_margin": (report.whole_gain_margin_db.values, "1", "whole loop gain margin (at the torque), in dB"),
        "attitude_crossover": (report.attitude_crossover_hz.values, "Hz", "attitude loop crossover achieved"),
    }
    data = {k: (("axis",), np.asarray(v), {"units": u, "long_name": n}) for k, (v, u, n) in per_axis.items()}
    data["mode_frequency"] = (("mount", "mode"), freqs, {"units": "Hz", "long_name": "isolator rigid-body mode"})
    data["mode_dofs"] = (("mount", "mode"), labels, {"units": "1", "long_name": "dominant DOFs of the mode (energy)"})
    data["mode_shape"] = (
        ("mount", "dof", "mode"),
        shapes,
        {
            "units": "1",
            "long_name": "mode shape at the reference point, largest coordinate +1: m (x, y, z) or rad (rotations) per "
            "unit of it",
        },
    )
    data["post_yield_mode_frequency"] = (
        ("mount", "mode"),
        yielded,
        {"units": "Hz", "long_name": "rigid-body mode with the hysteretic axes at alpha k, fully yielded (wire rope)"},
    )
    coords = {
        "mount": ("mount", list(section.mounts), {"units": "1", "long_name": "camera mount (isolator)"}),
        "mode": ("mode", np.arange(len(DOFS)), {"units": "1", "long_name": "rigid-body mode, ascending frequency"}),
        "dof": ("dof", list(DOFS), {"units": "1", "long_name": "payload DOF (x, y, z; rotations about them)"}),
        "axis": ("axis", axes, {"units": "1", "long_name": "stabilised gimbal axis"}),
    }
    attrs = {"damping_N_s_m": section.middle_damping, "gimbal_payload_mass_kg": gimbal_payload(section).mass}
    modes_and_loops = xr.Dataset(data, coords=coords, attrs=attrs)
    # left join: the config's mounts in its order (the transmissibility has no wire rope: NaN there)
    merged = xr.merge([modes_and_loops, transmissibility.dataset(section)], join="left", combine_attrs="override")
    return xr.merge([merged, isolator_curves(section)], combine_attrs="override")
