"""The column report's 3D view in a real headless Chromium (Chrome DevTools Protocol).

The shipped truck column is run by the ``sso`` command; its report.html is opened from
the file system with the page's console, exceptions and network requests recorded.
A scripted drag and wheel go through Chromium's own input pipeline
(``Input.dispatchMouseEvent``), so the page sees trusted pointer events as from a mouse.
Skipped, with the reason, where no Chromium or no websocket-client is installed.
"""

from __future__ import annotations

import base64
import math
import subprocess
import sys
from pathlib import Path

import pytest
from headless_browser import Browser, chromium_path

ROOT = Path(__file__).resolve().parents[2]
TRUCK = ROOT / "cases" / "column_truck_three_joints.toml"
DRAG_PX = (120.0, 40.0)
TURN_PER_PX_DEG = math.degrees(0.01)  # the renderer turns 0.01 rad per pixel

pytest.importorskip("websocket", reason="websocket-client is not installed (pip install "
                    "'shaft-series-optimisation[test]')")
CHROMIUM = chromium_path()
pytestmark = pytest.mark.skipif(CHROMIUM is None, reason="no Chromium on PATH (Debian: apt-get "
                                "install chromium); the browser test needs a real browser")


@pytest.fixture(scope="module")
def truck_report(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("view")
    completed = subprocess.run([sys.executable, "-m", "sso._cli", "run", str(TRUCK), "--out",
                                str(folder), "--no-plots"], cwd=folder, capture_output=True,
                               text=True, timeout=600)
    assert completed.returncode == 0, completed.stderr
    return folder / "column_truck_three_joints" / "report.html"


@pytest.fixture(scope="module")
def page(truck_report):
    assert CHROMIUM is not None
    with Browser(CHROMIUM) as browser:
        for domain in ("Page", "Runtime", "Log", "Network"):
            browser.page(f"{domain}.enable")
        browser.page("Page.navigate", {"url": truck_report.as_uri()})
        browser.wait_for_event("Page.loadEventFired")
        yield browser


def view_state(browser) -> dict:
    return browser.evaluate(
        "(() => { const c = document.querySelector('.view3d canvas'); c.scrollIntoView(); "
        "const r = c.getBoundingClientRect(); return {yaw: +c.dataset.yawDeg, "
        "pitch: +c.dataset.pitchDeg, zoom: +c.dataset.zoom, left: r.left + c.clientLeft, "
        "top: r.top + c.clientTop, width: c.clientWidth, height: c.clientHeight, "
        "canvasWidth: c.width, canvasHeight: c.height, "
        "pixels: c.toDataURL('image/png')}; })()")


def mouse(browser, kind: str, x: float, y: float, **extra) -> None:
    browser.page("Input.dispatchMouseEvent", {"type": kind, "x": x, "y": y, **extra})


def test_the_report_loads_with_no_console_error_and_no_other_host(page):
    errors = [event for event in page.events
              if event.get("method") == "Runtime.exceptionThrown"
              or event.get("method") == "Runtime.consoleAPICalled"
              and event["params"]["type"] in ("error", "assert")
              or event.get("method") == "Log.entryAdded"
              and event["params"]["entry"]["level"] == "error"]
    assert errors == []
    requests = [event["params"]["request"]["url"] for event in page.events
                if event.get("method") == "Network.requestWillBeSent"]
    assert requests and requests[0].startswith("file://")
    assert all(url.startswith(("file://", "data:")) for url in requests), requests
    assert page.evaluate("document.querySelectorAll('.view3d canvas').length") == 1


def test_the_view_draws_the_truck_column(page, truck_report):
    scene = page.evaluate("JSON.parse(document.querySelector('.view3d script').textContent)")
    names = [item["name"] for item in scene["items"]]
    assert sum(name.startswith("bend plane of joint") for name in names) == 3
    assert sum(name.startswith("box of joint") for name in names) == 3 * 12
    assert names[:4] == ["input shaft (P0 to P1), 450.0 mm", "intermediate shaft 1 (P1 to P2), "
                         "379.9 mm", "intermediate shaft 2 (P2 to P3), 520.1 mm",
                         "output shaft (P3 to P4), 149.9 mm"]
    assert "the column with its joints moved within their boxes" in names
    # The canvas is not blank: the PNG of a drawn column is far larger than an empty one.
    assert len(base64.b64decode(view_state(page)["pixels"].split(",")[1])) > 20_000


def test_a_scripted_drag_turns_the_view_and_the_wheel_zooms(page):
    before = view_state(page)
    x = before["left"] + before["width"] / 2
    y = before["top"] + before["height"] / 2
    mouse(page, "mouseMoved", x, y)
    mouse(page, "mousePressed", x, y, button="left", buttons=1, clickCount=1)
    for step in range(1, 5):
        mouse(page, "mouseMoved", x + DRAG_PX[0] * step / 4, y + DRAG_PX[1] * step / 4,
              button="left", buttons=1)
    mouse(page, "mouseReleased", x + DRAG_PX[0], y + DRAG_PX[1], button="left", buttons=0,
          clickCount=1)
    after = view_state(page)
    # CSS pixels are canvas pixels at this window size (the canvas is 960 wide).
    assert after["width"] == before["canvasWidth"]
    assert after["height"] == before["canvasHeight"]
    assert after["yaw"] - before["yaw"] == pytest.approx(DRAG_PX[0] * TURN_PER_PX_DEG, abs=2e-3)
    assert after["pitch"] - before["pitch"] == pytest.approx(DRAG_PX[1] * TURN_PER_PX_DEG,
                                                            abs=2e-3)
    assert after["pixels"] != before["pixels"]
    mouse(page, "mouseWheel", x, y, deltaX=0, deltaY=-300)
    assert view_state(page)["zoom"] == pytest.approx(math.exp(0.3), rel=1e-3)
    mouse(page, "mouseMoved", x, y)
    page.page("Input.dispatchMouseEvent", {"type": "mousePressed", "x": x, "y": y,
                                           "button": "left", "clickCount": 2})
    page.page("Input.dispatchMouseEvent", {"type": "mouseReleased", "x": x, "y": y,
                                           "button": "left", "clickCount": 2})
    reset = view_state(page)
    assert (reset["yaw"], reset["pitch"], reset["zoom"]) == (before["yaw"], before["pitch"], 1.0)


def test_hovering_a_joint_names_it(page):
    state = view_state(page)
    scene = page.evaluate("JSON.parse(document.querySelector('.view3d script').textContent)")
    joint = next(item for item in scene["items"] if item.get("label") == "joint 2")
    x, y = project(scene, joint["at"], state)
    mouse(page, "mouseMoved", state["left"] + x, state["top"] + y)
    tip = page.evaluate("(() => { const t = document.querySelector('.view3d .tip'); "
                        "return t.hidden ? null : t.textContent; })()")
    assert tip == joint["name"]
    assert tip.startswith("joint 2 (P2): operating angle 13.30 deg")


def project(scene: dict, point: list[float], state: dict) -> tuple[float, float]:
    """Canvas pixel of a model point: the view's orthographic projection written again
    from its definition (turn about z by yaw, then tilt by pitch; fit 2.3 radii)."""
    yaw, pitch = math.radians(state["yaw"]), math.radians(state["pitch"])
    x, y, z = (point[axis] - scene["centre"][axis] for axis in range(3))
    across = math.cos(yaw) * x - math.sin(yaw) * y
    along = math.sin(yaw) * x + math.cos(yaw) * y
    scale = state["zoom"] * min(state["canvasWidth"], state["canvasHeight"]) / (
        2.3 * scene["radius"])
    up = math.cos(pitch) * z - math.sin(pitch) * along
    return state["canvasWidth"] / 2 + scale * across, state["canvasHeight"] / 2 - scale * up

