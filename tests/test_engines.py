"""The engine comparison (config/engines.yaml; morphlearn.analysis.engines; figures engines and
disagreement): its committed outputs in results/mujoco re-made from the committed tables and
re-rendered by their notebooks to the same bytes, and the committed MuJoCo-pybullet comparison
(results/mujoco/survey_compare.json, quoted in docs/results.md) recomputed from the tables."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from morphlearn import configure
from morphlearn.analysis import engines as engine_compare
from morphlearn.analysis.compare import spearman_ci
from morphlearn.grid import DesignGrid, canonical_design

ROOT = Path(__file__).resolve().parents[1]
MJ = ROOT / "results/mujoco"
PB = ROOT / "results/survey/empirical/metrics.csv"
CONFIG = configure.load(ROOT / "config.yaml", [ROOT / "config/engines.yaml"])


def _render(name: str, tmp_path: Path, files: tuple[str, ...], **extra: object) -> Path:
    """Run figure ``name``'s notebook on a copy of the committed inputs ``files`` (as its rule
    does: papermill, the project's src importable); returns the copy's figures folder."""
    from morphlearn.bundles.render import render_notebook

    run = tmp_path / "results" / "mujoco"
    (run / "figures").mkdir(parents=True)
    for f in files:
        shutil.copyfile(MJ / f, run / f)
    rel = Path("results/mujoco")
    params = {
        "results_dir": str(rel),
        "style": str(ROOT / "notebooks/style.mplstyle"),
        **{
            k: str(rel / "figures" / f"{name}.{ext}")
            for k, ext in (("png", "png"), ("pdf", "pdf"), ("caption", "caption.md"))
        },
        **extra,
    }
    render_notebook(ROOT, f"notebooks/{name}.ipynb", tmp_path, rel / "logs" / f"{name}.ipynb", params)
    return run / "figures"


def test_engine_numbers_are_the_committed_ones(tmp_path: Path) -> None:
    """Rule engines_numbers' work on the committed tables gives the committed engines.csv and
    engines.json byte for byte."""
    s = CONFIG.engines
    assert s.enabled and CONFIG.results_dir == "results/mujoco"
    stats = engine_compare.write_numbers(s, tmp_path / "engines.csv", tmp_path / "engines.json")
    assert (tmp_path / "engines.csv").read_bytes() == (MJ / "engines.csv").read_bytes()
    assert (tmp_path / "engines.json").read_bytes() == (MJ / "engines.json").read_bytes()
    # custody: the sealed record names both files; an edit to either is caught before a read
    from morphlearn import provenance

    provenance.check_derived(tmp_path / "engines.csv")
    (tmp_path / "engines.json").write_text((tmp_path / "engines.json").read_text().replace("625", "626", 1))
    with pytest.raises(provenance.CustodyError, match=r"engines\.json"):
        provenance.check_derived(tmp_path / "engines.csv")
    # the table reads back to the same floats (the figure draws it): the shortest exact repr
    both = pd.read_csv(tmp_path / "engines.csv")
    assert len(both) == 625 and stats["canonical_design"] == DesignGrid(5).index_of(*canonical_design())
    assert both.M_L_mujoco.mul(engine_compare.CELLS).round(9).mod(1).eq(0).all()  # integers of 121


@pytest.mark.slow
def test_engines_figure_renders_the_committed_bytes(tmp_path: Path) -> None:
    import matplotlib.image as mpimg

    out = _render("engines", tmp_path, ("engines.csv", "engines.json", "engines.provenance.json"))
    img = mpimg.imread(out / "engines.png")
    assert img.shape[0] > 500 and img.shape[1] > 500
    dark = (img[..., :3].mean(axis=-1) < 0.5).mean()
    assert 0.005 < dark < 0.5, dark  # drawn on, not blank, not black
    for ext in ("png", "pdf", "caption.md"):
        assert (out / f"engines.{ext}").read_bytes() == (MJ / "figures" / f"engines.{ext}").read_bytes(), ext


@pytest.mark.slow
def test_disagreement_figure_renders_the_committed_bytes(tmp_path: Path) -> None:
    body = CONFIG.models["empirical"].params.to_dict()
    files = ("disagreement.json", "disagreement_success.npy", "disagreement_paths.npy", "disagreement.provenance.json")
    out = _render("disagreement", tmp_path, files, morphology=body)
    for ext in ("png", "pdf", "caption.md"):
        got, want = (out / f"disagreement.{ext}").read_bytes(), (MJ / "figures" / f"disagreement.{ext}").read_bytes()
        assert got == want, ext


def test_committed_disagreement_agrees_with_the_tables() -> None:
    """The committed re-simulation (rule engines_disagreement) is of the design the tables pick,
    with their generalist counts, and its controller is a generalist in exactly one engine."""
    info = json.loads((MJ / "disagreement.json").read_text())
    s = CONFIG.engines
    pb, mj = engine_compare.read_table(s.pybullet), engine_compare.read_table(s.mujoco)
    assert info["design"] == engine_compare.pick_design(pb, mj)
    succ = np.load(MJ / "disagreement_success.npy")
    assert succ.dtype == bool and succ.shape == (2, 4, 11, 11)
    gen = succ.all(axis=1)
    for k, (e, tab) in enumerate((("pybullet", pb), ("mujoco", mj))):
        want = int(tab.set_index("design").loc[info["design"], "generalists"])
        assert int(gen[k].sum()) == info["generalists"][e] == want
    i, j = (round((w + 1) * 5) for w in info["controller"])
    assert gen[0, i, j] != gen[1, i, j]
    paths = engine_compare.split_paths(info, np.load(MJ / "disagreement_paths.npy"))
    assert [len(p) - 1 for p in paths["mujoco"]] == info["steps"]["mujoco"]


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
    pick = engine_compare.pick_design
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
    # the further engine's answers to the paper's physics claims are rows beside the claims table
    # (another engine and body: no verdict), each with the paper's own value (the paper's physics
    # ran in ODE, not pybullet) and the engine named
    table = reproduction_table(theory, emp, None, "cfg", 1.0, engines={"mujoco": mj}).set_index("key")
    assert table.at["mujoco_canonical_M_L", "ours"] == f"{canon.M_L:.4g}"
    assert table.at["mujoco_canonical_generalists", "ours"].startswith(f"{int(canon.generalists)} of {m2}")
    assert table.at["mujoco_canonical_M_L", "quantity"] == "canonical design: M_L"
    assert table.at["mujoco_canonical_M_L", "model"] == "MuJoCo (another engine, the project's own body)"
    assert table.at["mujoco_canonical_M_L", "section"] == "another robot"
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
