"""A workflow design's partial file seeded from a committed exhaustive refine folder.

A pybullet design at the paper's 121 x 121 weights is hours of one core. The folders' runner
(deleted; the folders are read-only history, :mod:`morphlearn.refine.folder`) and the workflow's
evaluator made the same per-cell call (same runner, same reach bound, same floats; the folders'
rows equal the workflow's refine bundles, ``tests/test_refine_bundle.py``), so the episodes of an
exhaustive folder, complete or not, are episodes the workflow would simulate. :func:`seed`
writes them as the design's partial file (:mod:`morphlearn.physics.partial`) in a config's
design cache: the workflow run then "resumes" the design and simulates only the cells of its
path (e.g. the adaptive grid's) that the folder lacks, to the bytes of a run that had no file
(``evaluate_design`` infers the folder's cells its path does not visit, as it would have).

Two things are not taken from a folder, and are simulated instead:
- a cell whose closest approach, stored as float32 by the folder, lies within one float32 step of
  the adaptive grid's "near" distance (the workflow compares the float64 value: the rounding could
  change the path);
- anything of a folder made for another body, weights, early stop or engine (refused, with which).

:func:`seed_designs` does the same from another run's design cache (e.g. an adaptive survey's,
``results/<run>/<model>/designs/<digest>/``): the cells its run simulated (not those its adaptive grid
inferred) of every design this config simulates, matched by sensor coordinates, so an exhaustive
refinement of a surveyed design simulates only the rest. Its run may differ in design grid,
adaptive grid and mirror handling, nothing else (refused, naming the key).
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import numpy as np

from morphlearn import grid as gridmod
from morphlearn import models, store
from morphlearn.physics import design_cache
from morphlearn.physics import partial as partial_cells
from morphlearn.physics.options import SweepOptions
from morphlearn.physics.params import EmpiricalParams
from morphlearn.refine import folder as rz
from morphlearn.results import STATUS_INFERRED
from morphlearn.settings import Settings

#: Science keys a design cache's run may differ in from the seeded config: they choose which cells
#: and designs a run simulates, not an episode's outcome.
PATH_KEYS = frozenset({"adaptive_weights", "mirror_derive", "positions_per_axis"})


@dataclass(frozen=True)
class Seeded:
    """What :func:`seed` did, for its report."""

    design: int
    path: Path
    rows: int  # complete w1 rows of the folder (a design cache's design: its simulated cells)
    seeded: int  # cells written to the partial file (new ones)
    kept: int  # cells the partial file already held (not replaced)
    near_threshold: int  # cells left out: float32 rounding could move them across "near"
    finished: bool  # the design is already in the design cache: nothing written


def seed(folder: str | Path, s: Settings, model: str | None = None) -> Seeded:
    """Write ``folder``'s episodes as the partial file of its design in ``s``'s design cache (the
    model: the one running the folder's engine, unless named)."""
    asm = rz.assemble(folder)
    job = rz.job_from_manifest(asm.manifest)
    plugin = _plugin(s, model or _model_of_engine(job.engine))
    e = plugin.settings(s)
    w = plugin.weights(s)
    _check_same_episodes(job, plugin.engine, e.params, e.options, w)
    try:
        d = s.grid.designs.index_of(job.l1, job.l2)
    except ValueError as err:
        raise rz.RefineError(f"{folder}: its design is not on this config's grid ({err})") from None
    if d not in e.simulated:
        raise rz.RefineError(
            f"{folder}: design {d} (l1 = {job.l1}, l2 = {job.l2}) is not one this config simulates; "
            f"allowed: {list(e.simulated)}"
        )
    m = len(w)
    take = np.broadcast_to(asm.rows_done[None, :, None], (4, m, m)).copy()
    return _into_partial(plugin, s, d, asm.result, take, int(asm.rows_done.sum()))


def seed_designs(cache: str | Path, s: Settings) -> list[Seeded]:
    """Seed every design of another run's design cache ``cache`` that ``s`` simulates (matched by
    its sensors' coordinates) with the cells that run simulated; one :class:`Seeded` each, in the
    cache's order of design numbers. Every file is verified (science digest, data checksum)."""
    named = ((p, re.fullmatch(r"design_(\d+)\.nc", p.name)) for p in Path(cache).glob("design_*.nc"))
    files = [p for p, _ in sorted(((p, int(m[1])) for p, m in named if m), key=lambda x: x[1])]
    if not files:
        raise rz.RefineError(f"{cache}: no design_<n>.nc files (a run's <model>/designs/<digest>/ folder)")
    out = []
    for f in files:
        try:
            sh = store.read_shard(f)
            science = json.loads(sh.attrs.get("science_json", "{}"))
            m = sh.arrays["status"].shape[-1]
            store.verify_shard(sh, model=str(sh.attrs.get("model")), science=science, designs=sh.designs[:1], m=m)
        except (store.ShardError, ValueError) as e:
            raise rz.RefineError(f"{f}: not a verified design file ({e})") from None
        model = str(sh.attrs["model"])
        plugin = _plugin(s, model)
        _check_same_science(f, science, design_cache.design_science(plugin.science(s)))
        c = gridmod.DesignGrid(int(science["positions_per_axis"])).coords(sh.designs)[0]
        try:
            d = s.grid.designs.index_of((float(c[0]), float(c[1])), (float(c[2]), float(c[3])))
        except ValueError:
            continue  # not on this config's design grid
        if d not in plugin.settings(s).simulated:
            continue
        r = SimpleNamespace(**{k: sh.arrays[k][0] for k in store.VARS})
        take = r.status != STATUS_INFERRED
        out.append(_into_partial(plugin, s, d, r, take, int(take.sum())))
    return out


def _model_of_engine(engine: str) -> str:
    """The workflow model that runs ``engine`` (a MuJoCo folder is MuJoCo's, not pybullet's)."""
    return next((n for n, m in models.MODELS.items() if getattr(m, "engine", None) == engine), engine)


def _plugin(s: Settings, model: str) -> Any:
    """The physics model ``model`` of ``s``, if it reads partial files in this run."""
    plugin = models.get(model)
    if not getattr(plugin, "resumes_inside_design", False):
        allowed = [n for n, m in models.MODELS.items() if getattr(m, "resumes_inside_design", False)]
        raise rz.RefineError(f"model {model!r} keeps no partial designs; allowed: {allowed}")
    if not plugin.simulates(s):
        raise rz.RefineError(f"this config does not simulate {model!r} ({model}.enabled, {model}.results_from)")
    if not s.design_cache:
        raise rz.RefineError("design_cache = false: the workflow would not read a partial file")
    return plugin


def _check_same_science(source: Path, theirs: dict[str, Any], ours: dict[str, Any]) -> None:
    """The source run's episodes are this config's only if nothing but the path keys differ."""
    keys = sorted(k for k in set(theirs) | set(ours) if k not in PATH_KEYS and theirs.get(k) != ours.get(k))
    if keys:
        raise rz.RefineError(f"{source}: made with other {keys} than this config (only {sorted(PATH_KEYS)} may differ)")


def _into_partial(plugin: Any, s: Settings, d: int, r: Any, take: np.ndarray, rows: int) -> Seeded:
    """Write the cells ``take`` of outcome arrays ``r`` (float32 as stored) into design ``d``'s
    partial file, keeping the cells it already holds."""
    e = plugin.settings(s)
    m = len(plugin.weights(s))
    cache = design_cache.cache_dir(s.results_dir, plugin.name, plugin.science(s))
    path = design_cache.partial_path(cache, d)
    if design_cache.design_path(cache, d).is_file():
        return Seeded(d, path, rows, 0, 0, 0, True)
    ident = plugin.partial_identity(s, d)
    cells = partial_cells.load(path, ident, (4, m, m)) or partial_cells.Cells.empty(m)
    near_risk = np.zeros_like(take)
    if e.options.adaptive_weights:
        near = np.float32(e.options.near * e.params.contact_distance)
        # |d32 - near| within one float32 step of either: the float64 original may lie on the other side
        step = np.spacing(np.maximum(np.abs(r.min_dist), np.abs(near)))
        near_risk = take & (np.abs(r.min_dist - near) <= step)
    kept = int(cells.simulated.sum())
    take &= ~near_risk & ~cells.simulated  # what the file already holds was simulated by the workflow
    cells.first_time[take] = r.first_time[take].astype(np.float64)
    cells.min_dist[take] = r.min_dist[take].astype(np.float64)
    cells.status[take] = r.status[take]
    cells.simulated[take] = True
    if take.any():
        cache.mkdir(parents=True, exist_ok=True)
        partial_cells.save(path, ident, cells)
    return Seeded(d, path, rows, int(take.sum()), kept, int(near_risk.sum()), False)


def _check_same_episodes(
    job: rz.Job, engine: str, params: EmpiricalParams, options: SweepOptions, w: np.ndarray
) -> None:
    """The folder's episodes are the workflow's only for the same engine, body, weights and early stop."""
    diffs = []
    if job.engine != engine:
        diffs.append(f"engine {job.engine!r} (the config's model runs {engine!r})")
    if job.params != params:
        keys = [k for k, v in job.params.to_dict().items() if params.to_dict().get(k) != v]
        diffs.append(f"body parameters {keys} (the config's body file and params overrides)")
    if not np.array_equal(job.weights, w):
        diffs.append(f"weights {job.m} per synapse (the config's: {len(w)})")
    if (job.options.early_stop, job.options.margin) != (options.early_stop, options.margin):
        diffs.append(f"early_stop = {job.options.early_stop} (the config's: {options.early_stop})")
    if diffs:
        raise rz.RefineError("the folder's episodes are not this config's: another " + "; another ".join(diffs))
