"""What the virtual Nano's pins did, read while it runs.

`articula-vnano --trace-steps FILE` writes one CSV row per coil event, and one per line the
firmware received (event `line`, motor -1) (`cycle,motor,steps,pattern,event,time_us`,
hil/README.md), through C stdio. A regular file
is block-buffered, so its last rows are only on disk at exit; a terminal is line-buffered.
So the harness gives the virtual Nano a pseudo-terminal of its own as the trace file (raw
mode: no CR added) and reads it in a thread. The virtual Nano writes a coil event's row the
moment it decodes the port write, before the firmware can have finished the move and
before any later byte of the serial line: when the harness has the `<Idle|...>` report
that follows a move, every row of that move is already in the trace pseudo-terminal.
`sync()` reads everything there is and returns the count of rows; rows since the previous
`sync()` are the pins' share of the command just finished.
"""

from __future__ import annotations

import os
import select
import threading
import tty
from dataclasses import dataclass


@dataclass
class TraceRow:
    cycle: int
    motor: int
    steps: int
    pattern: str
    event: str
    time_us: float

    @property
    def is_step(self) -> bool:
        return self.event in ("step+", "step-")

    @property
    def is_coil(self) -> bool:
        """A motor's row; not a `line` row (the firmware had a line's LF)."""
        return self.motor >= 0

    @property
    def is_fault(self) -> bool:
        return self.event.startswith("fault")


class TraceReader:
    def __init__(self, motors: int = 3):
        self.master, self.slave = os.openpty()
        tty.setraw(self.slave)
        self.path = os.ttyname(self.slave)
        os.set_blocking(self.master, False)
        self.rows: list[TraceRow] = []
        self.bad_rows: list[str] = []
        self.positions = [0] * motors
        self._partial = b""
        self._lock = threading.Lock()
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name="vnano-trace", daemon=True)
        self._closed = False

    def start(self) -> None:
        self._thread.start()

    def _read_available(self) -> None:
        # Called with the lock held: reads until nothing is waiting.
        while True:
            try:
                data = os.read(self.master, 65536)
            except BlockingIOError:
                return
            except OSError:
                return
            if not data:
                return
            self._partial += data
            *lines, self._partial = self._partial.split(b"\n")
            for raw in lines:
                self._parse(raw.decode("ascii", errors="replace").strip())

    def _parse(self, text: str) -> None:
        if not text or text.startswith("cycle,"):
            return
        parts = text.split(",")
        try:
            row = TraceRow(int(parts[0]), int(parts[1]), int(parts[2]), parts[3], parts[4], float(parts[5]))
        except (ValueError, IndexError):
            self.bad_rows.append(text)
            return
        self.rows.append(row)
        if 0 <= row.motor < len(self.positions):
            self.positions[row.motor] = row.steps

    def _run(self) -> None:
        while not self._stop.is_set():
            try:
                ready, _, _ = select.select([self.master], [], [], 0.1)
            except (OSError, ValueError):
                return
            if ready:
                with self._lock:
                    self._read_available()

    def sync(self) -> tuple[int, list[int]]:
        """Reads every row written so far; returns the number of rows and the decoded
        position of each motor."""
        with self._lock:
            self._read_available()
            return len(self.rows), list(self.positions)

    def close(self) -> None:
        if self._closed:
            return
        self._closed = True
        self._stop.set()
        if self._thread.is_alive():
            self._thread.join(timeout=2)
        with self._lock:
            self._read_available()
        for fd in (self.master, self.slave):
            try:
                os.close(fd)
            except OSError:
                pass

    def write_csv(self, path) -> None:
        with open(path, "w") as f:
            f.write("cycle,motor,steps,pattern,event,time_us\n")
            for r in self.rows:
                f.write(f"{r.cycle},{r.motor},{r.steps},{r.pattern},{r.event},{r.time_us:.4f}\n")
