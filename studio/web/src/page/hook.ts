// The test hook, `window.articula`: the page's state to read, never to write. Tests and people
// who script the page read it instead of pixels. What the Editor holds (the robot, the pose,
// the scene, the physics, the timeline, the arm's link, the project, the History) is a view of
// the Editor (`viewOf`); the rest is what the panels measure and report, kept up to date by them.
import type { Editor } from "../editor/editor";
import { saving } from "../project/autosave";
import type { ArmStatusMsg, IkMsg, PhysicsMsg, PoseMsg, RobotMsg, SceneMsg, SimEvent, TimelineMsg } from "../engine/messages";

// the ink on the sheet: the rows (steps or tool points) it is made of, its points and strokes,
// and the rows received so far (more than it is made of: its next version is on its way)
type Ink = { rows: number; points: number; strokes: number[][][]; received: number };

export interface Hook {
  ready: boolean;
  connected: boolean;
  robot: RobotMsg | null;
  pose: PoseMsg | null;
  ik: IkMsg | null;
  timeline: TimelineMsg | null;
  // What the view draws of the program: the tool's predicted path (points, every step) and the
  // straight lines asked for (T), with the worst distance of the path from them.
  paths: { points: number; lines: number; worstMm: number };
  ikLine: string; // the last straight line the IK panel made
  // the Draw panel's last drawing: whether the pen reaches it, the engine's refusal or advice,
  // the line the arm will draw (its worst distance, mm, and steps), the program's lines
  // the line the arm will draw (its worst distance, mm, and steps; `ink` its strokes), the program's lines
  drawing: { fits: boolean; error: string; advice: string; worstMm: number; steps: number; lines: number; program: string;
    ink: number[][][] } | null;
  drawings: number; // how many drawings the panel has shown (a test waits for the next)
  // the paper: its sheet on the table ([min_x, min_y, max_x, max_y] mm), the share of it the pen
  // reaches, the strokes drawn by hand; the ink the virtual Nano's steps left (rows: the step rows
  // seen, strokes of [x, y]) and the physics' tool left (rows: its positions seen)
  paper: { area: number[]; reachShare: number; maps: number; hand: number; ink: Ink; physicsInk: Ink };
  playing: boolean;
  programError: string;
  robotError: string;
  lastError: string;
  teach: string;
  // an exercise's goal: its parts drawn in the view, the facts under it, a drawing target's strokes on the paper
  goal: { drawn: number; facts: string[]; target?: number };
  runOnArm: boolean; // Run sends the program to the connected arm ("on the arm" beside it ticked)
  fps: number;
  framesDrawn: number;
  firstFrameAt: number; // performance.now() of the first frame with the arm drawn
  latency: number[]; // ms from a slider's input to the frame that shows its pose
  ikUpdates: number[]; // performance.now() of each IK pose drawn while dragging
  messages: number;
  targetScreen: number[]; // where the IK target's centre is on screen (CSS px), to drag it
  scene: SceneMsg | null;
  physics: PhysicsMsg | null;
  events: SimEvent[]; // the physics events since the simulation started or was reset
  simCommand: string; // the last line a pose became for the simulated controller
  objectScreen: (name: string) => number[] | null;
  arm: { connected: boolean; error: string; label: string; status: ArmStatusMsg | null; reply: unknown; stopMs: number | null;
         programLines: unknown[]; programDone: boolean; roundTrips: number[]; nano: unknown;
         configurable: boolean; configured: { name: string; checksum: number } | null; checksum: number | null;
         lostTrace: unknown[] }; // the link's last events when it was lost (panels/arm.ts)
  stream: { messages: number }; // physics and pose messages while the physics runs
  // panels/experiment.ts: the pose waiting for its measurement, the engine's question, the
  // poses so far, the report's tables and CSV, lines where the arm differed from the model
  experiment: { running: boolean; waiting: { joint: number; angle: number; line: number; command: string; model: number[] } | null;
    question: string; points: unknown[]; tables: unknown; csv: string; mismatches: string[] };
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
  shareLink: string; // the last link Share made
  shareCopied: string; // what "Copy the link" did last: "copied", "selected" (no clipboard), "" (not pressed)
  programMode: string; // "text" or "blocks"
  programName: string; // the program's file name (a typed one: "program.arm")
  blocksCode: { text: string; robosim: string; python: string } | null; // the program the blocks make
  blockProblems: { block: string; message: string }[]; // warnings on blocks (refusals, values beyond a range)
  runningBlock: string; // the block of the running line
  blockStacks: number; // stacks of blocks in the workspace (procedure definitions aside)
  blocksPending: boolean;
  stops: number; // STOP pressed (button or Escape)
  pngCaption: string; // what the last exported plot picture says it shows // the blocks changed and their program is not made yet
  blocksFirstPaintMs: number; // from opening the blocks to their first frame
  exercise: { parts: { label: string; met: boolean; detail: string; distance_mm: number }[]; met: boolean; error?: string } | null;
  flash: { busy: boolean; phase: string; done: number; total: number; error: string; errorKind: string;
           result: { bytes: number; pages: number; baud: number; seconds: number } | null };
  history: { undo: number; redo: number; undoName: string; redoName: string; undoDetail: string; ready: boolean }; // editor/history.ts: the steps; undoDetail: where the step to undo first changed the project; ready: the project is on screen, an edit now is a step
}

export const hook: Hook = {
  ready: false, connected: false, robot: null, pose: null, ik: null, timeline: null, playing: false,
  paths: { points: 0, lines: 0, worstMm: 0 }, ikLine: "", drawing: null, drawings: 0,
  paper: { area: [], reachShare: 0, maps: 0, hand: 0, ink: { rows: 0, points: 0, strokes: [], received: 0 }, physicsInk: { rows: 0, points: 0, strokes: [], received: 0 } },
  programError: "", robotError: "", lastError: "", teach: "", goal: { drawn: 0, facts: [] }, runOnArm: false, fps: 0, framesDrawn: 0, firstFrameAt: 0,
  latency: [], ikUpdates: [], messages: 0, targetScreen: [0, 0], armPixels: () => 0,
  camera: () => ({ distance: 0, azimuth: 0 }), viewpoint: () => ({ eye: [], target: [] }),
  scene: null, physics: null, events: [], simCommand: "", objectScreen: () => null,
  arm: { connected: false, error: "", label: "", status: null, reply: null, stopMs: null, programLines: [], programDone: false, roundTrips: [], nano: null,
         configurable: false, configured: null, checksum: null, lostTrace: [] },
  stream: { messages: 0 }, experiment: { running: false, waiting: null, question: "", points: [], tables: null, csv: "", mismatches: [] }, errors: 0, errorLog: [], pageErrors: [], internalErrors: [], engineStartMs: 0, engineSend: () => undefined, engineWaiting: () => [],
  layout: { mode: "", plotsInTab: false, tab: "" }, webgl: true, language: "", storage: true,
  project: { id: "", name: "", robot: "", program: "", blocks: null, mode: "text", rev: 0, goal: null, persistent: true, dirty: false,
             saves: 0, saveMs: [], savedAt: 0, saveError: "", lastDeleted: "", otherTab: 0 },
  shareLink: "", shareCopied: "", programMode: "text", programName: "program.arm", blocksCode: null, blockProblems: [], runningBlock: "", blockStacks: 0, blocksPending: false, stops: 0, pngCaption: "",
  blocksFirstPaintMs: 0, exercise: null,
  flash: { busy: false, phase: "", done: 0, total: 0, error: "", errorKind: "", result: null },
  history: { undo: 0, redo: 0, undoName: "", redoName: "", undoDetail: "", ready: false },
};

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
  get(hook.arm, "connected", () => ed.armConnected);
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

/** An error reply from the engine or the arm, as the hook keeps it. */
export function noteError(message: string): void {
  hook.errors++;
  hook.lastError = message;
  hook.errorLog.push(message);
  if (hook.errorLog.length > 50) hook.errorLog.shift();
  if (message.startsWith("internal error")) hook.internalErrors.push(message);
}
