# Co-optimising the body against a four-synapse controller (beyond the paper, issue 27;
# docs/coopt.md): the four-weight landscape of three designs, one job per setup and learner
# variant (its CSV is the cache: a finished job is not rerun), then the analysis. Custody as the
# sweep's (common.smk): outputs update(), the analysis sealed (summary.provenance.json), the
# metrics table it reads and its record checked at start and by every step before reading.


custody_at_start([S.coopt.best_metrics], [f"{R}/coopt/summary.csv"])


localrules:
    coopt_analysis,


rule coopt_landscape:
    input:
        S.coopt.best_metrics,
    output:
        update(f"{R}/coopt/landscape/{{design}}.json"),
    log:
        f"{R}/logs/coopt/landscape_{{design}}.log",
    benchmark:
        f"{R}/benchmarks/coopt/landscape_{{design}}.tsv"
    wildcard_constraints:
        design="|".join(coopt_stage.LANDSCAPE_DESIGNS),
    conda:
        "../../envs/learners.yaml"
    threads: 2
    params:
        science=cfgmod.digest(coopt_stage.science(S)),
    script:
        "../scripts/coopt_landscape.py"


rule coopt_runs:
    input:
        S.coopt.best_metrics,
    output:
        update(f"{R}/coopt/runs/{{setup}}_{{variant}}.csv"),
    log:
        f"{R}/logs/coopt/runs_{{setup}}_{{variant}}.log",
    benchmark:
        f"{R}/benchmarks/coopt/runs_{{setup}}_{{variant}}.tsv"
    wildcard_constraints:
        setup="[a-e]",
        variant=r"[a-z_]+(-[0-9.e-]+)?",
    conda:
        "../../envs/learners.yaml"
    threads: 1
    params:
        science=cfgmod.digest(coopt_stage.science(S)),
    script:
        "../scripts/coopt_runs.py"


rule coopt_analysis:
    input:
        metrics=S.coopt.best_metrics,
        landscapes=expand(
            f"{R}/coopt/landscape/{{design}}.json",
            design=coopt_stage.LANDSCAPE_DESIGNS,
        ),
        runs=expand(
            f"{R}/coopt/runs/{{setup}}_{{variant}}.csv",
            setup=S.coopt.setups,
            variant=coopt_stage.variant_names(S.coopt),
        ),
    output:
        runs=update(f"{R}/coopt/runs.csv"),
        summary=update(f"{R}/coopt/summary.csv"),
        landscape=update(f"{R}/coopt/landscape.csv"),
        md=update(f"{R}/coopt/summary.md"),
        # the figure's background (M_L by sensor position); the figure is figure_coopt
        position_map=update(f"{R}/coopt/position_map.csv"),
        provenance=update(f"{R}/coopt/summary.provenance.json"),
    log:
        f"{R}/logs/coopt/analysis.log",
    conda:
        "../../envs/learners.yaml"
    script:
        "../scripts/coopt_analysis.py"
