// The arm in the page (link/arm-link.ts, panels/arm.ts) asks the engine three things, each in one round
// trip: a line from the arm read by the core's parsers, with the arm's pose when it is a
// status report; the model's prediction of a line after those the arm accepted; and the
// robot shown as a Nano's configuration (its lines and checksum, or why a Nano cannot take it).
import { EngineError } from "../../../../wasm/js/engine.mjs";
import type { Robot } from "../../../../wasm/js/engine.mjs";
import { numbers, round6, text } from "./checks";
import type { Msg, Out } from "./checks";
import { S, toolForTip } from "./state";
import type { RobotInfo } from "./state";

export const armHandlers: Record<string, (m: Msg) => Out[]> = {
  // One protocol line, formatted by the engine (host/lib/blocks.h, protocol_line): the page
  // writes no line itself.
  protocol_line(m) {
    const word = text(m, "word", 1);
    let values = Array.isArray(m.values) ? numbers(m, "values", [m.values.length]) : [];
    // a point the page aims at with a pen held is its tip: the line takes the tool point above it
    if (m.at_tip === true && (word === "P" || word === "T") && values.length >= 3) values = toolForTip(values);
    try {
      return [{ type: "protocol_line", line: S.robot.protocolLine(word, values) }];
    } catch (e) {
      if (!(e instanceof EngineError)) throw e;
      return [{ type: "protocol_line", error: e.message }];
    }
  },
  arm_read: (m) => [armRead(S.robot, m)],
  arm_config: () => [armConfig(S.robot)],
  arm_predict: (m) => [armPredict(S.robot, m)],
};

// (each for a robot: the one shown, or an arm of a cell on a Nano of its own, engine/cell.ts)

/** {type: "arm_read", parsed, pose}: an arm's line read; a status report's pose with it. */
export function armRead(robot: Robot, m: Msg): Out {
  const parsed = S.engine.parseArmLine(text(m, "line", 1000));
  let pose: Out | null = null;
  const n = (robot.info as unknown as RobotInfo).num_motors;
  if (parsed.kind === "status" && parsed.angles.length === n) {
    const angles = numbers({ angles: parsed.angles }, "angles", [n]);
    const q = robot.jointsFromMotors(angles) as number[];
    // the line that commands the reported angles: after a stop, what the arm holds
    pose = { q, frames: (robot.pose(q).frames as number[][]).map((f) => f.map(round6)), line: robot.protocolLine("M", angles) };
  }
  return { type: "arm_read", parsed, pose };
}

/** {type: "arm_config", config}: the robot as a Nano's configuration, or why a Nano cannot take it. */
export function armConfig(robot: Robot): Out {
  try {
    return { type: "arm_config", config: robot.nanoConfig() };
  } catch (e) {
    if (!(e instanceof EngineError)) throw e;
    return { type: "arm_config", config: { error: e.message } };
  }
}

/** {type: "arm_predicted", ...}: a line's prediction after those the arm accepted (`history`). */
export function armPredict(robot: Robot, m: Msg): Out {
  const raw = text(m, "line", 200);
  // the line as the arm acts on it (the core's comment rule): a comment alone is no command
  const line = S.engine.lineCommand(raw);
  if (line === "") return { type: "arm_predicted", command: "", reply: "ok", steps: null, meaning: "" };
  const history = Array.isArray(m.history) ? (m.history as unknown[]).filter((x): x is string => typeof x === "string") : [];
  let out: Out;
  try {
    const doc = robot.predict([...history, line].join("\n") + "\n", "arm.arm") as { records: Record<string, unknown>[] };
    const rec = doc.records[doc.records.length - 1];
    const code = rec.code as number;
    out = { command: line, reply: code === 0 ? "ok" : `error:${code}`, steps: rec.steps, meaning: S.engine.statusText(code), seconds: rec.seconds };
  } catch (e) {
    if (!(e instanceof EngineError)) throw e;
    const code = (robot.quantize([line])[0] as { code: number }).code;
    out = { command: line, reply: `error:${code}`, steps: null, meaning: S.engine.statusText(code) };
  }
  return { type: "arm_predicted", ...out };
}
