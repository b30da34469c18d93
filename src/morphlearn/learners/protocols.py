"""The two training protocols, as generators, and the driver that batches many runs.

A run is a generator: it yields a request ``(env_idx, w)`` (trajectories it needs: environment
indices (k,) and weights (k, 2)) and receives ``(loss, success)`` for them. The driver advances
every run of a batch together and evaluates all their requests in one kernel call, so Python's
per-step cost is shared and the cores see large batches; a run's numbers do not depend on its
neighbours (each learner has its own generator).

- **joint**: the learner minimises the joint loss (all four environments); ``budget`` controller
  evaluations (4 trajectories each). A generalist is reached at the first evaluated controller
  that succeeds in all four; the elitist incumbent then is one (the joint loss ranks generalists
  first), so joint runs end on a generalist exactly when they reach one.
- **sequential**: phases of ``per_phase`` evaluations (1 trajectory each) on one environment's
  loss, in the fixed order 45, 135, 225, 315 degrees, ``cycles`` times. The incumbent of a phase
  is its best controller on that phase's environment, starting from the previous incumbent
  (elitist: training never loses the current environment). After every phase the incumbent is
  measured in all four environments (4 trajectories, not counted in the learner's budget; the
  next environment's loss is taken from it). Generalist reached: an incumbent after some phase
  succeeds in all four; forgetting: an environment the incumbent solved after one phase and no
  longer solves after the next (the environment trained in that next phase is not counted: it
  cannot be lost there). Joint and sequential runs simulate the same number of learner
  trajectories when ``budget * 4 == cycles * 4 * per_phase``.
"""

from __future__ import annotations

import math
from collections.abc import Generator, Iterable
from dataclasses import asdict, dataclass

import numpy as np

from morphlearn.learners import algorithms
from morphlearn.learners.objective import N_ENV, Evaluator, joint_loss

PROTOCOLS = ("joint", "sequential")
Request = tuple[np.ndarray, np.ndarray]
Reply = tuple[np.ndarray, np.ndarray]
Run = Generator[Request, Reply, "RunResult"]


@dataclass(frozen=True)
class RunResult:
    """One learner run. ``evals_to_generalist`` is NaN when none was reached; the forgetting
    counts are 0 in the joint protocol. ``incumbent``: the final incumbent's search point (joint:
    the best evaluated by the joint loss; sequential: the last phase's), for where co-optimised
    bodies end up."""

    reached: bool
    evals_to_generalist: float
    final_generalist: bool
    forget_events: int
    forget_opportunities: int
    evaluations: int
    incumbent: tuple[float, ...] = ()


def joint(learner: algorithms.Learner, budget: int) -> Run:
    evals = 0
    first = math.nan
    best_f, best_x = math.inf, None
    while evals < budget:
        x = learner.ask()[: budget - evals]
        n = len(x)
        loss, ok = yield np.tile(np.arange(N_ENV), n), np.repeat(x, N_ENV, axis=0)
        loss, ok = loss.reshape(n, N_ENV), ok.reshape(n, N_ENV)
        f = joint_loss(loss)
        gen = ok.all(axis=1)
        if math.isnan(first) and gen.any():
            first = float(evals + 1 + int(np.argmax(gen)))
        evals += n
        i = int(np.argmin(f))
        if f[i] < best_f:
            best_f, best_x = float(f[i]), x[i]
        learner.tell(x, f)
    reached = not math.isnan(first)
    return RunResult(reached, first, reached, 0, 0, evals, _point(best_x))


def sequential(learner: algorithms.Learner, per_phase: int, cycles: int, order: Iterable[int] = range(N_ENV)) -> Run:
    order = list(order)
    evals = 0
    first = math.nan
    inc_x: np.ndarray | None = None
    inc_f = math.inf
    prev: np.ndarray | None = None  # incumbent's successes after the previous phase
    events = opportunities = 0
    measured_loss: np.ndarray | None = None
    for phase in range(cycles * len(order)):
        env = order[phase % len(order)]
        if inc_x is not None and measured_loss is not None:
            inc_f = float(measured_loss[env])  # the objective changed under the incumbent
            learner.rescore(inc_f)
        done = 0
        while done < per_phase:
            x = learner.ask()[: per_phase - done]
            loss, _ = yield np.full(len(x), env), x
            i = int(np.argmin(loss))
            if loss[i] <= inc_f:
                inc_x, inc_f = x[i].copy(), float(loss[i])
            learner.tell(x, loss)
            done += len(x)
        evals += done
        measured_loss, ok = yield np.arange(N_ENV), np.repeat(inc_x[None, :], N_ENV, axis=0)
        if prev is not None:
            kept = np.arange(N_ENV) != env
            opportunities += int((prev & kept).sum())
            events += int((prev & kept & ~ok).sum())
        if math.isnan(first) and ok.all():
            first = float(evals)
        prev = ok
    reached = not math.isnan(first)
    return RunResult(reached, first, bool(prev is not None and prev.all()), events, opportunities, evals, _point(inc_x))


def _point(x: np.ndarray | None) -> tuple[float, ...]:
    return () if x is None else tuple(float(v) for v in x)


def drive(evaluator: Evaluator, runs: list[tuple[int, Run]]) -> list[RunResult]:
    """Advance runs ``(design_idx, generator)`` together, one kernel call per round."""
    results: list[RunResult | None] = [None] * len(runs)
    pending: dict[int, Request] = {}
    for k, (_, g) in enumerate(runs):
        pending[k] = next(g)
    while pending:
        keys = list(pending)
        sizes = [len(pending[k][0]) for k in keys]
        d_idx = np.concatenate([np.full(s, runs[k][0]) for k, s in zip(keys, sizes, strict=True)])
        e_idx = np.concatenate([pending[k][0] for k in keys])
        w = np.concatenate([pending[k][1] for k in keys])
        loss, ok = evaluator(d_idx, e_idx, w)
        at = 0
        for k, s in zip(keys, sizes, strict=True):
            try:
                pending[k] = runs[k][1].send((loss[at : at + s], ok[at : at + s]))
            except StopIteration as stop:
                results[k] = stop.value
                del pending[k]
            at += s
    return [r for r in results if r is not None]


def as_dict(r: RunResult) -> dict[str, float | int | bool]:
    return asdict(r)
