// The site's files for the engine's worker: the shipped robots, scenes and programs (make web
// writes data/index.json), a robot file named by the address, and the files the user opened.
import type { Robot } from "../../../../wasm/js/engine.mjs";
import { BadMessage } from "./checks";
import type { Msg } from "./checks";
import { S } from "./state";
import type { RobotInfo } from "./state";

export const site = new URL("./", self.location.href.replace(/assets\/[^/]*$/, ""));

export async function fetchText(path: string): Promise<string> {
  const r = await fetch(new URL(path, site));
  if (!r.ok) throw new Error(`${path}: ${r.status} ${r.statusText}`);
  return r.text();
}

export async function fetchBytes(path: string): Promise<Uint8Array> {
  const r = await fetch(new URL(path, site));
  if (!r.ok) throw new Error(`${path}: ${r.status} ${r.statusText}`);
  return new Uint8Array(await r.arrayBuffer());
}

export async function loadIndex(): Promise<void> {
  S.index = JSON.parse(await fetchText("data/index.json"));
  // the examples' texts (a few KB): the menu offers a robot the ones its parser reads
  await Promise.all(S.index.programs.map(async (p) => S.programTexts.set(p, await fetchText(`data/programs/${p}`).catch(() => ""))));
}

export async function shippedRobot(name: string): Promise<Robot> {
  if (!S.index.robots.includes(name)) throw new BadMessage(`no shipped robot '${name}'`);
  const path = `/robots/${name}.json`;
  if (!S.engine.exists(path)) S.engine.writeFile(path, await fetchText(`data/robots/${name}.json`));
  const r = S.engine.robot(name);
  // Its meshes, from the site, where the robot file says they are (relative to it).
  for (const l of (r.info as unknown as RobotInfo).links)
    for (const s of l.shapes)
      if (s.mesh && !S.engine.exists(s.mesh)) S.engine.writeFile(s.mesh, await fetchBytes(`data${s.mesh}`));
  return r;
}

// A robot file on the web (?robot=path/arm.json, relative to the site), with the meshes its
// shapes name beside it.
export async function urlRobot(path: string): Promise<Robot> {
  const url = new URL(path, site);
  const name = decodeURIComponent(url.pathname.split("/").pop() ?? "robot.json");
  userFiles({});
  const r = S.engine.robot();
  try {
    r.parse(await fetchText(url.href), name);
    for (const l of (r.info as unknown as RobotInfo).links)
      for (const s of l.shapes)
        if (s.mesh && !S.engine.exists(s.mesh))
          S.engine.writeFile(s.mesh, await fetchBytes(new URL(s.mesh.replace(/^\/user\//, ""), url).href));
  } catch (e) {
    r.delete();
    throw e;
  }
  return r;
}

// The files the user opened beside a robot file (meshes), into the engine's /user folder,
// where the robot file's relative mesh paths point (the robot is read as /user/<its name>).
export function userFiles(m: Msg): void {
  const engine = S.engine;
  engine.chdir("/");
  if (!engine.exists("/user")) engine.writeFile("/user/.keep", "");
  engine.chdir("/user");
  const files = m.files;
  if (files === undefined) return;
  if (!Array.isArray(files)) throw new BadMessage("'files' must be a list of {name, data}");
  for (const f of files as { name: unknown; data: unknown }[]) {
    if (typeof f?.name !== "string" || !(f.data instanceof ArrayBuffer))
      throw new BadMessage("'files' must be a list of {name, data (an ArrayBuffer)}");
    const rel = f.name.replace(/^[\\/]+/, "").replace(/\.\.(\/|\\)/g, "");
    engine.writeFile(`/user/${rel}`, new Uint8Array(f.data));
    // a mesh opened by itself also answers for the path meshes/<name>
    engine.writeFile(`/user/meshes/${rel.split("/").pop()}`, new Uint8Array(f.data));
  }
}

const sceneTexts = new Map<string, string>();
export async function sceneFile(name: string): Promise<string> {
  let s = sceneTexts.get(name);
  if (s === undefined) {
    s = await fetchText(`data/scenes/${name}.json`);
    sceneTexts.set(name, s);
  }
  return s;
}
export const sceneText = (name: string) => sceneTexts.get(name) ?? "";
