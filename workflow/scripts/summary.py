"""Rule summary: canonical design and top designs, JSON + Markdown."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(snakemake.scriptdir)))  # noqa: F821
from _entry import setup

cfg = setup(snakemake)  # noqa: F821
from morphlearn import pipeline  # noqa: E402

tables = dict(snakemake.input.items())  # noqa: F821
pipeline.run_summary(cfg, tables, snakemake.output.json, snakemake.output.md)  # noqa: F821
