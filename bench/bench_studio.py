#!/usr/bin/env python3
"""Articula Studio's speed, measured in the page (bench/README.md, "Studio"), in Debian's
headless Chromium (software WebGL, SwiftShader) at 1600x900. The page is the static site
(studio/web/dist) served by a plain file server under a sub-path, its engine, the virtual Nano
and the flasher in the page (no articula process).

  - a cold load of the static site (a new browser profile: nothing cached) to the first frame
    with the arm drawn: median of 5 loads, and the engine's own start in its worker;
  - a slider move to the new pose on screen: the page stamps each input and the frame that
    shows its pose (window.articula.latency); 200 moves of the Panda's shoulder at 30 a second;
  - dragging the IK target on the Panda with the mouse for 3 s at 60 moves a second: poses
    drawn per second;
  - frames per second drawing the Panda when the page draws every frame (?fps=continuous);
  - live physics, the Panda in scenes/cluttered.json for 5 s while the arm moves through the
    clutter: the real-time factor, how fast the stepping alone could run, whether it ever fell
    behind, and the updates a second the page gets;
  - the virtual Nano in the page (the firmware's hex on avr8js in a Web Worker): its speed
    against real time idle, and with three motors stepping while the page draws; `?` to the
    drawn pose (median, p95);
  - STOP (Escape) on the virtual Nano during a long move at $1 = 20,000 to the arm at rest;
  - flashing the MK2's firmware from the page through the virtual Nano's Optiboot: from the
    first byte to the flash verified, and on to the firmware's banner.

    .venv/bin/python bench/bench_studio.py
"""
import re
import statistics
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
ARGS = ["--no-sandbox", "--disable-background-networking", "--disable-component-update", "--disable-sync",
        "--no-first-run", "--disable-quic"]


class StaticSite:
    """studio/web/dist behind Python's http.server, at /articula/ (no articula process)."""

    def __init__(self):
        import tempfile
        self.root = tempfile.mkdtemp(prefix="articula-bench-www-")
        (Path(self.root) / "articula").symlink_to(REPO / "studio" / "web" / "dist", target_is_directory=True)
        self.proc = subprocess.Popen([sys.executable, "-u", "-m", "http.server", "0", "--bind", "127.0.0.1",
                                      "--directory", self.root], stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
                                     text=True)
        port = re.search(r"port (\d+)", self.proc.stdout.readline()).group(1)
        self.url = f"http://127.0.0.1:{port}/articula/"

    def stop(self):
        self.proc.terminate()
        self.proc.wait()


def open_page(browser, url):
    ctx = browser.new_context(viewport={"width": 1600, "height": 900})
    ctx.add_init_script("localStorage.setItem('articula.studio.tour.done', '1')")
    page = ctx.new_page()
    page.goto(url)
    page.wait_for_function("() => window.articula && window.articula.firstFrameAt > 0", timeout=30000)
    return ctx, page


def pct(v, p):
    v = sorted(v)
    return v[min(len(v) - 1, int(p * (len(v) - 1) + 0.5))]


def main():
    from playwright.sync_api import sync_playwright

    with sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path="/usr/bin/chromium", headless=True, args=ARGS)
        site = StaticSite()
        firsts, engine = [], []
        for _ in range(5):
            ctx, page = open_page(browser, site.url + "?robot=panda")  # a new context: an empty cache
            firsts.append(page.evaluate("window.articula.firstFrameAt") / 1000)
            engine.append(page.evaluate("window.articula.engineStartMs") / 1000)
            ctx.close()
        print(f"cold load of the static site to the first frame with the arm (Panda): median "
              f"{statistics.median(firsts):.3f} s, min {min(firsts):.3f}, max {max(firsts):.3f} (5 loads); the engine's "
              f"start in its worker (wasm compiled, robot fetched and loaded): median {statistics.median(engine):.3f} s")

        ctx, page = open_page(browser, site.url + "?robot=panda")
        page.evaluate("""async () => {
            const s = document.querySelector('#joints input[type=range][data-joint="1"]');
            for (let i = 0; i < 200; i++) {
              s.value = String(-60 + 120 * Math.abs(Math.sin(i / 20)));
              s.dispatchEvent(new Event('input'));
              await new Promise(r => setTimeout(r, 33));
            }
            await new Promise(r => setTimeout(r, 300));
        }""")
        lat = page.evaluate("window.articula.latency.slice()")
        print(f"slider move to the pose on screen (Panda): median {statistics.median(lat):.1f} ms, "
              f"p95 {pct(lat, 0.95):.1f} ms, max {max(lat):.1f} ms ({len(lat)} poses drawn for 200 moves)")

        page.check("#show-target")
        page.wait_for_timeout(300)
        x, y = page.evaluate("window.articula.targetScreen")
        # The mouse is pressed on the target by the browser; the moves then come from inside
        # the page, one a display frame (Playwright's own calls take longer than a frame).
        page.mouse.move(x, y)
        page.mouse.down()
        moves, dt, drawn = page.evaluate("""async ([x, y]) => {
            const c = document.querySelector('#view canvas');
            const n0 = window.articula.ikUpdates.length;
            const t0 = performance.now();
            let k = 0;
            while (performance.now() - t0 < 3000) {
              await new Promise(r => requestAnimationFrame(r));
              k++;
              c.dispatchEvent(new PointerEvent('pointermove', {clientX: x - 60 * Math.abs(Math.sin(k / 30)),
                clientY: y + 40 * Math.sin(k / 45), pointerId: 1, pointerType: 'mouse', isPrimary: true, button: -1,
                buttons: 1, bubbles: true}));
            }
            return [k, (performance.now() - t0) / 1000, window.articula.ikUpdates.length - n0];
        }""", [x, y])
        page.mouse.up()
        status = page.evaluate("window.articula.ik.status")
        print(f"IK target dragged (Panda): {drawn / dt:.1f} poses drawn a second for {moves / dt:.1f} pointer moves "
              f"a second (one a display frame; last status {status})")
        ctx.close()

        ctx = browser.new_context(viewport={"width": 1600, "height": 900})
        ctx.add_init_script("localStorage.setItem('articula.studio.tour.done', '1')")
        page = ctx.new_page()
        page.goto(site.url + "?robot=panda&fps=continuous")
        page.wait_for_function("() => window.articula && window.articula.firstFrameAt > 0", timeout=30000)
        page.wait_for_timeout(2000)
        fps = []
        for _ in range(5):
            page.wait_for_timeout(1000)
            fps.append(page.evaluate("window.articula.fps"))
        print(f"frames per second drawing the Panda, every frame drawn: median {statistics.median(fps)} "
              f"(readings {fps})")
        ctx.close()

        # Live physics: the Panda in the cluttered scene, moving through it.
        ctx, page = open_page(browser, site.url + "?robot=panda&scene=cluttered")
        page.wait_for_function("() => window.articula.physics && window.articula.physics.on")
        page.evaluate("""async () => {
            const q = [[0, 40, 0, -90, 0, 130, 45], [60, 50, 0, -80, 0, 130, 45], [-60, 30, 0, -100, 0, 130, 45]];
            for (let k = 0; k < 3; k++) {
              document.querySelectorAll('#joints input[type=number]').forEach((el, j) => {
                el.value = String(q[k][j]); el.dispatchEvent(new Event('input')); });
              await new Promise(r => setTimeout(r, 300));
            }
        }""")
        m0 = page.evaluate("window.articula.stream.messages")
        rtfs, caps, behind = [], [], 0
        t0 = time.monotonic()
        for _ in range(50):
            page.wait_for_timeout(100)
            ph = page.evaluate("window.articula.physics")
            rtfs.append(ph["rtf"])
            caps.append(ph["capacity"] or 0)
            behind += bool(ph["behind"])
        dt = time.monotonic() - t0
        m1 = page.evaluate("window.articula.stream.messages")
        events = page.evaluate("window.articula.events.length")
        print(f"live physics, Panda in scenes/cluttered.json (7 objects), 5 s: real-time factor median "
              f"{statistics.median(rtfs):.3f} (min {min(rtfs):.3f}), the stepping alone could run "
              f"{statistics.median(caps):.0f}x real time, behind real time in {behind} of 50 readings; "
              f"{(m1 - m0) / dt / 2:.1f} updates a second (a pose and a world message each); {events} events")
        ctx.close()

        # The virtual Nano in the page: avr8js in a worker, paced to real time.
        ctx, page = open_page(browser, site.url + "?robot=mk2plus")
        page.select_option("#arm-port", "page:virtual")
        page.click("#arm-connect")
        page.wait_for_function("() => window.articula.arm.connected && window.articula.arm.nano", timeout=30000)
        page.wait_for_timeout(3000)
        idle, idle_cap = [], []
        for _ in range(10):
            page.wait_for_timeout(300)
            idle.append(page.evaluate("window.articula.arm.nano.rtf"))
            idle_cap.append(page.evaluate("window.articula.arm.nano.capacity"))
        n0 = len(page.evaluate("window.articula.arm.roundTrips"))
        moving, moving_cap = [], []
        for line in ("$1=20000", "M 80 120 10", "M -80 40 -40", "M 0 90 0"):
            page.fill("#arm-line", line)
            page.click("#arm-send")
            for _ in range(6):
                page.wait_for_timeout(300)
                if line.startswith("M"):
                    moving.append(page.evaluate("window.articula.arm.nano.rtf"))
                    moving_cap.append(page.evaluate("window.articula.arm.nano.capacity"))
        rt = page.evaluate("window.articula.arm.roundTrips.slice()")[n0:]
        print(f"virtual Nano in the page (avr8js): idle {statistics.median(idle):.3f}x real time (min {min(idle):.3f}), "
              f"the emulator alone could run {statistics.median(idle_cap):.2f}x; three motors stepping while the page "
              f"draws {statistics.median(moving):.3f}x (min {min(moving):.3f}), could run {statistics.median(moving_cap):.2f}x; "
              f"? to the drawn pose: median {statistics.median(rt):.1f} ms, p95 {pct(rt, 0.95):.1f} ms ({len(rt)} reports)")
        ctx.close()
        site.stop()

        # STOP on the page's Nano, then flashing it.
        site = StaticSite()
        ctx, page = open_page(browser, site.url + "?robot=mk2plus")
        page.select_option("#arm-port", "page:virtual")
        page.click("#arm-connect")
        page.wait_for_function("() => window.articula.arm.connected && window.articula.arm.status", timeout=30000)
        stops = []
        for _ in range(5):
            for line in ("$1=20000", "M 80 90 0"):
                page.fill("#arm-line", line)
                page.click("#arm-send")
                page.wait_for_timeout(200)
            page.wait_for_function("() => window.articula.arm.status.state === 'Run'", timeout=15000)
            page.wait_for_timeout(150)
            page.keyboard.press("Escape")
            page.wait_for_function("() => window.articula.arm.stopMs !== null", timeout=15000)
            stops.append(page.evaluate("window.articula.arm.stopMs"))
            page.fill("#arm-line", "M 0 90 0")
            page.click("#arm-send")
            page.wait_for_timeout(2500)
        print(f"STOP (Escape) on the page's Nano during a move at $1 = 20000 to the arm at rest (Idle): median "
              f"{statistics.median(stops):.0f} ms, max {max(stops):.0f} ms (5 stops)")
        flashes, banners = [], []
        for _ in range(3):
            page.click("#arm-flash")
            page.wait_for_function("() => window.articula.flash.phase === 'write'", timeout=30000)
            page.wait_for_function("() => !window.articula.flash.busy", timeout=180000)
            r = page.evaluate("window.articula.flash")
            assert not r["error"], r["error"]
            t0 = time.monotonic()
            page.click("#arm-connect")
            page.wait_for_function("() => window.articula.arm.connected", timeout=30000)
            flashes.append(r["result"]["seconds"])
            banners.append(r["result"]["seconds"] + time.monotonic() - t0)
        print(f"flashing the MK2 firmware ({r['result']['bytes']:,} bytes, {r['result']['pages']} pages) through the "
              f"virtual Nano's Optiboot at 115200 baud: written and verified in {statistics.median(flashes):.1f} s "
              f"(median of 3), to its banner {statistics.median(banners):.1f} s")
        ctx.close()
        site.stop()
        browser.close()


if __name__ == "__main__":
    main()
