"""Episodes per core-second of the authors' robot in ODE, MuJoCo, pybullet and the reduced model
(docs/authors_robot.md, docs/reduced.md).

The same cells in each engine: ``--designs`` designs of the 5-positions-per-axis grid (the
canonical design first, then a fixed random sample) x 4 environments x ``--m`` x ``--m`` weights,
the body ``config/authors_body.yaml``, one process (one core; MuJoCo's batch on one thread; all of
a design's episodes in one batch, as the workflow's sweep runs them), every episode to its first
success or the horizon. Rate = episodes / CPU seconds of this process; and how many cells each
engine gives ODE's outcome. Usage::

    NUMBA_NUM_THREADS=1 python benchmarks/bench_authors_robot.py [--designs 3] [--m 5] [--seed 0] [--only ODE reduced]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from morphlearn.empirical.authors import AuthorsEpisodeRunner
from morphlearn.grid import DesignGrid, canonical_design, weights
from morphlearn.mujoco.authors import AuthorsBatchRunner
from morphlearn.ode import core
from morphlearn.physics.params import load_params
from morphlearn.reduced import core as reduced

ROOT = Path(__file__).resolve().parents[1]


def designs(n: int, seed: int) -> list[tuple[tuple[float, float], tuple[float, float]]]:
    g = DesignGrid(5)
    canon = g.index_of(*canonical_design())
    rng = np.random.default_rng(seed)
    idx = [canon, *rng.choice(np.setdiff1d(np.arange(g.size), [canon]), n - 1, replace=False)]
    c = g.coords(np.array(idx, dtype=int))
    return [((float(r[0]), float(r[1])), (float(r[2]), float(r[3]))) for r in c]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--designs", type=int, default=3)
    ap.add_argument("--m", type=int, default=5)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--only", nargs="+", help="these engines only (ODE first: the reference)")
    a = ap.parse_args()
    body = load_params(ROOT / "config/authors_body.yaml")
    w = weights(a.m)
    e, i, j = np.meshgrid(np.arange(4), np.arange(a.m), np.arange(a.m), indexing="ij")
    ww, env = np.stack([w[i.ravel()], w[j.ravel()]], 1), e.ravel()
    engines = {
        "ODE": lambda d: core.run(body, *d, ww, env)[0].success,
        "MuJoCo": lambda d: ~np.isnan(AuthorsBatchRunner(body).run(*d, ww, env).first_time),
        "pybullet": lambda d: ~np.isnan(AuthorsEpisodeRunner(body).run(*d, ww, env).first_time),
        # the reduced model's kernel is compiled (numba's cache) before the clock starts, on one thread
        "reduced": lambda d: reduced.run(body, *d, ww, env)[0].success,
    }
    reduced.run(body, *designs(1, a.seed)[0], ww[:1], env[:1])
    out: dict[str, tuple[float, list[np.ndarray]]] = {}
    for name, run in engines.items():
        if a.only and name not in a.only:
            continue
        t = time.process_time()
        succ = [run(d) for d in designs(a.designs, a.seed)]
        out[name] = (time.process_time() - t, succ)
    n = a.designs * len(ww)
    print(f"{a.designs} designs x 4 envs x {a.m}x{a.m} weights = {n} episodes per engine; one core")
    if "reduced" in out and "ODE" in out:
        print(f"reduced / ODE episodes per core-second: {out['ODE'][0] / out['reduced'][0]:.0f}x")
    ref = np.concatenate(out["ODE"][1])
    for name, (spent, succ) in out.items():
        s = np.concatenate(succ)
        print(
            f"{name}: {n / spent:.1f} episodes/core-s ({1e3 * spent / n:.1f} ms an episode, {spent:.1f} s); "
            f"{int(s.sum())} successes; {int((s == ref).sum())}/{n} cells as ODE"
        )


if __name__ == "__main__":
    main()
