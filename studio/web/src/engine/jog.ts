// The worker's jog: a nudge of one joint, or of the tool along x, y or z of the table's frame
// or of the tool's own, by a chosen step; and what whole steps make of it. The engine answers
// each part: the joint's limits, IK for the point (the pen's tip when a pen is held), and the
// firmware's prediction of the two poses as `M` lines (host/lib/predict.h), whose whole-step
// tools give "1 mm asked, 0.93 mm in whole steps". A nudge that cannot be made leaves the pose.
import { EngineError } from "../../../../wasm/js/engine.mjs";
import { BadMessage, num, numbers, round6, text } from "./checks";
import type { Msg, Out } from "./checks";
import { info, moveLine, poseMessage, S, toolForTip } from "./state";

type Rec = { code: number; joints: number[]; tool_quantized_mm: number[]; steps: number[] };

/** The whole-step records of two poses in turn (null: a robot without motors, or refused). */
function wholeSteps(from: number[], to: number[]): [Rec, Rec] | null {
  if (!info().num_motors) return null;
  try {
    const doc = S.robot.predict(`${moveLine(from)}\n${moveLine(to)}\n`, "jog.arm") as { records: Rec[] };
    const [a, b] = doc.records;
    return a && b && a.code === 0 && b.code === 0 ? [a, b] : null;
  } catch (e) {
    if (e instanceof EngineError) return null;
    throw e;
  }
}

const sub = (a: number[], b: number[]) => a.map((v, i) => v - b[i]);
const dot = (a: number[], b: number[]) => a.reduce((t, v, i) => t + v * b[i], 0);
const fmt = (v: number) => (Math.abs(v) >= 10 ? v.toFixed(1) : v.toFixed(2)).replace(/\.?0+$/, "") || "0";

const axisName0 = (k: number, frame: string) => `${"xyz"[k]}${frame === "tool" ? " (the tool's)" : ""}`;
const FAR_MM = [400, 300, 200, 150, 100, 70, 50, 30, 20, 10, 5, 2, 1]; // a held jog's straight line: the longest the arm takes

// A held jog of the tool: `T` to the farthest point along `u` whose straight line the firmware
// takes from `from` (its prediction accepts it: within the limits and the reach at every segment).
function farLine(from: number[], tip: number[], u: number[], speed: number, axisName: string, frame: string): Out {
  for (const far of FAR_MM) {
    const target = toolForTip(tip.map((v, i) => v + u[i] * far));
    let line: string;
    try {
      line = S.robot.protocolLine("T", [...target, speed]);
      const doc = S.robot.predict(`${moveLine(from)}\n${line}\n`, "jog.arm") as { records: Rec[] };
      if (doc.records[1]?.code !== 0) continue;
    } catch (e) {
      if (e instanceof EngineError) continue;
      throw e;
    }
    return { type: "jog", moved: true, frame, hold: true, line, said: `${axisName}: held, at ${speed} mm/s, as far as ${far} mm (let go to stop)` };
  }
  return { type: "jog", moved: false, frame, hold: true, said: `${axisName}: no straight line that way from here` };
}

export const jogHandlers: Record<string, (m: Msg) => Out[]> = {
  jog(m) {
    const frame = text(m, "frame", 8);
    if (!["joint", "table", "tool"].includes(frame)) throw new BadMessage("'frame' must be joint, table or tool");
    const step = num(m, "step", 0.01, 100);
    const dir = num(m, "dir", -1, 1) < 0 ? -1 : 1;
    const r = info();
    // from the pose shown, or the arm's (a jog of the arm starts where it is)
    const from = m.from === undefined || m.from === null ? [...S.q] : numbers(m, "from", [r.num_joints]);
    // held: one move as far as the jog may go (a joint's limit; the farthest point along the axis a
    // straight line reaches), that a `!` ends when the jog is let go
    const hold = m.hold === true;
    let to: number[];
    let asked: string, unit: string, axisName: string;
    let along: (a: Rec, b: Rec) => { along: number; off: number };
    if (frame === "joint") {
      const j = num(m, "axis", 0, r.num_joints - 1);
      if (!Number.isInteger(j)) throw new BadMessage("'axis' must be a joint's index");
      const [lo, hi] = r.limits[j];
      unit = ((r.joints[j] as { unit?: string }).unit ?? "deg") === "mm" ? "mm" : "°";
      axisName = r.joint_names[j] ?? `joint ${j + 1}`;
      to = [...from];
      to[j] = hold ? (dir < 0 ? lo : hi) : Math.min(hi, Math.max(lo, from[j] + dir * step));
      if (Math.abs(to[j] - from[j]) < 1e-9)
        return [{ type: "jog", moved: false, frame, said: `${axisName} is at its limit (${fmt(dir < 0 ? lo : hi)}${unit}): no further that way` }, poseMessage()];
      asked = fmt(to[j] - from[j]);
      along = (a, b) => ({ along: b.joints[j] - a.joints[j], off: 0 });
    } else {
      const k = num(m, "axis", 0, 2);
      if (!Number.isInteger(k)) throw new BadMessage("'axis' must be 0 (x), 1 (y) or 2 (z)");
      const pose = S.robot.pose(from) as { frames: number[][]; tool: { xyz: number[] } };
      const f = pose.frames[pose.frames.length - 1];
      // the table's axis, or the tool's own (a column of its rotation)
      const d = frame === "table" ? [0, 1, 2].map((i) => (i === k ? dir * step : 0)) : [f[k] * dir * step, f[4 + k] * dir * step, f[8 + k] * dir * step];
      const tip = S.pen > 0 ? [pose.tool.xyz[0], pose.tool.xyz[1], pose.tool.xyz[2] - S.pen] : pose.tool.xyz;
      if (hold) return [farLine(from, tip, d.map((v) => v / step), num(m, "speed", 0.1, 1000), axisName0(k, frame), frame)];
      const target = tip.map((v, i) => v + d[i]);
      const res = S.robot.ik({ target: toolForTip(target), solver: "auto", start: from }) as { status: string; q: number[]; why?: string };
      axisName = axisName0(k, frame);
      unit = " mm";
      if (res.status !== "reached")
        return [{ type: "jog", moved: false, frame, said: `${dir < 0 ? "−" : "+"}${step} mm in ${axisName} is not reached: ${res.why || res.status}. The arm stays.` }, poseMessage()];
      to = res.q;
      asked = fmt(dir * step);
      const u = d.map((v) => v / step);
      along = (a, b) => {
        const moved = sub(b.tool_quantized_mm, a.tool_quantized_mm);
        const l = dot(moved, u);
        return { along: l, off: Math.hypot(...sub(moved, u.map((v) => v * l))) };
      };
    }
    // (held: the arm moves; the model follows the arm once it is let go and at rest)
    if (hold) return [{ type: "jog", moved: true, frame, hold: true, line: moveLine(to), said: `${axisName}: held, towards its limit (let go to stop)` }];
    S.q = to;
    const w = wholeSteps(from, to);
    let said = `${axisName}: ${asked}${unit} asked`;
    let whole: number | null = null;
    if (w) {
      const { along: l, off } = along(w[0], w[1]);
      whole = round6(l);
      said += `, ${fmt(l)}${unit} in whole steps` + (off >= 0.05 ? ` (and ${fmt(off)} mm off the axis)` : "");
    }
    return [{ type: "jog", moved: true, frame, said, asked: Number(asked), whole, line: moveLine(to), q: to }, poseMessage(S.q, { seq: m.seq ?? null })];
  },
};
