"""Base-morphology optimisation (NSGA-II), as the paper did before its empirical sweep.

Sensors fixed canonical (``l1 = (0.5, 0.5)``, ``l2 = (0.5, -0.5)``), controller ``w = (1, 1)``.
Decision variables: body, wheel and castor mass, wheel radius, max wheel speed, max torque,
each searched as ``log(value / authors' value)`` within the factor bounds of :data:`BOUNDS`
(multiplicative bounds suit quantities that span orders of magnitude).

- objective 1: summed minimum centre-to-light distance over the 4 environments (minimise;
  episodes stop at contact, so a reached light scores the contact distance);
- objective 2: actuation, ``max_torque + max_speed`` (minimise; the numbers, N m + rad/s,
  as the authors summed them);
- constraints (stability): during the four episodes and an open-loop stress test (full speed
  forward, abrupt full reverse, spins both ways) the body must tilt at most ``max_tilt_deg``
  and its centre must stay within ``max_lift_frac * wheel_radius`` of its resting height.
  The stress test guards the later sweep, whose controllers can saturate the motors.

Selection rule for the chosen morphology (:func:`select`): among feasible Pareto points where
``w = (1, 1)`` reaches the light in all four environments, the one with the smallest actuation
that is robust: each of the 12 bodies with one decision variable scaled by 1 -+ ``robust_rel``
(1 %) also reaches all four lights. Some regions of the parameter space are chaotic (fast,
heavy bodies pass the light at a near miss; rounding a parameter in its 7th digit flipped an
outcome), and a knife-edge optimum would make the sweep's baseline an accident. If no Pareto
point is robust, the other evaluated bodies reaching all four lights are tried the same way
(by actuation); failing that, the most robust one checked; if no body reaches all four, the
feasible Pareto point with the most reached, then the smallest distance objective.
Deterministic for a seed, independent of ``workers``. Writes nothing.
"""

from __future__ import annotations

import argparse
import math
import time
from collections.abc import Callable, Sequence
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import pybullet as pb
import yaml

from morphlearn.empirical.episode import EpisodeRunner
from morphlearn.empirical.robot import LEFT_WHEEL, RIGHT_WHEEL, build_world
from morphlearn.grid import ENV_ANGLES_DEG, canonical_design
from morphlearn.physics.params import EmpiricalParams

AUTHORS = EmpiricalParams()
#: Decision variable -> (lowest, highest) factor of the authors' value.
BOUNDS: dict[str, tuple[float, float]] = {
    "body_mass": (0.1, 10.0),
    "wheel_mass": (0.1, 10.0),
    "castor_mass": (0.1, 10.0),
    "wheel_radius": (0.5, 2.0),
    "max_speed": (0.25, 8.0),
    "max_torque": (0.25, 16.0),
}
VARIABLES = tuple(BOUNDS)
#: Open-loop stress schedule: (steps, right target, left target) in units of max speed.
STRESS = ((60, 1.0, 1.0), (60, -1.0, -1.0), (60, 1.0, -1.0), (60, -1.0, 1.0))


def decode(x: Sequence[float], base: EmpiricalParams = AUTHORS) -> EmpiricalParams:
    """Log-factor vector -> parameters."""
    vals = {k: getattr(AUTHORS, k) * math.exp(v) for k, v in zip(VARIABLES, x, strict=True)}
    return base.replace(**vals)


def stress(params: EmpiricalParams) -> tuple[float, float]:
    """Max tilt (rad) and max |z - wheel_radius| (m) under the open-loop STRESS schedule."""
    world = build_world(params, (1e3, 1e3))  # light far away: not in the way
    c, robot = world.client, world.robot
    tilt_c, lift = 1.0, 0.0
    try:
        for n, right, left in STRESS:
            for _ in range(n):
                pb.setJointMotorControlArray(
                    robot,
                    [RIGHT_WHEEL, LEFT_WHEEL],
                    pb.VELOCITY_CONTROL,
                    targetVelocities=[right * params.max_speed, left * params.max_speed],
                    forces=[params.max_torque] * 2,
                    physicsClientId=c,
                )
                pb.stepSimulation(physicsClientId=c)
                (_, _, z), (qx, qy, _, _) = pb.getBasePositionAndOrientation(robot, physicsClientId=c)
                if not math.isfinite(z + qx + qy):
                    return math.inf, math.inf
                tilt_c = min(tilt_c, 1.0 - 2.0 * (qx * qx + qy * qy))
                lift = max(lift, abs(z - params.wheel_radius))
    finally:
        world.close()
    return math.acos(max(-1.0, min(1.0, tilt_c))), lift


def score(params: EmpiricalParams) -> dict[str, Any]:
    """Objectives and stability measures of one body (canonical sensors, w = (1, 1))."""
    l1, l2 = canonical_design()
    row: dict[str, Any] = {k: getattr(params, k) for k in VARIABLES}
    dists, tilt, lift = [], 0.0, 0.0
    with EpisodeRunner(params) as runner:
        for env, ang in enumerate(ENV_ANGLES_DEG):
            ep = runner.run(l1, l2, 1.0, 1.0, env)
            d = ep.min_dist if ep.finite else math.inf
            dists.append(d)
            row[f"success_{ang}"] = ep.success
            row[f"time_{ang}"] = ep.first_time
            tilt, lift = max(tilt, ep.max_tilt), max(lift, ep.max_lift if ep.finite else math.inf)
    s_tilt, s_lift = stress(params)
    row["f_distance"] = float(sum(dists))
    row["f_actuation"] = params.max_torque + params.max_speed
    row["n_success"] = sum(bool(row[f"success_{a}"]) for a in ENV_ANGLES_DEG)
    row["max_tilt_deg"] = math.degrees(max(tilt, s_tilt))
    row["max_lift"] = max(lift, s_lift)
    return row


def _score_x(x: Sequence[float]) -> dict[str, Any]:
    return score(decode(x))


def _problem(pool: ProcessPoolExecutor | None, max_tilt_deg: float, max_lift_frac: float) -> Any:
    from pymoo.core.problem import Problem

    lo = np.log([BOUNDS[k][0] for k in VARIABLES])
    hi = np.log([BOUNDS[k][1] for k in VARIABLES])

    class BaseMorphology(Problem):
        def __init__(self) -> None:
            super().__init__(n_var=len(VARIABLES), n_obj=2, n_ieq_constr=2, xl=lo, xu=hi)
            self.rows: dict[tuple[float, ...], dict[str, Any]] = {}

        def _evaluate(self, x_pop: np.ndarray, out: dict[str, Any], *a: Any, **k: Any) -> None:
            xs = [list(map(float, x)) for x in x_pop]
            rows = list(pool.map(_score_x, xs)) if pool else [_score_x(x) for x in xs]
            for x, r in zip(xs, rows, strict=True):
                self.rows[tuple(x)] = r
            big = 1e6  # finite stand-in for unstable (non-finite) bodies
            f = [[min(r["f_distance"], big), r["f_actuation"]] for r in rows]
            g = [
                [
                    min(r["max_tilt_deg"] - max_tilt_deg, big),
                    min(r["max_lift"] - max_lift_frac * r["wheel_radius"], big),
                ]
                for r in rows
            ]
            out["F"], out["G"] = np.array(f), np.array(g)

    return BaseMorphology()


def n_reached(params: EmpiricalParams) -> int:
    """Environments where the canonical robot with ``w = (1, 1)`` touches the light."""
    l1, l2 = canonical_design()
    with EpisodeRunner(params) as runner:
        return sum(runner.run(l1, l2, 1.0, 1.0, env).success for env in range(4))


def perturbations(params: EmpiricalParams, rel: float) -> list[EmpiricalParams]:
    """Each decision variable scaled by ``1 - rel`` and ``1 + rel`` in turn."""
    return [params.replace(**{k: getattr(params, k) * f}) for k in VARIABLES for f in (1.0 - rel, 1.0 + rel)]


def select(table: pd.DataFrame, robustness: Callable[[EmpiricalParams], int], max_checks: int = 30) -> int:
    """Label of the chosen row; fills the ``robust`` column of the rows it checks.

    ``table`` has every evaluated body, with a ``pareto`` column. Rule: feasible bodies that
    reach all 4 lights, Pareto points first, each group by increasing actuation; the first
    whose ``robustness`` is full (every perturbation still reaches all 4) is chosen, else the
    most robust one checked (ties: earlier in that order); at most ``max_checks`` are checked.
    Without any such body: the feasible Pareto point with the most lights reached, then the
    smallest distance objective.
    """
    feas = table[table["feasible"]]
    if feas.empty:
        raise RuntimeError("no feasible (stable) body found; raise the budget or the bounds")
    full = feas[feas["n_success"] == 4].sort_values(
        ["pareto", "f_actuation", "f_distance"], ascending=[False, True, True]
    )
    if full.empty:
        front = feas[feas["pareto"]] if feas["pareto"].any() else feas
        order = front.sort_values(["n_success", "f_distance"], ascending=[False, True])
        return int(order.index[0])
    best, best_n = -1, -1
    for label, row in full.head(max_checks).iterrows():
        n = robustness(EmpiricalParams().replace(**{k: float(row[k]) for k in VARIABLES}))
        table.loc[label, "robust"] = n
        if n > best_n:
            best, best_n = int(label), n
        if n == 2 * len(VARIABLES):
            break
    return best


def optimise(
    budget_evals: int,
    seed: int,
    *,
    pop_size: int = 20,
    workers: int = 1,
    max_tilt_deg: float = 30.0,
    max_lift_frac: float = 0.25,
    robust_rel: float = 0.01,
    verbose: bool = False,
) -> tuple[pd.DataFrame, dict[str, Any]]:
    """Run NSGA-II for ``budget_evals`` body evaluations.

    Returns the final Pareto set (one row per non-dominated body: the six parameters, both
    objectives, per-environment success and contact time, tilt/lift, ``feasible``, ``robust``
    (perturbations out of 12 still reaching all 4 lights, where checked), ``pareto``,
    ``chosen``; the chosen body is added with ``pareto = False`` if it came from outside the
    front) and the chosen body as a full :class:`EmpiricalParams` mapping (``to_dict()``).
    ``attrs["n_evals"]`` counts the distinct bodies NSGA-II evaluated.
    """
    from pymoo.algorithms.moo.nsga2 import NSGA2
    from pymoo.optimize import minimize

    if budget_evals < pop_size:
        raise ValueError(f"budget_evals = {budget_evals} must be >= pop_size = {pop_size}")
    if workers < 1:
        raise ValueError(f"workers = {workers} must be >= 1")
    pool = ProcessPoolExecutor(workers) if workers > 1 else None

    def robustness(params: EmpiricalParams) -> int:
        bodies = perturbations(params, robust_rel)
        reached = pool.map(n_reached, bodies) if pool else map(n_reached, bodies)
        return sum(n == 4 for n in reached)

    try:
        problem = _problem(pool, max_tilt_deg, max_lift_frac)
        res = minimize(
            problem,
            NSGA2(pop_size=pop_size, eliminate_duplicates=True),
            ("n_eval", budget_evals),
            seed=seed,
            verbose=verbose,
        )
        front = {tuple(map(float, x)) for x in np.atleast_2d(res.opt.get("X"))}
        table = pd.DataFrame(list(problem.rows.values()))
        table["pareto"] = [x in front for x in problem.rows]
        table["feasible"] = [
            r["max_tilt_deg"] <= max_tilt_deg and r["max_lift"] <= max_lift_frac * r["wheel_radius"]
            for r in problem.rows.values()
        ]
        table["robust"] = np.nan
        chosen = select(table, robustness)
    finally:
        if pool is not None:
            pool.shutdown()
    table["chosen"] = table.index == chosen
    params = EmpiricalParams().replace(**{k: float(table.loc[chosen, k]) for k in VARIABLES})
    out = table[table["pareto"] | table["chosen"]].sort_values("f_actuation")
    out = out.reset_index(drop=True)
    out.attrs["n_evals"] = len(problem.rows)
    return out, params.to_dict()


def morphology_yaml(
    pareto: pd.DataFrame, chosen: dict[str, Any], *, budget_evals: int, seed: int, **settings: Any
) -> str:
    """YAML text of the chosen body with a header saying how it was produced."""
    row = pareto[pareto["chosen"]].iloc[0]
    reached = ", ".join(
        f"{a} deg: {row[f'time_{a}']:.2f} s" if row[f"success_{a}"] else f"{a} deg: missed" for a in ENV_ANGLES_DEG
    )
    extra = ", ".join(f"{k}={v}" for k, v in settings.items())
    header = [
        "Base morphology of the empirical (pybullet) model.",
        "Produced by morphlearn.empirical.optimise.optimise (NSGA-II, pymoo):",
        f"  budget_evals={budget_evals}, seed={seed}" + (f", {extra}" if extra else ""),
        f"  {pareto.attrs.get('n_evals', '?')} bodies evaluated; Pareto set of {int(pareto['pareto'].sum())}.",
        "Decision variables: body/wheel/castor mass, wheel radius, max speed, max torque.",
        "Objectives (canonical sensors, w = (1, 1)): summed min centre-to-light distance over",
        "  the 4 environments; actuation = max_torque + max_speed. Constraint: tilt <= 30 deg",
        "  and |z - wheel_radius| <= 0.25 wheel_radius in the episodes and a stress test.",
        "Selection rule: the least-actuation feasible Pareto point reaching all 4 lights whose",
        "  12 one-at-a-time +-1 % perturbations also reach all 4 (see optimise.select).",
        f"Chosen: f_distance = {row['f_distance']:.6g}, f_actuation = {row['f_actuation']:.6g}, "
        f"robust {int(row['robust']) if row['robust'] == row['robust'] else '?'}/12, "
        f"Pareto point: {bool(row['pareto'])}",
        f"  w = (1, 1) contact times: {reached}.",
        f"  max tilt {row['max_tilt_deg']:.3g} deg, max lift {row['max_lift']:.3g} m.",
        "Units: kg, m, rad/s, N m, s. Values are exact (the dynamics are sensitive).",
    ]
    body = yaml.safe_dump(chosen, sort_keys=False)
    return "".join(f"# {h}\n" for h in header) + body


def main(argv: Sequence[str] | None = None) -> None:
    """``python -m morphlearn.empirical.optimise --budget N --seed S --out FILE.yaml``."""
    ap = argparse.ArgumentParser(description="Base-morphology optimisation (NSGA-II).")
    ap.add_argument("--budget", type=int, required=True, help="body evaluations")
    ap.add_argument("--seed", type=int, required=True)
    ap.add_argument("--pop-size", type=int, default=20)
    ap.add_argument("--workers", type=int, default=1)
    ap.add_argument("--out", type=Path, help="write the chosen body here (YAML)")
    ap.add_argument("--pareto", type=Path, help="write the Pareto table here (CSV)")
    a = ap.parse_args(argv)
    t0 = time.time()
    pareto, chosen = optimise(a.budget, a.seed, pop_size=a.pop_size, workers=a.workers)
    wall = time.time() - t0
    text = morphology_yaml(pareto, chosen, budget_evals=a.budget, seed=a.seed, pop_size=a.pop_size)
    print(text + f"# wall time {wall:.0f} s with {a.workers} worker(s)")
    if a.out:
        a.out.write_text(text)
    if a.pareto:
        pareto.to_csv(a.pareto, index=False)


if __name__ == "__main__":
    main()
