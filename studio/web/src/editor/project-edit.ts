// A student's edit of the project as one command: the document before and after it. What a
// step covers is what the project keeps (the robot, the scene, the program as text and
// blocks, an exercise's goal, the experiment's measurements); the pose, the camera and the
// project's name are not history (as in three.js's editor). Pure: the page hands in how a
// document is put on screen.
import type { Project } from "../project/document";
import type { Command } from "./history";

/** The parts of a project that are history, in the order a change is named by. */
const PARTS: { key: keyof Project; name: string }[] = [
  { key: "robot", name: "the robot" },
  { key: "scene", name: "the scene" },
  { key: "world", name: "your scene" },
  { key: "cell", name: "the cell" },
  { key: "goal", name: "the exercise" },
  { key: "program", name: "the program" },
  { key: "experiment", name: "the measurements" },
];

const same = (a: unknown, b: unknown) => JSON.stringify(a ?? null) === JSON.stringify(b ?? null);

// A part as history sees it. A program in blocks on both sides: its text is what the blocks
// make (the engine writes it, on a busy machine seconds after the blocks are on screen), not
// a student's edit, so only the blocks count.
function part(d: Project, key: keyof Project, other: Project): unknown {
  if (key === "program" && d.program.mode === "blocks" && other.program.mode === "blocks") return { ...d.program, text: "" };
  return d[key];
}

/** Which history parts differ between two documents (none: not an edit). */
export function changedParts(a: Project, b: Project): string[] {
  return PARTS.filter((p) => !same(part(a, p.key, b), part(b, p.key, a))).map((p) => p.name);
}

/** How a change is named on the undo button, and the kind that joins a burst of it into one step
 * (typing, or dragging blocks about). */
export function describeChange(a: Project, b: Project): { name: string; kind: string } | null {
  const parts = changedParts(a, b);
  if (parts.length === 0) return null;
  if (parts.length === 1 && parts[0] === "the cell" && a.cell && b.cell && a.cell.name === b.cell.name)
    return { name: "the cell's programs", kind: "cell-text" };
  if (parts.length === 1 && parts[0] === "the program") {
    const text = a.program.text !== b.program.text, blocks = !same(a.program.blocks, b.program.blocks);
    const mode = a.program.mode !== b.program.mode;
    if (mode) return { name: `the program as ${b.program.mode}`, kind: "" };
    if (blocks) return { name: "the blocks", kind: "program-blocks" };
    if (text) return { name: "the program's text", kind: "program-text" };
    return { name: "the program's name", kind: "" };
  }
  return { name: parts.join(" and "), kind: "" };
}

/** Where two JSON values first differ ("program.blocks.blocks.blocks[0].x: 24 -> 30"), "" where
 * they do not: what a step changed, for whoever reads a test's failure. */
export function firstDifference(a: unknown, b: unknown, path = ""): string {
  if (same(a, b)) return "";
  const show = (v: unknown) => (v === undefined ? "none" : JSON.stringify(v).slice(0, 60));
  if (a && b && typeof a === "object" && typeof b === "object" && Array.isArray(a) === Array.isArray(b)) {
    const keys = [...new Set([...Object.keys(a), ...Object.keys(b)])];
    for (const k of keys) {
      const d = firstDifference((a as Record<string, unknown>)[k], (b as Record<string, unknown>)[k],
        Array.isArray(a) ? `${path}[${k}]` : path ? `${path}.${k}` : k);
      if (d) return d;
    }
  }
  return `${path || "the whole"}: ${show(a)} -> ${show(b)}`;
}

/** The edit from `before` to `after`; `show` puts a document's history parts on screen. */
export class ProjectEdit implements Command {
  name: string;
  kind: string;
  constructor(public before: Project, public after: Project, private show: (doc: Project) => void) {
    const d = describeChange(before, after);
    this.name = d?.name ?? "nothing";
    this.kind = d?.kind ?? "";
  }
  /** Where the step first changed the project. */
  detail(): string {
    return firstDifference(this.before, this.after);
  }
  undo(): void {
    this.show(this.before);
  }
  redo(): void {
    this.show(this.after);
  }
  merge(later: Command): void {
    this.after = (later as ProjectEdit).after;
  }
}
