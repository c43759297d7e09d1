// An exercise's Check, in the engine's worker: the program runs (its time line for the
// tool's points; the physics, from power-up in the exercise's scene, where an object must end
// in a place) and every part of the goal is measured: met or not, and by how much.
import { EngineError } from "../../../../wasm/js/engine.mjs";
import { BadMessage, text } from "./checks";
import type { Msg, Out } from "./checks";
import { info, powerUpQ, S } from "./state";
import { sceneFile } from "./site";
import type { DrawingPart, GoalPart } from "../project/document";
import { ensureFont } from "./draw";
import { cellOutcome } from "./cell";

const SETTLE_S = 1.5; // the physics runs on this long after the program, for objects to come to rest

interface PartResult { label: string; met: boolean; detail: string; distance_mm: number; target?: number[][][]; ink?: number[][][] }

// A drawing part's target as the engine takes it: the student's text where the part asks for it.
function drawingTarget(p: DrawingPart, answer: string): Record<string, unknown> {
  if (p.ask && !answer.trim()) throw new BadMessage(`type ${p.ask} first`);
  return p.ask ? { ...p.target, text: answer.trim().slice(0, 40) } : { ...p.target };
}

const f1 = (v: number) => v.toFixed(1);

/** An object of the scene a goal moves, and how low the tool's point can come above it. */
export interface GoalObject { name: string; size: number[]; xyz: number[]; lowest_tool_z: number | null }

// How far outside its box an object's centre is (0: inside), as a part's result.
type SimEventJson = { kind: string; t: number; line: number; a: string; b: string; point_mm?: number[]; detail?: string };

// What happened to an object that did not end in its place, from the physics' events: whether
// the gripper held it and where it let it go, and the lines the arm refused (issue 55, 8: Check
// said only how far it was; why was in the event log).
function objectStory(name: string, events: SimEventJson[]): string {
  const mine = (e: SimEventJson) => e.a === name || e.b === name;
  const grasps = events.filter((e) => e.kind === "grasp" && mine(e));
  const releases = events.filter((e) => e.kind === "release" && mine(e));
  const refused = events.filter((e) => e.kind === "rejected");
  const gone = events.find((e) => e.kind === "object_removed" && mine(e));
  const said: string[] = [];
  if (gone) said.push(`it left the world at ${f1(gone.t)} s`);
  else if (!grasps.length) said.push("the gripper never held it");
  else {
    const g = grasps[0], r = releases.find((x) => x.t >= g.t);
    said.push(`the gripper held it from line ${g.line}` + (r ? ` and let it go at line ${r.line}${r.point_mm ? `, at (${r.point_mm.map(f1).join(", ")}) mm` : ""}`
      : ", and still holds it"));
  }
  if (refused.length) said.push(`line ${refused[0].line} was refused (${refused[0].detail ?? refused[0].a})` + (refused.length > 1 ? ` and ${refused.length - 1} more` : ""));
  return said.join("; ");
}

function objectResult(p: Extract<GoalPart, { kind: "object" }>, objects: { name: string; pose: number[] }[], events: SimEventJson[] = []): PartResult {
  const o = objects.find((x) => x.name === p.object);
  if (!o) throw new BadMessage(`the scene has no object '${p.object}'`);
  const at = [o.pose[3], o.pose[7], o.pose[11]];
  const out = at.map((v, i) => Math.max(p.min[i] - v, 0, v - p.max[i]));
  const d = Math.hypot(...out);
  return { label: p.label || `${p.object} in its place`, met: d === 0, distance_mm: d,
    detail: d === 0 ? `in place, at (${at.map(f1).join(", ")}) mm`
      : `${f1(d)} mm from its place: it is at (${at.map(f1).join(", ")}) mm` + (events.length ? `; ${objectStory(p.object, events)}` : "") };
}

// A cell's exercise (the project's cell, with its arms' programs): its objects' places, no
// collision, every program to its end.
async function cellCheck(doc: { name?: unknown; programs?: unknown }, parts: GoalPart[]): Promise<Out> {
  if (typeof doc.name !== "string" || !Array.isArray(doc.programs) || !doc.programs.every((p) => typeof p === "string"))
    throw new BadMessage("'cell' must be {name, programs}");
  const wrong = parts.find((p) => p.kind === "reach" || p.kind === "drawing");
  if (wrong) throw new BadMessage(`a cell's exercise checks objects, collisions and the programs' ends, not '${wrong.kind}'`);
  let w;
  try {
    w = await cellOutcome({ name: doc.name, programs: doc.programs as string[] }, SETTLE_S);
  } catch (e) {
    if (e instanceof BadMessage) return { type: "exercise_result", error: e.message, parts: [] };
    throw e;
  }
  const results: PartResult[] = [];
  for (const p of parts) {
    if (p.kind === "object") results.push(objectResult(p, w.objects, w.events as SimEventJson[]));
    if (p.kind === "no_collision") {
      const hits = w.events.filter((e) => e.kind === "collision" || e.kind === "self_collision" || e.kind === "squeeze");
      const first = hits[0];
      results.push({ label: p.label || "no arm hits anything", met: hits.length === 0, distance_mm: hits.length,
        detail: first ? `${hits.length} collision${hits.length > 1 ? "s" : ""}: the first at ${f1(first.t)} s, ${first.arm ?? "the arm"}'s ${first.a} hit ${first.b}`
          : "no collision" });
    }
    if (p.kind === "programs_end") {
      const stuck = w.events.find((e) => e.kind === "deadlock");
      const ranOut = w.waits.filter((x) => !x.met);
      results.push({ label: p.label || "every arm's program runs to its end, each wait ended by the other arm's signal",
        met: !stuck && ranOut.length === 0, distance_mm: ranOut.length + (stuck ? 1 : 0),
        detail: stuck ? `stuck at ${f1(stuck.t)} s: ${stuck.detail ?? "the arms wait for each other"}` + (ranOut.length ? `; ${waitWords(ranOut[0])}` : "")
          : ranOut.length ? waitWords(ranOut[0]) : "every wait ended at the other arm's signal" });
    }
    if (p.kind === "waits_for") {
      const mine = w.waits.filter((x) => x.arm === p.arm && x.name === p.input);
      const ended = mine.find((x) => x.met && x.end_t !== x.t);
      results.push({ label: p.label || `${p.arm} waits for \`${p.input}\``, met: !!ended, distance_mm: ended ? 0 : 1,
        detail: ended ? `it waited from ${f1(ended.t)} s until the signal came at ${f1(ended.end_t!)} s`
          : mine.some((x) => !x.met) ? waitWords(mine.find((x) => !x.met)!)
          : mine.length ? `its wait for \`${p.input}\` ended at once: the input already read that level`
          : `${p.arm}'s program never waits for \`${p.input}\` (W on its pin)` });
    }
  }
  return { type: "exercise_result", parts: results, met: results.every((r) => r.met) };
}

const waitWords = (x: { arm: string; line: number; name: string; t: number; end_t: number | null }) =>
  x.end_t === null ? `${x.arm}'s wait for \`${x.name}\` (line ${x.line}) never ended`
    : `${x.arm}'s wait for \`${x.name}\` (line ${x.line}) ran out after ${f1(x.end_t - x.t)} s: no signal came`;

export const exerciseHandlers: Record<string, (m: Msg) => Promise<Out[]>> = {
  // What the student needs to see of a goal: each object it moves (its size, where it stands)
  // and how low the tool's point can come there (the IK's closest pose to the table under it:
  // the MK2's motors stop it tens of mm above the ground). The page draws the goal's places.
  async exercise_targets(m) {
    const parts = m.parts as GoalPart[];
    if (!Array.isArray(parts)) throw new BadMessage("'parts' must be a list of the goal's parts");
    const scene = typeof m.scene === "string" ? m.scene : "";
    const names = new Set(parts.filter((p) => p.kind === "object").map((p) => (p as { object: string }).object));
    const objects: GoalObject[] = [];
    // a drawing's target: its strokes on the paper, to draw faintly there
    const drawings: { strokes: number[][][]; z: number; pen: number; error?: string }[] = [];
    const answer = typeof m.answer === "string" ? m.answer : "";
    for (const p of parts.filter((x) => x.kind === "drawing") as DrawingPart[]) {
      if (p.ask && !answer.trim()) {
        drawings.push({ strokes: [], z: p.z, pen: p.pen });
        continue;
      }
      await ensureFont();
      try {
        drawings.push({ strokes: S.robot.draw({ ...drawingTarget(p, answer), z: p.z, pen: p.pen }).strokes, z: p.z, pen: p.pen });
      } catch (e) {
        if (!(e instanceof EngineError)) throw e;
        drawings.push({ strokes: [], z: p.z, pen: p.pen, error: e.message });
      }
    }
    if (names.size && scene && S.index.scenes.includes(scene)) {
      const doc = JSON.parse(await sceneFile(scene)) as { objects?: { name: string; type: string; size?: number[]; radius?: number; height?: number; xyz: number[] }[] };
      for (const o of doc.objects ?? []) {
        if (!names.has(o.name)) continue;
        const size = o.size ?? (o.radius !== undefined ? [2 * o.radius, 2 * o.radius, o.height ?? 2 * o.radius] : []);
        let lowest: number | null = null;
        try {
          const r = S.robot.ik({ target: [o.xyz[0], o.xyz[1], 0], solver: "auto", start: S.q }) as unknown as { tool?: number[] };
          lowest = r.tool ? r.tool[2] : null;
        } catch (e) {
          if (!(e instanceof EngineError)) throw e;
        }
        objects.push({ name: o.name, size, xyz: o.xyz, lowest_tool_z: lowest });
      }
    }
    return [{ type: "exercise_targets", objects, drawings }];
  },

  async exercise_check(m) {
    const src = text(m, "text");
    const name = typeof m.name === "string" && m.name ? m.name : "program.arm";
    const parts = m.parts as GoalPart[];
    if (!Array.isArray(parts) || parts.length === 0) throw new BadMessage("'parts' must be a list of the goal's parts");
    const scene = typeof m.scene === "string" ? m.scene : "";
    const results: PartResult[] = [];
    const cellDoc = m.cell as { name?: unknown; programs?: unknown } | null | undefined;
    if (cellDoc) return [await cellCheck(cellDoc, parts)];
    const reach = parts.filter((p) => p.kind === "reach") as Extract<GoalPart, { kind: "reach" }>[];
    const objects = parts.filter((p) => p.kind === "object") as Extract<GoalPart, { kind: "object" }>[];
    const drawings = parts.filter((p) => p.kind === "drawing") as DrawingPart[];
    const answer = typeof m.answer === "string" ? m.answer : "";
    try {
      if (drawings.length) await ensureFont();
      for (const p of drawings) {
        const c = S.robot.drawingCheck({ program: src, name, target: drawingTarget(p, answer), z: p.z, pen: p.pen, tolerance: p.tolerance_mm });
        results.push({ label: p.label || `the drawing (${c.what})`, met: c.met, detail: c.says,
          distance_mm: Math.max(c.ink_off_mm ?? Infinity, c.uncovered_mm ?? Infinity), target: c.target, ink: c.ink });
      }
      if (reach.length) {
        const start = info().num_motors ? powerUpQ() : [...S.q];
        const tl = S.engine.timeline(S.robot, src, name, start);
        const tools = tl.doc.records.filter((r) => r.reply === "ok").map((r) => r.tool);
        tl.delete();
        for (const p of reach) {
          const d = Math.min(Infinity, ...tools.map((t) => Math.hypot(t[0] - p.xyz[0], t[1] - p.xyz[1], t[2] - p.xyz[2])));
          const met = d <= p.tolerance_mm;
          results.push({ label: `the tool at (${p.xyz.join(", ")}) mm`, met, distance_mm: d,
            detail: !Number.isFinite(d) ? "the program never moved the tool"
              : met ? `reached: ${f1(d)} mm away (within ${p.tolerance_mm} mm)` : `closest ${f1(d)} mm away: needs to be within ${p.tolerance_mm} mm` });
        }
      }
      if (objects.length) {
        if (!scene || !S.index.scenes.includes(scene)) throw new BadMessage("this goal needs a scene: the exercise names none that ships");
        const sim = S.engine.sim(S.robot, await sceneFile(scene), `scenes/${scene}.json`);
        try {
          sim.loadProgram(src, name);
          sim.runUntil(sim.endTime + SETTLE_S);
          const state = sim.state() as { objects: { name: string; pose: number[] }[] };
          const events = sim.events(0) as SimEventJson[];
          for (const p of objects) results.push(objectResult(p, state.objects, events));
        } finally {
          sim.delete();
        }
      }
    } catch (e) {
      if (e instanceof EngineError) return [{ type: "exercise_result", error: e.message, parts: [] }];
      throw e;
    }
    return [{ type: "exercise_result", parts: results, met: results.every((r) => r.met) }];
  },
};
