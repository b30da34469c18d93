# morphlearn: sensor placement vs controller learnability (see README.md).
import sys

from snakemake.utils import min_version

# The package lives in src/; the workflow runs from a clone without installing it.
sys.path.insert(0, f"{workflow.basedir}/src")

min_version("9.0")


configfile: "config.yaml"


report: "workflow/report/workflow.rst"


include: "workflow/rules/common.smk"


# scenarios: named variants of this config instead of the main workflow (docs/scenarios.md).
if S.scenarios is not None:

    include: "workflow/rules/scenarios.smk"

    ALL_TARGETS = SCENARIO_TARGETS


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
