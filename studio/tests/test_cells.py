"""A cell of arms in the page (cells/README.md): the Physics menu's cells open a shipped cell, its arms drawn
in a colour each where the cell stands them, each on its own firmware in the page's engine; the
events name the arm; a wait ends when the other arm's output changes, as `articula sim` has it;
a deadlock is told in words; STOP pauses every arm."""

from __future__ import annotations

from conftest import SHOTS, cli_json


def test_a_cell_of_two_arms_on_two_builds_runs_and_signals(open_page):
    pg = open_page("mk2plus")
    assert "cell:signal" in pg.page.eval_on_selector_all("#scene-select option", "os => os.map(o => o.value)")
    pg.page.select_option("#scene-select", "cell:signal")
    pg.wait("a.cell.name === 'signal' && a.cell.arms.length === 2 && a.cell.frames > 0", timeout=30000)
    assert pg.hook("a.cell.arms") == ["mk2", "mearm"]
    # the meArm waits for the MK2's signal (2.65 s in): its wait ends at the first look after it
    pg.wait("a.cell.signals[1].length > 0 && a.cell.signals[1][0].end_t != null", timeout=30000)
    mk2_out, mearm_wait = pg.hook("a.cell.signals[0][0]"), pg.hook("a.cell.signals[1][0]")
    assert (mk2_out["kind"], mk2_out["name"]) == ("output", "placed")
    assert 0 <= mearm_wait["end_t"] - mk2_out["t"] <= 0.001
    # as the CLI runs it
    cli = cli_json("sim", "signal")
    arms = {a["name"]: a for a in cli["arms"]}
    assert abs(arms["mearm"]["signals"][0]["end_t"] - mearm_wait["end_t"]) < 1e-9
    # the events name the arm, in words
    pg.wait("a.cell.events.some(e => e.kind === 'grasp' && e.arm === 'mk2')")
    assert "mk2: the gripper holds" in pg.page.text_content("#events")
    pg.page.wait_for_timeout(300)
    assert pg.hook("a.armPixels()") > 0.02
    assert pg.page.is_visible("#cell-legend") and "mearm (meArm)" in pg.page.text_content("#cell-legend")
    pg.page.screenshot(path=str(SHOTS / "studio-cell-signal.png"))
    # STOP pauses every arm: the clock stands still
    pg.page.click("#stop")
    pg.wait("a.cell.running === false")
    t = pg.hook("a.cell.t")
    pg.page.wait_for_timeout(400)
    assert pg.hook("a.cell.t") == t
    # a scene closes the cell: the single arm again
    pg.page.select_option("#scene-select", "push")
    pg.wait("a.cell.name === null && a.physics && a.physics.on")
    assert pg.errors == []


def test_a_deadlock_in_a_cell_is_told_in_words(open_page):
    pg = open_page("mk2plus")
    pg.page.select_option("#scene-select", "cell:shared-zone-deadlock")
    pg.wait("a.cell.name === 'shared-zone-deadlock' && a.cell.deadlock !== ''", timeout=30000)
    words = "left waits for `done` from right (low), which waits for `done` from left (low)"
    assert pg.hook("a.cell.deadlock") == words
    pg.wait("document.querySelector('#view-status').textContent.includes('stuck')")
    assert words in pg.page.text_content("#view-status")
    assert "the arms wait for each other" in pg.page.text_content("#events")
    pg.page.screenshot(path=str(SHOTS / "studio-cell-deadlock.png"))
    assert pg.errors == []
