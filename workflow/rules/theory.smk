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
        # theory.backend cuda: one GPU per shard job (the SLURM plugin submits --gpus=1; add
        # gpu_model or a GPU partition with --set-resources, docs/cluster.md). auto asks for none.
        gpu=1 if CFG["theory"]["backend"] == "cuda" else 0,
    params:
        key=shard_params("theory"),
    script:
        "../scripts/shard.py"
