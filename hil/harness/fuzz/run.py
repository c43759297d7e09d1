"""The fuzz's run: the lines sent over a Link, one at a time with the protocol's flow control,
each exchange checked, and the summary of what was found."""

from __future__ import annotations

import time
from dataclasses import dataclass, field

from articula.link import Link, LinkTimeout, LinkVanished, Status, parse_info, parse_setting, parse_status
from ..robot import Robot
from .generate import RUN_SETTINGS, Generator
from .oracle import Exchange, check, is_reply


# ---------------------------------------------------------------------------------------
# The run.

@dataclass
class Summary:
    lines: int = 0
    by_class: dict = field(default_factory=dict)
    replies: dict = field(default_factory=dict)
    accepted_moves: int = 0
    moves_that_stepped: int = 0
    stops_mid_move: int = 0
    status_reports: int = 0
    bytes_sent: int = 0
    findings: list = field(default_factory=list)
    seconds: float = 0.0
    answers_at_end: bool = False
    end_steps: list | None = None
    pins_end: list | None = None
    vnano: dict | None = None
    aborted: str = ""

    def count(self, kind: str) -> int:
        return sum(1 for f in self.findings if f.kind == kind)

    @property
    def ok(self) -> bool:
        return not self.findings and self.answers_at_end and not self.aborted

    def figures(self) -> dict:
        kinds = ["replies", "reply", "reset", "hang", "motion", "pins", "steps", "reports", "unexpected", "coil",
                 "vanished"]
        return {
            "lines": self.lines, "bytes": self.bytes_sent, "seconds": round(self.seconds, 3),
            "lines_per_s": round(self.lines / self.seconds, 1) if self.seconds else 0.0,
            "by_class": dict(sorted(self.by_class.items())),
            "replies": {"ok": self.replies.get("ok", 0), "error": sum(v for k, v in self.replies.items() if k != "ok"),
                        "none": self.replies.get(None, 0)},
            "errors_by_code": {k[6:]: v for k, v in sorted(self.replies.items(), key=lambda kv: (
                kv[0] is None, int(kv[0][6:]) if kv[0] and kv[0].startswith("error:") else -1)) if k and k != "ok"},
            "accepted_moves": self.accepted_moves, "moves_that_stepped": self.moves_that_stepped,
            "stops_mid_move": self.stops_mid_move, "status_reports": self.status_reports,
            "findings": {k: self.count(k) for k in kinds},
            "resets": self.count("reset"), "hangs": self.count("hang"),
            "mismatches": sum(self.count(k) for k in kinds if k not in ("reset", "hang")),
            "answers_at_end": self.answers_at_end, "end_steps": self.end_steps, "pins_end": self.pins_end,
            "aborted": self.aborted, "ok": self.ok,
        }

    def text(self) -> str:
        f = self.figures()
        classes = ", ".join(f"{k} {v}" for k, v in f["by_class"].items())
        codes = ", ".join(f"{k}: {v}" for k, v in f["errors_by_code"].items())
        out = [
            f"articula fuzz: {f['lines']} lines ({f['bytes']} bytes) in {f['seconds']:.1f} s, {f['lines_per_s']} lines/s",
            f"  classes: {classes}",
            f"  replies: ok {f['replies']['ok']}, error {f['replies']['error']}, none {f['replies']['none']}"
            f" (errors by code {codes})",
            f"  accepted moves: {f['accepted_moves']} ({f['moves_that_stepped']} stepped; {f['stops_mid_move']} stopped "
            f"by ! mid-move); status reports: {f['status_reports']}",
            f"  resets: {f['resets']}, hangs: {f['hangs']}, mismatches: {f['mismatches']}"
            + ("" if not f["mismatches"] else " (" + ", ".join(f"{k} {v}" for k, v in f["findings"].items()
                                                               if v and k not in ("reset", "hang")) + ")"),
            f"  end: {'the arm answers' if f['answers_at_end'] else 'THE ARM DOES NOT ANSWER'}"
            + (f", steps {f['end_steps']}" if f["end_steps"] is not None else "")
            + (f", pins {f['pins_end']}" if f["pins_end"] is not None else ""),
        ]
        if self.aborted:
            out.append(f"  aborted: {self.aborted}")
        for fd in self.findings[:10]:
            out.append("  " + fd.describe())
        if len(self.findings) > 10:
            out.append(f"  ... {len(self.findings) - 10} more findings")
        out.append(f"  result: {'pass' if self.ok else 'FAIL'}")
        return "\n".join(out)


class Fuzzer:
    """Runs the lines over a Link. `pins()` returns (rows, positions) of the virtual Nano's
    trace (None on a real port); `coil_events(rows_from, rows_to)` those rows (trace.TraceRow)."""

    def __init__(self, link: Link, robot: Robot, seed: int, *, pins=None, coil_events=None, timeout: float = 5.0,
                 poll: float = 0.002, progress=None, bursts: bool = False):
        self.link = link
        self.robot = robot
        self.gen = Generator(robot, seed, bursts)
        self.pins = pins
        self.coil_events = coil_events
        self.timeout = timeout
        self.poll = poll
        self.progress = progress
        self.summary = Summary()
        self.status: Status | None = None
        self._first_report = True
        self.saved_settings: dict[int, float] = {}

    # -- the conversation --
    def _read(self, ex: Exchange, deadline: float) -> str:
        t = self.link.read_line(deadline)
        ex.received.append(t)
        return t

    def _poll_status(self, ex: Exchange) -> Status:
        """Sends '?' and reads up to the status report it gets."""
        self.link.send_realtime(b"?")
        ex.polls += 1
        deadline = time.monotonic() + self.timeout
        while True:
            st = parse_status(self._read(ex, deadline))
            if st is not None:
                return st

    def _until_reply(self, ex: Exchange, deadline: float) -> str:
        while True:
            t = self._read(ex, deadline)
            if is_reply(t):
                return t

    def setup_line(self, text: str) -> tuple[str, list[str]]:
        """A line outside the fuzz (settings): its reply and the lines before it."""
        ex = Exchange()
        self.link.send_line(text)
        r = self._until_reply(ex, time.monotonic() + self.timeout)
        return r, ex.received[:-1]

    def start(self, restore_settings: bool) -> None:
        ex = Exchange()
        st = self._poll_status(ex)
        self._first_report = False
        if st.steps is None or len(st.steps) != len(self.robot.motors):
            raise LinkVanished(f"the arm's status report does not name {len(self.robot.motors)} motors: {st.text}")
        r, lines = self.setup_line("I")
        info = next((parse_info(t) for t in lines if parse_info(t)), None)
        if r != "ok" or info is None or info.robot != self.robot.name:
            raise LinkVanished(f"`I` answered {lines + [r]}: not the firmware for {self.robot.name}")
        if restore_settings:
            r, lines = self.setup_line("$")
            for t in lines:
                s = parse_setting(t)
                if s:
                    self.saved_settings[s[0]] = s[1]
        for n, v in RUN_SETTINGS.items():
            r, _ = self.setup_line(f"${n}={v}")
            if r != "ok":
                raise LinkVanished(f"`${n}={v}` answered {r}")
        ex = Exchange()
        self.status = self._poll_status(ex)
        self.gen.arm.rederive(self.status.steps)  # a fresh '!'-free start: commanded = the steps' angles
        if any(self.status.steps):
            self.gen.arm.exact = False  # a real arm not on step 0: its commanded angles are not known

    def finish(self) -> None:
        s = self.summary
        try:
            ex = Exchange()
            st = self._poll_status(ex)
            r, lines = self.setup_line("I")
            s.answers_at_end = st is not None and r == "ok" and any(parse_info(t) for t in lines)
            s.end_steps = st.steps
            if self.pins:
                s.pins_end = self.pins()[1]
            for n, v in self.saved_settings.items():  # a real arm: its own settings back
                self.setup_line(f"${n}={int(v)}")
        except (LinkTimeout, LinkVanished) as e:
            s.answers_at_end = False
            s.aborted = s.aborted or f"no answer at the end: {e}"

    def one(self, index: int, line: FuzzLine) -> Exchange:
        ex = Exchange(before=self.status)
        if self.pins:
            ex.pins_before = self.pins()
        try:
            for sub in line.burst:  # each as soon as the one before is answered (not checked as the line)
                self.link.write(sub)
                got = self._until_reply(Exchange(), time.monotonic() + self.timeout)
                if got != "ok":
                    ex.received.append(f"(streamed {sub!r} answered {got})")
            self.link.write(line.data)
            deadline = time.monotonic() + self.timeout
            try:
                reply = self._until_reply(ex, deadline)
            except LinkTimeout as e:
                ex.timeout = f"no reply within {self.timeout:.1f} s{e.got}"
                reply = None
            if line.stop_after and reply == "ok":
                # at once: the virtual Nano runs far ahead of the wall clock through a move
                self.link.send_realtime(b"!")
            # At rest before the next line: '?' until Idle (a rejected line: one '?').
            run_deadline = time.monotonic() + self.timeout + (20.0 if line.moves else 0.0)
            while True:
                try:
                    st = self._poll_status(ex)
                except LinkTimeout as e:
                    ex.timeout = ex.timeout or f"no answer to ? within {self.timeout:.1f} s{e.got}"
                    break
                ex.after = st
                if st.at_rest or time.monotonic() > run_deadline:
                    break
                time.sleep(self.poll)
        except LinkVanished as e:
            ex.vanished = f"the port vanished: {e}"
        if self.pins and not ex.vanished:
            ex.pins_after = self.pins()
            if self.coil_events:
                rows = self.coil_events(ex.pins_before[0], ex.pins_after[0])
                ex.coil_faults = [f"motor {r.motor} {r.event} to {r.pattern} at {r.time_us / 1e6:.6f} s"
                                  for r in rows if r.is_fault]
                ex.coil_moves = sum(1 for r in rows if r.event != "released")
        return ex

    def run(self, n: int) -> Summary:
        s = self.summary
        t0 = time.monotonic()
        i = 0
        while i < n:
            line = self.gen.next()
            i += 1
            ex = self.one(i, line)
            reply, findings = check(i, line, ex)
            s.lines += 1
            s.bytes_sent += len(line.data)
            s.by_class[line.cls] = s.by_class.get(line.cls, 0) + 1
            s.replies[reply] = s.replies.get(reply, 0) + 1
            s.status_reports += sum(1 for t in ex.received if t.startswith("<"))
            s.findings.extend(findings)
            self._follow(line, reply, ex)
            if self.progress:
                self.progress(i, n)
            if ex.vanished or (ex.timeout and not self._recover(ex)):
                s.aborted = f"line {i}: " + (ex.vanished or ex.timeout + "; the arm does not answer any more")
                break
            if any(f.kind == "reset" for f in findings):
                s.aborted = f"line {i}: the firmware reset"
                break
        s.seconds = time.monotonic() - t0
        return s

    def _follow(self, line: FuzzLine, reply: str | None, ex: Exchange) -> None:
        """Keeps the generator's model of the arm in step with what happened."""
        s, arm = self.summary, self.gen.arm
        st = ex.after
        if st is None or st.steps is None:
            return
        moved = ex.before is not None and ex.before.steps != st.steps
        if reply == "ok" and line.moves:
            s.accepted_moves += 1
            s.moves_that_stepped += moved
        if line.stop_after and reply == "ok":
            if st.steps != line.target:
                s.stops_mid_move += 1
            arm.rederive(st.steps)
        else:  # ('!' in a line: the generator made the commanded angles the steps' before the line)
            arm.steps = list(st.steps)
            expected_ok = line.expect is not None and "ok" in line.expect
            if reply == "ok" and not expected_ok and moved:
                arm.estimate(st)  # a random line that moved the arm: take its word
            elif expected_ok and reply != "ok" and line.moves:
                arm.estimate(st)  # the generator counted on a move that did not happen
            elif line.estimate and reply == "ok":
                arm.estimate(st)
        self.status = st

    def _recover(self, ex: Exchange) -> bool:
        """After a timeout: does the arm still answer '?'"""
        try:
            self.link.send_realtime(b"!")
            self.link.drain(0.3)
            self.link.discard_input()
            e = Exchange()
            self.status = self._poll_status(e)
            self.gen.arm.rederive(self.status.steps)
            return True
        except (LinkTimeout, LinkVanished):
            return False
