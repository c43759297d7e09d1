// The Editor (after three.js's editor/js/Editor.js): the one object that holds the page's
// state. The project document on screen (`project`, editor/open-project.ts: put on screen,
// read back, each edit a step of the History with undo and redo), the state the engine and
// the arm report (the robot, the pose, the scene, the physics, the program's timeline, the
// arm's link), the signals the panels talk through (no panel imports another), and the parts
// of the state the panel that owns them answers for (the program's text, the blocks, the arm's
// link, the paper). main.ts makes it and wires the panels to it; `window.articula`
// (page/hook.ts) is a read-only view of it.
import type { ArmLink } from "../link/arm-link";
import type { CellDoc, Experiment, Goal, Paper, Project } from "../project/document";
import type { PhysicsMsg, PoseMsg, RobotMsg, SceneMsg, TimelineMsg } from "../engine/messages";
import type { SerialLike } from "../link/ports";
import { History } from "./history";
import { Signal } from "./signal";

/** The program as blocks (the blocks panel answers for it). */
export interface BlocksPart {
  mode(): "text" | "blocks";
  setMode(m: "text" | "blocks", fromProject?: boolean): void;
  json(): object | null; // the workspace as Blockly's JSON, what a project keeps
  load(json: unknown): void; // a project's blocks (null: none)
  fromText(): void; // the program's text as blocks
  record(m: { kind: string; q: number[]; xyz?: number[]; line: string }, name: string): void; // a pose recorded, as a block at the end (named: a function)
  dragging(): boolean; // a block is being dragged: what the workspace holds is not an edit yet
  pending(): boolean; // the blocks changed and their program is not made yet
}

/** The program's text (the program panel answers for it). */
export interface ProgramPart {
  text(): string;
  name(): string; // its file name (program.arm, blocks.arm, drawing.arm, an example's)
  set(text: string, name: string): void; // a new text, as opening a file would put it
}

/** The arm's link (the arm panel answers for it). */
export interface ArmPart {
  link(): ArmLink | null; // while connected
  run(text: string, breaks?: Iterable<number>): void; // a program on the arm, line by line (pausing after `breaks`)
  send(line: string): boolean; // one line, as the Send box sends it; false: no arm
  choosePort(): Promise<{ port: SerialLike; label: string } | { why: string }>;
  disconnect(): Promise<void>;
  pose(): number[] | null; // the joint values of the arm's last status report (null: none)
  restAt(): number; // when (performance.now(), ms) the page read the last report if it said Idle; -Infinity if not
}

/** Draw and write's paper and pen, as a project keeps them (the draw panel answers for it). */
export interface PaperPart {
  get(): Paper;
  set(p: Paper | null): void; // null: the panel's defaults
}

/** The robot file a student opened (with its meshes, base64): the project keeps it. */
export interface RobotFile {
  file: { name: string; text: string; legacy: boolean; scale: number };
  meshes: { name: string; data: string }[];
}

/** Where the documents are kept: project/autosave.ts answers. */
export interface Keeper {
  save(): Promise<void>; // what is on screen, saved now (after any save under way)
  read(id: string): Promise<{ doc: Project; rev: number } | undefined>; // a kept project's latest revision
}

/** The project on screen (editor/open-project.ts answers for it; main.ts wires it). */
export interface ProjectOnScreen {
  id: string;
  rev: number;
  doc: Project; // as last saved or opened
  shown: { id: string; rev: number; doc: Project }; // as last put on screen, or saved
  applying: boolean; // being put on screen: what the page does meanwhile is not an edit
  ready: boolean; // on screen, and the History follows it
  keeper: Keeper;
  readonly busy: boolean; // a project (or an undo's or redo's) is still being put on screen
  follow(): void;
  start(doc: Project, id: string, rev: number): void;
  document(): Project; // as on screen now
  note(doc: Project): void;
  saved(id: string, rev: number, doc: Project): void;
  setExperiment(e: Experiment): void;
  rename(name: string): void;
  setNote(note: string): void;
  open(doc: Project, id?: string, rev?: number): Promise<void>;
}

/** What changed on screen, as the Editor's `changed` signal names it. */
// ("project": another project opened, or an undo or a redo put on screen; "experiment", "name":
// the measurements and the name, which are not the parts' but the document's own)
export type ProjectPart = "robot" | "scene" | "cell" | "program" | "blocks" | "pose" | "view" | "paper" | "experiment" | "name" | "project";

const none = (): never => {
  throw new Error("the Editor's part is not wired yet (main.ts)");
};

export class Editor {
  readonly history = new History();
  // What the engine and the arm say the state is (main.ts and the panels set it as their
  // messages come; everything else reads it here, and `window.articula` shows it):
  robot: RobotMsg | null = null; // the robot shown
  pose: PoseMsg | null = null; // its pose as last drawn
  scene: SceneMsg | null = null; // the scene and its objects
  cell: CellDoc | null = null; // the cell of arms open, its programs as its tabs hold them (panels/cell.ts)
  physics: PhysicsMsg | null = null; // the physics' last step (null: never run)
  timeline: TimelineMsg | null = null; // the program's timeline (null: no program loaded)
  playing = false; // the program plays on the model
  armConnected = false; // the arm's link is open (the Editor's armConnected signal says when it changes)
  // how fast the simulated world runs against real time (the Program panel's speed, ?speed= in
  // the address): the model's playing, the live physics and the virtual Nano; the real arm keeps its own
  speed = 1;
  stops = 0; // STOP pressed (the button or Escape), so far: a wait that began before a STOP ends
  taught = ""; // the last pose taught: a protocol line (text) or a block's values (blocks)
  blocks: BlocksPart = { mode: () => "text", setMode: none, json: () => null, load: none, fromText: none, record: none,
    dragging: () => false, pending: () => false };
  program: ProgramPart = { text: () => "", name: () => "program.arm", set: none };
  arm: ArmPart = { link: () => null, run: none, send: () => false, choosePort: none, disconnect: async () => undefined, pose: () => null, restAt: () => -Infinity };
  paper: PaperPart = { get: none, set: none };
  robotFile: RobotFile | null = null;
  // the camera a project opens with, taken when its robot is first drawn (else the robot is framed)
  keptView: { eye: number[]; target: number[] } | null = null;
  readonly signals = {
    historyChanged: this.history.changed,
    // before an undo or a redo: an edit still waiting to be recorded (typing) is recorded now
    settle: new Signal<void>(),
    // an undo or a redo was taken: the project on screen is changing (it is put on screen
    // meanwhile, and `changed` says "project" once it is there)
    stepTaken: new Signal<"undo" | "redo">(),
    // an exercise asked for by name (the examples menu, the projects list): the projects open it
    exerciseWanted: new Signal<string>(),
    // STOP was pressed (the button or Escape): whatever moves, stops
    stopped: new Signal<void>(),
    // the arm's link opened (true) or closed or lost (false)
    armConnected: new Signal<boolean>(),
    // the simulated world's speed changed (editor.speed)
    speedChanged: new Signal<number>(),
    // the virtual Nano's motors stepped: each motor's steps after every step, row after row
    nanoSteps: new Signal<{ rows: Int32Array; motors: number }>(),
    // the physics moved the arm: its tool point's path since the last time, mm (x, y, z, flat)
    physicsTool: new Signal<number[]>(),
    // a part of the project on screen changed (the robot, the scene, the program's text or
    // blocks, the pose, the camera, the paper and the pen): the project is saved, and an edit
    // of a history part becomes a step of the History (editor/open-project.ts records the step, project/autosave.ts saves)
    changed: new Signal<ProjectPart>(),
    // a drawing exercise's target on the paper (and, after Check, the program's ink); null: none
    drawingGoal: new Signal<{ target: number[][][]; z: number; pen: number; ink?: number[][][] } | null>(),
    // a program's line is running (0: none), on the model, in the physics or on the arm;
    // `refused`: it was refused. The text shows the line, the blocks light its block.
    lineRunning: new Signal<{ line: number; refused: boolean }>(),
    // the model or the arm refused a line of the program: the blocks put it on its block
    lineRefused: new Signal<{ line: number; message: string }>(),
    // what the program's status line says (the program panel shows it)
    programSaid: new Signal<{ text: string; rejected?: string[]; bad?: boolean }>(),
    // a robot is shown (the robot panel built its view): the other panels follow it
    robotShown: new Signal<RobotMsg>(),
    // a project's saved experiment (null: none) to show
    experimentOpened: new Signal<Experiment | null>(),
    // another project is being put on screen (its robot loads first)
    projectOpened: new Signal<Project>(),
    // a project that carries a teacher's note is on screen (from a link, a file)
    noteOpened: new Signal<string>(),
    // a program on the arm paused after this line (0: it goes on, or ended)
    armPaused: new Signal<number>(),
    // the arm reported its joints (a status report, 15 a second while connected)
    armReported: new Signal<number[]>(),
    // the exercise's goal on screen (null: the project is no exercise)
    goalShown: new Signal<Goal | null>(),
  };
  // the project on screen (editor/open-project.ts; main.ts makes it with the Editor)
  project: ProjectOnScreen = {
    id: "", rev: 0, doc: null as unknown as Project, shown: null as unknown as ProjectOnScreen["shown"], applying: true, ready: false,
    keeper: { save: none, read: none }, busy: false, follow: none, start: none, document: none, note: none, saved: none,
    setExperiment: none, rename: none, setNote: none, open: none,
  };
  // true while an edit is being put on screen (a robot loading): undo and redo wait for it,
  // in the order they were asked for (a student tapping Undo three times gets three steps)
  busy(): boolean {
    return this.project.busy;
  }
  private waiting: ("undo" | "redo")[] = [];

  undo(): void {
    this.ask("undo");
  }

  redo(): void {
    this.ask("redo");
  }

  /** The page has put an edit on screen: the next undo or redo asked for meanwhile, if any. */
  settled(): void {
    while (this.waiting.length && !this.busy()) this.act(this.waiting.shift()!);
  }

  private ask(what: "undo" | "redo"): void {
    if (this.busy() || this.waiting.length) {
      if (this.waiting.length < 50) this.waiting.push(what);
      return;
    }
    this.act(what);
  }

  private act(what: "undo" | "redo"): void {
    this.signals.settle.dispatch();
    if (what === "undo" ? this.history.undo() : this.history.redo()) this.signals.stepTaken.dispatch(what);
  }
}
