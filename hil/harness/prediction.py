"""The host's prediction of a plan: `articula.Robot.predict` (the firmware on its virtual clock, as
host/lib/predict.h, the same as `articula predict --json`), in process.

The prediction checks a whole program before it runs it and refuses one with a line the
protocol's parser rejects (`L 0 1e3`, `G 150`, a line over 64 bytes): the arm answers such a
line with its error and changes nothing. So when the prediction names a line it cannot parse,
the harness asks `Robot.quantize` (the same parser) for that line's error code, blanks the
line (the line numbers stay) and predicts again; the line's prediction is then that error
reply with nothing changed.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import articula

from .robot import Robot


class PredictError(Exception):
    pass


@dataclass
class Prediction:
    line: int
    command: str
    reply: str                       # "ok" or "error:N"
    steps: list[int]                 # motor steps after the command
    actuator_deg: list[float]        # the angles the steps give
    commanded_deg: list[float]
    joints: list[float]              # joint values of the steps
    tool_ideal: list[float]          # tool position of the commanded angles
    tool_quantized: list[float]      # tool position of the steps
    error_mm: float                  # |quantized - ideal|
    seconds: float                   # the action's duration (0: nothing queued)
    queued: bool
    gripper_percent: int | None
    dominant_steps: int = 0
    target_mm: list[float] | None = None
    target_error_mm: float | None = None
    note: str = ""
    codec_rejected: bool = False     # refused by the parser (predicted by quantize)
    raw: dict = field(default_factory=dict, repr=False)


def settings_arg(settings: dict[int, float]) -> str:
    return ",".join(f"{n}={int(v) if float(v).is_integer() else v}" for n, v in sorted(settings.items()))


def quantize_code(robot: Robot, line: str) -> int:
    """The error code the protocol's parser gives a line (0 when it parses)."""
    return int(robot.model.quantize([line])[0].code)


def predict_plan(robot: Robot, plan_path: Path, settings: dict[int, float] | None,
                 lines: list[str] | None = None) -> tuple[dict[int, Prediction], dict]:
    """Predicts every command line of a plan. Returns {plan line: Prediction} and the
    prediction's top-level fields (settings, summary)."""
    if lines is None:
        lines = plan_path.read_text(encoding="ascii", errors="surrogateescape").splitlines()
    lines = list(lines)
    codec: dict[int, int] = {}
    # Named as the plan is (the name picks the language), always a protocol program.
    name = str(plan_path.with_suffix(".arm"))
    for _ in range(len(lines) + 1):
        text = ("\n".join(lines) + "\n").encode("ascii", errors="surrogateescape")
        program = articula.Program.parse(text, name)
        try:
            doc = robot.model.predict(program, settings=settings_arg(settings) if settings else None).to_dict()
            break
        except articula.ProgramError as e:
            n = e.line
            if n in codec or not 1 <= n <= len(lines):
                raise PredictError(f"articula predict: {e}") from None
            code = quantize_code(robot, lines[n - 1])
            if code == 0:
                raise PredictError(f"{plan_path}:{n}: the prediction refuses a line the parser accepts: {e}") from None
            codec[n] = code
            lines[n - 1] = "#"
        except ValueError as e:
            raise PredictError(f"articula predict: {e}") from None
    else:
        raise PredictError("articula predict: too many lines refused")

    out: dict[int, Prediction] = {}
    for r in doc["records"]:
        reply = "ok" if r["reply"] == "ok" else f"error:{r['code']}"
        out[r["line"]] = Prediction(
            line=r["line"], command=r["command"], reply=reply, steps=list(r["steps"]),
            actuator_deg=list(r["actuator_deg"]), commanded_deg=list(r["commanded_deg"]),
            joints=list(r["joints"]), tool_ideal=list(r["tool_ideal_mm"]),
            tool_quantized=list(r["tool_quantized_mm"]), error_mm=float(r["error_mm"]),
            seconds=float(r["seconds"]), queued=bool(r.get("queued")), gripper_percent=r.get("gripper_percent"),
            dominant_steps=int(r.get("dominant_steps", 0)), target_mm=r.get("target_mm"),
            target_error_mm=r.get("target_error_mm"), note=r.get("note", ""), raw=r)

    # Lines the parser refuses: an error reply, the state of the command before them.
    if codec:
        zero = robot.zero_angles
        tool0 = list(robot.tool_from_actuators(zero))
        state = Prediction(line=0, command="", reply="ok", steps=[0] * len(zero), actuator_deg=list(zero),
                           commanded_deg=list(zero), joints=robot.joints_from_actuators(zero), tool_ideal=tool0,
                           tool_quantized=tool0, error_mm=0.0, seconds=0.0, queued=False, gripper_percent=None)
        for n in range(1, len(lines) + 1):
            if n in out:
                state = out[n]
            elif n in codec:
                out[n] = Prediction(
                    line=n, command=lines_original(plan_path, n), reply=f"error:{codec[n]}", steps=list(state.steps),
                    actuator_deg=list(state.actuator_deg), commanded_deg=list(state.commanded_deg),
                    joints=list(state.joints), tool_ideal=list(state.tool_ideal),
                    tool_quantized=list(state.tool_quantized), error_mm=state.error_mm, seconds=0.0, queued=False,
                    gripper_percent=state.gripper_percent, note="refused by the parser (Robot.quantize)",
                    codec_rejected=True)
    return out, {k: v for k, v in doc.items() if k != "records"}


def lines_original(path: Path, n: int) -> str:
    try:
        return path.read_text(encoding="ascii", errors="surrogateescape").splitlines()[n - 1].strip()
    except (OSError, IndexError):
        return ""


def first_interval_s(settings: dict[int, float], pred: Prediction | None = None) -> float:
    """The first step interval of a move, from rest (docs/protocol.md, "Timing of moves"): the
    firmware's own profile (shared/articula/motion.h, through articula._core). No pin shows
    when a move starts, so the virtual Nano's measured duration is this interval plus the span
    of the move's steps. A straight line (T) whose first segment cruises slower than that
    first step takes its cruise interval (the prediction's `cruise4`, in 4-tick units)."""
    d = articula.DEFAULT_SETTINGS
    c0 = articula._core.first_interval_s(int(settings.get(0, d[0])), int(settings.get(1, d[1])))
    segments = pred.raw.get("segments") if pred is not None else None
    return max(c0, 4 * segments[0]["cruise4"] / articula.STEP_TICK_HZ) if segments else c0
