rule excitation:
    input:
        runs=expand(f"{OUT}/helicopter/runs/{{rotor}}.nc", rotor=CASE_RUNS),
        logs=expand(f"{OUT}/flight_logs/{{name}}.nc", name=CASE_LOGS),
    output:
        f"{OUT}/excitation/cases.nc",
    log:
        f"{OUT}/logs/excitation.log",
    conda:
        ENV
    params:
        excitation=STUDY_EXCITATION,
        runs=CASE_RUNS,
        logs=CASE_LOGS,
    script:
        "../scripts/excitation.py"


rule study:
    input:
        cases=f"{OUT}/excitation/cases.nc",
        model=f"{OUT}/anfis/model.nc",
        plugins=PLUGINS,
    output:
        comparison=f"{OUT}/study/comparison.nc",
        fig10=report(
            f"{OUT}/figures/study_fig10_rigid.png",
            caption="../report/study_fig10.rst",
            category="Study",
        ),
        fig11=report(
            f"{OUT}/figures/study_fig11_passive_vs_anfis.png",
            caption="../report/study_fig11.rst",
            category="Study",
        ),
        fig12=report(
            f"{OUT}/figures/study_fig12_tracked_frequency.png",
            caption="../report/study_fig12.rst",
            category="Study",
        ),
        fig13=report(
            f"{OUT}/figures/study_fig13_passive_vs_anfis.png",
            caption="../report/study_fig13.rst",
            category="Study",
        ),
        blur=report(
            f"{OUT}/figures/study_blur.png",
            caption="../report/study_blur.rst",
            category="Study",
        ),
        sharp=report(
            f"{OUT}/figures/study_sharp_frames.png",
            caption="../report/study_sharp_frames.rst",
            category="Study",
        ),
        # one named figure per case of the config, so that a deleted one is replanned
        strategies=[
            report(
                f"{OUT}/figures/study_strategies/{case}.png",
                caption="../report/study_strategies.rst",
                category="Study",
            )
            for case in STUDY_CASES
        ],
    log:
        f"{OUT}/logs/study.log",
    benchmark:
        f"{OUT}/benchmarks/study.tsv"
    conda:
        ENV
    params:
        study=STUDY_RUNS,
        camera=CAMERA,
        platform=PLATFORM_MODEL,
        stroke=canonical(config["platform"]["stroke"]),
        figures=STUDY_FIGURES,
        extrapolation=EXTRAPOLATION["study"],
    script:
        "../scripts/study.py"
