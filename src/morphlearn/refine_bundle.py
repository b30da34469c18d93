"""A results bundle made of complete ``tools/refine_design.py`` folders (one design each).

The physics designs the paper bundle shows at 121 x 121 controllers are simulated one by one with
the resumable runner (:mod:`morphlearn.resumable`): hours of one core each in pybullet,
outside the workflow. :func:`build` turns one or more COMPLETE folders of one engine, weight grid,
body and levers into the bundle a workflow run reads with ``<model>.results_from`` (``empirical``
for pybullet, ``mujoco`` for MuJoCo) on the design grid of :data:`POSITIONS` positions per axis:

- ``<model>/merged.zarr``: written the workflow's way, one shard per folder
  (:func:`morphlearn.store.write_shard`) merged by :func:`morphlearn.store.merge_shards`, with a
  science record that says what was run (the model's keys, so ``describe`` and ``positions_of``
  read it as a run's, and under ``refine`` the engine's identity, the body file's SHA-256 and
  each folder's run key);
- ``<model>/metrics.csv`` and its sealed provenance record (:func:`morphlearn.metrics.metrics_table`),
  checked against each folder's own metrics (:func:`resumable.summary`) before anything is kept;
- ``bundle.json`` (the manifest :func:`morphlearn.bundle_check.check` verifies) and ``README.md``.

The bundle is written beside its destination and swapped in whole (never half-written); a
destination that holds anything but an earlier refine bundle of the same model is refused.
"""

from __future__ import annotations

import json
import shlex
import tempfile
from collections import Counter
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from morphlearn import __version__, bounded, metrics, models, provenance, store
from morphlearn import resumable as rz
from morphlearn.bundle import MANIFEST, bundle_files
from morphlearn.config import RESULTS_ALLOWED, place_refusal
from morphlearn.grid import DesignGrid

#: The design grid the bundles are on (the paper's: 9 positions per axis, 6561 designs).
POSITIONS = 9
#: The registered model whose results a folder's engine makes.
MODEL_OF_ENGINE = {models.get(n).engine: n for n in models.physics()}
#: ``made_by.tool`` of these bundles: an out folder holding one (same model) may be replaced.
TOOL = "tools/refine_design.py bundle"


@dataclass(frozen=True)
class Source:
    """One complete refine folder: its rows, its job and its index on the design grid."""

    folder: Path
    asm: rz.Assembled
    job: rz.Job
    design: int

    @property
    def manifest(self) -> dict[str, Any]:
        return self.asm.manifest


def settings_of(man: dict[str, Any]) -> dict[str, Any]:
    """What must agree between the folders of one bundle: the run identity without the design
    (engine and its version and settings, weights, body parameters, levers, format) and the body
    file's digest."""
    ident = {k: v for k, v in man["identity"].items() if k != "design"}
    return {**ident, "body_file_sha256": man.get("body_file_sha256")}


def load_sources(folders: list[Path], positions: int = POSITIONS) -> list[Source]:
    """Every folder assembled and verified; RefineError (exit 2) naming the first folder that is
    incomplete or damaged, off the design grid, a repeat of a design, or made with other settings
    than the first folder."""
    if not folders:
        raise rz.RefineError("no refine folders given; allowed: one or more complete refine_design folders")
    grid = DesignGrid(positions)
    out: list[Source] = []
    ref: dict[str, Any] | None = None
    for folder in folders:
        damaged: list[str] = []
        asm = rz.assemble(folder, log=damaged.append)
        if not asm.complete:
            n, m = int(asm.rows_done.sum()), len(asm.rows_done)
            why = f"; damaged: {damaged[0]}" if damaged else ""
            raise rz.RefineError(
                f"{folder}: {n} of {m} rows verified{why}; allowed: complete folders only "
                "(finish it with morphlearn.resumable.run)"
            )
        job = rz.job_from_manifest(asm.manifest)
        try:
            design = grid.index_of(job.l1, job.l2)
        except ValueError as e:
            raise rz.RefineError(
                f"{folder}: design l1={list(job.l1)} l2={list(job.l2)} is not on the {positions}-position "
                f"design grid ({e}); allowed: a design of grid.positions_per_axis = {positions}"
            ) from None
        here = settings_of(asm.manifest)
        if ref is None:
            ref = here
        else:
            diff = sorted(k for k in ref.keys() | here.keys() if ref.get(k) != here.get(k))
            if diff:
                k = diff[0]
                raise rz.RefineError(
                    f"{folder}: {k} = {here.get(k)!r} differs from {folders[0]}'s {ref.get(k)!r}"
                    f"{f' (also {diff[1:]})' if len(diff) > 1 else ''}; allowed: folders of one engine, "
                    "weight grid, body and levers"
                )
        twin = next((s for s in out if s.design == design), None)
        if twin is not None:
            raise rz.RefineError(
                f"{folder}: design {design} is already given by {twin.folder}; allowed: each design once"
            )
        out.append(Source(Path(folder), asm, job, design))
    return sorted(out, key=lambda s: s.design)


def science_record(sources: list[Source], positions: int = POSITIONS) -> dict[str, Any]:
    """The store's science record: the keys a workflow run of the model records (so captions and
    the grid read it alike) and, under ``refine``, where the numbers come from."""
    job, man = sources[0].job, sources[0].manifest
    engine_keys = ("pybullet", "engine", "mujoco", "mujoco_settings")
    return {
        "model": MODEL_OF_ENGINE[job.engine],
        "positions_per_axis": positions,
        "weights": job.m,
        "designs": [s.design for s in sources],
        "params": job.params.to_dict(),
        # the levers as a run records them: early stop on, no adaptive grid; mirror images not
        # derived (no mirror_derive key): every cell of every design simulated
        **job.options.science(),
        "refine": {
            "tool": "tools/refine_design.py (morphlearn.resumable)",
            "format": man["identity"]["format"],
            "engine": job.engine,
            "engine_identity": {k: man["identity"][k] for k in engine_keys if k in man["identity"]},
            "body_file": man.get("body_file"),
            "body_file_sha256": man.get("body_file_sha256"),
            "run_keys": {str(s.design): s.manifest["run_key"] for s in sources},
            # said outright here (the run's keys above only name levers that are on)
            "every_cell_simulated": True,
            "adaptive_weights": False,
            "mirror_derive": False,
        },
    }


def _row_commits(folder: Path) -> dict[str, int]:
    """Rows per commit that computed them (progress.jsonl; the last record of a row)."""
    last: dict[int, str] = {}
    p = folder / "progress.jsonl"
    if p.is_file():
        for line in p.read_text().splitlines():
            if line.strip():
                r = json.loads(line)
                last[int(r["row"])] = str(r.get("commit", "unknown"))
    return dict(sorted(Counter(last.values()).items()))


def check_target(out: Path, model: str) -> None:
    """Refuse (RefineError) an out folder that holds anything but a refine bundle of ``model``."""
    allowed = f"allowed: an absent or empty folder, or a bundle this command made for model {model!r}"
    why = place_refusal(out)  # the write guard every writer shares (config.write_refusal); bundles: below
    if why:
        raise rz.RefineError(f"--out {out} {why}; nothing was written; allowed: {RESULTS_ALLOWED}")
    if out.is_symlink() or (out.exists() and not out.is_dir()):
        raise rz.RefineError(f"--out {out}: a file or a link, not a bundle folder; {allowed}")
    if not out.is_dir() or not any(out.iterdir()):
        return
    try:
        by = bounded.json_file(out / MANIFEST).get("made_by", {})
    except (ValueError, AttributeError):
        by = None
    if not isinstance(by, dict) or by.get("tool") != TOOL:
        raise rz.RefineError(
            f"--out {out}: holds files that this command did not make (no refine bundle.json); {allowed}"
        )
    if by.get("model") != model:
        raise rz.RefineError(f"--out {out}: holds a refine bundle of model {by.get('model')!r}; {allowed}")


def build(folders: list[str | Path], out: str | Path, *, command: str | None = None) -> dict[str, Any]:
    """Write the bundle of ``folders`` to ``out`` (see the module docstring); its manifest."""
    out = Path(out)
    sources = load_sources([Path(f) for f in folders])
    job = sources[0].job
    model = MODEL_OF_ENGINE[job.engine]
    check_target(out, model)
    sci = science_record(sources)
    grid = DesignGrid(POSITIONS)
    weights = job.weights
    th = rz.thresholds(job.params)
    folders_rec = {
        str(s.folder): {
            "design": s.design,
            "run_key": s.manifest["run_key"],
            "rows_sha256": provenance.sha256_file(s.folder / "rows"),
            "manifest_sha256": provenance.sha256_file(rz.manifest_path(s.folder)),
            "row_commits": _row_commits(s.folder),
            # wall and CPU time of its rows (None where the folder logged none: JSON has no NaN)
            "cost": {k: None if isinstance(v, float) and v != v else v for k, v in rz.cost(s.folder).items()},
        }
        for s in sources
    }
    command = command or "python tools/refine_design.py bundle " + " ".join(
        shlex.quote(str(s)) for s in [*folders, "--out", out]
    )
    with store.atomic_path(out) as tmp, tempfile.TemporaryDirectory(prefix="refine-shards-") as shard_dir:
        tmp.mkdir(parents=True)
        shards = []
        for i, s in enumerate(sources):
            # one shard per folder, recording the commits that computed its rows (not this one)
            commits = folders_rec[str(s.folder)]["row_commits"]
            path = Path(shard_dir) / f"shard_{i}.nc"
            store.write_shard(
                path,
                model=model,
                grid=grid,
                weights=weights,
                designs=np.array([s.design], dtype=np.int64),
                results=[s.asm.result],
                science=sci,
                provenance={
                    "git_commit": " + ".join(commits) or "unknown",
                    "backend": job.engine,
                    "device": "cpu (not recorded by refine_design)",
                },
            )
            shards.append(path)
        rec = provenance.record(sci, libraries=models.get(model).libraries)
        rec |= {"refine_folders": folders_rec, "command": command}
        merged = tmp / model / "merged.zarr"
        store.merge_shards(
            shards,
            merged,
            model=model,
            grid=grid,
            weights=weights,
            shard_designs=[np.array([s.design], dtype=np.int64) for s in sources],
            science=sci,
            mirror=False,
            provenance=rec,
        )
        ds = store.open_merged(merged)
        table = metrics.metrics_table(ds, th)
        _check_against_folders(table, sources)
        _write_metrics(table, tmp / model, th, ds, model)
        shard_prov = json.loads(ds.attrs["provenance_json"])["shards"]
        manifest: dict[str, Any] = {
            "made_by": {
                "tool": TOOL,
                "model": model,
                "command": command,
                "refine_folders": [str(s.folder) for s in sources],
                "configs": [],
                "results_dir": None,
                "git_commit": provenance.git_commit(),
                "version": __version__,
            },
            "subsets": {
                model: {"designs": [s.design for s in sources], "of": len(sources), "simulated_by": shard_prov}
            },
            "files": {},
        }
        (tmp / "README.md").write_text(readme(manifest, sci, table, folders_rec))
        manifest["files"] = {p.relative_to(tmp).as_posix(): provenance.sha256_file(p) for p in bundle_files(tmp)}
        (tmp / MANIFEST).write_text(json.dumps(manifest, indent=1, sort_keys=True) + "\n")
    return manifest


def _check_against_folders(table: pd.DataFrame, sources: list[Source]) -> None:
    """Each design's row must be its folder's own metrics (resumable.summary), count for count."""
    for s in sources:
        row = table[table.design == s.design].iloc[0]
        want = rz.summary(s.asm)["metrics_over_rows_done"]
        got = {
            "per_env": [int(row[c]) for c in table.columns if c.startswith("n_")],
            "generalists": int(row.generalists),
            "at_least_one": int(row.at_least_one),
            "flagged": int(row.flagged),
        }
        if any(got[k] != want[k] for k in got):
            raise rz.RefineError(f"{s.folder}: the bundle's metrics {got} differ from the folder's {want} (a bug)")


def _write_metrics(table: pd.DataFrame, folder: Path, th: metrics.Thresholds, ds: Any, model: str) -> None:
    """metrics.csv and its sealed record, as the metrics rule writes them (rules.run_metrics), with
    the store named by its path inside the bundle (not the temporary one it was written to)."""
    csv = folder / "metrics.csv"
    table.to_csv(csv, index=False, float_format=metrics.CSV_FLOAT_FORMAT)
    subset = {"thresholds": th.__dict__, "model": model, "merged_sha256_overall": ds.attrs["integrity"]["overall"]}
    rec = provenance.record(subset, libraries=models.get(model).libraries) | {
        "inputs": {f"{model}/merged.zarr": provenance.sha256_file(folder / "merged.zarr")}
    }
    provenance.write_sealed(provenance.sidecar_of(csv), rec, [csv])


README = """# Refined physics designs: {model} ({engine}) at {m} x {m} controllers

Made by `{tool}` (morphlearn.refine_bundle) from {n} complete `tools/refine_design.py` folder(s);
do not edit by hand: `bundle.json` lists the SHA-256 of every file and `morphlearn check-bundle
<folder>` compares them. A workflow run reads it with `{model}.results_from: <this folder>` on
`grid.positions_per_axis: {positions}` (design indices below are on that grid).

- What was run: every (environment, w1, w2) cell of each design simulated in {engine} ({engine_id}),
  {m} x {m} weights, early stop on (exact), no adaptive weight grid, no mirror derivation; body
  `{body}` (sha256 {body_sha}); horizon {steps} steps of dt = {dt}.
- Command: `{command}` (package {version}, commit `{commit}`; the rows' commits are below).
- `{model}/merged.zarr`: the outcome arrays of the {n} design(s); `{model}/metrics.csv` (+ its
  sealed `.provenance.json`): their metrics, equal to each folder's `tools/refine_design.py
  assemble` (checked when this bundle was made). Its science record (`science_json`) holds the
  settings and, under `refine`, each folder's run key.
- `morphlearn check-bundle --resimulate` re-simulates a design from that record (refused when this
  machine's engine version or settings differ from the recorded ones); one design costs what its
  folder's rows cost (below).

| design | l1 | l2 | generalists | at least one | M_L | M_CF | folder | run key | rows by commit | CPU s |
|---|---|---|---|---|---|---|---|---|---|---|
{rows}
"""


def readme(manifest: dict[str, Any], sci: dict[str, Any], table: pd.DataFrame, folders: dict[str, Any]) -> str:
    by = manifest["made_by"]
    ref, pr = sci["refine"], sci["params"]
    by_design = {v["design"]: (k, v) for k, v in folders.items()}
    rows = []
    for _, r in table.iterrows():
        folder, f = by_design[int(r.design)]
        commits = ", ".join(f"{c[:12]}: {n}" for c, n in f["row_commits"].items())
        rows.append(
            f"| {int(r.design)} | ({r.l1x:g}, {r.l1y:g}) | ({r.l2x:g}, {r.l2y:g}) | {int(r.generalists)} | "
            f"{int(r.at_least_one)} | {r.M_L:.6g} | {r.M_CF:.6g} | `{folder}` | `{f['run_key'][:16]}` | "
            f"{commits or 'not logged'} | {f['cost']['cpu_s']:,.0f} |"
        )
    eid = ref["engine_identity"]
    engine_id = ", ".join(f"{k} {v}" for k, v in eid.items() if k not in ("engine", "mujoco_settings"))
    if "mujoco_settings" in eid:
        engine_id += ", default MujocoSettings " + json.dumps(eid["mujoco_settings"], sort_keys=True)
    return README.format(
        model=sci["model"],
        engine=ref["engine"],
        m=sci["weights"],
        tool=by["tool"],
        n=len(table),
        positions=sci["positions_per_axis"],
        engine_id=engine_id,
        body=ref["body_file"],
        body_sha=ref["body_file_sha256"],
        steps=pr["steps"],
        dt=pr["dt"],
        command=by["command"],
        version=by["version"],
        commit=by["git_commit"],
        rows="\n".join(rows),
    )
