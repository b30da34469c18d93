"""What each workflow rule does, as functions: the Snakemake scripts only unpack and call."""

from __future__ import annotations

import json
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from morphlearn import config as cfgmod
from morphlearn import design_cache, metrics, provenance, store
from morphlearn import grid as gridmod
from morphlearn.figures.registry import FIGURES as FIGURE_SPECS
from morphlearn.results import DesignResult
from morphlearn.theory import TheoryParams, evaluate

MODELS = ("theory", "empirical")
#: The figures, one notebook and one rule each; listed (with what they read) in morphlearn.figures.registry.
#: These are the paper's, drawn by every run; ``figures(cfg)`` adds those of enabled extra stages.
FIGURES = tuple(f for f, spec in FIGURE_SPECS.items() if spec.needs is None)


def empirical_survey(cfg: dict[str, Any]) -> bool:
    """The empirical results cover every design of the grid (simulated, or read from a bundle)."""
    emp = cfg["empirical"]
    return bool(emp.get("enabled")) and (emp["results_from"] is not None or emp["designs"] == "all")


#: Figure conditions besides "a config section is enabled" (registry ``needs``).
FIGURE_CONDITIONS: dict[str, Callable[[dict[str, Any]], bool]] = {"empirical_survey": empirical_survey}


def figures(cfg: dict[str, Any]) -> list[str]:
    """The figures this config draws: the paper's and those whose ``needs`` is met."""
    def met(needs: str | None) -> bool:
        if needs is None:
            return True
        return FIGURE_CONDITIONS[needs](cfg) if needs in FIGURE_CONDITIONS else bool(cfg.get(needs, {}).get("enabled"))

    return [f for f, s in FIGURE_SPECS.items() if met(s.needs)]


def models(cfg: dict[str, Any]) -> list[str]:
    """The models this config runs."""
    return ["theory"] + (["empirical"] if cfg["empirical"].get("enabled") else [])


def simulated_models(cfg: dict[str, Any]) -> list[str]:
    """The models this config simulates (the empirical results may come from a bundle instead:
    ``empirical.results_from``)."""
    return [m for m in models(cfg) if m != "empirical" or cfg["empirical"]["results_from"] is None]


def designs_to_evaluate(cfg: dict[str, Any], model: str = "theory") -> np.ndarray:
    if model == "empirical":
        return np.array(cfgmod.empirical_simulated(cfg), dtype=np.int64)
    g = gridmod.DesignGrid(cfg["grid"]["positions_per_axis"])
    return g.representatives() if cfg["sweep"]["mirror_symmetry"] else np.arange(g.size)


def shard_designs(cfg: dict[str, Any], model: str = "theory") -> list[np.ndarray]:
    n = cfg["empirical"]["shards"] if model == "empirical" else cfg["sweep"]["shards"]
    return gridmod.split_shards(designs_to_evaluate(cfg, model), n)


def weights(cfg: dict[str, Any], model: str) -> np.ndarray:
    m = cfg["empirical"]["weights"] if model == "empirical" else cfg["grid"]["weights"]
    return gridmod.weights(m)


def empirical_params(cfg: dict[str, Any]) -> Any:
    from morphlearn.empirical import EmpiricalParams, load_params

    base = load_params(cfg["empirical"]["morphology"])
    return EmpiricalParams.from_mapping({**base.to_dict(), **cfg["empirical"].get("params", {})})


def science(cfg: dict[str, Any], model: str) -> dict[str, Any]:
    if model == "theory":
        return cfgmod.theory_science(cfg)
    if model == "empirical":
        from morphlearn.empirical import load_params

        return cfgmod.empirical_science(cfg, load_params(cfg["empirical"]["morphology"]).to_dict())
    raise ValueError(f"unknown model {model!r}; allowed: {MODELS}")


def mirror_derived(cfg: dict[str, Any], model: str) -> bool:
    """Theory mirror images are derived (exact); empirical ones are simulated unless
    ``empirical.mirror_derive`` (Bullet is symmetric only to solver tolerance)."""
    if model == "empirical":
        return bool(cfg["empirical"]["mirror_derive"])
    return cfg["sweep"]["mirror_symmetry"]


def evaluate_designs(
    cfg: dict[str, Any], model: str, designs: np.ndarray,
    done: Callable[[int, DesignResult], None] | None = None,
) -> list[DesignResult]:
    """Results of ``designs``, in order; ``done(i, result)`` is called as each one finishes (the
    theory kernel finishes its designs a batch at a time, the empirical model one by one)."""
    g = gridmod.DesignGrid(cfg["grid"]["positions_per_axis"])
    w = weights(cfg, model)
    if model == "theory":
        return evaluate(g.coords(designs), w, TheoryParams.from_config(cfg["theory"]), progress=True, done=done)
    from tqdm import tqdm

    from morphlearn.empirical import evaluate_design
    from morphlearn.empirical.options import SweepOptions

    params = empirical_params(cfg)
    options = SweepOptions.from_config(cfg["empirical"])
    out = []
    for i, c in enumerate(tqdm(g.coords(designs), unit="design", mininterval=1.0)):
        log = EpisodeProgress(f"design {int(designs[i])} ({i + 1}/{len(designs)})")
        out.append(evaluate_design((c[0], c[1]), (c[2], c[3]), w, params, progress=log, options=options))
        if done:
            done(i, out[-1])
    return out


class EpisodeProgress:
    """Episode-level progress lines for a shard log: one line at most every ``every_s`` seconds
    and one at the end of the design (a paper-resolution empirical design runs 58,564 episodes,
    hours of one core, so a per-design line alone would leave the log silent for hours)."""

    def __init__(self, label: str, every_s: float = 30.0, clock: Callable[[], float] = time.monotonic) -> None:
        self.label, self.every_s, self.clock = label, every_s, clock
        self.start = self.last = clock()

    def __call__(self, done: int, total: int) -> None:
        now = self.clock()
        if now - self.last < self.every_s and done < total:
            return
        self.last = now
        rate = (now - self.start) / done
        left = f", ~{rate * (total - done):.0f} s left in this design" if done < total else ""
        print(f"{self.label}: {done}/{total} episodes, {rate:.3f} s each{left}", flush=True)


def run_shard(cfg: dict[str, Any], model: str, shard: int, out: str | Path) -> None:
    """Evaluate one shard; with ``design_cache`` (default) reuse the designs already finished under
    the same science (design_cache) and save each new one as soon as it is done."""
    g = gridmod.DesignGrid(cfg["grid"]["positions_per_axis"])
    designs = shard_designs(cfg, model)[shard]
    sci = science(cfg, model)
    w = weights(cfg, model)
    prov = provenance.record(sci) | provenance.backend(cfg, model)
    results: dict[int, DesignResult] = {}
    folder = design_cache.cache_dir(cfg["results_dir"], model, sci) if cfg.get("design_cache", True) else None
    if folder:
        results = design_cache.load(folder, designs, model=model, science=sci, m=len(w))
    todo = np.array([d for d in designs if int(d) not in results], dtype=np.int64)
    print(f"shard {shard}: {len(designs)} designs, reused {len(results)}, to compute {len(todo)}"
          + (f" (design cache {folder})" if folder else ""), flush=True)  # fmt: skip

    def finished(i: int, r: DesignResult) -> None:
        results[int(todo[i])] = r
        if folder:
            design_cache.save(folder, int(todo[i]), r, model=model, grid=g, weights=w, science=sci,
                              provenance=prov)  # fmt: skip
        print(f"shard {shard}: design {int(todo[i])} computed ({i + 1}/{len(todo)})", flush=True)

    if len(todo):
        evaluate_designs(cfg, model, todo, done=finished)
    store.write_shard(out, model=model, grid=g, weights=w, designs=designs,
                      results=[results[int(d)] for d in designs], science=sci, provenance=prov)  # fmt: skip


def run_merge(cfg: dict[str, Any], model: str, shards: list[str], out: str | Path) -> None:
    g = gridmod.DesignGrid(cfg["grid"]["positions_per_axis"])
    sci = science(cfg, model)
    store.merge_shards(
        shards, out, model=model, grid=g, weights=weights(cfg, model),
        shard_designs=shard_designs(cfg, model), science=sci, mirror=mirror_derived(cfg, model),
        provenance=provenance.record(sci, shards),
    )  # fmt: skip


def check_render_inputs(paths: list[str]) -> None:
    """Render-only starts only from complete results: every file present, every merged store's
    digest record, coordinates and chunk files intact (raises store.IntegrityError naming the
    first). The figures verify each design's chunks when they read them."""
    for p in sorted(paths):
        if not Path(p).exists():
            raise store.IntegrityError(f"{p}: missing (render_only re-renders from stored results)")
        if p.endswith(".zarr"):
            store.check_merged_files(p)


def thresholds(cfg: dict[str, Any], model: str) -> metrics.Thresholds:
    src = cfg.get("empirical", {}).get("results_from") if model == "empirical" else None
    if src is not None:  # the bundle's own, as its metrics were made
        prov = json.loads((Path(src) / "empirical" / "metrics.provenance.json").read_text())
        return metrics.Thresholds(**prov["config"]["thresholds"])
    if model == "empirical":  # success = touching the light within the episode
        p = empirical_params(cfg)
        return metrics.Thresholds(p.horizon, p.contact_distance, p.horizon, p.contact_distance)
    th = cfg["theory"]
    a = cfg["analysis"]
    return metrics.Thresholds(
        horizon=a["horizon"] if a.get("horizon") is not None else th["horizon"],
        radius=a["success_radius"] if a.get("success_radius") is not None else th["success_radius"],
        sim_horizon=th["horizon"],
        sim_radius=th["success_radius"],
    )


def run_metrics(cfg: dict[str, Any], model: str, merged: str | Path, out_csv: str | Path) -> None:
    th = thresholds(cfg, model)
    ds = store.open_merged(merged)
    table = metrics.metrics_table(ds, th)  # verifies every chunk before anything is written
    subset = {"thresholds": th.__dict__, "model": model,
              "merged_sha256_overall": ds.attrs["integrity"]["overall"]}  # fmt: skip
    _write_csv_with_provenance(table, out_csv, subset, [merged])


def _write_csv_with_provenance(
    table: pd.DataFrame, out_csv: str | Path, subset: dict[str, Any], inputs: list
) -> None:
    out_csv = Path(out_csv)
    with store.atomic_path(out_csv) as tmp:
        table.to_csv(tmp, index=False, float_format=metrics.CSV_FLOAT_FORMAT)
    prov = provenance.record(subset, inputs)
    with store.atomic_path(out_csv.with_suffix(".provenance.json")) as tmp:
        tmp.write_text(json.dumps(prov, indent=1, sort_keys=True) + "\n")


def _row(r: pd.Series) -> dict[str, Any]:
    return {
        "l1": [r.l1x, r.l1y], "l2": [r.l2x, r.l2y], "generalists": int(r.generalists),
        "at_least_one": int(r.at_least_one), "M_L": float(r.M_L), "M_CF": float(r.M_CF),
        "flagged": int(r.flagged),
    }  # fmt: skip


def summarise(table: pd.DataFrame, top: int) -> dict[str, Any]:
    """Canonical design (with its rank by M_L), best designs by M_L and by M_CF."""
    c = metrics.find_row(table, gridmod.canonical_design())
    by_ml = metrics.rank_designs(table, "M_L")
    by_cf = metrics.rank_designs(table, "M_CF")
    out: dict[str, Any] = {"designs": len(table), "controllers": None}
    if c is not None:
        out["canonical"] = _row(c) | {f"rank_{m}": metrics.rank_of(table, c, m) for m in ("M_L", "M_CF")}
    out["top_M_L"] = [_row(r) for _, r in by_ml.head(top).iterrows()]
    out["top_M_CF"] = [_row(r) for _, r in by_cf.head(top).iterrows()]
    out["M_CF_eq_1"] = int((table.M_CF == 1.0).sum())
    best_cf1 = table[table.M_CF == 1.0]
    out["best_M_L_among_M_CF_eq_1"] = float(best_cf1.M_L.max()) if len(best_cf1) else None
    return out


def run_summary(cfg: dict[str, Any], tables: dict[str, str], out_json: str | Path,
                out_md: str | Path) -> None:  # fmt: skip
    summary = {"weights": cfg["grid"]["weights"], "positions_per_axis": cfg["grid"]["positions_per_axis"]}
    for model, path in tables.items():
        t = pd.read_csv(path)
        s = summarise(t, cfg["analysis"]["top"])
        s["controllers"] = len(weights(cfg, model)) ** 2
        summary[model] = s
    with store.atomic_path(out_json) as tmp:
        tmp.write_text(json.dumps(summary, indent=1, sort_keys=True) + "\n")
    with store.atomic_path(out_md) as tmp:
        tmp.write_text(summary_markdown(summary))


def _fmt(d: dict[str, Any]) -> str:
    return (f"| ({d['l1'][0]:g}, {d['l1'][1]:g}) | ({d['l2'][0]:g}, {d['l2'][1]:g}) | "
            f"{d['generalists']} | {d['at_least_one']} | {d['M_L']:.4f} | {d['M_CF']:.4f} | "
            f"{d['flagged']} |")  # fmt: skip


def summary_markdown(summary: dict[str, Any]) -> str:
    head = "| l1 | l2 | generalists | at least one | M_L | M_CF | flagged |\n|---|---|---|---|---|---|---|"
    lines = [
        "# Summary",
        "",
        f"Grid: {summary['positions_per_axis']} positions per axis per sensor, "
        f"{summary['weights']} weights per synapse.",
    ]
    for model in ("theory", "empirical"):
        s = summary.get(model)
        if not s:
            continue
        lines += ["", f"## {model} ({s['designs']} designs, {s['controllers']} controllers each)", ""]
        if "canonical" in s:
            c = s["canonical"]
            lines += [f"Canonical design: rank {c['rank_M_L']} by M_L, {c['rank_M_CF']} by M_CF.",
                      "", head, _fmt(c), ""]  # fmt: skip
        lines += ["Top designs by M_L:", "", head, *map(_fmt, s["top_M_L"]), ""]
        lines += ["Top designs by M_CF:", "", head, *map(_fmt, s["top_M_CF"]), ""]
        lines += [f"Designs with M_CF = 1: {s['M_CF_eq_1']}; best M_L among them: "
                  f"{s['best_M_L_among_M_CF_eq_1']}"]  # fmt: skip
    return "\n".join(lines) + "\n"


#: Figure options computed from the config rather than read from its ``figures`` section.
DERIVED_FIGURE_OPTIONS: dict[str, Callable[[dict[str, Any]], Any]] = {
    "morphology": lambda cfg: empirical_params(cfg).to_dict(),  # Fig. 1C: the empirical model's body
    "trajectory_settings": lambda cfg: trajectory_settings(cfg),
    "top": lambda cfg: cfg["analysis"]["top"],  # the survey figure's sensor maps: the summary's top designs
}


def figure_options(cfg: dict[str, Any], fig: str) -> dict[str, Any]:
    """Notebook parameters of figure ``fig`` from the config (registry: what it reads and takes).

    Only what that figure uses, so that changing a figure parameter re-renders only the figures
    that depend on it: ``<model>_thresholds`` of the models it reads (empirical only when enabled,
    with ``empirical_enabled``), then its options from DERIVED_FIGURE_OPTIONS or ``figures.<name>``.
    """
    spec = FIGURE_SPECS[fig]
    emp = "empirical" in models(cfg)
    opts: dict[str, Any] = {}
    for m in spec.reads:
        if m == "empirical":
            opts["empirical_enabled"] = emp
        if m != "empirical" or emp:
            opts[f"{m}_thresholds"] = thresholds(cfg, m).__dict__
    for name in spec.options:
        opts[name] = DERIVED_FIGURE_OPTIONS[name](cfg) if name in DERIVED_FIGURE_OPTIONS else cfg["figures"][name]
    return opts


def trajectory_settings(cfg: dict[str, Any]) -> dict[str, float]:
    """What a reference trajectory for a figure needs (figures.data.TheorySettings fields)."""
    th = cfg["theory"]
    return {"r": th["r"], "horizon": th["horizon"], "radius": th["success_radius"], "tol": th["rtol"]}
