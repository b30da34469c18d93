"""What the explorer's live computation costs: a design's overlap matrix by the theory kernel
(``morphlearn.apps.explore.Explorer.landscape``, the paper bundle's parameters) at 41 x 41 and 121 x 121
weights, on a random sample of the designs the bundle does not hold. A design's cost depends on how
many of its trajectories run to the step cap (10,000 steps), so the spread is wide. Usage::

    PYTHONPATH=src python benchmarks/bench_explore.py [--designs 12] [--seed 0]
"""

from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

import numpy as np

from morphlearn.apps import explore


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--designs", type=int, default=12, help="random designs timed at each grid")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--bundle", default=str(Path(__file__).resolve().parents[1] / "results" / "paper"))
    a = ap.parse_args()
    ex = explore.Explorer(explore.open_source(explore.Source(Path(a.bundle), "theory")))
    t0 = time.perf_counter()
    explore.warm_up()
    print(
        f"kernel load (numba cache) {time.perf_counter() - t0:.2f} s; {os.cpu_count()} CPUs, "
        f"load average {os.getloadavg()[0]:.1f}"
    )
    rng = np.random.default_rng(a.seed)
    free = np.array([d for d in range(ex.grid.size) if not ex.held(d)])
    designs = rng.choice(free, a.designs, replace=False)
    for m in explore.LIVE_WEIGHTS:
        secs = []
        for d in designs:
            land = ex._live(int(d), m)  # uncached
            secs.append(land.seconds)
        s = np.array(secs)
        each = ", ".join(f"{d}: {x:.2f}" for d, x in zip(designs, s, strict=True))
        print(
            f"{m} x {m}: median {np.median(s):.2f} s, min {s.min():.2f} s, max {s.max():.2f} s over "
            f"{len(s)} designs; per design (s): {each}"
        )


if __name__ == "__main__":
    main()
