// The History of a student's edits, after three.js's editor (editor/js/History.js): every
// edit is a command that can be undone and redone. Pure: no DOM, no engine (tested in node,
// studio/web/tests/editor.test.mjs).
import { Signal } from "./signal";

/** An edit: what it says it did, and how to take it back and do it again. */
export interface Command {
  name: string; // for the buttons' titles: "Undo: the program's text"
  undo(): void;
  redo(): void;
  // Commands of the same kind in a row (typing, dragging a slider's value) join into one
  // step when they come within `History.mergeMs` of each other: `merge` takes the later.
  kind?: string;
  merge?(later: Command): void;
}

export class History {
  readonly changed = new Signal<void>();
  mergeMs = 1000;
  private undos: { cmd: Command; at: number }[] = [];
  private redos: Command[] = [];
  private limit: number;

  constructor(limit = 200) {
    this.limit = limit;
  }

  /** A command already carried out (the edit is on screen): it becomes the step to undo. */
  record(cmd: Command, now = Date.now()): void {
    const last = this.undos[this.undos.length - 1];
    if (last && cmd.kind && last.cmd.kind === cmd.kind && last.cmd.merge && now - last.at <= this.mergeMs) {
      last.cmd.merge(cmd);
      last.at = now;
    } else {
      this.undos.push({ cmd, at: now });
      if (this.undos.length > this.limit) this.undos.shift();
    }
    this.redos = [];
    this.changed.dispatch();
  }

  /** Carries out `cmd` (its redo) and records it. */
  execute(cmd: Command, now = Date.now()): void {
    cmd.redo();
    this.record(cmd, now);
  }

  get canUndo(): boolean {
    return this.undos.length > 0;
  }
  get canRedo(): boolean {
    return this.redos.length > 0;
  }
  /** What undo and redo would take back or do again ("" if nothing). */
  get undoName(): string {
    return this.undos[this.undos.length - 1]?.cmd.name ?? "";
  }
  get redoName(): string {
    return this.redos[this.redos.length - 1]?.name ?? "";
  }
  /** The step undo would take back, if any. */
  get undoCommand(): Command | undefined {
    return this.undos[this.undos.length - 1]?.cmd;
  }
  get steps(): { undo: number; redo: number } {
    return { undo: this.undos.length, redo: this.redos.length };
  }

  undo(): boolean {
    const e = this.undos.pop();
    if (!e) return false;
    e.cmd.undo();
    this.redos.push(e.cmd);
    this.changed.dispatch();
    return true;
  }

  redo(): boolean {
    const cmd = this.redos.pop();
    if (!cmd) return false;
    cmd.redo();
    this.undos.push({ cmd, at: -Infinity }); // (a redone step never merges with the next edit)
    this.changed.dispatch();
    return true;
  }

  clear(): void {
    this.undos = [];
    this.redos = [];
    this.changed.dispatch();
  }
}
