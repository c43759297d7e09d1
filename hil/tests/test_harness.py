"""The harness (hil/harness) end to end on the virtual Nano: the shipped plans, a random plan,
and what it does when things go wrong (an error reply, a timeout, a port that vanishes or
hangs). Run by ctest (hil.harness) with the paths of the binaries in the environment:

    ARTICULA_VNANO, ARTICULA_NANO_ELF, ARTICULA_SOURCE_DIR

and the `articula` package built (make). It fails, never skips, when one is missing. About 40 s.
"""

import csv
import json
import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

SOURCE = Path(os.environ.get("ARTICULA_SOURCE_DIR") or Path(__file__).resolve().parents[2])
sys.path.insert(0, str(SOURCE))

from hil.harness import report  # noqa: E402
from hil.harness.plan import parse_plan  # noqa: E402
from hil.harness.robot import Robot  # noqa: E402
from hil.harness.runner import Runner, kill_later  # noqa: E402
from hil.harness.targets import VirtualNanoTarget  # noqa: E402

ROBOT = SOURCE / "robots" / "mk2plus.json"
PLANS = sorted((SOURCE / "hil" / "plans").glob("*.arm"))


def _binary(name: str, default: Path) -> str:
    p = Path(os.environ.get(name) or default)
    assert p.exists(), f"{name}: no {p} (build first: cmake --build build)"
    return str(p)


@pytest.fixture(scope="module")
def bins():
    return {
        "vnano": _binary("ARTICULA_VNANO", SOURCE / "build" / "virtual-nano" / "articula-vnano"),
        "elf": _binary("ARTICULA_NANO_ELF", SOURCE / "build" / "avr" / "firmware" / "articula-nano.elf"),
    }


# A guard against a hang, not a speed check: ctest's own limit (600 s) is the outer one, and a
# busy machine may take several times a quiet one's minute.
def harness(bins, *args, timeout=500):
    cmd = [sys.executable, "-m", "hil.harness", "run", "--vnano", bins["vnano"],
           "--elf", bins["elf"], *map(str, args)]
    env = dict(os.environ, PYTHONPATH=str(SOURCE))
    t0 = time.monotonic()
    p = subprocess.run(cmd, cwd=SOURCE, capture_output=True, text=True, timeout=timeout, env=env)
    p.wall = time.monotonic() - t0
    return p


def rows(out: Path):
    with open(out / "commands.csv") as f:
        return list(csv.DictReader(f))


def test_shipped_plans_match_everywhere(bins, tmp_path):
    assert len(PLANS) >= 3, PLANS
    # Measured positions for a few plan steps (as from a tape measure): the report then
    # compares them with the prediction. Offsets of 1-2 mm from the ideal position.
    measured = tmp_path / "measured.csv"
    measured.write_text("plan,plan_line,x_mm,y_mm,z_mm\n"
                        "thesis-single-joint.arm,30,232.4,40.0,213.5\n"
                        "thesis-single-joint.arm,30,232.6,40.2,213.3\n"
                        "thesis-single-joint.arm,51,313.0,0.5,187.0\n"
                        "thesis-repeatability.arm,61,170.0,-110.0,200.0\n")
    out = tmp_path / "report"
    p = harness(bins, *PLANS, "--out", out, "--measured", measured)
    print(p.stdout, p.stderr)
    assert p.returncode == 0, p.stdout + p.stderr
    n = sum(len(parse_plan(x).commands) for x in PLANS)
    assert f"steps matched: {n}/{n} (prediction = firmware = pins)" in p.stdout
    assert "faults: 0" in p.stdout
    assert f"report: {out / 'report.md'}" in p.stdout

    data = rows(out)
    assert len(data) == n
    for r in data:
        assert r["matched"] == "True", r
        assert r["firmware_match"] == "True" and r["pins_match"] == "True", r
        assert r["predicted_reply"] == r["firmware_reply"] == r["expect"], r
        assert r["coil_faults"] == "0" and not r["faults"], r
    timed = [r for r in data if r["duration_err_pct"]]
    assert len(timed) >= 40
    for r in timed:
        assert abs(float(r["duration_err_pct"])) < 1.0, r   # predicted vs pins' cycle stamps
    assert any(r["kind"] == "single-joint" for r in data)
    assert any(r["kind"] == "repeat-out" for r in data)

    for f in ("report.md", "report.html", "commands.csv", "steps.png", "quantization.png", "durations.png",
              "single-joint-0.png", "single-joint-1.png", "single-joint-2.png",
              "repeatability-thesis-repeatability.png", "vnano/thesis-single-joint.json",
              "transcripts/tool-points.txt"):
        assert (out / f).is_file() and (out / f).stat().st_size > 0, f
    md = (out / "report.md").read_text()
    for heading in ("## Summary", "## Faults", "## Step agreement", "## Predicted quantization error",
                    "## Durations", "## Single-joint movements (thesis 5.2, Table 4, Figs. 30-32)",
                    "## Repeatability (thesis 5.3, Table 5)", "## Tool to points (P)", "## Measured tool positions",
                    "## Virtual Nano"):
        assert heading in md, heading
    # Table 4: max %, max mm, average mm per joint and axis.
    assert "| axis | joint 0 max % | joint 0 max mm | joint 0 avg mm | joint 1 max % |" in md
    assert re.search(r"^\| X \| [0-9.]+ \| [0-9.]+ \| [0-9.]+ \|", md, re.M)
    assert "**Measured vs predicted (quantized)**" in md
    # Table 5: chains of 1 to 5 moves, back exactly at the start.
    table5 = [ln for ln in md.splitlines() if re.match(r"^\| [1-5] \| \d+ \| [0-9.]+ \| \d+ \| 0\.000 \| yes \| yes", ln)]
    assert len(table5) == 5, md
    assert "Refused by the arm (beyond its limits), as the plan expects" in md
    html = (out / "report.html").read_text()
    assert "<table>" in html and "steps.png" in html


def test_random_plan(bins, tmp_path):
    out = tmp_path / "random"
    # The acceptance: at least 1,000 random commands, 0 mismatches, 0 faults. Fast settings
    # ($0, $1, $5) keep it short: 1,000 commands in about 50 s.
    # (--no-plots: a report of tables only, none of matplotlib's work; test_shipped_plans... draws them)
    p = harness(bins, "--random", 1000, "--seed", 11, "--settings", "0=4000,1=100000,5=20", "--out", out, "--no-plots")
    print(p.stdout, p.stderr)
    assert p.returncode == 0, p.stdout + p.stderr
    assert "steps matched: 1000/1000 (prediction = firmware = pins)" in p.stdout
    assert "faults: 0" in p.stdout
    assert not list(out.glob("*.png"))
    assert "| plots | not drawn (--no-plots): the tables below have every figure |" in (out / "report.md").read_text()
    plan = out / "random-1000-seed-11.arm"
    assert plan.is_file()
    data = rows(out)
    assert len(data) == 1000
    assert all(r["matched"] == "True" for r in data)
    refused = [r for r in data if r["expect"] != "ok"]
    assert len(refused) >= 10
    assert all(r["firmware_reply"] == r["expect"] for r in refused)
    kinds = {r["command"].split()[0] for r in data if r["expect"] == "ok"}
    assert kinds >= {"L", "M", "P", "G"}
    for r in data:
        if r["duration_err_pct"]:
            assert abs(float(r["duration_err_pct"])) < 1.0, r
    # Same seed, same plan.
    env = dict(os.environ, PYTHONPATH=str(SOURCE))
    g = subprocess.run([sys.executable, "-m", "hil.harness", "generate", "1000", "--seed", "11"],
                       cwd=SOURCE, capture_output=True, text=True, env=env, timeout=60)
    assert g.returncode == 0, g.stderr
    assert g.stdout == plan.read_text()


def test_rejected_line_is_reported_with_its_plan_line(bins, tmp_path):
    plan = tmp_path / "reject.arm"
    plan.write_text("# a line the arm refuses, not marked #@ expect\nL 0 10\nL 1 100\nL 0 -10\n")
    out = tmp_path / "out"
    p = harness(bins, plan, "--out", out, "--no-plots")
    print(p.stdout, p.stderr)
    assert p.returncode == 1
    assert "faults: 1" in p.stdout
    assert "reject.arm:3: L 1 100: error reply error:9" in p.stdout
    assert "MISMATCH OR FAULT" in p.stdout
    md = (out / "report.md").read_text()
    assert "| reject.arm:3 | `L 1 100` | error-reply |" in md
    data = rows(out)
    assert [r["firmware_reply"] for r in data] == ["ok", "error:9", "ok"]
    assert data[2]["fw_steps_0"] == "0"  # the rest of the plan ran


def test_timeout_is_reported(bins, tmp_path):
    plan = tmp_path / "slow.arm"
    # At 2 steps/s L 0 80 takes two minutes of the Nano's time. The virtual Nano sleeps through
    # most of a slow move and can finish it within 0.3 s of the wall clock on a quiet machine:
    # the limit holds in the Nano's time (the pins' cycle stamps) as well as the wall clock's.
    plan.write_text("L 0 5\n$0=2\n#@ timeout 0.3\nL 0 80\nL 0 -85\n")
    out = tmp_path / "out"
    p = harness(bins, plan, "--out", out, "--no-plots")
    print(p.stdout, p.stderr)
    assert p.returncode == 1
    assert p.wall < 30
    assert re.search(r"slow\.arm:4: L 0 80: timeout: not at rest within 0\.3 s", p.stdout), p.stdout
    md = (out / "report.md").read_text()
    assert "1 command(s) not run" in md
    assert [r["firmware_reply"] for r in rows(out)] == ["ok", "ok", "ok", ""]


class _Signal:
    """A hook that signals the virtual Nano shortly after a given plan line is sent."""

    def __init__(self, line, sig, delay=0.3):
        self.line, self.sig, self.delay = line, sig, delay
        self.pid = None

    def after_send(self, runner, rec):
        if rec.line == self.line:
            self.pid = runner.target.proc.pid
            kill_later(self.pid, self.delay, self.sig)


def _run_with_hook(bins, tmp_path, text, hook, timeout=5.0):
    robot = Robot(ROBOT)
    path = tmp_path / "hooked.arm"
    path.write_text(text)
    target = VirtualNanoTarget(bins["vnano"], bins["elf"], len(robot.motors))
    runner = Runner(target, robot, tmp_path / "out", timeout=timeout, hooks=hook)
    t0 = time.monotonic()
    try:
        res = runner.run_plan(parse_plan(path))
    finally:
        target.close()
    return res, time.monotonic() - t0, target


def test_vanished_port_is_reported(bins, tmp_path):
    # The kill comes 50 ms after line 3 is sent, while the harness waits for its move to end.
    # The move is slow in the Nano's time (256 steps at 1 step/s), and the sleeping firmware
    # lets the emulator run it some 80 times faster than real time: about 3 s of wall time,
    # long enough on a busy machine (0.3 s after a 2 steps/s move was not: the move could end
    # first, and the port vanish at line 4).
    hook = _Signal(3, signal.SIGKILL, delay=0.05)
    res, wall, target = _run_with_hook(bins, tmp_path, "L 0 10\n$0=1\nL 0 80\nL 0 -90\n", hook)
    assert wall < 15
    kinds = [(f.line, f.kind) for f in res.faults]
    assert (3, "vanished") in kinds, res.faults
    f = next(f for f in res.faults if f.kind == "vanished")
    assert "the port vanished" in f.message and "killed by SIGKILL" in f.message, f.message
    assert "1 command(s) not run" in res.aborted
    assert target.proc.poll() is not None
    # line 3's ok may or may not have come before the kill; line 4 was never sent
    replies = [r.reply for r in res.records]
    assert replies[:2] == ["ok", "ok"] and replies[2] in ("ok", None) and replies[3] is None, replies
    # And the report says so.
    run = report.Run(results=[res], target="virtual Nano", robot_name="MK2 Plus", robot_path=str(ROBOT),
                     vnano=bins["vnano"], elf=bins["elf"], started="now", wall_s=wall,
                     settings_override={}, measured_path=None, has_pins=True, command_line="test")
    md = report.build(run, tmp_path / "out", Robot(ROBOT))
    text = md.read_text()
    assert "| hooked.arm:3 | `L 0 80` | vanished |" in text
    assert "hooked.arm:3: L 0 80: the port vanished" in report.summary_text(run, md)


def test_hung_port_times_out(bins, tmp_path):
    # The virtual Nano stops (SIGSTOP) in the middle of a move: the port stays open and
    # silent. The harness gives up after its timeout and still ends the process.
    hook = _Signal(3, signal.SIGSTOP, delay=0.1)
    res, wall, target = _run_with_hook(bins, tmp_path, "L 0 10\n$0=2\nL 0 60\nL 0 -70\n", hook, timeout=1.0)
    assert wall < 60  # gave up (1 s timeouts), rather than waiting forever
    f = next(f for f in res.faults if f.kind == "timeout")
    assert f.line == 3, res.faults
    # The stop may land in the middle of a status line; the message then quotes the partial line
    # between its two parts, so check them separately.
    assert "no answer to ? within 1.0 s" in f.message, f.message
    assert "the port is silent" in f.message, f.message
    assert target.proc.poll() is not None  # continued and terminated


def test_a_serial_port_takes_the_same_path(bins, tmp_path):
    """--port: the harness opens a port by its name, exactly as it would /dev/ttyUSB0. Here the
    port is a virtual Nano started by hand (in real time, as a person would run it), so there
    are no pins: durations come from the host's clock. After each plan the harness puts back
    the settings the arm had and parks it at step 0."""
    import serial

    link = tmp_path / "nano"
    proc = subprocess.Popen([bins["vnano"], "--elf", bins["elf"], "--pty-link", str(link), "--realtime", "--quiet"],
                            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL)
    try:
        assert proc.stdout.readline().startswith(b"pty: ")
        one = tmp_path / "one.arm"
        one.write_text("$0=800\nL 0 20\nG 50\nL 1 -10\n")
        two = tmp_path / "two.arm"
        two.write_text("L 0 5\nL 2 -5\n")
        out = tmp_path / "out"
        p = harness(bins, one, two, "--port", link, "--boot-wait", "0", "--out", out)
        print(p.stdout, p.stderr)
        assert p.returncode == 0, p.stdout + p.stderr
        assert "steps matched: 6/6 (prediction = firmware)" in p.stdout
        assert "timed by the host clock" in p.stdout
        data = rows(out)
        assert all(r["pins_match"] == "" for r in data)
        timed = [r for r in data if r["duration_source"] == "host clock"]
        assert len(timed) == 5
        for r in timed:
            # Only roughly: the host clock adds the line's and the status report's transmission
            # and up to one poll, and a virtual Nano in real time on a busy machine lags and
            # catches up (its pins, not the host clock, are what times it exactly).
            pred, meas = float(r["pred_duration_s"]), float(r["measured_duration_s"])
            assert 0.5 * pred - 0.05 < meas < 2 * pred + 2.0, r
        assert "| target | serial port" in (out / "report.md").read_text()
        # Left as found: default settings, every motor on step 0.
        with serial.Serial(str(link), 115200, timeout=2) as s:
            s.write(b"$\n")
            assert s.readline() == b"$0=600.000\n"
            while s.readline() != b"ok\n":
                pass
            s.write(b"?")
            assert s.readline().startswith(b"<Idle|S:0,0,0|")
    finally:
        proc.terminate()
        proc.wait(timeout=10)


# The co-design arms, and the shipped robots of each drive but the thesis's L298N (whose MK2 every
# plan already runs): the MK2 Plus on a CNC shield, the meArm, the EEZYbotARM MK2 on servos, the micro arm on
# 28BYJ-48s.
SHIPPED = [SOURCE / "robots" / f for f in (
    "mk2plus-cnc.json", "mearm.json", "eezybot-mk2.json", "micro-arm-28byj48.json")]
ARMS = sorted((SOURCE / "hil" / "robots").glob("*.json")) + SHIPPED


@pytest.mark.parametrize("arm", ARMS, ids=[a.stem for a in ARMS])
def test_one_firmware_configured_for_each_arm(bins, tmp_path, arm):
    """Co-design: the one firmware, configured at run time for an arm of hil/robots (the
    harness sends its configuration when the banner's checksum differs), runs the shipped
    plans and random lines to the steps `articula predict` gives for that arm, with the
    replies the prediction gives (the plans' #@ expect are the MK2's). The page's virtual Nano
    runs the same arms (studio/web/tests/nano-codesign.test.mjs)."""
    out = tmp_path / "report"
    # The plans' 73 commands and 130 random lines: at least 200 lines an arm (issue 40's bar).
    p = harness(bins, *PLANS, "--robot", arm, "--random", 130, "--seed", 3, "--expect-predicted", "--out", out, "--no-plots")
    print(p.stdout, p.stderr)
    assert p.returncode == 0, p.stdout + p.stderr
    data = rows(out)
    n = len(data)
    assert n >= 200
    assert f"steps matched: {n}/{n} (prediction = firmware = pins)" in p.stdout
    assert "faults: 0" in p.stdout
    for r in data:
        assert r["predicted_reply"] == r["firmware_reply"], r
    # The configuration went in once per plan (a fresh virtual Nano each) and took (a shipped
    # robot may be its build's built-in arm: then none is needed).
    transcript = (out / "transcripts" / "tool-points.txt").read_text()
    assert "|K:" in transcript and ("$199=" in transcript or arm in SHIPPED)
    # (Timed by the pins' cycle stamps: a move no pin shows is timed by the host's clock, which a
    # busy machine stretches; the bound below is the pins'.)
    timed = [r for r in data if r["duration_err_pct"] and r["duration_source"] == "pins"]
    assert len(timed) > 60
    worst_us = max(abs(float(r["duration_diff_us"])) for r in timed)
    worst_pct = max(abs(float(r["duration_err_pct"])) for r in timed)
    print(f"  {arm.stem}: {n} commands, {len(timed)} moves timed, worst duration error {worst_pct:.5f} % "
          f"({worst_us:.1f} us)")
    # Every step lands on the tick the prediction gives; a pin shows it a few microseconds
    # late (the step interrupt's entry), never more than the firmware's jitter target. A servo's
    # pin shows its width once a period (20 ms), and a change shows once it is two ticks, or one
    # that two pulses agree on: at $1's 2000 steps/s^2 a ramp's first two ticks take
    # sqrt(2 * 2 / 2000) = 45 ms, so a move's first change shows up to 45 ms + two periods after
    # its first step, and its last as much before or after its last: its span on the pins is
    # the prediction's within 2 x 85 = 170 ms. The steps themselves are checked where they end.
    servos = any(m.get("driver", {}).get("kind") == "servo" for m in json.loads(arm.read_text())["motors"])
    assert worst_us <= (170000.0 if servos else 10.0)
    # Each build keeps its stack margin (issue 40: at least 128 bytes never used), whatever the
    # arm's drive: the virtual Nano paints the stack and reports the least left free.
    free = [json.loads(f.read_text())["stack"]["min_free_bytes"] for f in sorted((out / "vnano").glob("*.json"))]
    assert len(free) == len(PLANS) + 1 and min(free) >= 128, free
    print(f"  {arm.stem}: stack never used, least of {len(free)} runs: {min(free)} bytes")


def test_a_drawing_runs_on_the_firmware_step_for_step(bins, tmp_path):
    """Issue 29: `articula draw`, then the harness on simavr: the firmware's steps and its pins
    along every line of the drawing are the prediction's."""
    cli = _binary("ARTICULA_CLI", SOURCE / "build" / "host" / "cli" / "articula")
    for name, what in (("hi", ["--text", "Hi"]), ("house", [str(SOURCE / "examples" / "drawings" / "house.svg")])):
        program = tmp_path / f"{name}.arm"
        d = subprocess.run([cli, "draw", "mk2plus", *what, "--width", "40", "--at", "260,0", "--z", "0", "--pen", "120",
                            "-o", str(program)], capture_output=True, text=True, timeout=120)
        assert d.returncode == 0, d.stdout + d.stderr
        lines = [ln for ln in program.read_text().splitlines() if ln and not ln.startswith("#")]
        out = tmp_path / f"{name}-report"
        p = harness(bins, program, "--expect-predicted", "--out", out, "--no-progress", "--no-plots")
        assert p.returncode == 0, p.stdout + p.stderr
        assert f"steps matched: {len(lines)}/{len(lines)} (prediction = firmware = pins)" in p.stdout, p.stdout
        assert "result: every command matched" in p.stdout
        assert len(rows(out)) == len(lines)
