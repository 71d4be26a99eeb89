digest(
    "excitation",
    {
        "excitation": STUDY_EXCITATION,
        "runs": CASE_RUNS,
        "logs": CASE_LOGS,
        "sources": CASE_SOURCES,
    },
    *[RUN_RULE[r] for r in CASE_RUNS],
    *[f"flight_log:{name}" for name in CASE_LOGS],
)


rule excitation:
    input:
        runs=expand(f"{OUT}/helicopter/runs/{{rotor}}.nc", rotor=CASE_RUNS),
        logs=expand(f"{OUT}/flight_logs/{{name}}.nc", name=CASE_LOGS),
    output:
        f"{OUT}/excitation/cases.nc",
    log:
        f"{OUT}/logs/excitation.log",
    priority: 3  # the study's longest chains first: docs/getting-started.md
    conda:
        ENV
    params:
        digest=DIGESTS["excitation"],
        expects=expects(
            {
                **{f"{OUT}/helicopter/runs/{r}.nc": RUN_RULE[r] for r in CASE_RUNS},
                **{f"{OUT}/flight_logs/{n}.nc": f"flight_log:{n}" for n in CASE_LOGS},
            }
        ),
        excitation=STUDY_EXCITATION,
        runs=CASE_RUNS,
        logs=CASE_LOGS,
        sources=CASE_SOURCES,
    script:
        "../scripts/excitation.py"


digest(
    "study",
    {
        "study": STUDY_RUNS,
        "camera": CAMERA,
        "platform": PLATFORM_MODEL,
        "stroke": canonical(config["platform"]["stroke"]),
        "figures": STUDY_FIGURES,
        "extrapolation": EXTRAPOLATION["study"],
        "plugins": PLUGINS,
    },
    "excitation",
    "anfis",
)


rule study:
    input:
        cases=f"{OUT}/excitation/cases.nc",
        model=f"{OUT}/anfis/model.nc",
        plugins=PLUGINS,
        plugin_data=PLUGIN_DATA,
    output:
        comparison=f"{OUT}/study/comparison.nc",
        fig10=report(
            f"{OUT}/figures/study_fig10_rigid.png",
            caption="../report/study_fig10.rst",
            category="Study",
            subcategory="Paper's figures",
            labels={"figure": "Fig. 10: rigid mount, camera Y"},
        ),
        fig11=report(
            f"{OUT}/figures/study_fig11_passive_vs_anfis.png",
            caption="../report/study_fig11.rst",
            category="Study",
            subcategory="Paper's figures",
            labels={"figure": "Fig. 11: passive against ANFIS, camera Y"},
        ),
        fig12=report(
            f"{OUT}/figures/study_fig12_tracked_frequency.png",
            caption="../report/study_fig12.rst",
            category="Study",
            subcategory="Paper's figures",
            labels={"figure": "Fig. 12: the tracked Z frequency"},
        ),
        fig13=report(
            f"{OUT}/figures/study_fig13_passive_vs_anfis.png",
            caption="../report/study_fig13.rst",
            category="Study",
            subcategory="Paper's figures",
            labels={"figure": "Fig. 13: passive against ANFIS, camera Z"},
        ),
        blur=report(
            f"{OUT}/figures/study_blur.png",
            caption="../report/study_blur.rst",
            category="Study",
            subcategory="Image quality",
            labels={"figure": "blur of every frame per strategy"},
        ),
        sharp=report(
            f"{OUT}/figures/study_sharp_frames.png",
            caption="../report/study_sharp_frames.rst",
            category="Study",
            subcategory="Image quality",
            labels={"figure": "fraction of sharp frames per strategy"},
        ),
        # one named figure per case of the config, so that a deleted one is replanned
        strategies=[
            report(
                f"{OUT}/figures/study_strategies/{case}.png",
                caption="../report/study_strategies.rst",
                category="Study",
                subcategory="Strategies",
                labels={"figure": f"every strategy side by side, case {case}"},
            )
            for case in STUDY_CASES
        ],
    log:
        f"{OUT}/logs/study.log",
    benchmark:
        f"{OUT}/benchmarks/study.tsv"
    priority: 1  # the study's longest chains first: docs/getting-started.md
    conda:
        ENV
    params:
        digest=DIGESTS["study"],
        expects=expects(
            {
                f"{OUT}/excitation/cases.nc": "excitation",
                f"{OUT}/anfis/model.nc": "anfis",
            }
        ),
        study=STUDY_RUNS,
        camera=CAMERA,
        platform=PLATFORM_MODEL,
        stroke=canonical(config["platform"]["stroke"]),
        figures=STUDY_FIGURES,
        extrapolation=EXTRAPOLATION["study"],
    script:
        "../scripts/study.py"
