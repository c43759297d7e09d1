// A page module (TypeScript, under src/) as node imports it: bundled with esbuild as the page's
// bundle is, so it imports nothing itself, and loaded from a data: URL (no file left behind).
// For the node tests of the page's pure modules (no DOM).
import { buildSync } from "esbuild";
import { join } from "node:path";
import { fileURLToPath } from "node:url";

const SRC = fileURLToPath(new URL("../src/", import.meta.url));

export async function load(path) {
  const r = buildSync({ entryPoints: [join(SRC, path)], bundle: true, format: "esm", platform: "neutral", write: false });
  return import("data:text/javascript;base64," + Buffer.from(r.outputFiles[0].text).toString("base64"));
}
