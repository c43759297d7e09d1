// The Experiment panel (panels/experiment.ts) asks the engine three things: a test plan read
// (the host's plan reader, host/lib/plan.h) with the prediction of every line on the robot
// shown; the question a typed tool position raises; and the thesis's tables of the poses
// measured (host/lib/experiment.h, the numbers the harness's report has).
import { EngineError } from "../../../../wasm/js/engine.mjs";
import { BadMessage, text } from "./checks";
import type { Msg, Out } from "./checks";
import { info, S } from "./state";

type Xyz = [number, number, number];

// [x, y, z] from the page: a typed value that is not a number arrives as NaN (or null) and
// goes on as NaN, for the engine's question to name it.
function xyz(m: Msg, key: string): Xyz {
  const v = m[key];
  if (!Array.isArray(v) || v.length !== 3) throw new BadMessage(`'${key}' must be three numbers [x, y, z]`);
  return v.map((x) => (typeof x === "number" ? x : NaN)) as Xyz;
}

function finiteXyz(m: Record<string, unknown>, key: string): Xyz {
  const v = xyz(m, key);
  if (!v.every(Number.isFinite)) throw new BadMessage(`'${key}' must be three finite numbers`);
  return v;
}

export const experimentHandlers: Record<string, (m: Msg) => Out[]> = {
  experiment_plan(m) {
    const name = text(m, "name", 200), body = text(m, "text");
    try {
      const plan = S.engine.parsePlan(body, name);
      const doc = S.robot.predict(body, name) as { records: Record<string, unknown>[] };
      const records = doc.records.map((r) => ({ line: r.line, code: r.code, steps: r.steps, seconds: r.seconds,
        actuator_deg: r.actuator_deg, tool_ideal_mm: r.tool_ideal_mm, tool_quantized_mm: r.tool_quantized_mm, target_mm: r.target_mm ?? null }));
      const zero = (S.robot.info.motors as { zero: number }[]).map((x) => x.zero);
      // the tool at the power-up pose (every motor at step 0: its zero angle, exactly)
      const start = (S.robot.pose(S.robot.jointsFromMotors(zero)) as { tool: { xyz: number[] } }).tool.xyz;
      // the repeatability chains, grouped by the engine (host/lib/experiment.h, repeat_chains)
      const chains = S.engine.repeatChains((plan as { commands: { line: number; repeat: [number, string] | null }[] }).commands);
      return [{ type: "experiment_plan", plan, records, chains, reach_mm: info().reach_mm, zero, start, start_line: S.robot.protocolLine("M", zero) }];
    } catch (e) {
      if (!(e instanceof EngineError)) throw e;
      return [{ type: "experiment_plan", error: e.message }];
    }
  },
  experiment_question(m) {
    const question = S.engine.measurementQuestion(xyz(m, "measured"), finiteXyz(m, "predicted"), info().reach_mm);
    return [{ type: "experiment_question", question }];
  },
  // points: [{joint, angle, ideal, quant, measured (or null)}]. Per point its errors, and per
  // comparison the thesis's Table 4 (quantized vs ideal; measured vs quantized; measured vs ideal);
  // chains: the repeatability chains, for Table 5; targets: the tool points (P) (host/lib/records_json.h's shapes).
  experiment_tables(m) {
    const points = m.points;
    if (!Array.isArray(points) || points.length > 10000) throw new BadMessage("'points' must be a list");
    const rows = (points as Record<string, unknown>[]).map((p, i) => {
      if (typeof p !== "object" || p === null || !Number.isInteger(p.joint)) throw new BadMessage(`'points[${i}].joint' must be a whole number`);
      const ideal = finiteXyz(p, "ideal"), quant = finiteXyz(p, "quant");
      const measured = p.measured == null ? null : finiteXyz(p, "measured");
      return { joint: p.joint as number, angle: p.angle, ideal, quant, measured,
        quant_vs_ideal: S.engine.axisErrors(quant, ideal),
        measured_vs_quant: measured ? S.engine.axisErrors(measured, quant) : null,
        measured_vs_ideal: measured ? S.engine.axisErrors(measured, ideal) : null };
    });
    const table = (pick: (r: (typeof rows)[number]) => [Xyz | null, Xyz]) =>
      S.engine.table4(rows.flatMap((r) => {
        const [value, reference] = pick(r);
        return value ? [{ joint: r.joint, value, reference }] : [];
      }));
    const chains = Array.isArray(m.chains) ? (m.chains as Record<string, unknown>[]).slice(0, 100) : [];
    const targets = Array.isArray(m.targets) ? (m.targets as Record<string, unknown>[]).slice(0, 1000) : [];
    return [{ type: "experiment_tables", rows, table5: S.engine.table5(chains), targets: S.engine.toolPoints(targets),
      csv: typeof m.experiment === "object" && m.experiment !== null ? S.engine.experimentCsv(m.experiment as Record<string, unknown>) : "",
      verdicts: S.engine.jointVerdicts(rows.map((r) => ({ joint: r.joint, ideal: r.ideal, quant: r.quant, measured: r.measured }))),
      quant_vs_ideal: table((r) => [r.quant, r.ideal]),
      measured_vs_quant: table((r) => [r.measured, r.quant]),
      measured_vs_ideal: table((r) => [r.measured, r.ideal]) }];
  },
};
