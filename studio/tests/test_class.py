"""A studio for a class (issue 21): programs in blocks, projects kept in the browser, links that
carry them, exercises the page checks. The real page, from the static site, in Chromium; the
blocks are dragged from the toolbox with the mouse and their numbers typed, as a student does."""

from __future__ import annotations

import base64
import json
import random
import subprocess
import zlib
from pathlib import Path

import pytest

from conftest import PATIENCE, REPO, SHOTS, Page, cli_json
from test_studio import _connect_page_nano

SOLUTION = [  # pick and place: the thesis's Fig. 20 (programs/grasp-and-lift.arm) in the sliders' values
    ("Gripper", "arm_gripper_open", None),
    ("Move", "arm_joints", "0, 75, -95"),
    ("Move", "arm_joints", "0, 50, -90"),
    ("Gripper", "arm_gripper_close", None),
    ("Move", "arm_joints", "0, 75, -95"),
    ("Move", "arm_joints", "40, 75, -95"),
    ("Gripper", "arm_gripper_open", None),
]
WIP = pytest.mark.skip(reason="issue 21, not finished: this test fails today (see the issue's note); it is the acceptance to meet")


TOP = "#blockly svg.blocklySvg > g.blocklyWorkspace > g.blocklyBlockCanvas > g[data-id]"


def _blocks(pg):
    pg.page.click("#tab-program") if pg.page.is_visible("#tab-program") else None
    pg.page.click("#mode-blocks")
    pg.page.wait_for_selector("#blockly .blocklyToolbox")


def _block_rect(page, where: str, kind_or_id: str, by_type=False):
    """The outline of a block once it has stopped moving: [x, y, width, height]."""
    sel = f"g.{kind_or_id}[data-id]" if by_type else f"g[data-id='{kind_or_id}']"
    return page.evaluate("""([where, sel]) => new Promise((resolve) => {
        let last = "", same = 0;
        const look = () => {
          const g = document.querySelector(`#blockly svg.${where} ${sel}`);
          const p = g && [...g.children].find(c => c.classList.contains('blocklyPath'));
          const r = p ? p.getBoundingClientRect() : null;
          const now = r ? JSON.stringify([r.x, r.y, r.width, r.height]) : "";
          same = now && now === last ? same + 1 : 0;
          last = now;
          if (same >= 6) resolve(JSON.parse(now)); else requestAnimationFrame(look);
        };
        look();
      })""", [where, sel])


def _drag_block(pg, category: str, kind: str, below: str | None) -> str:
    """Drags the toolbox's block of type `kind` under block `below` (or into the workspace's
    top left): returns the new block's id."""
    page = pg.page
    shown = (f"() => {{ const f = document.querySelector('#blockly svg.blocklyToolboxFlyout'); "
             f"return f && getComputedStyle(f).display !== 'none' && f.querySelector('g.{kind}[data-id]') !== null; }}")
    new: list[str] = []
    for _ in range(3):  # a busy machine can turn a drag into a click: then again
        before = set(page.eval_on_selector_all(f"#blockly svg.blocklySvg g.{kind}[data-id]", "gs => gs.map(g => g.dataset.id)"))
        for _ in range(3):  # a click on an open category closes it
            page.click(f"#blockly .blocklyToolboxCategory:has-text('{category}')")
            try:
                page.wait_for_function(shown, timeout=3000)
                break
            except Exception:
                continue
        sx, sy, _, _ = _block_rect(page, "blocklyToolboxFlyout", kind, by_type=True)
        if below:  # the block's own outline (its group also holds the blocks under it)
            x, y, _, height = _block_rect(page, "blocklySvg", below)
            tx, ty = x + 2, y + height + 2  # just under it: its own next connection is the nearest
        else:
            tb = page.locator("#blockly .blocklyToolbox").bounding_box()
            tx, ty = tb["x"] + tb["width"] + 14, tb["y"] + 24
        page.mouse.move(sx + 6, sy + 8)
        page.mouse.down()
        page.mouse.move(sx + 40, sy + 30, steps=4)
        page.mouse.move(tx + 6, ty + 8, steps=8)
        page.mouse.up()
        after = page.eval_on_selector_all(f"#blockly svg.blocklySvg g.{kind}[data-id]", "gs => gs.map(g => g.dataset.id)")
        new = [i for i in after if i not in before]
        if new:
            break
    assert len(new) == 1, (kind, new)
    # a drop a few pixels off leaves the block beside the stack: picked up and dropped again
    # (the test's aim, not the page, is what misses)
    for _ in range(3):
        try:
            pg.wait("a.blockStacks === 1", timeout=500)
            break
        except Exception:
            if not below:
                break
            x, y, _, _ = _block_rect(page, "blocklySvg", new[0])
            bx, by, _, bh = _block_rect(page, "blocklySvg", below)
            page.mouse.move(x + 6, y + 8)
            page.mouse.down()
            page.mouse.move(x + 30, y + 30, steps=4)
            page.mouse.move(bx + 8, by + bh + 6, steps=8)
            page.mouse.up()
    pg.wait("a.blockStacks === 1 && !a.blocksPending", timeout=5000)
    # whether it snapped under `below` shows in the program it makes (the callers check it)
    return new[0]


def _type_field(pg, block: str, text: str):
    """Clicks the block's text field, as a student does, and types `text` into it."""
    page = pg.page
    # where the field is once the block has settled (a dropped block moves as it snaps)
    xy = page.evaluate("""(id) => new Promise((resolve) => {
        let last = null, same = 0;
        const look = () => {
          const f = [...document.querySelectorAll('#blockly svg.blocklySvg .blocklyEditableField')]
            .filter(x => x.closest('g[data-id]').dataset.id === id).map(x => x.getBoundingClientRect()).find(r => r.width > 0);
          const now = f ? [f.x + f.width / 2, f.y + f.height / 2] : null;
          same = now && last && now[0] === last[0] && now[1] === last[1] ? same + 1 : 0;
          last = now;
          if (same >= 5) resolve(now); else requestAnimationFrame(look);
        };
        look();
      })""", block)
    page.mouse.click(xy[0], xy[1])
    page.wait_for_selector(".blocklyHtmlInput", timeout=10000)
    page.keyboard.press("Control+a")
    page.keyboard.type(text)
    page.keyboard.press("Enter")
    page.wait_for_selector(".blocklyHtmlInput", state="detached", timeout=10000)


def _chain(kinds) -> dict:
    """Blockly's JSON of one stack of blocks: (type, the joints' values or None)."""
    blocks = []
    for i, (kind, value) in enumerate(kinds):
        b = {"type": kind, "id": f"b{i}"}
        if value is not None:
            b["fields"] = {"VALUES": value}
        blocks.append(b)
    for a, b in zip(blocks[:-1], blocks[1:]):
        a["next"] = {"block": b}
    blocks[0].update(x=20, y=20)
    return {"blocks": {"languageVersion": 0, "blocks": [blocks[0]]}}


def _open_project(pg, tmp_path, doc, name="p.articula"):
    f = tmp_path / name
    f.write_text(json.dumps(doc))
    pg.page.click("#projects-button")
    pg.page.set_input_files("#project-file", str(f))


def _build_solution(pg):
    """The solution from blocks alone: each dragged from the toolbox under the last, its
    numbers typed."""
    last = None
    for n, (category, kind, value) in enumerate(SOLUTION, 1):
        last = _drag_block(pg, category, kind, last)
        if value:
            _type_field(pg, last, value)
        # it joined the stack: the program has one more command
        pg.wait(f"!a.blocksPending && a.blocksCode && a.blocksCode.text.split('\\n').filter(l => /^[A-Z]/.test(l)).length === {n}", timeout=10000)
    pg.wait("a.blocksCode && a.blocksCode.text.split('\\n').filter(l => /^[A-Z]/.test(l)).length === 7")


def test_a_pick_and_place_from_blocks_in_physics_on_the_nano_after_a_reload_and_by_link(open_page, browser, site, tmp_path):
    """The issue's 'done when', steps 1 to 5, in Chromium."""
    pg = open_page("mk2plus", width=1366, height=768)
    # 5 (first): the shipped exercise, opened from the projects
    pg.page.click("#projects-button")
    pg.page.select_option("#exercise-select", "pick-and-place.articula")
    pg.wait("a.project.goal !== null && a.scene && a.scene.name === 'grasp-and-lift'")
    assert pg.hook("a.project.name") == "Exercise: pick and place the block"
    _blocks(pg)
    # 1: the program from blocks alone, dragged from the toolbox, their numbers typed
    _build_solution(pg)
    lines = [l for l in pg.hook("a.blocksCode.text").splitlines() if l and not l.startswith("#")]
    assert lines == ["G 100", "M 0 75 -20", "M 0 50 -40", "G 0", "M 0 75 -20", "M 40 75 -20", "G 100"]
    pg.page.screenshot(path=str(SHOTS / "studio-blocks.png"))
    # 5: Check runs it in the physics: the block ends in its place
    pg.page.click("#exercise-check")
    pg.wait("a.exercise !== null", timeout=30000)
    assert pg.hook("a.exercise.met") is True, pg.hook("a.exercise")
    assert "in place" in pg.page.text_content("#exercise-result")
    pg.page.screenshot(path=str(SHOTS / "studio-exercise.png"))
    # 2: watched in the live physics (the scene is on): it carries the block, and the running
    # line's block lights up
    pg.page.click("#run")
    pg.wait("a.runningBlock !== ''", timeout=20000)
    pg.wait("a.events.some(e => e.kind === 'release')", timeout=40000)
    assert pg.hook("a.events.some(e => e.kind === 'grasp')")
    pg.page.screenshot(path=str(SHOTS / "studio-class-physics.png"))
    # ... then on the virtual Nano, to the steps the prediction gives
    pg.page.select_option("#scene-select", value="")
    pg.wait("!a.physics || !a.physics.on")
    pg.page.click("#tab-arm")
    _connect_page_nano(pg)
    pg.page.click("#tab-program")
    pg.page.check("#drive-arm")
    pg.page.click("#run")
    pg.wait("a.arm.programDone === true", timeout=60000)
    text = pg.hook("a.blocksCode.text")
    prog = REPO / "build" / "class-solution.arm"
    prog.write_text(text)
    want = cli_json("predict", "mk2plus", str(prog))["records"][-1]["steps"]
    pg.wait(f"a.arm.status.state === 'Idle' && JSON.stringify(a.arm.status.steps) === '{json.dumps(want, separators=(',', ':'))}'",
            timeout=30000)
    assert all(r == "ok" for _, r in pg.hook("a.arm.programLines"))
    pg.page.screenshot(path=str(SHOTS / "studio-class-nano.png"))
    # 3: a reload brings it all back, the camera too (turned with the keyboard first)
    pg.page.evaluate("() => document.activeElement && document.activeElement.blur()")
    for _ in range(4):
        pg.page.keyboard.press("ArrowLeft")
    view = pg.hook("a.viewpoint()")
    pg.wait("a.project.dirty === false && a.project.saves > 0", timeout=5000)
    pg.page.wait_for_timeout(800)
    pg.wait("a.project.dirty === false", timeout=5000)
    blocks_before = pg.hook("JSON.stringify(a.project.blocks.blocks)")
    pg.page.reload()
    pg.page.wait_for_function("() => window.articula && window.articula.ready && window.articula.project.name !== ''",
                              timeout=20000 * PATIENCE)
    pg.wait("a.programMode === 'blocks' && a.blocksCode !== null", timeout=20000)
    assert pg.hook("a.project.name") == "Exercise: pick and place the block"
    assert pg.hook("a.blocksCode.text") == text
    assert pg.hook("JSON.stringify(a.project.blocks.blocks)") == blocks_before
    pg.page.wait_for_timeout(300)
    assert pg.hook("a.viewpoint()") == view
    assert pg.hook("a.scene && a.scene.name") is None  # as it was: physics off, for the Nano
    pg.page.click("#tab-program")
    pg.page.screenshot(path=str(SHOTS / "studio-class-reload.png"))
    # 4: shared as a link, opened in a second profile: the same project, a copy
    pg.page.click("#share-button")
    pg.wait("a.shareLink !== ''")
    link = pg.hook("a.shareLink")
    assert pg.page.get_by_role("button", name="Share").count() == 1
    # "Copy the link" says it copied, and the clipboard holds the link
    pg.context.grant_permissions(["clipboard-read", "clipboard-write"], origin=pg.page.url.split("/articula-site")[0])
    pg.page.click("#share-copy")
    pg.wait("a.shareCopied === 'copied'")
    assert "Copied" in pg.page.inner_text("#share-copy")
    assert pg.page.evaluate("() => navigator.clipboard.readText()") == link
    pg.page.screenshot(path=str(SHOTS / "studio-class-share.png"))
    other = Page(browser, link, width=1366, height=768,
                 ready="window.articula.project.name.includes('from a link')")
    try:
        other.wait("a.blocksCode !== null || a.project.program !== ''", timeout=20000)
        other.wait("a.project.program === " + json.dumps(text), timeout=20000)
        assert other.hook("a.project.goal.title") == "Pick and place the block"
        other.page.click("#exercise-check")
        other.wait("a.exercise !== null", timeout=30000)
        assert other.hook("a.exercise.met") is True
        other.page.screenshot(path=str(SHOTS / "studio-class-link.png"))
        assert other.errors == []
    finally:
        other.close()
    assert pg.errors == [], pg.errors
    assert pg.hook("a.pageErrors") == []


def test_a_wait_block_waits_and_a_wait_beyond_its_range_is_refused_on_it(open_page, tmp_path):
    num = lambda n: {"shadow": {"type": "math_number", "fields": {"NUM": n}}}  # noqa: E731

    def program(seconds):
        return {"blocks": {"languageVersion": 0, "blocks": [{
            "type": "arm_gripper_open", "id": "g1", "x": 20, "y": 20, "next": {"block": {
                "type": "arm_wait", "id": "w", "inputs": {"SECONDS": num(seconds)}, "next": {"block": {
                    "type": "arm_gripper_close", "id": "g2"}}}}}]}}

    pg = open_page("mk2plus")
    _open_project(pg, tmp_path, _project("Wait", blocks=program(1.5)))
    pg.wait("a.project.name === 'Wait' && !a.blocksPending && a.blocksCode !== null")
    assert [l for l in pg.hook("a.blocksCode.text").splitlines() if not l.startswith("#")] == ["G 100", "D 1.5", "G 0"]
    pg.page.click("#run")
    pg.wait("a.timeline !== null && a.timeline.duration > 0")
    # two gripper actions of $5 = 300 ms each, and the wait between them
    assert abs(pg.hook("a.timeline.duration") - (0.3 + 1.5 + 0.3)) < 1e-6, pg.hook("a.timeline.duration")
    # a program file with a wait opens as blocks: the wait is a wait block
    f = tmp_path / "wait.arm"
    f.write_text("G 100\nD 2.5\n")
    pg.page.set_input_files("#program-file", str(f))
    pg.wait("!a.blocksPending && a.blocksCode !== null && a.blocksCode.text.includes('D 2.5')")
    assert pg.page.locator("#blockly svg.blocklySvg g.arm_wait[data-id]").count() == 1
    # beyond its range: refused on its block, with the range
    _open_project(pg, tmp_path, _project("Too long", blocks=program(700)), name="q.articula")
    pg.wait("a.project.name === 'Too long' && !a.blocksPending && a.blocksCode !== null && a.blocksCode.text.includes('D 700')")
    pg.page.click("#run")
    pg.wait("a.blockProblems.some(p => p.block === 'w')")
    message = pg.hook("a.blockProblems.find(p => p.block === 'w').message")
    assert "0 to 600" in message, message


def test_a_program_file_opens_as_blocks_with_its_comments_and_gives_the_same_prediction(open_page):
    pg = open_page("mk2plus")
    _blocks(pg)
    pg.page.select_option("#program-select", "demo.arm")
    pg.wait("a.blocksCode !== null && a.blocksCode.text.includes('P 200 -150 150')")
    text = pg.hook("a.blocksCode.text")
    # the comments are kept, as note blocks
    assert "# base 30 degrees to the left" in text
    # the lines that have no block are raw-line blocks that say so
    assert pg.page.locator("#blockly .blocklyText:text-is('line with no block:')").count() >= 3
    # the blocks' program predicts what the file predicts
    blocks_prog = REPO / "build" / "class-demo-blocks.arm"
    blocks_prog.write_text(text)
    a = cli_json("predict", "mk2plus", str(blocks_prog))["records"]
    b = cli_json("predict", "mk2plus", str(REPO / "programs" / "demo.arm"))["records"]
    assert [r["steps"] for r in a] == [r["steps"] for r in b]
    assert [r["reply"] for r in a] == [r["reply"] for r in b]


def test_show_code_gives_a_python_script_that_predicts_what_the_page_plays(open_page, tmp_path):
    pg = open_page("mk2plus")
    _open_project(pg, tmp_path, _project("Code", blocks=_chain([("arm_joints", "30, 70, -100"), ("arm_gripper_close", None), ("arm_home", None)])))
    pg.wait("a.blocksCode && a.blocksCode.text.includes('G 0') && a.blocksCode.text.includes('M 0 90 0')")
    pg.page.click("#show-code")
    pg.page.click("#code-tabs button[data-code=python]")
    script = pg.page.text_content("#code-text")
    pg.page.click("#code-close")
    (tmp_path / "blocks.py").write_text(script)
    out = subprocess.run([str(REPO / ".venv" / "bin" / "python"), str(tmp_path / "blocks.py")], capture_output=True, text=True,
                         timeout=120, env={"PYTHONPATH": str(REPO / "python")})
    assert out.returncode == 0, out.stderr
    import re
    printed = [re.fullmatch(r"line (\d+): (.*) -> (\S+), steps (.*)", line).groups() for line in out.stdout.splitlines()]
    pg.page.click("#run")
    pg.wait("a.timeline !== null")
    records = pg.hook("a.timeline.records")
    assert [(str(r["line"]), r["command"], r["reply"]) for r in records] == [(p[0], p[1], p[2]) for p in printed]
    assert [json.dumps(r["steps"]).replace(" ", "") for r in records] == [p[3].replace(" ", "") for p in printed]


def test_blocks_that_unroll_too_far_or_go_beyond_a_joint_are_refused_on_the_block(open_page, tmp_path):
    pg = open_page("mk2plus")
    _open_project(pg, tmp_path, _project("Far", blocks=_chain([("arm_joints", "0, 90, -150")])), "far.articula")
    first = "b0"
    pg.wait("a.blockProblems.length > 0")
    problem = pg.hook("a.blockProblems[0]")
    assert problem["block"] == first
    # the joint, the value and its range, in the sliders' units
    assert "elbow" in problem["message"].lower() or "-150" in problem["message"], problem
    assert "-150°" in problem["message"] and " to " in problem["message"]
    # a repeat of a repeat that makes 20,000 lines: refused, naming the repeat block
    rep = {"type": "controls_repeat_ext", "id": "outer", "x": 20, "y": 20,
           "inputs": {"TIMES": {"shadow": {"type": "math_number", "fields": {"NUM": 200}}},
                      "DO": {"block": {"type": "controls_repeat_ext", "id": "inner",
                                       "inputs": {"TIMES": {"shadow": {"type": "math_number", "fields": {"NUM": 100}}},
                                                  "DO": {"block": {"type": "arm_gripper_open", "id": "g"}}}}}}}
    project = _project("Too long", blocks={"blocks": {"languageVersion": 0, "blocks": [rep]}})
    f = tmp_path / "long.articula"
    f.write_text(json.dumps(project))
    pg.page.click("#projects-button")
    pg.page.set_input_files("#project-file", str(f))
    pg.wait("a.blockProblems.some(p => p.block === 'outer')", timeout=15000)
    msg = pg.hook("a.blockProblems.find(p => p.block === 'outer').message")
    assert "repeat" in msg and "10,000" in msg
    assert "10,000" in pg.page.text_content("#program-status")


def _project(name, text="", blocks=None, robot="mk2plus", mode="blocks", **extra):
    return {"format": "articula-project", "version": 1, "name": name, "robot": {"shipped": robot}, "scene": "",
            "program": {"mode": mode, "name": "program.arm", "text": text, "blocks": blocks}, "pose": None, "goal": None, **extra}


def _fragment(doc) -> str:
    raw = json.dumps(doc).encode() if not isinstance(doc, bytes) else doc
    c = zlib.compressobj(9, zlib.DEFLATED, -15)
    packed = c.compress(raw) + c.flush()
    return "project=" + base64.urlsafe_b64encode(packed).decode().rstrip("=")


def test_hostile_and_broken_links_say_what_is_wrong_and_change_nothing(browser, site):
    """A fuzz of links: truncated, bit-flipped, oversized, a newer version, script in every
    string field. Nothing runs, no page error, and the project saved before is untouched."""
    script = "<img src=x onerror=window.__pwned=1><script>window.__pwned=1</script>"
    hostile = _project(script, text=f"# {script}\nG 100\n", mode="text")
    hostile["goal"] = {"title": script, "text": script, "parts": [{"kind": "reach", "xyz": [200, 0, 150], "tolerance_mm": 5}]}
    hostile_blocks = _project(script, blocks={"blocks": {"languageVersion": 0, "blocks": [
        {"type": "arm_comment", "id": "c", "x": 10, "y": 10, "fields": {"TEXT": script},
         "next": {"block": {"type": "arm_raw", "id": "r", "fields": {"TEXT": script}}}}]}})
    good = _fragment(_project("Fine", text="G 100\n", mode="text"))
    rng = random.Random(21)
    links = [
        ("truncated", good[: len(good) // 2]),
        ("bit-flipped", good[:40] + ("A" if good[40] != "A" else "B") + good[41:]),
        ("a character no link has", good[:30] + "%3C" + good[30:]),
        ("oversized", "project=" + "A" * 120_000),
        ("not a project", _fragment({"hello": "world"})),
        ("a newer version", _fragment(_project("Future", text="", mode="text", version=99))),
        ("a block of another kind", _fragment(_project("Odd", blocks={"blocks": {"blocks": [{"type": "javascript_eval", "id": "x"}]}}))),
        ("a zip bomb", _fragment(b"[" + b" " * 6_000_000 + b"]")),
    ]
    for _ in range(6):
        b = bytearray(base64.urlsafe_b64decode(good[len("project="):] + "=="))
        b[rng.randrange(len(b))] ^= 1 << rng.randrange(8)
        links.append(("random bit", "project=" + base64.urlsafe_b64encode(bytes(b)).decode().rstrip("=")))
    p = Page(browser, f"{site.url}?robot=mk2plus")
    try:
        p.page.fill("#editor", "L 0 10\n")
        p.wait("a.project.saves > 0 && a.project.dirty === false", timeout=5000)
        saved = p.hook("a.project.id")
        for i, (what, frag) in enumerate(links):
            p.page.goto(f"{site.url}?n={i}#{frag}")
            p.page.wait_for_function("() => window.articula && window.articula.ready", timeout=20000 * PATIENCE)
            if what != "random bit":
                p.page.wait_for_selector("#banner:not([hidden])")
                msg = p.page.text_content("#banner-text")
                assert "cannot be opened" in msg and "Nothing you saved has changed" in msg, (what, msg)
            assert p.page.evaluate("() => window.__pwned") is None
            assert p.hook("a.pageErrors") == [], what
        # the hostile ones open, and every string stays text
        for i, doc in enumerate((hostile, hostile_blocks)):
            p.page.goto(f"{site.url}?h={i}#{_fragment(doc)}")
            p.page.wait_for_function("() => window.articula && window.articula.ready && window.articula.project.name.includes('from a link')",
                                     timeout=20000 * PATIENCE)
            if doc is hostile_blocks:
                p.wait("a.blocksCode !== null", timeout=15000)
            assert p.page.evaluate("() => window.__pwned") is None
            assert p.page.evaluate("() => document.querySelectorAll('img[src=x], main script, header script').length") == 0
            assert script in p.page.text_content("#project-name")
        assert p.hook("a.pageErrors") == []
        # what was saved before is as it was
        p.page.click("#projects-button")
        p.page.wait_for_selector("#project-list li")
        names = p.page.eval_on_selector_all("#project-list li b", "bs => bs.map(b => b.textContent)")
        assert any(n.startswith("Project") for n in names)
        p.page.click(f"#project-list li:has-text('Project') button:text-is('Open')")
        p.wait(f"a.project.id === {json.dumps(saved)}")
        p.wait("a.project.program === 'L 0 10\\n'")
    finally:
        p.close()


def test_bad_project_files_are_refused_and_a_broken_saved_project_does_not_stop_the_page(open_page, tmp_path):
    pg = open_page("mk2plus")
    pg.page.fill("#editor", "G 50\n")
    pg.wait("a.project.saves > 0 && a.project.dirty === false", timeout=5000)
    for name, body, words in [
        ("corrupt.articula", '{"format": "articula-project", "version": 1, "name": ', "is not JSON"),
        ("newer.articula", json.dumps(_project("Future", version=7)), "newer Articula"),
        ("bad-robot.articula", json.dumps({**_project("X"), "robot": 5}), "robot must"),
    ]:
        f = tmp_path / name
        f.write_text(body)
        pg.page.click("#projects-button")
        pg.page.set_input_files("#project-file", str(f))
        pg.page.wait_for_selector("#banner:not([hidden])")
        assert words in pg.page.text_content("#banner-text")
        assert name in pg.page.text_content("#banner-text")
        pg.page.click("#banner-close")
    assert pg.hook("a.project.program") == "G 50\n"
    # a saved record that cannot be read: the page starts with a new project and names it
    pg.page.evaluate("""() => new Promise((res, rej) => { const r = indexedDB.open('articula', 1);
        r.onsuccess = () => { const t = r.result.transaction('projects', 'readwrite');
          t.objectStore('projects').put({id: 'broken', name: 'Broken one', updated: Date.now() + 1e6, rev: 1, doc: {format: 'nope'}});
          t.oncomplete = res; t.onerror = rej; }; })""")
    pg.page.evaluate("() => sessionStorage.clear()")
    pg.page.goto(pg.page.url.split("?")[0])
    pg.page.wait_for_function("() => window.articula && window.articula.ready", timeout=20000 * PATIENCE)
    pg.page.wait_for_selector("#banner:not([hidden])")
    assert 'The saved project "Broken one" cannot be read' in pg.page.text_content("#banner-text")
    assert pg.hook("a.pageErrors") == []


def test_a_project_too_big_for_a_link_offers_the_file(open_page, tmp_path):
    """A robot from a file with a mesh of 120 KB that does not compress: the link would be
    longer than the page reads, so Share says so and offers the file instead."""
    pg = open_page("mk2plus")
    noise = base64.b64encode(random.Random(7).randbytes(120_000)).decode()
    doc = _project("Big", text="G 100\n", mode="text")
    doc["robot"] = {"file": {"name": "mk2plus.json", "text": (REPO / "robots" / "mk2plus.json").read_text(),
                             "legacy": False, "scale": 1}, "meshes": [{"name": "noise.stl", "data": noise}]}
    _open_project(pg, tmp_path, doc)
    # the name shows at once, the robot when the engine has read the file (later on a busy
    # machine); a file named as a shipped robot is the file, meshes and all, not the shipped robot
    pg.wait("a.project.name === 'Big'")
    pg.wait("a.robot.source !== '/robots/mk2plus.json'")
    assert pg.hook("a.robot.source") == "mk2plus.json"
    pg.page.click("#share-button")
    pg.page.wait_for_function("() => document.querySelector('#share-note').textContent.includes('too big for a link')")
    assert pg.hook("a.shareLink") == ""
    assert pg.page.input_value("#share-link") == ""
    assert pg.page.locator("#share-copy").is_hidden()
    with pg.page.expect_download() as dl:
        pg.page.click("#share-note button")
    assert dl.value.suggested_filename.endswith(".articula")
    saved = json.loads(Path(dl.value.path()).read_text())
    assert saved["robot"]["meshes"][0]["data"] == noise  # the file carries what the link cannot
    assert pg.errors == []


def test_a_long_project_name_leaves_the_header_whole(open_page, tmp_path):
    """At 1366 px (a lab PC), a long project name gives way: STOP, Tour and the engine's chip
    stay whole on screen; the name is cut with an ellipsis, and whole in its tooltip."""
    pg = open_page("mk2plus", width=1366, height=768, query="&scene=grasp-and-lift")
    name = "Exercise: pick and place the block, by a student with a very long name"
    _open_project(pg, tmp_path, _project(name, text="G 100\n", mode="text"))
    pg.wait(f"a.project.name === {json.dumps(name)}")
    for sel in ("#stop", "#conn", "#share-button"):
        box = pg.page.locator(sel).bounding_box()
        assert box["x"] >= 0 and box["x"] + box["width"] <= 1366, (sel, box)
        assert pg.page.evaluate(f"() => {{ const e = document.querySelector('{sel}'); return e.scrollWidth <= e.clientWidth + 1; }}"), sel
    assert pg.page.get_attribute("#project-name", "title").startswith(name)


def test_projects_new_rename_duplicate_delete_with_undo(open_page, monkeypatch):
    pg = open_page("mk2plus")
    pg.page.fill("#editor", "G 10\n")
    pg.wait("a.project.saves > 0 && a.project.dirty === false", timeout=5000)
    first = pg.hook("a.project.id")
    pg.page.click("#projects-button")
    pg.page.once("dialog", lambda d: d.accept("My arm"))
    pg.page.click("#project-list li.current button:text-is('Rename')")
    pg.wait("a.project.name === 'My arm'")
    pg.page.click("#project-list li.current button:text-is('Duplicate')")
    pg.page.wait_for_selector("#project-list li:has-text('My arm (copy)')")
    pg.page.click("#project-new")
    pg.wait(f"a.project.id !== {json.dumps(first)} && a.project.program === ''", timeout=10000)
    pg.page.click("#projects-button")
    pg.page.click("#project-list li:has-text('My arm (copy)') button:text-is('Delete')")
    pg.wait("a.project.lastDeleted === 'My arm (copy)'")
    assert pg.page.locator("#project-list li:has-text('My arm (copy)')").count() == 0
    pg.page.click("#banner-text button:text-is('Undo')")
    pg.page.wait_for_selector("#project-list li:has-text('My arm (copy)')")
    pg.page.click("#project-list li:has(b:text-is('My arm')) button:text-is('Open')")
    pg.wait(f"a.project.id === {json.dumps(first)}")
    pg.wait("a.project.program === 'G 10\\n'")
    assert pg.hook("a.pageErrors") == []


def test_saves_at_once_never_fork_the_tabs_own_project(open_page):
    """Two saves asked for at once (the page hidden twice, Share during an autosave) run one
    after the other: the second never goes over a revision the first replaced, which would
    make a copy "(other tab)" of the tab's own project. A change made during a save is kept."""
    pg = open_page("mk2plus")
    pg.page.fill("#editor", "G 100\n")
    pg.wait("a.project.saves > 0 && !a.project.dirty")
    name = pg.hook("a.project.name")
    for n in range(12):  # the second save starts 0 to 11 ms after the first: one lands in its middle
        pg.page.fill("#editor", f"G {n}\n")
        pg.page.evaluate(f"""async () => {{
            window.dispatchEvent(new Event('pagehide'));
            await new Promise(r => setTimeout(r, {n}));
            document.querySelector('#editor').value = 'G {n + 50}\\n';  // a change during the save
            document.querySelector('#editor').dispatchEvent(new Event('input'));
            window.dispatchEvent(new Event('pagehide'));
        }}""")
        pg.wait(f"!a.project.dirty && a.project.program === 'G {n + 50}\\n' && a.project.saves > {n}")
    assert pg.hook("a.project.name") == name
    assert pg.hook("a.project.otherTab") == 0
    assert "other tab" not in pg.page.text_content("#banner-text")
    pg.page.click("#projects-button")
    assert "(other tab)" not in pg.page.text_content("#project-list")


def test_private_mode_quota_and_two_tabs(browser, site):
    # no IndexedDB (private mode): the page works and says to save a file
    p = Page(browser, f"{site.url}?robot=mk2plus", init_script="Object.defineProperty(window, 'indexedDB', {value: undefined})")
    try:
        p.page.wait_for_selector("#banner:not([hidden])")
        assert "keeps nothing" in p.page.text_content("#banner-text")
        assert p.hook("a.project.persistent") is False
        p.page.fill("#editor", "G 20\n")
        p.wait("a.project.saves > 0")
        assert p.hook("a.pageErrors") == []
    finally:
        p.close()
    # the quota reached: 'not saved', and the last save is what a reload brings back
    p = Page(browser, f"{site.url}?robot=mk2plus")
    try:
        p.page.fill("#editor", "G 30\n")
        p.wait("a.project.saves > 0 && a.project.dirty === false", timeout=5000)
        p.page.evaluate("""() => { IDBObjectStore.prototype.put = function () {
            throw new DOMException('The quota has been exceeded.', 'QuotaExceededError'); }; }""")
        p.page.fill("#editor", "G 31\n")
        p.wait("a.project.saveError === 'quota'", timeout=5000)
        assert "no room left" in p.page.text_content("#banner-text")
        assert p.page.text_content("#project-saved") == "not saved"
        p.page.reload()
        p.page.wait_for_function("() => window.articula && window.articula.ready", timeout=20000 * PATIENCE)
        p.wait("a.project.program === 'G 30\\n'", timeout=10000)
        # two tabs on one project: the second tab's save goes to a copy, the first's stays
        second = p.context.new_page()
        second.goto(site.url)
        second.evaluate("() => 0")
        second.wait_for_function("() => window.articula && window.articula.ready", timeout=20000 * PATIENCE)
        # the second tab opened the same (most recent) project
        pid = p.hook("a.project.id")
        second.wait_for_function(f"() => window.articula.project.id === {json.dumps(pid)}", timeout=10000)
        p.page.fill("#editor", "G 40\n")
        p.wait("a.project.dirty === false && a.project.program === 'G 40\\n'", timeout=5000)
        second.fill("#editor", "G 41\n")
        second.wait_for_function("() => window.articula.project.name.endsWith('(other tab)')", timeout=10000)
        assert "changed in another tab" in second.text_content("#banner-text")
        # nothing lost: both are in the list
        p.page.click("#projects-button")
        p.page.wait_for_selector("#project-list li:has-text('(other tab)')")
        names = p.page.eval_on_selector_all("#project-list li b", "bs => bs.map(b => b.textContent)")
        assert any(n.endswith("(other tab)") for n in names) and len(names) >= 2
        second.close()
    finally:
        p.close()


# ---- what a student and a teacher hit (issue 21): one test for each group of fixes

def test_the_program_speaks_the_sliders_numbers_and_every_refusal_says_why(open_page):
    pg = open_page("mk2plus", width=1366, height=768)
    # beside each slider, the motor's angle where it differs (the MK2's elbow: -90 joint, 0 motor)
    pg.wait("a.pose && a.pose.motors !== undefined")
    elbow = pg.page.text_content("#joints .motor-angle[data-motor='2']")
    assert elbow == "motor elbow: 0.00°", elbow
    assert pg.page.text_content("#joints .motor-angle[data-motor='0']") == ""  # the base: the same number
    pg.page.click("#tab-program")
    # M 0 90 -90: refused, naming the motor, the value and its range
    pg.page.fill("#editor", "M 0 90 -90\n")
    pg.page.click("#run")
    pg.wait("a.timeline !== null")
    text = pg.page.text_content("#program-status")
    assert "error:9" in text and "the elbow motor to -90 deg is beyond its range, -43 to 15 deg" in text, text
    # M 1 2: how many values M takes, and what they are; L 0 ten: the word that is not a number
    for line, words in (("M 1 2", "M takes 3 values, one angle in degrees for each motor (base, shoulder, elbow); this line gives 2"),
                        ("L 0 ten", "'ten' is not a number")):
        pg.page.fill("#editor", f"G 100\n{line}\n")
        pg.page.click("#run")
        pg.page.wait_for_function(f"() => document.querySelector('#program-status').textContent.includes({json.dumps(words)})")
        status = pg.page.text_content("#program-status")
        assert words in status and status.startswith("line 2:"), status  # the line, not an old file's name
    # Teach in blocks speaks the sliders' values too
    pg.page.click("#mode-blocks")
    pg.page.wait_for_selector("#blockly .blocklyToolbox")
    pg.page.click("#teach")
    pg.wait("a.teach === '0, 90, -90'")


def test_the_editor_explains_itself_and_an_empty_program_says_so(open_page):
    pg = open_page("mk2plus", width=1366, height=768)
    pg.page.click("#tab-program")
    assert "Type a program here" in pg.page.get_attribute("#editor", "placeholder")
    pg.page.click("#run")
    assert "The program is empty" in pg.page.text_content("#program-status")
    pg.page.click("#command-card summary")
    assert "moves the tip of the tool to a point" in pg.page.text_content("#command-card")
    pg.page.fill("#editor", "G 100\nP 200 0 150\n")
    pg.page.click("#editor")
    pg.page.keyboard.press("Control+End")
    pg.page.keyboard.press("ArrowUp")
    pg.page.wait_for_function("() => document.querySelector('#line-help').textContent.startsWith('P x y z')")
    # help on hover: the pointer over line 1 (the gripper's) says what G does, as the tooltip too
    box = pg.page.locator("#editor").bounding_box()
    lh = pg.page.evaluate("() => { const cs = getComputedStyle(document.querySelector('#editor')); "
                          "return [parseFloat(cs.lineHeight), parseFloat(cs.paddingTop)]; }")
    pg.page.mouse.move(box["x"] + 40, box["y"] + lh[1] + lh[0] * 0.5)
    pg.page.wait_for_function("() => document.querySelector('#line-help').textContent.startsWith('line 1: G percent')")
    assert pg.page.get_attribute("#editor", "title").startswith("line 1: G percent")
    pg.page.mouse.move(box["x"] + 40, box["y"] + lh[1] + lh[0] * 1.5)
    pg.page.wait_for_function("() => document.querySelector('#editor').title.startsWith('line 2: P x y z')")
    # the running line is not drawn as an error is
    run_bg = pg.page.evaluate("() => { const e = document.querySelector('#current-line'); e.hidden = false; return getComputedStyle(e).borderLeftColor; }")
    err_bg = pg.page.evaluate("() => { const e = document.querySelector('#current-line'); e.classList.add('error'); "
                              "const c = getComputedStyle(e).borderLeftColor; e.classList.remove('error'); e.hidden = true; return c; }")
    assert run_bg != err_bg


def test_examples_fit_the_robot_and_a_scene_comes_with_its_example(open_page):
    pg = open_page("panda", width=1366, height=768)
    offered = pg.page.eval_on_selector_all("#program-select option", "os => os.map(o => o.value).filter(Boolean)")
    assert "demo.arm" not in offered  # an MK2 program: the Panda's parser refuses it
    pg.page.select_option("#robot-select", "mk2plus")
    pg.wait("a.robot.name === 'MK2 Plus'")
    offered = pg.page.eval_on_selector_all("#program-select option", "os => os.map(o => o.value).filter(Boolean)")
    assert "demo.arm" in offered and "grasp-and-lift.arm" in offered
    pg.page.click("#tab-program")
    pg.page.select_option("#program-select", "grasp-and-lift.arm")
    pg.wait("a.scene && a.scene.name === 'grasp-and-lift' && a.physics && a.physics.on", timeout=20000)
    assert "this program is made for" in pg.page.text_content("#program-status")
    # the gripper starts open in physics, and stays open: the first move down meets no fingers
    pg.wait("a.physics.t > 0.5", timeout=20000)
    assert pg.hook("a.pose.gripper") == 100


def test_stale_state_goes_and_bad_input_is_said(open_page):
    pg = open_page("mk2plus", width=1600, height=900)
    # an IK verdict for the MK2 does not stay for the Panda
    for c, v in zip("xyz", (900, 0, 100)):
        pg.page.fill(f"#t{c}", str(v))
    pg.page.click("#solve")
    pg.wait("a.ik !== null")
    assert pg.page.text_content("#ik-status") != ""
    pg.page.select_option("#robot-select", "panda")
    pg.wait("a.robot.name.startsWith('Panda') || a.robot.name.includes('Panda')", timeout=20000)
    assert pg.page.text_content("#ik-status") == ""
    # z = 1e308: said, nothing thrown
    pg.page.fill("#tz", "1e308")
    pg.page.click("#solve")
    assert "too far" in pg.page.text_content("#ik-status")
    # 99999 in the base box: the box shows where the arm is (clamped)
    pg.page.select_option("#robot-select", "mk2plus")
    pg.wait("a.robot.name === 'MK2 Plus'")
    box = "#joints input[type=number][data-joint='0']"
    pg.page.fill(box, "99999")
    pg.page.press(box, "Enter")
    pg.wait("a.pose.q[0] > 89")
    pg.page.wait_for_function(f"() => parseFloat(document.querySelector(\"{box}\").value) === window.articula.pose.q[0]")
    # the physics counter goes with the physics
    pg.page.select_option("#scene-select", "push")
    pg.wait("a.physics && a.physics.on && a.physics.t > 0.2", timeout=20000)
    pg.page.select_option("#scene-select", value="")
    pg.wait("!a.physics.on")
    assert pg.page.text_content("#phys-rtf") == ""
    # STOP says it stopped
    pg.page.click("#stop")
    pg.wait("a.stops === 1")
    assert pg.page.text_content("#banner-text").startswith("STOP:")
    assert pg.hook("a.pageErrors") == [] and pg.errors == []


def test_rough_edges(open_page, tmp_path):
    # the plots' picture says what it shows; a program can play slower
    pg = open_page("mk2plus")
    pg.page.select_option("#program-select", "demo.arm")
    pg.page.wait_for_function("() => document.querySelector('#editor').value.includes('P 200')")
    pg.page.select_option("#play-speed", "0.25")
    pg.page.click("#run")
    pg.wait("a.playing === true")
    t0 = pg.hook("performance.now()")
    pg.wait("a.playing === false", timeout=60000)
    wall = (pg.hook("performance.now()") - t0) / 1000
    duration = pg.hook("a.timeline.duration")
    assert wall > duration * 2.5, (wall, duration)  # a quarter of the speed: four times as long
    with pg.page.expect_download() as dl:
        pg.page.click("#export-png")
    assert dl.value.suggested_filename == "articula-plots-demo_arm.png"
    assert pg.hook("a.pngCaption").startswith("MK2 Plus, demo.arm, ")
    # the IK ball is drawn over the arm: at the tool, inside the gripper, it shows (orange)
    import io

    from PIL import Image

    pg.page.click("#home")
    pg.page.check("#show-target")
    pg.page.wait_for_timeout(300)
    x, y = pg.hook("a.targetScreen")
    shot = Image.open(io.BytesIO(pg.page.screenshot(clip={"x": x - 1, "y": y - 1, "width": 3, "height": 3}))).convert("RGB")
    r, g, b = shot.getpixel((1, 1))
    assert r > 150 and r > g > b, (r, g, b)


def test_the_puma_at_home_stands_above_the_floor(open_page):
    pg = open_page("puma560")
    pg.wait("a.pose && a.robot.name.startsWith('PUMA')")
    heights = pg.hook("a.pose.frames.map(f => f[11])")  # row-major: z is the third row's last
    assert min(heights) >= 0, heights
    assert pg.hook("a.pose.tool.xyz[2]") > 100


@pytest.mark.parametrize("size", [(768, 1024), (390, 844)], ids=["tablet", "phone"])
def test_blocks_and_an_exercise_on_a_tablet_and_a_phone(open_page, size):
    """The exercise's goal and its blocks on a touch screen: STOP on screen, the blocks in sight."""
    w, h = size
    pg = open_page("mk2plus", width=w, height=h, touch=True)
    pg.page.tap("#projects-button")
    pg.page.select_option("#exercise-select", "pick-and-place.articula")
    pg.wait("a.project.goal !== null && a.programMode === 'blocks'")
    pg.page.wait_for_selector("#exercise:not([hidden])")
    stop = pg.page.locator("#stop").bounding_box()
    assert 0 <= stop["x"] and stop["x"] + stop["width"] <= w, stop
    pg.page.locator("#blockly").scroll_into_view_if_needed()
    blocks = pg.page.locator("#blockly").bounding_box()
    assert blocks["width"] >= w * 0.8 and blocks["height"] >= 300, blocks
    assert pg.page.evaluate("() => document.documentElement.scrollWidth") <= w
    # no drag needed: a block tapped in the toolbox joins the end of the program
    count = "(a.blocksPending ? -1 : a.blocksCode ? a.blocksCode.text.split('\\n').filter(l => /^[A-Z]/.test(l)).length : 0)"
    n0 = pg.hook(count)
    for i, (category, kind) in enumerate([("Gripper", "arm_gripper_open"), ("Move", "arm_joints")], 1):
        pg.page.tap(f"#blockly .blocklyToolboxCategory:has-text('{category}')")
        pg.page.wait_for_selector(f"#blockly svg.blocklyToolboxFlyout g.{kind}[data-id]")
        pg.page.locator(f"#blockly svg.blocklyToolboxFlyout g.{kind}[data-id] > path.blocklyPath").first.tap(position={"x": 6, "y": 8})
        pg.wait(f"a.blockStacks === 1 && {count} === {n0 + i}", timeout=10000)
    pg.page.screenshot(path=str(SHOTS / f"studio-class-{'tablet' if w == 768 else 'phone'}.png"))


def test_variables_arithmetic_and_procedures_unroll_into_lines(open_page, tmp_path):
    """A beginner's control, unrolled: a variable changed in a repeat, arithmetic, and a
    procedure with a parameter called twice."""
    num = lambda n: {"shadow": {"type": "math_number", "fields": {"NUM": n}}}  # noqa: E731
    var = {"type": "variables_get", "fields": {"VAR": {"id": "v1"}}}
    define = {"type": "procedures_defnoreturn", "id": "def", "x": 20, "y": 400, "fields": {"NAME": "wave"},
              "extraState": {"params": [{"name": "angle", "id": "p1"}]},
              "inputs": {"STACK": {"block": {"type": "arm_joint_to", "id": "w1", "fields": {"JOINT": "0"},
                                              "inputs": {"VALUE": {"block": {"type": "variables_get", "fields": {"VAR": {"id": "p1"}}}}},
                                              "next": {"block": {"type": "arm_gripper_close", "id": "w2"}}}}}}
    main = {"type": "variables_set", "id": "s", "x": 20, "y": 20, "fields": {"VAR": {"id": "v1"}}, "inputs": {"VALUE": num(10)},
            "next": {"block": {"type": "controls_repeat_ext", "id": "r", "inputs": {
                "TIMES": num(3),
                "DO": {"block": {"type": "arm_joint_to", "id": "j", "fields": {"JOINT": "0"},
                                 "inputs": {"VALUE": {"block": {"type": "math_arithmetic", "fields": {"OP": "MULTIPLY"},
                                                                "inputs": {"A": {"block": var}, "B": num(2)}}}},
                                 "next": {"block": {"type": "math_change", "fields": {"VAR": {"id": "v1"}}, "inputs": {"DELTA": num(5)}}}}}},
                "next": {"block": {"type": "procedures_callnoreturn", "id": "c1", "extraState": {"name": "wave", "params": ["angle"]},
                                   "inputs": {"ARG0": num(-20)},
                                   "next": {"block": {"type": "procedures_callnoreturn", "id": "c2",
                                                      "extraState": {"name": "wave", "params": ["angle"]}, "inputs": {"ARG0": num(25)}}}}}}}}
    blocks = {"blocks": {"languageVersion": 0, "blocks": [main, define]},
              "variables": [{"name": "step", "id": "v1"}, {"name": "angle", "id": "p1"}]}
    pg = open_page("mk2plus")
    f = tmp_path / "control.articula"
    f.write_text(json.dumps(_project("Control", blocks=blocks)))
    pg.page.click("#projects-button")
    pg.page.set_input_files("#project-file", str(f))
    pg.wait("a.blocksCode !== null && !a.blocksPending", timeout=15000)
    lines = [l for l in pg.hook("a.blocksCode.text").splitlines() if l and not l.startswith("#")]
    # step 10, 15, 20 doubled: the base to 20, 30, 40; then wave(-20) and wave(25)
    assert lines == ["M 20 90 0", "M 30 90 0", "M 40 90 0", "M -20 90 0", "G 0", "M 25 90 0", "G 0"], lines


def test_every_shipped_exercise_can_be_solved(open_page, tmp_path):
    solutions = {
        "reach-three-points.articula": None,  # below: three tool blocks
        "pick-and-place.articula": _chain([(k, v) for _, k, v in SOLUTION]),
        "stack-two-blocks.articula": _chain([(k, v) for _, k, v in SOLUTION]),
    }
    # reach: three tool blocks, with their points
    points = [(200, -150, 150), (250, 100, 150), (260, 0, 100)]
    reach = [{"type": "arm_tool_to", "id": f"t{i}", "inputs": {a: {"shadow": {"type": "math_number", "fields": {"NUM": v}}}
                                                              for a, v in zip("XYZ", p)}} for i, p in enumerate(points)]
    for a, b in zip(reach[:-1], reach[1:]):
        a["next"] = {"block": b}
    solutions["reach-three-points.articula"] = {"blocks": {"languageVersion": 0, "blocks": [{**reach[0], "x": 20, "y": 20}]}}
    pg = open_page("mk2plus")
    for name, blocks in solutions.items():
        doc = json.loads((REPO / "exercises" / name).read_text())
        doc["program"]["blocks"] = blocks
        f = tmp_path / name
        f.write_text(json.dumps(doc))
        pg.page.click("#projects-button")
        pg.page.set_input_files("#project-file", str(f))
        pg.wait(f"a.project.goal !== null && a.project.goal.title === {json.dumps(doc['goal']['title'])}")
        pg.wait("a.blocksCode !== null && !a.blocksPending && a.blocksCode.text.includes(" +
                json.dumps("P 260 0 100" if name.startswith("reach") else "G 0") + ")", timeout=15000)
        prev = pg.hook("a.exercise ? JSON.stringify(a.exercise) : ''")
        pg.page.click("#exercise-check")
        pg.wait(f"a.exercise !== null && JSON.stringify(a.exercise) !== {json.dumps(prev)}", timeout=30000)
        assert pg.hook("a.exercise.met") is True, (name, pg.hook("a.exercise"))
    # a program that misses says which part, and by how much
    doc = json.loads((REPO / "exercises" / "reach-three-points.articula").read_text())
    doc["program"]["blocks"] = {"blocks": {"languageVersion": 0, "blocks": [{**reach[0], "x": 20, "y": 20, "next": None}]}}
    del doc["program"]["blocks"]["blocks"]["blocks"][0]["next"]
    f = tmp_path / "miss.articula"
    f.write_text(json.dumps(doc))
    pg.page.click("#projects-button")
    pg.page.set_input_files("#project-file", str(f))
    pg.wait("a.exercise === null || true")
    pg.wait("a.blocksCode !== null && !a.blocksPending && !a.blocksCode.text.includes('P 260 0 100')", timeout=15000)
    prev = pg.hook("JSON.stringify(a.exercise)")
    pg.page.click("#exercise-check")
    pg.wait(f"JSON.stringify(a.exercise) !== {json.dumps(prev)}", timeout=30000)
    parts = pg.hook("a.exercise.parts")
    assert [p["met"] for p in parts] == [True, False, False]
    assert "mm away: needs to be within 5 mm" in parts[1]["detail"]


def test_a_project_file_dropped_on_the_page_opens(open_page):
    pg = open_page("mk2plus")
    doc = _project("Dropped", text="G 42\n", mode="text")
    dt = pg.page.evaluate_handle("""(text) => { const d = new DataTransfer();
        d.items.add(new File([text], 'dropped.articula', { type: 'application/json' })); return d; }""", json.dumps(doc))
    pg.page.dispatch_event("#view", "dragover", {"dataTransfer": dt})
    pg.page.dispatch_event("#view", "drop", {"dataTransfer": dt})
    pg.wait("a.project.name === 'Dropped' && a.project.program === 'G 42\\n'", timeout=15000)
