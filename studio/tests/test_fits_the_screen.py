"""What a class found cut or too small (issue 55, item 9), each named after what a student saw:
at a lab PC's 1366x768 the Plots tab ran off the panel's edge and the engine's chip off the
header; on an upright tablet Blockly's categories were 25 px and its number fields 23 px tall,
against the 44 px every touch target gets."""

from __future__ import annotations

from pathlib import Path

REPO = Path(__file__).resolve().parents[2]

TABS = """() => { const l = document.getElementById('dock-tabs'), r = l.getBoundingClientRect();
  return { fits: l.scrollWidth <= l.clientWidth,
           out: [...l.children].filter(t => { const b = t.getBoundingClientRect();
             return b.left < r.left - 0.5 || b.right > r.right + 0.5 || t.scrollWidth > t.clientWidth; }).map(t => t.id) }; }"""
HEADER = """() => [...document.querySelector('header').children].filter(e => !e.hidden && e.getBoundingClientRect().width > 0)
  .filter(e => e.getBoundingClientRect().right > innerWidth + 0.5 || (e.id !== 'project-tools' && e.scrollWidth > e.clientWidth + 0.5))
  .map(e => e.id || e.className)"""


def test_at_1366_every_panel_tab_and_the_engine_chip_are_whole(open_page):
    pg = open_page("mk2plus", width=1366, height=768)
    assert pg.page.evaluate(TABS) == {"fits": True, "out": []}
    # Blocks widen the panel; the project saved: its name gives way, the chips and STOP stay whole
    pg.page.click("#tab-program")
    pg.page.click("#mode-blocks")
    pg.wait("a.programMode === 'blocks' && document.getElementById('project-saved').textContent !== ''")
    assert pg.page.evaluate(TABS) == {"fits": True, "out": []}
    assert pg.page.evaluate(HEADER) == []
    chip = pg.page.locator("#conn").bounding_box()
    assert chip["x"] + chip["width"] <= 1366, chip
    assert pg.page.evaluate("() => document.documentElement.scrollWidth") <= 1366
    # opening the toolbox's categories moves nothing sideways (a class saw the page shift 9 px):
    # the blocks' area, the panel and the page stay where they were, nothing scrolled
    where = """() => [document.getElementById('blockly').getBoundingClientRect().x,
      document.querySelector('.dock').getBoundingClientRect().x, scrollX,
      [...document.querySelectorAll('body *')].filter(e => e.scrollLeft > 0 && !e.closest('#blockly')).length]"""
    before = pg.page.evaluate(where)
    for name in ("Move", "Signals", "Numbers"):
        pg.page.click(f"#blockly .blocklyToolboxCategory:has-text('{name}')")
        pg.page.wait_for_selector("#blockly svg.blocklyToolboxFlyout g[data-id]")
        assert pg.page.evaluate(where) == before, (name, before)
        assert pg.page.evaluate("() => document.documentElement.scrollWidth") <= 1366
    assert pg.errors == []


def test_on_a_tablet_blocks_categories_and_number_fields_are_44_px(open_page):
    pg = open_page("mk2plus", width=768, height=1024, touch=True)
    pg.page.tap("#tab-program")
    pg.page.tap("#mode-blocks")
    pg.page.locator("#blockly").scroll_into_view_if_needed()
    pg.page.wait_for_selector("#blockly .blocklyToolboxCategory")
    heights = pg.page.eval_on_selector_all("#blockly .blocklyToolboxCategory", "cs => cs.map(c => c.getBoundingClientRect().height)")
    assert min(heights) >= 44, heights
    pg.page.tap("#blockly .blocklyToolboxCategory:has-text('Move')")
    pg.page.wait_for_selector("#blockly svg.blocklyToolboxFlyout g.arm_tool_to[data-id]")
    # a number is a shadow block of its own, tapped to type in it
    fields = pg.page.eval_on_selector_all("#blockly svg.blocklyToolboxFlyout g.arm_tool_to[data-id] g.math_number.blocklyShadow",
                                          "fs => fs.map(f => f.getBoundingClientRect().height)")
    assert len(fields) == 3 and min(fields) >= 44, fields
    pg.page.screenshot(path="/tmp/articula-tablet-blocks.png")
    assert pg.errors == []


def test_a_tap_on_a_sliders_track_does_not_jump_the_joint(open_page):
    """Issue 55, 9: on the tablet a tap on a joint slider's track, away from its thumb, jumped
    the joint by 56 degrees. The thumb is what a finger drags."""
    pg = open_page("mk2plus", width=768, height=1024, touch=True)
    if pg.page.is_visible("#tab-joints"):
        pg.page.tap("#tab-joints")
    q0 = pg.hook("a.pose.q[0]")
    track = pg.page.locator("#joints input[type=range][data-joint='0']").bounding_box()
    pg.page.touchscreen.tap(track["x"] + track["width"] - 6, track["y"] + track["height"] / 2)
    pg.page.wait_for_timeout(600)
    assert pg.hook("a.pose.q[0]") == q0
    assert abs(float(pg.page.input_value("#joints input[type=range][data-joint='0']")) - q0) < 0.11
    assert pg.errors == []


CODE_BOTTOM = """() => { const c = [document.getElementById('blockly'), document.getElementById('text-editor')]
  .find(e => !e.hidden && e.offsetParent !== null); return c.getBoundingClientRect().bottom; }"""


def test_in_an_exercise_the_code_comes_into_sight_once_the_student_starts(open_page):
    """Issue 55, 9: at 1366x768 an exercise's task pushed the program below the window's bottom.
    The task shows whole when the exercise opens; once the student works on the program it folds
    to its title line, the program in sight, and a tap on that line opens it again."""
    pg = open_page("mk2plus", width=1366, height=768)
    pg.page.click("#projects-button")
    pg.page.set_input_files("#project-file", str(REPO / "exercises" / "pick-and-place.articula"))
    pg.wait("a.project.goal !== null && a.goal.facts.length > 1")
    assert pg.page.is_visible("#exercise-text")
    assert pg.page.evaluate(CODE_BOTTOM) > 768  # the task whole: the program's bottom cut
    pg.page.click("#mode-text")  # (a change the student did not make in the program: the task stays)
    pg.wait("a.programMode === 'text'")
    assert pg.page.is_visible("#exercise-text")
    pg.page.click("#editor")
    pg.page.keyboard.press("Control+End")
    pg.page.keyboard.type("\nG 100\n")
    pg.wait("!document.getElementById('exercise-task').open")
    assert pg.page.evaluate(CODE_BOTTOM) <= 768
    assert pg.page.is_visible("#exercise-check")  # Check stays
    # the title line opens the task again, and it stays open while the student types on
    pg.page.click("#exercise-task > summary")
    assert pg.page.is_visible("#exercise-text")
    pg.page.click("#editor")
    pg.page.keyboard.type("G 0\n")
    pg.page.wait_for_timeout(300)
    assert pg.page.is_visible("#exercise-text")
    assert pg.errors == []
