// The project on screen: the Editor's document. It is put on screen part by part (the robot
// first: the engine loads it, then the program, the blocks, the paper, the pose, the goal and
// the experiment), read back from the parts as they are now (`document()`), and every change
// of its history parts is a step of the Editor's History (editor/project-edit.ts), recorded from the
// Editor's change signal once the edits pause (autosave only keeps the document). Opening
// another project (a file, a link, an exercise, the list) is one step too, whose undo opens
// the project that was on screen again. Where the document is kept (the browser's store) is
// project/autosave.ts's: it tells this module how to save and read (`keeper`).
import type { EngineClient } from "../page/engine-client";
import type { View } from "../view/view";
import { newProject } from "../project/document";
import type { Experiment, Project } from "../project/document";
import { newId } from "../project/store";
import type { Editor, Keeper, ProjectOnScreen } from "./editor";
import { ProjectEdit, changedParts, describeChange } from "./project-edit";

// An edit becomes a step of the History this long after the last change (as autosave saves it).
const NOTE_AFTER_MS = 500;

export class OpenProject implements ProjectOnScreen {
  id = newId();
  rev = 0; // the store's revision this document is saved over
  doc: Project = newProject("My project"); // as last saved or opened (`document()`: as on screen now)
  // the project as last put on screen, or saved (window.articula.project shows it: the project
  // opening is not on screen until its robot is)
  shown: { id: string; rev: number; doc: Project } = { id: this.id, rev: 0, doc: this.doc };
  // a project is being put on screen: what the page does meanwhile is not a student's edit
  applying = true;
  // the project is on screen and the History follows it: an edit now is a step (window.articula.history.ready)
  ready = false;
  keeper: Keeper = { save: async () => undefined, read: async () => undefined };
  private pending: Project | null = null; // waits for its robot to be shown
  private recorded: Project | null = null; // as of the History's last step: an edit is what differs from it
  private undoing = false; // an undo or redo that changed the robot, waiting for it
  private undoTarget: Project | null = null;
  private opening = 0; // projects being reopened by an undo or a redo

  constructor(private ed: Editor, private engine: EngineClient, private view: View) {
    // before an undo or a redo: an edit still waiting to be recorded (typing) is recorded now
    ed.signals.settle.add(() => !this.applying && this.note(this.document()));
    // an edit on screen: a step of the History once the edits pause (a burst of typing, a drag:
    // one step); what the page does while a project is put on screen is no edit
    ed.signals.changed.add(() => !this.applying && this.noteSoon());
  }

  private noteTimer = 0;
  private noteSoon(): void {
    clearTimeout(this.noteTimer);
    this.noteTimer = window.setTimeout(() => {
      if (this.applying || this.ed.blocks.dragging()) return this.noteSoon(); // (mid-drag: the edit is its end)
      this.note(this.document());
    }, NOTE_AFTER_MS);
  }

  /** A project (or an undo's or redo's) is still being put on screen. */
  get busy(): boolean {
    return this.applying || this.opening > 0;
  }

  /** Puts projects on screen from now on: called once every panel follows the robot shown
   * (a project's robot is shown first; its program, blocks and pose go to panels that know it). */
  follow(): void {
    this.ed.signals.robotShown.add(() => this.robotShown());
  }

  /** The first project, chosen before the engine starts: shown once its robot is. */
  start(doc: Project, id: string, rev: number): void {
    Object.assign(this, { doc, id, rev });
    this.pending = doc;
    this.ed.signals.changed.dispatch("name"); // (while it is put on screen: not an edit)
  }

  /** The document as on screen now: the Editor's state and its parts. */
  document(): Project {
    const d = this.doc, ed = this.ed, r = ed.robot;
    let robot: Project["robot"] = d.robot;
    // a shipped robot (the engine's word: a file of the same name the user opened is not it)
    if (r?.shipped) robot = { shipped: r.shipped };
    else if (ed.robotFile) robot = ed.robotFile;
    return {
      ...d, robot, scene: ed.scene?.name ?? "", world: ed.scene?.world ?? null, cell: ed.cell && { name: ed.cell.name, programs: [...ed.cell.programs] },
      program: { mode: ed.blocks.mode(), name: ed.program.name(), text: ed.program.text(),
        blocks: ed.blocks.mode() === "blocks" || d.program.blocks ? ed.blocks.json() : null },
      pose: ed.pose ? { q: ed.pose.q, gripper: ed.pose.gripper } : d.pose,
      view: this.view.viewpoint(),
      paper: ed.paper.get(),
    };
  }

  /** `doc` as on screen: a step of the History if its history parts changed. */
  note(doc: Project): void {
    clearTimeout(this.noteTimer);
    if (!this.recorded || !describeChange(this.recorded, doc)) return;
    this.ed.history.record(new ProjectEdit(this.recorded, doc, (d) => this.showEdit(d)));
    this.recorded = doc;
  }

  /** The store kept `doc` as revision `rev` of project `id`. */
  saved(id: string, rev: number, doc: Project): void {
    Object.assign(this, { id, rev, doc });
    this.shown = { id, rev, doc };
  }

  /** The experiment's measurements, kept with the project. */
  setExperiment(e: Experiment): void {
    this.doc = { ...this.doc, experiment: e };
    this.ed.signals.changed.dispatch("experiment");
  }

  /** A new name for the project on screen (not history). */
  /** The teacher's note the project carries (shown first when it opens from a link or a file). */
  setNote(note: string): void {
    this.doc = { ...this.document(), note };
    this.shown = { ...this.shown, doc: this.doc };
    this.ed.signals.changed.dispatch("name");
  }

  rename(name: string): void {
    this.doc = { ...this.document(), name };
    this.shown = { ...this.shown, doc: this.doc };
    this.ed.signals.changed.dispatch("name");
  }

  /** Opens `doc` as the project on screen (a new id unless `id` is given): one step of the
   * History, whose undo opens the project that was on screen again. */
  async open(doc: Project, id = newId(), rev = 0): Promise<void> {
    await this.keeper.save();
    if (this.recorded && !this.applying) {
      this.note(this.document()); // (an edit not recorded yet is a step before the opening)
      const before = { id: this.id, doc: this.document() }, after = { id, doc };
      this.ed.history.record({ name: `opening "${doc.name}"`, undo: () => void this.reopen(before), redo: () => void this.reopen(after) });
    }
    this.put(doc, id, rev);
  }

  // A project of the History on screen again: as its store keeps it (its latest revision), else
  // as it was when it was left. Undo and redo wait for it (a redo taken meanwhile was put on
  // screen first, and then covered by the project still opening).
  private async reopen(p: { id: string; doc: Project }): Promise<void> {
    this.opening++;
    this.ready = false;
    try {
      const kept = await this.keeper.read(p.id).catch(() => undefined);
      await this.keeper.save();
      this.put(kept?.doc ?? p.doc, p.id, kept?.rev ?? 0);
    } finally {
      this.opening--;
      if (!this.applying) this.ed.settled();
    }
  }

  private put(doc: Project, id: string, rev: number): void {
    Object.assign(this, { doc, id, rev });
    this.pending = doc;
    this.applying = true;
    this.recorded = null; // set again once it is on screen (robotShown)
    this.ready = false;
    this.undoing = false;
    this.ed.signals.projectOpened.dispatch(doc);
    const robot = "shipped" in doc.robot ? doc.robot.shipped : null;
    this.engine.send({ type: "scene", name: doc.scene || null, world: doc.world ?? null });
    if (robot) this.engine.send({ type: "load_robot", name: robot });
    else this.robotShown();
    if (rev === 0) { // not kept yet: kept once on screen
      setTimeout(() => {
        this.applying = false;
        this.ed.signals.changed.dispatch("project");
        this.ed.settled();
      }, 1000);
    }
  }

  // The robot shown is the one the project wants: the rest of the project on screen.
  private robotShown(): void {
    const d = this.pending;
    if (!d) return;
    this.pending = null;
    this.applying = true;
    const ed = this.ed;
    // the camera as it was (shown where a new robot would be framed), else the robot framed
    ed.keptView = d.view ?? null;
    if (d.view) this.view.setViewpoint(d.view);
    if ("file" in d.robot) {
      const f = d.robot.file;
      const files = d.robot.meshes.map((m) => ({ name: m.name, data: fromBase64(m.data).buffer }));
      this.engine.send({ type: "load_robot", text: f.text, filename: f.name, legacy: f.legacy, scale: f.scale, files }, files.map((x) => x.data as ArrayBuffer));
    }
    // a cell (several arms) with the programs the project gives them (an undo's is on its way: showEdit)
    if (d.cell && !this.undoing) this.engine.send({ type: "cell", name: d.cell.name, programs: d.cell.programs });
    // a scene of the student's own (the engine started with the shipped one it was built on)
    else if (d.world && !this.undoing) this.engine.send({ type: "scene", name: d.scene || null, world: d.world });
    ed.program.set(d.program.text, d.program.name);
    ed.paper.set(d.paper ?? null);
    ed.blocks.setMode(d.program.mode, true);
    ed.blocks.load(d.program.blocks); // none: an empty workspace, not the last project's blocks
    if (d.pose) {
      this.engine.send({ type: "set_joints", q: d.pose.q });
      if (ed.robot?.gripper) this.engine.send({ type: "gripper", percent: d.pose.gripper });
    }
    ed.signals.goalShown.dispatch(d.goal);
    // a teacher's note, first, when the project comes from a link, a file or an exercise (not yet kept)
    if (d.note && this.rev === 0 && !this.undoing) ed.signals.noteOpened.dispatch(d.note);
    ed.signals.experimentOpened.dispatch(d.experiment ?? null);
    this.shown = { id: this.id, rev: this.rev, doc: this.doc };
    // what the engine answers to these is the project as it was, not an edit
    this.settle(() => {
      if (this.undoing) { // an undo or redo that changed the robot: the rest is on screen now
        this.undoing = false;
        this.recorded = this.undoTarget ? this.document() : null;
        ed.signals.changed.dispatch("project");
      } else {
        this.recorded = this.document();
      }
      this.ready = this.recorded !== null;
    });
  }

  // A step of the History: `doc`'s history parts on screen, the pose and the camera as they are.
  private showEdit(doc: Project): void {
    const now = this.document(), ed = this.ed;
    this.doc = { ...this.doc, robot: doc.robot, scene: doc.scene, world: doc.world, cell: doc.cell, program: doc.program, goal: doc.goal,
      experiment: doc.experiment };
    this.applying = true;
    const parts = changedParts(now, doc);
    // (a scene, or none, closes a cell)
    if (parts.includes("the scene") || parts.includes("your scene") || (parts.includes("the cell") && !doc.cell)) this.engine.send({ type: "scene", name: doc.scene || null, world: doc.world ?? null });
    if (parts.includes("the cell") && doc.cell) this.engine.send({ type: "cell", name: doc.cell.name, programs: doc.cell.programs });
    if (parts.includes("the robot")) {
      this.undoing = true;
      this.undoTarget = doc;
      this.pending = { ...this.doc, pose: null, view: this.view.viewpoint() };
      if ("shipped" in doc.robot) this.engine.send({ type: "load_robot", name: doc.robot.shipped });
      else this.robotShown();
      return;
    }
    ed.program.set(doc.program.text, doc.program.name);
    ed.blocks.setMode(doc.program.mode, true);
    if (JSON.stringify(now.program.blocks) !== JSON.stringify(doc.program.blocks)) ed.blocks.load(doc.program.blocks);
    if (parts.includes("the exercise")) ed.signals.goalShown.dispatch(doc.goal);
    if (parts.includes("the measurements")) ed.signals.experimentOpened.dispatch(doc.experiment ?? null);
    this.shown = { id: this.id, rev: this.rev, doc: this.doc };
    this.settle(() => {
      this.recorded = this.document(); // (the text the blocks make, as they make it)
      this.ready = true;
      ed.signals.changed.dispatch("project");
    });
  }

  // Once the engine has answered what was sent (the `sync` round trip) and blocks put on screen
  // have made their program (Blockly reports its changes a moment later, the blocks panel
  // compiles 150 ms after the last): `then`, with the project on screen, and the next undo or
  // redo asked for meanwhile.
  private settle(then: () => void): void {
    this.engine.call({ type: "sync" }).catch(() => undefined).then(async () => {
      await new Promise((r) => setTimeout(r, 30));
      for (let i = 0; i < 60 && this.ed.blocks.pending(); i++) await new Promise((r) => setTimeout(r, 50));
    }).finally(() => {
      this.applying = false;
      then();
      this.ed.settled();
    });
  }
}

function fromBase64(s: string): Uint8Array {
  const bin = atob(s);
  return Uint8Array.from(bin, (c) => c.charCodeAt(0));
}
