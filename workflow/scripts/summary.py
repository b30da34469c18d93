"""Rule summary: canonical design and top designs, JSON + Markdown."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(snakemake.scriptdir)))  # noqa: F821
from _entry import setup

s = setup(snakemake)  # noqa: F821
from morphlearn.analysis import summary  # noqa: E402

tables = dict(snakemake.input.items())  # noqa: F821
out = snakemake.output  # noqa: F821
summary.run_summary(s, tables, out.json, out.md, out.provenance)
