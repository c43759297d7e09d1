"""Undo and redo (issue 28's Editor, studio/web/src/editor/): every edit a student makes to the
project is a step of one History; the buttons on screen and Ctrl+Z / Ctrl+Shift+Z / Ctrl+Y take
the steps back and do them again, and a reload keeps the project as it is."""
from __future__ import annotations


def robot_scene_text(pg):
    return pg.hook("[a.robot && a.robot.name, (a.scene && a.scene.name) || '', document.getElementById('editor').value]")


def test_edits_undone_to_the_start_and_redone_to_the_end(open_page):
    pg = open_page("mk2plus")
    pg.wait("a.project.id !== '' && !a.project.dirty")
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
