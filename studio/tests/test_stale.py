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


def test_run_works_the_program_out_again_after_the_physics_is_turned_off(open_page):
    """What a class hit (issue 55, 2 and 6): a program run with the physics on, then the physics
    turned off, and Run and Step did nothing but a red "no program loaded: send program_load
    first" (the engine had dropped the time line, the page still played it); the corner under
    the view kept the physics' clock and counts. Now Run works the program out again and plays
    it, and the corner is the model's."""
    pg = open_page("mk2plus")
    pg.page.click("#tab-program") if pg.page.is_visible("#tab-program") else None
    pg.page.fill("#editor", "M 0 90 0\nM 20 90 0\n")
    pg.page.click("#run")
    pg.wait("a.timeline !== null && !a.playing")
    pg.page.select_option("#scene-select", "push")
    pg.wait("a.physics && a.physics.on && a.physics.t > 0.2", timeout=20000)
    pg.page.click("#run")
    pg.wait("document.getElementById('view-status').textContent.includes('steps')", timeout=20000)
    pg.page.select_option("#scene-select", value="")
    pg.wait("!a.physics.on")
    assert pg.page.text_content("#view-status") == ""
    pg.page.click("#run")
    pg.wait("a.timeline !== null && !a.playing", timeout=20000)
    pg.wait("document.getElementById('program-status').textContent.startsWith('2 commands')")
    assert pg.page.text_content("#view-status").startswith("t = ")
    assert pg.hook("a.pageErrors") == [] and pg.errors == []


def test_a_servo_arm_in_the_physics_runs_its_gripper_line_and_loses_no_steps(open_page):
    """What a class hit (issue 55, 1): the meArm in the live physics, grasp-and-lift, the program
    `L 0 20 / L 1 -20 / G 0`: the two L lines ran, then nothing for over 40 s, and the corner
    under the view read "lost -10 10 -10", which a servo arm cannot lose (a servo rests anywhere
    within half its dead band of its pulse). Now the gripper line runs, the program ends, and the
    corner gives the counts and no loss."""
    pg = open_page("mearm")
    pg.page.click("#tab-program") if pg.page.is_visible("#tab-program") else None
    pg.page.select_option("#scene-select", "grasp-and-lift-mearm")
    pg.wait("a.physics && a.physics.on", timeout=20000)
    pg.page.fill("#editor", "L 0 20\nL 1 -20\nG 0\n")
    pg.page.click("#run")
    # (a freeze: busy for ever, the gripper never closed)
    pg.wait("!a.physics.busy && a.pose.gripper === 0 && Math.round(a.pose.q[0]) === 20 && Math.round(a.pose.q[2]) === -70 && "
            "document.getElementById('view-status').textContent.includes('steps')", timeout=40000)
    corner = pg.page.text_content("#view-status")
    assert "lost" not in corner, corner
    pg.page.select_option("#scene-select", value="")
    pg.wait("!a.physics.on")
    assert pg.hook("a.pageErrors") == [] and pg.errors == []
