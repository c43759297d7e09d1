// Blocks to the arm's actions: a workspace (Blockly's JSON, as it saves and as a project or a
// link carries it) unrolled into a flat list of actions in the student's units (joint values
// as the sliders show them, mm, percent), each naming the block it came from. Loops,
// variables, arithmetic and procedures end here: what leaves is a list the engine turns into
// program lines (engine/blocks.ts), and the program runs as any other. Pure data in, data
// out, no Blockly and no DOM: node's tests run it too.

/** One action of the arm, from one block. */
export type Op =
  | { op: "joint_to"; joint: number; value: number; block: string }
  | { op: "joint_by"; joint: number; value: number; block: string }
  | { op: "joints"; values: number[]; block: string }
  | { op: "tool_to"; xyz: number[]; block: string }
  | { op: "line_to"; xyz: number[]; speed: number; block: string }
  | { op: "gripper"; percent: number; block: string }
  | { op: "speed"; percent: number; block: string }
  | { op: "wait"; seconds: number; block: string }
  | { op: "output"; pin: number; level: number; block: string }
  | { op: "wait_input"; pin: number; level: number; seconds: number; block: string }
  | { op: "home"; block: string }
  | { op: "comment"; text: string; block: string }
  | { op: "raw"; text: string; block: string }
  | { op: "pen"; pen: number; z: number; block: string }
  | { op: "pen_down"; block: string }
  | { op: "pen_up"; block: string }
  | { op: "pen_to"; xy: number[]; block: string }
  | { op: "write"; text: string; width: number; at: number[]; block: string }
  | { op: "shape"; shape: string; width: number; at: number[]; block: string };

type Bare<T> = T extends unknown ? Omit<T, "block"> : never;
/** An action without its block (a program's text read as actions). */
export type Action = Bare<Op>;

/** A block that cannot be unrolled: which block, and why, in words a student reads. */
export class BlockError extends Error {
  constructor(readonly block: string, message: string) {
    super(message);
  }
}

/** The block types a program may hold (a project or a link with any other is refused). */
export const BLOCK_TYPES = new Set([
  "arm_joint_to", "arm_joint_by", "arm_joints", "arm_tool_to", "arm_line_to", "arm_home", "arm_gripper_open", "arm_gripper_close",
  "arm_gripper_to", "arm_speed", "arm_wait", "arm_comment", "arm_raw", "arm_pen", "arm_pen_down", "arm_pen_up", "arm_pen_to",
  "arm_write", "arm_shape", "arm_output", "arm_wait_input", "controls_repeat_ext", "variables_set", "variables_get",
  "math_change", "math_number", "math_arithmetic", "procedures_defnoreturn", "procedures_callnoreturn",
]);

/** The most lines a program from blocks may unroll into. */
export const MAX_LINES = 10_000;
const MAX_DEPTH = 100; // procedure calls inside procedure calls

type J = Record<string, unknown>;
interface Ctx {
  ops: Op[];
  vars: Map<string, number>; // variable id -> value
  names: Map<string, string>; // variable id -> name, for messages
  procs: Map<string, J>; // procedure name -> its definition block
  loops: J[]; // the repeats and calls being run, outermost first (to name one when too long)
  depth: number;
}

const field = (b: J, name: string): unknown => (b.fields as J | undefined)?.[name];
const input = (b: J, name: string): J | null => {
  const i = (b.inputs as J | undefined)?.[name] as J | undefined;
  return ((i?.block ?? i?.shadow) as J | undefined) ?? null;
};
const next = (b: J): J | null => (((b.next as J | undefined)?.block) as J | undefined) ?? null;

/** What a block says, for messages: "repeat 1000 times", "turn base by 30". */
export function describe(b: J): string {
  switch (b.type) {
    case "controls_repeat_ext": return "repeat";
    case "procedures_callnoreturn": return `call "${String((b.extraState as J | undefined)?.name ?? "")}"`;
    case "procedures_defnoreturn": return `"${String(field(b, "NAME") ?? "")}"`;
    default: return String(b.type ?? "a block").replace(/^arm_/, "").replace(/_/g, " ");
  }
}

/** A workspace's actions, in order: the stacks from top to bottom (procedure definitions are
 * run where they are called). Throws BlockError. */
export function unroll(workspace: unknown): Op[] {
  const ws = (workspace ?? {}) as J;
  const top = (((ws.blocks as J | undefined)?.blocks) ?? []) as J[];
  if (!Array.isArray(top)) throw new BlockError("", "the blocks cannot be read");
  const ctx: Ctx = { ops: [], vars: new Map(), names: new Map(), procs: new Map(), loops: [], depth: 0 };
  for (const v of ((ws.variables ?? []) as J[])) if (typeof v?.id === "string") ctx.names.set(v.id, String(v.name ?? v.id));
  for (const b of top)
    if (b?.type === "procedures_defnoreturn") ctx.procs.set(String(field(b, "NAME") ?? ""), b);
  const stacks = top.filter((b) => b && b.type !== "procedures_defnoreturn")
    .sort((a, b) => (Number(a.y) || 0) - (Number(b.y) || 0) || (Number(a.x) || 0) - (Number(b.x) || 0));
  for (const b of stacks) run(b, ctx);
  return ctx.ops;
}

function push(ctx: Ctx, op: Op): void {
  if (ctx.ops.length >= MAX_LINES) {
    const culprit = ctx.loops[0];
    const id = String((culprit ?? { id: op.block }).id ?? op.block);
    throw new BlockError(id, culprit
      ? `The ${describe(culprit)} block makes more than ${MAX_LINES.toLocaleString("en")} lines: repeat fewer times.`
      : `The program has more than ${MAX_LINES.toLocaleString("en")} lines.`);
  }
  ctx.ops.push(op);
}

function run(first: J | null, ctx: Ctx): void {
  for (let b = first; b; b = next(b)) statement(b, ctx);
}

function statement(b: J, ctx: Ctx): void {
  const id = String(b.id ?? "");
  if (b.enabled === false) return;
  const n = (name: string) => value(input(b, name), ctx, b, name);
  switch (b.type) {
    case "arm_joint_to":
      return push(ctx, { op: "joint_to", joint: Number(field(b, "JOINT")), value: n("VALUE"), block: id });
    case "arm_joint_by":
      return push(ctx, { op: "joint_by", joint: Number(field(b, "JOINT")), value: n("VALUE"), block: id });
    case "arm_joints": {
      const values = String(field(b, "VALUES") ?? "").split(/[\s,;]+/).filter(Boolean).map(Number);
      if (!values.length || values.some((v) => !Number.isFinite(v)))
        throw new BlockError(id, `"${String(field(b, "VALUES") ?? "")}" is not a list of numbers: write them like 0, 90, -90`);
      return push(ctx, { op: "joints", values, block: id });
    }
    case "arm_tool_to":
      return push(ctx, { op: "tool_to", xyz: [n("X"), n("Y"), n("Z")], block: id });
    case "arm_line_to":
      return push(ctx, { op: "line_to", xyz: [n("X"), n("Y"), n("Z")], speed: n("SPEED"), block: id });
    case "arm_gripper_open": return push(ctx, { op: "gripper", percent: 100, block: id });
    case "arm_gripper_close": return push(ctx, { op: "gripper", percent: 0, block: id });
    case "arm_gripper_to": return push(ctx, { op: "gripper", percent: n("PERCENT"), block: id });
    case "arm_speed": return push(ctx, { op: "speed", percent: n("PERCENT"), block: id });
    case "arm_wait": return push(ctx, { op: "wait", seconds: n("SECONDS"), block: id });
    case "arm_home": return push(ctx, { op: "home", block: id });
    case "arm_output": return push(ctx, { op: "output", pin: Number(field(b, "PIN")), level: Number(field(b, "LEVEL")), block: id });
    case "arm_wait_input":
      return push(ctx, { op: "wait_input", pin: Number(field(b, "PIN")), level: Number(field(b, "LEVEL")), seconds: n("SECONDS"), block: id });
    case "arm_comment": return push(ctx, { op: "comment", text: String(field(b, "TEXT") ?? ""), block: id });
    case "arm_raw": return push(ctx, { op: "raw", text: String(field(b, "TEXT") ?? ""), block: id });
    case "arm_pen": return push(ctx, { op: "pen", pen: n("PEN"), z: n("Z"), block: id });
    case "arm_pen_down": return push(ctx, { op: "pen_down", block: id });
    case "arm_pen_up": return push(ctx, { op: "pen_up", block: id });
    case "arm_pen_to": return push(ctx, { op: "pen_to", xy: [n("X"), n("Y")], block: id });
    case "arm_write":
      return push(ctx, { op: "write", text: String(field(b, "TEXT") ?? ""), width: n("WIDTH"), at: [n("X"), n("Y")], block: id });
    case "arm_shape":
      return push(ctx, { op: "shape", shape: String(field(b, "SHAPE") ?? ""), width: n("WIDTH"), at: [n("X"), n("Y")], block: id });
    case "controls_repeat_ext": {
      const times = n("TIMES");
      if (!Number.isFinite(times) || times < 0) throw new BlockError(id, `repeat needs a number of times of 0 or more, not ${times}`);
      ctx.loops.push(b);
      for (let i = 0; i < Math.floor(times); i++) run(input(b, "DO"), ctx);
      ctx.loops.pop();
      return;
    }
    case "variables_set": {
      const v = String((field(b, "VAR") as J | undefined)?.id ?? "");
      ctx.vars.set(v, n("VALUE"));
      return;
    }
    case "math_change": {
      const v = String((field(b, "VAR") as J | undefined)?.id ?? "");
      ctx.vars.set(v, (ctx.vars.get(v) ?? 0) + n("DELTA"));
      return;
    }
    case "procedures_callnoreturn": {
      const extra = (b.extraState ?? {}) as J;
      const name = String(extra.name ?? "");
      const def = ctx.procs.get(name);
      if (!def) throw new BlockError(id, `there is no "define ${name}" block for this call`);
      if (ctx.depth >= MAX_DEPTH) throw new BlockError(id, `"${name}" calls itself too deeply (more than ${MAX_DEPTH} calls inside each other)`);
      const params = (((def.extraState as J | undefined)?.params ?? []) as J[]);
      params.forEach((p, i) => ctx.vars.set(String(p.id ?? ""), n(`ARG${i}`)));
      ctx.loops.push(b);
      ctx.depth++;
      run(input(def, "STACK"), ctx);
      ctx.depth--;
      ctx.loops.pop();
      return;
    }
    default:
      throw new BlockError(id, `the block "${describe(b)}" cannot be part of an arm program`);
  }
}

/** A number block's value (a plain number, a variable, arithmetic). */
function value(b: J | null, ctx: Ctx, parent: J, name: string): number {
  if (!b) throw new BlockError(String(parent.id ?? ""), `the block "${describe(parent)}" needs a number in its ${name.toLowerCase()} slot`);
  const id = String(b.id ?? "");
  switch (b.type) {
    case "math_number": {
      const v = Number(field(b, "NUM"));
      if (!Number.isFinite(v)) throw new BlockError(id, `"${String(field(b, "NUM"))}" is not a number`);
      return v;
    }
    case "variables_get": {
      const v = String((field(b, "VAR") as J | undefined)?.id ?? "");
      if (!ctx.vars.has(v)) throw new BlockError(id, `the variable "${ctx.names.get(v) ?? v}" has no value yet: set it first`);
      return ctx.vars.get(v)!;
    }
    case "math_arithmetic": {
      const a = value(input(b, "A"), ctx, b, "A"), c = value(input(b, "B"), ctx, b, "B");
      const op = String(field(b, "OP"));
      const r = op === "ADD" ? a + c : op === "MINUS" ? a - c : op === "MULTIPLY" ? a * c : op === "DIVIDE" ? a / c : op === "POWER" ? a ** c : NaN;
      if (!Number.isFinite(r)) throw new BlockError(id, `${a} ${op.toLowerCase()} ${c} gives no number`);
      return r;
    }
    default:
      throw new BlockError(id, `the block "${describe(b)}" does not give a number`);
  }
}

/** Actions as blocks (a program opened as blocks): one stack, Blockly's JSON. */
export function opsToWorkspace(ops: Action[]): J {
  const num = (n: number) => ({ shadow: { type: "math_number", fields: { NUM: Math.round(n * 1000) / 1000 } } });
  const r3 = (n: number) => Math.round(n * 1000) / 1000;
  const blocks: J[] = ops.map((o) => {
    switch (o.op) {
      case "joint_to": return { type: "arm_joint_to", fields: { JOINT: String(o.joint) }, inputs: { VALUE: num(o.value) } };
      case "joint_by": return { type: "arm_joint_by", fields: { JOINT: String(o.joint) }, inputs: { VALUE: num(o.value) } };
      case "joints": return { type: "arm_joints", fields: { VALUES: o.values.map(r3).join(", ") } };
      case "tool_to": return { type: "arm_tool_to", inputs: { X: num(o.xyz[0]), Y: num(o.xyz[1]), Z: num(o.xyz[2]) } };
      case "line_to": return { type: "arm_line_to", inputs: { X: num(o.xyz[0]), Y: num(o.xyz[1]), Z: num(o.xyz[2]), SPEED: num(o.speed) } };
      case "gripper": return o.percent >= 100 ? { type: "arm_gripper_open" } : o.percent <= 0 ? { type: "arm_gripper_close" }
        : { type: "arm_gripper_to", inputs: { PERCENT: num(o.percent) } };
      case "speed": return { type: "arm_speed", inputs: { PERCENT: num(o.percent) } };
      case "wait": return { type: "arm_wait", inputs: { SECONDS: num(o.seconds) } };
      case "home": return { type: "arm_home" };
      case "output": return { type: "arm_output", fields: { PIN: String(o.pin), LEVEL: String(o.level) } };
      case "wait_input": return { type: "arm_wait_input", fields: { PIN: String(o.pin), LEVEL: String(o.level) }, inputs: { SECONDS: num(o.seconds) } };
      case "comment": return { type: "arm_comment", fields: { TEXT: o.text } };
      case "raw": return { type: "arm_raw", fields: { TEXT: o.text } };
      case "pen": return { type: "arm_pen", inputs: { PEN: num(o.pen), Z: num(o.z) } };
      case "pen_down": return { type: "arm_pen_down" };
      case "pen_up": return { type: "arm_pen_up" };
      case "pen_to": return { type: "arm_pen_to", inputs: { X: num(o.xy[0]), Y: num(o.xy[1]) } };
      case "write": return { type: "arm_write", fields: { TEXT: o.text }, inputs: { WIDTH: num(o.width), X: num(o.at[0]), Y: num(o.at[1]) } };
      case "shape": return { type: "arm_shape", fields: { SHAPE: o.shape }, inputs: { WIDTH: num(o.width), X: num(o.at[0]), Y: num(o.at[1]) } };
    }
  });
  for (let i = blocks.length - 2; i >= 0; i--) blocks[i].next = { block: blocks[i + 1] };
  return { blocks: { languageVersion: 0, blocks: blocks.length ? [{ ...blocks[0], x: 20, y: 20 }] : [] } };
}
