"""The serial line to the arm (docs/protocol.md), over any pyserial port: a Nano on
/dev/ttyUSB0 or the virtual Nano's pseudo-terminal, the same code for both. The harness
(hil/harness) talks to the arm through it, and reads its lines with the firmware's own parsers
(shared/articula/protocol.h, through articula._core.parse_arm_line). Needs pyserial.

Every read has a deadline: a port that stops answering raises LinkTimeout, one that goes
away (the device unplugged, the virtual Nano gone) LinkVanished. Never a hang.
"""

from __future__ import annotations

import os
import select
import time
from dataclasses import dataclass
from pathlib import Path

import serial

from . import _core
from . import status_text as _status_text


class LinkError(Exception):
    pass


class LinkTimeout(LinkError):
    def __init__(self, what: str, partial: str = ""):
        self.what, self.partial = what, partial
        super().__init__(what + self.got)

    @property
    def got(self) -> str:
        """What came without a line end, if anything."""
        return f" (got '{self.partial}' without a line end)" if self.partial else ""


class LinkVanished(LinkError):
    pass


def status_text(reply: str) -> str:
    """`error:9` -> "target beyond a joint limit" (the core's status table, through the
    `articula` package)."""
    try:
        return _status_text(reply)
    except ValueError:
        return "not a reply"


@dataclass
class Status:
    """A status report, `<Idle|S:32,0,-8|A:10.133,90.000,-5.821|G:0|Q:8|C:1>`, as the firmware's
    own parser reads it (shared/articula/protocol.h, through `articula._core.parse_arm_line`)."""
    state: str
    steps: list[int]
    angles: list[float]  # deg
    millideg: list[int]  # the same angles, exactly as sent (thousandths of a degree)
    gripper: int
    queue: int  # free places in the motion queue
    coils: int
    warning: int | None  # a status code said once (14: settings reset), None when absent
    text: str = ""
    # nothing runs and nothing will until another line (Idle, or Alarm): the core's
    # state_at_rest (shared/articula/protocol.h), the rule every sender waits by
    at_rest: bool = False


@dataclass
class Info:
    """The banner, `[Articula|V:0.1.0|P:5|J:3|R:MK2 Plus|K:21232]`, read by the firmware's parser."""
    version: str
    protocol: int
    joints: int
    robot: str
    warning: int | None
    text: str = ""
    checksum: int | None = None  # K: the robot configuration's (protocol 4); None before


def parse_status(line: str) -> Status | None:
    p = _core.parse_arm_line(line)
    if p["kind"] != "status":
        return None
    return Status(state=p["state"], steps=p["steps"], angles=p["angles"], millideg=p["millideg"], gripper=p["gripper"],
                  queue=p["free"], coils=int(p["coils"]), warning=p["warning"] or None, text=line,
                  at_rest=p["at_rest"])


def parse_info(line: str) -> Info | None:
    p = _core.parse_arm_line(line)
    if p["kind"] != "info":
        return None
    return Info(version=p["version"], protocol=p["protocol"], joints=p["joints"], robot=p["robot"],
                warning=p["warning"] or None, text=line, checksum=p.get("checksum"))


def parse_setting(line: str) -> tuple[int, float] | None:
    """`$3=200.000` -> (3, 200.0): a setting as the firmware lists it."""
    p = _core.parse_arm_line(line)
    return (p["number"], p["value"]) if p["kind"] == "setting" else None


class Link:
    """Lines to and from the arm. `port` is a pyserial port (or anything with read, write,
    in_waiting and a settable timeout); `alive` says whether the other end still exists
    (the virtual Nano's process), so a dead one is noticed without waiting for a timeout;
    `log` receives every line, both ways."""

    def __init__(self, port, alive=None, log=None):
        self.port = port
        self.alive = alive or (lambda: True)
        self.log = log
        self._buf = b""
        # A POSIX serial port or pseudo-terminal is read with select() on its file descriptor:
        # no termios call per read (setting pyserial's timeout is one), which halves the time
        # of a short exchange. Anything else (a port without one) through pyserial's read.
        try:
            self._fd = port.fileno()
        except (AttributeError, OSError, ValueError, TypeError):
            self._fd = None
        if not isinstance(self._fd, int):
            self._fd = None

    def _note(self, direction: str, text: str) -> None:
        if self.log:
            self.log(direction, text)

    def write(self, data: bytes) -> None:
        try:
            # pyserial writes at once (no flush: tcdrain could wait on a device that is gone).
            self.port.write(data)
        except serial.SerialTimeoutException:  # (a SerialException: first)
            raise LinkTimeout("the port takes no more bytes (write timeout)") from None
        except (serial.SerialException, OSError, ValueError) as e:  # ValueError: port closed
            raise LinkVanished(f"writing: {e}") from None

    def send_line(self, text: str) -> None:
        self._note(">", text)
        self.write(text.encode("ascii", errors="surrogateescape") + b"\n")

    def send_realtime(self, byte: bytes) -> None:
        self.write(byte)

    def read_line(self, deadline: float) -> str:
        """The next line from the arm, without its LF (and CR)."""
        while b"\n" not in self._buf:
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                raise LinkTimeout("no answer", self._buf.decode("ascii", errors="replace"))
            try:
                if self._fd is not None:
                    ready, _, _ = select.select([self._fd], [], [], min(remaining, 0.1))
                    data = os.read(self._fd, 4096) if ready else None
                else:
                    t = min(remaining, 0.05)
                    if self.port.timeout != t:
                        self.port.timeout = t
                    waiting = self.port.in_waiting
                    data = self.port.read(max(1, min(waiting, 4096)))
            except (serial.SerialException, OSError, ValueError, TypeError) as e:
                raise LinkVanished(str(e) or type(e).__name__) from None
            if data:
                self._buf += data
            elif data == b"" and self._fd is not None:  # ready, and nothing: the other end closed
                raise LinkVanished("the device at its other end is gone")
            elif not self.alive():
                raise LinkVanished("the device at its other end is gone")
        raw, _, self._buf = self._buf.partition(b"\n")
        text = raw.decode("ascii", errors="replace").rstrip("\r")
        self._note("<", text)
        return text

    def drain(self, seconds: float) -> list[str]:
        """Every line that arrives within `seconds` (what a reset or a stop leaves behind)."""
        lines = []
        end = time.monotonic() + seconds
        while True:
            try:
                lines.append(self.read_line(end))
            except LinkTimeout:
                return lines

    def discard_input(self) -> None:
        self._buf = b""
        try:
            self.port.reset_input_buffer()
        except (serial.SerialException, OSError, ValueError, AttributeError):  # (a port with no such call)
            pass


def wait_for_pty(proc, link_path: Path, timeout: float) -> bool:
    """Whether a just-started `articula-vnano --pty-link PATH` is ready: its first line names
    its pseudo-terminal (`pty: /dev/pts/N`) and PATH links to it, within `timeout` seconds."""
    deadline = time.monotonic() + timeout
    first = b""
    while not first.endswith(b"\n"):
        remaining = deadline - time.monotonic()
        if remaining <= 0 or proc.poll() is not None:
            break
        ready, _, _ = select.select([proc.stdout], [], [], min(remaining, 0.1))
        if ready:
            chunk = os.read(proc.stdout.fileno(), 256)
            if not chunk:
                break
            first += chunk
    return first.startswith(b"pty: ") and Path(link_path).exists()
