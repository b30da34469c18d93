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

Modules, by job (imports point down this list):

- :mod:`.steps`: what the workflow's scenario rules do (their scripts only unpack and call);
- :mod:`.markdown`: the plan and the comparison as Markdown;
- :mod:`.scan`: the free search over the thresholds a stored simulation answers;
- :mod:`.comparison`: every scenario against the base, and the distance to the paper's text values;
- :mod:`.plan`: the fewest simulations that answer every scenario;
- :mod:`.definition`: the scenario file, read, selected and expanded into settings (the config).

The names below are re-exported so ``from morphlearn import scenarios`` (the Snakefile, the rule
scripts, the scenarios notebook) reads one namespace; the modules import each other, never this one.
"""

from __future__ import annotations

from morphlearn.scenarios.comparison import (
    PAPER_BEST_DESIGN,
    TEXT_BEST_M_L,
    TEXT_CANONICAL_M_L,
    compare,
    text_distance,
)
from morphlearn.scenarios.definition import (
    BASE,
    NAME_RE,
    OVERRIDABLE,
    Scenario,
    ScenarioError,
    expand,
    read_file,
    scenarios_dir,
    select,
)
from morphlearn.scenarios.markdown import comparison_markdown, plan_markdown
from morphlearn.scenarios.plan import HOW_DIRECT, HOW_HORIZON, HOW_RADIUS, Answer, Plan, answers, plan, sim_id
from morphlearn.scenarios.scan import (
    SCAN_HORIZON_STEP,
    SCAN_RADII,
    derivable,
    generalist_fraction,
    threshold_scan,
)
from morphlearn.scenarios.steps import run_compare, run_metrics

__all__ = [
    "BASE",
    "HOW_DIRECT",
    "HOW_HORIZON",
    "HOW_RADIUS",
    "NAME_RE",
    "OVERRIDABLE",
    "PAPER_BEST_DESIGN",
    "SCAN_HORIZON_STEP",
    "SCAN_RADII",
    "TEXT_BEST_M_L",
    "TEXT_CANONICAL_M_L",
    "Answer",
    "Plan",
    "Scenario",
    "ScenarioError",
    "answers",
    "compare",
    "comparison_markdown",
    "derivable",
    "expand",
    "generalist_fraction",
    "plan",
    "plan_markdown",
    "read_file",
    "run_compare",
    "run_metrics",
    "scenarios_dir",
    "select",
    "sim_id",
    "text_distance",
    "threshold_scan",
]
