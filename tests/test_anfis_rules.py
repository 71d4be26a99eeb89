"""The rule base as a table (uavdamp.anfis.rules): each rule's membership functions in its input's units (K in N/m
even when learnt as log10 K), its consequent, and how often it fires, checked against a computation done here."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import anfis_options

from uavdamp.anfis import DampingModel
from uavdamp.anfis.rules import rules_markdown


def cells() -> np.ndarray:
    """A table's cells: f_y, f_z in 3..12 Hz, K 10..3000 N/m on a log grid."""
    grids = np.meshgrid(np.linspace(3, 12, 7), np.linspace(3, 12, 6), np.geomspace(10, 3000, 5), indexing="ij")
    return np.column_stack([g.ravel() for g in grids])


def fitted(structure: dict, log: bool) -> DampingModel:
    model = DampingModel.unfitted(anfis_options(epochs=15, log_stiffness=log, log_damping=log))
    model.estimator.set_params(**structure)
    X = cells()
    return model.fit(X, 1.0 + 0.2 * X[:, 0] + 0.1 * X[:, 1] * np.log10(X[:, 2]))


def rows(text: str) -> list[list[str]]:
    table = [line.split("|")[1:-1] for line in text.splitlines() if line.startswith("|")]
    return [[c.strip() for c in cells] for cells in table if cells[0].strip().isdigit()]


@pytest.mark.parametrize("log", [True, False])
def test_every_rule_in_the_inputs_units_with_its_firing_share(log):
    model = fitted({"init": "grid", "n_mfs": 2}, log)
    est, X = model.anfis, cells()
    text = rules_markdown(model, X)
    table = rows(text)
    assert len(table) == est.n_rules_ == 8
    # the firing strengths computed here: product of Gaussians of the learnt inputs, normalised
    learnt = model.inputs(X)
    mu = np.exp(
        -((learnt[None, :, :] - est.centres_[est.rule_mf_][:, None, :]) ** 2)
        / (2 * est.sigmas_[est.rule_mf_][:, None, :] ** 2)
    )
    w = mu.prod(axis=2)
    w /= w.sum(axis=0)
    share = np.bincount(w.argmax(axis=0), minlength=8) / len(X)
    np.testing.assert_allclose([float(r[-2]) for r in table], 100 * share, atol=0.05)
    np.testing.assert_allclose([float(r[-1]) for r in table], 100 * w.mean(axis=1), atol=0.05)
    for r, cells_ in enumerate(table):
        k_mf = est.rule_mf_[r, 2]
        centre, sigma = est.centres_[k_mf], est.sigmas_[k_mf]
        k_text = cells_[3].split(":", 1)[1].split()
        if log:  # K in N/m: 10^c and the band 10^(c -+ sigma)
            assert float(k_text[0]) == pytest.approx(10**centre, rel=5e-3)
            band = cells_[3].split("(")[1].rstrip(")").split(" to ")
            np.testing.assert_allclose([float(b) for b in band], 10 ** (centre + np.array([-sigma, sigma])), rtol=5e-3)
        else:
            assert float(k_text[0]) == pytest.approx(centre, rel=5e-3) and k_text[1] == "±"
        f_y = cells_[1].split(":", 1)[1].split()
        assert float(f_y[0]) == pytest.approx(est.centres_[est.rule_mf_[r, 0]], rel=5e-3)
        # C at the rule's centre (clamped to the training range), N s/m
        x = np.clip(est.centres_[est.rule_mf_[r]], est.input_range_[:, 0], est.input_range_[:, 1])
        expected = est.consequents_[r, :-1] @ x + est.consequents_[r, -1]
        assert float(cells_[5]) == pytest.approx(10**expected if log else expected, rel=5e-3)
    assert ("log10_C =" in text) == log and "K 10 to 3000 N/m" in text


def test_a_clustering_model_has_one_row_per_rule():
    model = fitted({"init": "fcm", "n_rules": 5}, True)
    table = rows(rules_markdown(model, cells()))
    assert [int(r[0]) for r in table] == [1, 2, 3, 4, 5]
    assert [r[1].split(":")[0] for r in table] == ["MF1", "MF2", "MF3", "MF4", "MF5"]
    assert sum(float(r[-2]) for r in table) == pytest.approx(100, abs=0.25)
