"""The explorer's widgets and figures (ipywidgets + ipympl, and a small anywidget bridge to the page;
docs/explorer.md says why).

``App(results_dir)`` builds the interface: a source (bundle and model), the M_L and M_CF maps over
sensor placements (hover a cell for its design, click it to select it), a top-N table ranked by M_L
or M_CF with a search, the selected design's overlap matrix (click a controller), its four
trajectories, its metrics, ranks and mirror image, and the bundle's models (engines) side by side.
The drawing reuses the paper figures' code (morphlearn.figures.draw); the logic is
morphlearn.apps.explore. Each figure's ``canvas`` is an ipympl widget under ``%matplotlib widget``;
under another backend (Agg in the unit tests) the handlers are called directly.

:class:`Bridge` does what only the page can: it reports the page's width (the figures are sized to
it), writes the view into the URL, downloads exports, and confirms that the figures are drawn (the
status says "done" only then).
"""

from __future__ import annotations

import html
import math
import os
import threading
import time
from pathlib import Path
from typing import Any

import anywidget
import ipywidgets as W  # noqa: N812 (the ipywidgets convention)
import matplotlib.pyplot as plt
import numpy as np
import traitlets
from IPython.display import display
from matplotlib import patches
from matplotlib.figure import Figure

from morphlearn import grid as gridmod
from morphlearn.apps import explore
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
        ax.format_coord = _map_coord(ex)  # ipympl's read-out: the design, not "(x, y) = (, )"
    return marks


def _map_coord(ex: explore.Explorer) -> Any:
    def fmt(x: float, y: float) -> str:
        d = ex.design_at(x, y)
        return "" if d is None else ex.hover(d)

    return fmt


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
        f"$(w_1, w_2) = ({w[0]:.3g}, {w[1]:.3g})${solves}\nfirst success t ({s.horizon:g} max):\n{times}",
    )
    ax.title.set_fontsize(9)
    trajectory.trajectory_legend(fig, None)
    # the paper figures' legend in two columns (its four are wider than this one panel), and fixed
    # margins: under ipympl, constrained layout cuts the top of this two-line title
    legend = fig.legends.pop()
    fig.legend(handles=legend.legend_handles, loc="lower center", ncols=2, frameon=False, fontsize=9)
    traj_margins(fig)


def traj_margins(fig: Figure) -> None:
    """The trajectory panel's margins in pixels, whatever the figure's size (it follows the page):
    three title lines above, the x label and the legend's four rows below."""
    w_px, h_px = fig.get_size_inches() * getattr(fig, "_original_dpi", fig.dpi)
    fig.subplots_adjust(left=58 / w_px, right=1 - 14 / w_px, top=1 - 62 / h_px, bottom=142 / h_px)


def draw_engines(fig: Figure, panels: list[tuple[str, explore.Landscape | None, str]]) -> None:
    """One overlap matrix per model of the bundle, side by side, for the same design: (title, its
    landscape or None, the note drawn where it has none)."""
    fig.clear()
    axes = fig.subplots(1, len(panels), squeeze=False)[0]
    shown = []
    for ax, (title, land, note) in zip(axes, panels, strict=True):
        if land is None:
            panel.missing(ax, note, title=title)
            ax.title.set_fontsize(9)
            continue
        shown.append(ax)
        im = matrix.overlap_image(ax, land.overlap, land.weights, title)
        ax.title.set_fontsize(9)
    if shown:
        matrix.overlap_colorbar(fig, im, shown)


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


def layout_sizes(width: int) -> dict[str, tuple[int, int]]:
    """Each figure's size in CSS pixels for an app ``width`` pixels wide (the page's, as the bridge
    measures it), so that none is wider than the page: the maps beside a 400-pixel side bar (status,
    metrics, top-N table) from 1100 pixels up, above it below that; the design and its trajectories
    side by side where they fit (the boxes wrap otherwise)."""
    w = max(int(width), 480)
    side = SIDEBAR if w >= 1100 else w - 8
    maps_w = min(w - SIDEBAR - 24, 1400) if w >= 1100 else w - 8
    design_w = min(w - 8, 860)
    traj_w = min(w - 8, 440)
    return {
        "maps": (maps_w, round(maps_w * 0.47)),
        "design": (design_w, round(design_w * 0.38)),
        "traj": (traj_w, round(traj_w * 1.15)),
        "engines": (min(w - 8, 1100), 300),
        "side": (side, 0),
    }


#: The side bar's width (px): status, the design's metrics, the top-N table.
SIDEBAR = 400
#: The page width assumed until the page reports its own: a 1366-pixel laptop screen's, less the
#: scroll bar and Voila's margins (the figures fit it; a wider page enlarges them).
DEFAULT_WIDTH = 1320
#: Rows of the top-N table.
TOP_N = 40

_BRIDGE_ESM = """
function render({ model, el }) {
  el.style.width = "100%";
  el.style.height = "0px";
  const report = () => {
    const box = el.getBoundingClientRect().width;
    const w = Math.floor(Math.min(box > 0 ? box : 1e9, document.documentElement.clientWidth));
    if (w !== model.get("width")) {
      model.set("width", w);
      model.save_changes();
    }
  };
  let timer = null;
  const later = () => { clearTimeout(timer); timer = setTimeout(report, 150); };
  window.addEventListener("resize", later);
  const ro = new ResizeObserver(later);
  ro.observe(el);
  report();
  const writeUrl = () => {
    if (!model.get("sync_url")) return;
    const url = new URL(window.location.href);
    url.search = model.get("query");
    window.history.replaceState(null, "", url);
  };
  model.on("change:query", writeUrl);
  writeUrl();
  // The kernel sends its figures' images before it changes the token (one channel, in order): once
  // the page has handled the token and painted twice, the images sent before it are on the page.
  const ack = () => {
    const token = model.get("token");
    requestAnimationFrame(() => requestAnimationFrame(() => setTimeout(() => {
      model.set("drawn", token);
      model.save_changes();
    }, 20)));
  };
  model.on("change:token", ack);
  if (model.get("token") !== model.get("drawn")) ack();  // an update sent before this view existed
  model.on("msg:custom", (msg) => {
    if (!msg || !msg.download) return;
    const blob = new Blob([msg.text], { type: msg.mime });
    const a = document.createElement("a");
    a.href = URL.createObjectURL(blob);
    a.download = msg.download;
    document.body.appendChild(a);
    a.click();
    setTimeout(() => { URL.revokeObjectURL(a.href); a.remove(); }, 1000);
  });
  return () => { window.removeEventListener("resize", later); ro.disconnect(); };
}
export default { render };
"""


class Bridge(anywidget.AnyWidget):
    """The page side of the app (a few lines of JavaScript, no visible element): the app's width
    on the page, the URL's query (written when ``sync_url``: under Voila, not in JupyterLab, whose
    URL is its own), the images' arrival (``drawn`` echoes ``token``) and file downloads."""

    _esm = _BRIDGE_ESM
    width = traitlets.Int(0).tag(sync=True)
    query = traitlets.Unicode("").tag(sync=True)
    sync_url = traitlets.Bool(False).tag(sync=True)
    token = traitlets.Int(0).tag(sync=True)
    drawn = traitlets.Int(0).tag(sync=True)

    def download(self, filename: str, text: str, mime: str) -> None:
        self.send({"download": filename, "text": text, "mime": mime})


class App:
    """The explorer's interface over the bundles under ``results_dir``; ``url_query`` (Voila's
    ``QUERY_STRING``) reopens a shared view and wins over ``source``, ``design`` and ``controller``."""

    def __init__(
        self,
        results_dir: str | Path = "results",
        *,
        source: str | None = None,
        design: tuple[data.Point, data.Point] | None = None,
        live_weights: int = 41,
        controller: data.Point | None = None,
        url_query: str | None = None,
    ) -> None:
        self.sources = explore.sources(results_dir)
        if not self.sources:
            raise explore.ExploreError(f"{results_dir}: no results bundle (a folder with bundle.json)")
        labels = [s.label for s in self.sources]
        if source is not None and source not in labels:
            raise explore.ExploreError(f"source {source!r}: allowed: {', '.join(labels)}")
        # A shared link: its errors are shown (the default view opens), not raised: the page must open.
        url_note, view = "", explore.View()
        try:
            view = explore.parse_view(url_query)
            if view.source is not None and view.source not in labels:
                raise explore.ExploreError(f"URL source={explore._shown(view.source)}: allowed: {', '.join(labels)}")
        except explore.ExploreError as e:
            url_note, view = str(e), explore.View()
        self._explorers: dict[str, explore.Explorer] = {}
        self.timings: list[dict[str, Any]] = []  # one entry per update (what, seconds)
        # Load the theory kernel's compiled code (numba's cache: ~3 s) while the page draws, not on
        # the first live design.
        threading.Thread(target=explore.warm_up, daemon=True).start()
        self.sizes = layout_sizes(DEFAULT_WIDTH)
        with plt.ioff():  # figures are shown as widgets, not as cell outputs
            self.fig_maps = plt.figure(figsize=_inches(self.sizes["maps"]), layout="constrained")
            self.fig_design = plt.figure(figsize=_inches(self.sizes["design"]), layout="constrained")
            self.fig_traj = plt.figure(figsize=_inches(self.sizes["traj"]))
            self.fig_engines = plt.figure(figsize=_inches(self.sizes["engines"]), layout="constrained")
        self.figures = {
            "maps": self.fig_maps,
            "design": self.fig_design,
            "traj": self.fig_traj,
            "engines": self.fig_engines,
        }
        for f in self.figures.values():
            _canvas_options(f)
        self.bridge = Bridge(sync_url=os.environ.get("SERVER_SOFTWARE", "").startswith("voila"))
        self.w_source = W.Dropdown(
            options=labels,
            value=view.source or source or labels[0],
            description="results",
            layout=W.Layout(width="290px"),
            style={"description_width": "60px"},
        )
        self.w_weights = W.ToggleButtons(
            options=list(explore.LIVE_WEIGHTS),
            value=live_weights,
            description="live grid",
            tooltips=["41 x 41", "121 x 121"],
            style={"button_width": "60px", "description_width": "60px"},
            layout=W.Layout(width="auto", margin="2px 4px 2px 16px"),  # clear of the sensor 2 dropdown
        )
        # wide enough for the longest position, "(-0.375, -0.125)", beside its label (issue 59)
        sensor = {"layout": W.Layout(width="225px"), "style": {"description_width": "60px"}}
        self.w_l1 = W.Dropdown(description="sensor 1", **sensor)
        self.w_l2 = W.Dropdown(description="sensor 2", **sensor)
        self.w_best = W.Dropdown(
            options=["-", "best M_L", "best M_CF", "canonical"],
            value="-",
            description="go to",
            layout=W.Layout(width="175px"),
            style={"description_width": "45px"},
        )
        self.w_rank_by = W.ToggleButtons(
            options=list(explore.METRIC_NAMES), value=view.metric, description="rank by", style={"button_width": "60px"}
        )
        self.w_search = W.Text(
            placeholder="search: a design number, or (x, y), e.g. l1 (0.5, 0.5)",
            layout=W.Layout(width="98%"),
        )
        self.w_search.add_class("ml-search")
        head = html.escape(_top_row("#", "design", "l1", "l2", "M_L", "M_CF"))
        self.w_top_head = W.HTML(f"<pre class='ml-top-head' style='{_MONO}'>{head}</pre>")
        self.w_top = W.Select(rows=14, layout=W.Layout(width="98%"))
        self.w_top.add_class("ml-top")
        self.w_export_csv = W.Button(description="export CSV", tooltip="the shown design's outcomes per controller")
        self.w_export_json = W.Button(description="export JSON", tooltip="the shown design's metrics and arrays")
        for b in (self.w_export_csv, self.w_export_json):
            b.add_class("ml-export")
            b.layout.width = "110px"
        # a fixed height: the figure below stays put when the text changes
        self.w_info = W.HTML(layout=W.Layout(height="170px", overflow="auto", margin="0 0 4px 0"))
        self.w_status = W.HTML()
        self.w_hover = W.HTML("<i>hover a map cell for its design; click it to select it</i>")
        self.w_engines = W.HTML()
        self._side = W.VBox(
            [self.w_status, self.w_info, self.w_rank_by, self.w_search, self.w_top_head, self.w_top],
            layout=W.Layout(width=f"{self.sizes['side'][0]}px"),
        )
        # the bundle's models side by side: shown where the bundle holds several
        self._engines_box = W.VBox([self.w_engines])  # + the figure, in widget()
        self.w_status.add_class("ml-status")  # the browser test waits on this
        self.w_info.add_class("ml-info")
        self.w_hover.add_class("ml-hover")
        self._quiet = False
        self._maps_of: str | None = None
        self._marks: list[patches.Rectangle] = []
        self._hovered: int | None = None
        self._pending: tuple[int, str, float] | None = None  # token, status text, start
        self._unsettled = False  # an image went by the page's round trip (draw_idle) or a figure was resized
        self._rounds = 0
        self._shown = ""  # the last update's text, as the status showed it
        self.trs: list | None = None
        self.design = 0
        self.land: explore.Landscape | None = None
        self.w: tuple[float, float] | None = None
        self.note = url_note
        first = None
        if view.design is not None:
            first = self._in_grid(self.ex, view.design)
        self._set_source(self.w_source.value, design, view.w or controller, first=first)
        self.w_source.observe(lambda ch: self._set_source(ch["new"], carry=ch["old"]), names="value")
        self.w_l1.observe(self._on_dropdown, names="value")
        self.w_l2.observe(self._on_dropdown, names="value")
        self.w_weights.observe(lambda ch: self.select(self.design), names="value")
        self.w_best.observe(self._on_goto, names="value")
        self.w_rank_by.observe(self._on_rank_by, names="value")
        self.w_search.observe(lambda ch: self._fill_top(), names="value")
        self.w_top.observe(self._on_top, names="value")
        self.w_export_csv.on_click(lambda _b: self.export("csv"))
        self.w_export_json.on_click(lambda _b: self.export("json"))
        self.bridge.observe(self._on_width, names="width")
        self.bridge.observe(self._on_drawn, names="drawn")
        self.fig_maps.canvas.mpl_connect("button_press_event", self._on_map_click)
        self.fig_maps.canvas.mpl_connect("motion_notify_event", self._on_map_hover)
        self.fig_design.canvas.mpl_connect("button_press_event", self._on_matrix_click)

    # -- state -------------------------------------------------------------------------------------
    def explorer(self, label: str) -> explore.Explorer:
        if label not in self._explorers:
            src = next(s for s in self.sources if s.label == label)
            self._explorers[label] = explore.Explorer(explore.open_source(src))
        return self._explorers[label]

    @property
    def ex(self) -> explore.Explorer:
        return self.explorer(self.w_source.value)

    @property
    def source(self) -> explore.Source:
        return next(s for s in self.sources if s.label == self.w_source.value)

    def siblings(self) -> list[explore.Source]:
        """The models of the shown source's bundle (the engines shown side by side)."""
        return [s for s in self.sources if s.bundle == self.source.bundle]

    def _in_grid(self, ex: explore.Explorer, design: int) -> int | None:
        try:
            return ex.check_design(design)
        except explore.ExploreError as e:
            self.note = f"URL: {e}"
            return None

    def _set_source(
        self,
        label: str,
        design: tuple[data.Point, data.Point] | None = None,
        controller: data.Point | None = None,
        *,
        carry: str | None = None,
        first: int | None = None,
    ) -> None:
        ex = self.ex
        opts = [(_fmt((x, y)), (float(x), float(y))) for x in ex.axis[::-1] for y in ex.axis[::-1]]
        self._quiet = True
        try:
            self.w_l1.options = opts
            self.w_l2.options = opts
        finally:
            self._quiet = False
        if first is not None:
            d = first
        elif design is not None:
            d = ex.design_of(*design)
        elif carry is not None:
            # the design shown before, kept: the same sensor positions, or the nearest on this grid
            was = self.explorer(carry).coords(self.design)
            d, exact = ex.nearest_design(*was)
            if not exact:
                self.note = (
                    f"{data.design_label(*was)} is not on this bundle's {ex.n} x {ex.n} grid: "
                    f"the nearest design, {d}, is shown"
                )
            controller = controller or self.w
        else:
            d = ex.best(self.w_rank_by.value)
        self.w_weights.disabled = ex.theory_params is None
        self._fill_top()
        self.select(d, controller)

    def _busy(self, text: str) -> None:
        self.w_status.value = f"<span data-stage='busy'><i>{html.escape(text)}</i></span>"

    def select(self, design: int, controller: data.Point | None = None) -> None:
        """Show a design: maps, its overlap matrix (bundle or live), a controller's trajectories,
        the bundle's other models; the status says "done" once the page has drawn them."""
        ex = self.ex
        design = ex.check_design(design)
        t0 = time.perf_counter()
        self._busy(f"computing design {design} ...")
        self.design = design
        l1, l2 = ex.coords(design)
        self._quiet = True
        try:
            self.w_l1.value, self.w_l2.value = l1, l2
            self.w_top.value = design if design in dict(self.w_top.options).values() else None
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
        self._push(self.fig_maps, self.fig_design)
        info = describe_html(explore.describe(ex, self.land)) if self.land is not None else ""
        extra = " ".join(x for x in (self.note, note) if x)
        self.w_info.value = info + (f"<p style='color:#a33'>{html.escape(extra)}</p>" if extra else "")
        self.note = ""
        self._write_url()
        land_s = time.perf_counter() - t0
        self._status(f"design {design}: landscape shown in {land_s:.2f} s; integrating trajectories ...", "landscape")
        self._draw_controller()
        traj_s = time.perf_counter() - t0 - land_s
        self._draw_engines()
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
        self._await_page(
            f"design {design}: landscape in {land_s:.2f} s, trajectories in {traj_s:.2f} s, "
            f"models in {total - land_s - traj_s:.2f} s",
            t0,
        )

    def select_controller(self, w1: float, w2: float) -> None:
        if self.land is None:
            return
        i, j = self.land.controller(w1, w2)
        self.w = (float(self.land.weights[i]), float(self.land.weights[j]))
        t0 = time.perf_counter()
        draw_design(self.fig_design, self.ex, self.land, self.design, self.w)
        self._push(self.fig_design)
        self._draw_controller()
        self._write_url()
        self.timings.append(
            {"what": "controller", "design": self.design, "w": self.w, "total_s": time.perf_counter() - t0}
        )
        self._await_page(f"controller ({self.w[0]:.3g}, {self.w[1]:.3g}) of design {self.design} shown", t0)

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
        self._push(self.fig_traj)

    def engines(self) -> list[dict[str, Any]]:
        """The shown design in every model of its bundle: engine, metrics and ranks (None: the
        model did not simulate it) and its landscape where the bundle holds it (the theory model:
        computed live otherwise, as the main view does)."""
        coords = self.ex.coords(self.design)
        out = []
        for src in self.siblings():
            ex = self.explorer(src.label)
            d, exact = ex.nearest_design(*coords)
            row = ex.row(d) if exact else None
            land = None
            if exact and (ex.held(d) or ex.theory_params is not None):
                land = self.land if src.label == self.w_source.value else ex.landscape(d, self.w_weights.value)
            out.append(
                {
                    "label": src.label,
                    "engine": src.engine,
                    "design": d if exact else None,
                    "designs": len(ex.res.table),
                    "M_L": None if row is None else float(row.M_L),
                    "M_CF": None if row is None else float(row.M_CF),
                    "rank": None if row is None else {by: ex.rank(d, by) for by in explore.METRIC_NAMES},
                    "landscape": land,
                }
            )
        return out

    def _draw_engines(self) -> None:
        several = len(self.siblings()) > 1
        self._engines_box.layout.display = None if several else "none"
        if not several:
            return
        rows = self.engines()
        panels = []
        for r in rows:
            land = r["landscape"]
            if land is None:
                panels.append((r["engine"], None, f"not simulated\n({r['designs']} designs are)"))
                continue
            m = len(land.weights)
            how = "bundle" if land.source == "bundle" else f"live, {land.seconds:.2f} s"
            ml = "" if r["M_L"] is None else f"\nM_L {r['M_L']:.4g}, M_CF {r['M_CF']:.4g}"
            panels.append((f"{r['engine']}: {m} x {m} ({how}){ml}", land, ""))
        draw_engines(self.fig_engines, panels)
        self._push(self.fig_engines)
        self.w_engines.value = engines_html(rows, self.source.bundle.name)

    def _status(self, text: str, stage: str = "done") -> None:
        # data-*: what the browser test reads (stage: "landscape" drawn, "sent" all figures sent,
        # "done" on the page); the text: what a person reads
        w = "None" if self.w is None else f"({self.w[0]:.6g}, {self.w[1]:.6g})"
        self.w_status.value = (
            f"<span data-design='{self.design}' data-w='{w}' data-stage='{stage}'>{html.escape(text)}</span>"
        )

    # -- the page ----------------------------------------------------------------------------------
    def _has_page(self) -> bool:
        return isinstance(self.fig_maps.canvas, W.DOMWidget)

    def _push(self, *figs: Figure) -> None:
        for fig in figs:
            if not _push(fig):
                self._unsettled = True

    def _await_page(self, text: str, t0: float) -> None:
        """Status "done" once the page has the figures: at once without a page (Agg, papermill),
        else when the bridge echoes a token sent after the images."""
        if not self._has_page():
            self._shown = text
            self._status(text)
            return
        token = self.bridge.token + 1
        self._pending = (token, text, t0)
        self._rounds = 0
        self._status(f"{text}; drawing on the page ...", "sent")
        self.bridge.token = token

    def _on_drawn(self, change: dict[str, Any]) -> None:
        if self._pending is None or change["new"] != self._pending[0]:
            return  # an older update's echo
        token, text, t0 = self._pending
        if self._unsettled and self._rounds < 100 and time.perf_counter() - t0 < 60:
            # some image went by the page's own request (before the page showed its canvas, or
            # after a resize): send every figure again, directly, and wait for another echo
            self._unsettled = False
            self._rounds += 1
            self._push(*self.figures.values())
            self._pending = (token + 1, text, t0)
            self.bridge.token = token + 1
            return
        page_s = time.perf_counter() - t0
        if self.timings:
            self.timings[-1]["page_s"] = page_s
        self._pending = None
        self._shown = text
        self._status(f"{text}; on the page in {page_s:.2f} s")

    def _on_width(self, change: dict[str, Any]) -> None:
        sizes = layout_sizes(change["new"])
        if sizes == self.sizes:
            return
        self.sizes = sizes
        for name, fig in self.figures.items():
            _resize(fig, sizes[name])
        traj_margins(self.fig_traj)
        self._side.layout.width = f"{sizes['side'][0]}px"
        self._unsettled = True
        self._push(*self.figures.values())
        if self._pending is not None:
            return  # the update under way sends every figure again before it says "done"
        self._await_page(f"{self._shown}; figures sized to the page ({change['new']} pixels)", time.perf_counter())

    def _write_url(self) -> None:
        view = explore.View(self.w_source.value, self.design, self.w_rank_by.value, self.w)
        self.bridge.query = view.query()

    def export(self, what: str) -> str | None:
        """The shown design's data as a download (CSV: per controller; JSON: metrics and arrays);
        returns the text (None: no design data shown)."""
        if self.land is None:
            self._status(f"design {self.design}: no outcome arrays to export", "done")
            return None
        ex, land = self.ex, self.land
        name = f"morphlearn_{ex.res.model}_{self.source.bundle.name}_design{self.design}"
        if what == "csv":
            text, mime = explore.export_csv(land), "text/csv"
        else:
            text, mime = explore.export_json(ex, land, self.w, self.w_source.value), "application/json"
        self.bridge.download(f"{name}.{what}", text, mime)
        return text

    # -- events ------------------------------------------------------------------------------------
    def _on_dropdown(self, _change: dict[str, Any]) -> None:
        if self._quiet or self.w_l1.value is None or self.w_l2.value is None:
            return
        d = self.ex.design_of(self.w_l1.value, self.w_l2.value)
        if d != self.design:  # not the page echoing the value the kernel set
            self.select(d)

    def _on_goto(self, change: dict[str, Any]) -> None:
        what = change["new"]
        if what == "-":
            return
        ex = self.ex
        d = ex.design_of(*gridmod.canonical_design()) if what == "canonical" else ex.best(what.split()[1])
        self.w_best.value = "-"
        self.select(d)

    def _fill_top(self) -> None:
        ex = self.ex
        t = ex.top(self.w_rank_by.value, TOP_N, self.w_search.value)
        opts = [
            (
                _top_row(
                    str(r.rank),
                    str(r.design),
                    f"{r.l1x:g},{r.l1y:g}",
                    f"{r.l2x:g},{r.l2y:g}",
                    f"{r.M_L:.4f}",
                    f"{r.M_CF:.3f}",
                ),
                int(r.design),
            )
            for r in t.itertuples()
        ]
        self._quiet = True
        try:
            self.w_top.options = opts or [("no design matches", -1)]
            self.w_top.value = self.design if any(v == self.design for _, v in opts) else None
        finally:
            self._quiet = False

    def _on_top(self, change: dict[str, Any]) -> None:
        if self._quiet or change["new"] is None or change["new"] < 0 or change["new"] == self.design:
            return
        self.select(change["new"])

    def _on_rank_by(self, _change: dict[str, Any]) -> None:
        self._fill_top()
        self._write_url()

    def _on_map_click(self, event: Any) -> None:
        # the two maps, not their colour bars (whose data coordinates are metric values)
        if event.inaxes is None or event.inaxes not in self._marks_axes() or event.xdata is None:
            return
        d = self.ex.design_at(event.xdata, event.ydata)
        if d is not None:
            self.select(d)

    def _on_map_hover(self, event: Any) -> None:
        if event.inaxes is None or event.inaxes not in self._marks_axes() or event.xdata is None:
            return
        d = self.ex.design_at(event.xdata, event.ydata)
        if d is None or d == self._hovered:
            return
        self._hovered = d
        self.w_hover.value = f"<span data-hover='{d}'>{html.escape(self.ex.hover(d))}</span>"

    def _marks_axes(self) -> list[Any]:
        return [m.axes for m in self._marks]

    def _on_matrix_click(self, event: Any) -> None:
        axes = self.fig_design.axes
        if self.land is None or len(axes) < 3 or event.inaxes is not axes[2] or event.xdata is None:
            return
        self.select_controller(event.xdata, event.ydata)

    # -- layout ------------------------------------------------------------------------------------
    def widget(self) -> W.Widget:
        canvas = _canvas_widget
        self._engines_box.children = [self.w_engines, canvas(self.fig_engines)]
        wrap = W.Layout(flex_flow="row wrap", align_items="flex-start", width="100%")
        head = W.HTML(
            "Hover a map cell for its design, click it (or a row of the top-N table) to select it; "
            "click a controller in the matrix for its trajectories. The address bar holds the view: "
            "copy it to share it."
        )
        style = W.HTML(_CSS)
        controls = W.HBox(
            [self.w_source, self.w_best, self.w_l1, self.w_l2, self.w_weights, self.w_export_csv, self.w_export_json],
            layout=wrap,
        )
        maps = W.VBox([canvas(self.fig_maps), self.w_hover], layout=W.Layout(margin="0 16px 0 0"))
        lower = W.HBox([canvas(self.fig_design), canvas(self.fig_traj)], layout=wrap)
        parts = [style, self.bridge, head, controls, W.HBox([maps, self._side], layout=wrap), lower, self._engines_box]
        return W.VBox(parts, layout=W.Layout(width="100%"))


#: The top-N table in a fixed-width font (its columns line up); nothing wider than the page.
_CSS = """<style>
.ml-top select { font-family: monospace; font-size: 11.5px; }
.ml-status, .ml-hover { font-size: 13px; }
.jupyter-matplotlib-figure { max-width: 100%; }
</style>"""


#: The top-N table's font: fixed width, so that its header and rows line up.
_MONO = "font-family: monospace; font-size: 11.5px; margin: 4px 0 0 5px; line-height: 1.2"


def _top_row(rank: str, design: str, l1: str, l2: str, ml: str, mcf: str) -> str:
    """A row of the top-N table (fixed-width columns: it fits the side bar)."""
    return f"{rank:>4} {design:>5} {l1:>13} {l2:>13} {ml:>6} {mcf:>5}"


def engines_html(rows: list[dict[str, Any]], bundle: str) -> str:
    """The design in every model of the bundle: engine, M_L and M_CF with ranks, or not simulated."""
    body = ""
    for r in rows:
        if r["M_L"] is None:
            cells = f"<td colspan=2>not simulated ({r['designs']} designs are)</td>"
        else:
            cells = "".join(
                f"<td>{r[by]:.4g} (rank {r['rank'][by]} of {r['designs']})</td>" for by in explore.METRIC_NAMES
            )
        body += f"<tr><th style='text-align:left;padding-right:10px'>{html.escape(r['engine'])}</th>{cells}</tr>"
    return (
        f"<b>The design in each model of the {html.escape(bundle)} bundle</b>"
        "<table class='ml-engines' style='font-size:12px'><tr><th></th><th>M_L</th><th>M_CF</th></tr>"
        f"{body}</table>"
    )


def _canvas_widget(fig: Figure) -> W.Widget:
    """The figure's ipympl canvas, or (another backend) its static image in an Output."""
    c = fig.canvas
    if isinstance(c, W.DOMWidget):
        return c
    out = W.Output()
    with out:
        display(fig)
    return out


def _inches(size: tuple[int, int]) -> tuple[float, float]:
    return size[0] / 100, size[1] / 100  # the figures' dpi is matplotlib's default, 100


def _resize(fig: Figure, size: tuple[int, int]) -> None:
    """Resize a figure to ``size`` CSS pixels (ipympl: its canvas on the page follows)."""
    dpi = getattr(fig, "_original_dpi", fig.dpi)  # the dpi before the page's device pixel ratio
    fig.set_size_inches(size[0] / dpi, size[1] / dpi, forward=True)


def _push(fig: Figure) -> bool:
    """Show a figure's new drawing now. ipympl: draw() sends the image at once, while the callback
    goes on (to the trajectories); draw_idle() asks the page for a round trip that the busy kernel
    answers only when the callback ends. Before the page has shown the canvas (``syncing_data_url``)
    it must be draw_idle(): an image sent then reaches the page as a broken data URL (ipympl 0.10).
    Always a full image, not a diff against the last one sent: a diff applied to a page whose image
    is not that one (a draw the page never showed) leaves stale pixels. Returns whether the image
    was sent at once (False: by draw_idle, after the page asks)."""
    c = fig.canvas
    if getattr(c, "syncing_data_url", False):
        c.draw_idle()
        return False
    c._force_full = True
    c.draw()
    return True


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
