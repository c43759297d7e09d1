// Articula Studio's page: panels around the 3D view. It sends intents to the engine, which
// runs in a Web Worker (engine/worker.ts: the C++ core, host library and ODE in WebAssembly) -
// "set joint 2 to 30 deg", "solve for this target", "run this program" - and draws the poses
// that come back; it never computes kinematics itself (docs/studio.md). The arm in the loop
// is the page's too (panels/arm.ts): the virtual Nano (virtual-nano/) or a Nano over Web
// Serial, which the page can flash (panels/flash.ts). No server takes part.
//
// This file only wires the parts together: the hook (page/hook.ts), the engine's client
// (page/engine-client.ts), the 3D view, the plots and one module per panel (panels/).
import { language, storage } from "./page/environment"; // first: a page must not die on its locale (uPlot reads it as it loads)
import { View } from "./view/view";
import { Plots } from "./plots";
import { startTour } from "./tour";
import { Layout } from "./layout";
import type { PoseMsg, EngineMsg } from "./engine/messages";
import { EngineClient } from "./page/engine-client";
import { $, banner } from "./page/dom";
import { exposeHook, hook, showOwn, viewOf, viewOfEngine } from "./page/hook";
import { noteError } from "./page/errors";
import type { Studio } from "./page/context";
import { armFrameDrawn, armReport, initArm, stopEverything } from "./panels/arm";
import { experimentReport, initExperiment } from "./panels/experiment";
import { flashStatus, initFlash } from "./panels/flash";
import { initWiring, wiringStatus } from "./panels/wiring";
import { drawReady, drawReport, initDraw } from "./panels/draw";
import { followTool, ikReport, initIk, setLineTargets, showIk } from "./panels/ik";
import { initJoints, showJointValues } from "./panels/joints";
import { initJog, jogReport } from "./panels/jog";
import { initPhysics, physicsReport, showPhysics, showScene } from "./panels/physics";
import { initSceneEdit, sceneEditRefused, showSceneEdit } from "./panels/scene-edit";
import { cellReport, initCell, showCell, showCellFrame, showCellRefused } from "./panels/cell";
import { appendProgramLine, ghostShown, initProgram, programHandlers, programReady, programReport, showTime } from "./panels/program";
import { blocksReport, initBlocks } from "./panels/blocks";
import { initProjects, projectsReport } from "./panels/projects";
import { exerciseReport, initExercise } from "./panels/exercise";
import { chooseProject } from "./project/autosave";
import { fitNewRobot, initRobot, robotError, robotReport, saveUrdf, showRobot } from "./panels/robot";
import { Editor } from "./editor/editor";
import { OpenProject } from "./editor/open-project";

const params = new URLSearchParams(location.search);
exposeHook();

// The engine starts first: it compiles and loads the robot in its worker while the page
// builds its 3D view.
setConn("starting the engine…", "ok");
const engine = new EngineClient();
const layout = new Layout(); // before the view: the view takes the box the layout gives it
layout.onChange = () => (hook.layout = { mode: layout.mode ?? "", plotsInTab: layout.plotsInTab, tab: layout.active });
layout.onChange();
const view = new View($("view"));
Object.assign(hook, { webgl: view.renderer !== null, language, storage: storage !== null });
const plots = new Plots($("plots"));
const editor = new Editor();
editor.project = new OpenProject(editor, engine, view);
viewOf(editor);
// The project shown first (a link's, this tab's after a reload, the last one, or a new one)
// names the robot the engine loads first.
// (The view's frame period too: a page that draws a frame every 200 ms, ?fps=5, gets the live
// physics' state at most twice a frame, not at every display frame.)
chooseProject(editor, params).then((first) => engine.start(first, view.frameMs), () =>
  engine.start({ robot: params.get("robot") ?? undefined, scene: params.get("scene") ?? undefined }, view.frameMs));
const studio: Studio = { engine, view, plots, editor };
hook.armPixels = () => view.armPixels();
hook.camera = () => view.cameraState();
hook.viewpoint = () => view.viewpoint();
hook.objectScreen = (n) => view.objectScreen(n);
hook.pointScreen = (p) => view.pointScreen(p);
hook.engineSend = (msg) => engine.post(msg);
viewOfEngine(engine);
// (the first pose shown: the page is ready; the first frame drawn with the arm in it)
let posed = false, firstFrameAt = 0;
showOwn("ready", () => posed);
showOwn("firstFrameAt", () => firstFrameAt);
showOwn("flash", () => flashStatus);
showOwn("wiring", () => wiringStatus);
// The panels' own facts in window.articula (page/reports.ts): each read from its panel's report.
showOwn("drawing", () => drawReport.drawing);
showOwn("drawings", () => drawReport.drawings);
showOwn("paper", () => drawReport.paper);
showOwn("goal", () => exerciseReport.goal);
showOwn("cell", () => cellReport);
showOwn("exercise", () => exerciseReport.exercise);
showOwn("experiment", () => experimentReport.experiment);
showOwn("ik", () => ikReport.ik);
showOwn("ikLine", () => ikReport.ikLine);
showOwn("ikUpdates", () => ikReport.ikUpdates);
showOwn("events", () => physicsReport.events);
showOwn("paths", () => programReport.paths);
showOwn("pngCaption", () => programReport.pngCaption);
showOwn("programError", () => programReport.programError);
showOwn("programName", () => programReport.programName);
showOwn("runOnArm", () => programReport.runOnArm);
showOwn("shareLink", () => projectsReport.shareLink);
showOwn("shareCopied", () => projectsReport.shareCopied);
showOwn("noteShown", () => projectsReport.noteShown);
showOwn("jog", () => jogReport);
showOwn("debug", () => ({ breaks: programReport.breaks, pausedAt: programReport.pausedAt, watch: programReport.watch }));
showOwn("robotError", () => robotReport.robotError);
showOwn("blockProblems", () => blocksReport.blockProblems);
showOwn("blockStacks", () => blocksReport.blockStacks);
showOwn("blocksCode", () => blocksReport.blocksCode);
showOwn("blocksFirstPaintMs", () => blocksReport.blocksFirstPaintMs);
showOwn("programMode", () => blocksReport.programMode);
showOwn("runningBlock", () => blocksReport.runningBlock);
showOwn("arm", () => armReport);
engine.streaming = () => !!editor.physics?.on;

engine.onReady = () => {
  setConn("engine ready", "ok");
  drawReady();
  programReady();
  engine.send({ type: "hello" });
};
engine.onFatal = (message) => {
  setConn("the engine did not start", "bad");
  banner(message);
};
engine.onMessage = handle;

initRobot(studio);
initJoints(studio);
initJog(studio);
initIk(studio);
initProgram(studio);
initPhysics(studio);
initSceneEdit(studio);
initCell(studio, { reveal: (id) => layout.reveal(id) });
initArm(studio);
initFlash(studio);
initWiring(studio);
initExperiment(studio);
initDraw(studio);
setLineTargets((line) => editor.arm.send(line), appendProgramLine);
initBlocks(studio);
initProjects(studio);
initExercise(studio, { reveal: (id) => layout.reveal(id) });
editor.project.follow(); // last: a project's parts go to panels that already follow its robot
wireHistory(editor);
view.onViewChange = () => editor.signals.changed.dispatch("view");

// Undo and redo: the buttons (a tablet has no keyboard) and Ctrl+Z, Ctrl+Shift+Z, Ctrl+Y
// everywhere on the page, the program's text and the blocks included (their own undo would
// keep a history beside this one).
function wireHistory(ed: Editor): void {
  const undo = $("undo") as HTMLButtonElement, redo = $("redo") as HTMLButtonElement;
  const show = () => {
    const h = ed.history;
    undo.disabled = !h.canUndo;
    redo.disabled = !h.canRedo;
    undo.title = h.canUndo ? `Undo: ${h.undoName} (Ctrl+Z)` : "Nothing to undo";
    redo.title = h.canRedo ? `Redo: ${h.redoName} (Ctrl+Shift+Z)` : "Nothing to redo";
  };
  ed.signals.historyChanged.add(show);
  show();
  undo.onclick = () => ed.undo();
  redo.onclick = () => ed.redo();
  window.addEventListener("keydown", (e) => {
    if (!(e.ctrlKey || e.metaKey) || e.altKey) return;
    const k = e.key.toLowerCase();
    const isUndo = k === "z" && !e.shiftKey, isRedo = (k === "z" && e.shiftKey) || (k === "y" && !e.shiftKey);
    if (!isUndo && !isRedo) return;
    e.preventDefault();
    e.stopPropagation();
    if (isUndo) ed.undo();
    else ed.redo();
  }, true);
}

function setConn(text: string, kind: "ok" | "bad"): void {
  const c = $("conn");
  c.textContent = text;
  c.className = `conn ${kind}`;
}

// What the engine says, to the panel it is for.
function handle(m: EngineMsg): void {
  switch (m.type) {
    case "robot":
      showRobot(m); // the other panels follow it (the Editor's robotShown)
      return editor.signals.changed.dispatch("robot");
    case "robot_error": return robotError(m.message);
    case "urdf": return saveUrdf(m);
    case "pose": return showPose(m);
    case "ik":
    case "jt_frame": return showIk(m);
    case "timeline": return programHandlers.timeline(m);
    case "playing": return programHandlers.playing(m);
    case "program_error": return programHandlers.program_error(m);
    case "program_text": return programHandlers.program_text(m);
    case "teach": return programHandlers.teach(m);
    case "cell": return void showCell(m);
    case "cell_frame": return showCellFrame(m);
    case "cell_refused": return showCellRefused(m);
    case "scene":
      if (cellReport.name !== null) void showCell({ type: "cell", name: null }); // (a scene, or off, closed the cell)
      showScene(m);
      showSceneEdit(m);
      return editor.signals.changed.dispatch("scene");
    case "physics": return showPhysics(m, editor.robot);
    case "sim_command":
      hook.simCommand = m.line;
      if (m.seq !== undefined && m.seq !== null) engine.replyArrived(m.seq);
      return;
    case "error":
      noteError(m.message);
      sceneEditRefused();
      engine.replyArrived();
      return banner(m.message);
  }
}

function showPose(p: PoseMsg): void {
  if (p.seq !== undefined && p.seq !== null) engine.applied(p.seq);
  if (!ghostShown()) delete p.ghost;
  view.pose(p);
  fitNewRobot();
  editor.pose = p;
  if (p.t === undefined && !editor.physics?.on) editor.signals.changed.dispatch("pose");
  if (editor.physics?.on) editor.signals.physicsTool.dispatch(p.trail ?? p.tool.xyz);
  if (!editor.robot) return;
  showJointValues(p, editor.robot);
  showTime(p);
  followTool(p.tip ?? p.tool.xyz, p.tool.rpy, !posed);
  posed = true;
}

view.onFrame = (now) => {
  hook.fps = view.fps;
  if (view.continuous) $("fps").textContent = `${view.fps} frames/s`;
  hook.framesDrawn = view.framesDrawn;
  hook.targetScreen = view.targetScreen();
  if (!firstFrameAt && editor.pose && editor.robot) firstFrameAt = now;
  hook.latency.push(...engine.drawn(now));
  armFrameDrawn(now);
};

// STOP, always: the button and Escape.
$("stop").onclick = stopEverything;
window.addEventListener("keydown", (e) => {
  if (e.key === "Escape") stopEverything();
});
// The view's keys (orbit, zoom), when no box has the keyboard.
document.addEventListener("keydown", (e) => {
  if ((e.target as HTMLElement).closest("input, textarea, select")) return;
  if (view.key(e.code)) e.preventDefault();
});
$("banner-close").onclick = () => ($("banner").hidden = true);
$("fit").onclick = () => view.fit();
$("show-axes").addEventListener("change", (e) => view.showAxes((e.target as HTMLInputElement).checked));
$("tour-button").onclick = () => startTour(true, (id) => layout.reveal(id));
// Offline use and installing as an app (sw.js keeps the whole site).
if ("serviceWorker" in navigator && !params.has("nosw")) navigator.serviceWorker.register("sw.js").catch(() => undefined);
// the tour is for a first visit to the plain page: not over a scene, an exercise or a link
if (!params.has("scene") && !location.hash.includes("project=")) startTour(false, (id) => layout.reveal(id));
