"""The camera platform (SPT 200-like pan-tilt head) on a semi-active Y-Z isolator, and the plants that run it.

params        PlatformParams, PlatformSection: the config section as typed sections
design        closed-form mass matrix and stiffness design (the paper's Table 1 modes)
model         the Exudyn kinematic tree (assembly)
exudyn_plant  ExudynPlant: time stepping, the reference plant (`uavdamp.contract.Plant`)
linear_plant  LinearPlant: the exact linear plant from Exudyn's linearisation
statespace    exact discretisation and sine responses of a linear time-invariant plant
plants        which plant runs a strategy
modes         the clamped platform's modes by eigen-analysis
six_axis      a rigid payload on N isolator elements: matrices, six rigid-body modes, state space, transmissibility
six_axis_run  its exact time-domain run under a mount motion and a semi-active damping schedule
six_axis_exudyn  the same payload and elements in Exudyn (the modes' independent check)
bouc_wen      Bouc-Wen hysteresis of a wire-rope element
imu           the gimbal's IMU and its complementary filter
gimbal        the gyro-stabilised gimbal: parameters, axis plant, closed-form cascade gains
gimbal_loop   the gimbal's discrete loop in closed form: margins, sensitivity, base to line of sight
gimbal_sim    the stabilised gimbal on a moving base in the time domain
gimbal_exudyn  the same gimbal as a nested three-body mechanism in Exudyn (the time-domain run's check)
"""

from uavdamp.platform.design import design_stiffness, mass_matrix
from uavdamp.platform.exudyn_plant import ExudynPlant
from uavdamp.platform.linear_plant import LinearPlant
from uavdamp.platform.modes import modes_dataset, natural_frequencies
from uavdamp.platform.params import PlatformParams, PlatformSection
from uavdamp.platform.plants import Plants

__all__ = [
    "ExudynPlant",
    "LinearPlant",
    "PlatformParams",
    "PlatformSection",
    "Plants",
    "design_stiffness",
    "mass_matrix",
    "modes_dataset",
    "natural_frequencies",
]
