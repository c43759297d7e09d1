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
  };
  // true while an edit is being put on screen (a robot loading): undo and redo wait for it
  busy: () => boolean = () => false;

  undo(): boolean {
    if (this.busy()) return false;
    this.signals.settle.dispatch();
    return this.history.undo();
  }

  redo(): boolean {
    if (this.busy()) return false;
    this.signals.settle.dispatch();
    return this.history.redo();
  }
}
