// The Draw and write panel: text, a shape or an SVG file for a pen held in the gripper, its
// width and place on the paper, the paper's height and the pen's length; the engine lays it
// out, checks the pen reaches it, orders it, writes the program and predicts it step by step
// (host/lib/draw.h, through the worker). The view draws the drawing and the line the arm will
// draw over each other on the paper; "Put in the program" hands the program to the editor.
// Everything from a file is shown as text, never as HTML.
import type { Studio } from "../page/context";
import { $ } from "../page/dom";
import { hook } from "../page/hook";

const MAX_SVG_BYTES = 5 * 1024 * 1024; // the engine's limit too (host/lib/svg.h)

interface Drawing {
  error?: string; what: string; strokes: number[][][]; program: string; width_mm: number; height_mm: number; seconds?: number;
  reach: { fits: boolean; points: number; advice: string };
  ink?: { strokes: number[][][]; worst_mm: number; worst_line: number; steps: number };
}

let s: Studio;
let program = "";
let setText: (text: string, name: string) => void = () => undefined;

const num = (id: string) => parseFloat(($(id) as HTMLInputElement).value);

function say(text: string, kind: "" | "ok" | "bad" = ""): void {
  const el = $("draw-status");
  el.textContent = text;
  el.className = kind ? `status ${kind}` : "status";
}

export function initDraw(studio: Studio, program_: { setText: (text: string, name: string) => void }): void {
  s = studio;
  setText = program_.setText;
  const kind = $("draw-kind") as HTMLSelectElement;
  const showKind = () => {
    $("draw-text").hidden = kind.value !== "text";
    $("draw-file").hidden = kind.value !== "svg";
  };
  kind.addEventListener("change", showKind);
  showKind();
  $("draw-go").onclick = () => void draw();
  $("draw-use").onclick = () => {
    if (!program) return;
    setText(program, "drawing.arm");
    say("The drawing is the program now: Run plays it, on the arm too when it is connected.", "ok");
  };
  s.editor.signals.robotShown.add(() => {
    s.view.showDrawing([], [], 0);
    program = "";
    ($("draw-use") as HTMLButtonElement).disabled = true;
    hook.drawing = null;
  });
}

async function draw(): Promise<void> {
  const kind = ($("draw-kind") as HTMLSelectElement).value;
  const request: Record<string, unknown> = {
    width: num("draw-width"), at: [num("draw-x"), num("draw-y")], z: num("draw-z"), pen: num("draw-pen"),
  };
  const steps = ($("draw-steps") as HTMLSelectElement).value;
  if (steps) request.microsteps = Number(steps);
  for (const [k, v] of Object.entries(request))
    if ((typeof v === "number" && !Number.isFinite(v)) || (Array.isArray(v) && !v.every(Number.isFinite)))
      return say(`The ${k === "at" ? "place (x, y)" : k} holds no number: type one.`, "bad");
  if (kind === "text") {
    request.text = ($("draw-text") as HTMLInputElement).value;
    if (!request.text) return say("Type the text to write.", "bad");
  } else if (kind === "svg") {
    const f = ($("draw-file") as HTMLInputElement).files?.[0];
    if (!f) return say("Choose an SVG file to draw.", "bad");
    if (f.size > MAX_SVG_BYTES) return say(`${f.name}: ${Math.round(f.size / 1024)} KB: a drawing is at most 5 MB.`, "bad");
    request.svg = await f.text();
    request.svg_name = f.name;
  } else {
    request.shape = kind;
  }
  say("drawing…");
  const d = (await s.engine.call({ type: "draw", request })) as unknown as Drawing;
  program = "";
  ($("draw-use") as HTMLButtonElement).disabled = true;
  if (d.error) {
    s.view.showDrawing([], [], 0);
    hook.drawing = { fits: false, error: d.error, advice: "", worstMm: 0, steps: 0, lines: 0, program: "" };
    hook.drawings++;
    return say(d.error, "bad");
  }
  s.view.showDrawing(d.strokes, d.ink?.strokes ?? [], request.z as number);
  hook.drawing = { fits: d.reach.fits, error: "", advice: d.reach.advice, worstMm: d.ink?.worst_mm ?? 0, steps: d.ink?.steps ?? 0,
    lines: d.program ? d.program.split("\n").length - 1 : 0, program: d.program };
  hook.drawings++;
  if (!d.reach.fits) return say(`${d.what}: ${d.reach.advice}.`, "bad");
  program = d.program;
  ($("draw-use") as HTMLButtonElement).disabled = false;
  const size = `${d.width_mm.toFixed(0)} × ${d.height_mm.toFixed(0)} mm`;
  say(d.ink
    ? `${d.what}, ${size}: ${d.strokes.length} strokes, ${hook.drawing.lines} lines, ${d.seconds?.toFixed(0)} s. ` +
      `The pen (orange) stays within ${d.ink.worst_mm.toFixed(2)} mm of the drawing (blue) at every one of its ${d.ink.steps} ` +
      `steps; the worst on line ${d.ink.worst_line}.`
    : `${d.what}, ${size}: ${d.strokes.length} strokes, ${hook.drawing.lines} lines.`, "ok");
}
