"""An exercise's goal is drawn, with what the student needs to know (issue 28, what a class hit,
5): the pick-and-place target was only text, "(215, 180) mm", and a grasp too high failed only
at Check. Now the place is a green box in the view, each point to reach a numbered ball, and
the goal says how tall the block is and how low the tool's point comes above it."""
from __future__ import annotations

import json
import re

from conftest import REPO, SHOTS, cli_json


def _open_exercise(pg, name):
    pg.page.select_option("#program-select", f"exercise:{name}")
    pg.wait(f"a.project.goal !== null && a.goal.drawn > 0 && a.project.name !== ''")


def test_the_goal_is_drawn_and_says_how_low_the_tool_goes(open_page):
    pg = open_page("mk2plus")
    pg.page.click("#tab-program") if pg.page.is_visible("#tab-program") else None
    assert pg.hook("a.goal.drawn") == 0
    _open_exercise(pg, "pick-and-place.articula")
    assert pg.hook("a.goal.drawn") == 1  # one place: where the block must end
    pg.wait("a.goal.facts.length >= 2")
    facts = pg.hook("a.goal.facts")
    shown = pg.page.inner_text("#exercise-facts")
    assert facts[0] in shown
    # the block of the scene (24 x 24 x 100 mm at (305, 0)), its top, and how low the tool comes:
    # what articula ik gives for the point on the table under it
    assert "24 × 24 × 100 mm" in facts[0] and "(305, 0)" in facts[0] and "top 100 mm" in facts[0], facts
    lowest = cli_json("ik", "mk2plus", "--target", "305,0,0")["tool"][2]
    said = int(re.search(r"comes down to (\d+) mm", facts[0]).group(1))
    assert said == round(lowest) and 40 < said < 100, (said, lowest)
    pg.page.screenshot(path=str(SHOTS / "studio-exercise-goal.png"))

    # three points to reach: three numbered balls, and no box
    _open_exercise(pg, "reach-three-points.articula")
    pg.wait("a.goal.drawn === 3")
    assert "3 numbered green balls" in pg.hook("a.goal.facts[0]")
    # undo: the pick-and-place goal again; a project with no goal draws none
    pg.page.click("#undo")
    pg.wait("a.goal.drawn === 1 && a.project.goal && a.project.goal.title === 'Pick and place the block'")
    pg.page.click("#projects-button")
    pg.page.click("#project-new")
    pg.wait("a.project.goal === null && a.goal.drawn === 0")
    assert pg.errors == []


def test_a_hostile_goal_draws_nothing_it_should_not(open_page, tmp_path):
    """A project file's goal is untrusted: an object goal naming nothing in its scene draws its
    place and says nothing more, and no text of it is read as HTML."""
    pg = open_page("mk2plus")
    doc = json.loads((REPO / "exercises" / "pick-and-place.articula").read_text())
    doc["goal"]["parts"][0]["object"] = "<img src=x onerror=alert(1)>"
    doc["goal"]["title"] = "<b>bold</b>"
    f = tmp_path / "odd.articula"
    f.write_text(json.dumps(doc))
    pg.page.click("#projects-button")
    pg.page.set_input_files("#project-file", str(f))
    pg.wait("a.project.goal !== null && a.goal.drawn === 1")
    pg.page.keyboard.press("Escape")
    assert pg.page.inner_text("#exercise-title") == "<b>bold</b>"
    pg.wait("a.goal.facts.length === 1")  # only the box's sentence: no such object in the scene
    assert pg.page.locator("#exercise img").count() == 0
    assert pg.errors == []
