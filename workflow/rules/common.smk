# Shared by the rule files: derived config views, so each rule's params hold only what it uses.
ROTORS = ["balanced", "imbalanced"]
ENV = "../envs/uavdamp.yaml"

# the helicopter section less the spectrum options, which do not change a run
HELICOPTER_MODEL = {k: v for k, v in config["helicopter"].items() if k != "spectrum"}
