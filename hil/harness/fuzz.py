"""Protocol fuzz: `python -m hil.harness fuzz [--lines N] [--seed S] [--port DEV] [--report FILE]`.

Sends N seeded random and malformed lines to the firmware (the virtual Nano by default, or a
Nano on a serial port) and holds every one to docs/protocol.md: exactly one reply (`ok` or
`error:N`), no reset, no hang, no motion from a rejected line, and on the virtual Nano the
motor driver pins where the status report says the motors are.

How lines are framed. A fuzz line is the bytes before one LF (0x0A) plus that LF: the
generator never puts an LF inside a line, so every fuzz line is exactly one protocol line
and must get exactly one reply. Every other byte value (0x00-0xFF, CR included) may appear
in a line, except the realtime bytes `?` and `!`: they are put in on purpose by the
`realtime` class (at most one `?` and one `!` a line, anywhere before the LF), so the
checker knows how many status reports to expect and when the arm was told to stop.

Classes (the share of lines, roughly): valid lines the arm must accept (`valid`, 12 %: small
`L`, `M` within the limits, reachable `P`, `G`, `S`, `H`, `I`, `$`, comments, a command padded
to exactly 64 bytes, CRLF), random bytes (`random`), overlong lines (`overlong`, 65-300 bytes,
some of them valid commands padded with blanks or a comment: `error:7` and no motion), bad
numbers, NaN and inf, bad joint indices, out-of-range targets (`L`/`M` beyond a limit, `P` out
of reach, `G`, `S`), missing and extra arguments, unknown command letters, control and
non-ASCII bytes, empty lines, setting lines with bad values (and a few good ones, each
followed by a line that puts the old value back), realtime bytes mid-line (`realtime`: a line
of another class with `?` and/or `!` inserted; its reply must be that line's), and `stop`: a
long `M` and a `!` while it runs (the arm decelerates; the commanded angles become those of
the steps reached, as the protocol says, and the fuzz goes on from there).

For each line the fuzz knows the reply it must get where the protocol fixes it (every class
but `random`, whose lines only need one reply of either kind). The arm is at rest before
every line (after an accepted move the fuzz polls `?` until `Idle`: the protocol's flow
control), so the steps in the status report after a rejected line must equal those before
it, and no coil may have changed on the pins. A valid `L` or `M` must end on the steps the
protocol's rounding gives (actuation.h, recomputed here in integers).

The run's settings: `$0=4000`, `$1=100000`, `$5=0` (short moves, no gripper pause), set
before the first fuzz line; on a real port the arm's own settings are put back at the end.
"""

from __future__ import annotations

import json
import math
import os
import random
import select
import tempfile
import time
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path

import articula
from articula.link import Link, LinkTimeout, LinkVanished, parse_info, parse_setting, parse_status, Status
from .randplan import millis_text as fmt
from .robot import Robot

RUN_SETTINGS = {0: 4000, 1: 100000, 5: 0}
# The firmware's settings and their defaults: shared/articula/settings.h, through the bindings.
SETTING_DEFAULTS = {n: default for n, (_lo, _hi, default) in articula._core._settings_table.items()}
COMMAND_LETTERS = set("LSMPGHZIDNT")
UNKNOWN_LETTERS = [c for c in "ABCEFJKOQRUVWXY"]
REALTIME = (ord("?"), ord("!"))
MAX_LINE = 64
VALID_MARGIN = 1500  # thousandths of a degree: valid targets stay this far inside the limits


# ---------------------------------------------------------------------------------------
# The arm's arithmetic (shared/articula/actuation.h), in integers.

def _div_round_half_away(n: int, d: int) -> int:
    q, r = divmod(abs(n), d)
    if 2 * r >= d:
        q += 1
    return q if n >= 0 else -q


class Axis:
    """One motor: angles in thousandths of a degree, steps as actuation.h counts them."""

    def __init__(self, m):
        self.name = m.name
        self.zero = round(m.zero * 1000)
        self.min = round(m.min * 1000)
        self.max = round(m.max * 1000)
        self.dir = m.direction
        self.num = m.steps_per_rev * m.microsteps * int(m.gear[0])
        self.den = 360000 * int(m.gear[1])

    def quantize(self, millideg: int) -> int:
        return _div_round_half_away(self.dir * (millideg - self.zero) * self.num, self.den)

    def step_angle_exact(self, steps: int) -> Fraction:
        return self.zero + Fraction(self.dir * steps * self.den, self.num)

    def step_angle(self, steps: int) -> int:
        """The step's angle rounded to a thousandth, half away from zero (the A field)."""
        return self.zero + _div_round_half_away(self.dir * steps * self.den, self.num)

    def quantize_within_limits(self, millideg: int) -> int:
        s = self.quantize(millideg)
        while self.step_angle_exact(s) > self.max:
            s -= self.dir
        while self.step_angle_exact(s) < self.min:
            s += self.dir
        return s


def millideg(text: str) -> int:
    """`-12.345` -> -12345 (the report's fixed-point angles, read exactly)."""
    t = text.strip()
    neg = t.startswith("-")
    whole, _, frac = t.lstrip("+-").partition(".")
    v = int(whole or "0") * 1000 + int((frac + "000")[:3])
    return -v if neg else v


# ---------------------------------------------------------------------------------------
# The lines.

@dataclass
class FuzzLine:
    cls: str                      # the class (summary key)
    data: bytes                   # every byte sent for this line, its LF last
    expect: frozenset | None      # replies the protocol allows ("ok", "error:9"); None: either kind
    kind: str = ""                # what the line is (sub-class, for findings)
    moves: bool = False           # a valid move: the arm may move (and must end on `target`)
    target: list[int] | None = None   # the steps a valid L/M must end on (None: not predicted)
    queries: int = 0              # '?' bytes inside
    stop: bool = False            # '!' inside
    info: bool = False            # `I`: one info line before the reply
    listing: bool = False         # `$`: a setting line per setting before the reply
    setting: tuple[int, int] | None = None  # a valid `$n=v`
    stop_after: bool = False      # class stop: '!' sent after the reply, mid-move
    start: list[int] | None = None  # class stop: the steps the move starts from
    estimate: bool = False        # P, H: the commanded angles afterwards are taken from the status
    burst: list[bytes] = field(default_factory=list)  # class burst: lines streamed before this one,
                                                      # each sent once the one before is answered ok

    def text(self) -> str:
        return repr(self.data)[2:-1]


class ArmModel:
    """What the fuzz knows about the arm between lines: its steps (from the last status
    report) and its commanded angles (exact after M, L, '!'; estimated after P and H)."""

    def __init__(self, robot: Robot):
        self.axes = [Axis(m) for m in robot.motors]
        self.commanded = [a.zero for a in self.axes]
        self.steps = [0] * len(self.axes)
        self.exact = True

    def rederive(self, steps: list[int]) -> None:
        """After '!': the commanded angles become the angles of the steps reached."""
        self.steps = list(steps)
        self.commanded = [a.step_angle(s) for a, s in zip(self.axes, steps)]
        self.exact = True

    def estimate(self, status: Status) -> None:
        """After a move whose commanded angles the fuzz cannot compute (P, H): the angles of
        the steps, within half a step of the commanded ones."""
        self.steps = list(status.steps)
        self.commanded = list(status.millideg)
        self.exact = False


class Generator:
    """Seeded: the same seed, robot and replies give the same lines."""

    WEIGHTS = [("valid", 12), ("random", 14), ("overlong", 7), ("number", 10), ("nan", 6), ("joint", 7),
               ("target", 10), ("args", 5), ("unknown", 6), ("control", 5), ("empty", 2), ("settings", 6),
               ("realtime", 9), ("stop", 1)]

    # With bursts: a stream of moves that fills the queue, then a line held until there is room
    # (opt-in: the default classes, and so every seed's lines, stay as they were).
    BURST_WEIGHT = ("burst", 6)

    def __init__(self, robot: Robot, seed: int, bursts: bool = False):
        self.robot = robot
        self.rng = random.Random(seed)
        self.n = len(robot.motors)
        self.arm = ArmModel(robot)
        self.pending: list[FuzzLine] = []  # lines that must follow (a setting put back)
        weights = self.WEIGHTS + ([self.BURST_WEIGHT] if bursts else [])
        self.classes = [c for c, _ in weights]
        self.weights = [w for _, w in weights]

    # -- helpers --
    def _num(self, millis: int) -> str:
        """A number's text, exactly `millis` thousandths, in one of the forms the protocol reads."""
        r = self.rng.random()
        s = fmt(millis)
        if r < 0.1 and millis >= 0:
            s = "+" + s
        elif r < 0.15 and "." not in s:
            s += "."
        elif r < 0.2 and "." in s:
            s += "0"  # a trailing zero: more decimals, the same value
        return s

    def _blank(self) -> str:
        return self.rng.choice((" ", " ", " ", "  ", "\t", " \t "))

    def _words(self, *words: str) -> str:
        lead = self._blank() if self.rng.random() < 0.1 else ""
        trail = self._blank() if self.rng.random() < 0.1 else ""
        line = lead + self._blank().join(words) + trail
        if self.rng.random() < 0.05:
            line += " # " + self.rng.choice(("a comment", "x", "L 0 5", "ok"))
        return line

    def _letter(self, c: str) -> str:
        return c.lower() if self.rng.random() < 0.3 else c

    def _rj(self) -> int:
        return self.rng.randrange(self.n)

    def _turn(self, j: int, delta: int) -> list[int] | None:
        """An accepted `L j delta`: the commanded angle moves; the steps it must end on
        (None while the commanded angles are not known exactly)."""
        arm = self.arm
        target = None
        if arm.exact:
            new = list(arm.commanded)
            new[j] += delta
            target = [a.quantize_within_limits(v) for a, v in zip(arm.axes, new)]
        arm.commanded[j] += delta
        return target

    def _inside(self, j: int) -> tuple[int, int]:
        a = self.arm.axes[j]
        margin = VALID_MARGIN if self.arm.exact else VALID_MARGIN + 1000
        return a.min + margin, a.max - margin

    @staticmethod
    def _line(cls, text: str, expect, kind: str, **kw) -> FuzzLine:
        data = text.encode("latin-1") if isinstance(text, str) else text
        exp = None if expect is None else frozenset([expect] if isinstance(expect, str) else expect)
        return FuzzLine(cls=cls, data=data + b"\n", expect=exp, kind=kind, **kw)

    # -- the classes --
    def next(self) -> FuzzLine:
        if self.pending:
            return self.pending.pop(0)
        cls = self.rng.choices(self.classes, self.weights)[0]
        return getattr(self, "_" + cls)(cls)

    def _valid(self, cls: str, allow_moves: bool = True) -> FuzzLine:
        rng, arm = self.rng, self.arm
        r = rng.random()
        if not allow_moves:
            r = 0.9 + 0.1 * rng.random()
        if r < 0.40:  # L: a small relative move
            j = self._rj()
            lo, hi = self._inside(j)
            c = arm.commanded[j]
            delta = rng.randint(-8000, 8000)
            if rng.random() < 0.5:
                delta = delta // 10 * 10
            delta = max(lo - c, min(hi - c, delta))
            target = self._turn(j, delta)
            return self._line(cls, self._words(self._letter("L"), str(j), self._num(delta)), "ok", "L", moves=True,
                              target=target)
        if r < 0.55:  # M: near where the arm is, sometimes anywhere
            angles = []
            for j in range(self.n):
                lo, hi = self._inside(j)
                if rng.random() < 0.8:
                    c = arm.commanded[j]
                    lo, hi = max(lo, c - 15000), min(hi, c + 15000)
                angles.append(rng.randint(lo, hi) if lo < hi else lo)
            arm.commanded = angles
            arm.exact = True
            target = [a.quantize_within_limits(v) for a, v in zip(arm.axes, angles)]
            return self._line(cls, self._words(self._letter("M"), *(self._num(a) for a in angles)), "ok", "M",
                              moves=True, target=target)
        if r < 0.65:  # P: a point the tool reaches at angles inside the limits
            act = [rng.uniform(a.min / 1000 + 3, a.max / 1000 - 3) for a in arm.axes]
            x, y, z = self.robot.tool_from_actuators(act)
            dec = rng.choice((0, 1, 3))
            arm.exact = False  # the closed form's angles: taken from the status afterwards
            return self._line(cls, self._words(self._letter("P"), f"{x:.{dec}f}", f"{y:.{dec}f}", f"{z:.{dec}f}"),
                              "ok", "P", moves=True, estimate=True)
        if r < 0.72:
            v = rng.randint(0, 100000)
            return self._line(cls, self._words(self._letter("G"), fmt(v)), "ok", "G", moves=True)
        if r < 0.78:
            return self._line(cls, self._words(self._letter("S"), rng.choice("01")), "ok", "S", moves=True)
        if r < 0.80:
            arm.exact = False
            return self._line(cls, self._words(self._letter("H")), "ok", "H", moves=True, estimate=True)
        if r < 0.84:  # padded to exactly 64 bytes (a CR before the LF is not counted)
            j = self._rj()
            lo, hi = self._inside(j)
            c = arm.commanded[j]
            delta = max(lo - c, min(hi - c, rng.randint(-3000, 3000)))
            base = f"L {j} {fmt(delta)}"
            target = self._turn(j, delta)
            pad = MAX_LINE - len(base)
            text = base + (" " * pad if rng.random() < 0.5 else " #" + "x" * (pad - 2))
            if rng.random() < 0.5:
                text += "\r"
            return self._line(cls, text, "ok", "L padded to 64 bytes", moves=True, target=target)
        if r < 0.90:
            return self._line(cls, self._words(self._letter("I")), "ok", "I", info=True)
        if r < 0.94:
            return self._line(cls, self._words("$"), "ok", "$", listing=True)
        return self._line(cls, rng.choice(("# a comment", "#", "   # x", "#L 0 90", "# ? is realtime")).replace("?", ""),
                          "ok", "comment")

    def _random(self, cls: str) -> FuzzLine:
        rng = self.rng
        n = rng.choice((rng.randint(0, 20), rng.randint(0, 80)))
        if rng.random() < 0.5:
            pool = [b for b in range(256) if b != 0x0A and b not in REALTIME]
        else:
            pool = [b for b in range(0x20, 0x7F) if b not in REALTIME] + [0x09]
        return self._line(cls, bytes(rng.choice(pool) for _ in range(n)), None, "random bytes")

    def _overlong(self, cls: str) -> FuzzLine:
        rng = self.rng
        n = rng.choice((MAX_LINE + 1, MAX_LINE + 1, rng.randint(MAX_LINE + 1, 100), rng.randint(100, 300)))
        r = rng.random()
        if r < 0.5:  # a valid command, padded past the limit: must not run
            j = self._rj()
            base = rng.choice((f"L {j} 1", "M 0 90 0", f"L {j} -1", "G 50", "S 1", "H", "I", "$"))
            text = base + (" " * (n - len(base)) if rng.random() < 0.5 else " #" + "y" * (n - len(base) - 2))
            kind = "valid command padded past 64 bytes"
        elif r < 0.8:
            text = "".join(rng.choice("0123456789 .-LMPGS") for _ in range(n))
            kind = "printable"
        else:
            pool = [b for b in range(256) if b != 0x0A and b not in REALTIME]
            return self._line(cls, bytes(rng.choice(pool) for _ in range(n)), "error:7", "random bytes")
        return self._line(cls, text, "error:7", kind)

    BAD_NUMBERS = ["1e3", "1E3", "2e0", "e5", "1e", "1.2.3", "12a", "a12", ".", "-", "+", "+-1", "-+1", "--1", "++1",
                   "0x1F", "1,5", "1_000", "1/2", "(1)", "1..", "..1", "-.", "+.", "1-", "1+", "1000000.001",
                   "1000001", "99999999999999999999", "-1000000.0005", "0.5.", "1'", "\"1\"", "1;", "٣",
                   "1:2", "$1", "1%", "~1", "1 000"]

    def _bad_number(self) -> str:
        v = self.rng.choice(self.BAD_NUMBERS)
        return v.replace("٣", "x3")

    def _number(self, cls: str) -> FuzzLine:
        rng = self.rng
        bad = self._bad_number()
        expect = "error:3"
        r = rng.random()
        j = self._rj()
        if bad == "1 000":  # two words: L's third argument is one too many
            return self._line(cls, f"L {j} 1 000", "error:5", "L with a split number")
        if r < 0.35:
            return self._line(cls, self._words(self._letter("L"), str(j), bad), expect, "L bad number")
        if r < 0.6:
            args = [fmt(a) for a in self.arm.commanded]
            args[rng.randrange(self.n)] = bad
            return self._line(cls, self._words(self._letter("M"), *args), expect, "M bad number")
        if r < 0.8:
            args = ["200", "0", "150"]
            args[rng.randrange(3)] = bad
            return self._line(cls, self._words(self._letter("P"), *args), expect, "P bad number")
        if r < 0.9:
            return self._line(cls, self._words(self._letter("G"), bad), expect, "G bad number")
        return self._line(cls, f"${rng.choice((0, 1, 2, 4, 5))}={bad}", expect, "$ bad number")

    NANS = ["nan", "NaN", "NAN", "-nan", "inf", "-inf", "+inf", "Infinity", "-Infinity", "INF", "nan(0x1)", "1e309",
            "1e-400", "0x1p3", "1e+3"]

    def _nan(self, cls: str) -> FuzzLine:
        rng = self.rng
        bad = rng.choice(self.NANS)
        r = rng.random()
        j = self._rj()
        if r < 0.3:
            return self._line(cls, self._words(self._letter("L"), str(j), bad), "error:3", "L " + bad)
        if r < 0.55:
            args = [fmt(a) for a in self.arm.commanded]
            args[rng.randrange(self.n)] = bad
            return self._line(cls, self._words(self._letter("M"), *args), "error:3", "M " + bad)
        if r < 0.75:
            args = ["235", "0", "213"]
            args[rng.randrange(3)] = bad
            return self._line(cls, self._words(self._letter("P"), *args), "error:3", "P " + bad)
        if r < 0.85:
            return self._line(cls, self._words(self._letter("G"), bad), "error:3", "G " + bad)
        if r < 0.92:
            return self._line(cls, self._words(self._letter("S"), bad), "error:3", "S " + bad)
        return self._line(cls, f"${rng.choice((0, 1, 2, 4, 5))}={bad}", "error:3", "$ " + bad)

    def _joint(self, cls: str) -> FuzzLine:
        rng = self.rng
        bad = rng.choice([str(self.n), str(self.n + rng.randint(1, 5)), "99", "999", "255", "256", "1000", "0000",
                          "-1", "+1", "1.0", "1.", ".0", "x", "J1", "1e0", "-0", "0x0", "00000001"])
        return self._line(cls, self._words(self._letter("L"), bad, str(rng.randint(-20, 20))), "error:6",
                          "L bad joint " + bad)

    def _target(self, cls: str) -> FuzzLine:
        rng, arm = self.rng, self.arm
        r = rng.random()
        j = rng.randrange(self.n)
        a = arm.axes[j]
        c = arm.commanded[j]
        if r < 0.35:  # L beyond a limit: by a thousandth when the commanded angle is known exactly
            over = rng.choice((1, 1, 10, 500, 1000)) if arm.exact else 0
            over += rng.randint(1000 if not arm.exact else 0, 200000)
            delta = (a.max - c + over) if rng.random() < 0.5 else (a.min - c - over)
            return self._line(cls, self._words(self._letter("L"), str(j), fmt(delta)), "error:9", "L beyond a limit")
        if r < 0.42:  # the largest numbers: a commanded angle beyond 1,000,000 is error:8
            delta = rng.choice((1000000000, -1000000000, 999999999, -999999999))
            return self._line(cls, self._words("L", str(j), fmt(delta)), ("error:8", "error:9"), "L by a million")
        if r < 0.65:
            angles = [rng.randint(*self._inside(i)) for i in range(self.n)]
            over = rng.choice((1, 1000, rng.randint(1, 1000000), 1000000000 - max(abs(a.max), abs(a.min))))
            angles[j] = a.max + over if rng.random() < 0.5 else a.min - over
            angles[j] = max(-1000000000, min(1000000000, angles[j]))
            return self._line(cls, self._words(self._letter("M"), *(fmt(v) for v in angles)), "error:9",
                              "M beyond a limit")
        if r < 0.8:
            ang = rng.uniform(0, 2 * math.pi)
            radius = rng.choice((rng.uniform(500, 2000), rng.uniform(2000, 999999)))
            z = rng.uniform(-1000, 1000)
            pts = [f"{radius * math.cos(ang):.3f}", f"{radius * math.sin(ang):.3f}", f"{z:.3f}"]
            if rng.random() < 0.2:  # behind the base, within reach of the links but not of the base's range
                pts = ["-235", "0", "213"]
            return self._line(cls, self._words(self._letter("P"), *pts), "error:10", "P out of reach")
        if r < 0.92:
            v = rng.choice((100001, 100500, 101000, rng.randint(100001, 1000000000), -1, -500, -rng.randint(1, 1000000)))
            return self._line(cls, self._words(self._letter("G"), fmt(v)), "error:8", "G out of range")
        return self._line(cls, self._words(self._letter("S"), str(rng.randint(2, 9))), "error:8", "S out of range")

    def _args(self, cls: str) -> FuzzLine:
        rng = self.rng
        n = self.n
        choices = [
            (["L"], "error:4"), (["L", "0"], "error:4"), (["M"] + ["0"] * (n - 1), "error:4"), (["M"], "error:4"),
            (["P", "1", "2"], "error:4"), (["G"], "error:4"), (["S"], "error:4"),
            (["L", "0", "1", "2"], "error:5"), (["M"] + ["0"] * (n + 1), "error:5"), (["P", "1", "2", "3", "4"], "error:5"),
            (["G", "1", "2"], "error:5"), (["S", "1", "1"], "error:5"), (["H", "1"], "error:5"), (["Z", "0"], "error:5"),
            (["I", "x"], "error:5"), (["$", "1=5", "6"], "error:5"),
        ]
        words, expect = rng.choice(choices)
        words = [self._letter(words[0])] + words[1:]
        return self._line(cls, self._words(*words), expect, "arguments " + " ".join(words))

    def _unknown(self, cls: str) -> FuzzLine:
        rng = self.rng
        r = rng.random()
        if r < 0.6:
            w = self._letter(rng.choice(UNKNOWN_LETTERS))
        elif r < 0.8:
            w = rng.choice(("G1", "LL", "L0", "M0", "HOME", "Hi", "IZ", "SS", "P1", "Z0", "ok", "error:1"))
        else:
            w = rng.choice(("5", "%", "-L", "+", "*", "@", "[", "<Idle>", "0", "=", ".", "~", "\\", "/"))
        args = [str(rng.randint(-99, 99)) for _ in range(rng.randint(0, 3))]
        return self._line(cls, self._words(w, *args), "error:2", "unknown command " + w)

    def _control(self, cls: str) -> FuzzLine:
        rng = self.rng
        inner = self._valid(cls, allow_moves=False) if rng.random() < 0.5 else self._unknown(cls)
        body = inner.data[:-1].split(b"#")[0].rstrip(b"\r")  # the bad byte goes outside any comment
        if not body.strip():
            body = b"I"
        bad = rng.choice([b for b in range(0x20)] + [0x7F] + list(range(0x80, 0x100)))
        if bad == 0x0A:
            bad = 0x0D
        if bad == 0x09:  # a tab is allowed
            bad = 0x7F
        pos = rng.randint(0, len(body))
        data = body[:pos] + bytes([bad]) + body[pos:]
        if bad == 0x0D and pos == len(body):
            data += b"\r"  # a second CR before the LF: still error:11
        return self._line(cls, data[:MAX_LINE], "error:11", f"byte 0x{bad:02X}")

    def _empty(self, cls: str) -> FuzzLine:
        return self._line(cls, self.rng.choice(("", " ", "\t", "   ", " \t ", "\r", "  \r")), "error:1", "empty")

    BAD_SETTINGS = [("$x=1", 13), ("$=5", 13), ("$1000=1", 13), ("$-1=1", 13), ("$$", 13), ("$8=1", 13),
                    ("$9=1", 13), ("$99=0", 13), ("$1=", 4), ("$1", 4), ("$1 =5", 4), ("$ 1", 4), ("$1=abc", 3),
                    ("$1=5=6", 3), ("$1=nan", 3), ("$0=inf", 3), ("$1=5 6", 5), ("$0=0", 8), ("$0=4001", 8),
                    ("$0=600.5", 8), ("$0=-5", 8), ("$1=0", 8), ("$1=100001", 8), ("$2=60001", 8), ("$2=-1", 8),
                    ("$3=8", 8), ("$3=-1", 8), ("$3=0.5", 8), ("$4=0", 8), ("$4=4001", 8), ("$5=10001", 8),
                    ("$5=-0.001", 8), ("$0=1000000", 8), ("$5=0.001", 8)]

    def _settings(self, cls: str) -> FuzzLine:
        rng = self.rng
        if rng.random() < 0.1:  # a good one, and the next line puts the value back
            n = rng.choice((2, 4))
            v = rng.randint(0, 60000) if n == 2 else rng.randint(1, 4000)
            old = SETTING_DEFAULTS[n]
            txt = f"${n}={v}" + (".000" if rng.random() < 0.3 else "")
            self.pending.append(self._line(cls, f"${n}={old}", "ok", "setting put back", setting=(n, old)))
            return self._line(cls, txt, "ok", "setting", setting=(n, v))
        text, code = rng.choice(self.BAD_SETTINGS)
        if rng.random() < 0.3 and text[1:2].isdigit():
            text = "$ " + text[1:]  # `$ 1=5` is `$1=5`
        return self._line(cls, text, f"error:{code}", "setting " + text)

    def _realtime(self, cls: str) -> FuzzLine:
        rng = self.rng
        r = rng.random()
        q, bang = (1, False) if r < 0.65 else (0, True) if r < 0.85 else (1, True)
        if bang:  # at rest, '!' makes the commanded angles those of the steps: before the line runs
            self.arm.rederive(self.arm.steps)
        inner_cls = rng.choices([c for c, _ in self.WEIGHTS if c not in ("realtime", "stop", "settings")],
                                [w for c, w in self.WEIGHTS if c not in ("realtime", "stop", "settings")])[0]
        inner = getattr(self, "_" + inner_cls)(inner_cls)
        body = bytearray(inner.data[:-1])
        for b in ([ord("?")] * q) + ([ord("!")] if bang else []):
            body.insert(rng.randint(0, len(body)), b)
        inner.cls = cls
        inner.kind = f"{inner_cls}: {inner.kind}"
        inner.data = bytes(body) + b"\n"
        inner.queries, inner.stop = q, bang
        return inner

    def _burst(self, cls: str) -> FuzzLine:
        """Fourteen short moves of one motor, there and back, streamed as GRBL's senders stream
        (the next line as soon as the last is answered), so the queue (12 places) fills; then
        D, held until there is room and answered ok (it was error:255). The arm ends where it
        began."""
        arm = self.arm
        j = self._rj()
        lo, hi = self._inside(j)
        d = self.rng.choice([1000, 2000, 3000])
        if arm.commanded[j] + d > hi:
            d = -d
        if not lo <= arm.commanded[j] + d <= hi:
            return self._valid("valid")
        lines = [f"L {j} {fmt(d if k % 2 == 0 else -d)}\n".encode() for k in range(14)]
        target = list(arm.steps) if arm.exact else None
        wait = self.rng.choice(["D 0.2", "D 0", "D 0.05"])
        return self._line(cls, wait, "ok", f"14 moves streamed, then {wait} held for room", moves=True,
                          target=target, burst=lines)

    def _stop(self, cls: str) -> FuzzLine:
        """A long M, then '!' mid-move."""
        arm = self.arm
        angles = []
        for j, a in enumerate(arm.axes):
            lo, hi = self._inside(j)
            far = hi if abs(hi - arm.commanded[j]) > abs(lo - arm.commanded[j]) else lo
            angles.append(far)
        target = [a.quantize_within_limits(v) for a, v in zip(arm.axes, angles)]
        start = list(arm.steps)
        arm.exact = False  # the '!' decides: rederived from the status at rest
        return self._line(cls, "M " + " ".join(fmt(v) for v in angles), "ok", "M then ! mid-move", moves=True,
                          target=target, stop_after=True, start=start)


# ---------------------------------------------------------------------------------------
# The checker: one line's transcript against the protocol.

@dataclass
class Exchange:
    """What came back for one line: every line from the arm from sending it up to the
    status report that ends its check, the reports the fuzz asked for itself (`polls`), the
    status before and after, and the pins (rows seen, decoded positions) before and after."""
    received: list[str] = field(default_factory=list)
    polls: int = 0
    before: Status | None = None
    after: Status | None = None
    pins_before: tuple[int, list[int]] | None = None
    pins_after: tuple[int, list[int]] | None = None
    coil_faults: list[str] = field(default_factory=list)
    coil_moves: int = 0  # coil events other than the idle release ($5), while the line ran
    timeout: str = ""
    vanished: str = ""
    first_report: bool = False  # the run's first status report is in `received` (W:14 allowed)


@dataclass
class Finding:
    kind: str        # replies, reply, reset, hang, motion, pins, steps, reports, unexpected, coil, vanished
    index: int       # the line's number in the run (1-based)
    line: FuzzLine
    message: str

    def describe(self) -> str:
        return f"line {self.index} ({self.line.cls}, {self.line.kind}) b'{self.line.text()}': {self.kind}: {self.message}"


def is_reply(text: str) -> bool:
    if text == "ok":
        return True
    if text.startswith("error:"):
        code = text[6:]
        return code.isdigit()
    return False


def check(index: int, line: FuzzLine, ex: Exchange) -> tuple[str | None, list[Finding]]:
    """The reply (None when there was none) and every way the exchange breaks the protocol."""
    out: list[Finding] = []

    def bad(kind: str, msg: str) -> None:
        out.append(Finding(kind, index, line, msg))

    if ex.vanished:
        bad("vanished", ex.vanished)
    if ex.timeout:
        bad("hang", ex.timeout)
    replies = [t for t in ex.received if is_reply(t)]
    reply = replies[0] if replies else None
    if len(replies) != 1 and not ex.timeout and not ex.vanished:
        bad("replies", f"{len(replies)} replies ({', '.join(replies) or 'none'}), the protocol says exactly one")
    reports = 0
    infos = settings = 0
    for t in ex.received:
        if is_reply(t):
            continue
        st = parse_status(t)
        if st is not None:
            reports += 1
            if st.warning == 14 and not (ex.first_report and reports == 1):
                bad("reset", f"settings reset to defaults (W:14) after the first report: the firmware started "
                             f"again ({t})")
            continue
        info = parse_info(t)
        if info is not None:
            infos += 1
            if not line.info or infos > 1:
                bad("reset", f"an info line nobody asked for: the firmware started again? ({t})")
            elif info.warning == 14:
                bad("reset", f"settings reset to defaults (W:14) in an info line ({t})")
            continue
        if t.startswith("$") and parse_setting(t) is not None and line.listing:
            settings += 1
            continue
        bad("unexpected", f"a line the protocol does not send here: '{t}'")
    if line.listing and reply == "ok" and settings != len(SETTING_DEFAULTS):
        bad("unexpected", f"{settings} setting lines for `$`, {len(SETTING_DEFAULTS)} expected")
    if line.info and reply == "ok" and infos != 1:
        bad("unexpected", f"{infos} info lines for `I`, 1 expected")
    expected_reports = line.queries + ex.polls
    if not ex.timeout and not ex.vanished and reports != expected_reports:
        bad("reports", f"{reports} status reports for {line.queries} '?' in the line and {ex.polls} sent after it")
    if reply is not None and line.expect is not None and reply not in line.expect:
        bad("reply", f"reply {reply}, the protocol says {' or '.join(sorted(line.expect))}")

    b, a = ex.before, ex.after
    if a is not None and b is not None and a.steps is not None and b.steps is not None:
        if reply is not None and reply != "ok" and a.steps != b.steps:
            bad("motion", f"a rejected line ({reply}) moved the motors: steps {b.steps} -> {a.steps}")
        if line.moves and reply == "ok" and line.target is not None and not line.stop_after and a.steps != line.target:
            bad("steps", f"the move ended on steps {a.steps}, the protocol's rounding gives {line.target}")
        if line.stop_after and reply == "ok" and line.start is not None and line.target is not None:
            for i, (s0, s, t) in enumerate(zip(line.start, a.steps, line.target)):
                if not min(s0, t) <= s <= max(s0, t):
                    bad("steps", f"after ! motor {i} is on step {s}, off the move from {s0} to {t}")
        if a.state not in ("Idle", "Alarm") and not ex.timeout:
            bad("hang", f"not at rest after the line: {a.text}")
    if ex.pins_before is not None and ex.pins_after is not None:
        rows0, _ = ex.pins_before
        rows1, pins = ex.pins_after
        # (the coils' release after $5 ms at rest may fall in any line's time: not the line's doing)
        if reply is not None and reply != "ok" and ex.coil_moves:
            bad("motion", f"a rejected line ({reply}) changed the coils: {ex.coil_moves} coil event(s)")
        if a is not None and a.steps is not None and pins != a.steps:
            bad("pins", f"the pins say the motors are on steps {pins}, the status report {a.steps}")
    for f in ex.coil_faults:
        bad("coil", f)
    return reply, out


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


class LineReader:
    """Lines from the arm with a deadline: select() on the port's file descriptor where it
    has one (a POSIX serial port or pseudo-terminal: no termios call per read, which halves
    the time of a short exchange), else the Link's own read_line. Raises LinkTimeout and
    LinkVanished as the Link does."""

    def __init__(self, link: Link):
        self.link = link
        self.buf = b""
        try:
            self.fd = link.port.fileno()
        except (AttributeError, OSError, ValueError):
            self.fd = None
        if self.fd is not None:
            link._buf, self.buf = b"", link._buf  # (whatever the Link had read ahead)

    def read_line(self, deadline: float) -> str:
        if self.fd is None:
            return self.link.read_line(deadline)
        while b"\n" not in self.buf:
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                raise LinkTimeout("no answer", self.buf.decode("ascii", errors="replace"))
            try:
                ready, _, _ = select.select([self.fd], [], [], min(remaining, 0.1))
                data = os.read(self.fd, 4096) if ready else None
            except (OSError, ValueError) as e:
                raise LinkVanished(str(e) or type(e).__name__) from None
            if data:
                self.buf += data
            elif data == b"" or not self.link.alive():
                raise LinkVanished("the device at its other end is gone")
        raw, _, self.buf = self.buf.partition(b"\n")
        return raw.decode("ascii", errors="replace").rstrip("\r")

    def drain(self, seconds: float) -> None:
        end = time.monotonic() + seconds
        try:
            while True:
                self.read_line(end)
        except LinkTimeout:
            self.buf = b""


class Fuzzer:
    """Runs the lines over a Link. `pins()` returns (rows, positions) of the virtual Nano's
    trace (None on a real port); `coil_events(rows_from, rows_to)` those rows (trace.TraceRow)."""

    def __init__(self, link: Link, robot: Robot, seed: int, *, pins=None, coil_events=None, timeout: float = 5.0,
                 poll: float = 0.002, progress=None, bursts: bool = False):
        self.link = link
        self.reader = LineReader(link)
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
        t = self.reader.read_line(deadline)
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
                if st.state in ("Idle", "Alarm") or time.monotonic() > run_deadline:
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
            self.reader.drain(0.3)
            e = Exchange()
            self.status = self._poll_status(e)
            self.gen.arm.rederive(self.status.steps)
            return True
        except (LinkTimeout, LinkVanished):
            return False


def report_doc(summary: Summary, seed: int, target: str, command_line: str) -> dict:
    return {"seed": seed, "target": target, "command": command_line, "summary": summary.figures(),
            "findings": [{"kind": f.kind, "line": f.index, "class": f.line.cls, "what": f.line.kind,
                          "bytes": f.line.text(), "message": f.message} for f in summary.findings],
            "vnano": summary.vnano}


def run_fuzz(args, robot: Robot, vnano: str | None, elf: str | None, command_line: str) -> int:
    """The `fuzz` sub-command (cli.py finds the binaries)."""
    from .targets import SerialTarget, VirtualNanoTarget

    tmp = None
    if args.port:
        target = SerialTarget(args.port, boot_wait=args.boot_wait)
        out_dir = Path(tempfile.mkdtemp(prefix="articula-fuzz-"))
    else:
        grip = (robot.servo_closed, robot.servo_open) if robot.servo_closed is not None and \
            robot.servo_open is not None else None
        target = VirtualNanoTarget(vnano, elf, len(robot.motors), gripper=grip, half_step=robot.half_step_motors)
        tmp = tempfile.TemporaryDirectory(prefix="articula-fuzz-")
        out_dir = Path(tmp.name)
    summary = Summary()
    try:
        link = target.start_plan("fuzz", out_dir)
        pins = coil_events = None
        if target.trace is not None:
            trace = target.trace

            def pins():
                return trace.sync()

            def coil_events(a, b):
                return trace.rows[a:b]

        progress = _progress_printer(args.lines) if not args.no_progress else None
        fz = Fuzzer(link, robot, args.seed, pins=pins, coil_events=coil_events, timeout=args.timeout,
                    progress=progress, bursts=getattr(args, "bursts", False))
        try:
            fz.start(restore_settings=bool(args.port))
            summary = fz.run(args.lines)
        except (LinkTimeout, LinkVanished) as e:
            summary = fz.summary
            summary.aborted = summary.aborted or f"{e}"
        fz.finish()
        if progress:
            progress(None, None)
    finally:
        rep = target.end_plan()
        target.close()
    if rep is not None:
        motors = rep.get("motors") or []
        summary.vnano = {"exit": rep.get("_exit"), "steps": [m.get("steps") for m in motors],
                         "coil_faults": sum(m.get("faults", 0) for m in motors)}
        if summary.pins_end is not None and summary.vnano["steps"] != summary.pins_end:
            summary.findings.append(Finding("pins", summary.lines, FuzzLine("end", b"", None, "end of run"),
                                            f"the virtual Nano's report says steps {summary.vnano['steps']}, the "
                                            f"trace {summary.pins_end}"))
        if summary.vnano["coil_faults"]:
            summary.findings.append(Finding("coil", summary.lines, FuzzLine("end", b"", None, "end of run"),
                                            f"{summary.vnano['coil_faults']} coil fault(s) in the virtual Nano's report"))
    if tmp is not None:
        tmp.cleanup()
    print(summary.text())
    if args.report:
        Path(args.report).write_text(json.dumps(report_doc(summary, args.seed, "serial port " + args.port if args.port
                                                           else "virtual Nano", command_line), indent=1) + "\n")
        print(f"  report: {args.report}")
    return 0 if summary.ok else 1


def _progress_printer(total: int):
    import sys

    state = {"last": 0.0}
    tty = sys.stderr.isatty()

    def show(i, n):
        if i is None:
            if tty:
                sys.stderr.write("\n")
            return
        now = time.monotonic()
        if now - state["last"] < 0.5 and i != n:
            return
        state["last"] = now
        msg = f"fuzz: {i}/{n} lines"
        if tty:
            sys.stderr.write("\r" + msg)
        elif i == n or i % 1000 == 0:
            sys.stderr.write(msg + "\n")
        sys.stderr.flush()

    return show
