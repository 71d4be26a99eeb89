"""The rotorcraft in Exudyn: its parameters, the multibody model, the vibration it sends to the platform mount, and
its modal analyses.

params       Helicopter, HelicopterRun, FlightRun, HelicopterSection: the config section as typed sections
model        the kinematic tree (6-DOF fuselage, articulated main rotor, tail rotor), build, solve, run (vacuum)
aerodynamics blade-element loads; inflow: momentum and Pitt-Peters inflow
treekinematics, rotorloads   the tree's frames from its coordinates; the blade-element loads on it, per step
trim         the trim solve on the held fuselage; hold: the pilot (height, attitude and position hold)
flight, flightdata   flight runs (hover, forward): trim, release, fly; their datasets (`flight_run`)
vibration    runs combined with their spectra and dominant lines (the paper's Fig. 3)
modes        coupled rotor-fuselage modes in multiblade coordinates; the Campbell diagram
floquet      Floquet analysis of the imbalanced (periodic) rotor
sensitivity  one-at-a-time runs over the uncertain parameters
"""

from uavdamp.helicopter.flightdata import run as flight_run
from uavdamp.helicopter.model import AXES, Model, blade_frequencies, build, run, solve
from uavdamp.helicopter.params import (
    FLIGHTS,
    Aerodynamics,
    BladeSection,
    Campbell,
    Flight,
    FlightRun,
    Fuselage,
    Helicopter,
    HelicopterRun,
    HelicopterSection,
    HoldOptions,
    Imbalance,
    MainRotor,
    Sensitivity,
    SolverOptions,
    Spectrum,
    TailRotor,
    TrimOptions,
)
from uavdamp.helicopter.vibration import vibration

__all__ = [
    "AXES",
    "FLIGHTS",
    "Aerodynamics",
    "BladeSection",
    "Campbell",
    "Flight",
    "FlightRun",
    "Fuselage",
    "HoldOptions",
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
    "TrimOptions",
    "blade_frequencies",
    "build",
    "flight_run",
    "run",
    "solve",
    "vibration",
]
