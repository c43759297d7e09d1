// The test hook, `window.articula`: the page's state to read, never to write, and never read by
// the page's own code (only main.ts, which builds it, imports this module). Tests and people who
// script the page read it instead of pixels. Every fact in it is a view, read from its owner
// whenever it is read: what the Editor holds (the robot, the pose, the scene, the physics, the
// timeline, the project, the History: `viewOf`), what the engine's client counts
// (`viewOfEngine`), the error log (page/errors.ts), and each panel's own report object
// (page/reports.ts gives their types; main.ts wires them with `showOwn`).
import type { Editor } from "../editor/editor";
import type { EngineClient } from "./engine-client";
import { saving } from "../project/autosave";
import { errorReport } from "./errors";
import type { PhysicsMsg, PoseMsg, RobotMsg, SceneMsg, TimelineMsg } from "../engine/messages";
import type { Reports } from "./reports";


export interface Hook extends Reports {
  ready: boolean;
  connected: boolean;
  robot: RobotMsg | null;
  pose: PoseMsg | null;
  timeline: TimelineMsg | null;
  playing: boolean;
  lastError: string;
  teach: string;
  fps: number;
  framesDrawn: number;
  firstFrameAt: number; // performance.now() of the first frame with the arm drawn
  latency: number[]; // ms from a slider's input to the frame that shows its pose
  messages: number;
  targetScreen: number[]; // where the IK target's centre is on screen (CSS px), to drag it
  scene: SceneMsg | null;
  physics: PhysicsMsg | null;
  simCommand: string; // the last line a pose became for the simulated controller
  objectScreen: (name: string) => number[] | null;
  pointScreen: (p: number[]) => number[]; // where a point of the world (mm) is on the page (CSS px)
  stream: { messages: number }; // physics and pose messages while the physics runs
  armPixels: () => number;
  camera: () => { distance: number; azimuth: number }; // the view's camera (view.ts cameraState)
  viewpoint: () => { eye: number[]; target: number[] }; // where the camera is and looks (mm) // share of the view's pixels that are the arm's colours (0..1)
  errors: number; // error replies from the engine or the arm
  errorLog: string[]; // the last 50 of them, oldest first
  pageErrors: string[]; // the page's own uncaught errors and rejections (for browsers whose driver shows no console)
  internalErrors: string[]; // replies that say the engine itself went wrong (never expected)
  engineStartMs: number; // the worker's time from its first message to the robot loaded
  engineSend: (msg: unknown) => void; // for tests: a message to the engine as the page would post it
  engineWaiting: () => { type: string; ms: number }[]; // the engine's requests not answered yet (what a stuck page waits for)
  layout: { mode: string; plotsInTab: boolean; tab: string }; // layout.ts: the screen's layout, the tab shown
  webgl: boolean; // false where the browser gives the page no WebGL (the 3D view is then off)
  language: string; // the language the page formats with (a valid tag, whatever the browser says)
  storage: boolean; // false where the page can keep nothing (private mode, storage off)
  project: { id: string; name: string; robot: string; program: string; blocks: unknown; mode: string; rev: number; goal: unknown;
             persistent: boolean; dirty: boolean; saves: number; saveMs: number[]; savedAt: number; saveError: string;
             lastDeleted: string; otherTab: number };
  blocksPending: boolean;
  stops: number; // STOP pressed (button or Escape)
  history: { undo: number; redo: number; undoName: string; redoName: string; undoDetail: string; ready: boolean }; // editor/history.ts: the steps; undoDetail: where the step to undo first changed the project; ready: the project is on screen, an edit now is a step
}

// (the panels' own facts, Reports, are views of their report objects: main.ts wires them)
export const hook = {
  ready: false, connected: false, robot: null, pose: null, timeline: null, playing: false,
  lastError: "", teach: "", fps: 0, framesDrawn: 0, firstFrameAt: 0,
  latency: [], messages: 0, targetScreen: [0, 0], armPixels: () => 0,
  camera: () => ({ distance: 0, azimuth: 0 }), viewpoint: () => ({ eye: [], target: [] }),
  scene: null, physics: null, simCommand: "", objectScreen: () => null, pointScreen: () => [0, 0],
  stream: { messages: 0 }, errors: 0, errorLog: [], pageErrors: [], internalErrors: [], engineStartMs: 0, engineSend: () => undefined, engineWaiting: () => [],
  layout: { mode: "", plotsInTab: false, tab: "" }, webgl: true, language: "", storage: true,
  project: { id: "", name: "", robot: "", program: "", blocks: null, mode: "text", rev: 0, goal: null, persistent: true, dirty: false,
             saves: 0, saveMs: [], savedAt: 0, saveError: "", lastDeleted: "", otherTab: 0 },
  blocksPending: false, stops: 0,
  history: { undo: 0, redo: 0, undoName: "", redoName: "", undoDetail: "", ready: false },
} as Omit<Hook, keyof Reports> as Hook;

/** What the Editor holds, read from it whenever it is read. */
export function viewOf(ed: Editor): void {
  const get = (o: object, key: string, f: () => unknown) => Object.defineProperty(o, key, { get: f, enumerable: true, configurable: true });
  get(hook, "robot", () => ed.robot);
  get(hook, "pose", () => ed.pose);
  get(hook, "scene", () => ed.scene);
  get(hook, "physics", () => ed.physics);
  get(hook, "timeline", () => ed.timeline);
  get(hook, "playing", () => ed.playing);
  get(hook, "stops", () => ed.stops);
  get(hook, "teach", () => ed.taught);
  get(hook, "blocksPending", () => ed.blocks.pending());
  // the project on screen (one opening is not, until its robot is), each field read when it is
  // read (the blocks' JSON is not cheap)
  const project = {};
  const p = () => ed.project.shown, d = () => ed.project.shown.doc;
  const fields: Record<string, () => unknown> = {
    id: () => p().id, name: () => d().name, robot: () => {
      const r = d().robot;
      return "shipped" in r ? r.shipped : r.file.name;
    },
    program: () => ed.program.text(), blocks: () => ed.blocks.json(), mode: () => ed.blocks.mode(), rev: () => p().rev,
    goal: () => d().goal,
  };
  for (const k of Object.keys(saving)) fields[k] = () => saving[k as keyof typeof saving];
  for (const [k, f] of Object.entries(fields)) get(project, k, f);
  get(hook, "project", () => project);
  get(hook, "history", () => {
    const h = ed.history;
    const step = h.undoCommand as { detail?: () => string } | undefined;
    // (undoDetail compares two whole documents: worked out only when it is read, not at every poll)
    return { ...h.steps, undoName: h.undoName, redoName: h.redoName, get undoDetail() { return step?.detail?.() ?? ""; },
      ready: ed.project.ready };
  });
}

/** A fact a panel owns, read from it whenever the hook's `key` is read (main.ts wires them). */
export function showOwn<K extends keyof Hook>(key: K, read: () => Hook[K]): void {
  Object.defineProperty(hook, key, { get: read, enumerable: true, configurable: true });
}

/** What the engine client counts, read from it whenever it is read. */
export function viewOfEngine(engine: EngineClient): void {
  const get = (o: object, key: string, f: () => unknown) => Object.defineProperty(o, key, { get: f, enumerable: true, configurable: true });
  get(hook, "connected", () => engine.ready);
  get(hook, "messages", () => engine.messages);
  get(hook, "engineStartMs", () => engine.startMs);
  get(hook.stream, "messages", () => engine.streamMessages);
  hook.engineWaiting = () => engine.waiting();
  for (const k of Object.keys(errorReport) as (keyof typeof errorReport)[]) get(hook, k, () => errorReport[k]);
}

/** `window.articula`, read-only from outside. */
export function exposeHook(): void {
  const readOnly = new Proxy(hook, { set: () => false, deleteProperty: () => false });
  Object.defineProperty(window, "articula", { value: readOnly, writable: false });
  const keep = (what: unknown) => {
    hook.pageErrors.push(what instanceof Error ? `${what.name}: ${what.message}` : String(what));
    if (hook.pageErrors.length > 50) hook.pageErrors.shift();
  };
  window.addEventListener("error", (e) => keep(e.error ?? e.message));
  window.addEventListener("unhandledrejection", (e) => keep(e.reason));
  // what the page's Content-Security-Policy refused: never expected (the page writes no inline
  // style or script), so the browser tests fail on any
  document.addEventListener("securitypolicyviolation", (e) =>
    keep(`Content-Security-Policy refused ${e.effectiveDirective || e.violatedDirective}: ${e.blockedURI || "inline"} ${e.sample || ""} (${e.sourceFile || "?"}:${e.lineNumber})`));
}
