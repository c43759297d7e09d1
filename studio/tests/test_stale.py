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


def test_the_exercises_lead_the_examples_menu(open_page):
    """Exercises are found where programs are (issue 28, what a class hit, 4): the examples menu
    starts with them, and choosing one opens it with its goal; no look-alike without a goal."""
    pg = open_page("mk2plus")
    pg.page.click("#tab-program") if pg.page.is_visible("#tab-program") else None
    pg.page.wait_for_function("() => document.querySelector('#program-select optgroup') !== null")
    groups = pg.page.eval_on_selector_all("#program-select optgroup", "gs => gs.map(g => [g.label, [...g.children].map(o => o.value)])")
    assert groups[0][0].startswith("Exercises")
    assert "exercise:pick-and-place.articula" in groups[0][1]
    assert not any("pick-and-place" in v for v in groups[1][1]), groups[1]
    pg.page.select_option("#program-select", "exercise:pick-and-place.articula")
    pg.wait("a.project.goal !== null && a.project.goal.title === 'Pick and place the block'")
    assert pg.page.is_visible("#exercise-check")
    assert pg.errors == []
