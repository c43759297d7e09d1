"""A cell of arms in the page (cells/README.md): the Physics menu's cells open a shipped cell, its arms drawn
in a colour each where the cell stands them, each on its own firmware in the page's engine; the
events name the arm; a wait ends when the other arm's output changes, as `articula sim` has it;
a deadlock is told in words; STOP pauses every arm."""

from __future__ import annotations

import subprocess
from pathlib import Path

from conftest import SHOTS, cli_json, cli_path


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


def test_a_belt_and_a_light_barrier_on_the_arms_wires_in_the_page(open_page):
    """cells/conveyor.json in the page: the MK2 runs the belt through its relay, the block breaks
    the barrier's beam, the arm's wait ends there and stops the belt, and the arm picks the block
    off it; each device's change in words, at the CLI's times."""
    pg = open_page("mk2plus")
    pg.page.select_option("#scene-select", "cell:conveyor")
    pg.wait("a.cell.name === 'conveyor' && a.cell.frames > 0", timeout=30000)
    # the timeline's wait on the barrier: the prediction cannot know its end (drawn so, and said)
    assert pg.page.locator("#cell-timeline rect.wait.unknown").count() == 1
    assert "? gate.beam" in pg.page.text_content("#cell-timeline")
    assert pg.hook("a.cell.arrows") == 0
    # the arm's wait (W on the barrier's input) ends once the block breaks the beam
    pg.wait("a.cell.signals[0].length > 1 && a.cell.signals[0][1].end_t != null", timeout=60000)
    devices = pg.hook("a.cell.events.filter(e => e.kind === 'device').map(e => [e.a, e.b, e.detail, e.t])")
    assert [d[:3] for d in devices[:3]] == [["conveyor", "", "runs"], ["gate", "block", "the beam is broken"],
                                           ["conveyor", "", "stands"]], devices
    wait = pg.hook("a.cell.signals[0][1]")
    assert 0 <= wait["end_t"] - devices[1][3] <= 0.002, (wait, devices)
    # as the CLI runs it
    cli = [e for e in cli_json("sim", "conveyor")["events"] if e["kind"] == "device"]
    assert [(e["a"], e["detail"], round(e["t"], 6)) for e in cli[:3]] == [(d[0], d[2], round(d[3], 6)) for d in devices[:3]]
    text = pg.page.text_content("#events")
    assert 'the belt "conveyor" runs' in text and '"block" breaks the beam of "gate"' in text
    pg.page.screenshot(path=str(SHOTS / "studio-cell-conveyor.png"))
    # then the arm picks the block off the belt
    pg.wait("a.cell.events.some(e => e.kind === 'grasp' && e.b === 'block')", timeout=60000)
    # the table's mat to print: the file the CLI writes (articula mat conveyor)
    with pg.page.expect_download() as got:
        pg.page.click("#cell-mat")
    assert got.value.suggested_filename == "conveyor-mat.svg"
    mat = Path(got.value.path()).read_text()
    cli = subprocess.run([cli_path(), "mat", "conveyor"], capture_output=True, text=True, timeout=60)
    assert cli.returncode == 0 and mat == cli.stdout
    assert "gate: light barrier, 10 mm up" in mat and 'width="' in mat
    assert pg.errors == []


def test_the_station_feeds_its_first_block_onto_the_belt_in_the_page(open_page):
    """cells/station.json in the page: the feeder puts out the first block at once (the arm's
    output falls), the belt brings it, as the CLI runs it; the feeder's other blocks are out of
    the world, and not drawn, until it puts them out."""
    pg = open_page("mk2plus")
    pg.page.select_option("#scene-select", "cell:station")
    pg.wait("a.cell.name === 'station' && a.cell.frames > 0", timeout=30000)
    pg.wait("a.cell.events.some(e => e.kind === 'device' && e.a === 'gate' && e.b === 'block1')", timeout=60000)
    devices = pg.hook("a.cell.events.filter(e => e.kind === 'device').map(e => [e.a, e.b, e.detail, e.t])")
    cli = [e for e in cli_json("sim", "station")["events"] if e["kind"] == "device"]
    assert [(d[0], d[1], d[2], round(d[3], 6)) for d in devices] == [(e["a"], e["b"], e["detail"], round(e["t"], 6)) for e in cli[:len(devices)]]
    assert 'the feeder "feeder" puts out "block1"' in pg.page.text_content("#events")
    assert pg.hook("a.objectScreen('block1')") is not None and pg.hook("a.objectScreen('block2')") is None
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


def test_each_arm_has_its_program_in_a_tab_and_run_all_runs_them(open_page):
    import json

    from conftest import REPO

    pg = open_page("mk2plus")
    pg.page.select_option("#scene-select", "cell:signal")
    pg.wait("a.cell.name === 'signal' && a.cell.frames > 0", timeout=30000)
    # the cell's panels take the one robot's: its arms, their programs, the timeline
    assert pg.page.is_visible("#cell-section") and pg.page.is_visible("#cell-arms-section")
    assert not pg.page.is_visible("#ik-section") and not pg.page.is_visible("#program-section")
    assert pg.page.eval_on_selector_all("#cell-tabs button", "bs => bs.map(b => b.textContent)") == ["mk2", "mearm"]
    shipped = json.loads((REPO / "cells" / "signal.json").read_text())["arms"]
    assert pg.page.input_value("#cell-program").split("\n") == shipped[0]["program"]
    pg.page.click("#cell-tabs button >> nth=1")
    assert pg.page.input_value("#cell-program").split("\n") == shipped[1]["program"]
    assert "mk2.placed – mearm.go" in pg.page.text_content("#cell-wires")
    # the timeline: each arm's lines as its own firmware runs them in the cell (the CLI's
    # prediction in the cell, line for line), and an arrow from the MK2's output to the wait it ends
    for k, arm in enumerate(["mk2", "mearm"]):
        cli = [(r["line"], r["command"], round(r["start_s"], 6), round(r["end_s"], 6))
               for r in cli_json("predict", "signal", arm)["records"] if r["command"]]
        page = [(x["line"], x["command"], x["start_s"], x["end_s"]) for x in pg.hook(f"a.cell.timeline[{k}].lines")]
        assert page == cli
    assert pg.hook("a.cell.arrows") == 1
    assert pg.page.locator("#cell-timeline rect.wait").count() == 1
    # the arms' boxes say what each does: the meArm waits for the MK2's signal (said, and maybe
    # over already on a slow machine: the cell runs on while the CLI predicts)
    pg.wait("a.cell.said[1].some(t => t.includes('waits for go (A0) to read 0'))")
    # a line the meArm cannot run: refused by arm and line, and the cell runs on as it was
    t0 = pg.hook("a.cell.t")
    pg.page.fill("#cell-program", "W 14 0 30\nL 9 10\nG 0")
    pg.page.click("#cell-run-all")
    pg.wait("a.cell.refused !== ''")
    assert pg.hook("a.cell.refused").startswith("mearm, line 2: ")
    assert "Not run: mearm, line 2" in pg.page.text_content("#cell-program-state")
    assert pg.hook("a.cell.t") >= t0 and pg.hook("a.cell.timeline[1].lines.length") == len(shipped[1]["program"])
    assert pg.page.locator("#cell-tabs button >> nth=1").get_attribute("class") == "edited"
    # Run all with the meArm's program edited: it waves at once, without waiting for the MK2
    pg.page.fill("#cell-program", "G 100\nM 60 100 0\nG 0")
    pg.page.click("#cell-run-all")
    pg.wait("a.cell.timeline[1].lines.length === 3 && a.cell.t < 2 && a.cell.frames > 0")
    assert pg.hook("a.cell.refused") == "" and pg.hook("a.cell.arrows") == 0
    assert pg.hook("a.cell.programs[1]") == "G 100\nM 60 100 0\nG 0"
    pg.wait("a.cell.doing[1].startsWith('line ')")
    assert pg.hook("a.cell.signals[1].length") == 0  # no wait
    # STOP stops every arm
    pg.page.click("#stop")
    pg.wait("a.cell.running === false")
    # Shipped programs: every arm's as the cell comes, run from the start
    pg.page.click("#cell-revert")
    pg.wait("a.cell.timeline[1].lines.length === %d && a.cell.arrows === 1" % len(shipped[1]["program"]))
    assert pg.page.locator("#cell-tabs button.edited").count() == 0
    pg.page.click("#banner-close")  # (STOP's word)
    pg.wait("a.cell.t > 3.5")  # the meArm's wait has ended at the MK2's signal, and it waves
    pg.page.screenshot(path=str(SHOTS / "studio-cell-programs.png"))
    # a scene closes the cell: the one robot's panels again
    pg.page.select_option("#scene-select", "push")
    pg.wait("a.cell.name === null")
    assert pg.page.is_visible("#ik-section") and not pg.page.is_visible("#cell-section")
    assert pg.errors == []


def test_a_collision_between_arms_shows_on_both_links(open_page):
    """The shared zone without its wires' O and W lines: the arms meet in the zone, and the
    collision flashes the part of each arm it names."""
    import json

    from conftest import REPO

    pg = open_page("mk2plus")
    pg.page.select_option("#scene-select", "cell:shared-zone")
    pg.wait("a.cell.name === 'shared-zone' && a.cell.frames > 0", timeout=30000)
    arms = json.loads((REPO / "cells" / "shared-zone.json").read_text())["arms"]
    progs = []
    for a in arms:
        lines = a["program"] if isinstance(a["program"], list) else (REPO / "cells" / a["program"]).read_text().split("\n")
        progs.append("\n".join(x for x in lines if x.split()[:1] not in (["O"], ["W"])))
    for k, text in enumerate(progs):
        pg.page.click(f"#cell-tabs button >> nth={k}")
        pg.page.fill("#cell-program", text)
    pg.page.click("#cell-run-all")
    pg.wait("a.cell.events.some(e => e.kind === 'collision' && e.b.includes(': '))", timeout=60000)
    e = pg.hook("a.cell.events.find(e => e.kind === 'collision' && e.b.includes(': '))")
    assert {e["arm"], e["b"].split(": ")[0]} == {"left", "right"}
    flashed = pg.hook("a.cell.flashed")
    assert f"{e['arm']}: {e['a']}" in flashed and e["b"] in flashed
    other, part = e["b"].split(": ")
    assert f"{e['arm']}: the {e['a']} hits {other}'s {part}" in pg.page.text_content("#events")
    assert pg.errors == []


def test_a_cell_and_its_programs_are_kept_in_the_project_undone_and_shared_by_link(open_page, browser, site):
    from class_page import _fragment, _project
    from conftest import Page

    pg = open_page("mk2plus")
    pg.page.select_option("#scene-select", "cell:signal")
    pg.wait("a.cell.name === 'signal' && a.cell.frames > 0", timeout=30000)
    pg.wait("a.project.dirty === false", timeout=10000)
    pg.page.click("#cell-tabs button >> nth=1")
    pg.page.fill("#cell-program", "G 100\nM 60 100 0\nG 0")
    # an edit of a cell's program is a step of the History, and kept
    pg.wait("document.querySelector('#undo').title.includes(\"the cell's programs\")")
    pg.wait("a.project.saves > 0 && a.project.dirty === false", timeout=10000)
    pg.page.click("#undo")
    pg.wait("a.cell.programs[1].startsWith('W 14 0 30')", timeout=30000)
    pg.page.click("#redo")
    pg.wait("a.cell.programs[1] === 'G 100\\nM 60 100 0\\nG 0' && a.cell.timeline[1].lines.length === 3", timeout=30000)
    # shared by link: the cell opens with the edited program in its tab, and runs it
    pg.page.click("#share-button")
    pg.wait("a.shareLink !== ''")
    other = Page(browser, pg.hook("a.shareLink"), ready="window.articula.project.name.includes('from a link')")
    try:
        other.wait("a.cell.name === 'signal' && a.cell.timeline.length === 2", timeout=30000)
        assert other.hook("a.cell.programs[1]") == "G 100\nM 60 100 0\nG 0"
        assert other.hook("a.cell.timeline[1].lines.length") == 3
        assert other.page.locator("#cell-tabs button.edited").count() == 1
        assert other.errors == []
    finally:
        other.close()
    # a link's cell that is not shipped, or a program an arm cannot run, is said, and nothing runs it
    script = "<img src=x onerror=window.__pwned=1>"
    for cell, words in [({"name": script, "programs": ["G 0"]}, "no shipped cell"),
                        ({"name": "signal", "programs": ["G 100", f"L 9 10 {script}"]}, "mearm, line 1")]:
        p = Page(browser, f"{site.url}#{_fragment(_project('Cell', mode='text', cell=cell))}",
                 ready="window.articula.project.name.includes('from a link')")
        try:
            if words.startswith("no"):
                p.page.wait_for_selector("#banner:not([hidden])")
                assert words in p.page.text_content("#banner-text")
                assert p.hook("a.cell.name") is None
            else:
                p.wait("a.cell.refused !== ''", timeout=30000)
                assert p.hook("a.cell.refused").startswith(words)
                assert p.hook("a.cell.programs[1]") == f"L 9 10 {script}"  # kept in its tab, as text
                assert p.hook("a.cell.timeline[1].lines.length") == len(__import__("json").loads(
                    (__import__("conftest").REPO / "cells" / "signal.json").read_text())["arms"][1]["program"])
            assert p.page.evaluate("() => window.__pwned") is None
        finally:
            p.close()
    assert pg.errors == []


def test_a_cell_runs_on_two_virtual_nanos_wired_pin_to_pin_and_stop_stops_both(open_page):
    """Each arm's own firmware hex (the MK2's articula-nano, the meArm's articula-servo) on a
    virtual Nano of its own, configured for its arm; the MK2's output A5 drives the meArm's input
    A0, so the meArm waits for it, as in the engine; STOP sends both the realtime `!`."""
    pg = open_page("mk2plus")
    pg.page.select_option("#scene-select", "cell:signal")
    pg.wait("a.cell.name === 'signal' && a.cell.frames > 0", timeout=30000)
    pg.page.select_option("#cell-run-on", "nanos")
    pg.page.click("#cell-run-all")
    pg.wait("a.cell.nanos !== null && a.cell.nanos.arms.every(x => x.connected)", timeout=60000)
    assert pg.hook("a.cell.nanos.arms.map(x => x.error)") == ["", ""]
    # the meArm waits on line 1 (W 14 0 30) until the MK2 has set A5 low (its last line, O 19 0)
    pg.wait("a.cell.nanos.arms[1].line === 1 && a.cell.nanos.arms[0].line >= 2", timeout=30000)
    pg.wait("a.cell.nanos.arms[0].done", timeout=60000)
    # (the Nano's worker reports its pins apart from its replies: the level can come a moment
    # after the reply that ended the program)
    pg.wait("a.cell.nanos.arms[0].levels.A5 === 0 && a.cell.nanos.drives >= 2", timeout=10000)
    pg.wait("a.cell.nanos.arms[1].line >= 2", timeout=30000)
    assert pg.hook("a.cell.nanos.arms[0].error") == "" and not pg.hook("a.cell.nanos.arms[0].stopped")
    # each arm drawn where its Nano reports it
    assert pg.hook("a.cell.nanos.arms[0].reports") > 5 and pg.hook("a.cell.nanos.arms[1].reports") > 5
    assert "On virtual Nanos" in pg.page.text_content("#view-status")
    assert pg.hook("a.cell.doing[1]").startswith("line ")
    # STOP: both Nanos stop, no further line
    pg.page.click("#stop")
    pg.wait("a.cell.nanos.arms.every(x => x.done)", timeout=30000)
    assert pg.hook("a.cell.nanos.arms[1].stopped") is True and pg.hook("a.cell.nanos.stops") == 1
    line = pg.hook("a.cell.nanos.arms[1].line")
    pg.page.wait_for_timeout(500)
    assert pg.hook("a.cell.nanos.arms[1].line") == line
    rtf = pg.hook("a.cell.nanos.arms.map(x => x.rtf)")
    assert all(r is not None and r > 0.5 for r in rtf), rtf
    # back to the engine: the Nanos are let go
    pg.page.select_option("#cell-run-on", "engine")
    pg.wait("a.cell.nanos === null")
    assert pg.errors == [] and pg.hook("a.pageErrors") == []


def test_the_cell_exercises_are_not_met_as_given_and_met_once_solved(open_page):
    """Each cell lesson ships as an exercise (exercises/*.articula with a cell): opened, its cell
    runs the programs given; Check says which part fails and why; the shipped cell's own
    programs solve it."""
    import json

    from conftest import REPO

    def programs(cell):
        return ["\n".join(a["program"]) for a in json.loads((REPO / "cells" / f"{cell}.json").read_text())["arms"]]

    cases = [
        ("take-turns-in-the-shared-zone.articula", "shared-zone", [
            (False, "stuck at 4.1 s: left waits for `done` from right (low), which waits for `done` from left (low)"), (True, "no collision")]),
        ("hand-the-block-over.articula", "handover", [(False, "mm from its place"), (True, "no collision")]),
        ("stop-the-belt-at-the-barrier.articula", "conveyor", [(False, "never waits for `part`"), (False, "mm from its place"),
                                                              (True, "no collision")]),
        ("wait-for-the-mk2.articula", "signal", [(False, "never waits for `go`"), (True, ""), (True, "no collision")]),
    ]
    pg = open_page("mk2plus")
    for name, solved_by, given in cases:
        doc = json.loads((REPO / "exercises" / name).read_text())
        pg.page.click("#projects-button")
        pg.page.select_option("#exercise-select", name)
        pg.wait(f"a.project.goal !== null && a.project.goal.title === {json.dumps(doc['goal']['title'])} && "
                f"a.cell.name === {json.dumps(doc['cell']['name'])} && a.cell.frames > 0", timeout=30000)
        assert pg.hook("a.cell.programs") == doc["cell"]["programs"]
        assert pg.page.is_visible("#exercise-check")  # (in the cell's panel: the program's is hidden)
        assert not pg.page.is_visible("#cell-revert")  # (the cell's own programs would be the answer)
        prev = pg.hook("JSON.stringify(a.exercise)")  # (the last exercise's verdict, if any)
        pg.page.click("#exercise-check")
        pg.wait(f"a.exercise !== null && a.exercise.parts.length > 0 && JSON.stringify(a.exercise) !== {json.dumps(prev)}", timeout=60000)
        parts = pg.hook("a.exercise.parts")
        assert [p["met"] for p in parts] == [m for m, _ in given], (name, parts)
        for p, (_, words) in zip(parts, given):
            assert words in p["detail"], (name, p)
        # the shipped cell's programs, typed into the tabs, solve it
        for k, text in enumerate(programs(solved_by)):
            pg.page.click(f"#cell-tabs button >> nth={k}")
            pg.page.fill("#cell-program", text)
        prev = pg.hook("JSON.stringify(a.exercise)")
        pg.page.click("#exercise-check")
        pg.wait(f"JSON.stringify(a.exercise) !== {json.dumps(prev)}", timeout=60000)
        assert pg.hook("a.exercise.met") is True, (name, pg.hook("a.exercise"))
    pg.page.screenshot(path=str(SHOTS / "studio-cell-exercise.png"))
    assert pg.errors == [] and pg.hook("a.pageErrors") == []
