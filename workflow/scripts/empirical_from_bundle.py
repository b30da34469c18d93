"""Rule empirical_from_bundle: a committed bundle's empirical results, checked and copied."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(snakemake.scriptdir)))  # noqa: F821
from _entry import setup

cfg = setup(snakemake)  # noqa: F821
from morphlearn import bundle  # noqa: E402

out = snakemake.output  # noqa: F821
src = Path(snakemake.input[0]).parent  # noqa: F821  (the input is the bundle's bundle.json)
bundle.extract_model(src, "empirical", {"metrics": out.metrics, "provenance": out.provenance, "merged": out.merged})
print(f"empirical results from {src} (checksums verified)")
