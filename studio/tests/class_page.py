"""Driving the studio as a class does, for the tests of blocks, projects and exercises: blocks
dragged from the toolbox with the mouse and their numbers typed, projects opened from files,
links made as the page makes them."""

from __future__ import annotations

import base64
import json
import time
import zlib

import pytest

from conftest import PATIENCE



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
    tried = []  # (each attempt: seconds, stacks, blocks in the workspace, new ids) for a failure
    # The workspace's blocks (not the toolbox's, nor one still held by a drag: Blockly drags it on
    # a layer of its own); and those added since `before`, outermost only (not a block's inner
    # ones), whatever their type: a busy page can draw a new block's type some time after it
    all_ids = "() => [...document.querySelectorAll('#blockly svg.blocklySvg g.blocklyBlockCanvas g[data-id]')].map(g => g.dataset.id)"
    added = """(before) => [...document.querySelectorAll('#blockly svg.blocklySvg g.blocklyBlockCanvas g[data-id]')]
        .filter(g => !before.includes(g.dataset.id))
        .filter(g => { const p = g.parentElement.closest('g[data-id]'); return !p || before.includes(p.dataset.id); })
        .map(g => g.dataset.id)"""
    dropped = "() => !document.querySelector('#blockly .blocklyBlockDragSurface g[data-id]')"
    under = """([x, y, kind]) => { const g = document.elementFromPoint(x, y)?.closest('g[data-id]');
        return !!g && g.classList.contains(kind) && !!g.closest('svg.blocklyToolboxFlyout'); }"""
    of_kind = "([ids, kind]) => ids.every(id => document.querySelector(`#blockly svg.blocklySvg g[data-id='${id}']`)?.classList.contains(kind))"
    for _ in range(3):  # a busy machine can turn a drag into a click: then again
        t0 = time.time()
        before = page.evaluate(all_ids)
        for _ in range(3):  # a click on an open category closes it
            page.click(f"#blockly .blocklyToolboxCategory:has-text('{category}')")
            try:
                page.wait_for_function(shown, timeout=3000)
                break
            except Exception:
                continue
        # the toolbox's block of that type under the pointer (a flyout a busy page is still laying
        # out, or redraws for the robot, moves its blocks: a press measured before then grabs
        # the block beside, a gripper set to 50 for an open gripper)
        for _ in range(10):
            sx, sy, _, _ = _block_rect(page, "blocklyToolboxFlyout", kind, by_type=True)
            if page.evaluate(under, [sx + 6, sy + 8, kind]):
                break
            page.wait_for_timeout(200)
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
        # the drop done (a busy page can be behind the mouse): then the workspace has one more
        # block, or none when a drop on the open toolbox deleted it (or the drag became a click)
        try:
            page.wait_for_function(dropped, timeout=5000 * PATIENCE)
        except Exception:
            pass
        new = page.evaluate(added, before)
        try:  # (its type drawn: a busy page draws it after the block)
            new and page.wait_for_function(of_kind, arg=[new, kind], timeout=2000 * PATIENCE)
        except Exception:  # the block beside: undone, and dragged again
            tried.append(("another block", new))
            page.keyboard.press("Control+z")
            page.wait_for_function(f"() => !{json.dumps(new)}.some(id => document.querySelector(`#blockly svg.blocklySvg g[data-id='${{id}}']`))",
                                   timeout=5000 * PATIENCE)
            new = []
            continue
        tried.append((round(time.time() - t0, 1), pg.hook("a.blockStacks"), len(page.evaluate(all_ids)), new))
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
    try:
        pg.wait("a.blockStacks === 1 && !a.blocksPending", timeout=5000)
    except AssertionError as e:  # (what the workspace held: a failure says which drag went wrong)
        raise AssertionError(f"dragging {kind} under {below}: {new} appeared; blockStacks "
                             f"{pg.hook('a.blockStacks')}, pending {pg.hook('a.blocksPending')}, "
                             f"in the workspace {page.eval_on_selector_all('#blockly svg.blocklySvg g[data-id]', 'gs => gs.map(g => g.dataset.id).length')} "
                             f"blocks; attempts {tried}; {e}") from None
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


def _project(name, text="", blocks=None, robot="mk2plus", mode="blocks", **extra):
    return {"format": "articula-project", "version": 1, "name": name, "robot": {"shipped": robot}, "scene": "",
            "program": {"mode": mode, "name": "program.arm", "text": text, "blocks": blocks}, "pose": None, "goal": None, **extra}


def _fragment(doc) -> str:
    raw = json.dumps(doc).encode() if not isinstance(doc, bytes) else doc
    c = zlib.compressobj(9, zlib.DEFLATED, -15)
    packed = c.compress(raw) + c.flush()
    return "project=" + base64.urlsafe_b64encode(packed).decode().rstrip("=")
