"""Refusals a student can act on (issue 55, item 8): what a class with meArms and MK2s met, each
named after what the student sees. Every line that cannot be read is named at once; a point out
of reach says what holds the tool back and how far it stays; a joint or motor is named once."""

from __future__ import annotations

import json

from conftest import REPO


def show_program_tab(pg) -> None:
    if pg.page.is_visible("#tab-program"):
        pg.page.click("#tab-program")


def test_a_program_with_three_bad_lines_names_all_three_and_marks_them(open_page):
    """Before: only the first bad line was said, so a student mended one line per Run."""
    pg = open_page("mk2plus")
    show_program_tab(pg)
    pg.page.fill("#editor", "M 0 90 0\nL 7 3\nG 50\nQ 1\nM 0 90\n")
    pg.page.click("#run")
    pg.wait("document.getElementById('program-status').textContent.includes('cannot be read')")
    said = pg.page.text_content("#program-status")
    assert said.startswith("3 lines cannot be read; nothing ran."), said
    for line, what in ((2, "'L 7 3': error:6"), (4, "'Q 1': error:2"), (5, "'M 0 90': error:4")):
        assert f"line {line}: {what}" in said, said
    marked = pg.page.eval_on_selector_all("#gutter .refused", "els => els.map(e => e.textContent)")
    assert marked == ["2", "4", "5"], marked
    # mended, the marks go with the text that had them
    pg.page.fill("#editor", "M 0 90 0\nL 0 3\nG 50\nM 0 90 -80\n")
    assert pg.page.eval_on_selector_all("#gutter .refused", "els => els.length") == 0
    pg.page.click("#run")
    pg.wait("a.timeline !== null && document.getElementById('program-status').textContent.startsWith('4 commands')")
    assert pg.hook("a.pageErrors") == [] and pg.errors == []


def test_a_point_out_of_reach_says_how_far_it_stays(open_page):
    """Before: `P 400 0 100 -> error:10, target out of reach`, with no distance."""
    pg = open_page("mk2plus")
    show_program_tab(pg)
    pg.page.fill("#editor", "P 400 0 100\nP 235 0 213\n")
    pg.page.click("#run")
    pg.wait("a.timeline !== null && document.getElementById('program-status').textContent.startsWith('2 commands')")
    said = pg.page.text_content("#program-status")
    assert ("line 1: P 400 0 100 → error:10, target out of reach: nothing moves (it is farther than the arm is "
            "long; the nearest the tool comes is 63.8 mm away)") in said, said


def test_the_mearms_ik_names_what_holds_it_back_once_with_its_range(open_page):
    """Before: "held back by the limit of shoulder, shoulder, elbow" (the joint and the motor of
    one name, and no word of where or how far)."""
    pg = open_page("mearm")
    if pg.page.is_visible("#tab-ik"):
        pg.page.click("#tab-ik")
    for k, v in zip("xyz", (170, 0, 20)):
        pg.page.fill(f"#t{k}", str(v))
    pg.page.click("#solve")
    pg.wait("a.ik && a.ik.status === 'limited'")
    said = pg.page.text_content("#ik-status")
    assert said.startswith("Not reached: held back by the shoulder motor at 30.0° (its range 30° to 135°)"), said
    assert said.endswith("; the nearest the tool comes is 23.2 mm away."), said
    assert said.count("shoulder") == 1, said
    assert pg.errors == []


def test_check_says_why_an_object_is_not_in_its_place(open_page, tmp_path):
    """Issue 55, 8: Check said "161.6 mm from its place" and why the grasp failed was only in
    the event log: it now says whether the gripper held the object, where it let it go, and the
    first line the arm refused."""
    doc = json.loads((REPO / "exercises" / "pick-and-place.articula").read_text())
    doc["program"] = {"mode": "text", "name": "program.arm", "text": "G 100\nM 0 90 -60\nG 0\n", "blocks": None}
    f = tmp_path / "miss.articula"
    f.write_text(json.dumps(doc))
    pg = open_page("mk2plus")
    pg.page.click("#projects-button")
    pg.page.set_input_files("#project-file", str(f))
    pg.wait("a.project.goal !== null && a.programMode === 'text'")
    pg.page.click("#exercise-check")
    pg.wait("a.exercise !== null && a.exercise.parts.length > 0", timeout=30000)
    detail = [p for p in pg.hook("a.exercise.parts") if not p["met"]][0]["detail"]
    assert "mm from its place" in detail and "the gripper never held it" in detail, detail
    assert "line 2 was refused (error:9" in detail, detail
    assert pg.errors == []
