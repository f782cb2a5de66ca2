"""Drive ``shapegen edit`` in headless Chromium: the steps of the browser tests, and the
screenshots of docs/editor.md.

The browser tests (tests/editor/test_editor_browser.py) take the pictures as they check the
page (:func:`screenshot`): into the test's own folder, or into the folder named by
``SHAPEGEN_SCREENSHOTS``. Run this file to refresh the pictures in docs/images/ (it runs those
tests with ``SHAPEGEN_SCREENSHOTS=docs/images``):

    .venv/bin/python docs/editor_screenshots.py

It needs Chromium (Debian: ``apt-get install chromium``) and the ``playwright`` Python package
(installed with the test extra); playwright drives the system's browser, nothing is downloaded.

One picture of a page, taken once its model is drawn (a headless browser's own
``--screenshot`` takes it when the page has loaded, before the model has come)::

    .venv/bin/python docs/editor_screenshots.py --shot http://127.0.0.1:8765/ page.png
    .venv/bin/python docs/editor_screenshots.py --shot rules/barrel_vault.grammar page.png

A rule file is opened in a ``shapegen edit`` of its own, stopped after the picture. The picture
waits for the model drawn (``window.shapegenEditor.modelsRendered``), the drawn model being the
state's (``renderedModelVersion === state.model_version``) and, with ``--scans``, the stable
intervals of the free sliders shaded.
"""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
from pathlib import Path

IMAGES = Path(__file__).resolve().parent / "images"
BROWSERS = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")
# Software WebGL: a headless machine has no GPU.
BROWSER_ARGS = ["--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--ignore-gpu-blocklist"]
VIEWPORT = {"width": 1280, "height": 760}
SCREENSHOTS_VARIABLE = "SHAPEGEN_SCREENSHOTS"


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
    # the state says the scan is done, and the row shows it (the page draws the shading and
    # the status line from the same state): no sleep, which a loaded machine outlasts
    page.wait_for_function(
        """n => window.shapegenEditor.state?.stability?.[n]?.status === 'done'
          && document.querySelector(`.attr[data-attr="${n}"] .status`)?.textContent
               .startsWith('stands')""",
        arg=name,
        timeout=timeout_ms,
    )
    return page.inner_text(f'.attr[data-attr="{name}"] .status')


def settle(page) -> None:
    """Wait until the page shows the state's model and has drawn what it asked to draw."""
    page.wait_for_function("window.shapegenEditor.renderedModelVersion"
                           " === window.shapegenEditor.state.model_version")  # fmt: skip
    page.evaluate(
        "() => new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(done)))"
    )


def screenshot(page, name: str, folder: Path) -> Path:
    """A picture of the page as ``name``.png: into ``SHAPEGEN_SCREENSHOTS`` when it is set
    (the documentation's pictures), else into ``folder``."""
    chosen = os.environ.get(SCREENSHOTS_VARIABLE)
    path = (Path(chosen) if chosen else Path(folder)) / f"{name}.png"
    page.screenshot(path=str(path))
    return path


def wait_for_scans(page, timeout_ms: float = 600_000) -> None:
    """Wait until every free slider's stable interval is shaded (or said to be nowhere)."""
    page.wait_for_function(
        """() => {
          const s = window.shapegenEditor.state;
          const free = s.attrs.filter((a) => a.free).map((a) => a.name);
          return free.every((n) => s.stability?.[n]?.status === 'done');
        }""",
        timeout=timeout_ms,
    )


def shot(target: str, output: Path, scans: bool = False) -> Path:
    """A picture of the page at ``target`` (its address, or a rule file opened for it) once
    the model is drawn."""
    from playwright.sync_api import sync_playwright

    executable = find_browser()
    if executable is None:
        sys.exit("no Chromium found: apt-get install chromium")
    editor = None if target.startswith(("http://", "https://")) else Editor(target)
    try:
        with sync_playwright() as playwright:
            browser = launch(playwright, executable)
            page = open_page(browser, target if editor is None else editor.url)
            if scans:
                wait_for_scans(page)
            settle(page)
            page.screenshot(path=str(output))
            browser.close()
    finally:
        if editor is not None:
            editor.stop()
    return output


def main() -> None:
    import argparse

    parser = argparse.ArgumentParser(description="The design page's pictures, in Chromium.")
    parser.add_argument(
        "--shot",
        nargs=2,
        metavar=("PAGE", "PNG"),
        help="one picture of PAGE (an address, or a rule file) once its model is drawn",
    )
    parser.add_argument(
        "--scans",
        action="store_true",
        help="with --shot: wait also for the free sliders' stable intervals",
    )
    args = parser.parse_args()
    if args.shot:
        print(shot(args.shot[0], Path(args.shot[1]), scans=args.scans))
        return
    if find_browser() is None:
        sys.exit("no Chromium found: apt-get install chromium")
    IMAGES.mkdir(exist_ok=True)
    tests = Path(__file__).resolve().parent.parent / "tests" / "editor" / "test_editor_browser.py"
    environment = {**os.environ, SCREENSHOTS_VARIABLE: str(IMAGES)}
    command = [sys.executable, "-m", "pytest", "-q", "-m", "slow", str(tests)]
    done = subprocess.run(command, env=environment)
    if done.returncode:
        sys.exit(done.returncode)
    for path in sorted(IMAGES.glob("editor_*.png")):
        print(f"{path}")


if __name__ == "__main__":
    main()
