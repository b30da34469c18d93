"""Rule scenario_summary: a scenario's canonical design and top designs (pipeline.run_summary)."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(snakemake.scriptdir)))  # noqa: F821
from _entry import setup

setup(snakemake)  # noqa: F821
from morphlearn import config as cfgmod  # noqa: E402
from morphlearn import pipeline  # noqa: E402

smk = snakemake  # noqa: F821
pipeline.run_summary(cfgmod.validate(dict(smk.params.cfg)), dict(smk.input.items()), smk.output.json, smk.output.md)
