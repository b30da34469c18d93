"""Where pybullet and MuJoCo disagree most, drawn (issue 25): one design, both engines' paths.

    nice -n 10 .venv/bin/python tools/mujoco_disagreement.py   # ~2-4 min, most of it pybullet

writes ``results/mujoco/disagreement.{png,pdf,caption.md,json}``.

- The design: the largest |generalists in pybullet - generalists in MuJoCo| in the committed
  tables (``results/survey/empirical/metrics.csv``, ``results/mujoco/survey_metrics.csv``), ties
  to the larger sum of both, then the lower design index.
- Its 4 x 11 x 11 episodes are simulated again in each engine (exact early stop, as the surveys;
  no adaptive grid) and the generalist counts are checked against the committed tables.
- The controller: the first (w1, w2) (row-major) that is a generalist in exactly one engine; its
  four episodes are run again in both engines to contact or horizon with the centre path recorded
  (``EpisodeRunner.run(path=...)``, ``BatchRunner.run(path=...)``).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from matplotlib.colors import ListedColormap
from matplotlib.patches import Circle

from morphlearn.empirical.episode import EpisodeRunner
from morphlearn.empirical.episode import evaluate_design as pybullet_design
from morphlearn.figures.output import save, use_style
from morphlearn.grid import ENV_ANGLES_DEG, DesignGrid, light_positions, weights
from morphlearn.metrics import design_metrics
from morphlearn.mujoco.episode import BatchRunner
from morphlearn.mujoco.episode import evaluate_design as mujoco_design
from morphlearn.physics.options import SweepOptions
from morphlearn.physics.params import load_params

ROOT = Path(__file__).resolve().parents[1]
PYBULLET = ROOT / "results/survey/empirical/metrics.csv"
MUJOCO = ROOT / "results/mujoco/survey_metrics.csv"
OUT = ROOT / "results/mujoco"
GRID, M = DesignGrid(5), 11
COLORS = ("tab:blue", "tab:orange", "tab:green", "tab:purple")


def pick_design(pb: pd.DataFrame, mj: pd.DataFrame) -> int:
    """The design whose generalist counts differ most between the engines (ties: see the module)."""
    t = pb[["design", "generalists"]].merge(mj[["design", "generalists"]], on="design", suffixes=("_pb", "_mj"))
    t["diff"] = (t.generalists_pb - t.generalists_mj).abs()
    t["sum"] = t.generalists_pb + t.generalists_mj
    return int(t.sort_values(["diff", "sum", "design"], ascending=[False, False, True]).design.iloc[0])


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", type=Path, default=OUT)
    args = ap.parse_args(argv)
    params = load_params(ROOT / "config/empirical_morphology.yaml")
    pb_tab, mj_tab = pd.read_csv(PYBULLET), pd.read_csv(MUJOCO)
    d = pick_design(pb_tab, mj_tab)
    c = GRID.coords(d)
    l1, l2 = (float(c[0]), float(c[1])), (float(c[2]), float(c[3]))
    w = weights(M)
    opts = SweepOptions(early_stop=True)
    succ = {
        "pybullet": ~np.isnan(pybullet_design(l1, l2, w, params, options=opts).first_time),
        "mujoco": ~np.isnan(mujoco_design(l1, l2, w, params, options=opts).first_time),
    }
    gen = {e: (s.sum(axis=0) == 4) for e, s in succ.items()}
    for e, tab in (("pybullet", pb_tab), ("mujoco", mj_tab)):
        want = int(tab.set_index("design").loc[d, "generalists"])
        got = design_metrics(succ[e]).generalists
        if got != want:
            raise RuntimeError(f"design {d} in {e}: {got} generalists simulated, {want} in the committed table")
    only = np.argwhere(gen["pybullet"] != gen["mujoco"])
    i, j = (int(x) for x in only[0])
    w1, w2 = float(w[i]), float(w[j])

    # the four episodes of that controller, paths recorded, to contact or horizon (no early stop)
    paths: dict[str, list[np.ndarray]] = {"pybullet": [], "mujoco": []}
    closest: dict[str, list[float]] = {"pybullet": [], "mujoco": []}
    with EpisodeRunner(params) as runner:
        for env in range(4):
            p: list[tuple[float, float]] = []
            closest["pybullet"].append(runner.run(l1, l2, w1, w2, env, path=p).min_dist)
            paths["pybullet"].append(np.array(p))
    rec: list[np.ndarray] = []
    closest["mujoco"] = (
        BatchRunner(params).run(l1, l2, np.tile([w1, w2], (4, 1)), np.arange(4), path=rec).min_dist.tolist()
    )
    xy = np.stack(rec)  # (steps, 4, 2)
    paths["mujoco"] = [xy[~np.isnan(xy[:, e, 0]), e] for e in range(4)]

    use_style(ROOT / "notebooks/style.mplstyle")
    fig, (ax0, ax1) = plt.subplots(1, 2, figsize=(11.5, 5.6), width_ratios=[1, 1.45])
    code = gen["pybullet"].astype(int) + 2 * gen["mujoco"].astype(int)  # 0 none, 1 pb, 2 mj, 3 both
    cmap = ListedColormap(["white", "tab:orange", "tab:green", "0.45"])
    ax0.imshow(code.T, origin="lower", cmap=cmap, vmin=-0.5, vmax=3.5, extent=(-1.1, 1.1, -1.1, 1.1))
    ax0.scatter([w1], [w2], marker="x", s=120, c="k", linewidths=2, zorder=3)
    for k, name in ((1, "generalist in pybullet only"), (2, "in MuJoCo only"), (3, "in both")):
        ax0.scatter([], [], marker="s", s=80, color=cmap(k), label=name)
    ax0.scatter([], [], marker="x", s=80, c="k", label="controller drawn right")
    ax0.set(xlabel="w1 (sensor 1 -> right wheel)", ylabel="w2 (sensor 2 -> left wheel)")
    ax0.set_title(f"(a) design {d}: generalists of 121 controllers")
    ax0.legend(loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2, fontsize=9)

    lights = light_positions(params.light_distance)
    for env in range(4):
        lx, ly = lights[env]
        ax1.add_patch(Circle((lx, ly), params.contact_distance, fc="gold", ec="0.4", alpha=0.5, zorder=1))
        ax1.text(lx, ly, f"{ENV_ANGLES_DEG[env]}°", ha="center", va="center", fontsize=9)
        for e, ls in (("pybullet", "-"), ("mujoco", "--")):
            pth = paths[e][env]
            ax1.plot(pth[:, 0], pth[:, 1], ls, color=COLORS[env], lw=1.6)
            hit = bool(succ[e][env, i, j])
            ax1.plot(*pth[-1], "o" if hit else "x", color=COLORS[env], ms=7, mfc="white" if e == "mujoco" else None)
    ax1.plot([0], [0], marker=(3, 0, -90), ms=12, c="k")
    ax1.plot([], [], "-", c="0.3", label="pybullet")
    ax1.plot([], [], "--", c="0.3", label="MuJoCo")
    ax1.plot([], [], "o", c="0.3", ls="none", label="end: contact")
    ax1.plot([], [], "x", c="0.3", ls="none", label="end: horizon")
    ax1.set_aspect("equal")
    ax1.set(xlabel="x", ylabel="y")
    ax1.set_title(f"(b) centre paths, w = ({w1:g}, {w2:g}), start at the triangle facing +x")
    ax1.legend(loc="best", fontsize=9)

    failed = {e: [ENV_ANGLES_DEG[k] for k in range(4) if not succ[e][k, i, j]] for e in succ}
    missed = {e: ", ".join(f"{a} deg" for a in v) or "none" for e, v in failed.items()}
    info = {
        "design": d,
        "l1": list(l1),
        "l2": list(l2),
        "generalists": {e: int(g.sum()) for e, g in gen.items()},
        "generalist_in_one_engine_only": {
            "pybullet": int((gen["pybullet"] & ~gen["mujoco"]).sum()),
            "mujoco": int((gen["mujoco"] & ~gen["pybullet"]).sum()),
        },
        "cells_differing": int((succ["pybullet"] != succ["mujoco"]).sum()),
        "cells": int(succ["pybullet"].size),
        "controller": [round(w1, 12), round(w2, 12)],
        "envs_failed_deg": failed,
        "steps": {e: [len(p) - 1 for p in paths[e]] for e in paths},
        "closest_approach": {e: [round(float(x), 4) for x in v] for e, v in closest.items()},
        "contact_distance": round(params.contact_distance, 4),
    }
    caption = (
        f"**Where the engines disagree most.** Design {d} (sensors at {l1} and {l2}) has the largest "
        f"difference in generalists between the engines: {info['generalists']['pybullet']} of 121 in pybullet, "
        f"{info['generalists']['mujoco']} in MuJoCo; {info['cells_differing']} of its {info['cells']} "
        f"episodes end differently. (a) Which controllers are generalists in which engine. (b) The body "
        f"centre's path in the four environments (colour; lights with their contact circle) for the "
        f"controller w = ({w1:g}, {w2:g}), pybullet solid, MuJoCo dashed, to contact (circle) or the "
        f"horizon (cross; MuJoCo's end markers hollow). Lights it misses: {missed['pybullet']} in pybullet, "
        f"{missed['mujoco']} in MuJoCo. Made by `tools/mujoco_disagreement.py`.\n"
    )
    out: Path = args.out
    save(fig, caption, out / "disagreement.png", out / "disagreement.pdf", out / "disagreement.caption.md")
    plt.close(fig)
    (out / "disagreement.json").write_text(json.dumps(info, indent=1) + "\n")
    print(json.dumps(info, indent=1))


if __name__ == "__main__":
    main()
