"""Rule <model>_from_bundle: a committed bundle's results of one model, checked and copied."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(snakemake.scriptdir)))  # noqa: F821
from _entry import setup

setup(snakemake)  # noqa: F821
from morphlearn.bundles import check as bundle_check  # noqa: E402

out = snakemake.output  # noqa: F821
model = snakemake.params.model  # noqa: F821
src = Path(snakemake.input[0]).parent  # noqa: F821  (the input is the bundle's bundle.json)
bundle_check.extract_model(src, model, {"metrics": out.metrics, "provenance": out.provenance, "merged": out.merged})
print(f"{model} results from {src} (checksums verified)")
