// What every panel works with: the engine (the worker), the 3D view and the plots. main.ts
// makes them and hands them to each panel's init().
import type { View } from "../view";
import type { Plots } from "../plots";
import type { EngineClient } from "./engine";

export interface Studio {
  engine: EngineClient;
  view: View;
  plots: Plots;
}
