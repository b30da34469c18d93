"""The explorer's widgets and figures (ipywidgets + ipympl; docs/explorer.md says why).

``App(results_dir)`` builds the interface: a source (bundle and model), the M_L and M_CF maps over
sensor placements (click a cell), dropdowns for the two sensor positions, the selected design's
overlap matrix (click a controller), its four trajectories, and its metrics, ranks and mirror
image. The drawing reuses the paper figures' code (morphlearn.figures.draw); the logic is
morphlearn.explore. Each figure's ``canvas`` is an ipympl widget under ``%matplotlib widget``;
under another backend (Agg in the unit tests) the handlers are called directly.
"""

from __future__ import annotations

import html
import math
import threading
import time
from pathlib import Path
from typing import Any

import ipywidgets as W  # noqa: N812 (the ipywidgets convention)
import matplotlib.pyplot as plt
import numpy as np
from matplotlib import patches
from matplotlib.figure import Figure

from morphlearn import explore
from morphlearn.figures import data
from morphlearn.figures.draw import matrix, panel, sketch, trajectory
from morphlearn.grid import ENV_ANGLES_DEG

MAP_CMAP = "viridis"


def _fmt(p: data.Point) -> str:
    return f"({p[0]:g}, {p[1]:g})"


def draw_maps(fig: Figure, ex: explore.Explorer) -> list[patches.Rectangle]:
    """The M_L and M_CF maps; returns the markers :func:`mark_maps` moves (per map: the design's,
    solid, and its mirror image's, dashed)."""
    fig.clear()
    axes = fig.subplots(1, 2)
    n = ex.n
    marks = []
    for ax, metric in zip(axes, ("M_L", "M_CF"), strict=True):
        img = ex.map_image(metric)
        cmap = plt.get_cmap(MAP_CMAP).with_extremes(bad="#e0e0e0")  # designs the sweep has not run
        top = float(np.nanmax(img)) if np.isfinite(img).any() else 1.0
        im = ax.imshow(
            np.ma.masked_invalid(img), origin="lower", cmap=cmap, interpolation="nearest", vmin=0.0, vmax=max(top, 1e-9)
        )
        for k in range(1, n):  # block borders: one block per position of sensor 1
            ax.axhline(k * n - 0.5, color="white", lw=0.6)
            ax.axvline(k * n - 0.5, color="white", lw=0.6)
        ticks = [k * n + (n - 1) / 2 for k in range(n)]
        ax.set_xticks(ticks, [f"{v:g}" for v in ex.axis], fontsize=7)
        ax.set_yticks(ticks, [f"{v:g}" for v in ex.axis], fontsize=7)
        ax.set_xlabel("sensor 1 x (forward); inside a block: sensor 2 x", fontsize=9)
        ax.set_ylabel("sensor 1 y (left); inside a block: sensor 2 y", fontsize=9)
        ax.set_title(
            f"{metric} of {ex.res.model} ({ex.res.paths['metrics'].split('/')[-3]}), {len(ex.res.table)} designs",
            fontsize=10,
        )
        for ls, col in (("--", "white"), ("-", "red")):
            marks.append(ax.add_patch(patches.Rectangle((0, 0), 1, 1, fill=False, ec=col, lw=2.0, ls=ls)))
        fig.colorbar(im, ax=ax, shrink=0.8, pad=0.02)
    return marks


def mark_maps(marks: list[patches.Rectangle], ex: explore.Explorer, design: int) -> None:
    """Move the map markers to a design (solid red) and its mirror image (dashed white)."""
    for k, mark in enumerate(marks):
        c, r = ex.map_cell(ex.mirror(design) if k % 2 == 0 else design)
        mark.set_xy((c - 0.5, r - 0.5))


def draw_design(
    fig: Figure,
    ex: explore.Explorer,
    land: explore.Landscape | None,
    design: int,
    w: tuple[float, float] | None,
    note: str = "",
) -> None:
    """The design's sketch and its mirror image's, and its overlap matrix with the chosen controller."""
    fig.clear()
    a_robot, a_mirror, a_mat = fig.subplots(1, 3, width_ratios=[1, 1, 2.2])
    for ax, d, what in ((a_robot, design, "design"), (a_mirror, ex.mirror(design), "mirror image")):
        l1, l2 = ex.coords(d)
        sketch.robot(ax, l1, l2)
        sketch.body_axes(ax, 0.8)
        ax.set_title(f"{what} {d}\nl1 {_fmt(l1)}\nl2 {_fmt(l2)}", fontsize=9)
    if land is None:
        panel.missing(a_mat, note or "no outcome arrays", title="overlap matrix")
        return
    m = len(land.weights)
    how = "bundle" if land.source == "bundle" else f"live, {land.seconds:.2f} s"
    im = matrix.overlap_image(a_mat, land.overlap, land.weights, f"overlap O, {m} x {m} ({how})")
    a_mat.title.set_fontsize(10)
    matrix.overlap_colorbar(fig, im, a_mat)
    if w is not None:
        a_mat.plot(*w, marker="s", ms=9, mfc="none", mec="black", mew=1.8)


def draw_trajectories(
    fig: Figure,
    ex: explore.Explorer,
    design: int,
    w: tuple[float, float] | None,
    trs: list | None,
    overlap: int | None,
    note: str = "",
) -> None:
    """The controller's four trajectories, the light (success radius) and the first successes."""
    fig.clear()
    ax = fig.subplots()
    if trs is None or w is None:
        panel.missing(ax, note or "no trajectories", title="trajectories")
        return
    s = ex.settings()
    times = ", ".join(
        f"{a}°: {'-' if not math.isfinite(t.first_time) else f'{t.first_time:.1f}'}"
        for a, t in zip(ENV_ANGLES_DEG, trs, strict=True)
    )
    solves = "" if overlap is None else f", solves {overlap} of 4 on the grid"
    trajectory.trajectory_panel(
        ax,
        trs,
        ex.coords(design),
        s.r,
        s.radius,
        f"$(w_1, w_2) = ({w[0]:.3g}, {w[1]:.3g})${solves}\nfirst success t ({s.horizon:g} max): {times}",
    )
    ax.title.set_fontsize(9)
    trajectory.trajectory_legend(fig, None)
    # the paper figures' legend in two columns (its four are wider than this one panel), and fixed
    # margins: under ipympl, constrained layout cuts the top of this two-line title
    legend = fig.legends.pop()
    fig.legend(handles=legend.legend_handles, loc="lower center", ncols=2, frameon=False, fontsize=9)
    fig.subplots_adjust(left=0.13, right=0.97, top=0.89, bottom=0.24)


def describe_html(info: dict[str, Any]) -> str:
    """The design's metrics, ranks and mirror image as a small HTML table."""
    t = info.get("table")
    rank = info.get("rank", {})
    mat = info["matrix"]
    rows = [("design", f"{info['design']}: l1 {_fmt(info['l1'])}, l2 {_fmt(info['l2'])}")]
    if t:
        rows += [
            ("M_L (bundle)", f"{t['M_L']:.4g} (rank {rank['M_L']} of {info['designs']})"),
            ("M_CF (bundle)", f"{t['M_CF']:.4g} (rank {rank['M_CF']} of {info['designs']})"),
            ("generalists", f"{t['generalists']}; at least one env.: {t['at_least_one']}; flagged {t['flagged']}"),
        ]
    src = "the bundle's arrays" if info["source"] == "bundle" else f"computed live in {info['seconds']:.2f} s"
    check = {True: "; equals the bundle's metrics", False: "; DIFFERS from the bundle's metrics", None: ""}[
        info["matches_table"]
    ]
    rows.append(
        (
            "matrix",
            f"{info['weights']} x {info['weights']} weights, {src}: generalists "
            f"{mat['generalists']}, M_L {mat['M_L']:.4g}, M_CF {mat['M_CF']:.4g}{check}",
        )
    )
    mt = info.get("mirror_table")
    ml1, ml2 = info["mirror_coords"]
    rows.append(
        (
            "mirror image",
            f"{info['mirror']}: l1 {_fmt(ml1)}, l2 {_fmt(ml2)}"
            + (f"; M_L {mt['M_L']:.4g}, M_CF {mt['M_CF']:.4g}" if mt else ""),
        )
    )
    body = "".join(
        f"<tr><th style='text-align:left;vertical-align:top;padding-right:8px;white-space:nowrap'>"
        f"{html.escape(k)}</th><td>{html.escape(v)}</td></tr>"
        for k, v in rows
    )
    return f"<table style='font-size:12px;line-height:1.35'>{body}</table>"


class App:
    """The explorer's interface over the bundles under ``results_dir``."""

    def __init__(
        self,
        results_dir: str | Path = "results",
        *,
        source: str | None = None,
        design: tuple[data.Point, data.Point] | None = None,
        live_weights: int = 41,
        controller: data.Point | None = None,
    ) -> None:
        self.sources = explore.sources(results_dir)
        if not self.sources:
            raise explore.ExploreError(f"{results_dir}: no results bundle (a folder with bundle.json)")
        labels = [s.label for s in self.sources]
        if source is not None and source not in labels:
            raise explore.ExploreError(f"source {source!r}: allowed: {', '.join(labels)}")
        self._explorers: dict[str, explore.Explorer] = {}
        self.timings: list[dict[str, Any]] = []  # one entry per update (what, seconds)
        # Load the theory kernel's compiled code (numba's cache: ~3 s) while the page draws, not on
        # the first live design.
        threading.Thread(target=explore.warm_up, daemon=True).start()
        with plt.ioff():  # figures are shown as widgets, not as cell outputs
            self.fig_maps = plt.figure(figsize=(10.5, 4.6), layout="constrained")
            self.fig_design = plt.figure(figsize=(9.5, 3.4), layout="constrained")
            self.fig_traj = plt.figure(figsize=(5.4, 6.2))
        for f in (self.fig_maps, self.fig_design, self.fig_traj):
            _canvas_options(f)
        self.w_source = W.Dropdown(options=labels, value=source or labels[0], description="results")
        self.w_weights = W.ToggleButtons(
            options=list(explore.LIVE_WEIGHTS),
            value=live_weights,
            description="live grid",
            tooltips=["41 x 41", "121 x 121"],
        )
        self.w_l1 = W.Dropdown(description="sensor 1")
        self.w_l2 = W.Dropdown(description="sensor 2")
        self.w_best = W.Dropdown(options=["-", "best M_L", "best M_CF", "canonical"], value="-", description="go to")
        # a fixed height: the figure below stays put when the text changes
        self.w_info = W.HTML(layout=W.Layout(height="190px", overflow="auto", margin="0 0 8px 0"))
        self.w_status = W.HTML()
        self.w_status.add_class("ml-status")  # the browser test waits on this
        self.w_info.add_class("ml-info")
        self._quiet = False
        self._maps_of: str | None = None
        self._marks: list[patches.Rectangle] = []
        self.trs: list | None = None
        self.design = 0
        self.land: explore.Landscape | None = None
        self.w: tuple[float, float] | None = None
        self._set_source(self.w_source.value, design, controller)
        self.w_source.observe(lambda ch: self._set_source(ch["new"]), names="value")
        self.w_l1.observe(self._on_dropdown, names="value")
        self.w_l2.observe(self._on_dropdown, names="value")
        self.w_weights.observe(lambda ch: self.select(self.design), names="value")
        self.w_best.observe(self._on_goto, names="value")
        self.fig_maps.canvas.mpl_connect("button_press_event", self._on_map_click)
        self.fig_design.canvas.mpl_connect("button_press_event", self._on_matrix_click)

    # -- state -------------------------------------------------------------------------------------
    @property
    def ex(self) -> explore.Explorer:
        label = self.w_source.value
        if label not in self._explorers:
            src = next(s for s in self.sources if s.label == label)
            self._explorers[label] = explore.Explorer(explore.open_source(src))
        return self._explorers[label]

    def _set_source(
        self, label: str, design: tuple[data.Point, data.Point] | None = None, controller: data.Point | None = None
    ) -> None:
        ex = self.ex
        opts = [(_fmt((x, y)), (float(x), float(y))) for x in ex.axis[::-1] for y in ex.axis[::-1]]
        self._quiet = True
        try:
            self.w_l1.options = opts
            self.w_l2.options = opts
        finally:
            self._quiet = False
        d = ex.design_of(*design) if design is not None else ex.best("M_L")
        self.w_weights.disabled = ex.theory_params is None
        self.select(d, controller)

    def _busy(self, text: str) -> None:
        self.w_status.value = f"<i>{html.escape(text)}</i>"

    def select(self, design: int, controller: data.Point | None = None) -> None:
        """Show a design: maps, its overlap matrix (bundle or live), a controller's trajectories."""
        ex = self.ex
        design = ex.check_design(design)
        t0 = time.perf_counter()
        self._busy(f"computing design {design} ...")
        self.design = design
        l1, l2 = ex.coords(design)
        self._quiet = True
        try:
            self.w_l1.value, self.w_l2.value = l1, l2
        finally:
            self._quiet = False
        note = ""
        try:
            self.land = ex.landscape(design, self.w_weights.value)
        except explore.ExploreError as e:
            self.land, note = None, str(e)
        if self._maps_of != self.w_source.value:  # the maps are drawn once per source
            self._marks = draw_maps(self.fig_maps, ex)
            self._maps_of = self.w_source.value
        mark_maps(self._marks, ex, design)
        if self.land is not None:
            self.w = controller if controller is not None else ex.default_controller(self.land)
            i, j = self.land.controller(*self.w)
            self.w = (float(self.land.weights[i]), float(self.land.weights[j]))
        else:
            self.w = None
        draw_design(self.fig_design, ex, self.land, design, self.w, note)
        _push(self.fig_maps)
        _push(self.fig_design)
        self.w_info.value = (
            describe_html(explore.describe(ex, self.land)) if self.land is not None else f"<p>{html.escape(note)}</p>"
        )
        land_s = time.perf_counter() - t0
        self._status(f"design {design}: landscape shown in {land_s:.2f} s; integrating trajectories ...", "landscape")
        self._draw_controller()
        total = time.perf_counter() - t0
        self.timings.append(
            {
                "what": "design",
                "design": design,
                "landscape_s": land_s,
                "total_s": total,
                "source": None if self.land is None else self.land.source,
                "live_s": None if self.land is None else self.land.seconds,
            }
        )
        self._status(f"design {design}: landscape in {land_s:.2f} s, trajectories in {total - land_s:.2f} s")

    def select_controller(self, w1: float, w2: float) -> None:
        if self.land is None:
            return
        i, j = self.land.controller(w1, w2)
        self.w = (float(self.land.weights[i]), float(self.land.weights[j]))
        t0 = time.perf_counter()
        draw_design(self.fig_design, self.ex, self.land, self.design, self.w)
        _push(self.fig_design)
        self._draw_controller()
        self.timings.append(
            {"what": "controller", "design": self.design, "w": self.w, "total_s": time.perf_counter() - t0}
        )
        self._status(f"controller ({self.w[0]:.3g}, {self.w[1]:.3g}) of design {self.design} shown")

    def _draw_controller(self) -> None:
        ex, note = self.ex, ""
        trs = overlap = None
        if self.w is not None and ex.theory_params is not None:
            trs = ex.trajectories(self.design, self.w)
            i, j = self.land.controller(*self.w)
            overlap = int(self.land.overlap[i, j])
        elif ex.theory_params is None:
            note = "trajectories: theory model only"
        self.trs = trs
        draw_trajectories(self.fig_traj, ex, self.design, self.w, trs, overlap, note)
        _push(self.fig_traj)

    def _status(self, text: str, stage: str = "done") -> None:
        # data-*: what the browser test reads (stage: "landscape" drawn, or "done" with the
        # trajectories); the text: what a person reads
        self.w_status.value = (
            f"<span data-design='{self.design}' data-w='{self.w}' data-stage='{stage}'>{html.escape(text)}</span>"
        )

    # -- events ------------------------------------------------------------------------------------
    def _on_dropdown(self, _change: dict[str, Any]) -> None:
        if self._quiet or self.w_l1.value is None or self.w_l2.value is None:
            return
        self.select(self.ex.design_of(self.w_l1.value, self.w_l2.value))

    def _on_goto(self, change: dict[str, Any]) -> None:
        what = change["new"]
        if what == "-":
            return
        from morphlearn import grid as gridmod

        ex = self.ex
        d = ex.design_of(*gridmod.canonical_design()) if what == "canonical" else ex.best(what.split()[1])
        self.w_best.value = "-"
        self.select(d)

    def _on_map_click(self, event: Any) -> None:
        # the two maps, not their colour bars (whose data coordinates are metric values)
        if event.inaxes is None or event.inaxes not in self._marks_axes() or event.xdata is None:
            return
        d = self.ex.design_at(event.xdata, event.ydata)
        if d is not None:
            self.select(d)

    def _marks_axes(self) -> list[Any]:
        return [m.axes for m in self._marks]

    def _on_matrix_click(self, event: Any) -> None:
        axes = self.fig_design.axes
        if self.land is None or len(axes) < 3 or event.inaxes is not axes[2] or event.xdata is None:
            return
        self.select_controller(event.xdata, event.ydata)

    # -- layout ------------------------------------------------------------------------------------
    def widget(self) -> W.Widget:
        def canvas(fig: Figure) -> W.Widget:
            c = fig.canvas
            if isinstance(c, W.DOMWidget):
                return c
            out = W.Output()  # not the widget backend: a static image
            with out:
                from IPython.display import display

                display(fig)
            return out

        head = W.HTML(
            "Click a cell of a map (or pick the two sensor positions) for a design's overlap matrix; "
            "click a controller in the matrix for its trajectories."
        )
        controls = W.HBox([self.w_source, self.w_l1, self.w_l2])
        left = W.VBox([canvas(self.fig_maps), canvas(self.fig_design)])
        right = W.VBox([self.w_status, self.w_info, canvas(self.fig_traj)], layout=W.Layout(width="620px"))
        return W.VBox([head, controls, W.HBox([self.w_weights, self.w_best]), W.HBox([left, right])])


def _push(fig: Figure) -> None:
    """Show a figure's new drawing now. ipympl: draw() sends the image at once, while the callback
    goes on (to the trajectories); draw_idle() asks the page for a round trip that the busy kernel
    answers only when the callback ends. Before the page has shown the canvas (``syncing_data_url``)
    it must be draw_idle(): an image sent then reaches the page as a broken data URL (ipympl 0.10).
    Always a full image, not a diff against the last one sent: a diff applied to a page whose image
    is not that one (a draw the page never showed) leaves stale pixels."""
    c = fig.canvas
    if getattr(c, "syncing_data_url", False):
        c.draw_idle()
    else:
        c._force_full = True
        c.draw()


def _canvas_options(fig: Figure) -> None:
    c = fig.canvas
    for k, v in (
        ("header_visible", False),
        ("footer_visible", False),
        ("toolbar_visible", False),
        ("resizable", False),
    ):
        if hasattr(c, k):
            setattr(c, k, v)
