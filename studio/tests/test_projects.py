"""Projects kept in the browser (issue 21): new, rename, duplicate, delete with undo; saved at
once and never forked between tabs; private mode and a full quota; project files and links,
hostile, broken or too big, refused saying what is wrong and changing nothing."""

from __future__ import annotations

import base64
import json
import random
from pathlib import Path

from conftest import Page, PATIENCE, REPO
from class_page import _fragment, _open_project, _project


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
        ("bad-paper.articula", json.dumps({**_project("X"), "paper": {"sheet": "A3", "at": [0, 0], "z": 0, "pen": 1}}), "paper.sheet"),
        ("bad-pen.articula", json.dumps({**_project("X"), "paper": {"sheet": "A5", "at": [0, 0], "z": 0, "pen": "long"}}), "paper.pen"),
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


def test_a_project_file_dropped_on_the_page_opens(open_page):
    pg = open_page("mk2plus")
    doc = _project("Dropped", text="G 42\n", mode="text")
    dt = pg.page.evaluate_handle("""(text) => { const d = new DataTransfer();
        d.items.add(new File([text], 'dropped.articula', { type: 'application/json' })); return d; }""", json.dumps(doc))
    pg.page.dispatch_event("#view", "dragover", {"dataTransfer": dt})
    pg.page.dispatch_event("#view", "drop", {"dataTransfer": dt})
    pg.wait("a.project.name === 'Dropped' && a.project.program === 'G 42\\n'", timeout=15000)
