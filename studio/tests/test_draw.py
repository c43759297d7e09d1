"""Draw and write (issue 29) in the page: text, a shape or an SVG file for a pen in the gripper,
the reach check, the line the arm will draw (the engine's prediction, step by step) over the
drawing, and the program into the editor; a hostile SVG refused as text."""
from __future__ import annotations

import sys

from conftest import REPO, SHOTS

sys.path.insert(0, str(REPO / "python"))
import articula  # noqa: E402


def _draw(pg, kind="text", text=None, width=60, x=250, y=0, z=0, pen=120, steps=""):
    pg.page.select_option("#draw-kind", kind)
    if text is not None:
        pg.page.fill("#draw-text", text)
    for box, v in (("#draw-width", width), ("#draw-x", x), ("#draw-y", y), ("#draw-z", z), ("#draw-pen", pen)):
        pg.page.fill(box, str(v))
    pg.page.select_option("#draw-steps", steps)
    n = pg.hook("a.drawings")  # (the page's hook is read-only: wait for the next drawing)
    pg.page.click("#draw-go")
    pg.wait(f"a.drawings > {n}", timeout=60000)
    return pg.hook("a.drawing")


def test_write_hello_see_the_line_the_arm_will_draw_and_run_it(open_page):
    pg = open_page("mk2plus")
    if pg.page.is_visible("#tab-program"):
        pg.page.click("#tab-program")
    pg.page.locator("#draw-section").scroll_into_view_if_needed()
    d = _draw(pg, text="Hello")
    assert d["fits"] and d["error"] == "", d
    # the engine's own numbers: the same drawing from Python
    mk2 = articula.Robot.load("mk2plus")
    py = mk2.draw(text="Hello", width=60, at=(250, 0), z=0, pen=120)
    assert d["program"] == py["program"]
    assert d["steps"] == py["ink"]["steps"] and abs(d["worstMm"] - py["ink"]["worst_mm"]) < 1e-9
    status = pg.page.text_content("#draw-status")
    assert f"stays within {py['ink']['worst_mm']:.2f} mm of the drawing" in status, status
    pg.page.screenshot(path=str(SHOTS / "studio-draw.png"))
    # half steps: the same program, smaller stairs
    half = _draw(pg, text="Hello", steps="2")
    assert half["program"] == d["program"] and half["worstMm"] < d["worstMm"] and half["steps"] > d["steps"]
    # into the editor, and Run plays it on the model
    pg.page.click("#draw-use")
    pg.page.wait_for_function("document.querySelector('#editor').value.startsWith('# drawn by Articula')")
    assert pg.page.input_value("#editor") == py["program"]
    pg.page.click("#run")
    pg.wait(f"a.timeline !== null && a.timeline.records.length === {py['program'].count(chr(10)) - 2}", timeout=60000)
    assert pg.hook("a.timeline.records.every(r => r.reply === 'ok')")
    assert pg.errors == []


def test_a_drawing_out_of_reach_and_a_hostile_svg_are_said_plainly(open_page, tmp_path):
    pg = open_page("mk2plus")
    if pg.page.is_visible("#tab-program"):
        pg.page.click("#tab-program")
    d = _draw(pg, kind="square", width=40, x=120)
    assert not d["fits"] and "toward +x (away from the base)" in d["advice"]
    assert "toward +x" in pg.page.text_content("#draw-status")
    assert pg.page.is_disabled("#draw-use")
    # a file with a script and markup in its name: refused, and shown as text
    bad = tmp_path / "<b>evil<i>.svg"
    bad.write_text('<svg xmlns="http://www.w3.org/2000/svg"><script>alert(1)</script><path d="M0 0 L10 10"/></svg>')
    pg.page.select_option("#draw-kind", "svg")
    pg.page.set_input_files("#draw-file", str(bad))
    d = _draw(pg, kind="svg", width=40, x=260)
    assert "holds a <script>: a drawing never runs code" in d["error"], d
    assert "<b>evil<i>.svg" in pg.page.text_content("#draw-status")  # the name as text
    assert pg.page.locator("#draw-status b").count() == 0  # never as HTML
    # a shipped icon draws
    pg.page.set_input_files("#draw-file", str(REPO / "examples" / "drawings" / "bicycle.svg"))
    d = _draw(pg, kind="svg", width=50, x=260)
    assert d["fits"] and d["steps"] > 100, d
    assert pg.errors == []
