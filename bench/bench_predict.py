"""The prediction as a user calls it: `Robot.predict` in Python and `robot.predict` in the web
engine (node, the engine.wasm the page's worker loads), on bench_predict.cpp's programs: the
shipped streams and programs one after the other to 10,000 lines, and bench_draw.py's
60-character text as `robot.draw` writes it. The whole call: the program read, predicted
(`--sender rest`), and its records made (Python objects, or JSON for the page). In turn,
round after round; medians. bench/README.md, "The prediction".

    .venv/bin/python bench/bench_predict.py [--rounds 5] [--build build]
"""
from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "bench"))
from bench_draw import TEXT  # noqa: E402

FILES = ["hil/streams/circle.arm", "hil/streams/collinear-split.arm", "hil/streams/lines.arm",
         "hil/streams/square.arm", "hil/streams/stream-mixed.arm", "hil/streams/zigzag.arm",
         "programs/demo.arm", "programs/grasp-and-lift.arm", "programs/push.arm"]


def lines_of(text: str) -> list[str]:
    """The protocol lines of a program file, comments and blank lines left out (the core's
    rule: articula.line_command)."""
    from articula import line_command
    return [c for c in map(line_command, text.splitlines()) if c]


def streams10k() -> str:
    lines = [ln for f in FILES for ln in lines_of((REPO / f).read_text())]
    return "".join(lines[n % len(lines)] + "\n" for n in range(10000))


NODE = """
import { readFileSync } from "node:fs";
import { nodeEngine } from %(node)s;
const e = await nodeEngine(%(wasm)s);
const r = e.robot("mk2plus");
const cases = JSON.parse(readFileSync(0, "utf8")), rounds = %(rounds)d, out = {};
for (const [name, text] of Object.entries(cases)) {
  r.predict(text, name + ".arm");
  const ms = [];
  let p;
  for (let i = 0; i < rounds; i++) { const t = performance.now(); p = r.predict(text, name + ".arm"); ms.push(performance.now() - t); }
  out[name] = { ms, records: p.records.length, total_s: p.summary.total_s };
}
console.log(JSON.stringify(out));
"""


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--build", default=str(REPO / "build"))
    args = ap.parse_args()
    import articula

    mk2 = articula.Robot.load("mk2plus")
    cases = {"streams10k": streams10k(),
             "draw_text": mk2.draw(text=TEXT, width=120, at=(255, 0), z=0, pen=120)["program"]}
    wasm_dir = Path(args.build) / "wasm" / "wasm"
    script = NODE % {"node": json.dumps(str(REPO / "wasm" / "js" / "node.mjs")), "wasm": json.dumps(str(wasm_dir)),
                     "rounds": args.rounds}
    web = json.loads(subprocess.run(["node", "--no-experimental-fetch", "--input-type=module", "-e", script],
                                    input=json.dumps(cases), capture_output=True, text=True,
                                    check=True).stdout.strip().splitlines()[-1])
    print(f"bench_predict: MK2 Plus, --sender rest, {args.rounds} rounds each; the whole call, records made")
    print(f"{'program':<11} {'engine':<16} {'best ms':>8} {'median ms':>10}  what")
    for name, text in cases.items():
        program = articula.Program.parse(text, name + ".arm")
        mk2.predict(program)
        ms = []
        for _ in range(args.rounds):
            t = time.perf_counter()
            p = mk2.predict(program)
            ms.append((time.perf_counter() - t) * 1000)
        w = web[name]
        total = p.summary["total_s"] if isinstance(p.summary, dict) else p.summary.total_s
        # (the same records; the end may differ by a few ticks where a P's closed form, in float,
        # rounds differently under emscripten's libm: printed, not hidden)
        assert w["records"] == len(p.records), ("the two engines differ", name, w["records"], len(p.records))
        print(f"{name:<11} {'native (Python)':<16} {min(ms):>8.1f} {statistics.median(ms):>10.1f}  "
              f"{len(p.records)} records, {total:.6f} s of the arm's time")
        print(f"{name:<11} {'web (node wasm)':<16} {min(w['ms']):>8.1f} {statistics.median(w['ms']):>10.1f}  "
              f"web/native {statistics.median(w['ms']) / statistics.median(ms):.2f}x (medians); {w['total_s']:.6f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
