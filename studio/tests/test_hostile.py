"""Untrusted input never runs in the page. A robot file, a scene, a program and its name, and
what the arm sends back carry markup with event handlers and `</textarea><script>` in every
string field. Opened, played, simulated, connected to the virtual Nano and exported: nothing
runs, no element comes from them, the Content-Security-Policy never has to block anything, and
every name shows as the text it is."""

from __future__ import annotations

import json
import shutil
import xml.etree.ElementTree as ET

import pytest

from conftest import DIST, REPO, Page, StaticSite

# Every way a string could turn into code if it reached HTML: a handler, a script element after
# closing a textarea, an SVG handler, a javascript: link. Each bumps window.__pwned if it runs.
HOSTILE = ('<img src=x onerror="window.__pwned=(window.__pwned||0)+1">'
           '</textarea><script>window.__pwned=(window.__pwned||0)+1</script>'
           '<svg onload="window.__pwned=1"></svg><a href="javascript:window.__pwned=1">x</a>')


def h(label: str) -> str:
    return f"{label}{HOSTILE}"


# The page's own listeners, before its module: what the CSP blocked, and any error.
WATCH = """
window.__pwned = 0;
window.__violations = [];
document.addEventListener('securitypolicyviolation', (e) =>
  window.__violations.push(`${e.violatedDirective} ${e.blockedURI} ${e.sample}`));
localStorage.setItem('articula.studio.tour.done', '1');
"""


def hostile_robot() -> dict:
    r = json.loads((REPO / "robots" / "mk2plus.json").read_text())
    names = {"base": h("j1"), "shoulder": h("j2"), "elbow": h("j3")}
    r["name"] = h("Robot")
    r["description"] = h("About it")
    for row in r["dh"]:
        t = row["theta"]
        if "joint" in t:
            t["joint"] = names[t["joint"]]
        else:
            t["linked"] = {names[k]: v for k, v in t["linked"].items()}
    for m in r["motors"]:
        m["name"] = h(f"motor {m['name']}")
    r["home"] = {names[k]: v for k, v in r["home"].items()}
    return r


SCENE = {
    "name": h("Scene"),
    "description": h("A scene"),
    "objects": [{"name": h("block"), "type": "box", "size": [40, 40, 40], "xyz": [260, 0, 60], "movable": True, "mass": 0.05},
                {"name": h("post"), "type": "cylinder", "size": [15, 200], "xyz": [0, -300, 100]}],
}
# A program that cannot be read: its line of markup comes back in the error, quoted.
BAD_LINE = "L 0 <img src=x onerror=window.__pwned=1>"
PROGRAM = f"# {HOSTILE}\nL 0 10\n{BAD_LINE}\n"
# One that plays: markup in a comment, and a line the arm refuses (error:9).
PLAYED = f"# {HOSTILE}\nL 0 10\nL 1 150\n"
PROGRAM_NAME = "evil<img src=x onerror=window.__pwned=1>.arm"


@pytest.fixture(scope="module")
def hostile_site(tmp_path_factory):
    """The built site with a hostile scene and a shipped program of a hostile name beside the
    real ones, as a school's copy someone tampered with would be."""
    root = tmp_path_factory.mktemp("hostile-www")
    copy = root / "site-copy"
    shutil.copytree(DIST, copy)
    (copy / "data" / "scenes" / "hostile.json").write_text(json.dumps(SCENE))
    (copy / "data" / "programs" / PROGRAM_NAME).write_text(PROGRAM)
    index = json.loads((copy / "data" / "index.json").read_text())
    index["scenes"].append("hostile")
    index["programs"].append(PROGRAM_NAME)
    (copy / "data" / "index.json").write_text(json.dumps(index))
    site = StaticSite(root / "served", dist=copy)
    yield site
    site.stop()


def nothing_ran(page) -> None:
    assert page.evaluate("window.__pwned") == 0
    assert page.evaluate("window.__violations") == []
    # no element the strings could have made: one script (the page's module), no image, no
    # SVG, no javascript: link, no inline handler anywhere (the 3D view, the paper view, the
    # wiring and a cell's timeline are the page's own drawings; they hold only the shapes and
    # text nodes the page draws)
    assert page.evaluate("document.scripts.length") == 1
    assert page.evaluate("""[...document.querySelectorAll('img, svg, a[href^="javascript"], iframe, object, embed')]
        .filter(e => !e.closest('#view') && !['paper-view', 'wiring', 'cell-timeline'].includes(e.id)).length""") == 0
    assert page.evaluate("""[...document.querySelectorAll('#cell-timeline *')].map(e => e.localName)
        .filter(n => !['defs', 'pattern', 'marker', 'g', 'rect', 'line', 'path', 'text', 'title'].includes(n))""") == []
    assert page.evaluate("""[...document.querySelectorAll('#paper-view *')].map(e => e.localName)
        .filter(n => !['g', 'rect', 'polyline', 'circle'].includes(n))""") == []
    assert page.evaluate("""[...document.querySelectorAll('#wiring *')].map(e => e.localName)
        .filter(n => !['rect', 'text', 'line', 'circle'].includes(n))""") == []
    assert page.evaluate("""[...document.querySelectorAll('*')].flatMap(e => [...e.attributes])
        .filter(a => a.name.startsWith('on')).map(a => a.name)""") == []


def test_hostile_strings_show_as_text_and_never_run(browser, hostile_site, tmp_path):
    pg = Page(browser, f"{hostile_site.url}?robot=mk2plus&nosw", init_script=WATCH)
    page = pg.page
    try:
        # a robot file with markup in its name, description, joint and motor names
        robot = tmp_path / "robot.json"
        robot.write_text(json.dumps(hostile_robot()))
        page.set_input_files("#robot-file", str(robot))
        pg.wait(f"a.robot.name === {json.dumps(h('Robot'))}")
        assert page.text_content("#robot-name") == f"{h('Robot')}: {h('About it')}"
        joints = page.text_content("#joints")
        for j in ("j1", "j2", "j3"):
            assert h(j) in joints
        assert h("motor base") in page.text_content("#weights")
        # sliders still move it
        page.fill('#joints input[type=number][data-joint="0"]', "12")
        pg.wait("Math.abs(a.pose.q[0] - 12) < 1e-9")
        nothing_ran(page)

        # a shipped program of a hostile name, and a program whose comments and lines are markup
        assert PROGRAM_NAME in page.eval_on_selector_all("#program-select option", "os => os.map(o => o.textContent)")
        page.select_option("#program-select", PROGRAM_NAME)
        pg.wait(f"document.querySelector('#editor').value === {json.dumps(PROGRAM)}")
        page.click("#run")
        pg.wait("a.programError !== ''", timeout=15000)
        # refused as a whole, the file (in the hook) and the line named as the text they are; the
        # panel names the line of the program on screen
        assert pg.hook("a.programError").startswith(f"{PROGRAM_NAME}:3: '{BAD_LINE}': error:3 bad number")
        assert page.text_content("#program-status") == pg.hook("a.programError").replace(f"{PROGRAM_NAME}:3: ", "line 3: ")
        nothing_ran(page)
        # a program file of a hostile name opened from disk: played, its refused line listed as text
        name = "x<script>window.__pwned=1</script>.arm"
        page.set_input_files("#program-file", files=[{"name": name, "mimeType": "text/plain", "buffer": PLAYED.encode()}])
        page.click("#run")
        pg.wait("a.timeline !== null && a.timeline.records.length === 2", timeout=15000)
        assert "line 3: L 1 150 → error:9, target beyond a joint limit" in page.text_content("#program-status")
        assert h("j1") in page.text_content("#plots")  # the plots' legend: the joint names as text
        with page.expect_download() as d:
            page.click("#save-program")
        assert d.value.suggested_filename.endswith(".arm")
        nothing_ran(page)

        # URDF out: the hostile names escaped, a well-formed file
        with page.expect_download() as d:
            page.click("#export-urdf")
        urdf = d.value.path().read_text()
        ET.fromstring(urdf)  # well-formed XML: every name escaped or made an identifier
        assert "<img" not in urdf and "<script" not in urdf

        # the hostile scene: objects named with markup, in the menu, the 3D view and the events
        page.select_option("#scene-select", "hostile")
        pg.wait("a.scene && a.scene.name === 'hostile' && a.physics && a.physics.on && a.events.length > 0", timeout=20000)
        assert h("block") in page.text_content("#events")
        nothing_ran(page)
        page.select_option("#scene-select", "")

        # the arm: the virtual Nano is an MK2, not this robot: it says so, naming both as text
        page.select_option("#arm-port", "page:virtual")
        page.click("#arm-connect")
        pg.wait("a.arm.error !== ''", timeout=30000)
        assert f"the studio shows the {h('Robot')}" in page.text_content("#arm-state")
        assert pg.hook("a.arm.connected") is False and pg.hook("a.arm.configurable") is True
        # the MK2 shown: the Nano is that robot, driven at once; a line of markup sent, refused,
        # shown as text on both sides
        page.select_option("#robot-select", "mk2plus")
        pg.wait("a.robot.name === 'MK2 Plus'")
        pg.wait("a.arm.connected && a.arm.status !== null", timeout=30000)
        line = "L 0 <img src=x onerror=window.__pwned=1>"
        page.fill("#arm-line", line)
        page.click("#arm-send")
        pg.wait(f"a.arm.reply && a.arm.reply.line === {json.dumps(line)}", timeout=15000)
        assert line in page.text_content("#arm-reply")
        nothing_ran(page)
        assert pg.errors == []
    finally:
        pg.close()


def test_the_site_has_a_content_security_policy(browser, site):
    """Scripts from the site only, WebAssembly allowed, nothing inline: an inline script or
    handler injected into the page is blocked and reported."""
    pg = Page(browser, f"{site.url}?robot=mk2plus", init_script=WATCH)
    try:
        csp = pg.page.get_attribute('meta[http-equiv="Content-Security-Policy"]', "content")
        assert "script-src 'self' 'wasm-unsafe-eval'" in csp and "'unsafe-inline'" not in csp and "object-src 'none'" in csp
        # the page works under it: the engine (WebAssembly in its worker) answered, the arm is drawn
        assert pg.hook("a.pose.tool.xyz")[0] == pytest.approx(235)
        # what it blocks: an injected inline handler and an inline script
        pg.page.evaluate("""() => {
            const d = document.createElement('div');
            d.innerHTML = '<img src="data:," onerror="window.__pwned=1">';
            document.body.appendChild(d);
            const s = document.createElement('script');
            s.textContent = 'window.__pwned = 2';
            document.body.appendChild(s);
        }""")
        pg.page.wait_for_function("() => window.__violations.length >= 2")
        assert pg.page.evaluate("window.__pwned") == 0
        assert all("script-src" in v for v in pg.page.evaluate("window.__violations"))
    finally:
        pg.close(csp_refusals_expected=True)  # the two refusals above are the test
