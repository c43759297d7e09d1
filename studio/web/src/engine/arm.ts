// The arm in the page (link/arm-link.ts, panels/arm.ts) asks the engine three things, each in one round
// trip: a line from the arm read by the core's parsers, with the arm's pose when it is a
// status report; the model's prediction of a line after those the arm accepted; and the
// robot shown as a Nano's configuration (its lines and checksum, or why a Nano cannot take it).
import { EngineError } from "../../../../wasm/js/engine.mjs";
import { numbers, text } from "./checks";
import type { Msg, Out } from "./checks";
import { framesAt, info, S } from "./state";

export const armHandlers: Record<string, (m: Msg) => Out[]> = {
  arm_read(m) {
    const parsed = S.engine.parseArmLine(text(m, "line", 1000));
    let pose: Out | null = null;
    if (parsed.kind === "status" && parsed.angles.length === info().num_motors) {
      const q = S.robot.jointsFromMotors(numbers({ angles: parsed.angles }, "angles", [info().num_motors])) as number[];
      pose = { q, frames: framesAt(q) };
    }
    return [{ type: "arm_read", parsed, pose }];
  },
  arm_config() {
    try {
      return [{ type: "arm_config", config: S.robot.nanoConfig() }];
    } catch (e) {
      if (!(e instanceof EngineError)) throw e;
      return [{ type: "arm_config", config: { error: e.message } }];
    }
  },
  arm_predict(m) {
    const line = text(m, "line", 200);
    const history = Array.isArray(m.history) ? (m.history as unknown[]).filter((x): x is string => typeof x === "string") : [];
    let out: Out;
    try {
      const doc = S.robot.predict([...history, line].join("\n") + "\n", "arm.arm") as { records: Record<string, unknown>[] };
      const rec = doc.records[doc.records.length - 1];
      const code = rec.code as number;
      out = { reply: code === 0 ? "ok" : `error:${code}`, steps: rec.steps, meaning: S.engine.statusText(code), seconds: rec.seconds };
    } catch (e) {
      if (!(e instanceof EngineError)) throw e;
      const code = (S.robot.quantize([line])[0] as { code: number }).code;
      out = { reply: `error:${code}`, steps: null, meaning: S.engine.statusText(code) };
    }
    return [{ type: "arm_predicted", ...out }];
  },
};
