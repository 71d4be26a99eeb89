"""The results page, generated from a run's datasets: findings, descriptions and tables, never typed.

`summary_page(outputs, figures)` takes the run's datasets by role (xarray, as the stages write them; roles:
vibration, modes, table, stroke, training, comparison, cases, benchmark) and returns a `Page`: the findings as
sentences generated from the comparison, the cases and strategies described (from the datasets' description
coordinates), the key figures and the tables. `uavdamp.results.render` writes it as Markdown and as a standalone
HTML page. Tables are built from the datasets' dimensions (one labelled column per row dimension: case, K,
strategy, and any dimension a stage adds later), never from a list of names:

    helicopter     dominant angular frequency of the imbalanced rotor runs against the paper's lines; the
                   balanced rotor's apart, as a reference (the paper's lines are of the imbalanced rotor)
    platform       the clamped platform's modes against the paper's Table 1
    reference      per stiffness: optimal damping spread and scheduling gain, static sag, feasible share, share of cells
                   whose optimum sits on an edge of the C grid inside the damper's bounds
    anfis          the ANFIS and its baselines on the checking rows
    study          per case, stiffness and strategy: camera std, line of sight, blur, stroke needed and whether
                   it fits
    payload        per input and payload: line of sight (µrad) rigid and on each isolator at its best C
    benchmark_payload  the controller benchmark on the payload: mean / worst J per mount and law (when it has run)
    benchmark      mean / worst J per controller and criterion over the evaluation set (when it has run)
"""

from __future__ import annotations

import hashlib
import itertools

import numpy as np
import pandas as pd
import xarray as xr

from uavdamp.results.page import MISSING, Figure, Page, Table, fmt, signed
from uavdamp.results.payload_page import (
    benchmark_payload_finding,
    benchmark_payload_table,
    payload_findings,
    payload_table,
)
from uavdamp.study import strategies

PAPER_OMEGA_RAD_S = {"y": 44.04, "z": 50.58}  # Marichal et al. 2014, Fig. 3: the fuselage's dominant lines
UNIT_TEXT = {"N m-1": "N/m", "N s m-1": "N s/m", "rad s-1": "rad/s", "m s-1": "m/s", "s-1": "1/s"}
DIM_LABELS = {"stiffness": "K"}  # a dimension's column label, when not its name


def unit_text(units: str) -> str:
    """CF units as a reader writes them ('N m-1' -> 'N/m')."""
    return UNIT_TEXT.get(units, units)


def dim_label(coord: xr.DataArray) -> str:
    """A dimension's column label: its short name, with its units unless dimensionless ('K (N/m)', 'case')."""
    name = DIM_LABELS.get(str(coord.name), str(coord.name).replace("_", " "))
    units = coord.attrs.get("units", "1")
    return name if units in ("1", "") else f"{name} ({unit_text(units)})"


def coord_text(value) -> str:
    """A coordinate value as a label: numbers without a trailing '.0' ('10', not '10.0')."""
    return fmt(value, 6) if isinstance(value, (float, np.floating)) else str(value)


def dataset_table(columns: dict[str, xr.DataArray], rows: list[str] | None = None, formats: dict | None = None):
    """A flat table from DataArrays sharing their row dimensions: one labelled column per row dimension (in the
    arrays' order unless `rows` is given), then one column per entry of `columns`, each cell formatted by
    `formats[name]` (a function of the value; default `fmt`)."""
    formats = formats or {}
    first = next(iter(columns.values()))
    rows = list(first.dims) if rows is None else rows
    coords = [first[d] for d in rows]
    records = []
    for combo in itertools.product(*(c.values for c in coords)):
        where = dict(zip(rows, combo, strict=True))
        record = {dim_label(c): coord_text(v) for c, v in zip(coords, combo, strict=True)}
        for name, array in columns.items():
            value = array.sel(where).values.item()
            record[name] = formats.get(name, fmt)(value)
        records.append(record)
    return pd.DataFrame(records)


def feasible_text(value) -> str:
    """A 0/1 feasibility flag as words (NaN: no isolator, nothing to fit)."""
    return MISSING if not np.isfinite(value) else ("yes" if value >= 0.5 else "no")


def percent_text(value) -> str:
    return MISSING if not np.isfinite(value) else f"{fmt(100 * value, 3)} %"


def helicopter_tables(vibration: xr.Dataset) -> list[Table]:
    """The imbalanced rotor runs' dominant lines against the paper's (Fig. 3), and the balanced rotor's apart."""
    omega = vibration.dominant_omega.sel(axis=list(PAPER_OMEGA_RAD_S))
    imbalance = vibration.get("mass_imbalance_factor", xr.full_like(vibration.rotor, np.nan, dtype=float))
    balanced = [str(r) for r, f in zip(vibration.rotor.values, imbalance.values, strict=True) if f == 1.0]
    compared = [str(r) for r in vibration.rotor.values if str(r) not in balanced]
    paper = ", ".join(f"{a} {v} rad/s" for a, v in PAPER_OMEGA_RAD_S.items())
    tables = []
    if compared:
        part = omega.sel(rotor=compared)
        columns = {}
        for axis, ref in PAPER_OMEGA_RAD_S.items():
            columns[f"{axis} dominant (rad/s)"] = part.sel(axis=axis)
            columns[f"{axis} minus paper (rad/s)"] = part.sel(axis=axis) - ref
        frame = dataset_table(columns, formats={k: (lambda v: signed(v, 3)) for k in columns if "minus" in k})
        if "flight" in vibration:
            frame.insert(1, "flight", [str(vibration.flight.sel(rotor=r).values) for r in frame["rotor"]])
        note = f"The paper's lines (Fig. 3, imbalanced rotor): {paper}."
        tables.append(Table("Helicopter: the imbalanced rotor's dominant lines against the paper's", frame, note, 3))
    if balanced:
        part = omega.sel(rotor=balanced)
        frame = dataset_table({f"{a} dominant (rad/s)": part.sel(axis=a) for a in PAPER_OMEGA_RAD_S})
        note = (
            "A reference run without the mass imbalance; the paper's lines are of the imbalanced rotor, so it is "
            "not compared with them."
        )
        tables.append(Table("Helicopter: the balanced rotor (reference)", frame, note, 2))
    return tables


def platform_table(modes: xr.Dataset) -> Table:
    """The clamped platform's natural frequencies (Exudyn) against the targets (paper, Table 1), Hz."""
    frame = dataset_table(
        {
            "Exudyn (Hz)": modes.natural_frequency,
            "paper, Table 1 (Hz)": modes.target_frequency,
        }
    )
    return Table("Platform: the clamped modes", frame)


def reference_table(table: xr.Dataset, stroke: xr.Dataset | None = None) -> Table:
    """Per stiffness: the learnt criterion's optimal-damping spread and scheduling gain; with the stroke budget,
    the static sag and the share of the (f_y, f_z) band whose optimum fits the stroke."""
    chosen = table.sel(criterion=table.attrs["criterion"], window=table.attrs["window"])
    columns = {
        "optimal C spread (max/min)": chosen.damping_opt_spread,
        "scheduling gain (1: none)": chosen.scheduling_gain,
    }
    formats = {}
    if "optimum_at_grid_edge" in chosen:  # a bound, not an optimum: the C grid's edge inside the damper's range
        columns["optimum at a C grid edge"] = chosen.optimum_at_grid_edge.isin([1, 2]).mean(["freq_y", "freq_z"])
        formats["optimum at a C grid edge"] = percent_text
    if stroke is not None:
        columns["static sag (mm)"] = 1e3 * stroke.static_sag.sel(stiffness=chosen.stiffness)
        columns["band whose optimum fits the stroke"] = stroke.stroke_feasible.mean(["freq_y", "freq_z"])
        formats["band whose optimum fits the stroke"] = percent_text
    note = f"Criterion learnt: {table.attrs['criterion']}, window {table.attrs['window']}."
    return Table("Reference table", dataset_table(columns, formats=formats), note)


def anfis_table(training: xr.Dataset) -> Table:
    """The ANFIS and its baselines on the checking rows (lower is better in every column)."""
    columns = {
        "RMSE of log10 C": training.check_rmse_target,
        "regret mean (1: optimal)": training.check_regret_mean,
        "regret worst": training.check_regret_max,
    }
    frame = dataset_table(columns)
    if "model_description" in training.coords:
        frame.insert(1, "what it is", [str(v) for v in training.model_description.values])
    chosen = training.attrs.get("selected_candidate")
    note = "Lower is better in every column." + (f" ANFIS structure chosen: {chosen}." if chosen else "")
    return Table("ANFIS and baselines, checking rows", frame, note, 2)


# column: (variable, selection or "max" over the axes, scale to the column's unit, format)
STUDY_COLUMNS = {
    "camera std y (mm)": ("std_total", {"axis": "y"}, 1e3, fmt),
    "camera std z (mm)": ("std_total", {"axis": "z"}, 1e3, fmt),
    "LOS std (mrad)": ("los_std", {}, 1e3, fmt),
    "blur p95 (px)": ("blur_p95", {}, 1.0, fmt),
    "stroke needed (mm)": ("stroke_needed", "max", 1e3, fmt),
    "stroke fits": ("stroke_feasible", {}, 1.0, feasible_text),
}


def study_rows(comparison: xr.Dataset) -> list[str]:
    """The row dimensions of the study's scalars: every dimension but the axes (case, stiffness, strategy, ...)."""
    return [d for d in comparison.blur_p95.dims if d != "axis"] if "blur_p95" in comparison else ["case"]


def study_table(comparison: xr.Dataset) -> Table:
    """Per case, stiffness and strategy (and any other row dimension): the camera, line of sight, image, stroke."""
    columns, formats = {}, {}
    for name, (var, where, scale, form) in STUDY_COLUMNS.items():
        if var in comparison:
            values = comparison[var]
            columns[name] = scale * (values.max("axis") if where == "max" else values.sel(where))
            formats[name] = form
    rows = study_rows(comparison)
    frame = dataset_table({k: v.transpose(*rows) for k, v in columns.items()}, rows, formats)
    note = "Lower is better in every number column; '-': no isolator (rigid mount)."
    return Table("Closed-loop study", frame, note, len(rows))


def benchmark_table(criteria: xr.Dataset) -> Table:
    """Mean / worst J per controller, stiffness, damper and criterion over the evaluation set; '-': not run."""
    mean, worst = criteria.J_mean, criteria.J_worst
    rows = [d for d in mean.dims if d != "criterion"]
    records = []
    for combo in itertools.product(*(mean[d].values for d in rows)):
        where = dict(zip(rows, combo, strict=True))
        record = {dim_label(mean[d]): coord_text(v) for d, v in where.items()}
        for c in mean.criterion.values:
            m, w = (float(x.sel({**where, "criterion": c})) for x in (mean, worst))
            record[str(c)] = MISSING if not np.isfinite(m) else f"{fmt(m, 3)} / {fmt(w, 3)}"
        records.append(record)
    n = int((criteria.set == "evaluation").sum()) if "set" in criteria.coords else criteria.sizes["scenario"]
    note = f"Mean / worst J over {n} evaluation scenarios (J = 1: the rigid mount; lower is better); '-': not run."
    return Table("Controller benchmark", pd.DataFrame(records), note, len(rows))


def descriptions(comparison: xr.Dataset, cases: xr.Dataset | None = None) -> list[tuple[str, dict[str, str]]]:
    """(title, {name: one sentence}) for every row dimension with a `<dim>_description` coordinate (case and
    strategy as the study writes them; else a case's from the excitation's `description`, a strategy's from the
    registry, `uavdamp.study.strategies.describe`)."""
    out = []
    for dim in study_rows(comparison):
        text = None
        if f"{dim}_description" in comparison.coords:
            text = comparison[f"{dim}_description"]
        elif dim == "case" and cases is not None and "description" in cases:
            text = cases.description.sel(case=comparison.case)
        elif dim == "strategy":  # a comparison written before it described its strategies: the registry's
            text = xr.DataArray([strategies.describe(str(s)) for s in comparison.strategy.values])
        if text is not None:
            titles = {"case": "Cases (the mount's input)", "strategy": "Damping strategies"}
            entries = {str(k): str(v) for k, v in zip(comparison[dim].values, text.values, strict=True)}
            out.append((titles.get(dim, dim.replace("_", " ").capitalize()), entries))
    return out


HEADLINE = (  # (variable, selection, scale, units, label): lower is better for each
    ("blur_p95", {}, 1.0, "px", "blur p95"),
    ("los_std", {}, 1e3, "mrad", "line-of-sight std"),
    ("std_total", {"axis": "y"}, 1e3, "mm", "camera std y"),
)


def _ranked(values: pd.Series, units: str) -> str:
    """'a lowest at 13.12 px, 0.012 px (0.09 %) below b (13.14 px)', or 'a and b tie at 13.12 px' (equal to the
    shown `DIGITS`)."""
    ordered = values.dropna().sort_values()
    first, best = ordered.index[0], ordered.iloc[0]
    if ordered.size == 1:
        return f"{first} at {fmt(best)} {units}"
    second, runner = ordered.index[1], ordered.iloc[1]
    if fmt(best) == fmt(runner):
        tied = [s for s, v in ordered.items() if fmt(v) == fmt(best)]
        return f"{' and '.join(tied)} tie at {fmt(best)} {units}"
    gap = runner - best
    return (
        f"{first} lowest at {fmt(best)} {units}, {fmt(gap, 2)} {units} ({fmt(100 * gap / runner, 2)} %) below "
        f"{second} ({fmt(runner)} {units})"
    )


def _span(values: xr.DataArray, units: str) -> str:
    lo, hi = fmt(float(values.min())), fmt(float(values.max()))
    return f"{lo} {units}" if lo == hi else f"{lo}-{hi} {units}"


def _where_text(comparison: xr.Dataset, where: dict) -> str:
    """'case1, K = 10 N/m': a row's coordinates as words."""
    return ", ".join(
        f"{DIM_LABELS[d]} = {coord_text(v)} {unit_text(comparison[d].attrs.get('units', ''))}".strip()
        if d in DIM_LABELS
        else coord_text(v)
        for d, v in where.items()
    )


def findings(comparison: xr.Dataset) -> list[str]:
    """The headline as sentences, one item per combination of the study's row dimensions but strategy (case, K,
    ...): the best strategy on blur and line of sight and by how much over the runner-up, how far isolation gets
    below the rigid mount, the ANFIS against the passive damper, and whether the stroke fits."""
    rows = [d for d in study_rows(comparison) if d != "strategy"]
    out = []
    for combo in itertools.product(*(comparison[d].values for d in rows)):
        where = dict(zip(rows, combo, strict=True))
        part = comparison.sel(where)
        names = [str(s) for s in part.strategy.values]
        isolated = [s for s in names if s != "rigid"]
        sentences = []
        for var, sel, scale, units, text in HEADLINE[:2]:
            if var not in part or not isolated:
                continue
            values = pd.Series({s: scale * float(part[var].sel({**sel, "strategy": s})) for s in isolated})
            sentence = f"{text.capitalize()}: {_ranked(values, units)}"
            if "rigid" in names:
                rigid = scale * float(part[var].sel({**sel, "strategy": "rigid"}))
                change = signed(100 * (values.min() / rigid - 1), 2)
                sentence += f"; rigid mount {fmt(rigid)} {units} (best isolated {change} %)"
            sentences.append(sentence + ".")
        if {"anfis", "passive"} <= set(names):
            diffs = []
            for var, sel, scale, units, text in HEADLINE:
                if var in part:
                    a, p = (scale * float(part[var].sel({**sel, "strategy": s})) for s in ("anfis", "passive"))
                    diffs.append(f"{text} {signed(a - p)} {units} ({signed(100 * (a / p - 1), 2)} %)")
            sentences.append("ANFIS minus passive (negative: ANFIS better): " + ", ".join(diffs) + ".")
        if "stroke_feasible" in part and isolated:
            fits = [s for s in isolated if part.stroke_feasible.sel(strategy=s) >= 0.5]
            span = _span(1e3 * part.stroke_needed.sel(strategy=isolated).max("axis"), "mm")
            who = "every isolated strategy" if len(fits) == len(isolated) else ", ".join(fits) or "no isolated strategy"
            sentences.append(f"Stroke: {who} fits ({span} needed).")
        out.append(f"**{_where_text(comparison, where)}.** " + " ".join(sentences))
    return out


FIGURES = {  # role: (title, caption)
    "blur": ("Image blur per strategy", "Blur of every frame (px) per strategy, case and K; dashed: sharp threshold."),
    "strategies": ("Every strategy on one case", "Camera y and z, damping C(t) and the metrics, per K."),
    "fuselage": ("The fuselage's vibration", "Motion at the mount and its spectra, imbalanced and balanced rotor."),
    "reference": ("The reference table", "Optimal damping C per input frequency pair and stiffness K."),
    "benchmark": ("Controller benchmark", "Mean and worst J per controller and criterion (J = 1: rigid mount)."),
    "benchmark_payload": ("Controller benchmark on the payload", "J per damping law and evaluation scenario, gimbal."),
    "payload": ("Payloads and mounts", "Line of sight (µrad) per payload and mount against the isolator's damping."),
}


def summary_page(outputs: dict[str, xr.Dataset], figures: dict[str, str] | None = None) -> Page:
    """The page from the datasets by role (see the module docstring) and the figures by role (`FIGURES`:
    path relative to the page)."""
    comparison = outputs["comparison"]
    page = Page(provenance_of(comparison), findings(comparison), descriptions(comparison, outputs.get("cases")))
    for role, path in (figures or {}).items():
        title, caption = FIGURES.get(role, (role, ""))
        page.figures.append(Figure(str(path), title, caption))
    if "vibration" in outputs:
        page.tables += helicopter_tables(outputs["vibration"])
    if "modes" in outputs:
        page.tables.append(platform_table(outputs["modes"]))
    if "table" in outputs:
        page.tables.append(reference_table(outputs["table"], outputs.get("stroke")))
    if "training" in outputs:
        page.tables.append(anfis_table(outputs["training"]))
    page.tables.append(study_table(comparison))
    if "payload" in outputs:
        page.findings.extend(payload_findings(outputs["payload"]))
        page.tables.append(payload_table(outputs["payload"]))
    if "benchmark" in outputs:
        page.tables.append(benchmark_table(outputs["benchmark"]))
    if "benchmark_payload" in outputs:
        page.findings.append(benchmark_payload_finding(outputs["benchmark_payload"]))
        page.tables.append(benchmark_payload_table(outputs["benchmark_payload"]))
    return page


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
