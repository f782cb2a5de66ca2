"""The design page in a real browser: headless Chromium driven by playwright.

Skipped, saying why, where no Chromium or no playwright is installed (.ci/run installs Debian's
``chromium``; playwright comes with the test extra and drives that browser, downloading nothing).
The steps are those of docs/editor_screenshots.py, which takes the documentation's pictures.
"""

import re
import shutil
import sys
from pathlib import Path

import pytest

DOCS = Path(__file__).resolve().parents[2] / "docs"
RULES = Path(__file__).resolve().parents[2] / "rules"
sys.path.insert(0, str(DOCS))
import editor_screenshots as page_steps  # noqa: E402
import make_figures  # noqa: E402
from editor_stack import STACK  # noqa: E402

pytest.importorskip(
    "playwright.sync_api", reason="the browser tests need playwright (pip install playwright)"
)
BROWSER = page_steps.find_browser()
pytestmark = [
    pytest.mark.skipif(
        BROWSER is None,
        reason="no Chromium found: the browser tests need Debian's chromium package"
        " (apt-get install chromium; .ci/run installs it) or SHAPEGEN_CHROMIUM=/path/to/chrome",
    ),
    pytest.mark.slow,  # a browser, a server and a stable-range scan: 10-50 s each
]


@pytest.fixture(scope="module")
def browser():
    from playwright.sync_api import sync_playwright

    with sync_playwright() as playwright:
        browser = page_steps.launch(playwright, BROWSER)
        yield browser
        browser.close()


@pytest.fixture
def stack_grammar(tmp_path):
    """editor_stack's two blocks, in a rule file of the test's own that it may rewrite."""
    grammar = tmp_path / "stack.grammar"
    grammar.write_text(STACK, encoding="utf-8")
    return grammar


def test_the_canvas_shows_the_model_and_a_slider_changes_the_verdict(browser, tmp_path):
    # arch_columns with 1 m columns: the file's thin arch needs tension, a 0.3 m one stands
    with page_steps.Editor("arch_columns.grammar", "--set", "column_width=1.0") as editor:
        page = page_steps.open_page(browser, editor.url)
        assert page_steps.verdict(page) == "needs tension"
        coverage = page_steps.model_coverage(page)
        assert coverage > 0.02, f"the model covers {coverage:.1%} of the canvas"
        taken = page_steps.drag_slider(page, "arch_thickness", 0.4)
        assert 0.3 < taken < 0.5
        page_steps.wait_for_verdict(page, "stands")
        assert page.inner_text("#measure").startswith("y/W² = ")
        page.wait_for_function("window.shapegenEditor.renderedModelVersion"
                               " === window.shapegenEditor.state.model_version")  # fmt: skip
        assert page_steps.model_coverage(page) > 0.02
        value = page.input_value('.attr[data-attr="arch_thickness"] input.value')
        assert abs(float(value) - taken) < 1e-3
        status = page_steps.wait_for_stable_range(page, "arch_thickness")
        assert status.startswith("stands for "), status
        assert page.locator('.attr[data-attr="arch_thickness"] .shade').count() >= 1
        page.check("#colour-tension")
        page.check("#show-ground")
        assert "ground reaction" in page.inner_text("#legend")
        page.screenshot(path=str(tmp_path / "arch.png"))
        assert not page.problems, page.problems
    assert editor.process.returncode == 0


def test_editing_the_file_reloads_the_model_and_shows_a_grammar_error(browser, tmp_path):
    source = page_steps.Path(__file__).resolve().parents[2] / "rules" / "arch_columns.grammar"
    grammar = tmp_path / "arch.grammar"
    shutil.copy(source, grammar)
    good = grammar.read_text()
    with page_steps.Editor(grammar) as editor:
        page = page_steps.open_page(browser, editor.url)
        rendered = page.evaluate("window.shapegenEditor.modelsRendered")
        assert page.is_hidden("#grammar-error")
        # a mistake: the page shows it with file, line, column and caret; the model stays
        grammar.write_text(good.replace("attr column_height = 3", "attr column_height = 3 *"))
        page.wait_for_selector("#grammar-error", state="visible", timeout=10_000)
        text = page.inner_text("#grammar-error-text")
        line = good.splitlines().index("attr column_height = 3") + 1
        place = re.search(r"arch\.grammar:(\d+):(\d+): ", text)
        assert place and line <= int(place[1]) <= line + 3, text  # at or after the dangling '*'
        assert "^" in text
        assert page_steps.model_coverage(page) > 0.02
        page.screenshot(path=str(tmp_path / "error.png"))
        # fixed, with taller columns: the new model replaces the old one
        grammar.write_text(good.replace("attr column_height = 3", "attr column_height = 4"))
        page.wait_for_selector("#grammar-error", state="hidden", timeout=10_000)
        page.wait_for_function("n => window.shapegenEditor.modelsRendered > n", arg=rendered,
                               timeout=10_000)  # fmt: skip
        value = page.input_value('.attr[data-attr="column_height"] input.value')
        assert float(value) == 4
        assert not page.problems, page.problems


# How many animation frames the page's code asks for while ``frames`` frames pass.
ASKED_FOR_FRAMES = """frames => new Promise((resolve) => {
  const original = window.requestAnimationFrame.bind(window);
  let asked = 0;
  let passed = 0;
  window.requestAnimationFrame = (callback) => { asked += 1; return original(callback); };
  const tick = () => {
    passed += 1;
    if (passed < frames) { original(tick); return; }
    window.requestAnimationFrame = original;
    resolve(asked);
  };
  original(tick);
})"""


def test_an_idle_page_draws_nothing_and_the_shading_lines_up_with_the_slider(browser, tmp_path):
    # the stack on a column of `courses` drums: a count, whose slider steps by 1
    grammar = tmp_path / "stack.grammar"
    grammar.write_text(
        STACK.replace("attr courses = 2", "@Range(1, 4)\nattr courses = 2").replace(
            'Lower --> label("lower") i("box")',
            'Lower --> label("lower") i("column", courses = courses)',
        ),
        encoding="utf-8",
    )
    with page_steps.Editor(grammar) as editor:
        page = page_steps.open_page(browser, editor.url)
        status = page_steps.wait_for_stable_range(page, "offset")
        assert status.startswith("stands for "), status
        # the green shading and the grey band are centred on the slider's own track
        boxes = page.evaluate(
            """() => Object.fromEntries(['input[type=range]', '.band', '.shade'].map((s) => {
                 const box = document.querySelector(`.attr[data-attr="offset"] ${s}`)
                   .getBoundingClientRect();
                 return [s, box.top + box.height / 2];
               }))"""
        )
        assert abs(boxes[".shade"] - boxes["input[type=range]"]) <= 1, boxes
        assert abs(boxes[".band"] - boxes["input[type=range]"]) <= 1, boxes
        # idle, the page asks for no frame (it drew one every frame): counted over a few
        # frames of the browser's own, so the count does not depend on the machine's speed
        page.wait_for_function("window.shapegenEditor.renderedModelVersion"
                               " === window.shapegenEditor.state.model_version")  # fmt: skip
        asked = page.evaluate(ASKED_FOR_FRAMES, 10)
        assert asked == 0, f"the idle page asked for {asked} frames in 10"
        drawn = page.evaluate("window.shapegenEditor.framesDrawn")
        # orbiting draws: a drag across the canvas
        box = page.locator("#canvas").bounding_box()
        x, y = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
        page.mouse.move(x, y)
        page.mouse.down()
        page.mouse.move(x + 120, y + 30, steps=6)
        page.mouse.up()
        page.wait_for_function("n => window.shapegenEditor.framesDrawn > n + 3", arg=drawn)
        assert page_steps.model_coverage(page) > 0.02
        # a count's slider steps by 1: a click between two values sends the nearest whole one
        courses = page.locator('#attrs input[type=range][name="courses"]')
        assert courses.get_attribute("step") == "1"
        assert page_steps.drag_slider(page, "courses", 2.7) == 3
        page.wait_for_function(
            "() => window.shapegenEditor.state.attrs.find((a) => a.name === 'courses').value === 3"
        )
        assert page.evaluate("window.shapegenEditor.errors") == []
        assert not page.problems, page.problems
    assert "Traceback" not in editor.stderr


def test_the_inspector_honours_the_cga_annotations(browser, tmp_path):
    from editor_stack import annotated_project

    with page_steps.Editor(annotated_project(tmp_path)) as editor:
        page = page_steps.open_page(browser, editor.url)
        # @Group sections in their order, a subgroup inside its group; @Order within a group
        groups = page.eval_on_selector_all(
            "#attrs details.group", "els => els.map((e) => e.dataset.group)"
        )
        assert groups == ["Structure", "Structure / Deep", "Look"]
        names = page.eval_on_selector_all(".attr", "els => els.map((e) => e.dataset.attr)")
        assert names[:8] == ["offset", "angle", "loose", "stone", "detail", "lanes", "size",
                             "loose_end"]  # fmt: skip
        assert names[8:] == ["courses", "mortar", "depth", "tint", "asset", "textures"]
        assert page.locator('#attrs details[data-group="Structure / Deep"] .attr').count() == 1
        assert "sizes" not in names  # @Hidden
        # @Description as the tooltip; @Range's stepsize as the slider's step
        offset = page.locator('.attr[data-attr="offset"]')
        assert offset.get_attribute("title") == "Shift of the upper block along x (m)"
        assert page.locator('input[type=range][name="angle"]').get_attribute("step") == "15"
        # an @Enum is a drop-down of its values; choosing one changes the design
        stone = page.locator('select[name="stone"]')
        options = stone.locator("option").evaluate_all("els => els.map((e) => e.value)")
        assert options == ["limestone", "granite", "marble"]
        version = page.evaluate("window.shapegenEditor.state.model_version")
        stone.select_option("granite")
        page.wait_for_function(
            "v => window.shapegenEditor.state.model_version > v"
            " && window.shapegenEditor.state.attrs.find((a) => a.name === 'stone').value"
            " === 'granite'",
            arg=version,
        )
        assert page.locator('select[name="size"] option').count() == 3  # valuesAttr
        assert page.locator('input[name="lanes"]').get_attribute("list")  # unrestricted @Enum
        # @Color: a colour picker; its value reaches the design
        page.locator('input[type=color][name="tint"]').fill("#336699")
        page.wait_for_function(
            "() => window.shapegenEditor.state.attrs.find((a) => a.name === 'tint').value"
            " === '#336699'"
        )
        # @File: the project's assets; a boolean: a check box
        files = page.locator('select[name="asset"] option').evaluate_all(
            "els => els.map((e) => e.value)"
        )
        assert files == ["doors/door.obj", "near.obj", "plate.obj"]
        assert page.locator('input[type=checkbox][name="mortar"]').count() == 1
        # an array attr (the hidden one) does not keep the free attr's stable range from being
        # scanned: the upper block stands up to half a block of offset
        status = page_steps.wait_for_stable_range(page, "offset")
        assert status.startswith("stands for 0–0.49"), status
        page_steps.settle(page)
        page_steps.screenshot(page, "editor_inspector", tmp_path)
        assert page.evaluate("window.shapegenEditor.errors") == []
        assert not page.problems, page.problems


def test_the_barrel_vault_stands_at_60_degrees_and_needs_tension_at_90(browser, tmp_path):
    # the pictures at the top of docs/editor.md
    good = (RULES / "barrel_vault.grammar").read_text(encoding="utf-8")
    grammar = tmp_path / "barrel_vault.grammar"
    grammar.write_text(good, encoding="utf-8")
    with page_steps.Editor(grammar) as editor:
        page = page_steps.open_page(browser, editor.url)
        page_steps.drag_slider(page, "angle", 60)
        page_steps.wait_for_verdict(page, "stands")
        status = page_steps.wait_for_stable_range(page, "angle")
        # the picture shows what docs/editor.md says it shows (docs/make_figures.py measures it)
        (angle,) = [m for m in make_figures.MEASUREMENTS if m.name == "editor-barrel-vault-angle"]
        interval, resolution = (f.stated() for f in angle.figures[1:])
        assert status == f"stands for {interval} (±{resolution})", status
        page.check("#show-ground")
        page_steps.settle(page)
        page_steps.screenshot(page, "editor_barrel_vault", tmp_path)
        page_steps.drag_slider(page, "angle", 90)  # the exact cone: stands up to about 87
        page_steps.wait_for_verdict(page, "needs tension")
        page.check("#colour-tension")
        page.check("#show-joints")
        page.uncheck("#show-ground")
        page_steps.wait_for_stable_range(page, "angle")
        page_steps.settle(page)
        assert "largest joint tension" in page.inner_text("#legend")
        page_steps.screenshot(page, "editor_tension", tmp_path)
        # a section across z at mid-length shows the vault's profile and the walls' joints
        page.uncheck("#show-joints")
        page.check("#section-on")
        assert page.evaluate("window.shapegenEditor.section")["axis"] == "z"
        page_steps.settle(page)
        page_steps.screenshot(page, "editor_section", tmp_path)
        page.uncheck("#section-on")
        grammar.write_text(good.replace("attr span = 6.0", "attr span = 6.0 *"))
        page.wait_for_selector("#grammar-error", state="visible", timeout=10_000)
        page_steps.screenshot(page, "editor_error", tmp_path)
        assert not page.problems, page.problems


def attr_value(page, name: str):
    return page.evaluate(
        "n => window.shapegenEditor.state.attrs.find((a) => a.name === n).value", name
    )


def wait_for_value(page, name: str, value) -> None:
    page.wait_for_function(
        "([n, v]) => window.shapegenEditor.state.attrs.find((a) => a.name === n).value === v",
        arg=[name, value],
    )


def type_value(page, name: str, text: str, value) -> None:
    """``text`` typed into the field of attr ``name`` and Enter pressed; waits until the
    design holds ``value``."""
    field = f'.attr[data-attr="{name}"] input.value'
    page.fill(field, text)
    page.press(field, "Enter")
    wait_for_value(page, name, value)


def test_undo_redo_reset_and_the_mark_on_the_designers_values(browser, stack_grammar):
    with page_steps.Editor(stack_grammar) as editor:
        page = page_steps.open_page(browser, editor.url)
        mark = '.attr[data-attr="{}"] .user'
        assert page.is_hidden(mark.format("offset")) and page.is_disabled("#undo")
        # a drag of the slider, then a check box: two changes, both marked
        page_steps.drag_slider(page, "offset", 0.7)
        page_steps.wait_for_verdict(page, "needs tension")
        page.check('input[type=checkbox][name="mortar"]')
        wait_for_value(page, "mortar", True)
        assert page.is_visible(mark.format("offset")) and page.is_visible(mark.format("mortar"))
        title = page.get_attribute(mark.format("offset"), "title")
        assert "the rule's default: 0.2" in title, title
        # Ctrl+Z undoes the check box, then the drag; Ctrl+Shift+Z and Ctrl+Y redo them
        page.keyboard.press("Control+z")
        wait_for_value(page, "mortar", False)
        assert page.is_hidden(mark.format("mortar"))
        page.keyboard.press("Control+z")
        page_steps.wait_for_verdict(page, "stands")
        assert attr_value(page, "offset") == 0.2
        assert page.input_value('input[type=range][name="offset"]') == "0.2"
        page.keyboard.press("Control+Shift+z")
        page_steps.wait_for_verdict(page, "needs tension")
        page.keyboard.press("Control+y")
        wait_for_value(page, "mortar", True)
        assert page.is_checked('input[type=checkbox][name="mortar"]')
        # the row's reset button: the rule's default again
        page.click('.attr[data-attr="offset"] .reset')
        page_steps.wait_for_verdict(page, "stands")
        assert page.is_hidden(mark.format("offset"))
        # a typed count, then the file's defaults change: the untouched offset takes its new
        # default, the designer's courses keeps its value, marked with the default it hides
        page.fill('input[name="courses"]', "4")
        page.press('input[name="courses"]', "Enter")
        wait_for_value(page, "courses", 4)
        text = STACK.replace("attr offset = 0.2", "attr offset = 0.1")
        stack_grammar.write_text(text.replace("attr courses = 2", "attr courses = 3"))
        wait_for_value(page, "offset", 0.1)
        assert attr_value(page, "courses") == 4
        assert page.is_hidden(mark.format("offset")) and page.is_visible(mark.format("courses"))
        title = page.get_attribute(mark.format("courses"), "title")
        assert "the rule's default: 3" in title, title
        page.click("#reset-all")
        wait_for_value(page, "courses", 3)
        assert page.locator(".attr .user:visible").count() == 0
        assert page.evaluate("window.shapegenEditor.errors") == []
        assert not page.problems, page.problems


def test_a_block_clicked_is_highlighted_and_its_account_shown(browser, tmp_path, stack_grammar):
    # the upper block shifted beyond half a block: its joint with the lower one needs tension
    with page_steps.Editor(stack_grammar, "--set", "offset=0.7") as editor:
        page = page_steps.open_page(browser, editor.url)
        assert page_steps.verdict(page) == "needs tension"
        x, y = page.evaluate("window.shapegenEditor.blockScreenPoint('b1')")
        before = page.evaluate(f"window.shapegenEditor.pixelAt({x}, {y})")
        page.mouse.click(x, y)
        page.wait_for_selector("#block", state="visible")
        assert page.evaluate("window.shapegenEditor.selected") == "b1"
        after = page.evaluate(f"window.shapegenEditor.pixelAt({x}, {y})")
        assert sum(abs(a - b) for a, b in zip(after, before, strict=True)) > 30, (before, after)
        text = page.inner_text("#block")
        assert "Block b1" in text and "labels: upper" in text
        assert "rules: Lot › Upper" in text
        assert "attrs its rules read: offset = 0.7" in text
        details = page.evaluate("window.shapegenEditor.blockDetails")
        (joint,) = details["joints"]
        assert joint["other"] == "b0" and joint["tension"] > 0
        assert "its worst joint needs" in text and "of tension" in text
        # the attr's link shows its row in the Inspector
        page.click('#block a[data-attr="offset"]')
        assert page.locator('.attr[data-attr="offset"]').is_visible()
        page_steps.screenshot(page, "editor_block", tmp_path)
        # a drag orbits and selects nothing; Esc deselects
        page.mouse.move(x, y)
        page.mouse.down()
        page.mouse.move(x + 80, y + 10, steps=4)
        page.mouse.up()
        assert page.evaluate("window.shapegenEditor.selected") == "b1"
        page.keyboard.press("Escape")
        page.wait_for_selector("#block", state="hidden")
        assert not page.problems, page.problems


def test_the_page_exports_the_model_the_report_and_the_attrs(browser, stack_grammar):
    import json
    import shlex

    from shapegen.cli import build_parser

    with page_steps.Editor(stack_grammar) as editor:
        page = page_steps.open_page(browser, editor.url)
        page_steps.drag_slider(page, "offset", 0.4)
        page.wait_for_function("window.shapegenEditor.exported?.set?.offset !== undefined")
        offset = attr_value(page, "offset")
        downloads = {}
        for link in ("download-model", "download-report", "download-attrs"):
            with page.expect_download() as info:
                page.click(f"#{link}")
            download = info.value
            downloads[download.suggested_filename] = Path(download.path()).read_bytes()
        assert set(downloads) == {"stack.glb", "stack.report.json", "stack.attrs.json"}
        assert downloads["stack.glb"][:4] == b"glTF"
        report = json.loads(downloads["stack.report.json"])
        assert report["attrs"]["offset"] == offset and report["analysis"]["feasible"]
        exported = json.loads(downloads["stack.attrs.json"])
        assert exported["set"] == {"offset": offset}
        # the command line on the page builds this design again
        line = page.inner_text("#command")
        assert line == exported["command"]
        args = build_parser().parse_args(shlex.split(line)[1:])
        assert dict(args.assignments) == {"offset": offset}
        page.click("#copy-command")  # copied, or selected where the page has no clipboard
        page.wait_for_function(
            "() => document.getElementById('message').textContent.startsWith('the command line is')"
        )
        assert not page.problems, page.problems


def in_view(page, fill: float = 0.6) -> bool:
    """The model's box lies inside the view and spans at least ``fill`` of its width or height."""
    x0, x1, y0, y1 = page.evaluate("window.shapegenEditor.modelExtent()")
    inside = x0 >= -1 and x1 <= 1 and y0 >= -1 and y1 <= 1
    return inside and max(x1 - x0, y1 - y0) >= 2 * fill


def test_the_first_view_frames_the_bridge_and_a_tall_tower(browser):
    with page_steps.Editor("suspension_bridge.grammar") as editor:
        page = page_steps.open_page(browser, editor.url)
        x0, x1, _, _ = page.evaluate("window.shapegenEditor.modelExtent()")
        left, right, _, _ = page.evaluate("window.shapegenEditor.freeRegion()")
        # the bridge runs across the view, beside the panel at its top left
        assert in_view(page) and x0 >= left - 1e-6 and x1 - x0 > 0.8 * (right - left), (x0, x1)
        assert page_steps.model_coverage(page) > 0.02  # it showed at 1 %
        # judged by its cables: no tension colours (the structure says so, not its name)
        assert page.locator("#colour-tension").is_disabled()
    with page_steps.Editor("tower.grammar") as editor:
        page = browser.new_page(viewport={"width": 760, "height": 520})  # a small window
        page.problems = []
        page.goto(editor.url)
        page.wait_for_function("window.shapegenEditor.modelsRendered > 0")
        assert in_view(page, 0.8), page.evaluate("window.shapegenEditor.modelExtent()")
        page.set_viewport_size({"width": 1100, "height": 420})  # wider and lower: framed again
        page.wait_for_function(
            "() => { const [x0, x1, y0, y1] = window.shapegenEditor.modelExtent();"
            " return y0 >= -1 && y1 <= 1 && y1 - y0 > 1.6; }"
        )
        assert not page.problems, page.problems


def test_frame_all_views_and_the_orthographic_camera(browser, tmp_path):
    source = RULES / "arch_columns.grammar"
    with page_steps.Editor(source) as editor:
        page = page_steps.open_page(browser, editor.url)
        assert in_view(page)
        # taller columns: the model no longer fits, and is framed again (once the page has the
        # new state, whose model is the one drawn: the old one fits already)
        taken = page_steps.drag_slider(page, "column_height", 6)
        wait_for_value(page, "column_height", taken)
        page.wait_for_function("window.shapegenEditor.renderedModelVersion"
                               " === window.shapegenEditor.state.model_version")  # fmt: skip
        assert in_view(page)
        # the designer zooms in: the view is left alone until Frame all
        box = page.locator("#canvas").bounding_box()
        page.mouse.move(box["x"] + box["width"] / 2, box["y"] + box["height"] / 2)
        for _ in range(6):
            page.mouse.wheel(0, -400)
        page.wait_for_function(
            "() => { const [x0, x1, y0, y1] = window.shapegenEditor.modelExtent();"
            " return x0 < -1 || x1 > 1 || y0 < -1 || y1 > 1; }"
        )
        assert page.evaluate("window.shapegenEditor.cameraView().auto") is False
        page.click("#frame-all")
        assert in_view(page)
        # top, front, side
        for button, axis in (("#view-top", 1), ("#view-front", 2), ("#view-side", 0)):
            page.click(button)
            direction = page.evaluate("window.shapegenEditor.cameraView().direction")
            assert direction[axis] > 0.999, (button, direction)
            assert in_view(page)
        # orthographic keeps the view, and frames as the perspective does
        page.click("#view-reset")
        before = page.evaluate("window.shapegenEditor.modelExtent()")
        page.check("#orthographic")
        view = page.evaluate("window.shapegenEditor.cameraView()")
        assert view["kind"] == "orthographic"
        after = page.evaluate("window.shapegenEditor.modelExtent()")
        assert abs((after[1] - after[0]) - (before[1] - before[0])) < 0.35, (before, after)
        page.click("#view-front")
        assert in_view(page)
        assert page_steps.model_coverage(page) > 0.03
        page_steps.screenshot(page, "editor_orthographic", tmp_path)
        page.uncheck("#orthographic")
        assert page.evaluate("window.shapegenEditor.cameraView().kind") == "perspective"
        assert in_view(page, 0.4), page.evaluate(
            "[window.shapegenEditor.modelExtent(), window.shapegenEditor.cameraView()]"
        )
        assert not page.problems, page.problems


def test_an_exact_value_is_typed_and_arrow_keys_step_by_the_attrs_step(browser, tmp_path):
    from editor_stack import annotated_project

    with page_steps.Editor(annotated_project(tmp_path)) as editor:
        page = page_steps.open_page(browser, editor.url)
        field = '.attr[data-attr="{}"] input.value'
        # an exact value, typed into the slider's field
        type_value(page, "offset", "0.4321", 0.4321)
        # the slider goes to its nearest step; the design takes the value typed
        assert page.input_value('input[type=range][name="offset"]') == "0.432"
        # a value beyond the range, or off the stepsize's grid, is built as given with a
        # warning the page shows (a range is a hint, as on the command line)
        type_value(page, "offset", "0.95", 0.95)
        page.wait_for_function(
            "() => document.getElementById('warnings-list').textContent"
            ".includes('attr offset=0.95 is outside its @Range [0, 0.9]: built as given')"
        )
        type_value(page, "offset", "0.4", 0.4)
        type_value(page, "angle", "37", 37)
        page.wait_for_function(
            "() => document.getElementById('warnings-list').textContent"
            ".includes('attr angle=37 is off its @Range stepsize 15 from 0')"
        )
        type_value(page, "angle", "30", 30)
        # restricted=false: the typed value is taken as it is
        type_value(page, "loose", "52.5", 52.5)
        # arrow keys on the slider step by its step: 15 for angle, 1/500 of the range rounded
        # down to a power of ten for offset (0.001)
        page.focus('input[type=range][name="angle"]')
        page.keyboard.press("ArrowRight")
        wait_for_value(page, "angle", 45)
        page.keyboard.press("ArrowLeft")
        wait_for_value(page, "angle", 30)  # each step taken before the next key
        page.keyboard.press("ArrowLeft")
        wait_for_value(page, "angle", 15)
        page.focus('input[type=range][name="offset"]')
        page.keyboard.press("ArrowLeft")
        wait_for_value(page, "offset", 0.399)
        # and in the typed field too
        page.focus(field.format("angle"))
        page.keyboard.press("ArrowUp")
        page.press(field.format("angle"), "Enter")
        wait_for_value(page, "angle", 30)
        assert page.evaluate("window.shapegenEditor.errors") == []
        assert not page.problems, page.problems


def test_labels_hide_and_a_section_plane_cuts_the_model(browser, tmp_path, stack_grammar):
    with page_steps.Editor(stack_grammar) as editor:
        page = page_steps.open_page(browser, editor.url)
        full = page_steps.model_coverage(page)
        x, y = page.evaluate("window.shapegenEditor.blockScreenPoint('b1')")
        upper = page.evaluate(f"window.shapegenEditor.pixelAt({x}, {y})")
        # the upper block's label unchecked: it is neither drawn nor picked
        page.uncheck('#legend input[data-label="upper"]')
        hidden = page.evaluate(f"window.shapegenEditor.pixelAt({x}, {y})")
        assert sum(abs(a - b) for a, b in zip(upper, hidden, strict=True)) > 30
        assert page_steps.model_coverage(page) < 0.8 * full
        page.mouse.click(x, y)
        assert page.evaluate("window.shapegenEditor.selected") in (None, "b0")
        # it stays hidden in the next model
        page_steps.drag_slider(page, "offset", 0.3)
        page.wait_for_function("window.shapegenEditor.renderedModelVersion"
                               " === window.shapegenEditor.state.model_version")  # fmt: skip
        assert not page.is_checked('#legend input[data-label="upper"]')
        assert page_steps.model_coverage(page) < 0.8 * full
        page.check('#legend input[data-label="upper"]')
        assert page_steps.model_coverage(page) > 0.9 * full
        # a section across y at half the height keeps the lower block only
        page.keyboard.press("Escape")
        page.check("#section-on")
        page.select_option("#section-axis", "y")
        page.fill("#section-at", "500")
        page.dispatch_event("#section-at", "input")
        section = page.evaluate("window.shapegenEditor.section")
        assert section["axis"] == "y" and abs(section["at"] - 1.0) < 1e-6
        assert page_steps.model_coverage(page) < 0.8 * full
        x, y = page.evaluate("window.shapegenEditor.blockScreenPoint('b1')")
        page.mouse.click(x, y)  # the cut-away block is not picked
        assert page.evaluate("window.shapegenEditor.selected") in (None, "b0")
        # the other side kept: the upper block only
        page.check("#section-flip")
        page.mouse.click(x, y)
        page.wait_for_function("window.shapegenEditor.selected === 'b1'")
        page.screenshot(path=str(tmp_path / "stack_section.png"))
        page.uncheck("#section-on")
        assert page_steps.model_coverage(page) > 0.9 * full
        assert not page.problems, page.problems


def settings(page) -> dict:
    return page.evaluate("window.shapegenEditor.state.settings")


def test_the_searchs_settings_free_attrs_margin_seed_and_lot(browser, tmp_path, stack_grammar):
    with page_steps.Editor(stack_grammar, "--set", "offset=0.8") as editor:
        page = page_steps.open_page(browser, editor.url)
        page.click("#settings summary")
        # the margin: closest stands with every joint shrunk to half its size, offset <= 1/3
        page.fill("#margin", "0.5")
        page.press("#margin", "Enter")
        page.wait_for_function("window.shapegenEditor.state.settings.margin === 0.5")
        page.click("#closest")
        page_steps.wait_for_verdict(page, "stands")
        assert attr_value(page, "offset") <= 1 / 3 + 1e-3
        # the free mark: clicked, the attr is fixed, and the search has nothing to vary
        free = '.attr[data-attr="offset"] button.free'
        page.click(free)
        page.wait_for_function("window.shapegenEditor.state.settings.free.length === 0")
        assert page.inner_text(free) == "fixed"
        page.click("#optimize")
        page.wait_for_function(
            "() => document.getElementById('message').textContent.includes('no attr is free')"
        )
        page.click(free)
        page.wait_for_function("window.shapegenEditor.state.settings.free[0] === 'offset'")
        # the seed and the lot: a 2 x 1 lot, then a polygon, then the file's again
        page.fill("#seed", "5")
        page.press("#seed", "Enter")
        page.wait_for_function("window.shapegenEditor.state.settings.seed === 5")
        page.fill("#lot-width", "2")
        page.press("#lot-width", "Enter")
        page.wait_for_function("window.shapegenEditor.state.settings.lot?.[0] === 2")
        volume = "fetch('/api/blocks/b1').then((r) => r.json()).then((b) => b.volume)"
        assert abs(page.evaluate(volume) - 2.0) < 1e-9
        page.fill("#lot-polygon", "0,0 0,2 2,2 2,0")
        page.press("#lot-polygon", "Enter")
        page.wait_for_function("window.shapegenEditor.state.settings.lot?.length === 4")
        assert abs(page.evaluate(volume) - 4.0) < 1e-9
        page_steps.settle(page)
        # the command line is fetched once the model is drawn
        page.wait_for_function(
            "() => document.getElementById('command').textContent.includes(\"--lot '0,0 0,2\")"
        )
        assert in_view(page)  # a larger model: framed again
        page_steps.screenshot(page, "editor_settings", tmp_path)
        page.click("#lot-file")
        page.wait_for_function("window.shapegenEditor.state.settings.lot === null")
        assert page.input_value("#lot-width") == "1"
        # every change of the settings is undone as an attr's is: the lot, then the margin
        page.keyboard.press("Control+z")
        page.wait_for_function("window.shapegenEditor.state.settings.lot?.length === 4")
        page.fill("#margin", "0.3")
        page.press("#margin", "Enter")
        page.wait_for_function("window.shapegenEditor.state.settings.margin === 0.3")
        page.locator("#margin").blur()  # Ctrl+Z in a text field undoes its typing
        page.keyboard.press("Control+z")
        page.wait_for_function("window.shapegenEditor.state.settings.margin === 0.5")
        assert page.input_value("#margin") == "0.5"
        assert not page.problems, page.problems


def test_a_cga_rule_opens_with_its_warnings_shown(browser, tmp_path):
    from editor_stack import CGA_WARNING, cga_package

    with page_steps.Editor(cga_package(tmp_path)) as editor:  # a .rpk: its start rule
        page = page_steps.open_page(browser, editor.url)
        assert page.inner_text("#file").startswith("building.rpk › building.cga")
        assert page.is_visible("#warnings")
        assert page.inner_text("#warnings-count") == "⚠ 1 warning"
        page.click("#warnings-count")
        assert CGA_WARNING in page.inner_text("#warnings-list")
        # the imported attr has its slider; the @Group its section
        assert page.locator('#attrs details[data-group="Mass"] .attr').count() == 1
        assert (
            page.locator('#attrs details[data-group="lib"] .attr[data-attr="lib.height"]').count()
            == 1
        )
        page_steps.drag_slider(page, "lib.height", 9)
        page.wait_for_function("window.shapegenEditor.state.grammar.blocks === 9")
        page_steps.settle(page)
        page_steps.screenshot(page, "editor_cga", tmp_path)
        assert page.evaluate("window.shapegenEditor.errors") == []
        assert not page.problems, page.problems


# whether attr n has the value v in the page's state
ATTR_IS = "([n, v]) => window.shapegenEditor.state.attrs.find((a) => a.name === n).value === v"


def test_angles_percents_and_distances_show_their_units(browser, tmp_path):
    from test_editor_annotations import UNITS_CGA

    rule = tmp_path / "units.cga"
    rule.write_text(UNITS_CGA, encoding="utf-8")

    def value_of(name):
        return page.evaluate(
            "n => window.shapegenEditor.state.attrs.find((a) => a.name === n).value", name
        )

    with page_steps.Editor(rule) as editor:
        page = page_steps.open_page(browser, editor.url)
        units = {
            name: page.inner_text(f'.attr[data-attr="{name}"] .unit')
            for name in ("pitch", "tilt", "share", "setback")
        }
        assert units == {"pitch": "°", "tilt": "°", "share": "%", "setback": "m"}
        # @Angle without a @Range: CityEngine's slider over 0-360 degrees
        pitch = page.locator('input[type=range][name="pitch"]')
        assert (pitch.get_attribute("min"), pitch.get_attribute("max")) == ("0", "360")
        # @Percent: shown and typed in percent, the value a fraction
        share = page.locator('.attr[data-attr="share"] input.value')
        assert float(share.input_value()) == 25
        share.fill("40")
        share.press("Enter")
        page.wait_for_function(ATTR_IS, arg=["share", 0.4])
        assert float(share.input_value()) == 40
        # unrestricted: a typed angle past the slider's end is taken as typed
        field = page.locator('.attr[data-attr="pitch"] input.value')
        field.fill("400")
        field.press("Enter")
        page.wait_for_function(ATTR_IS, arg=["pitch", 400])
        assert value_of("setback") == 1.5
        assert page.locator('.attr[data-attr="pitch"] button.free').count() == 0  # no @Range
        assert page.locator('.attr[data-attr="tilt"] button.free').count() == 1
        page_steps.settle(page)
        page_steps.screenshot(page, "editor_units", tmp_path)
        assert page.evaluate("window.shapegenEditor.errors") == []
        assert not page.problems, page.problems
