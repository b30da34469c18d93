"""Planning: the fewest simulations that answer every scenario (the package docstring has when a
stored simulation answers a scenario), and each scenario's thresholds on its simulation."""

from __future__ import annotations

import copy
import itertools
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

from morphlearn import config as cfgmod
from morphlearn import configure, metrics, models
from morphlearn.scenarios.definition import BASE, Scenario
from morphlearn.settings import Settings

HOW_DIRECT = "simulated"
HOW_HORIZON = "shorter horizon from stored first-success times"
HOW_RADIUS = "larger radius from stored minimum distances"


@dataclass(frozen=True)
class Answer:
    """How a scenario is answered: which simulation, and the thresholds applied to it."""

    scenario: str
    sim: str
    how: str
    horizon: float
    radius: float


@dataclass
class Plan:
    #: id -> the simulation's settings (its ``source``, the validated config, is what its rules
    #: receive as a parameter and parse again at their edge)
    sims: dict[str, Settings] = field(default_factory=dict)
    answers: dict[str, Answer] = field(default_factory=dict)  # scenario -> answer

    def thresholds(self, scenario: str) -> metrics.Thresholds:
        """The scenario's thresholds on its simulation (the simulated value itself where equal, as
        the simulation's own metrics would record it)."""
        a = self.answers[scenario]
        p = self.sims[a.sim].models["theory"].params
        return metrics.Thresholds(
            horizon=p.horizon if a.horizon == p.horizon else a.horizon,
            radius=p.success_radius if a.radius == p.success_radius else a.radius,
            sim_horizon=p.horizon,
            sim_radius=p.success_radius,
        )

    def config(self, sim: str) -> dict[str, Any]:
        """A simulation's validated config, as a rule parameter."""
        return copy.deepcopy(dict(self.sims[sim].source))


def answers(sim: tuple[float, float], need: tuple[float, float]) -> str | None:
    """How a simulation at (horizon, radius) ``sim`` answers ``need``, or None if it cannot."""
    (ts, rs), (t, r) = sim, need
    if r == rs and t == ts:
        return HOW_DIRECT
    if r == rs and t < ts:
        return HOW_HORIZON
    if r > rs and t == ts:
        return HOW_RADIUS
    return None


def _cover(needs: list[tuple[float, float]], base_need: tuple[float, float] | None) -> list[tuple[float, float]]:
    """Fewest simulations answering every need; then the least total horizon (cost grows with it);
    then the base simulated as itself; then the most scenarios simulated as themselves."""
    cands = sorted({(t, r) for t, _ in needs for _, r in needs})
    if len(cands) > 16:  # exhaustive search too large: each need simulated as itself
        return sorted(set(needs))
    for k in range(1, len(set(needs)) + 1):
        best, best_key = None, None
        for combo in itertools.combinations(cands, k):
            if not all(any(answers(s, n) for s in combo) for n in needs):
                continue
            key = (sum(t for t, _ in combo), base_need not in combo, -sum(n in combo for n in set(needs)), combo)
            if best_key is None or key < best_key:
                best, best_key = list(combo), key
        if best is not None:
            return best
    raise AssertionError("unreachable: the needs themselves cover")


def _theory_science(s: Settings) -> dict[str, Any]:
    """The reference model's (the theory's) science of ``s``."""
    return models.get(models.REFERENCE).science(s)


def _group_key(s: Settings) -> str:
    sci = _theory_science(s)
    del sci["theory"]["horizon"], sci["theory"]["success_radius"]
    return cfgmod.digest(sci)


def sim_id(s: Settings) -> str:
    """A simulation's identity: its science digest's prefix (as the design cache's folder)."""
    return cfgmod.digest(_theory_science(s))[:16]


def plan(scenarios: Sequence[Scenario], cache_results_dir: str) -> Plan:
    """The simulations to run and how each scenario is answered from them. Each simulation's
    ``results_dir`` is ``cache_results_dir`` (the base config's), so its design cache is the main
    run's: designs already finished under the same science there are reused."""
    out = Plan()
    groups: dict[str, list[Scenario]] = {}
    for s in scenarios:
        groups.setdefault(_group_key(s.settings), []).append(s)
    for members in groups.values():
        needs = [(s.horizon, s.radius) for s in members]
        base_need = next(((s.horizon, s.radius) for s in members if s.name == BASE), None)
        chosen = _cover(needs, base_need)
        for s in members:
            # prefer the simulation of the scenario itself, then one with the same radius
            options = [(answers(c, (s.horizon, s.radius)), c) for c in chosen]
            rank = {HOW_DIRECT: 0, HOW_HORIZON: 1, HOW_RADIUS: 2}
            how, (ts, rs) = min(((h, c) for h, c in options if h), key=lambda x: (rank[x[0]], x[1]))
            sim = configure.parse(
                cfgmod.deep_merge(
                    dict(s.settings.source),
                    {
                        "theory": {"horizon": ts, "success_radius": rs},
                        "analysis": {"horizon": None, "success_radius": None},
                        "results_dir": cache_results_dir,
                    },
                )
            )
            sid = sim_id(sim)
            out.sims.setdefault(sid, sim)
            out.answers[s.name] = Answer(s.name, sid, how, s.horizon, s.radius)
    return out
