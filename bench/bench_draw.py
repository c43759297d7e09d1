#!/usr/bin/env python3
"""Drawing: a text and an SVG become a program and its prediction, step by step (bench/README.md,
"Drawing").

Issue 29's target: a 60-character text and a 200-path SVG become a program and its prediction
in under 300 ms in the page. The page's engine is the web engine (wasm); this runs it in node,
the same engine.wasm the page's worker loads, beside the native library through Python, round
after round, and prints each one's best and median over the rounds and the ratio web/native.
The work timed is one call: `robot.draw(request)`: the text laid out in the Hershey font or the
SVG read and flattened, placed, reach checked, ordered, the program written, predicted with the
pen's tip at every step, and the worst distance found.

    .venv/bin/python bench/bench_draw.py [--rounds 7] [--build build]
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "python"))

TEXT = "The quick brown fox jumps over the lazy dog: 0123456789, ok!"  # 60 characters
assert len(TEXT) == 60


def svg_200_paths() -> str:
    """200 paths on a 100 x 60 sheet: curves, arcs and lines, made here (deterministic)."""
    paths = []
    for i in range(200):
        x, y = 5 + (i % 20) * 4.5, 5 + (i // 20) * 5.5
        if i % 3 == 0:
            d = f"M{x:.2f} {y:.2f} c1 -2 3 -2 4 0 s3 2 4 0"
        elif i % 3 == 1:
            d = f"M{x:.2f} {y:.2f} a2 1.5 0 1 1 3 0 l-1 2 z"
        else:
            d = f"M{x:.2f} {y:.2f} q2 3 4 0 t4 0"
        paths.append(f'<path d="{d}"/>')
    return '<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 60">' + "".join(paths) + "</svg>"


CASES = {
    "text": {"text": TEXT, "width": 120, "at": [255, 0], "z": 0, "pen": 120},
    "svg": {"svg": svg_200_paths(), "svg_name": "200-paths.svg", "width": 60, "at": [260, 0], "z": 0, "pen": 120},
}

NODE = """
import { nodeEngine } from %(node)s;
const e = await nodeEngine(%(wasm)s);
const r = e.robot("mk2plus");
const cases = %(cases)s, rounds = %(rounds)d, out = {};
for (const [name, req] of Object.entries(cases)) {
  r.draw(req);  // the first call compiles; the page's worker makes it before a student draws
  const ms = [];
  let d;
  for (let i = 0; i < rounds; i++) { const t = performance.now(); d = r.draw(req); ms.push(performance.now() - t); }
  out[name] = { ms, lines: d.program.split("\\n").length - 1, steps: d.ink.steps, worst: d.ink.worst_mm, paths: d.strokes.length };
}
console.log(JSON.stringify(out));
"""


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--build", default=str(REPO / "build"))
    args = ap.parse_args()
    import articula

    wasm_dir = Path(args.build) / "wasm" / "wasm"
    script = NODE % {"node": json.dumps(str(REPO / "wasm" / "js" / "node.mjs")), "wasm": json.dumps(str(wasm_dir)),
                     "cases": json.dumps(CASES), "rounds": args.rounds}
    web = json.loads(subprocess.run(["node", "--no-experimental-fetch", "--input-type=module", "-e", script],
                                    capture_output=True, text=True, check=True).stdout.strip().splitlines()[-1])
    mk2 = articula.Robot.load("mk2plus")
    print(f"bench_draw: MK2 Plus, {args.rounds} rounds each; one call: layout or SVG read, placing, reach check, order, "
          "program, prediction step by step, the pen's worst distance")
    print(f"{'case':<6} {'engine':<16} {'best ms':>8} {'median ms':>10}  what")
    ok = True
    for name, req in CASES.items():
        mk2.draw(**req)
        ms = []
        for _ in range(args.rounds):
            t = time.perf_counter()
            d = mk2.draw(**req)
            ms.append((time.perf_counter() - t) * 1000)
        w = web[name]
        assert w["lines"] == d["program"].count("\n") and w["steps"] == d["ink"]["steps"], ("the two engines differ", name, w["lines"], w["steps"], d["ink"]["steps"])
        what = (f"{len(d['strokes'])} strokes, {w['lines']} lines, {w['steps']} steps, worst {d['ink']['worst_mm']:.2f} mm")
        print(f"{name:<6} {'native (Python)':<16} {min(ms):>8.1f} {statistics.median(ms):>10.1f}  {what}")
        print(f"{name:<6} {'web (node wasm)':<16} {min(w['ms']):>8.1f} {statistics.median(w['ms']):>10.1f}  "
              f"web/native {statistics.median(w['ms']) / statistics.median(ms):.2f}x (medians)")
        met = statistics.median(w["ms"]) < 300
        ok &= met
        print(f"{'':<6} target: under 300 ms in the page's engine: {'met' if met else 'NOT met'}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
