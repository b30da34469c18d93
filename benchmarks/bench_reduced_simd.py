"""Episodes per core-second of the reduced model's scalar kernel (reduced.backend cpu), its SIMD
kernel (cpu-simd) and ODE, measured in one run, interleaved (docs/reduced.md, Cost).

The machine is shared and its load changes within minutes, so the three are measured design by
design in turn (ODE, scalar, SIMD on the same cells, then scalar and SIMD on a design's larger
cell set), and the ratios are what the run reports; absolute rates move with the load. Designs:
``--designs`` of the paper's 9-point grid drawn at random (seed ``--seed``), every episode to its
first success or the horizon (as the sweep runs them), one thread (numba's set to 1 here), CPU
seconds of this process. Every cell's outcomes (success step, closest approach, steps, finite) are
compared between the two reduced kernels and must be identical. From the SIMD rate it estimates all
6561 designs at 121 x 121, every cell, one of each mirror pair simulated. ``--adaptive N``: also N
of the designs swept whole at 121 x 121 with the levers of config/reduced_paper.yaml (adaptive grid,
stride 6, near 2.5), scalar and SIMD in turn, and the 6561 map's cost with them. Usage::

    python benchmarks/bench_reduced_simd.py [--designs 6] [--m 41] [--m-ode 5] [--seed 0] [--adaptive 0]
"""

from __future__ import annotations

import os

os.environ["NUMBA_NUM_THREADS"] = "1"  # per core: before numba is imported

import argparse
import time
from pathlib import Path

import numpy as np

from morphlearn.grid import DesignGrid, weights
from morphlearn.ode import core as ode
from morphlearn.physics.params import load_params
from morphlearn.reduced import core as reduced
from morphlearn.reduced import simd

ROOT = Path(__file__).resolve().parents[1]
FIELDS = ("first_step", "min_dist", "steps", "finite")


def cells(m: int) -> tuple[np.ndarray, np.ndarray]:
    w = weights(m)
    e, i, j = np.meshgrid(np.arange(4), np.arange(m), np.arange(m), indexing="ij")
    return np.stack([w[i.ravel()], w[j.ravel()]], 1), e.ravel()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--designs", type=int, default=6)
    ap.add_argument("--m", type=int, default=41, help="weights per axis of the reduced kernels' own cells")
    ap.add_argument("--m-ode", type=int, default=5, help="weights per axis of the cells all three run")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--adaptive", type=int, default=0, help="designs swept with the paper map's adaptive grid")
    a = ap.parse_args()
    body = load_params(ROOT / "config/authors_body.yaml")
    g = DesignGrid(9)
    idx = np.random.default_rng(a.seed).choice(g.size, a.designs, replace=False)
    designs = [((float(c[0]), float(c[1])), (float(c[2]), float(c[3]))) for c in g.coords(idx)]
    small, big = cells(a.m_ode), cells(a.m)
    kernels = {
        "ODE": lambda d, w, e: ode.run(body, *d, w, e)[0],
        "scalar": lambda d, w, e: reduced.run(body, *d, w, e)[0],
        "simd": lambda d, w, e: reduced.run(body, *d, w, e, backend="cpu-simd")[0],
    }
    for name in ("scalar", "simd"):  # compiled (numba's cache) or loaded before the clock starts
        kernels[name](designs[0], small[0][:1], small[1][:1])
    spent = {(k, s): 0.0 for k in kernels for s in ("small", "big")}
    count = {(k, s): 0 for k in kernels for s in ("small", "big")}
    steps = 0
    for d in designs:
        for size, (w, e) in (("small", small), ("big", big)):
            out = {}
            for name, run in kernels.items():
                if name == "ODE" and size == "big":
                    continue
                t = time.process_time()
                out[name] = run(d, w, e)
                spent[name, size] += time.process_time() - t
                count[name, size] += len(w)
            for f in FIELDS:  # the two reduced kernels: every cell identical
                x, y = np.asarray(getattr(out["scalar"], f)), np.asarray(getattr(out["simd"], f))
                if x.tobytes() != y.tobytes():
                    raise SystemExit(f"design {d}: {f} differs between the kernels at {int((x != y).sum())} cells")
            if size == "big":
                steps += int(out["scalar"].steps.sum())
    rate = {k: count[k] / spent[k] for k in spent if count[k]}
    isa, tanh = simd.mode()
    print(f"{a.designs} designs of the 9-point grid (seed {a.seed}); one core; SIMD kernel: {isa}, tanh {tanh}")
    print(f"cells all three ran: 4 envs x {a.m_ode}x{a.m_ode} a design; the reduced kernels' own: 4 x {a.m}x{a.m}")
    for k in kernels:
        print(f"  {k:6s} small: {rate[k, 'small']:9.1f} episodes/core-s" + (
            f"   big: {rate[k, 'big']:9.1f} episodes/core-s" if (k, "big") in rate else ""))  # fmt: skip
    print(f"SIMD / scalar: {rate['simd', 'small'] / rate['scalar', 'small']:.2f}x (small), "
          f"{rate['simd', 'big'] / rate['scalar', 'big']:.2f}x (big); "
          f"SIMD / ODE: {rate['simd', 'small'] / rate['ODE', 'small']:.0f}x; "
          f"scalar / ODE: {rate['scalar', 'small'] / rate['ODE', 'small']:.0f}x")  # fmt: skip
    print(f"every cell identical between the kernels ({count['simd', 'small'] + count['simd', 'big']} episodes); "
          f"{steps / count['scalar', 'big']:.0f} steps an episode (big)")  # fmt: skip
    full = DesignGrid(9)
    simulated = len({min(d, int(full.mirror(d))) for d in range(full.size)})
    episodes = simulated * 4 * 121 * 121
    for k in ("scalar", "simd"):
        print(
            f"all 6561 designs at 121 x 121, every cell, mirror derivation ({simulated} simulated, "
            f"{episodes / 1e6:.1f} M episodes) at the {k} rate (big): {episodes / rate[k, 'big'] / 3600:.2f} core-hours"
        )
    if a.adaptive:
        adaptive(body, designs[: a.adaptive], simulated)


def adaptive(body: object, designs: list, simulated: int) -> None:
    """Whole sweeps with the paper map's levers, scalar and SIMD in turn, every result identical."""
    import yaml

    from morphlearn.physics.options import SweepOptions
    from morphlearn.reduced.episode import evaluator

    sec = yaml.safe_load((ROOT / "config/reduced_paper.yaml").read_text())["reduced"]
    options, w = SweepOptions.from_config(sec), weights(121)
    spent = {"cpu": 0.0, "cpu-simd": 0.0}
    for d in designs:
        out = {}
        for b in spent:
            t = time.process_time()
            out[b] = evaluator(b)(*d, w, body, options=options)
            spent[b] += time.process_time() - t
        for v in ("first_time", "min_dist"):
            if np.asarray(getattr(out["cpu"], v)).tobytes() != np.asarray(getattr(out["cpu-simd"], v)).tobytes():
                raise SystemExit(f"design {d}: the adaptive sweeps' {v} differ between the kernels")
    n = len(designs)
    print(f"adaptive grid (config/reduced_paper.yaml's levers), {n} designs at 121 x 121, results identical:")
    for b, t in spent.items():
        hours = simulated * t / n / 3600
        print(f"  {b:8s} {t / n:6.2f} CPU-s a design; 6561 designs ({simulated} simulated): {hours:.2f} core-hours")
    print(f"  SIMD / scalar: {spent['cpu'] / spent['cpu-simd']:.2f}x")


if __name__ == "__main__":
    main()
