# uavdamp's workflow, as the layout puts it at the repository's top: `snakemake -j2 all` from here. The stages,
# their config checks and the rule `all` live in workflow/Snakefile (the folder the Snakemake workflow catalog
# reads); this file only includes it.


include: "workflow/Snakefile"


# Snakemake restores the default target after an include: name it here.
rule default:
    default_target: True
    input:
        rules.all.input,
