# The theory sweep: one job per shard of designs.


rule theory_shard:
    output:
        f"{R}/theory/shards/shard_{{shard}}.nc",
    log:
        f"{R}/logs/theory/shard_{{shard}}.log",
    benchmark:
        f"{R}/benchmarks/theory/shard_{{shard}}.tsv"
    wildcard_constraints:
        shard=r"\d+",
    conda:
        "../../envs/theory.yaml"
    threads: CFG["sweep"]["threads"]
    resources:
        runtime=60,
        mem_mb=2000,
    params:
        key=shard_params("theory"),
    script:
        "../scripts/shard.py"
