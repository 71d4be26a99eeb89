# Shared by the rule files: the config views each rule's params receive. A view holds exactly the keys of the
# typed section class its job parses (uavdamp.settings.view), with sorted keys (uavdamp.workflow.canonical), so
# an edit reruns exactly the stages it affects and reordering a YAML file reruns nothing.
from uavdamp.anfis import AnfisOptions
from uavdamp.camera.optics import CameraOptics
from uavdamp.sources.excitation import ExcitationOptions
from uavdamp.helicopter import FlightRun, HelicopterRun
from uavdamp.platform import PlatformParams
from uavdamp.plugins import data_inputs
from uavdamp.reference_table import ReferenceGrid
from uavdamp.settings import view
from uavdamp.study.comparison import StudyOptions
from uavdamp.workflow import canonical

OUT = config[
    "output_dir"
]  # every output, log and benchmark file of the run goes under this folder
# flight runs (blade-element aerodynamics, gravity, trim, pilot) unless helicopter.aerodynamics.inflow is none
FLIGHT_RUNS = (
    ["hover", "forward"]
    if config["helicopter"]["aerodynamics"]["inflow"] != "none"
    else []
)
VACUUM_RUNS = [
    "balanced",
    "imbalanced",
    "both_rotors",
]  # the paper's; both_rotors: tail rotor turning
ROTORS = ["balanced", "imbalanced"] + FLIGHT_RUNS  # runs of the vibration stage
RUNS = VACUUM_RUNS + FLIGHT_RUNS  # every helicopter run
ENV = "../envs/uavdamp.yaml"

CAMERA = canonical(config["camera"])
# the grid's blur criterion sees the optics only (uavdamp.camera.optics.CameraOptics): a sharp_threshold_px edit reruns the
# study and the benchmark runs, not the grid
CAMERA_OPTICS = canonical(view(config["camera"], CameraOptics))
PLUGINS = list(
    config["plugins"]
)  # plug-in law files: inputs of the rules that import them (uavdamp.plugins)
# the files those plug-ins declare they read (their DATA_FILES): inputs of the same rules
PLUGIN_DATA = data_inputs(PLUGINS)
PLATFORM = canonical(  # the platform stage: the platform and its response figure (not the stroke budget)
    {
        **view(config["platform"], PlatformParams),
        "response": config["platform"]["response"],
    }
)
PLATFORM_MODEL = canonical(view(config["platform"], PlatformParams))
# The grid's chunks see what they compute: the grid, its windows and the camera (the blur criterion); not the
# criterion and window the ANFIS learns (REFERENCE_TARGET), so choosing another reruns the table, not the grid.
REFERENCE_GRID = canonical(view(config["reference_table"], ReferenceGrid))
REFERENCE_TARGET = [
    config["reference_table"]["criterion"],
    config["reference_table"]["window"],
]
ANFIS = canonical(view(config["anfis"], AnfisOptions))
STUDY_EXCITATION = canonical(view(config["study"], ExcitationOptions))
STUDY_RUNS = canonical(view(config["study"], StudyOptions))
STUDY_FIGURES = canonical(config["study"]["figures"])
STUDY_CASES = list(
    config["study"]["cases"]
)  # names (schema pattern): one strategies figure each
# what the study's cases take their motion from: helicopter runs and measured flights (flight_logs)
CASE_RUNS = sorted(
    {c["run"] for c in config["study"]["cases"].values() if c.get("run")}
)
CASE_LOGS = sorted(
    {c["flight_log"] for c in config["study"]["cases"].values() if c.get("flight_log")}
)
# the stated sources the cases use (sources.NAME): their keys are the excitation job's params
CASE_SOURCES = canonical(
    {
        c["source"]: config["sources"][c["source"]]
        for c in config["study"]["cases"].values()
        if c.get("source")
    }
)
FLIGHT_LOGS = sorted(config["flight_logs"])
# A run sees the model and its solver, not the analyses' options, so editing `spectrum`, `campbell` or
# `sensitivity` reruns only the stage that reads it.
HELICOPTER_RUN = canonical(view(config["helicopter"], HelicopterRun))
# a flight run also sees the aerodynamics and the flight (gravity, trim, pilot)
FLIGHT_RUN = canonical(view(config["helicopter"], FlightRun))

# Which run an output belongs to (uavdamp.integrity): every rule's config digest, of its config view and of the
# digests of the rules it reads from; a job stamps its outputs with its own (params `digest`) and refuses an input
# whose stamp is not the one this plan expects (params `expects`: path -> [digest, rule]).
from uavdamp import integrity

PLAN = integrity.Plan()
DIGESTS = PLAN.digests  # "rule" or "rule:wildcard" -> digest
digest = PLAN.digest  # digest(key, params, *upstream): register a rule's digest
expects = PLAN.expects  # expects({path: key}): a consumer's {path: [digest, rule]}

# the rule that writes each helicopter run
RUN_RULE = {
    **{r: "helicopter_run" for r in VACUUM_RUNS},
    **{f: "helicopter_flight" for f in FLIGHT_RUNS},
}
