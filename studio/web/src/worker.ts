// The studio's engine in a Web Worker: the web engine (wasm/, the same C++ as the CLI and
// the Python package) and one page's session - the robot shown, its pose, the program's time
// line, the Jacobian transpose animated, the live physics. The page posts intents (the
// messages of protocol.ts) and draws what comes back; nothing here blocks its drawing.
//
// Every pose, solve, prediction and physics step is the engine's: this file only keeps the
// state of the page and turns intents into engine calls (docs/studio.md, "What runs where").
import type { Engine, Robot, Sim } from "../../../wasm/js/engine.mjs";
import { EngineError, loadEngine } from "../../../wasm/js/engine.mjs";

type Msg = Record<string, unknown>;
type Out = Record<string, unknown>;

const FRAME_MS = 1000 / 60;
const MAX_TEXT = 1_000_000; // characters of a robot file or program from the page
const PHYSICS_INTENTS = new Set(["set_joint", "set_joints", "home", "zero", "ik", "gripper", "drag", "release",
  "physics_run", "physics_pause", "physics_step", "physics_reset", "program_load", "play", "pause"]);

class BadMessage extends Error {}

// ---- checks of what the page sends (a bad message gets an error reply, never a crash)

function num(m: Msg, key: string, lo = -Infinity, hi = Infinity): number {
  const v = m[key];
  if (typeof v !== "number" || !Number.isFinite(v)) throw new BadMessage(`'${key}' must be a finite number`);
  if (v < lo || v > hi) throw new BadMessage(`'${key}' must be within ${lo} .. ${hi}`);
  return v;
}

function numbers(m: Msg, key: string, counts: number[]): number[] {
  const v = m[key];
  if (!Array.isArray(v) || !counts.includes(v.length))
    throw new BadMessage(`'${key}' must be a list of ${counts.join(" or ")} numbers`);
  return v.map((x, i) => {
    if (typeof x !== "number" || !Number.isFinite(x)) throw new BadMessage(`'${key}[${i}]' must be a finite number`);
    return x;
  });
}

function text(m: Msg, key: string, limit = MAX_TEXT): string {
  const v = m[key];
  if (typeof v !== "string") throw new BadMessage(`'${key}' must be text`);
  if (v.length > limit) throw new BadMessage(`'${key}' is larger than ${limit.toLocaleString("en")} characters`);
  return v;
}

const round6 = (x: number) => Math.round(x * 1e6) / 1e6;
const clamp = (v: number, lo: number, hi: number) => Math.min(Math.max(v, lo), hi);

// ---- the site's files: robots, scenes, programs (make web writes data/index.json)

interface SiteIndex { robots: string[]; scenes: string[]; programs: string[]; meshes: string[] }
const site = new URL("./", self.location.href.replace(/assets\/[^/]*$/, ""));
let index: SiteIndex = { robots: [], scenes: [], programs: [], meshes: [] };

async function fetchText(path: string): Promise<string> {
  const r = await fetch(new URL(path, site));
  if (!r.ok) throw new Error(`${path}: ${r.status} ${r.statusText}`);
  return r.text();
}

async function fetchBytes(path: string): Promise<Uint8Array> {
  const r = await fetch(new URL(path, site));
  if (!r.ok) throw new Error(`${path}: ${r.status} ${r.statusText}`);
  return new Uint8Array(await r.arrayBuffer());
}

// ---- the session

interface TimelineRecord {
  line: number; command: string; reply: string; code: number; error: string; note: string;
  start_s: number; end_s: number; q: number[]; q_ideal: number[]; tool: number[]; tool_ideal: number[];
  error_mm: number; steps: number[] | null; gripper: number | null;
}

let engine: Engine;
let robot: Robot;
let q: number[] = [];
let gripper = 100; // percent open
let timeline: { records: TimelineRecord[]; startQ: number[]; duration: number } | null = null;
let t = 0; // the time line's clock, s
let speed = 1;
let task: ReturnType<typeof setTimeout> | null = null; // playback or the JT animation
// Live physics: the scene's name (null: none), its simulation, the events sent so far.
let sceneName: string | null = null;
let sim: Sim | null = null;
let eventsSent = 0;
let physicsRunning = true;
let physicsTimer: ReturnType<typeof setTimeout> | null = null;
let pendingMove: string | null = null;
let pendingGrip: string | null = null;
const meshUrls = new Map<string, string>(); // engine path -> blob URL the page draws
let greeted = false; // the page said hello: it has the robot, poses may stream

function post(msgs: Out[]): void {
  for (const m of msgs) (self as unknown as Worker).postMessage(m);
}

function info() {
  return robot.info as {
    name: string; description: string; source: string; joints: { name: string }[]; dh: unknown[];
    num_rows: number; num_joints: number; num_motors: number; home: number[]; limits: [number, number][];
    motors: { name: string; zero: number }[]; links: { frame: number; shapes: { type: string; size: number[];
    pose: number[]; mesh?: string }[] }[]; gripper: null | { max_opening_mm: number }; reach_mm: number;
    import_notes: string[]; joint_names: string[];
  };
}

function meshUrl(path: string): string {
  let url = meshUrls.get(path);
  if (!url) {
    url = URL.createObjectURL(new Blob([engine.readFile(path) as Uint8Array<ArrayBuffer>]));
    meshUrls.set(path, url);
  }
  return url;
}

function robotMessage(): Out {
  const r = info();
  const links = r.links.map((l) => ({
    frame: l.frame,
    shapes: l.shapes.map((s) => {
      const shape: Out = { type: s.type, size: s.size, pose: s.pose.map(round6) };
      if (s.type === "mesh" && s.mesh) {
        shape.url = meshUrl(s.mesh);
        shape.format = s.mesh.split(".").pop()!.toLowerCase();
      }
      return shape;
    }),
  }));
  return {
    type: "robot", name: r.name, description: r.description, source: r.source, joints: r.joints, dh: r.dh,
    num_rows: r.num_rows, home: r.home, motors: r.motors.map((m) => m.name), links, gripper: r.gripper,
    reach_mm: r.reach_mm, robots: index.robots, programs: index.programs, scenes: index.scenes,
    import_notes: r.import_notes,
  };
}

function poseMessage(at: number[] = q, extra: Out = {}): Out {
  const r = info();
  const opening = r.gripper ? (r.gripper.max_opening_mm * gripper) / 100 : NaN;
  const p = robot.pose(at, opening) as { frames: number[][]; tool: unknown; dh_table: number[][];
    within_limits: boolean; fingers?: number[][] };
  const msg: Out = {
    type: "pose", q: at, frames: p.frames.map((f) => f.map(round6)), tool: p.tool, dh_table: p.dh_table,
    gripper, within_limits: p.within_limits,
  };
  if (p.fingers) msg.fingers = p.fingers.map((f) => f.map(round6));
  return Object.assign(msg, extra);
}

function adopt(r: Robot): void {
  const old = robot;
  robot = r;
  if (old && old !== r) old.delete();
  q = [...info().home];
  gripper = 100;
  timeline = null;
  if (sceneName !== null) startPhysics(sceneName);
}

function powerUpQ(): number[] {
  const r = info();
  return robot.jointsFromMotors(r.motors.map((m) => m.zero)) as number[];
}

function clampQ(v: number[]): number[] {
  return v.map((x, j) => clamp(x, info().limits[j][0], info().limits[j][1]));
}

async function shippedRobot(name: string): Promise<Robot> {
  if (!index.robots.includes(name)) throw new BadMessage(`no shipped robot '${name}'`);
  const path = `/robots/${name}.json`;
  if (!engine.exists(path)) engine.writeFile(path, await fetchText(`data/robots/${name}.json`));
  const r = engine.robot(name);
  // Its meshes, from the site, where the robot file says they are (relative to it).
  for (const l of (r.info as ReturnType<typeof info>).links)
    for (const s of l.shapes)
      if (s.mesh && !engine.exists(s.mesh)) engine.writeFile(s.mesh, await fetchBytes(`data${s.mesh}`));
  return r;
}

// A robot file on the web (?robot=path/arm.json, relative to the site: articula-studio serves
// the file it was started with so), with the meshes its shapes name beside it.
async function urlRobot(path: string): Promise<Robot> {
  const url = new URL(path, site);
  const name = decodeURIComponent(url.pathname.split("/").pop() ?? "robot.json");
  userFiles({});
  const r = engine.robot();
  try {
    r.parse(await fetchText(url.href), name);
    for (const l of (r.info as ReturnType<typeof info>).links)
      for (const s of l.shapes)
        if (s.mesh && !engine.exists(s.mesh))
          engine.writeFile(s.mesh, await fetchBytes(new URL(s.mesh.replace(/^\/user\//, ""), url).href));
  } catch (e) {
    r.delete();
    throw e;
  }
  return r;
}

// ---- messages

type Handler = (m: Msg) => Out[] | Promise<Out[]>;

const handlers: Record<string, Handler> = {
  hello: () => {
    greeted = true;
    if (sim) setTimeout(ensurePhysics, 0); // after these replies: the page has its robot first
    return [robotMessage(), sceneMessage(), physicsMessage(), poseMessage()];
  },

  set_joint(m) {
    const j = num(m, "joint", 0, info().num_joints - 1);
    if (!Number.isInteger(j)) throw new BadMessage("'joint' must be a whole number");
    const [lo, hi] = info().limits[j];
    q = [...q];
    q[j] = clamp(num(m, "value"), lo, hi);
    return [poseMessage(q, { seq: m.seq ?? null })];
  },
  set_joints(m) {
    q = clampQ(numbers(m, "q", [info().num_joints]));
    return [poseMessage(q, { seq: m.seq ?? null })];
  },
  home: () => {
    q = [...info().home];
    return [poseMessage()];
  },
  // The motors' zero angles (where the real arm powers up), or all joint variables 0 (clamped
  // into the limits) for a robot without motors.
  zero: () => {
    q = info().num_motors ? powerUpQ() : clampQ(q.map(() => 0));
    return [poseMessage()];
  },
  gripper(m) {
    if (!info().gripper) throw new BadMessage(`${info().name} has no gripper`);
    gripper = num(m, "percent", 0, 100);
    return [poseMessage()];
  },

  // Solve for a target and move there (to the best pose found when not reached).
  ik(m) {
    const res = solve(ikArgs(m));
    q = res.q;
    return [ikReply(res, m.seq), poseMessage(q, { seq: m.seq ?? null })];
  },
  jt_animate(m) {
    const args = ikArgs(m);
    args.solver = "jt";
    let i = 0;
    const frame = () => {
      const res = solve({ ...args, start: q, max_iterations: 1 });
      const moved = Math.max(...res.q.map((v: number, k: number) => Math.abs(v - q[k])));
      q = res.q;
      const done = res.status !== "budget" || moved < 1e-9 || i + 1 >= 400;
      let last = res;
      if (done && res.status === "budget" && i + 1 < 400) {
        // It stopped moving short of the target: the solver's own verdict from here.
        last = solve({ ...args, start: q });
        q = last.q;
      }
      post([{ ...ikReply(last, m.seq), type: "jt_frame", iteration: i + 1, done }, poseMessage(q, { seq: m.seq ?? null })]);
      i++;
      task = done ? null : setTimeout(frame, FRAME_MS);
    };
    stopTasks();
    frame();
    return [];
  },
  stop_animation: () => {
    stopTasks();
    return [poseMessage()];
  },

  // ---- programs

  async program_open(m) {
    const name = text(m, "name", 200);
    if (!index.programs.includes(name)) throw new BadMessage(`no shipped program '${name}'`);
    return [{ type: "program_text", name, text: await fetchText(`data/programs/${name}`) }];
  },
  // Predict (robots with motors) or run (kinematic robots) a program: the time line the page
  // plays. A program that cannot be read is an error naming the line.
  program_load(m) {
    const src = text(m, "text");
    const name = (typeof m.name === "string" && m.name) || "program.arm";
    const r = info();
    let doc: { records: Record<string, unknown>[]; summary: Record<string, number> };
    let records: Record<string, unknown>[];
    try {
      if (r.num_motors) {
        doc = robot.predict(src, name) as typeof doc;
        records = doc.records;
      } else {
        doc = robot.run(src, name) as typeof doc;
        records = timed(doc.records);
      }
    } catch (e) {
      if (e instanceof EngineError) return [{ type: "program_error", message: e.message, line: (e as { line?: number }).line ?? 0 }];
      throw e;
    }
    const steps: TimelineRecord[] = records.map((rec) => {
      const qr = rec.joints as number[];
      const qi = (rec.joints_ideal as number[] | undefined) ?? qr;
      return {
        line: rec.line as number, command: rec.command as string, reply: rec.reply as string, code: rec.code as number,
        error: (rec.error as string) ?? "", note: (rec.note as string) ?? "", start_s: rec.start_s as number,
        end_s: rec.end_s as number, q: qr, q_ideal: qi, tool: toolAt(qr), tool_ideal: toolAt(qi),
        error_mm: (rec.error_mm as number) ?? 0, steps: (rec.steps as number[]) ?? null,
        gripper: (rec.gripper_percent as number | null) ?? null,
      };
    });
    const startQ = r.num_motors ? powerUpQ() : [...q];
    timeline = { records: steps, startQ, duration: steps.length ? steps[steps.length - 1].end_s : 0 };
    q = [...startQ];
    t = 0;
    return [{ type: "timeline", name, format: robot.programFormat(src, name), records: steps, duration: timeline.duration,
      joints: r.joint_names, summary: doc.summary }, poseMessage(q, { t: 0, line: 0 })];
  },
  play(m) {
    const tl = needTimeline();
    if ("speed" in m) speed = num(m, "speed", 0.05, 20);
    stopTasks();
    if (t >= tl.duration) t = 0;
    let last = performance.now();
    post([{ type: "playing", t, playing: true }]);
    const frame = () => {
      const now = performance.now();
      t = Math.min(tl.duration, t + ((now - last) / 1000) * speed);
      last = now;
      post([poseAt(t)]);
      if (t >= tl.duration) {
        task = null;
        post([{ type: "playing", t, playing: false, ended: true }]);
        return;
      }
      task = setTimeout(frame, FRAME_MS);
    };
    frame();
    return [];
  },
  pause: () => {
    stopTasks();
    return [{ type: "playing", t, playing: false }];
  },
  // To the end of the next action (a line).
  step: () => {
    const tl = needTimeline();
    stopTasks();
    const next = tl.records.find((r) => r.end_s > t + 1e-9);
    t = next ? next.end_s : tl.duration;
    return [poseAt(t), { type: "playing", t, playing: false }];
  },
  seek(m) {
    const tl = needTimeline();
    stopTasks();
    t = num(m, "t", 0, tl.duration + 1e-9);
    return [poseAt(t), { type: "playing", t, playing: false }];
  },
  rewind: () => {
    needTimeline();
    stopTasks();
    t = 0;
    return [poseAt(0), { type: "playing", t: 0, playing: false }];
  },
  // The current pose as a program line (RoboSim's Teach): `M` with the motor angles (joint
  // variables for a robot without motors), or RoboSim's `m` and one value a line.
  teach(m) {
    let line: string;
    if (m.format === "robosim") line = "m\n" + q.map((v) => v.toFixed(3)).join("\n");
    else line = moveLine(q);
    return [{ type: "teach", line }];
  },

  // ---- files

  // A shipped robot by name, or a robot file's text (JSON, or a thesis appendix C file with
  // its scale), with the mesh files the user opened beside it. A file that cannot be used
  // keeps the robot that was there.
  async load_robot(m) {
    let r: Robot;
    try {
      if ("name" in m) {
        r = await shippedRobot(text(m, "name", 200));
      } else {
        const body = text(m, "text");
        const filename = ("filename" in m ? text(m, "filename", 200) : "robot.json").replace(/[\\/]/g, "_");
        r = engine.robot();
        try {
          userFiles(m);
          if (m.legacy) r.fromLegacy(body, filename, num(m, "scale", 1e-6, 1e6));
          else r.parse(body, filename);
          for (const l of (r.info as ReturnType<typeof info>).links)
            for (const s of l.shapes)
              if (s.mesh && !engine.exists(s.mesh))
                throw new EngineError({ error: `${filename}: the mesh file ${s.mesh.replace(/^\/user\//, "")} was not ` +
                  "opened: open it together with the robot file (select both)" });
        } catch (e) {
          r.delete();
          throw e;
        }
      }
    } catch (e) {
      if (e instanceof EngineError) return [{ type: "robot_error", message: e.message }];
      throw e;
    }
    stopTasks();
    adopt(r);
    return [robotMessage(), poseMessage()];
  },
  // RoboSim's l: the lengths a(i-1) of the rows the robot file lets change, in row order.
  set_lengths(m) {
    const rows = info().dh.filter((row) => typeof (row as { a: unknown }).a === "object");
    const values = numbers(m, "values", [rows.length]);
    const keepQ = q, keepGrip = gripper;
    try {
      robot.setLinkLengths(values);
    } catch (e) {
      if (e instanceof EngineError) throw new BadMessage(e.message);
      throw e;
    }
    adopt(robot);
    q = keepQ;
    gripper = keepGrip;
    return [{ ...robotMessage(), keep_view: true }, poseMessage(q, { seq: m.seq ?? null })];
  },
  export_urdf: () => [{ type: "urdf", name: info().name, xml: robot.urdf() }],
  status_text(m) {
    const code = Math.trunc(num(m, "code", 0, 255));
    return [{ type: "status_text", code, text: engine.statusText(code) }];
  },

  // ---- the arm in the page (arm.ts): its lines read by the core's parsers, its pose from its
  // motor angles, the model's prediction of a line after those the arm accepted.

  arm_parse(m) {
    return [{ type: "arm_parsed", id: m.id, parsed: engine.parseArmLine(text(m, "line", 1000)) }];
  },
  arm_pose(m) {
    const r = info();
    const angles = numbers(m, "angles", [r.num_motors]);
    const qa = robot.jointsFromMotors(angles);
    const frames = (robot.pose(qa).frames as number[][]).map((f) => f.map(round6));
    return [{ type: "arm_posed", id: m.id, q: qa, frames }];
  },
  arm_predict(m) {
    const line = text(m, "line", 200);
    const history = Array.isArray(m.history) ? (m.history as unknown[]).filter((x): x is string => typeof x === "string") : [];
    let out: Out;
    try {
      const doc = robot.predict([...history, line].join("\n") + "\n", "arm.arm") as { records: Record<string, unknown>[] };
      const rec = doc.records[doc.records.length - 1];
      const code = rec.code as number;
      out = { reply: code === 0 ? "ok" : `error:${code}`, steps: rec.steps, meaning: engine.statusText(code), seconds: rec.seconds };
    } catch (e) {
      if (!(e instanceof EngineError)) throw e;
      const code = (robot.quantize([line])[0] as { code: number }).code;
      out = { reply: `error:${code}`, steps: null, meaning: engine.statusText(code) };
    }
    return [{ type: "arm_predicted", id: m.id, ...out }];
  },

  // ---- live physics

  async scene(m) {
    let name: string | null = null;
    if (m.name !== null && m.name !== undefined) {
      name = text(m, "name", 200);
      if (name && !index.scenes.includes(name)) throw new BadMessage(`no shipped scene '${name}'`);
    }
    stopTasks();
    if (name) await sceneFile(name);
    try {
      startPhysics(name);
    } catch (e) {
      if (e instanceof EngineError) throw new BadMessage(e.message);
      throw e;
    }
    timeline = null;
    return [sceneMessage(), physicsMessage(), poseMessage()];
  },
};

function stopTasks(): void {
  if (task !== null) clearTimeout(task);
  task = null;
}

function needTimeline() {
  if (!timeline) throw new BadMessage("no program loaded: send program_load first");
  return timeline;
}

function toolAt(v: number[]): number[] {
  return (robot.pose(v).tool as { xyz: number[] }).xyz;
}

// The files the user opened beside a robot file (meshes), into the engine's /user folder,
// where the robot file's relative mesh paths point (the robot is read as /user/<its name>).
function userFiles(m: Msg): void {
  engine.chdir("/");
  if (!engine.exists("/user")) engine.writeFile("/user/.keep", "");
  engine.chdir("/user");
  const files = m.files;
  if (files === undefined) return;
  if (!Array.isArray(files)) throw new BadMessage("'files' must be a list of {name, data}");
  for (const f of files as { name: unknown; data: unknown }[]) {
    if (typeof f?.name !== "string" || !(f.data instanceof ArrayBuffer))
      throw new BadMessage("'files' must be a list of {name, data (an ArrayBuffer)}");
    const rel = f.name.replace(/^[\\/]+/, "").replace(/\.\.(\/|\\)/g, "");
    engine.writeFile(`/user/${rel}`, new Uint8Array(f.data));
    // a mesh opened by itself also answers for the path meshes/<name>
    engine.writeFile(`/user/meshes/${rel.split("/").pop()}`, new Uint8Array(f.data));
  }
}

type IkArgs = { target: number[]; solver: string; start: number[]; weights?: number[]; max_iterations?: number };

function ikArgs(m: Msg): IkArgs {
  const target = numbers(m, "target", [3, 6]);
  const solver = m.solver ?? "auto";
  if (typeof solver !== "string" || !["auto", "closed", "lm", "jt"].includes(solver))
    throw new BadMessage("'solver' must be auto, closed, lm or jt");
  const args: IkArgs = { target, solver, start: q };
  if (m.weights !== undefined && m.weights !== null) {
    const r = info();
    args.weights = numbers(m, "weights", [r.num_joints, r.num_motors].filter((n) => n > 0));
  }
  return args;
}

// `articula ik --json`'s result, and beyond_reach.
interface IkResult {
  status: string; solver: string; q: number[]; position_error_mm: number; orientation_error_deg: number;
  iterations: number; limited_by?: string[]; limited_by_motors?: string[]; beyond_reach: boolean;
}

function solve(args: IkArgs): IkResult {
  try {
    return robot.ik(args) as unknown as IkResult;
  } catch (e) {
    if (e instanceof EngineError) throw new BadMessage(e.message);
    throw e;
  }
}

function ikReply(res: IkResult, seq: unknown): Out {
  return {
    type: "ik", status: res.status, solver: res.solver, position_error_mm: res.position_error_mm,
    orientation_error_deg: res.orientation_error_deg, iterations: res.iterations,
    limited_by: [...(res.limited_by ?? []), ...(res.limited_by_motors ?? [])], beyond_reach: res.beyond_reach,
    seq: seq ?? null,
  };
}

// A robot without motors has no controller timing: each move lasts as its largest joint
// change at 60 deg/s (100 mm/s), as the physics moves such robots; a gripper action 0.3 s.
function timed(records: Record<string, unknown>[]): Record<string, unknown>[] {
  let clock = 0;
  let prev: number[] | null = null;
  return records.map((rec) => {
    const j = rec.joints as number[];
    let dur = 0;
    if (rec.reply === "ok") {
      if (prev) dur = Math.max(0, ...j.map((v, k) => Math.abs(v - prev![k]))) / 60;
      if ("GSh".includes(String(rec.command)[0])) dur = Math.max(dur, 0.3);
      prev = j;
    }
    const out = { ...rec, start_s: clock, end_s: clock + dur };
    clock += dur;
    return out;
  });
}

// The arm at time s of the time line: each action moves from the pose before it to its own in
// its time (joint values linear in time: a drawing of the move, not the motors' speed
// profile), the whole-step pose and the ideal one (the ghost).
function poseAt(s: number): Out {
  const tl = timeline!;
  let qPrev = tl.startQ, qiPrev = tl.startQ;
  let cur = qPrev, ideal = qiPrev;
  let line = 0, err = 0;
  let steps: number[] | null = null, grip: number | null = null;
  for (const rec of tl.records) {
    if (rec.reply !== "ok") {
      if (rec.start_s <= s) line = rec.line;
      continue;
    }
    const a = rec.start_s, b = rec.end_s;
    if (s >= b) {
      qPrev = rec.q;
      qiPrev = rec.q_ideal;
      cur = qPrev;
      ideal = qiPrev;
      line = rec.line;
      steps = rec.steps;
      err = rec.error_mm;
      if (rec.gripper !== null) grip = rec.gripper;
      continue;
    }
    if (s >= a) {
      const f = b > a ? (s - a) / (b - a) : 1;
      cur = qPrev.map((v, k) => v + f * (rec.q[k] - v));
      ideal = qiPrev.map((v, k) => v + f * (rec.q_ideal[k] - v));
      line = rec.line;
    }
    break;
  }
  q = [...cur];
  if (grip !== null) gripper = grip;
  const ghost = (robot.pose(ideal).frames as number[][]).map((f) => f.map(round6));
  return poseMessage(q, { t: s, line, steps, error_mm: err, ghost });
}

// The protocol line that moves the (simulated) arm to joint values v: `M` with the motor
// angles, or the joint variables of a robot without motors.
function moveLine(v: number[]): string {
  const values = info().num_motors ? (robot.motorsFromJoints(v) as number[]) : v;
  return "M " + values.map((x) => x.toFixed(3)).join(" ");
}

// ---- live physics

const sceneTexts = new Map<string, string>();
async function sceneFile(name: string): Promise<string> {
  let s = sceneTexts.get(name);
  if (s === undefined) {
    s = await fetchText(`data/scenes/${name}.json`);
    sceneTexts.set(name, s);
  }
  return s;
}

// The arm in a scene, simulated from power-up; null: no physics, the kinematic model.
function startPhysics(name: string | null): void {
  const next = name === null ? null : engine.sim(robot, name ? sceneTexts.get(name)! : "", `scenes/${name}.json`);
  sim?.delete();
  sim = next;
  sceneName = name;
  eventsSent = 0;
  pendingMove = pendingGrip = null;
  if (sim) {
    q = (sim.state() as { joints: number[] }).joints;
    ensurePhysics();
  }
}

function sceneMessage(): Out {
  return { type: "scene", name: sceneName, title: sim ? sim.sceneName : "", objects: sim ? sim.objects : [],
    scenes: index.scenes };
}

function physicsMessage(rtf: number | null = null, behind = false): Out {
  if (!sim) return { type: "physics", on: false };
  const st = sim.state() as { t: number; busy: boolean; joints: number[]; gripper_mm: number;
    objects: { pose: number[] }[]; contacts: unknown; counted_steps: number[]; lost_steps: number[] };
  q = st.joints;
  const g = info().gripper;
  if (g) gripper = (100 * st.gripper_mm) / g.max_opening_mm;
  const fresh = eventsSent === 0;
  const events = sim.events(eventsSent) as unknown[];
  eventsSent += events.length;
  return {
    type: "physics", on: true, fresh, t: st.t, busy: st.busy,
    objects: st.objects.map((o: { pose: number[] }) => ({ ...o, pose: o.pose.map(round6) })),
    contacts: st.contacts, events, steps: st.counted_steps, lost: st.lost_steps, rtf, behind,
  };
}

// With physics on, the arm is the simulated controller's: a pose from a slider, Home, Zero or
// the IK becomes an `M` line for it (the newest waits until the arm is idle), the gripper a
// `G` line; programs run in the simulation; objects can be dragged.
function physicsIntent(kind: string, m: Msg): Out[] {
  const s = sim!;
  if (["set_joint", "set_joints", "home", "zero", "ik"].includes(kind)) {
    const replies = handlers[kind](m) as Out[];
    pendingMove = moveLine(q);
    return [...replies.filter((r) => r.type !== "pose"), { type: "sim_command", line: pendingMove, seq: m.seq ?? null }];
  }
  switch (kind) {
    case "gripper":
      pendingGrip = `G ${num(m, "percent", 0, 100)}`;
      return [];
    case "drag": {
      const target = numbers(m, "target", [3]);
      if (typeof m.object !== "string" && typeof m.object !== "number") throw new BadMessage("drag: 'object' must name an object");
      try {
        s.drag(String(typeof m.object === "number" ? s.objects[m.object]?.name ?? m.object : m.object), target);
      } catch (e) {
        if (e instanceof EngineError) throw new BadMessage(e.message);
        throw e;
      }
      return [];
    }
    case "release":
      s.release();
      return [];
    case "physics_run":
    case "play":
      physicsRunning = true;
      return kind === "play" ? [{ type: "playing", t: s.time, playing: true }] : [];
    case "physics_pause":
    case "pause":
      physicsRunning = false;
      return kind === "pause" ? [{ type: "playing", t: s.time, playing: false }] : [];
    case "physics_step":
      physicsRunning = false;
      s.step(Math.round(0.1 / s.dt)); // 100 ms
      return [poseMessage(), physicsMessage()];
    case "physics_reset":
      s.reset();
      eventsSent = 0;
      pendingMove = pendingGrip = null;
      return [physicsMessage(), poseMessage()];
    case "program_load": {
      const replies = handlers.program_load(m) as Out[];
      if (replies[0]?.type === "timeline") {
        s.reset();
        eventsSent = 0;
        pendingMove = pendingGrip = null;
        s.loadProgram(m.text as string, (typeof m.name === "string" && m.name) || "program.arm");
        physicsRunning = false;
      }
      return [...replies, physicsMessage()];
    }
  }
  throw new BadMessage(`'${kind}' does not apply while the physics runs`);
}

// Steps the simulation in real time and streams the world to the page, one message a display
// frame. `rtf` is simulated time over wall time (1.0 when keeping up), `capacity` how many
// times real time the stepping alone could run; `behind` when it cannot keep up.
function ensurePhysics(): void {
  if (physicsTimer !== null || !sim || !greeted) return;
  let last = performance.now();
  let due = last;
  let window: [number, number, number][] = [];
  const frame = () => {
    physicsTimer = null;
    const s = sim;
    if (!s) return;
    const now = performance.now();
    const wall = (now - last) / 1000;
    last = now;
    let stepped = 0, busy = 0;
    if (physicsRunning) {
      if (!s.busy) {
        if (pendingMove) {
          s.command(pendingMove);
          pendingMove = null;
        } else if (pendingGrip) {
          s.command(pendingGrip);
          pendingGrip = null;
        }
      }
      const n = Math.round(Math.min(wall, 0.1) / s.dt);
      const t0 = performance.now();
      s.step(n);
      busy = (performance.now() - t0) / 1000;
      stepped = n * s.dt;
    }
    window.push([wall, stepped, busy]);
    window = window.slice(-60);
    const sum = (i: number) => window.reduce((acc, x) => acc + x[i], 0);
    const w = sum(0), st = sum(1), bz = sum(2);
    const rtf = w > 0 ? st / w : 0;
    const capacity = bz > 0 ? st / bz : null;
    const behind = physicsRunning && (wall > 0.1 || (capacity !== null && capacity < 1));
    const msg = physicsMessage(rtf, behind);
    msg.capacity = capacity;
    msg.running = physicsRunning;
    post([poseMessage(), msg]);
    due = Math.max(due + FRAME_MS, performance.now() - FRAME_MS);
    physicsTimer = setTimeout(frame, Math.max(0, due - performance.now()));
  };
  physicsTimer = setTimeout(frame, 0);
}

// ---- dispatch

async function dispatch(m: unknown): Promise<Out[]> {
  if (typeof m !== "object" || m === null || Array.isArray(m)) throw new BadMessage("a message is an object with a 'type'");
  const msg = m as Msg;
  const kind = msg.type;
  if (typeof kind !== "string") throw new BadMessage(`unknown message type ${JSON.stringify(kind) ?? "undefined"}`);
  if (sim && PHYSICS_INTENTS.has(kind)) return physicsIntent(kind, msg);
  if (["drag", "release", "physics_run", "physics_pause", "physics_step", "physics_reset"].includes(kind))
    throw new BadMessage("no physics: choose a scene first");
  const handler = Object.prototype.hasOwnProperty.call(handlers, kind) ? handlers[kind] : undefined;
  if (!handler) throw new BadMessage(`unknown message type '${kind}'`);
  if (["set_joint", "set_joints", "ik", "home", "zero", "program_load", "set_lengths"].includes(kind)) stopTasks();
  return handler(msg);
}

// Messages are handled one at a time, in order (a robot that is still being fetched answers
// before the slider moved after it).
let queue: Promise<void> = Promise.resolve();

function receive(m: unknown): void {
  // A request with an `id` (the page's engineCall) gets it back on its answers.
  const id = typeof m === "object" && m !== null && typeof (m as Msg).id === "number" ? (m as Msg).id : undefined;
  const tagged = (msgs: Out[]) => (id === undefined ? msgs : msgs.map((x) => ({ ...x, id })));
  queue = queue.then(async () => {
    try {
      post(tagged(await dispatch(m)));
    } catch (e) {
      const request = typeof m === "object" && m !== null ? (m as Msg).type : null;
      if (e instanceof BadMessage || e instanceof EngineError) post(tagged([{ type: "error", message: e.message, request: request ?? null }]));
      else post(tagged([{ type: "error", message: `internal error: ${(e as Error)?.message ?? String(e)}`, request: request ?? null }]));
    }
  });
}

// The first message is {type: "start", robot, scene}: the engine loads, the site's index is
// read, the robot shown first is loaded; then "ready".
async function start(first: Msg): Promise<void> {
  const t0 = performance.now();
  const engineUrl = new URL("engine/engine.mjs", site).href;
  const { default: createEngine } = await import(/* @vite-ignore */ engineUrl);
  engine = await loadEngine(createEngine, { locateFile: (f: string) => new URL(`engine/${f}`, site).href });
  index = JSON.parse(await fetchText("data/index.json"));
  const wanted = typeof first.robot === "string" ? first.robot : "mk2plus";
  try {
    robot = wanted.endsWith(".json") ? await urlRobot(wanted) : await shippedRobot(index.robots.includes(wanted) ? wanted : "mk2plus");
  } catch (e) {
    // A robot the address names but that cannot be used: the MK2, and the page says why.
    robot = await shippedRobot("mk2plus");
    post([{ type: "robot_error", message: (e as Error).message }]);
  }
  q = [...info().home];
  const scene = typeof first.scene === "string" && index.scenes.includes(first.scene) ? first.scene : null;
  if (scene) {
    await sceneFile(scene);
    startPhysics(scene);
  }
  post([{ type: "ready", ms: performance.now() - t0 }]);
}

let started: Promise<void> | null = null;
self.onmessage = (e: MessageEvent) => {
  const m = e.data;
  if (!started) {
    started = start(typeof m === "object" && m !== null ? m : {}).catch((err) => {
      post([{ type: "fatal", message: `the engine did not start: ${(err as Error)?.message ?? err}` }]);
    });
    queue = started;
    return;
  }
  receive(m);
};
