"""The arm in the loop: a Nano on a serial port, or the virtual Nano (the real firmware ELF in
`articula-vnano`, reached through its pseudo-terminal: the same code path as a real port).

One thread owns the port: it reads every line (status reports `<...>`, info `[...]`, replies
`ok` / `error:N`), polls `?` at 15 Hz, and notices a port that goes away or stops answering
within 2 s. Commands go one at a time (the protocol's flow control: the reply before the next
line); the realtime stop `!` goes at once, whatever is waiting.
"""

from __future__ import annotations

import os
import queue
import shutil
import subprocess
import tempfile
import threading
import time
from pathlib import Path
from typing import Callable

import serial

from ..link import Link, LinkError, LinkTimeout, LinkVanished, Status, parse_info, parse_status, wait_for_pty

REPO = Path(__file__).resolve().parents[3]  # the tree, where make builds the virtual Nano

BAUD = 115200
POLL_S = 1 / 15          # status polls (every 10 ms for a second after a stop)
SILENT_S = 1.5           # no status for this long: the arm stopped answering
REPLY_TIMEOUT_S = 5.0


def virtual_nano() -> tuple[str, str] | None:
    """The virtual Nano's program and the firmware ELF, if they are built."""
    vnano = os.environ.get("ARTICULA_VNANO") or str(REPO / "build" / "hil" / "articula-vnano")
    elf = os.environ.get("ARTICULA_NANO_ELF") or str(REPO / "build" / "avr" / "firmware" / "articula-nano.elf")
    return (vnano, elf) if Path(vnano).is_file() and Path(elf).is_file() else None


def ports() -> list[dict]:
    """What can be connected: the serial ports present, and the virtual Nano when built."""
    out = []
    if virtual_nano():
        out.append({"id": "virtual", "label": "virtual Nano (the firmware in simavr)"})
    try:
        from serial.tools import list_ports
        for p in list_ports.comports():
            out.append({"id": p.device, "label": f"{p.device}: {p.description}"})
    except Exception:  # no port listing on this system: the virtual Nano only
        pass
    return out


class ArmError(Exception):
    """The arm cannot be connected or used: the message says why."""


class Arm:
    def __init__(self, robot_name: str, motors: int, gripper: tuple[float, float] | None,
                 on_change: Callable[[], None] = lambda: None):
        self.robot_name, self.motors, self.gripper = robot_name, motors, gripper
        self.on_change = on_change  # called from the port's thread when the status or the state changes
        self.port = None
        self.link: Link | None = None
        self.proc: subprocess.Popen | None = None
        self.tmp: str | None = None
        self.label = ""
        self.info: dict | None = None
        self.status: Status | None = None
        self.status_at = 0.0
        self.error = ""       # why the arm is gone ("" while connected)
        self.replies: queue.Queue[str] = queue.Queue()
        self.write_lock = threading.Lock()
        self.command_lock = threading.Lock()
        self.thread: threading.Thread | None = None
        self.running = False
        self.poll_now = threading.Event()
        self.polled_at = 0.0      # when the last `?` went out
        self.fast_until = 0.0     # after a stop: poll every 10 ms for a while, to see it end
        self.rtt_ms: float | None = None  # `?` to its status report, the last one

    # ---- connecting (blocking: the server runs it in a thread)

    def open(self, port_id: str, boot_wait: float = 2.0) -> dict:
        if port_id == "virtual":
            found = virtual_nano()
            if not found:
                raise ArmError("the virtual Nano is not built (make builds build/hil/articula-vnano)")
            device = self._start_virtual_nano(*found)
            self.label = "virtual Nano"
            boot_wait = 0.0
        else:
            device, self.label = port_id, port_id
        try:
            self.port = serial.Serial(device, BAUD, timeout=0.05, write_timeout=2)
        except (serial.SerialException, OSError) as e:
            self.close()
            raise ArmError(f"cannot open {device}: {e}") from None
        self.link = Link(self.port, alive=self._alive)
        if boot_wait:
            time.sleep(boot_wait)  # opening a real Nano's port resets it: its bootloader first
        self.link.discard_input()
        try:
            self.link.send_line("I")
            deadline = time.monotonic() + 3.0
            while True:
                line = self.link.read_line(deadline)
                info = parse_info(line)
                if info is not None:
                    self.info = info
                elif line == "ok" and self.info is not None:
                    break
        except LinkError as e:
            self.close()
            raise ArmError(f"{self.label} does not answer `I` as the Articula firmware does: {e}") from None
        if self.info.get("R") != self.robot_name or self.info.get("J") != str(self.motors):
            got = f"{self.info.get('R')} with {self.info.get('J')} motors"
            self.close()
            raise ArmError(f"{self.label} runs the firmware for {got}, not for {self.robot_name}: load that robot, or "
                           "flash the firmware for this one")
        self.running = True
        self.status_at = time.monotonic()
        self.thread = threading.Thread(target=self._run, name="articula-arm", daemon=True)
        self.thread.start()
        return self.info

    def _start_virtual_nano(self, vnano: str, elf: str) -> str:
        self.tmp = tempfile.mkdtemp(prefix="articula-studio-")
        link = Path(self.tmp) / "nano"
        cmd = [vnano, "--pty-link", str(link), "--realtime", "--quiet", "--elf", elf]
        if self.gripper:
            cmd += ["--gripper", f"{self.gripper[0]:g}:{self.gripper[1]:g}"]
        try:
            self.proc = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                                         stderr=subprocess.DEVNULL)
        except OSError as e:
            raise ArmError(f"cannot start {vnano}: {e.strerror}") from None
        if not wait_for_pty(self.proc, link, 15):
            self.close()
            raise ArmError("the virtual Nano did not start (no 'pty:' line)")
        return str(link)

    def _alive(self) -> bool:
        return self.proc is None or self.proc.poll() is None

    # ---- the port's thread

    def _run(self) -> None:
        next_poll = 0.0
        while self.running:
            now = time.monotonic()
            try:
                if now >= next_poll or self.poll_now.is_set():
                    self.poll_now.clear()
                    with self.write_lock:
                        self.link.send_realtime(b"?")
                    self.polled_at = time.monotonic()
                    next_poll = now + (0.01 if now < self.fast_until else POLL_S)
                line = self.link.read_line(min(next_poll, now + 0.02))
            except LinkTimeout:
                if time.monotonic() - self.status_at > SILENT_S:
                    self._gone(f"{self.label} stopped answering: no status for {SILENT_S:g} s")
                continue
            except (LinkVanished, LinkError) as e:
                self._gone(f"{self.label} is gone: {e}")
                continue
            st = parse_status(line)
            if st is not None and st.warning == 14:
                # settings reset to defaults: the firmware started again
                self._gone(f"{self.label} reset (its settings went back to the defaults): its queue and position "
                           "are lost; connect again")
                continue
            if st is not None:
                changed = self.status is None or st.text != self.status.text
                self.status, self.status_at = st, time.monotonic()
                self.rtt_ms = (self.status_at - self.polled_at) * 1000
                if changed:
                    self.on_change()
            elif line == "ok" or line.startswith("error:"):
                self.replies.put(line)
            elif line.startswith("[Articula") and parse_info(line) is not None:
                # a banner out of turn: the Nano reset (a power glitch, the USB re-plugged):
                # it is back at step 0 and forgot its queue; the page must know
                self._gone(f"{self.label} reset (it sent its start-up banner): its queue and position are lost; "
                           "connect again")

    def _gone(self, why: str) -> None:
        if not self.running:
            return
        self.running = False
        self.error = why
        self.replies.put("")  # wakes a command waiting for its reply
        self.on_change()

    # ---- using it (blocking: the server runs them in a thread)

    def command(self, line: str) -> str:
        """Sends one line and returns the arm's reply (`ok`, `error:N`); one at a time."""
        if not self.running:
            raise ArmError(self.error or "not connected")
        with self.command_lock:
            while not self.replies.empty():
                self.replies.get_nowait()
            try:
                with self.write_lock:
                    self.link.send_line(line)
            except LinkError as e:
                self._gone(f"{self.label} is gone: {e}")
                raise ArmError(self.error) from None
            try:
                reply = self.replies.get(timeout=REPLY_TIMEOUT_S)
            except queue.Empty:
                raise ArmError(f"no reply to '{line}' within {REPLY_TIMEOUT_S:g} s") from None
            if not reply:
                raise ArmError(self.error)
            self.poll_now.set()
            return reply

    def stop(self) -> float:
        """The realtime stop `!`: the arm ends its move and empties its queue. Returns when it
        was sent (time.monotonic())."""
        if not self.running:
            raise ArmError(self.error or "not connected")
        with self.write_lock:
            self.link.send_realtime(b"!")
        t = time.monotonic()
        self.fast_until = t + 1.0
        self.poll_now.set()
        return t

    def wait_idle(self, timeout: float) -> bool:
        """Until the status says Idle after now (False: timeout or gone)."""
        start = time.monotonic()
        while time.monotonic() - start < timeout and self.running:
            st, at = self.status, self.status_at
            if st is not None and at > start + POLL_S / 2 and st.state == "Idle":
                return True
            time.sleep(0.01)
        return False

    def close(self) -> None:
        self.running = False
        if self.thread and self.thread is not threading.current_thread():
            self.thread.join(timeout=1)
        if self.port is not None:
            try:
                self.port.close()
            except (serial.SerialException, OSError):
                pass
            self.port = None
        if self.proc is not None:
            if self.proc.poll() is None:
                self.proc.terminate()
                try:
                    self.proc.wait(timeout=2)
                except subprocess.TimeoutExpired:
                    self.proc.kill()
                    self.proc.wait()
            self.proc = None
        if self.tmp:
            shutil.rmtree(self.tmp, ignore_errors=True)
            self.tmp = None
