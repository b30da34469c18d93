"""Rule bundle: the compact, checksummed record of this run's results."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(snakemake.scriptdir)))  # noqa: F821
from _entry import setup

S = setup(snakemake)  # noqa: F821
from morphlearn import models  # noqa: E402
from morphlearn.bundles import make as bundle  # noqa: E402

p = snakemake.params  # noqa: F821
made_by = bundle.made_by(list(p.configs), p.results)
bundle.check_target(snakemake.output[0], made_by)  # noqa: F821  (also checked at the start)
bundle.check_committed(made_by, p.results, models.simulated(S))
bundle.build(p.results, snakemake.output[0], top=p.top, made_by=made_by, designs_kept=p.designs_kept)  # noqa: F821
