"""Rule scenario_summary: a scenario's canonical design and top designs (summary.run_summary)."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(snakemake.scriptdir)))  # noqa: F821
from _entry import setup

smk = snakemake  # noqa: F821
s = setup(smk, smk.params.cfg)
from morphlearn.analysis import summary  # noqa: E402

summary.run_summary(s, dict(smk.input.items()), smk.output.json, smk.output.md, smk.output.provenance)
