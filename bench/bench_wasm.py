#!/usr/bin/env python3
"""The web engine's speed against native code, measured in the same run on the same machine
(bench/README.md, "The web engine").

bench/bench_engine.cpp is built twice, natively (build/bench/bench_engine) and by emscripten
(build/wasm/wasm/bench_engine.js, run by node). This runs the two in turn, round after round,
and prints each figure's best over the rounds (the machine is shared and its speed drifts by
up to 2x between seconds: the best is the steadiest estimate of what each build can do), the
ratio wasm/native of the two bests, judged against the targets of the issue that asked for the
web engine, and the range of the rounds' own ratios; then the site's size.

    .venv/bin/python bench/bench_wasm.py [--rounds 5] [--build build]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]

# figure, label, unit, lower is better, target ratio (wasm/native time), what the target says
FIGURES = [
    ("fk_ns", "Panda FK, one call", "ns", True, 1.3, "at most 1.3x native time"),
    ("panda_ik_median_us", "Panda IK, median", "us", True, 1.3, "at most 1.3x native"),
    ("panda_ik_p95_us", "Panda IK, 95th percentile", "us", True, 1.3, "at most 1.3x native"),
    ("mk2_ik_median_us", "MK2 closed-form IK, median", "us", True, 2.0, "at most 2x native"),
    ("mk2_ik_mean_us", "MK2 closed-form IK, mean of 1,000", "us", True, 2.0, "at most 2x native"),
    ("physics_steps_per_s", "physics, MK2 + cube, world steps/s", "/s", False, 0.6, "at least 0.6x native"),
]


def run(cmd: list[str]) -> dict:
    out = subprocess.run(cmd, capture_output=True, text=True, check=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--build", default=str(REPO / "build"))
    args = ap.parse_args()
    build = Path(args.build)
    native = [str(build / "bench" / "bench_engine")]
    # --no-liftoff: V8's optimising compiler from the start. A page's hot code gets there after
    # its first calls; the kernels' loops run once per measurement, too few calls to tier up.
    wasm = ["node", "--no-experimental-fetch", "--no-liftoff", str(build / "wasm" / "wasm" / "bench_engine.js")]
    # The web engine's build tree builds its copy on demand (it is not part of `make`).
    subprocess.run(["cmake", "--build", str(build / "wasm"), "--target", "bench_engine"], check=True,
                   env=dict(os.environ, NODE_PATH="/usr/share/nodejs"), stdout=subprocess.DEVNULL)
    for c in (native[0], wasm[-1]):
        if not Path(c).exists():
            print(f"bench_wasm: {c} is not built: run make")
            return 2
    rounds: list[tuple[dict, dict]] = []
    for r in range(args.rounds):
        n = run(native)
        w = run(wasm)
        rounds.append((n, w))
        print(f"round {r + 1}/{args.rounds}: FK {n['fk_ns']:.0f} / {w['fk_ns']:.0f} ns, Panda IK median "
              f"{n['panda_ik_median_us']:.2f} / {w['panda_ik_median_us']:.2f} us, physics "
              f"{n['physics_steps_per_s']:.0f} / {w['physics_steps_per_s']:.0f} steps/s (native / wasm)",
              file=sys.stderr, flush=True)
    print(f"\n{'figure (best of the rounds)':38s} {'native':>10s} {'wasm':>10s} {'ratio':>7s} {'rounds':>13s}  target")
    for key, label, unit, lower, target, words in FIGURES:
        best = min if lower else max
        nat = best(n[key] for n, _ in rounds)
        was = best(w[key] for _, w in rounds)
        ratios = [w[key] / n[key] for n, w in rounds]
        ratio = was / nat
        ok = ratio <= target if lower else ratio >= target
        print(f"{label:38s} {nat:10.3f} {was:10.3f} {ratio:6.2f}x {min(ratios):5.2f}..{max(ratios):4.2f}  "
              f"{words}: {'met' if ok else 'MISSED'}  ({unit})")
    for k in ("panda_ik_success", "mk2_ik_success"):
        print(f"{k}: native {rounds[0][0][k]:.3f}, wasm {rounds[0][1][k]:.3f}")
    sizes = REPO / "studio" / "web" / "dist" / "sizes.json"
    if sizes.is_file():
        s = json.loads(sizes.read_text())
        print(f"the site: {s['bytes'] / 1024:.0f} KB, {s['gzipped'] / 1024:.0f} KB gzipped (target 3 MB gzipped)")
        for f in ("engine/engine.wasm", "engine/engine.mjs"):
            p = sizes.parent / f
            import gzip
            b = p.read_bytes()
            print(f"  {f}: {len(b) / 1024:.0f} KB, {len(gzip.compress(b, 9)) / 1024:.0f} KB gzipped")
    return 0


if __name__ == "__main__":
    sys.exit(main())
