"""The results pages, generated from a run's datasets: tables and headline numbers as Markdown, never typed.

`summary_tables(outputs)` takes the run's datasets by role (xarray, as the stages write them) and returns the
sections of the results page, each a title and a pandas table; `headline(comparison)` the few numbers the README
and the report quote; `to_markdown` renders them with the run's provenance (date, commit, command, config). The
`summary` rule (workflow/rules/summary.smk) writes them to reports/summary.md and the docs include that file.
Tables (units in the column names):

    helicopter     dominant angular frequency per rotor state, mount and axis, against the paper's lines
    platform       the clamped platform's modes against the paper's Table 1
    reference      per stiffness: optimal damping spread and scheduling gain of the learnt criterion, static sag,
                   share of the band whose optimum fits the isolator's stroke
    anfis          the ANFIS and its baselines on the checking rows: RMSE of log10 C, regret mean and worst
    study          per case, stiffness and strategy: camera std (y, z), line-of-sight std, blur p95, stroke
                   needed, feasible
"""

from __future__ import annotations

import hashlib
import json

import numpy as np
import pandas as pd
import xarray as xr

PAPER_OMEGA_RAD_S = {"y": 44.04, "z": 50.58}  # Marichal et al. 2014, Fig. 3: the fuselage's dominant lines


def helicopter_table(vibration: xr.Dataset) -> pd.DataFrame:
    """Dominant angular frequency (rad/s) per rotor state, mount and axis y, z, with the paper's."""
    rows = []
    for rotor in vibration.rotor.values:
        for mount in vibration.mount.values:
            row = {"rotor": str(rotor), "mount": str(mount)}
            for axis in ("y", "z"):
                row[f"{axis} dominant (rad/s)"] = float(
                    vibration.dominant_omega.sel(rotor=rotor, mount=mount, axis=axis)
                )
                row[f"{axis} paper (rad/s)"] = PAPER_OMEGA_RAD_S[axis]
            rows.append(row)
    return pd.DataFrame(rows).set_index(["rotor", "mount"])


def platform_table(modes: xr.Dataset) -> pd.DataFrame:
    """The clamped platform's natural frequencies (Exudyn) against the targets (paper, Table 1), Hz."""
    return pd.DataFrame(
        {
            "mode": np.arange(1, modes.sizes["mode"] + 1),
            "Exudyn (Hz)": modes.natural_frequency.values,
            "paper, Table 1 (Hz)": modes.target_frequency.values,
        }
    ).set_index("mode")


def reference_table(table: xr.Dataset, stroke: xr.Dataset | None = None) -> pd.DataFrame:
    """Per stiffness: the learnt criterion's optimal-damping spread and scheduling gain; with the stroke budget,
    the static sag and the share of the (f_y, f_z) band whose optimum fits the stroke."""
    chosen = table.sel(criterion=table.attrs["criterion"], window=table.attrs["window"])
    frame = pd.DataFrame(
        {
            "K (N/m)": chosen.stiffness.values,
            "damping_opt spread (max/min)": chosen.damping_opt_spread.values,
            "scheduling gain": chosen.scheduling_gain.values,
        }
    )
    if stroke is not None:
        frame["static sag (mm)"] = 1e3 * stroke.static_sag.sel(stiffness=chosen.stiffness).values
        frame["feasible share of the band"] = stroke.stroke_feasible.mean(["freq_y", "freq_z"]).values
    return frame.set_index("K (N/m)")


def anfis_table(training: xr.Dataset) -> pd.DataFrame:
    """The ANFIS and its baselines on the checking rows."""
    return pd.DataFrame(
        {
            "model": [str(m) for m in training.model.values],
            "RMSE of log10 C": training.check_rmse_target.values,
            "regret mean": training.check_regret_mean.values,
            "regret worst": training.check_regret_max.values,
        }
    ).set_index("model")


STUDY_COLUMNS = {  # column: (variable, selection or "max" over the axes, scale to the column's unit)
    "camera std y (mm)": ("std_total", {"axis": "y"}, 1e3),
    "camera std z (mm)": ("std_total", {"axis": "z"}, 1e3),
    "LOS std (mrad)": ("los_std", {}, 1e3),
    "blur p95 (px)": ("blur_p95", {}, 1.0),
    "stroke needed (mm)": ("stroke_needed", "max", 1e3),
    "stroke feasible": ("stroke_feasible", {}, 1.0),
}


def study_table(comparison: xr.Dataset) -> pd.DataFrame:
    """Per case, stiffness and strategy: the camera, its line of sight and image, the stroke (if in the data)."""
    columns = {}
    for name, (var, where, scale) in STUDY_COLUMNS.items():
        if var not in comparison:
            continue
        values = comparison[var]
        values = values.max("axis") if where == "max" else values.sel(where)
        columns[name] = (scale * values).transpose("case", "stiffness", "strategy").to_series()
    frame = pd.DataFrame(columns)
    frame.index = frame.index.set_names(["case", "K (N/m)", "strategy"])
    return frame


def headline(comparison: xr.Dataset) -> dict[str, float]:
    """The numbers the README quotes: per case at the lowest stiffness, the ANFIS against the passive damper
    (camera std y, line of sight, blur; relative change, 1) and the stroke that stiffness needs (m)."""
    k = float(comparison.stiffness.min())
    out = {"stiffness_n_m": k}
    for case in comparison.case.values:
        part = comparison.sel(case=case, stiffness=k)
        for var, where, key in (
            ("std_total", {"axis": "y"}, "std_y"),
            ("los_std", {}, "los"),
            ("blur_p95", {}, "blur"),
        ):
            if var in part and {"anfis", "passive"} <= set(part.strategy.values):
                a, p = (float(part[var].sel(strategy=s, **where)) for s in ("anfis", "passive"))
                out[f"{case}_anfis_vs_passive_{key}"] = a / p - 1
        if "stroke_needed" in part:
            out[f"{case}_stroke_needed_m"] = float(part.stroke_needed.sel(strategy="passive").max())
    return out


def summary_tables(outputs: dict[str, xr.Dataset]) -> list[tuple[str, pd.DataFrame]]:
    """(title, table) of every section whose datasets are in `outputs` (roles: vibration, modes, table, stroke,
    training, comparison)."""
    sections = []
    if "vibration" in outputs:
        sections.append(("Helicopter: the fuselage's dominant lines", helicopter_table(outputs["vibration"])))
    if "modes" in outputs:
        sections.append(("Platform: the clamped modes", platform_table(outputs["modes"])))
    if "table" in outputs:
        sections.append(("Reference table", reference_table(outputs["table"], outputs.get("stroke"))))
    if "training" in outputs:
        sections.append(("ANFIS and baselines, checking rows", anfis_table(outputs["training"])))
    if "comparison" in outputs:
        sections.append(("Closed-loop study", study_table(outputs["comparison"])))
    return sections


def to_markdown(sections: list[tuple[str, pd.DataFrame]], numbers: dict[str, float], provenance: dict) -> str:
    """The results page: provenance, headline numbers, then every table (4 significant digits)."""
    lines = ["# Results of the run", ""]
    lines += [f"- {key}: `{value}`" for key, value in provenance.items()]
    lines += ["", "## Headline numbers", "", "```json", json.dumps(numbers, indent=2, sort_keys=True), "```", ""]
    for title, frame in sections:
        lines += [f"## {title}", "", frame.to_markdown(floatfmt=".4g"), ""]
    return "\n".join(lines)


def to_html(sections: list[tuple[str, pd.DataFrame]], numbers: dict[str, float], provenance: dict) -> str:
    """The same page as HTML tables (the Snakemake report's landing item)."""
    parts = ["<h1>Results of the run</h1>", "<ul>"]
    parts += [f"<li>{key}: <code>{value}</code></li>" for key, value in provenance.items()]
    parts += ["</ul>", "<h2>Headline numbers</h2>", f"<pre>{json.dumps(numbers, indent=2, sort_keys=True)}</pre>"]
    for title, frame in sections:
        parts += [f"<h2>{title}</h2>", frame.to_html(float_format=lambda v: f"{v:.4g}")]
    return "\n".join(parts)


def provenance_of(ds: xr.Dataset) -> dict:
    """The run's date, commit, command and config digest, from a dataset written by `uavdamp.io`."""

    keys = {
        "history": "run",
        "git_commit": "commit",
        "git_tree_dirty": "uncommitted changes",
        "command_line": "command",
    }
    out = {label: str(ds.attrs[key]) for key, label in keys.items() if key in ds.attrs}
    config = "".join(str(ds.attrs[k]) for k in sorted(ds.attrs) if k.startswith("config_"))
    out["config sha256 (of the study's config)"] = hashlib.sha256(config.encode()).hexdigest()[:16]
    return out
