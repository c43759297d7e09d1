// A cell of arms (cells/README.md) on the page: the Physics menu's cells open a shipped cell, its
// arms drawn in a colour each where the cell stands them (view/cell-arms.ts), all of them on their
// own firmware in the engine (engine/cell.ts); the physics bar runs, pauses, steps and resets it,
// STOP pauses it, and the events say which arm did what. A deadlock is told in words under the view.
//
// While a cell is open, the cell's panels take the one robot's (style.css, body.cell-open):
// - the cell's arms (the Joints tab): each arm's line now, or what it waits for, and its joints;
// - the cell's programs (the Program tab): a tab for each arm's program, Run all, and the
//   timeline: each arm's lines in time as its own firmware runs them in the cell, moves in its
//   colour, waits hatched, an arrow from each output to the wait it ends.
// Every name and line from a cell file is shown as text, never markup.
import type { CellFrameMsg, CellMsg, CellRefusedMsg, CellTimeline, SimEvent } from "../engine/messages";
import type { Studio } from "../page/context";
import { $, download, fill, h, svgEl } from "../page/dom";
import { ARM_COLORS } from "../view/cell-arms";
import { logEvents } from "./physics";
import { CellNanos } from "./cell-nanos";
import type { NanoRun } from "./cell-nanos";

type Signal = CellFrameMsg["arms"][number]["signals"][number];

/** What window.articula shows of the cell (main.ts wires it). */
export const cellReport: {
  name: string | null; title: string; arms: string[]; t: number; running: boolean; done: boolean; deadlock: string;
  events: SimEvent[]; lines: number[]; signals: Signal[][]; frames: number;
  programs: string[]; tab: number; refused: string; timeline: CellTimeline[]; arrows: number; doing: string[]; flashed: string[];
  nanos: NanoRun | null; // the arms on virtual Nanos (null: in the engine)
  said: string[][]; // each arm's box's words so far, each once (the last 40): what a passing wait said
  mats: number; // mats saved (Mat to print)
} = { name: null, title: "", arms: [], t: 0, running: false, done: false, deadlock: "", events: [], lines: [], signals: [], frames: 0,
  programs: [], tab: 0, refused: "", timeline: [], arrows: 0, doing: [], flashed: [], nanos: null, said: [], mats: 0 };

let s: Studio;
let reveal: (id: string) => void = () => undefined;
let shipped: string[] = []; // each arm's program as the cell comes
let texts: string[] = []; // as the tabs hold them (edited or not)
let timelineEnd = 1; // s: the timeline's right edge
let cursor: SVGLineElement | null = null;
let timelineX = (t: number) => t;
let lastCell: CellMsg | null = null; // the cell whose timeline is drawn

export const cellRunning = () => cellReport.name !== null && ((cellReport.running && !cellReport.done) || !!nanos?.run.running);
let nanos: CellNanos | null = null; // the arms on virtual Nanos of their own, while they run there
const onNanos = () => ($("cell-run-on") as HTMLSelectElement).value === "nanos";
const colour = (k: number) => `#${ARM_COLORS[k % ARM_COLORS.length].toString(16).padStart(6, "0")}`;

export function initCell(studio: Studio, layout: { reveal: (id: string) => void }): void {
  s = studio;
  reveal = layout.reveal;
  const ed = $("cell-program") as HTMLTextAreaElement;
  ed.addEventListener("input", () => {
    texts[cellReport.tab] = ed.value;
    edited();
  });
  $("cell-run-all").onclick = () => void runAll();
  $("cell-run-on").addEventListener("change", () => {
    if (!onNanos()) void endNanos(); // (the engine's arms again: Run all runs them)
  });
  s.editor.signals.stopped.add(() => void nanos?.stop());
  // drawn at the width it is shown at: again when that changes (a tab shown, a turned tablet)
  let drawnAt = 0;
  new ResizeObserver(() => {
    const w = $("cell-timeline").clientWidth;
    if (lastCell && w > 0 && Math.abs(w - drawnAt) > 8) {
      drawnAt = w;
      drawTimeline(lastCell);
    }
  }).observe($("cell-timeline"));
  // the table's mat, as a file to print (an SVG the engine draws: names in it are text)
  $("cell-mat").onclick = async () => {
    try {
      const r = (await s.engine.call({ type: "cell_mat" })) as unknown as { name: string; svg: string };
      download(`${r.name}-mat.svg`, r.svg, "image/svg+xml");
      cellReport.mats++;
    } catch (e) {
      $("cell-program-state").textContent = (e as Error).message;
    }
  };
  $("cell-revert").onclick = () => {
    texts = [...shipped];
    showTab(cellReport.tab);
    edited();
    runAll();
  };
}

/** Run all: every arm from the start, each with the program in its tab: in the engine, or on
 * virtual Nanos (the engine's cell, made with them, checks them and draws the timeline first). */
async function runAll(): Promise<void> {
  cellReport.refused = "";
  const st = $("cell-program-state");
  st.className = "status";
  st.textContent = "";
  await endNanos();
  if (!onNanos()) return s.engine.send({ type: "cell_run", programs: texts });
  const reply = (await s.engine.call({ type: "cell_run", programs: texts })) as unknown as CellMsg | CellRefusedMsg;
  if (reply.type === "cell_refused") return showCellRefused(reply);
  await showCell(reply);
  const n = new CellNanos(s, reply.arms ?? [], reply.wires ?? [], (k, frames, fingers) => {
    if (nanos === n) s.view.cellArms.poseArm(k, frames, fingers);
  }, () => nanos === n && showNanos(n));
  nanos = n;
  cellReport.nanos = n.run;
  s.engine.send({ type: "physics_reset" }); // (its arms stand aside, at rest, and the objects where they start)
  st.textContent = "Powering up a virtual Nano for each arm, and configuring it for its arm…";
  await n.start(texts);
  if (nanos === n && n.run.arms.every((a) => a.connected)) st.textContent = "";
}

async function endNanos(): Promise<void> {
  const n = nanos;
  nanos = null;
  cellReport.nanos = null;
  await n?.close();
}

// The arms on their Nanos: what each does, and each Nano's speed against real time.
function showNanos(n: CellNanos): void {
  cellReport.doing = n.run.arms.map((a, k) => showDoing(k, {
    text: a.error ? `its Nano: ${a.error}` : !a.connected ? "its virtual Nano powers up…"
      : a.done ? (a.stopped ? "stopped (STOP)" : "its program has ended") : a.line > 0 ? lineWords(k, a.line) : "ready",
    kind: a.error ? "waits" : a.done ? "ended" : "",
  }));
  const speeds = n.run.arms.map((a) => `${a.name} ${a.rtf === null ? "…" : `${a.rtf.toFixed(2)}x`}`).join(", ");
  $("view-status").textContent = `On virtual Nanos, t = ${n.run.t.toFixed(2)} s: ${speeds} real time` +
    (n.run.arms.some((a) => a.behind) ? " (behind: this machine cannot keep up)" : "") + (n.run.running ? "" : ", every program ended") +
    // (the belts, barriers, switches and feeders are the physics': the Nanos' wires reach the arms only)
    (lastCell?.devices?.length ? "; the cell's devices need the physics: here they stand, and a wait on one runs out" : "");
  $("phys-rtf").textContent = n.run.running ? "on virtual Nanos" : "ended";
  moveCursor(n.run.t);
}

// Arm k's box: what it does now (and its joints, where known); the words, for the report.
function showDoing(k: number, d: { text: string; kind: string }, joints?: number[]): string {
  const said = (cellReport.said[k] ??= []);
  if (!said.includes(d.text)) said.splice(0, Math.max(0, said.push(d.text) - 40));
  const box = $("cell-arms").children[k];
  if (!box) return d.text;
  const line = box.querySelector(".doing")!;
  line.className = `doing ${d.kind}`;
  line.textContent = d.text;
  if (joints) box.querySelector(".joints")!.textContent = `joints ${joints.map((q) => q.toFixed(1)).join("  ")}`;
  return d.text;
}

const lineWords = (k: number, line: number) => `line ${line}: ${(texts[k] ?? "").split("\n")[line - 1]?.trim() ?? ""}`;

// The timeline's cursor at the cell's time t (s).
function moveCursor(t: number): void {
  if (!cursor) return;
  const x = String(timelineX(Math.min(t, timelineEnd)));
  cursor.setAttribute("x1", x);
  cursor.setAttribute("x2", x);
}

function showTab(k: number): void {
  cellReport.tab = k;
  for (const [i, b] of Array.from($("cell-tabs").children).entries()) {
    b.setAttribute("aria-selected", String(i === k));
    (b as HTMLElement).tabIndex = i === k ? 0 : -1;
  }
  const ed = $("cell-program") as HTMLTextAreaElement;
  ed.value = texts[k] ?? "";
  ed.setAttribute("aria-label", `The program of ${cellReport.arms[k] ?? "the arm"}`);
}

function markEdited(): void {
  for (const [i, b] of Array.from($("cell-tabs").children).entries()) b.classList.toggle("edited", texts[i] !== shipped[i]);
}

// The tabs' programs changed: the project keeps them (a step of the History, saved)
function edited(): void {
  cellReport.programs = [...texts];
  markEdited();
  if (cellReport.name === null) return;
  s.editor.cell = { name: cellReport.name, programs: [...texts] };
  s.editor.signals.changed.dispatch("cell");
}

export async function showCell(m: CellMsg): Promise<void> {
  const reopened = m.name !== null && m.name === cellReport.name; // Run all: the same cell again
  if (!reopened) await endNanos();
  cellReport.name = m.name;
  cellReport.title = m.title ?? "";
  cellReport.arms = (m.arms ?? []).map((a) => a.name);
  cellReport.said = [];
  cellReport.events = [];
  cellReport.deadlock = "";
  cellReport.frames = 0;
  cellReport.flashed = [];
  const on = m.name !== null;
  document.body.classList.toggle("cell-open", on);
  // an exercise's goal and Check go with the programs they check: the cell's, while one is open
  if (on) $("cell-section").insertBefore($("exercise"), $("cell-tabs"));
  else $("program-status").after($("exercise"));
  const was = JSON.stringify(s.editor.cell);
  ($("scene-select") as HTMLSelectElement).value = on ? `cell:${m.name}` : s.editor.scene?.name ?? "";
  $("physics-bar").hidden = !on && !s.editor.scene?.name;
  $("events").hidden = !on && !s.editor.scene?.name;
  fill($("events"));
  // the arms' names in their colours, under the view
  // (the colour through the CSSOM: the site's Content-Security-Policy refuses style attributes)
  fill($("cell-legend"), ...(m.arms ?? []).map((a, k) => {
    const key = h("i", { class: "key" });
    key.style.background = colour(k);
    return h("span", {}, key, `${a.name} (${a.robot.name})`);
  }));
  $("cell-legend").hidden = !on;
  if (on) {
    s.view.setObjects(m.objects ?? []);
    $("view-status").textContent = `${m.title}: ${cellReport.arms.length} arms, each on its own firmware`;
    showPrograms(m, reopened);
    showArms(m);
    cellReport.timeline = (m.arms ?? []).map((a) => a.timeline);
    drawTimeline(m);
    if (!reopened) reveal("cell-section");
  } else if (!s.editor.scene?.name) {
    s.view.setObjects([]);
    $("view-status").textContent = "";
  }
  s.editor.cell = on ? { name: m.name!, programs: [...texts] } : null;
  if (JSON.stringify(s.editor.cell) !== was) s.editor.signals.changed.dispatch("cell");
  await s.view.showCell(m);
}

// The tabs of the arms' programs, as the arms run them (the cell's own, Run all's, a project's).
function showPrograms(m: CellMsg, reopened: boolean): void {
  const arms = m.arms ?? [];
  shipped = arms.map((a) => a.shipped);
  texts = arms.map((a) => a.program);
  if (!reopened) cellReport.tab = 0;
  cellReport.programs = [...texts];
  fill($("cell-tabs"), ...arms.map((a, k) => {
    const key = h("i", { class: "key" });
    key.style.background = colour(k);
    const b = h("button", { role: "tab", title: `${a.name}: the ${a.robot.name}'s program` }, key, a.name);
    b.style.borderBottomColor = colour(k);
    b.addEventListener("click", () => showTab(k));
    return b;
  }));
  $("cell-tabs").onkeydown = (e) => {
    const step = { ArrowRight: 1, ArrowLeft: -1 }[e.key];
    if (step === undefined) return;
    const k = (cellReport.tab + step + arms.length) % arms.length;
    showTab(k);
    ($("cell-tabs").children[k] as HTMLElement).focus();
  };
  showTab(Math.min(cellReport.tab, arms.length - 1));
  markEdited();
}

/** Run all refused a program: its arm's tab, its line selected, and why. The cell runs on as it was. */
export function showCellRefused(m: CellRefusedMsg): void {
  if (m.programs.length === texts.length) { // (a project's cell opens with its own programs: they stay in the tabs)
    texts = [...m.programs];
    edited();
  }
  const k = m.arm === null ? -1 : cellReport.arms.indexOf(m.arm);
  showTab(k >= 0 ? k : cellReport.tab);
  const where = `${m.arm ?? "the cell"}${m.line > 0 ? `, line ${m.line}` : ""}`;
  cellReport.refused = `${where}: ${m.text}`;
  const st = $("cell-program-state");
  st.className = "status bad";
  st.setAttribute("role", "alert");
  st.textContent = `Not run: ${cellReport.refused}. The arms go on with the programs they had.`;
  if (k >= 0 && m.line > 0) {
    const ed = $("cell-program") as HTMLTextAreaElement;
    const lines = ed.value.split("\n");
    const start = lines.slice(0, m.line - 1).reduce((n, l) => n + l.length + 1, 0);
    ed.focus();
    ed.setSelectionRange(start, start + (lines[m.line - 1]?.length ?? 0));
  }
}

// The cell's arms, a box each in its colour: its robot and firmware, and (each frame) its line or wait.
function showArms(m: CellMsg): void {
  fill($("cell-arms"), ...(m.arms ?? []).map((a, k) => {
    const box = h("div", { class: "cell-arm" },
      h("b", {}, a.name), ` · ${a.robot.name}` + (a.robot.firmware ? ` on ${a.robot.firmware}` : ""),
      h("div", { class: "doing" }), h("div", { class: "joints" }));
    box.style.borderLeftColor = colour(k);
    return box;
  }));
  const wires = m.wires ?? [];
  $("cell-wires").textContent = wires.length ? `Wires: ${wires.map((w) => `${w.from} – ${w.to}`).join(", ")}` : "No wires between the arms.";
}

// What an arm does at time t: its line now, the input it waits for, or that it has ended.
function doing(k: number, a: CellFrameMsg["arms"][number], t: number): { text: string; kind: string } {
  const wait = a.signals.find((x) => x.kind === "wait" && x.end_t == null);
  if (wait)
    return { kind: "waits", text: `line ${wait.line}: waits for ${wait.name || wait.pin} (${wait.pin}) to read ${wait.level}` +
      `, since ${wait.t.toFixed(2)} s` };
  const end = cellReport.timeline[k]?.end_s;
  if (end !== undefined && t >= end) return { kind: "ended", text: `its program ended at ${end.toFixed(2)} s` };
  return { kind: "", text: a.line > 0 ? lineWords(k, a.line) : "at power-up" };
}

export function showCellFrame(f: CellFrameMsg): void {
  if (cellReport.name === null) return;
  // on virtual Nanos: the world's objects, the arms at power-up (a reset's), then as their Nanos report
  if (nanos) return s.view.cellFrame(f, !!f.fresh);
  s.view.cellFrame(f);
  cellReport.t = f.t;
  cellReport.running = f.running;
  cellReport.done = f.done;
  cellReport.lines = f.arms.map((a) => a.line);
  cellReport.signals = f.arms.map((a) => a.signals);
  cellReport.frames++;
  if (f.fresh) {
    cellReport.events = [];
    fill($("events"));
  }
  cellReport.events.push(...f.events);
  // the parts an event names flash: the arm's own (its name first), and what it met, another
  // arm's part (named with that arm) or an object: a collision between arms shows on both links
  logEvents(f.events, (e) => {
    if (e.kind === "contact_ended") return;
    for (const part of [e.a && (e.arm ? `${e.arm}: ${e.a}` : e.a), e.b !== "ground" && e.b])
      if (part && s.view.flash(part) && cellReport.flashed.length < 100) cellReport.flashed.push(part);
  });
  cellReport.deadlock = f.deadlock;
  const waits = f.arms.filter((a) => a.signals.some((x) => x.kind === "wait" && x.end_t == null)).map((a) => a.name);
  $("view-status").textContent = `t = ${f.t.toFixed(2)} s` + (f.done ? ", every program ended" : f.running ? "" : ", paused") +
    (f.deadlock && waits.length > 1 ? `: stuck, ${f.deadlock}` : waits.length ? `: ${waits.join(", ")} waiting for a signal` : "");
  $("phys-rtf").textContent = f.running && !f.done ? "running" : f.done ? "ended" : `paused at ${f.t.toFixed(2)} s`;
  cellReport.doing = f.arms.map((a, k) => showDoing(k, doing(k, a, f.t), a.joints));
  moveCursor(f.t);
}

// The timeline: a row an arm, time across. Each line of its program where its firmware runs it
// in the cell: a move (or the gripper, a dwell) in the arm's colour, a wait (W) hatched, an
// output (O) a flag; an arrow from an output to each wait that ends at it (within 2 ms).
const ROW = 28, LEFT = 58, RIGHT = 14, TOP = 6, AXIS = 18;
function drawTimeline(m: CellMsg): void {
  lastCell = m;
  const svg = $("cell-timeline") as unknown as SVGSVGElement;
  const WIDTH = Math.max(240, svg.clientWidth || 310); // (one unit a pixel where it is shown: its text at the page's size)
  const arms = m.arms ?? [];
  const rows = arms.map((a) => a.timeline ?? { lines: [] });
  timelineEnd = Math.max(1, ...rows.map((r) => r.end_s ?? 0)) * 1.02;
  const height = TOP + arms.length * ROW + AXIS;
  svg.setAttribute("viewBox", `0 0 ${WIDTH} ${height}`);
  svg.setAttribute("height", String(height));
  timelineX = (t: number) => LEFT + (t / timelineEnd) * (WIDTH - LEFT - RIGHT);
  const x = timelineX;
  const defs = svgEl("defs");
  const hatch = svgEl("pattern", { id: "cell-hatch", width: 4, height: 4, patternUnits: "userSpaceOnUse", patternTransform: "rotate(45)" });
  hatch.append(svgEl("rect", { width: 4, height: 4, fill: "#fff4d6" }), svgEl("line", { x1: 0, y1: 0, x2: 0, y2: 4, stroke: "#d9a400", "stroke-width": 1.5 }));
  const arrow = svgEl("marker", { id: "cell-arrow", viewBox: "0 0 6 6", refX: 5, refY: 3, markerWidth: 6, markerHeight: 6, orient: "auto" });
  arrow.append(svgEl("path", { d: "M0,0 L6,3 L0,6 z", fill: "#b58100" }));
  defs.append(hatch, arrow);
  const parts: SVGElement[] = [defs];
  const outputs: { k: number; t: number }[] = [];
  const waits: { k: number; end: number }[] = [];
  rows.forEach((r, k) => {
    const y = TOP + k * ROW;
    parts.push(svgEl("text", { x: 2, y: y + ROW / 2 + 3, class: "arm-name" }, arms[k].name));
    parts.push(svgEl("line", { x1: LEFT, y1: y + ROW / 2, x2: WIDTH - RIGHT, y2: y + ROW / 2, class: "axis" }));
    if (r.why) parts.push(svgEl("text", { x: LEFT + 4, y: y + ROW / 2 - 3 }, "no timeline: " + r.why.slice(0, 60)));
    for (const l of r.lines) {
      const word = l.command.trim().split(/\s+/)[0]?.toUpperCase() ?? "";
      const tip = svgEl("title", {}, `${arms[k].name}, line ${l.line}: ${l.command}  ${l.start_s.toFixed(2)}–${l.end_s.toFixed(2)} s` +
        (l.ok ? "" : " (refused)"));
      if (!l.ok) {
        const mark = svgEl("rect", { x: x(l.start_s) - 1.5, y: y + 4, width: 3, height: ROW - 8, class: "refused" });
        mark.append(tip);
        parts.push(mark);
      } else if (word === "O") {
        outputs.push({ k, t: l.start_s });
        const flag = svgEl("path", { d: `M${x(l.start_s)},${y + ROW - 4} V${y + 3} l7,3 l-7,3`, stroke: "#b58100", "stroke-width": 1.4,
          fill: "#f2c14e" });
        flag.append(tip);
        parts.push(flag);
      } else if (l.end_s > l.start_s) {
        const wait = word === "W";
        // a wait on a device (a light barrier): when an object comes, only the physics knows; the
        // prediction runs it to its time
        const device = wait ? arms[k].io?.find((p) => p.by_device && String(p.number) === l.command.trim().split(/\s+/)[1]) : undefined;
        if (wait && !device) waits.push({ k, end: l.end_s });
        if (device) tip.textContent = `${arms[k].name}, line ${l.line}: ${l.command}: waits for ${device.driven_by} from ` +
          `${l.start_s.toFixed(2)} s, at most until ${l.end_s.toFixed(2)} s; when an object breaks the beam, the physics says`;
        const bar = svgEl("rect", { x: x(l.start_s), y: y + (wait ? 6 : 7), width: Math.max(1, x(l.end_s) - x(l.start_s)),
          height: ROW - (wait ? 12 : 14), rx: 2,
          ...(wait ? { class: device ? "wait unknown" : "wait" } : { fill: colour(k), opacity: word === "D" ? 0.35 : 0.85 }) });
        bar.append(tip);
        parts.push(bar);
        // (its pin's name where the bar has room for it: about 6 px a letter)
        const label = `? ${device?.driven_by ?? ""}`;
        if (device) parts.push(svgEl("text", { x: x(l.start_s) + 3, y: y + ROW / 2 + 3, class: "unknown" },
          x(l.end_s) - x(l.start_s) > label.length * 6 + 6 ? label : "?"));
      }
    }
  });
  // each output to the waits on other arms that end at it
  let arrows = 0;
  for (const w of waits)
    for (const o of outputs)
      if (o.k !== w.k && w.end >= o.t && w.end - o.t <= 0.002) {
        const y0 = TOP + o.k * ROW + ROW / 2, y1 = TOP + w.k * ROW + ROW / 2;
        parts.push(svgEl("path", { d: `M${x(o.t)},${y0 + (y1 > y0 ? 6 : -6)} L${x(w.end)},${y1 + (y1 > y0 ? -7 : 7)}`, class: "signal" }));
        arrows++;
      }
  cellReport.arrows = arrows;
  // the seconds below
  const axisY = TOP + arms.length * ROW + 12;
  const step = [1, 2, 5, 10, 20, 30, 60].find((d) => timelineEnd / d <= 6) ?? 120;
  for (let t = 0; t <= timelineEnd; t += step) parts.push(svgEl("text", { x: x(t), y: axisY, "text-anchor": "middle" }, `${t} s`));
  cursor = svgEl("line", { x1: x(0), y1: TOP, x2: x(0), y2: TOP + arms.length * ROW, class: "now" });
  parts.push(cursor);
  svg.replaceChildren(...parts);
}
