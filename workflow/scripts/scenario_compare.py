"""Rule scenario_compare: every scenario against the base, and the text-value threshold scan."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(snakemake.scriptdir)))  # noqa: F821
from _entry import setup

setup(snakemake)  # noqa: F821
from morphlearn import scenarios  # noqa: E402

smk = snakemake  # noqa: F821
tables = dict(zip(smk.params.names, smk.input.tables, strict=True))
merged = dict(zip(smk.params.sims, smk.input.merged, strict=True))
out = smk.output
scenarios.run_compare(tables, merged, smk.params.top, out.csv, out.md, out.scan, smk.params.plan, out.provenance)
