"""The look-ahead planner, measured on the real firmware in simavr (the virtual Nano).

For each streamed plan of hil/streams (the 60 degree split, the circle, the zigzag, the square
with pen-up travel) on the MK2 in full steps and in half steps, streamed as a host that waits
for each reply sends it (`articula-vnano --paced`, the prediction's `stream` sender):

- the time from the first step to the last with the planner (the default $6) and with $6=0
  (every move from rest to rest, the firmware before the planner), and their ratio;
- the prediction's time for the same stream (the firmware itself, on its virtual clock);
- the worst difference between a move's end on the firmware and in the prediction.

Also the 60 degree base turn as one move against the same turn as 20 collinear moves (the
issue's benchmark: at most 1.03x).

Straight lines (T, hil/streams/lines.arm):
- the tool's worst distance from its line at every step the firmware makes, against the
  chord tolerance plus the one-step bound (hil/tests/test_planner_streams.py asserts it);
- the Nano's cost of a line: from the end of its bytes to its first step, less the first
  step's interval and what a plain `M` line costs the same way (reading and quantizing),
  over its segments: the time to check the whole line and cut and plan its first segment;
  and the segments a second that leaves (two passes over each), against what a 50 mm/s
  drawing of the line's segments needs.

    .venv/bin/python bench/bench_planner.py            # after `make`
"""
from __future__ import annotations

import sys
import tempfile
from pathlib import Path

SOURCE = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(SOURCE))
sys.path.insert(0, str(SOURCE / "python"))

import articula  # noqa: E402
from hil.harness.streams import ARMS, PLANS, compare, first_interval_ticks, lines_of, predicted, run_streamed  # noqa: E402


def span(steps: list[int]) -> float:
    return (steps[-1] - steps[0]) / TICKS_PER_MS  # ms


def predicted_ms(robot: Path, plan: Path) -> float:
    p = predicted(robot, plan)
    moves = [r for r in p["records"] if r.get("dominant_steps", 0) > 0]
    return (moves[-1]["end_tick"] - moves[0]["start_tick"] - first_interval_ticks()) / TICKS_PER_MS


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
        print("| plan | arm | planner ms | $6=0 ms | planner / $6=0 | predicted ms | worst move end vs prediction |")
        print("|---|---|---|---|---|---|---|")
        for name in ("collinear-split", "circle", "zigzag", "square"):
            plan = PLANS / f"{name}.arm"
            for arm in ("full", "half"):
                robot = ARMS[arm]
                r = compare(robot, plan, tmp_path)
                _, rest = run_streamed(robot, ["$6=0"] + lines_of(plan), tmp_path)
                blended = span(r["steps"])
                p12 = predicted_ms(robot, plan)
                print(f"| {name} | {arm} | {blended:.1f} | {span(rest):.1f} | {blended / span(rest):.3f} | {p12:.1f} | "
                      f"{r['worst_end_ticks'] / 2:.1f} us |")
        print()
        lines_figures(tmp_path)
    return 0


def first_step_ms(robot: Path, line: str, tmp: Path) -> float:
    """The Nano's time (ms from the start of the run) of the first step of `line`, sent alone."""
    _, steps = run_streamed(robot, [line], tmp)
    return steps[0] / TICKS_PER_MS


TICKS_PER_MS = articula.STEP_TICK_HZ / 1000  # the step timer's ticks a millisecond (motion.h)


def lines_figures(tmp: Path) -> None:
    plan = PLANS / "lines.arm"
    byte_ms = 10 * 17 / TICKS_PER_MS  # a byte at the Nano's 117,647 baud (17 ticks a bit), in ms
    c0 = first_interval_ticks() / TICKS_PER_MS
    print("| arm | lines | segments | firmware ms | predicted ms | $6=0 ms | line's worst distance mm | "
          "check + first segment ms (a line of n segments) | per segment ms | segments/s the Nano cuts | "
          "segments/s at 50 mm/s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for arm in ("full", "half"):
        robot = ARMS[arm]
        r = compare(robot, plan, tmp)
        _, rest = run_streamed(robot, ["$6=0"] + lines_of(plan), tmp)
        pred = predicted(robot, plan)
        ts = [x for x in pred["records"] if x.get("segments")]
        segments = sum(len(x["segments"]) for x in ts)
        worst = max(x["line_error_mm"] for x in ts)
        # One line from the power-up pose: the first record of lines.arm.
        first = ts[0]
        t_line = first["command"]
        m_line = "M " + " ".join(f"{v:.3f}" for v in first_segment_angles(robot, first, pred))
        cruise_ms = max(c0, 4 * first["segments"][0]["cruise4"] / TICKS_PER_MS)
        cost = (first_step_ms(robot, t_line, tmp) - cruise_ms) - (first_step_ms(robot, m_line, tmp) - c0) \
            - (len(t_line) - len(m_line)) * byte_ms
        n = len(first["segments"])
        per = cost / n
        length = sum(((a - b) ** 2 for a, b in zip(first["target_mm"], [235.0, 0.0, 213.0]))) ** 0.5
        need = 50.0 / (length / n)
        print(f"| {arm} | {len(ts)} | {segments} | {span(r['steps']):.1f} | {r['predicted_ticks'] / 2000:.1f} | "
              f"{span(rest):.1f} | {worst:.3f} | {cost:.1f} ({n}) | {per:.2f} | {1000 / (2 * per):.0f} | {need:.1f} |")


def first_segment_angles(robot: Path, rec: dict, pred: dict) -> list[float]:
    """The motor angles at the end of a T record's first segment (its steps from power-up)."""
    import articula
    motors = articula.Robot.load(str(robot)).motors
    steps = rec["segments"][0]["delta_steps"]
    return [m["zero"] + m["direction"] * s * m["deg_per_step"] for m, s in zip(motors, steps)]


if __name__ == "__main__":
    sys.exit(main())
