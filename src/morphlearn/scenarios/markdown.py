"""The plan and the comparison as Markdown (the scenario_compare rule's comparison.md)."""

from __future__ import annotations

from collections.abc import Sequence

import pandas as pd

from morphlearn.scenarios.comparison import TEXT_BEST_M_L, TEXT_CANONICAL_M_L
from morphlearn.scenarios.definition import Scenario
from morphlearn.scenarios.plan import Plan, sim_id
from morphlearn.scenarios.scan import SCAN_HORIZON_STEP, SCAN_RADII


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
