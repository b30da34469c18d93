"""Rule bundle: the compact, checksummed record of this run's results."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(snakemake.scriptdir)))  # noqa: F821
from _entry import setup

cfg = setup(snakemake)  # noqa: F821
from morphlearn import bundle  # noqa: E402

p = snakemake.params  # noqa: F821
bundle.build(p.results, snakemake.output[0], positions_per_axis=p.positions, top=p.top,  # noqa: F821
             made_by=bundle.made_by(list(p.configs), p.results))  # fmt: skip
