// The program panel: the editor with its line numbers and running line, the shipped examples,
// open and save, Run (on the model, or on the arm when asked), Pause, Step, Reset, Teach, the
// ghost, the plots of the time line. The engine predicts and plays; this panel shows.
import type { PoseMsg, TimelineMsg, TimelineRecord } from "../engine/messages";
import type { Studio } from "../page/context";
import { $, banner, download, fill, h } from "../page/dom";
import type { Reports } from "../page/reports";
import { language } from "../page/environment";

/** The program panel's reports (window.articula shows it; main.ts wires it). */
export const programReport: { paths: Reports["paths"]; pngCaption: string; programError: string; programName: string; runOnArm: boolean;
  breaks: number[]; pausedAt: number; watch: Record<string, string> } = {
  paths: { points: 0, lines: 0, worstMm: 0 }, pngCaption: "", programError: "", programName: "program.arm", runOnArm: false,
  breaks: [], pausedAt: 0, watch: {},
};

let s: Studio;
let currentProgram = "program.arm";
let autoplay: number[] | null = null; // loading to play at once, with these breakpoints
let forArm = false; // loading the model's prediction of a program the arm runs: the arm's messages say how it goes
let showGhost = true;
let lineShown = 0;
const editor = () => $("editor") as HTMLTextAreaElement;
// Run goes to the arm: one is connected and "on the arm" (beside Run) is ticked
const onTheArm = () => s.editor.armConnected && ($("drive-arm") as HTMLInputElement).checked;
/** Where Run runs: "▶ Run [✓] on the arm" reads as one sentence; the tooltip says it whole. */
function runTarget(): void {
  const run = $("run");
  run.title = onTheArm() ? "Send the program to the arm, line by line (untick “on the arm” to play it on the model only)"
    : s.editor.armConnected ? "Play the program on the model only: the arm stays still (tick “on the arm” to drive it)"
    : "Run the program with the controller's real timing";
  programReport.runOnArm = onTheArm();
}

export const ghostShown = () => showGhost;
const playSpeed = () => parseFloat(($("play-speed") as HTMLSelectElement).value) || 1;

// What the command on the caret's line does, under the editor.
const HELP: Record<string, string> = {
  L: "L joint degrees: turns one motor by an angle",
  M: "M a b c: every motor to an angle (the motors' angles, shown beside the sliders)",
  P: "P x y z: the tip of the tool to a point, mm from the base",
  T: "T x y z speed: the tip of the tool along a straight line to a point, mm from the base, at mm/s",
  G: "G percent: the gripper's opening, 0 closed to 100 open",
  S: "S 1 closes the gripper, S 0 opens it",
  D: "D seconds: waits that long before the next line",
  H: "H: home", Z: "Z: here is home", I: "I: the arm says what it is", $: "$: a setting ($0 speed, $1 acceleration)",
  m: "RoboSim m: every joint's value follows, one a line", a: "RoboSim a: a point follows, x y z on three lines",
  h: "RoboSim h: the hand, 0.0 open to 0.5 closed", s: "RoboSim s: speed, 1 slow to 82 fast",
  w: "RoboSim w: IK weights, one a joint", l: "RoboSim l: link lengths", z: "RoboSim z: the view's zoom",
};
function helpFor(line: string): string {
  const word = line.trim().split(/\s+/)[0] ?? "";
  const key = word.startsWith("#") ? "#" : word.startsWith("$") ? "$" : word.length === 1 ? (HELP[word] ? word : word.toUpperCase()) : "";
  return key === "#" ? "# a note for people: the arm ignores it" : HELP[key] ?? "";
}
function lineHelp(): void {
  const ed = editor();
  const start = ed.value.lastIndexOf("\n", ed.selectionStart - 1) + 1;
  const end = ed.value.indexOf("\n", start);
  $("line-help").textContent = helpFor(ed.value.slice(start, end < 0 ? undefined : end));
}
// Help on hover: the line under the pointer says what its command does (the editor's tooltip,
// and the help line under it while the pointer is over the editor). Only when the pointer
// comes to another line (-1: the text changed, or the pointer left).
let hoverRow = -1;
function hoverHelp(e: MouseEvent): void {
  const ed = editor();
  const cs = getComputedStyle(ed);
  const lh = parseFloat(cs.lineHeight) || 1.4 * parseFloat(cs.fontSize);
  const row = Math.floor((e.offsetY + ed.scrollTop - parseFloat(cs.paddingTop)) / lh);
  if (row === hoverRow) return;
  hoverRow = row;
  const line = ed.value.split("\n")[row];
  const help = line === undefined ? "" : helpFor(line);
  ed.title = help ? `line ${row + 1}: ${help}` : "";
  if (help) $("line-help").textContent = ed.title;
}

export function initProgram(studio: Studio): void {
  s = studio;
  s.editor.program = { text: () => editor().value, name: () => currentProgram, set: (text, name) => setProgram(name, text) };
  const sig = s.editor.signals;
  sig.lineRunning.add(({ line, refused }) => highlightLine(line, refused));
  sig.programSaid.add(({ text, rejected, bad }) => programStatus(text, rejected, bad));
  sig.robotShown.add((r) => {
    showExamples(r.programs);
    if (!r.keep_view) resetProgramView(); // keep_view: the same robot, other link lengths
  });
  // The physics turned on, off or to another scene: the engine dropped the time line it had
  // worked out (with the physics the world runs the program), so Run and Step work it out
  // again rather than play one that is gone (issue 55, 2).
  sig.changed.add((part) => {
    if (part !== "scene" || !s.editor.timeline) return;
    resetProgramView();
    programStatus("The world changed: Run works the program out again and runs it.");
  });
  // the arm connected: Run drives it (the choice beside Run); lost or closed: the model only
  sig.armConnected.add((on) => {
    $("drive-arm-row").hidden = !on;
    (($("drive-arm") as HTMLInputElement).checked = on);
    runTarget();
  });
  $("drive-arm").addEventListener("change", runTarget);
  initSpeed();
  // the exercises, first in the examples menu: each has a goal the page checks
  fetch(new URL("data/index.json", document.baseURI)).then((r) => r.json()).then((idx: { exercises?: string[] }) => {
    exercises = idx.exercises ?? [];
    showExamples(examples);
  }).catch(() => undefined);
  const ed = editor();
  ed.addEventListener("input", () => {
    editorChanged();
    lineHelp();
  });
  for (const ev of ["click", "keyup", "focus"]) ed.addEventListener(ev, lineHelp);
  ed.addEventListener("mouseleave", () => {
    hoverRow = -1;
    lineHelp();
  });
  ed.addEventListener("mousemove", hoverHelp);
  ed.addEventListener("scroll", () => {
    $("gutter").scrollTop = ed.scrollTop;
    positionLine();
  });
  $("program-select").addEventListener("change", (e) => {
    const name = (e.target as HTMLSelectElement).value;
    if (name.startsWith("exercise:")) s.editor.signals.exerciseWanted.dispatch(name.slice("exercise:".length));
    else if (name) s.engine.send({ type: "program_open", name });
    (e.target as HTMLSelectElement).value = "";
  });
  $("open-program").onclick = () => $("program-file").click();
  $("program-file").addEventListener("change", async (e) => {
    const f = (e.target as HTMLInputElement).files?.[0];
    if (!f) return;
    setProgram(f.name, await f.text());
    (e.target as HTMLInputElement).value = "";
    if (s.editor.blocks.mode() === "blocks") s.editor.blocks.fromText();
  });
  $("save-program").onclick = () => download(currentProgram, ed.value, "text/plain");
  $("run").onclick = () => run();
  $("run-to").onclick = () => run(caretLine());
  $("pause").onclick = () => {
    const link = armProgram();
    if (link) return link.pauseAfterLine(); // (at rest after the line running)
    s.engine.send({ type: "pause" });
  };
  $("step").onclick = () => {
    const link = armProgram();
    if (link) return link.pausedAt ? link.resume(true) : link.pauseAfterLine();
    if (s.editor.timeline) s.engine.send({ type: "step" });
    else load();
  };
  $("reset").onclick = () => (s.editor.timeline ? s.engine.send({ type: "rewind" }) : load());
  $("teach").onclick = () => record();
  // breakpoints: a line number clicked, or F9 on the caret's line (Ctrl+F8: run to the caret)
  $("gutter").addEventListener("click", (e) => {
    const el = (e.target as HTMLElement).closest("#gutter > div");
    if (el) toggleBreak([...$("gutter").children].indexOf(el) + 1);
  });
  ed.addEventListener("keydown", (e) => {
    if (e.key === "F9") {
      e.preventDefault();
      toggleBreak(caretLine());
    } else if (e.key === "F8" && e.ctrlKey) {
      e.preventDefault();
      run(caretLine());
    }
  });
  const scrub = $("scrub") as HTMLInputElement;
  scrub.addEventListener("input", () => {
    if (s.editor.timeline) s.engine.send({ type: "seek", t: parseFloat(scrub.value) });
  });
  s.editor.signals.armReported.add(() => s.editor.pose && showWatch(s.editor.pose));
  s.editor.signals.armPaused.add((line) => {
    programReport.pausedAt = line;
    $("run").classList.toggle("active", false);
  });
  $("show-ghost").addEventListener("change", (e) => {
    showGhost = (e.target as HTMLInputElement).checked;
    if (!showGhost && s.editor.pose) s.view.pose({ ...s.editor.pose, ghost: undefined });
  });
  s.plots.onSeek = (t) => s.engine.send({ type: "seek", t });
  $("export-png").onclick = () => {
    const caption = `${s.editor.robot?.name ?? ""}, ${currentProgram}, ${new Date().toLocaleString(language)}`;
    programReport.pngCaption = caption;
    s.plots.png(caption).then((blob) => blob && download(`articula-plots-${currentProgram.replace(/\W+/g, "_")}.png`, blob, "image/png"));
  };
  $("export-csv").onclick = () => s.editor.timeline && download("articula-timeline.csv", s.plots.csv(s.editor.timeline), "text/csv");
  editorChanged();
}

// A program on the arm (sent line by line now): its link; null: none runs.
function armProgram() {
  const link = s.editor.armConnected ? s.editor.arm.link() : null;
  return link?.running ? link : null;
}

/** Run: on the arm or the model, pausing after each breakpoint's line (and after `to` too, for
 * this run: Run to caret). A program paused goes on. */
function run(to = 0): void {
  const ed = editor();
  if (!ed.value.trim())
    return programStatus("The program is empty: type commands (“What the commands mean” below says how), choose an example, or build it from Blocks.", [], true);
  const breaks = [...breakpoints, ...(to ? [to] : [])];
  const link = armProgram();
  if (link) {
    link.setBreaks(breaks);
    return link.resume();
  }
  if (onTheArm()) {
    // the model's prediction beside it: the plots, and the time the run is compared with
    if (!s.editor.timeline && !s.editor.physics?.on) { // (with the physics on a program load would restart the world)
      forArm = true;
      load();
    }
    return s.editor.arm.run(ed.value, breaks);
  }
  programReport.pausedAt = 0;
  if (s.editor.timeline) s.engine.send({ type: "play", speed: playSpeed(), breaks });
  else {
    autoplay = breaks;
    load();
  }
}

/** The caret's line, 1 on. */
function caretLine(): number {
  const ed = editor();
  return ed.value.slice(0, ed.selectionStart).split("\n").length;
}

const breakpoints = new Set<number>();
function toggleBreak(line: number): void {
  if (line < 1) return;
  if (breakpoints.has(line)) breakpoints.delete(line);
  else breakpoints.add(line);
  showBreaks();
  armProgram()?.setBreaks(breakpoints);
}
function showBreaks(): void {
  programReport.breaks = [...breakpoints].sort((a, b) => a - b);
  [...$("gutter").children].forEach((el, i) => {
    const on = breakpoints.has(i + 1);
    el.classList.toggle("break", on);
    el.setAttribute("aria-label", `line ${i + 1}${on ? ": a breakpoint" : ""}`);
  });
}

/** Record: the pose (a connected arm's, else the model's) as a line or a block, named or not. */
function record(): void {
  const kind = ($("record-as") as HTMLSelectElement).value;
  const q = s.editor.armConnected ? s.editor.arm.pose() : null;
  const ed = editor();
  const first = ed.value.split("\n").find((l) => l.trim() && !l.trim().startsWith("#")) ?? "";
  const robosim = s.editor.blocks.mode() !== "blocks" && (currentProgram.endsWith(".robosim") || /^\s*[a-z]\s*$/m.test(first));
  if (robosim && kind !== "M") return programStatus("A RoboSim program records the joints (m): choose “the joints (M)”.", [], true);
  const speed = parseFloat(($("ik-line-speed") as HTMLInputElement | null)?.value ?? "") || 30;
  s.engine.send({ type: "teach", kind, q, speed, format: robosim ? "robosim" : "protocol" });
}

/** The shipped examples, for the menu: the exercises first (a goal the page checks), then the
 * programs that fit the robot shown. */
function showExamples(names: string[]): void {
  examples = names;
  const sel = $("program-select") as HTMLSelectElement;
  fill(sel, h("option", { value: "" }, "examples…"),
    ...(exercises.length ? [h("optgroup", { label: "Exercises: the page checks them" },
      ...exercises.map((x) => h("option", { value: `exercise:${x}` }, exerciseLabel(x))))] : []),
    h("optgroup", { label: "Programs" }, ...names.map((n) => h("option", { value: n }, n))));
  sel.value = "";
}
let examples: string[] = [];
let timelineCommands = ""; // the commands the time line shown was made from
/** A program's commands without its comments and blank lines (what the arm is sent). */
const commandsOf = (text: string) => text.split("\n").map((l) => l.replace(/#.*/, "").trim()).filter((l) => l).join("\n");
let exercises: string[] = [];
const exerciseLabel = (file: string) => file.replace(/\.articula$/, "").replace(/-/g, " ");

/** The program's text and file name (from a file, an example, the blocks, a project). */
/** A line added at the end of the program (the IK panel's straight line without an arm). */
/** The simulated world's speed: the select beside Run, first from ?speed= in the address (one of
 * its values: 0.25, 0.5, 1, 2 or 4); the engine (the model's playing, the live physics) and the
 * virtual Nano (panels/arm.ts) follow it through the Editor. */
function initSpeed(): void {
  const select = $("play-speed") as HTMLSelectElement;
  const values = [...select.options].map((o) => o.value);
  const wanted = new URLSearchParams(location.search).get("speed");
  if (wanted !== null) {
    if (values.includes(wanted)) select.value = wanted;
    else banner(`The address asks for speed=${wanted.slice(0, 24)}${wanted.length > 24 ? "…" : ""}: the speeds are ${values.join(", ")} ` +
      "times real time. The world runs in real time.");
  }
  const apply = () => {
    s.editor.speed = playSpeed();
    s.engine.send({ type: "speed", speed: s.editor.speed });
    s.editor.signals.speedChanged.dispatch(s.editor.speed);
  };
  s.editor.speed = playSpeed();
  select.addEventListener("change", apply);
}

/** The engine is ready: it runs at the page's speed. */
export function programReady(): void {
  if (s.editor.speed !== 1) s.engine.send({ type: "speed", speed: s.editor.speed });
}

export function appendProgramLine(line: string): void {
  const ed = editor();
  ed.value = (ed.value && !ed.value.endsWith("\n") ? ed.value + "\n" : ed.value) + line + "\n";
  ed.dispatchEvent(new Event("input"));
}

function setProgram(name: string, text: string): void {
  if (text !== editor().value) breakpoints.clear(); // another program: its own breakpoints
  editor().value = text;
  currentProgram = name;
  programReport.programName = name;
  editorChanged();
}

function load(): void {
  s.engine.send({ type: "program_load", text: editor().value, name: currentProgram });
}

function editorChanged(): void {
  hoverRow = -1; // the text changed: the line under the pointer may say something else
  const ed = editor();
  const n = ed.value.split("\n").length;
  fill($("gutter"), ...Array.from({ length: n }, (_, i) => h("div", null, i + 1)));
  for (const b of [...breakpoints]) if (b > n) breakpoints.delete(b);
  showBreaks();
  $("gutter").scrollTop = ed.scrollTop;
  if (s.editor.timeline && commandsOf(ed.value) !== timelineCommands) {
    // what was worked out for the text before is not this text's: no old result on screen
    // (the same commands written again, as the blocks write them, keep it)
    s.editor.timeline = null;
    s.plots.clear();
    $("scrub-row").hidden = true;
    s.view.showPaths([], []);
    programReport.paths = { points: 0, lines: 0, worstMm: 0 };
    programStatus("Changed: Play works it out and runs it.");
  }
  s.editor.signals.changed.dispatch("program");
}

function highlightLine(line: number, error: boolean): void {
  const ed = editor();
  if (line > 0 && line !== lineShown) {
    // keep the line in sight: scroll the editor when it leaves the visible part
    const lh = parseFloat(getComputedStyle(ed).lineHeight) || 18;
    const top = (line - 1) * lh, view = ed.clientHeight;
    if (top < ed.scrollTop || top + lh > ed.scrollTop + view) ed.scrollTop = Math.max(0, top - view / 3);
    $("gutter").scrollTop = ed.scrollTop;
  }
  lineShown = line;
  const bar = $("current-line");
  bar.hidden = line <= 0;
  bar.classList.toggle("error", error);
  positionLine();
}

function positionLine(): void {
  const ed = editor();
  const lh = parseFloat(getComputedStyle(ed).lineHeight) || 18;
  const pad = parseFloat(getComputedStyle(ed).paddingTop) || 0;
  $("current-line").style.top = `${pad + (lineShown - 1) * lh - ed.scrollTop}px`;
  $("current-line").style.height = `${lh}px`;
}

/** The panel's status: a sentence, and the refused lines under it. */
function programStatus(text: string, rejected: string[] = [], bad = false): void {
  const el = $("program-status");
  if (!text && !rejected.length) fill(el); // nothing to say: the status goes
  else fill(el, h("div", null, text), ...rejected.map((r) => h("div", { class: "rejected" }, r)));
  el.className = `status ${bad ? "bad" : ""}`;
}

/** Where the time line's clock is: the running line, the playhead, the status under the view. */
export function showTime(p: PoseMsg): void {
  showWatch(p);
  if (p.t === undefined) return;
  const scrub = $("scrub") as HTMLInputElement;
  if (document.activeElement !== scrub) scrub.value = String(p.t);
  $("scrub-t").textContent = `${p.t.toFixed(2)} s`;
  s.plots.playhead(p.t);
  s.editor.signals.lineRunning.dispatch({ line: p.line ?? 0, refused: false });
  const err = p.error_mm !== undefined ? `, quantization error ${p.error_mm.toFixed(3)} mm` : "";
  $("view-status").textContent = `t = ${p.t.toFixed(2)} s, line ${p.line ?? 0}${err}${p.steps ? `, steps ${p.steps.join(" ")}` : ""}`;
}

/** The watch: the joints, the tool point (the pen's tip with a pen), the gripper, and the line's
 * whole-step error, at the instant shown (an arm's own, when it is connected, beside the model's). */
function showWatch(p: PoseMsg): void {
  const r = s.editor.robot;
  if (!r) return;
  if (!s.editor.timeline && !programReport.pausedAt && !armProgram()) return void fill($("watch")); // nothing to debug
  const f = (v: number, d = 1) => v.toFixed(d);
  const rows: [string, string][] = [
    ["joints", `${p.q.map((v) => f(v)).join("  ")}`],
    [p.tip ? "pen tip" : "tool", `${(p.tip ?? p.tool.xyz).map((v) => f(v)).join("  ")} mm`],
  ];
  if (r.gripper) rows.push(["gripper", `${f(p.gripper, 0)} % open`]);
  if (p.line) rows.push(["line", `${p.line}`]);
  // how far the whole steps put the tool from where the exact angles would
  if (p.line && p.error_mm !== undefined) rows.push(["whole-step error", `${f(p.error_mm, 3)} mm`]);
  const st = s.editor.armConnected ? s.editor.arm.pose() : null;
  if (st) rows.push(["the arm", `${st.map((v) => f(v)).join("  ")}`]);
  programReport.watch = Object.fromEntries(rows);
  fill($("watch"), ...rows.map(([k, v]) => h("span", null, h("b", null, k), ` ${v}`)));
}

export const programHandlers = {
  timeline(m: TimelineMsg): void {
    s.editor.timeline = m;
    timelineCommands = commandsOf(editor().value);
    programReport.programError = "";
    s.plots.show(m);
    // The path the tool will take, every step, over the straight lines the program asks for.
    const path: number[] = [];
    const lines: number[][] = [];
    let worst = 0;
    let before: number[] | null = m.start_tool ?? null; // the tool where the last action left it
    for (const r of m.records) {
      if (r.reply !== "ok") continue;
      if (r.path?.length) {
        if (!path.length && before) path.push(...before);
        path.push(...r.path);
      }
      before = r.tool;
      if (r.straight) {
        lines.push([...r.straight.from, ...r.straight.to]);
        worst = Math.max(worst, r.straight.error_mm);
      }
    }
    s.view.showPaths(path, lines);
    programReport.paths = { points: path.length / 3, lines: lines.length, worstMm: worst };
    // a refusal's note says why (the motor and its range, how far a point is out of reach)
    const why = (r: TimelineRecord) => (r.note ? ` (${r.note.replace(/^.*?nothing changes; /, "")})` : "");
    for (const r of m.records) if (r.reply !== "ok") s.editor.signals.lineRefused.dispatch({ line: r.line, message: `the arm refuses this: ${r.reply}, ${r.error}${why(r)}` });
    const rejected = m.records.filter((r) => r.reply !== "ok")
      .map((r) => `line ${r.line}: ${r.command} → error:${r.code}, ${r.error}: nothing moves${why(r)}`);
    if (forArm) {
      forArm = false;
      return;
    }
    programStatus(`${m.records.length} commands, ${m.summary.rejected ?? 0} rejected` +
      (m.summary.worst_error_mm !== undefined ? `, worst quantization error ${m.summary.worst_error_mm.toFixed(3)} mm` : "") +
      (lines.length ? `, ${lines.length} straight line${lines.length > 1 ? "s" : ""}: the tool within ${worst.toFixed(2)} mm of ${lines.length > 1 ? "them" : "it"} at every step` : "") +
      `, ${m.duration.toFixed(2)} s` +
      (s.editor.armConnected ? ". On the model only: the arm did not move (tick “on the arm” beside Run to drive it)" : ""), rejected);
    ($("scrub") as HTMLInputElement).max = String(m.duration);
    $("scrub-row").hidden = false;
    if (autoplay) {
      s.engine.send({ type: "play", speed: playSpeed(), breaks: autoplay });
      autoplay = null;
    }
  },
  playing(m: { playing: boolean; paused_at?: number; ended?: boolean; t: number }): void {
    s.editor.playing = m.playing;
    $("run").classList.toggle("active", m.playing);
    programReport.pausedAt = !m.playing && m.paused_at && !m.ended ? m.paused_at : 0;
    if (programReport.pausedAt) {
      s.editor.signals.lineRunning.dispatch({ line: m.paused_at!, refused: false });
      programStatus(`Paused after line ${m.paused_at} at ${m.t.toFixed(2)} s${breakpoints.has(m.paused_at!) ? " (a breakpoint)" : ""}: ` +
        "Run goes on, Step runs one line, the time line scrubs.");
    }
  },
  program_error(m: { message: string; line: number; problems?: { line: number; problem: string }[] }): void {
    programReport.programError = m.message;
    // the program on screen: its lines, not a file's name; every line that cannot be read at once
    const problems = m.problems?.length ? m.problems : [{ line: m.line, problem: m.message.replace(/^.*?:\d+: /, "") }];
    const said = problems.map((p) => (p.line > 0 ? `line ${p.line}: ${p.problem}` : m.message));
    if (said.length === 1) programStatus(said[0], [], true);
    else programStatus(`${said.length} lines cannot be read; nothing ran. Mend them and Run again:`, said, true);
    s.editor.signals.lineRunning.dispatch({ line: m.line, refused: true });
    const gutter = $("gutter").children;
    problems.forEach((p, k) => {
      const number = gutter[p.line - 1] as HTMLElement | undefined; // its number marked until the text changes
      if (number) (number.classList.add("refused"), (number.title = said[k]));
      if (p.line > 0) s.editor.signals.lineRefused.dispatch({ line: p.line, message: said[k] }); // from blocks: on the block it came from
    });
  },
  program_text(m: { name: string; text: string }): void {
    setProgram(m.name, m.text);
    // an example made for a scene (grasp-and-lift.arm, push.arm): its objects come with it
    const stem = m.name.replace(/\.(arm|robosim)$/, "");
    if (s.editor.scene?.scenes.includes(stem) && s.editor.scene.name !== stem) {
      s.engine.send({ type: "scene", name: stem });
      programStatus(`The physics is on, with the scene "${stem}" this program is made for: its objects are in the view.`);
    }
    if (s.editor.blocks.mode() === "blocks") s.editor.blocks.fromText();
  },
  teach(m: { line: string; kind: string; q: number[]; xyz?: number[] }): void {
    const name = ($("record-name") as HTMLInputElement).value.trim().replace(/[#\n]/g, " ").slice(0, 40);
    if (s.editor.blocks.mode() === "blocks") {
      s.editor.blocks.record(m, name);
    } else {
      s.editor.taught = m.line;
      const ed = editor();
      const line = name && !m.line.includes("\n") ? `${m.line}  # ${name}` : m.line;
      ed.value = ed.value.replace(/\s*$/, "") + (ed.value.trim() ? "\n" : "") + line + "\n";
      editorChanged();
    }
    ($("record-name") as HTMLInputElement).value = "";
    const from = s.editor.armConnected ? "the arm's pose" : "the pose";
    programStatus(`recorded ${from}${name ? ` as “${name}”` : ""}: ${m.line.replace(/\n/g, " ")}`);
  },
};

/** A new robot: its plots and time line start afresh. */
function resetProgramView(): void {
  s.editor.timeline = null;
  s.plots.clear();
  $("scrub-row").hidden = true;
}
