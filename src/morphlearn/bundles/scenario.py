"""The scenario set's results bundle: the small, committed record of a scenario run
(``snakemake --cores 2 --config scenarios=all``; docs/scenarios.md), like ``morphlearn.bundles.make``'s
for a main run.

It holds what the comparison figure and the numbers in docs/ come from, and nothing that needs the
simulations: ``comparison.{csv,md}``, ``text_values.csv``, the figure ``comparison.{png,pdf}`` and
its caption, per scenario its metrics table, summary and ``scenario.json``, what the run cost
(every job's benchmark), a README, and ``bundle.json`` with the SHA-256 of every file (the same
manifest as a main bundle's, so ``morphlearn check-bundle`` checks it). The simulations
(``_sims/``: shards and merged stores, about 25 CPU-minutes) stay out; the command in
``bundle.json`` regenerates them.

:func:`render` re-renders the figure from a bundle alone, as the rule ``scenario_report`` does
(papermill on notebooks/scenarios.ipynb), and checks it against the manifest: the figure renders
from a fresh clone, to the same bytes. Usage::

    python -m morphlearn.bundles.scenario build results/scenarios results/scenario-set
    python -m morphlearn.bundles.scenario render results/scenario-set
"""

from __future__ import annotations

import argparse
import json
import shutil
import sys
from pathlib import Path
from typing import Any

import pandas as pd

from morphlearn import __version__, config, provenance, store
from morphlearn.bundles import check as bundle_check
from morphlearn.bundles import make as bundlemod
from morphlearn.bundles import render as bundle_render

#: Files of the scenario folder copied as they are (paths relative to it).
DATA = ("comparison.csv", "comparison.md", "text_values.csv")
#: The figure: rendered again from the bundle's copy of the data (its caption names the data files).
FIGURE = ("comparison.png", "comparison.pdf", "comparison.caption.md")
TOP = DATA + FIGURE
#: Per scenario.
PER_SCENARIO = ("scenario.json", "summary.json", "summary.md", "theory/metrics.csv", "theory/metrics.provenance.json")
NOTEBOOK = "notebooks/scenarios.ipynb"
COMMAND = "snakemake --cores 2 --config scenarios=all"


def scenario_names(scen_dir: Path) -> list[str]:
    """The scenarios of a run: the rows of its comparison table, in its order."""
    return [str(s) for s in pd.read_csv(scen_dir / "comparison.csv").scenario]


def run_cost(scen_dir: Path) -> pd.DataFrame:
    """One row per job with a benchmark file anywhere under the scenario folder (the simulations'
    under ``_sims/<id>/benchmarks/``, each scenario's, the comparison's)."""
    rows = []
    for p in sorted(scen_dir.rglob("benchmarks/*.tsv")):
        t = pd.read_csv(p, sep="\t")
        if len(t):
            job = str(p.relative_to(scen_dir).with_suffix("")).replace("benchmarks/", "")
            rows.append(
                {
                    "job": job,
                    "wall_s": float(t.s.iloc[-1]),
                    "cpu_s": float(t.cpu_time.iloc[-1]),
                    "max_rss_mb": float(t.max_rss.iloc[-1]),
                }
            )
    return pd.DataFrame(rows, columns=["job", "wall_s", "cpu_s", "max_rss_mb"])


def build(
    scen_dir: str | Path, out_dir: str | Path, made_by: dict[str, Any], root: str | Path | None = None
) -> dict[str, Any]:
    """Write the bundle of a finished scenario run to ``out_dir`` (a folder ``results/<name>``).

    The data files are copied (the folder replaced as a whole, atomically); then the figure is
    rendered from the bundle's own copies, so that its caption names them and :func:`render` gives
    the same bytes; then ``bundle.json`` is written (a bundle whose rendering failed has none, and
    ``check`` refuses it)."""
    scen_dir, out_dir = Path(scen_dir), Path(out_dir)
    missing = [n for n in TOP if not (scen_dir / n).is_file()]
    if missing:
        raise bundlemod.BundleError(f"{scen_dir}: no {', '.join(missing)}; run the scenarios first ({COMMAND})")
    names = scenario_names(scen_dir)
    # which commits simulated each shard (the merged stores' record), which may differ from the
    # commit that made the bundle
    sims = {p.parent.name: bundlemod._simulated_by(p) for p in sorted(scen_dir.glob("_sims/*/merged.zarr"))}
    manifest: dict[str, Any] = {"made_by": made_by, "scenarios": names, "simulated_by": sims, "files": {}}
    cost = run_cost(scen_dir)
    with store.atomic_path(out_dir) as tmp:
        tmp.mkdir(parents=True)
        for n in DATA:
            shutil.copy2(scen_dir / n, tmp / n)
        for s in names:
            for n in PER_SCENARIO:
                if (scen_dir / s / n).is_file():
                    (tmp / s / n).parent.mkdir(parents=True, exist_ok=True)
                    shutil.copy2(scen_dir / s / n, tmp / s / n)
        if len(cost):
            cost.to_csv(tmp / bundlemod.COST, index=False, float_format="%.2f")
        (tmp / "README.md").write_text(readme(manifest, cost))
    _render(out_dir, root)
    listed = [
        p
        for p in sorted(out_dir.rglob("*"))
        if p.is_file() and p.name != bundlemod.MANIFEST and "logs" not in p.relative_to(out_dir).parts
    ]
    manifest["files"] = {str(p.relative_to(out_dir)): provenance.sha256_file(p) for p in listed}
    (out_dir / bundlemod.MANIFEST).write_text(json.dumps(manifest, indent=1, sort_keys=True) + "\n")
    return manifest


def readme(manifest: dict[str, Any], cost: pd.DataFrame) -> str:
    by = manifest["made_by"]
    lines = [
        "# Scenario-set bundle",
        "",
        "Generated by `python -m morphlearn.bundles.scenario build` (morphlearn.bundles.scenario); do not edit",
        "by hand: `bundle.json` lists the SHA-256 of every file and `morphlearn check-bundle <folder>` compares them.",
        "",
        f"- Bundled from `{by.get('results_dir', '?')}` at commit `{by.get('git_commit', '?')}` "
        f"(package {by.get('version', '?')}).",
        f"- Command that made the run: `{by.get('command', COMMAND)}` (scenarios: `config/scenarios.yaml`).",
        f"- Scenarios: {', '.join(manifest['scenarios'])}.",
        "",
        "| path | what |",
        "|---|---|",
        "| `comparison.{csv,md}` | per scenario: how it is answered, the canonical and the paper's best design's "
        "M_L, M_CF and rank, the best designs, top-10 overlap and Kendall's tau with the base |",
        "| `text_values.csv` | canonical and best M_L at every horizon and radius the stored simulations answer |",
        "| `comparison.{png,pdf}`, `comparison.caption.md` | the comparison figure (notebooks/scenarios.ipynb) |",
        "| `<scenario>/theory/metrics.csv` (+ `.provenance.json`) | the scenario's metrics of every design |",
        "| `<scenario>/summary.{json,md}`, `<scenario>/scenario.json` | its summary; its overrides, parameters and "
        "the simulation that answers it |",
        f"| `{bundlemod.COST}` | each job's wall and CPU seconds and peak memory (its benchmark file) |",
        "",
        "Re-render the figure from this folder alone (papermill, as the rule `scenario_report`), then compare",
        "every file with `bundle.json`: `python -m morphlearn.bundles.scenario render <folder>`.",
    ]
    sims = manifest.get("simulated_by", {})
    if sims:
        lines += ["", "Simulations (`_sims/<id>`, left out) and the commits that simulated their shards:", ""]
        lines += [
            f"- `{sid}`: " + ", ".join(f"{k}: {v}" for k, v in by.get("git_commits", {}).items())
            for sid, by in sims.items()
        ]
    if len(cost):
        lines += [
            "",
            "What the run cost (sums of the jobs' benchmark files; wall seconds add up jobs that ran "
            "side by side; the machine was shared):",
            "",
            *bundlemod.cost_lines(cost),
        ]
    lines += [
        "",
        "Left out: the simulations (`_sims/`: shards and merged stores), logs and benchmarks; the command "
        "above regenerates them.",
        "",
    ]
    return "\n".join(lines)


def _params(rel: Path, style: str) -> dict[str, str]:
    return {
        "comparison": str(rel / "comparison.csv"),
        "scan": str(rel / "text_values.csv"),
        "style": style,
        "png": str(rel / "comparison.png"),
        "pdf": str(rel / "comparison.pdf"),
        "caption": str(rel / "comparison.caption.md"),
    }


def _render(out_dir: Path, root: str | Path | None) -> float:
    """Render the comparison figure from a bundle's files, in place, as the rule ``scenario_report``
    does (:func:`morphlearn.bundles.render.figure_in_place`)."""
    return bundle_render.figure_in_place(out_dir, root, NOTEBOOK, "comparison.ipynb", _params)


def render(out_dir: str | Path, root: str | Path | None = None) -> tuple[float, list[str]]:
    """Re-render the comparison figure of a bundle in place; returns the wall seconds and the
    problems :func:`morphlearn.bundles.check.check` then finds (empty: the figure came out byte-identical)."""
    seconds = _render(Path(out_dir), root)
    return seconds, bundle_check.check(out_dir)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m morphlearn.bundles.scenario", description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    b = sub.add_parser("build", help="bundle a finished scenario run")
    b.add_argument("scenarios_dir", help="the run's scenario folder (results/scenarios)")
    b.add_argument("bundle_dir", help="where to write the bundle (results/scenario-set)")
    r = sub.add_parser("render", help="re-render a bundle's figure and check the bundle")
    r.add_argument("bundle_dir")
    a = ap.parse_args(argv)
    if a.cmd == "build":
        why = config.place_refusal(a.bundle_dir)  # the write guard every writer shares (config.write_refusal)
        if why:
            print(f"bundle_dir {a.bundle_dir!r} {why}; nothing was written; allowed: {config.RESULTS_ALLOWED}")
            return 2
        made_by = {
            "results_dir": a.scenarios_dir,
            "command": COMMAND,
            "git_commit": provenance.git_commit(),
            "version": __version__,
        }
        m = build(a.scenarios_dir, a.bundle_dir, made_by)
        print(f"{a.bundle_dir}: {len(m['files'])} files, scenarios {', '.join(m['scenarios'])}")
        return 0
    return bundle_render.report_in_place(a.bundle_dir, *render(a.bundle_dir))


if __name__ == "__main__":
    sys.exit(main())
