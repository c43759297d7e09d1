// The Experiment panel: the thesis's sim-vs-real experiment (section 5, appendices I and K) on
// the arm shown, the virtual Nano or a real one. A plan of hil/plans runs line by line (each
// reply and each rest's steps against the model's); at each single-joint pose the student
// measures the tool with a ruler and types x, y, z; then the report: the thesis's Table 4 and
// Figs. 30-32 per joint (error per axis against the joint's angle, in mm and per cent), the
// quantization error the prediction gives beside the measured error, and a verdict per joint.
// It exports as HTML (with the plots) and CSV, and stays with the project.
//
// Every number is the host library's (host/lib/plan.h, experiment.h) through the engine's
// worker (engine/experiment.ts): the harness's report (hil/harness/report.py) has the same.
import uPlot from "uplot";
import type { Studio } from "../page/context";
import { $, download, fill, h, setOptions, status } from "../page/dom";
import type { Reports } from "../page/reports";
import type { Experiment, ExperimentChain, ExperimentPoint, ExperimentTarget } from "../project/document";

/** The experiment under way (window.articula shows it; main.ts wires it). */
export const experimentReport: { experiment: Reports["experiment"] } = {
  experiment: { running: false, waiting: null, question: "", points: [], tables: null, csv: "", mismatches: [] },
};

type Xyz = [number, number, number];
interface Axis { max_pct: number | null; max_mm: number; avg_mm: number }
interface Table4Row { joint: number; poses: number; axes: Axis[] }
interface Errors { mm: number[]; pct: (number | null)[] }
interface Table5Row {
  chain: number; moves: number; back_moves: number; dest_error_mm: number; return_error_mm: number | null;
  measured_dest_mm: number | null; measured_dest_ideal_mm: number | null; measured_return_mm: number | null; return_from_measured_start: boolean;
}
interface Tables {
  rows: { joint: number; angle: number; quant_vs_ideal: Errors; measured_vs_quant: Errors | null }[];
  quant_vs_ideal: Table4Row[]; measured_vs_quant: Table4Row[]; measured_vs_ideal: Table4Row[]; table5: Table5Row[];
  targets: { line: number; model_from_target_mm: number; ideal_from_target_mm: number; measured_from_target_mm: number | null;
    measured_from_model_mm: number | null }[];
  csv: string; // the experiment as CSV, the engine's (host/lib/records_json.h, experiment_csv)
  verdicts: { joint: number; measured: boolean; worst_mm: number; quant_mm: number; within: boolean; text: string }[];
}
interface PlanDoc {
  plan: { title: string; notes: string[]; commands: { line: number; text: string; kind: string; single_joint: [number, number] | null;
    repeat: [number, "out" | "back"] | null }[] };
  records: { line: number; code: number; steps: number[] | null; tool_ideal_mm: Xyz; tool_quantized_mm: Xyz; target_mm: Xyz | null }[];
  chains: { chain: number; moves: number; back_moves: number; line_before: number | null; line_out: number; line_back: number | null }[];
  zero: number[]; start: Xyz; start_line: string; error?: string;
}

const AXES = ["x", "y", "z"];
const COLORS = ["#d1495b", "#2e86ab", "#3a7d44", "#8d6a9f"];

let s: Studio;
let shown: Experiment | null = null;
let charts: uPlot[] = [];
let answer: ((xyz: number[] | null) => void) | null = null; // the pose waiting for its measurement
let asked: number[] | null = null; // the values the question was about ("Use it anyway" takes them)

export function initExperiment(studio: Studio): void {
  s = studio;
  s.editor.signals.experimentOpened.add(showSavedExperiment);
  $("exp-run").onclick = () => void run();
  $("exp-record").onclick = () => void record();
  $("exp-anyway").onclick = () => asked && give(asked);
  $("exp-skip").onclick = () => give(null);
  for (const id of ["exp-x", "exp-y", "exp-z"])
    $(id).addEventListener("keydown", (e) => (e as KeyboardEvent).key === "Enter" && void record());
  $("exp-html").onclick = () => void exportHtml();
  $("exp-csv").onclick = () => shown && experimentReport.experiment.csv && download(fileStem() + ".csv", experimentReport.experiment.csv, "text/csv");
  fetch(new URL("data/index.json", document.baseURI)).then((r) => r.json()).then((idx: { plans?: string[] }) => {
    const sel = $("exp-plan") as HTMLSelectElement;
    setOptions(sel, (idx.plans ?? []).map((p) => ({ value: p, label: planLabel(p) })));
    if ((idx.plans ?? []).includes("thesis-single-joint.arm")) sel.value = "thesis-single-joint.arm"; // the thesis's first
  }).catch(() => undefined);
}

const planLabel = (p: string) => ({ "thesis-single-joint.arm": "single joints (thesis 5.2, appendix K)",
  "thesis-repeatability.arm": "repeatability (thesis 5.3)", "tool-points.arm": "tool points (P)",
  "straight-lines.arm": "straight lines (T)" } as Record<string, string>)[p] ?? p;
const fileStem = () => `articula-experiment-${(shown?.plan ?? "plan").replace(/\.arm$/, "").replace(/[^\w-]+/g, "_")}`;
const say = (text: string, kind: "" | "ok" | "bad" = "") => status($("exp-state"), text, kind);

/** The project's experiment, shown again (its tables made from its measurements). */
function showSavedExperiment(e: Experiment | null): void {
  shown = e;
  experimentReport.experiment.points = e?.points ?? [];
  if (!e) {
    fill($("exp-report"));
    experimentReport.experiment.tables = null;
    return;
  }
  void report(e);
}

async function run(): Promise<void> {
  if (experimentReport.experiment.running) return;
  experimentReport.experiment.running = true; // at once: a test (or a second click) sees the run from its click on
  ($("exp-run") as HTMLButtonElement).disabled = true;
  try {
    await runPlan();
  } finally {
    experimentReport.experiment.running = false;
    experimentReport.experiment.waiting = null;
    $("exp-measure").hidden = true;
    ($("exp-run") as HTMLButtonElement).disabled = false;
  }
}

async function runPlan(): Promise<void> {
  const link = s.editor.arm.link();
  if (!link || !s.editor.armConnected) return say("Connect the arm first (the virtual Nano or a Nano on USB), above.", "bad");
  const name = ($("exp-plan") as HTMLSelectElement).value;
  if (!name) return say("Choose a plan first.", "bad");
  say(`reading ${name}…`);
  const text = await fetch(new URL(`data/plans/${name}`, document.baseURI)).then((r) => (r.ok ? r.text() : ""));
  const doc = (await s.engine.call({ type: "experiment_plan", text, name })) as unknown as PlanDoc;
  if (doc.error || !text) return say(`The plan cannot run: ${doc.error ?? "it is missing from this site"}`, "bad");
  const byLine = new Map(doc.records.map((r) => [r.line, r]));
  const stops = s.editor.stops;
  const points: ExperimentPoint[] = [];
  // Repeatability chains (thesis 5.3), as the engine groups them: the pose before each, its
  // last move out and its last move back are measured (a pose measured once serves every
  // chain that starts there).
  const chains = new Map<number, ExperimentChain & { before: number | null }>();
  for (const rc of doc.chains) {
    const out = byLine.get(rc.line_out);
    if (!out) continue;
    const b = rc.line_before === null ? null : byLine.get(rc.line_before);
    const back = rc.line_back === null ? null : byLine.get(rc.line_back);
    chains.set(rc.chain, { chain: rc.chain, moves: rc.moves, back_moves: rc.back_moves, line_out: rc.line_out, line_back: rc.line_back,
      start: b ? b.tool_quantized_mm : doc.start, dest_quant: out.tool_quantized_mm, dest_ideal: out.tool_ideal_mm,
      back_quant: back ? back.tool_quantized_mm : null, start_measured: null, dest_measured: null, back_measured: null,
      steps_back: null, before: rc.line_before });
  }
  const chainAt = (line: number) => [...chains.values()].filter((ch) => ch.before === line || ch.line_out === line || ch.line_back === line);
  const measuredAt = new Map<number, number[] | null>(); // line: what was measured there
  const stepsAt = new Map<number, number[]>(); // line: the arm's steps after it
  const targets: ExperimentTarget[] = [];
  const mismatches: string[] = [];
  experimentReport.experiment.points = points;
  experimentReport.experiment.mismatches = mismatches;
  try {
    // From the power-up pose (every motor at step 0), as the prediction assumes.
    say("to the start pose (every motor at step 0)…");
    const start = await link.runLine(doc.start_line);
    if (start.reply !== "ok") throw new Error(`the arm refused the start pose: ${start.reply}`);
    const n = doc.plan.commands.length;
    for (let i = 0; i < n; i++) {
      if (s.editor.stops !== stops) return say(`Stopped after ${i} of ${n} lines: the measurements so far are kept below.`, "bad");
      const c = doc.plan.commands[i];
      const pred = byLine.get(c.line);
      say(`line ${c.line} (${i + 1} of ${n}): ${c.text}`);
      const r = await link.runLine(c.text);
      const expected = pred ? (pred.code === 0 ? "ok" : `error:${pred.code}`) : "?";
      if (r.reply !== expected) mismatches.push(`line ${c.line}, ${c.text}: the arm said ${r.reply}, the model ${expected}`);
      else if (r.reply === "ok" && pred?.steps && r.steps.join() !== pred.steps.join())
        mismatches.push(`line ${c.line}, ${c.text}: the arm is at steps ${r.steps.join(" ")}, the model at ${pred.steps.join(" ")}`);
      stepsAt.set(c.line, r.steps);
      const inChains = chainAt(c.line);
      const target = c.kind === "target" && pred?.target_mm ? pred.target_mm : null;
      if ((c.single_joint || inChains.length || target) && r.reply === "ok" && pred) {
        const what = c.single_joint ? `joint ${c.single_joint[0]} at the thesis's ${c.single_joint[1]} deg`
          : target ? `the point (${target.map((x) => x.toFixed(0)).join(", ")}) it was sent to`
          : inChains.map((ch) => ch.line_out === c.line ? `chain ${ch.chain} at its destination`
            : ch.line_back === c.line ? `chain ${ch.chain} back at its start` : `the start of chain ${ch.chain}`).join("; ");
        const measured = await ask(what, c.single_joint ? c.single_joint[0] : -1, c.single_joint ? c.single_joint[1] : NaN,
          c.line, c.text, pred.tool_quantized_mm);
        if (s.editor.stops !== stops) return say(`Stopped after ${i + 1} of ${n} lines: the measurements so far are kept below.`, "bad");
        measuredAt.set(c.line, measured);
        if (target)
          targets.push({ line: c.line, command: c.text, target, quant: pred.tool_quantized_mm, ideal: pred.tool_ideal_mm, measured });
        if (c.single_joint)
          points.push({ joint: c.single_joint[0], angle: c.single_joint[1], line: c.line, command: c.text, ideal: pred.tool_ideal_mm,
            quant: pred.tool_quantized_mm, measured });
      }
    }
    say(`The plan ran: ${n} lines, ${measuredAt.size ? [...measuredAt.values()].filter(Boolean).length : 0} of ${measuredAt.size} poses measured` +
      (mismatches.length ? `; ${mismatches.length} differ from the model (below).` : "; every reply and every step as the model predicts."),
      mismatches.length ? "bad" : "ok");
  } catch (e) {
    say(`The experiment stopped: ${(e as Error).message}`, "bad");
  } finally {
    const done: ExperimentChain[] = [];
    for (const { before, ...ch } of chains.values()) {
      ch.line_before = before;
      if (!stepsAt.has(ch.line_out)) continue; // not reached
      const start = before === null ? doc.zero.map(() => 0) : stepsAt.get(before);
      const back = ch.line_back === null ? undefined : stepsAt.get(ch.line_back);
      done.push({ ...ch, start_measured: before === null ? null : measuredAt.get(before) ?? null,
        dest_measured: measuredAt.get(ch.line_out) ?? null, back_measured: ch.line_back === null ? null : measuredAt.get(ch.line_back) ?? null,
        back_quant: back ? ch.back_quant : null, steps_back: back && start ? back.join() === start.join() : null });
    }
    if (points.length || done.length || targets.length) {
      shown = { plan: name, title: doc.plan.title, robot: s.editor.robot?.name ?? "", when: new Date().toISOString(), points, chains: done, targets };
      s.editor.project.setExperiment(shown); // kept with the project
      await report(shown, mismatches);
    }
  }
}

// The measurement of one pose: the student's x, y, z, or null (skipped). joint -1: a
// repeatability pose.
function ask(what: string, joint: number, angle: number, line: number, command: string, model: Xyz): Promise<number[] | null> {
  experimentReport.experiment.waiting = { joint, angle, line, command, model };
  experimentReport.experiment.question = "";
  asked = null;
  $("exp-measure").hidden = false;
  $("exp-question").textContent = "";
  $("exp-anyway").hidden = true;
  fill($("exp-prompt"), h("b", null, `Measure the tool: ${what}`), ` (line ${line}, ${command}). ` +
    `The model puts it at x ${model[0].toFixed(1)}, y ${model[1].toFixed(1)}, z ${model[2].toFixed(1)} mm, from the base: ` +
    "x forward, y to the left, z up.");
  for (const id of ["exp-x", "exp-y", "exp-z"]) ($(id) as HTMLInputElement).value = "";
  ($("exp-x") as HTMLInputElement).focus({ preventScroll: true });
  const stops = s.editor.stops;
  stopWatch = window.setInterval(() => s.editor.stops !== stops && give(null), 200); // STOP ends the wait too
  return new Promise((resolve) => (answer = resolve));
}

let stopWatch = 0;

function give(xyz: number[] | null): void {
  clearInterval(stopWatch);
  const a = answer;
  answer = null;
  experimentReport.experiment.waiting = null;
  $("exp-measure").hidden = true;
  a?.(xyz);
}

// Record: the values typed, questioned by the engine (not a number, typed in cm, beyond the
// reach, far from the model) before they are used.
async function record(): Promise<void> {
  const w = experimentReport.experiment.waiting;
  if (!w) return;
  const xyz = ["exp-x", "exp-y", "exp-z"].map((id) => {
    const t = ($(id) as HTMLInputElement).value.trim().replace(",", ".");
    return t === "" ? NaN : Number(t);
  });
  const r = (await s.engine.call({ type: "experiment_question", measured: xyz, predicted: w.model })) as unknown as { question: string };
  experimentReport.experiment.question = r.question;
  if (!r.question) return give(xyz);
  $("exp-question").textContent = r.question;
  asked = xyz.every(Number.isFinite) ? xyz : null;
  $("exp-anyway").hidden = !asked; // a value that is not a number is never used
}

// ---- the report

async function report(e: Experiment, mismatches: string[] = []): Promise<void> {
  const t = (await s.engine.call({ type: "experiment_tables",
    points: e.points.map((p) => ({ joint: p.joint, angle: p.angle, ideal: p.ideal, quant: p.quant, measured: p.measured })),
    chains: e.chains ?? [], targets: e.targets ?? [], experiment: e })) as unknown as Tables;
  experimentReport.experiment.tables = t;
  experimentReport.experiment.csv = t.csv;
  charts.forEach((c) => c.destroy());
  charts = [];
  const joints = [...new Set(e.points.map((p) => p.joint))].sort((a, b) => a - b);
  const measured = e.points.filter((p) => p.measured).length;
  const box = $("exp-report");
  fill(box,
    h("h3", null, `${e.title}: ${e.robot}`),
    h("p", { class: "note" }, `${new Date(e.when).toLocaleString()}; measured with a ruler: ${measuredSummary(e)}. ` +
      "Errors per axis (x forward, y left, z up) in mm, and in per cent of the coordinate as the thesis gives them " +
      "(none where the coordinate is within 1 mm of 0)."),
    ...mismatches.map((m) => h("p", { class: "status bad" }, m)),
    joints.length ? h("h4", null, "Verdict per joint") : null,
    joints.length ? verdicts(t) : null,
    (e.chains ?? []).length ? table5(e, t) : null,
    (e.targets ?? []).length ? targetTable(e, t) : null,
    measured ? table4("Table 4: measured against the model (whole steps)", t.measured_vs_quant) : null,
    measured ? table4("Measured against the exact angles", t.measured_vs_ideal) : null,
    joints.length ? table4("What whole steps alone leave: the model's quantization error", t.quant_vs_ideal) : null,
    joints.length ? h("h4", null, "Error against the joint's angle (thesis Figs. 30-32)") : null,
    h("div", { id: "exp-plots" }),
    e.points.length ? poses(e, t) : null,
  );
  for (const j of joints) plot(e, t, j);
  $("exp-export").hidden = false;
}

const TABLE5_HEAD = ["chain", "moves", "line out", "destination: whole steps vs exact mm", "line back", "return: model vs start mm",
  "steps back at start", "measured vs model at destination mm", "measured return vs start mm"];

function table5Rows(e: Experiment, t: Tables): string[][] {
  const f = (v: number | null | undefined) => (v === null || v === undefined ? "—" : v.toFixed(3));
  return (e.chains ?? []).map((c, i) => {
    const r = t.table5[i];
    return [String(c.chain), `${c.moves} out, ${c.back_moves} back`, String(c.line_out), f(r.dest_error_mm), c.line_back === null ? "—" : String(c.line_back),
      f(r.return_error_mm), c.steps_back === null ? "—" : c.steps_back ? "yes" : "no", f(r.measured_dest_mm),
      r.measured_return_mm === null ? "—" : `${f(r.measured_return_mm)} (from the ${r.return_from_measured_start ? "measured" : "model's"} start)`];
  });
}

// Table 5 (thesis 5.3): each chain's destination and return.
function table5(e: Experiment, t: Tables): HTMLElement {
  return h("div", { class: "table4" }, h("h4", null, "Table 5: repeatability, out and back"), h("table", null,
    h("thead", null, h("tr", null, ...TABLE5_HEAD.map((c) => h("th", null, c)))),
    h("tbody", null, ...table5Rows(e, t).map((row) => h("tr", null, ...row.map((c, k) => (k === 6 && c === "no"
      ? h("td", { class: "bad" }, c) : h("td", null, c))))))));
}

const TARGET_HEAD = ["line", "command", "model tool mm", "model from target mm", "exact angles from target mm", "measured mm",
  "measured from target mm", "measured from model mm"];

function targetRows(e: Experiment, t: Tables): string[][] {
  const f = (v: number | null, d = 3) => (v === null ? "—" : v.toFixed(d));
  return (e.targets ?? []).map((p, i) => {
    const r = t.targets[i];
    return [String(p.line), p.command, p.quant.map((x) => x.toFixed(1)).join(", "), f(r.model_from_target_mm), f(r.ideal_from_target_mm, 4),
      p.measured ? p.measured.map((x) => x.toFixed(1)).join(", ") : "—", f(r.measured_from_target_mm), f(r.measured_from_model_mm)];
  });
}

// The tool sent to points (P): the closed form's, the steps' and the arm's distance to each.
function targetTable(e: Experiment, t: Tables): HTMLElement {
  return h("div", { class: "table4" }, h("h4", null, "Tool to points (P)"), h("table", null,
    h("thead", null, h("tr", null, ...TARGET_HEAD.map((c) => h("th", null, c)))),
    h("tbody", null, ...targetRows(e, t).map((row) => h("tr", null, ...row.map((c) => h("td", null, c)))))));
}

// What was measured, of what the plan asked about: "9 of 12 single-joint poses, 5 chains ...".
function measuredSummary(e: Experiment): string {
  const chains = e.chains ?? [], targets = e.targets ?? [];
  const parts = [
    e.points.length ? `${e.points.filter((p) => p.measured).length} of ${e.points.length} single-joint poses` : "",
    chains.length ? `${chains.filter((c) => c.dest_measured).length} of ${chains.length} repeatability chains` : "",
    targets.length ? `${targets.filter((p) => p.measured).length} of ${targets.length} points` : "",
  ].filter(Boolean);
  return parts.join(", ") || "nothing";
}

// The engine's verdict per joint (host/lib/experiment.h, joint_verdicts): the harness report's too.
function verdicts(t: Tables): HTMLElement {
  return h("ul", { class: "verdicts" }, ...t.verdicts.map((v) =>
    h("li", v.measured ? { class: v.within ? "ok" : "bad" } : null, h("b", null, `joint ${v.joint}: `), v.text)));
}

function table4(title: string, rows: Table4Row[]): HTMLElement {
  const head = ["axis", ...rows.flatMap((r) => [`joint ${r.joint} max %`, `joint ${r.joint} max mm`, `joint ${r.joint} avg mm`])];
  return h("div", { class: "table4" }, h("h4", null, title), h("table", null,
    h("thead", null, h("tr", null, ...head.map((c) => h("th", null, c)))),
    h("tbody", null, ...AXES.map((axis, k) => h("tr", null, h("th", null, axis.toUpperCase()),
      ...rows.flatMap((r) => [num(r.axes[k].max_pct, 2), num(r.axes[k].max_mm, 3), num(r.axes[k].avg_mm, 3)]))))));
}

const num = (v: number | null, d: number) => h("td", null, v === null ? "—" : v.toFixed(d));

function poses(e: Experiment, t: Tables): HTMLElement {
  const head = ["joint", "thesis deg", "line", "command", "model mm (whole steps)", "measured mm", "|dx| mm", "|dy| mm", "|dz| mm", "quantization mm"];
  return h("details", null, h("summary", null, "Every pose"), h("table", { class: "poses" },
    h("thead", null, h("tr", null, ...head.map((c) => h("th", null, c)))),
    h("tbody", null, ...e.points.map((p, i) => {
      const r = t.rows[i];
      const m = r.measured_vs_quant;
      return h("tr", null, h("td", null, p.joint), h("td", null, p.angle), h("td", null, p.line), h("td", null, p.command),
        h("td", null, p.quant.map((x) => x.toFixed(1)).join(", ")), h("td", null, p.measured ? p.measured.map((x) => x.toFixed(1)).join(", ") : "—"),
        ...[0, 1, 2].map((k) => num(m ? m.mm[k] : null, 2)), num(Math.hypot(...r.quant_vs_ideal.mm), 3));
    }))));
}

function plot(e: Experiment, t: Tables, joint: number): void {
  const idx = e.points.map((p, i) => i).filter((i) => e.points[i].joint === joint).sort((a, b) => e.points[a].angle - e.points[b].angle);
  const x = idx.map((i) => e.points[i].angle);
  const series = [0, 1, 2].map((k) => idx.map((i) => t.rows[i].measured_vs_quant?.mm[k] ?? null));
  const quant = idx.map((i) => Math.hypot(...t.rows[i].quant_vs_ideal.mm));
  const div = h("div", { class: "plot" });
  $("exp-plots").append(div);
  const width = Math.max(260, Math.min(520, ($("exp-report").clientWidth || 320) - 8));
  charts.push(new uPlot({
    title: `joint ${joint}: error against its angle`, width, height: 200,
    scales: { x: { time: false } },
    axes: [{ label: "thesis angle (deg)", size: 34 }, { label: "mm", size: 46 }],
    series: [{ label: "deg" }, ...AXES.map((a, k) => ({ label: `|d${a}| measured`, stroke: COLORS[k], width: 2, points: { show: true, size: 6 } })),
      { label: "quantization", stroke: COLORS[3], width: 2, dash: [4, 4], points: { show: true, size: 5 } }],
    legend: { show: true, live: false },
    cursor: { drag: { x: false, y: false } },
  }, [x, ...series, quant] as uPlot.AlignedData, div));
}

// The HTML: the report's tables and verdicts, its plots as pictures, in one file. Written as
// text with every string escaped (nothing here is parsed by this page).
const esc = (v: unknown) => String(v).replace(/[&<>"']/g, (c) => `&#${c.charCodeAt(0)};`);

function htmlTable(head: string[], rows: (string | number)[][]): string {
  return `<table><tr>${head.map((c) => `<th>${esc(c)}</th>`).join("")}</tr>` +
    rows.map((r) => `<tr>${r.map((c) => `<td>${esc(c)}</td>`).join("")}</tr>`).join("") + "</table>";
}

function htmlTable4(title: string, rows: Table4Row[]): string {
  const head = ["axis", ...rows.flatMap((r) => [`joint ${r.joint} max %`, `joint ${r.joint} max mm`, `joint ${r.joint} avg mm`])];
  const f = (v: number | null, d: number) => (v === null ? "—" : v.toFixed(d));
  return `<h2>${esc(title)}</h2>` + htmlTable(head, AXES.map((axis, k) =>
    [axis.toUpperCase(), ...rows.flatMap((r) => [f(r.axes[k].max_pct, 2), f(r.axes[k].max_mm, 3), f(r.axes[k].avg_mm, 3)])]));
}

async function exportHtml(): Promise<void> {
  const e = shown, t = experimentReport.experiment.tables as Tables | null;
  if (!e || !t) return;
  const measured = e.points.some((p) => p.measured);
  const verdictItems = [...$("exp-report").querySelectorAll(".verdicts li")].map((li) =>
    `<li class="${li.classList.contains("bad") ? "bad" : "ok"}">${esc(li.textContent)}</li>`);
  const body = [
    `<h1>${esc(e.title)}: ${esc(e.robot)}</h1>`,
    `<p>${esc(new Date(e.when).toLocaleString())}; measured with a ruler: ${esc(measuredSummary(e))}. ` +
      "Errors per axis (x forward, y left, z up) in mm, and in per cent of the coordinate (none within 1 mm of 0). " +
      "Made by Articula Studio from the host library's numbers (the harness's report has the same).</p>",
    verdictItems.length ? `<h2>Verdict per joint</h2><ul>${verdictItems.join("")}</ul>` : "",
    (e.chains ?? []).length ? "<h2>Table 5: repeatability, out and back</h2>" + htmlTable(TABLE5_HEAD, table5Rows(e, t)) : "",
    (e.targets ?? []).length ? "<h2>Tool to points (P)</h2>" + htmlTable(TARGET_HEAD, targetRows(e, t)) : "",
    measured ? htmlTable4("Table 4: measured against the model (whole steps)", t.measured_vs_quant) : "",
    measured ? htmlTable4("Measured against the exact angles", t.measured_vs_ideal) : "",
    e.points.length ? htmlTable4("What whole steps alone leave: the model's quantization error", t.quant_vs_ideal) : "",
    "<h2>Error against the joint's angle (thesis Figs. 30-32)</h2>",
    ...charts.map((c) => `<img src="${c.ctx.canvas.toDataURL("image/png")}" alt="${esc(c.root.querySelector(".u-title")?.textContent ?? "plot")}">`),
    e.points.length ? "<h2>Every pose</h2>" : "",
    !e.points.length ? "" : htmlTable(["joint", "thesis deg", "line", "command", "model mm", "measured mm", "|dx| mm", "|dy| mm", "|dz| mm"],
      e.points.map((p, i) => {
        const m = t.rows[i].measured_vs_quant;
        return [p.joint, p.angle, p.line, p.command, p.quant.map((x) => x.toFixed(2)).join(", "),
          p.measured ? p.measured.map((x) => x.toFixed(2)).join(", ") : "—", ...[0, 1, 2].map((k) => (m ? m.mm[k].toFixed(3) : "—"))];
      })),
  ];
  const style = "body{font:14px system-ui,sans-serif;margin:24px;color:#1d2733;max-width:1000px}table{border-collapse:collapse;margin:8px 0}" +
    "td,th{border:1px solid #c9d3dd;padding:3px 7px;text-align:right}li.bad{color:#8d1c1c}li.ok{color:#155e55}img{max-width:100%;display:block;margin:8px 0}";
  download(fileStem() + ".html", `<!doctype html>\n<html lang="en"><head><meta charset="utf-8"><title>${esc(`Articula experiment: ${e.title}`)}</title>` +
    `<style>${style}</style></head><body>${body.join("\n")}</body></html>\n`, "text/html");
}
