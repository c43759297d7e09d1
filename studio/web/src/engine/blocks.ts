// Blocks and programs, in the engine's worker: the actions a workspace unrolls into
// (blocks/unroll.ts) become the program lines the engine already runs, and a program file
// becomes actions again, both by the engine (host/lib/blocks.h: its limits, IK, speed rule
// and line formatter; its own parser), so text and blocks cannot disagree. This file only
// passes them through and writes the Python script that predicts the same program.
import { EngineError } from "../../../../wasm/js/engine.mjs";
import { BadMessage, text } from "./checks";
import type { Msg, Out } from "./checks";
import { info, S, shippedName } from "./state";
import type { Action, Op } from "../blocks/unroll";

/** The program for a list of actions: protocol lines (what runs), RoboSim, and which block
 * each protocol line came from; the blocks whose values the arm would refuse, and why; or the
 * block that cannot become a line at all. The engine's (host/lib/blocks.h): its limits, its
 * IK, its speed rule and its line formatter. */
export function compile(ops: Op[]) {
  return S.robot.blocksProgram(ops);
}

/** The actions of a program's text (its comments kept), read by the engine's parser. */
export function opsOfProgram(src: string, name: string): { ops: Action[]; format: string } {
  const parsed = S.robot.programActions(src, name);
  return { ops: parsed.ops as unknown as Action[], format: parsed.format };
}

/** The Python script that predicts the same program with `import articula`. */
export function pythonScript(program: string): string {
  const r = info();
  const shipped = shippedName();
  const robot = shipped ? `articula.Robot.load(${JSON.stringify(shipped)})`
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
    const c = compile(m.ops as Op[]);
    if ("error" in c) return [{ type: "blocks_program", error: c.error }];
    return [{ type: "blocks_program", ...c, python: pythonScript(c.text) }];
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
