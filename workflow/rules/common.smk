# Shared by the rule files: derived config views, so each rule's params hold only what it uses.
ROTORS = ["balanced", "imbalanced"]  # the vibration stage's rotor states
RUNS = ROTORS + [
    "both_rotors"
]  # helicopter runs; both_rotors: imbalanced, tail rotor running
ENV = "../envs/uavdamp.yaml"

# the helicopter section less the spectrum options, which do not change a run
HELICOPTER_MODEL = {k: v for k, v in config["helicopter"].items() if k != "spectrum"}

# the platform section less the stage figure's settings, which do not change a simulation
PLATFORM_MODEL = {k: v for k, v in config["platform"].items() if k != "response"}

# the grid that the reference table searches, less the job layout and the table options
REFERENCE_GRID = {
    k: v
    for k, v in config["reference_table"].items()
    if k not in ("n_chunks", "threads", "flat_tolerance")
}

# the study's input cases, and the closed-loop runs (less what only the excitation or the figures use)
STUDY_EXCITATION = {
    k: v
    for k, v in config["study"].items()
    if k in ("cases", "duration", "highpass_hz", "tracking")
}
STUDY_RUNS = {
    k: v
    for k, v in config["study"].items()
    if k not in ("cases", "duration", "highpass_hz", "figures")
}
