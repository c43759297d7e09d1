// A cell of arms (cells/README.md) on the page: the Physics menu's cells open a shipped cell, its arms drawn in a colour each where the cell stands them (view/cell-arms.ts), all of
// them on their own firmware in the engine (engine/cell.ts); the physics bar runs, pauses, steps
// and resets it, STOP pauses it, and the events say which arm did what. A deadlock is told in
// words under the view.
import type { CellFrameMsg, CellMsg, SimEvent } from "../engine/messages";
import type { Studio } from "../page/context";
import { $, fill, h } from "../page/dom";
import { ARM_COLORS } from "../view/cell-arms";
import { logEvents } from "./physics";

/** What window.articula shows of the cell (main.ts wires it). */
export const cellReport: {
  name: string | null; title: string; arms: string[]; t: number; running: boolean; done: boolean; deadlock: string;
  events: SimEvent[]; lines: number[]; signals: CellFrameMsg["arms"][number]["signals"][]; frames: number;
} = { name: null, title: "", arms: [], t: 0, running: false, done: false, deadlock: "", events: [], lines: [], signals: [], frames: 0 };

let s: Studio;

export const cellRunning = () => cellReport.name !== null && cellReport.running && !cellReport.done;

export function initCell(studio: Studio): void {
  s = studio;
}

export async function showCell(m: CellMsg): Promise<void> {
  cellReport.name = m.name;
  cellReport.title = m.title ?? "";
  cellReport.arms = (m.arms ?? []).map((a) => a.name);
  cellReport.events = [];
  cellReport.deadlock = "";
  cellReport.frames = 0;
  const on = m.name !== null;
  ($("scene-select") as HTMLSelectElement).value = on ? `cell:${m.name}` : s.editor.scene?.name ?? "";
  $("physics-bar").hidden = !on && !s.editor.scene?.name;
  $("events").hidden = !on && !s.editor.scene?.name;
  fill($("events"));
  // the arms' names in their colours, under the view
  // (the colour through the CSSOM: the site's Content-Security-Policy refuses style attributes)
  fill($("cell-legend"), ...(m.arms ?? []).map((a, k) => {
    const key = h("i", { class: "key" });
    key.style.background = `#${ARM_COLORS[k % ARM_COLORS.length].toString(16).padStart(6, "0")}`;
    return h("span", {}, key, `${a.name} (${a.robot.name})`);
  }));
  $("cell-legend").hidden = !on;
  if (on) {
    s.view.setObjects(m.objects ?? []);
    $("view-status").textContent = `${m.title}: ${cellReport.arms.length} arms, each on its own firmware`;
  } else if (!s.editor.scene?.name) {
    s.view.setObjects([]);
    $("view-status").textContent = "";
  }
  await s.view.showCell(m);
}

export function showCellFrame(f: CellFrameMsg): void {
  if (cellReport.name === null) return;
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
  logEvents(f.events);
  cellReport.deadlock = f.deadlock;
  const waits = f.arms.filter((a) => a.signals.some((x) => x.kind === "wait" && x.end_t == null)).map((a) => a.name);
  $("view-status").textContent = `t = ${f.t.toFixed(2)} s` + (f.done ? ", every program ended" : f.running ? "" : ", paused") +
    (f.deadlock && waits.length > 1 ? `: stuck, ${f.deadlock}` : waits.length ? `: ${waits.join(", ")} waiting for a signal` : "");
  $("phys-rtf").textContent = f.running && !f.done ? "running" : f.done ? "ended" : `paused at ${f.t.toFixed(2)} s`;
}
