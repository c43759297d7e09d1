// Projects: what is on screen is a project, kept in the browser as it changes (within a second
// of the last change), brought back by a reload, listed (new, open, rename, duplicate, delete
// with undo), saved as one .articula file and opened from one (or dropped on the page), shared
// as a link that holds it all. An exercise is a project with a goal: Check says which parts
// are met. Every file, link and stored record is untrusted: project/document.ts reads it.
import type { Studio } from "../page/context";
import { $, banner, download, fill, h, setOptions } from "../page/dom";
import { hook } from "../page/hook";
import { LINK_KEY, MAX_FILE_BYTES, MAX_LINK, ProjectError, newProject, parseProject, projectFragment, projectOfFragment, readProject } from "../project/document";
import type { DrawingPart, Experiment, Goal, GoalPart, Project } from "../project/document";
import { ProjectStore, newId } from "../project/store";
import type { Stored } from "../project/store";
import type { Editor } from "../editor/editor";
import { ProjectEdit, changedParts, describeChange } from "../editor/project-edit";

const SAVE_AFTER_MS = 500; // a save this long after the last change
const SESSION_KEY = "articula.project"; // this tab's project (a reload reopens it)

let s: Studio;
const store = new ProjectStore();
let current: { id: string; rev: number; doc: Project } = { id: newId(), rev: 0, doc: newProject("My project") };
let applying = true; // a project is being put on screen: its own changes are not edits
let timer = 0;
let pendingApply: Project | null = null;
let reveal: (id: string) => void = () => undefined;
let editor: Editor | null = null;
let copyTimer = 0;
let checkedText: string | null = null; // the program the exercise's result shown is for
// The document as of the history's last step (null until the project is on screen): an edit is
// what differs from it (editor/project-edit.ts).
let recorded: Project | null = null;

/** The project to start with, before the engine starts (it loads the project's robot first). */
export async function chooseProject(params: URLSearchParams): Promise<{ robot?: string; scene?: string }> {
  await store.open();
  store.onOtherTab = otherTabSaved;
  hook.project.persistent = store.persistent;
  let note = "";
  const fromLink = location.hash.includes(LINK_KEY);
  let chosen: Project | null = null;
  if (fromLink) {
    try {
      chosen = await projectOfFragment(location.hash);
      chosen.name = `${chosen.name} (from a link)`;
    } catch (e) {
      note = `This link's project cannot be opened: ${(e as Error).message}. Nothing you saved has changed.`;
    }
    history.replaceState(null, "", location.pathname + location.search);
  }
  if (!chosen) {
    const mine = sessionGet();
    const records = await store.list().catch(() => [] as Stored[]);
    const named = params.has("robot") || params.has("scene");
    const rec = mine ? records.find((r) => r.id === mine) : named ? undefined : records[0];
    if (rec) {
      try {
        chosen = readProject(rec.doc);
        current = { id: rec.id, rev: rec.rev, doc: chosen };
      } catch (e) {
        note = `The saved project "${rec.name}" cannot be read (${(e as Error).message}): a new project is open, and "${rec.name}" is kept as it was.`;
        chosen = null;
      }
    }
  }
  if (chosen && current.doc !== chosen) current = { id: newId(), rev: 0, doc: chosen };
  if (!chosen) current = { id: newId(), rev: 0, doc: newProject(await freshName(), params.get("robot") ?? "mk2plus", params.get("scene") ?? "") };
  sessionSet(current.id);
  if (note) setTimeout(() => banner(note), 0);
  if (!store.persistent) setTimeout(() => banner("This browser keeps nothing for this page (private mode, or storage turned off): save your project as a file (Projects) before you close it.", "info"), 0);
  pendingApply = current.doc;
  showName();
  const d = current.doc;
  return { robot: "shipped" in d.robot ? d.robot.shipped : undefined, scene: d.scene || undefined };
}

export function initProjects(studio: Studio, program: { reveal: (id: string) => void }): void {
  s = studio;
  const ed = s.editor;
  editor = ed;
  ed.signals.robotShown.add(projectRobotShown);
  ed.busy = () => applying || opening > 0;
  ed.signals.exerciseWanted.add((name) => void openExercise(name));
  ed.signals.settle.add(() => {
    if (!applying && hook.project.dirty) noteEdit(capture());
  });
  reveal = program.reveal;
  $("projects-button").onclick = () => {
    listWanted = true;
    void openList();
  };
  $("projects-close").onclick = () => closeList();
  $("project-new").onclick = () => void startNew();
  $("project-save-file").onclick = saveFile;
  $("project-open-file").onclick = () => $("project-file").click();
  $("project-file").addEventListener("change", (e) => {
    const f = (e.target as HTMLInputElement).files?.[0];
    (e.target as HTMLInputElement).value = "";
    if (f) void openFile(f);
  });
  $("exercise-select").addEventListener("change", (e) => {
    const name = (e.target as HTMLSelectElement).value;
    (e.target as HTMLSelectElement).value = "";
    if (name) void openExercise(name);
  });
  $("share-button").onclick = () => void share();
  $("share-close").onclick = () => ($("share-dialog") as HTMLDialogElement).close();
  $("share-copy").onclick = async () => {
    const t = $("share-link") as HTMLTextAreaElement;
    const b = $("share-copy") as HTMLButtonElement;
    t.select();
    // said on the button: copied, or (no clipboard for this page: plain http, a browser's
    // setting) selected for Ctrl+C
    let copied = false;
    try {
      if (navigator.clipboard) {
        await navigator.clipboard.writeText(t.value);
        copied = true;
      }
    } catch {
      copied = false;
    }
    if (!copied) {
      try {
        copied = document.execCommand("copy");
      } catch {
        copied = false;
      }
    }
    hook.shareCopied = copied ? "copied" : "selected";
    b.textContent = copied ? "✓ Copied" : "Selected: press Ctrl+C";
    b.classList.toggle("done", copied);
    clearTimeout(copyTimer);
    copyTimer = window.setTimeout(() => {
      b.textContent = "Copy the link";
      b.classList.remove("done");
    }, 2500);
  };
  $("exercise-check").onclick = () => void check();
  s.editor.signals.changed.add(projectChanged); // autosave: whatever changed, saved within a second
  let asked = 0;
  $("exercise-answer").addEventListener("input", () => { // the target follows what the student types
    clearTimeout(asked);
    asked = window.setTimeout(() => current.doc.goal && void showDrawingTarget(current.doc.goal), 250);
  });
  // a .articula file dropped anywhere on the page opens as a project
  window.addEventListener("dragover", (e) => {
    if (e.dataTransfer?.types.includes("Files")) e.preventDefault();
  });
  window.addEventListener("drop", (e) => {
    const f = e.dataTransfer?.files?.[0];
    if (!f) return;
    e.preventDefault();
    if (/\.(articula|json)$/i.test(f.name)) void openFile(f);
  });
  window.addEventListener("keydown", (e) => {
    if (e.key !== "Escape") return;
    closeList();
    for (const id of ["share-dialog", "code-dialog"]) ($(id) as HTMLDialogElement).close();
  });
  window.addEventListener("pagehide", () => void saveNow());
  document.addEventListener("visibilitychange", () => document.visibilityState === "hidden" && void saveNow());
  fetch(new URL("data/index.json", document.baseURI)).then((r) => r.json()).then((idx: { exercises?: string[] }) => {
    setOptions($("exercise-select") as HTMLSelectElement, [{ value: "", label: "exercises…" }, ...(idx.exercises ?? [])]);
  }).catch(() => undefined);
}

/** The robot shown is the engine's first: put the rest of the project on screen. */
function projectRobotShown(): void {
  const d = pendingApply;
  if (!d) return;
  pendingApply = null;
  applying = true;
  // the camera as it was (shown where a new robot would be framed), else the robot framed
  s.editor.keptView = d.view ?? null;
  if (d.view) s.view.setViewpoint(d.view);
  if ("file" in d.robot) {
    const f = d.robot.file;
    const files = d.robot.meshes.map((m) => ({ name: m.name, data: fromBase64(m.data).buffer }));
    s.engine.send({ type: "load_robot", text: f.text, filename: f.name, legacy: f.legacy, scale: f.scale, files }, files.map((x) => x.data as ArrayBuffer));
  }
  s.editor.program.set(d.program.text, d.program.name);
  s.editor.paper.set(d.paper ?? null);
  s.editor.blocks.setMode(d.program.mode, true);
  s.editor.blocks.load(d.program.blocks); // none: an empty workspace, not the last project's blocks
  if (d.pose) {
    s.engine.send({ type: "set_joints", q: d.pose.q });
    if (hook.robot?.gripper) s.engine.send({ type: "gripper", percent: d.pose.gripper });
  }
  showGoal(d.goal);
  s.editor.signals.experimentOpened.dispatch(d.experiment ?? null);
  updateHook();
  // what the engine answers to these is the project as it was, not an edit; the camera last,
  // once a new robot's first pose has framed it
  s.engine.call({ type: "sync" }).catch(() => undefined).then(blocksSettled).finally(() => {
    applying = false;
    if (undoing) {  // an undo or redo that changed the robot: the rest is on screen now
      undoing = false;
      recorded = undoTarget ? capture() : null;
      edited();
    } else {
      recorded = capture();
    }
    hook.history.ready = recorded !== null;
    editor?.settled();
  });
}

// A step of the history: `doc`'s history parts on screen, the pose and the camera as they are.
let undoing = false;
let undoTarget: Project | null = null;
function showEdit(doc: Project): void {
  const now = capture();
  current = { ...current, doc: { ...current.doc, robot: doc.robot, scene: doc.scene, program: doc.program, goal: doc.goal,
    experiment: doc.experiment } };
  applying = true;
  const parts = changedParts(now, doc);
  if (parts.includes("the scene")) s.engine.send({ type: "scene", name: doc.scene || null });
  if (parts.includes("the robot")) {
    undoing = true;
    undoTarget = doc;
    pendingApply = { ...current.doc, pose: null, view: s.view.viewpoint() };
    if ("shipped" in doc.robot) s.engine.send({ type: "load_robot", name: doc.robot.shipped });
    else projectRobotShown();
    return;
  }
  s.editor.program.set(doc.program.text, doc.program.name);
  s.editor.blocks.setMode(doc.program.mode, true);
  if (JSON.stringify(now.program.blocks) !== JSON.stringify(doc.program.blocks)) s.editor.blocks.load(doc.program.blocks);
  if (parts.includes("the exercise")) showGoal(doc.goal);
  if (parts.includes("the measurements")) s.editor.signals.experimentOpened.dispatch(doc.experiment ?? null);
  updateHook();
  s.engine.call({ type: "sync" }).catch(() => undefined).then(blocksSettled).finally(() => {
    applying = false;
    recorded = capture();  // (the text the blocks make, as they make it)
    hook.history.ready = true;
    edited();
    editor?.settled();
  });
}

// Once blocks put on screen have made their program (Blockly reports its changes a moment later,
// the blocks panel compiles 150 ms after the last): what they make is part of what was applied.
async function blocksSettled(): Promise<void> {
  await new Promise((r) => setTimeout(r, 30));
  for (let i = 0; i < 60 && hook.blocksPending; i++) await new Promise((r) => setTimeout(r, 50));
}

// What an undo or a redo put on screen is the project now: saved as an edit would be.
function edited(): void {
  edits++;
  hook.project.dirty = true;
  clearTimeout(timer);
  timer = window.setTimeout(() => void saveNow(), SAVE_AFTER_MS);
}

// The project as captured: a step of the history if its history parts changed.
function noteEdit(doc: Project): void {
  if (!recorded || !editor) return;
  if (!describeChange(recorded, doc)) return;
  editor.history.record(new ProjectEdit(recorded, doc, showEdit));
  recorded = doc;
}

/** The experiment's measurements, kept with the project. */
export function setProjectExperiment(e: Experiment): void {
  current = { ...current, doc: { ...current.doc, experiment: e } };
  projectChanged();
}

// Something on screen changed (the Editor's `changed`): saved within a second.
function projectChanged(): void {
  // an exercise's result is for the program that was checked: gone once it changes
  if (checkedText !== null && s.editor.program.text() !== checkedText) {
    checkedText = null;
    hook.exercise = null;
    fill($("exercise-result"));
  }
  if (applying) return;
  clearTimeout(timer);
  edits++;
  hook.project.dirty = true;
  timer = window.setTimeout(() => void saveNow(), SAVE_AFTER_MS);
}

function capture(): Project {
  const d = current.doc;
  const r = hook.robot;
  const stem = r?.source.split("/").pop()?.replace(/\.json$/, "") ?? "";
  let robot: Project["robot"] = d.robot;
  // a shipped robot is read from /robots/; a file of the same name the user opened is not it
  if (r && r.robots.includes(stem) && r.source === `/robots/${stem}.json`) robot = { shipped: stem };
  else if (s.editor.robotFile) robot = s.editor.robotFile;
  return {
    ...d, robot, scene: hook.scene?.name ?? "",
    program: { mode: s.editor.blocks.mode(), name: s.editor.program.name(), text: s.editor.program.text(),
      blocks: s.editor.blocks.mode() === "blocks" || d.program.blocks ? s.editor.blocks.json() : null },
    pose: hook.pose ? { q: hook.pose.q, gripper: hook.pose.gripper } : d.pose,
    view: s.view.viewpoint(),
    paper: s.editor.paper.get(),
  };
}

// Saves one after the other: a save that began before the last one ended would go over a
// revision this tab no longer holds, and fork the tab's own project as "(other tab)".
let saving: Promise<void> = Promise.resolve();
let edits = 0; // changes so far: a change made while a save is under way keeps the project dirty
function saveNow(): Promise<void> {
  saving = saving.then(saveOnce, saveOnce);
  return saving;
}

async function saveOnce(): Promise<void> {
  clearTimeout(timer);
  if (applying || !hook.project.dirty) return;
  if (s.editor.blocks.dragging()) { // mid-drag: the edit is the drag's end (one step, not two)
    timer = window.setTimeout(() => void saveNow(), SAVE_AFTER_MS);
    return;
  }
  const t0 = performance.now();
  const editsSaved = edits;
  const doc = capture();
  noteEdit(doc);
  const tCaptured = performance.now();
  try {
    const res = await store.save(current.id, current.rev, doc);
    if (res.forked) banner(`This project was changed in another tab: your work here is saved as "${doc.name} (other tab)", and the other tab's is kept too.`, "info");
    current = { id: res.id, rev: res.rev, doc: res.forked ? { ...doc, name: `${doc.name} (other tab)` } : doc };
    sessionSet(current.id);
    hook.project.dirty = edits !== editsSaved;
    if (hook.project.dirty) timer = window.setTimeout(() => void saveNow(), SAVE_AFTER_MS);
    hook.project.saves++;
    hook.project.saveMs.push(tCaptured - t0 + store.lastPutMs); // main-thread time: the capture and the store's copy
    if (hook.project.saveMs.length > 100) hook.project.saveMs.shift();
    hook.project.savedAt = Date.now();
    $("project-saved").textContent = store.persistent ? "saved" : "not kept (save a file)";
    $("project-saved").className = "project-saved";
  } catch (e) {
    const quota = (e as Error)?.name === "QuotaExceededError" || /quota/i.test(String((e as Error)?.message));
    hook.project.saveError = quota ? "quota" : String((e as Error)?.message ?? e);
    $("project-saved").textContent = "not saved";
    $("project-saved").className = "project-saved bad";
    banner(quota
      ? "Not saved: this browser has no room left for the studio. Your last save is kept; save the project as a file (Projects) or delete old projects."
      : `Not saved: the browser's store failed (${(e as Error)?.message ?? e}). Your last save is kept; save the project as a file.`);
  }
  updateHook();
  showName();
}

function updateHook(): void {
  const d = current.doc;
  Object.assign(hook.project, {
    id: current.id, name: d.name, robot: "shipped" in d.robot ? d.robot.shipped : d.robot.file.name,
    program: s.editor.program.text(), blocks: s.editor.blocks.json(), mode: s.editor.blocks.mode(), rev: current.rev,
    goal: d.goal,
  });
}

function showName(): void {
  $("project-name").textContent = current.doc.name;
  $("project-name").title = `${current.doc.name}: the project shown, kept in this browser as you work`;
}

async function freshName(): Promise<string> {
  const names = new Set((await store.list().catch(() => [])).map((r) => r.name));
  for (let i = 1; ; i++) if (!names.has(`Project ${i}`)) return `Project ${i}`;
}

/** Opens `doc` as the project on screen (a new id unless `id` is given): one step of the
 * history, whose undo opens the project that was on screen again. */
async function show(doc: Project, id = newId(), rev = 0): Promise<void> {
  await saveNow();
  if (editor && recorded && !applying) {
    const before = { id: current.id, doc: capture() }, after = { id, doc };
    editor.history.record({ name: `opening "${doc.name}"`, undo: () => void reopen(before), redo: () => void reopen(after) });
  }
  await put(doc, id, rev);
}

// A project of the history on screen again: as its store keeps it (its latest revision), else
// as it was when it was left.
// A project being opened by an undo or a redo: its record read and the current project saved
// before it is put on screen. Undo and redo wait for it (a redo taken meanwhile was put on
// screen first, and then covered by the project still opening).
let opening = 0;

async function reopen(p: { id: string; doc: Project }): Promise<void> {
  opening++;
  hook.history.ready = false;
  try {
    const rec = await store.get(p.id).catch(() => undefined);
    let doc = p.doc;
    try {
      if (rec) doc = readProject(rec.doc);
    } catch {
      // (unreadable now: the copy the history kept)
    }
    await saveNow();
    await put(doc, p.id, rec?.rev ?? 0);
  } finally {
    opening--;
    if (!applying) editor?.settled();
  }
}

async function put(doc: Project, id: string, rev: number): Promise<void> {
  current = { id, rev, doc };
  sessionSet(id);
  pendingApply = doc;
  applying = true;
  recorded = null;  // set again once it is on screen (projectRobotShown)
  hook.history.ready = false;
  undoing = false;
  showName();
  const robot = "shipped" in doc.robot ? doc.robot.shipped : null;
  s.engine.send({ type: "scene", name: doc.scene || null });
  if (robot) s.engine.send({ type: "load_robot", name: robot });
  else projectRobotShown();
  if (rev === 0) {
    hook.project.dirty = true;
    setTimeout(() => {
      applying = false;
      void saveNow();
      editor?.settled();
    }, SAVE_AFTER_MS * 2);
  }
}

async function startNew(): Promise<void> {
  closeList();
  await show(newProject(await freshName()));
}

let listWanted = false; // the list is asked for (and not closed since): a slow listing must not reopen it

function closeList(): void {
  listWanted = false;
  ($("projects-dialog") as HTMLDialogElement).close();
}

async function openList(): Promise<void> {
  await saveNow();
  const list = $("project-list");
  const records = await store.list();
  fill(list, ...records.map((rec) => {
    let robot = "";
    try {
      const d = readProject(rec.doc);
      robot = "shipped" in d.robot ? d.robot.shipped : d.robot.file.name;
    } catch {
      robot = "cannot be read";
    }
    const when = new Date(rec.updated).toLocaleString(hook.language || undefined);
    const openB = h("button", { class: "primary", title: "Open this project" }, "Open");
    const renameB = h("button", { title: "Give it another name" }, "Rename");
    const dupB = h("button", { title: "A copy of it" }, "Duplicate");
    const delB = h("button", { title: "Delete it (you can undo)" }, "Delete");
    openB.onclick = () => void openRecord(rec);
    renameB.onclick = () => void rename(rec);
    dupB.onclick = () => void duplicate(rec);
    delB.onclick = () => void remove(rec);
    return h("li", { class: rec.id === current.id ? "current" : "" },
      h("div", { class: "project-info" }, h("b", null, rec.name), h("span", { class: "note" }, ` ${robot}, ${when}`)),
      h("div", { class: "row buttons" }, openB, renameB, dupB, delB));
  }));
  const d = $("projects-dialog") as HTMLDialogElement;
  if (listWanted && !d.open) d.show();
}

async function openRecord(rec: Stored): Promise<void> {
  closeList();
  try {
    const doc = readProject(rec.doc);
    await show(doc, rec.id, rec.rev);
  } catch (e) {
    banner(`The project "${rec.name}" cannot be opened: ${(e as Error).message}. It is kept as it was.`);
  }
}

async function rename(rec: Stored): Promise<void> {
  const name = prompt("The project's new name:", rec.name);
  if (name === null || !name.trim()) return;
  const clean = name.trim().slice(0, 200);
  if (rec.id === current.id) {
    current.doc = { ...capture(), name: clean };
    hook.project.dirty = true;
    await saveNow();
  } else {
    const doc = readProject(rec.doc);
    await store.save(rec.id, rec.rev, { ...doc, name: clean });
  }
  showName();
  await openList();
}

async function duplicate(rec: Stored): Promise<void> {
  const doc = rec.id === current.id ? capture() : readProject(rec.doc);
  await store.save(newId(), 0, { ...doc, name: `${doc.name} (copy)` });
  await openList();
}

async function remove(rec: Stored): Promise<void> {
  await store.remove(rec.id);
  const undo = h("button", { class: "primary" }, "Undo");
  undo.onclick = async () => {
    await store.restore(rec);
    $("banner").hidden = true;
    hook.project.lastDeleted = "";
    if (listWanted) await openList();
  };
  hook.project.lastDeleted = rec.name;
  banner(`Deleted "${rec.name}". `, "info");
  $("banner-text").append(undo);
  if (rec.id === current.id) await show(newProject(await freshName()));
  await openList();
}

function saveFile(): void {
  const doc = capture();
  download(`${doc.name.replace(/[^\w.-]+/g, "_") || "project"}.articula`, JSON.stringify(doc, null, 1), "application/json");
}

async function openFile(f: File): Promise<void> {
  closeList();
  if (f.size > MAX_FILE_BYTES) return banner(`${f.name} cannot be opened: it is larger than ${MAX_FILE_BYTES / 1e6} MB. Nothing you saved has changed.`);
  try {
    const doc = parseProject(await f.text());
    await show(doc);
  } catch (e) {
    if (!(e instanceof ProjectError)) throw e;
    banner(`${f.name} cannot be opened: ${e.message}. Nothing you saved has changed.`);
  }
}

async function openExercise(name: string): Promise<void> {
  closeList();
  try {
    const r = await fetch(new URL(`data/exercises/${encodeURIComponent(name)}`, document.baseURI));
    await show(parseProject(await r.text()));
  } catch (e) {
    banner(`The exercise ${name} cannot be opened: ${(e as Error).message}`);
  }
}

async function share(): Promise<void> {
  await saveNow();
  const doc = capture();
  const d = $("share-dialog") as HTMLDialogElement;
  const fragment = await projectFragment(doc);
  const link = `${location.origin}${location.pathname}#${fragment}`;
  if (fragment.length > MAX_LINK) {
    $("share-note").textContent = `This project is too big for a link (${Math.round(fragment.length / 1000)} thousand characters, ` +
      "most of them its robot's meshes): save it as a file and send the file instead.";
    ($("share-link") as HTMLTextAreaElement).value = "";
    $("share-copy").hidden = true;
    const b = h("button", { class: "primary" }, "Save as file");
    b.onclick = saveFile;
    $("share-note").append(" ", b);
    hook.shareLink = "";
  } else {
    $("share-note").textContent = `Anyone who opens this link gets a copy of "${doc.name}" in their own browser. Nothing is uploaded: the project is in the link (${link.length.toLocaleString("en")} characters).`;
    ($("share-link") as HTMLTextAreaElement).value = link;
    $("share-copy").hidden = false;
    hook.shareLink = link;
  }
  d.show();
}

function showGoal(goal: Goal | null): void {
  $("exercise").hidden = !goal;
  fill($("exercise-result"));
  fill($("exercise-facts"));
  // the goal drawn: where the tool must go, where an object must end (a drawing's target: on the paper)
  s.view.showGoal((goal?.parts ?? []).filter((p) => p.kind !== "drawing") as Exclude<GoalPart, DrawingPart>[]);
  hook.goal = { drawn: s.view.goalShown(), facts: [] };
  const ask = goal?.parts.find((p) => p.kind === "drawing" && p.ask) as DrawingPart | undefined;
  $("exercise-ask-row").hidden = !ask;
  $("exercise-ask-label").textContent = ask ? ask.ask : "";
  if (!goal?.parts.some((p) => p.kind === "drawing")) s.editor.signals.drawingGoal.dispatch(null);
  if (!goal) return;
  reveal("exercise"); // an exercise: its goal and the program in sight
  $("exercise-title").textContent = goal.title;
  $("exercise-text").textContent = goal.text;
  void goalFacts(goal);
}

/** What the student needs to know of the objects a goal moves: their size, and how low the
 *  tool's point comes above them (a grasp too high fails only at Check, else). */
async function goalFacts(goal: Goal): Promise<void> {
  const facts: string[] = [];
  const show = () => {
    hook.goal = { drawn: s.view.goalShown(), facts };
    fill($("exercise-facts"), ...facts.map((t) => h("li", null, t)));
  };
  const reach = goal.parts.filter((p) => p.kind === "reach").length;
  if (reach) facts.push(`In the view: ${reach > 1 ? `the ${reach} numbered green balls are the points` : "the green ball is the point"}, each as wide as its tolerance.`);
  const drawing = goal.parts.find((p) => p.kind === "drawing") as DrawingPart | undefined;
  if (drawing) {
    facts.push(`On the paper (Draw and write): the faint purple line is the target. The paper lies at z ${drawing.z} mm, ` +
      `the pen is ${drawing.pen} mm long; the ink must stay within ${drawing.tolerance_mm} mm of the target and cover all of it.`);
    void showDrawingTarget(goal);
  }
  show();
  if (!goal.parts.some((p) => p.kind === "object")) return;
  const f0 = (v: number) => Math.round(v).toString();
  try {
    const r = await s.engine.call({ type: "exercise_targets", parts: goal.parts, scene: goal.scene || current.doc.scene }) as
      { objects: { name: string; size: number[]; xyz: number[]; lowest_tool_z: number | null }[] };
    if (current.doc.goal !== goal) return; // another project came meanwhile
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
async function showDrawingTarget(goal: Goal): Promise<void> {
  const part = goal.parts.find((p) => p.kind === "drawing") as DrawingPart;
  const r = await s.engine.call({ type: "exercise_targets", parts: goal.parts, scene: "", answer: answer() }) as
    { drawings: { strokes: number[][][]; z: number; pen: number; error?: string }[] };
  if (current.doc.goal !== goal) return;
  const t = r.drawings[0];
  s.editor.signals.drawingGoal.dispatch({ target: t?.strokes ?? [], z: part.z, pen: part.pen });
  hook.goal = { ...hook.goal, target: t?.strokes.length ?? 0 };
}

const answer = () => ($("exercise-answer") as HTMLInputElement).value;

async function check(): Promise<void> {
  const goal = current.doc.goal;
  if (!goal) return;
  fill($("exercise-result"), h("li", null, "checking…"));
  try {
    checkedText = s.editor.program.text();
    const r = await s.engine.call({ type: "exercise_check", parts: goal.parts, text: s.editor.program.text(), name: s.editor.program.name(),
      scene: goal.scene || current.doc.scene, answer: answer() }) as
      { parts: { label: string; met: boolean; detail: string; target?: number[][][]; ink?: number[][][] }[]; met?: boolean; error?: string };
    hook.exercise = r as unknown as typeof hook.exercise;
    if (r.error) return fill($("exercise-result"), h("li", { class: "bad" }, r.error));
    const drawn = goal.parts.findIndex((p) => p.kind === "drawing");
    if (drawn >= 0 && r.parts[drawn]?.target) { // the target and the program's ink, on the paper
      const part = goal.parts[drawn] as DrawingPart;
      s.editor.signals.drawingGoal.dispatch({ target: r.parts[drawn].target!, z: part.z, pen: part.pen, ink: r.parts[drawn].ink });
    }
    fill($("exercise-result"), h("li", { class: r.met ? "ok" : "bad" }, r.met ? "Every part is met: well done!" : "Not yet:"),
      ...r.parts.map((p) => h("li", { class: p.met ? "ok" : "bad" }, p.met ? "✓ " : "✗ ", h("b", null, p.label), `: ${p.detail}`)));
  } catch (e) {
    hook.exercise = { parts: [], met: false, error: (e as Error).message };
    fill($("exercise-result"), h("li", { class: "bad" }, (e as Error).message));
  }
}

function otherTabSaved(id: string, rev: number): void {
  if (id === current.id && rev > current.rev) hook.project.otherTab = rev;
}

function sessionGet(): string | null {
  try {
    return sessionStorage.getItem(SESSION_KEY);
  } catch {
    return null;
  }
}
function sessionSet(id: string): void {
  try {
    sessionStorage.setItem(SESSION_KEY, id);
  } catch {
    /* no storage: the project lives in memory */
  }
}

function fromBase64(s: string): Uint8Array {
  const bin = atob(s);
  return Uint8Array.from(bin, (c) => c.charCodeAt(0));
}
