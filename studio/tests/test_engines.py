"""The page in Firefox and WebKit (Safari's engine): it loads and draws, typed joints give the
tool articula fk gives, IK reaches a typed target, a program plays, the live physics runs, and
the virtual Nano is driven to the predicted steps and flashed. Chromium runs the deep suite
(test_studio.py and the others), which covers the same session and more; `engines.py` can
drive it here too (bench_engines.py does). The pictures are docs/studio.md's."""

from __future__ import annotations

import json
import subprocess

import numpy as np
import pytest

from conftest import PATIENCE, REPO, SHOTS
from engines import ENGINES, Engines, missing

ARTICULA = REPO / "build" / "host" / "cli" / "articula"


def _fk(q):
    import os

    p = subprocess.run([os.environ.get("ARTICULA_CLI") or str(ARTICULA), "fk", "mk2plus", "--q", ",".join(map(str, q)),
                        "--json"], capture_output=True, text=True, cwd=REPO, timeout=60)
    assert p.returncode == 0, p.stderr
    return json.loads(p.stdout)


@pytest.fixture(scope="module")
def engines(playwright):
    e = Engines(playwright)
    yield e
    e.stop()


# Chromium runs the deep suite (test_studio.py and the others), which covers all of this and
# more; here the other engines run the same session.
@pytest.fixture(params=[e for e in ENGINES if e != "chromium"])
def page(request, engines, site):
    why = missing(request.param)
    if why:
        pytest.fail(why)
    opened = []

    def open_(query="", **kw):
        p = engines.open(request.param, f"{site.url}?robot=mk2plus{query}", **kw)
        opened.append(p)
        p.wait("a.ready && a.firstFrameAt > 0", 60 * PATIENCE, "the page's first frame with the arm")
        return p

    yield open_
    for p in opened:
        errors = p.page_errors()
        p.close()
        assert errors == [], f"{request.param}: the page's errors: {errors}"


def test_loads_draws_and_follows_typed_joints_and_ik(page):
    pg = page()
    assert pg.hook("a.webgl") is True
    pg.wait("a.armPixels() > 0.02", 30 * PATIENCE, "the arm drawn")
    # typed joints: the tool where articula fk puts it
    for j, v in enumerate((30, 60, -80)):
        pg.type_into(f'#joints input[type=number][data-joint="{j}"]', str(v))
        pg.wait(f"Math.abs(a.pose.q[{j}] - {v}) < 1e-9", 30 * PATIENCE)
    doc = _fk([30, 60, -80])
    np.testing.assert_allclose(pg.hook("a.pose.tool.xyz"), doc["tool"]["position"], atol=1e-6)
    # IK to a typed target
    for c, v in zip("xyz", (250, 50, 150)):
        pg.type_into(f"#t{c}", str(v))
    pg.click("#solve")
    pg.wait("a.ik && a.ik.status === 'reached'", 30 * PATIENCE)
    np.testing.assert_allclose(pg.hook("a.pose.tool.xyz"), [250, 50, 150], atol=0.011)
    pg.screenshot(SHOTS / f"studio-{pg.engine}.png")


def test_a_program_plays_and_the_physics_runs(page):
    pg = page()
    pg.set_text("#editor", "L 0 30\nM 0 60 -60\nG 0")
    pg.click("#run")
    pg.wait("a.timeline !== null && a.playing === false && a.pose.t >= a.timeline.duration - 1e-9", 60 * PATIENCE,
            "the program played to its end")
    assert pg.hook("a.pose.q") == pytest.approx(pg.hook("a.timeline.records[a.timeline.records.length - 1].q"), abs=1e-6)
    # live physics: a box dropped on the ground comes to rest there, upright
    pg.select("#scene-select", "push")
    pg.wait("a.physics !== null && a.physics.t > 1.0", 60 * PATIENCE, "the physics ran a second")
    pg.wait("(() => { const p = a.physics.objects.find(o => o.name === 'box').pose; "
            "return Math.abs(p[11] - 40) < 1.5 && Math.abs(p[10] - 1) < 0.01; })()", 60 * PATIENCE, "the box at rest")
    # how fast (speed is the benchmark's to judge: bench/bench_engines.py); here, that it says
    assert pg.hook("typeof a.physics.rtf === 'number' && typeof a.physics.behind === 'boolean'")


def test_the_virtual_nano_drives_as_predicted_and_is_flashed(page):
    pg = page()
    pg.select("#arm-port", "page:virtual")
    pg.click("#arm-connect")
    pg.wait("a.arm.connected && a.arm.status !== null", 60 * PATIENCE, "the virtual Nano connected")
    assert pg.hook("a.arm.label").startswith("MK2 Plus (firmware ")
    pg.type_into("#arm-line", "L 0 10", enter=True)
    pg.wait("a.arm.reply && a.arm.reply.line === 'L 0 10'", 30 * PATIENCE)
    reply = pg.hook("a.arm.reply")
    assert reply["reply"] == "ok" and reply["predicted"]["steps"] == [32, 0, 0]
    pg.wait("a.arm.status.state === 'Idle' && a.arm.status.steps[0] === 32", 30 * PATIENCE)
    pg.wait("a.arm.nano !== null && a.arm.nano.steps[0] === 32 && a.arm.nano.faults === 0", 30 * PATIENCE)
    # flashed through its bootloader, read back; it comes out into the firmware
    pg.click("#arm-flash")
    pg.wait("a.flash.busy === false && a.flash.result !== null || a.flash.error !== ''", 240 * PATIENCE, "the flash")
    assert pg.hook("a.flash.error") == ""
    result = pg.hook("a.flash.result")
    assert result["pages"] == (result["bytes"] + 127) // 128 and result["baud"] == 115200
    pg.click("#arm-connect")
    pg.wait("a.arm.connected && a.arm.status !== null", 60 * PATIENCE, "the flashed Nano connected")
    assert pg.hook("a.arm.status.steps") == [0, 0, 0]
