// Builds Articula Studio as a static site into dist/ (`make web`), to be served by any web
// server, at the site's root or under a sub-path, with no articula process:
//   index.html, icon.svg, manifest.webmanifest, sw.js (offline use, an installable app)
//   assets/app.js, app.css  the page (esbuild: src/main.ts, three.js, uPlot)
//   assets/worker.js        the engine's Web Worker (src/engine/worker.ts)
//   assets/nano-worker.js   the virtual Nano's Web Worker (src/virtual-nano/worker.ts, avr8js)
//   engine/engine.mjs, .wasm the web engine (wasm/, built by emscripten; ARTICULA_WASM_DIR)
//   engine/nano.mjs, .wasm   the virtual Nano's parts for its worker (virtual-nano/web/nano_parts.cpp)
//   data/                   the shipped robots, scenes and programs, and data/index.json;
//                           data/firmware/articula-nano.hex, the firmware `make flash` writes
//                           (ARTICULA_NANO_HEX, --hex), and articula-cnc.hex and articula-servo.hex beside it (the
//                           build for a CNC shield's STEP/DIR drivers); firmware.json says each
// Every path is relative: nothing is loaded from another site.
//
//   node build.mjs [--wasm DIR] [--hex FILE]  (defaults: ../../build/wasm/wasm, ../../build/avr/firmware/articula-nano.hex)
import * as esbuild from "esbuild";
import { createHash } from "node:crypto";
import { copyFileSync, existsSync, mkdirSync, readdirSync, readFileSync, rmSync, statSync, writeFileSync } from "node:fs";
import { basename, dirname, join, relative } from "node:path";
import { fileURLToPath } from "node:url";
import { gzipSync } from "node:zlib";

const here = dirname(fileURLToPath(import.meta.url));
const repo = join(here, "../..");
const out = join(here, "dist");
const arg = process.argv.indexOf("--wasm");
const wasmDir = arg > 0 ? process.argv[arg + 1] : process.env.ARTICULA_WASM_DIR || join(repo, "build/wasm/wasm");
const hexArg = process.argv.indexOf("--hex");
const hexFile = hexArg > 0 ? process.argv[hexArg + 1] : process.env.ARTICULA_NANO_HEX || join(repo, "build/avr/firmware/articula-nano.hex");
const bootArg = process.argv.indexOf("--bootloader");
const bootFile = bootArg > 0 ? process.argv[bootArg + 1] : join(dirname(hexFile), "optiboot_atmega328.hex");
for (const f of [hexFile, bootFile])
  if (!existsSync(f)) {
    console.error(`studio: the firmware is not built (${f} is missing): run make`);
    process.exit(2);
  }
for (const f of ["engine.mjs", "engine.wasm", "nano.mjs", "nano.wasm"])
  if (!existsSync(join(wasmDir, f))) {
    console.error(`studio: the web engine is not built (${join(wasmDir, f)} is missing): run make`);
    process.exit(2);
  }

rmSync(out, { recursive: true, force: true });
mkdirSync(join(out, "assets"), { recursive: true });
const common = { bundle: true, format: "esm", target: "es2020", minify: true, sourcemap: true, logLevel: "warning" };
await esbuild.build({ ...common, entryPoints: [join(here, "src/main.ts")], outfile: join(out, "assets/app.js") });
await esbuild.build({ ...common, entryPoints: [join(here, "src/engine/worker.ts")], outfile: join(out, "assets/worker.js") });
await esbuild.build({ ...common, entryPoints: [join(here, "src/virtual-nano/worker.ts")], outfile: join(out, "assets/nano-worker.js") });
const css = readFileSync(join(here, "node_modules/uplot/dist/uPlot.min.css"), "utf8") + "\n" +
  await blocklyCss("blockly-media") + "\n" + readFileSync(join(here, "src/style.css"), "utf8");
copyTree(join(here, "node_modules/blockly/media"), join(out, "assets/blockly-media"), () => true);
writeFileSync(join(out, "assets/app.css"), css);
copyFileSync(join(here, "index.html"), join(out, "index.html"));
copyFileSync(join(here, "icon.svg"), join(out, "icon.svg"));

mkdirSync(join(out, "engine"));
for (const f of ["engine.mjs", "engine.wasm", "nano.mjs", "nano.wasm"]) copyFileSync(join(wasmDir, f), join(out, "engine", f));

// Blockly's own CSS, as a file: Blockly would put it in a <style> element, which the page's
// Content-Security-Policy refuses (style-src 'self'), so the page starts Blockly with
// css: false and the build writes the CSS Blockly would inject (read in jsdom, Blockly's own
// dependency) into app.css, its media paths relative to assets/.
async function blocklyCss(media) {
  const { JSDOM } = await import("jsdom");
  const dom = new JSDOM('<!doctype html><html><head></head><body><div id="b"></div></body></html>', { pretendToBeVisual: true });
  const keep = {};
  for (const k of ["window", "document", "navigator", "Element", "HTMLElement", "SVGElement", "Node", "DOMParser", "XMLSerializer", "ShadowRoot"]) {
    keep[k] = Object.getOwnPropertyDescriptor(globalThis, k);
    Object.defineProperty(globalThis, k, { value: dom.window[k], configurable: true, writable: true });
  }
  try {
    const Blockly = await import("blockly");
    try {
      (Blockly.default ?? Blockly).inject(dom.window.document.getElementById("b"), { media: `${media}/`, sounds: false });
    } catch {
      // jsdom draws no SVG: the CSS is in the document before the drawing fails
    }
    const style = dom.window.document.getElementById("blockly-common-style");
    if (!style) throw new Error("studio: Blockly injected no CSS (its injection changed?)");
    // and the renderer's, which its constant provider would inject (panels/blocks.ts starts
    // the zelos renderer with the classic theme and no injection of its own)
    const B = Blockly.default ?? Blockly;
    const cp = new B.zelos.ConstantProvider();
    cp.setTheme(B.Themes.Classic);
    const renderer = cp.getCSS_(".zelos-renderer.classic-theme").join("\n");
    return style.textContent + "\n" + renderer;
  } finally {
    for (const [k, d] of Object.entries(keep)) {
      if (d) Object.defineProperty(globalThis, k, d);
      else delete globalThis[k];
    }
  }
}

// The shipped files, and their index (the worker lists robots, scenes and programs from it).
const index = { robots: [], scenes: [], sceneSizedFor: {}, cells: [], programs: [], meshes: [], exercises: [], plans: [] };
function copyTree(from, to, keep) {
  for (const name of readdirSync(from).sort()) {
    const src = join(from, name), dst = join(to, name);
    if (statSync(src).isDirectory()) copyTree(src, dst, keep);
    else if (keep(name)) {
      mkdirSync(to, { recursive: true });
      copyFileSync(src, dst);
    }
  }
}
const isData = (n) => n.endsWith(".json") && !n.endsWith(".schema.json");
copyTree(join(repo, "robots"), join(out, "data/robots"), (n) => isData(n) || /\.(stl|obj)$/i.test(n));
copyTree(join(repo, "scenes"), join(out, "data/scenes"), isData);
copyTree(join(repo, "programs"), join(out, "data/programs"), (n) => /\.(arm|robosim)$/.test(n));
index.robots = readdirSync(join(out, "data/robots")).filter(isData).map((n) => n.replace(/\.json$/, ""));
index.scenes = readdirSync(join(out, "data/scenes")).filter(isData).map((n) => n.replace(/\.json$/, ""));
// which arms each scene is placed for (its "sized_for": the menu offers a scene first to them;
// the engine's loader checks the whole file when it opens)
for (const n of index.scenes) index.sceneSizedFor[n] = JSON.parse(readFileSync(join(out, `data/scenes/${n}.json`), "utf8")).sized_for ?? [];
index.programs = readdirSync(join(out, "data/programs"));
// The cells (several arms, cells/README.md): of shipped robots, the page opens them by name.
copyTree(join(repo, "cells"), join(out, "data/cells"), isData);
index.cells = readdirSync(join(out, "data/cells")).filter(isData).map((n) => n.replace(/\.json$/, ""));
copyTree(join(repo, "hil/plans"), join(out, "data/plans"), (n) => n.endsWith(".arm"));
index.plans = readdirSync(join(out, "data/plans"));
copyTree(join(repo, "exercises"), join(out, "data/exercises"), (n) => n.endsWith(".articula"));
index.exercises = readdirSync(join(out, "data/exercises"));
// The drawing's single-stroke font, from Debian's hershey-fonts-data (scripts/bootstrap installs it).
{
  const font = "/usr/share/hershey-fonts/futural.jhf";
  if (!existsSync(font)) throw new Error(`${font} is missing: scripts/bootstrap installs hershey-fonts-data`);
  mkdirSync(join(out, "data/fonts"), { recursive: true });
  copyFileSync(font, join(out, "data/fonts/futural.jhf"));
}
mkdirSync(join(out, "data/firmware"), { recursive: true });
copyFileSync(hexFile, join(out, "data/firmware/articula-nano.hex"));
// The build for a CNC shield (STEP/DIR drivers), beside the Nano's: the page flashes and runs
// the one the robot's drivers need.
const cncHexFile = join(dirname(hexFile), "articula-cnc.hex");
copyFileSync(cncHexFile, join(out, "data/firmware/articula-cnc.hex"));
// And the build for servo arms (meArm, EEZYbotARM on servos): a pulse per servo from Timer1.
const servoHexFile = join(dirname(hexFile), "articula-servo.hex");
copyFileSync(servoHexFile, join(out, "data/firmware/articula-servo.hex"));
copyFileSync(bootFile, join(out, "data/firmware/optiboot_atmega328.hex"));
// What the firmware says it is (its banner, asked of it on the virtual Nano), for the page's
// flash panel: the robot it is built for, its version, its size.
{
  const { nodeEngine, nodeNanoParts } = await import("../../wasm/js/node.mjs");
  const { VirtualNano } = await import("./src/virtual-nano/avr-nano.mjs");
  const engine = await nodeEngine(wasmDir);
  const parts = await nodeNanoParts(wasmDir);
  const describe = (file, cnc) => {
    const hex = readFileSync(file, "utf8");
    const nano = new VirtualNano({ hex, parts, cnc });
    let info = null; // the banner, read by the core's parser (shared/articula/protocol.h)
    nano.onLine = (l) => {
      const p = engine.parseArmLine(l);
      if (p.kind === "info") info = p;
    };
    nano.runFor(0.3);
    nano.send("I\n");
    for (let i = 0; i < 100 && !info; i++) nano.runFor(0.01);
    if (!info) {
      console.error(`studio: the firmware ${file} gives no banner on the virtual Nano`);
      process.exit(2);
    }
    const d = { file: basename(file), bytes: nano.flashUsed, version: info.version, protocol: info.protocol, robot: info.robot,
      sha256: createHash("sha256").update(hex).digest("hex") };
    nano.delete();
    return d;
  };
  // The Nano's build at the top (what a page before the CNC build read), every build by name.
  const nano = describe(hexFile, false);
  writeFileSync(join(out, "data/firmware/firmware.json"), JSON.stringify({
    ...nano, bootloader: "optiboot_atmega328.hex",
    builds: { "articula-nano": nano, "articula-cnc": describe(cncHexFile, true), "articula-servo": describe(servoHexFile, false) },
  }, null, 1));
}
writeFileSync(join(out, "data/index.json"), JSON.stringify(index, null, 1));

// Every file of the site, for the service worker to keep (offline use) and for the sizes.
function files(dir) {
  return readdirSync(dir).flatMap((n) => (statSync(join(dir, n)).isDirectory() ? files(join(dir, n)) : [join(dir, n)]));
}
const version = createHash("sha256");
const list = files(out).filter((f) => !f.endsWith(".map")).map((f) => relative(out, f)).sort();
for (const f of list) version.update(f).update(readFileSync(join(out, f)));
writeFileSync(join(out, "manifest.webmanifest"), JSON.stringify({
  name: "Articula Studio",
  short_name: "Articula",
  description: "Robot arms from their DH tables: 3D, IK, programs, physics, and the real arm",
  start_url: "./",
  scope: "./",
  display: "standalone",
  background_color: "#eef2f6",
  theme_color: "#1d2733",
  icons: [{ src: "icon.svg", sizes: "any", type: "image/svg+xml", purpose: "any" }],
}, null, 1));
const sw = readFileSync(join(here, "src/sw.js"), "utf8")
  .replace("__VERSION__", version.digest("hex").slice(0, 12))
  .replace("__FILES__", JSON.stringify(["./", ...list.filter((f) => f !== "index.html"), "manifest.webmanifest"]));
writeFileSync(join(out, "sw.js"), sw);

// Sizes: the whole site gzipped, the engine's files one by one.
let raw = 0, gz = 0;
for (const f of files(out).filter((f) => !f.endsWith(".map"))) {
  const b = readFileSync(f);
  raw += b.length;
  gz += gzipSync(b, { level: 9 }).length;
}
const kb = (n) => `${(n / 1024).toFixed(0)} KB`;
const engineSizes = ["engine/engine.wasm", "engine/engine.mjs", "engine/nano.wasm", "engine/nano.mjs"].map((f) => {
  const b = readFileSync(join(out, f));
  return `${f} ${kb(b.length)} (${kb(gzipSync(b, { level: 9 }).length)} gzipped)`;
});
writeFileSync(join(out, "sizes.json"), JSON.stringify({ bytes: raw, gzipped: gz }));
console.log(`studio: the static site is in studio/web/dist: ${kb(raw)}, ${kb(gz)} gzipped; ${engineSizes.join(", ")}`);
