"""The ANFIS of the paper: a first-order Takagi-Sugeno neuro-fuzzy regressor that learns [f_y, f_z, K] -> C.

params           AnfisOptions, Candidate, Selection: the config section as typed sections
estimator        ANFIS: the scikit-learn estimator (Jang's hybrid rule, MATLAB's step-size rule)
_math            the arithmetic shared by fitting and prediction
initialisation   rules from a grid partition, fuzzy c-means or subtractive clustering
netcdf           the fitted estimator to and from an xarray Dataset, and its rules in words
model_selection  the structure by k-fold cross-validation on the training rows
baselines        the regressors the ANFIS is judged against
training         the training stage: samples of the reference table, the split, selection, baselines, the record
"""

from uavdamp.anfis.estimator import ANFIS
from uavdamp.anfis.params import AnfisOptions, Candidate, Selection
from uavdamp.anfis.training import DampingModel, train

__all__ = ["ANFIS", "AnfisOptions", "Candidate", "DampingModel", "Selection", "train"]
