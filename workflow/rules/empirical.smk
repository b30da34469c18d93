# The empirical (pybullet) sweep, and the base-morphology optimisation that feeds it.


if CFG["empirical"]["results_from"] is None:

    rule empirical_shard:
        input:
            morphology=CFG["empirical"]["morphology"],
        output:
            f"{R}/empirical/shards/shard_{{shard}}.nc",
        log:
            f"{R}/logs/empirical/shard_{{shard}}.log",
        benchmark:
            f"{R}/benchmarks/empirical/shard_{{shard}}.tsv"
        wildcard_constraints:
            shard=r"\d+",
        conda:
            "../../envs/empirical.yaml"
        threads: 1
        resources:
            runtime=240,
            mem_mb=2000,
        params:
            key=shard_params("empirical"),
        script:
            "../scripts/shard.py"

else:

    # empirical.results_from: the committed results of a bundle, checked and copied, not simulated.
    rule empirical_from_bundle:
        input:
            f"{CFG['empirical']['results_from']}/bundle.json",
        output:
            metrics=f"{R}/empirical/metrics.csv",
            provenance=f"{R}/empirical/metrics.provenance.json",
            merged=directory(f"{R}/empirical/merged.zarr"),
        log:
            f"{R}/logs/empirical/from_bundle.log",
        benchmark:
            f"{R}/benchmarks/empirical/from_bundle.tsv"
        localrule: True
        conda:
            "../../envs/analysis.yaml"
        script:
            "../scripts/empirical_from_bundle.py"


# Not part of `all`: the committed morphology is used; `snakemake optimise_morphology`
# regenerates the Pareto set and a candidate morphology with the configured budget.
rule optimise_morphology:
    output:
        pareto=f"{R}/morphology/pareto.csv",
        plot=f"{R}/morphology/pareto.png",
        chosen=f"{R}/morphology/empirical_morphology.yaml",
    log:
        f"{R}/logs/morphology/optimise.log",
    benchmark:
        f"{R}/benchmarks/morphology/optimise.tsv"
    conda:
        "../../envs/empirical.yaml"
    threads: 2
    params:
        budget=CFG["empirical"]["optimise"],
    script:
        "../scripts/optimise_morphology.py"
