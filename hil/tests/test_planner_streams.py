"""The look-ahead planner on the real firmware in simavr, against the prediction.

Each plan of hil/streams (the collinear split, the circle, the
zigzag, the square with pen-up travel, a stream mixed with G, D, S and a setting) goes into
the virtual Nano paced as `articula predict --sender stream` models the host: each line as
soon as the reply to the one before is off the wire (`articula-vnano --paced`). On the MK2
in full steps and in half steps (configured at run time, hil/robots/mk2-halfstep.json):

- the firmware makes the predicted steps, move by move;
- every move ends where the prediction says, to within the HAL's jitter (10 us), and the
  whole stream within 0.01 % of its predicted duration;
- a stream without reversals does not stop: no step interval at an inner junction is as
  long as the first step from rest;
- with $6=0 the same split takes its rest-to-rest time (the issue's 4.6x);
- the straight lines (T) of lines.arm keep the tool, at every step the firmware makes, within
  the chord tolerance plus one step of each motor of the line;
- '!' sent at set times after the first step (`--stop-at`, a student pressing STOP) mid-move,
  mid-stream and in a pause: the arm comes to rest on the predicted steps at the predicted
  tick, the line waiting then is answered error:15, the lines after start from there.

The figures are printed (pytest -s shows them); bench/bench_planner.py reports them.
"""
from __future__ import annotations

import os
import sys
from pathlib import Path

import pytest

SOURCE = Path(os.environ.get("ARTICULA_SOURCE_DIR", Path(__file__).resolve().parents[2]))
sys.path.insert(0, str(SOURCE))
from hil.harness.streams import ARMS, MAX_DURATION_PCT, MAX_END_TICKS, PLANS, STREAMED, compare, first_interval_ticks, \
    lines_of, predicted, run_streamed  # noqa: E402

@pytest.mark.parametrize("arm", ["full", "half"])
@pytest.mark.parametrize("name", STREAMED)
def test_a_stream_ends_on_the_predicted_steps_and_ticks(name, arm, tmp_path):
    r = compare(ARMS[arm], PLANS / f"{name}.arm", tmp_path)
    print(f"{name} ({arm} step): {len(r['steps'])} steps, measured {r['measured_ticks'] / 2000:.3f} ms, "
          f"predicted {r['predicted_ticks'] / 2000:.3f} ms, worst move end {r['worst_end_ticks'] / 2:.1f} us")
    assert r["worst_end_ticks"] <= MAX_END_TICKS
    if name != "stream-mixed":  # ($6= waits for rest: the gap after it is the host's, not predicted)
        assert abs(r["measured_ticks"] - r["predicted_ticks"]) <= r["predicted_ticks"] * MAX_DURATION_PCT / 100


@pytest.mark.parametrize("arm", ["full", "half"])
def test_a_stream_of_segments_does_not_stop(arm, tmp_path):
    # (not the zigzag: its base reverses at every junction, where the rule's level, $6 / 100 =
    # 0.5, rounds to rest; a reversal must stop)
    for name in ("collinear-split", "circle"):
        r = compare(ARMS[arm], PLANS / f"{name}.arm", tmp_path)
        steps, c0 = r["steps"], first_interval_ticks()
        k = 0
        for m in r["moves"][:-1]:  # inner junctions: the first step of the next move
            k += m["dominant_steps"]
            gap = steps[k] - steps[k - 1]
            assert gap < c0, f"{name}: the arm stopped after line {m['line']} ({gap} ticks, a start from rest is {c0})"


def test_the_junction_setting_at_zero_is_rest_to_rest(tmp_path):
    plan = PLANS / "collinear-split.arm"
    lines = lines_of(plan)
    _, blended = run_streamed(ARMS["full"], lines, tmp_path)
    _, rest = run_streamed(ARMS["full"], ["$6=0"] + lines, tmp_path)
    one_move = predicted(ARMS["full"], plan, "6=0")
    assert len(blended) == len(rest)
    ratio_blended = (blended[-1] - blended[0])
    ratio_rest = (rest[-1] - rest[0])
    # The rest-to-rest split is the sum of its moves' rest-to-rest profiles (the prediction at $6=0).
    moves = [r for r in one_move["records"] if r.get("dominant_steps", 0) > 0]
    expect_rest = sum(r["ticks"] for r in moves) - first_interval_ticks()
    assert abs(ratio_rest - expect_rest) <= MAX_END_TICKS
    print(f"60 deg base turn as 20 moves: blended {ratio_blended / 2000:.3f} ms, $6=0 {ratio_rest / 2000:.3f} ms "
          f"({ratio_rest / ratio_blended:.2f}x)")
    assert ratio_rest > 4 * ratio_blended


@pytest.mark.parametrize("arm", ["full", "half"])
def test_a_straight_line_stays_within_one_step_of_the_line(arm, tmp_path):
    """The straight lines of lines.arm, the tool at every step the firmware makes (its coils'
    trace through the forward kinematics): within the chord tolerance ($7, 0.1 mm) plus the
    one-step bound of the ideal line, the bound where the tool is (each motor one step on,
    the tool's displacements summed: |J_i| times the step angle, summed)."""
    from hil.harness.robot import Robot
    robot = Robot(ARMS[arm])
    plan = PLANS / "lines.arm"
    pred = predicted(ARMS[arm], plan)
    positions: list[list[int]] = []
    replies, _ = run_streamed(ARMS[arm], lines_of(plan), tmp_path, positions, robot.half_step_motors)
    assert replies == ["ok"] * len(lines_of(plan))

    def tool(counts):
        return robot.tool_from_actuators([m.zero + m.direction * c * m.deg_per_step for m, c in zip(robot.motors, counts)])

    def distance(p, a, b):
        ab = [b[i] - a[i] for i in range(3)]
        t = sum((p[i] - a[i]) * ab[i] for i in range(3)) / max(sum(x * x for x in ab), 1e-12)
        t = min(1.0, max(0.0, t))
        return sum((p[i] - a[i] - t * ab[i]) ** 2 for i in range(3)) ** 0.5

    k, start, worst, worst_ratio = 0, list(robot.tool_from_actuators(robot.zero_angles)), 0.0, 0.0
    for r in pred["records"]:
        n = r.get("dominant_steps", 0)
        if r.get("segments"):
            a, b = start, r["target_mm"]
            for counts in positions[k:k + n]:
                here = tool(counts)
                bound = 0.0
                for i in range(3):
                    moved = list(counts)
                    moved[i] += 1
                    bound += sum((x - y) ** 2 for x, y in zip(tool(moved), here)) ** 0.5
                d = distance(here, a, b)
                assert d <= 0.1 + bound + 1e-6, f"line {r['line']}: {d:.3f} mm off the line, bound {0.1 + bound:.3f}"
                worst = max(worst, d)
                worst_ratio = max(worst_ratio, d / (0.1 + bound))
            assert abs(r["line_error_mm"] - max(distance(tool(c), a, b) for c in positions[k:k + n])) < 1e-3
        k += n
        start = r["tool_ideal_mm"]
    assert k == len(positions)
    print(f"lines.arm ({arm} step): the tool at every step within {worst:.3f} mm of its line, at most "
          f"{worst_ratio * 100:.0f} % of the chord tolerance plus one step")


# (times after the first step; the plans whose lines the Nano reads as fast as the model: M,
# G, D, S, $, and P lines that are queued ahead. While the Nano is still cutting a T, or
# solving a P that waits for room, its own computing time decides where a '!' lands.)
STOPS = {"stream-mixed": [[0.05, 0.7], [0.15, 1.2, 2.5]], "collinear-split": [[0.1, 0.6]],
         "square": [[0.4, 1.5]]}


@pytest.mark.parametrize("name,stop_at", [(n, t) for n, ts in STOPS.items() for t in ts])
def test_a_stop_ends_on_the_predicted_steps(name, stop_at, tmp_path):
    plan = PLANS / f"{name}.arm"
    pred = predicted(ARMS["full"], plan, stop_at=stop_at)
    positions: list = []
    replies, steps = run_streamed(ARMS["full"], lines_of(plan), tmp_path, positions=positions, stop_at=stop_at)
    records = pred["records"]
    assert replies == [r["reply"] if r["reply"] == "ok" else f"error:{r['code']}" for r in records if not r.get("stop")]
    assert len(records) - len(replies) == len(stop_at)
    assert len(steps) == sum(r["dominant_steps"] for r in records), "the firmware made other steps than predicted"
    first = pred["summary"]["first_step_tick"]
    k, cut, worst = 0, 0, 0
    for r in records:
        k += r["dominant_steps"]
        cut += bool(r.get("cut"))
        if r.get("stop") and k:
            # at rest where predicted, and when (the last step before the '!' settled)
            assert positions[k - 1] == r["steps"], f"'!' at {r['stop_at_tick']}: {positions[k - 1]} != {r['steps']}"
            # (the first: after a stop the Nano's own time to take up the lines again, not modelled,
            # shifts the times, not the steps)
            if r["end_tick"] > r["stop_at_tick"] and r is next(x for x in records if x.get("stop")):
                d = (steps[k - 1] - steps[0]) - (r["end_tick"] - first)
                worst = max(worst, abs(d))
        elif r["dominant_steps"]:
            assert positions[k - 1] == r["steps"], f"line {r['line']}"
    assert cut > 0, "no '!' cut anything short: the test would not see a wrong stop"
    assert worst <= MAX_END_TICKS
    print(f"{name}, '!' at {stop_at} s: {len(steps)} steps, {cut} lines cut short or dropped, "
          f"worst rest tick {worst / 2:.1f} us off")
