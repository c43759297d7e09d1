"""The protocol fuzz (hil/harness/fuzz/): a seeded run on the virtual Nano with the real
firmware ELF, the generator's framing, and the checker on transcripts that break the
protocol (two replies, none, a reset, motion from a rejected line, pins that disagree), so
a pass means something. Run by ctest (hil.fuzz) with the binaries' paths in the environment:

    ARTICULA_VNANO, ARTICULA_NANO_ELF, ARTICULA_SOURCE_DIR   (and FUZZ_LINES, default 3000)

It fails, never skips, when a binary is missing. The ctest run sends 3,000 lines (about 45 s
on this 2-core machine, more when it is busy), which already send every class of line and
draw every error code the checks below ask for; FUZZ_LINES=10000 (or `python -m hil.harness
fuzz --lines 10000`) is the long run.
"""

import json
import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

SOURCE = Path(os.environ.get("ARTICULA_SOURCE_DIR") or Path(__file__).resolve().parents[2])
sys.path.insert(0, str(SOURCE))

from hil.harness import fuzz  # noqa: E402
from articula.link import Link, parse_status  # noqa: E402
from hil.harness.robot import Robot  # noqa: E402

ROBOT = Robot(SOURCE / "robots" / "mk2plus.json")
LINES = int(os.environ.get("FUZZ_LINES", "3000"))


def _binary(name: str, default: Path) -> str:
    p = Path(os.environ.get(name) or default)
    assert p.exists(), f"{name}: no {p} (build first: cmake --build build --target articula-vnano)"
    return str(p)


# ---- the real firmware on the virtual Nano ----

def test_fuzz_with_bursts_that_fill_the_queue_before_a_held_line(tmp_path):
    """--bursts: besides the usual classes, moves streamed as GRBL's senders stream (the next
    line as soon as the last is answered) until the queue is full, then D, held until there is
    room: answered ok (it was error:255), the arm back where it began, pins = status."""
    vnano = _binary("ARTICULA_VNANO", SOURCE / "build" / "virtual-nano" / "articula-vnano")
    elf = _binary("ARTICULA_NANO_ELF", SOURCE / "build" / "avr" / "firmware" / "articula-nano.elf")
    report = tmp_path / "fuzz.json"
    p = subprocess.run([sys.executable, "-m", "hil.harness", "fuzz", "--lines", "300", "--seed", "5", "--bursts",
                        "--vnano", vnano, "--elf", elf, "--report", str(report), "--no-progress"],
                       cwd=SOURCE, capture_output=True, text=True, timeout=300)
    print(p.stdout, p.stderr)
    assert p.returncode == 0, p.stdout + p.stderr
    s = json.loads(report.read_text())["summary"]
    assert s["by_class"].get("burst", 0) >= 10
    assert all(v == 0 for v in s["findings"].values()), s["findings"]
    assert (s["resets"], s["hangs"], s["mismatches"]) == (0, 0, 0)


def test_fuzz_on_the_virtual_nano(tmp_path):
    vnano = _binary("ARTICULA_VNANO", SOURCE / "build" / "virtual-nano" / "articula-vnano")
    elf = _binary("ARTICULA_NANO_ELF", SOURCE / "build" / "avr" / "firmware" / "articula-nano.elf")
    report = tmp_path / "fuzz.json"
    t0 = time.monotonic()
    p = subprocess.run([sys.executable, "-m", "hil.harness", "fuzz", "--lines", str(LINES), "--seed", "1",
                        "--vnano", vnano, "--elf", elf, "--report", str(report), "--no-progress"],
                       cwd=SOURCE, capture_output=True, text=True, timeout=LINES * 0.15 + 120)  # a hang guard
    print(p.stdout, p.stderr, f"({time.monotonic() - t0:.1f} s)")
    assert p.returncode == 0, p.stdout + p.stderr
    doc = json.loads(report.read_text())
    s = doc["summary"]
    assert s["lines"] == LINES
    assert (s["resets"], s["hangs"], s["mismatches"]) == (0, 0, 0)
    assert all(v == 0 for v in s["findings"].values()), s["findings"]
    # Exactly one reply a line, and every line answered.
    assert s["replies"]["ok"] + s["replies"]["error"] == LINES and s["replies"]["none"] == 0
    # Every class was sent, and the replies cover the codes the protocol gives for bad lines.
    assert set(s["by_class"]) == {c for c, _ in fuzz.Generator.WEIGHTS}
    assert {"1", "2", "3", "4", "5", "6", "7", "8", "9", "10", "11", "13"} <= set(s["errors_by_code"])
    # Good lines still move the arm: the fuzz is not passing because nothing happens.
    assert s["accepted_moves"] > LINES // 20 and s["moves_that_stepped"] > LINES // 25
    assert s["stops_mid_move"] > 0
    assert s["answers_at_end"] and s["end_steps"] == s["pins_end"] == doc["vnano"]["steps"]
    assert doc["vnano"]["coil_faults"] == 0 and doc["vnano"]["exit"] == "exited with status 0"
    assert "resets: 0, hangs: 0, mismatches: 0" in p.stdout


def test_usage_errors_exit_2(tmp_path):
    p = subprocess.run([sys.executable, "-m", "hil.harness", "fuzz", "--lines", "0"], cwd=SOURCE,
                       capture_output=True, text=True, timeout=30)
    assert p.returncode == 2 and "--lines" in p.stderr
    p = subprocess.run([sys.executable, "-m", "hil.harness", "fuzz", "--elf", str(tmp_path / "none.elf"),
                        "--vnano", _binary("ARTICULA_VNANO", SOURCE / "build" / "virtual-nano" / "articula-vnano")],
                       cwd=SOURCE, capture_output=True, text=True, timeout=30)
    assert p.returncode == 2 and "none.elf" in p.stderr


# ---- the generator ----

def _lines(seed, n=3000):
    g = fuzz.Generator(ROBOT, seed)
    return [g.next() for _ in range(n)]


def test_generator_is_seeded_and_frames_one_line_each():
    a, b, c = _lines(7), _lines(7), _lines(8)
    assert [x.data for x in a] == [x.data for x in b]
    assert [x.data for x in a] != [x.data for x in c]
    for x in a:
        assert x.data.endswith(b"\n") and x.data.count(b"\n") == 1, x
        assert x.data.count(b"?") == x.queries and x.data.count(b"!") == int(x.stop), x
        if x.cls == "overlong" or (x.expect == {"error:7"}):
            body = x.data[:-1].replace(b"?", b"").replace(b"!", b"")
            body = body[:-1] if body.endswith(b"\r") else body
            assert len(body) > fuzz.MAX_LINE, x
        if x.expect is not None and "error:7" not in x.expect and x.cls != "random":
            body = x.data[:-1].replace(b"?", b"").replace(b"!", b"")
            assert len(body.removesuffix(b"\r")) <= fuzz.MAX_LINE, x
    assert {x.cls for x in a} == {c for c, _ in fuzz.Generator.WEIGHTS}


def test_quantization_matches_the_protocol_examples():
    base, shoulder = fuzz.Axis(ROBOT.motors[0]), fuzz.Axis(ROBOT.motors[1])
    assert base.quantize(10000) == 32 and base.step_angle(32) == 10133  # docs/protocol.md
    assert base.quantize(1000) == 3 and base.quantize(100) == 0
    assert shoulder.quantize(130000) == 55 and shoulder.quantize_within_limits(130000) == 54
    assert fuzz.millideg("-5.821") == -5821 and fuzz.millideg("90.000") == 90000


# ---- the checker: transcripts that break the protocol ----

IDLE = "<Idle|S:3,0,0|A:0.950,90.000,0.000|G:0|Q:8|C:1>"
MOVED = "<Idle|S:4,0,0|A:1.267,90.000,0.000|G:0|Q:8|C:1>"


def _line(text=b"L 0 200", expect="error:9", **kw):
    return fuzz.FuzzLine(cls="target", data=text + b"\n", expect=frozenset([expect]) if expect else None,
                         kind="test", **kw)


def _ex(received, after=IDLE, pins_after=(10, [3, 0, 0]), **kw):
    return fuzz.Exchange(received=received, polls=1, before=parse_status(IDLE), after=parse_status(after),
                         pins_before=(10, [3, 0, 0]), pins_after=pins_after, **kw)


def _kinds(line, ex):
    return sorted({f.kind for f in fuzz.check(1, line, ex)[1]})


def test_a_correct_transcript_passes():
    assert _kinds(_line(), _ex(["error:9", IDLE])) == []
    assert _kinds(_line(b"L 0 ?200", queries=1), _ex([IDLE, "error:9", IDLE])) == []
    assert _kinds(_line(b"I", "ok", info=True), _ex(["[Articula|V:0.1.0|P:2|J:3|R:MK2 Plus]", "ok", IDLE])) == []
    assert _kinds(_line(b"L 0 0.3", "ok", moves=True, target=[4, 0, 0]),
                  _ex(["ok", MOVED], after=MOVED, pins_after=(12, [4, 0, 0]))) == []


def test_two_replies_for_one_line_fail():
    assert _kinds(_line(), _ex(["error:9", "error:9", IDLE])) == ["replies"]
    assert _kinds(_line(b"X", None), _ex(["ok", "error:2", IDLE])) == ["replies"]


def test_no_reply_is_a_hang():
    ex = _ex([IDLE])
    ex.timeout = "no reply within 5.0 s"
    assert "hang" in _kinds(_line(), ex)
    assert _kinds(_line(), _ex([IDLE])) == ["replies"]


def test_a_reset_fails():
    info = "[Articula|V:0.1.0|P:2|J:3|R:MK2 Plus]"
    assert "reset" in _kinds(_line(), _ex([info, "error:9", IDLE]))
    w14 = "<Idle|S:0,0,0|A:0.000,90.000,0.000|G:0|Q:8|C:0|W:14>"
    assert "reset" in _kinds(_line(), _ex(["error:9", w14], after=w14, pins_after=(10, [3, 0, 0])))


def test_motion_from_a_rejected_line_fails():
    # The status says the motors moved...
    assert "motion" in _kinds(_line(), _ex(["error:9", MOVED], after=MOVED, pins_after=(10, [4, 0, 0])))
    # ...or only the pins do (a coil event other than the idle release)...
    assert _kinds(_line(), _ex(["error:9", IDLE], pins_after=(11, [3, 0, 0]), coil_moves=1)) == ["motion"]
    # ...but the coils' release after $5 ms at rest may come while any line runs
    assert _kinds(_line(), _ex(["error:9", IDLE], pins_after=(13, [3, 0, 0]), coil_moves=0)) == []


def test_pins_that_disagree_with_the_status_fail():
    assert _kinds(_line(), _ex(["error:9", IDLE], pins_after=(10, [2, 0, 0]))) == ["pins"]


def test_wrong_replies_reports_and_steps_fail():
    assert _kinds(_line(), _ex(["error:8", IDLE])) == ["reply"]
    assert _kinds(_line(b"L 0 ?200", queries=1), _ex(["error:9", IDLE])) == ["reports"]
    assert _kinds(_line(b"L 0 0.3", "ok", moves=True, target=[5, 0, 0]),
                  _ex(["ok", MOVED], after=MOVED, pins_after=(12, [4, 0, 0]))) == ["steps"]
    assert _kinds(_line(), _ex(["error:9", "huh", IDLE])) == ["unexpected"]


# ---- the whole loop against a scripted arm that misbehaves ----

class FakeNano:
    """Answers every line `error:2` (or as `answer` says) and every '?' with a status report;
    `answer(n, line)` returns the replies for line n, `steps(n)` the steps after it."""

    def __init__(self, answer=None, steps=None, silent_from=None):
        self.silent_from = silent_from
        self.out = b""
        self.inbuf = b""
        self.n = 0
        self.answer = answer or (lambda n, line: ["error:2"])
        self.steps = steps or (lambda n: [0, 0, 0])
        self.timeout = 0.05

    def status(self):
        s = self.steps(self.n)
        return f"<Idle|S:{','.join(map(str, s))}|A:0.000,90.000,0.000|G:0|Q:8|C:1>\n".encode()

    def write(self, data):
        if self.silent_from is not None and self.n >= self.silent_from:
            return len(data)  # hung: reads nothing, says nothing
        for b in data:
            c = bytes([b])
            if c == b"?":
                self.out += self.status()
            elif c == b"!":
                pass
            elif c == b"\n":
                line, self.inbuf = self.inbuf, b""
                text = line.decode("latin-1")
                self.n += 1
                if text == "I":
                    self.out += b"[Articula|V:0.1.0|P:2|J:3|R:MK2 Plus]\nok\n"
                elif text.startswith("$") and "=" in text and self.n <= 4:
                    self.out += b"ok\n"
                else:
                    for r in self.answer(self.n, text):
                        self.out += r.encode() + b"\n"
            else:
                self.inbuf += c
        return len(data)

    @property
    def in_waiting(self):
        return len(self.out)

    def read(self, n):
        data, self.out = self.out[:n], self.out[n:]
        return data


def _fake_run(nano, n=200, timeout=0.3):
    fz = fuzz.Fuzzer(Link(nano), ROBOT, 3, timeout=timeout)
    fz.start(restore_settings=False)
    s = fz.run(n)
    fz.finish()
    return s


def test_the_loop_reports_a_second_reply():
    s = _fake_run(FakeNano(answer=lambda n, line: ["error:2", "ok"] if n == 50 else ["error:2"]))
    assert s.count("replies") >= 1 and not s.ok
    assert any(f.index == 50 - 4 for f in s.findings if f.kind == "replies")  # 4 set-up lines before the fuzz


def test_the_loop_reports_motion_and_a_silent_arm():
    s = _fake_run(FakeNano(steps=lambda n: [0, 0, 0] if n < 30 else [1, 0, 0]))
    assert s.count("motion") >= 1
    t0 = time.monotonic()
    s = _fake_run(FakeNano(silent_from=20), timeout=0.2)
    assert s.count("hang") == 1 and s.lines == 20 - 4 and "does not answer" in s.aborted
    assert not s.answers_at_end and not s.ok
    assert time.monotonic() - t0 < 10
