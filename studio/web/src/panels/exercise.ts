// The exercise: a project with a goal. Its box says the task and what the student needs to
// know (the objects' size, how low the tool's point comes above them, the drawing's target on
// the paper); the goal is drawn in the view; Check asks the engine which parts are met. A
// result is for the program that was checked: gone once the program changes.
import type { Studio } from "../page/context";
import { $, fill, h } from "../page/dom";
import type { Reports } from "../page/reports";
import type { DrawingPart, Goal, GoalPart } from "../project/document";

/** The exercise's goal on screen and its last check (window.articula shows it; main.ts wires it). */
export const exerciseReport: { goal: Reports["goal"]; exercise: Reports["exercise"] } = {
  goal: { drawn: 0, facts: [] }, exercise: null,
};

let s: Studio;
let reveal: (id: string) => void = () => undefined;
let checkedText: string | null = null; // the program the result shown is for
let working = false; // the student has touched the program since the exercise opened
let folded = false; // ... and the task was folded for it

const goal = () => s.editor.project.doc.goal;
const answer = () => ($("exercise-answer") as HTMLInputElement).value;

export function initExercise(studio: Studio, layout: { reveal: (id: string) => void }): void {
  s = studio;
  reveal = layout.reveal;
  s.editor.signals.goalShown.add(showGoal);
  s.editor.signals.changed.add(() => {
    if (checkedText === null || checked() === checkedText) return;
    checkedText = null;
    exerciseReport.exercise = null;
    fill($("exercise-result"));
  });
  $("exercise-check").onclick = () => void check();
  // Once the student starts on the program (a change after their own touch or key in it), the
  // task folds to its title line if the program is cut by the window's bottom: the code in sight
  // (issue 55, 9). Once an exercise: opened again, it stays open.
  for (const id of ["blockly", "editor"]) {
    for (const kind of ["pointerdown", "keydown"]) $(id).addEventListener(kind, () => (working = true), { capture: true });
  }
  s.editor.signals.changed.add(() => {
    const task = $("exercise-task") as HTMLDetailsElement;
    if (!working || folded || !task.open || $("exercise").hidden) return;
    const code = [$("blockly"), $("text-editor")].find((e) => !e.hidden && e.offsetParent !== null);
    if (!code || code.getBoundingClientRect().bottom <= window.innerHeight) return;
    folded = true;
    task.open = false;
  });
  let asked = 0;
  $("exercise-answer").addEventListener("input", () => { // the target follows what the student types
    clearTimeout(asked);
    asked = window.setTimeout(() => {
      const g = goal();
      if (g) void showDrawingTarget(g);
    }, 250);
  });
}

// What a verdict is for: the program, or a cell's arms' programs (another one: no verdict yet)
const checked = () => s.editor.program.text() + (s.editor.cell ? `\n${JSON.stringify(s.editor.cell)}` : "");

function showGoal(g: Goal | null): void {
  $("exercise").hidden = !g;
  exerciseReport.exercise = null;
  fill($("exercise-result"));
  fill($("exercise-facts"));
  // the goal drawn: where the tool must go, where an object must end (a drawing's target: on the paper)
  s.view.showGoal((g?.parts ?? []).filter((p) => p.kind === "reach" || p.kind === "object") as Extract<GoalPart, { kind: "reach" | "object" }>[]);
  exerciseReport.goal = { drawn: s.view.goalShown(), facts: [] };
  const ask = g?.parts.find((p) => p.kind === "drawing" && p.ask) as DrawingPart | undefined;
  $("exercise-ask-row").hidden = !ask;
  $("exercise-ask-label").textContent = ask ? ask.ask : "";
  if (!g?.parts.some((p) => p.kind === "drawing")) s.editor.signals.drawingGoal.dispatch(null);
  if (!g) return;
  reveal("exercise"); // an exercise: its goal and the program in sight
  ($("exercise-task") as HTMLDetailsElement).open = true;
  working = folded = false;
  $("exercise-title").textContent = g.title;
  $("exercise-text").textContent = g.text;
  void goalFacts(g);
}

/** What the student needs to know of the objects a goal moves: their size, and how low the
 *  tool's point comes above them (a grasp too high fails only at Check, else). */
async function goalFacts(g: Goal): Promise<void> {
  const facts: string[] = [];
  const show = () => {
    exerciseReport.goal = { drawn: s.view.goalShown(), facts };
    fill($("exercise-facts"), ...facts.map((t) => h("li", null, t)));
  };
  const reach = g.parts.filter((p) => p.kind === "reach").length;
  if (reach) facts.push(`In the view: ${reach > 1 ? `the ${reach} numbered green balls are the points` : "the green ball is the point"}, each as wide as its tolerance.`);
  const drawing = g.parts.find((p) => p.kind === "drawing") as DrawingPart | undefined;
  if (drawing) {
    facts.push(`On the paper (Draw and write): the faint purple line is the target. The paper lies at z ${drawing.z} mm, ` +
      `the pen is ${drawing.pen} mm long; the ink must stay within ${drawing.tolerance_mm} mm of the target and cover all of it.`);
    void showDrawingTarget(g);
  }
  show();
  if (!g.parts.some((p) => p.kind === "object")) return;
  const f0 = (v: number) => Math.round(v).toString();
  try {
    const r = await s.engine.call({ type: "exercise_targets", parts: g.parts, scene: g.scene || s.editor.project.doc.scene }) as
      { objects: { name: string; size: number[]; xyz: number[]; lowest_tool_z: number | null }[] };
    if (goal() !== g) return; // another project came meanwhile
    facts.push(...r.objects.map((o) => `The ${o.name}: ${o.size.map(f0).join(" × ")} mm, standing at (${f0(o.xyz[0])}, ${f0(o.xyz[1])}) mm, ` +
      `its top ${f0(o.xyz[2] + (o.size[2] ?? 0) / 2)} mm above the table.` +
      (o.lowest_tool_z !== null ? ` Above it the tool's point comes down to ${f0(o.lowest_tool_z)} mm, no lower: grasp it above that.` : "")));
    facts.push("The green box in the view is where it must end.");
    show();
  } catch {
    /* the facts are a help: the goal and Check stand without them */
  }
}

/** A drawing exercise's target, from the engine (with the student's answer where it asks for one), to the paper. */
async function showDrawingTarget(g: Goal): Promise<void> {
  const part = g.parts.find((p) => p.kind === "drawing") as DrawingPart;
  const r = await s.engine.call({ type: "exercise_targets", parts: g.parts, scene: "", answer: answer() }) as
    { drawings: { strokes: number[][][]; z: number; pen: number; error?: string }[] };
  if (goal() !== g) return;
  const t = r.drawings[0];
  s.editor.signals.drawingGoal.dispatch({ target: t?.strokes ?? [], z: part.z, pen: part.pen });
  exerciseReport.goal = { ...exerciseReport.goal, target: t?.strokes.length ?? 0 };
}

async function check(): Promise<void> {
  const g = goal();
  if (!g) return;
  fill($("exercise-result"), h("li", null, "checking…"));
  try {
    checkedText = checked();
    const r = await s.engine.call({ type: "exercise_check", parts: g.parts, text: s.editor.program.text(), name: s.editor.program.name(),
      scene: g.scene || s.editor.project.doc.scene, answer: answer(), cell: s.editor.cell }) as
      { parts: { label: string; met: boolean; detail: string; target?: number[][][]; ink?: number[][][] }[]; met?: boolean; error?: string };
    exerciseReport.exercise = r as unknown as typeof exerciseReport.exercise;
    if (r.error) return fill($("exercise-result"), h("li", { class: "bad" }, r.error));
    const drawn = g.parts.findIndex((p) => p.kind === "drawing");
    if (drawn >= 0 && r.parts[drawn]?.target) { // the target and the program's ink, on the paper
      const part = g.parts[drawn] as DrawingPart;
      s.editor.signals.drawingGoal.dispatch({ target: r.parts[drawn].target!, z: part.z, pen: part.pen, ink: r.parts[drawn].ink });
    }
    fill($("exercise-result"), h("li", { class: r.met ? "ok" : "bad" }, r.met ? "Every part is met: well done!" : "Not yet:"),
      ...r.parts.map((p) => h("li", { class: p.met ? "ok" : "bad" }, p.met ? "✓ " : "✗ ", h("b", null, p.label), `: ${p.detail}`)));
  } catch (e) {
    exerciseReport.exercise = { parts: [], met: false, error: (e as Error).message };
    fill($("exercise-result"), h("li", { class: "bad" }, (e as Error).message));
  }
}
