"""Tests of the MATLAB .fis export and import (uavdamp.anfis.fis): exact round trips, a plain Sugeno evaluator
written here (it reads the text itself and imports no uavdamp code), a third-party engine (fuzzylite), and the
refusals. Expected values come from the test's own data and evaluator, never from the code under test."""

import itertools
import math
import shutil
import subprocess

import numpy as np
import pytest
from conftest import anfis_options, apt_install
from sklearn.exceptions import NotFittedError
from sklearn.linear_model import LinearRegression

from uavdamp import io
from uavdamp.anfis import ANFIS, DampingModel
from uavdamp.anfis.fis import from_fis, to_fis

# any warning not expected with pytest.warns fails the test
pytestmark = pytest.mark.filterwarnings("error")

LO, HI = np.array([5.0, 5.0, 10.0]), np.array([30.0, 30.0, 1000.0])  # f_y, f_z [Hz], K [N/m]
RTOL = 1e-12


def fitted(structure: dict, epochs: int) -> DampingModel:
    """A DampingModel on log10 K and C with the ANFIS `structure` (init and its size), fitted on TRAIN."""
    model = DampingModel.unfitted(anfis_options(epochs=epochs, seed=0, log_stiffness=True, log_damping=True))
    model.estimator.set_params(**structure)
    return model.fit(TRAIN, damping(TRAIN))


def damping(X):
    """Test function: C [N s/m] = 10^(1 + 0.3 sin(f_y / 5) + 0.2 (f_z / 20)^2 - 0.25 log10(K / 1 N/m))."""
    return 10 ** (1 + 0.3 * np.sin(X[:, 0] / 5) + 0.2 * (X[:, 1] / 20) ** 2 - 0.25 * np.log10(X[:, 2]))


def sample(n, seed):
    """n rows [f_y, f_z, K]: f_y, f_z uniform in [5, 30] Hz, K log-uniform in [10, 1000] N/m."""
    u = np.random.default_rng(seed).random((n, 3))
    X = LO + (HI - LO) * u
    X[:, 2] = 10 ** (1 + 2 * u[:, 2])
    return X


TRAIN = sample(200, 0)
INITS = {"grid": {"init": "grid", "n_mfs": 2}, "subtractive": {"init": "subtractive", "radius": 0.6}}


@pytest.fixture(scope="module", params=list(INITS))
def table_model(request):
    """A DampingModel on log10 K and log10 C: grid init (2 MFs per input, shared by 8 rules) or subtractive
    clustering (every rule its own MF per input)."""
    return fitted(INITS[request.param], epochs=20)


def inside(n, seed):
    """n points inside the training box: the model's and the file's ranges are the training extremes."""
    u = np.random.default_rng(seed).random((n, 3))
    lo, hi = TRAIN.min(axis=0), TRAIN.max(axis=0)
    return np.column_stack([lo[:2] + (hi[:2] - lo[:2]) * u[:, :2], lo[2] * (hi[2] / lo[2]) ** u[:, 2]])


def learnt(X):
    """Rows [f_y, f_z, K] as the FIS inputs [f_y Hz, f_z Hz, log10(K / 1 N/m)]."""
    return np.column_stack([X[:, 0], X[:, 1], np.log10(X[:, 2])])


# ---------------------------------------------------------------------------------------------
# An independent reader and evaluator of the classic .fis text (MATLAB's semantics for this subset)


def parse_fis(text):
    """{section: {key: value}} with [Rules] a list of lines; '%' lines and blanks skipped."""
    sections, current = {}, None
    for raw in text.splitlines():
        line = raw.strip()
        if not line or line.startswith("%"):
            continue
        if line.startswith("["):
            current = line[1:-1]
            sections[current] = [] if current == "Rules" else {}
        elif current == "Rules":
            sections[current].append(line)
        else:
            key, value = line.split("=", 1)
            sections[current][key] = value
    return sections


def numbers(value):
    return [float(v) for v in value.strip()[1:-1].split()]


def mf(value):
    """(type, params) of "'name':'type',[params]"."""
    head, params = value.split(",", 1)
    return head.split(":")[1].strip("'"), numbers(params)


def plain_sugeno(text, X):
    """evalfis of a first-order Sugeno FIS with gaussmf inputs, product AND and weighted average, no clamping."""
    fis = parse_fis(text)
    n_in = int(fis["System"]["NumInputs"])
    inputs = []
    for i in range(1, n_in + 1):
        sec = fis[f"Input{i}"]
        inputs.append([mf(sec[f"MF{k}"])[1] for k in range(1, int(sec["NumMFs"]) + 1)])
    out = fis["Output1"]
    linear = [mf(out[f"MF{k}"])[1] for k in range(1, int(out["NumMFs"]) + 1)]
    rules = []
    for line in fis["Rules"]:
        left, right = line.split(",")
        rules.append(([int(v) for v in left.split()], int(right.split("(")[0])))
    result = []
    for x in X:
        num = den = 0.0
        for antecedent, consequent in rules:
            w = 1.0
            for i, k in enumerate(antecedent):
                sigma, c = inputs[i][k - 1]
                w *= math.exp(-((x[i] - c) ** 2) / (2 * sigma**2))
            p = linear[consequent - 1]
            num += w * (sum(p[i] * x[i] for i in range(n_in)) + p[-1])
            den += w
        result.append(num / den)
    return np.array(result)


# ---------------------------------------------------------------------------------------------


def test_round_trip_predictions_are_identical(table_model):
    back = from_fis(to_fis(table_model))
    assert (back.log_stiffness, back.log_damping) == (True, True)
    assert back.anfis.n_rules_ == table_model.anfis.n_rules_
    X = np.vstack([inside(300, 1), sample(50, 2) * [1.5, 0.5, 3.0]])  # and outside: both clamp
    np.testing.assert_allclose(back.predict_target(X), table_model.predict_target(X), rtol=RTOL, atol=0)
    np.testing.assert_allclose(back.predict(X), table_model.predict(X), rtol=RTOL, atol=0)
    assert back.rules_text() == table_model.rules_text()
    assert to_fis(back) == to_fis(table_model)


def test_the_clustering_model_has_one_mf_per_rule_and_input(table_model):
    fis = parse_fis(to_fis(table_model))
    n_rules = int(fis["System"]["NumRules"])
    n_mfs = [int(fis[f"Input{i}"]["NumMFs"]) for i in (1, 2, 3)]
    if table_model.anfis.init == "grid":
        assert (n_rules, n_mfs) == (8, [2, 2, 2])
    else:
        assert n_rules >= 3 and n_mfs == [n_rules] * 3
    assert int(fis["Output1"]["NumMFs"]) == n_rules == len(fis["Rules"])


def test_a_bare_anfis_round_trips_with_its_units_in_the_names():
    names = dict(input_names=["f_y", "f_z", "K"], input_units=["Hz", "Hz", "N/m"], output_name="C")
    est = ANFIS(n_mfs=2, epochs=10, **names, output_units="N s/m").fit(TRAIN, damping(TRAIN))
    text = to_fis(est)
    fis = parse_fis(text)
    assert [fis[s]["Name"] for s in ("Input1", "Input2", "Input3", "Output1")] == [
        "'f_y_Hz'",
        "'f_z_Hz'",
        "'K_N_m'",
        "'C_N_s_m'",
    ]
    back = from_fis(text)
    assert (back.log_stiffness, back.log_damping) == (False, False)
    X = inside(200, 3)
    np.testing.assert_allclose(back.predict(X), est.predict(X), rtol=RTOL, atol=0)
    np.testing.assert_allclose(plain_sugeno(text, X), est.predict(X), rtol=RTOL, atol=0)


def test_the_file_alone_predicts_the_model_inside_the_ranges(table_model):
    text = to_fis(table_model)
    fis = parse_fis(text)
    system = fis["System"]
    assert {k: system[k] for k in ("Type", "AndMethod", "OrMethod", "ImpMethod", "AggMethod", "DefuzzMethod")} == {
        "Type": "'sugeno'",
        "AndMethod": "'prod'",
        "OrMethod": "'probor'",
        "ImpMethod": "'prod'",
        "AggMethod": "'sum'",
        "DefuzzMethod": "'wtaver'",
    }
    sections = ("Input1", "Input2", "Input3", "Output1")
    assert [fis[s]["Name"] for s in sections] == ["'f_y_Hz'", "'f_z_Hz'", "'log10_K_N_m'", "'log10_C_N_s_m'"]
    box = learnt(TRAIN)
    for i in range(3):
        assert numbers(fis[f"Input{i + 1}"]["Range"]) == [box[:, i].min(), box[:, i].max()]
    assert all(line.endswith(" (1) : 1") for line in fis["Rules"])
    X = np.vstack([inside(300, 4), TRAIN[:20]])
    expected = plain_sugeno(text, learnt(X))
    np.testing.assert_allclose(table_model.predict_target(X), expected, rtol=RTOL, atol=0)
    np.testing.assert_allclose(table_model.predict(X), 10**expected, rtol=RTOL, atol=0)


def test_the_stage_writes_a_fis_that_evaluates_like_its_model(quick_run):
    """reports-quick/anfis/model.fis, as the quick run wrote it: read back it predicts model.nc's model bit for bit on
    every table cell, and the plain evaluator here (no uavdamp code) agrees on the cells clamped to its Ranges."""
    out = quick_run / "reports-quick/anfis"
    text = (out / "model.fis").read_text()
    model = DampingModel.from_dataset(io.open_dataset(out / "model.nc"))
    record = io.open_dataset(out / "training.nc")
    X = np.column_stack([record[name].values for name in ("freq_y", "freq_z", "stiffness")])
    np.testing.assert_array_equal(from_fis(text).predict(X), model.predict(X))
    fis = parse_fis(text)
    assert int(fis["System"]["NumRules"]) == model.anfis.n_rules_ == record.attrs["n_rules"]
    ranges = np.array([numbers(fis[f"Input{i}"]["Range"]) for i in (1, 2, 3)])
    clamped = np.clip(learnt(X), ranges[:, 0], ranges[:, 1])
    np.testing.assert_allclose(10 ** plain_sugeno(text, clamped), model.predict(X), rtol=RTOL, atol=0)


def test_outside_the_ranges_the_file_user_must_clamp(table_model):
    """evalfis does not clamp (the plain evaluator neither); the model does, and the output Range bounds it."""
    text = to_fis(table_model)
    box = learnt(TRAIN)
    raw = sample(50, 5) * [2.0, 0.1, 1.0]  # f_y up to 60 Hz, f_z down to 0.5 Hz
    outside = learnt(raw)
    clamped = np.clip(outside, box.min(axis=0), box.max(axis=0))
    model = table_model.predict_target(raw)
    np.testing.assert_allclose(model, plain_sugeno(text, clamped), rtol=RTOL, atol=0)
    assert np.abs(plain_sugeno(text, outside) - model).max() > 1e-3


def test_the_output_range_is_the_rules_extremes_over_the_input_box(table_model):
    """Each linear consequent is extreme at a corner of the box; a weighted average stays within them."""
    fis = parse_fis(to_fis(table_model))
    corners = np.array(list(itertools.product(*[numbers(fis[f"Input{i}"]["Range"]) for i in (1, 2, 3)])))
    rules = np.array([mf(fis["Output1"][f"MF{k}"])[1] for k in range(1, int(fis["Output1"]["NumMFs"]) + 1)])
    values = corners @ rules[:, :3].T + rules[:, 3]
    lo, hi = numbers(fis["Output1"]["Range"])
    np.testing.assert_allclose([lo, hi], [values.min(), values.max()], rtol=RTOL, atol=0)
    inner = table_model.predict_target(inside(500, 6))
    assert lo <= inner.min() and inner.max() <= hi


# ---------------------------------------------------------------------------------------------
# fuzzylite: a third-party engine


def fll_of(text):
    """The FIS as FuzzyLite Language, from the test's own reading of the file."""
    fis = parse_fis(text)
    lines = ["Engine: e"]
    n_in = int(fis["System"]["NumInputs"])
    names = [fis[f"Input{i}"]["Name"].strip("'") for i in range(1, n_in + 1)]
    for i, name in enumerate(names, 1):
        sec = fis[f"Input{i}"]
        lines += [f"InputVariable: {name}", "  range: " + " ".join(map(repr, numbers(sec["Range"])))]
        for k in range(1, int(sec["NumMFs"]) + 1):
            sigma, c = mf(sec[f"MF{k}"])[1]
            lines.append(f"  term: m{k} Gaussian {c!r} {sigma!r}")
    out = fis["Output1"]
    lines += [f"OutputVariable: {out['Name'].strip(chr(39))}", "  range: " + " ".join(map(repr, numbers(out["Range"])))]
    lines += ["  aggregation: UnboundedSum", "  defuzzifier: WeightedAverage Automatic", "  default: nan"]
    for k in range(1, int(out["NumMFs"]) + 1):
        lines.append(f"  term: r{k} Linear " + " ".join(map(repr, mf(out[f"MF{k}"])[1])))
    lines += ["RuleBlock: rules", "  conjunction: AlgebraicProduct", "  activation: General"]
    for line in fis["Rules"]:
        left, right = line.split(",")
        conds = " and ".join(f"{n} is m{k}" for n, k in zip(names, left.split(), strict=True))
        lines.append(f"  rule: if {conds} then {out['Name'].strip(chr(39))} is r{right.split('(')[0].strip()}")
    return "\n".join(lines) + "\n"


@pytest.fixture
def fl(monkeypatch):
    """pyfuzzylite, its absolute tolerance set to 0: by default (1e-6 in 7.1, 1e-3 in 8.0) its rule activation
    drops every rule whose firing strength is below it (moving the clustering model's output by ~1e-4
    relative at 1e-6); evalfis and the ANFIS keep every rule."""
    fl = pytest.importorskip("fuzzylite")
    if hasattr(fl, "settings"):  # pyfuzzylite 8
        monkeypatch.setattr(fl.settings, "atol", 0.0)
    else:  # pyfuzzylite 7
        monkeypatch.setattr(fl.lib, "abs_tolerance", 0.0)
    return fl


def evaluate_engine(engine, X):
    out = []
    for x in X:
        for variable, value in zip(engine.input_variables, x, strict=True):
            variable.value = float(value)
        engine.process()
        out.append(np.asarray(engine.output_variables[0].value).item())
    return np.array(out)


def install_fuzzylite() -> str:
    """The C++ fuzzylite's command, installed from Debian (as the SLURM tests install SLURM); skip if it cannot be."""
    why = apt_install(["fuzzylite"])
    binary = shutil.which("fuzzylite")
    if binary is None:
        pytest.skip(
            f"pyfuzzylite has no FisImporter and the C++ fuzzylite is absent ({why or 'not found after apt-get'})"
        )
    return binary


def fuzzylite_engine(fl, text, tmp_path):
    """pyfuzzylite's engine of the .fis text, imported by fuzzylite's own FIS importer.

    pyfuzzylite (7.1, 8.0) has no FisImporter: its README lists the fis importer under the C++ fuzzylite
    only. So: pyfuzzylite's importer if a release has one, else the C++ fuzzylite's (Debian package
    `fuzzylite`: fis -> FLL, 17 decimals) read by pyfuzzylite's FllImporter; else skip."""
    if hasattr(fl, "FisImporter"):
        return fl.FisImporter().from_string(text)
    binary = shutil.which("fuzzylite") or install_fuzzylite()
    (tmp_path / "model.fis").write_text(text)
    command = [binary, "-i", "model.fis", "-if", "fis", "-o", "model.fll", "-of", "fll", "-decimals", "17"]
    subprocess.run(command, cwd=tmp_path, check=True, capture_output=True, timeout=60)
    return fl.FllImporter().from_string((tmp_path / "model.fll").read_text())


def test_fuzzylite_imports_the_file_and_evaluates_the_model(fl, table_model, tmp_path):
    engine = fuzzylite_engine(fl, to_fis(table_model), tmp_path)
    X = inside(100, 7)
    np.testing.assert_allclose(evaluate_engine(engine, learnt(X)), table_model.predict_target(X), rtol=1e-9, atol=0)


def test_pyfuzzylite_evaluates_the_file_as_read_here(fl, table_model):
    engine = fl.FllImporter().from_string(fll_of(to_fis(table_model)))
    X = inside(100, 8)
    np.testing.assert_allclose(evaluate_engine(engine, learnt(X)), table_model.predict_target(X), rtol=1e-9, atol=0)


def swap_mfs(text, section, column):
    """The text with MF1 and MF2 of ``section`` swapped, and the rules' numbers in ``column`` swapped to match."""
    lines = text.splitlines()
    start = lines.index(f"[{section}]")
    one = next(i for i in range(start, len(lines)) if lines[i].startswith("MF1="))
    lines[one], lines[one + 1] = "MF1=" + lines[one + 1][4:], "MF2=" + lines[one][4:]
    rules = lines.index("[Rules]")
    for i in range(rules + 1, len(lines)):
        left, right = lines[i].split(",")
        fields = left.split() + [right.split("(")[0].strip()]
        fields[column] = {"1": "2", "2": "1"}.get(fields[column], fields[column])
        lines[i] = " ".join(fields[:-1]) + f", {fields[-1]} (1) :" + lines[i].rsplit(":", 1)[1]
    return "\n".join(lines) + "\n"


def test_the_rules_mf_numbers_are_honoured(grid_text):
    """Reordering an input's or the output's MFs, with the rules renumbered to match, is the same FIS."""
    X = inside(200, 9)
    expected = from_fis(grid_text).predict(X)
    for section, column in (("Input1", 0), ("Input3", 2), ("Output1", 3)):
        text = swap_mfs(grid_text, section, column)
        assert text != grid_text
        np.testing.assert_allclose(from_fis(text).predict(X), expected, rtol=RTOL, atol=0)


def test_a_constant_output_mf_is_a_linear_one_with_zero_coefficients(grid_text):
    line = next(line for line in grid_text.splitlines() if line.startswith("MF1='rule1'"))
    c = mf(line.split("=", 1)[1])[1][-1]
    zero = grid_text.replace(line, f"MF1='rule1':'linear',[0 0 0 {c!r}]")
    constant = grid_text.replace(line, f"MF1='rule1':'constant',[{c!r}]")
    X = inside(200, 10)
    np.testing.assert_allclose(from_fis(constant).predict(X), from_fis(zero).predict(X), rtol=RTOL, atol=0)
    np.testing.assert_allclose(from_fis(zero).predict_target(X), plain_sugeno(zero, learnt(X)), rtol=RTOL, atol=0)


# ---------------------------------------------------------------------------------------------
# Refusals


@pytest.fixture(scope="module")
def grid_text():
    return to_fis(fitted({"init": "grid", "n_mfs": 2}, epochs=5))


def line_of(text, fragment):
    return next(n for n, line in enumerate(text.splitlines(), 1) if fragment in line)


@pytest.mark.parametrize(
    "old, new, message",
    [
        ("Type='sugeno'", "Type='mamdani'", r"\[System\] line {}: Type='mamdani' is not supported"),
        ("AndMethod='prod'", "AndMethod='min'", r"\[System\] line {}: AndMethod='min' is not supported"),
        ("AndMethod='prod'\n", "", r"\[System\]: AndMethod is missing"),
        ("DefuzzMethod='wtaver'", "DefuzzMethod='wtsum'", r"\[System\] line {}: DefuzzMethod='wtsum'"),
        ("NumOutputs=1", "NumOutputs=2", r"\[System\] line {}: NumOutputs must be 1"),
        ("'gaussmf',[", "'gbellmf',[2 ", r"\[Input1\] line {}: MF type 'gbellmf' is not supported"),
        ("MF1='rule1':'linear'", "MF1='rule1':'trimf'", r"\[Output1\] line {}: MF type 'trimf' is not supported"),
        ("1 1 1, 1 (1) : 1", "1 1 1, 1 (1) : 2", r"\[Rules\] line {}: connection 2 \(OR\) is not supported"),
        ("1 1 1, 1 (1) : 1", "1 1 1, 1 (0.5) : 1", r"\[Rules\] line {}: rule weight 0.5 is not supported"),
        ("1 1 1, 1 (1) : 1", "1 0 1, 1 (1) : 1", r"\[Rules\] line {}: input 2 MF number 0 is not supported"),
        ("1 1 1, 1 (1) : 1", "1 1 -1, 1 (1) : 1", r"\[Rules\] line {}: input 3 MF number -1 is not supported"),
        ("1 1 1, 1 (1) : 1", "1 1, 1 (1) : 1", r"\[Rules\] line {}: needs 3 input MF numbers"),
        ("Name='f_y_Hz'", "Name='log10_f_y_Hz'", r"\[Input1\]: log10_f_y_Hz is log-transformed"),
        ("Range=[", "Range=[1 ", r"\[Input1\] line {}: Range must be \[min max\]"),
        ("NumRules=8", "NumRules=9", r"NumRules=9 but \[Rules\] has 8 rules"),
        ("[Output1]", "[Output]", r"section \[Output1\] is missing"),
        ('% uavdamp-names: {"inputs"', '% uavdamp-names: {inputs"', r"line {}: % uavdamp-names: is not JSON"),
    ],
)
def test_unsupported_files_are_refused_with_the_place(grid_text, old, new, message):
    assert old in grid_text
    bad = grid_text.replace(old, new, 1)
    number = line_of(bad, new.strip() or "\n") if "{}" in message else None
    with pytest.raises(ValueError, match=message.format(number)):
        from_fis(bad)


def test_models_the_file_cannot_hold_are_refused():
    with pytest.raises(NotFittedError):
        to_fis(ANFIS())
    with pytest.raises(TypeError, match="needs a DampingModel of an ANFIS"):
        to_fis(DampingModel(LinearRegression().fit(TRAIN, damping(TRAIN)), False, False))
    X = TRAIN.copy()
    X[:, 1] = 12.0
    with pytest.warns(UserWarning, match="constant"):
        constant = ANFIS(n_mfs=2, epochs=2, input_names=["f_y", "f_z", "K"]).fit(X, damping(TRAIN))
    with pytest.raises(ValueError, match="input f_z is constant"):
        to_fis(constant)
    tm = fitted({"init": "grid", "n_mfs": 2}, epochs=2)
    with pytest.raises(ValueError, match="input 3 is named 'log10_K'.*export the DampingModel"):
        to_fis(tm.anfis)


# ---------------------------------------------------------------------------------------------
# Edits that change what the file means: refused naming the file, the line and the rule


@pytest.mark.parametrize(
    "old, new, section",
    [
        ("Name='log10_K_N_m'", "Name='K_N_m'", "Input3"),  # K read as N/m, not log10: a 10-1000 times larger input
        ("Name='log10_C_N_s_m'", "Name='C_N_s_m'", "Output1"),  # the output read as C, not log10 C
        ("Name='f_y_Hz'", "Name='f_y_kHz'", "Input1"),  # another unit than the names comment's
    ],
)
def test_a_name_outside_the_documented_transforms_is_refused_naming_file_and_line(
    grid_text, tmp_path, old, new, section
):
    """Seen failing on the previous main: the edited file was read (the log10 transform silently dropped, f_y's
    unit changed) and predicted other values with no message."""
    from uavdamp.anfis.fis import read_fis

    path = tmp_path / "model.fis"
    path.write_text(grid_text.replace(old, new, 1))
    number = line_of(path.read_text(), new)
    with pytest.raises(ValueError, match=rf"^{path}: \[{section}\] line {number}: {new} does not match"):
        read_fis(path)
    no_names = "\n".join(line for line in grid_text.splitlines() if not line.startswith("% uavdamp-names"))
    cut = no_names.replace("Name='log10_K_N_m'", "Name='log10_K'", 1)  # the log10 name without its unit
    cut_line = line_of(cut, "Name='log10_K'")
    with pytest.raises(ValueError, match=rf"\[Input3\] line {cut_line}: Name='log10_K' is log"):
        from_fis(cut)


def test_a_duplicated_key_is_refused_naming_both_lines(grid_text, tmp_path):
    """Seen failing on the previous main: the second Range= of [Input1] silently replaced the first."""
    from uavdamp.anfis.fis import read_fis

    first = line_of(grid_text, "Range=")
    lines = grid_text.splitlines()
    lines.insert(first, "Range=[0.0 100.0]")  # right after the first
    path = tmp_path / "model.fis"
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(
        ValueError, match=rf"^{path}: \[Input1\] line {first + 1}: Range appears twice \(first at line "
    ):
        read_fis(path)
    tagged = grid_text.replace("\n[System]", f"\n{next(s for s in lines if s.startswith('% uavdamp-names'))}\n[System]")
    with pytest.raises(ValueError, match="a second % uavdamp-names: line"):
        from_fis(tagged)


def test_a_consequent_predicting_a_non_finite_value_is_refused_naming_the_rule(grid_text, tmp_path):
    """Seen failing on the previous main: a constant term of 1e300 was read, and the model predicted C = inf
    (10**1e300)."""
    from uavdamp.anfis.fis import read_fis

    sections = parse_fis(grid_text)
    mf3 = sections["Output1"]["MF3"]
    params = numbers(mf3.split(",", 1)[1])
    edited = mf3.split(",", 1)[0] + ",[" + " ".join(repr(v) for v in [*params[:-1], 1e300]) + "]"
    text = grid_text.replace("MF3=" + mf3, "MF3=" + edited, 1)
    top = np.max(plain_sugeno(text, learnt(inside(50, 3))))  # the file's own log10 C, by the plain evaluator
    assert top > np.log10(np.finfo(float).max)  # 10**top overflows: C = inf
    rules = [n for n, line in enumerate(text.splitlines(), 1) if line.strip().endswith(", 3 (1) : 1")]
    path = tmp_path / "model.fis"
    path.write_text(text)
    rule = f"MF3 of rule 3 \\(\\[Rules\\] line {rules[0]}\\) gives a non-finite prediction"
    with pytest.raises(ValueError, match=rf"^{path}: \[Output1\] line {line_of(text, 'MF3=' + edited)}: {rule}"):
        read_fis(path)
