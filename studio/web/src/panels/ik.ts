// The IK panel: a typed target (position, and orientation when asked), the solver, per-joint
// weights, Solve and the thesis's Jacobian transpose animated; the target in the 3D view,
// dragged. What the solver says is shown as a sentence.
import type { IkMsg, RobotMsg } from "../engine/messages";
import type { Studio } from "../page/context";
import { $, fill, fmt, h } from "../page/dom";
import type { Reports } from "../page/reports";

/** The IK panel's last solve, line and drag updates (window.articula shows it; main.ts wires it). */
export const ikReport: { ik: Reports["ik"]; ikLine: string; ikUpdates: number[] } = {
  ik: null, ikLine: "", ikUpdates: [],
};

let s: Studio;
let dragging = false;
// Where the straight line goes (main.ts connects them; the panels import no panel): the arm
// when one is connected (true), else a line of the program.
let lineToArm: (line: string) => boolean = () => false;
let lineToProgram: (line: string) => void = () => undefined;
export const setLineTargets = (arm: (line: string) => boolean, program: (line: string) => void) => {
  lineToArm = arm;
  lineToProgram = program;
};

export const isDragging = () => dragging;

export function initIk(studio: Studio): void {
  s = studio;
  s.editor.signals.robotShown.add((r) => {
    buildWeights(r);
    if (!r.keep_view) clearIk();
  });
  $("show-target").addEventListener("change", (e) => {
    const on = (e.target as HTMLInputElement).checked;
    if (on && s.editor.pose) s.view.setTarget(s.editor.pose.tip ?? s.editor.pose.tool.xyz, s.editor.pose.tool.rpy);
    s.view.showTarget(on);
  });
  $("gizmo-mode").addEventListener("change", (e) => s.view.gizmoMode((e.target as HTMLSelectElement).value as "translate" | "rotate"));
  $("use-rpy").addEventListener("change", (e) => ($("rpy-row").hidden = !(e.target as HTMLInputElement).checked));
  const solveWith = (type: string) => {
    const m = ikMessage(type);
    // a box that holds no number, or one no arm could reach, is said so here
    const names = ["x", "y", "z", "roll", "pitch", "yaw"];
    const bad = (m.target as number[]).findIndex((v) => !Number.isFinite(v) || Math.abs(v) > 1e6);
    if (bad >= 0) {
      const v = (m.target as number[])[bad];
      const el = $("ik-status");
      el.textContent = Number.isFinite(v) ? `${names[bad]} = ${v} is too far: type a target within 1,000,000 mm (a kilometre).`
        : `${names[bad]} holds no number: type one, like 150.`;
      el.className = "status bad";
      return;
    }
    s.view.setTarget((m.target as number[]).slice(0, 3), (m.target as number[]).slice(3));
    s.engine.send(m);
  };
  $("solve").onclick = () => solveWith("ik");
  // The target along a straight line: T x y z speed (docs/protocol.md, "Straight lines").
  $("ik-line").onclick = async () => {
    const num = (id: string) => parseFloat(($(id) as HTMLInputElement).value);
    const xyz = [num("tx"), num("ty"), num("tz")];
    const speed = num("ik-line-speed");
    const el = $("ik-status");
    if (xyz.some((v) => !Number.isFinite(v) || Math.abs(v) > 1e6) || !(speed > 0 && speed <= 1000)) {
      el.textContent = "A straight line needs x, y and z as numbers, and a speed from 1 to 1000 mm/s.";
      el.className = "status bad";
      return;
    }
    // the target to a tenth of a mm (a dragged target holds many more digits), the line the engine's
    // (a target with a pen held is its tip: the engine writes the tool point above it)
    const r = await s.engine.call({ type: "protocol_line", word: "T", values: [...xyz.map((v) => Math.round(v * 10) / 10), speed],
      at_tip: true });
    if (typeof r.line !== "string") {
      el.textContent = `No straight line: ${String(r.error)}`;
      el.className = "status bad";
      return;
    }
    const line = r.line;
    ikReport.ikLine = line;
    if (lineToArm(line)) {
      el.textContent = `Sent to the arm: ${line}. It answers with its reply in the arm panel.`;
      el.className = "status ok";
    } else {
      lineToProgram(line);
      el.textContent = `Added to the program: ${line}. Run plays it; the view draws the path the tool will take.`;
      el.className = "status";
    }
  };
  $("animate-jt").onclick = () => solveWith("jt_animate");
  for (const id of ["tx", "ty", "tz", "troll", "tpitch", "tyaw"]) {
    $(id).addEventListener("keydown", (e) => {
      if ((e as KeyboardEvent).key === "Enter") $("solve").click();
    });
  }
  s.view.onTarget = (t, final) => {
    dragging = !final;
    ["tx", "ty", "tz"].forEach((id, i) => (($(id) as HTMLInputElement).value = fmt(t.xyz[i], 1)));
    ["troll", "tpitch", "tyaw"].forEach((id, i) => (($(id) as HTMLInputElement).value = fmt(t.rpy[i], 1)));
    s.engine.request(ikMessage("ik", t.xyz, t.rpy));
  };
}

/** A weight box for each motor (or joint variable) of a robot just loaded. */
function buildWeights(r: RobotMsg): void {
  fill($("weights"), ...(r.motors.length ? r.motors : r.joints.map((j) => j.name)).map((n, i) =>
    h("label", null, `${n} `, h("input", { type: "number", min: 0, step: 0.1, value: 1, "data-weight": i, "aria-label": `weight of ${n}` }))));
}

function ikMessage(type: string, xyz?: number[], rpy?: number[]): Record<string, unknown> {
  const num = (id: string) => parseFloat(($(id) as HTMLInputElement).value);
  const pos = xyz ?? [num("tx"), num("ty"), num("tz")];
  const useRpy = ($("use-rpy") as HTMLInputElement).checked;
  const ang = rpy ?? [num("troll"), num("tpitch"), num("tyaw")];
  const msg: Record<string, unknown> = { type, target: useRpy ? [...pos, ...ang] : pos, solver: ($("solver") as HTMLSelectElement).value };
  const w = [...$("weights").querySelectorAll<HTMLInputElement>("input")].map((i) => parseFloat(i.value));
  if (w.some((v) => v !== 1)) msg.weights = w;
  return msg;
}

/** The typed target follows the tool (unless the user is typing there, or dragging). */
export function followTool(xyz: number[], rpy: number[], first: boolean): void {
  if (!first && $("show-target").matches(":checked") && dragging) return;
  if (document.activeElement?.closest("#ik-section")) return;
  ["tx", "ty", "tz"].forEach((id, i) => (($(id) as HTMLInputElement).value = fmt(xyz[i], 1)));
  ["troll", "tpitch", "tyaw"].forEach((id, i) => (($(id) as HTMLInputElement).value = fmt(rpy[i], 1)));
  if (first || !s.view.target.visible) s.view.setTarget(xyz, rpy);
}

/** A new robot: the last robot's IK verdict goes. */
function clearIk(): void {
  ikReport.ik = null;
  $("ik-status").textContent = "";
  $("ik-status").className = "status";
}

export function showIk(m: IkMsg): void {
  ikReport.ik = m;
  if (dragging) ikReport.ikUpdates.push(performance.now());
  const el = $("ik-status");
  // an error the engine could not give as a number (a target at 1e308 mm) is "very far"
  const mm = (v: number | null) => (typeof v === "number" && Number.isFinite(v) ? v.toFixed(3) : "too far to measure:");
  const err = `${mm(m.position_error_mm)} mm` + (m.orientation_error_deg ? `, ${mm(m.orientation_error_deg)} deg` : "");
  let text = "";
  // the engine's words for a miss: what holds the tool back, each joint or motor once with its range
  const why = m.why && Number.isFinite(m.position_error_mm) ? m.why : "";
  if (m.status === "reached") text = `Reached (${m.solver}, ${m.iterations} iterations): ${err} from the target.`;
  else if (m.status === "unreachable") text = why ? `Unreachable: ${why}.` : `Unreachable: the arm stretches toward it and stays ${err} away` + (m.beyond_reach ? " (farther than the arm is long)." : ".");
  else if (m.status === "limited") text = why ? `Not reached: ${why}.` : `Not reached: held back by a joint's range; ${err} away.`;
  else text = `Not reached yet after ${m.iterations} iterations: ${err} away.`;
  if (m.type === "jt_frame") {
    text = `Jacobian transpose, iteration ${m.iteration}: ${err} away.`;
    if (m.done) {
      if (m.status === "reached") text += " Converged.";
      else if (m.status === "limited") text += ` Stopped: ${why || "held back by a joint's range"}.`;
      else if (m.status === "unreachable") text += " Stopped: the target is out of reach; the arm stretches toward it.";
      else text += " Stopped: it stopped improving (stuck in a local minimum, or the arm 'fell in line').";
    }
    else if ((m.iteration ?? 0) >= 400) text += " Stopped after 400 iterations.";
  }
  // with a pen in the gripper the target is its tip, not the tool point: said, or a student
  // wonders why the tool stops above the ball
  if (m.pen_mm) text = `The pen's tip (${m.pen_mm} mm below the tool point) is the target. ${text}`;
  if (s.editor.physics?.on && m.status === "reached")
    text += " In the physics the arm goes there unless something blocks it (the events in the view say so).";
  el.textContent = text;
  el.className = `status ${m.status === "reached" ? "ok" : m.status === "budget" && m.type === "jt_frame" && !m.done ? "" : "bad"}`;
}
