"""No old result on screen after a change (issue 28, what a class hit, 7): the program's status,
its plots and path, and an exercise's Check result are for the program they were made from;
a change of the program takes them away."""
from __future__ import annotations


def test_a_changed_program_takes_its_old_results_away(open_page):
    pg = open_page("mk2plus")
    pg.page.click("#tab-program") if pg.page.is_visible("#tab-program") else None
    pg.page.fill("#editor", "M 0 90 0\nM 30 90 0\n")
    pg.page.click("#run")
    pg.wait("a.timeline !== null && !a.playing")
    pg.wait("document.getElementById('program-status').textContent.startsWith('2 commands')")
    pg.page.fill("#editor", "M 0 90 0\nM 30 90 0\nM 0 80 -10\n")
    pg.wait("a.timeline === null")
    assert pg.hook("document.getElementById('program-status').textContent").startswith("Changed")
    assert pg.hook("a.paths.points") == 0

    # an exercise: Check's result goes with the program it checked
    pg.page.click("#projects-button")
    pg.page.select_option("#exercise-select", "pick-and-place.articula")
    pg.wait("a.project.goal !== null")
    pg.page.keyboard.press("Escape")
    assert pg.hook("document.getElementById('program-status').textContent") in ("", "Changed: Play works it out and runs it.")
    pg.page.click("#mode-text")
    pg.page.fill("#editor", "G 100\n")
    pg.page.click("#exercise-check")
    pg.wait("a.exercise !== null && document.querySelectorAll('#exercise-result li').length > 1")
    assert pg.hook("a.exercise.met") is False
    pg.page.fill("#editor", "G 100\nM 0 75 -20\n")
    pg.wait("a.exercise === null && document.querySelectorAll('#exercise-result li').length === 0")
    assert pg.errors == []
