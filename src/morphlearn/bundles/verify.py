"""``morphlearn verify``: re-evaluate a random sample of stored cells with the scipy reference.

A cell is one trajectory of a merged dataset: ``(design, env, w1, w2)``. The parameters that made
the dataset (light distance ``r``, horizon, success radius, integrator) are read from its
``science_json`` attribute, so the check needs nothing but the dataset. Each sampled cell is
integrated with :func:`morphlearn.theory.reference.reference_trajectory` and compared:

- **success**: stored ``first_time`` is a number <=> the reference reaches the success radius
  within the horizon;
- **first-success time**: where both succeed, ``|stored - reference| <= time_tol``.

A disagreement is *near the boundary* (expected from tiny numerical differences, see
``docs/model.md``) only where the side that did *not* succeed came genuinely close: its closest
approach within ``2e-3`` of the success radius (a successful trajectory stops at the radius, so
its own closest approach says nothing), or the success happens within 1 time unit of the horizon,
or either side stopped the trajectory (singular trajectories: stored ``status != 0`` or reference
status != 0). Other disagreements are *unexplained*.

Besides the sample, every stored cell of the whole store is checked for internal consistency:
status in 0..3, ``min_dist`` a number >= 0, a ``first_time`` in [0, horizon] only with
``min_dist <= radius``, and ``min_dist`` below the radius only with a ``first_time`` (a lost
success). Every chunk is verified against the store's digests on the way.

Exit codes (``morphlearn verify``): 0 agree; 1 an unexplained disagreement, a first-success time
outside ``time_tol`` or an inconsistent cell; 2 unusable input (missing, unreadable or damaged).
"""

from __future__ import annotations

import json
import math
import multiprocessing
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from morphlearn import grid as gridmod
from morphlearn.models import REFERENCE
from morphlearn.results import STATUS_OK

#: Closest approach within this of the success radius counts as near the boundary.
DIST_TOL = 2e-3
#: Success within this of the horizon counts as near the boundary.
HORIZON_TOL = 1.0
#: Right-hand-side evaluation cap of the reference (singular trajectories stall any integrator).
MAX_NFEV = 300_000


class VerifyError(ValueError):
    """Bad input to ``verify``: one line naming the argument and what is allowed."""


@dataclass
class Cell:
    design: int
    env: int  # light angle in degrees
    w1: float
    w2: float
    l1: tuple[float, float]
    l2: tuple[float, float]
    stored_time: float
    stored_dist: float
    stored_status: int
    ref_time: float = math.nan
    ref_dist: float = math.nan
    ref_status: int = 0

    @property
    def stored_success(self) -> bool:
        return not math.isnan(self.stored_time)

    @property
    def ref_success(self) -> bool:
        return not math.isnan(self.ref_time)


@dataclass
class Report:
    merged: str
    samples: int
    seed: int
    parameters: dict[str, Any]
    success_agree: int = 0
    success_agreement: float = 0.0
    disagree_near_boundary: int = 0
    disagree_unexplained: int = 0
    both_succeed: int = 0
    first_time_agree: int = 0
    first_time_agreement: float | None = None
    first_time_max_abs_diff: float | None = None
    time_tol: float = 0.05
    reference_stopped: int = 0
    stored_flagged: int = 0
    disagreements: list[dict[str, Any]] = field(default_factory=list)
    cells_checked: int = 0
    #: Whole-store consistency: cells with min_dist below the radius and no first_time.
    lost_successes: int = 0
    #: Other inconsistent cells: bad status, bad min_dist, first_time out of range or far away.
    inconsistent: int = 0
    inconsistent_examples: list[str] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        return (
            self.disagree_unexplained == 0
            and self.first_time_agree == self.both_succeed
            and self.lost_successes == 0
            and self.inconsistent == 0
        )

    def as_dict(self) -> dict[str, Any]:
        return asdict(self) | {"ok": self.ok}


def near_boundary(c: Cell, radius: float, horizon: float) -> bool:
    """A success disagreement that a tiny numerical difference may explain. Only the failing
    side's closest approach counts: the succeeding side stopped at the radius by construction."""
    failing_dist = c.stored_dist if c.ref_success else c.ref_dist
    success_time = c.ref_time if c.ref_success else c.stored_time
    return (
        c.ref_status != STATUS_OK
        or c.stored_status != STATUS_OK
        or abs(failing_dist - radius) < DIST_TOL
        or horizon - success_time < HORIZON_TOL
    )


def check_consistency(ds: Any, radius: float, horizon: float, rep: Report) -> None:
    """Every stored cell (all chunks, verified against their digests) against the definitions."""
    from morphlearn import store

    designs = ds["design"].values
    for sl, a in store.read_blocks(ds):
        ft, md, st = a["first_time"], a["min_dist"], a["status"]
        rep.cells_checked += ft.size
        has_t = ~np.isnan(ft)
        lost = ~has_t & (md < radius)  # NaN min_dist compares False: counted below
        with np.errstate(invalid="ignore"):
            bad = (
                (st < 0)
                | (st > 3)
                | ~np.isfinite(md)
                | (md < 0)
                | (has_t & ((ft < 0) | (ft > horizon) | (md > radius)))
            )
        rep.lost_successes += int(lost.sum())
        rep.inconsistent += int(bad.sum())
        for kind, mask in (("min_dist below the radius but no first_time", lost), ("inconsistent", bad)):
            for i, e, w1, w2 in np.argwhere(mask)[: 3 - len(rep.inconsistent_examples)]:
                rep.inconsistent_examples.append(
                    f"design {int(designs[sl.start + i])} env index {e} w index ({w1}, {w2}): {kind} "
                    f"(first_time {ft[i, e, w1, w2]:.6g}, min_dist {md[i, e, w1, w2]:.6g}, "
                    f"status {st[i, e, w1, w2]})"
                )


def read_parameters(ds: Any, path: str | Path) -> dict[str, Any]:
    """r, horizon, success radius and integrator of a merged dataset, from ``science_json``."""
    raw = ds.attrs.get("science_json")
    if raw is None:
        raise VerifyError(f"--merged {path}: no 'science_json' attribute; not a merged morphlearn dataset")
    sci = json.loads(raw)
    model = sci.get("model", ds.attrs.get("model"))
    if model != REFERENCE:  # the scipy reference solves the ODE of the reference model
        raise VerifyError(f"--merged {path}: model {model!r}; allowed: {REFERENCE!r} (the reference is the ODE)")
    th = sci["theory"]
    return {
        "model": REFERENCE,
        **{k: th[k] for k in ("r", "horizon", "success_radius", "integrator")},
        **{k: th[k] for k in ("rtol", "atol", "dt") if k in th},
    }


def _reference(args: tuple) -> tuple[float, float, int]:
    from morphlearn.theory.reference import reference_trajectory

    start, l1, l2, w1, w2, radius, horizon = args
    r = reference_trajectory(start, l1, l2, w1, w2, radius=radius, horizon=horizon, max_nfev=MAX_NFEV)
    return r.first_time, r.min_dist, r.status


def sample_cells(ds: Any, samples: int, seed: int) -> list[Cell]:
    """``samples`` distinct cells drawn uniformly, with their stored values (one chunk read per
    sampled design)."""
    nd, ne, m = ds.sizes["design"], ds.sizes["env"], ds.sizes["w1"]
    total = nd * ne * m * m
    if not 1 <= samples <= total:
        raise VerifyError(f"--samples = {samples}; allowed: 1..{total} (the cells of the dataset)")
    rng = np.random.default_rng(seed)
    flat = np.sort(rng.choice(total, size=samples, replace=False))
    di, ei, ai, bi = np.unravel_index(flat, (nd, ne, m, m))
    w1s, w2s = ds["w1"].values, ds["w2"].values
    envs = ds["env"].values
    coords = {c: ds[c].values for c in ("l1x", "l1y", "l2x", "l2y")}
    designs = ds["design"].values
    cells = []
    for d in np.unique(di):
        block = {k: ds[k][int(d)].values for k in ("first_time", "min_dist", "status")}
        for j in np.flatnonzero(di == d):
            e, a, b = int(ei[j]), int(ai[j]), int(bi[j])
            cells.append(
                Cell(
                    design=int(designs[d]),
                    env=int(envs[e]),
                    w1=float(w1s[a]),
                    w2=float(w2s[b]),
                    l1=(float(coords["l1x"][d]), float(coords["l1y"][d])),
                    l2=(float(coords["l2x"][d]), float(coords["l2y"][d])),
                    stored_time=float(block["first_time"][e, a, b]),
                    stored_dist=float(block["min_dist"][e, a, b]),
                    stored_status=int(block["status"][e, a, b]),
                )
            )
    return cells


def verify(
    merged: str | Path, *, samples: int = 200, seed: int = 0, workers: int = 1, time_tol: float = 0.05
) -> Report:
    """Re-evaluate ``samples`` random cells of a merged theory dataset with the reference solver."""
    from morphlearn import store

    path = Path(merged)
    if workers < 1:
        raise VerifyError(f"--workers = {workers}; allowed: >= 1")
    if not time_tol > 0:
        raise VerifyError(f"--time-tol = {time_tol}; allowed: > 0")
    if not path.exists():
        raise VerifyError(f"--merged {path}: not found (a merged.zarr made by the workflow)")
    if not np.isfinite(time_tol):
        raise VerifyError(f"--time-tol = {time_tol}; allowed: a finite number > 0")
    try:
        ds = store.open_merged(path)  # it ignores Snakemake's timestamp file in directory outputs
    except store.IntegrityError as e:
        raise VerifyError(f"--merged {e}") from None
    except Exception as e:  # zarr/xarray raise many kinds
        raise VerifyError(f"--merged {path}: not a readable Zarr dataset ({type(e).__name__})") from None
    par = read_parameters(ds, path)
    rep = Report(merged=str(path), samples=0, seed=seed, parameters=par, time_tol=time_tol)
    try:
        check_consistency(ds, par["success_radius"], par["horizon"], rep)  # also verifies every chunk
    except store.IntegrityError as e:
        raise VerifyError(f"--merged {e}") from None
    cells = sample_cells(ds, samples, seed)
    starts = gridmod.env_starts(par["r"])
    env_index = {a: i for i, a in enumerate(gridmod.ENV_ANGLES_DEG)}
    jobs = [
        (tuple(starts[env_index[c.env]]), c.l1, c.l2, c.w1, c.w2, par["success_radius"], par["horizon"]) for c in cells
    ]
    if workers == 1:
        refs = [_reference(j) for j in jobs]
    else:  # spawn, not fork: forking after numba's threads started can deadlock the children
        with multiprocessing.get_context("spawn").Pool(workers) as pool:
            refs = pool.map(_reference, jobs, chunksize=max(1, len(jobs) // (8 * workers)))
    rep.samples = len(cells)
    diffs = []
    for c, (t, dist, st) in zip(cells, refs, strict=True):
        c.ref_time, c.ref_dist, c.ref_status = float(t), float(dist), int(st)
        rep.reference_stopped += c.ref_status != STATUS_OK
        rep.stored_flagged += c.stored_status != STATUS_OK
        if c.stored_success == c.ref_success:
            rep.success_agree += 1
            if c.stored_success:
                rep.both_succeed += 1
                diffs.append(abs(c.stored_time - c.ref_time))
                if diffs[-1] <= time_tol:
                    rep.first_time_agree += 1
                else:
                    rep.disagreements.append(asdict(c) | {"kind": "first_time", "near_boundary": False})
            continue
        near = near_boundary(c, par["success_radius"], par["horizon"])
        if near:
            rep.disagree_near_boundary += 1
        else:
            rep.disagree_unexplained += 1
        rep.disagreements.append(asdict(c) | {"kind": "success", "near_boundary": near})
    rep.success_agreement = rep.success_agree / len(cells)
    if diffs:
        rep.first_time_agreement = rep.first_time_agree / len(diffs)
        rep.first_time_max_abs_diff = float(max(diffs))
    return rep


def format_report(rep: Report) -> str:
    p = rep.parameters
    n = rep.samples
    lines = [
        f"verify {rep.merged}: {n} random cells (seed {rep.seed}), r = {p['r']}, horizon = {p['horizon']}, "
        f"success radius = {p['success_radius']}, stored integrator {p['integrator']}; reference: "
        "scipy DOP853 at 1e-10",
        f"success flags agree: {rep.success_agree}/{n} = {rep.success_agreement:.4f}; disagreements: "
        f"{rep.disagree_near_boundary} near the boundary, {rep.disagree_unexplained} unexplained",
    ]
    if rep.first_time_agreement is not None:
        lines.append(
            f"first-success time (both succeed, {rep.both_succeed} cells): {rep.first_time_agree} within "
            f"{rep.time_tol} = {rep.first_time_agreement:.4f}; max |diff| = {rep.first_time_max_abs_diff:.3g}"
        )
    else:
        lines.append("first-success time: no sampled cell where both succeed")
    lines.append(f"flagged (stopped) trajectories: stored {rep.stored_flagged}, reference {rep.reference_stopped}")
    lines.append(
        f"whole store ({rep.cells_checked} cells, every chunk's digest verified): {rep.lost_successes} "
        f"lost successes (min_dist below the radius but no first_time), {rep.inconsistent} other "
        "inconsistent cells"
    )
    lines += [f"  {x}" for x in rep.inconsistent_examples]
    for d in rep.disagreements:
        lines.append(
            f"  {d['kind']}: {'near boundary' if d['near_boundary'] else 'UNEXPLAINED'}: "
            f"design {d['design']} "
            f"l1={d['l1']} l2={d['l2']} env {d['env']} w=({d['w1']:g}, {d['w2']:g}): "
            f"stored t={d['stored_time']:.6g} dist={d['stored_dist']:.6g} status={d['stored_status']}; "
            f"reference t={d['ref_time']:.6g} dist={d['ref_dist']:.6g} status={d['ref_status']}"
        )
    return "\n".join(lines)
