"""The ANFIS as a MATLAB Fuzzy Logic Toolbox ``.fis`` text file, and back.

``to_fis`` writes a fitted ``DampingModel`` (or bare ``ANFIS``) as the classic text format that
``readfis`` / ``evalfis`` accept: Type='sugeno', AndMethod='prod', OrMethod='probor',
ImpMethod='prod', AggMethod='sum', DefuzzMethod='wtaver'; per input one ``gaussmf`` [sigma c] per
membership function (MF), rules sharing MFs (grid init) or each with its own (clustering inits)
alike; the output with one ``linear`` MF [p_1 .. p_d p_0] per rule; one rule per line, weight 1,
connection 1 (AND). The ANFIS already stores its centres, sigmas and consequents in the units of
its (transformed) inputs and output, with fit's internal output scaling folded in, so the file's
numbers are the model's own, written with 17 significant digits (exact float64 round trip).
``from_fis`` reads such a file back into a ``DampingModel``; predictions are bit-identical.

Transforms and units, by naming convention (a .fis cannot hold log10; variable names survive
MATLAB's readfis/writefis, comments do not): a transformed variable is ``log10_<name>_<unit>``,
its values log10 of the quantity in that unit, e.g. ``log10_K_N_m`` = log10(K / (1 N/m)) and the
output ``log10_C_N_s_m`` = log10(C / (1 N s/m)); others are ``<name>_<unit>`` (``f_y_Hz``), or
``<name>`` when dimensionless. ``from_fis`` takes the DampingModel's ``log_stiffness`` from the
third input's ``log10_`` prefix and ``log_damping`` from the output's. Lines starting with '%'
(comments: readfis's line reader skips them, as does fuzzylite's FisImporter) say this in words and
hold, as ``% uavdamp-names: <JSON>``, the ANFIS's exact names and units; without that line the
imported ANFIS is named after the file's variables, dimensionless. Hyper-parameters and training
histories are not in the file.

Inputs outside Range. The ANFIS clamps every input to its training range (the file's Range)
before evaluating: it does not extrapolate. MATLAB does not clamp: evalfis evaluates the MFs and
linear consequents at the raw value and, by default, warns ("Input 1 expects a value in range
[0 1], but has a value of ..."; evalfisOptions OutOfRangeInputValueMessage "warning" | "error" |
"none": "When an input value is out of range, corresponding rules in the fuzzy system can have
unexpected firing strengths", MathWorks evalfisOptions reference page; MathWorks' answers advise to
"limit input values to individual input range values before you feed it to the FIS"). A Sugeno
FIS cannot encode the clamp (both the MFs and the linear consequents see the raw input), so the
file's user must clamp, e.g. ``evalfis(fis, min(max(x, lo), hi))`` with lo, hi the Ranges, or a
Saturation block before Simulink's Fuzzy Logic Controller; inside the ranges the two agree.
Where every firing strength underflows to 0 (a point tens of sigmas from every rule), evalfis
returns the midpoint of the output Range ("No rules fired for Output 1. Defuzzified output value
set to its mean range value") where the ANFIS, normalising in log space, returns the nearest
rule's output. The output Range written is a bound of the model over the input box (each rule's
linear consequent at its extremes over the box; a weighted average cannot leave it).

Other readers: the C++ fuzzylite (6.0) imports the file, and its engine (or pyfuzzylite's, which has
no FIS importer of its own) agrees with the model to ~1e-15 once its absolute tolerance is 0: by
default (1e-6; 1e-3 in pyfuzzylite 8) it drops rules firing below it, which evalfis does not.

A constant input (zero training range) is refused: MATLAB requires Range(1) < Range(2), and the
ANFIS ignores such an input anyway. ``from_fis`` refuses, naming the section and line, what the
ANFIS cannot represent: a type other than sugeno, AND other than prod, a defuzzifier other than
wtaver, MFs other than gaussmf (inputs) or linear/constant (output), OR rules, rule weights other
than 1, "don't care" (0) or NOT (negative) antecedents, more than one output; and what would change the file's
meaning unnoticed: a key (or the names comment) given twice, a variable name outside the transforms above (a
``log10_`` name without its unit suffix; with the names comment, any name other than the one ``to_fis`` writes for
it, e.g. ``K_N_m`` for ``log10_K``), and a rule whose output over the input Ranges is not finite (10**it for a
``log10_`` output). ``read_fis(path)`` prefixes every such error with the file.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np

from uavdamp.anfis._math import _incidence
from uavdamp.anfis.damping import DampingModel
from uavdamp.anfis.estimator import ANFIS

__all__ = ["to_fis", "from_fis", "read_fis"]

NAMES_TAG = "% uavdamp-names:"
LOG = "log10_"
# units of the quantities DampingModel may learn as log10 (uavdamp.anfis.DampingModel: K in N/m, C in N s/m)
LOG_UNITS = {"input": "N/m", "output": "N s/m"}
# [System] settings the ANFIS has; readfis defaults the first three to mamdani, min and centroid when
# absent (so they are required) and forces ImpMethod prod and AggMethod sum for sugeno (checked if present)
SYSTEM = {"Type": "sugeno", "AndMethod": "prod", "DefuzzMethod": "wtaver", "ImpMethod": "prod", "AggMethod": "sum"}
REQUIRED = ("Type", "AndMethod", "DefuzzMethod")


def _num(value: float) -> str:
    """Shortest text that reads back as the same float64."""
    return repr(float(value))


def _vector(values) -> str:
    return "[" + " ".join(_num(v) for v in values) + "]"


def _slug(text: str) -> str:
    """An identifier from ``text``: runs of other characters become '_'."""
    return re.sub(r"[^A-Za-z0-9]+", "_", text).strip("_")


def _fis_name(name: str, unit: str, log: bool, log_unit: str, what: str) -> tuple[str, str]:
    """(file variable name, its definition in words) for an ANFIS variable."""
    base = _slug(name[len(LOG) :] if log and name.startswith(LOG) else name)
    if not base or not base[0].isalpha():
        base = "x" + base
    if not log and base.startswith(LOG):
        raise ValueError(
            f"{what} is named {name!r}, but the file reserves the prefix {LOG!r} for what a DampingModel "
            "log-transforms; export the DampingModel (not its ANFIS) or rename the variable"
        )
    if log:
        return f"{LOG}{base}_{_slug(log_unit)}", f"log10({base} / (1 {log_unit}))"
    if unit in ("", "1"):
        return base, f"{base} (dimensionless)"
    return f"{base}_{_slug(unit)}", f"{base} in {unit}"


def _parts(model) -> tuple[ANFIS, bool, bool]:
    if isinstance(model, DampingModel):
        est, log_k, log_c = model.estimator, model.log_stiffness, model.log_damping
    else:
        est, log_k, log_c = model, False, False
    if not isinstance(est, ANFIS):
        raise TypeError(f"to_fis needs a DampingModel of an ANFIS or an ANFIS, got {type(est).__name__}")
    est._check_fitted()
    return est, log_k, log_c


def _output_range(est: ANFIS) -> tuple[float, float]:
    """Bounds of every rule's linear consequent over the input box (so of the model's output there)."""
    lo, hi = est.input_range_[:, 0], est.input_range_[:, 1]
    coef, const = est.consequents_[:, :-1], est.consequents_[:, -1]
    low = const + np.minimum(coef * lo, coef * hi).sum(axis=1)
    high = const + np.maximum(coef * lo, coef * hi).sum(axis=1)
    a, b = float(low.min()), float(high.max())
    if a == b:  # every rule constant and equal: any Range around it
        pad = 0.5 * max(abs(a), 1.0)
        a, b = a - pad, b + pad
    return a, b


def to_fis(model, name: str = "uavdamp_anfis") -> str:
    """The fitted ``DampingModel`` (or ``ANFIS``) as the text of a MATLAB Sugeno ``.fis`` file (see module doc)."""
    est, log_k, log_c = _parts(model)
    d, n_rules = est.n_features_in_, est.n_rules_
    if "'" in name or "\n" in name:
        raise ValueError(f"the FIS name must not contain quotes or newlines, got {name!r}")
    lo, hi = est.input_range_[:, 0], est.input_range_[:, 1]
    variables = [
        _fis_name(est.input_names_[i], est.input_units_[i], log_k and i == 2, LOG_UNITS["input"], f"input {i + 1}")
        for i in range(d)
    ]
    variables.append(_fis_name(est.output_name, est.output_units, log_c, LOG_UNITS["output"], "the output"))
    if len({v for v, _ in variables}) != len(variables):
        raise ValueError(f"the variables' file names are not distinct: {[v for v, _ in variables]}")
    constant = np.flatnonzero(~(lo < hi))
    if constant.size:
        i = constant[0]
        raise ValueError(
            f"input {variables[i][0]} is constant ({lo[i]:g}) in the training data: a .fis Range needs min < max "
            "(and the model ignores that input); refit without it"
        )
    kind = "a DampingModel" if isinstance(model, DampingModel) else "an ANFIS"
    names = {"inputs": [[n, u] for n, u in zip(est.input_names_, est.input_units_, strict=True)]}
    names["output"] = [est.output_name, est.output_units]
    lines = [
        f"% {kind} of uavdamp (first-order Takagi-Sugeno, Gaussian MFs), written by uavdamp.anfis.fis.to_fis.",
        "% The FIS works on the transformed values named below (log10_ prefix: decimal log; suffix: unit).",
        *[f"%   {'Input' + str(i + 1) if i < d else 'Output1'} {v} = {text}" for i, (v, text) in enumerate(variables)],
        "% Clamp every input to its Range before evalfis: the model does not extrapolate, evalfis does not clamp.",
        NAMES_TAG + " " + json.dumps(names),
        "",
        "[System]",
        f"Name='{name}'",
        "Type='sugeno'",
        "Version=2.0",
        f"NumInputs={d}",
        "NumOutputs=1",
        f"NumRules={n_rules}",
        "AndMethod='prod'",
        "OrMethod='probor'",
        "ImpMethod='prod'",
        "AggMethod='sum'",
        "DefuzzMethod='wtaver'",
    ]
    local = np.empty(est.centres_.size, dtype=int)  # per-input MF number (1-based) of every MF
    for i in range(d):
        mfs = np.flatnonzero(est.mf_input_ == i)
        local[mfs] = np.arange(1, mfs.size + 1)
        lines += ["", f"[Input{i + 1}]", f"Name='{variables[i][0]}'", f"Range={_vector(est.input_range_[i])}"]
        lines.append(f"NumMFs={mfs.size}")
        lines += [f"MF{k}='mf{k}':'gaussmf',{_vector([est.sigmas_[m], est.centres_[m]])}" for k, m in enumerate(mfs, 1)]
    lines += ["", "[Output1]", f"Name='{variables[-1][0]}'", f"Range={_vector(_output_range(est))}"]
    lines.append(f"NumMFs={n_rules}")
    lines += [f"MF{r}='rule{r}':'linear',{_vector(p)}" for r, p in enumerate(est.consequents_, 1)]
    lines += ["", "[Rules]"]
    lines += [" ".join(str(k) for k in local[mfs]) + f", {r} (1) : 1" for r, mfs in enumerate(est.rule_mf_, 1)]
    return "\n".join(lines) + "\n"


# ---------------------------------------------------------------------------------------------
# Reading


def _sections(text: str) -> tuple[dict[str, list[tuple[int, str]]], dict | None]:
    """Section name -> its (line number, content) lines; the ``uavdamp-names`` JSON (or None)."""
    sections: dict[str, list[tuple[int, str]]] = {}
    current, names, names_line = None, None, None
    for number, raw in enumerate(text.splitlines(), start=1):
        line = raw.strip()
        if line.startswith(NAMES_TAG):
            if names_line is not None:
                raise ValueError(f"line {number}: a second {NAMES_TAG} line (first at line {names_line})")
            names_line = number
            try:
                names = json.loads(line[len(NAMES_TAG) :])
            except json.JSONDecodeError as err:
                raise ValueError(f"line {number}: {NAMES_TAG} is not JSON ({err})") from err
        if not line or line.startswith("%"):
            continue
        match = re.fullmatch(r"\[(\w+)\]", line)
        if match:
            current = match.group(1)
            if current in sections:
                raise ValueError(f"line {number}: section [{current}] appears twice")
            sections[current] = []
        elif current is None:
            raise ValueError(f"line {number}: {line!r} before the first [section]")
        else:
            sections[current].append((number, line))
    return sections, names


def _keys(sections, section: str) -> dict[str, tuple[int, str]]:
    """key -> (line number, raw value) of a ``key=value`` section."""
    if section not in sections:
        raise ValueError(f"section [{section}] is missing")
    out = {}
    for number, line in sections[section]:
        key, sep, value = line.partition("=")
        if not sep:
            raise ValueError(f"[{section}] line {number}: expected key=value, got {line!r}")
        if key.strip() in out:
            raise ValueError(
                f"[{section}] line {number}: {key.strip()} appears twice (first at line {out[key.strip()][0]}): "
                "which one the file means is ambiguous"
            )
        out[key.strip()] = (number, value.strip())
    return out


def _get(keys, section: str, key: str, kind: str):
    """The value of ``key`` as ``kind`` ("str", "int", "vector"), refusing it missing or malformed."""
    if key not in keys:
        raise ValueError(f"[{section}]: {key} is missing")
    number, value = keys[key]
    where = f"[{section}] line {number}"
    if kind == "str":
        match = re.fullmatch(r"'([^']*)'", value)
        if not match:
            raise ValueError(f"{where}: {key} must be a quoted string, got {value}")
        return match.group(1)
    if kind == "int":
        if not re.fullmatch(r"\d+", value):
            raise ValueError(f"{where}: {key} must be a non-negative integer, got {value}")
        return int(value)
    return _parse_vector(value, where, key)


def _parse_vector(value: str, where: str, what: str) -> np.ndarray:
    match = re.fullmatch(r"\[([^\]]*)\]", value.strip())
    try:
        if not match:
            raise ValueError
        out = np.array([float(v) for v in match.group(1).replace(",", " ").split()])
    except ValueError:
        raise ValueError(f"{where}: {what} must be a vector of numbers [a b ...], got {value}") from None
    if not np.isfinite(out).all():
        raise ValueError(f"{where}: {what} has a non-finite number: {value}")
    return out


def _variable(sections, section: str, mf_types: tuple[str, ...], n_params: int) -> tuple[str, np.ndarray, list, dict]:
    """(Name, Range, [(type, params)] per MF, key -> line number) of an [InputN] or [OutputN] section, checked."""
    keys = _keys(sections, section)
    name, rng = _get(keys, section, "Name", "str"), _get(keys, section, "Range", "vector")
    if rng.size != 2 or not rng[0] < rng[1]:
        raise ValueError(f"[{section}] line {keys['Range'][0]}: Range must be [min max] with min < max")
    mfs = []
    for k in range(1, _get(keys, section, "NumMFs", "int") + 1):
        if f"MF{k}" not in keys:
            raise ValueError(f"[{section}]: MF{k} is missing")
        number, value = keys[f"MF{k}"]
        where = f"[{section}] line {number}"
        match = re.fullmatch(r"'[^']*'\s*:\s*'([^']*)'\s*,\s*(.*)", value)
        if not match:
            raise ValueError(f"{where}: expected MF{k}='name':'type',[params], got {value}")
        mf_type, params = match.group(1), _parse_vector(match.group(2), where, f"MF{k} parameters")
        if mf_type not in mf_types:
            raise ValueError(f"{where}: MF type {mf_type!r} is not supported here (only {', '.join(mf_types)})")
        size = 1 if mf_type == "constant" else n_params
        if params.size != size:
            raise ValueError(f"{where}: {mf_type} needs {size} parameters, got {params.size}")
        mfs.append((mf_type, params))
    return name, rng, mfs, {key: number for key, (number, _) in keys.items()}


def _rules(sections, n_mfs: list[int], n_out: int) -> np.ndarray:
    """(R, d + 1) 0-based per-input MF numbers and output MF number of every rule, checked."""
    if "Rules" not in sections:
        raise ValueError("section [Rules] is missing")
    rows = []
    for number, line in sections["Rules"]:
        where = f"[Rules] line {number}"
        match = re.fullmatch(r"([-\d\s]+),([-\d\s]+)\(([^)]*)\)\s*:\s*(\d+)", line)
        if not match:
            raise ValueError(f"{where}: expected 'i_1 ... i_d, o (weight) : connection', got {line!r}")
        antecedent = [int(v) for v in match.group(1).split()]
        consequent = [int(v) for v in match.group(2).split()]
        if len(antecedent) != len(n_mfs) or len(consequent) != 1:
            raise ValueError(f"{where}: needs {len(n_mfs)} input MF numbers and 1 output MF number, got {line!r}")
        if float(match.group(3)) != 1.0:
            raise ValueError(f"{where}: rule weight {match.group(3)} is not supported (only 1)")
        if match.group(4) != "1":
            raise ValueError(f"{where}: connection {match.group(4)} (OR) is not supported (only 1, AND)")
        for i, k in enumerate(antecedent):
            if not 1 <= k <= n_mfs[i]:
                raise ValueError(
                    f"{where}: input {i + 1} MF number {k} is not supported (1..{n_mfs[i]}; no 0 "
                    "'don't care', no negative NOT)"
                )
        if not 1 <= consequent[0] <= n_out:
            raise ValueError(f"{where}: output MF number {consequent[0]} is not in 1..{n_out}")
        rows.append([k - 1 for k in antecedent + consequent])
    if not rows:
        raise ValueError("[Rules]: no rules")
    return np.array(rows, dtype=np.int64)


def _check_system(sections) -> tuple[int, int]:
    """(NumInputs, NumRules) of [System], refusing settings the ANFIS does not have."""
    keys = _keys(sections, "System")
    for key, expected in SYSTEM.items():
        if key in keys or key in REQUIRED:
            value = _get(keys, "System", key, "str")
            if value != expected:
                raise ValueError(f"[System] line {keys[key][0]}: {key}='{value}' is not supported (only '{expected}')")
    if _get(keys, "System", "NumOutputs", "int") != 1:
        raise ValueError(f"[System] line {keys['NumOutputs'][0]}: NumOutputs must be 1")
    n_inputs = _get(keys, "System", "NumInputs", "int")
    if n_inputs < 1:
        raise ValueError(f"[System] line {keys['NumInputs'][0]}: NumInputs must be at least 1")
    return n_inputs, _get(keys, "System", "NumRules", "int")


def _names(fis_names: list[str], names: dict | None) -> tuple[list[list[str]], list[str]]:
    """The ANFIS's [name, unit] per input and of the output: from the names comment, else the file's names."""
    if names is None:
        return [[n, "1"] for n in fis_names[:-1]], [fis_names[-1], "1"]
    try:
        inputs, output = [[str(n), str(u)] for n, u in names["inputs"]], [str(v) for v in names["output"]]
        ok = len(inputs) == len(fis_names) - 1 and len(output) == 2
    except (KeyError, TypeError, ValueError):
        ok = False
    if not ok:
        n = len(fis_names) - 1
        raise ValueError(f"{NAMES_TAG} must hold 'inputs' ({n} [name, unit]) and 'output' [name, unit]")
    return inputs, output


def _check_names(fis_names: list[str], lines: list[int], names: dict | None, inputs, output) -> None:
    """Refuse a variable name outside the documented transforms: a ``log10_`` name without its unit suffix, or,
    with the names comment, a name other than the one ``to_fis`` writes for that comment's name and unit."""
    d = len(fis_names) - 1
    for i, (fis, number) in enumerate(zip(fis_names, lines, strict=True)):
        section, kind = (f"Input{i + 1}", "input") if i < d else ("Output1", "output")
        where = f"[{section}] line {number}"
        suffix = "_" + _slug(LOG_UNITS[kind])
        if fis.startswith(LOG) and not fis.endswith(suffix):
            raise ValueError(
                f"{where}: Name='{fis}' is log-transformed but lacks the unit suffix {suffix!r} "
                f"(documented: log10_<name>{suffix}, the log10 of the quantity in {LOG_UNITS[kind]})"
            )
        if names is None:
            continue
        name, unit = inputs[i] if i < d else output
        log = name.startswith(LOG)  # the ANFIS learns log10 of this variable (a DampingModel's transform)
        try:
            expected = _fis_name(name, unit, log, LOG_UNITS[kind], f"{kind} {i + 1}")[0]
        except ValueError:
            expected = None
        if fis != expected:
            transform = "its log10" if log else "the quantity itself"
            raise ValueError(
                f"{where}: Name='{fis}' does not match {NAMES_TAG} {name!r} ({unit}), whose documented name is "
                f"'{expected}' ({transform}): an edited name changes what the file computes; refused"
            )


def _check_finite(est: ANFIS, log_c: bool, rules: np.ndarray, out_lines: dict, rule_lines: list[int]) -> None:
    """Refuse a rule whose output (its linear consequent over the input Ranges; 10**it for a log10 output) is not
    finite: the model would predict inf or NaN there."""
    lo, hi = est.input_range_[:, 0], est.input_range_[:, 1]
    coef, const = est.consequents_[:, :-1], est.consequents_[:, -1]
    with np.errstate(over="ignore", invalid="ignore"):
        low = const + np.minimum(coef * lo, coef * hi).sum(axis=1)
        high = const + np.maximum(coef * lo, coef * hi).sum(axis=1)
        bad = ~(np.isfinite(low) & np.isfinite(high))
        if log_c:
            bad |= ~np.isfinite(10.0**high)
    if bad.any():
        r = int(np.flatnonzero(bad)[0])
        k = int(rules[r, -1]) + 1
        scale = "10**" if log_c else ""
        raise ValueError(
            f"[Output1] line {out_lines[f'MF{k}']}: MF{k} of rule {r + 1} ([Rules] line {rule_lines[r]}) gives a "
            f"non-finite prediction over the inputs' Ranges (output {scale}[{low[r]:.6g}, {high[r]:.6g}]): refused"
        )


def from_fis(text: str, source: str | None = None) -> DampingModel:
    """The ``DampingModel`` of a ``.fis`` text written by ``to_fis`` (or any file it can represent; see module doc).

    ValueError naming the section and line (prefixed by `source`, the file, when given) of anything it cannot
    represent, a duplicated key, a name outside the documented transforms or a rule predicting a non-finite value.
    """
    try:
        return _from_fis(text)
    except ValueError as error:
        if source is None:
            raise
        raise ValueError(f"{source}: {error}") from None


def read_fis(path) -> DampingModel:
    """``from_fis`` of the file at `path` (errors name it)."""
    return from_fis(Path(path).read_text(), source=str(path))


def _from_fis(text: str) -> DampingModel:
    sections, names = _sections(text)
    d, n_rules = _check_system(sections)
    fis_names, ranges, mfs, name_lines = [], [], [], []
    for i in range(1, d + 1):
        name, rng, var_mfs, lines = _variable(sections, f"Input{i}", ("gaussmf",), 2)
        fis_names.append(name)
        name_lines.append(lines["Name"])
        ranges.append(rng)
        mfs.append(np.array([p for _, p in var_mfs]).reshape(-1, 2))
        if any(p[0] <= 0 for _, p in var_mfs):
            raise ValueError(f"[Input{i}]: every gaussmf sigma must be > 0")
    out_name, _, out_mfs, out_lines = _variable(sections, "Output1", ("linear", "constant"), d + 1)
    fis_names.append(out_name)
    name_lines.append(out_lines["Name"])
    rules = _rules(sections, [m.shape[0] for m in mfs], len(out_mfs))
    if rules.shape[0] != n_rules:
        raise ValueError(f"[System]: NumRules={n_rules} but [Rules] has {rules.shape[0]} rules")
    for i, n in enumerate(fis_names[:-1]):
        if n.startswith(LOG) and i != 2:
            raise ValueError(f"[Input{i + 1}]: {n} is log-transformed; a DampingModel transforms only input 3 (K)")
    inputs, output = _names(fis_names, names)
    _check_names(fis_names, name_lines, names, inputs, output)
    consequents = np.array([np.r_[np.zeros(d), p] if kind == "constant" else p for kind, p in out_mfs])
    est = ANFIS(
        input_names=[n for n, _ in inputs],
        input_units=[u for _, u in inputs],
        output_name=output[0],
        output_units=output[1],
    )
    sizes = [m.shape[0] for m in mfs]
    est.n_features_in_ = d
    est.input_names_, est.input_units_ = [n for n, _ in inputs], [u for _, u in inputs]
    est.input_range_ = np.array(ranges)
    est.mf_input_ = np.repeat(np.arange(d), sizes)
    est.rule_mf_ = rules[:, :-1] + np.cumsum([0] + sizes[:-1])
    est.sigmas_, est.centres_ = np.concatenate(mfs)[:, 0], np.concatenate(mfs)[:, 1]
    est.initial_centres_, est.initial_sigmas_ = est.centres_.copy(), est.sigmas_.copy()
    est.consequents_ = consequents[rules[:, -1]]
    est.train_rmse_, est.val_rmse_, est.step_sizes_ = np.array([]), np.array([]), np.array([])
    est.best_epoch_ = 0
    est._incidence_ = _incidence(est.rule_mf_, est.centres_.size)  # as ANFIS.from_dataset
    log_c = out_name.startswith(LOG)
    _check_finite(est, log_c, rules, out_lines, [number for number, _ in sections["Rules"]])
    return DampingModel(est, d >= 3 and fis_names[2].startswith(LOG), log_c)
