"""Does the paper's physics conclusion survive the engine? Each engine and robot against ODE with
the authors' robot, design by design (issue 42; config/agreement.yaml; rule ``agreement``; figure
``agreement``, notebooks/agreement.ipynb; docs/authors_robot.md).

The reference is the ODE model's survey of a design grid (the authors' robot in the authors'
engine); each candidate is another physics survey of the same designs and weights: an engine with
the authors' robot (``robot: authors``) separates the engine from the body, the same engine with
the project's body (the committed surveys) adds the body. Per candidate, against the reference:

- Spearman's rho of M_L and of M_CF over the designs, with a seeded bootstrap 95 % interval, and
  of the cells each design solves (successes over its environments and controllers): at a coarse
  weight grid most designs have no generalist in ODE, so M_L and M_CF are mostly ties at 0 and the
  solved cells are the measure that still orders every design;
- the share of cells (design, environment, w1, w2) with the same outcome, over the designs both
  bundles hold outcome arrays of (a survey bundle kept whole: every design);
- the overlap of the top 10 designs by M_L and by M_CF, counting only designs with a positive value
  (designs tied at 0 are not "best" on either side); the share of designs with a generalist;
- the ranks of the canonical design and of each side's best design in the other (ties share a
  rank).

Light imports only at module level: the Snakefile imports this module at parse time.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from morphlearn.grid import ENV_ANGLES_DEG, DesignGrid, canonical_design
from morphlearn.settings import AgreementSettings, Source  # the stage's settings (configure.parse)

if TYPE_CHECKING:
    import pandas as pd

#: Designs compared in the top-N overlap.
TOP = 10
#: Generalists per design "close" to the reference's: within this many (issue 56's acceptance).
GENERALIST_SLACK = 2


@dataclass(frozen=True)
class Survey:
    """A source read and checked: its table, its science record and its outcome arrays."""

    source: Source
    table: pd.DataFrame
    science: dict[str, Any]
    success: dict[int, np.ndarray]  # design -> bool (4, m, m), the designs whose arrays it holds
    thresholds: dict[str, float]

    @property
    def engine(self) -> str:
        from morphlearn import models

        return models.get(self.source.model).engine

    @property
    def robot(self) -> str:
        from morphlearn import models

        return str(self.science.get("robot", models.get(self.source.model).robots[0]))

    @property
    def label(self) -> str:
        from morphlearn import models

        m = models.get(self.source.model)
        body = "the authors' robot" if self.robot == "authors" else "the project's body"
        return f"{getattr(m, 'engine_label', '') or self.engine}, {body}"

    def levers(self) -> str:
        """What may make its cells differ from an exhaustive run's (the survey's own levers)."""
        out = []
        if ad := self.science.get("adaptive_weights"):
            out.append(f"adaptive weight grid (near {ad.get('near')}: unsimulated cells count as failures)")
        if self.science.get("early_stop"):
            out.append("reach-bound early stop (exact)")
        return "; ".join(out) or "every cell simulated"


def read(src: Source) -> Survey:
    """A survey from its bundle: the table checked against its record (custody), the outcome
    arrays of every design the bundle holds."""
    from morphlearn import bounded, metrics, provenance, store

    provenance.check_derived(src.table)
    import pandas as pd

    table = pd.read_csv(src.table, comment="#")
    ds = store.open_merged(src.merged)
    sci = store.science_of(ds)
    prov = bounded.json_file(src.table.parent / "metrics.provenance.json")
    th = dict(prov["config"]["thresholds"])
    tr = metrics.Thresholds(**th)
    success = {}
    for i, d in enumerate(ds.design.values.astype(int)):
        a = store.read_design(ds, i)
        success[int(d)] = metrics.success(a["first_time"], a["min_dist"], tr)
    return Survey(src, table, sci, success, th)


def solved(table: pd.DataFrame) -> pd.Series:
    """Cells each design solves: its successes summed over the environments (``n_<angle>``)."""
    return table[[f"n_{a}" for a in ENV_ANGLES_DEG]].sum(axis=1)


def _rank(table: pd.DataFrame, by: str, design: int) -> int:
    """A design's rank by ``by``: 1 + the designs strictly better (ties share a rank: at 11 x 11
    most designs are tied at 0 and the few with a generalist have one each)."""
    from morphlearn import metrics

    return metrics.rank_of(table, table.set_index("design").loc[design], by)


def _best(table: pd.DataFrame, by: str) -> int:
    """The best design by ``by`` (ties broken as :func:`metrics.rank_designs`)."""
    from morphlearn import metrics

    return int(metrics.rank_designs(table, by).design.iloc[0])


def compare(ref: Survey, cand: Survey) -> dict[str, Any]:
    """The candidate against the reference (see the module docstring)."""
    from morphlearn import metrics
    from morphlearn.analysis.compare import spearman_ci

    a = ref.table.set_index("design")
    b = cand.table.set_index("design")
    common = a.index.intersection(b.index)
    if len(common) != len(a) or len(common) != len(b):
        raise ValueError(
            f"{cand.source.table}: {len(b)} designs, the reference {len(a)}, {len(common)} in both; "
            "allowed: surveys of the same designs"
        )
    wa, wb = int(ref.science["weights"]), int(cand.science["weights"])
    if wa != wb or ref.science["positions_per_axis"] != cand.science["positions_per_axis"]:
        raise ValueError(f"{cand.source.table}: another weight or design grid than the reference's; allowed: the same")
    out: dict[str, Any] = {
        "engine": cand.engine,
        "robot": cand.robot,
        "label": cand.label,
        "bundle": cand.source.bundle,
        "model": cand.source.model,
        "levers": cand.levers(),
        "designs": len(common),
    }
    for m in ("M_L", "M_CF"):
        r = spearman_ci(a.loc[common, m].to_numpy(), b.loc[common, m].to_numpy(), m)
        out[f"rho_{m}"] = {"rho": r.rho, "lo": r.low, "hi": r.high}
        top_a, top_b = metrics.best_designs(ref.table, m, TOP), metrics.best_designs(cand.table, m, TOP)
        out[f"top{TOP}_{m}"] = len(set(top_a) & set(top_b))
        out[f"top{TOP}_{m}_sizes"] = {"reference": len(top_a), "candidate": len(top_b)}
        best_b, best_a = _best(cand.table, m), _best(ref.table, m)
        out[f"best_{m}"] = {
            "candidate_best": best_b,
            "its_rank_in_reference": _rank(ref.table, m, best_b),
            "reference_best": best_a,
            "its_rank_in_candidate": _rank(cand.table, m, best_a),
        }
    r = spearman_ci(solved(a.loc[common]).to_numpy(), solved(b.loc[common]).to_numpy(), "solved")
    out["rho_solved"] = {"rho": r.rho, "lo": r.low, "hi": r.high}
    g = DesignGrid(int(ref.science["positions_per_axis"]))
    canon = int(g.index_of(*canonical_design()))
    # None where the sources do not both hold it (a screen's best designs, a random sample)
    out["canonical"] = (
        {
            "design": canon,
            **{f"rank_{m}_reference": _rank(ref.table, m, canon) for m in ("M_L", "M_CF")},
            **{f"rank_{m}_candidate": _rank(cand.table, m, canon) for m in ("M_L", "M_CF")},
            # designs sharing its M_L (its rank is shared with them)
            "tied_M_L_reference": int((a.M_L == a.M_L[canon]).sum()) - 1,
            "tied_M_L_candidate": int((b.M_L == b.M_L[canon]).sum()) - 1,
        }
        if canon in a.index and canon in b.index
        else None
    )
    out["with_generalist"] = {
        "reference": float((a.generalists > 0).mean()),
        "candidate": float((b.generalists > 0).mean()),
    }
    # a design's generalist count as a screen reads it: within GENERALIST_SLACK of the reference's
    gap = (a.loc[common, "generalists"] - b.loc[common, "generalists"]).abs()
    out["generalists_close"] = {"within": GENERALIST_SLACK, "share": float((gap <= GENERALIST_SLACK).mean())}
    out["screen"] = screen(ref, cand)
    held = sorted(set(ref.success) & set(cand.success))
    same = sum(int((ref.success[d] == cand.success[d]).sum()) for d in held)
    cells = sum(int(ref.success[d].size) for d in held)
    out["cells"] = {"designs": len(held), "cells": cells, "same": same, "share": same / cells if cells else None}
    return out


def shard_cpu(src: Source) -> float | None:
    """CPU seconds of a survey's shard jobs by its bundle's run cost (None: not recorded there)."""
    import pandas as pd

    path = Path(src.bundle) / "run_cost.csv"
    if not path.is_file():
        return None
    cost = pd.read_csv(path)
    rows = cost[cost.job.str.startswith(f"{src.model}/shard")]
    return float(rows.cpu_s.sum()) if len(rows) else None


def screen(ref: Survey, cand: Survey, n: int = TOP) -> dict[str, Any]:
    """The candidate as a screen for the reference (config/ode_screened.yaml's strategy): its ``n``
    best designs by M_L and their mirror images simulated in the reference engine. Which of the
    reference's ``n`` best it would miss (both sides' best: :func:`metrics.best_designs`, designs
    with a generalist), and its cost against the reference's survey of every design (CPU of the
    shard jobs by each bundle's run cost; the refined designs at the reference's mean CPU per
    design)."""
    from morphlearn import metrics

    g = DesignGrid(int(ref.science["positions_per_axis"]))
    picked = set(metrics.best_designs(cand.table, "M_L", n))  # with a generalist: ties at 0 rank nothing
    picked |= {int(g.mirror(d)) for d in picked}
    best = metrics.best_designs(ref.table, "M_L", n)
    missed = [d for d in best if d not in picked]
    c_ref, c_cand = shard_cpu(ref.source), shard_cpu(cand.source)
    out: dict[str, Any] = {
        "n": n,
        "designs_refined": len(picked),
        "reference_best": best,
        "reference_best_missed": missed,
    }
    if c_ref is not None and c_cand is not None:
        refine = c_ref * len(picked) / len(ref.table)
        out.update(cpu_s_reference=c_ref, cpu_s_screen=c_cand, cpu_s_refine=refine, saved=1 - (c_cand + refine) / c_ref)
    return out


def numbers(s: AgreementSettings) -> dict[str, Any]:
    from morphlearn import models

    ref = read(s.reference)
    paper = models.paper_engine()
    if ref.engine != models.get(paper).engine:
        raise ValueError(f"agreement.reference = {s.reference.model!r}: allowed: a survey of the {paper} model")
    rows = [compare(ref, read(c)) for c in s.candidates]
    return {
        "reference": {"bundle": s.reference.bundle, "model": s.reference.model, "label": ref.label},
        "designs": len(ref.table),
        "weights": int(ref.science["weights"]),
        "positions_per_axis": int(ref.science["positions_per_axis"]),
        "candidates": rows,
    }


def table(n: dict[str, Any]) -> pd.DataFrame:
    """One row per candidate, the columns the docs and the figure quote."""
    import pandas as pd

    rows = []
    for c in n["candidates"]:
        rows.append(
            {
                "engine": c["engine"],
                "robot": c["robot"],
                "designs": c["designs"],
                **{
                    f"rho_{m}{k}": c[f"rho_{m}"][v]
                    for m in ("M_L", "M_CF")
                    for k, v in (("", "rho"), ("_lo", "lo"), ("_hi", "hi"))
                },
                "rho_solved": c["rho_solved"]["rho"],
                "rho_solved_lo": c["rho_solved"]["lo"],
                "rho_solved_hi": c["rho_solved"]["hi"],
                "cells_same": c["cells"]["share"],
                "cells_compared": c["cells"]["cells"],
                f"top{TOP}_M_L": c[f"top{TOP}_M_L"],
                f"top{TOP}_M_CF": c[f"top{TOP}_M_CF"],
                "canonical_rank_M_L": (c["canonical"] or {}).get("rank_M_L_candidate"),
                "canonical_rank_M_L_ode": (c["canonical"] or {}).get("rank_M_L_reference"),
                "with_generalist": c["with_generalist"]["candidate"],
                "with_generalist_ode": c["with_generalist"]["reference"],
                f"generalists_within_{GENERALIST_SLACK}": c["generalists_close"]["share"],
                "best_M_L_rank_in_ode": c["best_M_L"]["its_rank_in_reference"],
                "levers": c["levers"],
                "bundle": c["bundle"],
            }
        )
    return pd.DataFrame(rows)


def write(s: AgreementSettings, table_csv: str | Path, numbers_json: str | Path) -> dict[str, Any]:
    """The table and the numbers; custody: their sealed record (the sources' digests and theirs).
    Refuses (ValueError, nothing written) uncommitted code: the outputs are committed, and their
    record would name a commit that did not make them."""
    from morphlearn import provenance, store

    commit = provenance.git_commit()
    if provenance.uncommitted(commit):
        raise ValueError(
            f"the worktree is at {commit}: the agreement stage writes committed results, so it runs "
            "from committed code only; allowed: commit (or stash) the changes, then run it again"
        )
    n = numbers(s)
    with store.atomic_path(Path(numbers_json)) as tmp:
        tmp.write_text(json.dumps(n, indent=1) + "\n")
    with store.atomic_path(Path(table_csv)) as tmp:
        table(n).to_csv(tmp, index=False)
    # the bundles' manifests too: the screen reads their run cost, which their SHA-256 lists cover
    files = dict.fromkeys(f for src in s.sources() for f in src.files())
    rec = provenance.record(s.science(), list(files))
    provenance.write_sealed(provenance.sidecar_of(table_csv), rec, [table_csv, numbers_json])
    return n
