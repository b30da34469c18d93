"""Benchmark of the empirical (pybullet) model: episodes per core-second, current loop vs new.

Default: the survey's cost per design, four ways in one run, on ``--pairs`` mirror pairs of the
5-positions-per-axis grid at 11 x 11 weights (CPU seconds of this process, one core):

- current: every episode to contact or the horizon (``early_stop: false``), both designs of
  each pair simulated;
- early stop: the exact lever alone (config.yaml's default);
- survey: config/survey.yaml's levers (read from it): early stop + adaptive weight grid (near
  misses within 1.5 contact distances), one design of each pair simulated and the other derived;
- near 4: the same with the adaptive grid's default threshold, which missed no success in
  validation.

"Episodes" are the (env, w1, w2) cells of the designs covered, so a lever that skips episodes
raises the rate; the ratios are the per-design core-second savings.

``--batched``: the older study of several robots in one world. It runs the same set of
full-length episodes (no early stop) two ways, side by side:

- solo: one robot per world (the production :class:`EpisodeRunner`, world reused);
- batched: ``--batch`` robots in one world, each with its own light, collision filters so
  that a robot touches only the floor and its own light; one ``stepSimulation`` per step.

Prints CPU seconds per episode, episodes/s per core, the batched speed-up, and whether the
batched outcomes equal the solo ones bit for bit. Also times production episodes that stop at
contact. Single process (one core). Usage::

    python benchmarks/bench_empirical.py [--pairs 2]
    python benchmarks/bench_empirical.py --batched [--batch 8] [--params FILE.yaml]
"""

from __future__ import annotations

import argparse
import math
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
import pybullet as pb
import yaml

from morphlearn.empirical import EpisodeRunner, evaluate_design
from morphlearn.empirical.robot import (
    LEFT_WHEEL,
    RIGHT_WHEEL,
    add_floor,
    add_light,
    add_robot,
    configure,
)
from morphlearn.grid import DesignGrid, light_positions, weights
from morphlearn.physics.options import SweepOptions
from morphlearn.physics.params import EmpiricalParams, load_params
from morphlearn.physics.refine import DEFAULT_NEAR

Case = tuple[tuple[float, float], tuple[float, float], float, float, int]


def cases(n: int) -> list[Case]:
    """``n`` (l1, l2, w1, w2, env) cases: a mix of designs, weights and environments."""
    rng = np.random.default_rng(0)
    axis = np.linspace(-0.5, 0.5, 5)
    w = np.linspace(-1.0, 1.0, 5)
    out = []
    for i in range(n):
        x1, y1, x2, y2 = (float(v) for v in rng.choice(axis, 4))
        out.append(((x1, y1), (x2, y2), float(rng.choice(w)), float(rng.choice(w)), i % 4))
    return out


def solo(params: EmpiricalParams, cs: list[Case], stop: bool) -> tuple[float, list[float]]:
    t = time.process_time()
    with EpisodeRunner(params) as runner:
        d = [runner.run(*c, stop_at_contact=stop).min_dist for c in cs]
    return time.process_time() - t, d


def batched(params: EmpiricalParams, cs: list[Case]) -> tuple[float, list[float]]:
    """All cases at once in one world (prototype; mirrors EpisodeRunner.run's controller)."""
    t = time.process_time()
    c = pb.connect(pb.DIRECT)
    configure(c, params)
    floor = add_floor(c, params)
    pb.setCollisionFilterGroupMask(floor, -1, 1, 0xFFFF, physicsClientId=c)
    lights = light_positions(params.light_distance)
    robots, lxy = [], []
    for i, (_, _, _, _, env) in enumerate(cs):
        bit = 1 << (i + 1)  # group per robot: floor (1) + own light only
        rob = add_robot(c, params)
        lit = add_light(c, params, tuple(lights[env]))
        for link in range(-1, 3):
            pb.setCollisionFilterGroupMask(rob, link, bit, 1 | bit, physicsClientId=c)
        pb.setCollisionFilterGroupMask(lit, -1, bit, bit, physicsClientId=c)
        robots.append(rob)
        lxy.append((float(lights[env][0]), float(lights[env][1])))
    vmax, tau = params.max_speed, params.max_torque
    min_d2 = [math.inf] * len(cs)
    for k in range(params.steps + 1):
        for i, ((l1, l2, w1, w2, _), rob) in enumerate(zip(cs, robots, strict=True)):
            (px, py, _), (qx, qy, qz, qw) = pb.getBasePositionAndOrientation(rob, physicsClientId=c)
            dx, dy = px - lxy[i][0], py - lxy[i][1]
            min_d2[i] = min(min_d2[i], dx * dx + dy * dy)
            if k == params.steps:
                continue
            ax, ay = 1.0 - 2.0 * (qy * qy + qz * qz), 2.0 * (qx * qy + qz * qw)
            bx, by = 2.0 * (qx * qy - qz * qw), 1.0 - 2.0 * (qx * qx + qz * qz)
            e1x, e1y = dx + ax * l1[0] + bx * l1[1], dy + ay * l1[0] + by * l1[1]
            e2x, e2y = dx + ax * l2[0] + bx * l2[1], dy + ay * l2[0] + by * l2[1]
            s1 = 1.0 / (e1x * e1x + e1y * e1y)
            s2 = 1.0 / (e2x * e2x + e2y * e2y)
            pb.setJointMotorControlArray(
                rob,
                [RIGHT_WHEEL, LEFT_WHEEL],
                pb.VELOCITY_CONTROL,
                targetVelocities=[math.tanh(w1 * s1) * vmax, math.tanh(w2 * s2) * vmax],
                forces=[tau, tau],
                physicsClientId=c,
            )
        if k < params.steps:
            pb.stepSimulation(physicsClientId=c)
    pb.disconnect(c)
    return time.process_time() - t, [math.sqrt(v) for v in min_d2]


#: Designs of the comparison: the paper's best theory pair first, then seeded others.
def pair_designs(pairs: int) -> list[tuple[int, int]]:
    g = DesignGrid(5)
    d = np.arange(g.size)
    reps = d[d < g.mirror(d)]
    best = g.index_of((-0.5, -0.25), (0.5, 0.25))
    best = min(best, int(g.mirror(best)))
    others = np.random.default_rng(1).permutation(reps[reps != best])[: pairs - 1]
    return [(int(x), int(g.mirror(x))) for x in [best, *others]]


def levers(params: EmpiricalParams, pairs: int, m: int, survey: dict) -> None:
    """``survey``: config/survey.yaml's ``empirical`` section (its levers, read, not restated)."""
    g = DesignGrid(5)
    w = weights(m)
    cells = 4 * m * m
    opt = SweepOptions.from_config(survey)
    derive = bool(survey.get("mirror_derive"))
    # name -> (options, one design of each pair simulated and the other derived?)
    ways = {
        "current": (SweepOptions(), False),
        "early stop": (SweepOptions(early_stop=True), False),
        "survey": (opt, derive),
        f"near {DEFAULT_NEAR:g}": (replace(opt, near=DEFAULT_NEAR), derive),
    }
    cpu = dict.fromkeys(ways, 0.0)
    found = dict.fromkeys(ways, 0)
    designs = pair_designs(pairs)
    print(
        f"{len(designs)} mirror pairs ({2 * len(designs)} designs) x {cells} episodes, {m} x {m} weights, "
        f"{params.steps} steps of dt {params.dt}, one core"
    )
    for pair in designs:
        for name, (options, derived) in ways.items():
            for d in pair[:1] if derived else pair:
                c = g.coords(d)
                t = time.process_time()
                r = evaluate_design((c[0], c[1]), (c[2], c[3]), w, params, options=options)
                cpu[name] += time.process_time() - t
                found[name] += int(np.isfinite(r.first_time).sum()) * (2 if derived else 1)
        print(f"  pair {pair}: " + ", ".join(f"{k} {v:.0f} CPU-s" for k, v in cpu.items()), flush=True)
    n = 2 * len(designs) * cells
    for name in ways:
        per = cpu[name] / (2 * len(designs))
        print(
            f"{name:>10}: {per:7.1f} core-s per design, {n / cpu[name]:6.2f} episodes/core-s, "
            f"{cpu['current'] / cpu[name]:5.2f}x the current loop; successes {found[name]}"
        )


def main() -> None:
    root = Path(__file__).resolve().parents[1]
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--params", default=str(root / "config" / "empirical_morphology.yaml"))
    ap.add_argument("--pairs", type=int, default=2, help="mirror pairs of designs in the comparison")
    ap.add_argument("--weights", type=int, default=11, help="weights per synapse in the comparison")
    ap.add_argument("--batched", action="store_true", help="the batching study instead")
    ap.add_argument("--batch", type=int, default=8, help="robots per world in the batched run")
    ap.add_argument("--episodes", type=int, default=16, help="episodes per measurement")
    a = ap.parse_args()
    params = load_params(a.params) if Path(a.params).exists() else EmpiricalParams()
    if not a.batched:
        print(f"params: {a.params}")
        survey = yaml.safe_load((root / "config" / "survey.yaml").read_text())["empirical"]
        levers(params, a.pairs, a.weights, survey)
        return
    cs = cases(a.episodes)
    print(f"params: {a.params if Path(a.params).exists() else 'authors defaults'}")
    print(f"{len(cs)} episodes of {params.steps} steps, dt {params.dt}, one core")

    t_solo, d_solo = solo(params, cs, stop=False)
    print(f"solo, full length:      {t_solo / len(cs):.4f} s/episode, {len(cs) / t_solo:6.2f} ep/s")
    t_stop, _ = solo(params, cs, stop=True)
    print(f"solo, stop at contact:  {t_stop / len(cs):.4f} s/episode, {len(cs) / t_stop:6.2f} ep/s")

    t_b, d_b = 0.0, []
    for i in range(0, len(cs), a.batch):
        t, d = batched(params, cs[i : i + a.batch])
        t_b += t
        d_b += d
    same = sum(x == y for x, y in zip(d_solo, d_b, strict=True))
    print(
        f"batched ({a.batch}/world):    {t_b / len(cs):.4f} s/episode, {len(cs) / t_b:6.2f} ep/s"
        f"  -> speed-up {t_solo / t_b:.2f}x over solo full length"
    )
    print(f"batched min distance == solo bit for bit: {same}/{len(cs)} episodes")


if __name__ == "__main__":
    main()
