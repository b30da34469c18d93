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


# What this run makes: the paper's workflow, or one stage instead of it (morphlearn.workflow.runs).
for _rules in RUN.rule_files:

    include: _rules


rule all:
    default_target: True
    input:
        ALL_TARGETS,
