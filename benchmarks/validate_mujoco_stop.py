"""Validate the early stop (reach bound, margin 2) in the MuJoCo model: run full-length episodes
that only record where the bound said "out of reach", and count successes after that step (must
be 0 for the stop to be exact). Usage: ``python benchmarks/validate_mujoco_stop.py [designs...]``.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from morphlearn.grid import DesignGrid, weights
from morphlearn.mujoco.episode import BatchRunner
from morphlearn.physics.params import load_params

ROOT = Path(__file__).resolve().parents[1]


def main() -> None:
    designs = [int(a) for a in sys.argv[1:]] or [620, 120, 91, 300]
    p = load_params(ROOT / "config/empirical_morphology.yaml")
    runner, g, w = BatchRunner(p), DesignGrid(5), weights(11)
    pairs = np.array([(a, b) for a in w for b in w])
    w4, env = np.tile(pairs, (4, 1)), np.repeat(np.arange(4), len(pairs))
    tot = bad = flagged = succ = 0
    for d in designs:
        c = g.coords(d)
        ep = runner.run(c[:2], c[2:], w4, env, margin=2.0, stop_hopeless=False)
        f = ep.hopeless_step >= 0
        bad += int((f & ep.success & (np.round(ep.first_time / p.dt) >= ep.hopeless_step)).sum())
        tot, flagged, succ = tot + len(w4), flagged + int(f.sum()), succ + int(ep.success.sum())
    print(
        f"designs {designs}: episodes {tot}, flagged out of reach {flagged}, successes {succ}, "
        f"successes after the flag {bad}"
    )


if __name__ == "__main__":
    main()
