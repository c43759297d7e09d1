"""Surprises a class met (issue 55, item 7), named after what a student saw: a pick and place run
on the virtual Nano left pen ink on the floor (the default pen and paper counted though no one
had chosen to draw), and with a pen held the IK aimed the pen's tip without saying so."""

from __future__ import annotations

from test_studio import _connect_page_nano


def _on_the_virtual_nano(pg):
    """The page connected to its virtual Nano, the Program panel in sight."""
    pg.page.click("#tab-arm") if pg.page.is_visible("#tab-arm") else None
    _connect_page_nano(pg)
    pg.page.click("#tab-program") if pg.page.is_visible("#tab-program") else None
    return pg


def test_a_pick_and_place_on_the_virtual_nano_leaves_no_ink(open_page):
    pg = _on_the_virtual_nano(open_page("mk2plus"))
    # down low (the tool about 60 mm above the floor: a 120 mm pen's tip would be in it) and back
    pg.page.fill("#editor", "G 100\nM 0 50 -40\nG 0\nM 0 75 -20\n")
    pg.page.check("#drive-arm")
    pg.page.click("#run")
    pg.wait("a.arm.programDone === true || a.arm.error !== ''", timeout=90000)
    assert pg.hook("a.arm.error") == ""
    pg.page.wait_for_timeout(600)  # (the ink is asked for at most every 250 ms)
    assert pg.hook("a.paper.ink.points") == 0 and pg.hook("a.paper.ink.received") == 0
    assert pg.page.locator("#paper-view #ink polyline").count() == 0
    assert pg.errors == []


def test_with_a_pen_held_the_ik_says_it_aims_the_pens_tip(open_page):
    pg = open_page("mk2plus")
    pg.page.click("#tab-ik") if pg.page.is_visible("#tab-ik") else None
    for k, v in zip("xyz", (250, 0, 150)):
        pg.page.fill(f"#t{k}", str(v))
    pg.page.click("#solve")
    pg.wait("a.ik && a.ik.status === 'reached'")
    assert pg.page.text_content("#ik-status").startswith("Reached"), pg.page.text_content("#ik-status")
    # the paper panel used: a pen in the gripper
    pg.page.click("#tab-program") if pg.page.is_visible("#tab-program") else None
    pg.page.locator("#draw-section").scroll_into_view_if_needed()
    pg.page.fill("#draw-z", "10")
    pg.page.dispatch_event("#draw-z", "change")
    pg.page.click("#tab-ik") if pg.page.is_visible("#tab-ik") else None
    pg.page.fill("#tz", "20")
    pg.page.click("#solve")
    pg.wait("a.ik && a.ik.pen_mm === 120")
    said = pg.page.text_content("#ik-status")
    assert said.startswith("The pen's tip (120 mm below the tool point) is the target. Reached"), said
    assert pg.errors == []


def test_a_program_run_on_the_virtual_nano_plots_its_prediction_and_says_how_long_it_took(open_page):
    """Issue 55, 6: after a run on the virtual Nano, Plots still said "Run a program to see...",
    and nothing said that a run sent line by line takes longer than the prediction."""
    pg = _on_the_virtual_nano(open_page("mk2plus"))
    pg.page.fill("#editor", "L 0 10\nL 0 -10\n")
    pg.page.click("#run")
    pg.wait("a.arm.programDone === true", timeout=60000)
    said = pg.page.text_content("#program-status")
    assert "all accepted in " in said and "s of the arm's time (the model: " in said, said
    assert "Run a program to see" not in pg.page.text_content("#plots")
    assert pg.errors == []


BOX = "a.physics.objects.find(o => o.name === 'box').pose"


def test_an_object_dragged_by_hand_stays_there_at_run_and_reset_puts_it_back(open_page):
    """Issue 55, 3: a block dragged closer to the arm went back to its place at Run. Run starts
    the world again from power-up with each object where the student let go of it; Reset puts
    every object back where the scene has it."""
    pg = open_page("mk2plus", query="&scene=push")
    pg.wait("a.physics && a.physics.on && a.physics.objects.length > 0")
    pg.wait(f"Math.abs({BOX}[11] - 40) < 1.5", timeout=20000)
    x0, y0 = pg.hook(f"[{BOX}[3], {BOX}[7]]")
    x, y = pg.hook("a.objectScreen('box')")
    pg.page.mouse.move(x, y)
    pg.page.mouse.down()
    for k in range(1, 16):
        pg.page.mouse.move(x - 8 * k, y - 2 * k)
        pg.page.wait_for_timeout(30)
    pg.wait(f"Math.hypot({BOX}[3] - {x0}, {BOX}[7] - {y0}) > 40", timeout=15000)
    pg.page.mouse.up()
    # let go: it comes to rest on the ground, somewhere else
    pg.wait(f"Math.abs({BOX}[11] - 40) < 1.5 && Math.abs({BOX}[10] - 1) < 0.01", timeout=20000)
    pg.page.wait_for_timeout(500)
    x1, y1 = pg.hook(f"[{BOX}[3], {BOX}[7]]")
    assert ((x1 - x0) ** 2 + (y1 - y0) ** 2) ** 0.5 > 40
    # Run (a program that leaves the box alone): the world from power-up, the box where it was
    # let go; it falls from there again, from rest this time, to within a few mm of before
    pg.page.click("#tab-program") if pg.page.is_visible("#tab-program") else None
    pg.page.fill("#editor", "D 1\n")
    t = pg.hook("a.physics.t")
    pg.page.click("#run")
    pg.wait(f"a.physics.t < {t} && a.physics.t > 0.8", timeout=20000)
    x2, y2 = pg.hook(f"[{BOX}[3], {BOX}[7]]")
    assert ((x2 - x1) ** 2 + (y2 - y1) ** 2) ** 0.5 < 10, ((x1, y1), (x2, y2))
    assert ((x2 - x0) ** 2 + (y2 - y0) ** 2) ** 0.5 > 30, ((x0, y0), (x2, y2))
    # Reset: where the scene has it
    pg.page.click("#phys-reset")
    pg.wait(f"Math.hypot({BOX}[3] - {x0}, {BOX}[7] - {y0}) < 2", timeout=20000)
    assert pg.errors == []
