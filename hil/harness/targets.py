"""Where the plans run: a real port, or the virtual Nano. Both hand the runner a pyserial
port opened the same way (`serial.Serial(path, 115200)`); only the virtual Nano also has pins
to read (its trace) and a report at the end.
"""

from __future__ import annotations

import json
import shutil
import signal
import subprocess
import tempfile
import time
from pathlib import Path

import serial

from articula.link import Link, wait_for_pty
from .trace import TraceReader

BAUD = 115200


class TargetError(Exception):
    """The target cannot be started or opened (a usage error: exit code 2)."""


class SerialTarget:
    """A Nano on a serial port. Opening the port resets a real Nano (DTR), so the harness
    waits `boot_wait` seconds for its bootloader before it talks."""

    kind = "serial"
    has_pins = False

    def __init__(self, device: str, boot_wait: float = 2.0, log=None):
        self.device = device
        self.boot_wait = boot_wait
        self.log = log
        self.port = None
        self.link: Link | None = None
        self.fresh = False
        self.trace = None
        self.dead = False

    def describe(self) -> str:
        return f"serial port {self.device}"

    def start_plan(self, name: str, out_dir: Path) -> Link:
        if self.dead:
            raise TargetError(f"{self.device} went away earlier in this run")
        if self.port is None:
            try:
                self.port = serial.Serial(self.device, BAUD, timeout=0.05, write_timeout=2)
            except (serial.SerialException, OSError) as e:
                raise TargetError(f"cannot open {self.device}: {e}") from None
            time.sleep(self.boot_wait)
            self.link = Link(self.port, log=self.log)
            self.link.discard_input()
            self.fresh = True  # just reset by opening; the first plan still re-homes (below)
        else:
            self.fresh = False
        return self.link

    def alive(self, settle: float = 0.0) -> bool:
        return not self.dead

    def end_plan(self, vanished: bool = False) -> dict | None:
        if vanished:
            self.dead = True
            self.close()
        return None

    def close(self) -> None:
        if self.port is not None:
            try:
                self.port.close()
            except (serial.SerialException, OSError):
                pass
            self.port = None


class VirtualNanoTarget:
    """A fresh `articula-vnano` for every plan: the firmware powers up at step 0 with blank
    EEPROM (default settings), exactly what `articula predict` assumes. It runs as fast as
    it can (no --realtime); its pseudo-terminal is opened with pyserial like a real port."""

    kind = "vnano"
    has_pins = True

    def __init__(self, vnano: str, elf: str | None, motors: int, gripper: tuple[float, float] | None = None,
                 log=None, keep_traces: bool = False, start_timeout: float = 15.0, half_step: list[int] = (),
                 unipolar: bool = False, cnc: bool = False, servos: list[tuple[int, str, float]] = ()):
        self.servos = list(servos)
        self.half_step = list(half_step)
        self.unipolar = unipolar
        self.cnc = cnc
        self.vnano = vnano
        self.elf = elf
        self.motors = motors
        self.gripper = gripper
        self.log = log
        self.keep_traces = keep_traces
        self.start_timeout = start_timeout
        self.proc: subprocess.Popen | None = None
        self.port = None
        self.link: Link | None = None
        self.trace: TraceReader | None = None
        self.tmp: str | None = None
        self.report_path: Path | None = None
        self.trace_path: Path | None = None
        self.stderr_path: Path | None = None
        self.fresh = True
        self.exit_status: int | None = None

    def describe(self) -> str:
        return "virtual Nano"

    def start_plan(self, name: str, out_dir: Path) -> Link:
        self.tmp = tempfile.mkdtemp(prefix="articula-harness-")
        link_path = Path(self.tmp) / "nano"
        vdir = out_dir / "vnano"
        vdir.mkdir(parents=True, exist_ok=True)
        stem = Path(name).stem
        self.report_path = vdir / f"{stem}.json"
        self.trace_path = vdir / f"{stem}-trace.csv"
        self.stderr_path = Path(self.tmp) / "stderr.txt"
        self.trace = TraceReader(self.motors)
        cmd = [self.vnano, "--pty-link", str(link_path), "--report", str(self.report_path),
               "--trace-steps", self.trace.path, "--quiet"]
        if self.elf:
            cmd += ["--elf", self.elf]
        if self.gripper:
            cmd += ["--gripper", f"{self.gripper[0]:g}:{self.gripper[1]:g}"]
        for m in self.half_step:
            cmd += ["--half-step", str(m)]
        if self.unipolar:
            cmd += ["--uln2003"]
        if self.cnc:
            cmd += ["--cnc"]
        for m, pin, us in self.servos:
            cmd += ["--servo", f"{m}:{pin}:{us:g}"]
        self.exit_status = None
        try:
            with open(self.stderr_path, "w") as err:
                self.proc = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=err)
        except OSError as e:
            self._cleanup_files()
            raise TargetError(f"cannot start {self.vnano}: {e.strerror}") from None
        # The first line names the pseudo-terminal: `pty: /dev/pts/N`.
        if not wait_for_pty(self.proc, link_path, self.start_timeout):
            why = self._stderr_text() or f"no 'pty:' line within {self.start_timeout:.0f} s"
            self._stop_process()
            self._cleanup_files()
            raise TargetError(f"the virtual Nano did not start: {why}")
        try:
            self.port = serial.Serial(str(link_path), BAUD, timeout=0.05, write_timeout=2)
        except (serial.SerialException, OSError) as e:
            self._stop_process()
            self._cleanup_files()
            raise TargetError(f"cannot open the virtual Nano's port {link_path}: {e}") from None
        self.trace.start()
        self.link = Link(self.port, alive=self.alive, log=self.log)
        self.fresh = True
        return self.link

    def alive(self, settle: float = 0.0) -> bool:
        """Whether the process runs; `settle`: give a dying one that long to be gone (its
        port closes a moment before it can be waited for)."""
        if self.proc is None:
            return False
        if settle:
            try:
                self.proc.wait(timeout=settle)
            except subprocess.TimeoutExpired:
                pass
        if self.proc.poll() is not None:
            self.exit_status = self.proc.returncode
            return False
        return True

    def exit_description(self) -> str:
        rc = self.proc.returncode if self.proc else None
        if rc is None:
            return "still running"
        if rc < 0:
            try:
                return f"was killed by {signal.Signals(-rc).name}"
            except ValueError:
                return f"was killed by signal {-rc}"
        return f"exited with status {rc}"

    def _stderr_text(self) -> str:
        try:
            return self.stderr_path.read_text().strip() if self.stderr_path else ""
        except OSError:
            return ""

    def _stop_process(self) -> None:
        p = self.proc
        if p is None or p.poll() is not None:
            return
        try:
            p.send_signal(signal.SIGCONT)  # a stopped process acts on SIGTERM only once continued
            p.send_signal(signal.SIGTERM)
            p.wait(timeout=10)
        except subprocess.TimeoutExpired:
            p.kill()
            p.wait(timeout=10)
        except ProcessLookupError:
            pass

    def _cleanup_files(self) -> None:
        if self.trace:
            self.trace.close()
        if self.tmp:
            shutil.rmtree(self.tmp, ignore_errors=True)
            self.tmp = None

    def end_plan(self, vanished: bool = False) -> dict | None:
        """Ends the run (SIGTERM: the virtual Nano writes its report) and returns the report."""
        if self.port is not None:
            try:
                self.port.close()
            except (serial.SerialException, OSError):
                pass
            self.port = None
        self._stop_process()
        if self.proc is not None:
            self.exit_status = self.proc.returncode
            if self.proc.stdout:
                self.proc.stdout.close()
        if self.trace:
            self.trace.close()
            if self.keep_traces and self.trace_path:
                self.trace.write_csv(self.trace_path)
        report = None
        if self.report_path and self.report_path.exists():
            try:
                report = json.loads(self.report_path.read_text())
            except (OSError, json.JSONDecodeError):
                report = None
        stderr = self._stderr_text()
        if self.tmp:
            shutil.rmtree(self.tmp, ignore_errors=True)
            self.tmp = None
        if report is not None:
            report["_stderr"] = stderr
            report["_exit"] = self.exit_description()
        return report

    def close(self) -> None:
        if self.proc is not None and self.proc.poll() is None:
            self._stop_process()
        self._cleanup_files()
