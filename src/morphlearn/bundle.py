"""A results bundle: the compact, committed record of a finished run.

A bundle is a results folder (same layout, so the figure and reproduction rules render from it
unchanged with ``render_only``) that holds:

- every model's per-design metrics table and its provenance, the summary, the reproduction table
  and persistence counts, and the rendered figures with their captions;
- for each model, ``merged.zarr`` restricted to the designs the figures and the table draw
  (:func:`drawn_designs`), written by :func:`morphlearn.store.write_subset`, which records the
  digest of the full merged dataset it was cut from;
- ``bundle.json``: which run and commit made it, which designs the subsets hold, and the SHA-256
  of every file of the bundle, so :func:`check` can tell a damaged or edited bundle;
- ``README.md``, generated from the above.

The full merged datasets (3.5 GB at paper resolution) and the shards stay out; the run's config
and the command in ``bundle.json`` regenerate them.
"""

from __future__ import annotations

import json
import shutil
from collections.abc import Iterable
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from morphlearn import __version__, metrics, provenance, store
from morphlearn import grid as gridmod

#: Files copied from the run's results folder, when present (paths relative to it).
#: The learner stage's small tables (its figure and reproduction rows read them).
LEARNER_FILES = ("runs.csv", "correlations.csv", "summary.md")
COPIED = (
    "summary.json",
    "summary.md",
    "reproduction.csv",
    "reproduction.md",
    "reproduction.html",
    "persistence.csv",
)
#: Per model.
MODEL_FILES = ("metrics.csv", "metrics.provenance.json")
#: Per figure (the executed notebook's HTML is left out: it is large and re-rendered on demand).
FIGURE_SUFFIXES = (".png", ".pdf", ".caption.md")
MANIFEST = "bundle.json"


class BundleError(ValueError):
    """A bundle that cannot be built or does not check out; the message names the file."""


def drawn_designs(table: pd.DataFrame, n: int, top: int) -> np.ndarray:
    """Designs whose outcome arrays the figures and the reproduction table read.

    The canonical design, the paper's best design, the ``top`` best by M_L and by M_CF (the
    figures draw the best of each, the rest let a reader look at the runners-up), and the mirror
    image of each (ties between mirror images decide which one is "best").
    """
    g = gridmod.DesignGrid(n)
    present = set(table.design.astype(int))
    want = set()
    for design in (gridmod.canonical_design(), gridmod.PAPER_BEST_DESIGN):
        try:
            want.add(g.index_of(*design))
        except ValueError:  # not on this grid (a coarse test grid)
            pass
    for by in ("M_L", "M_CF"):
        want |= set(metrics.rank_designs(table, by).design.head(top).astype(int))
    want |= {int(g.mirror(d)) for d in want}
    return np.array(sorted(d for d in want if d in present), dtype=np.int64)


def made_by(configs: list[str], results_dir: str) -> dict[str, Any]:
    """What made a run: its config files, results folder, the command, commit and version."""
    extra = [c for c in configs if Path(c).name != "config.yaml"]  # config.yaml is always loaded
    command = "snakemake --cores 2" + (f" --configfile {' '.join(extra)}" if extra else "")
    return {"configs": configs, "results_dir": results_dir, "command": command,
            "git_commit": provenance.git_commit(), "version": __version__}  # fmt: skip


def _models(run_dir: Path) -> list[str]:
    return [m for m in ("theory", "empirical") if (run_dir / m / "metrics.csv").is_file()]


def _files(out_dir: Path) -> Iterable[Path]:
    for p in sorted(out_dir.rglob("*")):
        if p.is_file() and p.name != MANIFEST and ".snakemake_timestamp" not in p.name:
            yield p


def build(run_dir: str | Path, out_dir: str | Path, *, positions_per_axis: int, top: int,
          made_by: dict[str, Any]) -> dict[str, Any]:  # fmt: skip
    """Write the bundle of ``run_dir`` to ``out_dir`` (replaced as a whole, atomically)."""
    run_dir, out_dir = Path(run_dir), Path(out_dir)
    models = _models(run_dir)
    if "theory" not in models:
        raise BundleError(f"{run_dir}: no theory/metrics.csv; run the workflow first")
    subsets: dict[str, Any] = {}
    with store.atomic_path(out_dir) as tmp:
        tmp.mkdir(parents=True)
        for name in COPIED:
            if (run_dir / name).is_file():
                shutil.copy2(run_dir / name, tmp / name)
        for model in models:
            (tmp / model).mkdir()
            for name in MODEL_FILES:
                shutil.copy2(run_dir / model / name, tmp / model / name)
            table = pd.read_csv(run_dir / model / "metrics.csv")
            n = positions_per_axis if model == "theory" else _positions_of(run_dir / model)
            designs = drawn_designs(table, n, top) if model == "theory" else np.sort(table.design)
            src = run_dir / model / "merged.zarr"
            store.write_subset(src, designs, tmp / model / "merged.zarr")
            subsets[model] = {"designs": [int(d) for d in designs], "of": len(table)}
        for name in LEARNER_FILES:  # the learner stage (beyond the paper), when the run has it
            if (run_dir / "learners" / name).is_file():
                (tmp / "learners").mkdir(exist_ok=True)
                shutil.copy2(run_dir / "learners" / name, tmp / "learners" / name)
        figs = sorted(p for p in (run_dir / "figures").glob("*") if p.name.endswith(FIGURE_SUFFIXES))
        if figs:
            (tmp / "figures").mkdir()
            for p in figs:
                shutil.copy2(p, tmp / "figures" / p.name)
        manifest = {
            "made_by": made_by,
            "subsets": subsets,
            "files": {str(p.relative_to(tmp)): provenance.sha256_file(p) for p in _files(tmp)},
        }
        (tmp / "README.md").write_text(readme(manifest, run_dir))
        manifest["files"]["README.md"] = provenance.sha256_file(tmp / "README.md")
        manifest["files"] = dict(sorted(manifest["files"].items()))
        (tmp / MANIFEST).write_text(json.dumps(manifest, indent=1, sort_keys=True) + "\n")
    return manifest


def _positions_of(model_dir: Path) -> int:
    """Positions per axis of a model's run, from its merged dataset's science record."""
    sci = store.science_of(store.open_merged(model_dir / "merged.zarr"))
    return int(sci.get("grid", {}).get("positions_per_axis", sci.get("positions_per_axis")))


def check(out_dir: str | Path) -> list[str]:
    """Problems of a bundle (empty: every file listed, present and unchanged, nothing extra)."""
    out_dir = Path(out_dir)
    mpath = out_dir / MANIFEST
    if not mpath.is_file():
        return [f"{mpath}: missing"]
    try:
        listed = json.loads(mpath.read_text())["files"]
    except (ValueError, KeyError) as e:
        return [f"{mpath}: unreadable ({e})"]
    problems = []
    for rel, digest in listed.items():
        p = out_dir / rel
        if not p.is_file():
            problems.append(f"{p}: listed in {MANIFEST} but missing")
        elif provenance.sha256_file(p) != digest:
            problems.append(f"{p}: checksum differs from {MANIFEST} (changed or damaged)")
    for p in _files(out_dir):
        rel = str(p.relative_to(out_dir))
        if rel not in listed and not rel.startswith(_RENDERED):
            problems.append(f"{p}: not listed in {MANIFEST}")
    return problems


#: What a re-render writes beside the bundle's files (logs, benchmarks, notebook HTML).
_RENDERED = ("logs/", "benchmarks/", "figures/fig", ".snakemake")


def readme(manifest: dict[str, Any], run_dir: Path) -> str:
    by = manifest["made_by"]
    sub = manifest["subsets"]
    lines = [
        "# Results bundle",
        "",
        "Generated by the rule `bundle` (morphlearn.bundle); do not edit by hand: `bundle.json` lists",
        "the SHA-256 of every file and `morphlearn check-bundle <folder>` compares them.",
        "",
        f"- Made from the results folder `{by.get('results_dir', run_dir)}` of the config "
        f"`{' + '.join(by.get('configs', ['?']))}`",
        f"  at commit `{by.get('git_commit', '?')}` (package {by.get('version', '?')}).",
        f"- Command that made the run: `{by.get('command', '?')}`",
        "",
        "| path | what |",
        "|---|---|",
        "| `<model>/metrics.csv` (+ `.provenance.json`) | every design: successes per environment, "
        "generalists, M_L, M_CF, flagged trajectories |",
        "| `<model>/merged.zarr` | outcome arrays (first-success time, closest approach, status) "
        "of only the designs listed below; its attributes name the full dataset's digest |",
        "| `summary.{json,md}` | canonical design and its rank, top designs |",
        "| `reproduction.{csv,md,html}`, `persistence.csv` | the paper's numbers beside ours |",
        "| `figures/figN.{png,pdf,caption.md}` | the seven figures and their captions |",
        "",
        "Designs held in the subsets:",
        "",
    ]
    for model, s in sub.items():
        lines.append(f"- {model}: {len(s['designs'])} of {s['of']} designs: {s['designs']}")
    lines += [
        "",
        "Left out (regenerate with the command above; the shards take the CPU time stated in",
        "`docs/performance.md`): the shards, the full merged datasets, logs, benchmarks and the",
        "executed notebooks' HTML (re-rendering writes them).",
        "",
    ]
    return "\n".join(lines)
