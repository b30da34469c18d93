# Config validation (one-line error, exit 2, nothing written) and shared helpers.
import json
import os
import sys
from pathlib import Path

import yaml

from morphlearn import configure
from morphlearn import config as cfgmod
from morphlearn.analysis import engines as engine_compare
from morphlearn.bundles import make as bundlemod
from morphlearn import models, provenance, settings
from morphlearn.workflow import results_check, rules, runs
from morphlearn.learners import experiment as learner_experiment
from morphlearn.coopt import stage as coopt_stage
from morphlearn.figures import options as figure_options
from morphlearn.figures import registry as figure_registry

# The config, parsed once into typed settings: everything below reads S, never the raw dict.
# results_dir is checked again with the config files given (the write guard): a render_only run
# re-renders a bundle only with the configs its bundle.json records (issue 57).
try:
    S = configure.parse(config)
    RUN = runs.run(S)
    cfgmod.check_results_dir(
        S.results_dir, S.render_only, [os.path.relpath(f) for f in workflow.configfiles]
    )
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

R = S.results_dir
MODELS = models.enabled(S)
SIMULATED = models.simulated(S)
# the {model} wildcard of the rules that merge and score simulated results; "(?!)" matches
# nothing (an empty constraint would be none at all, and every model read from a bundle would
# then be tried against them: the InputFunctionException noise of a run that simulates nothing)
SIMULATED_MODEL = "|".join(SIMULATED) or "(?!)"
# each simulated model's shards and science, once per start
SHARDS = {m: models.get(m).shard_designs(S) for m in SIMULATED}
SCIENCE = {m: models.get(m).science(S) for m in SIMULATED}
LEARNER_SHARDS = learner_experiment.shards(S) if S.learners.enabled else []


# Results this config did not make that Snakemake has no record of (copied in, or .snakemake
# metadata cleaned) would count as done until the merge refuses them: stop now. Main process only:
# cluster jobs re-parse this file and must not re-read the shards. Not for `--unlock`, which only
# clears a lock (Snakemake gives the Snakefile no other way to tell that mode than its arguments).
if not S.render_only and workflow.is_main_process and "--unlock" not in sys.argv:
    for _m in SIMULATED:
        # (a results bundle is no results_dir but to re-render it: config._check_results_dir)
        _stale = results_check.unrecorded_stale(R, _m, SCIENCE[_m], SHARDS[_m])
        if _stale:
            print(
                f"morphlearn: {_stale} was made by another science config or shard count and "
                f"Snakemake has no record of it (.snakemake metadata), so it would count as done; "
                f"allowed: this config's own results_dir, or delete {R}/{_m}/shards and "
                f"{R}/{_m}/merged.zarr (finished designs in {R}/{_m}/designs are reused)",
                file=sys.stderr,
            )
            sys.exit(2)


def custody_at_start(tables, derived=()):
    """Custody: a metrics table (``tables``) or a derived file with a record (``derived``) edited
    or damaged since its rule wrote it stops the run here, before anything is written (what reads
    it would follow the edit); every stage calls it for the files it reads."""
    if S.render_only or not workflow.is_main_process or "--unlock" in sys.argv:
        return
    try:
        rules.check_custody(tables, derived)
    except provenance.CustodyError as err:
        print(f"morphlearn: {err}; nothing was run", file=sys.stderr)
        sys.exit(2)


custody_at_start(
    [f"{R}/{m}/metrics.csv" for m in MODELS],
    [f"{R}/summary.json", f"{R}/reproduction.csv"],
)


def shard_ids(model):
    return range(len(SHARDS[model]))


def shard_params(model):
    """Rerun triggers: a shard depends on the science subset and on the designs it holds."""
    return lambda w: {
        "science": cfgmod.digest(SCIENCE[model]),
        "designs": cfgmod.digest(SHARDS[model][int(w.shard)].tolist()),
    }


# The largest physics survey, read from its bundle (survey_from): Fig. 7 C-D and the survey rows.
SURVEY_FILES = (
    [f"{R}/{S.survey.folder}/{n}" for n in ("metrics.csv", "merged.zarr")]
    if S.survey.bundle
    else []
)
# Figures need the theory results; render_only re-renders them from stored results alone.
RENDER_ONLY = S.render_only
# render_only reads the stored persistence table (its trajectories are a simulation: ~60 CPU-s
# at paper resolution) instead of integrating them again, as it reads every other stored result
# (a changed figures.near_distance or persistence_controllers needs a full run); a folder without
# one makes it.
STORED_PERSISTENCE = RENDER_ONLY and Path(f"{R}/persistence.csv").is_file()
FIGURES = figure_options.figures(S)
# Once per start: both a figure's inputs and its params use them.
FIGURE_OPTIONS = {fig: figure_options.figure_options(S, fig) for fig in FIGURES}
FIGURE_TARGETS = [
    *(f"{R}/figures/{fig}.{ext}" for fig in FIGURES for ext in runs.FIGURE_EXTENSIONS),
    # the reproduction table compares with the theory: not in a physics-only run
    *([f"{R}/reproduction.md"] if FIGURES and models.REFERENCE in MODELS else []),
]
# The targets of all: a stage's figures alone (scenarios.smk adds its comparison), or the
# paper's workflow's figures and tables (coopt.smk adds its bundle).
ALL_TARGETS = (
    RUN.figure_targets(R)
    if RUN.figures is not None
    else FIGURE_TARGETS
    + (
        []
        if RENDER_ONLY
        else [
            *(f"{R}/{m}/metrics.csv" for m in MODELS),
            *SURVEY_FILES[:1],
            f"{R}/summary.md",
            *([f"{R}/learners/summary.md"] if S.learners.enabled else []),
            *([f"{R}/coopt/summary.md"] if S.coopt.enabled else []),
        ]
    )
)


def figure_data(fig):
    """Results a figure reads (registry), of the models enabled."""
    return (
        [
            f"{R}/{m}/{name}"
            for m in figure_options.data_models(S, fig)
            for name in ("metrics.csv", "merged.zarr")
        ]
        + [f"{R}/{f}" for f in figure_registry.FIGURES[fig].files]
        + (SURVEY_FILES if figure_registry.FIGURES[fig].survey else [])
    )


# The engine comparison (config/engines.yaml): the committed tables it reads; when enabled the run
# makes (or, render_only, re-renders) only its figures, from its own stored outputs.
ENGINES = S.engines
# The agreement stage (config/agreement.yaml): likewise, the committed surveys it reads.
AGREEMENT = S.agreement

# render_only: refuse to start, by name, when a stored result is missing or fails its digests.
if RENDER_ONLY and FIGURES and RUN.kind == "paper":
    try:
        rules.check_render_inputs(
            [f"{R}/{m}/{n}" for m in MODELS for n in ("metrics.csv", "merged.zarr")]
            + SURVEY_FILES
        )
        if STORED_PERSISTENCE:
            rules.check_stored_persistence(f"{R}/persistence.csv")
    except ValueError as err:
        print(f"morphlearn: render_only: {err}", file=sys.stderr)
        sys.exit(2)


def figure_modules(fig):
    """Every package module the figure's notebook imports, directly or through other package
    modules, or by a name its options give (Fig. 1C's body, which its engine supplies): editing
    any of them re-renders the figure (and no other code does)."""
    named = figure_options.imported_modules(FIGURE_OPTIONS[fig])
    return sorted(
        {
            *figure_registry.notebook_modules(
                figure_registry.notebook_path(fig), "src"
            ),
            *figure_registry.named_modules(named, "src"),
        }
    )


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
        # in the order given: the notebooks draw the first physics model of `physics` (the
        # paper's engine first), which sorted keys would turn into the alphabetical first
        sort_keys=False,
    ).strip()


onstart:
    # Snakemake leaves the empty folders of its update() backups behind; a bundle run after a
    # render-only run of that bundle would stop on them (rules.prune_empty_backups)
    rules.prune_empty_backups(Path(workflow.persistence.path) / "backups")
