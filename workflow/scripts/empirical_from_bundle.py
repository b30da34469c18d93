"""Rule empirical_from_bundle: a committed bundle's empirical results, checked and copied."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(snakemake.scriptdir)))  # noqa: F821
from _entry import setup

cfg = setup(snakemake)  # noqa: F821
from morphlearn import bundle  # noqa: E402

out = snakemake.output  # noqa: F821
bundle.extract_model(snakemake.params.bundle, "empirical",  # noqa: F821
                     {"metrics": out.metrics, "provenance": out.provenance, "merged": out.merged})  # fmt: skip
print(f"empirical results from {snakemake.params.bundle} (checksums verified)")  # noqa: F821
