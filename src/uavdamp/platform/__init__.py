"""The camera platform (SPT 200-like pan-tilt head) on a semi-active Y-Z isolator.

params        PlatformParams: the config section as typed sections
design        closed-form mass matrix and stiffness design (the paper's Table 1 modes)
model         the Exudyn kinematic tree (assembly)
exudyn_plant  ExudynPlant: time stepping, the reference plant (`uavdamp.contract.Plant`)
modes         the clamped platform's modes by eigen-analysis
"""

from uavdamp.platform.design import design_stiffness, mass_matrix
from uavdamp.platform.exudyn_plant import ExudynPlant
from uavdamp.platform.modes import modes_dataset, natural_frequencies
from uavdamp.platform.params import PlatformParams

__all__ = ["ExudynPlant", "PlatformParams", "design_stiffness", "mass_matrix", "modes_dataset", "natural_frequencies"]
