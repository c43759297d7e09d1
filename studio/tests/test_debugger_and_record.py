"""Issue 55, item 10: the debugger (breakpoints on line numbers, Run to caret, Pause, Step, a
watch and a time line to scrub) on the model, the live physics and the virtual Nano, and Record
(the pose as M, P, T or G, a named waypoint a function in blocks) that replays to the same steps."""

from __future__ import annotations

import json

from conftest import SHOTS, cli_json

FOUR = "L 0 10\nL 0 10\nL 0 10\nL 0 10\n"


def _tab(pg, name):
    if pg.page.is_visible(f"#tab-{name}"):
        pg.page.click(f"#tab-{name}")


def _caret_on_line(pg, line):
    pg.page.evaluate("""(n) => { const ed = document.querySelector('#editor'); const lines = ed.value.split('\\n');
        const at = lines.slice(0, n - 1).join('\\n').length + (n > 1 ? 1 : 0); ed.focus(); ed.setSelectionRange(at, at); }""", line)


def test_a_breakpoint_pauses_the_model_after_its_line_step_goes_one_line_and_the_time_line_scrubs(open_page):
    pg = open_page("mk2plus")
    _tab(pg, "program")
    pg.page.fill("#editor", FOUR)
    pg.page.click("#gutter > div:nth-child(2)")  # a breakpoint on line 2
    pg.wait("a.debug.breaks.length === 1 && a.debug.breaks[0] === 2")
    assert "break" in pg.page.get_attribute("#gutter > div:nth-child(2)", "class")
    pg.page.click("#run")
    pg.wait("a.debug.pausedAt === 2", timeout=30000)
    # at rest after line 2: the base turned 20 degrees (64 whole steps: 19.95 degrees)
    assert abs(pg.hook("a.pose.q[0]") - 20) < 0.1
    assert "Paused after line 2" in pg.page.text_content("#program-status")
    watch = pg.hook("a.debug.watch")
    assert watch["joints"].startswith("19.9") and watch["line"].startswith("2"), watch
    pg.page.locator("#watch").scroll_into_view_if_needed()
    pg.page.screenshot(path=str(SHOTS / "studio-debugger.png"))
    pg.page.click("#step")
    pg.wait("Math.abs(a.pose.q[0] - 30) < 0.2")
    # Run goes on to the end (no breakpoint ahead)
    pg.page.click("#run")
    pg.wait("Math.abs(a.pose.q[0] - 40) < 0.2", timeout=30000)
    # the time line: back to its start, the first line highlighted
    pg.page.locator("#scrub").fill("0")
    pg.wait("Math.abs(a.pose.q[0]) < 1e-6")
    # Run to caret: line 3, though its only breakpoint is line 2, taken off with F9 on it
    _caret_on_line(pg, 2)
    pg.page.keyboard.press("F9")
    pg.wait("a.debug.breaks.length === 0")
    _caret_on_line(pg, 3)
    pg.page.click("#run-to")
    pg.wait("a.debug.pausedAt === 3", timeout=30000)
    assert abs(pg.hook("a.pose.q[0]") - 30) < 0.2
    assert pg.errors == []


def test_a_breakpoint_pauses_the_live_physics_after_its_line(open_page):
    pg = open_page("mk2plus")
    pg.page.select_option("#physics", "ground") if pg.page.locator("#physics option[value='ground']").count() else None
    _tab(pg, "program")
    pg.page.fill("#editor", FOUR)
    pg.page.click("#gutter > div:nth-child(1)")
    pg.page.click("#run")
    pg.wait("a.debug.pausedAt === 1", timeout=60000)
    paused = pg.hook("a.pose.q[0]")
    assert 9 < paused < 14, paused  # line 1 done (10 degrees), line 2 begun by at most a frame
    pg.page.wait_for_timeout(500)
    assert pg.hook("a.pose.q[0]") == paused, "the world went on while paused"
    assert pg.errors == []


def _predicted_base_steps(program: str, tmp_path) -> list[int]:
    """The base motor's steps after each line, as `articula predict` (the firmware on the host) says."""
    f = tmp_path / "program.arm"
    f.write_text(program)
    return [r["steps"][0] for r in cli_json("predict", "mk2plus", str(f))["records"]]


def test_a_breakpoint_stops_the_virtual_nano_at_rest_after_its_line_and_step_goes_one_line(open_page, tmp_path):
    one, two, three = _predicted_base_steps("L 0 10\nL 0 10\nL 0 10\n", tmp_path)
    pg = open_page("mk2plus")
    _tab(pg, "arm")
    pg.page.select_option("#arm-port", "page:virtual")
    pg.page.click("#arm-connect")
    pg.wait("a.arm.connected && a.arm.status !== null", timeout=60000)
    _tab(pg, "program")
    pg.page.fill("#editor", "L 0 10\nL 0 10\nL 0 10\n")
    pg.page.click("#gutter > div:nth-child(1)")
    pg.page.check("#drive-arm")
    pg.page.click("#run")
    pg.wait(f"a.arm.pausedAt === 1 && a.arm.status.state === 'Idle' && a.arm.status.steps[0] === {one}", timeout=60000)
    pg.page.wait_for_timeout(700)
    assert pg.hook("a.arm.status.steps[0]") == one and pg.hook("a.arm.programLines.length") == 1, "it went on past the breakpoint"
    assert "the arm" in pg.hook("a.debug.watch"), pg.hook("a.debug.watch")
    pg.page.click("#step")
    pg.wait(f"a.arm.pausedAt === 2 && a.arm.status.state === 'Idle' && a.arm.status.steps[0] === {two}", timeout=60000)
    pg.page.click("#run")
    pg.wait("a.arm.programDone === true", timeout=60000)
    pg.wait(f"a.arm.status.state === 'Idle' && a.arm.status.steps[0] === {three}", timeout=30000)
    assert pg.hook("a.arm.error") == ""
    pg.wait(f"a.arm.nano !== null && a.arm.nano.steps[0] === {three} && a.arm.nano.faults === 0", timeout=30000)
    assert pg.errors == []


def test_a_recorded_waypoint_replays_to_the_same_steps_on_the_virtual_nano(open_page):
    pg = open_page("mk2plus")
    _tab(pg, "arm")
    pg.page.select_option("#arm-port", "page:virtual")
    pg.page.click("#arm-connect")
    pg.wait("a.arm.connected && a.arm.status !== null", timeout=60000)
    # jogged to a pose no round number names: 1 degree asked, three times
    _tab(pg, "joints")
    pg.page.select_option("#jog-frame", "joint")
    for i in range(3):
        pg.page.click("[aria-label='base plus']")
        pg.wait(f"a.arm.reply && a.arm.reply.reply === 'ok' && a.jog.jogs === {i + 1}", timeout=30000)
        pg.wait("a.arm.status.state === 'Idle'", timeout=30000)
    pg.page.wait_for_timeout(300)
    steps = pg.hook("a.arm.status.steps")
    # the taps add up (each from the last one's target): 3 degrees, in whole steps, as predicted
    assert steps == pg.hook("a.arm.reply.predicted.steps"), steps
    assert abs(pg.hook("a.arm.status.angles[0]") - 3) < 0.35, pg.hook("a.arm.status.angles")
    _tab(pg, "program")
    pg.page.fill("#editor", "")
    pg.page.fill("#record-name", "spot")
    pg.page.click("#teach")
    pg.wait("a.teach !== ''")
    line = pg.page.input_value("#editor").strip()
    assert line.startswith("M ") and line.endswith("# spot"), line
    # away, then the recorded line: the same steps
    _tab(pg, "arm")
    pg.page.fill("#arm-line", "L 0 20")
    pg.page.click("#arm-send")
    pg.wait("a.arm.reply && a.arm.reply.line === 'L 0 20' && a.arm.status.state === 'Idle' && "
            "a.arm.status.steps[0] === a.arm.reply.predicted.steps[0]", timeout=30000)
    assert pg.hook("a.arm.status.steps[0]") > steps[0] + 60
    pg.page.fill("#arm-line", line)
    pg.page.click("#arm-send")
    pg.wait(f"a.arm.reply.line === {line!r} && a.arm.reply.reply === 'ok'", timeout=30000)
    recorded = json.dumps(steps, separators=(",", ":"))
    pg.wait(f"a.arm.status.state === 'Idle' && JSON.stringify(a.arm.status.steps) === '{recorded}'", timeout=30000)
    # the tool point (P), a straight line (T) and the gripper (G), each a line
    _tab(pg, "program")
    for kind, word in (("P", "P "), ("T", "T "), ("G", "G ")):
        pg.page.select_option("#record-as", kind)
        pg.page.click("#teach")
        pg.wait(f"document.querySelector('#editor').value.trim().split('\\n').pop().startsWith({word!r})")
    assert pg.errors == []


def test_a_named_waypoint_becomes_a_function_to_call_again_in_blocks(open_page):
    pg = open_page("mk2plus")
    _tab(pg, "program")
    pg.page.click("#mode-blocks")
    pg.wait("a.programMode === 'blocks'")
    pg.page.fill("#record-name", "above the box")
    pg.page.click("#teach")
    pg.wait("a.blocksCode && a.blocksCode.text.includes('M ')", timeout=20000)
    doc = pg.page.evaluate("() => window.articula.project")
    names = [t.replace("\xa0", " ") for t in pg.page.evaluate("""() => [...document.querySelectorAll('#blockly .blocklyText')].map((e) => e.textContent)""")]
    # the function "to above the box" holds the joints; the program calls it
    pg.page.screenshot(path=str(SHOTS / "studio-record-blocks.png"))
    assert names.count("above the box") == 2 and "to" in names and "move every joint to" in names, names
    assert pg.hook("a.blockStacks") == 1, doc
    assert pg.errors == []
