// The project on screen, kept in the browser as it changes: saved within a second of the last
// change (the Editor's `changed` signal), brought back by a reload (this tab's project), and
// which project a page opens first (a link's, this tab's, the last one, or a new one). Every
// link and stored record is untrusted: project/document.ts reads it.
import { banner } from "../page/dom";
import type { Editor } from "../editor/editor";
import { LINK_KEY, newProject, projectOfFragment, readProject } from "./document";
import type { Project } from "./document";
import { ProjectStore, newId } from "./store";
import type { Stored } from "./store";

const SAVE_AFTER_MS = 500; // a save this long after the last change
const SESSION_KEY = "articula.project"; // this tab's project (a reload reopens it)

/** How the keeping goes (window.articula.project shows it). */
export const saving = {
  persistent: true, // false: this browser keeps nothing (private mode, storage off)
  dirty: false, // changed since the last save
  saves: 0,
  saveMs: [] as number[], // the main thread's time of each save: the document read back and the store's copy
  savedAt: 0,
  saveError: "",
  lastDeleted: "", // the project deleted last (the list's Undo brings it back)
  otherTab: 0, // another tab saved this project, at this revision
};

export const store = new ProjectStore();
let ed: Editor;
let timer = 0;
let edits = 0; // changes so far: a change made while a save is under way keeps the project dirty
let queue: Promise<void> = Promise.resolve();
let onSaved: (ok: boolean) => void = () => undefined;
/** `f` is called after each save (true) or failed save (the projects panel shows "saved"). */
export function setOnSaved(f: (ok: boolean) => void): void {
  onSaved = f;
}

/** The project to start with, put in the Editor before the engine starts (it loads the
 * project's robot first). */
export async function chooseProject(editor: Editor, params: URLSearchParams): Promise<{ robot?: string; scene?: string }> {
  ed = editor;
  ed.project.keeper = { save: saveNow, read };
  ed.signals.changed.add(changed);
  // an undo or a redo: not saved until it is on screen and saved (a save under way when it was
  // taken does not make the project clean, and a reload meanwhile is not taken for saved)
  ed.signals.stepTaken.add(() => edited(false));
  ed.signals.projectOpened.add(() => {
    sessionSet(ed.project.id);
    if (ed.project.rev === 0) saving.dirty = true; // not kept yet: kept once on screen
  });
  window.addEventListener("pagehide", () => void saveNow());
  document.addEventListener("visibilitychange", () => document.visibilityState === "hidden" && void saveNow());
  await store.open();
  store.onOtherTab = (id, rev) => {
    if (id === ed.project.id && rev > ed.project.rev) saving.otherTab = rev;
  };
  saving.persistent = store.persistent;
  let note = "";
  let chosen: { doc: Project; id: string; rev: number } | null = null;
  if (location.hash.includes(LINK_KEY)) {
    try {
      const doc = await projectOfFragment(location.hash);
      chosen = { doc: { ...doc, name: `${doc.name} (from a link)` }, id: newId(), rev: 0 };
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
        chosen = { doc: readProject(rec.doc), id: rec.id, rev: rec.rev };
      } catch (e) {
        note = `The saved project "${rec.name}" cannot be read (${(e as Error).message}): a new project is open, and "${rec.name}" is kept as it was.`;
      }
    }
  }
  chosen ??= { doc: newProject(await freshName(), params.get("robot") ?? "mk2plus", params.get("scene") ?? ""), id: newId(), rev: 0 };
  ed.project.start(chosen.doc, chosen.id, chosen.rev);
  sessionSet(chosen.id);
  if (note) setTimeout(() => banner(note), 0);
  if (!store.persistent) setTimeout(() => banner("This browser keeps nothing for this page (private mode, or storage turned off): save your project as a file (Projects) before you close it.", "info"), 0);
  const d = chosen.doc;
  return { robot: "shipped" in d.robot ? d.robot.shipped : undefined, scene: d.scene || undefined };
}

/** A name no kept project has yet ("Project 3"). */
export async function freshName(): Promise<string> {
  const names = new Set((await store.list().catch(() => [])).map((r) => r.name));
  for (let i = 1; ; i++) if (!names.has(`Project ${i}`)) return `Project ${i}`;
}

// Something on screen changed: saved within a second (another project opened: now).
function changed(part: string): void {
  if (!ed.project.applying) edited(part === "project");
}

// The project on screen differs from the one saved: saved now, or SAVE_AFTER_MS after the last edit.
function edited(now: boolean): void {
  clearTimeout(timer);
  edits++;
  saving.dirty = true;
  if (now) void saveNow();
  else timer = window.setTimeout(() => void saveNow(), SAVE_AFTER_MS);
}

async function read(id: string): Promise<{ doc: Project; rev: number } | undefined> {
  const rec = await store.get(id);
  if (!rec) return undefined;
  try {
    return { doc: readProject(rec.doc), rev: rec.rev };
  } catch {
    return undefined; // (unreadable now: the copy the History kept)
  }
}

/** Saves what is on screen now. Saves go one after the other: a save that began before the
 * last one ended would go over a revision this tab no longer holds, and fork the tab's own
 * project as "(other tab)". */
export function saveNow(): Promise<void> {
  queue = queue.then(saveOnce, saveOnce);
  return queue;
}

async function saveOnce(): Promise<void> {
  clearTimeout(timer);
  const p = ed.project;
  if (!saving.dirty) return;
  // a project, an undo or a redo being put on screen: saved once it is there; mid-drag: the
  // edit is the drag's end (one step, not two)
  if (p.applying || ed.blocks.dragging()) {
    timer = window.setTimeout(() => void saveNow(), SAVE_AFTER_MS);
    return;
  }
  const t0 = performance.now();
  const editsSaved = edits;
  const doc = p.document();
  const tRead = performance.now();
  try {
    const res = await store.save(p.id, p.rev, doc);
    if (res.forked) banner(`This project was changed in another tab: your work here is saved as "${doc.name} (other tab)", and the other tab's is kept too.`, "info");
    p.saved(res.id, res.rev, res.forked ? { ...doc, name: `${doc.name} (other tab)` } : doc);
    sessionSet(res.id);
    saving.dirty = edits !== editsSaved;
    if (saving.dirty) timer = window.setTimeout(() => void saveNow(), SAVE_AFTER_MS);
    saving.saves++;
    saving.saveMs.push(tRead - t0 + store.lastPutMs);
    if (saving.saveMs.length > 100) saving.saveMs.shift();
    saving.savedAt = Date.now();
    onSaved(true);
  } catch (e) {
    const quota = (e as Error)?.name === "QuotaExceededError" || /quota/i.test(String((e as Error)?.message));
    saving.saveError = quota ? "quota" : String((e as Error)?.message ?? e);
    onSaved(false);
    banner(quota
      ? "Not saved: this browser has no room left for the studio. Your last save is kept; save the project as a file (Projects) or delete old projects."
      : `Not saved: the browser's store failed (${(e as Error)?.message ?? e}). Your last save is kept; save the project as a file.`);
  }
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
