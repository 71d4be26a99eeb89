# Shared by the rule files: the config views each rule's params receive. A view holds only what the
# rule uses, with sorted keys (uavdamp.workflow.config_view), so an edit reruns exactly the stages it
# affects and reordering a YAML file reruns nothing.
from uavdamp.workflow import canonical, config_view

ROTORS = ["balanced", "imbalanced"]  # rotor states of the vibration stage
RUNS = ROTORS + [
    "both_rotors"
]  # helicopter runs; both_rotors: imbalanced, tail rotor turning
ENV = "../envs/uavdamp.yaml"

PLATFORM = canonical(config["platform"])
PLATFORM_MODEL = config_view(config["platform"], drop=["response"])
# The grid's chunks see what they compute: the grid, its windows and the camera (the blur criterion); not the
# criterion and window the ANFIS learns (REFERENCE_TARGET), so choosing another reruns the table, not the grid.
REFERENCE_GRID = config_view(
    config["reference_table"],
    drop=["n_chunks", "threads", "flat_tolerance", "verify", "criterion", "window"],
)
REFERENCE_CAMERA = canonical(config["camera"])
REFERENCE_TARGET = config_view(config["reference_table"], keep=["criterion", "window"])
ANFIS = canonical(config["anfis"])
STUDY_EXCITATION = config_view(
    config["study"], keep=["cases", "duration_s", "highpass_hz", "tracking"]
)
STUDY_RUNS = {
    **config_view(
        config["study"], drop=["cases", "duration_s", "highpass_hz", "figures"]
    ),
    "camera": canonical(config["camera"]),
}
STUDY_FIGURES = canonical(config["study"]["figures"])
