"""The explorer as a person uses it: Voila serves notebooks/explore.ipynb on localhost and Debian's
chromium (headless, driven by Playwright) loads it, picks a design with the sensor dropdowns, waits
until the overlap matrix on the page has changed, clicks a map cell and a controller, and saves a
screenshot whose path the test prints with the click-to-landscape time.

Skipped when chromium is not installed (``apt-get install -y chromium`` as root), unless
MORPHLEARN_REQUIRE_BROWSER=1 (set by .ci/run, which installs it): then a missing browser fails.
"""

from __future__ import annotations

import os
import shutil
import socket
import subprocess
import sys
import time
from pathlib import Path

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
#: The figures' image canvases (ipympl draws each figure on two stacked canvases: image, rubberband),
#: in page order: maps, design (overlap matrix), trajectories.
CANVASES = "Array.from(document.querySelectorAll('.jupyter-matplotlib-canvas-div canvas'))"


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
def voila(tmp_path: Path):
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


def test_explorer_in_a_browser(voila: tuple[str, Path], tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    from playwright.sync_api import sync_playwright

    url, log = voila
    shot = tmp_path / "explorer.png"
    expected = gridmod.DesignGrid(9).index_of(PICK_L1, PICK_L2)  # the paper bundle: 9 positions per axis
    t_start = time.perf_counter()
    with sync_playwright() as p:
        ctx = p.chromium.launch_persistent_context(
            str(tmp_path / "profile"),
            executable_path=CHROMIUM,
            headless=True,
            args=FLAGS,
            viewport={"width": 1700, "height": 1250},
        )
        try:
            page = ctx.new_page()
            page.goto(url, timeout=120_000)
            status = page.locator(".ml-status [data-design]")
            done = page.locator(".ml-status [data-stage='done']")
            try:
                status.wait_for(timeout=180_000)  # the kernel starts, reads the bundle, draws
            except Exception:
                raise AssertionError(f"the app did not render; voila log:\n{log.read_text()[-3000:]}") from None
            loaded = time.perf_counter() - t_start
            done.wait_for(timeout=120_000)
            # Each figure's canvas is sized and drawn after a round trip with the kernel (ipympl).
            page.wait_for_function(
                f"() => {{ const c = {CANVASES}; return c.length === 6 && "
                "c.every(x => x.width > 0 && x.height > 0); }",
                timeout=120_000,
            )
            loaded = time.perf_counter() - t_start
            first = status.get_attribute("data-design")

            def select(label: str, option: tuple[float, float]) -> None:
                box = page.locator(".widget-dropdown", has_text=label).locator("select")
                box.select_option(label=f"({option[0]:g}, {option[1]:g})")

            def matrix() -> str:  # the overlap matrix figure's pixels, as the page shows them
                return page.evaluate(f"{CANVASES}[2].toDataURL()")

            def click(figure: int, fx: float, fy: float) -> None:
                box = page.evaluate(
                    f"(() => {{ const r = {CANVASES}[{2 * figure}].getBoundingClientRect(); "
                    "return [r.x, r.y, r.width, r.height]; })()"
                )
                page.mouse.click(box[0] + fx * box[2], box[1] + fy * box[3])

            select("sensor 2", PICK_L2)  # one design on the way (sensor 1 still the first design's)
            page.wait_for_function(
                "d => document.querySelector('.ml-status [data-design]')?.getAttribute('data-design') !== d",
                arg=first,
                timeout=120_000,
            )
            middle = status.get_attribute("data-design")
            done.wait_for(timeout=120_000)  # its trajectories drawn too: the kernel is idle
            page.wait_for_timeout(500)
            before = matrix()
            # The click that is timed: sensor 1 -> the landscape of the design picked.
            t0 = time.perf_counter()
            select("sensor 1", PICK_L1)
            page.locator(f".ml-status [data-design='{expected}']").wait_for(timeout=120_000)
            t_status = time.perf_counter() - t0
            while matrix() == before:  # the image on the page, not just the status line
                assert time.perf_counter() - t0 < 60, "the overlap matrix on the page did not change"
                page.wait_for_timeout(20)
            t_landscape = time.perf_counter() - t0
            done.wait_for(timeout=120_000)
            info = page.locator(".ml-info").inner_text()
            assert f"{expected}: l1 (-0.125, 0), l2 (-0.25, -0.25)" in info, info
            assert "computed live" in info and "41 x 41" in info, info
            server = status.inner_text()  # the kernel's own timing of the update
            # A click on the M_L map picks another design.
            click(0, 0.3, 0.75)
            page.wait_for_function(
                f"() => document.querySelector('.ml-status [data-design]')"
                f"?.getAttribute('data-design') !== '{expected}'",
                timeout=120_000,
            )
            clicked = status.get_attribute("data-design")
            done.wait_for(timeout=120_000)
            # "go to: best M_L": a design the bundle holds (121 x 121, read, not computed).
            page.wait_for_timeout(300)
            before = matrix()
            t0 = time.perf_counter()
            page.locator(".widget-dropdown", has_text="go to").locator("select").select_option(label="best M_L")
            page.wait_for_function(
                f"() => document.querySelector('.ml-status [data-design]')"
                f"?.getAttribute('data-design') !== '{clicked}'",
                timeout=120_000,
            )
            while matrix() == before:
                assert time.perf_counter() - t0 < 60, "the overlap matrix on the page did not change"
                page.wait_for_timeout(20)
            t_bundle = time.perf_counter() - t0
            best = status.get_attribute("data-design")
            done.wait_for(timeout=120_000)
            assert "121 x 121 weights, the bundle's arrays" in page.locator(".ml-info").inner_text()
            # A click in the matrix's generalist corner (w1 < 0 < w2) picks that controller.
            w_before = status.get_attribute("data-w")
            click(1, 0.6, 0.25)
            page.wait_for_function(
                "w => document.querySelector('.ml-status [data-w]')?.getAttribute('data-w') !== w",
                arg=w_before,
                timeout=120_000,
            )
            w_after = status.get_attribute("data-w")
            done.wait_for(timeout=120_000)
            page.wait_for_timeout(1000)  # let the last canvas images arrive before the screenshot
            page.screenshot(path=str(shot), full_page=True)
        finally:
            ctx.close()
    assert middle not in (first, str(expected)), (first, middle, expected)
    assert clicked != str(expected)
    total = time.perf_counter() - t_start
    with capsys.disabled():
        print(
            f"\nexplorer screenshot: {shot}\n  page loaded and drawn in {loaded:.1f} s; click to status "
            f"{t_status:.2f} s, click to updated landscape on the page {t_landscape:.2f} s (design {expected}, "
            f"live 41 x 41; kernel: {server!r}); map click -> design {clicked}; go to best M_L -> design {best}, "
            f"click to landscape {t_bundle:.2f} s (the bundle's 121 x 121); matrix click -> controller {w_after}; "
            f"browser session {total:.1f} s"
        )
    if os.environ.get("MORPHLEARN_SCREENSHOT"):  # keep a copy where asked
        shutil.copy(shot, os.environ["MORPHLEARN_SCREENSHOT"])
