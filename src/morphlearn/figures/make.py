"""One function per figure: each returns the matplotlib figure and its caption (Markdown).

Captions say what the figure shows, which data (files and checksums) and which config made it,
and at what resolution. They use only Markdown that is also valid reStructuredText (paragraphs,
``**bold**``, ``- `` lists), because the Snakemake report renders them as RST.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.figure import Figure

from morphlearn import grid as gridmod
from morphlearn.figures import data as fd
from morphlearn.figures import draw
from morphlearn.pipeline import FIGURES
from morphlearn.provenance import sha256_file

#: Figure sizes in inches at ``DPI``: the PNG is exactly ``size * DPI`` pixels.
DPI = 150
SIZES: dict[str, tuple[float, float]] = {
    "fig1": (13.0, 4.4),
    "fig2": (9.0, 5.6),
    "fig3": (13.0, 4.8),
    "fig4": (12.0, 6.8),
    "fig5": (16.5, 6.6),
    "fig6": (15.0, 9.6),
    "fig7": (12.0, 8.6),
}
assert tuple(SIZES) == FIGURES
PAPER_POSITIONS, PAPER_WEIGHTS = 9, 121


@dataclass
class FigureOutput:
    fig: Figure
    caption: str
    info: dict[str, Any]


# ---------------------------------------------------------------------------------------------
# Provenance text


def _short(h: str | None) -> str:
    return (h or "?")[:12]


def _provenance_record(res: fd.ModelResults) -> dict[str, Any]:
    p = Path(res.paths["metrics"]).with_suffix(".provenance.json")
    return json.loads(p.read_text()) if p.is_file() else {}


def science_summary(res: fd.ModelResults) -> str:
    """The config subset the dataset was made with (from the dataset itself)."""
    sci = res.science
    m = len(res.weights)
    if res.model == "theory":
        g, th = sci.get("grid", {}), sci.get("theory", {})
        tol = (f"rtol = atol = {th.get('rtol')}" if th.get("integrator") == "dp5" else f"dt = {th.get('dt')}")
        return (f"grid {g.get('positions_per_axis')} positions per axis per sensor, {g.get('weights')} "
                f"weights per synapse; r = {th.get('r')}, T = {th.get('horizon')}, success radius "
                f"{th.get('success_radius')}, integrator {th.get('integrator')} ({tol}), step cap "
                f"{th.get('max_steps')}, mirror symmetry {sci.get('mirror_symmetry')}")  # fmt: skip
    pr = sci.get("params", {})
    return (f"{res.n_designs} designs simulated on the {sci.get('positions_per_axis')}-point grid, "
            f"{m} weights per synapse; light distance {pr.get('light_distance', float('nan')):.4g}, "
            f"{pr.get('steps')} steps of dt = {pr.get('dt')}, success = touching the light; body "
            f"from the committed morphology (wheel radius {pr.get('wheel_radius', float('nan')):.4g})")  # fmt: skip


def resolution_note(res: fd.ModelResults) -> str:
    n = res.positions_per_axis
    m = len(res.weights)
    full_designs = res.n_designs == (n or 0) ** 4
    if n == PAPER_POSITIONS and m == PAPER_WEIGHTS and full_designs:
        return "paper resolution"
    subset = "" if full_designs else f", {res.n_designs} of {(n or 0) ** 4} designs"
    return (f"reduced resolution ({n} positions per axis, {m} weights{subset}; the paper used "
            f"{PAPER_POSITIONS} and {PAPER_WEIGHTS}, all designs)")  # fmt: skip


def provenance_md(results: Sequence[fd.ModelResults | None], extra: str = "") -> str:
    """The caption's data-and-config paragraph."""
    parts = []
    for res in results:
        if res is None:
            continue
        rec = _provenance_record(res)
        merged_sha = next(iter(rec.get("inputs", {}).values()), None)
        parts.append(
            f"- {res.model}: {res.paths['metrics']} (sha256 {_short(sha256_file(res.paths['metrics']))}) "
            f"and {res.paths['merged']} (sha256 {_short(merged_sha)}), git commit "
            f"{rec.get('git_commit', '?')}; {science_summary(res)}; {resolution_note(res)}."
        )
    text = "**Data and config.**" + (" " + extra if extra else "")
    return text + ("\n\n" + "\n".join(parts) if parts else "")


def _caption(title: str, body: Sequence[str], prov: str) -> str:
    paras = [f"**{title}**"] + [b for b in body if b] + [prov]
    return "\n\n".join(paras) + "\n"


def _need_empirical(emp: fd.ModelResults | None, enabled: bool) -> fd.ModelResults | None:
    if enabled and emp is None:
        raise FileNotFoundError("empirical.enabled is true but the empirical results are missing")
    return emp if enabled else None


def _fmt_design(row: Any) -> str:
    return fd.design_label(*fd.row_design(row))


def _metric_line(row: Any, m: int, sep: str = ", ") -> str:
    return (f"M_L = {row.M_L:.4g} ({int(row.generalists)} of {m} controllers){sep}"
            f"M_CF = {row.M_CF:.4g}")  # fmt: skip


# ---------------------------------------------------------------------------------------------
# Figures


def fig1(morphology: dict[str, Any] | None = None, canonical: fd.Design | None = None,
         **_: Any) -> FigureOutput:  # fmt: skip
    """A: lateral vs contralateral wiring; B: theoretical robot with l1, l2; C: pybullet render."""
    from morphlearn.empirical.params import EmpiricalParams
    from morphlearn.figures.render import render_robot

    l1, l2 = canonical or gridmod.canonical_design()
    fig = draw.new_figure(SIZES["fig1"])
    axes = fig.subplots(1, 3, gridspec_kw={"width_ratios": [1.25, 1.0, 1.25]})
    draw.braitenberg_wiring(axes[0])
    axes[0].set_title("sensor-to-wheel wiring, light ahead on the left", fontsize=10)
    draw.theory_robot(axes[1], l1, l2)
    axes[1].set_title("theoretical model (canonical design)", fontsize=10)
    params = EmpiricalParams.from_mapping(morphology) if morphology else EmpiricalParams()
    rnd = render_robot(params, l1, l2)
    ax = axes[2]
    ax.imshow(rnd.rgb)
    ax.set_xticks([])
    ax.set_yticks([])
    ax.set_title("simulated robot (pybullet, offscreen render)", fontsize=10)
    offsets = {"sensor 1": (90, -130), "sensor 2": (150, 120), "left wheel": (-110, -130),
               "right wheel": (-60, 190), "castor": (230, 30), "light": (0, -120)}  # fmt: skip
    for name, (u, v) in rnd.labels.items():
        du, dv = offsets[name]
        ax.annotate(name, xy=(u, v), xytext=(u + du, v + dv), fontsize=9, ha="center",
                    arrowprops={"arrowstyle": "-", "color": "0.2", "lw": 0.8},
                    bbox={"facecolor": "white", "edgecolor": "none", "alpha": 0.8, "pad": 1})  # fmt: skip
    for ax, letter in zip(axes, "ABC", strict=True):
        draw.panel_letter(ax, letter)
    fig.subplots_adjust(left=0.02, right=0.99, top=0.88, bottom=0.1, wspace=0.15)
    src = "the committed morphology file" if morphology else "the paper authors' defaults (no morphology file)"
    body = [
        "**A:** lateral and contralateral excitatory sensor-to-wheel connections (after Braitenberg): "
        "with the light on the robot's left, lateral wiring turns the robot away from it and "
        "contralateral wiring turns it towards it. Both models use contralateral synapses: sensor 1 "
        "drives the right wheel with weight w1, sensor 2 the left wheel with w2.",
        f"**B:** the theoretical model, a 1 x 1 body (x forward, y left) with the sensor positions "
        f"l1 and l2 measured from its centre; drawn in the canonical design ({fd.design_label(l1, l2)}).",
        "**C:** the simulated (pybullet) robot in the canonical design, rendered offscreen "
        "(DIRECT mode, ER_TINY_RENDERER) from the same body the empirical sweep builds: two light "
        "sensors (red markers; they are points, not simulated bodies), two motorised sphere wheels "
        "(black), a passive frictionless castor at the front (grey), and the light (yellow).",
    ]
    prov = (f"**Data and config.** No results are used. Body parameters from {src}: "
            f"wheel radius {params.wheel_radius:.4g}, body mass {params.body_mass:.4g}, wheel mass "
            f"{params.wheel_mass:.4g}, max wheel speed {params.max_speed:.4g} rad/s, max torque "
            f"{params.max_torque:.4g}.")  # fmt: skip
    return FigureOutput(fig, _caption("Figure 1. Modelling the robot.", body, prov), {})


def fig2(theory: fd.ModelResults, design: str = "best_M_L", envs: Sequence[int] = (45, 135),
         **_: Any) -> FigureOutput:  # fmt: skip
    """Two environments' binary success matrices overlapped, for one design of the theory run."""
    if design == "canonical":
        l1, l2 = gridmod.canonical_design()
        row = theory.row(l1, l2)
        which = "the canonical design"
    else:
        row = theory.best(design.removeprefix("best_"))
        l1, l2 = fd.row_design(row)
        which = f"the best design by {design.removeprefix('best_')}"
    pos = theory.find(l1, l2)
    succ = theory.success(pos)
    ka, kb = (gridmod.ENV_ANGLES_DEG.index(int(e)) for e in envs)
    names = (f"{envs[0]}°", f"{envs[1]}°")
    fig = draw.new_figure(SIZES["fig2"])
    ax = fig.add_axes((0.1, 0.12, 0.5, 0.76))
    draw.success_pair(ax, succ[ka], succ[kb], theory.weights, names,
                      f"theory, {fd.design_label(l1, l2)}\n"
                      f"success with the light at {names[0]} and at {names[1]}")  # fmt: skip
    both = int((succ[ka] & succ[kb]).sum())
    body = [
        f"Binary success matrices of {which} ({fd.design_label(l1, l2)}) of the theory run for two "
        f"environments, the light at {names[0]} (A) and at {names[1]} (B), overlapped. Each cell is "
        f"one controller (w1, w2) of the {len(theory.weights)} x {len(theory.weights)} weight grid. "
        f"Controllers that solve both environments ({both}) lie in the intersection of the two "
        "environment-specific success sets; the paper's Fig. 2 draws the same construction for "
        "generic tasks A and B.",
        f"This design over all four environments: {_metric_line(row, theory.n_controllers)}.",
    ]
    return FigureOutput(fig, _caption("Figure 2. Overlapped binary success matrices.", body,
                                      provenance_md([theory])), {"design": (l1, l2), "both": both})  # fmt: skip


def _sketch(ax: Any, row: Any, title: str, castor: bool = False) -> None:
    l1, l2 = fd.row_design(row)
    draw.robot(ax, l1, l2, castor=castor)
    draw.body_axes(ax)
    ax.set_title(title, fontsize=10)


def fig3(theory: fd.ModelResults, empirical: fd.ModelResults | None = None, empirical_enabled: bool = False,
         **_: Any) -> FigureOutput:  # fmt: skip
    """Best designs: theory by M_L, theory by M_CF, empirical (by M_L; and M_CF if the same)."""
    emp = _need_empirical(empirical, empirical_enabled)
    fig = draw.new_figure(SIZES["fig3"])
    axes = fig.subplots(1, 3)
    b_ml, b_cf = theory.best("M_L"), theory.best("M_CF")
    m = theory.n_controllers
    # Metrics on their own line: a title wider than its axes would run into the panel letter.
    _sketch(axes[0], b_ml, f"theory, best by M_L\n{_fmt_design(b_ml)}\n{_metric_line(b_ml, m, chr(10))}")
    _sketch(axes[1], b_cf, f"theory, best by M_CF\n{_fmt_design(b_cf)}\n{_metric_line(b_cf, m, chr(10))}")
    body = [
        f"Sensor placements (red; 1 drives the right wheel, 2 the left) of the best designs. "
        f"**A:** theory, highest controller learnability M_L: {_fmt_design(b_ml)}, {_metric_line(b_ml, m)}; "
        f"{len(theory.tied_with(b_ml, 'M_L'))} design(s) share this M_L (a design and its mirror image "
        "score the same). "
        f"**B:** theory, highest resistance to forgetting M_CF: {_fmt_design(b_cf)}, {_metric_line(b_cf, m)}; "
        f"{len(theory.tied_with(b_cf, 'M_CF'))} design(s) share this M_CF. Ties are broken by the other "
        "metric, then by the smaller design index.",
    ]
    if emp is None:
        draw.missing(axes[2], title="empirical, best design")
        body.append("**C:** empirical results are not in this run (empirical.enabled is false).")
    else:
        e_ml, e_cf = emp.best("M_L"), emp.best("M_CF")
        same = fd.row_design(e_ml) == fd.row_design(e_cf)
        me = emp.n_controllers
        _sketch(axes[2], e_ml, f"empirical, best by M_L{' and M_CF' if same else ''}\n{_fmt_design(e_ml)}\n"
                f"{_metric_line(e_ml, me, chr(10))}", castor=True)  # fmt: skip
        sub = "" if emp.n_designs == theory.n_designs else (
            f" Only {emp.n_designs} designs were simulated empirically in this run, so this is the best "
            "of those, not of all designs.")  # fmt: skip
        body.append(
            f"**C:** empirical (pybullet), best by M_L: {_fmt_design(e_ml)}, {_metric_line(e_ml, me)}; "
            + ("it is also the best by M_CF, as in the paper." if same else
               f"the best by M_CF is a different design, {_fmt_design(e_cf)} (M_CF = {e_cf.M_CF:.4g}).")
            + sub
        )  # fmt: skip
    for ax, letter in zip(axes, "ABC", strict=True):
        draw.panel_letter(ax, letter)
    fig.subplots_adjust(left=0.05, right=0.98, top=0.74, bottom=0.1, wspace=0.35)
    return FigureOutput(fig, _caption("Figure 3. The best designs.", body, provenance_md([theory, emp])), {})


def _trajectory_figure(name: str, theory: fd.ModelResults, design: fd.Design, targets: Sequence[fd.Point],
                       settings: fd.TheorySettings, near: float, title: str, which: str
                       ) -> FigureOutput:  # fmt: skip
    pos = theory.find(*design)
    if pos is None:
        raise ValueError(f"{fd.design_label(*design)} is not on this run's design grid")
    o = theory.overlap(pos)
    chosen = fd.pick_controllers(o, theory.weights, targets)
    fig = draw.new_figure(SIZES[name])
    axes = fig.subplots(1, len(chosen))
    axes = np.atleast_1d(axes)
    lines = []
    for k, (ax, c) in enumerate(zip(axes, chosen, strict=True)):
        trs = fd.trajectories(design, (c.w1, c.w2), settings)
        ok = fd.stays_near(trs, near)
        far = [fd.max_distance_after_success(t) for t in trs]
        solved = sum(math.isfinite(t.first_time) for t in trs)
        status = "generalist" if c.generalist else f"solves {c.overlap} of 4"
        draw.trajectory_panel(ax, trs, design, settings.r, settings.radius,
                              f"$(w_1, w_2) = ({c.w1:.3g}, {c.w2:.3g})$ {status}\n"
                              f"paper: ({c.target[0]:g}, {c.target[1]:g}); "
                              f"{'stays near the light' if ok else 'does not stay near'}", near=near)  # fmt: skip
        draw.panel_letter(ax, "ABC"[k])
        far_s = ", ".join("none" if not math.isfinite(x) else f"{x:.2f}" for x in far)
        lines.append(f"- **{'ABC'[k]}:** {c.describe()}; on this grid it solves {c.overlap} of 4 environments "
                     f"(reference integration: {solved} of 4); largest distance from the light after the first "
                     f"success, per environment 45/135/225/315°: {far_s}; "
                     f"{'stays' if ok else 'does not stay'} near the source.")  # fmt: skip
    draw.trajectory_legend(fig, near)
    fig.subplots_adjust(left=0.05, right=0.99, top=0.86, bottom=0.2, wspace=0.28)
    row = theory.row(*design)
    n_gen = int((o == 4).sum())
    if n_gen >= len(chosen):
        pick = "the generalist controllers of this run's weight grid nearest to the paper's"
    else:
        pick = (f"this run's weight grid has {n_gen} generalist(s) for this design, fewer than the paper "
                "shows, so the nearest generalists and then the nearest controllers with the next highest "
                "overlap stand in for the paper's")  # fmt: skip
    body = [
        f"Trajectories of {which} ({fd.design_label(*design)}) under the theoretical model for "
        f"{len(chosen)} controllers: {pick}. The light (yellow, success radius {settings.radius:g}) is at "
        f"the origin; the four starts (light at 45, 135, 225 and 315° from the robot, distance "
        f"{settings.r:g}) are drawn as small robots facing +x, superimposed. Paths run to the horizon "
        f"T = {settings.horizon:g} (not stopped at success; scipy DOP853 at rtol = atol = {settings.tol:g}); "
        f"circles mark the first success, crosses the position at T; the frame clips paths that leave it.",
        f"This design: {_metric_line(row, theory.n_controllers)}. 'Stays near the source': after its first "
        f"success in each environment the centre never again moves farther than {near:g} from the light "
        "up to T (dotted circle).",
        "\n".join(lines),
    ]
    return FigureOutput(fig, _caption(title, body, provenance_md([theory])),
                        {"controllers": chosen})  # fmt: skip


def fig4(theory: fd.ModelResults, settings: dict[str, float], targets: Sequence[fd.Point] | None = None,
         near: float = fd.NEAR_DISTANCE, **_: Any) -> FigureOutput:  # fmt: skip
    targets = targets or fd.PAPER_CANONICAL_CONTROLLERS
    return _trajectory_figure("fig4", theory, gridmod.canonical_design(), targets,
                              fd.TheorySettings(**settings), near,
                              "Figure 4. Trajectories of the canonical design (theory).",
                              "the canonical design")  # fmt: skip


def fig5(theory: fd.ModelResults, settings: dict[str, float], targets: Sequence[fd.Point] | None = None,
         near: float = fd.NEAR_DISTANCE, **_: Any) -> FigureOutput:  # fmt: skip
    targets = targets or fd.PAPER_BEST_CONTROLLERS
    design = fd.row_design(theory.best("M_L"))
    which = "the design with the highest M_L in this run"
    if design != fd.PAPER_BEST_DESIGN:
        which += f" (the paper's is {fd.design_label(*fd.PAPER_BEST_DESIGN)})"
    return _trajectory_figure("fig5", theory, design, targets, fd.TheorySettings(**settings), near,
                              "Figure 5. Trajectories of the best design by M_L (theory).", which)  # fmt: skip


def _overlap_row(fig: Figure, axes: Sequence[Any], res: fd.ModelResults, letters: str, model: str
                 ) -> tuple[Any, list[str]]:  # fmt: skip
    canon = gridmod.canonical_design()
    picks: list[tuple[str, fd.Design | None]] = [("canonical", canon if res.find(*canon) is not None else None),
                                                ("best by M_L", fd.row_design(res.best("M_L"))),
                                                ("best by M_CF", fd.row_design(res.best("M_CF")))]  # fmt: skip
    im, lines = None, []
    for ax, letter, (label, design) in zip(axes, letters, picks, strict=True):
        draw.panel_letter(ax, letter)
        if design is None:
            draw.missing(ax, "the canonical design was not simulated in this run", f"{model}, {label}")
            lines.append(f"**{letter}:** {model}, {label}: not simulated in this run.")
            continue
        row = res.row(*design)
        im = draw.overlap_image(ax, res.overlap(res.find(*design)), res.weights,
                                f"{model}, {label}\n{fd.design_label(*design)}\n"
                                f"M_L = {row.M_L:.4g}, M_CF = {row.M_CF:.4g}")  # fmt: skip
        lines.append(f"**{letter}:** {model}, {label}: {fd.design_label(*design)}, "
                     f"{_metric_line(row, res.n_controllers)}.")  # fmt: skip
    return im, lines


def fig6(theory: fd.ModelResults, empirical: fd.ModelResults | None = None, empirical_enabled: bool = False,
         **_: Any) -> FigureOutput:  # fmt: skip
    """Overlap heatmaps (0-4) over the weight grid: theory A-C, empirical D-F, one colour scale."""
    emp = _need_empirical(empirical, empirical_enabled)
    fig = draw.new_figure(SIZES["fig6"])
    axes = fig.subplots(2, 3)
    im, lines = _overlap_row(fig, axes[0], theory, "ABC", "theory")
    if emp is None:
        for ax, letter, label in zip(axes[1], "DEF", ("canonical", "best by M_L", "best by M_CF"), strict=True):
            draw.missing(ax, title=f"empirical, {label}")
            draw.panel_letter(ax, letter)
        lines.append("**D-F:** empirical results are not in this run (empirical.enabled is false).")
    else:
        im_e, more = _overlap_row(fig, axes[1], emp, "DEF", "empirical")
        im = im or im_e
        lines += more
        if fd.row_design(emp.best("M_L")) == fd.row_design(emp.best("M_CF")):
            lines.append("Empirically the best design by M_L is also the best by M_CF, so E and F are identical.")
        if emp.n_designs != theory.n_designs:
            lines.append(f"Only {emp.n_designs} designs were simulated empirically in this run; E and F are "
                         "the best of those.")  # fmt: skip
    fig.subplots_adjust(left=0.05, right=0.84, top=0.9, bottom=0.07, hspace=0.55, wspace=0.3)
    cax = fig.add_axes((0.87, 0.25, 0.018, 0.5))
    cb = fig.colorbar(im, cax=cax, ticks=range(5))
    cb.ax.set_yticklabels(draw.OVERLAP_LABELS)
    cb.set_label("environments solved, O")
    body = [
        "The overlap O (number of the four environments a controller solves) over the weight grid, "
        "w1 on the x axis and w2 on the y axis, for the canonical design, the best design by M_L and the "
        "best by M_CF; theory (A-C) and empirical (D-F) on one colour scale, generalists (O = 4) in cyan. "
        "M_L is the share of cyan cells, M_CF the cyan cells over the non-dark-blue ones (O of at least 1).",
        "\n\n".join(lines),
    ]
    return FigureOutput(fig, _caption("Figure 6. Measuring learnability and forgetting.", body,
                                      provenance_md([theory, emp])), {})  # fmt: skip


def _dist_row(axes: Sequence[Any], res: fd.ModelResults, model: str, letters: str, note: str | None) -> None:
    canon = res.row(*gridmod.canonical_design())
    for ax, metric, letter in zip(axes, ("M_L", "M_CF"), letters, strict=True):
        marks = [("best", float(res.table[metric].max()), "-")]
        if canon is not None:
            marks.insert(0, ("canonical", float(canon[metric]), "--"))
        draw.distribution(ax, res.table[metric].to_numpy(), metric,
                          f"{model}: {metric} over {res.n_designs} designs", marks, note)  # fmt: skip
        draw.panel_letter(ax, letter)


def fig7(theory: fd.ModelResults, empirical: fd.ModelResults | None = None, empirical_enabled: bool = False,
         **_: Any) -> FigureOutput:  # fmt: skip
    """Distributions of M_L and M_CF over all designs, theory (A, B) and empirical (C, D)."""
    emp = _need_empirical(empirical, empirical_enabled)
    fig = draw.new_figure(SIZES["fig7"])
    axes = fig.subplots(2, 2)
    _dist_row(axes[0], theory, "theory", "AB", None)
    body = [
        "Distributions over designs of the controller learnability M_L (share of the weight grid that "
        "solves all four environments) and the resistance to forgetting M_CF (generalists over controllers "
        "that solve at least one; 0 if none), with the canonical design (dashed) and the best (solid) "
        "marked. Counts are on a log scale.",
        f"**A, B:** theory, all {theory.n_designs} designs of this run.",
    ]
    if emp is None:
        for ax, letter, metric in zip(axes[1], "CD", ("M_L", "M_CF"), strict=True):
            draw.missing(ax, title=f"empirical: {metric}")
            draw.panel_letter(ax, letter)
        body.append("**C, D:** empirical results are not in this run (empirical.enabled is false).")
    else:
        subset = emp.n_designs != theory.n_designs
        note = f"subset: {emp.n_designs} of {theory.n_designs}\ndesigns simulated" if subset else None
        _dist_row(axes[1], emp, "empirical", "CD", note)
        body.append(f"**C, D:** empirical, {emp.n_designs} designs"
                    + (" (only a subset of the designs was simulated in this run: not the distribution over "
                       "all designs)." if subset else "."))  # fmt: skip
    fig.subplots_adjust(left=0.08, right=0.98, top=0.93, bottom=0.08, hspace=0.42, wspace=0.25)
    return FigureOutput(fig, _caption("Figure 7. Distributions of M_L and M_CF over designs.", body,
                                      provenance_md([theory, emp])), {})  # fmt: skip


MAKERS: dict[str, Callable[..., FigureOutput]] = {
    "fig1": fig1, "fig2": fig2, "fig3": fig3, "fig4": fig4, "fig5": fig5, "fig6": fig6, "fig7": fig7,
}  # fmt: skip


def make_figure(name: str, results_dir: str | None = None, theory_thresholds: dict | None = None,
                empirical_thresholds: dict | None = None, empirical_enabled: bool = False,
                **kwargs: Any) -> FigureOutput:  # fmt: skip
    """Load what figure ``name`` needs from ``results_dir`` and draw it."""
    if name not in MAKERS:
        raise ValueError(f"unknown figure {name!r}; allowed: {list(MAKERS)}")
    if name != "fig1":
        theory = fd.load_results(results_dir, "theory", theory_thresholds)
        if theory is None:
            raise FileNotFoundError(f"no theory results under {results_dir}")
        kwargs["theory"] = theory
        if empirical_enabled:
            kwargs["empirical"] = fd.load_results(results_dir, "empirical", empirical_thresholds)
    return MAKERS[name](empirical_enabled=empirical_enabled, **kwargs)


def save_outputs(out: FigureOutput, png: str | Path, pdf: str | Path, caption: str | Path) -> None:
    """PNG (exactly ``SIZES * DPI`` pixels), PDF (no timestamp) and the caption."""
    for p in (png, pdf, caption):
        Path(p).parent.mkdir(parents=True, exist_ok=True)
    out.fig.savefig(png, dpi=DPI, metadata={"Software": None})
    out.fig.savefig(pdf, metadata={"CreationDate": None, "ModDate": None, "Producer": None})
    Path(caption).write_text(out.caption)
