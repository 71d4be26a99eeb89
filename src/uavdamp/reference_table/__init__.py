"""The reference table: the best constant damping over a grid of mono-frequency inputs and isolator stiffnesses.

params      ReferenceGrid, VerifyOptions, ReferenceTableSection: the config section as typed sections
grid        GridSpec (the axes as arrays), point numbering and chunking
sine_batch  every (f_y, f_z) of one (K, C) at once on the exact linear plant (superposition)
chunks      a chunk's criteria with joblib, the chunk guard (one writer, checked before use), the merge
verify      the grid's corners and a seeded sample rerun on the Exudyn plant
criteria    the criteria of a response over time windows, and the table: the damping that minimises each
lookup      TableLookup: the table as a predictor of the optimal damping
"""

from uavdamp.reference_table.criteria import CRITERIA, reference_table, select_grid, select_table
from uavdamp.reference_table.grid import GridSpec
from uavdamp.reference_table.lookup import TableLookup
from uavdamp.reference_table.params import Axis, ReferenceGrid, ReferenceTableSection, VerifyOptions

__all__ = [
    "CRITERIA",
    "Axis",
    "GridSpec",
    "ReferenceGrid",
    "ReferenceTableSection",
    "TableLookup",
    "VerifyOptions",
    "reference_table",
    "select_grid",
    "select_table",
]
