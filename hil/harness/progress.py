"""A progress bar on stderr: redrawn in place on a terminal, one line per plan otherwise."""

from __future__ import annotations

import sys
import time


class Progress:
    def __init__(self, total: int, stream=None, enabled: bool = True):
        self.total = max(total, 1)
        self.done = 0
        self.stream = stream or sys.stderr
        self.enabled = enabled
        self.tty = enabled and hasattr(self.stream, "isatty") and self.stream.isatty()
        self.t0 = time.monotonic()
        self._last = 0.0
        self._width = 0

    def plan(self, name: str, commands: int) -> None:
        if self.enabled and not self.tty:
            print(f"harness: {name}: {commands} commands ({self.done}/{self.total} done)", file=self.stream,
                  flush=True)

    def step(self, label: str) -> None:
        self.done += 1
        self._draw(label)

    def skip(self, n: int) -> None:
        self.done += n
        self._draw("")

    def _draw(self, label: str) -> None:
        if not self.tty:
            return
        now = time.monotonic()
        if now - self._last < 0.05 and self.done < self.total:
            return
        self._last = now
        frac = min(self.done / self.total, 1.0)
        bar = "#" * int(frac * 30)
        text = f"\r[{bar:<30}] {self.done}/{self.total} {now - self.t0:5.1f} s  {label[:40]}"
        pad = max(0, self._width - len(text))
        self._width = len(text)
        self.stream.write(text + " " * pad)
        self.stream.flush()

    def finish(self) -> None:
        if self.tty:
            self.stream.write("\r" + " " * self._width + "\r")
            self.stream.flush()
