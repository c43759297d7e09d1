"""Every drive kind on the emulated pins: the real firmware's hex in simavr (the virtual Nano).

For each stepper drive (the MK2 on L298Ns, on 28BYJ-48s and ULN2003s, on STEP/DIR drivers in a
CNC shield: robots/ and hil/robots/), the same moves at the firmware's top rate ($0=4000 steps/s,
$1=100000 steps/s^2), then from the virtual Nano's report:

- the step interrupt's time per call (TIMER1_COMPA, mean and worst), and the step rate it could
  sustain if it took the whole CPU (1 / worst, 1 / mean), against GRBL's published 30 kHz on
  the same chip (GRBL's README: "up to 30kHz of stable, jitter free control pulses");
- the highest step rate the pins showed (the busiest 10 ms of all motors together);
- on STEP/DIR drivers: the shortest and longest STEP high time and the shortest DIR setup
  time the pins kept, against each chip's datasheet minimum (shared/articula/drive.h, read
  from there);
- for each shipped servo arm (robots/mearm.json, eezybot-mk2.json: the servo build): each servo's resolution, one
  tick of its pulse (0.5 us) in degrees from its calibration, and how far the pulses' widths on
  the pins lay from their whole tick (the edges' jitter), against the tick.

    .venv/bin/python bench/bench_drives.py            # after `make`
"""
from __future__ import annotations

import json
import re
import subprocess
import sys
import tempfile
from pathlib import Path

SOURCE = Path(__file__).resolve().parents[1]
BUILD = SOURCE / "build"
VNANO = BUILD / "virtual-nano" / "articula-vnano"
CLI = BUILD / "host" / "cli" / "articula"
GRBL_HZ = 30000

ARMS = [  # (what, robot file, firmware build, virtual Nano options)
    ("L298N, full steps", SOURCE / "robots" / "mk2plus.json", "articula-nano", []),
    ("ULN2003 (28BYJ-48)", SOURCE / "hil" / "robots" / "mk2-28byj48.json", "articula-nano", ["--uln2003"]),
    ("STEP/DIR (CNC shield)", SOURCE / "robots" / "mk2plus-cnc.json", "articula-cnc", ["--cnc"]),
]
MOVES = ["$0=4000", "$1=100000", "M 60 100 -5", "M -60 50 10", "M 0 90 0", "L 0 30", "L 0 -30"]
SERVO_ARMS = [("meArm (4 x SG90)", SOURCE / "robots" / "mearm.json"),
              ("EEZYbotARM MK2 (3 x MG996R)", SOURCE / "robots" / "eezybot-mk2.json")]
SERVO_MOVES = ["M 25 100 -30", "M -25 60 15", "M 0 90 0", "L 0 20", "L 0 -20"]  # within both arms' limits


def chips() -> list[tuple[str, float, float]]:
    """(chip, STEP high ns, DIR setup ns) as shared/articula/drive.h gives them."""
    text = (SOURCE / "shared" / "articula" / "drive.h").read_text()
    return [(m[2], float(m[3]), float(m[4])) for m in re.finditer(r'\{"(\w+)", "([\w/]+)", 0x[0-9A-F]+, (\d+), (\d+)\}', text)]


def run(robot: Path, build: str, options: list[str], tmp: Path) -> dict:
    config = subprocess.run([str(CLI), "configure", str(robot), "--dry-run"], capture_output=True, text=True, check=True)
    lines = config.stdout.splitlines() + MOVES
    report = tmp / "report.json"
    subprocess.run([str(VNANO), "--elf", str(BUILD / "avr" / "firmware" / f"{build}.elf"), "--stdio", "--paced",
                    "--quiet", "--report", str(report), *options],
                   input="".join(l + "\n" for l in lines), capture_output=True, text=True, check=True, timeout=600)
    return json.loads(report.read_text())


def main() -> int:
    print(f"| drive | step interrupt mean / worst us | sustainable steps/s (worst .. mean) | vs GRBL {GRBL_HZ // 1000} kHz | "
          "busiest 10 ms, steps/s | coil faults |")
    print("|---|---|---|---|---|---|")
    timing = None
    with tempfile.TemporaryDirectory() as tmp:
        for what, robot, build, options in ARMS:
            r = run(robot, build, options, Path(tmp))
            isr = next(v for v in r["interrupts"] if v["name"] == "TIMER1_COMPA")["duration_us"]
            worst, mean = 1e6 / isr["max"], 1e6 / isr["mean"]
            print(f"| {what} | {isr['mean']:.1f} / {isr['max']:.1f} | {worst:,.0f} .. {mean:,.0f} | "
                  f"{GRBL_HZ / mean:.1f}x .. {GRBL_HZ / worst:.1f}x below | {r['peak_steps_per_s_10ms']:,.0f} | {r['faults']} |")
            if build == "articula-cnc":
                timing = r["motors"]
    print()
    if timing is None:
        return 1
    high_min = min(m["step_high_min_us"] for m in timing if m["step_high_min_us"] is not None)
    high_max = max(m["step_high_max_us"] for m in timing if m["step_high_max_us"] is not None)
    setups = [m["dir_setup_min_us"] for m in timing if m["dir_setup_min_us"] is not None]
    setup = min(setups) if setups else float("nan")
    servo_rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for what, robot in SERVO_ARMS:
            motors = json.loads(robot.read_text())["motors"]
            options = []
            for i, m in enumerate(motors):
                options += ["--servo", f"{i}:{m['driver']['pin']}:{m['driver']['at'][0][0]}"]
            config = subprocess.run([str(CLI), "configure", str(robot), "--dry-run"], capture_output=True, text=True, check=True)
            report = Path(tmp) / "servo.json"
            subprocess.run([str(VNANO), "--elf", str(BUILD / "avr" / "firmware" / "articula-servo.elf"), "--stdio", "--paced",
                            "--quiet", "--report", str(report), *options],
                           input="".join(l + "\n" for l in config.stdout.splitlines() + SERVO_MOVES),
                           capture_output=True, text=True, check=True, timeout=600)
            r = json.loads(report.read_text())
            for i, m in enumerate(motors):
                (p0, a0), (p1, a1) = m["driver"]["at"]
                us_per_deg = abs((p1 - p0) / (a1 - a0))
                off = r["motors"][i]["width_off_tick_max_us"]
                band = float(m["driver"].get("deadband", 5))
                servo_rows.append((what, m["name"], us_per_deg, 0.5 / us_per_deg, off, off / us_per_deg,
                                   r["motors"][i]["pulses"], r["motors"][i]["period_max_us"], band, band / us_per_deg))
    print(f"STEP/DIR on the pins: STEP high {high_min:.3f} .. {high_max:.3f} us, shortest DIR setup {setup:.3f} us "
          f"({sum(m['pulses'] for m in timing)} pulses)")
    print()
    print("| chip | datasheet STEP high | pins' shortest | margin | datasheet DIR setup | pins' shortest | margin |")
    print("|---|---|---|---|---|---|---|")
    for chip, high_ns, setup_ns in chips():
        print(f"| {chip} | {high_ns / 1000:.3f} us | {high_min:.3f} us | {high_min * 1000 / high_ns:.2f}x | "
              f"{setup_ns / 1000:.3f} us | {setup:.3f} us | {setup * 1000 / setup_ns:,.0f}x |")
    print()
    print("| servo arm | servo | us per degree | one tick (0.5 us) | widths off their tick at most | the servo's dead band "
          "(file) | pulses | longest period |")
    print("|---|---|---|---|---|---|---|---|")
    for what, name, usd, tick_deg, off_us, off_deg, pulses, period, band, band_deg in servo_rows:
        print(f"| {what} | {name} | {usd:.2f} | {tick_deg:.4f} deg | {off_us:.3f} us ({off_deg:.4f} deg, "
              f"{off_us / 0.5:.2f} tick) | {band:g} us = {band_deg:.3f} deg ({band / 0.5:.0f} ticks) | {pulses} | "
              f"{period / 1000:.3f} ms |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
