"""The reference table as a predictor: its optimal damping interpolated at (f_y, f_z, K), the table lookup law's
model (the baseline the ANFIS must beat)."""

from __future__ import annotations

import numpy as np
import xarray as xr

from uavdamp.reference_table.criteria import select_table


class TableLookup:
    """The reference table as a model: predict([[f_y Hz, f_z Hz, K N/m]]) -> damping_opt, N s m-1.

    table: the reference table (`criterion.reference_table`, over criterion and window, as `table.nc` holds it);
    criterion, window: the optimum to look up (default: the ones the table names in its attributes, those the
    ANFIS learns). Trilinear interpolation of `damping_opt` (freq_y, freq_z, stiffness) in (f_y, f_z, log10 K)
    (choice: K's grid is logarithmic); inputs outside the grid are moved to its edge (choice: no extrapolation); a
    cell next to a NaN optimum gives NaN (`AnfisLaw` then holds its last demand).
    """

    def __init__(self, table: xr.Dataset, criterion: str | None = None, window: str | None = None):
        from scipy.interpolate import RegularGridInterpolator

        if "criterion" in table.dims or "window" in table.dims:
            criterion = table.attrs["criterion"] if criterion is None else criterion
            window = table.attrs["window"] if window is None else window
            table = select_table(table, criterion, window)
        self.criterion, self.window = table.attrs.get("criterion"), table.attrs.get("window")
        da = table["damping_opt"].transpose("freq_y", "freq_z", "stiffness")
        self.axes = (
            np.asarray(table.freq_y, float),
            np.asarray(table.freq_z, float),
            np.log10(np.asarray(table.stiffness, float)),
        )
        self._interp = RegularGridInterpolator(self.axes, np.asarray(da.values, float), method="linear")

    def predict(self, X) -> np.ndarray:
        X = np.atleast_2d(np.asarray(X, dtype=float)).copy()
        if X.shape[1] != 3:
            raise ValueError(f"X: expected (n, 3) rows of (f_y Hz, f_z Hz, K N/m), got shape {X.shape}")
        X[:, 2] = np.log10(X[:, 2])
        for j, axis in enumerate(self.axes):
            X[:, j] = np.clip(X[:, j], axis[0], axis[-1])
        return self._interp(X)
