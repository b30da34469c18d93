"""tools/mujoco_figure.py on the committed tables, and the committed MuJoCo-pybullet comparison
(results/mujoco/survey_compare.json, quoted in docs/results.md) recomputed from those tables."""

from __future__ import annotations

import json
import runpy
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from morphlearn.compare import spearman_ci
from morphlearn.grid import DesignGrid, canonical_design

ROOT = Path(__file__).resolve().parents[1]
MJ = ROOT / "results/mujoco"
PB = ROOT / "results/survey/empirical/metrics.csv"


def test_figure_script_writes_the_committed_figure(tmp_path: Path) -> None:
    import matplotlib.image as mpimg

    runpy.run_path(str(ROOT / "tools/mujoco_figure.py"), run_name="not_main")["main"](["--out", str(tmp_path)])
    img = mpimg.imread(tmp_path / "engines.png")
    assert img.shape[0] > 500 and img.shape[1] > 500
    dark = (img[..., :3].mean(axis=-1) < 0.5).mean()
    assert 0.005 < dark < 0.5, dark  # drawn on, not blank, not black
    # deterministic and up to date: the same bytes and numbers as the committed files
    assert (tmp_path / "engines.png").read_bytes() == (MJ / "engines.png").read_bytes()
    assert (tmp_path / "engines.pdf").read_bytes() == (MJ / "engines.pdf").read_bytes()
    assert json.loads((tmp_path / "engines.json").read_text()) == json.loads((MJ / "engines.json").read_text())


def test_committed_comparison_equals_what_compare_computes() -> None:
    saved = json.loads((MJ / "survey_compare.json").read_text())
    mj = pd.read_csv(MJ / "survey_metrics.csv")
    pb = pd.read_csv(PB).set_index("design").loc[mj.design].reset_index()
    assert len(mj) == 625 and (pb.design.to_numpy() == mj.design.to_numpy()).all()
    canon = int(np.flatnonzero(mj.design.to_numpy() == DesignGrid(5).index_of(*canonical_design()))[0])
    for m in ("M_L", "M_CF"):
        a, b = pb[m].to_numpy(float), mj[m].to_numpy(float)
        nz = (a > 0) | (b > 0)
        for key, rows in (("all", slice(None)), ("nonzero_either", nz)):
            r = spearman_ci(a[rows], b[rows], m)
            got = saved[m][key]
            assert got["n"] == r.n
            assert [got["rho"], got["lo"], got["hi"]] == pytest.approx([r.rho, r.low, r.high], rel=1e-9), (m, key)
        # top 10 by each engine, ties at the 10th value broken by design index
        top = [set(t.sort_values([m, "design"], ascending=[False, True]).design[:10]) for t in (pb, mj)]
        assert saved[m]["top10_overlap"] == len(top[0] & top[1])
        assert saved[m]["canonical_rank"] == {
            "pybullet": int((a > a[canon]).sum()) + 1,
            "mujoco": int((b > b[canon]).sum()) + 1,
        }
    assert saved["share_with_generalist"] == {
        "pybullet": pytest.approx((pb.generalists > 0).mean()),
        "mujoco": pytest.approx((mj.generalists > 0).mean()),
    }
    # the figure's numbers for the engines are the same statistics
    fig = json.loads((MJ / "engines.json").read_text())
    for m in ("M_L", "M_CF"):
        for key in ("all", "nonzero_either"):
            assert fig[f"{m} pybullet-mujoco"][key]["rho"] == pytest.approx(saved[m][key]["rho"], rel=1e-12)


def test_disagreement_picks_the_largest_difference_then_the_most_generalists() -> None:
    pick = runpy.run_path(str(ROOT / "tools/mujoco_disagreement.py"), run_name="not_main")["pick_design"]
    pb = pd.DataFrame({"design": [0, 1, 2, 3, 4], "generalists": [5, 1, 6, 6, 2]})
    mj = pd.DataFrame({"design": [0, 1, 2, 3, 4], "generalists": [4, 4, 3, 3, 2]})
    assert pick(pb, mj) == 2  # |diff| 3 for designs 1, 2, 3; 2 and 3 have 9 generalists; 2 first
    assert pick(pb.iloc[[0, 1, 4]], mj.iloc[[0, 1, 4]]) == 1


def test_reproduction_engine_rows_on_the_committed_surveys() -> None:
    """The reproduction table's pybullet-vs-MuJoCo rows (beyond the paper): rho as scipy gives it
    on the two committed tables, the non-zero subset and the top-10 overlap by the project's ranking."""
    import dataclasses

    from scipy import stats

    from morphlearn import metrics
    from morphlearn.figures import data as fd
    from morphlearn.figures.reproduction.claims import BEYOND_ENGINES
    from morphlearn.figures.reproduction.stages.engines import engine_rows

    emp = fd.load_results(ROOT / "results/survey", "empirical", None)
    mj_table = pd.read_csv(MJ / "survey_metrics.csv")
    mj = dataclasses.replace(emp, model="mujoco", table=mj_table)
    rows = {r["key"]: r for r in engine_rows(emp, mj, ("empirical", "mujoco"), "MuJoCo", "cfg")}
    assert {r["paper"] for r in rows.values()} == {BEYOND_ENGINES}
    pb = emp.table.set_index("design").loc[mj_table.design].reset_index()
    for m in metrics.METRICS:
        a, b = pb[m].to_numpy(float), mj_table[m].to_numpy(float)
        rho = stats.spearmanr(a, b).statistic
        assert rows[f"engines_mujoco_rho_{m}"]["ours"].startswith(f"{rho:.3f} [")
        nz = (a > 0) | (b > 0)
        assert f"{nz.sum()} designs" in rows[f"engines_mujoco_rho_{m}_nonzero"]["ours"]
        assert rows[f"engines_mujoco_rho_{m}_nonzero"]["ours"].startswith(
            f"{stats.spearmanr(a[nz], b[nz]).statistic:.3f} ["
        )
        top_a = set(metrics.rank_designs(pb, m).design[:10])
        top_b = set(metrics.rank_designs(mj_table, m).design[:10])
        assert rows[f"engines_mujoco_top10_{m}"]["ours"] == f"{len(top_a & top_b)} of 10"


def test_reproduction_survey_rows_of_a_further_engine_against_the_theory() -> None:
    """The survey rows of the MuJoCo survey (theory vs MuJoCo rho): the joined columns carry the
    engine's name (this raised KeyError 'M_L_empirical' when the survey-mujoco run first reached it)."""
    import dataclasses

    from scipy import stats

    from morphlearn.figures import data as fd
    from morphlearn.figures.reproduction.stages.survey import survey_rows

    theory = fd.load_results(ROOT / "results/survey", "theory", None)
    emp = fd.load_results(ROOT / "results/survey", "empirical", None)
    mj = dataclasses.replace(emp, model="mujoco", table=pd.read_csv(MJ / "survey_metrics.csv"))
    rows = {r["key"]: r for r in survey_rows(theory, mj, "cfg", model="mujoco", label="MuJoCo survey")}
    t = theory.table.set_index("design").loc[mj.table.design]
    rho = stats.spearmanr(t["M_L"].to_numpy(float), mj.table["M_L"].to_numpy(float)).statistic
    said = [r["ours"] for k, r in rows.items() if "rho" in k and "M_L" in k]
    assert said and said[0].startswith(f"{rho:.3f} ["), rows.keys()


def test_refined_rows_say_how_the_theory_best_designs_do_in_physics() -> None:
    """Rows of physics results that are not a survey (issue 26's designs at 121 x 121): a further
    engine's canonical and best designs as the reference engine's rows, and for each metric the
    theory's best design (or its mirror image) in physics, or "not among the designs held"; here on
    the committed paper bundle (theory at paper resolution; pybullet on a few designs)."""
    import dataclasses

    from morphlearn import grid, metrics
    from morphlearn.figures import data as fd
    from morphlearn.figures.reproduction.stages.refined import refined_rows
    from morphlearn.figures.reproduction.table import reproduction_table

    theory = fd.load_results(ROOT / "results/paper", "theory", None)
    emp = fd.load_results(ROOT / "results/paper", "empirical", None)
    mj = dataclasses.replace(emp, model="mujoco")
    rows = {r["key"]: r for r in refined_rows(theory, mj, "mujoco", "cfg")}
    canon = metrics.find_row(emp.table, grid.canonical_design())
    m2 = emp.n_controllers
    # the further engine's answers to the paper's physics claims are rows of the claims table, each
    # with the paper's own value (the paper's physics ran in ODE, not pybullet) and the engine named
    table = reproduction_table(theory, emp, None, "cfg", 1.0, engines={"mujoco": mj}).set_index("key")
    assert table.at["mujoco_canonical_M_L", "ours"] == f"{canon.M_L:.4g}"
    assert table.at["mujoco_canonical_generalists", "ours"].startswith(f"{int(canon.generalists)} of {m2}")
    assert table.at["mujoco_canonical_M_L", "quantity"] == "canonical design: M_L"
    assert table.at["mujoco_canonical_M_L", "model"] == "MuJoCo (another engine)"
    assert table.at["mujoco_best_on_both", "paper"] == "yes"
    assert set(rows) == {f"mujoco_theory_best_{by}_in_physics" for by in metrics.METRICS}
    for by in metrics.METRICS:
        top = theory.best(by)
        design = fd.row_design(top)
        mirror = fd.row_design(theory.table[theory.table.design == grid.DesignGrid(9).mirror(int(top.design))].iloc[0])
        held = [emp.row(*d) for d in (design, mirror) if emp.row(*d) is not None]
        said = rows[f"mujoco_theory_best_{by}_in_physics"]["ours"]
        if held:
            r = held[0]
            assert said.startswith(f"{fd.design_label(*fd.row_design(r))}") and f"{int(r.generalists)} of {m2}" in said
        else:
            assert said.endswith(f"not among the {mj.n_designs} designs these results hold")
    # the reference engine gets only the theory-best rows (its own rows are the paper's quantities)
    assert {r["key"] for r in refined_rows(theory, emp, "empirical", "cfg")} == {
        f"empirical_theory_best_{by}_in_physics" for by in metrics.METRICS
    }
