"""Drive ``shapegen edit`` in headless Chromium: the screenshots of docs/editor.md.

The browser tests (tests/editor/test_editor_browser.py) run the same steps and check them; run
this file to refresh the pictures in docs/images/:

    .venv/bin/python docs/editor_screenshots.py

It needs Chromium (Debian: ``apt-get install chromium``) and the ``playwright`` Python package
(installed with the test extra); playwright drives the system's browser, nothing is downloaded.
"""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

IMAGES = Path(__file__).resolve().parent / "images"
BROWSERS = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")
# Software WebGL: a headless machine has no GPU.
BROWSER_ARGS = ["--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--ignore-gpu-blocklist"]
VIEWPORT = {"width": 1280, "height": 760}


def find_browser() -> str | None:
    """The path of a Chromium-family browser, or None."""
    override = os.environ.get("SHAPEGEN_CHROMIUM")
    if override:
        return override if Path(override).is_file() else None
    for name in BROWSERS:
        found = shutil.which(name)
        if found:
            return found
    return None


class Editor:
    """``shapegen edit`` in a child process on a free port; ``url`` once it listens."""

    def __init__(self, grammar: str | Path, *args: str):
        self.stderr = ""
        command = [sys.executable, "-m", "shapegen", "edit", str(grammar), "--port", "0"]
        self.process = subprocess.Popen(
            [*command, "--no-open", *args],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        line = self.process.stdout.readline()
        if not line.startswith("shapegen edit: http://"):
            self.stop()
            raise RuntimeError(f"shapegen edit did not start: {line}{self.stderr}")
        self.url = line.split()[2]

    def stop(self) -> int:
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGINT)
        try:
            _, self.stderr = self.process.communicate(timeout=30)
        except subprocess.TimeoutExpired:
            self.process.kill()
            _, self.stderr = self.process.communicate()
        return self.process.returncode

    def __enter__(self) -> Editor:
        return self

    def __exit__(self, *exc) -> None:
        self.stop()


def launch(playwright, executable: str):
    return playwright.chromium.launch(executable_path=executable, args=BROWSER_ARGS)


def open_page(browser, url: str, timeout_ms: float = 120_000):
    """A page on the editor, once its first model is drawn."""
    page = browser.new_page(viewport=VIEWPORT)
    page.problems = []
    page.on("pageerror", lambda error: page.problems.append(str(error)))
    page.goto(url)
    page.wait_for_function("window.shapegenEditor && window.shapegenEditor.modelsRendered > 0",
                           timeout=timeout_ms)  # fmt: skip
    return page


def model_coverage(page) -> float:
    """The fraction of the canvas the model covers (pixels that change when it is hidden)."""
    return float(page.evaluate("window.shapegenEditor.modelCoverage()"))


def verdict(page) -> str:
    return page.inner_text("#verdict")


def drag_slider(page, name: str, value: float) -> float:
    """Click the slider of attr ``name`` where ``value`` lies, as a designer would; returns the
    value the slider took."""
    slider = page.locator(f'#attrs input[type=range][name="{name}"]')
    low, high = float(slider.get_attribute("min")), float(slider.get_attribute("max"))
    box = slider.bounding_box()
    thumb = 16  # px: Chromium's default thumb, whose centre travels the track less its width
    x = box["x"] + thumb / 2 + (value - low) / (high - low) * (box["width"] - thumb)
    page.mouse.click(x, box["y"] + box["height"] / 2)
    return float(slider.input_value())


def wait_for_verdict(page, text: str, timeout_ms: float = 120_000) -> None:
    page.wait_for_function(
        "t => document.getElementById('verdict').textContent === t", arg=text, timeout=timeout_ms
    )


def wait_for_stable_range(page, name: str, timeout_ms: float = 300_000) -> str:
    """The status line under a free slider once its stable interval is shaded."""
    page.wait_for_function(
        "n => (window.shapegenEditor.state?.stability?.[n]?.status === 'done')",
        arg=name,
        timeout=timeout_ms,
    )
    time.sleep(0.3)  # the shading is drawn on the next state
    return page.inner_text(f'.attr[data-attr="{name}"] .status')


def main() -> None:
    import tempfile

    from playwright.sync_api import sync_playwright

    executable = find_browser()
    if executable is None:
        sys.exit("no Chromium found: apt-get install chromium")
    IMAGES.mkdir(exist_ok=True)
    rules = Path(__file__).resolve().parent.parent / "rules"
    with tempfile.TemporaryDirectory() as folder:
        grammar = Path(folder) / "barrel_vault.grammar"
        good = (rules / "barrel_vault.grammar").read_text(encoding="utf-8")
        grammar.write_text(good, encoding="utf-8")
        with Editor(grammar) as editor, sync_playwright() as playwright:
            browser = launch(playwright, executable)
            page = open_page(browser, editor.url)
            drag_slider(page, "angle", 60)
            wait_for_verdict(page, "stands")
            latency = page.evaluate("window.shapegenEditor.lastLatencyMs")
            print(f"slider change to verdict on screen: {latency / 1000:.3f} s")
            wait_for_stable_range(page, "angle")
            page.check("#show-ground")
            time.sleep(1.0)
            page.screenshot(path=str(IMAGES / "editor_barrel_vault.png"))
            drag_slider(page, "angle", 85)
            wait_for_verdict(page, "needs tension")
            page.check("#colour-tension")
            page.check("#show-joints")
            page.uncheck("#show-ground")
            wait_for_stable_range(page, "angle")
            time.sleep(1.0)
            page.screenshot(path=str(IMAGES / "editor_tension.png"))
            grammar.write_text(good.replace("attr span = 6.0", "attr span = 6.0 *"))
            page.wait_for_selector("#grammar-error", state="visible", timeout=10_000)
            time.sleep(0.5)
            page.screenshot(path=str(IMAGES / "editor_error.png"))
            browser.close()
    for name in ("editor_barrel_vault", "editor_tension", "editor_error"):
        print(f"wrote {IMAGES / name}.png")


if __name__ == "__main__":
    main()
