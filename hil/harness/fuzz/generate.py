"""The fuzz's lines: the classes of valid, malformed and hostile lines, seeded, each with the
reply the protocol fixes for it, and a model of the arm (its commanded angles, the steps the
protocol's rounding gives) that says what a valid line must do."""

from __future__ import annotations

import math
import random
from dataclasses import dataclass, field
from fractions import Fraction

import articula
from articula.link import Status
from ..randplan import millis_text as fmt
from ..robot import Robot

RUN_SETTINGS = {0: 4000, 1: 100000, 5: 0}
# The firmware's settings and their defaults: shared/articula/settings.h, through the bindings.
SETTING_DEFAULTS = {n: default for n, (_lo, _hi, default) in articula._core._settings_table.items()}
UNKNOWN_LETTERS = [c for c in "ABCEFJKQRUVXY"]  # (O and W are commands since protocol 5)
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
            return self._line(cls, bytes(rng.choice(pool) for _ in range(n)), articula.REPLY["LineTooLong"], "random bytes")
        return self._line(cls, text, articula.REPLY["LineTooLong"], kind)

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
        expect = articula.REPLY["BadNumber"]
        r = rng.random()
        j = self._rj()
        if bad == "1 000":  # two words: L's third argument is one too many
            return self._line(cls, f"L {j} 1 000", articula.REPLY["ExtraArgument"], "L with a split number")
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
            return self._line(cls, self._words(self._letter("L"), str(j), bad), articula.REPLY["BadNumber"], "L " + bad)
        if r < 0.55:
            args = [fmt(a) for a in self.arm.commanded]
            args[rng.randrange(self.n)] = bad
            return self._line(cls, self._words(self._letter("M"), *args), articula.REPLY["BadNumber"], "M " + bad)
        if r < 0.75:
            args = ["235", "0", "213"]
            args[rng.randrange(3)] = bad
            return self._line(cls, self._words(self._letter("P"), *args), articula.REPLY["BadNumber"], "P " + bad)
        if r < 0.85:
            return self._line(cls, self._words(self._letter("G"), bad), articula.REPLY["BadNumber"], "G " + bad)
        if r < 0.92:
            return self._line(cls, self._words(self._letter("S"), bad), articula.REPLY["BadNumber"], "S " + bad)
        return self._line(cls, f"${rng.choice((0, 1, 2, 4, 5))}={bad}", articula.REPLY["BadNumber"], "$ " + bad)

    def _joint(self, cls: str) -> FuzzLine:
        rng = self.rng
        bad = rng.choice([str(self.n), str(self.n + rng.randint(1, 5)), "99", "999", "255", "256", "1000", "0000",
                          "-1", "+1", "1.0", "1.", ".0", "x", "J1", "1e0", "-0", "0x0", "00000001"])
        return self._line(cls, self._words(self._letter("L"), bad, str(rng.randint(-20, 20))), articula.REPLY["BadJoint"],
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
            return self._line(cls, self._words(self._letter("L"), str(j), fmt(delta)), articula.REPLY["JointLimit"], "L beyond a limit")
        if r < 0.42:  # the largest numbers: a commanded angle beyond 1,000,000 is error:8
            delta = rng.choice((1000000000, -1000000000, 999999999, -999999999))
            return self._line(cls, self._words("L", str(j), fmt(delta)), (articula.REPLY["ValueOutOfRange"], articula.REPLY["JointLimit"]), "L by a million")
        if r < 0.65:
            angles = [rng.randint(*self._inside(i)) for i in range(self.n)]
            over = rng.choice((1, 1000, rng.randint(1, 1000000), 1000000000 - max(abs(a.max), abs(a.min))))
            angles[j] = a.max + over if rng.random() < 0.5 else a.min - over
            angles[j] = max(-1000000000, min(1000000000, angles[j]))
            return self._line(cls, self._words(self._letter("M"), *(fmt(v) for v in angles)), articula.REPLY["JointLimit"],
                              "M beyond a limit")
        if r < 0.8:
            ang = rng.uniform(0, 2 * math.pi)
            radius = rng.choice((rng.uniform(500, 2000), rng.uniform(2000, 999999)))
            z = rng.uniform(-1000, 1000)
            pts = [f"{radius * math.cos(ang):.3f}", f"{radius * math.sin(ang):.3f}", f"{z:.3f}"]
            if rng.random() < 0.2:  # behind the base, within reach of the links but not of the base's range
                pts = ["-235", "0", "213"]
            return self._line(cls, self._words(self._letter("P"), *pts), articula.REPLY["Unreachable"], "P out of reach")
        if r < 0.92:
            v = rng.choice((100001, 100500, 101000, rng.randint(100001, 1000000000), -1, -500, -rng.randint(1, 1000000)))
            return self._line(cls, self._words(self._letter("G"), fmt(v)), articula.REPLY["ValueOutOfRange"], "G out of range")
        return self._line(cls, self._words(self._letter("S"), str(rng.randint(2, 9))), articula.REPLY["ValueOutOfRange"], "S out of range")

    def _args(self, cls: str) -> FuzzLine:
        rng = self.rng
        n = self.n
        choices = [
            (["L"], articula.REPLY["MissingArgument"]), (["L", "0"], articula.REPLY["MissingArgument"]), (["M"] + ["0"] * (n - 1), articula.REPLY["MissingArgument"]), (["M"], articula.REPLY["MissingArgument"]),
            (["P", "1", "2"], articula.REPLY["MissingArgument"]), (["G"], articula.REPLY["MissingArgument"]), (["S"], articula.REPLY["MissingArgument"]),
            (["L", "0", "1", "2"], articula.REPLY["ExtraArgument"]), (["M"] + ["0"] * (n + 1), articula.REPLY["ExtraArgument"]), (["P", "1", "2", "3", "4"], articula.REPLY["ExtraArgument"]),
            (["G", "1", "2"], articula.REPLY["ExtraArgument"]), (["S", "1", "1"], articula.REPLY["ExtraArgument"]), (["H", "1"], articula.REPLY["ExtraArgument"]), (["Z", "0"], articula.REPLY["ExtraArgument"]),
            (["I", "x"], articula.REPLY["ExtraArgument"]), (["$", "1=5", "6"], articula.REPLY["ExtraArgument"]),
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
            w = rng.choice(("G1", "LL", "L0", "M0", "HOME", "Hi", "IZ", "SS", "P1", "Z0", "ok", articula.REPLY["EmptyLine"]))
        else:
            w = rng.choice(("5", "%", "-L", "+", "*", "@", "[", "<Idle>", "0", "=", ".", "~", "\\", "/"))
        args = [str(rng.randint(-99, 99)) for _ in range(rng.randint(0, 3))]
        return self._line(cls, self._words(w, *args), articula.REPLY["UnknownCommand"], "unknown command " + w)

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
        return self._line(cls, data[:MAX_LINE], articula.REPLY["BadCharacter"], f"byte 0x{bad:02X}")

    def _empty(self, cls: str) -> FuzzLine:
        return self._line(cls, self.rng.choice(("", " ", "\t", "   ", " \t ", "\r", "  \r")), articula.REPLY["EmptyLine"], "empty")

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
