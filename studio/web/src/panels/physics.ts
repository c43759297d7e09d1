// Live physics: the scene menu, run / pause / step / reset, the speed against real time, the
// events as they come (objects named by the scene file: shown as text), objects to drag.
import type { PhysicsMsg, RobotMsg, SceneMsg, SimEvent } from "../engine/messages";
import type { Studio } from "../page/context";
import { $, fill, h, setOptions } from "../page/dom";
import type { Reports } from "../page/reports";

/** The physics' events since it started or was reset (window.articula shows it; main.ts wires it). */
export const physicsReport: { events: Reports["events"] } = {
  events: [],
};

let s: Studio;
let dragSent = 0;

const TROUBLE = new Set(["collision", "self_collision", "squeeze", "steps_lost", "blocked", "rejected", "object_removed",
  "gripper_blocked", "stall", "deadlock"]);

/** An event in words a student reads (the engine's own words stay in its title, on hover). */
export function eventWords(e: SimEvent): string {
  const part = (x: string) => x.startsWith("link") || x.startsWith("finger") || x === "base" || x === "ground" || x === "gripper";
  const the = (x: string) => {
    // in a cell, a part of an arm is "arm: link 2": the event's own arm's is its part, another's that arm's
    const armPart = /^([A-Za-z][\w-]*): (.*)$/.exec(x);
    if (armPart && part(armPart[2])) return armPart[1] === e.arm ? `the ${armPart[2]}` : `${armPart[1]}'s ${armPart[2]}`;
    return part(x) ? `the ${x}` : `"${x}"`;
  };
  switch (e.kind) {
    case "contact_started": return `${the(e.a)} touches ${the(e.b)}`;
    case "contact_ended": return `${the(e.a)} no longer touches ${the(e.b)}`;
    case "grasp": return `the gripper holds ${the(e.b)}`;
    case "release": return `the gripper lets go of ${the(e.b)}`;
    case "squeeze": return `the gripper presses on ${the(e.b)}: the arm stops there`;
    case "collision": return `${the(e.a)} hits ${the(e.b)}: the arm stops there`;
    case "self_collision": return `the arm hits itself (${e.a}, ${e.b}): it stops there`;
    case "steps_lost": return "a motor skipped steps: something holds the arm back";
    case "blocked": return `${the(e.a)} is blocked${e.b ? ` by ${the(e.b)}` : ""}`;
    case "gripper_blocked": return `the gripper cannot close further: ${the(e.b || "object")} is in the way`;
    case "rejected": return `the arm refused line ${e.line}`;
    case "object_removed": return `${the(e.a)} fell off the world`;
    case "stall": return "a motor stalled: it could not turn the load";
    case "deadlock": return `the arms wait for each other: ${e.detail ?? ""}`;
    case "device": // (a cell's belt, light barrier and feeder: cells/README.md)
      if (e.detail === "runs" || e.detail === "stands") return `the belt ${the(e.a)} ${e.detail}`;
      if (e.detail === "puts one out") return `the feeder ${the(e.a)} puts out ${the(e.b)}`;
      if (e.detail === "is empty" || e.detail?.startsWith("waits")) return `the feeder ${the(e.a)} ${e.detail}`;
      if (e.detail === "is pressed") return `${the(e.b)} presses the switch ${the(e.a)}`;
      if (e.detail === "is let go") return `the switch ${the(e.a)} is let go`;
      return e.b ? `${the(e.b)} breaks the beam of ${the(e.a)}` : `the beam of ${the(e.a)} is clear`;
    default: return `${e.kind}: ${e.a}${e.b ? ` / ${e.b}` : ""}`;
  }
}

/** Events into the view's log, in words (a cell's with the arm's name first), the engine's own
 * words on hover; `each` after each one. The log keeps the last 200. */
export function logEvents(events: SimEvent[], each: (e: SimEvent) => void = () => undefined): void {
  const log = $("events");
  for (const e of events) {
    const detail = `${e.t.toFixed(2)} s ${e.kind}: ${e.a}${e.b ? ` / ${e.b}` : ""}${e.detail ? ` - ${e.detail}` : ""}`;
    const cls = TROUBLE.has(e.kind) ? "trouble" : e.kind === "grasp" || e.kind === "release" ? "grasp" : null;
    log.appendChild(h("div", { class: cls, title: detail }, `${e.t.toFixed(1)} s: ${e.arm ? `${e.arm}: ` : ""}${eventWords(e)}`));
    each(e);
  }
  while (log.childElementCount > 200) log.firstElementChild!.remove();
  if (events.length) log.scrollTop = log.scrollHeight;
}

export function initPhysics(studio: Studio): void {
  s = studio;
  s.editor.signals.robotShown.add(() => s.editor.scene && sceneMenu(s.editor.scene)); // another arm, other scenes first
  $("scene-select").addEventListener("change", (e) => {
    const v = (e.target as HTMLSelectElement).value;
    // a cell (several arms: panels/cell.ts), or a scene for the one arm (which closes a cell)
    if (v === YOURS) return;
    if (v.startsWith("cell:")) s.engine.send({ type: "cell", name: v.slice(5) });
    else s.engine.send({ type: "scene", name: v || null });
  });
  $("phys-run").onclick = () => s.engine.send({ type: "physics_run" });
  $("phys-pause").onclick = () => s.engine.send({ type: "physics_pause" });
  $("phys-step").onclick = () => s.engine.send({ type: "physics_step" });
  $("phys-reset").onclick = () => s.engine.send({ type: "physics_reset" });
  s.view.onDrag = (object, target) => {
    if (target === null) return s.engine.send({ type: "release" });
    const now = performance.now();
    if (now - dragSent < 15) return; // one pull a display frame is plenty
    dragSent = now;
    s.engine.send({ type: "drag", object, target });
  };
}

/** The scene menu: the scenes placed for the arm shown first, those placed for other arms after
 * (said so), then the cells; the scene on. */
function sceneMenu(m: SceneMsg): void {
  const sel = $("scene-select") as HTMLSelectElement;
  // the scenes placed for the arm shown first; those placed for other arms after, said so
  const shipped = s.editor.robot?.shipped ?? "";
  const fits = (n: string) => !(m.sized_for?.[n]?.length) || m.sized_for[n].includes(shipped);
  const mine = m.scenes.filter(fits), others = m.scenes.filter((n) => !fits(n));
  // a scene of the student's own first (the scene editor's: panels/scene-edit.ts)
  setOptions(sel, [{ value: "", label: "off" }, ...(m.world ? [{ value: YOURS, label: m.title || "your scene" }] : []), ...mine]);
  if (others.length)
    sel.appendChild(h("optgroup", { label: "placed for other arms" }, ...others.map((n) => h("option", { value: n }, n))));
  if (m.cells?.length)
    sel.appendChild(h("optgroup", { label: "several arms: a cell" }, ...m.cells.map((c) => h("option", { value: `cell:${c}` }, c))));
  sel.value = m.world ? YOURS : m.name ?? "";
}

const YOURS = "@yours"; // the menu's entry for a scene of the student's own

export function showScene(m: SceneMsg): void {
  s.editor.scene = m;
  sceneMenu(m);
  s.view.setObjects(m.objects);
  $("physics-bar").hidden = m.name === null;
  $("events").hidden = m.name === null;
  fill($("events"));
  // the physics' clock and counts under the view are not the model's (issue 55, 6)
  if (m.name === null) $("view-status").textContent = "";
}

export function showPhysics(p: PhysicsMsg, robot: RobotMsg | null): void {
  s.editor.physics = p;
  if (!p.on) {
    $("phys-rtf").textContent = ""; // no physics, no counter
    return;
  }
  s.view.physics(p);
  if (p.t !== undefined && s.editor.timeline) s.plots.playhead(p.t);
  if (p.line !== undefined) {
    s.editor.signals.lineRunning.dispatch({ line: p.line, refused: false });
  }
  if (p.fresh) {
    physicsReport.events = [];
    fill($("events"));
  }
  const rtf = $("phys-rtf");
  if (p.running === false) {
    rtf.textContent = `paused at ${p.t?.toFixed(2)} s`;
    rtf.className = "rtf";
  } else if (p.rtf !== undefined && p.rtf !== null) {
    const cap = p.capacity ? `, could run ${Math.round(p.capacity)}x` : "";
    const speed = s.editor.speed;
    rtf.textContent = p.behind ? `behind ${speed === 1 ? "real time" : `its speed (${speed}x)`}: ${p.rtf.toFixed(2)}x`
      : `${p.rtf.toFixed(2)}x real time${cap}`;
    rtf.className = `rtf ${p.behind ? "behind" : ""}`;
  }
  physicsReport.events.push(...(p.events ?? []));
  logEvents(p.events ?? [], (e) => {
    if (e.kind !== "contact_ended") {
      if (e.a) s.view.flash(e.a);
      if (e.b && e.b !== "ground") s.view.flash(e.b);
    }
  });
  if (p.steps && robot?.motors.length) $("view-status").textContent = `t = ${p.t?.toFixed(2)} s, steps ${p.steps.join(" ")}` +
    (p.lost?.some((v) => v) ? `, lost ${p.lost.join(" ")}` : "");
}
