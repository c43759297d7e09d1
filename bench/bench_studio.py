#!/usr/bin/env python3
"""Articula Studio's speed, measured in the page (bench/README.md, "Studio"), in Debian's
headless Chromium (software WebGL, SwiftShader) at 1440x900:

  - from the server's start to the first frame with the arm drawn (the browser already
    running, as a user's is): median of 5 starts;
  - a slider move to the new pose on screen: the page stamps each input and the frame that
    shows its pose (window.articula.latency); 200 moves of the Panda's shoulder at 30 a second;
  - dragging the IK target on the Panda with the mouse for 3 s at 60 moves a second: poses
    drawn per second;
  - frames per second drawing the Panda when the page draws every frame (?fps=continuous);
  - live physics, the Panda in scenes/cluttered.json for 5 s while the arm moves through the
    clutter: the real-time factor, how fast the stepping alone could run, and the state
    stream to the page (messages a second, bytes a message);
  - the virtual Nano: a status report's round trip, from the server's `?` to the frame that
    draws the arm from it (window.articula.arm.roundTrips), median and p95 over 10 s, the
    arm moving.

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


def start(robot, *extra):
    t0 = time.time()
    p = subprocess.Popen([sys.executable, "-m", "articula.studio", robot, *extra, "--no-browser"], cwd=REPO,
                         stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    url = re.match(r"studio: (\S+)", p.stdout.readline()).group(1)
    return p, url, t0


def open_page(browser, url):
    ctx = browser.new_context(viewport={"width": 1440, "height": 900})
    ctx.add_init_script("localStorage.setItem('articula.studio.tour.done', '1')")
    page = ctx.new_page()
    page.goto(url)
    page.wait_for_function("window.articula && window.articula.firstFrameAt > 0", timeout=30000)
    return ctx, page


def pct(v, p):
    v = sorted(v)
    return v[min(len(v) - 1, int(p * (len(v) - 1) + 0.5))]


def main():
    from playwright.sync_api import sync_playwright

    with sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path="/usr/bin/chromium", headless=True, args=ARGS)
        starts = []
        for _ in range(5):
            p, url, t0 = start("panda")
            ctx, page = open_page(browser, url)
            first = page.evaluate("performance.timeOrigin + window.articula.firstFrameAt") / 1000
            starts.append(first - t0)
            ctx.close()
            p.terminate()
            p.wait()
        print(f"server start to the first frame with the arm (Panda): median {statistics.median(starts):.3f} s, "
              f"min {min(starts):.3f}, max {max(starts):.3f} (5 starts)")

        p, url, _ = start("panda")
        ctx, page = open_page(browser, url)
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
        p.terminate()
        p.wait()

        p, url, _ = start("panda")
        ctx = browser.new_context(viewport={"width": 1440, "height": 900})
        ctx.add_init_script("localStorage.setItem('articula.studio.tour.done', '1')")
        page = ctx.new_page()
        page.goto(url + "&fps=continuous")
        page.wait_for_function("window.articula && window.articula.firstFrameAt > 0", timeout=30000)
        page.wait_for_timeout(2000)
        fps = []
        for _ in range(5):
            page.wait_for_timeout(1000)
            fps.append(page.evaluate("window.articula.fps"))
        print(f"frames per second drawing the Panda, every frame drawn: median {statistics.median(fps)} "
              f"(readings {fps})")
        ctx.close()
        p.terminate()
        p.wait()

        # Live physics: the Panda in the cluttered scene, moving through it.
        p, url, _ = start("panda", "--scene", "cluttered")
        ctx, page = open_page(browser, url)
        page.wait_for_function("window.articula.physics && window.articula.physics.on")
        page.evaluate("""async () => {
            const q = [[0, 40, 0, -90, 0, 130, 45], [60, 50, 0, -80, 0, 130, 45], [-60, 30, 0, -100, 0, 130, 45]];
            for (let k = 0; k < 3; k++) {
              document.querySelectorAll('#joints input[type=number]').forEach((el, j) => {
                el.value = String(q[k][j]); el.dispatchEvent(new Event('input')); });
              await new Promise(r => setTimeout(r, 300));
            }
        }""")
        m0, b0 = page.evaluate("[window.articula.stream.messages, window.articula.stream.bytes]")
        rtfs, caps = [], []
        t0 = time.monotonic()
        for _ in range(10):
            page.wait_for_timeout(500)
            ph = page.evaluate("window.articula.physics")
            rtfs.append(ph["rtf"])
            caps.append(ph["capacity"] or 0)
        dt = time.monotonic() - t0
        m1, b1 = page.evaluate("[window.articula.stream.messages, window.articula.stream.bytes]")
        events = page.evaluate("window.articula.events.length")
        behind = page.evaluate("window.articula.physics.behind")
        print(f"live physics, Panda in scenes/cluttered.json (7 objects), 5 s: real-time factor median "
              f"{statistics.median(rtfs):.3f} (min {min(rtfs):.3f}), the stepping alone could run "
              f"{statistics.median(caps):.0f}x real time, behind: {behind}; stream {(m1 - m0) / dt / 2:.1f} "
              f"updates a second (a pose and a world message each), {(b1 - b0) / max(1, m1 - m0):.0f} bytes a "
              f"message; {events} events")
        ctx.close()
        p.terminate()
        p.wait()

        # The virtual Nano: `?` to the drawn pose.
        p, url, _ = start("mk2plus")
        ctx, page = open_page(browser, url)
        page.click("#arm-port")
        page.wait_for_function("[...document.querySelectorAll('#arm-port option')].some(o => o.value === 'virtual')")
        page.select_option("#arm-port", "virtual")
        page.click("#arm-connect")
        page.wait_for_function("window.articula.arm.connected && window.articula.arm.status", timeout=20000)
        for line in ("M 60 70 -30", "M -60 110 10", "M 0 90 0"):
            page.fill("#arm-line", line)
            page.click("#arm-send")
            page.wait_for_timeout(3000)
        rt = page.evaluate("window.articula.arm.roundTrips.slice()")
        print(f"virtual Nano, ? to the drawn pose: median {statistics.median(rt):.1f} ms, p95 {pct(rt, 0.95):.1f} ms, "
              f"max {max(rt):.1f} ms ({len(rt)} reports drawn while it moved)")
        ctx.close()
        p.terminate()
        p.wait()
        browser.close()


if __name__ == "__main__":
    main()
