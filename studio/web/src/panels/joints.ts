// The joints panel: a slider and a box for every joint variable of the DH table (and for each
// row length the robot file lets change, RoboSim's l), Home, Zero, the gripper; the DH table
// at the pose and the tool pose. The names come from the robot file: shown as text only.
import type { PoseMsg, RobotMsg } from "../engine/messages";
import type { Studio } from "../page/context";
import { $, fill, fmt, h } from "../page/dom";

let s: Studio;
let typing: HTMLInputElement | null = null; // the number box being typed in (left alone until done)

export function initJoints(studio: Studio): void {
  s = studio;
  s.editor.signals.robotShown.add(buildJoints);
  $("home").onclick = () => s.engine.send({ type: "home" });
  $("zero").onclick = () => s.engine.send({ type: "zero" });
  for (const id of ["gripper", "gripper-num"]) {
    $(id).addEventListener("input", (e) => {
      const v = parseFloat((e.target as HTMLInputElement).value);
      if (Number.isFinite(v)) s.engine.send({ type: "gripper", percent: Math.min(100, Math.max(0, v)) });
    });
  }
}

const PARAM_TITLE: Record<string, string> = { theta: "An angle about z", alpha: "A twist about x", d: "A slide along z" };

/** The sliders of a robot just loaded. */
function buildJoints(r: RobotMsg): void {
  const box = $("joints");
  const rows: HTMLElement[] = r.joints.map((j, i) => {
    const step = j.unit === "deg" ? 0.1 : 0.5;
    const sub = j.param === "alpha" ? j.row - 1 : j.row;
    const range = { min: j.min, max: j.max, step, "data-joint": i };
    return h("div", { class: "joint" },
      h("label", { title: `${PARAM_TITLE[j.param] ?? "A joint variable"} of DH row ${j.row}: ${j.min} .. ${j.max} ${j.unit}` },
        `${j.name} `, h("span", { class: "unit" }, j.param, h("sub", null, sub), `, ${j.unit}`)),
      h("input", { type: "range", ...range, "aria-label": `${j.name}, ${j.unit}` }),
      h("input", { type: "number", ...range, "aria-label": `${j.name}, ${j.unit}` }),
      r.motors[i] ? h("div", { class: "motor-angle", "data-motor": i, title: `The ${r.motors[i]} motor's angle: what M and L take for it` }) : null);
  });
  // RoboSim's l: a slider for each row whose length a(i-1) the robot file lets change.
  const lengths = r.dh.map((row, i) => ({ a: row.a as unknown, row: i + 1 }))
    .filter((x) => typeof x.a === "object" && x.a !== null) as { a: { value: number; min: number; max: number }; row: number }[];
  for (const { a, row } of lengths) {
    const range = { min: a.min, max: a.max, step: 0.5, value: a.value, "data-length": row };
    rows.push(h("div", { class: "joint length" },
      h("label", { title: `The length a(${row - 1}) of DH row ${row}: ${a.min} .. ${a.max} mm (RoboSim's l)` },
        "a", h("sub", null, row - 1), " ", h("span", { class: "unit" }, `row ${row} length, mm`)),
      h("input", { type: "range", ...range, "aria-label": `a${row - 1}, mm` }),
      h("input", { type: "number", ...range, "aria-label": `a${row - 1}, mm` })));
  }
  fill(box, ...rows);
  // On a touch screen a finger that lands on a slider's track, away from its thumb, moves
  // nothing (a tap there jumped the joint by tens of degrees, issue 55, 9): the thumb is dragged.
  box.querySelectorAll<HTMLInputElement>("input[type=range]").forEach((inp) => {
    inp.addEventListener("touchstart", (e) => {
      const t = e.touches[0];
      if (t && !nearThumb(inp, t.clientX)) e.preventDefault();
    }, { passive: false });
  });
  box.querySelectorAll<HTMLInputElement>("input[data-joint]").forEach((inp) => {
    // typed: the box shows what the arm took (a value beyond the range, clamped) once done
    inp.addEventListener("change", () => {
      typing = null;
      // (a pose older than this edit leaves it: the answer to the edit puts the value there)
      const p = s.editor.pose;
      if (p && !s.engine.editedSince(`set_joint:${inp.dataset.joint}`, p.seq))
        inp.value = inp.type === "number" ? fmt(p.q[Number(inp.dataset.joint)], 2) : inp.value;
    });
    inp.addEventListener("input", () => {
      if (inp.type === "number") typing = inp;
      const v = parseFloat(inp.value);
      if (!Number.isFinite(v)) return;
      s.engine.request({ type: "set_joint", joint: Number(inp.dataset.joint), value: v });
    });
  });
  box.querySelectorAll<HTMLInputElement>("input[data-length]").forEach((inp) => {
    inp.addEventListener("change", () => {
      const values = lengths.map(({ row, a }) => {
        const el = box.querySelector<HTMLInputElement>(`input[data-length="${row}"]${inp.dataset.length === String(row) ? `[type=${inp.type}]` : ""}`);
        const v = el ? parseFloat(el.value) : a.value;
        return Number.isFinite(v) ? v : a.value;
      });
      s.engine.request({ type: "set_lengths", values });
    });
  });
  $("gripper-row").hidden = !r.gripper;
}

const THUMB_PX = 22; // a slider's thumb on a touch screen (style.css), and a finger's slack beside it
function nearThumb(inp: HTMLInputElement, x: number): boolean {
  const r = inp.getBoundingClientRect();
  const lo = Number(inp.min), hi = Number(inp.max);
  const f = hi > lo ? (Number(inp.value) - lo) / (hi - lo) : 0;
  return Math.abs(x - (r.left + THUMB_PX / 2 + f * (r.width - THUMB_PX))) <= THUMB_PX;
}

/** Sliders, gripper, the DH table and the tool pose follow a pose (not the slider in hand). */
export function showJointValues(p: PoseMsg, robot: RobotMsg): void {
  $("joints").querySelectorAll<HTMLInputElement>("input[data-joint]").forEach((inp) => {
    const v = p.q[Number(inp.dataset.joint)];
    if (s.engine.editedSince(`set_joint:${inp.dataset.joint}`, p.seq)) return; // an older state than the box's
    if (inp !== typing && (document.activeElement !== inp || inp.type === "number")) inp.value = inp.type === "number" ? fmt(v, 2) : String(v);
  });
  // the motor's angle, where it is not the joint's value (M takes motors' angles)
  $("joints").querySelectorAll<HTMLElement>(".motor-angle").forEach((el) => {
    const i = Number(el.dataset.motor);
    const m = p.motors?.[i];
    const differs = m !== undefined && Math.abs(m - p.q[i]) > 0.005;
    el.textContent = differs ? `motor ${robot.motors[i]}: ${fmt(m!, 2)}°` : "";
  });
  const g = $("gripper") as HTMLInputElement;
  if (document.activeElement !== g) g.value = String(p.gripper);
  ($("gripper-num") as HTMLInputElement).value = fmt(p.gripper, 0);
  const linked = new Set<string>();
  robot.dh.forEach((row, i) => {
    for (const k of ["a", "alpha", "d", "theta"]) {
      const v = row[k] as Record<string, unknown> | number;
      if (typeof v === "object" && v && "linked" in v) linked.add(`${i}.${k}`);
    }
  });
  const vars = new Set(robot.joints.map((j) => `${j.row - 1}.${j.param}`));
  fill($("dh").querySelector("tbody")!, ...p.dh_table.map((r, i) =>
    h("tr", null, h("td", null, i + 1), ...["a", "alpha", "d", "theta"].map((k, c) =>
      h("td", { class: vars.has(`${i}.${k}`) ? "var" : linked.has(`${i}.${k}`) ? "linked" : null }, fmt(r[c], c % 2 ? 2 : 1))))));
  // with a pen held, where its tip is (the tool point is the pen's length above it)
  const [x, y, z] = p.tip ?? p.tool.xyz;
  $("tool-title").textContent = p.tip ? "Pen tip" : "Tool pose";
  const [ro, pi, ya] = p.tool.rpy;
  const unit = (u: string) => h("span", { class: "unit" }, u);
  fill($("tool"),
    h("div", null, h("b", null, "x"), ` ${fmt(x)}`), h("div", null, h("b", null, "y"), ` ${fmt(y)}`),
    h("div", null, h("b", null, "z"), ` ${fmt(z)} `, unit("mm")),
    h("div", null, h("b", null, "roll"), ` ${fmt(ro, 1)}`), h("div", null, h("b", null, "pitch"), ` ${fmt(pi, 1)}`),
    h("div", null, h("b", null, "yaw"), ` ${fmt(ya, 1)} `, unit("deg")));
}
