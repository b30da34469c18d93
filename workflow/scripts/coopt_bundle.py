"""Rule coopt_bundle: the coopt stage's committed bundle (results/coopt with config/coopt.yaml).

Settings: ``coopt.bundle_dir`` (the folder), the config files given (the command recorded).
Inputs: the stage's tables (rule coopt_analysis: runs, summary, landscape, position map, summary.md,
the restart runs and their summary when on) and the figure's png, pdf and caption (rule
figure_coopt). Outputs: those files in the bundle folder and ``bundle.json`` (every file's SHA-256,
a README already there included; the command, commit and library versions), which
``morphlearn check-bundle`` reads.
"""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(snakemake.scriptdir)))  # noqa: F821
from _entry import setup

s = setup(snakemake)  # noqa: F821
from morphlearn.coopt import bundle  # noqa: E402

bundle.build(
    list(snakemake.input.tables),  # noqa: F821
    list(snakemake.input.figure),  # noqa: F821
    Path(snakemake.output.manifest).parent,  # noqa: F821
    list(snakemake.params.configs),  # noqa: F821
)
