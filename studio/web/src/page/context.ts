// What every panel works with: the engine (the worker), the 3D view, the plots and the Editor
// (its History and the signals the panels talk through: no panel imports another). main.ts
// makes them and hands them to each panel's init().
import type { Editor } from "../editor/editor";
import type { View } from "../view/view";
import type { Plots } from "../plots";
import type { EngineClient } from "./engine-client";

export interface Studio {
  engine: EngineClient;
  view: View;
  plots: Plots;
  editor: Editor;
}
