"""The rotorcraft in Exudyn: its parameters, the multibody model, the vibration it sends to the platform mount, and
its modal analyses.

params       Helicopter, HelicopterRun, HelicopterSection: the config section as typed sections
model        the kinematic tree (6-DOF fuselage, articulated main rotor, tail rotor), build, solve, run
vibration    runs combined with their spectra and dominant lines (the paper's Fig. 3)
modes        coupled rotor-fuselage modes in multiblade coordinates; the Campbell diagram
floquet      Floquet analysis of the imbalanced (periodic) rotor
sensitivity  one-at-a-time runs over the uncertain parameters
"""

from uavdamp.helicopter.model import AXES, Model, blade_frequencies, build, run, solve
from uavdamp.helicopter.params import (
    Campbell,
    Fuselage,
    Helicopter,
    HelicopterRun,
    HelicopterSection,
    Imbalance,
    MainRotor,
    Sensitivity,
    SolverOptions,
    Spectrum,
    TailRotor,
)
from uavdamp.helicopter.vibration import vibration

__all__ = [
    "AXES",
    "Campbell",
    "Fuselage",
    "Helicopter",
    "HelicopterRun",
    "HelicopterSection",
    "Imbalance",
    "MainRotor",
    "Model",
    "Sensitivity",
    "SolverOptions",
    "Spectrum",
    "TailRotor",
    "blade_frequencies",
    "build",
    "run",
    "solve",
    "vibration",
]
