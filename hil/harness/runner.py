"""Runs plans on a target, one command at a time, and records for every command what the
prediction, the firmware and (on the virtual Nano) the pins say.

For each command line: send it, read its reply (`ok` / `error:N`, with the info or setting
lines some commands send first), then poll `?` until the status report says `Idle` (the
protocol's flow control: the next line goes only after that). At that moment the firmware's
`S` (steps) and `A` (angles) are recorded and, on the virtual Nano, the trace is read up to
now: the pins' decoded positions then are the cumulative positions after this command, and
the coil events since the previous command's Idle are this command's (see trace.py).
"""

from __future__ import annotations

import signal
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path

import articula
from articula.link import (Link, LinkError, LinkTimeout, LinkVanished, Status, parse_info, parse_setting, parse_status,
                   status_text)
from .plan import Command, Plan
from .prediction import Prediction, PredictError, first_interval_s, predict_plan
from .robot import Robot

ANGLE_TOLERANCE = 0.0005 + 1e-9  # status angles have three decimals


@dataclass
class Fault:
    plan: str
    line: int | None
    command: str
    kind: str      # error-reply, timeout, vanished, reset, coil, unexpected, crash, setup, pins
    message: str

    def where(self) -> str:
        return f"{self.plan}:{self.line}" if self.line else self.plan


@dataclass
class Record:
    plan: str
    command: Command
    pred: Prediction | None = None
    sent: bool = False
    reply: str | None = None
    lines: list[str] = field(default_factory=list)   # info / setting lines before the reply
    status: Status | None = None
    t_sent: float | None = None
    t_idle: float | None = None
    pins: list[int] | None = None          # cumulative decoded positions at Idle
    pins_before: list[int] | None = None
    step_events: int = 0
    first_step_us: float | None = None
    last_step_us: float | None = None
    coil_faults: list[str] = field(default_factory=list)
    measured_s: float | None = None
    measured_source: str = ""
    first_interval_s: float | None = None
    tool_firmware: list[float] | None = None
    faults: list[Fault] = field(default_factory=list)
    measured_xyz: list[float] | None = None
    measured_count: int = 0
    pin_slack: list[int] | None = None  # how far each motor's pins may lie off its steps (servos: 1 tick)

    @property
    def line(self) -> int:
        return self.command.line

    @property
    def fw_steps(self) -> list[int] | None:
        return self.status.steps if self.status else None

    @property
    def reply_match(self) -> bool | None:
        if self.pred is None or self.reply is None:
            return None
        return self.pred.reply == self.reply

    @property
    def firmware_match(self) -> bool | None:
        """Prediction = firmware: reply, steps, angles (and the gripper, once set)."""
        if self.pred is None or self.reply is None or self.status is None or self.status.steps is None:
            return None
        if self.pred.reply != self.reply or self.status.steps != self.pred.steps:
            return False
        if self.status.angles is not None and (
                len(self.status.angles) != len(self.pred.actuator_deg) or
                any(abs(a - b) > ANGLE_TOLERANCE for a, b in zip(self.status.angles, self.pred.actuator_deg))):
            return False
        if self.pred.gripper_percent is not None and self.status.gripper is not None \
                and self.status.gripper != self.pred.gripper_percent:
            return False
        return True

    @property
    def pins_match(self) -> bool | None:
        if self.pins is None:
            return None
        if self.pred is None or self.status is None or self.status.steps is None:
            return False
        if self.pred.steps != self.status.steps or len(self.pins) != len(self.pred.steps):
            return False
        # A servo's pins hold the width within one tick (the decoder's deadband: its edges'
        # jitter); a stepper's, every step.
        slack = self.pin_slack or [0] * len(self.pins)
        return all(abs(p - q) <= s for p, q, s in zip(self.pins, self.pred.steps, slack))

    @property
    def matched(self) -> bool:
        """Every command must have been run and agree everywhere it can be checked."""
        if not self.sent or self.firmware_match is not True:
            return False
        if self.pins is not None and self.pins_match is not True:
            return False
        return True

    @property
    def expected_ok(self) -> bool:
        return self.reply == self.command.expect

    @property
    def pin_delta(self) -> list[int] | None:
        if self.pins is None or self.pins_before is None:
            return None
        return [a - b for a, b in zip(self.pins, self.pins_before)]

    @property
    def duration_error_pct(self) -> float | None:
        if self.measured_s is None or self.pred is None or self.pred.seconds <= 0:
            return None
        return (self.measured_s - self.pred.seconds) / self.pred.seconds * 100.0


@dataclass
class PlanResult:
    plan: Plan
    records: list[Record]
    faults: list[Fault] = field(default_factory=list)   # every fault, the records' included
    info: dict | None = None
    info_line: str = ""
    settings_arm: dict[int, float] = field(default_factory=dict)     # as found
    settings_start: dict[int, float] = field(default_factory=dict)   # the plan's first line sees
    predictions: dict = field(default_factory=dict)
    predict_doc: dict = field(default_factory=dict)
    vnano_report: dict | None = None
    wall_s: float = 0.0
    aborted: str = ""
    transcript: list[str] = field(default_factory=list)
    configured: bool = False  # the harness wrote the robot's configuration before the plan



def after_line(rows: list, lo: int, hi: int, pins: list[int]) -> tuple[int, list[int]]:
    """Where a command's own rows start among rows[lo:hi] (read since its line went out, when
    the pins were `pins`): after the trace's first `line` row, the firmware's receipt of the
    line's LF in the Nano's time. Returns that index and the pins as they were there. Without
    a `line` row (an older virtual Nano), lo and `pins`."""
    at = list(pins)
    for k in range(lo, hi):
        r = rows[k]
        if r.event == "line":
            return k + 1, at
        if 0 <= r.motor < len(at):
            at[r.motor] = r.steps
    return lo, list(pins)


def pin_span(steps: list, slack: list[int], start: list[int] | None, end: list[int]) -> tuple[float, float]:
    """The first and last step of a move on the pins, in microseconds, from the rows after the
    firmware had its line and the pins as they were then (`start`). A stepper's pins show its steps and
    nothing else. A servo's pin on a tick's edge can alternate by one at rest (two pulses decode
    apart): an alternation before the move starts (the line is on its way) or after it (the host
    took its time to look) is not the move's. So a servo's move starts after the last time its
    pin showed where it started, and ends the first time its pin shows where it ends."""
    first, last = steps[0].time_us, steps[-1].time_us
    if not any(slack) or start is None:
        return first, last
    firsts, lasts = [], []
    for m in sorted({r.motor for r in steps}):
        mine = [r for r in steps if r.motor == m]
        if not slack[m]:
            firsts.append(mine[0].time_us)
            lasts.append(mine[-1].time_us)
            continue
        at_start = [k for k, r in enumerate(mine) if r.steps == start[m]]
        begin = mine[at_start[-1] + 1] if at_start and at_start[-1] + 1 < len(mine) else mine[0]
        arrived = [r for r in mine if r.steps == end[m] and r.time_us >= begin.time_us]
        firsts.append(begin.time_us)
        lasts.append(arrived[0].time_us if arrived else mine[-1].time_us)
    return min(firsts), max(lasts)

class Runner:
    def __init__(self, target, robot: Robot, out_dir: Path, *, settings: dict[int, float] | None = None,
                 timeout: float = 5.0, poll: float = 0.01, progress=None, hooks=None,
                 expect_predicted: bool = False):
        # expect_predicted: each command must get the reply the prediction gives (plans written
        # for another arm, run on this one), not the plan's `#@ expect`.
        self.expect_predicted = expect_predicted
        self.target = target
        self.robot = robot
        self.out_dir = out_dir
        self.settings_override = settings or {}
        self.timeout = timeout
        self.poll = poll
        self.progress = progress
        self.hooks = hooks  # optional object: before_send(runner, record), after_send(runner, record)
        self.link: Link | None = None
        self._transcript: list[str] = []
        self._t0 = time.monotonic()
        self._reports_seen = 0
        self._expect_info = False
        self.current_settings: dict[int, float] = {}
        # How far each motor's pins may lie off its steps: a servo's one tick (servo_decoder.h).
        self.pin_slack = [1 if m["driver"]["kind"] == "servo" else 0 for m in robot.model.motors]

    # ---- the serial conversation ----

    def _log(self, direction: str, text: str) -> None:
        self._transcript.append(f"{time.monotonic() - self._t0:9.3f} {direction} {text}")

    def _unexpected(self, line: str, where: Record | None, plan: str) -> Fault:
        """Lines nobody asked for. An info line or a settings-reset warning is the firmware
        starting again: a reset."""
        info = parse_info(line)
        if info is not None and not self._expect_info:
            return Fault(plan, where.line if where else None, where.command.text if where else "", "reset",
                         f"firmware reset: an info line nobody asked for ({line})")
        return Fault(plan, where.line if where else None, where.command.text if where else "", "unexpected",
                     f"unexpected output from the arm: '{line}'")

    def _check_status_reset(self, st: Status, rec: Record | None, plan: str) -> Fault | None:
        self._reports_seen += 1
        if st.warning == 14 and self._reports_seen > 1:
            return Fault(plan, rec.line if rec else None, rec.command.text if rec else "", "reset",
                         f"firmware reset: settings reset to defaults (W:14) mid-plan ({st.text})")
        return None

    def read_reply(self, deadline: float, rec: Record | None, plan: str, faults: list[Fault]) -> tuple[str, list[str]]:
        """Lines up to `ok` or `error:N`."""
        extra = []
        while True:
            line = self.link.read_line(deadline)
            if line == "ok" or line.startswith("error:"):
                return line, extra
            if line.startswith("[") and self._expect_info:
                info = parse_info(line)
                self._reports_seen += 1
                if info and info.warning == 14 and self._reports_seen > 1:
                    faults.append(Fault(plan, rec.line if rec else None, rec.command.text if rec else "", "reset",
                                        f"firmware reset: settings reset to defaults (W:14) mid-plan ({line})"))
                    raise _Reset(faults[-1])
                extra.append(line)
                continue
            if line.startswith("$") and parse_setting(line):
                extra.append(line)
                continue
            if line.startswith("<"):  # a status report nobody asked for: keep going
                st = parse_status(line)
                if st:
                    f = self._check_status_reset(st, rec, plan)
                    if f:
                        faults.append(f)
                        raise _Reset(f)
                continue
            faults.append(self._unexpected(line, rec, plan))
            if faults[-1].kind == "reset":
                raise _Reset(faults[-1])

    def status(self, deadline: float, rec: Record | None, plan: str, faults: list[Fault]) -> Status:
        self.link.send_realtime(b"?")
        while True:
            try:
                line = self.link.read_line(deadline)
            except LinkTimeout as e:
                raise LinkTimeout("no answer to ?", e.partial) from None
            st = parse_status(line)
            if st is not None:
                f = self._check_status_reset(st, rec, plan)
                if f:
                    faults.append(f)
                    raise _Reset(f)
                return st
            faults.append(self._unexpected(line, rec, plan))
            if faults[-1].kind == "reset":
                raise _Reset(faults[-1])

    def wait_idle(self, deadline: float, rec: Record | None, plan: str, faults: list[Fault]) -> tuple[Status, float]:
        """Polls `?` until the arm is at rest. Each report has `timeout` seconds to come (a
        hung port); the arm has until `deadline` to come to rest."""
        moving = None  # the last report that said the arm moved
        while True:
            asked = time.monotonic()
            st = self.status(asked + self.timeout, rec, plan, faults)
            if st.at_rest:
                # at rest, but first seen after the deadline while it still moved at the look
                # before: it did not come to rest in time (a busy host can oversleep its poll
                # while the arm, or the emulator, runs on; the deadline still holds)
                if moving is not None and asked >= deadline:
                    raise LinkTimeout(f"last status {moving.text} before the deadline")
                return st, time.monotonic()
            moving = st
            if time.monotonic() >= deadline:
                raise LinkTimeout(f"last status {st.text}")
            time.sleep(self.poll)

    def command(self, text: str, plan: str, faults: list[Fault], timeout: float | None = None) -> tuple[str, list[str]]:
        """A line outside the plan (handshake, settings, re-homing): sent, answered, at rest."""
        self._expect_info = text.strip().upper() == "I"
        self.link.send_line(text)
        reply, extra = self.read_reply(time.monotonic() + (timeout or self.timeout), None, plan, faults)
        self._expect_info = False
        return reply, extra

    # ---- plans ----

    def run_plan(self, plan: Plan) -> PlanResult:
        t_start = time.monotonic()
        self._transcript = []
        self._reports_seen = 0
        res = PlanResult(plan=plan, records=[Record(plan=plan.name, command=c) for c in plan.commands])
        faults = res.faults
        name = plan.name
        vanished = False
        try:
            self.link = self.target.start_plan(name, self.out_dir)
            self.link.log = self._log
            self._setup(res, faults)
            if not res.aborted:
                self._run_commands(res, faults)
        except _Reset as r:
            res.aborted = r.fault.message
        except LinkVanished as e:
            vanished = True
            f = Fault(name, None, "", "vanished", f"the port vanished before the plan began ({e})")
            faults.append(f)
            res.aborted = f.message
        except LinkTimeout as e:
            f = Fault(name, None, "", "timeout", f"timeout before the plan began: {e}")
            faults.append(f)
            res.aborted = f.message
        except PredictError as e:
            f = Fault(name, None, "", "setup", f"no prediction: {e}")
            faults.append(f)
            res.aborted = f.message
        finally:
            vanished = vanished or any(f.kind == "vanished" for f in faults)
            if self.link is not None and not vanished and self.target.kind == "serial":
                self._leave_arm(res, faults)
            res.vnano_report = self.target.end_plan(vanished=vanished)
            self.link = None
        if res.vnano_report is not None:
            self._vnano_faults(res, faults)
        res.wall_s = time.monotonic() - t_start
        res.transcript = self._transcript
        return res

    def _setup(self, res: PlanResult, faults: list[Fault]) -> None:
        name = res.plan.name
        link = self.link
        # Who is there: `I` (a few tries: a Nano that was just reset may miss the first).
        reply = ""
        extra: list[str] = []
        for attempt in range(3):
            try:
                reply, extra = self.command("I", name, faults, timeout=min(self.timeout, 2.0))
                break
            except LinkTimeout:
                if attempt == 2:
                    raise
                link.discard_input()
        info = next((parse_info(x) for x in extra if parse_info(x)), None)
        res.info = info
        res.info_line = next((x for x in extra if x.startswith("[")), "")
        if reply != "ok" or info is None:
            res.aborted = f"the arm does not answer I with an info line (got {reply!r})"
            faults.append(Fault(name, None, "I", "setup", res.aborted))
            return
        if info.checksum is not None and self.robot.config_error:
            res.aborted = f"the arm cannot be configured for this robot: {self.robot.config_error}"
            faults.append(Fault(name, None, "I", "setup", res.aborted))
            return
        if info.checksum is not None and info.checksum != self.robot.config["checksum"]:
            # Configured for another arm (a fresh Nano runs the MK2): configure it for this one.
            info = self._configure(res, faults)
            if info is None:
                return
        # (A firmware before protocol 4 has no checksum: its name says which arm it was built for.)
        named = info.checksum is not None or info.robot == self.robot.name
        if not named or info.joints != len(self.robot.motors):
            res.aborted = (f"the arm is '{info.robot}' with {info.joints} joints, the robot file "
                           f"'{self.robot.name}' with {len(self.robot.motors)}: wrong robot file or firmware")
            faults.append(Fault(name, None, "I", "setup", res.aborted))
            return
        # The arm's settings (a real arm keeps them in EEPROM), then --settings' values.
        r, extra = self.command("$", name, faults)
        res.settings_arm = dict(s for s in (parse_setting(x) for x in extra) if s)
        self.current_settings = dict(res.settings_arm)
        if self.settings_override:
            for n, v in sorted(self.settings_override.items()):
                r, _ = self.command(f"${n}={v:g}", name, faults)
                if r != "ok":
                    res.aborted = f"the arm refuses the setting ${n}={v:g}: {r}"
                    faults.append(Fault(name, None, f"${n}={v:g}", "setup", res.aborted))
                    return
                self.current_settings[n] = v
            r, extra = self.command("$", name, faults)
        settings = dict(s for s in (parse_setting(x) for x in extra) if s)
        res.settings_start = settings
        self.current_settings = dict(settings)
        st = self.status(time.monotonic() + self.timeout, None, name, faults)
        if not self.target.fresh or st.steps != [0] * len(self.robot.motors):
            # Not at power-up (a real arm after another plan): back to step 0 on every motor,
            # the commanded angles exactly the zero angles, as the prediction assumes.
            zero = " ".join(f"{a:g}" for a in self.robot.zero_angles)
            r, _ = self.command(f"M {zero}", name, faults)
            if r != "ok":
                res.aborted = f"cannot return to the power-up pose (M {zero}): {r}"
                faults.append(Fault(name, None, f"M {zero}", "setup", res.aborted))
                return
            st, _ = self.wait_idle(time.monotonic() + self.timeout + 30, None, name, faults)
        if not st.at_rest:
            res.aborted = f"the arm is not at rest at the start ({st.text})"
            faults.append(Fault(name, None, "?", "setup", res.aborted))
            return
        res.predictions, res.predict_doc = predict_plan(self.robot, res.plan.path, settings)
        for rec in res.records:
            rec.pred = res.predictions.get(rec.line)
            if rec.pred is None:
                raise PredictError(f"{res.plan.path}:{rec.line}: articula predict has no record for '{rec.command.text}'")

    def _configure(self, res: PlanResult, faults: list[Fault]):
        """Writes the robot's configuration (`articula configure`'s lines) and reads the banner
        again: its Info when the checksum now agrees, else None with the plan aborted."""
        name = res.plan.name
        for line in self.robot.config["lines"]:
            r, _ = self.command(line, name, faults)
            if r != "ok":
                res.aborted = f"the arm refuses its configuration at `{line}`: {r}"
                faults.append(Fault(name, None, line, "setup", res.aborted))
                return None
        r, extra = self.command("I", name, faults)
        info = next((parse_info(x) for x in extra if parse_info(x)), None)
        res.configured = True
        if info is None or info.checksum != self.robot.config["checksum"]:
            res.aborted = (f"the arm's configuration checksum is {info and info.checksum} after configuring, "
                           f"not {self.robot.config['checksum']}")
            faults.append(Fault(name, None, "I", "setup", res.aborted))
            return None
        res.info = info
        res.info_line = next((x for x in extra if x.startswith("[")), "")
        return info

    def _run_commands(self, res: PlanResult, faults: list[Fault]) -> None:
        name = res.plan.name
        trace = self.target.trace if self.target.has_pins else None
        pins_before = None
        fw_before: list[int] | None = None
        pred_before: list[int] | None = [0] * len(self.robot.motors)  # the prediction's steps before this command (power-up: 0)
        n_rows = 0
        if trace:
            n_rows, pins_before = trace.sync()
        for i, rec in enumerate(res.records):
            cmd = rec.command
            if self.progress:
                self.progress.step(f"{name}:{cmd.line} {articula.line_command(cmd.text)}")
            pred = rec.pred
            reply_deadline = cmd.timeout or self.timeout
            run_deadline = cmd.timeout or (self.timeout + 3.0 * (pred.seconds if pred else 0.0))
            if self.hooks and hasattr(self.hooks, "before_send"):
                self.hooks.before_send(self, rec)
            if trace:
                rows_at_send, pins_at_send = trace.sync()
            try:
                self._expect_info = cmd.word == "I"
                rec.t_sent = time.monotonic()
                self.link.send_line(cmd.text)
                rec.sent = True
                if self.hooks and hasattr(self.hooks, "after_send"):
                    self.hooks.after_send(self, rec)
                rec.reply, rec.lines = self.read_reply(rec.t_sent + reply_deadline, rec, name, rec.faults)
                self._expect_info = False
                rec.status, rec.t_idle = self.wait_idle(rec.t_sent + run_deadline, rec, name, rec.faults)
            except _Reset as r:
                self._abort(res, rec, r.fault, faults, i + 1)
                return
            except LinkTimeout as e:
                if rec.reply is None:
                    msg = f"timeout: no reply within {reply_deadline:.1f} s of sending the line{e.got}"
                elif e.what == "no answer to ?":
                    msg = f"timeout: no answer to ? within {self.timeout:.1f} s{e.got}: the port is silent"
                else:
                    msg = f"timeout: not at rest within {run_deadline:.1f} s of sending the line ({e})"
                self._abort(res, rec, Fault(name, cmd.line, cmd.text, "timeout", msg), faults, i + 1, stop=True)
                return
            except LinkVanished as e:
                extra = ""
                if hasattr(self.target, "exit_description") and not self.target.alive(settle=1.0):
                    extra = f"; the virtual Nano {self.target.exit_description()}"
                self._abort(res, rec, Fault(name, cmd.line, cmd.text, "vanished", f"the port vanished ({e}){extra}"),
                            faults, i + 1)
                return
            finally:
                self._expect_info = False

            # What the firmware says.
            expect = rec.pred.reply if self.expect_predicted and rec.pred is not None else cmd.expect
            if rec.reply != expect:
                what = f"error reply {rec.reply} ({status_text(rec.reply)})" if rec.reply.startswith("error:") \
                    else f"reply {rec.reply}"
                rec.faults.append(Fault(name, cmd.line, cmd.text, "error-reply", f"{what}, the {'prediction' if self.expect_predicted else 'plan'} expects {expect}"))
            if rec.status is not None and rec.status.angles and len(rec.status.angles) == len(self.robot.motors):
                rec.tool_firmware = list(self.robot.tool_from_actuators(rec.status.angles))
            if rec.reply == "ok" and cmd.word == "$" and "=" in cmd.text:
                s = parse_setting(articula.line_command(cmd.text).replace(" ", ""))
                if s:
                    self.current_settings[s[0]] = s[1]
            # Every motor suddenly back on step 0 after agreeing with the prediction so far,
            # which the prediction does not say: the firmware started again (a real Nano
            # resets without a word).
            fw_now = rec.status.steps if rec.status is not None else None
            if pred is not None and fw_now is not None and fw_before and any(fw_before) and \
                    any(pred.steps) and not any(fw_now):
                rec.faults.append(Fault(name, cmd.line, cmd.text, "reset",
                                        f"firmware reset? every motor back at step 0 (it was on {fw_before}), "
                                        f"the prediction says {pred.steps}"))
            fw_before = fw_now if rec.firmware_match else None

            # What the pins did.
            if trace:
                rows_before = n_rows
                n_rows, pins = trace.sync()
                rec.pin_slack = self.pin_slack
                # A servo's pin shows a width once a period (20 ms), a change of one tick when
                # two pulses agree: the firmware is at rest a period or two before its pins are.
                # Wait for them to show its steps, so that every change of this move is counted
                # with it and none with the next. A few periods of the virtual Nano's time, which
                # a loaded machine may stretch to a second of the wall's; after 3 s the pins are
                # taken as they are (within the slack: a width on a tick's edge can alternate).
                if pred is not None and any(rec.pin_slack):
                    deadline = time.monotonic() + 3.0
                    while time.monotonic() < deadline and pins[:len(pred.steps)] != pred.steps:
                        time.sleep(0.005)
                        n_rows, pins = trace.sync()
                rec.pins_before, rec.pins = pins_before, pins
                pins_before = pins
                rows = trace.rows[rows_before:n_rows]
                # A servo that the command does not move may still show a one-tick change when two
                # pulses on a tick's edge decode alike (servo_decoder.h): not this move's.
                moving = None
                if pred is not None and pred_before is not None and any(rec.pin_slack):
                    moving = {i for i, (a, b) in enumerate(zip(pred.steps, pred_before)) if a != b}

                def move_steps(window):
                    return [r for r in window if r.is_step
                            and (moving is None or not rec.pin_slack[r.motor] or r.motor in moving)]

                steps = move_steps(rows)
                rec.step_events = len(steps)
                # The move's span counts the rows after the firmware had the line (the trace's
                # `line` row: its LF in the Nano's time), from the pins as they were then. A
                # servo's pin at rest may flip by one at any time; the virtual Nano's clock runs
                # on between the command before and this line (it sleeps through it, however
                # long the host takes), and a flip back to where the move starts, dated as the
                # move's first change, made a CI run measure a move 2 s longer than predicted.
                start_at, start_pins = after_line(trace.rows, max(rows_at_send, rows_before), n_rows, pins_at_send)
                sent = move_steps(trace.rows[start_at:n_rows])
                if sent:
                    rec.first_step_us, rec.last_step_us = pin_span(sent, rec.pin_slack, start_pins, pins)
                for r in rows:
                    if r.is_fault:
                        rec.coil_faults.append(f"motor {r.motor} {r.event} to {r.pattern} at {r.time_us / 1e6:.6f} s")
                if rec.coil_faults:
                    rec.faults.append(Fault(name, cmd.line, cmd.text, "coil",
                                            f"{len(rec.coil_faults)} coil fault(s): " + "; ".join(rec.coil_faults[:3])))
                # Duration from the cycle stamps: the first interval (no pin shows a move's
                # start) plus the span from the first step to the last.
                if sent and pred is not None and pred.seconds > 0:
                    rec.first_interval_s = first_interval_s(self.current_settings, pred)
                    rec.measured_s = rec.first_interval_s + (rec.last_step_us - rec.first_step_us) / 1e6
                    rec.measured_source = "pins"
            elif pred is not None and pred.queued and rec.reply == "ok" and rec.t_idle is not None:
                rec.measured_s = rec.t_idle - rec.t_sent
                rec.measured_source = "host clock"
            # A plan's time limit holds in the arm's own time. The virtual Nano runs faster than
            # the wall clock while it sleeps through a slow move, so there the limit is checked
            # against the pins' cycle stamps too (the wall clock still catches a hung port).
            if trace and cmd.timeout and rec.measured_s is not None and rec.measured_s > cmd.timeout:
                self._abort(res, rec, Fault(name, cmd.line, cmd.text, "timeout",
                                            f"timeout: not at rest within {cmd.timeout:.1f} s of sending the line "
                                            f"(it took {rec.measured_s:.1f} s of the virtual Nano's time, "
                                            f"by its pins' cycle stamps)"),
                            faults, i + 1, stop=True)
                return
            pred_before = pred.steps if pred is not None else None
            faults.extend(rec.faults)
            resets = [f for f in rec.faults if f.kind == "reset"]
            if resets:
                self._abort(res, rec, resets[0], faults, i + 1)
                return

        # Nothing may move after the last command came to rest.
        if trace:
            time.sleep(0.05)
            n_after, pins = trace.sync()
            moved = [r for r in trace.rows[n_rows:n_after] if r.is_step]
            if moved:
                last = res.records[-1]
                faults.append(Fault(name, last.line, last.command.text, "pins",
                                    f"{len(moved)} step(s) on the pins after the last command was at rest "
                                    f"(positions now {pins})"))

    def _abort(self, res: PlanResult, rec: Record | None, fault: Fault, faults: list[Fault], first_not_run: int,
               stop: bool = False) -> None:
        """Ends a plan early: the fault goes to its command, the commands from `first_not_run`
        on are not run."""
        if rec is not None and fault not in rec.faults:
            rec.faults.append(fault)
        for f in (rec.faults if rec is not None else [fault]):
            if f not in faults:
                faults.append(f)
        left = len(res.records) - first_not_run
        res.aborted = f"stopped at {fault.where()}: {fault.message}" + (f"; {left} command(s) not run" if left else "")
        if stop:
            # Stop the arm (`!`) so that nothing runs on; best effort.
            try:
                self.link.send_realtime(b"!")
                self.link.drain(0.3)
            except LinkError:
                pass
        if self.progress:
            self.progress.skip(left)

    def _leave_arm(self, res: PlanResult, faults: list[Fault]) -> None:
        """A real arm after a plan: the settings it had (it keeps them in EEPROM) put back,
        and the arm parked at its power-up pose (step 0 everywhere), where it must be when
        the port is next opened (that resets a Nano, which then takes itself to be at step 0)."""
        name = res.plan.name
        changed = {n: v for n, v in res.settings_arm.items() if self.current_settings.get(n) != v}
        try:
            for n, v in sorted(changed.items()):
                r, _ = self.command(f"${n}={v:g}", name, faults)
                if r != "ok":
                    faults.append(Fault(name, None, f"${n}={v:g}", "setup", f"could not restore ${n}: {r}"))
            st = self.status(time.monotonic() + self.timeout, None, name, faults)
            if st.state == "Idle" and st.steps and any(st.steps):
                zero = " ".join(f"{a:g}" for a in self.robot.zero_angles)
                r, _ = self.command(f"M {zero}", name, faults)
                if r == "ok":
                    self.wait_idle(time.monotonic() + self.timeout + 60, None, name, faults)
                else:
                    faults.append(Fault(name, None, f"M {zero}", "setup", f"could not park the arm: {r}"))
        except (LinkError, _Reset) as e:
            faults.append(Fault(name, None, "", "setup", f"after the plan: {e}"))

    def _vnano_faults(self, res: PlanResult, faults: list[Fault]) -> None:
        rep = res.vnano_report
        name = res.plan.name
        attributed = sum(len(r.coil_faults) for r in res.records)
        total = int(rep.get("faults") or 0)
        if total > attributed:
            faults.append(Fault(name, None, "", "coil",
                                f"{total - attributed} coil fault(s) outside any command (virtual Nano report)"))
        reason = rep.get("exit_reason", "")
        if reason.startswith("firmware"):
            faults.append(Fault(name, None, "", "crash", f"the firmware stopped: {reason} ({rep.get('cpu_state')})"))


class _Reset(Exception):
    def __init__(self, fault: Fault):
        super().__init__(fault.message)
        self.fault = fault


def kill_later(pid: int, seconds: float, sig=signal.SIGKILL) -> threading.Timer:
    """For tests: signal a process (the virtual Nano) after `seconds`."""
    import os

    def fire():
        try:
            os.kill(pid, sig)
        except ProcessLookupError:
            pass

    t = threading.Timer(seconds, fire)
    t.daemon = True
    t.start()
    return t
