# The two physics engines compared design by design (issue 25; beyond the paper; config/engines.yaml,
# docs/mujoco.md): from the committed metrics tables of the pybullet survey, the MuJoCo survey and
# the theory (engines.pybullet, .mujoco, .theory), the joined table and its statistics, and the
# design where the engines disagree most simulated again in both; the figures engines and
# disagreement are registered figures (morphlearn.figures.registry; rules in figures.smk) that read
# these outputs. Outputs update(): a failed rerun keeps the previous ones.


localrules:
    engines_numbers,


rule engines_numbers:
    input:
        **ENGINES.tables(),
        # the package modules the script imports, so a code edit re-runs it
        code=figure_registry.notebook_modules(
            "workflow/scripts/engines_numbers.py", "src"
        ),
    output:
        table=update(f"{R}/engines.csv"),
        numbers=update(f"{R}/engines.json"),
        # custody: the tables' digests and these files' (the figure checks it)
        provenance=update(f"{R}/engines.provenance.json"),
    log:
        f"{R}/logs/engines/numbers.log",
    benchmark:
        f"{R}/benchmarks/engines/numbers.tsv"
    conda:
        "../../envs/analysis.yaml"
    params:
        engines=ENGINES.science(),
    script:
        "../scripts/engines_numbers.py"


rule engines_disagreement:
    input:
        # the two engines' tables (the registry's pair, models.COMPARED)
        **{e: ENGINES.tables()[e] for e in engine_compare.ENGINES},
        code=figure_registry.notebook_modules(
            "workflow/scripts/engines_disagreement.py", "src"
        ),
    output:
        info=update(f"{R}/disagreement.json"),
        success=update(f"{R}/disagreement_success.npy"),
        paths=update(f"{R}/disagreement_paths.npy"),
        provenance=update(f"{R}/disagreement.provenance.json"),
    log:
        f"{R}/logs/engines/disagreement.log",
    benchmark:
        f"{R}/benchmarks/engines/disagreement.tsv"
    conda:
        "../../envs/empirical.yaml"
    threads: 1
    params:
        engines=ENGINES.science(),
        # the body both engines simulate (empirical.morphology): its values are the rerun trigger
        body=S.models[models.reference_physics()].params.to_dict(),
    script:
        "../scripts/engines_disagreement.py"
