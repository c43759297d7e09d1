"""Random plans: `--random N --seed S`.

N commands, the same N for the same seed and robot file: L (relative, within the limits
from the commanded angle the arm will have), M (absolute, within the limits), P (a point the
tool reaches at random motor angles 2 degrees inside the limits), G (0 to 100 %), and about
one in ten that the arm must refuse, each marked `#@ expect error:N`:

    L beyond a limit       error:9     M with one angle beyond a limit   error:9
    P out of reach         error:10    G above 100 or below 0            error:8
    L on a joint it lacks  error:6     a number with an exponent         error:3

Numbers have 0 to 3 decimals (the protocol keeps thousandths). The generator follows the
commanded angles exactly, in thousandths of a degree, as the firmware does; after a P it
takes them from the prediction (`articula.Robot.predict`: the firmware's closed-form
solution, rounded to thousandths), so every later L is valid to the thousandth.
"""

from __future__ import annotations

import math
import random
from pathlib import Path

import articula

from .prediction import predict_plan
from .robot import Robot

P_MARGIN_DEG = 2.0


def millis_text(millis: int) -> str:
    """A value in thousandths as a protocol line writes it (`articula.protocol_number`, the
    firmware's own number writer): no trailing zeros, so a value with fewer decimals has fewer."""
    return articula.protocol_number(millis / 1000)


def _random_millis(rng: random.Random, lo: int, hi: int) -> tuple[int, int]:
    """A value in [lo, hi] (thousandths) with a random number of decimals: (millis, decimals)."""
    decimals = rng.choice((0, 0, 1, 1, 2, 3))
    step = 10 ** (3 - decimals)
    a, b = -((-lo) // step), hi // step  # multiples of step within [lo, hi]
    if a > b:
        return lo, 3
    return rng.randint(a, b) * step, decimals


def generate(robot: Robot, n: int, seed: int) -> str:
    rng = random.Random(seed)
    motors = robot.motors
    lo = [round(m.min * 1000) for m in motors]
    hi = [round(m.max * 1000) for m in motors]
    cmd = [round(m.zero * 1000) for m in motors]  # commanded angles, thousandths
    head = [
        f"# Random plan: {n} commands, seed {seed}, robot {robot.name}",
        "# (python -m hil.harness run --random N --seed S). Valid L, M, P",
        "# and G within the limits, and about one in ten commands the",
        "# arm must refuse (each marked #@ expect).",
        f"#@ title Random plan, {n} commands, seed {seed}",
    ]
    body: list[str] = []
    state_lines: list[str] = []  # the lines that can change the arm's state (for predict)

    def sync_after_p():
        # The commanded angles the firmware's closed form gives: from the prediction.
        preds, _ = predict_plan(robot, Path("random.arm"), None, lines=list(state_lines))
        last = preds[max(preds)]
        for i, a in enumerate(last.commanded_deg):
            cmd[i] = round(a * 1000)

    for _ in range(n):
        r = rng.random()
        if r < 0.10:
            kind = rng.choice(("L-limit", "M-limit", "P-far", "G-range", "L-joint", "number"))
            if kind == "L-limit":
                j = rng.randrange(len(motors))
                over = rng.randint(1, 40) * 1000 + rng.choice((0, 500))
                delta = (hi[j] - cmd[j] + over) if rng.random() < 0.5 else (lo[j] - cmd[j] - over)
                body += ["#@ expect error:9", f"L {j} {millis_text(delta)}"]
            elif kind == "M-limit":
                angles = [_random_millis(rng, lo[i], hi[i]) for i in range(len(motors))]
                j = rng.randrange(len(motors))
                angles[j] = (hi[j] + rng.randint(1, 30) * 1000, 0) if rng.random() < 0.5 else \
                    (lo[j] - rng.randint(1, 30) * 1000, 0)
                body += ["#@ expect error:9", "M " + " ".join(millis_text(a) for a, _ in angles)]
            elif kind == "P-far":
                ang = rng.uniform(0, 2 * math.pi)
                radius = rng.uniform(500, 900)
                body += ["#@ expect error:10",
                         f"P {radius * math.cos(ang):.1f} {radius * math.sin(ang):.1f} {rng.uniform(-300, 600):.1f}"]
            elif kind == "G-range":
                v = rng.choice((rng.randint(101, 250), -rng.randint(1, 50)))
                body += ["#@ expect error:8", f"G {v}"]
            elif kind == "L-joint":
                body += ["#@ expect error:6", f"L {len(motors) + rng.randint(0, 5)} {rng.randint(-20, 20)}"]
            else:
                body += ["#@ expect error:3", f"L {rng.randrange(len(motors))} {rng.randint(1, 9)}e{rng.randint(0, 2)}"]
        elif r < 0.45:
            j = rng.randrange(len(motors))
            # Mostly moderate moves, sometimes across the whole range.
            span_lo, span_hi = lo[j] - cmd[j], hi[j] - cmd[j]
            if rng.random() < 0.7:
                span_lo, span_hi = max(span_lo, -30000), min(span_hi, 30000)
            delta, dec = _random_millis(rng, span_lo, span_hi)
            cmd[j] += delta
            body.append(f"L {j} {millis_text(delta)}")
            state_lines.append(body[-1])
        elif r < 0.70:
            angles = [_random_millis(rng, lo[i], hi[i]) for i in range(len(motors))]
            for i, (a, _) in enumerate(angles):
                cmd[i] = a
            body.append("M " + " ".join(millis_text(a) for a, _ in angles))
            state_lines.append(body[-1])
        elif r < 0.88:
            act = [rng.uniform(m.min + P_MARGIN_DEG, m.max - P_MARGIN_DEG) for m in motors]
            x, y, z = robot.tool_from_actuators(act)
            dec = rng.choice((0, 1, 3))
            body.append(f"P {x:.{dec}f} {y:.{dec}f} {z:.{dec}f}")
            state_lines.append(body[-1])
            sync_after_p()
        else:
            v, dec = _random_millis(rng, 0, 100000)
            body.append(f"G {millis_text(v)}")
    return "\n".join(head + body) + "\n"
