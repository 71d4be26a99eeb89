"""The ANFIS of the paper: a first-order Takagi-Sugeno neuro-fuzzy regressor that learns [f_y, f_z, K] -> C.

params           AnfisOptions, AnfisSection, Candidate, Selection: the config section as typed sections
estimator        ANFIS: the scikit-learn estimator (Jang's hybrid rule, MATLAB's step-size rule)
_math            the arithmetic shared by fitting and prediction
initialisation   rules from a grid partition, fuzzy c-means or subtractive clustering
netcdf           the fitted estimator to and from an xarray Dataset, and its rules in words
rules            the rule base as a table in the inputs' units, with how often each rule fires
fis              the fitted model as a MATLAB Fuzzy Logic Toolbox .fis file, and back
damping          DampingModel (the ANFIS on K in N/m and C in N s/m) and the regret of a damping choice
model_selection  the structure by k-fold cross-validation on the training rows (one-SE rule), in parallel
baselines        the regressors the ANFIS is judged against
training         the training stage: samples of the reference table, the split, selection, baselines, the record
"""

from uavdamp.anfis.damping import DampingModel
from uavdamp.anfis.estimator import ANFIS
from uavdamp.anfis.params import AnfisOptions, AnfisSection, Candidate, Selection
from uavdamp.anfis.training import train

__all__ = ["ANFIS", "AnfisOptions", "AnfisSection", "Candidate", "DampingModel", "Selection", "train"]
