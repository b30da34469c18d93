"""The table's sealed record of its inputs and outputs (custody)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from morphlearn import provenance, store

#: The table's sealed record of its inputs and outputs.
RECORD = "reproduction.provenance.json"


def write_record(
    results_dir: str | Path,
    models: list[str],
    outputs: list[str | Path],
    extra: list[str | Path],
    outside: Sequence[str | Path] = (),
) -> None:
    """The table's sealed provenance record (``reproduction.provenance.json``): the digests of the
    metrics tables it read, of the merged stores (their recorded overall digest: hashing a
    3.5 GB store costs minutes) and of its own files. ``outside``: tables it read from committed
    bundles where they are (the screen's), by their path from the repository root."""
    r = Path(results_dir)
    # paths relative to the results folder and no commit: a bundle re-rendered anywhere, at any
    # commit, gives the same bytes (as its captions do)
    rec = {
        "inputs": {
            str(Path(p).relative_to(r)): provenance.sha256_file(p)
            for p in [*(r / m / "metrics.csv" for m in models), *extra]
        },
        **({"bundles_read": {str(p): provenance.sha256_file(p) for p in outside}} if outside else {}),
        # the full dataset's digest: the same for a run's store and for its bundle's subset
        "merged_stores": {
            f"{m}/merged.zarr": provenance.merged_source(store.open_merged(r / m / "merged.zarr")) for m in models
        },
    }
    provenance.write_sealed(Path(outputs[0]).with_name(RECORD), rec, outputs)
