"""Streams on the virtual Nano against the prediction: a plan's lines paced into the real
firmware in simavr as `articula predict --sender stream` models the host (`articula-vnano
--paced`), its steps read from the coil trace, each move's end compared with the predicted
one. hil/tests/test_planner_streams.py asserts on it, bench/bench_planner.py reports it.
"""
from __future__ import annotations

import csv
import json
import os
import subprocess
from pathlib import Path

import articula

SOURCE = Path(os.environ.get("ARTICULA_SOURCE_DIR", Path(__file__).resolve().parents[2]))
VNANO = Path(os.environ.get("ARTICULA_VNANO", SOURCE / "build/virtual-nano/articula-vnano"))
ELF = Path(os.environ.get("ARTICULA_NANO_ELF", SOURCE / "build/avr/firmware/articula-nano.elf"))
CLI = Path(os.environ.get("ARTICULA_CLI", SOURCE / "build/host/cli/articula"))
PLANS = SOURCE / "hil" / "streams"
STREAMED = ["collinear-split", "circle", "zigzag", "square", "stream-mixed", "lines"]
ARMS = {"full": SOURCE / "robots" / "mk2plus.json", "half": SOURCE / "hil" / "robots" / "mk2-halfstep.json"}
TICKS_PER_CYCLE = 16_000_000 // articula.STEP_TICK_HZ  # cycles of the 16 MHz Nano a step-timer tick
MAX_END_TICKS = 20           # 10 us: the HAL's jitter bound (firmware/README.md)
MAX_DURATION_PCT = 0.01


def lines_of(path: Path) -> list[str]:
    """The plan's lines as the harness sends them: comments and blanks out."""
    out = []
    for line in path.read_text().splitlines():
        text = articula.line_command(line)
        if text:
            out.append(text)
    return out


def configure_lines(robot: Path) -> list[str]:
    if robot == ARMS["full"]:
        return []
    p = subprocess.run([str(CLI), "configure", str(robot), "--dry-run"], capture_output=True, text=True, timeout=60)
    assert p.returncode == 0, p.stderr
    return [l for l in p.stdout.splitlines() if l.strip()]


def run_streamed(robot: Path, lines: list[str], tmp: Path, positions: list | None = None,
                 half_step: list[int] | None = None, stop_at: list[float] | None = None) -> tuple[list[str], list[int]]:
    """The lines through the virtual Nano, paced; its replies and the ticks of its steps (one
    a dominant step: the coil events of one deadline together). `positions`, when given, gets
    every motor's count after each of those steps (`half_step`: the motors counted in half
    steps). `stop_at`: a '!' at each of these times (seconds from the first line's arrival)."""
    trace = tmp / "trace.csv"
    setup = configure_lines(robot)
    extra = [a for m in (half_step or []) for a in ("--half-step", str(m))]
    extra += [a for t in (stop_at or []) for a in ("--stop-at", repr(t))]
    p = subprocess.run([str(VNANO), "--elf", str(ELF), "--stdio", "--paced", "--quiet", "--trace-steps", str(trace),
                        *extra], input="".join(l + "\n" for l in setup + lines), capture_output=True, text=True,
                       timeout=300)
    assert p.returncode == 0, p.stderr
    replies = [l for l in p.stdout.splitlines() if l == "ok" or l.startswith("error:")]
    assert replies[:len(setup)] == ["ok"] * len(setup), replies[:len(setup)]
    cycles: list[int] = []
    counts = [0, 0, 0]
    with trace.open() as f:
        for row in csv.DictReader(f):
            if not row["event"].startswith("step"):
                continue
            c = int(row["cycle"])
            counts[int(row["motor"])] = int(row["steps"])
            if cycles and c - cycles[-1] < 400:  # the same deadline: motors step a few cycles apart
                if positions is not None:
                    positions[-1] = list(counts)
                continue
            cycles.append(c)
            if positions is not None:
                positions.append(list(counts))
    return replies[len(setup):], [c // TICKS_PER_CYCLE for c in cycles]


def predicted(robot: Path, plan: Path, settings: str = "", stop_at: list[float] | None = None) -> dict:
    cmd = [str(CLI), "predict", str(robot), str(plan), "--sender", "stream", "--json"]
    if stop_at:
        cmd += ["--stop-at", ",".join(repr(t) for t in stop_at)]
    if settings:
        cmd += ["--settings", settings]
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert p.returncode in (0, 1), p.stderr
    return json.loads(p.stdout)


def first_interval_ticks(max_rate: int = articula.DEFAULT_SETTINGS[0], accel: int = articula.DEFAULT_SETTINGS[1]) -> int:
    """The profile's own first step (motion.h), in step-timer ticks: the firmware's defaults unless given."""
    return round(articula._core.first_interval_s(max_rate, accel) * articula.STEP_TICK_HZ)


def compare(robot: Path, plan: Path, tmp: Path) -> dict:
    pred = predicted(robot, plan)
    replies, steps = run_streamed(robot, lines_of(plan), tmp)
    records = pred["records"]
    assert replies == [r["reply"] if r["reply"] == "ok" else f"error:{r['code']}" for r in records]
    moves = [r for r in records if r.get("dominant_steps", 0) > 0]
    assert len(steps) == sum(r["dominant_steps"] for r in moves), "the firmware made other steps than predicted"
    c0 = first_interval_ticks()
    worst, k, offset, prev_end = 0.0, 0, None, None
    for r in moves:
        if prev_end is None or r["start_tick"] != prev_end:  # after rest with the arm idle: anchor again
            # (a T's first segment may cruise slower than the first step from rest: its interval)
            first = max(c0, 4 * r["segments"][0]["cruise4"]) if r.get("segments") else c0
            offset = steps[k] - (r["start_tick"] + first)
        k += r["dominant_steps"]
        d = steps[k - 1] - offset - r["end_tick"]
        worst = max(worst, abs(d))
        prev_end = r["end_tick"]
    measured = steps[-1] - steps[0]
    first = max(c0, 4 * moves[0]["segments"][0]["cruise4"]) if moves[0].get("segments") else c0
    expect = moves[-1]["end_tick"] - (moves[0]["start_tick"] + first)
    return {"worst_end_ticks": worst, "measured_ticks": measured, "predicted_ticks": expect, "steps": steps,
            "moves": moves}


