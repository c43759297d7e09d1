"""Undo and redo (issue 28's Editor, studio/web/src/editor/): every edit a student makes to the
project is a step of one History; the buttons on screen and Ctrl+Z / Ctrl+Shift+Z / Ctrl+Y take
the steps back and do them again, and a reload keeps the project as it is."""
from __future__ import annotations


def robot_scene_text(pg):
    return pg.hook("[a.robot && a.robot.name, (a.scene && a.scene.name) || '', document.getElementById('editor').value]")


def test_edits_undone_to_the_start_and_redone_to_the_end(open_page):
    pg = open_page("mk2plus")
    pg.wait("a.history.ready && !a.project.dirty")
    start = robot_scene_text(pg)
    assert pg.hook("a.history.undo") == 0
    assert pg.page.is_disabled("#undo") and pg.page.is_disabled("#redo")

    # three edits: the program's text, the robot, the scene
    pg.page.fill("#editor", "M 0 90 0\nG 50\n")
    pg.wait("a.history.undo === 1")
    assert pg.hook("a.history.undoName") == "the program's text"
    assert "Undo: the program's text" in pg.page.get_attribute("#undo", "title")
    pg.page.select_option("#robot-select", "panda")
    pg.wait("a.robot.name !== 'MK2 Plus' && a.history.undo === 2")
    pg.page.select_option("#scene-select", "push")
    pg.wait("a.scene && a.scene.name === 'push' && a.history.undo === 3")
    end = robot_scene_text(pg)
    assert end[1] == "push" and end[2] == "M 0 90 0\nG 50\n"

    # back to the start with the button, one step at a time
    pg.page.click("#undo")
    pg.wait("!(a.scene && a.scene.name) && a.history.undo === 2 && a.history.redo === 1")
    pg.page.click("#undo")
    pg.wait("a.robot.name === 'MK2 Plus' && a.history.undo === 1")
    assert pg.hook("document.getElementById('editor').value") == "M 0 90 0\nG 50\n", "the robot's undo kept the program"
    pg.page.click("#undo")
    pg.wait("a.history.undo === 0 && a.history.redo === 3")
    assert robot_scene_text(pg) == start
    assert pg.page.is_disabled("#undo")

    # and to the end by the keys (the text box has the keyboard: its own undo does not take over)
    pg.page.focus("#editor")
    for n in (1, 2, 3):
        pg.page.keyboard.press("Control+Shift+Z" if n < 3 else "Control+Y")
        pg.wait(f"a.history.undo === {n} && !a.project.dirty")
    pg.wait("a.scene && a.scene.name === 'push'")
    assert robot_scene_text(pg) == end
    assert pg.hook("a.history.redo") == 0

    # Ctrl+Z in the text box is the page's undo too
    saves = pg.hook("a.project.saves")
    pg.page.keyboard.press("Control+Z")
    pg.wait(f"!(a.scene && a.scene.name) && a.history.undo === 2 && a.project.saves > {saves} && !a.project.dirty")

    # a reload keeps the project as it is on screen
    pg.page.reload()
    pg.wait("window.articula && a.ready && a.robot && a.robot.name !== 'MK2 Plus'")
    pg.wait("document.getElementById('editor').value === 'M 0 90 0\\nG 50\\n'")
    assert pg.hook("(a.scene && a.scene.name) || ''") == ""
    assert pg.errors == []


def test_an_exercise_and_its_blocks_undone_by_touch_on_a_tablet(open_page):
    """On an upright tablet (touch, no keyboard): opening an exercise is one step, each block
    tapped in is one; the Undo button takes them back to the project before, Redo brings them again."""
    pg = open_page("mk2plus", width=768, height=1024, touch=True)
    pg.wait("a.history.ready && !a.project.dirty")
    first = pg.hook("a.project.name")
    pg.page.tap("#projects-button")
    pg.page.select_option("#exercise-select", "pick-and-place.articula")
    pg.wait("a.project.goal !== null && a.programMode === 'blocks' && a.history.undo === 1")
    assert pg.hook("a.history.undoName").startswith("opening")
    pg.page.keyboard.press("Escape")  # (the projects list closed)
    count = "(a.blocksPending ? -1 : a.blocksCode ? a.blocksCode.text.split('\\n').filter(l => /^[A-Z]/.test(l)).length : 0)"
    n0 = pg.hook(count)
    pg.page.locator("#blockly").scroll_into_view_if_needed()
    for i, (category, kind) in enumerate([("Gripper", "arm_gripper_open"), ("Move", "arm_joints")], 1):
        pg.page.tap(f"#blockly .blocklyToolboxCategory:has-text('{category}')")
        pg.page.wait_for_selector(f"#blockly svg.blocklyToolboxFlyout g.{kind}[data-id]")
        pg.page.locator(f"#blockly svg.blocklyToolboxFlyout g.{kind}[data-id] > path.blocklyPath").first.tap(position={"x": 6, "y": 8})
        pg.wait(f"{count} === {n0 + i}", timeout=10000)
    pg.wait("a.history.undo >= 2 && !a.project.dirty")
    steps = pg.hook("a.history.undo")
    assert pg.page.locator("#undo").is_visible()
    seen = []
    for n in range(steps):  # the blocks, then the opening: the project before it, again
        pg.page.tap("#undo")
        pg.wait(f"a.history.undo === {steps - 1 - n} && a.history.redo === {n + 1}")
        seen.append(pg.hook(f"[{count}, a.project.goal !== null]"))
    assert [n0, True] in seen, seen  # the exercise as it opened, its blocks taken back
    pg.wait(f"a.project.goal === null && a.project.name === {first!r}")
    # every step still to redo, once the project before has settled (a wait that fails prints
    # a.history: the step a late change recorded, and where it changed the project)
    pg.wait(f"a.history.ready && a.history.undo === 0 && a.history.redo === {steps}")
    pg.page.wait_for_timeout(1500)
    pg.wait(f"a.history.undo === 0 && a.history.redo === {steps}")
    for n in range(steps):
        pg.page.tap("#redo")
        pg.wait(f"a.history.undo === {n + 1}")
    pg.wait(f"a.project.goal !== null && {count} === {n0 + 2}")
    assert pg.errors == []
