# morphlearn: sensor placement vs controller learnability (see README.md).
import sys

from snakemake.utils import min_version

# The package lives in src/; the workflow runs from a clone without installing it.
sys.path.insert(0, f"{workflow.basedir}/src")

from morphlearn.workflow import blas_kernel

# One BLAS kernel for every rule, notebook and job: the reference trajectories' last digits
# depend on it (src/morphlearn/workflow/blas_kernel.py).
blas_kernel.pin()

min_version("9.0")

# Refused at start (one line, exit 2): a run from another folder, a config file that is not a YAML
# mapping with each key once (Snakemake keeps the last of two equal keys silently).
from morphlearn import config as cfgmod

try:
    cfgmod.check_start(workflow.basedir, [*workflow.configfiles, "config.yaml"])
except cfgmod.ConfigError as err:
    print(f"morphlearn: config error: {err}", file=sys.stderr)
    sys.exit(2)


configfile: "config.yaml"


report: "workflow/report/workflow.rst"


include: "workflow/rules/common.smk"


# The engine comparison's figures (config/engines.yaml; ENGINES: common.smk).
ENGINE_TARGETS = [
    f"{R}/figures/{fig}.{ext}"
    for fig in ("engines", "disagreement")
    for ext in ("png", "pdf", "html")
]


# scenarios: named variants of this config instead of the main workflow (docs/scenarios.md).
if S.scenarios is not None:

    include: "workflow/rules/scenarios.smk"

    ALL_TARGETS = SCENARIO_TARGETS


# agreement: each engine and robot against ODE only (render_only: its figure from the stored outputs).
elif AGREEMENT.enabled:
    if not RENDER_ONLY:

        include: "workflow/rules/agreement.smk"

    ALL_TARGETS = [f"{R}/figures/agreement.{ext}" for ext in ("png", "pdf", "html")]


# engines: the engine comparison only (render_only: its figures from the stored outputs).
elif ENGINES.enabled:
    if not RENDER_ONLY:

        include: "workflow/rules/engines.smk"

    ALL_TARGETS = ENGINE_TARGETS


# render_only: no rule that simulates, merges or computes metrics exists.
elif not RENDER_ONLY:

    include: "workflow/rules/simulate.smk"
    include: "workflow/rules/empirical.smk"
    include: "workflow/rules/analysis.smk"

    if S.learners.enabled:

        include: "workflow/rules/learners.smk"

    if S.coopt.enabled:

        include: "workflow/rules/coopt.smk"

    if S.bundle_dir:

        include: "workflow/rules/bundle.smk"


if S.scenarios is None:

    include: "workflow/rules/figures.smk"


rule all:
    default_target: True
    input:
        ALL_TARGETS,
