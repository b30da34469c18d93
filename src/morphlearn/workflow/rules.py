"""What the simulate / merge / metrics rules do, for any registered model: the rule scripts
(``workflow/scripts``) parse the settings and call these."""

from __future__ import annotations

import json
from collections import Counter
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from morphlearn import metrics, models, provenance, store
from morphlearn.bundles import check as bundle_check
from morphlearn.bundles import make as bundle
from morphlearn.bundles.make import MANIFEST
from morphlearn.physics import design_cache
from morphlearn.results import DesignResult
from morphlearn.settings import Settings


def run_shard(s: Settings, model: str, shard: int, out: str | Path) -> None:
    """Evaluate one shard; with ``design_cache`` (default) reuse the designs already finished under
    the same science (design_cache) and save each new one as soon as it is done."""
    m = models.get(model)
    g = s.grid.designs
    designs = m.shard_designs(s)[shard]
    sci = m.science(s)
    w = m.weights(s)
    prov = provenance.record(sci, libraries=m.libraries) | m.backend(s)
    results: dict[int, DesignResult] = {}
    made_at: dict[int, str] = {}  # a reused design's commit (the design cache's record of it)
    folder = design_cache.cache_dir(s.results_dir, model, sci) if s.design_cache else None
    if folder:
        legacy = design_cache.legacy_dir(s.results_dir, model, sci)
        results = design_cache.load(folder, designs, model=model, science=sci, m=len(w), legacy=legacy, commits=made_at)
    todo = np.array([d for d in designs if int(d) not in results], dtype=np.int64)
    print(
        f"shard {shard}: {len(designs)} designs, reused {len(results)}, to compute {len(todo)}"
        + (f" (design cache {folder})" if folder else ""),
        flush=True,
    )

    def finished(i: int, r: DesignResult) -> None:
        results[int(todo[i])] = r
        if folder:
            design_cache.save(folder, int(todo[i]), r, model=model, grid=g, weights=w, science=sci, provenance=prov)
        print(f"shard {shard}: design {int(todo[i])} computed ({i + 1}/{len(todo)})", flush=True)

    if len(todo):
        # a running design keeps its episodes beside the finished ones, in the same cache
        partial = (lambda d: design_cache.partial_path(folder, d)) if folder else None
        m.evaluate(s, todo, done=finished, partial=partial)
    # the code of every design the shard holds: the commit that computed it (reused designs keep
    # theirs), so a shard assembled now from designs of earlier code claims no commit for them
    here = prov["git_commit"]
    prov["design_commits"] = dict(sorted(Counter(made_at.get(int(d), here) for d in designs).items()))
    store.write_shard(
        out,
        model=model,
        grid=g,
        weights=w,
        designs=designs,
        results=[results[int(d)] for d in designs],
        science=sci,
        provenance=prov,
    )


def run_merge(s: Settings, model: str, shards: list[str], out: str | Path) -> None:
    m = models.get(model)
    sci = m.science(s)
    store.merge_shards(
        shards,
        out,
        model=model,
        grid=s.grid.designs,
        weights=m.weights(s),
        shard_designs=m.shard_designs(s),
        science=sci,
        mirror=m.mirror_derived(s),
        provenance=provenance.record(sci, shards, m.libraries),
    )


def run_metrics(model: str, th: metrics.Thresholds, merged: str | Path, out_csv: str | Path) -> None:
    """The metrics table of a merged store at thresholds ``th`` (a model's, or a scenario's)."""
    ds = store.open_merged(merged)
    table = metrics.metrics_table(ds, th)  # verifies every chunk before anything is written
    subset = {"thresholds": th.__dict__, "model": model, "merged_sha256_overall": ds.attrs["integrity"]["overall"]}
    write_csv_with_provenance(table, out_csv, subset, [merged], models.get(model).libraries)


def write_csv_with_provenance(
    table: pd.DataFrame, out_csv: str | Path, subset: dict[str, Any], inputs: list, libraries: Sequence[str] = ()
) -> None:
    out_csv = Path(out_csv)
    with store.atomic_path(out_csv) as tmp:
        table.to_csv(tmp, index=False, float_format=metrics.CSV_FLOAT_FORMAT)
    # sealed: the table's digest and the record's own, checked by every reader (custody)
    prov = provenance.seal(provenance.record(subset, inputs, libraries), [out_csv])
    with store.atomic_path(provenance.sidecar_of(out_csv)) as tmp:
        tmp.write_text(json.dumps(prov, indent=1, sort_keys=True) + "\n")


def check_render_inputs(paths: list[str]) -> None:
    """Render-only starts only from complete, untouched results (raises a ValueError naming the
    first problem). A bundle (``bundle.json`` beside the results) is checked against its manifest,
    file by file, chunks included, and row by row; other results: every file present, every
    table against its provenance record and store, every chunk of every merged store against its
    digest."""
    for p in sorted(paths):
        if not Path(p).exists():
            raise store.IntegrityError(f"{p}: missing (render_only re-renders from stored results)")
    bundles = {r for r in {Path(p).parent.parent for p in paths} if (r / bundle.MANIFEST).is_file()}
    for root in sorted(bundles):
        problems = bundle_check.check(root)
        if problems:
            raise bundle.BundleError(
                f"{root} does not match its {bundle.MANIFEST} ({len(problems)} problem(s)); nothing was "
                "rendered:\n  " + "\n  ".join(problems[:10]) + ("\n  ..." if len(problems) > 10 else "")
            )
    for p in sorted(paths):
        if p.endswith(".zarr"):
            if Path(p).parent.parent not in bundles:  # a bundle's chunks: checked by their digests above
                store.verify_merged(p)
        else:
            provenance.check_derived(p, store.open_merged(Path(p).with_name("merged.zarr")))


def prune_empty_backups(root: str | Path) -> list[Path]:
    """Remove the empty folders under Snakemake's backup folder (``.snakemake/backups``); the ones
    removed. Snakemake 9 (snakemake PRs 3833, 3839) copies an ``update()`` output there before its
    job and deletes the copy after, but not the folders it made for it, so a later job whose output
    is a folder at such a path (the bundle after a render-only run of it: ``results/paper``) fails
    with FileExistsError. An empty folder holds no backup; anything else is left alone."""
    root = Path(root)
    if not root.is_dir():
        return []
    removed = []
    # deepest first, so a folder whose only content was empty folders goes too
    for d in sorted((p for p in root.rglob("*") if p.is_dir()), key=lambda p: len(p.parts), reverse=True):
        if not any(d.iterdir()):
            d.rmdir()
            removed.append(d)
    return removed


def check_stored_persistence(path: str | Path) -> None:
    """render_only reads a stored persistence table instead of integrating its trajectories
    again: it must be the one the reproduction record beside it sealed (CustodyError naming it).

    A bundle made before that record existed (``results/survey``, bundled at 1f12008) has none;
    there its ``bundle.json`` vouches for the table, as it does for a bundle's older unsealed
    metrics records (:func:`provenance.check_derived`). A record present is always checked."""
    from morphlearn.figures.reproduction.record import RECORD

    path = Path(path)
    record = path.with_name(RECORD)
    if not record.is_file() and (path.parent / MANIFEST).is_file():
        provenance.check_listed(path.parent, [(path, provenance.sha256_file(path))])
        return
    provenance.check_derived(path, record=record)


def check_custody(tables: list[str | Path], derived: list[str | Path] = ()) -> None:
    """At the start of a run: every metrics table already there is the one its rule wrote
    (provenance.CustodyError naming the first edited or damaged one), so no edit flows into the
    summary, the table, a figure or a bundle; so is every file of ``derived`` (the summary, the
    reproduction table) that has a record."""
    for p in tables:
        if Path(p).is_file():
            provenance.check_derived(p)
    for p in derived:
        if Path(p).is_file() and provenance.sidecar_of(p).is_file():
            provenance.check_derived(p)
