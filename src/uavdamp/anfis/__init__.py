"""The ANFIS of the paper: a first-order Takagi-Sugeno neuro-fuzzy regressor that learns [f_y, f_z, K] -> C.

params           AnfisOptions, AnfisSection, Candidate, Selection: the config section as typed sections
estimator        ANFIS: the scikit-learn estimator (Jang's hybrid rule, MATLAB's step-size rule)
_math            the arithmetic shared by fitting and prediction
initialisation   rules from a grid partition, fuzzy c-means or subtractive clustering
netcdf           the fitted estimator to and from an xarray Dataset, and its rules in words
rules            the rule base as a table in the inputs' units, with how often each rule fires
fis              the fitted model as a MATLAB Fuzzy Logic Toolbox .fis file, and back
damping          DampingModel (the ANFIS on K in N/m and C in N s/m) and the regret of a damping choice
predictor        DampingPredictor: a trained DampingModel's predictions without scikit-learn (the laws' runs)
model_selection  the structure by k-fold cross-validation on the training rows (one-SE rule), in parallel
baselines        the regressors the ANFIS is judged against
training         the training stage: samples of the reference table, the split, selection, baselines, the record
"""

from importlib import import_module

from uavdamp.anfis.params import AnfisOptions, AnfisSection, Candidate, Selection

__all__ = [
    "ANFIS",
    "AnfisOptions",
    "AnfisSection",
    "Candidate",
    "DampingModel",
    "DampingPredictor",
    "Selection",
    "train",
]
# imported when first asked for (PEP 562): the config layer and the Snakefile read the typed sections above without
# importing scikit-learn (1.2 s of every Snakemake start: a dry run of the study 5.07 -> 3.9 s, measured)
_LAZY = {
    "ANFIS": "uavdamp.anfis.estimator",
    "DampingModel": "uavdamp.anfis.damping",
    "DampingPredictor": "uavdamp.anfis.predictor",
    "train": "uavdamp.anfis.training",
}


def __getattr__(name: str):
    """ANFIS, DampingModel, DampingPredictor and train from their modules on first use."""
    if name in _LAZY:
        return getattr(import_module(_LAZY[name]), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
