"""The config section ``anfis`` as typed sections: structure candidates, training, the split and the baselines."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from uavdamp.settings import require, setting

BASELINES = ("linear", "gp", "knn", "hgb")  # the baseline regressors by name (`uavdamp.anfis.baselines.make`)

CANDIDATE_KEYS = {"grid": "n_mfs", "fcm": "n_rules", "subtractive": "radius"}  # each init's one size parameter
EPOCH_SELECTION = ("validation", "checking")
SELECTION_RULES = ("one_se", "best")  # fewest rules within one standard error of the best, or the best
_W = "anfis."


# here beside the section, not in `training`: the config checks count the training rows without importing the
# estimators (scikit-learn: about 0.5 s of every Snakemake start)
def split(n: int, train_fraction: float, seed: int) -> np.ndarray:
    """Boolean mask of the training rows: a seeded random `train_fraction` of n (at least one of each)."""
    if n < 2:
        raise ValueError(f"need at least 2 samples to split, got {n}")
    n_train = min(max(int(round(train_fraction * n)), 1), n - 1)
    mask = np.zeros(n, dtype=bool)
    mask[np.random.default_rng(seed).permutation(n)[:n_train]] = True
    return mask


@dataclass(frozen=True)
class Candidate:
    """One ANFIS structure tried by the cross-validation: an init and its one size parameter."""

    init: str = setting()
    n_mfs: int | None = setting(default=None)  # grid: MFs per input
    n_rules: int | None = setting(default=None)  # fcm: rules
    radius: float | None = setting(default=None)  # subtractive: cluster radius, fraction of each input's range

    def validate(self, where: str) -> None:
        require(
            self.init in CANDIDATE_KEYS, f"{where}.init", f"must be one of {list(CANDIDATE_KEYS)}, got {self.init!r}"
        )
        wanted = CANDIDATE_KEYS[self.init]
        for key in CANDIDATE_KEYS.values():
            given = getattr(self, key) is not None
            require(given == (key == wanted), f"{where}.{key}", f"init {self.init!r} takes {wanted!r} only")

    def params(self) -> dict:
        """The estimator parameters, e.g. {"init": "grid", "n_mfs": 3}."""
        key = CANDIDATE_KEYS[self.init]
        return {"init": self.init, key: getattr(self, key)}


@dataclass(frozen=True)
class Selection:
    """k-fold cross-validation over the candidates, on the training rows only (``anfis.selection``).

    ``rule``: ``one_se`` picks the candidate with the fewest rules whose mean CV RMSE is within one standard error
    (std over folds / sqrt(folds)) of the lowest; ``best`` the lowest mean CV RMSE.
    """

    folds: int = setting()
    candidates: tuple[Candidate, ...] = setting()
    rule: str = setting()

    def validate(self) -> None:
        require(self.folds >= 2, _W + "selection.folds", f"must be >= 2, got {self.folds}")
        require(
            self.rule in SELECTION_RULES,
            _W + "selection.rule",
            f"must be one of {list(SELECTION_RULES)}, got {self.rule!r}",
        )
        require(bool(self.candidates), _W + "selection.candidates", "needs at least one candidate")
        labels = [str(c.params()) for c in self.candidates]
        require(len(set(labels)) == len(labels), _W + "selection.candidates", f"duplicate candidates in {labels}")


@dataclass(frozen=True)
class AnfisOptions:
    """The config section ``anfis``: the ANFIS learns [f_y, f_z, K] -> optimal C (Jang 1993, MATLAB's anfis)."""

    selection: Selection = setting()
    epochs: int = setting()
    error_goal: float = setting()  # the learnt target's unit (N s m-1, or 1 with log_damping)
    step_size: float = setting()  # 1, initial premise step as a fraction of each input's range
    step_increase: float = setting()  # 1
    step_decrease: float = setting()  # 1
    min_sigma_frac: float = setting()  # 1, floor of every MF width as a fraction of its input's range
    ridge: float = setting()  # 1, relative Tikhonov term of the consequent least squares
    epoch_selection: str = setting()  # validation | checking
    validation_fraction: float = setting()  # 1, share of the training rows that choose the epoch
    baselines: tuple[str, ...] = setting()
    log_stiffness: bool = setting()
    log_damping: bool = setting()
    train_fraction: float = setting()  # 1
    seed: int = setting()
    max_memory_gb: float = setting(default=4.0)  # GB, a fit needing more is refused (uavdamp.anfis.estimator)

    def validate(self) -> None:
        require(self.epochs >= 1, _W + "epochs", f"must be >= 1, got {self.epochs}")
        require(
            self.epoch_selection in EPOCH_SELECTION,
            _W + "epoch_selection",
            f"must be one of {list(EPOCH_SELECTION)}, got {self.epoch_selection!r}",
        )
        if self.epoch_selection == "validation":
            require(
                0 < self.validation_fraction < 1,
                _W + "validation_fraction",
                f"must lie in (0, 1) with epoch_selection 'validation', got {self.validation_fraction}",
            )
        require(0 < self.train_fraction < 1, _W + "train_fraction", f"must lie in (0, 1), got {self.train_fraction}")
        for name in self.baselines:
            require(name in BASELINES, _W + "baselines", f"unknown baseline {name!r}; choose from {list(BASELINES)}")

    def estimator_params(self) -> dict:
        """The ANFIS parameters these options set (structure aside: the selection chooses it)."""
        names = (
            "epochs",
            "error_goal",
            "step_size",
            "step_increase",
            "step_decrease",
            "min_sigma_frac",
            "ridge",
            "max_memory_gb",
        )
        params = {name: getattr(self, name) for name in names}
        return {**params, "validation_fraction": self.validation_fraction, "random_state": self.seed}


@dataclass(frozen=True, kw_only=True)
class AnfisSection(AnfisOptions):
    """The config section ``anfis``: the options (the stage's params, what the results depend on) and its threads.

    ``threads`` (the rule's ``threads:``, joblib workers of the cross-validation and the baselines) is not an
    option: the results are identical whatever its value, so changing it reruns nothing.
    """

    threads: int = setting()

    def validate(self) -> None:
        super().validate()
        require(self.threads >= 1, _W + "threads", f"must be >= 1, got {self.threads}")
