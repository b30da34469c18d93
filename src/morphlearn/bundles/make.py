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
import re
import shutil
from collections.abc import Iterable
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from morphlearn import __version__, bounded, metrics, models, provenance, store
from morphlearn import grid as gridmod
from morphlearn.config import bundle_holding, place_refusal

#: Files copied from the run's results folder, when present (paths relative to it).
#: The learner stage's small tables (its figure and reproduction rows read them).
LEARNER_FILES = ("runs.csv", "correlations.csv", "summary.md", "correlations.provenance.json")
COPIED = (
    "summary.json",
    "summary.md",
    "reproduction.csv",
    "reproduction.md",
    "reproduction.html",
    "persistence.csv",
    "summary.provenance.json",
    "reproduction.provenance.json",
)
#: Per model.
MODEL_FILES = ("metrics.csv", "metrics.provenance.json")
#: Per figure (the executed notebook's HTML is left out: it is large and re-rendered on demand).
FIGURE_SUFFIXES = (".png", ".pdf", ".caption.md")
MANIFEST = "bundle.json"
#: What the run cost, per job, from its rules' benchmark files (measured times: unlike the
#: results, these differ from run to run).
COST = "run_cost.csv"


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
    for by in metrics.METRICS:
        want |= set(metrics.rank_designs(table, by).design.head(top).astype(int))
    want |= {int(g.mirror(d)) for d in want}
    return np.array(sorted(d for d in want if d in present), dtype=np.int64)


#: Where a bundled run's config files may lie: a relative path inside the project, of plain words,
#: ending .yaml or .yml (check-bundle's rule, bundles.check.CONFIG_NAME: a bundle made from a
#: config outside the project, "../my.yaml" or "/tmp/my.yaml", was written and then refused by
#: check-bundle and the explorer).
CONFIG_LOCATION = re.compile(r"(?!/)(?!-)(?!.*(^|/)\.\.(/|$))[\w./-]+\.ya?ml")


def check_config_locations(configs: list[str]) -> None:
    """Refuse (BundleError, before anything runs) a config file check-bundle would not read."""
    for c in configs:
        if not CONFIG_LOCATION.fullmatch(c):
            raise BundleError(
                f"--configfile {c}: a bundle's config files must lie inside the project (check-bundle and the "
                "explorer read them there); allowed: a relative YAML path below the project root, e.g. "
                "config/mine.yaml or mine.yaml; nothing was run"
            )


def command_of(configs: list[str]) -> str:
    """The command a bundle's ``made_by`` records for a run of ``configs`` (check-bundle recomputes it)."""
    extra = [c for c in configs if Path(c).name != "config.yaml"]  # config.yaml is always loaded
    return "snakemake --cores 2" + (f" --configfile {' '.join(extra)}" if extra else "")


def made_by(configs: list[str], results_dir: str) -> dict[str, Any]:
    """What made a run: its config files, results folder, the command, commit and version."""
    return {
        "configs": configs,
        "results_dir": results_dir,
        "command": command_of(configs),
        "git_commit": provenance.git_commit(),
        "version": __version__,
    }


def check_committed(made_by: dict[str, Any], run_dir: str | Path, simulated: list[str]) -> None:
    """A bundle names the commit that made it, so it is made from committed code only: refuse
    (BundleError) a dirty worktree, and shards of this run's simulated models made from one (the
    record would claim a commit that did not make them; a worktree's diff is not recorded), and
    any commit named (the bundle's, its designs') that is not HEAD or an ancestor of it, where a
    repository answers (:func:`provenance.in_history`). Results read from another bundle keep that
    bundle's record."""
    if provenance.uncommitted(made_by["git_commit"]):
        raise BundleError(
            f"the worktree is at {made_by['git_commit']}: a bundle is made from committed code only; "
            "allowed: commit (or stash) the changes, then run the bundle rule again (finished shards are kept)"
        )
    named = {made_by["git_commit"]: "the bundle"}
    for model in simulated:
        by = _simulated_by(Path(run_dir) / model / "merged.zarr")
        # per design where the shards record it (a design reused from the design cache keeps its commit)
        commits = by.get("design_commits") or by.get("git_commits", {})
        bad = sorted(c for c in commits if provenance.uncommitted(c))
        if bad:
            raise BundleError(
                f"{run_dir}/{model}: {sum(commits[c] for c in bad)} design(s) or shard(s) were simulated at {bad[0]}, "
                "not a commit; allowed: shards made at a clean commit (delete those shards and the design "
                "cache entries of that run, or re-run from a clean worktree)"
            )
        named |= {c: f"{commits[c]} design(s) or shard(s) of {run_dir}/{model}" for c in commits if c not in named}
    # A clean-looking name is not yet a commit that made them: MORPHLEARN_GIT_COMMIT (cluster nodes,
    # a lent machine) can name any string, and a mistyped hash once nearly went into a record. The
    # history asked is the run's working directory's, the project being bundled (the package may be
    # imported from another checkout, e.g. an editable install).
    for c, what in named.items():
        if provenance.in_history(c, cwd=Path.cwd()) is False:
            raise BundleError(
                f"commit {c!r}, named by {what}, is not this repository's HEAD or an ancestor of it "
                "(a mistyped MORPHLEARN_GIT_COMMIT, code of another branch, or history a shallow clone lacks); "
                "allowed: results made at commits of this history (re-run those designs, or merge the branch "
                "that made them)"
            )


def check_target(bundle_dir: str | Path, made_by: dict[str, Any]) -> None:
    """Refuse (BundleError) a ``bundle_dir`` whose contents this run did not make: only an absent or
    empty folder, or a bundle whose ``bundle.json`` names the same configs and results folder, may
    be (re)written. The message names what is there and never advises deleting it."""
    target = Path(bundle_dir)
    here = Path.cwd().resolve()
    results = Path(made_by["results_dir"]).resolve()
    allowed = (
        "allowed: an absent or empty folder, or a bundle made by this same config (its bundle.json "
        f"made_by: configs {sorted(made_by['configs'])}, results_dir {made_by['results_dir']!r}); nothing was written"
    )
    held = bundle_holding(target)
    why = place_refusal(target)  # the same guard as results_dir's (config.write_refusal); bundles: below
    if why:
        pass
    elif target.resolve() in (here, *here.parents) or target.resolve() in (results, *results.parents):
        why = "is the project folder, the results folder or one that holds them"
    elif held is not None and held != target.resolve():
        why = f"is inside the results bundle {held}"
    elif target.is_symlink() or (target.exists() and not target.is_dir()):
        why = "is a file (or a link), not a bundle folder"
    elif target.is_dir() and any(target.iterdir()):
        mpath = target / MANIFEST
        try:
            by = bounded.json_file(mpath).get("made_by", {})
        except (ValueError, AttributeError):
            by = None
        if not isinstance(by, dict):
            why = f"holds files and no readable {MANIFEST}: the bundle rule would replace what it did not make"
        elif (
            sorted(by.get("configs") or []) != sorted(made_by["configs"])
            or by.get("results_dir") != made_by["results_dir"]
        ):
            why = (
                f"holds a bundle made by configs {sorted(by.get('configs') or [])} from results_dir "
                f"{by.get('results_dir')!r}, which this run's config would overwrite"
            )
    if why:
        raise BundleError(f"bundle_dir = {str(bundle_dir)!r} {why}; {allowed}")


def _models(run_dir: Path) -> list[str]:
    return [m for m in models.MODELS if (run_dir / m / "metrics.csv").is_file()]


def _survey_folders(run_dir: Path) -> list[str]:
    """``survey/<model>`` folders of the run: a survey copied from another bundle (already a subset)."""
    return [
        f"{store.SURVEY_DIR}/{m}" for m in models.MODELS if (run_dir / store.SURVEY_DIR / m / "metrics.csv").is_file()
    ]


def bundle_files(out_dir: Path) -> Iterable[Path]:
    """Every file under the bundle folder but its manifest (a stray one included)."""
    for p in sorted(out_dir.rglob("*")):
        if p.is_file() and p.relative_to(out_dir).as_posix() != MANIFEST:
            yield p


def build(
    run_dir: str | Path, out_dir: str | Path, *, top: int, made_by: dict[str, Any], designs_kept: str = "drawn"
) -> dict[str, Any]:
    """Write the bundle of ``run_dir`` to ``out_dir`` (replaced as a whole, atomically).
    ``designs_kept``: ``drawn`` or ``all``, whose outcome arrays a model of every design keeps."""
    run_dir, out_dir = Path(run_dir), Path(out_dir)
    held = _models(run_dir)
    if not held:  # a physics survey alone (config/survey9_mujoco.yaml) is a bundle too
        raise BundleError(f"{run_dir}: no model's metrics.csv (<model>/metrics.csv); run the workflow first")
    subsets: dict[str, Any] = {}
    for name in ("summary.json", "reproduction.csv", "learners/correlations.csv"):  # custody: as recorded
        if provenance.sidecar_of(run_dir / name).is_file():
            provenance.check_derived(run_dir / name)
    with store.atomic_path(out_dir) as tmp:
        tmp.mkdir(parents=True)
        for name in COPIED:
            if (run_dir / name).is_file():
                shutil.copy2(run_dir / name, tmp / name)
        surveys = _survey_folders(run_dir)
        for model in [*held, *surveys]:
            (tmp / model).mkdir(parents=True)
            for name in MODEL_FILES:
                shutil.copy2(run_dir / model / name, tmp / model / name)
            src = run_dir / model / "merged.zarr"
            # custody: what goes into the bundle is what the metrics rule wrote from this store
            provenance.check_derived(run_dir / model / "metrics.csv", store.open_merged(src))
            table = pd.read_csv(run_dir / model / "metrics.csv")
            n = positions_of(run_dir / model)
            # every design of the grid (theory, or a physics survey): only the drawn ones' arrays;
            # a survey read from another bundle holds that bundle's subset already: kept whole
            every = len(table) == n**4 and designs_kept == "drawn"
            if model in surveys:
                designs = np.sort(store.open_merged(src).design.values.astype(np.int64))
            else:
                designs = drawn_designs(table, n, top) if every else np.sort(table.design)
            store.write_subset(src, designs, tmp / model / "merged.zarr")
            subsets[model] = {
                "designs": [int(d) for d in designs],
                "of": len(table),
                "simulated_by": _simulated_by(src),
            }
        for name in LEARNER_FILES:  # the learner stage (beyond the paper), when the run has it
            if (run_dir / "learners" / name).is_file():
                (tmp / "learners").mkdir(exist_ok=True)
                shutil.copy2(run_dir / "learners" / name, tmp / "learners" / name)
        cost = run_cost(run_dir)
        if len(cost):
            cost.to_csv(tmp / COST, index=False, float_format="%.2f")
        figs = sorted(p for p in (run_dir / "figures").glob("*") if p.name.endswith(FIGURE_SUFFIXES))
        if figs:
            (tmp / "figures").mkdir()
            for p in figs:
                shutil.copy2(p, tmp / "figures" / p.name)
        manifest = {
            "made_by": made_by,
            "subsets": subsets,
            "files": {str(p.relative_to(tmp)): provenance.sha256_file(p) for p in bundle_files(tmp)},
        }
        (tmp / "README.md").write_text(readme(manifest, run_dir, cost))
        manifest["files"]["README.md"] = provenance.sha256_file(tmp / "README.md")
        manifest["files"] = dict(sorted(manifest["files"].items()))
        (tmp / MANIFEST).write_text(json.dumps(manifest, indent=1, sort_keys=True) + "\n")
    return manifest


def run_cost(run_dir: str | Path) -> pd.DataFrame:
    """One row per job of the run that has a benchmark file (Snakemake's ``benchmark:``):
    job (its benchmark path without ``.tsv``), wall seconds, CPU seconds, peak memory (MB)."""
    rows = []
    bench = Path(run_dir) / "benchmarks"
    for p in sorted(bench.rglob("*.tsv")):
        t = pd.read_csv(p, sep="\t")
        if len(t):
            rows.append(
                {
                    "job": str(p.relative_to(bench).with_suffix("")),
                    "wall_s": float(t.s.iloc[-1]),
                    "cpu_s": float(t.cpu_time.iloc[-1]),
                    "max_rss_mb": float(t.max_rss.iloc[-1]),
                }
            )
    return pd.DataFrame(rows, columns=["job", "wall_s", "cpu_s", "max_rss_mb"])


def cost_lines(cost: pd.DataFrame) -> list[str]:
    """Markdown lines: wall and CPU time of the run by stage (the job path less its number:
    ``theory/shard_3`` -> ``theory/shard``, ``figures/fig1`` -> ``figures/fig``)."""
    if not len(cost):
        return []
    g = cost.assign(stage=cost.job.str.replace(r"_?\d+$", "", regex=True)).groupby("stage", sort=True)
    lines = ["| stage | jobs | wall s (sum) | CPU s (sum) |", "|---|---|---|---|"]
    for name, t in g:
        lines.append(f"| {name} | {len(t)} | {t.wall_s.sum():,.0f} | {t.cpu_s.sum():,.0f} |")
    lines.append(f"| all | {len(cost)} | {cost.wall_s.sum():,.0f} | {cost.cpu_s.sum():,.0f} |")
    return lines


def _simulated_by(merged: Path) -> dict[str, Any]:
    """Commits, backends and devices that made the run's shards (the merged store's record), which
    may differ from the commit that made the bundle."""
    prov = json.loads(store.open_merged(merged).attrs.get("provenance_json", "{}"))
    return prov.get("shards", {})


def positions_of(model_dir: str | Path) -> int:
    """Positions per axis of a model's run, from its merged dataset's science record."""
    sci = store.science_of(store.open_merged(Path(model_dir) / "merged.zarr"))
    return models.get(sci["model"]).positions_of(sci)


def readme(manifest: dict[str, Any], run_dir: Path, cost: pd.DataFrame) -> str:
    by = manifest["made_by"]
    sub = manifest["subsets"]
    lines = [
        "# Results bundle",
        "",
        "Generated by the rule `bundle` (morphlearn.bundle); do not edit by hand: `bundle.json` lists",
        "the SHA-256 of every file and `morphlearn check-bundle <folder>` compares them.",
        "",
        f"- Bundled from the results folder `{by.get('results_dir', run_dir)}` of the config "
        f"`{' + '.join(by.get('configs', ['?']))}`",
        f"  at commit `{by.get('git_commit', '?')}` (package {by.get('version', '?')}); the commits that "
        "simulated the shards are listed below.",
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
        f"| `{COST}` | each job's wall and CPU seconds and peak memory (its benchmark file) |",
        *(
            [
                f"| `{store.SURVEY_DIR}/<model>/` | a physics survey of every design, read from another bundle "
                "(config `survey_from`; its `metrics.provenance.json` names it): Fig. 7 C-D and the survey rows |"
            ]
            if any(m.startswith(store.SURVEY_DIR + "/") for m in sub)
            else []
        ),
        "",
        "Designs held in the subsets:",
        "",
    ]
    for model, s in sub.items():
        lines.append(f"- {model}: {len(s['designs'])} of {s['of']} designs: {s['designs']}")
    lines += ["", "Shards simulated by (commit: shards; backend; device):", ""]
    for model, s in sub.items():
        by = s.get("simulated_by", {})
        lines.append(
            f"- {model}: "
            + "; ".join(
                ", ".join(f"{k}: {v}" for k, v in by.get(part, {}).items())
                for part in ("git_commits", "backends", "devices")
            )
            # the commit that computed each design, where the shards record it (design cache reuse)
            + (
                "; designs by commit: " + ", ".join(f"{k}: {v}" for k, v in dc.items())
                if (dc := by.get("design_commits"))
                else ""
            )
        )
    if len(cost):
        lines += [
            "",
            "What the run cost (sums of the jobs' benchmark files; wall seconds add up jobs that ran side by side):",
            "",
            *cost_lines(cost),
        ]
    lines += [
        "",
        "Left out (regenerate with the command above; the shards take the CPU time stated in",
        "`docs/performance.md`): the shards, the full merged datasets, logs, benchmarks and the",
        "executed notebooks' HTML (re-rendering writes them).",
        "",
    ]
    return "\n".join(lines)
