"""The look-ahead planner, measured on the real firmware in simavr (the virtual Nano).

For each streamed plan of hil/streams (the 60 degree split, the circle, the zigzag, the square
with pen-up travel) on the MK2 in full steps and in half steps, streamed as a host that waits
for each reply sends it (`articula-vnano --paced`, the prediction's `stream` sender):

- the time from the first step to the last with the planner (the default $6) and with $6=0
  (every move from rest to rest, the firmware before the planner), and their ratio;
- the prediction's time for the same stream with the firmware's queue, and with a queue of
  100,000 places (what the queue's size costs);
- the worst difference between a move's end on the firmware and in the prediction.

Also the 60 degree base turn as one move against the same turn as 20 collinear moves (the
issue's benchmark: at most 1.03x).

    .venv/bin/python bench/bench_planner.py            # after `make`
"""
from __future__ import annotations

import sys
import tempfile
from pathlib import Path

SOURCE = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(SOURCE))
sys.path.insert(0, str(SOURCE / "python"))

from hil.harness.streams import ARMS, PLANS, compare, first_interval_ticks, lines_of, predicted, run_streamed  # noqa: E402


def span(steps: list[int]) -> float:
    return (steps[-1] - steps[0]) / 2000.0  # ms


def predicted_ms(robot: Path, plan: Path, queue: int = 0) -> float:
    p = predicted(robot, plan, queue=queue)
    moves = [r for r in p["records"] if r.get("dominant_steps", 0) > 0]
    return (moves[-1]["end_tick"] - moves[0]["start_tick"] - first_interval_ticks()) / 2000.0


def main() -> int:
    with tempfile.TemporaryDirectory() as tmp:
        tmp_path = Path(tmp)
        print("60 degree base turn (MK2), first step to last, in the virtual Nano:")
        for arm in ("full", "half"):
            robot = ARMS[arm]
            _, one = run_streamed(robot, ["M 60 90 0"], tmp_path)
            _, split = run_streamed(robot, lines_of(PLANS / "collinear-split.arm"), tmp_path)
            print(f"  {arm} step: one move {span(one):.3f} ms, 20 moves {span(split):.3f} ms, "
                  f"ratio {span(split) / span(one):.4f}")
        print()
        print("| plan | arm | planner ms | $6=0 ms | planner / $6=0 | predicted ms (queue 12) | "
              "predicted ms (queue 100,000) | queue's cost | worst move end vs prediction |")
        print("|---|---|---|---|---|---|---|---|---|")
        for name in ("collinear-split", "circle", "zigzag", "square"):
            plan = PLANS / f"{name}.arm"
            for arm in ("full", "half"):
                robot = ARMS[arm]
                r = compare(robot, plan, tmp_path)
                _, rest = run_streamed(robot, ["$6=0"] + lines_of(plan), tmp_path)
                blended = span(r["steps"])
                p12 = predicted_ms(robot, plan)
                big = predicted_ms(robot, plan, queue=100000)
                print(f"| {name} | {arm} | {blended:.1f} | {span(rest):.1f} | {blended / span(rest):.3f} | {p12:.1f} | "
                      f"{big:.1f} | {p12 / big:.3f}x | {r['worst_end_ticks'] / 2:.1f} us |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
