# Named scenarios (docs/scenarios.md; the science is morphlearn.scenarios). Included instead of
# the main workflow when `scenarios` is set: simulations shared between scenarios under
# {SR}/_sims/<science digest>/, one results folder per scenario, and their comparison. Custody as
# the sweep's (common.smk): outputs update() (a refused rerun keeps them), the tables, summaries and
# comparison sealed, checked at start and by their readers.
import re
from dataclasses import asdict

from morphlearn import scenarios as scenmod

try:
    _SCENARIO_FILE = scenmod.read_file(S.scenario_file)
    SCENARIO_NAMES = scenmod.select(_SCENARIO_FILE, S.scenarios)
    SCENARIOS = {s.name: s for s in scenmod.expand(S, _SCENARIO_FILE, SCENARIO_NAMES)}
except cfgmod.ConfigError as err:
    print(f"morphlearn: scenario error: {err}", file=sys.stderr)
    sys.exit(2)
PLAN = scenmod.plan(list(SCENARIOS.values()), R)
SR = scenmod.scenarios_dir(S)
SIM_SHARDS = {
    sid: models.get("theory").shard_designs(sim) for sid, sim in PLAN.sims.items()
}
custody_at_start(
    [f"{SR}/{s}/theory/metrics.csv" for s in SCENARIO_NAMES],
    [*(f"{SR}/{s}/summary.json" for s in SCENARIO_NAMES), f"{SR}/comparison.csv"],
)
SCENARIO_TARGETS = [
    f"{SR}/comparison.md",
    f"{SR}/comparison.png",
    *(f"{SR}/{s}/summary.md" for s in SCENARIO_NAMES),
]
ALL_TARGETS.extend(SCENARIO_TARGETS)


wildcard_constraints:
    sim="[0-9a-f]{16}",
    scenario="|".join(re.escape(s) for s in SCENARIO_NAMES),


localrules:
    scenario_merge,
    scenario_metrics,
    scenario_summary,
    scenario_compare,
    scenario_report,


rule scenario_shard:
    output:
        update(f"{SR}/_sims/{{sim}}/shards/shard_{{shard}}.nc"),
    log:
        f"{SR}/_sims/{{sim}}/logs/shard_{{shard}}.log",
    benchmark:
        f"{SR}/_sims/{{sim}}/benchmarks/shard_{{shard}}.tsv"
    wildcard_constraints:
        shard=r"\d+",
    conda:
        "../../envs/theory.yaml"
    threads: S.sweep.threads
    resources:
        runtime=60,
        mem_mb=2000,
    params:
        cfg=lambda w: PLAN.config(w.sim),
        designs=lambda w: cfgmod.digest(SIM_SHARDS[w.sim][int(w.shard)].tolist()),
    script:
        "../scripts/scenario_shard.py"


rule scenario_merge:
    input:
        lambda w: expand(
            f"{SR}/_sims/{w.sim}/shards/shard_{{shard}}.nc",
            shard=range(len(SIM_SHARDS[w.sim])),
        ),
    output:
        update(directory(f"{SR}/_sims/{{sim}}/merged.zarr")),
    log:
        f"{SR}/_sims/{{sim}}/logs/merge.log",
    benchmark:
        f"{SR}/_sims/{{sim}}/benchmarks/merge.tsv"
    conda:
        "../../envs/analysis.yaml"
    params:
        cfg=lambda w: PLAN.config(w.sim),
    script:
        "../scripts/scenario_merge.py"


rule scenario_metrics:
    input:
        lambda w: f"{SR}/_sims/{PLAN.answers[w.scenario].sim}/merged.zarr",
    output:
        table=update(f"{SR}/{{scenario}}/theory/metrics.csv"),
        # custody: the table's sealed record (rules.run_metrics)
        provenance=update(f"{SR}/{{scenario}}/theory/metrics.provenance.json"),
        record=update(f"{SR}/{{scenario}}/scenario.json"),
    log:
        f"{SR}/{{scenario}}/logs/metrics.log",
    benchmark:
        f"{SR}/{{scenario}}/benchmarks/metrics.tsv"
    conda:
        "../../envs/analysis.yaml"
    params:
        thresholds=lambda w: PLAN.thresholds(w.scenario).__dict__,
        record=lambda w: {
            "scenario": w.scenario,
            "overrides": SCENARIOS[w.scenario].overrides,
            "theory": dict(
                SCENARIOS[w.scenario].settings.models[models.REFERENCE].section
            ),
            "answer": asdict(PLAN.answers[w.scenario]),
            "simulated": dict(
                PLAN.sims[PLAN.answers[w.scenario].sim]
                .models[models.REFERENCE]
                .section
            ),
        },
    script:
        "../scripts/scenario_metrics.py"


rule scenario_summary:
    input:
        theory=f"{SR}/{{scenario}}/theory/metrics.csv",
    output:
        json=update(f"{SR}/{{scenario}}/summary.json"),
        md=update(f"{SR}/{{scenario}}/summary.md"),
        provenance=update(f"{SR}/{{scenario}}/summary.provenance.json"),
    log:
        f"{SR}/{{scenario}}/logs/summary.log",
    benchmark:
        f"{SR}/{{scenario}}/benchmarks/summary.tsv"
    conda:
        "../../envs/analysis.yaml"
    params:
        cfg=lambda w: dict(SCENARIOS[w.scenario].settings.source),
    script:
        "../scripts/scenario_summary.py"


rule scenario_compare:
    input:
        tables=expand(f"{SR}/{{s}}/theory/metrics.csv", s=SCENARIO_NAMES),
        merged=expand(f"{SR}/_sims/{{sim}}/merged.zarr", sim=sorted(PLAN.sims)),
    output:
        csv=update(f"{SR}/comparison.csv"),
        md=update(f"{SR}/comparison.md"),
        scan=update(f"{SR}/text_values.csv"),
        provenance=update(f"{SR}/comparison.provenance.json"),
    log:
        f"{SR}/logs/compare.log",
    benchmark:
        f"{SR}/benchmarks/compare.tsv"
    conda:
        "../../envs/analysis.yaml"
    params:
        names=SCENARIO_NAMES,
        sims=sorted(PLAN.sims),
        top=S.analysis.top,
        plan=scenmod.plan_markdown(PLAN, list(SCENARIOS.values())),
    script:
        "../scripts/scenario_compare.py"


rule scenario_report:
    input:
        notebook="notebooks/scenarios.ipynb",
        style=figure_registry.STYLE,
        code=figure_registry.notebook_modules("notebooks/scenarios.ipynb", "src"),
        csv=f"{SR}/comparison.csv",
        scan=f"{SR}/text_values.csv",
    output:
        png=report(
            update(f"{SR}/comparison.png"),
            caption=str(Path(f"{SR}/comparison.caption.md").resolve()),
            category="Scenarios",
        ),
        caption=update(f"{SR}/comparison.caption.md"),
        pdf=update(f"{SR}/comparison.pdf"),
        html=update(f"{SR}/comparison.html"),
    log:
        notebook=f"{SR}/logs/comparison.ipynb",
        text=f"{SR}/logs/comparison.log",
    benchmark:
        f"{SR}/benchmarks/report.tsv"
    conda:
        "../../envs/figures.yaml"
    params:
        parameters=lambda w, input, output: yaml.safe_dump(
            {
                "comparison": input.csv,
                "scan": input.scan,
                "style": input.style,
                "png": output.png,
                "pdf": output.pdf,
                "caption": output.caption,
            },
            default_flow_style=True,
            width=10**6,
        ).strip(),
    shell:
        # relative, as the figures' (figures.smk): a moved project re-renders nothing
        "(export PYTHONPATH=src${{PYTHONPATH:+:$PYTHONPATH}}; "
        "papermill {input.notebook:q} {log.notebook:q} -y {params.parameters:q} && "
        'jupyter nbconvert --to html --log-level WARN --output-dir "$(dirname {output.html:q})" '
        "--output comparison {log.notebook:q}) > {log.text:q} 2>&1"


rule scenarios:
    input:
        SCENARIO_TARGETS,
