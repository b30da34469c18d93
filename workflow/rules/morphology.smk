# The base-morphology optimisation that picks the physics body (empirical.optimise).


# Not part of `all`: the committed morphology is used; `snakemake optimise_morphology`
# regenerates the Pareto set and a candidate morphology with the configured budget.
rule optimise_morphology:
    output:
        # update: a failed or refused rerun keeps the previous set (as every rule's, common.smk)
        pareto=update(f"{R}/morphology/pareto.csv"),
        plot=update(f"{R}/morphology/pareto.png"),
        chosen=update(f"{R}/morphology/empirical_morphology.yaml"),
    log:
        f"{R}/logs/morphology/optimise.log",
    benchmark:
        f"{R}/benchmarks/morphology/optimise.tsv"
    conda:
        "../../envs/empirical.yaml"
    threads: 2
    params:
        budget=dict(S.models["empirical"].optimise),
    script:
        "../scripts/optimise_morphology.py"
