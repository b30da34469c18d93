"""The explorer as a person uses it: Voila serves notebooks/explore.ipynb on localhost and Debian's
chromium (headless, driven by Playwright) loads it at a laptop's 1366 x 768 and at 1920 x 1080.

At 1366 x 768: nothing wider than the page (every figure, colour bars included, inside the
viewport), hover over a map cell names the design, a design picked with the sensor dropdowns, from
the top-N table and by a map click, each timed from the click to the overlap matrix's pixels
changing on the page and to the status saying "done" (which must come after the pixels), a
controller clicked, the URL following the view, the shown design exported as CSV and JSON.
At 1920 x 1080: a shared URL reopens its view, the bundle's engines side by side, the design kept
when the results source changes. Screenshots (viewport and whole page) are saved and their paths
printed with the times; ``MORPHLEARN_SCREENSHOT_DIR`` keeps them there too.

Skipped when chromium is not installed (``apt-get install -y chromium`` as root), unless
MORPHLEARN_REQUIRE_BROWSER=1 (set by .ci/run, which installs it): then a missing browser fails.
"""

from __future__ import annotations

import json
import os
import shutil
import socket
import subprocess
import sys
import time
import urllib.parse
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from morphlearn import grid as gridmod

ROOT = Path(__file__).resolve().parents[1]
CHROMIUM = "/usr/bin/chromium"
REQUIRE = os.environ.get("MORPHLEARN_REQUIRE_BROWSER") == "1"
FLAGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]
#: The design the test picks: not in the paper bundle's arrays, so its matrix is computed live
#: (41 x 41), and one of the quick ones (0.4 s; a design with many step-capped trajectories takes
#: up to 10 times longer: docs/explorer.md).
PICK_L1, PICK_L2 = (-0.125, 0.0), (-0.25, -0.25)
GRID = gridmod.DesignGrid(9)  # the paper bundle: 9 positions per axis
#: A design every model of the paper bundle holds (theory, pybullet, MuJoCo): the engines side by side.
SHARED_DESIGN = 720
#: The figures' image canvases (ipympl draws each figure on two stacked canvases: image, rubberband),
#: in page order: maps, design (overlap matrix), trajectories, engines.
CANVASES = "Array.from(document.querySelectorAll('.jupyter-matplotlib-canvas-div canvas'))"
#: Every widget and canvas whose box reaches past the viewport's right or left edge (what a person
#: would have to scroll sideways for, or would not see at all), and the page's scroll width.
OVERFLOW = """() => {
  const vw = document.documentElement.clientWidth;
  const bad = [];
  let n = 0;
  for (const e of document.querySelectorAll('.jupyter-widgets, .jupyter-matplotlib-figure, canvas')) {
    const r = e.getBoundingClientRect();
    if (r.width === 0 || r.height === 0) continue;
    n += 1;
    if (r.left < -0.5 || r.right > vw + 0.5)
      bad.push(`${e.tagName}.${e.className}: ${Math.round(r.left)}..${Math.round(r.right)}`);
  }
  const cells = document.querySelector('#rendered_cells') || document.documentElement;
  return {vw, n, bad, scroll: Math.max(document.documentElement.scrollWidth, cells.scrollWidth),
          figures: Array.from(document.querySelectorAll('.jupyter-matplotlib-canvas-div canvas'))
            .filter((c, i) => i % 2 === 0).map(c => Math.round(c.getBoundingClientRect().width))};
}"""


#: Per figure (maps, design, trajectories, engines): whether its canvas on the page holds a drawing,
#: not a blank or unsized canvas (a sample of its pixels is not all one colour).
PAINTED = f"""() => {CANVASES}.filter((c, i) => i % 2 === 0).map(c => {{
  if (!c.width || !c.height) return false;
  const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
  for (let k = 4; k < d.length; k += 4 * 97)
    if (d[k] !== d[0] || d[k + 1] !== d[1] || d[k + 2] !== d[2]) return true;
  return false;
}})"""


def _need_browser() -> None:
    why = None
    if not Path(CHROMIUM).is_file():
        why = f"{CHROMIUM} not installed (apt-get install -y chromium)"
    else:
        try:
            import playwright.sync_api  # noqa: F401
        except ImportError as e:
            why = f"playwright not importable ({e}); bash tools/setup.sh installs it"
    if why:
        if REQUIRE:
            pytest.fail(f"MORPHLEARN_REQUIRE_BROWSER=1 but {why}", pytrace=False)
        pytest.skip(why)


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _wait_port(port: int, proc: subprocess.Popen, timeout: float) -> None:
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if proc.poll() is not None:
            raise AssertionError(f"voila exited with {proc.returncode}")
        with socket.socket() as s:
            if s.connect_ex(("127.0.0.1", port)) == 0:
                return
        time.sleep(0.2)
    raise AssertionError(f"voila did not listen on port {port} within {timeout:.0f} s")


@pytest.fixture
def voila(tmp_path: Path) -> Iterator[tuple[str, Path]]:
    _need_browser()
    port = _free_port()
    log = (tmp_path / "voila.log").open("w")
    env = {k: v for k, v in os.environ.items() if k != "MPLBACKEND"}
    proc = subprocess.Popen(
        [
            str(Path(sys.executable).with_name("voila")),
            "notebooks/explore.ipynb",
            "--no-browser",
            f"--port={port}",
            "--Voila.ip=127.0.0.1",
            "--show_tracebacks=True",
        ],
        cwd=ROOT,
        stdout=log,
        stderr=subprocess.STDOUT,
        env=env,
    )
    try:
        _wait_port(port, proc, 60)
        yield f"http://127.0.0.1:{port}/", tmp_path / "voila.log"
    finally:
        proc.terminate()
        try:
            proc.wait(10)
        except subprocess.TimeoutExpired:
            proc.kill()
        log.close()


class Page:
    """The explorer's page: what the tests read and click."""

    def __init__(self, page: Any, log: Path) -> None:
        self.page = page
        self.log = log
        self.status = page.locator(".ml-status [data-design]")

    def open(self, url: str) -> float:
        """Load and wait until the status says done (the kernel started, the bundle checked, every
        figure drawn on the page); returns the seconds."""
        t0 = time.perf_counter()
        self.page.goto(url, timeout=120_000)
        try:
            self.done(180)
        except Exception:
            raise AssertionError(f"the app did not render; voila log:\n{self.log.read_text()[-3000:]}") from None
        t = time.perf_counter() - t0
        painted = self.page.evaluate(PAINTED)  # at once: "done" must mean drawn
        assert len(painted) == 4 and all(painted), f"status done, figures painted: {painted}"
        return t

    def done(self, timeout_s: float = 120) -> None:
        self.page.locator(".ml-status [data-stage='done']").wait_for(timeout=timeout_s * 1000)

    def design(self) -> str | None:
        return self.status.get_attribute("data-design")

    def matrix(self) -> str:  # the overlap matrix figure's pixels, as the page shows them
        return self.page.evaluate(f"{CANVASES}[2].toDataURL()")

    def figures(self) -> list[str]:  # every figure's pixels: maps, design, trajectories, engines
        return self.page.evaluate(f"{CANVASES}.filter((c, i) => i % 2 === 0).map(c => c.toDataURL())")

    def box(self, figure: int) -> list[float]:
        return self.page.evaluate(
            f"(() => {{ const r = {CANVASES}[{2 * figure}].getBoundingClientRect(); "
            "return [r.x, r.y, r.width, r.height]; })()"
        )

    def click(self, figure: int, fx: float, fy: float) -> None:
        # on a laptop's screen the lower figures start below the fold: the mouse needs them shown
        self.page.evaluate(f"{CANVASES}[{2 * figure}].scrollIntoView({{block: 'center'}})")
        self.page.wait_for_timeout(200)
        b = self.box(figure)
        self.page.mouse.click(b[0] + fx * b[2], b[1] + fy * b[3])

    def select(self, label: str, option: str) -> None:
        self.page.locator(".widget-dropdown", has_text=label).locator("select").select_option(label=option)

    def timed(self, action: Any, want: str | None = None) -> dict[str, float | str]:
        """Do ``action`` (a click) on an idle page; the seconds to the overlap matrix's pixels
        changing on the page and to the status saying done, which must not come first: when the
        status says done the new matrix must be on the page."""
        self.done()
        self.page.wait_for_timeout(300)
        before, was = self.matrix(), self.design()
        figures = self.figures()
        t0 = time.perf_counter()
        action()
        changed = None
        while True:
            # one read of the page: the status's stage and design, then the matrix's pixels (read
            # apart, a "done" of the design before could pass for the new one's)
            stage, design, pixels = self.page.evaluate(
                "() => { const s = document.querySelector('.ml-status [data-stage]'); "
                f"return [s?.dataset.stage, s?.dataset.design, {CANVASES}[2].toDataURL()]; }}"
            )
            if changed is None and pixels != before:
                changed = time.perf_counter() - t0
            if stage == "done" and design != was:
                t_done = time.perf_counter() - t0
                assert changed is not None, f"status done after {t_done:.2f} s, the matrix on the page unchanged"
                # and every figure is the new design's: maps (the marker), matrix, trajectories, engines
                same = [k for k, (a, b) in enumerate(zip(figures, self.figures(), strict=True)) if a == b]
                assert not same, f"status done after {t_done:.2f} s, figures {same} unchanged on the page"
                break
            assert time.perf_counter() - t0 < 120, "no update within 120 s"
            self.page.wait_for_timeout(15)
        if want is not None:
            assert design == want, (design, want)
        return {"design": design, "pixels_s": changed, "done_s": t_done}

    def overflow(self) -> dict[str, Any]:
        return self.page.evaluate(OVERFLOW)

    def shots(self, out: Path, name: str) -> list[Path]:
        """The viewport as a person sees it, and the whole page (Voila scrolls #rendered_cells, not
        the document: the viewport is made as tall as the content for that shot, then restored)."""
        view = out / f"explorer_{name}.png"
        self.page.screenshot(path=str(view))
        size = self.page.viewport_size
        tall = self.page.evaluate(
            "(() => { const c = document.querySelector('#rendered_cells'); "
            "return c ? c.scrollHeight + c.getBoundingClientRect().top + 20 : document.body.scrollHeight; })()"
        )
        self.page.set_viewport_size({"width": size["width"], "height": int(tall)})
        self.page.wait_for_timeout(800)
        full = out / f"explorer_{name}_page.png"
        self.page.screenshot(path=str(full))
        self.page.set_viewport_size(size)
        self.page.wait_for_timeout(300)
        return [view, full]


def _browser(p: Any, tmp_path: Path, width: int, height: int) -> Any:
    return p.chromium.launch_persistent_context(
        str(tmp_path / "profile"),
        executable_path=CHROMIUM,
        headless=True,
        args=FLAGS,
        viewport={"width": width, "height": height},
        accept_downloads=True,
    )


def _assert_fits(ui: Page, where: str) -> dict[str, Any]:
    fit = ui.overflow()
    assert fit["n"] > 10, fit  # the widgets were found
    assert not fit["bad"], f"{where}: cut off at {fit['vw']} px: {fit['bad']}"
    assert fit["scroll"] <= fit["vw"], f"{where}: the page scrolls sideways: {fit}"
    return fit


def _keep(paths: list[Path]) -> None:
    keep = os.environ.get("MORPHLEARN_SCREENSHOT_DIR")
    if keep:
        Path(keep).mkdir(parents=True, exist_ok=True)
        for p in paths:
            shutil.copy(p, Path(keep) / p.name)


def test_explorer_on_a_laptop_screen(voila: tuple[str, Path], tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    from playwright.sync_api import sync_playwright

    url, log = voila
    expected = GRID.index_of(PICK_L1, PICK_L2)
    with sync_playwright() as p:
        ctx = _browser(p, tmp_path, 1366, 768)
        try:
            ui = Page(ctx.new_page(), log)
            loaded = ui.open(url)
            fit = _assert_fits(ui, "1366 x 768 after loading")
            # the maps are the width the page leaves them, not their fixed 1050 pixels of before
            assert fit["figures"][0] < 1366 - 380, fit
            first = ui.design()
            # hover: the design under the mouse, its sensors and metrics
            b = ui.box(0)
            t0 = time.perf_counter()
            ui.page.mouse.move(b[0] + 0.3 * b[2], b[1] + 0.5 * b[3])
            ui.page.locator(".ml-hover [data-hover]").wait_for(timeout=30_000)
            t_hover = time.perf_counter() - t0
            hover = ui.page.locator(".ml-hover").inner_text()
            hovered = int(ui.page.locator(".ml-hover [data-hover]").get_attribute("data-hover"))
            x1, y1, x2, y2 = (float(v) for v in GRID.coords(hovered))
            assert f"design {hovered}: l1 ({x1:g}, {y1:g}), l2 ({x2:g}, {y2:g}): M_L " in hover, hover
            assert "M_CF" in hover and "rank" in hover and "(, )" not in hover, hover
            # one design on the way (sensor 1 still the first design's), then the timed pick
            ui.timed(lambda: ui.select("sensor 2", f"({PICK_L2[0]:g}, {PICK_L2[1]:g})"))
            live = ui.timed(lambda: ui.select("sensor 1", f"({PICK_L1[0]:g}, {PICK_L1[1]:g})"), str(expected))
            info = ui.page.locator(".ml-info").inner_text()
            assert f"{expected}: l1 (-0.125, 0), l2 (-0.25, -0.25)" in info, info
            assert "computed live" in info and "41 x 41" in info, info
            server = ui.status.inner_text()  # the kernel's own timing of the update
            query = urllib.parse.parse_qs(urllib.parse.urlparse(ui.page.url).query)
            assert query["design"] == [str(expected)] and query["source"] == ["theory (paper)"], ui.page.url
            assert query["metric"] == ["M_L"], ui.page.url
            # the top-N table: search, then pick its second row
            ui.page.locator(".ml-search input").fill("l1(0.5,0.5)")
            ui.page.wait_for_function(
                "() => Array.from(document.querySelectorAll('.ml-top option')).every(o => o.text.includes('0.5,0.5'))"
                " && document.querySelectorAll('.ml-top option').length > 1",
                timeout=30_000,
            )
            rows = ui.page.locator(".ml-top option").all_inner_texts()
            pick = rows[1].split()[1]
            top = ui.timed(lambda: ui.page.locator(".ml-top select").select_option(index=1), pick)
            # a click on the M_L map
            clicked = ui.timed(lambda: ui.click(0, 0.3, 0.75))
            assert clicked["design"] not in (pick, first), clicked
            # go to best M_L: a design the bundle holds, read, not computed
            held = ui.timed(lambda: ui.select("go to", "best M_L"))
            assert "121 x 121 weights, the bundle's arrays" in ui.page.locator(".ml-info").inner_text()
            # a click in the matrix's generalist corner (w1 < 0 < w2) picks that controller
            w_before = ui.status.get_attribute("data-w")
            ui.click(1, 0.6, 0.25)
            ui.page.wait_for_function(
                "w => document.querySelector('.ml-status [data-w]')?.getAttribute('data-w') !== w",
                arg=w_before,
                timeout=120_000,
            )
            ui.done()
            w_after = ui.status.get_attribute("data-w")
            w_url = urllib.parse.parse_qs(urllib.parse.urlparse(ui.page.url).query)["w"][0]
            assert [float(v) for v in w_url.split(",")] == pytest.approx(
                [float(v) for v in w_after.strip("()").split(",")]
            )
            # export: the shown design's data as downloads
            with ui.page.expect_download(timeout=60_000) as dl:
                ui.page.locator(".ml-export", has_text="CSV").click()
            csv_lines = Path(dl.value.path()).read_text().splitlines()
            with ui.page.expect_download(timeout=60_000) as dl:
                ui.page.locator(".ml-export", has_text="JSON").click()
            exported = json.loads(Path(dl.value.path()).read_text())
            assert csv_lines[0].startswith("design,w1,w2,overlap,success_45")
            assert len(csv_lines) == 1 + 121 * 121 and csv_lines[1].startswith(f"{held['design']},")
            assert exported["design"] == int(held["design"]) and exported["results"] == "theory (paper)"
            assert len(exported["overlap"]) == 121 and exported["table"]["M_L"] > 0
            ui.page.wait_for_timeout(500)
            _assert_fits(ui, "1366 x 768 after the clicks")
            shots = ui.shots(tmp_path, "1366x768")
        finally:
            ctx.close()
    _keep(shots)
    with capsys.disabled():
        print(
            f"\nexplorer at 1366 x 768: {', '.join(map(str, shots))}\n  page loaded and drawn in {loaded:.1f} s; "
            f"figure widths {fit['figures']} px in {fit['vw']} px; hover in {t_hover:.2f} s: {hover!r}\n"
            f"  click to new matrix on the page / to status done: sensor dropdown (design {expected}, live 41 x 41) "
            f"{live['pixels_s']:.2f} / {live['done_s']:.2f} s (kernel: {server!r}); top-N row (design {pick}) "
            f"{top['pixels_s']:.2f} / {top['done_s']:.2f} s; map click (design "
            f"{clicked['design']}) {clicked['pixels_s']:.2f} / {clicked['done_s']:.2f} s; go to best M_L (design "
            f"{held['design']}) {held['pixels_s']:.2f} / {held['done_s']:.2f} s; controller {w_after}"
        )


def test_shared_url_and_engines_side_by_side(
    voila: tuple[str, Path], tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    from playwright.sync_api import sync_playwright

    url, log = voila
    view = "?" + urllib.parse.urlencode(
        {"source": "theory (paper)", "design": SHARED_DESIGN, "metric": "M_CF", "w": "0.6,0.95"}
    )
    with sync_playwright() as p:
        ctx = _browser(p, tmp_path, 1920, 1080)
        try:
            ui = Page(ctx.new_page(), log)
            loaded = ui.open(url + view)
            assert ui.design() == str(SHARED_DESIGN)
            assert ui.status.get_attribute("data-w") == "(0.6, 0.95)"
            assert "M_CF" in ui.page.locator(".widget-toggle-button.mod-active").all_inner_texts()
            fit = _assert_fits(ui, "1920 x 1080")
            assert fit["figures"][0] > 1200, fit  # a wide page: larger maps
            # the bundle's three models side by side, each with the design's metrics
            engines = ui.page.locator(".ml-engines").inner_text()
            for engine in ("theory", "pybullet", "MuJoCo"):
                assert engine in engines, engines
            assert "not simulated" not in engines, engines
            assert ui.page.evaluate(f"{CANVASES}[6].width") > 0
            shots = ui.shots(tmp_path, "1920x1080")
            # another results source: the design is kept
            ui.select("results", "MuJoCo (paper)")
            ui.page.wait_for_function(
                "() => (new URLSearchParams(location.search)).get('source') === 'MuJoCo (paper)'", timeout=120_000
            )
            ui.done()
            assert ui.design() == str(SHARED_DESIGN)
            assert f"{SHARED_DESIGN}: l1 (-0.5, 0.5), l2 (0.5, -0.5)" in ui.page.locator(".ml-info").inner_text()
            assert "MuJoCo" in ui.page.locator(".ml-engines").inner_text()
            # the window made a laptop's: the figures follow (the page reports its width, the kernel
            # resizes them and sends them again before it says done)
            ui.page.set_viewport_size({"width": 1366, "height": 768})
            t0 = time.perf_counter()
            ui.page.wait_for_function(f"() => {CANVASES}[0].getBoundingClientRect().width < 1000", timeout=60_000)
            ui.page.wait_for_function(
                "() => { const s = document.querySelector('.ml-status [data-stage]'); "
                "return s?.dataset.stage === 'done' && "
                "/figures sized to the page \\(13\\d\\d pixels\\)/.test(s.innerText); }",
                timeout=60_000,
            )
            t_resize = time.perf_counter() - t0
            assert all(ui.page.evaluate(PAINTED))
            small = _assert_fits(ui, "1920 x 1080 made 1366 x 768")
            # a link with a typo says so, and the page opens
            bad = ui.open(url + "?design=abc")
            assert bad > 0 and "URL design='abc'" in ui.page.locator(".ml-info").inner_text()
        finally:
            ctx.close()
    _keep(shots)
    with capsys.disabled():
        print(
            f"\nexplorer at 1920 x 1080: {', '.join(map(str, shots))}\n  shared view loaded and drawn in "
            f"{loaded:.1f} s; figure widths {fit['figures']} px in {fit['vw']} px; the window narrowed to 1366: "
            f"figures {small['figures']} px, done in {t_resize:.2f} s"
        )
