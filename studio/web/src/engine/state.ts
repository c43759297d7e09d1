// One page's session in the engine's worker: the robot shown, its pose and gripper, the
// program's time line and its clock, the live physics. The engine computes; this holds what
// the page is looking at, and turns it into the messages the page draws (engine/messages.ts).
import type { Engine, Robot, Sim, Timeline } from "../../../../wasm/js/engine.mjs";
import { clamp, round6 } from "./checks";
import type { Out } from "./checks";
import type { Places, RobotMsg } from "./messages";

export interface RobotInfo {
  name: string; description: string; source: string; joints: { name: string }[]; dh: unknown[];
  num_rows: number; num_joints: number; num_motors: number; home: number[]; limits: [number, number][];
  motors: { name: string; zero: number; driver?: { kind: string; pin?: string; at?: number[][] } }[]; links: { frame: number; shapes: { type: string; size: number[];
  pose: number[]; mesh?: string }[] }[]; gripper: null | { max_opening_mm: number }; reach_mm: number; places: Places;
  import_notes: string[]; joint_names: string[];
  wiring: NonNullable<RobotMsg["wiring"]>; // host/lib/wiring.h: the firmware build for its drivers, and every wire
}

/** The site's shipped files (data/index.json, which make web writes). */
export interface SiteIndex {
  robots: string[]; scenes: string[]; cells?: string[]; programs: string[]; meshes: string[];
  sceneSizedFor?: Record<string, string[]>; // each scene's "sized_for": the shipped robots its objects are placed for
}

export const S = {
  engine: null as unknown as Engine,
  index: { robots: [], scenes: [], programs: [], meshes: [] } as SiteIndex,
  robot: null as unknown as Robot,
  q: [] as number[],
  gripper: 100, // percent open
  // A pen in the gripper, its tip this far below the tool point (mm; 0: no pen): the tool point
  // the page shows and aims is then the pen's tip (host/lib/draw.h: the pen hangs straight
  // down). The robot and the lines sent to the arm stay the tool point's.
  pen: 0,
  timeline: null as Timeline | null,
  t: 0, // the time line's clock, s
  speed: 1, // the simulated world against real time: the time line's playing and the live physics
  // The least time between two states of the live physics sent to the page, ms: half the page's
  // frame period (?fps=N, ?quality=low), or none (every display frame). The world steps as
  // often either way; what the page shows (a readout, a plot's playhead) needs no more.
  postMs: 0,
  task: null as ReturnType<typeof setTimeout> | null, // playback or the JT animation
  sceneName: null as string | null, // live physics: the scene (null: none)
  sceneWorld: null as string | null, // a scene of the student's own (its file's text), in place of sceneName's
  sim: null as Sim | null,
  greeted: false, // the page said hello: it has the robot, poses may stream
  // physics frames posted that the page has not taken yet (physics_ack): the stream waits at a
  // few, so that a page slower than the physics (a busy tablet) gets the engine's answers
  // between frames instead of behind a queue of them that only grows
  unacked: 0,
  programTexts: new Map<string, string>(), // the shipped examples' texts (site.ts reads them)
};

/** The shipped examples for the robot shown: not those made for an arm of another shape (the
 * engine's program_fit says so); a program broken for every arm is offered, and says why when
 * opened. */
export function examplesFor(robot: Robot): string[] {
  return S.index.programs.filter((p) => !robot.programFit(S.programTexts.get(p) ?? "", p).other_arm);
}

const meshUrls = new Map<string, string>(); // engine path -> blob URL the page draws

export function post(msgs: Out[]): void {
  for (const m of msgs) (self as unknown as Worker).postMessage(m);
}

export const info = () => S.robot.info as unknown as RobotInfo;

export function stopTasks(): void {
  if (S.task !== null) clearTimeout(S.task);
  S.task = null;
}

function meshUrl(path: string): string {
  let url = meshUrls.get(path);
  if (!url) {
    url = URL.createObjectURL(new Blob([S.engine.readFile(path) as Uint8Array<ArrayBuffer>]));
    meshUrls.set(path, url);
  }
  return url;
}

/** The shipped robot shown, by its name in the site's list ("": a robot opened from a file). */
export function shippedName(): string {
  const source = info().source;
  const stem = /^\/robots\/([^/]+)\.json$/.exec(source)?.[1] ?? "";
  return S.index.robots.includes(stem) ? stem : "";
}

export function robotMessage(): Out {
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
    type: "robot", name: r.name, description: r.description, source: r.source, shipped: shippedName(), joints: r.joints, dh: r.dh,
    num_rows: r.num_rows, home: r.home, motors: r.motors.map((m) => m.name), links, gripper: r.gripper,
    reach_mm: r.reach_mm, places: r.places, robots: S.index.robots, programs: examplesFor(S.robot), scenes: S.index.scenes,
    import_notes: r.import_notes, wiring: r.wiring, ...nanoBuild(r),
  };
}

/** What a virtual Nano needs to drive the robot: its firmware build, and a servo arm's servos
 * in motor order (the virtual Nano decodes their pins). */
export function nanoBuild(r: RobotInfo): { firmware: string; servos: { pin: string; zeroUs: number }[] | null } {
  return {
    firmware: r.wiring.firmware,
    servos: r.motors.length > 0 && r.motors.every((m) => m.driver?.kind === "servo")
      ? r.motors.map((m) => ({ pin: String(m.driver?.pin), zeroUs: Number(m.driver?.at?.[0]?.[0]) })) : null,
  };
}

export function poseMessage(at: number[] = S.q, extra: Out = {}): Out {
  const r = info();
  const opening = r.gripper ? (r.gripper.max_opening_mm * S.gripper) / 100 : NaN;
  const p = S.robot.pose(at, opening) as { frames: number[][]; tool: unknown; dh_table: number[][];
    within_limits: boolean; fingers?: number[][] };
  const msg: Out = {
    type: "pose", q: at, frames: p.frames.map((f) => f.map(round6)), tool: p.tool, dh_table: p.dh_table,
    gripper: S.gripper, within_limits: p.within_limits,
  };
  if (p.fingers) msg.fingers = p.fingers.map((f) => f.map(round6));
  if (S.pen > 0) msg.tip = penTip((p.tool as { xyz: number[] }).xyz);
  // the motors' angles, which `M` takes, beside the joint values the sliders show
  if (r.num_motors) msg.motors = (S.robot.motorsFromJoints(at) as number[]).map(round6);
  return Object.assign(msg, extra);
}

/** The pen's tip for a tool point, and the tool point for a tip (S.pen; draw.h's rule). */
export const penTip = (tool: number[]) => [tool[0], tool[1], round6(tool[2] - S.pen)];
export const toolForTip = (tip: number[]) => [tip[0], tip[1], tip[2] + S.pen, ...tip.slice(3)];

/** The frames of a pose, for the arm in the loop. */
export function framesAt(q: number[]): number[][] {
  return (S.robot.pose(q).frames as number[][]).map((f) => f.map(round6));
}

/** The ghost (the ideal pose) as the engine poses it: its frames, and its fingers at the
 * gripper's opening. */
export function ghostAt(q: number[]): Out {
  const r = info();
  const opening = r.gripper ? (r.gripper.max_opening_mm * S.gripper) / 100 : NaN;
  const p = S.robot.pose(q, opening) as { frames: number[][]; fingers?: number[][] };
  const out: Out = { ghost: p.frames.map((f) => f.map(round6)) };
  if (p.fingers) out.ghost_fingers = p.fingers.map((f) => f.map(round6));
  return out;
}

// A robot becomes the one shown: at its home, the gripper open, no program.
export function adopt(r: Robot, restartPhysics: (scene: string) => void): void {
  const old = S.robot;
  S.robot = r;
  if (old && old !== r) old.delete();
  S.q = [...info().home];
  S.gripper = 100;
  dropTimeline();
  if (S.sceneName !== null) restartPhysics(S.sceneName);
}

export function dropTimeline(): void {
  S.timeline?.delete();
  S.timeline = null;
}

// Where the real arm powers up: every motor at its zero angle.
export function powerUpQ(): number[] {
  return S.robot.jointsFromMotors(info().motors.map((m) => m.zero)) as number[];
}

export function clampQ(v: number[]): number[] {
  return v.map((x, j) => clamp(x, info().limits[j][0], info().limits[j][1]));
}

// The protocol line that moves the (simulated) arm to joint values v: `M` with the motor
// angles, or the joint variables of a robot without motors.
export function moveLine(v: number[]): string {
  return S.robot.moveLine(v);
}
