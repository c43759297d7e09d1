// The worker's program intents: a shipped example, a program's time line (the engine's:
// host/lib/timeline.h predicts a robot with motors and times a kinematic one), and its clock:
// play, pause, step, seek, rewind. The arm at each instant is the engine's answer too.
import { EngineError } from "../../../../wasm/js/engine.mjs";
import { BadMessage, num, text } from "./checks";
import type { Msg, Out } from "./checks";
import { dropTimeline, ghostAt, info, poseMessage, post, powerUpQ, S, stopTasks } from "./state";
import { fetchText } from "./site";

const FRAME_MS = 1000 / 60;

function needTimeline() {
  if (!S.timeline) throw new BadMessage("no program loaded: send program_load first");
  return S.timeline;
}

// The arm at time s of the time line: the whole-step pose and the ideal one (the ghost).
// (`ended`: the line that ends at s, named rather than the one that begins there: a pause
// after a line shows that line)
export function poseAt(s: number, ended?: number): Out {
  const p = needTimeline().at(s);
  S.q = p.q;
  if (p.gripper !== null) S.gripper = p.gripper;
  return poseMessage(S.q, { t: p.t, line: ended ?? p.line, steps: p.steps, error_mm: p.error_mm, ...ghostAt(p.q_ideal) });
}

/** A message's `breaks`: the line numbers a run pauses after (none: an empty set). */
export function lineNumbers(m: Msg): Set<number> {
  const v = m.breaks;
  if (v === undefined || v === null) return new Set();
  if (!Array.isArray(v) || v.length > 100_000 || !v.every((x) => Number.isInteger(x) && x > 0))
    throw new BadMessage("'breaks' must be a list of line numbers");
  return new Set(v as number[]);
}

export const programHandlers: Record<string, (m: Msg) => Out[] | Promise<Out[]>> = {
  async program_open(m) {
    const name = text(m, "name", 200);
    if (!S.index.programs.includes(name)) throw new BadMessage(`no shipped program '${name}'`);
    return [{ type: "program_text", name, text: await fetchText(`data/programs/${name}`) }];
  },
  // The time line the page plays: predicted from power-up (robots with motors) or run from the
  // pose shown. A program that cannot be read is an error naming the line.
  program_load(m) {
    const src = text(m, "text");
    const name = (typeof m.name === "string" && m.name) || "program.arm";
    const start = info().num_motors ? powerUpQ() : [...S.q];
    let tl;
    try {
      tl = S.engine.timeline(S.robot, src, name, start);
    } catch (e) {
      if (e instanceof EngineError) {
        const x = e as { line?: number; problems?: { line: number; problem: string }[] };
        return [{ type: "program_error", message: e.message, line: x.line ?? 0, problems: x.problems ?? [] }];
      }
      throw e;
    }
    dropTimeline();
    S.timeline = tl;
    S.t = 0;
    S.q = [...tl.doc.start_q];
    const d = tl.doc;
    return [{ type: "timeline", name, format: d.format, records: d.records, duration: d.duration, start_tool: d.start_tool,
      joints: info().joint_names, summary: d.summary, samples: d.samples }, poseMessage(S.q, { t: 0, line: 0 })];
  },
  // How fast the simulated world runs against real time: the time line's playing and the live
  // physics (the page's speed select, ?speed= in its address).
  speed(m) {
    S.speed = num(m, "speed", 0.05, 20);
    return [];
  },
  // Plays from the clock to the end, or to the end of the first breakpoint's line ahead
  // (`breaks`: line numbers; the arm at rest after it, as the firmware would leave it).
  play(m) {
    const tl = needTimeline();
    if ("speed" in m) S.speed = num(m, "speed", 0.05, 20);
    const breaks = lineNumbers(m);
    stopTasks();
    if (S.t >= tl.duration) S.t = 0;
    const at = tl.doc.records.filter((r) => breaks.has(r.line) && r.end_s > S.t + 1e-9).sort((a, b) => a.end_s - b.end_s)[0];
    const until = at ? at.end_s : tl.duration;
    let last = performance.now();
    post([{ type: "playing", t: S.t, playing: true }]);
    const frame = () => {
      const now = performance.now();
      S.t = Math.min(until, S.t + ((now - last) / 1000) * S.speed);
      last = now;
      post([poseAt(S.t, S.t >= until && at ? at.line : undefined)]);
      if (S.t >= until) {
        S.task = null;
        post([at && until < tl.duration + 1e-9 && S.t < tl.duration - 1e-9
          ? { type: "playing", t: S.t, playing: false, paused_at: at.line }
          : { type: "playing", t: S.t, playing: false, ended: true, ...(at ? { paused_at: at.line } : {}) }]);
        return;
      }
      S.task = setTimeout(frame, Math.max(FRAME_MS, S.postMs)); // (the page's frame rate: S.postMs)
    };
    frame();
    return [];
  },
  pause: () => {
    stopTasks();
    return [{ type: "playing", t: S.t, playing: false }];
  },
  // To the end of the next action (a line).
  step: () => {
    const tl = needTimeline();
    stopTasks();
    const next = tl.doc.records.find((r) => r.end_s > S.t + 1e-9);
    S.t = next ? next.end_s : tl.duration;
    return [poseAt(S.t, next?.line), { type: "playing", t: S.t, playing: false, ...(next ? { paused_at: next.line } : {}) }];
  },
  seek(m) {
    const tl = needTimeline();
    stopTasks();
    S.t = num(m, "t", 0, tl.duration + 1e-9);
    return [poseAt(S.t), { type: "playing", t: S.t, playing: false }];
  },
  rewind: () => {
    needTimeline();
    stopTasks();
    S.t = 0;
    return [poseAt(0), { type: "playing", t: 0, playing: false }];
  },
};
