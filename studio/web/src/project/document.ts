// A project: what is on screen (the robot, the scene, the program as text or blocks, the pose)
// and, for an exercise, its goal. One document format for the browser's store, the .articula
// file and the share link; every one of them is untrusted input and goes through
// `readProject`, which names the problem and where it is (docs/studio.md, "Projects").
import { BLOCK_TYPES } from "../blocks/unroll";

export const FORMAT = "articula-project";
export const VERSION = 1;
export const MAX_FILE_BYTES = 30_000_000; // a .articula file, meshes included
const MAX_TEXT = 1_000_000; // a program's or a robot file's text
const MAX_NAME = 200;
const MAX_BLOCKS_JSON = 2_000_000;
export const MAX_NOTE = 2000; // a teacher's note, characters

/** One part of an exercise's goal: the tool at a point, or an object inside a box. */
export type GoalPart =
  | { kind: "reach"; xyz: number[]; tolerance_mm: number }
  | { kind: "object"; object: string; min: number[]; max: number[]; label: string }
  | DrawingPart
  // a cell's (the project's cell, run from power-up with its arms' programs): no arm hits
  // anything; every arm's program runs to its end with no wait running out and no deadlock
  | { kind: "no_collision"; label: string }
  | { kind: "programs_end"; label: string }
  // ... and the arm waits (W) on its input, until another arm's output ends the wait
  | { kind: "waits_for"; arm: string; input: string; label: string };

/** A drawing to draw with a pen in the gripper: the ink of the program (its prediction) within
 * `tolerance_mm` of the target and covering it. The target is a drawing request (a shape, or
 * text: `ask` names what the student types instead, "your initials"), on paper at `z` with a
 * pen `pen` mm long. */
export interface DrawingPart {
  kind: "drawing"; target: { shape?: string; text?: string; width: number; at: number[]; rotate?: number };
  ask: string; tolerance_mm: number; z: number; pen: number; label: string;
}

/** An exercise's goal; `scene`: where its objects are (Check runs the physics there). */
export interface Goal { title: string; text: string; scene: string; parts: GoalPart[] }

/** A pose of the sim-vs-real experiment: where the model puts the tool (ideal: the exact
 * angles; quant: the whole steps) and where the student measured it (null: not measured). */
export interface ExperimentPoint {
  joint: number; angle: number; line: number; command: string;
  ideal: number[]; quant: number[]; measured: number[] | null;
}
/** A repeatability chain (thesis 5.3): the model's tool before it, at its destination (whole
 * steps and exact angles) and back; what was measured (null: not); the arm's steps back at
 * the start (null: it did not come back). */
export interface ExperimentChain {
  chain: number; moves: number; back_moves: number; line_before?: number | null; line_out: number; line_back: number | null;
  start: number[]; dest_quant: number[]; dest_ideal: number[]; back_quant: number[] | null;
  start_measured: number[] | null; dest_measured: number[] | null; back_measured: number[] | null; steps_back: boolean | null;
}
/** The tool sent to a point (P): the target, the model's tool (whole steps; exact angles), and
 * where it was measured (null: not). */
export interface ExperimentTarget { line: number; command: string; target: number[]; quant: number[]; ideal: number[]; measured: number[] | null }
/** The experiment's measurements (the tables and plots are made from them again on opening). */
export interface Experiment {
  plan: string; title: string; robot: string; when: string; points: ExperimentPoint[]; chains?: ExperimentChain[];
  targets?: ExperimentTarget[];
}

export interface Project {
  format: typeof FORMAT;
  version: number;
  name: string;
  robot: { shipped: string } | { file: { name: string; text: string; legacy: boolean; scale: number }; meshes: { name: string; data: string }[] };
  scene: string; // "" for none
  world?: object | null; // a scene of the student's own (a scene file's JSON: scenes/README.md), in place of `scene`
  program: { mode: "text" | "blocks"; name: string; text: string; blocks: object | null };
  pose: { q: number[]; gripper: number } | null;
  view?: { eye: number[]; target: number[] } | null; // the camera (mm)
  goal: Goal | null;
  experiment?: Experiment | null;
  paper?: Paper | null; // Draw and write's sheet and pen (the robot file stays as it is)
  cell?: CellDoc | null; // a cell of arms open (its robot, scene and program then stand aside)
  note?: string; // a teacher's note, shown first when the project opens from a link or a file ("": none)
}

/** A shipped cell (cells/), with each arm's program as the project has it, in the cell's order of arms. */
export interface CellDoc { name: string; programs: string[] }

const MAX_CELL_ARMS = 8; // (as cells/README.md allows)
const MAX_WORLD = 100_000; // a scene of the student's own, as text (the engine's limit too)

/** The sheet on the table (its size, centre, whether it lies landscape), its height and the pen's length, mm. */
export interface Paper { sheet: "A4" | "A5" | "Letter"; at: number[]; landscape: boolean; z: number; pen: number }

/** A document that is not a project, or not one this studio can open: `where` names the field. */
export class ProjectError extends Error {}

export function newProject(name: string, robot = "mk2plus", scene = ""): Project {
  return { format: FORMAT, version: VERSION, name, robot: { shipped: robot }, scene,
    program: { mode: "text", name: "program.arm", text: "", blocks: null }, pose: null, goal: null };
}

type J = Record<string, unknown>;
const isObj = (x: unknown): x is J => typeof x === "object" && x !== null && !Array.isArray(x);

function str(o: J, key: string, where: string, limit: number): string {
  const v = o[key];
  if (typeof v !== "string") throw new ProjectError(`${where}.${key} must be text`);
  if (v.length > limit) throw new ProjectError(`${where}.${key} is longer than ${limit.toLocaleString("en")} characters`);
  return v;
}

function nums(v: unknown, where: string, n?: number, limit = 1e6): number[] {
  if (!Array.isArray(v) || (n !== undefined && v.length !== n) || v.length > 64)
    throw new ProjectError(`${where} must be a list of ${n ?? "up to 64"} numbers`);
  return v.map((x, i) => {
    if (typeof x !== "number" || !Number.isFinite(x) || Math.abs(x) > limit) throw new ProjectError(`${where}[${i}] must be a number`);
    return x;
  });
}

/** Blockly's JSON of a workspace, checked: only the arm's and the beginner's block types, no
 * deeper than a program needs. Its strings stay strings: Blockly shows them as text. */
function checkBlocks(b: unknown): object | null {
  if (b === null || b === undefined) return null;
  if (!isObj(b)) throw new ProjectError("program.blocks must be Blockly's JSON of a workspace");
  if (JSON.stringify(b).length > MAX_BLOCKS_JSON) throw new ProjectError("program.blocks is too large");
  const walk = (x: unknown, depth: number, where: string): void => {
    if (depth > 400) throw new ProjectError(`${where}: the blocks nest too deeply`);
    if (Array.isArray(x)) return x.forEach((y, i) => walk(y, depth + 1, `${where}[${i}]`));
    if (!isObj(x)) return;
    if ("type" in x && (where.endsWith(".block") || where.endsWith(".shadow") || /blocks\[\d+\]$/.test(where))) {
      if (typeof x.type !== "string" || !BLOCK_TYPES.has(x.type))
        throw new ProjectError(`${where}: "${String(x.type).slice(0, 60)}" is not a block of Articula's`);
    }
    for (const [k, v] of Object.entries(x)) walk(v, depth + 1, `${where}.${k}`);
  };
  walk(b, 0, "program.blocks");
  return b;
}

function checkGoal(g: unknown): Goal | null {
  if (g === null || g === undefined) return null;
  if (!isObj(g)) throw new ProjectError("goal must be an object");
  const parts = g.parts;
  if (!Array.isArray(parts) || parts.length === 0 || parts.length > 50) throw new ProjectError("goal.parts must be a list of 1 to 50 parts");
  return {
    title: str(g, "title", "goal", MAX_NAME),
    text: str(g, "text", "goal", 5000),
    scene: typeof g.scene === "string" ? g.scene.slice(0, MAX_NAME) : "",
    parts: parts.map((p, i): GoalPart => {
      const where = `goal.parts[${i}]`;
      if (!isObj(p)) throw new ProjectError(`${where} must be an object`);
      if (p.kind === "reach") {
        const tol = nums([p.tolerance_mm], `${where}.tolerance_mm`, 1)[0];
        if (tol <= 0) throw new ProjectError(`${where}.tolerance_mm must be above 0`);
        return { kind: "reach", xyz: nums(p.xyz, `${where}.xyz`, 3), tolerance_mm: tol };
      }
      if (p.kind === "object")
        return { kind: "object", object: str(p, "object", where, MAX_NAME), min: nums(p.min, `${where}.min`, 3),
          max: nums(p.max, `${where}.max`, 3), label: typeof p.label === "string" ? p.label.slice(0, MAX_NAME) : "" };
      if (p.kind === "drawing") {
        const t = p.target;
        if (!isObj(t)) throw new ProjectError(`${where}.target must be an object: a shape or text, its width and place`);
        const target: DrawingPart["target"] = { width: nums([t.width], `${where}.target.width`, 1, 500)[0], at: nums(t.at, `${where}.target.at`, 2) };
        if (t.shape !== undefined) {
          if (!["square", "circle", "star"].includes(t.shape as string)) throw new ProjectError(`${where}.target.shape must be square, circle or star`);
          target.shape = t.shape as string;
        }
        if (t.text !== undefined) target.text = str(t, "text", `${where}.target`, 40);
        if (t.rotate !== undefined) target.rotate = nums([t.rotate], `${where}.target.rotate`, 1, 360)[0];
        const ask = typeof p.ask === "string" ? p.ask.slice(0, MAX_NAME) : "";
        if (!target.shape && !target.text && !ask) throw new ProjectError(`${where}.target needs a shape or a text (or ask for one)`);
        const tol = nums([p.tolerance_mm], `${where}.tolerance_mm`, 1, 50)[0];
        if (tol <= 0) throw new ProjectError(`${where}.tolerance_mm must be above 0`);
        return { kind: "drawing", target, ask, tolerance_mm: tol, z: nums([p.z ?? 0], `${where}.z`, 1, 1000)[0],
          pen: nums([p.pen ?? 0], `${where}.pen`, 1, 1000)[0], label: typeof p.label === "string" ? p.label.slice(0, MAX_NAME) : "" };
      }
      const label = typeof p.label === "string" ? p.label.slice(0, MAX_NAME) : "";
      if (p.kind === "no_collision" || p.kind === "programs_end") return { kind: p.kind, label };
      if (p.kind === "waits_for") return { kind: "waits_for", arm: str(p, "arm", where, MAX_NAME), input: str(p, "input", where, MAX_NAME), label };
      throw new ProjectError(`${where}.kind must be "reach", "object", "drawing", "no_collision", "programs_end" or "waits_for"`);
    }),
  };
}

function checkExperiment(e: unknown): Experiment | null {
  if (e === null || e === undefined) return null;
  if (!isObj(e)) throw new ProjectError("experiment must be an object");
  const points = e.points;
  if (!Array.isArray(points) || points.length > 1000) throw new ProjectError("experiment.points must be a list of up to 1000 poses");
  const chains = e.chains ?? [];
  if (!Array.isArray(chains) || chains.length > 100) throw new ProjectError("experiment.chains must be a list of up to 100 chains");
  const xyzOrNull = (v: unknown, where: string) => (v === null || v === undefined ? null : nums(v, where, 3));
  const targets = e.targets ?? [];
  if (!Array.isArray(targets) || targets.length > 1000) throw new ProjectError("experiment.targets must be a list of up to 1000 points");
  return {
    targets: targets.map((t, i) => {
      const where = `experiment.targets[${i}]`;
      if (!isObj(t)) throw new ProjectError(`${where} must be an object`);
      return { line: nums([t.line], `${where}.line`, 1)[0], command: str(t, "command", where, MAX_NAME), target: nums(t.target, `${where}.target`, 3),
        quant: nums(t.quant, `${where}.quant`, 3), ideal: nums(t.ideal, `${where}.ideal`, 3), measured: xyzOrNull(t.measured, `${where}.measured`) };
    }),
    chains: chains.map((c, i) => {
      const where = `experiment.chains[${i}]`;
      if (!isObj(c)) throw new ProjectError(`${where} must be an object`);
      const [chain, moves, back_moves, line_out] = nums([c.chain, c.moves, c.back_moves, c.line_out], where, 4);
      return { chain, moves, back_moves, line_out, line_back: c.line_back == null ? null : nums([c.line_back], `${where}.line_back`, 1)[0],
        line_before: c.line_before == null ? null : nums([c.line_before], `${where}.line_before`, 1)[0],
        start: nums(c.start, `${where}.start`, 3), dest_quant: nums(c.dest_quant, `${where}.dest_quant`, 3),
        dest_ideal: nums(c.dest_ideal, `${where}.dest_ideal`, 3), back_quant: xyzOrNull(c.back_quant, `${where}.back_quant`),
        start_measured: xyzOrNull(c.start_measured, `${where}.start_measured`), dest_measured: xyzOrNull(c.dest_measured, `${where}.dest_measured`),
        back_measured: xyzOrNull(c.back_measured, `${where}.back_measured`), steps_back: typeof c.steps_back === "boolean" ? c.steps_back : null };
    }),
    plan: str(e, "plan", "experiment", MAX_NAME), title: str(e, "title", "experiment", MAX_NAME),
    robot: str(e, "robot", "experiment", MAX_NAME), when: str(e, "when", "experiment", MAX_NAME),
    points: points.map((p, i) => {
      const where = `experiment.points[${i}]`;
      if (!isObj(p)) throw new ProjectError(`${where} must be an object`);
      const [joint, angle, line] = nums([p.joint, p.angle, p.line], where, 3);
      if (!Number.isInteger(joint) || joint < 0 || joint > 63) throw new ProjectError(`${where}.joint must be a joint index`);
      return { joint, angle, line, command: str(p, "command", where, MAX_NAME), ideal: nums(p.ideal, `${where}.ideal`, 3),
        quant: nums(p.quant, `${where}.quant`, 3), measured: p.measured === null ? null : nums(p.measured, `${where}.measured`, 3) };
    }),
  };
}

/** A project from untrusted JSON (a file, a link, the browser's store). Throws ProjectError. */
export function readProject(x: unknown): Project {
  if (!isObj(x) || x.format !== FORMAT) throw new ProjectError("this is not an Articula project");
  if (typeof x.version !== "number" || !Number.isInteger(x.version) || x.version < 1)
    throw new ProjectError("its version is not a version number");
  if (x.version > VERSION)
    throw new ProjectError(`it was made by a newer Articula (project version ${x.version}; this studio reads up to ${VERSION}): update the studio`);
  const name = str(x, "name", "project", MAX_NAME);
  const r = x.robot;
  let robot: Project["robot"];
  if (isObj(r) && "shipped" in r) robot = { shipped: str(r, "shipped", "robot", MAX_NAME) };
  else if (isObj(r) && isObj(r.file)) {
    const f = r.file;
    const meshes = r.meshes ?? [];
    if (!Array.isArray(meshes) || meshes.length > 100) throw new ProjectError("robot.meshes must be a list of up to 100 meshes");
    robot = {
      file: { name: str(f, "name", "robot.file", MAX_NAME), text: str(f, "text", "robot.file", MAX_TEXT), legacy: f.legacy === true,
        scale: typeof f.scale === "number" && f.scale > 0 ? f.scale : 1 },
      meshes: meshes.map((m, i) => {
        if (!isObj(m)) throw new ProjectError(`robot.meshes[${i}] must be an object`);
        const data = str(m, "data", `robot.meshes[${i}]`, MAX_FILE_BYTES * 2);
        if (!/^[A-Za-z0-9+/]*={0,2}$/.test(data)) throw new ProjectError(`robot.meshes[${i}].data is not base64`);
        return { name: str(m, "name", `robot.meshes[${i}]`, MAX_NAME), data };
      }),
    };
  } else throw new ProjectError("robot must name a shipped robot or hold a robot file");
  const scene = x.scene === undefined || x.scene === null ? "" : str(x, "scene", "project", MAX_NAME);
  // (its form only; the engine's scene loader checks what is in it, as any scene file's)
  let world: object | null = null;
  if (x.world !== null && x.world !== undefined) {
    if (!isObj(x.world)) throw new ProjectError("world must be a scene (an object)");
    if (JSON.stringify(x.world).length > MAX_WORLD) throw new ProjectError(`world is longer than ${MAX_WORLD.toLocaleString("en")} characters`);
    world = x.world;
  }
  const p = x.program;
  if (!isObj(p)) throw new ProjectError("program must be an object");
  const mode = p.mode === "blocks" ? "blocks" : p.mode === "text" ? "text" : null;
  if (!mode) throw new ProjectError('program.mode must be "text" or "blocks"');
  const program = { mode, name: str(p, "name", "program", MAX_NAME), text: str(p, "text", "program", MAX_TEXT), blocks: checkBlocks(p.blocks) } as Project["program"];
  let pose: Project["pose"] = null;
  if (x.pose !== null && x.pose !== undefined) {
    if (!isObj(x.pose)) throw new ProjectError("pose must be an object");
    const grip = nums([x.pose.gripper], "pose.gripper", 1)[0];
    pose = { q: nums(x.pose.q, "pose.q"), gripper: Math.min(100, Math.max(0, grip)) };
  }
  let view: Project["view"] = null;
  if (x.view !== null && x.view !== undefined) {
    if (!isObj(x.view)) throw new ProjectError("view must be an object");
    view = { eye: nums(x.view.eye, "view.eye", 3), target: nums(x.view.target, "view.target", 3) };
  }
  let paper: Paper | null = null;
  if (x.paper !== null && x.paper !== undefined) {
    const q = x.paper;
    if (!isObj(q)) throw new ProjectError("paper must be an object");
    if (q.sheet !== "A4" && q.sheet !== "A5" && q.sheet !== "Letter") throw new ProjectError('paper.sheet must be "A4", "A5" or "Letter"');
    const pen = nums([q.pen], "paper.pen", 1, 1000)[0];
    if (pen < 0) throw new ProjectError("paper.pen must be 0 mm or more");
    paper = { sheet: q.sheet, at: nums(q.at, "paper.at", 2, 10000), landscape: q.landscape === true, z: nums([q.z], "paper.z", 1, 10000)[0], pen };
  }
  return { format: FORMAT, version: VERSION, name, robot, scene, ...(world ? { world } : {}), program, pose, view, goal: checkGoal(x.goal),
    experiment: checkExperiment(x.experiment), paper, cell: checkCell(x.cell),
    ...(x.note === undefined || x.note === null || x.note === "" ? {} : { note: str(x, "note", "project", MAX_NOTE) }) };
}

// (a cell's name and programs are checked here for their form; the engine's cell loader checks
// that the cell is shipped and that each program fits its arm)
function checkCell(c: unknown): CellDoc | null {
  if (c === null || c === undefined) return null;
  if (!isObj(c)) throw new ProjectError("cell must be an object");
  const programs = c.programs;
  if (!Array.isArray(programs) || programs.length < 1 || programs.length > MAX_CELL_ARMS)
    throw new ProjectError(`cell.programs must be a list of 1 to ${MAX_CELL_ARMS} programs, one for each arm`);
  return {
    name: str(c, "name", "cell", MAX_NAME),
    programs: programs.map((p, i) => {
      if (typeof p !== "string") throw new ProjectError(`cell.programs[${i}] must be text`);
      if (p.length > MAX_TEXT) throw new ProjectError(`cell.programs[${i}] is longer than ${MAX_TEXT.toLocaleString("en")} characters`);
      return p;
    }),
  };
}

/** A project from a file's or a link's text. Throws ProjectError. */
export function parseProject(text: string): Project {
  if (text.length > MAX_FILE_BYTES * 1.5) throw new ProjectError(`it is larger than ${MAX_FILE_BYTES / 1e6} MB`);
  let x: unknown;
  try {
    x = JSON.parse(text);
  } catch (e) {
    throw new ProjectError(`it is not JSON (${(e as Error).message})`);
  }
  return readProject(x);
}

// ---- The share link: the project, compressed, in the address's fragment -----------------

export const LINK_KEY = "project=";
export const MAX_LINK = 100_000; // characters of a link's fragment the page reads
const MAX_UNPACKED = 4_000_000;

async function pipe(data: Uint8Array, stream: CompressionStream | DecompressionStream, limit: number): Promise<Uint8Array> {
  const out = new Blob([data as BlobPart]).stream().pipeThrough(stream).getReader();
  const chunks: Uint8Array[] = [];
  let n = 0;
  for (;;) {
    const { done, value } = await out.read();
    if (done) break;
    n += value.length;
    if (n > limit) {
      await out.cancel();
      throw new ProjectError(`it unpacks to more than ${limit / 1e6} MB`);
    }
    chunks.push(value);
  }
  const all = new Uint8Array(n);
  let at = 0;
  for (const c of chunks) {
    all.set(c, at);
    at += c.length;
  }
  return all;
}

function base64url(bytes: Uint8Array): string {
  let s = "";
  for (let i = 0; i < bytes.length; i += 0x8000) s += String.fromCharCode(...bytes.subarray(i, i + 0x8000));
  return btoa(s).replace(/\+/g, "-").replace(/\//g, "_").replace(/=+$/, "");
}

function unbase64url(s: string): Uint8Array {
  const bad = s.search(/[^A-Za-z0-9_-]/);
  if (bad >= 0) throw new ProjectError(`it holds a character a project link never has, at position ${bad + 1}`);
  let bin: string;
  try {
    bin = atob(s.replace(/-/g, "+").replace(/_/g, "/"));
  } catch {
    throw new ProjectError("it was cut short (its length is not one a link can have)");
  }
  return Uint8Array.from(bin, (c) => c.charCodeAt(0));
}

/** Blockly's JSON without the blocks' own ids (random, 20 characters each, they do not
 * compress; Blockly makes new ones as it loads). A variable's id stays: blocks name it by id. */
function withoutBlockIds(x: unknown): unknown {
  if (Array.isArray(x)) return x.map(withoutBlockIds);
  if (!isObj(x)) return x;
  const out: J = {};
  const block = typeof x.type === "string" && !("name" in x);
  for (const [k, v] of Object.entries(x)) if (!(block && k === "id")) out[k] = withoutBlockIds(v);
  return out;
}

/** The fragment of a link that holds `p` ("project=..."). */
export async function projectFragment(p: Project): Promise<string> {
  const slim = p.program.blocks ? { ...p, program: { ...p.program, blocks: withoutBlockIds(p.program.blocks) as object } } : p;
  const bytes = new TextEncoder().encode(JSON.stringify(slim));
  return LINK_KEY + base64url(await pipe(bytes, new CompressionStream("deflate-raw"), Infinity));
}

/** The project a link's fragment holds. Throws ProjectError naming what is wrong. */
export async function projectOfFragment(fragment: string): Promise<Project> {
  const body = fragment.replace(/^#/, "");
  if (!body.startsWith(LINK_KEY)) throw new ProjectError("it holds no project");
  const data = body.slice(LINK_KEY.length);
  if (data.length > MAX_LINK) throw new ProjectError(`it is longer than ${MAX_LINK.toLocaleString("en")} characters`);
  let text: string;
  try {
    text = new TextDecoder("utf-8", { fatal: true }).decode(await pipe(unbase64url(data), new DecompressionStream("deflate-raw"), MAX_UNPACKED));
  } catch (e) {
    if (e instanceof ProjectError) throw e;
    throw new ProjectError("it is damaged or was cut short: the project in it cannot be unpacked");
  }
  return parseProject(text);
}
