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
