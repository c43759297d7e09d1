// What the panels report of themselves, as window.articula (page/hook.ts) shows it: the types
// of the facts each panel owns and keeps in its own report object (drawReport in panels/draw.ts,
// ...), which main.ts wires into the hook. Types only: a panel reads and writes its own facts,
// never the hook.
import type { ArmStatusMsg, IkMsg, SimEvent } from "../engine/messages";

// the ink on the sheet: the rows (steps or tool points) it is made of, its points and strokes,
// and the rows received so far (more than it is made of: its next version is on its way)
type Ink = { rows: number; points: number; strokes: number[][][]; received: number };

export interface Reports {
  ik: IkMsg | null;
  // What the view draws of the program: the tool's predicted path (points, every step) and the
  // straight lines asked for (T), with the worst distance of the path from them.
  paths: { points: number; lines: number; worstMm: number };
  ikLine: string; // the last straight line the IK panel made
  // the Draw panel's last drawing: whether the pen reaches it, the engine's refusal or advice,
  // the line the arm will draw (its worst distance, mm, and steps; `ink` its strokes), the program's lines
  drawing: { fits: boolean; error: string; advice: string; worstMm: number; steps: number; lines: number; program: string;
    ink: number[][][] } | null;
  drawings: number; // how many drawings the panel has shown (a test waits for the next)
  // the paper: its sheet on the table ([min_x, min_y, max_x, max_y] mm), the share of it the pen
  // reaches, the strokes drawn by hand; the ink the virtual Nano's steps left (rows: the step rows
  // seen, strokes of [x, y]) and the physics' tool left (rows: its positions seen)
  paper: { area: number[]; reachShare: number; maps: number; hand: number; ink: Ink; physicsInk: Ink };
  programError: string;
  robotError: string;
  // an exercise's goal: its parts drawn in the view, the facts under it, a drawing target's strokes on the paper
  goal: { drawn: number; facts: string[]; target?: number };
  runOnArm: boolean; // Run sends the program to the connected arm ("on the arm" beside it ticked)
  ikUpdates: number[]; // performance.now() of each IK pose drawn while dragging
  events: SimEvent[]; // the physics events since the simulation started or was reset
  arm: { connected: boolean; error: string; label: string; status: ArmStatusMsg | null; reply: unknown; stopMs: number | null;
         programLines: unknown[]; programDone: boolean; roundTrips: number[]; nano: unknown;
         configurable: boolean; configured: { name: string; checksum: number } | null; checksum: number | null;
         lostTrace: unknown[]; console: number; pausedAt: number }; // the link's last events when it was lost (panels/arm.ts)
  // panels/experiment.ts: the pose waiting for its measurement, the engine's question, the
  // poses so far, the report's tables and CSV, lines where the arm differed from the model
  experiment: { running: boolean; waiting: { joint: number; angle: number; line: number; command: string; model: number[] } | null;
    question: string; points: unknown[]; tables: unknown; csv: string; mismatches: string[] };
  shareLink: string; // the last link Share made
  shareCopied: string; // what "Copy the link" did last: "copied", "selected" (no clipboard), "" (not pressed)
  jog: { said: string; jogs: number; held: number; lets: number; last: { asked: number; whole: number | null; line: string } | null; haltAt: number }; // panels/jog.ts
  debug: { breaks: number[]; pausedAt: number; watch: Record<string, string> }; // panels/program.ts: breakpoints, where the model paused, the watch
  noteShown: string; // the teacher's note last shown as a project opened (panels/projects.ts)
  programMode: string; // "text" or "blocks"
  programName: string; // the program's file name (a typed one: "program.arm")
  blocksCode: { text: string; robosim: string; python: string } | null; // the program the blocks make
  blockProblems: { block: string; message: string }[]; // warnings on blocks (refusals, values beyond a range)
  runningBlock: string; // the block of the running line
  blockStacks: number; // stacks of blocks in the workspace (procedure definitions aside)
  pngCaption: string; // what the last exported plot picture says it shows // the blocks changed and their program is not made yet
  blocksFirstPaintMs: number; // from opening the blocks to their first frame
  exercise: { parts: { label: string; met: boolean; detail: string; distance_mm: number }[]; met: boolean; error?: string } | null;
  flash: { busy: boolean; phase: string; done: number; total: number; error: string; errorKind: string;
           result: { bytes: number; pages: number; baud: number; seconds: number } | null };
  wiring: { board: string; firmware: string; wires: number; error: string }; // the Wiring view's (panels/wiring.ts)
  cell: typeof import("../panels/cell").cellReport; // panels/cell.ts: the cell shown (name null: none), its arms, time, events, deadlock
}
