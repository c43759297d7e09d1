#!/usr/bin/env python3
"""A studio for a class (issue 21), measured in the page of the static site in Debian's
headless Chromium (software WebGL), at 1600x900:

- the site's size gzipped, and Blockly's part of it (the bundle with and without it is not
  two builds: Blockly's share is its modules' bytes in app.js's source map);
- a cold load to the first frame with the arm, and the block editor's first paint after it
  is opened (5 loads each);
- autosave of the Panda with a 500-line program: the main thread's time per save (the
  project captured, and the browser's copy of it as IndexedDB's put() is called), against
  JSON.stringify of the same project in the same page (a peer: the cheapest way to copy it);
- reopening that project after a reload: the time to the arm drawn (3 reloads);
- the share link's length for the MK2 with programs/demo.arm (as text, and as blocks).

    .venv/bin/python bench/bench_class.py
"""

from __future__ import annotations

import gzip
import json
import statistics
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "bench"))
from bench_studio import StaticSite as Site, open_page  # noqa: E402

DIST = REPO / "studio" / "web" / "dist"


def sizes() -> dict:
    files = [f for f in DIST.rglob("*") if f.is_file() and not f.name.endswith(".map")]
    gz = {str(f.relative_to(DIST)): len(gzip.compress(f.read_bytes(), 9)) for f in files}
    # Blockly's share of app.js: its modules' source bytes, from the source map
    smap = json.loads((DIST / "assets" / "app.js.map").read_text())
    src = smap.get("sourcesContent") or []
    by = lambda pred: sum(len(c or "") for s, c in zip(smap["sources"], src) if pred(s))  # noqa: E731
    blockly_src, all_src = by(lambda s: "node_modules/blockly" in s), by(lambda s: True)
    app = gz["assets/app.js"]
    return {"total_gz": sum(gz.values()), "files": len(gz), "app_js_gz": app,
            "blockly_share_of_app_js": blockly_src / max(all_src, 1),
            "largest": sorted(gz.items(), key=lambda kv: -kv[1])[:6]}


def main() -> None:
    from playwright.sync_api import sync_playwright

    s = sizes()
    print(f"site: {s['total_gz'] / 1e6:.2f} MB gzipped in {s['files']} files (target: at most 3 MB)")
    for name, n in s["largest"]:
        print(f"  {name:32s} {n / 1024:7.0f} KB gzipped")
    print(f"  Blockly: {100 * s['blockly_share_of_app_js']:.0f} % of app.js's sources, so about "
          f"{s['app_js_gz'] * s['blockly_share_of_app_js'] / 1024:.0f} KB of its {s['app_js_gz'] / 1024:.0f} KB gzipped")
    site = Site()
    with sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path="/usr/bin/chromium", headless=True,
                                     args=["--no-sandbox", "--disable-background-networking"])
        loads, paints = [], []
        for _ in range(5):
            ctx, page = open_page(browser, site.url + "?robot=mk2plus&nosw")
            loads.append(page.evaluate("() => window.articula.firstFrameAt"))
            page.click("#mode-blocks")
            page.wait_for_function("() => window.articula.blocksFirstPaintMs > 0")
            paints.append(page.evaluate("() => window.articula.blocksFirstPaintMs"))
            ctx.close()
        print(f"cold load to the arm drawn: median {statistics.median(loads):.0f} ms, worst {max(loads):.0f} ms "
              f"(target 1,500 ms: {statistics.median(loads) / 1500:.2f} of it)")
        print(f"the block editor's first paint after it is opened: median {statistics.median(paints):.0f} ms, "
              f"worst {max(paints):.0f} ms")

        # autosave: the Panda with a 500-line program
        ctx, page = open_page(browser, site.url + "?robot=panda&nosw")
        lines = [f"M {' '.join(f'{(i * 7 + j * 13) % 60 - 30:.3f}' for j in range(7))}" for i in range(500)]
        text = "\n".join(lines) + "\n"
        for i in range(12):  # each edit saved half a second later
            page.fill("#editor", text + f"# edit {i}\n")
            page.wait_for_function(f"() => window.articula.project.saves >= {i + 1} && !window.articula.project.dirty",
                                   timeout=20000)
        saves = page.evaluate("() => window.articula.project.saveMs.slice(2)")
        peer = page.evaluate("""() => { const p = window.articula.project; const t = [];
            for (let i = 0; i < 10; i++) { const t0 = performance.now();
              for (let k = 0; k < 100; k++) JSON.stringify({program: p.program, blocks: p.blocks});
              t.push((performance.now() - t0) / 100); } return t; }""")
        print(f"autosave, the Panda with 500 lines ({len(text) / 1024:.0f} KB): main thread median {statistics.median(saves):.2f} ms, "
              f"worst {max(saves):.2f} ms per save (target 50 ms); JSON.stringify of it: median {statistics.median(peer):.2f} ms "
              f"(save / stringify: {statistics.median(saves) / max(statistics.median(peer), 1e-3):.1f})")
        reopen = []
        for _ in range(3):
            page.reload()
            page.wait_for_function("() => window.articula && window.articula.firstFrameAt > 0 && "
                                   "window.articula.project.program.length > 10000", timeout=30000)
            reopen.append(page.evaluate("() => window.articula.firstFrameAt"))
        print(f"reopened after a reload, to the Panda drawn: median {statistics.median(reopen):.0f} ms, worst {max(reopen):.0f} ms "
              f"(target 1,000 ms)")
        ctx.close()

        # the share link for the MK2 with programs/demo.arm
        ctx, page = open_page(browser, site.url + "?robot=mk2plus&nosw")
        page.select_option("#program-select", "demo.arm")
        page.wait_for_function("() => document.querySelector('#editor').value.includes('P 200')")
        page.click("#share-button")
        page.wait_for_function("() => window.articula.shareLink !== ''")
        text_link = len(page.evaluate("() => window.articula.shareLink"))
        page.click("#share-close")
        page.click("#mode-blocks")
        page.wait_for_function("() => window.articula.blocksCode !== null && !window.articula.blocksPending")
        page.click("#share-button")
        page.wait_for_function(f"() => window.articula.shareLink.length !== {text_link}")
        blocks_link = len(page.evaluate("() => window.articula.shareLink"))
        print(f"share link, the MK2 with demo.arm: {text_link:,} characters as text, {blocks_link:,} as blocks (aim: under 2,000); "
              f"the file itself is {len((REPO / 'programs' / 'demo.arm').read_bytes()):,} bytes")
        ctx.close()
        browser.close()
    site.stop()


if __name__ == "__main__":
    main()
