// Live physics in the engine's worker: the arm and a scene in ODE (the engine's Sim), stepped
// in real time and streamed to the page a display frame at a time. With physics on, the arm
// is the simulated controller's: a pose from a slider, Home, Zero or the IK becomes an `M`
// line for it (the newest waits until the arm is idle), the gripper a `G` line; programs run
// in the simulation; objects can be dragged.
import { EngineError } from "../../../../wasm/js/engine.mjs";
import { RealTimeMeter, every } from "../pacer";
import { BadMessage, num, numbers, round6, text } from "./checks";
import type { Msg, Out } from "./checks";
import { dropTimeline, info, moveLine, poseMessage, post, S, stopTasks } from "./state";
import { lineNumbers } from "./program";
import { sceneFile, sceneText } from "./site";

const FRAME_MS = 1000 / 60;
let eventsSent = 0;
let running = true;
let loop: { stop(): void } | null = null;
let pendingMove: string | null = null;
let pendingGrip: string | null = null;

/** The intents that go to the simulation while the physics runs. */
export const PHYSICS_INTENTS = new Set(["set_joint", "set_joints", "home", "zero", "ik", "gripper", "drag", "release",
  "physics_run", "physics_pause", "physics_step", "physics_reset", "program_load", "play", "pause"]);
export const PHYSICS_ONLY = new Set(["drag", "release", "physics_run", "physics_pause", "physics_step", "physics_reset"]);

// The arm in a scene, simulated from power-up; null: no physics, the kinematic model. `world`:
// a scene of the student's own, as its file's text (the scene editor's), in place of the
// shipped scene `name` it started from; the engine's loader checks it as any scene file.
export function startPhysics(name: string | null, world: string | null = null): void {
  usePhysics(newSim(name, world), name, world);
}

// The simulation of startPhysics (built first: a scene the loader refuses changes nothing).
function newSim(name: string | null, world: string | null): typeof S.sim {
  return world !== null ? S.engine.sim(S.robot, world, "your scene")
    : name === null ? null : S.engine.sim(S.robot, name ? sceneText(name) : "", `scenes/${name}.json`);
}

function usePhysics(next: typeof S.sim, name: string | null, world: string | null): void {
  S.sim?.delete();
  S.sim = next;
  S.sceneName = world !== null ? name ?? "" : name;
  S.sceneWorld = world;
  eventsSent = 0;
  pendingMove = pendingGrip = null;
  if (S.sim) {
    S.q = (S.sim.state() as { joints: number[] }).joints;
    ensurePhysics();
  }
}

/** A new robot in the same scene. */
export const restartPhysics = (scene: string) => startPhysics(scene, S.sceneWorld);

// The largest scene of a student's own, as text: far above a class's table (500 objects).
const MAX_WORLD = 100_000;

export function sceneMessage(): Out {
  return { type: "scene", name: S.sceneName, title: S.sim ? S.sim.sceneName : "", objects: S.sim ? S.sim.objects : [],
    world: S.sceneWorld === null ? null : JSON.parse(S.sceneWorld),
    scenes: S.index.scenes, sized_for: S.index.sceneSizedFor ?? {}, cells: S.index.cells ?? [] };
}

export function physicsMessage(rtf: number | null = null, behind = false): Out {
  const sim = S.sim;
  if (!sim) return { type: "physics", on: false };
  const st = sim.state() as { t: number; busy: boolean; joints: number[]; gripper_mm: number;
    objects: { pose: number[] }[]; contacts: unknown; counted_steps: number[]; lost_steps: number[]; line: number };
  S.q = st.joints;
  const g = info().gripper;
  if (g) S.gripper = (100 * st.gripper_mm) / g.max_opening_mm;
  const fresh = eventsSent === 0;
  const events = sim.events(eventsSent) as unknown[];
  eventsSent += events.length;
  return {
    type: "physics", on: true, fresh, t: st.t, busy: st.busy, line: st.busy ? st.line : 0,
    objects: st.objects.map((o: { pose: number[] }) => ({ ...o, pose: o.pose.map(round6) })),
    contacts: st.contacts, events, steps: st.counted_steps, lost: st.lost_steps, rtf, behind,
  };
}

export async function sceneIntent(m: Msg): Promise<Out[]> {
  let name: string | null = null;
  if (m.name !== null && m.name !== undefined) {
    name = text(m, "name", 200);
    if (name && !S.index.scenes.includes(name)) throw new BadMessage(`no shipped scene '${name}'`);
  }
  let world: string | null = null;
  if (m.world !== null && m.world !== undefined) {
    if (typeof m.world !== "object" || Array.isArray(m.world)) throw new BadMessage("scene: 'world' must be a scene (an object: scenes/README.md)");
    world = JSON.stringify(m.world);
    if (world.length > MAX_WORLD) throw new BadMessage(`your scene is ${world.length} characters: at most ${MAX_WORLD}`);
  }
  if (name) await sceneFile(name);
  // built first, as any scene file is loaded: a refused one (a student's edit) changes nothing
  let next: typeof S.sim;
  try {
    next = newSim(name, world);
  } catch (e) {
    if (e instanceof EngineError) throw new BadMessage(e.message);
    throw e;
  }
  stopTasks();
  usePhysics(next, name, world);
  dropTimeline();
  return [sceneMessage(), physicsMessage(), poseMessage()];
}

// The world from power-up: for a program's run (`placed`), each object a drag let go of where
// it was let go (the student put it there); for Reset, every object where the scene file has it.
function restart(placed = false): void {
  if (placed) S.sim!.restart();
  else S.sim!.reset();
  eventsSent = 0;
  pendingMove = pendingGrip = null;
  trail = [];
}

/** An intent while the physics runs; `kinematic` answers the pose intents as without physics. */
export function physicsIntent(kind: string, m: Msg, kinematic: (kind: string, m: Msg) => Out[]): Out[] {
  const s = S.sim!;
  if (["set_joint", "set_joints", "home", "zero", "ik"].includes(kind)) {
    const replies = kinematic(kind, m);
    pendingMove = moveLine(S.q);
    return [...replies.filter((r) => r.type !== "pose"), { type: "sim_command", line: pendingMove, seq: m.seq ?? null }];
  }
  switch (kind) {
    case "gripper":
      pendingGrip = S.robot.protocolLine("G", [num(m, "percent", 0, 100)]);
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
      running = true;
      breaks = kind === "play" ? lineNumbers(m) : new Set();
      lineNow = -1;
      return kind === "play" ? [{ type: "playing", t: s.time, playing: true }] : [];
    case "physics_pause":
    case "pause":
      running = false;
      return kind === "pause" ? [{ type: "playing", t: s.time, playing: false }] : [];
    case "physics_step":
      running = false;
      s.step(Math.round(0.1 / s.dt)); // 100 ms
      return [poseMessage(), physicsMessage()];
    case "physics_reset":
      restart();
      return [physicsMessage(), poseMessage()];
    case "program_load": {
      const replies = kinematic(kind, m);
      if (replies[0]?.type === "timeline") {
        restart(true);
        s.loadProgram(m.text as string, (typeof m.name === "string" && m.name) || "program.arm");
        running = false;
      }
      return [...replies, physicsMessage()];
    }
  }
  throw new BadMessage(`'${kind}' does not apply while the physics runs`);
}

// Steps the simulation in real time (times S.speed, the page's speed) and streams the world to
// the page, one message a display frame. `rtf` is simulated time over wall time (1.0 when keeping
// up at speed 1), `capacity` how many times real time the stepping alone could run; `behind`
// when it cannot keep up with the speed.
const MAX_UNACKED = 3;
// The tool's path since the last frame sent (x, y, z mm, flat): a page too busy to take every
// frame still gets every point (a pen's ink is drawn from them). At most 100,000 points wait.
const TRAIL_MAX = 300_000;
let trail: number[] = [];
// A program's breakpoints in the live physics: the world pauses once a breakpoint's line has
// ended (looked at every display frame: the next line may have begun by up to a frame's time).
let breaks = new Set<number>();
let lineNow = -1; // the program's line at the last frame (-1: not looked at yet)
const REST_POST_MS = 1000; // a world at rest: a state a second
export function ensurePhysics(): void {
  if (loop !== null || !S.sim || !S.greeted) return;
  S.unacked = 0;
  trail = [];
  const meter = new RealTimeMeter(60);
  let last = performance.now();
  let owed = 0; // the world's seconds due and not yet stepped (less than a step)
  let posted = -Infinity, postedRunning = running, postedStill = "", postedT = 0; // the last state sent to the page
  let postedTool: number[] | null = null;
  loop = every(FRAME_MS, () => {
    const s = S.sim;
    if (!s) {
      loop = null;
      return false;
    }
    const now = performance.now();
    const wall = (now - last) / 1000;
    last = now;
    let stepped = 0, busy = 0;
    if (running) {
      if (!s.busy) {
        if (pendingMove) {
          s.command(pendingMove);
          pendingMove = null;
        } else if (pendingGrip) {
          s.command(pendingGrip);
          pendingGrip = null;
        }
      }
      owed += Math.min(wall, 0.1) * S.speed; // (at the page's speed: 1 keeps real time)
      const n = Math.floor(owed / s.dt + 1e-9);
      owed = Math.max(0, owed - n * s.dt);
      // the tool's path every 10 ms of the world's time, kept until a frame takes it
      const path = s.stepPath(n, Math.max(1, Math.round(0.01 / s.dt)));
      if (trail.length + path.length <= TRAIL_MAX) for (const v of path) trail.push(v);
      busy = (performance.now() - now) / 1000;
      stepped = n * s.dt;
    }
    if (running && breaks.size) {
      const st = s.state() as { busy: boolean; line: number };
      const line = st.busy ? st.line : 0;
      if (breaks.has(lineNow) && line !== lineNow) {
        running = false;
        post([{ type: "playing", t: s.time, playing: false, paused_at: lineNow }]);
      }
      lineNow = line;
    }
    meter.slice(stepped, busy);
    const capacity = meter.capacity;
    const behind = running && (wall > 0.1 || (capacity !== null && capacity < S.speed));
    if (S.unacked >= MAX_UNACKED) return; // (the page is behind: this frame is skipped, the physics runs on)
    // (at most one state every S.postMs, and one at once when the world starts or stops: the
    // events and the tool's trail wait for the next, none is lost)
    if (now - posted < S.postMs && running === postedRunning) return;
    const msg = physicsMessage(meter.rtf, behind);
    const pose = poseMessage();
    // (a world at rest - the arm idle, every object where it was, nothing new - is told once a
    // second, its clock's readout: each state costs the page a frame and a layout, and an idle
    // scene took a third of a core in Chromium with SwiftShader)
    // (the tool's path since: one point over and over, or a new one)
    const tool = trail.length ? trail.slice(0, 3) : null;
    const toolStill = trail.every((v, i) => v === trail[i % 3]);
    const still = JSON.stringify([msg.objects, msg.contacts, msg.steps, msg.lost, pose.q, pose.gripper, tool ?? postedTool]);
    const atRest = running === postedRunning && !msg.busy && (msg.events as unknown[]).length === 0 &&
      toolStill && still === postedStill && (msg.t as number) >= postedT; // (an earlier t: a reset)
    if (tool) postedTool = tool;
    if (atRest && now - posted < REST_POST_MS) return; // (the tool's points wait for it, none lost)
    posted = now;
    postedRunning = running;
    postedStill = still;
    postedT = msg.t as number;
    msg.capacity = capacity;
    msg.running = running;
    S.unacked++;
    pose.trail = trail.splice(0); // (every point since the last frame the page was sent)
    post([pose, msg]);
  });
}
