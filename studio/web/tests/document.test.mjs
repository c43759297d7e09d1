// The page's pure modules in node, without a browser: the project reader (project/document.ts),
// which takes files, links and the browser's store as untrusted input, and the blocks'
// unrolling (blocks/unroll.ts), which turns a workspace into the arm's actions.
import assert from "node:assert/strict";
import { test } from "node:test";
import { load } from "./page-module.mjs";

const doc = await load("project/document.ts");
const { readProject, parseProject, newProject, projectFragment, projectOfFragment, ProjectError } = doc;

/** A project that reads, to break one part of at a time. */
function good() {
  const p = newProject("Mine");
  p.program.text = "L 0 30\n";
  return JSON.parse(JSON.stringify(p));
}

/** The reader's refusal of `x`: a ProjectError whose message names the part. */
function refusal(x) {
  try {
    readProject(x);
  } catch (e) {
    assert.ok(e instanceof ProjectError, `not a ProjectError: ${e}`);
    return e.message;
  }
  assert.fail(`accepted: ${JSON.stringify(x).slice(0, 200)}`);
}

test("a project reads back as it was written, through a file and through a link", async () => {
  const p = good();
  assert.deepEqual(readProject(p).program, p.program);
  assert.deepEqual(parseProject(JSON.stringify(p)).name, "Mine");
  const back = await projectOfFragment(await projectFragment(readProject(p)));
  assert.equal(back.program.text, "L 0 30\n");
  assert.equal(back.robot.shipped, "mk2plus");
});

test("hostile projects are refused with the part named, never half read", () => {
  const cases = [
    [null, "not an Articula project"],
    [{ ...good(), format: "x" }, "not an Articula project"],
    [{ ...good(), version: 99 }, "newer Articula"],
    [{ ...good(), version: 1.5 }, "version"],
    [{ ...good(), name: 42 }, "project.name must be text"],
    [{ ...good(), name: "x".repeat(201) }, "project.name is longer than 200"],
    [{ ...good(), robot: { url: "http://evil" } }, "robot must name a shipped robot"],
    [{ ...good(), robot: { file: { name: "r.json", text: "{}" }, meshes: [{ name: "m.stl", data: "<script>" }] } }, "robot.meshes[0].data is not base64"],
    [{ ...good(), program: { ...good().program, mode: "python" } }, 'program.mode must be "text" or "blocks"'],
    [{ ...good(), program: { ...good().program, blocks: { blocks: { blocks: [{ type: "js_eval" }] } } } }, '"js_eval" is not a block of Articula'],
    [{ ...good(), pose: { q: [0, NaN], gripper: 0 } }, "pose.q[1] must be a number"],
    [{ ...good(), pose: { q: [0, 1e300], gripper: 0 } }, "pose.q[1] must be a number"],
    [{ ...good(), view: { eye: [0, 0], target: [0, 0, 0] } }, "view.eye must be a list of 3 numbers"],
    [{ ...good(), goal: { title: "t", text: "x", parts: [] } }, "goal.parts must be a list of 1 to 50 parts"],
    [{ ...good(), goal: { title: "t", text: "x", parts: [{ kind: "reach", xyz: [1, 2, 3], tolerance_mm: 0 }] } }, "goal.parts[0].tolerance_mm must be above 0"],
    [{ ...good(), goal: { title: "t", text: "x", parts: [{ kind: "teleport" }] } }, 'goal.parts[0].kind must be "reach", "object", "drawing", "no_collision", "programs_end" or "waits_for"'],
    [{ ...good(), experiment: { points: "all" } }, "experiment.points must be a list"],
  ];
  for (const [x, said] of cases) {
    const message = refusal(x);
    assert.ok(message.includes(said), `${JSON.stringify(said)} not in ${JSON.stringify(message)}`);
  }
  // blocks nested past any program's depth, and text that is no JSON at all
  let deep = { type: "math_number", fields: { NUM: 1 } };
  for (let i = 0; i < 300; i++) deep = { type: "controls_repeat_ext", inputs: { DO: { block: deep } } };
  assert.match(refusal({ ...good(), program: { ...good().program, mode: "blocks", blocks: { blocks: { blocks: [deep] } } } }), /nest too deeply/);
  assert.throws(() => parseProject("{ not json"), (e) => e instanceof ProjectError && /not JSON/.test(e.message));
});

test("strings stay strings: markup in a project is kept as text, for the page to show as text", () => {
  const p = good();
  p.name = '<img src=x onerror="alert(1)">';
  p.program.text = "# <script>alert(1)</script>\nL 0 1\n";
  const r = readProject(p);
  assert.equal(r.name, p.name);
  assert.equal(r.program.text, p.program.text);
  // what the reader does not know is dropped, not carried along
  const extra = { ...good(), onload: "alert(1)", __proto__: { polluted: true } };
  const q = readProject(extra);
  assert.equal("onload" in q, false);
  assert.equal({}.polluted, undefined);
});

test("a damaged or oversized link is refused saying so", async () => {
  await assert.rejects(projectOfFragment("#nothing"), /holds no project/);
  await assert.rejects(projectOfFragment("#project=abc$def"), /a character a project link never has, at position 4/);
  await assert.rejects(projectOfFragment("#project=AAAA"), /damaged or was cut short/);
  await assert.rejects(projectOfFragment("#project=" + "A".repeat(100_001)), /longer than 100,000 characters/);
  // a link that unpacks to far more than any project (a zip bomb): refused, not unpacked
  const big = { ...good(), program: { ...good().program, text: "L 0 1\n".repeat(1_000_000) } };
  const frag = await projectFragment(big);
  assert.ok(frag.length < 100_000, `the bomb's link is ${frag.length} characters`);
  await assert.rejects(projectOfFragment(frag), /unpacks to more than 4 MB/);
});

const { unroll, opsToWorkspace, BlockError, MAX_LINES } = await load("blocks/unroll.ts");

const num = (v) => ({ shadow: { type: "math_number", fields: { NUM: v } } });
const chain = (...blocks) => {
  for (let i = blocks.length - 2; i >= 0; i--) blocks[i].next = { block: blocks[i + 1] };
  return blocks[0];
};
const ws = (...top) => ({ blocks: { blocks: top }, variables: [{ id: "v", name: "angle" }] });

test("blocks unroll to the arm's actions: loops, variables, arithmetic and procedures end here", () => {
  const body = chain({ type: "arm_joint_by", id: "by", fields: { JOINT: 0 }, inputs: { VALUE: { block: { type: "variables_get", fields: { VAR: { id: "v" } } } } } },
    { type: "math_change", id: "ch", fields: { VAR: { id: "v" } }, inputs: { DELTA: num(5) } });
  const program = chain({ type: "variables_set", id: "set", fields: { VAR: { id: "v" } }, inputs: { VALUE: num(10) } },
    { type: "controls_repeat_ext", id: "rep", inputs: { TIMES: num(3), DO: { block: body } } },
    { type: "procedures_callnoreturn", id: "call", extraState: { name: "wave" } });
  const def = { type: "procedures_defnoreturn", id: "def", fields: { NAME: "wave" }, y: -100,
    inputs: { STACK: { block: { type: "arm_gripper_to", id: "g", inputs: { PERCENT: { block: { type: "math_arithmetic", fields: { OP: "MULTIPLY" }, inputs: { A: num(20), B: num(2.5) } } } } } } } };
  const ops = unroll(ws(program, def));
  assert.deepEqual(ops.map((o) => [o.op, o.value ?? o.percent]), [["joint_by", 10], ["joint_by", 15], ["joint_by", 20], ["gripper", 50]]);
  assert.deepEqual(ops.map((o) => o.block), ["by", "by", "by", "g"]);
  // and back: actions as one stack of blocks, which unrolls to the same actions
  const again = unroll(opsToWorkspace(ops.map(({ block, ...a }) => a)));
  assert.deepEqual(again.map(({ block, ...a }) => a), ops.map(({ block, ...a }) => a));
});

test("a block that cannot be unrolled is named, with a reason a student reads", () => {
  const refused = (w) => {
    try {
      unroll(w);
    } catch (e) {
      assert.ok(e instanceof BlockError, String(e));
      return [e.block, e.message];
    }
    assert.fail("unrolled");
  };
  const [b1, m1] = refused(ws({ type: "controls_repeat_ext", id: "many", inputs: { TIMES: num(MAX_LINES + 1), DO: { block: { type: "arm_home", id: "h" } } } }));
  assert.equal(b1, "many");
  assert.match(m1, /more than 10,000 lines: repeat fewer times/);
  const [b2, m2] = refused(ws({ type: "arm_joint_to", id: "empty", fields: { JOINT: 0 } }));
  assert.equal(b2, "empty");
  assert.match(m2, /needs a number in its value slot/);
  const [b3, m3] = refused(ws({ type: "procedures_callnoreturn", id: "self", extraState: { name: "loop" } },
    { type: "procedures_defnoreturn", fields: { NAME: "loop" }, inputs: { STACK: { block: { type: "procedures_callnoreturn", id: "inner", extraState: { name: "loop" } } } } }));
  assert.equal(b3, "inner");
  assert.match(m3, /calls itself too deeply/);
  const [, m4] = refused(ws({ type: "arm_joints", id: "j", fields: { VALUES: "0, ninety, 0" } }));
  assert.match(m4, /is not a list of numbers/);
  const [, m5] = refused(ws({ type: "arm_wait", id: "w", inputs: { SECONDS: { block: { type: "math_arithmetic", id: "div", fields: { OP: "DIVIDE" }, inputs: { A: num(1), B: num(0) } } } } }));
  assert.match(m5, /1 divide 0 gives no number/);
});

test("a drawing exercise's goal and the project's paper read back; bad ones are refused by name", () => {
  const p = good();
  p.paper = { sheet: "A4", at: [240, 10], landscape: true, z: 5, pen: 95 };
  p.goal = { title: "Square", text: "Draw it", scene: "", parts: [
    { kind: "drawing", target: { shape: "square", width: 40, at: [250, 0] }, tolerance_mm: 3, z: 0, pen: 120, label: "the square" },
    { kind: "drawing", target: { width: 40, at: [250, 0] }, ask: "your initials", tolerance_mm: 3, z: 0, pen: 120 }] };
  const back = readProject(p);
  assert.deepEqual(back.paper, p.paper);
  assert.deepEqual(back.goal.parts[0].target, { shape: "square", width: 40, at: [250, 0] });
  assert.equal(back.goal.parts[1].ask, "your initials");
  const broken = (change) => {
    const q = JSON.parse(JSON.stringify(p));
    change(q);
    return refusal(q);
  };
  assert.match(broken((q) => { q.paper.sheet = "A3"; }), /paper\.sheet/);
  assert.match(broken((q) => { q.paper.pen = -1; }), /paper\.pen/);
  assert.match(broken((q) => { q.paper.at = ["x", 0]; }), /paper\.at\[0\]/);
  assert.match(broken((q) => { q.goal.parts[0].target.shape = "<img src=x onerror=1>"; }), /goal\.parts\[0\]\.target\.shape/);
  assert.match(broken((q) => { q.goal.parts[0].tolerance_mm = 0; }), /goal\.parts\[0\]\.tolerance_mm/);
  assert.match(broken((q) => { delete q.goal.parts[1].ask; }), /goal\.parts\[1\]\.target needs a shape or a text/);
  assert.match(broken((q) => { q.goal.parts[0].target = "square"; }), /goal\.parts\[0\]\.target must be an object/);
});

test("the pen's blocks unroll to the pen's actions and back", () => {
  const program = chain(
    { type: "arm_pen", id: "p", inputs: { PEN: num(120), Z: num(0) } },
    { type: "arm_shape", id: "s", fields: { SHAPE: "star" }, inputs: { WIDTH: num(40), X: num(250), Y: num(0) } },
    { type: "arm_pen_down", id: "d" },
    { type: "arm_pen_to", id: "l", inputs: { X: num(260), Y: num(5) } },
    { type: "arm_pen_up", id: "u" },
    { type: "arm_write", id: "w", fields: { TEXT: "Hi" }, inputs: { WIDTH: num(30), X: num(250), Y: num(0) } });
  const ops = unroll(ws(program));
  assert.deepEqual(ops.map(({ block, ...a }) => a), [
    { op: "pen", pen: 120, z: 0 }, { op: "shape", shape: "star", width: 40, at: [250, 0] }, { op: "pen_down" },
    { op: "pen_to", xy: [260, 5] }, { op: "pen_up" }, { op: "write", text: "Hi", width: 30, at: [250, 0] }]);
  const again = unroll(opsToWorkspace(ops.map(({ block, ...a }) => a)));
  assert.deepEqual(again.map(({ block, ...a }) => a), ops.map(({ block, ...a }) => a));
});

test("the signal blocks unroll to O and W actions and back", () => {
  const program = chain(
    { type: "arm_output", id: "o", fields: { PIN: "19", LEVEL: "1" } },
    { type: "arm_wait_input", id: "w", fields: { PIN: "14", LEVEL: "0" }, inputs: { SECONDS: num(30) } });
  const ops = unroll(ws(program));
  assert.deepEqual(ops, [{ op: "output", pin: 19, level: 1, block: "o" }, { op: "wait_input", pin: 14, level: 0, seconds: 30, block: "w" }]);
  const again = unroll(opsToWorkspace(ops.map(({ block, ...a }) => a)));
  assert.deepEqual(again.map(({ block, ...a }) => a), ops.map(({ block, ...a }) => a));
});

test("a project's cell of arms reads back with each arm's program; a bad one is refused by name", async () => {
  const p = good();
  p.cell = { name: "signal", programs: ["G 100\nO 19 0", "W 14 0 30\n<b>wave</b>"] };
  const back = await projectOfFragment(await projectFragment(readProject(p)));
  assert.deepEqual(back.cell, p.cell);
  assert.equal(readProject(good()).cell, null); // (none: the one robot's project)
  const bad = (cell) => refusal({ ...good(), cell });
  assert.match(bad("signal"), /^cell must be an object/);
  assert.match(bad({ name: "signal" }), /cell\.programs must be a list of 1 to 8 programs/);
  assert.match(bad({ name: "signal", programs: Array(9).fill("G 0") }), /1 to 8/);
  assert.match(bad({ name: "signal", programs: ["G 0", 7] }), /cell\.programs\[1\] must be text/);
  assert.match(bad({ name: 3, programs: ["G 0"] }), /cell\.name must be text/);
  assert.match(bad({ name: "signal", programs: ["x".repeat(1_000_001)] }), /cell\.programs\[0\] is longer than/);
});

test("a scene of one's own (the project's world) reads back through a link; its form is checked, its contents left to the engine", async () => {
  const world = { name: "Your scene", objects: [{ name: "cube 1", type: "box", size: [25, 25, 25], xyz: [200, 0, 12.5], movable: true }] };
  const p = { ...good(), world };
  assert.deepEqual(readProject(p).world, world);
  assert.deepEqual((await projectOfFragment(await projectFragment(p))).world, world);
  assert.equal("world" in readProject(good()), false); // none: no field
  assert.equal("world" in readProject({ ...good(), world: null }), false);
  assert.match(refusal({ ...good(), world: [1, 2] }), /^world must be a scene/);
  assert.match(refusal({ ...good(), world: "cluttered" }), /^world must be a scene/);
  const big = { name: "big", objects: Array.from({ length: 2000 }, (_, i) => ({ name: `cube ${i}`, type: "box", size: [25, 25, 25], xyz: [i * 30, 0, 12.5] })) };
  assert.match(refusal({ ...good(), world: big }), /^world is longer than 100,000 characters/);
});
