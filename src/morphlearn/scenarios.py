"""Named scenarios: overrides of the base config, the simulations that answer them, and their
comparison (docs/scenarios.md).

A scenario file (``config/scenarios.yaml``) maps a name to overrides of the base config, as
PyPSA-eur's ``config/scenarios.yaml`` does. Each scenario is the base config with its overrides,
validated with the same schema; its results go to ``<results_dir>/scenarios/<name>/``.

Work sharing. Scenarios whose theory science differs only in ``theory.horizon`` and
``theory.success_radius`` are answered from as few simulations as possible, because a stored
simulation at horizon ``Ts`` and radius ``rs`` answers a scenario ``(T, rad)`` without
re-simulating when

- ``rad == rs`` and ``T <= Ts``: success iff first-success time <= T (stored exactly);
- ``rad > rs`` and ``T == Ts``: success iff the minimum distance up to ``Ts`` <= rad.

It cannot answer a larger horizon, a smaller radius, or a larger radius at a shorter horizon: the
kernel stops a trajectory at its first entry into ``rs`` and keeps no time of entry into any other
radius. Those scenarios get their own simulation. Simulations are identified by their science
digest (the design cache's key), so two scenarios, or two runs of different subsets, never
simulate the same science twice.
"""

from __future__ import annotations

import copy
import itertools
import json
import math
import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from morphlearn import config as cfgmod
from morphlearn import configure, metrics, models
from morphlearn import grid as gridmod
from morphlearn.settings import Settings

#: The reference scenario every comparison is made against; every scenario file must define it.
BASE = "base"
#: Scenario names: folder names, not starting with '_' (reserved for shared simulations).
NAME_RE = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]*$")
#: Top-level config keys a scenario may override (the theory sweep and its analysis).
OVERRIDABLE = ("grid", "theory", "sweep", "analysis", "design_cache")
PAPER_BEST_DESIGN = gridmod.PAPER_BEST_DESIGN
#: The paper's text values of M_L (canonical, best design); its captions give 57 and 2255 / 14641.
TEXT_CANONICAL_M_L = 0.049
TEXT_BEST_M_L = 0.286

HOW_DIRECT = "simulated"
HOW_HORIZON = "shorter horizon from stored first-success times"
HOW_RADIUS = "larger radius from stored minimum distances"


class ScenarioError(cfgmod.ConfigError):
    """A bad scenario file, name or override (one line, naming it)."""


@dataclass(frozen=True)
class Scenario:
    name: str
    overrides: dict[str, Any]
    settings: Settings  # the scenario "as if simulated"

    @property
    def theory(self) -> Any:
        """Its theory parameters (morphlearn.theory.TheoryParams)."""
        return self.settings.models["theory"].params

    @property
    def horizon(self) -> float:
        return float(self.theory.horizon)

    @property
    def radius(self) -> float:
        return float(self.theory.success_radius)


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


# ---------------------------------------------------------------------------------------------
# Reading and expanding scenarios


def read_file(path: str | Path) -> dict[str, dict[str, Any]]:
    """Scenario name -> overrides, checked for form (names, allowed keys); not yet validated."""
    data = cfgmod._read_yaml(path)
    out: dict[str, dict[str, Any]] = {}
    for name, over in data.items():
        if not isinstance(name, str) or not NAME_RE.match(name):
            raise ScenarioError(
                f"{path}: scenario name {name!r} is invalid; allowed: letters, digits, "
                "'_', '.', '-', not starting with '_' or '.'"
            )
        over = {} if over is None else over
        if not isinstance(over, dict):
            raise ScenarioError(
                f"{path}: scenario {name!r} must be a mapping of config overrides, got {type(over).__name__}"
            )
        bad = sorted(set(over) - set(OVERRIDABLE))
        if bad:
            raise ScenarioError(
                f"{path}: scenario {name!r}: key{'s' if len(bad) > 1 else ''} {bad} "
                f"cannot be overridden; allowed: {list(OVERRIDABLE)}"
            )
        for k in ("horizon", "success_radius"):
            if over.get("analysis", {}).get(k) is not None:
                raise ScenarioError(
                    f"{path}: scenario {name!r}: analysis.{k} is set by the planner; "
                    f"allowed: theory.{k} (derived from a stored simulation if it can be)"
                )
        out[name] = over
    if BASE not in out:
        raise ScenarioError(
            f"{path}: no scenario named {BASE!r}; allowed: a file that defines "
            f"'{BASE}' (the reference of the comparison, usually {{}})"
        )
    return out


def select(available: Iterable[str], wanted: str | Sequence[str]) -> list[str]:
    """The scenarios to run, in file order, always with the base: ``"all"``, a comma-separated
    string of names, or a list of names."""
    avail = list(available)
    names = [s.strip() for s in wanted.split(",")] if isinstance(wanted, str) else [str(s) for s in wanted]
    names = [n for n in names if n]
    if names == ["all"]:
        return avail
    unknown = [n for n in names if n not in avail]
    if unknown or not names:
        raise ScenarioError(
            f"scenarios = {wanted!r}: unknown scenario{'s' if len(unknown) > 1 else ''} "
            f"{unknown}; allowed: 'all' or names from {avail}"
        )
    chosen = {BASE, *names}
    return [n for n in avail if n in chosen]


def expand(base: Settings, file_scenarios: dict[str, dict[str, Any]], names: Sequence[str]) -> list[Scenario]:
    """Each named scenario's settings: base config + overrides, theory only, its own results
    folder ``<results_dir>/scenarios/<name>``."""
    root = scenarios_dir(base)
    out = []
    for name in names:
        over = file_scenarios[name]
        raw = cfgmod.deep_merge(dict(base.source), over)
        raw = cfgmod.deep_merge(
            raw,
            {
                "results_dir": f"{root}/{name}",
                "empirical": {"enabled": False},
                "figures": {"enabled": False},
                "bundle_dir": None,
                "render_only": False,
                "scenarios": None,
            },
        )
        try:
            sc = configure.parse(raw)
        except cfgmod.ConfigError as e:
            raise ScenarioError(f"scenario {name!r}: {e}") from None
        if sc.analysis.horizon is not None or sc.analysis.success_radius is not None:
            raise ScenarioError(
                f"scenario {name!r}: the base config sets analysis.horizon/success_radius; "
                "allowed: null in the base config of a scenario run"
            )
        out.append(Scenario(name, over, sc))
    return out


def scenarios_dir(base: Settings) -> str:
    return f"{base.results_dir}/scenarios"


# ---------------------------------------------------------------------------------------------
# Planning: the fewest simulations that answer every scenario


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


def _group_key(s: Settings) -> str:
    sci = models.get("theory").science(s)
    del sci["theory"]["horizon"], sci["theory"]["success_radius"]
    return cfgmod.digest(sci)


def sim_id(s: Settings) -> str:
    """A simulation's identity: its science digest's prefix (as the design cache's folder)."""
    return cfgmod.digest(models.get("theory").science(s))[:16]


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


def plan_markdown(plan_: Plan, scenarios: Sequence[Scenario]) -> str:
    """The plan as a table: which simulation answers which scenario, and how."""
    lines = [
        "| scenario | r | T | radius | simulation | simulated (r, T, radius) | answered by |",
        "|---|---|---|---|---|---|---|",
    ]
    for s in scenarios:
        a = plan_.answers[s.name]
        th = plan_.sims[a.sim].models["theory"].params
        lines.append(
            f"| {s.name} | {s.theory.r:.6g} | {s.horizon:g} | {s.radius:g} | `{a.sim}` | "
            f"({th.r:.6g}, {th.horizon:g}, {th.success_radius:g}) | {a.how} |"
        )
    own = len({sim_id(s.settings) for s in scenarios})
    lines += [
        "",
        f"{len(plan_.sims)} simulations for {len(scenarios)} scenarios "
        f"({own} if every scenario were simulated as itself).",
    ]
    return "\n".join(lines) + "\n"


# ---------------------------------------------------------------------------------------------
# Comparison


def _label(r: pd.Series) -> str:
    return f"({r.l1x:g},{r.l1y:g}),({r.l2x:g},{r.l2y:g})"


def compare(tables: dict[str, pd.DataFrame], top: int = 10, base: str = BASE) -> pd.DataFrame:
    """One row per scenario, against the base scenario: the canonical design's and the paper's
    best design's M_L / M_CF and rank, the best design by each metric, the overlap of the top
    ``top`` designs with the base's (ranked as the summary ranks), and Kendall's tau-b of the
    designs' M_L (and M_CF) with the base's. Tables are per-design metrics (metrics.csv)."""
    from scipy.stats import kendalltau

    ref = tables[base].set_index("design").sort_index()
    rows = []
    for name, t in tables.items():
        t = t.set_index("design").sort_index()
        if not t.index.equals(ref.index):
            raise ValueError(f"scenario {name!r}: its designs differ from {base!r}'s; allowed: the same grid")
        tr = t.reset_index()
        row: dict[str, Any] = {"scenario": name}
        for label, design in (("canonical", gridmod.canonical_design()), ("paper_best", PAPER_BEST_DESIGN)):
            d = metrics.find_row(tr, design)
            for m in ("M_L", "M_CF"):
                row[f"{label}_{m}"] = float(d[m]) if d is not None else math.nan
                row[f"{label}_rank_{m}"] = metrics.rank_of(tr, d, m) if d is not None else None
        for m in ("M_L", "M_CF"):
            ranked = metrics.rank_designs(tr, m)
            best = ranked.iloc[0]
            row[f"best_{m}_design"] = _label(best)
            row[f"best_{m}"] = float(best[m])
            mine = set(ranked.design.head(top))
            theirs = set(metrics.rank_designs(ref.reset_index(), m).design.head(top))
            row[f"top{top}_overlap_{m}"] = len(mine & theirs)
            row[f"paper_best_in_top{top}_{m}"] = bool(metrics.find_row(ranked.head(top), PAPER_BEST_DESIGN) is not None)
            tau = kendalltau(t[m].to_numpy(), ref[m].to_numpy()).statistic
            row[f"tau_{m}"] = float(tau)
        row["text_distance"] = text_distance(row["canonical_M_L"], row["best_M_L"])
        rows.append(row)
    return pd.DataFrame(rows)


def text_distance(canonical_ml: float, best_ml: float) -> float:
    """How far (canonical M_L, best M_L) is from the paper's text values (0.049, 0.286): the
    Euclidean norm of the two relative errors (0 = both met exactly)."""
    return math.hypot(canonical_ml / TEXT_CANONICAL_M_L - 1, best_ml / TEXT_BEST_M_L - 1)


# ---------------------------------------------------------------------------------------------
# Free search over the thresholds a stored simulation can answer

#: The free threshold scan over every stored simulation: horizons in steps of this, up to the
#: simulated one, and these radii (each where the simulation answers it).
SCAN_HORIZON_STEP = 50.0
SCAN_RADII = (0.1, 0.15, 0.2, 0.3, 0.4, 0.5, 0.6, 0.8, 1.0)


def derivable(
    sim_horizon: float, sim_radius: float, horizons: Iterable[float], radii: Iterable[float]
) -> list[tuple[float, float]]:
    """The (horizon, radius) pairs of the given lists (plus the simulation's own) that a stored
    simulation answers without re-simulating."""
    pairs = {(float(t), float(r)) for t in [*horizons, sim_horizon] for r in [*radii, sim_radius]}
    return sorted(p for p in pairs if answers((sim_horizon, sim_radius), p))


def generalist_fraction(first_time: np.ndarray, min_dist: np.ndarray, th: metrics.Thresholds) -> np.ndarray:
    """M_L per design from arrays of shape (designs, 4, m, m) (metrics.success, metrics.overlap)."""
    o = metrics.overlap(metrics.success(first_time, min_dist, th))
    return (o == 4).mean(axis=(-2, -1))


def threshold_scan(merged: str | Path, pairs: Sequence[tuple[float, float]] | None = None) -> pd.DataFrame:
    """Canonical M_L, best M_L and the paper's best design's M_L at every (horizon, radius) of
    ``pairs`` that the merged store answers (its simulated horizon and radius from its attrs);
    by default every pair of the free scan (SCAN_HORIZON_STEP, SCAN_RADII) it answers."""
    from morphlearn import store

    ds = store.open_merged(merged)
    sci = store.science_of(ds)["theory"]
    ts, rs = float(sci["horizon"]), float(sci["success_radius"])
    if pairs is None:
        horizons = np.arange(SCAN_HORIZON_STEP, ts + SCAN_HORIZON_STEP / 2, SCAN_HORIZON_STEP)
        pairs = derivable(ts, rs, horizons, SCAN_RADII)
    ft, md = [], []
    for _, arrays in store.read_blocks(ds):
        ft.append(arrays["first_time"])
        md.append(arrays["min_dist"])
    first_time, min_dist = np.concatenate(ft), np.concatenate(md)
    coords = pd.DataFrame({c: ds[c].values for c in ("l1x", "l1y", "l2x", "l2y")})
    canon = metrics.find_row(coords, gridmod.canonical_design()).name
    best = metrics.find_row(coords, PAPER_BEST_DESIGN)
    rows = []
    for t, r in pairs:
        if not answers((ts, rs), (t, r)):
            allowed = derivable(ts, rs, [t], [r]) or "none"
            raise ValueError(
                f"(horizon {t}, radius {r}) is not answered by the simulation at "
                f"(horizon {ts}, radius {rs}); allowed: {allowed}"
            )
        ml = generalist_fraction(first_time, min_dist, metrics.Thresholds(t, r, ts, rs))
        rows.append(
            {
                "r": float(sci["r"]),
                "horizon": t,
                "radius": r,
                "canonical_M_L": float(ml[canon]),
                "best_M_L": float(ml.max()),
                "best_design": _label(coords.iloc[int(ml.argmax())]),
                "paper_best_M_L": float(ml[best.name]) if best is not None else math.nan,
                "text_distance": text_distance(float(ml[canon]), float(ml.max())),
            }
        )
    return pd.DataFrame(rows)


# ---------------------------------------------------------------------------------------------
# What the workflow's scenario rules do (their scripts only unpack and call)


def run_metrics(
    th: metrics.Thresholds, merged: str | Path, out_csv: str | Path, record: dict[str, Any], out_json: str | Path
) -> None:
    """A scenario's metrics from its simulation at its thresholds (Plan.thresholds), and its record
    (overrides, simulation, how it is answered)."""
    from morphlearn import rules, store

    rules.run_metrics("theory", th, merged, out_csv)
    with store.atomic_path(Path(out_json)) as tmp:
        tmp.write_text(json.dumps(record, indent=1, sort_keys=True) + "\n")


def run_compare(
    tables: dict[str, str],
    merged: dict[str, str],
    top: int,
    out_csv: str | Path,
    out_md: str | Path,
    out_scan: str | Path,
    plan_md: str,
    out_record: str | Path | None = None,
) -> None:
    """The comparison table (compare), and the threshold scan of every simulation for the
    paper's text values (threshold_scan), closest first; with ``out_record`` their sealed record.
    Every scenario's table is checked against its record before it is read (custody)."""
    from morphlearn import provenance, store

    for p in tables.values():
        provenance.check_derived(p)
    comp = compare({n: pd.read_csv(p) for n, p in tables.items()}, top=top)
    scans = [threshold_scan(path).assign(simulation=sid) for sid, path in merged.items()]
    scan = pd.concat(scans, ignore_index=True).sort_values(["text_distance", "r", "horizon", "radius"])
    with store.atomic_path(Path(out_csv)) as tmp:
        comp.to_csv(tmp, index=False, float_format="%.6g")
    with store.atomic_path(Path(out_scan)) as tmp:
        scan.to_csv(tmp, index=False, float_format="%.6g")
    with store.atomic_path(Path(out_md)) as tmp:
        tmp.write_text(comparison_markdown(comp, scan, top, plan_md))
    if out_record is not None:
        # the scenarios vary the theory, the reference model: its libraries
        rec = provenance.record(
            {"scenarios": sorted(tables), "top": top}, [*tables.values()], models.get(models.REFERENCE).libraries
        )
        provenance.write_sealed(out_record, rec, [out_csv, out_md, out_scan])


def comparison_markdown(comp: pd.DataFrame, scan: pd.DataFrame, top: int, plan_md: str) -> str:
    lines = [
        "# Scenarios",
        "",
        "## How each scenario is answered",
        "",
        plan_md.strip(),
        "",
        f"## Against the base scenario (top {top} by each metric; tau: Kendall's tau-b of all designs' values)",
        "",
        f"| scenario | canonical M_L (rank) | paper's best M_L (rank) | in top {top} | best by M_L | "
        f"best by M_CF | top-{top} overlap M_L / M_CF | tau M_L | tau M_CF |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for _, r in comp.iterrows():
        lines.append(
            f"| {r.scenario} | {r.canonical_M_L:.4f} ({r.canonical_rank_M_L}) | "
            f"{r.paper_best_M_L:.4f} ({r.paper_best_rank_M_L}) | "
            f"{'yes' if r[f'paper_best_in_top{top}_M_L'] else 'no'} | {r.best_M_L_design} {r.best_M_L:.4f} | "
            f"{r.best_M_CF_design} {r.best_M_CF:.4f} | {r[f'top{top}_overlap_M_L']} / {r[f'top{top}_overlap_M_CF']} | "
            f"{r.tau_M_L:.3f} | {r.tau_M_CF:.3f} |"
        )
    best = scan.head(10)
    lines += [
        "",
        f"## The paper's text values (canonical M_L {TEXT_CANONICAL_M_L}, best M_L {TEXT_BEST_M_L})",
        "",
        "Every (horizon, radius) each stored simulation answers without re-simulating "
        f"(horizons in steps of {SCAN_HORIZON_STEP:g}, radii {list(SCAN_RADII)}), closest first "
        "(distance: norm of the two relative errors).",
        "",
        "| r | T | radius | canonical M_L | best M_L (design) | paper's best M_L | distance |",
        "|---|---|---|---|---|---|---|",
    ]
    for _, r in best.iterrows():
        lines.append(
            f"| {r.r:.6g} | {r.horizon:g} | {r.radius:g} | {r.canonical_M_L:.4f} | "
            f"{r.best_M_L:.4f} {r.best_design} | {r.paper_best_M_L:.4f} | "
            f"{r.text_distance:.3f} |"
        )
    return "\n".join(lines) + "\n"
