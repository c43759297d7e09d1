// wasm/js/node.mjs - the web engine in node, for the parity tests and the benchmark: loads
// build/wasm/wasm/engine.mjs (or $ARTICULA_WASM_DIR) and puts the shipped robots, scenes, cells and programs
// (and the drawing's font) into its files, where the studio's worker puts what it fetched; and the virtual Nano's
// parts (nano.mjs) for the emulated Nano's tests.
import { createRequire } from "node:module";
import { existsSync, readFileSync, readdirSync } from "node:fs";
import { dirname, join, resolve } from "node:path";
import { fileURLToPath, pathToFileURL } from "node:url";
import { loadEngine } from "./engine.mjs";
import { loadNanoParts } from "../../virtual-nano/web/nano-parts.mjs";

export const REPO = resolve(dirname(fileURLToPath(import.meta.url)), "../..");

export async function nodeEngine(wasmDir = process.env.ARTICULA_WASM_DIR || join(REPO, "build/wasm/wasm")) {
  // emscripten 3.1.6's ES module expects CommonJS's require and __dirname under node.
  globalThis.require ??= createRequire(import.meta.url);
  globalThis.__dirname ??= wasmDir;
  const { default: createEngine } = await import(pathToFileURL(join(wasmDir, "engine.mjs")).href);
  const engine = await loadEngine(createEngine, { wasmBinary: readFileSync(join(wasmDir, "engine.wasm")) });
  for (const kind of ["robots", "scenes", "cells", "programs"])
    for (const f of readdirSync(join(REPO, kind)).filter((f) => /\.(json|arm|robosim)$/.test(f)))
      engine.writeFile(`/${kind}/${f}`, readFileSync(join(REPO, kind, f)));
  // the drawing's font, at the path the engine reads it from (host/lib/draw.h, default_font_path)
  const font = "/usr/share/hershey-fonts/futural.jhf";
  if (existsSync(font)) engine.writeFile(font, readFileSync(font));
  return engine;
}

/** The virtual Nano's parts (nano.mjs, nano.wasm) in node, for the emulated Nano's tests. */
export async function nodeNanoParts(wasmDir = process.env.ARTICULA_WASM_DIR || join(REPO, "build/wasm/wasm")) {
  globalThis.require ??= createRequire(import.meta.url);
  globalThis.__dirname ??= wasmDir;
  const { default: createNanoParts } = await import(pathToFileURL(join(wasmDir, "nano.mjs")).href);
  return loadNanoParts(createNanoParts, { wasmBinary: readFileSync(join(wasmDir, "nano.wasm")) });
}
