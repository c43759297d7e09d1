// Jog: nudge a joint, or the tool along x, y or z of the table's frame or of its own, by 0.1, 1
// or 10 mm or degrees, from on-screen buttons, keys (while no box has the keyboard) or a
// gamepad. The engine makes each nudge (engine/jog.ts) and says what whole steps make of it.
// A connected arm is jogged from where it is: a tap is one move, and a held jog is one move
// as far as the jog may go (a joint's limit, or the farthest straight line) that a `!` ends on
// letting go, so the arm decelerates to rest along its path; the model then takes its pose.
import type { RobotMsg } from "../engine/messages";
import type { Studio } from "../page/context";
import { $, fill, h } from "../page/dom";

type Frame = "joint" | "table" | "tool";
/** One jog a button, a key or a gamepad's stick gives: a joint (frame "joint") or an axis. */
interface Jog { frame: Frame; axis: number; dir: 1 | -1 }

/** What the jog did last (window.articula.jog shows it; main.ts wires it). */
export const jogReport = { said: "", jogs: 0, held: 0, lets: 0, last: null as null | { asked: number; whole: number | null; line: string },
  haltAt: 0 }; // haltAt: when the last held jog's `!` was written (epoch ms)

let s: Studio;
const HOLD_MS = 400; // a press held this long is a held jog
const REPEAT_MS = 100; // the model's held jog: a nudge this often
let pointerAt = -Infinity; // the last press of a jog button by a pointer (its click is that press's)
let halting: Promise<void> | null = null; // a held jog let go, until the arm is at rest (the next jog waits)
let pressed: { jog: Jog; timer: number; repeat: number; onArm: boolean; held: boolean } | null = null;

const frame = () => ($("jog-frame") as HTMLSelectElement).value as Frame;
const stepNow = () => parseFloat((document.querySelector("input[name=jog-step]:checked") as HTMLInputElement | null)?.value ?? "1");
const armLink = () => (s.editor.armConnected ? s.editor.arm.link() : null);

export function initJog(studio: Studio): void {
  s = studio;
  s.editor.signals.robotShown.add(buildPad);
  // another hand on the arm (STOP, a new connection): the next jog starts from its report
  s.editor.signals.stopped.add(() => (armTarget = null));
  s.editor.signals.armConnected.add(() => (armTarget = null));
  $("jog-frame").addEventListener("change", () => s.editor.robot && buildPad(s.editor.robot));
  // a press ends wherever the pointer is let go (or the page loses it)
  for (const ev of ["pointerup", "pointercancel", "blur"]) window.addEventListener(ev, () => letGo());
  document.addEventListener("keydown", keyDown);
  document.addEventListener("keyup", (e) => pressed && keyJog(e) && letGo());
  pollGamepads();
}

/** The buttons for the frame chosen: a − and a + for each joint, or for x, y and z. */
function buildPad(r: RobotMsg): void {
  const f = frame();
  const rows = f === "joint"
    ? r.joints.map((j, i) => ({ name: j.name, unit: j.unit === "mm" ? "mm" : "°", axis: i }))
    : ["x", "y", "z"].map((n, i) => ({ name: f === "tool" ? `tool ${n}` : n, unit: "mm", axis: i }));
  fill($("jog-pad"), ...rows.map((row) => h("div", { class: "jog-row" },
    h("span", { class: "jog-name" }, row.name),
    ...([-1, 1] as const).map((dir) => {
      const b = h("button", { class: "jog-button", type: "button", "data-axis": row.axis, "data-dir": dir,
        "aria-label": `${row.name} ${dir < 0 ? "minus" : "plus"}`, title: `Nudge ${row.name} by ${dir < 0 ? "−" : "+"}the step; hold to keep going` },
      dir < 0 ? "−" : "+") as HTMLButtonElement;
      b.addEventListener("pointerdown", (e) => {
        e.preventDefault(); // (no text selection, no focus theft on a long press)
        pointerAt = performance.now();
        try {
          b.setPointerCapture(e.pointerId);
        } catch {
          /* a pointer the browser no longer knows: the window's pointerup still ends the press */
        }
        press({ frame: f, axis: row.axis, dir });
      });
      // a click no pointer pressed (the keyboard's Enter and Space, an assistive tool: a click of
      // no count): one nudge. A pointer's click is its press's, however long it was held: after a
      // held jog it would be a nudge from a report older than the let go, behind the arm.
      b.addEventListener("click", (e) => {
        if (e.detail === 0 && performance.now() - pointerAt > 1000) void jogOnce({ frame: f, axis: row.axis, dir });
      });
      return b;
    }))));
}

/** A jog pressed: one nudge now; held, it goes on until let go. */
function press(jog: Jog): void {
  if (pressed) letGo();
  const link = armLink();
  const onArm = !!link;
  pressed = { jog, onArm, held: false, repeat: 0, timer: 0 };
  const p = pressed;
  void jogOnce(jog).then(() => {
    if (pressed !== p) return;
    p.timer = window.setTimeout(() => {
      if (pressed !== p) return;
      p.held = true;
      jogReport.held++;
      if (onArm) void holdOnArm(jog);
      else p.repeat = window.setInterval(() => void jogOnce(jog, true), REPEAT_MS);
    }, HOLD_MS);
  });
}

/** Let go: the model's nudges stop; the arm's held move is ended by `!` and the model takes
 * the arm's pose once it is at rest. */
function letGo(): void {
  const p = pressed;
  if (!p) return;
  pressed = null;
  clearTimeout(p.timer);
  clearInterval(p.repeat);
  if (!p.held || !p.onArm) return;
  jogReport.lets++;
  armTarget = null;
  const link = armLink();
  if (!link) return;
  const h: Promise<void> = link.halt().then(() => {
    jogReport.haltAt = performance.timeOrigin + performance.now();
    return followArm();
  }).finally(() => {
    if (halting === h) halting = null;
  });
  halting = h;
}

// After a held jog on the arm: the model where the arm came to rest (a report read after the `!`
// was written: one read before it is from before the arm slowed down).
function followArm(): Promise<void> {
  const start = performance.now();
  return new Promise((done) => {
    const look = () => {
      const q = s.editor.arm.pose();
      const link = armLink();
      if (!link) return done();
      if (link.atRest && q && s.editor.arm.restAt() > start) {
        s.engine.request({ type: "set_joints", q });
        say(`${jogReport.said.replace(/ \(let go to stop\)$/, "")}: let go, the arm came to rest there`);
        return done();
      }
      if (performance.now() - start < 30000) setTimeout(look, 100);
      else done();
    };
    look();
  });
}

function say(text: string, bad = false): void {
  jogReport.said = text;
  const el = $("jog-said");
  el.textContent = text;
  el.className = `status ${bad ? "bad" : ""}`;
}

// Nudges one after another: each starts where the last one ended (quick taps add up).
let queue: Promise<void> = Promise.resolve();
let waiting = 0;
function jogOnce(jog: Jog, repeat = false): Promise<void> {
  if (repeat && waiting) return queue; // (a held jog's next nudge: only once the last is done)
  waiting++;
  const p = queue.then(() => jogNow(jog)).finally(() => waiting--);
  queue = p.catch(() => undefined);
  return p;
}

/** One nudge: the model's (the engine moves it), or the arm's from where it is. */
async function jogNow(jog: Jog): Promise<void> {
  if (!s.editor.robot) return;
  const link = armLink();
  if (link?.running) return say("The arm is running a program: jog it when it is done (or STOP it).", true);
  // a held jog let go: the arm is slowing down, and its reports lag behind it; a nudge starts
  // where it comes to rest (from an older report it would go back)
  if (link && halting) await halting;
  const from = link ? armFrom() : null;
  let r: { moved?: boolean; said?: string; asked?: number; whole?: number | null; line?: string; q?: number[] };
  try {
    r = (await s.engine.call({ type: "jog", frame: jog.frame, axis: jog.axis, dir: jog.dir, step: stepNow(), from })) as typeof r;
  } catch (e) {
    return say((e as Error).message, true);
  }
  jogReport.jogs++;
  say(r.said ?? "", !r.moved);
  if (r.moved) jogReport.last = { asked: r.asked ?? 0, whole: r.whole ?? null, line: r.line ?? "" };
  if (r.moved && link && r.line) {
    armTarget = r.q ?? null;
    okAt = Infinity; // (no report counts until the arm has taken the line)
    await link.send(r.line);
    okAt = performance.now();
  }
}

// Taps on an arm add up: each starts from the last one's target until the arm reports itself
// at rest after taking it (a report read before its `ok` may be older than the line).
let armTarget: number[] | null = null;
let okAt = -Infinity;
function armFrom(): number[] | null {
  return armTarget && !(s.editor.arm.restAt() > okAt) ? armTarget : s.editor.arm.pose();
}

/** A held jog on the arm: one line as far as the jog may go, ended by `!` when let go. */
async function holdOnArm(jog: Jog): Promise<void> {
  const link = armLink();
  const from = armFrom();
  if (!link || !from) return;
  // the tool's held speed follows the step: 1, 10 or 100 mm/s
  const r = (await s.engine.call({ type: "jog", frame: jog.frame, axis: jog.axis, dir: jog.dir, step: stepNow(), from,
    hold: true, speed: stepNow() * 10 })) as { moved?: boolean; said?: string; line?: string };
  say(r.said ?? "", !r.moved);
  if (r.moved && r.line && pressed?.held) void link.send(r.line);
}

// Keys, while no box has the keyboard (the 3D view's arrows and + - stay the camera's):
// W S: x + -, A D: y + -, R F: z + - (the frame chosen; the table's when "each joint" is);
// 1 to 6: that joint +, with Shift -; [ and ]: a smaller or a larger step.
const AXIS_KEYS: Record<string, [number, 1 | -1]> = { KeyW: [0, 1], KeyS: [0, -1], KeyA: [1, 1], KeyD: [1, -1], KeyR: [2, 1], KeyF: [2, -1] };
function keyJog(e: KeyboardEvent): Jog | null {
  if (e.ctrlKey || e.metaKey || e.altKey) return null;
  const t = e.target as HTMLElement | null;
  if (t?.closest?.("input, textarea, select, [contenteditable], .blocklyWidgetDiv, .blocklyHtmlInput")) return null;
  if (document.body.classList.contains("cell-open")) return null;
  const a = AXIS_KEYS[e.code];
  if (a) return { frame: frame() === "tool" ? "tool" : "table", axis: a[0], dir: a[1] };
  const digit = /^Digit([1-9])$/.exec(e.code);
  if (digit && s.editor.robot && Number(digit[1]) <= s.editor.robot.joints.length)
    return { frame: "joint", axis: Number(digit[1]) - 1, dir: e.shiftKey ? -1 : 1 };
  return null;
}
function keyDown(e: KeyboardEvent): void {
  const t = e.target as HTMLElement | null;
  if ((e.code === "BracketLeft" || e.code === "BracketRight") && !t?.closest?.("input, textarea, select")) {
    const radios = [...document.querySelectorAll<HTMLInputElement>("input[name=jog-step]")];
    const i = radios.findIndex((r) => r.checked) + (e.code === "BracketLeft" ? -1 : 1);
    if (radios[i]) radios[i].checked = true;
    return;
  }
  const jog = keyJog(e);
  if (!jog) return;
  e.preventDefault();
  if (e.repeat) return; // (held: the press goes on until the key is let go)
  press(jog);
}

// A gamepad (the Gamepad API): the left stick x and y, the right stick's y z, each a jog held
// while the stick is pushed past halfway; its shoulder buttons change the step.
let padJog: Jog | null = null;
let padButtons: boolean[] = [];
function pollGamepads(): void {
  const tick = () => {
    const pads = navigator.getGamepads ? [...navigator.getGamepads()].filter((g): g is Gamepad => !!g) : [];
    if (pads.length) readPad(pads[0]);
    requestAnimationFrame(tick);
  };
  window.addEventListener("gamepadconnected", () => {
    say("A gamepad is connected: the left stick jogs x and y, the right stick z; its shoulder buttons change the step.");
  });
  requestAnimationFrame(tick);
}
function readPad(g: Gamepad): void {
  const ax = (i: number) => g.axes[i] ?? 0;
  // stick up is -1: up is +x (away from the base), left is +y, right stick up is +z
  const pushes: [number, number][] = [[0, -ax(1)], [1, -ax(0)], [2, -ax(3)]];
  const [axis, v] = pushes.reduce((best, p) => (Math.abs(p[1]) > Math.abs(best[1]) ? p : best), [0, 0]);
  const want: Jog | null = Math.abs(v) > 0.5 ? { frame: frame() === "tool" ? "tool" : "table", axis, dir: v > 0 ? 1 : -1 } : null;
  const same = (a: Jog | null, b: Jog | null) => (a && b ? a.frame === b.frame && a.axis === b.axis && a.dir === b.dir : a === b);
  if (!same(want, padJog)) {
    if (padJog) letGo();
    padJog = want;
    if (want) press(want);
  }
  const buttons = g.buttons.map((b) => b.pressed);
  for (const [i, code] of [[4, "BracketLeft"], [5, "BracketRight"]] as const)
    if (buttons[i] && !padButtons[i]) keyDown(new KeyboardEvent("keydown", { code }));
  padButtons = buttons;
}
