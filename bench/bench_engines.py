#!/usr/bin/env python3
"""Articula Studio in each browser engine, one run (bench/README.md, "Every engine"): Debian's
Chromium and Firefox ESR through Playwright, WebKitGTK (Safari's engine) through Selenium;
Firefox and WebKit on an Xvfb display (software WebGL: llvmpipe), Chromium headless
(SwiftShader). The page is the static site served by a plain file server, at 1600x900.

  - the first frame with the arm drawn, from the navigation's start (3 loads);
  - a slider move to the new pose on screen: 90 moves at 30 a second (window.articula.latency);
  - the virtual Nano in the page (the firmware's hex on avr8js in a Web Worker, paced to real
    time): how many times real time the emulator alone could run, idle, and with three motors
    stepping while the page draws every frame (?fps=continuous);
  - live physics (the MK2 in scenes/push.json running demo.arm): the real-time factor, how fast
    the stepping alone could run, and in how many readings it fell behind real time;
  - a cell of two arms on two virtual Nanos (cells/signal.json: the MK2 on articula-nano, the
    meArm on articula-servo, wired A5 to A0), both running: each Nano's real-time factor, how
    fast it could run, in how many readings it fell behind; STOP to both stopped.

    .venv/bin/python bench/bench_engines.py [chromium firefox webkit]
"""
from __future__ import annotations

import statistics
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "studio" / "tests"))

from conftest import StaticSite  # noqa: E402  (the tests' file server)
from engines import ENGINES, Engines, missing  # noqa: E402


def _wait(pg, expr, timeout=120.0):
    pg.wait(expr, timeout)


def first_frame(engines, engine, url):
    times = []
    for _ in range(3):
        pg = engines.open(engine, url + "?robot=mk2plus")
        _wait(pg, "a.ready && a.firstFrameAt > 0")
        times.append(pg.hook("a.firstFrameAt"))
        pg.close()
    return times


def slider(pg):
    # 90 inputs on the shoulder's slider at 30 a second, from a timer in the page
    pg.run("""
      const s = document.querySelector('#joints input[type=range][data-joint="1"]');
      let k = 0;
      const t = setInterval(() => {
        s.value = String(60 + 40 * Math.sin(k / 6)); s.dispatchEvent(new Event('input', { bubbles: true }));
        if (++k >= 90) clearInterval(t);
      }, 33);""")
    _wait(pg, "a.latency.length >= 85", 60)
    time.sleep(0.5)
    return pg.hook("a.latency.slice()")


def nano(pg):
    pg.select("#arm-port", "page:virtual")
    pg.click("#arm-connect")
    _wait(pg, "a.arm.connected && a.arm.status !== null")
    time.sleep(6)  # the meter judges over its last slices
    idle = []
    for _ in range(5):
        time.sleep(0.4)
        idle.append(pg.hook("a.arm.nano.capacity"))
    # three motors stepping (about 6 s at $0=40: coordinated, they all end together) while the
    # page draws every frame
    for line in ("$0=40", "M 80 120 -30"):
        pg.type_into("#arm-line", line, enter=True)
        _wait(pg, f"a.arm.reply && a.arm.reply.line === '{line}'")
    _wait(pg, "a.arm.status.state === 'Run'")
    time.sleep(1.5)
    moving = []
    for _ in range(6):
        time.sleep(0.5)
        if pg.hook("a.arm.status.state") == "Run":
            moving.append(pg.hook("a.arm.nano.capacity"))
    rtf = pg.hook("a.arm.nano.rtf")
    return idle, moving, rtf


def physics(pg):
    pg.select("#scene-select", "push")
    _wait(pg, "a.physics !== null")
    pg.select("#program-select", "push.arm")
    _wait(pg, "document.querySelector('#editor').value.length > 0")
    pg.click("#run")
    readings = []
    for _ in range(40):
        time.sleep(0.125)
        ph = pg.hook("a.physics && { rtf: a.physics.rtf, capacity: a.physics.capacity, behind: a.physics.behind }")
        if ph and ph["rtf"] is not None:
            readings.append(ph)
    return readings


def cell_nanos(pg):
    """The signal cell on two virtual Nanos (the MK2 on articula-nano, the meArm on articula-servo,
    one wire): each Nano's speed against real time and how fast it could run, read every 0.5 s
    while both run, then STOP to both stopped (ms)."""
    pg.select("#scene-select", "cell:signal")
    _wait(pg, "a.cell.name === 'signal' && a.cell.frames > 0")
    pg.select("#cell-run-on", "nanos")
    pg.click("#cell-run-all")
    _wait(pg, "a.cell.nanos !== null && a.cell.nanos.arms.every(x => x.connected) && a.cell.nanos.running")
    readings = []
    for _ in range(16):
        time.sleep(0.5)
        r = pg.hook("a.cell.nanos.arms.map(x => [x.rtf, x.capacity, x.behind])")
        if all(x[0] is not None and x[1] is not None for x in r):
            readings.append(r)
    t0 = time.perf_counter()
    pg.click("#stop")
    _wait(pg, "a.cell.nanos.arms.every(x => x.done)")
    return readings, (time.perf_counter() - t0) * 1000


def pct(xs, q):
    xs = sorted(xs)
    return xs[min(len(xs) - 1, int(q * len(xs)))]


def main(argv):
    wanted = argv or list(ENGINES)
    site = StaticSite(Path(tempfile.mkdtemp(prefix="articula-bench-www-")))
    engines = Engines()
    try:
        for engine in wanted:
            why = missing(engine)
            if why:
                print(f"{engine}: skipped ({why})")
                continue
            ff = first_frame(engines, engine, site.url)
            pg = engines.open(engine, site.url + "?robot=mk2plus")
            _wait(pg, "a.ready && a.firstFrameAt > 0")
            lat = slider(pg)
            ph = physics(pg)
            errors = pg.page_errors()
            pg.close()
            pg = engines.open(engine, site.url + "?robot=mk2plus&fps=continuous")
            _wait(pg, "a.ready && a.firstFrameAt > 0")
            idle, moving, rtf = nano(pg)
            errors += pg.page_errors()
            pg.close()
            pg = engines.open(engine, site.url + "?robot=mk2plus")
            _wait(pg, "a.ready && a.firstFrameAt > 0")
            cell, stop_ms = cell_nanos(pg)
            errors += pg.page_errors()
            pg.close()
            version = getattr(engines.browsers.get(engine), "version", "") or "WebKitGTK"
            print(f"== {engine} {version}")
            print(f"  first frame: median {statistics.median(ff):.0f} ms (min {min(ff):.0f}, max {max(ff):.0f}; 3 loads)")
            print(f"  slider to pixels: median {statistics.median(lat):.1f} ms, p95 {pct(lat, 0.95):.1f} ms ({len(lat)} moves)")
            print(f"  virtual Nano could run: idle median {statistics.median(idle):.1f}x real time (min {min(idle):.1f}); "
                  f"three motors stepping while the page draws every frame: median "
                  f"{statistics.median(moving):.1f}x (min {min(moving):.1f}; {len(moving)} readings); it ran at {rtf:.3f}x")
            behind = sum(1 for r in ph if r["behind"])
            caps = [r["capacity"] for r in ph if r["capacity"]]
            print(f"  live physics: real-time factor median {statistics.median(r['rtf'] for r in ph):.3f} "
                  f"(min {min(r['rtf'] for r in ph):.3f}); the stepping alone could run median "
                  f"{statistics.median(caps) if caps else 0:.0f}x; behind in {behind} of {len(ph)} readings")
            arms = ("MK2 (articula-nano)", "meArm (articula-servo)")
            print("  a cell of two arms on two virtual Nanos (signal, wired A5 to A0), both running: " + "; ".join(
                f"{name} at median {statistics.median(r[k][0] for r in cell):.3f}x real time (min {min(r[k][0] for r in cell):.3f}), "
                f"could run median {statistics.median(r[k][1] for r in cell):.1f}x (min {min(r[k][1] for r in cell):.1f}), "
                f"behind in {sum(1 for r in cell if r[k][2])} of {len(cell)}" for k, name in enumerate(arms))
                + f"; STOP to both stopped {stop_ms:.0f} ms")
            if errors:
                print(f"  the page's errors: {errors}")
    finally:
        engines.stop()
        site.stop()


if __name__ == "__main__":
    main(sys.argv[1:])
