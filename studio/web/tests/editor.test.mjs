// The Editor's pure modules in node (src/editor/): the History of commands, built from the
// TypeScript sources with esbuild as the page's bundle is.
import assert from "node:assert/strict";
import { test } from "node:test";
import { load } from "./page-module.mjs";

/** A value edited through commands, as the page's program text is. */
function setter(box, name, from, to, kind) {
  return { name, kind, undo: () => (box.v = from), redo: () => (box.v = to),
    merge(later) { to = later.to; this.redo = () => (box.v = to); }, to };
}

test("History: undo to the start, redo to the end; a new edit drops the redos", async () => {
  const { History } = await load("editor/history.ts");
  const h = new History();
  const box = { v: 0 };
  let signals = 0;
  h.changed.add(() => signals++);
  for (let i = 1; i <= 3; i++) h.execute(setter(box, `set ${i}`, i - 1, i), i * 10_000);
  assert.equal(box.v, 3);
  assert.equal(h.undoName, "set 3");
  while (h.undo());
  assert.equal(box.v, 0);
  assert.equal(h.canUndo, false);
  assert.equal(h.redoName, "set 1");
  while (h.redo());
  assert.equal(box.v, 3);
  h.undo();
  h.execute(setter(box, "set 9", 2, 9), 100_000);
  assert.equal(h.canRedo, false, "a new edit after an undo drops what could be redone");
  h.undo();
  assert.equal(box.v, 2);
  assert.ok(signals >= 10);
});

test("History: edits of one kind in a burst are one step; apart, two", async () => {
  const { History } = await load("editor/history.ts");
  const h = new History();
  const box = { v: "" };
  h.record(setter(box, "text", "", "a", "text"), 1000);
  h.record(setter(box, "text", "a", "ab", "text"), 1500);
  h.record(setter(box, "text", "ab", "abc", "text"), 2000);
  box.v = "abc";
  assert.deepEqual(h.steps, { undo: 1, redo: 0 });
  h.undo();
  assert.equal(box.v, "", "one undo takes the burst back");
  h.redo();
  assert.equal(box.v, "abc");
  h.record(setter(box, "text", "abc", "abcd", "text"), 9000);
  assert.deepEqual(h.steps, { undo: 2, redo: 0 }, "a redone step does not swallow the next edit");
  h.record(setter(box, "text", "abcd", "abcde", "text"), 20_000);
  assert.deepEqual(h.steps, { undo: 3, redo: 0 });
});

test("History: at most `limit` steps are kept, the oldest go", async () => {
  const { History } = await load("editor/history.ts");
  const h = new History(5);
  const box = { v: 0 };
  for (let i = 1; i <= 8; i++) h.execute(setter(box, `set ${i}`, i - 1, i), i * 10_000);
  let n = 0;
  while (h.undo()) n++;
  assert.equal(n, 5);
  assert.equal(box.v, 3);
});

test("A project edit names what changed; the pose, the camera and the name are not history", async () => {
  const { describeChange, changedParts, ProjectEdit } = await load("editor/project-edit.ts");
  const { newProject } = await load("project/document.ts");
  const a = newProject("P");
  const moved = { ...a, name: "Q", pose: { q: [1, 2, 3], gripper: 50 }, view: { eye: [1, 1, 1], target: [0, 0, 0] } };
  assert.equal(describeChange(a, moved), null);
  const typed = { ...a, program: { ...a.program, text: "M 0 90 0" } };
  assert.deepEqual(describeChange(a, typed), { name: "the program's text", kind: "program-text" });
  const robot = { ...typed, robot: { shipped: "puma560" } };
  assert.deepEqual(changedParts(typed, robot), ["the robot"]);
  const both = { ...robot, scene: "table" };
  assert.equal(describeChange(typed, both).name, "the robot and the scene");
  const shown = [];
  const e = new ProjectEdit(a, typed, (d) => shown.push(d));
  e.merge(new ProjectEdit(typed, { ...typed, program: { ...typed.program, text: "M 0 90 0\nG 0" } }, () => undefined));
  e.undo();
  e.redo();
  assert.equal(shown[0], a);
  assert.equal(shown[1].program.text, "M 0 90 0\nG 0", "a merged edit redoes to the last text");
  // a program in blocks: the text the blocks make is not an edit (it comes after the blocks, late
  // on a busy machine, and recorded as one it dropped the redo steps), the blocks are
  const inBlocks = { ...a, program: { ...a.program, mode: "blocks", blocks: { blocks: { blocks: [] } } } };
  assert.equal(describeChange(inBlocks, { ...inBlocks, program: { ...inBlocks.program, text: "G 100" } }), null);
  const dragged = { ...inBlocks, program: { ...inBlocks.program, blocks: { blocks: { blocks: [{ type: "arm_home" }] } }, text: "H" } };
  assert.deepEqual(describeChange(inBlocks, dragged), { name: "the blocks", kind: "program-blocks" });
  // into blocks from text: the text still tells them apart
  assert.equal(describeChange(typed, { ...typed, program: { ...typed.program, mode: "blocks" } }).name, "the program as blocks");
  // a cell opened is "the cell"; typing in its arms' programs joins into one step of its own kind
  const cell = { ...a, cell: { name: "signal", programs: ["G 0", "W 14 0 30"] } };
  assert.deepEqual(describeChange(a, cell), { name: "the cell", kind: "" });
  const edited = { ...cell, cell: { name: "signal", programs: ["G 0", "G 100"] } };
  assert.deepEqual(describeChange(cell, edited), { name: "the cell's programs", kind: "cell-text" });
  assert.equal(describeChange(cell, { ...cell, cell: { name: "handover", programs: ["G 0", "G 0"] } }).name, "the cell");
});
