"""The real Nano firmware (the ELF `make` builds for the board) in the virtual Nano.

Run by ctest (hil.vnano_firmware) with the project's venv, which passes the paths in
ARTICULA_VNANO, ARTICULA_NANO_ELF and ARTICULA_CLI; by hand:

    .venv/bin/python -m pytest -q -s hil/tests/test_vnano.py     # paths default to build/

Nothing here is skipped: a missing ELF, virtual Nano or CLI fails every test. Figures
(jitter, latencies, longest interrupt, stack) are printed (-s shows them).
"""

import json
import os
import queue
import re
import signal
import subprocess
import threading
import time
from pathlib import Path

import pytest
import serial

SOURCE = Path(os.environ.get("ARTICULA_SOURCE_DIR", Path(__file__).resolve().parents[2]))
VNANO = Path(os.environ.get("ARTICULA_VNANO", SOURCE / "build/hil/articula-vnano"))
ELF = Path(os.environ.get("ARTICULA_NANO_ELF", SOURCE / "build/avr/firmware/articula-nano.elf"))
CLI = Path(os.environ.get("ARTICULA_CLI", SOURCE / "build/host/cli/articula"))

# Wall-clock limits for a hang; the simulation itself runs faster than real time.
LINE_TIMEOUT = 15.0
RUN_TIMEOUT = 30.0

STATUS_RE = re.compile(r"^<(Idle|Run|Stop|Home|Alarm)((?:\|[A-Z]:[^|>]*)*)>$")
INFO_RE = re.compile(r"^\[Articula\|V:\d+\.\d+\.\d+\|P:2\|J:3\|R:MK2 Plus(\|W:14)?\]$")


@pytest.fixture(scope="session")
def tools():
    """The firmware ELF, the virtual Nano and the CLI must exist: fail, never skip."""
    assert ELF.is_file(), f"no firmware ELF at {ELF}: build it (cmake --build build, or make firmware)"
    assert VNANO.is_file(), f"no virtual Nano at {VNANO}: build it (cmake --build build)"
    assert CLI.is_file(), f"no articula CLI at {CLI}: build it (cmake --build build)"
    return VNANO, ELF, CLI


def quantize(*lines):
    """The host's step arithmetic: `articula quantize mk2plus LINE...`, the steps after the last."""
    out = subprocess.run([str(CLI), "quantize", "mk2plus", *lines, "--json"], check=True, capture_output=True,
                         text=True, timeout=30).stdout
    rows = [json.loads(x) for x in out.splitlines() if x.strip()]
    assert rows and all(r["reply"] == "ok" for r in rows), out
    return rows[-1]["all_steps"]


def parse_status(line):
    m = STATUS_RE.match(line)
    assert m, f"not a status report: {line!r}"
    fields = dict(f.split(":", 1) for f in m.group(2).split("|") if f)
    return {"state": m.group(1), "S": [int(x) for x in fields["S"].split(",")], "G": int(fields["G"]),
            "fields": fields}


class Nano:
    """articula-vnano --stdio: the firmware's serial line on a pipe."""

    def __init__(self, tmp_path, *extra):
        self.report_path = tmp_path / "report.json"
        cmd = [str(VNANO), "--stdio", "--elf", str(ELF), "--report", str(self.report_path), *map(str, extra)]
        self.proc = subprocess.Popen(cmd, stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                     bufsize=0)
        self.lines = queue.Queue()
        self.stderr = []
        threading.Thread(target=self._read_stdout, daemon=True).start()
        threading.Thread(target=self._read_stderr, daemon=True).start()

    def _read_stdout(self):
        buf = b""
        while True:
            chunk = self.proc.stdout.read(1)
            if not chunk:
                break
            buf += chunk
            if chunk == b"\n":
                self.lines.put(buf.decode("ascii", "replace").rstrip("\n"))
                buf = b""

    def _read_stderr(self):
        for raw in self.proc.stderr:
            self.stderr.append(raw.decode("utf-8", "replace"))

    def send(self, text):
        self.proc.stdin.write(text.encode("ascii"))
        self.proc.stdin.flush()

    def line(self):
        try:
            return self.lines.get(timeout=LINE_TIMEOUT)
        except queue.Empty:
            raise AssertionError("no line from the virtual Nano; its stderr:\n" + "".join(self.stderr)) from None

    def command(self, text):
        """Sends a line; returns every line up to and including its reply (ok / error:N)."""
        self.send(text + "\n")
        got = []
        while True:
            got.append(self.line())
            if got[-1] == "ok" or got[-1].startswith("error:"):
                return got

    def status(self):
        self.send("?")
        while True:
            line = self.line()
            if line.startswith("<"):
                return parse_status(line)

    def wait_idle(self):
        deadline = time.monotonic() + RUN_TIMEOUT
        while time.monotonic() < deadline:
            st = self.status()
            if st["state"] == "Idle":
                return st
            time.sleep(0.02)
        raise AssertionError("the arm never came to rest")

    def close(self):
        """EOF on the serial line: the virtual Nano ends once the firmware is quiet."""
        self.proc.stdin.close()
        try:
            rc = self.proc.wait(timeout=RUN_TIMEOUT)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            raise AssertionError("the virtual Nano did not end at EOF") from None
        time.sleep(0.05)  # let the stderr reader finish
        assert rc == 0, "".join(self.stderr)
        return json.loads(self.report_path.read_text())


def boot(nano):
    """I, answered at once: the firmware is up (a '?' sent before its setup ends is lost)."""
    lines = nano.command("I")
    assert len(lines) == 2 and INFO_RE.match(lines[0]) and lines[1] == "ok", lines
    return lines[0]


def figures(report):
    out = []
    for m in report["motors"]:
        iv = m["interval_us"]
        if iv["count"]:
            out.append(f"motor {m['motor']}: {m['step_events']} steps, up to {m['max_rate_steps_per_s']:.0f} steps/s, "
                       f"jitter {m['jitter_us']} us, delay after deadline {m['deadline_delay_us']['min']}.."
                       f"{m['deadline_delay_us']['max']} us")
    st = report["status"]
    if st["first_byte_us"]["count"]:
        out.append(f"status: first byte {st['first_byte_us']['min']}..{st['first_byte_us']['max']} us, "
                   f"LF {st['line_end_us']['min']}..{st['line_end_us']['max']} us")
    li, ld = report["longest_interrupt"], report["longest_interrupts_disabled"]
    out.append(f"longest interrupt {li['us']} us ({li['vector']}), interrupts off at most {ld['us']} us "
               f"({ld['function']}); stack: {report['stack']['min_free_bytes']} bytes never used; "
               f"{report['speed_x_realtime']}x real time")
    print("\n  " + "\n  ".join(out))


def test_info_move_quantization_and_status_latency(tools, tmp_path):
    nano = Nano(tmp_path)
    boot(nano)
    st = nano.status()
    assert st["state"] == "Idle" and st["S"] == [0, 0, 0]
    assert nano.command("M 10 100 5") == ["ok"]
    st = nano.wait_idle()
    # The host's arithmetic: the same move as relative L lines from step 0 (shoulder zero 90).
    expected = quantize("L 0 10", "L 1 10", "L 2 5")
    assert expected == [32, 14, 7]
    assert st["S"] == expected
    report = nano.close()
    figures(report)

    assert report["exit_reason"] == "end of input"
    decoded = [m["steps"] for m in report["motors"]]
    assert decoded == st["S"], "the coils say otherwise than the firmware's S: field"
    assert report["faults"] == 0
    for m, n in zip(report["motors"], expected):
        assert m["mode"] == "full"
        assert m["step_events"] == abs(n) and m["backward"] == 0
        # Every step was made in the step interrupt and timed against its deadline.
        assert m["unattributed_steps"] == 0 and m["deadline_delay_us"]["count"] == abs(n)
    assert report["timer1_calibration"]["valid"] and report["timer1_calibration"]["outliers"] == 0
    status = report["status"]
    assert status["requests"] >= 2 and status["replies"] == status["requests"]
    assert status["first_byte_us"]["max"] < 1000.0, status  # firmware target: within 1 ms
    assert report["uart"]["frame_cycles"] == 1360  # 8N1 at 117,647 baud (UBRR 16, U2X)
    assert report["stack"]["min_free_bytes"] > 0


def test_gripper_servo_pulse(tools, tmp_path):
    robot = json.loads((SOURCE / "robots/mk2plus.json").read_text())["gripper"]
    closed, opened = robot["servo_closed"], robot["servo_open"]
    angle = closed + (opened - closed) * 0.5
    expected_us = round(544 + angle * (2400 - 544) / 180)  # the Servo library's scale, as the firmware
    nano = Nano(tmp_path, "--gripper", f"{closed}:{opened}")
    boot(nano)
    assert nano.command("G 50") == ["ok"]
    st = nano.wait_idle()
    assert st["G"] == 50
    report = nano.close()
    figures(report)
    servo = report["servo"]
    assert servo["pulses"] >= 10
    # Each edge comes with the COMPB interrupt's entry latency (0 to 6 us, mostly Timer0's
    # interrupt): the median pulse is within 2 us (0.2 degree), every pulse within 10 us.
    widths = sorted(w["us"] for w in servo["widths"] for _ in range(w["pulses"]))
    median = widths[len(widths) // 2]
    assert abs(median - expected_us) <= 2.0, servo["widths"]
    assert servo["width_us"]["min"] >= expected_us - 10 and servo["width_us"]["max"] <= expected_us + 10
    assert abs(servo["period_us"]["mean"] - 20000.0) <= 1.0
    assert abs(servo["last_aperture_percent"] - 50.0) <= 0.5
    print(f"  servo: {servo['width_us']['min']}..{servo['width_us']['max']} us, median {median} us, for {expected_us} us")


def test_homing_with_endstop(tools, tmp_path):
    base_min = quantize("L 0 -90")[0]  # the base's minimum angle, where its switch sits
    assert base_min == -284
    nano = Nano(tmp_path, "--endstop", "0:-20")
    boot(nano)
    assert nano.command("$3=1") == ["ok"]  # the base has a switch
    assert nano.command("H") == ["ok"]
    st = nano.wait_idle()
    assert st["S"] == [base_min, 0, 0]  # homed: the switch is the base's minimum
    assert nano.command("M 0 90 0") == ["ok"]
    st = nano.wait_idle()
    assert st["S"] == [0, 0, 0]
    report = nano.close()
    figures(report)
    assert report["faults"] == 0
    base = report["motors"][0]
    # The switch closed at decoded step -20; the firmware called that -284 and went to 0.
    assert base["steps"] == -20 - base_min
    assert base["step_events"] == 20 + (-base_min)
    (end,) = report["endstops"]
    assert end["presses"] == 1 and end["first_press_steps"] == -20 and not end["pressed"]
    assert report["motors"][1]["step_events"] == 0 and report["motors"][2]["step_events"] == 0


def test_fast_moves_figures(tools, tmp_path):
    nano = Nano(tmp_path)
    boot(nano)
    assert nano.command("$0=4000") == ["ok"]
    assert nano.command("$1=100000") == ["ok"]
    assert nano.command("M 90 130 15") == ["ok"]
    st = nano.wait_idle()
    assert nano.command("M -90 36 -43") == ["ok"]
    st = nano.wait_idle()
    assert st["S"] == quantize("L 0 -90", "L 1 -54", "L 2 -43")
    # About as many steps on every motor: the most steps per second summed over the motors.
    assert nano.command("M -25 36 -43") == ["ok"]
    assert nano.command("M 0 90 0") == ["ok"]
    st = nano.wait_idle()
    report = nano.close()
    figures(report)
    print(f"  peak {report['peak_steps_per_s_10ms']:.0f} steps/s summed over 10 ms")
    assert [m["steps"] for m in report["motors"]] == st["S"] == [0, 0, 0]
    assert report["faults"] == 0
    assert report["jitter_us"] is not None
    for m in report["motors"]:
        assert m["unattributed_steps"] == 0
    assert report["motors"][0]["max_rate_steps_per_s"] > 3000  # $0=4000 steps/s is reached


def test_pty_parallel_runs_and_sigterm(tools, tmp_path):
    runs = []
    for k in range(2):  # two at once: each its own pseudo-terminal
        link = tmp_path / f"nano{k}"
        rep = tmp_path / f"report{k}.json"
        proc = subprocess.Popen([str(VNANO), "--elf", str(ELF), "--pty-link", str(link), "--report", str(rep)],
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        runs.append((proc, link, rep))
    try:
        names = []
        for proc, link, rep in runs:
            first = proc.stdout.readline().strip()
            assert first.startswith("pty: /dev/pts/"), first
            names.append(first[5:])
            assert os.readlink(link) == names[-1]
        assert names[0] != names[1]
        for proc, link, rep in runs:
            with serial.Serial(str(link), 115200, timeout=LINE_TIMEOUT) as port:
                port.write(b"I\n")
                assert INFO_RE.match(port.readline().decode().strip())
                assert port.readline() == b"ok\n"
                port.write(b"?")
                assert port.readline().decode().startswith("<Idle|S:0,0,0|")
        for proc, link, rep in runs:
            proc.send_signal(signal.SIGTERM)
            assert proc.wait(timeout=10) == 0, proc.stderr.read()
            report = json.loads(rep.read_text())
            assert report["exit_reason"] == "SIGTERM"
            assert report["status"]["replies"] == 1 and report["status"]["first_byte_us"]["max"] < 1000.0
            assert not link.exists() and not link.is_symlink()  # the link is removed at exit
    finally:
        for proc, _, _ in runs:
            if proc.poll() is None:
                proc.kill()


def test_missing_elf_is_an_error(tools, tmp_path):
    r = subprocess.run([str(VNANO), "--stdio", "--elf", str(tmp_path / "none.elf")], input=b"", capture_output=True,
                       timeout=30)
    assert r.returncode == 2 and b"no firmware ELF" in r.stderr
