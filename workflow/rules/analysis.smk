# Merge shards, compute metrics, summarise: cheap, so local on clusters.


localrules:
    merge,
    metrics,
    summary,


rule merge:
    input:
        lambda w: expand(
            f"{R}/{w.model}/shards/shard_{{shard}}.nc", shard=shard_ids(w.model)
        ),
    output:
        # update: Snakemake keeps (and on failure restores) the previous store instead of deleting
        # it before the job; the merge writes aside and swaps only on success.
        update(directory(f"{R}/{{model}}/merged.zarr")),
    log:
        f"{R}/logs/{{model}}/merge.log",
    benchmark:
        f"{R}/benchmarks/{{model}}/merge.tsv"
    wildcard_constraints:
        model=SIMULATED_MODEL,
    conda:
        "../../envs/analysis.yaml"
    params:
        science=lambda w: cfgmod.digest(SCIENCE[w.model]),
    script:
        "../scripts/merge.py"


rule metrics:
    input:
        f"{R}/{{model}}/merged.zarr",
    output:
        # update (here and below): a failed or refused rerun leaves the previous valid outputs in
        # place (Snakemake backs them up instead of deleting them, and restores them on failure).
        table=update(f"{R}/{{model}}/metrics.csv"),
        provenance=report(
            update(f"{R}/{{model}}/metrics.provenance.json"),
            caption="../report/provenance.rst",
            category="Provenance",
        ),
    log:
        f"{R}/logs/{{model}}/metrics.log",
    benchmark:
        f"{R}/benchmarks/{{model}}/metrics.tsv"
    wildcard_constraints:
        model=SIMULATED_MODEL,
    conda:
        "../../envs/analysis.yaml"
    params:
        thresholds=lambda w: models.get(w.model).thresholds(S).__dict__,
    script:
        "../scripts/metrics.py"


rule summary:
    input:
        **{m: f"{R}/{m}/metrics.csv" for m in MODELS},
    output:
        json=update(f"{R}/summary.json"),
        md=update(f"{R}/summary.md"),
        # custody: the tables' digests and the summary's (provenance.write_sealed)
        provenance=update(f"{R}/summary.provenance.json"),
    log:
        f"{R}/logs/summary.log",
    benchmark:
        f"{R}/benchmarks/summary.tsv"
    conda:
        "../../envs/analysis.yaml"
    params:
        top=S.analysis.top,
    script:
        "../scripts/summary.py"
