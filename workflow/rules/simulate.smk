# The sweeps: one job per shard of designs, for every registered model this config simulates
# (rule <model>_shard); a model whose results come from a committed bundle (<model>.results_from)
# gets <model>_from_bundle instead, which checks and copies them; a physics survey read from a
# bundle (survey_from) gets survey_from_bundle.


for _m in SIMULATED:

    rule:
        name:
            f"{_m}_shard"
        input:
            **models.get(_m).inputs(S),
        output:
            # update: a failed rerun keeps the previous shard (backed up, restored on failure)
            update(f"{R}/{_m}/shards/shard_{{shard}}.nc"),
        log:
            f"{R}/logs/{_m}/shard_{{shard}}.log",
        benchmark:
            f"{R}/benchmarks/{_m}/shard_{{shard}}.tsv"
        wildcard_constraints:
            shard=r"\d+",
        conda:
            f"../../{models.get(_m).env_file}"
        threads: models.get(_m).resources(S).threads
        resources:
            runtime=models.get(_m).resources(S).runtime,
            mem_mb=models.get(_m).resources(S).mem_mb,
            # a model on a GPU asks for one per shard job (docs/cluster.md)
            gpu=models.get(_m).resources(S).gpu,
        params:
            model=_m,
            key=shard_params(_m),
        script:
            "../scripts/shard.py"


for _m in (m for m in MODELS if models.get(m).results_from(S) is not None):

    rule:
        name:
            f"{_m}_from_bundle"
        input:
            f"{models.get(_m).results_from(S)}/bundle.json",
        output:
            metrics=update(f"{R}/{_m}/metrics.csv"),
            provenance=update(f"{R}/{_m}/metrics.provenance.json"),
            merged=update(directory(f"{R}/{_m}/merged.zarr")),
        log:
            f"{R}/logs/{_m}/from_bundle.log",
        benchmark:
            f"{R}/benchmarks/{_m}/from_bundle.tsv"
        localrule: True
        conda:
            "../../envs/analysis.yaml"
        params:
            model=_m,
        script:
            "../scripts/from_bundle.py"


if S.survey.bundle:

    rule survey_from_bundle:
        input:
            f"{S.survey.bundle}/bundle.json",
        output:
            metrics=update(SURVEY_FILES[0]),
            provenance=update(f"{R}/{S.survey.folder}/metrics.provenance.json"),
            merged=update(directory(SURVEY_FILES[1])),
        log:
            f"{R}/logs/survey/from_bundle.log",
        benchmark:
            f"{R}/benchmarks/survey/from_bundle.tsv"
        localrule: True
        conda:
            "../../envs/analysis.yaml"
        params:
            model=S.survey.model,
        script:
            "../scripts/from_bundle.py"
