// A cell (cells/README.md) in the engine's worker: several arms, each on its own firmware, in one
// world (the engine's Cell: host/physics/cell_sim.h), stepped in real time and streamed to the
// page a display frame at a time. Each arm is drawn from its robot's model at the joints the cell
// gives it (the pose the single arm's physics shows), in its own base frame, which the page puts
// where the cell file stands it. While a cell is open the single arm's physics is off.
import { EngineError } from "../../../../wasm/js/engine.mjs";
import type { CellDevice } from "./messages";
import type { Cell, Robot } from "../../../../wasm/js/engine.mjs";
import { every } from "../pacer";
import { armConfig, armPredict, armRead } from "./arm";
import { BadMessage, num, numbers, round6, text } from "./checks";
import type { Msg, Out } from "./checks";
import { sceneMessage, startPhysics } from "./physics";
import { fetchText, sceneFile, shippedRobot } from "./site";
import { nanoBuild, post, S, stopTasks } from "./state";
import type { RobotInfo } from "./state";

const FRAME_MS = 1000 / 60;
const MAX_UNACKED = 3;
let cell: Cell | null = null;
let robots: Robot[] = [];
let loop: { stop(): void } | null = null;
let running = false;
let eventsSent = 0;
let cellName: string | null = null; // the shipped cell open
let cellSource: Record<string, unknown> | null = null; // its file as shipped (JSON), for Run all's programs
let programs: string[] = []; // each arm's program as it runs now (text, a line a line)
let shipped: string[] = []; // each arm's program as the cell comes
let timeline: Out[] = []; // each arm's lines in time, as its firmware runs them in the cell
let dirty = false; // a frame the page has not had (a control, a reset)

/** The intents a cell takes while it is open (the physics bar's and STOP's). */
export const CELL_INTENTS = new Set(["physics_run", "physics_pause", "physics_step", "physics_reset", "play", "pause"]);
export const cellOpen = () => cell !== null;

interface ArmState { name: string; robot_ref: string; joints: number[]; gripper_mm: number; line: number; io: Out[];
  base: { xyz: number[]; yaw: number }; program_end_s: number;
  signals: { kind: string; line: number; name: string; level: number; t: number; end_t?: number | null; met?: boolean | null }[] }
interface CellState { t: number; arms: ArmState[]; objects: { name: string; pose: number[]; removed: boolean; carried_by: string | null }[];
  devices?: CellDevice[] }

export function closeCell(): void {
  loop?.stop();
  loop = null;
  cell?.delete();
  cell = null;
  for (const r of robots) r.delete();
  robots = [];
}

// The files a shipped cell names, in the engine's files where its loader looks: the shipped
// robots (/robots), scenes (/scenes) and programs (/programs, a cell's "../programs/x.arm").
async function cellFiles(): Promise<void> {
  for (const r of S.index.robots) {
    const path = `/robots/${r}.json`;
    if (!S.engine.exists(path)) S.engine.writeFile(path, await fetchText(`data/robots/${r}.json`));
  }
  for (const sc of S.index.scenes) {
    const path = `/scenes/${sc}.json`;
    if (!S.engine.exists(path)) S.engine.writeFile(path, await sceneFile(sc));
  }
  for (const [p, body] of S.programTexts) {
    const path = `/programs/${p}`;
    if (!S.engine.exists(path)) S.engine.writeFile(path, body);
  }
}

function cellMessage(): Out {
  if (!cell) return { type: "cell", name: null };
  const st = cell.state() as unknown as CellState;
  return {
    type: "cell", name: cellName, title: cell.name, objects: cell.objects as unknown as Out[],
    arms: st.arms.map((a, i) => ({ name: a.name, robot: { ...robots[i].info as unknown as RobotInfo, ...nanoBuild(robots[i].info as unknown as RobotInfo) },
      base: a.base, io: a.io,
      program: programs[i] ?? "", shipped: shipped[i] ?? "", timeline: timeline[i] })),
    // (checked by the loader: each end an arm's or a device's pin)
    wires: ((cellSource?.wires ?? []) as { from: unknown; to: unknown }[]).map((w) => ({ from: String(w.from), to: String(w.to) })),
    devices: st.devices ?? [],
  };
}

// An arm's program as text: its lines in place, or the shipped program file it names
// ("../programs/x.arm": the site's examples).
function programText(p: unknown): string {
  if (Array.isArray(p)) return p.map(String).join("\n");
  if (typeof p === "string") return S.programTexts.get(p.split("/").pop() ?? "") ?? "";
  return "";
}

// Each arm's lines in time (engine Cell.predict: its own firmware, the other arms' signals
// through the wires), as the timeline draws them: what each line is (a move, a wait for an
// input, an output, a dwell, the gripper) and when it runs. An arm without motors has none.
function armTimeline(c: Cell, name: string): Out {
  try {
    const p = c.predict(name) as unknown as { records: { line: number; command: string; reply: string; start_s: number; end_s: number }[];
      summary: { total_s: number } };
    return {
      end_s: round6(p.summary.total_s),
      lines: p.records.filter((r) => r.command !== "").map((r) => ({
        line: r.line, command: r.command, ok: r.reply === "ok", start_s: round6(r.start_s), end_s: round6(r.end_s),
      })),
    };
  } catch (e) {
    return { why: e instanceof Error ? e.message : String(e), lines: [] };
  }
}

// A cell file's text with each arm's program in place of its own (its lines written in place).
function withPrograms(source: Record<string, unknown>, texts: string[]): string {
  const arms = (source.arms ?? []) as Record<string, unknown>[];
  return JSON.stringify({ ...source, arms: arms.map((a, i) => ({ ...a, program: texts[i].split("\n") })) });
}

// The cell from its file's text: made, with its robots and each arm's timeline, or a refusal.
async function makeCell(body: string, name: string): Promise<{ cell: Cell; robots: Robot[]; timeline: Out[] }> {
  const c = S.engine.cell(body, `${name}.json`, "/cells");
  const rs: Robot[] = [];
  try {
    const arms = (c.state() as unknown as CellState).arms;
    for (const a of arms) rs.push(await shippedRobot(a.robot_ref));
    return { cell: c, robots: rs, timeline: arms.map((a) => armTimeline(c, a.name)) };
  } catch (e) {
    c.delete();
    for (const r of rs) r.delete();
    throw e;
  }
}

function frameMessage(): Out {
  const c = cell!;
  const st = c.state() as unknown as CellState;
  const events = c.events(eventsSent) as unknown[];
  eventsSent += events.length;
  return {
    type: "cell_frame", t: st.t, running, done: c.done, deadlock: c.deadlock, events,
    arms: st.arms.map((a, i) => {
      const p = robots[i].pose(a.joints, a.gripper_mm) as { frames: number[][]; fingers?: number[][] };
      return { name: a.name, line: a.line, joints: a.joints.map(round6), frames: p.frames.map((f) => f.map(round6)), fingers: p.fingers?.map((f) => f.map(round6)),
        program_end_s: a.program_end_s, signals: a.signals };
    }),
    objects: st.objects.map((o) => ({ name: o.name, pose: o.pose.map(round6), removed: o.removed, carried: o.carried_by !== null })),
    devices: st.devices ?? [],
  };
}

/** {type: "cell", name, programs?}: a shipped cell opened (its arms at power-up, running), or
 * closed (null); `programs`: each arm's program in place of the cell's (as Run all's: a project's
 * cell), refused as Run all refuses them (the cell then runs its own). */
export async function cellIntent(m: Msg): Promise<Out[]> {
  const name = m.name === null || m.name === undefined ? null : text(m, "name", 200);
  stopTasks();
  closeCell();
  cellName = null;
  cellSource = null;
  if (name === null) return [{ type: "cell", name: null }];
  if (!(S.index.cells ?? []).includes(name)) throw new BadMessage(`no shipped cell '${name}'`);
  startPhysics(null);
  const body = await fetchText(`data/cells/${name}.json`);
  await cellFiles();
  let made;
  try {
    made = await makeCell(body, name);
  } catch (e) {
    if (e instanceof EngineError) throw new BadMessage(e.message);
    throw e;
  }
  cellSource = JSON.parse(body) as Record<string, unknown>;
  shipped = ((cellSource.arms ?? []) as { program?: unknown }[]).map((a) => programText(a.program));
  programs = [...shipped];
  const out = opened(name, made);
  if (m.programs === undefined || m.programs === null) return out;
  return [...out, ...(await runPrograms(m.programs))];
}

function opened(name: string, made: { cell: Cell; robots: Robot[]; timeline: Out[] }): Out[] {
  ({ cell, robots, timeline } = made);
  cellName = name;
  eventsSent = 0;
  running = true;
  S.unacked = 0;
  startLoop();
  return [sceneMessage(), cellMessage(), frameMessage()];
}

/** {type: "cell_run", programs: [text, ...]}: Run all. The open cell again from t = 0, each arm
 * running the program given for it (in the cell's order of arms; its lines as the cell file's
 * lines in place). A program the loader refuses leaves the cell as it was, and the refusal
 * names the arm and the line: {type: "cell_refused", arm, line (1-based, or 0), text}. */
export async function cellRunIntent(m: Msg): Promise<Out[]> {
  if (!cell || !cellName || !cellSource) throw new BadMessage("no cell is open: choose one in the Physics menu");
  return runPrograms(m.programs);
}

async function runPrograms(given: unknown): Promise<Out[]> {
  if (!cellName || !cellSource) return [];
  const arms = (cellSource.arms ?? []) as Record<string, unknown>[];
  if (!Array.isArray(given) || given.length !== arms.length)
    throw new BadMessage(`'programs' must be a list of ${arms.length} texts, one for each of the cell's arms`);
  const texts = given.map((p, i) => text({ [`programs[${i}]`]: p }, `programs[${i}]`, 100_000));
  if (cell && texts.every((t, i) => t === programs[i])) { // the programs it runs: from the start again
    cell.reset();
    eventsSent = 0;
    running = true;
    return [cellMessage(), { ...frameMessage(), fresh: true }];
  }
  let made;
  try {
    made = await makeCell(withPrograms(cellSource, texts), cellName);
  } catch (e) {
    if (!(e instanceof EngineError)) throw e;
    const where = /^\/arms\/(\d+)(?:\/program(?:\/(\d+))?)?/.exec(String((e as { json_path?: string }).json_path ?? ""));
    const arm = where ? Number(where[1]) : -1;
    return [{ type: "cell_refused", arm: arms[arm]?.name ?? null, line: where?.[2] !== undefined ? Number(where[2]) + 1 : 0,
      text: String((e as { problem?: string }).problem ?? e.message), programs: texts }];
  }
  stopTasks();
  closeCell();
  programs = texts;
  return opened(cellName, made).slice(1); // (the scene is as it was)
}

/** The physics bar's intents and STOP's pause, for the cell. */
export function cellControl(kind: string): Out[] {
  const c = cell!;
  switch (kind) {
    case "physics_run":
    case "play":
      running = true;
      break;
    case "physics_pause":
    case "pause":
      running = false;
      break;
    case "physics_step":
      running = false;
      c.step(Math.round(0.1 / c.dt));
      break;
    case "physics_reset":
      c.reset();
      eventsSent = 0;
      running = false;
      return [{ ...frameMessage(), fresh: true }];
  }
  dirty = true;
  return [frameMessage()];
}

// Real time (times the page's speed), a frame to the page each display frame it has taken.
function startLoop(): void {
  let last = performance.now();
  let owed = 0;
  let posted = -Infinity, stepped = false; // the last frame sent to the page; steps since
  loop = every(FRAME_MS, () => {
    const c = cell;
    if (!c) return false;
    const now = performance.now();
    const wall = (now - last) / 1000;
    last = now;
    let n = 0;
    if (running && !c.done) {
      owed += Math.min(wall, 0.1) * S.speed;
      n = Math.floor(owed / c.dt + 1e-9);
      owed = Math.max(0, owed - n * c.dt);
      c.step(n);
    }
    if (n > 0) stepped = true;
    if (S.unacked >= MAX_UNACKED || !(stepped || dirty)) return; // (nothing new: no frame)
    // (at most a frame every S.postMs, the page's frame rate, unless something else changed;
    // the events wait for the next, and the last steps' frame always comes)
    if (!dirty && now - posted < S.postMs) return;
    posted = now;
    stepped = false;
    dirty = false;
    S.unacked++;
    post([frameMessage()]);
  });
}

// A cell's arm on a Nano of its own (panels/cell-nanos.ts: its own virtual Nano or a real one):
// the arm link's three questions (engine/arm.ts) for that arm's robot, {arm: its index}.
function armRobot(m: Msg): Robot {
  if (!cell) throw new BadMessage("no cell is open: choose one in the Physics menu");
  return robots[num(m, "arm", 0, robots.length - 1) | 0];
}
export const cellArmHandlers: Record<string, (m: Msg) => Out[]> = {
  // the open cell's mat: a 1:1 drawing from above (SVG, mm) to print (host/physics/mat.h)
  cell_mat() {
    if (!cell || !cellName) throw new BadMessage("no cell is open: choose one in the Physics menu");
    return [{ type: "cell_mat", name: cellName, svg: cell.matSvg() }];
  },
  cell_arm_read: (m) => [armRead(armRobot(m), m)],
  cell_arm_config: (m) => [armConfig(armRobot(m))],
  cell_arm_predict: (m) => [armPredict(armRobot(m), m)],
  // {arm, q, gripper_mm}: the arm's frames (and fingers) at joints q, in its base frame
  cell_arm_pose(m) {
    const r = armRobot(m);
    const n = (r.info as unknown as RobotInfo).num_joints;
    const p = r.pose(numbers(m, "q", [n]), num(m, "gripper_mm", 0, 1000)) as { frames: number[][]; fingers?: number[][] };
    return [{ type: "cell_arm_pose", frames: p.frames.map((f) => f.map(round6)), fingers: p.fingers?.map((f) => f.map(round6)) }];
  },
};

/** An exercise's Check on a cell (engine/exercise.ts): the shipped cell `doc.name` with the
 * project's programs, run from power-up to every program's end and `settle` s more, and the
 * world it leaves: each object's place, the collisions, the deadlocks and each wait, and when
 * it ended (at another arm's output, or when its time ran out). */
export async function cellOutcome(doc: { name: string; programs: string[] }, settle: number): Promise<{
  objects: { name: string; pose: number[] }[]; events: { t: number; kind: string; arm?: string; a: string; b: string; detail?: string }[];
  waits: { arm: string; line: number; name: string; t: number; end_t: number | null; met: boolean }[];
}> {
  if (!(S.index.cells ?? []).includes(doc.name)) throw new BadMessage(`no shipped cell '${doc.name}'`);
  await cellFiles();
  const source = JSON.parse(await fetchText(`data/cells/${doc.name}.json`)) as Record<string, unknown>;
  const arms = (source.arms ?? []) as Record<string, unknown>[];
  if (doc.programs.length !== arms.length) throw new BadMessage(`the cell '${doc.name}' has ${arms.length} arms: the project gives ${doc.programs.length} programs`);
  let c: Cell;
  try {
    c = S.engine.cell(withPrograms(source, doc.programs), `${doc.name}.json`, "/cells");
  } catch (e) {
    if (e instanceof EngineError) throw new BadMessage(e.message);
    throw e;
  }
  try {
    c.run();
    c.runUntil(c.time + settle);
    const st = c.state() as unknown as CellState;
    const events = c.events(0) as never;
    const waits = st.arms.flatMap((a) => a.signals.filter((x) => x.kind === "wait").map((x) => ({
      arm: a.name, line: x.line, name: x.name, t: x.t, end_t: x.end_t ?? null, met: x.met === true,
    })));
    return { objects: st.objects, events, waits };
  } finally {
    c.delete();
  }
}
