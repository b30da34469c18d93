# Config validation (one-line error, exit 2, nothing written) and shared helpers.
import json
import os
import sys
from pathlib import Path

import yaml

from morphlearn import config as cfgmod
from morphlearn import pipeline, results_check
from morphlearn.learners import experiment as learner_experiment
from morphlearn.figures import registry as figure_registry

try:
    CFG = cfgmod.validate(config)
except cfgmod.ConfigError as err:
    print(f"morphlearn: config error: {err}", file=sys.stderr)
    sys.exit(2)


envvars:
    "PATH",


# Shell rules (papermill, nbconvert) find the tools of the Python running Snakemake even when its
# environment is not activated; with --sdm conda the rule's environment still comes first.
os.environ["PATH"] = (
    f"{Path(sys.executable).parent}{os.pathsep}{os.environ.get('PATH', '')}"
)

R = CFG["results_dir"]
MODELS = pipeline.models(CFG)
SIMULATED = pipeline.simulated_models(CFG)
SHARDS = {m: pipeline.shard_designs(CFG, m) for m in SIMULATED}
LEARNER_SHARDS = learner_experiment.shards(CFG) if CFG["learners"]["enabled"] else []


# Results this config did not make that Snakemake has no record of (copied in, or .snakemake
# metadata cleaned) would count as done until the merge refuses them: stop now. Main process only:
# cluster jobs re-parse this file and must not re-read the shards. Not for `--unlock`, which only
# clears a lock (Snakemake gives the Snakefile no other way to tell that mode than its arguments).
if not CFG["render_only"] and workflow.is_main_process and "--unlock" not in sys.argv:
    for _m in SIMULATED:
        _stale = results_check.unrecorded_stale(
            R, _m, pipeline.science(CFG, _m), SHARDS[_m]
        )
        if _stale:
            print(
                f"morphlearn: {_stale} was made by another science config or shard count and "
                f"Snakemake has no record of it (.snakemake metadata), so it would count as done; "
                f"allowed: this config's own results_dir, or delete {R}/{_m}/shards and "
                f"{R}/{_m}/merged.zarr (finished designs in {R}/{_m}/designs are reused)",
                file=sys.stderr,
            )
            sys.exit(2)


def shard_ids(model):
    return range(len(SHARDS[model]))


def shard_params(model):
    """Rerun triggers: a shard depends on the science subset and on the designs it holds."""
    return lambda w: {
        "science": cfgmod.digest(pipeline.science(CFG, model)),
        "designs": cfgmod.digest(SHARDS[model][int(w.shard)].tolist()),
    }


# Figures need the theory results; render_only re-renders them from stored results alone.
RENDER_ONLY = CFG["render_only"]
FIGURE_SPECS = figure_registry.FIGURES
FIGURES = (
    pipeline.figures(CFG) if CFG["figures"]["enabled"] and "theory" in MODELS else []
)
# Once per start: the options read the body file, and both a figure's inputs and params use them.
FIGURE_OPTIONS = {fig: pipeline.figure_options(CFG, fig) for fig in FIGURES}
FIGURE_TARGETS = [
    *(f"{R}/figures/{fig}.{ext}" for fig in FIGURES for ext in ("png", "pdf", "html")),
    *([f"{R}/reproduction.md"] if FIGURES else []),
]
ALL_TARGETS = FIGURE_TARGETS + (
    []
    if RENDER_ONLY
    else [
        *(f"{R}/{m}/metrics.csv" for m in MODELS),
        f"{R}/summary.md",
        *([f"{R}/learners/summary.md"] if CFG["learners"]["enabled"] else []),
    ]
)


def figure_data(fig):
    """Results a figure reads (registry), empirical only when that model is enabled."""
    models = [
        m
        for m in FIGURE_SPECS[fig].reads
        if m != "empirical" or FIGURE_OPTIONS[fig]["empirical_enabled"]
    ]
    return [
        f"{R}/{m}/{name}" for m in models for name in ("metrics.csv", "merged.zarr")
    ] + [f"{R}/{f}" for f in FIGURE_SPECS[fig].files]


# render_only: refuse to start, by name, when a stored result is missing or fails its digests.
if RENDER_ONLY and FIGURES:
    try:
        pipeline.check_render_inputs(
            [f"{R}/{m}/{n}" for m in MODELS for n in ("metrics.csv", "merged.zarr")]
        )
    except ValueError as err:
        print(f"morphlearn: render_only: {err}", file=sys.stderr)
        sys.exit(2)


def figure_modules(fig):
    """Every package module the figure's notebook imports, directly or through other package
    modules: editing any of them re-renders the figure (and no other code does)."""
    return figure_registry.notebook_modules(figure_registry.notebook_path(fig), "src")


def figure_parameters(fig):
    """The notebook's parameters (papermill -y), as YAML that PyYAML reads back exactly."""
    return lambda w, input, output: yaml.safe_dump(
        {
            "results_dir": str(Path(output.png).parents[1]),
            "png": output.png,
            "pdf": output.pdf,
            "caption": output.caption,
            "style": input.style,
            **FIGURE_OPTIONS[fig],
        },
        default_flow_style=True,
        width=10**6,
    ).strip()
