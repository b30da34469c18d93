# Co-optimising the body against a four-synapse controller (beyond the paper, issue 27;
# docs/coopt.md): the four-weight landscape of three designs, one job per setup and learner
# variant (its CSV is the cache: a finished job is not rerun), then the analysis. Custody as the
# sweep's (common.smk): outputs update(), the analysis sealed (summary.provenance.json), the
# metrics table it reads and its record checked at start and by every step before reading.


from morphlearn.coopt import bundle as coopt_bundlemod

custody_at_start([S.coopt.best_metrics], [f"{R}/coopt/summary.csv"])

# The opt-in restart runs (coopt.restart; None: off) and the stage's committed bundle (coopt.bundle_dir).
COOPT_RESTART = coopt_stage.restart_settings(S)
COOPT_BUNDLE = coopt_stage.bundle_dir(S)
COOPT_TABLES = [
    *coopt_stage.ANALYSIS_OUTPUTS,
    *(coopt_stage.RESTART_OUTPUTS if COOPT_RESTART else ()),
]


localrules:
    coopt_analysis,
    coopt_bundle,


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
        restart=False,
    script:
        "../scripts/coopt_runs.py"


rule coopt_restart_runs:
    input:
        S.coopt.best_metrics,
    output:
        update(f"{R}/coopt/restart/{{setup}}_{{variant}}.csv"),
    log:
        f"{R}/logs/coopt/restart_{{setup}}_{{variant}}.log",
    benchmark:
        f"{R}/benchmarks/coopt/restart_{{setup}}_{{variant}}.tsv"
    wildcard_constraints:
        setup="[a-e]",
        variant=r"[a-z_]+-[0-9.e-]+",
    conda:
        "../../envs/learners.yaml"
    threads: 1
    params:
        science=cfgmod.digest(coopt_stage.restart_science(S)),
        restart=True,
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
        restart=(
            expand(
                f"{R}/coopt/restart/{{setup}}_{{variant}}.csv",
                setup=COOPT_RESTART.setups,
                variant=coopt_stage.variant_names(COOPT_RESTART),
            )
            if COOPT_RESTART
            else []
        ),
    output:
        runs=update(f"{R}/coopt/runs.csv"),
        summary=update(f"{R}/coopt/summary.csv"),
        landscape=update(f"{R}/coopt/landscape.csv"),
        md=update(f"{R}/coopt/summary.md"),
        # the figure's background (M_L by sensor position); the figure is figure_coopt
        position_map=update(f"{R}/coopt/position_map.csv"),
        restart=(
            [update(f"{R}/coopt/{n}") for n in coopt_stage.RESTART_OUTPUTS]
            if COOPT_RESTART
            else []
        ),
        provenance=update(f"{R}/coopt/summary.provenance.json"),
    log:
        f"{R}/logs/coopt/analysis.log",
    benchmark:
        f"{R}/benchmarks/coopt/analysis.tsv"
    conda:
        "../../envs/learners.yaml"
    params:
        science=cfgmod.digest(coopt_stage.restart_science(S) or coopt_stage.science(S)),
    script:
        "../scripts/coopt_analysis.py"


# The committed bundle (results/coopt): the stage's tables and its figure (rule figure_coopt), and
# bundle.json with every file's SHA-256, the command, commit and library versions.
if COOPT_BUNDLE:

    ALL_TARGETS.append(f"{COOPT_BUNDLE}/bundle.json")

    rule coopt_bundle:
        input:
            tables=[f"{R}/coopt/{n}" for n in COOPT_TABLES],
            figure=[f"{R}/figures/coopt.{ext}" for ext in ("png", "pdf", "caption.md")],
        output:
            files=[
                update(f"{COOPT_BUNDLE}/{n}")
                for n in (*COOPT_TABLES, *coopt_bundlemod.FIGURE)
            ],
            manifest=update(f"{COOPT_BUNDLE}/bundle.json"),
        log:
            f"{R}/logs/coopt/bundle.log",
        benchmark:
            f"{R}/benchmarks/coopt/bundle.tsv"
        conda:
            "../../envs/figures.yaml"
        params:
            # the config files given (the command bundle.json names), relative: not the machine's paths
            configs=[os.path.relpath(f) for f in workflow.configfiles],
        script:
            "../scripts/coopt_bundle.py"
