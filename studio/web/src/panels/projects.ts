// Projects: the list of the projects kept in the browser (new, open, rename, duplicate,
// delete with undo), a project saved as one .articula file and opened from one (or dropped on
// the page), shared as a link that holds it all, and the exercises to open. Opening one is the
// Editor's (editor/open-project.ts: one step of the History); keeping them is
// project/autosave.ts's. Every file is untrusted: project/document.ts reads it.
import type { Studio } from "../page/context";
import { $, banner, download, fill, h, setOptions } from "../page/dom";
import type { Reports } from "../page/reports";
import { MAX_FILE_BYTES, MAX_LINK, MAX_NOTE, ProjectError, newProject, parseProject, projectFragment, readProject } from "../project/document";
import type { Project } from "../project/document";
import { freshName, saveNow, saving, setOnSaved, store } from "../project/autosave";
import { newId } from "../project/store";
import type { Stored } from "../project/store";
import { language } from "../page/environment";

/** The Projects panel's share link (window.articula shows it; main.ts wires it). */
export const projectsReport: { shareLink: string; shareCopied: string; noteShown: string } = {
  shareLink: "", shareCopied: "", noteShown: "",
};

let s: Studio;
let copyTimer = 0;
let listWanted = false; // the list is asked for (and not closed since): a slow listing must not reopen it

const project = () => s.editor.project;
const show = (doc: Project, id?: string, rev?: number) => project().open(doc, id, rev);

export function initProjects(studio: Studio): void {
  s = studio;
  const ed = s.editor;
  ed.signals.exerciseWanted.add((name) => void openExercise(name));
  ed.signals.projectOpened.add(showName);
  ed.signals.changed.add((part) => part === "name" && showName());
  setOnSaved((ok) => {
    $("project-saved").textContent = !ok ? "not saved" : store.persistent ? "saved" : "not kept (save a file)";
    $("project-saved").className = ok ? "project-saved" : "project-saved bad";
    showName();
  });
  showName();
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
  // the teacher's note travels in the link: the link is made again as it is typed
  let noteTimer = 0;
  $("share-teacher-note").addEventListener("input", (e) => {
    ed.project.setNote((e.target as HTMLTextAreaElement).value.slice(0, MAX_NOTE));
    clearTimeout(noteTimer);
    noteTimer = window.setTimeout(() => void share(), 300);
  });
  $("teacher-note-close").onclick = () => ($("teacher-note") as HTMLDialogElement).close();
  // a project opened from a link or a file: its note first
  ed.signals.noteOpened.add(showTeacherNote);
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
    projectsReport.shareCopied = copied ? "copied" : "selected";
    b.textContent = copied ? "✓ Copied" : "Selected: press Ctrl+C";
    b.classList.toggle("done", copied);
    clearTimeout(copyTimer);
    copyTimer = window.setTimeout(() => {
      b.textContent = "Copy the link";
      b.classList.remove("done");
    }, 2500);
  };
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
    for (const id of ["share-dialog", "code-dialog", "teacher-note"]) ($(id) as HTMLDialogElement).close();
  });
  fetch(new URL("data/index.json", document.baseURI)).then((r) => r.json()).then((idx: { exercises?: string[] }) => {
    setOptions($("exercise-select") as HTMLSelectElement, [{ value: "", label: "exercises…" }, ...(idx.exercises ?? [])]);
  }).catch(() => undefined);
}

function showName(): void {
  const name = project().doc.name;
  $("project-name").textContent = name;
  $("project-name").title = `${name}: the project shown, kept in this browser as you work`;
}

async function startNew(): Promise<void> {
  closeList();
  await show(newProject(await freshName()));
}


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
    const when = new Date(rec.updated).toLocaleString(language);
    const openB = h("button", { class: "primary", title: "Open this project" }, "Open");
    const renameB = h("button", { title: "Give it another name" }, "Rename");
    const dupB = h("button", { title: "A copy of it" }, "Duplicate");
    const delB = h("button", { title: "Delete it (you can undo)" }, "Delete");
    openB.onclick = () => void openRecord(rec);
    renameB.onclick = () => void rename(rec);
    dupB.onclick = () => void duplicate(rec);
    delB.onclick = () => void remove(rec);
    return h("li", { class: rec.id === project().id ? "current" : "" },
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
  if (rec.id === project().id) {
    project().rename(clean);
    await saveNow();
  } else {
    const doc = readProject(rec.doc);
    await store.save(rec.id, rec.rev, { ...doc, name: clean });
  }
  showName();
  await openList();
}

async function duplicate(rec: Stored): Promise<void> {
  const doc = rec.id === project().id ? project().document() : readProject(rec.doc);
  await store.save(newId(), 0, { ...doc, name: `${doc.name} (copy)` });
  await openList();
}

async function remove(rec: Stored): Promise<void> {
  await store.remove(rec.id);
  const undo = h("button", { class: "primary" }, "Undo");
  undo.onclick = async () => {
    await store.restore(rec);
    $("banner").hidden = true;
    saving.lastDeleted = "";
    if (listWanted) await openList();
  };
  saving.lastDeleted = rec.name;
  banner(`Deleted "${rec.name}". `, "info");
  $("banner-text").append(undo);
  if (rec.id === project().id) await show(newProject(await freshName()));
  await openList();
}

function saveFile(): void {
  const doc = project().document();
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

/** The note a project carries (a teacher's, for whoever opens it), as text, before anything else. */
function showTeacherNote(note: string): void {
  $("teacher-note-text").textContent = note;
  projectsReport.noteShown = note;
  const d = $("teacher-note") as HTMLDialogElement;
  if (!d.open) d.show();
  ($("teacher-note-close") as HTMLButtonElement).focus();
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
  const doc = project().document();
  const noteBox = $("share-teacher-note") as HTMLTextAreaElement;
  if (document.activeElement !== noteBox) noteBox.value = doc.note ?? "";
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
    projectsReport.shareLink = "";
  } else {
    $("share-note").textContent = `Anyone who opens this link gets a copy of "${doc.name}" in their own browser. Nothing is uploaded: the project is in the link (${link.length.toLocaleString("en")} characters).`;
    ($("share-link") as HTMLTextAreaElement).value = link;
    $("share-copy").hidden = false;
    projectsReport.shareLink = link;
  }
  d.show();
}

