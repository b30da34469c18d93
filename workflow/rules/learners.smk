# Real learners on the theory model (beyond the paper, issue 15): one job per shard of designs,
# then the analysis against the theory metrics (M_L, M_CF). Custody as the sweep's (common.smk):
# outputs update() (a refused rerun keeps them), the analysis sealed (correlations.provenance.json)
# and checked, with the table it reads, at start and by its readers.


custody_at_start([], [f"{R}/learners/correlations.csv"])


localrules:
    learners_analysis,


rule learners_shard:
    output:
        update(f"{R}/learners/shards/shard_{{shard}}.csv"),
    log:
        f"{R}/logs/learners/shard_{{shard}}.log",
    benchmark:
        f"{R}/benchmarks/learners/shard_{{shard}}.tsv"
    wildcard_constraints:
        shard=r"\d+",
    conda:
        "../../envs/learners.yaml"
    threads: S.learners.threads
    resources:
        runtime=60,
        mem_mb=2000,
    params:
        key=lambda w: {
            "science": cfgmod.digest(learner_experiment.science(S)),
            "designs": cfgmod.digest(LEARNER_SHARDS[int(w.shard)].tolist()),
        },
    script:
        "../scripts/learners_shard.py"


rule learners_analysis:
    input:
        shards=expand(
            f"{R}/learners/shards/shard_{{shard}}.csv",
            shard=range(len(LEARNER_SHARDS)),
        ),
        metrics=f"{R}/theory/metrics.csv",
    output:
        runs=update(f"{R}/learners/runs.csv"),
        correlations=update(f"{R}/learners/correlations.csv"),
        md=update(f"{R}/learners/summary.md"),
        provenance=update(f"{R}/learners/correlations.provenance.json"),
    log:
        f"{R}/logs/learners/analysis.log",
    benchmark:
        f"{R}/benchmarks/learners/analysis.tsv"
    conda:
        "../../envs/learners.yaml"
    params:
        bootstrap=S.learners.bootstrap,
    script:
        "../scripts/learners_analysis.py"
