// Blocks and programs, in the engine's worker: the actions a workspace unrolls into
// (blocks/unroll.ts) become the program lines the engine already runs, and a program file
// becomes actions again (the engine's own parser reads it: host/lib/records_json.h,
// program_json), so text and blocks cannot disagree.
//
// Blocks speak in the student's values (the sliders' joint values, mm, percent); the arm's
// protocol moves motors. This is where one becomes the other: `M` takes the motor angles the
// engine gives for the joint values (Robot.motorsFromJoints), `P` the point, `G` the percent.
import { EngineError } from "../../../../wasm/js/engine.mjs";
import { BadMessage, text } from "./checks";
import type { Msg, Out } from "./checks";
import { info, powerUpQ, S } from "./state";
import type { Action, Op } from "../blocks/unroll";

const ROBOSIM_FAST = 82; // RoboSim's s: 1 (slow) .. 82 (fast), appendix B
const COMMENT_BYTES = 60; // a protocol line holds 64 bytes, "# " and the comment included

interface MotorInfo { name: string; min: number; max: number }

const f3 = (v: number) => (Math.abs(v) < 0.0005 ? 0 : v).toFixed(3).replace(/\.?0+$/, "") || "0";

/** Comment lines of at most COMMENT_BYTES bytes each. */
function commentLines(s: string): string[] {
  const enc = new TextEncoder();
  const out: string[] = [];
  let cur = "";
  for (const ch of s.replace(/[\r\n]+/g, " ")) {
    if (enc.encode(cur + ch).length > COMMENT_BYTES) {
      out.push(cur);
      cur = "";
    }
    cur += ch;
  }
  out.push(cur);
  return out.map((c) => `# ${c}`.trimEnd());
}

/** The program for a list of actions: protocol lines (what runs), RoboSim, and which block
 * each protocol line came from; the blocks whose values the arm would refuse, and why. */
export function compile(ops: Op[]): { text: string; robosim: string; lines: string[]; problems: { block: string; message: string }[] } {
  const r = info();
  const motors = r.num_motors > 0 ? (r.motors as unknown as MotorInfo[]) : [];
  let q = motors.length ? powerUpQ() : [...r.home];
  const proto: string[] = ["# made from blocks in Articula Studio"];
  const lines: string[] = [""];
  const rs: string[] = ["# made from blocks in Articula Studio"];
  const problems: { block: string; message: string }[] = [];
  const emit = (block: string, ...ls: string[]) => {
    for (const l of ls) {
      proto.push(l);
      lines.push(block);
    }
  };
  const unit = (j: number) => (r.joints[j] as unknown as { unit: string }).unit;
  const show = (j: number, v: number) => `${f3(v)}${unit(j) === "mm" ? " mm" : "°"}`;
  // Joint values to a move: the problems the arm would refuse it for, named in the student's
  // units; the pose follows only when the move is allowed.
  const move = (block: string, target: number[]) => {
    let ok = true;
    target.forEach((v, j) => {
      const [lo, hi] = r.limits[j];
      if (v < lo - 1e-9 || v > hi + 1e-9) {
        ok = false;
        problems.push({ block, message: `${r.joint_names[j]} at ${show(j, v)} is beyond its range, ${show(j, lo)} to ${show(j, hi)}` });
      }
    });
    let values = target;
    if (motors.length) {
      values = S.robot.motorsFromJoints(target) as number[];
      values.forEach((m, k) => {
        if (ok && (m < motors[k].min - 1e-6 || m > motors[k].max + 1e-6)) {
          ok = false;
          problems.push({ block, message: `this pose needs the ${motors[k].name} motor at ${f3(m)}°, beyond its range ` +
            `${f3(motors[k].min)}° to ${f3(motors[k].max)}° (the joints: ${target.map((v, j) => `${r.joint_names[j]} ${show(j, v)}`).join(", ")})` });
        }
      });
    }
    emit(block, "M " + values.map(f3).join(" "));
    rs.push("m", ...target.map(f3));
    if (ok) q = target;
  };
  // The tool to a point (P, and T's end): the pose follows when the engine's IK reaches it.
  const reach = (block: string, xyz: number[]) => {
    let res: { status: string; q: number[] };
    try {
      res = S.robot.ik({ target: xyz, solver: "auto", start: q }) as unknown as { status: string; q: number[] };
    } catch (e) {
      if (e instanceof EngineError) throw new BlockProblem(block, e.message);
      throw e;
    }
    if (res.status === "reached") q = res.q;
    else problems.push({ block, message: `the tool cannot reach (${xyz.map(f3).join(", ")}) mm: it is out of reach or beyond a joint's range` });
  };
  for (const o of ops) {
    const b = o.block;
    switch (o.op) {
      case "joint_to":
      case "joint_by": {
        if (!Number.isInteger(o.joint) || o.joint < 0 || o.joint >= r.num_joints)
          throw new BlockProblem(b, `${r.name} has no joint ${o.joint + 1}: choose one of ${r.joint_names.join(", ")}`);
        const t = [...q];
        t[o.joint] = o.op === "joint_to" ? o.value : q[o.joint] + o.value;
        move(b, t);
        break;
      }
      case "joints":
        if (o.values.length !== r.num_joints)
          throw new BlockProblem(b, `${r.name} has ${r.num_joints} joints (${r.joint_names.join(", ")}): this block gives ${o.values.length} values`);
        move(b, o.values);
        break;
      case "home":
        move(b, [...r.home]);
        break;
      case "tool_to":
        emit(b, `P ${o.xyz.map(f3).join(" ")}`);
        rs.push("a", ...o.xyz.map(f3));
        reach(b, o.xyz);
        break;
      case "line_to": {
        // The line itself is checked where the arm checks it: the engine's prediction refuses
        // a line it cannot follow, on this block's line, and says where.
        if (!(o.speed > 0 && o.speed <= 1000))
          problems.push({ block: b, message: `the speed is from more than 0 to 1000 mm/s, not ${f3(o.speed)} mm/s` });
        emit(b, `T ${o.xyz.map(f3).join(" ")} ${f3(o.speed)}`);
        rs.push("# (a straight line: RoboSim moves to its end)", "a", ...o.xyz.map(f3));
        reach(b, o.xyz);
        break;
      }
      case "gripper":
        if (!r.gripper) problems.push({ block: b, message: `${r.name} has no gripper` });
        if (o.percent < 0 || o.percent > 100) problems.push({ block: b, message: `the gripper opens from 0 % to 100 %, not ${f3(o.percent)} %` });
        emit(b, `G ${f3(o.percent)}`);
        rs.push("h", f3(((100 - o.percent) / 100) * 0.5));
        break;
      case "speed": {
        if (o.percent <= 0 || o.percent > 100) throw new BlockProblem(b, `the speed is from 1 % to 100 %, not ${f3(o.percent)} %`);
        // $0 at 100 %: the firmware's default top rate (shared/articula/settings.h, through the engine)
        emit(b, `$0=${Math.max(1, Math.round((S.engine.settings[0][2] * o.percent) / 100))}`);
        rs.push("s", String(Math.max(1, Math.round((ROBOSIM_FAST * o.percent) / 100))));
        break;
      }
      case "wait":
        emit(b, `D ${f3(o.seconds)}`); // (its range is the parser's: a wait beyond it is refused on its block)
        rs.push(`# (a wait of ${f3(o.seconds)} s: RoboSim has none)`);
        break;
      case "comment":
        emit(b, ...commentLines(o.text));
        rs.push(...commentLines(o.text));
        break;
      case "raw":
        emit(b, o.text.replace(/[\r\n]+/g, " "));
        rs.push(`# (a protocol line, no RoboSim) ${o.text.replace(/[\r\n]+/g, " ")}`);
        break;
    }
  }
  return { text: proto.join("\n") + "\n", robosim: rs.join("\n") + "\n", lines, problems };
}

/** A block the engine cannot make a line of at all. */
export class BlockProblem extends Error {
  constructor(readonly block: string, message: string) {
    super(message);
  }
}

/** The actions of a program's text (its comments kept), read by the engine's parser. */
export function opsOfProgram(src: string, name: string): { ops: Action[]; format: string } {
  const r = info();
  const parsed = S.robot.parseProgram(src, name);
  const ops: { line: number; op: Action }[] = [];
  for (const c of parsed.comments) ops.push({ line: c.line - (c.whole_line ? 0 : 0.5), op: { op: "comment", text: c.text } });
  const motors = r.num_motors > 0;
  for (const st of parsed.statements) {
    let op: Action;
    if (st.kind === "protocol") {
      const p = st as { text: string; command: string; args: number[] };
      const a = p.args;
      switch (p.command) {
        case "M": op = { op: "joints", values: motors ? (S.robot.jointsFromMotors(a) as number[]) : a }; break;
        case "P": op = { op: "tool_to", xyz: a }; break;
        case "T": op = { op: "line_to", xyz: a.slice(0, 3), speed: a[3] }; break;
        case "G": op = { op: "gripper", percent: a[0] }; break;
        case "S": op = { op: "gripper", percent: a[0] ? 0 : 100 }; break;
        case "D": op = { op: "wait", seconds: a[0] }; break;
        default: op = { op: "raw", text: p.text };
      }
    } else {
      const v = (st as { values: number[] }).values;
      switch (st.kind) {
        case "m": op = { op: "joints", values: v }; break;
        case "a": op = { op: "tool_to", xyz: v.slice(0, 3) }; break;
        case "h": op = { op: "gripper", percent: ((0.5 - v[0]) / 0.5) * 100 }; break;
        case "s": op = { op: "speed", percent: (v[0] / ROBOSIM_FAST) * 100 }; break;
        default: op = { op: "raw", text: `${st.kind} ${v.map(f3).join(" ")}` };
      }
    }
    ops.push({ line: st.line, op });
  }
  ops.sort((x, y) => x.line - y.line);
  return { ops: ops.map((x) => x.op), format: parsed.format };
}

/** The Python script that predicts the same program with `import articula`. */
export function pythonScript(program: string): string {
  const r = info();
  const shipped = S.index.robots.includes(r.source.split("/").pop()?.replace(/\.json$/, "") ?? "");
  const robot = shipped ? `articula.Robot.load(${JSON.stringify(r.source.split("/").pop()!.replace(/\.json$/, ""))})`
    : `articula.Robot.load("my-robot.json")  # the robot file you opened`;
  const fn = r.num_motors ? "predict" : "run";
  return [
    "# The program made from blocks in Articula Studio, with the same engine from Python.",
    "# pip install the articula package (README), then: python this-file.py",
    "import articula",
    "",
    `robot = ${robot}`,
    `program = articula.Program(${JSON.stringify(program)}, "blocks.arm")`,
    `result = robot.${fn}(program)`,
    "for r in result.records:",
    r.num_motors ? '    print(f"line {r.line}: {r.command} -> {r.reply}, steps {r.steps}")' : '    print(f"line {r.line}: {r.command} -> {r.reply}, joints {r.q}")',
    "",
  ].join("\n");
}

export const blockHandlers: Record<string, (m: Msg) => Out[]> = {
  // The program of a workspace's actions (the page unrolled them).
  blocks_compile(m) {
    if (!Array.isArray(m.ops)) throw new BadMessage("'ops' must be a list of actions");
    if (m.ops.length > 10_000) throw new BadMessage("'ops' holds more than 10,000 actions");
    try {
      const c = compile(m.ops as Op[]);
      return [{ type: "blocks_program", ...c, python: pythonScript(c.text) }];
    } catch (e) {
      if (e instanceof BlockProblem) return [{ type: "blocks_program", error: { block: e.block, message: e.message } }];
      throw e;
    }
  },
  // A program's text as actions, for blocks.
  program_ops(m) {
    const src = text(m, "text");
    const name = typeof m.name === "string" && m.name ? m.name : "program.arm";
    try {
      return [{ type: "program_ops", ...opsOfProgram(src, name) }];
    } catch (e) {
      if (e instanceof EngineError) return [{ type: "program_ops", error: e.message, line: (e as { line?: number }).line ?? 0 }];
      throw e;
    }
  },
};
