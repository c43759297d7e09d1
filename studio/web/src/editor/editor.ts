// The Editor (after three.js's editor/js/Editor.js): the page's edits as one History with
// undo and redo. Panels record their edits into it and listen to its signals; main.ts wires the
// buttons and the keys. (The project document, the robot, the scene and the program still live
// in panels/projects.ts and the panels: moving them here is issue 28's next part.)
import { History } from "./history";
import { Signal } from "./signal";

export class Editor {
  readonly history = new History();
  readonly signals = {
    historyChanged: this.history.changed,
    // before an undo or a redo: an edit still waiting to be recorded (typing) is recorded now
    settle: new Signal<void>(),
    // an exercise asked for by name (the examples menu, the projects list): the projects open it
    exerciseWanted: new Signal<string>(),
  };
  // true while an edit is being put on screen (a robot loading): undo and redo wait for it,
  // in the order they were asked for (a student tapping Undo three times gets three steps)
  busy: () => boolean = () => false;
  private waiting: ("undo" | "redo")[] = [];

  undo(): void {
    this.ask("undo");
  }

  redo(): void {
    this.ask("redo");
  }

  /** The page has put an edit on screen: the next undo or redo asked for meanwhile, if any. */
  settled(): void {
    while (this.waiting.length && !this.busy()) this.act(this.waiting.shift()!);
  }

  private ask(what: "undo" | "redo"): void {
    if (this.busy() || this.waiting.length) {
      if (this.waiting.length < 50) this.waiting.push(what);
      return;
    }
    this.act(what);
  }

  private act(what: "undo" | "redo"): void {
    this.signals.settle.dispatch();
    if (what === "undo") this.history.undo();
    else this.history.redo();
  }
}
