// The robot: the shipped ones, a robot file opened with its meshes (or a thesis appendix C
// file with its scale), URDF out. A robot file is untrusted input: its names and description
// are shown as text, and a file that cannot be used keeps the robot that was there.
import type { RobotMsg } from "../engine/messages";
import type { Studio } from "../page/context";
import { $, banner, download, h, setOptions } from "../page/dom";
import type { Reports } from "../page/reports";

/** Why the last robot could not be used (window.articula shows it; main.ts wires it). */
export const robotReport: { robotError: string } = {
  robotError: "",
};

const MAX_FILE = 20_000_000; // bytes of a robot file or mesh the page opens
let s: Studio;
let needFit: Promise<void> | null = null;

function base64(buf: ArrayBuffer): string {
  const bytes = new Uint8Array(buf);
  let s = "";
  for (let i = 0; i < bytes.length; i += 0x8000) s += String.fromCharCode(...bytes.subarray(i, i + 0x8000));
  return btoa(s);
} // a new robot: frame it once its first pose is drawn

export function initRobot(studio: Studio): void {
  s = studio;
  $("robot-select").addEventListener("change", (e) => s.engine.send({ type: "load_robot", name: (e.target as HTMLSelectElement).value }));
  $("open-robot").onclick = () => $("robot-file").click();
  $("robot-file").addEventListener("change", (e) => void openFiles(e.target as HTMLInputElement));
  $("export-urdf").onclick = () => s.engine.send({ type: "export_urdf" });
}

// The robot file, and any mesh files (STL, OBJ) its shapes name, opened together.
async function openFiles(input: HTMLInputElement): Promise<void> {
  const all = [...(input.files ?? [])];
  input.value = "";
  const f = all.find((x) => /\.(json|txt)$/i.test(x.name)) ?? all[0];
  if (!f) return;
  const meshes = all.filter((x) => x !== f);
  if (f.size > MAX_FILE || meshes.some((x) => x.size > MAX_FILE))
    return banner(`That file is larger than ${MAX_FILE / 1e6} MB: the studio opens robot files and meshes up to that size.`);
  const text = await f.text();
  const files = await Promise.all(meshes.map(async (x) => ({ name: x.name, data: await x.arrayBuffer() })));
  const transfer = files.map((x) => x.data);
  const meshesKept = files.map((x) => ({ name: x.name, data: base64(x.data) }));
  if (f.name.toLowerCase().endsWith(".json")) {
    s.editor.robotFile = { file: { name: f.name, text, legacy: false, scale: 1 }, meshes: meshesKept };
    return s.engine.send({ type: "load_robot", text, filename: f.name, files }, transfer);
  }
  const answer = prompt(`${f.name} is a robot file of the thesis's original system: how many millimetres is one of its units? (the thesis's MK2 model: 25.75)`, "10");
  if (answer === null) return;
  const scale = parseFloat(answer);
  if (!(scale > 0)) return banner("The scale must be a number above 0");
  s.editor.robotFile = { file: { name: f.name, text, legacy: true, scale }, meshes: meshesKept };
  s.engine.send({ type: "load_robot", text, filename: f.name, legacy: true, scale }, transfer);
}

/** A robot to show: its view and the robot menu; then the other panels follow it (robotShown). */
export function showRobot(r: RobotMsg): void {
  s.editor.robot = r;
  robotReport.robotError = "";
  const built = s.view.build(r);
  s.view.showAxes(($("show-axes") as HTMLInputElement).checked);
  $("robot-name").textContent = r.description ? `${r.name}: ${r.description}` : r.name;
  $("robot-name").title = r.source;
  const sel = $("robot-select") as HTMLSelectElement;
  setOptions(sel, r.robots);
  // a robot opened from a file: named in the list (not chosen again from it)
  if (!r.shipped) sel.append(h("option", { value: "", disabled: true }, `${r.name} (opened file)`));
  sel.value = r.shipped;
  if (!r.keep_view) { // keep_view: the same robot, other link lengths
    if (r.import_notes.length) banner(`Imported. ${r.import_notes.length} things had no place in a robot file; the first: ${r.import_notes[0]}`, "info");
    needFit = built;
  }
  s.editor.signals.robotShown.dispatch(r);
}

/** The first pose of a new robot is drawn: frame it (or show the camera its project kept). */
export function fitNewRobot(): void {
  if (!needFit) return;
  needFit.then(() => requestAnimationFrame(() => {
    const kept = s.editor.keptView;
    if (kept) s.view.setViewpoint(kept);
    else s.view.fit(false);
    s.editor.keptView = null;
  }));
  needFit = null;
}

export function robotError(message: string): void {
  robotReport.robotError = message;
  banner(`This robot file cannot be used, the robot stays ${s.editor.robot?.name ?? ""}: ${message}`);
}

export function saveUrdf(m: { name: string; xml: string }): void {
  download(`${m.name.replace(/\W+/g, "_")}.urdf`, m.xml, "application/xml");
}
