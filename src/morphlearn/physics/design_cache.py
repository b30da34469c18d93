"""Per-design cache: finished designs survive re-sharding and killed shard jobs.

Each shard job writes every design it finishes as a one-design file in the shard schema
(:func:`store.write_shard`) under ``{results_dir}/{model}/designs/{science_sha256[:16]}/``. Snakemake
does not own these files, so they outlive a shard's rerun: a shard job first reuses every design
found there whose science digest and data checksum check out (:func:`store.verify_shard`), computes
the rest, and assembles its shard file from both. Changing the shard count then recomputes
nothing, and a killed shard resumes from its last finished design (empirical) or batch of designs
(theory: the kernel's batches, ~6 designs at paper resolution). A physics engine whose designs
resume inside themselves (``resumes_inside_design``) keeps a running design's episodes here too
(:func:`partial_path`, :mod:`morphlearn.physics.partial`), removed when the design is saved: this
module owns both kinds of file; the shard job (``rules.run_shard``) hands a model its designs' paths.

Disk: the cache holds the same arrays as the shards (theory at paper resolution ~1.8 GB more);
``design_cache: false`` in the config turns it off.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np

from morphlearn import config as cfgmod
from morphlearn import store
from morphlearn.grid import DesignGrid
from morphlearn.results import DesignResult


def design_science(science: dict[str, Any]) -> dict[str, Any]:
    """What one design's outcomes depend on: the run's science without the list of designs it holds
    (a physics run's ``designs``), so that adding designs to a run reuses those already done."""
    return {k: v for k, v in science.items() if k != "designs"}


def cache_dir(results_dir: str | Path, model: str, science: dict[str, Any]) -> Path:
    """Folder of one science config's designs (the digest prefix keeps configs apart)."""
    return Path(results_dir) / model / "designs" / cfgmod.digest(design_science(science))[:16]


def legacy_dir(results_dir: str | Path, model: str, science: dict[str, Any]) -> Path | None:
    """Where designs were kept before the folder was keyed without the design list (the digest of
    the whole science), when that differs: still read, never written."""
    if "designs" not in science:
        return None
    return Path(results_dir) / model / "designs" / cfgmod.digest(science)[:16]


def design_path(folder: Path, design: int) -> Path:
    return folder / f"design_{int(design)}.nc"


def partial_path(folder: Path, design: int) -> Path:
    """Where a running design keeps its finished episodes (:mod:`morphlearn.physics.partial`):
    the shard job hands it to the model (``Model.evaluate``'s ``partial``); :func:`save` removes it."""
    return folder / f"design_{int(design)}.partial.npz"


def load(
    folder: Path,
    designs: np.ndarray,
    *,
    model: str,
    science: dict[str, Any],
    m: int,
    legacy: Path | None = None,
    commits: dict[int, str] | None = None,
) -> dict[int, DesignResult]:
    """The designs of ``designs`` already in ``folder`` (else in ``legacy``, see :func:`legacy_dir`)
    that verify; damaged or foreign ones are reported and left to be recomputed (their file is
    overwritten then). ``commits``, when given, receives the commit each reused design was made at
    (its file's record), so a shard names the code of every design it holds."""
    found: dict[int, DesignResult] = {}
    places = [(folder, design_science(science)), *([(legacy, science)] if legacy else [])]
    for d in designs:
        for where, sci in places:
            p = design_path(where, d)
            if not p.is_file():
                continue
            try:
                sh = store.read_shard(p)
                store.verify_shard(sh, model=model, science=sci, designs=np.array([int(d)]), m=m)
            except store.ShardError as e:
                print(f"design cache: not reused: {e}", flush=True)
                continue
            found[int(d)] = DesignResult(*(sh.arrays[k][0] for k in store.VARS))
            if commits is not None:
                commits[int(d)] = json.loads(sh.attrs.get("provenance_json", "{}")).get("git_commit", "unknown")
            partial_path(folder, d).unlink(missing_ok=True)  # left by a kill between save and removal
            break
    return found


def save(
    folder: Path,
    design: int,
    result: DesignResult,
    *,
    model: str,
    grid: DesignGrid,
    weights: np.ndarray,
    science: dict[str, Any],
    provenance: dict[str, Any],
) -> None:
    """Write one finished design (atomically, in the shard schema) and remove its partial file
    (:func:`partial_path`), no longer needed: the cache is the one owner of both."""
    store.write_shard(
        design_path(folder, design),
        model=model,
        grid=grid,
        weights=weights,
        designs=np.array([int(design)]),
        results=[result],
        science=design_science(science),
        provenance=provenance,
    )
    partial_path(folder, design).unlink(missing_ok=True)
