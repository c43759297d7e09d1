"""Articula Studio in a real browser: the static site (its engine in the page) - the sliders,
the IK, programs, robot files and meshes, physics, bad messages - and articula-studio, which
serves the same site and connects the arm. The screenshots in docs/img/studio-*.png are taken
here."""

from __future__ import annotations

import contextlib
import json
import re
import subprocess

import numpy as np
import pytest

from conftest import FAST, PATIENCE, REPO, SHOTS, cli_json, cli_path, wait_with_progress



def test_the_static_site_loads_without_errors_and_shows_the_arm(open_page, site):
    """Served by a plain file server under a sub-path of another name, no articula process."""
    pg = open_page("mk2plus", tour=True, query="&quality=high")  # antialiased, full size: a screenshot for the docs
    assert pg.page.url.startswith(f"http://127.0.0.1:{site.port}/articula-site/")
    # the first-run tour: five steps, the last the exercises
    assert pg.page.is_visible("#tour")
    assert pg.page.text_content("#tour-step") == "1 of 5"
    assert "right-drag" in pg.page.text_content("#tour-text")  # a mouse's words
    for _ in range(4):
        pg.page.click("#tour-next")
    assert pg.page.text_content("#tour-step") == "5 of 5"
    assert "exercises" in pg.page.text_content("#tour-text")
    pg.page.click("#tour-next")
    assert not pg.page.is_visible("#tour")
    pg.page.wait_for_timeout(500)
    share = pg.hook("a.armPixels()")
    assert share > 0.02, f"the arm's colours cover {share:.3%} of the view"
    pg.page.screenshot(path=str(SHOTS / "studio-mk2.png"))
    assert pg.hook("a.robot.name") == "MK2 Plus"
    np.testing.assert_allclose(pg.hook("a.pose.tool.xyz"), [235, 0, 213], atol=1e-9)
    # the arm panel offers the virtual Nano, and a Nano on USB through Web Serial (Chromium has it)
    assert "Connect the virtual Nano" in pg.page.text_content("#arm-state")
    assert pg.errors == []


def test_without_web_serial_the_arm_panel_says_so_and_offers_the_virtual_nano(browser, site):
    ctx = browser.new_context(viewport={"width": 1600, "height": 900})
    ctx.add_init_script("localStorage.setItem('articula.studio.tour.done', '1')")
    ctx.add_init_script("Object.defineProperty(Navigator.prototype, 'serial', { get: () => undefined })")
    try:
        page = ctx.new_page()
        page.goto(site.url + "?robot=mk2plus")
        page.wait_for_function("() => window.articula && window.articula.ready", timeout=20000 * PATIENCE)
        assert page.text_content("#arm-state") == (
            "This browser has no Web Serial (Chrome, Edge and Opera have it): the virtual Nano runs the firmware here.")
        assert page.eval_on_selector_all("#arm-port option", "os => os.map(o => o.value)") == ["page:virtual"]
    finally:
        ctx.close()


def test_the_site_works_offline_once_loaded_and_is_installable(open_page, site):
    pg = open_page("panda", service_worker=True)
    assert pg.page.evaluate("navigator.serviceWorker.ready.then(() => true)")
    pg.page.wait_for_function("() => caches.keys().then(ks => ks.some(k => k.startsWith('articula-studio-')))")
    manifest = pg.page.evaluate("fetch('manifest.webmanifest').then(r => r.json())")
    assert manifest["name"] == "Articula Studio" and manifest["start_url"] == "./"
    # the server goes away: the page reloads from what the service worker kept, and works
    pg.page.reload()
    pg.wait("a.ready && a.firstFrameAt > 0")
    pg.context.set_offline(True)
    pg.page.reload()
    pg.wait("a.ready && a.firstFrameAt > 0", timeout=20000)
    assert pg.hook("a.robot.name").startswith("Franka")
    pg.page.fill('#joints input[type=number][data-joint="0"]', "20")
    pg.wait("Math.abs(a.pose.q[0] - 20) < 1e-9")
    pg.context.set_offline(False)


def test_articula_studio_prints_its_address_first_and_serves_the_same_site(open_served_page):
    pg = open_served_page("panda")
    s = pg.server
    assert s.first_line == f"studio: http://127.0.0.1:{s.port}/?token={s.token}&robot=panda"
    assert pg.hook("a.robot.name").startswith("Franka")
    assert pg.errors == []


def test_a_slider_moves_the_tool_to_what_articula_fk_gives(open_page):
    pg = open_page("mk2plus")
    # the shoulder's number box, then the elbow's slider (a range input set as a user drags it)
    pg.page.fill('#joints input[type=number][data-joint="1"]', "60")
    pg.wait("Math.abs(a.pose.q[1] - 60) < 1e-9")
    pg.page.evaluate("""() => { const s = document.querySelector('#joints input[type=range][data-joint="2"]');
        s.value = '-80'; s.dispatchEvent(new Event('input')); }""")
    pg.wait("Math.abs(a.pose.q[2] + 80) < 1e-9")
    pg.page.fill('#joints input[type=number][data-joint="0"]', "30")
    pg.wait("Math.abs(a.pose.q[0] - 30) < 1e-9")
    doc = cli_json("fk", "mk2plus", "--q", "30,60,-80")
    np.testing.assert_allclose(pg.hook("a.pose.tool.xyz"), doc["tool"]["position"], atol=1e-6)
    np.testing.assert_allclose(pg.hook("a.pose.tool.rpy"), doc["tool"]["rpy"], atol=1e-6)
    # the DH table follows: theta4 = -(theta2 + theta3) on the linked row
    np.testing.assert_allclose(pg.hook("a.pose.dh_table.map(r => r[3])"), [30, 60, -80, 20], atol=1e-9)
    assert pg.page.text_content("#dh tbody tr:nth-child(4) td:nth-child(5)") == "20.00"
    # each of the three moves timed from input to frame (a loaded machine draws the last late)
    pg.wait("a.latency.length >= 3")
    assert pg.errors == []


def test_ik_reaches_a_typed_target_on_the_panda_and_follows_a_drag(open_page):
    pg = open_page("panda", query="&quality=high")
    pg.page.fill("#tx", "400")
    pg.page.fill("#ty", "100")
    pg.page.fill("#tz", "500")
    pg.page.check("#use-rpy")
    pg.page.fill("#troll", "180")
    pg.page.fill("#tpitch", "0")
    pg.page.fill("#tyaw", "0")
    pg.page.click("#solve")
    pg.wait("a.ik && a.ik.status === 'reached'")
    np.testing.assert_allclose(pg.hook("a.pose.tool.xyz"), [400, 100, 500], atol=0.011)
    assert "Reached" in pg.page.text_content("#ik-status")
    # drag the target with the mouse: the arm follows
    pg.page.uncheck("#use-rpy")
    pg.page.check("#show-target")
    pg.page.wait_for_timeout(300)
    x, y = pg.hook("a.targetScreen")
    before = pg.hook("a.pose.tool.xyz")
    pg.page.mouse.move(x, y)
    pg.page.mouse.down()
    for k in range(1, 21):
        pg.page.mouse.move(x - 3 * k, y + 2 * k)
        pg.page.wait_for_timeout(16)
    pg.page.mouse.up()
    pg.wait("a.ik && a.ik.status === 'reached'")
    pg.page.wait_for_timeout(300)
    after = pg.hook("a.pose.tool.xyz")
    assert np.linalg.norm(np.subtract(after, before)) > 20, (before, after)
    assert pg.hook("a.ikUpdates.length") >= 5
    target = [float(pg.page.input_value(f"#t{c}")) for c in "xyz"]
    np.testing.assert_allclose(after, target, atol=0.06)  # the inputs show the target to 0.1 mm
    pg.page.check("#show-axes")
    pg.page.wait_for_timeout(300)
    pg.page.screenshot(path=str(SHOTS / "studio-panda-ik.png"))
    assert pg.errors == []


def test_a_point_beyond_the_mk2s_reach_is_unreachable(open_page):
    pg = open_page("mk2plus")
    for k, v in zip("xyz", (600, 0, 100)):
        pg.page.fill(f"#t{k}", str(v))
    pg.page.click("#solve")
    pg.wait("a.ik && a.ik.status === 'unreachable'")
    text = pg.page.text_content("#ik-status")
    assert text == "Unreachable: it is farther than the arm is long; the nearest the tool comes is 259.9 mm away.", text
    # the thesis's Jacobian transpose, animated: frames come one iteration at a time
    # (the MK2's elbow limit holds it 12.3 mm short of this one, as the whole solve says)
    for k, v in zip("xyz", (200, 50, 100)):
        pg.page.fill(f"#t{k}", str(v))
    pg.page.click("#animate-jt")
    pg.wait("a.ik && a.ik.type === 'jt_frame' && a.ik.iteration >= 5")
    pg.wait("a.ik && a.ik.done === true", timeout=30000)
    assert pg.hook("a.ik.status") == "limited"
    assert pg.hook("a.ik.limited_by") == ["elbow"]
    assert "Stopped: held back by the elbow " in pg.page.text_content("#ik-status")


def test_demo_program_ends_on_the_predicted_steps_and_teach_re_runs_to_the_pose(open_page):
    pg = open_page("mk2plus", query="&quality=high")
    pg.page.select_option("#program-select", "demo.arm")
    pg.page.wait_for_function("() => document.querySelector('#editor').value.includes('P 200 -150 150')")
    pg.page.click("#run")
    # It plays (a busy machine may draw no frame while its 3.3 s play, and see it only ended)
    pg.wait("a.timeline !== null && (a.playing === true || a.pose.t > 0)")
    pg.page.wait_for_timeout(1500)
    pg.page.screenshot(path=str(SHOTS / "studio-program.png"))
    pg.wait("a.playing === false && a.pose.t >= a.timeline.duration - 1e-9", timeout=20000)
    predicted = cli_json("predict", "mk2plus", "programs/demo.arm")
    assert pg.hook("a.pose.steps") == predicted["records"][-1]["steps"]
    assert pg.hook("a.timeline.records.length") == len(predicted["records"])
    # Teach: move the arm, record the pose, run the taught line alone: the same pose
    pg.page.fill('#joints input[type=number][data-joint="0"]', "-25.5")
    pg.wait("Math.abs(a.pose.q[0] + 25.5) < 1e-9")
    taught_q = pg.hook("a.pose.q")
    pg.page.click("#teach")
    pg.wait("a.teach.startsWith('M ')")
    line = pg.hook("a.teach")
    assert pg.page.input_value("#editor").rstrip().endswith(line)
    pg.page.fill("#editor", line + "\n")
    pg.page.click("#run")
    pg.wait("a.timeline !== null && a.playing === false && a.pose.t >= a.timeline.duration - 1e-9", timeout=20000)
    ideal = pg.hook("a.timeline.records[0].q_ideal")
    np.testing.assert_allclose(ideal, taught_q, atol=1e-3)
    assert pg.errors == []


def test_a_rejected_line_shows_its_error_and_meaning(open_page):
    pg = open_page("mk2plus")
    pg.page.fill("#editor", "L 0 10\nL 1 150\n")
    pg.page.click("#step")
    pg.wait("a.timeline !== null")
    text = pg.page.text_content("#program-status")
    assert "line 2: L 1 150 → error:9, target beyond a joint limit: nothing moves" in text
    pg.page.fill("#editor", "L 0 10\nL 0 1e3\n")
    pg.page.click("#step")
    pg.wait("a.programError !== ''")
    assert pg.hook("a.programError").startswith("program.arm:2:")


def test_a_malformed_robot_file_keeps_the_robot_and_says_why(open_page, tmp_path):
    pg = open_page("mk2plus")
    doc = json.loads((REPO / "robots" / "mk2plus.json").read_text())
    doc["dh"][1]["theta"]["min"] = 200
    bad = tmp_path / "bad-arm.json"
    bad.write_text(json.dumps(doc))
    pg.page.set_input_files("#robot-file", str(bad))
    pg.wait("a.robotError !== ''")
    assert pg.hook("a.robotError") == "bad-arm.json: /dh/1/theta/min: limits inverted (min 200 > max 130)"
    assert pg.page.is_visible("#banner")
    assert "the robot stays MK2 Plus" in pg.page.text_content("#banner-text")
    assert pg.hook("a.robot.name") == "MK2 Plus"
    # a good one loads
    pg.page.set_input_files("#robot-file", str(REPO / "robots" / "puma560.json"))
    pg.wait("a.robot.name.startsWith('PUMA')")
    # a thesis appendix C file, through the legacy importer with its scale
    pg.page.once("dialog", lambda d: d.accept("10"))
    pg.page.set_input_files("#robot-file", str(REPO / "docs" / "examples" / "thesis-example.legacy.txt"))
    pg.wait("a.robot.import_notes.length === 28")
    assert pg.errors == []


def test_bad_messages_to_the_engine_get_error_replies_and_it_keeps_working(open_page):
    pg = open_page("mk2plus")
    before = pg.hook("a.errors")
    pg.page.evaluate("""() => {
        for (const m of ['garbage', [1, 2], {type: 7}, {type: 'set_joint', joint: 9, value: 1},
                         {type: 'set_joint', joint: 0, value: NaN}, {type: 'ik', target: [1, 2]},
                         {type: '__proto__'}, {type: 'seek', t: 5}, {type: 'load_robot', name: '../../etc/passwd'}])
          window.articula.engineSend(m);
    }""")
    pg.wait(f"a.errors >= {before + 9}")
    assert pg.hook("a.internalErrors") == []
    # each got its own reply, in order, naming what is wrong
    assert pg.hook("a.errorLog.slice(-9)") == [
        "a message is an object with a 'type'", "a message is an object with a 'type'", "unknown message type 7",
        "'joint' must be within 0 .. 2", "'value' must be a finite number", "'target' must be a list of 3 or 6 numbers",
        "unknown message type '__proto__'", "no program loaded: send program_load first", "no shipped robot '../../etc/passwd'"]
    pg.page.fill('#joints input[type=number][data-joint="0"]', "12")
    pg.wait("Math.abs(a.pose.q[0] - 12) < 1e-9")
    # what is not a number in a box (NaN, as the page reads it) moves nothing
    errors = pg.hook("a.errors")
    pg.page.evaluate("""() => { const s = document.querySelector('#joints input[type=number][data-joint="1"]');
        s.value = ''; s.dispatchEvent(new Event('input')); }""")
    pg.page.evaluate("document.querySelector('#tx').value = ''")
    pg.page.click("#solve")
    # the IK panel says so itself, and sends nothing
    assert pg.page.text_content("#ik-status") == "x holds no number: type one, like 150."
    assert pg.hook("a.errors") == errors
    assert pg.hook("a.pose.q[1]") == pytest.approx(90)
    assert pg.hook("a.internalErrors") == []


def test_the_server_holds_no_arm_and_serves_only_the_site_to_its_own_host(server_factory):
    """articula-studio serves files and nothing else: no WebSocket, no arm, no session (the
    page drives the arm itself); a foreign Host (DNS rebinding) gets nothing."""
    import asyncio
    from concurrent.futures import ThreadPoolExecutor

    import aiohttp

    s = server_factory("mk2plus")

    async def get(path, headers=None):
        async with aiohttp.ClientSession() as http:
            async with http.get(f"http://127.0.0.1:{s.port}{path}", headers=headers or {}) as r:
                return r.status

    def run(coro):  # its own thread: Playwright's loop may be running in this one
        with ThreadPoolExecutor(1) as ex:
            return ex.submit(asyncio.run, coro).result()

    assert run(get("/")) == 200
    assert run(get("/engine/engine.wasm")) == 200
    assert run(get("/data/firmware/articula-nano.hex")) == 200
    assert run(get(f"/ws?token={s.token}")) == 404  # no WebSocket: nothing on the server moves an arm
    assert run(get("/", {"Host": f"evil.example:{s.port}"})) == 403
    assert run(get("/../../etc/passwd")) == 404
    assert run(get("/%2e%2e/%2e%2e/etc/passwd")) == 404
    assert run(get(f"/t/wrong/files/{'x' * 5}.json")) == 403


def test_the_first_arm_tutorials_files_load_and_show_their_frames(open_page):
    """docs/studio.md, "Your first arm": each step's robot file opens in the studio."""
    pg = open_page("mk2plus", query="&quality=high")
    pg.page.check("#show-axes")
    steps = sorted((REPO / "docs" / "examples" / "first-arm").glob("step*.json"))
    assert len(steps) == 3
    for i, path in enumerate(steps, 1):
        pg.page.set_input_files("#robot-file", str(path))
        pg.wait(f"a.robot.name === 'First arm, step {i}'")
        pg.page.wait_for_timeout(600)
        assert pg.hook("a.robot.num_rows") == i + 1
        if i in (1, 3):
            pg.page.screenshot(path=str(SHOTS / f"studio-first-arm-{i}.png"))
    # step 3 is the MK2's kinematics: the same tool pose at the same joint values
    pg.page.fill('#joints input[type=number][data-joint="1"]', "90")
    pg.page.fill('#joints input[type=number][data-joint="2"]', "-90")
    pg.page.fill('#joints input[type=number][data-joint="0"]', "0")
    pg.wait("Math.abs(a.pose.q[0]) < 1e-9 && Math.abs(a.pose.q[2] + 90) < 1e-9")
    np.testing.assert_allclose(pg.hook("a.pose.tool.xyz"), [235, 0, 213], atol=1e-9)
    assert pg.errors == []


def test_a_robot_with_a_mesh_shape_draws_it(open_page):
    """A link shape from an STL file, opened with its robot file from the user's disk (the File
    API): both stay in the browser."""
    data = REPO / "host" / "physics" / "tests" / "data"
    pg = open_page("mk2plus")
    # the robot file alone: it names a mesh that was not opened
    pg.page.set_input_files("#robot-file", str(data / "mesh-arm.json"))
    pg.wait("a.robotError !== ''")
    assert "cube20.stl was not opened" in pg.hook("a.robotError")
    assert pg.hook("a.robot.name") == "MK2 Plus"
    pg.page.set_input_files("#robot-file", [str(data / "mesh-arm.json"), str(data / "cube20.stl")])
    pg.wait("a.robot.links.some(l => l.shapes.some(x => x.type === 'mesh'))")
    url = pg.hook("a.robot.links.flatMap(l => l.shapes).find(x => x.type === 'mesh').url")
    assert url.startswith("blob:"), url
    pg.page.wait_for_timeout(500)
    assert pg.hook("a.armPixels()") > 0.02
    assert pg.errors == []


def test_articula_studio_serves_the_robot_file_it_was_given_with_its_mesh(open_served_page):
    pg = open_served_page(str(REPO / "host" / "physics" / "tests" / "data" / "mesh-arm.json"))
    pg.wait("a.robot && a.robot.name === 'MK2 with a mesh hand'")
    pg.wait("a.robot.links.some(l => l.shapes.some(x => x.type === 'mesh'))")
    pg.page.wait_for_timeout(500)
    assert pg.hook("a.armPixels()") > 0.02
    assert pg.errors == []
    status = pg.page.evaluate(f"fetch('t/{pg.server.token}/files/cube20.stl').then(r => r.status)")
    assert status == 200
    assert pg.page.evaluate("fetch('t/wrong/files/cube20.stl').then(r => r.status)") == 403


def test_a_robosim_program_plays_and_the_time_line_exports_as_csv(open_page):
    pg = open_page("mk2plus")
    pg.page.select_option("#program-select", "robosim-example.robosim")
    pg.page.wait_for_function("() => document.querySelector('#editor').value.length > 0")
    pg.page.click("#step")
    pg.wait("a.timeline !== null")
    assert pg.hook("a.timeline.format") == "robosim"
    predicted = cli_json("predict", "mk2plus", "programs/robosim-example.robosim")
    assert pg.hook("a.timeline.records.map(r => r.steps)") == [r["steps"] for r in predicted["records"]]
    with pg.page.expect_download() as d:
        pg.page.click("#export-csv")
    text = open(d.value.path()).read().splitlines()
    # the path the arm takes (issue 28, what a class hit, 8): the time line's samples, not each
    # command's end joined; each line's command and reply on its first row
    assert text[0] == "t_s,line,command,reply,joint_base,joint_shoulder,joint_elbow,tool_x,tool_y,tool_z"
    samples = pg.hook("a.timeline.samples")
    rows = [r.split(",") for r in text[1:]]
    assert len(rows) == len(samples["t"]) > 2 * len(predicted["records"])
    assert [float(r[0]) for r in rows] == samples["t"] and [int(r[1]) for r in rows] == samples["line"]
    assert [float(r[7]) for r in rows] == samples["tool"][0]
    lines = [int(r[1]) for r in rows]
    assert lines == sorted(lines)
    named = [(int(r[1]), r[2], r[3]) for r in rows if r[2]]
    assert named == [(rec["line"], rec["command"], rec["reply"]) for rec in predicted["records"] if rec["line"] in lines]
    with pg.page.expect_download() as d:
        pg.page.click("#export-png")
    assert open(d.value.path(), "rb").read(8) == b"\x89PNG\r\n\x1a\n"


def test_an_adjustable_link_length_has_its_slider(open_page, tmp_path):
    """RoboSim's l: a row whose a(i-1) has a range gets a length slider."""
    import sys
    sys.path.insert(0, str(REPO / "python"))
    import articula

    doc = json.loads((REPO / "docs" / "examples" / "first-arm" / "step2-elbow.json").read_text())
    doc["dh"][2]["a"] = {"value": 135, "min": 100, "max": 200}
    path = tmp_path / "adjustable.json"
    path.write_text(json.dumps(doc))
    pg = open_page("mk2plus")
    pg.page.set_input_files("#robot-file", str(path))
    pg.wait("a.robot.name === 'First arm, step 2'")
    try:
        pg.page.fill('#joints input[type=number][data-length="3"]', "180")
        pg.page.press('#joints input[type=number][data-length="3"]', "Enter")
        pg.wait("a.pose.dh_table[2][0] === 180")
        want = articula.Robot.load(str(path)).with_link_lengths([180]).fk(pg.hook("a.pose.q"))
        np.testing.assert_allclose(pg.hook("a.pose.tool.xyz"), want[:3, 3], atol=1e-9)
        assert pg.errors == []
    finally:
        pg.close()


# ---- live physics


def _physics_page(open_page, robot, scene, query=""):
    pg = open_page(robot, query=f"&scene={scene}{query}")
    pg.wait("a.physics && a.physics.on && a.physics.objects.length > 0")
    return pg


def test_a_dragged_object_moves_and_falls_back_to_rest(open_page):
    pg = _physics_page(open_page, "mk2plus", "push")
    try:
        pg.page.wait_for_timeout(500)
        z0 = pg.hook("a.physics.objects.find(o => o.name === 'box').pose[11]")
        assert z0 == pytest.approx(40, abs=1)
        x, y = pg.hook("a.objectScreen('box')")
        pg.page.mouse.move(x, y)
        pg.page.mouse.down()
        for k in range(1, 16):
            pg.page.mouse.move(x, y - 6 * k)
            pg.page.wait_for_timeout(30)
        # lifted by the pull (however fast this machine steps the world: a busy one takes longer)
        pg.wait(f"a.physics.objects.find(o => o.name === 'box').pose[11] > {z0 + 30}", timeout=15000)
        pg.page.mouse.up()
        # let go: it falls and comes to rest on the ground, upright (the speed against real time
        # is bench_studio.py's to measure, not a test's)
        pg.wait("(() => { const p = a.physics.objects.find(o => o.name === 'box').pose; "
                "return Math.abs(p[11] - 40) < 1.5 && Math.abs(p[10] - 1) < 0.01; })()", timeout=20000)
        t = pg.hook("a.physics.t")
        # still running (a world at rest tells the page its clock once a second), and the box
        # stays put
        pg.wait(f"a.physics.t > {t}", timeout=5000)
        rest = pg.hook("a.physics.objects.find(o => o.name === 'box').pose")
        assert rest[11] == pytest.approx(40, abs=1.5) and abs(rest[10] - 1) < 0.01
        assert pg.errors == []
    finally:
        pg.close()


def test_grasp_and_lift_in_the_studio_as_articula_sim_does(open_page, tmp_path):
    subprocess.run([cli_path(), "sim", "mk2plus", "programs/grasp-and-lift.arm", "--scene", "grasp-and-lift",
                          "--sample", "0", "--json", "--events", str(tmp_path / "ev.jsonl")],
                         capture_output=True, text=True, cwd=REPO, timeout=60)
    cli_events = [json.loads(line) for line in (tmp_path / "ev.jsonl").read_text().splitlines()]
    pg = _physics_page(open_page, "mk2plus", "grasp-and-lift", "&quality=high")
    try:
        pg.page.select_option("#program-select", "grasp-and-lift.arm")
        pg.page.wait_for_function("() => document.querySelector('#editor').value.includes('G 0')")
        # the picture while it carries the block up: the program loaded (the program's Step),
        # the world stepped 0.1 s at a time to 1.5 s (the same simulation whatever the
        # machine's speed), then Run plays the rest
        pg.page.click("#step")
        pg.wait("a.timeline !== null && a.physics.running === false")
        while pg.hook("a.physics.t") < 1.5:
            t = pg.hook("a.physics.t")
            pg.page.click("#phys-step")
            pg.wait(f"a.physics.t > {t}")
        assert pg.hook("a.physics.objects[0].carried")
        pg.page.screenshot(path=str(SHOTS / "studio-grasp.png"))
        pg.page.click("#run")
        pg.wait("a.physics.t > 3.4 && !a.physics.busy", timeout=20000)
        kinds = pg.hook("a.events.map(e => e.kind)")
        assert "grasp" in kinds and "release" in kinds
        # it carried the block up: the gripper let it go high above where it took it (50 mm)
        released = pg.hook("a.events.find(e => e.kind === 'release').point_mm")
        assert released[2] > 100, released
        # the same simulation: the same events at the same times as articula sim
        studio = pg.hook("a.events.filter(e => e.t <= 3.0).map(e => [e.kind, e.a, e.b, e.t])")
        want = [[e["kind"], e["a"], e["b"], e["t"]] for e in cli_events if e["t"] <= 3.0]
        assert studio == want
        block = pg.hook("a.physics.objects[0].pose")
        assert block[11] == pytest.approx(49.8, abs=0.5)
        assert pg.errors == []
    finally:
        pg.close()


def test_a_page_drawing_5_frames_a_second_gets_the_worlds_state_at_most_10_times_a_second(open_page):
    """?fps=5 (a slow computer; every test here): the live physics steps as often as ever, and
    sends the page its state at most twice a frame (docs/studio.md): each state costs the page
    a layout of its readouts, at every display frame about three times the page's CPU time."""
    pg = _physics_page(open_page, "mk2plus", "grasp-and-lift", "&fps=5")
    try:
        pg.page.select_option("#program-select", "grasp-and-lift.arm")
        pg.page.wait_for_function("() => document.querySelector('#editor').value.includes('G 0')")
        pg.page.click("#run")
        pg.wait("a.physics.running && a.physics.t > 0.2")
        # two seconds of the page's clock: the messages that came (a pose and a world state each)
        # and the world's time they carried
        m, t, wall = pg.page.evaluate("""() => new Promise((done) => {
            const a = window.articula, m0 = a.stream.messages, t0 = a.physics.t, w0 = performance.now();
            setTimeout(() => done([a.stream.messages - m0, a.physics.t - t0, (performance.now() - w0) / 1000]), 2000);
        })""")
        states = m / 2 / wall
        assert states <= 12, f"{states:.1f} states a second at ?fps=5"
        assert t > 0.1 and states >= 2, (m, t, wall)  # the world ran, and the page heard of it
    finally:
        pg.close()


def test_a_thousand_random_and_malformed_messages_never_break_the_engine(open_page):
    """Each is answered (an error reply, or what a valid one gets) in order; none is an internal
    error; the page keeps working."""
    pg = open_page("mk2plus")
    pg.page.evaluate("""() => {
        let seed = 12345;
        const rnd = () => (seed = (seed * 1103515245 + 12345) % 2147483648) / 2147483648;
        const pick = a => a[Math.floor(rnd() * a.length)];
        const types = ['hello', 'set_joint', 'set_joints', 'ik', 'jt_animate', 'home', 'zero', 'gripper',
          'program_load', 'play', 'pause', 'step', 'seek', 'rewind', 'teach', 'load_robot', 'scene', 'drag',
          'release', 'physics_run', 'export_urdf', 'arm_read', 'arm_predict', 'set_lengths', 'stop_animation', 'nonsense', '',
          null, 7, 'constructor', 'toString'];
        const values = [null, true, -1, 0, 1e308, -1e308, 3.5, NaN, Infinity, 'x', '', [], [1, 2, 3], [NaN], {}, {a: 1},
          'L 0 10', 'L 0 1e3', '\u0000\u00ff', 'a'.repeat(5000), 'push', 'mk2plus', 'demo.arm'];
        const keys = ['joint', 'value', 'q', 'target', 'solver', 'weights', 'percent', 'text', 'name', 't', 'speed',
          'format', 'filename', 'legacy', 'scale', 'object', 'code', 'seq', 'values', 'files', 'line', 'history'];
        for (let i = 0; i < 1000; i++) {
          const r = rnd();
          if (r < 0.15) { window.articula.engineSend(String.fromCharCode(...Array.from({length: 1 + Math.floor(rnd() * 40)}, () => Math.floor(rnd() * 256)))); continue; }
          const m = {type: pick(types)};
          for (let k = 0; k < Math.floor(rnd() * 4); k++) m[pick(keys)] = pick(values);
          window.articula.engineSend(m);
        }
        window.articula.engineSend({type: 'arm_read', line: '<Idle|S:0,0,0|A:0.000,90.000,0.000|G:0|Q:8|C:1>'});
    }""")
    pg.wait("a.errors > 300", timeout=60000)
    pg.page.wait_for_timeout(1000)
    assert pg.hook("a.internalErrors") == []
    # the page still works
    pg.page.select_option("#scene-select", "")
    pg.page.select_option("#robot-select", "mk2plus")
    pg.wait("a.robot.name === 'MK2 Plus'")
    pg.page.fill('#joints input[type=number][data-joint="0"]', "7")
    pg.wait("Math.abs(a.pose.q[0] - 7) < 1e-9")
    pg.page.reload()
    pg.wait("a.ready && a.firstFrameAt > 0")


def test_a_50_mb_mesh_is_refused_and_the_robot_stays(open_page, tmp_path):
    big = tmp_path / "huge.stl"
    with open(big, "wb") as f:
        f.truncate(50_000_000)
    pg = open_page("mk2plus")
    pg.page.set_input_files("#robot-file", [str(REPO / "host" / "physics" / "tests" / "data" / "mesh-arm.json"), str(big)])
    pg.page.wait_for_function("() => !document.querySelector('#banner').hidden")
    assert "larger than 20 MB" in pg.page.text_content("#banner-text")
    assert pg.hook("a.robot.name") == "MK2 Plus"
    pg.page.fill('#joints input[type=number][data-joint="0"]', "5")
    pg.wait("Math.abs(a.pose.q[0] - 5) < 1e-9")


# ---- the arm in the loop: the virtual Nano (the real firmware ELF in simavr)


def _refused_on_both_sides(pg):
    """A line the arm refuses: its error and its meaning, and the model says the same."""
    pg.page.fill("#arm-line", "L 1 150")
    pg.page.press("#arm-line", "Enter")
    pg.wait("a.arm.reply && a.arm.reply.line === 'L 1 150'", timeout=15000)
    reply = pg.hook("a.arm.reply")
    assert reply["reply"] == "error:9" and reply["meaning"] == "target beyond a joint limit"
    assert reply["predicted"]["reply"] == "error:9"
    assert "error:9 (target beyond a joint limit)" in pg.page.text_content("#arm-reply")


# ---- the arm in the page: the firmware's hex on avr8js (the virtual Nano), and Web Serial


def _connect_page_nano(pg, port="page:virtual"):
    pg.page.select_option("#arm-port", port)
    pg.page.click("#arm-connect")
    pg.wait("a.arm.connected && a.arm.status !== null", timeout=30000)


def _send(pg, line):
    pg.page.fill("#arm-line", line)
    pg.page.click("#arm-send")
    pg.wait(f"a.arm.reply && a.arm.reply.line === {json.dumps(line)}", timeout=15000)
    return pg.hook("a.arm.reply")


def test_the_virtual_nano_in_the_page(open_page):
    """The static site alone: the firmware's own hex runs in the page (avr8js) beside the model."""
    # the page's default quality: on a software renderer, full quality would take the CPU the
    # emulator needs to keep real time (the panel would say so)
    pg = open_page("mk2plus")
    assert "page:virtual" in pg.page.eval_on_selector_all("#arm-port option", "os => os.map(o => o.value)")
    _connect_page_nano(pg)
    assert pg.hook("a.arm.label").startswith("MK2 Plus (firmware ")  # its I banner names the robot shown
    assert pg.hook("a.arm.status.steps") == [0, 0, 0]
    reply = _send(pg, "L 0 10")
    assert reply["reply"] == "ok" and reply["predicted"]["reply"] == "ok"
    pg.wait("a.arm.status.state === 'Idle' && a.arm.status.steps[0] === 32", timeout=20000)
    assert pg.hook("a.arm.status.steps") == reply["predicted"]["steps"] == [32, 0, 0]
    pg.wait("a.arm.nano !== null && a.arm.nano.steps[0] === 32")  # its coils turned the base 32 steps
    assert pg.hook("a.arm.nano.faults") == 0
    # its servo pulse read back as the harness reads it (shared/articula/servo.h): the aperture asked for
    assert _send(pg, "G 40")["reply"] == "ok"
    pg.wait("a.arm.nano.gripper !== null && Math.abs(a.arm.nano.gripper - 40) < 1", timeout=10000)
    # (the pulse's edges carry the interrupt's entry latency, a few us: 40.6 % shows as 41)
    shown = re.search(r"gripper (\d+) %", pg.page.text_content("#arm-speed"))
    assert shown and abs(int(shown.group(1)) - 40) <= 1, pg.page.text_content("#arm-speed")
    _refused_on_both_sides(pg)
    assert "real time" in pg.page.text_content("#arm-speed")
    pg.page.screenshot(path=str(SHOTS / "studio-page-nano.png"))
    assert pg.errors == []


def test_a_robot_on_step_dir_drivers_gets_the_cnc_shield_build(open_page):
    """robots/mk2plus-cnc.json (A4988s at 1/8 step in a CNC shield): the flash panel offers the
    build for a CNC shield, and the virtual Nano sits on one and runs it (the shield's STEP/DIR
    pins decoded): a fresh one is the MK2 Plus CNC, and L 0 10 pulses the X socket's driver the
    253 steps the model predicts. Back on the MK2 Plus, the Nano's own build again."""
    pg = open_page("mk2plus-cnc")
    fw = pg.page.evaluate("fetch('data/firmware/firmware.json').then(r => r.json())")
    cnc = fw["builds"]["articula-cnc"]
    pg.wait("document.querySelector('#flash-info').textContent.includes('CNC shield')", timeout=15000)
    assert f"{cnc['bytes']:,} bytes: the build for a CNC shield" in pg.page.text_content("#flash-info")
    _connect_page_nano(pg)
    assert pg.hook("a.arm.label").startswith("MK2 Plus CNC (firmware ")
    reply = _send(pg, "L 0 10")
    assert reply["reply"] == "ok" and reply["predicted"]["steps"] == [253, 0, 0]
    pg.wait("a.arm.status.state === 'Idle' && a.arm.status.steps[0] === 253", timeout=20000)
    pg.wait("a.arm.nano !== null && a.arm.nano.steps[0] === 253")  # 253 STEP pulses, DIR high
    assert pg.hook("a.arm.nano.faults") == 0
    pg.page.click("#arm-disconnect")
    pg.wait("!a.arm.connected")
    pg.page.select_option("#robot-select", "mk2plus")
    pg.wait("a.robot.name === 'MK2 Plus'")
    pg.wait("!document.querySelector('#flash-info').textContent.includes('CNC')", timeout=15000)
    _connect_page_nano(pg)
    assert pg.hook("a.arm.label").startswith("MK2 Plus (firmware ")
    assert pg.errors == []


def test_a_servo_arm_gets_the_servo_build_and_its_pins_move_the_arm(open_page):
    """robots/mearm.json (four SG90s): the flash panel offers the servo build, and the virtual
    Nano runs it with its servos' pins read by the servo decoder: a fresh one is the meArm, and
    L 0 10 ends with the base servo's pulse 220 ticks (110 us) shorter, the steps the model
    predicts. The wiring view draws a signal wire to each servo."""
    pg = open_page("mearm")
    fw = pg.page.evaluate("fetch('data/firmware/firmware.json').then(r => r.json())")
    servo = fw["builds"]["articula-servo"]
    pg.wait("document.querySelector('#flash-info').textContent.includes('servo arms')", timeout=15000)
    assert f"{servo['bytes']:,} bytes: the build for servo arms" in pg.page.text_content("#flash-info")
    pg.wait("a.wiring.wires > 0", timeout=15000)
    assert pg.hook("a.wiring") == {"board": "nano", "firmware": "articula-servo", "wires": 7, "error": ""}
    _connect_page_nano(pg)
    assert pg.hook("a.arm.label").startswith("meArm (firmware ")
    reply = _send(pg, "L 0 10")
    assert reply["reply"] == "ok" and reply["predicted"]["steps"] == [-220, 0, 0]
    pg.wait("a.arm.status.state === 'Idle' && a.arm.status.steps[0] === -220", timeout=20000)
    # the base servo's pin: its pulse's ticks less its step-0 pulse, once a period shows it
    pg.wait("a.arm.nano !== null && a.arm.nano.steps[0] === -220", timeout=5000)
    assert pg.hook("a.arm.nano.faults") == 0
    assert pg.errors == []


def test_the_wiring_view_draws_every_wire_from_the_robot_file(open_page, tmp_path):
    """The arm panel's Wiring: every wire of the robot shown (the engine's wiring, from board.h),
    one line each, labelled with its pin and input; a file's names are text, never markup."""
    pg = open_page("mk2plus-cnc")
    pg.wait("a.wiring.wires > 0", timeout=15000)
    assert pg.hook("a.wiring") == {"board": "uno-cnc-v3", "firmware": "articula-cnc", "wires": 14, "error": ""}
    assert pg.page.eval_on_selector_all("#wiring line.wire", "ls => ls.length") == 14
    texts = pg.page.eval_on_selector_all("#wiring text", "ts => ts.map(t => t.textContent)")
    for t in ("Arduino Uno on a CNC Shield V3", "D2", "STEP", "socket X (A4988), base", "D8", "EN", "A3"):
        assert t in texts, (t, texts)
    # what the wires alone do not say: the motor supply, each driver's jumpers for the file's 1/8 step
    supply = pg.page.eval_on_selector_all("#wiring-supply li", "ls => ls.map(l => l.textContent)")
    assert supply[0].startswith("The shield's motor supply: 12 to 24 V"), supply
    assert supply[1].startswith("Each A4988 (base, shoulder and elbow motors): 1/8 step, its microstep jumpers on: MS1 and MS2;"), supply
    # ... and the top rate 1/8 step needs: $0=4000 (issue 55, 5)
    assert supply[2].startswith("At 1/8 step a motor turn is 1600 steps") and "send $0=4000" in supply[2], supply
    assert len(supply) == 3, supply
    pg.page.click("#wiring-box summary")
    pg.page.locator("#wiring-box").screenshot(path=str(SHOTS / "studio-wiring.png"))
    # a file whose motor is named like markup: drawn as the text it is
    arm = json.loads((REPO / "robots" / "mk2plus.json").read_text())
    arm["name"] = "Markup arm"
    arm["motors"][0]["name"] = '<img src=x onerror="window.pwned=1">'
    path = tmp_path / "markup-arm.json"
    path.write_text(json.dumps(arm))
    pg.page.set_input_files("#robot-file", str(path))
    pg.wait("a.robot.name === 'Markup arm'")
    pg.wait("a.wiring.board === 'nano' && a.wiring.wires === 19")  # serial, LED, gripper; 3 x (IN1..IN4, switch)
    texts = pg.page.eval_on_selector_all("#wiring text", "ts => ts.map(t => t.textContent)")
    assert 'L298N #0, <img src=x onerror="window.pwned=1">' in texts
    assert pg.page.eval_on_selector_all("#wiring img", "is => is.length") == 0
    assert pg.page.evaluate("window.pwned === undefined")
    assert pg.errors == []


def test_stop_ends_a_long_move_on_the_page_nano(open_page):
    """STOP in the middle of a move. The virtual Nano keeps real time whatever the page does, so
    the move is slow enough ($0 = 25 steps/s: about ten seconds) that the stop comes mid-way
    even when a busy machine delays the status reports, the test's polling and the click by
    seconds (a one-second move was over before the stop on a loaded machine)."""
    pg = open_page("mk2plus")
    _connect_page_nano(pg)
    for line in ("$0=25", "$1=20000", "M 80 90 0"):
        assert _send(pg, line)["reply"] == "ok"
    pg.wait("a.arm.status.state === 'Run' && a.arm.status.steps[0] > 0", timeout=15000)
    pg.page.click("#stop")
    pg.wait("a.arm.stopMs !== null", timeout=15000)
    assert pg.hook("a.arm.status.state") == "Idle"
    steps = pg.hook("a.arm.status.steps")
    assert 0 < steps[0] < 253, steps  # stopped short of the move's 253 steps
    # it stays there: the queue is empty, nothing more moves
    pg.page.wait_for_timeout(500)
    assert pg.hook("a.arm.status.steps") == steps and pg.hook("a.arm.status.state") == "Idle"


def test_run_says_where_it_runs_with_an_arm_connected(open_page):
    """With the Nano connected, Run drives it, and its face says so; the choice sits beside Run
    (not three swipes below); unticked, Run plays the model only and the status says the arm
    did not move. A legend names the teal arm (the arm as it reports itself)."""
    pg = open_page("mk2plus")
    assert pg.page.is_hidden("#drive-arm-row") and pg.page.is_hidden("#view-legend")
    _connect_page_nano(pg)
    pg.wait("a.runOnArm === true")
    # beside Run: the same row, on screen with it
    assert pg.page.evaluate("() => document.querySelector('#drive-arm-row').parentElement === document.querySelector('#run').parentElement")
    assert pg.page.is_checked("#drive-arm") and pg.page.inner_text("#drive-arm-row").strip() == "on the arm"
    assert "Send the program to the arm" in pg.page.get_attribute("#run", "title")
    assert pg.page.is_visible("#view-legend") and "as it reports itself" in pg.page.inner_text("#view-legend")
    # the model only: the arm stays where it is, and the status says so
    steps = pg.hook("a.arm.status.steps")
    pg.page.uncheck("#drive-arm")
    assert not pg.hook("a.runOnArm") and "the arm stays still" in pg.page.get_attribute("#run", "title")
    pg.page.fill("#editor", "L 0 20\n")
    pg.page.click("#run")
    pg.wait("a.timeline !== null && !a.playing && a.pose.t > 0")
    status = pg.page.inner_text("#program-status")
    assert "the arm did not move" in status, status
    assert pg.hook("a.arm.status.steps") == steps and pg.hook("a.arm.programLines") == []
    # on the arm again: it moves
    pg.page.check("#drive-arm")
    pg.page.click("#run")
    pg.wait("a.arm.programDone === true", timeout=30000)
    assert pg.hook("a.arm.programLines") == [[1, "ok"]]
    # closed: Run is the model's again, and the legend goes with the teal arm
    pg.page.click("#arm-disconnect")
    pg.wait("!a.arm.connected")
    assert pg.page.is_hidden("#drive-arm-row") and pg.page.is_hidden("#view-legend") and not pg.hook("a.runOnArm")


def test_a_program_drives_the_page_nano_to_the_predicted_steps(open_page, tmp_path):
    pg = open_page("mk2plus")
    _connect_page_nano(pg)
    text = "$0=2000\n$1=40000\nL 0 10\nL 1 150\nM -20 80 -10\nL 2 5\n"
    pg.page.fill("#editor", text)
    pg.page.check("#drive-arm")
    pg.page.click("#run")
    pg.wait("a.arm.programDone === true", timeout=60000)
    assert pg.hook("a.arm.programLines") == [[1, "ok"], [2, "ok"], [3, "ok"], [4, "error:9"], [5, "ok"], [6, "ok"]]
    program = tmp_path / "drive.arm"
    program.write_text(text)
    want = cli_json("predict", "mk2plus", str(program))["records"][-1]["steps"]
    pg.wait(f"a.arm.status.state === 'Idle' && JSON.stringify(a.arm.status.steps) === '{json.dumps(want, separators=(',', ':'))}'",
            timeout=20000)


def test_a_straight_line_on_the_page_nano_with_its_predicted_path_drawn(open_page, tmp_path):
    """A student types straight lines (T): the view draws the tool's predicted path at every
    step over the lines asked for, the status line says how close the path keeps to them, and
    the page's virtual Nano runs the lines to the predicted steps."""
    pg = open_page("mk2plus", query=FAST)
    text = "T 240 0 140 50\nT 280 -40 140 50\nT 280 40 140 50\n"
    pg.page.fill("#editor", text)
    pg.page.click("#run")  # the model plays it
    pg.wait("a.timeline !== null && a.timeline.records.length === 3 && a.paths.lines === 3", timeout=20000)
    pg.wait("a.playing === false && a.pose.t >= a.timeline.duration - 1e-9", timeout=30000)
    program = tmp_path / "lines.arm"
    program.write_text(text)
    pred = cli_json("predict", "mk2plus", str(program))["records"]
    steps = sum(r["dominant_steps"] for r in pred)
    worst = max(r["line_error_mm"] for r in pred)
    assert pg.hook("a.paths.points") == steps + 1  # every step, from where the tool began
    assert abs(pg.hook("a.paths.worstMm") - worst) < 1e-6
    assert f"3 straight lines: the tool within {worst:.2f} mm of them at every step" in pg.page.text_content("#program-status")
    pg.page.screenshot(path=str(SHOTS / "studio-straight-lines.png"))
    # the IK panel's straight line, no arm connected: a line of the program
    for box, v in (("#tx", "250"), ("#ty", "-30"), ("#tz", "150")):
        pg.page.fill(box, v)
    pg.page.click("#ik-line")
    pg.wait("a.ikLine === 'T 250 -30 150 30'")  # the engine's formatter writes it
    assert pg.page.input_value("#editor").endswith("T 250 -30 150 30\n")
    assert "Added to the program" in pg.page.text_content("#ik-status")
    pg.page.fill("#editor", text)
    _connect_page_nano(pg)
    # the page's speed (?speed=4 in its address: the Speed beside Run) is the virtual Nano's
    assert pg.page.input_value("#play-speed") == "4"
    pg.wait("a.arm.nano !== null && a.arm.nano.speed === 4", timeout=10000)
    pg.wait("document.querySelector('#arm-speed').textContent.includes('4x real time')", timeout=10000)
    pg.page.check("#drive-arm")
    pg.page.click("#run")
    pg.wait("a.arm.programDone === true", timeout=90000)
    assert pg.hook("a.arm.programLines") == [[1, "ok"], [2, "ok"], [3, "ok"]]
    want = pred[-1]["steps"]
    pg.wait(f"a.arm.status.state === 'Idle' && JSON.stringify(a.arm.status.steps) === '{json.dumps(want, separators=(',', ':'))}'",
            timeout=30000)
    # the Speed back at 1x: the Nano keeps real time again
    pg.page.select_option("#play-speed", "1")
    pg.wait("a.arm.nano.speed === 1 && document.querySelector('#arm-speed').textContent.includes('keeps real time')",
            timeout=10000)
    # with the arm connected, the IK panel's straight line goes to the arm
    pg.page.fill("#tx", "250")
    pg.page.click("#ik-line")
    pg.wait("a.arm.reply && a.arm.reply.line === a.ikLine", timeout=30000)
    assert pg.hook("a.arm.reply.error || ''") == ""
    assert pg.hook("a.arm.reply.reply") == "ok" and pg.hook("a.arm.reply.predicted.reply") == "ok"
    assert "Sent to the arm" in pg.page.text_content("#ik-status")
    assert pg.errors == []


def test_a_speed_in_a_link_that_is_none_is_said_as_text_and_the_world_keeps_real_time(open_page):
    pg = open_page("mk2plus", query="&speed=%3Cimg%20src%3Dx%20onerror%3Dalert(1)%3E")
    pg.page.wait_for_function("() => !document.querySelector('#banner').hidden")
    said = pg.page.text_content("#banner-text")
    assert "speed=<img src=x onerror=al" in said and "the speeds are 0.25, 0.5, 1, 2, 4 times real time" in said, said
    assert pg.page.query_selector("#banner img") is None
    assert pg.page.input_value("#play-speed") == "1"
    assert pg.errors == []


# A stand-in for navigator.serial (headless Chromium has no serial device to offer): its port
# carries the same bytes to and from the virtual Nano's worker, so the page's Web Serial code
# path is the real one, all but the browser API. unplug() makes the port vanish mid-read. At
# another rate than the Nano's 115,200 it opens, as a real port does, and nothing is understood
# either way (the flasher tries the old bootloader's 57,600 when Optiboot does not answer).
SERIAL_STAND_IN = """
(() => {
  let unplug = null;
  class StandInPort {
    async open({ baudRate }) {
      if (baudRate !== 115200) {
        this.worker = null;
        this.readable = new ReadableStream({ start() {} });
        this.writable = new WritableStream({ write() {} });
        return;
      }
      const w = new Worker(new URL('assets/nano-worker.js', document.baseURI), { type: 'module' });
      let ctl;
      this.readable = new ReadableStream({ start(c) { ctl = c; } });
      this.writable = new WritableStream({ write(chunk) { w.postMessage({ type: 'rx', bytes: new Uint8Array(chunk) }); } });
      await new Promise((resolve, reject) => {
        w.onmessage = (e) => {
          if (e.data.type === 'ready') resolve();
          else if (e.data.type === 'tx') ctl.enqueue(e.data.bytes);
          else if (e.data.type === 'fatal') reject(new Error(e.data.message));
        };
        w.postMessage({ type: 'start' });
      });
      unplug = () => { w.terminate(); ctl.error(new DOMException('The device has been lost.', 'NetworkError')); };
      this.worker = w;
    }
    async setSignals({ dataTerminalReady }) {
      if (dataTerminalReady !== undefined) this.worker?.postMessage({ type: 'signals', dtr: dataTerminalReady });
    }
    async close() { this.worker?.terminate(); }
    getInfo() { return { usbVendorId: 0x1a86, usbProductId: 0x7523 }; }
  }
  Object.defineProperty(navigator, 'serial', { value: {
    requestPort: async () => new StandInPort(), getPorts: async () => [] } });
  window.unplugStandIn = () => unplug && unplug();
})();
"""


@contextlib.contextmanager
def _page_with_serial_stand_in(browser, site):
    """The static site with the stand-in for navigator.serial: (the page, its errors)."""
    ctx = browser.new_context(viewport={"width": 1600, "height": 900})
    ctx.add_init_script("localStorage.setItem('articula.studio.tour.done', '1')")
    ctx.add_init_script(SERIAL_STAND_IN)
    page = ctx.new_page()
    errors = []
    page.on("pageerror", lambda e: errors.append(str(e)))
    try:
        page.goto(site.url + "?robot=mk2plus")
        page.wait_for_function("() => window.articula && window.articula.ready && window.articula.firstFrameAt > 0", timeout=20000 * PATIENCE)
        yield page, errors
    finally:
        ctx.close()


def test_web_serial_drives_the_arm_and_a_vanished_port_is_noticed(browser, site):
    with _page_with_serial_stand_in(browser, site) as (page, errors):
        assert "page:serial" in page.eval_on_selector_all("#arm-port option", "os => os.map(o => o.value)")
        page.select_option("#arm-port", "page:serial")
        page.click("#arm-connect")
        page.wait_for_function("() => window.articula.arm.connected && window.articula.arm.status !== null", timeout=30000 * PATIENCE)
        assert page.evaluate("window.articula.arm.label").startswith("MK2 Plus")
        page.fill("#arm-line", "L 0 10")
        page.click("#arm-send")
        page.wait_for_function("() => window.articula.arm.status.state === 'Idle' && window.articula.arm.status.steps[0] === 32",
                               timeout=20000 * PATIENCE)
        # `I` typed by a student: its banner is the answer, not a reset (it dropped the link)
        page.fill("#arm-line", "I")
        page.click("#arm-send")
        page.wait_for_function("() => window.articula.arm.reply && window.articula.arm.reply.line === 'I'",
                               timeout=20000 * PATIENCE)
        assert page.evaluate("window.articula.arm.reply.reply") == "ok"
        page.fill("#arm-line", "L 0 -5")
        page.click("#arm-send")
        page.wait_for_function("() => window.articula.arm.reply && window.articula.arm.reply.line === 'L 0 -5'",
                               timeout=20000 * PATIENCE)
        assert page.evaluate("window.articula.arm.reply.reply") == "ok"
        page.wait_for_function("() => window.articula.arm.status.state === 'Idle' && window.articula.arm.status.steps[0] === 16",
                               timeout=20000 * PATIENCE)
        assert page.evaluate("window.articula.arm.connected") is True
        assert "Lost the arm" not in page.text_content("#arm-state")
        page.fill("#arm-line", "M 80 90 0")
        page.click("#arm-send")
        # under way (a busy machine's reports may all fall before or after the 0.4 s move: then
        # the steps say it moved)
        page.wait_for_function("() => window.articula.arm.status.state === 'Run' || window.articula.arm.status.steps[0] !== 16",
                               timeout=15000 * PATIENCE)
        page.evaluate("window.unplugStandIn()")
        page.wait_for_function("() => window.articula.arm.connected === false && window.articula.arm.error !== ''", timeout=15000 * PATIENCE)
        # noticed from the port itself (its read fails at once), not from 1.5 s of silence
        assert page.evaluate("window.articula.arm.error").startswith("the port failed"), page.evaluate("window.articula.arm.error")
        assert "Lost the arm" in page.text_content("#arm-state")
        # no green state left, and a report still in flight does not bring it back
        page.wait_for_timeout(300)
        assert "ok" not in page.get_attribute("#arm-state", "class").split()
        assert page.evaluate("window.articula.arm.status") is None
        # the studio goes on with the model
        page.fill('#joints input[type=number][data-joint="0"]', "15")
        page.wait_for_function("() => Math.abs(window.articula.pose.q[0] - 15) < 1e-9")
        assert errors == []


def test_the_page_nano_is_never_driven_as_a_robot_it_cannot_be(open_page):
    """The PUMA has no motors: no Nano can drive it, the panel says why, and nothing is offered."""
    pg = open_page("puma560")
    pg.page.select_option("#arm-port", "page:virtual")
    pg.page.click("#arm-connect")
    pg.wait("a.arm.error !== ''", timeout=30000)
    assert "a Nano cannot drive the robot shown" in pg.hook("a.arm.error")
    assert "has no motors" in pg.hook("a.arm.error")
    assert pg.hook("a.arm.connected") is False and pg.hook("a.arm.configurable") is False
    assert not pg.page.is_visible("#arm-configure")


# ---- flashing the Nano from the page (src/link/stk500.mjs), through the virtual Nano's Optiboot


def test_the_page_flashes_the_virtual_nano_through_its_bootloader(open_page):
    """The flash panel writes this site's one firmware through the Nano's bootloader (Optiboot,
    built from Debian's source, in the virtual Nano's boot section), reads it back, and the Nano
    then answers I as the MK2 (what a blank EEPROM gets) and drives as predicted. Then a student's
    own arm (hil/robots/thesis-example-arm.json, opened as a file): the Nano is configured for
    the MK2, so it is not driven until "Configure the Nano for this robot" writes the arm shown;
    then random lines end on the steps the model predicts."""
    pg = open_page("mk2plus")
    fw = pg.page.evaluate("fetch('data/firmware/firmware.json').then(r => r.json())")
    assert re.fullmatch(r"Articula \S+, [\d,]+ bytes: for every arm it can drive .*", pg.page.text_content("#flash-info"))
    assert f"{fw['bytes']:,}" in pg.page.text_content("#flash-info")
    pg.page.select_option("#arm-port", "page:virtual")
    pg.page.click("#arm-flash")
    f = "window.articula.flash"
    progress = f"[{f}.phase, {f}.done, {f}.attempt]"  # each page is progress (a slow machine's flash takes long)
    wait_with_progress(pg.page, f"{f}.phase === 'write' && {f}.done >= {f}.total / 3", progress, 30, "a third written")
    assert "writing page" in pg.page.text_content("#flash-state")
    assert pg.page.is_visible("#flash-progress")
    pg.page.screenshot(path=str(SHOTS / "studio-flash.png"))
    wait_with_progress(pg.page, f"!{f}.busy", progress, 30, "the flash's end")
    assert pg.hook("a.flash.error") == ""
    result = pg.hook("a.flash.result")
    assert result["baud"] == 115200 and result["bytes"] == fw["bytes"]
    assert result["pages"] == (fw["bytes"] + 127) // 128
    assert "Flashed and verified" in pg.page.text_content("#flash-state")
    pg.wait(f"a.arm.nano !== null && a.arm.nano.flashWrites === {result['pages']}")  # the bootloader wrote every page
    # the Nano came out of its bootloader into the firmware: it drives as predicted
    _connect_page_nano(pg)
    assert pg.hook("a.arm.label").startswith(f"MK2 Plus (firmware {fw['version']})")
    reply = _send(pg, "L 0 10")
    assert reply["reply"] == "ok"
    pg.wait("a.arm.status.state === 'Idle' && a.arm.status.steps[0] === 32", timeout=20000)
    pg.page.click("#arm-disconnect")
    pg.wait("!a.arm.connected")

    # Another arm on the same firmware: configured from the page.
    pg.page.set_input_files("#robot-file", str(REPO / "hil" / "robots" / "thesis-example-arm.json"))
    pg.wait("a.robot.name === 'Thesis example arm'")
    pg.page.select_option("#arm-port", "page:virtual")
    pg.page.click("#arm-connect")
    pg.wait("a.arm.configurable && a.arm.error !== ''", timeout=30000)
    assert "The Nano is configured for the MK2 Plus; the studio shows the Thesis example arm" in pg.hook("a.arm.error")
    assert pg.hook("a.arm.connected") is False  # never driven as another robot
    assert pg.page.is_visible("#arm-configure") and not pg.page.is_visible("#arm-send-row")
    pg.page.screenshot(path=str(SHOTS / "studio-configure.png"))
    pg.page.click("#arm-configure")
    pg.wait("a.arm.connected && a.arm.configured !== null && a.arm.status !== null", timeout=60000)
    assert pg.hook("a.arm.configured.name") == "Thesis example arm"
    assert pg.hook("a.arm.checksum") == pg.hook("a.arm.configured.checksum")
    assert pg.hook("a.arm.label").startswith("Thesis example arm (firmware ")
    assert "configured for the Thesis example arm" in pg.page.text_content("#banner-text")
    # random lines (a seeded generator): each reply and its steps as the model predicts
    import random
    rnd = random.Random(5)
    motors = json.loads((REPO / "hil" / "robots" / "thesis-example-arm.json").read_text())["motors"]
    for _ in range(6):
        line = "M " + " ".join(f"{rnd.uniform(m['min'] - 5, m['max'] + 5):.2f}" for m in motors)
        reply = _send(pg, line)
        assert reply["reply"] == reply["predicted"]["reply"], reply
        if reply["reply"] == "ok":
            steps = reply["predicted"]["steps"]
            pg.wait(f"a.arm.status.state === 'Idle' && JSON.stringify(a.arm.status.steps) === {json.dumps(json.dumps(steps, separators=(',', ':')))}",
                    timeout=30000)
    reply = _send(pg, "P 100 0 50")  # no closed form on this arm: refused as the model says
    assert reply["reply"] == reply["predicted"]["reply"] == "error:16"
    # Another robot shown: the Nano, configured for the thesis arm, is driven no more
    assert pg.page.is_hidden("#arm-configure")  # nothing to configure while the robots agree
    pg.page.select_option("#robot-select", "mk2plus")
    pg.wait("a.robot.name === 'MK2 Plus'")
    pg.wait("!a.arm.connected && a.arm.configurable", timeout=30000)
    assert "configured for the Thesis example arm; the studio shows the MK2 Plus" in pg.hook("a.arm.error")
    assert pg.page.is_visible("#arm-configure") and not pg.page.is_visible("#arm-send-row")
    assert pg.errors == []


def test_the_page_flashes_a_nano_over_web_serial(browser, site):
    """The same flash through the page's Web Serial path (the stand-in port: the browser's API
    is all that differs): DTR resets the Nano into Optiboot, the pages go and come back."""
    with _page_with_serial_stand_in(browser, site) as (page, errors):
        page.select_option("#arm-port", "page:serial")
        page.click("#arm-flash")
        # (each page written or read back is progress: a slow machine's flash takes long, a stalled one fails)
        f = "window.articula.flash"
        wait_with_progress(page, f"{f}.result !== null || {f}.error !== ''", f"[{f}.phase, {f}.done, {f}.attempt]", 30,
                           "the flash's end")
        f = page.evaluate("window.articula.flash")
        assert f["error"] == "", f["error"]
        assert f["result"]["baud"] == 115200 and f["result"]["pages"] == (f["result"]["bytes"] + 127) // 128
        assert "Flashed and verified" in page.text_content("#flash-state")
        assert errors == []
