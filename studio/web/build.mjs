// Builds the page into dist/: esbuild bundles src/main.ts (three.js, uPlot) into
// assets/app.js and the styles into assets/app.css; index.html is copied. No CDN: everything
// the page loads is served by the studio's server.
import * as esbuild from "esbuild";
import { copyFileSync, mkdirSync, readFileSync, writeFileSync } from "node:fs";

const out = "dist";
mkdirSync(`${out}/assets`, { recursive: true });
await esbuild.build({
  entryPoints: ["src/main.ts"],
  bundle: true,
  format: "esm",
  target: "es2020",
  minify: true,
  sourcemap: true,
  outfile: `${out}/assets/app.js`,
  logLevel: "warning",
});
const css = readFileSync("node_modules/uplot/dist/uPlot.min.css", "utf8") + "\n" + readFileSync("src/style.css", "utf8");
writeFileSync(`${out}/assets/app.css`, css);
copyFileSync("index.html", `${out}/index.html`);
console.log(`studio page built into studio/web/${out}`);
