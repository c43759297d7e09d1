// The Draw and write panel: a sheet of paper on the table and a pen held in the gripper; text,
// a shape, an SVG file or strokes drawn by hand on the paper view; the drawing's width and place,
// the paper's height and the pen's length. The engine (host/lib/draw.h, through the worker) lays
// it out, checks the pen reaches it, orders it, writes the program and predicts it step by step,
// and says where on the sheet the pen reaches (the paper view shades it). The paper view and the
// 3D view draw the drawing and the line the arm will draw over each other, and the ink the
// virtual Nano's own steps leave as it runs (the engine's rule for where the pen touches the
// paper, the prediction's too). "Put in the program" hands the program to the editor.
// Everything from a file is shown as text, never as markup.
import type { Studio } from "../page/context";
import { $, download } from "../page/dom";
import type { Reports } from "../page/reports";
import { PaperView } from "./paper-view";
import type { Paper } from "../project/document";
import type { RobotMsg } from "../engine/messages";

/** What the Draw panel has shown (window.articula shows it) (window.articula shows it; main.ts wires it). */
export const drawReport: { drawing: Reports["drawing"]; drawings: number; paper: Reports["paper"] } = {
  drawing: null, drawings: 0, paper: { area: [], reachShare: 0, maps: 0, hand: 0, ink: { rows: 0, points: 0, strokes: [], received: 0 }, physicsInk: { rows: 0, points: 0, strokes: [], received: 0 } },
};

const MAX_SVG_BYTES = 5 * 1024 * 1024; // the engine's limit too (host/lib/svg.h)
const REACH_CELL_MM = 4;

interface Drawing {
  error?: string; what: string; strokes: number[][][]; program: string; width_mm: number; height_mm: number; seconds?: number;
  reach: { fits: boolean; points: number; unreachable: number[][]; advice: string };
  ink?: { strokes: number[][][]; worst_mm: number; worst_at: number[]; worst_line: number; steps: number };
}
interface ReachMap { error?: string; rows: number; cols: number; cell: number; area: number[]; reached: string }

let s: Studio;
let paper: PaperView;
let program = "";
let drawing: Drawing | null = null;
let hand: number[][][] = []; // strokes drawn by hand, on the table (mm)
let nanoMotors = 0;
let drawnLift = NaN; // the last drawing's lift, mm (the engine's default until a drawing)
// The sheet and the pen appear in 3D once the student draws (the panel used, a drawing exercise):
// not on the table of every other lesson.
let inUse = false;
let goalActive = false;
let sheetArea: number[] | null = null;
function use(): void {
  if (inUse) return;
  inUse = true;
  if (sheetArea) s.view.showSheet(sheetArea, num("draw-z"));
  holdPen(num("draw-pen"));
}

// A pen in the gripper (0: none), in 3D and in the engine: the page then shows and aims the
// pen's tip (the IK target, the tool pose), the lines it writes stay the tool point's.
function holdPen(mm: number): void {
  const max = field("pen")?.max ?? 0;
  const pen = Number.isFinite(mm) && mm > 0 && mm <= max ? mm : 0;
  s.view.setPen(pen);
  s.engine.send({ type: "pen", mm: pen });
}

const plural = (n: number, word: string) => `${n} ${word}${n === 1 ? "" : "s"}`;
const input = (id: string) => $(id) as HTMLInputElement;
const num = (id: string) => parseFloat(input(id).value);

function say(text: string, kind: "" | "ok" | "bad" = ""): void {
  const el = $("draw-status");
  el.textContent = text;
  el.className = kind ? `status ${kind}` : "status";
}

// The sheet as the engine takes it: its name, centre and whether it lies landscape.
const sheetRequest = () => ({ paper: ($("draw-paper") as HTMLSelectElement).value, at: [num("paper-x"), num("paper-y")],
  landscape: ($("draw-orient") as HTMLSelectElement).value === "landscape" });

// The sheet's reach map from the engine: the paper view frames and shades it, the 3D view lays it.
let reachTimer = 0;
function askReach(): void {
  clearTimeout(reachTimer);
  reachTimer = window.setTimeout(async () => {
    const { paper: name, at, landscape } = sheetRequest();
    const z = num("draw-z"), pen = num("draw-pen");
    if (![...at, z, pen].every(Number.isFinite)) return;
    const m = (await s.engine.call({ type: "reach_map", request: { paper: name, at, landscape, z, pen, cell: REACH_CELL_MM } })) as
      unknown as ReachMap;
    if (m.error) return say(m.error, "bad");
    paper.setSheet(m.area);
    paper.setReach(m);
    sheetArea = m.area;
    if (inUse) s.view.showSheet(m.area, z);
    drawReport.paper.area = m.area;
    drawReport.paper.reachShare = m.reached.length ? [...m.reached].filter((c) => c === "1").length / m.reached.length : 0;
    drawReport.paper.maps++;
  }, 120);
}

// The ink on the sheet: the virtual Nano's (from its steps) and the physics' (from its tool).
interface InkSource { rows: number[]; strokes: number[][][]; asked: boolean; body: (rows: number[]) => Record<string, unknown> }
const ink: Record<"nano" | "physics", InkSource> = {
  nano: { rows: [], strokes: [], asked: false, body: (rows) => ({ steps: rows }) },
  physics: { rows: [], strokes: [], asked: false, body: (rows) => ({ tool: rows }) },
};

function showInk(): void {
  const all = [...ink.nano.strokes, ...ink.physics.strokes];
  paper.setLayer("ink", all);
  s.view.showInk(all, num("draw-z"));
}

// A source's ink, asked of the engine at most every 250 ms.
let inkEpoch = 0; // a new sheet: the ink asked for before it is not this sheet's
const inkHook = (which: "nano" | "physics") => (which === "nano" ? drawReport.paper.ink : drawReport.paper.physicsInk);
const rowWidth = (which: "nano" | "physics") => Math.max(1, which === "nano" ? nanoMotors : 3);

function askInk(which: "nano" | "physics"): void {
  const src = ink[which];
  inkHook(which).received = src.rows.length / rowWidth(which);
  if (src.asked) return;
  src.asked = true;
  const epoch = inkEpoch;
  window.setTimeout(async () => {
    const rows = src.rows.length;
    const m = (await s.engine.call({ type: "ink", request: { ...src.body(src.rows.slice()), z: num("draw-z"), pen: num("draw-pen"),
      lift: drawnLift } })) as
      unknown as { error?: string; strokes: number[][][]; points: number };
    if (epoch !== inkEpoch) return; // the sheet was cleared meanwhile
    src.asked = false;
    if (m.error) {
      return say(`The ${which === "nano" ? "virtual Nano's" : "physics'"} ink: ${m.error}`, "bad");
    }
    src.strokes = m.strokes;
    showInk();
    const seen = { rows: rows / rowWidth(which), points: m.points, strokes: m.strokes, received: src.rows.length / rowWidth(which) };
    if (which === "nano") drawReport.paper.ink = seen;
    else drawReport.paper.physicsInk = seen;
    if (src.rows.length > rows) askInk(which);
  }, 250);
}

function clearInk(): void {
  inkEpoch++;
  for (const src of Object.values(ink)) {
    src.rows = [];
    src.strokes = [];
    src.asked = false;
  }
  drawReport.paper.ink = { rows: 0, points: 0, strokes: [], received: 0 };
  drawReport.paper.physicsInk = { rows: 0, points: 0, strokes: [], received: 0 };
  showInk();
}

// A new sheet: no ink, nothing drawn by hand.
function newSheet(): void {
  hand = [];
  drawReport.paper.hand = 0;
  paper.setLayer("hand", []);
  clearInk();
}

function clearDrawing(): void {
  drawing = null;
  program = "";
  ($("draw-use") as HTMLButtonElement).disabled = true;
  for (const l of ["ideal", "predicted"] as const) paper.setLayer(l, []);
  paper.setMarks([], null);
  s.view.showDrawing([], [], 0);
}

// A new sheet: A5 in front of the arm where its pen draws, and the pen it holds (the engine's
// places for the arm: a 120 mm pen at 250 mm for the MK2 Plus, 70 mm at 170 mm for the meArm;
// a request without a pen has none: host/lib/draw.h).
function defaultPaper(r: RobotMsg | null = s.editor.robot): Paper {
  const p = r?.places;
  return { sheet: "A5", at: p ? [p.draw_at[0], p.draw_at[1]] : [250, 0], landscape: false, z: p?.paper_z ?? 0, pen: p?.pen ?? 120 };
}
const samePaper = (a: Paper, b: Paper) => JSON.stringify(a) === JSON.stringify(b);
let shownDefault: Paper | null = null; // the last robot's new sheet (its paper follows the robot while untouched)

function paperSettings(): Paper {
  const { paper: sheet, at, landscape } = sheetRequest();
  const d = defaultPaper();
  const v = (x: number, fallback: number) => (Number.isFinite(x) ? x : fallback);
  return { sheet: sheet as Paper["sheet"], at: [v(at[0], d.at[0]), v(at[1], d.at[1])], landscape, z: v(num("draw-z"), d.z),
    pen: v(num("draw-pen"), d.pen) };
}

// The pen's boxes, by the engine's key (host/lib/draw.h kPenFields: defaults and ranges live there).
const PEN_BOXES: Record<string, string> = { pen: "draw-pen", lift: "draw-lift", speed: "draw-speed", travel_speed: "draw-travel" };
const field = (key: string) => s.engine.penFields.find((f) => f.key === key);

/** The engine is ready: the pen's boxes take its ranges, and its defaults (the pen's length is the sheet's). */
export function drawReady(): void {
  for (const f of s.engine.penFields) {
    const box = PEN_BOXES[f.key];
    if (!box) continue;
    input(box).min = String(f.min);
    input(box).max = String(f.max);
    if (f.key !== "pen" && input(box).value === "") input(box).value = String(f.default);
  }
  if (!Number.isFinite(drawnLift)) drawnLift = field("lift")?.default ?? NaN;
}

function setPaper(p: Paper | null): void {
  const q = p ?? defaultPaper();
  ($("draw-paper") as HTMLSelectElement).value = q.sheet;
  ($("draw-orient") as HTMLSelectElement).value = q.landscape ? "landscape" : "portrait";
  input("paper-x").value = String(q.at[0]);
  input("paper-y").value = String(q.at[1]);
  input("draw-z").value = String(q.z);
  input("draw-pen").value = String(q.pen);
  askReach();
}

export function initDraw(studio: Studio): void {
  s = studio;
  paper = new PaperView($("paper-view") as unknown as SVGSVGElement);
  const kind = $("draw-kind") as HTMLSelectElement;
  const showKind = () => {
    $("draw-text").hidden = kind.value !== "text";
    $("draw-file").hidden = kind.value !== "svg";
    paper.freehand = kind.value === "hand";
    $("draw-place").hidden = paper.freehand; // drawn by hand: where it was drawn, as big
    $("paper-view").classList.toggle("freehand", paper.freehand);
    $("paper-hint").textContent = paper.freehand
      ? "Draw on the paper with a finger or the mouse, then Draw."
      : "Drag the sheet to move it. Shaded: where the pen reaches the paper.";
  };
  kind.addEventListener("change", showKind);
  showKind();
  paper.onStroke = (points) => {
    hand.push(points);
    drawReport.paper.hand = hand.length;
  };
  paper.onMoveSheet = (dx, dy) => {
    input("paper-x").value = String(num("paper-x") + dx);
    input("paper-y").value = String(num("paper-y") + dy);
    input("draw-x").value = String(num("draw-x") + dx);
    input("draw-y").value = String(num("draw-y") + dy);
    hand = hand.map((st) => st.map(([x, y]) => [x + dx, y + dy]));
    paper.setLayer("hand", hand);
    askReach();
    s.editor.signals.changed.dispatch("paper");
    if (drawing) void draw();
  };
  for (const id of ["draw-paper", "draw-orient", "paper-x", "paper-y", "draw-z", "draw-pen"])
    $(id).addEventListener("change", () => {
      askReach();
      s.editor.signals.changed.dispatch("paper"); // the project keeps them
    });
  s.editor.paper = { get: paperSettings, set: setPaper };
  $("draw-go").onclick = () => void draw();
  $("draw-text").addEventListener("keydown", (e) => { // Enter draws; Shift+Enter starts a new line
    if (e.key === "Enter" && !e.shiftKey) {
      e.preventDefault();
      void draw();
    }
  });
  $("draw-use").onclick = () => {
    if (!program) return;
    s.editor.program.set(program, "drawing.arm");
    say("The drawing is the program now: Run plays it, on the arm too when it is connected.", "ok");
  };
  $("draw-new-sheet").onclick = () => {
    newSheet();
    say("A new sheet: no ink on it.", "ok");
  };
  $("draw-save-svg").onclick = () => download("drawing.svg", paper.svgText(drawing?.what ?? "a sheet"), "image/svg+xml");
  $("draw-save-png").onclick = () => void savePng();
  $("draw-pen").addEventListener("change", () => inUse && holdPen(num("draw-pen")));
  for (const id of ["draw-paper", "draw-orient", "paper-x", "paper-y", "draw-z", "draw-kind", "draw-go"])
    $(id).addEventListener(id === "draw-go" ? "click" : "change", use);
  $("paper-view").addEventListener("pointerdown", use);
  s.editor.signals.robotShown.add((r) => {
    clearDrawing();
    inUse = false;
    holdPen(0);
    // a sheet no one moved is the new arm's (the MK2's sheet is beyond a meArm's reach)
    if (!goalActive && samePaper(paperSettings(), shownDefault ?? defaultPaper(null))) setPaper(defaultPaper(r));
    shownDefault = defaultPaper(r);
    s.view.showSheet(null, 0);
    if (goalActive) use(); // a drawing exercise's robot: its paper and pen stay
    drawReport.drawing = null;
    askReach();
  });
  s.editor.signals.nanoSteps.add(({ rows, motors }) => {
    nanoMotors = motors;
    if (!inUse) return; // ink once there is a sheet and a pen (the panel used), not a pick and place's
    for (const v of rows) ink.nano.rows.push(v);
    askInk("nano");
  });
  s.editor.signals.drawingGoal.add((g) => {
    paper.setLayer("target", g?.target ?? []);
    goalActive = !!g;
    if (!g) return;
    input("draw-z").value = String(g.z); // the exercise's paper and pen
    input("draw-pen").value = String(g.pen);
    use();
    askReach();
    if (g.ink) {
      paper.setLayer("predicted", g.ink);
      $("draw-section").scrollIntoView({ block: "nearest" });
    }
  });
  s.editor.signals.physicsTool.add((xyz) => {
    if (!inUse) return; // ink once there is a sheet and a pen (the panel used)
    ink.physics.rows.push(...xyz);
    askInk("physics");
  });
}

// The paper view as a PNG, 8 pixels a millimetre: its SVG drawn on a canvas.
async function savePng(): Promise<void> {
  const text = paper.svgText(drawing?.what ?? "a sheet");
  const url = URL.createObjectURL(new Blob([text], { type: "image/svg+xml" }));
  try {
    const img = new Image();
    img.src = url;
    await img.decode();
    const [, , w, h] = (paper.svg.getAttribute("viewBox") ?? "0 0 100 100").split(" ").map(Number);
    const canvas = document.createElement("canvas");
    canvas.width = Math.round(w * 8);
    canvas.height = Math.round(h * 8);
    const g = canvas.getContext("2d")!;
    g.fillStyle = "#ffffff";
    g.fillRect(0, 0, canvas.width, canvas.height);
    g.drawImage(img, 0, 0, canvas.width, canvas.height);
    const blob = await new Promise<Blob | null>((r) => canvas.toBlob(r, "image/png"));
    if (blob) download("drawing.png", blob, "image/png");
  } catch (e) {
    say(`No PNG: ${(e as Error).message}`, "bad");
  } finally {
    URL.revokeObjectURL(url);
  }
}

async function draw(): Promise<void> {
  const kind = ($("draw-kind") as HTMLSelectElement).value;
  const request: Record<string, unknown> = {
    width: num("draw-width"), at: [num("draw-x"), num("draw-y")], z: num("draw-z"), pen: num("draw-pen"),
    speed: num("draw-speed"), travel_speed: num("draw-travel"), lift: num("draw-lift"),
    paper: ($("draw-paper") as HTMLSelectElement).value, // a drawing bigger than the sheet is refused
  };
  // the engine's rotation is from the drawing's own axes; 90 stands it upright for a student at +x
  const turn = num("draw-turn");
  if (turn) request.rotate = 90 + turn;
  const steps = ($("draw-steps") as HTMLSelectElement).value;
  if (steps) request.microsteps = Number(steps);
  for (const [k, v] of Object.entries(request))
    if ((typeof v === "number" && !Number.isFinite(v)) || (Array.isArray(v) && !v.every(Number.isFinite)))
      return say(`The ${k === "at" ? "place (x, y)" : k} holds no number: type one.`, "bad");
  if (kind === "text") {
    request.text = ($("draw-text") as HTMLTextAreaElement).value;
    request.line_spacing = num("draw-spacing");
    if (!Number.isFinite(request.line_spacing as number)) return say("The line spacing holds no number: type one.", "bad");
    if (!request.text) return say("Type the text to write.", "bad");
  } else if (kind === "svg") {
    const f = input("draw-file").files?.[0];
    if (!f) return say("Choose an SVG file to draw.", "bad");
    if (f.size > MAX_SVG_BYTES) return say(`${f.name}: ${Math.round(f.size / 1024)} KB: a drawing is at most 5 MB.`, "bad");
    request.svg = await f.text();
    request.svg_name = f.name;
  } else if (kind === "hand") {
    if (!hand.length) return say("Draw on the paper first: with a finger or the mouse.", "bad");
    request.strokes = hand;
    delete request.at; // drawn where it goes
    delete request.width;
  } else {
    request.shape = kind;
  }
  say("drawing…");
  const d = (await s.engine.call({ type: "draw", request })) as unknown as Drawing;
  clearDrawing();
  clearInk(); // the ink from here on is this drawing's
  if (d.error) {
    drawReport.drawing = { fits: false, error: d.error, advice: "", worstMm: 0, steps: 0, lines: 0, program: "", ink: [] };
    drawReport.drawings++;
    return say(d.error, "bad");
  }
  drawing = d;
  drawnLift = request.lift as number; // the ink's rule: the pen on the paper below half of it
  if (kind === "hand") {
    hand = [];
    paper.setLayer("hand", []);
  }
  const z = request.z as number;
  use();
  holdPen(request.pen as number);
  s.view.showDrawing(d.strokes, d.ink?.strokes ?? [], z);
  paper.setLayer("ideal", d.strokes);
  paper.setLayer("predicted", d.ink?.strokes ?? []);
  paper.setMarks(d.reach.unreachable, d.ink ? d.ink.worst_at : null);
  drawReport.drawing = { fits: d.reach.fits, error: "", advice: d.reach.advice, worstMm: d.ink?.worst_mm ?? 0, steps: d.ink?.steps ?? 0,
    lines: d.program ? d.program.split("\n").length - 1 : 0, program: d.program, ink: d.ink?.strokes ?? [] };
  drawReport.drawings++;
  if (!d.reach.fits) return say(`${d.what}: ${d.reach.advice}. The red dots are out of the pen's reach.`, "bad");
  program = d.program;
  ($("draw-use") as HTMLButtonElement).disabled = false;
  const size = `${d.width_mm.toFixed(0)} × ${d.height_mm.toFixed(0)} mm`;
  say(d.ink
    ? `${d.what}, ${size}: ${plural(d.strokes.length, "stroke")}, ${drawReport.drawing.lines} lines, ${d.seconds?.toFixed(0)} s. ` +
      `The pen (orange) stays within ${d.ink.worst_mm.toFixed(2)} mm of the drawing (blue) at every one of its ${d.ink.steps} ` +
      `steps; the worst (ringed) on line ${d.ink.worst_line}.`
    : `${d.what}, ${size}: ${plural(d.strokes.length, "stroke")}, ${drawReport.drawing.lines} lines.`, "ok");
  $("draw-status").scrollIntoView({ block: "nearest" });
}
