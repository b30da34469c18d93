"""Rule bundle: the compact, checksummed record of this run's results."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(snakemake.scriptdir)))  # noqa: F821
from _entry import setup

setup(snakemake)  # noqa: F821
from morphlearn import bundle  # noqa: E402

p = snakemake.params  # noqa: F821
bundle.build(p.results, snakemake.output[0], top=p.top, made_by=bundle.made_by(list(p.configs), p.results))  # noqa: F821
