// The scene editor: a scene of the student's own, built on the shipped one on screen (or on the
// bare table). A palette of a class's objects in millimetres, each dropped where the pointer
// presses on the view (onto the surface under it, snapped to 5 mm; Shift: free); every object's
// position and turn typed in mm and degrees; drop to the table, copy, delete; saved as a scene
// file the CLI and Python read. Each edit is a whole new scene sent to the engine, whose scene
// loader checks it as any scene file (a refused one changes nothing, its reason in the banner);
// the scene it answers with is the project's `world`, so every edit is a step of the History
// and goes into the project and its share links.
import type { SceneMsg } from "../engine/messages";
import type { Studio } from "../page/context";
import { $, download, fill, h } from "../page/dom";

type Obj = { name: string; type: string; size: number[]; xyz: number[]; rpy?: number[]; movable?: boolean; mass?: number } &
  Record<string, unknown>;
type World = { name?: string; objects?: Obj[] } & Record<string, unknown>;

/** The palette: a class's objects, sizes in mm, a movable one's mass in kg. */
export const PALETTE: { key: string; label: string; title: string; make: Omit<Obj, "name" | "xyz"> }[] = [
  { key: "cube", label: "Cube", title: "A 25 mm cube (20 g) to pick and stack", make: { type: "box", size: [25, 25, 25], movable: true, mass: 0.02 } },
  { key: "cylinder", label: "Cylinder", title: "A cylinder 25 mm across and 25 mm high (15 g)", make: { type: "cylinder", size: [12.5, 25], movable: true, mass: 0.015 } },
  { key: "ball", label: "Ball", title: "A ball 25 mm across (10 g): it rolls", make: { type: "sphere", size: [12.5], movable: true, mass: 0.01, friction: 0.5 } },
  { key: "pallet", label: "Pallet", title: "A fixed pallet 80 x 80 mm, 20 mm high, to put things on", make: { type: "box", size: [80, 80, 20] } },
  { key: "wall", label: "Wall", title: "A fixed wall 200 mm long, 20 mm thick, 60 mm high", make: { type: "box", size: [200, 20, 60] } },
];

let s: Studio;
const YOURS = "Your scene"; // a scene of one's own built on the bare table
let shipped: { name: string; world: World } | null = null; // the shipped scene's file an edit builds on (fetched once)
let editing = false; // an edit sent, the engine's answer not here yet

const round1 = (v: number) => Math.round(v * 10) / 10;
const snap = (v: number, free: boolean) => (free ? round1(v) : Math.round(v / 5) * 5);
/** How far an object's centre is above what it stands on (mm). */
const halfHeight = (o: { type: string; size: number[] }) => (o.type === "box" ? o.size[2] / 2 : o.type === "cylinder" ? o.size[1] / 2 : o.size[0]);

/** The scene on screen as a world to edit: the student's own, else the shipped one's file, else
 * the bare table. */
async function current(): Promise<World> {
  const m = s.editor.scene;
  if (m?.world) return structuredClone(m.world) as World;
  if (m?.name) {
    if (shipped?.name !== m.name) {
      const r = await fetch(`data/scenes/${encodeURIComponent(m.name)}.json`);
      if (r.ok) shipped = { name: m.name, world: (await r.json()) as World };
    }
    if (shipped?.name === m.name) return structuredClone(shipped.world);
  }
  return { name: YOURS, objects: [] };
}

function send(w: World): void {
  s.editor.signals.settle.dispatch(); // (the edit before is a step of its own: each drop, each typed value)
  const name = String(w.name ?? "");
  if (name !== YOURS && !name.endsWith("(yours)")) w.name = name ? `${name} (yours)`.slice(0, 120) : YOURS;
  editing = true;
  s.engine.send({ type: "scene", name: s.editor.scene?.name || "", world: w });
}

/** The first free name "cube 1", "cube 2", ... */
function freeName(w: World, base: string): string {
  const taken = new Set((w.objects ?? []).map((o) => o.name));
  for (let i = 1; ; ++i) if (!taken.has(`${base} ${i}`)) return `${base} ${i}`;
}

/** Adds one of the palette's objects at `at` (the surface under the pointer, mm). */
export async function addObject(key: string, at: number[], free = false): Promise<void> {
  const p = PALETTE.find((x) => x.key === key);
  if (!p) return;
  const w = await current();
  const o = { name: freeName(w, p.key), ...structuredClone(p.make) } as Obj;
  o.xyz = [snap(at[0], free), snap(at[1], free), round1(at[2] + halfHeight(o))];
  w.objects = [...(w.objects ?? []), o];
  send(w);
}

async function edit(name: string, change: (o: Obj, w: World) => void): Promise<void> {
  const w = await current();
  const o = (w.objects ?? []).find((x) => x.name === name);
  if (!o) return;
  change(o, w);
  send(w);
}

function hint(text: string): void {
  $("scene-hint").textContent = text;
}

function choose(key: string): void {
  const p = PALETTE.find((x) => x.key === key)!;
  hint(`${p.label}: click or tap where it goes (on the table or on top of something; it snaps to 5 mm, Shift: free). Escape: not now.`);
  s.view.placing = (at, free) => {
    hint("");
    void addObject(key, at, free);
  };
}

/** A number field of an object's row: typed mm or degrees, sent when it changes. */
function field(o: Obj, label: string, value: number, set: (o: Obj, v: number) => void): HTMLElement {
  const input = h("input", { type: "number", step: "any", value: round1(value), "aria-label": `${o.name}: ${label}`, title: `${label} (${label === "turn" ? "degrees about the vertical" : "mm"})`,
    "data-object": o.name, "data-field": label });
  input.addEventListener("change", () => {
    const v = Number(input.value);
    if (input.value.trim() === "" || !Number.isFinite(v)) {
      hint(`${o.name}: ${label} must be a number`);
      input.value = String(round1(value));
      return;
    }
    void edit(o.name, (x) => set(x, round1(v)));
  });
  return input;
}

function rows(m: SceneMsg): void {
  const list = $("scene-objects");
  const objs = (m.world?.objects ?? []) as Obj[];
  fill(list, ...objs.map((o) => {
    const yaw = o.rpy?.[2] ?? 0;
    const drop = h("button", { title: `Down onto the table: ${o.name} stands on it`, "aria-label": `${o.name}: onto the table` }, "\u2193");
    drop.addEventListener("click", () => void edit(o.name, (x) => { x.xyz = [x.xyz[0], x.xyz[1], round1(halfHeight(x))]; }));
    const copy = h("button", { title: `A copy of ${o.name} beside it`, "aria-label": `${o.name}: copy` }, "copy");
    copy.addEventListener("click", () => void edit(o.name, (x, w) => {
      const c = { ...structuredClone(x), name: freeName(w, x.name.replace(/ \d+$/, "")) };
      c.xyz = [x.xyz[0] + 5 * Math.ceil((Math.max(...x.size.slice(0, 2)) * (x.type === "box" ? 1 : 2) + 10) / 5), x.xyz[1], x.xyz[2]];
      w.objects = [...(w.objects ?? []), c];
    }));
    const del = h("button", { title: `Take ${o.name} out of the scene`, "aria-label": `${o.name}: delete` }, "\u2715");
    del.addEventListener("click", () => void edit(o.name, (x, w) => { w.objects = (w.objects ?? []).filter((y) => y !== x); }));
    const cell = (label: string, input: HTMLElement) => h("label", null, h("span", null, label), input);
    return h("div", { class: "scene-obj", "data-row": o.name },
      h("div", { class: "head" }, h("span", { class: "name", title: `${o.type}, ${o.size.join(" x ")} mm${o.movable ? ", movable" : ", fixed"}` }, o.name),
        h("span", { class: "acts" }, drop, copy, del)),
      h("div", { class: "coords" },
        cell("x", field(o, "x", o.xyz[0], (x, v) => { x.xyz = [v, x.xyz[1], x.xyz[2]]; })),
        cell("y", field(o, "y", o.xyz[1], (x, v) => { x.xyz = [x.xyz[0], v, x.xyz[2]]; })),
        cell("z", field(o, "z", o.xyz[2], (x, v) => { x.xyz = [x.xyz[0], x.xyz[1], v]; })),
        cell("turn\u00b0", field(o, "turn", yaw, (x, v) => { x.rpy = [x.rpy?.[0] ?? 0, x.rpy?.[1] ?? 0, v]; }))));
  }));
}

/** The engine refused the last edit (the banner says why): the fields show the scene as it is. */
export function sceneEditRefused(): void {
  if (!editing) return;
  editing = false;
  if (s.editor.scene) rows(s.editor.scene);
}

/** The scene on screen changed (the engine's scene message): the editor shows its objects. */
export function showSceneEdit(m: SceneMsg): void {
  editing = false;
  rows(m);
  $("scene-save").toggleAttribute("disabled", !m.world);
  const n = (m.world?.objects as unknown[] | undefined)?.length ?? 0;
  $("scene-edit-note").textContent = m.world ? `${m.title}: ${n} object${n === 1 ? "" : "s"}, yours to change (undo takes an edit back).`
    : m.name ? `The shipped scene "${m.title}": add an object and it becomes yours (the shipped file stays as it is).`
    : "Add an object and the physics turns on, with your own scene.";
}

export function initSceneEdit(studio: Studio): void {
  s = studio;
  const palette = $("scene-palette");
  for (const p of PALETTE) {
    const b = h("button", { title: p.title, "data-add": p.key }, `+ ${p.label}`);
    b.addEventListener("click", () => choose(p.key));
    palette.appendChild(b);
  }
  document.addEventListener("keydown", (e) => {
    if (e.key === "Escape" && s.view.placing) {
      s.view.placing = null;
      hint("");
    }
  });
  $("scene-save").addEventListener("click", () => {
    const w = s.editor.scene?.world;
    if (!w) return;
    const file = { $schema: "./scene.schema.json", ...w };
    const base = String(w.name ?? "scene").replace(/ \(yours\)$/, "").toLowerCase().replace(/[^a-z0-9]+/g, "-").replace(/^-|-$/g, "") || "scene";
    download(`${base}.json`, JSON.stringify(file, null, 2) + "\n", "application/json");
  });
}
